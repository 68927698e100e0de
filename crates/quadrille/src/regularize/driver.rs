//! The regularization loop of one face (paper §II.A, spec §5.5–5.7).
//!
//! Quads are swept in id order (new quads are visited in the same sweep). At a
//! quad with an irregular vertex, the basic operations around it ([`candidates_at`])
//! are scored by exact valence bookkeeping; those that lower the score
//! `(N_irr, Σ|val − ideal|)` lexicographically are tried best first. When none
//! does, compositions are searched: a first operation that may worsen the score
//! by at most one irregular vertex (a swap, or a collapse/split that only moves
//! irregularity), followed by any operation around the vertices it changed;
//! the pair is kept when together they lower the score. This covers the
//! paper's swap-collapse, swap-split, double collapse, double split and double
//! swap (Figs 7–11). Translations (valence-neutral swaps that move an
//! irregular vertex next to others, Fig 5) are chains of such pairs whose
//! first step is neutral.
//!
//! Every operation is followed by local repositioning and a validity check of
//! the quads around every vertex it touched; if the region holds more invalid
//! quads than before, the whole sequence is rolled back.

use geometry::Face;

use crate::face_quads::FaceQuads;

use super::ops::{apply, apply_topology, candidates_at, effect, score_delta, Op};
use super::reposition::repair;
use super::validity::{quad_valid, AngleWindow};

/// Counters of one regularization run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct OpCounts {
    /// Accepted single swaps.
    pub swaps: usize,
    /// Accepted single collapses.
    pub collapses: usize,
    /// Accepted single splits.
    pub splits: usize,
    /// Accepted two-operation compositions (including translation + operation).
    pub compositions: usize,
    /// Sequences rejected because the region could not be made valid.
    pub rejected: usize,
    /// Sweeps over the quads.
    pub sweeps: usize,
}

/// The regularization state of one face: the quads, the face geometry and the
/// per-quad invalid flags (base window) used to compare regions before and after.
pub struct Regularizer<'a> {
    /// The face's surface (for positions and normals).
    pub face: &'a Face,
    /// The quads being edited.
    pub fq: &'a mut FaceQuads,
    /// Invalid flag per quad id (base window), kept in step with accepted edits.
    invalid: Vec<bool>,
    /// What happened so far.
    pub counts: OpCounts,
    /// Try compositions of two operations.
    pub compositions: bool,
    /// Candidate sequences tried with geometry per quad visit.
    pub tries: usize,
    /// Longest operation sequence searched (2: compositions; 3: also translation + composition).
    pub max_ops: usize,
    /// Topological trial applications per sequence search.
    pub budget: usize,
    /// Longest translation chain (valence-neutral swaps moving an irregular vertex).
    pub translation_steps: usize,
    singles_in_search: bool,
}

/// Topological applications allowed per sequence search at one quad.
const SEARCH_BUDGET: usize = 600;

fn better(a: (i64, i64)) -> bool {
    a.0 < 0 || (a.0 == 0 && a.1 < 0)
}

impl<'a> Regularizer<'a> {
    /// Prepares the state (computes the invalid flags of every quad).
    pub fn new(face: &'a Face, fq: &'a mut FaceQuads) -> Self {
        let invalid = (0..fq.quads.len() as u32).map(|q| fq.quad_alive[q as usize] && !quad_valid(fq, face, q, AngleWindow::BASE)).collect();
        Regularizer { face, fq, invalid, counts: OpCounts::default(), compositions: true, tries: 4, max_ops: 3, budget: SEARCH_BUDGET, translation_steps: 8, singles_in_search: false }
    }

    /// Number of live quads currently invalid for the base window.
    pub fn invalid_count(&self) -> usize {
        self.fq.live_quads().filter(|&q| self.invalid[q as usize]).count()
    }

    /// Repairs the invalid quads of the input where repositioning can (each
    /// kept only when its region does not get worse).
    pub fn initial_repair(&mut self) {
        let bad: Vec<u32> = self.fq.live_quads().filter(|&q| self.invalid[q as usize]).collect();
        for q in bad {
            if !self.invalid[q as usize] {
                continue;
            }
            let cp = self.fq.checkpoint();
            let region = self.fq.quads[q as usize].to_vec();
            repair(self.fq, self.face, &region, AngleWindow::BASE);
            if !self.settle(cp) {
                self.fq.rollback(cp);
            }
            self.fq.commit();
        }
    }

    /// Compares the quads touched since `cp` with their state at `cp`: keeps the
    /// edit (updating the flags) when no more of them are invalid than before.
    fn settle(&mut self, cp: crate::face_quads::Checkpoint) -> bool {
        let touched = self.fq.touched_since(cp);
        let live: Vec<u32> = touched.iter().copied().filter(|&v| self.fq.verts[v as usize].alive).collect();
        let mut check = self.fq.quads_around(&live);
        let mut all = check.clone();
        all.extend(self.fq.quads_touched_since(cp));
        all.sort_unstable();
        all.dedup();
        let before = all.iter().filter(|&&q| (q as usize) < self.invalid.len() && self.invalid[q as usize]).count();
        check.retain(|&q| self.fq.quad_alive[q as usize]);
        let flags: Vec<(u32, bool)> = check.iter().map(|&q| (q, !quad_valid(self.fq, self.face, q, AngleWindow::BASE))).collect();
        let after = flags.iter().filter(|f| f.1).count();
        if after > before {
            return false;
        }
        self.invalid.resize(self.fq.quads.len(), false);
        for q in all {
            if (q as usize) < self.invalid.len() {
                self.invalid[q as usize] = false;
            }
        }
        for (q, f) in flags {
            self.invalid[q as usize] = f;
        }
        true
    }

    /// Applies `ops` in order, each followed by repositioning; keeps them when
    /// the result is no less valid than before, else rolls everything back.
    pub fn try_sequence(&mut self, ops: &[Op]) -> bool {
        let cp = self.fq.checkpoint();
        for &op in ops {
            let Some(region) = apply(self.fq, self.face, op) else {
                self.fq.rollback(cp);
                return false;
            };
            repair(self.fq, self.face, &region, AngleWindow::BASE);
        }
        if self.settle(cp) {
            self.fq.commit();
            true
        } else {
            self.fq.rollback(cp);
            self.counts.rejected += 1;
            false
        }
    }

    fn has_irregular(&self, q: u32) -> bool {
        self.fq.quads[q as usize].iter().any(|&v| self.fq.is_irregular(v))
    }

    /// Tries to lower the score around quad `q`; returns whether something was accepted.
    pub fn improve_at(&mut self, q: u32) -> bool {
        if !self.fq.quad_alive[q as usize] || !self.has_irregular(q) {
            return false;
        }
        let cands = candidates_at(self.fq, q);
        let mut single: Vec<((i64, i64), usize, Op)> = Vec::new();
        for (i, &op) in cands.iter().enumerate() {
            let Some(eff) = effect(self.fq, op) else { continue };
            let d = score_delta(self.fq, &eff);
            if better(d) {
                single.push((d, i, op));
            }
        }
        single.sort();
        for &(_, _, op) in single.iter().take(self.tries) {
            if self.try_sequence(&[op]) {
                match op {
                    Op::Swap { .. } => self.counts.swaps += 1,
                    Op::Collapse { .. } => self.counts.collapses += 1,
                    Op::Split { .. } => self.counts.splits += 1,
                }
                return true;
            }
        }
        if !self.compositions {
            return false;
        }
        // compositions and translations, shortest first
        for len in 2..=self.max_ops {
            let mut found = Vec::new();
            let mut budget = self.budget;
            self.extend(&cands, &mut Vec::new(), (0, 0), &[], len, &mut found, &mut budget);
            found.sort();
            found.dedup_by(|a, b| a.1 == b.1);
            for (_, ops) in found.iter().take(self.tries) {
                if self.try_sequence(ops) {
                    self.counts.compositions += 1;
                    return true;
                }
            }
        }
        false
    }

    /// Depth-first search of operation sequences of at most `len` operations
    /// starting at quad `q`: each further operation must change the valence of
    /// a vertex the previous one changed; intermediate states may be worse by
    /// at most one irregular vertex. Sequences of ≥ 2 operations that lower the
    /// score are collected in `found`. Topology only (rolled back after).
    #[allow(clippy::too_many_arguments)]
    fn extend(&mut self, start: &[Op], path: &mut Vec<Op>, acc: (i64, i64), seeds: &[u32], len: usize, found: &mut Vec<((i64, i64), Vec<Op>)>, budget: &mut usize) {
        let cands: Vec<Op> = if path.is_empty() {
            start.to_vec()
        } else {
            self.fq.quads_around(seeds).into_iter().flat_map(|p| candidates_at(self.fq, p)).collect()
        };
        for op in cands {
            let Some(eff) = effect(self.fq, op) else { continue };
            if !path.is_empty() && !eff.changes.iter().any(|c| c.1 != c.2 && seeds.binary_search(&c.0).is_ok()) {
                continue;
            }
            let d1 = score_delta(self.fq, &eff);
            let d = (acc.0 + d1.0, acc.1 + d1.1);
            if better(d) {
                if !path.is_empty() || self.singles_in_search {
                    let mut ops = path.clone();
                    ops.push(op);
                    found.push((d, ops));
                }
                continue;
            }
            if path.len() + 1 >= len || d.0 > 1 || *budget == 0 {
                continue;
            }
            *budget -= 1;
            let cp = self.fq.checkpoint();
            if apply_topology(self.fq, op).is_some() {
                let mut changed: Vec<u32> = eff.changes.iter().filter(|c| c.1 != c.2).map(|c| c.0).collect();
                changed.extend(cp.verts_len() as u32..self.fq.verts.len() as u32);
                changed.sort_unstable();
                changed.dedup();
                path.push(op);
                self.extend(&[], path, d, &changed, len, found, budget);
                path.pop();
            }
            self.fq.rollback(cp);
        }
    }

    /// Sweeps the quads until no operation is accepted (or `max_sweeps`), then
    /// translates the remaining irregular vertices toward each other and
    /// sweeps again, while that helps.
    pub fn run(&mut self, max_sweeps: usize) {
        for _ in 0..max_sweeps {
            self.sweep(max_sweeps);
            if self.fq.irregular_count() == 0 || self.translation_steps == 0 || !self.compositions {
                break;
            }
            let mut moved = false;
            let mut v = 0u32;
            while (v as usize) < self.fq.verts.len() {
                if self.translate_at(v) {
                    moved = true;
                }
                v += 1;
            }
            if !moved {
                break;
            }
        }
    }

    fn sweep(&mut self, max_sweeps: usize) {
        for _ in 0..max_sweeps {
            self.counts.sweeps += 1;
            let mut changed = false;
            let mut q = 0u32;
            while (q as usize) < self.fq.quads.len() {
                if self.improve_at(q) {
                    changed = true;
                }
                q += 1;
            }
            if !changed || self.fq.irregular_count() == 0 {
                break;
            }
        }
    }

    /// Applies one operation with repositioning, without deciding (journaled).
    fn apply_repaired(&mut self, op: Op) -> bool {
        match apply(self.fq, self.face, op) {
            Some(region) => {
                repair(self.fq, self.face, &region, AngleWindow::BASE);
                true
            }
            None => false,
        }
    }

    /// Hops from `from` to the nearest irregular vertex outside `exclude`
    /// (`radius + 1` when none is that close).
    fn hops_to_irregular(&self, from: &[u32], exclude: &[u32], radius: usize) -> usize {
        let mut seen: Vec<u32> = from.to_vec();
        seen.sort_unstable();
        let mut front = seen.clone();
        for h in 1..=radius {
            let mut next = Vec::new();
            for &v in &front {
                for l in self.fq.links(v) {
                    if seen.binary_search(&l).is_ok() {
                        continue;
                    }
                    if self.fq.is_irregular(l) && !exclude.contains(&l) {
                        return h;
                    }
                    let pos = seen.binary_search(&l).unwrap_or_else(|e| e);
                    seen.insert(pos, l);
                    next.push(l);
                }
            }
            front = next;
        }
        radius + 1
    }

    /// Translation (paper Fig. 5): moves the irregular vertex `v` (with its
    /// irregular links, e.g. a (3, 5) pair) by valence-neutral swaps, each
    /// bringing it strictly closer to another irregular vertex, until an
    /// operation or composition lowers the score; keeps the whole chain only
    /// then (and only if valid), else rolls it back.
    pub fn translate_at(&mut self, v: u32) -> bool {
        if (v as usize) >= self.fq.verts.len() || !self.fq.is_irregular(v) || self.fq.verts[v as usize].fixed {
            return false;
        }
        const RADIUS: usize = 8;
        let cp = self.fq.checkpoint();
        let mut moving: Vec<u32> = std::iter::once(v).chain(self.fq.links(v).into_iter().filter(|&l| self.fq.is_irregular(l))).collect();
        moving.sort_unstable();
        let mut dist = self.hops_to_irregular(&moving, &moving, RADIUS);
        if dist > RADIUS {
            return false;
        }
        for _ in 0..self.translation_steps {
            // neutral swaps that move the group closer to another irregular vertex
            let mut best: Option<(usize, Op, Vec<u32>)> = None;
            for q in self.fq.quads_around(&moving) {
                for op in candidates_at(self.fq, q) {
                    if !matches!(op, Op::Swap { .. }) {
                        continue;
                    }
                    let Some(eff) = effect(self.fq, op) else { continue };
                    let d = score_delta(self.fq, &eff);
                    if d.0 != 0 || d.1 > 0 || !eff.changes.iter().any(|c| moving.binary_search(&c.0).is_ok()) {
                        continue;
                    }
                    let cp2 = self.fq.checkpoint();
                    if apply_topology(self.fq, op).is_some() {
                        let mut group: Vec<u32> = eff.changes.iter().map(|c| c.0).filter(|&x| self.fq.is_irregular(x)).collect();
                        group.sort_unstable();
                        let h = self.hops_to_irregular(&group, &group, RADIUS);
                        if h < dist && best.as_ref().map_or(true, |b| h < b.0) {
                            best = Some((h, op, group));
                        }
                    }
                    self.fq.rollback(cp2);
                }
            }
            let Some((h, op, group)) = best else { break };
            if !self.apply_repaired(op) {
                break;
            }
            dist = h;
            moving = group;
            // an improving operation or composition around the moved group?
            let start: Vec<Op> = self.fq.quads_around(&moving).into_iter().flat_map(|p| candidates_at(self.fq, p)).collect();
            let mut found = Vec::new();
            let mut budget = self.budget;
            self.singles_in_search = true;
            self.extend(&start, &mut Vec::new(), (0, 0), &moving, 2, &mut found, &mut budget);
            self.singles_in_search = false;
            found.sort();
            found.dedup_by(|a, b| a.1 == b.1);
            for (_, ops) in found.iter().take(self.tries) {
                let cp3 = self.fq.checkpoint();
                if ops.iter().all(|&o| self.apply_repaired(o)) && self.settle(cp) {
                    self.fq.commit();
                    self.counts.compositions += 1;
                    return true;
                }
                self.fq.rollback(cp3);
            }
        }
        self.fq.rollback(cp);
        false
    }
}
