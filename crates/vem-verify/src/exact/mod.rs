//! Exact (manufactured) solutions of the one- and two-body problems of the specification
//! `docs/manufactured.md` (section numbers below refer to it).
//!
//! The trait [`ExactSolution`] describes a linear-elasticity solution on one rectangle or on
//! two stacked rectangles: material, domains, displacement, gradient, stress, body force and
//! the Dirichlet and Neumann sides with their data. A two-body contact solution also
//! implements [`ExactContact`]: law (any [`vem_contact::ContactLaw`]), initial gap, interface values in the sign conventions
//! of `docs/formulation.md`, expected active and stick/slip sets, resultants.
//!
//! Built-in cases (constructors take the [`Lame`] parameters; [`Lame::default`] is the
//! reference material `lambda = 2`, `mu = 1`):
//!
//! | name | type | problem |
//! |---|---|---|
//! | M1, M2, M3, M4 | [`FamilyA`] | two bodies: contact/separation, Tresca stick/slip, full contact, no contact |
//! | your own | [`InterfaceData`] | two bodies, Family A from interface data you give |
//! | E1, E2 | [`E1`], [`E2`] | one body, clamped: trigonometric; divergence free (locking) |
//! | PT0a, PT0b | [`AffinePatch`] | one body, linear patch tests |
//! | PTC1, PTC1h, PTC2, PTC3 | [`ContactPatch`] | two bodies, linear contact patch tests |
//! | E2c | [`DivergenceFreeContact`] | two bodies, frictionless full contact, divergence free (locking); not in [`CASE_NAMES`] |
//!
//! ```
//! use vem_verify::exact::{case_by_name, BodyId, Lame};
//! use vem_mesh::Point;
//! let m3 = case_by_name("M3", Lame::default())?;
//! let u = m3.displacement(BodyId::One, Point::new(0.25, 1.0 / 3.0));
//! assert!((u.x - 1.0 / 60.0).abs() < 1e-15);
//! let contact = m3.contact().expect("M3 is a contact problem");
//! assert!(contact.interface_values(0.5).sigma_nu <= -1.0);
//! # Ok::<(), vem_verify::exact::ExactError>(())
//! ```

mod contact_patch;
mod divergence_free;
mod elasticity;
mod error;
mod family_a;
mod hertz;
mod jet;
mod solution;

pub use contact_patch::{ContactPatch, PATCH_FRICTION_BOUND};
pub use divergence_free::{DivergenceFreeContact, DIVERGENCE_FREE_GAP};
pub use elasticity::{AffinePatch, E1, E2};
pub use error::ExactError;
pub use family_a::{
    FamilyA, InterfaceData, TraceData, Traces, CONTACT_SWITCH_POINT, FAMILY_A_FRICTION_BOUND,
    STICK_SLIP_POINT,
};
pub use hertz::{HertzContact, HertzSphere};
pub use jet::{Jet, SwitchPower, SwitchSide};
pub use solution::{
    BodyId, ContactSet, ExactContact, ExactSolution, ExpectedSets, FrictionSet, InterfaceValues,
    Lame, Resultants, Side, CONTACT_SIDES,
};

/// A constructor of a built-in case.
pub(crate) type Constructor = fn(Lame) -> Box<dyn ExactSolution>;

/// The built-in cases, in the order of the specification.
pub(crate) const CASES: [(&str, Constructor); 12] = [
    ("M1", |lame| Box::new(FamilyA::m1(lame))),
    ("M2", |lame| Box::new(FamilyA::m2(lame))),
    ("M3", |lame| Box::new(FamilyA::m3(lame))),
    ("M4", |lame| Box::new(FamilyA::m4(lame))),
    ("E1", |lame| Box::new(E1::new(lame))),
    ("E2", |lame| Box::new(E2::new(lame))),
    ("PT0a", |lame| Box::new(AffinePatch::pt0a(lame))),
    ("PT0b", |lame| Box::new(AffinePatch::pt0b(lame))),
    ("PTC1", |lame| Box::new(ContactPatch::ptc1(lame))),
    ("PTC1h", |lame| Box::new(ContactPatch::ptc1h(lame))),
    ("PTC2", |lame| Box::new(ContactPatch::ptc2(lame))),
    ("PTC3", |lame| Box::new(ContactPatch::ptc3(lame))),
];

/// The names of the built-in cases, in the order of [`all_cases`]:
/// M1, M2, M3, M4, E1, E2, PT0a, PT0b, PTC1, PTC1h, PTC2, PTC3.
pub const CASE_NAMES: [&str; CASES.len()] = {
    let mut names = [""; CASES.len()];
    let mut i = 0;
    while i < CASES.len() {
        names[i] = CASES[i].0;
        i += 1;
    }
    names
};

/// The built-in case `name` (one of [`CASE_NAMES`], ASCII case-insensitive) with the material
/// `lame`.
///
/// # Errors
/// [`ExactError::UnknownCase`] for any other name.
pub fn case_by_name(name: &str, lame: Lame) -> Result<Box<dyn ExactSolution>, ExactError> {
    CASES
        .iter()
        .find(|(known, _)| known.eq_ignore_ascii_case(name))
        .map(|(_, construct)| construct(lame))
        .ok_or_else(|| ExactError::UnknownCase {
            name: name.to_owned(),
            known: CASE_NAMES.join(", "),
        })
}

/// Every built-in case with the material `lame`, in the order of [`CASE_NAMES`].
pub fn all_cases(lame: Lame) -> Vec<Box<dyn ExactSolution>> {
    CASES.iter().map(|(_, construct)| construct(lame)).collect()
}
