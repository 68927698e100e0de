//! Tensor-product B-spline patches: evaluation, partial derivatives, normal.

use crate::basis::with_basis_derivatives;
use crate::curve::BSplineCurve;
use crate::error::{Result, SplineError};
use crate::knots::KnotVector;
use crate::vec3::{axpy, cross, norm, scale, Point3, Vec3};

/// A non-rational tensor-product B-spline patch. The control net is
/// row-major with s fastest: `control[j * n_s + i]` is P_ij, i along s,
/// j along t. Boundaries: bottom S(s, t0) is row 0, top row `n_t − 1`,
/// left S(s0, t) column 0, right column `n_s − 1`.
#[derive(Clone, Debug, PartialEq)]
pub struct BSplinePatch {
    knots_s: KnotVector,
    knots_t: KnotVector,
    control: Vec<Point3>,
}

impl BSplinePatch {
    /// A patch from its knot vectors and control net; the net must hold
    /// `n_s × n_t` points.
    pub fn new(knots_s: KnotVector, knots_t: KnotVector, control: Vec<Point3>) -> Result<Self> {
        let (ns, nt) = (knots_s.num_control_points(), knots_t.num_control_points());
        if control.len() != ns * nt {
            return Err(SplineError::Shape(format!(
                "patch: knots need {ns} × {nt} = {} control points, got {}",
                ns * nt,
                control.len()
            )));
        }
        Ok(Self {
            knots_s,
            knots_t,
            control,
        })
    }

    /// The knot vector in s.
    pub fn knots_s(&self) -> &KnotVector {
        &self.knots_s
    }

    /// The knot vector in t.
    pub fn knots_t(&self) -> &KnotVector {
        &self.knots_t
    }

    /// Control points along s.
    pub fn n_s(&self) -> usize {
        self.knots_s.num_control_points()
    }

    /// Control points along t.
    pub fn n_t(&self) -> usize {
        self.knots_t.num_control_points()
    }

    /// The control net, row-major (s fastest).
    pub fn control_points(&self) -> &[Point3] {
        &self.control
    }

    /// Control point P_ij.
    pub fn control_point(&self, i: usize, j: usize) -> Point3 {
        self.control[j * self.n_s() + i]
    }

    /// The point S(s, t) (parameters clamped to the domain).
    pub fn eval(&self, s: f64, t: f64) -> Point3 {
        self.derivatives(s, t).0
    }

    /// S(s, t) and its partials S_s, S_t.
    pub fn derivatives(&self, s: f64, t: f64) -> (Point3, Vec3, Vec3) {
        let (p, q) = (self.knots_s.degree(), self.knots_t.degree());
        let (ss, st) = (self.knots_s.find_span(s), self.knots_t.find_span(t));
        let ns = self.n_s();
        // Values and first derivatives, each as two rows of one flat buffer.
        with_basis_derivatives(&self.knots_s, ss, s, 1, |bs, ws| {
            with_basis_derivatives(&self.knots_t, st, t, 1, |bt, wt| {
                let (mut x, mut xs, mut xt) = ([0.0; 3], [0.0; 3], [0.0; 3]);
                for (b, (&t0, &t1)) in bt[..wt].iter().zip(&bt[wt..]).enumerate() {
                    let j = st - q + b;
                    for (a, (&s0, &s1)) in bs[..ws].iter().zip(&bs[ws..]).enumerate() {
                        let cp = self.control[j * ns + ss - p + a];
                        x = axpy(x, s0 * t0, cp);
                        xs = axpy(xs, s1 * t0, cp);
                        xt = axpy(xt, s0 * t1, cp);
                    }
                }
                (x, xs, xt)
            })
        })
    }

    /// The unit normal S_s × S_t / |S_s × S_t|, `None` where the patch is
    /// degenerate (zero cross product).
    pub fn normal(&self, s: f64, t: f64) -> Option<Vec3> {
        let (_, xs, xt) = self.derivatives(s, t);
        let n = cross(xs, xt);
        let l = norm(n);
        (l > 0.0 && l.is_finite()).then(|| scale(n, 1.0 / l))
    }

    /// Boundary curve 0 = bottom (+s), 1 = right (+t), 2 = top (+s),
    /// 3 = left (+t); `None` for another side number.
    pub fn boundary(&self, side: usize) -> Option<BSplineCurve> {
        let (ns, nt) = (self.n_s(), self.n_t());
        let (knots, pts): (&KnotVector, Vec<Point3>) = match side {
            0 => (
                &self.knots_s,
                (0..ns).map(|i| self.control_point(i, 0)).collect(),
            ),
            1 => (
                &self.knots_t,
                (0..nt).map(|j| self.control_point(ns - 1, j)).collect(),
            ),
            2 => (
                &self.knots_s,
                (0..ns).map(|i| self.control_point(i, nt - 1)).collect(),
            ),
            3 => (
                &self.knots_t,
                (0..nt).map(|j| self.control_point(0, j)).collect(),
            ),
            _ => return None,
        };
        BSplineCurve::new(knots.clone(), pts).ok()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vec3::dist;

    /// A bicubic Bézier patch of the graph z = s²t + t³ over [0,1]²
    /// (polynomial of degree ≤ 3 in each variable, so exactly representable
    /// by its Bézier net computed via blossoms at the Bernstein points).
    fn graph_patch() -> BSplinePatch {
        let kv = KnotVector::clamped_uniform(3, 1).unwrap();
        // z = s^2 t + t^3: blossom in s of s^2 at (a,b,c) = (ab+bc+ca)/3,
        // of t at (a,b,c) = (a+b+c)/3, t^3 = abc. Bézier points: a..c ∈ {0,1}.
        let s2 = [0.0, 0.0, 1.0 / 3.0, 1.0];
        let t1 = [0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0];
        let t3 = [0.0, 0.0, 0.0, 1.0];
        let mut net = Vec::new();
        for j in 0..4 {
            for (i, s2i) in s2.iter().enumerate() {
                net.push([i as f64 / 3.0, j as f64 / 3.0, s2i * t1[j] + t3[j]]);
            }
        }
        BSplinePatch::new(kv.clone(), kv, net).unwrap()
    }

    #[test]
    fn evaluation_partials_and_normal() {
        let p = graph_patch();
        let (s, t) = (0.3, 0.7);
        let (x, xs, xt) = p.derivatives(s, t);
        assert!(dist(x, [s, t, s * s * t + t * t * t]) < 1e-14);
        assert!(dist(xs, [1.0, 0.0, 2.0 * s * t]) < 1e-13);
        assert!(dist(xt, [0.0, 1.0, s * s + 3.0 * t * t]) < 1e-13);
        let n = p.normal(s, t).unwrap();
        let want = cross(xs, xt);
        assert!(dist(n, scale(want, 1.0 / norm(want))) < 1e-14);
        let top = p.boundary(2).unwrap();
        assert!(dist(top.eval(0.4), p.eval(0.4, 1.0)) < 1e-14);
        assert!(p.boundary(4).is_none());
    }

    #[test]
    fn wrong_net_size_is_error() {
        let kv = KnotVector::clamped_uniform(3, 2).unwrap();
        let e = BSplinePatch::new(kv.clone(), kv, vec![[0.0; 3]; 16]).unwrap_err();
        assert!(e.to_string().contains("5 × 5 = 25"), "{e}");
    }
}
