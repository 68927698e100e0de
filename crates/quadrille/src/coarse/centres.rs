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

/// The layout vertices whose centre node has fewer input edges into a face
/// than interior block sides (not on a curve) of that face end there:
/// `(vertex, sides, input edges)`. Such sides cannot all get paths that share
/// no input edge (each path leaves the centre by an interior input edge), so
/// the layout cannot be placed — e.g. a regular curve node (one interior
/// edge per side) where an arc along the curve collapsed and two sides meet.
pub(crate) fn deficits(
    mesh: &QuadMesh,
    conn: &Connectivity,
    layout: &BlockLayout,
    edge_curve: &[Option<u32>],
    edge_face: &[FaceId],
) -> Vec<(u32, usize, usize)> {
    let mut sides: BTreeMap<(u32, FaceId), usize> = BTreeMap::new();
    for (e, edge) in layout.edges.iter().enumerate() {
        if edge_curve[e].is_none() {
            for v in edge.ends {
                *sides.entry((v, edge_face[e])).or_insert(0) += 1;
            }
        }
    }
    let mut out = Vec::new();
    for ((v, f), k) in sides {
        let m = interior_edges(mesh, conn, layout.vertex_node[v as usize], f);
        if k > m && out.last().is_none_or(|&(w, _, _)| w != v) {
            out.push((v, k, m));
        }
    }
    out
}

/// The input edges at node `c` a block side inside face `f` may leave by:
/// not on a CAD curve, to a node of `f` or of its boundary.
fn interior_edges(mesh: &QuadMesh, conn: &Connectivity, c: u32, f: FaceId) -> usize {
    conn.neighbours(mesh, c)
        .0
        .into_iter()
        .filter(|&n| {
            conn.edge_curve(c, n).is_none()
                && match mesh.node_class[n as usize] {
                    NodeClass::Face(g, _) => g == f,
                    _ => true,
                }
        })
        .count()
}

/// Moves the centre of each layout vertex with a deficit ([`deficits`]) to
/// another input node of its group that has enough interior edges into
/// every face its block sides enter: same kind (face node, or node of the
/// same CAD curve; corners never move), not another vertex's centre, the
/// nearest to the old centre (ties: lowest id). Ours: the paper's "any
/// node" of a merged group (§IV.B) fails when a valence-5 group sits on a
/// valence-4 node — five sides cannot leave by four edges.
pub(crate) fn recentre(
    mesh: &QuadMesh,
    conn: &Connectivity,
    layout: &mut BlockLayout,
    edge_curve: &[Option<u32>],
    edge_face: &[FaceId],
    group_anchors: impl Fn(u32) -> Vec<u32>,
) -> usize {
    let mut sides: BTreeMap<u32, BTreeMap<FaceId, usize>> = BTreeMap::new();
    for (e, edge) in layout.edges.iter().enumerate() {
        if edge_curve[e].is_none() {
            for v in edge.ends {
                *sides.entry(v).or_default().entry(edge_face[e]).or_insert(0) += 1;
            }
        }
    }
    let mut used: HashSet<u32> = layout.vertex_node.iter().copied().collect();
    let mut moved = 0;
    for (v, per_face) in sides {
        let c = layout.vertex_node[v as usize];
        let enough = |n: u32| per_face.iter().all(|(&f, &k)| interior_edges(mesh, conn, n, f) >= k);
        if enough(c) {
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
            .filter(|&n| !used.contains(&n) && kind(n) == Some(want) && enough(n))
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
