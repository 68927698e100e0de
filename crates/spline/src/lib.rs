//! B-spline math for trim-free spline patches (spec ricci-flow-iga-reconstruction
//! §9.3–9.6): clamped knot vectors, Cox–de Boor basis, cubic curve fitting with
//! interpolated ends, tensor-product patches, the exact B-spline Coons patch,
//! Boehm refinement, Bézier extraction with a Jacobian check, a conforming
//! multipatch (shared control-point indices) and its writers (JSON, VTU, IGES).
//!
//! Points and vectors are plain `[f64; 3]` so that the crate needs nothing but
//! `thiserror` and `serde`.

pub mod atomic;
pub mod basis;
pub mod bezier;
pub mod coons;
pub mod curve;
pub mod error;
pub mod iges;
pub mod json;
pub mod knots;
pub mod linalg;
pub mod multipatch;
pub mod refine;
pub mod surface;
pub mod vec3;
pub mod vtu;

pub use bezier::{extract_bezier, jacobian_check, BezierElement, JacobianReport};
pub use coons::coons_patch;
pub use curve::{fit_curve, max_fit_error, BSplineCurve};
pub use error::SplineError;
pub use knots::KnotVector;
pub use multipatch::{ArcId, ArcUse, Multipatch, MultipatchBuilder, PatchGrid, SharedSides};
pub use refine::{insert_knot, refine, refine_curve};
pub use surface::BSplinePatch;
pub use vec3::{Point3, Vec3};
