//! The plain-Rust half of the Python package: everything the bindings do
//! that needs no Python, so that `cargo test` checks it without an
//! interpreter. Loading a model (CAD or triangle mesh), checking the meshing
//! options, meshing on a worker thread that can be cancelled, the report and
//! statistics as JSON, the flat arrays the NumPy arrays are made of, writing
//! and reading mesh files, and the cross field.
//!
//! Every failure is an [`Error`] of one [`ErrorKind`] (the Python exception
//! class) whose message names the file, as the command line's do.

use std::panic::{catch_unwind, resume_unwind, AssertUnwindSafe};
use std::path::Path;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Condvar, Mutex};
use std::time::Duration;

use geometry::Model;
use mesh::{NodeClass, QuadMesh};
use quadrille::{MeshMethod, MeshOptions, MeshReport, ProgressFn, Size, Stages};
use serde_json::{json, Value};

/// Which Python exception an [`Error`] becomes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ErrorKind {
    /// A file: missing, empty, unreadable, malformed, unknown extension,
    /// unwritable (`quadrille.FileError`).
    File,
    /// An option: a bad size, method, thread count, stage combination
    /// (`quadrille.OptionError`).
    Option,
    /// Meshing or the cross field failed on a valid model and valid options
    /// (`quadrille.MeshingError`).
    Meshing,
}

/// A failure of the package: its kind and a one-line message.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Error {
    /// The exception class.
    pub kind: ErrorKind,
    /// The message (names the file when there is one).
    pub message: String,
}

impl Error {
    /// A `kind` error with `message`.
    pub fn new(kind: ErrorKind, message: impl Into<String>) -> Self {
        Error {
            kind,
            message: message.into(),
        }
    }
    fn file(message: impl Into<String>) -> Self {
        Error::new(ErrorKind::File, message)
    }
    fn option(message: impl Into<String>) -> Self {
        Error::new(ErrorKind::Option, message)
    }
    fn meshing(message: impl Into<String>) -> Self {
        Error::new(ErrorKind::Meshing, message)
    }
}

impl std::fmt::Display for Error {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for Error {}

/// The extensions of CAD models (read by OpenCASCADE).
pub const CAD_EXTENSIONS: [&str; 6] = ["step", "stp", "iges", "igs", "brep", "brp"];

/// Lower-case extension of `path` ("" when none).
fn extension(path: &Path) -> String {
    path.extension()
        .map(|e| e.to_string_lossy().to_lowercase())
        .unwrap_or_default()
}

/// A model read from a file, with the import's warnings (repairs of a
/// triangle mesh).
pub struct Loaded {
    /// The B-rep.
    pub model: Model,
    /// One line per repair the triangle-mesh import made (empty for CAD).
    pub warnings: Vec<String>,
}

/// Loads a model: CAD (STEP, IGES, BREP) through OpenCASCADE, or a triangle
/// mesh (STL, OBJ, PLY, MSH) as a discrete B-rep whose feature curves are the
/// edges sharper than `feature_angle` degrees.
pub fn load(path: &Path, feature_angle: f64) -> Result<Loaded, Error> {
    if !(feature_angle.is_finite() && feature_angle > 0.0 && feature_angle < 180.0) {
        return Err(Error::option(format!(
            "feature_angle {feature_angle}: it must be an angle in degrees between 0 and 180"
        )));
    }
    let ext = extension(path);
    if trimesh::Format::from_extension(&ext).is_some() {
        let opts = trimesh::Options {
            feature_angle,
            ..Default::default()
        };
        let imp = trimesh::load(path, &opts).map_err(|e| Error::file(e.to_string()))?;
        let warnings = imp
            .report
            .warnings
            .iter()
            .map(|w| format!("{}: {w}", path.display()))
            .collect();
        return Ok(Loaded {
            model: imp.model,
            warnings,
        });
    }
    if !CAD_EXTENSIONS.contains(&ext.as_str()) {
        return Err(Error::file(format!(
            "{}: unknown model extension '.{ext}' (expected .step, .stp, .iges, .igs, .brep, .brp, or a triangle mesh: .stl, .obj, .ply, .msh)",
            path.display()
        )));
    }
    let model = occt::load(path).map_err(|e| Error::file(e.to_string()))?;
    Ok(Loaded {
        model,
        warnings: Vec::new(),
    })
}

/// The meshing methods, by their command-line names.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// `quasi-structured` (the default).
    QuasiStructured,
    /// `unstructured`.
    Unstructured,
    /// `baseline`.
    Baseline,
    /// `regular`.
    Regular,
}

impl Method {
    /// Every method, in the order the documentation lists them.
    pub const ALL: [Method; 4] = [
        Method::QuasiStructured,
        Method::Unstructured,
        Method::Baseline,
        Method::Regular,
    ];

    /// The method called `name` (as on the command line; `_` for `-` accepted).
    pub fn parse(name: &str) -> Result<Method, Error> {
        let key = name.trim().to_ascii_lowercase().replace('_', "-");
        Method::ALL
            .into_iter()
            .find(|m| m.name() == key)
            .ok_or_else(|| {
                Error::option(format!(
                    "unknown method {name:?} (expected quasi-structured, unstructured, baseline or regular)"
                ))
            })
    }

    /// The command-line name.
    pub fn name(self) -> &'static str {
        match self {
            Method::QuasiStructured => "quasi-structured",
            Method::Unstructured => "unstructured",
            Method::Baseline => "baseline",
            Method::Regular => "regular",
        }
    }
}

/// The options of `quadrille.mesh`, as given from Python.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshRequest {
    /// Target edge length (model units); `None` for `size_factor` × the default.
    pub size: Option<f64>,
    /// Multiplier of the default edge length (1/24 of the bounding-box diagonal).
    pub size_factor: f64,
    /// The method.
    pub method: Method,
    /// Worker threads (`None`: all cores).
    pub threads: Option<usize>,
    /// The quasi-structured method's steps.
    pub stages: Stages,
    /// Quads per full turn of the normal on curved faces (0: off).
    pub quads_per_turn: f64,
    /// The size guard's limit on the estimated quad count (0: no limit).
    pub max_quads: u64,
}

impl Default for MeshRequest {
    fn default() -> Self {
        MeshRequest {
            size: None,
            size_factor: 1.0,
            method: Method::QuasiStructured,
            threads: None,
            stages: Stages::ALL,
            quads_per_turn: quadrille::DEFAULT_QUADS_PER_TURN,
            max_quads: quadrille::DEFAULT_MAX_QUADS,
        }
    }
}

/// The library's size from `size` / `size_factor`, checked.
pub fn size_of(size: Option<f64>, size_factor: f64) -> Result<Size, Error> {
    if !(size_factor.is_finite() && size_factor > 0.0) {
        return Err(Error::option(format!(
            "size_factor {size_factor}: it must be a positive number"
        )));
    }
    match size {
        Some(h) if !(h.is_finite() && h > 0.0) => Err(Error::option(format!(
            "size {h}: it must be a positive length in model units"
        ))),
        Some(_) if size_factor != 1.0 => Err(Error::option(
            "give size or size_factor, not both (size is an absolute edge length)",
        )),
        Some(h) => Ok(Size::Absolute(h)),
        None => Ok(Size::Factor(size_factor)),
    }
}

impl MeshRequest {
    /// The library's options and method, or why the request is refused.
    /// `progress` is called as faces finish (meshing, then regularizing).
    pub fn to_library(
        &self,
        progress: Option<ProgressFn>,
    ) -> Result<(MeshOptions, MeshMethod), Error> {
        let size = size_of(self.size, self.size_factor)?;
        if self.threads == Some(0) {
            return Err(Error::option(
                "threads 0: give at least 1 (or None for all cores)",
            ));
        }
        if !(self.quads_per_turn.is_finite() && self.quads_per_turn >= 0.0) {
            return Err(Error::option(format!(
                "quads_per_turn {}: it must be 0 (off) or a positive number",
                self.quads_per_turn
            )));
        }
        let s = self.stages;
        let off = s.switched_off();
        if self.method != Method::QuasiStructured && !off.is_empty() {
            return Err(Error::option(format!(
                "{}=False only applies to method=\"quasi-structured\" (the default); method {:?} has no such step",
                off.join("=False, "),
                self.method.name()
            )));
        }
        let method = match self.method {
            Method::QuasiStructured => MeshMethod::QuasiStructured(s),
            Method::Unstructured => MeshMethod::Unstructured,
            Method::Baseline => MeshMethod::Baseline,
            Method::Regular => MeshMethod::regular(self.threads),
        };
        let opts = MeshOptions {
            size,
            threads: self.threads,
            progress: progress.clone(),
            regularize_progress: progress,
            quads_per_turn: self.quads_per_turn,
            max_quads: self.max_quads,
            ..MeshOptions::default()
        };
        Ok((opts, method))
    }
}

/// The library's error as an [`Error`] naming `path` (the model's file).
fn meshing_error(path: &str, e: quadrille::MeshError) -> Error {
    use quadrille::MeshError as E;
    let kind = match e {
        E::InvalidSize(_) | E::Sizing(_) | E::TooManyQuads(_) => ErrorKind::Option,
        _ => ErrorKind::Meshing,
    };
    let message = match &e {
        E::TooManyQuads(t) => t.message("size", "size_factor", "max_quads"),
        e => e.to_string(),
    };
    Error::new(kind, format!("{path}: {message}"))
}

/// What a [`Job`] ends with: its value, an error, or cancelled.
#[derive(Debug)]
pub enum Outcome<T> {
    /// Finished.
    Done(T),
    /// Failed (a library panic is a [`ErrorKind::Meshing`] error too).
    Failed(Error),
    /// Stopped by [`Job::cancel`].
    Cancelled,
}

/// The panic payload a cancelled job unwinds with (no panic message printed).
struct Cancelled;

/// Faces done and faces in all, as the progress callback last reported them.
#[derive(Default)]
pub struct Progress {
    done: AtomicUsize,
    total: AtomicUsize,
}

impl Progress {
    /// `(faces done, faces in all)` of the current phase.
    pub fn get(&self) -> (usize, usize) {
        (
            self.done.load(Ordering::Relaxed),
            self.total.load(Ordering::Relaxed),
        )
    }
}

/// Long work (meshing, a cross field) on a thread of its own, so that the
/// caller can wait with the interpreter free, show progress, and give up.
///
/// Cancelling sets a flag the progress callback checks: the next face that
/// finishes unwinds the work (with a payload of our own, so no panic
/// message), which ends at the next face, not at once; the caller need not
/// wait for it.
pub struct Job<T> {
    slot: Arc<(Mutex<Option<Outcome<T>>>, Condvar)>,
    cancel: Arc<AtomicBool>,
    progress: Arc<Progress>,
}

impl<T: Send + 'static> Job<T> {
    /// Starts `work` on a new thread, giving it the progress callback to
    /// pass to the library.
    pub fn spawn(work: impl FnOnce(ProgressFn) -> Result<T, Error> + Send + 'static) -> Job<T> {
        let slot = Arc::new((Mutex::new(None), Condvar::new()));
        let cancel = Arc::new(AtomicBool::new(false));
        let progress = Arc::new(Progress::default());
        let callback: ProgressFn = {
            let cancel = cancel.clone();
            let progress = progress.clone();
            Arc::new(move |done, total| {
                if cancel.load(Ordering::Relaxed) {
                    resume_unwind(Box::new(Cancelled));
                }
                progress.total.store(total, Ordering::Relaxed);
                progress.done.store(done, Ordering::Relaxed);
            })
        };
        let (s, c) = (slot.clone(), cancel.clone());
        std::thread::spawn(move || {
            let outcome = match catch_unwind(AssertUnwindSafe(|| work(callback))) {
                Ok(Ok(v)) => Outcome::Done(v),
                Ok(Err(e)) => Outcome::Failed(e),
                Err(_) if c.load(Ordering::Relaxed) => Outcome::Cancelled,
                Err(payload) => Outcome::Failed(Error::meshing(format!(
                    "internal error (please report it): {}",
                    panic_text(&payload)
                ))),
            };
            let (lock, cv) = &*s;
            *lock.lock().unwrap_or_else(|e| e.into_inner()) = Some(outcome);
            cv.notify_all();
        });
        Job {
            slot,
            cancel,
            progress,
        }
    }

    /// Waits at most `timeout` for the outcome; `None` when still running.
    /// The outcome is handed out once.
    pub fn wait(&self, timeout: Duration) -> Option<Outcome<T>> {
        let (lock, cv) = &*self.slot;
        let guard = lock.lock().unwrap_or_else(|e| e.into_inner());
        let (mut guard, _) = cv
            .wait_timeout_while(guard, timeout, |o| o.is_none())
            .unwrap_or_else(|e| e.into_inner());
        guard.take()
    }

    /// Asks the work to stop at the next face that finishes.
    pub fn cancel(&self) {
        self.cancel.store(true, Ordering::Relaxed);
    }

    /// The progress the work last reported.
    pub fn progress(&self) -> &Progress {
        &self.progress
    }
}

/// The message of a panic payload.
fn panic_text(payload: &Box<dyn std::any::Any + Send>) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        s.to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "a panic".to_string()
    }
}

/// Starts meshing `model` (read from `path`, named in errors) as `request` asks.
/// Options are checked before the thread starts.
pub fn start_mesh(
    model: Arc<Model>,
    path: String,
    request: &MeshRequest,
) -> Result<Job<(QuadMesh, MeshReport)>, Error> {
    request.to_library(None)?;
    let request = request.clone();
    Ok(Job::spawn(move |progress| {
        let (opts, method) = request.to_library(Some(progress))?;
        quadrille::mesh_model_with(&model, &opts, method).map_err(|e| meshing_error(&path, e))
    }))
}

/// The report of a mesh as JSON (`QuadMesh.report` in Python): the method and
/// its steps, per-step counts, faces meshed by a pattern or by the fallback,
/// curves meshed as points, the regularization, stage times in seconds.
pub fn report_json(
    report: &MeshReport,
    request: &MeshRequest,
    faces: usize,
    mesh: &QuadMesh,
) -> Value {
    let secs = |d: Duration| d.as_secs_f64();
    let t = &report.times;
    let d = &report.defects;
    let c = &report.cavities;
    let (tried, kept, removed) = report.regular_pass;
    let qs = request.method == Method::QuasiStructured;
    json!({
        "method": request.method.name(),
        "stages": if qs {
            json!({
                "patterns": request.stages.patterns,
                "defects": request.stages.defects,
                "cavities": request.stages.cavities,
                "regular_pass": request.stages.regular_pass,
            })
        } else {
            Value::Null
        },
        "faces": faces,
        "nodes": mesh.nodes.len(),
        "quads": mesh.quads.len(),
        "estimated_quads": report.estimated_quads,
        "patterns": report.patterns.iter().map(|(f, name)| json!({"face": f.0 + 1, "pattern": name})).collect::<Vec<_>>(),
        "fallback": report.fallback.iter().map(|(f, why)| json!({"face": f.0 + 1, "reason": why.to_string()})).collect::<Vec<_>>(),
        "defects": {
            "found": d.found,
            "replaced": d.replaced,
            "undone": d.undone,
            "corners_found": d.boundary_found,
            "corners_replaced": d.boundary_replaced,
        },
        "cavities": {
            "irregular_before": c.irregular_before,
            "irregular_after": c.irregular_after,
            "singular": c.singular,
            "replaced": c.replaced,
            "rejected": c.rejected,
            "capped": c.capped,
        },
        "regular_pass": {"tried": tried, "kept": kept, "removed": removed},
        "regularize": report.regularize.as_ref().map(|r| {
            let (before, after) = r.irregular();
            json!({
                "faces": r.faces.len(),
                "irregular_before": before,
                "irregular_after": after,
                "reverted": r.faces.iter().filter(|f| f.reverted).count(),
                "skipped": r.skipped.iter().map(|(f, why)| json!({"face": f.0 + 1, "reason": why})).collect::<Vec<_>>(),
            })
        }),
        "slivers": report.slivers.iter().map(|(c, len)| json!({"curve": c.0 + 1, "length": len})).collect::<Vec<_>>(),
        "times": {
            "fields": secs(t.fields),
            "curves": secs(t.curves),
            "faces": secs(t.faces),
            "patterns": secs(t.patterns),
            "frontal": secs(t.frontal),
            "smoothing": secs(t.smoothing),
            "defects": secs(t.defects),
            "cavities": secs(t.cavities),
            "regular_pass": secs(t.regular_pass),
            "fallback": secs(t.fallback),
            "assembly": secs(t.assembly),
            "curve_slide": secs(t.curve_slide),
            "regularize": secs(t.regularize),
            "total": secs(t.total),
        },
    })
}

/// Node positions, row after row (`n × 3`).
pub fn flat_nodes(mesh: &QuadMesh) -> Vec<f64> {
    mesh.nodes.iter().flatten().copied().collect()
}

/// Quad corners, 0-based (`m × 4`).
pub fn flat_quads(mesh: &QuadMesh) -> Vec<i64> {
    mesh.quads.iter().flatten().map(|&v| v as i64).collect()
}

/// Triangle corners, 0-based (`k × 3`; only meshes read from files have triangles).
pub fn flat_triangles(mesh: &QuadMesh) -> Vec<i64> {
    mesh.triangles.iter().flatten().map(|&v| v as i64).collect()
}

/// `(dim, id)` of every node (`n × 2`): dimension 0 corner, 1 curve, 2 face,
/// id 1-based as in MSH files; `(-1, 0)` for a node on no entity.
pub fn flat_node_entity(mesh: &QuadMesh) -> Vec<i64> {
    mesh.node_class
        .iter()
        .flat_map(|c| match *c {
            NodeClass::Corner(k) => [0, k.0 as i64 + 1],
            NodeClass::Curve(k, _) => [1, k.0 as i64 + 1],
            NodeClass::Face(k, _) => [2, k.0 as i64 + 1],
            NodeClass::Unclassified => [-1, 0],
        })
        .collect()
}

/// 1-based CAD face of each element of `faces`.
pub fn one_based(faces: &[geometry::FaceId]) -> Vec<i64> {
    faces.iter().map(|f| f.0 as i64 + 1).collect()
}

/// Writes `mesh` by the extension of `path`: `.msh` (MSH 4.1, ASCII or
/// `binary`, parametric coordinates only when `parametric`), `.vtu` (with the
/// SICN of each quad) or `.obj`. `model` gives MSH its entities and VTU its
/// CAD normals. Nothing is left behind on failure.
pub fn write_mesh(
    mesh: &QuadMesh,
    model: Option<&Model>,
    path: &Path,
    binary: bool,
    parametric: bool,
) -> Result<(), Error> {
    let ext = extension(path);
    let result = match ext.as_str() {
        "msh" => {
            let enc = if binary {
                mesh::msh::MshEncoding::Binary
            } else {
                mesh::msh::MshEncoding::Ascii
            };
            let opts = mesh::msh::MshWriteOptions::new(enc).with_parametric(parametric);
            mesh::msh::write_msh(path, mesh, model, opts).map_err(|e| e.to_string())
        }
        "vtu" | "obj" if binary || parametric => {
            return Err(Error::option(format!(
                "{}: binary and parametric apply to .msh files only",
                path.display()
            )))
        }
        "vtu" => {
            let sicn = mesh::stats::quad_sicn_values(mesh, model);
            mesh::vtu::write_vtu(mesh, Some(&sicn), path).map_err(|e| e.to_string())
        }
        "obj" => mesh::obj::write_obj(mesh, path).map_err(|e| e.to_string()),
        _ => {
            return Err(Error::file(format!(
                "{}: unknown output extension '.{ext}' (expected .msh, .vtu or .obj)",
                path.display()
            )))
        }
    };
    result.map_err(|message| {
        // the writers' messages name the file; make sure of it
        let name = path.display().to_string();
        Error::file(if message.contains(&name) {
            message
        } else {
            format!("{name}: {message}")
        })
    })
}

/// Reads an MSH file (4.1 ASCII or binary, 2.2 ASCII), from any mesher.
pub fn read_mesh(path: &Path) -> Result<QuadMesh, Error> {
    let ext = extension(path);
    if ext != "msh" {
        return Err(Error::file(format!(
            "{}: unknown mesh extension '.{ext}' (expected .msh, MSH 4.1 or 2.2)",
            path.display()
        )));
    }
    mesh::msh::read_msh(path)
        .map(|r| r.mesh)
        .map_err(|e| Error::file(e.to_string()))
}

/// `quadrille stats --json` of `mesh` (with `model`: CAD normals and distances, as `--cad`).
pub fn stats_json(mesh: &QuadMesh, model: Option<&Model>) -> String {
    let stats = mesh::stats::MeshStats::compute(mesh, model);
    serde_json::to_string(&stats).expect("statistics serialize")
}

/// A cross field as flat arrays and a JSON report (`quadrille.field`).
pub struct FieldData {
    /// Background triangulation nodes (`n × 3`; each face has its own).
    pub points: Vec<f64>,
    /// Background triangles, 0-based (`m × 3`).
    pub triangles: Vec<i64>,
    /// 1-based CAD face of each triangle.
    pub triangle_face: Vec<i64>,
    /// One unit branch of the cross per triangle (`m × 3`; NaN at a singularity).
    pub cross: Vec<f64>,
    /// The size map per triangle (empty without one).
    pub size: Vec<f64>,
    /// Singularities: `[x, y, z]` and index (+1 valence 3, −1 valence 5) and 1-based face.
    pub singularities: Vec<([f64; 3], i32, i64)>,
    /// Everything else (sizes, per-face relation (2), totals) as JSON.
    pub report: Value,
}

/// Starts the cross field of every face of `model` (see `quadrille field`).
pub fn start_field(
    model: Arc<Model>,
    path: String,
    size: Option<f64>,
    size_factor: f64,
    quads_per_turn: f64,
) -> Result<Job<FieldData>, Error> {
    let size = size_of(size, size_factor)?;
    if !(quads_per_turn.is_finite() && quads_per_turn >= 0.0) {
        return Err(Error::option(format!(
            "quads_per_turn {quads_per_turn}: it must be 0 (off) or a positive number"
        )));
    }
    Ok(Job::spawn(move |progress| {
        field_data(&model, &path, size, quads_per_turn, progress)
    }))
}

fn field_data(
    model: &Model,
    path: &str,
    size: Size,
    quads_per_turn: f64,
    progress: ProgressFn,
) -> Result<FieldData, Error> {
    use quadrille::field::{model_fields, FieldOptions, SingularitySite, SizeMapOptions};
    let opts = FieldOptions {
        size,
        progress: Some(progress),
        sizing: SizeMapOptions {
            quads_per_turn: (quads_per_turn != 0.0).then_some(quads_per_turn),
            ..Default::default()
        },
        ..Default::default()
    };
    let fields = model_fields(model, &opts).map_err(|e| meshing_error(path, e))?;
    let fm = fields.to_field_mesh(model);
    if fm.triangles.is_empty() {
        let why = fields.first_failure().unwrap_or_default();
        return Err(Error::meshing(format!(
            "{path}: no face could be given a cross field ({why})"
        )));
    }
    let faces: Vec<Value> = fields
        .faces
        .iter()
        .map(|r| match &r.outcome {
            Ok(f) => json!({
                "face": r.face.0 + 1,
                "triangles": f.triangles(),
                "euler_characteristic": f.singularities.euler_characteristic,
                "singularities": f.singularities.list.iter().map(|s| json!({
                    "index": s.index,
                    "position": s.position,
                    "site": match s.site {
                        SingularitySite::Vertex(_) => "vertex",
                        SingularitySite::Triangle(_) => "triangle",
                        SingularitySite::AcuteCorner(..) => "acute_corner",
                    },
                })).collect::<Vec<_>>(),
                "corner_indices": f.corner_indices(),
                "euler_ok": r.euler_ok(),
            }),
            Err(e) => json!({
                "face": r.face.0 + 1,
                "triangles": 0,
                "euler_characteristic": null,
                "singularities": [],
                "corner_indices": [],
                "euler_ok": false,
                "error": e.to_string(),
            }),
        })
        .collect();
    let report = json!({
        "size": fields.size,
        "background_size": fields.background_size,
        "faces": faces,
        "totals": {
            "faces": fields.faces.len(),
            "faces_euler_ok": fields.faces_euler_ok(),
            "euler_ok_share": fields.euler_ok_share(),
            "faces_failed": fields.faces_failed(),
            "triangles": fields.triangles(),
        },
    });
    Ok(FieldData {
        points: fm.nodes.iter().flatten().copied().collect(),
        triangles: fm.triangles.iter().flatten().map(|&v| v as i64).collect(),
        triangle_face: one_based(&fm.triangle_face),
        cross: fm
            .cross
            .iter()
            .flat_map(|c| c.unwrap_or([f64::NAN; 3]))
            .collect(),
        size: fm.size.clone().unwrap_or_default(),
        singularities: fm
            .singularities
            .iter()
            .map(|s| (s.position, s.index, s.face.0 as i64 + 1))
            .collect(),
        report,
    })
}

#[cfg(test)]
mod tests;
