//! Contact solvers: matrices, constraint rows and bounds in; displacements and nodal contact
//! forces out.
//!
//! Every solver implements [`ContactSolver`] and returns a [`ContactSolution`] whose
//! [`SolveReport`] carries KKT residuals recomputed from the answer, or a
//! [`ContactSolverError`] carrying the report of the failed run.
//!
//! # Sign conventions
//!
//! The KKT system of the Lagrangian `E(u) + lambda_N'(B_N u - g)` (with `E` the energy of
//! [`ContactSystem`]) reads
//!
//! ```text
//! K u - f + B_N' lambda_N + B_T' lambda_T = 0
//! lambda_N >= 0,  B_N u - g <= 0,  lambda_N,i (B_N u - g)_i = 0
//! |lambda_T,i| <= b_i,  lambda_T,i = b_i sign((B_T u)_i)  where (B_T u)_i != 0
//! ```
//!
//! * `normal_force[i] = lambda_N,i >= 0` is the compressive nodal contact force at interface
//!   node `i` (divide by the tributary length for the pressure `p = -sigma_nu`).
//! * `tangential_force[i] = lambda_T,i` is the nodal friction force conjugate to the slip
//!   `(B_T u)_i = [u]_1tau`: it has the sign of the slip, and `-lambda_T,i` (times the tangent
//!   of body 1) is the friction force acting on body 1, opposing its slip.
//!   For frictionless systems it is all zeros.

mod active_set;
mod box_qp;
mod condensed;
mod error;
#[cfg(feature = "clarabel")]
mod exact;
mod newton_matrix;
mod penalty;
mod report;
mod shared;
mod system;

pub use active_set::{ActiveSetSettings, ActiveSetSettingsBuilder, ActiveSetSolver};
pub use condensed::{CondensedSettings, CondensedSettingsBuilder, CondensedSolver};
pub use error::{ContactSolverError, SettingsError};
#[cfg(feature = "clarabel")]
pub use exact::{ExactSettings, ExactSettingsBuilder, ExactSolver};
pub use penalty::{PenaltyParameter, PenaltySettings, PenaltySettingsBuilder, PenaltySolver};
pub(crate) use report::ForceScales;
pub use report::{
    KktResiduals, KktScales, KktTolerance, SolveReport, SolveStatus, StageTimes, WorkCounters,
};
pub(crate) use system::borrowed_block;
pub use system::{
    ConstraintRows, ContactSystem, ContactSystemError, Friction, PatternId, StiffnessBlock,
};

/// The answer of a contact solve.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactSolution {
    /// Displacement `u` (length `n`).
    pub displacement: Vec<f64>,
    /// `lambda_N` (length `m`): compressive nodal contact forces, `>= 0`.
    pub normal_force: Vec<f64>,
    /// `lambda_T` (length `m`): nodal friction forces with the sign of the slip `B_T u`; zeros
    /// for a frictionless system.
    pub tangential_force: Vec<f64>,
    /// What the solve measured.
    pub report: SolveReport,
}

/// A contact solver. Object safe: assembly code holds a `Box<dyn ContactSolver>` and new
/// solvers are added without touching it.
///
/// `solve` takes `&mut self` so that a solver may keep work from one solve to the next: the
/// symbolic work of a structure with the same [`PatternId`] (e.g. along a Coulomb fixed-point
/// iteration of Tresca problems, or load steps on one discretisation).
pub trait ContactSolver {
    /// Short name used in reports.
    fn name(&self) -> &'static str;

    /// Solves the problem.
    ///
    /// # Errors
    /// [`ContactSolverError`]: no convergence, rigid sliding, unbounded energy, infeasible
    /// constraints or a backend failure; run failures carry their [`SolveReport`].
    fn solve(&mut self, system: &ContactSystem<'_>) -> Result<ContactSolution, ContactSolverError>;

    /// Relative accuracy of the nodal forces this solver guarantees (`0` for solvers whose
    /// forces are exact up to rounding). Outer fixed points (Coulomb) cannot resolve changes of
    /// the forces below it and use it as a floor of their stopping tolerance.
    fn force_accuracy(&self) -> f64 {
        0.0
    }
}
