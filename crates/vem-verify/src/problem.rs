//! Discrete problems built from an exact solution, and their solution.
//!
//! The problem is a [`vem_scene::Scene`], built into a [`vem_scene::Model`] as the command line
//! and the Python package build theirs. For every body of an [`ExactSolution`]: its mesh given
//! inline, the material of [`ExactSolution::lame`] (`lambda`, `mu`, plane strain), the exact
//! displacement as Dirichlet data on the [`dirichlet_sides`](ExactSolution::dirichlet_sides),
//! the exact traction `sigma nu` on the [`neumann_sides`](ExactSolution::neumann_sides) with
//! [`ProblemSettings::traction_points`] points per edge (the body's `traction_points`) and the
//! exact body force, all three as functions ([`ScalarValue::function`],
//! [`VectorValue::function`]). A contact case (`ExactSolution::contact` is `Some`) adds the
//! pair between the bottom side of body one and the top side of body two ([`CONTACT_SIDES`])
//! with the case's law (or [`ProblemSettings::law`]) and its initial gap `h0(x)` as the
//! `imposed_gap`: the two sides coincide, so the geometric gap is zero and the total gap is `h0`
//! (spec section 1). The element and the law are registered in the scene's registries under
//! the names [`ELEMENT`] and [`LAW`] (the default element is the built-in `"vem1"`). Bodies
//! without an interface are solved one by one.
//!
//! [`DiscreteProblem::scene`] shows the scene; its functions do not serialise, so it is looked
//! at with `Debug` (they print as `<function>`) rather than written as a scene file.
//!
//! ```
//! use std::sync::Arc;
//! use vem_mesh::generators::{structured_quads, Rectangle};
//! use vem_verify::exact::{case_by_name, Lame};
//! use vem_verify::problem::{DiscreteProblem, ProblemSettings};
//! use vem_contact::ExactSolver;
//! // The linear patch test PT0a is reproduced exactly by the VEM on any mesh.
//! let case: Arc<_> = case_by_name("PT0a", Lame::default())?.into();
//! let mesh = structured_quads(&Rectangle::unit_square(), 3, 3)?;
//! let problem = DiscreteProblem::try_new(case, vec![mesh], &ProblemSettings::default())?;
//! let solution = problem.solve(&mut ExactSolver::default())?;
//! let errors = solution.errors(&**problem.exact())?;
//! assert!(errors[0].grad < 1e-12 && errors[0].energy < 1e-12);
//! // The problem is a scene: one body, its mesh inline, four traction points per edge.
//! let body = &problem.scene().bodies[0];
//! assert_eq!((body.name.as_str(), body.traction_points), ("PT0a-body-1", Some(4)));
//! assert_eq!(body.mesh.polygons.as_ref().map(Vec::len), Some(9));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::sync::Arc;
use std::time::{Duration, Instant};

use vem_contact::{
    BodyResult, ContactLaw, ContactProblem, ContactSolver, FixedPointReport, InterfaceNode,
    SolveReport, StageTimes, WorkCounters,
};
use vem_elastic::{CholeskySolver, ElasticBody};
use vem_mesh::{Mesh, Point};
use vem_scene::description::{
    BodyDescription, ContactDescription, DirichletDescription, MaterialDescription,
    PlaneDescription, TractionDescription,
};
use vem_scene::resources::MemoryLimit;
use vem_scene::{BuildOptions, BuiltMesh, Model, Registries, ScalarValue, Scene, VectorValue};
use vem_space::{Choice, ElementRegistry, ElementSpace, LowestOrderVem, RegistryError};

use crate::exact::{BodyId, ExactSolution, CONTACT_SIDES};
use crate::norms::{body_errors, ErrorNorms};
use crate::VerifyError;

/// How a discrete problem is built from an exact solution; build it with
/// [`ProblemSettings::builder`] or take the [`Default`].
#[derive(Clone)]
pub struct ProblemSettings {
    element: Arc<dyn ElementSpace>,
    /// The element given by the user (registered under [`ELEMENT`]); `None`: the default.
    given_element: Option<Arc<dyn ElementSpace>>,
    traction_points: usize,
    law: Option<Arc<dyn ContactLaw>>,
    memory_limit: Option<MemoryLimit>,
}

impl ProblemSettings {
    /// Four points per edge: exact for tractions of degree <= 6 along an edge (the built-in
    /// tractions are of degree <= 2 along the lateral sides; a user's solution may be
    /// trigonometric), and a negligible cost on the boundary.
    pub const DEFAULT_TRACTION_POINTS: usize = 4;

    /// A builder starting from the defaults.
    pub fn builder() -> ProblemSettingsBuilder {
        ProblemSettingsBuilder {
            settings: Self::default(),
        }
    }

    /// The element space of every body (default: [`LowestOrderVem::default`]).
    pub fn element(&self) -> &Arc<dyn ElementSpace> {
        &self.element
    }

    /// Gauss–Legendre points per boundary edge for the tractions (default
    /// [`ProblemSettings::DEFAULT_TRACTION_POINTS`]).
    pub fn traction_points(&self) -> usize {
        self.traction_points
    }

    /// The contact law that replaces the case's own (default: none, the case's law).
    pub fn law(&self) -> Option<&Arc<dyn ContactLaw>> {
        self.law.as_ref()
    }

    /// The memory limit the problem's scene is built under (default: `None`, the memory the
    /// system reports available; see [`vem_scene::resources`]).
    pub fn memory_limit(&self) -> Option<MemoryLimit> {
        self.memory_limit
    }

    /// The same settings with another contact law.
    pub(crate) fn with_law(mut self, law: Arc<dyn ContactLaw>) -> Self {
        self.law = Some(law);
        self
    }

    /// The same settings with another element space.
    pub(crate) fn with_element(mut self, element: Arc<dyn ElementSpace>) -> Self {
        self.element = Arc::clone(&element);
        self.given_element = Some(element);
        self
    }
}

impl Default for ProblemSettings {
    fn default() -> Self {
        Self {
            element: Arc::new(LowestOrderVem::default()),
            given_element: None,
            traction_points: Self::DEFAULT_TRACTION_POINTS,
            law: None,
            memory_limit: None,
        }
    }
}

/// Builder of [`ProblemSettings`]; values are checked by [`ProblemSettingsBuilder::build`].
#[derive(Clone)]
pub struct ProblemSettingsBuilder {
    settings: ProblemSettings,
}

impl ProblemSettingsBuilder {
    /// The element space of every body.
    pub fn element(mut self, element: Arc<dyn ElementSpace>) -> Self {
        self.settings = self.settings.with_element(element);
        self
    }

    /// A contact law in place of the case's own: the same exact solution solved under another
    /// law (a law of one's own against a case whose answer it must reproduce, say).
    pub fn law(mut self, law: Arc<dyn ContactLaw>) -> Self {
        self.settings.law = Some(law);
        self
    }

    /// Gauss–Legendre points per boundary edge for the tractions.
    pub fn traction_points(mut self, points: usize) -> Self {
        self.settings.traction_points = points;
        self
    }

    /// The memory limit the scene is built under, in place of the memory the system reports
    /// available (a benchmark that measures the memory itself, up to sizes the estimate of a
    /// run refuses).
    pub fn memory_limit(mut self, limit: MemoryLimit) -> Self {
        self.settings.memory_limit = Some(limit);
        self
    }

    /// Validates the settings (the number of traction points must give a Gauss–Legendre rule).
    ///
    /// # Errors
    /// [`VerifyError::InvalidSetting`] naming the setting.
    pub fn build(self) -> Result<ProblemSettings, VerifyError> {
        vem_space::quadrature::GaussLegendre::try_new(self.settings.traction_points).map_err(
            |e| VerifyError::InvalidSetting {
                reason: format!("traction_points = {}: {e}", self.settings.traction_points),
            },
        )?;
        Ok(self.settings)
    }
}

impl std::fmt::Debug for ProblemSettingsBuilder {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.settings.fmt(f)
    }
}

impl std::fmt::Debug for ProblemSettings {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ProblemSettings")
            .field("element", &self.element.name())
            .field("traction_points", &self.traction_points)
            .field("law", &self.law.as_ref().map(|l| l.describe()))
            .field("memory_limit", &self.memory_limit)
            .finish()
    }
}

/// The name under which a settings' element ([`ProblemSettingsBuilder::element`]) is
/// registered in the element registry the scene is built with (the default element is the
/// built-in `"vem1"`).
pub const ELEMENT: &str = "verify-element";

/// The name under which the problem's contact law (the case's own, or
/// [`ProblemSettings::law`]) is registered in the law registry the scene is built with.
pub const LAW: &str = "verify-law";

/// The scene of `exact` with one mesh per body (see the module docs for the data), and the
/// registries that give its element and law their names.
fn scene_of(
    exact: &Arc<dyn ExactSolution>,
    meshes: Vec<Mesh>,
    settings: &ProblemSettings,
) -> Result<(Scene, Registries), VerifyError> {
    let ids = exact.bodies();
    let law = exact
        .contact()
        .map(|contact| settings.law.clone().unwrap_or_else(|| contact.law()));
    let registries =
        registries_with(settings.given_element.clone(), law).map_err(|e| invalid(e.to_string()))?;
    let element = match settings.given_element {
        Some(_) => ELEMENT,
        None => ElementRegistry::DEFAULT,
    };
    let lame = exact.lame();
    let names: Vec<String> = ids.iter().map(|&id| body_name(&**exact, id)).collect();
    let mut scene = Scene {
        title: Some(exact.name().to_string()),
        ..Scene::default()
    };
    for ((&body, mesh), name) in ids.iter().zip(meshes).zip(&names) {
        let mut spec = BodyDescription {
            name: name.clone(),
            mesh: BuiltMesh::Plane(mesh).to_inline(),
            material: MaterialDescription {
                lambda: Some(lame.lambda()),
                mu: Some(lame.mu()),
                plane: Some(PlaneDescription::Strain),
                ..MaterialDescription::default()
            },
            element: Some(Choice::named(element)),
            traction_points: Some(settings.traction_points),
            ..BodyDescription::default()
        };
        for side in exact.dirichlet_sides(body) {
            let component = |k: usize| {
                let exact = Arc::clone(exact);
                ScalarValue::function(move |x, _| exact.displacement(body, point(x))[k])
            };
            spec.dirichlet.push(DirichletDescription {
                part: side.name().to_string(),
                x: Some(component(0)),
                y: Some(component(1)),
                ..DirichletDescription::default()
            });
        }
        for side in exact.neumann_sides(body) {
            let exact = Arc::clone(exact);
            spec.traction.push(TractionDescription {
                part: side.name().to_string(),
                value: Some(VectorValue::function(move |x, _| {
                    let g = exact.traction(body, side, point(x));
                    vec![g.x, g.y]
                })),
                ..TractionDescription::default()
            });
        }
        let force = Arc::clone(exact);
        spec.body_force = Some(VectorValue::function(move |x, _| {
            let f = force.body_force(body, point(x));
            vec![f.x, f.y]
        }));
        scene.bodies.push(spec);
    }
    if exact.contact().is_some() {
        let [(_, side_a), (_, side_b)] = CONTACT_SIDES;
        let gap = Arc::clone(exact);
        scene.contacts.push(ContactDescription {
            body: names[0].clone(),
            part: side_a.name().to_string(),
            other_body: Some(names[1].clone()),
            other_part: Some(side_b.name().to_string()),
            law: Some(Choice::named(LAW)),
            imposed_gap: Some(ScalarValue::function(move |x, _| {
                gap.contact().map_or(0.0, |c| c.initial_gap(x[0]))
            })),
            ..ContactDescription::default()
        });
    }
    Ok((scene, registries))
}

/// The built-in registries with `element`, if given, registered as [`ELEMENT`] and `law`, if
/// given, as [`LAW`].
pub(crate) fn registries_with(
    element: Option<Arc<dyn ElementSpace>>,
    law: Option<Arc<dyn ContactLaw>>,
) -> Result<Registries, RegistryError> {
    let mut registries = Registries::default();
    if let Some(element) = element {
        let summary = format!("the element of the study: {}", element.name());
        registries
            .elements
            .register(ELEMENT, summary, move || Arc::clone(&element))?;
    }
    if let Some(law) = law {
        let summary = format!("the law of the study: {}", law.describe());
        registries.laws.register(LAW, summary, move |options| {
            options.refuse_all(LAW)?;
            Ok(Arc::clone(&law))
        })?;
    }
    Ok(registries)
}

/// The point of the coordinates `x` of a scene's function.
fn point(x: &[f64]) -> Point {
    Point::new(x[0], x[1])
}

/// An invalid setting.
fn invalid(reason: String) -> VerifyError {
    VerifyError::InvalidSetting { reason }
}

/// The scene's name of the body `body` of `exact`: "M1-body-1".
fn body_name(exact: &dyn ExactSolution, body: BodyId) -> String {
    format!("{}-body-{}", scene_name(exact.name()), body.index() + 1)
}

/// `name` as a scene's body name: the characters a body name may not hold replaced by `-`, a
/// leading `.` removed ("M1-3D body 1" gives "M1-3D-body-1").
pub(crate) fn scene_name(name: &str) -> String {
    let name: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.') {
                c
            } else {
                '-'
            }
        })
        .collect();
    name.trim_start_matches('.').to_string()
}

/// A discrete problem: the scene of an exact solution on given meshes, built into a
/// [`Model`], ready to solve.
#[derive(Clone)]
pub struct DiscreteProblem {
    exact: Arc<dyn ExactSolution>,
    scene: Scene,
    model: Model,
    bodies: Vec<ElasticBody>,
}

impl std::fmt::Debug for DiscreteProblem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DiscreteProblem")
            .field("case", &self.exact.name())
            .field("bodies", &self.bodies)
            .finish()
    }
}

impl DiscreteProblem {
    /// The problem of `exact` with one mesh per body (in the order of
    /// [`ExactSolution::bodies`]): its scene ([`DiscreteProblem::scene`]) built by
    /// [`Model::build`].
    ///
    /// # Errors
    /// A wrong number of meshes, a contact case without two bodies, [`VerifyError::Scene`]
    /// for a scene the model refuses (an invalid material or setting, a side the mesh does
    /// not name, inconsistent Dirichlet data).
    pub fn try_new(
        exact: Arc<dyn ExactSolution>,
        meshes: Vec<Mesh>,
        settings: &ProblemSettings,
    ) -> Result<Self, VerifyError> {
        let ids = exact.bodies();
        if meshes.len() != ids.len() {
            return Err(VerifyError::Case {
                case: exact.name().to_string(),
                reason: format!("{} bodies but {} meshes given", ids.len(), meshes.len()),
            });
        }
        if exact.contact().is_some() && ids != BodyId::BOTH {
            return Err(VerifyError::Case {
                case: exact.name().to_string(),
                reason: "a contact solution must have the two bodies One and Two".to_string(),
            });
        }
        let (scene, registries) = scene_of(&exact, meshes, settings)?;
        let options = BuildOptions {
            registries,
            memory_limit: settings.memory_limit,
            ..BuildOptions::default()
        };
        let model = Model::build(&scene, &options).map_err(|source| VerifyError::Scene {
            case: exact.name().to_string(),
            source: Box::new(source),
        })?;
        let bodies = model.bodies().iter().map(|b| b.body.clone()).collect();
        Ok(Self {
            exact,
            scene,
            model,
            bodies,
        })
    }

    /// The exact solution.
    pub fn exact(&self) -> &Arc<dyn ExactSolution> {
        &self.exact
    }

    /// The problem as a scene: one body per body of the exact solution with its mesh inline,
    /// the material by `lambda` and `mu` in plane strain, the exact data as functions, the
    /// element and law by the names [`ELEMENT`] (a settings' element, else `"vem1"`) and
    /// [`LAW`] of the registries it was built with. The functions do not serialise: a scene
    /// written with serde stops at the first one (its meshes and keys can be looked at with
    /// `Debug`, which prints `<function>` for them).
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The model the scene was built into (bodies, contact problem, registries).
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// The bodies on their given meshes (before any interface node insertion).
    pub fn bodies(&self) -> &[ElasticBody] {
        &self.bodies
    }

    /// The mesh size `h`: the largest polygon diameter over all bodies.
    pub fn mesh_size(&self) -> f64 {
        self.bodies
            .iter()
            .map(|b| b.mesh().mesh_size())
            .fold(0.0, f64::max)
    }

    /// The contact problem of a contact case (`None` for elasticity cases): body one's bottom
    /// against body two's top, the case's law (or the settings' [`ProblemSettings::law`]),
    /// `h0` as the imposed gap; the model's ([`Model::contact_problem`]).
    pub fn contact_problem(&self) -> Option<ContactProblem> {
        self.model
            .contact_problem()
            .map(|(problem, _)| problem.clone())
    }

    /// Solves: the contact problem with `solver` for a contact case, otherwise every body
    /// with the sparse Cholesky solver (`solver` unused).
    ///
    /// # Errors
    /// Assembly, interface or solver failures, naming the case.
    pub fn solve(&self, solver: &mut dyn ContactSolver) -> Result<DiscreteSolution, VerifyError> {
        let case = self.exact.name().to_string();
        if let Some(problem) = self.contact_problem() {
            let mut result = problem
                .solve(solver)
                .map_err(|source| VerifyError::Contact {
                    case: case.clone(),
                    source: Box::new(source),
                })?;
            return Ok(DiscreteSolution {
                bodies: std::mem::take(&mut result.bodies),
                interface: Some(InterfaceOutcome {
                    nodes: result.nodes,
                    report: result.report,
                    fixed_point: result.fixed_point,
                    inserted_nodes: result.model.inserted_nodes,
                }),
                work: result.work,
                assembly_time: result.work.times.insertion + result.work.times.assembly,
                solve_time: result.work.times.contact_solve,
            });
        }
        let elastic = |source| VerifyError::Elastic {
            case: case.clone(),
            source: Box::new(source),
        };
        let (mut assembly_time, mut solve_time) = (Duration::ZERO, Duration::ZERO);
        let mut bodies = Vec::with_capacity(self.bodies.len());
        for body in &self.bodies {
            let start = Instant::now();
            let system = body.assemble().map_err(elastic)?;
            assembly_time += start.elapsed();
            let start = Instant::now();
            let solution = body
                .solve_system(&system, &mut CholeskySolver::default())
                .map_err(elastic)?;
            solve_time += start.elapsed();
            bodies.push(BodyResult {
                body: body.clone(),
                system: Arc::new(system),
                solution,
            });
        }
        // One assembly, symbolic analysis, factorisation and solve per body.
        let count = self.bodies.len();
        let work = WorkCounters {
            assemblies: count,
            symbolic_analyses: count,
            numeric_factorisations: count,
            triangular_solves: count,
            times: StageTimes {
                assembly: assembly_time,
                contact_solve: solve_time,
                ..StageTimes::default()
            },
        };
        Ok(DiscreteSolution {
            bodies,
            interface: None,
            work,
            assembly_time,
            solve_time,
        })
    }
}

/// What the contact solve found on the interface.
#[derive(Debug, Clone)]
pub struct InterfaceOutcome {
    /// The interface nodes, ordered along body one's contact side.
    pub nodes: Vec<InterfaceNode>,
    /// The contact solver's report (iterations, KKT residuals) of the last solve.
    pub report: SolveReport,
    /// Coulomb friction: the report of the fixed point of Tresca problems.
    pub fixed_point: Option<FixedPointReport>,
    /// Vertices inserted into the two meshes to make the interface node-to-node.
    pub inserted_nodes: usize,
}

/// The solution of a [`DiscreteProblem`].
#[derive(Debug, Clone)]
pub struct DiscreteSolution {
    /// Per body (order of [`ExactSolution::bodies`]): the body on the mesh it was solved on
    /// (enlarged by interface node insertion for contact), its system and its solution.
    pub bodies: Vec<BodyResult>,
    /// Contact cases: the interface result.
    pub interface: Option<InterfaceOutcome>,
    /// What the solve computed: assemblies, symbolic analyses, numeric factorisations,
    /// triangular solves, stage times (for elasticity cases one of each per body).
    pub work: WorkCounters,
    /// Interface insertion and assembly time.
    pub assembly_time: Duration,
    /// Linear or contact solve time.
    pub solve_time: Duration,
}

impl DiscreteSolution {
    /// The error measures of every body against `exact` (the solution the problem was built
    /// from), in the order of [`ExactSolution::bodies`]; combine them with
    /// [`ErrorNorms::combine`].
    ///
    /// # Errors
    /// As [`body_errors`].
    pub fn errors(&self, exact: &dyn ExactSolution) -> Result<Vec<ErrorNorms>, VerifyError> {
        exact
            .bodies()
            .iter()
            .zip(&self.bodies)
            .map(|(&id, result)| {
                body_errors(
                    exact,
                    id,
                    &result.body,
                    &result.system,
                    result.solution.displacement(),
                )
            })
            .collect()
    }
}
