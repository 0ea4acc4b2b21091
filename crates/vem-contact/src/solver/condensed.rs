//! The condensed solver: contact at the cost of one factorisation of the stiffness.
//!
//! Every contact row touches only the **interface unknowns** `G` of each body (the unknowns of
//! the nodes that carry a normal or tangential row); call the others `I`. Each body's stiffness
//! is factorised once with its interface unknowns eliminated last
//! ([`LinearSolver::analyse_with_trailing`](vem_elastic::LinearSolver::analyse_with_trailing)), so that the trailing block of the factor is the
//! Cholesky factor `L_GG` of the interface Schur complement `S = K_GG - K_GI K_II^-1 K_IG`, and
//! `(K^-1)_GG = S^-1`. With `B = [B_N; B_T]` and `u0 = K^-1 f`, the displacement for given
//! multipliers is `u = u0 - K^-1 B' lambda`, and the contact problem becomes its dual, a small
//! dense **bound-constrained** QP in the multipliers:
//!
//! ```text
//! minimise 1/2 lambda' H lambda - d' lambda,   H = B S^-1 B' = W'W,  W = L_GG^-1 B_G',
//!                                               d = B u0 - [g; s],
//! subject to  lambda_N >= 0,  -b <= lambda_T <= b   (in space: |lambda_T,i| <= b_i),
//! ```
//!
//! with `s` the reference slip of the friction term (zero from rest; the tangential jump of the
//! previous load step in a load history).
//!
//! Tresca friction is a box constraint in the dual of a planar problem, and a disk of the
//! node's two tangential rows in space; a Coulomb fixed point changes only the box (the
//! radii), and a load step only `d`. The QP is solved by projected Newton steps with an Armijo
//! search (globally convergent; it cannot cycle, unlike a plain primal-dual active set; in
//! space the Newton step of a node sliding on its disk's rim is taken along the rim, with the
//! rim's curvature, see `disk_qp`), then
//! `u` follows from one more solve. Per structure (the [`PatternId`] and the stiffness values)
//! the solver keeps the factorisations and `H`; per solve it does dense interface work and
//! one triangular solve pair per body for `u`, and one more for `u0` only when the load
//! leaves the span of the loads solved before (the same load again: a Coulomb step; a
//! combination of earlier loads: the steps of a load history, whose loads are combinations of
//! a few per-condition loads). The multipliers of the last solve start the next one.
//! [`ContactSolver::solve_forces`] stops before the back substitution: the steps of a Coulomb
//! fixed point cost interface work only.
//!
//! **The iterative interface** ([`InterfaceMethod`]): for large interfaces the dense work
//! (`|G|^3 / 3` for the trailing block, `W`, `H`) loses against an iteration on the operator
//! `lambda -> B K^-1 B' lambda`: each body is factorised in its best order (no trailing block)
//! and the QP is solved by MPGP (`mprgp`; with friction in space by projected Newton steps
//! along the rims whose Newton systems are solved by conjugate gradients, `mprgp`,
//! preconditioned by the Ritz pairs of the products kept per structure, `kept_products`), one
//! pair of triangular solves per body and product, warm-started like the dense QP;
//! `B u = [g; s] + d - H lambda` comes from the last product. It is chosen by size
//! ([`ITERATIVE_FROM`] interface unknowns without friction, [`ITERATIVE_WITH_FRICTION_FROM`]
//! with friction in space, [`ITERATIVE_WITH_FRICTION_IN_THE_PLANE_FROM`] in the plane) or
//! forced by the settings; a singular body makes the solver take the dense interface.
//! Where few nodes carry a force (a Hertz-like zone on a large face, the later steps of a
//! Coulomb fixed point) the iterative interface solves first on its **candidate nodes**
//! (`candidates`): the dense QP on their rows with `H_CC = B_C K^-1 B_C'` from one block solve
//! per body (kept per structure), checked on the whole interface with one product; nodes that
//! fail the check join the candidates, and too many of them hand the problem to the iteration.
//!
//! **A body held only by contact or friction** has a singular stiffness (a rigid motion in
//! the kernel) and no Cholesky factor. Its interface unknowns are then shifted: the body is
//! factorised as `K_s = K + s E_G` (`E_G` the identity on its interface unknowns, `s` a small
//! multiple of their largest stiffness), which changes only the trailing block (`M = S + s I`)
//! because those unknowns are eliminated last. The exact problem is recovered by proximal point
//! steps on the interface,
//!
//! ```text
//! v_k+1 = argmin 1/2 v'Sv - f~'v + s/2 |v - v_k|^2 (+ friction)  s.t.  B v <= g,
//! ```
//!
//! each the same box QP with `H = B M^-1 B'` and a new `d`; they converge to a minimiser when
//! the contact or friction holds the body, and otherwise move along the free mode by a
//! constant step, which is reported as [`ContactSolverError::RigidSliding`] or
//! [`ContactSolverError::Unbounded`]. The answer is `u = K_s^-1 (f - B' lambda + s E_G v)`.
//! A body that stays singular with the shift (a part not connected to the interface), or
//! proximal steps that converge too slowly, are handed to the [`ActiveSetSolver`]; the report
//! (and the error) of such a solve names the condensed solver and the handover.

use std::time::Instant;
use vem_space::{Options, OptionsError};

use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::{Accum, Mat, MatMut, MatRef, Par};
use rayon::prelude::*;
use std::sync::Arc;

use vem_elastic::{
    CholeskyAnalysis, CholeskySettings, CholeskySolver, LinearSolver, SolveError, SolveSupport,
};

use super::active_set::ActiveSetSolver;
use super::box_qp::{BoxQp, BoxQpOutcome, ReducedFactor};
use super::disk_qp::{Disk, DiskQp};
use super::error::{ContactSolverError, SettingsError};
use super::kept_products::KeptProducts;
use super::mprgp::{self, Mprgp};
use super::report::{
    certify, inf_norm as inf, unloaded, unloaded_solution, KktResiduals, SolveReport, SolveStatus,
    WorkCounters,
};
use super::shared::{self, BlockFactor, BlockKey, BlockOrder, FactorKey};
use super::system::{matrix_entry, ContactSystem, PatternId};
use super::{ContactForces, ContactSolution, ContactSolver};

mod candidates;
use candidates::{solve_on_candidates, CandidateHessian, CandidateOutcome};

const NAME: &str = "condensed (interface Schur complement)";
/// The name in the reports of the solves on the iterative interface.
const ITERATIVE_NAME: &str = "condensed (iterative interface, MPGP)";
/// The name in the reports of the solves of the iterative interface on its candidate nodes
/// (`candidates`).
const CANDIDATES_NAME: &str = "condensed (iterative interface, dense on the candidate nodes)";
/// The name in the reports of the solves the condensed solver hands over to the active-set
/// solver: the solver the user chose, and who solved.
const HANDED_OVER: &str =
    "condensed (interface Schur complement), handed over to the active set (primal-dual)";

/// Settings of [`CondensedSolver`]; build them with [`CondensedSettings::builder`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CondensedSettings {
    tolerance: f64,
    max_iterations: usize,
    cholesky: CholeskySettings,
    interface: InterfaceMethod,
}

/// How the condensed solver solves its interface problem (the dual QP in the multipliers).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum InterfaceMethod {
    /// The dense interface Schur complement: each body factorised with its interface unknowns
    /// eliminated last, `H = W'W` formed, the QP solved by projected Newton steps. Exact
    /// in a few steps; its cost grows like the cube of the interface unknowns.
    Dense,
    /// The dual iteration on the Schur operator: each body factorised in its best ordering,
    /// `lambda -> B K^-1 B' lambda` applied with one pair of triangular solves per body per
    /// product, the QP solved by MPGP (MPRGP on sign bounds and boxes) or, with disks
    /// (friction in space), by projected Newton steps whose Newton systems are solved by
    /// conjugate gradients on the products. Its cost grows with the products times the cost
    /// of a solve.
    Iterative,
    /// [`InterfaceMethod::Iterative`] from [`ITERATIVE_FROM`] interface unknowns (summed
    /// over the bodies) for frictionless problems, from [`ITERATIVE_WITH_FRICTION_FROM`] with
    /// friction in space and from [`ITERATIVE_WITH_FRICTION_IN_THE_PLANE_FROM`] with friction
    /// in the plane, [`InterfaceMethod::Dense`] below (measured in docs/contact-3d.md, section
    /// 7). The default.
    #[default]
    Auto,
}

/// The number of interface unknowns (summed over the bodies) from which
/// [`InterfaceMethod::Auto`] chooses the iterative interface for frictionless problems (see
/// docs/contact-3d.md, section 7, for the measurements behind it).
pub const ITERATIVE_FROM: usize = 4000;

/// The number of interface unknowns from which [`InterfaceMethod::Auto`] chooses the
/// iterative interface for problems with friction in space (disks: projected Newton steps).
/// Measured on a block pressed on a plane (docs/contact-3d.md, section 7): at 5 043 interface
/// unknowns the iterative interface costs 4.24 elastic solves for Tresca against 5.28 dense,
/// 9.24 for Coulomb against 8.66; at 9 747 Tresca 3.37 against 8.34, and the dense time grows
/// like `m^2.5` (its `H` and trailing block take `16 m^2` bytes).
pub const ITERATIVE_WITH_FRICTION_FROM: usize = 5_000;

/// The number of interface unknowns from which [`InterfaceMethod::Auto`] chooses the
/// iterative interface for problems with friction in the plane (boxes: MPGP). Not measured at
/// such sizes; kept above the interfaces of the plane's benchmarks (about 5 700 interface
/// unknowns at 8·10^6 unknowns), whose dense interface is cheap against the factorisation.
pub const ITERATIVE_WITH_FRICTION_IN_THE_PLANE_FROM: usize = 20_000;

/// The loosest tolerance of the interface problem that [`ContactSolver::solve_forces`]
/// accepts from a caller's `accuracy`.
const LOOSEST_TOLERANCE: f64 = 1e-3;

impl Default for CondensedSettings {
    /// Relative tolerance `1e-12` on the projected gradient of the interface problem, at most
    /// 200 projected Newton steps, the default sparse Cholesky settings.
    fn default() -> Self {
        Self {
            tolerance: 1e-12,
            max_iterations: 200,
            cholesky: CholeskySettings::default(),
            interface: InterfaceMethod::Auto,
        }
    }
}

impl CondensedSettings {
    /// A builder starting from the defaults.
    pub fn builder() -> CondensedSettingsBuilder {
        CondensedSettingsBuilder {
            settings: Self::default(),
        }
    }

    /// Tolerance on the projected gradient of the interface problem, a force, relative to
    /// `max_i |clamp(d_i / H_ii)|` (the force that would close the largest unconstrained
    /// penetration, or stop the largest slip, alone, within its bounds).
    pub fn tolerance(&self) -> f64 {
        self.tolerance
    }

    /// The acceptance test of an answer: every relative KKT residual
    /// ([`KktResiduals`](super::KktResiduals)) below `max(100 tolerance, 1e-9)`.
    pub fn acceptance(&self) -> f64 {
        (100.0 * self.tolerance).max(1e-9)
    }

    /// Limit on the projected Newton steps (the iterative interface allows
    /// [`ITERATIONS_PER_STEP`] times as many MPGP iterations, or as many operator products in
    /// its Newton steps with friction in space).
    pub fn max_iterations(&self) -> usize {
        self.max_iterations
    }

    /// How the interface problem is solved.
    pub fn interface(&self) -> InterfaceMethod {
        self.interface
    }

    /// Settings of the sparse Cholesky factorisation of each body.
    pub fn cholesky(&self) -> &CholeskySettings {
        &self.cholesky
    }
}

/// Builder of [`CondensedSettings`]; values are checked by
/// [`CondensedSettingsBuilder::build`].
#[derive(Debug, Clone, Copy)]
pub struct CondensedSettingsBuilder {
    settings: CondensedSettings,
}

impl CondensedSettingsBuilder {
    /// Relative tolerance, finite and `> 0`.
    pub fn tolerance(mut self, value: f64) -> Self {
        self.settings.tolerance = value;
        self
    }

    /// Limit on the projected Newton steps, `>= 1`.
    pub fn max_iterations(mut self, value: usize) -> Self {
        self.settings.max_iterations = value;
        self
    }

    /// Settings of the sparse Cholesky factorisations.
    pub fn cholesky(mut self, value: CholeskySettings) -> Self {
        self.settings.cholesky = value;
        self
    }

    /// How the interface problem is solved (default [`InterfaceMethod::Auto`]).
    pub fn interface(mut self, value: InterfaceMethod) -> Self {
        self.settings.interface = value;
        self
    }

    /// Validates the settings.
    ///
    /// # Errors
    /// [`SettingsError`] naming the first invalid setting.
    pub fn build(self) -> Result<CondensedSettings, SettingsError> {
        let s = self.settings;
        SettingsError::positive("tolerance", s.tolerance)?;
        SettingsError::at_least_one("max_iterations", s.max_iterations)?;
        Ok(s)
    }
}

/// The settings a scene or a dict may give the condensed solver (registry name `"condensed"`).
#[derive(Debug, Default, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct CondensedOptions {
    tolerance: Option<f64>,
    max_iterations: Option<usize>,
    interface: Option<InterfaceMethod>,
}

impl CondensedSettings {
    /// The settings of a table of options (`tolerance`, `max_iterations`, `interface` one of
    /// `"dense"`, `"iterative"`, `"auto"`), checked.
    ///
    /// # Errors
    /// [`OptionsError`] naming the unknown or invalid setting.
    pub fn from_options(options: &Options) -> Result<Self, OptionsError> {
        let o: CondensedOptions = options.parse()?;
        let mut b = Self::builder();
        if let Some(t) = o.tolerance {
            b = b.tolerance(t);
        }
        if let Some(m) = o.max_iterations {
            b = b.max_iterations(m);
        }
        if let Some(i) = o.interface {
            b = b.interface(i);
        }
        b.build().map_err(OptionsError::from)
    }
}

/// Contact solver by condensation onto the interface: one sparse factorisation per body and
/// structure, an exact dense interface problem, one back substitution (see the module
/// documentation of `solver::condensed`). The default solver.
///
/// ```
/// use faer::sparse::{SparseColMat, Triplet};
/// use vem_contact::{ConstraintRows, ContactSolver, ContactSystem, CondensedSolver};
/// // A spring of stiffness 2 pushed by 3 against a wall at gap 1: it touches, and the wall
/// // takes 3 - 2 * 1 = 1.
/// let k = SparseColMat::try_new_from_triplets(1, 1, &[Triplet::new(0, 0, 2.0)]).unwrap();
/// let rows = ConstraintRows::try_from_triplets(1, 1, &[(0, 0, 1.0)]).unwrap();
/// let system = ContactSystem::try_new(k, vec![3.0], rows, vec![1.0], None).unwrap();
/// let solution = CondensedSolver::default().solve(&system).unwrap();
/// assert!((solution.displacement[0] - 1.0).abs() < 1e-14);
/// assert!((solution.normal_force[0] - 1.0).abs() < 1e-14);
/// ```
#[derive(Debug, Default)]
pub struct CondensedSolver {
    settings: CondensedSettings,
    structure: Option<Structure>,
    fallback: Option<ActiveSetSolver>,
}

/// What depends only on the structure and the stiffness values.
#[derive(Debug)]
struct Structure {
    pattern: PatternId,
    stiffness_version: u64,
    has_friction: bool,
    /// The shared orders and analyses of the blocks (held for the other solvers of the
    /// structure, and for a refilled stiffness).
    held: Held,
    /// `None` when a body stays singular with the shift (the active-set fallback solves).
    factors: Option<Factors>,
}

/// Shared work a solver holds so that other solvers of the structure find it.
#[derive(Debug, Default)]
struct Held {
    orders: Vec<Arc<BlockOrder>>,
    analyses: Vec<Arc<CholeskyAnalysis>>,
}

#[derive(Debug)]
struct Factors {
    bodies: Vec<BodyFactor>,
    /// `H = B M^-1 B'` (rows: normal, then tangential); empty for the iterative interface.
    hessian: Mat<f64>,
    /// The iterative interface: the bodies factorised in their best order (no trailing
    /// block), `H` applied by solves; `norm` its estimated norm (made at the first solve).
    iterative: Option<IterativeState>,
    /// The load of the last solve and `u0 = K_s^-1 f` for it.
    unconstrained: Option<(Vec<f64>, Vec<f64>)>,
    /// Per body, the loads solved for so far (see [`LoadSpan`]).
    spans: Vec<LoadSpan>,
    /// The multipliers of the last solve (warm start).
    multipliers: Option<Vec<f64>>,
    /// The factor of the reduced Hessian of the last Newton step of the interface QP.
    reduced: ReducedFactor,
}

#[derive(Debug)]
struct BodyFactor {
    offset: usize,
    n: usize,
    cholesky: CholeskySolver,
    /// The shared factor (held for the other solvers of the structure; none for the iterative
    /// interface, whose factor has no other user).
    _shared: Option<Arc<BlockFactor>>,
    /// The body's interface unknowns (local numbering, in trailing order).
    interface: Vec<usize>,
    /// The iterative interface: the part of the factor a solve on the interface unknowns
    /// reaches (`None` for the dense interface).
    support: Option<SolveSupport>,
    /// `L_GG`, the trailing block of the factor (empty without interface unknowns): the
    /// forward substitution of a right-hand side on the interface unknowns.
    trailing: Mat<f64>,
    /// Bodies with a singular stiffness: the shift, `W = L_GG^-1 B_G'` and the interface
    /// displacement `v` of the last solve (the start of the next proximal iteration).
    proximal: Option<Proximal>,
}

#[derive(Debug)]
struct Proximal {
    /// The shift `s` of the interface unknowns.
    shift: f64,
    w: Mat<f64>,
    interface_displacement: Vec<f64>,
    /// The change of `v` in the last proximal step.
    last_step: Vec<f64>,
}

impl CondensedSolver {
    /// A solver with the given settings.
    pub fn new(settings: CondensedSettings) -> Self {
        Self {
            settings,
            structure: None,
            fallback: None,
        }
    }

    /// The settings.
    pub fn settings(&self) -> &CondensedSettings {
        &self.settings
    }
}

/// The shift of a singular body's interface unknowns, relative to their largest stiffness.
const RELATIVE_SHIFT: f64 = 1e-4;
/// Proximal steps whose size shrinks by less than this factor (five times in a row) move along
/// a free mode: nothing holds it. (A mode held by a stiffness below `1e-6 s` looks the same.)
const STAGNATION: f64 = 1.0 - 1e-6;

/// The constraint rows of a system as `(columns, values)` per row: normal rows, then
/// tangential rows.
fn all_rows<'s>(system: &'s ContactSystem<'_>) -> Vec<(&'s [usize], &'s [f64])> {
    let normal = system.normal_rows();
    let mut rows: Vec<_> = (0..normal.nrows()).map(|i| normal.row(i)).collect();
    if let Some(friction) = system.friction() {
        let t = friction.tangential_rows();
        rows.extend((0..t.nrows()).map(|i| t.row(i)));
    }
    rows
}

fn backend(e: SolveError) -> ContactSolverError {
    ContactSolverError::Backend {
        solver: NAME,
        detail: e.to_string(),
    }
}

impl Structure {
    /// The structure of `system`; `factors` is `None` when a body stays singular with the
    /// shift.
    fn build(
        system: &ContactSystem<'_>,
        settings: &CondensedSettings,
        work: &mut WorkCounters,
    ) -> Result<Self, ContactSolverError> {
        let mut held = Held::default();
        let factors = Factors::build(system, settings, &mut held, work)?;
        Ok(Self {
            pattern: system.pattern(),
            stiffness_version: system.stiffness_version(),
            has_friction: system.friction().is_some(),
            held,
            factors,
        })
    }

    fn fits(&self, system: &ContactSystem<'_>) -> bool {
        self.pattern == system.pattern()
            && self.stiffness_version == system.stiffness_version()
            && self.has_friction == system.friction().is_some()
    }
}

impl Factors {
    fn build(
        system: &ContactSystem<'_>,
        settings: &CondensedSettings,
        held: &mut Held,
        work: &mut WorkCounters,
    ) -> Result<Option<Self>, ContactSolverError> {
        let rows = all_rows(system);
        let interfaces = shared::interfaces(system);
        let unknowns: usize = interfaces.iter().map(Vec::len).sum();
        let iterative = match settings.interface {
            InterfaceMethod::Dense => false,
            InterfaceMethod::Iterative => true,
            InterfaceMethod::Auto => {
                let from = match system.friction() {
                    None => ITERATIVE_FROM,
                    Some(friction) if friction.rows_per_node() == 2 => ITERATIVE_WITH_FRICTION_FROM,
                    Some(_) => ITERATIVE_WITH_FRICTION_IN_THE_PLANE_FROM,
                };
                unknowns >= from
            }
        };
        if iterative {
            if let Some(factors) =
                Self::build_iterative(system, settings, interfaces.clone(), work)?
            {
                return Ok(Some(factors));
            }
            // A body without a Cholesky factor (held only by contact or friction): the dense
            // interface with its shift and proximal steps.
        }
        // The bodies' blocks are independent: each is ordered, analysed and factorised on its
        // own thread (an ordering runs on one core; each factorisation chooses its own
        // parallelism), then their interface parts are summed in the order of the bodies.
        let parts: Vec<Result<BodyPart, ContactSolverError>> = interfaces
            .into_par_iter()
            .enumerate()
            .map(|(b, interface)| BodyPart::build(system, b, interface, &rows, settings))
            .collect();
        let mut hessian = Mat::<f64>::zeros(rows.len(), rows.len());
        let mut bodies = Vec::with_capacity(parts.len());
        let mut singular = false;
        for part in parts {
            let part = part?;
            *work += part.work;
            held.orders.push(part.order);
            held.analyses.push(part.analysis);
            let Some(mut body) = part.body else {
                singular = true;
                continue;
            };
            if let Some(w) = part.w {
                // H += W'W.
                matmul(
                    hessian.as_mut(),
                    Accum::Add,
                    w.transpose(),
                    w.as_ref(),
                    1.0,
                    Par::rayon(0),
                );
                if let Some(proximal) = body.proximal.as_mut() {
                    proximal.w = w;
                }
            }
            bodies.push(body);
        }
        if singular {
            return Ok(None);
        }
        Ok(Some(Self {
            bodies,
            hessian,
            iterative: None,
            unconstrained: None,
            spans: Vec::new(),
            multipliers: None,
            reduced: ReducedFactor::default(),
        }))
    }
}

impl Factors {
    /// The factors of the iterative interface: each body analysed and factorised in its best
    /// order (the bodies in parallel), nothing dense. `None` when a body's stiffness is
    /// singular (the caller turns to the dense interface and its shifted factors).
    fn build_iterative(
        system: &ContactSystem<'_>,
        settings: &CondensedSettings,
        interfaces: Vec<Vec<usize>>,
        work: &mut WorkCounters,
    ) -> Result<Option<Self>, ContactSolverError> {
        let parts: Vec<Result<(Option<BodyFactor>, WorkCounters), ContactSolverError>> = interfaces
            .into_par_iter()
            .enumerate()
            .map(|(b, interface)| {
                let mut work = WorkCounters::default();
                let block = &system.stiffness_blocks()[b];
                let (offset, k) = (block.offset(), block.matrix());
                let mut cholesky = CholeskySolver::new(settings.cholesky);
                let start = Instant::now();
                cholesky.analyse(k.symbolic()).map_err(backend)?;
                work.symbolic_analyses += 1;
                work.times.symbolic += start.elapsed();
                let start = Instant::now();
                let outcome = cholesky.factorise(k);
                work.numeric_factorisations += 1;
                work.times.numeric += start.elapsed();
                match outcome {
                    Ok(()) => Ok((
                        Some(BodyFactor {
                            offset,
                            n: k.nrows(),
                            support: Some(cholesky.support(&interface).map_err(backend)?),
                            cholesky,
                            _shared: None,
                            interface,
                            trailing: Mat::zeros(0, 0),
                            proximal: None,
                        }),
                        work,
                    )),
                    Err(SolveError::NotPositiveDefinite { .. }) => Ok((None, work)),
                    Err(e) => Err(backend(e)),
                }
            })
            .collect();
        let mut bodies = Vec::with_capacity(parts.len());
        let mut singular = false;
        for part in parts {
            let (body, part_work) = part?;
            *work += part_work;
            match body {
                Some(body) => bodies.push(body),
                None => singular = true,
            }
        }
        if singular {
            return Ok(None);
        }
        Ok(Some(Self {
            bodies,
            hessian: Mat::zeros(0, 0),
            iterative: Some(IterativeState {
                norm: None,
                scaling: None,
                kept: KeptProducts::new(),
                candidates: CandidateHessian::default(),
            }),
            unconstrained: None,
            spans: Vec::new(),
            multipliers: None,
            reduced: ReducedFactor::default(),
        }))
    }

    /// `H x = B K^-1 B' x` (one pair of triangular solves per body, the bodies in parallel).
    fn apply_operator(
        &self,
        rows: &[(&[usize], &[f64])],
        n: usize,
        x: &[f64],
        work: &mut WorkCounters,
    ) -> Result<Vec<f64>, ContactSolverError> {
        let mut load = vec![0.0; n];
        for (&(cols, values), &l) in rows.iter().zip(x) {
            if l != 0.0 {
                for (&c, v) in cols.iter().zip(values) {
                    load[c] += v * l;
                }
            }
        }
        self.solve_on_supports(&mut load, work)?;
        Ok(rows
            .iter()
            .map(|&(cols, values)| cols.iter().zip(values).map(|(&c, v)| v * load[c]).sum())
            .collect())
    }
}

/// What the iterative interface keeps per structure.
#[derive(Debug)]
struct IterativeState {
    /// The estimate of `|S H S|_2` (power iterations at the first solve).
    norm: Option<f64>,
    /// The scaling `S` of the multipliers ([`lumped_scaling`], made at the first solve).
    scaling: Option<Vec<f64>>,
    /// The products of `S H S` kept across the Newton systems and the solves of the
    /// structure (a Coulomb fixed point's steps share `H`): the spectral preconditioner of
    /// the Newton systems (`kept_products`).
    kept: KeptProducts,
    /// `H_CC` on the candidate nodes (`candidates`).
    candidates: CandidateHessian,
}

/// Power iterations for the estimate of `|S H S|_2` of the iterative interface (from the
/// smoothest vector, close to the eigenvector; the conjugate gradient steps raise the estimate
/// when their curvature exceeds it, and a projected step that raises the energy halves the
/// step length).
const NORM_ITERATIONS: usize = 3;
/// The iterative interface allows this many MPGP iterations (or operator products of its
/// projected Newton steps, with friction in space) per projected Newton step of
/// [`CondensedSettings::max_iterations`].
pub const ITERATIONS_PER_STEP: usize = 10;

/// What one body contributes to [`Factors`]: its shared order and analysis, its factor
/// (`None` when it stays singular with the shift), `W = L_GG^-1 B_G'` and the work done.
struct BodyPart {
    order: Arc<BlockOrder>,
    analysis: Arc<CholeskyAnalysis>,
    body: Option<BodyFactor>,
    w: Option<Mat<f64>>,
    work: WorkCounters,
}

impl BodyPart {
    fn build(
        system: &ContactSystem<'_>,
        b: usize,
        interface: Vec<usize>,
        rows: &[(&[usize], &[f64])],
        settings: &CondensedSettings,
    ) -> Result<Self, ContactSolverError> {
        let mut work = WorkCounters::default();
        let ordering = settings.cholesky.ordering();
        let block = &system.stiffness_blocks()[b];
        let (offset, k) = (block.offset(), block.matrix());
        let n = k.nrows();
        // The position of each interface unknown in G.
        const NONE: usize = usize::MAX;
        let mut position = vec![NONE; n];
        for (p, &i) in interface.iter().enumerate() {
            position[i] = p;
        }
        // The analysis with the interface last, on the block's shared order.
        let start = Instant::now();
        let order = shared::order_of_block(system, b, &interface, ordering).map_err(backend)?;
        let key = BlockKey::of(system, b, ordering);
        let (analysis, made) = shared::block_analysis(key, || {
            let mut cholesky = CholeskySolver::new(settings.cholesky);
            cholesky.analyse_with_order(k.symbolic(), &order.order, interface.len())?;
            Ok::<_, SolveError>(cholesky.shared_analysis().expect("analysed above"))
        })
        .map_err(backend)?;
        if made {
            work.symbolic_analyses += 1;
            work.times.symbolic += start.elapsed();
        }
        // The numeric factor for these stiffness values, shared.
        let factor_key = FactorKey {
            block: key,
            stiffness_version: system.stiffness_version(),
            settings: format!("{:?}", settings.cholesky),
        };
        let (block_factor, _) = shared::block_factor(factor_key, || {
            let mut cholesky =
                CholeskySolver::from_analysis(settings.cholesky, Arc::clone(&analysis));
            let shift = factorise_or_shift(&mut cholesky, k, &interface, &mut work)?;
            Ok::<_, ContactSolverError>(BlockFactor {
                factor: shift.and_then(|_| cholesky.shared_factor()),
                shift: shift.unwrap_or(0.0),
            })
        })?;
        let Some(factor) = block_factor.factor.clone() else {
            return Ok(Self {
                order,
                analysis,
                body: None,
                w: None,
                work,
            });
        };
        let shift = block_factor.shift;
        let cholesky = CholeskySolver::from_factor(settings.cholesky, factor);
        let mut proximal = None;
        let mut trailing = Mat::<f64>::zeros(0, 0);
        let mut w_of_body = None;
        if !interface.is_empty() {
            // W = L_GG^-1 B_G'.
            let mut w = Mat::<f64>::zeros(interface.len(), rows.len());
            for (r, &(cols, values)) in rows.iter().enumerate() {
                for (&c, &v) in cols.iter().zip(values) {
                    if (offset..offset + n).contains(&c) {
                        w[(position[c - offset], r)] += v;
                    }
                }
            }
            let l = cholesky.trailing_factor().map_err(backend)?;
            solve_lower_triangular_in_place(l.as_ref(), w.as_mut(), Par::rayon(0));
            if shift > 0.0 {
                proximal = Some(Proximal {
                    shift,
                    w: Mat::zeros(0, 0),
                    interface_displacement: vec![0.0; interface.len()],
                    last_step: vec![0.0; interface.len()],
                });
            }
            trailing = l;
            w_of_body = Some(w);
        }
        Ok(Self {
            order,
            analysis,
            body: Some(BodyFactor {
                offset,
                n,
                cholesky,
                _shared: Some(block_factor),
                interface,
                support: None,
                trailing,
                proximal,
            }),
            w: w_of_body,
            work,
        })
    }
}

/// Factorises `k`; if it is singular, factorises `k + s E_G` instead (the shift on the
/// interface unknowns). Returns the shift (`0` without one), or `None` if the shifted matrix
/// is singular too.
fn factorise_or_shift(
    cholesky: &mut CholeskySolver,
    k: faer::sparse::SparseColMatRef<'_, usize, f64>,
    interface: &[usize],
    work: &mut WorkCounters,
) -> Result<Option<f64>, ContactSolverError> {
    let start = Instant::now();
    let plain = cholesky.factorise(k);
    work.numeric_factorisations += 1;
    work.times.numeric += start.elapsed();
    match plain {
        Ok(()) => return Ok(Some(0.0)),
        Err(SolveError::NotPositiveDefinite { .. }) if !interface.is_empty() => {}
        Err(SolveError::NotPositiveDefinite { .. }) => return Ok(None),
        Err(e) => return Err(backend(e)),
    }
    let diagonal_slot = |j: usize| {
        let rows = k.symbolic().row_idx_of_col_raw(j);
        rows.binary_search(&j).ok().map(|p| k.col_ptr()[j] + p)
    };
    let largest = interface
        .iter()
        .filter_map(|&j| diagonal_slot(j).map(|slot| k.val()[slot].abs()))
        .fold(0.0f64, f64::max);
    let shift = RELATIVE_SHIFT * largest;
    // Only the values are copied; the pattern is the stiffness'.
    let mut values = k.val().to_vec();
    for &j in interface {
        // The stiffness pattern holds every diagonal entry (element matrices are dense).
        if let Some(slot) = diagonal_slot(j) {
            values[slot] += shift;
        }
    }
    let shifted = faer::sparse::SparseColMatRef::new(k.symbolic(), &values);
    let start = Instant::now();
    let outcome = cholesky.factorise(shifted);
    work.numeric_factorisations += 1;
    work.times.numeric += start.elapsed();
    match outcome {
        Ok(()) if shift > 0.0 => Ok(Some(shift)),
        Ok(()) | Err(SolveError::NotPositiveDefinite { .. }) => Ok(None),
        Err(e) => Err(backend(e)),
    }
}

impl Factors {
    /// The bodies' parts of `x`, in the order of the bodies (consecutive blocks).
    fn parts<'a>(&'a self, x: &'a mut [f64]) -> Vec<(&'a BodyFactor, &'a mut [f64])> {
        let mut parts = Vec::with_capacity(self.bodies.len());
        let mut rest = x;
        let mut position = 0;
        for body in &self.bodies {
            let (_, tail) = rest.split_at_mut(body.offset - position);
            let (part, tail) = tail.split_at_mut(body.n);
            parts.push((body, part));
            rest = tail;
            position = body.offset + body.n;
        }
        parts
    }

    /// `f(body, part)` on each body's part of `x`, the bodies in parallel (their blocks are
    /// independent), counted as one triangular solve pair per body.
    fn per_body(
        &self,
        x: &mut [f64],
        work: &mut WorkCounters,
        f: impl Fn(&BodyFactor, &mut [f64]) -> Result<(), ContactSolverError> + Sync,
    ) -> Result<(), ContactSolverError> {
        let start = Instant::now();
        self.parts(x)
            .into_par_iter()
            .map(|(body, part)| f(body, part))
            .collect::<Result<Vec<()>, _>>()?;
        work.triangular_solves += self.bodies.len();
        work.times.solves += start.elapsed();
        Ok(())
    }

    /// `K_s^-1 x`.
    fn solve(&self, x: &mut [f64], work: &mut WorkCounters) -> Result<(), ContactSolverError> {
        self.per_body(x, work, |body, part| {
            body.cholesky
                .solve_in_place(MatMut::from_column_major_slice_mut(part, body.n, 1))
                .map_err(backend)
        })
    }

    /// `(K_s^-1 x)` at the interface unknowns for an `x` that vanishes outside them, each body
    /// by [`CholeskySolver::solve_on_support`] (the iterative interface: the supernodes the
    /// interface unknowns do not reach are not read; a complete solve without a support).
    /// Entries of `x` outside the interface unknowns are left as they were.
    fn solve_on_supports(
        &self,
        x: &mut [f64],
        work: &mut WorkCounters,
    ) -> Result<(), ContactSolverError> {
        self.per_body(x, work, |body, part| {
            let Some(support) = &body.support else {
                return body
                    .cholesky
                    .solve_in_place(MatMut::from_column_major_slice_mut(part, body.n, 1))
                    .map_err(backend);
            };
            let mut values: Vec<f64> = body.interface.iter().map(|&i| part[i]).collect();
            body.cholesky
                .solve_on_support(support, &mut values)
                .map_err(backend)?;
            for (&i, v) in body.interface.iter().zip(values) {
                part[i] = v;
            }
            Ok(())
        })
    }

    /// `K_s^-1 x` for an `x` that vanishes outside the interface unknowns: the forward
    /// substitution on the interface block (dense, with `L_GG`), then the backward
    /// substitution of the body's factor ([`CholeskySolver::solve_from_trailing`]), half a
    /// solve.
    fn solve_on_interface(
        &self,
        x: &mut [f64],
        work: &mut WorkCounters,
    ) -> Result<(), ContactSolverError> {
        self.per_body(x, work, |body, part| {
            if body.interface.is_empty() {
                part.fill(0.0);
                return Ok(());
            }
            let mut y =
                Mat::<f64>::from_fn(body.interface.len(), 1, |k, _| part[body.interface[k]]);
            solve_lower_triangular_in_place(body.trailing.as_ref(), y.as_mut(), Par::Seq);
            let y: Vec<f64> = (0..body.interface.len()).map(|k| y[(k, 0)]).collect();
            body.cholesky.solve_from_trailing(&y, part).map_err(backend)
        })
    }

    fn is_shifted(&self) -> bool {
        self.bodies.iter().any(|b| b.proximal.is_some())
    }

    /// `u0 = K_s^-1 f` for the load `load`: the last one again, or body by body from the span
    /// of the loads solved before (one triangular solve pair only for a body whose load leaves
    /// that span).
    fn unconstrained(
        &mut self,
        load: &[f64],
        work: &mut WorkCounters,
    ) -> Result<Vec<f64>, ContactSolverError> {
        if let Some((last, u0)) = &self.unconstrained {
            if last == load {
                return Ok(u0.clone());
            }
        }
        let start = Instant::now();
        self.spans.resize_with(self.bodies.len(), LoadSpan::default);
        let mut u0 = vec![0.0; load.len()];
        for (body, span) in self.bodies.iter().zip(&mut self.spans) {
            let range = body.offset..body.offset + body.n;
            let (direction, residual) = span.combine(&load[range.clone()], &mut u0[range.clone()]);
            if let Some(mut direction) = direction {
                // A new direction: K_s^-1 of it, kept with it.
                let mut z = direction.clone();
                body.cholesky
                    .solve_in_place(MatMut::from_column_major_slice_mut(&mut z, body.n, 1))
                    .map_err(backend)?;
                work.triangular_solves += 1;
                for (u, zi) in u0[range].iter_mut().zip(&z) {
                    *u += residual * zi;
                }
                if span.basis.len() == SPAN_SIZE {
                    span.basis.clear();
                }
                direction.shrink_to_fit();
                span.basis.push((direction, z));
            }
        }
        work.times.solves += start.elapsed();
        self.unconstrained = Some((load.to_vec(), u0.clone()));
        Ok(u0)
    }
}

/// The loads a body has been solved for, as an orthonormal basis `q_k` with `z_k = K_s^-1 q_k`:
/// a load `f = sum_k a_k q_k + r` has `K_s^-1 f = sum_k a_k z_k + K_s^-1 r`, and the last term
/// is needed only when `r` is not round-off. Along a load history (a few conditions scaled by
/// their factors) the loads of the steps span a space of the dimension of the number of
/// conditions: after the first steps, `u0` costs no triangular solve.
#[derive(Debug, Default)]
struct LoadSpan {
    basis: Vec<(Vec<f64>, Vec<f64>)>,
}

/// Largest number of directions kept per body (the basis starts again when full).
const SPAN_SIZE: usize = 8;
/// A load whose part outside the span is below this fraction of it lies in the span: the
/// equations are then solved to this relative residual (the acceptance test checks them at
/// `1e-9` or above).
const SPAN_TOLERANCE: f64 = 1e-13;

impl LoadSpan {
    /// Adds `sum_k a_k z_k` to `u` for the coefficients `a_k` of `f` on the basis (Gram-Schmidt
    /// twice) and returns the unit direction of the rest with its norm, when the rest is not
    /// round-off (`None` then: `u` is `K_s^-1 f`).
    fn combine(&self, f: &[f64], u: &mut [f64]) -> (Option<Vec<f64>>, f64) {
        let norm = f.iter().map(|x| x * x).sum::<f64>().sqrt();
        if norm == 0.0 {
            return (None, 0.0);
        }
        let mut rest = f.to_vec();
        let mut coefficients = vec![0.0; self.basis.len()];
        for _ in 0..2 {
            for ((q, _), a) in self.basis.iter().zip(&mut coefficients) {
                let c: f64 = q.iter().zip(&rest).map(|(q, r)| q * r).sum();
                for (r, qi) in rest.iter_mut().zip(q) {
                    *r -= c * qi;
                }
                *a += c;
            }
        }
        for ((_, z), &a) in self.basis.iter().zip(&coefficients) {
            for (ui, zi) in u.iter_mut().zip(z) {
                *ui += a * zi;
            }
        }
        let residual = rest.iter().map(|x| x * x).sum::<f64>().sqrt();
        if residual <= SPAN_TOLERANCE * norm {
            return (None, 0.0);
        }
        for r in &mut rest {
            *r /= residual;
        }
        (Some(rest), residual)
    }
}

/// What the interface iteration returns.
struct Interface {
    lambda: Vec<f64>,
    /// The linear term `d` of the last interface QP solved (`d0`, or the last proximal
    /// step's): `B u = [g; s] + d - H lambda` for the answer `u` of `lambda`.
    d: Vec<f64>,
    iterations: usize,
    converged: bool,
    /// The proximal steps moved along a free mode instead of converging.
    free_mode: bool,
    /// `H lambda` (the iterative interface, which has no `H` to multiply by).
    hessian_lambda: Option<Vec<f64>>,
    /// The solver's name in the report: how the interface was solved.
    solver: &'static str,
}

/// The bound-constrained interface QP, with the tolerance relative to
/// `max_i |clamp(d_i / H_ii)|` (the force that would close the largest unconstrained
/// penetration, or stop the largest slip, alone, within its bounds); zero data give exactly
/// zero forces.
#[allow(clippy::too_many_arguments)]
fn interface_qp(
    hessian: MatRef<'_, f64>,
    d: &[f64],
    lower: &[f64],
    upper: &[f64],
    disks: &[Disk],
    warm: &[f64],
    settings: &CondensedSettings,
    kept: &mut ReducedFactor,
) -> BoxQpOutcome {
    // Rows that cannot carry a force do not set the scale: an open gap (d_i < 0 on a normal
    // row, whose lower bound is 0) and a tangential row beyond its bound (a disk's radius).
    let mut cap = vec![f64::INFINITY; d.len()];
    for disk in disks {
        cap[disk.first] = disk.radius;
        cap[disk.first + 1] = disk.radius;
    }
    let force_scale = (0..d.len())
        .filter(|&i| hessian[(i, i)] > 0.0)
        .fold(0.0f64, |a, i| {
            let force = d[i] / hessian[(i, i)];
            a.max(force.max(lower[i]).min(upper[i]).abs().min(cap[i]))
        });
    if force_scale == 0.0 {
        return BoxQpOutcome {
            x: vec![0.0; d.len()],
            iterations: 0,
            converged: true,
        };
    }
    dense_qp(
        hessian,
        d,
        lower,
        upper,
        disks,
        warm,
        settings.tolerance * force_scale,
        settings.max_iterations,
        kept,
    )
}

/// The dense interface QP from `warm` to the force `tolerance` of the projected Newton
/// methods: the disk QP with disks (friction in space), else the box QP.
#[allow(clippy::too_many_arguments)]
fn dense_qp(
    hessian: MatRef<'_, f64>,
    d: &[f64],
    lower: &[f64],
    upper: &[f64],
    disks: &[Disk],
    warm: &[f64],
    tolerance: f64,
    max_iterations: usize,
    kept: &mut ReducedFactor,
) -> BoxQpOutcome {
    if !disks.is_empty() {
        return DiskQp {
            hessian,
            linear: d,
            lower,
            upper,
            disks,
        }
        .solve_with(warm, tolerance, max_iterations, kept);
    }
    BoxQp {
        hessian,
        linear: d,
        lower,
        upper,
    }
    .solve_with(warm, tolerance, max_iterations, kept)
}

/// The interface QP by MPGP on the Schur operator `H = B K^-1 B'` (the iterative interface),
/// from `warm`. The stopping test is `|g^P|_inf <= tolerance * L` with `L` the length scale of
/// the data: `max_i d_i^+` over the normal rows (the largest unconstrained penetration) and
/// `|d_i|` over the tangential rows whose bound is not zero (the largest slip); zero data give
/// exactly zero forces. `|H|` is estimated once per structure.
#[allow(clippy::too_many_arguments)]
fn iterative_interface(
    factors: &mut Factors,
    system: &ContactSystem<'_>,
    rows: &[(&[usize], &[f64])],
    d: Vec<f64>,
    lower: &[f64],
    upper: &[f64],
    disks: &[Disk],
    warm: &[f64],
    settings: &CondensedSettings,
    work: &mut WorkCounters,
) -> Result<Interface, ContactSolverError> {
    let mut carries = vec![true; d.len()];
    for (i, c) in carries.iter_mut().enumerate() {
        *c = upper[i] > lower[i];
    }
    for disk in disks {
        carries[disk.first] = disk.radius > 0.0;
        carries[disk.first + 1] = disk.radius > 0.0;
    }
    // Normal rows: lower bound 0, upper +inf; tangential rows: symmetric bounds or disks.
    let length_scale = (0..d.len()).filter(|&i| carries[i]).fold(0.0f64, |a, i| {
        let length = if lower[i] == 0.0 && upper[i] == f64::INFINITY {
            d[i].max(0.0)
        } else {
            d[i].abs()
        };
        a.max(length)
    });
    if length_scale == 0.0 {
        return Ok(Interface {
            lambda: vec![0.0; d.len()],
            d,
            iterations: 0,
            converged: true,
            free_mode: false,
            hessian_lambda: Some(vec![0.0; rows.len()]),
            solver: ITERATIVE_NAME,
        });
    }
    let tolerance = settings.tolerance * length_scale;
    // Few nodes carry a force: the dense QP on them (`candidates`).
    let warm = match solve_on_candidates(
        factors,
        rows,
        system.n_dofs(),
        (
            system.n_constraints(),
            system.friction().map_or(0, |f| f.rows_per_node()),
        ),
        &d,
        (lower, upper, disks),
        &carries,
        warm,
        tolerance,
        settings.max_iterations,
        work,
    )? {
        CandidateOutcome::Solved(interface) => return Ok(interface),
        CandidateOutcome::Iterate(warm) => warm,
    };
    // The problem in scaled multipliers `lambda = S y` (`S` the [`lumped_scaling`]), whose
    // operator `S H S` has a nearly uniform diagonal; the stopping test stays unscaled.
    let scale = match factors.iterative.as_ref().and_then(|s| s.scaling.clone()) {
        Some(scale) => scale,
        None => lumped_scaling(system, rows, disks),
    };
    let unit = |v: &[f64], f: fn(f64, f64) -> f64| -> Vec<f64> {
        v.iter().zip(&scale).map(|(&v, &s)| f(v, s)).collect()
    };
    let (times, over) = (|v: f64, s: f64| v * s, |v: f64, s: f64| v / s);
    let scaled_d = unit(&d, times);
    let (scaled_lower, scaled_upper) = (unit(lower, over), unit(upper, over));
    let scaled_disks: Vec<Disk> = disks
        .iter()
        .map(|disk| Disk {
            first: disk.first,
            radius: disk.radius / scale[disk.first],
        })
        .collect();
    let weights: Vec<f64> = scale.iter().map(|s| 1.0 / s).collect();
    // The products kept from the earlier solves of the structure (the same `S H S`), and the
    // ones of this solve added to them: the preconditioner of the Newton systems.
    let mut kept = factors
        .iterative
        .as_mut()
        .map(|state| std::mem::take(&mut state.kept))
        .unwrap_or_default();
    let (this, n): (&Factors, _) = (factors, system.n_dofs());
    let mut apply = |y: &[f64]| -> Result<Vec<f64>, ContactSolverError> {
        let hx = this.apply_operator(rows, n, &unit(y, times), work)?;
        Ok(unit(&hx, times))
    };
    let norm = match this.iterative.as_ref().and_then(|s| s.norm) {
        Some(norm) => norm,
        None => mprgp::norm_estimate(d.len(), NORM_ITERATIONS, |v| {
            let hv = apply(v)?;
            kept.add(v, &hv);
            Ok(hv)
        })?,
    };
    let qp = Mprgp {
        linear: &scaled_d,
        lower: &scaled_lower,
        upper: &scaled_upper,
        disks: &scaled_disks,
        weights: &weights,
    };
    let budget = settings.max_iterations * ITERATIONS_PER_STEP;
    let start = unit(&warm, over);
    let outcome = if disks.is_empty() {
        qp.solve(&start, tolerance, budget, norm, &mut apply)?
    } else {
        // Friction in space: the sliding nodes move along their rims by Newton steps.
        qp.solve_by_newton(
            &start,
            tolerance,
            settings.max_iterations,
            budget,
            norm,
            &mut kept,
            &mut apply,
        )?
    };
    let lambda = unit(&outcome.x, times);
    let hessian_lambda = unit(&outcome.hx, over);
    if let Some(state) = factors.iterative.as_mut() {
        state.norm = Some(norm);
        state.scaling = Some(scale);
        state.kept = kept;
    }
    Ok(Interface {
        lambda,
        d,
        iterations: outcome.iterations,
        converged: outcome.converged,
        free_mode: false,
        hessian_lambda: Some(hessian_lambda),
        solver: ITERATIVE_NAME,
    })
}

/// The scaling `S` of the iterative interface's multipliers: `s_i = sqrt(k_i / mean k)` with
/// `k_i = (B K B')_ii`, the stiffness of row `i`'s constraint (its nodes held by their
/// elements alone). The compliance `H_ii = (B K^-1 B')_ii` of a node varies about as `1 / k_i`
/// (a node of a small overlay cell is stiff and its force small), so `S H S` has a nearly
/// uniform diagonal and conjugate gradients need fewer iterations on irregular interfaces.
/// The two rows of a disk share one scale (the geometric mean): a disk stays a disk.
fn lumped_scaling(
    system: &ContactSystem<'_>,
    rows: &[(&[usize], &[f64])],
    disks: &[Disk],
) -> Vec<f64> {
    let blocks = system.stiffness_blocks();
    let entry = |a: usize, b: usize| -> f64 {
        // The block holding `a` (blocks in order of their offsets).
        let i = blocks.partition_point(|block| block.offset() <= a);
        let Some(block) = i.checked_sub(1).map(|i| &blocks[i]) else {
            return 0.0;
        };
        let k = block.matrix().as_ref();
        let (a, Some(b)) = (a - block.offset(), b.checked_sub(block.offset())) else {
            return 0.0;
        };
        if a >= k.nrows() || b >= k.ncols() {
            return 0.0;
        }
        let sorted = k.row_idx_of_col_raw(b).windows(2).all(|w| w[0] < w[1]);
        matrix_entry(k, a, b, sorted)
    };
    let mut stiffness: Vec<f64> = rows
        .iter()
        .map(|&(cols, values)| {
            let mut sum = 0.0;
            for (&a, va) in cols.iter().zip(values) {
                for (&b, vb) in cols.iter().zip(values) {
                    sum += va * vb * entry(a, b);
                }
            }
            sum
        })
        .collect();
    for disk in disks {
        let (a, b) = (disk.first, disk.first + 1);
        let mean = (stiffness[a].max(0.0) * stiffness[b].max(0.0)).sqrt();
        stiffness[a] = mean;
        stiffness[b] = mean;
    }
    let positive: Vec<f64> = stiffness
        .iter()
        .copied()
        .filter(|k| *k > 0.0 && k.is_finite())
        .collect();
    if positive.is_empty() {
        return vec![1.0; rows.len()];
    }
    let mean = positive.iter().sum::<f64>() / positive.len() as f64;
    stiffness
        .iter()
        .map(|&k| {
            if k > 0.0 && k.is_finite() {
                (k / mean).sqrt()
            } else {
                1.0
            }
        })
        .collect()
}

/// Proximal point steps on the interface for systems with shifted (singular) bodies: each step
/// is the interface QP with `d = d0 + sum_b W_b' L_b^-1 (s_b v_b)`, then
/// `v_b <- u0_b + L_b^-T (L_b^-1 s_b v_b - W_b lambda)` on each shifted body. Stops when the
/// interface force residual `s_b |v_k+1 - v_k|` is below the tolerance times the force scale
/// `max(||f||, ||B' lambda||)`, or when the steps stop shrinking (a free mode).
#[allow(clippy::too_many_arguments)]
fn proximal_iteration(
    factors: &mut Factors,
    system: &ContactSystem<'_>,
    rows: &[(&[usize], &[f64])],
    u0: &[f64],
    d0: &[f64],
    lower: &[f64],
    upper: &[f64],
    disks: &[Disk],
    warm: Vec<f64>,
    settings: &CondensedSettings,
) -> Interface {
    let mut result = Interface {
        lambda: warm,
        d: d0.to_vec(),
        iterations: 0,
        converged: false,
        free_mode: false,
        hessian_lambda: None,
        solver: NAME,
    };
    let load_scale = inf(system.load());
    let mut reaction = vec![0.0; system.n_dofs()];
    let (mut previous_step, mut stagnant) = (f64::INFINITY, 0);
    for _ in 0..settings.max_iterations {
        let mut d = d0.to_vec();
        let mut shifted_loads = Vec::new();
        for body in &factors.bodies {
            if let Some(p) = &body.proximal {
                let mut z = Mat::<f64>::from_fn(p.interface_displacement.len(), 1, |i, _| {
                    p.shift * p.interface_displacement[i]
                });
                solve_lower_triangular_in_place(body.trailing.as_ref(), z.as_mut(), Par::Seq);
                let wz = p.w.transpose() * &z;
                for (i, di) in d.iter_mut().enumerate() {
                    *di += wz[(i, 0)];
                }
                shifted_loads.push(z);
            }
        }
        let outcome = interface_qp(
            factors.hessian.as_ref(),
            &d,
            lower,
            upper,
            disks,
            &result.lambda,
            settings,
            &mut factors.reduced,
        );
        result.iterations += outcome.iterations;
        result.lambda = outcome.x;
        result.d = d;
        if !outcome.converged {
            return result;
        }
        let lambda = Mat::<f64>::from_fn(result.lambda.len(), 1, |i, _| result.lambda[i]);
        let mut residual = 0.0f64;
        let mut step = 0.0f64;
        for (body, mut z) in factors
            .bodies
            .iter_mut()
            .filter(|b| b.proximal.is_some())
            .zip(shifted_loads)
        {
            let p = body.proximal.as_mut().expect("filtered");
            matmul(
                z.as_mut(),
                Accum::Add,
                p.w.as_ref(),
                lambda.as_ref(),
                -1.0,
                Par::Seq,
            );
            solve_upper_triangular_in_place(body.trailing.transpose(), z.as_mut(), Par::Seq);
            let mut body_step = 0.0f64;
            for (k, &i) in body.interface.iter().enumerate() {
                let v = u0[body.offset + i] + z[(k, 0)];
                p.last_step[k] = v - p.interface_displacement[k];
                body_step = body_step.max(p.last_step[k].abs());
                p.interface_displacement[k] = v;
            }
            residual = residual.max(p.shift * body_step);
            step = step.max(body_step);
        }
        // ||B' lambda||_inf, touching only the rows' columns.
        for (&(cols, values), &l) in rows.iter().zip(&result.lambda) {
            for (&c, v) in cols.iter().zip(values) {
                reaction[c] += v * l;
            }
        }
        let mut reaction_scale = 0.0f64;
        for &(cols, _) in rows {
            for &c in cols {
                reaction_scale = reaction_scale.max(reaction[c].abs());
                reaction[c] = 0.0;
            }
        }
        let force_scale = load_scale.max(reaction_scale);
        if residual <= settings.tolerance * force_scale {
            result.converged = true;
            return result;
        }
        // A step that does not shrink moves along a free mode only if it approaches no normal
        // row (otherwise a gap is still closing, by steps of the same size).
        let not_shrinking = step > STAGNATION * previous_step;
        stagnant = if not_shrinking && !approaches_a_constraint(factors, system, rows) {
            stagnant + 1
        } else {
            0
        };
        if stagnant >= 5 {
            result.free_mode = true;
            return result;
        }
        previous_step = step;
    }
    result
}

/// True when the last proximal step `dv` of the shifted bodies moves some node towards closing
/// its normal gap: `(B_N dv)_i > 0`.
fn approaches_a_constraint(
    factors: &Factors,
    system: &ContactSystem<'_>,
    rows: &[(&[usize], &[f64])],
) -> bool {
    let mut step = vec![0.0; system.n_dofs()];
    for body in &factors.bodies {
        if let Some(p) = &body.proximal {
            for (&i, dv) in body.interface.iter().zip(&p.last_step) {
                step[body.offset + i] = *dv;
            }
        }
    }
    let largest = inf(&step);
    rows[..system.n_constraints()]
        .iter()
        .any(|&(cols, values)| {
            let approach: f64 = cols.iter().zip(values).map(|(&c, v)| v * step[c]).sum();
            approach > 1e-12 * largest
        })
}

/// Solves with the active-set solver, adding the work done so far; its report, and the
/// report of its failure, name the condensed solver and the handover.
fn fall_back(
    fallback: &mut Option<ActiveSetSolver>,
    system: &ContactSystem<'_>,
    work: WorkCounters,
) -> Result<ContactSolution, ContactSolverError> {
    match fallback
        .get_or_insert_with(ActiveSetSolver::default)
        .solve(system)
    {
        Ok(mut solution) => {
            solution.report.work += work;
            solution.report.solver = HANDED_OVER;
            Ok(solution)
        }
        Err(mut error) => {
            match &mut error {
                ContactSolverError::NotConverged { report }
                | ContactSolverError::RigidSliding { report, .. }
                | ContactSolverError::Unbounded { report, .. }
                | ContactSolverError::Infeasible { report } => {
                    report.work += work;
                    report.solver = HANDED_OVER;
                }
                ContactSolverError::Backend { solver, .. } => *solver = HANDED_OVER,
            }
            Err(error)
        }
    }
}

/// Where a solve stands after the interface problem.
enum Stage {
    /// Answered without the interface problem (unloaded, or handed over).
    Done(ContactSolution),
    /// The interface answer, before the back substitution.
    Interface {
        interface: Interface,
        u0: Vec<f64>,
        start: Instant,
        work: WorkCounters,
    },
}

impl CondensedSolver {
    /// Everything up to the interface answer: the factors (kept per structure), `u0`, the
    /// interface QP (with the proximal steps of shifted bodies).
    fn interface_stage(&mut self, system: &ContactSystem<'_>) -> Result<Stage, ContactSolverError> {
        let start = Instant::now();
        if unloaded(system) {
            return Ok(Stage::Done(unloaded_solution(system, NAME, start)));
        }
        let mut work = WorkCounters::default();
        if !self.structure.as_ref().is_some_and(|s| s.fits(system)) {
            // The old factors go before the new ones are made; the orders and analyses stay
            // (a refilled stiffness keeps its pattern).
            let held = self.structure.take().map(|s| s.held);
            self.structure = Some(Structure::build(system, &self.settings, &mut work)?);
            drop(held);
        }
        let structure = self.structure.as_mut().expect("built above");
        let Some(factors) = structure.factors.as_mut() else {
            // Singular even with the interface shifted: the active-set solver's shifted
            // factorisation and free-mode test handle it.
            return fall_back(&mut self.fallback, system, work).map(Stage::Done);
        };
        let m = system.n_constraints();
        let rows = all_rows(system);

        // u0 = K_s^-1 f (the last one again for the same load, Coulomb steps; from the span of
        // the loads solved before, load steps).
        let u0 = factors.unconstrained(system.load(), &mut work)?;
        let apply_rows = |x: &[f64]| -> Vec<f64> {
            rows.iter()
                .map(|&(cols, values)| cols.iter().zip(values).map(|(&c, v)| v * x[c]).sum())
                .collect()
        };
        let mut d0 = apply_rows(&u0);
        for (di, g) in d0.iter_mut().zip(system.gap()) {
            *di -= g;
        }
        if let Some(friction) = system.friction() {
            friction.subtract_reference(&mut d0[m..]);
        }
        let mut lower = vec![0.0; rows.len()];
        let mut upper = vec![f64::INFINITY; rows.len()];
        let mut disks = Vec::new();
        if let Some(friction) = system.friction() {
            let t = friction.rows_per_node();
            for (i, &b) in friction.bounds().iter().enumerate() {
                if t == 1 {
                    // The plane: an interval, the box QP.
                    lower[m + i] = -b;
                    upper[m + i] = b;
                } else {
                    // Space: a disk of the node's two tangential rows.
                    for k in 0..t {
                        lower[m + t * i + k] = f64::NEG_INFINITY;
                    }
                    disks.push(Disk {
                        first: m + t * i,
                        radius: b,
                    });
                }
            }
        }
        let warm = factors
            .multipliers
            .take()
            .filter(|l| l.len() == rows.len())
            .unwrap_or_else(|| vec![0.0; rows.len()]);
        let interface = if factors.iterative.is_some() {
            iterative_interface(
                factors,
                system,
                &rows,
                d0,
                &lower,
                &upper,
                &disks,
                &warm,
                &self.settings,
                &mut work,
            )?
        } else if factors.is_shifted() {
            proximal_iteration(
                factors,
                system,
                &rows,
                &u0,
                &d0,
                &lower,
                &upper,
                &disks,
                warm,
                &self.settings,
            )
        } else {
            let outcome = interface_qp(
                factors.hessian.as_ref(),
                &d0,
                &lower,
                &upper,
                &disks,
                &warm,
                &self.settings,
                &mut factors.reduced,
            );
            Interface {
                lambda: outcome.x,
                d: d0,
                iterations: outcome.iterations,
                converged: outcome.converged,
                free_mode: false,
                hessian_lambda: None,
                solver: NAME,
            }
        };
        if !interface.converged && !interface.free_mode && factors.is_shifted() {
            // The proximal steps converge too slowly (a floating body held by a much softer
            // one): the active-set solver's shifted factorisation of the whole system does not
            // depend on the shift's size in the same way.
            return fall_back(&mut self.fallback, system, work).map(Stage::Done);
        }
        factors.multipliers = Some(interface.lambda.clone());
        Ok(Stage::Interface {
            interface,
            u0,
            start,
            work,
        })
    }

    /// The displacement of the interface answer (one back substitution), its certification
    /// and report.
    fn finish(
        &mut self,
        system: &ContactSystem<'_>,
        interface: Interface,
        u0: Vec<f64>,
        start: Instant,
        mut work: WorkCounters,
    ) -> Result<ContactSolution, ContactSolverError> {
        let factors = self
            .structure
            .as_mut()
            .and_then(|s| s.factors.as_mut())
            .expect("an interface answer has factors");
        let (n, m) = (system.n_dofs(), system.n_constraints());
        let rows = all_rows(system);
        let lambda = interface.lambda;

        // u = K_s^-1 (f - B' lambda + s E_G v) = u0 - K_s^-1 (B' lambda - s E_G v).
        let mut correction = vec![0.0; n];
        for (&(cols, values), &l) in rows.iter().zip(&lambda) {
            if l != 0.0 {
                for (&c, v) in cols.iter().zip(values) {
                    correction[c] += v * l;
                }
            }
        }
        for body in &factors.bodies {
            if let Some(p) = &body.proximal {
                // v_k, the start of the last proximal step (whose lambda this is): then the
                // interface part of u is v_k+1 exactly.
                for ((&i, v), dv) in body
                    .interface
                    .iter()
                    .zip(&p.interface_displacement)
                    .zip(&p.last_step)
                {
                    correction[body.offset + i] -= p.shift * (v - dv);
                }
            }
        }
        if factors.iterative.is_some() {
            factors.solve(&mut correction, &mut work)?;
        } else {
            // The correction lies on the interface unknowns: half a solve per body.
            factors.solve_on_interface(&mut correction, &mut work)?;
        }
        let displacement: Vec<f64> = u0.iter().zip(&correction).map(|(a, b)| a - b).collect();
        let normal_force = lambda[..m].to_vec();
        let tangential_force = if system.friction().is_some() {
            lambda[m..].to_vec()
        } else {
            vec![0.0; m]
        };

        let (status, residuals) = if interface.converged {
            match certify(
                system,
                &displacement,
                &normal_force,
                &tangential_force,
                self.settings.acceptance(),
            ) {
                Ok(residuals) => (SolveStatus::Converged, residuals),
                Err(residuals) => (SolveStatus::FailedCheck, residuals),
            }
        } else {
            let status = if interface.free_mode {
                SolveStatus::Unbounded
            } else {
                SolveStatus::MaxIterations
            };
            let residuals =
                KktResiduals::evaluate(system, &displacement, &normal_force, &tangential_force);
            (status, residuals)
        };
        work.times.contact_solve = start.elapsed();
        let report = SolveReport {
            solver: interface.solver,
            status,
            iterations: interface.iterations,
            work,
            wall_time: start.elapsed(),
            residuals,
            warnings: Vec::new(),
        };
        if interface.free_mode {
            // The free mode: the change of u over one proximal step, from the last
            // interface step (zero load, zero force: K_s d = s E_G dv).
            let mut direction = vec![0.0; n];
            for body in &factors.bodies {
                if let Some(p) = &body.proximal {
                    for (&i, v) in body.interface.iter().zip(&p.last_step) {
                        direction[body.offset + i] = p.shift * v;
                    }
                }
            }
            let mut scratch = WorkCounters::default();
            factors.solve(&mut direction, &mut scratch)?;
            return Err(ContactSolverError::from_free_mode(
                system,
                &direction,
                Box::new(report),
            ));
        }
        if status == SolveStatus::Converged {
            Ok(ContactSolution {
                displacement,
                normal_force,
                tangential_force,
                report,
            })
        } else {
            Err(ContactSolverError::NotConverged {
                report: Box::new(report),
            })
        }
    }
}

impl CondensedSolver {
    /// One solve at the settings' tolerance: the interface stage, then the back substitution
    /// and the KKT check.
    fn solve_once(
        &mut self,
        system: &ContactSystem<'_>,
    ) -> Result<ContactSolution, ContactSolverError> {
        match self.interface_stage(system)? {
            Stage::Done(solution) => Ok(solution),
            Stage::Interface {
                interface,
                u0,
                start,
                work,
            } => self.finish(system, interface, u0, start, work),
        }
    }
}

impl ContactSolver for CondensedSolver {
    fn name(&self) -> &'static str {
        NAME
    }

    fn solve(&mut self, system: &ContactSystem<'_>) -> Result<ContactSolution, ContactSolverError> {
        let first = self.solve_once(system);
        let shifted = self
            .structure
            .as_ref()
            .and_then(|s| s.factors.as_ref())
            .is_some_and(Factors::is_shifted);
        match first {
            // The proximal iteration of a floating body stops on a small step, and converges
            // linearly: warm-started near its fixed point it may stop at once, short of the KKT
            // check by a little (seen at 1.1e-9 against 1e-9 on a block held sideways by
            // Coulomb friction alone). Iterate on, from where it stopped, at a tolerance 1e-3
            // tighter; the answer is certified as before.
            Err(ContactSolverError::NotConverged { report })
                if shifted && report.status == SolveStatus::FailedCheck =>
            {
                let tolerance = self.settings.tolerance;
                self.settings.tolerance = tolerance * 1e-3;
                let again = self.solve_once(system);
                self.settings.tolerance = tolerance;
                again.map(|mut solution| {
                    solution.report.work += report.work;
                    solution.report.iterations += report.iterations;
                    solution
                })
            }
            other => other,
        }
    }

    /// The forces of the interface answer and `B u = [g; s] + d - H lambda` (the gap and the
    /// reference slip less the dual gradient), without the back substitution: interface work
    /// only once `u0` is known. The interface problem stops at `accuracy` where it is looser
    /// than the settings' tolerance (at most `1e-3`).
    fn solve_forces(
        &mut self,
        system: &ContactSystem<'_>,
        accuracy: f64,
    ) -> Result<ContactForces, ContactSolverError> {
        let tolerance = self.settings.tolerance;
        self.settings.tolerance = tolerance.max(accuracy.min(LOOSEST_TOLERANCE));
        let stage = self.interface_stage(system);
        self.settings.tolerance = tolerance;
        let (interface, u0, start, mut work) = match stage? {
            Stage::Done(solution) => return Ok(ContactForces::of_solution(system, solution)),
            Stage::Interface {
                interface,
                u0,
                start,
                work,
            } => (interface, u0, start, work),
        };
        if !interface.converged || interface.free_mode {
            // The complete solve's error, with its report.
            return self
                .finish(system, interface, u0, start, work)
                .map(|solution| ContactForces::of_solution(system, solution));
        }
        let factors = self
            .structure
            .as_ref()
            .and_then(|s| s.factors.as_ref())
            .expect("an interface answer has factors");
        let m = system.n_constraints();
        let lambda = &interface.lambda;
        let mut values = interface.d.clone();
        if let Some(hessian_lambda) = &interface.hessian_lambda {
            for (v, hl) in values.iter_mut().zip(hessian_lambda) {
                *v -= hl;
            }
        } else {
            let h = factors.hessian.as_ref();
            for (j, &l) in lambda.iter().enumerate() {
                if l != 0.0 {
                    for (v, hij) in values.iter_mut().zip(h.col(j).iter()) {
                        *v -= hij * l;
                    }
                }
            }
        }
        for (v, g) in values.iter_mut().zip(system.gap()) {
            *v += g;
        }
        let (normal_rows, tangential_rows) = match system.friction() {
            Some(friction) => {
                let mut tangential = values.split_off(m);
                if let Some(slip) = friction.reference_slip() {
                    for (v, s) in tangential.iter_mut().zip(slip) {
                        *v += s;
                    }
                }
                (values, tangential)
            }
            None => (values, Vec::new()),
        };
        let tangential_force = if system.friction().is_some() {
            lambda[m..].to_vec()
        } else {
            vec![0.0; m]
        };
        work.times.contact_solve = start.elapsed();
        Ok(ContactForces {
            normal_force: lambda[..m].to_vec(),
            tangential_force,
            normal_rows,
            tangential_rows,
            iterations: interface.iterations,
            work,
            solution: None,
        })
    }
}
