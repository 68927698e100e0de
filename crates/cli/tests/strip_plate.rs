//! Strips along straight sides of wide faces (issue 32): the plate of
//! `data/strips`, 113.93 × 49.41 × 2.11 with 0.72 edge fillets. The width
//! rule used to lower the floor (2.59) to the fillets' and side walls'
//! widths (0.74 and 1.55), and the grading from there refined both wide
//! faces: 5,918 quads and 241 irregular vertices (5.25 %) where Gmsh has
//! 3,641 and 106 (3.61 %). With the strips kept at the floor
//! (`narrow::keep_strips_off_wide_faces`) it is 2,323 quads and 56 (3.24 %).
//! The bounds below lie between the two.

mod common;

use std::path::Path;

use common::{json_number, mesh_logged, stats_json};

#[test]
fn strips_along_straight_sides_keep_the_floor() {
    let model = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../data/strips/thin_plate_edge_fillets.step");
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("plate.msh");
    let r = mesh_logged(&model, &out, "quadrille::field::size_map=debug", &["--quiet"]);
    let log = String::from_utf8_lossy(&r.stderr).into_owned();
    assert!(r.status.success(), "{log}");
    // the four edge fillets and the four side walls are strips the rule
    // would lower; every one of them lies along a straight side of a wide face
    let candidates = log.matches("width rule: face").count()
        - log.matches("dropped (a long straight side").count();
    let dropped = log.matches("dropped (a long straight side").count();
    assert!(dropped >= 8, "{dropped} strips dropped of {candidates}\n{log}");
    let stats = stats_json(&out, &model);
    let quads = json_number(&stats, "quads");
    assert!(quads <= 3000.0, "{quads} quads");
    let irregular = json_number(&stats, "irregular_percent");
    assert!(irregular <= 4.0, "irregular {irregular} %");
    for key in [
        "inverted_quads_outside_sharp",
        "inverted_quads_element_geometry_outside_sharp",
        "open_edges",
    ] {
        assert_eq!(json_number(&stats, key), 0.0, "{key}: {stats}");
    }
}
