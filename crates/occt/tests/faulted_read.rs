//! A CAD file on which OCCT faults is refused, and so is every later read in
//! the process, naming that file. Found by the fuzzer (issue 32, seed 7):
//! after a fault caught inside OCCT (OCCT's handler jumps out of the faulting
//! frames, skipping their destructors and unlocks), later reads in the same
//! process aborted in `free` ("munmap_chunk(): invalid pointer") or
//! segfaulted at random, on files that read cleanly in a fresh process. The
//! input here is an IGES face whose surface is null: OCCT's transfer
//! dereferences it and then recovers by itself, so before this rule the
//! read even answered with a face. A test binary of its own, since the
//! process stays in that state.

use std::path::Path;

#[test]
fn a_read_that_faults_inside_occt_is_refused_and_so_are_later_reads() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let good = root.join("../../data/cad/s17o_sphere.stp");
    assert_eq!(occt::cad_reads_refused(), None);
    let before = occt::load(&good).unwrap();
    assert!(!before.faces.is_empty());

    let faulty = root.join("../fuzz/regressions/iges/null_surface_segfault.igs");
    let e = occt::load(&faulty).unwrap_err().to_string();
    assert!(e.contains("null_surface_segfault.igs"), "{e}");
    assert!(
        e.contains("memory fault inside OpenCASCADE was caught")
            && e.contains("reads no more CAD files"),
        "{e}"
    );
    assert_eq!(e.lines().count(), 1, "{e}");

    let why = occt::cad_reads_refused().expect("reads refused after the fault");
    assert!(
        why.contains("faulted while reading") && why.contains("null_surface_segfault.igs"),
        "{why}"
    );
    let e = occt::load(&good).unwrap_err().to_string();
    assert!(e.contains("s17o_sphere.stp"), "{e}");
    assert!(
        e.contains("null_surface_segfault.igs") && e.contains("restart the program"),
        "{e}"
    );
}
