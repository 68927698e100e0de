//! The PyO3 module `quadrille._quadrille`. The doc comments below are the
//! Python docstrings; `python/quadrille/_quadrille.pyi` holds the types.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Duration;

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2};
use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};

use crate::engine::{self, ErrorKind, Job, MeshRequest, Method, Outcome};

create_exception!(
    quadrille,
    Error,
    PyException,
    "Base class of every error quadrille raises."
);
create_exception!(
    quadrille,
    FileError,
    Error,
    "A file is missing, empty, unreadable, malformed, of an unknown extension, or cannot be written."
);
create_exception!(
    quadrille,
    OptionError,
    Error,
    "An option is invalid: size, size_factor, method, threads, stage switches, feature_angle."
);
create_exception!(
    quadrille,
    MeshingError,
    Error,
    "Meshing (or the cross field) failed on a valid model with valid options."
);

/// The Python exception of an engine error.
fn py_err(e: engine::Error) -> PyErr {
    match e.kind {
        ErrorKind::File => FileError::new_err(e.message),
        ErrorKind::Option => OptionError::new_err(e.message),
        ErrorKind::Meshing => MeshingError::new_err(e.message),
    }
}

/// `json.loads(text)`.
fn json_to_py<'py>(py: Python<'py>, text: &str) -> PyResult<Bound<'py, PyAny>> {
    py.import("json")?.call_method1("loads", (text,))
}

/// A read-only `rows × cols` NumPy array of `data` (row after row).
fn array2<'py, T: numpy::Element>(
    py: Python<'py>,
    data: Vec<T>,
    cols: usize,
) -> PyResult<Bound<'py, PyArray2<T>>> {
    let rows = data.len() / cols;
    let a = Array2::from_shape_vec((rows, cols), data)
        .expect("flat arrays hold whole rows")
        .into_pyarray(py);
    a.getattr("flags")?.setattr("writeable", false)?;
    Ok(a)
}

/// A read-only one-dimensional NumPy array of `data`.
fn array1<'py, T: numpy::Element>(
    py: Python<'py>,
    data: Vec<T>,
) -> PyResult<Bound<'py, PyArray1<T>>> {
    let a = PyArray1::from_vec(py, data);
    a.getattr("flags")?.setattr("writeable", false)?;
    Ok(a)
}

/// How `progress=` is shown while waiting.
enum ProgressSink<'py> {
    None,
    /// `progress=True`: a line on `sys.stderr`, redrawn in place.
    Stderr(Bound<'py, PyAny>),
    /// A callable `progress(done, total)`.
    Call(Bound<'py, PyAny>),
}

impl<'py> ProgressSink<'py> {
    fn new(py: Python<'py>, progress: &Bound<'py, PyAny>) -> PyResult<Self> {
        if progress.is_none() {
            return Ok(ProgressSink::None);
        }
        if progress.is_callable() {
            return Ok(ProgressSink::Call(progress.clone()));
        }
        if progress.is_truthy()? {
            Ok(ProgressSink::Stderr(py.import("sys")?.getattr("stderr")?))
        } else {
            Ok(ProgressSink::None)
        }
    }

    fn show(&self, label: &str, done: usize, total: usize) -> PyResult<()> {
        match self {
            ProgressSink::None => Ok(()),
            ProgressSink::Stderr(err) => {
                err.call_method1("write", (format!("\r{label}: {done}/{total} faces"),))?;
                err.call_method0("flush")?;
                Ok(())
            }
            ProgressSink::Call(f) => f.call1((done, total)).map(|_| ()),
        }
    }

    fn end(&self) -> PyResult<()> {
        if let ProgressSink::Stderr(err) = self {
            err.call_method1("write", ("\n",))?;
        }
        Ok(())
    }
}

/// Waits for `job` with the interpreter free (other Python threads run),
/// checking for Ctrl-C every 100 ms and showing progress. On Ctrl-C (or an
/// exception from a progress callable) the job is cancelled and the
/// exception raised at once; the work stops at its next face.
fn wait_for<T: Send + 'static>(
    py: Python<'_>,
    job: Job<T>,
    progress: &ProgressSink<'_>,
    label: &str,
) -> PyResult<T> {
    let mut shown = (usize::MAX, usize::MAX);
    let outcome = loop {
        if let Some(o) = py.detach(|| job.wait(Duration::from_millis(100))) {
            break o;
        }
        let now = job.progress().get();
        let step = py.check_signals().and_then(|_| {
            if now != shown && now.1 > 0 {
                shown = now;
                progress.show(label, now.0, now.1)?;
            }
            Ok(())
        });
        if let Err(e) = step {
            job.cancel();
            let _ = progress.end();
            return Err(e);
        }
    };
    // the last state, even when the work ended before the first poll
    let now = job.progress().get();
    if now != shown && now.1 > 0 {
        shown = now;
        progress.show(label, now.0, now.1)?;
    }
    if shown.1 != usize::MAX {
        progress.end()?;
    }
    match outcome {
        Outcome::Done(v) => Ok(v),
        Outcome::Failed(e) => Err(py_err(e)),
        Outcome::Cancelled => Err(pyo3::exceptions::PyKeyboardInterrupt::new_err(
            "meshing cancelled",
        )),
    }
}

/// A model: a CAD B-rep (STEP, IGES, BREP) or a triangle mesh read as one
/// (STL, OBJ, PLY, MSH: faces between feature curves). Made by `load`.
#[pyclass(frozen, module = "quadrille")]
pub struct Model {
    inner: Arc<geometry::Model>,
    path: PathBuf,
    warnings: Vec<String>,
    bbox: ([f64; 3], [f64; 3]),
}

#[pymethods]
impl Model {
    /// The file the model was read from.
    #[getter]
    fn path(&self) -> PathBuf {
        self.path.clone()
    }
    /// Number of CAD faces.
    #[getter]
    fn faces(&self) -> usize {
        self.inner.faces.len()
    }
    /// Number of CAD curves.
    #[getter]
    fn curves(&self) -> usize {
        self.inner.curves.len()
    }
    /// Number of CAD corners.
    #[getter]
    fn corners(&self) -> usize {
        self.inner.corners.len()
    }
    /// Axis-aligned bounding box `((xmin, ymin, zmin), (xmax, ymax, zmax))`.
    #[getter]
    #[allow(clippy::type_complexity)]
    fn bounding_box(&self) -> ((f64, f64, f64), (f64, f64, f64)) {
        let t = |p: [f64; 3]| (p[0], p[1], p[2]);
        (t(self.bbox.0), t(self.bbox.1))
    }
    /// Length of the bounding-box diagonal (the default quad size is 1/24 of it).
    #[getter]
    fn diagonal(&self) -> f64 {
        geometry::vec3::dist(self.bbox.0, self.bbox.1)
    }
    /// Repairs the triangle-mesh import made (empty for CAD models).
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.warnings.clone()
    }
    fn __repr__(&self) -> String {
        format!(
            "Model({:?}: {} faces, {} curves, {} corners)",
            self.path.display().to_string(),
            self.faces(),
            self.curves(),
            self.corners()
        )
    }
}

/// Reads a model: CAD (.step, .stp, .iges, .igs, .brep, .brp) or a triangle
/// mesh (.stl, .obj, .ply, .msh) whose edges sharper than `feature_angle`
/// degrees become CAD curves. Raises FileError (missing, empty, unreadable
/// file, unknown extension) or OptionError (bad feature_angle).
#[pyfunction]
#[pyo3(signature = (path, feature_angle = 30.0))]
fn load(py: Python<'_>, path: PathBuf, feature_angle: f64) -> PyResult<Model> {
    let loaded = py
        .detach(|| engine::load(&path, feature_angle))
        .map_err(py_err)?;
    let bbox = loaded.model.bounding_box();
    Ok(Model {
        inner: Arc::new(loaded.model),
        path,
        warnings: loaded.warnings,
        bbox,
    })
}

/// A surface mesh: quads (and, read from a file, triangles) with every node
/// classified on a CAD entity. The arrays are read-only NumPy arrays.
#[pyclass(frozen, module = "quadrille")]
pub struct QuadMesh {
    mesh: ::mesh::QuadMesh,
    model: Option<Py<Model>>,
    report: Option<String>,
    nodes: Py<PyArray2<f64>>,
    quads: Py<PyArray2<i64>>,
    triangles: Py<PyArray2<i64>>,
    node_entity: Py<PyArray2<i64>>,
    quad_face: Py<PyArray1<i64>>,
    triangle_face: Py<PyArray1<i64>>,
}

impl QuadMesh {
    fn new(
        py: Python<'_>,
        mesh: ::mesh::QuadMesh,
        model: Option<Py<Model>>,
        report: Option<String>,
    ) -> PyResult<QuadMesh> {
        Ok(QuadMesh {
            nodes: array2(py, engine::flat_nodes(&mesh), 3)?.unbind(),
            quads: array2(py, engine::flat_quads(&mesh), 4)?.unbind(),
            triangles: array2(py, engine::flat_triangles(&mesh), 3)?.unbind(),
            node_entity: array2(py, engine::flat_node_entity(&mesh), 2)?.unbind(),
            quad_face: array1(py, engine::one_based(&mesh.quad_face))?.unbind(),
            triangle_face: array1(py, engine::one_based(&mesh.triangle_face))?.unbind(),
            mesh,
            model,
            report,
        })
    }
}

#[pymethods]
impl QuadMesh {
    /// Node positions, float64 array of shape (n, 3).
    #[getter]
    fn nodes(&self, py: Python<'_>) -> Py<PyArray2<f64>> {
        self.nodes.clone_ref(py)
    }
    /// Quads as 0-based node indices, int64 array of shape (m, 4), each
    /// counter-clockwise seen from the outside (the CAD face's normal).
    #[getter]
    fn quads(&self, py: Python<'_>) -> Py<PyArray2<i64>> {
        self.quads.clone_ref(py)
    }
    /// Triangles as 0-based node indices, int64 array of shape (k, 3) (empty
    /// for meshes quadrille makes; files from other meshers may have some).
    #[getter]
    fn triangles(&self, py: Python<'_>) -> Py<PyArray2<i64>> {
        self.triangles.clone_ref(py)
    }
    /// The CAD entity of each node, int64 array of shape (n, 2): (dimension,
    /// 1-based id) with dimension 0 for a corner, 1 a curve, 2 a face (-1, 0
    /// for a node on no entity, only in files from elsewhere).
    #[getter]
    fn node_entity(&self, py: Python<'_>) -> Py<PyArray2<i64>> {
        self.node_entity.clone_ref(py)
    }
    /// The 1-based CAD face of each quad, int64 array of shape (m,).
    #[getter]
    fn quad_face(&self, py: Python<'_>) -> Py<PyArray1<i64>> {
        self.quad_face.clone_ref(py)
    }
    /// The 1-based CAD face of each triangle, int64 array of shape (k,).
    #[getter]
    fn triangle_face(&self, py: Python<'_>) -> Py<PyArray1<i64>> {
        self.triangle_face.clone_ref(py)
    }
    /// The model the mesh was made from (None for a mesh read from a file).
    #[getter]
    fn model(&self, py: Python<'_>) -> Option<Py<Model>> {
        self.model.as_ref().map(|m| m.clone_ref(py))
    }
    /// What meshing did, as a dict: method, stages, faces, nodes, quads,
    /// faces meshed by a pattern or by the baseline fallback, defect and
    /// cavity counts, regular pass, regularization, curves meshed as points,
    /// stage times in seconds. None for a mesh read from a file.
    #[getter]
    fn report<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        self.report
            .as_deref()
            .map(|r| json_to_py(py, r))
            .transpose()
    }
    /// Writes the mesh by the extension of `path`: .msh (MSH 4.1, ASCII or
    /// `binary`; parametric coordinates only with `parametric`, which meshio
    /// cannot read), .vtu (VTK, with the SICN of each quad) or .obj. A mesh
    /// made by quadrille writes its model's entities. Raises FileError
    /// (unknown extension, unwritable path) or OptionError (binary or
    /// parametric for VTU or OBJ); no partial file is left.
    #[pyo3(signature = (path, binary = false, parametric = false))]
    fn write(&self, py: Python<'_>, path: PathBuf, binary: bool, parametric: bool) -> PyResult<()> {
        let model = self.model.as_ref().map(|m| m.get().inner.clone());
        py.detach(|| engine::write_mesh(&self.mesh, model.as_deref(), &path, binary, parametric))
            .map_err(py_err)
    }
    /// Quality statistics, the dict `quadrille stats --json` prints: SICN
    /// and scaled Jacobian summaries, valences, irregular vertices, inverted
    /// quads, open edges. With `model` (as `--cad`): SICN with the CAD
    /// normals and the distance of the nodes to the CAD; without, the
    /// normals of the mesh itself. Pass `mesh.model` for a mesh quadrille made.
    #[pyo3(signature = (model = None))]
    fn stats<'py>(&self, py: Python<'py>, model: Option<Py<Model>>) -> PyResult<Bound<'py, PyAny>> {
        let model = model.map(|m| m.get().inner.clone());
        let text = py.detach(|| engine::stats_json(&self.mesh, model.as_deref()));
        json_to_py(py, &text)
    }
    /// The mesh as a `meshio.Mesh` (meshio must be installed): points, "quad"
    /// cells (and "triangle" cells when there are triangles), cell data
    /// "cad_face" (1-based face per cell), point data "cad_dim" and "cad_id"
    /// (the node's entity, as `node_entity`).
    fn to_meshio<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let meshio = py.import("meshio").map_err(|e| {
            pyo3::exceptions::PyImportError::new_err(format!(
                "QuadMesh.to_meshio needs meshio (pip install meshio): {e}"
            ))
        })?;
        let cells = PyList::empty(py);
        let faces = PyList::empty(py);
        cells.append(("quad", self.quads.bind(py)))?;
        faces.append(self.quad_face.bind(py))?;
        if !self.mesh.triangles.is_empty() {
            cells.append(("triangle", self.triangles.bind(py)))?;
            faces.append(self.triangle_face.bind(py))?;
        }
        let cell_data = PyDict::new(py);
        cell_data.set_item("cad_face", faces)?;
        let point_data = PyDict::new(py);
        let ent = self.node_entity.bind(py);
        point_data.set_item(
            "cad_dim",
            ent.get_item((pyo3::types::PySlice::full(py), 0))?,
        )?;
        point_data.set_item("cad_id", ent.get_item((pyo3::types::PySlice::full(py), 1))?)?;
        let kwargs = PyDict::new(py);
        kwargs.set_item("point_data", point_data)?;
        kwargs.set_item("cell_data", cell_data)?;
        meshio
            .getattr("Mesh")?
            .call((self.nodes.bind(py), cells), Some(&kwargs))
    }
    /// Number of quads.
    fn __len__(&self) -> usize {
        self.mesh.quads.len()
    }
    fn __repr__(&self) -> String {
        let tri = if self.mesh.triangles.is_empty() {
            String::new()
        } else {
            format!(", {} triangles", self.mesh.triangles.len())
        };
        format!(
            "QuadMesh({} nodes, {} quads{tri})",
            self.mesh.nodes.len(),
            self.mesh.quads.len()
        )
    }
}

/// The model of `model_or_path`: a Model, or a path loaded with the default
/// feature angle.
fn model_of(py: Python<'_>, model_or_path: &Bound<'_, PyAny>) -> PyResult<Py<Model>> {
    if let Ok(m) = model_or_path.extract::<Py<Model>>() {
        return Ok(m);
    }
    let path: PathBuf = model_or_path.extract().map_err(|_| {
        pyo3::exceptions::PyTypeError::new_err(format!(
            "expected a quadrille.Model or a path, got {}",
            model_or_path
                .get_type()
                .name()
                .map(|n| n.to_string())
                .unwrap_or_default()
        ))
    })?;
    Py::new(py, load(py, path, trimesh::DEFAULT_FEATURE_ANGLE)?)
}

/// Meshes a model (a Model or a path to one) with quads and returns a
/// QuadMesh.
///
/// - size: target edge length in model units; or size_factor: times the
///   default, 1/24 of the bounding-box diagonal (not both).
/// - method: "quasi-structured" (default), "unstructured", "baseline" or
///   "regular" (as `quadrille mesh --method`).
/// - threads: worker threads (None: all cores); the mesh is the same for any count.
/// - progress: True prints "meshing: done/total faces" on stderr; a callable
///   is called as progress(done, total) (from the calling thread, at most
///   every 0.1 s, and once at the end).
/// - patterns, defects, cavities, regular_pass: the quasi-structured
///   method's steps (False switches one off, as --no-patterns etc.).
/// - quads_per_turn: quads per full turn of the normal on curved faces (0: off).
/// - max_quads: refuse (OptionError) when the quad count estimated before
///   meshing is above this; 0 lifts the limit.
///
/// The interpreter is free while meshing (other threads run); Ctrl-C raises
/// KeyboardInterrupt at once (the work stops at its next face). Raises
/// FileError, OptionError or MeshingError.
#[pyfunction(name = "mesh")]
#[pyo3(signature = (model_or_path, size = None, size_factor = 1.0, method = "quasi-structured",
    threads = None, progress = None, patterns = true, defects = true, cavities = true,
    regular_pass = true, quads_per_turn = quadrille::DEFAULT_QUADS_PER_TURN,
    max_quads = quadrille::DEFAULT_MAX_QUADS as i64))]
#[allow(clippy::too_many_arguments)]
fn mesh_model(
    py: Python<'_>,
    model_or_path: &Bound<'_, PyAny>,
    size: Option<f64>,
    size_factor: f64,
    method: &str,
    threads: Option<i64>,
    progress: Option<Bound<'_, PyAny>>,
    patterns: bool,
    defects: bool,
    cavities: bool,
    regular_pass: bool,
    quads_per_turn: f64,
    max_quads: i64,
) -> PyResult<QuadMesh> {
    let threads = match threads {
        Some(n) if n < 1 => {
            return Err(OptionError::new_err(format!(
                "threads {n}: give at least 1 (or None for all cores)"
            )))
        }
        n => n.map(|n| n as usize),
    };
    if max_quads < 0 {
        return Err(OptionError::new_err(format!(
            "max_quads {max_quads}: give a quad count (0: no limit)"
        )));
    }
    let max_quads = max_quads as u64;
    let request = MeshRequest {
        size,
        size_factor,
        method: Method::parse(method).map_err(py_err)?,
        threads,
        stages: quadrille::Stages {
            patterns,
            defects,
            cavities,
            regular_pass,
        },
        quads_per_turn,
        max_quads,
    };
    // options first: a bad one is refused before a long load
    request.to_library(None).map_err(py_err)?;
    let model = model_of(py, model_or_path)?;
    let m = model.get();
    let progress = progress.unwrap_or_else(|| py.None().into_bound(py));
    let sink = ProgressSink::new(py, &progress)?;
    let job = engine::start_mesh(m.inner.clone(), m.path.display().to_string(), &request)
        .map_err(py_err)?;
    let (qm, report) = wait_for(py, job, &sink, "meshing")?;
    let report = engine::report_json(&report, &request, m.inner.faces.len(), &qm).to_string();
    QuadMesh::new(py, qm, Some(model), Some(report))
}

/// Reads a mesh file: MSH 4.1 (ASCII or binary) or 2.2 (ASCII), from
/// quadrille, Gmsh or any other mesher. Raises FileError.
#[pyfunction]
fn read_mesh(py: Python<'_>, path: PathBuf) -> PyResult<QuadMesh> {
    let m = py.detach(|| engine::read_mesh(&path)).map_err(py_err)?;
    QuadMesh::new(py, m, None, None)
}

/// The cross field of every face (as `quadrille field`), on the background
/// triangulation the mesher uses, as a dict:
///
/// - "points" (n, 3), "triangles" (m, 3) 0-based, "triangle_face" (m,) 1-based;
/// - "cross" (m, 3): one unit branch of the cross per triangle (NaN where
///   the field vanishes); "size" (m,): the size map (None without one);
/// - "singularities": list of dicts {"face", "index" (+1 valence 3, -1
///   valence 5), "position"};
/// - "faces": per face its singularities with their site, corner indices,
///   Euler characteristic and whether relation (2) holds ("euler_ok");
///   "totals"; "size" and "background_size".
///
/// size / size_factor / quads_per_turn / progress as for `mesh`.
#[pyfunction]
#[pyo3(signature = (model_or_path, size = None, size_factor = 1.0, progress = None,
    quads_per_turn = quadrille::DEFAULT_QUADS_PER_TURN))]
fn field<'py>(
    py: Python<'py>,
    model_or_path: &Bound<'py, PyAny>,
    size: Option<f64>,
    size_factor: f64,
    progress: Option<Bound<'py, PyAny>>,
    quads_per_turn: f64,
) -> PyResult<Bound<'py, PyDict>> {
    engine::size_of(size, size_factor).map_err(py_err)?;
    let model = model_of(py, model_or_path)?;
    let m = model.get();
    let progress = progress.unwrap_or_else(|| py.None().into_bound(py));
    let sink = ProgressSink::new(py, &progress)?;
    let job = engine::start_field(
        m.inner.clone(),
        m.path.display().to_string(),
        size,
        size_factor,
        quads_per_turn,
    )
    .map_err(py_err)?;
    let f = wait_for(py, job, &sink, "cross field")?;
    let out = json_to_py(py, &f.report.to_string())?.cast_into::<PyDict>()?;
    out.set_item("points", array2(py, f.points, 3)?)?;
    out.set_item("triangles", array2(py, f.triangles, 3)?)?;
    out.set_item("triangle_face", array1(py, f.triangle_face)?)?;
    out.set_item("cross", array2(py, f.cross, 3)?)?;
    if f.size.is_empty() {
        out.set_item("size_map", py.None())?;
    } else {
        out.set_item("size_map", array1(py, f.size)?)?;
    }
    let sings = PyList::empty(py);
    for (position, index, face) in f.singularities {
        let d = PyDict::new(py);
        d.set_item("face", face)?;
        d.set_item("index", index)?;
        d.set_item("position", PyTuple::new(py, position)?)?;
        sings.append(d)?;
    }
    out.set_item("singularities", sings)?;
    Ok(out)
}

/// Quadrille's quad mesher for Python (the native module; import `quadrille`).
#[pymodule]
fn _quadrille(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("Error", py.get_type::<Error>())?;
    m.add("FileError", py.get_type::<FileError>())?;
    m.add("OptionError", py.get_type::<OptionError>())?;
    m.add("MeshingError", py.get_type::<MeshingError>())?;
    m.add_class::<Model>()?;
    m.add_class::<QuadMesh>()?;
    m.add_function(wrap_pyfunction!(load, m)?)?;
    m.add_function(wrap_pyfunction!(mesh_model, m)?)?;
    m.add_function(wrap_pyfunction!(read_mesh, m)?)?;
    m.add_function(wrap_pyfunction!(field, m)?)?;
    Ok(())
}
