use super::*;

fn poly(corners: &[[f64; 2]]) -> OrthogonalPolygon {
    OrthogonalPolygon {
        corners: corners.to_vec(),
        corner_vertices: (0..corners.len()).collect(),
        max_deviation: 0.0,
        size: 4.0,
    }
}

fn area(l: &Layout) -> f64 {
    l.rects
        .iter()
        .map(|r| {
            let (a, c) = (l.nodes[r.corners[0]], l.nodes[r.corners[2]]);
            (c[0] - a[0]) * (c[1] - a[1])
        })
        .sum()
}

#[test]
fn square_is_one_rectangle() {
    let l = trace_layout(&poly(&[[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]])).unwrap();
    assert_eq!(
        (l.rects.len(), l.nodes.len(), l.arcs.len(), l.separatrices),
        (1, 4, 4, 0)
    );
    assert!(l.arc_on_boundary.iter().all(|&b| b));
}

#[test]
fn l_shape_gives_three_rectangles() {
    // reflex corner at (1, 1)
    let l = trace_layout(&poly(&[
        [0.0, 0.0],
        [2.0, 0.0],
        [2.0, 1.0],
        [1.0, 1.0],
        [1.0, 2.0],
        [0.0, 2.0],
    ]))
    .unwrap();
    assert_eq!(l.separatrices, 2);
    assert_eq!(l.rects.len(), 3);
    // 6 corners + 2 separatrix ends on the boundary
    assert_eq!(l.nodes.len(), 8);
    // 8 boundary arcs + 2 separatrices
    assert_eq!(l.arcs.len(), 10);
    assert_eq!(l.arc_on_boundary.iter().filter(|&&b| !b).count(), 2);
    assert!((area(&l) - 3.0).abs() < 1e-12);
}

#[test]
fn crossing_separatrices_split_a_plus_into_nine() {
    // a plus sign: 4 reflex corners; their separatrices cross in the middle
    let c = [
        [1.0, 0.0],
        [2.0, 0.0],
        [2.0, 1.0],
        [3.0, 1.0],
        [3.0, 2.0],
        [2.0, 2.0],
        [2.0, 3.0],
        [1.0, 3.0],
        [1.0, 2.0],
        [0.0, 2.0],
        [0.0, 1.0],
        [1.0, 1.0],
    ];
    let l = trace_layout(&poly(&c)).unwrap();
    assert_eq!(l.separatrices, 8);
    assert_eq!(l.rects.len(), 5);
    assert!((area(&l) - 5.0).abs() < 1e-12);
}

#[test]
fn staircase_separatrices_cross_without_t_junctions() {
    // a U: two reflex corners at the bottom of the notch
    let c = [
        [0.0, 0.0],
        [3.0, 0.0],
        [3.0, 2.0],
        [2.0, 2.0],
        [2.0, 1.0],
        [1.0, 1.0],
        [1.0, 2.0],
        [0.0, 2.0],
    ];
    let l = trace_layout(&poly(&c)).unwrap();
    assert_eq!(l.separatrices, 4);
    // the horizontal separatrices run along y = 1 and meet: 5 rectangles
    assert_eq!(l.rects.len(), 5);
    assert!((area(&l) - 5.0).abs() < 1e-12);
    for r in &l.rects {
        for &(a, _) in &r.sides {
            assert!(a < l.arcs.len());
        }
    }
}

#[test]
fn a_slanted_side_is_refused() {
    let e = trace_layout(&poly(&[[0.0, 0.0], [2.0, 0.0], [1.5, 1.0], [0.0, 1.0]])).unwrap_err();
    assert!(matches!(e, LayoutError::NotOrthogonal(_)), "{e}");
}
