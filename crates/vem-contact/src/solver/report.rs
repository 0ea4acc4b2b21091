//! What a solve measured: status, iterations, time and KKT residuals recomputed from the answer.

use std::ops::AddAssign;
use std::time::Duration;

use super::system::ContactSystem;
use crate::warning::Warning;

/// How a solver run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
#[non_exhaustive]
pub enum SolveStatus {
    /// Converged to the requested tolerances.
    Converged,
    /// The backend stopped with reduced accuracy (Clarabel's `AlmostSolved`).
    ReducedAccuracy,
    /// The iteration limit was reached.
    MaxIterations,
    /// The constraints `B_N u <= g` admit no displacement.
    Infeasible,
    /// The energy is unbounded below (rigid sliding or a floating body).
    Unbounded,
    /// The backend failed numerically (lack of progress, factorisation failure, ...).
    NumericalFailure,
    /// The solver stopped on its own criteria, but its answer failed the KKT acceptance test
    /// (the residuals in the report exceed the solver's tolerance).
    FailedCheck,
}

impl SolveStatus {
    /// A few words for messages ("iteration limit reached", ...).
    pub fn describe(self) -> &'static str {
        match self {
            SolveStatus::Converged => "converged",
            SolveStatus::ReducedAccuracy => "reduced accuracy",
            SolveStatus::MaxIterations => "iteration limit reached",
            SolveStatus::Infeasible => "infeasible constraints",
            SolveStatus::Unbounded => "unbounded energy",
            SolveStatus::NumericalFailure => "numerical failure",
            SolveStatus::FailedCheck => "answer failed the KKT check",
        }
    }
}

/// The scales in which [`KktResiduals`] are measured, taken from the problem and the answer
/// (so that the residuals do not change with the units of lengths, forces or moduli).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct KktScales {
    /// Force scale `F = max_b F_b` over the stiffness blocks (bodies) `b`, with
    /// `F_b = max(||f_b||_inf, ||(K u)_b||_inf, ||(B_N' lambda_N + B_T' lambda_T)_b||_inf)`.
    /// Zero only for an unloaded problem with a zero answer.
    pub force: f64,
    /// Displacement scale `U = max(||u||_inf, ||g||_inf, ||s||_inf, ||f||_inf / k)` (`s` the
    /// reference slip of [`Friction`](super::Friction)) with `k` the largest
    /// diagonal entry of `K` (the last term keeps `U` a scale of the problem when the answer
    /// and the gaps vanish).
    pub displacement: f64,
}

/// KKT residuals of a returned `(u, lambda_N, lambda_T)`, computed independently of the solver
/// that produced it (see [`KktResiduals::evaluate`]), every one relative to the problem's own
/// scales ([`KktScales`]): unit free, invariant under a change of the units of lengths, forces
/// and moduli.
///
/// Conventions (spec section 4): `(B_N u - g)_i > 0` is penetration; `lambda_N,i >= 0` is the
/// compressive nodal contact force; the tangential force satisfies
/// `lambda_T,i = b_i sign((B_T u - s0)_i)` where node `i` slips (`s0` the reference slip; in
/// space `b_i` times the unit slip vector of the tangent plane).
///
/// The force scale of interface node `i`, `F_i`, is the smallest `F_b` of the bodies its rows
/// touch: a contact force must be accurate relative to the forces of the softer (or less
/// loaded) body, not only to those of a stiff body whose Dirichlet lifting dominates the load.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct KktResiduals {
    /// The scales the figures below are relative to.
    pub scales: KktScales,
    /// `max_i (B_N u - g)_i^+ / U`: largest penetration.
    pub max_penetration: f64,
    /// `max_i (-lambda_N,i)^+ / F_i`: most negative (tensile) normal force.
    pub negative_normal_force: f64,
    /// `max_i |lambda_N,i| |(g - B_N u)_i| / (F_i U)`: normal complementarity.
    pub complementarity: f64,
    /// `max_b ||(K u - f + B_N' lambda_N + B_T' lambda_T)_b||_inf / F_b`: stationarity of
    /// every body relative to its own force scale.
    pub stationarity: f64,
    /// The round-off floor of [`KktResiduals::stationarity`]:
    /// `max_b 8 eps ||(|K||u| + |f| + |B_N'||lambda_N| + |B_T'||lambda_T|)_b||_inf / F_b`, and
    /// for a body that carries constraint rows at least `8 eps max_b F_b / F_b` (the forces it
    /// receives through the interface are known to round-off of the largest force scale). A
    /// body with a large rigid displacement (held only by a soft body), or one touching at zero
    /// load, cannot be checked below it; the acceptance test takes the larger of its tolerance
    /// and this floor.
    pub stationarity_floor: f64,
    /// `max_i (|lambda_T,i| - b_i)^+ / F_i`: violation of the friction bound (0 when
    /// frictionless; in space `|.|` is the Euclidean norm of the nodal friction force in the
    /// tangent plane, and the bound a disk).
    pub friction_bound_violation: f64,
    /// `max_i |b_i s_i - |s_i| lambda_T,i| / (F_i U)` over the nodes that slip (vectors of
    /// the tangent plane in space: the force must be `b_i` times the unit slip direction,
    /// which also asks `|lambda_T,i| = b_i`),
    /// `|s_i| = |(B_T u)_i - s0_i| > t U` (`s0` the reference slip; `t`: the acceptance
    /// tolerance, `1e-10` for [`KktResiduals::evaluate`]): the failure of the tangential
    /// force to be `b_i` times the slip direction (0 when frictionless). Slips below `t U`
    /// count as stick.
    pub slip_direction_violation: f64,
}

/// Slips below this fraction of the displacement scale count as stick in
/// [`KktResiduals::evaluate`].
const DEFAULT_SLIP_FLOOR: f64 = 1e-10;

/// `x / s`, with `0 / 0 = 0` (a residual that vanishes with its scale).
fn relative(x: f64, s: f64) -> f64 {
    if x == 0.0 {
        0.0
    } else if s > 0.0 {
        x / s
    } else {
        f64::INFINITY
    }
}

/// `max_i |v_i|`.
pub(crate) fn inf_norm(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |a, x| a.max(x.abs()))
}

/// Per-body force scales `F_b` and the stationarity residual `r = K u - f + B' lambda`.
pub(crate) struct ForceScales {
    /// `F_b` for every stiffness block.
    pub(crate) blocks: Vec<f64>,
    /// `F_i` for every interface node (smallest `F_b` of the blocks its rows touch).
    pub(crate) rows: Vec<f64>,
    /// `max_b ||r_b||_inf / F_b`.
    pub(crate) stationarity: f64,
    /// Round-off floor of `stationarity` (see [`KktResiduals::stationarity_floor`]).
    pub(crate) stationarity_floor: f64,
}

impl ForceScales {
    /// Force scales of the answer `(u, lambda_N, lambda_T)` given `K u`.
    pub(crate) fn of(
        system: &ContactSystem<'_>,
        displacement: &[f64],
        ku: &[f64],
        normal_force: &[f64],
        tangential_force: &[f64],
    ) -> Self {
        let abs_u: Vec<f64> = displacement.iter().map(|x| x.abs()).collect();
        let mut stiffness_magnitude = vec![0.0; system.n_dofs()];
        system.stiffness_apply_with(&abs_u, &mut stiffness_magnitude, f64::abs);
        Self::from_products(
            system,
            ku,
            stiffness_magnitude,
            normal_force,
            tangential_force,
        )
    }

    /// [`ForceScales::of`] with `K u` computed here, in the same pass over `K` as `|K||u|`;
    /// returns `K u` too.
    pub(crate) fn of_answer(
        system: &ContactSystem<'_>,
        displacement: &[f64],
        normal_force: &[f64],
        tangential_force: &[f64],
    ) -> (Self, Vec<f64>) {
        let (ku, magnitude) = system.stiffness_apply_and_magnitude(displacement);
        let scales = Self::from_products(system, &ku, magnitude, normal_force, tangential_force);
        (scales, ku)
    }

    /// The scales from `K u` and `|K||u|` (`stiffness_magnitude`).
    fn from_products(
        system: &ContactSystem<'_>,
        ku: &[f64],
        stiffness_magnitude: Vec<f64>,
        normal_force: &[f64],
        tangential_force: &[f64],
    ) -> Self {
        let mut reaction = vec![0.0; system.n_dofs()];
        system
            .normal_rows()
            .add_transpose_apply(normal_force, &mut reaction);
        if let Some(friction) = system.friction() {
            friction
                .tangential_rows()
                .add_transpose_apply(tangential_force, &mut reaction);
        }
        let load = system.load();
        // |K||u| + |f| + |B'||lambda|: what the evaluation of r rounds.
        let mut magnitude = stiffness_magnitude;
        for (m, f) in magnitude.iter_mut().zip(load) {
            *m += f.abs();
        }
        let mut add_abs = |rows: &super::ConstraintRows, y: &[f64]| {
            for (i, &yi) in y.iter().enumerate() {
                let (cols, vals) = rows.row(i);
                for (&c, v) in cols.iter().zip(vals) {
                    magnitude[c] += (v * yi).abs();
                }
            }
        };
        add_abs(system.normal_rows(), normal_force);
        if let Some(friction) = system.friction() {
            add_abs(friction.tangential_rows(), tangential_force);
        }
        let ranges = block_ranges(system);
        let mut blocks = Vec::with_capacity(ranges.len());
        let mut stationarity = 0.0f64;
        let mut floors = Vec::with_capacity(ranges.len());
        for range in &ranges {
            let r = range.clone();
            let scale = inf_norm(&load[r.clone()])
                .max(inf_norm(&ku[r.clone()]))
                .max(inf_norm(&reaction[r.clone()]));
            let residual = r.fold(0.0f64, |a, j| a.max((ku[j] - load[j] + reaction[j]).abs()));
            stationarity = stationarity.max(relative(residual, scale));
            floors.push(8.0 * f64::EPSILON * inf_norm(&magnitude[range.clone()]));
            blocks.push(scale);
        }
        let global = blocks.iter().fold(0.0f64, |a, &b| a.max(b));
        let block_of = |col: usize| ranges.iter().position(|r| r.contains(&col));
        // The forces a block receives through constraint rows are computed with the whole
        // problem, to round-off of its largest force scale: a block that carries constraint
        // rows cannot be checked below 8 eps F / F_b (e.g. a body touching at zero load, whose
        // only forces are the round-off of the other body's).
        let mut coupled = vec![false; ranges.len()];
        let mut mark = |rows_b: &super::ConstraintRows| {
            for i in 0..rows_b.nrows() {
                for &c in rows_b.row(i).0 {
                    if let Some(b) = block_of(c) {
                        coupled[b] = true;
                    }
                }
            }
        };
        mark(system.normal_rows());
        if let Some(friction) = system.friction() {
            mark(friction.tangential_rows());
        }
        let stationarity_floor = floors.iter().zip(&blocks).zip(&coupled).fold(
            0.0f64,
            |a, ((&floor, &scale), &coupled)| {
                let floor = if coupled {
                    floor.max(8.0 * f64::EPSILON * global)
                } else {
                    floor
                };
                a.max(relative(floor, scale))
            },
        );
        let m = system.n_constraints();
        let mut rows = vec![f64::INFINITY; m];
        // Row `i` of `rows_b` belongs to node `i / per_node`.
        let mut touch = |rows_b: &super::ConstraintRows, per_node: usize| {
            for i in 0..rows_b.nrows() {
                let row_scale = &mut rows[i / per_node];
                for &c in rows_b.row(i).0 {
                    if let Some(b) = block_of(c) {
                        *row_scale = row_scale.min(blocks[b]);
                    }
                }
            }
        };
        touch(system.normal_rows(), 1);
        if let Some(friction) = system.friction() {
            touch(friction.tangential_rows(), friction.rows_per_node());
        }
        for row_scale in &mut rows {
            if !row_scale.is_finite() {
                *row_scale = global;
            }
        }
        Self {
            blocks,
            rows,
            stationarity,
            stationarity_floor,
        }
    }

    /// `F = max_b F_b`.
    pub(crate) fn global(&self) -> f64 {
        self.blocks.iter().fold(0.0f64, |a, &b| a.max(b))
    }
}

/// The unknowns of every stiffness block.
pub(crate) fn block_ranges(system: &ContactSystem<'_>) -> Vec<std::ops::Range<usize>> {
    system
        .stiffness_blocks()
        .iter()
        .map(|b| b.offset()..b.offset() + b.matrix().ncols())
        .collect()
}

impl KktResiduals {
    /// Recomputes every residual from the problem and a candidate answer, in the problem's
    /// own scales (see the field docs); slips below `1e-10 U` count as stick.
    ///
    /// For a frictionless system `tangential_force` is ignored (it should be all zeros).
    ///
    /// # Panics
    /// If the lengths do not match the system (`u`: `n`, forces: `m`).
    pub fn evaluate(
        system: &ContactSystem,
        displacement: &[f64],
        normal_force: &[f64],
        tangential_force: &[f64],
    ) -> Self {
        Self::evaluate_with_floor(
            system,
            displacement,
            normal_force,
            tangential_force,
            DEFAULT_SLIP_FLOOR,
        )
    }

    fn evaluate_with_floor(
        system: &ContactSystem,
        displacement: &[f64],
        normal_force: &[f64],
        tangential_force: &[f64],
        slip_floor: f64,
    ) -> Self {
        let m = system.n_constraints();
        assert_eq!(normal_force.len(), m, "KktResiduals: normal force length");
        if system.friction().is_some() {
            assert_eq!(
                tangential_force.len(),
                system.n_tangential(),
                "KktResiduals: tangential force length"
            );
        }
        let zeros;
        let tangential_force = if system.friction().is_some() {
            tangential_force
        } else {
            zeros = vec![0.0; m];
            &zeros
        };
        let (forces, _) =
            ForceScales::of_answer(system, displacement, normal_force, tangential_force);
        let k_max = system
            .stiffness_diagonal()
            .into_iter()
            .fold(0.0f64, f64::max);
        let load_displacement = if k_max > 0.0 {
            inf_norm(system.load()) / k_max
        } else {
            0.0
        };
        let reference_slip = system
            .friction()
            .and_then(|f| f.reference_slip())
            .map_or(0.0, inf_norm);
        let u_scale = inf_norm(displacement)
            .max(inf_norm(system.gap()))
            .max(reference_slip)
            .max(load_displacement);
        let constraint = system.normal_rows().apply(displacement);
        let mut r = Self {
            scales: KktScales {
                force: forces.global(),
                displacement: u_scale,
            },
            stationarity: forces.stationarity,
            stationarity_floor: forces.stationarity_floor,
            ..Self::default()
        };
        for i in 0..m {
            let c = constraint[i] - system.gap()[i];
            let f_i = forces.rows[i];
            r.max_penetration = r.max_penetration.max(relative(c.max(0.0), u_scale));
            r.negative_normal_force = r
                .negative_normal_force
                .max(relative((-normal_force[i]).max(0.0), f_i));
            r.complementarity = r
                .complementarity
                .max(relative((normal_force[i] * c).abs(), f_i * u_scale));
        }
        if let Some(friction) = system.friction() {
            let slip = friction.slip(displacement);
            let t = friction.rows_per_node();
            let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
            for i in 0..m {
                let rows = t * i..t * (i + 1);
                let (b, lt, s) = (
                    friction.bounds()[i],
                    &tangential_force[rows.clone()],
                    &slip[rows],
                );
                let f_i = forces.rows[i];
                r.friction_bound_violation = r
                    .friction_bound_violation
                    .max(relative((norm(lt) - b).max(0.0), f_i));
                let s_norm = norm(s);
                if s_norm > slip_floor * u_scale {
                    // |b s - |s| lambda_T|: zero exactly when lambda_T = b s / |s|.
                    let direction: Vec<f64> =
                        s.iter().zip(lt).map(|(s, l)| b * s - s_norm * l).collect();
                    r.slip_direction_violation = r
                        .slip_direction_violation
                        .max(relative(norm(&direction), f_i * u_scale));
                }
            }
        }
        r
    }

    /// The largest of all residuals except stationarity: a quick "is this an answer" figure
    /// for tests and logs (unit free, like every residual).
    pub fn max_violation(&self) -> f64 {
        self.max_penetration
            .max(self.negative_normal_force)
            .max(self.complementarity)
            .max(self.friction_bound_violation)
            .max(self.slip_direction_violation)
    }

    /// Whether every residual passes `tolerance` (see [`KktTolerance`]); stationarity passes
    /// at its round-off floor too.
    pub fn passes(&self, tolerance: &KktTolerance) -> bool {
        self.stationarity <= tolerance.stationarity.max(self.stationarity_floor)
            && self.max_penetration <= tolerance.feasibility
            && self.negative_normal_force <= tolerance.sign
            && self.complementarity <= tolerance.complementarity
            && self.friction_bound_violation <= tolerance.sign
            && self.slip_direction_violation <= tolerance.complementarity
    }
}

/// What a solver's answer must satisfy to be reported as converged: a bound on each relative
/// [`KktResiduals`] figure. A number converts into the same bound on every figure.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KktTolerance {
    /// Bound on [`KktResiduals::stationarity`].
    pub stationarity: f64,
    /// Bound on [`KktResiduals::max_penetration`].
    pub feasibility: f64,
    /// Bound on [`KktResiduals::negative_normal_force`] and
    /// [`KktResiduals::friction_bound_violation`] (the signs and bounds of the forces).
    pub sign: f64,
    /// Bound on [`KktResiduals::complementarity`] and
    /// [`KktResiduals::slip_direction_violation`]; also the slip below which (relative to
    /// `U`) a node counts as stick.
    pub complementarity: f64,
}

impl From<f64> for KktTolerance {
    fn from(t: f64) -> Self {
        Self {
            stationarity: t,
            feasibility: t,
            sign: t,
            complementarity: t,
        }
    }
}

impl KktTolerance {
    /// What a penalty method guarantees: stationarity and the signs and bounds of its forces to
    /// `t`; penetration and complementarity are its consistency error (`O(1 / penalty)`),
    /// reported but not bounded.
    pub fn penalty(t: f64) -> Self {
        Self {
            stationarity: t,
            feasibility: f64::INFINITY,
            sign: t,
            complementarity: f64::INFINITY,
        }
    }
}

/// The acceptance test every solver runs on its answer before reporting
/// [`SolveStatus::Converged`]: the KKT residuals recomputed from `(u, lambda_N, lambda_T)` in
/// the problem's own scales, checked against `tolerance` (a number bounds every figure; see
/// [`KktTolerance`]). `Ok(residuals)` when they pass, `Err(residuals)` otherwise: the solver
/// then returns [`ContactSolverError::NotConverged`](super::ContactSolverError::NotConverged)
/// with status [`SolveStatus::FailedCheck`] and these residuals in its report.
pub(crate) fn certify(
    system: &ContactSystem<'_>,
    displacement: &[f64],
    normal_force: &[f64],
    tangential_force: &[f64],
    tolerance: impl Into<KktTolerance>,
) -> Result<KktResiduals, KktResiduals> {
    let tolerance = tolerance.into();
    let residuals = KktResiduals::evaluate_with_floor(
        system,
        displacement,
        normal_force,
        tangential_force,
        tolerance.complementarity.min(DEFAULT_SLIP_FLOOR.sqrt()),
    );
    if residuals.passes(&tolerance) {
        Ok(residuals)
    } else {
        Err(residuals)
    }
}

/// True when the answer is exactly `u = 0, lambda = 0`: no load and no gap closed by the
/// prescribed displacements (`f = 0`, `g >= 0`) and no reference slip. Then `u = 0` minimises the (non-negative)
/// energy and every solver returns it without iterating, so a zero load gives exactly zero
/// contact forces.
pub(crate) fn unloaded(system: &ContactSystem<'_>) -> bool {
    system.load().iter().all(|&f| f == 0.0)
        && system.gap().iter().all(|&g| g >= 0.0)
        && system
            .friction()
            .is_none_or(|f| f.reference_slip().is_none())
}

/// The answer of an [`unloaded`] system with its report.
pub(crate) fn unloaded_solution(
    system: &ContactSystem<'_>,
    solver: &'static str,
    start: std::time::Instant,
) -> super::ContactSolution {
    let (n, m) = (system.n_dofs(), system.n_constraints());
    let displacement = vec![0.0; n];
    let normal_force = vec![0.0; m];
    let tangential_force = vec![0.0; system.n_tangential()];
    let residuals = KktResiduals::evaluate(system, &displacement, &normal_force, &tangential_force);
    super::ContactSolution {
        displacement,
        normal_force,
        tangential_force,
        report: SolveReport {
            solver,
            status: SolveStatus::Converged,
            iterations: 0,
            work: WorkCounters::default(),
            wall_time: start.elapsed(),
            residuals,
            warnings: Vec::new(),
        },
    }
}

/// What travels with every answer (and every failure): who solved, how it ended, how long it
/// took and how good the answer is.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct SolveReport {
    /// Name of the solver (`"exact (clarabel)"`, `"penalty"`, ...).
    pub solver: &'static str,
    /// How the run ended.
    pub status: SolveStatus,
    /// Iterations of the solver: projected Newton steps of the interface problem, summed over
    /// proximal steps (condensed), interior-point iterations (exact), Newton steps (penalty) or
    /// active-set splits solved (active set).
    pub iterations: usize,
    /// What the run computed: symbolic analyses, numeric factorisations, triangular solves and
    /// their times.
    pub work: WorkCounters,
    /// Wall-clock time of the whole solve, set-up included.
    #[cfg_attr(feature = "serde", serde(serialize_with = "crate::seconds"))]
    pub wall_time: Duration,
    /// KKT residuals of the returned answer.
    pub residuals: KktResiduals,
    /// What the answer's user should know although the solve converged (a penalty in its
    /// round-off regime, ...).
    pub warnings: Vec<Warning>,
}

/// Seconds spent in each stage of a model build or a solve. A backend that does not expose a
/// stage leaves it at zero (its whole time is in [`StageTimes::contact_solve`]).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct StageTimes {
    /// Interface node insertion (and the node geometry).
    #[cfg_attr(
        feature = "serde",
        serde(
            serialize_with = "crate::seconds",
            deserialize_with = "crate::from_seconds"
        )
    )]
    pub insertion: Duration,
    /// Element matrices, scatter, loads, constraint rows.
    #[cfg_attr(
        feature = "serde",
        serde(
            serialize_with = "crate::seconds",
            deserialize_with = "crate::from_seconds"
        )
    )]
    pub assembly: Duration,
    /// Symbolic analyses (orderings, symbolic factorisations, solver set-up).
    #[cfg_attr(
        feature = "serde",
        serde(
            serialize_with = "crate::seconds",
            deserialize_with = "crate::from_seconds"
        )
    )]
    pub symbolic: Duration,
    /// Numeric factorisations.
    #[cfg_attr(
        feature = "serde",
        serde(
            serialize_with = "crate::seconds",
            deserialize_with = "crate::from_seconds"
        )
    )]
    pub numeric: Duration,
    /// Triangular solves.
    #[cfg_attr(
        feature = "serde",
        serde(
            serialize_with = "crate::seconds",
            deserialize_with = "crate::from_seconds"
        )
    )]
    pub solves: Duration,
    /// Whole contact solves (including the three stages above).
    #[cfg_attr(
        feature = "serde",
        serde(
            serialize_with = "crate::seconds",
            deserialize_with = "crate::from_seconds"
        )
    )]
    pub contact_solve: Duration,
    /// Post-processing (full displacements, reactions, energies, interface results).
    #[cfg_attr(
        feature = "serde",
        serde(
            serialize_with = "crate::seconds",
            deserialize_with = "crate::from_seconds"
        )
    )]
    pub post: Duration,
}

impl AddAssign for StageTimes {
    fn add_assign(&mut self, other: Self) {
        self.insertion += other.insertion;
        self.assembly += other.assembly;
        self.symbolic += other.symbolic;
        self.numeric += other.numeric;
        self.solves += other.solves;
        self.contact_solve += other.contact_solve;
        self.post += other.post;
    }
}

/// What a build or a solve computed, counted where it happens and carried with every result
/// (the CLI's `summary.json` and the xtask reports print these figures).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct WorkCounters {
    /// Global assemblies of the stiffness and load (one per body and build or refill).
    pub assemblies: usize,
    /// Symbolic analyses of a sparse matrix (or set-ups of an external solver).
    pub symbolic_analyses: usize,
    /// Numeric factorisations (for the interior-point solver: one KKT factorisation per
    /// iteration plus the initial one).
    pub numeric_factorisations: usize,
    /// Forward and backward triangular solve pairs (a block of right-hand sides solved at once
    /// counts once; 0 where the backend does not tell).
    pub triangular_solves: usize,
    /// The time of each stage.
    pub times: StageTimes,
}

impl AddAssign for WorkCounters {
    fn add_assign(&mut self, other: Self) {
        self.assemblies += other.assemblies;
        self.symbolic_analyses += other.symbolic_analyses;
        self.numeric_factorisations += other.numeric_factorisations;
        self.triangular_solves += other.triangular_solves;
        self.times += other.times;
    }
}

#[cfg(test)]
mod tests {
    use std::borrow::Cow;

    use faer::sparse::{SparseColMat, Triplet};

    use super::*;
    use crate::solver::system::borrowed_block;
    use crate::solver::{ConstraintRows, PatternId};

    fn spring() -> SparseColMat<usize, f64> {
        SparseColMat::<usize, f64>::try_new_from_triplets(1, 1, &[Triplet::new(0, 0, 1.0)])
            .expect("valid triplets")
    }

    /// Two springs, the first loaded by 1 and touching the second (gap 1) at zero force: the
    /// second's only forces are round-off of the first's (1e-19). Its stationarity relative to
    /// its own scale is 0.1, but it is below the floor of the coupled problem, 8 eps.
    #[test]
    fn a_body_touching_at_zero_load_is_checked_to_the_round_off_of_the_coupled_problem() {
        let k = spring();
        let rows = ConstraintRows::try_from_triplets(1, 2, &[(0, 0, 1.0), (0, 1, -1.0)])
            .expect("valid rows");
        let system = ContactSystem::try_from_parts(
            PatternId::fresh(),
            0,
            vec![borrowed_block(0, &k), borrowed_block(1, &k)],
            Cow::Owned(vec![1.0, 0.0]),
            Cow::Owned(rows),
            Cow::Owned(vec![1.0]),
            None,
        )
        .expect("a valid system");
        let r = KktResiduals::evaluate(&system, &[1.0, 1e-19], &[0.9e-19], &[]);
        assert!((r.stationarity - 0.1).abs() < 1e-6, "{r:?}");
        assert!(r.stationarity_floor > r.stationarity, "{r:?}");
        // Without the constraint row coupling them the second body is checked on its own.
        let rows = ConstraintRows::try_from_triplets(1, 2, &[(0, 0, 1.0)]).expect("valid rows");
        let system = ContactSystem::try_from_parts(
            PatternId::fresh(),
            0,
            vec![borrowed_block(0, &k), borrowed_block(1, &k)],
            Cow::Owned(vec![1.0, 0.9e-19]),
            Cow::Owned(rows),
            Cow::Owned(vec![2.0]),
            None,
        )
        .expect("a valid system");
        let r = KktResiduals::evaluate(&system, &[1.0, 1e-19], &[0.0], &[]);
        assert!((r.stationarity - 0.1).abs() < 1e-6, "{r:?}");
        assert!(r.stationarity_floor < 1e-10, "{r:?}");
    }
}
