//! Cusps: CAD corners where two curves of a face leave in the same direction
//! (an interior angle near 0°, as where an arc meets its tangent line). The
//! face is a wedge there whose width grows like `κ s² / 2` at a distance `s`
//! from the corner (`κ` the curves' relative curvature). A quad between two
//! curve nodes at distance `s` is about `κ s / 2` as wide as it is long, so
//! if the first curve nodes sit close to the corner, the quads just beyond
//! the corner quad are slivers. The quad at the corner is poor whatever is
//! done (its corner angle is the CAD's); [`cusp_reaches`] says how far out
//! the first nodes must go for the next quads to be at least
//! [`MIN_WIDTH_RATIO`] as wide as long, and [`crate::curves::curve_mesh`] spaces the
//! curves' ends accordingly.

use geometry::vec3::{self, Vec3};
use geometry::{CurveId, Model};

/// Two curves leaving a corner within this angle (degrees) of each other
/// make a cusp.
pub const CUSP_DEG: f64 = 10.0;

/// Width over length the first quads beyond a cusp should reach. 0.2
/// rather than 0.1: on the 26 shared models the worst quad of the five
/// models with cusps rises (i13o_s6 0.097 → 0.164, i12o_s5 0.108 → 0.149,
/// i16o_s9 0.117 → 0.188, i14o_s7 0.105 → 0.124, i03o_m3 0.097 → 0.117) and
/// the irregular share falls on three of them (BENCHMARKS.md, "Cusps again").
pub const MIN_WIDTH_RATIO: f64 = 0.2;

/// Distances along the curves at which the wedge width is measured: shares
/// of the shorter curve's length, growing geometrically up to a half.
const PROBES: usize = 24;

/// Per curve, `[at its start, at its end]`: the distance from the corner
/// that its first curve node should keep when the corner is a cusp in some
/// face (0 where it is not). Degenerate curves and closed curves meeting
/// themselves are ignored.
pub fn cusp_reaches(model: &Model) -> Vec<[f64; 2]> {
    let mut out = vec![[0.0; 2]; model.curves.len()];
    for face in &model.faces {
        for lp in &face.loops {
            let n = lp.uses.len();
            if n < 2 {
                continue;
            }
            for k in 0..n {
                let (a, b) = (&lp.uses[k], &lp.uses[(k + 1) % n]);
                if a.curve == b.curve {
                    continue;
                }
                // a arrives at the corner (its end in the loop's direction), b leaves it
                let a_end = if a.forward { 1 } else { 0 };
                let b_end = if b.forward { 0 } else { 1 };
                let Some(reach) = reach(model, (a.curve, a_end), (b.curve, b_end)) else {
                    continue;
                };
                let ra = &mut out[a.curve.idx()][a_end];
                *ra = f64::max(*ra, reach);
                let rb = &mut out[b.curve.idx()][b_end];
                *rb = f64::max(*rb, reach);
            }
        }
    }
    out
}

/// The point of curve `c` a share `share` of its parameter range away from
/// its end `end` (0: start, 1: end): about that share of its length.
fn from_end(model: &Model, c: CurveId, end: usize, share: f64) -> Option<Vec3> {
    let ce = &model.curves[c.idx()];
    let g = ce.geom.as_ref()?;
    let (t0, t1) = ce.range;
    let t = if end == 0 {
        t0 + share * (t1 - t0)
    } else {
        t1 - share * (t1 - t0)
    };
    let p = g.eval(t);
    p.iter().all(|x| x.is_finite()).then_some(p)
}

/// The distance the first nodes must keep from the corner where `a` and `b`
/// (each with the end at that corner) meet, when they make a cusp.
fn reach(model: &Model, a: (CurveId, usize), b: (CurveId, usize)) -> Option<f64> {
    let (ca, cb) = (&model.curves[a.0.idx()], &model.curves[b.0.idx()]);
    if ca.degenerate || cb.degenerate {
        return None;
    }
    let la = geometry::slivers::curve_length(model, a.0)?;
    let lb = geometry::slivers::curve_length(model, b.0)?;
    if !(la > 0.0 && lb > 0.0) {
        return None;
    }
    let corner = from_end(model, a.0, a.1, 0.0)?;
    // leaving directions, on short chords
    let short = 1e-3 * la.min(lb);
    let da = vec3::normalize(vec3::sub(from_end(model, a.0, a.1, short / la)?, corner))?;
    let db = vec3::normalize(vec3::sub(from_end(model, b.0, b.1, short / lb)?, corner))?;
    if vec3::dot(da, db) < CUSP_DEG.to_radians().cos() {
        return None;
    }
    // the first distance where the wedge is MIN_WIDTH_RATIO as wide as far
    let longest = 0.5 * la.min(lb);
    for i in 0..=PROBES {
        let s = longest * (0.01f64).powf(1.0 - i as f64 / PROBES as f64);
        let pa = from_end(model, a.0, a.1, s / la)?;
        let pb = from_end(model, b.0, b.1, s / lb)?;
        if vec3::dist(pa, pb) >= MIN_WIDTH_RATIO * s {
            return Some(s);
        }
    }
    Some(longest)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_circle_tangent_to_a_line_asks_for_two_fifths_of_its_radius() {
        // the wedge between y = 0 and the circle of radius R about (0, R):
        // width s² / 2R at distance s, a fifth of s at s = 2R / 5
        let model = geometry::primitives::cusp(7.0, 0.0);
        let r = cusp_reaches(&model);
        let at_origin = [r[0][0], r[2][0]];
        for reach in at_origin {
            assert!(reach > 0.36 * 7.0 && reach < 0.5 * 7.0, "{r:?}");
        }
        // the 90° corner at (R, 0) is no cusp
        assert_eq!(r[0][1], 0.0, "{r:?}");
        assert_eq!(r[1][0], 0.0, "{r:?}");
    }

    #[test]
    fn the_final_curve_plan_keeps_the_first_nodes_away_from_a_cusp() {
        use crate::curves::curve_mesh::{discretize_all, plan_curves_sized, plan_final_curves};
        let model = geometry::primitives::cusp(7.0, 0.0);
        // a size map of 0.5 along the line and the arc, 3 elsewhere
        let half_pi = std::f64::consts::FRAC_PI_2;
        let sizes = vec![
            Some(vec![[0.0, 0.5], [1.0, 0.5]]),
            None,
            Some(vec![[-half_pi, 0.5], [0.0, 0.5]]),
        ];
        let first = |cms: &[crate::curves::curve_mesh::CurveMesh], c: usize| {
            geometry::vec3::norm(cms[c].points[1])
        };
        let plain = discretize_all(&model, &plan_curves_sized(&model, 3.0, &sizes));
        let kept = discretize_all(&model, &plan_final_curves(&model, 3.0, &sizes));
        for c in [0, 2] {
            assert!(first(&plain, c) < 0.6, "{}", first(&plain, c));
            // two fifths of the radius: where the wedge is a fifth as wide as long
            assert!(first(&kept, c) > 0.36 * 7.0, "{}", first(&kept, c));
        }
    }
}
