//! Triangulation of one face in its parameter plane: the boundary polygon is
//! built from the shared curve meshes (coarse points), triangulated by a
//! constrained Delaunay triangulation (`spade`, exact predicates) and refined
//! until the triangles have the target **3D** size, follow the surface (chord
//! deviation) and keep the orientation of the CAD normal.
//!
//! The Delaunay work happens in a scaled (u, v) plane (`u·su, v·sv` with the
//! mean metric of the face) so that anisotropic parametrizations (a cylinder in
//! radians × millimetres) still give well-shaped triangles.
//!
//! Special boundary nodes:
//! - seam nodes appear twice (once on each side of the period) as distinct
//!   local nodes with the same [`NodeRef`];
//! - nodes on a degenerate curve (a pole) are all the same corner; their uv is
//!   the whole degenerate pcurve, so each pole node carries that segment and is
//!   moved along it toward the point it is combined with ([`LocalNode::uv_toward`]).
//!   Triangles with two nodes on the same pole are degenerate and dropped.
//!
//! The refinement to the 3D size (candidate search, insertion, normal
//! layers, and the limits that drive it) is in the `refine` submodule,
//! the plane-geometry helpers in `plane`.

use crate::core::fast_hash::{FastMap, FastSet};
use std::collections::HashMap;

use geometry::vec3::{self, Vec3};
use geometry::{CurveId, Face, FaceId, Model};
use spade::handles::{FixedFaceHandle, FixedVertexHandle, InnerTag};
use spade::{
    ConstrainedDelaunayTriangulation, HasPosition, Point2, PositionInTriangulation, Triangulation,
};

use crate::core::patch::{FaceFailure, LocalNode, NodeRef};
use crate::curves::curve_mesh::CurveMesh;

mod plane;
mod refine;

use plane::segments_touch;
pub use plane::{centroid_uv, edge_mid_uv};
use refine::{CHORD_RATIO, NORMAL_COS};

/// The midpoint node of a boundary edge.
#[derive(Clone, Copy, Debug)]
pub struct BoundaryMid {
    /// The midpoint as a local node.
    pub node: LocalNode,
    /// Its 3D position (on the CAD curve).
    pub pos: Vec3,
    /// The curve the edge lies on.
    pub curve: CurveId,
}

#[derive(Clone, Copy, Debug)]
struct Vtx {
    pos: Point2<f64>,
    id: u32,
}

impl HasPosition for Vtx {
    type Scalar = f64;
    fn position(&self) -> Point2<f64> {
        self.pos
    }
}

type Cdt = ConstrainedDelaunayTriangulation<Vtx>;

/// A face's constrained triangulation in (u, v) with its local nodes.
#[derive(Clone)]
pub struct FaceTriangulation<'a> {
    face: &'a Face,
    /// Local nodes (boundary nodes first, then inserted interior nodes).
    pub nodes: Vec<LocalNode>,
    /// 3D position of each local node.
    pub pos: Vec<Vec3>,
    /// Midpoints of boundary edges, keyed by the sorted local node pair.
    pub boundary_mid: FastMap<(u32, u32), BoundaryMid>,
    /// Curves of the boundary, for error reports.
    pub curves: Vec<CurveId>,
    loops: Vec<Vec<u32>>,
    cdt: Cdt,
    /// The triangulation's handle of each local node (index = node id).
    handles: Vec<FixedVertexHandle>,
    /// Nodes `0..boundary_nodes` are the boundary's; later ones are inserted.
    boundary_nodes: u32,
    inside: Vec<bool>,
    scale: [f64; 2],
    origin: [f64; 2],
    target: f64,
    /// Limits of the curvature refinement: (chord ratio, normal cosine).
    turn_limits: (f64, f64),
}

/// Maps (u, v) to the triangulation plane: centred on the face's uv box,
/// scaled by the mean metric, and with magnitudes `spade` accepts.
fn plane_point(uv: [f64; 2], origin: [f64; 2], scale: [f64; 2]) -> Point2<f64> {
    let fix = |x: f64| if x.abs() < 1e-30 { 0.0 } else { x };
    Point2::new(
        fix((uv[0] - origin[0]) * scale[0]),
        fix((uv[1] - origin[1]) * scale[1]),
    )
}

/// The smallest ratio of the two sides of a face's triangulation plane (its
/// uv box scaled by [`metric_scale`]: about the ratio of the face's mean
/// widths, whatever its parametrization). Below it the plane is a strip so
/// thin that squared distances in it lose the short direction (the ratio
/// squared nears `f64`'s 1e-16), and `spade`'s nearest-neighbour walk went on
/// without end: the fuzzer's mutated tori (issue 32), major radius 9.2e18 or
/// 4.3e9 against a minor radius of 5 (ratios 5e-19 and 1e-9). A real face
/// stays far above it (a strip 1 µm wide and 1 m long has 1e-6).
const MIN_METRIC_RATIO: f64 = 1e-6;

/// Why `face` cannot be triangulated in its (u, v) plane, when the plane's
/// sides differ by more than `1 / MIN_METRIC_RATIO`.
pub fn degenerate_metric(face: &Face) -> Option<String> {
    let scale = metric_scale(face);
    let b = face.uv_bounds;
    let sides = [
        (b.umax - b.umin).abs() * scale[0],
        (b.vmax - b.vmin).abs() * scale[1],
    ];
    let ratio = sides[0].min(sides[1]) / sides[0].max(sides[1]);
    (ratio < MIN_METRIC_RATIO).then(|| {
        format!(
            "its (u, v) map is degenerate: the face is {:.1e} times longer one way than the other",
            1.0 / ratio
        )
    })
}

/// Mean lengths of ∂S/∂u and ∂S/∂v over the face's uv box: the scaling that
/// makes (u, v) roughly isometric.
fn metric_scale(face: &Face) -> [f64; 2] {
    let b = face.uv_bounds;
    let (mut su, mut sv, mut k) = (0.0, 0.0, 0usize);
    for i in 0..=8 {
        for j in 0..=8 {
            let uv = [
                b.umin + (b.umax - b.umin) * i as f64 / 8.0,
                b.vmin + (b.vmax - b.vmin) * j as f64 / 8.0,
            ];
            let d = face.surface.first_derivs(uv);
            let (a, c) = (vec3::norm(d.du), vec3::norm(d.dv));
            if a.is_finite() && c.is_finite() {
                su += a;
                sv += c;
                k += 1;
            }
        }
    }
    if k == 0 || !(su > 0.0) || !(sv > 0.0) {
        return [1.0, 1.0];
    }
    let (su, sv) = (su / k as f64, sv / k as f64);
    // normalize so the larger factor is 1 (keeps coordinates near the uv range)
    let m = su.max(sv);
    [su / m, sv / m]
}

fn global_ref(model: &Model, c: CurveId, cm: &CurveMesh, i: usize) -> NodeRef {
    let ce = &model.curves[c.idx()];
    if ce.degenerate || i == 0 {
        NodeRef::Corner(ce.start)
    } else if i == cm.params.len() - 1 {
        NodeRef::Corner(ce.end)
    } else {
        NodeRef::Curve(c, i as u32)
    }
}

impl<'a> FaceTriangulation<'a> {
    /// Builds the boundary of face `fid` from the curve meshes and its
    /// constrained Delaunay triangulation (no interior points yet).
    /// `target` is the triangle edge length (twice the final quad size).
    pub fn new(
        model: &'a Model,
        fid: FaceId,
        curve_meshes: &[CurveMesh],
        target: f64,
    ) -> Result<Self, FaceFailure> {
        let face = &model.faces[fid.idx()];
        if let Some(why) = degenerate_metric(face) {
            return Err(FaceFailure::Fatal(why));
        }
        let scale = metric_scale(face);
        let mut nodes: Vec<LocalNode> = Vec::new();
        let mut pos: Vec<Vec3> = Vec::new();
        let mut loops: Vec<Vec<u32>> = Vec::new();
        let mut mids: Vec<Vec<BoundaryMid>> = Vec::new();
        let mut curves: Vec<CurveId> = Vec::new();
        let mut extent = 0.0f64;
        for lp in &face.loops {
            let mut ids = Vec::new();
            let mut lm = Vec::new();
            let nuses = lp.uses.len();
            for (k, u) in lp.uses.iter().enumerate() {
                let c = u.curve;
                if !curves.contains(&c) {
                    curves.push(c);
                }
                let ce = &model.curves[c.idx()];
                let cm = &curve_meshes[c.idx()];
                let m = cm.params.len() - 1;
                let pole_seg = ce.degenerate.then(|| face.pole_segment(u, ce));
                // the previous / next uses may be degenerate: the corner nodes are poles then
                let prev_deg = {
                    let p = &lp.uses[(k + nuses - 1) % nuses];
                    let pc = &model.curves[p.curve.idx()];
                    pc.degenerate.then(|| face.pole_segment(p, pc))
                };
                for j in 0..cm.coarse {
                    let (i0, i1) = if u.forward {
                        (2 * j, 2 * j + 1)
                    } else {
                        (m - 2 * j, m - 2 * j - 1)
                    };
                    let uv = u.pcurve.eval(cm.params[i0]);
                    if !(uv[0].is_finite() && uv[1].is_finite()) {
                        return Err(FaceFailure::Fatal(format!(
                            "pcurve of curve {} is not finite",
                            c.0 + 1
                        )));
                    }
                    extent = extent.max(uv[0].abs()).max(uv[1].abs());
                    let pole = if pole_seg.is_some() {
                        pole_seg
                    } else if j == 0 {
                        prev_deg
                    } else {
                        None
                    };
                    ids.push(nodes.len() as u32);
                    nodes.push(LocalNode {
                        uv,
                        node: global_ref(model, c, cm, i0),
                        pole,
                    });
                    pos.push(cm.points[i0]);
                    let muv = u.pcurve.eval(cm.params[i1]);
                    lm.push(BoundaryMid {
                        node: LocalNode {
                            uv: muv,
                            node: global_ref(model, c, cm, i1),
                            pole: pole_seg,
                        },
                        pos: cm.points[i1],
                        curve: c,
                    });
                }
                // the end of this use must meet the start of the next in uv
                let next = &lp.uses[(k + 1) % nuses];
                let nce = &model.curves[next.curve.idx()];
                let end = u
                    .pcurve
                    .eval(if u.forward { ce.range.1 } else { ce.range.0 });
                let start = next.pcurve.eval(if next.forward {
                    nce.range.0
                } else {
                    nce.range.1
                });
                let gap = (end[0] - start[0]).hypot(end[1] - start[1]);
                let span = (face.uv_bounds.umax - face.uv_bounds.umin).abs()
                    + (face.uv_bounds.vmax - face.uv_bounds.vmin).abs();
                if gap > 1e-3 * span.max(1e-300) {
                    return Err(FaceFailure::Fatal(format!(
                        "loop not closed in (u, v): curve {} ends {gap:.3e} away from where curve {} starts",
                        c.0 + 1,
                        next.curve.0 + 1
                    )));
                }
            }
            if ids.len() < 3 {
                return Err(FaceFailure::RefineCurves(
                    lp.uses.iter().map(|u| u.curve).collect(),
                    "a loop has fewer than 3 points".into(),
                ));
            }
            loops.push(ids);
            mids.push(lm);
        }
        if loops.is_empty() {
            return Err(FaceFailure::Fatal("face has no boundary loop".into()));
        }
        let _ = extent;
        let b = face.uv_bounds;
        let origin = [0.5 * (b.umin + b.umax), 0.5 * (b.vmin + b.vmax)];
        let origin = if origin[0].is_finite() && origin[1].is_finite() {
            origin
        } else {
            [0.0, 0.0]
        };
        let mut cdt = Cdt::new();
        let mut handles: Vec<FixedVertexHandle> = Vec::with_capacity(nodes.len());
        for (i, n) in nodes.iter().enumerate() {
            let p = plane_point(n.uv, origin, scale);
            if let PositionInTriangulation::OnVertex(_) = cdt.locate(p) {
                let c = curve_of_node(&loops, &mids, i as u32);
                return Err(FaceFailure::RefineCurves(
                    c,
                    "two boundary points coincide in (u, v)".into(),
                ));
            }
            let h = cdt
                .insert(Vtx {
                    pos: p,
                    id: i as u32,
                })
                .map_err(|e| FaceFailure::Fatal(format!("bad uv coordinate: {e:?}")))?;
            handles.push(h);
        }
        let mut boundary_mid = FastMap::default();
        for (l, ids) in loops.iter().enumerate() {
            for k in 0..ids.len() {
                let (a, b) = (ids[k], ids[(k + 1) % ids.len()]);
                let (ha, hb) = (handles[a as usize], handles[b as usize]);
                let added = cdt.try_add_constraint(ha, hb);
                if added.is_empty() || !cdt.exists_constraint(ha, hb) {
                    // the polygon self-intersects (or a point lies on an edge)
                    let mut cs = vec![mids[l][k].curve];
                    for (l2, ids2) in loops.iter().enumerate() {
                        for k2 in 0..ids2.len() {
                            let (c, d) = (ids2[k2], ids2[(k2 + 1) % ids2.len()]);
                            let pa = nodes[a as usize].uv;
                            let pb = nodes[b as usize].uv;
                            if segments_touch(pa, pb, nodes[c as usize].uv, nodes[d as usize].uv)
                                && !cs.contains(&mids[l2][k2].curve)
                            {
                                cs.push(mids[l2][k2].curve);
                            }
                        }
                    }
                    return Err(FaceFailure::RefineCurves(
                        cs,
                        "the boundary polygon self-intersects in (u, v)".into(),
                    ));
                }
                boundary_mid.insert((a.min(b), a.max(b)), mids[l][k]);
            }
        }
        let boundary_nodes = nodes.len() as u32;
        let mut ft = FaceTriangulation {
            face,
            nodes,
            pos,
            boundary_mid,
            curves,
            loops,
            cdt,
            handles,
            boundary_nodes,
            inside: Vec::new(),
            scale,
            origin,
            target,
            turn_limits: (CHORD_RATIO, NORMAL_COS),
        };
        ft.classify();
        if ft.inside.iter().all(|&b| !b) {
            return Err(FaceFailure::RefineCurves(
                ft.curves.clone(),
                "the boundary polygon encloses no area".into(),
            ));
        }
        Ok(ft)
    }

    /// Marks each face of the triangulation inside / outside the domain by the
    /// parity of the constraint edges crossed from the outer face.
    fn classify(&mut self) {
        let n = self.cdt.num_all_faces();
        let mut level = vec![u8::MAX; n];
        let mut stack = Vec::new();
        level[self.cdt.outer_face().fix().index()] = 0;
        for e in self.cdt.convex_hull() {
            for f in [e.face(), e.rev().face()] {
                if let Some(inner) = f.as_inner() {
                    let i = inner.fix().index();
                    if level[i] == u8::MAX {
                        level[i] = u8::from(e.as_undirected().data().is_constraint_edge());
                        stack.push(inner.fix());
                    }
                }
            }
        }
        while let Some(f) = stack.pop() {
            let fl = level[f.index()];
            for e in self.cdt.face(f).adjacent_edges() {
                if let Some(g) = e.rev().face().as_inner() {
                    let gi = g.fix().index();
                    if level[gi] == u8::MAX {
                        level[gi] = fl ^ u8::from(e.as_undirected().data().is_constraint_edge());
                        stack.push(g.fix());
                    }
                }
            }
        }
        self.inside = level.iter().map(|&l| l == 1).collect();
    }

    fn is_inside(&self, f: FixedFaceHandle<InnerTag>) -> bool {
        self.inside.get(f.index()).copied().unwrap_or(false)
    }

    fn to_scaled(&self, uv: [f64; 2]) -> Point2<f64> {
        plane_point(uv, self.origin, self.scale)
    }

    fn uv_of_plane(&self, p: [f64; 2]) -> [f64; 2] {
        [
            p[0] / self.scale[0] + self.origin[0],
            p[1] / self.scale[1] + self.origin[1],
        ]
    }

    /// Curves whose boundary edges no triangle of `tris` uses (the mesh would have a hole there).
    pub fn missing_boundary_edges(&self, tris: &[[u32; 3]]) -> Vec<CurveId> {
        let mut seen = FastSet::default();
        for t in tris {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                seen.insert((a.min(b), a.max(b)));
            }
        }
        let mut out: Vec<CurveId> = self
            .boundary_mid
            .iter()
            .filter(|(k, bm)| !seen.contains(*k) && bm.node.pole.is_none())
            .map(|(_, bm)| bm.curve)
            .collect();
        out.sort();
        out.dedup();
        out
    }

    /// All triangles inside the domain, as local node ids, counter-clockwise in
    /// (u, v), including those with two nodes on the same pole.
    fn inside_triangles(&self) -> Vec<[u32; 3]> {
        let mut out = Vec::new();
        for f in self.cdt.inner_faces() {
            if self.is_inside(f.fix()) {
                let v = f.vertices();
                out.push([v[0].data().id, v[1].data().id, v[2].data().id]);
            }
        }
        out
    }

    /// The index (0..3) of the edge of `t` joining two nodes on the same pole, if any.
    fn pole_edge(&self, t: [u32; 3]) -> Option<usize> {
        (0..3).find(|&k| self.nodes[t[k] as usize].same_pole(&self.nodes[t[(k + 1) % 3] as usize]))
    }

    /// The inner triangles inside the domain, as local node ids, counter-clockwise
    /// in (u, v); triangles with two nodes on the same pole (zero area in 3D)
    /// are left out.
    pub fn triangles(&self) -> Vec<[u32; 3]> {
        self.inside_triangles()
            .into_iter()
            .filter(|&t| self.pole_edge(t).is_none())
            .collect()
    }

    /// Makes each pole one node in `tris` (this triangulation's
    /// [`Self::triangles`]): a pole's local instances along its (u, v) segment
    /// are replaced by the first, and the boundary midpoints of edges to a
    /// later instance are also keyed by the first. The two triangles on
    /// either side of a pole's vanishing triangle then share an edge, so
    /// recombination can pair them into the quad a pole corner asks for (at
    /// the 90° pole corner of s14o_cube_corner_sub_sphere's sphere octant, a
    /// fan of three quads and four irregular vertices around it otherwise).
    /// [`crate::triangulate::subdivide::subdivide`] already places midpoints and centres
    /// of elements at a pole by its one identity. Poles where a quad cornered
    /// there would fold ([`crate::core::queries::folds_at_pole`]: the apex of
    /// i04o_m4's half cones) keep their instances apart.
    pub fn merge_poles(&mut self, tris: &mut [[u32; 3]]) {
        let mut first: HashMap<NodeRef, Option<u32>> = HashMap::new();
        let mut canon: Vec<u32> = (0..self.nodes.len() as u32).collect();
        for (i, n) in self.nodes.iter().enumerate() {
            let Some(seg) = n.pole else { continue };
            // not where one quad cornered at the pole would fold (a cone's apex)
            let c = *first.entry(n.node).or_insert_with(|| {
                (!crate::core::queries::folds_at_pole(self.face, seg)).then_some(i as u32)
            });
            if let Some(c) = c {
                canon[i] = c;
            }
        }
        if canon.iter().enumerate().all(|(i, &c)| c == i as u32) {
            return;
        }
        for t in tris.iter_mut() {
            *t = t.map(|v| canon[v as usize]);
        }
        let mut aliases: Vec<((u32, u32), BoundaryMid)> = Vec::new();
        for (&(a, b), m) in &self.boundary_mid {
            let (ca, cb) = (canon[a as usize], canon[b as usize]);
            if (ca, cb) != (a, b) && ca != cb {
                aliases.push(((ca.min(cb), ca.max(cb)), *m));
            }
        }
        // sorted, so that a key reached from two instances gets the same one
        aliases.sort_by_key(|(k, _)| *k);
        for (k, m) in aliases {
            self.boundary_mid.entry(k).or_insert(m);
        }
    }

    fn is_boundary_edge(&self, a: u32, b: u32) -> bool {
        // boundary nodes come first: an edge with an inserted node is interior
        a < self.boundary_nodes
            && b < self.boundary_nodes
            && self.boundary_mid.contains_key(&(a.min(b), a.max(b)))
    }

    /// Surface point of a local (u, v).
    fn eval(&self, uv: [f64; 2]) -> Vec3 {
        self.face.surface.eval(uv)
    }

    /// (u, v) of the centroid of triangle `t` (poles moved toward the others).
    pub fn centroid_uv(&self, t: [u32; 3]) -> [f64; 2] {
        centroid_uv(&self.nodes, t)
    }
}

fn curve_of_node(loops: &[Vec<u32>], mids: &[Vec<BoundaryMid>], id: u32) -> Vec<CurveId> {
    let mut out = Vec::new();
    for (l, ids) in loops.iter().enumerate() {
        for (k, &i) in ids.iter().enumerate() {
            if i == id {
                out.push(mids[l][k].curve);
                out.push(mids[l][(k + ids.len() - 1) % ids.len()].curve);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests;
