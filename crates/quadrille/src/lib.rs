//! Quadrille's meshing methods, as layered stage folders and the method
//! recipes that chain them.
//!
//! Start with [`mesh_model`] (the default, quasi-structured method) or
//! [`mesh_model_with`] and a [`MeshMethod`]:
//!
//! ```
//! use quadrille::{mesh_model_with, MeshMethod, MeshOptions, Size};
//! let model = geometry::primitives::cylinder(1.0, 2.0);
//! let opts = MeshOptions { size: Size::Factor(1.0), threads: Some(1), ..Default::default() };
//! let (mesh, report) = mesh_model_with(&model, &opts, MeshMethod::default()).unwrap();
//! assert!(!mesh.quads.is_empty() && report.fallback.is_empty());
//! ```
//!
//! The folders, bottom to top; each imports only the ones before it (checked
//! by `tests/layers.rs`; ARCHITECTURE.md says what each holds):
//!
//! - [`core`]: the per-face quad patch, quad quality, valence rules, geometry
//!   queries, options and errors, hashing and the work queue;
//! - [`combinatorics`]: pattern library and disk quadrangulations, as tables;
//! - [`curves`]: the mesh of every CAD curve;
//! - [`triangulate`]: triangulation of a face in (u, v), triangles to quads;
//! - [`field`]: cross field, singularities, scaling and size map;
//! - [`smoothing`]: node placement with fixed topology;
//! - [`direct`]: simple faces meshed by a pattern;
//! - [`frontal`]: frontal points along the cross field;
//! - [`topology`]: defects, cavities, regularization;
//! - [`coarse`]: the coarse high-order method's stages;
//! - [`curvenet`]: quads from closed 3D curve cycles;
//! - [`shell`], [`ricci`], [`cut`], [`immersion`], [`layout`]: the stages of
//!   `quadrille spline` (open shell, Ricci flow, cut, plane map, quad layout);
//! - [`methods`]: the recipes ([`MeshMethod`]) and the driver.
//!
//! Each folder exposes the items other crates use (re-exported in its
//! `mod.rs`); its modules are private to the crate.

// Public items document the stages they call, which are private to the
// crate: the links resolve with `cargo doc --document-private-items`, the
// documentation for the people who work on the mesher.
#![allow(rustdoc::private_intra_doc_links)]

pub mod coarse;
pub mod combinatorics;
pub mod cones;
pub mod core;
pub mod curves;
pub mod curvenet;
pub mod cut;
pub mod direct;
pub mod field;
#[cfg(any(test, feature = "fixtures"))]
pub mod fixtures;
pub mod frontal;
pub mod immersion;
pub mod layout;
pub mod layout_energy;
pub mod methods;
pub mod ricci;
pub mod shell;
pub mod smoothing;
pub mod topology;
pub mod trace;
pub mod triangulate;

pub use core::error::{FaceError, MeshError, TooManyQuads};
pub use core::options::{default_size, resolve_size, ProgressFn, Size, DEFAULT_DIVISIONS};
pub use methods::driver::SLIVER_LENGTH;
pub use methods::options::{MeshOptions, Stages, DEFAULT_QUADS_PER_TURN};
pub use methods::report::{FaceOutcome, MadeBy, MeshReport, StageTimes};
pub use methods::coarse::{
    check_input_mesh, mesh_coarse, CoarseMesh, CoarseOptions, CoarseReport, CoarseTimes,
};
pub use methods::{
    estimate_quads, mesh_model, mesh_model_with, MeshMethod, BYTES_PER_QUAD, DEFAULT_MAX_QUADS,
};
