//! Discrete problems built from an exact solution, and their solution.
//!
//! For every body of an [`ExactSolution`]: a mesh of its domain, the material of
//! [`ExactSolution::lame`] (plane strain), the exact displacement as Dirichlet data on the
//! [`dirichlet_sides`](ExactSolution::dirichlet_sides), the exact traction `sigma nu` on the
//! [`neumann_sides`](ExactSolution::neumann_sides) and the exact body force. A contact case
//! (`ExactSolution::contact` is `Some`) becomes a [`ContactProblem`] between the bottom side
//! of body one and the top side of body two ([`CONTACT_SIDES`]) with the case's law and its
//! initial gap `h0(x)` as the imposed gap: the two sides coincide, so the geometric gap is zero
//! and the total gap is `h0` (spec section 1). Bodies without an interface are solved one by
//! one.
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
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::sync::Arc;
use std::time::{Duration, Instant};

use vem_contact::{
    BodyResult, ContactLaw, ContactProblem, ContactSolver, FixedPointReport, InterfaceNode,
    SolveReport, StageTimes, WorkCounters,
};
use vem_elastic::{CholeskySolver, Component, Dirichlet, ElasticBody, Material, Plane};
use vem_mesh::Mesh;
use vem_space::{ElementSpace, LowestOrderVem};

use crate::exact::{BodyId, ExactSolution, CONTACT_SIDES};
use crate::norms::{body_errors, ErrorNorms};
use crate::VerifyError;

/// How a discrete problem is built from an exact solution; build it with
/// [`ProblemSettings::builder`] or take the [`Default`].
#[derive(Clone)]
pub struct ProblemSettings {
    element: Arc<dyn ElementSpace>,
    traction_points: usize,
    law: Option<Arc<dyn ContactLaw>>,
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

    /// The same settings with another contact law.
    pub(crate) fn with_law(mut self, law: Arc<dyn ContactLaw>) -> Self {
        self.law = Some(law);
        self
    }

    /// The same settings with another element space.
    pub(crate) fn with_element(mut self, element: Arc<dyn ElementSpace>) -> Self {
        self.element = element;
        self
    }
}

impl Default for ProblemSettings {
    fn default() -> Self {
        Self {
            element: Arc::new(LowestOrderVem::default()),
            traction_points: Self::DEFAULT_TRACTION_POINTS,
            law: None,
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
        self.settings.element = element;
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
            .finish()
    }
}

/// The elastic body `body` of `exact` on `mesh` (see the module docs for the data).
///
/// # Errors
/// An invalid material or setting, a side the mesh does not name, inconsistent Dirichlet data.
pub fn elastic_body(
    exact: &Arc<dyn ExactSolution>,
    body: BodyId,
    mesh: Mesh,
    settings: &ProblemSettings,
) -> Result<ElasticBody, VerifyError> {
    let case = exact.name().to_string();
    let lame = exact.lame();
    let elastic = |source| VerifyError::Elastic {
        case: case.clone(),
        source: Box::new(source),
    };
    let material = Material::from_lame(lame.lambda(), lame.mu(), Plane::Strain).map_err(elastic)?;
    let mut builder = ElasticBody::builder(
        format!("{case} body {}", body.index() + 1),
        mesh,
        material,
        Arc::clone(&settings.element),
    )
    .traction_points(settings.traction_points);
    for side in exact.dirichlet_sides(body) {
        let exact = Arc::clone(exact);
        builder = builder.dirichlet(Dirichlet::prescribed(
            side.name(),
            Component::All,
            move |x| exact.displacement(body, x),
        ));
    }
    for side in exact.neumann_sides(body) {
        let exact = Arc::clone(exact);
        builder = builder.traction(side.name(), move |x| exact.traction(body, side, x));
    }
    let force = Arc::clone(exact);
    builder
        .body_force(move |x| force.body_force(body, x))
        .build()
        .map_err(elastic)
}

/// A discrete problem: the bodies of an exact solution on given meshes, ready to solve.
#[derive(Clone)]
pub struct DiscreteProblem {
    exact: Arc<dyn ExactSolution>,
    bodies: Vec<ElasticBody>,
    law: Option<Arc<dyn ContactLaw>>,
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
    /// [`ExactSolution::bodies`]).
    ///
    /// # Errors
    /// A wrong number of meshes, a contact case without two bodies, any error of
    /// [`elastic_body`].
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
        let bodies = ids
            .iter()
            .zip(meshes)
            .map(|(&id, mesh)| elastic_body(&exact, id, mesh, settings))
            .collect::<Result<_, _>>()?;
        Ok(Self {
            exact,
            bodies,
            law: settings.law.clone(),
        })
    }

    /// The exact solution.
    pub fn exact(&self) -> &Arc<dyn ExactSolution> {
        &self.exact
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
    /// `h0` as the imposed gap.
    pub fn contact_problem(&self) -> Option<ContactProblem> {
        let contact = self.exact.contact()?;
        let law = self.law.clone().unwrap_or_else(|| contact.law());
        let [(_, side_a), (_, side_b)] = CONTACT_SIDES;
        let exact = Arc::clone(&self.exact);
        let problem = ContactProblem::two_bodies(
            self.bodies[0].clone(),
            side_a.name(),
            self.bodies[1].clone(),
            side_b.name(),
            law,
        )
        .with_imposed_gap(move |x| exact.contact().map_or(0.0, |c| c.initial_gap(x.x)));
        Some(problem)
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
