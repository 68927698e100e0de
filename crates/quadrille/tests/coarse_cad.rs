//! The coarse method on the bundled MAMBO models M1–M5 at the default size:
//! fewer blocks than input quads, almost every element valid with the CAD
//! normals at its nodes and Gauss points (a few thin input quads with a
//! folded curved edge are not, even one block per quad: measured, reported),
//! every node on the CAD, the elements conforming (each edge shared by two
//! elements with the same nodes, no open edge on these closed solids), every
//! CAD curve a chain of element edges, every CAD corner an element corner
//! with its input valence.

use std::collections::HashMap;
use std::path::Path;

use geometry::Model;
use mesh::high_order::HighOrderStats;
use mesh::{HighOrderQuadMesh, NodeClass, QuadMesh};
use quadrille::{mesh_coarse, CoarseOptions, MeshOptions};

fn load(name: &str) -> Model {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/cad").join(name);
    occt::load(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// The nodes of side `k` of element `e`, from corner `k` to corner `k + 1`.
fn side(ho: &HighOrderQuadMesh, e: usize, k: usize) -> Vec<u32> {
    let n = ho.order;
    (0..=n)
        .map(|s| match k {
            0 => ho.node_at(e, s, 0),
            1 => ho.node_at(e, n, s),
            2 => ho.node_at(e, n - s, n),
            _ => ho.node_at(e, 0, n - s),
        })
        .collect()
}

/// Conformity: every element side is used by exactly two elements, once in
/// each direction, with the same nodes.
fn check_conforming(ho: &HighOrderQuadMesh) {
    let mut uses: HashMap<Vec<u32>, usize> = HashMap::new();
    for e in 0..ho.num_elements() {
        for k in 0..4 {
            *uses.entry(side(ho, e, k)).or_insert(0) += 1;
        }
    }
    for (s, &n) in &uses {
        let back: Vec<u32> = s.iter().rev().copied().collect();
        assert_eq!(n, 1, "side {s:?} used {n} times in one direction");
        assert_eq!(uses.get(&back), Some(&1), "side {s:?} has no neighbour (open edge or T-junction)");
    }
}

/// Every curve edge is an element side; each CAD curve's edges chain end to
/// end, from corner to corner (or around, for a closed curve).
fn check_curves(ho: &HighOrderQuadMesh, model: &Model) {
    let mut sides: HashMap<Vec<u32>, ()> = HashMap::new();
    for e in 0..ho.num_elements() {
        for k in 0..4 {
            sides.insert(side(ho, e, k), ());
        }
    }
    let mut per_curve: HashMap<u32, Vec<[u32; 2]>> = HashMap::new();
    for k in 0..ho.num_curve_edges() {
        let nodes = ho.curve_edge(k).to_vec();
        let back: Vec<u32> = nodes.iter().rev().copied().collect();
        assert!(sides.contains_key(&nodes) || sides.contains_key(&back), "curve edge {k} is no element side");
        per_curve
            .entry(ho.curve_edge_curve[k].0)
            .or_default()
            .push([nodes[0], *nodes.last().unwrap()]);
    }
    for (c, ce) in model.curves.iter().enumerate() {
        if ce.degenerate {
            continue;
        }
        let edges = per_curve.get(&(c as u32)).unwrap_or_else(|| panic!("curve {c} has no element edge"));
        // a chain: every end node used twice, except the two ends of an open curve
        let mut count: HashMap<u32, usize> = HashMap::new();
        for &[a, b] in edges {
            *count.entry(a).or_insert(0) += 1;
            *count.entry(b).or_insert(0) += 1;
        }
        let ends = count.values().filter(|&&n| n == 1).count();
        assert!(count.values().all(|&n| n <= 2), "curve {c} branches");
        assert!(ends == 0 || ends == 2, "curve {c} is not one chain ({ends} ends)");
        assert_eq!(ends == 0, ce.start == ce.end, "curve {c}: closed chain iff closed curve");
    }
}

/// Every CAD corner is an element corner with as many elements as input quads.
fn check_corners(ho: &HighOrderQuadMesh, input: &QuadMesh) {
    for &(node, corner) in &input.corner_nodes {
        let input_quads = input.quads.iter().filter(|q| q.contains(&node)).count();
        let v = ho
            .corner_nodes
            .iter()
            .find(|&&(_, c)| c == corner)
            .unwrap_or_else(|| panic!("corner {} has no node", corner.0))
            .0;
        let elements = (0..ho.num_elements()).filter(|&e| ho.corners(e).contains(&v)).count();
        assert_eq!(elements, input_quads, "corner {} keeps its valence", corner.0);
    }
}

#[test]
fn mambo_models_give_valid_conforming_high_order_quads_on_the_cad() {
    for name in ["i01o_m1.step", "i02o_m2.step", "i03o_m3.step", "i04o_m4.step", "i05o_m5.step"] {
        let model = load(name);
        let diag = model.diagonal();
        for order in [2, 5] {
            let opts = CoarseOptions { order, ..CoarseOptions::default() };
            let mopts = MeshOptions { threads: Some(2), ..MeshOptions::default() };
            let (out, report) = mesh_coarse(&model, &mopts, &opts, None).expect(name);
            let ho = &out.high_order;
            assert!(!report.used_input_layout, "{name}: {:?}", report.geometry_notes);
            assert!(ho.num_elements() < out.input.quads.len(), "{name}: {} blocks", ho.num_elements());
            let s = HighOrderStats::compute(ho, Some(&model));
            assert!(s.invalid_elements * 200 <= s.elements, "{name} order {order}: {s:?}");
            assert!(s.max_node_cad_distance.unwrap() < 1e-6 * diag, "{name}: {s:?}");
            assert!(ho.node_class.iter().all(|c| !matches!(c, NodeClass::Unclassified)));
            check_conforming(ho);
            check_curves(ho, &model);
            check_corners(ho, &out.input);
        }
    }
}

#[test]
fn the_same_output_for_one_and_two_threads() {
    let model = load("i02o_m2.step");
    let run = |threads| {
        let mopts = MeshOptions { threads: Some(threads), ..MeshOptions::default() };
        mesh_coarse(&model, &mopts, &CoarseOptions::default(), None).unwrap().0.high_order
    };
    assert_eq!(run(1), run(2));
}
