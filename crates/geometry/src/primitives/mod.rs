//! Analytic surfaces and curves (plane, cylinder, sphere, cone, line, circle) and
//! small ready-made models built from them ([`models`]). They let every crate
//! test its stage on exactly known geometry without reading a CAD file.

mod models;
pub use models::*;

use std::f64::consts::{FRAC_PI_2, TAU};

use crate::model::*;
use crate::traits::*;
use crate::vec3::{self, add, cross, dot, scale, sub, Vec3};

/// The plane `origin + u·xdir + v·ydir` (xdir, ydir orthonormal).
#[derive(Clone, Debug)]
pub struct Plane {
    /// Point at (0, 0).
    pub origin: Vec3,
    /// Unit u direction.
    pub xdir: Vec3,
    /// Unit v direction, orthogonal to `xdir`.
    pub ydir: Vec3,
    /// Bounds reported by `uv_bounds`.
    pub bounds: Bounds2,
}

impl Surface for Plane {
    fn eval(&self, uv: [f64; 2]) -> Vec3 {
        add(
            self.origin,
            add(scale(self.xdir, uv[0]), scale(self.ydir, uv[1])),
        )
    }
    fn derivs(&self, uv: [f64; 2]) -> SurfaceDerivs {
        SurfaceDerivs {
            point: self.eval(uv),
            du: self.xdir,
            dv: self.ydir,
            duu: [0.0; 3],
            duv: [0.0; 3],
            dvv: [0.0; 3],
        }
    }
    fn uv_bounds(&self) -> Bounds2 {
        self.bounds
    }
    fn periods(&self) -> [Option<f64>; 2] {
        [None, None]
    }
    fn project(&self, p: Vec3, _hint: Option<[f64; 2]>) -> Option<([f64; 2], Vec3)> {
        let d = sub(p, self.origin);
        let uv = [dot(d, self.xdir), dot(d, self.ydir)];
        Some((uv, self.eval(uv)))
    }
}

/// The cylinder `center + r (cos u·xdir + sin u·ydir) + v·axis`, u periodic (2π).
#[derive(Clone, Debug)]
pub struct Cylinder {
    /// Point on the axis at v = 0.
    pub center: Vec3,
    /// Unit direction of u = 0.
    pub xdir: Vec3,
    /// Unit direction of u = π/2.
    pub ydir: Vec3,
    /// Radius.
    pub radius: f64,
    /// v range reported by `uv_bounds`.
    pub height: (f64, f64),
}

impl Cylinder {
    fn axis(&self) -> Vec3 {
        cross(self.xdir, self.ydir)
    }
}

impl Surface for Cylinder {
    fn eval(&self, uv: [f64; 2]) -> Vec3 {
        let r = self.radius;
        add(
            self.center,
            add(
                scale(self.xdir, r * uv[0].cos()),
                add(scale(self.ydir, r * uv[0].sin()), scale(self.axis(), uv[1])),
            ),
        )
    }
    fn derivs(&self, uv: [f64; 2]) -> SurfaceDerivs {
        let (s, c) = uv[0].sin_cos();
        let r = self.radius;
        SurfaceDerivs {
            point: self.eval(uv),
            du: add(scale(self.xdir, -r * s), scale(self.ydir, r * c)),
            dv: self.axis(),
            duu: add(scale(self.xdir, -r * c), scale(self.ydir, -r * s)),
            duv: [0.0; 3],
            dvv: [0.0; 3],
        }
    }
    fn uv_bounds(&self) -> Bounds2 {
        Bounds2 {
            umin: 0.0,
            umax: TAU,
            vmin: self.height.0,
            vmax: self.height.1,
        }
    }
    fn periods(&self) -> [Option<f64>; 2] {
        [Some(TAU), None]
    }
    fn project(&self, p: Vec3, hint: Option<[f64; 2]>) -> Option<([f64; 2], Vec3)> {
        let d = sub(p, self.center);
        let mut u = dot(d, self.ydir).atan2(dot(d, self.xdir));
        u = match hint {
            Some(h) => nearest_period(u, TAU, h[0]),
            None => u.rem_euclid(TAU),
        };
        let uv = [u, dot(d, self.axis())];
        Some((uv, self.eval(uv)))
    }
}

/// The sphere `center + r (cos v cos u, cos v sin u, sin v)`; u periodic (2π),
/// v in [−π/2, π/2] with poles at the ends.
#[derive(Clone, Debug)]
pub struct Sphere {
    /// Centre.
    pub center: Vec3,
    /// Radius.
    pub radius: f64,
}

impl Surface for Sphere {
    fn eval(&self, uv: [f64; 2]) -> Vec3 {
        let (su, cu) = uv[0].sin_cos();
        let (sv, cv) = uv[1].sin_cos();
        add(self.center, scale([cv * cu, cv * su, sv], self.radius))
    }
    fn derivs(&self, uv: [f64; 2]) -> SurfaceDerivs {
        let (su, cu) = uv[0].sin_cos();
        let (sv, cv) = uv[1].sin_cos();
        let r = self.radius;
        SurfaceDerivs {
            point: self.eval(uv),
            du: scale([-cv * su, cv * cu, 0.0], r),
            dv: scale([-sv * cu, -sv * su, cv], r),
            duu: scale([-cv * cu, -cv * su, 0.0], r),
            duv: scale([sv * su, -sv * cu, 0.0], r),
            dvv: scale([-cv * cu, -cv * su, -sv], r),
        }
    }
    fn normal(&self, uv: [f64; 2]) -> Option<Vec3> {
        vec3::normalize(sub(self.eval(uv), self.center))
    }
    fn uv_bounds(&self) -> Bounds2 {
        Bounds2 {
            umin: 0.0,
            umax: TAU,
            vmin: -FRAC_PI_2,
            vmax: FRAC_PI_2,
        }
    }
    fn periods(&self) -> [Option<f64>; 2] {
        [Some(TAU), None]
    }
    fn project(&self, p: Vec3, hint: Option<[f64; 2]>) -> Option<([f64; 2], Vec3)> {
        let d = sub(p, self.center);
        let rxy = (d[0] * d[0] + d[1] * d[1]).sqrt();
        let mut u = if rxy > 1e-14 * self.radius {
            d[1].atan2(d[0])
        } else {
            hint.map_or(0.0, |h| h[0])
        };
        u = match hint {
            Some(h) => nearest_period(u, TAU, h[0]),
            None => u.rem_euclid(TAU),
        };
        let uv = [u, d[2].atan2(rxy)];
        Some((uv, self.eval(uv)))
    }
}

/// The cone `(r + v sin a)(cos u·x + sin u·y) + (h + v cos a)·z` about the z
/// axis, parametrized like OpenCASCADE's: radius `r` at v = 0 (height `h`),
/// half-angle `a` (0 < a < π/2), u periodic (2π). The apex is at
/// `v = −r / sin a`; beyond it (v smaller) lies the other nappe, where the
/// radius is negative and `du × dv` points the other way.
#[derive(Clone, Debug)]
pub struct Cone {
    /// Radius at v = 0.
    pub radius: f64,
    /// Height (z) of the circle v = 0.
    pub height: f64,
    /// Half-angle at the apex, radians.
    pub half_angle: f64,
}

impl Cone {
    /// v of the apex.
    pub fn apex_v(&self) -> f64 {
        -self.radius / self.half_angle.sin()
    }
}

impl Surface for Cone {
    fn eval(&self, uv: [f64; 2]) -> Vec3 {
        let (su, cu) = uv[0].sin_cos();
        let (sa, ca) = self.half_angle.sin_cos();
        let rho = self.radius + uv[1] * sa;
        [rho * cu, rho * su, self.height + uv[1] * ca]
    }
    fn derivs(&self, uv: [f64; 2]) -> SurfaceDerivs {
        let (su, cu) = uv[0].sin_cos();
        let (sa, ca) = self.half_angle.sin_cos();
        let rho = self.radius + uv[1] * sa;
        SurfaceDerivs {
            point: self.eval(uv),
            du: [-rho * su, rho * cu, 0.0],
            dv: [sa * cu, sa * su, ca],
            duu: [-rho * cu, -rho * su, 0.0],
            duv: [-sa * su, sa * cu, 0.0],
            dvv: [0.0; 3],
        }
    }
    fn uv_bounds(&self) -> Bounds2 {
        Bounds2 {
            umin: 0.0,
            umax: TAU,
            vmin: self.apex_v(),
            vmax: 0.0,
        }
    }
    fn periods(&self) -> [Option<f64>; 2] {
        [Some(TAU), None]
    }
    /// Exact on the nappe the point faces: u from its angle about the axis,
    /// v from the closest point of that generatrix line.
    fn project(&self, p: Vec3, hint: Option<[f64; 2]>) -> Option<([f64; 2], Vec3)> {
        let rxy = p[0].hypot(p[1]);
        let mut u = if rxy > 1e-14 * self.radius {
            p[1].atan2(p[0])
        } else {
            hint.map_or(0.0, |h| h[0])
        };
        u = match hint {
            Some(h) => nearest_period(u, TAU, h[0]),
            None => u.rem_euclid(TAU),
        };
        let (sa, ca) = self.half_angle.sin_cos();
        let uv = [u, (rxy - self.radius) * sa + (p[2] - self.height) * ca];
        Some((uv, self.eval(uv)))
    }
}

/// The line `origin + t·dir` on `range`.
#[derive(Clone, Debug)]
pub struct Line {
    /// Point at t = 0.
    pub origin: Vec3,
    /// Direction (any length).
    pub dir: Vec3,
    /// Parameter range.
    pub range: (f64, f64),
}

impl Curve for Line {
    fn eval(&self, t: f64) -> Vec3 {
        add(self.origin, scale(self.dir, t))
    }
    fn deriv(&self, _t: f64) -> Vec3 {
        self.dir
    }
    fn range(&self) -> (f64, f64) {
        self.range
    }
    fn project(&self, p: Vec3, _hint: Option<f64>) -> Option<(f64, Vec3)> {
        let t = (dot(sub(p, self.origin), self.dir) / dot(self.dir, self.dir))
            .clamp(self.range.0, self.range.1);
        Some((t, self.eval(t)))
    }
}

/// The circle (or arc) `center + r (cos t·xdir + sin t·ydir)` on `range`.
#[derive(Clone, Debug)]
pub struct Circle {
    /// Centre.
    pub center: Vec3,
    /// Unit direction of t = 0.
    pub xdir: Vec3,
    /// Unit direction of t = π/2.
    pub ydir: Vec3,
    /// Radius.
    pub radius: f64,
    /// Parameter range.
    pub range: (f64, f64),
}

impl Curve for Circle {
    fn eval(&self, t: f64) -> Vec3 {
        add(
            self.center,
            add(
                scale(self.xdir, self.radius * t.cos()),
                scale(self.ydir, self.radius * t.sin()),
            ),
        )
    }
    fn deriv(&self, t: f64) -> Vec3 {
        add(
            scale(self.xdir, -self.radius * t.sin()),
            scale(self.ydir, self.radius * t.cos()),
        )
    }
    fn range(&self) -> (f64, f64) {
        self.range
    }
    fn project(&self, p: Vec3, hint: Option<f64>) -> Option<(f64, Vec3)> {
        let d = sub(p, self.center);
        let t0 = dot(d, self.ydir).atan2(dot(d, self.xdir));
        let target = hint.unwrap_or(0.5 * (self.range.0 + self.range.1));
        let t = nearest_period(t0, TAU, target).clamp(self.range.0, self.range.1);
        Some((t, self.eval(t)))
    }
}

/// The ellipse (or arc) `center + a cos t·xdir + b sin t·ydir` on `range`.
#[derive(Clone, Debug)]
pub struct Ellipse {
    /// Centre.
    pub center: Vec3,
    /// Unit direction of the `a` axis (t = 0).
    pub xdir: Vec3,
    /// Unit direction of the `b` axis (t = π/2).
    pub ydir: Vec3,
    /// Semi-axis along `xdir`.
    pub a: f64,
    /// Semi-axis along `ydir`.
    pub b: f64,
    /// Parameter range.
    pub range: (f64, f64),
}

impl Curve for Ellipse {
    fn eval(&self, t: f64) -> Vec3 {
        add(self.center, add(scale(self.xdir, self.a * t.cos()), scale(self.ydir, self.b * t.sin())))
    }
    fn deriv(&self, t: f64) -> Vec3 {
        add(scale(self.xdir, -self.a * t.sin()), scale(self.ydir, self.b * t.cos()))
    }
    fn range(&self) -> (f64, f64) {
        self.range
    }
    fn project(&self, p: Vec3, hint: Option<f64>) -> Option<(f64, Vec3)> {
        let d = sub(p, self.center);
        let (x, y) = (dot(d, self.xdir), dot(d, self.ydir));
        let target = hint.unwrap_or(0.5 * (self.range.0 + self.range.1));
        let mut t = nearest_period((y / self.b).atan2(x / self.a), TAU, target);
        // Newton on f(t) = (E(t) − p)·E'(t) = 0
        for _ in 0..20 {
            let (c, s) = (t.cos(), t.sin());
            let (ex, ey) = (self.a * c - x, self.b * s - y);
            let (dx, dy) = (-self.a * s, self.b * c);
            let f = ex * dx + ey * dy;
            let df = dx * dx + dy * dy + ex * (-self.a * c) + ey * (-self.b * s);
            if df.abs() < 1e-300 {
                break;
            }
            let step = f / df;
            t -= step;
            if step.abs() < 1e-15 {
                break;
            }
        }
        let t = nearest_period(t, TAU, target).clamp(self.range.0, self.range.1);
        Some((t, self.eval(t)))
    }
}

/// The pcurve `center + (a cos t, b sin t)` in a parameter plane.
#[derive(Clone, Debug)]
pub struct Ellipse2d {
    /// Centre.
    pub center: [f64; 2],
    /// Semi-axis along u.
    pub a: f64,
    /// Semi-axis along v.
    pub b: f64,
}

impl Curve2d for Ellipse2d {
    fn eval(&self, t: f64) -> [f64; 2] {
        [self.center[0] + self.a * t.cos(), self.center[1] + self.b * t.sin()]
    }
    fn deriv(&self, t: f64) -> [f64; 2] {
        [-self.a * t.sin(), self.b * t.cos()]
    }
}

/// The pcurve `origin + t·dir` in a parameter plane.
#[derive(Clone, Debug)]
pub struct Line2d {
    /// Point at t = 0.
    pub origin: [f64; 2],
    /// Direction.
    pub dir: [f64; 2],
}

impl Curve2d for Line2d {
    fn eval(&self, t: f64) -> [f64; 2] {
        [
            self.origin[0] + t * self.dir[0],
            self.origin[1] + t * self.dir[1],
        ]
    }
    fn deriv(&self, _t: f64) -> [f64; 2] {
        self.dir
    }
}

/// The pcurve `center + r (cos t, sin t)` in a parameter plane.
#[derive(Clone, Debug)]
pub struct Circle2d {
    /// Centre.
    pub center: [f64; 2],
    /// Radius.
    pub radius: f64,
}

impl Curve2d for Circle2d {
    fn eval(&self, t: f64) -> [f64; 2] {
        [
            self.center[0] + self.radius * t.cos(),
            self.center[1] + self.radius * t.sin(),
        ]
    }
    fn deriv(&self, t: f64) -> [f64; 2] {
        [-self.radius * t.sin(), self.radius * t.cos()]
    }
}

#[cfg(test)]
mod tests {

    use super::*;
    use crate::model::signed_area;

    fn check_model(m: &Model) {
        m.validate().unwrap();
        for (fi, f) in m.faces.iter().enumerate() {
            for (li, l) in f.loops.iter().enumerate() {
                let poly = m.loop_uv_polyline(FaceId(fi as u32), li, 8);
                assert!(
                    signed_area(&poly) > 0.0,
                    "face {fi} loop {li} must be counter-clockwise"
                );
                // consecutive uses meet in uv, and in 3D the pcurve maps onto the curve
                for (k, u) in l.uses.iter().enumerate() {
                    let c = &m.curves[u.curve.idx()];
                    let next = &l.uses[(k + 1) % l.uses.len()];
                    let cn = &m.curves[next.curve.idx()];
                    let end = u.pcurve.eval(if u.forward { c.range.1 } else { c.range.0 });
                    let start =
                        next.pcurve
                            .eval(if next.forward { cn.range.0 } else { cn.range.1 });
                    assert!((end[0] - start[0]).hypot(end[1] - start[1]) < 1e-12);
                    for i in 0..=4 {
                        let t = c.range.0 + (c.range.1 - c.range.0) * i as f64 / 4.0;
                        let d = vec3::dist(f.surface.eval(u.pcurve.eval(t)), c.eval(m, t));
                        assert!(d < 1e-12, "pcurve off its curve by {d}");
                    }
                }
            }
        }
    }

    #[test]
    fn primitive_models_follow_the_conventions() {
        check_model(&square(2.0));
        check_model(&cylinder(1.0, 3.0));
        check_model(&sphere(1.5));
        check_model(&cone(1.0, 2.0));
    }

    #[test]
    fn projection_round_trips() {
        let m = cylinder(1.0, 3.0);
        for f in &m.faces {
            let b = f.uv_bounds;
            for i in 1..5 {
                let uv = [
                    b.umin + (b.umax - b.umin) * i as f64 / 5.0,
                    b.vmin + (b.vmax - b.vmin) * 0.3,
                ];
                let p = f.surface.eval(uv);
                let (_, q) = f.surface.project(p, None).unwrap();
                assert!(vec3::dist(p, q) < 1e-12);
            }
        }
        let s = Sphere {
            center: [0.0; 3],
            radius: 2.0,
        };
        let (uv, _) = s.project([0.0, 2.0, 0.0], None).unwrap();
        assert!((uv[0] - FRAC_PI_2).abs() < 1e-12 && uv[1].abs() < 1e-12);
    }

    #[test]
    fn outward_normals() {
        let m = cylinder(1.0, 3.0);
        let n_side = m.faces[0].normal([0.0, 1.0]).unwrap();
        assert!((n_side[0] - 1.0).abs() < 1e-12);
        assert!((m.faces[1].normal([0.0, 0.0]).unwrap()[2] + 1.0).abs() < 1e-12);
        assert!((m.faces[2].normal([0.0, 0.0]).unwrap()[2] - 1.0).abs() < 1e-12);
    }

    #[test]
    fn cone_normal_points_away_from_the_axis_and_flips_past_the_apex() {
        let m = cone(1.0, 1.0);
        let f = &m.faces[0];
        let va = f.uv_bounds.vmin;
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let n = f.normal([0.0, 0.5 * va]).unwrap();
        assert!(vec3::dist(n, [s, 0.0, -s]) < 1e-12, "{n:?}");
        // on the other nappe, just past the apex
        let n = f.normal([0.0, va - 1e-9]).unwrap();
        assert!(vec3::dist(n, [-s, 0.0, s]) < 1e-6, "{n:?}");
        let p = f.surface.eval([1.0, 0.5 * va]);
        let (uv, q) = f.surface.project(p, None).unwrap();
        assert!(
            vec3::dist(p, q) < 1e-12
                && (uv[0] - 1.0).abs() < 1e-12
                && (uv[1] - 0.5 * va).abs() < 1e-12
        );
    }
}
