//! The errors of the triangle-mesh import: each names the file and where.

use std::path::PathBuf;

/// Why a triangle mesh could not be turned into a [`geometry::Model`].
#[derive(Debug, thiserror::Error)]
pub enum TrimeshError {
    /// The file could not be read.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The system error.
        source: std::io::Error,
    },
    /// The file is not a valid mesh of its format (says where: line, byte, triangle).
    #[error("{path}: {msg}")]
    Parse {
        /// The file.
        path: PathBuf,
        /// What is wrong and where.
        msg: String,
    },
    /// The mesh is readable but cannot be used (no triangles, non-manifold,
    /// non-orientable, a patch that cannot be parametrized...).
    #[error("{path}: {msg}")]
    Invalid {
        /// The file (or `<memory>`).
        path: PathBuf,
        /// What is wrong and where.
        msg: String,
    },
}
