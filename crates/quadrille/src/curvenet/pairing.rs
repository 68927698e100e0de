//! The entry point of §1–§4: a [`CycleLoops`] in, a [`PairedCycle`] out, with
//! the options (the spec's parameters) and a report of what happened.

use thiserror::Error;

use super::polyline::{densify_closed, diameter, dist, norm, newell_normal, P3};
use super::refine::{refine_loop, Context};
use super::segment::{join_hole, segment_loop, LoopSegmentation, SegmentedLoop};
use super::{CycleLoops, LoopPolyline, PairedCycle};

/// The parameters of segmentation, costs, matching and refinement; `Default`
/// gives the spec's values (§8).
#[derive(Clone, Debug, PartialEq)]
pub struct PairingOptions {
    /// Weight of bridge curvature b in c (0.8).
    pub w_bridge: f64,
    /// Weight of similarity s in c (0.1).
    pub w_similarity: f64,
    /// Weight of distance d in c (0.1).
    pub w_distance: f64,
    /// Arc-length samples per segment for b, s and d (50).
    pub samples: usize,
    /// σ of the shape term's Gaussian, in D (1/3).
    pub shape_sigma: f64,
    /// b in radians (true, the default) or over π (false); interacts with `dom`.
    pub b_in_radians: bool,
    /// A neighbour m influences i when `influence_length · l_m > l_i` (1.5).
    pub influence_length: f64,
    /// … and the angle between their flow directions is at most this, degrees (135).
    pub influence_angle: f64,
    /// Dominant pairs: c below this (0.15).
    pub dom: f64,
    /// Refinement continues while the average cost drops by this factor (1.25).
    pub drop: f64,
    /// A corner turns by more than this over the window, degrees (40).
    pub corner_angle: f64,
    /// The corner window: samples each way (2).
    pub corner_window: usize,
    /// Fewer corners than this use the curvature-and-arc-length fallback (3).
    pub min_corners: usize,
    /// A curvature maximum of the fallback turns by at least this, degrees (10).
    pub fallback_min_turn: f64,
    /// Near-linear: distance to the chord at most τ·|chord| (0.25).
    pub near_linear_tau: f64,
    /// Near-linear: total turn at most this, degrees (100).
    pub near_linear_turn: f64,
    /// Costs within this relative difference are tied (1e-9).
    pub tie_relative: f64,
    /// Cap on refinement steps (20).
    pub max_iterations: usize,
    /// Cap on the segment count (40).
    pub max_segments: usize,
    /// Loops are densified to samples at most this fraction of D apart (1/200).
    pub sample_spacing: f64,
    /// The outer loop's closing edge (from its last point back to its first)
    /// stays one segment, never split: set for the parts of a cut cycle
    /// (Fig. 10), whose closing edge is the cut both parts must sample alike.
    pub closing_edge_unsplittable: bool,
    /// Edges of the outer loop (from one point to the next, by position)
    /// that stay one segment, never split: the connectors of an annulus
    /// split in two (`curvenet::ring::split_annulus`). Their ends must be
    /// fixed points.
    pub unsplittable_edges: Vec<[P3; 2]>,
}

impl Default for PairingOptions {
    fn default() -> Self {
        PairingOptions {
            w_bridge: 0.8,
            w_similarity: 0.1,
            w_distance: 0.1,
            samples: 50,
            shape_sigma: 1.0 / 3.0,
            b_in_radians: true,
            influence_length: 1.5,
            influence_angle: 135.0,
            dom: 0.15,
            drop: 1.25,
            corner_angle: 40.0,
            corner_window: 2,
            min_corners: 3,
            fallback_min_turn: 10.0,
            near_linear_tau: 0.25,
            near_linear_turn: 100.0,
            tie_relative: 1e-9,
            max_iterations: 20,
            max_segments: 40,
            sample_spacing: 1.0 / 200.0,
            closing_edge_unsplittable: false,
            unsplittable_edges: Vec::new(),
        }
    }
}

/// What happened while a cycle was segmented and paired.
#[derive(Clone, Debug, PartialEq)]
pub struct PairingReport {
    /// Segments after the initial segmentation and the hole connectors.
    pub initial_segments: usize,
    /// Segments of the returned pairing.
    pub final_segments: usize,
    /// Refinement steps taken (rolled-back ones included).
    pub iterations: usize,
    /// Loops (0 = outer, k = hole k) that used the curvature-and-arc-length
    /// fallback, with the corners found on each.
    pub fallbacks: Vec<(usize, usize)>,
    /// The odd parties met, segment indices at the time they were found.
    pub odd_parties: Vec<Vec<usize>>,
    /// Connectors added for holes (each two segments).
    pub connectors: usize,
    /// The pair costs, in the returned pairs' order.
    pub costs: Vec<f64>,
    /// Σc²/(2⌊n/2⌋) of the returned matching.
    pub average_cost: f64,
    /// The largest pair cost of the returned matching.
    pub worst_cost: f64,
    /// Per step: segment count, average and worst cost (∞ for an odd party).
    pub history: Vec<(usize, f64, f64)>,
}

impl PairingReport {
    /// One line per fallback, naming it (the issue asks that a line names it).
    pub fn notes(&self) -> Vec<String> {
        let mut lines: Vec<String> = self
            .fallbacks
            .iter()
            .map(|(l, c)| format!("loop {l}: {c} corners, segmented by curvature maxima and arc length (fallback)"))
            .collect();
        for p in &self.odd_parties {
            lines.push(format!("odd party of segments {p:?}: each split in two"));
        }
        lines
    }
}

/// Why a cycle could not be segmented and paired.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum PairingError {
    /// The closing edge asked to stay one segment does not run between two
    /// segment starts (its ends must be fixed points).
    #[error("curve cycle: the closing edge from point {last} to point 0 is not one segment between fixed points")]
    ClosingEdge {
        /// The dense index of the outer loop's last point.
        last: usize,
    },
    /// An edge asked to stay one segment does not run between two segment
    /// starts.
    #[error("curve cycle: the connector from {from:?} to {to:?} is not one segment between fixed points")]
    KeptEdge {
        /// The edge's first point.
        from: P3,
        /// The edge's second point.
        to: P3,
    },
    /// A loop with too few distinct points.
    #[error("curve cycle, loop {loop_index}: {count} distinct points, at least 3 needed")]
    TooFewPoints {
        /// 0 = outer, k = hole k.
        loop_index: usize,
        /// Distinct consecutive points.
        count: usize,
    },
    /// A NaN or infinite coordinate.
    #[error("curve cycle, loop {loop_index}, point {point}: a coordinate is not finite")]
    NotFinite {
        /// 0 = outer, k = hole k.
        loop_index: usize,
        /// The point's index.
        point: usize,
    },
    /// A fixed point index past the end.
    #[error("curve cycle, loop {loop_index}: fixed index {index} but only {count} points")]
    FixedOutOfRange {
        /// 0 = outer, k = hole k.
        loop_index: usize,
        /// The bad index.
        index: usize,
        /// The point count.
        count: usize,
    },
    /// The outer loop encloses no area (folded flat, figure-eight, a point).
    #[error("curve cycle: the outer loop has no inward side (Newell area {area:e} < {limit:e} = 1e-6 D², D = {diameter:e})")]
    NoInwardSide {
        /// Half the Newell normal's length.
        area: f64,
        /// 1e-6 D².
        limit: f64,
        /// The cycle diameter.
        diameter: f64,
    },
    /// No even segmentation with a stable matching within the caps.
    #[error("curve cycle: no even segmentation with a stable matching within {iterations} refinements and {segments} segments")]
    NoEvenMatching {
        /// The iteration cap.
        iterations: usize,
        /// The segment cap.
        segments: usize,
    },
}

/// A loop with consecutive duplicate points removed (fixed indices moved to
/// the surviving copy), checked for finite coordinates and ≥ 3 points.
pub(super) fn clean_loop(lp: &LoopPolyline, loop_index: usize, tol: f64) -> Result<(Vec<P3>, Vec<usize>), PairingError> {
    for (i, p) in lp.points.iter().enumerate() {
        if p.iter().any(|v| !v.is_finite()) {
            return Err(PairingError::NotFinite { loop_index, point: i });
        }
    }
    if let Some(&index) = lp.fixed.iter().find(|&&f| f >= lp.points.len()) {
        return Err(PairingError::FixedOutOfRange { loop_index, index, count: lp.points.len() });
    }
    let mut points: Vec<P3> = Vec::new();
    let mut new_index = Vec::with_capacity(lp.points.len());
    for p in &lp.points {
        if points.last().is_none_or(|q| dist(*q, *p) > tol) {
            points.push(*p);
        }
        new_index.push(points.len() - 1);
    }
    while points.len() > 1 && dist(points[0], points[points.len() - 1]) <= tol {
        points.pop();
        for v in new_index.iter_mut().filter(|v| **v >= points.len()) {
            *v = 0;
        }
    }
    if points.len() < 3 {
        return Err(PairingError::TooFewPoints { loop_index, count: points.len() });
    }
    let mut fixed: Vec<usize> = lp.fixed.iter().map(|&f| new_index[f]).collect();
    fixed.sort_unstable();
    fixed.dedup();
    Ok((points, fixed))
}

/// Marks the segment from dense point `last` (the outer loop's last input
/// point) around to point 0 unsplittable: the closing edge of a cut part.
/// Both ends must be segment starts (the cut's ends are fixed points).
fn keep_closing_edge(lp: &mut SegmentedLoop, last: usize) -> Result<(), PairingError> {
    let k = lp.starts.len();
    match lp.starts.iter().position(|&s| s == last) {
        Some(s) if lp.starts[(s + 1) % k] == 0 => {
            lp.unsplittable[s] = true;
            Ok(())
        }
        _ => Err(PairingError::ClosingEdge { last }),
    }
}

/// Marks the segment from position `from` to position `to` (both segment
/// starts, within `tol`) unsplittable.
fn keep_edge(lp: &mut SegmentedLoop, from: P3, to: P3, tol: f64) -> Result<(), PairingError> {
    let k = lp.starts.len();
    let at = |s: usize, p: P3| dist(lp.points[lp.starts[s % k]], p) <= tol;
    match (0..k).find(|&s| at(s, from) && at(s + 1, to)) {
        Some(s) => {
            lp.unsplittable[s] = true;
            Ok(())
        }
        None => Err(PairingError::KeptEdge { from, to }),
    }
}

/// Segments a cycle, joins its holes, and refines the segmentation with
/// stable matching (spec §1–§4) into a [`PairedCycle`] for the layout stage.
pub fn pair_cycle(cycle: &CycleLoops, opts: &PairingOptions) -> Result<(PairedCycle, PairingReport), PairingError> {
    let loops: Vec<&LoopPolyline> = std::iter::once(&cycle.outer).chain(&cycle.holes).collect();
    let all: Vec<P3> = loops.iter().flat_map(|l| l.points.iter().copied()).collect();
    if let Some((li, pi)) = loops
        .iter()
        .enumerate()
        .find_map(|(li, l)| l.points.iter().position(|p| p.iter().any(|v| !v.is_finite())).map(|pi| (li, pi)))
    {
        return Err(PairingError::NotFinite { loop_index: li, point: pi });
    }
    let d = diameter(&all);
    let normal = newell_normal(&cycle.outer.points);
    let area = 0.5 * norm(normal);
    if !(d > 0.0) || area < 1e-6 * d * d {
        return Err(PairingError::NoInwardSide { area, limit: 1e-6 * d * d, diameter: d });
    }
    let mut segmented: Vec<LoopSegmentation> = Vec::new();
    for (li, lp) in loops.iter().enumerate() {
        let (points, fixed) = clean_loop(lp, li, 1e-12 * d)?;
        let (dense, index_of) = densify_closed(&points, opts.sample_spacing * d);
        let fixed: Vec<usize> = fixed.iter().map(|&f| index_of[f]).collect();
        let mut loop_segments = segment_loop(dense, &fixed, opts);
        if li == 0 && opts.closing_edge_unsplittable {
            keep_closing_edge(&mut loop_segments.segmented, index_of[points.len() - 1])?;
        }
        if li == 0 {
            for &[from, to] in &opts.unsplittable_edges {
                keep_edge(&mut loop_segments.segmented, from, to, 1e-9 * d)?;
            }
        }
        segmented.push(loop_segments);
    }
    let fallbacks: Vec<(usize, usize)> =
        segmented.iter().enumerate().filter(|(_, s)| s.fallback).map(|(i, s)| (i, s.corners)).collect();
    let mut joined: SegmentedLoop = segmented[0].segmented.clone();
    for hole in &segmented[1..] {
        joined = join_hole(&joined, &hole.segmented, d, normal, opts, cycle.surface.as_ref());
    }
    let initial_segments = joined.starts.len();
    let ctx = Context::new(d, normal, opts, cycle.surface.as_ref());
    let refined = refine_loop(&ctx, joined)
        .ok_or(PairingError::NoEvenMatching { iterations: opts.max_iterations, segments: opts.max_segments })?;
    let best = &refined.result;
    let mate = best.mates().unwrap_or(&[]);
    let pairs: Vec<(usize, usize)> =
        (0..mate.len()).filter_map(|i| mate[i].filter(|&j| j > i).map(|j| (i, j))).collect();
    let costs: Vec<f64> = pairs.iter().map(|&(i, j)| best.costs[i][j]).collect();
    let paired = PairedCycle {
        points: best.seg.lp.points.clone(),
        starts: best.seg.lp.starts.clone(),
        pairs,
        costs: costs.clone(),
        unsplittable: best.seg.lp.unsplittable.clone(),
        diameter: d,
    };
    let report = PairingReport {
        initial_segments,
        final_segments: paired.starts.len(),
        iterations: refined.iterations,
        fallbacks,
        odd_parties: refined.odd_parties.clone(),
        connectors: cycle.holes.len(),
        costs,
        average_cost: best.average,
        worst_cost: best.worst,
        history: refined.history.clone(),
    };
    Ok((paired, report))
}
