//! Field: the guidance of the quasi-structured methods, per face on a
//! background triangulation.
//!
//! - [`crossfield`]: the boundary-aligned cross field (quasi-structured
//!   meshing paper §3.1, MBO iterations);
//! - [`singularities`]: its singularities and the index check of relation (2);
//! - [`scaling`]: the conformal scaling of the field (paper §4.1);
//! - [`size_map`]: the size map (paper §4: conformal size, small features,
//!   gradation, user sizes);
//! - [`background`]: point location and field interpolation on the
//!   background (ours);
//! - [`field_report`]: all of the above for every face of a model
//!   (`quadrille field`).

pub mod background;
pub mod crossfield;
pub mod field_report;
pub mod scaling;
pub mod singularities;
pub mod size_map;
