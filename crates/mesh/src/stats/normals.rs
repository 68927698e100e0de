//! The reference normals of the statistics at every quad corner (the CAD's,
//! by the mesher's rule, or the mesh's own where there is no CAD) and the
//! per-quad values measured with them: SICN, scaled Jacobian, the
//! element-geometry SICN and the meshers' acceptance value.

use std::collections::HashMap;

use geometry::vec3::{self, add, cross, sub, Vec3};
use geometry::{CornerUv, FaceId, Model};
use rayon::prelude::*;

use crate::quadmesh::{NodeClass, QuadMesh};
use crate::quality::{
    corner_scaled_jacobian, corner_sicn, element_corner_sicn, quad_sicn_both_judges,
};

/// Unit normal of each corner of each quad, used as the reference normal of
/// SICN and SJ: the oriented CAD normal of the quad's face at the node when
/// `model` is given ([`geometry::Face::corner_normal`]: at a node on a
/// degenerate curve of the face or another singular point, the limit normal
/// approached from inside the quad; with a mesh-based fallback where the CAD
/// normal is undefined), else one normal per quad: the mean unit normal of the
/// same-face quads sharing a node with it (see `mesh_corner_normals`).
pub fn quad_corner_normals(mesh: &QuadMesh, model: Option<&Model>) -> Vec<[Vec3; 4]> {
    match model {
        None => mesh_corner_normals(mesh),
        Some(model) => {
            let all: Vec<u32> = (0..mesh.quads.len() as u32).collect();
            quad_corner_normals_of(mesh, model, &all)
        }
    }
}

/// [`quad_corner_normals`] of the quads `quads` only (in that order), for
/// callers that work on a few quads of a large mesh: the CAD normals of
/// those quads, the mesh-based fallback computed only when one is missing.
pub fn quad_corner_normals_of(mesh: &QuadMesh, model: &Model, quads: &[u32]) -> Vec<[Vec3; 4]> {
    corner_normals_and_folds(mesh, model, quads).0
}

/// [`quad_corner_normals_of`], and the number of corners measured with
/// their quad's centre normal because the surface folds back inside the
/// quad (see [`geometry::Face::corner_normal`]).
pub(super) fn corner_normals_and_folds(
    mesh: &QuadMesh,
    model: &Model,
    quads: &[u32],
) -> (Vec<[Vec3; 4]>, usize) {
    let diagonal = model.diagonal();
    // fixed chunks, each with its own projection cache: the same result on
    // any number of threads
    let chunks: Vec<(Vec<[Option<Vec3>; 4]>, usize)> = quads
        .par_chunks(NORMAL_CHUNK)
        .map(|chunk| {
            let mut cad = CadNormals::new(mesh, model, diagonal);
            let found = chunk
                .iter()
                .map(|&qi| match mesh.quads.get(qi as usize) {
                    Some(q) => cad.quad_normals(qi as usize, q),
                    None => [None; 4],
                })
                .collect();
            (found, cad.folds)
        })
        .collect();
    let folds = chunks.iter().map(|c| c.1).sum();
    let found: Vec<[Option<Vec3>; 4]> = chunks.into_iter().flat_map(|c| c.0).collect();
    let fallback = found
        .iter()
        .any(|n| n.iter().any(Option::is_none))
        .then(|| mesh_corner_normals(mesh));
    let normals = quads
        .iter()
        .zip(found)
        .map(|(&qi, n)| {
            let base = fallback
                .as_ref()
                .and_then(|f| f.get(qi as usize).copied())
                .unwrap_or([[0.0, 0.0, 1.0]; 4]);
            [0, 1, 2, 3].map(|k| n[k].unwrap_or(base[k]))
        })
        .collect();
    (normals, folds)
}

/// Quads per task of [`corner_normals_and_folds`]: CAD normals cost a few
/// microseconds a corner, so a chunk is worth a task.
const NORMAL_CHUNK: usize = 256;

/// SICN of every quad (minimum over its corners), with the normals of
/// [`quad_corner_normals`]. Used by the statistics, the VTU writer and the renderer.
///
/// Like [`quad_corner_normals`], it expects a consistent mesh (node indices
/// in range, one face per quad); [`MeshStats::compute`] tolerates broken ones.
pub fn quad_sicn_values(mesh: &QuadMesh, model: Option<&Model>) -> Vec<f64> {
    let normals = quad_corner_normals(mesh, model);
    mesh.quads
        .iter()
        .zip(&normals)
        .map(|(q, n)| min4(corner_sicn(&quad_points(mesh, q), n)))
        .collect()
}

/// Every quad's SICN by both judges ([`crate::quality::quad_sicn_both_judges`],
/// the normals of [`quad_corner_normals`]): what the meshers' final checks
/// compare, so no written quad is inverted for either judge.
pub fn quad_acceptance_sicn_values(mesh: &QuadMesh, model: Option<&Model>) -> Vec<f64> {
    let normals = quad_corner_normals(mesh, model);
    mesh.quads
        .iter()
        .zip(&normals)
        .map(|(q, n)| quad_sicn_both_judges(&quad_points(mesh, q), n))
        .collect()
}

/// Element-geometry SICN of every quad ([`crate::quality::quad_element_sicn`]):
/// no reference normal, so no Model; negative where Gmsh's `minSICN` is.
pub fn quad_element_sicn_values(mesh: &QuadMesh) -> Vec<f64> {
    mesh.quads
        .iter()
        .map(|q| min4(element_corner_sicn(&quad_points(mesh, q))))
        .collect()
}

/// Scaled Jacobian of every quad (minimum over its corners), with the normals
/// of [`quad_corner_normals`].
pub fn quad_scaled_jacobian_values(mesh: &QuadMesh, model: Option<&Model>) -> Vec<f64> {
    let normals = quad_corner_normals(mesh, model);
    mesh.quads
        .iter()
        .zip(&normals)
        .map(|(q, n)| min4(corner_scaled_jacobian(&quad_points(mesh, q), n)))
        .collect()
}

pub(super) fn min4(v: [f64; 4]) -> f64 {
    v.into_iter().fold(f64::INFINITY, f64::min)
}

pub(super) fn quad_points(mesh: &QuadMesh, q: &[u32; 4]) -> [Vec3; 4] {
    [0, 1, 2, 3].map(|k| mesh.nodes[q[k] as usize])
}

/// The mesh-based reference normal of each quad (used at its four corners):
/// the mean of the unit normals of the quads of the same face that share a
/// node with it, itself included. One normal per quad measures the quad's
/// shape in its own plane, as Gmsh's evaluation does (on curved faces a
/// per-node normal would charge every quad the chord's tilt), while a flipped
/// quad still disagrees with its neighbours and comes out inverted.
///
/// Calibrated on Gmsh's quasi-structured meshes of the MAMBO models: it gives
/// Gmsh's own min / 1st-percentile SICN and inverted-quad counts, and average
/// SICN within 0.3 % of Gmsh's (a per-node average normal is ~0.8 % lower).
pub(super) fn mesh_corner_normals(mesh: &QuadMesh) -> Vec<[Vec3; 4]> {
    let unit: Vec<Option<Vec3>> = mesh
        .quads
        .iter()
        .map(|q| {
            let p = quad_points(mesh, q);
            vec3::normalize(cross(sub(p[2], p[0]), sub(p[3], p[1])))
        })
        .collect();
    let mut around: HashMap<(u32, FaceId), Vec<u32>> = HashMap::new();
    for (qi, (q, &f)) in mesh.quads.iter().zip(&mesh.quad_face).enumerate() {
        for &v in q {
            around.entry((v, f)).or_default().push(qi as u32);
        }
    }
    let mut nbrs: Vec<u32> = Vec::new();
    mesh.quads
        .iter()
        .zip(&mesh.quad_face)
        .enumerate()
        .map(|(qi, (q, &f))| {
            nbrs.clear();
            for &v in q {
                nbrs.extend(around.get(&(v, f)).map_or(&[][..], |l| &l[..]));
            }
            nbrs.sort_unstable();
            nbrs.dedup();
            let sum = nbrs
                .iter()
                .filter_map(|&j| unit[j as usize])
                .fold([0.0; 3], add);
            let n = vec3::normalize(sum).or(unit[qi]).unwrap_or([0.0, 0.0, 1.0]);
            [n; 4]
        })
        .collect()
}

/// Oriented CAD normals at quad corners, by [`geometry::Face::corner_normal`]
/// (the rule the mesher's own quality checks use), with a cache of node
/// projections per face.
///
/// Each corner needs its (u, v) on the quad's face and the quad's (u, v)
/// centre: a node on a degenerate curve of the face (a pole: sphere pole,
/// cone apex) has no single (u, v) and takes the limit normal from inside the
/// quad; a node on a seam takes the side of the quad's other nodes.
struct CadNormals<'a> {
    mesh: &'a QuadMesh,
    model: &'a Model,
    /// The model's bounding-box diagonal (scale of the projection tolerance).
    diagonal: f64,
    projected: HashMap<(u32, FaceId), Option<[f64; 2]>>,
    /// Curve parameters recovered for curve nodes read without them.
    curve_params: HashMap<u32, Option<f64>>,
    /// Corners on a CAD curve measured with their quad's centre normal
    /// because the surface folds back inside the quad ([`Face::corner_normal`]).
    folds: usize,
}

impl<'a> CadNormals<'a> {
    /// `diagonal`: the model's [`Model::diagonal`] (costly: computed once by the caller).
    fn new(mesh: &'a QuadMesh, model: &'a Model, diagonal: f64) -> Self {
        Self {
            mesh,
            model,
            diagonal,
            projected: HashMap::new(),
            curve_params: HashMap::new(),
            folds: 0,
        }
    }

    /// The (u, v) segments of the degenerate curves of face `f` at node `v`
    /// (empty unless the node is a pole of the face).
    fn pole_segments(&self, v: u32, f: FaceId) -> Vec<[[f64; 2]; 2]> {
        match self.mesh.node_class.get(v as usize) {
            Some(NodeClass::Corner(k)) => self.model.pole_segments(f, *k),
            Some(NodeClass::Curve(c, _)) => match self.model.curves.get(c.idx()) {
                Some(ce) if ce.degenerate => self.model.pole_segments(f, ce.start),
                _ => Vec::new(),
            },
            _ => Vec::new(),
        }
    }

    /// The parameter of curve node `v` on its curve `c`: from the mesh, else
    /// (a file written without parametric coordinates) the node projected on
    /// the curve, kept when it lands on it (cached).
    fn curve_param(&mut self, v: u32, c: geometry::CurveId, t: Option<f64>) -> Option<f64> {
        if t.is_some() {
            return t;
        }
        if let Some(&t) = self.curve_params.get(&v) {
            return t;
        }
        let p = self.mesh.nodes[v as usize];
        let on_curve = 1e-6 * self.diagonal;
        let t = self
            .model
            .curves
            .get(c.idx())
            .and_then(|ce| {
                let (t, q) = ce.geom.as_ref()?.project(p, None)?;
                let (lo, hi) = ce.range;
                let tol = 1e-9 * (hi - lo).abs();
                (vec3::dist(p, q) <= on_curve && t >= lo - tol && t <= hi + tol).then_some(t)
            })
            .filter(|t| t.is_finite());
        self.curve_params.insert(v, t);
        t
    }

    /// Candidate (u, v) of node `v` on face `f` from its classification: the
    /// face (u, v), the pcurves at a curve parameter or at a corner (two on a
    /// seam). A curve node read without its parameter gets it by projection
    /// on its curve, so that a node on a seam still gets both sides.
    fn classified_uvs(&mut self, v: u32, f: FaceId) -> Vec<[f64; 2]> {
        let model = self.model;
        let Some(face) = model.faces.get(f.idx()) else {
            return Vec::new();
        };
        let class = self.mesh.node_class.get(v as usize).copied();
        let curve_t = match class {
            Some(NodeClass::Curve(c, t)) if face.curve_uses().any(|u| u.curve == c) => {
                self.curve_param(v, c, t)
            }
            _ => None,
        };
        match &class {
            Some(NodeClass::Face(g, Some(uv))) if *g == f => vec![*uv],
            Some(NodeClass::Curve(c, _)) => match curve_t {
                Some(t) => face
                    .curve_uses()
                    .filter(|u| u.curve == *c)
                    .map(|u| u.pcurve.eval(t))
                    .collect(),
                None => Vec::new(),
            },
            Some(NodeClass::Corner(k)) => {
                let mut out = Vec::new();
                for u in face.curve_uses() {
                    let Some(c) = model.curves.get(u.curve.idx()) else {
                        continue;
                    };
                    if c.start == *k {
                        out.push(u.pcurve.eval(c.range.0));
                    }
                    if c.end == *k {
                        out.push(u.pcurve.eval(c.range.1));
                    }
                }
                out
            }
            _ => Vec::new(),
        }
        .into_iter()
        .filter(|uv| uv[0].is_finite() && uv[1].is_finite())
        .collect()
    }

    /// (u, v) of node `v` projected on face `f` (cached). The projection from
    /// `hint` (the side of a seam of the quad's other nodes) is kept when it
    /// lands on the node inside the face's (u, v) range; otherwise (the other
    /// nappe of a cone reached from a hint near its apex, the other side of a
    /// thin wing reached by a local search) the global projection decides.
    fn projected_uv(&mut self, v: u32, f: FaceId, hint: Option<[f64; 2]>) -> Option<[f64; 2]> {
        if let Some(&uv) = self.projected.get(&(v, f)) {
            return uv;
        }
        let face = self.model.faces.get(f.idx())?;
        let p = self.mesh.nodes[v as usize];
        let on_surface = 1e-7 * self.diagonal;
        let candidate = |hint: Option<[f64; 2]>| {
            face.surface
                .project(p, hint)
                .filter(|(uv, _)| in_face_range(face, *uv))
                .map(|(uv, q)| (uv, vec3::dist(p, q)))
        };
        let mut best = candidate(hint);
        if hint.is_some() && !best.is_some_and(|(_, d)| d <= on_surface) {
            if let Some(g) = candidate(None) {
                if !best.is_some_and(|(_, d)| d <= g.1) {
                    best = Some(g);
                }
            }
        }
        // nothing inside the face range: the plain projection
        let uv = best
            .map(|(uv, _)| uv)
            .or_else(|| face.surface.project(p, hint).map(|(uv, _)| uv));
        self.projected.insert((v, f), uv);
        uv
    }

    /// CAD normals at the four corners of quad `qi` (None where undefined).
    fn quad_normals(&mut self, qi: usize, q: &[u32; 4]) -> [Option<Vec3>; 4] {
        let Some(&f) = self.mesh.quad_face.get(qi) else {
            return [None; 4];
        };
        let Some(face) = self.model.faces.get(f.idx()) else {
            return [None; 4];
        };
        let poles = q.map(|v| self.pole_segments(v, f));
        let cands: [Vec<[f64; 2]>; 4] = [0, 1, 2, 3].map(|k| {
            if poles[k].is_empty() {
                self.classified_uvs(q[k], f)
            } else {
                Vec::new()
            }
        });
        // (u, v) of the other corners: unambiguous ones first, then seam nodes
        // on the side of those, then projections near them. The hint never
        // comes from a singular point (an apex not classified as a pole): its
        // u is arbitrary and it is a poor start for projecting the others.
        let regular = |uv: &[f64; 2]| !face.is_singular(*uv);
        let mut uvs: [Option<[f64; 2]>; 4] =
            [0, 1, 2, 3].map(|k| (cands[k].len() == 1).then(|| cands[k][0]));
        let mut hint = uvs.iter().flatten().copied().find(regular);
        if hint.is_none() {
            // no corner with one (u, v) (a file without parametric
            // coordinates): the face nodes' projections first, so that a
            // seam node takes their side rather than an arbitrary one
            for k in 0..4 {
                if uvs[k].is_none() && poles[k].is_empty() && cands[k].is_empty() {
                    uvs[k] = self.projected_uv(q[k], f, None);
                    hint = hint.or(uvs[k].filter(regular));
                }
            }
        }
        for k in 0..4 {
            if uvs[k].is_none() && !cands[k].is_empty() {
                let h = hint.unwrap_or(cands[k][0]);
                uvs[k] = cands[k]
                    .iter()
                    .copied()
                    .min_by(|a, b| uv_dist2(*a, h).total_cmp(&uv_dist2(*b, h)));
                hint = hint.or(uvs[k].filter(regular));
            }
        }
        for k in 0..4 {
            if uvs[k].is_none() && poles[k].is_empty() {
                uvs[k] = self.projected_uv(q[k], f, hint);
                hint = hint.or(uvs[k].filter(regular));
            }
        }
        let Some(hint) = hint.or(uvs.iter().flatten().next().copied()) else {
            return [None; 4];
        };
        let periods = face.surface.periods();
        let unwrap =
            |uv: [f64; 2], target: [f64; 2]| geometry::nearest_periodic_uv(uv, periods, target);
        // the centre: the mean of the ordinary corners (a singular corner's
        // u is arbitrary), unwrapped with the least spread (a quad spanning
        // half a period round a cone apex stays on its own half)
        let mut known: Vec<[f64; 2]> = uvs.iter().flatten().copied().filter(regular).collect();
        if known.is_empty() {
            known = uvs.iter().flatten().copied().collect();
        }
        let known = least_spread_unwrap(&known, periods, hint);
        let centre = known
            .iter()
            .fold([0.0, 0.0], |c, uv| [c[0] + uv[0], c[1] + uv[1]]);
        let centre = [
            centre[0] / known.len() as f64,
            centre[1] / known.len() as f64,
        ];
        let mut out = [None; 4];
        for k in 0..4 {
            let n = if poles[k].is_empty() {
                uvs[k].and_then(|uv| {
                    let on_curve = matches!(
                        self.mesh.node_class.get(q[k] as usize),
                        Some(NodeClass::Curve(..) | NodeClass::Corner(_))
                    );
                    if !on_curve {
                        return face.corner_normal(CornerUv::Point(uv), unwrap(centre, uv));
                    }
                    let n = face.corner_normal(CornerUv::Curve(uv), unwrap(centre, uv));
                    let own = face.corner_normal(CornerUv::Point(uv), unwrap(centre, uv));
                    if let (Some(a), Some(b)) = (n, own) {
                        if vec3::dot(a, b) < 1.0 - 1e-12 {
                            self.folds += 1;
                        }
                    }
                    n
                })
            } else {
                // the segment nearest the centre, the centre in its period
                poles[k]
                    .iter()
                    .map(|&seg| {
                        let c = unwrap(centre, CornerUv::Pole(seg).toward(centre));
                        (uv_dist2(CornerUv::Pole(seg).toward(c), c), seg, c)
                    })
                    .min_by(|a, b| a.0.total_cmp(&b.0))
                    .and_then(|(_, seg, c)| face.corner_normal(CornerUv::Pole(seg), c))
            };
            out[k] = n.filter(|n| n.iter().all(|x| x.is_finite()));
        }
        out
    }
}

/// `uvs` moved by whole periods into one window of the least spread in
/// each periodic coordinate, for their mean: first each to the
/// representative nearest `hint`'s ([`geometry::nearest_periodic_uv`]), then,
/// where that leaves a gap between two sorted values wider than the one
/// across the period's end, the window is moved to start after the widest
/// gap and shifted back by a period if that moved `hint`'s own value. A
/// value exactly half a period from `hint` is rounded either way by the
/// first step; this keeps a quad spanning half a period (a half cone round
/// its apex) on its own half. Where the values span less than half a
/// period the first step's result is returned unchanged (bit for bit).
fn least_spread_unwrap(
    uvs: &[[f64; 2]],
    periods: [Option<f64>; 2],
    hint: [f64; 2],
) -> Vec<[f64; 2]> {
    let mut out: Vec<[f64; 2]> = uvs
        .iter()
        .map(|&uv| geometry::nearest_periodic_uv(uv, periods, hint))
        .collect();
    for d in 0..2 {
        let Some(p) = periods[d].filter(|p| *p > 0.0) else {
            continue;
        };
        let mut sorted: Vec<f64> = out.iter().map(|uv| uv[d]).collect();
        sorted.sort_by(f64::total_cmp);
        let (Some(&lo), Some(&hi)) = (sorted.first(), sorted.last()) else {
            continue;
        };
        // the widest inner gap, kept only when wider than the wrap gap
        let mut cut: Option<(f64, f64)> = None; // (gap, the value before it)
        for w in sorted.windows(2) {
            let gap = w[1] - w[0];
            if gap > lo + p - hi && cut.map_or(true, |c| gap > c.0) {
                cut = Some((gap, w[0]));
            }
        }
        let Some((_, before)) = cut else {
            continue;
        };
        // hint's own value is unchanged by the first step
        let hint_moves = hint[d] <= before;
        for uv in &mut out {
            if uv[d] <= before {
                uv[d] += p;
            }
            if hint_moves {
                uv[d] -= p;
            }
        }
    }
    out
}

/// True when `uv` lies in the face's (u, v) bounds, up to 1e-6 of their
/// extent, in every non-periodic direction.
fn in_face_range(face: &geometry::Face, uv: [f64; 2]) -> bool {
    let b = face.uv_bounds;
    let periods = face.surface.periods();
    let ok = |x: f64, lo: f64, hi: f64, periodic: bool| {
        let tol = 1e-6 * (hi - lo).abs().max(1e-300);
        periodic || !(lo.is_finite() && hi.is_finite()) || (x >= lo - tol && x <= hi + tol)
    };
    ok(uv[0], b.umin, b.umax, periods[0].is_some())
        && ok(uv[1], b.vmin, b.vmax, periods[1].is_some())
}

fn uv_dist2(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)
}
