//! The regular pass on hand-made patches of the unit square's grid.

use geometry::primitives::square;
use geometry::FaceId;

use super::*;
use crate::fixtures::grids::square_grid;
use crate::topology::regularize::ops::{apply, Op};

/// The 8 × 8 grid with the edge between cells (3, 3) and (4, 3) swapped
/// (two valence-3 and two valence-5 interior vertices), smoothed until
/// every quad is valid.
fn grid_with_a_swapped_edge(face: &geometry::Face) -> QuadPatch {
    let n = 8;
    let grid = square_grid(n, |_, _| false);
    let mut fq = to_face_quads(FaceId(0), &grid).expect("a grid converts");
    let q = (3 * n + 3) as u32;
    assert!(apply(&mut fq, face, Op::Swap { q, e: 1, k: 1 }).is_some());
    let mut p = to_patch(&fq, &grid);
    optimize(face, &mut p, &OptimizeOptions::default());
    p
}

#[test]
fn a_patch_comes_back_unchanged_from_face_quads() {
    let grid = square_grid(5, |x, y| x == 2 && y == 2);
    let fq = to_face_quads(FaceId(0), &grid).expect("a grid with a hole converts");
    let back = to_patch(&fq, &grid);
    assert_eq!(back.quads, grid.quads);
    assert_eq!(back.pos, grid.pos);
    for (a, b) in back.nodes.iter().zip(&grid.nodes) {
        assert_eq!(a.node, b.node);
        assert_eq!(a.uv, b.uv);
    }
    // boundary nodes fixed, interior ones movable; the hole's rim is fixed too
    // (its fans are open), and counts as regular at 3 or 4 edges as it should
    let fixed = fq.verts.iter().filter(|v| v.fixed).count();
    assert_eq!(fixed, 20 + 4);
}

#[test]
fn a_swapped_edge_in_a_grid_is_swapped_back() {
    let model = square(1.0);
    let face = &model.faces[0];
    let mut p = grid_with_a_swapped_edge(face);
    assert_eq!(
        p.interior_irregular(),
        4,
        "the swap makes two 3s and two 5s"
    );
    let before = patch_quality(face, &p);
    assert!(before.0 > 0.0, "the swapped grid is valid: {before:?}");
    let rep = reduce_irregular(face, FaceId(0), &mut p, &[], &RegularPassOptions::default());
    assert!(rep.tried && rep.kept, "{rep:?}");
    assert_eq!(rep.irregular, (4, 0));
    assert_eq!(p.interior_irregular(), 0);
    assert_eq!(p.quads.len(), 64);
    let after = patch_quality(face, &p);
    assert_eq!(after, rep.after);
    assert!(
        after.0 >= POOR_SICN && after.1 > before.1,
        "{before:?} → {after:?}"
    );
}

#[test]
fn a_regular_patch_is_not_tried() {
    let model = square(1.0);
    let mut p = square_grid(6, |_, _| false);
    let before = p.clone();
    let rep = reduce_irregular(
        &model.faces[0],
        FaceId(0),
        &mut p,
        &[],
        &RegularPassOptions::default(),
    );
    assert!(!rep.tried && !rep.kept, "{rep:?}");
    assert_eq!(p.quads, before.quads);
    assert_eq!(p.pos, before.pos);
}

#[test]
fn a_result_that_fails_the_quality_check_leaves_the_patch_exactly_as_it_was() {
    let model = square(1.0);
    let face = &model.faces[0];
    let mut p = grid_with_a_swapped_edge(face);
    let input = p.clone();
    // an average that must rise by 1: no result can pass
    let opts = RegularPassOptions {
        average_loss: -1.0,
        ..Default::default()
    };
    let rep = reduce_irregular(face, FaceId(0), &mut p, &[], &opts);
    assert!(rep.tried && !rep.kept, "{rep:?}");
    assert_eq!(rep.irregular, (4, 4));
    assert_eq!(p.quads, input.quads);
    assert_eq!(p.pos, input.pos);
    let uv_same = p.nodes.iter().zip(&input.nodes).all(|(a, b)| a.uv == b.uv);
    assert!(uv_same);
}

#[test]
fn a_face_above_the_quad_cap_is_left_alone() {
    let model = square(1.0);
    let face = &model.faces[0];
    let mut p = grid_with_a_swapped_edge(face);
    let opts = RegularPassOptions {
        max_quads: 63,
        ..Default::default()
    };
    let rep = reduce_irregular(face, FaceId(0), &mut p, &[], &opts);
    assert!(!rep.tried, "{rep:?}");
    assert_eq!(p.interior_irregular(), 4);
}
