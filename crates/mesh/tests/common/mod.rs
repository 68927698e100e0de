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

/// The Python that has gmsh: `QUADRILLE_PYTHON` (set by `run-tests`), else `python3`.
pub fn python() -> String {
    std::env::var("QUADRILLE_PYTHON")
        .ok()
        .filter(|s| !s.is_empty())
        .unwrap_or_else(|| "python3".to_string())
}

/// True when the Python module `module` imports; false (the test skips) when
/// it does not, unless `QUADRILLE_REQUIRE_GMSH=1`, where it panics.
pub fn python_module_available(module: &str) -> bool {
    let ok = Command::new(python())
        .args(["-c", &format!("import {module}")])
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false);
    if !ok {
        if std::env::var("QUADRILLE_REQUIRE_GMSH").as_deref() == Ok("1") {
            panic!("QUADRILLE_REQUIRE_GMSH=1 but the {module} Python module is not importable (pip install {module})");
        }
        eprintln!("SKIPPED {module} interop test: the {module} Python module is not importable (set QUADRILLE_REQUIRE_GMSH=1 to make this an error)");
    }
    ok
}
