//! From a quantization to the coarse block layout (paper §IV.A–C, spec
//! §5.1–5.3). Splitting and merging are one union–find over *points*: T-mesh
//! nodes, the `q − 1` inner points of every arc, the `(Q1 + 1) × (Q2 + 1)`
//! points of every grid patch quantized to `Q1 × Q2`, and the input nodes of
//! frozen patches. A patch's boundary points are its arcs' points; an arc of
//! length 0 joins its two ends, and a patch of zero width joins its opposite
//! sides point by point — the "1 × 0 patches merged along their long sides".
//! Each unit cell left is a block; each group of points a layout vertex,
//! centred on a CAD corner, else a CAD-curve node, else its lowest node.
//! Edges follow the CAD curve they lie on, else the shortest input-mesh path
//! inside the block's face.

use super::block_layout::{Block, BlockLayout, LayoutEdge};
use super::centres::{deficits, recentre};
use super::connectivity::Connectivity;
use super::tmesh::{PatchShape, SideArc, TMesh};
use geometry::{vec3, CurveId, FaceId};
use mesh::{NodeClass, QuadMesh};
use std::cmp::Reverse;
use std::collections::{BTreeMap, BinaryHeap, HashMap, HashSet};

/// Why a quantization gave no usable layout, with the arcs to hold at their
/// input length in the next round.
#[derive(Clone, Debug, Default)]
pub(crate) struct LayoutFailure {
    /// What went wrong (first few, for the log).
    pub reasons: Vec<String>,
    /// Arcs near the failures (to hold at their input length when no
    /// collapsed arc is to blame).
    pub arcs: HashSet<u32>,
    /// Collapsed arcs (`q = 0`) inside the failing vertices' groups: kept at
    /// length ≥ 1 next round, which un-merges the group (ours: gentler than
    /// holding whole patches, whose input lengths spread along their chords).
    pub separate: HashSet<u32>,
    /// Failures by cause (for the log): `deficit at a regular curve node`
    /// (two interior block sides end at a curve node with one interior input
    /// edge into the face), `deficit elsewhere`, `path at a merged group`,
    /// `path elsewhere`, `merge` (corners, curves, repeated vertices, edges
    /// bounding three blocks, corner valence).
    pub causes: BTreeMap<&'static str, usize>,
}

impl LayoutFailure {
    /// Counts one failure of cause `c`.
    fn cause(&mut self, c: &'static str) {
        *self.causes.entry(c).or_insert(0) += 1;
    }
}

/// The anchor of a point that stands for no input node of its own.
const NO_ANCHOR: u32 = u32::MAX;

/// The points of the union–find and what they came from.
struct Points {
    parent: Vec<u32>,
    /// The input node each point stands for before merging ([`NO_ANCHOR`]
    /// for a grid patch's boundary points).
    anchor: Vec<u32>,
    /// The point of each T-mesh node (by input node).
    node_point: HashMap<u32, u32>,
    /// First inner point of each arc (`q ≥ 2`).
    arc_base: Vec<u32>,
}

impl Points {
    fn push(&mut self, anchor: u32) -> u32 {
        let id = self.parent.len() as u32;
        self.parent.push(id);
        self.anchor.push(anchor);
        id
    }

    fn find(&mut self, mut i: u32) -> u32 {
        while self.parent[i as usize] != i {
            let g = self.parent[self.parent[i as usize] as usize];
            self.parent[i as usize] = g;
            i = g;
        }
        i
    }

    fn union(&mut self, a: u32, b: u32) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            self.parent[ra.max(rb) as usize] = ra.min(rb);
        }
    }

    /// Point `k` of arc `a` (0 and `q` are its end nodes).
    fn arc_point(&self, tm: &TMesh, q: &[u32], a: u32, k: u32) -> u32 {
        let arc = &tm.arcs[a as usize];
        if k == 0 {
            self.node_point[&arc.nodes[0]]
        } else if k == q[a as usize] {
            self.node_point[arc.nodes.last().expect("arc nodes")]
        } else {
            self.arc_base[a as usize] + k - 1
        }
    }
}

/// Input position along a side of quantized position `t` (piecewise linear
/// per arc, rounded).
fn side_input_position(tm: &TMesh, q: &[u32], side: &[SideArc], t: u32) -> u32 {
    let (mut cq, mut cl) = (0u32, 0u32);
    for &(a, _) in side {
        let (qa, la) = (q[a as usize], tm.arcs[a as usize].len());
        if qa > 0 && t <= cq + qa {
            return cl + ((t - cq) as f64 * la as f64 / qa as f64).round() as u32;
        }
        cq += qa;
        cl += la;
    }
    cl
}

/// One cell before the layout is numbered: corner points, face, and for each
/// side the CAD curve it lies on.
struct Cell {
    points: [u32; 4],
    face: FaceId,
    side_curve: [Option<u32>; 4],
    patch: u32,
}

/// Builds the block layout of arc lengths `q` (per arc).
pub(crate) fn build_layout(
    mesh: &QuadMesh,
    conn: &Connectivity,
    tm: &TMesh,
    q: &[u32],
) -> Result<BlockLayout, LayoutFailure> {
    let mut pts =
        Points { parent: Vec::new(), anchor: Vec::new(), node_point: HashMap::new(), arc_base: Vec::new() };
    for v in 0..mesh.nodes.len() as u32 {
        if tm.is_node[v as usize] {
            let p = pts.push(v);
            pts.node_point.insert(v, p);
        }
    }
    for (a, arc) in tm.arcs.iter().enumerate() {
        let qa = q[a];
        pts.arc_base.push(pts.parent.len() as u32);
        for k in 1..qa.max(1) {
            let at = (k as f64 * arc.len() as f64 / qa as f64).round() as usize;
            pts.push(arc.nodes[at]);
        }
        if qa == 0 {
            let (s, e) = (pts.node_point[&arc.nodes[0]], pts.node_point[arc.nodes.last().unwrap()]);
            pts.union(s, e);
        }
    }
    let mut cells: Vec<Cell> = Vec::new();
    let mut frozen_point: HashMap<u32, u32> = HashMap::new();
    for (pi, patch) in tm.patches.iter().enumerate() {
        match &patch.shape {
            PatchShape::Grid { sides, dims, grid } => {
                let sq = |s: usize| sides[s].iter().map(|&(a, _)| q[a as usize]).sum::<u32>();
                let (q1, q2) = (sq(0), sq(1));
                let w = q1 as usize + 1;
                let base = pts.parent.len() as u32;
                // inner points anchor on the grid; boundary points take their
                // arc point's anchor through the union below
                for j in 0..=q2 {
                    let jj = side_input_position(tm, q, &sides[1], j);
                    for i in 0..=q1 {
                        let ii = side_input_position(tm, q, &sides[0], i);
                        let inner = i > 0 && j > 0 && i < q1 && j < q2;
                        pts.push(if inner {
                            grid[ii as usize + (dims[0] as usize + 1) * jj as usize]
                        } else {
                            NO_ANCHOR
                        });
                    }
                }
                let at = |i: u32, j: u32| base + i + w as u32 * j;
                let mut side_curve_at: [Vec<Option<u32>>; 4] = Default::default();
                for (s, side) in sides.iter().enumerate() {
                    let mut pos = 0;
                    for &(a, rev) in side {
                        let qa = q[a as usize];
                        for k in 0..=qa {
                            let t = pos + k;
                            let gp = match s {
                                0 => at(t, 0),
                                1 => at(q1, t),
                                2 => at(q1 - t, q2),
                                _ => at(0, q2 - t),
                            };
                            let ap = pts.arc_point(tm, q, a, if rev { qa - k } else { k });
                            pts.union(gp, ap);
                        }
                        for _ in 0..qa {
                            side_curve_at[s].push(tm.arcs[a as usize].curve);
                        }
                        pos += qa;
                    }
                }
                for j in 0..q2 {
                    for i in 0..q1 {
                        let side_curve = [
                            if j == 0 { side_curve_at[0][i as usize] } else { None },
                            if i + 1 == q1 { side_curve_at[1][j as usize] } else { None },
                            if j + 1 == q2 { side_curve_at[2][(q1 - 1 - i) as usize] } else { None },
                            if i == 0 { side_curve_at[3][(q2 - 1 - j) as usize] } else { None },
                        ];
                        cells.push(Cell {
                            points: [at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)],
                            face: patch.face,
                            side_curve,
                            patch: pi as u32,
                        });
                    }
                }
            }
            PatchShape::Frozen => {
                for &qi in &patch.quads {
                    let quad = mesh.quads[qi as usize];
                    let mut points = [0u32; 4];
                    for (k, &v) in quad.iter().enumerate() {
                        points[k] = match pts.node_point.get(&v) {
                            Some(&p) => p,
                            None => *frozen_point.entry(v).or_insert_with(|| pts.push(v)),
                        };
                    }
                    let side_curve =
                        std::array::from_fn(|k| conn.edge_curve(quad[k], quad[(k + 1) % 4]));
                    cells.push(Cell { points, face: patch.face, side_curve, patch: pi as u32 });
                }
            }
        }
    }
    // frozen patches' boundary nodes are their arcs' points (q = l there)
    for (a, arc) in tm.arcs.iter().enumerate() {
        if q[a] != arc.len() {
            continue;
        }
        for (k, v) in arc.nodes.iter().enumerate() {
            if let Some(&fp) = frozen_point.get(v) {
                let ap = pts.arc_point(tm, q, a as u32, k as u32);
                pts.union(fp, ap);
            }
        }
    }
    assemble(mesh, conn, tm, q, &mut pts, &cells)
}

/// Numbers the groups, checks the cells and edges, places the vertices and
/// finds the edge paths.
fn assemble(
    mesh: &QuadMesh,
    conn: &Connectivity,
    tm: &TMesh,
    q: &[u32],
    pts: &mut Points,
    cells: &[Cell],
) -> Result<BlockLayout, LayoutFailure> {
    let mut fail = LayoutFailure::default();
    // collapsed arcs by end node, to un-merge a failing group
    let mut zero_at: HashMap<u32, Vec<u32>> = HashMap::new();
    for (a, arc) in tm.arcs.iter().enumerate() {
        if q[a] == 0 {
            for v in [arc.nodes[0], *arc.nodes.last().expect("arc nodes")] {
                zero_at.entry(v).or_default().push(a as u32);
            }
        }
    }
    let separate = |anchors: &[u32], f: &mut LayoutFailure| {
        for v in anchors {
            f.separate.extend(zero_at.get(v).into_iter().flatten());
        }
    };
    let patch_arcs = |p: u32, f: &mut LayoutFailure| f.arcs.extend(&tm.patches[p as usize].boundary_arcs);
    // groups of the points cells use, in order of first use
    let mut vertex_of_root: BTreeMap<u32, u32> = BTreeMap::new();
    let mut roots_of_cells: Vec<[u32; 4]> = Vec::with_capacity(cells.len());
    for c in cells {
        let r = c.points.map(|p| pts.find(p));
        roots_of_cells.push(r);
    }
    // the groups a collapsed arc merged (for the failure causes)
    let mut merged_roots: HashSet<u32> = HashSet::new();
    for (a, arc) in tm.arcs.iter().enumerate() {
        if q[a] == 0 {
            merged_roots.insert(pts.find(pts.node_point[&arc.nodes[0]]));
        }
    }
    let mut members: HashMap<u32, Vec<u32>> = HashMap::new();
    for p in 0..pts.parent.len() as u32 {
        let r = pts.find(p);
        members.entry(r).or_default().push(p);
    }
    let mut layout = BlockLayout::default();
    let mut root_ids: Vec<u32> = roots_of_cells.iter().flatten().copied().collect();
    root_ids.sort_unstable();
    root_ids.dedup();
    for &r in &root_ids {
        let anchors: Vec<u32> = members[&r]
            .iter()
            .map(|&p| pts.anchor[p as usize])
            .filter(|&a| a != NO_ANCHOR)
            .collect();
        match centre(mesh, &anchors) {
            Ok(v) => {
                vertex_of_root.insert(r, layout.vertex_node.len() as u32);
                layout.vertex_node.push(v);
            }
            Err(why) => {
                fail.reasons.push(why);
                fail.cause("merge");
                for &a in &anchors {
                    arcs_at_node(tm, a, &mut fail.arcs);
                }
                separate(&anchors, &mut fail);
                vertex_of_root.insert(r, layout.vertex_node.len() as u32);
                layout.vertex_node.push(anchors.first().copied().unwrap_or(0));
            }
        }
    }
    let mut root_of_vertex: Vec<Option<u32>> = vec![None; layout.vertex_node.len()];
    for (&r, &v) in &vertex_of_root {
        root_of_vertex[v as usize] = Some(r);
    }
    let merged = |v: u32| root_of_vertex[v as usize].is_some_and(|r| merged_roots.contains(&r));
    let group_anchors = |v: u32| -> Vec<u32> {
        root_of_vertex[v as usize]
            .and_then(|r| members.get(&r))
            .into_iter()
            .flatten()
            .map(|&p| pts.anchor[p as usize])
            .filter(|&a| a != NO_ANCHOR)
            .collect()
    };
    // cells → blocks, sides → edges
    let mut edge_of: HashMap<(u32, u32), u32> = HashMap::new();
    let mut edge_uses: Vec<Vec<(u32, bool)>> = Vec::new();
    let mut edge_face: Vec<FaceId> = Vec::new();
    let mut edge_curve: Vec<Option<u32>> = Vec::new();
    for (ci, c) in cells.iter().enumerate() {
        let corners = roots_of_cells[ci].map(|r| vertex_of_root[&r]);
        let distinct: HashSet<u32> = corners.iter().copied().collect();
        if distinct.len() != 4 {
            // a 1 × 0 remnant: merged away when two corners coincide in pairs
            if distinct.len() <= 2 {
                continue;
            }
            fail.reasons.push(format!("a block with corners {corners:?} repeats a vertex"));
            fail.cause("merge");
            patch_arcs(c.patch, &mut fail);
            for v in corners {
                separate(&group_anchors(v), &mut fail);
            }
            continue;
        }
        let mut sides = [(0u32, false); 4];
        for k in 0..4 {
            let (a, b) = (corners[k], corners[(k + 1) % 4]);
            let key = (a.min(b), a.max(b));
            let id = *edge_of.entry(key).or_insert_with(|| {
                layout.edges.push(LayoutEdge { ends: [key.0, key.1], path: Vec::new(), curve: None });
                edge_uses.push(Vec::new());
                edge_face.push(c.face);
                edge_curve.push(None);
                layout.edges.len() as u32 - 1
            });
            edge_uses[id as usize].push((ci as u32, a > b));
            if c.side_curve[k].is_some() {
                edge_curve[id as usize] = c.side_curve[k];
            }
            sides[k] = (id, a > b);
        }
        layout.blocks.push(Block { corners, sides, face: c.face });
    }
    for (e, uses) in edge_uses.iter().enumerate() {
        let bad = uses.len() > 2 || (uses.len() == 2 && uses[0].1 == uses[1].1);
        if bad {
            fail.reasons.push(format!("layout edge {e} bounds {} blocks", uses.len()));
            fail.cause("merge");
            for &(ci, _) in uses {
                patch_arcs(cells[ci as usize].patch, &mut fail);
            }
            for v in layout.edges[e].ends {
                separate(&group_anchors(v), &mut fail);
            }
        }
    }
    for v in corner_valences(mesh, &layout) {
        fail.reasons.push(format!("the CAD corner at node {} loses its valence", layout.vertex_node[v as usize]));
        fail.cause("merge");
        let anchors = group_anchors(v);
        for &a in &anchors {
            arcs_at_node(tm, a, &mut fail.arcs);
        }
        separate(&anchors, &mut fail);
    }
    if !fail.reasons.is_empty() {
        return Err(fail);
    }
    let moved = recentre(mesh, conn, &mut layout, &edge_curve, &edge_face, &group_anchors);
    let short = deficits(mesh, conn, &layout, &edge_curve, &edge_face);
    if moved > 0 || !short.is_empty() {
        tracing::debug!("coarse: {moved} layout vertices re-centred, {} still short of input edges", short.len());
    }
    let failed = edge_paths(mesh, conn, &mut layout, &edge_curve, &edge_face, &mut fail);
    // hold the arcs of the patches the failed edges' blocks came from, and
    // the arcs through the nodes their ends merged
    for e in failed {
        let ends = layout.edges[e].ends;
        match short.iter().find(|s| ends.contains(&s.0)) {
            Some(&(v, k, m)) => {
                let node = layout.vertex_node[v as usize];
                tracing::debug!("coarse: edge {e}: its vertex at node {node} has {k} interior block sides, {m} interior input edges");
                let on_curve = matches!(mesh.node_class[node as usize], NodeClass::Curve(..));
                fail.cause(if on_curve && m == 1 { "deficit at a regular curve node" } else { "deficit elsewhere" });
            }
            None => {
                fail.cause(if ends.iter().any(|&v| merged(v)) { "path at a merged group" } else { "path elsewhere" });
            }
        }
        for &(ci, _) in &edge_uses[e] {
            patch_arcs(cells[ci as usize].patch, &mut fail);
        }
        for v in layout.edges[e].ends {
            let anchors = group_anchors(v);
            for &a in &anchors {
                arcs_at_node(tm, a, &mut fail.arcs);
            }
            separate(&anchors, &mut fail);
        }
    }
    if fail.reasons.is_empty() {
        Ok(layout)
    } else {
        Err(fail)
    }
}

/// The input-mesh path of every layout edge (§IV.C): along its CAD curve,
/// else the shortest path inside its face, never through another layout
/// vertex. Paths that share a node are then rerouted one by one, the longest
/// first, around the nodes of all other paths (ours, the issue's "crossing
/// paths rerouted": on a mesh, paths that cross share a node).
///
/// Returns the edges with no path (their reasons pushed to `fail`).
fn edge_paths(
    mesh: &QuadMesh,
    conn: &Connectivity,
    layout: &mut BlockLayout,
    edge_curve: &[Option<u32>],
    edge_face: &[FaceId],
    fail: &mut LayoutFailure,
) -> Vec<usize> {
    let vertex_nodes: HashSet<u32> = layout.vertex_node.iter().copied().collect();
    let ends: Vec<[u32; 2]> =
        layout.edges.iter().map(|e| e.ends.map(|v| layout.vertex_node[v as usize])).collect();
    let route = |e: usize, blocked: &dyn Fn(u32) -> bool| -> Option<Vec<u32>> {
        let [a, b] = ends[e];
        let free = |v: u32| v == b || (!blocked(v) && !vertex_nodes.contains(&v));
        let along = |c: u32| shortest_path(mesh, conn, a, b, |u, v| conn.edge_curve(u, v) == Some(c) && free(v));
        match edge_curve[e] {
            Some(c) => along(c),
            None => {
                let f = edge_face[e];
                let inner = |v: u32| matches!(mesh.node_class[v as usize], NodeClass::Face(g, _) if g == f);
                shortest_path(mesh, conn, a, b, |u, v| {
                    conn.edge_curve(u, v).is_none() && free(v) && (inner(v) || v == b)
                })
                .or_else(|| common_curve(mesh, conn, a, b).and_then(along))
            }
        }
    };
    let route_edges = |e: usize, taken: &HashSet<(u32, u32)>| -> Option<Vec<u32>> {
        let [a, b] = ends[e];
        let ok = |u: u32, v: u32| {
            !taken.contains(&(u.min(v), u.max(v))) && (v == b || !vertex_nodes.contains(&v))
        };
        match edge_curve[e] {
            Some(c) => shortest_path(mesh, conn, a, b, |u, v| conn.edge_curve(u, v) == Some(c) && ok(u, v)),
            None => {
                let f = edge_face[e];
                let inner = |v: u32| matches!(mesh.node_class[v as usize], NodeClass::Face(g, _) if g == f);
                shortest_path(mesh, conn, a, b, |u, v| {
                    conn.edge_curve(u, v).is_none() && ok(u, v) && (inner(v) || v == b)
                })
            }
        }
    };
    let mut paths: Vec<Option<Vec<u32>>> = (0..ends.len()).map(|e| route(e, &|_| false)).collect();
    let mut uses: HashMap<u32, u32> = HashMap::new();
    let inner_nodes = |p: &Vec<u32>| p[1..p.len() - 1].to_vec();
    for p in paths.iter().flatten() {
        for v in inner_nodes(p) {
            *uses.entry(v).or_insert(0) += 1;
        }
    }
    let length = |p: &Vec<u32>| p.windows(2).map(|w| vec3::dist(mesh.nodes[w[0] as usize], mesh.nodes[w[1] as usize])).sum::<f64>();
    let mut clashing: Vec<(f64, usize)> = paths
        .iter()
        .enumerate()
        .filter_map(|(e, p)| {
            let p = p.as_ref()?;
            inner_nodes(p).iter().any(|v| uses[v] > 1).then(|| (length(p), e))
        })
        .collect();
    clashing.sort_by(|x, y| y.0.total_cmp(&x.0).then(x.1.cmp(&y.1)));
    for (_, e) in clashing {
        let old = paths[e].take().expect("a clashing path");
        if !inner_nodes(&old).iter().any(|v| uses[v] > 1) {
            paths[e] = Some(old);
            continue;
        }
        for v in inner_nodes(&old) {
            *uses.get_mut(&v).expect("counted") -= 1;
        }
        let new = route(e, &|v| uses.get(&v).is_some_and(|&n| n > 0)).or_else(|| {
            // no node-disjoint way: share nodes, never an edge (the fine
            // mesh's check refuses shared edges)
            let taken: HashSet<(u32, u32)> = paths
                .iter()
                .flatten()
                .flat_map(|p| p.windows(2).map(|w| (w[0].min(w[1]), w[0].max(w[1]))))
                .collect();
            route_edges(e, &taken)
        });
        if let Some(p) = &new {
            for v in inner_nodes(p) {
                *uses.entry(v).or_insert(0) += 1;
            }
        }
        paths[e] = new;
    }
    let mut failed = Vec::new();
    for (e, path) in paths.into_iter().enumerate() {
        let [a, b] = ends[e];
        let edge = &mut layout.edges[e];
        match path {
            Some(p) => {
                // the curve the path runs along (a side that collapsed onto
                // a curve runs along it too)
                let on: Vec<Option<u32>> = p.windows(2).map(|w| conn.edge_curve(w[0], w[1])).collect();
                edge.curve = match on.first() {
                    Some(&Some(c)) if on.iter().all(|&x| x == Some(c)) => Some(CurveId(c)),
                    _ => edge_curve[e].map(CurveId),
                };
                edge.path = p;
            }
            None => {
                if tracing::enabled!(tracing::Level::DEBUG) {
                    let open = |u: u32, v: u32| match edge_curve[e] {
                        Some(c) => conn.edge_curve(u, v) == Some(c),
                        None => conn.edge_curve(u, v).is_none(),
                    };
                    let walls = shortest_path(mesh, conn, a, b, |u, v| open(u, v) && (v == b || !vertex_nodes.contains(&v)))
                        .map(|p| p.len() - 1);
                    let any = shortest_path(mesh, conn, a, b, open).map(|p| p.len() - 1);
                    let hops = shortest_path(mesh, conn, a, b, |_, _| true).map(|p| p.len() - 1);
                    tracing::debug!(
                        "coarse: edge {e} has no path: {:?} to {:?}, face {:?}, curve {:?}; avoiding only vertices {:?} edges, ignoring them {:?}, any edge {:?}",
                        mesh.node_class[a as usize], mesh.node_class[b as usize], edge_face[e], edge_curve[e], walls, any, hops
                    );
                }
                fail.reasons.push(format!("no free input path for layout edge {e} ({a} to {b})"));
                failed.push(e);
            }
        }
    }
    failed
}

/// A CAD curve both nodes lie on (a corner counts for every curve of its
/// mesh edges; here: the curve of a curve node, when the other is on it too
/// or a corner).
fn common_curve(mesh: &QuadMesh, conn: &Connectivity, a: u32, b: u32) -> Option<u32> {
    if let Some(c) = conn.edge_curve(a, b) {
        return Some(c);
    }
    let curve = |v: u32| match mesh.node_class[v as usize] {
        NodeClass::Curve(c, _) => Some(c.0),
        _ => None,
    };
    match (curve(a), curve(b)) {
        (Some(x), Some(y)) if x == y => Some(x),
        (Some(x), None) | (None, Some(x)) => Some(x),
        _ => None,
    }
}

/// The layout vertices of CAD corners that lost their input valence (their
/// number of quads).
fn corner_valences(mesh: &QuadMesh, layout: &BlockLayout) -> Vec<u32> {
    let mut quads_at = vec![0u32; mesh.nodes.len()];
    for quad in &mesh.quads {
        for &v in quad {
            quads_at[v as usize] += 1;
        }
    }
    let mut blocks_at = vec![0u32; layout.vertex_node.len()];
    for b in &layout.blocks {
        for &c in &b.corners {
            blocks_at[c as usize] += 1;
        }
    }
    (0..layout.vertex_node.len() as u32)
        .filter(|&v| {
            let node = layout.vertex_node[v as usize] as usize;
            matches!(mesh.node_class[node], NodeClass::Corner(_)) && blocks_at[v as usize] != quads_at[node]
        })
        .collect()
}

/// The arcs with an end at input node `v`, or through it.
fn arcs_at_node(tm: &TMesh, v: u32, out: &mut HashSet<u32>) {
    for (a, arc) in tm.arcs.iter().enumerate() {
        if arc.nodes.contains(&v) {
            out.insert(a as u32);
        }
    }
}

/// The centre of a group from its members' input nodes: the CAD corner, else
/// among the nodes on the (single) CAD curve, else among all, the one nearest
/// their centroid (the paper takes "any"; the middle keeps the layout's edges
/// apart; ties by the lowest node).
fn centre(mesh: &QuadMesh, anchors: &[u32]) -> Result<u32, String> {
    let mut corners: Vec<u32> = anchors
        .iter()
        .copied()
        .filter(|&v| matches!(mesh.node_class[v as usize], NodeClass::Corner(_)))
        .collect();
    corners.sort_unstable();
    corners.dedup();
    if corners.len() > 1 {
        return Err(format!("CAD corners at nodes {corners:?} merge into one vertex"));
    }
    if let Some(&c) = corners.first() {
        return Ok(c);
    }
    let mut on_curve: Vec<(u32, u32)> = anchors
        .iter()
        .filter_map(|&v| match mesh.node_class[v as usize] {
            NodeClass::Curve(c, _) => Some((c.0, v)),
            _ => None,
        })
        .collect();
    on_curve.sort_unstable();
    if let (Some(first), Some(last)) = (on_curve.first(), on_curve.last()) {
        if first.0 != last.0 {
            return Err(format!("nodes of CAD curves {} and {} merge into one vertex", first.0, last.0));
        }
        let nodes: Vec<u32> = on_curve.iter().map(|&(_, v)| v).collect();
        return Ok(nearest_centroid(mesh, &nodes).unwrap_or(first.1));
    }
    nearest_centroid(mesh, anchors).ok_or_else(|| "an empty group".to_string())
}

/// The node of `nodes` nearest their centroid (ties: the lowest).
fn nearest_centroid(mesh: &QuadMesh, nodes: &[u32]) -> Option<u32> {
    let n = nodes.len() as f64;
    let c = nodes.iter().fold([0.0; 3], |s, &v| vec3::add(s, vec3::scale(mesh.nodes[v as usize], 1.0 / n)));
    nodes.iter().copied().min_by(|&x, &y| {
        let d = |v: u32| vec3::dist(mesh.nodes[v as usize], c);
        d(x).total_cmp(&d(y)).then(x.cmp(&y))
    })
}

/// Shortest input-mesh path from `a` to `b` (Euclidean edge lengths) over the
/// edges `allowed` accepts, or `None`.
fn shortest_path(
    mesh: &QuadMesh,
    conn: &Connectivity,
    a: u32,
    b: u32,
    allowed: impl Fn(u32, u32) -> bool,
) -> Option<Vec<u32>> {
    if a == b {
        return None;
    }
    let mut dist: HashMap<u32, (f64, u32)> = HashMap::new();
    let mut heap = BinaryHeap::new();
    dist.insert(a, (0.0, a));
    heap.push(Reverse((Ordered(0.0), a)));
    while let Some(Reverse((Ordered(d), u))) = heap.pop() {
        if u == b {
            let mut path = vec![b];
            let mut x = b;
            while x != a {
                x = dist[&x].1;
                path.push(x);
            }
            path.reverse();
            return Some(path);
        }
        if d > dist[&u].0 {
            continue;
        }
        for n in conn.neighbours(mesh, u).0 {
            if !allowed(u, n) {
                continue;
            }
            let nd = d + vec3::dist(mesh.nodes[u as usize], mesh.nodes[n as usize]);
            if dist.get(&n).is_none_or(|&(old, _)| nd < old) {
                dist.insert(n, (nd, u));
                heap.push(Reverse((Ordered(nd), n)));
            }
        }
    }
    None
}

/// An `f64` with a total order, for the heap.
#[derive(Clone, Copy, PartialEq)]
struct Ordered(f64);

impl Eq for Ordered {}

impl PartialOrd for Ordered {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Ordered {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&other.0)
    }
}
