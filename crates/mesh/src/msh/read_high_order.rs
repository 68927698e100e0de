//! Reading an MSH file (4.1 ASCII or binary, 2.2 ASCII) as a
//! [`HighOrderQuadMesh`]: every surface element a Lagrange quad of one order
//! N (types 3, 10, 36, 37, 38, 47–51), lines of the same order on curves,
//! points on corners. Element nodes go from Gmsh's order back to tensor
//! order, lines back to end-to-end order; node classification is restored as
//! by [`super::read_msh`]. Anything else (triangles, quads of two orders,
//! volume elements) is refused with an [`MshError::Parse`] naming the element.

use std::path::Path;

use geometry::{CornerId, CurveId, FaceId};

use super::element_dim;
use super::read::{RawFile, Reader, R};
use super::MshError;
use crate::high_order::{
    gmsh_line_ordering, gmsh_quad_ordering, order_of_gmsh_line, order_of_gmsh_quad,
    HighOrderQuadMesh,
};
use crate::quadmesh::NodeClass;

/// Reads an MSH file as a high-order quad mesh (see the module docs).
pub fn read_high_order_msh(path: &Path) -> Result<HighOrderQuadMesh, MshError> {
    let data = std::fs::read(path).map_err(|source| MshError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    read_high_order_msh_bytes(&data, path)
}

/// Reads MSH content already in memory as a high-order quad mesh; `name` is
/// used in error messages.
pub fn read_high_order_msh_bytes(data: &[u8], name: &Path) -> Result<HighOrderQuadMesh, MshError> {
    let mut r = Reader::new(data, name);
    let raw = r.read_raw()?;
    r.section = "$Elements".into();
    build(&r, &raw)
}

/// The order of the file's quads: that of the first, all others alike.
fn quad_order(r: &Reader, raw: &RawFile) -> R<usize> {
    let mut order = None;
    for el in raw.elements.iter().filter(|e| element_dim(e.ty) == Some(2)) {
        let Some(n) = order_of_gmsh_quad(el.ty) else {
            return r.err(format!(
                "element {} is a triangle (type {}): a high-order quad mesh holds quads only",
                el.tag, el.ty
            ));
        };
        match order {
            None => order = Some(n),
            Some(m) if m != n => {
                return r.err(format!(
                    "element {} is a quad of order {n} (type {}), the first quad is of order {m}",
                    el.tag, el.ty
                ))
            }
            Some(_) => {}
        }
    }
    match order {
        Some(n) => Ok(n),
        None => r.err("the file has no quad elements"),
    }
}

fn build(r: &Reader, raw: &RawFile) -> R<HighOrderQuadMesh> {
    let n = quad_order(r, raw)?;
    let to_msh = |e: crate::high_order::HighOrderError| -> MshError {
        r.err::<()>(e.to_string()).unwrap_err()
    };
    let quad_perm = gmsh_quad_ordering(n).map_err(to_msh)?;
    let line_perm = gmsh_line_ordering(n).map_err(to_msh)?;
    let mut mesh = HighOrderQuadMesh {
        order: n,
        nodes: raw.nodes.iter().map(|v| v.pos).collect(),
        node_class: raw.nodes.iter().map(|v| v.class).collect(),
        ..Default::default()
    };
    let k = mesh.nodes_per_element();
    // MSH 2: a node takes the lowest-dimensional entity of its elements
    let mut dim_of = vec![u8::MAX; if raw.v2 { mesh.nodes.len() } else { 0 }];
    for el in &raw.elements {
        let Some(dim) = element_dim(el.ty) else {
            return r.err(format!(
                "element {} has type {}, which a high-order quad mesh does not hold \
                 (points, lines and quads only)",
                el.tag, el.ty
            ));
        };
        if dim != el.dim {
            return r.err(format!(
                "element {} of type {} lies on an entity of dimension {}, not {dim}",
                el.tag, el.ty, el.dim
            ));
        }
        if dim == 1 && order_of_gmsh_line(el.ty) != Some(n) {
            return r.err(format!(
                "element {} is a line of type {}, not of order {n} like the quads",
                el.tag, el.ty
            ));
        }
        let mut idx = Vec::with_capacity(el.nodes.len());
        for &t in &el.nodes {
            match raw.index(t) {
                Some(i) => idx.push(i),
                None => {
                    return r.err(format!(
                        "element {} refers to node {t}, which is not defined",
                        el.tag
                    ))
                }
            }
        }
        let entity = if el.entity < 1 || el.entity > u32::MAX as i64 {
            return r.err(format!(
                "entity tag {} is not a positive 32-bit number",
                el.entity
            ));
        } else {
            (el.entity - 1) as u32
        };
        match dim {
            0 => mesh.corner_nodes.push((idx[0], CornerId(entity))),
            1 => {
                let mut seq = vec![0u32; n + 1];
                for (p, &v) in line_perm.iter().zip(&idx) {
                    seq[*p] = v;
                }
                mesh.curve_edge_nodes.extend(seq);
                mesh.curve_edge_curve.push(CurveId(entity));
            }
            _ => {
                let mut tensor = vec![0u32; k];
                for (p, &v) in quad_perm.iter().zip(&idx) {
                    tensor[*p] = v;
                }
                mesh.element_nodes.extend(tensor);
                mesh.element_face.push(FaceId(entity));
            }
        }
        if raw.v2 {
            for &i in &idx {
                if (dim as u8) < dim_of[i as usize] {
                    dim_of[i as usize] = dim as u8;
                    mesh.node_class[i as usize] = match dim {
                        0 => NodeClass::Corner(CornerId(entity)),
                        1 => NodeClass::Curve(CurveId(entity), None),
                        _ => NodeClass::Face(FaceId(entity), None),
                    };
                }
            }
        }
    }
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::high_order_patch;
    use crate::msh::{write_high_order_msh_to, MshEncoding, MshWriteOptions};

    fn read(text: &str) -> Result<HighOrderQuadMesh, MshError> {
        read_high_order_msh_bytes(text.as_bytes(), Path::new("ho.msh"))
    }

    #[test]
    fn round_trips_every_order_in_both_encodings() {
        for order in 1..=10 {
            let mesh = high_order_patch(order, 2, 2, |u, v| {
                [u.cos() / 3.0, u.sin() * 1e-7, v * 1e5 + u * v]
            });
            for enc in [MshEncoding::Ascii, MshEncoding::Binary] {
                for parametric in [false, true] {
                    let opts = MshWriteOptions::new(enc).with_parametric(parametric);
                    let mut out = Vec::new();
                    write_high_order_msh_to(&mut out, &mesh, None, opts).unwrap();
                    let back = read_high_order_msh_bytes(&out, Path::new("rt.msh")).unwrap();
                    if parametric {
                        assert_eq!(back, mesh, "order {order} {enc:?}");
                    } else {
                        let strip = |c: &NodeClass| match *c {
                            NodeClass::Curve(k, _) => NodeClass::Curve(k, None),
                            NodeClass::Face(f, _) => NodeClass::Face(f, None),
                            other => other,
                        };
                        let want = HighOrderQuadMesh {
                            node_class: mesh.node_class.iter().map(strip).collect(),
                            ..mesh.clone()
                        };
                        assert_eq!(back, want, "order {order} {enc:?}");
                    }
                    // the linear reader skips the high-order elements, counting them
                    let linear = crate::msh::read_msh_bytes(&out, Path::new("rt.msh")).unwrap();
                    assert_eq!(linear.mesh.nodes, mesh.nodes);
                    if order > 1 {
                        assert!(linear.mesh.quads.is_empty());
                        assert_eq!(linear.skipped_elements.values().sum::<usize>(), 4 + 8);
                    }
                }
            }
        }
    }

    const V22: &str = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n9\n\
1 0 0 0\n2 0.5 0 0\n3 1 0 0\n4 0 0.5 0\n5 0.5 0.5 0\n6 1 0.5 0\n7 0 1 0\n8 0.5 1 0\n9 1 1 0\n$EndNodes\n\
$Elements\n3\n1 15 2 0 1 1\n2 8 2 0 1 1 3 2\n3 10 2 0 1 1 3 9 7 2 6 8 4 5\n$EndElements\n";

    #[test]
    fn reads_msh22_with_derived_classification() {
        let m = read(V22).unwrap();
        assert_eq!(m.order, 2);
        assert_eq!(m.element_nodes, (0..9).collect::<Vec<u32>>());
        assert_eq!(m.element_face, vec![FaceId(0)]);
        assert_eq!(m.curve_edge_nodes, vec![0, 1, 2]);
        assert_eq!(m.corner_nodes, vec![(0, CornerId(0))]);
        assert_eq!(m.node_class[0], NodeClass::Corner(CornerId(0)));
        assert_eq!(m.node_class[1], NodeClass::Curve(CurveId(0), None));
        assert_eq!(m.node_class[4], NodeClass::Face(FaceId(0), None));
    }

    #[test]
    fn files_that_are_not_one_order_of_quads_are_refused() {
        let quad10 = "3 10 2 0 1 1 3 9 7 2 6 8 4 5";
        let cases = [
            (V22.replace(quad10, "3 2 2 0 1 1 3 9"), "is a triangle"),
            (
                V22.replace("$Elements\n3\n", "$Elements\n4\n")
                    .replace("$EndElements", "4 3 2 0 1 1 3 9 7\n$EndElements"),
                "quad of order 1 (type 3), the first quad is of order 2",
            ),
            (
                V22.replace("2 8 2 0 1 1 3 2", "2 1 2 0 1 1 3"),
                "line of type 1, not of order 2",
            ),
            (
                V22.replace("2 8 2 0 1 1 3 2", "2 4 2 0 1 1 3 2 5"),
                "has type 4",
            ),
            (
                V22.replace(quad10, "3 10 2 0 1 1 3 9 7 2 6 8 4 12"),
                "refers to node 12",
            ),
            (V22.replace(quad10, "3 15 2 0 1 1"), "no quad elements"),
        ];
        for (text, want) in cases {
            let err = read(&text).expect_err(want).to_string();
            assert!(err.contains(want), "expected {want:?} in {err:?}");
            assert!(err.starts_with("ho.msh: "), "{err}");
        }
        // an MSH 4.1 point element on a surface entity
        let mesh = high_order_patch(2, 1, 1, |u, v| [u, v, 0.0]);
        let mut out = Vec::new();
        write_high_order_msh_to(&mut out, &mesh, None, MshWriteOptions::default()).unwrap();
        let text = String::from_utf8(out)
            .unwrap()
            .replace("0 1 15 1\n1 1\n", "2 1 15 1\n1 1\n");
        let err = read(&text).unwrap_err().to_string();
        assert!(
            err.contains("lies on an entity of dimension 2, not 0"),
            "{err}"
        );
    }
}
