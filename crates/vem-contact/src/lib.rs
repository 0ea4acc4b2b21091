//! Contact of elastic bodies with the lowest-order virtual element method: contact pairs,
//! laws, the discretisation built once, and the contact solvers.
//!
//! A [`ContactProblem`] holds any number of bodies ([`vem_elastic::ElasticBody`], in `R^D`,
//! `D = 2` by default) and contact pairs ([`ContactPair`]: two bodies, or a body and a
//! [`RigidObstacle`]), each with its [`ContactLaw`] ([`Frictionless`], [`Tresca`],
//! [`Coulomb`], or one's own: the [`law`] module). It is discretised once
//! ([`ContactDiscretisation`]) and solved as often as needed: statically, or step by step
//! along a load history ([`LoadHistory`], [`LoadPath`]), where friction acts on the slip
//! increments and the answer depends on the path.
//!
//! In space (`D = 3`, polyhedral bodies) the frictionless problem is solved by every solver:
//! against rigid obstacles ([`Obstacle3`]: a plane, a ball) and between two bodies on
//! non-matching surfaces, made node-to-node by the surface overlay
//! ([`vem_mesh::polyhedral::overlay::insert_surface_overlay`]). Friction in 3D is refused. See
//! docs/contact-3d.md.
//!
//! The [`solver`] layer is algebraic: a [`ContactSystem`] holds the stiffness `K`, the load
//! `f`, the normal constraint rows `B_N` with gaps `g` (`B_N u <= g`) and, for Tresca friction
//! with nodal quadrature, tangential rows `B_T` with nodal bounds `b`. Solvers implement
//! [`ContactSolver`]: [`CondensedSolver`] (the default: one factorisation per body, the exact
//! dual problem on the interface unknowns), [`ExactSolver`] (convex QP by Clarabel, the
//! independent oracle of the tests), [`PenaltySolver`] (semismooth Newton on faer sparse
//! Cholesky) and [`ActiveSetSolver`] (primal-dual active set on faer sparse Cholesky, exact KKT
//! answer). Every answer carries a [`SolveReport`] with KKT
//! residuals recomputed from it. Sign conventions are in the [`solver`] module docs:
//! `normal_force >= 0` is compression.
//!
//! # Example: a spring against a wall
//!
//! One unknown `u` with stiffness `k = 2`, load `f = 3`, wall at gap `g = 1`: free, the spring
//! would stretch to `f/k = 1.5 > g`, so it touches the wall, `u = 1`, and the wall carries
//! `lambda_N = f - k g = 1`.
//!
//! ```
//! use faer::sparse::{SparseColMat, Triplet};
//! use vem_contact::{ConstraintRows, ContactSolver, ContactSystem, ExactSolver};
//!
//! let k = SparseColMat::<usize, f64>::try_new_from_triplets(1, 1, &[Triplet::new(0, 0, 2.0)])
//!     .expect("valid triplets");
//! let wall = ConstraintRows::try_from_triplets(1, 1, &[(0, 0, 1.0)])?;
//! let system = ContactSystem::try_new(k, vec![3.0], wall, vec![1.0], None)?;
//! let solution = ExactSolver::default().solve(&system)?;
//! assert!((solution.displacement[0] - 1.0).abs() < 1e-8);
//! assert!((solution.normal_force[0] - 1.0).abs() < 1e-8);
//! assert!(solution.report.residuals.stationarity < 1e-8);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![deny(missing_docs)]

pub mod accuracy;
mod discretisation;
mod error;
pub mod estimate;
mod history;
pub mod law;
mod load;
mod node;
mod obstacle;
mod pairing;
mod problem;
pub mod registry;
mod result;
pub mod solver;
mod surface;
mod warning;

pub use accuracy::{AccuracyPreset, ErrorModel, UnknownPreset};
pub use discretisation::ContactDiscretisation;
pub use error::ContactError;
pub use estimate::ContactEstimate;
pub use history::{
    HistoryStep, LoadCondition, LoadCurve, LoadCurves, LoadFactors, LoadHistory, LoadPath, LoadStep,
};
pub use law::{
    ContactLaw, Coulomb, FixedPointSettings, FixedPointSettingsBuilder, FrictionBound,
    Frictionless, LawState, ScalarField, Tresca,
};
pub use node::{frame, tangent, ContactNode, Location};
pub use obstacle::{Obstacle, Obstacle3, ObstacleGap, RigidObstacle};
pub use problem::{ContactNormal, ContactPair, ContactProblem, Counterpart};
pub use registry::{LawRegistry, RegistryError, SolverRegistry};
pub use result::{
    consistent_traction, BodyResult, BodySummary, ContactResult, FixedPointReport, InterfaceNode,
    ModelSummary, NodeStatus, PairSummary, StatusCounts, TractionBound,
};

pub use warning::{Warning, ZoneLimit};

/// A duration as seconds (for serialised reports).
#[cfg(feature = "serde")]
fn seconds<S: serde::Serializer>(d: &std::time::Duration, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_f64(d.as_secs_f64())
}

/// A duration read from its seconds (the form [`seconds`] writes); negative or non-finite
/// seconds are an error.
#[cfg(feature = "serde")]
fn from_seconds<'de, D: serde::Deserializer<'de>>(d: D) -> Result<std::time::Duration, D::Error> {
    let s = <f64 as serde::Deserialize>::deserialize(d)?;
    std::time::Duration::try_from_secs_f64(s).map_err(serde::de::Error::custom)
}

pub use solver::{
    ActiveSetSettings, ActiveSetSolver, CondensedSettings, CondensedSolver, ConstraintRows,
    ContactForces, ContactSolution, ContactSolver, ContactSolverError, ContactSystem,
    ContactSystemError, Friction, InterfaceMethod, KktResiduals, KktScales, KktTolerance,
    PatternId, PenaltyParameter, PenaltySettings, PenaltySolver, SettingsError, SolveReport,
    SolveStatus, StageTimes, StiffnessBlock, WorkCounters,
};
#[cfg(feature = "clarabel")]
pub use solver::{ExactSettings, ExactSolver};
