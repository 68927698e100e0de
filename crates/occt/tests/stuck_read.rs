//! A CAD file on which OCCT's reader never finishes (found by the fuzzer: a
//! BREP file whose count became `inf`) is refused after the read time limit,
//! and every later read in the process is refused at once, naming that file:
//! its reader thread still holds OCCT's lock. A test binary of its own, since
//! the process stays in that state.

use std::path::Path;
use std::time::Instant;

#[test]
fn a_read_that_never_finishes_is_refused_and_so_are_later_reads() {
    std::env::set_var("QUADRILLE_CAD_READ_SECONDS", "1");
    let stuck = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../fuzz/regressions/brep/inf_count_endless_loop.brep");
    let started = Instant::now();
    let e = occt::load(&stuck).unwrap_err().to_string();
    let secs = started.elapsed().as_secs_f64();
    assert!(e.contains("did not finish reading it in 1 s"), "{e}");
    assert!(e.contains("inf_count_endless_loop.brep"), "{e}");
    assert!(secs < 30.0, "refused after {secs:.1} s");
    let good = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/cad/s17o_sphere.stp");
    let started = Instant::now();
    let e = occt::load(&good).unwrap_err().to_string();
    assert!(
        e.contains("still busy with") && e.contains("inf_count_endless_loop.brep"),
        "{e}"
    );
    assert!(started.elapsed().as_secs_f64() < 1.0, "a later read waited");
}
