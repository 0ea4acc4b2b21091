//! The active-set solver: a primal-dual active set method (semismooth Newton on the exact KKT
//! conditions written with the complementarity functions
//!
//! ```text
//! lambda_N = max(0, lambda_N + c (B_N u - g)),   lambda_T = proj_[-b, b](lambda_T + c (B_T u - s))
//! ```
//!
//! with `s` the reference slip). From the current `(u, lambda)` the nodes are split into active
//! (`lambda_N + c(B_N u - g) > 0`: `B_N u = g`) and inactive (`lambda_N = 0`), and, with
//! friction, sticking
//! (`|lambda_T + c (B_T u - s)| <= b`: `B_T u = s`) and slipping (`lambda_T = b sign(...)`, known).
//! In space the friction bound of a node is a disk of its two tangential rows: a node sticks
//! when `|zeta| <= b` (`zeta = lambda_T + c (B_T u - s)`, a vector of the tangent plane) and
//! slips with the force `b zeta / |zeta|` (the radial return). That force is linearised at the
//! current iterate (the primal-dual active set method of Hueber, Stadler and Wohlmuth for
//! three-dimensional friction, a semismooth Newton step): with `n = zeta / |zeta|`,
//! `lambda_T = b n + W (B_T u - s)`, `W = w (I - n n')`, `w = c a / (1 - a)`, `a = b / |zeta|`
//! (capped at `c`): a slipping node is a spring across its slip direction (the tangent of its
//! circle) carrying the known force `b n`, a 2x2 block of the Newton matrix. The slip
//! directions then converge superlinearly with the split; the iteration stops when the split
//! is the same and the directions moved by less than the tolerance.
//! The equality-constrained subproblem of a split is solved exactly by an augmented
//! Lagrangian (Uzawa) iteration on the SPD matrix `K + rho B_A'B_A + rho B_S'B_S` (`+ B_L'W B_L`
//! for the slipping nodes `L` in space), factorised
//! once per split on a symbolic analysis made once for the pattern of `K + B_N'B_N + B_T'B_T`:
//! each inner step is one solve, and it contracts the constraint residual by about
//! `k / (k + rho)` with `k` the interface stiffness. The iteration stops when the split does
//! not change and the subproblem's constraints hold to the tolerance; the answer then
//! satisfies the KKT conditions exactly (no penalty error).
//!
//! Singular `K` (floating bodies held only by contact or friction) is handled as in the
//! penalty solver: a shifted factorisation and a free-mode test that reports rigid sliding or
//! an unbounded energy.

use std::time::Instant;
use vem_space::{Options, OptionsError};

use faer::Par;

use super::error::{ContactSolverError, SettingsError};
use super::newton_matrix::{NewtonMatrix, SingularGuard};
use super::report::{certify, unloaded, unloaded_solution, KktResiduals, SolveReport, SolveStatus};
use super::system::ContactSystem;
use super::{ContactSolution, ContactSolver, PenaltyParameter};

const NAME: &str = "active set (primal-dual)";

/// In space, the split is the same when the slip directions moved by at most this fraction
/// of the acceptance tolerance (the certificate then decides).
const DIRECTION_TOLERANCE: f64 = 0.1;
/// In space, the constant `c` of the friction split (`zeta = lambda_T + c (B_T u - s)`) is
/// this multiple of the constrained stiffness ([`PenaltyParameter::RelativeToStiffness`]), not
/// the augmentation: a node wrongly taken as slipping then moves back by less than the
/// bound's worth and is taken as sticking at the next split, where with `c = rho` (`1e3` times
/// the stiffness) its slip direction was measured to flip at every split (a cycle) on the
/// problems with stick and slip zones; with factors 1e-3, 1e-2 and 1e-1 of `rho` it settled in
/// 6-7, 7-8 and 8 splits on one of them and cycled on the other at 1e-1.
const TANGENTIAL_SPLIT: f64 = 1.0;

/// The tangential stiffness `w` of a slipping node in space: the linearisation of its friction
/// force `b zeta / |zeta|` (`zeta = lambda_T + c (B_T u - s)`, `|zeta| > b`) at the current
/// iterate, with `lambda_T` eliminated, is `lambda_T = b n + w (I - n n') (B_T u - s)`,
/// `w = c a / (1 - a)`, `a = b / |zeta|` (at the answer `w = b / |B_T u - s|`, the curvature of
/// `b |slip|` across the slip). Capped at `c` (a node barely past its rim is held like a
/// sticking one along the tangent of its circle).
fn slip_stiffness(c: f64, cap: f64, bound: f64, zeta_norm: f64) -> f64 {
    if zeta_norm <= bound || zeta_norm <= 0.0 {
        return 0.0;
    }
    (c * bound / (zeta_norm - bound)).min(cap)
}

/// Settings of [`ActiveSetSolver`]; build them with [`ActiveSetSettings::builder`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ActiveSetSettings {
    augmentation: PenaltyParameter,
    tolerance: f64,
    max_iterations: usize,
    max_inner_iterations: usize,
    parallelism: Par,
}

impl Default for ActiveSetSettings {
    /// Augmentation `rho = 1e3 x` the largest constrained diagonal entry of `K`, relative
    /// constraint tolerance `1e-12`, at most 50 active-set changes and 50 inner (Uzawa) steps
    /// per split, sequential factorisation.
    fn default() -> Self {
        Self {
            augmentation: PenaltyParameter::RelativeToStiffness(1e3),
            tolerance: 1e-12,
            max_iterations: 50,
            max_inner_iterations: 50,
            parallelism: Par::Seq,
        }
    }
}

impl ActiveSetSettings {
    /// A builder starting from the defaults.
    pub fn builder() -> ActiveSetSettingsBuilder {
        ActiveSetSettingsBuilder {
            settings: Self::default(),
        }
    }

    /// Augmentation `rho` of the inner Uzawa iteration (also the constant `c` of the
    /// complementarity functions).
    pub fn augmentation(&self) -> PenaltyParameter {
        self.augmentation
    }

    /// Tolerance on the subproblem constraints `B_A u = g_A`, `B_S u = s_S`, relative to
    /// `max(||u||_inf, ||g||_inf)`.
    pub fn tolerance(&self) -> f64 {
        self.tolerance
    }

    /// The acceptance test of an answer: every relative KKT residual
    /// ([`KktResiduals`](super::KktResiduals)) below `max(100 tolerance, 1e-9)`.
    pub fn acceptance(&self) -> f64 {
        (100.0 * self.tolerance).max(1e-9)
    }

    /// Limit on the number of splits (outer iterations).
    pub fn max_iterations(&self) -> usize {
        self.max_iterations
    }

    /// Limit on the Uzawa steps per split.
    pub fn max_inner_iterations(&self) -> usize {
        self.max_inner_iterations
    }

    /// Parallelism of the factorisation and solves.
    pub fn parallelism(&self) -> Par {
        self.parallelism
    }
}

/// Builder of [`ActiveSetSettings`]; values are checked by
/// [`ActiveSetSettingsBuilder::build`].
#[derive(Debug, Clone, Copy)]
pub struct ActiveSetSettingsBuilder {
    settings: ActiveSetSettings,
}

impl ActiveSetSettingsBuilder {
    /// Augmentation `rho` (value or factor finite and `> 0`).
    pub fn augmentation(mut self, value: PenaltyParameter) -> Self {
        self.settings.augmentation = value;
        self
    }

    /// Relative constraint tolerance, finite and `> 0`.
    pub fn tolerance(mut self, value: f64) -> Self {
        self.settings.tolerance = value;
        self
    }

    /// Limit on the number of splits, `>= 1`.
    pub fn max_iterations(mut self, value: usize) -> Self {
        self.settings.max_iterations = value;
        self
    }

    /// Limit on the Uzawa steps per split, `>= 1`.
    pub fn max_inner_iterations(mut self, value: usize) -> Self {
        self.settings.max_inner_iterations = value;
        self
    }

    /// Parallelism of the factorisation and solves (default [`Par::Seq`]).
    pub fn parallelism(mut self, value: Par) -> Self {
        self.settings.parallelism = value;
        self
    }

    /// Validates the settings.
    ///
    /// # Errors
    /// [`SettingsError`] naming the first invalid setting.
    pub fn build(self) -> Result<ActiveSetSettings, SettingsError> {
        let s = self.settings;
        let (PenaltyParameter::RelativeToStiffness(rho) | PenaltyParameter::Absolute(rho)) =
            s.augmentation;
        SettingsError::positive("augmentation", rho)?;
        SettingsError::positive("tolerance", s.tolerance)?;
        SettingsError::at_least_one("max_iterations", s.max_iterations)?;
        SettingsError::at_least_one("max_inner_iterations", s.max_inner_iterations)?;
        Ok(s)
    }
}

/// The settings a scene or a dict may give the active-set solver (registry name `"active-set"`).
#[derive(Debug, Default, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct ActiveSetOptions {
    tolerance: Option<f64>,
    max_iterations: Option<usize>,
    max_inner_iterations: Option<usize>,
    augmentation: Option<PenaltyParameter>,
}

impl ActiveSetSettings {
    /// The settings of a table of options (`tolerance`, `max_iterations`,
    /// `max_inner_iterations`, `augmentation = { factor = .. }` or `{ value = .. }`), checked.
    ///
    /// # Errors
    /// [`OptionsError`] naming the unknown or invalid setting.
    pub fn from_options(options: &Options) -> Result<Self, OptionsError> {
        let o: ActiveSetOptions = options.parse()?;
        let mut b = Self::builder();
        if let Some(t) = o.tolerance {
            b = b.tolerance(t);
        }
        if let Some(m) = o.max_iterations {
            b = b.max_iterations(m);
        }
        if let Some(m) = o.max_inner_iterations {
            b = b.max_inner_iterations(m);
        }
        if let Some(a) = o.augmentation {
            b = b.augmentation(a);
        }
        b.build().map_err(OptionsError::from)
    }
}

/// Primal-dual active set contact solver on faer sparse Cholesky (exact KKT answer). Keeps
/// the symbolic analysis from one solve to the next while the patterns do not change.
#[derive(Debug, Default)]
pub struct ActiveSetSolver {
    settings: ActiveSetSettings,
    matrix: Option<NewtonMatrix>,
}

impl ActiveSetSolver {
    /// A solver with the given settings.
    pub fn new(settings: ActiveSetSettings) -> Self {
        Self {
            settings,
            matrix: None,
        }
    }

    /// The settings.
    pub fn settings(&self) -> &ActiveSetSettings {
        &self.settings
    }
}

/// A split of the interface nodes.
#[derive(Debug, Clone, PartialEq)]
struct Split {
    /// Normal constraint active (`B_N u = g`).
    active: Vec<bool>,
    /// Tangential state: `0` stick (`B_T u = s`, the reference slip), `+1`/`-1` slip with
    /// that sign; empty when frictionless.
    slip: Vec<i8>,
}

impl Split {
    /// The split of `(u, lambda)` and, in space, the unit slip direction `zeta / |zeta|` of
    /// every slipping node (two entries per node, zeros where it sticks) and `|zeta|` of every
    /// node (both empty in the plane).
    fn of(
        system: &ContactSystem<'_>,
        c: f64,
        c_t: f64,
        u: &[f64],
        ln: &[f64],
        lt: &[f64],
    ) -> (Self, Vec<f64>, Vec<f64>) {
        if let Some(f) = system.friction().filter(|f| f.rows_per_node() == 2) {
            let (split, _) = Self::of_plane(system, c, u, ln, &[]);
            let slip = f.slip(u);
            let mut directions = vec![0.0; slip.len()];
            let mut norms = vec![0.0; f.bounds().len()];
            let states = f
                .bounds()
                .iter()
                .enumerate()
                .map(|(i, &b)| {
                    let zeta = [
                        lt[2 * i] + c_t * slip[2 * i],
                        lt[2 * i + 1] + c_t * slip[2 * i + 1],
                    ];
                    let norm = zeta[0].hypot(zeta[1]);
                    norms[i] = norm;
                    if b > 0.0 && norm <= b {
                        0
                    } else {
                        if norm > 0.0 {
                            directions[2 * i] = zeta[0] / norm;
                            directions[2 * i + 1] = zeta[1] / norm;
                        }
                        1
                    }
                })
                .collect();
            return (
                Self {
                    active: split.active,
                    slip: states,
                },
                directions,
                norms,
            );
        }
        let (split, directions) = Self::of_plane(system, c, u, ln, lt);
        (split, directions, Vec::new())
    }

    /// The split with one tangential row per node (or none).
    fn of_plane(
        system: &ContactSystem<'_>,
        c: f64,
        u: &[f64],
        ln: &[f64],
        lt: &[f64],
    ) -> (Self, Vec<f64>) {
        let bn = system.normal_rows().apply(u);
        let active = bn
            .iter()
            .zip(system.gap())
            .zip(ln)
            .map(|((b, g), l)| l + c * (b - g) > 0.0)
            .collect();
        let slip = system
            .friction()
            .filter(|_| !lt.is_empty())
            .map_or_else(Vec::new, |f| {
                f.slip(u)
                    .iter()
                    .zip(lt)
                    .zip(f.bounds())
                    .map(|((s, l), &b)| {
                        let zeta = l + c * s;
                        if b > 0.0 && zeta.abs() <= b {
                            0
                        } else if zeta >= 0.0 {
                            1
                        } else {
                            -1
                        }
                    })
                    .collect()
            });
        (Self { active, slip }, Vec::new())
    }
}

impl ContactSolver for ActiveSetSolver {
    fn name(&self) -> &'static str {
        NAME
    }

    fn solve(&mut self, system: &ContactSystem<'_>) -> Result<ContactSolution, ContactSolverError> {
        let start = Instant::now();
        if unloaded(system) {
            return Ok(unloaded_solution(system, NAME, start));
        }
        let s = self.settings;
        let (n, m) = (system.n_dofs(), system.n_constraints());
        let t = system.friction().map_or(1, |f| f.rows_per_node());
        let rho = s.augmentation.value(system);
        // In space, the constant of the friction split: the constrained stiffness itself.
        let c_t = PenaltyParameter::RelativeToStiffness(TANGENTIAL_SPLIT).value(system);
        let matrix = NewtonMatrix::reuse_or_analyse(&mut self.matrix, system, s.parallelism)
            .map_err(|detail| ContactSolverError::Backend {
                solver: NAME,
                detail,
            })?;
        let guard = SingularGuard::new(system, rho, rho);
        let bounds = system.friction().map_or(&[][..], |f| f.bounds());
        let gap_inf = system.gap().iter().fold(0.0f64, |a, g| a.max(g.abs()));

        let mut u = vec![0.0; n];
        let mut ln = vec![0.0; m];
        let mut lt = vec![0.0; system.n_tangential()];
        let mut previous: Option<(Split, Vec<f64>)> = None;
        let mut inner_converged = false;
        let mut iterations = 0;
        let outcome: Result<(), (SolveStatus, Option<Vec<f64>>)> = 'outer: loop {
            let (split, directions, zeta_norms) = Split::of(system, rho, c_t, &u, &ln, &lt);
            if inner_converged {
                if let Some((last, last_directions)) = &previous {
                    // In space the slip directions of a split are continuous: the split is
                    // the same when they moved by less than the tolerance.
                    let moved = directions
                        .iter()
                        .zip(last_directions)
                        .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
                    if *last == split && moved <= DIRECTION_TOLERANCE * s.acceptance() {
                        break Ok(());
                    }
                }
            }
            if iterations == s.max_iterations {
                break Err((SolveStatus::MaxIterations, None));
            }
            iterations += 1;
            let wn: Vec<f64> = split
                .active
                .iter()
                .map(|&a| if a { rho } else { 0.0 })
                .collect();
            // One weight per tangential row (a node's state for each of its rows).
            let mut wt: Vec<f64> = split
                .slip
                .iter()
                .flat_map(|&state| std::iter::repeat_n(if state == 0 { rho } else { 0.0 }, t))
                .collect();
            // In space, a slipping node's block `W_i = w_i tau tau'` (the linearised radial
            // return) and the coupling of its two rows (empty in the plane).
            let mut coupling = Vec::new();
            if t > 1 {
                coupling = vec![0.0; m];
                for (i, &state) in split.slip.iter().enumerate() {
                    if state != 0 {
                        let w = slip_stiffness(c_t, rho, bounds[i], zeta_norms[i]);
                        let tau = [-directions[2 * i + 1], directions[2 * i]];
                        wt[2 * i] = w * tau[0] * tau[0];
                        wt[2 * i + 1] = w * tau[1] * tau[1];
                        coupling[i] = w * tau[0] * tau[1];
                    }
                }
            }
            let Some(shifted) = guard.factorise(matrix, system, &wn, &wt, &coupling) else {
                break Err((SolveStatus::NumericalFailure, None));
            };
            // Known multipliers of the split.
            for (i, &a) in split.active.iter().enumerate() {
                if !a {
                    ln[i] = 0.0;
                }
            }
            // The constant part of the friction force of a slipping node: the bound along
            // the sign (plane) or along the direction of `zeta` (space).
            let mut known = vec![0.0; lt.len()];
            for (i, &state) in split.slip.iter().enumerate() {
                if state != 0 {
                    if t == 1 {
                        known[i] = f64::from(state) * bounds[i];
                        lt[i] = known[i];
                    } else {
                        for k in 0..t {
                            known[t * i + k] = bounds[i] * directions[t * i + k];
                            lt[t * i + k] = known[t * i + k];
                        }
                    }
                }
            }
            inner_converged = false;
            for inner in 0..s.max_inner_iterations {
                // (K + rho B_A'B_A + rho B_S'B_S + B_L'W B_L) u
                //     = f - B_N'lambda_N - B_T'lambda_T + rho B_A' g_A + rho B_S's + B_L'(W s - b n)
                // (A active, S sticking, L slipping in space).
                let mut rhs = system.load().to_vec();
                let shifted_force: Vec<f64> = ln
                    .iter()
                    .zip(&wn)
                    .zip(system.gap())
                    .map(|((l, w), g)| -l + w * g)
                    .collect();
                system
                    .normal_rows()
                    .add_transpose_apply(&shifted_force, &mut rhs);
                if let Some(f) = system.friction() {
                    // Stick rows hold B_T u = s (the reference slip): + rho B_S' s; slipping
                    // rows carry the known force and, in space, W s.
                    let reference = f.reference_or_zero();
                    let mut shifted_friction: Vec<f64> = lt
                        .iter()
                        .zip(&wt)
                        .zip(reference.iter())
                        .map(|((l, w), s)| -l + w * s)
                        .collect();
                    if t > 1 {
                        for (i, &state) in split.slip.iter().enumerate() {
                            if state != 0 {
                                let (r0, r1) = (reference[2 * i], reference[2 * i + 1]);
                                shifted_friction[2 * i] =
                                    -known[2 * i] + wt[2 * i] * r0 + coupling[i] * r1;
                                shifted_friction[2 * i + 1] =
                                    -known[2 * i + 1] + coupling[i] * r0 + wt[2 * i + 1] * r1;
                            }
                        }
                    }
                    f.tangential_rows()
                        .add_transpose_apply(&shifted_friction, &mut rhs);
                }
                matrix.solve_in_place(&mut rhs);
                u = rhs;
                if shifted && inner == 0 {
                    if let Some(direction) = guard.free_mode(matrix, system, &u) {
                        break 'outer Err((SolveStatus::Unbounded, Some(direction)));
                    }
                }
                // Uzawa update of the unknown multipliers; residual of the split's equalities.
                let mut residual = 0.0f64;
                let bn = system.normal_rows().apply(&u);
                for i in 0..m {
                    if split.active[i] {
                        let r = bn[i] - system.gap()[i];
                        ln[i] += rho * r;
                        residual = residual.max(r.abs());
                    }
                }
                if let Some(f) = system.friction() {
                    let bt = f.slip(&u);
                    for (r, bt) in bt.iter().enumerate() {
                        if split.slip[r / t] == 0 {
                            lt[r] += rho * bt;
                            residual = residual.max(bt.abs());
                        }
                    }
                    if t > 1 {
                        // The linearised radial return: b n + W (B_T u - s).
                        for (i, &state) in split.slip.iter().enumerate() {
                            if state != 0 {
                                let (s0, s1) = (bt[2 * i], bt[2 * i + 1]);
                                lt[2 * i] = known[2 * i] + wt[2 * i] * s0 + coupling[i] * s1;
                                lt[2 * i + 1] =
                                    known[2 * i + 1] + coupling[i] * s0 + wt[2 * i + 1] * s1;
                            }
                        }
                    }
                }
                let scale = u.iter().fold(gap_inf, |a, x| a.max(x.abs()));
                if residual <= s.tolerance * if scale > 0.0 { scale } else { 1.0 } {
                    inner_converged = true;
                    break;
                }
                if shifted {
                    // The subproblem of a singular split has no solution: move on.
                    break;
                }
            }
            previous = Some((split, directions));
        };
        let (status, residuals) = match &outcome {
            Ok(()) => match certify(system, &u, &ln, &lt, s.acceptance()) {
                Ok(residuals) => (SolveStatus::Converged, residuals),
                Err(residuals) => (SolveStatus::FailedCheck, residuals),
            },
            Err((status, _)) => (*status, KktResiduals::evaluate(system, &u, &ln, &lt)),
        };
        let report = SolveReport {
            solver: NAME,
            status,
            iterations,
            work: {
                let mut work = matrix.take_work();
                work.times.contact_solve = start.elapsed();
                work
            },
            wall_time: start.elapsed(),
            residuals,
            warnings: Vec::new(),
        };
        match outcome {
            Ok(()) if status == SolveStatus::Converged => Ok(ContactSolution {
                displacement: u,
                normal_force: ln,
                tangential_force: lt,
                report,
            }),
            Err((_, Some(direction))) => Err(ContactSolverError::from_free_mode(
                system,
                &direction,
                Box::new(report),
            )),
            _ => Err(ContactSolverError::NotConverged {
                report: Box::new(report),
            }),
        }
    }
}
