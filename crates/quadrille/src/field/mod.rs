//! Field: the guidance of the quasi-structured methods, per face on a
//! background triangulation.
//!
//! - [`crossfield`]: the boundary-aligned cross field (quasi-structured
//!   meshing paper §3.1, MBO iterations);
//! - [`singularities`]: its singularities and the index check of relation (2);
//! - [`scaling`]: the conformal scaling of the field (paper §3.3);
//! - [`size_map`]: the size map (paper §4.1–4.2: conformal size, small features,
//!   gradation, user sizes);
//! - [`background`]: point location and field interpolation on the
//!   background (ours);
//! - [`field_report`]: all of the above for every face of a model
//!   (`quadrille field`);
//! - [`quad_estimate`]: `∫ dA / s²` of the size map on a background of
//!   bounded resolution, before meshing (the size guard's input; ours).

pub(crate) mod background;
pub(crate) mod crossfield;
pub(crate) mod field_report;
pub(crate) mod quad_estimate;
pub(crate) mod scaling;
pub(crate) mod singularities;
pub(crate) mod size_map;

pub use crossfield::assembly::{assemble, cr_stiffness};
pub use crossfield::linsolve::{LowerPattern, SparseSpd};
pub use crossfield::topology::NONE;
pub use crossfield::{compute_cross_field, CrossFieldOptions, FaceMesh, FaceTopology};
pub use field_report::{model_fields, FieldOptions, ModelFields, BACKGROUND_REFINE};
pub use quad_estimate::{size_integral, SizeIntegral, ESTIMATE_REFINE, PLAN_DIVISIONS};
pub use scaling::conformal_scaling;
pub use singularities::{extract_singularities, SingularitySite};
pub use size_map::{build_size_map, Entity, FaceBackground, SizeMapOptions, DEFAULT_GRADIENT};
