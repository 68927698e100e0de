//! The T-mesh (paper §III.A, spec §3.6): arcs are the chains of trace (and
//! CAD-curve) edges between T-mesh nodes, patches the regions of input quads
//! they bound, found by flood fill. A patch bounded by one loop with four
//! corners and an `L1 × L2` grid of quads inside is a *grid patch* with four
//! sides of arcs; any other region (an annulus, a region with a barrier
//! inside) is *frozen*: its arcs keep their input length.

use super::connectivity::{Connectivity, NONE};
use super::traces::{is_origin, Traces};
use geometry::FaceId;
use mesh::QuadMesh;
use std::collections::{HashMap, HashSet};

/// One arc: a chain of input-mesh edges between two T-mesh nodes.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Arc {
    /// Its input-mesh nodes, end to end (both ends T-mesh nodes).
    pub nodes: Vec<u32>,
    /// The CAD curve it runs along, if any.
    pub curve: Option<u32>,
}

impl Arc {
    /// Its input integer length `l_a` (edges).
    pub fn len(&self) -> u32 {
        self.nodes.len() as u32 - 1
    }
}

/// An arc as part of a patch side: `reversed` when the side runs from the
/// arc's last node to its first.
pub(crate) type SideArc = (u32, bool);

/// The shape of a patch.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum PatchShape {
    /// Four sides of arcs, counter-clockwise from corner 0; `dims` = the
    /// input lengths of sides 0 and 1; `grid[i + (dims[0] + 1) j]` the input
    /// node at grid point `(i, j)` (corner 0 at `(0, 0)`, side 0 along `i`).
    Grid { sides: [Vec<SideArc>; 4], dims: [u32; 2], grid: Vec<u32> },
    /// Kept as its input quads.
    Frozen,
}

/// A patch: input quads between arcs.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Patch {
    /// Its input quads.
    pub quads: Vec<u32>,
    /// The CAD face of its quads.
    pub face: FaceId,
    /// Grid or frozen.
    pub shape: PatchShape,
    /// Every arc on its boundary (with repeats removed).
    pub boundary_arcs: Vec<u32>,
}

/// The T-mesh: arcs, patches and the map from input edges to arcs.
#[derive(Debug, Default)]
pub(crate) struct TMesh {
    /// The arcs.
    pub arcs: Vec<Arc>,
    /// Each arc edge `(min, max)` → (arc, index of the edge along the arc).
    pub edge_arc: HashMap<(u32, u32), (u32, u32)>,
    /// Whether each input node is a T-mesh node.
    pub is_node: Vec<bool>,
    /// The patches.
    pub patches: Vec<Patch>,
}

impl TMesh {
    /// The arc (and whether it is run backwards) of input edge `a → b`.
    pub fn arc_of(&self, a: u32, b: u32) -> Option<SideArc> {
        let &(arc, k) = self.edge_arc.get(&(a.min(b), a.max(b)))?;
        Some((arc, self.arcs[arc as usize].nodes[k as usize] != a))
    }

    /// The arcs a trace runs along up to position `upto` (nodes `0..=upto`),
    /// each once per run.
    pub fn arcs_along(&self, nodes: &[u32], upto: usize) -> Vec<u32> {
        let mut out: Vec<u32> = Vec::new();
        for k in 0..upto.min(nodes.len().saturating_sub(1)) {
            if let Some((a, _)) = self.arc_of(nodes[k], nodes[k + 1]) {
                if out.last() != Some(&a) {
                    out.push(a);
                }
            }
        }
        out
    }
}

/// Builds the T-mesh of `traces` on `mesh`.
pub(crate) fn build_tmesh(mesh: &QuadMesh, conn: &Connectivity, traces: &Traces) -> TMesh {
    let nn = mesh.nodes.len();
    let mut barrier: HashSet<(u32, u32)> = HashSet::new();
    let key = |a: u32, b: u32| (a.min(b), a.max(b));
    for t in &traces.traces {
        for w in t.nodes.windows(2) {
            barrier.insert(key(w[0], w[1]));
        }
    }
    for &([a, b], _) in &mesh.curve_edges {
        barrier.insert(key(a, b));
    }
    // barrier neighbours of each node, in a fixed order
    let mut around: Vec<Vec<u32>> = vec![Vec::new(); nn];
    let mut sorted: Vec<(u32, u32)> = barrier.iter().copied().collect();
    sorted.sort_unstable();
    for &(a, b) in &sorted {
        around[a as usize].push(b);
        around[b as usize].push(a);
    }
    let seeds: HashSet<u32> = traces
        .traces
        .iter()
        .filter(|t| t.source == super::traces::Source::Seed)
        .map(|t| t.nodes[0])
        .collect();
    let mut is_node: Vec<bool> = (0..nn)
        .map(|v| {
            let a = &around[v];
            is_origin(conn.kind[v])
                || seeds.contains(&(v as u32))
                || (!a.is_empty() && a.len() != 2)
                || (a.len() == 2 && conn.straight_on(mesh, a[0], v as u32) != Some(a[1]))
        })
        .collect();
    let mut arcs: Vec<Arc> = Vec::new();
    let mut edge_arc: HashMap<(u32, u32), (u32, u32)> = HashMap::with_capacity(barrier.len());
    let walk_from = |n: u32,
                     is_node: &Vec<bool>,
                     arcs: &mut Vec<Arc>,
                     edge_arc: &mut HashMap<(u32, u32), (u32, u32)>| {
        for &m in &around[n as usize] {
            if edge_arc.contains_key(&key(n, m)) {
                continue;
            }
            let id = arcs.len() as u32;
            let mut nodes = vec![n, m];
            edge_arc.insert(key(n, m), (id, 0));
            let (mut prev, mut cur) = (n, m);
            while !is_node[cur as usize] {
                let a = &around[cur as usize];
                let next = if a[0] == prev { a[1] } else { a[0] };
                if edge_arc.contains_key(&key(cur, next)) {
                    break;
                }
                edge_arc.insert(key(cur, next), (id, nodes.len() as u32 - 1));
                nodes.push(next);
                (prev, cur) = (cur, next);
            }
            let curve = conn.edge_curve(nodes[0], nodes[1]);
            arcs.push(Arc { nodes, curve });
        }
    };
    for v in 0..nn as u32 {
        if is_node[v as usize] {
            walk_from(v, &is_node, &mut arcs, &mut edge_arc);
        }
    }
    // closed chains with no node: their lowest node becomes one
    for &(a, b) in &sorted {
        if !edge_arc.contains_key(&(a, b)) {
            is_node[a as usize] = true;
            walk_from(a, &is_node, &mut arcs, &mut edge_arc);
        }
    }
    let mut tm = TMesh { arcs, edge_arc, is_node, patches: Vec::new() };
    tm.patches = find_patches(mesh, conn, &tm, &barrier);
    tm
}

/// Flood fill of the quads across non-barrier edges, then each region's shape.
fn find_patches(
    mesh: &QuadMesh,
    conn: &Connectivity,
    tm: &TMesh,
    barrier: &HashSet<(u32, u32)>,
) -> Vec<Patch> {
    let nq = mesh.quads.len();
    let mut region = vec![u32::MAX; nq];
    let mut patches = Vec::new();
    for seed in 0..nq {
        if region[seed] != u32::MAX {
            continue;
        }
        let id = patches.len() as u32;
        let mut quads = vec![seed as u32];
        region[seed] = id;
        let mut k = 0;
        while k < quads.len() {
            let q = quads[k] as usize;
            k += 1;
            for e in 0..4 {
                let h = 4 * q + e;
                let (a, b) = (mesh.quads[q][e], mesh.quads[q][(e + 1) % 4]);
                let t = conn.twin[h];
                if t == NONE || barrier.contains(&(a.min(b), a.max(b))) {
                    continue;
                }
                let r = t as usize / 4;
                if region[r] == u32::MAX {
                    region[r] = id;
                    quads.push(r as u32);
                }
            }
        }
        let face = mesh.quad_face[seed];
        let shape = if quads.iter().all(|&q| mesh.quad_face[q as usize] == face) {
            grid_shape(mesh, conn, tm, &quads, &region, id)
        } else {
            None
        };
        let mut boundary_arcs = Vec::new();
        for &q in &quads {
            for e in 0..4 {
                let (a, b) = (mesh.quads[q as usize][e], mesh.quads[q as usize][(e + 1) % 4]);
                if let Some((arc, _)) = tm.arc_of(a, b) {
                    boundary_arcs.push(arc);
                }
            }
        }
        boundary_arcs.sort_unstable();
        boundary_arcs.dedup();
        patches.push(Patch {
            quads,
            face,
            shape: shape.unwrap_or(PatchShape::Frozen),
            boundary_arcs,
        });
    }
    patches
}

/// The grid shape of region `id`, or `None` when it is not a four-cornered
/// grid of quads bounded by whole arcs.
fn grid_shape(
    mesh: &QuadMesh,
    conn: &Connectivity,
    tm: &TMesh,
    quads: &[u32],
    region: &[u32],
    id: u32,
) -> Option<PatchShape> {
    let inside = |h: u32| h != NONE && region[h as usize / 4] == id;
    let on_boundary = |h: u32| {
        let (a, b) = (Connectivity::tail(mesh, h), Connectivity::head(mesh, h));
        !inside(conn.twin[h as usize]) || tm.edge_arc.contains_key(&(a.min(b), a.max(b)))
    };
    let mut boundary: Vec<u32> = Vec::new();
    for &q in quads {
        for e in 0..4 {
            let h = 4 * q + e;
            if on_boundary(h) {
                // a barrier edge with the region on both sides: not a disk
                if inside(conn.twin[h as usize]) {
                    return None;
                }
                boundary.push(h);
            }
        }
    }
    // the boundary loop, counter-clockwise: from a half-edge to the next one
    // around its head, inside the region; `turns[k]` = quads at the node
    // between boundary half-edges k and k + 1
    let start = *boundary.iter().min()?;
    let mut lp = vec![start];
    let mut turns = Vec::new();
    loop {
        let h = *lp.last()?;
        let mut g = (h & !3) | ((h + 1) & 3);
        let mut quads_here = 1;
        while !on_boundary(g) {
            let t = conn.twin[g as usize];
            g = (t & !3) | ((t + 1) & 3);
            quads_here += 1;
            if quads_here > 8 {
                return None;
            }
        }
        turns.push(quads_here);
        if g == start {
            break;
        }
        if lp.len() > boundary.len() {
            return None;
        }
        lp.push(g);
    }
    if lp.len() != boundary.len() || turns.iter().any(|&t| t > 2) {
        return None;
    }
    let corners: Vec<usize> = (0..lp.len()).filter(|&k| turns[k] == 1).collect();
    if corners.len() != 4 {
        return None;
    }
    // side s runs from boundary half-edge corners[s - 1] + 1 to corners[s]
    // (corner nodes at the heads of the half-edges `corners[...]`); corner 0
    // is the node with the lowest index
    let corner_node = |k: usize| Connectivity::head(mesh, lp[corners[k]]);
    let first = (0..4).min_by_key(|&k| corner_node(k))?;
    let n = lp.len();
    let mut sides: [Vec<SideArc>; 4] = Default::default();
    let mut side_nodes: [Vec<u32>; 4] = Default::default();
    for s in 0..4 {
        let from = corners[(first + s) % 4];
        let to = corners[(first + s + 1) % 4];
        let mut k = (from + 1) % n;
        side_nodes[s].push(Connectivity::tail(mesh, lp[k]));
        loop {
            let h = lp[k];
            let (a, b) = (Connectivity::tail(mesh, h), Connectivity::head(mesh, h));
            let sa = tm.arc_of(a, b)?;
            if sides[s].last() != Some(&sa) {
                sides[s].push(sa);
            }
            side_nodes[s].push(b);
            if k == to {
                break;
            }
            k = (k + 1) % n;
        }
    }
    let len = |s: usize| side_nodes[s].len() as u32 - 1;
    let dims = [len(0), len(1)];
    if len(2) != dims[0] || len(3) != dims[1] || quads.len() as u32 != dims[0] * dims[1] {
        return None;
    }
    // every side is whole arcs: its ends are T-mesh nodes and its arcs' lengths add up
    for s in 0..4 {
        let total: u32 = sides[s].iter().map(|&(a, _)| tm.arcs[a as usize].len()).sum();
        if total != len(s) {
            return None;
        }
    }
    let w = dims[0] as usize + 1;
    let mut grid = vec![u32::MAX; w * (dims[1] as usize + 1)];
    for i in 0..=dims[0] as usize {
        grid[i] = side_nodes[0][i];
    }
    // row by row: the quad on the left of (i, j) → (i + 1, j) gives row j + 1
    for j in 0..dims[1] as usize {
        for i in 0..dims[0] as usize {
            let (a, b) = (grid[i + w * j], grid[i + 1 + w * j]);
            let &h = conn.by_ends.get(&(a, b))?;
            if !inside(h) {
                return None;
            }
            let quad = mesh.quads[h as usize / 4];
            let e = h as usize % 4;
            let (c, d) = (quad[(e + 2) % 4], quad[(e + 3) % 4]);
            let (up_r, up_l) = (i + 1 + w * (j + 1), i + w * (j + 1));
            for (slot, v) in [(up_r, c), (up_l, d)] {
                if grid[slot] == u32::MAX {
                    grid[slot] = v;
                } else if grid[slot] != v {
                    return None;
                }
            }
        }
    }
    // the last row must be side 2 backwards
    for i in 0..=dims[0] as usize {
        if grid[i + w * dims[1] as usize] != side_nodes[2][dims[0] as usize - i] {
            return None;
        }
    }
    Some(PatchShape::Grid { sides, dims, grid })
}
