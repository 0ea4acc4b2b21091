//! Load histories: the loads of a contact problem as functions of a pseudo-time, solved step
//! by step on one discretisation.
//!
//! Every datum of a body that loads it is a **load condition** ([`LoadCondition`]): its body
//! force, each Dirichlet condition (a prescribed displacement, or the resultant of a rigid
//! plate, [`vem_elastic::Dirichlet::rigid_plate`]) and each traction. A load history gives each
//! condition a factor at every step: the condition's data (as the body was built) times the
//! factor. The data are linear in the factors, so a step costs no assembly: the load vector
//! `f(t) = sum_c s_c(t) f_c` and the gaps `g(t) = h0 - sum_c s_c(t) [u_D,c]_nu` are refilled
//! from per-condition parts computed once ([`LoadPath::new`]).
//!
//! * [`LoadCurve`]: the factor `s(t)` of one condition, piecewise linear through given points
//!   `(t_k, s_k)`, constant before the first and after the last;
//! * [`LoadCurves`]: a curve per condition and a default curve for the others (the ramp
//!   `s(t) = t` up to `t = 1`, then 1, by default);
//! * [`LoadFactors`]: the factors of one step (one per condition, a default for the others);
//! * [`LoadHistory`]: the steps (pseudo-time and factors), from curves evaluated at given
//!   times ([`LoadHistory::from_curves`]) or from explicit factors
//!   ([`LoadHistory::from_steps`]);
//! * [`LoadPath`]: the state of the problem along a history (the displacement and forces at
//!   the end of the last step), advanced one step at a time ([`LoadPath::advance`]) or through
//!   a whole history ([`LoadPath::run`],
//!   [`ContactDiscretisation::solve_history`](crate::ContactDiscretisation::solve_history)).
//!
//! **Friction is incremental along a history.** A step from the state `u_n` to `u_n+1` solves
//!
//! ```text
//! min 1/2 u'Ku - f(t_n+1)'u + sum_i b_i |(B_T u)_i - (B_T u_n)_i|   s.t.  B_N u <= g(t_n+1)
//! ```
//!
//! the friction functional on the increment of the tangential jump since the last step (the
//! reference slip of [`Friction`](crate::Friction)); Coulomb's bounds `b_i = F lambda_N,i`
//! come from the normal forces of the same step, by the fixed point of Tresca problems of
//! [`Coulomb`](crate::Coulomb), started from the bounds of the previous step. The first step
//! starts from rest (`u_0 = 0`): a one-step history is the static problem
//! ([`ContactDiscretisation::solve`](crate::ContactDiscretisation::solve)). Frictionless
//! contact has no memory: every step of a frictionless history is the static problem at its
//! loads. Each step keeps every factorisation, the interface operator of the condensed solver
//! and its multipliers (a warm start): it costs the interface work and one back substitution.
//!
//! # Mapping a problem description onto a history
//!
//! A scene that names its conditions maps them in the order it hands them to the body
//! builders: the `k`-th [`ElasticBodyBuilder::dirichlet`](vem_elastic::ElasticBodyBuilder::dirichlet)
//! call of body `b` (rigid plates included) is `LoadCondition::Dirichlet { body: b, index: k }`,
//! the `k`-th traction is `LoadCondition::Traction { body: b, index: k }`, and the body force is
//! `LoadCondition::BodyForce { body: b }` ([`ContactDiscretisation::load_conditions`] lists
//! them with their parts). A curve per condition, the times of the steps and the default
//! curve are all a history needs:
//!
//! ```
//! use std::sync::Arc;
//! use vem_contact::{
//!     CondensedSolver, ContactProblem, LoadCondition, LoadCurve, LoadCurves, LoadHistory,
//!     Tresca,
//! };
//! use vem_elastic::{Component, Dirichlet, ElasticBody, Material, Plane};
//! use vem_mesh::generators::{structured_quads, Rectangle};
//! use vem_mesh::{Point, Vector};
//! use vem_space::LowestOrderVem;
//!
//! let material = Material::from_young_poisson(100.0, 0.3, Plane::Strain)?;
//! let element = Arc::new(LowestOrderVem::default());
//! let square = |y0: f64| structured_quads(&Rectangle::new(Point::new(0.0, y0), Point::new(1.0, y0 + 1.0)), 4, 4);
//! // The upper block: its top pressed down (condition 0) and moved sideways (condition 1).
//! let upper = ElasticBody::builder("upper", square(0.0)?, material, element.clone())
//!     .dirichlet(Dirichlet::prescribed("top", Component::Y, |_| Vector::new(0.0, -0.01)))
//!     .dirichlet(Dirichlet::prescribed("top", Component::X, |_| Vector::new(0.002, 0.0)))
//!     .build()?;
//! let lower = ElasticBody::builder("lower", square(-1.0)?, material, element)
//!     .clamp("bottom")
//!     .build()?;
//! let problem = ContactProblem::two_bodies(upper, "bottom", lower, "top", Tresca::try_new(0.2)?);
//! let discretisation = problem.discretise()?;
//! // Press during t in [0, 1], then shear forth and back.
//! let press = LoadCondition::Dirichlet { body: 0, index: 0 };
//! let shear = LoadCondition::Dirichlet { body: 0, index: 1 };
//! let curves = LoadCurves::default()
//!     .with(press, LoadCurve::try_new(vec![(0.0, 0.0), (1.0, 1.0)])?)
//!     .with(shear, LoadCurve::try_new(vec![(1.0, 0.0), (2.0, 1.0), (3.0, -1.0)])?);
//! let history = LoadHistory::from_curves(LoadHistory::uniform_times(3.0, 6)?, &curves)?;
//! let steps = discretisation.solve_history(&mut CondensedSolver::default(), &history)?;
//! assert_eq!(steps.len(), 6);
//! // At t = 1 the block is pressed and not yet sheared: no friction force.
//! assert!(steps[1].result.tangential_resultant().abs() < 1e-12);
//! // Sheared forth (t = 2) and back (t = 3): the friction force changes sign.
//! assert!(steps[3].result.tangential_resultant() * steps[5].result.tangential_resultant() < 0.0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::fmt;
use std::time::Instant;

use crate::load::{LevelFactors, LoadParts};
use crate::{ContactDiscretisation, ContactError, ContactResult, ContactSolver};

/// A datum of a body that a load history scales (see the module docs): the body force, a
/// Dirichlet condition (prescribed displacement or rigid-plate resultant) or a traction, by
/// the index of the body in the problem and of the condition in the body's list
/// ([`vem_elastic::ElasticBody::dirichlet`], [`vem_elastic::ElasticBody::tractions`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum LoadCondition {
    /// The body force of body `body`.
    BodyForce {
        /// Index of the body in the problem.
        body: usize,
    },
    /// The Dirichlet condition `index` of body `body`: its prescribed displacement, or the
    /// resultant of a rigid plate (force control).
    Dirichlet {
        /// Index of the body in the problem.
        body: usize,
        /// Index of the condition in [`vem_elastic::ElasticBody::dirichlet`].
        index: usize,
    },
    /// The traction `index` of body `body`.
    Traction {
        /// Index of the body in the problem.
        body: usize,
        /// Index of the traction in [`vem_elastic::ElasticBody::tractions`].
        index: usize,
    },
}

impl LoadCondition {
    /// The body the condition belongs to.
    pub fn body(&self) -> usize {
        match *self {
            LoadCondition::BodyForce { body }
            | LoadCondition::Dirichlet { body, .. }
            | LoadCondition::Traction { body, .. } => body,
        }
    }
}

impl fmt::Display for LoadCondition {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LoadCondition::BodyForce { body } => write!(f, "body force of body {body}"),
            LoadCondition::Dirichlet { body, index } => {
                write!(f, "Dirichlet condition {index} of body {body}")
            }
            LoadCondition::Traction { body, index } => {
                write!(f, "traction {index} of body {body}")
            }
        }
    }
}

/// The factor `s(t)` of a condition along a history: piecewise linear through the points
/// `(t_k, s_k)` (pseudo-times strictly increasing), constant (`s_0`, the last `s_k`) before the
/// first and after the last point. A single point is a constant factor.
///
/// ```
/// use vem_contact::LoadCurve;
/// let cycle = LoadCurve::try_new(vec![(0.0, 0.0), (1.0, 1.0), (2.0, -1.0)])?;
/// assert_eq!(cycle.value(0.5), 0.5);
/// assert_eq!(cycle.value(1.5), 0.0);
/// assert_eq!(cycle.value(5.0), -1.0);
/// assert_eq!(LoadCurve::default().value(0.25), 0.25); // the ramp to 1 at t = 1
/// assert_eq!(LoadCurve::default().value(2.0), 1.0);
/// assert!(LoadCurve::try_new(vec![(1.0, 0.0), (1.0, 1.0)]).is_err());
/// # Ok::<(), vem_contact::ContactError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct LoadCurve {
    points: Vec<(f64, f64)>,
}

impl Default for LoadCurve {
    /// The ramp `s(t) = t` from `(0, 0)` to `(1, 1)`, then 1: a one-step history at `t = 1`
    /// is the static problem.
    fn default() -> Self {
        Self {
            points: vec![(0.0, 0.0), (1.0, 1.0)],
        }
    }
}

impl LoadCurve {
    /// The curve through `points` `(t_k, s_k)`.
    ///
    /// # Errors
    /// [`ContactError::InvalidSetting`] for no point, a value that is not finite or times that
    /// do not increase strictly (naming the point).
    pub fn try_new(points: Vec<(f64, f64)>) -> Result<Self, ContactError> {
        let invalid = |reason: String| ContactError::InvalidSetting {
            reason: format!("load curve: {reason}"),
        };
        if points.is_empty() {
            return Err(invalid("no point".to_string()));
        }
        for (k, &(t, s)) in points.iter().enumerate() {
            if !(t.is_finite() && s.is_finite()) {
                return Err(invalid(format!("point {k} ({t}, {s}) is not finite")));
            }
            if k > 0 && t <= points[k - 1].0 {
                return Err(invalid(format!(
                    "the time {t} of point {k} does not exceed the time {} of point {}",
                    points[k - 1].0,
                    k - 1
                )));
            }
        }
        Ok(Self { points })
    }

    /// The constant factor `value` (finite).
    ///
    /// # Errors
    /// [`ContactError::InvalidSetting`] for a value that is not finite.
    pub fn constant(value: f64) -> Result<Self, ContactError> {
        Self::try_new(vec![(0.0, value)])
    }

    /// The points `(t_k, s_k)`.
    pub fn points(&self) -> &[(f64, f64)] {
        &self.points
    }

    /// The factor at pseudo-time `t`.
    pub fn value(&self, t: f64) -> f64 {
        let p = &self.points;
        let k = p.partition_point(|&(tk, _)| tk <= t);
        if k == 0 {
            return p[0].1;
        }
        if k == p.len() {
            return p[k - 1].1;
        }
        let ((t0, s0), (t1, s1)) = (p[k - 1], p[k]);
        s0 + (s1 - s0) * (t - t0) / (t1 - t0)
    }
}

/// A load curve per condition, and the default curve of the others ([`LoadCurve::default`],
/// the ramp to 1 at `t = 1`, unless replaced).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct LoadCurves {
    default: LoadCurve,
    curves: Vec<(LoadCondition, LoadCurve)>,
}

impl LoadCurves {
    /// The curve `curve` for `condition` (replacing an earlier one).
    pub fn with(mut self, condition: LoadCondition, curve: LoadCurve) -> Self {
        self.curves.retain(|(c, _)| *c != condition);
        self.curves.push((condition, curve));
        self
    }

    /// The curve of the conditions that have none.
    pub fn with_default(mut self, curve: LoadCurve) -> Self {
        self.default = curve;
        self
    }

    /// The curve of `condition`.
    pub fn curve(&self, condition: LoadCondition) -> &LoadCurve {
        self.curves
            .iter()
            .find(|(c, _)| *c == condition)
            .map_or(&self.default, |(_, curve)| curve)
    }

    /// The factors at pseudo-time `t`.
    pub fn factors(&self, t: f64) -> LoadFactors {
        let mut factors = LoadFactors::uniform(self.default.value(t));
        for (condition, curve) in &self.curves {
            factors = factors.with(*condition, curve.value(t));
        }
        factors
    }
}

/// The factors of the conditions at one step: one per condition given, `default` for the
/// others (see the module docs).
///
/// ```
/// use vem_contact::{LoadCondition, LoadFactors};
/// let shear = LoadCondition::Dirichlet { body: 0, index: 1 };
/// let factors = LoadFactors::uniform(1.0).with(shear, -0.5);
/// assert_eq!(factors.factor(shear), -0.5);
/// assert_eq!(factors.factor(LoadCondition::BodyForce { body: 1 }), 1.0);
/// ```
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct LoadFactors {
    default: f64,
    factors: Vec<(LoadCondition, f64)>,
}

impl LoadFactors {
    /// Every condition scaled by `factor` (`1`: the problem as built).
    pub fn uniform(factor: f64) -> Self {
        Self {
            default: factor,
            factors: Vec::new(),
        }
    }

    /// The factor `factor` for `condition` (replacing an earlier one).
    pub fn with(mut self, condition: LoadCondition, factor: f64) -> Self {
        match self.factors.iter_mut().find(|(c, _)| *c == condition) {
            Some(entry) => entry.1 = factor,
            None => self.factors.push((condition, factor)),
        }
        self
    }

    /// The factor of `condition`.
    pub fn factor(&self, condition: LoadCondition) -> f64 {
        self.factors
            .iter()
            .find(|(c, _)| *c == condition)
            .map_or(self.default, |&(_, s)| s)
    }

    /// The factor of the conditions not given.
    pub fn default_factor(&self) -> f64 {
        self.default
    }

    /// The conditions given with their factors.
    pub fn given(&self) -> &[(LoadCondition, f64)] {
        &self.factors
    }
}

/// One step of a [`LoadHistory`]: its pseudo-time and the factors of the conditions.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct LoadStep {
    /// The pseudo-time (increasing along the history; a label of the step).
    pub time: f64,
    /// The factors of the conditions at this step.
    pub factors: LoadFactors,
}

/// The steps of a quasi-static loading, from rest (see the module docs).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct LoadHistory {
    steps: Vec<LoadStep>,
}

impl LoadHistory {
    /// One step at `t = 1` with every factor 1: the static problem.
    pub fn single() -> Self {
        Self {
            steps: vec![LoadStep {
                time: 1.0,
                factors: LoadFactors::uniform(1.0),
            }],
        }
    }

    /// The steps with the factors `steps`, at pseudo-times `1, 2, ...`.
    pub fn from_steps(steps: Vec<LoadFactors>) -> Self {
        Self {
            steps: steps
                .into_iter()
                .enumerate()
                .map(|(k, factors)| LoadStep {
                    time: (k + 1) as f64,
                    factors,
                })
                .collect(),
        }
    }

    /// The steps at the pseudo-times `times` (strictly increasing), the factors from
    /// `curves`.
    ///
    /// # Errors
    /// [`ContactError::InvalidSetting`] for no time, a time that is not finite or times that
    /// do not increase strictly.
    pub fn from_curves(
        times: impl IntoIterator<Item = f64>,
        curves: &LoadCurves,
    ) -> Result<Self, ContactError> {
        let times: Vec<f64> = times.into_iter().collect();
        check_times(&times)?;
        Ok(Self {
            steps: times
                .into_iter()
                .map(|time| LoadStep {
                    time,
                    factors: curves.factors(time),
                })
                .collect(),
        })
    }

    /// `steps` equal steps up to `end`: `end / steps, 2 end / steps, ..., end`.
    ///
    /// # Errors
    /// [`ContactError::InvalidSetting`] for no step or an `end` that is not finite and `> 0`.
    pub fn uniform_times(end: f64, steps: usize) -> Result<Vec<f64>, ContactError> {
        if steps == 0 || !(end.is_finite() && end > 0.0) {
            return Err(ContactError::InvalidSetting {
                reason: format!(
                    "load history: {steps} steps up to t = {end} (at least one step, an end \
                     finite and > 0)"
                ),
            });
        }
        Ok((1..=steps).map(|k| end * k as f64 / steps as f64).collect())
    }

    /// The steps.
    pub fn steps(&self) -> &[LoadStep] {
        &self.steps
    }
}

fn check_times(times: &[f64]) -> Result<(), ContactError> {
    let invalid = |reason: String| ContactError::InvalidSetting {
        reason: format!("load history: {reason}"),
    };
    if times.is_empty() {
        return Err(invalid("no step".to_string()));
    }
    for (k, &t) in times.iter().enumerate() {
        if !t.is_finite() {
            return Err(invalid(format!("the time {t} of step {k} is not finite")));
        }
        if k > 0 && t <= times[k - 1] {
            return Err(invalid(format!(
                "the time {t} of step {k} does not exceed the time {} of step {}",
                times[k - 1],
                k - 1
            )));
        }
    }
    Ok(())
}

/// The answer of one step of a history.
#[derive(Debug, Clone)]
pub struct HistoryStep<const D: usize = 2> {
    /// The step's index in the history (from 0).
    pub index: usize,
    /// Its pseudo-time.
    pub time: f64,
    /// The factors of the conditions.
    pub factors: LoadFactors,
    /// The answer at the end of the step; its [`work`](ContactResult::work) counts this step.
    pub result: ContactResult<D>,
}

/// The state at the end of the last step: what the next step starts from.
#[derive(Debug, Clone)]
pub(crate) struct PathState {
    /// `lambda_N` per node.
    pub(crate) normal_force: Vec<f64>,
    /// `lambda_T` per tangential row (empty without friction).
    pub(crate) tangential_force: Vec<f64>,
    /// The normal jumps `[u]_nu` (prescribed part included) per node.
    pub(crate) normal_jump: Vec<f64>,
    /// The tangential jumps `B_T u` per tangential row (empty without friction): the
    /// reference slip of the next step.
    pub(crate) slip: Vec<f64>,
}

impl PathState {
    /// The state as the laws see it.
    pub(crate) fn node_state(&self) -> NodeState<'_> {
        NodeState {
            normal_force: &self.normal_force,
            tangential_force: &self.tangential_force,
            normal_jump: &self.normal_jump,
            slip: &self.slip,
        }
    }
}

/// The forces and jumps at every interface node (all pairs), from which the laws' bounds are
/// made.
#[derive(Debug, Clone, Copy)]
pub(crate) struct NodeState<'a> {
    /// `lambda_N` per node.
    pub(crate) normal_force: &'a [f64],
    /// `lambda_T` per tangential row.
    pub(crate) tangential_force: &'a [f64],
    /// `[u]_nu` per node.
    pub(crate) normal_jump: &'a [f64],
    /// `B_T u` per tangential row.
    pub(crate) slip: &'a [f64],
}

/// A contact problem followed along a load history: the discretisation, the per-condition
/// parts of its load and gaps, and the state at the end of the last step (see the module
/// docs). A failed step leaves the state unchanged, so a caller may retry with a smaller
/// increment.
#[derive(Debug, Clone)]
pub struct LoadPath<'d, const D: usize = 2> {
    discretisation: &'d ContactDiscretisation<D>,
    parts: LoadParts,
    state: Option<PathState>,
    time: Option<f64>,
}

impl<'d, const D: usize> LoadPath<'d, D> {
    /// The problem of `discretisation` at rest (no step made), with the load and gap parts of
    /// every condition (computed here, once: one product with the Dirichlet coupling block per
    /// Dirichlet condition and the facet loads of each traction).
    ///
    /// # Errors
    /// A traction that cannot be integrated (as at assembly).
    pub fn new(discretisation: &'d ContactDiscretisation<D>) -> Result<Self, ContactError> {
        Ok(Self {
            parts: discretisation.load_parts()?,
            discretisation,
            state: None,
            time: None,
        })
    }

    /// The discretisation.
    pub fn discretisation(&self) -> &'d ContactDiscretisation<D> {
        self.discretisation
    }

    /// The pseudo-time of the last step (`None` at rest).
    pub fn time(&self) -> Option<f64> {
        self.time
    }

    /// Back to rest (the next step starts from `u = 0`, no force).
    pub fn reset(&mut self) {
        self.state = None;
        self.time = None;
    }

    /// Solves the step to the loads `factors` from the state at the end of the last step (from
    /// rest for the first), with friction on the slip increment, and makes its answer the new
    /// state. `time` labels the step and must exceed the last step's.
    ///
    /// # Errors
    /// A time that does not exceed the last one, a factor that is not finite or names a
    /// condition that does not exist, the solver's failure, a fixed point that does not
    /// settle, friction that cannot hold the load; the state is then unchanged.
    pub fn advance(
        &mut self,
        solver: &mut dyn ContactSolver,
        time: f64,
        factors: &LoadFactors,
    ) -> Result<ContactResult<D>, ContactError> {
        if !time.is_finite() || self.time.is_some_and(|last| time <= last) {
            return Err(ContactError::InvalidSetting {
                reason: format!(
                    "load step at t = {time}: the time must be finite and exceed the last \
                     step's ({})",
                    self.time.map_or("none".to_string(), |t| t.to_string())
                ),
            });
        }
        let start = Instant::now();
        let resolved = LevelFactors::resolve(self.discretisation, factors)?;
        let level = self.parts.level(self.discretisation, resolved);
        let (mut result, state) =
            self.discretisation
                .solve_level(solver, &level, self.state.as_ref())?;
        result.model.total_time = start.elapsed();
        self.state = Some(state);
        self.time = Some(time);
        Ok(result)
    }

    /// Solves every step of `history` in turn (after the steps already made).
    ///
    /// # Errors
    /// As [`LoadPath::advance`], at the first step that fails (the answers of the steps
    /// before it are lost; use [`LoadPath::advance`] to keep them).
    pub fn run(
        &mut self,
        solver: &mut dyn ContactSolver,
        history: &LoadHistory,
    ) -> Result<Vec<HistoryStep<D>>, ContactError> {
        let mut steps = Vec::with_capacity(history.steps().len());
        for (index, step) in history.steps().iter().enumerate() {
            let result = self.advance(solver, step.time, &step.factors)?;
            steps.push(HistoryStep {
                index,
                time: step.time,
                factors: step.factors.clone(),
                result,
            });
        }
        Ok(steps)
    }
}
