//! Convergence studies: one exact solution, one mesh family (and size factor) per body, a list
//! of sizes, a solver; per size the mesh size, the unknowns, every error measure, the contact
//! diagnostics and the time of each stage; rates fitted by least squares over the finest sizes
//! and a verdict against the expected rates (`docs/manufactured.md`, section 8).
//!
//! Each size's problem is a [`vem_scene::Scene`] built into a [`vem_scene::Model`]
//! ([`DiscreteProblem`]): [`Study::problem`] gives it, and its
//! [`scene`](DiscreteProblem::scene) shows what is solved (the study's element and law
//! registered under the names [`ELEMENT`](crate::problem::ELEMENT) and
//! [`LAW`](crate::problem::LAW)); the contact solver is the study's own.
//!
//! ```
//! use std::sync::Arc;
//! use vem_mesh::generators::MeshFamily;
//! use vem_verify::exact::{case_by_name, Lame};
//! use vem_verify::study::{MeshPairing, Study};
//! // Elasticity E1 on structured quads, n = 4, 8, 16: O(h) in energy, O(h^2) in L2.
//! let e1: Arc<_> = case_by_name("E1", Lame::default())?.into();
//! let result = Study::new(e1, MeshPairing::single(MeshFamily::Quads))
//!     .sizes([4, 8, 16])
//!     .run()?;
//! assert_eq!(result.records.len(), 3);
//! assert!(result.rates.grad.unwrap() > 0.9 && result.rates.l2.unwrap() > 1.8);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::fmt;
use std::str::FromStr;
use std::sync::Arc;
use std::time::Instant;

use serde::{Deserialize, Serialize};
use vem_contact::{ContactLaw, SolverRegistry, WorkCounters};
use vem_mesh::generators::MeshFamily;
use vem_mesh::Mesh;
use vem_space::ElementSpace;
use vem_space::Options;

use crate::diagnostics::{contact_diagnostics, ContactDiagnostics};
use crate::exact::ExactSolution;
use crate::norms::ErrorNorms;
use crate::problem::{DiscreteProblem, ProblemSettings};
use crate::VerifyError;

/// How one body is meshed in a study: a family, and the factor by which its size parameter
/// exceeds the study's `n` (a factor 3 on body two with 1 on body one gives the non-matching
/// ratio 1:3).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyMeshing {
    /// The mesh family.
    pub family: MeshFamily,
    /// Size factor (>= 1): the body's mesh has size parameter `factor * n`.
    pub factor: usize,
}

/// The meshing of every body of a study.
///
/// Written and parsed as `family[*factor]` per body, bodies separated by `/`:
/// `"quads"`, `"quads/quads*3"`, `"voronoi/quads"`, `"perturbed:0.2/hexagons"`.
///
/// ```
/// use vem_mesh::generators::MeshFamily;
/// use vem_verify::study::MeshPairing;
/// let pairing: MeshPairing = "quads/quads*3".parse()?;
/// assert_eq!(pairing, MeshPairing::pair(MeshFamily::Quads, 1, MeshFamily::Quads, 3));
/// assert_eq!(pairing.to_string(), "quads/quads*3");
/// assert_eq!(pairing.describe(), "quads/quads (n/3n)");
/// # Ok::<(), vem_verify::VerifyError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct MeshPairing {
    bodies: Vec<BodyMeshing>,
}

impl MeshPairing {
    /// One body meshed by `family`.
    pub fn single(family: MeshFamily) -> Self {
        Self {
            bodies: vec![BodyMeshing { family, factor: 1 }],
        }
    }

    /// Two bodies: body one by `family_1` with size factor `factor_1`, body two likewise.
    pub fn pair(
        family_1: MeshFamily,
        factor_1: usize,
        family_2: MeshFamily,
        factor_2: usize,
    ) -> Self {
        Self {
            bodies: vec![
                BodyMeshing {
                    family: family_1,
                    factor: factor_1,
                },
                BodyMeshing {
                    family: family_2,
                    factor: factor_2,
                },
            ],
        }
    }

    /// The meshing of each body.
    pub fn bodies(&self) -> &[BodyMeshing] {
        &self.bodies
    }

    /// A readable label: the families separated by `/`, then the size ratio when the factors
    /// differ, e.g. `"quads/quads (n/3n)"`, `"voronoi/quads"`.
    pub fn describe(&self) -> String {
        let families: Vec<String> = self.bodies.iter().map(|b| b.family.to_string()).collect();
        let mut label = families.join("/");
        if self
            .bodies
            .iter()
            .any(|b| b.factor != self.bodies[0].factor)
        {
            let ratio: Vec<String> = self
                .bodies
                .iter()
                .map(|b| match b.factor {
                    1 => "n".to_string(),
                    k => format!("{k}n"),
                })
                .collect();
            label.push_str(&format!(" ({})", ratio.join("/")));
        }
        label
    }

    /// A file-name friendly form of [`describe`](Self::describe): `"quads-quads-1x3"`.
    pub fn slug(&self) -> String {
        let families: Vec<String> = self
            .bodies
            .iter()
            .map(|b| b.family.to_string().replace([':', '.'], ""))
            .collect();
        let mut slug = families.join("-");
        if self
            .bodies
            .iter()
            .any(|b| b.factor != self.bodies[0].factor)
        {
            let ratio: Vec<String> = self.bodies.iter().map(|b| b.factor.to_string()).collect();
            slug.push('-');
            slug.push_str(&ratio.join("x"));
        }
        slug
    }

    /// The meshes of `exact`'s bodies at size `n`: body `k` (0-based) gets the mesh of size
    /// `factor_k n` of its family on its domain, generated with seed `seed + 2 factor_k n + k`.
    ///
    /// # Errors
    /// A pairing with another number of bodies than `exact`, a mesh generator error.
    pub fn generate(
        &self,
        exact: &dyn ExactSolution,
        n: usize,
        seed: u64,
    ) -> Result<Vec<Mesh>, VerifyError> {
        let ids = exact.bodies();
        if ids.len() != self.bodies.len() {
            return Err(VerifyError::Case {
                case: exact.name().to_string(),
                reason: format!(
                    "{} bodies but the mesh pairing '{self}' describes {}",
                    ids.len(),
                    self.bodies.len()
                ),
            });
        }
        ids.iter()
            .zip(&self.bodies)
            .map(|(&id, meshing)| {
                let size = meshing.factor * n;
                let body_seed = seed
                    .wrapping_add(2 * size as u64)
                    .wrapping_add(id.index() as u64);
                meshing
                    .family
                    .generate(&exact.domain(id), size, body_seed)
                    .map_err(|source| VerifyError::Mesh {
                        case: exact.name().to_string(),
                        body: id.index() + 1,
                        family: meshing.family.to_string(),
                        n: size,
                        source: Box::new(source),
                    })
            })
            .collect()
    }
}

impl fmt::Display for MeshPairing {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (k, body) in self.bodies.iter().enumerate() {
            if k > 0 {
                f.write_str("/")?;
            }
            write!(f, "{}", body.family)?;
            if body.factor != 1 {
                write!(f, "*{}", body.factor)?;
            }
        }
        Ok(())
    }
}

impl FromStr for MeshPairing {
    type Err = VerifyError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let invalid = |reason: String| VerifyError::InvalidSetting {
            reason: format!("mesh pairing '{s}': {reason}"),
        };
        let bodies = s
            .split('/')
            .map(|body| {
                let (family, factor) = match body.split_once('*') {
                    Some((family, factor)) => {
                        let factor: usize = factor.trim().parse().map_err(|_| {
                            invalid(format!("size factor '{factor}' is not a positive integer"))
                        })?;
                        (family, factor)
                    }
                    None => (body, 1),
                };
                if factor == 0 {
                    return Err(invalid("a size factor must be at least 1".to_string()));
                }
                let family: MeshFamily = family
                    .parse()
                    .map_err(|e: vem_mesh::MeshError| invalid(e.to_string()))?;
                Ok(BodyMeshing { family, factor })
            })
            .collect::<Result<Vec<_>, _>>()?;
        if bodies.len() > 2 {
            return Err(invalid(format!("{} bodies; at most two", bodies.len())));
        }
        Ok(Self { bodies })
    }
}

/// What a study must show (for contact cases also: on the finest mesh no interface node
/// contradicts [`ExactContact::expected_sets`](crate::ExactContact::expected_sets)).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Expectation {
    /// Fitted rates at least these (Theorems 4.1/4.2 and the expected L2 rate).
    Rates {
        /// Least rate of `E_grad`.
        grad: f64,
        /// Least rate of `E_a`.
        energy: f64,
        /// Least rate of `E_0`.
        l2: f64,
    },
    /// A patch test: at every size the relative errors `E_grad / |u|_1`, `E_a / |u_I|_a`,
    /// `E_0 / ||u||_0` are at most `tolerance`.
    Exact {
        /// The largest relative error.
        tolerance: f64,
    },
    /// Contact cases: on the finest mesh the sums of the nodal contact and friction forces
    /// match the exact resultants (the case's
    /// [`reference_resultants`](crate::ExactContact::reference_resultants), or their
    /// quadrature when it gives none) within `tolerance` relative to the larger of the two
    /// exact resultants' magnitudes (a separated case with zero resultants: absolute).
    Resultants {
        /// The largest relative resultant error.
        tolerance: f64,
    },
}

impl Expectation {
    /// The verdict of `docs/manufactured.md`, section 8: `E_grad` and `E_a` rates >= 0.9, `E_0` rate
    /// >= 1.8.
    pub const OPTIMAL_RATES: Expectation = Expectation::Rates {
        grad: 0.9,
        energy: 0.9,
        l2: 1.8,
    };
}

/// Seconds spent in each stage of one size.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct StageTimes {
    /// Mesh generation.
    pub mesh: f64,
    /// Interface node insertion and assembly.
    pub assembly: f64,
    /// Linear or contact solve.
    pub solve: f64,
    /// Error measures and diagnostics.
    pub errors: f64,
}

impl StageTimes {
    /// The sum of the stages.
    pub fn total(&self) -> f64 {
        self.mesh + self.assembly + self.solve + self.errors
    }
}

/// What one size of a study measured.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SizeRecord {
    /// The size parameter of each body's mesh.
    pub n: Vec<usize>,
    /// The mesh size: the largest polygon diameter over all bodies.
    pub h: f64,
    /// Polygons over all bodies.
    pub polygons: usize,
    /// Vertices over all bodies (after interface node insertion).
    pub vertices: usize,
    /// Unknowns (free degrees of freedom over all bodies).
    pub dofs: usize,
    /// The error measures of all bodies combined.
    pub errors: ErrorNorms,
    /// The error measures of each body.
    pub body_errors: Vec<ErrorNorms>,
    /// Contact cases: the interface diagnostics.
    pub contact: Option<ContactDiagnostics>,
    /// Contact cases: iterations of the contact solver.
    pub solver_iterations: Option<usize>,
    /// Contact cases: the solver's largest penetration `max (B_N u - g)^+`.
    pub max_penetration: Option<f64>,
    /// Contact cases: vertices inserted to make the interface node-to-node.
    pub inserted_nodes: Option<usize>,
    /// Coulomb cases: Tresca solves of the fixed point after the initial frictionless one.
    #[serde(default)]
    pub fixed_point_steps: Option<usize>,
    /// Coulomb cases: the last relative change of the normal forces of the fixed point.
    #[serde(default)]
    pub fixed_point_change: Option<f64>,
    /// Coulomb cases: the tolerance the fixed point stopped at (the law's, or the solver's
    /// force accuracy when larger).
    #[serde(default)]
    pub fixed_point_tolerance: Option<f64>,
    /// What the build and solve computed (assemblies, symbolic analyses, numeric
    /// factorisations, triangular solves, and the library's stage times).
    #[serde(default)]
    pub work: WorkCounters,
    /// Time of each stage.
    pub times: StageTimes,
}

/// Rates fitted by least squares to `log error = rate log h + c` over the finest sizes.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Rates {
    /// Rate of `E_grad` (`None` when undefined: fewer than two sizes or a zero error).
    pub grad: Option<f64>,
    /// Rate of `E_a`.
    pub energy: Option<f64>,
    /// Rate of `E_0`.
    pub l2: Option<f64>,
    /// How many of the finest sizes were fitted.
    pub fitted: usize,
}

/// Whether a study showed what was expected.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Verdict {
    /// True when nothing falls short.
    pub passed: bool,
    /// What falls short, one line each.
    pub shortfalls: Vec<String>,
}

/// The result of a study.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StudyResult {
    /// The case's name.
    pub case: String,
    /// "frictionless", "tresca", "coulomb" or "elasticity".
    pub law: String,
    /// The meshing ([`MeshPairing`]'s `Display` form, e.g. "quads/quads*3").
    pub pairing: String,
    /// A readable form of the meshing ([`MeshPairing::describe`]).
    pub pairing_label: String,
    /// A file-name friendly form ([`MeshPairing::slug`]).
    pub slug: String,
    /// The contact solver's name in the solver registry ("exact", "penalty", "active-set", a
    /// user's own; unused by elasticity cases).
    pub solver: String,
    /// The element space's name.
    pub element: String,
    /// The Lamé parameters `(lambda, mu)`.
    pub lame: (f64, f64),
    /// The base seed of the random mesh families.
    pub seed: u64,
    /// One record per size, coarse to fine.
    pub records: Vec<SizeRecord>,
    /// The fitted rates.
    pub rates: Rates,
    /// What was expected (the first expectation of the study).
    pub expectation: Expectation,
    /// Further expectations judged with it ([`Study::also_expect`]).
    #[serde(default)]
    pub also_expected: Vec<Expectation>,
    /// The names of the criteria of one's own judged with it ([`Study::also_check`]).
    #[serde(default)]
    pub criteria: Vec<String>,
    /// Whether it was met.
    pub verdict: Verdict,
    /// Wall-clock seconds of the whole study.
    pub seconds: f64,
}

impl StudyResult {
    /// A title such as "M1 (frictionless) on quads/quads (n/3n)".
    pub fn title(&self) -> String {
        format!("{} ({}) on {}", self.case, self.law, self.pairing_label)
    }

    /// The record of the finest size.
    pub fn finest(&self) -> Option<&SizeRecord> {
        self.records.last()
    }
}

/// The least-squares slope of `log e` against `log h`: the observed convergence rate. `None`
/// for fewer than two points, a non-positive or non-finite value, or equal mesh sizes.
///
/// ```
/// use vem_verify::study::fitted_rate;
/// let h = [0.5, 0.25, 0.125];
/// let e: Vec<f64> = h.iter().map(|h: &f64| 3.0 * h.powi(2)).collect();
/// assert!((fitted_rate(&h, &e).unwrap() - 2.0).abs() < 1e-12);
/// assert_eq!(fitted_rate(&h, &[1.0, 0.0, 1.0]), None);
/// ```
pub fn fitted_rate(h: &[f64], e: &[f64]) -> Option<f64> {
    if h.len() != e.len() || h.len() < 2 {
        return None;
    }
    let valid = |v: &f64| v.is_finite() && *v > 0.0;
    if !(h.iter().all(valid) && e.iter().all(valid)) {
        return None;
    }
    let x: Vec<f64> = h.iter().map(|v| v.ln()).collect();
    let y: Vec<f64> = e.iter().map(|v| v.ln()).collect();
    let m = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / m, y.iter().sum::<f64>() / m);
    let sxx: f64 = x.iter().map(|x| (x - mx).powi(2)).sum();
    let sxy: f64 = x.iter().zip(&y).map(|(x, y)| (x - mx) * (y - my)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

/// The rate between each pair of successive sizes (`None` before the first, or where
/// undefined).
pub fn successive_rates(h: &[f64], e: &[f64]) -> Vec<Option<f64>> {
    (0..h.len().min(e.len()))
        .map(|k| {
            if k == 0 {
                None
            } else {
                fitted_rate(&h[k - 1..=k], &e[k - 1..=k])
            }
        })
        .collect()
}

/// A convergence study of one exact solution on one mesh pairing (see the module docs).
#[derive(Clone)]
pub struct Study {
    exact: Arc<dyn ExactSolution>,
    pairing: MeshPairing,
    sizes: Vec<usize>,
    solver: String,
    registry: SolverRegistry,
    options: Options,
    settings: ProblemSettings,
    seed: u64,
    fitted: usize,
    expectation: Expectation,
    also_expected: Vec<Expectation>,
    criteria: Vec<Criterion>,
}

/// A criterion of one's own that a study must meet, besides its [`Expectation`]s: a name and
/// a check of the measured records and fitted rates that returns what falls short (nothing
/// when met). For example "the resultant errors below h^2 at every size".
///
/// ```
/// use vem_verify::study::Criterion;
/// let below_h2 = Criterion::new("resultant error <= h^2", |records, _rates| {
///     records
///         .iter()
///         .filter_map(|r| {
///             let c = r.contact.as_ref()?;
///             (c.normal_resultant_error > r.h * r.h).then(|| {
///                 format!("n = {:?}: error {:.2e} > h^2 = {:.2e}", r.n, c.normal_resultant_error, r.h * r.h)
///             })
///         })
///         .collect()
/// });
/// assert_eq!(below_h2.name(), "resultant error <= h^2");
/// assert!(below_h2.check(&[], &vem_verify::study::fit_rates(&[], 3)).is_empty());
/// ```
#[derive(Clone)]
pub struct Criterion {
    name: String,
    check: CriterionCheck,
}

/// The check of a [`Criterion`]: the shortfalls of the records and rates.
pub type CriterionCheck = Arc<dyn Fn(&[SizeRecord], &Rates) -> Vec<String> + Send + Sync>;

impl Criterion {
    /// The criterion `name` checked by `check`.
    pub fn new(
        name: impl Into<String>,
        check: impl Fn(&[SizeRecord], &Rates) -> Vec<String> + Send + Sync + 'static,
    ) -> Self {
        Self {
            name: name.into(),
            check: Arc::new(check),
        }
    }

    /// Its name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// What falls short of it.
    pub fn check(&self, records: &[SizeRecord], rates: &Rates) -> Vec<String> {
        (self.check)(records, rates)
    }
}

impl fmt::Debug for Criterion {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Criterion")
            .field("name", &self.name)
            .finish()
    }
}

impl fmt::Debug for Study {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Study")
            .field("case", &self.exact.name())
            .field("pairing", &self.pairing.to_string())
            .field("sizes", &self.sizes)
            .field("solver", &self.solver)
            .field("options", &self.options)
            .field("settings", &self.settings)
            .field("seed", &self.seed)
            .field("fitted", &self.fitted)
            .field("expectation", &self.expectation)
            .field("also_expected", &self.also_expected)
            .field("criteria", &self.criteria)
            .finish()
    }
}

impl Study {
    /// Default sizes: n = 4, 8, 16, 32.
    pub const DEFAULT_SIZES: [usize; 4] = [4, 8, 16, 32];
    /// Default number of finest sizes the rates are fitted over.
    pub const DEFAULT_FITTED: usize = 3;
    /// Default base seed of the random mesh families.
    pub const DEFAULT_SEED: u64 = 2016;

    /// A study of `exact` meshed by `pairing`, with the default sizes, the default contact
    /// solver of the built-in registry ([`SolverRegistry::DEFAULT`]) with default options, the
    /// default problem settings, rates fitted over the last three sizes and
    /// [`Expectation::OPTIMAL_RATES`].
    pub fn new(exact: Arc<dyn ExactSolution>, pairing: MeshPairing) -> Self {
        Self {
            exact,
            pairing,
            sizes: Self::DEFAULT_SIZES.to_vec(),
            solver: SolverRegistry::DEFAULT.to_string(),
            registry: SolverRegistry::builtin(),
            options: Options::new(),
            settings: ProblemSettings::default(),
            seed: Self::DEFAULT_SEED,
            fitted: Self::DEFAULT_FITTED,
            expectation: Expectation::OPTIMAL_RATES,
            also_expected: Vec::new(),
            criteria: Vec::new(),
        }
    }

    /// The sizes `n`, coarse to fine.
    pub fn sizes(mut self, sizes: impl Into<Vec<usize>>) -> Self {
        self.sizes = sizes.into();
        self
    }

    /// The contact solver: a name of the study's solver registry (the built-in one unless
    /// [`registry`](Self::registry) gives another): "exact", "penalty", "active-set" or a
    /// user's own. An unknown name is refused by [`validate`](Self::validate).
    pub fn solver(mut self, name: impl Into<String>) -> Self {
        self.solver = name.into();
        self
    }

    /// The registry the solver name is looked up in: a user's registry with solvers of their
    /// own (see `SolverRegistry::register`).
    pub fn registry(mut self, registry: SolverRegistry) -> Self {
        self.registry = registry;
        self
    }

    /// The options every solver of the study is made with (tolerance, iterations, penalty).
    pub fn solver_options(mut self, options: Options) -> Self {
        self.options = options;
        self
    }

    /// A contact law in place of the case's own (e.g. a law of one's own, or Tresca with a
    /// bound the case's Coulomb answer must reproduce); its name is reported in
    /// [`StudyResult::law`].
    pub fn law(mut self, law: Arc<dyn ContactLaw>) -> Self {
        self.settings = self.settings.clone().with_law(law);
        self
    }

    /// A criterion of one's own, judged with the expectations ([`Criterion`]); its
    /// shortfalls enter the verdict prefixed with its name.
    pub fn also_check(mut self, criterion: Criterion) -> Self {
        self.criteria.push(criterion);
        self
    }

    /// The element space and traction quadrature.
    pub fn settings(mut self, settings: ProblemSettings) -> Self {
        self.settings = settings;
        self
    }

    /// The element space of every body: a built-in one (`vem_space::LowestOrderVem`,
    /// `vem_space::LinearTriangle`) or a user's own [`ElementSpace`]. Its
    /// [`name`](ElementSpace::name) is reported in [`StudyResult::element`].
    pub fn element(mut self, element: Arc<dyn ElementSpace>) -> Self {
        self.settings = self.settings.clone().with_element(element);
        self
    }

    /// The base seed of the random mesh families.
    pub fn seed(mut self, seed: u64) -> Self {
        self.seed = seed;
        self
    }

    /// Fit the rates over the `fitted` finest sizes (at least two).
    pub fn fitted(mut self, fitted: usize) -> Self {
        self.fitted = fitted;
        self
    }

    /// What the study must show.
    pub fn expect(mut self, expectation: Expectation) -> Self {
        self.expectation = expectation;
        self
    }

    /// A further expectation judged together with the one of [`expect`](Self::expect), e.g.
    /// [`Expectation::Resultants`] besides the rates.
    pub fn also_expect(mut self, expectation: Expectation) -> Self {
        self.also_expected.push(expectation);
        self
    }

    /// The exact solution.
    pub fn exact(&self) -> &Arc<dyn ExactSolution> {
        &self.exact
    }

    /// The mesh pairing.
    pub fn pairing(&self) -> &MeshPairing {
        &self.pairing
    }

    /// The sizes.
    pub fn size_list(&self) -> &[usize] {
        &self.sizes
    }

    /// A title such as "M1 (frictionless) on quads/quads (n/3n)".
    pub fn title(&self) -> String {
        format!(
            "{} ({}) on {}",
            self.exact.name(),
            self.law_name(),
            self.pairing.describe()
        )
    }

    fn law_name(&self) -> String {
        match (self.exact.contact(), self.settings.law()) {
            (None, _) => "elasticity".to_string(),
            (Some(_), Some(law)) => law.name().to_string(),
            (Some(c), None) => c.law().name().to_string(),
        }
    }

    /// Checks the settings: at least one size, sizes positive and increasing, at least two
    /// fitted sizes, as many meshings as bodies, positive size factors, a contact solver the
    /// registry makes with the options.
    ///
    /// # Errors
    /// [`VerifyError::InvalidSetting`] or [`VerifyError::Case`] naming the first problem.
    pub fn validate(&self) -> Result<(), VerifyError> {
        let invalid = |reason: String| {
            Err(VerifyError::InvalidSetting {
                reason: format!("study of {}: {reason}", self.exact.name()),
            })
        };
        if self.sizes.is_empty() {
            return invalid("no sizes".to_string());
        }
        if self.sizes[0] == 0 || self.sizes.windows(2).any(|w| w[1] <= w[0]) {
            return invalid(format!(
                "sizes {:?} must be positive and increasing",
                self.sizes
            ));
        }
        if self.fitted < 2 {
            return invalid(format!(
                "rates need at least 2 fitted sizes, got {}",
                self.fitted
            ));
        }
        if self.pairing.bodies.iter().any(|b| b.factor == 0) {
            return invalid(format!("pairing '{}' has a zero size factor", self.pairing));
        }
        self.registry
            .make(&self.solver, &self.options)
            .map_err(|source| VerifyError::Solver {
                case: self.exact.name().to_string(),
                name: self.solver.clone(),
                source: Box::new(source),
            })?;
        if self.pairing.bodies.len() != self.exact.bodies().len() {
            return Err(VerifyError::Case {
                case: self.exact.name().to_string(),
                reason: format!(
                    "{} bodies but the mesh pairing '{}' describes {}",
                    self.exact.bodies().len(),
                    self.pairing,
                    self.pairing.bodies.len()
                ),
            });
        }
        Ok(())
    }

    /// The discrete problem of size `n`: the meshes of the pairing and the problem's scene
    /// ([`DiscreteProblem::scene`]) built with the study's element and law, as
    /// [`run_size`](Self::run_size) solves it.
    ///
    /// ```
    /// use std::sync::Arc;
    /// use vem_mesh::generators::MeshFamily;
    /// use vem_verify::exact::{case_by_name, Lame};
    /// use vem_verify::study::{MeshPairing, Study};
    /// let m1: Arc<_> = case_by_name("M1", Lame::default())?.into();
    /// let study = Study::new(m1, "quads/quads*2".parse::<MeshPairing>()?);
    /// let scene = study.problem(4)?.scene().clone();
    /// assert_eq!(scene.bodies.len(), 2);
    /// assert_eq!(scene.contacts[0].other_part.as_deref(), Some("top"));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    ///
    /// # Errors
    /// Mesh generation failures, as [`DiscreteProblem::try_new`].
    pub fn problem(&self, n: usize) -> Result<DiscreteProblem, VerifyError> {
        let meshes = self.pairing.generate(&*self.exact, n, self.seed)?;
        DiscreteProblem::try_new(Arc::clone(&self.exact), meshes, &self.settings)
    }

    /// Measures one size `n`.
    ///
    /// # Errors
    /// Mesh generation, assembly, solve or measurement failures.
    pub fn run_size(&self, n: usize) -> Result<SizeRecord, VerifyError> {
        let exact = &*self.exact;
        let start = Instant::now();
        let meshes = self.pairing.generate(exact, n, self.seed)?;
        let mesh_time = start.elapsed().as_secs_f64();
        let problem = DiscreteProblem::try_new(Arc::clone(&self.exact), meshes, &self.settings)?;
        let h = problem.mesh_size();
        let mut solver = self
            .registry
            .make(&self.solver, &self.options)
            .map_err(|source| VerifyError::Solver {
                case: exact.name().to_string(),
                name: self.solver.clone(),
                source: Box::new(source),
            })?;
        let solution = problem.solve(&mut *solver)?;
        let start = Instant::now();
        let body_errors = solution.errors(exact)?;
        let contact = match (exact.contact(), &solution.interface) {
            (Some(contact), Some(interface)) => {
                Some(contact_diagnostics(contact, &interface.nodes))
            }
            _ => None,
        };
        let errors_time = start.elapsed().as_secs_f64();
        let interface = solution.interface.as_ref();
        Ok(SizeRecord {
            n: self.pairing.bodies.iter().map(|b| b.factor * n).collect(),
            h,
            polygons: solution
                .bodies
                .iter()
                .map(|b| b.body.mesh().n_polygons())
                .sum(),
            vertices: solution
                .bodies
                .iter()
                .map(|b| b.body.mesh().n_vertices())
                .sum(),
            dofs: solution
                .bodies
                .iter()
                .map(|b| b.system.dofs().n_free())
                .sum(),
            errors: ErrorNorms::combine(&body_errors),
            body_errors,
            contact,
            solver_iterations: interface.map(|i| i.report.iterations),
            // The report's residual is relative to the displacement scale: back to a length.
            max_penetration: interface.map(|i| {
                let r = &i.report.residuals;
                r.max_penetration * r.scales.displacement
            }),
            inserted_nodes: interface.map(|i| i.inserted_nodes),
            fixed_point_steps: interface.and_then(|i| i.fixed_point.as_ref().map(|f| f.steps)),
            work: solution.work,
            fixed_point_change: interface.and_then(|i| i.fixed_point.as_ref().map(|f| f.residual)),
            fixed_point_tolerance: interface
                .and_then(|i| i.fixed_point.as_ref().map(|f| f.tolerance)),
            times: StageTimes {
                mesh: mesh_time,
                assembly: solution.assembly_time.as_secs_f64(),
                solve: solution.solve_time.as_secs_f64(),
                errors: errors_time,
            },
        })
    }

    /// Runs every size.
    ///
    /// # Errors
    /// Invalid settings, or the first failure of [`run_size`](Self::run_size).
    pub fn run(&self) -> Result<StudyResult, VerifyError> {
        self.run_with(|_| {})
    }

    /// Runs every size, calling `progress` with each record as soon as it is measured.
    ///
    /// # Errors
    /// Invalid settings, or the first failure of [`run_size`](Self::run_size).
    pub fn run_with(
        &self,
        mut progress: impl FnMut(&SizeRecord),
    ) -> Result<StudyResult, VerifyError> {
        self.validate()?;
        let start = Instant::now();
        let mut records = Vec::with_capacity(self.sizes.len());
        for &n in &self.sizes {
            let record = self.run_size(n)?;
            progress(&record);
            records.push(record);
        }
        let rates = fit_rates(&records, self.fitted);
        let mut expectations = vec![self.expectation];
        expectations.extend_from_slice(&self.also_expected);
        let mut verdict = judge(&expectations, &records, &rates);
        for criterion in &self.criteria {
            let shortfalls = criterion.check(&records, &rates);
            verdict.passed &= shortfalls.is_empty();
            verdict.shortfalls.extend(
                shortfalls
                    .into_iter()
                    .map(|s| format!("{}: {s}", criterion.name())),
            );
        }
        let lame = self.exact.lame();
        Ok(StudyResult {
            case: self.exact.name().to_string(),
            law: self.law_name(),
            pairing: self.pairing.to_string(),
            pairing_label: self.pairing.describe(),
            slug: self.pairing.slug(),
            solver: self.solver.clone(),
            element: self.settings.element().name().to_string(),
            lame: (lame.lambda(), lame.mu()),
            seed: self.seed,
            records,
            rates,
            expectation: self.expectation,
            also_expected: self.also_expected.clone(),
            criteria: self.criteria.iter().map(|c| c.name().to_string()).collect(),
            verdict,
            seconds: start.elapsed().as_secs_f64(),
        })
    }
}

/// Rates over the `fitted` finest records (all of them if fewer), by [`fitted_rate`].
///
/// ```
/// use vem_verify::study::{fit_rates, SizeRecord};
/// # fn record(h: f64, e: f64) -> SizeRecord {
/// #     let mut errors = vem_verify::norms::ErrorNorms::default();
/// #     (errors.grad, errors.energy, errors.l2) = (e, e, e * h);
/// #     SizeRecord { n: vec![1], h, polygons: 0, vertices: 0, dofs: 0, errors,
/// #         body_errors: vec![], contact: None, solver_iterations: None,
/// #         max_penetration: None, inserted_nodes: None, fixed_point_steps: None,
/// #         work: Default::default(),
/// #         fixed_point_change: None, fixed_point_tolerance: None, times: Default::default() }
/// # }
/// // E_grad = E_a = h, E_0 = h^2 on the three finest of four sizes.
/// let records: Vec<SizeRecord> = [0.8, 0.4, 0.2, 0.1].iter().map(|&h| record(h, h)).collect();
/// let rates = fit_rates(&records, 3);
/// assert_eq!(rates.fitted, 3);
/// assert!((rates.grad.unwrap() - 1.0).abs() < 1e-12 && (rates.l2.unwrap() - 2.0).abs() < 1e-12);
/// ```
pub fn fit_rates(records: &[SizeRecord], fitted: usize) -> Rates {
    let first = records.len().saturating_sub(fitted);
    let tail = &records[first..];
    let h: Vec<f64> = tail.iter().map(|r| r.h).collect();
    let rate = |f: fn(&ErrorNorms) -> f64| {
        let e: Vec<f64> = tail.iter().map(|r| f(&r.errors)).collect();
        fitted_rate(&h, &e)
    };
    Rates {
        grad: rate(|e| e.grad),
        energy: rate(|e| e.energy),
        l2: rate(|e| e.l2),
        fitted: tail.len(),
    }
}

/// The verdict of `records` with fitted `rates` against every expectation of `expectations`,
/// plus, for contact cases, no interface node contradicting the expected sets on the finest
/// mesh. [`Study::run`] calls it; call it yourself to judge records of your own runner.
pub fn judge(expectations: &[Expectation], records: &[SizeRecord], rates: &Rates) -> Verdict {
    let mut shortfalls = Vec::new();
    for expectation in expectations {
        judge_one(expectation, records, rates, &mut shortfalls);
    }
    // The statuses away from the switch points must be right on the finest mesh (they held
    // from n = 32 on in the prototype of docs/manufactured.md, section 8).
    if let Some(finest) = records.last() {
        if let Some(violation) = finest.contact.iter().flat_map(|c| &c.set_violations).next() {
            let count = finest
                .contact
                .as_ref()
                .map_or(0, |c| c.set_violations.len());
            shortfalls.push(format!(
                "n = {:?}: {count} interface node(s) contradict the expected sets, first at \
                 x = {:.4} (expected {}, found {})",
                finest.n, violation.x, violation.expected, violation.found
            ));
        }
    }
    Verdict {
        passed: shortfalls.is_empty(),
        shortfalls,
    }
}

/// The shortfalls of `records` and `rates` against one expectation.
fn judge_one(
    expectation: &Expectation,
    records: &[SizeRecord],
    rates: &Rates,
    shortfalls: &mut Vec<String>,
) {
    match *expectation {
        Expectation::Rates { grad, energy, l2 } => {
            for (name, rate, least) in [
                ("E_grad", rates.grad, grad),
                ("E_a", rates.energy, energy),
                ("E_0", rates.l2, l2),
            ] {
                match rate {
                    Some(r) if r >= least => {}
                    Some(r) => shortfalls.push(format!("{name} rate {r:.3} < {least}")),
                    None => shortfalls.push(format!("{name} rate undefined")),
                }
            }
        }
        Expectation::Exact { tolerance } => {
            for record in records {
                let e = &record.errors;
                for (name, value) in [
                    ("E_grad/|u|_1", e.relative_grad()),
                    ("E_a/|u_I|_a", e.relative_energy()),
                    ("E_0/||u||_0", e.relative_l2()),
                ] {
                    if value.is_nan() || value > tolerance {
                        shortfalls.push(format!(
                            "n = {:?}: {name} = {value:.3e} > {tolerance:e}",
                            record.n
                        ));
                    }
                }
            }
        }
        Expectation::Resultants { tolerance } => {
            let Some(finest) = records.last() else {
                return;
            };
            let Some(c) = finest.contact.as_ref() else {
                shortfalls.push(format!(
                    "n = {:?}: resultants expected but the case has no contact interface",
                    finest.n
                ));
                return;
            };
            let scale = c
                .normal_resultant_exact
                .abs()
                .max(c.tangential_resultant_exact.abs());
            let scale = if scale > 0.0 { scale } else { 1.0 };
            for (name, error) in [
                ("normal resultant", c.normal_resultant_error),
                ("tangential resultant", c.tangential_resultant_error),
            ] {
                let relative = error / scale;
                if relative.is_nan() || relative > tolerance {
                    shortfalls.push(format!(
                        "n = {:?}: {name} error {relative:.3e} (relative) > {tolerance:e}",
                        finest.n
                    ));
                }
            }
        }
    }
}

/// The bodies of `exact` with the size factor 1, each meshed by `family` (a convenience for
/// one-family studies of one- or two-body cases).
pub fn same_family(exact: &dyn ExactSolution, family: MeshFamily) -> MeshPairing {
    MeshPairing {
        bodies: exact
            .bodies()
            .iter()
            .map(|_| BodyMeshing { family, factor: 1 })
            .collect(),
    }
}
