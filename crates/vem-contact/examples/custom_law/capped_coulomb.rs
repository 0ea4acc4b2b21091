//! A contact law written outside the contact crate: Coulomb friction capped by a shear
//! strength, `|sigma_tau| <= min(F |sigma_nu|, cap)` (the Coulomb-Orowan law of metal
//! forming, where the cap is the shear strength `m k` of the softer material: under high
//! pressure the interface shears at the cap instead of at `F p`).
//!
//! This file is all a law needs: the type, its `ContactLaw` implementation and the function
//! that registers it, with its settings, in a `LawRegistry`. It is shared by
//! `crates/vem-contact/examples/custom_law.rs` (the law on a block pressed and sheared on a
//! rigid line) and `crates/vem-scene/examples/custom_law_scene.rs` (the law named by a scene).

use std::sync::Arc;

use serde::Deserialize;
use vem_contact::{
    ContactError, ContactLaw, ContactNode, Coulomb, FixedPointSettings, LawRegistry, LawState,
    RegistryError, SettingsError,
};
use vem_space::{Options, OptionsError};

/// The law's name in the registry, in scene files and in reports.
pub const NAME: &str = "capped-coulomb";

/// Coulomb friction with coefficient `F`, capped by the shear strength `cap` (a force per
/// unit length in 2D, per unit area in 3D): the nodal friction bound is
/// `b_i = min(F lambda_N,i, l_i cap)`, with `lambda_N,i` the nodal normal force of the
/// previous solve and `l_i` the node's tributary measure (the nodal quadrature of `j_h`, as
/// for Tresca and Coulomb).
///
/// The bound depends on the normal forces, so the law declares the fixed point of Coulomb:
/// the discretisation repeats the solves, the bounds frozen at each, until the normal forces
/// settle. Before the first solve the Coulomb part holds every node (`+inf`), so the start
/// is Tresca with the cap.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CappedCoulomb {
    coulomb: Coulomb,
    cap: f64,
}

impl CappedCoulomb {
    /// The law with coefficient `F`, shear strength `cap` and the fixed-point settings.
    ///
    /// # Errors
    /// [`SettingsError`] for a coefficient or cap that is negative or not finite, or invalid
    /// fixed-point settings (those of [`Coulomb::try_with`]).
    pub fn try_new(
        coefficient: f64,
        cap: f64,
        fixed_point: FixedPointSettings,
    ) -> Result<Self, SettingsError> {
        let coulomb = Coulomb::try_with(coefficient, fixed_point)?;
        if !(cap.is_finite() && cap >= 0.0) {
            return Err(SettingsError {
                setting: "cap",
                value: cap,
                requirement: "finite and >= 0",
            });
        }
        Ok(Self { coulomb, cap })
    }
}

impl<const D: usize> ContactLaw<D> for CappedCoulomb {
    fn name(&self) -> &str {
        NAME
    }

    fn describe(&self) -> String {
        format!(
            "capped coulomb, F = {}, cap = {}",
            self.coulomb.coefficient(),
            self.cap
        )
    }

    fn has_friction(&self) -> bool {
        true
    }

    fn friction_bounds(
        &self,
        nodes: &[ContactNode<D>],
        state: Option<&LawState<'_>>,
    ) -> Result<Vec<f64>, ContactError> {
        // Coulomb's bounds (F lambda_N, or +inf before any solve), each capped by l_i cap.
        let coulomb = ContactLaw::<D>::friction_bounds(&self.coulomb, nodes, state)?;
        Ok(coulomb
            .into_iter()
            .zip(nodes)
            .map(|(b, node)| b.min(node.tributary_measure * self.cap))
            .collect())
    }

    fn fixed_point(&self) -> Option<FixedPointSettings> {
        ContactLaw::<D>::fixed_point(&self.coulomb)
    }
}

/// The settings a scene, a dict or a program gives the law: `coefficient`, `cap` and, as for
/// Coulomb, `fixed_point = { max_iterations, tolerance }`. Any other key is refused with its
/// path.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Settings {
    coefficient: f64,
    cap: f64,
    #[serde(default)]
    fixed_point: FixedPointSettings,
}

/// Registers the law as [`NAME`] in `laws`.
///
/// # Errors
/// [`RegistryError::DuplicateName`] if the name is taken.
pub fn register<const D: usize>(laws: &mut LawRegistry<D>) -> Result<(), RegistryError> {
    laws.register(
        NAME,
        "Coulomb friction capped by a shear strength: |sigma_tau| <= min(F |sigma_nu|, cap)",
        |options: &Options| {
            let s: Settings = options.parse()?;
            // The fixed-point settings name their keys without the table's: put it in front.
            s.fixed_point.validate().map_err(|e| {
                OptionsError::at(format!("fixed_point.{}", e.setting), e.to_string())
            })?;
            let law = CappedCoulomb::try_new(s.coefficient, s.cap, s.fixed_point)?;
            Ok(Arc::new(law) as Arc<dyn ContactLaw<D>>)
        },
    )
}
