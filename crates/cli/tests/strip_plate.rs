//! Strips along straight sides of wide faces (issue 32), on the parts of
//! `data/strips`. The size map's width rule (strips narrower than the floor)
//! and turn rule (fillets whose 90° arc is shorter than the floor) lower the
//! floor on narrow faces, and the grading from there refined the wide faces
//! beside them. Such strips now keep the floor
//! (`narrow::keep_strips_off_wide_faces`). The bounds below lie between the
//! figures before and after.

mod common;

use std::path::Path;

use common::{json_number, mesh_logged, stats_json};

/// Meshes `data/strips/<file>` with the size map's debug log and returns the
/// log, the number of narrow faces dropped from the lowered floor, and the
/// `stats --json` of the mesh, after checking that it is valid by both
/// judges and closed.
fn mesh_strips(file: &str) -> (String, usize, String) {
    let model = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../data/strips")
        .join(file);
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("strips.msh");
    let r = mesh_logged(&model, &out, "quadrille::field::size_map=debug", &["--quiet"]);
    let log = String::from_utf8_lossy(&r.stderr).into_owned();
    assert!(r.status.success(), "{log}");
    let dropped = log.matches("dropped (a long straight side").count();
    let stats = stats_json(&out, &model);
    for key in [
        "inverted_quads_outside_sharp",
        "inverted_quads_element_geometry_outside_sharp",
        "open_edges",
    ] {
        assert_eq!(json_number(&stats, key), 0.0, "{key}: {stats}");
    }
    (log, dropped, stats)
}

/// The plate, 113.93 × 49.41 × 2.11 with 0.72 edge fillets: the width rule
/// lowered the floor (2.59) to the fillets' and side walls' widths (0.74 and
/// 1.55): 5,918 quads and 241 irregular vertices (5.25 %) where Gmsh has
/// 3,641 and 106 (3.61 %); with the strips kept at the floor, 2,323 quads
/// and 56 (3.24 %).
#[test]
fn strips_along_straight_sides_keep_the_floor() {
    let (log, dropped, stats) = mesh_strips("thin_plate_edge_fillets.step");
    // the four edge fillets and the four side walls are strips the rule
    // would lower; every one of them lies along a straight side of a wide face
    let candidates = log.matches("width rule: face").count();
    assert!(dropped >= 8, "{dropped} strips dropped of {candidates}\n{log}");
    let quads = json_number(&stats, "quads");
    assert!(quads <= 3000.0, "{quads} quads");
    let irregular = json_number(&stats, "irregular_percent");
    assert!(irregular <= 4.0, "irregular {irregular} %");
}

/// The pocketed block, 67.55 × 25.39 × 15.46 with 0.49 fillets on all twelve
/// edges: the turn rule lowered the floor (1.54) to the fillets' 90° arc
/// (0.77), and the grading made every long edge 0.7 long: 9,653 quads, 48
/// irregular vertices (0.57 %; Gmsh 8,244 and 23, 0.32 %). With the twelve
/// edge fillets kept at the floor: 4,112 quads, 8 irregular (0.24 %). The
/// eight corner blends keep their lowered floor (no long side).
#[test]
fn edge_fillets_along_straight_sides_keep_the_floor() {
    let (log, dropped, stats) = mesh_strips("pocket_block_edge_fillets.step");
    // the size map is built twice (the size guard's estimate, then the
    // mesh): per build 20 faces turned, the 12 edge fillets dropped
    let turned = log.matches("turn rule: face").count();
    assert!(turned > 0 && turned % 20 == 0, "{turned} turned\n{log}");
    assert_eq!(dropped * 20, turned * 12, "{dropped} dropped of {turned}\n{log}");
    let quads = json_number(&stats, "quads");
    assert!(quads <= 6000.0, "{quads} quads");
    let irregular = json_number(&stats, "irregular_percent");
    assert!(irregular <= 0.4, "irregular {irregular} %");
}
