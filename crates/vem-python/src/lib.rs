//! The native part of the Python package `vemcontact`: a scene read from a TOML file, a TOML
//! text or a Python dict into the problem description of `vem_scene` (the same keys, checks
//! and located errors as the `vem` command), solved with the GIL released, and the results as
//! numpy arrays, in the plane and in space. Meshes come from a scene's mesh description
//! (generated, a file, or given inline by arrays: `vem_scene::inline_mesh`) and go back as
//! arrays (`Mesh`); the registries' names, the convergence study and the trade-off study's
//! groups are read from the libraries (`vem_verify::plan`, `vem_verify::tradeoff`). A solve
//! runs on a worker thread while the caller runs Python's signal handlers, so that Ctrl-C
//! raises `KeyboardInterrupt`. The package's Python part (`python/vemcontact`) adds the
//! builders, the meshio conversions, the exception and warning classes and the documentation
//! users read; docs/python.md shows it at work.
//!
//! Errors never cross the boundary as panics: a scene error becomes the package's
//! `SceneError` with its key path (and the file, line and column of a scene file), a failed
//! solve its `SolveError`, a failed write its `OutputError`; a panic inside the libraries is
//! caught and raised as a `SolveError` that says so.
#![deny(missing_docs)]

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};

use numpy::ndarray::{Array1, Array2, Array3};
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArray3};
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use serde_json::Value;
use vem_contact::{InterfaceNode, NodeStatus};
use vem_elastic::ElementField;
use vem_scene::toml_file::{self, SpanIndex};
use vem_scene::{BuildOptions, KeyPath, SceneError, Segment};

/// Where a scene came from: the text of a file (errors are shown at its line and column) or a
/// Python value (errors name the key path).
#[derive(Debug, Clone)]
enum Origin {
    /// A TOML text, with the file name it is reported under and its index of keys.
    Toml {
        file: PathBuf,
        source: String,
        spans: SpanIndex,
    },
    /// A dict (or anything that reads as one).
    Value,
}

/// The package's exception for `error` of a scene from `origin`, built by the Python class
/// `kind` of `vemcontact._errors` (`SceneError` or `SolveError`).
fn scene_error(py: Python<'_>, kind: &str, origin: &Origin, error: &SceneError) -> PyErr {
    let segments = PyList::empty(py);
    for segment in &error.path.0 {
        let item = match segment {
            Segment::Key(key) => key.clone().into_pyobject(py).map(Bound::into_any),
            Segment::Index(index) => index.into_pyobject(py).map(Bound::into_any),
        };
        let Ok(item) = item;
        let _ = segments.append(item);
    }
    let key_path = error.path.to_string();
    let (text, file, line, column) = match origin {
        Origin::Toml {
            file,
            source,
            spans,
        } => {
            let cli =
                vem_cli::CliError::at(file, source, spans.span(&error.path), error.message.clone());
            let (line, column) = cli
                .location()
                .map_or((None, None), |at| (Some(at.line), Some(at.column)));
            (
                cli.to_string(),
                Some(file.display().to_string()),
                line,
                column,
            )
        }
        Origin::Value => (error.to_string(), None, None, None),
    };
    let made = py
        .import("vemcontact._errors")
        .and_then(|module| module.getattr(kind))
        .and_then(|class| {
            class.call1((
                text.clone(),
                key_path,
                segments,
                error.message.clone(),
                file,
                line,
                column,
            ))
        });
    match made {
        Ok(value) => PyErr::from_value(value),
        Err(e) => e,
    }
}

/// A panic inside the libraries as a `SolveError` (a bug of the library, reported as one).
fn panic_error(py: Python<'_>, payload: Box<dyn std::any::Any + Send>) -> PyErr {
    let what = payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".to_string());
    let error = SceneError::at(
        KeyPath::root(),
        format!("internal error of the library (please report it with the scene): {what}"),
    );
    scene_error(py, "SolveError", &Origin::Value, &error)
}

/// A contact problem described as data: bodies, contact pairs, laws, solver, load history.
///
/// Made by `vemcontact.load(path)`, `vemcontact.loads(text)` or `vemcontact.from_dict(d)`;
/// already checked (every key, type and setting that can be checked without meshes).
/// `solve()` builds the meshes and solves.
#[pyclass(module = "vemcontact", name = "Scene", frozen)]
struct PyScene {
    scene: vem_scene::Scene,
    origin: Origin,
    base: PathBuf,
}

impl PyScene {
    /// A checked scene: the title defaulted, then `vem_scene::check::check`.
    fn checked(
        py: Python<'_>,
        mut scene: vem_scene::Scene,
        origin: Origin,
        base: PathBuf,
        default_title: String,
    ) -> PyResult<Self> {
        if scene.title.is_none() {
            scene.title = Some(default_title);
        }
        vem_scene::check::check(&scene).map_err(|e| scene_error(py, "SceneError", &origin, &e))?;
        Ok(Self {
            scene,
            origin,
            base,
        })
    }
}

/// The name errors give a TOML text that is not a file's.
const UNNAMED: &str = "<string>";

/// Reads the TOML text `source` as the scene file `file`.
fn parse_toml(py: Python<'_>, file: PathBuf, source: String) -> PyResult<PyScene> {
    let origin_of = |spans| Origin::Toml {
        file: file.clone(),
        source: source.clone(),
        spans,
    };
    let (scene, spans) = match toml_file::parse(&source) {
        Ok(parsed) => parsed,
        Err(e) => {
            let spans = SpanIndex::of(&source);
            let path = e
                .span
                .clone()
                .map_or_else(KeyPath::root, |span| spans.path_at(&source, span));
            // The TOML reader's own span is the exact place: show the error there.
            let located = vem_cli::CliError::at(&file, &source, e.span, e.message.clone());
            let error = SceneError::at(path, e.message);
            return Err(with_location(
                py,
                scene_error(py, "SceneError", &origin_of(spans), &error),
                &located,
            ));
        }
    };
    let base = file.parent().unwrap_or(Path::new("")).to_path_buf();
    let stem = match file.file_stem() {
        Some(stem) if file != Path::new(UNNAMED) => stem.to_string_lossy().into_owned(),
        _ => "scene".to_string(),
    };
    PyScene::checked(py, scene, origin_of(spans), base, stem)
}

/// The exception `error` with the message and position of `located` (the TOML reader's
/// span, which can be finer than the key path's).
fn with_location(py: Python<'_>, error: PyErr, located: &vem_cli::CliError) -> PyErr {
    let value = error.value(py);
    let _ = value.setattr("args", PyTuple::new(py, [located.to_string()]).ok());
    if let Some(at) = located.location() {
        let _ = value.setattr("line", at.line);
        let _ = value.setattr("column", at.column);
    }
    error
}

/// A Python value as the JSON value of a scene, every refusal at its key path.
fn to_value(object: &Bound<'_, PyAny>, path: &KeyPath) -> Result<Value, SceneError> {
    let refuse = |what: String| SceneError::at(path.clone(), what);
    if object.is_none() {
        return Ok(Value::Null);
    }
    if object.is_instance_of::<PyBool>() {
        return object
            .extract::<bool>()
            .map(Value::Bool)
            .map_err(|e| refuse(e.to_string()));
    }
    if object.is_instance_of::<PyInt>() {
        if let Ok(v) = object.extract::<i64>() {
            return Ok(Value::from(v));
        }
        if let Ok(v) = object.extract::<u64>() {
            return Ok(Value::from(v));
        }
        return Err(refuse(format!(
            "the integer {object} is out of range (64 bits)"
        )));
    }
    if object.is_instance_of::<PyFloat>() {
        let v = object.extract::<f64>().map_err(|e| refuse(e.to_string()))?;
        return serde_json::Number::from_f64(v)
            .map(Value::Number)
            .ok_or_else(|| refuse(format!("`{path}` = {v} must be finite")));
    }
    if object.is_instance_of::<PyString>() {
        return object
            .extract::<String>()
            .map(Value::String)
            .map_err(|e| refuse(e.to_string()));
    }
    if let Ok(dict) = object.cast::<PyDict>() {
        let mut map = serde_json::Map::new();
        for (key, value) in dict.iter() {
            let Ok(key) = key.extract::<String>() else {
                return Err(refuse(format!(
                    "the key {} is not a string: a scene's keys are names",
                    key.repr().map_or_else(|_| "?".into(), |r| r.to_string())
                )));
            };
            let value = to_value(&value, &path.at(&key))?;
            map.insert(key, value);
        }
        return Ok(Value::Object(map));
    }
    if object.is_instance_of::<PyList>() || object.is_instance_of::<PyTuple>() {
        let mut items = Vec::new();
        for (k, item) in object
            .try_iter()
            .map_err(|e| refuse(e.to_string()))?
            .enumerate()
        {
            let item = item.map_err(|e| refuse(e.to_string()))?;
            items.push(to_value(&item, &path.index(k))?);
        }
        return Ok(Value::Array(items));
    }
    // A path (`pathlib.Path`) names a file.
    if let Ok(fspath) = object.call_method0("__fspath__") {
        return to_value(&fspath, path);
    }
    // numpy arrays and scalars: their Python values.
    if let Ok(plain) = object.call_method0("tolist") {
        if !plain.is(object) {
            return to_value(&plain, path);
        }
    }
    let kind = object
        .get_type()
        .name()
        .map_or_else(|_| "?".to_string(), |n| n.to_string());
    Err(refuse(format!(
        "a value of type {kind} is not part of a scene: give numbers, strings, lists and dicts"
    )))
}

/// Reads the scene file at `path` (a TOML file) and checks it.
///
/// Raises `SceneError` (with `key_path`, `file`, `line`, `column`) for a scene that is not
/// valid, `OSError` for a file that cannot be read.
#[pyfunction]
fn load(py: Python<'_>, path: PathBuf) -> PyResult<PyScene> {
    let source = std::fs::read_to_string(&path).map_err(|e| {
        pyo3::exceptions::PyOSError::new_err((
            e.raw_os_error().unwrap_or(0),
            format!("cannot read the scene file {}: {e}", path.display()),
            path.display().to_string(),
        ))
    })?;
    parse_toml(py, path, source)
}

/// Reads a scene from TOML text; `path` names it in errors and is where mesh files are looked
/// up from (its folder; default: the current folder).
#[pyfunction]
#[pyo3(signature = (text, path = None))]
fn loads(py: Python<'_>, text: String, path: Option<PathBuf>) -> PyResult<PyScene> {
    parse_toml(py, path.unwrap_or_else(|| PathBuf::from(UNNAMED)), text)
}

/// Reads a scene from a dict with the keys of a scene file (`docs/scenes.md`): the same
/// types, checks and errors, each at its key path (`body[0].mesh.n`). Mesh files are looked
/// up from `base` (default: the current folder).
#[pyfunction]
#[pyo3(signature = (scene, base = None))]
fn from_dict(py: Python<'_>, scene: &Bound<'_, PyAny>, base: Option<PathBuf>) -> PyResult<PyScene> {
    let origin = Origin::Value;
    let value = to_value(scene, &KeyPath::root())
        .map_err(|e| scene_error(py, "SceneError", &origin, &e))?;
    if !value.is_object() {
        let error = SceneError::at(
            KeyPath::root(),
            "a scene is a dict of its keys (`body`, `contact`, `solver`, ...)",
        );
        return Err(scene_error(py, "SceneError", &origin, &error));
    }
    let description = vem_scene::Scene::from_value(value)
        .map_err(|e| scene_error(py, "SceneError", &origin, &e))?;
    PyScene::checked(
        py,
        description,
        origin,
        base.unwrap_or_default(),
        "scene".to_string(),
    )
}

#[pymethods]
impl PyScene {
    /// The scene's title (the file's stem when it has none).
    #[getter]
    fn title(&self) -> String {
        self.scene.title.clone().unwrap_or_default()
    }

    /// The names of the bodies, in order.
    #[getter]
    fn body_names(&self) -> Vec<String> {
        self.scene.bodies.iter().map(|b| b.name.clone()).collect()
    }

    /// The number of contact pairs.
    #[getter]
    fn n_contacts(&self) -> usize {
        self.scene.contacts.len()
    }

    /// The folder mesh files are looked up from.
    #[getter]
    fn base(&self) -> PathBuf {
        self.base.clone()
    }

    /// The scene as a dict of its keys (the form `from_dict` reads).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let text = serde_json::to_string(&self.scene)
            .map_err(|e| PyRuntimeError::new_err(format!("the scene does not serialise: {e}")))?;
        py.import("json")?.call_method1("loads", (text,))
    }

    /// Builds the meshes and the model and solves, with the GIL released.
    ///
    /// `memory_limit_gib` bounds the memory the run plans to use (default: the scene's
    /// `[limits] memory_gib`, else the memory available). Raises `SceneError` for a setting
    /// refused when building (an unknown part, a refused law setting) and `SolveError` when
    /// the solve fails.
    #[pyo3(signature = (memory_limit_gib = None))]
    fn solve(&self, py: Python<'_>, memory_limit_gib: Option<f64>) -> PyResult<PyResultSet> {
        let memory_limit = match memory_limit_gib {
            None => None,
            Some(gib) => Some(
                vem_scene::resources::MemoryLimit::try_from_gib(
                    gib,
                    vem_scene::resources::LimitOrigin::CommandLine,
                )
                .map_err(|e| pyo3::exceptions::PyValueError::new_err(e.to_string()))?,
            ),
        };
        let options = BuildOptions {
            base: self.base.clone(),
            memory_limit,
            ..BuildOptions::default()
        };
        let outcome = match run_interruptibly(py, self.scene.clone(), options)? {
            Run::Panicked(payload) => return Err(panic_error(py, payload)),
            Run::Refused(e) => return Err(scene_error(py, "SceneError", &self.origin, &e)),
            Run::Failed(e) => return Err(scene_error(py, "SolveError", &self.origin, &e)),
            Run::Solved(outcome) => *outcome,
            // Only a run interrupted stops there, and its result is never received.
            Run::Cancelled => {
                return Err(pyo3::exceptions::PyKeyboardInterrupt::new_err(
                    "the run was interrupted",
                ))
            }
        };
        let result = PyResultSet::new(py, outcome)?;
        // Every warning of the run as a Python warning (filtered, shown once or turned into
        // an error as the user's warning filters say); the list stays on the result.
        let category = py.import("vemcontact._errors")?.getattr("SceneWarning")?;
        for warning in result.warnings() {
            let text = std::ffi::CString::new(warning.replace('\0', " "))
                .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
            PyErr::warn(py, &category, &text, 1)?;
        }
        Ok(result)
    }

    fn __repr__(&self) -> String {
        let from = match &self.origin {
            Origin::Toml { file, .. } => format!(", file={}", quote(&file.display().to_string())),
            Origin::Value => String::new(),
        };
        let names: Vec<String> = self.body_names().iter().map(|n| quote(n)).collect();
        format!(
            "Scene(title={}, bodies=[{}], contacts={}{from})",
            quote(&self.title()),
            names.join(", "),
            self.scene.contacts.len()
        )
    }
}

/// How a run on the worker thread ended.
enum Run {
    /// Built and solved.
    Solved(Box<vem_cli::Outcome>),
    /// Refused when building (a scene error).
    Refused(SceneError),
    /// The solve failed.
    Failed(SceneError),
    /// A panic inside the libraries.
    Panicked(Box<dyn std::any::Any + Send>),
    /// Stopped at a stage boundary after an interrupt.
    Cancelled,
}

/// How often the waiting thread looks for signals (Ctrl-C) while a run computes.
const SIGNAL_POLL: std::time::Duration = std::time::Duration::from_millis(50);

/// Builds and solves `scene` on a worker thread while this thread, which holds the GIL every
/// [`SIGNAL_POLL`], runs Python's signal handlers (`Python::check_signals`): a Ctrl-C (or
/// any handler that raises) ends the wait at once with the handler's exception
/// (`KeyboardInterrupt`). The worker stops at the next stage boundary (after the model is
/// built, before the solve); a stage under way (the mesh generation and assembly, or the
/// contact solve) runs to its end on the worker and its result is dropped: the libraries'
/// solvers have no cancellation point inside a stage.
fn run_interruptibly(
    py: Python<'_>,
    scene: vem_scene::Scene,
    options: BuildOptions,
) -> PyResult<Run> {
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::sync::mpsc;
    use std::sync::Arc;

    let cancelled = Arc::new(AtomicBool::new(false));
    let (sender, receiver) = mpsc::channel();
    let worker_cancelled = Arc::clone(&cancelled);
    let worker = std::thread::Builder::new()
        .name("vemcontact-solve".into())
        .spawn(move || {
            let run = catch_unwind(AssertUnwindSafe(|| {
                let model = match vem_scene::Model::build(&scene, &options) {
                    Ok(model) => model,
                    Err(e) => return Run::Refused(e),
                };
                if worker_cancelled.load(Ordering::Relaxed) {
                    return Run::Cancelled;
                }
                match model.solve() {
                    Ok(outcome) => Run::Solved(Box::new(vem_cli::Outcome::new(outcome, &model))),
                    Err(e) => Run::Failed(e),
                }
            }))
            .unwrap_or_else(Run::Panicked);
            // The receiver is gone after an interrupt: the result is dropped.
            let _ = sender.send(run);
        })
        .map_err(|e| PyRuntimeError::new_err(format!("cannot start the solve's thread: {e}")))?;
    let mut receiver = receiver;
    loop {
        // The receiver goes into the wait and comes back (it is not `Sync`).
        let (back, received) = py.detach(move || {
            let received = receiver.recv_timeout(SIGNAL_POLL);
            (receiver, received)
        });
        receiver = back;
        match received {
            Ok(run) => {
                let _ = worker.join();
                return Ok(run);
            }
            Err(mpsc::RecvTimeoutError::Timeout) => {
                if let Err(interrupt) = py.check_signals() {
                    cancelled.store(true, Ordering::Relaxed);
                    return Err(interrupt);
                }
            }
            Err(mpsc::RecvTimeoutError::Disconnected) => {
                let _ = worker.join();
                return Ok(Run::Panicked(Box::new(
                    "the solve's thread ended without a result",
                )));
            }
        }
    }
}

/// `text` as Python writes a string literal (`'a'`, `"it's"`).
fn quote(text: &str) -> String {
    if text.contains('\'') && !text.contains('"') {
        format!("\"{text}\"")
    } else {
        format!("'{}'", text.replace('\\', "\\\\").replace('\'', "\\'"))
    }
}

/// A flat row-major array of `rows` rows of `columns` as an (rows, columns) numpy array.
fn matrix<'py>(
    py: Python<'py>,
    rows: usize,
    columns: usize,
    flat: Vec<f64>,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    Array2::from_shape_vec((rows, columns), flat)
        .map(|a| a.into_pyarray(py))
        .map_err(|e| PyRuntimeError::new_err(e.to_string()))
}

/// One body after the solve (or after one step of a load history), in the plane or in space.
///
/// Arrays: `vertices` (n, d) with d = 2 in the plane and 3 in space, `displacement` (n, d) at
/// the vertices, the cells as `cells` or `cell_offsets`/`cell_connectivity` (see `Mesh`), and
/// per element `stress` and `strain` (m, 3, 3; plane strain has `stress[:, 2, 2] = lambda
/// tr(eps)`) and `von_mises` (m,); `mesh` is the mesh solved, with its parts: a body in
/// contact has the interface nodes inserted into its contact part.
#[pyclass(module = "vemcontact", name = "BodyResult", frozen)]
struct PyBody {
    name: String,
    mesh: Py<PyMesh>,
    displacement: Vec<f64>,
    fields: Vec<ElementField>,
    strain_energy: f64,
    reactions: Vec<(String, Vec<f64>)>,
}

impl PyBody {
    /// A body in the plane.
    fn new(
        py: Python<'_>,
        body: &vem_elastic::ElasticBody,
        solution: &vem_elastic::Solution,
        fields: Vec<ElementField>,
    ) -> PyResult<Self> {
        let mesh = vem_scene::BuiltMesh::Plane(body.mesh().clone());
        Self::of(py, body.name(), &mesh, solution, fields)
    }

    /// A body in space.
    fn new_3d(
        py: Python<'_>,
        body: &vem_elastic::ElasticBody<3>,
        solution: &vem_elastic::Solution<3>,
        fields: Vec<ElementField>,
    ) -> PyResult<Self> {
        let mesh = vem_scene::BuiltMesh::Space(body.mesh().clone());
        Self::of(py, body.name(), &mesh, solution, fields)
    }

    fn of<const D: usize>(
        py: Python<'_>,
        name: &str,
        mesh: &vem_scene::BuiltMesh,
        solution: &vem_elastic::Solution<D>,
        fields: Vec<ElementField>,
    ) -> PyResult<Self> {
        Ok(Self {
            name: name.to_string(),
            mesh: Py::new(py, PyMesh::new(mesh, format!("the mesh of body '{name}'")))?,
            displacement: solution.displacement().to_vec(),
            fields,
            strain_energy: solution.strain_energy(),
            reactions: solution
                .reactions()
                .iter()
                .map(|r| (r.part.clone(), r.force.iter().copied().collect()))
                .collect(),
        })
    }

    fn tensors<'py>(
        &self,
        py: Python<'py>,
        of: impl Fn(&ElementField) -> &nalgebra::Matrix3<f64>,
    ) -> PyResult<Bound<'py, PyArray3<f64>>> {
        let mut flat = Vec::with_capacity(9 * self.fields.len());
        for field in &self.fields {
            let t = of(field);
            for i in 0..3 {
                for j in 0..3 {
                    flat.push(t[(i, j)]);
                }
            }
        }
        Array3::from_shape_vec((self.fields.len(), 3, 3), flat)
            .map(|a| a.into_pyarray(py))
            .map_err(|e| PyRuntimeError::new_err(e.to_string()))
    }
}

#[pymethods]
impl PyBody {
    /// The body's name.
    #[getter]
    fn name(&self) -> String {
        self.name.clone()
    }

    /// 2 (a body in the plane) or 3 (in space).
    #[getter]
    fn dimension(&self) -> usize {
        self.mesh.get().dimension
    }

    /// The mesh solved, with its boundary parts (interface nodes inserted into a contact
    /// part).
    #[getter]
    fn mesh(&self, py: Python<'_>) -> Py<PyMesh> {
        self.mesh.clone_ref(py)
    }

    /// Vertex coordinates, (n, d).
    #[getter]
    fn vertices<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.mesh.get().vertices(py)
    }

    /// Nodal displacement, (n, d), in the order of `vertices`.
    #[getter]
    fn displacement<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let d = self.dimension();
        matrix(
            py,
            self.displacement.len() / d,
            d,
            self.displacement.clone(),
        )
    }

    /// The cells: polygons as arrays of vertex indices (counter-clockwise), polyhedra as
    /// lists of outward face loops.
    #[getter]
    fn cells<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        self.mesh.get().cells(py)
    }

    /// Where each cell starts in `cell_connectivity` (m + 1 entries).
    #[getter]
    fn cell_offsets<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<usize>> {
        self.mesh.get().cell_offsets(py)
    }

    /// The vertex indices of every cell, one after the other (a polygon's loop, a
    /// polyhedron's distinct vertices).
    #[getter]
    fn cell_connectivity<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<usize>> {
        self.mesh.get().cell_connectivity(py)
    }

    /// The body as a `meshio.Mesh` (needs the package meshio): the mesh solved with the
    /// point data `displacement` and the cell data `stress` (m x 9) and `von_mises`.
    fn to_meshio<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyAny>> {
        slf.py()
            .import("vemcontact._meshio")?
            .call_method1("body_to_meshio", (slf,))
    }

    /// The stress tensor of every element, (m, 3, 3).
    #[getter]
    fn stress<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray3<f64>>> {
        self.tensors(py, |f| &f.stress)
    }

    /// The strain tensor of every element, (m, 3, 3).
    #[getter]
    fn strain<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray3<f64>>> {
        self.tensors(py, |f| &f.strain)
    }

    /// The von Mises stress of every element, (m,).
    #[getter]
    fn von_mises<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        Array1::from_iter(self.fields.iter().map(|f| f.von_mises)).into_pyarray(py)
    }

    /// The discrete strain energy.
    #[getter]
    fn strain_energy(&self) -> f64 {
        self.strain_energy
    }

    /// The force each Dirichlet condition or rigid plate exerts on the body, by part (the
    /// components of a part held more than once add up).
    #[getter]
    fn reactions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let dict = PyDict::new(py);
        for (part, force) in &self.reactions {
            let sum = match dict.get_item(part)? {
                Some(earlier) => {
                    let earlier: Vec<f64> = earlier.extract()?;
                    earlier.iter().zip(force).map(|(a, b)| a + b).collect()
                }
                None => force.clone(),
            };
            dict.set_item(part, PyArray1::from_vec(py, sum))?;
        }
        Ok(dict)
    }

    fn __repr__(&self) -> String {
        let mesh = self.mesh.get();
        format!(
            "BodyResult(name={}, dimension={}, vertices={}, cells={}, strain_energy={:.6e})",
            quote(&self.name),
            mesh.dimension,
            mesh.n_vertices(),
            mesh.n_cells(),
            self.strain_energy
        )
    }
}

/// The interface nodes of one contact pair, in their order along body A's contact part (in
/// space, in the order of body A's part's vertices).
///
/// Arrays (k nodes, d = 2 in the plane, 3 in space): `positions` (k, d) on body A, `normals`
/// (k, d), `tributary` (k,) the node's length (area in space), `initial_gap`, `normal_jump`
/// (`[u].nu`), `gap` (`initial_gap - normal_jump`, >= 0 up to the solver's tolerance),
/// `normal_force` (compression positive), `pressure` (`normal_force / tributary`),
/// `consistent_pressure`, `friction_force` (k, d) on body A, `friction` (k,) its tangential
/// component (in the plane), `friction_traction` (k, d), `slip` (k, d), `tangential_slip` (k,)
/// (in the plane), `status` (a list of "open", "contact", "stick", "slip", as contact.csv
/// writes it) and `status_code` (k,) (0 open, 1 contact, 2 stick, 3 slip, as interface.vtu
/// writes it).
#[pyclass(module = "vemcontact", name = "ContactPair", frozen)]
struct PyPair {
    index: usize,
    description: String,
    law: String,
    dimension: usize,
    nodes: Vec<PairNode>,
    frictionless: bool,
}

/// One interface node in either dimension: its vectors with `dimension` components, and in
/// the plane the tangential components of the friction force and the slip.
#[derive(Debug, Clone)]
struct PairNode {
    position: Vec<f64>,
    normal: Vec<f64>,
    friction_force: Vec<f64>,
    friction_traction: Vec<f64>,
    slip: Vec<f64>,
    tributary: f64,
    initial_gap: f64,
    normal_jump: f64,
    normal_force: f64,
    pressure: f64,
    consistent_pressure: f64,
    /// In the plane: the friction force and the slip along the tangent `(-n_y, n_x)`.
    tangential: Option<(f64, f64)>,
    status: NodeStatus,
    vertex_a: usize,
}

impl PairNode {
    fn of<const D: usize>(n: &InterfaceNode<D>) -> Self {
        let vector = |v: &vem_mesh::VectorD<D>| v.iter().map(|c| c + 0.0).collect::<Vec<f64>>();
        let tangential = (D == 2).then(|| {
            let t = [-n.normal[1], n.normal[0]];
            let along = |v: &vem_mesh::VectorD<D>| v[0] * t[0] + v[1] * t[1];
            (along(&n.friction_force), along(&n.slip))
        });
        Self {
            position: vector(&n.position.coords),
            normal: vector(&n.normal),
            friction_force: vector(&n.friction_force),
            friction_traction: vector(&n.consistent_friction_traction),
            slip: vector(&n.slip),
            tributary: n.tributary_measure,
            initial_gap: n.initial_gap,
            normal_jump: n.normal_jump,
            normal_force: n.normal_force,
            pressure: n.pressure,
            consistent_pressure: n.consistent_pressure,
            tangential,
            status: n.status,
            vertex_a: n.vertex_a,
        }
    }
}

impl PyPair {
    fn scalars<'py>(
        &self,
        py: Python<'py>,
        of: impl Fn(&PairNode) -> f64,
    ) -> Bound<'py, PyArray1<f64>> {
        Array1::from_iter(self.nodes.iter().map(|n| of(n) + 0.0)).into_pyarray(py)
    }

    fn vectors<'py>(
        &self,
        py: Python<'py>,
        of: impl Fn(&PairNode) -> &[f64],
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let flat = self.nodes.iter().flat_map(|n| of(n).to_vec()).collect();
        matrix(py, self.nodes.len(), self.dimension, flat)
    }

    /// A tangential component of the plane (`friction`, `tangential_slip`); in space an error
    /// naming the vector to use.
    fn tangential<'py>(
        &self,
        py: Python<'py>,
        name: &str,
        vector: &str,
        of: impl Fn((f64, f64)) -> f64,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        if self.dimension != 2 {
            return Err(pyo3::exceptions::PyAttributeError::new_err(format!(
                "`{name}` is the component along the tangent of a pair in the plane; in space \
                 the tangent plane has two directions: use `{vector}` (k, 3)"
            )));
        }
        Ok(self.scalars(py, |n| n.tangential.map_or(0.0, &of)))
    }
}

/// The pairs of a contact result (in the plane or in space), each with its nodes.
fn pairs_of<const D: usize>(result: &vem_contact::ContactResult<D>) -> Vec<PyPair> {
    let frictionless = result.model.tangential_rows == 0;
    result
        .model
        .pairs
        .iter()
        .enumerate()
        .map(|(k, pair)| PyPair {
            index: k,
            description: pair.description.clone(),
            law: pair.law.clone(),
            dimension: D,
            nodes: result.nodes[pair.nodes.clone()]
                .iter()
                .map(PairNode::of)
                .collect(),
            frictionless,
        })
        .collect()
}

#[pymethods]
impl PyPair {
    /// The pair's index in the scene's `contact` list.
    #[getter]
    fn index(&self) -> usize {
        self.index
    }

    /// Which parts face what, in words.
    #[getter]
    fn description(&self) -> String {
        self.description.clone()
    }

    /// The contact law, in words.
    #[getter]
    fn law(&self) -> String {
        self.law.clone()
    }

    /// The number of interface nodes.
    fn __len__(&self) -> usize {
        self.nodes.len()
    }

    /// 2 (a pair in the plane) or 3 (in space): the number of columns of the vector arrays.
    #[getter]
    fn dimension(&self) -> usize {
        self.dimension
    }

    /// Node positions on body A (reference configuration), (k, d).
    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.vectors(py, |n| &n.position)
    }

    /// The contact normals, (k, d).
    #[getter]
    fn normals<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.vectors(py, |n| &n.normal)
    }

    /// The nodes' tributary lengths (areas in space), (k,).
    #[getter]
    fn tributary<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.scalars(py, |n| n.tributary)
    }

    /// The initial gaps `h0`, (k,).
    #[getter]
    fn initial_gap<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.scalars(py, |n| n.initial_gap)
    }

    /// The normal jumps `[u].nu`, (k,).
    #[getter]
    fn normal_jump<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.scalars(py, |n| n.normal_jump)
    }

    /// The gaps after the solve, `h0 - [u].nu`, (k,).
    #[getter]
    fn gap<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.scalars(py, |n| n.initial_gap - n.normal_jump)
    }

    /// The nodal normal forces (compression positive), (k,).
    #[getter]
    fn normal_force<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.scalars(py, |n| n.normal_force)
    }

    /// The nodal pressures `normal_force / tributary`, (k,).
    #[getter]
    fn pressure<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.scalars(py, |n| n.pressure)
    }

    /// The consistent pressures (the non-negative L2 projection of the nodal forces), (k,).
    #[getter]
    fn consistent_pressure<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.scalars(py, |n| n.consistent_pressure)
    }

    /// The nodal friction forces on body A, (k, d).
    #[getter]
    fn friction_force<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.vectors(py, |n| &n.friction_force)
    }

    /// The friction forces' components along the tangent `(-n_y, n_x)`, (k,) (in the plane).
    #[getter]
    fn friction<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.tangential(py, "friction", "friction_force", |(f, _)| f)
    }

    /// The consistent friction tractions, (k, d).
    #[getter]
    fn friction_traction<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.vectors(py, |n| &n.friction_traction)
    }

    /// The slips (tangential part of `u_A - u_B`; zero without friction), (k, d).
    #[getter]
    fn slip<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.vectors(py, |n| &n.slip)
    }

    /// The slips along the tangent, (k,) (in the plane).
    #[getter]
    fn tangential_slip<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.tangential(py, "tangential_slip", "slip", |(_, s)| s)
    }

    /// The nodes' statuses as the outputs name them.
    #[getter]
    fn status(&self) -> Vec<&'static str> {
        self.nodes
            .iter()
            .map(|n| vem_cli::status_label(n.status, self.frictionless))
            .collect()
    }

    /// The statuses as integers (0 open, 1 contact, 2 stick, 3 slip), (k,).
    #[getter]
    fn status_code<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i32>> {
        let code = |n: &PairNode| match n.status {
            NodeStatus::Open => 0,
            NodeStatus::Slip if self.frictionless => 1,
            NodeStatus::Contact => 1,
            NodeStatus::Stick => 2,
            NodeStatus::Slip => 3,
        };
        Array1::from_iter(self.nodes.iter().map(code)).into_pyarray(py)
    }

    /// Body A's vertex of every node, (k,).
    #[getter]
    fn vertex_a<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<usize>> {
        Array1::from_iter(self.nodes.iter().map(|n| n.vertex_a)).into_pyarray(py)
    }

    /// The sum of the nodal normal forces.
    #[getter]
    fn normal_resultant(&self) -> f64 {
        self.nodes.iter().map(|n| n.normal_force).sum()
    }

    fn __repr__(&self) -> String {
        let active = self
            .nodes
            .iter()
            .filter(|n| n.status != NodeStatus::Open)
            .count();
        format!(
            "ContactPair(index={}, nodes={}, active={active}, law={})",
            self.index,
            self.nodes.len(),
            quote(&self.law)
        )
    }
}

/// A value of the library serialised to JSON and read back as Python dicts and lists.
fn to_python<'py>(py: Python<'py>, value: &impl serde::Serialize) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(value)
        .map_err(|e| PyRuntimeError::new_err(format!("a report does not serialise: {e}")))?;
    py.import("json")?.call_method1("loads", (text,))
}

/// One step of a load history: its pseudo-time, the bodies in contact and the pairs at the
/// end of the step, and the solver's report of the step.
#[pyclass(module = "vemcontact", name = "Step", frozen)]
struct PyStep {
    index: usize,
    time: f64,
    bodies: Vec<Py<PyBody>>,
    pairs: Vec<Py<PyPair>>,
    report: Py<PyAny>,
}

#[pymethods]
impl PyStep {
    /// The step's index (from 0).
    #[getter]
    fn index(&self) -> usize {
        self.index
    }

    /// The step's pseudo-time.
    #[getter]
    fn time(&self) -> f64 {
        self.time
    }

    /// The bodies in contact at the end of the step (bodies without contact are solved once,
    /// at the last step's load).
    #[getter]
    fn bodies(&self, py: Python<'_>) -> Vec<Py<PyBody>> {
        self.bodies.iter().map(|b| b.clone_ref(py)).collect()
    }

    /// The contact pairs at the end of the step.
    #[getter]
    fn pairs(&self, py: Python<'_>) -> Vec<Py<PyPair>> {
        self.pairs.iter().map(|p| p.clone_ref(py)).collect()
    }

    /// The contact solver's report of the step (status, iterations, KKT residuals,
    /// warnings), as a dict.
    #[getter]
    fn report(&self, py: Python<'_>) -> Py<PyAny> {
        self.report.clone_ref(py)
    }

    fn __repr__(&self) -> String {
        format!("Step(index={}, time={})", self.index, self.time)
    }
}

/// The result of a solve: every body, every contact pair, the summary and reports, every
/// step of a load history; `write(dir)` writes the outputs of the `vem` command.
#[pyclass(module = "vemcontact", name = "Result")]
struct PyResultSet {
    outcome: vem_cli::Outcome,
    bodies: Vec<Py<PyBody>>,
    pairs: Vec<Py<PyPair>>,
    steps: Vec<Py<PyStep>>,
    summary: Py<PyAny>,
}

impl PyResultSet {
    fn new(py: Python<'_>, outcome: vem_cli::Outcome) -> PyResult<Self> {
        let mut bodies = Vec::new();
        for b in &outcome.bodies {
            let body = PyBody::new(py, &b.body, &b.solution, b.fields.clone())?;
            bodies.push(Py::new(py, body)?);
        }
        for b in &outcome.bodies_3d {
            let body = PyBody::new_3d(py, &b.body, &b.solution, b.fields.clone())?;
            bodies.push(Py::new(py, body)?);
        }
        let pairs = match (&outcome.contact, &outcome.contact_3d) {
            (Some(result), _) => pairs_of(result),
            (None, Some(result)) => pairs_of(result),
            (None, None) => Vec::new(),
        };
        let pairs = pairs
            .into_iter()
            .map(|p| Py::new(py, p))
            .collect::<PyResult<Vec<_>>>()?;
        let mut steps = Vec::new();
        for step in &outcome.steps {
            let mut step_bodies = Vec::new();
            for b in &step.result.bodies {
                let fields = b
                    .body
                    .element_fields(b.solution.displacement())
                    .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
                step_bodies.push(Py::new(py, PyBody::new(py, &b.body, &b.solution, fields)?)?);
            }
            let step_pairs = pairs_of(&step.result)
                .into_iter()
                .map(|p| Py::new(py, p))
                .collect::<PyResult<Vec<_>>>()?;
            steps.push(Py::new(
                py,
                PyStep {
                    index: step.index,
                    time: step.time,
                    bodies: step_bodies,
                    pairs: step_pairs,
                    report: to_python(py, &step.result.report)?.unbind(),
                },
            )?);
        }
        for step in &outcome.steps_3d {
            let mut step_bodies = Vec::new();
            for b in &step.result.bodies {
                let fields = b
                    .body
                    .element_fields(b.solution.displacement())
                    .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
                step_bodies.push(Py::new(
                    py,
                    PyBody::new_3d(py, &b.body, &b.solution, fields)?,
                )?);
            }
            let step_pairs = pairs_of(&step.result)
                .into_iter()
                .map(|p| Py::new(py, p))
                .collect::<PyResult<Vec<_>>>()?;
            steps.push(Py::new(
                py,
                PyStep {
                    index: step.index,
                    time: step.time,
                    bodies: step_bodies,
                    pairs: step_pairs,
                    report: to_python(py, &step.result.report)?.unbind(),
                },
            )?);
        }
        // The last step is the outcome itself.
        let report = match (&outcome.contact, &outcome.contact_3d) {
            (Some(contact), _) => Some(&contact.report),
            (None, Some(contact)) => Some(&contact.report),
            (None, None) => None,
        };
        if let (Some(report), Some(last)) = (
            report,
            outcome
                .summary
                .contact
                .as_ref()
                .and_then(|c| c.history.last()),
        ) {
            let step_bodies = outcome
                .contact_bodies
                .iter()
                .map(|&i| bodies[i].clone_ref(py))
                .collect();
            steps.push(Py::new(
                py,
                PyStep {
                    index: outcome.steps.len() + outcome.steps_3d.len(),
                    time: last.time,
                    bodies: step_bodies,
                    pairs: pairs.iter().map(|p| p.clone_ref(py)).collect(),
                    report: to_python(py, report)?.unbind(),
                },
            )?);
        }
        let summary = to_python(py, outcome.summary())?.unbind();
        Ok(Self {
            outcome,
            bodies,
            pairs,
            steps,
            summary,
        })
    }
}

#[pymethods]
impl PyResultSet {
    /// Every body, in the order of the scene.
    #[getter]
    fn bodies(&self, py: Python<'_>) -> Vec<Py<PyBody>> {
        self.bodies.iter().map(|b| b.clone_ref(py)).collect()
    }

    /// The body named `name`; `KeyError` when there is none.
    fn body(&self, py: Python<'_>, name: &str) -> PyResult<Py<PyBody>> {
        self.bodies
            .iter()
            .find(|b| b.get().name == name)
            .map(|b| b.clone_ref(py))
            .ok_or_else(|| {
                let names: Vec<&str> = self.bodies.iter().map(|b| b.get().name.as_str()).collect();
                pyo3::exceptions::PyKeyError::new_err(format!(
                    "no body '{name}'; the bodies are {}",
                    names.join(", ")
                ))
            })
    }

    /// The body named `name` as a `meshio.Mesh` (see `BodyResult.to_meshio`).
    fn to_meshio<'py>(&self, py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyAny>> {
        let body = self.body(py, name)?.into_bound(py);
        py.import("vemcontact._meshio")?
            .call_method1("body_to_meshio", (body,))
    }

    /// The contact pairs, in the order of the scene (empty without contact).
    #[getter]
    fn pairs(&self, py: Python<'_>) -> Vec<Py<PyPair>> {
        self.pairs.iter().map(|p| p.clone_ref(py)).collect()
    }

    /// The steps of a load history of several steps, the last one included (empty for a
    /// single solve).
    #[getter]
    fn steps(&self, py: Python<'_>) -> Vec<Py<PyStep>> {
        self.steps.iter().map(|s| s.clone_ref(py)).collect()
    }

    /// Everything the run reports (what `summary.json` holds): bodies, DOFs, reactions,
    /// the contact model, solver, report, work, resultants, Hertz comparisons, history,
    /// times.
    #[getter]
    fn summary(&self, py: Python<'_>) -> Py<PyAny> {
        self.summary.clone_ref(py)
    }

    /// The contact solver's report of the (last) solve as a dict: `solver`, `status`,
    /// `iterations`, `residuals` (the KKT residuals), `warnings`; `None` without contact.
    #[getter]
    fn report<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        self.outcome
            .contact
            .as_ref()
            .map(|c| to_python(py, &c.report))
            .transpose()
    }

    /// Every warning of the run, one sentence each: the bodies' (a locking element near
    /// incompressibility), the contact's (solver and model), an adaptive refinement stopped
    /// by a limit before its target, earlier keys of the scene.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        let summary = self.outcome.summary();
        let mut all: Vec<String> = summary
            .bodies
            .iter()
            .flat_map(|b| b.warnings.iter().map(|w| format!("body '{}': {w}", b.name)))
            .collect();
        if let Some(c) = &summary.contact {
            all.extend(c.warnings.iter().cloned());
        }
        if let Some(w) = summary.adaptivity.as_ref().and_then(|a| a.warning.as_ref()) {
            all.push(w.clone());
        }
        all.extend(summary.deprecations.iter().map(|d| d.to_string()));
        all
    }

    /// Writes the outputs of the `vem` command into `dir` (VTU per body, interface.vtu,
    /// results.pvd, contact.csv, SVG pictures, summary.json; per step with a history) and
    /// returns the paths written. `files` (some of "vtu", "csv", "pictures") and
    /// `vtu_encoding` ("binary", "compressed", "ascii") replace the scene's `[output] files`
    /// and `vtu_encoding` for this call. The folder is replaced whole; one holding other files
    /// is refused (`OutputError`).
    #[pyo3(signature = (dir, *, files = None, vtu_encoding = None))]
    fn write(
        &mut self,
        py: Python<'_>,
        dir: PathBuf,
        files: Option<&Bound<'_, PyAny>>,
        vtu_encoding: Option<String>,
    ) -> PyResult<Vec<PathBuf>> {
        let encoding: Option<vem_scene::VtuEncodingName> = vtu_encoding
            .as_deref()
            .map(|name| output_name("vtu_encoding", name))
            .transpose()?;
        let names: Option<Vec<String>> = files
            .map(|files| {
                if files.is_instance_of::<pyo3::types::PyString>() {
                    return Err(not_a_list_of_kinds(files));
                }
                files.extract().map_err(|_| not_a_list_of_kinds(files))
            })
            .transpose()?;
        let kinds: Option<Vec<vem_scene::OutputFiles>> = names
            .as_deref()
            .map(|names| names.iter().map(|n| output_name("files", n)).collect())
            .transpose()?;
        let outcome = &mut self.outcome;
        let scene_settings = outcome.output_settings();
        if let Some(encoding) = encoding {
            outcome.set_vtu_encoding(encoding);
        }
        if let Some(kinds) = &kinds {
            outcome.set_files(kinds);
        }
        let written = py.detach(|| catch_unwind(AssertUnwindSafe(|| outcome.write(&dir))));
        outcome.set_output_settings(scene_settings);
        match written {
            Err(payload) => Err(panic_error(py, payload)),
            Ok(Ok(files)) => Ok(files),
            Ok(Err(e)) => {
                let class = py.import("vemcontact._errors")?.getattr("OutputError")?;
                Err(PyErr::from_value(
                    class.call1((vem_scene::one_line(&e), dir))?,
                ))
            }
        }
    }

    fn __repr__(&self) -> String {
        let summary = self.outcome.summary();
        let contact = summary.contact.as_ref().map_or_else(
            || "no contact".to_string(),
            |c| {
                format!(
                    "solver {}: {}, {} iterations",
                    c.report.solver,
                    c.report.status.describe(),
                    c.report.iterations
                )
            },
        );
        format!(
            "Result(title={}, bodies={}, pairs={}, steps={}, {contact})",
            quote(&summary.title),
            self.bodies.len(),
            self.pairs.len(),
            self.steps.len()
        )
    }

    fn __str__(&self) -> String {
        self.outcome.summary().to_string()
    }
}

/// A key path of a one-body scene (`body[0].mesh.polygons[3]`) as the path in the mesh
/// description the user gave (`polygons[3]`).
fn mesh_path(path: &KeyPath) -> KeyPath {
    let prefix = [
        Segment::Key("body".into()),
        Segment::Index(0),
        Segment::Key("mesh".into()),
    ];
    if path.0.starts_with(&prefix) {
        KeyPath(path.0[prefix.len()..].to_vec())
    } else {
        path.clone()
    }
}

/// The error of a `files` argument that is not a list of strings.
fn not_a_list_of_kinds(files: &Bound<'_, PyAny>) -> PyErr {
    let shown = files
        .repr()
        .map_or_else(|_| "this".to_string(), |r| r.to_string());
    pyo3::exceptions::PyTypeError::new_err(format!(
        "files: give a list of kinds (some of \"vtu\", \"csv\", \"pictures\"), not {shown}"
    ))
}

/// The setting of the scene's `[output]` table named `name` (an error naming `what` and the
/// choices when it names none).
fn output_name<T: std::str::FromStr<Err = String>>(what: &str, name: &str) -> PyResult<T> {
    name.parse()
        .map_err(|e| pyo3::exceptions::PyValueError::new_err(format!("{what}: {e}")))
}

/// Builds the mesh of the mesh description `description` (the keys of a body's `mesh`:
/// generated, a file relative to `base`, or given inline), validated as a scene's.
///
/// Raises `SceneError` at the key path in `description` (`polygons[3]`) with the located
/// message of the library (naming the cell and the vertex).
#[pyfunction]
#[pyo3(signature = (description, base = None))]
fn mesh(py: Python<'_>, description: &Bound<'_, PyAny>, base: Option<PathBuf>) -> PyResult<PyMesh> {
    let origin = Origin::Value;
    let refuse = |e: SceneError| {
        let error = SceneError {
            path: mesh_path(&e.path),
            ..e
        };
        scene_error(py, "SceneError", &origin, &error)
    };
    let value = to_value(description, &KeyPath::key("body").index(0).at("mesh")).map_err(refuse)?;
    let scene_of = |plane: bool| {
        let mut material = serde_json::json!({ "E": 1.0, "nu": 0.25 });
        if plane {
            material["plane"] = Value::from("strain");
        }
        vem_scene::Scene::from_value(serde_json::json!({
            "body": [{ "name": "mesh", "mesh": value.clone(), "material": material }]
        }))
    };
    let scene = scene_of(true).map_err(refuse)?;
    let scene = if vem_scene::check::declared_dimension(&scene.bodies[0]) == Some(3) {
        scene_of(false).map_err(refuse)?
    } else {
        scene
    };
    let base = base.unwrap_or_default();
    let built =
        py.detach(|| catch_unwind(AssertUnwindSafe(|| vem_scene::body_mesh(&scene, 0, &base))));
    match built {
        Err(payload) => Err(panic_error(py, payload)),
        Ok(Err(e)) => Err(refuse(e)),
        Ok(Ok((built, source))) => Ok(PyMesh::new(&built, source)),
    }
}

/// A mesh in the plane (polygons) or in space (polyhedra) with its named boundary parts: made
/// by `vemcontact.mesh(description)`, `vemcontact.generate(...)`, `vemcontact.from_meshio(m)`
/// or read off a result (`BodyResult.mesh`, the mesh solved, interface nodes inserted).
///
/// Arrays: `vertices` (n, 2) or (n, 3); `cell_offsets` and `cell_connectivity` (the polygons'
/// vertex loops, or the polyhedra's vertices); `cells` (polygons: a list of index arrays;
/// polyhedra: a list of lists of outward face loops); `parts` (name -> (k, 2) edges, or a
/// list of face loops). `to_dict()` is the mesh as the keys of a mesh given inline, for a
/// scene.
#[pyclass(module = "vemcontact", name = "Mesh", frozen)]
struct PyMesh {
    description: vem_scene::MeshDescription,
    dimension: usize,
    source: String,
}

impl PyMesh {
    fn new(mesh: &vem_scene::BuiltMesh, source: String) -> Self {
        Self {
            description: mesh.to_inline(),
            dimension: mesh.dimension(),
            source,
        }
    }

    fn vertex_list(&self) -> &[Vec<f64>] {
        self.description.vertices.as_deref().unwrap_or_default()
    }

    /// The vertex lists of the cells: a polygon's loop, a polyhedron's distinct vertices in
    /// increasing order.
    fn cell_vertex_lists(&self) -> Vec<Vec<usize>> {
        match (&self.description.polygons, &self.description.polyhedra) {
            (Some(polygons), _) => polygons.clone(),
            (None, Some(polyhedra)) => polyhedra
                .iter()
                .map(|faces| {
                    let mut all: Vec<usize> = faces.iter().flatten().copied().collect();
                    all.sort_unstable();
                    all.dedup();
                    all
                })
                .collect(),
            (None, None) => Vec::new(),
        }
    }
}

#[pymethods]
impl PyMesh {
    /// 2 (polygons in the plane) or 3 (polyhedra in space).
    #[getter]
    fn dimension(&self) -> usize {
        self.dimension
    }

    /// Where the mesh came from, in words ("voronoi, n = 8, seed 1, on [0, 1] x [0, 1]").
    #[getter]
    fn source(&self) -> String {
        self.source.clone()
    }

    /// The number of vertices.
    #[getter]
    fn n_vertices(&self) -> usize {
        self.vertex_list().len()
    }

    /// The number of cells (polygons or polyhedra).
    #[getter]
    fn n_cells(&self) -> usize {
        match (&self.description.polygons, &self.description.polyhedra) {
            (Some(p), _) => p.len(),
            (None, Some(p)) => p.len(),
            (None, None) => 0,
        }
    }

    /// Vertex coordinates, (n, 2) or (n, 3).
    #[getter]
    fn vertices<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let flat = self.vertex_list().iter().flatten().copied().collect();
        matrix(py, self.vertex_list().len(), self.dimension, flat)
    }

    /// The cells: polygons as arrays of vertex indices (counter-clockwise), polyhedra as
    /// lists of face loops (arrays of vertex indices, outward).
    #[getter]
    fn cells<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let list = PyList::empty(py);
        if let Some(polygons) = &self.description.polygons {
            for polygon in polygons {
                list.append(PyArray1::from_slice(py, polygon))?;
            }
        }
        if let Some(polyhedra) = &self.description.polyhedra {
            for faces in polyhedra {
                let faces: Vec<_> = faces.iter().map(|f| PyArray1::from_slice(py, f)).collect();
                list.append(PyList::new(py, faces)?)?;
            }
        }
        Ok(list)
    }

    /// Where each cell starts in `cell_connectivity` (m + 1 entries).
    #[getter]
    fn cell_offsets<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<usize>> {
        let mut offsets = vec![0];
        for cell in self.cell_vertex_lists() {
            offsets.push(offsets[offsets.len() - 1] + cell.len());
        }
        PyArray1::from_vec(py, offsets)
    }

    /// The vertex indices of every cell, one after the other: a polygon's loop
    /// (counter-clockwise), a polyhedron's distinct vertices (increasing).
    #[getter]
    fn cell_connectivity<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<usize>> {
        PyArray1::from_vec(py, self.cell_vertex_lists().concat())
    }

    /// The named boundary parts: in the plane name -> (k, 2) array of edges (vertex pairs);
    /// in space name -> list of face loops.
    #[getter]
    fn parts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let dict = PyDict::new(py);
        for (name, edges) in &self.description.part_edges {
            let flat: Vec<usize> = edges.iter().flatten().copied().collect();
            let array = Array2::from_shape_vec((edges.len(), 2), flat)
                .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
            dict.set_item(name, array.into_pyarray(py))?;
        }
        for (name, faces) in &self.description.part_faces {
            let faces: Vec<_> = faces.iter().map(|f| PyArray1::from_slice(py, f)).collect();
            dict.set_item(name, PyList::new(py, faces)?)?;
        }
        Ok(dict)
    }

    /// The mesh as a `meshio.Mesh` (needs the package meshio): the cells in order, the parts
    /// as boundary cell blocks named by `cell_sets`.
    fn to_meshio<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyAny>> {
        slf.py()
            .import("vemcontact._meshio")?
            .call_method1("mesh_to_meshio", (slf,))
    }

    /// The mesh as the keys of a mesh given inline (`vertices`, `polygons` or `polyhedra`,
    /// `part_edges` or `part_faces`): a body's `mesh` in a scene dict.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_python(py, &self.description)
    }

    fn __repr__(&self) -> String {
        format!(
            "Mesh(dimension={}, vertices={}, cells={}, parts=[{}])",
            self.dimension,
            self.n_vertices(),
            self.n_cells(),
            self.description
                .part_edges
                .keys()
                .chain(self.description.part_faces.keys())
                .map(|n| quote(n))
                .collect::<Vec<_>>()
                .join(", ")
        )
    }
}

/// The names the scenes accept, read from the library's registries: `solvers`, `elements`,
/// `laws`, `accuracy_presets`, `mesh_families` (of a `rectangle`) and
/// `mesh_families_3d` (of a `box`).
#[pyfunction]
fn names<'py>(py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
    let registries = vem_scene::Registries::default();
    let dict = PyDict::new(py);
    dict.set_item("solvers", registries.solvers.names())?;
    dict.set_item("elements", registries.elements.names())?;
    dict.set_item("laws", registries.laws.names())?;
    dict.set_item(
        "accuracy_presets",
        vem_contact::AccuracyPreset::ALL
            .iter()
            .map(|p| p.name())
            .collect::<Vec<_>>(),
    )?;
    dict.set_item(
        "mesh_families",
        vem_mesh::generators::MeshFamily::all()
            .iter()
            .map(|f| f.name())
            .collect::<Vec<_>>(),
    )?;
    dict.set_item(
        "mesh_families_3d",
        vem_mesh::generators::polyhedral::PolyhedralFamily::all()
            .iter()
            .map(|f| f.name())
            .collect::<Vec<_>>(),
    )?;
    Ok(dict)
}

/// A study's failure as the package's exception: a name the registries lack or a setting
/// refused as `ValueError`, a computation that fails as `SolveError`.
fn study_error(py: Python<'_>, error: vem_verify::VerifyError) -> PyErr {
    use vem_verify::VerifyError as E;
    match error {
        E::InvalidSetting { .. } | E::Exact(_) | E::Solver { .. } => {
            pyo3::exceptions::PyValueError::new_err(vem_scene::one_line(&error))
        }
        other => scene_error(
            py,
            "SolveError",
            &Origin::Value,
            &SceneError::at(KeyPath::root(), vem_scene::one_line(&other)),
        ),
    }
}

/// Runs the convergence study of the case `case` (a name of the case registry: M1..M4, E1,
/// E2, PT0a, ...) on the mesh pairing `pairing` ("quads/quads*3", "voronoi/quads", "quads")
/// at the sizes `sizes`, with the contact solver `solver` and the element `element`, with
/// the GIL released; judged by the case's expectation (its registry's, else the optimal
/// rates). Returns the study's result as a dict (what `convergence.json` holds per study:
/// records per size, fitted rates, verdict).
#[pyfunction]
#[pyo3(signature = (case, pairing, sizes, solver = None, element = None, seed = None))]
fn convergence_study<'py>(
    py: Python<'py>,
    case: &str,
    pairing: &str,
    sizes: Vec<usize>,
    solver: Option<String>,
    element: Option<String>,
    seed: Option<u64>,
) -> PyResult<Bound<'py, PyAny>> {
    use vem_verify::study::{Expectation, Study};
    let cases = vem_verify::cases::CaseRegistry::builtin();
    let exact = cases
        .make(case, vem_verify::exact::Lame::default())
        .map_err(|e| study_error(py, e.into()))?;
    let expectation = cases
        .expectation(exact.name())
        .unwrap_or(Expectation::OPTIMAL_RATES);
    let pairing: vem_verify::study::MeshPairing =
        pairing.parse().map_err(|e| study_error(py, e))?;
    let element = vem_space::ElementRegistry::builtin()
        .make(
            element
                .as_deref()
                .unwrap_or(vem_space::ElementRegistry::DEFAULT),
        )
        .map_err(|e| pyo3::exceptions::PyValueError::new_err(e.to_string()))?;
    let mut study = Study::new(exact, pairing)
        .sizes(sizes)
        .element(element)
        .expect(expectation);
    if let Some(solver) = solver {
        study = study.solver(solver);
    }
    if let Some(seed) = seed {
        study = study.seed(seed);
    }
    let run = py.detach(|| catch_unwind(AssertUnwindSafe(|| study.run())));
    match run {
        Err(payload) => Err(panic_error(py, payload)),
        Ok(Err(e)) => Err(study_error(py, e)),
        Ok(Ok(result)) => to_python(py, &result),
    }
}

/// The studies of the project's convergence run in the plane for the cases `cases` (default
/// M1, M2, E1), quick or full: a list of dicts `{case, pairing, sizes}` (the same plan as
/// `cargo xtask convergence`).
#[pyfunction]
#[pyo3(signature = (quick = true, cases = None))]
fn convergence_plan<'py>(
    py: Python<'py>,
    quick: bool,
    cases: Option<Vec<String>>,
) -> PyResult<Bound<'py, PyList>> {
    let registry = vem_verify::cases::CaseRegistry::builtin();
    let names = cases.unwrap_or_else(|| {
        vem_verify::plan::DEFAULT_CASES
            .iter()
            .map(|c| c.to_string())
            .collect()
    });
    let list = PyList::empty(py);
    for name in &names {
        let planned = vem_verify::plan::planned_studies(name, quick, &registry)
            .map_err(|e| study_error(py, e.into()))?;
        for study in planned {
            let item = PyDict::new(py);
            item.set_item("case", &study.case)?;
            item.set_item("pairing", study.pairing)?;
            item.set_item("sizes", study.sizes.to_vec())?;
            list.append(item)?;
        }
    }
    Ok(list)
}

/// The solver settings of the trade-off study: the quick ones or the full ones (labels such
/// as "draft", "exact", "penalty@factor=1e6").
#[pyfunction]
#[pyo3(signature = (quick = true))]
fn tradeoff_settings(quick: bool) -> Vec<&'static str> {
    if quick {
        vem_verify::tradeoff::QUICK_SETTINGS.to_vec()
    } else {
        vem_verify::tradeoff::FULL_SETTINGS.to_vec()
    }
}

/// One group of the trade-off study: the manufactured case `case` (M1, M2, E1, ...) on
/// `pairing` at size `n` with `element`, discretised once and solved with every setting of
/// `settings` (labels of `tradeoff_settings`), with the GIL released. Returns one dict per
/// setting: `setting`, `solver`, `status`, `error`, `n`, `h`, `unknowns`, `contact_rows`,
/// `iterations`, the errors `e_grad`, `e_0`, `e_a`, `pressure_l2`, `pressure_max`,
/// `resultant`, `misclassified`, and the seconds `mesh_generation`, `discretisation`,
/// `solve`, `errors`.
#[pyfunction]
#[pyo3(signature = (case, pairing, n, settings, element = None))]
fn tradeoff_group<'py>(
    py: Python<'py>,
    case: &str,
    pairing: &str,
    n: usize,
    settings: Vec<String>,
    element: Option<String>,
) -> PyResult<Bound<'py, PyAny>> {
    use vem_verify::tradeoff::{SolverSetting, TradeoffGroup};
    let settings = settings
        .iter()
        .map(|s| s.parse::<SolverSetting>())
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| study_error(py, e))?;
    let element = element.unwrap_or_else(|| vem_space::ElementRegistry::DEFAULT.to_string());
    let run = py.detach(|| {
        catch_unwind(AssertUnwindSafe(
            || -> Result<Vec<Value>, vem_verify::VerifyError> {
                let group = TradeoffGroup::build(case, pairing, &element, n)?;
                let base = serde_json::json!({
                    "case": case, "pairing": pairing, "element": element, "n": n,
                    "h": group.h, "mesh_generation": group.mesh_generation,
                });
                let mut rows = Vec::new();
                let Some(discretisation) = group.discretisation() else {
                    // Elasticity: one Cholesky solve per body, whatever the settings.
                    let solution = group
                        .problem()
                        .solve(&mut vem_contact::CondensedSolver::default())?;
                    let start = std::time::Instant::now();
                    let errors = group.elasticity_errors(&solution)?;
                    let mut row = base.clone();
                    row["setting"] = "cholesky".into();
                    row["solver"] = "cholesky".into();
                    row["status"] = "Solved".into();
                    row["unknowns"] = solution
                        .bodies
                        .iter()
                        .map(|b| b.system.dofs().n_free())
                        .sum::<usize>()
                        .into();
                    row["discretisation"] = solution.assembly_time.as_secs_f64().into();
                    row["solve"] = solution.solve_time.as_secs_f64().into();
                    row["errors"] = start.elapsed().as_secs_f64().into();
                    merge(&mut row, serde_json::to_value(errors).unwrap_or_default());
                    rows.push(row);
                    return Ok(rows);
                };
                let work = discretisation.work();
                for setting in &settings {
                    let mut row = base.clone();
                    row["setting"] = setting.label.clone().into();
                    row["solver"] = setting.solver.clone().into();
                    row["unknowns"] = discretisation.n_dofs().into();
                    row["contact_rows"] = discretisation.normal_rows().nrows().into();
                    row["discretisation"] = (work.times.insertion + work.times.assembly)
                        .as_secs_f64()
                        .into();
                    let mut solver = setting.make()?;
                    let start = std::time::Instant::now();
                    match discretisation.solve(solver.as_mut()) {
                        Ok(result) => {
                            row["solve"] = start.elapsed().as_secs_f64().into();
                            row["iterations"] = result
                                .fixed_point
                                .as_ref()
                                .map_or(result.report.iterations, |fp| fp.solver_iterations)
                                .into();
                            row["status"] = format!("{:?}", result.report.status).into();
                            let start = std::time::Instant::now();
                            let errors = group.errors(result)?;
                            row["errors"] = start.elapsed().as_secs_f64().into();
                            merge(&mut row, serde_json::to_value(errors).unwrap_or_default());
                        }
                        Err(error) => {
                            row["solve"] = start.elapsed().as_secs_f64().into();
                            row["status"] = "failed".into();
                            row["error"] = vem_scene::one_line(&error).into();
                        }
                    }
                    rows.push(row);
                }
                Ok(rows)
            },
        ))
    });
    match run {
        Err(payload) => Err(panic_error(py, payload)),
        Ok(Err(e)) => Err(study_error(py, e)),
        Ok(Ok(rows)) => to_python(py, &rows),
    }
}

/// The keys of the object `extra` set on the object `row`.
fn merge(row: &mut Value, extra: Value) {
    if let (Some(row), Value::Object(extra)) = (row.as_object_mut(), extra) {
        row.extend(extra);
    }
}

/// The native module `vemcontact._native`.
#[pymodule(name = "_native")]
mod native {
    #[pymodule_export]
    use super::{
        convergence_plan, convergence_study, from_dict, load, loads, mesh, names, tradeoff_group,
        tradeoff_settings, PyBody, PyMesh, PyPair, PyResultSet, PyScene, PyStep,
    };
}
