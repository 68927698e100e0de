//! The exact B-spline form of the bilinearly blended Coons patch (spec §9.4).
//!
//! P_ij = (1−t̂_j) c0_i + t̂_j c1_i + (1−ŝ_i) d0_j + ŝ_i d1_j
//!        − [(1−ŝ_i)(1−t̂_j) P00 + ŝ_i(1−t̂_j) P10 + (1−ŝ_i) t̂_j P01 + ŝ_i t̂_j P11]
//! with ŝ, t̂ the Greville abscissae mapped to [0, 1]: B-splines reproduce
//! linear functions through the Greville abscissae, so the linear blends are
//! exact and the tensor patch equals the Coons patch. The boundary rows and
//! columns are copied from the curves, so they are bit-identical to them.

use crate::curve::BSplineCurve;
use crate::error::{Result, SplineError};
use crate::surface::BSplinePatch;
use crate::vec3::{dist, Point3};

/// Relative tolerance on knot compatibility (times the domain length).
const KNOT_TOL: f64 = 1e-12;
/// Relative tolerance on corner agreement (times the boundary's size).
const CORNER_TOL: f64 = 1e-9;

/// The Coons patch of four boundary curves: `bottom` = S(s, 0) and `top` =
/// S(s, 1) on the same s-knots, `left` = S(0, t) and `right` = S(1, t) on
/// the same t-knots, their end points meeting at the four corners. Errors
/// when the knots differ or a corner does not meet.
pub fn coons_patch(
    bottom: &BSplineCurve,
    top: &BSplineCurve,
    left: &BSplineCurve,
    right: &BSplineCurve,
) -> Result<BSplinePatch> {
    let ks = bottom.knots();
    let kt = left.knots();
    if !ks.compatible(top.knots(), KNOT_TOL) {
        return Err(SplineError::Coons(format!(
            "bottom and top have different s-knots ({} and {} knots)",
            ks.knots().len(),
            top.knots().knots().len()
        )));
    }
    if !kt.compatible(right.knots(), KNOT_TOL) {
        return Err(SplineError::Coons(format!(
            "left and right have different t-knots ({} and {} knots)",
            kt.knots().len(),
            right.knots().knots().len()
        )));
    }
    let c0 = bottom.control_points();
    let c1 = top.control_points();
    let d0 = left.control_points();
    let d1 = right.control_points();
    let (ns, nt) = (c0.len(), d0.len());
    let size = c0
        .iter()
        .chain(c1)
        .chain(d0)
        .chain(d1)
        .map(|p| dist(*p, c0[0]))
        .fold(0.0, f64::max)
        .max(1.0);
    let corners = [
        ("bottom-left", c0[0], d0[0]),
        ("bottom-right", c0[ns - 1], d1[0]),
        ("top-left", c1[0], d0[nt - 1]),
        ("top-right", c1[ns - 1], d1[nt - 1]),
    ];
    for (name, a, b) in corners {
        let gap = dist(a, b);
        if !(gap <= CORNER_TOL * size) {
            return Err(SplineError::Coons(format!(
                "{name} corner: the curves' ends are {gap:.3e} apart"
            )));
        }
    }
    let unit = |g: Vec<f64>| -> Vec<f64> {
        let (a, b) = (g[0], g[g.len() - 1]);
        g.iter().map(|x| (x - a) / (b - a)).collect()
    };
    let sh = unit(ks.greville());
    let th = unit(kt.greville());
    let (p00, p10, p01, p11) = (c0[0], c0[ns - 1], c1[0], c1[ns - 1]);
    let mut net: Vec<Point3> = Vec::with_capacity(ns * nt);
    for j in 0..nt {
        for i in 0..ns {
            let p = if j == 0 {
                c0[i]
            } else if j == nt - 1 {
                c1[i]
            } else if i == 0 {
                d0[j]
            } else if i == ns - 1 {
                d1[j]
            } else {
                let (s, t) = (sh[i], th[j]);
                let mut x = [0.0; 3];
                for (k, xk) in x.iter_mut().enumerate() {
                    *xk = (1.0 - t) * c0[i][k] + t * c1[i][k] + (1.0 - s) * d0[j][k] + s * d1[j][k]
                        - ((1.0 - s) * (1.0 - t) * p00[k]
                            + s * (1.0 - t) * p10[k]
                            + (1.0 - s) * t * p01[k]
                            + s * t * p11[k]);
                }
                x
            };
            net.push(p);
        }
    }
    BSplinePatch::new(ks.clone(), kt.clone(), net)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::curve::fit_curve;
    use crate::vec3::{add, scale};

    fn fit(f: impl Fn(f64) -> Point3, spans: usize) -> BSplineCurve {
        let m = 60;
        let params: Vec<f64> = (0..m).map(|i| i as f64 / (m - 1) as f64).collect();
        let pts: Vec<Point3> = params.iter().map(|&t| f(t)).collect();
        fit_curve(&pts, &params, spans).unwrap()
    }

    #[test]
    fn boundaries_are_reproduced_exactly() {
        // A curved quad: four arcs meeting at the corners of a warped square.
        let bottom = |s: f64| [s, 0.2 * (3.0 * s).sin(), 0.1 * s * s];
        let top = |s: f64| [s + 0.1 * s * (1.0 - s), 1.0 + 0.1 * s, 0.3 * s];
        let left = |t: f64| [0.05 * (std::f64::consts::PI * t).sin(), t, 0.0];
        let right = |t: f64| {
            let b = bottom(1.0);
            let e = top(1.0);
            let w = 0.2 * (std::f64::consts::PI * t).sin();
            [
                b[0] + (e[0] - b[0]) * t + w,
                b[1] + (e[1] - b[1]) * t,
                b[2] + (e[2] - b[2]) * t,
            ]
        };
        for spans in [1, 3, 4] {
            let (cb, ct, cl, cr) = (
                fit(bottom, spans),
                fit(top, spans),
                fit(left, 2),
                fit(right, 2),
            );
            let patch = coons_patch(&cb, &ct, &cl, &cr).unwrap();
            assert_eq!((patch.n_s(), patch.n_t()), (spans + 3, 5));
            let mut worst: f64 = 0.0;
            for k in 0..=100 {
                let u = k as f64 / 100.0;
                worst = worst
                    .max(dist(patch.eval(u, 0.0), cb.eval(u)))
                    .max(dist(patch.eval(u, 1.0), ct.eval(u)))
                    .max(dist(patch.eval(0.0, u), cl.eval(u)))
                    .max(dist(patch.eval(1.0, u), cr.eval(u)));
            }
            assert!(worst < 1e-12, "spans {spans}: boundary error {worst:e}");
        }
    }

    #[test]
    fn interior_equals_continuous_coons_formula() {
        // The B-spline patch is the Coons patch itself, not an approximation.
        let cb = fit(|s| [s, 0.0, s * s], 2);
        let ct = fit(|s| [s, 1.0, 0.5 * s * s * s + 0.5 * s], 2);
        let cl = fit(|t| [0.0, t, 0.0], 3);
        let cr = fit(|t| [1.0, t, 1.0 - 0.5 * t * t * (1.0 - t)], 3);
        let patch = coons_patch(&cb, &ct, &cl, &cr).unwrap();
        let (p00, p10, p01, p11) = (cb.eval(0.0), cb.eval(1.0), ct.eval(0.0), ct.eval(1.0));
        for (s, t) in [(0.2, 0.3), (0.5, 0.5), (0.9, 0.1), (0.37, 0.81)] {
            let mut want = [0.0; 3];
            for k in 0..3 {
                want[k] = (1.0 - t) * cb.eval(s)[k]
                    + t * ct.eval(s)[k]
                    + (1.0 - s) * cl.eval(t)[k]
                    + s * cr.eval(t)[k]
                    - ((1.0 - s) * (1.0 - t) * p00[k]
                        + s * (1.0 - t) * p10[k]
                        + (1.0 - s) * t * p01[k]
                        + s * t * p11[k]);
            }
            assert!(dist(patch.eval(s, t), want) < 1e-12);
        }
    }

    #[test]
    fn four_lines_in_a_plane_give_the_bilinear_patch() {
        let (a, b, c, d) = (
            [0.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [0.5, 1.5, 0.0],
            [2.5, 1.0, 0.0],
        );
        let line =
            |p: Point3, q: Point3, spans| fit(move |u| add(scale(p, 1.0 - u), scale(q, u)), spans);
        let patch = coons_patch(
            &line(a, b, 3),
            &line(c, d, 3),
            &line(a, c, 4),
            &line(b, d, 4),
        )
        .unwrap();
        for k in 0..=10 {
            for l in 0..=10 {
                let (s, t) = (k as f64 / 10.0, l as f64 / 10.0);
                let mut want = [0.0; 3];
                for m in 0..3 {
                    want[m] = (1.0 - s) * (1.0 - t) * a[m]
                        + s * (1.0 - t) * b[m]
                        + (1.0 - s) * t * c[m]
                        + s * t * d[m];
                }
                assert!(dist(patch.eval(s, t), want) < 1e-12);
            }
        }
    }

    #[test]
    fn incompatible_boundaries_are_errors() {
        let cb = fit(|s| [s, 0.0, 0.0], 2);
        let ct = fit(|s| [s, 1.0, 0.0], 3);
        let cl = fit(|t| [0.0, t, 0.0], 2);
        let cr = fit(|t| [1.0, t, 0.0], 2);
        assert!(coons_patch(&cb, &ct, &cl, &cr)
            .unwrap_err()
            .to_string()
            .contains("s-knots"));
        let ct2 = fit(|s| [s, 1.2, 0.0], 2);
        let e = coons_patch(&cb, &ct2, &cl, &cr).unwrap_err().to_string();
        assert!(e.contains("top-left corner"), "{e}");
    }
}
