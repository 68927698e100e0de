//! The curve network (issue 30, items 1 and 10): curves as polylines, cycles
//! as loops of curve uses, and the closed, oriented, checked polylines of one
//! cycle ([`CycleLoops`]) that segmentation starts from.
//!
//! **Welding.** [`CurveNetwork::new`] welds every point within
//! [`WELD_FACTOR`] × the bounding-box diagonal: points that close are one
//! point (bit-identical afterwards), repeated points in a curve are dropped,
//! and a curve end or a listed corner that lies on another curve's segment is
//! inserted there as a point of that curve. Distinct points are then at least
//! the tolerance apart, so δ ([`CurveNetwork::delta`], spec §7.2) is never 0.
//!
//! **Orientation.** A loop's Newell vector is the normal about which it runs
//! counter-clockwise. The outer loop of a cycle is kept as given: the quads
//! face the side its Newell vector points to (right-hand rule). Holes run the
//! other way, so the surface is always on the left: a hole given the same way
//! as the outer loop (positive dot product of the Newell vectors) is reversed.
//! Cycles from CAD faces ([`NetworkCycle::cad_face`]) are taken as they are:
//! [`crate::curvenet::network_from_model`] orders their loops by the face
//! orientation, so the quads face out of a solid. Two cycles sharing a curve
//! must then use it in opposite directions.
//!
//! **Fixed points** ([`LoopPolyline::fixed`]): the listed corners, network
//! junctions where 3 or more curves used by cycles end, T-junctions (a used
//! curve's end on another used curve's interior), and the junctions of a
//! loop where consecutive curves meet turning more than
//! [`JUNCTION_TURN_DEGREES`] (not G1).

use std::collections::{HashMap, HashSet};

use geometry::vec3::{self, Vec3};
use geometry::{CurveId, FaceId};

use super::check::{self, key, SegmentGrid};
use super::error::{CurveNetError, Origin};
use super::{CycleLoops, CycleSurface, LoopPolyline};

/// Points closer than this fraction of the bounding-box diagonal are one point.
pub const WELD_FACTOR: f64 = 1e-9;

/// Consecutive curves of a loop meeting at a turn above this angle (degrees)
/// meet at a corner: a fixed point.
pub const JUNCTION_TURN_DEGREES: f64 = 40.0;

/// A loop whose Newell area is below this fraction of its bounding-box
/// diagonal squared has no inward side.
pub const INWARD_AREA_FACTOR: f64 = 1e-6;

/// One curve of the network: a polyline from its first point to its last (a
/// closed curve repeats its first point at the end).
#[derive(Clone, Debug, PartialEq)]
pub struct NetworkCurve {
    /// The samples in order.
    pub points: Vec<Vec3>,
    /// The CAD curve it samples, if any.
    pub cad: Option<CurveId>,
}

/// One use of a curve by a cycle loop.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct CycleUse {
    /// Index into the network's curves.
    pub curve: usize,
    /// True to traverse the curve from its first point to its last (`+1` in
    /// the JSON format), false for the other way (`-1`).
    pub forward: bool,
}

/// A cycle marked for surfacing: its outer loop first, then its holes, each a
/// list of curve uses whose ends meet.
#[derive(Clone, Debug, PartialEq)]
pub struct NetworkCycle {
    /// The loops; the first is the outer one.
    pub loops: Vec<Vec<CycleUse>>,
    /// The CAD face it bounds, if any: its loops are then oriented by the
    /// face and taken as they are.
    pub cad_face: Option<FaceId>,
    /// The CAD face's surface, when the network comes from a model
    /// (`network_from_model`); handed to the cycle's [`CycleLoops`].
    pub surface: Option<CycleSurface>,
}

/// A welded curve network: curves, the cycles to surface, the points that must
/// stay segment endpoints. Built by [`CurveNetwork::new`] (and the readers),
/// which welds it; each cycle is checked when [`CurveNetwork::cycle_loops`]
/// turns it into closed polylines.
#[derive(Clone, Debug)]
pub struct CurveNetwork {
    curves: Vec<NetworkCurve>,
    cycles: Vec<NetworkCycle>,
    corners: Vec<Vec3>,
    file: Option<String>,
    diagonal: f64,
    tolerance: f64,
    /// Points that stay segment endpoints in every cycle through them.
    fixed: HashSet<[u64; 3]>,
    /// Per cycle and loop: reversed to run opposite the outer loop.
    flips: Vec<Vec<bool>>,
    /// Per curve: the uses `(cycle, loop, forward after flips)`.
    curve_uses: Vec<Vec<(usize, usize, bool)>>,
}

/// Two networks are equal when their curves, cycles and corners are (the file
/// name is not compared).
impl PartialEq for CurveNetwork {
    fn eq(&self, other: &Self) -> bool {
        self.curves == other.curves && self.cycles == other.cycles && self.corners == other.corners
    }
}

impl CurveNetwork {
    /// Checks and welds a network: every curve id in range, every coordinate
    /// finite, at least one curve and one cycle and two distinct points.
    /// Cycles are checked one by one by [`CurveNetwork::cycle_loops`].
    pub fn new(
        curves: Vec<NetworkCurve>,
        cycles: Vec<NetworkCycle>,
        corners: Vec<Vec3>,
    ) -> Result<CurveNetwork, CurveNetError> {
        CurveNetwork::new_in(curves, cycles, corners, None)
    }

    /// [`CurveNetwork::new`] naming `file` in its errors and its cycles'.
    pub(crate) fn new_in(
        mut curves: Vec<NetworkCurve>,
        cycles: Vec<NetworkCycle>,
        mut corners: Vec<Vec3>,
        file: Option<String>,
    ) -> Result<CurveNetwork, CurveNetError> {
        let empty = |message: &str| CurveNetError::Empty {
            file: file.clone(),
            message: message.to_string(),
        };
        if curves.is_empty() {
            return Err(empty("no curves"));
        }
        if cycles.is_empty() {
            return Err(empty("no cycles"));
        }
        let mut first_user = vec![None; curves.len()];
        for (ci, cyc) in cycles.iter().enumerate() {
            for (li, lp) in cyc.loops.iter().enumerate() {
                for (ui, u) in lp.iter().enumerate() {
                    if u.curve >= curves.len() {
                        return Err(CurveNetError::UnknownCurve {
                            origin: Origin {
                                file: file.clone(),
                                cycle: Some(ci),
                                cad_face: cyc.cad_face,
                            },
                            loop_index: li,
                            use_index: ui,
                            curve: u.curve,
                            curves: curves.len(),
                        });
                    }
                    first_user[u.curve].get_or_insert(ci);
                }
            }
        }
        for (c, curve) in curves.iter().enumerate() {
            if curve.points.is_empty() {
                return Err(CurveNetError::Format {
                    file: file.clone(),
                    message: format!("curve {c} has no points"),
                });
            }
            if let Some(i) = curve.points.iter().position(|p| !finite(*p)) {
                let used = match first_user[c] {
                    Some(cy) => format!(" (used by cycle {cy})"),
                    None => String::new(),
                };
                return Err(CurveNetError::NotFinite {
                    file: file.clone(),
                    item: format!("curve {c} point {i}{used}"),
                    value: curve.points[i],
                });
            }
        }
        if let Some(i) = corners.iter().position(|p| !finite(*p)) {
            return Err(CurveNetError::NotFinite {
                file: file.clone(),
                item: format!("corner {i}"),
                value: corners[i],
            });
        }
        let all = curves.iter().flat_map(|c| c.points.iter()).chain(&corners);
        let (lo, hi) = check::bbox(all).expect("curves have points");
        let diagonal = vec3::dist(lo, hi);
        if !diagonal.is_finite() {
            return Err(CurveNetError::Format {
                file: file.clone(),
                message: format!("coordinates too large: the bounding box spans {lo:?} to {hi:?}"),
            });
        }
        if diagonal == 0.0 {
            return Err(empty("every point is the same point"));
        }
        let tolerance = WELD_FACTOR * diagonal;
        weld_points(&mut curves, &mut corners, tolerance);
        let used: Vec<bool> = first_user.iter().map(Option::is_some).collect();
        insert_touching_points(&mut curves, &corners, &used, tolerance);
        let fixed = fixed_points(&curves, &corners, &used);
        let flips = hole_flips(&curves, &cycles);
        let mut curve_uses = vec![Vec::new(); curves.len()];
        for (ci, cyc) in cycles.iter().enumerate() {
            for (li, lp) in cyc.loops.iter().enumerate() {
                for u in lp {
                    curve_uses[u.curve].push((ci, li, u.forward != flips[ci][li]));
                }
            }
        }
        Ok(CurveNetwork {
            curves,
            cycles,
            corners,
            file,
            diagonal,
            tolerance,
            fixed,
            flips,
            curve_uses,
        })
    }

    /// The same network naming `file` in its cycles' errors.
    pub fn with_file(mut self, file: impl Into<String>) -> CurveNetwork {
        self.file = Some(file.into());
        self
    }

    /// The file named in errors, if any.
    pub fn file(&self) -> Option<&str> {
        self.file.as_deref()
    }

    /// The curves, welded.
    pub fn curves(&self) -> &[NetworkCurve] {
        &self.curves
    }

    /// The cycles.
    pub fn cycles(&self) -> &[NetworkCycle] {
        &self.cycles
    }

    /// The listed corners, welded to the curve points they are on.
    pub fn corners(&self) -> &[Vec3] {
        &self.corners
    }

    /// Bounding-box diagonal of every point (before welding).
    pub fn diagonal(&self) -> f64 {
        self.diagonal
    }

    /// The weld tolerance, [`WELD_FACTOR`] × [`CurveNetwork::diagonal`].
    pub fn weld_tolerance(&self) -> f64 {
        self.tolerance
    }

    /// δ (spec §7.2): the smallest distance between adjacent samples of the
    /// curves used by cycles, after welding; at least the weld tolerance.
    /// Infinite when no used curve has two points.
    pub fn delta(&self) -> f64 {
        let mut d = f64::INFINITY;
        for (c, curve) in self.curves.iter().enumerate() {
            if self.curve_uses[c].is_empty() {
                continue;
            }
            for w in curve.points.windows(2) {
                d = d.min(vec3::dist(w[0], w[1]));
            }
        }
        d
    }

    /// The cycles using curve `c`, one entry per use (empty when out of range).
    pub fn curve_cycles(&self, c: usize) -> Vec<usize> {
        self.curve_uses.get(c).map_or_else(Vec::new, |u| u.iter().map(|&(cycle, _, _)| cycle).collect())
    }

    /// True when `p` is a point every cycle keeps as a segment endpoint: a
    /// listed corner or a junction of three or more curve ends (spec §7.2's
    /// fixed input corners and T-junctions).
    pub fn is_fixed_point(&self, p: Vec3) -> bool {
        self.fixed.contains(&key(p))
    }

    /// Total number of curve points.
    pub fn point_count(&self) -> usize {
        self.curves.iter().map(|c| c.points.len()).sum()
    }

    /// The origin of errors about cycle `c`.
    fn origin(&self, c: usize) -> Origin {
        Origin {
            file: self.file.clone(),
            cycle: Some(c),
            cad_face: self.cycles.get(c).and_then(|cy| cy.cad_face),
        }
    }

    /// Cycle `cycle` as closed polylines: its curve uses concatenated (shared
    /// ends once), holes reversed where needed (see the module's
    /// orientation), the fixed points marked. Fails, naming the cycle and the
    /// place, when a loop is open, has fewer than 3 distinct points, the cycle
    /// crosses or touches itself, a loop has no inward side, or a curve it
    /// shares is used the same way by the other cycle.
    pub fn cycle_loops(&self, cycle: usize) -> Result<CycleLoops, CurveNetError> {
        let cyc = self.cycles.get(cycle).ok_or(CurveNetError::OutOfRange {
            what: "cycle",
            index: cycle,
            count: self.cycles.len(),
        })?;
        let origin = self.origin(cycle);
        if cyc.loops.is_empty() {
            return Err(CurveNetError::TooFewPoints {
                origin,
                loop_index: 0,
                distinct: 0,
                at: None,
            });
        }
        let mut loops = Vec::with_capacity(cyc.loops.len());
        for (li, lp) in cyc.loops.iter().enumerate() {
            let (mut pts, mut joins) = self.concat(&origin, li, lp)?;
            let distinct: HashSet<[u64; 3]> = pts.iter().map(|p| key(*p)).collect();
            if distinct.len() < 3 {
                return Err(CurveNetError::TooFewPoints {
                    origin,
                    loop_index: li,
                    distinct: distinct.len(),
                    at: pts.first().copied(),
                });
            }
            if self.flips[cycle][li] {
                let n = pts.len();
                pts[1..].reverse();
                for j in &mut joins {
                    *j = (n - *j) % n;
                }
            }
            loops.push((pts, joins));
        }
        let refs: Vec<&[Vec3]> = loops.iter().map(|(p, _)| p.as_slice()).collect();
        if let Some((a, b, distance, at)) = check::self_contact(&refs, self.tolerance) {
            return Err(CurveNetError::SelfIntersecting {
                origin,
                loops: (a, b),
                at,
                distance,
                tolerance: self.tolerance,
            });
        }
        for (li, (pts, _)) in loops.iter().enumerate() {
            let area = vec3::norm(check::newell(pts));
            let (lo, hi) = check::bbox(pts.iter()).expect("3 points");
            let minimum = INWARD_AREA_FACTOR * vec3::dist(lo, hi).powi(2);
            if !(area >= minimum) {
                return Err(CurveNetError::NoInwardSide {
                    origin,
                    loop_index: li,
                    area,
                    minimum,
                    at: check::centroid(pts),
                });
            }
        }
        self.check_orientation(cycle, &origin)?;
        let mut out = loops.into_iter().map(|(points, joins)| {
            let fixed = self.fixed_indices(&points, &joins);
            LoopPolyline { points, fixed }
        });
        let outer = out.next().expect("a loop");
        Ok(CycleLoops {
            outer,
            holes: out.collect(),
            surface: cyc.surface.clone(),
        })
    }

    /// Every cycle's error, in cycle order (empty when every cycle is valid).
    pub fn validate(&self) -> Vec<CurveNetError> {
        (0..self.cycles.len())
            .filter_map(|c| self.cycle_loops(c).err())
            .collect()
    }

    /// The points of loop `lp` joined, closed (the first point not repeated),
    /// and the indices where one curve use meets the next.
    fn concat(
        &self,
        origin: &Origin,
        li: usize,
        lp: &[CycleUse],
    ) -> Result<(Vec<Vec3>, Vec<usize>), CurveNetError> {
        let mut pts: Vec<Vec3> = Vec::new();
        let mut joins = Vec::with_capacity(lp.len());
        let open = |from: Vec3, to: Vec3| CurveNetError::Open {
            origin: origin.clone(),
            loop_index: li,
            from,
            to,
            gap: vec3::dist(from, to),
            tolerance: self.tolerance,
        };
        for u in lp {
            let cp = &self.curves[u.curve].points;
            let oriented: Box<dyn Iterator<Item = &Vec3>> = if u.forward {
                Box::new(cp.iter())
            } else {
                Box::new(cp.iter().rev())
            };
            let mut oriented = oriented.peekable();
            let first = **oriented.peek().expect("curves have points");
            match pts.last() {
                Some(&last) => {
                    if key(last) != key(first) {
                        return Err(open(last, first));
                    }
                    joins.push(pts.len() - 1);
                    pts.extend(oriented.skip(1));
                }
                None => {
                    joins.push(0);
                    pts.extend(oriented);
                }
            }
        }
        let (Some(&first), Some(&last)) = (pts.first(), pts.last()) else {
            return Ok((pts, joins));
        };
        if key(first) != key(last) {
            return Err(open(last, first));
        }
        if pts.len() > 1 {
            pts.pop();
        }
        let n = pts.len().max(1);
        for j in &mut joins {
            *j %= n;
        }
        Ok((pts, joins))
    }

    /// NonOrientable when a curve of `cycle` used by exactly two loops is
    /// used the same way by both.
    fn check_orientation(&self, cycle: usize, origin: &Origin) -> Result<(), CurveNetError> {
        for lp in &self.cycles[cycle].loops {
            for u in lp {
                let uses = &self.curve_uses[u.curve];
                if uses.len() != 2 || uses[0].2 != uses[1].2 {
                    continue;
                }
                let other = if uses[0].0 == cycle { uses[1] } else { uses[0] };
                let pts = &self.curves[u.curve].points;
                return Err(CurveNetError::NonOrientable {
                    origin: origin.clone(),
                    other_cycle: other.0,
                    other_face: self.cycles[other.0].cad_face,
                    curve: u.curve,
                    // the middle of the curve
                    at: vec3::lerp(pts[(pts.len() - 1) / 2], pts[pts.len() / 2], 0.5),
                });
            }
        }
        Ok(())
    }

    /// Indices of the fixed points of a closed loop: the network's fixed
    /// points on it, and the joins where the loop turns by more than
    /// [`JUNCTION_TURN_DEGREES`].
    fn fixed_indices(&self, pts: &[Vec3], joins: &[usize]) -> Vec<usize> {
        let n = pts.len();
        let limit = JUNCTION_TURN_DEGREES.to_radians();
        let mut out: Vec<usize> = (0..n)
            .filter(|&i| self.fixed.contains(&key(pts[i])))
            .collect();
        for &j in joins {
            if turn(pts[(j + n - 1) % n], pts[j], pts[(j + 1) % n]) > limit {
                out.push(j);
            }
        }
        out.sort_unstable();
        out.dedup();
        out
    }
}

fn finite(p: Vec3) -> bool {
    p.iter().all(|x| x.is_finite())
}

/// The turning angle (radians) at `b` going from `a` through `b` to `c`.
pub(crate) fn turn(a: Vec3, b: Vec3, c: Vec3) -> f64 {
    let u = vec3::sub(b, a);
    let v = vec3::sub(c, b);
    let nn = vec3::norm(u) * vec3::norm(v);
    if !(nn > 0.0) {
        return 0.0;
    }
    (vec3::dot(u, v) / nn).clamp(-1.0, 1.0).acos()
}

/// Welds every curve point and corner within `tol` and drops repeated
/// consecutive points of each curve.
fn weld_points(curves: &mut [NetworkCurve], corners: &mut [Vec3], tol: f64) {
    let all: Vec<Vec3> = curves
        .iter()
        .flat_map(|c| c.points.iter().copied())
        .chain(corners.iter().copied())
        .collect();
    let welded = check::weld(&all, tol);
    let mut it = welded.into_iter();
    for c in curves.iter_mut() {
        for p in c.points.iter_mut() {
            *p = it.next().expect("one per point");
        }
        c.points.dedup_by(|a, b| key(*a) == key(*b));
    }
    for p in corners.iter_mut() {
        *p = it.next().expect("one per corner");
    }
}

/// Inserts each end of a used curve, and each corner, that lies within `tol`
/// of a segment of another used curve (not at its ends) into that segment,
/// at the nearest segment of each such curve.
fn insert_touching_points(curves: &mut [NetworkCurve], corners: &[Vec3], used: &[bool], tol: f64) {
    let mut segs = Vec::new();
    let mut owner = Vec::new();
    for (c, curve) in curves.iter().enumerate() {
        if !used[c] {
            continue;
        }
        for (i, w) in curve.points.windows(2).enumerate() {
            segs.push([w[0], w[1]]);
            owner.push((c, i));
        }
    }
    if segs.is_empty() {
        return;
    }
    let grid = SegmentGrid::new(&segs, tol);
    let mut queries: Vec<(Option<usize>, Vec3)> = Vec::new();
    for (c, curve) in curves.iter().enumerate() {
        if used[c] {
            queries.push((Some(c), curve.points[0]));
            queries.push((Some(c), *curve.points.last().expect("points")));
        }
    }
    queries.extend(corners.iter().map(|&p| (None, p)));
    // per curve: (segment, parameter, point)
    let mut inserts: HashMap<usize, Vec<(usize, f64, Vec3)>> = HashMap::new();
    for (own, q) in queries {
        let mut best: HashMap<usize, (f64, usize, f64)> = HashMap::new();
        for &s in grid.near(q) {
            let (c, i) = owner[s as usize];
            let [a, b] = segs[s as usize];
            if Some(c) == own || key(q) == key(a) || key(q) == key(b) {
                continue;
            }
            let (d, t) = check::point_segment(q, a, b);
            if d < tol && best.get(&c).is_none_or(|&(bd, _, _)| d < bd) {
                best.insert(c, (d, i, t));
            }
        }
        for (c, (_, i, t)) in best {
            inserts.entry(c).or_default().push((i, t, q));
        }
    }
    for (c, mut list) in inserts {
        list.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
        list.dedup_by(|a, b| key(a.2) == key(b.2));
        let old = std::mem::take(&mut curves[c].points);
        let mut k = 0;
        for (i, p) in old.iter().enumerate() {
            curves[c].points.push(*p);
            while k < list.len() && list[k].0 == i {
                curves[c].points.push(list[k].2);
                k += 1;
            }
        }
    }
}

/// The network's fixed points: listed corners, ends of 3 or more used curves
/// (a closed curve's point counts twice), and T-junctions (an end of a used
/// curve that is an interior point of another used curve).
fn fixed_points(curves: &[NetworkCurve], corners: &[Vec3], used: &[bool]) -> HashSet<[u64; 3]> {
    let mut out: HashSet<[u64; 3]> = corners.iter().map(|p| key(*p)).collect();
    let mut degree: HashMap<[u64; 3], usize> = HashMap::new();
    for (c, curve) in curves.iter().enumerate() {
        if used[c] {
            *degree.entry(key(curve.points[0])).or_default() += 1;
            *degree
                .entry(key(*curve.points.last().expect("points")))
                .or_default() += 1;
        }
    }
    out.extend(degree.iter().filter(|(_, &d)| d >= 3).map(|(k, _)| *k));
    for (c, curve) in curves.iter().enumerate() {
        if !used[c] || curve.points.len() < 3 {
            continue;
        }
        for p in &curve.points[1..curve.points.len() - 1] {
            if degree.contains_key(&key(*p)) {
                out.insert(key(*p));
            }
        }
    }
    out
}

/// The points of a loop, uses joined without checks (for Newell vectors).
fn raw_loop(curves: &[NetworkCurve], lp: &[CycleUse]) -> Vec<Vec3> {
    let mut pts = Vec::new();
    for u in lp {
        let cp = &curves[u.curve].points;
        if u.forward {
            pts.extend(cp.iter().copied());
        } else {
            pts.extend(cp.iter().rev().copied());
        }
    }
    pts
}

/// Per cycle and loop: true for a hole of a cycle not from CAD whose Newell
/// vector points along the outer loop's (it runs the same way).
fn hole_flips(curves: &[NetworkCurve], cycles: &[NetworkCycle]) -> Vec<Vec<bool>> {
    cycles
        .iter()
        .map(|cyc| {
            let mut flips = vec![false; cyc.loops.len()];
            if cyc.cad_face.is_some() || cyc.loops.len() < 2 {
                return flips;
            }
            let outer = check::newell(&raw_loop(curves, &cyc.loops[0]));
            for (li, lp) in cyc.loops.iter().enumerate().skip(1) {
                let hole = check::newell(&raw_loop(curves, lp));
                flips[li] = vec3::dot(outer, hole) > 0.0;
            }
            flips
        })
        .collect()
}

#[cfg(test)]
mod tests;
