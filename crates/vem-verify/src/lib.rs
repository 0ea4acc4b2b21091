//! Verification of the VEM contact solver: exact (manufactured) solutions of the one- and
//! two-body problems of the specification, in the sign conventions of `docs/formulation.md`.
//!
//! The module [`exact`] holds the [`ExactSolution`] trait (implement it for a solution of your
//! own), its contact companion [`ExactContact`] (any law of `vem_contact`: frictionless, Tresca
//! with a constant or variable bound, Coulomb) and the built-in cases M1–M4, E1, E2,
//! PT0a, PT0b, PTC1, PTC1h, PTC2, PTC3.
//!
//! On top of them:
//! - [`problem`]: the discrete (VEM elasticity or contact) problem of an exact solution on given
//!   meshes, and its solve;
//! - [`norms`]: the error measures `E_grad = ||grad(u - Pi u_h)||`, `E_0 = ||u - Pi u_h||`
//!   and `E_a = a_h(u_I - u_h, u_I - u_h)^(1/2)` (`docs/manufactured.md`, section 8);
//! - [`diagnostics`]: resultants, switch points and expected sets of contact solutions;
//! - [`study`]: convergence studies over mesh sizes with fitted rates and a verdict;
//! - [`cases`]: the registry of cases by name (built-in and a user's own) the tools run;
//! - [`report`]: Markdown tables, log-log SVG plots and JSON;
//! - `plot` (feature `plots`): every plot of the workspace as an SVG document (charts of
//!   layers, the log-log plot of the studies, ticks), used by `report`, `cargo xtask` and
//!   `vem run`;
//! - `extremes` (feature `extremes`): the rows of the study of stability at the extremes, each
//!   with its independent expected answer, in the plane and in space;
//! - [`three_d`]: the same in space: exact solutions on the unit cube, errors on polyhedral
//!   meshes, the patch test and the convergence study on every polyhedral family.
//!
//! ```
//! use vem_verify::{all_cases, BodyId, ExactSolution, Lame};
//! use vem_mesh::Point;
//! // The body force balances the stress of every built-in case: check one component of
//! // -div sigma = f by central differences at an interior point.
//! for case in all_cases(Lame::default()) {
//!     let (x, h) = (Point::new(0.3, 0.4), 1e-4);
//!     let s = |dx: f64, dy: f64| case.stress(BodyId::One, Point::new(x.x + dx, x.y + dy));
//!     let div_x = (s(h, 0.0)[(0, 0)] - s(-h, 0.0)[(0, 0)]
//!         + s(0.0, h)[(0, 1)] - s(0.0, -h)[(0, 1)]) / (2.0 * h);
//!     let f = case.body_force(BodyId::One, x);
//!     assert!((div_x + f.x).abs() < 1e-5 * (1.0 + f.x.abs()), "{}", case.name());
//! }
//! ```
//!
//! # Cargo features
//!
//! `plots` (on by default) adds the module `plot` (SVG plots) and the log-log plots of
//! [`report`] (`report::plot_svg`, `report::write_plot`), and with them the `plotters`
//! dependency; `extremes` adds the module
//! `extremes` (the rows of the study of stability at the extremes) and with it the `vem-scene`
//! dependency; everything else needs no feature.
#![deny(missing_docs)]

pub mod adaptive;
pub mod cases;
pub mod diagnostics;
mod error;
pub mod exact;
#[cfg(feature = "extremes")]
pub mod extremes;
pub mod fretting;
pub mod norms;
pub mod plan;
#[cfg(feature = "plots")]
pub mod plot;
pub mod problem;
pub mod report;
pub mod study;
pub mod three_d;
pub mod tradeoff;

pub use error::VerifyError;
pub use exact::{
    all_cases, case_by_name, BodyId, ExactContact, ExactError, ExactSolution, Lame, Side,
};
/// The linear algebra the traits speak in (`nalgebra::Matrix2` for gradients and stresses).
pub use nalgebra;
