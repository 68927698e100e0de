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
//! quads than before (in strict mode: any invalid quad), the whole sequence is
//! rolled back.
//!
//! Beyond the paper: once sweeps and translations stop, the **pair search**
//! ([`Regularizer::cancel_pair_at`]) looks, for each irregular vertex, for the
//! nearest vertex of opposite index a few hops away (a 5 for a 3, a boundary
//! vertex with an extra edge, or another dipole for a (3, 5) dipole) and
//! searches deeper sequences (4 operations by default, beam-limited) along
//! the path between them. The paper names such separated high-low pairs as
//! what its star-local operations leave behind (§IV; spec §11.1).
//!
//! Quads and pair searches that found nothing are not searched again until a
//! vertex near them changes (an epoch stamp per vertex), so later sweeps only
//! revisit the regions that moved.

use geometry::Face;

use crate::core::face_quads::FaceQuads;

use super::ops::{
    apply, apply_topology, candidates_at, effect_valences as effect, score_delta, Op,
};
use super::reposition::{repair, repair_rounds, REPAIR_ITERATIONS};
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
    /// Invalid flag per quad id (base window, or inverted by either judge:
    /// `quad_bad`), kept in step with accepted edits.
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
    /// Pair search ([`Regularizer::cancel_pair_at`]): hop radius within which a
    /// partner of opposite index is looked for (0 turns the search off).
    pub pair_radius: usize,
    /// Pair search: longest operation sequence.
    pub pair_depth: usize,
    /// Pair search: operations expanded per level, best score first.
    pub pair_beam: usize,
    /// Pair search: topological trial applications per searched pair.
    pub pair_budget: usize,
    /// Keep an edit only when its region ends with no invalid quad at all
    /// (default: no more than before, which lets an edit move an invalid quad
    /// of the input around).
    pub strict: bool,
    /// Visiting order of quads and vertices: 0 increasing ids, 1 decreasing,
    /// k ≥ 2 a fixed pseudo-random permutation seeded by k (each order ends
    /// the greedy search in a different local minimum).
    pub order: u32,
    /// Rounds of the repair loop after each operation
    /// ([`super::reposition::repair_rounds`]; default
    /// [`REPAIR_ITERATIONS`]). [`Regularizer::initial_repair`] lowers it to
    /// [`STUCK_REPAIR_ROUNDS`] when quads of the input stay invalid: every
    /// operation near such a quad would otherwise spend all rounds moving
    /// vertices around it, on a region that grows each round.
    pub repair_rounds: usize,
    /// Quad count the face should approach (0: no preference): among
    /// operations with the same valence score, those moving the count toward
    /// it win, and valence-neutral ones that do are accepted.
    pub target_quads: usize,
    /// +1 while above [`Regularizer::target_quads`], −1 below, 0 at it or off.
    quad_dir: i64,
    pub(super) singles_in_search: bool,
    /// Count of accepted edits; `stamp[v]` is the count when `v` last changed.
    pub(super) epoch: u64,
    pub(super) stamp: Vec<u64>,
    /// Epoch at which the pair search around a vertex last found nothing.
    pub(super) pair_failed: Vec<u64>,
    /// Epoch at which [`Regularizer::improve_at`] last found nothing at a quad.
    quad_failed: Vec<u64>,
    /// Work done so far, in counted units: [`GEOMETRIC_WORK`] per operation
    /// applied with repositioning, [`TRIAL_WORK`] per topological trial of a
    /// search, [`EVALUATION_WORK`] per candidate operation whose valence
    /// effect is evaluated (where most of the time of the searches goes).
    pub work: u64,
    /// What [`Regularizer::work`] counted, by kind.
    pub tally: WorkTally,
    /// Stop searching once [`Regularizer::work`] reaches this (0: no bound).
    /// Counted, never timed, so the result does not depend on the machine.
    pub work_cap: u64,
}

/// Work units of one operation applied with repositioning and its validity
/// check ([`Regularizer::work`]).
pub const GEOMETRIC_WORK: u64 = 300;

/// Work units of one topological trial of a search ([`Regularizer::work`]).
pub const TRIAL_WORK: u64 = 1;

/// Work units of one evaluation of a candidate operation's valence effect
/// ([`Regularizer::work`]).
pub const EVALUATION_WORK: u64 = 1;

/// The events [`Regularizer::work`] counts, by kind (for the logs and the
/// calibration of [`super::RegularizeOptions::work_per_quad`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct WorkTally {
    /// Operations applied with repositioning and a validity check.
    pub geometric: u64,
    /// Topological trials of the searches (applied and rolled back).
    pub trials: u64,
    /// Valence effects of candidate operations evaluated.
    pub evaluations: u64,
}

impl WorkTally {
    /// The sum of two tallies.
    pub fn plus(self, o: WorkTally) -> WorkTally {
        WorkTally {
            geometric: self.geometric + o.geometric,
            trials: self.trials + o.trials,
            evaluations: self.evaluations + o.evaluations,
        }
    }
}

/// Score change of an operation sequence: (irregular vertices, Σ|valence −
/// ideal|, quads away from [`Regularizer::target_quads`]), compared
/// lexicographically; negative is better.
pub(super) type Score = (i64, i64, i64);

/// Repair rounds per operation on a face whose input keeps invalid quads
/// after [`Regularizer::initial_repair`] (see [`Regularizer::repair_rounds`]).
pub const STUCK_REPAIR_ROUNDS: usize = 4;

/// Topological applications allowed per sequence search at one quad.
const SEARCH_BUDGET: usize = 600;

/// The ids `0..n` in the visiting order `order` (see [`Regularizer::order`]).
pub fn visiting_order(n: u32, order: u32) -> Vec<u32> {
    let mut ids: Vec<u32> = (0..n).collect();
    match order {
        0 => {}
        1 => ids.reverse(),
        k => {
            // splitmix64 of (id, seed): a permutation that depends only on k
            let key = |i: u32| {
                let mut z = (i as u64) ^ ((k as u64) << 32);
                z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
                z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
                z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
                z ^ (z >> 31)
            };
            ids.sort_by_key(|&i| key(i));
        }
    }
    ids
}

/// The flag [`Regularizer`] keeps per quad: invalid for the base window
/// ([`quad_valid`]) or inverted by either judge of the final check
/// ([`super::validity::quad_inverted`]; the projected check alone let edits
/// fold a corner of a large quad on a curved face against the surface there).
fn quad_bad(fq: &FaceQuads, face: &Face, q: u32) -> bool {
    !quad_valid(fq, face, q, AngleWindow::BASE) || super::validity::quad_inverted(fq, face, q)
}

pub(super) fn better(a: Score) -> bool {
    a < (0, 0, 0)
}

impl<'a> Regularizer<'a> {
    /// Prepares the state (computes the invalid flags of every quad).
    pub fn new(face: &'a Face, fq: &'a mut FaceQuads) -> Self {
        let invalid = (0..fq.quads.len() as u32)
            .map(|q| fq.quad_alive[q as usize] && quad_bad(fq, face, q))
            .collect();
        Regularizer {
            face,
            fq,
            invalid,
            counts: OpCounts::default(),
            compositions: true,
            tries: 4,
            max_ops: 3,
            budget: SEARCH_BUDGET,
            translation_steps: 8,
            pair_radius: 2,
            pair_depth: 4,
            pair_beam: 5,
            pair_budget: 600,
            strict: false,
            order: 0,
            repair_rounds: REPAIR_ITERATIONS,
            target_quads: 0,
            quad_dir: 0,
            singles_in_search: false,
            epoch: 1,
            stamp: Vec::new(),
            pair_failed: Vec::new(),
            quad_failed: Vec::new(),
            work: 0,
            tally: WorkTally::default(),
            work_cap: 0,
        }
    }

    /// True once [`Regularizer::work`] has reached a non-zero
    /// [`Regularizer::work_cap`]: no further search starts.
    pub fn exhausted(&self) -> bool {
        self.work_cap > 0 && self.work >= self.work_cap
    }

    pub(super) fn update_quad_dir(&mut self) {
        let q = self.fq.num_quads();
        self.quad_dir = if self.target_quads == 0 || q == self.target_quads {
            0
        } else if q > self.target_quads {
            1
        } else {
            -1
        };
    }

    /// The valence effect of `op` ([`super::ops::effect_valences`]), counted
    /// as [`EVALUATION_WORK`].
    pub(super) fn evaluate(&mut self, op: Op) -> Option<super::ops::Effect> {
        self.work += EVALUATION_WORK;
        self.tally.evaluations += 1;
        effect(self.fq, op)
    }

    /// One topological trial of a search, counted as [`TRIAL_WORK`].
    pub(super) fn count_trial(&mut self) {
        self.work += TRIAL_WORK;
        self.tally.trials += 1;
    }

    /// One operation applied with repositioning, counted as [`GEOMETRIC_WORK`].
    fn count_geometric(&mut self) {
        self.work += GEOMETRIC_WORK;
        self.tally.geometric += 1;
    }

    /// Score change of one operation ([`Score`]).
    pub(super) fn delta(&self, eff: &super::ops::Effect) -> Score {
        let d = score_delta(self.fq, eff);
        let dq = if eff.removed.is_some() {
            -1
        } else if eff.created.is_some() {
            1
        } else {
            0
        };
        (d.0, d.1, dq * self.quad_dir)
    }

    /// Number of live quads currently invalid for the base window.
    pub fn invalid_count(&self) -> usize {
        self.fq
            .live_quads()
            .filter(|&q| self.invalid[q as usize])
            .count()
    }

    /// Repairs the invalid quads of the input where repositioning can (each
    /// kept only when its region does not get worse). When some stay invalid,
    /// later operations get [`STUCK_REPAIR_ROUNDS`] repair rounds.
    pub fn initial_repair(&mut self) {
        let bad: Vec<u32> = self
            .fq
            .live_quads()
            .filter(|&q| self.invalid[q as usize])
            .collect();
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
        if self.invalid_count() > 0 {
            self.repair_rounds = self.repair_rounds.min(STUCK_REPAIR_ROUNDS);
        }
    }

    /// Compares the quads touched since `cp` with their state at `cp`: keeps the
    /// edit (updating the flags) when no more of them are invalid than before.
    pub(super) fn settle(&mut self, cp: crate::core::face_quads::Checkpoint) -> bool {
        let touched = self.fq.touched_since(cp);
        let live: Vec<u32> = touched
            .iter()
            .copied()
            .filter(|&v| self.fq.verts[v as usize].alive)
            .collect();
        let mut check = self.fq.quads_around(&live);
        let mut all = check.clone();
        all.extend(self.fq.quads_touched_since(cp));
        all.sort_unstable();
        all.dedup();
        let before = all
            .iter()
            .filter(|&&q| (q as usize) < self.invalid.len() && self.invalid[q as usize])
            .count();
        check.retain(|&q| self.fq.quad_alive[q as usize]);
        let flags: Vec<(u32, bool)> = check
            .iter()
            .map(|&q| (q, quad_bad(self.fq, self.face, q)))
            .collect();
        let after = flags.iter().filter(|f| f.1).count();
        if after > before || (self.strict && after > 0) {
            return false;
        }
        self.epoch += 1;
        self.stamp.resize(self.fq.verts.len(), 0);
        for &v in &touched {
            self.stamp[v as usize] = self.epoch;
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
            self.count_geometric();
            let Some(region) = apply(self.fq, self.face, op) else {
                self.fq.rollback(cp);
                return false;
            };
            repair_rounds(
                self.fq,
                self.face,
                &region,
                AngleWindow::BASE,
                self.repair_rounds,
            );
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
        self.fq.quads[q as usize]
            .iter()
            .any(|&v| self.fq.is_irregular(v))
    }

    /// Tries to lower the score around quad `q`; returns whether something was accepted.
    pub fn improve_at(&mut self, q: u32) -> bool {
        if self.exhausted() || !self.fq.quad_alive[q as usize] || !self.has_irregular(q) {
            return false;
        }
        let cands = candidates_at(self.fq, q);
        self.update_quad_dir();
        let mut single: Vec<(Score, usize, Op)> = Vec::new();
        for (i, &op) in cands.iter().enumerate() {
            let Some(eff) = self.evaluate(op) else {
                continue;
            };
            let d = self.delta(&eff);
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
            self.extend(
                &cands,
                &mut Vec::new(),
                (0, 0, 0),
                &[],
                len,
                &mut found,
                &mut budget,
            );
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
    pub(super) fn extend(
        &mut self,
        start: &[Op],
        path: &mut Vec<Op>,
        acc: Score,
        seeds: &[u32],
        len: usize,
        found: &mut Vec<(Score, Vec<Op>)>,
        budget: &mut usize,
    ) {
        let cands: Vec<Op> = if path.is_empty() {
            start.to_vec()
        } else {
            self.fq
                .quads_around(seeds)
                .into_iter()
                .flat_map(|p| candidates_at(self.fq, p))
                .collect()
        };
        for op in cands {
            let Some(eff) = self.evaluate(op) else {
                continue;
            };
            if !path.is_empty()
                && !eff
                    .changes
                    .iter()
                    .any(|c| c.1 != c.2 && seeds.binary_search(&c.0).is_ok())
            {
                continue;
            }
            let d1 = self.delta(&eff);
            let d = (acc.0 + d1.0, acc.1 + d1.1, acc.2 + d1.2);
            if better(d) {
                if !path.is_empty() || self.singles_in_search {
                    let mut ops = path.clone();
                    ops.push(op);
                    found.push((d, ops));
                }
                continue;
            }
            if path.len() + 1 >= len || d.0 > 1 || *budget == 0 || self.exhausted() {
                continue;
            }
            *budget -= 1;
            self.count_trial();
            let cp = self.fq.checkpoint();
            if apply_topology(self.fq, op).is_some() {
                let mut changed: Vec<u32> = eff
                    .changes
                    .iter()
                    .filter(|c| c.1 != c.2)
                    .map(|c| c.0)
                    .collect();
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
    /// searches for pairs of opposite index to cancel ([`Regularizer::cancel_pair_at`]),
    /// sweeping again after each, while that helps.
    pub fn run(&mut self, max_sweeps: usize) {
        for _ in 0..max_sweeps {
            self.sweep(max_sweeps);
            if self.fq.irregular_count() == 0 || !self.compositions || self.exhausted() {
                break;
            }
            let mut moved = false;
            if self.translation_steps > 0 {
                for v in visiting_order(self.fq.verts.len() as u32, self.order) {
                    if self.exhausted() {
                        break;
                    }
                    if self.translate_at(v) {
                        moved = true;
                    }
                }
            }
            if !moved && self.pair_radius > 0 {
                for v in visiting_order(self.fq.verts.len() as u32, self.order) {
                    if self.exhausted() {
                        break;
                    }
                    if self.cancel_pair_at(v) {
                        moved = true;
                    }
                }
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
            let n = self.fq.quads.len() as u32;
            for q in visiting_order(n, self.order) {
                if self.exhausted() {
                    break;
                }
                if (q as usize) < self.fq.quads.len() && self.visit(q) {
                    changed = true;
                }
            }
            if !changed || self.fq.irregular_count() == 0 || self.exhausted() {
                break;
            }
        }
    }

    /// [`Regularizer::improve_at`], skipped when it already found nothing at
    /// `q` and no vertex within two hops of `q` has changed since.
    fn visit(&mut self, q: u32) -> bool {
        if !self.fq.quad_alive[q as usize] || !self.has_irregular(q) {
            return false;
        }
        self.stamp.resize(self.fq.verts.len(), 0);
        self.quad_failed.resize(self.fq.quads.len(), 0);
        let failed = self.quad_failed[q as usize];
        if failed > 0 {
            let corners = self.fq.quads[q as usize];
            let mut near = Vec::new();
            for c in corners {
                near.extend(self.ball(c, 2));
            }
            if near.iter().all(|&w| self.stamp[w as usize] <= failed) {
                return false;
            }
        }
        if self.improve_at(q) {
            true
        } else {
            self.quad_failed.resize(self.fq.quads.len(), 0);
            self.quad_failed[q as usize] = self.epoch;
            false
        }
    }

    /// The vertices within `radius` hops of `v` (itself included).
    pub(super) fn ball(&self, v: u32, radius: usize) -> Vec<u32> {
        let mut seen = vec![v];
        let mut front = vec![v];
        for _ in 0..radius {
            let mut next = Vec::new();
            for &a in &front {
                for l in self.fq.links(a) {
                    if !seen.contains(&l) {
                        seen.push(l);
                        next.push(l);
                    }
                }
            }
            front = next;
        }
        seen
    }

    /// Applies one operation with repositioning, without deciding (journaled).
    pub(super) fn apply_repaired(&mut self, op: Op) -> bool {
        self.count_geometric();
        match apply(self.fq, self.face, op) {
            Some(region) => {
                repair_rounds(
                    self.fq,
                    self.face,
                    &region,
                    AngleWindow::BASE,
                    self.repair_rounds,
                );
                true
            }
            None => false,
        }
    }
}
