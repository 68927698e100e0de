//! Methods: each meshing method as its recipe of stages, and the driver that
//! meshes every face and assembles the model's mesh.
//!
//! - [`baseline`]: triangle split (ours; always valid);
//! - [`unstructured`]: the quasi-structured meshing paper's §5 per face;
//! - [`pipeline`]: options, parallel per-face meshing, assembly.

pub mod baseline;
pub mod pipeline;
#[cfg(test)]
pub(crate) mod test_grid;
pub mod unstructured;
