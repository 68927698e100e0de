//! Frontal: points inserted along the scaled cross field (quasi-structured
//! meshing paper §5.1).
//!
//! - [`insertion`]: frontal point insertion into the face triangulation.

pub(crate) mod insertion;
