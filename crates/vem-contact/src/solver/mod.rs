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
//! |lambda_T,i| <= b_i,  lambda_T,i = b_i sign((B_T u - s)_i)  where (B_T u - s)_i != 0
//! ```
//!
//! with `s` the reference slip of [`Friction`] (zero for a problem from rest, the tangential
//! jump of the previous step in a load history).
//!
//! * `normal_force[i] = lambda_N,i >= 0` is the compressive nodal contact force at interface
//!   node `i` (divide by the tributary length for the pressure `p = -sigma_nu`).
//! * `tangential_force[i] = lambda_T,i` is the nodal friction force conjugate to the slip
//!   `(B_T u - s)_i` (the tangential jump `[u]_1tau` since the reference slip): it has the
//!   sign of the slip, and `-lambda_T,i` (times the tangent
//!   of body 1) is the friction force acting on body 1, opposing its slip.
//!   For frictionless systems it is all zeros.

mod active_set;
mod box_qp;
mod condensed;
mod disk_qp;
mod error;
#[cfg(feature = "clarabel")]
mod exact;
mod kept_products;
mod mprgp;
mod newton_matrix;
mod penalty;
mod report;
mod shared;
mod system;

pub use active_set::{ActiveSetSettings, ActiveSetSettingsBuilder, ActiveSetSolver};
pub use condensed::{
    CondensedSettings, CondensedSettingsBuilder, CondensedSolver, InterfaceMethod,
    ITERATIONS_PER_STEP, ITERATIVE_FROM, ITERATIVE_WITH_FRICTION_FROM,
    ITERATIVE_WITH_FRICTION_IN_THE_PLANE_FROM,
};
pub use error::{ContactSolverError, SettingsError};
#[cfg(feature = "clarabel")]
pub use exact::{ExactSettings, ExactSettingsBuilder, ExactSolver};
pub use penalty::{PenaltyParameter, PenaltySettings, PenaltySettingsBuilder, PenaltySolver};
pub(crate) use report::ForceScales;
pub use report::{
    KktResiduals, KktScales, KktTolerance, SolveReport, SolveStatus, StageTimes, WorkCounters,
};
pub(crate) use system::{check_finite, checked_block, matrix_diagonal};
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

/// The forces of a contact solve and the values of the constraint rows at its displacement,
/// without the displacement itself: what an outer fixed point (Coulomb) needs between its
/// steps ([`ContactSolver::solve_forces`]).
#[derive(Debug, Clone, PartialEq)]
pub struct ContactForces {
    /// `lambda_N` (length `m`).
    pub normal_force: Vec<f64>,
    /// `lambda_T` (length `m`; zeros for a frictionless system).
    pub tangential_force: Vec<f64>,
    /// `B_N u` (length `m`).
    pub normal_rows: Vec<f64>,
    /// `B_T u` (length `m`; empty for a frictionless system).
    pub tangential_rows: Vec<f64>,
    /// Iterations of the solver.
    pub iterations: usize,
    /// What the solve computed.
    pub work: WorkCounters,
    /// The complete answer, when the solver formed it anyway (the default
    /// [`ContactSolver::solve_forces`] does): a caller that needs it then solves no more.
    pub solution: Option<ContactSolution>,
}

impl ContactForces {
    /// The forces of a complete answer `solution` of `system` (which it keeps).
    pub fn of_solution(system: &ContactSystem<'_>, solution: ContactSolution) -> Self {
        let u = &solution.displacement;
        Self {
            normal_force: solution.normal_force.clone(),
            tangential_force: solution.tangential_force.clone(),
            normal_rows: system.normal_rows().apply(u),
            tangential_rows: system
                .friction()
                .map_or_else(Vec::new, |f| f.tangential_rows().apply(u)),
            iterations: solution.report.iterations,
            work: solution.report.work,
            solution: Some(solution),
        }
    }
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

    /// The forces of the answer and the values `B_N u`, `B_T u` of its constraint rows, for the
    /// steps of an outer fixed point (Coulomb), whose last step is a [`ContactSolver::solve`].
    /// A solver that condenses onto the interface returns them without forming `u` (the
    /// condensed solver: interface work only); the default solves completely and keeps the
    /// answer in [`ContactForces::solution`]. These forces are not certified: the complete
    /// solve is.
    ///
    /// `accuracy` is the relative accuracy the caller needs (`0`: the solver's own): an
    /// iterative solver may stop at it where it is looser than its own tolerance (the condensed
    /// solver does), so that the early steps of a fixed point, whose forces only make the next
    /// step's bounds, cost less (an inexact fixed point). The default ignores it.
    ///
    /// # Errors
    /// As [`ContactSolver::solve`].
    fn solve_forces(
        &mut self,
        system: &ContactSystem<'_>,
        accuracy: f64,
    ) -> Result<ContactForces, ContactSolverError> {
        let _ = accuracy;
        let solution = self.solve(system)?;
        Ok(ContactForces::of_solution(system, solution))
    }

    /// Relative accuracy of the nodal forces this solver guarantees (`0` for solvers whose
    /// forces are exact up to rounding). Outer fixed points (Coulomb) cannot resolve changes of
    /// the forces below it and use it as a floor of their stopping tolerance.
    fn force_accuracy(&self) -> f64 {
        0.0
    }
}

/// Uniform numbers in `[-1, 1)` from a 64-bit linear congruential generator (Knuth's MMIX
/// constants): the solvers' unit tests draw their random problems from it.
#[cfg(test)]
pub(crate) fn uniform(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    ((*seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
}
