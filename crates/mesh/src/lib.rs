//! Mesh structures classified on a [`geometry::Model`], their quality metrics
//! and statistics, file readers and writers, and pictures.

pub mod atomic;
pub mod field;
pub mod fixtures;
pub mod high_order;
pub mod msh;
pub mod obj;
pub mod quadmesh;
pub mod quality;
pub mod render;
pub mod stats;
pub mod vtu;

pub use high_order::HighOrderQuadMesh;
pub use quadmesh::{NodeClass, QuadMesh};
