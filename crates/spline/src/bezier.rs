//! Bézier extraction (every interior knot raised to multiplicity = degree)
//! and the Jacobian check at the 4 × 4 Gauss points of every Bézier element
//! (spec §14.5: (S_s × S_t)·n > 0 everywhere).

use crate::error::Result;
use crate::refine::insert_knots_patch;
use crate::surface::BSplinePatch;
use crate::vec3::{axpy, cross, dot, norm, Point3, Vec3};

/// One Bézier element of a patch: its parameter box and its
/// `(p + 1) × (q + 1)` control points, row-major with s fastest.
#[derive(Clone, Debug, PartialEq)]
pub struct BezierElement {
    /// The element's s interval in the patch's parameters.
    pub s_range: (f64, f64),
    /// The element's t interval in the patch's parameters.
    pub t_range: (f64, f64),
    /// Degrees (p in s, q in t).
    pub degree: (usize, usize),
    /// The Bézier control net, `control[b * (p + 1) + a]`.
    pub control: Vec<Point3>,
}

/// Bernstein polynomials of degree `n` at `x` and their derivatives.
fn bernstein(n: usize, x: f64) -> (Vec<f64>, Vec<f64>) {
    // de Casteljau-style build-up of B^k from B^(k-1).
    let mut b = vec![1.0];
    let mut prev = vec![1.0];
    for k in 1..=n {
        prev = b.clone();
        b = vec![0.0; k + 1];
        for i in 0..k {
            b[i] += (1.0 - x) * prev[i];
            b[i + 1] += x * prev[i];
        }
    }
    let mut d = vec![0.0; n + 1];
    if n > 0 {
        // prev holds degree n-1.
        for i in 0..=n {
            let left = if i > 0 { prev[i - 1] } else { 0.0 };
            let right = if i < n { prev[i] } else { 0.0 };
            d[i] = n as f64 * (left - right);
        }
    }
    (b, d)
}

impl BezierElement {
    /// S, S_s, S_t at the patch parameters (s, t) inside this element.
    pub fn derivatives(&self, s: f64, t: f64) -> (Point3, Vec3, Vec3) {
        let (p, q) = self.degree;
        let (hs, ht) = (
            self.s_range.1 - self.s_range.0,
            self.t_range.1 - self.t_range.0,
        );
        let (bs, dbs) = bernstein(p, (s - self.s_range.0) / hs);
        let (bt, dbt) = bernstein(q, (t - self.t_range.0) / ht);
        let (mut x, mut xs, mut xt) = ([0.0; 3], [0.0; 3], [0.0; 3]);
        for b in 0..=q {
            for a in 0..=p {
                let cp = self.control[b * (p + 1) + a];
                x = axpy(x, bs[a] * bt[b], cp);
                xs = axpy(xs, dbs[a] * bt[b] / hs, cp);
                xt = axpy(xt, bs[a] * dbt[b] / ht, cp);
            }
        }
        (x, xs, xt)
    }

    /// The point at patch parameters (s, t).
    pub fn eval(&self, s: f64, t: f64) -> Point3 {
        self.derivatives(s, t).0
    }
}

/// The Bézier elements of `patch`, row by row (t slowest, s fastest).
pub fn extract_bezier(patch: &BSplinePatch) -> Result<Vec<BezierElement>> {
    let extra = |kv: &crate::knots::KnotVector| -> Vec<f64> {
        let bp = kv.breakpoints();
        let mut out = Vec::new();
        for &b in &bp[1..bp.len() - 1] {
            for _ in kv.multiplicity(b)..kv.degree() {
                out.push(b);
            }
        }
        out
    };
    let full = insert_knots_patch(patch, &extra(patch.knots_s()), &extra(patch.knots_t()))?;
    let (p, q) = (full.knots_s().degree(), full.knots_t().degree());
    let (bs, bt) = (full.knots_s().breakpoints(), full.knots_t().breakpoints());
    let mut out = Vec::with_capacity((bs.len() - 1) * (bt.len() - 1));
    for (ej, wt) in bt.windows(2).enumerate() {
        for (ei, ws) in bs.windows(2).enumerate() {
            let mut control = Vec::with_capacity((p + 1) * (q + 1));
            for b in 0..=q {
                for a in 0..=p {
                    control.push(full.control_point(ei * p + a, ej * q + b));
                }
            }
            out.push(BezierElement {
                s_range: (ws[0], ws[1]),
                t_range: (wt[0], wt[1]),
                degree: (p, q),
                control,
            });
        }
    }
    Ok(out)
}

/// The 4-point Gauss–Legendre abscissae on [0, 1].
pub const GAUSS4: [f64; 4] = [
    0.5 * (1.0 - 0.861_136_311_594_052_6),
    0.5 * (1.0 - 0.339_981_043_584_856_3),
    0.5 * (1.0 + 0.339_981_043_584_856_3),
    0.5 * (1.0 + 0.861_136_311_594_052_6),
];

/// The result of the Jacobian check of one patch.
#[derive(Clone, Debug, PartialEq)]
pub struct JacobianReport {
    /// Gauss points checked (16 per Bézier element).
    pub points: usize,
    /// Gauss points where (S_s × S_t)·n ≤ 0: the patch folds there.
    pub non_positive: usize,
    /// The smallest (S_s × S_t)·n.
    pub min_jacobian: f64,
    /// The smallest scaled Jacobian (S_s × S_t)·n / (|S_s| |S_t|), in [−1, 1].
    pub min_scaled_jacobian: f64,
}

impl JacobianReport {
    /// True when the Jacobian is positive at every Gauss point.
    pub fn is_positive(&self) -> bool {
        self.non_positive == 0
    }
}

/// Checks (S_s × S_t)·n > 0 at the 4 × 4 Gauss points of every Bézier
/// element of `patch`, where `reference_normal(x, s, t)` gives the normal
/// the patch should agree with at the point x = S(s, t) (e.g. the shell's
/// normal there); it is normalised here.
pub fn jacobian_check(
    patch: &BSplinePatch,
    reference_normal: &dyn Fn(Point3, f64, f64) -> Vec3,
) -> Result<JacobianReport> {
    let mut rep = JacobianReport {
        points: 0,
        non_positive: 0,
        min_jacobian: f64::INFINITY,
        min_scaled_jacobian: f64::INFINITY,
    };
    for el in extract_bezier(patch)? {
        for gt in GAUSS4 {
            for gs in GAUSS4 {
                let s = el.s_range.0 + gs * (el.s_range.1 - el.s_range.0);
                let t = el.t_range.0 + gt * (el.t_range.1 - el.t_range.0);
                let (x, xs, xt) = el.derivatives(s, t);
                let n = reference_normal(x, s, t);
                let ln = norm(n);
                let j = if ln > 0.0 {
                    dot(cross(xs, xt), n) / ln
                } else {
                    f64::NAN
                };
                let scaled = j / (norm(xs) * norm(xt));
                rep.points += 1;
                if !(j > 0.0) {
                    rep.non_positive += 1;
                }
                rep.min_jacobian =
                    rep.min_jacobian
                        .min(if j.is_nan() { f64::NEG_INFINITY } else { j });
                rep.min_scaled_jacobian =
                    rep.min_scaled_jacobian
                        .min(if scaled.is_nan() { -1.0 } else { scaled });
            }
        }
    }
    Ok(rep)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::knots::KnotVector;
    use crate::refine::refine;
    use crate::vec3::dist;

    fn sheet(spans: usize, fold: bool) -> BSplinePatch {
        let kv = KnotVector::clamped_uniform(3, spans).unwrap();
        let g = kv.greville();
        let mut net = Vec::new();
        for &t in &g {
            for &s in &g {
                // Linear precision: control points at the Greville abscissae
                // give S(s,t) = (s, t, ...) exactly in x and y.
                let x = if fold {
                    s - 1.6 * s * (1.0 - s) * 3.0 * (s - 0.5).max(0.0) * 4.0
                } else {
                    s
                };
                net.push([x, t, 0.2 * (s * 3.0).sin() * t]);
            }
        }
        BSplinePatch::new(kv.clone(), kv, net).unwrap()
    }

    #[test]
    fn extraction_reproduces_the_patch() {
        for spans in [1, 3, 4] {
            let p = refine(&sheet(spans, false), 2).unwrap();
            let els = extract_bezier(&p).unwrap();
            assert_eq!(els.len(), 4 * spans * spans);
            let mut worst: f64 = 0.0;
            for el in &els {
                assert_eq!(el.control.len(), 16);
                for (a, b) in [(0.1, 0.2), (0.5, 0.5), (0.9, 0.7), (0.0, 1.0)] {
                    let s = el.s_range.0 + a * (el.s_range.1 - el.s_range.0);
                    let t = el.t_range.0 + b * (el.t_range.1 - el.t_range.0);
                    let (x, xs, xt) = el.derivatives(s, t);
                    let (y, ys, yt) = p.derivatives(s, t);
                    worst = worst
                        .max(dist(x, y))
                        .max(dist(xs, ys) * 1e-2)
                        .max(dist(xt, yt) * 1e-2);
                }
            }
            assert!(worst < 1e-12, "spans {spans}: {worst:e}");
        }
    }

    #[test]
    fn jacobian_positive_on_good_patch_negative_on_folded() {
        let up = |_: Point3, _: f64, _: f64| [0.0, 0.0, 1.0];
        let good = jacobian_check(&sheet(3, false), &up).unwrap();
        assert_eq!(good.points, 9 * 16);
        assert!(good.is_positive(), "{good:?}");
        assert!(
            good.min_scaled_jacobian > 0.5 && good.min_scaled_jacobian <= 1.0,
            "{good:?}"
        );
        let folded = jacobian_check(&sheet(3, true), &up).unwrap();
        assert!(!folded.is_positive(), "{folded:?}");
        assert!(folded.min_jacobian < 0.0 && folded.min_scaled_jacobian < 0.0);
        // The same good patch judged against the opposite normal is inverted everywhere.
        let down = |_: Point3, _: f64, _: f64| [0.0, 0.0, -2.0];
        assert_eq!(
            jacobian_check(&sheet(3, false), &down)
                .unwrap()
                .non_positive,
            9 * 16
        );
    }
}
