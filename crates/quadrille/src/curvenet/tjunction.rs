//! The network stage's T-junctions (spec §7.2–7.3): after every cycle is
//! paired on its own, the segment endpoints two cycles put on a curve they
//! share are made to agree.
//!
//! - A *primary* vertex is a segment endpoint of the pairing (§1–§4). A
//!   primary vertex of one side with no vertex of the other side at the same
//!   place is a T-junction. It is merged with the other side's nearest vertex
//!   within 5δ (the vertex that is not an input corner or junction moves),
//!   else the other side's segment is split there and so is its mate, at the
//!   same arc-length fraction run backwards: the poly-chord becomes two
//!   parallel chords.
//! - The mate's split point is a *secondary* vertex: merged with the other
//!   side's vertex when one lies within 5δ, else left inside its primary
//!   segment, where [`snap_secondary_vertices`] moves it onto a sample of the
//!   primary segment's one sampling once the intervals are known.
//!
//! Positions along a part's closed boundary are arc lengths from its first
//! point ("unwrapped": segment starts ascend from `q[0]` to below
//! `q[0] + total`); positions along a network curve are arc lengths from
//! its first point.

use geometry::vec3::{self, Vec3};

use super::geometry::Polyline;
use super::{CurveNetwork, PairedCycle};

/// One part of a meshed cycle (the whole cycle, a part after a cut, or its
/// midpoint layout) as the network stage sees it.
#[derive(Clone, Debug)]
pub struct NetLeaf {
    /// The cycle the part belongs to.
    pub cycle: usize,
    /// The part's pairing, split and moved by this stage.
    pub paired: PairedCycle,
    /// Per segment start: a primary vertex (see the module docs).
    pub primary: Vec<bool>,
    /// True once this stage changed the pairing.
    pub changed: bool,
}

impl NetLeaf {
    /// A part as paired, every segment start primary.
    pub fn new(cycle: usize, paired: PairedCycle) -> NetLeaf {
        let primary = vec![true; paired.starts.len()];
        NetLeaf {
            cycle,
            paired,
            primary,
            changed: false,
        }
    }
}

/// Arc lengths along a part's closed boundary.
struct Arcs {
    cumulative: Vec<f64>,
    total: f64,
}

impl Arcs {
    fn of(points: &[Vec3]) -> Arcs {
        let mut cumulative = Vec::with_capacity(points.len());
        let mut acc = 0.0;
        for k in 0..points.len() {
            if k > 0 {
                acc += vec3::dist(points[k - 1], points[k]);
            }
            cumulative.push(acc);
        }
        let total = acc + points.last().map_or(0.0, |&l| vec3::dist(l, points[0]));
        Arcs { cumulative, total }
    }

    /// The boundary point at position `u` (any real: taken modulo the total).
    fn point_at(&self, points: &[Vec3], u: f64) -> Vec3 {
        let n = points.len();
        if self.total <= 0.0 {
            return points[0];
        }
        let u = u - self.total * (u / self.total).floor();
        let k = self.cumulative.partition_point(|&c| c <= u).clamp(1, n) - 1;
        let end = if k + 1 < n {
            self.cumulative[k + 1]
        } else {
            self.total
        };
        let len = end - self.cumulative[k];
        let f = if len > 0.0 {
            ((u - self.cumulative[k]) / len).clamp(0.0, 1.0)
        } else {
            0.0
        };
        vec3::add(
            points[k],
            vec3::scale(vec3::sub(points[(k + 1) % n], points[k]), f),
        )
    }
}

/// The segment starts of a part as boundary positions (ascending).
fn start_positions(paired: &PairedCycle, arcs: &Arcs) -> Vec<f64> {
    paired.starts.iter().map(|&s| arcs.cumulative[s]).collect()
}

/// The part's pairing with its segment starts at positions `q` (ascending,
/// within one turn from `q[0]`): the boundary rebuilt from `q[0]` with a
/// point inserted where a start falls between two points (a start on a
/// point keeps the point). Pairs, costs and flags are the caller's.
fn rebuild(paired: &PairedCycle, arcs: &Arcs, q: &[f64]) -> (Vec<Vec3>, Vec<usize>) {
    let np = paired.points.len();
    let eps = 1e-12 * arcs.total.max(f64::MIN_POSITIVE);
    let (q0, end) = (q[0], q[0] + arcs.total);
    let turn = (q0 / arcs.total.max(f64::MIN_POSITIVE)).floor();
    let mut originals: Vec<(f64, usize)> = (0..2 * np)
        .map(|i| {
            (
                arcs.cumulative[i % np] + arcs.total * (turn + (i / np) as f64),
                i % np,
            )
        })
        .filter(|&(u, _)| u >= q0 - eps && u < end - eps)
        .collect();
    originals.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut points = Vec::with_capacity(originals.len() + q.len());
    let mut starts = Vec::with_capacity(q.len());
    let mut next = 0;
    for &u in q {
        while next < originals.len() && originals[next].0 < u - eps {
            points.push(paired.points[originals[next].1]);
            next += 1;
        }
        starts.push(points.len());
        if next < originals.len() && (originals[next].0 - u).abs() <= eps {
            points.push(paired.points[originals[next].1]);
            next += 1;
        } else {
            points.push(arcs.point_at(&paired.points, u));
        }
    }
    points.extend(originals[next..].iter().map(|&(_, i)| paired.points[i]));
    (points, starts)
}

/// True when segment start `k` of `leaf` ends or starts a cut or hole
/// connector: the other part of the cycle holds the same end, so moving it
/// here alone would open the seam between the parts.
fn pinned(leaf: &NetLeaf, k: usize) -> bool {
    let u = &leaf.paired.unsplittable;
    let m = u.len();
    m > 0 && (u[k % m] || u[(k + m - 1) % m])
}

/// Moves segment start `k` of `leaf` by `shift` along its boundary (it
/// stays strictly between its neighbours, else nothing happens; an end of
/// a cut or connector never moves, [`pinned`]). Returns whether it moved.
fn move_start(leaf: &mut NetLeaf, k: usize, shift: f64) -> bool {
    if pinned(leaf, k) {
        return false;
    }
    let arcs = Arcs::of(&leaf.paired.points);
    let mut q = start_positions(&leaf.paired, &arcs);
    let m = q.len();
    let new = q[k] + shift;
    let prev = if k > 0 {
        q[k - 1]
    } else {
        q[m - 1] - arcs.total
    };
    let next = if k + 1 < m {
        q[k + 1]
    } else {
        q[0] + arcs.total
    };
    if !(new > prev && new < next) {
        return false;
    }
    q[k] = new;
    let (points, starts) = rebuild(&leaf.paired, &arcs, &q);
    leaf.paired.points = points;
    leaf.paired.starts = starts;
    leaf.changed = true;
    true
}

/// Splits segment `k` of `leaf` at arc-length fraction `f` and its mate at
/// `1 − f` (the pair's orientation is reversed): the chord becomes two
/// parallel chords. The new start on `k` is primary, the mate's secondary.
/// Refused (false) when the mate is the segment itself, a cut or connector,
/// or a piece would be shorter than 1e-9 of the boundary.
fn split_chord(leaf: &mut NetLeaf, k: usize, f: f64) -> bool {
    let p = &leaf.paired;
    let m = p.starts.len();
    let Some(pair) = p.pairs.iter().position(|&(a, b)| a == k || b == k) else {
        return false;
    };
    let (a, b) = p.pairs[pair];
    let j = if a == k { b } else { a };
    if j == k || p.unsplittable[j] || p.unsplittable[k] {
        return false;
    }
    let arcs = Arcs::of(&p.points);
    let q = start_positions(p, &arcs);
    let end = |s: usize| {
        if s + 1 < m {
            q[s + 1]
        } else {
            q[0] + arcs.total
        }
    };
    let (lk, lj) = (end(k) - q[k], end(j) - q[j]);
    let least = 1e-9 * arcs.total;
    if f * lk < least || (1.0 - f) * lk < least || f * lj < least || (1.0 - f) * lj < least {
        return false;
    }
    let (pk, pj) = (q[k] + f * lk, q[j] + (1.0 - f) * lj);
    let mut new_q = Vec::with_capacity(m + 2);
    let mut primary = Vec::with_capacity(m + 2);
    let mut unsplittable = Vec::with_capacity(m + 2);
    let mut first = vec![0usize; m];
    for s in 0..m {
        first[s] = new_q.len();
        new_q.push(q[s]);
        primary.push(leaf.primary[s]);
        unsplittable.push(p.unsplittable[s]);
        if s == k || s == j {
            new_q.push(if s == k { pk } else { pj });
            primary.push(s == k);
            unsplittable.push(false);
        }
    }
    let ordered = |x: usize, y: usize| (x.min(y), x.max(y));
    let mut pairs = Vec::with_capacity(p.pairs.len() + 1);
    let mut costs = Vec::with_capacity(p.pairs.len() + 1);
    for (i, &(x, y)) in p.pairs.iter().enumerate() {
        let cost = p.costs.get(i).copied().unwrap_or(0.0);
        if i == pair {
            pairs.push(ordered(first[k], first[j] + 1));
            pairs.push(ordered(first[k] + 1, first[j]));
            costs.extend([cost, cost]);
        } else {
            pairs.push(ordered(first[x], first[y]));
            costs.push(cost);
        }
    }
    let (points, starts) = rebuild(p, &arcs, &new_q);
    leaf.paired = PairedCycle {
        points,
        starts,
        pairs,
        costs,
        unsplittable,
        diameter: p.diameter,
    };
    leaf.primary = primary;
    leaf.changed = true;
    true
}

/// The nearest point of a polyline to `p`: (distance, arc length there).
fn project(curve: &Polyline, p: Vec3) -> (f64, f64) {
    let mut best = (f64::INFINITY, 0.0);
    for k in 1..curve.points.len() {
        let (a, b) = (curve.points[k - 1], curve.points[k]);
        let (d, t) = vec3::segment_closest(p, a, b);
        if d < best.0 {
            best = (
                d,
                curve.cumulative[k - 1] + t * (curve.cumulative[k] - curve.cumulative[k - 1]),
            );
        }
    }
    best
}

/// A segment of a part lying along a shared curve.
#[derive(Clone, Copy, Debug)]
pub struct SideSegment {
    /// Index of the part in the leaves.
    pub leaf: usize,
    /// The segment's index in the part.
    pub segment: usize,
    /// Curve positions of its start and its end.
    pub from: f64,
    /// See `from`.
    pub to: f64,
}

impl SideSegment {
    fn lo(&self) -> f64 {
        self.from.min(self.to)
    }
    fn hi(&self) -> f64 {
        self.from.max(self.to)
    }
}

/// A network curve two cycles share, and each side's segments along it.
#[derive(Clone, Debug)]
pub struct SharedCurve {
    /// The curve's index in the network.
    pub curve: usize,
    /// Its length.
    pub length: f64,
    /// The two cycles.
    pub cycles: [usize; 2],
    /// Per side, its segments along the curve, by curve position.
    pub sides: [Vec<SideSegment>; 2],
}

impl SharedCurve {
    /// Curve positions of one side's vertices (segment ends), ascending.
    pub fn vertices(&self, side: usize) -> Vec<f64> {
        let mut v: Vec<f64> = self.sides[side]
            .iter()
            .flat_map(|s| [s.from, s.to])
            .collect();
        v.sort_by(f64::total_cmp);
        v.dedup_by(|a, b| (*a - *b).abs() <= 1e-12 * self.length);
        v
    }

    /// The primary segments: consecutive positions where both sides have a
    /// vertex (within `tol`), the curve's ends included, except the
    /// positions in `joined` (common vertices made secondary on both sides
    /// by [`demote_common_vertex`]: the segments either side are one).
    pub fn primary_segments(&self, tol: f64, joined: &[f64]) -> Vec<(f64, f64)> {
        let other = self.vertices(1);
        let common: Vec<f64> = self
            .vertices(0)
            .into_iter()
            .filter(|&u| other.iter().any(|&w| (u - w).abs() <= tol))
            .filter(|&u| !joined.iter().any(|&j| (u - j).abs() <= tol))
            .collect();
        common.windows(2).map(|w| (w[0], w[1])).collect()
    }

    /// One side's segments inside `[a, b]`, by curve position.
    pub fn inside(&self, side: usize, a: f64, b: f64, tol: f64) -> Vec<SideSegment> {
        let mut out: Vec<SideSegment> = self.sides[side]
            .iter()
            .filter(|s| s.lo() >= a - tol && s.hi() <= b + tol)
            .copied()
            .collect();
        out.sort_by(|x, y| x.lo().total_cmp(&y.lo()));
        out
    }
}

/// The shared curves of the network whose two cycles are both meshed and
/// whose every point both sides cover with segments; the others are
/// counted as the second value (left as they are).
pub fn shared_curves(
    net: &CurveNetwork,
    leaves: &[NetLeaf],
    tol: f64,
) -> (Vec<SharedCurve>, usize) {
    let mut out = Vec::new();
    let mut skipped = 0;
    for c in 0..net.curves().len() {
        match shared_curve(net, leaves, c, tol) {
            Some(Ok(sc)) => out.push(sc),
            Some(Err(())) => skipped += 1,
            None => {}
        }
    }
    (out, skipped)
}

/// Curve `c` as a [`SharedCurve`]: `None` when two meshed cycles do not
/// share it, `Err` when a side does not cover it with segments.
fn shared_curve(
    net: &CurveNetwork,
    leaves: &[NetLeaf],
    c: usize,
    tol: f64,
) -> Option<Result<SharedCurve, ()>> {
    let uses = net.curve_cycles(c);
    if uses.len() != 2 || uses[0] == uses[1] {
        return None;
    }
    if !uses
        .iter()
        .all(|&cycle| leaves.iter().any(|l| l.cycle == cycle))
    {
        return None;
    }
    let poly = Polyline::new(net.curves()[c].points.clone());
    let length = poly.length();
    let mut shared = SharedCurve {
        curve: c,
        length,
        cycles: [uses[0], uses[1]],
        sides: [vec![], vec![]],
    };
    for (side, &cycle) in uses.iter().enumerate() {
        for (li, leaf) in leaves.iter().enumerate().filter(|(_, l)| l.cycle == cycle) {
            shared.sides[side].extend(segments_along(leaf, li, &poly, tol));
        }
    }
    let covered = |side: usize| {
        let sum: f64 = shared.sides[side].iter().map(|s| s.hi() - s.lo()).sum();
        (sum - length).abs() <= 1e-6 * length + 2.0 * tol
    };
    Some(if covered(0) && covered(1) {
        Ok(shared)
    } else {
        Err(())
    })
}

/// The segments of `leaf` lying along `curve` (ends and middle within `tol`,
/// as long as the curve between them), cuts and connectors excluded.
fn segments_along(leaf: &NetLeaf, li: usize, curve: &Polyline, tol: f64) -> Vec<SideSegment> {
    let p = &leaf.paired;
    let arcs = Arcs::of(&p.points);
    let q = start_positions(p, &arcs);
    let m = q.len();
    let mut out = Vec::new();
    for s in 0..m {
        if p.unsplittable[s] {
            continue;
        }
        let end = if s + 1 < m {
            q[s + 1]
        } else {
            q[0] + arcs.total
        };
        let (d0, from) = project(curve, arcs.point_at(&p.points, q[s]));
        let (d1, to) = project(curve, arcs.point_at(&p.points, end));
        let (dm, _) = project(curve, arcs.point_at(&p.points, 0.5 * (q[s] + end)));
        let along = ((to - from).abs() - (end - q[s])).abs() <= 1e-6 * (end - q[s]) + 2.0 * tol;
        if d0 <= tol && d1 <= tol && dm <= tol && along && (to - from).abs() > tol {
            out.push(SideSegment {
                leaf: li,
                segment: s,
                from,
                to,
            });
        }
    }
    out
}

/// What [`resolve_t_junctions`] did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TJunctionReport {
    /// Shared curves resolved.
    pub shared_curves: usize,
    /// Shared curves left alone (a side does not cover the curve with segments).
    pub skipped_curves: usize,
    /// Vertices moved onto the other side's vertex (within 5δ).
    pub merged: usize,
    /// Chords split in two (primary T-junctions).
    pub split: usize,
    /// Primary T-junctions that could not be removed (the mate is a cut or
    /// connector, or the split would be degenerate).
    pub unresolved: usize,
    /// Secondary vertices left inside their primary segments.
    pub secondary: usize,
}

/// Passes over the shared curves (each pass can add secondary vertices on
/// other curves); the work is capped by this many passes.
const MAX_PASSES: usize = 8;

/// Resolves the T-junctions on every shared curve (module docs); `delta`
/// is the network's δ, `tol` the weld tolerance, `fixed(p)` tells the input
/// corners and junctions, which never move.
pub fn resolve_t_junctions(
    net: &CurveNetwork,
    leaves: &mut [NetLeaf],
    delta: f64,
    tol: f64,
    fixed: &dyn Fn(Vec3) -> bool,
) -> TJunctionReport {
    let mut report = TJunctionReport::default();
    let radius = 5.0 * delta;
    let mut refused: std::collections::BTreeSet<(usize, u64)> = Default::default();
    for _ in 0..MAX_PASSES {
        let mut changed = false;
        let (curves, _) = shared_curves(net, leaves, tol);
        for sc in &curves {
            // one change at a time: the sides are measured again after it
            while let Some(done) =
                resolve_one(sc.curve, net, leaves, radius, tol, fixed, &mut refused)
            {
                match done {
                    Change::Merged => report.merged += 1,
                    Change::Split => report.split += 1,
                }
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    let (curves, skipped) = shared_curves(net, leaves, tol);
    report.shared_curves = curves.len();
    report.skipped_curves = skipped;
    for sc in &curves {
        for side in 0..2 {
            let other = sc.vertices(1 - side);
            for v in sc.vertices(side) {
                if other.iter().any(|&w| (v - w).abs() <= tol) {
                    continue;
                }
                match vertex_start(sc, side, v, leaves, tol) {
                    Some((li, k, _)) if !leaves[li].primary[k] => report.secondary += 1,
                    _ => report.unresolved += 1,
                }
            }
        }
    }
    report
}

enum Change {
    Merged,
    Split,
}

/// The part, segment start and orientation (+1: the part runs up the curve)
/// of one side's vertex at curve position `v`.
fn vertex_start(
    sc: &SharedCurve,
    side: usize,
    v: f64,
    leaves: &[NetLeaf],
    tol: f64,
) -> Option<(usize, usize, f64)> {
    for s in &sc.sides[side] {
        let sign = if s.to > s.from { 1.0 } else { -1.0 };
        if (s.from - v).abs() <= tol {
            return Some((s.leaf, s.segment, sign));
        }
        if (s.to - v).abs() <= tol {
            let m = leaves[s.leaf].paired.starts.len();
            return Some((s.leaf, (s.segment + 1) % m, sign));
        }
    }
    None
}

/// Finds one unmatched vertex on `curve` and merges or splits it.
#[allow(clippy::too_many_arguments)]
fn resolve_one(
    curve: usize,
    net: &CurveNetwork,
    leaves: &mut [NetLeaf],
    radius: f64,
    tol: f64,
    fixed: &dyn Fn(Vec3) -> bool,
    refused: &mut std::collections::BTreeSet<(usize, u64)>,
) -> Option<Change> {
    let sc = shared_curve(net, leaves, curve, tol)?.ok()?;
    let interior = |u: f64| u > tol && u < sc.length - tol;
    for side in 0..2 {
        let mine = sc.vertices(side);
        let other = sc.vertices(1 - side);
        for &v in mine.iter().filter(|&&v| interior(v)) {
            if other.iter().any(|&w| (v - w).abs() <= tol) {
                continue;
            }
            let tag = (curve, (v / sc.length * 1e9).round() as u64);
            if refused.contains(&tag) {
                continue;
            }
            let Some((li, k, sign)) = vertex_start(&sc, side, v, leaves, tol) else {
                continue;
            };
            let here = point_of(&leaves[li], k);
            let v_primary = leaves[li].primary[k];
            // merge: the nearest other-side vertex within 5δ
            let near = other
                .iter()
                .copied()
                .filter(|&w| (v - w).abs() <= radius && !mine.iter().any(|&u| (u - w).abs() <= tol))
                .min_by(|a, b| (a - v).abs().total_cmp(&(b - v).abs()));
            if let Some(w) = near {
                if let Some((lw, kw, sw)) = vertex_start(&sc, 1 - side, w, leaves, tol) {
                    let w_point = point_of(&leaves[lw], kw);
                    // the moving vertex: a secondary one, else one that is
                    // no corner and no end of a cut or connector
                    let stays_mine = fixed(here) || pinned(&leaves[li], k);
                    let stays_w = fixed(w_point) || pinned(&leaves[lw], kw);
                    let move_mine = !v_primary || (stays_w && !stays_mine);
                    let moved = if move_mine {
                        !stays_mine && move_start(&mut leaves[li], k, sign * (w - v))
                    } else {
                        !stays_w && move_start(&mut leaves[lw], kw, sw * (v - w))
                    };
                    if moved {
                        leaves[if move_mine { li } else { lw }].primary
                            [if move_mine { k } else { kw }] = true;
                        return Some(Change::Merged);
                    }
                }
            }
            if !v_primary {
                // a secondary vertex stays: the intervals place it
                refused.insert(tag);
                continue;
            }
            // split the other side's segment that holds v, and its mate
            let holder = sc.sides[1 - side]
                .iter()
                .find(|s| s.lo() < v - tol && s.hi() > v + tol)
                .copied();
            if let Some(s) = holder {
                let f = (v - s.from).abs() / (s.to - s.from).abs();
                if split_chord(&mut leaves[s.leaf], s.segment, f) {
                    return Some(Change::Split);
                }
            }
            refused.insert(tag);
        }
    }
    None
}

/// Makes the vertex both sides of `sc` have at curve position `u` (inside
/// the curve) secondary on both sides: the primary segments either side of
/// it join into one, whose one equal sum replaces their two (a relaxation:
/// the program's least mismatch can only fall), and
/// [`snap_secondary_vertices`] then places each side's vertex by its own
/// counts on the joined segment's one sampling. Refused (false, nothing
/// changed) when a side has no single vertex there, or it is an input
/// corner or junction (`fixed`) or an end of a cut or connector.
pub fn demote_common_vertex(
    sc: &SharedCurve,
    u: f64,
    leaves: &mut [NetLeaf],
    tol: f64,
    fixed: &dyn Fn(Vec3) -> bool,
) -> bool {
    if !(u > tol && u < sc.length - tol) {
        return false;
    }
    let mut found = Vec::with_capacity(2);
    for side in 0..2 {
        let mut here: Vec<(usize, usize)> = Vec::new();
        for s in &sc.sides[side] {
            let at = if (s.from - u).abs() <= tol {
                Some(s.segment)
            } else if (s.to - u).abs() <= tol {
                Some((s.segment + 1) % leaves[s.leaf].paired.starts.len())
            } else {
                None
            };
            if let Some(k) = at {
                if !here.contains(&(s.leaf, k)) {
                    here.push((s.leaf, k));
                }
            }
        }
        let [(li, k)] = here[..] else {
            return false;
        };
        if pinned(&leaves[li], k) || fixed(point_of(&leaves[li], k)) {
            return false;
        }
        found.push((li, k));
    }
    for (li, k) in found {
        leaves[li].primary[k] = false;
    }
    true
}

/// The position of segment start `k` of a part.
fn point_of(leaf: &NetLeaf, k: usize) -> Vec3 {
    leaf.paired.points[leaf.paired.starts[k]]
}

/// Moves every secondary vertex on a shared curve onto the sample its
/// interval counts give it: in a primary segment `[a, b]` of `N` intervals,
/// the vertex after `m` intervals goes to `a + m/N·(b − a)`, so both sides
/// sample the primary segment at the same points. `intervals(leaf, s)` is the
/// interval count of segment `s` of part `leaf`; `joined` the (curve,
/// position) of common vertices made secondary ([`demote_common_vertex`]).
/// Returns the vertices moved.
pub fn snap_secondary_vertices(
    net: &CurveNetwork,
    leaves: &mut [NetLeaf],
    tol: f64,
    intervals: &dyn Fn(usize, usize) -> usize,
    joined: &[(usize, f64)],
) -> usize {
    let mut moved = 0;
    let (curves, _) = shared_curves(net, leaves, tol);
    for sc in &curves {
        let here: Vec<f64> = joined.iter().filter(|j| j.0 == sc.curve).map(|j| j.1).collect();
        for (a, b) in sc.primary_segments(tol, &here) {
            for side in 0..2 {
                let segs = sc.inside(side, a, b, tol);
                let total: usize = segs.iter().map(|s| intervals(s.leaf, s.segment)).sum();
                if segs.len() < 2 || total == 0 {
                    continue;
                }
                // Every secondary vertex's target first; then moves in
                // passes until none succeeds: a vertex whose target lies
                // past its neighbour waits until that neighbour has moved
                // (a run of them sliding one way moves front first).
                let mut count = 0;
                let mut pending: Vec<(f64, f64)> = Vec::with_capacity(segs.len() - 1);
                for pair in segs.windows(2) {
                    count += intervals(pair[0].leaf, pair[0].segment);
                    pending.push((pair[0].hi(), a + (b - a) * count as f64 / total as f64));
                }
                loop {
                    let before = pending.len();
                    pending.retain(|&(v, target)| {
                        let Some((li, k, sign)) = vertex_start(sc, side, v, leaves, tol) else {
                            return false;
                        };
                        if leaves[li].primary[k] || (target - v).abs() <= 1e-12 * sc.length {
                            return false;
                        }
                        if move_start(&mut leaves[li], k, sign * (target - v)) {
                            moved += 1;
                            return false;
                        }
                        true
                    });
                    if pending.is_empty() || pending.len() == before {
                        break;
                    }
                }
            }
        }
    }
    moved
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square_leaf() -> NetLeaf {
        // a 2 × 1 rectangle, 4 segments, pairs (0, 2), (1, 3)
        let paired = PairedCycle {
            points: vec![
                [0.0, 0.0, 0.0],
                [2.0, 0.0, 0.0],
                [2.0, 1.0, 0.0],
                [0.0, 1.0, 0.0],
            ],
            starts: vec![0, 1, 2, 3],
            pairs: vec![(0, 2), (1, 3)],
            costs: vec![0.1, 0.2],
            unsplittable: vec![false; 4],
            diameter: 5f64.sqrt(),
        };
        NetLeaf::new(0, paired)
    }

    /// Splitting the bottom at a quarter splits the top at three quarters
    /// (run backwards), the point across: two parallel chords (0, 4) and (1, 3).
    #[test]
    fn a_split_chord_becomes_two_parallel_chords() {
        let mut leaf = square_leaf();
        assert!(split_chord(&mut leaf, 0, 0.25));
        let p = &leaf.paired;
        assert_eq!(p.starts.len(), 6);
        let at = |k: usize| p.points[p.starts[k]];
        assert_eq!(at(1), [0.5, 0.0, 0.0]);
        assert_eq!(at(4), [0.5, 1.0, 0.0]);
        assert_eq!(p.pairs, vec![(0, 4), (1, 3), (2, 5)]);
        assert_eq!(leaf.primary, vec![true, true, true, true, false, true]);
        assert!(crate::curvenet::layout::embed(p).is_ok());
    }

    /// A start moved along the boundary lands on the given point, and its
    /// neighbours' order is kept (a move past a neighbour is refused).
    #[test]
    fn a_moved_start_stays_between_its_neighbours() {
        let mut leaf = square_leaf();
        assert!(split_chord(&mut leaf, 0, 0.25));
        assert!(move_start(&mut leaf, 1, 0.25));
        assert_eq!(point_of(&leaf, 1), [0.75, 0.0, 0.0]);
        assert!(!move_start(&mut leaf, 1, 2.0));
        assert_eq!(leaf.paired.starts.len(), 6);
    }

    /// The ends of a cut or connector (segment 1, the right side, here)
    /// never move: the cycle's other part holds the same ends. Start 1
    /// begins it and start 2 ends it; start 3 is free.
    #[test]
    fn the_ends_of_a_connector_stay_put() {
        let mut leaf = square_leaf();
        leaf.paired.unsplittable[1] = true;
        assert!(pinned(&leaf, 1) && pinned(&leaf, 2) && !pinned(&leaf, 3) && !pinned(&leaf, 0));
        assert!(!move_start(&mut leaf, 1, -0.5));
        assert!(!move_start(&mut leaf, 2, -0.5));
        assert_eq!(point_of(&leaf, 1), [2.0, 0.0, 0.0]);
        assert_eq!(point_of(&leaf, 2), [2.0, 1.0, 0.0]);
        assert!(!leaf.changed);
        assert!(move_start(&mut leaf, 3, -0.5));
        assert_eq!(point_of(&leaf, 3), [0.5, 1.0, 0.0]);
    }

    /// Two parts split the bottom side (curve positions 0..2) at x = 1 and
    /// agree there: two primary segments. Demoting the common vertex makes
    /// it secondary on both sides and joins them into one (the band rule's
    /// relaxation); a curve end, an input corner and a connector end are
    /// refused and change nothing.
    #[test]
    fn a_demoted_common_vertex_joins_two_primary_segments() {
        let mut leaves = [square_leaf(), square_leaf()];
        for leaf in &mut leaves {
            assert!(split_chord(leaf, 0, 0.5));
        }
        let seg = |leaf, segment, from, to| SideSegment { leaf, segment, from, to };
        let sc = SharedCurve {
            curve: 0,
            length: 2.0,
            cycles: [0, 1],
            sides: [
                vec![seg(0, 0, 0.0, 1.0), seg(0, 1, 1.0, 2.0)],
                vec![seg(1, 0, 2.0, 1.0), seg(1, 1, 1.0, 0.0)],
            ],
        };
        let tol = 1e-9;
        assert_eq!(sc.primary_segments(tol, &[]), vec![(0.0, 1.0), (1.0, 2.0)]);
        let never = |_: Vec3| false;
        assert!(!demote_common_vertex(&sc, 0.0, &mut leaves, tol, &never));
        let corner = |p: Vec3| p == [1.0, 0.0, 0.0];
        assert!(!demote_common_vertex(&sc, 1.0, &mut leaves, tol, &corner));
        leaves[1].paired.unsplittable[1] = true;
        assert!(!demote_common_vertex(&sc, 1.0, &mut leaves, tol, &never));
        assert!(leaves[0].primary[1] && leaves[1].primary[1]);
        leaves[1].paired.unsplittable[1] = false;
        assert!(demote_common_vertex(&sc, 1.0, &mut leaves, tol, &never));
        assert!(!leaves[0].primary[1] && !leaves[1].primary[1]);
        assert_eq!(sc.primary_segments(tol, &[1.0]), vec![(0.0, 2.0)]);
    }
}
