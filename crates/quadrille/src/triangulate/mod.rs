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

pub mod face_triangulation;
pub mod recombine;
pub mod split;
pub mod subdivide;
