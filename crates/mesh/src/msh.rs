//! Gmsh's MSH format: a writer for MSH 4.1 (ASCII and binary) that keeps the
//! classification of every node and element on the model's entities, and a
//! reader for MSH 4.1 (ASCII and binary) and MSH 2.2 (ASCII) that restores it.
//! Parametric coordinates are written only on request ([`MshWriteOptions`]):
//! without them every reader (Gmsh, meshio) takes the file.
//!
//! Entity tags are `id + 1` (a corner is a point entity, a curve a curve
//! entity, a face a surface entity), so Gmsh and meshio see our meshes with
//! their CAD entities, and meshes written by Gmsh read back classified.

mod read;
mod write;

use std::path::PathBuf;

pub use read::{read_msh, read_msh_bytes, MshRead};
pub use write::{write_msh, write_msh_to, MshEncoding, MshWriteOptions};

/// Everything that can go wrong reading or writing an MSH file.
#[derive(Debug, thiserror::Error)]
pub enum MshError {
    /// The file could not be opened, read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The system error.
        #[source]
        source: std::io::Error,
    },
    /// The file's content is malformed or unsupported.
    #[error("{path}: {location} (section {section}): {message}")]
    Parse {
        /// The file.
        path: PathBuf,
        /// `line N` (ASCII) or `byte N` (binary data).
        location: String,
        /// The `$Section` being read (or `-` outside sections).
        section: String,
        /// What is wrong.
        message: String,
    },
    /// The mesh given to the writer is inconsistent (nothing was written).
    #[error("{path}: cannot write this mesh: {message}")]
    InvalidMesh {
        /// The file that was to be written.
        path: PathBuf,
        /// What is wrong with the mesh.
        message: String,
    },
}

/// Number of nodes of the Gmsh element types (1–31, 36, 37), `None` for others.
pub(crate) fn nodes_per_element(ty: i32) -> Option<usize> {
    Some(match ty {
        1 => 2,
        2 => 3,
        3 => 4,
        4 => 4,
        5 => 8,
        6 => 6,
        7 => 5,
        8 => 3,
        9 => 6,
        10 => 9,
        11 => 10,
        12 => 27,
        13 => 18,
        14 => 14,
        15 => 1,
        16 => 8,
        17 => 20,
        18 => 15,
        19 => 13,
        20 => 9,
        21 => 10,
        22 => 12,
        23 => 15,
        24 => 15,
        25 => 21,
        26 => 4,
        27 => 5,
        28 => 6,
        29 => 20,
        30 => 35,
        31 => 56,
        36 => 16,
        37 => 25,
        _ => return None,
    })
}
