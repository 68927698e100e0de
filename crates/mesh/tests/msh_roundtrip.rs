//! MSH 4.1 write → read round trips (ASCII and binary), and the reader's
//! behaviour on truncated and corrupted files.

use std::path::{Path, PathBuf};

use mesh::fixtures::{cube, square_grid};
use mesh::msh::{read_msh, read_msh_bytes, write_msh, write_msh_to, MshEncoding, MshWriteOptions};
use mesh::stats::MeshStats;
use mesh::{NodeClass, QuadMesh};

fn temp_dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("quadrille-msh-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Everything the file format keeps, compared exactly.
fn assert_same(a: &QuadMesh, b: &QuadMesh) {
    assert_eq!(a.nodes, b.nodes);
    assert_eq!(a.node_class, b.node_class);
    assert_eq!(a.quads, b.quads);
    assert_eq!(a.quad_face, b.quad_face);
    assert_eq!(a.triangles, b.triangles);
    assert_eq!(a.triangle_face, b.triangle_face);
    assert_eq!(a.curve_edges, b.curve_edges);
    assert_eq!(a.corner_nodes, b.corner_nodes);
}

/// A cube mesh with awkward coordinates (not exactly representable in
/// decimal, tiny and huge magnitudes) to check that coordinates round-trip bit for bit.
fn awkward_cube() -> (geometry::Model, QuadMesh) {
    let (model, mut mesh) = cube(1.0 / 3.0, 3);
    for (i, p) in mesh.nodes.iter_mut().enumerate() {
        p[0] += 1e-17 * i as f64;
        p[2] *= 1.0 + 1e-9;
    }
    mesh.nodes[0][1] = 1.234e-300;
    mesh.nodes[1][1] = -9.87e250;
    (model, mesh)
}

#[test]
fn ascii_and_binary_round_trips_keep_everything() {
    let dir = temp_dir("rt");
    for (name, (model, mesh)) in [("cube", awkward_cube()), ("square", square_grid(2.0, 4))] {
        for enc in [MshEncoding::Ascii, MshEncoding::Binary] {
            for with_model in [true, false] {
                let path = dir.join(format!("{name}-{enc:?}-{with_model}.msh"));
                // with parameters: the file keeps everything the mesh holds
                let opts = MshWriteOptions::new(enc).with_parametric(true);
                write_msh(&path, &mesh, with_model.then_some(&model), opts).unwrap();
                let r = read_msh(&path).unwrap();
                assert_eq!(r.version, "4.1");
                assert_eq!(r.binary, enc == MshEncoding::Binary);
                assert!(r.skipped_elements.is_empty());
                assert_same(&mesh, &r.mesh);
                let nc = model.corners.len();
                assert_eq!(
                    r.entity_counts,
                    [nc, model.curves.len(), model.faces.len(), 0]
                );
            }
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn read_back_cube_is_closed_with_euler_two() {
    let (model, mesh) = cube(2.0, 4);
    let mut bytes = Vec::new();
    let opts = MshWriteOptions::new(MshEncoding::Binary);
    write_msh_to(&mut bytes, &mesh, Some(&model), opts).unwrap();
    let r = read_msh_bytes(&bytes, Path::new("cube.msh")).unwrap();
    let s = MeshStats::compute(&r.mesh, Some(&model));
    assert_eq!(s.open_edges, 0);
    assert_eq!(s.non_manifold_edges, 0);
    assert_eq!(s.euler_characteristic, 2);
    assert_eq!((s.nodes, s.quads), (6 * 9 + 12 * 3 + 8, 96));
    assert_eq!(s.face_interior_nodes, 54);
    assert_eq!(s.valence_histogram.get(&4), Some(&54));
    assert_eq!(s.inverted_quads, 0);
    assert!(s.cad_distance.unwrap().max < 1e-12);
    // an open square: every boundary mesh edge is open
    let (_, sq) = square_grid(1.0, 5);
    let s = MeshStats::compute(&sq, None);
    assert_eq!(s.open_edges, 20);
    assert_eq!(s.euler_characteristic, 1);
}

#[test]
fn mixed_unclassified_and_parameterless_nodes() {
    let (model, mut mesh) = square_grid(1.0, 3);
    // drop some parameters and one classification, add a triangle
    mesh.node_class[5] = NodeClass::Face(geometry::FaceId(0), None);
    mesh.node_class[1] = NodeClass::Curve(geometry::CurveId(0), None);
    mesh.nodes.push([0.5, -0.2, 0.0]);
    mesh.node_class.push(NodeClass::Unclassified);
    mesh.triangles.push([0, 1, 16]);
    mesh.triangle_face.push(geometry::FaceId(0));
    for enc in [MshEncoding::Ascii, MshEncoding::Binary] {
        let mut bytes = Vec::new();
        let opts = MshWriteOptions::new(enc).with_parametric(true);
        write_msh_to(&mut bytes, &mesh, Some(&model), opts).unwrap();
        let r = read_msh_bytes(&bytes, Path::new("mixed.msh")).unwrap();
        assert_eq!(r.mesh.nodes, mesh.nodes);
        assert_eq!(r.mesh.triangles, mesh.triangles);
        // a block with a parameterless node is written without parameters
        assert_eq!(
            r.mesh.node_class[5],
            NodeClass::Face(geometry::FaceId(0), None)
        );
        assert_eq!(
            r.mesh.node_class[6],
            NodeClass::Face(geometry::FaceId(0), None)
        );
        assert_eq!(
            r.mesh.node_class[1],
            NodeClass::Curve(geometry::CurveId(0), None)
        );
        // the unclassified node lands on the face of its triangle
        assert_eq!(
            r.mesh.node_class[16],
            NodeClass::Face(geometry::FaceId(0), None)
        );
        // other curves keep their parameters
        assert!(matches!(r.mesh.node_class[7], NodeClass::Curve(_, Some(_))));
    }
}

#[test]
fn truncated_and_corrupted_files_give_errors_not_panics() {
    let (model, mesh) = cube(1.0, 2);
    let encodings = [MshEncoding::Ascii, MshEncoding::Binary];
    for (enc, parametric) in encodings.into_iter().flat_map(|e| [(e, false), (e, true)]) {
        let mut bytes = Vec::new();
        let opts = MshWriteOptions::new(enc).with_parametric(parametric);
        write_msh_to(&mut bytes, &mesh, Some(&model), opts).unwrap();
        let name = Path::new("broken.msh");
        // every truncation point short of the final "$EndElements" fails
        let end = bytes.len() - "$EndElements\n".len();
        for cut in (0..end).step_by(7) {
            let err = read_msh_bytes(&bytes[..cut], name);
            assert!(
                err.is_err(),
                "{enc:?} cut at {cut} of {} was accepted",
                bytes.len()
            );
            assert!(err.unwrap_err().to_string().starts_with("broken.msh: "));
        }
        // corrupted bytes: any result, but no panic
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        for _ in 0..400 {
            let mut b = bytes.clone();
            for _ in 0..3 {
                seed ^= seed << 13;
                seed ^= seed >> 7;
                seed ^= seed << 17;
                let i = (seed % b.len() as u64) as usize;
                b[i] = (seed >> 32) as u8;
            }
            let _ = read_msh_bytes(&b, name);
        }
    }
}

#[test]
fn missing_file_is_an_io_error_naming_it() {
    let err = read_msh(Path::new("/nonexistent/dir/x.msh"))
        .unwrap_err()
        .to_string();
    assert!(err.starts_with("/nonexistent/dir/x.msh: "), "{err}");
    let (_, mesh) = square_grid(1.0, 1);
    let err = write_msh(
        Path::new("/nonexistent/dir/y.msh"),
        &mesh,
        None,
        MshWriteOptions::default(),
    )
    .unwrap_err();
    assert!(
        err.to_string().starts_with("/nonexistent/dir/y.msh: "),
        "{err}"
    );
}
