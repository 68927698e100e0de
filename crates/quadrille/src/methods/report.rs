//! What a method reports besides the mesh: per face, how it was made and
//! what each stage did ([`FaceOutcome`]); for the model, their sums and the
//! stage times ([`MeshReport`]).

use std::time::{Duration, Instant};

use geometry::{CurveId, FaceId};

use crate::core::error::FaceError;
use crate::core::patch::QuadPatch;
use crate::topology::cavity::CavityReport;
use crate::topology::defects::DefectReport;
use crate::topology::regular_pass::RegularPassReport;

/// Time spent in each stage of [`crate::mesh_model_with`]. The per-face
/// stages (`patterns` to `fallback`) are sums over faces (and over the
/// attempts of a face whose curves were refined); faces run in parallel, so
/// with several threads these sums exceed the wall time [`StageTimes::faces`].
/// Timings never change the mesh.
#[derive(Clone, Copy, Debug, Default)]
pub struct StageTimes {
    /// The size guard's quad-count estimate ([`crate::methods::guard`]).
    pub estimate: Duration,
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
    /// [`crate::MeshMethod::Baseline`] (sum over faces).
    pub fallback: Duration,
    /// Assembly of the global mesh and the final SICN check.
    pub assembly: Duration,
    /// Curve nodes slid along their curves on the assembled mesh ([`crate::smoothing::curve_slide`]).
    pub curve_slide: Duration,
    /// Topological regularization of the assembled baseline mesh
    /// ([`crate::MeshMethod::Regular`]).
    pub regularize: Duration,
    /// Wall time of the whole call.
    pub total: Duration,
}

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

/// What [`crate::mesh_model_with`] reports besides the mesh.
#[derive(Clone, Debug, Default)]
pub struct MeshReport {
    /// Faces meshed with the baseline because the requested method failed on
    /// them, with the reason, in face order.
    pub fallback: Vec<(FaceId, FaceError)>,
    /// Faces meshed directly by a pattern ([`crate::direct::pattern_face`]), with the
    /// pattern's name, in face order.
    pub patterns: Vec<(FaceId, String)>,
    /// Very irregular vertices found and replaced by disk quadrangulations
    /// ([`crate::topology::defects`]), over all faces.
    pub defects: crate::topology::defects::DefectReport,
    /// Cavity remeshing ([`crate::topology::cavity`]), summed over the faces it ran on.
    pub cavities: crate::topology::cavity::CavityReport,
    /// The regular pass ([`crate::topology::regular_pass`]): faces tried, faces whose
    /// result was kept, irregular face-interior vertices it removed (faces
    /// whose mesh was kept only).
    pub regular_pass: (usize, usize, usize),
    /// The regularization of [`crate::MeshMethod::Regular`].
    pub regularize: Option<crate::topology::regularize::RegularizeReport>,
    /// Time of each stage .
    pub times: StageTimes,
    /// Sliver curves meshed as points (shorter than [`crate::methods::driver::SLIVER_LENGTH`] of the
    /// diagonal: [`geometry::slivers`]), with their lengths, in curve order.
    pub slivers: Vec<(CurveId, f64)>,
    /// The quad count the size guard estimated before meshing
    /// ([`crate::estimate_quads`]).
    pub estimated_quads: u64,
}

/// How one face's mesh was made.
#[derive(Clone, Debug, PartialEq)]
pub enum MadeBy {
    /// The method's own per-face mesher.
    Method,
    /// A pattern of the library ([`crate::direct::pattern_face`]), by name.
    Pattern(String),
    /// The baseline, because the method failed on the face (the reason).
    Fallback(FaceError),
}

/// One face's mesh and what the stages did to it: the unit that the driver
/// keeps per face (replaced when the face is meshed again after its curves
/// were refined) and sums into the [`MeshReport`].
#[derive(Clone, Debug)]
pub struct FaceOutcome {
    /// The face's quads.
    pub patch: QuadPatch,
    /// How they were made.
    pub made_by: MadeBy,
    /// Defect removal and cavity remeshing, when they ran.
    pub topology: Option<(DefectReport, CavityReport)>,
    /// The regular pass, when it was tried.
    pub regular_pass: Option<RegularPassReport>,
}

impl FaceOutcome {
    /// A face meshed as `made_by` says, with no topology stage.
    pub fn new(patch: QuadPatch, made_by: MadeBy) -> Self {
        FaceOutcome {
            patch,
            made_by,
            topology: None,
            regular_pass: None,
        }
    }
}

impl PartialEq for MeshReport {
    /// Equal counts and lists: everything but the stage times, which change
    /// from run to run (two runs of one model agree on everything else,
    /// whatever the thread count).
    fn eq(&self, o: &MeshReport) -> bool {
        self.fallback == o.fallback
            && self.patterns == o.patterns
            && self.defects == o.defects
            && self.cavities == o.cavities
            && self.regular_pass == o.regular_pass
            && self.regularize == o.regularize
            && self.slivers == o.slivers
            && self.estimated_quads == o.estimated_quads
    }
}

impl MeshReport {
    /// The per-face parts of the report summed from the faces' outcomes, in
    /// face order: faces by pattern, fallbacks, defects, cavities and the
    /// regular pass (the last three over faces whose method's mesh was kept).
    pub fn from_faces(outcomes: &[Option<FaceOutcome>]) -> MeshReport {
        let mut r = MeshReport::default();
        for (f, o) in outcomes.iter().enumerate() {
            let Some(o) = o else { continue };
            let fid = FaceId(f as u32);
            match &o.made_by {
                MadeBy::Pattern(name) => r.patterns.push((fid, name.clone())),
                MadeBy::Fallback(why) => {
                    r.fallback.push((fid, why.clone()));
                    continue;
                }
                MadeBy::Method => {}
            }
            if let Some((d, c)) = &o.topology {
                r.defects = r.defects.add(d);
                r.cavities = r.cavities.add(c);
            }
            if let Some(p) = &o.regular_pass {
                let removed = if p.kept {
                    p.irregular.0 - p.irregular.1
                } else {
                    0
                };
                r.regular_pass.0 += 1;
                r.regular_pass.1 += p.kept as usize;
                r.regular_pass.2 += removed;
            }
        }
        r
    }
}

/// Runs `work` inside a `tracing` span named `stage` (with the stage's
/// `name`, so a log shows which face and stage an event comes from) and adds
/// its wall time to `slot`: the one way the methods time their stages.
pub(crate) fn timed<T>(slot: &mut Duration, name: &'static str, work: impl FnOnce() -> T) -> T {
    let _span = tracing::debug_span!("stage", name).entered();
    let started = Instant::now();
    let out = work();
    *slot += started.elapsed();
    out
}
