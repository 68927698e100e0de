//! Quasi-structured topology by cavity remeshing (paper §6.2, spec §10), on
//! the quads of one face ([`QuadPatch`]) after the unstructured mesher and
//! the defect removal.
//!
//! - **Singular vertices** (§10.2): each cross-field singularity of index
//!   ±1 flags the nearest face-interior vertex of valence 3 / 5 within
//!   [`MATCH_RADIUS`] × its local edge length (pairs by increasing distance,
//!   each vertex at most once). Every other irregular vertex is
//!   *unnecessary*.
//! - **Cavity growth** (§10.3): from the quads around a seed vertex, quads
//!   are added in breadth-first order; a face-interior vertex of the cavity
//!   boundary with one outside quad (a concave vertex) gets that quad first.
//!   A quad is never added when it would make a singular vertex interior or
//!   concave, leave a concave CAD corner (ideal valence ≥ 3) without an
//!   outside quad or with three cavity quads, or touch a pole. (A concave
//!   corner with more quads than its ideal may have three cavity quads: it
//!   is then a side vertex of the pattern, which gives it two back.) Each time the cavity has absorbed a new
//!   irregular vertex and is a convex disk (corners: boundary vertices with
//!   one cavity quad, or a convex CAD corner fully inside), its side counts
//!   are matched against the target patterns (Eq. 14, [`crate::combinatorics::patterns`]).
//!   A *minimal* cavity is the first that matches, a *maximal* one the last
//!   before [`MAX_MAXIMAL_QUADS`].
//! - **Strategy** (§10.4), repeated while a pass removes irregular vertices:
//!   Step 1 maximal grid (R1) cavities around unnecessary irregular
//!   vertices; Step 2 minimal triangle (T3) / pentagon (P5) cavities around
//!   each singular vertex of valence 3 / 5, one per singularity and pass;
//!   Step 3 = Step 1; Step 4 minimal cavities matching any rectangular
//!   pattern.
//! - **Acceptance**: no new edge doubles an existing one between two cavity
//!   boundary vertices; the irregular vertices of the cavity's closure
//!   (face-interior valence ≠ 4, curve vertices with ≠ 2 quads, corners off
//!   their ideal) strictly decrease; after placing the new vertices by a
//!   harmonic map in (u, v) and smoothing them with the face-interior
//!   vertices of the cavity boundary and of the quads around it (uv
//!   Laplacian, the Winslow / angle-based kernels, untangling), every quad
//!   around is valid, the worst SICN there is at least [`KEEP`] (Steps 1–3)
//!   or [`STEP4_KEEP`] (Step 4) of the old worst, and the average SICN there
//!   dropped by at most [`AVG_SLACK`]. Otherwise the patch is restored
//!   exactly, and that replacement is not tried again until another one is
//!   kept.
//! - Growth keeps the cavity a disk: a quad is added only when it meets the
//!   cavity along one path of its edges, so cavities never wrap around a
//!   hole of the face.
//!
//! Work is counted in units (quads added to cavities, vertices smoothed) and
//! capped per face; nothing depends on the clock or on hash-map order, so
//! the result is deterministic.

use std::collections::{HashMap, VecDeque};

use geometry::vec3::{self, Vec3};
use geometry::Face;

use crate::combinatorics::patterns::{library, match_pattern_where, refine, Pattern, PatternMatch};
use crate::core::patch::QuadPatch;
use crate::core::patch::{LocalNode, NodeRef};
use crate::core::quality::quad_quality;
use crate::field::singularities::{Singularity, SingularitySite};

/// Largest maximal cavity, in quads (the spec's §10.3 default is 2000).
/// 500 leaves every one of the 26 shared models unchanged at the default
/// size; on i01o_m1 at size factor 0.0625 the cavity stage takes 1.6 s
/// instead of 2.6 s for 370 irregular vertices left instead of 352 (of
/// 991), in 235k quads (BENCHMARKS.md, "Smaller maximal cavities").
pub const MAX_MAXIMAL_QUADS: usize = 500;
/// Largest minimal cavity, in quads (spec §10.3 default).
pub const MAX_MINIMAL_QUADS: usize = 500;
/// A singularity flags a vertex within this many local edge lengths (spec ρ = 2).
pub const MATCH_RADIUS: f64 = 2.0;
/// After the passes, a singularity still unmatched flags the nearest
/// remaining vertex of its valence within this many sizes, and the passes
/// run again (n12o_limit_cycle_genus0: the unstructured mesh leaves two of
/// each face's four valence-3 vertices 2.6–2.9 sizes away).
pub const LATE_MATCH_RADIUS: f64 = 3.0;
/// Steps 1–3 keep a replacement whose worst SICN is at least this share of the old worst.
pub const KEEP: f64 = 0.9;
/// Step 4 keeps a replacement whose worst SICN is at least this share of the old worst.
pub const STEP4_KEEP: f64 = 0.8;
/// Sweeps of the kernels on a replaced cavity. 8 rather than 30: on the 26
/// shared models the same replacements are kept except on i16o_s9, whose
/// irregular share falls (2.9 → 2.1 %) while its average SICN drops by
/// 0.012; at size factor 0.0625 the cavity stage of i01o_m1 takes a quarter
/// less time (BENCHMARKS.md).
const SMOOTHING_SWEEPS: usize = 8;
/// Work units charged per vertex of a smoothed cavity (the per-face cap,
/// [`default_work_cap`], was calibrated with this charge).
const SMOOTHING_WORK: usize = 30;
/// Quads below this SICN after the kernels get the untangler.
const UNTANGLE_BELOW: f64 = 0.2;
/// A replacement may lower the average SICN of the quads around it by this much at most.
pub const AVG_SLACK: f64 = 0.02;
/// Remeshable cavities kept per minimal growth (tried in order).
const MINIMAL_CANDIDATES: usize = 3;
/// Remeshable cavities tried per maximal growth (the largest ones).
const MAXIMAL_CANDIDATES: usize = 4;
/// [`Work::across`] not asked yet for this quad edge.
const NBR_UNKNOWN: u32 = u32::MAX - 1;
/// No quad across this edge (the face boundary).
const NBR_NONE: u32 = u32::MAX;

fn unknown_neighbours() -> [std::cell::Cell<u32>; 4] {
    std::array::from_fn(|_| std::cell::Cell::new(NBR_UNKNOWN))
}

/// Options of [`remesh_cavities`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CavityOptions {
    /// Steps 1–4 of §10.4 to run (Step 3 is Step 1 again).
    pub steps: [bool; 4],
    /// Passes of the four steps at most (a pass that removes no irregular vertex ends earlier).
    pub max_passes: usize,
    /// Work units allowed per face (`None`: [`default_work_cap`] of the face's quads).
    pub max_work: Option<u64>,
}

impl Default for CavityOptions {
    fn default() -> Self {
        CavityOptions {
            steps: [true; 4],
            max_passes: 8,
            max_work: None,
        }
    }
}

/// The default work cap of a face with `quads` quads. Of the bundled
/// models only `wing_surface` reaches it (one face of 12.5k quads, 22 %
/// irregular, no cross-field singularity), where it bounds the stage to a
/// few seconds; the next highest face uses 40 % of its cap.
pub fn default_work_cap(quads: usize) -> u64 {
    500_000 + 1_000 * quads as u64
}

/// What [`remesh_cavities`] did on one face.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CavityReport {
    /// Face-interior irregular vertices before.
    pub irregular_before: usize,
    /// Face-interior irregular vertices after.
    pub irregular_after: usize,
    /// Vertices flagged as singular (matched to cross-field singularities).
    pub singular: usize,
    /// Replacements kept by Steps 1, 2, 3 and 4.
    pub replaced: [usize; 4],
    /// Replacements undone (geometry or quality).
    pub rejected: usize,
    /// Work units spent.
    pub work: u64,
    /// True when the work cap stopped the face early.
    pub capped: bool,
}

impl CavityReport {
    /// Sums two reports (over faces).
    pub fn add(&self, o: &CavityReport) -> CavityReport {
        let mut r = *self;
        r.irregular_before += o.irregular_before;
        r.irregular_after += o.irregular_after;
        r.singular += o.singular;
        for k in 0..4 {
            r.replaced[k] += o.replaced[k];
        }
        r.rejected += o.rejected;
        r.work += o.work;
        r.capped |= o.capped;
        r
    }
}

/// What a vertex is for the cavity rules.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    /// Face interior (movable, ideal valence 4).
    Inner,
    /// On the face boundary, with its ideal number of quads (2 on a curve).
    Bound(u8),
    /// On a degenerate curve: cavities stay away.
    Pole,
}

/// The role of a cavity boundary vertex in the cavity polygon.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Role {
    Interior,
    Corner,
    Flat,
    Concave,
}

/// Which patterns a growth targets.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Target {
    /// The regular grid R1.
    Grid,
    /// Any rectangular pattern.
    Rect,
    /// A pattern with `n` sides and one irregular vertex (T3, P5).
    Star(usize),
}

impl Target {
    fn keeps(self, p: &Pattern) -> bool {
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
struct Candidate {
    quads: Vec<u32>,
    ring: Vec<u32>,
    corners: Vec<usize>,
    found: PatternMatch,
}

/// The face being edited with its adjacency and the growth scratch space.
struct Work<'a> {
    face: &'a Face,
    p: &'a mut QuadPatch,
    alive: Vec<bool>,
    /// Live quads at each vertex, sorted.
    at: Vec<Vec<u32>>,
    kind: Vec<Kind>,
    singular: Vec<bool>,
    units: u64,
    // growth scratch, valid for the current `stamp`
    stamp: u32,
    in_c: Vec<u32>,
    queued: Vec<u32>,
    barred: Vec<u32>,
    nin: Vec<(u32, u16)>,
    order: Vec<u32>,
    absorbed: bool,
    /// Growth keeps the cavity a disk (off while the seed's quads go in).
    disk_rule: bool,
    /// Replacements undone since the last kept one (cavity quads, pattern, subdivisions):
    /// not tried again.
    undone: std::collections::HashSet<Vec<u32>>,
    // boundary successor map of [`Work::boundary`], valid where `bmark == bclock`
    bnext: Vec<u32>,
    bmark: Vec<u32>,
    bclock: u32,
    // vertices counted by [`Work::check`], stamped with `bclock`
    vseen: Vec<u32>,
    /// Per quad and edge, the quad across ([`Work::across`]): [`NBR_UNKNOWN`]
    /// until asked, [`NBR_NONE`] on the face boundary.
    nbr: Vec<[std::cell::Cell<u32>; 4]>,
    /// The ball the current growth has reached: its centre (the seed), the
    /// largest distance from it to a vertex of a quad added, and the longest
    /// edge of those quads.
    reach: (Vec3, f64, f64),
    /// Balls of the replacements kept so far (every vertex of the new quads
    /// and of the quads smoothed around them), in order.
    kept_balls: Vec<(Vec3, f64)>,
    /// Seeds whose last attempt at a step found nothing to keep: the number
    /// of kept replacements then, and the ball the attempt depended on. A
    /// later pass tries them again only if a replacement since has reached
    /// that ball (otherwise they would fail the same way).
    failed: HashMap<(u32, usize), (usize, Vec3, f64)>,
}

impl<'a> Work<'a> {
    fn new(face: &'a Face, p: &'a mut QuadPatch) -> Self {
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

    fn deg(&self, v: u32) -> usize {
        self.at[v as usize].len()
    }

    /// Irregular: a live vertex off its ideal number of quads.
    fn irregular(&self, v: u32) -> bool {
        self.irregular_with(v, self.deg(v))
    }

    fn irregular_with(&self, v: u32, d: usize) -> bool {
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
    fn inner_irregular(&self) -> usize {
        (0..self.at.len() as u32)
            .filter(|&v| self.kind[v as usize] == Kind::Inner && self.irregular(v))
            .count()
    }

    fn all_irregular(&self) -> usize {
        (0..self.at.len() as u32)
            .filter(|&v| self.irregular(v))
            .count()
    }

    /// Flags singular vertices (spec §10.2): each singularity not `used`
    /// yet takes the nearest free vertex of its valence within `radius`
    /// sizes; returns how many were matched (and marks them `used`).
    fn match_singularities(
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

    // ---- growth -------------------------------------------------------

    fn in_c(&self, q: u32) -> bool {
        self.in_c[q as usize] == self.stamp
    }

    fn nin(&self, v: u32) -> usize {
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
    fn sheds_a_quad(&self, v: u32, ideal: u8) -> bool {
        ideal >= 3 && self.deg(v) > ideal as usize && self.deg(v) >= 4
    }

    fn role(&self, v: u32) -> Role {
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
    fn forget_neighbours(&self, quads: &[u32]) {
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
    fn forbidden(&self, q: u32, seed: Option<u32>) -> bool {
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
    fn grow(
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

    // ---- replacement --------------------------------------------------

    /// Replaces the cavity by its refined pattern if every acceptance rule
    /// holds (see the module documentation); otherwise leaves the patch as it was.
    fn replace(
        &mut self,
        cand: &Candidate,
        keep: f64,
        report: &mut CavityReport,
    ) -> Option<Vec<u32>> {
        let mut key: Vec<u32> = cand.quads.clone();
        key.sort_unstable();
        key.extend([
            u32::MAX,
            cand.found.pattern as u32,
            cand.found.shift as u32,
            cand.found.mirror as u32,
        ]);
        key.extend_from_slice(&cand.found.subdivisions);
        if self.undone.contains(&key) {
            return None;
        }
        let pattern = &library()[cand.found.pattern];
        let refined = refine(pattern, &cand.found.subdivisions);
        let (ring, corners) = (&cand.ring, &cand.corners);
        let (nb, m) = (ring.len(), corners.len());
        if refined.boundary.len() != nb {
            return None;
        }
        let f = &cand.found;
        let ring_of = |k: usize| {
            if f.mirror {
                (corners[(f.shift + 1) % m] + nb - k % nb) % nb
            } else {
                (corners[f.shift] + k) % nb
            }
        };
        let nv = refined.coords.len();
        let first_new = self.p.nodes.len() as u32;
        let mut local = vec![u32::MAX; nv];
        let mut fixed = vec![false; nv];
        for (k, &v) in refined.boundary.iter().enumerate() {
            local[v as usize] = ring[ring_of(k)];
            fixed[v as usize] = true;
        }
        let mut fresh = 0u32;
        for v in 0..nv {
            if !fixed[v] {
                local[v] = first_new + fresh;
                fresh += 1;
            }
        }
        let new_quads: Vec<[u32; 4]> = refined
            .quads
            .iter()
            .map(|q| {
                let l = q.map(|v| local[v as usize]);
                if f.mirror {
                    [l[0], l[3], l[2], l[1]]
                } else {
                    l
                }
            })
            .collect();
        // (a) no new edge between two boundary vertices already linked outside
        let pos_in_ring: HashMap<u32, usize> =
            ring.iter().enumerate().map(|(i, &v)| (v, i)).collect();
        let mut sorted_quads = cand.quads.clone();
        sorted_quads.sort_unstable();
        let in_cav = |q: u32| sorted_quads.binary_search(&q).is_ok();
        for q in &new_quads {
            for k in 0..4 {
                let (a, b) = (q[k], q[(k + 1) % 4]);
                if a == b {
                    return None;
                }
                if let (Some(&i), Some(&j)) = (pos_in_ring.get(&a), pos_in_ring.get(&b)) {
                    let d = (i + nb - j) % nb;
                    if d == 1 || d == nb - 1 {
                        continue;
                    }
                    let linked = self.at[a as usize].iter().any(|&r| {
                        !in_cav(r) && {
                            let o = self.p.quads[r as usize];
                            let i = o.iter().position(|&x| x == a).unwrap_or(0);
                            o[(i + 1) % 4] == b || o[(i + 3) % 4] == b
                        }
                    });
                    if linked {
                        return None;
                    }
                }
            }
        }
        // (d) fewer irregular vertices in the closure
        let mut closure: Vec<u32> = cand
            .quads
            .iter()
            .flat_map(|&q| self.p.quads[q as usize])
            .collect();
        closure.sort_unstable();
        closure.dedup();
        let before = closure.iter().filter(|&&v| self.irregular(v)).count();
        let mut new_count: HashMap<u32, usize> = HashMap::new();
        for q in &new_quads {
            for &v in q {
                *new_count.entry(v).or_insert(0) += 1;
            }
        }
        let mut after = 0;
        for &v in ring {
            let d = self.deg(v) - self.nin(v) + new_count.get(&v).copied().unwrap_or(0);
            if self.irregular_with(v, d) {
                after += 1;
            }
        }
        for v in first_new..first_new + fresh {
            if new_count.get(&v).copied().unwrap_or(0) != 4 {
                after += 1;
            }
        }
        if after >= before {
            return None;
        }
        // the quads whose quality the replacement can change, and their worst before
        // the smoothing region (spec §11.5): the face-interior vertices of the
        // cavity boundary and of the quads around it
        let mut movable_ring: Vec<u32> = Vec::new();
        for &v in ring.iter() {
            for &q in &self.at[v as usize] {
                if !in_cav(q) {
                    movable_ring.extend(
                        self.p.quads[q as usize]
                            .iter()
                            .copied()
                            .filter(|&x| self.kind[x as usize] == Kind::Inner),
                    );
                }
            }
        }
        movable_ring.sort_unstable();
        movable_ring.dedup();
        let mut region_old: Vec<u32> = cand.quads.clone();
        for &v in &movable_ring {
            region_old.extend_from_slice(&self.at[v as usize]);
        }
        region_old.sort_unstable();
        region_old.dedup();
        let old_worst = region_old
            .iter()
            .map(|&q| self.quality(q))
            .fold(f64::INFINITY, f64::min);
        let region_old_avg = region_old.iter().map(|&q| self.quality(q)).sum::<f64>()
            / region_old.len().max(1) as f64;
        // apply
        let saved_quads = self.p.quads.len();
        let saved_nodes = self.p.nodes.len();
        let saved_ring: Vec<([f64; 2], Vec3)> = movable_ring
            .iter()
            .map(|&v| (self.p.nodes[v as usize].uv, self.p.pos[v as usize]))
            .collect();
        let mut uv: Vec<[f64; 2]> = vec![[0.0, 0.0]; nv];
        let centre = {
            let s = ring.iter().fold([0.0, 0.0], |a, &v| {
                [
                    a[0] + self.p.nodes[v as usize].uv[0],
                    a[1] + self.p.nodes[v as usize].uv[1],
                ]
            });
            [s[0] / nb as f64, s[1] / nb as f64]
        };
        for v in 0..nv {
            uv[v] = if fixed[v] {
                self.p.nodes[local[v] as usize].uv
            } else {
                centre
            };
        }
        crate::direct::pattern_face::harmonic_uv(&refined.quads, &mut uv, &fixed);
        let mut ok = true;
        let mut new_nodes = vec![
            (
                LocalNode {
                    uv: centre,
                    node: NodeRef::Interior,
                    pole: None
                },
                [0.0; 3]
            );
            fresh as usize
        ];
        for v in 0..nv {
            if !fixed[v] {
                let x = self.face.surface.eval(uv[v]);
                ok &= x.iter().all(|c| c.is_finite()) && uv[v].iter().all(|c| c.is_finite());
                new_nodes[(local[v] - first_new) as usize] = (
                    LocalNode {
                        uv: uv[v],
                        node: NodeRef::Interior,
                        pole: None,
                    },
                    x,
                );
            }
        }
        if !ok {
            return None;
        }
        let origin = self
            .p
            .quad_tri
            .get(cand.quads[0] as usize)
            .copied()
            .unwrap_or(0);
        for &q in &cand.quads {
            self.alive[q as usize] = false;
            for &v in &self.p.quads[q as usize] {
                self.at[v as usize].retain(|&r| r != q);
            }
        }
        for (n, x) in new_nodes {
            self.p.nodes.push(n);
            self.p.pos.push(x);
            self.at.push(Vec::new());
            self.kind.push(Kind::Inner);
            self.singular.push(false);
            self.nin.push((0, 0));
        }
        for q in &new_quads {
            let id = self.p.quads.len() as u32;
            for &v in q {
                self.at[v as usize].push(id);
            }
            self.p.quads.push(*q);
            self.p.quad_tri.push(origin);
            self.alive.push(true);
            self.in_c.push(0);
            self.queued.push(0);
            self.barred.push(0);
            self.nbr.push(unknown_neighbours());
        }
        self.forget_neighbours(&cand.quads);
        // geometry: the new vertices and the boundary's face-interior ones
        let movable: Vec<u32> = (first_new..first_new + fresh)
            .chain(movable_ring.iter().copied())
            .collect();
        let region_new = self.smooth_region(&movable);
        let mut region_new = region_new;
        region_new.extend(saved_quads as u32..self.p.quads.len() as u32);
        region_new.sort_unstable();
        region_new.dedup();
        let new_worst = region_new
            .iter()
            .map(|&q| self.quality(q))
            .fold(f64::INFINITY, f64::min);
        let target = if old_worst > 0.0 {
            keep * old_worst.min(1.0)
        } else {
            0.0
        };
        let new_avg = region_new.iter().map(|&q| self.quality(q)).sum::<f64>()
            / region_new.len().max(1) as f64;
        let accept =
            new_worst > 0.0 && new_worst >= target && new_avg >= region_old_avg - AVG_SLACK;
        if tracing::enabled!(tracing::Level::DEBUG) {
            let avg = |qs: &[u32]| {
                qs.iter().map(|&q| self.quality(q)).sum::<f64>() / qs.len().max(1) as f64
            };
            tracing::debug!(
                "  cavity {} {:?} sides {:?}: {} → {} quads, irregular {before} → {after}, worst {old_worst:.3} → {new_worst:.3}, avg region {:.3} → {:.3}: {}",
                library()[cand.found.pattern].name,
                cand.found.subdivisions,
                cand.corners.iter().enumerate().map(|(i, &c)| (cand.corners[(i + 1) % m] + nb - c) % nb).collect::<Vec<_>>(),
                cand.quads.len(),
                new_quads.len(),
                region_old_avg,
                avg(&region_new),
                if accept { "kept" } else { "undone" }
            );
        }
        if accept {
            self.undone.clear();
            let centre = self.p.pos[ring[0] as usize];
            let radius = region_new
                .iter()
                .flat_map(|&q| self.p.quads[q as usize])
                .map(|v| vec3::dist(self.p.pos[v as usize], centre))
                .fold(0.0, f64::max);
            self.kept_balls.push((centre, radius));
            return Some((first_new..first_new + fresh).collect());
        }
        // undo, exactly
        report.rejected += 1;
        self.undone.insert(key);
        for q in saved_quads..self.p.quads.len() {
            for &v in &self.p.quads[q] {
                if (v as usize) < saved_nodes {
                    self.at[v as usize].retain(|&r| (r as usize) < saved_quads);
                }
            }
        }
        self.p.quads.truncate(saved_quads);
        self.p.quad_tri.truncate(saved_quads);
        self.alive.truncate(saved_quads);
        self.in_c.truncate(saved_quads);
        self.queued.truncate(saved_quads);
        self.barred.truncate(saved_quads);
        for &q in &cand.quads {
            self.alive[q as usize] = true;
            for &v in &self.p.quads[q as usize] {
                let l = &mut self.at[v as usize];
                l.push(q);
                l.sort_unstable();
            }
        }
        self.nbr.truncate(saved_quads);
        self.forget_neighbours(&cand.quads);
        self.p.nodes.truncate(saved_nodes);
        self.p.pos.truncate(saved_nodes);
        self.at.truncate(saved_nodes);
        self.kind.truncate(saved_nodes);
        self.singular.truncate(saved_nodes);
        self.nin.truncate(saved_nodes);
        for (&v, &(uv, x)) in movable_ring.iter().zip(&saved_ring) {
            self.p.nodes[v as usize].uv = uv;
            self.p.pos[v as usize] = x;
        }
        None
    }

    fn quality(&self, q: u32) -> f64 {
        quad_quality(
            self.face,
            &self.p.nodes,
            &self.p.pos,
            &self.p.quads[q as usize],
        )
    }

    /// Smooths the vertices `movable` on a copy of the quads around them
    /// (the other vertices fixed) and writes their new positions back;
    /// returns those quads.
    fn smooth_region(&mut self, movable: &[u32]) -> Vec<u32> {
        let mut quads: Vec<u32> = movable
            .iter()
            .flat_map(|&v| self.at[v as usize].iter().copied())
            .collect();
        quads.sort_unstable();
        quads.dedup();
        let mut map: HashMap<u32, u32> = HashMap::new();
        let mut sub = QuadPatch::default();
        let mut is_movable = vec![false; self.p.nodes.len()];
        for &v in movable {
            is_movable[v as usize] = true;
        }
        let mut back: Vec<u32> = Vec::new();
        for &q in &quads {
            let quad = self.p.quads[q as usize];
            let mut l = [0u32; 4];
            for k in 0..4 {
                let v = quad[k];
                l[k] = *map.entry(v).or_insert_with(|| {
                    let mut n = self.p.nodes[v as usize];
                    if !is_movable[v as usize] {
                        // fixed in the copy: anything but a face-interior node
                        n.node = NodeRef::Corner(geometry::CornerId(u32::MAX));
                    }
                    sub.nodes.push(n);
                    sub.pos.push(self.p.pos[v as usize]);
                    back.push(v);
                    (sub.nodes.len() - 1) as u32
                });
            }
            sub.quads.push(l);
            sub.quad_tri.push(q);
        }
        crate::smoothing::smooth(self.face, &mut sub, 8);
        crate::smoothing::optimize(
            self.face,
            &mut sub,
            &crate::smoothing::OptimizeOptions {
                max_sweeps: SMOOTHING_SWEEPS,
                ..Default::default()
            },
        );
        let worst = sub
            .quads
            .iter()
            .map(|q| quad_quality(self.face, &sub.nodes, &sub.pos, q))
            .fold(f64::INFINITY, f64::min);
        if worst < UNTANGLE_BELOW {
            crate::smoothing::untangle(self.face, &mut sub, UNTANGLE_BELOW, 4, 5000, &[]);
        }
        self.units += (movable.len() * SMOOTHING_WORK) as u64 + quads.len() as u64;
        for (i, &v) in back.iter().enumerate() {
            if is_movable[v as usize] {
                self.p.nodes[v as usize].uv = sub.nodes[i].uv;
                self.p.pos[v as usize] = sub.pos[i];
            }
        }
        quads
    }

    /// Step 1 / 3 / 4: cavities around the unnecessary irregular vertices.
    fn rect_step(
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
    fn star_step(&mut self, cap: u64, report: &mut CavityReport) {
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
    fn mark(&mut self, quads: &[u32]) {
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

/// Remeshes cavities of one face's quads (see the module documentation).
/// `singularities` are the face's cross-field singularities (3D positions).
/// Quads stay counter-clockwise; curve and corner nodes never move; replaced
/// quads are dropped and new nodes appended (old interior nodes of a
/// replaced cavity stay in `p.nodes`, unused).
pub fn remesh_cavities(
    face: &Face,
    p: &mut QuadPatch,
    singularities: &[Singularity],
    opts: &CavityOptions,
) -> CavityReport {
    let mut report = CavityReport::default();
    if p.quads.is_empty()
        || p.pos.len() != p.nodes.len()
        || p.quad_tri.len() != p.quads.len()
        || p.quads
            .iter()
            .flatten()
            .any(|&v| v as usize >= p.nodes.len())
    {
        return report;
    }
    let cap = opts
        .max_work
        .unwrap_or_else(|| default_work_cap(p.quads.len()));
    let mut w = Work::new(face, p);
    let mut used = vec![false; singularities.len()];
    report.singular = w.match_singularities(singularities, MATCH_RADIUS, &mut used);
    report.irregular_before = w.inner_irregular();
    let maximal_grid = |w: &mut Work, step: usize, report: &mut CavityReport| {
        w.rect_step(Target::Grid, false, KEEP, step, cap, report)
    };
    let passes = |w: &mut Work, report: &mut CavityReport, max_passes: usize| {
        for _ in 0..max_passes {
            let before = w.all_irregular();
            if opts.steps[0] {
                maximal_grid(w, 0, report);
            }
            if opts.steps[1] {
                w.star_step(cap, report);
            }
            if opts.steps[2] {
                maximal_grid(w, 2, report);
            }
            if opts.steps[3] {
                w.rect_step(Target::Rect, true, STEP4_KEEP, 3, cap, report);
            }
            if w.all_irregular() >= before || report.capped {
                break;
            }
        }
    };
    passes(&mut w, &mut report, opts.max_passes);
    // a singularity whose vertex the unstructured mesh left a little
    // farther away: matched now, among the vertices the passes could not
    // remove, and the passes run again around it
    if !report.capped {
        let late = w.match_singularities(singularities, LATE_MATCH_RADIUS, &mut used);
        if late > 0 {
            // the seeds' roles changed: every seed may be tried again
            w.failed.clear();
            report.singular += late;
            passes(&mut w, &mut report, opts.max_passes);
        }
    }
    report.irregular_after = w.inner_irregular();
    report.work = w.units;
    let alive = std::mem::take(&mut w.alive);
    drop(w);
    crate::topology::defects::drop_dead_quads(p, &alive);
    if report.replaced.iter().sum::<usize>() > 0 {
        crate::smoothing::optimize(face, p, &crate::smoothing::OptimizeOptions::default());
    }
    report
}

#[cfg(test)]
mod tests;
