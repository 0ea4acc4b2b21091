//! From a checked [`Scene`] to library objects: meshes, elastic bodies, the contact problem
//! and the contact solver. Only what the scene requires is built: no contact pair, no contact
//! problem (plain elasticity); a rigid obstacle is a gap function, not a mesh.

use std::fmt;
use std::sync::Arc;
use std::time::{Duration, Instant};

use toml::Spanned;
use vem_contact::{
    ContactError, ContactLaw, ContactProblem, ContactSolver, Coulomb, ErrorModel,
    FixedPointSettings, Frictionless, Obstacle, PenaltyParameter, RegistryError, SettingsError,
    SolverOptions, SolverRegistry, Tresca,
};
use vem_elastic::{Component, Dirichlet, ElasticBody, ElasticError, Material, Plane, Traction};
use vem_mesh::generators::{MeshFamily, Rectangle};
use vem_mesh::interface::{boundary_chain, insert_interface_nodes, InterfaceOptions};
use vem_mesh::{Mesh, Point, Vector};
use vem_space::{
    DRecipe, DofiDofi, ElementRegistry, ElementSpace, LowestOrderVem, SpaceError, Stabilisation,
    StabilisationScaling,
};

use crate::resources::Footprint;
use crate::scene::{
    list, BodySpec, ContactSpec, LawKind, ObstacleSpec, PenaltySpec, PlaneSpec, ScalingSpec,
    StabilisationKind,
};
use crate::{CliError, Scene};

/// One body as built: its elastic body (mesh, material, conditions) and where its mesh came
/// from.
#[derive(Debug, Clone)]
pub struct ModelBody {
    /// The elastic body.
    pub body: ElasticBody,
    /// Where the mesh came from ("voronoi, n = 16, seed 1, on [0, 1] x [0, 1]" or a file).
    pub mesh_source: String,
    /// The element, in words ("vem1: dofi-dofi, trace(C), scale 1/8", "p1").
    pub element: String,
    /// A generated mesh in a scene with `accuracy` or `target_error`: the relative energy
    /// error `E_grad / |u|_1` the error model (`vem_contact::ErrorModel`) predicts for its size.
    pub predicted_error: Option<f64>,
}

/// The names a scene may use for its solvers and elements: the built-in ones by default, or a
/// user's own, registered in [`SolverRegistry`] and [`ElementRegistry`].
#[derive(Debug, Clone)]
pub struct Registries {
    /// Contact solvers (scene key `solver`).
    pub solvers: SolverRegistry,
    /// Element spaces (scene key `element` of a body).
    pub elements: ElementRegistry,
}

impl Default for Registries {
    /// The built-in solvers and elements.
    fn default() -> Self {
        Self {
            solvers: SolverRegistry::builtin(),
            elements: ElementRegistry::builtin(),
        }
    }
}

/// What body A is in contact with, as built.
#[derive(Debug, Clone)]
pub enum ModelCounterpart {
    /// Another body of the scene (its index) and its contact part.
    Body {
        /// Index into [`Model::bodies`].
        index: usize,
        /// Its contact part.
        part: String,
    },
    /// A rigid obstacle (nothing meshed).
    Obstacle(Obstacle),
}

/// The contact pair as built.
#[derive(Debug, Clone)]
pub struct ModelContact {
    /// Index of body A into [`Model::bodies`].
    pub body: usize,
    /// Body A's contact part.
    pub part: String,
    /// Body B or the obstacle.
    pub counterpart: ModelCounterpart,
    /// The problem handed to the contact library.
    pub problem: ContactProblem,
    /// The solver's name in the registry.
    pub solver: String,
    /// The solver's options, as the scene gives them (validated by the solver's factory).
    pub options: SolverOptions,
    /// Radius of the Hertz comparison, if asked for.
    pub hertz_radius: Option<f64>,
}

/// A scene turned into library objects, ready to solve.
#[derive(Debug, Clone)]
pub struct Model {
    scene: Scene,
    bodies: Vec<ModelBody>,
    contact: Option<ModelContact>,
    registry: SolverRegistry,
    mesh_time: Duration,
}

impl Model {
    /// Generates or reads every mesh, checks every part name against its mesh and builds the
    /// bodies, the contact problem and the solver settings, with the built-in solvers and
    /// elements.
    pub fn build(scene: &Scene) -> Result<Self, CliError> {
        Self::build_with(scene, &Registries::default())
    }

    /// As [`Model::build`], with the solvers and elements of `registries`: the scene's `solver`
    /// and `element` keys may name any of them (a solver or an element of one's own,
    /// registered with [`SolverRegistry::register`] or [`ElementRegistry::register`]).
    pub fn build_with(scene: &Scene, registries: &Registries) -> Result<Self, CliError> {
        let registry = &registries.solvers;
        let start = Instant::now();
        check_planned_memory(scene)?;
        let meshes = scene
            .file()
            .bodies
            .iter()
            .map(|spec| build_mesh(scene, spec))
            .collect::<Result<Vec<_>, _>>()?;
        let mesh_time = start.elapsed();
        check_memory_of_meshes(scene, &meshes)?;
        let mut bodies = Vec::with_capacity(meshes.len());
        for (spec, (mesh, mesh_source, predicted_error)) in scene.file().bodies.iter().zip(meshes) {
            let mut body = build_body(scene, spec, mesh, mesh_source, &registries.elements)?;
            body.predicted_error = predicted_error;
            bodies.push(body);
        }
        let contact = match scene.file().contacts.first() {
            Some(spec) => Some(build_contact(scene, spec.get_ref(), &bodies, registry)?),
            None => None,
        };
        Ok(Self {
            scene: scene.clone(),
            bodies,
            contact,
            registry: registry.clone(),
            mesh_time,
        })
    }

    /// A new solver for the contact pair, made by the registry the model was built with.
    pub(crate) fn make_solver(
        &self,
        contact: &ModelContact,
    ) -> Result<Box<dyn ContactSolver>, CliError> {
        self.registry
            .make(&contact.solver, &contact.options)
            .map_err(|e| locate_solver_error(&self.scene, e))
    }

    /// The scene this model was built from.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The bodies, in the order of the scene file.
    pub fn bodies(&self) -> &[ModelBody] {
        &self.bodies
    }

    /// The contact pair, if the scene has one.
    pub fn contact(&self) -> Option<&ModelContact> {
        self.contact.as_ref()
    }

    /// Time spent generating and reading meshes.
    pub fn mesh_time(&self) -> Duration {
        self.mesh_time
    }

    /// A description of what will be modelled, with the A1 quality figures of every mesh and
    /// the size of the contact interface, without solving (`vem check`).
    pub fn check(&self) -> Result<CheckReport, CliError> {
        let bodies = self
            .bodies
            .iter()
            .map(|b| {
                let mesh = b.body.mesh();
                CheckedBody {
                    name: b.body.name().to_string(),
                    mesh_source: b.mesh_source.clone(),
                    vertices: mesh.n_vertices(),
                    polygons: mesh.n_polygons(),
                    parts: mesh
                        .parts()
                        .iter()
                        .map(|p| (p.name.clone(), p.edges.len()))
                        .collect(),
                    quality: mesh.quality(),
                    material: describe_material(b.body.material()),
                    element: b.element.clone(),
                    conditions: describe_conditions(&self.scene, b.body.name()),
                }
            })
            .collect();
        let contact = match &self.contact {
            None => None,
            Some(c) => {
                let a = &self.bodies[c.body].body;
                let interface_nodes = match &c.counterpart {
                    ModelCounterpart::Body { index, part } => {
                        let b = &self.bodies[*index].body;
                        insert_interface_nodes(
                            a.mesh(),
                            &c.part,
                            b.mesh(),
                            part,
                            &interface_options(&self.scene)?,
                        )
                        .map_err(|source| CliError::Mesh {
                            context: format!(
                                "interface between '{}' of '{}' and '{part}' of '{}'",
                                c.part,
                                a.name(),
                                b.name()
                            ),
                            source,
                        })?
                        .pairs
                        .len()
                    }
                    ModelCounterpart::Obstacle(_) => boundary_chain(a.mesh(), &c.part)
                        .map_err(|source| CliError::Mesh {
                            context: format!("contact part of '{}'", a.name()),
                            source,
                        })?
                        .len(),
                };
                Some(CheckedContact {
                    description: self.describe_contact(c),
                    law: c.problem.pairs()[0].law().name().to_string(),
                    friction: c.problem.pairs()[0].law().has_friction(),
                    interface_nodes,
                    solver: c.solver.clone(),
                })
            }
        };
        Ok(CheckReport {
            scene: self.scene.path().display().to_string(),
            title: self.scene.title(),
            bodies,
            contact,
        })
    }

    /// "body 'disc' part 'arc' against body 'block' part 'top'", or "... against a rigid
    /// line".
    pub fn describe_contact(&self, contact: &ModelContact) -> String {
        let a = self.bodies[contact.body].body.name();
        let other = match &contact.counterpart {
            ModelCounterpart::Body { index, part } => {
                format!("body '{}' part '{part}'", self.bodies[*index].body.name())
            }
            ModelCounterpart::Obstacle(o) => format!("a rigid {}", obstacle_name(o)),
        };
        format!("body '{a}' part '{}' against {other}", contact.part)
    }
}

/// `error` and its causes on one line ("a: b: c"), each cause once: a cause whose text the
/// error before it already spells out is not repeated.
pub(crate) fn one_line(error: &dyn std::error::Error) -> String {
    let mut text = error.to_string();
    let mut source = error.source();
    while let Some(cause) = source {
        let cause_text = cause.to_string();
        if !text.contains(&cause_text) {
            text.push_str(": ");
            text.push_str(&cause_text);
        }
        source = cause.source();
    }
    text
}

/// The elastic layer's `error`, located at the scene entry it comes from when it names one
/// (a traction or Dirichlet entry by body and part, a body force by body); otherwise as it
/// is. The library checks the values (finite data, consistent conditions); the scene only
/// says where they were written.
pub(crate) fn locate_elastic(scene: &Scene, error: ElasticError) -> CliError {
    let body = |name: &str| {
        scene
            .file()
            .bodies
            .iter()
            .find(|b| b.name.get_ref() == name)
    };
    let span = match &error {
        ElasticError::Traction { body: b, part, .. } => body(b).and_then(|spec| {
            spec.traction
                .iter()
                .find(|t| t.get_ref().part.get_ref() == part)
                .map(|t| t.span())
        }),
        ElasticError::NonFiniteDirichlet { body: b, part, .. }
        | ElasticError::ConflictingDirichlet {
            body: b,
            second: part,
            ..
        } => body(b).and_then(|spec| {
            spec.dirichlet
                .iter()
                .find(|d| d.get_ref().part.get_ref() == part)
                .map(|d| d.span())
        }),
        ElasticError::RigidPlateConflict { body: b, plate, .. }
        | ElasticError::NonFiniteResultant {
            body: b,
            part: plate,
            ..
        } => body(b).and_then(|spec| {
            spec.rigid_plate
                .iter()
                .find(|r| r.get_ref().part.get_ref() == plate)
                .map(|r| r.span())
        }),
        ElasticError::Element {
            body: b,
            source: SpaceError::NonFiniteLoad { .. },
            ..
        } => body(b).and_then(|spec| spec.body_force.as_ref().map(|f| f.span())),
        _ => None,
    };
    match span {
        Some(span) => scene.error(Some(span), one_line(&error)),
        None => CliError::Elastic(Box::new(error)),
    }
}

/// The contact layer's `error`, located like [`locate_elastic`] when it comes from a body.
pub(crate) fn locate_contact(scene: &Scene, error: ContactError) -> CliError {
    match error {
        ContactError::Elastic(e) => locate_elastic(scene, e),
        other => other.into(),
    }
}

/// "line", "circle" or "polyline".
pub(crate) fn obstacle_name(obstacle: &Obstacle) -> &'static str {
    match obstacle {
        Obstacle::Line { .. } => "line",
        Obstacle::Circle { .. } => "circle",
        Obstacle::Polyline(_) => "polyline",
    }
}

/// The interface options of the scene's contact pair, checked by the library and located at the
/// `max_distance` key.
fn interface_options(scene: &Scene) -> Result<InterfaceOptions, CliError> {
    let spec = scene.file().contacts.first().map(|c| c.get_ref());
    let Some(distance) = spec.and_then(|c| c.max_distance.as_ref()) else {
        return Ok(InterfaceOptions::default());
    };
    InterfaceOptions::builder()
        .max_distance(*distance.get_ref())
        .build()
        .map_err(|e| scene.error(Some(distance.span()), e.to_string()))
}

/// Refuses, before any mesh is generated, a scene whose generated meshes would not fit the
/// memory limit, or whose run would not: the error is at the largest body's mesh.
fn check_planned_memory(scene: &Scene) -> Result<(), CliError> {
    let limit = scene.memory_limit();
    let mut total = Footprint::default();
    let mut largest: Option<(f64, &BodySpec)> = None;
    for spec in &scene.file().bodies {
        let mesh = spec.mesh.get_ref();
        let (Some(family), Some(rectangle)) = (&mesh.family, &mesh.rectangle) else {
            continue; // a file: counted once read
        };
        let name = spec.name.get_ref();
        let n = generated_size(scene, spec)?.n;
        let parsed: MeshFamily = family
            .get_ref()
            .parse()
            .map_err(|e: vem_mesh::MeshError| scene.error(Some(family.span()), e.to_string()))?;
        let [[x0, y0], [x1, y1]] = *rectangle.get_ref();
        let rect = Rectangle::new(Point::new(x0, y0), Point::new(x1, y1));
        let size = parsed
            .size(&rect, n)
            .map_err(|e| scene.error(Some(spec.mesh.span()), format!("body '{name}': {e}")))?;
        let footprint = Footprint::of_size(&size);
        limit
            .check(
                footprint.mesh_bytes(),
                &format!(
                    "body '{name}': generating its mesh ({} polygons, {} vertices)",
                    size.polygons, size.vertices
                ),
            )
            .map_err(|message| scene.error(Some(spec.mesh.span()), message))?;
        if largest.is_none_or(|(bytes, _)| footprint.run_bytes() > bytes) {
            largest = Some((footprint.run_bytes(), spec));
        }
        total = total + footprint;
    }
    match largest {
        Some((_, spec)) => limit
            .check(
                total.run_bytes(),
                &format!(
                    "solving the scene ({:.0} polygons, {:.0} vertices in all; largest: body '{}')",
                    total.polygons,
                    total.vertices,
                    spec.name.get_ref()
                ),
            )
            .map_err(|message| scene.error(Some(spec.mesh.span()), message)),
        None => Ok(()),
    }
}

/// Refuses, before interface nodes are inserted and systems assembled, meshes (generated or
/// read) whose run would not fit the memory limit.
fn check_memory_of_meshes(
    scene: &Scene,
    meshes: &[(Mesh, String, Option<f64>)],
) -> Result<(), CliError> {
    let total = meshes
        .iter()
        .fold(Footprint::default(), |sum, (mesh, _, _)| {
            sum + Footprint::of_mesh(mesh)
        });
    scene
        .memory_limit()
        .check(
            total.run_bytes(),
            &format!(
                "solving the scene ({:.0} polygons, {:.0} vertices in all)",
                total.polygons, total.vertices
            ),
        )
        .map_err(|message| scene.error(None, message))
}

/// The size `n` of a generated mesh: the scene's, or the one the error model chooses for the
/// scene's target error (then with the error it predicts and a note for the description).
struct GeneratedSize {
    n: usize,
    note: String,
    predicted_error: Option<f64>,
}

/// The size of the generated mesh of `spec` (checked by `Scene::check`: a generated mesh has
/// `n` or the scene a target error).
fn generated_size(scene: &Scene, spec: &BodySpec) -> Result<GeneratedSize, CliError> {
    let name = spec.name.get_ref();
    let model = ErrorModel::LOWEST_ORDER_VEM;
    let target = scene.target_error();
    let (n, note) = match (&spec.mesh.get_ref().n, target) {
        (Some(n), _) => (*n.get_ref(), String::new()),
        (None, Some(target)) => {
            let n = model
                .try_size_for(target)
                .map_err(|e| scene.error(Some(spec.mesh.span()), format!("body '{name}': {e}")))?;
            (
                n,
                format!(" (chosen for a relative energy error of {target})"),
            )
        }
        (None, None) => return Err(scene.error(Some(spec.mesh.span()), "incomplete mesh")),
    };
    Ok(GeneratedSize {
        n,
        note,
        predicted_error: target.map(|_| model.predicted_error(n)),
    })
}

/// The mesh of one body, a description of where it came from and, in a scene with an
/// accuracy, the error predicted for its size.
fn build_mesh(scene: &Scene, spec: &BodySpec) -> Result<(Mesh, String, Option<f64>), CliError> {
    let name = spec.name.get_ref();
    let mesh = spec.mesh.get_ref();
    if let Some(file) = &mesh.file {
        let path = scene.resolve(file.get_ref());
        let read = vem_mesh::io::read_gmsh(&path)
            .map_err(|e| scene.error(Some(file.span()), format!("body '{name}': {e}")))?;
        return Ok((read, format!("Gmsh file {}", file.get_ref()), None));
    }
    // Checked by Scene::check: a generated mesh has family, rectangle and n or a target.
    let (Some(family), Some(rectangle)) = (&mesh.family, &mesh.rectangle) else {
        return Err(scene.error(Some(spec.mesh.span()), "incomplete mesh"));
    };
    let GeneratedSize {
        n,
        note: chosen,
        predicted_error: predicted,
    } = generated_size(scene, spec)?;
    let parsed: MeshFamily = family
        .get_ref()
        .parse()
        .map_err(|e: vem_mesh::MeshError| scene.error(Some(family.span()), e.to_string()))?;
    let [[x0, y0], [x1, y1]] = *rectangle.get_ref();
    let rect = Rectangle::new(Point::new(x0, y0), Point::new(x1, y1));
    let seed = mesh.seed.unwrap_or(1);
    let generated = parsed
        .generate(&rect, n, seed)
        .map_err(|e| scene.error(Some(spec.mesh.span()), format!("body '{name}': {e}")))?;
    let random = if parsed.is_random() {
        format!(", seed {seed}")
    } else {
        String::new()
    };
    Ok((
        generated,
        format!("{parsed}, n = {n}{chosen}{random}, on [{x0}, {x1}] x [{y0}, {y1}]"),
        predicted,
    ))
}

/// Checks that `part` names a boundary part of `mesh`; the error lists the parts.
fn check_part(
    scene: &Scene,
    mesh: &Mesh,
    body: &str,
    part: &Spanned<String>,
) -> Result<(), CliError> {
    if mesh.part(part.get_ref()).is_ok() {
        return Ok(());
    }
    Err(scene.error(
        Some(part.span()),
        format!(
            "body '{body}' has no boundary part named '{}'; its mesh has {}",
            part.get_ref(),
            list(&mesh.part_names())
        ),
    ))
}

fn build_body(
    scene: &Scene,
    spec: &BodySpec,
    mesh: Mesh,
    mesh_source: String,
    elements: &ElementRegistry,
) -> Result<ModelBody, CliError> {
    let name = spec.name.get_ref().clone();
    let m = spec.material.get_ref();
    let plane = match m.plane {
        PlaneSpec::Strain => Plane::Strain,
        PlaneSpec::Stress => Plane::Stress,
    };
    let material = match (m.young, m.nu, m.lambda, m.mu) {
        (Some(e), Some(nu), None, None) => Material::from_young_poisson(e, nu, plane),
        (None, None, Some(lambda), Some(mu)) => Material::from_lame(lambda, mu, plane),
        _ => return Err(scene.error(Some(spec.material.span()), "incomplete material")),
    }
    .map_err(|e| scene.error(Some(spec.material.span()), format!("body '{name}': {e}")))?;
    let stabilisation_error = |e: vem_space::SpaceError| {
        scene.error(
            spec.stabilisation.as_ref().map(|s| s.span()),
            format!("body '{name}': {e}"),
        )
    };
    let (element, description): (Arc<dyn ElementSpace>, String) = match &spec.element {
        Some(element) => {
            let made = elements
                .make(element.get_ref())
                .map_err(|e| scene.error(Some(element.span()), format!("body '{name}': {e}")))?;
            let description = elements.summary(element.get_ref()).map_or_else(
                || made.name().to_string(),
                |s| format!("{}: {s}", made.name()),
            );
            (made, description)
        }
        None => {
            let stabilisation: Arc<dyn Stabilisation> = match &spec.stabilisation {
                None => Arc::new(DofiDofi::default()),
                Some(s) => match s.get_ref().kind {
                    StabilisationKind::DRecipe => Arc::new(DRecipe),
                    StabilisationKind::DofiDofi => Arc::new(
                        DofiDofi::try_new(
                            match s.get_ref().scaling {
                                None | Some(ScalingSpec::Trace) => StabilisationScaling::TraceOfC,
                                Some(ScalingSpec::Shear) => StabilisationScaling::ShearModulus,
                            },
                            s.get_ref().scale.unwrap_or(DofiDofi::DEFAULT_SCALE),
                        )
                        .map_err(stabilisation_error)?,
                    ),
                },
            };
            let element =
                LowestOrderVem::try_new(Arc::clone(&stabilisation)).map_err(stabilisation_error)?;
            let description = format!("{}: {}", element.name(), stabilisation.description());
            (Arc::new(element), description)
        }
    };
    let mut builder = ElasticBody::builder(name.clone(), mesh.clone(), material, element);
    for d in &spec.dirichlet {
        let d = d.get_ref();
        check_part(scene, &mesh, &name, &d.part)?;
        let component = match (d.x, d.y) {
            (Some(_), Some(_)) => Component::All,
            (Some(_), None) => Component::X,
            _ => Component::Y,
        };
        let value = Vector::new(d.x.unwrap_or(0.0), d.y.unwrap_or(0.0));
        let part = d.part.get_ref().clone();
        builder = builder.dirichlet(if value == Vector::zeros() {
            Dirichlet::fixed(part, component)
        } else {
            Dirichlet::prescribed(part, component, move |_| value)
        });
    }
    for r in &spec.rigid_plate {
        let r = r.get_ref();
        check_part(scene, &mesh, &name, &r.part)?;
        let component = match (r.resultant_x, r.resultant_y) {
            (Some(_), Some(_)) => Component::All,
            (Some(_), None) => Component::X,
            _ => Component::Y,
        };
        let resultant = Vector::new(r.resultant_x.unwrap_or(0.0), r.resultant_y.unwrap_or(0.0));
        builder = builder.dirichlet(Dirichlet::rigid_plate(
            r.part.get_ref().clone(),
            component,
            resultant,
        ));
    }
    for t in &spec.traction {
        let t = t.get_ref();
        check_part(scene, &mesh, &name, &t.part)?;
        let part = t.part.get_ref().clone();
        builder = match (t.value, t.pressure) {
            (Some([gx, gy]), _) => builder.traction(part, move |_| Vector::new(gx, gy)),
            (None, Some(p)) => {
                let pressure = Traction::try_normal_pressure(&mesh, part.as_str(), p)
                    .map_err(|e| scene.error(Some(t.part.span()), e.to_string()))?;
                builder.traction(part, move |x| pressure.value_at(x))
            }
            (None, None) => builder,
        };
    }
    if let Some(f) = &spec.body_force {
        let [fx, fy] = *f.get_ref();
        builder = builder.body_force(move |_| Vector::new(fx, fy));
    }
    let body = builder
        .build()
        .map_err(|e| match locate_elastic(scene, e) {
            CliError::Elastic(e) => scene.error(Some(spec.name.span()), one_line(&e)),
            located => located,
        })?;
    Ok(ModelBody {
        body,
        mesh_source,
        element: description,
        predicted_error: None,
    })
}

fn build_contact(
    scene: &Scene,
    spec: &ContactSpec,
    bodies: &[ModelBody],
    registry: &SolverRegistry,
) -> Result<ModelContact, CliError> {
    let a = scene.body_index(&spec.body)?;
    let body_a = &bodies[a].body;
    check_part(scene, body_a.mesh(), body_a.name(), &spec.part)?;
    let law = build_law(scene, spec)?;
    let (counterpart, problem) = match (&spec.other_body, &spec.other_part, &spec.obstacle) {
        (Some(other), Some(other_part), _) => {
            let b = scene.body_index(other)?;
            let body_b = &bodies[b].body;
            check_part(scene, body_b.mesh(), body_b.name(), other_part)?;
            (
                ModelCounterpart::Body {
                    index: b,
                    part: other_part.get_ref().clone(),
                },
                ContactProblem::two_bodies(
                    body_a.clone(),
                    spec.part.get_ref().clone(),
                    body_b.clone(),
                    other_part.get_ref().clone(),
                    law,
                ),
            )
        }
        (_, _, Some(obstacle)) => {
            let built = build_obstacle(obstacle.get_ref());
            vem_contact::RigidObstacle::validate(&built)
                .map_err(|e| scene.error(Some(obstacle.span()), e.to_string()))?;
            (
                ModelCounterpart::Obstacle(built.clone()),
                ContactProblem::against_obstacle(
                    body_a.clone(),
                    spec.part.get_ref().clone(),
                    built,
                    law,
                ),
            )
        }
        _ => return Err(scene.error(Some(spec.body.span()), "incomplete contact pair")),
    };
    let options = interface_options(scene)?;
    let mut problem = problem.with_interface_options(options);
    if let Some(normal) = &spec.normal {
        problem = problem.with_normal(normal.get_ref().choice());
    }
    if let Some(gap) = spec.imposed_gap.as_ref().map(|g| *g.get_ref()) {
        problem = problem.with_imposed_gap(move |_| gap);
    }
    let (solver, options) = build_solver(scene, spec, registry)?;
    Ok(ModelContact {
        body: a,
        part: spec.part.get_ref().clone(),
        counterpart,
        problem,
        solver,
        options,
        hertz_radius: spec.hertz.as_ref().map(|h| h.get_ref().radius),
    })
}

fn build_obstacle(spec: &ObstacleSpec) -> Obstacle {
    let point = |[x, y]: [f64; 2]| Point::new(x, y);
    if let Some(line) = &spec.line {
        Obstacle::Line {
            point: point(line.point),
            normal: Vector::new(line.normal[0], line.normal[1]),
        }
    } else if let Some(circle) = &spec.circle {
        Obstacle::Circle {
            centre: point(circle.centre),
            radius: circle.radius,
        }
    } else {
        Obstacle::Polyline(spec.polyline.iter().flatten().map(|&p| point(p)).collect())
    }
}

fn penalty_parameter(spec: &PenaltySpec) -> PenaltyParameter {
    match (spec.factor, spec.value) {
        (_, Some(value)) => PenaltyParameter::Absolute(value),
        (factor, None) => PenaltyParameter::RelativeToStiffness(factor.unwrap_or(1e3)),
    }
}

/// The contact law; the library checks the values, the scene locates them.
fn build_law(scene: &Scene, spec: &ContactSpec) -> Result<Arc<dyn ContactLaw>, CliError> {
    let span_of = |value: &Option<Spanned<f64>>| value.as_ref().map(|v| v.span());
    let value_of = |value: &Option<Spanned<f64>>| value.as_ref().map_or(0.0, |v| *v.get_ref());
    let located = |span, e: SettingsError| scene.error(span, e.to_string());
    Ok(match spec.law() {
        LawKind::Frictionless => Arc::new(Frictionless),
        LawKind::Tresca => Arc::new(
            Tresca::try_new(value_of(&spec.friction_bound))
                .map_err(|e| located(span_of(&spec.friction_bound), e))?,
        ),
        LawKind::Coulomb => {
            let mut builder = FixedPointSettings::builder();
            if let Some(n) = &spec.fixed_point_max_iterations {
                builder = builder.max_iterations(*n.get_ref());
            }
            if let Some(t) = &spec.fixed_point_tolerance {
                builder = builder.tolerance(*t.get_ref());
            }
            let fixed_point = builder.build().map_err(|e| {
                let span = match e.setting {
                    "max_iterations" => spec.fixed_point_max_iterations.as_ref().map(|n| n.span()),
                    _ => span_of(&spec.fixed_point_tolerance),
                };
                located(span, e)
            })?;
            Arc::new(
                Coulomb::try_with(value_of(&spec.coefficient), fixed_point)
                    .map_err(|e| located(span_of(&spec.coefficient), e))?,
            )
        }
    })
}

/// The solver's name and options; the registry's factory is run once here so that an unknown
/// name or a refused option is reported, at its key, before anything is solved.
fn build_solver(
    scene: &Scene,
    spec: &ContactSpec,
    registry: &SolverRegistry,
) -> Result<(String, SolverOptions), CliError> {
    if let Some(preset) = scene.accuracy_preset() {
        let (name, options) = (preset.solver().to_string(), preset.solver_options());
        registry
            .make(&name, &options)
            .map_err(|e| locate_solver_error(scene, e))?;
        return Ok((name, options));
    }
    let mut options = SolverOptions::default();
    if let Some(t) = &spec.tolerance {
        options = options.tolerance(*t.get_ref());
    }
    if let Some(m) = &spec.max_iterations {
        options = options.max_iterations(*m.get_ref());
    }
    if let Some(p) = &spec.penalty {
        options = options.penalty(penalty_parameter(p.get_ref()));
    }
    if let Some(a) = &spec.augmentation {
        options = options.augmentation(penalty_parameter(a.get_ref()));
    }
    let name = spec.solver().to_string();
    registry
        .make(&name, &options)
        .map_err(|e| locate_solver_error(scene, e))?;
    Ok((name, options))
}

/// A registry error located at the scene key of the refused option, or at `solver` for an
/// unknown name.
fn locate_solver_error(scene: &Scene, error: RegistryError) -> CliError {
    let Some(spec) = scene.file().contacts.first().map(|c| c.get_ref()) else {
        return scene.error(None, one_line(&error));
    };
    let solver_span = spec.solver.as_ref().map(|s| s.span());
    match &error {
        RegistryError::Settings { name, source } => {
            let span = match source.setting {
                "tolerance" | "eps_abs" | "eps_rel" => spec.tolerance.as_ref().map(|s| s.span()),
                "max_iterations" => spec.max_iterations.as_ref().map(|s| s.span()),
                "penalty" => spec.penalty.as_ref().map(|s| s.span()),
                "augmentation" => spec.augmentation.as_ref().map(|s| s.span()),
                _ => None,
            };
            // An option the scene gave that the solver has no use for.
            let refused = span.is_some() && source.requirement.starts_with("unset");
            let message = if refused {
                format!(
                    "`{}` does not apply to solver = \"{name}\" (the solver does not use it)",
                    source.setting
                )
            } else {
                one_line(&error)
            };
            scene.error(span.or(solver_span), message)
        }
        _ => scene.error(solver_span, one_line(&error)),
    }
}

/// "E = 1, nu = 0.3, plane strain" (isotropic) for reports.
pub(crate) fn describe_material(material: &Material) -> String {
    let plane = match material.plane() {
        Some(Plane::Strain) => "plane strain",
        Some(Plane::Stress) => "plane stress",
        None => "general",
    };
    match young_poisson(material) {
        Some((e, nu)) => format!("E = {}, nu = {}, {plane}", short(e), short(nu)),
        None => plane.to_string(),
    }
}

/// A number to six significant digits without trailing zeros: "100", "0.3", "2.1e11".
fn short(value: f64) -> String {
    let magnitude = value.abs();
    if magnitude == 0.0 {
        return "0".into();
    }
    let trim = |text: &str| {
        if text.contains('.') {
            text.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            text.to_string()
        }
    };
    if (1e-3..1e6).contains(&magnitude) {
        let digits = (5 - magnitude.log10().floor() as i32).max(0) as usize;
        trim(&format!("{value:.digits$}"))
    } else {
        let text = format!("{value:.5e}");
        let (mantissa, exponent) = text.split_once('e').unwrap_or((&text, "0"));
        format!("{}e{exponent}", trim(mantissa))
    }
}

/// Young's modulus and Poisson's ratio of an isotropic material.
pub(crate) fn young_poisson(material: &Material) -> Option<(f64, f64)> {
    material.lame().map(|(lambda, mu)| {
        (
            mu * (3.0 * lambda + 2.0 * mu) / (lambda + mu),
            lambda / (2.0 * (lambda + mu)),
        )
    })
}

/// The boundary conditions of body `name` as written in the scene.
fn describe_conditions(scene: &Scene, name: &str) -> Vec<String> {
    let Some(spec) = scene
        .file()
        .bodies
        .iter()
        .find(|b| b.name.get_ref() == name)
    else {
        return Vec::new();
    };
    let mut lines = Vec::new();
    for d in &spec.dirichlet {
        let d = d.get_ref();
        let fmt = |c: &str, v: Option<f64>| v.map(|v| format!("u_{c} = {v}"));
        let parts: Vec<String> = [fmt("x", d.x), fmt("y", d.y)]
            .into_iter()
            .flatten()
            .collect();
        lines.push(format!(
            "dirichlet on '{}': {}",
            d.part.get_ref(),
            parts.join(", ")
        ));
    }
    for r in &spec.rigid_plate {
        let r = r.get_ref();
        let fmt = |c: &str, v: Option<f64>| v.map(|v| format!("R_{c} = {v}"));
        let parts: Vec<String> = [fmt("x", r.resultant_x), fmt("y", r.resultant_y)]
            .into_iter()
            .flatten()
            .collect();
        lines.push(format!(
            "rigid plate on '{}': {}",
            r.part.get_ref(),
            parts.join(", ")
        ));
    }
    for t in &spec.traction {
        let t = t.get_ref();
        match (t.value, t.pressure) {
            (Some([gx, gy]), _) => {
                lines.push(format!("traction on '{}': ({gx}, {gy})", t.part.get_ref()))
            }
            (None, Some(p)) => lines.push(format!("pressure on '{}': {p}", t.part.get_ref())),
            (None, None) => {}
        }
    }
    if let Some(f) = &spec.body_force {
        let [fx, fy] = *f.get_ref();
        lines.push(format!("body force: ({fx}, {fy})"));
    }
    lines
}

/// What `vem check` reports for one body.
#[derive(Debug, Clone)]
pub struct CheckedBody {
    /// Name.
    pub name: String,
    /// Where the mesh came from.
    pub mesh_source: String,
    /// Vertices.
    pub vertices: usize,
    /// Polygons.
    pub polygons: usize,
    /// Boundary parts and their numbers of edges.
    pub parts: Vec<(String, usize)>,
    /// A1 figures.
    pub quality: vem_mesh::quality::QualitySummary,
    /// The material.
    pub material: String,
    /// The element (and its stabilisation).
    pub element: String,
    /// Boundary conditions and body force.
    pub conditions: Vec<String>,
}

/// What `vem check` reports for the contact pair.
#[derive(Debug, Clone)]
pub struct CheckedContact {
    /// Which parts face what.
    pub description: String,
    /// The law's name.
    pub law: String,
    /// True when tangential rows will be built.
    pub friction: bool,
    /// Interface nodes (node pairs, or body nodes facing the obstacle): one normal row each.
    pub interface_nodes: usize,
    /// The solver's name.
    pub solver: String,
}

/// What `vem check` prints: the meshes, their quality and what will be modelled.
#[derive(Debug, Clone)]
pub struct CheckReport {
    /// The scene file.
    pub scene: String,
    /// Its title.
    pub title: String,
    /// Every body.
    pub bodies: Vec<CheckedBody>,
    /// The contact pair, if any.
    pub contact: Option<CheckedContact>,
}

impl fmt::Display for CheckReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "scene {} ({}): valid", self.scene, self.title)?;
        for b in &self.bodies {
            writeln!(f, "\nbody '{}': {}", b.name, b.mesh_source)?;
            let parts: Vec<String> = b
                .parts
                .iter()
                .map(|(name, edges)| format!("{name} ({edges} edges)"))
                .collect();
            writeln!(
                f,
                "  {} vertices, {} polygons; parts: {}",
                b.vertices,
                b.polygons,
                parts.join(", ")
            )?;
            writeln!(f, "  material: {}; element: {}", b.material, b.element)?;
            for c in &b.conditions {
                writeln!(f, "  {c}")?;
            }
            writeln!(f, "  mesh quality (A1):")?;
            for line in b.quality.to_string().lines() {
                writeln!(f, "    {line}")?;
            }
        }
        writeln!(f)?;
        match &self.contact {
            None => writeln!(
                f,
                "model: no contact pair: each body is solved as plain linear elasticity"
            ),
            Some(c) => {
                writeln!(f, "model: {}, law {}", c.description, c.law)?;
                let tangential = if c.friction {
                    format!("{} tangential rows", c.interface_nodes)
                } else {
                    "no tangential rows (frictionless)".to_string()
                };
                writeln!(
                    f,
                    "  {} interface nodes: {} normal rows, {tangential}; solver {}",
                    c.interface_nodes, c.interface_nodes, c.solver
                )
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_numbers() {
        assert_eq!(short(100.00000000000001), "100");
        assert_eq!(short(0.3), "0.3");
        assert_eq!(short(0.30000000000000004), "0.3");
        assert_eq!(short(2.1e11), "2.1e11");
        assert_eq!(short(-1.5e-7), "-1.5e-7");
        assert_eq!(short(0.0), "0");
        assert_eq!(short(123456.7), "123457");
    }
}
