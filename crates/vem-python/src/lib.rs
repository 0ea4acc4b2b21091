//! The native part of the Python package `vemcontact`: a scene read from a TOML file, a TOML
//! text or a Python dict into the problem description of `vem_scene` (the same keys, checks
//! and located errors as the `vem` command), solved with the GIL released, and the results as
//! numpy arrays. The package's Python part (`python/vemcontact`) adds the builders, the
//! exception and warning classes and the documentation users read; docs/python.md shows it
//! at work.
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
        let scene = &self.scene;
        let built = py.detach(|| {
            catch_unwind(AssertUnwindSafe(|| {
                let model = vem_scene::Model::build(scene, &options).map_err(|e| ("build", e))?;
                let outcome = model.solve().map_err(|e| ("solve", e))?;
                Ok::<_, (&str, SceneError)>(vem_cli::Outcome::new(outcome, &model))
            }))
        });
        let outcome = match built {
            Err(payload) => return Err(panic_error(py, payload)),
            Ok(Err(("build", e))) => return Err(scene_error(py, "SceneError", &self.origin, &e)),
            Ok(Err((_, e))) => return Err(scene_error(py, "SolveError", &self.origin, &e)),
            Ok(Ok(outcome)) => outcome,
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

/// One body after the solve (or after one step of a load history).
///
/// Arrays: `vertices` (n, 2), `displacement` (n, 2) at the vertices, the polygons as
/// `cells` (a list of index arrays) or `cell_offsets`/`cell_connectivity`, and per element
/// `stress` and `strain` (m, 3, 3; plane strain has `stress[:, 2, 2] = lambda tr(eps)`) and
/// `von_mises` (m,). The mesh is the one solved: a body in contact has the interface nodes
/// inserted into its contact part.
#[pyclass(module = "vemcontact", name = "BodyResult", frozen)]
struct PyBody {
    name: String,
    vertices: Vec<f64>,
    offsets: Vec<usize>,
    connectivity: Vec<usize>,
    displacement: Vec<f64>,
    fields: Vec<ElementField>,
    strain_energy: f64,
    reactions: Vec<(String, Vec<f64>)>,
}

impl PyBody {
    fn new(
        body: &vem_elastic::ElasticBody,
        solution: &vem_elastic::Solution,
        fields: Vec<ElementField>,
    ) -> Self {
        let mesh = body.mesh();
        let mut offsets = vec![0];
        let mut connectivity = Vec::new();
        for polygon in mesh.polygons() {
            connectivity.extend_from_slice(polygon);
            offsets.push(connectivity.len());
        }
        Self {
            name: body.name().to_string(),
            vertices: mesh.vertices().iter().flat_map(|p| [p.x, p.y]).collect(),
            offsets,
            connectivity,
            displacement: solution.displacement().to_vec(),
            fields,
            strain_energy: solution.strain_energy(),
            reactions: solution
                .reactions()
                .iter()
                .map(|r| (r.part.clone(), r.force.iter().copied().collect()))
                .collect(),
        }
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

    /// Vertex coordinates, (n, 2).
    #[getter]
    fn vertices<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        matrix(py, self.vertices.len() / 2, 2, self.vertices.clone())
    }

    /// Nodal displacement, (n, 2), in the order of `vertices`.
    #[getter]
    fn displacement<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        matrix(
            py,
            self.displacement.len() / 2,
            2,
            self.displacement.clone(),
        )
    }

    /// The polygons: a list of arrays of vertex indices, counter-clockwise.
    #[getter]
    fn cells<'py>(&self, py: Python<'py>) -> Vec<Bound<'py, PyArray1<usize>>> {
        self.offsets
            .windows(2)
            .map(|w| PyArray1::from_slice(py, &self.connectivity[w[0]..w[1]]))
            .collect()
    }

    /// Where each polygon starts in `cell_connectivity` (m + 1 entries).
    #[getter]
    fn cell_offsets<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<usize>> {
        PyArray1::from_slice(py, &self.offsets)
    }

    /// The vertex indices of every polygon, one after the other.
    #[getter]
    fn cell_connectivity<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<usize>> {
        PyArray1::from_slice(py, &self.connectivity)
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
        format!(
            "BodyResult(name={}, vertices={}, cells={}, strain_energy={:.6e})",
            quote(&self.name),
            self.vertices.len() / 2,
            self.offsets.len() - 1,
            self.strain_energy
        )
    }
}

/// The interface nodes of one contact pair, in their order along body A's contact part.
///
/// Arrays (k nodes): `positions` (k, 2) on body A, `normals` (k, 2), `tributary` (k,) the
/// node's length, `initial_gap`, `normal_jump` (`[u].nu`), `gap` (`initial_gap -
/// normal_jump`, >= 0 up to the solver's tolerance), `normal_force` (compression
/// positive), `pressure` (`normal_force / tributary`), `consistent_pressure`,
/// `friction_force` (k, 2) on body A, `friction` (k,) its tangential component,
/// `friction_traction` (k, 2), `slip` (k, 2), `tangential_slip` (k,), `status` (a list of
/// "open", "contact", "stick", "slip", as contact.csv writes it) and `status_code` (k,) (0
/// open, 1 contact, 2 stick, 3 slip, as interface.vtu writes it).
#[pyclass(module = "vemcontact", name = "ContactPair", frozen)]
struct PyPair {
    index: usize,
    description: String,
    law: String,
    nodes: Vec<InterfaceNode>,
    frictionless: bool,
}

impl PyPair {
    fn scalars<'py>(
        &self,
        py: Python<'py>,
        of: impl Fn(&InterfaceNode) -> f64,
    ) -> Bound<'py, PyArray1<f64>> {
        Array1::from_iter(self.nodes.iter().map(|n| of(n) + 0.0)).into_pyarray(py)
    }

    fn vectors<'py>(
        &self,
        py: Python<'py>,
        of: impl Fn(&InterfaceNode) -> vem_mesh::Vector,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let flat = self
            .nodes
            .iter()
            .flat_map(|n| {
                let v = of(n);
                [v.x + 0.0, v.y + 0.0]
            })
            .collect();
        matrix(py, self.nodes.len(), 2, flat)
    }
}

/// The pairs of a contact result, each with its nodes.
fn pairs_of(result: &vem_contact::ContactResult) -> Vec<PyPair> {
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
            nodes: result.nodes[pair.nodes.clone()].to_vec(),
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

    /// Node positions on body A (reference configuration), (k, 2).
    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.vectors(py, |n| n.position.coords)
    }

    /// The contact normals, (k, 2).
    #[getter]
    fn normals<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.vectors(py, |n| n.normal)
    }

    /// The nodes' tributary lengths, (k,).
    #[getter]
    fn tributary<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.scalars(py, |n| n.tributary_measure)
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

    /// The nodal friction forces on body A, (k, 2).
    #[getter]
    fn friction_force<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.vectors(py, |n| n.friction_force)
    }

    /// The friction forces' components along the tangent `(-n_y, n_x)`, (k,).
    #[getter]
    fn friction<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.scalars(py, InterfaceNode::friction_t)
    }

    /// The consistent friction tractions, (k, 2).
    #[getter]
    fn friction_traction<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.vectors(py, |n| n.consistent_friction_traction)
    }

    /// The slips (tangential part of `u_A - u_B`; zero without friction), (k, 2).
    #[getter]
    fn slip<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.vectors(py, |n| n.slip)
    }

    /// The slips along the tangent, (k,).
    #[getter]
    fn tangential_slip<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.scalars(py, InterfaceNode::slip_t)
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
        let code = |n: &InterfaceNode| match n.status {
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
        let bodies = outcome
            .bodies
            .iter()
            .map(|b| Py::new(py, PyBody::new(&b.body, &b.solution, b.fields.clone())))
            .collect::<PyResult<Vec<_>>>()?;
        let pairs = match &outcome.contact {
            Some(result) => pairs_of(result)
                .into_iter()
                .map(|p| Py::new(py, p))
                .collect::<PyResult<Vec<_>>>()?,
            None => Vec::new(),
        };
        let mut steps = Vec::new();
        for step in &outcome.steps {
            let mut step_bodies = Vec::new();
            for b in &step.result.bodies {
                let fields = b
                    .body
                    .element_fields(b.solution.displacement())
                    .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
                step_bodies.push(Py::new(py, PyBody::new(&b.body, &b.solution, fields))?);
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
        if let (Some(contact), Some(last)) = (
            &outcome.contact,
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
                    index: outcome.steps.len(),
                    time: last.time,
                    bodies: step_bodies,
                    pairs: pairs.iter().map(|p| p.clone_ref(py)).collect(),
                    report: to_python(py, &contact.report)?.unbind(),
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
    /// incompressibility), the contact's (solver and model), earlier keys of the scene.
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
        all.extend(summary.deprecations.iter().map(|d| d.to_string()));
        all
    }

    /// Writes the outputs of the `vem` command into `dir` (VTU per body, interface.vtu,
    /// results.pvd, contact.csv, SVG pictures, summary.json; per step with a history) and
    /// returns the paths written. The folder is replaced whole; one holding other files is
    /// refused (`OutputError`).
    fn write(&mut self, py: Python<'_>, dir: PathBuf) -> PyResult<Vec<PathBuf>> {
        let outcome = &mut self.outcome;
        let written = py.detach(|| catch_unwind(AssertUnwindSafe(|| outcome.write(&dir))));
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

/// The native module `vemcontact._native`.
#[pymodule(name = "_native")]
mod native {
    #[pymodule_export]
    use super::{from_dict, load, loads, PyBody, PyPair, PyResultSet, PyScene, PyStep};
}
