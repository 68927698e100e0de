//! The network stage of the curve-network method (spec §7): after every
//! cycle is paired and meshed on its own (`methods::curvenet`), the parts
//! are made to agree on the curves they share.
//!
//! 1. T-junctions merged within 5δ or split, chord by chord
//!    (`curvenet::tjunction::resolve_t_junctions`);
//! 2. one interval count per poly-chord of every part by the integer program
//!    of `curvenet::intervals`: at least ⌈length / h⌉ per segment, equal sums
//!    on both sides of every shared primary segment, equal counts on both
//!    sides of a cut or hole connector;
//! 3. secondary vertices snapped onto the primary segment's sampling
//!    (`curvenet::tjunction::snap_secondary_vertices`);
//! 4. every part laid out (when its pairing changed) and sampled again with
//!    those counts. A part whose new layout fails or folds keeps its own
//!    meshing (named in the report); its shared curves may then stay open.

use std::collections::BTreeMap;
use std::time::Instant;

use crate::core::work_queue::map_in_order;
use crate::curvenet::geometry::{segment_points, Polyline};
use geometry::vec3::Vec3;

use crate::curvenet::intervals::{solve_intervals, IntervalProgram, IntervalSolution};
use crate::curvenet::layout::embed;
use crate::curvenet::sample::sample_layout_with_intervals;
use crate::curvenet::tjunction::{
    demote_common_vertex, resolve_t_junctions, shared_curves, snap_secondary_vertices, NetLeaf,
    SharedCurve, TJunctionReport,
};
use crate::curvenet::{CurveNetwork, PairedCycle};

use super::curvenet::{mesh_cycle, segment_key, CurvesOptions, CurvesReport, CycleSummary, Leaf};
use super::curvenet_assemble::Welder;
use super::curvenet_facing::unfolded;

/// What the network stage did.
#[derive(Clone, Debug, Default)]
pub struct NetworkReport {
    /// The T-junction resolution's counts.
    pub t_junctions: TJunctionReport,
    /// Interval variables (poly-chords of all parts).
    pub chords: usize,
    /// Shared primary segments (soft equalities of the program).
    pub primary_segments: usize,
    /// `Σ |mismatch|` of the interval solution (0: watertight).
    pub mismatch: usize,
    /// `Σ n` of the interval solution: the program's second term.
    pub intervals: usize,
    /// Seconds in the interval solver.
    pub interval_seconds: f64,
    /// Common vertices made secondary on both sides because a primary
    /// segment they end stayed unbalanced (`join_unbalanced`).
    pub joined: usize,
    /// Secondary vertices snapped onto the shared sampling.
    pub snapped: usize,
    /// Parts laid out again after their pairing changed.
    pub relaid: usize,
    /// Lines worth showing (a solver failure, a part that kept its meshing).
    pub notes: Vec<String>,
    /// Wall time of the whole stage, seconds.
    pub seconds: f64,
}

/// Rounds of [`join_unbalanced`] (each solves the program again).
const MAX_JOIN_ROUNDS: usize = 4;

/// The interval program can be unbalanceable by counts alone: a band of thin
/// faces round a plate's thickness carries the chords of its two big faces,
/// which are paired independently, and a poly-chord loop round the band can
/// close with a shift (the soft equalities read `x + y = x`). The common
/// vertices ending each primary segment left unbalanced by `solved` are made
/// secondary on both sides (`tjunction::demote_common_vertex`): the segments
/// either side join, the shift is absorbed inside the joined segment, and the
/// snapping places both sides' vertices on its one sampling. Returns the
/// (curve, position) of the vertices demoted and every part's primary flags
/// before (to undo when the joined program does not lower the mismatch).
/// The network stage keeps the joins only when they reach mismatch 0 (a
/// partial balance moves vertices without closing any curve).
fn join_unbalanced(
    prog: &IntervalProgram,
    places: &[(usize, f64, f64)],
    curves: &[SharedCurve],
    solved: &IntervalSolution,
    leaves: &mut [NetLeaf],
    tol: f64,
    fixed: &dyn Fn(Vec3) -> bool,
) -> (Vec<(usize, f64)>, Vec<Vec<bool>>) {
    let kept: Vec<Vec<bool>> = leaves.iter().map(|l| l.primary.clone()).collect();
    let sum = |v: &[usize]| v.iter().map(|&x| solved.counts[x]).sum::<usize>();
    let mut tried: Vec<(usize, f64)> = Vec::new();
    for ((left, right), &(ci, a, b)) in prog.equal_sums.iter().zip(places) {
        if sum(left) == sum(right) {
            continue;
        }
        let sc = &curves[ci];
        for u in [a, b] {
            let known = tried
                .iter()
                .any(|&(c, w)| c == sc.curve && (u - w).abs() <= tol);
            if !known && demote_common_vertex(sc, u, leaves, tol, fixed) {
                tried.push((sc.curve, u));
            }
        }
    }
    (tried, kept)
}

/// Runs the network stage on the meshed cycles' parts, in place (module
/// docs). `tolerance`: the weld tolerance; `threads`: as the method's.
pub(super) fn network_stage(
    net: &CurveNetwork,
    meshed: &mut [(usize, Vec<Leaf>)],
    h: f64,
    tolerance: f64,
    threads: Option<usize>,
) -> NetworkReport {
    let started = Instant::now();
    let mut report = NetworkReport::default();
    let tol = tolerance.max(1e-9 * net.diagonal());
    let delta = net.delta();
    let mut leaves: Vec<NetLeaf> = meshed
        .iter()
        .flat_map(|(c, ls)| ls.iter().map(|l| NetLeaf::new(*c, l.paired.clone())))
        .collect();
    if delta.is_finite() {
        let fixed = |p| net.is_fixed_point(p);
        report.t_junctions = resolve_t_junctions(net, &mut leaves, delta, tol, &fixed);
    }
    // one variable per pair of every part
    let mut offset = Vec::with_capacity(leaves.len());
    let mut lower = Vec::new();
    for leaf in &leaves {
        offset.push(lower.len());
        let p = &leaf.paired;
        for &(i, j) in &p.pairs {
            let len = |s: usize| Polyline::new(segment_points(p, s)).length();
            lower.push(((len(i) / h).ceil().max((len(j) / h).ceil()).max(1.0)) as usize);
        }
    }
    let seg_var: Vec<Vec<usize>> = leaves
        .iter()
        .zip(&offset)
        .map(|(leaf, &o)| {
            let mut v = vec![0; leaf.paired.starts.len()];
            for (k, &(i, j)) in leaf.paired.pairs.iter().enumerate() {
                v[i] = o + k;
                v[j] = o + k;
            }
            v
        })
        .collect();
    let (curves, _) = shared_curves(net, &leaves, tol);
    let weld = Welder::new(tolerance);
    let mut by_key: BTreeMap<(usize, [[i64; 3]; 2]), Vec<usize>> = BTreeMap::new();
    for (li, leaf) in leaves.iter().enumerate() {
        for s in 0..leaf.paired.starts.len() {
            if leaf.paired.unsplittable[s] {
                let key = (leaf.cycle, segment_key(&leaf.paired, s, &weld));
                by_key.entry(key).or_default().push(seg_var[li][s]);
            }
        }
    }
    let equal: Vec<(usize, usize)> = by_key
        .values()
        .flat_map(|vars| vars.windows(2).map(|w| (w[0], w[1])))
        .collect();
    // the program with the common vertices `joined` made secondary, and
    // per soft equality its (shared curve, primary segment)
    let program = |joined: &[(usize, f64)]| {
        let mut prog = IntervalProgram {
            lower: lower.clone(),
            equal: equal.clone(),
            ..Default::default()
        };
        let mut places = Vec::new();
        for (ci, sc) in curves.iter().enumerate() {
            let here: Vec<f64> = joined
                .iter()
                .filter(|j| j.0 == sc.curve)
                .map(|j| j.1)
                .collect();
            for (a, b) in sc.primary_segments(tol, &here) {
                let side = |k: usize| -> Vec<usize> {
                    sc.inside(k, a, b, tol)
                        .iter()
                        .map(|s| seg_var[s.leaf][s.segment])
                        .collect()
                };
                prog.equal_sums.push((side(0), side(1)));
                places.push((ci, a, b));
            }
        }
        (prog, places)
    };
    let mut joined: Vec<(usize, f64)> = Vec::new();
    let (mut prog, mut places) = program(&joined);
    let mut solved = solve_intervals(&prog);
    let fixed = |p| net.is_fixed_point(p);
    let first_primary: Vec<Vec<bool>> = leaves.iter().map(|l| l.primary.clone()).collect();
    let first = (prog.clone(), solved.clone());
    for _ in 0..MAX_JOIN_ROUNDS {
        let Ok(s) = &solved else { break };
        if s.mismatch == 0 {
            break;
        }
        let (tried, kept) = join_unbalanced(&prog, &places, &curves, s, &mut leaves, tol, &fixed);
        if tried.is_empty() {
            break;
        }
        let all: Vec<(usize, f64)> = joined.iter().chain(&tried).copied().collect();
        let (p2, pl2) = program(&all);
        let s2 = solve_intervals(&p2);
        if matches!(&s2, Ok(x) if x.mismatch < s.mismatch) {
            (joined, prog, places, solved) = (all, p2, pl2, s2);
        } else {
            for (leaf, primary) in leaves.iter_mut().zip(kept) {
                leaf.primary = primary;
            }
            break;
        }
    }
    if !joined.is_empty() && !matches!(&solved, Ok(x) if x.mismatch == 0) {
        // joining without reaching watertightness only moves vertices
        for (leaf, primary) in leaves.iter_mut().zip(&first_primary) {
            leaf.primary.clone_from(primary);
        }
        joined.clear();
        (prog, solved) = first;
    }
    report.joined = joined.len();
    report.chords = prog.lower.len();
    report.primary_segments = prog.equal_sums.len();
    let counts = match solved {
        Ok(s) => {
            report.mismatch = s.mismatch;
            report.intervals = s.counts.iter().sum();
            report.interval_seconds = s.seconds;
            s.counts
        }
        Err(e) => {
            report
                .notes
                .push(format!("{e}: each chord keeps its smallest count"));
            prog.lower.clone()
        }
    };
    report.snapped = snap_secondary_vertices(
        net,
        &mut leaves,
        tol,
        &|li, s| counts[seg_var[li][s]],
        &joined,
    );
    // lay out and sample again, in parallel, in order
    let mut flat: Vec<&mut Leaf> = meshed
        .iter_mut()
        .flat_map(|(_, ls)| ls.iter_mut())
        .collect();
    let jobs: Vec<(usize, &NetLeaf, &Leaf)> = leaves
        .iter()
        .enumerate()
        .zip(flat.iter())
        .map(|((i, n), l)| (i, n, &**l))
        .collect();
    let resample = |&(li, net_leaf, old): &(usize, &NetLeaf, &Leaf)| -> Result<Option<(PairedCycle, crate::curvenet::CycleQuads)>, String> {
        let p = &net_leaf.paired;
        let intervals = |layout: &crate::curvenet::layout::Layout| -> Vec<usize> {
            layout
                .chords
                .iter()
                .map(|&(i, j)| {
                    let k = p.pairs.iter().position(|&pr| pr == (i.min(j), i.max(j))).unwrap_or(0);
                    counts[offset[li] + k]
                })
                .collect()
        };
        if !net_leaf.changed {
            let n = intervals(&old.quads.layout);
            if n == old.quads.intervals {
                return Ok(None);
            }
            let q = sample_layout_with_intervals(p, old.quads.layout.clone(), n);
            return unfolded(q, &old.facing, true).map(|q| Some((p.clone(), q))).map_err(|e| e.to_string());
        }
        let layout = embed(p).map_err(|e| e.to_string())?;
        let n = intervals(&layout);
        let q = sample_layout_with_intervals(p, layout, n);
        unfolded(q, &old.facing, true).map(|q| Some((p.clone(), q))).map_err(|e| e.to_string())
    };
    let outcomes = match threads.and_then(|n| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n.max(1))
            .build()
            .ok()
    }) {
        Some(pool) => pool.install(|| map_in_order(&jobs, resample)),
        None => map_in_order(&jobs, resample),
    };
    drop(jobs);
    for ((li, outcome), leaf) in outcomes.into_iter().enumerate().zip(flat.iter_mut()) {
        match outcome {
            Ok(Some((paired, quads))) => {
                if leaves[li].changed {
                    report.relaid += 1;
                }
                leaf.paired = paired;
                leaf.quads = quads;
            }
            Ok(None) => {}
            Err(e) => report.notes.push(format!(
                "cycle {}: the network stage's layout failed ({e}): the part keeps its own sampling",
                leaves[li].cycle
            )),
        }
    }
    report.seconds = started.elapsed().as_secs_f64();
    report
}

/// Cycles meshed again (without the ring), or run in a pool of `threads`.
fn in_pool<T: Sync, R: Send>(
    threads: Option<usize>,
    items: &[T],
    job: impl Fn(&T) -> R + Sync + Send,
) -> Vec<R> {
    match threads.and_then(|n| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n.max(1))
            .build()
            .ok()
    }) {
        Some(pool) => pool.install(|| map_in_order(items, job)),
        None => map_in_order(items, job),
    }
}

/// A ring (`curvenet::ring`) gives every sector one chord from the outer
/// loop to the hole, so the outer loop's interval count equals the hole's:
/// a constraint of the interval program like any chord, but one the shared
/// curves may not allow (the loops' neighbours ask for different counts).
/// When the program leaves a mismatch, the ring cycles are meshed again
/// without the ring (the two-connector split, whose halves have chords
/// from the outer loop to itself) and the network stage rerun from `before`
/// (the leaves before the stage); then each ring is put back unless that
/// raises the mismatch, or at equal mismatch the interval total (a ring's
/// equal counts can inflate the counts round it, which the joined primary
/// segments of [`join_unbalanced`] otherwise let through). The outcome with
/// the least mismatch is kept
/// (`meshed`, the report's cycles and network), the rings when no split
/// helps.
pub(super) fn rings_to_splits(
    net: &CurveNetwork,
    before: Vec<(usize, Vec<Leaf>)>,
    meshed: &mut Vec<(usize, Vec<Leaf>)>,
    report: &mut CurvesReport,
    weld: &Welder,
    opts: &CurvesOptions,
) {
    let started = Instant::now();
    let first = report.network.mismatch;
    if first == 0 {
        return;
    }
    let h = report.h;
    let rings: Vec<usize> = (0..before.len())
        .filter(|&k| before[k].1.iter().any(|l| l.ring))
        .collect();
    let redo = |&k: &usize| -> Option<(usize, Vec<Leaf>, CycleSummary)> {
        let t0 = Instant::now();
        let loops = net.cycle_loops(before[k].0).ok()?;
        let (leaves, mut summary) = mesh_cycle(&loops, h, &opts.pairing, weld, false).ok()?;
        summary.cycle = before[k].0;
        summary.seconds = t0.elapsed().as_secs_f64();
        Some((k, leaves, summary))
    };
    let split: Vec<(usize, Vec<Leaf>, CycleSummary)> = in_pool(opts.threads, &rings, redo)
        .into_iter()
        .flatten()
        .collect();
    if split.is_empty() {
        return;
    }
    let stage = |use_split: &[bool]| {
        let mut m = before.clone();
        for ((k, leaves, _), _) in split.iter().zip(use_split).filter(|(_, &u)| u) {
            m[*k].1 = leaves.clone();
        }
        let r = network_stage(net, &mut m, h, weld.tolerance, opts.threads);
        (m, r)
    };
    let mut chosen = vec![true; split.len()];
    let (mut best, mut best_report) = stage(&chosen);
    if best_report.mismatch >= first {
        report.network.notes.push(format!(
            "interval mismatch {first}: splitting the {} ring(s) instead does not lower it ({}): rings kept",
            split.len(),
            best_report.mismatch
        ));
        report.network.seconds += started.elapsed().as_secs_f64();
        return;
    }
    for i in 0..split.len() {
        chosen[i] = false;
        let (m, r) = stage(&chosen);
        if (r.mismatch, r.intervals) <= (best_report.mismatch, best_report.intervals) {
            (best, best_report) = (m, r);
        } else {
            chosen[i] = true;
        }
    }
    *meshed = best;
    let mut replaced = Vec::new();
    for ((k, _, mut summary), _) in split.into_iter().zip(&chosen).filter(|(_, &u)| u) {
        summary.notes.push(
            "annulus: the ring's equal outer and hole counts left an interval mismatch: two-connector split used"
                .to_string(),
        );
        replaced.push(summary.cycle);
        report.cycles[k] = summary;
    }
    best_report.notes.push(format!(
        "interval mismatch {first} with rings, {} with cycles {replaced:?} split by two connectors instead",
        best_report.mismatch
    ));
    best_report.seconds = started.elapsed().as_secs_f64() + report.network.seconds;
    report.network = best_report;
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeMap;

    use geometry::vec3;

    use crate::curvenet::{fixtures, parse_json};
    use crate::methods::curvenet::{mesh_curve_network, CurvesOptions};

    /// Fig. 15: the L splits the shared side in the middle, the rectangle
    /// does not; at h = 0.3 the L samples each half 4 times and the
    /// rectangle the whole side 7 times, so without the network stage the
    /// side stays open. The stage splits the rectangle's chord in two: the
    /// mesh is open only on the outer boundary (length 2 + 1 + 2 + 1 + 8 − 4 = 10),
    /// no edge is used thrice, no quad is inverted.
    #[test]
    fn the_t_junction_of_an_ell_on_a_rectangle_is_resolved() {
        let net = parse_json(&fixtures::ell_on_rectangle_json(), None).unwrap();
        let opts = CurvesOptions {
            size: Some(0.3),
            threads: Some(1),
            ..Default::default()
        };
        let (mesh, report) = mesh_curve_network(&net, &opts).unwrap();
        let tj = &report.network.t_junctions;
        assert_eq!(tj.shared_curves, 1, "{:?}", report.network);
        assert!(tj.split >= 1, "{:?}", report.network);
        assert_eq!(tj.unresolved, 0, "{:?}", report.network);
        assert_eq!(report.network.mismatch, 0);
        let mut uses: BTreeMap<(u32, u32), usize> = BTreeMap::new();
        for q in &mesh.quads {
            for k in 0..4 {
                let (a, b) = (q[k], q[(k + 1) % 4]);
                *uses.entry((a.min(b), a.max(b))).or_insert(0) += 1;
            }
        }
        assert!(uses.values().all(|&n| n <= 2));
        let mut open_length = 0.0;
        for (&(a, b), _) in uses.iter().filter(|(_, &n)| n == 1) {
            let (p, q) = (mesh.nodes[a as usize], mesh.nodes[b as usize]);
            let mid = vec3::scale(vec3::add(p, q), 0.5);
            assert!(
                !(mid[1].abs() < 1e-9 && mid[0] > 1e-9 && mid[0] < 2.0 - 1e-9),
                "an open edge on the shared side at {mid:?}"
            );
            open_length += vec3::dist(p, q);
        }
        assert!(
            (open_length - 10.0).abs() < 1e-6,
            "open length {open_length}"
        );
        for q in &mesh.quads {
            let p = q.map(|v| mesh.nodes[v as usize]);
            assert!(mesh::quality::quad_sicn(&p, &[[0.0, 0.0, 1.0]; 4]) > 0.0);
        }
        // the same without the network stage: the shared side stays open
        let alone = CurvesOptions {
            network: false,
            ..opts
        };
        let (own, own_report) = mesh_curve_network(&net, &alone).unwrap();
        assert_eq!(own_report.network.t_junctions.split, 0);
        let mut own_uses: BTreeMap<(u32, u32), usize> = BTreeMap::new();
        for q in &own.quads {
            for k in 0..4 {
                let (a, b) = (q[k], q[(k + 1) % 4]);
                *own_uses.entry((a.min(b), a.max(b))).or_insert(0) += 1;
            }
        }
        let open_on_shared = own_uses
            .iter()
            .filter(|(_, &n)| n == 1)
            .filter(|(&(a, b), _)| {
                let mid = vec3::scale(vec3::add(own.nodes[a as usize], own.nodes[b as usize]), 0.5);
                mid[1].abs() < 1e-9 && mid[0] > 1e-9 && mid[0] < 2.0 - 1e-9
            })
            .count();
        assert!(open_on_shared > 0);
    }
}
