//! Bad input gives one clear error naming the file and the problem, a non-zero
//! exit code, no panic, and no output file.

use std::path::{Path, PathBuf};
use std::process::Command;

fn cad(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/cad").join(name)
}

/// Runs `quadrille mesh INPUT -o DIR/out.msh` and checks the failure contract;
/// returns stderr.
fn mesh_fails(input: &Path, dir: &Path) -> String {
    let out = dir.join("out.msh");
    let r = Command::new(env!("CARGO_BIN_EXE_quadrille"))
        .args(["mesh", input.to_str().unwrap(), "-o", out.to_str().unwrap(), "--quiet"])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&r.stderr).into_owned();
    assert!(!r.status.success(), "must fail on {}", input.display());
    assert_eq!(r.status.code(), Some(1), "clean error exit, not a crash: {stderr}");
    assert!(!stderr.contains("panicked"), "panic: {stderr}");
    assert!(stderr.starts_with("error: "), "one clear error line: {stderr}");
    let name = input.file_name().unwrap().to_string_lossy();
    assert!(stderr.contains(&*name), "error must name the file {name}: {stderr}");
    assert!(!out.exists(), "no output file may be left behind");
    let leftovers: Vec<_> = std::fs::read_dir(dir).unwrap().flatten().map(|e| e.file_name()).collect();
    assert!(leftovers.iter().all(|n| !n.to_string_lossy().contains("out.msh")), "partial files left: {leftovers:?}");
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
    assert!(err.to_lowercase().contains("not found") || err.contains("No such file"), "{err}");
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
    let garbage: Vec<u8> = (0..4096u32).map(|i| (i.wrapping_mul(2654435761) >> 13) as u8).collect();
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
    assert!(err.to_lowercase().contains("extension") || err.to_lowercase().contains("format"), "{err}");
}

/// Meshes a good model into `out`, which must be refused: checks the failure
/// contract and that the error names the output file.
fn output_refused(out: &Path) {
    let r = Command::new(env!("CARGO_BIN_EXE_quadrille"))
        .args(["mesh", cad("s17o_sphere.stp").to_str().unwrap(), "-o", out.to_str().unwrap(), "--quiet"])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&r.stderr);
    assert_eq!(r.status.code(), Some(1), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    let name = out.file_name().unwrap().to_string_lossy();
    assert!(stderr.contains(&*name), "error must name the output {name}: {stderr}");
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
    let p = write(dir.path(), "broken.msh", b"$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 5 1 5\n2 1 0 5\n1\n");
    let r = Command::new(env!("CARGO_BIN_EXE_quadrille")).args(["stats", p.to_str().unwrap()]).output().unwrap();
    let stderr = String::from_utf8_lossy(&r.stderr);
    assert_eq!(r.status.code(), Some(1), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(stderr.contains("broken.msh"), "{stderr}");
}
