//! The geometry traits every B-rep entity implements: surfaces, 3D curves and
//! parameter-space curves (pcurves). Implemented by the OpenCASCADE importer,
//! the discrete (triangle-mesh) model and the analytic primitives.

use crate::model::Bounds2;
use crate::vec3::Vec3;

/// Position and derivatives of a surface at one (u, v).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceDerivs {
    /// S(u, v).
    pub point: Vec3,
    /// ∂S/∂u.
    pub du: Vec3,
    /// ∂S/∂v.
    pub dv: Vec3,
    /// ∂²S/∂u².
    pub duu: Vec3,
    /// ∂²S/∂u∂v.
    pub duv: Vec3,
    /// ∂²S/∂v².
    pub dvv: Vec3,
}

/// Shifts `x` by whole periods to the representative nearest `target`.
pub fn nearest_period(x: f64, period: f64, target: f64) -> f64 {
    x + ((target - x) / period).round() * period
}

/// `uv` with each periodic coordinate (a positive period in `periods`, as
/// [`Surface::periods`] gives them) moved to the representative nearest
/// `target`'s: the corners of an element on a cylinder brought into one
/// period before they are averaged or compared.
pub fn nearest_periodic_uv(uv: [f64; 2], periods: [Option<f64>; 2], target: [f64; 2]) -> [f64; 2] {
    let mut out = uv;
    for d in 0..2 {
        if let Some(p) = periods[d].filter(|p| *p > 0.0) {
            out[d] = nearest_period(uv[d], p, target[d]);
        }
    }
    out
}

/// A parametric surface S(u, v) → R³ (the geometry of a face, without trimming).
///
/// The natural normal is `du × dv`; a [`crate::Face`] may reverse it.
pub trait Surface: Send + Sync + std::fmt::Debug {
    /// S(u, v).
    fn eval(&self, uv: [f64; 2]) -> Vec3;
    /// S and its first and second derivatives at (u, v).
    fn derivs(&self, uv: [f64; 2]) -> SurfaceDerivs;
    /// S and its first derivatives at (u, v), for the callers that need no
    /// more (normals, tangent frames, projections by Gauss–Newton): the
    /// second derivatives may be left at zero. A surface whose second
    /// derivatives cost extra (OpenCASCADE's) overrides it; by default the
    /// same as [`Surface::derivs`].
    fn first_derivs(&self, uv: [f64; 2]) -> SurfaceDerivs {
        self.derivs(uv)
    }
    /// Unit normal `du × dv / |du × dv|` at (u, v), or `None` where the
    /// parametrization is singular (a pole) and no limit normal is known.
    fn normal(&self, uv: [f64; 2]) -> Option<Vec3> {
        let d = self.derivs(uv);
        crate::vec3::normalize(crate::vec3::cross(d.du, d.dv))
    }
    /// Parameter bounds of the (untrimmed) surface; infinite surfaces report
    /// the bounds of the face that uses them.
    fn uv_bounds(&self) -> Bounds2;
    /// Period in u and in v (`None` when not periodic).
    fn periods(&self) -> [Option<f64>; 2];

    /// Length below which refining a triangulation for curvature gains
    /// nothing: 0 for smooth (CAD) surfaces; for a piecewise-linear surface,
    /// about its triangles' size (a crease between two input triangles turns
    /// the normal by the same angle at every scale, so chasing it never ends).
    fn resolution(&self) -> f64 {
        0.0
    }
    /// Closest point on the surface to `p`: `(uv, S(uv))`. `hint` is a
    /// starting guess. Returns `None` when the projection fails.
    fn project(&self, p: Vec3, hint: Option<[f64; 2]>) -> Option<([f64; 2], Vec3)>;
}

/// A parametric 3D curve C(t) on the range `[t0, t1]`.
pub trait Curve: Send + Sync + std::fmt::Debug {
    /// C(t).
    fn eval(&self, t: f64) -> Vec3;
    /// C'(t).
    fn deriv(&self, t: f64) -> Vec3;
    /// Parameter range `(t0, t1)` with `t0 < t1`.
    fn range(&self) -> (f64, f64);
    /// Closest point on the curve (within its range) to `p`: `(t, C(t))`.
    fn project(&self, p: Vec3, hint: Option<f64>) -> Option<(f64, Vec3)>;
    /// For a piecewise-linear curve (a feature polyline of a triangle
    /// mesh), its vertices' parameters in increasing order, so that the curve
    /// mesher samples it at its vertices and sees each vertex's turn spread
    /// over its segments instead of as a kink; `None` (the default) for a
    /// smooth curve.
    fn breakpoints(&self) -> Option<Vec<f64>> {
        None
    }
}

/// A curve in a surface's parameter plane, c(t) → (u, v). Pcurves share the
/// parameter t of their 3D curve: `surface.eval(pcurve.eval(t)) ≈ curve.eval(t)`.
pub trait Curve2d: Send + Sync + std::fmt::Debug {
    /// c(t).
    fn eval(&self, t: f64) -> [f64; 2];
    /// c'(t).
    fn deriv(&self, t: f64) -> [f64; 2];
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_period_picks_the_closest_representative() {
        let p = std::f64::consts::TAU;
        assert!((nearest_period(0.1, p, 6.0) - (0.1 + p)).abs() < 1e-15);
        assert!((nearest_period(6.2, p, 0.0) - (6.2 - p)).abs() < 1e-15);
        assert_eq!(nearest_period(1.0, p, 1.5), 1.0);
    }

    #[test]
    fn only_periodic_coordinates_move_toward_the_target() {
        let p = std::f64::consts::TAU;
        let uv = nearest_periodic_uv([0.1, 5.0], [Some(p), None], [6.0, -3.0]);
        assert!((uv[0] - (0.1 + p)).abs() < 1e-15);
        assert_eq!(uv[1], 5.0);
        // a zero period is no period
        assert_eq!(
            nearest_periodic_uv([0.1, 5.0], [Some(0.0), Some(0.0)], [6.0, -3.0]),
            [0.1, 5.0]
        );
    }
}
