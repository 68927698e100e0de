//! Triangulate: meshes of one face in its parameter plane, and the
//! triangle-to-quad steps.
//!
//! - [`face_triangulation`]: constrained Delaunay triangulation in (u, v),
//!   refined to the 3D size (ours, with spade);
//! - [`split`]: every triangle into three quads on the CAD (the baseline);
//! - [`recombine`]: greedy pairing of triangles into quads (quasi-structured
//!   meshing paper §5.2);
//! - [`subdivide`]: midpoint subdivision of the quad-dominant mesh into
//!   all-quads on the CAD (paper §5.2).

pub(crate) mod face_triangulation;
pub(crate) mod recombine;
pub(crate) mod split;
pub(crate) mod subdivide;

pub use face_triangulation::FaceTriangulation;
pub use split::split_triangles;
