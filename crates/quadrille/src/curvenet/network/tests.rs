use super::*;

fn curve(points: &[Vec3]) -> NetworkCurve {
    NetworkCurve {
        points: points.to_vec(),
        cad: None,
    }
}

fn uses(list: &[(usize, i32)]) -> Vec<CycleUse> {
    list.iter()
        .map(|&(curve, d)| CycleUse {
            curve,
            forward: d > 0,
        })
        .collect()
}

fn cycle(loops: &[&[(usize, i32)]]) -> NetworkCycle {
    NetworkCycle {
        loops: loops.iter().map(|l| uses(l)).collect(),
        cad_face: None,
        surface: None,
    }
}

/// A closed polyline as one curve (first point repeated at the end).
fn closed(points: &[Vec3]) -> NetworkCurve {
    let mut p = points.to_vec();
    p.push(points[0]);
    curve(&p)
}

fn single(points: &[Vec3]) -> CurveNetwork {
    CurveNetwork::new(vec![closed(points)], vec![cycle(&[&[(0, 1)]])], vec![]).unwrap()
}

fn square_pts(x0: f64, y0: f64, s: f64) -> Vec<Vec3> {
    vec![
        [x0, y0, 0.0],
        [x0 + s, y0, 0.0],
        [x0 + s, y0 + s, 0.0],
        [x0, y0 + s, 0.0],
    ]
}

/// Two unit squares side by side sharing the segment x = 1: curves 0 (the
/// left square's other three sides), 1 (the shared side, upward), 2 (the
/// right square's other three sides). `consistent`: the right square runs
/// counter-clockwise too, using the shared side downward; else clockwise,
/// using it upward as the left square does.
fn two_squares(consistent: bool) -> CurveNetwork {
    let right: &[(usize, i32)] = if consistent {
        &[(2, 1), (1, -1)]
    } else {
        &[(2, -1), (1, 1)]
    };
    let c0 = curve(&[
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
    ]);
    let c1 = curve(&[[1.0, 0.0, 0.0], [1.0, 0.5, 0.0], [1.0, 1.0, 0.0]]);
    let c2 = curve(&[
        [1.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [2.0, 1.0, 0.0],
        [1.0, 1.0, 0.0],
    ]);
    CurveNetwork::new(
        vec![c0, c1, c2],
        vec![cycle(&[&[(0, 1), (1, 1)]]), cycle(&[right])],
        vec![],
    )
    .unwrap()
}

fn circle(n: usize, r: f64) -> Vec<Vec3> {
    (0..n)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / n as f64;
            [r * a.cos(), r * a.sin(), 0.0]
        })
        .collect()
}

#[test]
fn a_square_closes_with_its_four_corners_fixed() {
    let net = single(&square_pts(0.0, 0.0, 1.0));
    let c = net.cycle_loops(0).unwrap();
    assert_eq!(c.outer.points, square_pts(0.0, 0.0, 1.0));
    // the closed curve's end is a join turning 90°; the other corners are
    // inside the curve (the segmentation finds them)
    assert_eq!(c.outer.fixed, vec![0]);
    assert!(c.holes.is_empty());
    assert!((net.delta() - 1.0).abs() < 1e-15);
}

#[test]
fn four_curves_meeting_at_right_angles_are_four_fixed_corners() {
    let p = square_pts(0.0, 0.0, 1.0);
    let curves = (0..4).map(|k| curve(&[p[k], p[(k + 1) % 4]])).collect();
    let net = CurveNetwork::new(
        curves,
        vec![cycle(&[&[(0, 1), (1, 1), (2, 1), (3, 1)]])],
        vec![],
    )
    .unwrap();
    let c = net.cycle_loops(0).unwrap();
    assert_eq!(c.outer.points, p);
    assert_eq!(c.outer.fixed, vec![0, 1, 2, 3]);
}

#[test]
fn a_smooth_join_is_not_fixed_and_a_listed_corner_is() {
    // a circle in two halves meeting tangentially: no fixed point
    let pts = circle(64, 1.0);
    let top: Vec<Vec3> = pts[..=32].to_vec();
    let mut bottom: Vec<Vec3> = pts[32..].to_vec();
    bottom.push(pts[0]);
    let curves = vec![curve(&top), curve(&bottom)];
    let cyc = vec![cycle(&[&[(0, 1), (1, 1)]])];
    let net = CurveNetwork::new(curves.clone(), cyc.clone(), vec![]).unwrap();
    let c = net.cycle_loops(0).unwrap();
    assert_eq!(c.outer.points.len(), 64);
    assert!(c.outer.fixed.is_empty(), "{:?}", c.outer.fixed);
    // corners: one a hair off a sample (welded to it), one on a segment's
    // middle (inserted there)
    let off = [pts[10][0] + 1e-12, pts[10][1], 0.0];
    let mid = [
        0.5 * (pts[40][0] + pts[41][0]),
        0.5 * (pts[40][1] + pts[41][1]),
        0.0,
    ];
    let net = CurveNetwork::new(curves, cyc, vec![off, mid]).unwrap();
    assert_eq!(net.corners()[0], pts[10]);
    let c = net.cycle_loops(0).unwrap();
    assert_eq!(c.outer.points.len(), 65);
    assert_eq!(c.outer.fixed, vec![10, 41]);
    assert_eq!(c.outer.points[41], mid);
}

#[test]
fn shared_curves_junctions_and_orientation() {
    let net = two_squares(true);
    assert!(net.validate().is_empty(), "{:?}", net.validate());
    let left = net.cycle_loops(0).unwrap();
    let right = net.cycle_loops(1).unwrap();
    // the junctions (1, 0) and (1, 1) join 3 curves: fixed in both cycles
    for (c, n) in [(&left, 5), (&right, 5)] {
        assert_eq!(c.outer.points.len(), n);
        let fixed: Vec<Vec3> = c.outer.fixed.iter().map(|&i| c.outer.points[i]).collect();
        assert!(fixed.contains(&[1.0, 0.0, 0.0]) && fixed.contains(&[1.0, 1.0, 0.0]));
        assert!(!fixed.contains(&[1.0, 0.5, 0.0]));
    }
    // both counter-clockwise about +z: the quads face the same side
    for c in [&left, &right] {
        assert!(check::newell(&c.outer.points)[2] > 0.0);
    }
    // the shared side used the same way by both: not orientable
    let bad = two_squares(false);
    let e = bad.cycle_loops(1).unwrap_err();
    assert!(
        matches!(
            e,
            CurveNetError::NonOrientable {
                other_cycle: 0,
                curve: 1,
                ..
            }
        ),
        "{e:?}"
    );
    assert_eq!(
        e.to_string(),
        "cycle 1: non-orientable network: uses curve 1 (through (1, 0.5, 0)) in the same \
         direction as cycle 0 does"
    );
    assert!(matches!(
        bad.cycle_loops(0),
        Err(CurveNetError::NonOrientable { other_cycle: 1, .. })
    ));
}

#[test]
fn a_t_junction_is_inserted_and_fixed() {
    // Fig. 15's shape: an L-shaped cycle beside a 1 × 2 rectangle whose left
    // side is one straight curve; the L ends on it at (1, 1)
    let rect = closed(&[
        [1.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [2.0, 2.0, 0.0],
        [1.0, 2.0, 0.0],
    ]);
    // the L: its side along x = 1 from (1, 0) up to (1, 1) (lying on the
    // rectangle's side, not shared with it), and the rest
    let side = curve(&[[1.0, 0.0, 0.0], [1.0, 1.0, 0.0]]);
    let rest = curve(&[
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
    ]);
    let net = CurveNetwork::new(
        vec![rect, side, rest],
        vec![cycle(&[&[(0, 1)]]), cycle(&[&[(1, 1), (2, 1)]])],
        vec![],
    )
    .unwrap();
    let r = net.cycle_loops(0).unwrap();
    // the rectangle's closing side (1, 2) → (1, 0) got the point (1, 1)
    assert_eq!(r.outer.points.len(), 5);
    let i = r
        .outer
        .points
        .iter()
        .position(|p| *p == [1.0, 1.0, 0.0])
        .unwrap();
    assert!(r.outer.fixed.contains(&i), "{:?}", r.outer.fixed);
}

#[test]
fn welding_merges_near_points_and_keeps_delta_positive() {
    // the square's last point a hair from its first, a repeated point, and
    // a second point 1e-12 from the first
    let pts = vec![
        [0.0, 0.0, 0.0],
        [1e-12, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 1e-12, 0.0],
    ];
    let net = CurveNetwork::new(vec![curve(&pts)], vec![cycle(&[&[(0, 1)]])], vec![]).unwrap();
    assert_eq!(net.curves()[0].points.len(), 5);
    assert!((net.delta() - 1.0).abs() < 1e-15, "{}", net.delta());
    assert!((net.weld_tolerance() - 1e-9 * 2f64.sqrt()).abs() < 1e-20);
    let c = net.cycle_loops(0).unwrap();
    assert_eq!(c.outer.points, square_pts(0.0, 0.0, 1.0));
}

#[test]
fn an_open_cycle_names_the_gap() {
    let p = square_pts(0.0, 0.0, 1.0);
    let a = curve(&[p[0], p[1], p[2]]);
    let b = curve(&[p[2], p[3], [0.0, 0.01, 0.0]]);
    let net = CurveNetwork::new(vec![a, b], vec![cycle(&[&[(0, 1), (1, 1)]])], vec![])
        .unwrap()
        .with_file("net.json");
    let e = net.cycle_loops(0).unwrap_err();
    assert!(
        matches!(e, CurveNetError::Open { loop_index: 0, .. }),
        "{e:?}"
    );
    let msg = e.to_string();
    assert!(
        msg.starts_with(
            "net.json: cycle 0: open cycle: the outer loop has a gap of 0.01 from (0, 0.01, 0) \
             to (0, 0, 0)"
        ),
        "{msg}"
    );
    // a gap between consecutive uses
    let net = CurveNetwork::new(
        vec![
            curve(&[p[0], p[1]]),
            curve(&[[1.0, 0.1, 0.0], p[2], p[3], p[0]]),
        ],
        vec![cycle(&[&[(0, 1), (1, 1)]])],
        vec![],
    )
    .unwrap();
    assert!(matches!(
        net.cycle_loops(0),
        Err(CurveNetError::Open { gap, .. }) if (gap - 0.1).abs() < 1e-12
    ));
}

#[test]
fn a_figure_eight_crossing_itself_is_refused() {
    // a bow tie: (0,0) → (2,2) → (2,0) → (0,2), crossing at (1, 1)
    let net = single(&[
        [0.0, 0.0, 0.0],
        [2.0, 2.0, 0.0],
        [2.0, 0.0, 0.0],
        [0.0, 2.0, 0.0],
    ]);
    let e = net.cycle_loops(0).unwrap_err();
    match &e {
        CurveNetError::SelfIntersecting {
            loops,
            at,
            distance,
            ..
        } => {
            assert_eq!(*loops, (0, 0));
            assert!(vec3::dist(*at, [1.0, 1.0, 0.0]) < 1e-12 && *distance < 1e-12);
        }
        _ => panic!("{e:?}"),
    }
    assert!(
        e.to_string()
            .contains("crosses or touches itself at (1, 1, 0)"),
        "{e}"
    );
}

#[test]
fn a_cycle_touching_itself_at_a_point_or_folding_back_is_refused() {
    // two triangles sharing the vertex (1, 0, 0)
    let net = single(&[
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [2.0, 1.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
    ]);
    assert!(matches!(
        net.cycle_loops(0),
        Err(CurveNetError::SelfIntersecting { .. })
    ));
    // a spike: out along the x axis and straight back
    let net = single(&[
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [1.5, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ]);
    let e = net.cycle_loops(0).unwrap_err();
    assert!(matches!(e, CurveNetError::SelfIntersecting { .. }), "{e:?}");
}

#[test]
fn non_planar_cycles_are_judged_by_3d_distance() {
    // a bow tie whose crossing strands pass 0.1 apart in z does not meet
    // itself: a valid twisted cycle (its lift gives it a Newell area)
    let net = single(&[
        [0.0, 0.0, 0.0],
        [2.0, 2.0, 0.1],
        [2.0, 0.0, 0.0],
        [0.0, 2.0, 0.0],
    ]);
    net.cycle_loops(0).unwrap();
    // a twisted quadrilateral (Fig. 4's saddle) is fine
    let net = single(&[
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.5],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.5],
    ]);
    net.cycle_loops(0).unwrap();
    // a helix-like loop whose two strands pass 1e-12 apart in 3D touches
    let net = single(&[
        [0.0, 0.0, 0.0],
        [2.0, 2.0, 1e-12],
        [2.0, 0.0, 0.0],
        [0.0, 2.0, 0.0],
    ]);
    assert!(matches!(
        net.cycle_loops(0),
        Err(CurveNetError::SelfIntersecting { .. })
    ));
}

#[test]
fn too_few_points_or_zero_length() {
    // a curve out and back: 2 distinct points
    let net = CurveNetwork::new(
        vec![curve(&[[0.0; 3], [1.0, 0.0, 0.0], [0.0; 3]])],
        vec![cycle(&[&[(0, 1)]])],
        vec![],
    )
    .unwrap();
    let e = net.cycle_loops(0).unwrap_err();
    assert!(
        matches!(e, CurveNetError::TooFewPoints { distinct: 2, .. }),
        "{e:?}"
    );
    assert!(e.to_string().contains("has 2 distinct points"), "{e}");
    // a cycle of one point (zero length) beside a valid one
    let net = CurveNetwork::new(
        vec![
            closed(&square_pts(0.0, 0.0, 1.0)),
            curve(&[[5.0, 5.0, 0.0]]),
        ],
        vec![cycle(&[&[(0, 1)]]), cycle(&[&[(1, 1)]])],
        vec![],
    )
    .unwrap();
    net.cycle_loops(0).unwrap();
    let e = net.cycle_loops(1).unwrap_err();
    assert!(
        matches!(
            e,
            CurveNetError::TooFewPoints {
                distinct: 1,
                at: Some([5.0, 5.0, 0.0]),
                ..
            }
        ),
        "{e:?}"
    );
    assert!(e.to_string().contains("zero length"), "{e}");
    // a cycle with no loop, a loop with no use
    let net = CurveNetwork::new(
        vec![closed(&square_pts(0.0, 0.0, 1.0))],
        vec![
            NetworkCycle {
                loops: vec![],
                cad_face: None,
        surface: None,
            },
            NetworkCycle {
                loops: vec![vec![]],
                cad_face: None,
        surface: None,
            },
        ],
        vec![],
    )
    .unwrap();
    assert_eq!(net.validate().len(), 2);
    assert!(net
        .validate()
        .iter()
        .all(|e| matches!(e, CurveNetError::TooFewPoints { distinct: 0, .. })));
}

#[test]
fn no_inward_side_folded_flat_or_a_figure_eight() {
    // a sliver triangle 1e-7 thick
    let net = single(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 1e-7, 0.0]]);
    let e = net.cycle_loops(0).unwrap_err();
    assert!(matches!(e, CurveNetError::NoInwardSide { .. }), "{e:?}");
    assert!(e.to_string().contains("no inward side"), "{e}");
    // a figure-eight lifted apart at its crossing (not touching): its two
    // lobes turn opposite ways and their areas cancel
    let h = 1e-7;
    let net = single(&[
        [0.0, 0.0, h],
        [-2.0, 1.0, 0.0],
        [-2.0, -1.0, 0.0],
        [0.0, 0.0, -h],
        [2.0, 1.0, 0.0],
        [2.0, -1.0, 0.0],
    ]);
    let e = net.cycle_loops(0).unwrap_err();
    assert!(matches!(e, CurveNetError::NoInwardSide { .. }), "{e:?}");
}

#[test]
fn unknown_curves_and_non_finite_coordinates() {
    let sq = closed(&square_pts(0.0, 0.0, 1.0));
    let e = CurveNetwork::new(
        vec![sq.clone()],
        vec![cycle(&[&[(0, 1)], &[(3, -1)]])],
        vec![],
    )
    .unwrap_err();
    assert!(
        matches!(
            e,
            CurveNetError::UnknownCurve {
                loop_index: 1,
                use_index: 0,
                curve: 3,
                curves: 1,
                ..
            }
        ),
        "{e:?}"
    );
    assert_eq!(
        e.to_string(),
        "cycle 0: unknown curve: use 0 of hole 1 names curve 3, but the curves are 0 to 0"
    );
    let mut nan = sq.clone();
    nan.points[2][1] = f64::NAN;
    let e = CurveNetwork::new(vec![nan], vec![cycle(&[&[(0, 1)]])], vec![]).unwrap_err();
    assert!(matches!(e, CurveNetError::NotFinite { .. }), "{e:?}");
    assert_eq!(
        e.to_string(),
        "not a finite number: curve 0 point 2 (used by cycle 0) is (1, NaN, 0)"
    );
    let e = CurveNetwork::new(
        vec![sq.clone()],
        vec![cycle(&[&[(0, 1)]])],
        vec![[f64::INFINITY, 0.0, 0.0]],
    )
    .unwrap_err();
    assert!(e.to_string().contains("corner 0 is (inf, 0, 0)"), "{e}");
    // empty networks
    assert!(matches!(
        CurveNetwork::new(vec![], vec![], vec![]),
        Err(CurveNetError::Empty { .. })
    ));
    assert!(matches!(
        CurveNetwork::new(vec![sq], vec![], vec![]),
        Err(CurveNetError::Empty { .. })
    ));
    assert!(matches!(
        CurveNetwork::new(
            vec![curve(&[[1.0; 3], [1.0; 3]])],
            vec![cycle(&[&[(0, 1)]])],
            vec![]
        ),
        Err(CurveNetError::Empty { .. })
    ));
    let net = single(&square_pts(0.0, 0.0, 1.0));
    assert!(matches!(
        net.cycle_loops(1),
        Err(CurveNetError::OutOfRange {
            index: 1,
            count: 1,
            ..
        })
    ));
}

#[test]
fn holes_run_opposite_the_outer_loop() {
    let outer = closed(&square_pts(0.0, 0.0, 4.0));
    let hole = closed(&square_pts(1.0, 1.0, 1.0)); // counter-clockwise too
    for dir in [1, -1] {
        let net = CurveNetwork::new(
            vec![outer.clone(), hole.clone()],
            vec![cycle(&[&[(0, 1)], &[(1, dir)]])],
            vec![],
        )
        .unwrap();
        let c = net.cycle_loops(0).unwrap();
        assert_eq!(c.holes.len(), 1);
        let (no, nh) = (
            check::newell(&c.outer.points),
            check::newell(&c.holes[0].points),
        );
        assert!(no[2] > 0.0 && nh[2] < 0.0, "{dir}: {no:?} {nh:?}");
        // the join at the hole curve's end stays fixed after the reversal
        assert_eq!(c.holes[0].fixed, vec![0]);
        assert_eq!(c.holes[0].points[0], [1.0, 1.0, 0.0]);
    }
    // a hole touching the outer loop
    let touching = closed(&square_pts(0.0, 1.0, 1.0));
    let net = CurveNetwork::new(
        vec![outer, touching],
        vec![cycle(&[&[(0, 1)], &[(1, -1)]])],
        vec![],
    )
    .unwrap();
    let e = net.cycle_loops(0).unwrap_err();
    assert!(
        matches!(e, CurveNetError::SelfIntersecting { loops: (0, 1), .. }),
        "{e:?}"
    );
    assert!(
        e.to_string()
            .contains("the outer loop and hole 1 cross or touch"),
        "{e}"
    );
}

#[test]
fn large_cycles_are_checked_whole() {
    // 100 000 points on a wavy circle: valid (a quadratic check would take
    // minutes here; its speed is a benchmark's business, not a timed test's)
    let n = 100_000;
    let pts: Vec<Vec3> = (0..n)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / n as f64;
            let r = 1.0 + 0.1 * (7.0 * a).sin();
            [r * a.cos(), r * a.sin(), 0.05 * (3.0 * a).cos()]
        })
        .collect();
    let net = single(&pts);
    let c = net.cycle_loops(0).unwrap();
    assert_eq!(c.outer.points.len(), n);
    // the same with one point pulled onto a far segment: found
    let mut bad = pts.clone();
    bad[n / 2] = vec3::lerp(pts[10], pts[11], 0.5);
    let net = single(&bad);
    assert!(matches!(
        net.cycle_loops(0),
        Err(CurveNetError::SelfIntersecting { .. })
    ));
}
