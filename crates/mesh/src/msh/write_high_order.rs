//! The MSH 4.1 writer of [`HighOrderQuadMesh`] (ASCII and binary): the same
//! file layout as the linear writer (`body`), with the elements as Lagrange
//! quads of the mesh's order (types 3, 10, 36, 37, 38, 47–51 for N = 1..10)
//! per CAD face, the curve edges as Lagrange lines (types 1, 8, 26, 27, 28,
//! 62–66) per curve and the corners as points (type 15), every element's
//! nodes in Gmsh's order ([`crate::high_order::gmsh_quad_ordering`]).

use std::io::{self, Write};
use std::path::Path;

use geometry::Model;

use super::body::{check_entity_ids, write_file, FileElement, FileMesh};
use super::write::MshWriteOptions;
use super::MshError;
use crate::atomic::write_atomically;
use crate::high_order::{
    gmsh_line_ordering, gmsh_line_type, gmsh_quad_ordering, gmsh_quad_type, HighOrderQuadMesh,
};

/// Writes `mesh` to `path` as MSH 4.1 (see the module docs; `model` and
/// `options` as for [`super::write_msh`]). An inconsistent mesh (bad order,
/// wrong lengths, missing nodes, non-finite coordinates) is refused with
/// [`MshError::InvalidMesh`] before anything is written; the file is written
/// atomically.
pub fn write_high_order_msh(
    path: &Path,
    mesh: &HighOrderQuadMesh,
    model: Option<&Model>,
    options: MshWriteOptions,
) -> Result<(), MshError> {
    let file = file_mesh(mesh).map_err(|message| MshError::InvalidMesh {
        path: path.to_path_buf(),
        message,
    })?;
    write_atomically::<io::Error, _>(path, |w| write_file(w, &file, model, options)).map_err(
        |source| MshError::Io {
            path: path.to_path_buf(),
            source,
        },
    )
}

/// Writes `mesh` as MSH 4.1 to any writer (see [`write_high_order_msh`]).
/// An inconsistent mesh gives an `InvalidInput` error before anything is written.
pub fn write_high_order_msh_to<W: Write>(
    w: &mut W,
    mesh: &HighOrderQuadMesh,
    model: Option<&Model>,
    options: MshWriteOptions,
) -> io::Result<()> {
    let file = file_mesh(mesh).map_err(|m| io::Error::new(io::ErrorKind::InvalidInput, m))?;
    write_file(w, &file, model, options)
}

/// Checks `mesh` and lists its elements in Gmsh's order: corners, curve
/// edges, quads.
fn file_mesh(mesh: &HighOrderQuadMesh) -> Result<FileMesh<'_>, String> {
    mesh.validate().map_err(|e| e.to_string())?;
    check_entity_ids(&mesh.node_class, mesh.element_face.iter().map(|f| f.0))?;
    let n = mesh.order;
    let err = |e: crate::high_order::HighOrderError| e.to_string();
    let (quad_type, line_type) = (
        gmsh_quad_type(n).map_err(err)?,
        gmsh_line_type(n).map_err(err)?,
    );
    let quad_perm = gmsh_quad_ordering(n).map_err(err)?;
    let line_perm = gmsh_line_ordering(n).map_err(err)?;
    let corners = mesh.corner_nodes.iter().map(|(v, k)| FileElement {
        dim: 0,
        entity: k.0,
        ty: 15,
        vertices: 1,
        nodes: vec![*v],
    });
    let lines = (0..mesh.num_curve_edges()).map(|k| {
        let seq = mesh.curve_edge(k);
        FileElement {
            dim: 1,
            entity: mesh.curve_edge_curve[k].0,
            ty: line_type,
            vertices: 2,
            nodes: line_perm.iter().map(|&p| seq[p]).collect(),
        }
    });
    let quads = (0..mesh.num_elements()).map(|e| {
        let elem = mesh.element(e);
        FileElement {
            dim: 2,
            entity: mesh.element_face[e].0,
            ty: quad_type,
            vertices: 4,
            nodes: quad_perm.iter().map(|&p| elem[p]).collect(),
        }
    });
    Ok(FileMesh {
        nodes: &mesh.nodes,
        node_class: &mesh.node_class,
        elements: corners.chain(lines).chain(quads).collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::high_order_patch;
    use crate::msh::MshEncoding;

    #[test]
    fn order_2_patch_in_ascii() {
        // one element over the unit square, order 2: 9 nodes, index i + 3 j
        let mesh = high_order_patch(2, 1, 1, |u, v| [u, v, 0.0]);
        let mut out = Vec::new();
        write_high_order_msh_to(&mut out, &mesh, None, MshWriteOptions::default()).unwrap();
        let text = String::from_utf8(out).unwrap();
        // 4 corners, 4 curves, 1 face; curve 1 bounded by corners 2 and 3
        assert!(text.contains("$Entities\n4 4 1 0\n"), "{text}");
        assert!(text.contains("\n2 1 0 0 1 1 0 0 2 2 -3\n"), "{text}");
        assert!(text.contains("\n1 0 0 0 1 1 0 0 4 1 2 3 4\n"), "{text}");
        // 4 points, 4 lines of type 8, 1 quad of type 10
        assert!(text.contains("$Elements\n9 9 1 9\n"), "{text}");
        // the bottom line: ends 1 and 3, middle 2
        assert!(text.contains("1 1 8 1\n5 1 3 2\n"), "{text}");
        // the top line runs from (1, 1) to (0, 1): nodes 9, 7, middle 8
        assert!(text.contains("1 3 8 1\n7 9 7 8\n"), "{text}");
        // the quad: corners 1 3 9 7, edge nodes 2 6 8 4, centre 5
        assert!(text.contains("2 1 10 1\n9 1 3 9 7 2 6 8 4 5\n"), "{text}");
    }

    #[test]
    fn bad_meshes_are_refused_and_nothing_written() {
        let dir = std::env::temp_dir().join(format!("quadrille-ho-msh-bad-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("bad.msh");
        let good = high_order_patch(3, 2, 2, |u, v| [u, v, 0.0]);
        let mut zero = good.clone();
        zero.order = 0;
        let mut eleven = good.clone();
        eleven.order = 11;
        let mut short = good.clone();
        short.element_nodes.pop();
        let mut missing = good.clone();
        missing.curve_edge_nodes[2] = 1000;
        let mut huge = good.clone();
        huge.element_face[0] = geometry::FaceId(u32::MAX - 1);
        let cases = [
            (zero, "order 0"),
            (eleven, "order 11"),
            (short, "element_nodes"),
            (missing, "curve edge 0 refers to node 1000"),
            (huge, "does not fit an MSH entity tag"),
        ];
        for (mesh, want) in cases {
            for enc in [MshEncoding::Ascii, MshEncoding::Binary] {
                let err = write_high_order_msh(&path, &mesh, None, MshWriteOptions::new(enc))
                    .unwrap_err();
                assert!(matches!(err, MshError::InvalidMesh { .. }), "{err}");
                assert!(
                    err.to_string().contains(want) && err.to_string().contains("bad.msh"),
                    "{err}"
                );
                let mut sink = Vec::new();
                let e = write_high_order_msh_to(&mut sink, &mesh, None, MshWriteOptions::new(enc));
                assert_eq!(e.unwrap_err().kind(), io::ErrorKind::InvalidInput);
                assert!(sink.is_empty());
            }
        }
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
