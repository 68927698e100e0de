//! OCCT geometry behind Quadrille's geometry traits: [`OcctSurface`],
//! [`OcctCurve`], [`OcctCurve2d`] (and [`PcurveOnSurface`] for an edge that
//! has no 3D curve of its own).
//!
//! Evaluation goes straight to the `Geom_*` object through the shim (about
//! 0.1 µs a call). Projection runs a damped Newton iteration in Rust from the
//! hint (or from the best point of a coarse grid), and falls back to OCCT's
//! global projectors (`GeomAPI_ProjectPointOnSurf` / `…OnCurve`, built per
//! call) when Newton does not converge. All types are `Send + Sync`: nothing
//! here mutates shared state.

use std::sync::Arc;

use geometry::vec3::{add, cross, dist, dot, normalize, scale, sub};
use geometry::{Bounds2, Curve, Curve2d, Surface, SurfaceDerivs, Vec3};

use crate::ffi::{self, Curve2dPtr, CurvePtr, SurfPtr};

const NAN3: Vec3 = [f64::NAN; 3];

/// The surface of one face: an OCCT `Geom_Surface` with the face location
/// applied, plus the face's uv bounds (`BRepTools::UVBounds`).
#[derive(Debug)]
pub struct OcctSurface {
    ptr: SurfPtr,
    /// uv bounds of the face (what [`Surface::uv_bounds`] reports).
    face_bounds: Bounds2,
    /// Natural bounds of the untrimmed surface (may be infinite).
    natural: Bounds2,
    periods: [Option<f64>; 2],
    /// Length scale of the face (diagonal of a few sampled points).
    size: f64,
}

impl OcctSurface {
    /// Wraps a shim surface; `face_bounds` are the uv bounds of the face using it.
    pub(crate) fn new(ptr: SurfPtr, face_bounds: Bounds2) -> Self {
        let (mut pu, mut pv) = (0.0, 0.0);
        let mut nb = [
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
        ];
        // SAFETY: ptr is a live shim surface; out-pointers are valid locals.
        unsafe {
            if ffi::occt_surf_periods(ptr.ptr(), &mut pu, &mut pv) != ffi::OK {
                pu = 0.0;
                pv = 0.0;
            }
            if ffi::occt_surf_bounds(ptr.ptr(), nb.as_mut_ptr()) != ffi::OK {
                nb = [
                    f64::NEG_INFINITY,
                    f64::INFINITY,
                    f64::NEG_INFINITY,
                    f64::INFINITY,
                ];
            }
        }
        let per = |p: f64| {
            if p > 0.0 && p.is_finite() {
                Some(p)
            } else {
                None
            }
        };
        // OCCT reports "infinite" bounds as ±2e100 (Precision::Infinite).
        let fin = |x: f64| {
            if x.abs() >= 1e100 {
                x.signum() * f64::INFINITY
            } else {
                x
            }
        };
        let natural = Bounds2 {
            umin: fin(nb[0]),
            umax: fin(nb[1]),
            vmin: fin(nb[2]),
            vmax: fin(nb[3]),
        };
        let mut s = OcctSurface {
            ptr,
            face_bounds,
            natural,
            periods: [per(pu), per(pv)],
            size: 1.0,
        };
        s.size = s.sample_size();
        s
    }

    fn sample_size(&self) -> f64 {
        let b = self.face_bounds;
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for i in 0..=4 {
            for j in 0..=4 {
                let p = self.eval([
                    b.umin + (b.umax - b.umin) * i as f64 / 4.0,
                    b.vmin + (b.vmax - b.vmin) * j as f64 / 4.0,
                ]);
                for k in 0..3 {
                    if p[k].is_finite() {
                        lo[k] = lo[k].min(p[k]);
                        hi[k] = hi[k].max(p[k]);
                    }
                }
            }
        }
        let d = dist(lo, hi);
        if d.is_finite() && d > 0.0 {
            d
        } else {
            1.0
        }
    }

    fn d1(&self, uv: [f64; 2]) -> Option<[Vec3; 3]> {
        let mut o = [0.0; 9];
        // SAFETY: live surface, 9-element output buffer.
        let rc = unsafe { ffi::occt_surf_d1(self.ptr.ptr(), uv[0], uv[1], o.as_mut_ptr()) };
        (rc == ffi::OK).then(|| [[o[0], o[1], o[2]], [o[3], o[4], o[5]], [o[6], o[7], o[8]]])
    }

    /// Keeps a Newton iterate inside the natural bounds in non-periodic directions.
    fn clamp(&self, uv: [f64; 2]) -> [f64; 2] {
        let b = self.natural;
        let u = if self.periods[0].is_some() {
            uv[0]
        } else {
            uv[0].clamp(b.umin, b.umax)
        };
        let v = if self.periods[1].is_some() {
            uv[1]
        } else {
            uv[1].clamp(b.vmin, b.vmax)
        };
        [u, v]
    }

    /// Moves periodic coordinates to the representative nearest `target`
    /// (the hint, else the middle of the face bounds).
    fn wrap(&self, uv: [f64; 2], target: [f64; 2]) -> [f64; 2] {
        geometry::nearest_periodic_uv(uv, self.periods, target)
    }

    /// Damped Newton (Levenberg–Marquardt) on ½|S(u,v) − p|² from `start`.
    /// Returns (uv, S(uv), converged): converged when S(uv) = p to round-off,
    /// or when S(uv) − p is normal to the surface (a stationary point).
    fn newton(&self, p: Vec3, start: [f64; 2]) -> Option<([f64; 2], Vec3, bool)> {
        let mut uv = self.clamp(start);
        let mut d = self.derivs(uv);
        if !d.point.iter().all(|x| x.is_finite()) {
            return None;
        }
        let mut f = dist(d.point, p);
        let mut mu = 1e-3;
        let on_surface = 1e-14 * self.size + 1e-15 * norm3(p);
        for _ in 0..60 {
            let r = sub(d.point, p);
            let g = [dot(r, d.du), dot(r, d.dv)];
            let (nu, nv) = (norm3(d.du), norm3(d.dv));
            if f <= on_surface || (g[0].abs() <= 1e-10 * f * nu && g[1].abs() <= 1e-10 * f * nv) {
                return Some((uv, d.point, true));
            }
            let h00 = dot(d.du, d.du) + dot(r, d.duu);
            let h01 = dot(d.du, d.dv) + dot(r, d.duv);
            let h11 = dot(d.dv, d.dv) + dot(r, d.dvv);
            let scale_h = (nu * nu + nv * nv).max(1e-300);
            let mut accepted = false;
            for _ in 0..16 {
                let a = h00 + mu * scale_h;
                let c = h11 + mu * scale_h;
                let det = a * c - h01 * h01;
                if !(det > 0.0 && det.is_finite() && a > 0.0) {
                    mu *= 10.0;
                    continue;
                }
                let du = -(c * g[0] - h01 * g[1]) / det;
                let dv = -(a * g[1] - h01 * g[0]) / det;
                let cand = self.clamp([uv[0] + du, uv[1] + dv]);
                let step3 = norm3(add(
                    scale(d.du, cand[0] - uv[0]),
                    scale(d.dv, cand[1] - uv[1]),
                ));
                let dc = self.derivs(cand);
                let fc = dist(dc.point, p);
                if fc.is_finite() && fc <= f {
                    uv = cand;
                    d = dc;
                    f = fc;
                    mu = (mu * 0.1).max(1e-12);
                    accepted = true;
                    // A near-Newton step that no longer moves: converged.
                    if step3 <= on_surface && mu <= 1e-2 {
                        return Some((uv, d.point, true));
                    }
                    break;
                }
                mu *= 10.0;
            }
            if !accepted {
                return Some((uv, d.point, false));
            }
        }
        Some((uv, d.point, false))
    }

    /// Best point of an n×n grid over the face bounds: a start for Newton.
    fn grid_seed(&self, p: Vec3, n: usize) -> ([f64; 2], f64) {
        let b = self.face_bounds;
        let mut best = (
            [0.5 * (b.umin + b.umax), 0.5 * (b.vmin + b.vmax)],
            f64::INFINITY,
        );
        for i in 0..=n {
            for j in 0..=n {
                let uv = [
                    b.umin + (b.umax - b.umin) * i as f64 / n as f64,
                    b.vmin + (b.vmax - b.vmin) * j as f64 / n as f64,
                ];
                let dd = dist(self.eval(uv), p);
                if dd < best.1 {
                    best = (uv, dd);
                }
            }
        }
        best
    }

    /// OCCT's global projection over the face bounds widened by 10 %.
    fn occt_project(&self, p: Vec3) -> Option<([f64; 2], Vec3)> {
        let b = self.face_bounds;
        let (wu, wv) = (0.1 * (b.umax - b.umin), 0.1 * (b.vmax - b.vmin));
        let nb = self.natural;
        let lo_u = if self.periods[0].is_some() {
            b.umin - wu
        } else {
            (b.umin - wu).max(nb.umin)
        };
        let hi_u = if self.periods[0].is_some() {
            b.umax + wu
        } else {
            (b.umax + wu).min(nb.umax)
        };
        let lo_v = if self.periods[1].is_some() {
            b.vmin - wv
        } else {
            (b.vmin - wv).max(nb.vmin)
        };
        let hi_v = if self.periods[1].is_some() {
            b.vmax + wv
        } else {
            (b.vmax + wv).min(nb.vmax)
        };
        let mut uv = [0.0; 2];
        let mut q = [0.0; 3];
        // SAFETY: live surface; p, uv, q are valid buffers of the right size.
        let rc = unsafe {
            ffi::occt_surf_project(
                self.ptr.ptr(),
                p.as_ptr(),
                lo_u,
                hi_u,
                lo_v,
                hi_v,
                uv.as_mut_ptr(),
                q.as_mut_ptr(),
            )
        };
        (rc == ffi::OK && uv[0].is_finite() && uv[1].is_finite()).then_some((uv, q))
    }
}

pub(crate) fn norm3(a: Vec3) -> f64 {
    dot(a, a).sqrt()
}

impl Surface for OcctSurface {
    fn eval(&self, uv: [f64; 2]) -> Vec3 {
        let mut o = [0.0; 3];
        // SAFETY: live surface, 3-element output buffer.
        let rc = unsafe { ffi::occt_surf_d0(self.ptr.ptr(), uv[0], uv[1], o.as_mut_ptr()) };
        if rc == ffi::OK {
            o
        } else {
            NAN3
        }
    }

    fn first_derivs(&self, uv: [f64; 2]) -> SurfaceDerivs {
        let [point, du, dv] = self.d1(uv).unwrap_or([NAN3; 3]);
        SurfaceDerivs {
            point,
            du,
            dv,
            duu: [0.0; 3],
            duv: [0.0; 3],
            dvv: [0.0; 3],
        }
    }

    fn derivs(&self, uv: [f64; 2]) -> SurfaceDerivs {
        let mut o = [f64::NAN; 18];
        // SAFETY: live surface, 18-element output buffer.
        let rc = unsafe { ffi::occt_surf_d2(self.ptr.ptr(), uv[0], uv[1], o.as_mut_ptr()) };
        if rc != ffi::OK {
            o = [f64::NAN; 18];
        }
        let v = |i: usize| [o[3 * i], o[3 * i + 1], o[3 * i + 2]];
        SurfaceDerivs {
            point: v(0),
            du: v(1),
            dv: v(2),
            duu: v(3),
            duv: v(4),
            dvv: v(5),
        }
    }

    /// `du × dv` normalised; at a singular point (a pole) the limit normal,
    /// taken a hair (1e-7 of the face's uv extent) towards the face centre.
    fn normal(&self, uv: [f64; 2]) -> Option<Vec3> {
        let [_, du, dv] = self.d1(uv)?;
        let n = cross(du, dv);
        // |du × dv| against |du|² + |dv|²: relative, so independent of scale.
        if norm3(n) > 1e-12 * (dot(du, du) + dot(dv, dv)) {
            if let Some(n) = normalize(n) {
                return Some(n);
            }
        }
        let b = self.face_bounds;
        let c = [0.5 * (b.umin + b.umax), 0.5 * (b.vmin + b.vmax)];
        for eps in [1e-7, 1e-5] {
            let q = [uv[0] + eps * (c[0] - uv[0]), uv[1] + eps * (c[1] - uv[1])];
            if let Some([_, du, dv]) = self.d1(q) {
                if let Some(n) = normalize(cross(du, dv)) {
                    return Some(n);
                }
            }
        }
        None
    }

    fn uv_bounds(&self) -> Bounds2 {
        self.face_bounds
    }

    fn periods(&self) -> [Option<f64>; 2] {
        self.periods
    }

    /// Newton from `hint` (or from a 9×9 grid over the face bounds); OCCT's
    /// global projector when Newton fails or, without hint, when the point is
    /// not on the surface (then the better of the two answers).
    /// Periodic coordinates come back nearest the hint, else inside the face
    /// range.
    fn project(&self, p: Vec3, hint: Option<[f64; 2]>) -> Option<([f64; 2], Vec3)> {
        if !(p[0].is_finite() && p[1].is_finite() && p[2].is_finite()) {
            return None;
        }
        let b = self.face_bounds;
        let centre = [0.5 * (b.umin + b.umax), 0.5 * (b.vmin + b.vmax)];
        let start = match hint {
            Some(h) if h[0].is_finite() && h[1].is_finite() => h,
            _ => self.grid_seed(p, 8).0,
        };
        let target = hint.unwrap_or(centre);
        let mut best: Option<([f64; 2], Vec3, f64)> = None;
        let mut good = false;
        if let Some((uv, q, conv)) = self.newton(p, start) {
            let dq = dist(p, q);
            if dq.is_finite() {
                best = Some((uv, q, dq));
                // On the surface: certainly the answer. Off it, a stationary
                // point is accepted near a hint; without one, OCCT's global
                // search decides.
                good = dq <= 1e-9 * self.size || (conv && hint.is_some());
            }
        }
        if !good {
            if let Some((uv, q)) = self.occt_project(p) {
                let dq = dist(p, q);
                if best.map(|b| dq < b.2).unwrap_or(true) {
                    best = Some((uv, q, dq));
                }
            }
        }
        best.map(|(uv, q, _)| (self.wrap(uv, target), q))
    }
}

/// The 3D curve of an edge: an OCCT `Geom_Curve` (location applied),
/// restricted to the edge's parameter range.
#[derive(Debug)]
pub struct OcctCurve {
    ptr: CurvePtr,
    range: (f64, f64),
    size: f64,
}

impl OcctCurve {
    /// Wraps a shim curve used on `range`.
    pub(crate) fn new(ptr: CurvePtr, range: (f64, f64)) -> Self {
        let mut c = OcctCurve {
            ptr,
            range,
            size: 1.0,
        };
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for i in 0..=8 {
            let p = c.eval(range.0 + (range.1 - range.0) * i as f64 / 8.0);
            for k in 0..3 {
                if p[k].is_finite() {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
            }
        }
        let d = dist(lo, hi);
        c.size = if d.is_finite() && d > 0.0 { d } else { 1.0 };
        c
    }

    fn d2(&self, t: f64) -> Option<[Vec3; 3]> {
        let mut o = [0.0; 9];
        // SAFETY: live curve, 9-element output buffer.
        let rc = unsafe { ffi::occt_curve_d2(self.ptr.ptr(), t, o.as_mut_ptr()) };
        (rc == ffi::OK).then(|| [[o[0], o[1], o[2]], [o[3], o[4], o[5]], [o[6], o[7], o[8]]])
    }

    fn d1(&self, t: f64) -> Option<[Vec3; 2]> {
        let mut o = [0.0; 6];
        // SAFETY: live curve, 6-element output buffer.
        let rc = unsafe { ffi::occt_curve_d1(self.ptr.ptr(), t, o.as_mut_ptr()) };
        (rc == ffi::OK).then(|| [[o[0], o[1], o[2]], [o[3], o[4], o[5]]])
    }
}

impl Curve for OcctCurve {
    fn eval(&self, t: f64) -> Vec3 {
        self.d1(t).map_or(NAN3, |d| d[0])
    }
    fn deriv(&self, t: f64) -> Vec3 {
        self.d1(t).map_or(NAN3, |d| d[1])
    }
    fn range(&self) -> (f64, f64) {
        self.range
    }
    /// Newton from `hint` (or the best of 33 samples), clamped to the range;
    /// OCCT's `GeomAPI_ProjectPointOnCurve` when Newton fails, or when the
    /// point is off the curve and no hint says which local minimum is wanted.
    fn project(&self, p: Vec3, hint: Option<f64>) -> Option<(f64, Vec3)> {
        if !(p[0].is_finite() && p[1].is_finite() && p[2].is_finite()) {
            return None;
        }
        let (t0, t1) = self.range;
        let ev = |t: f64| self.d2(t);
        let seed = match hint {
            Some(h) if h.is_finite() => h.clamp(t0, t1),
            _ => sample_seed(|t| self.eval(t), p, t0, t1, 32).0,
        };
        let newton = newton_1d(ev, p, seed, t0, t1, self.size);
        let mut best = None;
        let mut good = false;
        if let Some((t, q, conv)) = newton {
            let dq = dist(p, q);
            best = Some((t, q, dq));
            good = dq <= 1e-9 * self.size || (conv && hint.is_some());
        }
        if !good {
            let mut t = 0.0;
            let mut q = [0.0; 3];
            // SAFETY: live curve; p, q valid 3-element buffers.
            let rc = unsafe {
                ffi::occt_curve_project(self.ptr.ptr(), p.as_ptr(), t0, t1, &mut t, q.as_mut_ptr())
            };
            if rc == ffi::OK && t.is_finite() {
                let dq = dist(p, q);
                if best.map(|b: (f64, Vec3, f64)| dq < b.2).unwrap_or(true) {
                    best = Some((t, q, dq));
                }
            }
        }
        best.map(|(t, q, _)| (t, q))
    }
}

/// Best of `n + 1` uniform samples of a curve on [t0, t1].
fn sample_seed(eval: impl Fn(f64) -> Vec3, p: Vec3, t0: f64, t1: f64, n: usize) -> (f64, f64) {
    let mut best = (t0, f64::INFINITY);
    for i in 0..=n {
        let t = t0 + (t1 - t0) * i as f64 / n as f64;
        let dd = dist(eval(t), p);
        if dd < best.1 {
            best = (t, dd);
        }
    }
    best
}

/// Damped Newton on ½|C(t) − p|² over [t0, t1]; `ev` gives C, C', C''.
/// Converged when C(t) = p to round-off, at a stationary point, or stopped
/// at an end of the range with the distance growing inwards.
fn newton_1d(
    ev: impl Fn(f64) -> Option<[Vec3; 3]>,
    p: Vec3,
    start: f64,
    t0: f64,
    t1: f64,
    size: f64,
) -> Option<(f64, Vec3, bool)> {
    let mut t = start.clamp(t0, t1);
    let mut d = ev(t)?;
    let mut f = dist(d[0], p);
    if !f.is_finite() {
        return None;
    }
    let on_curve = 1e-14 * size + 1e-15 * norm3(p);
    for _ in 0..60 {
        let r = sub(d[0], p);
        let g = dot(r, d[1]);
        let n1 = norm3(d[1]);
        let at_end = (t <= t0 && g >= 0.0) || (t >= t1 && g <= 0.0);
        if f <= on_curve || g.abs() <= 1e-10 * f * n1 || at_end {
            return Some((t, d[0], true));
        }
        let h = dot(d[1], d[1]) + dot(r, d[2]);
        let h = if h > 0.0 { h } else { (n1 * n1).max(1e-300) };
        let mut step = -g / h;
        let mut accepted = false;
        for _ in 0..30 {
            let tc = (t + step).clamp(t0, t1);
            let step3 = n1 * (tc - t).abs();
            let dc = ev(tc)?;
            let fc = dist(dc[0], p);
            if fc.is_finite() && fc <= f {
                t = tc;
                d = dc;
                f = fc;
                accepted = true;
                if step3 <= on_curve {
                    return Some((t, d[0], true));
                }
                break;
            }
            step *= 0.5;
        }
        if !accepted {
            return Some((t, d[0], false));
        }
    }
    Some((t, d[0], false))
}

/// A pcurve of an edge in a face's (u, v): an OCCT `Geom2d_Curve`, optionally
/// reparametrised linearly so that it shares the parameter of its edge when
/// OCCT stores it on a different range.
#[derive(Debug)]
pub struct OcctCurve2d {
    ptr: Curve2dPtr,
    /// Maps the edge parameter t to the pcurve parameter `a + b t`.
    map: (f64, f64),
}

impl OcctCurve2d {
    /// Wraps a shim pcurve stored on `pc_range`, used for an edge on `edge_range`.
    pub(crate) fn new(ptr: Curve2dPtr, pc_range: (f64, f64), edge_range: (f64, f64)) -> Self {
        let (e0, e1) = edge_range;
        let (p0, p1) = pc_range;
        let same = (p0 - e0).abs() <= 1e-12 * (1.0 + e0.abs())
            && (p1 - e1).abs() <= 1e-12 * (1.0 + e1.abs());
        let map = if same
            || e1.partial_cmp(&e0) != Some(std::cmp::Ordering::Greater)
            || p1.partial_cmp(&p0) != Some(std::cmp::Ordering::Greater)
        {
            (0.0, 1.0)
        } else {
            let b = (p1 - p0) / (e1 - e0);
            (p0 - b * e0, b)
        };
        OcctCurve2d { ptr, map }
    }

    fn d1(&self, t: f64) -> Option<[f64; 4]> {
        let s = self.map.0 + self.map.1 * t;
        let mut o = [0.0; 4];
        // SAFETY: live pcurve, 4-element output buffer.
        let rc = unsafe { ffi::occt_curve2d_d1(self.ptr.ptr(), s, o.as_mut_ptr()) };
        (rc == ffi::OK).then_some([o[0], o[1], o[2] * self.map.1, o[3] * self.map.1])
    }
}

impl Curve2d for OcctCurve2d {
    fn eval(&self, t: f64) -> [f64; 2] {
        self.d1(t).map_or([f64::NAN; 2], |o| [o[0], o[1]])
    }
    fn deriv(&self, t: f64) -> [f64; 2] {
        self.d1(t).map_or([f64::NAN; 2], |o| [o[2], o[3]])
    }
}

/// The 3D geometry of an edge that OCCT stores only as a pcurve: S(c(t)).
#[derive(Debug)]
pub struct PcurveOnSurface {
    /// The surface of a face using the edge.
    pub surface: Arc<OcctSurface>,
    /// The edge's pcurve on that face.
    pub pcurve: Arc<OcctCurve2d>,
    /// Parameter range of the edge.
    pub range: (f64, f64),
}

impl Curve for PcurveOnSurface {
    fn eval(&self, t: f64) -> Vec3 {
        self.surface.eval(self.pcurve.eval(t))
    }
    fn deriv(&self, t: f64) -> Vec3 {
        let uv = self.pcurve.eval(t);
        let duv = self.pcurve.deriv(t);
        match self.surface.d1(uv) {
            Some([_, du, dv]) => add(scale(du, duv[0]), scale(dv, duv[1])),
            None => NAN3,
        }
    }
    fn range(&self) -> (f64, f64) {
        self.range
    }
    /// Best of 64 samples refined by a golden-section search.
    fn project(&self, p: Vec3, hint: Option<f64>) -> Option<(f64, Vec3)> {
        let (t0, t1) = self.range;
        let n = 64;
        let (seed, _) = sample_seed(|t| self.eval(t), p, t0, t1, n);
        let h = (t1 - t0) / n as f64;
        let (mut a, mut b) = match hint {
            Some(x) if x.is_finite() => ((x - h).max(t0), (x + h).min(t1)),
            _ => ((seed - h).max(t0), (seed + h).min(t1)),
        };
        let g = 0.5 * (5f64.sqrt() - 1.0);
        let f = |t: f64| dist(self.eval(t), p);
        for _ in 0..100 {
            let c = b - g * (b - a);
            let d = a + g * (b - a);
            if f(c) < f(d) {
                b = d;
            } else {
                a = c;
            }
        }
        let t = 0.5 * (a + b);
        let q = self.eval(t);
        q[0].is_finite().then_some((t, q))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Newton on a unit circle: off-curve points project radially, and the
    /// range clamps (a point beyond the end projects to the end).
    #[test]
    fn newton_1d_on_a_circle() {
        let ev = |t: f64| {
            Some([
                [t.cos(), t.sin(), 0.0],
                [-t.sin(), t.cos(), 0.0],
                [-t.cos(), -t.sin(), 0.0],
            ])
        };
        let (t, q, conv) = newton_1d(
            ev,
            [2.0 * 0.7f64.cos(), 2.0 * 0.7f64.sin(), 0.5],
            0.2,
            0.0,
            3.0,
            2.0,
        )
        .unwrap();
        assert!(conv && (t - 0.7).abs() < 1e-12, "{t}");
        assert!(dist(q, [0.7f64.cos(), 0.7f64.sin(), 0.0]) < 1e-12);
        let (t, _, conv) =
            newton_1d(ev, [3.5f64.cos(), 3.5f64.sin(), 0.0], 2.5, 0.0, 3.0, 2.0).unwrap();
        assert!(conv && t == 3.0, "{t}");
    }
}
