//! `quadrille mesh` writes MSH 4.1 without parametric coordinates by default
//! (parametric flag 0 on every node block; entities and node classification
//! kept), and with them under `--parametric`; `quadrille stats` reads and
//! judges both alike.

mod common;

use std::path::Path;

use common::{cad, quadrille, stats_json};
use mesh::NodeClass;
use serde_json::Value;

/// `(dim, tag, parametric flag, node count)` of every node block of an ASCII MSH 4.1 file.
fn node_blocks(text: &str) -> Vec<[i64; 4]> {
    let section = text
        .split("$Nodes\n")
        .nth(1)
        .and_then(|s| s.split("$EndNodes").next())
        .expect("a $Nodes section");
    let mut lines = section.lines();
    let ints = |l: &str| -> Vec<i64> { l.split(' ').map(|t| t.parse().unwrap()).collect() };
    let head = ints(lines.next().unwrap());
    let mut blocks = Vec::new();
    for _ in 0..head[0] {
        let b = ints(lines.next().unwrap());
        let n = b[3];
        blocks.push([b[0], b[1], b[2], n]);
        // node tags, then one line of coordinates (and parameters) per node
        for _ in 0..n {
            lines.next().unwrap();
        }
        for _ in 0..n {
            let values = lines.next().unwrap().split(' ').count() as i64;
            let want = 3 + if b[2] == 1 { b[0] } else { 0 };
            assert_eq!(values, want, "block {b:?}");
        }
    }
    blocks
}

/// Meshes `model` into `out` (quietly, one thread) with `extra` arguments.
fn mesh_to(model: &Path, out: &Path, extra: &[&str]) {
    let mut args = vec![
        "mesh",
        model.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--quiet",
        "--threads",
        "1",
    ];
    args.extend_from_slice(extra);
    let r = quadrille(&args);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
}

#[test]
fn parametric_coordinates_only_with_the_flag() {
    let dir = tempfile::tempdir().unwrap();
    let model = cad("s12o_cube_rounded_1.stp");
    let plain = dir.path().join("plain.msh");
    let param = dir.path().join("param.msh");
    mesh_to(&model, &plain, &[]);
    mesh_to(&model, &param, &["--parametric"]);

    let plain_text = std::fs::read_to_string(&plain).unwrap();
    let blocks = node_blocks(&plain_text);
    // classification kept: blocks on corners, curves and faces
    for dim in 0..3 {
        assert!(blocks.iter().any(|b| b[0] == dim), "{blocks:?}");
    }
    assert!(blocks.iter().all(|b| b[2] == 0), "{blocks:?}");
    let param_blocks = node_blocks(&std::fs::read_to_string(&param).unwrap());
    for b in &param_blocks {
        assert_eq!(b[2], (b[0] > 0) as i64, "block {b:?}");
    }
    // the same blocks, entity for entity
    let strip =
        |v: &[[i64; 4]]| -> Vec<[i64; 3]> { v.iter().map(|b| [b[0], b[1], b[3]]).collect() };
    assert_eq!(strip(&blocks), strip(&param_blocks));

    // binary: the reader sees parameters exactly with the flag
    let plain_bin = dir.path().join("plain-bin.msh");
    let param_bin = dir.path().join("param-bin.msh");
    mesh_to(&model, &plain_bin, &["--binary"]);
    mesh_to(&model, &param_bin, &["--binary", "--parametric"]);
    let a = mesh::msh::read_msh(&plain_bin).unwrap();
    let b = mesh::msh::read_msh(&param_bin).unwrap();
    assert!(a.binary && b.binary);
    assert_eq!(a.mesh.nodes, b.mesh.nodes);
    let mut with_params = 0;
    for (x, y) in a.mesh.node_class.iter().zip(&b.mesh.node_class) {
        match (x, y) {
            (NodeClass::Curve(c, None), NodeClass::Curve(d, Some(_))) => assert_eq!(c, d),
            (NodeClass::Face(f, None), NodeClass::Face(g, Some(_))) => assert_eq!(f, g),
            (NodeClass::Corner(c), NodeClass::Corner(d)) => assert_eq!(c, d),
            other => panic!("classes differ: {other:?}"),
        }
        with_params += !matches!(y, NodeClass::Corner(_)) as usize;
    }
    assert!(with_params > 0);
    // and the ASCII default reads as the binary one
    let ascii = mesh::msh::read_msh(&plain).unwrap();
    assert_eq!(ascii.mesh.node_class, a.mesh.node_class);
    assert_eq!(ascii.mesh.quads, a.mesh.quads);
}

/// `quadrille stats --cad` judges a file without parametric coordinates as
/// the one with them: curve nodes get their parameter back by projection on
/// their curve, and a quad with no face node of known (u, v) takes the side
/// of a seam its projected face nodes are on. On these models (cylinders
/// whose seam runs along quads, non-periodic in OpenCASCADE's (u, v)) the
/// files without parameters once read with inverted quads.
#[test]
fn stats_judge_both_files_alike() {
    let dir = tempfile::tempdir().unwrap();
    for name in [
        "s11o_cube_cyl.stp",
        "i10o_simp.step",
        "n11o_limit_cycle.stp",
    ] {
        let model = cad(name);
        let plain = dir.path().join("plain.msh");
        let param = dir.path().join("param.msh");
        mesh_to(&model, &plain, &[]);
        mesh_to(&model, &param, &["--parametric"]);
        let sa: Value = serde_json::from_str(&stats_json(&plain, &model)).unwrap();
        let sb: Value = serde_json::from_str(&stats_json(&param, &model)).unwrap();
        for key in [
            "nodes",
            "quads",
            "irregular_nodes",
            "open_edges",
            "inverted_quads",
            "inverted_quads_element_geometry",
            "fold_corners",
        ] {
            assert_eq!(sa[key], sb[key], "{name}: {key}");
        }
        assert_eq!(sa["inverted_quads"], 0, "{name}");
        assert_eq!(sa["inverted_quads_element_geometry"], 0, "{name}");
        for key in ["min", "avg", "p1"] {
            let (a, b) = (
                sa["sicn"][key].as_f64().unwrap(),
                sb["sicn"][key].as_f64().unwrap(),
            );
            assert!((a - b).abs() < 1e-9, "{name}: SICN {key} {a} vs {b}");
        }
    }
}

#[test]
fn mesh_help_lists_parametric() {
    let r = quadrille(&["mesh", "--help"]);
    assert!(r.status.success());
    let help = String::from_utf8_lossy(&r.stdout);
    assert!(
        help.contains("--parametric") && help.contains("meshio"),
        "{help}"
    );
}
