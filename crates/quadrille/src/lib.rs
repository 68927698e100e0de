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
//! - [`size_map`]: the model's size map (conformal size, small features,
//!   gradation, user sizes) on the background triangulations;
//! - [`field_report`]: the cross field, singularities and size map of every
//!   face of a model on its background triangulation (`quadrille field`);
//! - the unstructured method ([`MeshMethod::Unstructured`]): [`background`]
//!   (point location and field interpolation), [`frontal`] (frontal point
//!   insertion), [`recombine`] (greedy triangle pairing), [`subdivide`]
//!   (midpoint subdivision on the CAD), driven per face by [`unstructured`],
//!   whose topology is then improved by [`defects`] and [`cavity`].

pub mod combinatorics;
pub mod core;
pub mod curves;
pub mod direct;
pub mod field;
pub mod frontal;
pub mod methods;
pub mod smoothing;
pub mod topology;
pub mod triangulate;

pub use core::error::MeshError;
pub use core::options::{default_size, resolve_size, ProgressFn, Size, DEFAULT_DIVISIONS};
pub use methods::driver::SLIVER_LENGTH;
pub use methods::options::{MeshOptions, Stages, DEFAULT_QUADS_PER_TURN};
pub use methods::report::{FaceOutcome, MadeBy, MeshReport, StageTimes};
pub use methods::{mesh_model, mesh_model_with, MeshMethod};
