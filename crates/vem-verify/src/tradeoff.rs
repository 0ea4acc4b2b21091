//! The speed-accuracy trade of the contact solvers' settings (`cargo xtask tradeoff`,
//! `docs/tradeoff.md`) on the manufactured cases: a solver setting by its label
//! ([`SolverSetting`]: a preset, or `solver@key=value`), one measurement group (one case on one
//! mesh pairing at one size, discretised once: [`TradeoffGroup`]) and the errors of a setting's
//! solve against the exact solution ([`TradeoffGroup::errors`]). The `xtask` command adds the
//! problems without exact solution (Hertz, Coulomb against a fine reference), the process's
//! CPU time and peak memory; the Python package runs the same groups.
//!
//! ```
//! use vem_verify::tradeoff::{SolverSetting, TradeoffGroup};
//! let group = TradeoffGroup::build("M1", "quads/quads", "vem1", 8)?;
//! let discretisation = group.discretisation().expect("M1 is a contact case");
//! let mut e_grad = Vec::new();
//! for label in ["exact", "penalty@factor=1e8"] {
//!     let setting: SolverSetting = label.parse()?;
//!     let result = discretisation.solve(setting.make()?.as_mut()).expect("solved");
//!     e_grad.push(group.errors(result)?.e_grad);
//! }
//! // One discretisation: the penalty's stiff setting gives the exact solver's error.
//! assert!((e_grad[1] - e_grad[0]).abs() < 1e-3 * e_grad[0], "{e_grad:?}");
//! assert!("penalty@stiffness=2".parse::<SolverSetting>().is_err());
//! # Ok::<(), vem_verify::VerifyError>(())
//! ```

use std::str::FromStr;
use std::sync::Arc;
use std::time::Instant;

use serde::{Deserialize, Serialize};
use vem_contact::{
    AccuracyPreset, ContactDiscretisation, ContactResult, ContactSolver, PenaltyParameter,
    SolverRegistry,
};
use vem_elastic::{CholeskySolver, ElasticBody};
use vem_mesh::generators::polyhedral::{Cuboid, PolyhedralFamily};
use vem_mesh::PointD;
use vem_space::{Choice, ElementRegistry, Options};

use crate::diagnostics::contact_diagnostics;
use crate::exact::{case_by_name, BodyId, ExactSolution, Lame};
use crate::norms::ErrorNorms;
use crate::problem::{DiscreteProblem, DiscreteSolution, InterfaceOutcome, ProblemSettings};
use crate::study::{MeshPairing, Study};
use crate::three_d::{
    body_errors_3d, disc_contact_problem, solid_body, solid_case_by_name, DiscContact,
    ExactSolution3d, SOLID_SEED,
};
use crate::VerifyError;

/// The settings of the full study.
pub const FULL_SETTINGS: [&str; 10] = [
    "draft",
    "balanced",
    "reference",
    "exact",
    "exact@tol=1e-4",
    "penalty@factor=1e4",
    "penalty@factor=1e6",
    "penalty@factor=1e8",
    "active-set",
    "active-set@aug=1e-2",
];

/// The settings of the quick study.
pub const QUICK_SETTINGS: [&str; 4] = ["draft", "reference", "exact", "penalty@factor=1e6"];

/// Poisson's ratio of the near-incompressible cases, `"E2c"` of [`TradeoffGroup::build`] and
/// `"E2-3D"` of [`SolidGroup::build`] (with `mu = 1`).
pub const E2C_POISSON_RATIO: f64 = 0.4999;

/// The material of the near-incompressible cases: `mu = 1`, `lambda = 2 mu nu / (1 - 2 nu)` at
/// `nu =` [`E2C_POISSON_RATIO`], as in the extremes suite.
fn near_incompressible() -> Result<Lame, VerifyError> {
    let nu = E2C_POISSON_RATIO;
    Ok(Lame::try_new(2.0 * nu / (1.0 - 2.0 * nu), 1.0)?)
}
/// The suffix of an element name that inserts every edge's midpoint into the meshes
/// (`"vem1-bbar+midpoints"`: what a scene chooses on triangles close to incompressibility).
pub const MIDPOINTS: &str = "+midpoints";

/// One solver setting: a registry name and its options, with a label such as
/// `penalty@factor=1e6`; the accuracy presets go by their names ("draft", "balanced",
/// "reference").
#[derive(Debug, Clone)]
pub struct SolverSetting {
    /// The label it was read from (a preset's name, or `solver[@key=value]`).
    pub label: String,
    /// The solver's registry name.
    pub solver: String,
    /// The solver's options.
    pub options: Options,
}

impl SolverSetting {
    /// The solver of this setting, from the built-in registry.
    ///
    /// # Errors
    /// [`VerifyError::InvalidSetting`] when the registry refuses the options.
    pub fn make(&self) -> Result<Box<dyn ContactSolver>, VerifyError> {
        SolverRegistry::builtin()
            .make(&self.solver, &self.options)
            .map_err(|e| VerifyError::InvalidSetting {
                reason: format!("setting '{}': {e}", self.label),
            })
    }
}

impl FromStr for SolverSetting {
    type Err = VerifyError;

    /// A preset name (`draft`, `balanced`, `reference`) or `solver[@key=value]` with the key
    /// `tol` (tolerance), `factor` (penalty relative to the stiffness) or `aug` (augmentation
    /// relative to the stiffness).
    fn from_str(label: &str) -> Result<Self, VerifyError> {
        let invalid = |reason: String| VerifyError::InvalidSetting { reason };
        if let Ok(preset) = label.parse::<AccuracyPreset>() {
            return Ok(Self {
                label: preset.name().to_string(),
                solver: preset.solver().to_string(),
                options: preset.solver_options(),
            });
        }
        let (solver, option) = match label.split_once('@') {
            Some((s, o)) => (s, Some(o)),
            None => (label, None),
        };
        let mut options = Options::new();
        if let Some(option) = option {
            let (key, value) = option
                .split_once('=')
                .ok_or_else(|| invalid(format!("setting '{label}': give key=value after '@'")))?;
            let value: f64 = value
                .parse()
                .map_err(|_| invalid(format!("setting '{label}': '{value}' is not a number")))?;
            options = match key {
                "tol" => options.with("tolerance", value),
                "factor" => options.with("penalty", PenaltyParameter::RelativeToStiffness(value)),
                "aug" => options.with("augmentation", PenaltyParameter::RelativeToStiffness(value)),
                _ => {
                    return Err(invalid(format!(
                        "setting '{label}': unknown key '{key}' (tol, factor, aug)"
                    )))
                }
            };
        }
        let registry = SolverRegistry::builtin();
        if !registry.contains(solver) {
            return Err(invalid(format!(
                "setting '{label}': unknown solver '{solver}'; the solvers are {}",
                registry.names().join(", ")
            )));
        }
        Ok(Self {
            label: label.to_string(),
            solver: solver.to_string(),
            options,
        })
    }
}

/// The errors of one setting's solve against the exact solution, relative.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct ContactErrors {
    /// `E_grad / |u|_1`.
    pub e_grad: f64,
    /// `E_0 / ||u||_0`.
    pub e_0: f64,
    /// `E_a / |u_I|_a`.
    pub e_a: f64,
    /// Contact cases: the nodal pressure against the exact one, discrete L2 on the contact
    /// part (tributary lengths) relative to the exact pressure's.
    pub pressure_l2: Option<f64>,
    /// The same in the max norm, relative to the exact peak pressure.
    pub pressure_max: Option<f64>,
    /// Contact cases: the normal resultant against the exact one, relative (absolute when
    /// the exact one is zero).
    pub resultant: Option<f64>,
    /// Contact cases: interface nodes whose status contradicts the exact contact sets.
    pub misclassified: Option<usize>,
}

/// One measurement group of a manufactured case: the case on a mesh pairing at size `n`,
/// built once (meshes, bodies; for a contact case the interface insertion, assembly and
/// constraint rows), to be solved with every setting.
pub struct TradeoffGroup {
    problem: DiscreteProblem,
    discretisation: Option<ContactDiscretisation>,
    /// The mesh size (largest polygon diameter).
    pub h: f64,
    /// Seconds spent generating the meshes and building the bodies.
    pub mesh_generation: f64,
}

impl std::fmt::Debug for TradeoffGroup {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("TradeoffGroup")
            .field("case", &self.problem.exact().name())
            .field("h", &self.h)
            .field("contact", &self.discretisation.is_some())
            .finish()
    }
}

impl TradeoffGroup {
    /// The group of the manufactured case `case` (a name of [`crate::exact::all_cases`], or
    /// `"E2c"`: the divergence-free contact solution at nu = [`E2C_POISSON_RATIO`]) on
    /// `pairing` (`"quads/quads*3"`, `"voronoi"`) at size `n` with the element `element` (a
    /// name of the element registry, with [`MIDPOINTS`] appended for the meshes with every
    /// edge's midpoint inserted), the meshes of the studies' seed.
    ///
    /// # Errors
    /// An unknown case, pairing or element; a mesh, body or discretisation that fails.
    pub fn build(case: &str, pairing: &str, element: &str, n: usize) -> Result<Self, VerifyError> {
        let start = Instant::now();
        let exact: Arc<dyn ExactSolution> = if case == "E2c" {
            Arc::new(crate::exact::DivergenceFreeContact::new(
                near_incompressible()?,
            ))
        } else {
            Arc::from(case_by_name(case, Lame::default())?)
        };
        let pairing: MeshPairing = pairing.parse()?;
        let mut meshes = pairing.generate(&*exact, n, Study::DEFAULT_SEED)?;
        let element = match element.strip_suffix(MIDPOINTS) {
            Some(name) => {
                meshes = meshes
                    .iter()
                    .map(|m| m.with_edge_midpoints())
                    .collect::<Result<_, _>>()
                    .map_err(|e| VerifyError::InvalidSetting {
                        reason: format!("edge midpoints: {e}"),
                    })?;
                name
            }
            None => element,
        };
        let element =
            ElementRegistry::builtin()
                .make(element)
                .map_err(|e| VerifyError::InvalidSetting {
                    reason: e.to_string(),
                })?;
        let settings = ProblemSettings::builder().element(element).build()?;
        let problem = DiscreteProblem::try_new(Arc::clone(&exact), meshes, &settings)?;
        let mesh_generation = start.elapsed().as_secs_f64();
        let h = problem.mesh_size();
        let discretisation = match problem.contact_problem() {
            Some(contact) => {
                Some(
                    contact
                        .into_discretisation()
                        .map_err(|e| VerifyError::Contact {
                            case: exact.name().to_string(),
                            source: Box::new(e),
                        })?,
                )
            }
            None => None,
        };
        Ok(Self {
            problem,
            discretisation,
            h,
            mesh_generation,
        })
    }

    /// The problem (the exact solution, the bodies on their meshes).
    pub fn problem(&self) -> &DiscreteProblem {
        &self.problem
    }

    /// A contact case's discretisation, to be solved with each setting (`None` for an
    /// elasticity case: [`DiscreteProblem::solve`] solves it).
    pub fn discretisation(&self) -> Option<&ContactDiscretisation> {
        self.discretisation.as_ref()
    }

    /// The errors of a contact result of this group's discretisation against the exact
    /// solution: the energy, gradient and L2 errors of the displacements, the pressure's,
    /// the normal resultant's and the misclassified nodes.
    ///
    /// # Errors
    /// A case without contact, a failed error measure.
    pub fn errors(&self, result: ContactResult) -> Result<ContactErrors, VerifyError> {
        let exact = self.problem.exact();
        let contact = exact.contact().ok_or_else(|| VerifyError::Case {
            case: exact.name().to_string(),
            reason: "no contact".to_string(),
        })?;
        let (l2, max) = pressure_errors(&result, |p| -contact.interface_values(p.x).sigma_nu);
        let diagnostics = contact_diagnostics(contact, &result.nodes);
        let scale = diagnostics.normal_resultant_exact.abs();
        let resultant = if scale > 0.0 {
            diagnostics.normal_resultant_error / scale
        } else {
            diagnostics.normal_resultant_error
        };
        let solution = DiscreteSolution {
            bodies: result.bodies,
            interface: Some(InterfaceOutcome {
                nodes: result.nodes,
                report: result.report,
                fixed_point: result.fixed_point,
                inserted_nodes: result.model.inserted_nodes,
            }),
            work: result.work,
            assembly_time: result.work.times.insertion + result.work.times.assembly,
            solve_time: result.work.times.contact_solve,
        };
        let errors = ErrorNorms::combine(&solution.errors(&**exact)?);
        Ok(ContactErrors {
            e_grad: errors.relative_grad(),
            e_0: errors.relative_l2(),
            e_a: errors.relative_energy(),
            pressure_l2: Some(l2),
            pressure_max: Some(max),
            resultant: Some(resultant),
            misclassified: Some(diagnostics.set_violations.len()),
        })
    }

    /// The errors of an elasticity case's solution ([`DiscreteProblem::solve`]).
    ///
    /// # Errors
    /// A failed error measure.
    pub fn elasticity_errors(
        &self,
        solution: &DiscreteSolution,
    ) -> Result<ContactErrors, VerifyError> {
        let errors = ErrorNorms::combine(&solution.errors(&**self.problem.exact())?);
        Ok(ContactErrors {
            e_grad: errors.relative_grad(),
            e_0: errors.relative_l2(),
            e_a: errors.relative_energy(),
            ..ContactErrors::default()
        })
    }
}

/// Discrete L2 (tributary measures) and max errors of the nodal pressure against
/// `exact(position)`, relative to the exact pressure's norms (absolute when those are zero).
pub fn pressure_errors<const D: usize>(
    result: &ContactResult<D>,
    exact: impl Fn(&PointD<D>) -> f64,
) -> (f64, f64) {
    let (mut err2, mut norm2, mut err_max, mut norm_max) = (0.0, 0.0, 0.0_f64, 0.0_f64);
    for node in &result.nodes {
        let p = exact(&node.position);
        err2 += node.tributary_measure * (node.pressure - p).powi(2);
        norm2 += node.tributary_measure * p * p;
        err_max = err_max.max((node.pressure - p).abs());
        norm_max = norm_max.max(p.abs());
    }
    let relative = |e: f64, n: f64| if n > 0.0 { e / n } else { e };
    (
        relative(err2.sqrt(), norm2.sqrt()),
        relative(err_max, norm_max),
    )
}

/// One measurement group of a manufactured case in space, built once (meshes, bodies; for the
/// contact case the surface overlay, assembly and constraint rows), to be solved with every
/// setting: the counterpart of [`TradeoffGroup`] on polyhedral meshes.
///
/// ```
/// use vem_verify::tradeoff::{SolidGroup, SolverSetting};
/// let group = SolidGroup::build("M1-3D", "hexahedra/tetrahedra*0.75", "vem1", 4)?;
/// let discretisation = group.discretisation().expect("M1-3D is a contact case");
/// let mut e_grad = Vec::new();
/// for label in ["reference", "exact"] {
///     let setting: SolverSetting = label.parse()?;
///     let result = discretisation.solve(setting.make()?.as_mut()).expect("solved");
///     e_grad.push(group.errors(result)?.e_grad);
/// }
/// // One discretisation, two independent solvers: the same error.
/// assert!((e_grad[1] - e_grad[0]).abs() < 1e-6 * e_grad[0], "{e_grad:?}");
/// # Ok::<(), vem_verify::VerifyError>(())
/// ```
pub struct SolidGroup {
    case: SolidCase,
    /// The mesh size (largest cell diameter over the bodies).
    pub h: f64,
    /// Seconds spent generating the meshes and building the bodies.
    pub mesh_generation: f64,
}

/// What a [`SolidGroup`] solves.
enum SolidCase {
    /// M1-3D: two bodies in frictionless contact, discretised once.
    Contact {
        exact: DiscContact,
        discretisation: Box<ContactDiscretisation<3>>,
    },
    /// One body of an elasticity case.
    Elasticity {
        exact: Arc<dyn ExactSolution3d>,
        body: Box<ElasticBody<3>>,
    },
}

/// The solve of an elasticity group in space ([`SolidGroup::solve_elasticity`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolidElasticSolve {
    /// The errors against the exact solution (the contact fields `None`).
    pub errors: ContactErrors,
    /// Unknowns of the reduced system.
    pub unknowns: usize,
    /// Seconds of the assembly.
    pub assembly: f64,
    /// Seconds of the Cholesky solve.
    pub solve: f64,
}

impl std::fmt::Debug for SolidGroup {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let case = match &self.case {
            SolidCase::Contact { .. } => DiscContact::NAME.to_string(),
            SolidCase::Elasticity { exact, .. } => exact.name().to_string(),
        };
        f.debug_struct("SolidGroup")
            .field("case", &case)
            .field("h", &self.h)
            .finish()
    }
}

impl SolidGroup {
    /// The group of the case `case` in space: `"M1-3D"` (two bodies in contact on `pairing`
    /// `"upper/lower*r"`: the families of the upper and lower box, the lower at size
    /// `round(r n)`, `r = 1` when omitted), `"E1-3D"`, or `"E2-3D"` at nu =
    /// [`E2C_POISSON_RATIO`] (one body on the family `pairing`), at size `n` with the element
    /// `element` (a name of the element registry on polyhedra, with [`MIDPOINTS`] appended for
    /// the meshes with every edge's midpoint inserted), the meshes of the studies' seed.
    ///
    /// # Errors
    /// An unknown case, family or element; a size below one; a mesh, body or discretisation
    /// that fails.
    pub fn build(case: &str, pairing: &str, element: &str, n: usize) -> Result<Self, VerifyError> {
        let start = Instant::now();
        let invalid = |reason: String| VerifyError::InvalidSetting { reason };
        let (element, midpoints) = match element.strip_suffix(MIDPOINTS) {
            Some(name) => (name, true),
            None => (element, false),
        };
        let element = ElementRegistry::builtin()
            .make_polyhedral_choice(&Choice::named(element))
            .map_err(|e| invalid(e.to_string()))?;
        let generate = |family: &str, box_of: Cuboid, n: usize, body: usize| {
            let family: PolyhedralFamily = family
                .parse()
                .map_err(|e: vem_mesh::MeshError| invalid(format!("pairing '{pairing}': {e}")))?;
            let mesh =
                family
                    .generate(&box_of, n, SOLID_SEED)
                    .map_err(|source| VerifyError::Mesh {
                        case: case.to_string(),
                        body,
                        family: family.name().to_string(),
                        n,
                        source: Box::new(source),
                    })?;
            if midpoints {
                mesh.with_edge_midpoints()
                    .map_err(|e| invalid(format!("edge midpoints: {e}")))
            } else {
                Ok(mesh)
            }
        };
        if n == 0 {
            return Err(invalid(format!(
                "case '{case}': the size n must be at least 1"
            )));
        }
        let (case, h) = if case == DiscContact::NAME {
            let (families, ratio) = match pairing.split_once('*') {
                Some((families, ratio)) => {
                    let ratio: f64 = ratio.parse().map_err(|_| {
                        invalid(format!("pairing '{pairing}': '{ratio}' is not a number"))
                    })?;
                    (families, ratio)
                }
                None => (pairing, 1.0),
            };
            let (upper, lower) = families.split_once('/').ok_or_else(|| {
                invalid(format!(
                    "pairing '{pairing}': give the two families as upper/lower[*ratio]"
                ))
            })?;
            let lower_n = (ratio * n as f64).round();
            if !(1.0..=1e4).contains(&lower_n) {
                return Err(invalid(format!(
                    "pairing '{pairing}': the lower size round({ratio} x {n}) must be 1 to 10^4"
                )));
            }
            let upper = generate(upper, DiscContact::domain(BodyId::One), n, 1)?;
            let lower = generate(lower, DiscContact::domain(BodyId::Two), lower_n as usize, 2)?;
            let exact = DiscContact::new(Lame::default());
            let discretisation = disc_contact_problem(&exact, upper, lower, element)?
                .into_discretisation()
                .map_err(|e| VerifyError::Contact {
                    case: DiscContact::NAME.to_string(),
                    source: Box::new(e),
                })?;
            let h = discretisation
                .bodies()
                .iter()
                .map(|b| b.mesh().mesh_size())
                .fold(0.0, f64::max);
            let discretisation = Box::new(discretisation);
            (
                SolidCase::Contact {
                    exact,
                    discretisation,
                },
                h,
            )
        } else {
            let lame = if case == "E2-3D" {
                near_incompressible()?
            } else {
                Lame::default()
            };
            let exact: Arc<dyn ExactSolution3d> = Arc::from(
                solid_case_by_name(case, lame)
                    .filter(|e| e.contact_sides().is_empty())
                    .ok_or_else(|| {
                        invalid(format!(
                            "unknown case in space '{case}': M1-3D, E1-3D, E2-3D, PT0-3D"
                        ))
                    })?,
            );
            let mesh = generate(pairing, exact.domain(), n, 1)?;
            let h = mesh.mesh_size();
            let body = Box::new(solid_body(Arc::clone(&exact), mesh, element)?);
            (SolidCase::Elasticity { exact, body }, h)
        };
        Ok(Self {
            case,
            h,
            mesh_generation: start.elapsed().as_secs_f64(),
        })
    }

    /// The contact case's discretisation, to be solved with each setting (`None` for an
    /// elasticity case: [`SolidGroup::solve_elasticity`] solves it).
    pub fn discretisation(&self) -> Option<&ContactDiscretisation<3>> {
        match &self.case {
            SolidCase::Contact { discretisation, .. } => Some(discretisation),
            SolidCase::Elasticity { .. } => None,
        }
    }

    /// The errors of a contact result of this group's discretisation against M1-3D: the
    /// energy, gradient and L2 errors over both bodies, the pressure's, the normal
    /// resultant's, and the nodes whose status contradicts the exact contact disc farther than
    /// the mesh size `h` from its circle.
    ///
    /// # Errors
    /// An elasticity group, a failed error measure.
    pub fn errors(&self, result: ContactResult<3>) -> Result<ContactErrors, VerifyError> {
        let SolidCase::Contact { exact, .. } = &self.case else {
            return Err(VerifyError::Case {
                case: format!("{self:?}"),
                reason: "no contact".to_string(),
            });
        };
        let (l2, max) = pressure_errors(&result, |p| DiscContact::pressure(p.x, p.y));
        let exact_resultant = DiscContact::normal_resultant();
        let resultant = (result.normal_resultant() - exact_resultant).abs() / exact_resultant;
        let misclassified = result
            .nodes
            .iter()
            .filter(|n| {
                let r = DiscContact::radius(n.position.x, n.position.y);
                let active = n.status.is_active();
                (active && r > DiscContact::CONTACT_RADIUS + self.h)
                    || (!active && r < DiscContact::CONTACT_RADIUS - self.h)
            })
            .count();
        let mut errors = [ErrorNorms::default(); 2];
        for (k, id) in BodyId::BOTH.into_iter().enumerate() {
            let solved = &result.bodies[k];
            errors[k] = body_errors_3d(
                &exact.body(id),
                &solved.body,
                &solved.system,
                solved.solution.displacement(),
            )?;
        }
        let errors = ErrorNorms::combine(&errors);
        Ok(ContactErrors {
            e_grad: errors.relative_grad(),
            e_0: errors.relative_l2(),
            e_a: errors.relative_energy(),
            pressure_l2: Some(l2),
            pressure_max: Some(max),
            resultant: Some(resultant),
            misclassified: Some(misclassified),
        })
    }

    /// Assembles and solves an elasticity group (sparse Cholesky) and measures its errors.
    ///
    /// # Errors
    /// A contact group, a failed assembly, solve or error measure.
    pub fn solve_elasticity(&self) -> Result<SolidElasticSolve, VerifyError> {
        let SolidCase::Elasticity { exact, body } = &self.case else {
            return Err(VerifyError::InvalidSetting {
                reason: "M1-3D is a contact case: solve its discretisation".to_string(),
            });
        };
        let elastic = |source| VerifyError::Elastic {
            case: exact.name().to_string(),
            source: Box::new(source),
        };
        let start = Instant::now();
        let system = body.assemble().map_err(elastic)?;
        let assembly = start.elapsed().as_secs_f64();
        let start = Instant::now();
        let solution = body
            .solve_system(&system, &mut CholeskySolver::default())
            .map_err(elastic)?;
        let solve = start.elapsed().as_secs_f64();
        let errors = body_errors_3d(&**exact, body, &system, solution.displacement())?;
        Ok(SolidElasticSolve {
            errors: ContactErrors {
                e_grad: errors.relative_grad(),
                e_0: errors.relative_l2(),
                e_a: errors.relative_energy(),
                ..ContactErrors::default()
            },
            unknowns: body.dofs().n_unknowns(),
            assembly,
            solve,
        })
    }
}
