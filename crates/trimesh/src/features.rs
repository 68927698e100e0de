//! Feature detection: which edges are feature edges (dihedral angle above the
//! threshold, open boundary, user-given), and which vertices are corners
//! (where the number of curve edges is not 2, or where a chain of feature
//! edges turns by more than the threshold).

use geometry::{vec3, Vec3};

use crate::topology::Topology;

/// Unit normal of each triangle.
pub fn tri_normals(points: &[Vec3], tris: &[[u32; 3]]) -> Vec<Vec3> {
    tris.iter()
        .map(|t| {
            let [a, b, c] = t.map(|v| points[v as usize]);
            vec3::normalize(vec3::cross(vec3::sub(b, a), vec3::sub(c, a))).unwrap_or([0.0; 3])
        })
        .collect()
}

/// Feature flag of every edge: open boundary, or dihedral angle (between
/// the two triangle normals) above `angle` radians, or in `user` (edges given
/// as welded vertex pairs; `Err` gives the index in `user` of a pair that is
/// not an edge of the mesh).
pub fn feature_edges(
    normals: &[Vec3],
    topo: &Topology,
    angle: f64,
    user: &[[u32; 2]],
) -> Result<Vec<bool>, usize> {
    let cos = angle.cos();
    let mut f: Vec<bool> = topo
        .edge_tris
        .iter()
        .map(|&[t0, t1]| {
            t1 == u32::MAX || vec3::dot(normals[t0 as usize], normals[t1 as usize]) < cos
        })
        .collect();
    if !user.is_empty() {
        let mut index: Vec<(u64, u32)> = topo
            .edges
            .iter()
            .enumerate()
            .map(|(e, &[a, b])| (((a as u64) << 32) | b as u64, e as u32))
            .collect();
        index.sort_unstable();
        for (i, &[a, b]) in user.iter().enumerate() {
            let key = ((a.min(b) as u64) << 32) | a.max(b) as u64;
            match index.binary_search_by_key(&key, |x| x.0) {
                Ok(k) => f[index[k].1 as usize] = true,
                Err(_) => return Err(i),
            }
        }
    }
    Ok(f)
}

/// The curve edges at each vertex (compressed rows: `offsets[v]..offsets[v+1]`
/// into `edges`).
pub struct VertexEdges {
    /// Row starts, one more than the vertices.
    pub offsets: Vec<u32>,
    /// Edge ids.
    pub edges: Vec<u32>,
}

impl VertexEdges {
    /// The flagged edges around every vertex.
    pub fn new(nverts: usize, topo: &Topology, flag: &[bool]) -> Self {
        let mut offsets = vec![0u32; nverts + 1];
        for (e, &[a, b]) in topo.edges.iter().enumerate() {
            if flag[e] {
                offsets[a as usize + 1] += 1;
                offsets[b as usize + 1] += 1;
            }
        }
        for v in 0..nverts {
            offsets[v + 1] += offsets[v];
        }
        let mut fill = offsets.clone();
        let mut edges = vec![0u32; offsets[nverts] as usize];
        for (e, &[a, b]) in topo.edges.iter().enumerate() {
            if flag[e] {
                for v in [a, b] {
                    edges[fill[v as usize] as usize] = e as u32;
                    fill[v as usize] += 1;
                }
            }
        }
        VertexEdges { offsets, edges }
    }

    /// Edges at vertex `v`.
    pub fn at(&self, v: usize) -> &[u32] {
        &self.edges[self.offsets[v] as usize..self.offsets[v + 1] as usize]
    }
}

/// Corner flag of every vertex: the number of flagged edges there is neither
/// 0 nor 2, or it is 2 and the chain turns by more than `angle` radians.
pub fn corners(points: &[Vec3], topo: &Topology, flag: &[bool], angle: f64) -> Vec<bool> {
    let ve = VertexEdges::new(points.len(), topo, flag);
    let cos = angle.cos();
    (0..points.len())
        .map(|v| {
            let es = ve.at(v);
            match es.len() {
                0 => false,
                2 => {
                    let other = |e: u32| {
                        let [a, b] = topo.edges[e as usize];
                        if a as usize == v {
                            b
                        } else {
                            a
                        }
                    };
                    let (p, q) = (points[other(es[0]) as usize], points[other(es[1]) as usize]);
                    let d0 = vec3::normalize(vec3::sub(points[v], p));
                    let d1 = vec3::normalize(vec3::sub(q, points[v]));
                    match (d0, d1) {
                        (Some(d0), Some(d1)) => vec3::dot(d0, d1) < cos,
                        _ => true,
                    }
                }
                _ => true,
            }
        })
        .collect()
}
