//! The input quad mesh as the coarse method sees it (paper §II, spec §2):
//! half-edges with twins, the cyclic star of every node, which nodes are
//! irregular (trace origins), which are CAD corners, and how a trace goes
//! straight through a regular node.

use crate::core::error::MeshError;
use mesh::{NodeClass, QuadMesh};
use std::collections::HashMap;

/// No half-edge (an open boundary).
pub(crate) const NONE: u32 = u32::MAX;

/// What a node is to the trace construction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum NodeKind {
    /// Regular: a trace passes straight through.
    Regular,
    /// Irregular, with its number of quads: face-interior valence ≠ 4, or a
    /// curve node with other than two quads per side of the curve.
    Irregular { valence: u32, face_interior: bool },
    /// A CAD corner (a trace origin and a node, preserved).
    Corner,
}

/// Half-edge connectivity of an all-quad, edge-manifold mesh.
///
/// Half-edge `h = 4 q + k` runs from `quads[q][k]` to `quads[q][(k + 1) % 4]`.
pub(crate) struct Connectivity {
    /// The twin of each half-edge, or [`NONE`] on an open boundary.
    pub twin: Vec<u32>,
    /// One outgoing half-edge per node ([`NONE`] for a node of no quad); for a
    /// boundary node the one without a twin, where its counter-clockwise star
    /// starts.
    pub out: Vec<u32>,
    /// The kind of each node.
    pub kind: Vec<NodeKind>,
    /// Whether each undirected edge (by its lower half-edge index) lies on a
    /// CAD curve, with the curve index.
    pub curve_of_edge: HashMap<(u32, u32), u32>,
    /// The half-edge of each directed edge `(from, to)`.
    pub by_ends: HashMap<(u32, u32), u32>,
}

impl Connectivity {
    /// Builds the connectivity; an edge with three or more quads, two quads
    /// using it in the same direction, or triangles are errors naming the
    /// place.
    pub fn new(mesh: &QuadMesh) -> Result<Connectivity, MeshError> {
        if !mesh.triangles.is_empty() {
            return Err(MeshError::Coarse(format!(
                "the coarse method needs an all-quad mesh; this one has {} triangles",
                mesh.triangles.len()
            )));
        }
        let nh = mesh.quads.len() * 4;
        let mut by_ends: HashMap<(u32, u32), u32> = HashMap::with_capacity(nh);
        for (q, quad) in mesh.quads.iter().enumerate() {
            for k in 0..4 {
                let (a, b) = (quad[k], quad[(k + 1) % 4]);
                if a as usize >= mesh.nodes.len() || b as usize >= mesh.nodes.len() || a == b {
                    return Err(MeshError::Coarse(format!("quad {q} has a bad node index")));
                }
                if by_ends.insert((a, b), (4 * q + k) as u32).is_some() {
                    return Err(MeshError::Coarse(format!(
                        "the edge of nodes {a}–{b} is used twice in the same direction \
                         (a non-manifold or inconsistently oriented mesh; the coarse method \
                         needs each CAD curve on at most two faces)"
                    )));
                }
            }
        }
        let mut twin = vec![NONE; nh];
        let mut out = vec![NONE; mesh.nodes.len()];
        for (&(a, b), &h) in &by_ends {
            if let Some(&t) = by_ends.get(&(b, a)) {
                twin[h as usize] = t;
            }
            out[a as usize] = out[a as usize].min(h);
        }
        let mut conn = Connectivity {
            twin,
            out,
            kind: Vec::new(),
            curve_of_edge: HashMap::new(),
            by_ends: HashMap::new(),
        };
        // boundary nodes start their star at the half-edge with no twin on the
        // clockwise side: rotate clockwise until stopped
        for v in 0..mesh.nodes.len() {
            let h0 = conn.out[v];
            if h0 == NONE {
                continue;
            }
            let mut h = h0;
            let mut steps = 0;
            loop {
                let back = conn.rotate_cw(h);
                if back == NONE || back == h0 {
                    break;
                }
                h = back;
                steps += 1;
                if steps > nh {
                    break;
                }
            }
            conn.out[v] = if conn.rotate_cw(h) == NONE { h } else { h0 };
        }
        for &([a, b], c) in &mesh.curve_edges {
            conn.curve_of_edge.insert((a.min(b), a.max(b)), c.0);
        }
        conn.kind = node_kinds(mesh, &conn);
        conn.by_ends = by_ends;
        Ok(conn)
    }

    /// The end node of half-edge `h`.
    pub fn head(mesh: &QuadMesh, h: u32) -> u32 {
        let (q, k) = (h as usize / 4, h as usize % 4);
        mesh.quads[q][(k + 1) % 4]
    }

    /// The start node of half-edge `h`.
    pub fn tail(mesh: &QuadMesh, h: u32) -> u32 {
        mesh.quads[h as usize / 4][h as usize % 4]
    }

    /// The next outgoing half-edge counter-clockwise around the tail of `h`
    /// (through the quad of `h`), or [`NONE`] at an open boundary.
    pub fn rotate_ccw(&self, h: u32) -> u32 {
        let prev = (h & !3) | ((h + 3) & 3);
        self.twin[prev as usize]
    }

    /// The next outgoing half-edge clockwise around the tail of `h`, or
    /// [`NONE`] at an open boundary.
    pub fn rotate_cw(&self, h: u32) -> u32 {
        let t = self.twin[h as usize];
        if t == NONE {
            return NONE;
        }
        (t & !3) | ((t + 1) & 3)
    }

    /// The outgoing half-edges of node `v`, counter-clockwise, and whether the
    /// star is closed (an interior node). For a boundary node the last one has
    /// no quad on its left and is added as the twin-less reverse edge: it is
    /// reported as [`NONE`] then (its head is `last_head`).
    pub fn star(&self, v: u32) -> (Vec<u32>, bool) {
        let h0 = self.out[v as usize];
        let mut hs = Vec::new();
        if h0 == NONE {
            return (hs, false);
        }
        let mut h = h0;
        loop {
            hs.push(h);
            let next = self.rotate_ccw(h);
            if next == NONE {
                return (hs, false);
            }
            if next == h0 || hs.len() > 64 {
                return (hs, true);
            }
            h = next;
        }
    }

    /// The neighbours of node `v`, counter-clockwise, and whether the star is
    /// closed. An open star lists the node across its last quad's previous
    /// edge too, so that the first and last neighbours are along the boundary.
    pub fn neighbours(&self, mesh: &QuadMesh, v: u32) -> (Vec<u32>, bool) {
        let (hs, closed) = self.star(v);
        let mut ns: Vec<u32> = hs.iter().map(|&h| Self::head(mesh, h)).collect();
        if !closed {
            if let Some(&last) = hs.last() {
                let prev = (last & !3) | ((last + 3) & 3);
                ns.push(Self::tail(mesh, prev));
            }
        }
        (ns, closed)
    }

    /// The node a trace reaches from `v` going straight on, having arrived
    /// from `from`: the opposite neighbour of a closed star of four, the
    /// other boundary neighbour of an open star of three. `None` where a trace
    /// cannot go straight on (an irregular node, a transversal arrival at an
    /// open boundary).
    pub fn straight_on(&self, mesh: &QuadMesh, from: u32, v: u32) -> Option<u32> {
        let (ns, closed) = self.neighbours(mesh, v);
        let i = ns.iter().position(|&n| n == from)?;
        if closed && ns.len() == 4 {
            Some(ns[(i + 2) % 4])
        } else if !closed && ns.len() == 3 {
            match i {
                0 => Some(ns[2]),
                2 => Some(ns[0]),
                _ => None,
            }
        } else {
            None
        }
    }

    /// The CAD curve of edge `a`–`b`, if it lies on one.
    pub fn edge_curve(&self, a: u32, b: u32) -> Option<u32> {
        self.curve_of_edge.get(&(a.min(b), a.max(b))).copied()
    }
}

/// The kind of every node: corners; face-interior nodes with valence ≠ 4 and
/// curve nodes with other than two quads per side are irregular.
fn node_kinds(mesh: &QuadMesh, conn: &Connectivity) -> Vec<NodeKind> {
    let mut at: Vec<Vec<u32>> = vec![Vec::new(); mesh.nodes.len()];
    for (q, quad) in mesh.quads.iter().enumerate() {
        for &v in quad {
            at[v as usize].push(q as u32);
        }
    }
    let mut uses: HashMap<(u32, u32), u32> = HashMap::with_capacity(2 * mesh.quads.len());
    for (h, &t) in conn.twin.iter().enumerate() {
        let (a, b) = (Connectivity::tail(mesh, h as u32), Connectivity::head(mesh, h as u32));
        let key = (a.min(b), a.max(b));
        *uses.entry(key).or_insert(0) += if t == NONE { 1 } else { 0 };
        uses.entry(key).or_insert(0);
    }
    // `uses` as `curve_node_is_irregular` reads it: 1 on an open edge
    for u in uses.values_mut() {
        *u = if *u == 1 { 1 } else { 2 };
    }
    (0..mesh.nodes.len())
        .map(|v| {
            let valence = at[v].len() as u32;
            match mesh.node_class[v] {
                NodeClass::Corner(_) => NodeKind::Corner,
                NodeClass::Curve(..) => {
                    if mesh::stats::curve_node_is_irregular(mesh, v as u32, &at[v], &uses) {
                        NodeKind::Irregular { valence, face_interior: false }
                    } else {
                        NodeKind::Regular
                    }
                }
                _ => {
                    let closed = conn.star(v as u32).1;
                    if valence == 4 && closed {
                        NodeKind::Regular
                    } else if valence == 0 {
                        NodeKind::Regular
                    } else {
                        NodeKind::Irregular { valence, face_interior: closed }
                    }
                }
            }
        })
        .collect()
}
