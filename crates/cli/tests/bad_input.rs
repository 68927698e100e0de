//! Bad input gives one clear error naming the file and the problem, a non-zero
//! exit code, no panic, and no output file.

mod common;

use std::path::{Path, PathBuf};

use common::{assert_clean_failure, cad, quadrille};

/// Runs `quadrille mesh INPUT -o DIR/out.msh` and checks the failure contract;
/// returns stderr.
fn mesh_fails(input: &Path, dir: &Path) -> String {
    let out = dir.join("out.msh");
    let r = quadrille(&[
        "mesh",
        input.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(!r.status.success(), "must fail on {}", input.display());
    let stderr = assert_clean_failure(&r, &input.file_name().unwrap().to_string_lossy());
    assert!(!out.exists(), "no output file may be left behind");
    let leftovers: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| e.file_name())
        .collect();
    assert!(
        leftovers
            .iter()
            .all(|n| !n.to_string_lossy().contains("out.msh")),
        "partial files left: {leftovers:?}"
    );
    stderr
}

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, bytes).unwrap();
    p
}

#[test]
fn missing_file() {
    let dir = tempfile::tempdir().unwrap();
    let err = mesh_fails(&dir.path().join("no_such_model.step"), dir.path());
    assert!(
        err.to_lowercase().contains("not found") || err.contains("No such file"),
        "{err}"
    );
}

#[test]
fn empty_file() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(dir.path(), "empty.step", b"");
    let err = mesh_fails(&p, dir.path());
    assert!(err.to_lowercase().contains("empty"), "{err}");
}

#[test]
fn truncated_step() {
    let dir = tempfile::tempdir().unwrap();
    let full = std::fs::read(cad("i01o_m1.step")).unwrap();
    let p = write(dir.path(), "truncated.step", &full[..full.len() / 2]);
    mesh_fails(&p, dir.path());
}

#[test]
fn binary_garbage_named_step() {
    let dir = tempfile::tempdir().unwrap();
    let garbage: Vec<u8> = (0..4096u32)
        .map(|i| (i.wrapping_mul(2654435761) >> 13) as u8)
        .collect();
    let p = write(dir.path(), "garbage.step", &garbage);
    mesh_fails(&p, dir.path());
}

#[test]
fn step_without_faces() {
    let dir = tempfile::tempdir().unwrap();
    let step = b"ISO-10303-21;
HEADER;
FILE_DESCRIPTION(('a point only'),'2;1');
FILE_NAME('point.step','2026-01-01T00:00:00',(''),(''),'','','');
FILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'));
ENDSEC;
DATA;
#1=CARTESIAN_POINT('',(0.,0.,0.));
ENDSEC;
END-ISO-10303-21;
";
    let p = write(dir.path(), "point_only.step", step);
    let err = mesh_fails(&p, dir.path());
    assert!(err.to_lowercase().contains("face"), "{err}");
}

#[test]
fn unknown_extension() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(dir.path(), "model.xyz", b"solid nothing");
    let err = mesh_fails(&p, dir.path());
    assert!(
        err.to_lowercase().contains("extension") || err.to_lowercase().contains("format"),
        "{err}"
    );
}

/// Meshes a good model into `out`, which must be refused: checks the failure
/// contract and that the error names the output file.
fn output_refused(out: &Path) {
    let r = quadrille(&[
        "mesh",
        cad("s17o_sphere.stp").to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert_clean_failure(&r, &out.file_name().unwrap().to_string_lossy());
    assert!(!out.exists());
}

#[test]
fn unwritable_output_path() {
    let dir = tempfile::tempdir().unwrap();
    // the parent of the output is a regular file: nothing can be created there
    let blocker = write(dir.path(), "blocker", b"x");
    output_refused(&blocker.join("out.msh"));
}

#[test]
fn unknown_output_extension() {
    let dir = tempfile::tempdir().unwrap();
    output_refused(&dir.path().join("out.docx"));
}
#[test]
fn stats_on_garbage_mesh() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(
        dir.path(),
        "broken.msh",
        b"$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 5 1 5\n2 1 0 5\n1\n",
    );
    let r = quadrille(&["stats", p.to_str().unwrap()]);
    assert_clean_failure(&r, "broken.msh");
}

/// A reader that closes the pipe early (`quadrille info m.step | head -1`)
/// must not make the command panic while it prints.
#[test]
fn closed_output_pipe_is_not_a_panic() {
    use std::process::{Command, Stdio};
    let mut child = Command::new(env!("CARGO_BIN_EXE_quadrille"))
        .args(["info", common::cad("i01o_m1.step").to_str().unwrap()])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take()); // the reader goes away before anything is written
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !stderr.contains("panicked"),
        "panic on a closed pipe: {stderr}"
    );
    assert_ne!(
        out.status.code(),
        Some(101),
        "exit code 101 is a Rust panic: {stderr}"
    );
}

/// The error line says each cause once (library errors that print their
/// source must not have it repeated by the error chain).
#[test]
fn missing_mesh_error_says_its_cause_once() {
    let r = common::quadrille(&["stats", "/nonexistent/quadrille-missing.msh"]);
    let stderr = common::assert_clean_failure(&r, "quadrille-missing.msh");
    assert_eq!(
        stderr.matches("No such file or directory").count(),
        1,
        "cause repeated: {stderr}"
    );
}

#[test]
fn topology_switches_are_refused_for_a_method_without_them() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.msh");
    let r = quadrille(&[
        "mesh",
        cad("s15o_cylinder.stp").to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--method",
        "baseline",
        "--no-regular-pass",
        "--no-patterns",
    ]);
    assert!(!r.status.success());
    let stderr = String::from_utf8_lossy(&r.stderr);
    assert!(
        stderr.contains(
            "--no-patterns, --no-regular-pass only applies to --method quasi-structured (the default); --method baseline has no such step"
        ),
        "{stderr}"
    );
    assert!(!out.exists());
}
