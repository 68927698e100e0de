//! Curves: the mesh of every CAD curve, shared by the faces on its sides.
//!
//! - [`curve_mesh`]: curve planning against the size map and discretization
//!   (quasi-structured meshing paper §4.3: points uniform in ∫ dl / s);
//! - [`curve_chords`]: equal counts on opposite sides of four-sided faces
//!   (ours: chords of opposite curves, pattern-friendly side counts);
//! - [`count_balance`]: counts suited to the face they bound: grids on tori
//!   and bands, one count on an annulus's loops, square band cells (ours);
//! - [`cusps`]: curve spacing near cusp corners (ours).

pub(crate) mod count_balance;
pub(crate) mod curve_chords;
pub(crate) mod curve_mesh;
pub(crate) mod cusps;

pub use curve_chords::{opposite_pairs, CHORD_TOLERANCE};
pub use curve_mesh::{discretize_all, plan_curves, CurveMesh};
