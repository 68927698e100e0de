//! The stage folders of `crates/quadrille/src` import one way only: each
//! folder may use the folders before it in [`LAYERS`] and itself, never one
//! after it. Read from the `crate::…` paths of the non-test code (comments,
//! `#[cfg(test)]` modules, test files and the `fixtures` folder skipped:
//! tests may use any layer). Also: no `.rs` file directly in `src` but `lib.rs`, and
//! no file over 800 lines of non-test code.

use std::fs;
use std::path::{Path, PathBuf};

/// The folders of `src`, bottom to top (ARCHITECTURE.md, "The `quadrille` crate").
const LAYERS: [&str; 20] = [
    "core",
    "combinatorics",
    "curves",
    "triangulate",
    "field",
    "smoothing",
    "direct",
    "frontal",
    "topology",
    "coarse",
    "curvenet",
    "shell",
    "ricci",
    "cones",
    "cut",
    "immersion",
    "layout_energy",
    "trace",
    "layout",
    "methods",
];

/// The folder of test fixtures, outside the order: tests may use any layer.
const FIXTURES: &str = "fixtures";

/// Longest file, in lines of non-test code.
const MAX_LINES: usize = 800;

fn src() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("src")
}

/// Every `.rs` file under `dir`.
fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in fs::read_dir(dir).expect("readable src") {
        let p = e.expect("entry").path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// True for a file that holds only tests or test fixtures.
fn is_test_file(rel: &Path) -> bool {
    let name = rel.file_name().and_then(|n| n.to_str()).unwrap_or("");
    name == "tests.rs"
        || rel
            .components()
            .any(|c| c.as_os_str() == "tests" || c.as_os_str() == FIXTURES)
}

/// The lines of `text` before its first `#[cfg(test)]` line.
fn non_test_lines(text: &str) -> Vec<&str> {
    text.lines()
        .take_while(|l| l.trim() != "#[cfg(test)]")
        .collect()
}

/// The first path segments after `crate::` on a code line (comments cut).
fn crate_paths(line: &str) -> Vec<String> {
    let code = line.split("//").next().unwrap_or("");
    let mut out = Vec::new();
    let mut rest = code;
    while let Some(i) = rest.find("crate::") {
        let before = rest[..i].chars().last();
        rest = &rest[i + "crate::".len()..];
        if before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == '$') {
            continue;
        }
        let seg: String = rest
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        out.push(seg);
    }
    out
}

/// (file, line, from folder, to path) of every import against the layer order.
fn violations() -> Vec<String> {
    let mut files = Vec::new();
    rust_files(&src(), &mut files);
    let rank = |s: &str| LAYERS.iter().position(|l| *l == s);
    let mut bad = Vec::new();
    for f in files {
        let rel = f.strip_prefix(src()).expect("under src").to_path_buf();
        if rel == Path::new("lib.rs") || is_test_file(&rel) {
            continue;
        }
        let folder = rel
            .components()
            .next()
            .and_then(|c| c.as_os_str().to_str())
            .unwrap_or("")
            .to_string();
        let Some(from) = rank(&folder) else {
            bad.push(format!("{}: not in a layer folder", rel.display()));
            continue;
        };
        let text = fs::read_to_string(&f).expect("readable");
        for (i, line) in non_test_lines(&text).iter().enumerate() {
            for seg in crate_paths(line) {
                // a crate-root item (a re-export of `lib.rs`) counts as the top
                let to = rank(&seg).unwrap_or(LAYERS.len());
                if to > from {
                    bad.push(format!(
                        "{}:{}: {folder} uses crate::{seg}",
                        rel.display(),
                        i + 1
                    ));
                }
            }
        }
    }
    bad
}

#[test]
fn folders_import_only_the_layers_below_them() {
    let bad = violations();
    assert!(
        bad.is_empty(),
        "imports against the layer order:\n{}",
        bad.join("\n")
    );
}

#[test]
fn the_layer_check_sees_an_upward_import() {
    assert_eq!(
        crate_paths("use crate::methods::driver::X; // crate::core"),
        vec!["methods".to_string()]
    );
    assert_eq!(
        crate_paths("let x = $crate::a + quadrille::b;"),
        Vec::<String>::new()
    );
    assert_eq!(
        non_test_lines("a\n#[cfg(test)]\nuse crate::methods;"),
        vec!["a"]
    );
}

#[test]
fn lib_rs_is_the_only_file_at_the_top_and_no_file_is_too_long() {
    let mut top: Vec<String> = fs::read_dir(src())
        .expect("src")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.is_file())
        .filter_map(|p| p.file_name().and_then(|n| n.to_str()).map(String::from))
        .collect();
    top.sort();
    assert_eq!(top, vec!["lib.rs".to_string()]);
    let mut folders: Vec<String> = fs::read_dir(src())
        .expect("src")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.is_dir())
        .filter_map(|p| p.file_name().and_then(|n| n.to_str()).map(String::from))
        .collect();
    folders.sort();
    let mut layers: Vec<String> = LAYERS.iter().map(|s| s.to_string()).collect();
    layers.push(FIXTURES.to_string());
    layers.sort();
    assert_eq!(
        folders, layers,
        "every folder has its place in LAYERS (or is the fixtures)"
    );
    let mut files = Vec::new();
    rust_files(&src(), &mut files);
    let long: Vec<String> = files
        .iter()
        .filter(|f| !is_test_file(f.strip_prefix(src()).expect("under src")))
        .filter_map(|f| {
            let n = non_test_lines(&fs::read_to_string(f).expect("readable")).len();
            (n > MAX_LINES).then(|| format!("{}: {n} lines", f.display()))
        })
        .collect();
    assert!(
        long.is_empty(),
        "files over {MAX_LINES} lines:\n{}",
        long.join("\n")
    );
}
