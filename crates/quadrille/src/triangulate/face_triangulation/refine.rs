//! Refinement of a [`FaceTriangulation`] to the 3D size: the limits that
//! drive it (size, chord deviation, normal turn, budgets), the candidate
//! search ([`FaceTriangulation::refine`] and its per-triangle assessment),
//! the insertion of interior points ([`FaceTriangulation::try_insert`]) and
//! the normal layers beside the boundary
//! ([`FaceTriangulation::insert_normal_layers`]).


use geometry::vec3::{self, Vec3};
use spade::handles::FixedVertexHandle;
use spade::{Point2, PositionInTriangulation, Triangulation};

use crate::core::patch::{FaceFailure, LocalNode, NodeRef};

use super::plane::{centroid_uv, circumcenter, edge_mid_uv};
use super::{FaceTriangulation, Vtx};

/// Triangles longer than this times the target size are refined.
const SIZE_RATIO: f64 = 1.4;
/// An interior edge whose surface midpoint is farther than this fraction of its
/// length from its chord midpoint is refined (about 60° of arc).
pub(super) const CHORD_RATIO: f64 = 0.14;
/// Triangles whose normals (centre vs vertices, ends of interior edges)
/// differ by more than acos(this) are refined...
pub(super) const NORMAL_COS: f64 = 0.3;
/// [`CHORD_RATIO`] and [`NORMAL_COS`] of a triangulation whose interior points
/// come from a front already sized for curvature ([`FaceTriangulation::curvature_by_size_map`]):
/// about 120° of arc, and normals 120° apart. The curves allow a coarse
/// segment per 90° of turn, so a coarse triangle beside one may turn as much;
/// refining below that splits the front's regular rows into scattered points
/// (on the 26 shared models, plain unstructured method: 2 052 interior
/// irregular vertices against 3 320 with the tighter limits; BENCHMARKS.md,
/// "Curvature refinement of the plain method's triangulation").
const FRONT_CHORD_RATIO: f64 = 0.29;
/// See [`FRONT_CHORD_RATIO`].
const FRONT_NORMAL_COS: f64 = -0.5;
/// ...unless they are smaller than this fraction of the target size (or than
/// the surface's [`geometry::Surface::resolution`]): a bend narrower than
/// that (a trailing edge rounded far below the quad size) is a crease at the
/// mesh's scale ([`crate::curves::curve_mesh`]); resolving it took triangles down to
/// a thousandth of the size along the whole edge (with 0.001 here,
/// wing_surface's background had 22 500 triangles, 6 500 of them within 1 %
/// of the chord from its trailing edge).
const MIN_CURVATURE_SIZE: f64 = 0.1;
/// Refinement rounds before giving up.
const MAX_ROUNDS: usize = 200;
/// Normal turn (radians) between two points of a normal layer.
pub const LAYER_TURN: f64 = 0.45;
/// Geometric samples (6 per halving) of the march of a normal layer.
const LAYER_SAMPLES: usize = 100;
/// Refinement rounds after which a round that inserts fewer than 5% of its
/// candidates ends the refinement.
const STALL_AFTER: usize = 12;
/// Upper bound on the nodes of one face triangulation.
const MAX_NODES: usize = 500_000;

impl FaceTriangulation<'_> {
    /// Inserts an interior node at `uv` when it falls strictly inside the domain
    /// (not on a constraint, not on a vertex) and at least `min_dist` (3D) from
    /// the vertices around it. Returns true when inserted.
    pub fn try_insert(&mut self, uv: [f64; 2], min_dist: f64) -> bool {
        self.try_insert_near(uv, min_dist, None)
    }

    /// [`Self::try_insert`] with the local node `near` (when known) as the
    /// start of the point location: the walk through the triangulation is
    /// then short instead of starting from the last vertex looked up. The
    /// point's location is the same; a point on an edge may split it from
    /// the other side, which renumbers the triangulation's faces.
    pub fn try_insert_near(&mut self, uv: [f64; 2], min_dist: f64, near: Option<u32>) -> bool {
        if !(uv[0].is_finite() && uv[1].is_finite()) || self.nodes.len() >= self.node_budget() {
            return false;
        }
        let p = self.to_scaled(uv);
        let hint = near.and_then(|id| self.handles.get(id as usize).copied());
        let located = match hint {
            Some(h) => self.cdt.locate_with_hint(p, h),
            None => self.cdt.locate(p),
        };
        let near: Vec<FixedVertexHandle> = match located {
            PositionInTriangulation::OnFace(f) => {
                if !self.is_inside(f) {
                    return false;
                }
                // a point numerically on a boundary edge (a circumcentre or
                // centroid of a sliver along it) would make a triangle flat
                // in 3D, which the cross field refuses
                let x = self.eval(uv);
                for e in self.cdt.face(f).adjacent_edges() {
                    if e.as_undirected().data().is_constraint_edge() {
                        let a = self.pos[e.from().data().id as usize];
                        let b = self.pos[e.to().data().id as usize];
                        if vec3::segment_distance(x, a, b) < min_dist {
                            return false;
                        }
                    }
                }
                self.cdt
                    .face(f)
                    .vertices()
                    .iter()
                    .map(|v| v.fix())
                    .collect()
            }
            PositionInTriangulation::OnEdge(e) => {
                let e = self.cdt.directed_edge(e);
                if e.as_undirected().data().is_constraint_edge() {
                    return false;
                }
                let ok = [e.face(), e.rev().face()]
                    .iter()
                    .all(|f| f.as_inner().is_some_and(|g| self.is_inside(g.fix())));
                if !ok {
                    return false;
                }
                vec![e.from().fix(), e.to().fix()]
            }
            _ => return false,
        };
        let x = self.eval(uv);
        if !(x[0].is_finite() && x[1].is_finite() && x[2].is_finite()) {
            return false;
        }
        for v in near {
            let id = self.cdt.vertex(v).data().id as usize;
            if vec3::dist(self.pos[id], x) < min_dist {
                return false;
            }
        }
        let id = self.nodes.len() as u32;
        let before = self.cdt.num_all_faces();
        let inserted = match hint {
            Some(h) => self.cdt.insert_with_hint(Vtx { pos: p, id }, h),
            None => self.cdt.insert(Vtx { pos: p, id }),
        };
        let Ok(handle) = inserted else {
            return false;
        };
        self.handles.push(handle);
        self.nodes.push(LocalNode {
            uv,
            node: NodeRef::Interior,
            pole: None,
        });
        self.pos.push(x);
        // new faces come from splitting inside faces: they are inside
        let after = self.cdt.num_all_faces();
        self.inside.resize(after.max(before), true);
        true
    }

    /// Inserts *normal layers*: from each boundary node, marches inward (along
    /// the bisector of the adjacent boundary edges' inward normals) for one
    /// target length in 3D, and inserts a point wherever the surface normal has
    /// turned by more than [`LAYER_TURN`] since the previous point. Thin
    /// triangles then follow a surface that turns sharply right beside the
    /// boundary (a rounded trailing edge next to a seam), which isotropic
    /// refinement cannot resolve against long boundary edges. Returns the
    /// number of points inserted.
    pub fn insert_normal_layers(&mut self) -> usize {
        let mut pts: Vec<([f64; 2], f64)> = Vec::new();
        for ids in &self.loops {
            let k = ids.len();
            for i in 0..k {
                let (p, c, q) = (
                    ids[(i + k - 1) % k] as usize,
                    ids[i] as usize,
                    ids[(i + 1) % k] as usize,
                );
                if self.nodes[c].pole.is_some() {
                    continue;
                }
                let sp = |j: usize| self.to_scaled(self.nodes[j].uv);
                let (a, b, d) = (sp(p), sp(c), sp(q));
                let left = |x: f64, y: f64| {
                    let l = x.hypot(y);
                    if l > 0.0 {
                        [-y / l, x / l]
                    } else {
                        [0.0, 0.0]
                    }
                };
                let n1 = left(b.x - a.x, b.y - a.y);
                let n2 = left(d.x - b.x, d.y - b.y);
                let mut dir = [n1[0] + n2[0], n1[1] + n2[1]];
                let l = dir[0].hypot(dir[1]);
                if !(l > 1e-12) {
                    continue;
                }
                dir = [dir[0] / l / self.scale[0], dir[1] / l / self.scale[1]];
                let start = self.nodes[c].uv;
                let x0 = self.pos[c];
                let at = |t: f64| [start[0] + t * dir[0], start[1] + t * dir[1]];
                // the uv distance that reaches one target length in 3D
                let b2 = self.face.uv_bounds;
                let span = (b2.umax - b2.umin)
                    .abs()
                    .max((b2.vmax - b2.vmin).abs())
                    .max(1e-300);
                let mut tmax = 1e-6 * span;
                while tmax < 2.0 * span && vec3::dist(self.eval(at(tmax)), x0) < self.target {
                    tmax *= 2.0;
                }
                let Some(mut last) = self.face.surface.normal(at(1e-9 * span)) else {
                    continue;
                };
                for s in (0..=LAYER_SAMPLES).rev() {
                    let t = tmax * (-(s as f64) / 6.0).exp2();
                    let Some(nrm) = self.face.surface.normal(at(t)) else {
                        continue;
                    };
                    if vec3::dot(nrm, last) < LAYER_TURN.cos() {
                        pts.push((at(t), 1e-3 * vec3::dist(self.eval(at(t)), x0)));
                        last = nrm;
                    }
                }
            }
        }
        let mut n = 0;
        for (uv, min_dist) in pts {
            if self.try_insert(uv, min_dist) {
                n += 1;
            }
        }
        n
    }

    /// Most nodes refinement may create: generous for the face's boundary
    /// (a disc bounded by `nb` points needs about `nb²/10`), so that a face whose
    /// defects cannot be fixed by refinement stops early instead of filling memory.
    fn node_budget(&self) -> usize {
        let nb = self.boundary_mid.len();
        (nb * nb)
            .saturating_add(20 * nb)
            .saturating_add(20_000)
            .min(MAX_NODES)
    }

    /// From now on [`Self::refine`] splits triangles for curvature only past
    /// about 120° of turn (`FRONT_CHORD_RATIO` 0.29, `FRONT_NORMAL_COS` −0.5) instead
    /// of 60°–70°: for interior points placed by a front whose size map
    /// already bounds the turn per quad, the finer limits only scatter extra
    /// points between its rows.
    pub fn curvature_by_size_map(&mut self) {
        self.turn_limits = (FRONT_CHORD_RATIO, FRONT_NORMAL_COS);
    }

    /// Refines until every triangle has edges at most `SIZE_RATIO × target`
    /// long in 3D, follows the surface (chord deviation of interior edges) and
    /// has the orientation of the face normal.
    pub fn refine(&mut self) -> Result<(), FaceFailure> {
        // triangles found fine in an earlier round: `assess` depends on the
        // triangle's nodes alone, so one that survived unchanged stays fine;
        // kept per face slot of the triangulation with the triangle settled
        // there (a slot is reused by other triangles as points go in)
        let mut settled: Vec<Option<[u32; 3]>> = Vec::new();
        for round in 0..MAX_ROUNDS {
            // (badness, point, fallback point, min distance, a node of the triangle)
            let mut cands: Vec<(f64, [f64; 2], [f64; 2], f64, u32)> = Vec::new();
            settled.resize(self.cdt.num_all_faces(), None);
            for f in self.cdt.inner_faces() {
                if !self.is_inside(f.fix()) {
                    continue;
                }
                let v = f.vertices();
                let t = [v[0].data().id, v[1].data().id, v[2].data().id];
                let key = rotated_to_least(t);
                let slot = f.fix().index();
                if settled[slot] == Some(key) {
                    continue;
                }
                match self.assess(t) {
                    Some((bad, p, fallback, min_dist)) => cands.push((bad, p, fallback, min_dist, t[0])),
                    None => settled[slot] = Some(key),
                }
            }
            if cands.is_empty() {
                return Ok(());
            }
            cands.sort_by(|a, b| b.0.total_cmp(&a.0));
            if tracing::enabled!(tracing::Level::DEBUG) {
                tracing::debug!(
                    "refine round {round}: {} nodes, {} candidates, worst {:.3}",
                    self.nodes.len(),
                    cands.len(),
                    cands[0].0
                );
            }
            let mut inserted = 0usize;
            let ncands = cands.len();
            for (_, p, fallback, min_dist, near) in cands {
                if self.try_insert_near(p, min_dist, Some(near))
                    || (fallback != p && self.try_insert_near(fallback, min_dist, Some(near)))
                {
                    inserted += 1;
                }
            }
            // (no new classification: an inserted point splits inside faces
            // and its flips stay behind the constraints, so `try_insert` keeps
            // the inside flags; `inside_flags_stay_valid_while_inserting`)
            // stalled: the remaining defects cannot be fixed by inserting points
            // (they hang on boundary edges); the caller decides what to do
            if inserted == 0 || (round >= STALL_AFTER && inserted * 20 < ncands) {
                return Ok(());
            }
            if self.nodes.len() >= self.node_budget() {
                // stop here: what remains is judged by the caller on the quads
                return Ok(());
            }
        }
        Ok(())
    }

    /// Whether triangle `t` needs refinement: `(badness, point, fallback point, min distance)`.
    fn assess(&self, t: [u32; 3]) -> Option<(f64, [f64; 2], [f64; 2], f64)> {
        let n = [
            self.nodes[t[0] as usize],
            self.nodes[t[1] as usize],
            self.nodes[t[2] as usize],
        ];
        let p = [
            self.pos[t[0] as usize],
            self.pos[t[1] as usize],
            self.pos[t[2] as usize],
        ];
        let l = [
            vec3::dist(p[0], p[1]),
            vec3::dist(p[1], p[2]),
            vec3::dist(p[2], p[0]),
        ];
        let lmax = l[0].max(l[1]).max(l[2]);
        let lmin = l[0].min(l[1]).min(l[2]);
        let g = centroid_uv(&self.nodes, t);
        if let Some(k) = self.pole_edge(t) {
            // a triangle with two nodes on one pole vanishes; it must not take
            // a boundary edge with it
            let (b, c) = (t[(k + 1) % 3], t[(k + 2) % 3]);
            let a = t[k];
            if self.is_boundary_edge(b, c) || self.is_boundary_edge(c, a) {
                return Some((30.0, g, g, 1e-3 * lmax.max(1e-300)));
            }
            return None;
        }
        // below this, refining for curvature gains nothing
        let curvature_floor =
            (MIN_CURVATURE_SIZE * self.target).max(self.face.surface.resolution());
        // chord deviation of interior edges (and zero-length edges across a period)
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            if self.is_boundary_edge(a, b) {
                continue;
            }
            let (na, nb) = (&n[k], &n[(k + 1) % 3]);
            if na.same_pole(nb) {
                continue;
            }
            let m = edge_mid_uv(na, nb);
            let dev = vec3::dist(self.eval(m), vec3::lerp(p[k], p[(k + 1) % 3], 0.5));
            if l[k] < 1e-9 * self.target
                || (dev > self.turn_limits.0 * l[k] && l[k] > curvature_floor)
            {
                return Some((10.0 + dev / l[k].max(1e-300), m, g, 1e-3 * lmax.max(1e-300)));
            }
        }
        // orientation: counter-clockwise in (u, v) must map to the side of du × dv
        if let Some(nrm) = self.face.surface.normal(g) {
            let cr = vec3::cross(vec3::sub(p[1], p[0]), vec3::sub(p[2], p[0]));
            if vec3::dot(cr, nrm) <= 0.0 && lmin > curvature_floor {
                return Some((20.0, g, g, 1e-3 * lmax));
            }
        }
        // the surface turns a lot inside the triangle (a tight fillet, a
        // rounded trailing edge): the quads would not follow the CAD normal
        if lmin > curvature_floor {
            // compare the centre with each vertex, and the ends of interior
            // edges (a coarse boundary edge may itself span a large angle)
            if let Some(nc) = self.face.surface.normal(g) {
                let nv: Vec<Option<Vec3>> = (0..3)
                    .map(|k| {
                        if n[k].pole.is_none() {
                            self.face.surface.normal(n[k].uv)
                        } else {
                            None
                        }
                    })
                    .collect();
                let mut min_dot = 1.0f64;
                for k in 0..3 {
                    if let Some(a) = nv[k] {
                        min_dot = min_dot.min(vec3::dot(a, nc));
                        if let Some(b) = nv[(k + 1) % 3] {
                            if !self.is_boundary_edge(t[k], t[(k + 1) % 3]) {
                                min_dot = min_dot.min(vec3::dot(a, b));
                            }
                        }
                    }
                }
                if min_dot < self.turn_limits.1 {
                    return Some((15.0 - min_dot, g, g, 1e-3 * lmax));
                }
            }
        }
        if lmax > SIZE_RATIO * self.target {
            // circumcenter in the scaled plane, when visible from the centroid
            let q: Vec<[f64; 2]> = (0..3)
                .map(|k| n[k].uv_toward(g))
                .map(|uv| self.to_scaled(uv))
                .map(|p| [p.x, p.y])
                .collect();
            let cc = circumcenter(q[0], q[1], q[2]);
            let mut pt = g;
            if let Some(cc) = cc {
                let gs = self.to_scaled(g);
                let ccp = Point2::new(cc[0], cc[1]);
                if !self.cdt.intersects_constraint(gs, ccp) {
                    pt = self.uv_of_plane(cc);
                }
            }
            return Some((lmax / self.target, pt, g, 0.4 * self.target));
        }
        None
    }
}

/// Triangle `t` rotated so that its least node comes first (same
/// orientation): one key for the triangle however the triangulation lists it.
pub(super) fn rotated_to_least(t: [u32; 3]) -> [u32; 3] {
    let k = (0..3).min_by_key(|&k| t[k]).unwrap_or(0);
    [t[k], t[(k + 1) % 3], t[(k + 2) % 3]]
}
