//! Errors of the contact problem layer.

use vem_elastic::ElasticError;
use vem_mesh::MeshError;

use crate::{ContactSolverError, ContactSystemError, SettingsError, SolveReport};

/// What can go wrong when a contact problem is built or solved.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ContactError {
    /// A mesh-level failure (unknown part, interface insertion), with the body it concerns.
    #[error("{context}")]
    Mesh {
        /// Where it happened (body, part, interface).
        context: String,
        /// The mesh error.
        #[source]
        source: MeshError,
    },
    /// An elasticity failure (material, boundary condition, singular stiffness).
    #[error(transparent)]
    Elastic(#[from] ElasticError),
    /// The algebraic contact system was inconsistent (a bug or non-finite data).
    #[error(transparent)]
    System(#[from] ContactSystemError),
    /// The contact solver failed (no convergence, rigid sliding, ...); carries its report.
    #[error(transparent)]
    Solver(#[from] ContactSolverError),
    /// A setting of the law or of a solver is invalid (named by the error).
    #[error(transparent)]
    Settings(#[from] SettingsError),
    /// A rigid obstacle's data are invalid.
    #[error("invalid obstacle: {reason}")]
    InvalidObstacle {
        /// What is wrong.
        reason: String,
    },
    /// A setting or a data function is invalid (friction bound, coefficient, gap).
    #[error("invalid contact setting: {reason}")]
    InvalidSetting {
        /// What is wrong, and where.
        reason: String,
    },
    /// What the problem asks for is not available (yet) in this dimension or configuration.
    #[error("not supported: {what}")]
    Unsupported {
        /// What, and where.
        what: String,
    },
    /// Coulomb friction cannot hold the load: a Tresca step with the bounds `F lambda_N` of the
    /// normal forces found so far has no equilibrium, because along a rigid sliding mode `d`
    /// (scaled so that its largest nodal slip is 1) the load exceeds the friction capacity.
    #[error(
        "Coulomb friction cannot hold the load: along the sliding mode the load \
         {load_along_mode:.6e} exceeds the friction capacity {friction_capacity:.6e} \
         (sum_i F lambda_N,i |slip_i| with the normal forces of fixed-point step {step}; {})",
        report.solver
    )]
    FrictionCapacityExceeded {
        /// `f . d` for the unit-slip mode `d`.
        load_along_mode: f64,
        /// `sum_i F lambda_N,i |(B_T d)_i|`.
        friction_capacity: f64,
        /// The fixed-point step whose bounds could not hold the load (from 1).
        step: usize,
        /// The report of that solve.
        report: Box<SolveReport>,
    },
    /// The fixed point of Tresca problems (Coulomb) did not converge.
    #[error(
        "Coulomb fixed point did not converge in {steps} steps: relative change of the normal \
         forces {residual:e} > tolerance {tolerance:e}"
    )]
    FixedPointNotConverged {
        /// Tresca solves done.
        steps: usize,
        /// Last relative change of the normal forces.
        residual: f64,
        /// The tolerance in force.
        tolerance: f64,
        /// The report of the last Tresca solve.
        report: Box<SolveReport>,
    },
}
