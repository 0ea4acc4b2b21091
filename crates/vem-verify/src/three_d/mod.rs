//! Verification in three dimensions: exact solutions on the unit cube, error measures on
//! polyhedral meshes, the patch test and the convergence study of the lowest-order VEM on
//! every polyhedral family (`docs/manufactured.md`, section 11; `docs/polyhedral.md`).
//!
//! - [`ExactSolution3d`] and the built-in cases [`LinearSolid`] ("PT0-3D", the patch test),
//!   [`SmoothSolid`] ("E1-3D", with a traction side) and [`DivergenceFreeSolid`] ("E2-3D", for
//!   the locking study);
//! - [`DiscContact`] ("M1-3D"): frictionless contact of two stacked boxes on a disc, the case
//!   of Theorem 4.1 in space, each body an [`ExactSolution3d`] ([`DiscContact::body`]);
//! - [`StickSlipContact`] ("M2-3D"): Tresca friction between the same boxes, sticking inside a
//!   disc and slipping outside, the case of Theorem 4.2 in space; both are [`StackedContact`]
//!   cases;
//! - [`projection_errors_3d`], [`energy_error_3d`], [`body_errors_3d`]: `E_grad`, `E_0`, `E_a`;
//! - [`solid_body`], [`solve_solid`], [`run_solid`], [`three_d_convergence`]: the discrete
//!   problems on the families of `vem_mesh::generators::polyhedral` and the study over sizes;
//!   [`disc_contact_problem`], [`solve_disc_contact`], [`run_disc_contact`]: the contact
//!   problem of a [`StackedContact`] case on two non-matching meshes; [`solid_rates`] and
//!   [`solid_markdown`] fit and print the rates of both.
//!
//! ```
//! use std::sync::Arc;
//! use vem_mesh::generators::polyhedral::PolyhedralFamily;
//! use vem_space::PolyhedralVem;
//! use vem_verify::exact::Lame;
//! use vem_verify::three_d::{run_solid, LinearSolid};
//! // The patch test on octree cubes with hanging nodes: exact to round-off.
//! let run = run_solid(
//!     Arc::new(LinearSolid::new(Lame::REFERENCE)),
//!     PolyhedralFamily::Octree,
//!     2,
//!     Arc::new(PolyhedralVem::default()),
//! )?;
//! assert!(run.nodal_error < 1e-12 && run.errors.relative_grad() < 1e-12);
//! # Ok::<(), vem_verify::VerifyError>(())
//! ```

mod disc_contact;
mod exact;
mod norms;
mod stick_slip;
mod study;

pub use disc_contact::{DiscContact, DiscContactBody, InterfaceValues3d, StackedContact};
pub use exact::{
    solid_case_by_name, DivergenceFreeSolid, ExactSolution3d, LinearSolid, SmoothSolid, CUBE_PARTS,
    SOLID_CASE_NAMES,
};
pub use norms::{body_errors_3d, energy_error_3d, nodal_interpolant_3d, projection_errors_3d};
pub use stick_slip::{StickSlipBody, StickSlipContact};
pub use study::{
    disc_contact_problem, disc_contact_scene, run_disc_contact, run_solid, solid_body,
    solid_markdown, solid_rates, solid_scene, solve_disc_contact, solve_solid, three_d_convergence,
    SolidContact, SolidRates, SolidRun, SOLID_SEED,
};
