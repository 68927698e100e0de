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

use std::sync::Arc;

use crate::traits::{Curve, Curve2d, Surface};
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
    /// Unit normal with the face's orientation, or `None` at a singular point.
    pub fn normal(&self, uv: [f64; 2]) -> Option<Vec3> {
        let n = self.surface.normal(uv)?;
        Some(if self.reversed { vec3::scale(n, -1.0) } else { n })
    }

    /// All curves bounding this face (a seam appears twice).
    pub fn curve_uses(&self) -> impl Iterator<Item = &CurveUse> {
        self.loops.iter().flat_map(|l| l.uses.iter())
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
    pub fn loop_uv_polyline(&self, face: FaceId, loop_idx: usize, samples_per_use: usize) -> Vec<[f64; 2]> {
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

    /// Checks that every id refers to an existing entity.
    pub fn validate(&self) -> Result<(), ModelError> {
        for (i, c) in self.curves.iter().enumerate() {
            if c.start.idx() >= self.corners.len() || c.end.idx() >= self.corners.len() {
                return Err(ModelError::BadReference(format!("curve {} refers to a missing corner", i + 1)));
            }
        }
        for (i, f) in self.faces.iter().enumerate() {
            for u in f.curve_uses() {
                if u.curve.idx() >= self.curves.len() {
                    return Err(ModelError::BadReference(format!("face {} refers to a missing curve", i + 1)));
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
