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

pub mod cavity;
pub mod defects;
pub mod regular_pass;
pub mod regularize;
