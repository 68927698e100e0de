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
    /// The coarse method cannot run on this input (a triangle, a non-manifold
    /// edge, an option out of range), naming the entity or option.
    #[error("coarse method: {0}")]
    Coarse(String),
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

/// Why a method could not mesh one face, so that the face fell back to the
/// baseline ([`crate::MeshReport::fallback`]). The text of each variant is
/// what `quadrille mesh` prints.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum FaceError {
    /// The face id is not in the model (1-based).
    #[error("no face {0}")]
    NoSuchFace(u32),
    /// The face's cross field, size map or background failed.
    #[error("{0}")]
    Field(String),
    /// The boundary polygon could not be triangulated in (u, v).
    #[error("boundary: {0}")]
    Boundary(String),
    /// The triangulation could not be refined to the size.
    #[error("refinement: {0}")]
    Refinement(String),
    /// The triangulation holds no triangle.
    #[error("the triangulation is empty")]
    EmptyTriangulation,
    /// Edges of these curves (1-based) are missing from the triangulation.
    #[error("boundary edges of curves {0:?} left out of the triangulation")]
    MissingBoundaryEdges(Vec<u32>),
    /// No way of stepping the front was given.
    #[error("no front spacing to try")]
    NoFrontSpacing,
    /// Quads stayed inverted after smoothing and untangling (their count).
    #[error("{0} quads stay inverted")]
    InvertedQuads(usize),
    /// The face's mesh had quads that the mesh statistics find inverted
    /// once assembled with its neighbours.
    #[error("inverted quads in the assembled mesh")]
    InvertedInAssembly,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn face_errors_read_as_the_cli_prints_them() {
        assert_eq!(FaceError::NoSuchFace(3).to_string(), "no face 3");
        assert_eq!(
            FaceError::MissingBoundaryEdges(vec![2, 7]).to_string(),
            "boundary edges of curves [2, 7] left out of the triangulation"
        );
        assert_eq!(
            FaceError::InvertedQuads(4).to_string(),
            "4 quads stay inverted"
        );
        assert_eq!(
            FaceError::Refinement("Fatal(\"x\")".into()).to_string(),
            "refinement: Fatal(\"x\")"
        );
        assert_eq!(
            FaceError::InvertedInAssembly.to_string(),
            "inverted quads in the assembled mesh"
        );
    }

    #[test]
    fn mesh_errors_name_the_face_one_based() {
        let e = MeshError::Face {
            face: FaceId(4),
            reason: "x".into(),
        };
        assert_eq!(e.to_string(), "face 5 could not be meshed: x");
        assert_eq!(
            MeshError::Regularize("y".into()).to_string(),
            "regularization: y"
        );
    }
}
