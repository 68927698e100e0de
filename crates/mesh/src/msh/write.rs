//! The MSH 4.1 writer of [`QuadMesh`] (ASCII and binary).
//!
//! Layout written (by `body`, shared with the high-order writer):
//! `$MeshFormat`, `$Entities` (points, curves and surfaces with bounding boxes
//! and bounding entities), `$Nodes` in one block per entity, `$Elements` in
//! blocks per entity and type (points on corners, lines on curves, quads and
//! triangles on faces). Node tag = node index + 1.
//!
//! Elements are grouped by entity in increasing id order (points, then lines,
//! then per face quads and triangles), keeping their relative order within an
//! entity: a mesh whose element lists are already grouped that way reads back
//! with the same order.
//!
//! Parametric coordinates (the curve parameter of a curve node, the (u, v)
//! of a face node) are written only when [`MshWriteOptions::parametric`] asks
//! for them, and then on the blocks whose every node has them: Gmsh itself
//! writes them only with `Mesh.SaveParametric`, and some readers (meshio)
//! refuse files that have them. Without them the entities and the
//! classification of every node are still written.

use std::io::{self, Write};
use std::path::Path;

use geometry::Model;

use super::body::{check_entity_ids, write_file, FileElement, FileMesh};
use super::MshError;
use crate::atomic::write_atomically;
use crate::quadmesh::QuadMesh;

/// ASCII or binary MSH 4.1.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MshEncoding {
    /// Human-readable text.
    Ascii,
    /// Binary (little-endian on the usual machines, with 8-byte `size_t`): smaller and faster.
    Binary,
}

/// How [`write_msh`] and [`write_msh_to`] write a file: ASCII or binary, with
/// or without parametric coordinates. The default (ASCII, no parametric
/// coordinates) is the file every MSH reader takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MshWriteOptions {
    /// ASCII or binary.
    pub encoding: MshEncoding,
    /// Write the parametric coordinates of curve and face nodes (parametric
    /// flag 1 on the node blocks whose every node has finite parameters). Off
    /// by default: meshio, for one, cannot read such files.
    pub parametric: bool,
}

impl Default for MshWriteOptions {
    fn default() -> Self {
        MshWriteOptions::new(MshEncoding::Ascii)
    }
}

impl MshWriteOptions {
    /// `encoding`, without parametric coordinates.
    pub const fn new(encoding: MshEncoding) -> Self {
        MshWriteOptions {
            encoding,
            parametric: false,
        }
    }

    /// The same options with parametric coordinates on or off.
    pub const fn with_parametric(self, parametric: bool) -> Self {
        MshWriteOptions { parametric, ..self }
    }
}

/// Writes `mesh` to `path` as MSH 4.1. With `model`, every model entity is
/// listed in `$Entities` with its true bounding entities (curve ends, face
/// loops); without it, the entities and their adjacency are derived from the
/// mesh. The file is written atomically: on any error no partial file is left.
///
/// Nodes that are `Unclassified` are written on the surface of the first
/// element using them (a file format needs an entity per node); a reader then
/// sees them as face nodes without parameters.
pub fn write_msh(
    path: &Path,
    mesh: &QuadMesh,
    model: Option<&Model>,
    options: MshWriteOptions,
) -> Result<(), MshError> {
    validate(mesh).map_err(|message| MshError::InvalidMesh {
        path: path.to_path_buf(),
        message,
    })?;
    write_atomically::<io::Error, _>(path, |w| write_file(w, &file_mesh(mesh), model, options))
        .map_err(|source| MshError::Io {
            path: path.to_path_buf(),
            source,
        })
}

/// Writes `mesh` as MSH 4.1 to any writer (see [`write_msh`]). An
/// inconsistent mesh gives an `InvalidInput` error before anything is written.
pub fn write_msh_to<W: Write>(
    w: &mut W,
    mesh: &QuadMesh,
    model: Option<&Model>,
    options: MshWriteOptions,
) -> io::Result<()> {
    validate(mesh).map_err(|m| io::Error::new(io::ErrorKind::InvalidInput, m))?;
    write_file(w, &file_mesh(mesh), model, options)
}

/// Checks lengths, node references, ids and coordinates.
fn validate(mesh: &QuadMesh) -> Result<(), String> {
    let nn = mesh.nodes.len();
    if nn > u32::MAX as usize {
        return Err(format!("{nn} nodes is more than the writer supports"));
    }
    if mesh.node_class.len() != nn {
        return Err(format!(
            "{} node classifications for {} nodes",
            mesh.node_class.len(),
            nn
        ));
    }
    if mesh.quad_face.len() != mesh.quads.len() {
        return Err(format!(
            "{} quad faces for {} quads",
            mesh.quad_face.len(),
            mesh.quads.len()
        ));
    }
    if mesh.triangle_face.len() != mesh.triangles.len() {
        return Err(format!(
            "{} triangle faces for {} triangles",
            mesh.triangle_face.len(),
            mesh.triangles.len()
        ));
    }
    let bad = |what: &str, i: usize| format!("{what} {i} refers to a missing node");
    for (i, q) in mesh.quads.iter().enumerate() {
        if q.iter().any(|&v| v as usize >= nn) {
            return Err(bad("quad", i));
        }
    }
    for (i, t) in mesh.triangles.iter().enumerate() {
        if t.iter().any(|&v| v as usize >= nn) {
            return Err(bad("triangle", i));
        }
    }
    for (i, (e, _)) in mesh.curve_edges.iter().enumerate() {
        if e.iter().any(|&v| v as usize >= nn) {
            return Err(bad("curve edge", i));
        }
    }
    for (i, (v, _)) in mesh.corner_nodes.iter().enumerate() {
        if *v as usize >= nn {
            return Err(bad("corner node", i));
        }
    }
    if let Some(i) = mesh
        .nodes
        .iter()
        .position(|p| p.iter().any(|x| !x.is_finite()))
    {
        return Err(format!("node {i} has a non-finite coordinate"));
    }
    check_entity_ids(
        &mesh.node_class,
        mesh.quad_face
            .iter()
            .chain(&mesh.triangle_face)
            .map(|f| f.0),
    )?;
    Ok(())
}

/// The elements of `mesh` as the file holds them: corners, curve edges,
/// quads, triangles.
fn file_mesh(mesh: &QuadMesh) -> FileMesh<'_> {
    let element = |dim, entity, ty, nodes: &[u32]| FileElement {
        dim,
        entity,
        ty,
        vertices: nodes.len(),
        nodes: nodes.to_vec(),
    };
    let corners = mesh
        .corner_nodes
        .iter()
        .map(|(v, k)| element(0, k.0, 15, &[*v]));
    let lines = mesh.curve_edges.iter().map(|(e, c)| element(1, c.0, 1, e));
    let quads = mesh
        .quads
        .iter()
        .zip(&mesh.quad_face)
        .map(|(q, f)| element(2, f.0, 3, q));
    let triangles = mesh
        .triangles
        .iter()
        .zip(&mesh.triangle_face)
        .map(|(t, f)| element(2, f.0, 2, t));
    FileMesh {
        nodes: &mesh.nodes,
        node_class: &mesh.node_class,
        elements: corners.chain(lines).chain(quads).chain(triangles).collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures;
    use crate::quadmesh::NodeClass;

    #[test]
    fn ascii_layout_of_a_square() {
        let (model, mesh) = fixtures::square_grid(1.0, 1);
        let mut out = Vec::new();
        write_msh_to(&mut out, &mesh, Some(&model), MshWriteOptions::default()).unwrap();
        let text = String::from_utf8(out).unwrap();
        assert!(
            text.starts_with("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Entities\n4 4 1 0\n"),
            "{text}"
        );
        // the face is bounded by its four curves, all forward
        assert!(text.contains("\n1 0 0 0 1 1 0 0 4 1 2 3 4\n"), "{text}");
        // 4 corner nodes in 4 blocks, no curve or face nodes
        assert!(text.contains("$Nodes\n4 4 1 4\n"), "{text}");
        assert!(text.contains("$Elements\n9 9 1 9\n"), "{text}");
        assert!(text.contains("2 1 3 1\n9 1 2 4 3\n"), "{text}");
    }

    #[test]
    fn invalid_mesh_is_refused_and_nothing_written() {
        let (_, mut mesh) = fixtures::square_grid(1.0, 1);
        mesh.quads[0][2] = 99;
        let dir = std::env::temp_dir().join(format!("quadrille-msh-bad-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("bad.msh");
        let err = write_msh(&path, &mesh, None, MshWriteOptions::default()).unwrap_err();
        assert!(
            err.to_string().contains("quad 0 refers to a missing node"),
            "{err}"
        );
        assert!(!path.exists());
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// `(dim, tag, parametric flag)` of every node block of an ASCII file.
    fn node_block_flags(text: &str) -> Vec<(i32, i64, i32)> {
        let nodes = text
            .split("$Nodes\n")
            .nth(1)
            .and_then(|s| s.split("$EndNodes").next())
            .expect("a $Nodes section");
        let mut lines = nodes.lines();
        let head: Vec<usize> = lines
            .next()
            .unwrap()
            .split(' ')
            .map(|t| t.parse().unwrap())
            .collect();
        let mut out = Vec::new();
        for _ in 0..head[0] {
            let b: Vec<i64> = lines
                .next()
                .unwrap()
                .split(' ')
                .map(|t| t.parse().unwrap())
                .collect();
            out.push((b[0] as i32, b[1], b[2] as i32));
            // tags, then coordinates (and parameters)
            for _ in 0..2 * b[3] {
                lines.next().unwrap();
            }
        }
        out
    }

    #[test]
    fn parametric_coordinates_only_on_request() {
        let (model, mesh) = fixtures::cube(2.0, 3);
        let write = |opts: MshWriteOptions| {
            let mut out = Vec::new();
            write_msh_to(&mut out, &mesh, Some(&model), opts).unwrap();
            out
        };
        let plain = String::from_utf8(write(MshWriteOptions::default())).unwrap();
        let flags = node_block_flags(&plain);
        // corners, curves and faces all have node blocks, none with parameters
        for dim in 0..3 {
            assert!(flags.iter().any(|f| f.0 == dim), "{flags:?}");
        }
        assert!(flags.iter().all(|f| f.2 == 0), "{flags:?}");
        // every node line holds its three coordinates only
        let param = MshWriteOptions::default().with_parametric(true);
        let with = String::from_utf8(write(param)).unwrap();
        let flags = node_block_flags(&with);
        for (dim, tag, flag) in &flags {
            assert_eq!(*flag, (*dim > 0) as i32, "block {dim}:{tag}");
        }
        assert!(with.len() > plain.len());
        // both encodings: the reader sees parameters exactly when asked for
        for enc in [MshEncoding::Ascii, MshEncoding::Binary] {
            for parametric in [false, true] {
                let opts = MshWriteOptions::new(enc).with_parametric(parametric);
                let r = crate::msh::read_msh_bytes(&write(opts), Path::new("p.msh")).unwrap();
                assert_eq!(r.mesh.nodes, mesh.nodes);
                for (got, want) in r.mesh.node_class.iter().zip(&mesh.node_class) {
                    let expected = match *want {
                        NodeClass::Curve(c, t) => NodeClass::Curve(c, t.filter(|_| parametric)),
                        NodeClass::Face(f, uv) => NodeClass::Face(f, uv.filter(|_| parametric)),
                        other => other,
                    };
                    assert_eq!(*got, expected, "{enc:?} parametric {parametric}");
                }
            }
        }
    }
}
