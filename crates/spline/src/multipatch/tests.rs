use super::*;
use crate::curve::fit_curve;

/// An arc from a to b bulging by `bulge` in z, fitted with `spans` spans.
pub(crate) fn arc(a: Point3, b: Point3, bulge: f64, spans: usize) -> BSplineCurve {
    let m = 50;
    let params: Vec<f64> = (0..m).map(|i| i as f64 / (m - 1) as f64).collect();
    let pts: Vec<Point3> = params
        .iter()
        .map(|&t| {
            let mut p = [0.0; 3];
            for k in 0..3 {
                p[k] = a[k] + (b[k] - a[k]) * t;
            }
            p[2] += bulge * 4.0 * t * (1.0 - t);
            p
        })
        .collect();
    fit_curve(&pts, &params, spans).unwrap()
}

/// Two unit squares side by side sharing the arc x = 1, with the shared
/// arc used forward by one patch and reversed by the other.
pub(crate) fn two_squares(spans: usize) -> Multipatch {
    let mut b = MultipatchBuilder::new();
    let n: Vec<usize> = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 0.0],
        [2.0, 1.0, 0.0],
    ]
    .iter()
    .map(|&p| b.add_node(p))
    .collect();
    let pos = |b: &MultipatchBuilder, i: usize| b.points[n[i]];
    let mk = |b: &mut MultipatchBuilder, i: usize, j: usize, bulge: f64| {
        let (pa, pb) = (pos(b, i), pos(b, j));
        b.add_arc(n[i], n[j], &arc(pa, pb, bulge, spans)).unwrap()
    };
    let b01 = mk(&mut b, 0, 1, 0.1);
    let b12 = mk(&mut b, 1, 2, -0.1);
    let t34 = mk(&mut b, 3, 4, 0.05);
    let t45 = mk(&mut b, 4, 5, 0.0);
    let l03 = mk(&mut b, 0, 3, 0.0);
    // The shared arc stored top to bottom: patch 0 uses it reversed.
    let m41 = mk(&mut b, 4, 1, 0.2);
    let r25 = mk(&mut b, 2, 5, -0.05);
    b.add_coons_patch([
        ArcUse::forward(b01),
        ArcUse::forward(t34),
        ArcUse::forward(l03),
        ArcUse::reverse(m41),
    ])
    .unwrap();
    b.add_coons_patch([
        ArcUse::forward(b12),
        ArcUse::forward(t45),
        ArcUse::reverse(m41),
        ArcUse::forward(r25),
    ])
    .unwrap();
    b.build().unwrap()
}

#[test]
fn shared_arcs_share_indices_and_close_exactly() {
    let mp = two_squares(3);
    assert_eq!(mp.patches().len(), 2);
    let (a, b) = (&mp.patches()[0], &mp.patches()[1]);
    assert_eq!(a.side(1), b.side(3));
    // 6 nodes + 7 arcs × 4 interior points + 2 × 4 × 4 patch interiors.
    assert_eq!(mp.points().len(), 6 + 7 * 4 + 2 * 16);
    assert_eq!(
        mp.shared_sides(),
        SharedSides {
            pairs: 1,
            max_gap: 0.0
        }
    );
    assert_eq!(mp.components(), 1);
    // The evaluated boundaries coincide bit for bit.
    let (pa, pb) = (mp.patch(0).unwrap(), mp.patch(1).unwrap());
    for k in 0..=20 {
        let t = k as f64 / 20.0;
        assert_eq!(pa.eval(1.0, t), pb.eval(0.0, t));
    }
}

#[test]
fn refined_multipatch_stays_conforming() {
    let mp = two_squares(1);
    let fine = mp.refined(8).unwrap();
    assert_eq!((fine.patches()[0].n_s(), fine.patches()[0].n_t()), (11, 11));
    assert_eq!(fine.patches()[0].side(1), fine.patches()[1].side(3));
    // 2 × 121 minus the 11 shared.
    assert_eq!(fine.points().len(), 2 * 121 - 11);
    assert_eq!(
        fine.shared_sides(),
        SharedSides {
            pairs: 1,
            max_gap: 0.0
        }
    );
    assert_eq!(fine.components(), 1);
    for k in 0..2 {
        let (p, q) = (mp.patch(k).unwrap(), fine.patch(k).unwrap());
        for (s, t) in [(0.1, 0.2), (0.5, 0.9), (1.0, 0.3)] {
            assert!(crate::vec3::dist(p.eval(s, t), q.eval(s, t)) < 1e-12);
        }
    }
}

#[test]
fn detects_gaps_disconnection_and_bad_input() {
    let mp = two_squares(2);
    // Duplicate the shared arc's interior points for patch 1: two sides
    // with the same end nodes but different indices, moved apart.
    let mut points = mp.points().to_vec();
    let mut patches = mp.patches().to_vec();
    let (ns, nt) = (patches[1].n_s(), patches[1].n_t());
    for j in 1..nt - 1 {
        let old = patches[1].indices[j * ns];
        let mut p = points[old];
        p[2] += 1e-3;
        points.push(p);
        patches[1].indices[j * ns] = points.len() - 1;
    }
    let broken = Multipatch::from_parts(points, patches).unwrap();
    let found = broken.shared_sides();
    assert_eq!(found.pairs, 1);
    assert!((found.max_gap - 1e-3).abs() < 1e-12);
    // An unused point is a second component.
    let mut pts = mp.points().to_vec();
    pts.push([9.0; 3]);
    assert_eq!(
        Multipatch::from_parts(pts, mp.patches().to_vec())
            .unwrap()
            .components(),
        2
    );
    assert!(mp
        .patch(2)
        .unwrap_err()
        .to_string()
        .contains("patch 2 does not exist"));
    let mut bad = mp.patches().to_vec();
    bad[0].indices[0] = 10_000;
    assert!(Multipatch::from_parts(mp.points().to_vec(), bad)
        .unwrap_err()
        .to_string()
        .contains("index 10000"));
    // A patch whose corners are different nodes.
    let mut b = MultipatchBuilder::new();
    let (n0, n1, n2) = (
        b.add_node([0.0; 3]),
        b.add_node([1.0, 0.0, 0.0]),
        b.add_node([0.0, 1.0, 0.0]),
    );
    let a = b
        .add_arc(n0, n1, &arc([0.0; 3], [1.0, 0.0, 0.0], 0.0, 1))
        .unwrap();
    let c = b
        .add_arc(n0, n2, &arc([0.0; 3], [0.0, 1.0, 0.0], 0.0, 1))
        .unwrap();
    let e = b.add_coons_patch([
        ArcUse::forward(a),
        ArcUse::forward(a),
        ArcUse::forward(c),
        ArcUse::forward(c),
    ]);
    assert!(e.unwrap_err().to_string().contains("corner"));
    assert!(b
        .add_arc(n0, n1, &arc([0.0; 3], [1.0, 0.5, 0.0], 0.0, 1))
        .is_err());
}

#[test]
fn distinct_arcs_between_the_same_nodes_are_not_compared() {
    // Two patches on the same four nodes: they share top, left and right,
    // but their bottoms are two different arcs from A to B (a bigon).
    let mut b = MultipatchBuilder::new();
    let (pa, pb, pc, pd) = (
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 0.0],
    );
    let (na, nb, nc, nd) = (
        b.add_node(pa),
        b.add_node(pb),
        b.add_node(pc),
        b.add_node(pd),
    );
    let flat = b.add_arc(na, nb, &arc(pa, pb, 0.0, 2)).unwrap();
    let bulged = b.add_arc(na, nb, &arc(pa, pb, 0.6, 2)).unwrap();
    let top = b.add_arc(nc, nd, &arc(pc, pd, 0.0, 2)).unwrap();
    let left = b.add_arc(na, nc, &arc(pa, pc, 0.0, 2)).unwrap();
    let right = b.add_arc(nb, nd, &arc(pb, pd, 0.0, 2)).unwrap();
    let f = ArcUse::forward;
    b.add_coons_patch([f(flat), f(top), f(left), f(right)])
        .unwrap();
    b.add_coons_patch([f(bulged), f(top), f(left), f(right)])
        .unwrap();
    let mp = b.build().unwrap();
    assert_eq!(
        mp.shared_sides(),
        SharedSides {
            pairs: 3,
            max_gap: 0.0
        }
    );
    let fine = mp.refined(2).unwrap();
    assert_eq!(
        fine.shared_sides(),
        SharedSides {
            pairs: 3,
            max_gap: 0.0
        }
    );
    // 4 corners + 5 arcs × 5 interior points + 2 × 5 × 5 patch interiors.
    assert_eq!(fine.points().len(), 4 + 5 * 5 + 2 * 25);
}

#[test]
fn a_tube_closing_on_its_own_seam() {
    // One patch around a cylinder (the annulus of spec §9 footnote 3): the
    // bottom and top are closed circles, left and right the same seam arc.
    let tau = std::f64::consts::TAU;
    let circle = |z: f64| {
        let params: Vec<f64> = (0..200).map(|i| i as f64 / 199.0).collect();
        let pts: Vec<Point3> = params
            .iter()
            .map(|&t| [(tau * t).cos(), (tau * t).sin(), z])
            .collect();
        fit_curve(&pts, &params, 4).unwrap()
    };
    let mut b = MultipatchBuilder::new();
    let (na, nb) = (b.add_node([1.0, 0.0, 0.0]), b.add_node([1.0, 0.0, 1.0]));
    let bottom = b.add_arc(na, na, &circle(0.0)).unwrap();
    let top = b.add_arc(nb, nb, &circle(1.0)).unwrap();
    let seam = b
        .add_arc(na, nb, &arc([1.0, 0.0, 0.0], [1.0, 0.0, 1.0], 0.0, 4))
        .unwrap();
    let f = ArcUse::forward;
    b.add_coons_patch([f(bottom), f(top), f(seam), f(seam)])
        .unwrap();
    let mp = b.build().unwrap();
    for m in [mp.clone(), mp.refined(2).unwrap()] {
        let g = &m.patches()[0];
        let (ns, nt) = (g.n_s(), g.n_t());
        assert_eq!(g.side(1), g.side(3));
        assert_eq!(m.points().len(), (ns - 1) * nt);
        assert_eq!(
            m.shared_sides(),
            SharedSides {
                pairs: 1,
                max_gap: 0.0
            }
        );
        assert_eq!(m.components(), 1);
        let p = m.patch(0).unwrap();
        for k in 0..=10 {
            let t = k as f64 / 10.0;
            assert_eq!(p.eval(0.0, t), p.eval(1.0, t));
        }
        // Outward normal: S_s (around) × S_t (up) points away from the axis.
        let outward = |x: Point3, _: f64, _: f64| [x[0], x[1], 0.0];
        let rep = crate::bezier::jacobian_check(&p, &outward).unwrap();
        assert!(
            rep.is_positive() && rep.min_scaled_jacobian > 0.9,
            "{rep:?}"
        );
    }
}
