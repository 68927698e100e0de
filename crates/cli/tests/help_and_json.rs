//! The command-line surface: `info` and `stats` both take `--json`, and the
//! help texts say that triangle meshes are accepted as models.

mod common;

use common::{cad, quadrille};
use serde_json::Value;

#[test]
fn info_and_stats_both_take_json() {
    let dir = tempfile::tempdir().unwrap();
    let model = cad("s17o_sphere.stp");
    let r = quadrille(&["info", model.to_str().unwrap(), "--json"]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let info: Value = serde_json::from_slice(&r.stdout).expect("info --json is JSON");
    assert_eq!(info["faces"], 1);
    let out = dir.path().join("sphere.msh");
    let r = quadrille(&[
        "mesh",
        model.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let r = quadrille(&["stats", out.to_str().unwrap(), "--json"]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    let stats: Value = serde_json::from_slice(&r.stdout).expect("stats --json is JSON");
    assert!(stats["quads"].as_u64().unwrap() > 0, "{stats}");
    assert_eq!(stats["open_edges"], 0);
}

#[test]
fn help_says_triangle_meshes_are_accepted() {
    for args in [&["--help"][..], &["mesh", "--help"]] {
        let r = quadrille(args);
        assert!(r.status.success());
        let help = String::from_utf8_lossy(&r.stdout);
        assert!(
            help.contains("triangle mesh") && help.contains("STL, OBJ, PLY, MSH"),
            "{args:?}: {help}"
        );
    }
}
