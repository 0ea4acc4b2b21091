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
