//! Refinement of the one-rings of cones before the flow (issue 31, notes:
//! a cone on a coarse neighbourhood makes the Newton steps fail). Every edge
//! at a cone is split at its midpoint and each triangle is split by the set
//! of its split edges, so the mesh stays conforming and its geometry (a
//! polyhedron) is unchanged. New vertices are appended: old vertex indices,
//! cones included, keep their meaning.

use crate::shell::{Shell, ShellTopology};

/// The shell with every edge incident to a vertex of `cones` split at its
/// midpoint, each triangle split accordingly (2, 3 or 4 children).
pub fn refine_cone_rings(shell: &Shell, topo: &ShellTopology, cones: &[usize]) -> Shell {
    let mut is_cone = vec![false; shell.vertices.len()];
    for &c in cones {
        if c < is_cone.len() {
            is_cone[c] = true;
        }
    }
    let mut vertices = shell.vertices.clone();
    let mut midpoint = vec![usize::MAX; topo.edges.len()];
    for (e, &[a, b]) in topo.edges.iter().enumerate() {
        if is_cone[a] || is_cone[b] {
            let (p, q) = (shell.vertices[a], shell.vertices[b]);
            midpoint[e] = vertices.len();
            vertices.push([
                0.5 * (p[0] + q[0]),
                0.5 * (p[1] + q[1]),
                0.5 * (p[2] + q[2]),
            ]);
        }
    }
    let mut triangles = Vec::with_capacity(shell.triangles.len());
    for (f, t) in shell.triangles.iter().enumerate() {
        let m = topo.triangle_edges[f].map(|e| midpoint[e]);
        let split: Vec<usize> = (0..3).filter(|&k| m[k] != usize::MAX).collect();
        match split.len() {
            0 => triangles.push(*t),
            1 => {
                // Side k (corner k → k+1) split at m: two triangles.
                let k = split[0];
                let (a, b, c) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
                triangles.push([a, m[k], c]);
                triangles.push([m[k], b, c]);
            }
            2 => {
                // The unsplit side j: its corners j, j+1 and the third corner c.
                let j = (0..3).find(|k| !split.contains(k)).unwrap_or(0);
                let (a, b, c) = (t[j], t[(j + 1) % 3], t[(j + 2) % 3]);
                let (mbc, mca) = (m[(j + 1) % 3], m[(j + 2) % 3]);
                triangles.push([c, mca, mbc]);
                triangles.push([mca, a, b]);
                triangles.push([mca, b, mbc]);
            }
            _ => {
                let (a, b, c) = (t[0], t[1], t[2]);
                let (mab, mbc, mca) = (m[0], m[1], m[2]);
                triangles.push([a, mab, mca]);
                triangles.push([mab, b, mbc]);
                triangles.push([mca, mbc, c]);
                triangles.push([mab, mbc, mca]);
            }
        }
    }
    Shell {
        vertices,
        triangles,
    }
}
