//! The watertightness measure of a curve-network mesh (issue 30): its
//! open edges (used by one quad) sorted by where they lie, from the output
//! mesh and the network's curves alone:
//!
//! - **between cycles**: along a network curve that two or more meshed
//!   cycles use: the cycles did not agree on the curve's sampling, a real
//!   leak;
//! - **on unshared curves**: along a curve that one meshed cycle uses (the
//!   other user skipped, or none): the expected boundary of the mesh;
//! - **inside cycles**: along no network curve: a seam between the parts of
//!   one cycle (cuts, hole connectors) that were sampled differently.
//!
//! An edge lies along a curve when both its nodes are within the weld
//! tolerance of the curve's polyline and its midpoint within a quarter of
//! its length (a chord of the curve, not a cut across it).

use std::collections::{BTreeMap, HashMap};

use geometry::vec3::{self, Vec3};
use geometry::FaceId;
use mesh::QuadMesh;

use crate::curvenet::CurveNetwork;

/// Open and non-manifold edge counts of a curve-network mesh (module docs).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct OpenEdges {
    /// Every edge used by exactly one quad.
    pub total: usize,
    /// Open edges along curves two or more meshed cycles use.
    pub between_cycles: usize,
    /// Open edges along curves one meshed cycle uses.
    pub on_unshared_curves: usize,
    /// Open edges along no network curve (seams inside a cycle).
    pub inside_cycles: usize,
    /// Edges used by three or more quads.
    pub non_manifold: usize,
    /// Per cycle with open edges between or inside cycles:
    /// `(cycle, between, inside)`, in cycle order.
    pub by_cycle: Vec<(usize, usize, usize)>,
}

/// Sorts the open edges of `mesh` (module docs). `cycles`: the meshed
/// cycles; `tolerance`: the weld tolerance (nodes on a curve are within it).
pub fn classify_open_edges(
    net: &CurveNetwork,
    mesh: &QuadMesh,
    cycles: &[usize],
    tolerance: f64,
) -> OpenEdges {
    let uses = mesh::stats::edge_uses(mesh);
    let face_cycle: HashMap<FaceId, usize> = cycles
        .iter()
        .map(|&c| (net.cycles()[c].cad_face.unwrap_or(FaceId(c as u32)), c))
        .collect();
    let meshed: Vec<bool> = {
        let mut m = vec![false; net.cycles().len()];
        for &c in cycles {
            m[c] = true;
        }
        m
    };
    let mut out = OpenEdges::default();
    let mut per_cycle: BTreeMap<usize, (usize, usize)> = BTreeMap::new();
    // each edge off two quads with the quad of an open one (usize::MAX for
    // a non-manifold edge)
    let mut open: Vec<((u32, u32), usize)> = uses
        .iter()
        .filter(|(_, &n)| n > 2)
        .map(|(&e, _)| (e, usize::MAX))
        .collect();
    for (qi, q) in mesh.quads.iter().enumerate() {
        for k in 0..4 {
            let (a, b) = (q[k], q[(k + 1) % 4]);
            let e = (a.min(b), a.max(b));
            if uses.get(&e) == Some(&1) {
                open.push((e, qi));
            }
        }
    }
    open.sort_unstable();
    for ((a, b), quad) in open {
        if quad == usize::MAX {
            out.non_manifold += 1;
            continue;
        }
        out.total += 1;
        let (p, q) = (mesh.nodes[a as usize], mesh.nodes[b as usize]);
        let cycle = face_cycle.get(&mesh.quad_face[quad]).copied();
        let entry = cycle.map(|c| per_cycle.entry(c).or_default());
        match curve_along(net, p, q, tolerance) {
            Some(c) => {
                let mut users = net.curve_cycles(c);
                users.retain(|&u| meshed.get(u).copied().unwrap_or(false));
                users.sort_unstable();
                users.dedup();
                if users.len() >= 2 {
                    out.between_cycles += 1;
                    if let Some(e) = entry {
                        e.0 += 1;
                    }
                } else {
                    out.on_unshared_curves += 1;
                }
            }
            None => {
                out.inside_cycles += 1;
                if let Some(e) = entry {
                    e.1 += 1;
                }
            }
        }
    }
    out.by_cycle = per_cycle
        .into_iter()
        .filter(|(_, (b, i))| b + i > 0)
        .map(|(c, (b, i))| (c, b, i))
        .collect();
    out
}

/// The network curve the edge `p`–`q` runs along, if any: both ends
/// within `tolerance` of its polyline and the midpoint within a quarter of
/// the edge's length (the nearest such curve to the midpoint).
fn curve_along(net: &CurveNetwork, p: Vec3, q: Vec3, tolerance: f64) -> Option<usize> {
    let mid = vec3::scale(vec3::add(p, q), 0.5);
    let slack = tolerance + 0.25 * vec3::dist(p, q);
    let mut best: Option<(usize, f64)> = None;
    for (c, curve) in net.curves().iter().enumerate() {
        let distance = |x: Vec3| {
            curve
                .points
                .windows(2)
                .map(|w| vec3::segment_distance(x, w[0], w[1]))
                .fold(f64::INFINITY, f64::min)
        };
        if distance(p) > tolerance || distance(q) > tolerance {
            continue;
        }
        let d = distance(mid);
        if d <= slack && best.is_none_or(|(_, bd)| d < bd) {
            best = Some((c, d));
        }
    }
    best.map(|(c, _)| c)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::curvenet::parse_json;
    use crate::methods::curvenet::{mesh_curve_network, CurvesOptions, CurvesReport};

    /// Two unit squares side by side sharing the curve x = 1 (curve 2),
    /// each made of its own three outer curves plus the shared one; the
    /// right square's outer curves are `right` (3 curves, used once).
    fn two_squares() -> String {
        r#"{"curves":[
            {"points":[[0,0,0],[1,0,0]]},
            {"points":[[1,1,0],[0,1,0],[0,0,0]]},
            {"points":[[1,0,0],[1,1,0]]},
            {"points":[[1,0,0],[2,0,0],[2,1,0],[1,1,0]]}
          ],
          "cycles":[
            {"loops":[[[0,1],[2,1],[1,1]]]},
            {"loops":[[[3,1],[2,-1]]]}
          ]}"#
        .to_string()
    }

    /// The two squares parsed and meshed at h = 0.25, one thread.
    fn two_squares_meshed() -> (CurveNetwork, QuadMesh, CurvesReport) {
        let net = parse_json(&two_squares(), None).unwrap();
        let opts = CurvesOptions {
            size: Some(0.25),
            threads: Some(1),
            ..Default::default()
        };
        let (mesh, report) = mesh_curve_network(&net, &opts).unwrap();
        (net, mesh, report)
    }

    /// The shared side sampled alike by both squares: no open edge
    /// between cycles, none inside; the open edges are the outline (6 sides
    /// of the two squares at h = 0.25: 24 edges).
    #[test]
    fn two_squares_sampled_alike_have_no_open_edge_between_them() {
        let (net, mesh, report) = two_squares_meshed();
        let o = classify_open_edges(&net, &mesh, &[0, 1], net.weld_tolerance());
        assert_eq!(o.between_cycles, 0, "{o:?} {:?}", report.network);
        assert_eq!(o.inside_cycles, 0, "{o:?}");
        assert_eq!(o.non_manifold, 0, "{o:?}");
        assert_eq!(o.on_unshared_curves, 24, "{o:?}");
        assert_eq!(o.total, 24);
        assert!(o.by_cycle.is_empty());
        // Only the left square meshed: the shared side is its boundary.
        let left: Vec<usize> = vec![0];
        let o = classify_open_edges(&net, &mesh, &left, net.weld_tolerance());
        assert_eq!(o.between_cycles, 0, "{o:?}");
        assert_eq!(o.on_unshared_curves, 24, "{o:?}");
    }

    /// The same mesh with the right square's nodes on the shared side
    /// unwelded and slid along it (a different sampling of the same
    /// curve): 4 open edges on each square's copy of the side, 8 between
    /// cycles, counted per cycle; the outline unchanged.
    #[test]
    fn a_shared_side_sampled_apart_counts_as_open_between_cycles() {
        let (net, mut mesh, _) = two_squares_meshed();
        // Unweld the shared side: the right square's quads get their own
        // copies of the nodes on x = 1, shifted along the side by 1/8 so
        // that they sample it differently (still on the curve).
        let on_side = |p: Vec3| (p[0] - 1.0).abs() < 1e-12 && p[1] > 1e-12 && p[1] < 1.0 - 1e-12;
        let mut copy: HashMap<u32, u32> = HashMap::new();
        for (qi, quad) in mesh.quads.clone().iter().enumerate() {
            if mesh.quad_face[qi] != FaceId(1) {
                continue;
            }
            for k in 0..4 {
                let v = quad[k];
                let p = mesh.nodes[v as usize];
                if !on_side(p) {
                    continue;
                }
                let id = *copy.entry(v).or_insert_with(|| {
                    mesh.nodes.push([p[0], p[1] + 0.125 * (1.0 - p[1]), p[2]]);
                    mesh.node_class.push(mesh.node_class[v as usize]);
                    (mesh.nodes.len() - 1) as u32
                });
                mesh.quads[qi][k] = id;
            }
        }
        assert_eq!(copy.len(), 3, "h = 0.25: three inner nodes on the side");
        let o = classify_open_edges(&net, &mesh, &[0, 1], net.weld_tolerance());
        assert_eq!(o.between_cycles, 8, "{o:?}");
        assert_eq!(o.inside_cycles, 0, "{o:?}");
        assert_eq!(o.on_unshared_curves, 24, "{o:?}");
        assert_eq!(o.by_cycle, vec![(0, 4, 0), (1, 4, 0)]);
    }

    /// An edge across the inside of a cycle (a seam between two parts) is
    /// along no curve: counted inside the cycle.
    #[test]
    fn an_open_edge_across_a_cycle_is_inside_it() {
        let net = parse_json(&two_squares(), None).unwrap();
        let mut mesh = QuadMesh::default();
        // two quads of the left square meeting at x = 0.5, not welded
        mesh.nodes = vec![
            [0.0, 0.0, 0.0],
            [0.5, 0.0, 0.0],
            [0.5, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.5, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.5, 1.0, 0.0],
        ];
        mesh.node_class = vec![mesh::NodeClass::Face(FaceId(0), None); 8];
        mesh.quads = vec![[0, 1, 2, 3], [4, 5, 6, 7]];
        mesh.quad_face = vec![FaceId(0); 2];
        let o = classify_open_edges(&net, &mesh, &[0, 1], net.weld_tolerance());
        assert_eq!(o.total, 8);
        assert_eq!(o.inside_cycles, 2, "{o:?}");
        // the side x = 1 is curve 2, used by both cycles
        assert_eq!(o.between_cycles, 1, "{o:?}");
        assert_eq!(o.on_unshared_curves, 5, "{o:?}");
        assert_eq!(o.by_cycle, vec![(0, 1, 2)]);
    }
}
