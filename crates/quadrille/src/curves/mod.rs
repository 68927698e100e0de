//! Curves: the mesh of every CAD curve, shared by the faces on its sides.
//!
//! - [`curve_mesh`]: curve planning against the size map and discretization
//!   (quasi-structured meshing paper §4.3: points uniform in ∫ dl / s);
//! - [`curve_chords`]: equal counts on opposite sides of four-sided faces
//!   (ours: chords of opposite curves, pattern-friendly side counts);
//! - [`cusps`]: curve spacing near cusp corners (ours).

pub mod curve_chords;
pub mod curve_mesh;
pub mod cusps;
