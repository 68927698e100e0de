//! The curve-network method (paper curve-network-quadrangulation): every
//! cycle of a [`CurveNetwork`] segmented and paired (`curvenet::pair_cycle`,
//! §3.1), laid out and sampled (`curvenet::sample`, §3.2), and the cycles'
//! quads assembled into one [`QuadMesh`], welded where their boundary
//! samples coincide.
//!
//! A chord graph in several pieces is cut (Fig. 10, `curvenet::cut`) and each
//! part paired again, recursively; cuts and hole connectors are sampled
//! alike on both sides (the larger count wins, and the cycle is redone). A
//! cycle whose layout still fails gets the midpoint layout (Fig. 5 top),
//! named in the report.
//!
//! Then the network stage (spec §7, `methods::curvenet_network`): the
//! T-junctions on curves two cycles share are merged or split
//! (`curvenet::tjunction`), one interval count per poly-chord is chosen for
//! the whole network (`curvenet::intervals`), secondary vertices are snapped
//! onto the shared sampling and the changed parts laid out and sampled again,
//! so every shared curve is sampled once and the weld closes the mesh.

use std::collections::BTreeMap;
use std::time::Instant;

use geometry::vec3::Vec3;
use mesh::QuadMesh;

use crate::core::work_queue::map_in_order;
use super::curvenet_assemble::{assemble, Welder};
use super::curvenet_facing::Facing;
use super::curvenet_facing::unfolded;
use crate::curvenet::cut::find_cut;
use crate::curvenet::polyline::edges_along;
pub use crate::curvenet::midpoint::midpoint_pairing;
use crate::curvenet::ring::{pair_ring, split_annulus};
use crate::curvenet::sample::quadrangulate_with_minimums;
use crate::curvenet::{
    pair_cycle, CurveNetError, CurveNetwork, CycleLoops, CycleQuads, LayoutError,
    PairedCycle, PairingOptions,
};

/// Options of [`mesh_curve_network`].
#[derive(Clone, Debug)]
pub struct CurvesOptions {
    /// Target edge length; `None`: [`CurvesOptions::size_factor`] × 1/24 of
    /// the network's diagonal (the default size of the CAD methods).
    pub size: Option<f64>,
    /// Multiplies the default size when `size` is `None`.
    pub size_factor: f64,
    /// Segmentation and matching parameters (§3.1; drop, dom, …).
    pub pairing: PairingOptions,
    /// Mesh the valid cycles and list the others instead of failing.
    pub skip_bad: bool,
    /// Run the network stage (spec §7, `methods::curvenet_network`); off:
    /// each cycle keeps its own sampling (for comparisons).
    pub network: bool,
    /// Worker threads (cycles are meshed in parallel); `None`: all cores.
    /// The output is the same for any count.
    pub threads: Option<usize>,
}

impl Default for CurvesOptions {
    fn default() -> Self {
        CurvesOptions {
            size: None,
            size_factor: 1.0,
            pairing: PairingOptions::default(),
            skip_bad: false,
            network: true,
            threads: None,
        }
    }
}

/// What happened to one cycle (summed over its parts when it was cut).
#[derive(Clone, Debug, Default)]
pub struct CycleSummary {
    /// The cycle's index in the network.
    pub cycle: usize,
    /// Parts the cycle was meshed in: 1, or more after cuts (Fig. 10).
    pub parts: usize,
    /// Segments of the final pairings.
    pub segments: usize,
    /// The pairs `(i, j)` of each part (segment indices of the part) and
    /// their costs.
    pub pairs: Vec<((usize, usize), f64)>,
    /// Refinement steps of the pairings (rolled-back ones included).
    pub iterations: usize,
    /// Loops segmented by the curvature-and-arc-length fallback.
    pub fallbacks: usize,
    /// Odd parties met.
    pub odd_parties: usize,
    /// Hole connectors added.
    pub connectors: usize,
    /// Coarse layout quads.
    pub patches: usize,
    /// Valences of the interior layout vertices.
    pub interior_valences: Vec<usize>,
    /// Dense quads of this cycle.
    pub quads: usize,
    /// The coarse layout: each patch's four corners (for pictures and
    /// `--layout`).
    pub layout_quads: Vec<[Vec3; 4]>,
    /// True when a part's paired layout failed and the midpoint layout was used.
    pub midpoint_layout: bool,
    /// Lines worth showing the user (fallbacks, odd parties, cuts, the midpoint layout).
    pub notes: Vec<String>,
    /// Wall time of this cycle, seconds.
    pub seconds: f64,
}

/// The report of [`mesh_curve_network`].
#[derive(Clone, Debug, Default)]
pub struct CurvesReport {
    /// The target edge length used.
    pub h: f64,
    /// One per meshed cycle, in cycle order.
    pub cycles: Vec<CycleSummary>,
    /// Cycles left out under `skip_bad`, with the reason.
    pub skipped: Vec<(usize, String)>,
    /// Boundary nodes merged with another part's or cycle's.
    pub welded_nodes: usize,
    /// What the network stage did.
    pub network: super::curvenet_network::NetworkReport,
    /// The output mesh's open edges, sorted by where they lie
    /// (`methods::curvenet_seams`).
    pub open_edges: super::curvenet_seams::OpenEdges,
}

/// Why a network could not be meshed.
#[derive(Debug, thiserror::Error)]
pub enum CurvesError {
    /// The network or one of its cycles is invalid.
    #[error(transparent)]
    Network(#[from] CurveNetError),
    /// A cycle could not be meshed by the paired layout nor the midpoint layout.
    #[error("{file}cycle {cycle}: {message}")]
    Cycle {
        /// `"FILE: "` or empty.
        file: String,
        /// The cycle's index.
        cycle: usize,
        /// Why.
        message: String,
    },
    /// `skip_bad` left no cycle to mesh.
    #[error("{file}no cycle could be meshed ({skipped} skipped)")]
    NothingMeshed {
        /// `"FILE: "` or empty.
        file: String,
        /// Cycles skipped.
        skipped: usize,
    },
    /// The size is not a positive number.
    #[error("edge length {0} must be a positive finite length")]
    BadSize(f64),
    /// The worker threads could not be started.
    #[error("could not start the worker threads: {0}")]
    Threads(String),
}

/// The target edge length: `opts.size`, or the factor × 1/24 of the diagonal.
pub fn curves_size(net: &CurveNetwork, opts: &CurvesOptions) -> Result<f64, CurvesError> {
    let h = opts
        .size
        .unwrap_or(opts.size_factor * net.diagonal() / crate::core::options::DEFAULT_DIVISIONS);
    if h.is_finite() && h > 0.0 {
        Ok(h)
    } else {
        Err(CurvesError::BadSize(h))
    }
}

/// Meshes every cycle of `net` with quads (see the module docs).
pub fn mesh_curve_network(
    net: &CurveNetwork,
    opts: &CurvesOptions,
) -> Result<(QuadMesh, CurvesReport), CurvesError> {
    let h = curves_size(net, opts)?;
    let file = net.file().map(|f| format!("{f}: ")).unwrap_or_default();
    let mut report = CurvesReport { h, ..Default::default() };
    let mut meshed: Vec<(usize, Vec<Leaf>)> = Vec::new();
    let weld = Welder::new(net.weld_tolerance().max(1e-12 * net.diagonal()));
    let cycles: Vec<usize> = (0..net.cycles().len()).collect();
    let mesh_one = |&cycle: &usize| {
        let t0 = Instant::now();
        net.cycle_loops(cycle)
            .map_err(CurvesError::from)
            .and_then(|loops| {
                mesh_cycle(&loops, h, &opts.pairing, &weld, true).map_err(|message| CurvesError::Cycle {
                    file: file.clone(),
                    cycle,
                    message,
                })
            })
            .map(|(pieces, mut summary)| {
                summary.cycle = cycle;
                summary.seconds = t0.elapsed().as_secs_f64();
                (pieces, summary)
            })
    };
    let outcomes = match opts.threads {
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n.max(1))
            .build()
            .map_err(|e| CurvesError::Threads(e.to_string()))?
            .install(|| map_in_order(&cycles, mesh_one)),
        None => map_in_order(&cycles, mesh_one),
    };
    for (cycle, outcome) in cycles.into_iter().zip(outcomes) {
        match outcome {
            Ok((pieces, summary)) => {
                report.cycles.push(summary);
                meshed.push((cycle, pieces));
            }
            Err(e) if opts.skip_bad => report.skipped.push((cycle, e.to_string())),
            Err(e) => return Err(e),
        }
    }
    if meshed.is_empty() {
        return Err(CurvesError::NothingMeshed { file, skipped: report.skipped.len() });
    }
    if opts.network {
        let before = meshed.iter().any(|(_, ls)| ls.iter().any(|l| l.ring)).then(|| meshed.clone());
        report.network =
            super::curvenet_network::network_stage(net, &mut meshed, h, weld.tolerance, opts.threads);
        if let Some(before) = before {
            super::curvenet_network::rings_to_splits(net, before, &mut meshed, &mut report, &weld, opts);
        }
    }
    for (summary, (_, leaves)) in report.cycles.iter_mut().zip(&meshed) {
        summarise_leaves(summary, leaves);
    }
    let meshed: Vec<(usize, Vec<CycleQuads>)> = meshed
        .into_iter()
        .map(|(c, leaves)| (c, leaves.into_iter().map(|l| l.quads).collect()))
        .collect();
    let (mesh, welded) = assemble(net, &meshed, &weld);
    report.welded_nodes = welded;
    let cycles: Vec<usize> = meshed.iter().map(|(c, _)| *c).collect();
    report.open_edges = super::curvenet_seams::classify_open_edges(net, &mesh, &cycles, weld.tolerance.max(1e-9 * net.diagonal()));
    Ok((mesh, report))
}

/// The error of a part with several holes that no split meshes.
const NO_SPLIT: &str = "no split by two connectors could be meshed";

/// Cuts nested deeper than this are not tried: the part gets the midpoint layout.
const MAX_CUT_DEPTH: usize = 8;

/// Rounds of re-meshing a cycle so that cuts and connectors get one count
/// on both sides (each round can only raise counts).
const MAX_COUNT_ROUNDS: usize = 6;

/// One leaf of a cycle's meshing: a part's pairing, its quads, which
/// way they face, and whether it is a ring layout (`curvenet::ring`).
#[derive(Clone, Debug)]
pub(super) struct Leaf {
    pub(super) paired: PairedCycle,
    pub(super) quads: CycleQuads,
    pub(super) facing: Facing,
    pub(super) ring: bool,
}

/// A cycle's summary figures of its (final) leaves: segments, pairs,
/// patches, layout quads, interior valences and quads.
fn summarise_leaves(summary: &mut CycleSummary, leaves: &[Leaf]) {
    summary.segments = leaves.iter().map(|l| l.paired.starts.len()).sum();
    summary.pairs = leaves
        .iter()
        .flat_map(|l| l.paired.pairs.iter().copied().zip(l.paired.costs.iter().copied()))
        .collect();
    summary.patches = leaves.iter().map(|l| l.quads.patches).sum();
    summary.layout_quads = leaves
        .iter()
        .flat_map(|l| {
            let corners = &l.quads.layout.positions;
            l.quads.layout.quads.iter().map(move |lq| lq.corners.map(|v| corners[v]))
        })
        .collect();
    summary.interior_valences = leaves
        .iter()
        .flat_map(|l| l.quads.interior_vertex_valences.iter().copied())
        .collect();
    summary.quads = leaves.iter().map(|l| l.quads.quads.len()).sum();
}

/// The quads of one cycle (one piece per part) and its summary; `rings`:
/// an annulus whose matched pairing folds may get the ring layout.
pub(super) fn mesh_cycle(
    loops: &CycleLoops,
    h: f64,
    opts: &PairingOptions,
    weld: &Welder,
    rings: bool,
) -> Result<(Vec<Leaf>, CycleSummary), String> {
    let mut least: BTreeMap<[[i64; 3]; 2], usize> = BTreeMap::new();
    for _ in 0..MAX_COUNT_ROUNDS {
        let mut leaves = Vec::new();
        let mut summary = CycleSummary::default();
        // Untangling by count is the last resort: a cycle whose layouts all
        // fold (untangled only up to the share) is meshed again with it, so
        // that a few thin inverted quads of a small layout do not pre-empt
        // the cut, ring or split routes.
        let env = PartEnv { h, least: &least, weld, rings, untangle_by_count: false };
        if mesh_part(loops, &env, opts, false, 0, &mut leaves, &mut summary).is_err() {
            (leaves, summary) = (Vec::new(), CycleSummary::default());
            let env = PartEnv { untangle_by_count: true, ..env };
            mesh_part(loops, &env, opts, false, 0, &mut leaves, &mut summary)?;
        }
        let mut counts: BTreeMap<[[i64; 3]; 2], Vec<usize>> = BTreeMap::new();
        for leaf in &leaves {
            for (key, n) in unsplittable_counts(leaf, weld) {
                counts.entry(key).or_default().push(n);
            }
        }
        let mut changed = false;
        for (key, ns) in counts {
            let most = ns.iter().copied().max().unwrap_or(0);
            if ns.iter().any(|&n| n != most) && least.get(&key).is_none_or(|&m| m < most) {
                least.insert(key, most);
                changed = true;
            }
        }
        if !changed {
            summary.parts = leaves.len();
            summary.quads = leaves.iter().map(|l| l.quads.quads.len()).sum();
            return Ok((leaves, summary));
        }
    }
    Err(format!(
        "cuts and connectors still sampled differently on their two sides after {MAX_COUNT_ROUNDS} rounds"
    ))
}

/// Pairs and meshes one part (the whole cycle at depth 0), cutting it
/// where its chord graph falls apart (Fig. 10), else the midpoint layout
/// where the layout fails. `closing`: the part's closing edge is a cut;
/// `rings`: an annulus may get the ring layout. A part with two or more
/// holes is only split by two connectors: its matched pairing, of many
/// segments, is slow and gave no valid layout on any corpus face (the
/// refinement spent minutes on such cycles before refusing them).
/// What stays fixed while one cycle is cut into parts and meshed: the
/// quad size `h`, the network's interval minimums per unsplittable segment
/// (`least`), the weld, and whether annuli may take the ring layout.
#[derive(Clone, Copy)]
struct PartEnv<'a> {
    h: f64,
    least: &'a BTreeMap<[[i64; 3]; 2], usize>,
    weld: &'a Welder,
    rings: bool,
    /// Whether a layout with up to [`UNTANGLE_MAX_QUADS`] inverted quads is
    /// untangled before it is refused, besides one with up to
    /// [`UNTANGLE_MAX_SHARE`] of its quads inverted ([`unfolded`]).
    untangle_by_count: bool,
}

#[allow(clippy::too_many_arguments)]
fn mesh_part(
    loops: &CycleLoops,
    env: &PartEnv<'_>,
    opts: &PairingOptions,
    closing: bool,
    depth: usize,
    leaves: &mut Vec<Leaf>,
    summary: &mut CycleSummary,
) -> Result<(), String> {
    let PartEnv { h, least, weld, rings, untangle_by_count } = *env;
    let popts = PairingOptions { closing_edge_unsplittable: closing, ..opts.clone() };
    let facing = Facing::of(loops);
    // a pairing's quads with the network's interval minimums, refused when folded
    let lay_out = |paired: &PairedCycle| {
        let minimums: Vec<usize> = (0..paired.starts.len())
            .map(|s| least.get(&segment_key(paired, s, weld)).copied().unwrap_or(0))
            .collect();
        quadrangulate_with_minimums(paired, h, &minimums).and_then(|q| unfolded(q, &facing, untangle_by_count))
    };
    // Hole splits are not counted against `MAX_CUT_DEPTH`: each leaves
    // fewer holes in both halves, so they end.
    if loops.holes.len() >= 2 {
        if split_holes(loops, env, opts, depth, leaves, summary) {
            return Ok(());
        }
        let why = summary
            .notes
            .last()
            .and_then(|n| n.strip_prefix("holes: the two-connector split failed ("))
            .and_then(|n| n.strip_suffix(')'));
        // A half that failed the same way passes its own line up: one
        // short line naming the hole count where the splitting stopped.
        if let Some(inner) = why.filter(|w| w.contains(NO_SPLIT)) {
            return Err(inner.to_string());
        }
        return Err(format!(
            "{NO_SPLIT} with {} holes left ({}); the matched pairing of several holes is not tried",
            loops.holes.len(),
            why.unwrap_or("no connectors clear of the loops")
        ));
    }
    let mut matched = pair_cycle(loops, &popts).map_err(|e| e.to_string());
    let mut matched_laid = matched.as_ref().ok().map(|(paired, _)| lay_out(paired));
    // On a CAD face whose pairing by the surface's bridge directions gives
    // no valid layout, the pairing by the curves alone (best-fit planes),
    // still judged and placed on the surface.
    if loops.surface.is_some() && !matches!(matched_laid, Some(Ok(_))) {
        let alone = CycleLoops { surface: None, ..loops.clone() };
        if let Ok((paired, report)) = pair_cycle(&alone, &popts) {
            let laid = lay_out(&paired);
            if laid.is_ok() {
                summary.notes.push("no valid layout from the CAD face's bridge directions: paired by the curves alone".to_string());
                matched = Ok((paired, report));
                matched_laid = Some(laid);
            }
        }
    }
    let matched_ok = matches!(matched_laid, Some(Ok(_)));
    // A cycle with holes whose matched pairing fails or folds: an annulus
    // gets the ring layout (`curvenet::ring`), else the holes are split off
    // by two connectors at a time; the matched pairing's cut or midpoint
    // layout only when both fail.
    let mut ring = None;
    if !loops.holes.is_empty() && !matched_ok {
        if rings {
            ring = pair_ring(loops, &popts).and_then(|r| r.ok()).and_then(|(paired, report)| {
                match lay_out(&paired) {
                    Ok(q) => Some((paired, report, q)),
                    Err(e) => {
                        summary.notes.push(format!("annulus: the ring layout failed ({e})"));
                        None
                    }
                }
            });
        }
        if ring.is_none()
            && split_holes(loops, env, opts, depth, leaves, summary)
        {
            return Ok(());
        }
    }
    let is_ring = ring.is_some();
    let (paired, report, laid) = match ring {
        Some((paired, report, q)) => {
            summary.notes.push(format!(
                "annulus: ring layout, one connector, {} sectors",
                paired.starts.len() / 2 - 1
            ));
            (paired, report, Ok(q))
        }
        None => {
            let (paired, report) = matched?;
            let Some(laid) = matched_laid else {
                return Err("curvenet: the matched pairing has no layout".to_string());
            };
            (paired, report, laid)
        }
    };
    let (paired, quads) = match laid {
        Ok(q) => (paired, q),
        Err(LayoutError::Disconnected { components, .. }) if depth < MAX_CUT_DEPTH => {
            let cut = find_cut(&paired)
                .map_err(|e| e.to_string())?
                .ok_or_else(|| format!("the chord graph has {components} components but no cut separates them"))?;
            summary.notes.push(format!(
                "the chord graph has {components} components: cut between segment starts {} and {} (Fig. 10)",
                cut.from, cut.to
            ));
            for part in &cut.parts {
                let mut kept = edges_along(&part.loops.outer.points, &opts.unsplittable_edges);
                // A part cut again keeps the earlier cut (its closing edge,
                // the last segment) when it falls in a sub-part: split
                // there, it would be sampled apart from its other side.
                let last = paired.starts.len() - 1;
                if closing && paired.unsplittable[last] && part.segments.contains(&last) {
                    kept.push([paired.points[paired.starts[last]], paired.points[paired.starts[0]]]);
                }
                let o = PairingOptions { unsplittable_edges: kept, ..opts.clone() };
                let part_loops = CycleLoops { surface: loops.surface.clone(), ..part.loops.clone() };
                mesh_part(&part_loops, env, &o, true, depth + 1, leaves, summary)?;
            }
            return Ok(());
        }
        Err(first) => {
            let mid = midpoint_pairing(&paired);
            let minimums: Vec<usize> = (0..mid.starts.len())
                .map(|s| least.get(&segment_key(&mid, s, weld)).copied().unwrap_or(0))
                .collect();
            let q = quadrangulate_with_minimums(&mid, h, &minimums)
                .and_then(|q| unfolded(q, &facing, untangle_by_count))
                .map_err(|e| format!("{first}; the midpoint layout failed too: {e}"))?;
            summary.midpoint_layout = true;
            summary.notes.push(format!("layout failed ({first}): midpoint layout used (Fig. 5 top)"));
            (mid, q)
        }
    };
    summary.notes.extend(report.notes());
    summary.segments += paired.starts.len();
    summary.pairs.extend(paired.pairs.iter().copied().zip(paired.costs.iter().copied()));
    summary.iterations += report.iterations;
    summary.fallbacks += report.fallbacks.len();
    summary.odd_parties += report.odd_parties.len();
    summary.connectors += report.connectors;
    summary.patches += quads.patches;
    let corners = &quads.layout.positions;
    summary
        .layout_quads
        .extend(quads.layout.quads.iter().map(|lq| lq.corners.map(|v| corners[v])));
    summary.interior_valences.extend(quads.interior_vertex_valences.iter().copied());
    leaves.push(Leaf { paired, quads, facing, ring: is_ring });
    Ok(())
}

/// The part's holes split off by two connectors (`curvenet::split_annulus`)
/// and both halves meshed: true when done (leaves and summary extended),
/// false with a note when no split is found or a half fails.
fn split_holes(
    loops: &CycleLoops,
    env: &PartEnv<'_>,
    opts: &PairingOptions,
    depth: usize,
    leaves: &mut Vec<Leaf>,
    summary: &mut CycleSummary,
) -> bool {
    let popts = PairingOptions { closing_edge_unsplittable: false, ..opts.clone() };
    let Some(halves) = split_annulus(loops, &opts.unsplittable_edges, &popts) else {
        return false;
    };
    let mut part_leaves = Vec::new();
    let mut part_summary = CycleSummary::default();
    let split = halves.iter().try_for_each(|half| {
        let o = PairingOptions { unsplittable_edges: half.connectors.clone(), ..opts.clone() };
        mesh_part(&half.loops, env, &o, false, depth, &mut part_leaves, &mut part_summary)
    });
    match split {
        Ok(()) => {
            summary.notes.push(format!(
                "holes: split in two by two connectors ({} and {} holes left)",
                halves[0].loops.holes.len(),
                halves[1].loops.holes.len()
            ));
            absorb(summary, part_summary);
            summary.connectors += 2;
            leaves.extend(part_leaves);
            true
        }
        Err(e) => {
            summary.notes.push(format!("holes: the two-connector split failed ({e})"));
            false
        }
    }
}

/// Adds a part's summary figures (of the halves of a split annulus) to
/// the cycle's.
fn absorb(summary: &mut CycleSummary, part: CycleSummary) {
    summary.segments += part.segments;
    summary.pairs.extend(part.pairs);
    summary.iterations += part.iterations;
    summary.fallbacks += part.fallbacks;
    summary.odd_parties += part.odd_parties;
    summary.connectors += part.connectors;
    summary.patches += part.patches;
    summary.interior_valences.extend(part.interior_valences);
    summary.layout_quads.extend(part.layout_quads);
    summary.midpoint_layout |= part.midpoint_layout;
    summary.notes.extend(part.notes);
}

/// Segment `s`'s end points, snapped and sorted: the same key for a cut or
/// connector seen from either side.
pub(super) fn segment_key(paired: &PairedCycle, s: usize, weld: &Welder) -> [[i64; 3]; 2] {
    let k = paired.starts.len();
    let a = weld.cell(paired.points[paired.starts[s]]);
    let b = weld.cell(paired.points[paired.starts[(s + 1) % k]]);
    if a <= b {
        [a, b]
    } else {
        [b, a]
    }
}

/// The interval count of every unsplittable segment (cuts, connectors) of
/// a leaf, by its key.
fn unsplittable_counts(leaf: &Leaf, weld: &Welder) -> Vec<([[i64; 3]; 2], usize)> {
    let chords = &leaf.quads.layout.chords;
    (0..leaf.paired.starts.len())
        .filter(|&s| leaf.paired.unsplittable[s])
        .filter_map(|s| {
            let c = chords.iter().position(|&(i, j)| i == s || j == s)?;
            Some((segment_key(&leaf.paired, s, weld), leaf.quads.intervals[c]))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use geometry::vec3;
    use crate::curvenet::fixtures;
    use crate::curvenet::parse_json;
    use mesh::stats::edge_uses;

    /// Total length of the mesh's open edges (on one quad), after checking
    /// that no edge is on more than two.
    fn open_length(mesh: &QuadMesh) -> f64 {
        let uses = edge_uses(mesh);
        assert!(uses.values().all(|&n| n <= 2));
        uses.iter()
            .filter(|(_, &n)| n == 1)
            .map(|(&(a, b), _)| vec3::dist(mesh.nodes[a as usize], mesh.nodes[b as usize]))
            .sum()
    }

    /// The OBJ example of docs/curve-networks.md: two unit squares sharing
    /// the side x = 1 become one welded mesh, open only on the outer
    /// boundary, every quad valid.
    #[test]
    fn two_squares_sharing_a_side_weld_into_one_mesh() {
        let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\nl 1 2 3 4 1\nl 2 5 6 3 2\n";
        let net = crate::curvenet::parse_obj(text, None).unwrap();
        let opts = CurvesOptions { size: Some(0.125), ..Default::default() };
        let (mesh, report) = mesh_curve_network(&net, &opts).unwrap();
        assert_eq!(report.cycles.len(), 2);
        assert!(report.cycles.iter().all(|c| c.patches == 1 && c.quads == 64));
        assert_eq!(mesh.quads.len(), 128);
        let uses = edge_uses(&mesh);
        let open: Vec<_> = uses.iter().filter(|(_, &n)| n == 1).collect();
        assert_eq!(open.len(), 6 * 8, "open edges only on the 6-unit outer boundary");
        assert!(uses.values().all(|&n| n <= 2));
        assert_eq!(mesh.curve_edges.len(), 7 * 8);
        assert_eq!(mesh.corner_nodes.len(), 6);
        let sicn = mesh::stats::quad_acceptance_sicn_values(&mesh, None);
        assert!(sicn.iter().all(|&s| s > 0.9), "{sicn:?}");
    }

    /// Meshes one cycle with a hole and checks it as an annulus: every
    /// quad valid by element geometry and facing +z, no edge used thrice,
    /// open edges only on the two loops (their lengths sum to
    /// `loops_length`), no node strictly inside the hole. Returns the
    /// summary.
    fn check_annulus(loops: &CycleLoops, in_hole: impl Fn(&Vec3) -> bool, loops_length: f64) -> CycleSummary {
        let weld = Welder::new(1e-9);
        let (leaves, summary) = mesh_cycle(loops, 0.1, &PairingOptions::default(), &weld, true).unwrap();
        let pieces: Vec<CycleQuads> = leaves.into_iter().map(|l| l.quads).collect();
        let net = json_of(loops);
        let (mesh, _) = assemble(&net, &[(0, pieces)], &weld);
        let open_length = open_length(&mesh);
        // The mesh's boundary edges are chords of the loops' polylines: a
        // little shorter on curved loops; a connector left open would add
        // twice its length.
        assert!(
            open_length <= loops_length + 1e-9 && open_length > (1.0 - 3e-3) * loops_length,
            "open length {open_length} ≠ {loops_length}"
        );
        assert!(!mesh.nodes.iter().any(in_hole), "a node inside the hole");
        for q in &mesh.quads {
            let p = q.map(|v| mesh.nodes[v as usize]);
            assert!(mesh::quality::quad_sicn(&p, &[[0.0, 0.0, 1.0]; 4]) > 0.0, "{p:?}");
        }
        let bad = mesh::stats::quad_acceptance_sicn_values(&mesh, None).iter().filter(|&&s| s <= 0.0).count();
        assert_eq!(bad, 0);
        summary
    }

    /// The perimeter of a regular n-gon of circumradius r.
    fn ngon(n: usize, r: f64) -> f64 {
        2.0 * n as f64 * r * (std::f64::consts::PI / n as f64).sin()
    }

    /// Fig. 17: the letter P. Its outer loop is not convex, so the ring
    /// folds (the stem's sector); it is split into two disks by two
    /// connectors and meshed: no node inside the hole, open edges only on
    /// the two loops, every quad valid.
    #[test]
    fn the_letter_p_is_meshed_around_its_hole_without_a_node_inside() {
        let [lo, hi] = fixtures::P_HOLE;
        let inside = |p: &Vec3| p[0] > lo[0] + 1e-9 && p[0] < hi[0] - 1e-9 && p[1] > lo[1] + 1e-9 && p[1] < hi[1] - 1e-9;
        let summary = check_annulus(&fixtures::letter_p(), inside, 13.0 + 5.0);
        assert_eq!(summary.connectors, 2, "{:?}", summary.notes);
        assert!(summary.notes.iter().any(|n| n.contains("two connectors")), "{:?}", summary.notes);
    }

    /// Annuli with smooth loops get the ring layout (one connector, four
    /// or more sectors): a circle in a circle, an off-centre hole, a square
    /// with a round hole.
    #[test]
    fn annuli_get_the_ring_layout_all_quads_valid_and_no_node_in_the_hole() {
        let cases = [
            (fixtures::annulus([0.0, 0.0], 0.4), [0.0, 0.0], 0.4, ngon(64, 1.0) + ngon(48, 0.4)),
            (fixtures::annulus([0.3, 0.1], 0.3), [0.3, 0.1], 0.3, ngon(64, 1.0) + ngon(48, 0.3)),
            (fixtures::square_with_round_hole([0.0, 0.0], 0.4), [0.0, 0.0], 0.4, 8.0 + ngon(48, 0.4)),
            (fixtures::square_with_round_hole([0.4, -0.3], 0.35), [0.4, -0.3], 0.35, 8.0 + ngon(48, 0.35)),
        ];
        for (loops, c, r, length) in cases {
            // Strictly inside the hole's inscribed circle.
            let apothem = r * (std::f64::consts::PI / 48.0).cos();
            let inside = |p: &Vec3| (p[0] - c[0]).hypot(p[1] - c[1]) < apothem - 1e-9;
            let summary = check_annulus(&loops, inside, length);
            assert_eq!(summary.connectors, 1);
            assert_eq!(summary.interior_valences, Vec::<usize>::new(), "a ring has no interior vertex");
            assert!(summary.patches >= 4, "{}", summary.patches);
            assert!(summary.notes.iter().any(|n| n.contains("ring layout")), "{:?}", summary.notes);
        }
    }

    /// Two round holes in a 4 × 2 rectangle: split by two connectors (the
    /// first note), then the half that keeps a hole is meshed around it (at
    /// least one more connector); the mesh is open only on the three loops,
    /// every quad valid, no node in a hole.
    #[test]
    fn a_rectangle_with_two_holes_is_split_and_meshed_around_both() {
        let holes = [([-1.0, 0.0], 0.3), ([1.0, 0.0], 0.3)];
        let loops = fixtures::rectangle_with_round_holes(2.0, &holes);
        let apothem = 0.3 * (std::f64::consts::PI / 48.0).cos();
        let in_hole = |p: &Vec3| holes.iter().any(|(c, _)| (p[0] - c[0]).hypot(p[1] - c[1]) < apothem - 1e-9);
        let summary = check_annulus(&loops, in_hole, 12.0 + 2.0 * ngon(48, 0.3));
        assert!(summary.notes[0].starts_with("holes: split in two by two connectors (1 and 0"), "{:?}", summary.notes);
        assert!(summary.connectors >= 3, "{:?}", summary.notes);
        assert!(summary.parts >= 2, "{}", summary.parts);
    }

    /// Two holes close together in the 2 × 2 square (0.3 apart, 0.25 from
    /// the sides): no half of any split meshes, and the cycle is refused
    /// with one short line naming where the splitting stopped (no nested
    /// repeats), with no matched pairing tried.
    #[test]
    fn two_holes_that_no_split_meshes_are_refused_with_one_short_line() {
        let loops = fixtures::square_with_round_holes(&[([-0.45, 0.0], 0.3), ([0.45, 0.0], 0.3)]);
        let weld = Welder::new(1e-9);
        let Err(message) = mesh_cycle(&loops, 0.1, &PairingOptions::default(), &weld, true) else {
            panic!("the two close holes were meshed");
        };
        assert!(message.starts_with("no split by two connectors could be meshed with 2 holes left ("), "{message}");
        assert_eq!(message.matches(NO_SPLIT).count(), 1, "{message}");
        assert!(!message.contains('\n'));
    }

    /// Without rings (`mesh_cycle(.., rings = false)`, the network stage's
    /// retry) an annulus is split by two connectors instead: no leaf is a
    /// ring, two connectors, the same checks as the ring's.
    #[test]
    fn an_annulus_without_rings_is_split_by_two_connectors() {
        let loops = fixtures::annulus([0.0, 0.0], 0.4);
        let weld = Welder::new(1e-9);
        let (with, _) = mesh_cycle(&loops, 0.1, &PairingOptions::default(), &weld, true).unwrap();
        assert!(with.iter().all(|l| l.ring) && with.len() == 1);
        let (leaves, summary) = mesh_cycle(&loops, 0.1, &PairingOptions::default(), &weld, false).unwrap();
        assert!(leaves.iter().all(|l| !l.ring) && leaves.len() >= 2, "{:?}", summary.notes);
        assert_eq!(summary.connectors, 2, "{:?}", summary.notes);
        let pieces: Vec<CycleQuads> = leaves.into_iter().map(|l| l.quads).collect();
        let (mesh, _) = assemble(&json_of(&loops), &[(0, pieces)], &weld);
        let open = open_length(&mesh);
        let loops_length = ngon(64, 1.0) + ngon(48, 0.4);
        assert!(open <= loops_length + 1e-9 && open > (1.0 - 3e-3) * loops_length, "{open} vs {loops_length}");
        for q in &mesh.quads {
            let p = q.map(|v| mesh.nodes[v as usize]);
            assert!(mesh::quality::quad_sicn(&p, &[[0.0, 0.0, 1.0]; 4]) > 0.0, "{p:?}");
        }
    }

    /// A cycle with a hole whose layout does not fold: a square plate with
    /// a square hole is meshed as one welded annulus, open only on the two
    /// loops, no node inside the hole, every quad valid.
    #[test]
    fn a_square_plate_with_a_square_hole_is_one_welded_annulus() {
        let square = |lo: f64, hi: f64| vec![[lo, lo, 0.0], [hi, lo, 0.0], [hi, hi, 0.0], [lo, hi, 0.0]];
        let mut hole = square(1.0, 2.0);
        hole.reverse();
        let loops = CycleLoops {
            outer: crate::curvenet::LoopPolyline { points: square(0.0, 3.0), fixed: vec![] },
            holes: vec![crate::curvenet::LoopPolyline { points: hole, fixed: vec![] }],
            surface: None,
        };
        let inside = |p: &Vec3| p[0] > 1.0 + 1e-9 && p[0] < 2.0 - 1e-9 && p[1] > 1.0 + 1e-9 && p[1] < 2.0 - 1e-9;
        let summary = check_annulus(&loops, inside, 16.0);
        assert_eq!(summary.connectors, 1);
    }

    /// Fig. 5 top: the house's midpoint layout is 5 patches around a
    /// valence-5 vertex.
    #[test]
    fn the_midpoint_layout_of_the_house_is_five_patches_around_a_valence_5_vertex() {
        let house = fixtures::house();
        let points = house.outer.points.clone();
        let paired = PairedCycle {
            starts: (0..5).collect(),
            pairs: vec![(0, 2), (1, 3)],
            costs: vec![0.0; 2],
            unsplittable: vec![false; 5],
            diameter: 2.5,
            points,
        };
        let mid = midpoint_pairing(&paired);
        assert_eq!(mid.starts.len(), 10);
        let q = crate::curvenet::quadrangulate(&mid, 0.1).unwrap();
        assert_eq!((q.patches, q.interior_vertex_valences.clone()), (5, vec![5]));
    }

    /// Bad sizes are refused before any work.
    #[test]
    fn a_size_that_is_not_positive_is_an_error() {
        let net = json_of(&fixtures::house());
        for size in [0.0, -1.0, f64::NAN] {
            let opts = CurvesOptions { size: Some(size), ..Default::default() };
            assert!(matches!(mesh_curve_network(&net, &opts), Err(CurvesError::BadSize(_))));
        }
    }

    /// A network of one curve per loop of `loops` and one cycle.
    fn json_of(loops: &CycleLoops) -> CurveNetwork {
        let curve = |pts: &[Vec3]| {
            let mut p: Vec<Vec3> = pts.to_vec();
            p.push(pts[0]);
            format!("{{\"points\": {}}}", serde_json::to_string(&p).unwrap())
        };
        let mut curves = vec![curve(&loops.outer.points)];
        curves.extend(loops.holes.iter().map(|h| curve(&h.points)));
        let uses: Vec<String> = (0..curves.len()).map(|i| format!("[[{i}, 1]]")).collect();
        let text = format!(
            "{{\"curves\": [{}], \"cycles\": [{{\"loops\": [{}]}}]}}",
            curves.join(","),
            uses.join(",")
        );
        parse_json(&text, None).unwrap()
    }
}
