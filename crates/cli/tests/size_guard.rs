//! The size guard of `quadrille mesh`: a size far too small is refused
//! before meshing with one line (the estimate, the memory, a size that
//! fits), exit code 1 and no file; `--max-quads` moves or lifts the limit;
//! `--timings` reports the estimate beside the count made.

mod common;

use std::path::Path;
use std::process::Output;
use std::time::Instant;

use common::{assert_clean_failure, cad, json_number, quadrille};

/// `quadrille mesh MODEL -o OUT --quiet EXTRA…`.
fn mesh(model: &Path, out: &Path, extra: &[&str]) -> Output {
    let mut args = vec![
        "mesh",
        model.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--quiet",
    ];
    args.extend_from_slice(extra);
    quadrille(&args)
}

/// The number after `flag ` in `text` (`--size 0.013` → 0.013).
fn value_after(text: &str, flag: &str) -> f64 {
    let rest = &text[text
        .find(&format!("{flag} "))
        .unwrap_or_else(|| panic!("no {flag}: {text}"))
        + flag.len()
        + 1..];
    rest.split(|c: char| c.is_whitespace() || c == ')' || c == ',')
        .next()
        .unwrap()
        .parse()
        .unwrap_or_else(|e| panic!("{flag} value in {text}: {e}"))
}

#[test]
fn a_far_too_small_size_is_refused_at_once_without_a_file() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("m1.msh");
    let started = Instant::now();
    let r = mesh(&cad("i01o_m1.step"), &out, &["--size", "1e-5"]);
    let seconds = started.elapsed().as_secs_f64();
    let err = assert_clean_failure(&r, "i01o_m1.step");
    assert_eq!(err.trim_end().lines().count(), 1, "one line: {err}");
    for part in [
        "quads estimated",
        "of memory",
        "above the limit of 50000000",
        "would fit",
        "--max-quads 0",
    ] {
        assert!(err.contains(part), "`{part}` missing: {err}");
    }
    // a size and a size factor that fit, coarser than asked
    assert!(value_after(&err, "--size") > 1e-5, "{err}");
    assert!(value_after(&err, "--size-factor") > 0.0, "{err}");
    assert!(!out.exists(), "no output file");
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        0,
        "nothing left behind"
    );
    // meshing at 1e-5 would take hours and terabytes: a generous bound
    // that only a refusal before meshing meets
    assert!(seconds < 60.0, "refused after {seconds:.1} s");
}

#[test]
fn max_quads_moves_the_limit_and_zero_lifts_it() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("m1.msh");
    let model = cad("i01o_m1.step");
    let r = mesh(&model, &out, &["--max-quads", "10"]);
    let err = assert_clean_failure(&r, "i01o_m1.step");
    assert!(err.contains("above the limit of 10 quads"), "{err}");
    assert!(!out.exists());
    let r = mesh(&model, &out, &["--max-quads", "0"]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    assert!(out.exists());
}

#[test]
fn the_suggested_size_is_accepted() {
    // with a limit below m1's count at the default size, the size the
    // refusal suggests passes the same limit
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("m1.msh");
    let model = cad("i01o_m1.step");
    let r = mesh(&model, &out, &["--max-quads", "2000"]);
    let err = assert_clean_failure(&r, "i01o_m1.step");
    let size = value_after(&err, "--size");
    let r = mesh(
        &model,
        &out,
        &[
            "--max-quads",
            "2000",
            "--size",
            &size.to_string(),
            "--timings",
        ],
    );
    let text = String::from_utf8_lossy(&r.stderr).into_owned();
    assert!(r.status.success(), "--size {size}: {text}");
    let json = text
        .lines()
        .find_map(|l| l.strip_prefix("timings:"))
        .unwrap_or_else(|| panic!("no timings: line\n{text}"));
    let number = |key: &str| json_number(json, key);
    let (estimated, made) = (number("estimated_quads"), number("quads"));
    assert!(estimated <= 2000.0, "{json}");
    assert!((estimated / made - 1.0).abs() < 0.3, "{json}");
    assert!(number("estimate") > 0.0, "{json}");
    assert!(text.contains("estimated before meshing"), "{text}");
}

#[test]
fn a_negative_limit_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("m.msh");
    let r = mesh(&cad("s17o_sphere.stp"), &out, &["--max-quads", "-1"]);
    assert!(!r.status.success());
    assert!(!out.exists());
}
