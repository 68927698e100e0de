//! `quadrille spline` for the shells that need no interior cone (issue 31,
//! paper ricci-flow-iga-reconstruction): a topological disk whose boundary
//! corner indices sum to 4, or an annulus (two loops, χ = 0) with smooth
//! loops. Boundary corners are the only cones (K̄ = I·π/2, 0 elsewhere).
//! A disk: the Ricci flow flattens it to an orthogonal polygon ψ, the
//! separatrices of its reflex corners cut ψ into rectangles (`layout`). An
//! annulus: the flat metric is a straight cylinder, the loop cut's two sides
//! differ by a translation, and ψ is one rectangle closing along the cut
//! (`layout::annulus_layout`, spec §8 footnote 3). Each rectangle becomes an
//! untrimmed bicubic B-spline patch: arcs fitted once (shared sides
//! bit-identical; an annulus's seam is one arc used as the patch's left and
//! right side), interiors by the exact Coons patch of §9.4 or fitted to the
//! shell (ours).
//!
//! Not built yet: splines on a traced layout with cones (S9 across the
//! cuts' charts), so a shell with more loops, an annulus with boundary
//! corners, Σ I ≠ 4χ over its corners, interior cones (S2, `cones`: given
//! through [`SplineOptions::cones`], run through the flow, cut, immersion,
//! layout energy and separatrix tracing by [`cone_core`] and
//! `refuse_unless_corner_cones`, then refused) or whose ψ is not orthogonal
//! is refused with one error line.

use std::time::Instant;

use spline::{jacobian_check, Multipatch, SplineError};
use thiserror::Error;

use crate::cut::{cut_to_disk, CutError, CutMesh};
use crate::immersion::{immerse, Immersion, ImmersionError};
use crate::layout::{
    annulus_layout, orthogonal_boundary, trace_layout, Layout, LayoutError, PsiLocator,
};
use crate::ricci::{boundary_corner_cones, ricci_flow, RicciError, RicciOptions};
use crate::shell::{Shell, ShellError, ShellTopology};

mod cones;
mod fit;
pub use cones::{
    cone_core, layout_energy, refuse_unless_corner_cones, ConeChoice, ConeCore, CoreTimes,
    EnergySummary,
};
pub use fit::{Interior, Segments, SEGMENT_CHOICES};

/// ψ's boundary runs must be straight and axis-aligned within this share of
/// ψ's diagonal (issue 31: 1e-6 of the size).
pub const ORTHOGONAL_TOLERANCE: f64 = 1e-6;

/// Default `--tolerance`: this share of the shell's diagonal (0.1 %).
pub const DEFAULT_TOLERANCE_SHARE: f64 = 1e-3;

/// Options of [`splines_from_shell`].
#[derive(Clone, Debug, PartialEq)]
pub struct SplineOptions {
    /// Spans per arc, or the smallest of [`SEGMENT_CHOICES`] meeting the tolerance.
    pub segments: Segments,
    /// Max distance of the shell's vertices to the patches (model units);
    /// `None`: [`DEFAULT_TOLERANCE_SHARE`] of the shell's diagonal.
    pub tolerance: Option<f64>,
    /// Boehm refinement: each span split into this many (1: none).
    pub refine: usize,
    /// How patch interiors are made.
    pub interior: Interior,
    /// The cones: boundary corners only, or a given set (refused while it
    /// has interior cones: the layout energy is not built).
    pub cones: ConeChoice,
}

impl Default for SplineOptions {
    fn default() -> Self {
        SplineOptions {
            segments: Segments::Auto,
            tolerance: None,
            refine: 1,
            interior: Interior::Fit,
            cones: ConeChoice::CornersOnly,
        }
    }
}

/// Wall times of the stages (seconds).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SplineTimes {
    /// Shell check and corner cones.
    pub shell: f64,
    /// Ricci flow.
    pub ricci: f64,
    /// Cut graph and cut mesh Ω.
    pub cut: f64,
    /// Immersion ψ_R.
    pub immersion: f64,
    /// Boundary check and tracing.
    pub layout: f64,
    /// Arc fits, patches, distances, refinement and the Jacobian check.
    pub splines: f64,
}

impl SplineTimes {
    /// The sum of the stages.
    pub fn total(&self) -> f64 {
        self.shell + self.ricci + self.cut + self.immersion + self.layout + self.splines
    }
}

/// What [`splines_from_shell`] did, with the figures of the report.
#[derive(Clone, Debug, PartialEq)]
pub struct SplineReport {
    /// Shell triangles and vertices.
    pub triangles: usize,
    /// Shell vertices.
    pub vertices: usize,
    /// Boundary corners (cones), and how many of them are reflex (I = −1).
    pub corners: usize,
    /// Reflex corners.
    pub reflex_corners: usize,
    /// Ricci Newton iterations and final max |K̄ − K|.
    pub ricci_iterations: usize,
    /// Final max |K̄ − K| (radians).
    pub ricci_error: f64,
    /// Boundary loops of the shell (1: a disk, 2: an annulus).
    pub boundary_loops: usize,
    /// An annulus: the rotation between its loop cut's two sides (radians;
    /// a flat cylinder has none). `None` for a disk.
    pub seam_rotation: Option<f64>,
    /// Largest bend of a boundary run of ψ off its axis, over ψ's diagonal.
    pub boundary_deviation: f64,
    /// Smallest signed triangle area of ψ over its 3D area (Q1: positive).
    pub min_area_ratio: f64,
    /// Separatrices traced.
    pub separatrices: usize,
    /// Patches (rectangles of the layout).
    pub patches: usize,
    /// Layout arcs (each fitted once).
    pub arcs: usize,
    /// Spans per arc before refinement.
    pub segments: usize,
    /// The refinement factor applied.
    pub refine: usize,
    /// Control points of the multipatch (shared ones once).
    pub control_points: usize,
    /// The shell's bounding-box diagonal.
    pub diagonal: f64,
    /// The tolerance in model units.
    pub tolerance: f64,
    /// Max and mean distance of the shell's vertices to their patch.
    pub max_distance: f64,
    /// Mean distance of the shell's vertices to their patch.
    pub mean_distance: f64,
    /// `max_distance ≤ tolerance`.
    pub tolerance_met: bool,
    /// Patch sides shared by two patches, and the largest control-point gap there (0: watertight).
    pub shared_sides: usize,
    /// Largest gap across shared sides.
    pub max_gap: f64,
    /// Smallest scaled Jacobian over every patch's Gauss points (after refinement).
    pub min_scaled_jacobian: f64,
    /// Patches whose interior fit folded and fell back to Coons.
    pub coons_fallbacks: usize,
    /// Stage times.
    pub times: SplineTimes,
}

/// The result: the multipatch, the layout in 3D (for pictures) and the report.
#[derive(Clone, Debug)]
pub struct SplineResult {
    /// The conforming multipatch.
    pub multipatch: Multipatch,
    /// The layout arcs as 3D polylines on the shell.
    pub layout_polylines: Vec<Vec<[f64; 3]>>,
    /// The report.
    pub report: SplineReport,
}

/// Why no multipatch was made.
#[derive(Debug, Error)]
pub enum SplineMethodError {
    /// The shell is not an open, oriented, genus-0 manifold.
    #[error("{0}")]
    Shell(#[from] ShellError),
    /// Interior cones would be needed.
    #[error("this version lays out only disks whose boundary corners sum to Σ I = 4 (no interior cones, no layout energy S6–S7): {0}")]
    NeedsCones(String),
    /// The cone set is not usable.
    #[error("{0}")]
    Cones(#[from] crate::cones::ConeError),
    /// Cones were placed, the layout energy (S6–S7) and the tracing (S8)
    /// ran, but splines on a traced layout are not built.
    #[error("{message}")]
    NeedsLayoutEnergy {
        /// What was placed and why it stops.
        message: String,
        /// Stage times of the core run with the cones.
        times: CoreTimes,
        /// How the layout energy ended.
        energy: EnergySummary,
    },
    /// The shell falls apart.
    #[error("the shell has {0} connected components; give the faces of one with --faces")]
    Components(usize),
    /// The Ricci flow failed.
    #[error("{0}")]
    Ricci(#[from] RicciError),
    /// The cut failed.
    #[error("{0}")]
    Cut(#[from] CutError),
    /// The immersion failed or folded.
    #[error("{0}")]
    Immersion(#[from] ImmersionError),
    /// The layout failed.
    #[error("{0}")]
    Layout(#[from] LayoutError),
    /// The spline math failed.
    #[error("splines: {0}")]
    Spline(#[from] SplineError),
    /// Patches whose Jacobian is not positive everywhere.
    #[error("non-positive Jacobian on {count} patch(es): {list}")]
    NonPositive {
        /// How many.
        count: usize,
        /// `patch k (min scaled J x)` for each.
        list: String,
    },
    /// Bad options.
    #[error("{0}")]
    Option(String),
}

/// The two kinds of shell that need no interior cone.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum ConeFree {
    /// A disk whose boundary corners' indices sum to 4.
    Disk,
    /// An annulus (two loops, χ = 0) with smooth loops: a flat cylinder.
    Annulus,
}

/// Which cone-free shell `topo` is, given its boundary corner cones
/// `corners` (`None`: it needs interior cones).
fn cone_free_kind(topo: &ShellTopology, corners: &[crate::ricci::Cone]) -> Option<ConeFree> {
    let sum: i32 = corners.iter().map(|c| c.index).sum();
    match (topo.euler, topo.boundary_loops.len(), sum) {
        (1, 1, 4) => Some(ConeFree::Disk),
        (0, 2, 0) if corners.is_empty() => Some(ConeFree::Annulus),
        _ => None,
    }
}

/// Whether a shell of topology `topo` and boundary corner cones `corners`
/// needs no interior cone: a disk whose corners sum to 4, or an annulus
/// with no corner (the shells [`splines_from_shell`] takes without cones).
pub fn is_cone_free(topo: &ShellTopology, corners: &[crate::ricci::Cone]) -> bool {
    cone_free_kind(topo, corners).is_some()
}

/// Checks the shell of topology `topo` is a single disk whose boundary
/// corners' indices sum to 4 (Σ I = 4χ, χ = 1), or an annulus (two loops,
/// χ = 0) without boundary corners, and returns its cones and kind.
fn cone_free_shell(
    shell: &Shell,
    topo: &ShellTopology,
) -> Result<(Vec<crate::ricci::Cone>, ConeFree), SplineMethodError> {
    let loops = topo.boundary_loops.len();
    if topo.components != 1 {
        return Err(SplineMethodError::Components(topo.components));
    }
    let cones = boundary_corner_cones(shell, topo);
    let sum: i32 = cones.iter().map(|c| c.index).sum();
    let kind = match cone_free_kind(topo, &cones) {
        Some(kind) => kind,
        None => {
            let convex = cones.iter().filter(|c| c.index > 0).count();
            return Err(SplineMethodError::NeedsCones(format!(
                "{loops} boundary loop(s), χ = {}, boundary corners {} ({convex} convex, {} reflex) with Σ I = {sum}; without interior cones only a disk (one loop, χ = 1) with Σ I = 4 or an annulus (two loops, χ = 0) with no boundary corner works",
                topo.euler,
                cones.len(),
                cones.iter().filter(|c| c.index < 0).count(),
            )));
        }
    };
    Ok((cones, kind))
}

/// The flat layout of a cone-free shell: the cut, ψ (rotated to the layout
/// for an annulus), the layout, its locator and the figures of the report.
struct FlatLayout {
    cut: CutMesh,
    imm: Immersion,
    layout: Layout,
    locator: PsiLocator,
    /// ψ's largest boundary bend over its size.
    boundary_deviation: f64,
    /// The rotation between the loop cut's two sides (annuli).
    seam_rotation: Option<f64>,
    /// Wall time of the cut (seconds).
    cut_time: f64,
    /// Wall time of the immersion (seconds).
    immersion_time: f64,
}

/// Cut, immersion and layout (S4–S8) of a cone-free shell: the rectangles
/// of an orthogonal polygon for a disk, one rectangle closing along the
/// loop cut for an annulus (`layout::annulus_layout`).
fn flat_layout(
    shell: &Shell,
    topo: &ShellTopology,
    cones: &[crate::ricci::Cone],
    metric: &crate::ricci::RicciMetric,
    kind: ConeFree,
) -> Result<FlatLayout, SplineMethodError> {
    let t0 = Instant::now();
    let cut = cut_to_disk(shell, topo, cones)?;
    let cut_time = t0.elapsed().as_secs_f64();
    let t1 = Instant::now();
    let imm = immerse(shell, topo, &cut, metric)?;
    let immersion_time = t1.elapsed().as_secs_f64();
    if !(imm.min_signed_area > 0.0) {
        return Err(SplineMethodError::Layout(LayoutError::NotOrthogonal(
            format!(
                "ψ folds: smallest signed triangle area {:.3e} (Q1)",
                imm.min_signed_area
            ),
        )));
    }
    match kind {
        ConeFree::Disk => {
            let poly = orthogonal_boundary(topo, &cut, &imm, cones, ORTHOGONAL_TOLERANCE)?;
            let layout = trace_layout(&poly)?;
            let locator = PsiLocator::new(&cut, &imm);
            Ok(FlatLayout {
                cut,
                imm,
                layout,
                locator,
                boundary_deviation: poly.max_deviation / poly.size,
                seam_rotation: None,
                cut_time,
                immersion_time,
            })
        }
        ConeFree::Annulus => {
            let a = annulus_layout(topo, &cut, &imm, ORTHOGONAL_TOLERANCE)?;
            let locator = PsiLocator::new(&cut, &a.immersion).with_period(a.period);
            Ok(FlatLayout {
                cut,
                imm: a.immersion,
                layout: a.layout,
                locator,
                boundary_deviation: a.max_deviation / a.size,
                seam_rotation: Some(a.seam_rotation),
                cut_time,
                immersion_time,
            })
        }
    }
}

/// The bounding-box diagonal of a point set.
fn diagonal(points: &[[f64; 3]]) -> f64 {
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for p in points {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    geometry::vec3::dist(lo, hi)
}

/// Runs the cone-free path on a shell: topology check, then
/// [`splines_from_checked_shell`].
pub fn splines_from_shell(
    shell: &Shell,
    opts: &SplineOptions,
) -> Result<SplineResult, SplineMethodError> {
    let t0 = Instant::now();
    let topo = shell.check()?;
    let t_check = t0.elapsed().as_secs_f64();
    let mut result = splines_from_checked_shell(shell, &topo, opts)?;
    result.report.times.shell += t_check;
    Ok(result)
}

/// Runs the cone-free path on a shell whose [`Shell::check`] gave `topo`
/// (the caller checked it once, e.g. to choose cones): corners, Ricci flow,
/// cut, immersion, layout, splines (see the module docs).
pub fn splines_from_checked_shell(
    shell: &Shell,
    topo: &ShellTopology,
    opts: &SplineOptions,
) -> Result<SplineResult, SplineMethodError> {
    if opts.refine == 0 {
        return Err(SplineMethodError::Option(
            "--refine must be at least 1".into(),
        ));
    }
    if let Segments::Fixed(k) = opts.segments {
        if k == 0 {
            return Err(SplineMethodError::Option(
                "--segments must be at least 1".into(),
            ));
        }
    }
    let t0 = Instant::now();
    if let ConeChoice::Given(given) = &opts.cones {
        refuse_unless_corner_cones(shell, topo, given)?;
    }
    let (cones, kind) = cone_free_shell(shell, topo)?;
    let diag = diagonal(&shell.vertices);
    let tolerance = opts.tolerance.unwrap_or(DEFAULT_TOLERANCE_SHARE * diag);
    if !(tolerance > 0.0 && tolerance.is_finite()) {
        return Err(SplineMethodError::Option(format!(
            "--tolerance {tolerance} must be a positive number"
        )));
    }
    let t_shell = t0.elapsed().as_secs_f64();
    let t1 = Instant::now();
    let metric = ricci_flow(shell, topo, &cones, &RicciOptions::default())?;
    let t_ricci = t1.elapsed().as_secs_f64();
    let t2 = Instant::now();
    let flat = flat_layout(shell, topo, &cones, &metric, kind)?;
    let FlatLayout {
        cut,
        imm,
        layout,
        locator,
        ..
    } = &flat;
    let t_layout = t2.elapsed().as_secs_f64();
    let t3 = Instant::now();
    let samples = fit::ShellSamples::new(shell, cut, imm, layout);
    let ctx = fit::FitContext {
        shell,
        layout,
        locator,
        samples: &samples,
    };
    let (segments, mut mp, mut dist, fallbacks) = match opts.segments {
        Segments::Fixed(k) => {
            let (mp, fb) = ctx.build(k, opts.interior)?;
            let d = ctx.distances(&mp)?;
            (k, mp, d, fb)
        }
        Segments::Auto => {
            let mut last = None;
            for &k in SEGMENT_CHOICES.iter() {
                let (mp, fb) = ctx.build(k, opts.interior)?;
                let d = ctx.distances(&mp)?;
                let ok = d.0 <= tolerance;
                last = Some((k, mp, d, fb));
                if ok {
                    break;
                }
            }
            last.ok_or_else(|| SplineMethodError::Option("no segment count to try".into()))?
        }
    };
    if opts.refine > 1 {
        mp = mp.refined(opts.refine)?;
        dist = ctx.distances(&mp)?;
    }
    let shared = mp.shared_sides();
    let mut min_sj = f64::INFINITY;
    let mut bad = Vec::new();
    for k in 0..layout.rects.len() {
        let patch = mp.patch(k)?;
        let normal = |_x: [f64; 3], s: f64, t: f64| ctx.normal(k, s, t);
        let rep = jacobian_check(&patch, &normal)?;
        min_sj = min_sj.min(rep.min_scaled_jacobian);
        if !rep.is_positive() {
            bad.push(format!(
                "patch {k} (min scaled J {:.3})",
                rep.min_scaled_jacobian
            ));
        }
    }
    if !bad.is_empty() {
        return Err(SplineMethodError::NonPositive {
            count: bad.len(),
            list: bad.join(", "),
        });
    }
    let layout_polylines = ctx.layout_polylines();
    let t_splines = t3.elapsed().as_secs_f64();
    let report = SplineReport {
        triangles: shell.triangles.len(),
        vertices: shell.vertices.len(),
        corners: cones.len(),
        reflex_corners: cones.iter().filter(|c| c.index < 0).count(),
        ricci_iterations: metric.iterations,
        ricci_error: metric.max_error,
        boundary_loops: topo.boundary_loops.len(),
        seam_rotation: flat.seam_rotation,
        boundary_deviation: flat.boundary_deviation,
        min_area_ratio: imm.min_area_ratio,
        separatrices: layout.separatrices,
        patches: layout.rects.len(),
        arcs: layout.arcs.len(),
        segments,
        refine: opts.refine,
        control_points: mp.points().len(),
        diagonal: diag,
        tolerance,
        max_distance: dist.0,
        mean_distance: dist.1,
        tolerance_met: dist.0 <= tolerance,
        shared_sides: shared.pairs,
        max_gap: shared.max_gap,
        min_scaled_jacobian: min_sj,
        coons_fallbacks: fallbacks,
        times: SplineTimes {
            shell: t_shell,
            ricci: t_ricci,
            cut: flat.cut_time,
            immersion: flat.immersion_time,
            layout: t_layout - flat.cut_time - flat.immersion_time,
            splines: t_splines,
        },
    };
    Ok(SplineResult {
        multipatch: mp,
        layout_polylines,
        report,
    })
}

/// The layout of `shell` alone (for tests and pictures): corners, flow,
/// immersion, boundary check and tracing.
pub fn layout_of_shell(shell: &Shell) -> Result<Layout, SplineMethodError> {
    let topo = shell.check()?;
    let (cones, kind) = cone_free_shell(shell, &topo)?;
    let metric = ricci_flow(shell, &topo, &cones, &RicciOptions::default())?;
    Ok(flat_layout(shell, &topo, &cones, &metric, kind)?.layout)
}

#[cfg(test)]
mod tests;
