//! The exact solver: the contact problem as a convex QP solved by Clarabel (interior point).
//!
//! Frictionless (P1^h): `min 1/2 u'Ku - f'u` s.t. `B_N u + s = g, s >= 0`.
//!
//! Tresca (P2^h with nodal quadrature): the variables are `(u, t)` with epigraph variables
//! `t_i >= |(B_T u - s)_i|` (`s` the reference slip, zero from rest) written as the two linear
//! inequalities `B_T u - t <= s` and `-B_T u - t <= -s` (no cone in 2D); the objective gains `sum_i b_i t_i`. With multipliers
//! `z = (lambda_N, z_+, z_-)` the stationarity in `t` gives `z_+ + z_- = b`, so
//! `lambda_T = z_+ - z_-` satisfies `|lambda_T| <= b` and has the sign of the slip.

use std::time::Instant;
use vem_space::{Options, OptionsError};

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettingsBuilder, DefaultSolver, IPSolver, NonnegativeConeT, SecondOrderConeT,
    SolverStatus,
};

use super::error::{ContactSolverError, SettingsError};
use super::report::{
    certify, unloaded, unloaded_solution, KktResiduals, KktTolerance, SolveReport, SolveStatus,
    StageTimes, WorkCounters,
};
use super::system::{ContactSystem, PatternId};
use super::{ContactSolution, ContactSolver};

const NAME: &str = "exact (clarabel)";

/// Settings of [`ExactSolver`]; build them with [`ExactSettings::builder`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExactSettings {
    eps_abs: f64,
    eps_rel: f64,
    max_iterations: usize,
    accept_reduced_accuracy: bool,
}

impl Default for ExactSettings {
    /// `eps_abs = eps_rel = 1e-10`, `max_iterations = 100`, reduced accuracy rejected.
    fn default() -> Self {
        Self {
            eps_abs: 1e-10,
            eps_rel: 1e-10,
            max_iterations: 100,
            accept_reduced_accuracy: false,
        }
    }
}

impl ExactSettings {
    /// A builder starting from the defaults.
    pub fn builder() -> ExactSettingsBuilder {
        ExactSettingsBuilder {
            settings: Self::default(),
        }
    }

    /// Absolute duality-gap tolerance (Clarabel `tol_gap_abs`).
    pub fn eps_abs(&self) -> f64 {
        self.eps_abs
    }

    /// Relative duality-gap and feasibility tolerance (Clarabel `tol_gap_rel`, `tol_feas`).
    pub fn eps_rel(&self) -> f64 {
        self.eps_rel
    }

    /// Interior-point iteration limit.
    pub fn max_iterations(&self) -> usize {
        self.max_iterations
    }

    /// Whether Clarabel's `AlmostSolved` (reduced accuracy) is returned as an answer (it must
    /// still pass the acceptance test).
    pub fn accept_reduced_accuracy(&self) -> bool {
        self.accept_reduced_accuracy
    }

    /// The acceptance test of an answer: stationarity, penetration and the signs and bounds
    /// of the forces below `t = max(100 max(eps_abs, eps_rel), 1e-8)` (`1e-8` by default), the
    /// normal and friction complementarity below `max(t, 1e-2 force accuracy)` (`1e-6` by
    /// default: the interior point stops at a barrier parameter of about its tolerance, and a
    /// weakly active node then has a force and a gap each only accurate to its square root).
    pub fn acceptance(&self) -> KktTolerance {
        let t = (100.0 * self.eps_abs.max(self.eps_rel)).max(1e-8);
        let force_accuracy = 10.0 * self.eps_abs.max(self.eps_rel).sqrt();
        KktTolerance {
            complementarity: t.max(1e-2 * force_accuracy),
            ..KktTolerance::from(t)
        }
    }
}

/// Builder of [`ExactSettings`]; values are checked by [`ExactSettingsBuilder::build`].
#[derive(Debug, Clone, Copy)]
pub struct ExactSettingsBuilder {
    settings: ExactSettings,
}

impl ExactSettingsBuilder {
    /// Absolute duality-gap tolerance, finite and `> 0`.
    pub fn eps_abs(mut self, value: f64) -> Self {
        self.settings.eps_abs = value;
        self
    }

    /// Relative gap and feasibility tolerance, finite and `> 0`.
    pub fn eps_rel(mut self, value: f64) -> Self {
        self.settings.eps_rel = value;
        self
    }

    /// Iteration limit, `>= 1`.
    pub fn max_iterations(mut self, value: usize) -> Self {
        self.settings.max_iterations = value;
        self
    }

    /// Accept Clarabel's reduced-accuracy answers instead of reporting
    /// [`ContactSolverError::NotConverged`].
    pub fn accept_reduced_accuracy(mut self, value: bool) -> Self {
        self.settings.accept_reduced_accuracy = value;
        self
    }

    /// Validates the settings.
    ///
    /// # Errors
    /// [`SettingsError`] naming the first invalid setting.
    pub fn build(self) -> Result<ExactSettings, SettingsError> {
        let s = self.settings;
        SettingsError::positive("eps_abs", s.eps_abs)?;
        SettingsError::positive("eps_rel", s.eps_rel)?;
        SettingsError::at_least_one("max_iterations", s.max_iterations)?;
        if u32::try_from(s.max_iterations).is_err() {
            return Err(SettingsError {
                setting: "max_iterations",
                value: s.max_iterations as f64,
                requirement: "<= u32::MAX",
            });
        }
        Ok(s)
    }
}

/// The settings a scene or a dict may give the exact solver (registry name `"exact"`).
#[derive(Debug, Default, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct ExactOptions {
    tolerance: Option<f64>,
    eps_abs: Option<f64>,
    eps_rel: Option<f64>,
    max_iterations: Option<usize>,
    accept_reduced_accuracy: Option<bool>,
}

impl ExactSettings {
    /// The settings of a table of options (`tolerance` for both `eps_abs` and `eps_rel`, or
    /// each; `max_iterations`, `accept_reduced_accuracy`), checked.
    ///
    /// # Errors
    /// [`OptionsError`] naming the unknown or invalid setting.
    pub fn from_options(options: &Options) -> Result<Self, OptionsError> {
        let o: ExactOptions = options.parse()?;
        let mut b = Self::builder();
        if let Some(t) = o.tolerance {
            b = b.eps_abs(t).eps_rel(t);
        }
        if let Some(t) = o.eps_abs {
            b = b.eps_abs(t);
        }
        if let Some(t) = o.eps_rel {
            b = b.eps_rel(t);
        }
        if let Some(m) = o.max_iterations {
            b = b.max_iterations(m);
        }
        if let Some(a) = o.accept_reduced_accuracy {
            b = b.accept_reduced_accuracy(a);
        }
        b.build().map_err(|e| {
            let mut e = OptionsError::from(e);
            if o.tolerance.is_some() && e.path.starts_with("eps_") {
                e.path = "tolerance".into();
            }
            e
        })
    }
}

/// Exact contact solver: the QP of [`ContactSystem`] solved by Clarabel's interior-point
/// method (default `qdldl` backend). Multipliers are the nodal contact forces.
///
/// Detects an unbounded energy from Clarabel's dual-infeasibility certificate `d` and reports
/// it as [`ContactSolverError::RigidSliding`] (when friction acts along `d`) or
/// [`ContactSolverError::Unbounded`]. A free mode with no load along it is not an error here:
/// one of the minimisers is returned.
#[derive(Default)]
pub struct ExactSolver {
    settings: ExactSettings,
    kept: Option<Kept>,
}

/// Clarabel's solver kept for the next solve of the same structure: its data are updated in
/// place (`update_P`, `update_q`, `update_b`) and its symbolic factorisation reused.
struct Kept {
    pattern: PatternId,
    has_friction: bool,
    stiffness_version: u64,
    solver: DefaultSolver<f64>,
}

impl std::fmt::Debug for ExactSolver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ExactSolver")
            .field("settings", &self.settings)
            .field("kept", &self.kept.as_ref().map(|k| k.pattern))
            .finish()
    }
}

impl Clone for ExactSolver {
    /// The settings only (the kept Clarabel workspace is not cloned).
    fn clone(&self) -> Self {
        Self::new(self.settings)
    }
}

impl ExactSolver {
    /// A solver with the given settings.
    pub fn new(settings: ExactSettings) -> Self {
        Self {
            settings,
            kept: None,
        }
    }

    /// The settings.
    pub fn settings(&self) -> &ExactSettings {
        &self.settings
    }
}

/// The units in which the QP is handed to Clarabel: a stiffness `k` (largest constrained
/// diagonal entry of `K`), a length `L = max(||g||_inf, ||s||_inf, ||f||_inf / k)` (`s` the
/// reference slip) and the force `k L`.
/// Clarabel normalises its residuals and duality gap by `max(1, .)`, so on data far from 1 its
/// relative tolerances become absolute; in these units the data are of order 1 and the answer
/// does not depend on the units of the problem.
#[derive(Debug, Clone, Copy)]
struct Units {
    stiffness: f64,
    length: f64,
}

impl Units {
    fn of(system: &ContactSystem<'_>) -> Self {
        let mut stiffness = system.max_constrained_diagonal();
        if stiffness <= 0.0 {
            stiffness = system.stiffness_diagonal().into_iter().fold(0.0, f64::max);
        }
        if stiffness <= 0.0 {
            stiffness = 1.0;
        }
        let inf = super::report::inf_norm;
        let reference_slip = system
            .friction()
            .and_then(|f| f.reference_slip())
            .map_or(0.0, inf);
        let length = inf(system.gap())
            .max(reference_slip)
            .max(inf(system.load()) / stiffness);
        Self {
            stiffness,
            length: if length > 0.0 { length } else { 1.0 },
        }
    }

    fn force(&self) -> f64 {
        self.stiffness * self.length
    }
}

/// The largest friction bound handed to Clarabel, in force units `k L` (see [`build_qp`]).
const FRICTION_BOUND_CAP: f64 = 1e4;

/// The QP data in Clarabel's form.
struct QpData {
    p: CscMatrix<f64>,
    q: Vec<f64>,
    a: CscMatrix<f64>,
    b: Vec<f64>,
    /// The cones of the rows of `a`, in order.
    cones: Vec<clarabel::solver::SupportedConeT<f64>>,
}

/// The QP in the [`Units`] `units`: `P = K / k`, `q = -f / (k L)` (and `b / (k L)` for the
/// friction variables), `b = g / L`; its solution is `u / L` and `lambda / (k L)`.
///
/// Friction: one variable `t_i >= |(B_T u)_i - s_i|` per node with the cost `b_i t_i` (the
/// epigraph of the friction term). In the plane it is two linear rows per node
/// (`+-(B_T u - s)_i - t_i <= 0`, nonnegative cone), the friction force the difference of their
/// multipliers; in space one second-order cone `(t_i, (B_T u)_i - s_i)` of dimension 3 per node,
/// the friction force minus the tangential part of its multiplier (whose first entry is `b_i`).
fn build_qp(system: &ContactSystem<'_>, units: Units) -> QpData {
    let (k, length, force) = (units.stiffness, units.length, units.force());
    let n = system.n_dofs();
    let m = system.n_constraints();
    let friction = system.friction();
    let n_t = friction.map_or(0, |f| f.n_nodes());
    let n_var = n + n_t;

    // P: upper triangle of K, columns sorted, duplicates summed; the t block is zero.
    let mut upper: Vec<(usize, usize, f64)> = system
        .stiffness_entries()
        .filter(|&(i, j, _)| i <= j)
        .map(|(i, j, v)| (i, j, v / k))
        .collect();
    upper.sort_by_key(|&(i, j, _)| (j, i));
    let mut colptr = vec![0usize; n_var + 1];
    let mut rowval: Vec<usize> = Vec::with_capacity(upper.len());
    let mut nzval: Vec<f64> = Vec::with_capacity(upper.len());
    let mut last: Option<(usize, usize)> = None;
    for (i, j, v) in upper {
        if last == Some((i, j)) {
            if let Some(value) = nzval.last_mut() {
                *value += v;
            }
        } else {
            rowval.push(i);
            nzval.push(v);
            colptr[j + 1] += 1;
            last = Some((i, j));
        }
    }
    for j in 0..n_var {
        colptr[j + 1] += colptr[j];
    }
    let p = CscMatrix::new(n_var, n_var, colptr, rowval, nzval);

    let mut q: Vec<f64> = system.load().iter().map(|f| -f / force).collect();
    let (mut ai, mut aj, mut av) = (Vec::new(), Vec::new(), Vec::new());
    let normal = system.normal_rows();
    for i in 0..m {
        let (cols, vals) = normal.row(i);
        for (&c, &v) in cols.iter().zip(vals) {
            ai.push(i);
            aj.push(c);
            av.push(v);
        }
    }
    let mut b: Vec<f64> = system.gap().iter().map(|g| g / length).collect();
    let mut cones = Vec::new();
    if m > 0 {
        cones.push(NonnegativeConeT(m));
    }
    if let Some(fr) = friction.filter(|f| f.rows_per_node() > 1) {
        // The disk: s = (t_i, (B_T u)_i - s_i) = b - A x in the second-order cone, with the
        // rows (-t_i; -(B_T u)_i) of A and (0; -s_i) of b.
        q.extend(
            fr.bounds()
                .iter()
                .map(|b| (b / force).min(FRICTION_BOUND_CAP)),
        );
        let t = fr.rows_per_node();
        let tangential = fr.tangential_rows();
        let reference = fr.reference_or_zero();
        for i in 0..m {
            let first = b.len();
            ai.push(first);
            aj.push(n + i);
            av.push(-1.0);
            b.push(0.0);
            for k in 0..t {
                let row = t * i + k;
                let (cols, vals) = tangential.row(row);
                for (&c, &v) in cols.iter().zip(vals) {
                    ai.push(first + 1 + k);
                    aj.push(c);
                    av.push(-v);
                }
                b.push(-reference[row] / length);
            }
            cones.push(SecondOrderConeT(t + 1));
        }
    } else if let Some(fr) = friction {
        // A bound beyond FRICTION_BOUND_CAP force units is never reached by a force of the
        // problem (the interface is effectively tied there): capping it keeps the interior
        // point's data of order 1. The acceptance test checks the answer against the true
        // bounds, so a capped bound that is reached makes the solve fail, not lie.
        q.extend(
            fr.bounds()
                .iter()
                .map(|b| (b / force).min(FRICTION_BOUND_CAP)),
        );
        let tangential = fr.tangential_rows();
        for i in 0..m {
            let (cols, vals) = tangential.row(i);
            for (&c, &v) in cols.iter().zip(vals) {
                // B_T u - t <= s (rows m..2m) and -B_T u - t <= -s (rows 2m..3m).
                ai.extend([m + i, 2 * m + i]);
                aj.extend([c, c]);
                av.extend([v, -v]);
            }
            ai.extend([m + i, 2 * m + i]);
            aj.extend([n + i, n + i]);
            av.extend([-1.0, -1.0]);
        }
        // The reference slip s: B_T u - t <= s and -B_T u - t <= -s.
        match fr.reference_slip() {
            Some(slip) => {
                b.extend(slip.iter().map(|s| s / length));
                b.extend(slip.iter().map(|s| -s / length));
            }
            None => b.extend(std::iter::repeat_n(0.0, 2 * m)),
        }
        cones = if m > 0 {
            vec![NonnegativeConeT(3 * m)]
        } else {
            vec![]
        };
    }
    let a = CscMatrix::new_from_triplets(b.len(), n_var, ai, aj, av);
    QpData { p, q, a, b, cones }
}

impl ContactSolver for ExactSolver {
    fn name(&self) -> &'static str {
        NAME
    }

    /// `10 sqrt(max(eps_abs, eps_rel))`: the interior point stops at a barrier parameter of about
    /// the gap tolerance, and the multiplier of a weakly active constraint (a node at the
    /// contact or stick/slip boundary) is then only accurate to `O(sqrt(mu))` (`1e-4` with the
    /// default settings).
    fn force_accuracy(&self) -> f64 {
        10.0 * self.settings.eps_abs.max(self.settings.eps_rel).sqrt()
    }

    fn solve(&mut self, system: &ContactSystem<'_>) -> Result<ContactSolution, ContactSolverError> {
        let start = Instant::now();
        if unloaded(system) {
            return Ok(unloaded_solution(system, NAME, start));
        }
        let n = system.n_dofs();
        let m = system.n_constraints();
        let units = Units::of(system);
        let qp = build_qp(system, units);
        let s = &self.settings;
        let backend = |detail: String| ContactSolverError::Backend {
            solver: NAME,
            detail,
        };
        let mut work = WorkCounters::default();
        let reusable = self.kept.as_ref().is_some_and(|k| {
            k.pattern == system.pattern() && k.has_friction == system.friction().is_some()
        });
        if reusable {
            let kept = self.kept.as_mut().expect("checked above");
            let updated = (if kept.stiffness_version != system.stiffness_version() {
                kept.solver.update_P(&qp.p.nzval)
            } else {
                Ok(())
            })
            .and_then(|()| kept.solver.update_q(&qp.q))
            .and_then(|()| kept.solver.update_b(&qp.b));
            if let Err(e) = updated {
                return Err(backend(format!("data update: {e}")));
            }
            kept.stiffness_version = system.stiffness_version();
        } else {
            let settings = DefaultSettingsBuilder::default()
                .verbose(false)
                .max_iter(s.max_iterations as u32)
                .tol_gap_abs(s.eps_abs)
                .tol_gap_rel(s.eps_rel)
                .tol_feas(s.eps_rel)
                .presolve_enable(false)
                .input_sparse_dropzeros(false)
                .build()
                .map_err(|e| backend(e.to_string()))?;
            let symbolic_start = Instant::now();
            let solver = DefaultSolver::new(&qp.p, &qp.q, &qp.a, &qp.b, &qp.cones, settings)
                .map_err(|e| backend(e.to_string()))?;
            work.symbolic_analyses = 1;
            work.times.symbolic = symbolic_start.elapsed();
            self.kept = Some(Kept {
                pattern: system.pattern(),
                has_friction: system.friction().is_some(),
                stiffness_version: system.stiffness_version(),
                solver,
            });
        }
        let solver = &mut self.kept.as_mut().expect("set above").solver;
        solver.solve();
        let sol = &solver.solution;

        let (length, force) = (units.length, units.force());
        let displacement: Vec<f64> = sol.x[..n].iter().map(|x| length * x).collect();
        let normal_force: Vec<f64> = sol.z[..m].iter().map(|z| force * z).collect();
        let tangential_force = match system.friction() {
            // The multiplier of cone i is (b_i, -lambda_T,i) in force units.
            Some(friction) if friction.rows_per_node() > 1 => {
                let t = friction.rows_per_node();
                (0..m)
                    .flat_map(|i| {
                        let first = m + (t + 1) * i + 1;
                        sol.z[first..first + t].iter().map(|z| -force * z)
                    })
                    .collect()
            }
            Some(_) => (0..m)
                .map(|i| force * (sol.z[m + i] - sol.z[2 * m + i]))
                .collect(),
            None => vec![0.0; m],
        };
        let status = match sol.status {
            SolverStatus::Solved => SolveStatus::Converged,
            SolverStatus::AlmostSolved => SolveStatus::ReducedAccuracy,
            SolverStatus::PrimalInfeasible | SolverStatus::AlmostPrimalInfeasible => {
                SolveStatus::Infeasible
            }
            SolverStatus::DualInfeasible | SolverStatus::AlmostDualInfeasible => {
                SolveStatus::Unbounded
            }
            SolverStatus::MaxIterations | SolverStatus::MaxTime => SolveStatus::MaxIterations,
            _ => SolveStatus::NumericalFailure,
        };
        let answered = status == SolveStatus::Converged
            || (status == SolveStatus::ReducedAccuracy && s.accept_reduced_accuracy);
        let (status, residuals) = if answered {
            match certify(
                system,
                &displacement,
                &normal_force,
                &tangential_force,
                s.acceptance(),
            ) {
                Ok(residuals) => (status, residuals),
                Err(residuals) => (SolveStatus::FailedCheck, residuals),
            }
        } else {
            let residuals =
                KktResiduals::evaluate(system, &displacement, &normal_force, &tangential_force);
            (status, residuals)
        };
        let report = Box::new(SolveReport {
            solver: NAME,
            status,
            iterations: sol.iterations as usize,
            work: WorkCounters {
                numeric_factorisations: sol.iterations as usize + 1,
                times: StageTimes {
                    contact_solve: start.elapsed(),
                    ..work.times
                },
                ..work
            },
            wall_time: start.elapsed(),
            residuals,
            warnings: Vec::new(),
        });
        match status {
            SolveStatus::Converged => {}
            SolveStatus::ReducedAccuracy if answered => {}
            SolveStatus::Infeasible => return Err(ContactSolverError::Infeasible { report }),
            SolveStatus::Unbounded => {
                return Err(ContactSolverError::from_free_mode(
                    system,
                    &sol.x[..n],
                    report,
                ))
            }
            _ => return Err(ContactSolverError::NotConverged { report }),
        }
        Ok(ContactSolution {
            displacement,
            normal_force,
            tangential_force,
            report: *report,
        })
    }
}
