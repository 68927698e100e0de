//! The face being edited ([`Work`]): the adjacency of its quads, what
//! each vertex is for the cavity rules ([`Kind`]) and whether it is
//! irregular, the matching of singular vertices (spec §10.2), and the
//! steps of the strategy (§10.4), which grow cavities around their seeds
//! and try the replacements, remembering the seeds that failed.

use std::collections::HashMap;

use geometry::vec3::{self, Vec3};
use geometry::Face;

use crate::core::patch::NodeRef;
use crate::core::patch::QuadPatch;
use crate::field::singularities::{Singularity, SingularitySite};

use super::growth::Target;
use super::{CavityReport, KEEP};

/// [`Work::across`] not asked yet for this quad edge.
pub(super) const NBR_UNKNOWN: u32 = u32::MAX - 1;
/// No quad across this edge (the face boundary).
pub(super) const NBR_NONE: u32 = u32::MAX;

pub(super) fn unknown_neighbours() -> [std::cell::Cell<u32>; 4] {
    std::array::from_fn(|_| std::cell::Cell::new(NBR_UNKNOWN))
}

/// What a vertex is for the cavity rules.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Kind {
    /// Face interior (movable, ideal valence 4).
    Inner,
    /// On the face boundary, with its ideal number of quads (2 on a curve).
    Bound(u8),
    /// On a degenerate curve: cavities stay away.
    Pole,
}

/// The face being edited with its adjacency and the growth scratch space.
pub(super) struct Work<'a> {
    pub(super) face: &'a Face,
    pub(super) p: &'a mut QuadPatch,
    pub(super) alive: Vec<bool>,
    /// Live quads at each vertex, sorted.
    pub(super) at: Vec<Vec<u32>>,
    pub(super) kind: Vec<Kind>,
    pub(super) singular: Vec<bool>,
    pub(super) units: u64,
    // growth scratch, valid for the current `stamp`
    pub(super) stamp: u32,
    pub(super) in_c: Vec<u32>,
    pub(super) queued: Vec<u32>,
    pub(super) barred: Vec<u32>,
    pub(super) nin: Vec<(u32, u16)>,
    pub(super) order: Vec<u32>,
    pub(super) absorbed: bool,
    /// Growth keeps the cavity a disk (off while the seed's quads go in).
    pub(super) disk_rule: bool,
    /// Replacements undone since the last kept one (cavity quads, pattern, subdivisions):
    /// not tried again.
    pub(super) undone: std::collections::HashSet<Vec<u32>>,
    // boundary successor map of [`Work::boundary`], valid where `bmark == bclock`
    pub(super) bnext: Vec<u32>,
    pub(super) bmark: Vec<u32>,
    pub(super) bclock: u32,
    // vertices counted by [`Work::check`], stamped with `bclock`
    pub(super) vseen: Vec<u32>,
    /// Per quad and edge, the quad across ([`Work::across`]): [`NBR_UNKNOWN`]
    /// until asked, [`NBR_NONE`] on the face boundary.
    pub(super) nbr: Vec<[std::cell::Cell<u32>; 4]>,
    /// The ball the current growth has reached: its centre (the seed), the
    /// largest distance from it to a vertex of a quad added, and the longest
    /// edge of those quads.
    pub(super) reach: (Vec3, f64, f64),
    /// Balls of the replacements kept so far (every vertex of the new quads
    /// and of the quads smoothed around them), in order.
    pub(super) kept_balls: Vec<(Vec3, f64)>,
    /// Seeds whose last attempt at a step found nothing to keep: the number
    /// of kept replacements then, and the ball the attempt depended on. A
    /// later pass tries them again only if a replacement since has reached
    /// that ball (otherwise they would fail the same way).
    pub(super) failed: HashMap<(u32, usize), (usize, Vec3, f64)>,
}

impl<'a> Work<'a> {
    pub(super) fn new(face: &'a Face, p: &'a mut QuadPatch) -> Self {
        let n = p.nodes.len();
        let mut at = vec![Vec::new(); n];
        for (qi, q) in p.quads.iter().enumerate() {
            for &v in q {
                at[v as usize].push(qi as u32);
            }
        }
        // ideal quads at a boundary vertex: 2 on a curve, from the angle at a corner
        let mut angle = vec![0.0; n];
        for q in &p.quads {
            for k in 0..4 {
                let v = q[k] as usize;
                if matches!(p.nodes[v].node, NodeRef::Corner(_)) {
                    let x = p.pos[v];
                    let (a, b) = (
                        vec3::sub(p.pos[q[(k + 1) % 4] as usize], x),
                        vec3::sub(p.pos[q[(k + 3) % 4] as usize], x),
                    );
                    let c = vec3::dot(a, b) / (vec3::norm(a) * vec3::norm(b));
                    if c.is_finite() {
                        angle[v] += c.clamp(-1.0, 1.0).acos();
                    }
                }
            }
        }
        let kind = (0..n)
            .map(|v| {
                let nd = &p.nodes[v];
                if nd.pole.is_some() {
                    return Kind::Pole;
                }
                match nd.node {
                    NodeRef::Interior => Kind::Inner,
                    NodeRef::Curve(..) => Kind::Bound(2),
                    NodeRef::Corner(_) => Kind::Bound(
                        crate::core::valence::ideal_corner_valence(angle[v]).clamp(1, 4) as u8,
                    ),
                }
            })
            .collect();
        let nq = p.quads.len();
        Work {
            face,
            alive: vec![true; nq],
            at,
            kind,
            singular: vec![false; n],
            units: 0,
            stamp: 0,
            in_c: vec![0; nq],
            queued: vec![0; nq],
            barred: vec![0; nq],
            nin: vec![(0, 0); n],
            order: Vec::new(),
            absorbed: false,
            disk_rule: false,
            undone: std::collections::HashSet::new(),
            bnext: Vec::new(),
            bmark: Vec::new(),
            bclock: 0,
            vseen: Vec::new(),
            nbr: (0..p.quads.len()).map(|_| unknown_neighbours()).collect(),
            reach: ([0.0; 3], 0.0, 0.0),
            kept_balls: Vec::new(),
            failed: HashMap::new(),
            p,
        }
    }

    pub(super) fn deg(&self, v: u32) -> usize {
        self.at[v as usize].len()
    }

    /// Irregular: a live vertex off its ideal number of quads.
    pub(super) fn irregular(&self, v: u32) -> bool {
        self.irregular_with(v, self.deg(v))
    }

    pub(super) fn irregular_with(&self, v: u32, d: usize) -> bool {
        if self.at[v as usize].is_empty() {
            return false;
        }
        match self.kind[v as usize] {
            Kind::Inner => d != 4,
            Kind::Bound(ideal) => d != ideal as usize,
            Kind::Pole => false,
        }
    }

    /// Face-interior irregular vertices.
    pub(super) fn inner_irregular(&self) -> usize {
        (0..self.at.len() as u32)
            .filter(|&v| self.kind[v as usize] == Kind::Inner && self.irregular(v))
            .count()
    }

    pub(super) fn all_irregular(&self) -> usize {
        (0..self.at.len() as u32)
            .filter(|&v| self.irregular(v))
            .count()
    }

    /// Flags singular vertices (spec §10.2): each singularity not `used`
    /// yet takes the nearest free vertex of its valence within `radius`
    /// sizes; returns how many were matched (and marks them `used`).
    pub(super) fn match_singularities(
        &mut self,
        list: &[Singularity],
        radius: f64,
        used: &mut [bool],
    ) -> usize {
        let mut pairs: Vec<(f64, usize, u32)> = Vec::new();
        for (si, s) in list.iter().enumerate() {
            if used[si] || matches!(s.site, SingularitySite::AcuteCorner(..)) || s.index.abs() != 1
            {
                continue;
            }
            let want = (4 - s.index) as usize;
            for v in 0..self.at.len() as u32 {
                if self.kind[v as usize] != Kind::Inner || self.deg(v) != want {
                    continue;
                }
                let x = self.p.pos[v as usize];
                let d = vec3::dist(x, s.position);
                let (mut len, mut k) = (0.0, 0);
                for &q in &self.at[v as usize] {
                    let quad = self.p.quads[q as usize];
                    let i = quad.iter().position(|&y| y == v).unwrap_or(0);
                    len += vec3::dist(x, self.p.pos[quad[(i + 1) % 4] as usize]);
                    k += 1;
                }
                // the size map at the singularity (spec §10.2); without it,
                // the vertex's own edges (short around a valence-3 vertex)
                let h = s.size.unwrap_or(len / k.max(1) as f64);
                if d.is_finite() && d <= radius * h {
                    pairs.push((d, si, v));
                }
            }
        }
        pairs.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
        let mut matched = 0;
        for (_, si, v) in pairs {
            if !used[si] && !self.singular[v as usize] {
                used[si] = true;
                self.singular[v as usize] = true;
                matched += 1;
            }
        }
        matched
    }

    /// Step 1 / 3 / 4: cavities around the unnecessary irregular vertices.
    pub(super) fn rect_step(
        &mut self,
        target: Target,
        minimal: bool,
        keep: f64,
        step: usize,
        cap: u64,
        report: &mut CavityReport,
    ) {
        // face-interior seeds first, then the boundary's
        let mut seeds: Vec<u32> = (0..self.at.len() as u32)
            .filter(|&v| self.irregular(v) && !self.singular[v as usize])
            .collect();
        seeds.sort_by_key(|&v| (self.kind[v as usize] != Kind::Inner, v));
        for seed in seeds {
            if self.units >= cap {
                report.capped = true;
                return;
            }
            if !self.irregular(seed) || self.singular[seed as usize] || self.unchanged(seed, step) {
                continue;
            }
            let mut kept = false;
            for cand in self.grow(seed, target, minimal, false) {
                if cand.quads.iter().any(|&q| !self.alive[q as usize]) {
                    continue;
                }
                self.stamp += 1;
                // `nin` of the candidate's quads for the rules of `replace`
                self.mark(&cand.quads);
                if self.replace(&cand, keep, report).is_some() {
                    report.replaced[step] += 1;
                    kept = true;
                    break;
                }
            }
            self.remember(seed, step, kept);
        }
    }

    /// Margin of a failed attempt's ball, in its longest edges: the growth
    /// rules look at the quads next to the cavity, the smoothing of a
    /// replacement at two rings around it.
    const BALL_MARGIN_EDGES: f64 = 3.0;

    /// The key of `failed` for an attempt at `seed` in `step`: steps 1 and 3
    /// grow the same maximal cavities with the same rules, so a seed that
    /// failed one fails the other until something changes near it.
    fn attempt_key(seed: u32, step: usize) -> (u32, usize) {
        (seed, if step == 2 { 0 } else { step })
    }

    /// Records the attempt just made at `seed` in `step` (see `failed`).
    fn remember(&mut self, seed: u32, step: usize, kept: bool) {
        let key = Self::attempt_key(seed, step);
        if kept {
            self.failed.remove(&key);
        } else {
            let (centre, r, e) = self.reach;
            let ball = (centre, r + Self::BALL_MARGIN_EDGES * e);
            self.failed
                .insert(key, (self.kept_balls.len(), ball.0, ball.1));
        }
    }

    /// True when `seed` failed at `step` before and no replacement kept
    /// since has reached the ball that attempt depended on: trying again
    /// would grow the same cavities and fail the same way.
    fn unchanged(&self, seed: u32, step: usize) -> bool {
        let Some(&(since, centre, radius)) = self.failed.get(&Self::attempt_key(seed, step)) else {
            return false;
        };
        self.kept_balls[since..]
            .iter()
            .all(|&(c, r)| vec3::dist(c, centre) > r + radius)
    }

    /// Step 2: minimal triangle / pentagon cavities around singular vertices.
    pub(super) fn star_step(&mut self, cap: u64, report: &mut CavityReport) {
        let seeds: Vec<u32> = (0..self.at.len() as u32)
            .filter(|&v| self.singular[v as usize])
            .collect();
        for seed in seeds {
            if self.units >= cap {
                report.capped = true;
                return;
            }
            let n = match self.deg(seed) {
                3 => 3,
                5 => 5,
                _ => continue,
            };
            if self.unchanged(seed, 1) {
                continue;
            }
            let mut kept = false;
            for cand in self.grow(seed, Target::Star(n), true, true) {
                self.stamp += 1;
                self.mark(&cand.quads);
                if let Some(fresh) = self.replace(&cand, KEEP, report) {
                    // the singularity moves to the pattern's irregular vertex
                    self.singular[seed as usize] = false;
                    if let Some(&c) = fresh.iter().find(|&&v| self.deg(v) == n) {
                        self.singular[c as usize] = true;
                    }
                    report.replaced[1] += 1;
                    kept = true;
                    break;
                }
            }
            self.remember(seed, 1, kept);
        }
    }

    /// Sets the cavity quads and `nin` for the current stamp.
    pub(super) fn mark(&mut self, quads: &[u32]) {
        let stamp = self.stamp;
        for &q in quads {
            self.in_c[q as usize] = stamp;
            for &v in &self.p.quads[q as usize] {
                let e = &mut self.nin[v as usize];
                if e.0 != stamp {
                    *e = (stamp, 0);
                }
                e.1 += 1;
            }
        }
    }
}
