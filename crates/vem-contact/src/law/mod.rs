//! Contact laws: what the interface of a contact pair transmits, behind one trait.
//!
//! The discretisation builds the constraint rows of every pair once (a normal row per interface
//! node; tangential rows where some pair carries friction) and asks each pair's
//! [`ContactLaw`] for the nodal data of the next solve: the friction bound `b_i` of every node
//! (`l_i g_F(x_i)` with the nodal quadrature of `j_h`). A law sees a narrow view: the geometry of
//! its pair's nodes ([`ContactNode`]) and, once a solve has been made, the forces and jumps of
//! the last one ([`LawState`]). A law whose bounds depend on that state (Coulomb) declares a
//! fixed point ([`ContactLaw::fixed_point`]): the discretisation then repeats the solves, the
//! bounds frozen at each step, until the normal forces settle.
//!
//! Built in: [`Frictionless`] (problem P1), [`Tresca`] (P2, a constant or variable bound) and
//! [`Coulomb`] (`g_F = F |sigma_nu|` by a fixed point of Tresca problems). In a load history
//! ([`LoadPath`](crate::LoadPath)) every law acts on the increment of the tangential jump
//! since the previous step (the solvers' reference slip), so that Tresca and Coulomb are
//! path dependent there, as the physics asks. A law of one's own is
//! one type implementing [`ContactLaw`] (and, to reach it from scene files, one entry in the
//! law registry); `docs/extending.md` works one through.
//!
//! ```
//! use vem_contact::{ContactLaw, ContactNode, Coulomb, LawState};
//! use vem_mesh::{Point, Vector};
//! let coulomb = Coulomb::try_new(0.3)?;
//! let node = ContactNode::<2> {
//!     pair: 0, body_a: 0, vertex_a: 0, body_b: Some(1), vertex_b: Some(0),
//!     position: Point::new(0.0, 0.0), normal: Vector::new(0.0, -1.0),
//!     tributary_measure: 0.5, geometric_gap: 0.0, initial_gap: 0.0,
//! };
//! // Before any solve: the node is held (the fixed point starts from the stick predictor).
//! assert_eq!(coulomb.friction_bounds(&[node], None)?, vec![f64::INFINITY]);
//! // Then F times the nodal normal force of the last solve.
//! let state = LawState { normal_forces: &[2.0], tangential_forces: &[0.1], normal_jumps: &[0.0], slips: &[0.0] };
//! assert_eq!(coulomb.friction_bounds(&[node], Some(&state))?, vec![0.6]);
//! assert!(ContactLaw::<2>::fixed_point(&coulomb).is_some());
//! # Ok::<(), vem_contact::ContactError>(())
//! ```

mod coulomb;
mod frictionless;
mod tresca;

use std::fmt;

pub use coulomb::Coulomb;
pub use frictionless::Frictionless;
pub use tresca::{FrictionBound, ScalarField, Tresca};

use crate::{ContactError, ContactNode, SettingsError};

/// The forces and jumps of the last solve at the nodes of one contact pair (in the order of the
/// pair's nodes).
#[derive(Debug, Clone, Copy)]
pub struct LawState<'a> {
    /// Nodal normal forces `lambda_N,i >= 0` (compression).
    pub normal_forces: &'a [f64],
    /// Nodal friction forces `lambda_T` along the tangent directions of each node, `D - 1` per
    /// node, with the sign of the slip.
    pub tangential_forces: &'a [f64],
    /// Normal jumps `[u]_nu` (compared with the initial gap `h0`).
    pub normal_jumps: &'a [f64],
    /// Slips `[u]_tau` along the tangent directions, `D - 1` per node.
    pub slips: &'a [f64],
}

/// A contact law on the interface of a contact pair (see the module docs). Implementations
/// are thread-safe and cheap to share (`Arc<dyn ContactLaw<D>>`).
pub trait ContactLaw<const D: usize = 2>: Send + Sync + fmt::Debug {
    /// The law's name in reports and in the law registry ("frictionless", "tresca", ...).
    fn name(&self) -> &str;

    /// The law with its parameters, for reports ("coulomb, F = 0.3").
    fn describe(&self) -> String {
        self.name().to_string()
    }

    /// Whether the interface transmits friction: tangential rows are built for the pair.
    fn has_friction(&self) -> bool;

    /// The nodal friction bounds `b_i >= 0` (force; the disk radius in 3D) of the next solve at
    /// the pair's nodes `nodes`, from their geometry and, once a solve has been made, the
    /// state of the last one (`None` before the first solve of a problem from rest). A law
    /// without friction returns zeros. A bound `f64::INFINITY` holds the node: its tangential
    /// motion is not allowed (the stick predictor; Coulomb's start, whose friction capacity
    /// comes from normal forces not yet known).
    ///
    /// # Errors
    /// A bound that is negative or NaN (naming the node), or the law's own check.
    fn friction_bounds(
        &self,
        nodes: &[ContactNode<D>],
        state: Option<&LawState<'_>>,
    ) -> Result<Vec<f64>, ContactError>;

    /// `Some` when the bounds depend on the state: the solves are repeated, the bounds frozen at
    /// each step, until the normal forces settle (default: `None`, one solve).
    fn fixed_point(&self) -> Option<FixedPointSettings> {
        None
    }
}

/// Checks that the nodal bounds `bounds` of `nodes` are finite and `>= 0` (or `+inf` too when
/// `infinite` is true: a held node); the error names the first node that is not (`what`
/// describes the bound).
pub(crate) fn checked_bounds<const D: usize>(
    nodes: &[ContactNode<D>],
    bounds: Vec<f64>,
    what: &str,
    infinite: bool,
) -> Result<Vec<f64>, ContactError> {
    let valid = |b: f64| b >= 0.0 && (b.is_finite() || (infinite && b == f64::INFINITY));
    if nodes.len() != bounds.len() {
        return Err(ContactError::InvalidSetting {
            reason: format!(
                "{what}: {} values for {} interface nodes",
                bounds.len(),
                nodes.len()
            ),
        });
    }
    if let Some((node, b)) = nodes.iter().zip(&bounds).find(|(_, b)| !valid(**b)) {
        let requirement = if infinite {
            ">= 0 (finite, or +inf for a held node)"
        } else {
            "finite and >= 0"
        };
        return Err(ContactError::InvalidSetting {
            reason: format!(
                "{what} = {b} at {} must be {requirement}",
                crate::Location::of(&node.position)
            ),
        });
    }
    Ok(bounds)
}

/// Settings of a fixed point of Tresca problems (Coulomb); build them with
/// [`FixedPointSettings::builder`].
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FixedPointSettings {
    max_iterations: usize,
    tolerance: f64,
}

impl Default for FixedPointSettings {
    /// At most 50 Tresca steps, tolerance `1e-8`.
    fn default() -> Self {
        Self {
            max_iterations: 50,
            tolerance: 1e-8,
        }
    }
}

impl FixedPointSettings {
    /// A builder starting from the defaults.
    pub fn builder() -> FixedPointSettingsBuilder {
        FixedPointSettingsBuilder {
            settings: Self::default(),
        }
    }

    /// Largest number of Tresca steps (solves with the bounds of a state; the solve of a held
    /// start, from rest, is not counted).
    pub fn max_iterations(&self) -> usize {
        self.max_iterations
    }

    /// Stop when the largest change of a nodal normal force, relative to the largest normal
    /// force, falls below this, or below the force accuracy of the inner solver
    /// ([`ContactSolver::force_accuracy`](crate::ContactSolver::force_accuracy), `1e-4` for the
    /// default interior-point `ExactSolver`, `0` for the other solvers), whichever is larger:
    /// changes below the inner accuracy are noise of the inner solves and the fixed point
    /// would stall there. The tolerance used is in
    /// [`FixedPointReport::tolerance`](crate::FixedPointReport::tolerance).
    pub fn tolerance(&self) -> f64 {
        self.tolerance
    }

    /// Checks the settings (as [`FixedPointSettingsBuilder::build`]).
    ///
    /// # Errors
    /// [`SettingsError`] naming the first invalid setting.
    pub fn validate(&self) -> Result<(), SettingsError> {
        SettingsError::at_least_one("max_iterations", self.max_iterations)?;
        SettingsError::positive("tolerance", self.tolerance)?;
        Ok(())
    }

    /// The settings of several laws iterated together: the most iterations, the tightest
    /// tolerance.
    pub(crate) fn strictest(settings: impl IntoIterator<Item = Self>) -> Option<Self> {
        settings.into_iter().reduce(|a, b| Self {
            max_iterations: a.max_iterations.max(b.max_iterations),
            tolerance: a.tolerance.min(b.tolerance),
        })
    }
}

/// Builder of [`FixedPointSettings`]; values are checked by
/// [`FixedPointSettingsBuilder::build`].
#[derive(Debug, Clone, Copy)]
pub struct FixedPointSettingsBuilder {
    settings: FixedPointSettings,
}

impl FixedPointSettingsBuilder {
    /// Largest number of Tresca steps, `>= 1`.
    pub fn max_iterations(mut self, value: usize) -> Self {
        self.settings.max_iterations = value;
        self
    }

    /// Relative change of the normal forces at which to stop, finite and `> 0`.
    pub fn tolerance(mut self, value: f64) -> Self {
        self.settings.tolerance = value;
        self
    }

    /// Validates the settings.
    ///
    /// # Errors
    /// [`SettingsError`] naming the first invalid setting.
    pub fn build(self) -> Result<FixedPointSettings, SettingsError> {
        self.settings.validate()?;
        Ok(self.settings)
    }
}

impl<const D: usize, L: ContactLaw<D> + ?Sized> ContactLaw<D> for std::sync::Arc<L> {
    fn name(&self) -> &str {
        (**self).name()
    }

    fn describe(&self) -> String {
        (**self).describe()
    }

    fn has_friction(&self) -> bool {
        (**self).has_friction()
    }

    fn friction_bounds(
        &self,
        nodes: &[ContactNode<D>],
        state: Option<&LawState<'_>>,
    ) -> Result<Vec<f64>, ContactError> {
        (**self).friction_bounds(nodes, state)
    }

    fn fixed_point(&self) -> Option<FixedPointSettings> {
        (**self).fixed_point()
    }
}
