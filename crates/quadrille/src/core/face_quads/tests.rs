//! Unit tests of [`FaceQuads`] and of the shared patch builders
//! ([`super::test_support`]).

use geometry::FaceId;
use mesh::NodeClass;

use super::*;
use crate::fixtures::face_quads::{grid, plane, Patch};

#[test]
fn grid_is_regular_with_boundary_ideals_from_angles() {
    let fq = grid(4);
    fq.check().unwrap();
    assert_eq!(fq.num_quads(), 16);
    assert_eq!(fq.irregular_count(), 0);
    // corner: 1 quad, 2 edges, 90° → ideal 2; side: 2 quads, 3 edges, 180° → 3; inside: 4
    assert_eq!(
        (fq.valence(0), fq.verts[0].ideal, fq.verts[0].fixed),
        (2, 2, true)
    );
    assert_eq!((fq.valence(2), fq.verts[2].ideal), (3, 3));
    assert_eq!(
        (fq.valence(12), fq.verts[12].ideal, fq.verts[12].fixed),
        (4, 4, false)
    );
    assert_eq!(ideal_boundary_valence(270.0), 4);
    assert_eq!(ideal_boundary_valence(30.0), 2);
}

#[test]
fn ordered_star_is_counter_clockwise_and_across_finds_neighbours() {
    let fq = grid(2);
    // centre vertex (1,1) = id 4
    let star = fq.ordered_star(4).unwrap();
    assert_eq!(star.len(), 4);
    let links: Vec<u32> = star.iter().map(|s| s.1[1]).collect();
    // consecutive links turn counter-clockwise about +z
    for i in 0..4 {
        let c = fq.verts[4].uv;
        let a = fq.verts[links[i] as usize].uv;
        let b = fq.verts[links[(i + 1) % 4] as usize].uv;
        let cross = (a[0] - c[0]) * (b[1] - c[1]) - (a[1] - c[1]) * (b[0] - c[0]);
        assert!(cross > 0.0);
    }
    assert!(fq.ordered_star(0).is_none());
    // quad 0 = (0,1,4,3); across its edge 1 → 4 lies quad 1 = (1,2,5,4)
    assert_eq!(fq.across(0, 1, 4), Some(1));
    assert_eq!(fq.across(0, 0, 1), None);
    assert_eq!(fq.edge_quads(1, 4), vec![0, 1]);
    assert_eq!(fq.links(4), vec![1, 3, 5, 7]);
}

#[test]
fn rollback_restores_topology_and_positions_exactly() {
    let m = plane(3.0);
    let face = &m.faces[0];
    let mut fq = grid(3);
    let orig = fq.clone();
    let cp = fq.checkpoint();
    assert!(fq.move_vertex(face, 5, [1.2, 1.1]));
    assert!(
        !fq.move_vertex(face, 0, [0.5, 0.5]),
        "fixed vertices never move"
    );
    let q = fq.quads[4];
    fq.set_quad(4, [q[1], q[2], q[3], q[0]]);
    let v = fq.add_vertex(QVertex::interior(
        [1.5, 1.5],
        [1.5, 1.5, 0.0],
        NodeClass::Face(FaceId(0), None),
    ));
    fq.kill_quad(0);
    fq.add_quad([0, 1, v, 4]);
    assert_ne!(fq.verts, orig.verts);
    assert_eq!(fq.touched_since(cp).last(), Some(&v));
    fq.rollback(cp);
    assert_eq!(fq.verts, orig.verts);
    assert_eq!(fq.quads, orig.quads);
    assert_eq!(fq.quad_alive, orig.quad_alive);
    fq.check().unwrap();
}

/// Twice the signed area of a planar quad (positive when counter-clockwise).
fn signed_area2(fq: &FaceQuads, q: u32) -> f64 {
    let p = fq.quads[q as usize].map(|v| fq.verts[v as usize].uv);
    (0..4)
        .map(|i| p[i][0] * p[(i + 1) % 4][1] - p[(i + 1) % 4][0] * p[i][1])
        .sum()
}

#[test]
fn patch_rings_make_the_core_interior_with_the_requested_valences() {
    // one unit quad, ringed so that its corners get (3, 5, 3, 5) quads
    let core = Patch::new(
        &[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
        &[[0, 1, 2, 3]],
    );
    assert_eq!(core.boundary_loop(), vec![0, 1, 2, 3]);
    let want = [3, 5, 3, 5];
    let once = core.ring(|v| want[v as usize]);
    let fq = once.build();
    for v in 0..4u32 {
        assert!(!fq.verts[v as usize].fixed);
        assert_eq!(fq.valence(v), want[v as usize]);
        assert!(fq.ordered_star(v).is_some());
    }
    // one ring quad per radial edge: Σ (valence − fan − 1) = 1 + 3 + 1 + 3
    assert_eq!(fq.num_quads(), 1 + 8);
    assert!(fq.live_quads().all(|q| signed_area2(&fq, q) > 0.0));
    // a second, regular ring makes the first ring's outer loop interior too
    let twice = once.clone().ring_regular(&[]);
    let fq2 = twice.build();
    for v in 0..fq.verts.len() as u32 {
        assert!(!fq2.verts[v as usize].fixed, "vertex {v}");
        if v < 4 {
            assert_eq!(fq2.valence(v), want[v as usize]);
        } else {
            assert!(fq2.valence(v) >= 4, "first-ring vertex {v}");
        }
    }
    assert!(fq2.live_quads().all(|q| signed_area2(&fq2, q) > 0.0));
    // relaxing moves only the rings (the boundary onto a circle), keeps the topology
    let relaxed = twice.clone().relaxed(4);
    assert_eq!(
        (&relaxed.pts[..4], &relaxed.quads),
        (&twice.pts[..4], &twice.quads)
    );
    let fq3 = relaxed.build();
    assert!(fq3.live_quads().all(|q| signed_area2(&fq3, q) > 0.0));
    // ids are stable: the core and the first ring keep their points
    assert_eq!(&twice.pts[..once.pts.len()], &once.pts[..]);
    assert_eq!(&twice.quads[..once.quads.len()], &once.quads[..]);
}

#[test]
fn a_pole_with_a_closed_fan_wants_the_valence_its_cone_angle_holds() {
    // the cone angle θ in right angles, rounded, at least 3
    assert_eq!(
        ideal_pole_valence(360.0),
        4,
        "a sphere pole is a smooth point"
    );
    assert_eq!(
        ideal_pole_valence(309.0),
        3,
        "a 118° drill tip: 360° · sin 59° ≈ 309°"
    );
    assert_eq!(
        ideal_pole_valence(180.0),
        3,
        "never fewer than 3 (no doublets)"
    );
    assert_eq!(ideal_pole_valence(450.0), 5);
    assert_eq!(ideal_pole_valence(f64::NAN), 4);
    // a fixed pole at the centre of a flat 6-star (360°) wants 4 edges, so it
    // is irregular with 6; before it kept its current valence as ideal
    let p = Patch::new(
        &[
            [0.0, 0.0],
            [1.0, 0.0],
            [0.5, 0.87],
            [-0.5, 0.87],
            [-1.0, 0.0],
            [-0.5, -0.87],
            [0.5, -0.87],
            [1.5, 0.87],
            [0.0, 1.73],
            [-1.5, 0.87],
            [-1.5, -0.87],
            [0.0, -1.73],
            [1.5, -0.87],
        ],
        &[
            [0, 1, 7, 2],
            [0, 2, 8, 3],
            [0, 3, 9, 4],
            [0, 4, 10, 5],
            [0, 5, 11, 6],
            [0, 6, 12, 1],
        ],
    );
    let mut fq = p.build();
    fq.verts[0].fixed = true;
    fq.verts[0].pole = Some([[0.0, 0.0], [0.0, 0.0]]);
    fq.verts[0].class = NodeClass::Curve(geometry::CurveId(0), None);
    fq.classify_fixed();
    let x = &fq.verts[0];
    assert_eq!((x.edge_offset, fq.valence(0), x.ideal), (0, 6, 4));
    assert!(fq.is_irregular(0));
    assert!((fq.angle_sum(0) - 360.0).abs() < 1.0);
}

#[test]
fn ordered_star_of_a_large_fan_matches_the_plain_scan() {
    // a wheel: centre 0, rim 1..=2n, quad i = (0, r(2i), r(2i+1), r(2i+2)),
    // listed in a shuffled order so that the fan is not already sorted
    let n = 3 * STAR_SCAN_MAX as u32;
    let rim = |k: u32| 1 + k % (2 * n);
    let mut verts = vec![QVertex::interior(
        [0.0, 0.0],
        [0.0, 0.0, 0.0],
        NodeClass::Face(FaceId(0), None),
    )];
    for k in 0..2 * n {
        let a = std::f64::consts::TAU * k as f64 / (2 * n) as f64;
        let r = if k % 2 == 0 { 1.0 } else { 1.2 };
        let p = [r * a.cos(), r * a.sin()];
        verts.push(QVertex::interior(
            p,
            [p[0], p[1], 0.0],
            NodeClass::Face(FaceId(0), None),
        ));
    }
    let order: Vec<u32> = (0..n).map(|i| (i * 7 + 3) % n).collect();
    let quads: Vec<[u32; 4]> = order
        .iter()
        .map(|&i| [0, rim(2 * i), rim(2 * i + 1), rim(2 * i + 2)])
        .collect();
    let fq = FaceQuads::new(verts, quads).unwrap();
    assert!(fq.verts[0].fan.len() > STAR_SCAN_MAX);
    // the plain k² scan, as ordered_star runs it on small fans
    let fan = &fq.verts[0].fan;
    let first = *fan.iter().min().unwrap();
    let mut plain = Vec::new();
    let mut q = first;
    loop {
        let r = fq.rotated(q, 0).unwrap();
        plain.push((q, r));
        let next = fan
            .iter()
            .copied()
            .find(|&p| p != q && fq.rotated(p, 0).is_some_and(|s| s[1] == r[3]))
            .unwrap();
        if next == first {
            break;
        }
        q = next;
    }
    let star = fq.ordered_star(0).unwrap();
    assert_eq!(star.len(), n as usize);
    assert_eq!(star, plain);
    // consecutive sectors share their edge: n_{i+1} of one is n_i of the next
    for i in 0..star.len() {
        assert_eq!(star[i].1[3], star[(i + 1) % star.len()].1[1]);
    }
    // a broken fan (one quad removed) has no closed star, as with the scan
    let mut open = fq.clone();
    open.kill_quad(star[5].0);
    assert!(open.ordered_star(0).is_none());
}
