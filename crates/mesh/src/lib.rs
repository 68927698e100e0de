//! Mesh structures classified on a [`geometry::Model`], their quality metrics
//! and statistics, file readers and writers, and pictures.

pub mod atomic;
pub mod quadmesh;
pub mod quality;

pub use quadmesh::{NodeClass, QuadMesh};
