//! Triangle-mesh models (STL, OBJ, PLY) on the command line: `info` and
//! `mesh` work on them as on CAD; bad triangle meshes give one clear error,
//! a non-zero exit, no panic and no output file.

mod common;

use std::path::{Path, PathBuf};

use common::{assert_clean_failure, quadrille};

/// Runs `quadrille mesh INPUT -o DIR/out.msh`, checks the failure contract; returns stderr.
fn mesh_fails(input: &Path, dir: &Path, extra: &[&str]) -> String {
    let out = dir.join("out.msh");
    let mut args = vec![
        "mesh",
        input.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--quiet",
    ];
    args.extend_from_slice(extra);
    let r = quadrille(&args);
    assert!(!r.status.success(), "must fail on {}", input.display());
    let stderr = assert_clean_failure(&r, &input.file_name().unwrap().to_string_lossy());
    assert!(!out.exists(), "no output file may be left behind");
    stderr
}

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, bytes).unwrap();
    p
}

/// A box as an OBJ: 8 vertices, 6 quads (fan-triangulated by the reader).
const BOX_OBJ: &str =
    "v 0 0 0\nv 2 0 0\nv 0 1 0\nv 2 1 0\nv 0 0 1.5\nv 2 0 1.5\nv 0 1 1.5\nv 2 1 1.5\n\
f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";

/// The box as a binary STL (two triangles per face).
fn box_stl() -> Vec<u8> {
    let soup = trimesh::read::read_bytes(
        BOX_OBJ.as_bytes(),
        trimesh::Format::Obj,
        Path::new("box.obj"),
    )
    .unwrap();
    trimesh::read::write_stl_binary(&soup.points, &soup.tris)
}

#[test]
fn info_and_mesh_work_on_an_stl_box() {
    let dir = tempfile::tempdir().unwrap();
    let stl = write(dir.path(), "box.stl", &box_stl());
    let r = quadrille(&["info", stl.to_str().unwrap(), "--json"]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let info: serde_json::Value = serde_json::from_slice(&r.stdout).unwrap();
    assert_eq!(
        (
            info["faces"].as_u64(),
            info["curves"].as_u64(),
            info["corners"].as_u64()
        ),
        (Some(6), Some(12), Some(8))
    );
    assert_eq!(info["boundary_curves"].as_u64(), Some(0));
    let out = dir.path().join("box.msh");
    let r = quadrille(&[
        "mesh",
        stl.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let r = quadrille(&[
        "stats",
        out.to_str().unwrap(),
        "--cad",
        stl.to_str().unwrap(),
        "--json",
    ]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let s: serde_json::Value = serde_json::from_slice(&r.stdout).unwrap();
    assert!(s["quads"].as_u64().unwrap() > 0);
    assert_eq!(s["triangles"].as_u64(), Some(0));
    assert_eq!(s["inverted_quads"].as_u64(), Some(0));
    assert_eq!(s["inverted_quads_element_geometry"].as_u64(), Some(0));
    assert_eq!(s["open_edges"].as_u64(), Some(0));
    // a feature angle above 90°: no box edge is a feature, the box is one
    // closed patch; no single map flattens it, so it is split into charts
    // (their borders are curves; no boundary curve: still closed)
    let r = quadrille(&[
        "info",
        stl.to_str().unwrap(),
        "--json",
        "--feature-angle",
        "95",
    ]);
    let info: serde_json::Value = serde_json::from_slice(&r.stdout).unwrap();
    assert!(info["faces"].as_u64().unwrap() >= 2, "{info}");
    assert_eq!(info["boundary_curves"].as_u64(), Some(0));
    // stats and render read a triangle-mesh --cad with the same options as
    // mesh (the mesh's faces must be the model's: at 60° the box keeps its 6
    // faces, and the nodes lie on them)
    let r = quadrille(&[
        "stats",
        out.to_str().unwrap(),
        "--cad",
        stl.to_str().unwrap(),
        "--feature-angle",
        "60",
        "--json",
    ]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let s: serde_json::Value = serde_json::from_slice(&r.stdout).unwrap();
    assert!(
        s["cad_distance"]["max_relative"].as_f64().unwrap() < 1e-9,
        "{s}"
    );
    let png = dir.path().join("box.png");
    let r = quadrille(&[
        "render",
        out.to_str().unwrap(),
        "-o",
        png.to_str().unwrap(),
        "--cad",
        stl.to_str().unwrap(),
        "--sicn",
        "--feature-angle",
        "60",
    ]);
    assert!(
        r.status.success() && png.exists(),
        "{}",
        String::from_utf8_lossy(&r.stderr)
    );
    let r = quadrille(&[
        "stats",
        out.to_str().unwrap(),
        "--cad",
        stl.to_str().unwrap(),
        "--feature-angle",
        "400",
    ]);
    assert!(!r.status.success());
    assert!(
        String::from_utf8_lossy(&r.stderr).contains("feature angle"),
        "{}",
        String::from_utf8_lossy(&r.stderr)
    );
}

#[test]
fn nan_coordinates() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(
        dir.path(),
        "nan.obj",
        BOX_OBJ.replace("v 2 1 0", "v 2 nan 0").as_bytes(),
    );
    let err = mesh_fails(&p, dir.path(), &[]);
    assert!(
        err.contains("line 4") && err.contains("non-finite"),
        "{err}"
    );
}

#[test]
fn zero_triangles() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(dir.path(), "empty.stl", b"solid empty\nendsolid empty\n");
    let err = mesh_fails(&p, dir.path(), &[]);
    assert!(err.contains("no triangle"), "{err}");
    let p = write(dir.path(), "points.obj", b"v 0 0 0\nv 1 0 0\n");
    mesh_fails(&p, dir.path(), &[]);
}

#[test]
fn non_manifold_obj() {
    let dir = tempfile::tempdir().unwrap();
    // the box plus a fin on its bottom front edge: three triangles on one edge
    let text = format!("{BOX_OBJ}v 1 -1 -1\nf 1 2 9\n");
    let p = write(dir.path(), "fin.obj", text.as_bytes());
    let err = mesh_fails(&p, dir.path(), &[]);
    assert!(
        err.contains("non-manifold edge")
            && err.contains("[0.0, 0.0, 0.0]")
            && err.contains("[2.0, 0.0, 0.0]"),
        "{err}"
    );
}

#[test]
fn truncated_binary_stl() {
    let dir = tempfile::tempdir().unwrap();
    let full = box_stl();
    let p = write(dir.path(), "cut.stl", &full[..full.len() - 30]);
    let err = mesh_fails(&p, dir.path(), &[]);
    assert!(
        err.contains("truncated") && err.contains("12 triangles"),
        "{err}"
    );
}

#[test]
fn bad_feature_edges_file() {
    let dir = tempfile::tempdir().unwrap();
    let stl = write(dir.path(), "box.stl", &box_stl());
    let fe = write(dir.path(), "edges.txt", b"1 2\n3 x\n");
    let out = dir.path().join("out.msh");
    let r = quadrille(&[
        "mesh",
        stl.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--feature-edges",
        fe.to_str().unwrap(),
    ]);
    let err = assert_clean_failure(&r, "edges.txt");
    assert!(err.contains("line 2") && !out.exists(), "{err}");
    let fe = write(dir.path(), "edges2.txt", b"1 500\n");
    let err = mesh_fails(&stl, dir.path(), &["--feature-edges", fe.to_str().unwrap()]);
    assert!(err.contains("feature edge 1"), "{err}");
}
