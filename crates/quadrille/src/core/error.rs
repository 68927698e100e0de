//! Why meshing a model failed: the errors every method returns.

use geometry::{FaceId, ModelError};

/// Why meshing failed.
#[derive(Debug, thiserror::Error)]
pub enum MeshError {
    /// The requested size is not a positive finite number.
    #[error("invalid mesh size {0}: it must be a positive finite number")]
    InvalidSize(f64),
    /// The model has no face to mesh.
    #[error("the model has no faces to mesh")]
    NoFaces,
    /// The model refers to missing entities.
    #[error("invalid model: {0}")]
    Model(#[from] ModelError),
    /// One face could not be meshed (face numbers are 1-based, as in files).
    #[error("face {} could not be meshed: {reason}", face.0 + 1)]
    Face {
        /// The face.
        face: FaceId,
        /// What went wrong.
        reason: String,
    },
    /// The size-map options are invalid (bad gradient, bounds or entity sizes).
    #[error("size map: {0}")]
    Sizing(String),
    /// Topological regularization failed (the regular method).
    #[error("regularization: {0}")]
    Regularize(String),
    /// The thread pool could not be created.
    #[error("could not start a pool of {threads} threads: {reason}")]
    Threads {
        /// Requested thread count.
        threads: usize,
        /// The pool builder's message.
        reason: String,
    },
}
