//! The driver of every method: curve meshes → each face meshed (the
//! baseline, [`crate::methods::baseline`]; the unstructured and quasi-structured
//! methods, falling back on the baseline face by face) → one global
//! [`QuadMesh`] → curve nodes slid along their curves.
//!
//! Faces are meshed in parallel (rayon) and assembled in face order, so the
//! output is bit-identical for any thread count. When a face's boundary
//! polygon is too coarse for its surface (self-intersecting in (u, v), or
//! quads at the boundary that cannot be made valid), the curves involved get
//! twice as many segments and the faces around them are meshed again.

use std::collections::{BTreeMap, BTreeSet};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use geometry::{CornerId, CurveId, FaceId, Model};
use mesh::{NodeClass, QuadMesh};
use rayon::prelude::*;

use crate::core::error::MeshError;
use crate::core::options::{default_size, resolve_size, ProgressFn, Size};
use crate::core::patch::QuadPatch;
use crate::core::patch::{FaceFailure, NodeRef};
use crate::curves::curve_mesh::{discretize_all, plan_curves, CurveMesh, CurvePlan};
use crate::methods::baseline::mesh_face;

/// Sweeps of [`crate::smoothing::raise_average`] on every face of the
/// default and unstructured methods, last: on the 25 shared models (wing
/// out) the average SICN rises by up to 0.006 (s17o_sphere 0.948 → 0.976)
/// for 4.5 % more time in all. 40 sweeps with nodes counted as done only
/// when their quads are all 0.995 ([`crate::smoothing::kernels::ASCENT_GOOD`])
/// instead of 10 and 0.98: s17o 0.979 → 0.986 (Gmsh 0.9856), the others
/// up by 0.0000 to 0.0009, time within noise (BENCHMARKS.md, "Raising the
/// average SICN").
const ASCENT_SWEEPS: usize = 40;

/// Ratio of the quad size to the background size for the plain unstructured
/// method ([`Stages::NONE`]), against [`crate::field::field_report::BACKGROUND_REFINE`]
/// (6) for the others. The finer background places the singularities the
/// topology steps match; the plain method only follows the field's
/// directions and sizes. On the 26 shared models it runs about 40 % faster
/// (the fields were most of the time of the small ones: n12o 0.22 → 0.10 s)
/// with the average SICN within ±0.01 except s17o_sphere (0.934 → 0.911)
/// (BENCHMARKS.md, "A coarser background for the plain unstructured method").
const PLAIN_BACKGROUND_REFINE: f64 = 4.0;
/// Sweeps of [`crate::smoothing::curve_slide::slide_curve_nodes`] over the assembled mesh.
const CURVE_SLIDE_SWEEPS: usize = 10;
/// Rounds of "refine the curves around failed faces and mesh them again".
const CURVE_ROUNDS: usize = 6;
/// The unstructured method bounds the size map to these multiples of the
/// target size, for faces and curves alike (the baseline fallback meshes at
/// the target size and copes with curves at most twice finer).
const SIZE_MAP_MIN: f64 = 0.5;
/// See [`SIZE_MAP_MIN`].
const SIZE_MAP_MAX: f64 = 2.0;
/// At coarse sizes the size map's floor is at most this multiple of the
/// default size: curved faces and small features keep a resolution a
/// coarse target would take away. With the floor at half the target, at
/// `--size-factor 4` a 90° fillet was one or two quads wide and i03o_m3 had
/// a quad of SICN 0.000 and an average of 0.525 (Gmsh: 0.727); with this,
/// 0.153 and 0.730 (BENCHMARKS.md, "Coarse sizes"). At size factors up to
/// 2 (the floor is then half the target) nothing changes.
const COARSE_FLOOR: f64 = 1.0;

/// The size map's lower bound for target size `h` ([`SIZE_MAP_MIN`] of it,
/// at most [`COARSE_FLOOR`] default sizes).
fn size_map_floor(model: &Model, h: f64) -> f64 {
    (SIZE_MAP_MIN * h).min(COARSE_FLOOR * default_size(model))
}

/// Options of [`mesh_model`].
#[derive(Clone)]
pub struct MeshOptions {
    /// Target size (final quad edge length).
    pub size: Size,
    /// Worker threads; `None` uses rayon's global pool. The output does not depend on it.
    pub threads: Option<usize>,
    /// Called as faces are finished.
    pub progress: Option<ProgressFn>,
    /// Quads per full turn of the surface normal on curved faces (a 90°
    /// fillet gets a quarter of them across), within the size map's bounds
    /// of half to twice the target size; 0 turns the bound off. Used by the
    /// quasi-structured and unstructured methods.
    pub quads_per_turn: f64,
}

/// Default of [`MeshOptions::quads_per_turn`]: five quads across a 90°
/// fillet (18° of turn per quad). Without it a fillet narrower than the
/// target size was one quad wide (s12o_cube_rounded_1: 600 quads, its 12
/// fillets one quad across, average SICN 0.956). 16 (four across) left
/// s13o_cube_rounded_2 at 864 quads and average SICN 0.984 against Gmsh
/// quadqs's 0.986 at 1536: a quad bent over 22.5° has SICN at most
/// cos 11.25° = 0.981. With 20 it has Gmsh's 1536 quads and 0.987; over
/// the 26 shared models the quad count goes from 0.95 to 1.03 of Gmsh's
/// and the irregular-share ratio from 0.620 to 0.587 (BENCHMARKS.md,
/// "Five quads per 90° of turn").
pub const DEFAULT_QUADS_PER_TURN: f64 = 20.0;

impl Default for MeshOptions {
    fn default() -> Self {
        MeshOptions {
            size: Size::default(),
            threads: None,
            progress: None,
            quads_per_turn: DEFAULT_QUADS_PER_TURN,
        }
    }
}

impl std::fmt::Debug for MeshOptions {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MeshOptions")
            .field("size", &self.size)
            .field("threads", &self.threads)
            .field("progress", &self.progress.as_ref().map(|_| "callback"))
            .field("quads_per_turn", &self.quads_per_turn)
            .finish()
    }
}

/// Curves shorter than this share of the model's diagonal are slivers, meshed
/// as a point ([`geometry::slivers`]): far below any mesh size (the default
/// is 1/24 of the diagonal), and a quad edge that short is a degenerate quad.
pub const SLIVER_LENGTH: f64 = 1e-5;

/// The model [`MeshMethod::Unstructured`] works on: `model` with its sliver
/// curves (shorter than [`SLIVER_LENGTH`] of the diagonal) collapsed to
/// points, same ids ([`geometry::slivers::collapse_short_curves`]); `None`
/// when it has none. The baseline keeps them: its triangle split gives a
/// sliver two short quad edges, which the regular method then works around.
pub fn collapse_slivers(model: &Model) -> Option<(Model, Vec<geometry::slivers::Collapsed>)> {
    geometry::slivers::collapse_short_curves(model, SLIVER_LENGTH * model.diagonal())
}

/// Meshes every face of `model` with the baseline method: an all-quad mesh,
/// conforming across shared curves and seams, every node on the CAD and
/// classified on its entity, every quad counter-clockwise seen from its face's
/// oriented normal. Output is identical for any `threads`.
pub fn mesh_model(model: &Model, opts: &MeshOptions) -> Result<QuadMesh, MeshError> {
    mesh_model_with(model, opts, MeshMethod::Baseline).map(|(m, _)| m)
}

/// The per-face meshing method of [`mesh_model_with`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum MeshMethod {
    /// Triangulate each face in (u, v) and split every triangle into three quads.
    #[default]
    Baseline,
    /// Frontal points along the cross field, recombination and midpoint
    /// subdivision ([`crate::methods::unstructured`]), then the topology stages of
    /// [`Stages`] (all of them in [`mesh_model_with`]: the quasi-structured
    /// method); a face where it fails is meshed with the baseline (listed in
    /// [`MeshReport::fallback`]).
    Unstructured,
}

/// Which topology stages (paper §6) [`MeshMethod::Unstructured`] runs after
/// the §5 mesh of each face; all of them by default ([`Stages::ALL`], the
/// quasi-structured method), none for the plain unstructured mesh ([`Stages::NONE`]).
///
/// ```
/// use quadrille::methods::pipeline::Stages;
/// let no_cavities = Stages { cavities: false, ..Stages::ALL };
/// assert!(no_cavities.patterns && no_cavities.defects && !no_cavities.cavities);
/// assert_eq!(Stages::default(), Stages::ALL);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Stages {
    /// Simple faces meshed directly by a pattern ([`crate::direct::pattern_face`], §6.1.2).
    pub patterns: bool,
    /// Very irregular vertices replaced by disk quadrangulations ([`crate::topology::defects`], §6.3).
    pub defects: bool,
    /// Cavity remeshing ([`crate::topology::cavity`], §6.2).
    pub cavities: bool,
    /// The regular method's operations on what the cavities left
    /// ([`crate::topology::regular_pass`]), faces not meshed by a pattern.
    pub regular_pass: bool,
}

impl Stages {
    /// Every stage: the quasi-structured method.
    pub const ALL: Stages = Stages {
        patterns: true,
        defects: true,
        cavities: true,
        regular_pass: true,
    };
    /// No stage: the unstructured mesh of §5 alone.
    pub const NONE: Stages = Stages {
        patterns: false,
        defects: false,
        cavities: false,
        regular_pass: false,
    };
}

impl Default for Stages {
    fn default() -> Self {
        Stages::ALL
    }
}

/// Time spent in each stage of [`mesh_model_with`]. The per-face stages
/// (`patterns` to `fallback`) are sums over faces (and over the attempts of a
/// face whose curves were refined); faces run in parallel, so with several
/// threads these sums exceed the wall time [`StageTimes::faces`].
///
/// Timings never change the mesh, and they never take part in equality:
/// `a == b` holds for any two `StageTimes`, so reports of identical runs
/// compare equal.
#[derive(Clone, Copy, Debug, Default)]
pub struct StageTimes {
    /// Cross fields, singularities and size map of every face (unstructured method).
    pub fields: Duration,
    /// Curve planning (quantization against the size map) and discretization.
    pub curves: Duration,
    /// Wall time of the per-face phase (all faces, all threads).
    pub faces: Duration,
    /// Pattern meshing of simple faces, successful or not (sum over faces).
    pub patterns: Duration,
    /// Frontal insertion, recombination and midpoint subdivision (sum over faces).
    pub frontal: Duration,
    /// Smoothing and untangling after subdivision (sum over faces).
    pub smoothing: Duration,
    /// Defect removal by disk quadrangulations (sum over faces).
    pub defects: Duration,
    /// Cavity remeshing (sum over faces).
    pub cavities: Duration,
    /// The regular method's operations after the cavities (sum over faces).
    pub regular_pass: Duration,
    /// Baseline meshing: the faces that fell back to it, or every face of
    /// [`MeshMethod::Baseline`] (sum over faces).
    pub fallback: Duration,
    /// Assembly of the global mesh and the final SICN check.
    pub assembly: Duration,
    /// Curve nodes slid along their curves on the assembled mesh ([`crate::smoothing::curve_slide`]).
    pub curve_slide: Duration,
    /// Wall time of the whole call.
    pub total: Duration,
}

impl PartialEq for StageTimes {
    /// Always true: timings are not part of a result's identity.
    fn eq(&self, _: &StageTimes) -> bool {
        true
    }
}

impl Eq for StageTimes {}

impl StageTimes {
    /// Adds the per-face stage times of `o` (patterns to fallback) to `self`.
    pub fn add_face(&mut self, o: &StageTimes) {
        self.patterns += o.patterns;
        self.frontal += o.frontal;
        self.smoothing += o.smoothing;
        self.defects += o.defects;
        self.cavities += o.cavities;
        self.regular_pass += o.regular_pass;
        self.fallback += o.fallback;
    }
}

/// What [`mesh_model_with`] reports besides the mesh.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshReport {
    /// Faces meshed with the baseline because the requested method failed on
    /// them, with the reason, in face order.
    pub fallback: Vec<(FaceId, String)>,
    /// Faces meshed directly by a pattern ([`crate::direct::pattern_face`]), with the
    /// pattern's name, in face order.
    pub patterns: Vec<(FaceId, String)>,
    /// Very irregular vertices found and replaced by disk quadrangulations
    /// ([`crate::topology::defects`]), over all faces.
    pub defects: crate::topology::defects::DefectReport,
    /// Cavity remeshing ([`crate::topology::cavity`]), summed over the faces it ran on.
    pub cavities: crate::topology::cavity::CavityReport,
    /// The regular pass ([`crate::topology::regular_pass`]): faces tried, faces whose
    /// result was kept, irregular face-interior vertices it removed.
    pub regular_pass: (usize, usize, usize),
    /// Time of each stage (not part of equality; see [`StageTimes`]).
    pub times: StageTimes,
    /// Sliver curves meshed as points (shorter than [`SLIVER_LENGTH`] of the
    /// diagonal: [`geometry::slivers`]), with their lengths, in curve order.
    pub slivers: Vec<(CurveId, f64)>,
}

/// [`mesh_model`] with a choice of method; also reports the faces that fell
/// back to the baseline. Output is identical for any `threads`.
/// [`MeshMethod::Unstructured`] runs every topology stage ([`Stages::ALL`]).
pub fn mesh_model_with(
    model: &Model,
    opts: &MeshOptions,
    method: MeshMethod,
) -> Result<(QuadMesh, MeshReport), MeshError> {
    mesh_model_stages(model, opts, method, Stages::ALL)
}

/// [`mesh_model_with`] with a choice of the topology stages that
/// [`MeshMethod::Unstructured`] runs (the baseline ignores `stages`).
///
/// ```
/// use quadrille::methods::pipeline::{mesh_model_stages, MeshMethod, MeshOptions, Stages};
/// let model = geometry::primitives::square(1.0);
/// let opts = MeshOptions { threads: Some(1), ..Default::default() };
/// let (mesh, report) = mesh_model_stages(&model, &opts, MeshMethod::Unstructured, Stages::NONE).unwrap();
/// assert!(!mesh.quads.is_empty());
/// // no stage ran: no face by a pattern, no cavity
/// assert!(report.patterns.is_empty() && report.cavities.replaced == [0; 4]);
/// ```
pub fn mesh_model_stages(
    model: &Model,
    opts: &MeshOptions,
    method: MeshMethod,
    stages: Stages,
) -> Result<(QuadMesh, MeshReport), MeshError> {
    let started = Instant::now();
    model.validate()?;
    if model.faces.is_empty() {
        return Err(MeshError::NoFaces);
    }
    let h = resolve_size(model, opts.size)?;
    // the quasi-structured and unstructured methods mesh sliver curves as
    // points (their corners one node; ids kept); the baseline, the regular
    // method's input, meshes the model as it is
    let collapsed = match method {
        MeshMethod::Unstructured => collapse_slivers(model),
        MeshMethod::Baseline => None,
    };
    let (model, slivers) = match &collapsed {
        Some((copy, list)) => (copy, list.as_slice()),
        None => (model, &[][..]),
    };
    let merged: Vec<CornerId> = slivers
        .iter()
        .filter(|c| c.removed != c.kept)
        .map(|c| c.removed)
        .collect();
    let merged = merged.as_slice();
    let go = || match method {
        MeshMethod::Baseline => {
            let mut times = StageTimes::default();
            let fallback = std::sync::Mutex::new(Duration::ZERO);
            let t = Instant::now();
            let plan = plan_curves(model, h);
            times.curves += t.elapsed();
            let timed_face = |fid, cms: &[CurveMesh]| {
                let t = Instant::now();
                let r = mesh_face(model, fid, cms, 2.0 * h);
                *fallback.lock().unwrap_or_else(|e| e.into_inner()) += t.elapsed();
                r
            };
            let (cms, results) = run(model, plan, opts.progress.as_ref(), &timed_face, &mut times)?;
            times.fallback = fallback.into_inner().unwrap_or_else(|e| e.into_inner());
            let t = Instant::now();
            let m = assemble(model, &cms, &results, merged)?;
            times.assembly = t.elapsed();
            Ok((
                m,
                MeshReport {
                    times,
                    ..Default::default()
                },
            ))
        }
        MeshMethod::Unstructured => run_unstructured(model, h, opts, stages, merged),
    };
    let mut out = match opts.threads {
        Some(n) => {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(n.max(1))
                .build()
                .map_err(|e| MeshError::Threads {
                    threads: n,
                    reason: e.to_string(),
                })?;
            pool.install(go)
        }
        None => go(),
    }?;
    out.1.times.total = started.elapsed();
    out.1.slivers = slivers.iter().map(|c| (c.curve, c.length)).collect();
    Ok(out)
}

/// The background refinement of the fields for the unstructured method
/// with `stages`: [`PLAIN_BACKGROUND_REFINE`] for the plain method, the
/// finer default as soon as a topology step will match singularities or
/// fit patterns.
fn background_refine(stages: Stages) -> f64 {
    if stages == Stages::NONE {
        PLAIN_BACKGROUND_REFINE
    } else {
        crate::field::field_report::BACKGROUND_REFINE
    }
}

/// The unstructured method: the cross field and size map of every face
/// first, then [`run`] with [`crate::methods::unstructured::mesh_face_unstructured`]
/// per face, the baseline where it fails.
fn run_unstructured(
    model: &Model,
    h: f64,
    opts: &MeshOptions,
    stages: Stages,
    merged: &[CornerId],
) -> Result<(QuadMesh, MeshReport), MeshError> {
    let progress = opts.progress.as_ref();
    if !(opts.quads_per_turn.is_finite() && opts.quads_per_turn >= 0.0) {
        return Err(MeshError::Sizing(format!(
            "quads per turn {} must be 0 (off) or a positive number",
            opts.quads_per_turn
        )));
    }
    use crate::direct::pattern_face::mesh_face_pattern;
    use crate::field::field_report::{model_fields, FieldOptions};
    use crate::methods::unstructured::improve_face_timed;
    use crate::methods::unstructured::{mesh_face_unstructured, UnstructuredOptions};
    use crate::topology::cavity::CavityReport;
    use crate::topology::defects::DefectReport;
    let mut times = StageTimes::default();
    // the size map, bounded so that faces, curves and the baseline fallback agree
    let t = Instant::now();
    let sizing = crate::field::size_map::SizeMapOptions {
        min_size: Some(size_map_floor(model, h)),
        max_size: Some(SIZE_MAP_MAX * h),
        quads_per_turn: (opts.quads_per_turn > 0.0).then_some(opts.quads_per_turn),
        ..Default::default()
    };
    let fields = model_fields(
        model,
        &FieldOptions {
            size: Size::Absolute(h),
            sizing,
            refine: background_refine(stages),
            ..Default::default()
        },
    )?;
    times.fields = t.elapsed();
    let mut uopts = UnstructuredOptions {
        defects: stages.defects,
        ..Default::default()
    };
    if !stages.cavities {
        uopts.cavity = None;
    }
    if stages == Stages::NONE {
        // the §5 mesh is the output: its interior follows the curves' spacing
        uopts.gradation = crate::methods::unstructured::PLAIN_GRADATION;
        uopts.front_spacings = vec![
            crate::methods::unstructured::FrontSpacing::BoundaryRatio,
            crate::methods::unstructured::FrontSpacing::BoundarySpacing,
        ];
        uopts.curvature_by_size_map = true;
        uopts.min_curve_corner_sicn = crate::methods::unstructured::PLAIN_MIN_CURVE_CORNER_SICN;
    }
    let face_times: std::sync::Mutex<StageTimes> = std::sync::Mutex::new(StageTimes::default());
    let fallback: std::sync::Mutex<BTreeMap<u32, String>> = std::sync::Mutex::new(BTreeMap::new());
    let patterns: std::sync::Mutex<BTreeMap<u32, String>> = std::sync::Mutex::new(BTreeMap::new());
    let defects: std::sync::Mutex<BTreeMap<u32, (DefectReport, CavityReport)>> =
        std::sync::Mutex::new(BTreeMap::new());
    let regular: std::sync::Mutex<BTreeMap<u32, crate::topology::regular_pass::RegularPassReport>> =
        std::sync::Mutex::new(BTreeMap::new());
    let pass_opts = crate::topology::regular_pass::RegularPassOptions::default();
    let mesh_one_face =
        |fid: FaceId, cms: &[CurveMesh], ft: &mut StageTimes| -> Result<QuadPatch, FaceFailure> {
            // a simple face is meshed by a pattern first (paper §6.1.2)
            let by_pattern = if stages.patterns {
                let t = Instant::now();
                let r = mesh_face_pattern(model, fid, cms);
                ft.patterns += t.elapsed();
                r
            } else {
                Err("patterns are off".into())
            };
            if let (Err(why), true) = (&by_pattern, tracing::enabled!(tracing::Level::DEBUG)) {
                tracing::debug!("face {}: no pattern: {why}", fid.0 + 1);
            }
            {
                let mut pt = patterns.lock().unwrap_or_else(|e| e.into_inner());
                match &by_pattern {
                    Ok((_, name)) => pt.insert(fid.0, name.clone()),
                    Err(_) => pt.remove(&fid.0),
                };
            }
            if let Ok((p, _)) = by_pattern {
                fallback
                    .lock()
                    .unwrap_or_else(|e| e.into_inner())
                    .remove(&fid.0);
                defects
                    .lock()
                    .unwrap_or_else(|e| e.into_inner())
                    .remove(&fid.0);
                return Ok(p);
            }
            let attempt = (|| -> Result<QuadPatch, String> {
                let ff = fields.faces[fid.idx()]
                    .outcome
                    .as_ref()
                    .map_err(|e| e.to_string())?;
                let topo_n = ff.field.topology.positions.len();
                // without a size map, the uniform size
                let size: Vec<f64> = match &ff.size {
                    Some(s) => s.clone(),
                    None => vec![h; topo_n],
                };
                let (mut p, fr) =
                    mesh_face_unstructured(model, fid, cms, &ff.field, &size, &uopts)?;
                ft.frontal += fr.times.frontal;
                ft.smoothing += fr.times.smoothing;
                // very irregular vertices out (paper §6.3), then cavity remeshing (§6.2)
                let r = improve_face_timed(
                    &model.faces[fid.idx()],
                    &mut p,
                    &ff.singularities.list,
                    &uopts,
                    ft,
                );
                // quads left below the quality bar: one more untangling pass
                let t = Instant::now();
                crate::smoothing::lift_poor_quads(
                    &model.faces[fid.idx()],
                    &mut p,
                    crate::smoothing::POOR_SICN,
                    &crate::core::queries::sharp_corners_of(model, fid),
                );
                ft.smoothing += t.elapsed();
                if tracing::enabled!(tracing::Level::DEBUG) {
                    tracing::debug!(
                        "face {}: {} quads ({} triangles, {} left), {} singularities, {:?}, {:?}",
                        fid.0 + 1,
                        p.quads.len(),
                        fr.triangles,
                        fr.leftover,
                        ff.singularities.list.len(),
                        r.0,
                        r.1
                    );
                }
                defects
                    .lock()
                    .unwrap_or_else(|e| e.into_inner())
                    .insert(fid.0, r);
                Ok(p)
            })();
            let mut fb = fallback.lock().unwrap_or_else(|e| e.into_inner());
            match attempt {
                Ok(p) => {
                    fb.remove(&fid.0);
                    Ok(p)
                }
                Err(reason) => {
                    fb.insert(fid.0, reason);
                    drop(fb);
                    let t = Instant::now();
                    let r = mesh_face(model, fid, cms, 2.0 * h);
                    ft.fallback += t.elapsed();
                    r
                }
            }
        };
    let face_mesher = |fid: FaceId, cms: &[CurveMesh]| -> Result<QuadPatch, FaceFailure> {
        let mut ft = StageTimes::default();
        let mut r = mesh_one_face(fid, cms, &mut ft);
        // last, the face's average quality (square quads, sizes free)
        if let Ok(p) = &mut r {
            // the regular method's operations on what the cavities left
            let by_pattern = patterns
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .contains_key(&fid.0);
            if stages.regular_pass && !by_pattern {
                let t = Instant::now();
                let rep = crate::topology::regular_pass::reduce_irregular(
                    &model.faces[fid.idx()],
                    fid,
                    p,
                    &crate::core::queries::sharp_corners_of(model, fid),
                    &pass_opts,
                );
                if tracing::enabled!(tracing::Level::DEBUG) {
                    tracing::debug!("face {}: regular pass {rep:?}", fid.0 + 1);
                }
                if rep.tried {
                    regular
                        .lock()
                        .unwrap_or_else(|e| e.into_inner())
                        .insert(fid.0, rep);
                }
                ft.regular_pass += t.elapsed();
            }
            // last, the face's average quality (square quads, sizes free)
            let t = Instant::now();
            let rep = crate::smoothing::raise_average(&model.faces[fid.idx()], p, ASCENT_SWEEPS);
            if tracing::enabled!(tracing::Level::DEBUG) {
                tracing::debug!(
                    "face {}: average SICN {:?} → {:?} sweeps {} moves {}",
                    fid.0 + 1,
                    rep.before,
                    rep.after,
                    rep.sweeps,
                    rep.moves
                );
            }
            ft.smoothing += t.elapsed();
        }
        face_times
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .add_face(&ft);
        r
    };
    // curves quantized against the size map (paper §4.3)
    let t = Instant::now();
    let plan = fields.curve_plan(model);
    times.curves += t.elapsed();
    let (cms, mut results) = run(model, plan, progress, &face_mesher, &mut times)?;
    times.add_face(&face_times.into_inner().unwrap_or_else(|e| e.into_inner()));
    let mut fb = fallback.into_inner().unwrap_or_else(|e| e.into_inner());
    let t = Instant::now();
    let mut mesh = assemble(model, &cms, &results, merged)?;
    // the final judge is the mesh statistics' SICN on the assembled mesh:
    // a face with a quad it finds inverted is meshed again with the baseline
    let sicn = mesh::stats::quad_sicn_values(&mesh, Some(model));
    let mut again: BTreeSet<usize> = BTreeSet::new();
    for (q, v) in sicn.iter().enumerate() {
        let f = mesh.quad_face[q].idx();
        if *v < 0.0 && !fb.contains_key(&(f as u32)) {
            again.insert(f);
        }
    }
    times.assembly += t.elapsed();
    if !again.is_empty() {
        let t = Instant::now();
        let redo: Vec<(usize, Result<QuadPatch, FaceFailure>)> = again
            .iter()
            .copied()
            .collect::<Vec<_>>()
            .into_par_iter()
            .map(|f| (f, mesh_face(model, FaceId(f as u32), &cms, 2.0 * h)))
            .collect();
        times.fallback += t.elapsed();
        let t = Instant::now();
        for (f, r) in redo {
            if let Ok(p) = r {
                results[f] = Some(p);
                fb.insert(f as u32, "inverted quads in the assembled mesh".into());
            }
        }
        mesh = assemble(model, &cms, &results, merged)?;
        times.assembly += t.elapsed();
    }
    // last, curve nodes slide along their curves (on every face that uses them)
    let t = Instant::now();
    let rep =
        crate::smoothing::curve_slide::slide_curve_nodes(model, &mut mesh, CURVE_SLIDE_SWEEPS);
    if tracing::enabled!(tracing::Level::DEBUG) {
        tracing::debug!("curve nodes slid: {rep:?}");
    }
    times.curve_slide = t.elapsed();
    let pt = patterns.into_inner().unwrap_or_else(|e| e.into_inner());
    let df = defects.into_inner().unwrap_or_else(|e| e.into_inner());
    let kept = || df.iter().filter(|(f, _)| !fb.contains_key(f));
    let total = kept().fold(DefectReport::default(), |a, (_, (r, _))| DefectReport {
        found: a.found + r.found,
        replaced: a.replaced + r.replaced,
        undone: a.undone + r.undone,
        boundary_found: a.boundary_found + r.boundary_found,
        boundary_replaced: a.boundary_replaced + r.boundary_replaced,
    });
    let cavities = kept().fold(CavityReport::default(), |a, (_, (_, c))| a.add(c));
    let rp = regular.into_inner().unwrap_or_else(|e| e.into_inner());
    let regular_pass =
        rp.iter()
            .filter(|(f, _)| !fb.contains_key(f))
            .fold((0, 0, 0), |a, (_, r)| {
                let removed = if r.kept {
                    r.irregular.0 - r.irregular.1
                } else {
                    0
                };
                (a.0 + 1, a.1 + r.kept as usize, a.2 + removed)
            });
    Ok((
        mesh,
        MeshReport {
            fallback: fb.into_iter().map(|(f, r)| (FaceId(f), r)).collect(),
            patterns: pt.into_iter().map(|(f, n)| (FaceId(f), n)).collect(),
            defects: total,
            cavities,
            regular_pass,
            times,
            slivers: Vec::new(),
        },
    ))
}

/// Per-face mesher of [`run`].
type FaceMesher<'a> = dyn Fn(FaceId, &[CurveMesh]) -> Result<QuadPatch, FaceFailure> + Sync + 'a;

/// Meshes every face with `mesher`, refining the curves around faces that
/// ask for it; returns the final curve meshes and the face patches.
/// Adds the curve discretization to `times.curves` and the per-face phase to `times.faces`.
fn run(
    model: &Model,
    mut plan: CurvePlan,
    progress: Option<&ProgressFn>,
    mesher: &FaceMesher<'_>,
    times: &mut StageTimes,
) -> Result<(Vec<CurveMesh>, Vec<Option<QuadPatch>>), MeshError> {
    let nf = model.faces.len();
    let curve_faces = model.curve_faces();
    let mut results: Vec<Option<QuadPatch>> = vec![None; nf];
    let mut pending: Vec<usize> = (0..nf).collect();
    let done = AtomicUsize::new(0);
    let mut cms: Vec<CurveMesh>;
    let mut round = 0;
    loop {
        let t = Instant::now();
        cms = discretize_all(model, &plan);
        times.curves += t.elapsed();
        let t = Instant::now();
        crate::curves::curve_mesh::largest_faces_first(model, &cms, &mut pending);
        let mut out: Vec<(usize, Result<QuadPatch, FaceFailure>)> =
            crate::core::work_queue::map_in_order(&pending, |&f| {
                let started = Instant::now();
                let r = mesher(FaceId(f as u32), &cms);
                if tracing::enabled!(tracing::Level::DEBUG) {
                    tracing::debug!(
                        "face {} meshed in {:.4} s",
                        f + 1,
                        started.elapsed().as_secs_f64()
                    );
                }
                if r.is_ok() {
                    let d = done.fetch_add(1, Ordering::Relaxed) + 1;
                    if let Some(p) = progress {
                        p(d.min(nf), nf);
                    }
                }
                (f, r)
            });
        out.sort_by_key(|(f, _)| *f);
        times.faces += t.elapsed();
        let mut refine: BTreeSet<CurveId> = BTreeSet::new();
        let mut failed: BTreeMap<usize, String> = BTreeMap::new();
        for (f, r) in out {
            match r {
                Ok(p) => results[f] = Some(p),
                Err(FaceFailure::Fatal(reason)) => {
                    return Err(MeshError::Face {
                        face: FaceId(f as u32),
                        reason,
                    })
                }
                Err(FaceFailure::RefineCurves(cs, reason)) => {
                    refine.extend(cs);
                    failed.insert(f, reason);
                }
            }
        }
        if tracing::enabled!(tracing::Level::DEBUG) {
            tracing::debug!(
                "round {round}: {} faces meshed, failed {:?}, refine {:?}",
                pending.len(),
                failed,
                refine
            );
        }
        if failed.is_empty() {
            break;
        }
        round += 1;
        if round >= CURVE_ROUNDS || refine.is_empty() {
            let (&f, reason) = failed.iter().next().ok_or(MeshError::NoFaces)?;
            return Err(MeshError::Face {
                face: FaceId(f as u32),
                reason: reason.clone(),
            });
        }
        let mut again: BTreeSet<usize> = failed.keys().copied().collect();
        let mut doubled: BTreeSet<CurveId> = BTreeSet::new();
        for &c in &refine {
            if !doubled.contains(&c) {
                doubled.extend(plan.refine(c));
            }
        }
        for c in &doubled {
            again.extend(curve_faces[c.idx()].iter().map(|f| f.idx()));
        }
        for &f in &again {
            if results[f].take().is_some() {
                done.fetch_sub(1, Ordering::Relaxed);
            }
        }
        pending = again.into_iter().collect();
    }
    Ok((cms, results))
}

/// Builds the global mesh: corners (but the ones in `merged`, which no curve
/// uses any more), then curve nodes by curve, then each face's interior
/// nodes in face order; quads in face order.
fn assemble(
    model: &Model,
    cms: &[CurveMesh],
    results: &[Option<QuadPatch>],
    merged: &[CornerId],
) -> Result<QuadMesh, MeshError> {
    let mut m = QuadMesh::default();
    let mut corner_node = vec![u32::MAX; model.corners.len()];
    for (i, c) in model.corners.iter().enumerate() {
        if merged.contains(&CornerId(i as u32)) {
            continue;
        }
        corner_node[i] = m.nodes.len() as u32;
        m.corner_nodes
            .push((m.nodes.len() as u32, CornerId(i as u32)));
        m.nodes.push(c.point);
        m.node_class.push(NodeClass::Corner(CornerId(i as u32)));
    }
    let mut offset = vec![0u32; model.curves.len()];
    for (ci, ce) in model.curves.iter().enumerate() {
        if ce.degenerate {
            continue;
        }
        let cm = &cms[ci];
        let n = cm.params.len();
        offset[ci] = m.nodes.len() as u32;
        for i in 1..n - 1 {
            m.nodes.push(cm.points[i]);
            m.node_class
                .push(NodeClass::Curve(CurveId(ci as u32), Some(cm.params[i])));
        }
        let id = |i: usize| {
            if i == 0 {
                corner_node[ce.start.idx()]
            } else if i == n - 1 {
                corner_node[ce.end.idx()]
            } else {
                offset[ci] + i as u32 - 1
            }
        };
        for i in 0..n - 1 {
            m.curve_edges.push(([id(i), id(i + 1)], CurveId(ci as u32)));
        }
    }
    for (fi, r) in results.iter().enumerate() {
        let fid = FaceId(fi as u32);
        let p = r.as_ref().ok_or(MeshError::Face {
            face: fid,
            reason: "no mesh was produced".into(),
        })?;
        let mut map = vec![u32::MAX; p.nodes.len()];
        for q in &p.quads {
            let mut g = [0u32; 4];
            for k in 0..4 {
                let l = q[k] as usize;
                if map[l] == u32::MAX {
                    map[l] = match p.nodes[l].node {
                        NodeRef::Corner(c) => corner_node[c.idx()],
                        NodeRef::Curve(c, i) => offset[c.idx()] + i - 1,
                        NodeRef::Interior => {
                            m.nodes.push(p.pos[l]);
                            m.node_class.push(NodeClass::Face(fid, Some(p.nodes[l].uv)));
                            (m.nodes.len() - 1) as u32
                        }
                    };
                }
                g[k] = map[l];
            }
            m.quads.push(g);
            m.quad_face.push(fid);
        }
    }
    Ok(m)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::options::DEFAULT_DIVISIONS;
    use geometry::primitives;

    #[test]
    fn sizes_resolve_against_the_default() {
        let m = primitives::square(1.0);
        let d = default_size(&m);
        assert!((d - 2f64.sqrt() / DEFAULT_DIVISIONS).abs() < 1e-12);
        assert_eq!(resolve_size(&m, Size::Factor(2.0)).unwrap(), 2.0 * d);
        assert_eq!(resolve_size(&m, Size::Absolute(0.3)).unwrap(), 0.3);
        assert!(resolve_size(&m, Size::Absolute(-1.0)).is_err());
        assert!(resolve_size(&m, Size::Factor(f64::INFINITY)).is_err());
    }

    #[test]
    fn the_size_floor_is_half_the_target_up_to_the_default_size() {
        let m = primitives::square(1.0);
        let d = default_size(&m);
        assert_eq!(size_map_floor(&m, d), SIZE_MAP_MIN * d);
        assert_eq!(size_map_floor(&m, 0.25 * d), SIZE_MAP_MIN * 0.25 * d);
        assert_eq!(size_map_floor(&m, 2.0 * d), COARSE_FLOOR * d);
        assert_eq!(size_map_floor(&m, 8.0 * d), COARSE_FLOOR * d);
    }

    #[test]
    fn only_the_plain_unstructured_method_has_the_coarse_background() {
        assert_eq!(background_refine(Stages::NONE), PLAIN_BACKGROUND_REFINE);
        const { assert!(PLAIN_BACKGROUND_REFINE < crate::field::field_report::BACKGROUND_REFINE) };
        assert_eq!(
            background_refine(Stages::ALL),
            crate::field::field_report::BACKGROUND_REFINE
        );
        // any one topology step brings the default background back
        let one = Stages {
            regular_pass: true,
            ..Stages::NONE
        };
        assert_eq!(
            background_refine(one),
            crate::field::field_report::BACKGROUND_REFINE
        );
    }

    #[test]
    fn nodes_are_numbered_corners_then_curves_then_faces() {
        let m = primitives::cylinder(1.0, 1.0);
        let mesh = mesh_model(&m, &MeshOptions::default()).unwrap();
        let rank = |c: &NodeClass| match c {
            NodeClass::Corner(_) => 0,
            NodeClass::Curve(..) => 1,
            NodeClass::Face(..) => 2,
            NodeClass::Unclassified => 3,
        };
        let ranks: Vec<u8> = mesh.node_class.iter().map(rank).collect();
        assert!(ranks.windows(2).all(|w| w[0] <= w[1]));
        assert!(!ranks.contains(&3));
        // face-interior nodes grouped by face, in face order
        let faces: Vec<u32> = mesh
            .node_class
            .iter()
            .filter_map(|c| {
                if let NodeClass::Face(f, _) = c {
                    Some(f.0)
                } else {
                    None
                }
            })
            .collect();
        assert!(faces.windows(2).all(|w| w[0] <= w[1]));
        assert_eq!(mesh.corner_nodes, vec![(0, CornerId(0)), (1, CornerId(1))]);
    }

    #[test]
    fn stages_switch_steps_off_and_stage_times_are_reported() {
        let opts = MeshOptions {
            size: Size::Absolute(0.12),
            threads: Some(1),
            progress: None,
            ..Default::default()
        };
        // the sphere without patterns (with them it is one cube, crate::direct::sphere_face)
        let sphere = primitives::sphere(1.0);
        let unpatterned = Stages {
            patterns: false,
            ..Stages::ALL
        };
        let (with, all) =
            mesh_model_stages(&sphere, &opts, MeshMethod::Unstructured, unpatterned).unwrap();
        assert!(
            all.cavities.replaced.iter().sum::<usize>() > 0,
            "{:?}",
            all.cavities
        );
        assert!(
            all.times.fields > Duration::ZERO
                && all.times.frontal > Duration::ZERO
                && all.times.cavities > Duration::ZERO,
            "{:?}",
            all.times
        );
        assert!(
            all.times.total >= all.times.fields + all.times.faces,
            "{:?}",
            all.times
        );
        let (without, off) = mesh_model_stages(
            &sphere,
            &opts,
            MeshMethod::Unstructured,
            Stages {
                cavities: false,
                ..unpatterned
            },
        )
        .unwrap();
        assert_eq!(
            off.cavities,
            crate::topology::cavity::CavityReport::default()
        );
        assert_eq!(off.times.cavities, Duration::ZERO);
        assert_eq!(off.defects, all.defects, "defects run before cavities");
        assert_ne!(with.quads, without.quads);
        let (_, none) =
            mesh_model_stages(&sphere, &opts, MeshMethod::Unstructured, Stages::NONE).unwrap();
        assert_eq!(
            none.defects,
            crate::topology::defects::DefectReport::default()
        );
        assert_eq!(none.regular_pass, (0, 0, 0));
        assert_eq!(none.times.regular_pass, Duration::ZERO);
        // with patterns, the sphere is a cube: one pattern, no cavity
        let (_, cube) =
            mesh_model_stages(&sphere, &opts, MeshMethod::Unstructured, Stages::ALL).unwrap();
        assert_eq!(cube.patterns.len(), 1, "{:?}", cube.patterns);
        // a square is meshed by a pattern unless patterns are off
        let square = primitives::square(1.0);
        let (_, p) =
            mesh_model_stages(&square, &opts, MeshMethod::Unstructured, Stages::ALL).unwrap();
        assert_eq!(p.patterns.len(), 1, "{:?}", p.patterns);
        let (_, q) = mesh_model_stages(
            &square,
            &opts,
            MeshMethod::Unstructured,
            Stages {
                patterns: false,
                ..Stages::ALL
            },
        )
        .unwrap();
        assert!(
            q.patterns.is_empty()
                && q.times.patterns == Duration::ZERO
                && q.times.frontal > Duration::ZERO,
            "{q:?}"
        );
        // the baseline's faces are all timed as baseline meshing
        let (_, b) = mesh_model_stages(&square, &opts, MeshMethod::Baseline, Stages::ALL).unwrap();
        assert!(
            b.times.fallback > Duration::ZERO && b.times.frontal == Duration::ZERO,
            "{:?}",
            b.times
        );
    }

    #[test]
    fn stage_times_never_take_part_in_equality() {
        let a = StageTimes {
            total: Duration::from_secs(3),
            ..Default::default()
        };
        assert_eq!(a, StageTimes::default());
        let r = MeshReport {
            times: a,
            ..Default::default()
        };
        assert_eq!(r, MeshReport::default());
        assert_ne!(
            MeshReport {
                patterns: vec![(FaceId(0), "x".into())],
                ..r.clone()
            },
            r
        );
    }

    #[test]
    fn error_names_the_face() {
        let e = MeshError::Face {
            face: FaceId(4),
            reason: "x".into(),
        };
        assert_eq!(e.to_string(), "face 5 could not be meshed: x");
    }
}
