//! Cavity growth (spec §10.3), the search for candidates: from the quads
//! around a seed vertex, a cavity grows in breadth-first order under the
//! growth rules (a disk, concave vertices filled first, singular vertices,
//! concave CAD corners and poles respected); each time it is a convex disk,
//! its side counts are matched against the target patterns ([`Target`]),
//! which gives the remeshable cavities ([`Candidate`]).

use std::collections::VecDeque;

use geometry::vec3;

use crate::combinatorics::patterns::{match_pattern_where, Pattern, PatternMatch};

use super::work::{Kind, Work, NBR_NONE, NBR_UNKNOWN};
use super::{MAX_MAXIMAL_QUADS, MAX_MINIMAL_QUADS};

/// Remeshable cavities kept per minimal growth (tried in order).
const MINIMAL_CANDIDATES: usize = 3;
/// Remeshable cavities tried per maximal growth (the largest ones).
const MAXIMAL_CANDIDATES: usize = 4;

/// The role of a cavity boundary vertex in the cavity polygon.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Role {
    Interior,
    Corner,
    Flat,
    Concave,
}

/// Which patterns a growth targets.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Target {
    /// The regular grid R1.
    Grid,
    /// Any rectangular pattern.
    Rect,
    /// A pattern with `n` sides and one irregular vertex (T3, P5).
    Star(usize),
}

impl Target {
    pub(super) fn keeps(self, p: &Pattern) -> bool {
        match self {
            Target::Grid => p.sides() == 4 && p.irregular == 0,
            Target::Rect => p.sides() == 4,
            Target::Star(n) => p.sides() == n && p.irregular == 1,
        }
    }
}

/// A remeshable cavity: its quads, boundary loop (in the quads' orientation),
/// positions of its corners in the loop, and the matched pattern.
#[derive(Clone, Debug)]
pub(super) struct Candidate {
    pub(super) quads: Vec<u32>,
    pub(super) ring: Vec<u32>,
    pub(super) corners: Vec<usize>,
    pub(super) found: PatternMatch,
}

impl Work<'_> {
    // ---- growth -------------------------------------------------------

    fn in_c(&self, q: u32) -> bool {
        self.in_c[q as usize] == self.stamp
    }

    pub(super) fn nin(&self, v: u32) -> usize {
        let (s, c) = self.nin[v as usize];
        if s == self.stamp {
            c as usize
        } else {
            0
        }
    }

    /// True for a concave CAD corner (ideal `ideal` ≥ 3 quads) that has
    /// more quads than its ideal: a cavity may take three of them and give
    /// it back two, a side vertex of the pattern (n12o_limit_cycle_genus0's
    /// 270° corner with 4 quads, which kept a valence-3 vertex beside it).
    pub(super) fn sheds_a_quad(&self, v: u32, ideal: u8) -> bool {
        ideal >= 3 && self.deg(v) > ideal as usize && self.deg(v) >= 4
    }

    pub(super) fn role(&self, v: u32) -> Role {
        let ni = self.nin(v);
        let no = self.deg(v) - ni;
        let by_count = match ni {
            0 | 1 => Role::Corner,
            2 => Role::Flat,
            _ => Role::Concave,
        };
        match self.kind[v as usize] {
            Kind::Pole => Role::Concave,
            Kind::Inner => {
                if no == 0 {
                    Role::Interior
                } else {
                    by_count
                }
            }
            Kind::Bound(ideal) => {
                if no > 0 {
                    if ni == 3 && self.sheds_a_quad(v, ideal) {
                        // a concave CAD corner with a quad too many: a side
                        // vertex of the pattern (2 quads), one quad fewer
                        Role::Flat
                    } else {
                        by_count
                    }
                } else {
                    match ideal {
                        1 => Role::Corner,
                        2 => Role::Flat,
                        _ => Role::Concave,
                    }
                }
            }
        }
    }

    /// The quad across edge `k` of live quad `q`, if any (kept in `nbr`
    /// until a replacement touches `q`'s vertices).
    fn across(&self, q: u32, k: usize) -> Option<u32> {
        let cached = &self.nbr[q as usize][k];
        match cached.get() {
            NBR_UNKNOWN => {}
            NBR_NONE => return None,
            r => return Some(r),
        }
        let quad = self.p.quads[q as usize];
        let (a, b) = (quad[k], quad[(k + 1) % 4]);
        let r = self.at[a as usize].iter().copied().find(|&r| {
            r != q && {
                let o = self.p.quads[r as usize];
                (0..4).any(|i| {
                    (o[i] == b && o[(i + 1) % 4] == a) || (o[i] == a && o[(i + 1) % 4] == b)
                })
            }
        });
        cached.set(r.unwrap_or(NBR_NONE));
        r
    }

    /// Forgets the neighbours of the live quads at the vertices of `quads`
    /// (their edges may now border other quads).
    pub(super) fn forget_neighbours(&self, quads: &[u32]) {
        for &q in quads {
            for &v in &self.p.quads[q as usize] {
                for &r in &self.at[v as usize] {
                    for c in &self.nbr[r as usize] {
                        c.set(NBR_UNKNOWN);
                    }
                }
            }
        }
    }

    /// True when the cavity plus quad `q` is still a disk: `q` meets the
    /// cavity along one path of 1 to 3 of its edges and nowhere else.
    fn keeps_disk(&self, q: u32) -> bool {
        let quad = self.p.quads[q as usize];
        let shared: Vec<bool> = (0..4)
            .map(|k| self.across(q, k).is_some_and(|r| self.in_c(r)))
            .collect();
        let n = shared.iter().filter(|&&s| s).count();
        if n == 0
            || n == 4
            || (0..4)
                .filter(|&k| shared[k] && !shared[(k + 3) % 4])
                .count()
                != 1
        {
            return false;
        }
        (0..4).all(|k| (self.nin(quad[k]) > 0) == (shared[k] || shared[(k + 3) % 4]))
    }

    /// True when adding quad `q` breaks a growth rule (`seed` may become interior).
    pub(super) fn forbidden(&self, q: u32, seed: Option<u32>) -> bool {
        if !self.alive[q as usize] || self.in_c(q) || self.barred[q as usize] == self.stamp {
            return true;
        }
        if self.disk_rule && !self.keeps_disk(q) {
            return true;
        }
        for &v in &self.p.quads[q as usize] {
            let ni = self.nin(v) + 1;
            let no = self.deg(v) - ni;
            match self.kind[v as usize] {
                Kind::Pole => return true,
                Kind::Inner => {
                    if self.singular[v as usize] && Some(v) != seed && (ni >= 3 || no <= 1) {
                        return true;
                    }
                }
                Kind::Bound(ideal) => {
                    if ideal >= 3
                        && (no == 0 || ni > 3 || (ni == 3 && !self.sheds_a_quad(v, ideal)))
                    {
                        return true;
                    }
                }
            }
        }
        false
    }

    fn add(&mut self, q: u32, todo: &mut Vec<u32>, queue: &mut VecDeque<u32>) {
        let stamp = self.stamp;
        self.in_c[q as usize] = stamp;
        self.order.push(q);
        self.units += 1;
        let quad = self.p.quads[q as usize];
        for k in 0..4 {
            let x = self.p.pos[quad[k] as usize];
            let r = vec3::dist(x, self.reach.0);
            let e = vec3::dist(x, self.p.pos[quad[(k + 1) % 4] as usize]);
            self.reach.1 = self.reach.1.max(r);
            self.reach.2 = self.reach.2.max(e);
        }
        for &v in &quad {
            let e = &mut self.nin[v as usize];
            if e.0 != stamp {
                *e = (stamp, 0);
            }
            e.1 += 1;
        }
        for &v in &quad {
            let no = self.deg(v) - self.nin(v);
            if no == 0 && self.irregular(v) && !self.singular[v as usize] {
                self.absorbed = true;
            }
            if no == 1 {
                todo.push(v);
            }
        }
        for k in 0..4 {
            if let Some(r) = self.across(q, k) {
                if self.queued[r as usize] != stamp && !self.in_c(r) {
                    self.queued[r as usize] = stamp;
                    queue.push_back(r);
                }
            }
        }
    }

    /// Undoes the growth back to `len` quads.
    fn shrink(&mut self, len: usize) {
        while self.order.len() > len {
            let q = self.order.pop().unwrap_or(0);
            self.in_c[q as usize] = 0;
            for &v in &self.p.quads[q as usize] {
                self.nin[v as usize].1 -= 1;
            }
        }
    }

    /// Absorbs the outside quad of every concave vertex with one outside
    /// quad; false when one of them is forbidden.
    fn convexify(
        &mut self,
        todo: &mut Vec<u32>,
        queue: &mut VecDeque<u32>,
        seed: Option<u32>,
        cap: usize,
    ) -> bool {
        while let Some(v) = todo.pop() {
            let ni = self.nin(v);
            let no = self.deg(v) - ni;
            if no != 1 {
                continue;
            }
            let concave = match self.kind[v as usize] {
                Kind::Inner => true,
                Kind::Bound(_) => ni >= 3,
                Kind::Pole => false,
            };
            if !concave {
                continue;
            }
            let Some(q) = self.at[v as usize].iter().copied().find(|&q| !self.in_c(q)) else {
                continue;
            };
            if self.forbidden(q, seed) || self.order.len() >= cap {
                return false;
            }
            self.add(q, todo, queue);
        }
        true
    }

    /// The boundary edges of the cavity (`self.order`) as a successor map,
    /// read with [`Work::boundary_next`] until the next call:
    /// `(tail of the first boundary edge met, smallest tail, boundary edges,
    /// inner edge sides)`; `None` when a vertex starts two boundary edges
    /// (the cavity is not a disk). Arrays stamped per call instead of a hash
    /// map: this runs at every check of every growing cavity.
    fn boundary(&mut self) -> Option<(Option<u32>, u32, usize, usize)> {
        let n = self.p.nodes.len();
        if self.bnext.len() < n {
            self.bnext.resize(n, 0);
            self.bmark.resize(n, 0);
        }
        self.bclock = self.bclock.wrapping_add(1);
        if self.bclock == 0 {
            self.bmark.fill(0);
            self.vseen.fill(0);
            self.bclock = 1;
        }
        let c = self.bclock;
        let (mut first, mut min, mut count, mut inner) = (None, u32::MAX, 0usize, 0usize);
        for i in 0..self.order.len() {
            let q = self.order[i];
            let quad = self.p.quads[q as usize];
            for k in 0..4 {
                match self.across(q, k) {
                    Some(r) if self.in_c(r) => inner += 1,
                    _ => {
                        let (a, b) = (quad[k], quad[(k + 1) % 4]);
                        if self.bmark[a as usize] == c {
                            return None;
                        }
                        self.bmark[a as usize] = c;
                        self.bnext[a as usize] = b;
                        first.get_or_insert(a);
                        min = min.min(a);
                        count += 1;
                    }
                }
            }
        }
        Some((first, min, count, inner))
    }

    /// The head of the boundary edge starting at `v` in the last
    /// [`Work::boundary`] map.
    fn boundary_next(&self, v: u32) -> Option<u32> {
        (self.bmark.get(v as usize) == Some(&self.bclock)).then(|| self.bnext[v as usize])
    }

    /// True when the cavity's boundary is one simple loop.
    fn is_disk(&mut self) -> bool {
        let Some((_, start, count, _)) = self.boundary() else {
            return false;
        };
        if count == 0 {
            return false;
        }
        let (mut v, mut len) = (start, 0);
        loop {
            v = match self.boundary_next(v) {
                Some(w) => w,
                None => return false,
            };
            len += 1;
            if v == start || len > count {
                break;
            }
        }
        v == start && len == count
    }

    /// The cavity's boundary loop if it is a convex disk, with the corner
    /// positions and the matched pattern if any: `(convex disk, candidate)`.
    fn check(&mut self, target: Target) -> (bool, Option<Candidate>) {
        let Some((first, _, count, inner_edges)) = self.boundary() else {
            return (false, None);
        };
        self.units += self.order.len() as u64;
        let Some(start) = first else {
            return (false, None);
        };
        let mut ring = vec![start];
        let Some(mut v) = self.boundary_next(start) else {
            return (false, None);
        };
        while v != start {
            ring.push(v);
            match self.boundary_next(v) {
                Some(w) if ring.len() <= count => v = w,
                _ => return (false, None),
            }
        }
        if ring.len() != count {
            return (false, None);
        }
        // Euler: V − E + F = 1 (vertices counted with a stamp of this check)
        if self.vseen.len() < self.bmark.len() {
            self.vseen.resize(self.bmark.len(), 0);
        }
        let mut verts = 0i64;
        for &q in &self.order {
            for v in self.p.quads[q as usize] {
                if self.vseen[v as usize] != self.bclock {
                    self.vseen[v as usize] = self.bclock;
                    verts += 1;
                }
            }
        }
        let edges = inner_edges / 2 + ring.len();
        if verts - edges as i64 + self.order.len() as i64 != 1 {
            return (false, None);
        }
        let mut corners = Vec::new();
        for (i, &v) in ring.iter().enumerate() {
            match self.role(v) {
                Role::Corner => corners.push(i),
                Role::Flat => {}
                Role::Concave | Role::Interior => return (false, None),
            }
        }
        let m = corners.len();
        let nb = ring.len();
        let sides: Vec<u32> = (0..m)
            .map(|i| ((corners[(i + 1) % m] + nb - corners[i]) % nb) as u32)
            .collect();
        if !(3..=5).contains(&m) {
            return (true, None);
        }
        let found = match_pattern_where(&sides, |p| target.keeps(p));
        (
            true,
            found.map(|found| Candidate {
                quads: self.order.clone(),
                ring,
                corners,
                found,
            }),
        )
    }

    /// Grows cavities from the quads around `seed` (spec §10.3) and returns
    /// the remeshable ones worth trying, best first.
    pub(super) fn grow(
        &mut self,
        seed: u32,
        target: Target,
        minimal: bool,
        seed_may_be_interior: bool,
    ) -> Vec<Candidate> {
        self.stamp += 1;
        self.order.clear();
        self.absorbed = false;
        self.reach = (self.p.pos[seed as usize], 0.0, 0.0);
        let allow = seed_may_be_interior.then_some(seed);
        let cap = if minimal {
            MAX_MINIMAL_QUADS
        } else {
            MAX_MAXIMAL_QUADS
        };
        let mut todo = Vec::new();
        let mut queue = VecDeque::new();
        self.disk_rule = false;
        for q in self.at[seed as usize].clone() {
            if self.forbidden(q, allow) {
                return Vec::new();
            }
            self.add(q, &mut todo, &mut queue);
        }
        if !self.is_disk() {
            return Vec::new();
        }
        self.disk_rule = true;
        if !self.convexify(&mut todo, &mut queue, allow, cap) {
            return Vec::new();
        }
        let mut found: Vec<Candidate> = Vec::new();
        // checked again after growing by an eighth (bounds the work by about 8 × the cavity)
        let mut next_check = 0;
        loop {
            if self.absorbed && self.order.len() >= next_check {
                let (convex, cand) = self.check(target);
                if convex {
                    self.absorbed = false;
                }
                next_check = self.order.len() + self.order.len() / 8 + 1;
                if let Some(c) = cand {
                    found.push(c);
                    if minimal && found.len() >= MINIMAL_CANDIDATES {
                        break;
                    }
                }
            }
            if self.order.len() >= cap {
                break;
            }
            // the next quad in breadth-first order that keeps the rules
            let mut grown = false;
            while let Some(q) = queue.pop_front() {
                if self.in_c(q) {
                    continue;
                }
                if !self.keeps_disk(q) {
                    // not now (it touches the cavity at a vertex, or its
                    // neighbour in the cavity was undone): it may come back
                    // when a neighbour joins the cavity
                    self.queued[q as usize] = 0;
                    continue;
                }
                if self.forbidden(q, allow) {
                    continue;
                }
                let len = self.order.len();
                let absorbed = self.absorbed;
                self.add(q, &mut todo, &mut queue);
                if self.convexify(&mut todo, &mut queue, allow, cap) {
                    grown = true;
                    break;
                }
                todo.clear();
                self.shrink(len);
                self.absorbed = absorbed;
                self.barred[q as usize] = self.stamp;
            }
            if !grown {
                break;
            }
        }
        if !minimal {
            // maximal: the largest remeshable cavities first
            found.reverse();
            found.truncate(MAXIMAL_CANDIDATES);
        }
        found
    }
}
