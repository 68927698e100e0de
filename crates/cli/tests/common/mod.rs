//! Helpers shared by the CLI integration tests.

#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A CAD model bundled in `data/cad`.
pub fn cad(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../data/cad")
        .join(name)
}

/// Runs the `quadrille` binary with `args`.
pub fn quadrille(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_quadrille"))
        .args(args)
        .output()
        .unwrap()
}

/// `quadrille mesh MODEL -o OUT --threads 1 EXTRA...` with `QUADRILLE_LOG`
/// set to `log` (the tests that read the mesher's debug lines).
pub fn mesh_logged(model: &Path, out: &Path, log: &str, extra: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_quadrille"))
        .args(["mesh", model.to_str().unwrap(), "-o", out.to_str().unwrap()])
        .args(["--threads", "1"])
        .args(extra)
        .env("QUADRILLE_LOG", log)
        .output()
        .unwrap()
}

/// Checks the failure contract of a command: exit code 1, one `error: ` line,
/// no panic, the message naming `name`; returns stderr.
pub fn assert_clean_failure(r: &Output, name: &str) -> String {
    let stderr = String::from_utf8_lossy(&r.stderr).into_owned();
    assert_eq!(
        r.status.code(),
        Some(1),
        "clean error exit, not a crash: {stderr}"
    );
    assert!(!stderr.contains("panicked"), "panic: {stderr}");
    assert!(
        stderr.starts_with("error: "),
        "one clear error line: {stderr}"
    );
    assert!(stderr.contains(name), "error must name {name}: {stderr}");
    stderr
}

/// `quadrille stats MESH --cad CAD --json`, checked to succeed; its JSON text.
pub fn stats_json(mesh: &Path, cad: &Path) -> String {
    let s = quadrille(&[
        "stats",
        mesh.to_str().unwrap(),
        "--cad",
        cad.to_str().unwrap(),
        "--json",
    ]);
    assert!(s.status.success(), "{}", String::from_utf8_lossy(&s.stderr));
    String::from_utf8_lossy(&s.stdout).into_owned()
}

#[path = "../../../mesh/tests/common/python.rs"]
mod python;
#[allow(unused_imports)] // not every test binary uses both
pub use python::{python, python_module_available};

/// Every CAD model bundled in `data/cad` (`.step` and `.stp`), sorted.
pub fn all_cad_models() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/cad");
    let mut out: Vec<PathBuf> = std::fs::read_dir(&dir)
        .map(|rd| rd.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    out.retain(|p| {
        let ext = p.extension().and_then(|e| e.to_str()).unwrap_or("");
        ext.eq_ignore_ascii_case("step") || ext.eq_ignore_ascii_case("stp")
    });
    out.sort();
    out
}

/// The number after `"key":` in a JSON text.
pub fn json_number(json: &str, key: &str) -> f64 {
    let at = json
        .find(&format!("\"{key}\":"))
        .unwrap_or_else(|| panic!("no {key} in {json}"));
    json[at + key.len() + 3..]
        .split([',', '}'])
        .next()
        .unwrap()
        .trim()
        .parse()
        .unwrap_or_else(|_| panic!("{key} is not a number in {json}"))
}
