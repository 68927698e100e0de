//! Quadrille's meshing methods, one module per stage, and the pipeline
//! functions that chain them.
//!
//! The first end-to-end method is the **baseline all-quad mesher**
//! ([`mesh_model`]): every CAD curve is discretized once (shared by its faces),
//! each face is triangulated in its parameter plane (constrained Delaunay with
//! refinement to the 3D size), every triangle is split into three quads and the
//! new nodes are placed on the CAD surface. Later methods build on its stages.
//!
//! Stages:
//! - [`curve_mesh`]: curve discretization (2n points per curve, shared by faces);
//! - [`face_triangulation`]: constrained Delaunay triangulation of one face in
//!   (u, v), refined to the 3D size;
//! - [`split`]: triangle → 3 quads, placement on the CAD, validity repair;
//! - [`smoothing`]: light uv-Laplacian smoothing with rollback;
//! - [`pipeline`]: options, parallel per-face meshing, deterministic assembly;
//! - [`field_report`]: the cross field, singularities and size map of every
//!   face of a model on its background triangulation (`quadrille field`).

pub mod crossfield;
pub mod curve_chords;
pub mod curve_mesh;
pub mod face_quads;
pub mod face_triangulation;
pub mod field_report;
pub mod pipeline;
pub mod regularize;
pub mod scaling;
pub mod singularities;
pub mod smoothing;
pub mod split;

pub use pipeline::{default_size, mesh_model, resolve_size, MeshError, MeshOptions, ProgressFn, Size};
