//! S4 of `quadrille spline` (spec ricci-flow-iga-reconstruction §6): the
//! cutting graph G and the cut mesh Ω = S − G. A multi-source Dijkstra
//! forest (`forest.rs`: one search whose sources grow with the tree) grows
//! from the longest boundary loop and adds, nearest first, a
//! shortest path to every other boundary loop (b − 1 loop cuts) and to every
//! interior cone (cuts go *to* cones, never through them). Ω gets one child
//! vertex per wedge of triangles between cut edges, and G is split into cut
//! paths β whose two sides the immersion compares.

use thiserror::Error;

use crate::ricci::Cone;
use crate::shell::{find, union, Shell, ShellTopology, NO_FACE};

/// What a branch of the cut forest was added for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CutTarget {
    /// An interior cone (its vertex).
    Cone(usize),
    /// A boundary loop (its index in [`ShellTopology::boundary_loops`]).
    Loop(usize),
}

/// One Dijkstra path of the forest, from the tree to its target.
#[derive(Clone, Debug, PartialEq)]
pub struct CutBranch {
    /// Shell vertices from the tree (or the outer loop) to the target.
    pub vertices: Vec<usize>,
    /// What it reaches.
    pub target: CutTarget,
}

/// The two sides of one cut edge `a → b` in Ω.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CutEdgeSides {
    /// Children of `a`, `b` in the triangle left of `a → b`.
    pub left: [usize; 2],
    /// Children of `a`, `b` in the triangle right of `a → b`.
    pub right: [usize; 2],
}

/// A cut path β: a maximal chain of cut edges whose inner vertices have two
/// children; ends at cones, the boundary, branch points or leaves.
#[derive(Clone, Debug, PartialEq)]
pub struct CutPath {
    /// Shell vertices along the path.
    pub vertices: Vec<usize>,
    /// Per edge of the path: its two child edges.
    pub sides: Vec<CutEdgeSides>,
}

/// The cut mesh Ω: the shell's triangles over child vertices.
#[derive(Clone, Debug, PartialEq)]
pub struct CutMesh {
    /// Child vertex of each triangle corner.
    pub corners: Vec<[usize; 3]>,
    /// Shell vertex of each child.
    pub parent: Vec<usize>,
    /// Per shell edge: in G.
    pub is_cut: Vec<bool>,
    /// The Dijkstra branches, in the order added.
    pub branches: Vec<CutBranch>,
    /// The cut paths β.
    pub paths: Vec<CutPath>,
    /// χ(Ω) (1 for a disk).
    pub euler: i64,
}

/// Why the shell could not be cut to a disk.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum CutError {
    /// A target no path reaches.
    #[error("cut graph: no path from the outer boundary to {what} at {position:?} (cones and boundary block the way)")]
    Unreachable {
        /// The target.
        what: String,
        /// Its position.
        position: [f64; 3],
    },
    /// Ω is not a disk.
    #[error("cut mesh is not a disk: χ(Ω) = {euler}, {loops} boundary loops ({detail})")]
    NotDisk {
        /// χ(Ω).
        euler: i64,
        /// Boundary loops of Ω.
        loops: usize,
        /// More.
        detail: String,
    },
}

/// Cuts the shell to a disk (spec §6). `cones` with index 0 are ignored.
pub fn cut_to_disk(
    shell: &Shell,
    topo: &ShellTopology,
    cones: &[Cone],
) -> Result<CutMesh, CutError> {
    let nv = shell.vertices.len();
    let is_cone = {
        let mut c = vec![false; nv];
        for cone in cones.iter().filter(|c| c.index != 0 && c.vertex < nv) {
            c[cone.vertex] = true;
        }
        c
    };
    let forest::Forest { is_cut, branches } = forest::grow_forest(shell, topo, &is_cone)?;
    let (corners, parent) = split_wedges(shell, topo, &is_cut);
    let paths = cut_paths(shell, topo, &is_cut, &is_cone, &corners);
    let cut_count = is_cut.iter().filter(|&&c| c).count() as i64;
    let euler =
        parent.len() as i64 - (topo.edges.len() as i64 + cut_count) + shell.triangles.len() as i64;
    // Ω as a shell of its own: one component, one boundary loop.
    let omega = Shell {
        vertices: parent.iter().map(|&p| shell.vertices[p]).collect(),
        triangles: corners.clone(),
    };
    let detail_error = |detail: String, loops: usize| CutError::NotDisk {
        euler,
        loops,
        detail,
    };
    match omega.check() {
        Ok(t) if t.euler == 1 && t.boundary_loops.len() == 1 && euler == 1 => {}
        Ok(t) => {
            return Err(detail_error(
                format!("{} components", t.components),
                t.boundary_loops.len(),
            ))
        }
        Err(e) => return Err(detail_error(e.to_string(), 0)),
    }
    Ok(CutMesh {
        corners,
        parent,
        is_cut,
        branches,
        paths,
        euler,
    })
}

/// Children: corners joined across every uncut interior edge (union–find),
/// numbered in order of their first corner.
fn split_wedges(
    shell: &Shell,
    topo: &ShellTopology,
    is_cut: &[bool],
) -> (Vec<[usize; 3]>, Vec<usize>) {
    let nf = shell.triangles.len();
    let corner = |f: usize, v: usize| -> usize {
        3 * f + (0..3).position(|k| shell.triangles[f][k] == v).unwrap_or(0)
    };
    let mut set: Vec<usize> = (0..3 * nf).collect();
    for (e, &[f, g]) in topo.edge_faces.iter().enumerate() {
        if f == NO_FACE || g == NO_FACE || is_cut[e] {
            continue;
        }
        for v in topo.edges[e] {
            union(&mut set, corner(f, v), corner(g, v));
        }
    }
    let mut child_of_root = vec![usize::MAX; 3 * nf];
    let mut parent = Vec::new();
    let mut corners = vec![[0usize; 3]; nf];
    for (f, (corner_children, t)) in corners.iter_mut().zip(&shell.triangles).enumerate() {
        for (k, (child, &v)) in corner_children.iter_mut().zip(t).enumerate() {
            let r = find(&mut set, 3 * f + k);
            if child_of_root[r] == usize::MAX {
                child_of_root[r] = parent.len();
                parent.push(v);
            }
            *child = child_of_root[r];
        }
    }
    (corners, parent)
}

/// Splits G into cut paths β between nodes (cones, boundary vertices and
/// vertices with other than two cut edges).
fn cut_paths(
    shell: &Shell,
    topo: &ShellTopology,
    is_cut: &[bool],
    is_cone: &[bool],
    corners: &[[usize; 3]],
) -> Vec<CutPath> {
    let nv = shell.vertices.len();
    let mut cut_edges_at: Vec<Vec<usize>> = vec![Vec::new(); nv];
    for (e, &[a, b]) in topo.edges.iter().enumerate() {
        if is_cut[e] {
            cut_edges_at[a].push(e);
            cut_edges_at[b].push(e);
        }
    }
    let is_node = |v: usize| is_cone[v] || topo.on_boundary[v] || cut_edges_at[v].len() != 2;
    let child = |f: usize, v: usize| -> usize {
        corners[f][(0..3).position(|k| shell.triangles[f][k] == v).unwrap_or(0)]
    };
    let sides = |a: usize, b: usize, e: usize| -> CutEdgeSides {
        let [f0, f1] = topo.edge_faces[e];
        // f0 holds min → max.
        let (left, right) = if a < b { (f0, f1) } else { (f1, f0) };
        CutEdgeSides {
            left: [child(left, a), child(left, b)],
            right: [child(right, a), child(right, b)],
        }
    };
    let mut used = vec![false; topo.edges.len()];
    let mut paths = Vec::new();
    for start in 0..nv {
        if !is_node(start) {
            continue;
        }
        for &e0 in &cut_edges_at[start] {
            if used[e0] {
                continue;
            }
            let mut vertices = vec![start];
            let mut path_sides = Vec::new();
            let (mut v, mut e) = (start, e0);
            loop {
                used[e] = true;
                let [a, b] = topo.edges[e];
                let w = if a == v { b } else { a };
                path_sides.push(sides(v, w, e));
                vertices.push(w);
                if is_node(w) {
                    break;
                }
                match cut_edges_at[w].iter().find(|&&x| !used[x]) {
                    Some(&next) => {
                        v = w;
                        e = next;
                    }
                    None => break,
                }
            }
            paths.push(CutPath {
                vertices,
                sides: path_sides,
            });
        }
    }
    paths
}

/// A total order on f64 for the heap (distances are finite).
#[derive(Clone, Copy, Debug, PartialEq)]
struct OrdF64(f64);

impl Eq for OrdF64 {}

impl PartialOrd for OrdF64 {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for OrdF64 {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&other.0)
    }
}

mod forest;

#[cfg(test)]
mod tests;
