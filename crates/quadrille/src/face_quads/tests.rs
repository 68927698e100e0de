//! Unit tests of [`FaceQuads`], and the hand-built planar patches the
//! regularization tests share.

use geometry::{primitives, CurveId, FaceId, Model};
use mesh::NodeClass;

use super::*;

/// The unit-square model whose face is the plane z = 0 with (u, v) = (x, y)
/// over `[0, side]²`; hand-built patches live on it.
pub(crate) fn plane(side: f64) -> Model {
    primitives::square(side)
}

/// A planar patch from (u, v) points and counter-clockwise quads: vertices with
/// an open fan are fixed boundary vertices, the others movable.
pub(crate) fn planar(points: &[[f64; 2]], quads: Vec<[u32; 4]>) -> FaceQuads {
    let verts = points
        .iter()
        .enumerate()
        .map(|(i, &uv)| QVertex { global: Some(i as u32), ..QVertex::interior(uv, [uv[0], uv[1], 0.0], NodeClass::Face(FaceId(0), Some(uv))) })
        .collect();
    let mut fq = FaceQuads::new(verts, quads).expect("valid quads");
    for v in 0..fq.verts.len() as u32 {
        if fq.ordered_star(v).is_none() {
            fq.verts[v as usize].fixed = true;
            fq.verts[v as usize].class = NodeClass::Curve(CurveId(0), None);
        }
    }
    fq.classify_fixed();
    fq
}

/// An n × n grid of unit quads on `[0, n]²`; vertex `(i, j)` has id `j (n + 1) + i`.
pub(crate) fn grid(n: u32) -> FaceQuads {
    let mut pts = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            pts.push([i as f64, j as f64]);
        }
    }
    let id = |i: u32, j: u32| j * (n + 1) + i;
    let mut quads = Vec::new();
    for j in 0..n {
        for i in 0..n {
            quads.push([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    planar(&pts, quads)
}

#[test]
fn grid_is_regular_with_boundary_ideals_from_angles() {
    let fq = grid(4);
    fq.check().unwrap();
    assert_eq!(fq.num_quads(), 16);
    assert_eq!(fq.irregular_count(), 0);
    // corner: 1 quad, 2 edges, 90° → ideal 2; side: 2 quads, 3 edges, 180° → 3; inside: 4
    assert_eq!((fq.valence(0), fq.verts[0].ideal, fq.verts[0].fixed), (2, 2, true));
    assert_eq!((fq.valence(2), fq.verts[2].ideal), (3, 3));
    assert_eq!((fq.valence(12), fq.verts[12].ideal, fq.verts[12].fixed), (4, 4, false));
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
    assert!(!fq.move_vertex(face, 0, [0.5, 0.5]), "fixed vertices never move");
    let q = fq.quads[4];
    fq.set_quad(4, [q[1], q[2], q[3], q[0]]);
    let v = fq.add_vertex(QVertex::interior([1.5, 1.5], [1.5, 1.5, 0.0], NodeClass::Face(FaceId(0), None)));
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
