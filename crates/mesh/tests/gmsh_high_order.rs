//! Interop of our high-order files: curved Lagrange quads of orders 2–5 on a
//! patch of a cylinder and of a sphere, written as MSH 4.1 (ASCII and
//! binary), opened by Gmsh's Python API: the element types (10, 36, 37, 38;
//! lines 8, 26, 27, 28), the counts, the node coordinates and every element's
//! nodes in Gmsh's order must match; Gmsh's own reference coordinates of its
//! element nodes must be where our orderings put them; Gmsh's "minSJ" and
//! "minSICN" must be positive on every element, and its extremes of det J
//! must bracket our judge's sampled ones within 1 %; our reader must read the
//! files, and Gmsh's binary rewrites of them, back. Orders 6–10 (types 47–51,
//! lines 62–66) are checked the same way on the cylinder (minSJ up to order
//! 9: see `check_gmsh_view`). The VTU (`VTK_LAGRANGE_QUADRILATERAL`) must
//! read in meshio with every cell's points in VTK's order and the cell data.
//!
//! Without the `gmsh` (or `meshio`) Python module a test prints a skip
//! message and passes, unless `QUADRILLE_REQUIRE_GMSH=1`, where it fails.

mod common;

use std::f64::consts::PI;
use std::path::PathBuf;

use common::{python_module_available, script_json};
use mesh::fixtures::high_order_patch;
use mesh::high_order::{
    gmsh_line_ordering, gmsh_line_type, gmsh_quad_ordering, gmsh_quad_type, vtk_quad_ordering,
};
use mesh::msh::{read_high_order_msh, write_high_order_msh, MshEncoding, MshWriteOptions};
use mesh::vtu::write_high_order_vtu;
use mesh::{HighOrderQuadMesh, NodeClass};
use serde_json::Value;

const GMSH_SCRIPT: &str = r#"
import sys, json, struct
import gmsh
gmsh.initialize(["-noenv"])
gmsh.option.setNumber("General.Terminal", 0)
gmsh.option.setNumber("General.NumThreads", 1)
gmsh.open(sys.argv[1])
out = {}
tags, coords, _ = gmsh.model.mesh.getNodes()
out["node_tags"] = [int(t) for t in tags]
# the bits of each double: JSON's decimal would not keep every last bit
out["coords"] = [struct.unpack("<Q", struct.pack("<d", x))[0] for x in coords]
types, etags, enodes = gmsh.model.mesh.getElements()
out["elements"] = {}
out["local"] = {}
out["minSJ"] = {}
for t, e, n in zip(types, etags, enodes):
    t = int(t)
    out["elements"][str(t)] = [int(x) for x in n]
    name, dim, order, num, local, primary = gmsh.model.mesh.getElementProperties(t)
    out["local"][str(t)] = {"dim": dim, "order": order, "coords": [float(x) for x in local]}
    if dim == 2:
        out["minSJ"][str(t)] = [float(q) for q in gmsh.model.mesh.getElementQualities(e, "minSJ")]
        out["minSICN"] = [float(q) for q in gmsh.model.mesh.getElementQualities(e, "minSICN")]
        out["minDetJac"] = [float(q) for q in gmsh.model.mesh.getElementQualities(e, "minDetJac")]
        out["maxDetJac"] = [float(q) for q in gmsh.model.mesh.getElementQualities(e, "maxDetJac")]
if len(sys.argv) > 2:
    # Gmsh's own binary rewrite, for our reader
    gmsh.option.setNumber("Mesh.Binary", 1)
    gmsh.write(sys.argv[2])
gmsh.finalize()
print("JSON" + json.dumps(out))
"#;

const MESHIO_SCRIPT: &str = r#"
import sys, json, struct
import meshio
m = meshio.read(sys.argv[1])
bits = lambda x: struct.unpack("<Q", struct.pack("<d", x))[0]
out = {"points": [[bits(x) for x in p] for p in m.points.tolist()], "blocks": []}
for b in m.cells:
    out["blocks"].append({"type": b.type, "cells": b.data.tolist()})
out["cell_data"] = {k: [[bits(float(x)) for x in a.reshape(-1)] for a in v] for k, v in m.cell_data.items()}
print("JSON" + json.dumps(out))
"#;

/// A quarter of the cylinder of radius 2 around z, 3 × 2 elements of 30°
/// by 0.6.
fn cylinder(order: usize) -> HighOrderQuadMesh {
    high_order_patch(order, 3, 2, |u, v| {
        let a = u * PI / 6.0;
        [2.0 * a.cos(), 2.0 * a.sin(), 0.6 * v]
    })
}

/// A patch of the unit sphere, 3 × 3 elements of 0.5 rad in longitude by 0.4
/// in latitude, across the equator.
fn sphere(order: usize) -> HighOrderQuadMesh {
    high_order_patch(order, 3, 3, |u, v| {
        let (lon, lat) = (0.5 * u, -0.6 + 0.4 * v);
        [lat.cos() * lon.cos(), lat.cos() * lon.sin(), lat.sin()]
    })
}

fn temp_dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("quadrille-ho-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The doubles of a JSON array of their bit patterns.
fn doubles(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap_or_else(|| panic!("not an array: {v}"))
        .iter()
        .map(|x| f64::from_bits(x.as_u64().unwrap()))
        .collect()
}

fn numbers(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap_or_else(|| panic!("not an array: {v}"))
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

/// Our mesh with its parametric coordinates dropped (the files have none).
fn without_parameters(mesh: &HighOrderQuadMesh) -> HighOrderQuadMesh {
    let strip = |c: &NodeClass| match *c {
        NodeClass::Curve(k, _) => NodeClass::Curve(k, None),
        NodeClass::Face(f, _) => NodeClass::Face(f, None),
        other => other,
    };
    HighOrderQuadMesh {
        node_class: mesh.node_class.iter().map(strip).collect(),
        ..mesh.clone()
    }
}

/// Equal up to the last bit or two: the ASCII parsers of Gmsh and numpy do
/// not always round our shortest decimal forms back to the same double.
fn near(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(x, y)| (x - y).abs() <= 1e-15 * (1.0 + y.abs()))
}

/// Checks Gmsh's view of the file of `mesh` against it: node coordinates
/// bit for bit when `exact` (binary files), else to the last bits.
fn check_gmsh_view(v: &Value, mesh: &HighOrderQuadMesh, what: &str, exact: bool) {
    let n = mesh.order;
    let (qt, lt) = (gmsh_quad_type(n).unwrap(), gmsh_line_type(n).unwrap());
    // nodes: the same count and coordinates, by tag
    let tags: Vec<u64> = v["node_tags"]
        .as_array()
        .unwrap()
        .iter()
        .map(|t| t.as_u64().unwrap())
        .collect();
    let coords = doubles(&v["coords"]);
    assert_eq!(tags.len(), mesh.nodes.len(), "{what}: node count");
    for (k, &t) in tags.iter().enumerate() {
        let want = mesh.nodes[t as usize - 1];
        let got = &coords[3 * k..3 * k + 3];
        if exact {
            assert_eq!(got, want, "{what}: node {t}");
        } else {
            assert!(near(got, &want), "{what}: node {t}: {got:?} vs {want:?}");
        }
    }
    // elements: exactly points, lines and quads of the order, in file order
    let elements = v["elements"].as_object().unwrap();
    let mut types: Vec<&String> = elements.keys().collect();
    types.sort();
    let mut want_types = [lt.to_string(), qt.to_string(), "15".to_string()];
    want_types.sort();
    assert_eq!(types, want_types.iter().collect::<Vec<_>>(), "{what}");
    let tags_of = |ty: i32| -> Vec<u64> {
        elements[&ty.to_string()]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_u64().unwrap())
            .collect()
    };
    let quad_perm = gmsh_quad_ordering(n).unwrap();
    let want_quads: Vec<u64> = (0..mesh.num_elements())
        .flat_map(|e| {
            quad_perm
                .iter()
                .map(move |&p| mesh.element(e)[p] as u64 + 1)
        })
        .collect();
    assert_eq!(
        tags_of(qt),
        want_quads,
        "{what}: quad nodes in Gmsh's order"
    );
    let line_perm = gmsh_line_ordering(n).unwrap();
    let want_lines: Vec<u64> = (0..mesh.num_curve_edges())
        .flat_map(|k| {
            line_perm
                .iter()
                .map(move |&p| mesh.curve_edge(k)[p] as u64 + 1)
        })
        .collect();
    assert_eq!(
        tags_of(lt),
        want_lines,
        "{what}: line nodes in Gmsh's order"
    );
    assert_eq!(tags_of(15).len(), mesh.corner_nodes.len(), "{what}");
    // Gmsh's reference coordinates of its nodes are where our orderings put them
    let local = &v["local"][qt.to_string()];
    assert_eq!(local["order"], n, "{what}");
    let uv = numbers(&local["coords"]);
    assert_eq!(uv.len(), 2 * quad_perm.len());
    for (k, &p) in quad_perm.iter().enumerate() {
        let (i, j) = (p % (n + 1), p / (n + 1));
        let want = [
            2.0 * i as f64 / n as f64 - 1.0,
            2.0 * j as f64 / n as f64 - 1.0,
        ];
        let got = [uv[2 * k], uv[2 * k + 1]];
        assert!(
            (got[0] - want[0]).abs() < 1e-12 && (got[1] - want[1]).abs() < 1e-12,
            "{what}: Gmsh's node {k} is at {got:?}, our ordering says tensor ({i}, {j})"
        );
    }
    let u = numbers(&v["local"][lt.to_string()]["coords"]);
    for (k, &p) in line_perm.iter().enumerate() {
        assert!(
            (u[k] - (2.0 * p as f64 / n as f64 - 1.0)).abs() < 1e-12,
            "{what}: line node {k}"
        );
    }
    // every element valid by Gmsh's judge
    let sicn = numbers(&v["minSICN"]);
    assert!(sicn.iter().all(|&q| q > 0.0), "{what}: minSICN {sicn:?}");
    let sj = numbers(&v["minSJ"][qt.to_string()]);
    assert_eq!(sj.len(), mesh.num_elements());
    // Gmsh 4.15's sampled minSJ loses its precision at order 10: on these
    // valid elements (minSICN, minDetJac and our judge agree) it gives values
    // below −1, impossible for a scaled Jacobian, and it already scatters
    // between identical elements at order 9; it is checked up to order 9
    if n <= 9 {
        assert!(sj.iter().all(|&q| q > 0.0), "{what}: minSJ {sj:?}");
    }
    // Gmsh's adaptive extremes of det J (on [-1, 1]², a quarter of ours)
    // bracket our sampled ones, closely
    let (lo, hi) = (numbers(&v["minDetJac"]), numbers(&v["maxDetJac"]));
    for (e, j) in mesh.jacobian_judge(None).unwrap().iter().enumerate() {
        let (glo, ghi) = (4.0 * lo[e], 4.0 * hi[e]);
        let tol = 1e-9 * j.max_det;
        assert!(
            glo <= j.min_det + tol && ghi >= j.max_det - tol,
            "{what}: element {e}: Gmsh [{glo}, {ghi}], ours {j:?}"
        );
        assert!(
            j.min_det - glo <= 0.01 * j.max_det && ghi - j.max_det <= 0.01 * j.max_det,
            "{what}: element {e}: Gmsh [{glo}, {ghi}], ours {j:?}"
        );
    }
}

#[test]
fn gmsh_reads_our_high_order_msh_of_orders_2_to_5() {
    if !python_module_available("gmsh") {
        return;
    }
    let dir = temp_dir("gmsh");
    for order in 2..=5 {
        for (name, mesh) in [("cylinder", cylinder(order)), ("sphere", sphere(order))] {
            // our own judge agrees the elements are valid
            let judged = mesh.jacobian_judge(None).unwrap();
            assert!(
                judged.iter().all(|j| j.min_det > 0.0 && j.ratio > 0.5),
                "{judged:?}"
            );
            for enc in [MshEncoding::Ascii, MshEncoding::Binary] {
                let what = format!("{name} order {order} {enc:?}");
                let path = dir.join(format!("{name}-{order}-{enc:?}.msh"));
                write_high_order_msh(&path, &mesh, None, MshWriteOptions::new(enc)).unwrap();
                let back = dir.join(format!("{name}-{order}-{enc:?}-by-gmsh.msh"));
                let v = script_json("gmsh", GMSH_SCRIPT, &[path.as_os_str(), back.as_os_str()]);
                check_gmsh_view(&v, &mesh, &what, enc == MshEncoding::Binary);
                println!(
                    "{what}: gmsh sees {} nodes, minSJ from {:.3}",
                    mesh.nodes.len(),
                    numbers(&v["minSJ"][gmsh_quad_type(order).unwrap().to_string()])
                        .into_iter()
                        .fold(f64::INFINITY, f64::min)
                );
                // and our reader reads our file and Gmsh's binary rewrite
                // of it back as the same mesh
                let want = without_parameters(&mesh);
                assert_eq!(read_high_order_msh(&path).unwrap(), want, "{what}");
                assert_eq!(
                    read_high_order_msh(&back).unwrap(),
                    want,
                    "{what}, Gmsh's rewrite"
                );
            }
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn gmsh_agrees_with_our_orderings_up_to_order_10() {
    if !python_module_available("gmsh") {
        return;
    }
    let dir = temp_dir("gmsh-high");
    for order in 6..=10 {
        let mesh = cylinder(order);
        let what = format!("cylinder order {order}");
        let path = dir.join(format!("cylinder-{order}.msh"));
        let back = dir.join(format!("cylinder-{order}-by-gmsh.msh"));
        write_high_order_msh(
            &path,
            &mesh,
            None,
            MshWriteOptions::new(MshEncoding::Binary),
        )
        .unwrap();
        let v = script_json("gmsh", GMSH_SCRIPT, &[path.as_os_str(), back.as_os_str()]);
        check_gmsh_view(&v, &mesh, &what, true);
        let want = without_parameters(&mesh);
        assert_eq!(
            read_high_order_msh(&back).unwrap(),
            want,
            "{what}, Gmsh's rewrite"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn meshio_reads_our_lagrange_vtu() {
    if !python_module_available("meshio") {
        return;
    }
    let dir = temp_dir("meshio");
    for order in [2, 3, 5] {
        let mesh = sphere(order);
        let path = dir.join(format!("sphere-{order}.vtu"));
        write_high_order_vtu(&mesh, &path).unwrap();
        let v = script_json("meshio", MESHIO_SCRIPT, &[path.as_os_str()]);
        let points: Vec<Vec<f64>> = v["points"]
            .as_array()
            .unwrap()
            .iter()
            .map(doubles)
            .collect();
        assert_eq!(points.len(), mesh.nodes.len());
        for (p, q) in points.iter().zip(&mesh.nodes) {
            assert!(near(p, q), "{p:?} vs {q:?}");
        }
        let blocks = v["blocks"].as_array().unwrap();
        assert_eq!(blocks.len(), 1, "order {order}: {blocks:?}");
        assert_eq!(blocks[0]["type"], "VTK_LAGRANGE_QUADRILATERAL");
        let cells = blocks[0]["cells"].as_array().unwrap();
        assert_eq!(cells.len(), mesh.num_elements());
        let perm = vtk_quad_ordering(order).unwrap();
        for (e, cell) in cells.iter().enumerate() {
            let got: Vec<u64> = cell
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_u64().unwrap())
                .collect();
            let want: Vec<u64> = perm.iter().map(|&p| mesh.element(e)[p] as u64).collect();
            assert_eq!(got, want, "order {order}, cell {e}");
        }
        let faces = doubles(&v["cell_data"]["cad_face"][0]);
        assert_eq!(faces, vec![1.0; mesh.num_elements()]);
        let ratios = doubles(&v["cell_data"]["jacobian_ratio"][0]);
        let want = mesh.jacobian_ratios().unwrap();
        assert!(near(&ratios, &want), "{ratios:?} vs {want:?}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
