//! Direct: simple faces meshed by a pattern, without a field (quasi-structured
//! meshing paper §6.1.2).
//!
//! - [`pattern_face`]: faces whose boundary matches a pattern of the library;
//! - [`holed_face`]: a plate with one hole as a grid with a rectangular hole (ours);
//! - [`sphere_face`]: a full sphere as a cube projected onto it (ours).

pub mod holed_face;
pub mod pattern_face;
pub mod sphere_face;
