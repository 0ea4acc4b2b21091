//! From a checked scene to library objects: meshes, elastic bodies, the contact problem and the
//! contact solver's choice. Only what the scene requires is built: no contact pair, no contact
//! problem (plain elasticity); a rigid obstacle is a gap function, not a mesh.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

use vem_contact::{
    AccuracyPreset, ContactError, ContactLaw, ContactNormal, ContactPair, ContactProblem,
    ErrorModel, LawRegistry, Obstacle, Obstacle3, RigidObstacle, SolverRegistry,
};
use vem_elastic::{Component, Dirichlet, ElasticBody, ElasticError, Material, Plane, Traction};
use vem_mesh::generators::{polygon_mesh, MeshFamily, PolygonDomain, Rectangle};
use vem_mesh::interface::InterfaceOptions;
use vem_mesh::{Mesh, Point, Point3, Vector, Vector3};
use vem_space::{Choice, ElementRegistry, RegistryError, SpaceError};

use crate::check::{body_index, list, Checked};
use crate::description::{
    BodyDescription, ContactDescription, NormalDescription, ObstacleDescription, PlaneDescription,
    Scene,
};
use crate::error::one_line;
use crate::resources::{Footprint, LimitOrigin, MemoryLimit};
use crate::space::BuiltMesh;
use crate::{KeyPath, SceneError};

/// The names a scene may use for its elements, contact laws and solvers: the built-in ones
/// by default, or a user's own, registered in the registries.
#[derive(Debug, Clone, Default)]
pub struct Registries {
    /// Contact solvers (scene key `solver`).
    pub solvers: SolverRegistry,
    /// Elements (scene key `element` of a body).
    pub elements: ElementRegistry,
    /// Contact laws in the plane (scene key `law` of a contact pair).
    pub laws: LawRegistry<2>,
    /// Contact laws in space (the same key): the built-in laws by default, under the same
    /// names.
    pub laws_3d: LawRegistry<3>,
}

/// How a scene is built: the folder its relative file names start from, the registries and
/// the memory the run may plan to use.
#[derive(Debug, Clone)]
pub struct BuildOptions {
    /// The folder of the scene file (mesh files are relative to it).
    pub base: PathBuf,
    /// The names the scene may use.
    pub registries: Registries,
    /// The memory limit; `None`: the scene's `[limits] memory_gib`, else the memory the system
    /// reports available.
    pub memory_limit: Option<MemoryLimit>,
}

impl Default for BuildOptions {
    /// Files relative to the current folder, the built-in registries, the scene's limit.
    fn default() -> Self {
        Self {
            base: PathBuf::new(),
            registries: Registries::default(),
            memory_limit: None,
        }
    }
}

/// One body as built: its elastic body (in the plane, or in space for `D = 3`), where its mesh
/// came from, its element in words.
#[derive(Debug, Clone)]
pub struct ModelBody<const D: usize = 2> {
    /// The elastic body.
    pub body: ElasticBody<D>,
    /// Where the mesh came from ("voronoi, n = 16, seed 1, on [0, 1] x [0, 1]" or a file).
    pub mesh_source: String,
    /// The element, in words ("vem1: lowest-order VEM ...").
    pub element: String,
    /// A generated mesh in a scene with `accuracy` or `target_error`: the relative energy
    /// error `E_grad / |u|_1` the error model predicts for its size.
    pub predicted_error: Option<f64>,
    /// Warnings about the body's model, one sentence each (a locking element at a Poisson's
    /// ratio close to 1/2).
    pub warnings: Vec<String>,
}

/// A contact pair as built: the scene's description, the counterpart's obstacle if any.
#[derive(Debug, Clone)]
pub struct ModelContact {
    /// Index of body A into [`Model::bodies`].
    pub body: usize,
    /// Index of body B, `None` against an obstacle.
    pub other: Option<usize>,
    /// The rigid obstacle in the plane, if any (for pictures).
    pub obstacle: Option<Obstacle>,
    /// The rigid obstacle in space, if any.
    pub obstacle_3d: Option<Obstacle3>,
    /// Which parts face what, in words.
    pub description: String,
    /// Radius of the Hertz comparison, if asked for.
    pub hertz_radius: Option<f64>,
}

/// A scene turned into library objects, ready to solve ([`Model::solve`]).
#[derive(Debug, Clone)]
pub struct Model {
    pub(crate) checked: Checked,
    pub(crate) bodies: Vec<ModelBody>,
    pub(crate) bodies_3d: Vec<ModelBody<3>>,
    pub(crate) contacts: Vec<ModelContact>,
    /// The contact problem of the bodies in contact (`None` without a contact pair) and, for
    /// each of its bodies, the index in [`Model::bodies`].
    pub(crate) problem: Option<(ContactProblem, Vec<usize>)>,
    /// The same in space.
    pub(crate) problem_3d: Option<(ContactProblem<3>, Vec<usize>)>,
    pub(crate) solver: Choice,
    pub(crate) registries: Registries,
    pub(crate) mesh_time: Duration,
    /// The memory limit the meshes were checked against (the refined meshes of `adapt` are
    /// checked against it too).
    pub(crate) limit: MemoryLimit,
    /// Per body, whether the locking-free default inserted its edge midpoints.
    pub(crate) midpoints: Vec<bool>,
}

impl Model {
    /// Checks the scene, generates or reads every mesh (after a check of the memory the run
    /// plans to use), checks every part name against its mesh and builds the bodies, the
    /// contact problem and the solver's choice.
    ///
    /// # Errors
    /// A [`SceneError`] at the key at fault.
    pub fn build(scene: &Scene, options: &BuildOptions) -> Result<Self, SceneError> {
        let checked = crate::check::check(scene)?;
        let located = |e: SceneError| SceneError {
            path: checked.written(&e.path),
            ..e
        };
        Self::build_checked(checked.clone(), options).map_err(located)
    }

    fn build_checked(checked: Checked, options: &BuildOptions) -> Result<Self, SceneError> {
        let scene = &checked.scene;
        let limit = options.memory_limit.unwrap_or_else(|| {
            scene
                .limits
                .memory_gib
                .and_then(|gib| MemoryLimit::try_from_gib(gib, LimitOrigin::Scene).ok())
                .unwrap_or_else(MemoryLimit::available)
        });
        let start = Instant::now();
        check_planned_memory(scene, &limit)?;
        // Every body's mesh on a thread of its own (independent files or generators); the
        // first failure in the order of the bodies is reported.
        let meshes = std::thread::scope(|scope| {
            let built: Vec<_> = scene
                .bodies
                .iter()
                .enumerate()
                .map(|(i, b)| {
                    let base = &options.base;
                    scope.spawn(move || build_mesh(scene, b, &KeyPath::key("body").index(i), base))
                })
                .collect();
            built
                .into_iter()
                .map(|h| {
                    h.join()
                        .unwrap_or_else(|panic| std::panic::resume_unwind(panic))
                })
                .collect::<Result<Vec<_>, _>>()
        })?;
        let mesh_time = start.elapsed();
        // The meshes decide the dimension: the checks that depend on it, then the bodies in
        // space apart.
        let dimensions: Vec<usize> = meshes.iter().map(|(m, _, _)| m.dimension()).collect();
        let known: Vec<Option<usize>> = dimensions.iter().map(|&d| Some(d)).collect();
        crate::check::check_one_dimension(scene, &known)?;
        crate::check::check_dimensions(scene, &dimensions)?;
        if scene.adapt.is_some() && dimensions.first() == Some(&3) {
            return Err(SceneError::at(
                KeyPath::key("adapt"),
                "adaptive refinement is in the plane only: remove `adapt` for bodies in space",
            ));
        }
        // The locking-free default inserts the edge midpoints on a mesh with simplices before
        // the memory check: they multiply the unknowns by about 4 on triangles and about 8 on
        // tetrahedra.
        let mut meshes = meshes;
        let mut midpoints = vec![false; meshes.len()];
        for (i, (spec, (mesh, _, _))) in scene.bodies.iter().zip(meshes.iter_mut()).enumerate() {
            if locking_free_default(spec).is_some() && mesh.n_simplices() > 0 {
                *mesh = mesh.with_edge_midpoints().map_err(|e| {
                    SceneError::at(
                        KeyPath::key("body").index(i).at("mesh"),
                        format!("body '{}': edge midpoints: {e}", spec.name),
                    )
                })?;
                midpoints[i] = true;
            }
        }
        if dimensions.first() == Some(&3) {
            check_memory_of_meshes_3d(&meshes, &limit)?;
            let mut bodies_3d = Vec::with_capacity(meshes.len());
            for (i, (spec, (mesh, source, _))) in scene.bodies.iter().zip(meshes).enumerate() {
                let BuiltMesh::Space(mesh) = mesh else {
                    continue;
                };
                let path = KeyPath::key("body").index(i);
                bodies_3d.push(crate::space::build_body(
                    spec,
                    mesh,
                    source,
                    midpoints[i],
                    &options.registries.elements,
                    scene,
                    &path,
                )?);
            }
            let solver = solver_choice(scene);
            options
                .registries
                .solvers
                .make_choice(&solver)
                .map_err(|e| registry_error(e, &KeyPath::key("solver")))?;
            let (contacts, problem_3d) = contact_pairs(
                scene,
                &bodies_3d,
                &options.registries.laws_3d,
                build_obstacle_3d,
            )?;
            let contacts = contacts
                .into_iter()
                .map(|(contact, obstacle_3d)| ModelContact {
                    obstacle_3d,
                    ..contact
                })
                .collect();
            return Ok(Self {
                checked,
                bodies: Vec::new(),
                bodies_3d,
                contacts,
                problem: None,
                problem_3d,
                solver,
                registries: options.registries.clone(),
                mesh_time,
                limit,
                midpoints,
            });
        }
        let meshes: Vec<(Mesh, String, Option<f64>)> = meshes
            .into_iter()
            .filter_map(|(mesh, source, predicted)| match mesh {
                BuiltMesh::Plane(mesh) => Some((mesh, source, predicted)),
                BuiltMesh::Space(_) => None,
            })
            .collect();
        Self::build_plane(
            checked,
            meshes,
            midpoints,
            &options.registries,
            limit,
            mesh_time,
        )
    }

    /// The model of the checked scene `checked` in the plane on the meshes `meshes` (each with
    /// where it came from and its predicted error): the memory check, the bodies, the contact
    /// pairs and the solver's choice.
    fn build_plane(
        checked: Checked,
        meshes: Vec<(Mesh, String, Option<f64>)>,
        midpoints: Vec<bool>,
        registries: &Registries,
        limit: MemoryLimit,
        mesh_time: Duration,
    ) -> Result<Self, SceneError> {
        let scene = &checked.scene;
        check_memory_of_meshes(&meshes, &limit)?;
        let mut bodies = Vec::with_capacity(meshes.len());
        for (i, (spec, (mesh, source, predicted))) in scene.bodies.iter().zip(meshes).enumerate() {
            let path = KeyPath::key("body").index(i);
            let mesh = BodyMeshOf {
                mesh,
                source,
                midpoints: midpoints[i],
            };
            let mut body = build_body(scene, spec, mesh, &registries.elements, &path)?;
            body.predicted_error = predicted;
            bodies.push(body);
        }
        let solver = solver_choice(scene);
        registries
            .solvers
            .make_choice(&solver)
            .map_err(|e| registry_error(e, &KeyPath::key("solver")))?;
        let (contacts, problem) = contact_pairs(scene, &bodies, &registries.laws, build_obstacle)?;
        let contacts = contacts
            .into_iter()
            .map(|(contact, obstacle)| ModelContact {
                obstacle,
                ..contact
            })
            .collect();
        Ok(Self {
            checked,
            bodies,
            bodies_3d: Vec::new(),
            contacts,
            problem,
            problem_3d: None,
            solver,
            registries: registries.clone(),
            mesh_time,
            limit,
            midpoints,
        })
    }

    /// The same scene in the plane on the meshes `meshes` (one per body, in the order of the
    /// scene, each with where it came from): the refined meshes of an adaptive cycle. The
    /// bodies, contact pairs (interface insertion included) and solver are built again;
    /// `mesh_time` is the time the meshes took.
    ///
    /// # Errors
    /// A [`SceneError`] at the key at fault (a mesh over the memory limit, a part lost).
    pub(crate) fn rebuilt(
        &self,
        meshes: Vec<(Mesh, String)>,
        mesh_time: Duration,
    ) -> Result<Self, SceneError> {
        let meshes = meshes
            .into_iter()
            .map(|(mesh, source)| (mesh, source, None))
            .collect();
        Self::build_plane(
            self.checked.clone(),
            meshes,
            self.midpoints.clone(),
            &self.registries,
            self.limit,
            mesh_time,
        )
        .map_err(|e| SceneError {
            path: self.written(&e.path),
            ..e
        })
    }

    /// The scene in its current form (the earlier keys folded into their new places).
    pub fn scene(&self) -> &Scene {
        &self.checked.scene
    }

    /// The notes about earlier keys the scene used.
    pub fn deprecations(&self) -> &[crate::Deprecation] {
        &self.checked.deprecations
    }

    /// The path where the user wrote the key `path` of the current form.
    pub fn written(&self, path: &KeyPath) -> KeyPath {
        self.checked.written(path)
    }

    /// The bodies in the plane, in the order of the scene (none in a scene in space).
    pub fn bodies(&self) -> &[ModelBody] {
        &self.bodies
    }

    /// The bodies in space, in the order of the scene (none in a scene in the plane).
    pub fn bodies_3d(&self) -> &[ModelBody<3>] {
        &self.bodies_3d
    }

    /// The dimension of the scene's bodies: 2 (in the plane) or 3 (in space).
    pub fn dimension(&self) -> usize {
        if self.bodies_3d.is_empty() {
            2
        } else {
            3
        }
    }

    /// The contact pairs, in the order of the scene.
    pub fn contacts(&self) -> &[ModelContact] {
        &self.contacts
    }

    /// The contact problem of the bodies in contact, and for each of its bodies the index
    /// into [`Model::bodies`].
    pub fn contact_problem(&self) -> Option<(&ContactProblem, &[usize])> {
        self.problem.as_ref().map(|(p, idx)| (p, idx.as_slice()))
    }

    /// The contact problem of the bodies in space in contact, and for each of its bodies the
    /// index into [`Model::bodies_3d`].
    pub fn contact_problem_3d(&self) -> Option<(&ContactProblem<3>, &[usize])> {
        self.problem_3d.as_ref().map(|(p, idx)| (p, idx.as_slice()))
    }

    /// The contact solver's registry name and settings.
    pub fn solver(&self) -> &Choice {
        &self.solver
    }

    /// The registries the model was built with.
    pub fn registries(&self) -> &Registries {
        &self.registries
    }

    /// Time spent generating and reading meshes.
    pub fn mesh_time(&self) -> Duration {
        self.mesh_time
    }
}

/// A pair about to join the problem, numbered by scene body until the problem's own numbering
/// is known.
struct PendingPair<const D: usize = 2> {
    pair: ContactPair<D>,
}

impl<const D: usize> PendingPair<D> {
    /// The pair with its bodies numbered `a` and `b` in the problem.
    fn renumbered(self, a: usize, b: Option<usize>) -> Self {
        let pair = self.pair;
        let counterpart = match (pair.counterpart(), b) {
            (vem_contact::Counterpart::Body { part, .. }, Some(b)) => {
                vem_contact::Counterpart::Body {
                    body: b,
                    part: part.clone(),
                }
            }
            (other, _) => other.clone(),
        };
        let mut renumbered = ContactPair::new(
            a,
            pair.part().to_string(),
            counterpart,
            Arc::clone(pair.law()),
        )
        .with_interface_options(*pair.interface_options())
        .with_normal(pair.normal());
        if let Some(gap) = pair.imposed_gap() {
            let gap = Arc::clone(gap);
            renumbered = renumbered.with_imposed_gap(move |x| gap(x));
        }
        Self { pair: renumbered }
    }
}

/// The solver of the scene: the accuracy preset's, the scene's `solver`, the preset matching
/// `target_error`, or the default.
fn solver_choice(scene: &Scene) -> Choice {
    if let Some(preset) = scene
        .accuracy
        .as_deref()
        .and_then(|a| a.parse::<AccuracyPreset>().ok())
    {
        return Choice::with_options(preset.solver(), preset.solver_options());
    }
    if let Some(solver) = &scene.solver {
        return solver.clone();
    }
    if let Some(target) = scene.target_error {
        let preset = AccuracyPreset::for_target(target);
        return Choice::with_options(preset.solver(), preset.solver_options());
    }
    Choice::named(SolverRegistry::DEFAULT)
}

/// A registry's refusal at the key of the choice `path` (or of the refused setting in it).
pub(crate) fn registry_error(error: RegistryError, path: &KeyPath) -> SceneError {
    let at = match error.option_path() {
        Some(option) => path.join(option),
        None => path.clone(),
    };
    SceneError::at(at, one_line(&error))
}

/// The target error generated meshes without `n` are sized for: `target_error`, else the
/// preset's target.
fn target_error(scene: &Scene) -> Option<f64> {
    scene.target_error.or_else(|| {
        scene
            .accuracy
            .as_deref()
            .and_then(|a| a.parse::<AccuracyPreset>().ok())
            .map(AccuracyPreset::target_error)
    })
}

/// The size `n` of a generated mesh: the scene's, or the one the error model chooses for the
/// scene's target error (then with the error it predicts and a note).
fn generated_size(
    scene: &Scene,
    spec: &BodyDescription,
    path: &KeyPath,
) -> Result<(usize, String, Option<f64>), SceneError> {
    let model = ErrorModel::LOWEST_ORDER_VEM;
    let target = target_error(scene);
    match (spec.mesh.n, target) {
        (Some(n), _) => Ok((n, String::new(), target.map(|_| model.predicted_error(n)))),
        (None, Some(target)) => {
            let n = model.try_size_for(target).map_err(|e| {
                SceneError::at(path.at("mesh"), format!("body '{}': {e}", spec.name))
            })?;
            Ok((
                n,
                format!(" (chosen for a relative energy error of {target})"),
                Some(model.predicted_error(n)),
            ))
        }
        (None, None) => Err(SceneError::at(path.at("mesh"), "incomplete mesh")),
    }
}

/// The family, the rectangle and, for a mesh of a `polygon`, the polygon of a generated mesh
/// (checked by `check`); the rectangle of a polygon is its bounding rectangle, on which the
/// family's mesh is made and then cut.
fn generator(
    spec: &BodyDescription,
    path: &KeyPath,
) -> Result<(MeshFamily, Rectangle, Option<PolygonDomain>), SceneError> {
    let mesh = &spec.mesh;
    let Some(family) = &mesh.family else {
        return Err(SceneError::at(path.at("mesh"), "incomplete mesh"));
    };
    let family: MeshFamily = family.parse().map_err(|e: vem_mesh::MeshError| {
        SceneError::at(path.at("mesh").at("family"), e.to_string())
    })?;
    if mesh.polygon.is_some() {
        let domain = crate::check::polygon_domain(mesh, &spec.name, &path.at("mesh"))?;
        return Ok((family, domain.bounding_rectangle(), Some(domain)));
    }
    let Some(rectangle) = &mesh.rectangle else {
        return Err(SceneError::at(path.at("mesh"), "incomplete mesh"));
    };
    let corner = |k: usize| Point::new(rectangle[k][0], rectangle[k][1]);
    Ok((family, Rectangle::new(corner(0), corner(1)), None))
}

/// Refuses, before any mesh is generated, a scene whose generated meshes would not fit the
/// memory limit, or whose run would not: the error is at the largest body's mesh.
fn check_planned_memory(scene: &Scene, limit: &MemoryLimit) -> Result<(), SceneError> {
    let mut total = Footprint::default();
    let mut largest: Option<(f64, usize)> = None;
    for (i, spec) in scene.bodies.iter().enumerate() {
        if spec.mesh.file.is_some() || spec.mesh.vertices.is_some() {
            continue; // a file or an inline mesh: counted once read
        }
        if spec.mesh.cuboid.is_some() {
            continue; // in space: counted once generated
        }
        let path = KeyPath::key("body").index(i);
        let (n, _, _) = generated_size(scene, spec, &path)?;
        // A polygon's mesh is at most about its bounding rectangle's.
        let (family, rect, _) = generator(spec, &path)?;
        let name = &spec.name;
        let size = family
            .size(&rect, n)
            .map_err(|e| SceneError::at(path.at("mesh"), format!("body '{name}': {e}")))?;
        let footprint = Footprint::of_size(&size);
        limit
            .check(
                footprint.mesh_bytes(),
                &format!(
                    "body '{name}': generating its mesh ({} polygons, {} vertices)",
                    size.polygons, size.vertices
                ),
            )
            .map_err(|message| SceneError::at(path.at("mesh"), message))?;
        if largest.is_none_or(|(bytes, _)| footprint.run_bytes() > bytes) {
            largest = Some((footprint.run_bytes(), i));
        }
        total = total + footprint;
    }
    match largest {
        Some((_, i)) => limit
            .check(
                total.run_bytes(),
                &format!(
                    "solving the scene ({:.0} polygons, {:.0} vertices in all; largest: body '{}')",
                    total.polygons, total.vertices, scene.bodies[i].name
                ),
            )
            .map_err(|message| SceneError::at(KeyPath::key("body").index(i).at("mesh"), message)),
        None => Ok(()),
    }
}

/// Refuses, before interface nodes are inserted and systems assembled, meshes (generated or
/// read) whose run would not fit the memory limit.
fn check_memory_of_meshes(
    meshes: &[(Mesh, String, Option<f64>)],
    limit: &MemoryLimit,
) -> Result<(), SceneError> {
    let total = meshes
        .iter()
        .fold(Footprint::default(), |sum, (mesh, _, _)| {
            sum + Footprint::of_mesh(mesh)
        });
    check_footprint(total, limit)
}

/// Refuses meshes in space whose run would not fit the memory limit.
fn check_memory_of_meshes_3d(
    meshes: &[(BuiltMesh, String, Option<f64>)],
    limit: &MemoryLimit,
) -> Result<(), SceneError> {
    let total = meshes
        .iter()
        .filter_map(|(m, _, _)| match m {
            BuiltMesh::Space(mesh) => Some(Footprint::of_polyhedral_mesh(mesh)),
            BuiltMesh::Plane(_) => None,
        })
        .fold(Footprint::default(), |sum, f| sum + f);
    check_footprint(total, limit)
}

/// Refuses a run of the footprint `total` beyond the limit.
fn check_footprint(total: Footprint, limit: &MemoryLimit) -> Result<(), SceneError> {
    limit
        .check(
            total.run_bytes(),
            &format!(
                "solving the scene ({:.0} polygons, {:.0} vertices in all)",
                total.polygons, total.vertices
            ),
        )
        .map_err(|message| SceneError::at(KeyPath::root(), message))
}

/// The mesh of the body `body` of `scene` as [`Model::build`] makes it before interface nodes
/// are inserted (generated, read from a file relative to `base` or given inline, with the
/// parts `parts` cut out), and where it came from in words. The scene is checked first (as
/// [`Model::build`] checks it); errors are at the scene's keys (`body[0].mesh.polygons[3]`).
///
/// # Errors
/// [`SceneError`] for a scene that is not valid, a body index out of range, a mesh that
/// cannot be generated, read or validated.
pub fn body_mesh(
    scene: &Scene,
    body: usize,
    base: &Path,
) -> Result<(BuiltMesh, String), SceneError> {
    let checked = crate::check::check(scene)?;
    let scene = &checked.scene;
    let Some(spec) = scene.bodies.get(body) else {
        return Err(SceneError::at(
            KeyPath::key("body"),
            format!("no body {body}: the scene has {}", scene.bodies.len()),
        ));
    };
    let path = KeyPath::key("body").index(body);
    let (mesh, source, _) = build_mesh(scene, spec, &path, base).map_err(|e| SceneError {
        path: checked.written(&e.path),
        ..e
    })?;
    Ok((mesh, source))
}

/// The mesh of one body, where it came from and, with a target error, the error predicted.
fn build_mesh(
    scene: &Scene,
    spec: &BodyDescription,
    path: &KeyPath,
    base: &Path,
) -> Result<(BuiltMesh, String, Option<f64>), SceneError> {
    let name = &spec.name;
    if spec.mesh.cuboid.is_some() {
        let (mesh, source) = crate::space::generate(spec, path)?;
        let mesh = crate::space::with_sub_parts(mesh, spec, path)?;
        return Ok((BuiltMesh::Space(mesh), source, None));
    }
    if spec.mesh.vertices.is_some() {
        return Ok(
            match inline_mesh(&spec.mesh, &spec.name, &path.at("mesh"))? {
                BuiltMesh::Plane(mesh) => {
                    let source = format!(
                        "given inline ({} polygons, {} vertices)",
                        mesh.n_polygons(),
                        mesh.n_vertices()
                    );
                    (
                        BuiltMesh::Plane(with_sub_parts(mesh, spec, path)?),
                        source,
                        None,
                    )
                }
                BuiltMesh::Space(mesh) => {
                    let source = format!(
                        "given inline ({} polyhedra, {} vertices)",
                        mesh.n_cells(),
                        mesh.n_vertices()
                    );
                    (
                        BuiltMesh::Space(crate::space::with_sub_parts(mesh, spec, path)?),
                        source,
                        None,
                    )
                }
            },
        );
    }
    if let Some(file) = &spec.mesh.file {
        let at = path.at("mesh").at("file");
        let full = base.join(file);
        let extension = full
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        let read = match extension.as_deref() {
            Some("msh") => {
                let read = crate::space::read_gmsh(&full)
                    .map_err(|e| SceneError::at(at.clone(), format!("body '{name}': {e}")))?;
                return match read {
                    BuiltMesh::Plane(mesh) => Ok((
                        BuiltMesh::Plane(with_sub_parts(mesh, spec, path)?),
                        format!("mesh file {file}"),
                        None,
                    )),
                    BuiltMesh::Space(mesh) => Ok((
                        BuiltMesh::Space(crate::space::with_sub_parts(mesh, spec, path)?),
                        format!("mesh file {file} (volume elements)"),
                        None,
                    )),
                };
            }
            Some("vtu") | Some("vtk") => {
                read_vtk(&full, &spec.mesh.part_names).map_err(|reason| vem_mesh::MeshError::Read {
                    path: full.clone(),
                    reason,
                })
            }
            Some("txt") | Some("poly") => vem_mesh::io::read_polymesher(&full),
            _ => {
                return Err(SceneError::at(
                    at,
                    format!(
                        "body '{name}': mesh file '{file}': give a Gmsh .msh, a VTK .vtu or .vtk, \
                         or a PolyMesher/mVEM .txt file"
                    ),
                ))
            }
        }
        .map_err(|e| SceneError::at(at.clone(), format!("body '{name}': {e}")))?;
        let read = with_sub_parts(read, spec, path)?;
        return Ok((BuiltMesh::Plane(read), format!("mesh file {file}"), None));
    }
    let (n, chosen, predicted) = generated_size(scene, spec, path)?;
    let (family, rect, polygon) = generator(spec, path)?;
    let seed = spec.mesh.seed.unwrap_or(1);
    let generated = match &polygon {
        Some(domain) => polygon_mesh(domain, family, n, seed),
        None => family.generate(&rect, n, seed),
    }
    .map_err(|e| SceneError::at(path.at("mesh"), format!("body '{name}': {e}")))?;
    let random = if family.is_random() {
        format!(", seed {seed}")
    } else {
        String::new()
    };
    let (a, b) = (rect.min, rect.max);
    let generated = with_sub_parts(generated, spec, path)?;
    let domain = match &polygon {
        Some(domain) => format!(
            "the polygon of {} vertices in [{}, {}] x [{}, {}]",
            domain.vertices().len(),
            a.x,
            b.x,
            a.y,
            b.y
        ),
        None => format!("[{}, {}] x [{}, {}]", a.x, b.x, a.y, b.y),
    };
    Ok((
        BuiltMesh::Plane(generated),
        format!("{family}, n = {n}{chosen}{random}, on {domain}"),
        predicted,
    ))
}

/// The mesh given inline by `vertices` with `polygons` (in the plane) or `polyhedra` (in
/// space) and its parts (`part_edges`, `part_faces`) of the body `name`, whose mesh
/// description is at the key `at`: checked as a scene's ([`crate::check::check`]) and
/// validated as every mesh of the library. An error is at the key of the polygon,
/// polyhedron, vertex or part it names (`body[0].mesh.polygons[3]`), its message naming the
/// cell and the vertex.
///
/// ```
/// use vem_scene::{inline_mesh, BuiltMesh, KeyPath, MeshDescription};
/// let mut mesh = MeshDescription::default();
/// mesh.vertices = Some(vec![vec![0.0, 0.0], vec![1.0, 0.0], vec![0.0, 1.0]]);
/// mesh.polygons = Some(vec![vec![0, 2, 1]]);
/// let error = inline_mesh(&mesh, "a", &KeyPath::key("mesh")).unwrap_err();
/// assert_eq!(error.path.to_string(), "mesh.polygons[0]");
/// assert!(error.message.contains("polygon 0 is clockwise"), "{}", error.message);
/// mesh.polygons = Some(vec![vec![0, 1, 2]]);
/// let BuiltMesh::Plane(built) = inline_mesh(&mesh, "a", &KeyPath::key("mesh"))? else {
///     panic!("a mesh in the plane")
/// };
/// assert_eq!(built.n_edges(), 3);
/// # Ok::<(), vem_scene::SceneError>(())
/// ```
///
/// # Errors
/// [`SceneError`] for a description that is not an inline mesh, points of the wrong length,
/// keys of another mesh source, and every error of the mesh's validation.
pub fn inline_mesh(
    mesh: &crate::description::MeshDescription,
    name: &str,
    at: &KeyPath,
) -> Result<BuiltMesh, SceneError> {
    crate::check::check_inline_mesh(mesh, name, at)?;
    let vertices = mesh.vertices.as_deref().unwrap_or_default();
    if let Some(polygons) = &mesh.polygons {
        let points = vertices.iter().map(|p| Point::new(p[0], p[1])).collect();
        let parts = mesh
            .part_edges
            .iter()
            .map(|(part, edges)| vem_mesh::PartSpec::new(part.clone(), edges.clone()))
            .collect();
        return Mesh::from_polygons(points, polygons, parts)
            .map(BuiltMesh::Plane)
            .map_err(|e| {
                SceneError::at(inline_error_path(&e, at, 2), format!("body '{name}': {e}"))
            });
    }
    let polyhedra = mesh.polyhedra.as_deref().unwrap_or_default();
    let points = vertices
        .iter()
        .map(|p| vem_mesh::Point3::new(p[0], p[1], p[2]))
        .collect();
    let parts = mesh
        .part_faces
        .iter()
        .map(|(part, faces)| vem_mesh::FacePartSpec::new(part.clone(), faces.clone()))
        .collect();
    vem_mesh::PolyhedralMesh::from_polyhedra(points, polyhedra, parts)
        .map(BuiltMesh::Space)
        .map_err(|e| SceneError::at(inline_error_path(&e, at, 3), format!("body '{name}': {e}")))
}

/// The key of an inline mesh (at `mesh`) that the mesh error `error` is about: the polygon
/// or polyhedron, the vertex or the part it names, else the cells as a whole.
fn inline_error_path(error: &vem_mesh::MeshError, mesh: &KeyPath, dimension: usize) -> KeyPath {
    use vem_mesh::MeshError as E;
    let cells = mesh.at(if dimension == 2 {
        "polygons"
    } else {
        "polyhedra"
    });
    let parts = mesh.at(if dimension == 2 {
        "part_edges"
    } else {
        "part_faces"
    });
    match error {
        E::TooFewVertices { polygon, .. }
        | E::VertexOutOfRange { polygon, .. }
        | E::RepeatedVertex { polygon, .. }
        | E::Clockwise { polygon, .. }
        | E::DegenerateArea { polygon, .. }
        | E::SelfIntersecting { polygon, .. }
        | E::NonConforming {
            polygon_a: polygon, ..
        }
        | E::Overlapping { b: polygon, .. } => cells.index(*polygon),
        // The polygon that used the edge once too often.
        E::OverusedEdge { polygons, .. } if !polygons.is_empty() => {
            cells.index(polygons[polygons.len() - 1])
        }
        E::CellTooFewFaces { cell, .. }
        | E::CellRepeatedFace { cell, .. }
        | E::CellNotClosed { cell, .. }
        | E::DisconnectedCell { cell, .. }
        | E::InvertedCell { cell, .. }
        | E::DegenerateCell { cell, .. } => cells.index(*cell),
        E::NonFiniteVertex { vertex, .. }
        | E::NonFiniteVertex3 { vertex, .. }
        | E::UnusedVertex { vertex }
        | E::HangingVertex { vertex, .. }
        | E::DuplicateVertices { b: vertex, .. } => mesh.at("vertices").index(*vertex),
        E::UnknownEdge { part, .. }
        | E::InteriorEdgeInPart { part, .. }
        | E::UnknownFace { part, .. }
        | E::InteriorFaceInPart { part, .. }
        | E::PartFaceOutOfRange { part, .. }
        | E::DuplicatePart { part } => parts.at(part),
        _ => cells,
    }
}

/// `mesh` with the body's further parts (`mesh.parts`): the boundary edges whose two end
/// points lie in each part's box (widened by 1e-9 of its size, so that points on its sides
/// count), among the edges of `of` when given.
///
/// # Errors
/// A part named like one of the mesh's, an `of` the mesh lacks, a box that holds no edge.
fn with_sub_parts(
    mut mesh: Mesh,
    spec: &BodyDescription,
    path: &KeyPath,
) -> Result<Mesh, SceneError> {
    let name = &spec.name;
    for (k, part) in spec.mesh.parts.iter().enumerate() {
        let at = path.at("mesh").at("parts").index(k);
        let of: Option<Vec<(Point, Point)>> = match &part.of {
            Some(of) => {
                check_part(&mesh, name, of, &at.at("of"))?;
                let vertices = mesh.vertices();
                Some(
                    mesh.part_specs()
                        .into_iter()
                        .find(|p| &p.name == of)
                        .map(|p| {
                            p.edges
                                .iter()
                                .map(|&[a, b]| (vertices[a], vertices[b]))
                                .collect()
                        })
                        .unwrap_or_default(),
                )
            }
            None => None,
        };
        let (lo, hi) = (&part.bounds[0], &part.bounds[1]);
        let slack = 1e-9
            * (hi[0] - lo[0])
                .abs()
                .max((hi[1] - lo[1]).abs())
                .max(f64::MIN_POSITIVE);
        let inside = |p: Point| {
            p.x >= lo[0] - slack
                && p.x <= hi[0] + slack
                && p.y >= lo[1] - slack
                && p.y <= hi[1] + slack
        };
        let in_of = |a: Point, b: Point| {
            of.as_ref().is_none_or(|edges| {
                edges
                    .iter()
                    .any(|&(p, q)| (p == a && q == b) || (p == b && q == a))
            })
        };
        let cut = mesh
            .with_part_where(&part.name, |a, b| inside(a) && inside(b) && in_of(a, b))
            .map_err(|e| SceneError::at(at.at("name"), format!("body '{name}': {e}")))?;
        if cut.part(&part.name).map_or(0, |p| p.edges.len()) == 0 {
            return Err(SceneError::at(
                at.at("box"),
                format!(
                    "body '{name}': part '{}' has no boundary edge{} with both ends in its box",
                    part.name,
                    part.of
                        .as_ref()
                        .map_or(String::new(), |of| format!(" of part '{of}'"))
                ),
            ));
        }
        mesh = cut;
    }
    Ok(mesh)
}

/// A polygonal mesh from a VTK file with the scene's part names.
fn read_vtk(
    path: &Path,
    part_names: &std::collections::BTreeMap<String, String>,
) -> Result<Mesh, String> {
    let grid = match path.extension().and_then(|e| e.to_str()) {
        Some(e) if e.eq_ignore_ascii_case("vtu") => vem_mesh::io::read_vtu(path),
        _ => vem_mesh::io::read_legacy_vtk(path),
    }
    .map_err(|e| e.to_string())?;
    let mut options = vem_mesh::io::GridMeshOptions::default();
    for (number, name) in part_names {
        let number: i64 = number
            .parse()
            .map_err(|_| format!("part number '{number}' is not an integer"))?;
        options.part_names.insert(number, name.clone());
    }
    vem_mesh::io::mesh_from_grid(&grid, &options)
}

/// Checks that `part` names a boundary part of `mesh`; the error lists the parts.
fn check_part(mesh: &Mesh, body: &str, part: &str, path: &KeyPath) -> Result<(), SceneError> {
    if mesh.part(part).is_ok() {
        return Ok(());
    }
    Err(SceneError::at(
        path.clone(),
        format!(
            "body '{body}' has no boundary part named '{part}'; its mesh has {}",
            list(&mesh.part_names())
        ),
    ))
}

fn build_body(
    scene: &Scene,
    spec: &BodyDescription,
    mesh: BodyMeshOf,
    elements: &ElementRegistry,
    path: &KeyPath,
) -> Result<ModelBody, SceneError> {
    let name = spec.name.clone();
    let BodyMeshOf {
        mesh,
        source: mesh_source,
        midpoints,
    } = mesh;
    let material = body_material(spec, path)?;
    let nearly = nearly_incompressible(&material);
    let simplices = mesh.polygons().filter(|p| p.len() == 3).count();
    let (choice, why) = element_choice(spec, nearly, midpoints, 2);
    let element = elements
        .make_choice(&choice)
        .map_err(|e| registry_error(e, &path.at("element")))?;
    let description = match (why, elements.summary(&choice.name)) {
        (Some(why), Some(s)) => format!("{why} ({s})"),
        (Some(why), None) => why,
        (None, Some(s)) => format!("{}: {s}", element.name()),
        (None, None) => element.name().to_string(),
    };
    let warnings: Vec<String> = locking_warning(spec, element.name(), nearly, simplices, 2)
        .into_iter()
        .collect();
    for (k, d) in spec.dirichlet.iter().enumerate() {
        check_part(
            &mesh,
            &name,
            &d.part,
            &path.at("dirichlet").index(k).at("part"),
        )?;
    }
    for (k, r) in spec.rigid_plate.iter().enumerate() {
        check_part(
            &mesh,
            &name,
            &r.part,
            &path.at("rigid_plate").index(k).at("part"),
        )?;
    }
    for (k, t) in spec.traction.iter().enumerate() {
        check_part(
            &mesh,
            &name,
            &t.part,
            &path.at("traction").index(k).at("part"),
        )?;
    }
    let t = load_time(scene);
    let mut pressures = Vec::new();
    for (k, traction) in spec.traction.iter().enumerate() {
        if let Some(p) = traction.pressure {
            let at = path.at("traction").index(k);
            pressures.push(
                Traction::try_normal_pressure(&mesh, traction.part.clone(), p)
                    .map_err(|e| SceneError::at(at.at("part"), e.to_string()))?,
            );
        }
    }
    let mut builder = ElasticBody::builder(name.clone(), mesh, material, element);
    if let Some(points) = spec.traction_points {
        builder = builder.traction_points(points);
    }
    for d in &spec.dirichlet {
        let component = match (&d.x, &d.y) {
            (Some(_), Some(_)) => Component::All,
            (Some(_), None) => Component::X,
            _ => Component::Y,
        };
        let (x, y) = (d.x.clone(), d.y.clone());
        builder = builder.dirichlet(Dirichlet::prescribed(d.part.clone(), component, move |p| {
            let at = [p.x, p.y];
            Vector::new(
                x.as_ref().map_or(0.0, |v| v.at(&at, t)),
                y.as_ref().map_or(0.0, |v| v.at(&at, t)),
            )
        }));
    }
    for r in &spec.rigid_plate {
        let component = match (r.resultant_x, r.resultant_y) {
            (Some(_), Some(_)) => Component::All,
            (Some(_), None) => Component::X,
            _ => Component::Y,
        };
        let resultant = Vector::new(r.resultant_x.unwrap_or(0.0), r.resultant_y.unwrap_or(0.0));
        builder = builder.dirichlet(Dirichlet::rigid_plate(r.part.clone(), component, resultant));
    }
    let mut pressures = pressures.into_iter();
    for traction in &spec.traction {
        builder = match &traction.value {
            Some(value) => {
                let value = value.clone();
                builder.traction(traction.part.clone(), move |p| {
                    let at = [p.x, p.y];
                    Vector::new(value.at(&at, t, 0), value.at(&at, t, 1))
                })
            }
            None => match pressures.next() {
                Some(pressure) => builder.traction_condition(pressure),
                None => builder,
            },
        };
    }
    if let Some(force) = &spec.body_force {
        let force = force.clone();
        builder = builder.body_force(move |p| {
            let at = [p.x, p.y];
            Vector::new(force.at(&at, t, 0), force.at(&at, t, 1))
        });
    }
    let body = builder.build().map_err(|e| {
        locate_elastic(scene, e).unwrap_or_else(|e| SceneError::at(path.clone(), e))
    })?;
    Ok(ModelBody {
        body,
        mesh_source,
        element: description,
        predicted_error: None,
        warnings,
    })
}

/// The mesh of one body as `build_body` takes it: the mesh, where it came from, and whether
/// the locking-free default inserted its edge midpoints.
struct BodyMeshOf {
    mesh: Mesh,
    source: String,
    midpoints: bool,
}

/// The material of a body; errors at `path.material`.
fn body_material(spec: &BodyDescription, path: &KeyPath) -> Result<Material, SceneError> {
    let m = spec.material;
    let plane = match m.plane {
        Some(PlaneDescription::Stress) => Plane::Stress,
        _ => Plane::Strain,
    };
    match (m.young, m.nu, m.lambda, m.mu) {
        (Some(e), Some(nu), None, None) => Material::from_young_poisson(e, nu, plane),
        (None, None, Some(lambda), Some(mu)) => Material::from_lame(lambda, mu, plane),
        _ => return Err(SceneError::at(path.at("material"), "incomplete material")),
    }
    .map_err(|e| SceneError::at(path.at("material"), format!("body '{}': {e}", spec.name)))
}

/// Poisson's ratio of the body `spec` when it names no element and is nearly incompressible
/// (isotropic, nu > [`NEARLY_INCOMPRESSIBLE`], in plane strain in the plane): the bodies for
/// which the locking-free default applies, in the plane and in space. A body in space has no
/// `plane` and its material is the full law, which is the plane-strain one here.
fn locking_free_default(spec: &BodyDescription) -> Option<f64> {
    if spec.element.is_some() {
        return None;
    }
    body_material(spec, &KeyPath::root())
        .ok()
        .and_then(|m| nearly_incompressible(&m))
}

/// The words in which the rule speaks of a body in the plane (`dimension` 2) or in space:
/// where nu is meant ("in plane strain" or nothing) and the simplices ("triangles",
/// "tetrahedra").
fn rule_words(dimension: usize) -> (&'static str, &'static str) {
    if dimension == 2 {
        (" in plane strain", "triangles")
    } else {
        ("", "tetrahedra")
    }
}

/// The element of the body `spec` by the rule shared by the plane and space: the element it
/// names; else [`LOCKING_FREE`] when it is nearly incompressible (`nearly`: its nu), with the
/// edge midpoints when the scene inserted them (`midpoints`: its mesh has simplices); else the
/// registry's default. With why, when the rule chose the locking-free element.
pub(crate) fn element_choice(
    spec: &BodyDescription,
    nearly: Option<f64>,
    midpoints: bool,
    dimension: usize,
) -> (Choice, Option<String>) {
    match (&spec.element, nearly) {
        (Some(choice), _) => (choice.clone(), None),
        (None, None) => (Choice::named(ElementRegistry::DEFAULT), None),
        (None, Some(nu)) => {
            let (strain, _) = rule_words(dimension);
            let with = if midpoints {
                " with edge midpoints"
            } else {
                ""
            };
            (
                Choice::named(LOCKING_FREE),
                Some(format!(
                    "{LOCKING_FREE}{with}: nu = {nu} > {NEARLY_INCOMPRESSIBLE}{strain}, the \
                     locking-free default"
                )),
            )
        }
    }
}

/// The warning about an element named for a nearly incompressible body (`nearly`: its nu), by
/// the rule shared by the plane and space: a locking element ([`LOCKING`]) locks; the
/// locking-free element on a mesh with `simplices` (triangles, tetrahedra) locks there, mildly
/// on triangles, fully on tetrahedra (the space of a tetrahedron is P1, whatever the
/// stabilisation); the remedy is the default, which inserts the edge midpoints. `None` for a
/// body that names no element (the default does not lock) or is not nearly incompressible.
pub(crate) fn locking_warning(
    spec: &BodyDescription,
    element: &str,
    nearly: Option<f64>,
    simplices: usize,
    dimension: usize,
) -> Option<String> {
    let (Some(nu), Some(_)) = (nearly, &spec.element) else {
        return None;
    };
    let name = &spec.name;
    let (strain, simplex) = rule_words(dimension);
    let remedy = format!(
        "remove `element` for the locking-free default ({LOCKING_FREE}, with the edge midpoints \
         inserted on {simplex})"
    );
    if LOCKING.contains(&element) {
        let effect = if dimension == 2 {
            " (contact zones too small, pressure peaks too high)"
        } else {
            ""
        };
        Some(format!(
            "body '{name}': element '{element}' locks at nu = {nu} > \
             {NEARLY_INCOMPRESSIBLE}{strain}{effect}; {remedy}"
        ))
    } else if element == LOCKING_FREE && simplices > 0 {
        let how = if dimension == 2 {
            "locks mildly".to_string()
        } else {
            "locks (the virtual element space of a tetrahedron is P1, which no stabilisation \
             changes)"
                .to_string()
        };
        Some(format!(
            "body '{name}': element '{LOCKING_FREE}' on {simplex} {how} at nu = {nu} > \
             {NEARLY_INCOMPRESSIBLE}{strain}; {remedy}"
        ))
    } else {
        None
    }
}

/// The Poisson's ratio above which a body in plane strain or in space counts as nearly
/// incompressible: the scene then chooses [`LOCKING_FREE`] by default (with the edge midpoints
/// on a mesh with triangles or tetrahedra) and warns about a locking element.
pub const NEARLY_INCOMPRESSIBLE: f64 = 0.45;

/// The element chosen by default for a nearly incompressible body (with the edge midpoints
/// inserted on a mesh with triangles or tetrahedra).
pub const LOCKING_FREE: &str = "vem1-bbar";

/// The built-in elements that lock as Poisson's ratio tends to 1/2.
pub(crate) const LOCKING: [&str; 4] = ["vem1", "vem1-shear", "vem1-drecipe", "p1"];

/// Poisson's ratio of an isotropic material in plane strain (or in space, whose law is the
/// plane-strain one) when it exceeds [`NEARLY_INCOMPRESSIBLE`]; `None` otherwise (plane stress does not lock: its in-plane ratio
/// `nu / (1 + nu)` stays below 1/3).
pub(crate) fn nearly_incompressible(material: &Material) -> Option<f64> {
    let (lambda, mu) = material.lame()?;
    if material.plane()? != Plane::Strain {
        return None;
    }
    let nu = lambda / (2.0 * (lambda + mu));
    // Rounded to the digits a scene writes (0.499, not 0.49899999999999994).
    let nu = (nu * 1e12).round() / 1e12;
    (nu > NEARLY_INCOMPRESSIBLE).then_some(nu)
}

/// The pseudo-time at which the values of the scene are taken: the end of the load history
/// (its steps scale the loads).
fn load_time(_scene: &Scene) -> f64 {
    1.0
}

/// Checks that `part` names a boundary part of `body` (in the plane or in space) with at least
/// one vertex; the error lists the parts, or names the mesh of an empty part (a physical group
/// of a mesh file without elements).
fn check_body_part<const D: usize>(
    model_body: &ModelBody<D>,
    part: &str,
    path: &KeyPath,
) -> Result<(), SceneError> {
    let body = &model_body.body;
    let mesh = body.mesh_arc();
    let names = mesh.part_names();
    if names.iter().any(|n| n == part) {
        if mesh.part_vertices(part).is_ok_and(|v| v.is_empty()) {
            return Err(SceneError::at(
                path.clone(),
                format!(
                    "body '{}': part '{part}' of its mesh ({}) is empty: a physical group \
                     without elements; give the group elements in the mesh, or name another \
                     part",
                    body.name(),
                    model_body.mesh_source
                ),
            ));
        }
        return Ok(());
    }
    Err(SceneError::at(
        path.clone(),
        format!(
            "body '{}' has no boundary part named '{part}'; its mesh has {}",
            body.name(),
            list(&names)
        ),
    ))
}

/// The contact pairs of a scene in the plane (`D = 2`) or in space (`D = 3`) and the contact
/// problem of the bodies they join (`None` without a pair), with each problem body's index
/// into `bodies`. `obstacle` builds a rigid obstacle of the dimension from its keys (checked by
/// `check`); each pair comes with its obstacle, if any.
#[allow(clippy::type_complexity)]
fn contact_pairs<const D: usize, O>(
    scene: &Scene,
    bodies: &[ModelBody<D>],
    laws: &LawRegistry<D>,
    obstacle: impl Fn(&ObstacleDescription) -> O,
) -> Result<
    (
        Vec<(ModelContact, Option<O>)>,
        Option<(ContactProblem<D>, Vec<usize>)>,
    ),
    SceneError,
>
where
    O: RigidObstacle<D> + Clone + 'static,
{
    let mut contacts = Vec::with_capacity(scene.contacts.len());
    let mut pairs = Vec::with_capacity(scene.contacts.len());
    let mut in_problem: Vec<usize> = Vec::new();
    let slot = |i: usize, in_problem: &mut Vec<usize>| match in_problem.iter().position(|&j| j == i)
    {
        Some(k) => k,
        None => {
            in_problem.push(i);
            in_problem.len() - 1
        }
    };
    for (k, spec) in scene.contacts.iter().enumerate() {
        let path = KeyPath::key("contact").index(k);
        let (contact, pair, built) = build_contact(scene, spec, bodies, laws, &obstacle, &path)?;
        let a = slot(contact.body, &mut in_problem);
        let b = contact.other.map(|o| slot(o, &mut in_problem));
        pairs.push(pair.renumbered(a, b));
        contacts.push((contact, built));
    }
    let problem = (!pairs.is_empty()).then(|| {
        let mut problem =
            ContactProblem::new(in_problem.iter().map(|&i| bodies[i].body.clone()).collect());
        for pair in pairs {
            problem = problem.with_pair(pair.pair);
        }
        (problem, in_problem)
    });
    Ok((contacts, problem))
}

/// One contact pair of the scene in `R^D`, its pair for the problem (numbered by scene body)
/// and its rigid obstacle, if any. The same keys in the plane and in space: only the
/// obstacle (`obstacle`) and the points of an imposed gap depend on the dimension.
fn build_contact<const D: usize, O>(
    scene: &Scene,
    spec: &ContactDescription,
    bodies: &[ModelBody<D>],
    laws: &LawRegistry<D>,
    obstacle: &impl Fn(&ObstacleDescription) -> O,
    path: &KeyPath,
) -> Result<(ModelContact, PendingPair<D>, Option<O>), SceneError>
where
    O: RigidObstacle<D> + Clone + 'static,
{
    let a = body_index(scene, &spec.body, &path.at("body"))?;
    let body_a = &bodies[a].body;
    check_body_part(&bodies[a], &spec.part, &path.at("part"))?;
    let law_choice = spec
        .law
        .clone()
        .unwrap_or_else(|| Choice::named(LawRegistry::<D>::DEFAULT));
    let law: Arc<dyn ContactLaw<D>> = laws
        .make_choice(&law_choice)
        .map_err(|e| registry_error(e, &path.at("law")))?;
    let mut options = InterfaceOptions::builder();
    if let Some(d) = spec.max_distance {
        options = options.max_distance(d);
    }
    let options = options
        .build()
        .map_err(|e| SceneError::at(path.at("max_distance"), e.to_string()))?;
    let (other, built, pair, description) =
        match (&spec.other_body, &spec.other_part, &spec.obstacle) {
            (Some(other), Some(other_part), _) => {
                let b = body_index(scene, other, &path.at("other_body"))?;
                let body_b = &bodies[b].body;
                check_body_part(&bodies[b], other_part, &path.at("other_part"))?;
                let description = format!(
                    "body '{}' part '{}' against body '{}' part '{other_part}'",
                    body_a.name(),
                    spec.part,
                    body_b.name()
                );
                let pair = ContactPair::new(
                    a,
                    spec.part.clone(),
                    vem_contact::Counterpart::Body {
                        body: b,
                        part: other_part.clone(),
                    },
                    law,
                );
                (Some(b), None, pair, description)
            }
            (_, _, Some(description)) => {
                let built = obstacle(description);
                RigidObstacle::validate(&built)
                    .map_err(|e| SceneError::at(path.at("obstacle"), e.to_string()))?;
                let description = format!(
                    "body '{}' part '{}' against a rigid {}",
                    body_a.name(),
                    spec.part,
                    RigidObstacle::name(&built)
                );
                let pair = ContactPair::new(
                    a,
                    spec.part.clone(),
                    vem_contact::Counterpart::Obstacle(Arc::new(built.clone())),
                    law,
                );
                (None, Some(built), pair, description)
            }
            _ => return Err(SceneError::at(path.at("body"), "incomplete contact pair")),
        };
    let mut pair = pair.with_interface_options(options);
    if let Some(normal) = spec.normal {
        pair = pair.with_normal(match normal {
            NormalDescription::BodyA => ContactNormal::BodyA,
            NormalDescription::BodyB => ContactNormal::BodyB,
            NormalDescription::Averaged => ContactNormal::Averaged,
        });
    }
    if let Some(gap) = spec.imposed_gap.clone() {
        let t = load_time(scene);
        pair = pair.with_imposed_gap(move |x| gap.at(x.coords.as_slice(), t));
    }
    Ok((
        ModelContact {
            body: a,
            other,
            obstacle: None,
            obstacle_3d: None,
            description,
            hertz_radius: spec.hertz.map(|h| h.radius),
        },
        PendingPair { pair },
        built,
    ))
}

/// A rigid obstacle in the plane from its keys (checked by `check`).
fn build_obstacle(spec: &ObstacleDescription) -> Obstacle {
    let point = |p: &[f64]| Point::new(p[0], p[1]);
    if let Some(line) = &spec.line {
        Obstacle::Line {
            point: point(&line.point),
            normal: Vector::new(line.normal[0], line.normal[1]),
        }
    } else if let Some(circle) = &spec.circle {
        Obstacle::Circle {
            centre: point(&circle.centre),
            radius: circle.radius,
        }
    } else {
        Obstacle::Polyline(spec.polyline.iter().flatten().map(|p| point(p)).collect())
    }
}

/// A rigid obstacle in space from its keys (checked by `check`: `plane` or `sphere`).
fn build_obstacle_3d(spec: &ObstacleDescription) -> Obstacle3 {
    let point = |p: &[f64]| Point3::new(p[0], p[1], p[2]);
    match (&spec.plane, &spec.sphere) {
        (Some(plane), _) => Obstacle3::Plane {
            point: point(&plane.point),
            normal: Vector3::new(plane.normal[0], plane.normal[1], plane.normal[2]),
        },
        (None, Some(sphere)) => Obstacle3::Sphere {
            centre: point(&sphere.centre),
            radius: sphere.radius,
        },
        // Unreachable after `check`; a plane through the origin keeps this total.
        (None, None) => Obstacle3::Plane {
            point: Point3::origin(),
            normal: Vector3::z(),
        },
    }
}

/// The elastic layer's `error` at the scene entry it comes from when it names one (a traction
/// or Dirichlet entry by body and part, a body force by body), else its text.
pub(crate) fn locate_elastic(scene: &Scene, error: ElasticError) -> Result<SceneError, String> {
    let body = |name: &str| scene.bodies.iter().position(|b| b.name == name);
    let entry = |b: usize, list: &str, part: &str| -> Option<KeyPath> {
        let spec = &scene.bodies[b];
        let k = match list {
            "traction" => spec.traction.iter().position(|t| t.part == part),
            "dirichlet" => spec.dirichlet.iter().position(|d| d.part == part),
            _ => spec.rigid_plate.iter().position(|r| r.part == part),
        }?;
        Some(KeyPath::key("body").index(b).at(list).index(k))
    };
    let path = match &error {
        ElasticError::Traction { body: b, part, .. } => {
            body(b).and_then(|b| entry(b, "traction", part))
        }
        ElasticError::NonFiniteDirichlet { body: b, part, .. }
        | ElasticError::ConflictingDirichlet {
            body: b,
            second: part,
            ..
        } => body(b).and_then(|b| entry(b, "dirichlet", part)),
        ElasticError::RigidPlateConflict { body: b, plate, .. }
        | ElasticError::NonFiniteResultant {
            body: b,
            part: plate,
            ..
        } => body(b).and_then(|b| entry(b, "rigid_plate", plate)),
        ElasticError::Element {
            body: b,
            source: SpaceError::NonFiniteLoad { .. },
            ..
        } => body(b).map(|b| KeyPath::key("body").index(b).at("body_force")),
        _ => None,
    };
    match path {
        Some(path) => Ok(SceneError::at(path, one_line(&error))),
        None => Err(one_line(&error)),
    }
}

/// The contact layer's `error` at the scene entry it comes from.
pub(crate) fn locate_contact(scene: &Scene, error: ContactError) -> SceneError {
    match error {
        ContactError::Elastic(e) => {
            locate_elastic(scene, e).unwrap_or_else(|text| SceneError::at(KeyPath::root(), text))
        }
        other => {
            // A pair's error names its index only through its context; the whole problem
            // otherwise.
            let path = if scene.contacts.len() == 1 {
                KeyPath::key("contact").index(0)
            } else {
                KeyPath::root()
            };
            SceneError::at(path, one_line(&other))
        }
    }
}
