//! `quadrille mesh --method unstructured`: writes a valid all-quad mesh that
//! `quadrille stats` accepts, and bad sizes are refused cleanly.

mod common;

use common::{assert_clean_failure, cad, quadrille, stats_json};

#[test]
fn unstructured_method_writes_a_valid_mesh() {
    let dir = tempfile::tempdir().unwrap();
    let model = cad("s11o_cube_cyl.stp");
    let out = dir.path().join("m.msh");
    let r = quadrille(&[
        "mesh",
        model.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--method",
        "unstructured",
        "--threads",
        "1",
    ]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let stderr = String::from_utf8_lossy(&r.stderr);
    assert!(stderr.contains("0 inverted"), "{stderr}");
    assert!(!stderr.contains("meshed with the baseline"), "{stderr}");
    let text = stats_json(&out, &model);
    assert!(
        text.contains("\"triangles\": 0") || text.contains("\"triangles\":0"),
        "{text}"
    );
    assert!(
        text.contains("\"inverted_quads\": 0") || text.contains("\"inverted_quads\":0"),
        "{text}"
    );
    assert!(
        text.contains("\"inverted_quads_element_geometry\": 0")
            || text.contains("\"inverted_quads_element_geometry\":0"),
        "{text}"
    );
}

#[test]
fn unstructured_method_refuses_a_bad_size() {
    let dir = tempfile::tempdir().unwrap();
    let model = cad("s11o_cube_cyl.stp");
    let out = dir.path().join("m.msh");
    let r = quadrille(&[
        "mesh",
        model.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--method",
        "unstructured",
        "--size=-1",
        "--quiet",
    ]);
    assert!(!r.status.success());
    assert_clean_failure(&r, "s11o_cube_cyl");
    assert!(!out.exists());
}
