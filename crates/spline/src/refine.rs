//! Boehm knot insertion and uniform h-refinement (spec §9.6): single knots
//! inserted in every span keep the spline C² and its shape unchanged.

use crate::curve::BSplineCurve;
use crate::error::{Result, SplineError};
use crate::knots::KnotVector;
use crate::surface::BSplinePatch;
use crate::vec3::{add, scale, Point3};

/// Inserts the knot `u` once (Boehm): returns the new knots and the
/// `n + 1` new control points. `u` must lie inside the domain and appear
/// fewer than `degree` times already.
pub fn insert_knot(
    knots: &KnotVector,
    control: &[Point3],
    u: f64,
) -> Result<(KnotVector, Vec<Point3>)> {
    let p = knots.degree();
    let (a, b) = knots.domain();
    if !(u > a && u < b) {
        return Err(SplineError::Refine(format!(
            "knot {u} is not inside the domain ({a}, {b})"
        )));
    }
    let mult = knots.multiplicity(u);
    if mult >= p {
        return Err(SplineError::Refine(format!(
            "knot {u} already appears {mult} times (degree {p})"
        )));
    }
    if control.len() != knots.num_control_points() {
        return Err(SplineError::Shape(format!(
            "knot insertion: {} control points for {} basis functions",
            control.len(),
            knots.num_control_points()
        )));
    }
    let k = knots.find_span(u);
    let kn = knots.knots();
    let n = control.len();
    let mut out = Vec::with_capacity(n + 1);
    for i in 0..=n {
        let q = if i + p <= k {
            control[i]
        } else if i > k - mult {
            control[i - 1]
        } else {
            let alpha = (u - kn[i]) / (kn[i + p] - kn[i]);
            add(scale(control[i], alpha), scale(control[i - 1], 1.0 - alpha))
        };
        out.push(q);
    }
    Ok((knots.with_inserted(k, u), out))
}

/// The knots that split every span of `knots` into `r` equal spans.
fn uniform_split_knots(knots: &KnotVector, r: usize) -> Vec<f64> {
    let bp = knots.breakpoints();
    let mut out = Vec::new();
    for w in bp.windows(2) {
        for k in 1..r {
            out.push(w[0] + (w[1] - w[0]) * k as f64 / r as f64);
        }
    }
    out
}

fn check_factor(r: usize) -> Result<()> {
    if r == 0 {
        return Err(SplineError::Refine(
            "refinement factor must be at least 1, got 0".into(),
        ));
    }
    Ok(())
}

/// Splits every span of `curve` into `r` equal spans by knot insertion.
pub fn refine_curve(curve: &BSplineCurve, r: usize) -> Result<BSplineCurve> {
    check_factor(r)?;
    let mut knots = curve.knots().clone();
    let mut control = curve.control_points().to_vec();
    for u in uniform_split_knots(curve.knots(), r) {
        (knots, control) = insert_knot(&knots, &control, u)?;
    }
    BSplineCurve::new(knots, control)
}

/// Inserts `s_knots` in s and `t_knots` in t (each once, in order).
pub fn insert_knots_patch(
    patch: &BSplinePatch,
    s_knots: &[f64],
    t_knots: &[f64],
) -> Result<BSplinePatch> {
    let (ns, nt) = (patch.n_s(), patch.n_t());
    // Rows (fixed j) refined in s.
    let mut ks = patch.knots_s().clone();
    let mut rows: Vec<Vec<Point3>> = (0..nt)
        .map(|j| (0..ns).map(|i| patch.control_point(i, j)).collect())
        .collect();
    for &u in s_knots {
        let mut new_ks = ks.clone();
        for row in rows.iter_mut() {
            let (k2, r2) = insert_knot(&ks, row, u)?;
            *row = r2;
            new_ks = k2;
        }
        ks = new_ks;
    }
    let ns2 = ks.num_control_points();
    // Columns (fixed i) refined in t.
    let mut kt = patch.knots_t().clone();
    let mut cols: Vec<Vec<Point3>> = (0..ns2)
        .map(|i| rows.iter().map(|row| row[i]).collect())
        .collect();
    for &u in t_knots {
        let mut new_kt = kt.clone();
        for col in cols.iter_mut() {
            let (k2, c2) = insert_knot(&kt, col, u)?;
            *col = c2;
            new_kt = k2;
        }
        kt = new_kt;
    }
    let nt2 = kt.num_control_points();
    let mut net = Vec::with_capacity(ns2 * nt2);
    for j in 0..nt2 {
        for col in &cols {
            net.push(col[j]);
        }
    }
    BSplinePatch::new(ks, kt, net)
}

/// Uniform h-refinement: every span in s and in t split into `r` equal
/// spans (`r − 1` single knots each), the same for every patch so that
/// interfaces stay conforming. `r = 1` returns the patch unchanged.
pub fn refine(patch: &BSplinePatch, r: usize) -> Result<BSplinePatch> {
    check_factor(r)?;
    insert_knots_patch(
        patch,
        &uniform_split_knots(patch.knots_s(), r),
        &uniform_split_knots(patch.knots_t(), r),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vec3::dist;

    /// A wavy patch with `spans` uniform spans in each direction.
    fn wavy(spans: usize) -> BSplinePatch {
        let kv = KnotVector::clamped_uniform(3, spans).unwrap();
        let n = kv.num_control_points();
        let mut net = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let (x, y) = (i as f64 / (n - 1) as f64, j as f64 / (n - 1) as f64);
                net.push([
                    x + 0.1 * y * y,
                    y,
                    (3.0 * x).sin() * (2.0 * y).cos() + ((i * 7 + j * 3) % 5) as f64 * 0.05,
                ]);
            }
        }
        BSplinePatch::new(kv.clone(), kv, net).unwrap()
    }

    #[test]
    fn paper_refinement_counts() {
        // §9.6: --segments 1 --refine 8, 4 --refine 2, 3 --refine 4.
        for (spans, r, want) in [(1, 8, 11), (4, 2, 11), (3, 4, 15)] {
            let p = refine(&wavy(spans), r).unwrap();
            assert_eq!((p.n_s(), p.n_t()), (want, want), "spans {spans} refine {r}");
            assert_eq!(p.knots_s().num_spans(), spans * r);
            assert!(p.knots_s().breakpoints()[1..spans * r]
                .iter()
                .all(|&k| p.knots_s().multiplicity(k) == 1));
        }
    }

    #[test]
    fn refinement_keeps_the_surface() {
        for (spans, r) in [(1, 8), (4, 2), (3, 4), (2, 3)] {
            let p = wavy(spans);
            let q = refine(&p, r).unwrap();
            let mut worst: f64 = 0.0;
            for k in 0..=37 {
                for l in 0..=37 {
                    let (s, t) = (k as f64 / 37.0, l as f64 / 37.0);
                    worst = worst.max(dist(p.eval(s, t), q.eval(s, t)));
                }
            }
            assert!(worst < 1e-12, "spans {spans} r {r}: {worst:e}");
        }
        assert_eq!(refine(&wavy(2), 1).unwrap(), wavy(2));
    }

    #[test]
    fn curve_refinement_and_errors() {
        let kv = KnotVector::clamped_uniform(3, 2).unwrap();
        let c = BSplineCurve::new(
            kv.clone(),
            vec![
                [0.0; 3],
                [1.0, 2.0, 0.0],
                [2.0, -1.0, 1.0],
                [3.0, 0.0, 0.0],
                [4.0, 1.0, 2.0],
            ],
        )
        .unwrap();
        let f = refine_curve(&c, 3).unwrap();
        assert_eq!(f.control_points().len(), 9);
        for k in 0..=50 {
            let u = k as f64 / 50.0;
            assert!(dist(c.eval(u), f.eval(u)) < 1e-13);
        }
        assert!(refine_curve(&c, 0).is_err());
        assert!(insert_knot(&kv, c.control_points(), 1.5).is_err());
        let (k1, p1) = insert_knot(&kv, c.control_points(), 0.5).unwrap();
        let (k2, p2) = insert_knot(&k1, &p1, 0.5).unwrap();
        let e = insert_knot(&k2, &p2, 0.5).unwrap_err().to_string();
        assert!(e.contains("3 times"), "{e}");
    }
}
