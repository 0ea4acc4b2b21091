//! The scene option `adapt`: adaptive refinement of the bodies in the plane
//! (docs/adaptivity.md, docs/scenes.md).
//!
//! Each cycle solves the scene on the current meshes ([`Model::solve`] without `adapt`), with
//! the residual error estimate `eta` of [`crate::ErrorEstimate`] and its indicators `eta_E`
//! per element. The run stops when
//!
//! 1. `eta / ||u_h|| <= target_error` (`||u_h|| = (sum 2 W_h)^(1/2)`, the energy norm of the
//!    solution): converged;
//! 2. the solves reach `max_cycles`;
//! 3. the next mesh would have more than `max_unknowns` unknowns (it is built, not solved).
//!
//! Otherwise the elements of all bodies together are marked by Dorfler's bulk criterion with
//! the fraction `theta` ([`vem_mesh::refine::dorfler_marking`]), every body's mesh as solved
//! (with the interface nodes inserted by the contact pairs) is refined at its marked elements
//! ([`vem_mesh::refine::refine`], the boundary parts carried to the pieces), and the bodies,
//! contact pairs (interface insertion, pairing) and solver are built again on the refined
//! meshes. The outcome is the last solve's, with [`AdaptSummary`] in its summary.

use std::time::{Duration, Instant};

use serde::Serialize;
use vem_mesh::refine::{dorfler_marking, refine};

use crate::description::AdaptDescription;
use crate::{KeyPath, Model, Outcome, SceneError};

/// What stopped an adaptive run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum AdaptStop {
    /// The relative estimate reached `target_error`.
    Converged,
    /// The next mesh would have had more than `max_unknowns` unknowns.
    MaxUnknowns,
    /// `max_cycles` solves were made.
    MaxCycles,
    /// Every indicator is zero: nothing to refine (the solution is exact for the method).
    NothingToRefine,
}

/// One cycle of an adaptive run (a row of `adapt.csv`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct AdaptCycle {
    /// The cycle, from 0.
    pub cycle: usize,
    /// The unknowns (free degrees of freedom) of all bodies.
    pub unknowns: usize,
    /// The elements of all bodies.
    pub cells: usize,
    /// The estimate `eta`.
    pub estimate: f64,
    /// `eta / ||u_h||`.
    pub relative_estimate: f64,
    /// The elements marked for refinement after this solve (0 on the last).
    pub marked: usize,
    /// Wall-clock seconds of the cycle: build (from the second on), solve, estimate, marking
    /// and refinement.
    pub time_s: f64,
}

/// The adaptive run of a scene with `adapt`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AdaptSummary {
    /// The target of the relative estimate, if any.
    pub target_error: Option<f64>,
    /// The limit of the unknowns.
    pub max_unknowns: usize,
    /// Dorfler's fraction.
    pub theta: f64,
    /// The limit of the solves.
    pub max_cycles: usize,
    /// Every cycle; the outputs are the last one's.
    pub cycles: Vec<AdaptCycle>,
    /// What stopped the run.
    pub stop: AdaptStop,
    /// With a target not met, the limit that stopped the run, in a sentence.
    pub warning: Option<String>,
}

impl AdaptSummary {
    /// True when the target was met.
    pub fn converged(&self) -> bool {
        self.stop == AdaptStop::Converged
    }
}

/// Runs the adaptive loop of `model` (a scene in the plane with `adapt`).
pub(crate) fn solve(
    model: &Model,
    adapt: &AdaptDescription,
    started: Instant,
) -> Result<Outcome, SceneError> {
    let max_unknowns = adapt.max_unknowns.unwrap_or(AdaptDescription::MAX_UNKNOWNS);
    let theta = adapt.theta.unwrap_or(AdaptDescription::THETA);
    let max_cycles = adapt.max_cycles.unwrap_or(AdaptDescription::MAX_CYCLES);
    let mut cycles: Vec<AdaptCycle> = Vec::new();
    let mut current: Option<Model> = None;
    let mut build_time = Duration::ZERO;
    let mut totals = crate::RunTimes::default();
    let sources: Vec<String> = model.bodies.iter().map(|b| b.mesh_source.clone()).collect();
    loop {
        let cycle_start = Instant::now();
        let this = current.as_ref().unwrap_or(model);
        let outcome = this.solve_plane(started)?;
        let times = outcome.summary.times;
        totals.mesh_s += times.mesh_s;
        totals.assembly_s += times.assembly_s;
        totals.solve_s += times.solve_s;
        totals.post_s += times.post_s;
        totals.estimate_s += times.estimate_s;
        let estimate = outcome
            .summary
            .error_estimate
            .expect("a solve in the plane has its estimate");
        let unknowns: usize = outcome.summary.bodies.iter().map(|b| b.free_dofs).sum();
        let cells: usize = outcome
            .bodies
            .iter()
            .map(|b| b.body.mesh().n_polygons())
            .sum();
        let mut record = AdaptCycle {
            cycle: cycles.len(),
            unknowns,
            cells,
            estimate: estimate.estimate,
            relative_estimate: estimate.relative,
            marked: 0,
            time_s: 0.0,
        };
        let finish = |mut outcome: Outcome,
                      mut cycles: Vec<AdaptCycle>,
                      mut record: AdaptCycle,
                      stop: AdaptStop,
                      totals: crate::RunTimes| {
            record.time_s = (build_time + cycle_start.elapsed()).as_secs_f64();
            cycles.push(record);
            let limit = match stop {
                AdaptStop::Converged => None,
                AdaptStop::MaxUnknowns => Some(format!(
                    "the next mesh would have more than max_unknowns = {max_unknowns} unknowns"
                )),
                AdaptStop::MaxCycles => Some(format!("max_cycles = {max_cycles} solves made")),
                AdaptStop::NothingToRefine => Some("every error indicator is zero".to_string()),
            };
            let warning = match (adapt.target_error, limit) {
                (_, None) => None,
                (Some(target), Some(limit)) => Some(format!(
                    "adaptive refinement stopped before the target: {limit}; the estimate is \
                     {:.3} % of the solution's energy norm, the target {:.3} %",
                    100.0 * record.relative_estimate,
                    100.0 * target
                )),
                (None, Some(limit)) => Some(format!(
                    "adaptive refinement without a target stopped: {limit}; the estimate is \
                     {:.3} % of the solution's energy norm",
                    100.0 * record.relative_estimate
                )),
            };
            let summary = &mut outcome.summary;
            summary.times.mesh_s = totals.mesh_s;
            summary.times.assembly_s = totals.assembly_s;
            summary.times.solve_s = totals.solve_s;
            summary.times.post_s = totals.post_s;
            summary.times.estimate_s = totals.estimate_s;
            summary.times.total_s = started.elapsed().as_secs_f64();
            summary.adaptivity = Some(AdaptSummary {
                target_error: adapt.target_error,
                max_unknowns,
                theta,
                max_cycles,
                cycles,
                stop,
                warning,
            });
            outcome
        };
        if adapt
            .target_error
            .is_some_and(|target| estimate.relative <= target)
        {
            return Ok(finish(
                outcome,
                cycles,
                record,
                AdaptStop::Converged,
                totals,
            ));
        }
        if cycles.len() + 1 >= max_cycles {
            return Ok(finish(
                outcome,
                cycles,
                record,
                AdaptStop::MaxCycles,
                totals,
            ));
        }
        // Mark over all bodies together, refine each body's mesh as solved.
        let refine_start = Instant::now();
        let all: Vec<f64> = outcome
            .bodies
            .iter()
            .flat_map(|b| b.error_indicator.iter().copied())
            .collect();
        if all.iter().all(|&e| e == 0.0) {
            return Ok(finish(
                outcome,
                cycles,
                record,
                AdaptStop::NothingToRefine,
                totals,
            ));
        }
        let marked = dorfler_marking(&all, theta).map_err(|e| {
            SceneError::at(KeyPath::key("adapt").at("theta"), format!("marking: {e}"))
        })?;
        let mut meshes = Vec::with_capacity(outcome.bodies.len());
        let mut offset = 0;
        for (b, solved) in outcome.bodies.iter().enumerate() {
            let n = solved.error_indicator.len();
            let mine: Vec<usize> = marked
                .iter()
                .filter(|&&c| c >= offset && c < offset + n)
                .map(|&c| c - offset)
                .collect();
            offset += n;
            let refined = refine(solved.body.mesh(), &mine).map_err(|e| {
                SceneError::at(
                    KeyPath::key("body").index(b).at("mesh"),
                    format!(
                        "body '{}': adaptive refinement, cycle {}: {e}",
                        solved.body.name(),
                        record.cycle
                    ),
                )
            })?;
            meshes.push((refined.mesh, format!("{}, refined adaptively", sources[b])));
        }
        let refine_time = refine_start.elapsed();
        let build_start = Instant::now();
        let next = this.rebuilt(meshes, refine_time)?;
        let next_unknowns: usize = next.bodies.iter().map(|b| b.body.dofs().n_free()).sum();
        if next_unknowns > max_unknowns {
            return Ok(finish(
                outcome,
                cycles,
                record,
                AdaptStop::MaxUnknowns,
                totals,
            ));
        }
        record.marked = marked.len();
        record.time_s = (build_time + cycle_start.elapsed()).as_secs_f64();
        build_time = build_start.elapsed();
        // The next cycle's build is counted in its time.
        record.time_s -= build_time.as_secs_f64();
        cycles.push(record);
        current = Some(next);
    }
}
