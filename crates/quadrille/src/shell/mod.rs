//! S0–S1 of `quadrille spline` (spec ricci-flow-iga-reconstruction §1.1, §3):
//! an open shell as a plain welded, indexed triangle mesh, and the topology
//! checks every later stage relies on (manifold, consistently oriented,
//! genus 0, at least one boundary loop), with the Euler characteristic, the
//! ordered boundary loops and the edge table the Ricci flow, the cut graph
//! and the immersion share.

use geometry::vec3::{cross, norm, sub};
use thiserror::Error;

mod from_model;
pub use from_model::shell_from_model;

/// Marks a missing face in [`ShellTopology::edge_faces`] (a boundary edge).
pub const NO_FACE: usize = usize::MAX;

/// An open shell: a welded triangle mesh whose triangles are counter-clockwise
/// seen from the side the shell's normal points to.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Shell {
    /// Vertex positions.
    pub vertices: Vec<[f64; 3]>,
    /// Triangles as three vertex indices each.
    pub triangles: Vec<[usize; 3]>,
}

/// The topology of a checked [`Shell`]: edges, their faces, boundary loops,
/// Euler characteristic, genus and components.
#[derive(Clone, Debug, PartialEq)]
pub struct ShellTopology {
    /// Undirected edges `[a, b]` with `a < b`, sorted.
    pub edges: Vec<[usize; 2]>,
    /// Per edge: the face holding the half-edge `a → b` and the face holding
    /// `b → a` ([`NO_FACE`] when absent: a boundary edge).
    pub edge_faces: Vec<[usize; 2]>,
    /// Per triangle, per side `k`: the edge from corner `k` to corner `k + 1`.
    pub triangle_edges: Vec<[usize; 3]>,
    /// Boundary loops, each an ordered vertex cycle following the triangles'
    /// orientation (the shell lies to the left).
    pub boundary_loops: Vec<Vec<usize>>,
    /// Per vertex: on a boundary loop.
    pub on_boundary: Vec<bool>,
    /// χ = V − E + F.
    pub euler: i64,
    /// Total genus over the components, from χ = Σ (2 − 2g − b).
    pub genus: usize,
    /// Number of face-connected components.
    pub components: usize,
}

impl ShellTopology {
    /// The edge joining `a` and `b`, if any.
    pub fn edge(&self, a: usize, b: usize) -> Option<usize> {
        let key = [a.min(b), a.max(b)];
        self.edges.binary_search(&key).ok()
    }

    /// True when edge `e` has one face only.
    pub fn is_boundary_edge(&self, e: usize) -> bool {
        self.edge_faces[e].contains(&NO_FACE)
    }
}

/// Why a shell is not an open, oriented, genus-0 manifold triangle mesh.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ShellError {
    /// No triangles.
    #[error("shell: no triangles")]
    Empty,
    /// A triangle refers to a vertex that does not exist.
    #[error("shell triangle {triangle}: vertex index {index} out of range (the shell has {count} vertices)")]
    BadIndex {
        /// The triangle.
        triangle: usize,
        /// The bad index.
        index: usize,
        /// Number of vertices.
        count: usize,
    },
    /// A triangle uses one vertex twice.
    #[error("shell triangle {triangle}: vertex {vertex} repeated")]
    RepeatedVertex {
        /// The triangle.
        triangle: usize,
        /// The repeated vertex.
        vertex: usize,
    },
    /// A vertex no triangle uses.
    #[error("shell vertex {vertex} at {position:?}: used by no triangle")]
    UnusedVertex {
        /// The vertex.
        vertex: usize,
        /// Its position.
        position: [f64; 3],
    },
    /// An edge with more than two triangles.
    #[error("non-manifold edge between {a:?} and {b:?}: {count} triangles")]
    NonManifoldEdge {
        /// One end point.
        a: [f64; 3],
        /// The other end point.
        b: [f64; 3],
        /// Triangles on the edge.
        count: usize,
    },
    /// Two triangles run through their common edge the same way.
    #[error("inconsistently oriented triangles {first} and {second} on the edge between {a:?} and {b:?}")]
    Orientation {
        /// One triangle.
        first: usize,
        /// The other.
        second: usize,
        /// One end point.
        a: [f64; 3],
        /// The other end point.
        b: [f64; 3],
    },
    /// A vertex whose triangles form more than one fan (a bow tie).
    #[error("non-manifold vertex {vertex} at {position:?}: its triangles form {fans} fans")]
    NonManifoldVertex {
        /// The vertex.
        vertex: usize,
        /// Its position.
        position: [f64; 3],
        /// Fans found (at least 2).
        fans: usize,
    },
    /// A component without boundary.
    #[error(
        "closed shell (component {component} has no boundary loop): open shells only; use --faces"
    )]
    Closed {
        /// The closed component.
        component: usize,
    },
    /// Genus above zero.
    #[error("shell of genus {genus} (χ = {euler}, {loops} boundary loops, {components} components): only genus-0 shells")]
    Genus {
        /// Total genus.
        genus: i64,
        /// Euler characteristic.
        euler: i64,
        /// Boundary loops.
        loops: usize,
        /// Components.
        components: usize,
    },
}

/// Find with path halving (union–find over indices).
pub(crate) fn find(parent: &mut [usize], mut x: usize) -> usize {
    while parent[x] != x {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    x
}

/// Union of the sets of `a` and `b`; the smaller root wins (deterministic).
pub(crate) fn union(parent: &mut [usize], a: usize, b: usize) {
    let (ra, rb) = (find(parent, a), find(parent, b));
    if ra != rb {
        let (lo, hi) = (ra.min(rb), ra.max(rb));
        parent[hi] = lo;
    }
}

/// The interior angle between vectors `a` and `b` (robust near 0 and π).
pub(crate) fn angle_between(a: [f64; 3], b: [f64; 3]) -> f64 {
    let c = cross(a, b);
    let d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    norm(c).atan2(d)
}

impl Shell {
    /// A shell from vertex positions and triangles (kept as given).
    pub fn from_triangles(vertices: Vec<[f64; 3]>, triangles: Vec<[usize; 3]>) -> Shell {
        Shell {
            vertices,
            triangles,
        }
    }

    /// A shell from vertex positions and triangles, keeping only the vertices
    /// some triangle uses (in order of first use), triangles renumbered.
    pub fn from_used_vertices(vertices: &[[f64; 3]], mut triangles: Vec<[usize; 3]>) -> Shell {
        let mut used = vec![usize::MAX; vertices.len()];
        let mut kept = Vec::new();
        for t in &mut triangles {
            for v in t.iter_mut() {
                if used[*v] == usize::MAX {
                    used[*v] = kept.len();
                    kept.push(vertices[*v]);
                }
                *v = used[*v];
            }
        }
        Shell::from_triangles(kept, triangles)
    }

    /// A shell from triangle soup: vertices at bit-identical positions merged
    /// into one (the first, in order of position), triangles renumbered.
    /// Triangles that collapse (two corners merged) are dropped.
    pub fn welded(vertices: &[[f64; 3]], triangles: &[[usize; 3]]) -> Shell {
        let mut order: Vec<usize> = (0..vertices.len()).collect();
        let key = |v: usize| vertices[v].map(|c| if c == 0.0 { 0.0 } else { c });
        order.sort_by(|&a, &b| {
            let (p, q) = (key(a), key(b));
            p[0].total_cmp(&q[0])
                .then(p[1].total_cmp(&q[1]))
                .then(p[2].total_cmp(&q[2]))
                .then(a.cmp(&b))
        });
        let mut new_id = vec![0usize; vertices.len()];
        let mut merged: Vec<[f64; 3]> = Vec::new();
        let mut last: Option<[f64; 3]> = None;
        for &v in &order {
            let p = key(v);
            if last != Some(p) {
                merged.push(vertices[v]);
                last = Some(p);
            }
            new_id[v] = merged.len() - 1;
        }
        let triangles = triangles
            .iter()
            .map(|t| t.map(|v| new_id[v]))
            .filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
            .collect();
        Shell {
            vertices: merged,
            triangles,
        }
    }

    /// A shell from a quad mesh, each quad `[a, b, c, d]` (counter-clockwise)
    /// split along its shorter diagonal (spec §3, the faceted-input path).
    pub fn from_quad_mesh(vertices: Vec<[f64; 3]>, quads: &[[usize; 4]]) -> Shell {
        let mut triangles = Vec::with_capacity(2 * quads.len());
        for q in quads {
            let d02 = norm(sub(vertices[q[0]], vertices[q[2]]));
            let d13 = norm(sub(vertices[q[1]], vertices[q[3]]));
            if d02 <= d13 {
                triangles.push([q[0], q[1], q[2]]);
                triangles.push([q[0], q[2], q[3]]);
            } else {
                triangles.push([q[0], q[1], q[3]]);
                triangles.push([q[1], q[2], q[3]]);
            }
        }
        Shell {
            vertices,
            triangles,
        }
    }

    /// The 3D length of the edge `a`–`b`.
    pub fn edge_length(&self, a: usize, b: usize) -> f64 {
        norm(sub(self.vertices[a], self.vertices[b]))
    }

    /// Per triangle, per corner: the 3D angle.
    pub fn corner_angles(&self) -> Vec<[f64; 3]> {
        self.triangles
            .iter()
            .map(|t| {
                let mut a = [0.0; 3];
                for k in 0..3 {
                    let p = self.vertices[t[k]];
                    a[k] = angle_between(
                        sub(self.vertices[t[(k + 1) % 3]], p),
                        sub(self.vertices[t[(k + 2) % 3]], p),
                    );
                }
                a
            })
            .collect()
    }

    /// Per vertex: the sum of its 3D triangle angles.
    pub fn angle_sums(&self) -> Vec<f64> {
        let mut sums = vec![0.0; self.vertices.len()];
        for (t, a) in self.triangles.iter().zip(self.corner_angles()) {
            for k in 0..3 {
                sums[t[k]] += a[k];
            }
        }
        sums
    }

    /// Total 3D area.
    pub fn area(&self) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let p = self.vertices[t[0]];
                0.5 * norm(cross(
                    sub(self.vertices[t[1]], p),
                    sub(self.vertices[t[2]], p),
                ))
            })
            .sum()
    }

    /// Checks S1 (manifold, oriented, open, genus 0) and returns the topology.
    pub fn check(&self) -> Result<ShellTopology, ShellError> {
        let nv = self.vertices.len();
        let nf = self.triangles.len();
        if nf == 0 {
            return Err(ShellError::Empty);
        }
        let mut used = vec![false; nv];
        for (f, t) in self.triangles.iter().enumerate() {
            for &v in t {
                if v >= nv {
                    return Err(ShellError::BadIndex {
                        triangle: f,
                        index: v,
                        count: nv,
                    });
                }
                used[v] = true;
            }
            if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
                let vertex = if t[0] == t[1] || t[0] == t[2] {
                    t[0]
                } else {
                    t[1]
                };
                return Err(ShellError::RepeatedVertex {
                    triangle: f,
                    vertex,
                });
            }
        }
        if let Some(v) = used.iter().position(|u| !u) {
            return Err(ShellError::UnusedVertex {
                vertex: v,
                position: self.vertices[v],
            });
        }
        // Half-edges sorted by their undirected key: runs of equal keys are edges.
        let mut half: Vec<([usize; 2], usize, usize)> = Vec::with_capacity(3 * nf);
        for (f, t) in self.triangles.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                half.push(([a.min(b), a.max(b)], f, k));
            }
        }
        half.sort_unstable();
        let mut edges = Vec::new();
        let mut edge_faces = Vec::new();
        let mut triangle_edges = vec![[0usize; 3]; nf];
        let mut i = 0;
        while i < half.len() {
            let key = half[i].0;
            let mut j = i;
            while j < half.len() && half[j].0 == key {
                j += 1;
            }
            let (a, b) = (self.vertices[key[0]], self.vertices[key[1]]);
            if j - i > 2 {
                return Err(ShellError::NonManifoldEdge { a, b, count: j - i });
            }
            let e = edges.len();
            let mut faces = [NO_FACE; 2];
            for &(_, f, k) in &half[i..j] {
                let forward = self.triangles[f][k] == key[0];
                let slot = if forward { 0 } else { 1 };
                if faces[slot] != NO_FACE {
                    return Err(ShellError::Orientation {
                        first: faces[slot],
                        second: f,
                        a,
                        b,
                    });
                }
                faces[slot] = f;
                triangle_edges[f][k] = e;
            }
            edges.push(key);
            edge_faces.push(faces);
            i = j;
        }
        let topo_edges = ShellTopology {
            edges,
            edge_faces,
            triangle_edges,
            boundary_loops: Vec::new(),
            on_boundary: vec![false; nv],
            euler: 0,
            genus: 0,
            components: 0,
        };
        self.finish_topology(topo_edges)
    }

    /// Vertex fans, boundary loops, components, χ and genus.
    fn finish_topology(&self, mut topo: ShellTopology) -> Result<ShellTopology, ShellError> {
        let nv = self.vertices.len();
        let nf = self.triangles.len();
        // The face across side k of f.
        let across = |topo: &ShellTopology, f: usize, k: usize| -> usize {
            let e = topo.triangle_edges[f][k];
            let [f0, f1] = topo.edge_faces[e];
            if f0 == f {
                f1
            } else {
                f0
            }
        };
        // Corners per vertex, and for each the boundary-fan starts.
        let mut corner_count = vec![0usize; nv];
        let mut first_corner = vec![(NO_FACE, 0usize); nv];
        let mut starts = vec![0usize; nv];
        let mut start_corner = vec![(NO_FACE, 0usize); nv];
        for (f, t) in self.triangles.iter().enumerate() {
            for (k, &v) in t.iter().enumerate() {
                corner_count[v] += 1;
                if first_corner[v].0 == NO_FACE {
                    first_corner[v] = (f, k);
                }
                // The side entering v (corner k+2 → k) on the boundary starts a fan.
                if across(&topo, f, (k + 2) % 3) == NO_FACE {
                    starts[v] += 1;
                    if start_corner[v].0 == NO_FACE {
                        start_corner[v] = (f, k);
                    }
                    topo.on_boundary[v] = true;
                }
            }
        }
        for v in 0..nv {
            let (mut f, mut k) = if starts[v] > 0 {
                start_corner[v]
            } else {
                first_corner[v]
            };
            let (f0, k0) = (f, k);
            let mut seen = 1;
            // Walk across the side leaving v (corner k → k+1).
            loop {
                let g = across(&topo, f, k);
                if g == NO_FACE || g == f0 {
                    break;
                }
                k = (0..3).position(|m| self.triangles[g][m] == v).unwrap_or(0);
                f = g;
                seen += 1;
                if seen > corner_count[v] {
                    break;
                }
            }
            let _ = k0;
            if starts[v] > 1 || seen != corner_count[v] {
                return Err(ShellError::NonManifoldVertex {
                    vertex: v,
                    position: self.vertices[v],
                    fans: starts[v].max(2),
                });
            }
        }
        // Components over faces.
        let mut parent: Vec<usize> = (0..nf).collect();
        for faces in &topo.edge_faces {
            if faces[0] != NO_FACE && faces[1] != NO_FACE {
                union(&mut parent, faces[0], faces[1]);
            }
        }
        let mut component_of_root = vec![usize::MAX; nf];
        let mut components = 0;
        let mut face_component = vec![0usize; nf];
        for (f, component) in face_component.iter_mut().enumerate() {
            let r = find(&mut parent, f);
            if component_of_root[r] == usize::MAX {
                component_of_root[r] = components;
                components += 1;
            }
            *component = component_of_root[r];
        }
        // Boundary loops: the next boundary half-edge leaves the vertex the
        // previous one enters (unique at a manifold vertex).
        let mut next_on_boundary = vec![usize::MAX; nv];
        let mut boundary_face_of = vec![NO_FACE; nv];
        for (e, faces) in topo.edge_faces.iter().enumerate() {
            let [a, b] = topo.edges[e];
            if faces[1] == NO_FACE {
                next_on_boundary[a] = b;
                boundary_face_of[a] = faces[0];
            } else if faces[0] == NO_FACE {
                next_on_boundary[b] = a;
                boundary_face_of[b] = faces[1];
            }
        }
        let mut visited = vec![false; nv];
        let mut loop_components = vec![0usize; components];
        for v in 0..nv {
            if next_on_boundary[v] == usize::MAX || visited[v] {
                continue;
            }
            let mut cycle = Vec::new();
            let mut w = v;
            while !visited[w] {
                visited[w] = true;
                cycle.push(w);
                w = next_on_boundary[w];
            }
            loop_components[face_component[boundary_face_of[v]]] += 1;
            topo.boundary_loops.push(cycle);
        }
        topo.euler = nv as i64 - topo.edges.len() as i64 + nf as i64;
        topo.components = components;
        if let Some(c) = loop_components.iter().position(|&n| n == 0) {
            return Err(ShellError::Closed { component: c });
        }
        let b = topo.boundary_loops.len() as i64;
        let twice_genus = 2 * components as i64 - b - topo.euler;
        if twice_genus != 0 {
            return Err(ShellError::Genus {
                genus: twice_genus / 2,
                euler: topo.euler,
                loops: topo.boundary_loops.len(),
                components,
            });
        }
        topo.genus = 0;
        Ok(topo)
    }
}

#[cfg(test)]
pub(crate) mod tests;
