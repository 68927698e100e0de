//! OCCT's IGES toolkits are loaded only when a file is IGES (the shim's IGES
//! half is a shared object loaded on first use): a process that reads STEP
//! does not map `libTKIGES`, and writing and reading IGES then works.
//! One test in its own binary, so that no other test has read IGES before.

mod common;

use std::path::Path;

use common::CAD_DIR;

/// True when a mapping of this process is a file named `libTKIGES…`.
fn iges_toolkit_mapped() -> bool {
    let maps = std::fs::read_to_string("/proc/self/maps").expect("Linux /proc/self/maps");
    maps.lines().any(|l| l.contains("/libTKIGES."))
}

#[test]
fn iges_toolkits_are_loaded_on_the_first_iges_file_only() {
    let src = Path::new(CAD_DIR).join("i16o_s9.step");
    let orig = occt::load(&src).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let brep = dir.path().join("copy.brep");
    occt::convert(&src, &brep).unwrap();
    occt::load(&brep).unwrap();
    assert!(
        !iges_toolkit_mapped(),
        "libTKIGES is mapped after STEP and BREP reads and writes only"
    );
    let iges = dir.path().join("copy.igs");
    occt::convert(&src, &iges).unwrap();
    assert!(iges_toolkit_mapped(), "libTKIGES not mapped after an IGES write");
    let back = occt::load(&iges).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(back.faces.len(), orig.faces.len());
    // a second IGES read reuses the loaded half
    let again = occt::load(&iges).unwrap();
    assert_eq!(again.faces.len(), orig.faces.len());
}
