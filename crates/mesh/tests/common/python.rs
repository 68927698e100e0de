//! The Python the Gmsh and meshio tests run (shared by the `mesh` and `cli`
//! test suites; the `cli` tests include this file by path).

use std::process::Command;

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
        eprintln!("SKIPPED {module} test: the {module} Python module is not importable (set QUADRILLE_REQUIRE_GMSH=1 to make this an error)");
    }
    ok
}
