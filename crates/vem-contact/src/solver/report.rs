//! What a solve measured: status, iterations, time and KKT residuals recomputed from the answer.

use std::ops::AddAssign;
use std::time::Duration;

use super::system::ContactSystem;

/// How a solver run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
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
        }
    }
}

/// KKT residuals of a returned `(u, lambda_N, lambda_T)`, computed independently of the solver
/// that produced it (see [`KktResiduals::evaluate`]).
///
/// Conventions (spec section 4): `(B_N u - g)_i > 0` is penetration; `lambda_N,i >= 0` is the
/// compressive nodal contact force; the tangential force satisfies
/// `lambda_T,i = b_i sign((B_T u)_i)` where node `i` slips.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct KktResiduals {
    /// `max_i (B_N u - g)_i^+`: largest penetration (a length).
    pub max_penetration: f64,
    /// `max_i (-lambda_N,i)^+`: magnitude of the most negative (tensile) normal force.
    pub negative_normal_force: f64,
    /// `max_i |lambda_N,i (B_N u - g)_i|`: normal complementarity (force x length).
    pub complementarity: f64,
    /// `||K u - f + B_N' lambda_N + B_T' lambda_T||_inf / s` with
    /// `s = max(||f||_inf, ||K u||_inf, ||B_N' lambda_N + B_T' lambda_T||_inf)` (or 1 if all
    /// vanish): relative stationarity.
    pub stationarity: f64,
    /// `max_i (|lambda_T,i| - b_i)^+`: violation of the friction bound (0 when frictionless).
    pub friction_bound_violation: f64,
    /// `max_i |b_i |(B_T u)_i| - lambda_T,i (B_T u)_i|`: friction complementarity, i.e. the
    /// failure of the tangential force to be `b_i` times the slip direction where the node
    /// slips (force x length; 0 when frictionless).
    pub slip_direction_violation: f64,
}

impl KktResiduals {
    /// Recomputes every residual from the problem and a candidate answer.
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
        let m = system.n_constraints();
        assert_eq!(normal_force.len(), m, "KktResiduals: normal force length");
        let constraint = system.normal_rows().apply(displacement);
        let mut r = Self::default();
        for i in 0..m {
            let c = constraint[i] - system.gap()[i];
            r.max_penetration = r.max_penetration.max(c);
            r.negative_normal_force = r.negative_normal_force.max(-normal_force[i]);
            r.complementarity = r.complementarity.max((normal_force[i] * c).abs());
        }
        let mut reaction = vec![0.0; system.n_dofs()];
        system
            .normal_rows()
            .add_transpose_apply(normal_force, &mut reaction);
        if let Some(friction) = system.friction() {
            assert_eq!(
                tangential_force.len(),
                m,
                "KktResiduals: tangential force length"
            );
            let slip = friction.tangential_rows().apply(displacement);
            for i in 0..m {
                let (b, lt, s) = (friction.bounds()[i], tangential_force[i], slip[i]);
                r.friction_bound_violation = r.friction_bound_violation.max(lt.abs() - b);
                r.slip_direction_violation =
                    r.slip_direction_violation.max((b * s.abs() - lt * s).abs());
            }
            friction
                .tangential_rows()
                .add_transpose_apply(tangential_force, &mut reaction);
        }
        let ku = system.stiffness_apply(displacement);
        let inf = |v: &[f64]| v.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        let scale = inf(system.load()).max(inf(&ku)).max(inf(&reaction));
        let scale = if scale > 0.0 { scale } else { 1.0 };
        let residual = ku
            .iter()
            .zip(system.load())
            .zip(&reaction)
            .fold(0.0f64, |a, ((k, f), b)| a.max((k - f + b).abs()));
        r.stationarity = residual / scale;
        r
    }

    /// The largest of all residuals except stationarity, each in its own unit: a quick
    /// "is this an answer" figure for tests and logs.
    pub fn max_violation(&self) -> f64 {
        self.max_penetration
            .max(self.negative_normal_force)
            .max(self.complementarity)
            .max(self.friction_bound_violation)
            .max(self.slip_direction_violation)
    }
}

/// What travels with every answer (and every failure): who solved, how it ended, how long it
/// took and how good the answer is.
#[derive(Debug, Clone, PartialEq)]
pub struct SolveReport {
    /// Name of the solver (`"exact (clarabel)"`, `"penalty"`, ...).
    pub solver: &'static str,
    /// How the run ended.
    pub status: SolveStatus,
    /// Iterations of the solver: interior-point iterations (exact), Newton steps (penalty) or
    /// active-set splits solved (active set).
    pub iterations: usize,
    /// What the run computed: symbolic analyses, numeric factorisations, triangular solves and
    /// their times.
    pub work: WorkCounters,
    /// Wall-clock time of the whole solve, set-up included.
    pub wall_time: Duration,
    /// KKT residuals of the returned answer.
    pub residuals: KktResiduals,
}

/// Seconds spent in each stage of a model build or a solve. A backend that does not expose a
/// stage leaves it at zero (its whole time is in [`StageTimes::contact_solve`]).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StageTimes {
    /// Interface node insertion (and the node geometry).
    pub insertion: Duration,
    /// Element matrices, scatter, loads, constraint rows.
    pub assembly: Duration,
    /// Symbolic analyses (orderings, symbolic factorisations, solver set-up).
    pub symbolic: Duration,
    /// Numeric factorisations.
    pub numeric: Duration,
    /// Triangular solves.
    pub solves: Duration,
    /// Whole contact solves (including the three stages above).
    pub contact_solve: Duration,
    /// Post-processing (full displacements, reactions, energies, interface results).
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
pub struct WorkCounters {
    /// Global assemblies of the stiffness and load (one per body and build or refill).
    pub assemblies: usize,
    /// Symbolic analyses of a sparse matrix (or set-ups of an external solver).
    pub symbolic_analyses: usize,
    /// Numeric factorisations (for the interior-point solver: one KKT factorisation per
    /// iteration plus the initial one).
    pub numeric_factorisations: usize,
    /// Forward and backward triangular solve pairs (0 where the backend does not tell).
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
