use super::*;
use crate::shell::tests::{grid, holed_grid};

#[test]
fn a_cone_walled_in_by_other_cones_is_unreachable() {
    let shell = grid(4, |x, y| [x, y, 0.0]);
    let topo = shell.check().unwrap();
    // Vertex 12 is (2, 2); all its neighbours are interior cones too.
    let mut cones = vec![Cone {
        vertex: 12,
        index: 1,
    }];
    for &[a, b] in &topo.edges {
        if a == 12 || b == 12 {
            cones.push(Cone {
                vertex: a + b - 12,
                index: -1,
            });
        }
    }
    let err = cut_to_disk(&shell, &topo, &cones).unwrap_err();
    assert_eq!(
        err,
        CutError::Unreachable {
            what: "the cone on vertex 12".into(),
            position: [0.5, 0.5, 0.0]
        }
    );
}

#[test]
fn a_disk_with_one_interior_cone_gets_one_cut_to_it() {
    let shell = grid(4, |x, y| [x, y, 0.0]);
    let topo = shell.check().unwrap();
    let cones = [Cone {
        vertex: 12,
        index: 1,
    }];
    let cut = cut_to_disk(&shell, &topo, &cones).unwrap();
    assert_eq!(cut.branches.len(), 1);
    let path = &cut.branches[0].vertices;
    // From the boundary to the cone, two edges long (the grid's nearest side).
    assert_eq!(path.len(), 3);
    assert!(topo.on_boundary[path[0]] && path[2] == 12);
    assert_eq!(cut.is_cut.iter().filter(|&&c| c).count(), 2);
    // The path's inner vertex gets two children, the cone one, the boundary end two.
    let children = |v: usize| cut.parent.iter().filter(|&&p| p == v).count();
    assert_eq!(
        (children(path[0]), children(path[1]), children(12)),
        (2, 2, 1)
    );
    assert_eq!(cut.parent.len(), shell.vertices.len() + 2);
    assert_eq!(cut.euler, 1);
    // One β with two sides whose children differ except at the cone.
    assert_eq!(cut.paths.len(), 1);
    let beta = &cut.paths[0];
    assert_eq!(beta.sides.len(), 2);
    for s in &beta.sides {
        assert_ne!(s.left[0], s.right[0]);
    }
    let last = beta.sides.last().unwrap();
    let cone_end = if *beta.vertices.last().unwrap() == 12 {
        1
    } else {
        0
    };
    assert_eq!(last.left[cone_end], last.right[cone_end]);
}

/// The per-target construction the forest replaced, kept as the reference:
/// one fresh multi-source Dijkstra from the whole tree for every target.
fn one_dijkstra_per_target(
    shell: &Shell,
    topo: &ShellTopology,
    cones: &[Cone],
) -> Result<(Vec<bool>, Vec<CutBranch>), CutError> {
    use std::cmp::Reverse;
    use std::collections::BinaryHeap;
    let nv = shell.vertices.len();
    let mut is_cone = vec![false; nv];
    for cone in cones.iter().filter(|c| c.index != 0) {
        is_cone[cone.vertex] = true;
    }
    // Adjacency over interior edges (never along the boundary).
    let mut adjacency: Vec<Vec<(usize, usize)>> = vec![Vec::new(); nv];
    for (e, &[a, b]) in topo.edges.iter().enumerate() {
        if !topo.is_boundary_edge(e) {
            adjacency[a].push((b, e));
            adjacency[b].push((a, e));
        }
    }
    let loop_length = |l: &Vec<usize>| -> f64 {
        (0..l.len())
            .map(|i| shell.edge_length(l[i], l[(i + 1) % l.len()]))
            .sum()
    };
    let loops = &topo.boundary_loops;
    let mut outer = 0;
    for (i, l) in loops.iter().enumerate() {
        if loop_length(l) > loop_length(&loops[outer]) {
            outer = i;
        }
    }
    let mut loop_of = vec![usize::MAX; nv];
    for (i, l) in loops.iter().enumerate() {
        for &v in l {
            loop_of[v] = i;
        }
    }
    let mut in_tree = vec![false; nv];
    for &v in &loops[outer] {
        in_tree[v] = true;
    }
    let mut pending_loop: Vec<bool> = (0..loops.len()).map(|i| i != outer).collect();
    let mut pending_cone = vec![false; nv];
    for v in 0..nv {
        pending_cone[v] = is_cone[v] && !topo.on_boundary[v];
    }
    let mut is_cut = vec![false; topo.edges.len()];
    let mut branches = Vec::new();
    loop {
        let remaining = pending_loop.iter().any(|&p| p) || pending_cone.iter().any(|&p| p);
        if !remaining {
            break;
        }
        let mut dist = vec![f64::INFINITY; nv];
        let mut pred = vec![(usize::MAX, usize::MAX); nv];
        let mut heap = BinaryHeap::new();
        for v in 0..nv {
            if in_tree[v] {
                dist[v] = 0.0;
                heap.push(Reverse((OrdF64(0.0), v)));
            }
        }
        let mut found = None;
        while let Some(Reverse((OrdF64(d), v))) = heap.pop() {
            if d > dist[v] {
                continue;
            }
            if !in_tree[v] {
                let hits_loop = loop_of[v] != usize::MAX && pending_loop[loop_of[v]];
                if pending_cone[v] || hits_loop {
                    found = Some(v);
                    break;
                }
                // Cones and other boundary vertices are never passed through.
                if is_cone[v] || topo.on_boundary[v] {
                    continue;
                }
            }
            for &(w, e) in &adjacency[v] {
                let nd = d + shell.edge_length(v, w);
                if nd < dist[w] {
                    dist[w] = nd;
                    pred[w] = (v, e);
                    heap.push(Reverse((OrdF64(nd), w)));
                }
            }
        }
        let Some(target_vertex) = found else {
            return Err(super::forest::unreachable(shell, loops, &pending_cone, &pending_loop));
        };
        let path = super::forest::walk_back(target_vertex, &in_tree, &pred, &mut is_cut);
        let target = if pending_cone[target_vertex] {
            pending_cone[target_vertex] = false;
            CutTarget::Cone(target_vertex)
        } else {
            let l = loop_of[target_vertex];
            pending_loop[l] = false;
            for &w in &loops[l] {
                in_tree[w] = true;
            }
            CutTarget::Loop(l)
        };
        for &w in &path {
            if !is_cone[w] {
                in_tree[w] = true;
            }
        }
        branches.push(CutBranch {
            vertices: path,
            target,
        });
    }
    Ok((is_cut, branches))
}


/// A reproducible number in [0, 1) from an index.
fn jitter(k: usize) -> f64 {
    let mut x = (k as u64 + 1).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    x ^= x >> 31;
    x = x.wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x ^= x >> 29;
    (x >> 11) as f64 / (1u64 << 53) as f64
}

/// Interior cones on every `step`-th interior vertex, alternating ±1.
fn every_nth_interior(topo: &ShellTopology, step: usize, offset: usize) -> Vec<Cone> {
    (0..topo.on_boundary.len())
        .filter(|&v| !topo.on_boundary[v])
        .skip(offset)
        .step_by(step)
        .enumerate()
        .map(|(k, vertex)| Cone {
            vertex,
            index: if k % 2 == 0 { 1 } else { -1 },
        })
        .collect()
}

fn path_length(shell: &Shell, path: &[usize]) -> f64 {
    path.windows(2).map(|w| shell.edge_length(w[0], w[1])).sum()
}

/// The forest against the per-target reference: the same branches (targets,
/// order, vertices), hence the same cut edges and lengths; Ω a disk.
fn assert_forest_is_reference(shell: &Shell, cones: &[Cone], loops: usize) {
    let topo = shell.check().unwrap();
    assert_eq!(topo.boundary_loops.len(), loops);
    let (ref_cut, ref_branches) = one_dijkstra_per_target(shell, &topo, cones).unwrap();
    let cut = cut_to_disk(shell, &topo, cones).unwrap();
    let interior = cones
        .iter()
        .filter(|c| c.index != 0 && !topo.on_boundary[c.vertex])
        .count();
    assert_eq!(cut.branches.len(), interior + loops - 1);
    assert_eq!(cut.branches, ref_branches);
    assert_eq!(cut.is_cut, ref_cut);
    let total =
        |b: &[CutBranch]| -> f64 { b.iter().map(|b| path_length(shell, &b.vertices)).sum() };
    assert_eq!(total(&cut.branches), total(&ref_branches));
    assert_eq!(cut.euler, 1);
    // Every branch ends at its target and starts on the tree grown before it.
    for b in &cut.branches {
        let end = *b.vertices.last().unwrap();
        match b.target {
            CutTarget::Cone(v) => assert_eq!(end, v),
            CutTarget::Loop(l) => assert!(topo.boundary_loops[l].contains(&end)),
        }
    }
}

#[test]
fn forest_matches_one_dijkstra_per_target_on_a_regular_grid_with_holes() {
    // A regular grid: many equal distances, so the tie rules are exercised.
    let shell = holed_grid(24, &[(5, 5), (17, 6), (8, 18), (19, 19)], |x, y| {
        [x, y, 0.0]
    });
    let topo = shell.check().unwrap();
    let cones = every_nth_interior(&topo, 13, 3);
    assert!(cones.len() > 30);
    assert_forest_is_reference(&shell, &cones, 5);
}

#[test]
fn forest_matches_one_dijkstra_per_target_on_a_jittered_curved_shell() {
    let n = 30;
    let shell = holed_grid(
        n,
        &[(4, 9), (20, 3), (12, 14), (25, 25), (7, 24)],
        |x, y| {
            let k = ((y * n as f64).round() as usize) * (n + 1) + (x * n as f64).round() as usize;
            let (dx, dy) = (0.3 * (jitter(2 * k) - 0.5), 0.3 * (jitter(2 * k + 1) - 0.5));
            let on_edge = |t: f64| t == 0.0 || t == 1.0;
            let (x, y) = (
                if on_edge(x) { x } else { x + dx / n as f64 },
                if on_edge(y) { y } else { y + dy / n as f64 },
            );
            [x, y, 0.3 * (3.0 * x).sin() * (2.0 * y).cos()]
        },
    );
    let topo = shell.check().unwrap();
    let cones = every_nth_interior(&topo, 7, 1);
    assert!(cones.len() > 100);
    assert_forest_is_reference(&shell, &cones, 6);
}

#[test]
fn forest_reports_the_same_unreachable_cone_as_the_reference() {
    let shell = grid(6, |x, y| [x, y, 0.0]);
    let topo = shell.check().unwrap();
    // Vertex 24 is (3, 3): walled in by cones on its six neighbours.
    let mut cones = vec![Cone {
        vertex: 24,
        index: 1,
    }];
    for &[a, b] in &topo.edges {
        if a == 24 || b == 24 {
            cones.push(Cone {
                vertex: a + b - 24,
                index: -1,
            });
        }
    }
    let reference = one_dijkstra_per_target(&shell, &topo, &cones).unwrap_err();
    assert_eq!(cut_to_disk(&shell, &topo, &cones).unwrap_err(), reference);
    assert!(reference.to_string().contains("vertex 24"), "{reference}");
}
