//! Coulomb friction by a fixed point of Tresca problems.

use super::{ContactLaw, FixedPointSettings, LawState};
use crate::{ContactError, ContactNode, SettingsError};

/// Coulomb friction `g_F = F |sigma_nu|`, by a fixed point of Tresca problems with the bound
/// frozen at each step (the paper's remark): the nodal bound of a step is
/// `b_i = F lambda_N,i` from the normal forces of the previous solve (the nodal form of
/// `F |sigma_nu|` times the tributary measure).
///
/// The fixed point starts from a state with friction capacity: from rest, the first solve
/// holds the tangential motion of every node (`b_i = +inf`, the stick predictor) and gives
/// the normal forces of the first Coulomb bounds, so that a body held sideways only by
/// friction (a punch pushed and sheared by a rigid plate) is held from the first Tresca step
/// on. In a load history ([`LoadPath`](crate::LoadPath)) a step starts from the bounds of the
/// normal forces of the previous step. The same law serves a static problem (the one-step
/// history) and every step of a history, where the friction acts on the increment of the
/// tangential jump since the previous step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Coulomb {
    coefficient: f64,
    fixed_point: FixedPointSettings,
}

impl Coulomb {
    /// Coulomb with friction coefficient `F` and default fixed-point settings.
    ///
    /// # Errors
    /// [`SettingsError`] for a coefficient that is negative or not finite.
    pub fn try_new(coefficient: f64) -> Result<Self, SettingsError> {
        Self::try_with(coefficient, FixedPointSettings::default())
    }

    /// Coulomb with friction coefficient `F` and the given fixed-point settings.
    ///
    /// # Errors
    /// [`SettingsError`] for a coefficient that is negative or not finite, or invalid
    /// fixed-point settings.
    pub fn try_with(
        coefficient: f64,
        fixed_point: FixedPointSettings,
    ) -> Result<Self, SettingsError> {
        SettingsError::non_negative("coefficient", coefficient)?;
        fixed_point.validate()?;
        Ok(Self {
            coefficient,
            fixed_point,
        })
    }

    /// The friction coefficient `F`.
    pub fn coefficient(&self) -> f64 {
        self.coefficient
    }

    /// The fixed-point settings.
    pub fn settings(&self) -> FixedPointSettings {
        self.fixed_point
    }
}

impl<const D: usize> ContactLaw<D> for Coulomb {
    fn name(&self) -> &str {
        "coulomb"
    }

    fn describe(&self) -> String {
        format!("coulomb, F = {}", self.coefficient)
    }

    fn has_friction(&self) -> bool {
        true
    }

    fn friction_bounds(
        &self,
        nodes: &[ContactNode<D>],
        state: Option<&LawState<'_>>,
    ) -> Result<Vec<f64>, ContactError> {
        Ok(match state {
            None => vec![f64::INFINITY; nodes.len()],
            Some(state) => state
                .normal_forces
                .iter()
                .map(|&f| self.coefficient * f.max(0.0))
                .collect(),
        })
    }

    fn fixed_point(&self) -> Option<FixedPointSettings> {
        Some(self.fixed_point)
    }
}
