//! Independent checks of a meshed model: quality with the CAD normals, open
//! edges, Euler characteristic, distance to the CAD, curve chains.

#![allow(dead_code)]

use std::collections::HashMap;
use std::path::PathBuf;

use geometry::vec3::{self, Vec3};
use geometry::{CurveId, FaceId, Model};
use mesh::quality::corner_sicn;
use mesh::{NodeClass, QuadMesh};

/// Measured properties of a mesh.
#[derive(Debug, Clone)]
pub struct Report {
    pub quads: usize,
    pub nodes: usize,
    pub min_sicn: f64,
    pub avg_sicn: f64,
    pub inverted: usize,
    pub open_edges: usize,
    pub nonmanifold_edges: usize,
    pub euler: i64,
    pub max_dist: f64,
    pub diagonal: f64,
    pub chain_errors: Vec<String>,
    pub class_errors: Vec<String>,
}

/// Candidate (u, v) of node `n` on face `f`.
fn node_uvs(model: &Model, mesh: &QuadMesh, f: FaceId, n: usize) -> Vec<[f64; 2]> {
    let face = &model.faces[f.idx()];
    match mesh.node_class[n] {
        NodeClass::Face(ff, Some(uv)) if ff == f => vec![uv],
        NodeClass::Curve(c, Some(t)) => face
            .curve_uses()
            .filter(|u| u.curve == c)
            .map(|u| u.pcurve.eval(t))
            .collect(),
        NodeClass::Corner(c) => {
            let mut out = Vec::new();
            for u in face.curve_uses() {
                let ce = &model.curves[u.curve.idx()];
                if ce.start == c {
                    out.push(u.pcurve.eval(ce.range.0));
                }
                if ce.end == c {
                    out.push(u.pcurve.eval(ce.range.1));
                }
            }
            if let Some((uv, _)) = face.surface.project(mesh.nodes[n], None) {
                out.push(uv);
            }
            out
        }
        _ => Vec::new(),
    }
}

fn node_normal(model: &Model, mesh: &QuadMesh, f: FaceId, n: usize) -> Option<Vec3> {
    let face = &model.faces[f.idx()];
    // a corner on a degenerate curve of the face is a singular point (pole,
    // apex): the CAD normal is undefined there, the caller uses the quad's others
    if let NodeClass::Corner(c) = mesh.node_class[n] {
        if face.curve_uses().any(|u| {
            model.curves[u.curve.idx()].degenerate && model.curves[u.curve.idx()].start == c
        }) {
            return None;
        }
    }
    node_uvs(model, mesh, f, n)
        .into_iter()
        .find_map(|uv| face.normal(uv))
}

/// CAD normal of face `f` at the (u, v) centre of quad `q`: the mean of its
/// corners' (u, v), each corner's candidate (a seam node has two) taken
/// nearest to a face-interior corner's (u, v), or to the first candidate.
fn centre_normal(model: &Model, mesh: &QuadMesh, f: FaceId, q: &[u32; 4]) -> Option<Vec3> {
    let face = &model.faces[f.idx()];
    let cands: Vec<Vec<[f64; 2]>> = q
        .iter()
        .map(|&v| node_uvs(model, mesh, f, v as usize))
        .collect();
    let hint = q
        .iter()
        .find_map(|&v| match mesh.node_class[v as usize] {
            NodeClass::Face(ff, Some(uv)) if ff == f => Some(uv),
            _ => None,
        })
        .or_else(|| cands.iter().flatten().next().copied())?;
    let d2 = |a: [f64; 2]| (a[0] - hint[0]).powi(2) + (a[1] - hint[1]).powi(2);
    let mut sum = [0.0, 0.0];
    for c in &cands {
        let uv = c.iter().copied().min_by(|a, b| d2(*a).total_cmp(&d2(*b)))?;
        sum = [sum[0] + 0.25 * uv[0], sum[1] + 0.25 * uv[1]];
    }
    face.normal(sum)
}

/// Measures `mesh` against `model`.
pub fn check(model: &Model, mesh: &QuadMesh) -> Report {
    let diagonal = model.diagonal();
    let mut min_sicn = f64::INFINITY;
    let mut sum = 0.0;
    let mut inverted = 0;
    let mut class_errors = Vec::new();
    for (qi, q) in mesh.quads.iter().enumerate() {
        let f = mesh.quad_face[qi];
        let p = [0, 1, 2, 3].map(|k| mesh.nodes[q[k] as usize]);
        let mut ns: [Option<Vec3>; 4] =
            [0, 1, 2, 3].map(|k| node_normal(model, mesh, f, q[k] as usize));
        // a singular point (pole): use the mean of the other corners' normals
        let known: Vec<Vec3> = ns.iter().flatten().copied().collect();
        if known.is_empty() {
            class_errors.push(format!("quad {qi}: no CAD normal at any corner"));
            continue;
        }
        let mean = vec3::normalize(known.iter().fold([0.0; 3], |a, &b| vec3::add(a, b)))
            .unwrap_or(known[0]);
        for n in ns.iter_mut() {
            if n.is_none() {
                *n = Some(mean);
            }
        }
        let mut n = ns.map(|n| n.unwrap_or(mean));
        // a corner on a CAD curve whose normal is more than 90° from the
        // surface's at the quad's centre: the surface folds back inside the
        // quad (a trailing edge rounded far below the quad size), and the
        // quad is measured against the surface on its own side
        let on_curve = |k: usize| {
            matches!(
                mesh.node_class[q[k] as usize],
                NodeClass::Curve(..) | NodeClass::Corner(_)
            )
        };
        if (0..4).any(on_curve) {
            if let Some(nc) = centre_normal(model, mesh, f, q) {
                for k in (0..4).filter(|&k| on_curve(k)) {
                    if vec3::dot(n[k], nc) < 0.0 {
                        n[k] = nc;
                    }
                }
            }
        }
        let s = corner_sicn(&p, &n)
            .into_iter()
            .fold(f64::INFINITY, f64::min);
        if !(s > 0.0) {
            inverted += 1;
        }
        min_sicn = min_sicn.min(s);
        sum += s;
    }
    // edges
    let mut edges: HashMap<(u32, u32), usize> = HashMap::new();
    for q in &mesh.quads {
        for k in 0..4 {
            let (a, b) = (q[k], q[(k + 1) % 4]);
            *edges.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    let open_edges = edges.values().filter(|&&c| c == 1).count();
    let nonmanifold_edges = edges.values().filter(|&&c| c > 2).count();
    let mut used = vec![false; mesh.nodes.len()];
    for q in &mesh.quads {
        for &n in q {
            used[n as usize] = true;
        }
    }
    let v = used.iter().filter(|&&u| u).count() as i64;
    let euler = v - edges.len() as i64 + mesh.quads.len() as i64;
    // distance to the CAD
    let mut max_dist = 0.0f64;
    for (i, x) in mesh.nodes.iter().enumerate() {
        let d = match mesh.node_class[i] {
            NodeClass::Corner(c) => vec3::dist(model.corners[c.idx()].point, *x),
            NodeClass::Curve(c, Some(t)) => vec3::dist(model.curves[c.idx()].eval(model, t), *x),
            NodeClass::Face(f, Some(uv)) => vec3::dist(model.faces[f.idx()].surface.eval(uv), *x),
            other => {
                class_errors.push(format!("node {i} has classification {other:?}"));
                0.0
            }
        };
        max_dist = max_dist.max(d);
    }
    for (qi, q) in mesh.quads.iter().enumerate() {
        for &n in q {
            if let NodeClass::Face(f, _) = mesh.node_class[n as usize] {
                if f != mesh.quad_face[qi] {
                    class_errors.push(format!(
                        "quad {qi} of face {:?} uses interior node {n} of face {f:?}",
                        mesh.quad_face[qi]
                    ));
                }
            }
        }
    }
    // sliver curves may be meshed as points (the default method does,
    // `quadrille::SLIVER_LENGTH`): no edges, and their end corners
    // share one node; a sliver whose merged-away corner has a node of its own
    // was meshed as a curve and is checked like any other
    let slivers: Vec<geometry::slivers::Collapsed> =
        geometry::slivers::collapse_short_curves(model, quadrille::SLIVER_LENGTH * diagonal)
            .map(|(_, list)| list)
            .unwrap_or_default()
            .into_iter()
            .filter(|c| !mesh.corner_nodes.iter().any(|&(_, k)| k == c.removed))
            .collect();
    let mut rep: Vec<usize> = (0..model.corners.len()).collect();
    for c in &slivers {
        rep[c.removed.idx()] = c.kept.idx();
    }
    for i in 0..rep.len() {
        while rep[rep[i]] != rep[i] {
            rep[i] = rep[rep[i]];
        }
    }
    let mut corner_node = vec![u32::MAX; model.corners.len()];
    for (i, _) in model.corners.iter().enumerate() {
        if rep[i] != i {
            continue;
        }
        match mesh.corner_nodes.iter().find(|&&(n, c)| {
            c.idx() == i && matches!(mesh.node_class[n as usize], NodeClass::Corner(cc) if cc == c)
        }) {
            Some(&(n, _)) => corner_node[i] = n,
            None => class_errors.push(format!("corner {i} has no corner node")),
        }
    }
    let node_of_corner = |c: geometry::CornerId| corner_node[rep[c.idx()]];
    // curve chains
    let mut chain_errors = Vec::new();
    for (ci, ce) in model.curves.iter().enumerate() {
        if ce.degenerate {
            continue;
        }
        let sliver = slivers.iter().any(|c| c.curve.idx() == ci);
        let es: Vec<[u32; 2]> = mesh
            .curve_edges
            .iter()
            .filter(|(_, c)| *c == CurveId(ci as u32))
            .map(|(e, _)| *e)
            .collect();
        if sliver {
            if !es.is_empty() {
                chain_errors.push(format!("sliver curve {ci} has {} edges", es.len()));
            }
            continue;
        }
        if es.is_empty() {
            chain_errors.push(format!("curve {ci} has no edges"));
            continue;
        }
        let used_by_faces = model
            .faces
            .iter()
            .any(|f| f.curve_uses().any(|u| u.curve.idx() == ci));
        let mut cur = node_of_corner(ce.start);
        for (k, e) in es.iter().enumerate() {
            if e[0] != cur {
                chain_errors.push(format!("curve {ci}: edge {k} does not continue the chain"));
                break;
            }
            if used_by_faces && !edges.contains_key(&(e[0].min(e[1]), e[0].max(e[1]))) {
                chain_errors.push(format!("curve {ci}: edge {k} is not a quad edge"));
            }
            cur = e[1];
        }
        if cur != node_of_corner(ce.end) {
            chain_errors.push(format!("curve {ci}: chain does not end at its end corner"));
        }
        let on_curve = mesh
            .node_class
            .iter()
            .filter(|c| matches!(c, NodeClass::Curve(cc, _) if cc.idx() == ci))
            .count();
        if on_curve + 1 != es.len() {
            chain_errors.push(format!(
                "curve {ci}: {} edges for {on_curve} curve nodes",
                es.len()
            ));
        }
    }
    Report {
        quads: mesh.quads.len(),
        nodes: mesh.nodes.len(),
        min_sicn,
        avg_sicn: sum / mesh.quads.len().max(1) as f64,
        inverted,
        open_edges,
        nonmanifold_edges,
        euler,
        max_dist,
        diagonal,
        chain_errors,
        class_errors,
    }
}

/// Edges on the boundary of the model (curves used by exactly one face), counted in mesh edges.
pub fn boundary_mesh_edges(model: &Model, mesh: &QuadMesh) -> usize {
    let cf = model.curve_faces();
    mesh.curve_edges
        .iter()
        .filter(|(_, c)| {
            let uses: usize = model
                .faces
                .iter()
                .map(|f| f.curve_uses().filter(|u| u.curve == *c).count())
                .sum();
            cf[c.idx()].len() == 1 && uses == 1
        })
        .count()
}

/// The bundled CAD models (`data/cad/*.step|stp`), sorted; `QUADRILLE_MODELS`
/// (comma-separated parts of names) keeps only those it names.
pub fn cad_models() -> Vec<PathBuf> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../data/cad");
    let filter: Vec<String> = std::env::var("QUADRILLE_MODELS")
        .map(|s| s.split(',').map(str::to_string).collect())
        .unwrap_or_default();
    let mut out: Vec<PathBuf> = std::fs::read_dir(&dir)
        .map(|rd| rd.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    out.retain(|p| {
        let ext = p
            .extension()
            .and_then(|e| e.to_str())
            .unwrap_or("")
            .to_ascii_lowercase();
        let name = p.file_name().and_then(|n| n.to_str()).unwrap_or("");
        (ext == "step" || ext == "stp")
            && (filter.is_empty() || filter.iter().any(|f| name.contains(f.as_str())))
    });
    out.sort();
    out
}
