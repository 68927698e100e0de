//! Curve discretization: every CAD curve is meshed once, and every face that
//! uses it sees the same points, so faces meet with identical nodes.
//!
//! Resolution convention (quasi-structured spec §1.2): a curve gets `n ≥ 1`
//! *coarse* segments at spacing about `2h` (the triangulation works at that
//! spacing) and is stored with `2n + 1` points uniform in arc length; the
//! odd-indexed points are the coarse segments' midpoints, which the
//! triangle → quad split uses, so every node lands exactly on the CAD curve and
//! each curve ends up with `2n` mesh edges of length about `h`.

use geometry::vec3::{self, Vec3};
use geometry::{CurveId, Model};

/// Largest turning angle of the tangent along one coarse segment (radians).
/// Keeps small circles from being a 1- or 2-segment polygon in (u, v).
pub const MAX_TURN_PER_SEGMENT: f64 = std::f64::consts::FRAC_PI_2;

/// Samples used to measure arc length and turning of a curve.
const SAMPLES: usize = 160;

/// The discretization of one curve.
#[derive(Clone, Debug)]
pub struct CurveMesh {
    /// Number of coarse segments `n` (the curve has `2n` mesh edges).
    pub coarse: usize,
    /// `2n + 1` curve parameters, increasing from `range.0` to `range.1`.
    pub params: Vec<f64>,
    /// `2n + 1` points: `C(params[i])`; for a degenerate curve, its corner.
    pub points: Vec<Vec3>,
}

impl CurveMesh {
    /// Number of mesh edges on the curve (`2 * coarse`).
    pub fn num_edges(&self) -> usize {
        2 * self.coarse
    }
}

/// Arc length and total turning angle of a curve, with the cumulative length table.
struct Profile {
    ts: Vec<f64>,
    cum: Vec<f64>,
    turn: f64,
}

fn profile(model: &Model, c: CurveId) -> Profile {
    let ce = &model.curves[c.idx()];
    let (t0, t1) = ce.range;
    let ts: Vec<f64> = (0..=SAMPLES).map(|i| t0 + (t1 - t0) * i as f64 / SAMPLES as f64).collect();
    let pts: Vec<Vec3> = ts.iter().map(|&t| ce.eval(model, t)).collect();
    let mut cum = vec![0.0; ts.len()];
    let mut turn = 0.0;
    let mut prev_dir: Option<Vec3> = None;
    for i in 1..pts.len() {
        let d = vec3::sub(pts[i], pts[i - 1]);
        let l = vec3::norm(d);
        cum[i] = cum[i - 1] + if l.is_finite() { l } else { 0.0 };
        if let Some(dir) = vec3::normalize(d) {
            if let Some(p) = prev_dir {
                turn += vec3::dot(p, dir).clamp(-1.0, 1.0).acos();
            }
            prev_dir = Some(dir);
        }
    }
    Profile { ts, cum, turn }
}

/// Length of every curve (0 for degenerate curves), measured on a fine polyline.
pub fn curve_lengths(model: &Model) -> Vec<f64> {
    (0..model.curves.len())
        .map(|i| if model.curves[i].degenerate { 0.0 } else { *profile(model, CurveId(i as u32)).cum.last().unwrap_or(&0.0) })
        .collect()
}

/// Coarse segment counts for target final edge length `h`: about
/// `length / 2h`, at least 1, enough to keep the turning angle per segment
/// below [`MAX_TURN_PER_SEGMENT`], at least 3 for a closed curve, and enough
/// that every face loop has at least 3 coarse segments.
pub fn initial_counts(model: &Model, h: f64) -> Vec<usize> {
    let mut counts: Vec<usize> = (0..model.curves.len())
        .map(|i| {
            let ce = &model.curves[i];
            if ce.degenerate {
                return 1;
            }
            let p = profile(model, CurveId(i as u32));
            let len = *p.cum.last().unwrap_or(&0.0);
            let by_size = (len / (2.0 * h)).round();
            let by_turn = (p.turn / MAX_TURN_PER_SEGMENT).ceil();
            let mut n = by_size.max(by_turn).clamp(1.0, 1.0e6) as usize;
            if ce.start == ce.end {
                n = n.max(3);
            }
            n
        })
        .collect();
    let lengths = curve_lengths(model);
    for f in &model.faces {
        for l in &f.loops {
            loop {
                let total: usize = l.uses.iter().map(|u| counts[u.curve.idx()]).sum();
                if total >= 3 || l.uses.is_empty() {
                    break;
                }
                // refine the use with the longest coarse segments (first on ties)
                let mut best = 0;
                let mut best_len = f64::NEG_INFINITY;
                for (k, u) in l.uses.iter().enumerate() {
                    let seg = lengths[u.curve.idx()] / counts[u.curve.idx()] as f64;
                    if seg > best_len {
                        best_len = seg;
                        best = k;
                    }
                }
                counts[l.uses[best].curve.idx()] += 1;
            }
        }
    }
    counts
}

/// Discretizes curve `c` with `n` coarse segments: `2n + 1` points uniform in arc length.
pub fn discretize_curve(model: &Model, c: CurveId, n: usize) -> CurveMesh {
    let ce = &model.curves[c.idx()];
    let n = n.max(1);
    let m = 2 * n;
    let (t0, t1) = ce.range;
    let mut params = Vec::with_capacity(m + 1);
    let prof = if ce.degenerate { None } else { Some(profile(model, c)) };
    let total = prof.as_ref().map_or(0.0, |p| *p.cum.last().unwrap_or(&0.0));
    for i in 0..=m {
        let s = i as f64 / m as f64;
        let t = match &prof {
            Some(p) if total > 0.0 && i > 0 && i < m => {
                let target = s * total;
                // first sample with cum >= target
                let k = p.cum.partition_point(|&x| x < target).clamp(1, p.cum.len() - 1);
                let (a, b) = (p.cum[k - 1], p.cum[k]);
                let w = if b > a { (target - a) / (b - a) } else { 0.0 };
                p.ts[k - 1] + w * (p.ts[k] - p.ts[k - 1])
            }
            _ => t0 + s * (t1 - t0),
        };
        params.push(t);
    }
    params[0] = t0;
    params[m] = t1;
    let points = params
        .iter()
        .enumerate()
        .map(|(i, &t)| {
            if ce.degenerate || i == 0 {
                model.corners[ce.start.idx()].point
            } else if i == m {
                model.corners[ce.end.idx()].point
            } else {
                ce.eval(model, t)
            }
        })
        .collect();
    CurveMesh { coarse: n, params, points }
}

/// Discretizes every curve with the given coarse counts (in parallel; the
/// result does not depend on the thread count).
pub fn discretize_all(model: &Model, counts: &[usize]) -> Vec<CurveMesh> {
    use rayon::prelude::*;
    (0..model.curves.len()).into_par_iter().map(|i| discretize_curve(model, CurveId(i as u32), counts[i])).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use geometry::primitives;

    #[test]
    fn counts_follow_size_and_closure() {
        let m = primitives::square(4.0);
        let c = initial_counts(&m, 0.5);
        assert_eq!(c, vec![4; 4]);
        let cyl = primitives::cylinder(1.0, 3.0);
        let c = initial_counts(&cyl, 10.0);
        // closed circles: at least 3, and 4 by turning angle; the seam line: 1
        assert_eq!(c, vec![4, 4, 1]);
        let s = primitives::sphere(1.0);
        let c = initial_counts(&s, 0.1);
        assert_eq!(c[0], 1);
        assert_eq!(c[2], 1);
        assert!(c[1] >= 15);
    }

    #[test]
    fn points_are_uniform_in_arc_length_and_on_the_curve() {
        let m = primitives::cylinder(2.0, 1.0);
        let cm = discretize_curve(&m, CurveId(0), 5);
        assert_eq!(cm.params.len(), 11);
        assert_eq!(cm.points.len(), 11);
        let target = 2.0 * std::f64::consts::PI * 2.0 / 10.0;
        for i in 1..cm.points.len() {
            let arc = 2.0 * (cm.params[i] - cm.params[i - 1]);
            assert!((arc - target).abs() < 1e-3 * target, "arc {arc} vs {target}");
        }
        assert_eq!(cm.points[0], m.corners[0].point);
        assert_eq!(cm.points[10], m.corners[0].point);
        let s = primitives::sphere(1.0);
        let pole = discretize_curve(&s, CurveId(0), 2);
        assert!(pole.points.iter().all(|p| *p == s.corners[0].point));
    }
}
