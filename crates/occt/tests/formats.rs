//! The BREP, IGES and STEP readers on the same shapes: each model is written
//! by OCCT in another format and read back.

mod common;

use std::path::Path;

use common::CAD_DIR;

fn counts(m: &geometry::Model) -> (usize, usize, usize) {
    (m.faces.len(), m.curves.len(), m.corners.len())
}

#[test]
fn brep_and_step_round_trips_keep_the_topology() {
    let dir = tempfile::tempdir().unwrap();
    for stem in [
        "i01o_m1.step",
        "s17o_sphere.stp",
        "n10o_qtorus_cyl.step",
        "wing_surface.step",
    ] {
        let src = Path::new(CAD_DIR).join(stem);
        let orig = occt::load(&src).unwrap();
        for ext in ["brep", "BRP", "step", "stp"] {
            let out = dir.path().join(format!("copy_of_{stem}.{ext}"));
            occt::convert(&src, &out).unwrap();
            let back = occt::load(&out).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(counts(&back), counts(&orig), "{stem} via .{ext}");
            assert_eq!(counts(&back), occt::topology_counts(&out).unwrap());
            // Same geometry: corner positions agree (same MapShapes order).
            for (a, b) in orig.corners.iter().zip(&back.corners) {
                assert!(
                    geometry::vec3::dist(a.point, b.point) <= 1e-9 * orig.diagonal(),
                    "{stem} via .{ext}"
                );
            }
        }
    }
}

#[test]
fn iges_round_trip_keeps_faces_and_their_loops() {
    let dir = tempfile::tempdir().unwrap();
    for stem in ["i16o_s9.step", "s16o_torus.stp"] {
        let src = Path::new(CAD_DIR).join(stem);
        let orig = occt::load(&src).unwrap();
        for ext in ["iges", "IGS"] {
            let out = dir.path().join(format!("copy_of_{stem}.{ext}"));
            occt::convert(&src, &out).unwrap();
            let back = occt::load(&out).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(
                counts(&back),
                occt::topology_counts(&out).unwrap(),
                "{stem}"
            );
            assert_eq!(back.faces.len(), orig.faces.len(), "{stem} via .{ext}");
            let loops = |m: &geometry::Model| m.faces.iter().map(|f| f.loops.len()).sum::<usize>();
            assert_eq!(loops(&back), loops(&orig), "{stem} via .{ext}");
            let rel = (back.diagonal() - orig.diagonal()).abs() / orig.diagonal();
            assert!(rel < 1e-6, "{stem} via .{ext}: size changed by {rel}");
        }
    }
}

#[test]
fn convert_to_unknown_extension_fails_naming_the_output() {
    let src = Path::new(CAD_DIR).join("s17o_sphere.stp");
    let e = occt::convert(&src, Path::new("/tmp/sphere_out.obj")).unwrap_err();
    assert!(e.to_string().contains("sphere_out.obj"), "{e}");
}
