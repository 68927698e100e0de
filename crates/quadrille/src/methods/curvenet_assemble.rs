//! The curve-network method's last stage: the cycles' quads in one
//! [`QuadMesh`], welded where their boundary samples coincide, with nodes
//! and edges classified on the network's corners and curves, the rest on
//! face = cycle id (issue 30 item 9, node classification).

use std::collections::BTreeMap;

use geometry::vec3::{self, Vec3};
use geometry::{CornerId, CurveId, FaceId};
use mesh::{NodeClass, QuadMesh};

use crate::core::fast_hash::FastMap;
use crate::curvenet::{CurveNetwork, CycleQuads, JUNCTION_TURN_DEGREES};

/// The cycles' quads in one mesh: boundary nodes (on the cycle's loops, its
/// cuts and connectors) within the weld tolerance of one another merged;
/// boundary nodes on a network curve classified on the nearest curve (curve
/// end points as corners), the rest on face = cycle id. Returns the mesh and
/// the number of merged nodes.
pub(super) fn assemble(net: &CurveNetwork, meshed: &[(usize, Vec<CycleQuads>)], weld: &Welder) -> (QuadMesh, usize) {
    let on_curve = weld.tolerance.max(1e-9 * net.diagonal());
    let curves: Vec<&[Vec3]> = net.curves().iter().map(|c| &c.points[..]).collect();
    let mut corner_at = WeldIndex::default();
    let mut corner_points: Vec<Vec3> = Vec::new();
    for p in corner_candidates(net) {
        if corner_at.find(weld, p, &corner_points).is_none() {
            corner_at.insert(weld, p, corner_points.len() as u32);
            corner_points.push(p);
        }
    }
    let mut mesh = QuadMesh::default();
    let mut boundary_at = WeldIndex::default();
    let mut welded = 0;
    // CAD networks keep the CAD's ids (so `stats --cad` measures against the
    // right entities); their corners are not numbered like the CAD's, so
    // corner nodes are classified on their curve instead.
    let from_cad = net.cycles().iter().any(|c| c.cad_face.is_some());
    let curve_id = |c: u32| net.curves()[c as usize].cad.unwrap_or(CurveId(c));
    for (cycle, pieces) in meshed {
        let face = net.cycles()[*cycle].cad_face.unwrap_or(FaceId(*cycle as u32));
        for q in pieces {
            let mut ids: Vec<u32> = Vec::with_capacity(q.nodes.len());
            for (&p, &on_boundary) in q.nodes.iter().zip(&q.boundary) {
                if on_boundary {
                    if let Some(id) = boundary_at.find(weld, p, &mesh.nodes) {
                        welded += 1;
                        ids.push(id);
                        continue;
                    }
                }
                let id = mesh.nodes.len() as u32;
                let class = if !on_boundary {
                    NodeClass::Face(face, None)
                } else {
                    match (corner_at.find(weld, p, &corner_points), nearest_curve(&curves, p)) {
                        (Some(c), _) if !from_cad => NodeClass::Corner(CornerId(c)),
                        (_, Some((c, d))) if d <= on_curve => NodeClass::Curve(curve_id(c), None),
                        _ => NodeClass::Face(face, None),
                    }
                };
                mesh.nodes.push(p);
                mesh.node_class.push(class);
                if on_boundary {
                    boundary_at.insert(weld, p, id);
                }
                ids.push(id);
            }
            for quad in &q.quads {
                mesh.quads.push(quad.map(|v| ids[v]));
                mesh.quad_face.push(face);
            }
        }
    }
    for (n, class) in mesh.node_class.iter().enumerate() {
        if let NodeClass::Corner(c) = class {
            mesh.corner_nodes.push((n as u32, *c));
        }
    }
    mesh.curve_edges = curve_edges(&mesh, &curves)
        .into_iter()
        .map(|(e, c)| (e, curve_id(c.0)))
        .collect();
    (mesh, welded)
}

/// The points meshed as corner nodes: every curve's end points, the points
/// where a curve turns by more than [`JUNCTION_TURN_DEGREES`], and the
/// network's listed corners, in that order.
fn corner_candidates(net: &CurveNetwork) -> Vec<Vec3> {
    let sharp = JUNCTION_TURN_DEGREES.to_radians();
    let mut out = Vec::new();
    for c in net.curves() {
        out.extend(c.points.first().copied());
        out.extend(c.points.last().copied());
        for w in c.points.windows(3) {
            let (a, b) = (vec3::sub(w[1], w[0]), vec3::sub(w[2], w[1]));
            let (la, lb) = (vec3::norm(a), vec3::norm(b));
            if la > 0.0 && lb > 0.0 && (vec3::dot(a, b) / (la * lb)).clamp(-1.0, 1.0).acos() > sharp {
                out.push(w[1]);
            }
        }
    }
    out.extend_from_slice(net.corners());
    out
}

/// Cells of the weld tolerance's size: points of two parts or cycles that
/// are one point fall in the same or a neighbouring cell.
pub(super) struct Welder {
    pub(super) tolerance: f64,
    cell_size: f64,
}

impl Welder {
    pub(super) fn new(tolerance: f64) -> Self {
        let tolerance = tolerance.max(f64::MIN_POSITIVE);
        Welder { tolerance, cell_size: 2.0 * tolerance }
    }

    /// The cell of `p`.
    pub(super) fn cell(&self, p: Vec3) -> [i64; 3] {
        p.map(|x| (x / self.cell_size).floor() as i64)
    }
}

/// Point ids by cell, for [`Welder`] searches.
#[derive(Default)]
struct WeldIndex {
    at: FastMap<[i64; 3], Vec<u32>>,
}

impl WeldIndex {
    /// The first stored point within the tolerance of `p` (`points[id]`
    /// are the stored points' positions), searching the 27 cells around it.
    fn find(&self, weld: &Welder, p: Vec3, points: &[Vec3]) -> Option<u32> {
        let c = weld.cell(p);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let key = [c[0] + dx, c[1] + dy, c[2] + dz];
                    if let Some(ids) = self.at.get(&key) {
                        if let Some(&id) = ids
                            .iter()
                            .find(|&&id| vec3::dist(points[id as usize], p) <= weld.tolerance)
                        {
                            return Some(id);
                        }
                    }
                }
            }
        }
        None
    }

    fn insert(&mut self, weld: &Welder, p: Vec3, id: u32) {
        self.at.entry(weld.cell(p)).or_default().push(id);
    }
}

/// The curve whose polyline passes nearest to `p`, and the distance.
fn nearest_curve(curves: &[&[Vec3]], p: Vec3) -> Option<(u32, f64)> {
    let mut best: Option<(u32, f64)> = None;
    for (i, c) in curves.iter().enumerate() {
        for w in c.windows(2) {
            let d = vec3::segment_distance(p, w[0], w[1]);
            if best.is_none_or(|b| d < b.1) {
                best = Some((i as u32, d));
            }
        }
    }
    best
}

/// Edges used by one quad of their cycle whose two nodes lie on the
/// network's curves, each on the curve nearest its middle: the mesh edges
/// along the curves (written as line elements).
fn curve_edges(mesh: &QuadMesh, curves: &[&[Vec3]]) -> Vec<([u32; 2], CurveId)> {
    let mut uses: BTreeMap<(u32, u32, u32), u32> = BTreeMap::new();
    for (q, f) in mesh.quads.iter().zip(&mesh.quad_face) {
        for k in 0..4 {
            let (a, b) = (q[k], q[(k + 1) % 4]);
            *uses.entry((a.min(b), a.max(b), f.0)).or_insert(0) += 1;
        }
    }
    let on_curve = |n: u32| !matches!(mesh.node_class[n as usize], NodeClass::Face(..));
    let mut edges: Vec<[u32; 2]> = uses
        .into_iter()
        .filter(|&((a, b, _), n)| n == 1 && on_curve(a) && on_curve(b))
        .map(|((a, b, _), _)| [a, b])
        .collect();
    edges.dedup();
    edges
        .into_iter()
        .filter_map(|[a, b]| {
            let mid = vec3::scale(vec3::add(mesh.nodes[a as usize], mesh.nodes[b as usize]), 0.5);
            nearest_curve(curves, mid).map(|(c, _)| ([a, b], CurveId(c)))
        })
        .collect()
}

