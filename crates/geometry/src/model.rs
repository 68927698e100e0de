//! The B-rep [`Model`]: corners, curves and faces with their boundary loops.
//!
//! Conventions (every producer of a `Model` must follow them; tests check them):
//! - Ids are dense indices into `Model::corners`, `Model::curves`, `Model::faces`.
//!   File formats that number entities from 1 use `id + 1`.
//! - A curve runs from `start` (at `range.0`) to `end` (at `range.1`); a closed
//!   curve has `start == end`. A degenerate curve (a pole of a sphere) has no 3D
//!   geometry: it is a single point, but its pcurves are segments in (u, v).
//! - Each face loop lists curve uses in order. A use traverses its pcurve from
//!   `range.0` to `range.1` when `forward`, else backwards. Traversed this way,
//!   **the face material lies to the left in the (u, v) plane**: the outer loop
//!   has positive signed uv area, holes negative. Consecutive uses meet in uv
//!   (up to tolerance); on periodic surfaces a seam curve appears twice in the
//!   same loop, once with each orientation, on opposite sides of the period.
//! - The face's oriented normal is `du × dv`, negated when `reversed`: it is the
//!   normal consistent with the face's orientation in its shell (outward for a
//!   solid as written by the CAD system).
//! - At a singular point of a face (a node on a degenerate curve: a sphere pole,
//!   a cone apex; or any (u, v) where `du × dv` vanishes) the normal of an
//!   element corner is the limit normal approached from inside the element
//!   ([`Face::corner_normal`]): at a cone apex it depends on the direction, and
//!   a (u, v) a rounding error past the apex lies on the other nappe, where
//!   `du × dv` is reversed.

use std::sync::Arc;

use crate::traits::{Curve, Curve2d, Surface, SurfaceDerivs};
use crate::vec3::{self, Vec3};

macro_rules! id_type {
    ($(#[$m:meta])* $name:ident) => {
        $(#[$m])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub struct $name(pub u32);
        impl $name {
            /// The id as a `usize` index.
            #[inline]
            pub fn idx(self) -> usize {
                self.0 as usize
            }
        }
    };
}
id_type!(
    /// Index of a corner (a B-rep vertex) in `Model::corners`.
    CornerId
);
id_type!(
    /// Index of a curve (a B-rep edge) in `Model::curves`.
    CurveId
);
id_type!(
    /// Index of a face in `Model::faces`.
    FaceId
);

/// An axis-aligned box in the (u, v) plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds2 {
    /// Lower u.
    pub umin: f64,
    /// Upper u.
    pub umax: f64,
    /// Lower v.
    pub vmin: f64,
    /// Upper v.
    pub vmax: f64,
}

/// A B-rep vertex.
#[derive(Clone, Debug)]
pub struct Corner {
    /// Its position.
    pub point: Vec3,
}

/// A B-rep edge: a 3D curve restricted to a parameter range, between two corners.
#[derive(Clone, Debug)]
pub struct CurveEntity {
    /// The 3D geometry; `None` for a degenerate curve (a point).
    pub geom: Option<Arc<dyn Curve>>,
    /// Parameter range used by the edge, `range.0 < range.1`.
    pub range: (f64, f64),
    /// Corner at `range.0`.
    pub start: CornerId,
    /// Corner at `range.1`.
    pub end: CornerId,
    /// True for a degenerate edge (zero length, e.g. a sphere pole).
    pub degenerate: bool,
}

impl CurveEntity {
    /// C(t); a degenerate curve evaluates to its start corner's point.
    pub fn eval(&self, model: &Model, t: f64) -> Vec3 {
        match &self.geom {
            Some(g) => g.eval(t),
            None => model.corners[self.start.idx()].point,
        }
    }
}

/// One use of a curve by a face loop, with the pcurve in that face's (u, v).
#[derive(Clone, Debug)]
pub struct CurveUse {
    /// The curve used.
    pub curve: CurveId,
    /// True when the loop traverses the curve from `range.0` to `range.1`.
    pub forward: bool,
    /// The curve's image in the face's parameter plane, sharing its parameter.
    pub pcurve: Arc<dyn Curve2d>,
    /// True when this curve is a seam of this face (it appears twice in the face).
    pub seam: bool,
}

/// A closed boundary loop of a face.
#[derive(Clone, Debug)]
pub struct Loop {
    /// Curve uses in traversal order.
    pub uses: Vec<CurveUse>,
    /// True for the outer loop (one per face), false for holes.
    pub outer: bool,
}

/// A B-rep face: a trimmed surface.
#[derive(Clone, Debug)]
pub struct Face {
    /// The underlying surface.
    pub surface: Arc<dyn Surface>,
    /// True when the face normal is opposite to `du × dv`.
    pub reversed: bool,
    /// Boundary loops: the outer one first, then holes.
    pub loops: Vec<Loop>,
    /// Bounds of the trimmed face in (u, v).
    pub uv_bounds: Bounds2,
}

impl Face {
    /// The (u, v) segment that maps to the pole of degenerate curve use `u`: its
    /// pcurve, widened to the face's whole (u, v) range when it runs along an
    /// iso-line. A cone apex's pcurve may cover only part of the face's u range
    /// (i04o_m4: a half cone whose apex pcurve spans a quarter turn, the next
    /// generatrix's pcurve starting from its end), yet every point of that
    /// iso-line is the apex; seen from an interior node the pole must sit at the
    /// node's own u, or the edges to it spiral across the surface.
    pub fn pole_segment(&self, u: &CurveUse, ce: &CurveEntity) -> [[f64; 2]; 2] {
        let a = u.pcurve.eval(ce.range.0);
        let b = u.pcurve.eval(ce.range.1);
        let bd = self.uv_bounds;
        let tol = 1e-9 * ((bd.umax - bd.umin).abs() + (bd.vmax - bd.vmin).abs()).max(1e-300);
        let finite = [bd.umin, bd.umax, bd.vmin, bd.vmax]
            .iter()
            .all(|x| x.is_finite());
        if !finite {
            return [a, b];
        }
        // keep the pcurve's direction so the segment is traversed the same way
        let span = |x: f64, y: f64, min: f64, max: f64| {
            if x <= y {
                (min.min(x), max.max(y))
            } else {
                (max.max(x), min.min(y))
            }
        };
        if (a[1] - b[1]).abs() <= tol {
            let (u0, u1) = span(a[0], b[0], bd.umin, bd.umax);
            [[u0, a[1]], [u1, b[1]]]
        } else if (a[0] - b[0]).abs() <= tol {
            let (v0, v1) = span(a[1], b[1], bd.vmin, bd.vmax);
            [[a[0], v0], [b[0], v1]]
        } else {
            [a, b]
        }
    }

    /// Unit normal with the face's orientation, or `None` at a singular point.
    pub fn normal(&self, uv: [f64; 2]) -> Option<Vec3> {
        let n = self.surface.normal(uv)?;
        Some(if self.reversed {
            vec3::scale(n, -1.0)
        } else {
            n
        })
    }

    /// Largest angle (radians) between the limit normals along pole segment
    /// `seg` ([`Face::pole_segment`]), sampled at [`POLE_SPREAD_SAMPLES`]
    /// points each taken just inside the face: 0 at a sphere's pole, where
    /// every direction sees one tangent plane; π − 2α at the apex of a cone
    /// of half-angle α spanning half a turn or more, whose normal turns with
    /// the generatrix. A single quad cornered at a pole with a large spread
    /// folds. `None` when a normal is undefined.
    pub fn pole_normal_spread(&self, seg: [[f64; 2]; 2]) -> Option<f64> {
        let b = self.uv_bounds;
        let centre = [0.5 * (b.umin + b.umax), 0.5 * (b.vmin + b.vmax)];
        let mid = [0.5 * (seg[0][0] + seg[1][0]), 0.5 * (seg[0][1] + seg[1][1])];
        // each sample steps inside parallel to the midpoint → centre direction
        let inward = [centre[0] - mid[0], centre[1] - mid[1]];
        let mut normals = Vec::with_capacity(POLE_SPREAD_SAMPLES);
        for i in 0..POLE_SPREAD_SAMPLES {
            let t = i as f64 / (POLE_SPREAD_SAMPLES - 1) as f64;
            let p = [
                seg[0][0] + t * (seg[1][0] - seg[0][0]) + POLE_OFFSET * inward[0],
                seg[0][1] + t * (seg[1][1] - seg[0][1]) + POLE_OFFSET * inward[1],
            ];
            normals.push(self.normal(p)?);
        }
        let mut spread = 0.0f64;
        for (i, a) in normals.iter().enumerate() {
            for c in &normals[i + 1..] {
                spread = spread.max(vec3::dot(*a, *c).clamp(-1.0, 1.0).acos());
            }
        }
        spread.is_finite().then_some(spread)
    }

    /// The largest absolute principal curvature of the surface at `uv`
    /// (1 / radius: 1/R on a sphere or a cylinder of radius R, 0 on a plane),
    /// from the first and second fundamental forms; `None` at a singular
    /// point or where the derivatives are not finite. The size map bounds
    /// the quad size on curved faces with it.
    pub fn max_curvature(&self, uv: [f64; 2]) -> Option<f64> {
        let d = self.surface.derivs(uv);
        let n = self.regular_normal_from(&d)?;
        let (e, f, g) = (
            vec3::dot(d.du, d.du),
            vec3::dot(d.du, d.dv),
            vec3::dot(d.dv, d.dv),
        );
        let (l, m, nn) = (
            vec3::dot(d.duu, n),
            vec3::dot(d.duv, n),
            vec3::dot(d.dvv, n),
        );
        let det = e * g - f * f;
        if !(det > 0.0) {
            return None;
        }
        // mean and Gaussian curvature; the principal ones are H ± √(H² − K)
        let mean = (e * nn - 2.0 * f * m + g * l) / (2.0 * det);
        let gauss = (l * nn - m * m) / det;
        let k = mean.abs() + (mean * mean - gauss).max(0.0).sqrt();
        k.is_finite().then_some(k)
    }

    /// All curves bounding this face (a seam appears twice).
    pub fn curve_uses(&self) -> impl Iterator<Item = &CurveUse> {
        self.loops.iter().flat_map(|l| l.uses.iter())
    }

    /// True when (u, v) is a singular point of the parametrization: `|du × dv|`
    /// below [`SINGULAR_RATIO`] `· (|du|² + |dv|²)` (scale-free), or the
    /// derivatives are not finite there.
    pub fn is_singular(&self, uv: [f64; 2]) -> bool {
        let ratio = singular_ratio(&self.surface.first_derivs(uv));
        ratio.is_nan() || ratio < SINGULAR_RATIO
    }

    /// [`Face::corner_normal`] of an element corner at the ordinary point
    /// `uv`, or `None` when `uv` is a singular point (there the corner normal
    /// depends on the element: ask [`Face::corner_normal`]). At an ordinary
    /// point the corner normal depends on `uv` alone, so callers that
    /// evaluate many elements around fixed nodes may keep it per node.
    pub fn regular_normal(&self, uv: [f64; 2]) -> Option<Vec3> {
        self.regular_normal_from(&self.surface.first_derivs(uv))
    }

    /// [`Face::regular_normal`] from the derivatives at the point, for
    /// callers that have them at hand.
    pub fn regular_normal_from(&self, d: &SurfaceDerivs) -> Option<Vec3> {
        let regular = singular_ratio(d) >= SINGULAR_RATIO; // false for NaN
        if !regular {
            return None;
        }
        let n = vec3::normalize(vec3::cross(d.du, d.dv))?;
        Some(if self.reversed {
            vec3::scale(n, -1.0)
        } else {
            n
        })
    }

    /// Oriented unit normal at an element corner: the reference normal `N_i`
    /// of the corner's SICN (Eq. 12 of the quasi-structured paper), shared by
    /// the mesher's quality checks and the mesh statistics.
    ///
    /// `centre` is a (u, v) point inside the element (its (u, v) centre), on
    /// the same side of any seam as the corner. At an ordinary point this is
    /// [`Face::normal`]. At a singular point, a [`CornerUv::Pole`] or a point
    /// where [`Face::is_singular`], the normal there is undefined or depends on
    /// the direction of approach (at a cone apex it does; and a (u, v) a
    /// rounding error past the apex, as the pcurves of OpenCASCADE's degenerate
    /// edges can be, lies on the other nappe where `du × dv` is reversed): it
    /// is the limit normal approached from the element, taken [`POLE_OFFSET`]
    /// of the way from the corner toward `centre`. A pole is first slid along
    /// its segment to the point nearest `centre`; so is a singular `Point`
    /// along the parameter whose derivative vanishes there (its pole segment
    /// is not known). Falls back to the normal at `centre`; `None` when that
    /// is undefined too.
    ///
    /// At a [`CornerUv::Curve`] corner (a node on a CAD curve of the face)
    /// whose normal makes more than 90° ([`FOLD_COS`]) with the normal at
    /// `centre`, the surface folds back between the curve and the element's
    /// centre over less than the element's width (a rounded trailing edge a
    /// fraction of the quad size thick): the element does not resolve that
    /// bend, the curve is a crease at its scale, and the corner's normal is
    /// the one at `centre`, the surface as seen from the element's side. On
    /// a surface that does not fold within an element this changes nothing,
    /// and an element inverted against a smooth surface stays inverted (its
    /// corner and centre normals agree).
    pub fn corner_normal(&self, at: CornerUv, centre: [f64; 2]) -> Option<Vec3> {
        let mut p = at.toward(centre);
        if let CornerUv::Point(_) | CornerUv::Curve(_) = at {
            let d = self.surface.first_derivs(p);
            if let Some(n) = self.regular_normal_from(&d) {
                if let CornerUv::Curve(_) = at {
                    // a bend narrower than the element at its boundary: the
                    // element sees the surface from its own side
                    if let Some(nc) = self.normal(centre) {
                        if vec3::dot(n, nc) < FOLD_COS {
                            return Some(nc);
                        }
                    }
                }
                return Some(n);
            }
            let (uu, vv) = (vec3::dot(d.du, d.du), vec3::dot(d.dv, d.dv));
            if singular_ratio(&d) >= SINGULAR_RATIO {
                // regular but du × dv does not normalize: the fallbacks below
            } else if uu < 1e-6 * vv {
                p[0] = centre[0];
            } else if vv < 1e-6 * uu {
                p[1] = centre[1];
            }
        }
        let w = [
            p[0] + POLE_OFFSET * (centre[0] - p[0]),
            p[1] + POLE_OFFSET * (centre[1] - p[1]),
        ];
        self.normal(w).or_else(|| self.normal(centre))
    }
}

/// `|du × dv| / (|du|² + |dv|²)` below which a (u, v) is a singular point of
/// the parametrization ([`Face::is_singular`]).
pub const SINGULAR_RATIO: f64 = 1e-9;

/// `|du × dv| / (|du|² + |dv|²)`: 0 at a singular point, at most ½ (NaN when
/// the derivatives are not finite).
fn singular_ratio(d: &SurfaceDerivs) -> f64 {
    vec3::norm(vec3::cross(d.du, d.dv)) / (vec3::dot(d.du, d.du) + vec3::dot(d.dv, d.dv))
}

/// Samples of [`Face::pole_normal_spread`] along a pole segment.
pub const POLE_SPREAD_SAMPLES: usize = 9;

/// Cosine of the angle between the normal at a [`CornerUv::Curve`] corner
/// and at its element's centre beyond which [`Face::corner_normal`] takes the
/// centre's (0: more than 90°, the surface folds back inside the element).
pub const FOLD_COS: f64 = 0.0;

/// Fraction of the way from a singular element corner toward the element's
/// (u, v) centre at which [`Face::corner_normal`] takes its limit normal.
pub const POLE_OFFSET: f64 = 1e-3;

/// Where an element corner lies in its face's (u, v) plane, for
/// [`Face::corner_normal`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CornerUv {
    /// A point of the parameter plane.
    Point([f64; 2]),
    /// A point of the parameter plane on a CAD curve bounding the face (a
    /// curve or corner node): like [`CornerUv::Point`], except where the
    /// surface folds back inside the element ([`Face::corner_normal`]).
    Curve([f64; 2]),
    /// A pole: the corner lies on a degenerate curve of the face (a sphere
    /// pole, a cone apex), whose whole (u, v) segment maps to that 3D point.
    Pole([[f64; 2]; 2]),
}

impl CornerUv {
    /// The corner's (u, v) seen from `other`: the point itself, or the point of
    /// the pole's segment nearest to `other`.
    pub fn toward(self, other: [f64; 2]) -> [f64; 2] {
        match self {
            CornerUv::Point(p) | CornerUv::Curve(p) => p,
            CornerUv::Pole([p, q]) => {
                let d = [q[0] - p[0], q[1] - p[1]];
                let dd = d[0] * d[0] + d[1] * d[1];
                let s = if dd > 0.0 {
                    (((other[0] - p[0]) * d[0] + (other[1] - p[1]) * d[1]) / dd).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                [p[0] + s * d[0], p[1] + s * d[1]]
            }
        }
    }
}

/// Error found while building or checking a [`Model`].
#[derive(Debug, thiserror::Error)]
pub enum ModelError {
    /// An id points past the end of its list.
    #[error("{0}")]
    BadReference(String),
}

/// A boundary-representation model: what every mesher in Quadrille consumes.
#[derive(Clone, Debug, Default)]
pub struct Model {
    /// B-rep vertices.
    pub corners: Vec<Corner>,
    /// B-rep edges.
    pub curves: Vec<CurveEntity>,
    /// B-rep faces.
    pub faces: Vec<Face>,
}

impl CurveUse {
    /// `n + 1` points of the pcurve in traversal order (`n ≥ 1` segments,
    /// uniform in the curve parameter over `range`).
    pub fn uv_polyline(&self, range: (f64, f64), n: usize) -> Vec<[f64; 2]> {
        let n = n.max(1);
        (0..=n)
            .map(|i| {
                let s = i as f64 / n as f64;
                let s = if self.forward { s } else { 1.0 - s };
                self.pcurve.eval(range.0 + s * (range.1 - range.0))
            })
            .collect()
    }
}

impl Model {
    /// Axis-aligned bounding box `(min, max)` of corners and sampled curves and faces.
    pub fn bounding_box(&self) -> (Vec3, Vec3) {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        let mut grow = |p: Vec3| {
            for k in 0..3 {
                if p[k].is_finite() {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
            }
        };
        for c in &self.corners {
            grow(c.point);
        }
        for c in &self.curves {
            if let Some(g) = &c.geom {
                for i in 0..=16 {
                    grow(g.eval(c.range.0 + (c.range.1 - c.range.0) * i as f64 / 16.0));
                }
            }
        }
        for f in &self.faces {
            let b = f.uv_bounds;
            for i in 0..=8 {
                for j in 0..=8 {
                    let u = b.umin + (b.umax - b.umin) * i as f64 / 8.0;
                    let v = b.vmin + (b.vmax - b.vmin) * j as f64 / 8.0;
                    grow(f.surface.eval([u, v]));
                }
            }
        }
        if lo[0] > hi[0] {
            return ([0.0; 3], [0.0; 3]);
        }
        (lo, hi)
    }

    /// Length of the bounding-box diagonal: the model's length scale.
    pub fn diagonal(&self) -> f64 {
        let (lo, hi) = self.bounding_box();
        vec3::dist(lo, hi)
    }

    /// For each curve, the faces that use it (a face using a seam is listed once).
    pub fn curve_faces(&self) -> Vec<Vec<FaceId>> {
        let mut out = vec![Vec::new(); self.curves.len()];
        for (fi, f) in self.faces.iter().enumerate() {
            for u in f.curve_uses() {
                let list: &mut Vec<FaceId> = &mut out[u.curve.idx()];
                if !list.contains(&FaceId(fi as u32)) {
                    list.push(FaceId(fi as u32));
                }
            }
        }
        out
    }

    /// The closed polyline of loop `loop_idx` of face `face` in (u, v), with
    /// `samples_per_use` segments per curve use. The last point equals the first
    /// only up to tolerance (the polyline is returned open: no repeated point).
    pub fn loop_uv_polyline(
        &self,
        face: FaceId,
        loop_idx: usize,
        samples_per_use: usize,
    ) -> Vec<[f64; 2]> {
        let f = &self.faces[face.idx()];
        let mut pts = Vec::new();
        for u in &f.loops[loop_idx].uses {
            let c = &self.curves[u.curve.idx()];
            let mut seg = u.uv_polyline(c.range, samples_per_use);
            seg.pop();
            pts.extend(seg);
        }
        pts
    }

    /// The (u, v) segments of the degenerate curves of `face` at `corner`, each
    /// mapping entirely to the corner (empty when the corner is no pole of
    /// the face). Each segment runs from the pcurve at `range.0` toward
    /// `range.1`, widened as [`Face::pole_segment`] says.
    pub fn pole_segments(&self, face: FaceId, corner: CornerId) -> Vec<[[f64; 2]; 2]> {
        let Some(f) = self.faces.get(face.idx()) else {
            return Vec::new();
        };
        f.curve_uses()
            .filter_map(|u| {
                let c = self.curves.get(u.curve.idx())?;
                (c.degenerate && (c.start == corner || c.end == corner))
                    .then(|| f.pole_segment(u, c))
            })
            .collect()
    }

    /// Checks that every id refers to an existing entity.
    pub fn validate(&self) -> Result<(), ModelError> {
        for (i, c) in self.curves.iter().enumerate() {
            if c.start.idx() >= self.corners.len() || c.end.idx() >= self.corners.len() {
                return Err(ModelError::BadReference(format!(
                    "curve {} refers to a missing corner",
                    i + 1
                )));
            }
        }
        for (i, f) in self.faces.iter().enumerate() {
            for u in f.curve_uses() {
                if u.curve.idx() >= self.curves.len() {
                    return Err(ModelError::BadReference(format!(
                        "face {} refers to a missing curve",
                        i + 1
                    )));
                }
            }
        }
        Ok(())
    }
}

/// Signed area of a closed polygon in the plane (positive when counter-clockwise).
pub fn signed_area(poly: &[[f64; 2]]) -> f64 {
    let n = poly.len();
    let mut a = 0.0;
    for i in 0..n {
        let p = poly[i];
        let q = poly[(i + 1) % n];
        a += p[0] * q[1] - q[0] * p[1];
    }
    0.5 * a
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::primitives::cone;

    /// The generatrix normal of `primitives::cone(1, 1)` at angle u.
    fn cone_normal(u: f64) -> Vec3 {
        let s = std::f64::consts::FRAC_1_SQRT_2;
        [s * u.cos(), s * u.sin(), -s]
    }

    #[test]
    fn a_curve_corner_takes_the_centre_normal_only_where_the_surface_folds_back() {
        let m = crate::primitives::sphere(1.0);
        let f = &m.faces[0];
        let at = [0.0, 0.0];
        let n = f.normal(at).unwrap();
        assert!(vec3::dist(vec3::scale(n, n[0].signum()), [1.0, 0.0, 0.0]) < 1e-9);
        // the element's centre on the far side of the sphere: the normals are
        // opposite, the surface turns by 180° between corner and centre
        let far = [std::f64::consts::PI, 0.0];
        let nf = f.normal(far).unwrap();
        assert!(vec3::dot(n, nf) < -0.999);
        assert_eq!(f.corner_normal(CornerUv::Curve(at), far), Some(nf));
        // an interior point keeps its own normal, whatever the element
        assert_eq!(f.corner_normal(CornerUv::Point(at), far), Some(n));
        // a centre 60° away: no fold, the corner's own normal
        let near = [std::f64::consts::FRAC_PI_3, 0.0];
        assert!(vec3::dot(n, f.normal(near).unwrap()) > 0.49);
        assert_eq!(f.corner_normal(CornerUv::Curve(at), near), Some(n));
    }

    #[test]
    fn corner_normal_at_a_cone_apex_is_the_limit_from_the_element() {
        let m = cone(1.0, 1.0);
        let f = &m.faces[0];
        let seg = m.pole_segments(FaceId(0), CornerId(0));
        assert_eq!(seg.len(), 1);
        assert!(m.pole_segments(FaceId(0), CornerId(1)).is_empty());
        let va = f.uv_bounds.vmin;
        for u in [0.3, 2.0, 4.5] {
            let n = f
                .corner_normal(CornerUv::Pole(seg[0]), [u, 0.5 * va])
                .unwrap();
            assert!(vec3::dist(n, cone_normal(u)) < 1e-9, "u {u}: {n:?}");
        }
    }

    #[test]
    fn corner_normal_just_past_a_cone_apex_is_not_flipped() {
        let m = cone(1.0, 1.0);
        let f = &m.faces[0];
        let va = f.uv_bounds.vmin;
        // a pcurve end a rounding error beyond the apex, as OpenCASCADE's are:
        // du × dv there belongs to the other nappe
        let past = [1.0, va - 1e-12];
        assert!(f.is_singular(past));
        let wrong = f.normal(past).unwrap();
        assert!(vec3::dot(wrong, cone_normal(1.0)) < -0.99);
        let n = f
            .corner_normal(CornerUv::Point(past), [2.0, 0.5 * va])
            .unwrap();
        assert!(vec3::dot(n, cone_normal(2.0)) > 1.0 - 1e-6, "{n:?}");
        // an ordinary point: the face normal
        let uv = [1.0, 0.5 * va];
        assert!(!f.is_singular(uv));
        assert_eq!(
            f.corner_normal(CornerUv::Point(uv), [2.0, 0.4 * va]),
            f.normal(uv)
        );
    }

    #[test]
    fn normals_spread_at_a_cone_apex_and_not_at_a_sphere_pole() {
        // cone(1, 1): half-angle 45°, normals (cos u, sin u, −1)/√2 around
        // the apex, opposite generatrices 90° apart
        let m = cone(1.0, 1.0);
        let f = &m.faces[0];
        let seg = f.pole_segment(&f.loops[0].uses[0], &m.curves[0]);
        let spread = f.pole_normal_spread(seg).unwrap().to_degrees();
        assert!((spread - 90.0).abs() < 0.5, "{spread}");
        // an eighth of a turn: cos θ = (cos 45° + 1) / 2, θ = 31.4°
        let eighth = [seg[0], [seg[0][0] + std::f64::consts::FRAC_PI_4, seg[0][1]]];
        let q = f.pole_normal_spread(eighth).unwrap().to_degrees();
        assert!((q - 31.40).abs() < 0.1, "{q}");
        // a sphere's pole: one tangent plane from every direction
        let s = crate::primitives::sphere(1.0);
        let f = &s.faces[0];
        for u in &f.loops[0].uses {
            let c = &s.curves[u.curve.idx()];
            if c.degenerate {
                let spread = f.pole_normal_spread(f.pole_segment(u, c)).unwrap();
                assert!(spread.to_degrees() < 1.0, "{}", spread.to_degrees());
            }
        }
    }

    #[test]
    fn max_curvature_is_one_over_the_radius() {
        let close = |a: f64, b: f64| (a - b).abs() < 1e-6 * b.max(1.0);
        let s = crate::primitives::sphere(2.5);
        let k = s.faces[0].max_curvature([0.3, 0.2]).unwrap();
        assert!(close(k, 0.4), "sphere {k}");
        let c = crate::primitives::cylinder(0.5, 3.0);
        let k = c.faces[0].max_curvature([1.0, 1.0]).unwrap();
        assert!(close(k, 2.0), "cylinder {k}");
        let p = crate::primitives::square(1.0);
        assert_eq!(p.faces[0].max_curvature([0.5, 0.5]), Some(0.0));
    }

    #[test]
    fn pole_toward_slides_along_the_segment() {
        let p = CornerUv::Pole([[0.0, 1.0], [6.0, 1.0]]);
        assert_eq!(p.toward([2.5, 0.0]), [2.5, 1.0]);
        assert_eq!(p.toward([-1.0, 0.0]), [0.0, 1.0]);
        assert_eq!(p.toward([9.0, 0.0]), [6.0, 1.0]);
        assert_eq!(CornerUv::Point([3.0, 4.0]).toward([0.0, 0.0]), [3.0, 4.0]);
    }
}
