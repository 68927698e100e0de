//! The industrial corpus (`data/industrial`, issue 32 item 3): small parts of it
//! meshed by the default method are valid by both judges (CAD normals and
//! element geometry) outside the quads excused at CAD corners below 10°, closed
//! (no open edge), the same bytes for 1 and 2 threads, and hold the face
//! count its MANIFEST.json records.

mod common;

use std::path::{Path, PathBuf};

use common::{quadrille, stats_json};

/// A part of `data/industrial`.
fn industrial(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../data/industrial")
        .join(name)
}

/// The face count MANIFEST.json records for `file`.
fn manifest_faces(file: &str) -> u64 {
    let text = std::fs::read_to_string(industrial("MANIFEST.json")).unwrap();
    let manifest: serde_json::Value = serde_json::from_str(&text).unwrap();
    let parts = manifest["parts"].as_array().unwrap();
    let part = parts.iter().find(|p| p["file"] == file).unwrap();
    part["faces"].as_u64().unwrap()
}

/// `quadrille mesh MODEL [--method METHOD] --threads N --quiet` into `out`
/// (the default method when `method` is `None`).
fn mesh_part(model: &Path, out: &Path, method: Option<&str>, threads: &str) -> std::process::Output {
    let mut args = vec!["mesh", model.to_str().unwrap(), "-o", out.to_str().unwrap()];
    if let Some(m) = method {
        args.extend(["--method", m]);
    }
    args.extend(["--threads", threads, "--quiet"]);
    quadrille(&args)
}

/// Meshes `model` into `out` (`method`, `threads`), checks the run
/// succeeded and returns the mesh's `stats --cad --json`.
fn meshed_stats(
    model: &Path,
    out: &Path,
    method: Option<&str>,
    threads: &str,
    label: &str,
) -> serde_json::Value {
    let r = mesh_part(model, out, method, threads);
    assert!(r.status.success(), "{label}: {}", String::from_utf8_lossy(&r.stderr));
    serde_json::from_str(&stats_json(out, model)).unwrap()
}

/// Checks `s` (a `stats --cad --json` report) has no quad inverted by
/// either judge outside the excused sharp corners and no open edge.
fn assert_valid_and_closed(s: &serde_json::Value, label: &str) {
    assert_eq!(s["inverted_quads_outside_sharp"], 0, "{label}: {s}");
    assert_eq!(s["inverted_quads_element_geometry_outside_sharp"], 0, "{label}: {s}");
    assert_eq!(s["open_edges"], 0, "{label}: {s}");
}

#[test]
fn small_corpus_parts_mesh_valid_by_both_judges_and_closed() {
    // a thread-simulating screw (13 faces), a cusp prism (2 cusp corners on
    // each end face), a plate with variable-radius fillets
    for name in [
        "socket_head_cap_screw_m6x20.step",
        "t_cusp_prism.step",
        "t_variable_fillet_plate.step",
    ] {
        let model = industrial(name);
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("part.msh");
        let s = meshed_stats(&model, &out, None, "1", name);
        assert!(s["quads"].as_u64().unwrap() > 100, "{name}: {s}");
        assert_eq!(s["triangles"], 0, "{name}");
        assert_valid_and_closed(&s, name);
        assert_eq!(s["non_manifold_edges"], 0, "{name}");
        // two threads write the same bytes
        let two = dir.path().join("part-2.msh");
        let r = mesh_part(&model, &two, None, "2");
        assert!(r.status.success(), "{name}");
        assert!(
            std::fs::read(&out).unwrap() == std::fs::read(&two).unwrap(),
            "{name}: the meshes of 1 and 2 threads differ"
        );
        // the loaded model is the part the manifest describes
        let info = quadrille(&["info", model.to_str().unwrap(), "--json"]);
        assert!(info.status.success(), "{name}");
        let info: serde_json::Value = serde_json::from_slice(&info.stdout).unwrap();
        assert_eq!(info["faces"].as_u64(), Some(manifest_faces(name)), "{name}");
    }
    // the cusp prism's two cusps (on each end face) are found as sharp corners
    let model = industrial("t_cusp_prism.step");
    let dir = tempfile::tempdir().unwrap();
    let s = meshed_stats(&model, &dir.path().join("cusp.msh"), None, "1", "cusp prism");
    assert!(!s["sharp_corners"].as_array().unwrap().is_empty(), "{s}");
}

/// Meshes `model` (default method, one thread) into `out` and returns its
/// `stats --cad --json` after checking it is closed, valid by both judges
/// and free of irregular face-interior vertices.
fn meshed_regular_and_valid(model: &Path, out: &Path, label: &str) -> serde_json::Value {
    let s = meshed_stats(model, out, None, "1", label);
    assert_eq!(s["irregular_nodes"], 0, "{label}: {s}");
    assert_valid_and_closed(&s, label);
    s
}

#[test]
fn washers_are_ring_grids_with_no_irregular_vertex() {
    // each flat side of a washer is an annulus between two circles: the
    // curve plan gives both circles one count and `direct::ring_face`
    // meshes it as a log-polar ring grid; the bore and the rims are bands
    // between circles of that count, so nothing is irregular. Before the
    // ring grids: 8 irregular vertices on the plain washer, 32 on the
    // chamfered one (Gmsh: 5.9 % and 5.0 %).
    for name in ["plain_washer_m8.step", "chamfered_washer_m8.step"] {
        let model = industrial(name);
        let dir = tempfile::tempdir().unwrap();
        let s = meshed_regular_and_valid(&model, &dir.path().join("washer.msh"), name);
        assert!(s["quads"].as_u64().unwrap() > 300, "{name}: {s}");
        // square cells: the worst quad is far from a sliver
        assert!(s["sicn"]["min"].as_f64().unwrap() > 0.6, "{name}: {s}");
    }
}

#[test]
fn a_shaft_keys_obround_faces_are_plain_grids() {
    // the key's top and bottom are stadiums (two half circles, two lines,
    // tangent): `direct::o_grid` meshes each as one grid whose corners sit
    // on the half circles, so no face-interior vertex is irregular (the
    // ringed O-grid left 4 valence-3 vertices on each: 1.27 %; Gmsh 0.8 %);
    // the worst quads are those four corners, about sin(e / R)
    let model = industrial("shaft_key_d20.step");
    let dir = tempfile::tempdir().unwrap();
    let s = meshed_regular_and_valid(&model, &dir.path().join("key.msh"), "shaft key");
    assert!(s["quads"].as_u64().unwrap() > 500, "{s}");
    let sicn = &s["sicn"];
    assert!(sicn["min"].as_f64().unwrap() >= 0.2, "{s}");
    assert!(sicn["avg"].as_f64().unwrap() > 0.97, "{s}");
}

#[test]
fn the_unstructured_method_meshes_a_face_cut_open_by_a_slit() {
    // the bearing's face 28 is a plane annulus cut open by a line used on
    // both sides of one loop: no (u, v) triangulation takes it, and the
    // plain method used to stop there ("two boundary points coincide")
    let name = "angular_contact_bearing_10_30_9.step";
    let model = industrial(name);
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("bearing.msh");
    let s = meshed_stats(&model, &out, Some("unstructured"), "1", name);
    assert_eq!(s["triangles"], 0, "{s}");
    assert_valid_and_closed(&s, name);
    assert_eq!(s["non_manifold_edges"], 0, "{s}");
}

#[test]
fn regular_method_meshes_a_part_its_baseline_cannot() {
    // the socket-weld flange's bolt-hole face has a curve beside a hole where
    // the baseline's triangle split leaves quads inverted at any curve
    // refinement ("face 3 could not be meshed: 8 quads stay inverted"); the
    // regular method regularizes the default method's mesh there instead
    // (the blind flange, which failed the same way, meshes since the ring
    // grids changed its curve counts)
    let name = "socket_weld_flange_1in_150.step";
    let model = industrial(name);
    let base_dir = tempfile::tempdir().unwrap();
    let base = mesh_part(&model, &base_dir.path().join("b.msh"), Some("baseline"), "1");
    assert!(
        !base.status.success(),
        "the baseline now meshes {name}: update this test"
    );
    let dir = tempfile::tempdir().unwrap();
    let (one, two) = (dir.path().join("one.msh"), dir.path().join("two.msh"));
    let s = meshed_stats(&model, &one, Some("regular"), "1", name);
    assert!(s["quads"].as_u64().unwrap() > 500, "{s}");
    assert_eq!(s["triangles"], 0);
    assert_valid_and_closed(&s, name);
    assert!(s["irregular_percent"].as_f64().unwrap() <= 5.0, "{s}");
    // the same mesh on two threads
    let r = mesh_part(&model, &two, Some("regular"), "2");
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    assert!(std::fs::read(&one).unwrap() == std::fs::read(&two).unwrap());
}

#[test]
fn the_threaded_rods_narrow_lens_faces_get_two_rows_of_quads() {
    // 83 faces; 44 of them are lenses between two nearly coincident helical
    // curves (about 2.5e-4 wide, 1.5 long: thread run-outs). Before
    // `direct::strip_face` the frontal mesher folded on them (face 3: 9 quads
    // stayed inverted, no mesh after about 100 s of CPU). Now each lens is two
    // rows of near-rectangles, all the rod's quads valid by both judges.
    // Gmsh 4.x on this part: 12.7 % irregular, average SICN 0.52, 195/161
    // inverted quads (CAD normals / element geometry).
    let model = industrial("t_threaded_rod_m6.step");
    let dir = tempfile::tempdir().unwrap();
    let s = meshed_stats(&model, &dir.path().join("rod.msh"), None, "1", "rod");
    assert!(s["quads"].as_u64().unwrap() > 5000, "{s}");
    assert_eq!(s["triangles"], 0, "{s}");
    // no exemption: not one inverted quad by either judge
    assert_eq!(s["inverted_quads"], 0, "{s}");
    assert_eq!(s["inverted_quads_element_geometry"], 0, "{s}");
    assert_eq!(s["open_edges"], 0, "{s}");
    assert_eq!(s["non_manifold_edges"], 0, "{s}");
    assert!(s["sicn"]["min"].as_f64().unwrap() > 0.0, "{s}");
    // measured 0.804 (Gmsh 0.52); irregular 13.7 % (Gmsh 12.7 %: not yet met)
    assert!(s["sicn"]["avg"].as_f64().unwrap() > 0.7, "{s}");
    assert!(s["irregular_percent"].as_f64().unwrap() < 15.0, "{s}");
}

#[test]
fn a_hex_nuts_faces_are_ring_grids_despite_their_sliver_corners() {
    // each end face of the unchamfered nut is an annulus between a hexagon
    // and the bore; the across-corners cylinder turns each hex corner into
    // two 150° junctions with an arc of 0.004 between them, and the hexagon
    // wants three times the bore's count. The bore's chord reaches only the
    // bore's cylinder and the other end face (a contained raise), so the
    // curve plan raises the bore to the hexagon's count and the ring grid
    // holds the quads at the arcs to validity only: no irregular vertex in
    // the part (before: 64 on the two end faces, 1,984 quads; Gmsh: 3.2 %).
    // The bore's cylinder keeps its rows (6), so the quads are 3,888, not
    // the 5,184 of a cylinder squared to the raised count.
    let model = industrial("unchamfered_hex_nut_m6.step");
    let dir = tempfile::tempdir().unwrap();
    let s = meshed_regular_and_valid(&model, &dir.path().join("nut.msh"), "nut");
    let quads = s["quads"].as_u64().unwrap();
    assert!((3000..=4000).contains(&quads), "{s}");
    assert!(s["sicn"]["avg"].as_f64().unwrap() > 0.84, "{s}");
}

#[test]
fn a_hex_heads_annulus_does_not_carry_its_count_down_the_shank() {
    // the hex head screw's underside is an annulus of the same kind
    // (hexagon around the shank), but the shank's chord runs on through
    // the shank, an end ring and the end disk: the raise is not contained,
    // so the plan leaves the shank's count alone (a raise gave 3,735 quads
    // for one irregular vertex fewer; today 1,390, 27 irregular).
    let model = industrial("hex_head_screw_m8x25.step");
    let dir = tempfile::tempdir().unwrap();
    let s = meshed_stats(&model, &dir.path().join("screw.msh"), None, "1", "screw");
    assert_valid_and_closed(&s, "screw");
    assert!(s["quads"].as_u64().unwrap() <= 1500, "{s}");
    assert!(s["irregular_nodes"].as_u64().unwrap() <= 30, "{s}");
}
