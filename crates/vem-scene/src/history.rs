//! The load history of a scene (`[history]` and the conditions' `curve`s) checked and turned
//! into the contact library's [`vem_contact::LoadHistory`], whose conditions are numbered as
//! the bodies' builders receive them: per body the Dirichlet conditions, then the rigid
//! plates (both Dirichlet conditions of the library), and the tractions, in the scene's order.

use vem_contact::{LoadCondition, LoadCurve, LoadCurves, LoadFactors, LoadHistory};

use crate::check::number;
use crate::description::{BodyDescription, LoadHistory as HistoryDescription};
use crate::{KeyPath, Scene, SceneError};

/// The most steps a history may have (a misplaced exponent, not a plan).
pub const MAX_STEPS: usize = 1_000_000;

/// A condition's curve and where it is written.
struct Curve<'s> {
    points: &'s [[f64; 2]],
    path: KeyPath,
}

/// The curves of `body` (the `k`-th of the scene), each with the condition it scales.
fn curves_of(body: &BodyDescription, k: usize) -> Vec<(Condition, Curve<'_>)> {
    let path = KeyPath::key("body").index(k);
    let mut curves = Vec::new();
    if let Some(points) = &body.body_force_curve {
        curves.push((
            Condition::BodyForce,
            Curve {
                points,
                path: path.at("body_force_curve"),
            },
        ));
    }
    let plates = body.rigid_plate.iter().map(|r| r.curve.as_ref());
    for (index, curve) in body
        .dirichlet
        .iter()
        .map(|d| d.curve.as_ref())
        .chain(plates)
        .enumerate()
    {
        if let Some(points) = curve {
            let at = if index < body.dirichlet.len() {
                path.at("dirichlet").index(index)
            } else {
                path.at("rigid_plate").index(index - body.dirichlet.len())
            };
            curves.push((
                Condition::Dirichlet(index),
                Curve {
                    points,
                    path: at.at("curve"),
                },
            ));
        }
    }
    for (index, traction) in body.traction.iter().enumerate() {
        if let Some(points) = &traction.curve {
            curves.push((
                Condition::Traction(index),
                Curve {
                    points,
                    path: path.at("traction").index(index).at("curve"),
                },
            ));
        }
    }
    curves
}

/// A condition of one body.
#[derive(Debug, Clone, Copy)]
enum Condition {
    BodyForce,
    Dirichlet(usize),
    Traction(usize),
}

impl Condition {
    fn of_body(self, body: usize) -> LoadCondition {
        match self {
            Condition::BodyForce => LoadCondition::BodyForce { body },
            Condition::Dirichlet(index) => LoadCondition::Dirichlet { body, index },
            Condition::Traction(index) => LoadCondition::Traction { body, index },
        }
    }
}

fn curve(curve: &Curve<'_>) -> Result<LoadCurve, SceneError> {
    LoadCurve::try_new(curve.points.iter().map(|p| (p[0], p[1])).collect())
        .map_err(|e| SceneError::at(curve.path.clone(), e.to_string()))
}

/// The times of a history with `times` or `end` and `increments` (checked).
fn times(history: &HistoryDescription) -> Result<Option<Vec<f64>>, SceneError> {
    let path = KeyPath::key("history");
    match (&history.times, history.end, history.increments) {
        (Some(times), None, None) => {
            if times.is_empty() || times.len() > MAX_STEPS {
                return Err(SceneError::at(
                    path.at("times"),
                    format!("a load history has 1 to {MAX_STEPS} times"),
                ));
            }
            LoadHistory::from_curves(times.iter().copied(), &LoadCurves::default())
                .map_err(|e| SceneError::at(path.at("times"), e.to_string()))?;
            Ok(Some(times.clone()))
        }
        (None, Some(end), Some(increments)) => {
            if increments > MAX_STEPS {
                return Err(SceneError::at(
                    path.at("increments"),
                    format!("a load history has 1 to {MAX_STEPS} steps"),
                ));
            }
            LoadHistory::uniform_times(end, increments)
                .map(Some)
                .map_err(|e| SceneError::at(path.clone(), e.to_string()))
        }
        (None, None, None) => Ok(None),
        _ => Err(SceneError::at(
            path,
            "give `times = [...]`, or `end` with `increments`",
        )),
    }
}

/// Checks the history and the curves: one form of `[history]`, curves only with times, every
/// curve a valid one.
///
/// # Errors
/// A [`SceneError`] at the key at fault.
pub(crate) fn check_history(scene: &Scene) -> Result<(), SceneError> {
    let path = KeyPath::key("history");
    let timed = match &scene.history {
        Some(history) => {
            let timed = times(history)?.is_some();
            match (&history.steps, timed) {
                (Some(steps), false) => {
                    if steps.is_empty() || steps.len() > MAX_STEPS {
                        return Err(SceneError::at(
                            path.at("steps"),
                            format!("a load history has 1 to {MAX_STEPS} steps"),
                        ));
                    }
                    for (k, &s) in steps.iter().enumerate() {
                        number(s, &path.at("steps").index(k), "a load factor")?;
                    }
                }
                (None, true) => {}
                (Some(_), true) => {
                    return Err(SceneError::at(
                        path.at("steps"),
                        "`steps` (load factors) or times with curves, not both",
                    ))
                }
                (None, false) => {
                    return Err(SceneError::at(
                        path,
                        "a load history needs `steps = [factors]`, `times = [...]`, or `end` \
                         with `increments`",
                    ))
                }
            }
            timed
        }
        None => false,
    };
    for (k, body) in scene.bodies.iter().enumerate() {
        for (_, c) in curves_of(body, k) {
            if !timed {
                return Err(SceneError::at(
                    c.path,
                    "a load curve needs a `[history]` with `times` or `end` and `increments`",
                ));
            }
            curve(&c)?;
        }
    }
    Ok(())
}

/// The history of a checked scene over the bodies of its contact problem (`in_problem[b]` is
/// the scene's index of the problem's body `b`): the static problem without `[history]`.
///
/// # Errors
/// Only for a scene that was not checked.
pub(crate) fn load_history(scene: &Scene, in_problem: &[usize]) -> Result<LoadHistory, SceneError> {
    let Some(history) = &scene.history else {
        return Ok(LoadHistory::single());
    };
    if let Some(steps) = &history.steps {
        return Ok(LoadHistory::from_steps(
            steps.iter().map(|&s| LoadFactors::uniform(s)).collect(),
        ));
    }
    let times = times(history)?.unwrap_or_default();
    let mut curves = LoadCurves::default();
    for (b, &k) in in_problem.iter().enumerate() {
        for (condition, c) in curves_of(&scene.bodies[k], k) {
            curves = curves.with(condition.of_body(b), curve(&c)?);
        }
    }
    LoadHistory::from_curves(times, &curves)
        .map_err(|e| SceneError::at(KeyPath::key("history"), e.to_string()))
}

/// The factor of every load of body `k` (outside the contact problem) at the end of the
/// history, when they are all the same: such a body is solved once, at that factor.
///
/// # Errors
/// A body outside contact whose conditions end at different factors, at its first curve.
pub(crate) fn final_factor(scene: &Scene, k: usize) -> Result<f64, SceneError> {
    let Some(history) = &scene.history else {
        return Ok(1.0);
    };
    if let Some(steps) = &history.steps {
        return Ok(steps.last().copied().unwrap_or(1.0));
    }
    let end = times(history)?
        .and_then(|t| t.last().copied())
        .unwrap_or(1.0);
    let ramp = LoadCurve::default().value(end);
    let body = &scene.bodies[k];
    let conditions = usize::from(body.body_force.is_some())
        + body.dirichlet.len()
        + body.rigid_plate.len()
        + body.traction.len();
    let curves = curves_of(body, k);
    let mut factors: Vec<f64> = curves
        .iter()
        .map(|(_, c)| curve(c).map(|c| c.value(end)))
        .collect::<Result<_, _>>()?;
    if curves.len() < conditions {
        factors.push(ramp);
    }
    match factors.split_first() {
        Some((&first, rest)) if rest.iter().any(|&f| f != first) => Err(SceneError::at(
            curves[0].1.path.clone(),
            format!(
                "body '{}' is in no contact pair and its loads end the history at different \
                 factors ({}): give its conditions one curve, or put it in contact",
                body.name,
                factors
                    .iter()
                    .map(|f| f.to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        )),
        Some((&first, _)) => Ok(first),
        None => Ok(ramp),
    }
}

impl crate::Model {
    /// The scene's load history as [`Model::solve`](crate::Model::solve) follows it: the
    /// contact library's history, its conditions numbered over the bodies of
    /// [`Model::contact_problem`](crate::Model::contact_problem) (in space
    /// [`Model::contact_problem_3d`](crate::Model::contact_problem_3d)) as their builders
    /// received them; the static problem (one step of factor 1) without `[history]`. For a
    /// study that drives the steps itself (`vem_contact::LoadPath`) on the model's contact
    /// problem.
    ///
    /// # Errors
    /// A [`SceneError`] at the history's key (not for a scene the model was built from).
    pub fn load_history(&self) -> Result<LoadHistory, SceneError> {
        let indices = self
            .problem
            .as_ref()
            .map(|(_, indices)| indices.as_slice())
            .or_else(|| {
                self.problem_3d
                    .as_ref()
                    .map(|(_, indices)| indices.as_slice())
            })
            .unwrap_or(&[]);
        load_history(self.scene(), indices)
    }
}
