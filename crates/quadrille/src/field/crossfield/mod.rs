//! Boundary-aligned cross field of one CAD face (paper §3.1, spec §2).
//!
//! A cross (four orthogonal unit tangent vectors) is represented by
//! `u = (cos 4θ, sin 4θ)`, one value per **edge** of the face triangulation
//! (Crouzeix–Raviart), θ measured in the edge's own frame (reference
//! direction = the edge, from its lower to its higher vertex id; angles
//! counter-clockwise about the triangle normals).
//!
//! [`compute_cross_field`] runs the paper's pipeline:
//! 1. topology and frames ([`topology`]); boundary copies of one point (seam,
//!    pole) are welded so a periodic face is solved on its true topology;
//! 2. Dirichlet `u = (1, 0)` (one branch tangent) on every feature edge — the
//!    triangulation's boundary edges plus [`FaceMesh::feature_edges`];
//! 3. the one-triangle boundary-condition extension (Laplace on the layer of
//!    triangles touching a feature curve, [`mbo::extend_boundary_conditions`]);
//! 4. the multilevel MBO heat diffusion of Algorithm 1 ([`mbo::diffuse`]) with
//!    `faer`'s sparse Cholesky (AMD ordering): one symbolic analysis per face,
//!    one numeric factorization per level into the same buffers, and
//!    [`linsolve`]'s own supernodal triangular solves for the iterations.
//!
//! Before step 3, a face whose boundary-aligned field is one constant 3D
//! direction projected on the surface (a cylinder's side, a plane face with
//! axis-parallel sides) gets that field directly ([`parallel_field`]): it
//! has zero Dirichlet energy, so the diffusion would converge to it.
//!
//! A surface without any feature edge (a closed sphere or torus given as one
//! triangle mesh) has no Dirichlet condition; the iterations then start from
//! a deterministic non-trivial field ([`mbo::closed_surface_start`]).

pub mod assembly;
pub mod linsolve;
pub mod mbo;
pub mod topology;

use geometry::vec3::{self, Vec3};
use geometry::{CornerId, CurveId};

pub use topology::{Cplx, FaceTopology};

/// Where a vertex of a face triangulation lies on the CAD model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum VertexClass {
    /// Strictly inside the face.
    Interior,
    /// On a CAD curve (boundary, seam or embedded curve), not at a corner.
    Curve(CurveId),
    /// At a CAD corner.
    Corner(CornerId),
}

/// Input of the cross-field stage: one face's background triangulation.
///
/// Triangles must be consistently oriented (all counter-clockwise with
/// respect to the face normal, or all clockwise). Vertices that are copies of
/// one boundary point (both sides of a seam, the copies of a pole) may be
/// given separately: non-interior vertices that coincide in 3D are welded.
#[derive(Clone, Debug, Default)]
pub struct FaceMesh {
    /// (u, v) of each vertex (kept for callers; the solver works in 3D).
    pub uv: Vec<[f64; 2]>,
    /// 3D position of each vertex.
    pub xyz: Vec<Vec3>,
    /// Vertex triples.
    pub triangles: Vec<[u32; 3]>,
    /// Classification of each vertex on the model.
    pub vertex_class: Vec<VertexClass>,
    /// Extra feature edges inside the face (embedded curves) on which the
    /// field is forced tangent; the triangulation's boundary edges always are.
    pub feature_edges: Vec<[u32; 2]>,
}

impl FaceMesh {
    /// The background triangulation of the baseline mesher
    /// ([`crate::triangulate::face_triangulation::FaceTriangulation`], after `refine`) as
    /// cross-field input: its local nodes, their 3D positions and classes,
    /// and its triangles (counter-clockwise in (u, v); seam and pole copies
    /// are welded by [`FaceTopology::build`]).
    pub fn from_face_triangulation(
        ft: &crate::triangulate::face_triangulation::FaceTriangulation<'_>,
    ) -> FaceMesh {
        use crate::core::patch::NodeRef;
        FaceMesh {
            uv: ft.nodes.iter().map(|n| n.uv).collect(),
            xyz: ft.pos.clone(),
            triangles: ft.triangles(),
            vertex_class: ft
                .nodes
                .iter()
                .map(|n| match n.node {
                    NodeRef::Corner(c) => VertexClass::Corner(c),
                    NodeRef::Curve(c, _) => VertexClass::Curve(c),
                    NodeRef::Interior => VertexClass::Interior,
                })
                .collect(),
            feature_edges: Vec::new(),
        }
    }
}

/// Why a cross field could not be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CrossFieldError {
    /// The triangulation is empty, inconsistent or degenerate.
    #[error("invalid face triangulation: {0}")]
    InvalidInput(String),
    /// The sparse solver failed (matrix not positive definite, out of memory).
    #[error("linear solver: {0}")]
    Solver(String),
}

/// Parameters of Algorithm 1.
#[derive(Clone, Debug)]
pub struct CrossFieldOptions {
    /// Number of diffusion levels N (the paper: 3–4 suffice for a CAD face).
    pub levels: usize,
    /// Convergence threshold c of a level: on the ∞-norm change between the
    /// solutions of successive linear solves, before their projection (see
    /// [`mbo::diffuse`]).
    pub tolerance: f64,
    /// Cap on the MBO iterations of one level. Each iteration costs a solve
    /// (about a ninth of a factorization at 100k triangles). Most levels of
    /// CAD faces converge before it (3.7 solves per level on the bundled
    /// models); on large smooth faces whose singularities travel far (the
    /// 100k-triangle disk and pentagon of `bench_crossfield`) a level needs
    /// 6–30 solves with the extrapolation of [`mbo::diffuse`], and the
    /// final level, `α = (3 h_min)²`, where singularities creep by about a
    /// triangle per 10–20 solves, up to 150. With 8 the 100k disk's
    /// singularities are at radius 0.800 and the pentagon's −1 within 0.016
    /// of its place with converged coarse levels (0.029 of the place with
    /// all levels converged; edge length 0.014).
    pub max_iterations: usize,
    /// Apply the one-triangle boundary-condition extension (§3.1 of the paper).
    pub extend_boundary_conditions: bool,
    /// Before the diffusion, try the parallel field of [`parallel_field`]
    /// (a cylinder, a plane with axis-aligned sides): when it exists it is
    /// the minimizer, and the diffusion is skipped.
    pub parallel_shortcut: bool,
}

impl Default for CrossFieldOptions {
    fn default() -> Self {
        CrossFieldOptions {
            levels: 4,
            tolerance: 1e-3,
            max_iterations: 8,
            extend_boundary_conditions: true,
            parallel_shortcut: true,
        }
    }
}

/// What one diffusion level did.
#[derive(Clone, Debug, PartialEq)]
pub struct LevelStats {
    /// Diffusion coefficient α (a length²).
    pub alpha: f64,
    /// MBO iterations (solve + projection) run.
    pub iterations: usize,
    /// ∞-norm change between the (unprojected) solutions of the last two
    /// solves of the level.
    pub final_change: f64,
    /// Time of the numeric factorization.
    pub factor_seconds: f64,
    /// Time of the whole level.
    pub seconds: f64,
}

/// A boundary-aligned cross field sampled on the edges of a face triangulation.
#[derive(Clone, Debug)]
pub struct CrossField {
    /// The welded triangulation the field lives on.
    pub topology: FaceTopology,
    /// Per edge, the unit representation `(cos 4θ_e, sin 4θ_e)` in the edge frame.
    pub u: Vec<Cplx>,
    /// Per edge, true when its value was fixed (feature edge or extended BC).
    pub fixed: Vec<bool>,
    /// Per-level statistics of the MBO diffusion.
    pub levels: Vec<LevelStats>,
    /// True for the field of [`parallel_field`] (no diffusion ran): its
    /// conformal scaling is 0, as on the developable surface it sits on.
    pub parallel: bool,
}

/// Computes the cross field of one face (see the module documentation).
pub fn compute_cross_field(
    mesh: &FaceMesh,
    opts: &CrossFieldOptions,
) -> Result<CrossField, CrossFieldError> {
    if opts.levels == 0 || !(opts.tolerance > 0.0) {
        return Err(CrossFieldError::InvalidInput(
            "levels must be ≥ 1 and tolerance > 0".into(),
        ));
    }
    let topology = FaceTopology::build(mesh)?;
    if opts.parallel_shortcut {
        if let Some(u) = parallel_field(&topology) {
            let fixed = topology.feature.clone();
            return Ok(CrossField {
                topology,
                u,
                fixed,
                levels: Vec::new(),
                parallel: true,
            });
        }
    }
    let ne = topology.edges.len();
    let mut fixed = topology.feature.clone();
    let mut u: Vec<Cplx> = vec![[0.0, 0.0]; ne];
    for e in 0..ne {
        if fixed[e] {
            u[e] = [1.0, 0.0];
        }
    }
    if !fixed.iter().any(|&f| f) {
        mbo::closed_surface_start(&topology, &mut u);
    } else if opts.extend_boundary_conditions {
        mbo::extend_boundary_conditions(&topology, &mut fixed, &mut u)?;
    }
    let levels = mbo::diffuse(&topology, &fixed, &mut u, opts)?;
    Ok(CrossField {
        topology,
        u,
        fixed,
        levels,
        parallel: false,
    })
}

/// Largest deviation, in radians of θ, that [`parallel_field`] accepts: of a
/// feature edge from the field, and between the crosses of one triangle's
/// three edges.
pub const PARALLEL_TOLERANCE: f64 = 0.5 * std::f64::consts::PI / 180.0;

/// The boundary-aligned cross field made of one constant 3D direction `a`
/// projected on every triangle's plane, when it exists: every feature edge
/// parallel or orthogonal to it and the three edges of every triangle
/// carrying the same cross (within [`PARALLEL_TOLERANCE`]). Such a field has
/// zero Dirichlet energy and meets every boundary condition, so it is what
/// the diffusion converges to, without the solves: the lateral face of a
/// cylinder (a = its axis), a plane face whose sides are parallel to two
/// orthogonal directions. The candidates for `a` are the first feature
/// edge's direction, the normal of the plane of that edge and the next
/// feature edge not parallel to it (a cylinder's axis, from two chords of
/// one circle), and the first edge's perpendicular in the tangent plane of
/// its triangle. `None` on a face without feature edges or when no
/// candidate fits.
pub fn parallel_field(topo: &FaceTopology) -> Option<Vec<Cplx>> {
    let first = topo.feature.iter().position(|&f| f)?;
    let t0 = topo.edge_tris[first]
        .iter()
        .copied()
        .find(|&t| t != topology::NONE)?;
    let x = topo.edge_dir[first];
    let n = topo.normals[t0 as usize];
    let tol4 = 4.0 * PARALLEL_TOLERANCE;
    // the normal of the plane of two non-parallel feature edges: a
    // cylinder's axis from two chords of one of its circles
    let across = (0..topo.edges.len())
        .filter(|&e| topo.feature[e])
        .map(|e| vec3::cross(x, topo.edge_dir[e]))
        .find(|c| vec3::norm(*c) > 0.2)
        .and_then(vec3::normalize);
    let candidates = [Some(x), across, Some(vec3::cross(n, x))];
    'candidate: for a in candidates.into_iter().flatten() {
        let mut u: Vec<Cplx> = Vec::with_capacity(topo.edges.len());
        for e in 0..topo.edges.len() {
            let t = topo.edge_tris[e]
                .iter()
                .copied()
                .find(|&t| t != topology::NONE)?;
            let n = topo.normals[t as usize];
            let d = vec3::sub(a, vec3::scale(n, vec3::dot(a, n)));
            let (ex, ey) = (topo.edge_dir[e], vec3::cross(n, topo.edge_dir[e]));
            let (c, s) = (vec3::dot(d, ex), vec3::dot(d, ey));
            if !(c.hypot(s) > 0.5) {
                continue 'candidate; // a leaves the tangent plane
            }
            let phi4 = 4.0 * s.atan2(c);
            if topo.feature[e] {
                if phi4.cos() < tol4.cos() {
                    continue 'candidate;
                }
                u.push([1.0, 0.0]);
            } else {
                u.push([phi4.cos(), phi4.sin()]);
            }
        }
        for t in 0..topo.triangles.len() {
            let v0 = topology::cmul(topo.rot4[t][0], u[topo.tri_edges[t][0] as usize]);
            for k in 1..3 {
                let v = topology::cmul(topo.rot4[t][k], u[topo.tri_edges[t][k] as usize]);
                if topology::arg_ratio(v, v0).abs() > tol4 {
                    continue 'candidate;
                }
            }
        }
        return Some(u);
    }
    None
}

impl CrossField {
    /// θ_e of edge `e` in its own frame, in (−π/4, π/4]: one branch makes this
    /// angle with the edge direction (counter-clockwise about the normal).
    pub fn edge_angle(&self, e: usize) -> f64 {
        self.u[e][1].atan2(self.u[e][0]) / 4.0
    }

    /// The representation of local edge `a`'s cross in the frame of triangle `t`.
    pub fn in_triangle(&self, t: usize, a: usize) -> Cplx {
        topology::cmul(
            self.topology.rot4[t][a],
            self.u[self.topology.tri_edges[t][a] as usize],
        )
    }

    /// The cross at barycentric coordinates `bary` of triangle `t` (CR
    /// interpolation `Σ_a (1 − 2λ_a) u_a` in the triangle frame, normalized):
    /// two orthogonal unit branch directions `[d1, d2]` (the others are their
    /// opposites). `None` where the interpolant vanishes (at a singularity).
    pub fn cross_at(&self, t: usize, bary: [f64; 3]) -> Option<[Vec3; 2]> {
        let mut w = [0.0, 0.0];
        for a in 0..3 {
            let psi = 1.0 - 2.0 * bary[a];
            let v = self.in_triangle(t, a);
            w[0] += psi * v[0];
            w[1] += psi * v[1];
        }
        if !(w[0].hypot(w[1]) > 1e-12) {
            return None;
        }
        let th = w[1].atan2(w[0]) / 4.0;
        let topo = &self.topology;
        let n = topo.normals[t];
        let x = topo.edge_dir[topo.tri_edges[t][0] as usize];
        let y = vec3::cross(n, x);
        let d1 = vec3::add(vec3::scale(x, th.cos()), vec3::scale(y, th.sin()));
        Some([d1, vec3::cross(n, d1)])
    }

    /// The cross at the barycentre of triangle `t` (mean of its three edge crosses).
    pub fn triangle_cross(&self, t: usize) -> Option<[Vec3; 2]> {
        self.cross_at(t, [1.0 / 3.0; 3])
    }

    /// Number of unknown (non-fixed) edges that the diffusion solved for.
    pub fn free_edges(&self) -> usize {
        self.fixed.iter().filter(|&&f| !f).count()
    }
}

#[cfg(test)]
mod tests;
