//! The ring layout of an annulus (a cycle with exactly one hole; issue 30,
//! Fig. 17): one straight connector between the closest samples of the two
//! loops, and the two loops split at matching arc-length fractions from the
//! connector into k sectors. The pairing is given, not matched: sector i of
//! the outer loop bridges to the hole segment facing it, and the two copies
//! of the connector bridge to each other, so the layout is k patches in a
//! ring (an O-grid) with no interior vertex, and every patch lies between
//! the two loops.
//!
//! Why not the matched pairing (§3.1) for annuli: the joined loop is a disk
//! cut along the connector, and the matching, free to pair a connector copy
//! or an outer segment with any other segment, builds chords that cross the
//! hole; their patches blend boundaries from both sides of the hole and
//! fold (every synthetic annulus and the letter P folded so). Pairing the
//! connector copies with each other is the only pairing whose chords all
//! stay inside the ring.

use super::pairing::{clean_loop, PairingError, PairingOptions, PairingReport};
use super::polyline::{densify_closed, diameter, dist, lerp, norm, newell_normal, P3};
use super::segment::segment_loop;
use super::{CycleLoops, PairedCycle};

/// Marks of the two loops within this share of the loop length of each
/// other are one sector boundary (each loop keeps its own point).
const MATCH_FRACTION: f64 = 0.03;

/// No sector spans more than this share of its loop (a quarter turn and a
/// bit on a circle).
const MAX_SECTOR_FRACTION: f64 = 0.3;

/// The ring layout's pairing of an annulus (see the module docs): segments
/// 0..k along the outer loop from the connector, segment k the connector,
/// k+1..=2k along the hole, 2k+1 the connector back; pairs (i, 2k − i) and
/// (k, 2k + 1). `None` when the cycle has not exactly one hole.
pub fn pair_ring(
    cycle: &CycleLoops,
    opts: &PairingOptions,
) -> Option<Result<(PairedCycle, PairingReport), PairingError>> {
    (cycle.holes.len() == 1).then(|| ring(cycle, opts))
}

fn ring(cycle: &CycleLoops, opts: &PairingOptions) -> Result<(PairedCycle, PairingReport), PairingError> {
    let all: Vec<P3> = cycle.outer.points.iter().chain(&cycle.holes[0].points).copied().collect();
    if let Some(point) = all.iter().position(|p| p.iter().any(|v| !v.is_finite())) {
        let (loop_index, point) = match point.checked_sub(cycle.outer.points.len()) {
            Some(p) => (1, p),
            None => (0, point),
        };
        return Err(PairingError::NotFinite { loop_index, point });
    }
    let d = diameter(&all);
    let area = 0.5 * norm(newell_normal(&cycle.outer.points));
    if !(d > 0.0) || area < 1e-6 * d * d {
        return Err(PairingError::NoInwardSide { area, limit: 1e-6 * d * d, diameter: d });
    }
    let mut loops = Vec::with_capacity(2);
    let mut fallbacks = Vec::new();
    for (li, lp) in [&cycle.outer, &cycle.holes[0]].into_iter().enumerate() {
        let (points, fixed) = clean_loop(lp, li, 1e-12 * d)?;
        let (dense, index_of) = densify_closed(&points, opts.sample_spacing * d);
        let fixed: Vec<usize> = fixed.iter().map(|&f| index_of[f]).collect();
        let seg = segment_loop(dense, &fixed, opts);
        // A loop with too few corners keeps only its fixed points: the
        // fallback's arc-length starts are arbitrary here, the sectors
        // below split it evenly from the connector instead.
        let marks = if seg.fallback {
            fallbacks.push((li, seg.corners));
            fixed
        } else {
            seg.segmented.starts.clone()
        };
        loops.push((seg.segmented.points, marks));
    }
    let (outer, hole) = (&loops[0], &loops[1]);
    let (ia, ib) = closest_samples(&outer.0, &hole.0);
    let outer_pts = rotated(&outer.0, ia);
    let hole_pts = rotated(&hole.0, ib);
    let fo = fractions(&outer_pts, outer.1.iter().map(|&i| (i + outer.0.len() - ia) % outer.0.len()));
    let fh = fractions(&hole_pts, hole.1.iter().map(|&i| (i + hole.0.len() - ib) % hole.0.len()));
    let bounds = sector_bounds(&fo, &fh);
    let k = bounds.len();
    // Outer marks ascending; hole marks ascending along the hole (its
    // traversal fraction t faces outer fraction 1 − t).
    let outer_marks: Vec<f64> = bounds.iter().map(|b| b.0).collect();
    let mut hole_marks: Vec<f64> = bounds.iter().map(|b| b.1).collect();
    hole_marks.sort_by(f64::total_cmp);
    let (outer_line, outer_at) = with_marks(&outer_pts, &outer_marks);
    let (hole_line, hole_at) = with_marks(&hole_pts, &hole_marks);
    if outer_at.len() != k || hole_at.len() != k {
        // Two marks closer than 1e-9 of the loop length: no ring.
        return Err(PairingError::NoEvenMatching { iterations: 0, segments: 2 * k + 2 });
    }
    let (m, h) = (outer_line.len(), hole_line.len());
    let mut points = outer_line.clone();
    points.push(outer_line[0]);
    points.extend_from_slice(&hole_line);
    points.push(hole_line[0]);
    let mut starts: Vec<usize> = outer_at;
    starts.push(m);
    starts.extend(hole_at.iter().map(|&i| m + 1 + i));
    starts.push(m + 1 + h);
    let mut pairs: Vec<(usize, usize)> = (0..k).map(|i| (i, 2 * k - i)).collect();
    pairs.push((k, 2 * k + 1));
    let mut unsplittable = vec![false; 2 * k + 2];
    unsplittable[k] = true;
    unsplittable[2 * k + 1] = true;
    // Connectors of an earlier split on the outer loop stay one segment.
    for &[from, to] in &opts.unsplittable_edges {
        let at = |s: usize, p: P3| dist(points[starts[s]], p) <= 1e-9 * d;
        match (0..k).find(|&s| at(s, from) && at(s + 1, to)) {
            Some(s) => unsplittable[s] = true,
            None => return Err(PairingError::KeptEdge { from, to }),
        }
    }
    let costs = vec![0.0; pairs.len()];
    let paired = PairedCycle { points, starts, pairs, costs: costs.clone(), unsplittable, diameter: d };
    let report = PairingReport {
        initial_segments: 2 * k + 2,
        final_segments: 2 * k + 2,
        iterations: 0,
        fallbacks,
        odd_parties: Vec::new(),
        connectors: 1,
        costs,
        average_cost: 0.0,
        worst_cost: 0.0,
        history: Vec::new(),
    };
    Ok((paired, report))
}

/// One half of a holed cycle split by two connectors: a cycle with fewer
/// holes and the connector edges (by position) that must stay one segment.
#[derive(Clone, Debug, PartialEq)]
pub struct AnnulusHalf {
    /// The half: its outer loop runs along the old outer loop, one
    /// connector, the split hole and the other connector; the other holes
    /// that lie in it are its holes.
    pub loops: CycleLoops,
    /// The connectors, as edges of the half's outer loop (the two new ones
    /// and any earlier ones it keeps).
    pub connectors: Vec<[P3; 2]>,
}

/// Candidate connector pairs tested per connector, nearest first.
const MAX_CONNECTOR_TRIES: usize = 4000;

/// A cycle with holes cut into two by two straight connectors between one
/// hole and the outer loop (the "two connectors" route, when the ring folds,
/// as for the letter P's non-convex outer loop, or when there are several
/// holes): the first from the outer loop to the hole's nearest sample, the
/// second from the hole's far half (a quarter to three quarters of its
/// length from the first) to the nearest outer sample; neither crosses a
/// loop or the other connector, and each leaves the hole into the face
/// (checked in the plane of the outer loop's Newell normal). The holes are
/// tried nearest the outer loop first; the other holes go to the half they
/// lie in, so halves are split again until none has a hole. `kept`: earlier
/// connectors on the outer loop, passed on to the half that has them.
/// `None` when there is no hole or no hole can be split off.
pub fn split_annulus(cycle: &CycleLoops, kept: &[[P3; 2]], opts: &PairingOptions) -> Option<[AnnulusHalf; 2]> {
    if cycle.holes.is_empty() {
        return None;
    }
    let all: Vec<P3> = std::iter::once(&cycle.outer).chain(&cycle.holes).flat_map(|l| l.points.iter().copied()).collect();
    let d = diameter(&all);
    let mut dense = Vec::with_capacity(1 + cycle.holes.len());
    for (li, lp) in std::iter::once(&cycle.outer).chain(&cycle.holes).enumerate() {
        let (points, fixed) = clean_loop(lp, li, 1e-12 * d).ok()?;
        let (pts, index_of) = densify_closed(&points, opts.sample_spacing * d);
        let fixed: Vec<usize> = fixed.iter().map(|&f| index_of[f]).collect();
        dense.push((pts, fixed));
    }
    let frame = Plane::of(&cycle.outer.points);
    let flat: Vec<Vec<[f64; 2]>> = dense.iter().map(|l| l.0.iter().map(|&p| frame.project(p)).collect()).collect();
    let o = &dense[0].0;
    let m = o.len();
    // Holes by their distance to the outer loop.
    let mut order: Vec<(f64, usize)> = (1..dense.len())
        .map(|t| (dense[t].0.iter().map(|&q| o.iter().map(|&p| dist(p, q)).fold(f64::INFINITY, f64::min)).fold(f64::INFINITY, f64::min), t))
        .collect();
    order.sort_by(|a, b| a.0.total_cmp(&b.0));
    for &(_, t) in &order {
        let h = &dense[t].0;
        let nh = h.len();
        // A connector from outer sample a to hole sample b is clear when it
        // crosses no loop (its own ends' edges aside) and no `other`
        // segment, and its middle lies in the face.
        let clear = |a: usize, b: usize, other: Option<[[f64; 2]; 2]>| {
            let seg = [flat[0][a], flat[t][b]];
            let mid = [0.5 * (seg[0][0] + seg[1][0]), 0.5 * (seg[0][1] + seg[1][1])];
            (0..flat.len()).all(|l| {
                let own = if l == 0 { a } else if l == t { b } else { usize::MAX };
                !crosses_loop(seg, &flat[l], own) && (l == 0) == inside(mid, &flat[l])
            }) && other.is_none_or(|c| !proper_cross(seg, c))
        };
        let nearest = |holes: &mut dyn Iterator<Item = usize>| -> Vec<(f64, usize, usize)> {
            let mut c: Vec<(f64, usize, usize)> =
                holes.flat_map(|b| (0..m).map(move |a| (dist(o[a], h[b]), a, b))).collect();
            c.sort_by(|x, y| x.0.total_cmp(&y.0));
            c.truncate(MAX_CONNECTOR_TRIES);
            c
        };
        let Some((_, ia, ib)) = nearest(&mut (0..nh)).into_iter().find(|&(_, a, b)| clear(a, b, None)) else {
            continue;
        };
        let first = [flat[0][ia], flat[t][ib]];
        let far = nearest(&mut (nh / 4..=(3 * nh) / 4).map(|s| (ib + s) % nh));
        let Some((_, ja, jb)) = far.into_iter().find(|&(_, a, b)| a != ia && b != ib && clear(a, b, Some(first))) else {
            continue;
        };
        let half = |oa: usize, ob: usize, ha: usize, hb: usize| -> AnnulusHalf {
            // Outer from oa to ob, connector, hole from ha to hb, closing connector.
            let outer_run = super::polyline::cyclic_range(m, oa, ob);
            let hole_run = super::polyline::cyclic_range(nh, ha, hb);
            let mut points: Vec<P3> = outer_run.iter().map(|&i| o[i]).collect();
            let last_outer = points.len() - 1;
            points.extend(hole_run.iter().map(|&i| h[i]));
            let mut fixed: Vec<usize> = vec![0, last_outer, last_outer + 1, points.len() - 1];
            fixed.extend(outer_run.iter().enumerate().filter(|(_, i)| dense[0].1.contains(i)).map(|(k, _)| k));
            fixed.extend(
                hole_run.iter().enumerate().filter(|(_, i)| dense[t].1.contains(i)).map(|(k, _)| k + last_outer + 1),
            );
            fixed.sort_unstable();
            fixed.dedup();
            let mut connectors =
                vec![[points[last_outer], points[last_outer + 1]], [points[points.len() - 1], points[0]]];
            connectors.extend(super::polyline::edges_along(&points, kept));
            let flat_half: Vec<[f64; 2]> = points.iter().map(|&p| frame.project(p)).collect();
            let holes = (1..dense.len())
                .filter(|&u| u != t && inside(flat[u][0], &flat_half))
                .map(|u| cycle.holes[u - 1].clone())
                .collect();
            AnnulusHalf { loops: CycleLoops { outer: super::LoopPolyline { points, fixed }, holes, surface: cycle.surface.clone() }, connectors }
        };
        return Some([half(ia, ja, jb, ib), half(ja, ia, ib, jb)]);
    }
    None
}

/// Whether the segment crosses an edge of the closed 2D polyline other
/// than the two edges at its own end `own` (an index into `points`, or
/// past it for an end on another loop).
fn crosses_loop(seg: [[f64; 2]; 2], points: &[[f64; 2]], own: usize) -> bool {
    let n = points.len();
    (0..n).any(|i| {
        let j = (i + 1) % n;
        own != i && own != j && proper_cross(seg, [points[i], points[j]])
    })
}

/// Whether two 2D segments cross or touch away from shared end points.
fn proper_cross(a: [[f64; 2]; 2], b: [[f64; 2]; 2]) -> bool {
    let orient = |p: [f64; 2], q: [f64; 2], r: [f64; 2]| (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]);
    let (d1, d2) = (orient(a[0], a[1], b[0]), orient(a[0], a[1], b[1]));
    let (d3, d4) = (orient(b[0], b[1], a[0]), orient(b[0], b[1], a[1]));
    d1 * d2 < 0.0 && d3 * d4 < 0.0
}

/// Whether a 2D point is inside a closed polyline (even-odd rule).
fn inside(p: [f64; 2], points: &[[f64; 2]]) -> bool {
    let n = points.len();
    let mut odd = false;
    for i in 0..n {
        let (a, b) = (points[i], points[(i + 1) % n]);
        if (a[1] > p[1]) != (b[1] > p[1]) {
            let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
            if x > p[0] {
                odd = !odd;
            }
        }
    }
    odd
}

/// The plane of a loop's Newell normal through the origin, for 2D tests.
struct Plane {
    u: P3,
    v: P3,
}

impl Plane {
    fn of(points: &[P3]) -> Plane {
        let n = super::polyline::normalized(newell_normal(points)).unwrap_or([0.0, 0.0, 1.0]);
        let seed = if n[0].abs() < 0.9 { [1.0, 0.0, 0.0] } else { [0.0, 1.0, 0.0] };
        let u = super::polyline::normalized(super::polyline::cross(n, seed)).unwrap_or([1.0, 0.0, 0.0]);
        let v = super::polyline::cross(n, u);
        Plane { u, v }
    }

    fn project(&self, p: P3) -> [f64; 2] {
        [super::polyline::dot(p, self.u), super::polyline::dot(p, self.v)]
    }
}

/// The closest pair of samples (outer index, hole index): the connector.
/// Between two nested loops of one plane it crosses neither (a crossing
/// would give a shorter one).
fn closest_samples(outer: &[P3], hole: &[P3]) -> (usize, usize) {
    let mut best = (f64::INFINITY, 0, 0);
    for (a, &p) in outer.iter().enumerate() {
        for (b, &q) in hole.iter().enumerate() {
            let dd = dist(p, q);
            if dd < best.0 {
                best = (dd, a, b);
            }
        }
    }
    (best.1, best.2)
}

/// The closed polyline started at index `from`.
fn rotated(points: &[P3], from: usize) -> Vec<P3> {
    points[from..].iter().chain(&points[..from]).copied().collect()
}

/// The cumulative arc length of a closed polyline at each point, and its
/// total (the closing edge included).
fn arc_lengths(points: &[P3]) -> (Vec<f64>, f64) {
    let mut acc = Vec::with_capacity(points.len());
    let mut s = 0.0;
    for i in 0..points.len() {
        acc.push(s);
        s += dist(points[i], points[(i + 1) % points.len()]);
    }
    (acc, s)
}

/// The arc-length fractions of the given point indices, ascending, 0 first.
fn fractions(points: &[P3], marks: impl Iterator<Item = usize>) -> Vec<f64> {
    let (acc, total) = arc_lengths(points);
    let mut out: Vec<f64> = std::iter::once(0.0)
        .chain(marks.map(|i| if total > 0.0 { acc[i] / total } else { 0.0 }))
        .collect();
    out.sort_by(f64::total_cmp);
    out.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
    out
}

/// The sector boundaries: (outer fraction, hole fraction) pairs, the first
/// (0, 0) at the connector, then by outer fraction ascending (hole fraction
/// descending). Each loop's own marks keep their place; a mark of one loop
/// within [`MATCH_FRACTION`] of a mark of the other is matched with it,
/// the others get a new point on the other loop at the facing fraction.
/// Sectors longer than [`MAX_SECTOR_FRACTION`] (and fewer than four) are
/// halved.
fn sector_bounds(fo: &[f64], fh: &[f64]) -> Vec<(f64, f64)> {
    // The hole's marks as outer fractions (1 − t), with their own value.
    let mut facing: Vec<(f64, f64)> = fh.iter().skip(1).map(|&t| (1.0 - t, t)).collect();
    let mut out: Vec<(f64, f64)> = vec![(0.0, 0.0)];
    for &s in fo.iter().skip(1) {
        let near = facing
            .iter()
            .enumerate()
            .filter(|(_, f)| (f.0 - s).abs() < MATCH_FRACTION)
            .min_by(|a, b| (a.1 .0 - s).abs().total_cmp(&(b.1 .0 - s).abs()))
            .map(|(i, _)| i);
        match near {
            Some(i) => out.push((s, facing.remove(i).1)),
            None => out.push((s, 1.0 - s)),
        }
    }
    out.extend(facing.into_iter().filter(|f| f.0 > MATCH_FRACTION && f.0 < 1.0 - MATCH_FRACTION));
    out.sort_by(|a, b| a.0.total_cmp(&b.0));
    loop {
        let gap = |i: usize| {
            let next = out.get(i + 1).map_or(1.0, |b| b.0);
            next - out[i].0
        };
        let Some(i) = (0..out.len()).max_by(|&a, &b| gap(a).total_cmp(&gap(b))) else { break };
        if gap(i) <= MAX_SECTOR_FRACTION && out.len() >= 4 {
            break;
        }
        let s = out[i].0 + 0.5 * gap(i);
        out.insert(i + 1, (s, 1.0 - s));
    }
    out
}

/// The closed polyline with a point at each arc-length fraction (ascending,
/// the first 0): an existing point within 1e-9 of the length, else a new
/// point on its edge. Returns the points and each mark's index.
fn with_marks(points: &[P3], marks: &[f64]) -> (Vec<P3>, Vec<usize>) {
    let (acc, total) = arc_lengths(points);
    let n = points.len();
    let mut out = Vec::with_capacity(n + marks.len());
    let mut at = Vec::with_capacity(marks.len());
    let mut next = 0;
    for i in 0..n {
        let end = if i + 1 < n { acc[i + 1] } else { total };
        out.push(points[i]);
        while next < marks.len() {
            let target = marks[next] * total;
            if (target - acc[i]).abs() <= 1e-9 * total {
                at.push(out.len() - 1);
            } else if target < end - 1e-9 * total {
                let t = (target - acc[i]) / (end - acc[i]);
                at.push(out.len());
                out.push(lerp(points[i], points[(i + 1) % n], t));
            } else {
                break;
            }
            next += 1;
        }
    }
    at.dedup();
    (out, at)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::curvenet::fixtures;
    use std::f64::consts::PI;

    /// A circle in a circle: the connector joins the closest samples, the
    /// fallback loops are split into four quarter sectors, the pairs run
    /// outer sector i to the facing hole sector, and the connector copies
    /// pair with each other.
    #[test]
    fn a_concentric_annulus_pairs_four_sectors_and_the_connector_copies() {
        let (p, report) = pair_ring(&fixtures::annulus([0.0, 0.0], 0.4), &PairingOptions::default())
            .unwrap()
            .unwrap();
        assert_eq!(p.starts.len(), 10);
        assert_eq!(p.pairs, vec![(0, 8), (1, 7), (2, 6), (3, 5), (4, 9)]);
        assert_eq!(report.connectors, 1);
        assert_eq!(p.unsplittable.iter().filter(|&&u| u).count(), 2);
        // The connector: from the outer polygon to the hole's, length 0.6
        // less the polygons' sagitta (the closest samples may lie on edges).
        let (a, b) = (p.points[p.starts[4]], p.points[p.starts[5]]);
        let c = (PI / 64.0).cos();
        assert!(dist(a, b) <= 0.6 + 1e-12 && dist(a, b) > c - 0.4, "{a:?} {b:?}");
        assert!(norm(a) >= c - 1e-12 && norm(a) <= 1.0 + 1e-12, "{a:?}");
        // Each sector boundary faces its mate: the same polar angle.
        for &(i, j) in &p.pairs[..4] {
            let (o, hh) = (p.points[p.starts[i]], p.points[p.starts[j + 1]]);
            // The same polar angle up to the polygons' arc-length error.
            let sin = (o[0] * hh[1] - o[1] * hh[0]) / (norm(o) * norm(hh));
            assert!(sin.abs() < 0.02, "{o:?} {hh:?}");
        }
    }

    /// A square's four corners become sector bounds on the hole too.
    #[test]
    fn a_square_with_a_round_hole_keeps_the_square_corners_as_sector_bounds() {
        let (p, _) = pair_ring(&fixtures::square_with_round_hole([0.0, 0.0], 0.4), &PairingOptions::default())
            .unwrap()
            .unwrap();
        let k = p.starts.len() / 2 - 1;
        let corners = (0..k)
            .filter(|&s| {
                let q = p.points[p.starts[s]];
                (q[0].abs() - 1.0).abs() < 1e-12 && (q[1].abs() - 1.0).abs() < 1e-12
            })
            .count();
        assert_eq!(corners, 4);
        assert!(k >= 5, "the connector point and the four corners: {k}");
    }

    /// The letter P splits into two disks whose connectors join the hole to
    /// the outer loop without crossing either loop; every point of each half
    /// is on one of the two loops.
    #[test]
    fn the_letter_p_splits_into_two_disks_by_two_connectors() {
        let halves = split_annulus(&fixtures::letter_p(), &[], &PairingOptions::default()).unwrap();
        let [lo, hi] = fixtures::P_HOLE;
        for half in &halves {
            assert_eq!(half.connectors.len(), 2);
            assert!(half.loops.holes.is_empty());
            for c in &half.connectors {
                let on_hole = |p: P3| {
                    (p[0] - lo[0]).abs().min((p[0] - hi[0]).abs()) < 1e-9 && p[1] >= lo[1] - 1e-9 && p[1] <= hi[1] + 1e-9
                        || (p[1] - lo[1]).abs().min((p[1] - hi[1]).abs()) < 1e-9 && p[0] >= lo[0] - 1e-9 && p[0] <= hi[0] + 1e-9
                };
                assert!(on_hole(c[0]) != on_hole(c[1]), "{c:?}: one end on the hole");
                // No connector passes through the hole's inside.
                let mid = [0.5 * (c[0][0] + c[1][0]), 0.5 * (c[0][1] + c[1][1])];
                assert!(!(mid[0] > lo[0] && mid[0] < hi[0] && mid[1] > lo[1] && mid[1] < hi[1]), "{c:?}");
            }
            let area = 0.5 * norm(newell_normal(&half.loops.outer.points));
            assert!(area > 0.1, "{area}");
        }
        // The two halves tile the face: their areas sum to the P's (7.75 − 1.5).
        let total: f64 = halves.iter().map(|h| newell_normal(&h.loops.outer.points)[2] * 0.5).sum();
        assert!((total - 6.25).abs() < 1e-9, "{total}");
    }

    /// Two round holes in a square: the hole nearest the outer loop is
    /// split off (the left one, ties by order), one half keeps the other
    /// hole, the other has none; the connectors are the halves' shared
    /// edges, each kept by both, and the halves' areas (holes subtracted)
    /// sum to the face's.
    #[test]
    fn a_square_with_two_holes_splits_into_a_half_with_one_hole_and_a_disk() {
        let cycle = fixtures::square_with_round_holes(&[([-0.45, 0.0], 0.3), ([0.45, 0.0], 0.3)]);
        let halves = split_annulus(&cycle, &[], &PairingOptions::default()).unwrap();
        let mut holes: Vec<usize> = halves.iter().map(|h| h.loops.holes.len()).collect();
        holes.sort_unstable();
        assert_eq!(holes, vec![0, 1]);
        for c in &halves[0].connectors {
            let back = [c[1], c[0]];
            assert!(halves[1].connectors.contains(&back), "{c:?} is not shared");
        }
        let area = |h: &AnnulusHalf| {
            0.5 * newell_normal(&h.loops.outer.points)[2]
                + h.loops.holes.iter().map(|l| 0.5 * newell_normal(&l.points)[2]).sum::<f64>()
        };
        let face = 4.0 - 2.0 * 0.5 * 48.0 * 0.09 * (2.0 * PI / 48.0).sin();
        let total: f64 = halves.iter().map(area).sum();
        assert!((total - face).abs() < 1e-9, "{total} vs {face}");
    }

    /// Only annuli get the ring.
    #[test]
    fn a_cycle_without_exactly_one_hole_gets_no_ring() {
        assert!(pair_ring(&fixtures::house(), &PairingOptions::default()).is_none());
    }
}
