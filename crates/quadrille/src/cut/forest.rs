//! The cutting graph G of spec §6 as one shortest-path forest: a single
//! multi-source Dijkstra from the tree grown so far. Distances are kept
//! between targets; when a branch joins the tree its vertices (and a joined
//! loop's) become sources at distance 0 and only the vertices they bring
//! closer are relaxed again, instead of one fresh Dijkstra per target.
//!
//! The result equals the per-target construction exactly (same targets in
//! the same order, same paths): distances are the same fixed point, the
//! nearest pending target is chosen by (distance, vertex), and a tie between
//! predecessors goes to the one with the smaller (distance, vertex), which is
//! the one a fresh Dijkstra pops first.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use super::{CutBranch, CutError, CutTarget, OrdF64};
use crate::shell::{Shell, ShellTopology};

/// No predecessor.
const NONE: usize = usize::MAX;

/// The forest: cut edges (per shell edge) and the branches in the order added.
pub(super) struct Forest {
    /// Per shell edge: in G.
    pub is_cut: Vec<bool>,
    /// The branches, nearest first.
    pub branches: Vec<CutBranch>,
}

/// Grows the forest from the longest boundary loop to every other loop and
/// every interior cone (`is_cone` per vertex), never walking along the
/// boundary and never passing through a cone or a boundary vertex that is
/// not in the tree.
pub(super) fn grow_forest(
    shell: &Shell,
    topo: &ShellTopology,
    is_cone: &[bool],
) -> Result<Forest, CutError> {
    let nv = shell.vertices.len();
    // Adjacency over interior edges, with their 3D lengths.
    let mut adjacency: Vec<Vec<(usize, usize, f64)>> = vec![Vec::new(); nv];
    for (e, &[a, b]) in topo.edges.iter().enumerate() {
        if !topo.is_boundary_edge(e) {
            let len = shell.edge_length(a, b);
            adjacency[a].push((b, e, len));
            adjacency[b].push((a, e, len));
        }
    }
    let loops = &topo.boundary_loops;
    let loop_length = |l: &Vec<usize>| -> f64 {
        (0..l.len())
            .map(|i| shell.edge_length(l[i], l[(i + 1) % l.len()]))
            .sum()
    };
    let mut outer = 0;
    for (i, l) in loops.iter().enumerate() {
        if loop_length(l) > loop_length(&loops[outer]) {
            outer = i;
        }
    }
    let mut loop_of = vec![NONE; nv];
    for (i, l) in loops.iter().enumerate() {
        for &v in l {
            loop_of[v] = i;
        }
    }
    let mut pending_loop: Vec<bool> = (0..loops.len()).map(|i| i != outer).collect();
    let mut pending_cone: Vec<bool> = (0..nv)
        .map(|v| is_cone[v] && !topo.on_boundary[v])
        .collect();
    // Target vertices: the pending cones and every vertex of a pending loop.
    let mut targets: Vec<usize> = (0..nv)
        .filter(|&v| pending_cone[v] || (loop_of[v] != NONE && pending_loop[loop_of[v]]))
        .collect();
    let mut search = Search {
        adjacency,
        in_tree: vec![false; nv],
        blocks: (0..nv).map(|v| is_cone[v] || topo.on_boundary[v]).collect(),
        dist: vec![f64::INFINITY; nv],
        pred: vec![(NONE, NONE); nv],
        heap: BinaryHeap::new(),
    };
    for &v in &loops[outer] {
        search.add_source(v);
    }
    let mut is_cut = vec![false; topo.edges.len()];
    let mut branches = Vec::new();
    while !targets.is_empty() {
        search.settle();
        // The nearest pending target, ties to the smaller vertex.
        let nearest = targets
            .iter()
            .copied()
            .filter(|&v| search.dist[v].is_finite())
            .min_by(|&a, &b| search.dist[a].total_cmp(&search.dist[b]).then(a.cmp(&b)));
        let Some(target_vertex) = nearest else {
            return Err(unreachable(shell, loops, &pending_cone, &pending_loop));
        };
        let path = walk_back(target_vertex, &search.in_tree, &search.pred, &mut is_cut);
        let target = if pending_cone[target_vertex] {
            pending_cone[target_vertex] = false;
            CutTarget::Cone(target_vertex)
        } else {
            let l = loop_of[target_vertex];
            pending_loop[l] = false;
            for &w in &loops[l] {
                search.add_source(w);
            }
            CutTarget::Loop(l)
        };
        // A cut goes to a cone, not through it: cones never join the tree.
        for &w in &path {
            if !is_cone[w] {
                search.add_source(w);
            }
        }
        targets.retain(|&v| pending_cone[v] || (loop_of[v] != NONE && pending_loop[loop_of[v]]));
        branches.push(CutBranch {
            vertices: path,
            target,
        });
    }
    Ok(Forest { is_cut, branches })
}

/// The Dijkstra state kept between targets.
struct Search {
    /// Per vertex: (neighbour, edge, length) over interior edges.
    adjacency: Vec<Vec<(usize, usize, f64)>>,
    /// In the tree (a source at distance 0).
    in_tree: Vec<bool>,
    /// Cones and boundary vertices: reached but never passed through unless
    /// in the tree.
    blocks: Vec<bool>,
    /// Distance from the tree.
    dist: Vec<f64>,
    /// Predecessor (vertex, edge) on a shortest path from the tree.
    pred: Vec<(usize, usize)>,
    /// Vertices whose distance went down and whose neighbours wait.
    heap: BinaryHeap<Reverse<(OrdF64, usize)>>,
}

impl Search {
    /// Puts `v` in the tree at distance 0.
    fn add_source(&mut self, v: usize) {
        if !self.in_tree[v] {
            self.in_tree[v] = true;
            self.dist[v] = 0.0;
            self.pred[v] = (NONE, NONE);
            self.heap.push(Reverse((OrdF64(0.0), v)));
        }
    }

    /// Relaxes until no distance goes down (distances only ever decrease,
    /// so the stale entries of earlier rounds are skipped).
    fn settle(&mut self) {
        while let Some(Reverse((OrdF64(d), v))) = self.heap.pop() {
            if d > self.dist[v] || (self.blocks[v] && !self.in_tree[v]) {
                continue;
            }
            for &(w, e, len) in &self.adjacency[v] {
                if self.in_tree[w] {
                    continue;
                }
                let nd = d + len;
                if nd < self.dist[w] {
                    self.dist[w] = nd;
                    self.pred[w] = (v, e);
                    self.heap.push(Reverse((OrdF64(nd), w)));
                } else if nd == self.dist[w] {
                    // A tie: keep the predecessor a fresh search pops first.
                    let p = self.pred[w].0;
                    if p == NONE || (d, v) < (self.dist[p], p) {
                        self.pred[w] = (v, e);
                    }
                }
            }
        }
    }
}

/// The path from the tree to `target` along the predecessors `pred`
/// (vertex, edge) up to the first vertex `in_tree`, tree end first; its
/// edges are marked in `is_cut`.
pub(super) fn walk_back(
    target: usize,
    in_tree: &[bool],
    pred: &[(usize, usize)],
    is_cut: &mut [bool],
) -> Vec<usize> {
    let mut path = vec![target];
    let mut v = target;
    while !in_tree[v] {
        let (p, e) = pred[v];
        is_cut[e] = true;
        path.push(p);
        v = p;
    }
    path.reverse();
    path
}

/// The error for targets no search reaches: the first pending cone, else
/// the first pending boundary loop (its first vertex).
pub(super) fn unreachable(
    shell: &Shell,
    loops: &[Vec<usize>],
    pending_cone: &[bool],
    pending_loop: &[bool],
) -> CutError {
    let (what, v) = match pending_cone.iter().position(|&p| p) {
        Some(v) => (format!("the cone on vertex {v}"), v),
        None => {
            let l = pending_loop.iter().position(|&p| p).unwrap_or(0);
            (format!("boundary loop {l}"), loops[l][0])
        }
    };
    CutError::Unreachable {
        what,
        position: shell.vertices[v],
    }
}
