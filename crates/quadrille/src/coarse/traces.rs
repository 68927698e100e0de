//! Traces of the T-mesh (paper §III.A, spec §3.1–3.5): from every irregular
//! node and CAD corner along each incident edge, straight through regular
//! nodes, in lockstep (one edge per round, traces in id order), until the
//! trace has met an in-cone candidate on each side, reaches an irregular node
//! or corner, an open boundary, or an edge some trace already ran along in the
//! same direction. Closed CAD curves with no corner and no irregular node get
//! two traces along them from a seed node, so that every curve is covered.

use super::connectivity::{Connectivity, NodeKind};
use mesh::{NodeClass, QuadMesh};
use std::collections::{BTreeMap, HashSet};

/// Where a trace comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Source {
    /// An irregular node or a CAD corner: an alignment candidate, with
    /// validity and geometric-consistency constraints.
    Origin,
    /// A seed node on a closed CAD curve without corner or irregular node:
    /// covers the curve, never a candidate.
    Seed,
}

/// Why a trace ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum TraceEnd {
    /// At another irregular node or corner (its last node).
    ReachedOrigin,
    /// After an in-cone candidate on each side.
    Candidates,
    /// Could not go straight on (open boundary).
    Boundary,
    /// Its next edge was already run along in the same direction.
    Revisit,
}

/// One trace: input-mesh nodes from its origin, one edge per step.
#[derive(Clone, Debug)]
pub(crate) struct Trace {
    /// Origin or seed.
    pub source: Source,
    /// Along a CAD curve (cone half-angle 0).
    pub on_curve: bool,
    /// Its nodes: `nodes[k]` is `k` edges from the origin `nodes[0]`.
    pub nodes: Vec<u32>,
    /// Why it ended.
    pub end: TraceEnd,
}

/// Two traces through one node, not along each other: `lengths[k]` is the
/// node's position along `traces[k]`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Crossing {
    /// The two traces.
    pub traces: [u32; 2],
    /// The input-mesh node.
    pub node: u32,
    /// Integer lengths from each trace's origin to the node.
    pub lengths: [u32; 2],
}

/// All traces and their crossings.
#[derive(Debug, Default)]
pub(crate) struct Traces {
    /// The traces, in id order.
    pub traces: Vec<Trace>,
    /// Every crossing, found when the later trace reached the node.
    pub crossings: Vec<Crossing>,
}

/// True when node kind `k` is a trace origin.
pub(crate) fn is_origin(k: NodeKind) -> bool {
    !matches!(k, NodeKind::Regular)
}

/// Draws the traces with cone half-angle `alpha` (radians) off CAD curves.
///
/// Without `stop_on_candidates` traces run until an irregular node, corner,
/// boundary or revisit: the input mesh's own quad layout (#P_init).
pub(crate) fn draw_traces(
    mesh: &QuadMesh,
    conn: &Connectivity,
    alpha: f64,
    stop_on_candidates: bool,
) -> Traces {
    let tan_alpha = alpha.tan();
    let mut traces: Vec<Trace> = Vec::new();
    for v in 0..mesh.nodes.len() as u32 {
        if !is_origin(conn.kind[v as usize]) {
            continue;
        }
        for n in conn.neighbours(mesh, v).0 {
            traces.push(start(conn, v, n, Source::Origin));
        }
    }
    for (v, curve) in seeds(mesh, conn) {
        for n in conn.neighbours(mesh, v).0 {
            if conn.edge_curve(v, n) == Some(curve) {
                traces.push(start(conn, v, n, Source::Seed));
            }
        }
    }
    let mut visits: Vec<Vec<(u32, u32)>> = vec![Vec::new(); mesh.nodes.len()];
    let mut used: HashSet<(u32, u32)> = HashSet::new();
    let mut sides: Vec<[u32; 2]> = vec![[0, 0]; traces.len()];
    let mut crossings = Vec::new();
    let mut active: Vec<u32> = Vec::new();
    // first edges: a trace whose first edge was already run along ends at once
    for t in 0..traces.len() {
        let e = (traces[t].nodes[0], traces[t].nodes[1]);
        if used.insert(e) {
            active.push(t as u32);
        } else {
            traces[t].nodes.pop();
            traces[t].end = TraceEnd::Revisit;
        }
    }
    // the first step happened above; from here each round handles arrival
    // at the head, then the step to the next node
    let mut arriving = active;
    while !arriving.is_empty() {
        let mut next_round = Vec::with_capacity(arriving.len());
        for &t in &arriving {
            let ti = t as usize;
            let p = traces[ti].nodes.len() - 1;
            let w = traces[ti].nodes[p];
            let back = traces[ti].nodes[p - 1];
            if is_origin(conn.kind[w as usize]) {
                traces[ti].end = TraceEnd::ReachedOrigin;
                visits[w as usize].push((t, p as u32));
                continue;
            }
            let forward = conn.straight_on(mesh, back, w);
            let (ns, closed) = conn.neighbours(mesh, w);
            for &(tj, pj) in &visits[w as usize] {
                if tj == t {
                    continue;
                }
                let tr = &traces[tj as usize];
                let j_prev = (pj > 0).then(|| tr.nodes[pj as usize - 1]);
                let j_next = tr.nodes.get(pj as usize + 1).copied();
                let along = [j_prev, j_next]
                    .iter()
                    .flatten()
                    .any(|&x| x == back || Some(x) == forward);
                if along {
                    continue;
                }
                crossings.push(Crossing { traces: [t, tj], node: w, lengths: [p as u32, pj] });
                if traces[ti].source == Source::Seed || tr.source == Source::Seed {
                    continue;
                }
                let tan_i = if traces[ti].on_curve { 0.0 } else { tan_alpha };
                if pj as f64 > tan_i * p as f64 + 1e-9 {
                    continue;
                }
                // the side j arrived from: left is counter-clockwise after forward
                if let (Some(jp), Some(f), true) = (j_prev, forward, closed && ns.len() == 4) {
                    let a = ns.iter().position(|&x| x == f).unwrap_or(0);
                    if ns[(a + 1) % 4] == jp {
                        sides[ti][0] += 1;
                    } else if ns[(a + 3) % 4] == jp {
                        sides[ti][1] += 1;
                    }
                }
            }
            visits[w as usize].push((t, p as u32));
            if stop_on_candidates && sides[ti][0] >= 1 && sides[ti][1] >= 1 {
                traces[ti].end = TraceEnd::Candidates;
                continue;
            }
            let Some(f) = forward else {
                traces[ti].end = TraceEnd::Boundary;
                continue;
            };
            if !used.insert((w, f)) {
                traces[ti].end = TraceEnd::Revisit;
                continue;
            }
            traces[ti].nodes.push(f);
            next_round.push(t);
        }
        arriving = next_round;
    }
    Traces { traces, crossings }
}

/// A trace from `v` whose first edge goes to `n`.
fn start(conn: &Connectivity, v: u32, n: u32, source: Source) -> Trace {
    Trace {
        source,
        on_curve: conn.edge_curve(v, n).is_some(),
        nodes: vec![v, n],
        end: TraceEnd::Revisit,
    }
}

/// One seed node (the lowest) per CAD curve that has mesh edges but no corner
/// and no irregular node among its nodes.
fn seeds(mesh: &QuadMesh, conn: &Connectivity) -> Vec<(u32, u32)> {
    let mut lowest: BTreeMap<u32, (u32, bool)> = BTreeMap::new();
    for &([a, b], c) in &mesh.curve_edges {
        for v in [a, b] {
            let e = lowest.entry(c.0).or_insert((v, false));
            e.0 = e.0.min(v);
            let covered = is_origin(conn.kind[v as usize])
                || matches!(mesh.node_class[v as usize], NodeClass::Corner(_));
            e.1 |= covered;
        }
    }
    lowest.into_iter().filter(|(_, (_, covered))| !covered).map(|(c, (v, _))| (v, c)).collect()
}
