use super::*;
use crate::coarse::fine_mesh::fine_mesh;
use crate::fixtures::layouts::{cylinder_ring, square_blocks};

/// The fine mesh of `layout` on `input` with its own loops' widths.
fn fine_of(model: &Model, input: &QuadMesh, layout: &BlockLayout) -> FineMesh {
    fine_mesh(model, input, layout, &QuadLoops::of(layout))
        .unwrap()
        .0
}

/// Checks that the split layout is a valid layout of its fine mesh, whose
/// grids and edges are its blocks' and edges' fine nodes.
fn assert_consistent(l: &BlockLayout, f: &FineMesh) {
    l.check(&f.mesh).unwrap();
    assert_eq!(
        f.mesh.quads.len(),
        f.block_grid
            .iter()
            .map(|g| g.size[0] * g.size[1])
            .sum::<usize>()
    );
    for (b, g) in f.block_grid.iter().enumerate() {
        let [w1, w2] = g.size;
        assert_eq!(
            l.blocks[b].corners,
            [g.at(0, 0), g.at(w1, 0), g.at(w1, w2), g.at(0, w2)]
        );
        assert_eq!(
            f.mesh.quads[g.first_quad as usize],
            [g.at(0, 0), g.at(1, 0), g.at(1, 1), g.at(0, 1)]
        );
    }
    for (v, &n) in l.vertex_node.iter().enumerate() {
        assert_eq!(n as usize, v, "vertex v is fine node v");
    }
}

#[test]
fn splitting_one_loop_halves_its_blocks() {
    let (model, input, layout) = square_blocks(8, 4);
    let fine = fine_of(&model, &input, &layout);
    let loops = QuadLoops::of(&layout);
    // the loop of the horizontal edges of the left column (blocks 0 and 2)
    let l = loops.edge_loop[0];
    let (split, sfine, done) = split_loops(&layout, &fine, &[l]).unwrap();
    assert_eq!(done, 1);
    assert_eq!(split.blocks.len(), 6);
    assert_consistent(&split, &sfine);
    // the same nodes, the same quads (reordered)
    assert_eq!(sfine.mesh.nodes.len(), fine.mesh.nodes.len());
    let mut a: Vec<[i64; 3]> = sfine
        .mesh
        .nodes
        .iter()
        .map(|p| p.map(|x| (x * 1e9) as i64))
        .collect();
    let mut b: Vec<[i64; 3]> = fine
        .mesh
        .nodes
        .iter()
        .map(|p| p.map(|x| (x * 1e9) as i64))
        .collect();
    a.sort_unstable();
    b.sort_unstable();
    assert_eq!(a, b);
    // the left column's blocks are 2 × 4 now, the right column's 4 × 4
    let sizes: Vec<[usize; 2]> = sfine.block_grid.iter().map(|g| g.size).collect();
    assert_eq!(sizes, vec![[2, 4], [2, 4], [4, 4], [2, 4], [2, 4], [4, 4]]);
    // and the elements are still affine
    let (ho, report) = extract_high_order(&model, &split, &sfine, 3).unwrap();
    assert_eq!(ho.num_elements(), 6);
    assert!((report.min_jacobian_ratio - 1.0).abs() < 1e-9);
    for p in &ho.nodes {
        for x in p {
            assert!((x * 12.0 - (x * 12.0).round()).abs() < 1e-9, "{p:?}");
        }
    }
}

#[test]
fn every_loop_split_across_a_seam_and_odd_widths() {
    // a ring of 3 blocks of 4 × 3 quads: widths 4 and 3 (odd: cut off centre)
    let (model, input, layout) = cylinder_ring(1.0, 2.0, 12, 3, 3);
    let fine = fine_of(&model, &input, &layout);
    let all: Vec<u32> = (0..QuadLoops::of(&layout).len() as u32).collect();
    let (split, sfine, done) = split_loops(&layout, &fine, &all).unwrap();
    assert_eq!(done, all.len());
    assert_eq!(split.blocks.len(), 12);
    assert_consistent(&split, &sfine);
    let mut sizes: Vec<[usize; 2]> = sfine.block_grid.iter().map(|g| g.size).collect();
    sizes.sort_unstable();
    sizes.dedup();
    assert_eq!(sizes, vec![[2, 1], [2, 2]]);
    // the seam and both circles are still followed, edge by edge
    assert_eq!(
        split.edges.iter().filter(|e| e.curve.is_some()).count(),
        6 + 6 + 2
    );
    let (ho, report) = extract_high_order(&model, &split, &sfine, 4).unwrap();
    assert!(report.invalid_elements.is_empty());
    for p in &ho.nodes {
        assert!((p[0].hypot(p[1]) - 1.0).abs() < 1e-9);
    }
    // a second split of the width-1 loops leaves them whole
    let ones: Vec<u32> = {
        let loops = QuadLoops::of(&split);
        (0..loops.len() as u32)
            .filter(|&l| loops.width[l as usize] == 1)
            .collect()
    };
    assert!(!ones.is_empty());
    let (again, _, done) = split_loops(&split, &sfine, &ones).unwrap();
    assert_eq!((done, again.blocks.len()), (0, 12));
}

#[test]
fn a_valid_extraction_splits_nothing_and_a_foreign_fine_mesh_is_an_error() {
    let (model, input, layout) = square_blocks(8, 4);
    let fine = fine_of(&model, &input, &layout);
    let x = extract_with_splits(&model, &layout, &fine, 5, SPLIT_ROUNDS).unwrap();
    assert_eq!((x.split_loops, x.mesh.num_elements()), (0, 4));
    assert_eq!(x.layout, layout);
    let (_, _, other) = square_blocks(8, 2);
    assert!(split_loops(&other, &fine, &[0]).is_err());
    assert!(extract_with_splits(&model, &other, &fine, 5, 1).is_err());
}

#[test]
fn half_a_cylinder_as_one_linear_element_is_split_until_valid() {
    // two blocks of 180°: a bilinear element's corners on a diameter, its
    // det J zero against the CAD normals; quarters are valid
    let (model, input, layout) = cylinder_ring(1.0, 2.0, 24, 4, 2);
    let fine = fine_of(&model, &input, &layout);
    let (_, first) = extract_high_order(&model, &layout, &fine, 1).unwrap();
    assert_eq!(first.invalid_elements, vec![0, 1]);
    let x = extract_with_splits(&model, &layout, &fine, 1, SPLIT_ROUNDS).unwrap();
    assert!(x.report.invalid_elements.is_empty(), "{:?}", x.report);
    assert!(x.report.min_jacobian_ratio > 0.0);
    // both loops of both blocks: four quarters, each two high
    assert_eq!((x.split_loops, x.mesh.num_elements()), (3, 8));
    assert_consistent(&x.layout, &x.fine);
    // no round without an invalid element; none beyond the limit
    let none = extract_with_splits(&model, &layout, &fine, 1, 0).unwrap();
    assert_eq!(
        (none.split_loops, none.report.invalid_elements.len()),
        (0, 2)
    );
}
