//! Tresca friction with a given bound, problem P2.

use std::fmt;
use std::sync::Arc;

use vem_mesh::PointD;

use super::checked_bounds;
use crate::{ContactError, ContactLaw, ContactNode, LawState, SettingsError};

/// A scalar field of position in `R^D` (friction bound, imposed gap).
pub type ScalarField<const D: usize = 2> = Arc<dyn Fn(PointD<D>) -> f64 + Send + Sync>;

/// The friction bound `g_F` of Tresca's law: a constant or a function of position.
#[derive(Clone)]
pub enum FrictionBound<const D: usize = 2> {
    /// The same bound everywhere.
    Constant(f64),
    /// A bound depending on the position on the interface (evaluated at the nodes of body A).
    Field(ScalarField<D>),
}

impl<const D: usize> fmt::Debug for FrictionBound<D> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FrictionBound::Constant(g) => write!(f, "Constant({g})"),
            FrictionBound::Field(_) => write!(f, "Field(..)"),
        }
    }
}

/// Tresca friction (problem P2): `|sigma_tau| <= g_F`, with the nodal quadrature of `j_h`, so
/// the nodal bound is `b_i = l_i g_F(x_i)` (tributary measure times the bound). The bound does
/// not depend on the solution: one solve.
///
/// ```
/// use vem_contact::{ContactLaw, Tresca};
/// let tresca: Tresca = Tresca::try_new(0.3)?;
/// assert_eq!(ContactLaw::<2>::describe(&tresca), "tresca, g_F = 0.3");
/// assert!(Tresca::<2>::try_new(-1.0).is_err());
/// # Ok::<(), vem_contact::SettingsError>(())
/// ```
#[derive(Debug, Clone)]
pub struct Tresca<const D: usize = 2> {
    bound: FrictionBound<D>,
}

impl<const D: usize> Tresca<D> {
    /// Tresca with a constant bound `g_F`.
    ///
    /// # Errors
    /// [`SettingsError`] for a bound that is negative or not finite.
    pub fn try_new(friction_bound: f64) -> Result<Self, SettingsError> {
        SettingsError::non_negative("friction_bound", friction_bound)?;
        Ok(Self {
            bound: FrictionBound::Constant(friction_bound),
        })
    }

    /// Tresca with the bound `g_F(x)`; its values are checked at the interface nodes when the
    /// problem is discretised.
    pub fn with_field(bound: impl Fn(PointD<D>) -> f64 + Send + Sync + 'static) -> Self {
        Self {
            bound: FrictionBound::Field(Arc::new(bound)),
        }
    }

    /// Tresca with the bound `bound` (a constant one is checked here).
    ///
    /// # Errors
    /// [`SettingsError`] for a constant bound that is negative or not finite.
    pub fn try_from_bound(bound: FrictionBound<D>) -> Result<Self, SettingsError> {
        if let FrictionBound::Constant(g) = bound {
            SettingsError::non_negative("friction_bound", g)?;
        }
        Ok(Self { bound })
    }

    /// The friction bound `g_F`.
    pub fn bound(&self) -> &FrictionBound<D> {
        &self.bound
    }
}

impl<const D: usize> ContactLaw<D> for Tresca<D> {
    fn name(&self) -> &str {
        "tresca"
    }

    fn describe(&self) -> String {
        match &self.bound {
            FrictionBound::Constant(g) => format!("tresca, g_F = {g}"),
            FrictionBound::Field(_) => "tresca, g_F(x)".to_string(),
        }
    }

    fn has_friction(&self) -> bool {
        true
    }

    fn friction_bounds(
        &self,
        nodes: &[ContactNode<D>],
        _state: Option<&LawState<'_>>,
    ) -> Result<Vec<f64>, ContactError> {
        let g = |node: &ContactNode<D>| match &self.bound {
            FrictionBound::Constant(g) => *g,
            FrictionBound::Field(g) => g(node.position),
        };
        let values: Vec<f64> = nodes.iter().map(g).collect();
        let values = checked_bounds(nodes, values, "friction bound g_F", false)?;
        Ok(nodes
            .iter()
            .zip(values)
            .map(|(node, g)| node.tributary_measure * g)
            .collect())
    }
}
