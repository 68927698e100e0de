use super::*;
use crate::curvenet::check;
use geometry::primitives;

fn max_spacing(net: &CurveNetwork) -> f64 {
    net.curves()
        .iter()
        .flat_map(|c| c.points.windows(2).map(|w| vec3::dist(w[0], w[1])))
        .fold(0.0, f64::max)
}

#[test]
fn a_square_face_is_one_cycle_of_four_cad_curves() {
    let m = primitives::square(2.0);
    let (net, skipped) = network_from_model(&m, None).unwrap();
    assert!(skipped.is_empty());
    assert_eq!(net.cycles().len(), 1);
    assert_eq!(net.curves().len(), 4);
    let cads: Vec<Option<CurveId>> = net.curves().iter().map(|c| c.cad).collect();
    assert_eq!(cads, (0..4).map(|i| Some(CurveId(i))).collect::<Vec<_>>());
    assert_eq!(net.cycles()[0].cad_face, Some(FaceId(0)));
    let d = m.diagonal();
    assert!(max_spacing(&net) <= d / 200.0 * (1.0 + 1e-12));
    let c = net.cycle_loops(0).unwrap();
    assert_eq!(c.outer.fixed.len(), 4);
    // counter-clockwise about the face normal (+z)
    let n = check::newell(&c.outer.points);
    assert!(n[2] > 0.0 && (n[2] - 4.0).abs() < 1e-9, "{n:?}");
}

#[test]
fn faces_with_a_seam_are_skipped_and_discs_face_out() {
    let m = primitives::cylinder(1.0, 2.0);
    let (net, skipped) = network_from_model(&m, None).unwrap();
    assert_eq!(skipped.len(), 1);
    assert!(matches!(skipped[0].reason, SkipReason::Seam(_)));
    assert!(
        skipped[0].to_string().contains("skipped: a seam"),
        "{}",
        skipped[0]
    );
    assert_eq!(net.cycles().len(), 2);
    for c in 0..2 {
        let l = net.cycle_loops(c).unwrap();
        // a circle: smooth, no fixed point but its curve's end if it turns
        assert!(l.outer.points.len() >= 72, "{}", l.outer.points.len());
        assert!(l.outer.fixed.is_empty(), "{:?}", l.outer.fixed);
        // the Newell normal points out of the solid (the disc at z = 0 down)
        let n = check::newell(&l.outer.points);
        let centre = check::centroid(&l.outer.points);
        assert!(n[2] * (centre[2] - 1.0) > 0.0, "{n:?} at {centre:?}");
    }
    // only the side face: everything skipped
    let side = (0..m.faces.len())
        .find(|&f| skipped[0].face.idx() == f)
        .unwrap();
    let e = network_from_model(&m, Some(&[side])).unwrap_err();
    assert!(matches!(e, CurveNetError::Empty { .. }), "{e:?}");
    assert!(e.to_string().contains("every CAD face was skipped"), "{e}");
    let e = network_from_model(&m, Some(&[7])).unwrap_err();
    assert_eq!(e.to_string(), "no CAD face 8: they are 1 to 3");
}

#[test]
fn a_sphere_is_skipped_and_an_ellipse_has_no_corner() {
    let m = primitives::sphere(1.0);
    let e = network_from_model(&m, None).unwrap_err();
    assert!(matches!(e, CurveNetError::Empty { .. }), "{e:?}");
    let m = primitives::ellipse(2.0, 1.0);
    let (net, _) = network_from_model(&m, None).unwrap();
    let l = net.cycle_loops(0).unwrap();
    // two half-ellipses meeting tangentially at (±2, 0): no fixed point
    assert!(l.outer.fixed.is_empty(), "{:?}", l.outer.fixed);
}

#[test]
fn curves_shared_by_faces_are_one_polyline_used_both_ways() {
    // the square and a copy of its face reversed: two faces on the same
    // four curves
    let mut m = primitives::square(1.0);
    let mut f = m.faces[0].clone();
    f.reversed = !f.reversed;
    m.faces.push(f);
    let (net, skipped) = network_from_model(&m, None).unwrap();
    assert!(skipped.is_empty());
    assert_eq!(net.curves().len(), 4);
    assert_eq!(net.cycles().len(), 2);
    // the two faces are the two sides of one square: each curve used once
    // each way, so the network is orientable
    assert!(net.validate().is_empty(), "{:?}", net.validate());
    let a = check::newell(&net.cycle_loops(0).unwrap().outer.points);
    let b = check::newell(&net.cycle_loops(1).unwrap().outer.points);
    assert!(a[2] > 0.0 && b[2] < 0.0);
}
