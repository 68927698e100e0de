//! Bad input: each case gives the right error, naming the file; nothing panics.

mod common;

use std::path::{Path, PathBuf};

use occt::{load, topology_counts, ImportError};

fn tmp(name: &str, bytes: &[u8]) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join(name);
    std::fs::write(&p, bytes).unwrap();
    (dir, p)
}

fn message_names_file(e: &ImportError, p: &Path) {
    let msg = e.to_string();
    let name = p.file_name().unwrap().to_string_lossy();
    assert!(msg.contains(&*name), "message {msg:?} does not name {name}");
}

#[test]
fn missing_file() {
    let p = Path::new("/nonexistent/dir/part_does_not_exist.step");
    let e = load(p).unwrap_err();
    assert!(matches!(e, ImportError::NotFound { .. }), "{e:?}");
    message_names_file(&e, p);
    assert!(matches!(
        topology_counts(p),
        Err(ImportError::NotFound { .. })
    ));
}

#[test]
fn empty_file() {
    let (_d, p) = tmp("empty_part.step", b"");
    let e = load(&p).unwrap_err();
    assert!(matches!(e, ImportError::Empty { .. }), "{e:?}");
    message_names_file(&e, &p);
}

#[test]
fn truncated_step() {
    let src = std::fs::read(Path::new(common::CAD_DIR).join("i01o_m1.step")).unwrap();
    let (_d, p) = tmp("half_of_m1.STEP", &src[..src.len() / 2]);
    let e = load(&p).unwrap_err();
    assert!(
        matches!(e, ImportError::Unreadable { format: "STEP", .. }),
        "{e:?}"
    );
    assert!(e.to_string().contains("truncated"), "{e}");
    message_names_file(&e, &p);
}

#[test]
fn binary_garbage_named_step() {
    // Deterministic pseudo-random bytes (xorshift), including NULs.
    let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
    let bytes: Vec<u8> = (0..20000)
        .map(|_| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 24) as u8
        })
        .collect();
    let (_d, p) = tmp("garbage.step", &bytes);
    let e = load(&p).unwrap_err();
    assert!(matches!(e, ImportError::Unreadable { .. }), "{e:?}");
    message_names_file(&e, &p);
}

#[test]
fn text_garbage_that_looks_like_step_reaches_occt_and_fails_cleanly() {
    let text = "ISO-10303-21;\nHEADER;\nthis is ( not ; a STEP ' file #12=\nENDSEC;\nDATA;\n#1=FOO(#2,'x',;\n#2=;\nENDSEC;\nEND-ISO-10303-21;\n";
    let (_d, p) = tmp("text_garbage.stp", text.as_bytes());
    let e = load(&p).unwrap_err();
    assert!(
        matches!(
            e,
            ImportError::Unreadable { .. } | ImportError::NoFace { .. }
        ),
        "{e:?}"
    );
    message_names_file(&e, &p);
}

/// A valid STEP file holding only a point.
const POINT_ONLY: &str = "ISO-10303-21;
HEADER;
FILE_DESCRIPTION(('a lone point'),'2;1');
FILE_NAME('point.step','2024-01-01T00:00:00',('test'),('test'),'none','none','');
FILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'));
ENDSEC;
DATA;
#1=CARTESIAN_POINT('',(1.0,2.0,3.0));
ENDSEC;
END-ISO-10303-21;
";

#[test]
fn step_without_face() {
    let (_d, p) = tmp("lonely_point.step", POINT_ONLY.as_bytes());
    let e = load(&p).unwrap_err();
    assert!(matches!(e, ImportError::NoFace { .. }), "{e:?}");
    assert!(e.to_string().contains("no face"), "{e}");
    message_names_file(&e, &p);
}

#[test]
fn unknown_extension() {
    let (_d, p) = tmp("model.xyz", POINT_ONLY.as_bytes());
    let e = load(&p).unwrap_err();
    assert!(
        matches!(&e, ImportError::UnknownExtension { ext, .. } if ext == "xyz"),
        "{e:?}"
    );
    message_names_file(&e, &p);
    let (_d2, p2) = tmp("no_extension", b"x");
    let e = load(&p2).unwrap_err();
    assert!(matches!(e, ImportError::UnknownExtension { .. }), "{e:?}");
    message_names_file(&e, &p2);
}

#[test]
fn garbage_iges_and_brep_fail_cleanly() {
    for name in ["junk.igs", "junk.IGES", "junk.brep", "junk.brp"] {
        let (_d, p) = tmp(name, b"hello, I am not a CAD model\n1 2 3\n");
        let e = load(&p).unwrap_err();
        assert!(
            matches!(
                e,
                ImportError::Unreadable { .. } | ImportError::NoFace { .. }
            ),
            "{name}: {e:?}"
        );
        message_names_file(&e, &p);
    }
}

#[test]
fn extension_is_case_insensitive() {
    let src = std::fs::read(Path::new(common::CAD_DIR).join("s17o_sphere.stp")).unwrap();
    let (_d, p) = tmp("SPHERE.StP", &src);
    let m = load(&p).unwrap();
    assert_eq!(m.faces.len(), topology_counts(&p).unwrap().0);
}

/// A STEP file cut in half and given back its terminator gets past the
/// header checks with dangling references (on which OCCT's parser or
/// transfer would crash): the importer refuses it. Cut mid-record
/// (a syntax error too) and cut at a record boundary (only dangling references).
#[test]
fn truncated_step_with_forged_terminator_is_refused() {
    let src = std::fs::read(Path::new(common::CAD_DIR).join("i01o_m1.step")).unwrap();
    let half = src.len() / 2;
    let boundary = src[..half].windows(2).rposition(|w| w == b";\n").unwrap() + 2;
    for (label, cut) in [("mid_record", half), ("at_boundary", boundary)] {
        let mut bytes = src[..cut].to_vec();
        bytes.extend_from_slice(b"\nENDSEC;\nEND-ISO-10303-21;\n");
        let (_d, p) = tmp(&format!("half_m1_{label}.step"), &bytes);
        let e = load(&p).unwrap_err();
        assert!(
            matches!(e, ImportError::Unreadable { .. }),
            "{label}: {e:?}"
        );
        // caught by the reference check before OCCT's parser (or, past it,
        // by OCCT's own check list)
        let msg = e.to_string();
        assert!(
            msg.contains("which it does not define") || msg.contains("structural error"),
            "{label}: {e}"
        );
        message_names_file(&e, &p);
    }
}
