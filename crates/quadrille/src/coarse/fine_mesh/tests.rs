use std::collections::BTreeMap;

use super::*;
use crate::coarse::block_layout::BlockLayout;
use crate::coarse::high_order_extraction::extract_high_order;
use crate::coarse::quad_loops::QuadLoops;
use crate::fixtures::layouts::{cylinder_ring, square_blocks, structured_blocks, triangle_blocks};
use crate::{mesh_model_with, MeshMethod, MeshOptions, Size};
use geometry::primitives;

/// The default method's mesh of `model` at size factor `f`, one thread.
pub(crate) fn default_mesh(model: &Model, f: f64) -> QuadMesh {
    let opts = MeshOptions {
        size: Size::Factor(f),
        threads: Some(1),
        ..Default::default()
    };
    mesh_model_with(model, &opts, MeshMethod::default())
        .unwrap()
        .0
}

/// Checks that `m` is a conforming quad mesh: quads of four distinct nodes,
/// each directed edge used once, each undirected edge by at most two
/// quads, curve edges on quad edges; returns the number of edges used by one
/// quad only (open edges).
pub(crate) fn assert_conforming(m: &QuadMesh) -> usize {
    let mut directed = BTreeMap::new();
    for (qi, q) in m.quads.iter().enumerate() {
        for k in 0..4 {
            assert!((k + 1..4).all(|l| q[k] != q[l]), "quad {qi} repeats a node");
            assert!(
                directed.insert((q[k], q[(k + 1) % 4]), qi).is_none(),
                "directed edge used twice"
            );
        }
    }
    for &([a, b], _) in &m.curve_edges {
        assert!(directed.contains_key(&(a, b)) || directed.contains_key(&(b, a)));
    }
    directed
        .keys()
        .filter(|(a, b)| !directed.contains_key(&(*b, *a)))
        .count()
}

/// Node positions of `m` as a sorted list of rounded coordinates.
fn rounded(nodes: &[Vec3]) -> Vec<[i64; 3]> {
    let mut v: Vec<[i64; 3]> = nodes
        .iter()
        .map(|p| p.map(|x| (x * 1e9).round() as i64))
        .collect();
    v.sort_unstable();
    v
}

#[test]
fn the_identity_layout_gives_back_the_input_quads_all_valid() {
    let cases = [
        mesh::fixtures::cube(1.0, 3),
        (
            primitives::cylinder(1.0, 2.0),
            default_mesh(&primitives::cylinder(1.0, 2.0), 1.0),
        ),
        (
            primitives::sphere(1.0),
            default_mesh(&primitives::sphere(1.0), 1.0),
        ),
    ];
    for (model, input) in &cases {
        let layout = BlockLayout::identity(input);
        let loops = QuadLoops::of(&layout);
        assert!(loops.width.iter().all(|&w| w == 1));
        let (fine, report) = fine_mesh(model, input, &layout, &loops).unwrap();
        assert_eq!(fine.mesh.quads.len(), input.quads.len());
        assert_eq!(fine.mesh.nodes.len(), input.nodes.len());
        assert_eq!(fine.mesh.curve_edges.len(), input.curve_edges.len());
        assert_eq!(fine.mesh.corner_nodes.len(), input.corner_nodes.len());
        assert_eq!(report.invalid_quads, 0, "{report:?}");
        assert!(report.min_sicn > 0.0);
        let sicn = quad_sicn_values(&fine.mesh, Some(model));
        assert!(sicn.iter().all(|&s| s > 0.0));
        // closed solids: no open edge
        assert_eq!(assert_conforming(&fine.mesh), 0);
        // each block's grid is its input quad, in the same corner order
        for (b, g) in fine.block_grid.iter().enumerate() {
            assert_eq!(g.size, [1, 1]);
            let q = fine.mesh.quads[g.first_quad as usize];
            assert_eq!(q, [g.at(0, 0), g.at(1, 0), g.at(1, 1), g.at(0, 1)]);
            assert_eq!(q, layout.blocks[b].corners);
        }
        // every node within 1e-9 of the diagonal of its CAD entity
        let d = mesh::stats::node_cad_distances(&fine.mesh, model);
        let tol = 1e-9 * model.diagonal();
        assert!(
            d.iter().all(|x| x.is_some_and(|x| x < tol)),
            "a node is off the CAD"
        );
    }
}

#[test]
fn blocks_of_an_8x8_grid_give_back_the_grid() {
    let (model, input, layout) = square_blocks(8, 4);
    let loops = QuadLoops::of(&layout);
    assert_eq!(loops.width, vec![4; 4]);
    let (fine, report) = fine_mesh(&model, &input, &layout, &loops).unwrap();
    assert_eq!(fine.mesh.nodes.len(), 81);
    assert_eq!(fine.mesh.quads.len(), 64);
    assert_eq!((report.invalid_quads, report.quads), (0, 64));
    assert!((report.min_sicn - 1.0).abs() < 1e-9, "{report:?}");
    // the same nodes (TFI of straight sides, Winslow's fixed point)
    assert_eq!(rounded(&fine.mesh.nodes), rounded(&input.nodes));
    // grid (i, j) of block (I, J) is input node (4I + i, 4J + j)
    for (b, g) in fine.block_grid.iter().enumerate() {
        let (bi, bj) = (b % 2, b / 2);
        assert_eq!(g.size, [4, 4]);
        for j in 0..=4 {
            for i in 0..=4 {
                let p = fine.mesh.nodes[g.at(i, j) as usize];
                let want = [(4 * bi + i) as f64 / 8.0, (4 * bj + j) as f64 / 8.0, 0.0];
                assert!(vec3::dist(p, want) < 1e-12, "{p:?} {want:?}");
            }
        }
    }
    assert_eq!(fine.mesh.curve_edges.len(), 32);
    assert_eq!(assert_conforming(&fine.mesh), 32);
    // layout vertices first: the corners are nodes 0, 2, 8, 6
    let corners: Vec<u32> = fine.mesh.corner_nodes.iter().map(|c| c.0).collect();
    assert_eq!(corners, vec![0, 2, 6, 8]);
}

#[test]
fn blocks_on_the_six_faces_of_a_cube_share_their_curve_edges() {
    let (model, input) = mesh::fixtures::cube(1.0, 6);
    let layout = structured_blocks(&input, 6, 3);
    layout.check(&input).unwrap();
    assert_eq!(
        (
            layout.blocks.len(),
            layout.edges.len(),
            layout.vertex_node.len()
        ),
        (24, 48, 26)
    );
    assert_eq!(
        layout.edges.iter().filter(|e| e.curve.is_some()).count(),
        24
    );
    let loops = QuadLoops::of(&layout);
    assert!(loops.width.iter().all(|&w| w == 3));
    let (fine, report) = fine_mesh(&model, &input, &layout, &loops).unwrap();
    assert_eq!(report.invalid_quads, 0);
    assert_eq!(rounded(&fine.mesh.nodes), rounded(&input.nodes));
    assert_eq!(assert_conforming(&fine.mesh), 0);
    assert_eq!(fine.mesh.curve_edges.len(), input.curve_edges.len());
    assert_eq!(fine.mesh.corner_nodes.len(), 8);
}

#[test]
fn widths_other_than_the_path_lengths_resample_the_edges_evenly() {
    let (model, input, layout) = square_blocks(8, 4);
    for w in [1, 2, 3, 6] {
        let mut loops = QuadLoops::of(&layout);
        loops.width = vec![w; loops.width.len()];
        let (fine, report) = fine_mesh(&model, &input, &layout, &loops).unwrap();
        let n = 2 * w;
        assert_eq!(fine.mesh.nodes.len(), (n + 1) * (n + 1));
        assert_eq!(report.invalid_quads, 0);
        // an even grid of the square: every node at a multiple of 1 / n
        let mut want = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                want.push([i as f64 / n as f64, j as f64 / n as f64, 0.0]);
            }
        }
        assert_eq!(rounded(&fine.mesh.nodes), rounded(&want), "width {w}");
        // curve nodes on their curve with their parameter
        for (p, c) in fine.mesh.nodes.iter().zip(&fine.mesh.node_class) {
            if let NodeClass::Curve(c, Some(t)) = *c {
                assert!(vec3::dist(model.curves[c.idx()].eval(&model, t), *p) < 1e-12);
            }
        }
    }
}

#[test]
fn a_ring_of_blocks_on_a_cylinder_stays_on_the_cylinder_across_its_seam() {
    let (r, h) = (1.0, 2.0);
    let (model, input, layout) = cylinder_ring(r, h, 24, 8, 4);
    let loops = QuadLoops::of(&layout);
    // the verticals form one loop around the ring
    assert_eq!(loops.len(), 5);
    let (fine, report) = fine_mesh(&model, &input, &layout, &loops).unwrap();
    assert_eq!(fine.mesh.nodes.len(), input.nodes.len());
    assert_eq!(fine.mesh.quads.len(), input.quads.len());
    assert_eq!(report.invalid_quads, 0, "{report:?}");
    // the regular grid again (TFI of the (u, v) sides, seam side included)
    assert_eq!(rounded(&fine.mesh.nodes), rounded(&input.nodes));
    for p in &fine.mesh.nodes {
        assert!((p[0].hypot(p[1]) - r).abs() < 1e-12 && p[2] > -1e-12 && p[2] < h + 1e-12);
    }
    assert_eq!(assert_conforming(&fine.mesh), 2 * 24);
}

#[test]
fn a_skewed_start_is_smoothed_into_valid_quads() {
    // widths 3 × 5 on a ring whose blocks are 6 × 4 input quads: the fine
    // grid differs from the input; its quads must come out valid and on the CAD
    let (model, input, layout) = cylinder_ring(1.0, 2.0, 24, 4, 4);
    let mut loops = QuadLoops::of(&layout);
    let vertical = loops.edge_loop[2] as usize;
    for (l, w) in loops.width.iter_mut().enumerate() {
        *w = if l == vertical { 5 } else { 3 };
    }
    let (fine, report) = fine_mesh(&model, &input, &layout, &loops).unwrap();
    assert_eq!(report.quads, 4 * 3 * 5);
    assert_eq!(report.invalid_quads, 0, "{report:?}");
    let d = mesh::stats::node_cad_distances(&fine.mesh, &model);
    assert!(d.iter().all(|x| x.is_some_and(|x| x < 1e-9)));
    for g in &fine.block_grid {
        assert_eq!(g.size, [3, 5]);
    }
}

/// Worst and average SICN of `m`'s quads.
fn quality(model: &Model, m: &QuadMesh) -> (f64, f64) {
    let s = quad_sicn_values(m, Some(model));
    (
        s.iter().copied().fold(f64::INFINITY, f64::min),
        s.iter().sum::<f64>() / s.len() as f64,
    )
}

#[test]
fn smoothing_straightens_wiggly_blocks_around_a_valence_3_vertex() {
    let (model, input, layout) = triangle_blocks(6, 0.7);
    layout.check(&input).unwrap();
    assert_eq!(
        (
            layout.blocks.len(),
            layout.edges.len(),
            layout.vertex_node.len()
        ),
        (3, 9, 7)
    );
    for w in [6, 9] {
        let mut loops = QuadLoops::of(&layout);
        loops.width = vec![w; loops.width.len()];
        let placed = place(&model, &input, &layout, &loops).unwrap();
        let before = quality(&model, &placed.mesh);
        let (fine, report) = fine_mesh(&model, &input, &layout, &loops).unwrap();
        let after = quality(&model, &fine.mesh);
        assert_eq!(report.invalid_quads, 0);
        assert!(
            after.0 >= before.0 && after.1 > before.1,
            "{before:?} → {after:?}"
        );
        assert!(after.0 > 0.5, "{after:?}");
        // the same topology: the centroid keeps its three quads
        assert_eq!(fine.mesh.quads, placed.mesh.quads);
        let centroid = (0..7)
            .find(|&v| matches!(fine.mesh.node_class[v], NodeClass::Face(..)))
            .unwrap();
        assert_eq!(fine.mesh.node_valences()[centroid], 3);
        // on the plane, inside the triangle, on the CAD
        for p in &fine.mesh.nodes {
            assert!(
                p[2].abs() < 1e-12
                    && p[1] > -1e-12
                    && p[1] <= 1.7 * (1.0 - (p[0] - 1.0).abs()) + 1e-9
            );
        }
        let d = mesh::stats::node_cad_distances(&fine.mesh, &model);
        assert!(d.iter().all(|x| x.is_some_and(|x| x < 1e-9)));
    }
}

#[test]
fn the_fine_and_high_order_meshes_do_not_depend_on_the_thread_count() {
    let model = primitives::sphere(1.0);
    let input = default_mesh(&model, 1.0);
    let layout = BlockLayout::identity(&input);
    let loops = QuadLoops::of(&layout);
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let (fine, _) = fine_mesh(&model, &input, &layout, &loops).unwrap();
            let (ho, _) = extract_high_order(&model, &layout, &fine, 3).unwrap();
            (fine.mesh.nodes, ho)
        })
    };
    let (a, b) = (run(1), run(3));
    assert!(a
        .0
        .iter()
        .zip(&b.0)
        .all(|(p, q)| p.map(f64::to_bits) == q.map(f64::to_bits)));
    assert_eq!(a.1, b.1);
}

#[test]
fn bad_layouts_and_loops_are_errors() {
    let (model, input, layout) = square_blocks(8, 4);
    let loops = QuadLoops::of(&layout);
    let mut broken = layout.clone();
    broken.blocks[0].corners.swap(0, 1);
    assert!(fine_mesh(&model, &input, &broken, &loops).is_err());
    let mut zero = loops.clone();
    zero.width[1] = 0;
    assert!(fine_mesh(&model, &input, &layout, &zero)
        .unwrap_err()
        .contains("width 0"));
    let other = QuadLoops::of(&square_blocks(8, 2).2);
    let e = fine_mesh(&model, &input, &layout, &other).unwrap_err();
    assert!(e.contains("quad loops"), "{e}");
    // a block on a face the model lacks
    let mut far = layout.clone();
    for b in &mut far.blocks {
        b.face = FaceId(7);
    }
    let mut m = input.clone();
    m.quad_face = vec![FaceId(7); m.quads.len()];
    assert!(fine_mesh(&model, &m, &far, &loops).is_err());
}

/// Prints the time of the fine mesh of about 30 000 quads (and of the
/// order-5 extraction of the identity layouts):
/// `cargo test -p quadrille --release fine_mesh_timing -- --ignored --nocapture`.
#[test]
#[ignore]
fn fine_mesh_timing() {
    for (name, model, f) in [
        ("cylinder", primitives::cylinder(1.0, 2.0), 0.19),
        ("sphere", primitives::sphere(1.0), 0.145),
    ] {
        let input = default_mesh(&model, f);
        let layout = BlockLayout::identity(&input);
        let loops = QuadLoops::of(&layout);
        let t = std::time::Instant::now();
        let (fine, report) = fine_mesh(&model, &input, &layout, &loops).unwrap();
        println!(
            "{name}: identity, {} quads: {:?} {report:?}",
            input.quads.len(),
            t.elapsed()
        );
        let t = std::time::Instant::now();
        let (_, ho) = extract_high_order(&model, &layout, &fine, 5).unwrap();
        println!(
            "{name}: order 5: {:?}, {} invalid, {} resampled, min ratio {}",
            t.elapsed(),
            ho.invalid_elements.len(),
            ho.resampled.len(),
            ho.min_jacobian_ratio
        );
    }
    // a ring of 8 blocks, 30 000 quads, each block's widths 4/5 of its input's, then equal
    let (model, input, layout) = cylinder_ring(1.0, 2.0, 240, 125, 8);
    for shrink in [true, false] {
        let mut loops = QuadLoops::of(&layout);
        if shrink {
            for w in &mut loops.width {
                *w = *w * 4 / 5;
            }
        }
        let t = std::time::Instant::now();
        let (_, report) = fine_mesh(&model, &input, &layout, &loops).unwrap();
        println!(
            "cylinder ring, {} quads: {:?} {report:?}",
            report.quads,
            t.elapsed()
        );
    }
}
