//! Mesh topology and local frames of one face triangulation, as the
//! Crouzeix–Raviart cross field needs them (spec §2.2).
//!
//! Built once per face from a [`FaceMesh`]: vertices that coincide in 3D on
//! the face boundary are welded (seam copies, pole copies), collapsed
//! triangles are dropped, edges are numbered deterministically (sorted vertex
//! pairs), and each triangle gets its normal, area and the rotation that takes
//! each edge's own frame into the triangle frame.

use geometry::vec3::{self, Vec3};

use super::{CrossFieldError, FaceMesh, VertexClass};

/// No triangle / no edge marker in adjacency tables.
pub const NONE: u32 = u32::MAX;

/// A complex number `(re, im)`; used for `e^{i·4φ}` frame rotations and cross
/// representation vectors `u = (cos 4θ, sin 4θ)`.
pub type Cplx = [f64; 2];

/// Complex product `a · b`.
#[inline]
pub fn cmul(a: Cplx, b: Cplx) -> Cplx {
    [a[0] * b[0] - a[1] * b[1], a[0] * b[1] + a[1] * b[0]]
}

/// Complex conjugate.
#[inline]
pub fn conj(a: Cplx) -> Cplx {
    [a[0], -a[1]]
}

/// Argument of `b / a` (the representation-angle step from `a` to `b`), in (−π, π].
#[inline]
pub fn arg_ratio(a: Cplx, b: Cplx) -> f64 {
    let r = cmul(b, conj(a));
    r[1].atan2(r[0])
}

/// Topology, geometry and frames of one face triangulation after welding.
///
/// Local edge `a` of triangle `t` is the edge opposite its local vertex `a`,
/// i.e. `(triangles[t][a+1], triangles[t][a+2])` (indices mod 3).
#[derive(Clone, Debug)]
pub struct FaceTopology {
    /// Input vertex → welded vertex.
    pub vertex_map: Vec<u32>,
    /// Welded vertex positions.
    pub positions: Vec<Vec3>,
    /// Welded vertex classes (a corner wins over a curve, a curve over interior).
    pub class: Vec<VertexClass>,
    /// Triangles on welded vertices, consistently oriented; collapsed ones removed.
    pub triangles: Vec<[u32; 3]>,
    /// Edges as sorted vertex pairs `[a, b]`, `a < b`, sorted lexicographically.
    pub edges: Vec<[u32; 2]>,
    /// Per triangle, the edge id of each local edge.
    pub tri_edges: Vec<[u32; 3]>,
    /// Per edge, its one or two triangles (`NONE` when absent).
    pub edge_tris: Vec<[u32; 2]>,
    /// Per edge: true when the edge carries a Dirichlet (feature) condition —
    /// a boundary edge of the triangulation or an embedded feature edge.
    pub feature: Vec<bool>,
    /// Per vertex: true when it is an endpoint of a mesh-boundary edge.
    pub on_boundary: Vec<bool>,
    /// Per vertex: true when it is an endpoint of a feature edge.
    pub on_feature: Vec<bool>,
    /// Unit normal of each triangle (`(p1 − p0) × (p2 − p0)` normalized).
    pub normals: Vec<Vec3>,
    /// Area of each triangle.
    pub areas: Vec<f64>,
    /// Unit reference direction of each edge: from its lower to its higher vertex id.
    pub edge_dir: Vec<Vec3>,
    /// Per triangle and local edge: `e^{i·4φ}`, φ the angle of the edge
    /// direction in the triangle frame (`x_T` = direction of local edge 0).
    pub rot4: Vec<[Cplx; 3]>,
    /// Length of the shortest edge.
    pub h_min: f64,
    /// Diagonal of the 3D bounding box.
    pub diagonal: f64,
}

fn find(parent: &mut [u32], mut i: u32) -> u32 {
    while parent[i as usize] != i {
        let p = parent[parent[i as usize] as usize];
        parent[i as usize] = p;
        i = p;
    }
    i
}

fn rank(c: VertexClass) -> u8 {
    match c {
        VertexClass::Interior => 0,
        VertexClass::Curve(_) => 1,
        VertexClass::Corner(_) => 2,
    }
}

/// Welds boundary-class vertices that coincide in 3D; returns input → welded
/// map and the number of welded vertices. Representatives keep the lowest
/// input id, so the result does not depend on anything but the input order.
fn weld(mesh: &FaceMesh, diagonal: f64) -> (Vec<u32>, usize) {
    let n = mesh.xyz.len();
    let mut parent: Vec<u32> = (0..n as u32).collect();
    let tol = 1e-9 * diagonal.max(f64::MIN_POSITIVE);
    let mut cand: Vec<u32> = (0..n as u32)
        .filter(|&i| mesh.vertex_class[i as usize] != VertexClass::Interior)
        .collect();
    cand.sort_by(|&a, &b| {
        mesh.xyz[a as usize][0]
            .total_cmp(&mesh.xyz[b as usize][0])
            .then(a.cmp(&b))
    });
    for (k, &a) in cand.iter().enumerate() {
        let pa = mesh.xyz[a as usize];
        for &b in &cand[k + 1..] {
            let pb = mesh.xyz[b as usize];
            if pb[0] - pa[0] > tol {
                break;
            }
            if vec3::dist(pa, pb) <= tol {
                let (ra, rb) = (find(&mut parent, a), find(&mut parent, b));
                if ra != rb {
                    let (lo, hi) = if ra < rb { (ra, rb) } else { (rb, ra) };
                    parent[hi as usize] = lo;
                }
            }
        }
    }
    let mut map = vec![NONE; n];
    let mut count = 0u32;
    for i in 0..n as u32 {
        let r = find(&mut parent, i);
        if map[r as usize] == NONE {
            map[r as usize] = count;
            count += 1;
        }
        map[i as usize] = map[r as usize];
    }
    (map, count as usize)
}

impl FaceTopology {
    /// Builds the topology of `mesh`. Errors on inconsistent sizes, bad
    /// indices, non-finite coordinates, non-manifold or inconsistently oriented
    /// edges, degenerate (zero-area) triangles and empty meshes.
    pub fn build(mesh: &FaceMesh) -> Result<FaceTopology, CrossFieldError> {
        let n_in = mesh.xyz.len();
        if mesh.vertex_class.len() != n_in {
            return Err(CrossFieldError::InvalidInput(format!(
                "{} positions but {} vertex classes",
                n_in,
                mesh.vertex_class.len()
            )));
        }
        if mesh.triangles.is_empty() {
            return Err(CrossFieldError::InvalidInput("no triangles".into()));
        }
        if let Some(i) = mesh
            .xyz
            .iter()
            .position(|p| p.iter().any(|c| !c.is_finite()))
        {
            return Err(CrossFieldError::InvalidInput(format!(
                "vertex {i} has a non-finite coordinate"
            )));
        }
        for (t, tri) in mesh.triangles.iter().enumerate() {
            if tri.iter().any(|&v| v as usize >= n_in) {
                return Err(CrossFieldError::InvalidInput(format!(
                    "triangle {t} references a missing vertex"
                )));
            }
        }
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for p in &mesh.xyz {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let diagonal = vec3::dist(lo, hi);
        let (vertex_map, nv) = weld(mesh, diagonal);
        let mut positions = vec![[0.0; 3]; nv];
        let mut class = vec![VertexClass::Interior; nv];
        for i in 0..n_in {
            let w = vertex_map[i] as usize;
            let c = mesh.vertex_class[i];
            // a corner class wins over a curve class, a curve class over interior
            if rank(c) > rank(class[w]) {
                class[w] = c;
            }
        }
        let mut written = vec![false; nv];
        for i in 0..n_in {
            let w = vertex_map[i] as usize;
            if !written[w] {
                positions[w] = mesh.xyz[i];
                written[w] = true;
            }
        }
        let triangles: Vec<[u32; 3]> = mesh
            .triangles
            .iter()
            .map(|t| {
                [
                    vertex_map[t[0] as usize],
                    vertex_map[t[1] as usize],
                    vertex_map[t[2] as usize],
                ]
            })
            .filter(|t| t[0] != t[1] && t[1] != t[2] && t[2] != t[0])
            .collect();
        if triangles.is_empty() {
            return Err(CrossFieldError::InvalidInput(
                "all triangles collapse after welding".into(),
            ));
        }

        // Edges: (key, triangle, local edge, forward) sorted by key then triangle.
        let mut half: Vec<([u32; 2], u32, u8, bool)> = Vec::with_capacity(3 * triangles.len());
        for (t, tri) in triangles.iter().enumerate() {
            for a in 0..3 {
                let (p, q) = (tri[(a + 1) % 3], tri[(a + 2) % 3]);
                half.push(([p.min(q), p.max(q)], t as u32, a as u8, p < q));
            }
        }
        half.sort_unstable_by(|x, y| x.0.cmp(&y.0).then(x.1.cmp(&y.1)));
        let mut edges: Vec<[u32; 2]> = Vec::with_capacity(half.len() / 2 + 8);
        let mut edge_tris: Vec<[u32; 2]> = Vec::with_capacity(half.len() / 2 + 8);
        let mut tri_edges = vec![[NONE; 3]; triangles.len()];
        let mut i = 0;
        while i < half.len() {
            let mut j = i + 1;
            while j < half.len() && half[j].0 == half[i].0 {
                j += 1;
            }
            if j - i > 2 {
                return Err(CrossFieldError::InvalidInput(format!(
                    "non-manifold edge ({}, {}) used by {} triangles",
                    half[i].0[0],
                    half[i].0[1],
                    j - i
                )));
            }
            if j - i == 2 && half[i].3 == half[i + 1].3 {
                return Err(CrossFieldError::InvalidInput(format!(
                    "triangles {} and {} are inconsistently oriented",
                    half[i].1,
                    half[i + 1].1
                )));
            }
            let e = edges.len() as u32;
            edges.push(half[i].0);
            let mut et = [NONE; 2];
            for (k, h) in half[i..j].iter().enumerate() {
                et[k] = h.1;
                tri_edges[h.1 as usize][h.2 as usize] = e;
            }
            edge_tris.push(et);
            i = j;
        }

        let ne = edges.len();
        let mut feature: Vec<bool> = edge_tris.iter().map(|t| t[1] == NONE).collect();
        let mut on_boundary = vec![false; nv];
        for (e, f) in feature.iter().enumerate() {
            if *f {
                on_boundary[edges[e][0] as usize] = true;
                on_boundary[edges[e][1] as usize] = true;
            }
        }
        for fe in &mesh.feature_edges {
            if fe.iter().any(|&v| v as usize >= n_in) {
                return Err(CrossFieldError::InvalidInput(
                    "feature edge references a missing vertex".into(),
                ));
            }
            let (p, q) = (vertex_map[fe[0] as usize], vertex_map[fe[1] as usize]);
            let key = [p.min(q), p.max(q)];
            if let Ok(e) = edges.binary_search(&key) {
                feature[e] = true;
            }
        }
        let mut on_feature = vec![false; nv];
        for e in 0..ne {
            if feature[e] {
                on_feature[edges[e][0] as usize] = true;
                on_feature[edges[e][1] as usize] = true;
            }
        }

        let mut edge_dir = Vec::with_capacity(ne);
        let mut h_min = f64::INFINITY;
        for (e, &[a, b]) in edges.iter().enumerate() {
            let d = vec3::sub(positions[b as usize], positions[a as usize]);
            let l = vec3::norm(d);
            if !(l > 0.0) {
                return Err(CrossFieldError::InvalidInput(format!(
                    "edge {e} ({a}, {b}) has zero length"
                )));
            }
            h_min = h_min.min(l);
            edge_dir.push(vec3::scale(d, 1.0 / l));
        }

        let mut normals = Vec::with_capacity(triangles.len());
        let mut areas = Vec::with_capacity(triangles.len());
        let mut rot4 = Vec::with_capacity(triangles.len());
        for (t, tri) in triangles.iter().enumerate() {
            let p = [
                positions[tri[0] as usize],
                positions[tri[1] as usize],
                positions[tri[2] as usize],
            ];
            let c = vec3::cross(vec3::sub(p[1], p[0]), vec3::sub(p[2], p[0]));
            let twice = vec3::norm(c);
            let lmax = (0..3)
                .map(|a| vec3::dist(p[a], p[(a + 1) % 3]))
                .fold(0.0, f64::max);
            if !(twice > 1e-14 * lmax * lmax) {
                return Err(CrossFieldError::InvalidInput(format!(
                    "triangle {t} is degenerate (zero area)"
                )));
            }
            let n = vec3::scale(c, 1.0 / twice);
            let x = edge_dir[tri_edges[t][0] as usize];
            let y = vec3::cross(n, x);
            let mut r = [[1.0, 0.0]; 3];
            for a in 0..3 {
                let d = edge_dir[tri_edges[t][a] as usize];
                let (cs, sn) = (vec3::dot(d, x), vec3::dot(d, y));
                let m = (cs * cs + sn * sn).sqrt();
                let z = [cs / m, sn / m];
                let z2 = cmul(z, z);
                r[a] = cmul(z2, z2);
            }
            normals.push(n);
            areas.push(0.5 * twice);
            rot4.push(r);
        }

        Ok(FaceTopology {
            vertex_map,
            positions,
            class,
            triangles,
            edges,
            tri_edges,
            edge_tris,
            feature,
            on_boundary,
            on_feature,
            normals,
            areas,
            edge_dir,
            rot4,
            h_min,
            diagonal,
        })
    }

    /// Euler characteristic V − E + F of the welded triangulation.
    pub fn euler_characteristic(&self) -> i64 {
        self.positions.len() as i64 - self.edges.len() as i64 + self.triangles.len() as i64
    }

    /// Edge vector opposite local vertex `a` of triangle `t`, oriented along
    /// the triangle (`p[a+2] − p[a+1]`).
    pub fn opposite_edge_vector(&self, t: usize, a: usize) -> Vec3 {
        let tri = self.triangles[t];
        vec3::sub(
            self.positions[tri[(a + 2) % 3] as usize],
            self.positions[tri[(a + 1) % 3] as usize],
        )
    }

    /// Interior angle of triangle `t` at its local vertex `a`.
    pub fn corner_angle(&self, t: usize, a: usize) -> f64 {
        let u = self.opposite_edge_vector(t, (a + 2) % 3); // p[a+1] − p[a]
        let v = vec3::scale(self.opposite_edge_vector(t, (a + 1) % 3), -1.0); // p[a+2] − p[a]
        let c = vec3::dot(u, v);
        let s = vec3::norm(vec3::cross(u, v));
        s.atan2(c)
    }
}
