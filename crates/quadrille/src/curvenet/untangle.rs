//! Local untangling of a cycle's dense quads (issue 30): a sampled layout
//! (§6.4) whose Coons patches leave a few quads inverted, typically thin
//! quads beside a connector or a concave corner, or the network stage's
//! re-sampling with other interval counts. The free nodes (not on the
//! cycle's polyline, which is shared with the neighbours) around the
//! inverted quads are moved towards the mean of their edge neighbours, one
//! at a time, and a move is kept only when it raises the worst quality of
//! the node's quads; the region grows by a ring of quads every few rounds.
//! Deterministic: nodes are visited in index order.
//!
//! The caller judges the result (the moves never make a node's worst quad
//! worse, but need not make every quad valid) and places each moved node
//! (on a CAD surface: its closest point and normal there).

use std::collections::BTreeSet;

use geometry::vec3::{self, Vec3};

/// Rounds of moves before giving up.
const ROUNDS: usize = 24;

/// The region grows by one ring of quads every this many rounds.
const ROUNDS_PER_RING: usize = 4;

/// The region never grows past this many rings around the inverted quads.
const MAX_RINGS: usize = 5;

/// Fractions of the step to the neighbours' mean tried, largest first.
const STEPS: [f64; 3] = [1.0, 0.5, 0.25];

/// Moves the free nodes around the quads of quality ≤ 0 (see the module
/// docs) and returns how many such quads are left. `normals[v]`: the
/// normal the quality uses at node `v` (kept in step with `nodes` by
/// `place`, which maps a moved point to its position and normal);
/// `fixed[v]`: node `v` must not move; `quality`: a quad's quality from its
/// corners and their normals, valid when > 0.
pub fn untangle(
    nodes: &mut [Vec3],
    normals: &mut [Option<Vec3>],
    quads: &[[usize; 4]],
    fixed: &[bool],
    place: &dyn Fn(Vec3) -> (Vec3, Option<Vec3>),
    quality: &dyn Fn(&[Vec3; 4], [Option<Vec3>; 4]) -> f64,
) -> usize {
    let n = nodes.len();
    let mut node_quads: Vec<Vec<usize>> = vec![Vec::new(); n];
    let mut neighbours: Vec<BTreeSet<usize>> = vec![BTreeSet::new(); n];
    for (k, q) in quads.iter().enumerate() {
        for c in 0..4 {
            node_quads[q[c]].push(k);
            neighbours[q[c]].insert(q[(c + 1) % 4]);
            neighbours[q[c]].insert(q[(c + 3) % 4]);
        }
    }
    let quad_quality = |nodes: &[Vec3], normals: &[Option<Vec3>], k: usize| {
        let q = quads[k];
        quality(&q.map(|v| nodes[v]), q.map(|v| normals[v]))
    };
    let worst_at = |nodes: &[Vec3], normals: &[Option<Vec3>], v: usize| {
        node_quads[v]
            .iter()
            .map(|&k| quad_quality(nodes, normals, k))
            .fold(f64::INFINITY, f64::min)
    };
    let bad = |nodes: &[Vec3], normals: &[Option<Vec3>]| -> Vec<usize> {
        (0..quads.len())
            .filter(|&k| !(quad_quality(nodes, normals, k) > 0.0))
            .collect()
    };
    let mut left = bad(nodes, normals);
    for round in 0..ROUNDS {
        if left.is_empty() {
            break;
        }
        let mut region: BTreeSet<usize> = left.iter().flat_map(|&k| quads[k]).collect();
        for _ in 0..(1 + round / ROUNDS_PER_RING).min(MAX_RINGS) {
            let grown: BTreeSet<usize> = region
                .iter()
                .flat_map(|&v| node_quads[v].iter().flat_map(|&k| quads[k]))
                .collect();
            region = grown;
        }
        let mut moved = false;
        for &v in region.iter().filter(|&&v| !fixed[v]) {
            let Some(target) = mean(neighbours[v].iter().map(|&u| nodes[u])) else {
                continue;
            };
            let before = worst_at(nodes, normals, v);
            let (old, old_normal) = (nodes[v], normals[v]);
            for t in STEPS {
                let (p, normal) = place(vec3::lerp(old, target, t));
                nodes[v] = p;
                normals[v] = normal;
                if worst_at(nodes, normals, v) > before {
                    moved = true;
                    break;
                }
                nodes[v] = old;
                normals[v] = old_normal;
            }
        }
        left = bad(nodes, normals);
        if !moved && (1 + round / ROUNDS_PER_RING) >= MAX_RINGS {
            break;
        }
    }
    left.len()
}

/// The mean of the points, `None` for none.
fn mean(points: impl Iterator<Item = Vec3>) -> Option<Vec3> {
    let (sum, count) = points.fold(([0.0; 3], 0usize), |(s, c), p| (vec3::add(s, p), c + 1));
    (count > 0).then(|| vec3::scale(sum, 1.0 / count as f64))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The signed area of a quad in the xy-plane over its squared diameter:
    /// > 0 counter-clockwise.
    fn area_quality(p: &[Vec3; 4], _: [Option<Vec3>; 4]) -> f64 {
        let mut a = 0.0;
        for k in 0..4 {
            let (u, w) = (p[k], p[(k + 1) % 4]);
            a += u[0] * w[1] - w[0] * u[1];
        }
        let d = vec3::dist(p[0], p[2]).max(vec3::dist(p[1], p[3]));
        0.5 * a / (d * d)
    }

    /// A 4 × 4 grid of the unit square (25 nodes, 16 quads), counter-clockwise.
    fn grid() -> (Vec<Vec3>, Vec<[usize; 4]>, Vec<bool>) {
        let at = |i: usize, j: usize| j * 5 + i;
        let nodes: Vec<Vec3> = (0..25)
            .map(|v| [(v % 5) as f64 / 4.0, (v / 5) as f64 / 4.0, 0.0])
            .collect();
        let quads = (0..4)
            .flat_map(|j| {
                (0..4).map(move |i| [at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)])
            })
            .collect();
        let fixed = (0..25)
            .map(|v| v % 5 == 0 || v % 5 == 4 || v / 5 == 0 || v / 5 == 4)
            .collect();
        (nodes, quads, fixed)
    }

    /// An interior node pushed across its neighbours folds four quads (two
    /// of them inverted); untangling moves it back inside and every quad is
    /// valid; the boundary nodes do not move.
    #[test]
    fn a_node_pushed_across_its_neighbours_is_moved_back_and_no_quad_is_left_inverted() {
        let (mut nodes, quads, fixed) = grid();
        let start = nodes.clone();
        // node (1, 1) pushed past (2, 2)
        nodes[6] = [0.6, 0.6, 0.0];
        let mut normals = vec![None; nodes.len()];
        let inverted = quads
            .iter()
            .filter(|q| area_quality(&q.map(|v| nodes[v]), [None; 4]) <= 0.0)
            .count();
        assert!(inverted >= 1, "the test's fold inverts no quad");
        let left = untangle(
            &mut nodes,
            &mut normals,
            &quads,
            &fixed,
            &|p| (p, None),
            &area_quality,
        );
        assert_eq!(left, 0);
        assert!(quads
            .iter()
            .all(|q| area_quality(&q.map(|v| nodes[v]), [None; 4]) > 0.0));
        for v in (0..25).filter(|&v| fixed[v]) {
            assert_eq!(nodes[v], start[v]);
        }
        // node (1, 1) is back inside the cell of its four neighbours' square
        assert!(nodes[6][0] < 0.5 && nodes[6][1] < 0.5, "{:?}", nodes[6]);
    }

    /// `place` keeps every moved node where it puts it: a projection onto
    /// the plane z = 0 flattens a node lifted off it when it moves.
    #[test]
    fn moved_nodes_are_placed_by_the_callers_projection() {
        let (mut nodes, quads, fixed) = grid();
        nodes[12] = [0.9, 0.9, 0.3];
        let mut normals = vec![None; nodes.len()];
        let flat = |p: Vec3| ([p[0], p[1], 0.0], Some([0.0, 0.0, 1.0]));
        let left = untangle(
            &mut nodes,
            &mut normals,
            &quads,
            &fixed,
            &flat,
            &area_quality,
        );
        assert_eq!(left, 0);
        assert_eq!(nodes[12][2], 0.0);
        assert_eq!(normals[12], Some([0.0, 0.0, 1.0]));
    }

    /// When no quad is inverted nothing moves.
    #[test]
    fn a_valid_grid_is_left_as_it_is() {
        let (mut nodes, quads, fixed) = grid();
        let start = nodes.clone();
        let mut normals = vec![None; nodes.len()];
        assert_eq!(
            untangle(
                &mut nodes,
                &mut normals,
                &quads,
                &fixed,
                &|p| (p, None),
                &area_quality
            ),
            0
        );
        assert_eq!(nodes, start);
    }
}
