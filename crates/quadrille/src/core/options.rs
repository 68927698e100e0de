//! The target size of a mesh and how it resolves against a model, and the
//! progress callback: the options every method takes.

use std::sync::Arc;

use geometry::Model;

use crate::core::error::MeshError;

/// The default final edge length is the bounding-box diagonal divided by this.
/// 24: on the 26 shared models Quadrille then makes as many quads as Gmsh at
/// its default size (geometric-mean ratio 1.00; at 18 it was 0.71), so a user
/// switching from Gmsh gets the density they know (BENCHMARKS.md, "Default size").
pub const DEFAULT_DIVISIONS: f64 = 24.0;

/// Target mesh size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Size {
    /// Final quad edge length, in model units.
    Absolute(f64),
    /// A multiple of the default size ([`default_size`]); `Factor(1.0)` is the default.
    Factor(f64),
}

impl Default for Size {
    fn default() -> Self {
        Size::Factor(1.0)
    }
}

/// Progress callback: called with `(faces done, total faces)` after each face
/// (from worker threads, in no particular order).
pub type ProgressFn = Arc<dyn Fn(usize, usize) + Send + Sync>;

/// The default final quad edge length: the model's bounding-box diagonal / [`DEFAULT_DIVISIONS`].
pub fn default_size(model: &Model) -> f64 {
    model.diagonal() / DEFAULT_DIVISIONS
}

/// Resolves a [`Size`] to a final edge length for `model`.
pub fn resolve_size(model: &Model, size: Size) -> Result<f64, MeshError> {
    let h = match size {
        Size::Absolute(h) => {
            if !(h.is_finite() && h > 0.0) {
                return Err(MeshError::InvalidSize(h));
            }
            h
        }
        Size::Factor(f) => {
            if !(f.is_finite() && f > 0.0) {
                return Err(MeshError::InvalidSize(f));
            }
            f * default_size(model)
        }
    };
    if !(h.is_finite() && h > 0.0) {
        return Err(MeshError::InvalidSize(h));
    }
    Ok(h)
}
