//! What the interop tests share: running the Python that has gmsh and
//! meshio (`QUADRILLE_PYTHON`), and skipping when it lacks a module.

use std::process::Command;

use serde_json::Value;

/// Runs the Python `script` (`tool` names it in the failure) on `args` and
/// returns the JSON it prints on its line starting with `JSON`.
pub fn script_json(tool: &str, script: &str, args: &[&std::ffi::OsStr]) -> Value {
    let out = Command::new(python())
        .arg("-c")
        .arg(script)
        .args(args)
        .output()
        .expect("python runs");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{tool} failed on {args:?}: {}\n{stdout}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json = stdout
        .lines()
        .find_map(|l| l.strip_prefix("JSON"))
        .expect("the script prints its JSON");
    serde_json::from_str(json).unwrap()
}

mod python;
#[allow(unused_imports)] // not every test binary uses both
pub use python::{python, python_module_available};
