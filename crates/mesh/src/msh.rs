//! Gmsh's MSH format: a writer for MSH 4.1 (ASCII and binary) that keeps the
//! classification of every node and element on the model's entities, and a
//! reader for MSH 4.1 (ASCII and binary) and MSH 2.2 (ASCII) that restores it.
//! Parametric coordinates are written only on request ([`MshWriteOptions`]):
//! without them every reader (Gmsh, meshio) takes the file.
//!
//! High-order quad meshes ([`crate::HighOrderQuadMesh`]) are written and read
//! with their own functions ([`write_high_order_msh`], [`read_high_order_msh`]):
//! Lagrange quads of types 3, 10, 36, 37, 38, 47–51 and lines of types 1, 8,
//! 26, 27, 28, 62–66 (orders 1 to 10), nodes in Gmsh's order.
//!
//! Entity tags are `id + 1` (a corner is a point entity, a curve a curve
//! entity, a face a surface entity), so Gmsh and meshio see our meshes with
//! their CAD entities, and meshes written by Gmsh read back classified.

mod body;
mod read;
mod read_high_order;
mod write;
mod write_high_order;

use std::path::PathBuf;

pub use read::{read_msh, read_msh_bytes, MshRead};
pub use read_high_order::{read_high_order_msh, read_high_order_msh_bytes};
pub use write::{write_msh, write_msh_to, MshEncoding, MshWriteOptions};
pub use write_high_order::{write_high_order_msh, write_high_order_msh_to};

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

/// Number of nodes of the Gmsh element types (1–31, the Lagrange quads 36,
/// 37, 38, 47–51 and lines 62–66), `None` for others.
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
        38 => 36,
        47 => 49,
        48 => 64,
        49 => 81,
        50 => 100,
        51 => 121,
        62 => 7,
        63 => 8,
        64 => 9,
        65 => 10,
        66 => 11,
        _ => return None,
    })
}

/// Dimension of the Gmsh element types this crate reads (points, Lagrange
/// lines, triangles, Lagrange quads), `None` for others.
pub(crate) fn element_dim(ty: i32) -> Option<i64> {
    use crate::high_order::{order_of_gmsh_line, order_of_gmsh_quad};
    match ty {
        15 => Some(0),
        2 => Some(2),
        _ if order_of_gmsh_line(ty).is_some() => Some(1),
        _ if order_of_gmsh_quad(ty).is_some() => Some(2),
        _ => None,
    }
}
