use super::growth::Role;
use super::work::Kind;
use super::*;
use crate::combinatorics::patterns::{library, match_pattern_where, refine};
use crate::core::patch::{LocalNode, NodeRef};
use crate::core::quality::quad_quality;
use crate::field::singularities::SingularitySite;
use geometry::vec3::{self, Vec3};
use geometry::{primitives, CornerId, CurveId};

/// An `n × n` grid on the unit square model's face (z = 0, uv = xy), with
/// the edge between cells `(i, j)` and `(i + 1, j)` rotated: its ends `b`,
/// `c` get valence 3, the new edge's ends `d`, `e` valence 5 (two +1/−1
/// pairs). Returns the patch and `[b, c, d, e]`.
fn rotated_grid(n: usize, i: usize, j: usize) -> (QuadPatch, [u32; 4]) {
    let id = |x: usize, y: usize| crate::fixtures::grids::grid_id(n, x, y);
    let mut p = crate::fixtures::grids::square_grid(n, |x, y| y == j && (x == i || x == i + 1));
    let (a, b, e) = (id(i, j), id(i + 1, j), id(i + 2, j));
    let (d, c, f) = (id(i, j + 1), id(i + 1, j + 1), id(i + 2, j + 1));
    p.quads.push([d, a, b, e]);
    p.quads.push([e, f, c, d]);
    // b down and c up, so that the two new quads are not flat at them
    let h = 0.3 / n as f64;
    for (v, dy) in [(b, -h), (c, h)] {
        p.nodes[v as usize].uv[1] += dy;
        p.pos[v as usize][1] += dy;
    }
    p.quad_tri = (0..p.quads.len() as u32).collect();
    (p, [b, c, d, e])
}

fn edge_key(a: u32, b: u32) -> (u32, u32) {
    (a.min(b), a.max(b))
}

fn valences(p: &QuadPatch) -> Vec<usize> {
    p.valences()
}

fn inner_irregular(p: &QuadPatch) -> usize {
    p.interior_irregular()
}

fn assert_valid_disk(face: &Face, p: &QuadPatch) {
    for q in &p.quads {
        assert!(
            quad_quality(face, &p.nodes, &p.pos, q) > 0.0,
            "quad {q:?} invalid"
        );
    }
    let val = valences(p);
    let used = val.iter().filter(|&&k| k > 0).count() as i64;
    let mut edges = std::collections::BTreeSet::new();
    for q in &p.quads {
        for k in 0..4 {
            edges.insert(edge_key(q[k], q[(k + 1) % 4]));
        }
    }
    assert_eq!(
        used - edges.len() as i64 + p.quads.len() as i64,
        1,
        "Euler characteristic of a disk"
    );
}

fn snapshot(
    p: &QuadPatch,
) -> (
    Vec<[u32; 4]>,
    Vec<u32>,
    Vec<[f64; 2]>,
    Vec<[f64; 3]>,
    Vec<NodeRef>,
) {
    (
        p.quads.clone(),
        p.quad_tri.clone(),
        p.nodes.iter().map(|n| n.uv).collect(),
        p.pos.clone(),
        p.nodes.iter().map(|n| n.node).collect(),
    )
}

fn singularity(index: i32, position: Vec3) -> Singularity {
    Singularity {
        index,
        position,
        site: SingularitySite::Vertex(0),
        size: None,
    }
}

#[test]
fn step_one_makes_a_grid_with_two_pairs_fully_regular() {
    let model = primitives::square(1.0);
    let face = &model.faces[0];
    assert_eq!(
        face.surface.eval([0.25, 0.5]),
        [0.25, 0.5, 0.0],
        "the test assumes uv = xy"
    );
    let n = 8;
    let (mut p, [b, c, d, e]) = rotated_grid(n, 3, 3);
    let val = valences(&p);
    assert_eq!(
        [
            val[b as usize],
            val[c as usize],
            val[d as usize],
            val[e as usize]
        ],
        [3, 3, 5, 5]
    );
    assert_valid_disk(face, &p);
    let boundary_before: Vec<(usize, [f64; 3])> = (0..p.nodes.len())
        .filter(|&v| p.nodes[v].node != NodeRef::Interior)
        .map(|v| (v, p.pos[v]))
        .collect();
    let opts = CavityOptions {
        steps: [true, false, false, false],
        ..Default::default()
    };
    let r = remesh_cavities(face, &mut p, &[], &opts);
    assert_eq!(r.irregular_before, 4);
    assert_eq!(r.irregular_after, 0, "{r:?}");
    assert!(r.replaced[0] >= 1, "{r:?}");
    assert_eq!(inner_irregular(&p), 0);
    assert_eq!(
        p.quads.len(),
        n * n,
        "a regular disk with sides n is the n × n grid"
    );
    assert_eq!(p.quad_tri.len(), p.quads.len());
    assert_valid_disk(face, &p);
    // the face boundary did not move
    for (v, x) in boundary_before {
        assert_eq!(p.pos[v], x);
    }
}

#[test]
fn a_singular_vertex_is_never_removed() {
    let model = primitives::square(1.0);
    let face = &model.faces[0];
    let (mut p, [b, _, _, _]) = rotated_grid(8, 3, 3);
    // a cross-field singularity of index +1 right at b (valence 3)
    let sing = [singularity(1, p.pos[b as usize])];
    let opts = CavityOptions {
        steps: [true, false, true, true],
        ..Default::default()
    };
    let r = remesh_cavities(face, &mut p, &sing, &opts);
    assert_eq!(r.singular, 1);
    assert_eq!(valences(&p)[b as usize], 3, "{r:?}");
    assert!(r.irregular_after >= 1);
    assert_valid_disk(face, &p);
    // far away, the singularity flags nothing and Step 1 regularizes everything
    let (mut q, _) = rotated_grid(8, 3, 3);
    let far = [singularity(1, [5.0, 5.0, 0.0])];
    let r = remesh_cavities(face, &mut q, &far, &opts);
    assert_eq!((r.singular, r.irregular_after), (0, 0), "{r:?}");
}

#[test]
fn a_singularity_a_little_farther_away_is_matched_late_in_size_map_units() {
    let model = primitives::square(1.0);
    let face = &model.faces[0];
    // steps off: only the matching runs
    let opts = CavityOptions {
        steps: [false; 4],
        ..Default::default()
    };
    let cell = 1.0 / 8.0;
    // a +1 singularity `k` cells below b (valence 3; c, the other valence-3
    // vertex, is 1.6 cells above b), the size map there one cell
    let flagged = |k: f64| {
        let (mut p, [b, _, _, _]) = rotated_grid(8, 3, 3);
        let x = p.pos[b as usize];
        let mut s = singularity(1, [x[0], x[1] - k * cell, 0.0]);
        s.size = Some(cell);
        remesh_cavities(face, &mut p, &[s], &opts).singular
    };
    // within MATCH_RADIUS, within LATE_MATCH_RADIUS, beyond both
    assert_eq!(flagged(1.5), 1);
    assert_eq!(flagged(2.5), 1);
    assert_eq!(flagged(3.5), 0);
}

/// Rotates the edge shared by quads `q1` and `q2` of `p` (see
/// [`rotated_grid`]) and moves its old ends apart along it by 0.3 of its
/// length, so that the new quads are not flat.
fn rotate_edge(p: &mut QuadPatch, q1: usize, q2: usize) {
    let (a, b) = (p.quads[q1], p.quads[q2]);
    // q1 = [a, x, y, d] with x → y the shared edge, q2 = [x, e, f, y]
    let k = (0..4)
        .find(|&k| b.contains(&a[k]) && b.contains(&a[(k + 1) % 4]))
        .expect("a shared edge");
    let r1 = [a[(k + 3) % 4], a[k], a[(k + 1) % 4], a[(k + 2) % 4]];
    let (x, y) = (r1[1], r1[2]);
    let m = b.iter().position(|&v| v == x).unwrap();
    let r2 = [b[m], b[(m + 1) % 4], b[(m + 2) % 4], b[(m + 3) % 4]];
    assert_eq!(r2[3], y);
    let (d, e, f) = (r1[3], r2[1], r2[2]);
    p.quads[q1] = [d, r1[0], x, e];
    p.quads[q2] = [e, f, y, d];
    let (px, py) = (p.nodes[x as usize].uv, p.nodes[y as usize].uv);
    let t = [0.3 * (py[0] - px[0]), 0.3 * (py[1] - px[1])];
    for (v, s) in [(x, -1.0), (y, 1.0)] {
        let n = &mut p.nodes[v as usize];
        n.uv = [n.uv[0] + s * t[0], n.uv[1] + s * t[1]];
        p.pos[v as usize] = [n.uv[0], n.uv[1], 0.0];
    }
}

#[test]
fn step_two_absorbs_two_pairs_into_a_pentagon_singularity() {
    let model = primitives::square(1.0);
    let face = &model.faces[0];
    // the refined pentagon P5 (8 edges per side) on the unit square, one valence-5 centre
    let p5 = library().iter().find(|p| p.name == "P5").unwrap();
    let r = refine(p5, &[4; 5]);
    let mut p = QuadPatch::default();
    let on_boundary: Vec<bool> = (0..r.coords.len() as u32)
        .map(|v| r.boundary.contains(&v))
        .collect();
    for (v, c) in r.coords.iter().enumerate() {
        let uv = [0.5 + 0.45 * c[0], 0.5 + 0.45 * c[1]];
        let node = if !on_boundary[v] {
            NodeRef::Interior
        } else if r.corners.iter().any(|&k| r.boundary[k] == v as u32) {
            NodeRef::Corner(CornerId(v as u32))
        } else {
            NodeRef::Curve(CurveId(0), v as u32)
        };
        p.nodes.push(LocalNode {
            uv,
            node,
            pole: None,
        });
        p.pos.push([uv[0], uv[1], 0.0]);
    }
    p.quads = r.quads.clone();
    p.quad_tri = (0..p.quads.len() as u32).collect();
    let val = valences(&p);
    let centre = (0..p.nodes.len())
        .find(|&v| !on_boundary[v] && val[v] == 5)
        .unwrap() as u32;
    assert_eq!(inner_irregular(&p), 1);
    assert_valid_disk(face, &p);
    // rotate an edge two to three edge lengths from the centre, away from it and the boundary
    let h = 0.45 / 4.0 * 0.5;
    let c = p.pos[centre as usize];
    let interior_quad = |q: &[u32; 4]| q.iter().all(|&v| !on_boundary[v as usize] && v != centre);
    let mut pick = None;
    'find: for q1 in 0..p.quads.len() {
        for q2 in q1 + 1..p.quads.len() {
            let (a, b) = (p.quads[q1], p.quads[q2]);
            let shared: Vec<u32> = a.iter().copied().filter(|v| b.contains(v)).collect();
            if shared.len() != 2
                || !interior_quad(&a)
                || !interior_quad(&b)
                || a.iter().chain(&b).any(|&v| val[v as usize] != 4)
            {
                continue;
            }
            let mid = vec3::scale(
                vec3::add(p.pos[shared[0] as usize], p.pos[shared[1] as usize]),
                0.5,
            );
            let dist = vec3::dist(mid, c);
            if dist > 2.0 * h && dist < 3.5 * h {
                pick = Some((q1, q2));
                break 'find;
            }
        }
    }
    let (q1, q2) = pick.expect("an edge near the centre");
    rotate_edge(&mut p, q1, q2);
    assert_eq!(inner_irregular(&p), 5);
    assert_valid_disk(face, &p);
    let sing = [singularity(-1, c)];
    let opts = CavityOptions {
        steps: [false, true, false, false],
        ..Default::default()
    };
    let rep = remesh_cavities(face, &mut p, &sing, &opts);
    assert_eq!(rep.singular, 1);
    assert!(rep.replaced[1] >= 1, "{rep:?}");
    assert_eq!(rep.irregular_after, 1, "{rep:?}");
    let val = valences(&p);
    let left: Vec<usize> = (0..p.nodes.len())
        .filter(|&v| p.nodes[v].node == NodeRef::Interior && val[v] > 0 && val[v] != 4)
        .map(|v| val[v])
        .collect();
    assert_eq!(left, vec![5], "only the singularity is left");
    assert_valid_disk(face, &p);
}

#[test]
fn a_rejected_replacement_leaves_the_patch_bit_identical() {
    // on the reversed face every quad is inverted, so no replacement can be valid
    let mut model = primitives::square(1.0);
    model.faces[0].reversed = true;
    let face = &model.faces[0];
    let (mut p, _) = rotated_grid(8, 3, 3);
    let before = snapshot(&p);
    let r = remesh_cavities(face, &mut p, &[], &CavityOptions::default());
    assert_eq!(r.replaced, [0; 4], "{r:?}");
    assert!(r.rejected >= 1, "{r:?}");
    assert_eq!(before, snapshot(&p));
}

#[test]
fn the_work_cap_stops_early_and_bad_input_is_refused() {
    let model = primitives::square(1.0);
    let face = &model.faces[0];
    let (mut p, _) = rotated_grid(8, 3, 3);
    let before = snapshot(&p);
    let r = remesh_cavities(
        face,
        &mut p,
        &[],
        &CavityOptions {
            max_work: Some(0),
            ..Default::default()
        },
    );
    assert!(r.capped);
    assert_eq!(r.replaced, [0; 4]);
    assert_eq!(before, snapshot(&p));
    // a quad on a missing node: nothing happens, no panic
    let (mut bad, _) = rotated_grid(4, 1, 1);
    bad.quads.push([0, 1, 2, 999]);
    bad.quad_tri.push(0);
    let r = remesh_cavities(face, &mut bad, &[], &CavityOptions::default());
    assert_eq!(r, CavityReport::default());
}

#[test]
fn patterns_are_filtered_by_target() {
    let grid = library().iter().find(|p| p.name == "R1").unwrap();
    let r3 = library().iter().find(|p| p.name == "R3").unwrap();
    let t3 = library().iter().find(|p| p.name == "T3").unwrap();
    assert!(Target::Grid.keeps(grid) && !Target::Grid.keeps(r3));
    assert!(Target::Rect.keeps(grid) && Target::Rect.keeps(r3) && !Target::Rect.keeps(t3));
    assert!(Target::Star(3).keeps(t3) && !Target::Star(5).keeps(t3));
    // sides 10, 4, 8, 6 match R3 but not the grid
    assert!(match_pattern_where(&[10, 4, 8, 6], |p| Target::Grid.keeps(p)).is_none());
    assert!(match_pattern_where(&[10, 4, 8, 6], |p| Target::Rect.keeps(p)).is_some());
}

/// A fan of `n` quads around a CAD corner at the origin spanning 270° (kites
/// between radius 1 and 1.4), on the unit square's face: the corner's
/// angle asks for 3 quads.
fn concave_corner_fan(n: usize) -> QuadPatch {
    let mut p = QuadPatch::default();
    let mut add = |x: f64, y: f64, node: NodeRef| {
        p.nodes.push(LocalNode {
            uv: [x, y],
            node,
            pole: None,
        });
        p.pos.push([x, y, 0.0]);
        (p.nodes.len() - 1) as u32
    };
    let corner = add(0.0, 0.0, NodeRef::Corner(CornerId(0)));
    let step = 1.5 * std::f64::consts::PI / n as f64;
    let rim: Vec<u32> = (0..=n)
        .map(|k| {
            let a = k as f64 * step;
            let node = if k == 0 || k == n {
                NodeRef::Curve(CurveId(0), k as u32)
            } else {
                NodeRef::Interior
            };
            add(a.cos(), a.sin(), node)
        })
        .collect();
    let outer: Vec<u32> = (0..n)
        .map(|k| {
            let a = (k as f64 + 0.5) * step;
            add(1.4 * a.cos(), 1.4 * a.sin(), NodeRef::Interior)
        })
        .collect();
    for k in 0..n {
        p.quads.push([corner, rim[k], outer[k], rim[k + 1]]);
    }
    p.quad_tri = (0..n as u32).collect();
    p
}

#[test]
fn a_concave_corner_with_a_quad_too_many_may_give_one_back() {
    let model = primitives::square(1.0);
    let face = &model.faces[0];
    // four quads where the 270° corner asks for three
    let mut p = concave_corner_fan(4);
    let mut w = Work::new(face, &mut p);
    assert_eq!(w.kind[0], Kind::Bound(3));
    assert!(w.sheds_a_quad(0, 3));
    // three of its quads in a cavity: a side vertex of the pattern (2 quads
    // come back), and the fourth may not join (no quad left outside)
    w.stamp += 1;
    w.mark(&[0, 1]);
    assert_eq!(w.role(0), Role::Flat);
    assert!(!w.forbidden(2, None));
    w.stamp += 1;
    w.mark(&[0, 1, 2]);
    assert_eq!(w.role(0), Role::Flat);
    assert!(w.forbidden(3, None));
    // with three quads, its ideal, the corner keeps at most two in a cavity
    let mut p = concave_corner_fan(3);
    let mut w = Work::new(face, &mut p);
    assert_eq!(w.kind[0], Kind::Bound(3));
    assert!(!w.sheds_a_quad(0, 3));
    w.stamp += 1;
    w.mark(&[0, 1]);
    assert!(w.forbidden(2, None));
}
