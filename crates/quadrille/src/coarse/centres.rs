//! Layout vertex centres with an input edge for every block side (ours,
//! issue 29): a merged group's centre (§IV.B: "any" member) must leave by a
//! separate interior input edge for each interior block side ending there,
//! else no placement of the layout's edges exists. [`deficits`] finds the
//! vertices short of edges; [`recentre`] moves them within their group.

use super::block_layout::BlockLayout;
use super::connectivity::Connectivity;
use geometry::{vec3, FaceId};
use mesh::{NodeClass, QuadMesh};
use std::collections::{BTreeMap, HashSet};

/// The layout vertices whose centre node has fewer *exits* into a face
/// than interior block sides (not on a curve) of that face end there:
/// `(vertex, sides, exits)`. An exit is an input edge off the CAD curves
/// that a side's path may take out of the centre (as the router allows it):
/// to a node of the face that is no layout vertex, or straight to the other
/// end of one of those sides. Each side leaves by its own exit, so such a
/// layout cannot be placed by any router — e.g. a regular curve node (one
/// interior edge) where an arc along the curve collapsed and two sides meet,
/// or a merged group whose members' edges lead to other vertices.
pub(crate) fn deficits(
    mesh: &QuadMesh,
    conn: &Connectivity,
    layout: &BlockLayout,
    edge_curve: &[Option<u32>],
    edge_face: &[FaceId],
) -> Vec<(u32, usize, usize)> {
    let used: HashSet<u32> = layout.vertex_node.iter().copied().collect();
    let mut out = Vec::new();
    for (v, per_face) in interior_sides(layout, edge_curve, edge_face) {
        let c = layout.vertex_node[v as usize];
        for (f, others) in per_face {
            let m = exits(mesh, conn, c, f, &others, &used);
            if others.len() > m {
                out.push((v, others.len(), m));
                break;
            }
        }
    }
    out
}

/// Per layout vertex and face: the centre nodes of the other ends of its
/// interior block sides in that face (one entry per side).
fn interior_sides(
    layout: &BlockLayout,
    edge_curve: &[Option<u32>],
    edge_face: &[FaceId],
) -> BTreeMap<u32, BTreeMap<FaceId, Vec<u32>>> {
    let mut sides: BTreeMap<u32, BTreeMap<FaceId, Vec<u32>>> = BTreeMap::new();
    for (e, edge) in layout.edges.iter().enumerate() {
        if edge_curve[e].is_none() {
            for k in 0..2 {
                let other = layout.vertex_node[edge.ends[1 - k] as usize];
                sides.entry(edge.ends[k]).or_default().entry(edge_face[e]).or_default().push(other);
            }
        }
    }
    sides
}

/// The exits of centre `c` into face `f` ([`deficits`]): input edges off the
/// CAD curves to a node of `f` that is not in `used` (the layout vertices'
/// centres), or to one of `others` (the far ends of its sides).
fn exits(mesh: &QuadMesh, conn: &Connectivity, c: u32, f: FaceId, others: &[u32], used: &HashSet<u32>) -> usize {
    conn.neighbours(mesh, c)
        .0
        .into_iter()
        .filter(|&n| {
            conn.edge_curve(c, n).is_none()
                && (others.contains(&n)
                    || (!used.contains(&n) && matches!(mesh.node_class[n as usize], NodeClass::Face(g, _) if g == f)))
        })
        .count()
}

/// Moves the centre of each layout vertex with a deficit ([`deficits`]) to
/// another input node of its group with an exit for every block side in
/// every face they enter: same kind (face node, or node of the same CAD
/// curve; corners never move), not another vertex's centre, the nearest to
/// the old centre (ties: lowest id). Ours: the paper's "any node" of a merged
/// group (§IV.B) fails when a valence-5 group sits on a valence-4 node — five
/// sides cannot leave by four edges.
pub(crate) fn recentre(
    mesh: &QuadMesh,
    conn: &Connectivity,
    layout: &mut BlockLayout,
    edge_curve: &[Option<u32>],
    edge_face: &[FaceId],
    group_anchors: impl Fn(u32) -> Vec<u32>,
) -> usize {
    let sides = interior_sides(layout, edge_curve, edge_face);
    let mut used: HashSet<u32> = layout.vertex_node.iter().copied().collect();
    let mut moved = 0;
    for (v, per_face) in sides {
        let c = layout.vertex_node[v as usize];
        // the old centre is free once the vertex leaves it
        let mut free_c = used.clone();
        free_c.remove(&c);
        let enough =
            |n: u32, used: &HashSet<u32>| per_face.iter().all(|(&f, o)| exits(mesh, conn, n, f, o, used) >= o.len());
        if enough(c, &used) {
            continue;
        }
        let kind = |n: u32| match mesh.node_class[n as usize] {
            NodeClass::Corner(_) => None,
            NodeClass::Curve(cv, _) => Some(Some(cv)),
            _ => Some(None),
        };
        let Some(want) = kind(c) else { continue };
        let mut anchors = group_anchors(v);
        anchors.sort_unstable();
        anchors.dedup();
        let best = anchors
            .into_iter()
            .filter(|&n| !used.contains(&n) && kind(n) == Some(want) && enough(n, &free_c))
            .min_by(|&x, &y| {
                let d = |n: u32| vec3::dist(mesh.nodes[n as usize], mesh.nodes[c as usize]);
                d(x).total_cmp(&d(y)).then(x.cmp(&y))
            });
        if let Some(n) = best {
            used.remove(&c);
            used.insert(n);
            layout.vertex_node[v as usize] = n;
            moved += 1;
        }
    }
    moved
}

/// Logs (debug) a short layout vertex `v` with `(sides, exits)`: its centre,
/// class, valence, group size, collapsed arcs, the layout vertices next to
/// it and its sides' far ends (to tell merged groups from single nodes).
pub(crate) fn describe_short(
    mesh: &QuadMesh,
    conn: &Connectivity,
    layout: &BlockLayout,
    v: u32,
    (k, m): (usize, usize),
    members: usize,
    collapsed: usize,
) {
    if !tracing::enabled!(tracing::Level::DEBUG) {
        return;
    }
    let c = layout.vertex_node[v as usize];
    let nb = conn.neighbours(mesh, c).0;
    let used: HashSet<u32> = layout.vertex_node.iter().copied().collect();
    let near: Vec<u32> = nb.iter().copied().filter(|n| used.contains(n)).collect();
    let ends: Vec<u32> = layout
        .edges
        .iter()
        .filter(|e| e.ends.contains(&v))
        .map(|e| layout.vertex_node[(e.ends[0] + e.ends[1] - v) as usize])
        .collect();
    tracing::debug!(
        "coarse: short vertex at node {c} ({:?}, valence {}): {k} sides, {m} exits, {members} group members, {collapsed} collapsed arcs; vertex neighbours {near:?}, side ends {ends:?}",
        mesh.node_class[c as usize],
        nb.len()
    );
}
