//! The penalty solver: a semismooth Newton method with exact line search for the penalised
//! energy
//!
//! ```text
//! Pi(u) = 1/2 u'Ku - f'u + eps_N/2 sum_i ((B_N u - g)_i)_+^2 + sum_i psi_i((B_T u - s0)_i)
//! ```
//!
//! where `s0` is the reference slip of the friction term (zero from rest) and `psi_i` the
//! Huber regularisation of `b_i |s|` (quadratic `eps_T s^2 / 2` for `|eps_T s| <= b_i`, then
//! `b_i |s| - b_i^2 / (2 eps_T)`). Its minimiser gives the forces
//! `lambda_N = eps_N (B_N u - g)_+` and `lambda_T = clamp(eps_T (B_T u - s0), -b, b)`; the
//! penetration and the elastic stick slip are O(1/eps), which is the penalty error.
//!
//! In space `psi_i` is the Huber regularisation of `b_i |s|` for the node's slip vector `s`
//! of the tangent plane (`lambda_T = eps_T s` returned radially onto the disk of radius
//! `b_i`); a sliding node's two rows then get the block `b_i (I - n n') / |s|` in the Newton
//! matrix (`n = s / |s|`: the consistent tangent of the radial return, the Hessian of
//! `b_i |s|`), and the line search brackets and bisects `phi'`, which is monotone but no longer
//! piecewise linear.
//!
//! In the plane `Pi` is convex, C^1 and piecewise quadratic. Each Newton step solves with
//! `H = K + eps_N B_A'B_A + eps_T B_S'B_S` (`A`: penetrating nodes, `S`: sticking nodes) on a
//! Cholesky factorisation whose symbolic analysis is done once for the pattern of
//! `K + B_N'B_N + B_T'B_T` (and kept across solves while the pattern does not change). When
//! `H` is singular (`K` singular along a mode that only inactive or sliding rows control) the
//! step is computed with `H + delta D` instead (`D = diag(K + eps_N B_N'B_N + eps_T B_T'B_T)`,
//! `delta = 1e-10`): a direction dominated by the free mode. The first step tries the
//! minimiser of the model with every node in contact and sticking, kept if it lowers `Pi`
//! (it usually lands near the final sets). Otherwise the step length is 1 (full semismooth Newton
//! step) when it satisfies the Armijo condition, else the exact minimiser of `Pi` along the
//! Newton direction, found among the breakpoints of the piecewise-linear derivative; an
//! energy that decreases without bound along the direction is reported as rigid sliding or a
//! floating body.
//!
//! Stopping: the penetrating and sticking sets did not change over the last step and
//! `||grad Pi||_inf` is below the relative tolerance or below the round-off floor of its own
//! evaluation (`8 eps_mach || |K||u| + |f| + eps_N |B_N|'(|B_N||u| + |g|) + eps_T |B_T|'|B_T||u| ||_inf`,
//! which dominates for very large penalties).

use std::time::Instant;
use vem_space::{Options, OptionsError};

use faer::Par;

use super::error::{ContactSolverError, SettingsError};
use super::newton_matrix::{NewtonMatrix, SingularGuard, FREE_MODE_CURVATURE};
use super::report::{
    block_ranges, certify, unloaded, unloaded_solution, ForceScales, KktResiduals, KktTolerance,
    SolveReport, SolveStatus,
};
use super::system::{ContactSystem, PatternId};
use super::{ContactSolution, ContactSolver};
use crate::warning::Warning;

const NAME: &str = "penalty (semismooth Newton)";

/// How a penalty parameter is chosen; written `{ factor = .. }` or `{ value = .. }` in
/// settings tables.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum PenaltyParameter {
    /// `factor` times the constrained stiffness of the softest body
    /// ([`ContactSystem::softest_constrained_diagonal`]: for one body, the largest diagonal
    /// entry of `K` over the unknowns that appear in a constraint row; falls back to the
    /// largest diagonal entry of `K`, then to 1, if that vanishes).
    #[serde(rename = "factor")]
    RelativeToStiffness(f64),
    /// An absolute value (force per length for unit constraint rows).
    #[serde(rename = "value")]
    Absolute(f64),
}

impl PenaltyParameter {
    fn validate(&self, setting: &'static str) -> Result<(), SettingsError> {
        let (Self::RelativeToStiffness(v) | Self::Absolute(v)) = *self;
        SettingsError::positive(setting, v).map(|_| ())
    }

    /// The number given (a factor or a value).
    pub fn number(self) -> f64 {
        let (Self::RelativeToStiffness(v) | Self::Absolute(v)) = self;
        v
    }

    /// The value for a given system.
    pub fn value(&self, system: &ContactSystem<'_>) -> f64 {
        match *self {
            Self::Absolute(v) => v,
            Self::RelativeToStiffness(factor) => {
                let mut scale = system.softest_constrained_diagonal();
                if scale <= 0.0 {
                    scale = system.stiffness_diagonal().into_iter().fold(0.0, f64::max);
                }
                factor * if scale > 0.0 { scale } else { 1.0 }
            }
        }
    }
}

/// Settings of [`PenaltySolver`]; build them with [`PenaltySettings::builder`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PenaltySettings {
    normal_penalty: PenaltyParameter,
    tangential_penalty: PenaltyParameter,
    tolerance: f64,
    max_iterations: usize,
    parallelism: Par,
}

impl Default for PenaltySettings {
    /// Normal and tangential penalty `1e3 x` the largest constrained diagonal entry of `K`,
    /// relative gradient tolerance `1e-10`, at most 50 Newton steps, sequential factorisation.
    fn default() -> Self {
        Self {
            normal_penalty: PenaltyParameter::RelativeToStiffness(1e3),
            tangential_penalty: PenaltyParameter::RelativeToStiffness(1e3),
            tolerance: 1e-10,
            max_iterations: 50,
            parallelism: Par::Seq,
        }
    }
}

impl PenaltySettings {
    /// A builder starting from the defaults.
    pub fn builder() -> PenaltySettingsBuilder {
        PenaltySettingsBuilder {
            settings: Self::default(),
        }
    }

    /// Normal penalty `eps_N`.
    pub fn normal_penalty(&self) -> PenaltyParameter {
        self.normal_penalty
    }

    /// Tangential (stick) penalty `eps_T`.
    pub fn tangential_penalty(&self) -> PenaltyParameter {
        self.tangential_penalty
    }

    /// Relative tolerance on `||grad Pi||_inf` (scaled like
    /// [`KktResiduals::stationarity`]).
    pub fn tolerance(&self) -> f64 {
        self.tolerance
    }

    /// The acceptance test of an answer: relative stationarity and the signs and bounds of
    /// the forces below `max(100 tolerance, 1e-6)` (penetration and complementarity are the
    /// penalty's consistency error, reported but not bounded; see
    /// [`KktTolerance::penalty`]). A penalty so large that the gradient's round-off floor
    /// exceeds this fails the test; one whose floor is between the tolerance and this passes
    /// with a [`Warning::PenaltyRoundOff`].
    pub fn acceptance(&self) -> f64 {
        (100.0 * self.tolerance).max(1e-6)
    }

    /// The round-off floor of the gradient above which a converged answer carries a
    /// [`Warning::PenaltyRoundOff`]: `min(100 tolerance, acceptance)` (`1e-8` by default; the
    /// default penalty factor `1e3` stays well below it).
    pub fn round_off_warning(&self) -> f64 {
        (100.0 * self.tolerance).min(self.acceptance())
    }

    /// Newton iteration limit.
    pub fn max_iterations(&self) -> usize {
        self.max_iterations
    }

    /// Parallelism of the factorisation and solves.
    pub fn parallelism(&self) -> Par {
        self.parallelism
    }
}

/// Builder of [`PenaltySettings`]; values are checked by [`PenaltySettingsBuilder::build`].
#[derive(Debug, Clone, Copy)]
pub struct PenaltySettingsBuilder {
    settings: PenaltySettings,
}

impl PenaltySettingsBuilder {
    /// Normal penalty (value or factor finite and `> 0`).
    pub fn normal_penalty(mut self, value: PenaltyParameter) -> Self {
        self.settings.normal_penalty = value;
        self
    }

    /// Tangential penalty (value or factor finite and `> 0`).
    pub fn tangential_penalty(mut self, value: PenaltyParameter) -> Self {
        self.settings.tangential_penalty = value;
        self
    }

    /// Sets both penalties.
    pub fn penalty(self, value: PenaltyParameter) -> Self {
        self.normal_penalty(value).tangential_penalty(value)
    }

    /// Relative gradient tolerance, finite and `> 0`.
    pub fn tolerance(mut self, value: f64) -> Self {
        self.settings.tolerance = value;
        self
    }

    /// Newton iteration limit, `>= 1`.
    pub fn max_iterations(mut self, value: usize) -> Self {
        self.settings.max_iterations = value;
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
    pub fn build(self) -> Result<PenaltySettings, SettingsError> {
        let s = self.settings;
        s.normal_penalty.validate("normal_penalty")?;
        s.tangential_penalty.validate("tangential_penalty")?;
        SettingsError::positive("tolerance", s.tolerance)?;
        SettingsError::at_least_one("max_iterations", s.max_iterations)?;
        Ok(s)
    }
}

/// The settings a scene or a dict may give the penalty solver (registry name `"penalty"`).
#[derive(Debug, Default, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct PenaltyOptions {
    tolerance: Option<f64>,
    max_iterations: Option<usize>,
    penalty: Option<PenaltyParameter>,
    normal_penalty: Option<PenaltyParameter>,
    tangential_penalty: Option<PenaltyParameter>,
}

impl PenaltySettings {
    /// The settings of a table of options (`tolerance`, `max_iterations`, `penalty` for both
    /// penalties, or `normal_penalty` and `tangential_penalty`; each `{ factor = .. }` or
    /// `{ value = .. }`), checked.
    ///
    /// # Errors
    /// [`OptionsError`] naming the unknown or invalid setting.
    pub fn from_options(options: &Options) -> Result<Self, OptionsError> {
        let o: PenaltyOptions = options.parse()?;
        let mut b = Self::builder();
        if let Some(t) = o.tolerance {
            b = b.tolerance(t);
        }
        if let Some(m) = o.max_iterations {
            b = b.max_iterations(m);
        }
        if let Some(p) = o.penalty {
            b = b.penalty(p);
        }
        if let Some(p) = o.normal_penalty {
            b = b.normal_penalty(p);
        }
        if let Some(p) = o.tangential_penalty {
            b = b.tangential_penalty(p);
        }
        b.build().map_err(|e| {
            let mut e = OptionsError::from(e);
            if o.penalty.is_some() && e.path.ends_with("_penalty") {
                e.path = "penalty".into();
            }
            e
        })
    }
}

/// Penalty contact solver (semismooth Newton on faer sparse Cholesky). Keeps the symbolic
/// analysis from one solve to the next while the patterns of `K`, `B_N` and `B_T` do not
/// change.
#[derive(Debug, Default)]
pub struct PenaltySolver {
    settings: PenaltySettings,
    matrix: Option<NewtonMatrix>,
    /// The last answer and the structure it solved: the start of the next solve of the same
    /// structure (a Coulomb step, a load step).
    warm: Option<(PatternId, Vec<f64>)>,
}

impl PenaltySolver {
    /// A solver with the given settings.
    pub fn new(settings: PenaltySettings) -> Self {
        Self {
            settings,
            matrix: None,
            warm: None,
        }
    }

    /// The settings.
    pub fn settings(&self) -> &PenaltySettings {
        &self.settings
    }
}

/// The penalised problem at one iterate.
struct State {
    /// `B_N u - g`.
    constraint: Vec<f64>,
    /// `B_T u` (empty when frictionless).
    slip: Vec<f64>,
    normal_force: Vec<f64>,
    tangential_force: Vec<f64>,
    /// `K u`.
    ku: Vec<f64>,
    /// `grad Pi(u)`.
    gradient: Vec<f64>,
    /// Relative `||grad Pi||_inf`.
    relative_gradient: f64,
    /// Round-off floor of `||grad Pi||_inf`, relative like `relative_gradient`.
    relative_noise: f64,
    /// Penetrating nodes, then sticking nodes.
    sets: Vec<bool>,
}

struct Penalised<'a> {
    system: &'a ContactSystem<'a>,
    eps_n: f64,
    eps_t: f64,
    /// Tangential rows per node: 1 in the plane, 2 in space (a disk).
    t: usize,
}

/// The friction force `eps_T s` returned onto the disk of radius `b` (an interval in the
/// plane): `eps_T s` where it sticks, `b s / |s|` where it slips.
fn radial_return(eps_t: f64, s: &[f64], b: f64, out: &mut [f64]) {
    let norm = eps_t * s.iter().map(|x| x * x).sum::<f64>().sqrt();
    let scale = if norm <= b { eps_t } else { eps_t * b / norm };
    for (o, s) in out.iter_mut().zip(s) {
        *o = scale * s;
    }
}

/// The Huber regularisation of `b |s|` (`|s|` the Euclidean norm of a node's slip).
fn huber(eps_t: f64, s: &[f64], b: f64) -> f64 {
    let x = s.iter().map(|x| x * x).sum::<f64>().sqrt();
    if eps_t * x <= b {
        0.5 * eps_t * x * x
    } else {
        b * x - 0.5 * b * b / eps_t
    }
}

impl Penalised<'_> {
    fn bounds(&self) -> &[f64] {
        self.system.friction().map_or(&[], |f| f.bounds())
    }

    fn state(&self, u: &[f64]) -> State {
        let sys = self.system;
        let inf = super::report::inf_norm;
        let m = sys.n_constraints();
        let constraint: Vec<f64> = sys
            .normal_rows()
            .apply(u)
            .iter()
            .zip(sys.gap())
            .map(|(bu, g)| bu - g)
            .collect();
        let normal_force: Vec<f64> = constraint.iter().map(|c| self.eps_n * c.max(0.0)).collect();
        let slip = sys.friction().map_or_else(Vec::new, |f| f.slip(u));
        let tangential_force: Vec<f64> = if slip.is_empty() {
            vec![0.0; m]
        } else {
            let mut force = vec![0.0; slip.len()];
            for ((s, f), &b) in slip
                .chunks(self.t)
                .zip(force.chunks_mut(self.t))
                .zip(self.bounds())
            {
                radial_return(self.eps_t, s, b, f);
            }
            force
        };
        let ku = sys.stiffness_apply(u);
        let mut reaction = vec![0.0; u.len()];
        sys.normal_rows()
            .add_transpose_apply(&normal_force, &mut reaction);
        if let Some(f) = sys.friction() {
            f.tangential_rows()
                .add_transpose_apply(&tangential_force, &mut reaction);
        }
        let gradient: Vec<f64> = ku
            .iter()
            .zip(sys.load())
            .zip(&reaction)
            .map(|((k, f), r)| k - f + r)
            .collect();
        // Relative to each body's own force scale, as the acceptance test measures it.
        let forces = ForceScales::of(sys, u, &ku, &normal_force, &tangential_force);
        let relative_gradient = forces.stationarity;
        let magnitudes = self.magnitudes(u);
        let relative_noise = block_ranges(sys)
            .into_iter()
            .zip(&forces.blocks)
            .map(|(range, &scale)| {
                let noise = 8.0 * f64::EPSILON * inf(&magnitudes[range]);
                if scale > 0.0 {
                    noise / scale
                } else {
                    0.0
                }
            })
            .fold(0.0f64, f64::max);
        let mut sets: Vec<bool> = constraint.iter().map(|&c| c > 0.0).collect();
        for (s, b) in slip.chunks(self.t).zip(self.bounds()) {
            let norm = s.iter().map(|x| x * x).sum::<f64>().sqrt();
            sets.extend(std::iter::repeat_n(self.eps_t * norm < *b, self.t));
        }
        State {
            constraint,
            slip,
            normal_force,
            tangential_force,
            ku,
            gradient,
            relative_gradient,
            relative_noise,
            sets,
        }
    }

    /// `|K||u| + |f| + eps_N |B_N|'(|B_N||u| + |g|) + eps_T |B_T|'|B_T||u|`: the magnitudes
    /// whose round-off bounds the evaluation error of the gradient.
    fn magnitudes(&self, u: &[f64]) -> Vec<f64> {
        let sys = self.system;
        let abs_u: Vec<f64> = u.iter().map(|x| x.abs()).collect();
        let mut out: Vec<f64> = sys.load().iter().map(|f| f.abs()).collect();
        sys.stiffness_apply_with(&abs_u, &mut out, f64::abs);
        let mut add = |rows: &super::ConstraintRows, eps: f64, offset: &[f64]| {
            for r in 0..rows.nrows() {
                let (cols, vals) = rows.row(r);
                let mut row_mag: f64 = cols
                    .iter()
                    .zip(vals)
                    .map(|(&c, v)| v.abs() * abs_u[c])
                    .sum();
                row_mag += offset.get(r).map_or(0.0, |g| g.abs());
                for (&c, v) in cols.iter().zip(vals) {
                    out[c] += eps * v.abs() * row_mag;
                }
            }
        };
        add(sys.normal_rows(), self.eps_n, sys.gap());
        if let Some(f) = sys.friction() {
            add(
                f.tangential_rows(),
                self.eps_t,
                f.reference_slip().unwrap_or(&[]),
            );
        }
        out
    }
}

/// Sufficient-decrease fraction of the full Newton step.
const ARMIJO: f64 = 1e-4;

/// Result of the exact line search.
enum Step {
    /// Minimiser of `Pi` along the direction.
    Length(f64),
    /// `Pi` decreases without bound along the direction.
    Unbounded,
    /// The direction is not a descent direction.
    NoDescent,
}

/// `Pi(u + d) - Pi(u)`, evaluated term by term.
fn energy_change(p: &Penalised, state: &State, d: &[f64]) -> f64 {
    let sys = p.system;
    let kd = sys.stiffness_apply(d);
    let mut change: f64 = state
        .ku
        .iter()
        .zip(sys.load())
        .zip(d.iter().zip(&kd))
        .map(|((k, f), (x, kx))| (k - f + 0.5 * kx) * x)
        .sum();
    let e = sys.normal_rows().apply(d);
    for (c, ei) in state.constraint.iter().zip(&e) {
        change += 0.5 * p.eps_n * ((c + ei).max(0.0).powi(2) - c.max(0.0).powi(2));
    }
    if let Some(f) = sys.friction() {
        let w = f.tangential_rows().apply(d);
        let mut moved = vec![0.0; p.t];
        for ((s, wi), &b) in state.slip.chunks(p.t).zip(w.chunks(p.t)).zip(f.bounds()) {
            for k in 0..p.t {
                moved[k] = s[k] + wi[k];
            }
            change += huber(p.eps_t, &moved, b) - huber(p.eps_t, s, b);
        }
    }
    change
}

/// What the line searches along a direction `d` need: `d'Kd`, `(Ku - f)'d` (the elastic part
/// of `phi'(0)`), and the rows `B_N d` and `B_T d`.
struct Directional {
    d_k_d: f64,
    a0: f64,
    e: Vec<f64>,
    w: Vec<f64>,
}

impl Directional {
    fn along(p: &Penalised, state: &State, d: &[f64]) -> Self {
        let sys = p.system;
        let kd = sys.stiffness_apply(d);
        Self {
            d_k_d: d.iter().zip(&kd).map(|(a, b)| a * b).sum(),
            a0: state
                .ku
                .iter()
                .zip(sys.load())
                .zip(d)
                .map(|((k, f), x)| (k - f) * x)
                .sum(),
            e: sys.normal_rows().apply(d),
            w: sys
                .friction()
                .map_or_else(Vec::new, |f| f.tangential_rows().apply(d)),
        }
    }
}

/// Exact minimisation of the convex piecewise quadratic `phi(t) = Pi(u + t d)` over `t >= 0`:
/// `phi'` is piecewise linear and non-decreasing; its zero is located among the breakpoints by
/// bisection, then interpolated linearly on its piece.
fn line_search(p: &Penalised, state: &State, d: &[f64], d_diag_d: f64) -> Step {
    if p.t > 1 {
        return disk_line_search(p, state, d, d_diag_d);
    }
    let Directional { d_k_d, a0, e, w } = Directional::along(p, state, d);
    let bounds = p.bounds();
    let dphi = |t: f64| -> f64 {
        let mut v = a0 + t * d_k_d;
        for (c, ei) in state.constraint.iter().zip(&e) {
            v += p.eps_n * (c + t * ei).max(0.0) * ei;
        }
        for ((s, wi), b) in state.slip.iter().zip(&w).zip(bounds) {
            v += (p.eps_t * (s + t * wi)).clamp(-b, *b) * wi;
        }
        v
    };
    let mut breakpoints: Vec<f64> = Vec::new();
    for (c, ei) in state.constraint.iter().zip(&e) {
        if *ei != 0.0 {
            breakpoints.push(-c / ei);
        }
    }
    for ((s, wi), b) in state.slip.iter().zip(&w).zip(bounds) {
        if *wi != 0.0 && *b > 0.0 {
            breakpoints.push((b / p.eps_t - s) / wi);
            breakpoints.push((-b / p.eps_t - s) / wi);
        }
    }
    breakpoints.retain(|t| *t > 0.0 && t.is_finite());
    breakpoints.sort_by(f64::total_cmp);
    breakpoints.dedup();

    let d0 = dphi(0.0);
    if d0 >= 0.0 {
        return Step::NoDescent;
    }
    // First breakpoint where phi' >= 0.
    let k = breakpoints.partition_point(|&t| dphi(t) < 0.0);
    let exact = if k < breakpoints.len() {
        let (ta, da) = if k == 0 {
            (0.0, d0)
        } else {
            (breakpoints[k - 1], dphi(breakpoints[k - 1]))
        };
        let (tb, db) = (breakpoints[k], dphi(breakpoints[k]));
        if db > da {
            ta - da * (tb - ta) / (db - da)
        } else {
            tb
        }
    } else {
        // Beyond the last breakpoint phi' is linear with the asymptotic curvature below.
        let t_last = breakpoints.last().copied().unwrap_or(0.0);
        let d_last = dphi(t_last);
        let curvature = d_k_d
            + p.eps_n
                * e.iter()
                    .filter(|&&ei| ei > 0.0)
                    .map(|ei| ei * ei)
                    .sum::<f64>();
        if curvature <= FREE_MODE_CURVATURE * d_diag_d {
            return Step::Unbounded;
        }
        t_last - d_last / curvature
    };
    // Prefer the full Newton step when it decreases the energy enough (Armijo): it changes
    // the active sets at once, where the exact minimiser along a direction computed for the
    // old sets would admit only a few nodes per step.
    let full_step = energy_change(p, state, d);
    if full_step <= ARMIJO * d0 {
        Step::Length(1.0)
    } else {
        Step::Length(exact)
    }
}

/// The line search of [`line_search`] with friction disks (in space): `phi'` is monotone but
/// not piecewise linear (the radial return), so its zero is bracketed by doubling and found by
/// bisection; beyond the bracket's growth the curvature of the contact and elastic terms
/// decides whether the energy is unbounded along `d`.
fn disk_line_search(p: &Penalised, state: &State, d: &[f64], d_diag_d: f64) -> Step {
    let Directional { d_k_d, a0, e, w } = Directional::along(p, state, d);
    let bounds = p.bounds();
    let dphi = |t: f64| -> f64 {
        let mut v = a0 + t * d_k_d;
        for (c, ei) in state.constraint.iter().zip(&e) {
            v += p.eps_n * (c + t * ei).max(0.0) * ei;
        }
        let (mut moved, mut force) = (vec![0.0; p.t], vec![0.0; p.t]);
        for ((s, wi), &b) in state.slip.chunks(p.t).zip(w.chunks(p.t)).zip(bounds) {
            for k in 0..p.t {
                moved[k] = s[k] + t * wi[k];
            }
            radial_return(p.eps_t, &moved, b, &mut force);
            v += force.iter().zip(wi).map(|(f, w)| f * w).sum::<f64>();
        }
        v
    };
    let d0 = dphi(0.0);
    if d0 >= 0.0 {
        return Step::NoDescent;
    }
    let (mut low, mut high) = (0.0, 1.0);
    let mut bracketed = false;
    for _ in 0..64 {
        if dphi(high) >= 0.0 {
            bracketed = true;
            break;
        }
        low = high;
        high *= 2.0;
    }
    if !bracketed {
        let curvature = d_k_d
            + p.eps_n
                * e.iter()
                    .filter(|&&ei| ei > 0.0)
                    .map(|ei| ei * ei)
                    .sum::<f64>();
        if curvature <= FREE_MODE_CURVATURE * d_diag_d {
            return Step::Unbounded;
        }
        return Step::Length(high);
    }
    for _ in 0..80 {
        let mid = 0.5 * (low + high);
        if mid <= low || mid >= high {
            break;
        }
        if dphi(mid) < 0.0 {
            low = mid;
        } else {
            high = mid;
        }
    }
    let exact = 0.5 * (low + high);
    let full_step = energy_change(p, state, d);
    if full_step <= ARMIJO * d0 {
        Step::Length(1.0)
    } else {
        Step::Length(exact)
    }
}

impl ContactSolver for PenaltySolver {
    fn name(&self) -> &'static str {
        NAME
    }

    fn solve(&mut self, system: &ContactSystem<'_>) -> Result<ContactSolution, ContactSolverError> {
        let start = Instant::now();
        if unloaded(system) {
            return Ok(unloaded_solution(system, NAME, start));
        }
        let s = self.settings;
        let n = system.n_dofs();
        let m = system.n_constraints();
        let p = Penalised {
            system,
            eps_n: s.normal_penalty.value(system),
            eps_t: s.tangential_penalty.value(system),
            t: system.friction().map_or(1, |f| f.rows_per_node()),
        };
        let matrix = NewtonMatrix::reuse_or_analyse(&mut self.matrix, system, s.parallelism)
            .map_err(|detail| ContactSolverError::Backend {
                solver: NAME,
                detail,
            })?;
        let guard = SingularGuard::new(system, p.eps_n, p.eps_t);

        let warm = self
            .warm
            .take()
            .filter(|(id, u)| *id == system.pattern() && u.len() == n)
            .map(|(_, u)| u);
        let warm_started = warm.is_some();
        let mut u = warm.unwrap_or_else(|| vec![0.0; n]);
        let mut state = p.state(&u);
        let mut previous_sets: Option<Vec<bool>> = None;
        let mut iterations = 0;
        let outcome: Result<(), (SolveStatus, Option<Vec<f64>>)> = loop {
            if state.relative_gradient <= s.tolerance.max(state.relative_noise)
                && previous_sets.as_ref() == Some(&state.sets)
            {
                break Ok(());
            }
            if iterations == s.max_iterations {
                break Err((SolveStatus::MaxIterations, None));
            }
            iterations += 1;
            if iterations == 1 && !warm_started {
                // First try the model with every node in contact and sticking (where friction
                // acts): its minimiser usually lies near the final sets, where Newton steps
                // from u = 0 would cross them one layer of nodes per step. Kept only if it
                // lowers the energy.
                let all_normal = vec![p.eps_n; m];
                let all_stick: Vec<f64> = p
                    .bounds()
                    .iter()
                    .flat_map(|&b| std::iter::repeat_n(if b > 0.0 { p.eps_t } else { 0.0 }, p.t))
                    .collect();
                if let Some(false) = guard.factorise(matrix, system, &all_normal, &all_stick, &[]) {
                    // Minimiser of 1/2 v'Kv - f'v + eps_N/2 |B_N v - g|^2 + eps_T/2 |B_T v - s0|^2.
                    let mut v = system.load().to_vec();
                    let weighted_gap: Vec<f64> = system.gap().iter().map(|g| p.eps_n * g).collect();
                    system
                        .normal_rows()
                        .add_transpose_apply(&weighted_gap, &mut v);
                    if let Some(f) = system.friction() {
                        if let Some(reference) = f.reference_slip() {
                            let weighted_slip: Vec<f64> = reference
                                .iter()
                                .zip(&all_stick)
                                .map(|(s, w)| w * s)
                                .collect();
                            f.tangential_rows()
                                .add_transpose_apply(&weighted_slip, &mut v);
                        }
                    }
                    matrix.solve_in_place(&mut v);
                    let d: Vec<f64> = v.iter().zip(&u).map(|(a, b)| a - b).collect();
                    if d.iter().all(|x| x.is_finite()) && energy_change(&p, &state, &d) < 0.0 {
                        u = v;
                        let mut forced: Vec<bool> = vec![true; m];
                        forced.extend(all_stick.iter().map(|&w| w > 0.0));
                        previous_sets = Some(forced);
                        state = p.state(&u);
                        continue;
                    }
                }
            }
            let normal_weights: Vec<f64> = state.sets[..m]
                .iter()
                .map(|&a| if a { p.eps_n } else { 0.0 })
                .collect();
            let mut tangential_weights: Vec<f64> = state.sets[m..]
                .iter()
                .map(|&a| if a { p.eps_t } else { 0.0 })
                .collect();
            let mut coupling = Vec::new();
            if p.t > 1 {
                // A node sliding on its disk's rim: the consistent tangent of the radial
                // return, `b (I - n n') / |s|` (`n = s / |s|`), on its two rows: stiffness
                // across the slip, none along it. Newton's method on `Pi` then converges
                // quadratically near the answer, slip directions included; the line search
                // keeps every step a descent step.
                coupling = vec![0.0; m];
                for (((s, w), c), &b) in state
                    .slip
                    .chunks(p.t)
                    .zip(tangential_weights.chunks_mut(p.t))
                    .zip(coupling.iter_mut())
                    .zip(p.bounds())
                {
                    let norm = s[0].hypot(s[1]);
                    if p.eps_t * norm >= b && norm > 0.0 {
                        let (n0, n1) = (s[0] / norm, s[1] / norm);
                        let k = b / norm;
                        w[0] = k * n1 * n1;
                        w[1] = k * n0 * n0;
                        *c = -k * n0 * n1;
                    }
                }
            }
            let Some(shifted) = guard.factorise(
                matrix,
                system,
                &normal_weights,
                &tangential_weights,
                &coupling,
            ) else {
                // Not definite even with the shift: K has a negative eigenvalue.
                break Err((SolveStatus::NumericalFailure, None));
            };
            let mut d: Vec<f64> = state.gradient.iter().map(|g| -g).collect();
            matrix.solve_in_place(&mut d);
            if d.iter().any(|x| !x.is_finite()) {
                break Err((SolveStatus::NumericalFailure, None));
            }
            if shifted {
                if let Some(direction) = guard.free_mode(matrix, system, &d) {
                    break Err((SolveStatus::Unbounded, Some(direction)));
                }
            }
            let d_diag_d = guard.size(&d);
            match line_search(&p, &state, &d, d_diag_d) {
                Step::Length(t) => {
                    u.iter_mut().zip(&d).for_each(|(ui, di)| *ui += t * di);
                }
                Step::Unbounded => break Err((SolveStatus::Unbounded, Some(d))),
                Step::NoDescent => {
                    // Round-off floor reached (or nothing to do): accept a small gradient.
                    if state.relative_gradient <= s.tolerance.max(state.relative_noise) {
                        break Ok(());
                    }
                    break Err((SolveStatus::NumericalFailure, None));
                }
            }
            previous_sets = Some(std::mem::take(&mut state.sets));
            state = p.state(&u);
        };
        let (ln, lt) = (&state.normal_force, &state.tangential_force);
        let (status, residuals) = match &outcome {
            Ok(()) => match certify(system, &u, ln, lt, KktTolerance::penalty(s.acceptance())) {
                Ok(residuals) => (SolveStatus::Converged, residuals),
                Err(residuals) => (SolveStatus::FailedCheck, residuals),
            },
            Err((status, _)) => (*status, KktResiduals::evaluate(system, &u, ln, lt)),
        };
        let mut warnings = Vec::new();
        if status == SolveStatus::Converged && state.relative_noise > s.round_off_warning() {
            let constrained = system.softest_constrained_diagonal();
            warnings.push(Warning::PenaltyRoundOff {
                solver: NAME,
                penalty: p.eps_n,
                penalty_factor: if constrained > 0.0 {
                    p.eps_n / constrained
                } else {
                    f64::NAN
                },
                noise_floor: state.relative_noise,
                tolerance: s.tolerance,
            });
        }
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
            warnings,
        };
        match outcome {
            Ok(()) if status == SolveStatus::Converged => Ok(ContactSolution {
                displacement: {
                    self.warm = Some((system.pattern(), u.clone()));
                    u
                },
                normal_force: state.normal_force,
                tangential_force: state.tangential_force,
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
