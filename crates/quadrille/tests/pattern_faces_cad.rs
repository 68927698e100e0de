//! Simple CAD faces meshed directly by a pattern (paper §6.1.2) on two
//! bundled models: the share of faces it takes, and on each of those faces a
//! valid patch (every quad SICN ≥ the threshold, with CAD normals) whose
//! only irregular interior vertices are the pattern's own, whose boundary is
//! exactly the face's curve meshes, and whose Euler characteristic is 1.

use std::collections::{HashMap, HashSet};
use std::path::PathBuf;

use geometry::FaceId;
use quadrille::combinatorics::library;
use quadrille::core::quad_quality;
use quadrille::core::NodeRef;
use quadrille::curves::{discretize_all, plan_curves};
use quadrille::direct::HOLED_GRID;
use quadrille::direct::{mesh_face_pattern, MIN_PATTERN_SICN, O_GRID, PLAIN_GRID, PLAIN_MIN_SICN};

fn model(name: &str) -> geometry::Model {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../data/cad")
        .join(name);
    occt::load(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// Meshes every face it can; returns how many.
fn check_model(name: &str) -> (usize, usize) {
    let m = model(name);
    let h = quadrille::default_size(&m);
    let cms = discretize_all(&m, &plan_curves(&m, h));
    let mut by_pattern = 0;
    for f in 0..m.faces.len() {
        let Ok((patch, pattern)) = mesh_face_pattern(&m, FaceId(f as u32), &cms, true) else {
            continue;
        };
        by_pattern += 1;
        let face = &m.faces[f];
        // a plain grid's corner quads have a floor of their own
        let floor = if pattern == PLAIN_GRID { PLAIN_MIN_SICN } else { MIN_PATTERN_SICN };
        for q in &patch.quads {
            let s = quad_quality(face, &patch.nodes, &patch.pos, q);
            assert!(s >= floor, "{name} face {}: SICN {s}", f + 1);
        }
        // irregular interior vertices: exactly the pattern's
        let mut val = vec![0usize; patch.nodes.len()];
        let mut edges: HashMap<(u32, u32), usize> = HashMap::new();
        for q in &patch.quads {
            for k in 0..4 {
                val[q[k] as usize] += 1;
                let (a, b) = (q[k].min(q[(k + 1) % 4]), q[k].max(q[(k + 1) % 4]));
                *edges.entry((a, b)).or_default() += 1;
            }
        }
        // a holed grid has none (its hole's corners sit on the inner loop);
        // an O-grid the four corners of its middle grid
        let want = match pattern.as_str() {
            HOLED_GRID | PLAIN_GRID => 0,
            O_GRID => 4,
            _ => {
                library()
                    .iter()
                    .find(|p| p.name == pattern)
                    .unwrap()
                    .irregular
            }
        };
        let irregular = (0..patch.nodes.len())
            .filter(|&i| patch.nodes[i].node == NodeRef::Interior && val[i] != 4)
            .count();
        assert_eq!(irregular, want, "{name} face {} ({pattern})", f + 1);
        // Euler characteristic over the used nodes: 1 for a disk, one less per hole
        let used = val.iter().filter(|&&v| v > 0).count();
        assert_eq!(
            used as i64 - edges.len() as i64 + patch.quads.len() as i64,
            2 - face.loops.len() as i64,
            "{name} face {}",
            f + 1
        );
        // edges in one quad are the boundary: every curve point of the face's curves, no interior node
        let boundary: HashSet<u32> = edges
            .iter()
            .filter(|(_, &n)| n == 1)
            .flat_map(|(&(a, b), _)| [a, b])
            .collect();
        for &v in &boundary {
            assert_ne!(
                patch.nodes[v as usize].node,
                NodeRef::Interior,
                "{name} face {}: interior node on the boundary",
                f + 1
            );
        }
        // (a pole counts once: it is the end of the curve before it and the start of the one after)
        let expected: usize = face
            .loops
            .iter()
            .flat_map(|l| &l.uses)
            .map(|u| {
                if m.curves[u.curve.idx()].degenerate {
                    0
                } else {
                    cms[u.curve.idx()].params.len() - 1
                }
            })
            .sum();
        assert_eq!(
            boundary.len(),
            expected,
            "{name} face {}: boundary nodes",
            f + 1
        );
    }
    (by_pattern, m.faces.len())
}

#[test]
fn a_plate_with_one_round_hole_is_a_holed_grid() {
    // s11o_cube_cyl: the cube's top is a square around the cylinder's circle
    assert_eq!(check_model("s11o_cube_cyl.stp"), (8, 8));
    let m = model("s11o_cube_cyl.stp");
    let cms = discretize_all(&m, &plan_curves(&m, quadrille::default_size(&m)));
    let plate = (0..m.faces.len())
        .find(|&f| m.faces[f].loops.len() == 2)
        .expect("the plate face");
    let (patch, pattern) = mesh_face_pattern(&m, FaceId(plate as u32), &cms, true).expect("a pattern");
    assert_eq!(pattern, HOLED_GRID);
    // the curve planning takes the plate's opposite sides as chords
    let outer: Vec<usize> = m.faces[plate]
        .loops
        .iter()
        .find(|l| l.uses.len() == 4)
        .expect("the outer loop")
        .uses
        .iter()
        .map(|u| u.curve.idx())
        .collect();
    let pairs = quadrille::curves::opposite_pairs(&m);
    assert!(pairs.contains(&[outer[0], outer[2]]) && pairs.contains(&[outer[1], outer[3]]));
    // on the hole: four nodes on three quads, the others on two
    let mut val = vec![0usize; patch.nodes.len()];
    for q in &patch.quads {
        for &v in q {
            val[v as usize] += 1;
        }
    }
    let hole_curve = m.faces[plate]
        .loops
        .iter()
        .find(|l| l.uses.len() == 1)
        .expect("the hole")
        .uses[0]
        .curve;
    let on_hole: Vec<usize> = (0..patch.nodes.len())
        .filter(|&i| match patch.nodes[i].node {
            NodeRef::Curve(c, _) => c == hole_curve,
            NodeRef::Corner(k) => m.curves[hole_curve.idx()].start == k,
            NodeRef::Interior => false,
        })
        .collect();
    assert_eq!(on_hole.iter().filter(|&&i| val[i] == 3).count(), 4);
    assert_eq!(
        on_hole.iter().filter(|&&i| val[i] == 2).count(),
        on_hole.len() - 4
    );
}

#[test]
fn simple_faces_of_cad_models_are_meshed_by_patterns() {
    // the rounded cube: 18 rectangles (R1) and 8 sphere corners with a pole (T3)
    assert_eq!(check_model("s12o_cube_rounded_1.stp"), (26, 26));
    // a MAMBO part: every face with one loop
    let (n, total) = check_model("i01o_m1.step");
    assert_eq!(total, 42);
    assert!(n >= 38, "{n} faces by pattern");
}
