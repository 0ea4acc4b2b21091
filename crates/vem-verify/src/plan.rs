//! The project's convergence run in the plane (`cargo xtask convergence`, `docs/convergence.md`):
//! which studies a case gets (the contact pairings of a two-body case, the elasticity families
//! of a one-body case) and at which sizes, in the full run and in the quick one. The `xtask`
//! command and the Python package run the same plan.
//!
//! ```
//! use vem_verify::cases::CaseRegistry;
//! use vem_verify::plan::{planned_studies, CONTACT_PAIRINGS, QUICK_SIZES};
//! let studies = planned_studies("M1", true, &CaseRegistry::builtin())?;
//! assert_eq!(studies.len(), CONTACT_PAIRINGS.len());
//! assert_eq!(studies[0].pairing, "quads/quads");
//! assert_eq!(studies[0].sizes, QUICK_SIZES);
//! # Ok::<(), vem_verify::ExactError>(())
//! ```

use crate::cases::CaseRegistry;
use crate::exact::{ExactError, Lame};
use crate::study::Expectation;

/// Mesh pairings (body 1 / body 2) of the contact studies: matching structured quads,
/// non-matching 1:3 quads, Voronoi over quads, non-convex over triangles, perturbed quads over
/// hexagons.
pub const CONTACT_PAIRINGS: [&str; 5] = [
    "quads/quads",
    "quads/quads*3",
    "voronoi/quads",
    "nonconvex/triangles",
    "perturbed/hexagons",
];

/// Mesh families of the elasticity studies (one body).
pub const ELASTICITY_FAMILIES: [&str; 3] = ["quads", "voronoi", "perturbed"];

/// Sizes n of the full run (body 2 of the 1:3 pairing has 3n cells across).
pub const SIZES: &[usize] = &[8, 16, 32, 64, 128];
/// Sizes of the 1:3 pairing in the full run (its finest mesh has 3 x 64 = 192 cells across).
pub const SIZES_ONE_TO_THREE: &[usize] = &[8, 16, 32, 64];
/// Sizes of the quick run.
pub const QUICK_SIZES: &[usize] = &[8, 16, 32];
/// Sizes of the 1:3 pairing in the quick run.
pub const QUICK_SIZES_ONE_TO_THREE: &[usize] = &[8, 16, 32];

/// The cases in the plane of the default run.
pub const DEFAULT_CASES: [&str; 3] = ["M1", "M2", "E1"];

/// One planned study: a case on a mesh pairing at a list of sizes, judged by an expectation.
#[derive(Debug, Clone, PartialEq)]
pub struct PlannedStudy {
    /// The case's name in the case registry.
    pub case: String,
    /// The mesh pairing ([`crate::study::MeshPairing`]'s form: "quads/quads*3", "voronoi").
    pub pairing: &'static str,
    /// The sizes n, coarse to fine.
    pub sizes: &'static [usize],
    /// What the study must show (the registry's expectation of the case, else the optimal
    /// rates).
    pub expectation: Expectation,
}

/// The sizes of a study on `pairing` in the quick or the full run.
pub fn sizes_for(quick: bool, pairing: &str) -> &'static [usize] {
    match (quick, pairing.contains("*3")) {
        (false, false) => SIZES,
        (false, true) => SIZES_ONE_TO_THREE,
        (true, false) => QUICK_SIZES,
        (true, true) => QUICK_SIZES_ONE_TO_THREE,
    }
}

/// The studies of the case `name` (any name of `cases`, in any case): on every contact pairing
/// for a case of two bodies, on every elasticity family for a case of one body, each at the
/// sizes of the quick or the full run.
///
/// # Errors
/// [`ExactError::UnknownCase`] for a name the registry lacks.
pub fn planned_studies(
    name: &str,
    quick: bool,
    cases: &CaseRegistry,
) -> Result<Vec<PlannedStudy>, ExactError> {
    let case = cases.make(name, Lame::default())?;
    let name = case.name().to_string();
    let expectation = cases
        .expectation(&name)
        .unwrap_or(Expectation::OPTIMAL_RATES);
    let pairings: &[&'static str] = if case.bodies().len() == 2 {
        &CONTACT_PAIRINGS
    } else {
        &ELASTICITY_FAMILIES
    };
    Ok(pairings
        .iter()
        .map(|&pairing| PlannedStudy {
            case: name.clone(),
            pairing,
            sizes: sizes_for(quick, pairing),
            expectation,
        })
        .collect())
}
