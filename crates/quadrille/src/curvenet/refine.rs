//! Iterative segmentation and matching (spec §4, paper §3.1 and §3.1.4):
//! split segments (midpoint and targeted length-ratio splits, else a global
//! mid-split; every segment of an odd party in two), rematch, and continue
//! while the average cost Σc²/(2⌊n/2⌋) drops by the factor `drop` and the worst
//! cost does not rise; then roll back to the last even segmentation.

use std::cell::RefCell;
use std::collections::HashMap;

use super::cost::{
    affine_residual, dominant_update, initial_direction, mean_bridge_angle, pair_cost_of_parts, segment_shapes,
    SegmentShape,
};
use super::polyline::{split_index, P3};
use super::roommates::{match_by_cost, MatchOutcome};
use super::segment::SegmentedLoop;
use super::{CycleSurface, PairingOptions};

/// A segmentation with the bridge direction of each segment (`None` until
/// a new segment gets its initial one).
#[derive(Clone, Debug)]
pub struct Segmentation {
    /// The loop and its segments.
    pub lp: SegmentedLoop,
    /// Bridge direction t per segment.
    pub t: Vec<Option<P3>>,
}

/// A segmentation with its costs and stable matching.
#[derive(Clone, Debug)]
pub struct Evaluated {
    /// The segmentation, every t set (after the dominant-pair update).
    pub seg: Segmentation,
    /// The symmetric cost matrix.
    pub costs: Vec<Vec<f64>>,
    /// The matching or the odd party.
    pub outcome: MatchOutcome,
    /// Σc²/(2⌊n/2⌋) over the matching (∞ for an odd party).
    pub average: f64,
    /// The largest pair cost of the matching (∞ for an odd party).
    pub worst: f64,
}

impl Evaluated {
    /// The segment count.
    pub fn len(&self) -> usize {
        self.seg.lp.starts.len()
    }
    /// Whether there are no segments.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Each segment's mate, when matched.
    pub fn mates(&self) -> Option<&[Option<usize>]> {
        match &self.outcome {
            MatchOutcome::Matched(m) => Some(m),
            MatchOutcome::OddParty(_) => None,
        }
    }
    /// Whether this is an even segmentation with a perfect stable matching.
    pub fn is_even_matched(&self) -> bool {
        self.len() % 2 == 0 && self.mates().is_some_and(|m| m.iter().all(Option::is_some))
    }
}

/// What stays fixed while a cycle is refined.
pub struct Context<'a> {
    /// The cycle diameter D.
    pub diameter: f64,
    /// The cycle's Newell normal, orienting the local planes.
    pub normal: P3,
    /// The parameters.
    pub opts: &'a PairingOptions,
    /// The cycle's CAD surface, when it bounds a CAD face: bridge
    /// directions are then set in its tangent planes.
    pub surface: Option<&'a CycleSurface>,
    /// CAD normals already asked for, by the point's bits.
    normals: RefCell<HashMap<[u64; 3], Option<P3>>>,
    /// Pair costs already computed, by the two segments' end indices and
    /// bridge directions (a pair's cost depends on nothing else; only looked
    /// up, never iterated, so the output does not depend on its order).
    cache: RefCell<HashMap<PairKey, f64>>,
    /// The cost's parts on a pair-cache miss (issue 30: a new bridge
    /// direction of one segment made every pair with it miss, and each miss
    /// recomputed both residuals, which do not depend on the directions):
    /// mean bridge angles by the from-segment's key and the to-segment's
    /// ends, affine residuals by the two segments' ends (each ordered).
    angles: RefCell<HashMap<(SegmentKey, SegmentEnds), f64>>,
    residuals: RefCell<HashMap<(SegmentEnds, SegmentEnds), f64>>,
}

/// A segment's ends (start indices of it and its successor): its polyline,
/// hence its samples, centre and length.
type SegmentEnds = (usize, usize);

/// A segment's identity for the cost cache: its two end indices and the bits
/// of its bridge direction.
type SegmentKey = (usize, usize, [u64; 3]);
type PairKey = (SegmentKey, SegmentKey);

/// Added to the cost of two neighbouring segments (ours; the spec's §3
/// allows forbidding them): their poly-chord would cross no other, a chord
/// graph in pieces (Fig. 10), as when the two collinear halves of a split
/// side pair with each other (the letter P's hole).
pub const ADJACENT_PAIR_PENALTY: f64 = 10.0;

impl<'a> Context<'a> {
    /// A context for one cycle.
    pub fn new(diameter: f64, normal: P3, opts: &'a PairingOptions, surface: Option<&'a CycleSurface>) -> Self {
        Context {
            diameter,
            normal,
            opts,
            surface,
            normals: RefCell::new(HashMap::new()),
            cache: RefCell::new(HashMap::new()),
            angles: RefCell::new(HashMap::new()),
            residuals: RefCell::new(HashMap::new()),
        }
    }

    /// The CAD normal at the closest point to `p`, through the cache.
    fn normal_at(&self, p: P3) -> Option<P3> {
        let surface = self.surface?;
        *self.normals.borrow_mut().entry(p.map(f64::to_bits)).or_insert_with(|| surface.bridge_normal_at(p))
    }

    /// The symmetric cost matrix, through the cache.
    fn cost_matrix(&self, lp: &SegmentedLoop, shapes: &[SegmentShape], t: &[P3]) -> Vec<Vec<f64>> {
        let k = shapes.len();
        let key = |s: usize| (lp.starts[s], lp.starts[(s + 1) % k], t[s].map(f64::to_bits));
        let mut c = vec![vec![0.0; k]; k];
        let mut cache = self.cache.borrow_mut();
        for i in 0..k {
            for j in i + 1..k {
                let mut v = *cache
                    .entry((key(i), key(j)))
                    .or_insert_with(|| self.pair_cost(&shapes[i], key(i), &shapes[j], key(j)));
                if k > 2 && (j == i + 1 || (i == 0 && j == k - 1)) {
                    v += ADJACENT_PAIR_PENALTY;
                }
                c[i][j] = v;
                c[j][i] = v;
            }
        }
        c
    }

    /// The total cost of pairing segments `a` (key `ka`, direction in it)
    /// and `b` (key `kb`), its mean bridge angles and affine residuals
    /// through their caches: the same value as `cost::pair_cost`.
    fn pair_cost(&self, a: &SegmentShape, ka: SegmentKey, b: &SegmentShape, kb: SegmentKey) -> f64 {
        let (ta, tb) = (ka.2.map(f64::from_bits), kb.2.map(f64::from_bits));
        let (ea, eb) = ((ka.0, ka.1), (kb.0, kb.1));
        let mut angles = self.angles.borrow_mut();
        let ab = *angles.entry((ka, eb)).or_insert_with(|| mean_bridge_angle(a, ta, b));
        let ba = *angles.entry((kb, ea)).or_insert_with(|| mean_bridge_angle(b, tb, a));
        let mut residuals = self.residuals.borrow_mut();
        let rab = *residuals.entry((ea, eb)).or_insert_with(|| affine_residual(a, b));
        let rba = *residuals.entry((eb, ea)).or_insert_with(|| affine_residual(b, a));
        pair_cost_of_parts(a, b, [ab, ba], [rab, rba], self.opts).total
    }

    /// The shapes of the segments.
    fn shapes(&self, lp: &SegmentedLoop) -> Vec<SegmentShape> {
        let at = |p: P3| self.normal_at(p);
        let normal_at: Option<super::cost::NormalAt<'_>> = self.surface.map(|_| &at as super::cost::NormalAt<'_>);
        segment_shapes(&lp.segment_polylines(), self.diameter, self.normal, self.opts.samples, normal_at)
    }

    /// Costs and matching of a segmentation: new segments get their initial
    /// t; match; update t from dominant pairs; recompute the costs; rematch
    /// (spec §2.4, order (a)–(e)).
    pub fn evaluate(&self, mut seg: Segmentation) -> Evaluated {
        let shapes = self.shapes(&seg.lp);
        let mut t: Vec<P3> =
            (0..shapes.len()).map(|i| seg.t[i].unwrap_or_else(|| initial_direction(&shapes, i, self.opts))).collect();
        let mut costs = self.cost_matrix(&seg.lp, &shapes, &t);
        let mut outcome = match_by_cost(&costs, self.opts.tie_relative);
        if let MatchOutcome::Matched(mate) = &outcome {
            let before = t.clone();
            dominant_update(&shapes, &mut t, mate, &costs, self.opts.dom);
            if before != t {
                costs = self.cost_matrix(&seg.lp, &shapes, &t);
                outcome = match_by_cost(&costs, self.opts.tie_relative);
            }
        }
        seg.t = t.into_iter().map(Some).collect();
        let (average, worst) = match &outcome {
            MatchOutcome::Matched(mate) => {
                let pair_costs: Vec<f64> =
                    (0..mate.len()).filter_map(|i| mate[i].filter(|&j| j > i).map(|j| costs[i][j])).collect();
                let n = mate.len();
                let avg = pair_costs.iter().map(|c| c * c).sum::<f64>() / (2 * (n / 2)).max(1) as f64;
                (avg, pair_costs.iter().copied().fold(0.0, f64::max))
            }
            MatchOutcome::OddParty(_) => (f64::INFINITY, f64::INFINITY),
        };
        Evaluated { seg, costs, outcome, average, worst }
    }
}

/// `seg` with the given `(segment, index)` splits: each split segment's
/// halves get new (unset) bridge directions.
fn with_splits(seg: &Segmentation, splits: &[(usize, usize)]) -> Segmentation {
    let mut entries: Vec<(usize, bool, Option<P3>)> =
        (0..seg.lp.starts.len()).map(|s| (seg.lp.starts[s], seg.lp.unsplittable[s], seg.t[s])).collect();
    for &(s, idx) in splits {
        entries[s].2 = None;
        entries.push((idx, false, None));
    }
    entries.sort_by_key(|e| e.0);
    entries.dedup_by_key(|e| e.0);
    Segmentation {
        lp: SegmentedLoop {
            points: seg.lp.points.clone(),
            starts: entries.iter().map(|e| e.0).collect(),
            unsplittable: entries.iter().map(|e| e.1).collect(),
        },
        t: entries.iter().map(|e| e.2).collect(),
    }
}

/// The split of segment `s` at `fraction` of its arc length, if it may be
/// split and has an interior sample.
fn split_at(seg: &Segmentation, s: usize, fraction: f64) -> Option<(usize, usize)> {
    let k = seg.lp.starts.len();
    if seg.lp.unsplittable[s] {
        return None;
    }
    split_index(&seg.lp.points, seg.lp.starts[s], seg.lp.starts[(s + 1) % k], fraction).map(|i| (s, i))
}

/// One refinement (spec §4 `refine(σ)`): an odd party splits each of its
/// segments in two; else the best single split (midpoint, then targeted
/// length-ratio splits), preferring those that do not raise the worst cost;
/// else, when no single split lowers the average, a global mid-split.
/// `None` when nothing can be split within the segment cap.
pub fn refine_step(ctx: &Context<'_>, cur: &Evaluated) -> Option<Evaluated> {
    let k = cur.len();
    let cap = ctx.opts.max_segments;
    let global = || {
        let splits: Vec<(usize, usize)> = (0..k).filter_map(|s| split_at(&cur.seg, s, 0.5)).collect();
        (!splits.is_empty() && k + splits.len() <= cap).then(|| ctx.evaluate(with_splits(&cur.seg, &splits)))
    };
    let Some(mate) = cur.mates() else {
        let MatchOutcome::OddParty(party) = &cur.outcome else { return None };
        let splits: Vec<(usize, usize)> = party.iter().filter_map(|&s| split_at(&cur.seg, s, 0.5)).collect();
        if splits.is_empty() || k + splits.len() > cap {
            return global();
        }
        return Some(ctx.evaluate(with_splits(&cur.seg, &splits)));
    };
    if k + 1 > cap {
        return None;
    }
    let shapes = ctx.shapes(&cur.seg.lp);
    let c = &cur.costs;
    let mut candidates: Vec<(usize, usize)> = Vec::new();
    for s in 0..k {
        candidates.extend(split_at(&cur.seg, s, 0.5));
        let Some(j) = mate[s] else { continue };
        for kk in (0..k).filter(|&x| x != s && x != j) {
            let wants = match mate[kk] {
                None => true,
                Some(l) => c[kk][s] < c[kk][l],
            };
            if !wants {
                continue;
            }
            let (lj, lk) = (shapes[j].length, shapes[kk].length);
            if lj + lk <= 0.0 {
                continue;
            }
            candidates.extend(split_at(&cur.seg, s, lj / (lj + lk)));
            candidates.extend(split_at(&cur.seg, s, lk / (lj + lk)));
        }
    }
    candidates.sort_unstable();
    candidates.dedup();
    let evaluated: Vec<Evaluated> = candidates
        .iter()
        .map(|&cand| ctx.evaluate(with_splits(&cur.seg, &[cand])))
        .filter(|e| e.mates().is_some())
        .collect();
    let lowest = |keep: &dyn Fn(&Evaluated) -> bool| {
        evaluated.iter().filter(|e| keep(e)).min_by(|a, b| a.average.total_cmp(&b.average)).cloned()
    };
    let best = lowest(&|e| e.worst <= cur.worst * (1.0 + 1e-12)).or_else(|| lowest(&|_| true));
    // An odd count's average leaves its worst segment out, so it is no
    // yardstick: from an odd count the best single split is taken as is.
    let comparable = cur.len() % 2 == 0;
    match best {
        Some(b) if !comparable || b.average < cur.average => Some(b),
        other => global().or(other),
    }
}

/// The outcome of the refinement loop.
#[derive(Clone, Debug)]
pub struct Refined {
    /// The accepted even segmentation and its matching.
    pub result: Evaluated,
    /// Refinement steps taken (including the rolled-back ones).
    pub iterations: usize,
    /// The odd parties met (segment indices at the time), in order.
    pub odd_parties: Vec<Vec<usize>>,
    /// Per step: segment count, average and worst cost (∞ for an odd party).
    pub history: Vec<(usize, f64, f64)>,
}

/// The outer loop of spec §4 on an initial segmentation. `None` when no even
/// segmentation with a perfect stable matching was reached within the caps.
pub fn refine_loop(ctx: &Context<'_>, initial: SegmentedLoop) -> Option<Refined> {
    let t = vec![None; initial.starts.len()];
    let mut cur = ctx.evaluate(Segmentation { lp: initial, t });
    let mut best: Option<Evaluated> = None;
    let (mut best_cost, mut best_worst) = (f64::INFINITY, f64::INFINITY);
    let mut iterations = 0;
    let mut odd_parties = Vec::new();
    let mut history = vec![(cur.len(), cur.average, cur.worst)];
    loop {
        if cur.is_even_matched() {
            best_cost = cur.average;
            best_worst = cur.worst;
            best = Some(cur.clone());
        }
        if iterations >= ctx.opts.max_iterations {
            break;
        }
        if let MatchOutcome::OddParty(p) = &cur.outcome {
            odd_parties.push(p.clone());
        }
        let Some(next) = refine_step(ctx, &cur) else { break };
        iterations += 1;
        cur = next;
        history.push((cur.len(), cur.average, cur.worst));
        if cur.is_even_matched()
            && (ctx.opts.drop * cur.average > best_cost || best_worst < cur.worst * (1.0 - 1e-12))
        {
            break;
        }
    }
    best.map(|result| Refined { result, iterations, odd_parties, history })
}
