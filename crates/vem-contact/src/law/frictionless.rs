//! Frictionless (Signorini-type) contact, problem P1.

use crate::{ContactError, ContactLaw, ContactNode, LawState};

/// Frictionless contact (problem P1): the interface transmits normal compression only, no
/// tangential rows are built for the pair (in a problem where another pair carries friction,
/// its nodes get the bound 0, the same problem).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Frictionless;

impl<const D: usize> ContactLaw<D> for Frictionless {
    fn name(&self) -> &str {
        "frictionless"
    }

    fn has_friction(&self) -> bool {
        false
    }

    fn friction_bounds(
        &self,
        nodes: &[ContactNode<D>],
        _state: Option<&LawState<'_>>,
    ) -> Result<Vec<f64>, ContactError> {
        Ok(vec![0.0; nodes.len()])
    }
}
