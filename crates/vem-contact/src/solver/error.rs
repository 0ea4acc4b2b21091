//! Errors of the contact solvers and of their settings.

use super::report::SolveReport;
use super::system::ContactSystem;

/// A setting was rejected when its builder was built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("invalid setting `{setting}` = {value}: must be {requirement}")]
pub struct SettingsError {
    /// Name of the setting.
    pub setting: &'static str,
    /// The rejected value.
    pub value: f64,
    /// What it must satisfy.
    pub requirement: &'static str,
}

impl From<SettingsError> for vem_space::OptionsError {
    /// The refused setting as an error at its key.
    fn from(e: SettingsError) -> Self {
        vem_space::OptionsError::at(e.setting, e.to_string())
    }
}

impl SettingsError {
    /// Checks `value` is finite and `> 0`.
    pub(crate) fn positive(setting: &'static str, value: f64) -> Result<f64, Self> {
        if value.is_finite() && value > 0.0 {
            Ok(value)
        } else {
            Err(Self {
                setting,
                value,
                requirement: "finite and > 0",
            })
        }
    }

    /// Checks `value` is finite and `>= 0`.
    pub(crate) fn non_negative(setting: &'static str, value: f64) -> Result<f64, Self> {
        if value.is_finite() && value >= 0.0 {
            Ok(value)
        } else {
            Err(Self {
                setting,
                value,
                requirement: "finite and >= 0",
            })
        }
    }

    /// Checks a count is at least 1.
    pub(crate) fn at_least_one(setting: &'static str, value: usize) -> Result<usize, Self> {
        if value >= 1 {
            Ok(value)
        } else {
            Err(Self {
                setting,
                value: value as f64,
                requirement: ">= 1",
            })
        }
    }
}

/// Why a contact solve produced no answer. Every variant that comes out of a run carries the
/// [`SolveReport`] of that run (iterations, time, residuals of the last iterate).
#[derive(Debug, Clone, thiserror::Error)]
#[non_exhaustive]
pub enum ContactSolverError {
    /// The solver stopped before meeting its tolerances (iteration limit, reduced accuracy,
    /// lack of progress).
    #[error(
        "{} did not converge ({}) after {} iterations: stationarity {:.1e}, max penetration \
         {:.1e}, complementarity {:.1e}, friction bound violation {:.1e}",
        report.solver,
        report.status.describe(),
        report.iterations,
        report.residuals.stationarity,
        report.residuals.max_penetration,
        report.residuals.complementarity,
        report.residuals.friction_bound_violation
    )]
    NotConverged {
        /// The report of the run; its residuals are those of the last iterate.
        report: Box<SolveReport>,
    },
    /// Tresca friction cannot hold the load: `K` is singular along a (tangential rigid) mode,
    /// and the load along that mode exceeds the friction capacity. No equilibrium exists.
    ///
    /// The mode `d` is scaled so that its largest nodal slip `max_i |(B_T d)_i|` is 1; then
    /// `load_along_mode = f . d` and `friction_capacity = sum_i b_i |(B_T d)_i|` are forces.
    /// `d` is the direction the solver detected: the free mode itself for the Newton solvers,
    /// Clarabel's dual-infeasibility certificate for the exact solver (which may add a little
    /// separating motion to the mode, so its figures are accurate to about 1%).
    #[error("rigid sliding: load along the free mode {load_along_mode:.6e} exceeds the friction capacity {friction_capacity:.6e} ({})", report.solver)]
    RigidSliding {
        /// `f . d` for the unit-slip mode `d`.
        load_along_mode: f64,
        /// `sum_i b_i |(B_T d)_i|`.
        friction_capacity: f64,
        /// Report of the run that detected it.
        report: Box<SolveReport>,
    },
    /// The energy is unbounded below along a mode that no constraint or friction controls
    /// (a floating body, a missing Dirichlet condition, a body pulled away from the contact).
    /// The mode `d` is scaled so that `max_j |d_j| = 1`.
    #[error("unbounded energy (floating body?): load along a free mode {load_along_mode:.6e} ({})", report.solver)]
    Unbounded {
        /// `f . d` for the free mode `d`.
        load_along_mode: f64,
        /// Report of the run that detected it.
        report: Box<SolveReport>,
    },
    /// The constraints `B_N u <= g` are contradictory (possible only for dependent rows).
    #[error("the contact constraints admit no displacement ({})", report.solver)]
    Infeasible {
        /// Report of the run that detected it.
        report: Box<SolveReport>,
    },
    /// The linear algebra backend refused the problem (out of memory, bad data).
    #[error("{solver}: backend failure: {detail}")]
    Backend {
        /// The solver.
        solver: &'static str,
        /// The backend's message.
        detail: String,
    },
}

impl ContactSolverError {
    /// The report of the failed run, if the failure happened during a run.
    pub fn report(&self) -> Option<&SolveReport> {
        match self {
            Self::NotConverged { report }
            | Self::RigidSliding { report, .. }
            | Self::Unbounded { report, .. }
            | Self::Infeasible { report } => Some(report),
            Self::Backend { .. } => None,
        }
    }

    /// Turns a direction `d` along which the energy decreases without bound into
    /// [`Self::RigidSliding`] (friction acts along `d`) or
    /// [`Self::Unbounded`], with the figures of the error's documentation.
    pub(crate) fn from_free_mode(
        system: &ContactSystem<'_>,
        direction: &[f64],
        report: Box<SolveReport>,
    ) -> Self {
        let inf = super::report::inf_norm;
        let load_along = |d: &[f64], scale: f64| {
            system
                .load()
                .iter()
                .zip(d)
                .map(|(f, x)| f * x / scale)
                .sum::<f64>()
        };
        if let Some(fr) = system.friction() {
            let slip = fr.tangential_rows().apply(direction);
            // The largest nodal slip (its Euclidean norm in the tangent plane in space).
            let t = fr.rows_per_node();
            let scale = slip
                .chunks(t)
                .map(|s| s.iter().map(|x| x * x).sum::<f64>().sqrt())
                .fold(0.0f64, f64::max);
            // A mode with slips below 1e-8 of its size is not resisted by friction.
            if scale > 1e-8 * inf(direction) {
                // sum_i b_i |s_i| (the Euclidean norm of the node's slip in space).
                let friction_capacity = fr
                    .bounds()
                    .iter()
                    .zip(slip.chunks(fr.rows_per_node()))
                    .map(|(b, s)| b * s.iter().map(|x| x * x).sum::<f64>().sqrt() / scale)
                    .sum::<f64>();
                return Self::RigidSliding {
                    load_along_mode: load_along(direction, scale),
                    friction_capacity,
                    report,
                };
            }
        }
        let scale = inf(direction);
        Self::Unbounded {
            load_along_mode: if scale > 0.0 {
                load_along(direction, scale)
            } else {
                0.0
            },
            report,
        }
    }
}
