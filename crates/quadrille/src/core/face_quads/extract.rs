//! Conversion between a global [`QuadMesh`] and per-face [`FaceQuads`].
//!
//! [`extract_face`] gives every quad vertex of one face a single-valued (u, v)
//! in that face: interior nodes carry it in their classification; nodes on
//! curves and corners get it from the face's pcurves (a seam node has two
//! candidates, one per side; a pole has a whole segment), and each quad picks
//! the candidate nearest to its interior nodes. Different picks of the same
//! global node become different local vertices (the two sides of a seam).
//!
//! [`write_back`] rebuilds the global mesh: boundary nodes keep their index,
//! position and classification bit-for-bit; the interior nodes of the edited
//! faces are replaced by the live movable vertices of their [`FaceQuads`].

use std::collections::{BTreeMap, BTreeSet};

use geometry::{FaceId, Model};
use mesh::{NodeClass, QuadMesh};

use super::{FaceQuads, QVertex};

/// Why a face could not be turned into a [`FaceQuads`] (the face is then left as it is).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ExtractError {
    /// The face id is not in the model.
    #[error("face {} is not in the model", .0 .0 + 1)]
    NoSuchFace(FaceId),
    /// A quad refers to a node index past the end of the mesh.
    #[error("quad {0} refers to a missing node")]
    BadNode(usize),
    /// No (u, v) could be found for a node of the face.
    #[error("node {0} has no (u, v) on face {}", .1 .0 + 1)]
    NoUv(usize, FaceId),
    /// The quads of the face do not form a consistently oriented manifold.
    #[error("face {}: {1}", .0 .0 + 1)]
    Inconsistent(FaceId, String),
}

#[derive(Clone, Copy, Debug)]
enum Cand {
    Pt([f64; 2]),
    Pole([[f64; 2]; 2]),
}

impl Cand {
    fn nearest(&self, p: [f64; 2]) -> [f64; 2] {
        match *self {
            Cand::Pt(x) => x,
            Cand::Pole(seg) => {
                let v = QVertex {
                    pole: Some(seg),
                    ..QVertex::interior(seg[0], [0.0; 3], NodeClass::Unclassified)
                };
                v.uv_toward(p)
            }
        }
    }
    fn dist2(&self, p: [f64; 2]) -> f64 {
        let q = self.nearest(p);
        (q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2)
    }
}

/// The quads of each face: `(face, quad indices in mesh order)`, faces in increasing id.
pub fn quads_by_face(mesh: &QuadMesh) -> Vec<(FaceId, Vec<usize>)> {
    let mut m: BTreeMap<FaceId, Vec<usize>> = BTreeMap::new();
    for (qi, f) in mesh.quad_face.iter().enumerate().take(mesh.quads.len()) {
        m.entry(*f).or_default().push(qi);
    }
    m.into_iter().collect()
}

fn candidates(model: &Model, fid: FaceId, class: NodeClass, xyz: [f64; 3]) -> Vec<Cand> {
    let face = &model.faces[fid.idx()];
    let mut out = Vec::new();
    match class {
        NodeClass::Curve(c, Some(t)) => {
            for u in face.curve_uses().filter(|u| u.curve == c) {
                out.push(Cand::Pt(u.pcurve.eval(t)));
            }
        }
        NodeClass::Corner(k) => {
            for u in face.curve_uses() {
                let Some(ce) = model.curves.get(u.curve.idx()) else {
                    continue;
                };
                if ce.degenerate && (ce.start == k || ce.end == k) {
                    out.push(Cand::Pole(face.pole_segment(u, ce)));
                    continue;
                }
                let (a, b) = (u.pcurve.eval(ce.range.0), u.pcurve.eval(ce.range.1));
                if ce.start == k {
                    out.push(Cand::Pt(a));
                }
                if ce.end == k {
                    out.push(Cand::Pt(b));
                }
            }
        }
        _ => {}
    }
    // drop duplicates (a corner shared by two consecutive uses)
    let b = face.uv_bounds;
    let tol = 1e-9 * ((b.umax - b.umin).abs() + (b.vmax - b.vmin).abs()).max(1e-12);
    let mut dedup: Vec<Cand> = Vec::new();
    for c in out {
        let p = c.nearest([0.0, 0.0]);
        let dup = dedup.iter().any(|d| match (c, d) {
            (Cand::Pt(_), Cand::Pt(_)) => d.dist2(p) < tol * tol,
            (Cand::Pole(s), Cand::Pole(t)) => s == *t,
            _ => false,
        });
        if !dup && p[0].is_finite() && p[1].is_finite() {
            dedup.push(c);
        }
    }
    if dedup.is_empty() {
        if let Some((uv, _)) = face.surface.project(xyz, None) {
            dedup.push(Cand::Pt(uv));
        }
    }
    dedup
}

/// Builds the [`FaceQuads`] of face `fid` from the quads `quad_ids` of `mesh`.
///
/// Vertices classified inside the face are movable; all others (corners, curve
/// nodes, poles, seam copies, nodes of other faces) are fixed with their input
/// position. A face-interior vertex whose fan is not a closed disk is fixed too.
/// Ideal valences: 4 inside; on the boundary from the interior angle
/// ([`super::ideal_boundary_valence`]); poles and other odd fixed vertices keep their
/// current valence as ideal (they are not counted as irregular).
pub fn extract_face(
    model: &Model,
    mesh: &QuadMesh,
    fid: FaceId,
    quad_ids: &[usize],
) -> Result<FaceQuads, ExtractError> {
    if fid.idx() >= model.faces.len() {
        return Err(ExtractError::NoSuchFace(fid));
    }
    let face = &model.faces[fid.idx()];
    let nn = mesh.nodes.len().min(mesh.node_class.len());
    // (u, v) of face-interior nodes, candidates of the others (cached by node)
    let mut interior_uv: BTreeMap<u32, [f64; 2]> = BTreeMap::new();
    let mut cands: BTreeMap<u32, Vec<Cand>> = BTreeMap::new();
    for &qi in quad_ids {
        let q = mesh.quads.get(qi).ok_or(ExtractError::BadNode(qi))?;
        for &n in q {
            if n as usize >= nn {
                return Err(ExtractError::BadNode(qi));
            }
            if interior_uv.contains_key(&n) || cands.contains_key(&n) {
                continue;
            }
            match mesh.node_class[n as usize] {
                NodeClass::Face(f, uv) if f == fid => {
                    let uv = match uv {
                        Some(uv) => uv,
                        None => {
                            face.surface
                                .project(mesh.nodes[n as usize], None)
                                .ok_or(ExtractError::NoUv(n as usize, fid))?
                                .0
                        }
                    };
                    interior_uv.insert(n, uv);
                }
                c => {
                    let cs = candidates(model, fid, c, mesh.nodes[n as usize]);
                    if cs.is_empty() {
                        return Err(ExtractError::NoUv(n as usize, fid));
                    }
                    cands.insert(n, cs);
                }
            }
        }
    }
    // local vertex per (node, candidate)
    let mut local: BTreeMap<(u32, usize), u32> = BTreeMap::new();
    let mut verts: Vec<QVertex> = Vec::new();
    let mut quads: Vec<[u32; 4]> = Vec::with_capacity(quad_ids.len());
    for &qi in quad_ids {
        let q = mesh.quads[qi];
        let inner: Vec<[f64; 2]> = q
            .iter()
            .filter_map(|n| interior_uv.get(n).copied())
            .collect();
        let reference = if !inner.is_empty() {
            inner
        } else {
            q.iter()
                .filter_map(|n| {
                    cands
                        .get(n)
                        .filter(|c| c.len() == 1)
                        .map(|c| c[0].nearest([0.0, 0.0]))
                })
                .collect()
        };
        if reference.is_empty() {
            return Err(ExtractError::NoUv(q[0] as usize, fid));
        }
        let k = reference.len() as f64;
        let r = [
            reference.iter().map(|p| p[0]).sum::<f64>() / k,
            reference.iter().map(|p| p[1]).sum::<f64>() / k,
        ];
        let mut lq = [0u32; 4];
        for i in 0..4 {
            let n = q[i];
            let (key, make): ((u32, usize), Box<dyn Fn() -> QVertex>) =
                if let Some(&uv) = interior_uv.get(&n) {
                    let xyz = mesh.nodes[n as usize];
                    (
                        (n, 0),
                        Box::new(move || QVertex {
                            global: Some(n),
                            ..QVertex::interior(uv, xyz, NodeClass::Face(fid, Some(uv)))
                        }),
                    )
                } else {
                    let cs = &cands[&n];
                    let best = (0..cs.len())
                        .min_by(|&a, &b| cs[a].dist2(r).total_cmp(&cs[b].dist2(r)))
                        .unwrap_or(0);
                    let c = cs[best];
                    let uv = c.nearest(r);
                    let xyz = mesh.nodes[n as usize];
                    let class = mesh.node_class[n as usize];
                    let pole = if let Cand::Pole(s) = c { Some(s) } else { None };
                    (
                        (n, best),
                        Box::new(move || QVertex {
                            uv,
                            xyz,
                            class,
                            fixed: true,
                            global: Some(n),
                            pole,
                            ideal: 0,
                            edge_offset: 1,
                            fan: Vec::new(),
                            alive: true,
                        }),
                    )
                };
            let id = *local.entry(key).or_insert_with(|| {
                verts.push(make());
                (verts.len() - 1) as u32
            });
            lq[i] = id;
        }
        quads.push(lq);
    }
    let mut fq = FaceQuads::new(verts, quads)
        .ok_or_else(|| ExtractError::Inconsistent(fid, "a quad repeats a vertex".into()))?;
    fq.classify_fixed();
    fq.check().map_err(|e| ExtractError::Inconsistent(fid, e))?;
    Ok(fq)
}

/// Rebuilds `mesh` with the faces in `edited` replaced by their [`FaceQuads`].
///
/// Nodes that are not movable vertices of an edited face keep their position and
/// classification (boundary nodes are bit-identical); the new interior nodes
/// follow, face by face. Quads are written face by face in increasing face id;
/// faces not in `edited` keep their quads in the original order.
pub fn write_back(mesh: &QuadMesh, edited: &[(FaceId, &FaceQuads)]) -> QuadMesh {
    let edited_ids: BTreeSet<FaceId> = edited.iter().map(|e| e.0).collect();
    let nn = mesh.nodes.len();
    let mut keep = vec![true; nn];
    for (n, c) in mesh.node_class.iter().enumerate().take(nn) {
        if let NodeClass::Face(f, _) = c {
            if edited_ids.contains(f) {
                keep[n] = false;
            }
        }
    }
    for (_, fq) in edited {
        for v in &fq.verts {
            if v.fixed && v.alive {
                if let Some(g) = v.global {
                    if (g as usize) < nn {
                        keep[g as usize] = true;
                    }
                }
            }
        }
    }
    let mut out = QuadMesh::default();
    let mut map = vec![u32::MAX; nn];
    for n in 0..nn {
        if keep[n] {
            map[n] = out.nodes.len() as u32;
            out.nodes.push(mesh.nodes[n]);
            out.node_class.push(
                mesh.node_class
                    .get(n)
                    .copied()
                    .unwrap_or(NodeClass::Unclassified),
            );
        }
    }
    let mut local_maps: BTreeMap<FaceId, Vec<u32>> = BTreeMap::new();
    for (fid, fq) in edited {
        let mut lm = vec![u32::MAX; fq.verts.len()];
        for q in fq.live_quads() {
            for v in fq.quads[q as usize] {
                let x = &fq.verts[v as usize];
                if lm[v as usize] != u32::MAX {
                    continue;
                }
                lm[v as usize] = match (x.fixed, x.global) {
                    (true, Some(g)) if (g as usize) < nn => map[g as usize],
                    _ => {
                        out.nodes.push(x.xyz);
                        out.node_class.push(NodeClass::Face(*fid, Some(x.uv)));
                        (out.nodes.len() - 1) as u32
                    }
                };
            }
        }
        local_maps.insert(*fid, lm);
    }
    for (fid, qids) in quads_by_face(mesh) {
        if let Some((_, fq)) = edited.iter().find(|e| e.0 == fid) {
            let lm = &local_maps[&fid];
            for q in fq.live_quads() {
                out.quads.push(fq.quads[q as usize].map(|v| lm[v as usize]));
                out.quad_face.push(fid);
            }
        } else {
            for qi in qids {
                let q = mesh.quads[qi];
                if q.iter()
                    .all(|&n| (n as usize) < nn && map[n as usize] != u32::MAX)
                {
                    out.quads.push(q.map(|n| map[n as usize]));
                    out.quad_face.push(fid);
                }
            }
        }
    }
    let ok = |n: u32| (n as usize) < nn && map[n as usize] != u32::MAX;
    for (t, f) in mesh.triangles.iter().zip(&mesh.triangle_face) {
        if t.iter().all(|&n| ok(n)) {
            out.triangles.push(t.map(|n| map[n as usize]));
            out.triangle_face.push(*f);
        }
    }
    for (e, c) in &mesh.curve_edges {
        if ok(e[0]) && ok(e[1]) {
            out.curve_edges
                .push(([map[e[0] as usize], map[e[1] as usize]], *c));
        }
    }
    for (n, c) in &mesh.corner_nodes {
        if ok(*n) {
            out.corner_nodes.push((map[*n as usize], *c));
        }
    }
    out
}
