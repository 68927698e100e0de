//! Curve discretization: every CAD curve is meshed once, and every face that
//! uses it sees the same points, so faces meet with identical nodes.
//!
//! Resolution convention (quasi-structured spec §1.2): a curve gets `n ≥ 1`
//! *coarse* segments at spacing about `2h` (the triangulation works at that
//! spacing) and is stored with `2n + 1` points; the odd-indexed points are the
//! coarse segments' midpoints, which the triangle → quad split uses, so every
//! node lands exactly on the CAD curve and each curve ends up with `2n` mesh
//! edges of length about `h`.
//!
//! Where a curve bends tightly (a small fillet, an airfoil's leading edge) the
//! spacing shrinks so that one coarse segment turns by at most
//! [`MAX_TURN_PER_SEGMENT`], and it grows back to `2h` at rate [`GRADING`]: the
//! points are uniform in ∫ ds / size(s), not in arc length. A bend tighter
//! than a twentieth of the spacing (a trailing edge rounded to a fraction of
//! the quad size) is not resolved: it is a crease at the mesh's scale. A
//! curve still gets a segment per 90° of turn on average (a small circle, 4).
//! Refining a curve (doubling its count) halves every spacing and keeps the
//! grading.

use geometry::vec3::{self, Vec3};
use geometry::{CurveId, Model};

use crate::curves::curve_chords::{
    balance_composite_sides, balance_for_patterns, chord_classes, chord_counts,
};
use crate::curves::count_balance::{
    balance_annuli, balance_band_seams, balance_seam_grids, square_band_seams,
};

/// Largest turning angle of the tangent along one coarse segment (radians).
/// Keeps small circles from being a 1- or 2-segment polygon in (u, v).
pub const MAX_TURN_PER_SEGMENT: f64 = std::f64::consts::FRAC_PI_2;

/// Growth of the coarse spacing per unit of arc length away from a tight bend
/// (0.3: neighbouring segments differ by about 30 %).
pub const GRADING: f64 = 0.3;

/// The smallest coarse spacing curvature may ask for, as a fraction of `2h`.
const MIN_SPACING_FRACTION: f64 = 1e-3;

/// The smallest coarse spacing a bend's curvature may ask for, as a fraction
/// of the spacing the size asks for there. A bend tighter than that (an
/// airfoil's trailing edge rounded to a few hundredths of the quad size) is
/// a crease at the mesh's scale: resolving it would take quads that small
/// along the whole edge. The quads on either side see the surface from
/// their own side ([`geometry::Face::corner_normal`]).
const MIN_BEND_SPACING_FRACTION: f64 = 0.05;

/// Uniform samples a curve's profile starts from.
const SAMPLES: usize = 160;
/// A sample interval whose two halves turn by more than this (radians) is split.
const SAMPLE_TURN: f64 = 0.05;
/// A turn at one sample larger than this after sampling is a kink (C0 point).
const KINK_TURN: f64 = 4.0 * SAMPLE_TURN;
/// Samples of one curve beyond which [`resample_to_sizes`] stops refining.
const MAX_SIZED_SAMPLES: usize = 1 << 18;
/// Bisection passes over the samples, at most.
const SAMPLE_DEPTH: u32 = 30;

/// The discretization of one curve.
#[derive(Clone, Debug)]
pub struct CurveMesh {
    /// Number of coarse segments `n` (the curve has `2n` mesh edges).
    pub coarse: usize,
    /// `2n + 1` curve parameters, increasing from `range.0` to `range.1`.
    pub params: Vec<f64>,
    /// `2n + 1` points: `C(params[i])`; for a degenerate curve, its corner.
    pub points: Vec<Vec3>,
}

impl CurveMesh {
    /// Number of mesh edges on the curve (`2 * coarse`).
    pub fn num_edges(&self) -> usize {
        2 * self.coarse
    }
}

/// A fine polyline of a curve with its cumulative arc length and cumulative
/// "segment budget" ∫ ds / spacing(s).
#[derive(Clone, Debug)]
struct Profile {
    ts: Vec<f64>,
    cum: Vec<f64>,
    budget: Vec<f64>,
}

/// How every curve of a model is to be discretized: its coarse segment count
/// and, for graded curves, where the points go. Built by [`plan_curves`];
/// [`CurvePlan::refine`] doubles a curve's count (with its chord).
#[derive(Clone, Debug)]
pub struct CurvePlan {
    /// Coarse segment count of each curve.
    pub counts: Vec<usize>,
    profiles: Vec<Option<Profile>>,
    /// Chord class of each curve (see [`crate::curves::curve_chords`]).
    chords: Vec<usize>,
    /// Ideal (real) coarse count of each curve: ∫ ds / spacing.
    ideal: Vec<f64>,
}

impl CurvePlan {
    /// Ideal coarse count of curve `c` before rounding and chord averaging.
    pub fn ideal(&self, c: CurveId) -> f64 {
        self.ideal[c.idx()]
    }

    /// Chord class of curve `c`: curves with the same class have the same count.
    pub fn chord(&self, c: CurveId) -> usize {
        self.chords[c.idx()]
    }

    /// Doubles the count of curve `c` and of every curve of its chord (so
    /// opposite sides stay equal); returns the curves changed.
    pub fn refine(&mut self, c: CurveId) -> Vec<CurveId> {
        let root = self.chords[c.idx()];
        let mut changed = Vec::new();
        for (i, &r) in self.chords.iter().enumerate() {
            if r == root {
                self.counts[i] = (self.counts[i] * 2).min(1 << 20);
                changed.push(CurveId(i as u32));
            }
        }
        changed
    }

    /// Refines curve `c` locally, alone (its chord class keeps its counts):
    /// the coarse spacing at a point `x` of the curve becomes at most
    /// `s + GRADING × max(0, |x − p| − r)` for every `(p, r, s)` of `near`,
    /// where the current spacing is larger, and the count grows by the
    /// segments that adds; the spacing elsewhere is kept. Returns whether the
    /// curve changed. A degenerate curve, or one the spots ask nothing of,
    /// is left alone.
    pub fn refine_near(&mut self, model: &Model, c: CurveId, near: &[(Vec3, f64, f64)]) -> bool {
        let i = c.idx();
        let Some(prof) = self.profiles.get(i).and_then(|p| p.as_ref()) else {
            return false;
        };
        let total = prof.budget.last().copied().unwrap_or(0.0);
        if near.is_empty() || prof.ts.len() < 2 || !(total > 0.0) {
            return false;
        }
        let ce = &model.curves[i];
        let target = |x: Vec3| -> f64 {
            near.iter()
                .map(|&(p, r, s)| s + GRADING * (vec3::dist(x, p) - r).max(0.0))
                .fold(f64::INFINITY, f64::min)
        };
        let min_len = min_sample_length(model);
        let mut ts = prof.ts.clone();
        let mut budget = prof.budget.clone();
        let mut pts: Vec<Vec3> = ts.iter().map(|&t| ce.eval(model, t)).collect();
        // samples at least twice as fine as the target spacing, so that
        // ∫ dl / spacing is integrated where the target is small; a new
        // sample takes the budget interpolated in the parameter, as
        // discretize_curve reads it
        for _ in 0..SAMPLE_DEPTH {
            if ts.len() > MAX_SIZED_SAMPLES {
                break;
            }
            let mut changed = false;
            let (mut nts, mut nb, mut npts) = (Vec::new(), Vec::new(), Vec::new());
            for j in 0..ts.len() - 1 {
                nts.push(ts[j]);
                nb.push(budget[j]);
                npts.push(pts[j]);
                let len = vec3::dist(pts[j], pts[j + 1]);
                if len > min_len && len > 0.5 * target(vec3::lerp(pts[j], pts[j + 1], 0.5)) {
                    let tm = 0.5 * (ts[j] + ts[j + 1]);
                    nts.push(tm);
                    nb.push(0.5 * (budget[j] + budget[j + 1]));
                    npts.push(ce.eval(model, tm));
                    changed = true;
                }
            }
            let last = ts.len() - 1;
            nts.push(ts[last]);
            nb.push(budget[last]);
            npts.push(pts[last]);
            (ts, budget, pts) = (nts, nb, npts);
            if !changed {
                break;
            }
        }
        // segments per budget unit now: kept, so the spacing away from the
        // spots stays as it is
        let per_unit = self.counts[i] as f64 / total;
        let mut nb = vec![0.0; ts.len()];
        for j in 0..ts.len() - 1 {
            let inc = budget[j + 1] - budget[j];
            let len = vec3::dist(pts[j], pts[j + 1]);
            let want = len / (per_unit * target(vec3::lerp(pts[j], pts[j + 1], 0.5)));
            nb[j + 1] = nb[j] + if want.is_finite() { inc.max(want) } else { inc };
        }
        let new_total = nb.last().copied().unwrap_or(0.0);
        if !(new_total > total * (1.0 + 1e-9)) {
            return false;
        }
        let count = ((per_unit * new_total).round() as usize).clamp(self.counts[i], 1 << 20);
        let cum = {
            let mut cum = vec![0.0; pts.len()];
            for j in 0..pts.len() - 1 {
                cum[j + 1] = cum[j] + vec3::dist(pts[j], pts[j + 1]);
            }
            cum
        };
        self.counts[i] = count;
        self.ideal[i] = new_total;
        self.profiles[i] = Some(Profile {
            ts,
            cum,
            budget: nb,
        });
        true
    }
}

/// The shortest sample interval [`sample`] still splits: 1e-9 of the
/// model's diagonal (computed once per call site: the bounding box
/// evaluates every face, and was 3 % of a whole run when taken per curve).
fn min_sample_length(model: &Model) -> f64 {
    1e-9 * model.diagonal().max(1e-300)
}

/// Samples the curve: uniform in its parameter, then bisected where the
/// polyline turns by more than [`SAMPLE_TURN`] at a sample or inside an
/// interval, so that features far smaller than the sample spacing (a rounded
/// trailing edge) are seen; intervals shorter than `min_len` are not split
/// ([`min_sample_length`]).
fn sample(model: &Model, c: CurveId, min_len: f64) -> (Vec<f64>, Vec<Vec3>) {
    let ce = &model.curves[c.idx()];
    let (t0, t1) = ce.range;
    // a polyline is sampled at its vertices, where all of its turning
    // happens (a vertex's turn over its segments is the curvature of the
    // curve it stands for): no bisection toward a vertex's kink
    if let Some(mut bp) = ce.geom.as_ref().and_then(|g| g.breakpoints()) {
        bp.retain(|t| t.is_finite() && *t > t0 && *t < t1);
        let mut ts = vec![t0];
        for t in bp.into_iter().chain([t1]) {
            if t > *ts.last().unwrap_or(&t0) {
                ts.push(t);
            }
        }
        let pts = ts.iter().map(|&t| ce.eval(model, t)).collect();
        return (ts, pts);
    }
    let mut ts: Vec<f64> = (0..=SAMPLES)
        .map(|i| t0 + (t1 - t0) * i as f64 / SAMPLES as f64)
        .collect();
    let mut pts: Vec<Vec3> = ts.iter().map(|&t| ce.eval(model, t)).collect();
    let turn = |a: Vec3, b: Vec3, c: Vec3| match (
        vec3::normalize(vec3::sub(b, a)),
        vec3::normalize(vec3::sub(c, b)),
    ) {
        (Some(d), Some(e)) => vec3::dot(d, e).clamp(-1.0, 1.0).acos(),
        _ => 0.0,
    };
    for _ in 0..SAMPLE_DEPTH {
        let n = pts.len();
        let turn_at = |i: usize| {
            if i == 0 || i + 1 >= n {
                0.0
            } else {
                turn(pts[i - 1], pts[i], pts[i + 1])
            }
        };
        let mut nts = Vec::with_capacity(n);
        let mut npts = Vec::with_capacity(n);
        let mut changed = false;
        for j in 0..n - 1 {
            nts.push(ts[j]);
            npts.push(pts[j]);
            if vec3::dist(pts[j], pts[j + 1]) <= min_len {
                continue;
            }
            let tm = 0.5 * (ts[j] + ts[j + 1]);
            let pm = ce.eval(model, tm);
            if turn_at(j).max(turn_at(j + 1)) > SAMPLE_TURN
                || turn(pts[j], pm, pts[j + 1]) > SAMPLE_TURN
            {
                nts.push(tm);
                npts.push(pm);
                changed = true;
            }
        }
        nts.push(ts[n - 1]);
        npts.push(pts[n - 1]);
        ts = nts;
        pts = npts;
        if !changed {
            break;
        }
    }
    (ts, pts)
}

/// Bisects the sample intervals longer than the size at their middle, so
/// that ∫ dl / s is integrated finely wherever the size map is small.
/// Sizes below `floor` count as `floor`; at most [`MAX_SIZED_SAMPLES`] samples.
fn resample_to_sizes(
    model: &Model,
    c: CurveId,
    mut ts: Vec<f64>,
    mut pts: Vec<Vec3>,
    sizes: &[[f64; 2]],
    floor: f64,
) -> (Vec<f64>, Vec<Vec3>) {
    let ce = &model.curves[c.idx()];
    for _ in 0..SAMPLE_DEPTH {
        if ts.len() > MAX_SIZED_SAMPLES {
            break;
        }
        let mut nts = Vec::with_capacity(ts.len());
        let mut npts = Vec::with_capacity(ts.len());
        let mut changed = false;
        for j in 0..ts.len() - 1 {
            nts.push(ts[j]);
            npts.push(pts[j]);
            let tm = 0.5 * (ts[j] + ts[j + 1]);
            if vec3::dist(pts[j], pts[j + 1]) > size_at(sizes, tm).max(floor) {
                nts.push(tm);
                npts.push(ce.eval(model, tm));
                changed = true;
            }
        }
        nts.push(ts[ts.len() - 1]);
        npts.push(pts[pts.len() - 1]);
        ts = nts;
        pts = npts;
        if !changed {
            break;
        }
    }
    (ts, pts)
}

/// Linear interpolation in a `(parameter, size)` profile sorted by parameter
/// (constant beyond its ends).
fn size_at(profile: &[[f64; 2]], t: f64) -> f64 {
    let k = profile.partition_point(|p| p[0] < t);
    if k == 0 {
        return profile[0][1];
    }
    if k == profile.len() {
        return profile[k - 1][1];
    }
    let ([ta, sa], [tb, sb]) = (profile[k - 1], profile[k]);
    if tb > ta {
        sa + (sb - sa) * (t - ta) / (tb - ta)
    } else {
        sa.min(sb)
    }
}

/// Profile of curve `c` for final size `h`: spacing `min(2s, radius × MAX_TURN)`
/// (not below `MIN_SPACING_FRACTION × 2h`, and the bend's term not below
/// `MIN_BEND_SPACING_FRACTION × 2s`), graded at rate [`GRADING`]
/// (around the closure point too for a closed curve). `s` is the size map
/// along the curve (`(parameter, size)` pairs) when given, else `h`.
fn profile(
    model: &Model,
    c: CurveId,
    h: f64,
    sizes: Option<&[[f64; 2]]>,
    reach: [f64; 2],
    min_len: f64,
) -> Profile {
    let ce = &model.curves[c.idx()];
    let (mut ts, mut pts) = sample(model, c, min_len);
    if let Some(p) = sizes.filter(|p| !p.is_empty()) {
        (ts, pts) = resample_to_sizes(model, c, ts, pts, p, MIN_SPACING_FRACTION * h);
    }
    let ns = pts.len() - 1;
    let len: Vec<f64> = (0..ns)
        .map(|j| {
            let l = vec3::dist(pts[j], pts[j + 1]);
            if l.is_finite() {
                l
            } else {
                0.0
            }
        })
        .collect();
    let dirs: Vec<Option<Vec3>> = (0..ns)
        .map(|j| vec3::normalize(vec3::sub(pts[j + 1], pts[j])))
        .collect();
    let closed = ce.start == ce.end && ns > 1;
    // turn of the tangent at each sample point, with the mean length of its
    // two intervals (0 at the ends of an open curve)
    let bend_at = |i: usize| -> (f64, f64) {
        let (a, b) = if i == 0 || i == ns {
            if !closed {
                return (0.0, 0.0);
            }
            (ns - 1, 0)
        } else {
            (i - 1, i)
        };
        match (dirs[a], dirs[b]) {
            (Some(da), Some(db)) => {
                let l = 0.5 * (len[a] + len[b]);
                let turn = vec3::dot(da, db).clamp(-1.0, 1.0).acos();
                // a turn the sampling could not spread out is a kink, not a bend:
                // no spacing resolves it, so it asks for none
                if l > 0.0 && turn <= KINK_TURN {
                    (turn, l)
                } else {
                    (0.0, 0.0)
                }
            }
            _ => (0.0, 0.0),
        }
    };
    // curvature at each sample point (turn over the mean length of its two intervals)
    let kappa_at = |i: usize| -> f64 {
        let (turn, l) = bend_at(i);
        if l > 0.0 {
            turn / l
        } else {
            0.0
        }
    };
    let smax = 2.0 * h;
    let smin = MIN_SPACING_FRACTION * smax;
    let mut sp: Vec<f64> = (0..ns)
        .map(|j| {
            let base = match sizes {
                Some(p) if !p.is_empty() => (2.0 * size_at(p, 0.5 * (ts[j] + ts[j + 1]))).max(smin),
                _ => smax,
            };
            let k = kappa_at(j).max(kappa_at(j + 1));
            if k > 0.0 {
                (MAX_TURN_PER_SEGMENT / k).clamp((MIN_BEND_SPACING_FRACTION * base).max(smin), base)
            } else {
                base
            }
        })
        .collect();
    // grading: spacing(j) ≤ spacing(i) + GRADING × distance; two laps for a closed curve
    let laps = if closed { 2 } else { 1 };
    for _ in 0..laps {
        for j in 1..ns {
            sp[j] = sp[j].min(sp[j - 1] + GRADING * 0.5 * (len[j - 1] + len[j]));
        }
        if closed {
            sp[0] = sp[0].min(sp[ns - 1] + GRADING * 0.5 * (len[ns - 1] + len[0]));
        }
    }
    for _ in 0..laps {
        for j in (0..ns.saturating_sub(1)).rev() {
            sp[j] = sp[j].min(sp[j + 1] + GRADING * 0.5 * (len[j] + len[j + 1]));
        }
        if closed {
            sp[ns - 1] = sp[ns - 1].min(sp[0] + GRADING * 0.5 * (len[ns - 1] + len[0]));
        }
    }
    let mut cum = vec![0.0; ns + 1];
    for j in 0..ns {
        cum[j + 1] = cum[j] + len[j];
    }
    // at a cusp end the first coarse segment spans at least twice the reach,
    // so that the first node (its midpoint) keeps that distance (crate::curves::cusps)
    for j in 0..ns {
        let mid = 0.5 * (cum[j] + cum[j + 1]);
        if mid < reach[0] {
            sp[j] = sp[j].max(2.0 * reach[0]);
        }
        if cum[ns] - mid < reach[1] {
            sp[j] = sp[j].max(2.0 * reach[1]);
        }
    }
    let mut budget = vec![0.0; ns + 1];
    for j in 0..ns {
        budget[j + 1] = budget[j] + len[j] / sp[j];
    }
    // on average a coarse segment turns by at most MAX_TURN_PER_SEGMENT: a
    // curve whose bends are all below the spacing floor (a circle far smaller
    // than the quads) still gets its 4 segments per turn
    let points = if closed { 0..ns } else { 1..ns };
    let total_turn: f64 = points.map(|i| bend_at(i).0).sum();
    let (need, have) = (total_turn / MAX_TURN_PER_SEGMENT, budget[ns]);
    if have > 0.0 && need > have {
        for b in &mut budget {
            *b *= need / have;
        }
    }
    Profile { ts, cum, budget }
}

/// Plans the curves for target final edge length `h`: each curve's ideal
/// coarse count is its segment budget ∫ ds / spacing (about `length / 2h` on
/// a gently curved curve); counts are the rounded chord means
/// ([`crate::curves::curve_chords`]), at least 1, at least 3 for a closed curve, and
/// enough that every face loop has at least 3 coarse segments.
pub fn plan_curves(model: &Model, h: f64) -> CurvePlan {
    plan_curves_sized(model, h, &[])
}

/// Plans the curves against a size map (quantization, paper §4.3): curve `c`
/// is spaced by `sizes[c]`, its size profile as `(parameter, size)` pairs
/// sorted by parameter ([`crate::field::size_map::SizeMap::curve_sizes`]); its ideal
/// coarse count is ∫ dl / 2s (the §1.2 convention: coarse segments of `2s`),
/// and points are placed uniformly in that integral (Eq. 11). A curve with no
/// profile (or beyond `sizes`) uses the uniform size `h`. Rounding, chords
/// and the minimum counts are as in [`plan_curves`].
pub fn plan_curves_sized(model: &Model, h: f64, sizes: &[Option<Vec<[f64; 2]>>]) -> CurvePlan {
    plan_curves_with(model, h, sizes, &[])
}

/// [`plan_curves_sized`] for the final mesh of the quasi-structured method:
/// also keeps the first node of a curve at a cusp corner far enough from it
/// that the quads beyond the corner quad are not slivers
/// ([`crate::curves::cusps::cusp_reaches`]), but no further than `h`: the curve is
/// shared with another face, where a longer first edge would do harm.
pub fn plan_final_curves(model: &Model, h: f64, sizes: &[Option<Vec<[f64; 2]>>]) -> CurvePlan {
    let reaches: Vec<[f64; 2]> = crate::curves::cusps::cusp_reaches(model)
        .into_iter()
        .map(|r| r.map(|x| x.min(h)))
        .collect();
    plan_curves_with(model, h, sizes, &reaches)
}

/// [`plan_curves_sized`] with `reaches[c]`: the distances from curve `c`'s
/// start and end its first nodes keep (none where `reaches` is short).
fn plan_curves_with(
    model: &Model,
    h: f64,
    sizes: &[Option<Vec<[f64; 2]>>],
    reaches: &[[f64; 2]],
) -> CurvePlan {
    use rayon::prelude::*;
    let min_len = min_sample_length(model);
    let profiles: Vec<Option<Profile>> = (0..model.curves.len())
        .into_par_iter()
        .map(|i| {
            let own = sizes.get(i).and_then(|s| s.as_deref());
            let reach = reaches.get(i).copied().unwrap_or([0.0; 2]);
            if model.curves[i].degenerate {
                None
            } else {
                Some(profile(model, CurveId(i as u32), h, own, reach, min_len))
            }
        })
        .collect();
    let mut ideal: Vec<f64> = profiles
        .iter()
        .map(|p| {
            p.as_ref()
                .map_or(1.0, |p| p.budget.last().copied().unwrap_or(0.0))
        })
        .collect();
    let lengths: Vec<f64> = profiles
        .iter()
        .map(|p| p.as_ref().map_or(0.0, |p| *p.cum.last().unwrap_or(&0.0)))
        .collect();
    balance_seam_grids(model, &mut ideal);
    balance_band_seams(model, &mut ideal, &lengths);
    balance_annuli(model, &mut ideal);
    let chords = chord_classes(model, &ideal);
    let mut counts = chord_counts(&chords, &ideal);
    let mut plan_chords = vec![Vec::new(); model.curves.len()];
    for (c, &root) in chords.iter().enumerate() {
        plan_chords[root].push(c);
    }
    let members = |c: usize| plan_chords[chords[c]].clone();
    // a side of several curves facing one curve: equal totals
    let raised = balance_composite_sides(model, &ideal, &mut counts, &members);
    enforce_minimum_counts(model, &mut counts, &members, &lengths);
    // the minimums may have raised a curve of a composite side: balance
    // again (the minimums then hold unless a balance undid one)
    let raised_again = balance_composite_sides(model, &ideal, &mut counts, &members);
    let raised: Vec<bool> = raised
        .iter()
        .zip(&raised_again)
        .map(|(a, b)| *a || *b)
        .collect();
    enforce_minimum_counts(model, &mut counts, &members, &lengths);
    // counts nudged so that more faces fit a pattern (§6.1.2)
    let min_count = |c: usize| {
        let ce = &model.curves[c];
        if ce.start == ce.end {
            3
        } else {
            1
        }
    };
    balance_for_patterns(model, &ideal, &mut counts, &members, &min_count);
    square_band_seams(model, &mut counts, &members, &lengths, &raised);
    enforce_minimum_counts(model, &mut counts, &members, &lengths);
    CurvePlan {
        counts,
        profiles,
        chords,
        ideal,
    }
}

/// The smallest counts the meshers need, raised chord by chord (`members`):
/// at least 3 on a closed curve, an even count on the seam of a full sphere
/// (meshed as a cube, [`crate::direct::sphere_face`]; its seam bounds no other face),
/// and at least 3 coarse segments on every face loop (the use with the
/// longest coarse segments, of length `lengths[c] / counts[c]`, is refined
/// first; the first on ties).
fn enforce_minimum_counts(
    model: &Model,
    counts: &mut [usize],
    members: &impl Fn(usize) -> Vec<usize>,
    lengths: &[f64],
) {
    for (i, ce) in model.curves.iter().enumerate() {
        if ce.start == ce.end && !ce.degenerate && counts[i] < 3 {
            for j in members(i) {
                counts[j] = counts[j].max(3);
            }
        }
    }
    let curve_faces = model.curve_faces();
    for f in 0..model.faces.len() {
        let fid = geometry::FaceId(f as u32);
        if let Some((s0, _)) = crate::core::queries::full_sphere_seam(model, fid) {
            let seam = model.faces[f].loops[0].uses[s0].curve.idx();
            if counts[seam] % 2 == 1 && curve_faces[seam].as_slice() == [fid] {
                for j in members(seam) {
                    counts[j] += 1;
                }
            }
        }
    }
    for f in &model.faces {
        for l in &f.loops {
            loop {
                let total: usize = l.uses.iter().map(|u| counts[u.curve.idx()]).sum();
                if total >= 3 || l.uses.is_empty() {
                    break;
                }
                let mut best = 0;
                let mut best_len = f64::NEG_INFINITY;
                for (k, u) in l.uses.iter().enumerate() {
                    let seg = lengths[u.curve.idx()] / counts[u.curve.idx()] as f64;
                    if seg > best_len {
                        best_len = seg;
                        best = k;
                    }
                }
                for j in members(l.uses[best].curve.idx()) {
                    counts[j] += 1;
                }
            }
        }
    }
}

/// Discretizes curve `c` with `plan.counts[c]` coarse segments: `2n + 1`
/// points uniform in the curve's segment budget (uniform in arc length where
/// the curve is gently curved).
pub fn discretize_curve(model: &Model, plan: &CurvePlan, c: CurveId) -> CurveMesh {
    let ce = &model.curves[c.idx()];
    let n = plan.counts[c.idx()].max(1);
    let m = 2 * n;
    let (t0, t1) = ce.range;
    let mut params = Vec::with_capacity(m + 1);
    let prof = plan.profiles[c.idx()].as_ref();
    let total = prof.map_or(0.0, |p| *p.budget.last().unwrap_or(&0.0));
    for i in 0..=m {
        let s = i as f64 / m as f64;
        let t = match prof {
            Some(p) if total > 0.0 && i > 0 && i < m => {
                let target = s * total;
                // first sample with budget >= target
                let k = p
                    .budget
                    .partition_point(|&x| x < target)
                    .clamp(1, p.budget.len() - 1);
                let (a, b) = (p.budget[k - 1], p.budget[k]);
                let w = if b > a { (target - a) / (b - a) } else { 0.0 };
                p.ts[k - 1] + w * (p.ts[k] - p.ts[k - 1])
            }
            _ => t0 + s * (t1 - t0),
        };
        params.push(t);
    }
    params[0] = t0;
    params[m] = t1;
    let points = params
        .iter()
        .enumerate()
        .map(|(i, &t)| {
            if ce.degenerate || i == 0 {
                model.corners[ce.start.idx()].point
            } else if i == m {
                model.corners[ce.end.idx()].point
            } else {
                ce.eval(model, t)
            }
        })
        .collect();
    CurveMesh {
        coarse: n,
        params,
        points,
    }
}

/// Discretizes every curve as planned (in parallel; the result does not
/// depend on the thread count).
pub fn discretize_all(model: &Model, plan: &CurvePlan) -> Vec<CurveMesh> {
    use rayon::prelude::*;
    (0..model.curves.len())
        .into_par_iter()
        .map(|i| discretize_curve(model, plan, CurveId(i as u32)))
        .collect()
}

/// The faces `faces` ordered for parallel meshing: largest estimated work
/// first (the square of the number of boundary mesh edges, about the number
/// of elements of a compact face), ties by face number. Handing the big faces
/// out first keeps a thread from being left with one large face at the end
/// while the others idle (longest-processing-time-first scheduling).
pub fn largest_faces_first(model: &Model, cms: &[CurveMesh], faces: &mut [usize]) {
    let work = |f: usize| -> usize {
        let edges: usize = model.faces[f]
            .curve_uses()
            .map(|u| cms.get(u.curve.idx()).map_or(0, |c| c.params.len() - 1))
            .sum();
        edges * edges
    };
    faces.sort_by_key(|&f| (std::cmp::Reverse(work(f)), f));
}
#[cfg(test)]
mod tests {
    use super::*;
    use geometry::primitives;

    #[test]
    fn counts_follow_size_and_closure() {
        let m = primitives::square(4.0);
        let c = plan_curves(&m, 0.5).counts;
        assert_eq!(c, vec![4; 4]);
        let cyl = primitives::cylinder(1.0, 3.0);
        let c = plan_curves(&cyl, 10.0).counts;
        // closed circles: at least 3, and 4 by turning angle; the seam line
        // 1 by the size, then 2 so that the band's cells are square:
        // round(3 / (2π / 4)) = round(1.91) (`square_band_seams`)
        assert_eq!(c, vec![4, 4, 2]);
        let s = primitives::sphere(1.0);
        let c = plan_curves(&s, 0.1).counts;
        assert_eq!(c[0], 1);
        assert_eq!(c[2], 1);
        assert!(c[1] >= 15);
    }

    /// Local refinement (the driver's answer to inverted quads in a neck): a
    /// spot in the middle of the bottom side of a 4 × 4 square (coarse
    /// spacing 0.2) asks for 0.05 there, graded at 0.3; the extra budget is
    /// 2 ∫₀^½ (1 / (0.05 + 0.3 x) − 1 / 0.2) dx = 2 (ln 4 / 0.3 − 2.5) = 4.24,
    /// so 20 coarse segments become 24: edges of 0.025 at the spot, 0.1
    /// beyond 1.5 from it. The top side (same chord class, 4 away) is left
    /// alone.
    #[test]
    fn refine_near_refines_around_the_spot_only() {
        let m = primitives::square(4.0);
        let mut plan = plan_curves(&m, 0.1);
        assert_eq!(plan.counts, vec![20; 4]);
        let (bottom, top) = (CurveId(0), CurveId(2));
        assert_eq!(plan.chord(bottom), plan.chord(top));
        let spot = [(([2.0, 0.0, 0.0]), 0.0, 0.05)];
        assert!(plan.refine_near(&m, bottom, &spot));
        assert!(!plan.refine_near(&m, top, &spot));
        assert_eq!(plan.counts, vec![24, 20, 20, 20]);
        let cm = discretize_curve(&m, &plan, bottom);
        assert_eq!(cm.points.len(), 49);
        let (mut near, mut far) = (0, 0);
        for w in cm.points.windows(2) {
            let len = vec3::dist(w[0], w[1]);
            let from_spot = (0.5 * (w[0][0] + w[1][0]) - 2.0).abs();
            if from_spot < 0.02 {
                near += 1;
                assert!((len - 0.025).abs() < 0.003, "edge {len} at the spot");
            } else if from_spot > 1.5 {
                far += 1;
                assert!((len - 0.1).abs() < 0.003, "edge {len} at {from_spot}");
            }
        }
        assert!(near >= 1 && far >= 8, "{near} edges at the spot, {far} far");
        let untouched = discretize_curve(&m, &plan, top);
        assert_eq!(untouched.points.len(), 41);
    }

    #[test]
    fn points_are_uniform_in_arc_length_and_on_the_curve() {
        let m = primitives::cylinder(2.0, 1.0);
        let mut plan = plan_curves(&m, 1.0);
        plan.counts[0] = 5;
        let cm = discretize_curve(&m, &plan, CurveId(0));
        assert_eq!(cm.params.len(), 11);
        assert_eq!(cm.points.len(), 11);
        let target = 2.0 * std::f64::consts::PI * 2.0 / 10.0;
        for i in 1..cm.points.len() {
            let arc = 2.0 * (cm.params[i] - cm.params[i - 1]);
            assert!(
                (arc - target).abs() < 1e-3 * target,
                "arc {arc} vs {target}"
            );
        }
        assert_eq!(cm.points[0], m.corners[0].point);
        assert_eq!(cm.points[10], m.corners[0].point);
        let s = primitives::sphere(1.0);
        let pole = discretize_curve(&s, &plan_curves(&s, 1.0), CurveId(0));
        assert!(pole.points.iter().all(|p| *p == s.corners[0].point));
    }

    /// A circle of radius 1 given as a 64-segment polyline that says so
    /// (`Curve::breakpoints`): sampled at its vertices, each 5.6° turn is a
    /// bend spread over its segments, so the count follows the size (about
    /// 2π / 2h), not thousands of points piled at the vertices.
    #[test]
    fn a_polyline_is_sampled_at_its_vertices() {
        use geometry::{Corner, CurveEntity};
        use std::sync::Arc;
        #[derive(Debug)]
        struct Polygon(Vec<Vec3>);
        impl geometry::Curve for Polygon {
            fn eval(&self, t: f64) -> Vec3 {
                let n = self.0.len() - 1;
                let x = t.clamp(0.0, n as f64);
                let i = (x.floor() as usize).min(n - 1);
                vec3::lerp(self.0[i], self.0[i + 1], x - i as f64)
            }
            fn deriv(&self, t: f64) -> Vec3 {
                let n = self.0.len() - 1;
                let i = (t.clamp(0.0, n as f64).floor() as usize).min(n - 1);
                vec3::sub(self.0[i + 1], self.0[i])
            }
            fn range(&self) -> (f64, f64) {
                (0.0, (self.0.len() - 1) as f64)
            }
            fn project(&self, _p: Vec3, _hint: Option<f64>) -> Option<(f64, Vec3)> {
                None
            }
            fn breakpoints(&self) -> Option<Vec<f64>> {
                Some((0..self.0.len()).map(|i| i as f64).collect())
            }
        }
        let pts: Vec<Vec3> = (0..=64)
            .map(|i| {
                let a = std::f64::consts::TAU * i as f64 / 64.0;
                [a.cos(), a.sin(), 0.0]
            })
            .collect();
        let model = Model {
            corners: vec![Corner { point: pts[0] }],
            curves: vec![CurveEntity {
                geom: Some(Arc::new(Polygon(pts))),
                range: (0.0, 64.0),
                start: geometry::CornerId(0),
                end: geometry::CornerId(0),
                degenerate: false,
            }],
            faces: vec![],
        };
        for (h, want) in [(0.5, 6..=7), (0.1, 31..=32)] {
            let n = plan_curves(&model, h).counts[0];
            assert!(want.contains(&n), "h = {h}: {n} coarse segments");
        }
        // a radius far below the size: at most 90° per coarse segment
        assert_eq!(plan_curves(&model, 50.0).counts[0], 4);
    }

    /// A closed ellipse with semi-axes 5 and `b` (tip radius `b² / 5`), closed
    /// at one tip, as one curve.
    fn ellipse_model(b: f64) -> Model {
        use geometry::{Corner, CurveEntity};
        use std::sync::Arc;
        #[derive(Debug)]
        struct Ellipse(f64);
        impl geometry::Curve for Ellipse {
            fn eval(&self, t: f64) -> Vec3 {
                [5.0 * t.cos(), self.0 * t.sin(), 0.0]
            }
            fn deriv(&self, t: f64) -> Vec3 {
                [-5.0 * t.sin(), self.0 * t.cos(), 0.0]
            }
            fn range(&self) -> (f64, f64) {
                (0.0, std::f64::consts::TAU)
            }
            fn project(&self, _p: Vec3, _hint: Option<f64>) -> Option<(f64, Vec3)> {
                None
            }
        }
        Model {
            corners: vec![Corner {
                point: [5.0, 0.0, 0.0],
            }],
            curves: vec![CurveEntity {
                geom: Some(Arc::new(Ellipse(b))),
                range: (0.0, std::f64::consts::TAU),
                start: geometry::CornerId(0),
                end: geometry::CornerId(0),
                degenerate: false,
            }],
            faces: vec![],
        }
    }

    /// Lengths of the coarse segments of curve 0 of `model` planned at `h`,
    /// and its count.
    fn coarse_segments(model: &Model, h: f64) -> (Vec<f64>, usize) {
        let plan = plan_curves(model, h);
        let cm = discretize_curve(model, &plan, CurveId(0));
        // coarse segments: points 0, 2, 4, ...
        let coarse = cm
            .points
            .iter()
            .step_by(2)
            .collect::<Vec<_>>()
            .windows(2)
            .map(|w| vec3::dist(*w[0], *w[1]))
            .collect();
        (coarse, plan.counts[0])
    }

    /// A thin ellipse (semi-axes 5 and 0.5, so a tip radius of 0.05, a tenth
    /// of the size): the spacing shrinks at the tips (each coarse segment
    /// turns ≤ 90°) and grows back by a bounded ratio per segment, across the
    /// closure point too.
    #[test]
    fn spacing_shrinks_at_a_tight_bend_and_grades_back() {
        let h = 0.5;
        let (coarse, count) = coarse_segments(&ellipse_model(0.5), h);
        let shortest = coarse.iter().cloned().fold(f64::INFINITY, f64::min);
        let longest = coarse.iter().cloned().fold(0.0, f64::max);
        // the tips (radius 0.05) ask for coarse spacing about 0.05 × π/2
        assert!(shortest < 0.1, "shortest coarse segment {shortest}");
        assert!(
            longest <= 2.0 * h * 1.05,
            "longest coarse segment {longest}"
        );
        // neighbours (cyclically) differ by a bounded ratio
        let n = coarse.len();
        for i in 0..n {
            let (a, b) = (coarse[i], coarse[(i + 1) % n]);
            assert!(a.max(b) / a.min(b) < 1.6, "segments {i}: {a} then {b}");
        }
        // a uniform split would need ~20 / 1 segments; grading adds a few dozen, not thousands
        assert!(count > 20 && count < 80, "count {count}");
    }

    /// A tip radius of 0.0005 (a thousandth of the size) is a crease at the
    /// mesh's scale: no coarse segment is shorter than the bend floor
    /// (a twentieth of the spacing `2h`), and the count stays far below what
    /// resolving the tips would take.
    #[test]
    fn a_bend_far_below_the_size_is_not_resolved() {
        let h = 0.5;
        let (coarse, count) = coarse_segments(&ellipse_model(0.05), h);
        let shortest = coarse.iter().cloned().fold(f64::INFINITY, f64::min);
        assert!(
            shortest >= 0.95 * MIN_BEND_SPACING_FRACTION * 2.0 * h,
            "shortest coarse segment {shortest}"
        );
        // grading back from the floor at rate 0.3 adds about 4 × ln(20) / 0.3
        // ≈ 40 to the ~20 of a uniform split; resolving the tips (spacing
        // 0.0008) would add about 4 × ln(1250) / 0.3 ≈ 95
        assert!((20..70).contains(&count), "count {count}");
    }
}
