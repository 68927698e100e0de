//! Quasi-structured topology by cavity remeshing (paper §6.2, spec §10), on
//! the quads of one face ([`QuadPatch`]) after the unstructured mesher and
//! the defect removal.
//!
//! - **Singular vertices** (§10.2): each cross-field singularity of index
//!   ±1 flags the nearest face-interior vertex of valence 3 / 5 within
//!   [`MATCH_RADIUS`] × its local edge length (pairs by increasing distance,
//!   each vertex at most once). Every other irregular vertex is
//!   *unnecessary*.
//! - **Cavity growth** (§10.3): from the quads around a seed vertex, quads
//!   are added in breadth-first order; a face-interior vertex of the cavity
//!   boundary with one outside quad (a concave vertex) gets that quad first.
//!   A quad is never added when it would make a singular vertex interior or
//!   concave, leave a concave CAD corner (ideal valence ≥ 3) without an
//!   outside quad or with three cavity quads, or touch a pole. (A concave
//!   corner with more quads than its ideal may have three cavity quads: it
//!   is then a side vertex of the pattern, which gives it two back.) Each time the cavity has absorbed a new
//!   irregular vertex and is a convex disk (corners: boundary vertices with
//!   one cavity quad, or a convex CAD corner fully inside), its side counts
//!   are matched against the target patterns (Eq. 14, [`crate::combinatorics::patterns`]).
//!   A *minimal* cavity is the first that matches, a *maximal* one the last
//!   before [`MAX_MAXIMAL_QUADS`].
//! - **Strategy** (§10.4), repeated while a pass removes irregular vertices:
//!   Step 1 maximal grid (R1) cavities around unnecessary irregular
//!   vertices; Step 2 minimal triangle (T3) / pentagon (P5) cavities around
//!   each singular vertex of valence 3 / 5, one per singularity and pass;
//!   Step 3 = Step 1; Step 4 minimal cavities matching any rectangular
//!   pattern.
//! - **Acceptance**: no new edge doubles an existing one between two cavity
//!   boundary vertices; the irregular vertices of the cavity's closure
//!   (face-interior valence ≠ 4, curve vertices with ≠ 2 quads, corners off
//!   their ideal) strictly decrease; after placing the new vertices by a
//!   harmonic map in (u, v) and smoothing them with the face-interior
//!   vertices of the cavity boundary and of the quads around it (uv
//!   Laplacian, the Winslow / angle-based kernels, untangling), every quad
//!   around is valid, the worst SICN there is at least [`KEEP`] (Steps 1–3)
//!   or [`STEP4_KEEP`] (Step 4) of the old worst, and the average SICN there
//!   dropped by at most [`AVG_SLACK`]. Otherwise the patch is restored
//!   exactly, and that replacement is not tried again until another one is
//!   kept. The untangling, the costliest part, is skipped when the average
//!   after the kernels is already far below that bound (the untangler does
//!   not raise the average, so the replacement would be undone anyway).
//! - Growth keeps the cavity a disk: a quad is added only when it meets the
//!   cavity along one path of its edges, so cavities never wrap around a
//!   hole of the face.
//!
//! Work is counted in units (quads added to cavities, vertices smoothed) and
//! capped per face; nothing depends on the clock or on hash-map order, so
//! the result is deterministic.

mod growth;
mod replace;
mod work;

use geometry::Face;

use crate::core::patch::QuadPatch;
use crate::field::singularities::Singularity;

use growth::Target;
use work::Work;

/// Largest maximal cavity, in quads (the spec's §10.3 default is 2000).
/// 500 leaves every one of the 26 shared models unchanged at the default
/// size; on i01o_m1 at size factor 0.0625 the cavity stage takes 1.6 s
/// instead of 2.6 s for 370 irregular vertices left instead of 352 (of
/// 991), in 235k quads (BENCHMARKS.md, "Smaller maximal cavities").
pub const MAX_MAXIMAL_QUADS: usize = 500;
/// Largest minimal cavity, in quads (spec §10.3 default).
pub const MAX_MINIMAL_QUADS: usize = 500;
/// A singularity flags a vertex within this many local edge lengths (spec ρ = 2).
pub const MATCH_RADIUS: f64 = 2.0;
/// After the passes, a singularity still unmatched flags the nearest
/// remaining vertex of its valence within this many sizes, and the passes
/// run again (n12o_limit_cycle_genus0: the unstructured mesh leaves two of
/// each face's four valence-3 vertices 2.6–2.9 sizes away).
pub const LATE_MATCH_RADIUS: f64 = 3.0;
/// Steps 1–3 keep a replacement whose worst SICN is at least this share of the old worst.
pub const KEEP: f64 = 0.9;
/// Step 4 keeps a replacement whose worst SICN is at least this share of the old worst.
pub const STEP4_KEEP: f64 = 0.8;
/// A replacement may lower the average SICN of the quads around it by this much at most.
pub const AVG_SLACK: f64 = 0.02;

/// Options of [`remesh_cavities`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CavityOptions {
    /// Steps 1–4 of §10.4 to run (Step 3 is Step 1 again).
    pub steps: [bool; 4],
    /// Passes of the four steps at most (a pass that removes no irregular vertex ends earlier).
    pub max_passes: usize,
    /// Work units allowed per face (`None`: [`default_work_cap`] of the face's quads).
    pub max_work: Option<u64>,
}

impl Default for CavityOptions {
    fn default() -> Self {
        CavityOptions {
            steps: [true; 4],
            max_passes: 8,
            max_work: None,
        }
    }
}

/// The default work cap of a face with `quads` quads. Of the bundled
/// models only `wing_surface` reaches it (one face of 12.5k quads, 22 %
/// irregular, no cross-field singularity), where it bounds the stage to a
/// few seconds; the next highest face uses 40 % of its cap.
pub fn default_work_cap(quads: usize) -> u64 {
    500_000 + 1_000 * quads as u64
}

/// What [`remesh_cavities`] did on one face.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CavityReport {
    /// Face-interior irregular vertices before.
    pub irregular_before: usize,
    /// Face-interior irregular vertices after.
    pub irregular_after: usize,
    /// Vertices flagged as singular (matched to cross-field singularities).
    pub singular: usize,
    /// Replacements kept by Steps 1, 2, 3 and 4.
    pub replaced: [usize; 4],
    /// Replacements undone (geometry or quality).
    pub rejected: usize,
    /// Work units spent.
    pub work: u64,
    /// True when the work cap stopped the face early.
    pub capped: bool,
}

impl CavityReport {
    /// Sums two reports (over faces).
    pub fn add(&self, o: &CavityReport) -> CavityReport {
        let mut r = *self;
        r.irregular_before += o.irregular_before;
        r.irregular_after += o.irregular_after;
        r.singular += o.singular;
        for k in 0..4 {
            r.replaced[k] += o.replaced[k];
        }
        r.rejected += o.rejected;
        r.work += o.work;
        r.capped |= o.capped;
        r
    }
}

/// Remeshes cavities of one face's quads (see the module documentation).
/// `singularities` are the face's cross-field singularities (3D positions).
/// Quads stay counter-clockwise; curve and corner nodes never move; replaced
/// quads are dropped and new nodes appended (old interior nodes of a
/// replaced cavity stay in `p.nodes`, unused).
pub fn remesh_cavities(
    face: &Face,
    p: &mut QuadPatch,
    singularities: &[Singularity],
    opts: &CavityOptions,
) -> CavityReport {
    let mut report = CavityReport::default();
    if p.quads.is_empty()
        || p.pos.len() != p.nodes.len()
        || p.quad_tri.len() != p.quads.len()
        || p.quads
            .iter()
            .flatten()
            .any(|&v| v as usize >= p.nodes.len())
    {
        return report;
    }
    let cap = opts
        .max_work
        .unwrap_or_else(|| default_work_cap(p.quads.len()));
    let mut w = Work::new(face, p);
    let mut used = vec![false; singularities.len()];
    report.singular = w.match_singularities(singularities, MATCH_RADIUS, &mut used);
    report.irregular_before = w.inner_irregular();
    let maximal_grid = |w: &mut Work, step: usize, report: &mut CavityReport| {
        w.rect_step(Target::Grid, false, KEEP, step, cap, report)
    };
    let passes = |w: &mut Work, report: &mut CavityReport, max_passes: usize| {
        for _ in 0..max_passes {
            let before = w.all_irregular();
            if opts.steps[0] {
                maximal_grid(w, 0, report);
            }
            if opts.steps[1] {
                w.star_step(cap, report);
            }
            if opts.steps[2] {
                maximal_grid(w, 2, report);
            }
            if opts.steps[3] {
                w.rect_step(Target::Rect, true, STEP4_KEEP, 3, cap, report);
            }
            if w.all_irregular() >= before || report.capped {
                break;
            }
        }
    };
    passes(&mut w, &mut report, opts.max_passes);
    // a singularity whose vertex the unstructured mesh left a little
    // farther away: matched now, among the vertices the passes could not
    // remove, and the passes run again around it
    if !report.capped {
        let late = w.match_singularities(singularities, LATE_MATCH_RADIUS, &mut used);
        if late > 0 {
            // the seeds' roles changed: every seed may be tried again
            w.failed.clear();
            report.singular += late;
            passes(&mut w, &mut report, opts.max_passes);
        }
    }
    report.irregular_after = w.inner_irregular();
    report.work = w.units;
    let alive = std::mem::take(&mut w.alive);
    drop(w);
    crate::topology::defects::drop_dead_quads(p, &alive);
    if report.replaced.iter().sum::<usize>() > 0 {
        crate::smoothing::optimize(face, p, &crate::smoothing::OptimizeOptions::default());
    }
    report
}

#[cfg(test)]
mod tests;
