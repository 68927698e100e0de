//! Patches: the connected sets of triangles between feature edges, cut into
//! topological disks, and the curves (chains of feature and seam edges
//! between corners).
//!
//! - A feature edge with the same patch on both sides (a crease that fades
//!   out inside a smooth region) separates nothing: it is dropped.
//! - A patch is cut along its seam edges into a disk: the *cut mesh* has one
//!   copy of a vertex per wedge of triangles between cut edges around it
//!   (a union-find over triangle corners joined across uncut edges).
//! - A patch with several boundary loops that cannot be projected onto a
//!   plane (a cylinder side; flat faces with holes keep them) gets seams:
//!   shortest paths inside the patch from the loops already joined to each
//!   other loop, ending on corners when the loop has some (so that a seam
//!   does not split a curve), anywhere on a loop without corners (the seam's
//!   end becomes that loop's corner).
//! - A closed patch (a sphere) gets one seam between two far-apart vertices:
//!   cut open along it, it is a disk whose boundary is the seam twice.
//! - A patch with handles (genus > 0, a torus) is not supported yet: it is an
//!   error naming the patch.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use geometry::{vec3, Vec3};

use crate::features::VertexEdges;
use crate::topology::Topology;

/// Patch label of each triangle (flood fill across non-feature edges) and
/// the number of patches.
pub fn label(ntris: usize, topo: &Topology, feature: &[bool]) -> (Vec<u32>, usize) {
    let mut patch = vec![u32::MAX; ntris];
    let mut n = 0u32;
    let mut stack = Vec::new();
    for seed in 0..ntris {
        if patch[seed] != u32::MAX {
            continue;
        }
        patch[seed] = n;
        stack.push(seed);
        while let Some(t) = stack.pop() {
            for &e in &topo.tri_edges[t] {
                let e = e as usize;
                if feature[e] {
                    continue;
                }
                for o in topo.edge_tris[e] {
                    if o != u32::MAX && patch[o as usize] == u32::MAX {
                        patch[o as usize] = n;
                        stack.push(o as usize);
                    }
                }
            }
        }
        n += 1;
    }
    (patch, n as usize)
}

/// Unflags feature edges with the same patch on both sides; returns how many.
pub fn drop_dangling(topo: &Topology, patch: &[u32], feature: &mut [bool]) -> usize {
    let mut n = 0;
    for (e, &[t0, t1]) in topo.edge_tris.iter().enumerate() {
        if feature[e] && t1 != u32::MAX && patch[t0 as usize] == patch[t1 as usize] {
            feature[e] = false;
            n += 1;
        }
    }
    n
}

/// One patch cut along its curve edges: vertex copies and boundary loops.
#[derive(Clone, Debug)]
pub struct CutPatch {
    /// The patch's triangles (global ids).
    pub tris: Vec<u32>,
    /// Triangles on copies (same order as `tris`, same orientation).
    pub copy_tris: Vec<[u32; 3]>,
    /// The original vertex of each copy.
    pub copy_vertex: Vec<u32>,
    /// Boundary loops: sequences of `(copy, edge)`: the loop leaves `copy`
    /// along `edge` (material on the left).
    pub loops: Vec<Vec<(u32, u32)>>,
    /// Euler characteristic of the cut mesh.
    pub euler: i64,
}

impl CutPatch {
    /// Genus of the patch (from the Euler characteristic and the loops).
    pub fn genus(&self) -> i64 {
        (2 - self.euler - self.loops.len() as i64) / 2
    }
    /// True when the cut mesh is a topological disk.
    pub fn is_disk(&self) -> bool {
        self.euler == 1 && self.loops.len() == 1
    }
}

fn find(p: &mut [u32], mut x: u32) -> u32 {
    while p[x as usize] != x {
        p[x as usize] = p[p[x as usize] as usize];
        x = p[x as usize];
    }
    x
}

/// Cuts patch `tris` along the edges where `cut` is true (and along its
/// border with other patches). `local` is a scratch array over all triangles
/// (`u32::MAX` outside; restored on return). `Err` names a vertex where the
/// boundary pinches.
pub fn cut_patch(
    mesh_tris: &[[u32; 3]],
    topo: &Topology,
    tris: Vec<u32>,
    cut: &[bool],
    local: &mut [u32],
) -> Result<CutPatch, u32> {
    for (i, &t) in tris.iter().enumerate() {
        local[t as usize] = i as u32;
    }
    let nc = 3 * tris.len();
    let mut parent: Vec<u32> = (0..nc as u32).collect();
    let mut nbh = 0usize;
    let corner_of =
        |t: usize, v: u32| -> usize { (0..3).find(|&k| mesh_tris[t][k] == v).unwrap_or(0) };
    for (i, &t) in tris.iter().enumerate() {
        for k in 0..3 {
            let e = topo.tri_edges[t as usize][k] as usize;
            let [t0, t1] = topo.edge_tris[e];
            let o = if t0 == t { t1 } else { t0 };
            if o == u32::MAX || cut[e] || local[o as usize] == u32::MAX {
                nbh += 1;
                continue;
            }
            let j = local[o as usize] as usize;
            for kk in [k, (k + 1) % 3] {
                let v = mesh_tris[t as usize][kk];
                let a = find(&mut parent, (3 * i + kk) as u32);
                let b = find(&mut parent, (3 * j + corner_of(o as usize, v)) as u32);
                if a != b {
                    parent[a.max(b) as usize] = a.min(b);
                }
            }
        }
    }
    let mut copy_of_root = vec![u32::MAX; nc];
    let mut copy_vertex = Vec::new();
    let mut copy_tris = vec![[0u32; 3]; tris.len()];
    for (i, &t) in tris.iter().enumerate() {
        for k in 0..3 {
            let r = find(&mut parent, (3 * i + k) as u32) as usize;
            if copy_of_root[r] == u32::MAX {
                copy_of_root[r] = copy_vertex.len() as u32;
                copy_vertex.push(mesh_tris[t as usize][k]);
            }
            copy_tris[i][k] = copy_of_root[r];
        }
    }
    // boundary half-edges on copies
    let ncopy = copy_vertex.len();
    let mut out = vec![u32::MAX; ncopy];
    let mut halves: Vec<(u32, u32, u32)> = Vec::with_capacity(nbh);
    for (i, &t) in tris.iter().enumerate() {
        for k in 0..3 {
            let e = topo.tri_edges[t as usize][k] as usize;
            let [t0, t1] = topo.edge_tris[e];
            let o = if t0 == t { t1 } else { t0 };
            if o == u32::MAX || cut[e] || local[o as usize] == u32::MAX {
                let (a, b) = (copy_tris[i][k], copy_tris[i][(k + 1) % 3]);
                if out[a as usize] != u32::MAX {
                    for &t in &tris {
                        local[t as usize] = u32::MAX;
                    }
                    return Err(copy_vertex[a as usize]);
                }
                out[a as usize] = halves.len() as u32;
                halves.push((a, b, e as u32));
            }
        }
    }
    for &t in &tris {
        local[t as usize] = u32::MAX;
    }
    let mut used = vec![false; halves.len()];
    let mut loops = Vec::new();
    for h0 in 0..halves.len() {
        if used[h0] {
            continue;
        }
        let mut lp = Vec::new();
        let mut h = h0;
        while !used[h] {
            used[h] = true;
            let (a, b, e) = halves[h];
            lp.push((a, e));
            let next = out[b as usize];
            if next == u32::MAX {
                return Err(copy_vertex[b as usize]);
            }
            h = next as usize;
        }
        loops.push(lp);
    }
    let nedges = (3 * tris.len() + halves.len()) / 2;
    let euler = ncopy as i64 - nedges as i64 + tris.len() as i64;
    Ok(CutPatch {
        tris,
        copy_tris,
        copy_vertex,
        loops,
        euler,
    })
}

/// Vertex → (neighbour, edge) adjacency of the whole mesh.
pub struct Adjacency {
    offsets: Vec<u32>,
    nbrs: Vec<(u32, u32)>,
}

impl Adjacency {
    /// Adjacency of every vertex over all edges.
    pub fn new(nverts: usize, topo: &Topology) -> Self {
        let all = vec![true; topo.edges.len()];
        let ve = VertexEdges::new(nverts, topo, &all);
        let nbrs = ve.edges.iter().map(|&e| (0u32, e)).collect::<Vec<_>>();
        let mut a = Adjacency {
            offsets: ve.offsets,
            nbrs,
        };
        for v in 0..nverts {
            for k in a.offsets[v] as usize..a.offsets[v + 1] as usize {
                let [p, q] = topo.edges[a.nbrs[k].1 as usize];
                a.nbrs[k].0 = if p as usize == v { q } else { p };
            }
        }
        a
    }
    /// `(neighbour, edge)` pairs of `v`.
    pub fn at(&self, v: u32) -> &[(u32, u32)] {
        &self.nbrs[self.offsets[v as usize] as usize..self.offsets[v as usize + 1] as usize]
    }
}

/// Shortest path (3D length) inside patch `p` from any `sources` vertex to
/// any `targets` vertex, through `free` vertices only, along edges of the
/// patch that are not cut. Returns the edges of the path.
#[allow(clippy::too_many_arguments)]
pub fn shortest_path(
    points: &[Vec3],
    topo: &Topology,
    adj: &Adjacency,
    patch_of: &[u32],
    p: u32,
    cut: &[bool],
    sources: &[u32],
    is_target: &dyn Fn(u32) -> bool,
    free: &dyn Fn(u32) -> bool,
) -> Option<Vec<u32>> {
    use std::collections::HashMap;
    let mut dist: HashMap<u32, f64> = HashMap::new();
    let mut prev: HashMap<u32, (u32, u32)> = HashMap::new();
    let mut heap = BinaryHeap::new();
    let key = |d: f64| Reverse((d * 1e12) as u64);
    for &s in sources {
        dist.insert(s, 0.0);
        heap.push((key(0.0), s));
    }
    let in_patch = |e: u32| {
        let [t0, t1] = topo.edge_tris[e as usize];
        t1 != u32::MAX
            && patch_of[t0 as usize] == p
            && patch_of[t1 as usize] == p
            && !cut[e as usize]
    };
    let mut best: Option<(f64, u32, u32, u32)> = None; // (length, last vertex, target, edge)
    while let Some((Reverse(dk), v)) = heap.pop() {
        let d = dist[&v];
        if (d * 1e12) as u64 != dk {
            continue;
        }
        if best.is_some_and(|b| b.0 <= d) {
            break;
        }
        for &(w, e) in adj.at(v) {
            if !in_patch(e) {
                continue;
            }
            let nd = d + vec3::dist(points[v as usize], points[w as usize]);
            if is_target(w) {
                if best.is_none_or(|b| nd < b.0) {
                    best = Some((nd, v, w, e));
                }
                continue;
            }
            if !free(w) {
                continue;
            }
            if dist.get(&w).is_none_or(|&old| nd < old) {
                dist.insert(w, nd);
                prev.insert(w, (v, e));
                heap.push((key(nd), w));
            }
        }
    }
    let (_, mut v, _, e) = best?;
    let mut path = vec![e];
    while let Some(&(u, e)) = prev.get(&v) {
        path.push(e);
        v = u;
    }
    path.reverse();
    Some(path)
}

/// Hop-count breadth-first search inside patch `p` over uncut edges from `s`:
/// the farthest vertex and the parent edge of every reached vertex.
pub fn bfs_far(
    topo: &Topology,
    adj: &Adjacency,
    patch_of: &[u32],
    p: u32,
    s: u32,
) -> (u32, std::collections::HashMap<u32, (u32, u32)>) {
    use std::collections::{HashMap, VecDeque};
    let mut prev: HashMap<u32, (u32, u32)> = HashMap::new();
    let mut q = VecDeque::new();
    q.push_back(s);
    prev.insert(s, (u32::MAX, u32::MAX));
    let mut last = s;
    while let Some(v) = q.pop_front() {
        last = v;
        for &(w, e) in adj.at(v) {
            let [t0, t1] = topo.edge_tris[e as usize];
            if t1 == u32::MAX
                || patch_of[t0 as usize] != p
                || patch_of[t1 as usize] != p
                || prev.contains_key(&w)
            {
                continue;
            }
            prev.insert(w, (v, e));
            q.push_back(w);
        }
    }
    (last, prev)
}

/// A curve of the discrete model: a chain of curve edges between corners.
#[derive(Clone, Debug)]
pub struct Chain {
    /// Vertices in order; `verts[0] == verts[last]` for a closed curve.
    pub verts: Vec<u32>,
    /// True for a seam (a cut inside a patch), false for a feature curve.
    pub seam: bool,
}

/// Chains the curve edges (`flag`) into curves between corners (`corner`,
/// updated: a closed chain without a corner gets one at its lowest vertex).
/// Returns the chains and, per edge, `(chain, segment)` (`u32::MAX` when the
/// edge is no curve edge).
pub fn chain_curves(
    nverts: usize,
    topo: &Topology,
    flag: &[bool],
    seam: &[bool],
    corner: &mut [bool],
) -> (Vec<Chain>, Vec<(u32, u32)>) {
    let ve = VertexEdges::new(nverts, topo, flag);
    for v in 0..nverts {
        if ve.at(v).len() != 2 && !ve.at(v).is_empty() {
            corner[v] = true;
        }
    }
    let mut edge_chain = vec![(u32::MAX, u32::MAX); topo.edges.len()];
    let mut chains = Vec::new();
    let walk = |start: u32,
                e0: u32,
                edge_chain: &mut Vec<(u32, u32)>,
                corner: &[bool],
                id: u32|
     -> Chain {
        let mut verts = vec![start];
        let mut v = start;
        let mut e = e0;
        loop {
            let [a, b] = topo.edges[e as usize];
            let w = if a == v { b } else { a };
            edge_chain[e as usize] = (id, verts.len() as u32 - 1);
            verts.push(w);
            v = w;
            if corner[v as usize] {
                break;
            }
            match ve
                .at(v as usize)
                .iter()
                .find(|&&x| edge_chain[x as usize].0 == u32::MAX)
            {
                Some(&x) => e = x,
                None => break,
            }
        }
        Chain {
            verts,
            seam: seam[e0 as usize],
        }
    };
    for v in 0..nverts {
        if !corner[v] {
            continue;
        }
        for &e in ve.at(v) {
            if edge_chain[e as usize].0 == u32::MAX {
                let id = chains.len() as u32;
                chains.push(walk(v as u32, e, &mut edge_chain, corner, id));
            }
        }
    }
    // closed chains without a corner
    for e in 0..topo.edges.len() {
        if !flag[e] || edge_chain[e].0 != u32::MAX {
            continue;
        }
        // collect the cycle's vertices to pick its lowest one
        let mut lowest = topo.edges[e][0];
        let mut v = topo.edges[e][0];
        let mut pe = e as u32;
        loop {
            let [a, b] = topo.edges[pe as usize];
            let w = if a == v { b } else { a };
            lowest = lowest.min(w);
            v = w;
            let es = ve.at(v as usize);
            let next = if es[0] == pe { es[1] } else { es[0] };
            if v == topo.edges[e][0] {
                break;
            }
            pe = next;
        }
        corner[lowest as usize] = true;
        let e0 = ve.at(lowest as usize)[0];
        let id = chains.len() as u32;
        chains.push(walk(lowest, e0, &mut edge_chain, corner, id));
    }
    (chains, edge_chain)
}
