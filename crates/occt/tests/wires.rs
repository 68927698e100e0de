//! `occt::load_wires` on a wire-only STEP file.
//!
//! `tests/data/wires.step` was written by Gmsh's OCC kernel (gmsh 4.15, Python):
//! ```python
//! occ = gmsh.model.occ
//! p = [occ.addPoint(x, y, 0) for x, y in ((0, 0), (2, 0), (2, 1), (0, 1))]
//! occ.addWire([occ.addLine(p[i], p[(i + 1) % 4]) for i in range(4)])  # a 2 × 1 rectangle
//! occ.addWire([occ.addCircle(5, 0.5, 0, 0.5)])                       # a circle, r = 0.5
//! occ.addLine(occ.addPoint(0, 3, 0), occ.addPoint(1, 3, 1))          # an open line
//! occ.synchronize(); gmsh.write("wires.step")
//! ```
//! Gmsh writes each curve as its own product of a `GEOMETRIC_CURVE_SET` with
//! its own end vertices, so the rectangle's wire has to be rebuilt by welding.

use std::f64::consts::PI;
use std::path::PathBuf;

use geometry::vec3::dist;

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

fn length(points: &[[f64; 3]]) -> f64 {
    points.windows(2).map(|w| dist(w[0], w[1])).sum()
}

#[test]
fn a_rectangle_and_a_circle_are_closed_wires_and_the_open_line_is_listed() {
    let w = occt::load_wires(&data("wires.step")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(w.model.curves.len(), 6, "4 lines, a circle, an open line");
    assert!(w.model.faces.is_empty());
    assert_eq!(
        w.closed.len(),
        2,
        "{:#?}",
        w.closed.iter().map(|c| c.uses.len()).collect::<Vec<_>>()
    );
    assert_eq!(w.open_curves.len(), 1);

    let rect = w
        .closed
        .iter()
        .find(|c| c.uses.len() == 4)
        .expect("the rectangle");
    let circle = w
        .closed
        .iter()
        .find(|c| c.uses.len() == 1)
        .expect("the circle");

    // the rectangle: consecutive uses share their end points exactly, the
    // wire closes, each CAD curve once, perimeter 6, every sample at z = 0
    // and on the rectangle's sides
    for (i, u) in rect.uses.iter().enumerate() {
        let next = &rect.uses[(i + 1) % 4];
        assert_eq!(
            u.points.last(),
            next.points.first(),
            "use {i} meets use {}",
            (i + 1) % 4
        );
        assert!(u.curve < 6 && !w.open_curves.contains(&u.curve));
    }
    let mut ids: Vec<usize> = rect.uses.iter().map(|u| u.curve).collect();
    ids.sort_unstable();
    ids.dedup();
    assert_eq!(ids.len(), 4);
    let perimeter: f64 = rect.uses.iter().map(|u| length(&u.points)).sum();
    assert!((perimeter - 6.0).abs() < 1e-9, "perimeter {perimeter}");
    for p in rect.polyline() {
        let on_side = p[0].abs() < 1e-9
            || (p[0] - 2.0).abs() < 1e-9
            || p[1].abs() < 1e-9
            || (p[1] - 1.0).abs() < 1e-9;
        assert!(p[2].abs() < 1e-12 && on_side, "{p:?} off the rectangle");
    }
    // spacing at most 1/200 of the diagonal (of all curves: (0,0,0)–(5.5,3,1))
    let diag = (5.5f64 * 5.5 + 3.0 * 3.0 + 1.0).sqrt();
    for u in &rect.uses {
        for s in u.points.windows(2) {
            assert!(dist(s[0], s[1]) <= diag / 200.0 * (1.0 + 1e-9));
        }
    }

    // the circle: one closed use, samples on the circle, ≥ 72 of them (5°),
    // polyline length just under 2π r
    let u = &circle.uses[0];
    assert_eq!(u.points.first(), u.points.last());
    assert!(u.points.len() >= 73, "{} samples", u.points.len());
    for p in &u.points {
        let r = dist(*p, [5.0, 0.5, 0.0]);
        assert!(
            (r - 0.5).abs() < 1e-7 && p[2].abs() < 1e-12,
            "{p:?} at radius {r}"
        );
    }
    let l = length(&u.points);
    assert!(l < PI && l > PI * 0.999, "circle length {l}");

    // the open line is no wire
    let open = w.open_curves[0];
    assert!(!w
        .closed
        .iter()
        .flat_map(|c| &c.uses)
        .any(|u| u.curve == open));
}

#[test]
fn a_file_with_faces_is_refused_with_one_line() {
    let cube =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../data/cad/s12o_cube_rounded_1.stp");
    let e = occt::load_wires(&cube).expect_err("s12o has faces");
    let msg = e.to_string();
    assert!(msg.contains("26 faces") && !msg.contains('\n'), "{msg}");
}

#[test]
fn a_missing_file_is_an_error() {
    assert!(matches!(
        occt::load_wires(&data("no-such-file.step")),
        Err(occt::ImportError::NotFound { .. })
    ));
}
