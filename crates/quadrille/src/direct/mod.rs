//! Direct: simple faces meshed by a pattern, without a field (quasi-structured
//! meshing paper §6.1.2).
//!
//! - [`pattern_face`]: faces whose boundary matches a pattern of the library;
//! - [`holed_face`]: a plate with one hole as a grid with a rectangular hole (ours);
//! - [`ring_face`]: an annulus between two smooth closed loops as a ring grid (ours);
//! - [`o_grid`]: a disk bounded by one smooth loop as an O-grid shaped like it, or an
//!   elongated one as one plain grid (ours);
//! - [`sphere_face`]: a full sphere as a cube projected onto it (ours);
//! - [`strip_face`]: a narrow lens (two convex corners) as one row of quads on its
//!   boundary points (ours).

pub(crate) mod holed_face;
pub(crate) mod o_grid;
pub(crate) mod pattern_face;
pub(crate) mod ring_face;
pub(crate) mod sphere_face;
pub(crate) mod strip_face;

pub use holed_face::HOLED_GRID;
pub use o_grid::{O_GRID, PLAIN_GRID, PLAIN_MIN_SICN};
pub use pattern_face::{mesh_face_pattern, MIN_PATTERN_SICN};
pub use ring_face::RING_GRID;
pub use strip_face::LENS_STRIP;
