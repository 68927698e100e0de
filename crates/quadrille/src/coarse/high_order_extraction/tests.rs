use super::*;
use crate::coarse::fine_mesh::fine_mesh;
use crate::coarse::quad_loops::QuadLoops;
use crate::fixtures::layouts::{cylinder_ring, square_blocks, structured_blocks, triangle_blocks};
use crate::{mesh_model_with, MeshMethod, MeshOptions, Size};
use geometry::{primitives, CurveId};
use mesh::QuadMesh;

/// The default method's mesh of `model` at size factor `f`, one thread.
fn default_mesh(model: &Model, f: f64) -> QuadMesh {
    let opts = MeshOptions {
        size: Size::Factor(f),
        threads: Some(1),
        ..Default::default()
    };
    mesh_model_with(model, &opts, MeshMethod::default())
        .unwrap()
        .0
}

/// The fine mesh and order-`n` mesh of `layout` on `input`.
fn high_order(
    model: &Model,
    input: &QuadMesh,
    layout: &BlockLayout,
    n: usize,
) -> (FineMesh, HighOrderQuadMesh, HighOrderReport) {
    let loops = QuadLoops::of(layout);
    let (fine, _) = fine_mesh(model, input, layout, &loops).unwrap();
    let (ho, report) = extract_high_order(model, layout, &fine, n).unwrap();
    (fine, ho, report)
}

/// Checks the shape of `ho`: `(N + 1)²` nodes per element, shared corner
/// and edge nodes between neighbours (each element edge's nodes the
/// reverse of its neighbour's), curve edges end to end.
fn assert_conforming(ho: &HighOrderQuadMesh) {
    let n = ho.order;
    assert_eq!(
        ho.element_nodes.len(),
        ho.num_elements() * (n + 1) * (n + 1)
    );
    assert_eq!(ho.node_class.len(), ho.nodes.len());
    let mut sides: std::collections::BTreeMap<(u32, u32), Vec<u32>> = Default::default();
    for e in 0..ho.num_elements() {
        let side = |k: usize| -> Vec<u32> {
            (0..=n)
                .map(|t| match k {
                    0 => ho.node_at(e, t, 0),
                    1 => ho.node_at(e, n, t),
                    2 => ho.node_at(e, n - t, n),
                    _ => ho.node_at(e, 0, n - t),
                })
                .collect()
        };
        for k in 0..4 {
            let s = side(k);
            assert!(
                sides.insert((s[0], s[n]), s).is_none(),
                "element side used twice in one direction"
            );
        }
    }
    for ((a, b), s) in &sides {
        if let Some(t) = sides.get(&(*b, *a)) {
            let mut r = t.clone();
            r.reverse();
            assert_eq!(&r, s, "neighbours disagree on the nodes of edge {a}–{b}");
        }
    }
    for k in 0..ho.num_curve_edges() {
        let c = ho.curve_edge(k);
        assert!(sides.contains_key(&(c[0], c[n])) || sides.contains_key(&(c[n], c[0])));
    }
}

#[test]
fn identity_layouts_give_one_valid_element_per_quad() {
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
        for n in [2, 5] {
            let (fine, ho, report) = high_order(model, input, &layout, n);
            assert_eq!(ho.num_elements(), input.quads.len());
            assert!(report.invalid_elements.is_empty(), "N = {n}: {report:?}");
            // (u, v) interpolation alone crowds the inner nodes of the
            // sphere's elements at its poles (a ratio of 0.17 there)
            assert!(report.min_jacobian_ratio > 0.3, "N = {n}: {report:?}");
            assert!(
                report.max_cad_distance < 1e-9 * model.diagonal(),
                "{report:?}"
            );
            // each element's corners are its block's, the fine mesh's nodes there
            for (e, b) in layout.blocks.iter().enumerate() {
                assert_eq!(ho.corners(e), b.corners);
                for &v in &b.corners {
                    assert_eq!(ho.nodes[v as usize], fine.mesh.nodes[v as usize]);
                }
            }
            assert_eq!(ho.num_curve_edges(), input.curve_edges.len());
            assert_eq!(ho.corner_nodes.len(), input.corner_nodes.len());
            // nodes: vertices, N − 1 per edge, (N − 1)² per element
            let want = layout.vertex_node.len()
                + (n - 1) * layout.edges.len()
                + (n - 1) * (n - 1) * layout.blocks.len();
            assert_eq!(ho.nodes.len(), want);
            assert_conforming(&ho);
        }
    }
}

#[test]
fn blocks_of_a_planar_grid_are_affine_elements() {
    let (model, input, layout) = square_blocks(8, 4);
    for n in [1, 2, 3, 5, 10] {
        let (_, ho, report) = high_order(&model, &input, &layout, n);
        assert_eq!(ho.num_elements(), 4);
        assert_eq!(ho.nodes.len(), (2 * n + 1) * (2 * n + 1));
        // constant det J: the ratio is 1
        assert!(
            (report.min_jacobian_ratio - 1.0).abs() < 1e-9,
            "N = {n}: {report:?}"
        );
        assert!(report.resampled.is_empty() && report.invalid_elements.is_empty());
        // node (i, j) of element (I, J) at ((N I + i) / 2N, (N J + j) / 2N), on the plane
        for e in 0..4 {
            let (bi, bj) = (e % 2, e / 2);
            for j in 0..=n {
                for i in 0..=n {
                    let p = ho.nodes[ho.node_at(e, i, j) as usize];
                    let want = [
                        (n * bi + i) as f64 / (2 * n) as f64,
                        (n * bj + j) as f64 / (2 * n) as f64,
                        0.0,
                    ];
                    assert!(vec3::dist(p, want) < 1e-12, "N = {n}: {p:?} {want:?}");
                }
            }
        }
        assert_eq!(ho.num_curve_edges(), 8);
        assert_eq!(ho.corner_nodes.len(), 4);
        assert_conforming(&ho);
    }
}

#[test]
fn a_cube_of_blocks_gives_affine_elements_meeting_on_its_edges() {
    let (model, input) = mesh::fixtures::cube(1.0, 6);
    let layout = structured_blocks(&input, 6, 3);
    for n in [2, 3, 5] {
        let (_, ho, report) = high_order(&model, &input, &layout, n);
        assert_eq!(ho.num_elements(), 24);
        // a closed grid of 2N × 2N per face
        assert_eq!(ho.nodes.len(), 6 * 4 * n * n + 2);
        assert!((report.min_jacobian_ratio - 1.0).abs() < 1e-9, "{report:?}");
        assert!(report.max_cad_distance < 1e-12);
        // every node on the lattice of step 1 / 2N
        for p in &ho.nodes {
            for x in p {
                let s = x * (2 * n) as f64;
                assert!((s - s.round()).abs() < 1e-9, "{p:?}");
            }
        }
        assert_eq!(ho.num_curve_edges(), 24);
        assert_conforming(&ho);
        // closed: every element side has its neighbour's reverse
        let mut count = std::collections::BTreeMap::new();
        for e in 0..ho.num_elements() {
            let c = ho.corners(e);
            for k in 0..4 {
                *count
                    .entry((c[k].min(c[(k + 1) % 4]), c[k].max(c[(k + 1) % 4])))
                    .or_insert(0) += 1;
            }
        }
        assert!(count.values().all(|&v| v == 2));
    }
}

#[test]
fn curve_edge_nodes_of_a_cylinder_lie_on_its_circles_and_seam() {
    let (r, h) = (2.0, 3.0);
    let (model, input, layout) = cylinder_ring(r, h, 24, 6, 4);
    for n in [2, 5, 7] {
        let (_, ho, report) = high_order(&model, &input, &layout, n);
        assert!(report.invalid_elements.is_empty(), "{report:?}");
        assert!(report.min_jacobian_ratio > 0.0);
        assert_eq!(ho.num_curve_edges(), 9);
        for k in 0..ho.num_curve_edges() {
            let c = ho.curve_edge_curve[k];
            for &v in ho.curve_edge(k) {
                let p = ho.nodes[v as usize];
                if c == CurveId(2) {
                    // the seam: the line x = r, y = 0
                    assert!(
                        (p[0] - r).abs() < 1e-9 * r && p[1].abs() < 1e-9 * r,
                        "{p:?}"
                    );
                } else {
                    let z = if c == CurveId(0) { 0.0 } else { h };
                    assert!((p[0].hypot(p[1]) - r).abs() < 1e-9 * r, "{p:?}");
                    assert!((p[2] - z).abs() < 1e-9 * r);
                }
            }
        }
        // every node on the cylinder; the circle edges' nodes evenly spread (90° edges)
        for p in &ho.nodes {
            assert!((p[0].hypot(p[1]) - r).abs() < 1e-9 * r);
        }
        let k = (0..ho.num_curve_edges())
            .find(|&k| ho.curve_edge_curve[k] == CurveId(0))
            .unwrap();
        let e = ho.curve_edge(k);
        let step = |a: u32, b: u32| vec3::dist(ho.nodes[a as usize], ho.nodes[b as usize]);
        for w in e.windows(3) {
            assert!(
                (step(w[0], w[1]) - step(w[1], w[2])).abs() < 1e-6,
                "uneven circle edge"
            );
        }
        assert_conforming(&ho);
    }
}

#[test]
fn wiggly_blocks_around_a_valence_3_vertex_give_valid_elements() {
    let (model, input, layout) = triangle_blocks(6, 0.7);
    for n in [2, 5, 10] {
        let (_, ho, report) = high_order(&model, &input, &layout, n);
        assert_eq!(ho.num_elements(), 3);
        assert!(report.invalid_elements.is_empty(), "N = {n}: {report:?}");
        assert!(report.min_jacobian_ratio > 0.2, "N = {n}: {report:?}");
        assert!(ho.nodes.iter().all(|p| p[2].abs() < 1e-12));
        assert_conforming(&ho);
    }
}

#[test]
fn an_inverted_element_is_resampled_from_its_fine_grid() {
    let (model, input, layout) = square_blocks(8, 4);
    let loops = QuadLoops::of(&layout);
    let (fine, _) = fine_mesh(&model, &input, &layout, &loops).unwrap();
    let n = 4;
    let patches = face_patches(&model, &fine.mesh).unwrap();
    let ctx = Ctx {
        model: &model,
        layout: &layout,
        fine: &fine,
        corners: quad_corner_nodes(&patches, fine.mesh.quads.len()),
        n,
        tol: 1e-12,
    };
    let mut ho = HighOrderQuadMesh {
        order: n,
        nodes: fine.mesh.nodes[..9].to_vec(),
        node_class: fine.mesh.node_class[..9].to_vec(),
        ..Default::default()
    };
    let chains = ctx.edges(&mut ho).unwrap();
    let mut el = ctx.element(&ho, &chains.nodes, &chains.samples, 3).unwrap();
    let diff = LagrangeDiff::new(n);
    assert!((ctx.jacobian_ratio(3, &el, &diff) - 1.0).abs() < 1e-9);
    let good: Vec<Vec3> = el.pos.clone();
    // fold the element: an inner node pulled past its neighbours
    let at = 6; // node (1, 1)
    el.pos[at] = [0.9, 0.9, 0.0];
    assert!(ctx.jacobian_ratio(3, &el, &diff) < 0.0);
    ctx.resample_inner(3, &mut el);
    assert!((ctx.jacobian_ratio(3, &el, &diff) - 1.0).abs() < 1e-9);
    for (p, q) in el.pos.iter().zip(&good) {
        assert!(vec3::dist(*p, *q) < 1e-12);
    }
}

#[test]
fn lagrange_derivatives_are_exact_for_polynomials_of_the_order() {
    for n in 1..=MAX_ORDER {
        let d = LagrangeDiff::new(n);
        let x = |m: usize| m as f64 / n as f64;
        for a in 0..=n {
            // d/dx of x^n at x_a: n x_a^(n−1)
            let got: f64 = (0..=n)
                .map(|i| d.d[a * (n + 1) + i] * x(i).powi(n as i32))
                .sum();
            let want = n as f64 * x(a).powi(n as i32 - 1);
            assert!(
                (got - want).abs() < 1e-7 * (1.0 + want.abs()),
                "N = {n}, a = {a}: {got} {want}"
            );
            // constants have no derivative
            let c: f64 = (0..=n).map(|i| d.d[a * (n + 1) + i]).sum();
            assert!(c.abs() < 1e-7);
        }
    }
}

#[test]
fn orders_out_of_range_and_foreign_fine_meshes_are_errors() {
    let (model, input, layout) = square_blocks(8, 4);
    let loops = QuadLoops::of(&layout);
    let (fine, _) = fine_mesh(&model, &input, &layout, &loops).unwrap();
    for n in [0, MAX_ORDER + 1] {
        let e = extract_high_order(&model, &layout, &fine, n).unwrap_err();
        assert!(e.contains("order"), "{e}");
    }
    let (_, _, other) = square_blocks(8, 2);
    assert!(extract_high_order(&model, &other, &fine, 2).is_err());
}
