//! Topology: stages that change the quads' connectivity to remove irregular
//! vertices.
//!
//! - [`defects`]: very irregular vertices replaced by disk quadrangulations
//!   (quasi-structured meshing paper §6.3);
//! - [`cavity`]: cavity remeshing (paper §6.2);
//! - [`regularize`]: the fully-regular paper's swaps, collapses and splits
//!   (the regular method);
//! - [`regular_pass`]: those operations as the quasi-structured method's
//!   last topological pass (ours).

pub(crate) mod cavity;
pub(crate) mod defects;
pub(crate) mod regular_pass;
pub(crate) mod regularize;

pub use defects::remove_defects;
pub use regularize::grid::{four_side_counts, single_boundary_loop};
pub use regularize::validity::{quad_angles, quad_valid};
pub use regularize::{
    regularize_mesh, regularize_mesh_with_progress, AngleWindow, QuadTarget, RegularizeError,
    RegularizeOptions, RegularizeReport,
};
