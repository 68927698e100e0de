//! Initial segmentation of a cycle's loops (spec §1, paper §3.1.1): corners
//! where the curve turns sharply, a curvature-and-arc-length fallback for
//! loops with too few corners, near-linear refinement, and the joining of
//! holes to the outer loop by shortest straight connectors.

use super::cost::{initial_direction, pair_cost, segment_shapes};
use super::polyline::{dist, point_segment_distance, split_index, sub_polyline, turning_angle, P3};
use super::{CycleSurface, PairingOptions};

/// One loop cut into segments: the points (closed) and the segment starts,
/// ascending, with a flag per segment for connectors that must not be split.
#[derive(Clone, Debug, PartialEq)]
pub struct SegmentedLoop {
    /// The closed polyline.
    pub points: Vec<P3>,
    /// Ascending start index of each segment.
    pub starts: Vec<usize>,
    /// Per segment: a connector (never split).
    pub unsplittable: Vec<bool>,
}

impl SegmentedLoop {
    /// The open polyline of each segment, in order.
    pub fn segment_polylines(&self) -> Vec<Vec<P3>> {
        let k = self.starts.len();
        (0..k).map(|s| sub_polyline(&self.points, self.starts[s], self.starts[(s + 1) % k])).collect()
    }
}

/// How a loop's initial segmentation was found.
#[derive(Clone, Debug, PartialEq)]
pub struct LoopSegmentation {
    /// The loop with its segments.
    pub segmented: SegmentedLoop,
    /// Corners found (turn plus fixed points), before any fallback.
    pub corners: usize,
    /// Whether the curvature-maxima-plus-arc-length fallback was used.
    pub fallback: bool,
}

/// Segments one closed loop (already densified): corners where the turn over
/// ±`window` samples exceeds the corner angle and is a local maximum, plus the
/// `fixed` points; the fallback below `min_corners`; then near-linear splits.
pub fn segment_loop(points: Vec<P3>, fixed: &[usize], opts: &PairingOptions) -> LoopSegmentation {
    let n = points.len();
    let w = opts.corner_window;
    let turn: Vec<f64> = (0..n).map(|i| turning_angle(&points, i, w)).collect();
    let limit = opts.corner_angle.to_radians();
    let is_local_max = |i: usize, reach: usize| {
        (1..=reach).all(|d| {
            let (a, b) = (turn[(i + n - d) % n], turn[(i + d) % n]);
            // Strict on one side so a plateau gives one corner.
            turn[i] > a && turn[i] >= b
        })
    };
    let mut starts: Vec<usize> = (0..n).filter(|&i| turn[i] > limit && is_local_max(i, w)).collect();
    starts.extend_from_slice(fixed);
    starts.sort_unstable();
    starts.dedup();
    let corners = starts.len();
    let fallback = corners < opts.min_corners;
    if fallback {
        // Curvature maxima: clear local maxima of the turn well above its median.
        let mut sorted = turn.clone();
        sorted.sort_by(f64::total_cmp);
        let median = sorted[n / 2];
        let reach = (n / 16).max(w);
        for (i, &ti) in turn.iter().enumerate() {
            let clear = ti > 2.0 * median && ti > opts.fallback_min_turn.to_radians();
            let near = starts.iter().any(|&s| cyclic_gap(s, i, n) <= 2 * w);
            if clear && !near && is_local_max(i, reach) {
                starts.push(i);
            }
        }
        starts.sort_unstable();
        // Arc length: halve the longest segment until there are four.
        if starts.is_empty() {
            starts.push(0);
        }
        while starts.len() < 4 {
            let Some((s, idx)) = longest_split(&points, &starts) else { break };
            let _ = s;
            starts.push(idx);
            starts.sort_unstable();
        }
    }
    let mut segmented = SegmentedLoop { unsplittable: vec![false; starts.len()], points, starts };
    refine_near_linear(&mut segmented, opts);
    LoopSegmentation { segmented, corners, fallback }
}

/// Steps between two indices of a loop of `n`, the shorter way round.
fn cyclic_gap(a: usize, b: usize, n: usize) -> usize {
    let d = a.abs_diff(b);
    d.min(n - d)
}

/// The midpoint split of the longest segment (by arc length): its position
/// and the new start index.
fn longest_split(points: &[P3], starts: &[usize]) -> Option<(usize, usize)> {
    let k = starts.len();
    let mut order: Vec<(f64, usize)> = (0..k)
        .map(|s| (super::polyline::open_length(&sub_polyline(points, starts[s], starts[(s + 1) % k])), s))
        .collect();
    order.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
    order.into_iter().find_map(|(_, s)| split_index(points, starts[s], starts[(s + 1) % k], 0.5).map(|i| (s, i)))
}

/// Splits segments until each is near-linear (spec §1): the largest
/// distance to its chord at most τ·|chord| and its total turn at most the
/// limit; a segment is split at its point farthest from the chord.
pub fn refine_near_linear(lp: &mut SegmentedLoop, opts: &PairingOptions) {
    for _ in 0..4 * lp.points.len() {
        let k = lp.starts.len();
        let mut split = None;
        for s in 0..k {
            if lp.unsplittable[s] {
                continue;
            }
            let idx = super::polyline::cyclic_range(lp.points.len(), lp.starts[s], lp.starts[(s + 1) % k]);
            if idx.len() < 3 {
                continue;
            }
            let (a, b) = (lp.points[idx[0]], lp.points[idx[idx.len() - 1]]);
            let chord = dist(a, b);
            let (far_k, far_d) = (1..idx.len() - 1)
                .map(|m| (m, point_segment_distance(lp.points[idx[m]], a, b)))
                .fold((0, -1.0), |best, x| if x.1 > best.1 { x } else { best });
            let turn: f64 = (1..idx.len() - 1)
                .map(|m| super::polyline::angle(
                    super::polyline::sub(lp.points[idx[m]], lp.points[idx[m - 1]]),
                    super::polyline::sub(lp.points[idx[m + 1]], lp.points[idx[m]]),
                ))
                .sum();
            if far_d > opts.near_linear_tau * chord || turn > opts.near_linear_turn.to_radians() {
                let at = if far_d > 0.0 && chord > 0.0 {
                    idx[far_k]
                } else {
                    match split_index(&lp.points, idx[0], idx[idx.len() - 1], 0.5) {
                        Some(i) => i,
                        None => continue,
                    }
                };
                split = Some(at);
                break;
            }
        }
        let Some(at) = split else { return };
        lp.starts.push(at);
        lp.starts.sort_unstable();
        lp.unsplittable = vec![false; lp.starts.len()];
    }
}

/// Joins `hole` to `outer` (spec §1): over the pairs of a splittable outer
/// segment and a hole segment, the least cost pair; its shortest straight
/// connector (closest samples) becomes two unsplittable segments, traversed
/// once each way. Returns the joined loop and the connector's length.
pub fn join_hole(
    outer: &SegmentedLoop,
    hole: &SegmentedLoop,
    diameter: f64,
    cycle_normal: P3,
    opts: &PairingOptions,
    surface: Option<&CycleSurface>,
) -> SegmentedLoop {
    let outer_lines = outer.segment_polylines();
    let hole_lines = hole.segment_polylines();
    let at = |p: P3| surface.and_then(|s| s.bridge_normal_at(p));
    let normal_at: Option<super::cost::NormalAt<'_>> = surface.map(|_| &at as super::cost::NormalAt<'_>);
    let so = segment_shapes(&outer_lines, diameter, cycle_normal, opts.samples, normal_at);
    let sh = segment_shapes(&hole_lines, diameter, cycle_normal, opts.samples, normal_at);
    let to: Vec<P3> = (0..so.len()).map(|i| initial_direction(&so, i, opts)).collect();
    let th: Vec<P3> = (0..sh.len()).map(|i| initial_direction(&sh, i, opts)).collect();
    let mut best: Option<(f64, usize, usize)> = None;
    for i in (0..so.len()).filter(|&i| !outer.unsplittable[i]) {
        for j in 0..sh.len() {
            let c = pair_cost(&so[i], to[i], &sh[j], th[j], opts).total;
            if best.is_none_or(|b| c < b.0) {
                best = Some((c, i, j));
            }
        }
    }
    let (_, si, sj) = best.unwrap_or((0.0, 0, 0));
    // Closest pair of samples of the two segments.
    let ko = outer.starts.len();
    let kh = hole.starts.len();
    let oi = super::polyline::cyclic_range(outer.points.len(), outer.starts[si], outer.starts[(si + 1) % ko]);
    let hj = super::polyline::cyclic_range(hole.points.len(), hole.starts[sj], hole.starts[(sj + 1) % kh]);
    let mut pick = (f64::INFINITY, oi[0], hj[0]);
    for &a in &oi {
        for &b in &hj {
            let d = dist(outer.points[a], hole.points[b]);
            if d < pick.0 {
                pick = (d, a, b);
            }
        }
    }
    let (_, ia, ib) = pick;
    splice(outer, hole, ia, ib)
}

/// The joined loop: outer up to `ia`, the connector to hole point `ib`, the
/// whole hole back to `ib`, the connector back to `ia`, the rest of outer.
fn splice(outer: &SegmentedLoop, hole: &SegmentedLoop, ia: usize, ib: usize) -> SegmentedLoop {
    let (m, h) = (outer.points.len(), hole.points.len());
    let mut points = outer.points[..=ia].to_vec();
    points.extend((0..=h).map(|k| hole.points[(ib + k) % h]));
    points.extend_from_slice(&outer.points[ia..]);
    let _ = m;
    let mut marked: Vec<(usize, bool)> = Vec::new();
    for (s, &x) in outer.starts.iter().enumerate() {
        let y = if x < ia { x } else { x + h + 2 };
        marked.push((y, outer.unsplittable[s]));
    }
    for (s, &x) in hole.starts.iter().enumerate() {
        marked.push((ia + 1 + (x + h - ib) % h, hole.unsplittable[s]));
    }
    marked.push((ia, true)); // connector there
    marked.push((ia + 1 + h, true)); // connector back
    marked.push((ia + 1, false)); // the hole from the connector's end
    marked.push((ia + h + 2, false)); // the outer loop from the connector's end
    // One entry per start; a connector flag wins over the loop's own.
    marked.sort_by(|a, b| a.0.cmp(&b.0).then(b.1.cmp(&a.1)));
    marked.dedup_by_key(|e| e.0);
    SegmentedLoop {
        points,
        starts: marked.iter().map(|e| e.0).collect(),
        unsplittable: marked.iter().map(|e| e.1).collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::curvenet::polyline::{angle, densify_closed, open_length, sub};

    #[test]
    fn a_square_has_four_corners_and_a_fixed_point_adds_a_fifth() {
        let o = PairingOptions::default();
        let sq = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
        let (pts, idx) = densify_closed(&sq, 0.01);
        let s = segment_loop(pts.clone(), &[], &o);
        assert_eq!((s.segmented.starts.clone(), s.corners, s.fallback), (idx.clone(), 4, false));
        let s = segment_loop(pts, &[idx[1] + 30], &o);
        assert_eq!(s.segmented.starts.len(), 5);
        assert!(s.segmented.starts.contains(&(idx[1] + 30)));
    }

    #[test]
    fn a_half_disc_falls_back_and_ends_near_linear() {
        let o = PairingOptions::default();
        let mut d: Vec<P3> = (0..=60).map(|k| {
            let a = std::f64::consts::PI * k as f64 / 60.0;
            [a.cos(), a.sin(), 0.0]
        }).collect();
        d.push([0.0, 0.0, 0.0]);
        let (pts, _) = densify_closed(&d, 0.01);
        let s = segment_loop(pts, &[], &o);
        assert!(s.fallback && s.corners == 2, "{:?}", (s.corners, s.fallback));
        let lines = s.segmented.segment_polylines();
        assert!(lines.len() >= 4);
        for l in &lines {
            let (a, b) = (l[0], l[l.len() - 1]);
            let far = l.iter().map(|p| point_segment_distance(*p, a, b)).fold(0.0, f64::max);
            let turn: f64 = l.windows(3).map(|w| angle(sub(w[1], w[0]), sub(w[2], w[1]))).sum();
            assert!(far <= o.near_linear_tau * dist(a, b) + 1e-12 && turn <= o.near_linear_turn.to_radians() + 1e-9);
            assert!(open_length(l) > 0.0);
        }
    }
}
