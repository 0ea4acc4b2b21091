//! One registry of contact solvers and one of contact laws for every tool: scene files, `cargo
//! xtask`, the verification studies and Python take names from them, and a user's own solver or
//! law joins them by `register`. Each factory reads its own settings from a table
//! ([`Options`]): a new setting is one field of the solver's (or law's) settings, in its own
//! file.
//!
//! ```
//! use vem_contact::{ContactSolver, ExactSolver, SolverRegistry};
//! use vem_space::Options;
//! let mut registry = SolverRegistry::builtin();
//! assert!(registry.names().contains(&"active-set"));
//! // A solver of one's own (here the exact solver under another name).
//! registry.register("my-qp", "my QP solver", |options: &Options| {
//!     options.refuse_all("my-qp")?;
//!     Ok(Box::new(ExactSolver::default()) as Box<dyn ContactSolver>)
//! })?;
//! assert_eq!(registry.make("my-qp", &Options::new())?.name(), "exact (clarabel)");
//! // Settings by name, checked by the solver; an unknown one is refused with its key.
//! let tight = Options::new().with("tolerance", 1e-10);
//! assert!(registry.make("condensed", &tight).is_ok());
//! let typo = Options::new().with("tolerence", 1e-10);
//! let error = registry.make("condensed", &typo).err().unwrap();
//! assert_eq!(error.option_path(), Some("tolerence"));
//! // An unknown name lists the known ones.
//! let error = registry.make("newton", &Options::new()).err().unwrap();
//! assert!(error.to_string().contains("active-set"));
//! # Ok::<(), vem_contact::RegistryError>(())
//! ```

use std::fmt;
use std::sync::Arc;

use serde::Deserialize;
use vem_space::{Choice, Options, OptionsError, Registry};

use crate::solver::{
    ActiveSetSettings, ActiveSetSolver, CondensedSettings, CondensedSolver, ContactSolver,
    PenaltySettings, PenaltySolver,
};
#[cfg(feature = "clarabel")]
use crate::solver::{ExactSettings, ExactSolver};
use crate::{ContactLaw, Coulomb, FixedPointSettings, Frictionless, Tresca};

pub use vem_space::RegistryError;

/// Contact solvers by name (see the module docs).
#[derive(Clone)]
pub struct SolverRegistry(Registry<Box<dyn ContactSolver>>);

impl fmt::Debug for SolverRegistry {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.0.fmt(f)
    }
}

impl Default for SolverRegistry {
    fn default() -> Self {
        Self::builtin()
    }
}

impl SolverRegistry {
    /// The name of the default solver: [`CondensedSolver`], exact and at the cost of about one
    /// factorisation of the stiffness.
    pub const DEFAULT: &'static str = "condensed";

    /// A registry without any solver.
    pub fn empty() -> Self {
        Self(Registry::empty("solver"))
    }

    /// The solvers of this crate: `"condensed"` ([`CondensedSolver`], the default),
    /// `"exact"` (`ExactSolver`, with the `clarabel` feature), `"penalty"` ([`PenaltySolver`])
    /// and `"active-set"` ([`ActiveSetSolver`]); each reads its settings with its
    /// `from_options` (e.g. [`CondensedSettings::from_options`]).
    pub fn builtin() -> Self {
        let mut registry = Self::empty();
        let r = &mut registry.0;
        r.register(
            "condensed",
            "condensation onto the interface: one factorisation, exact dense interface problem",
            |o| {
                Ok(
                    Box::new(CondensedSolver::new(CondensedSettings::from_options(o)?))
                        as Box<dyn ContactSolver>,
                )
            },
        )
        .expect("built-in names are valid and distinct");
        #[cfg(feature = "clarabel")]
        r.register(
            "exact",
            "convex QP by Clarabel's interior point (tolerance: gap and feasibility)",
            |o| {
                Ok(Box::new(ExactSolver::new(ExactSettings::from_options(o)?))
                    as Box<dyn ContactSolver>)
            },
        )
        .expect("built-in names are valid and distinct");
        r.register(
            "penalty",
            "penalty method, semismooth Newton with exact line search",
            |o| {
                Ok(
                    Box::new(PenaltySolver::new(PenaltySettings::from_options(o)?))
                        as Box<dyn ContactSolver>,
                )
            },
        )
        .expect("built-in names are valid and distinct");
        r.register(
            "active-set",
            "primal-dual active set on the exact KKT conditions",
            |o| {
                Ok(
                    Box::new(ActiveSetSolver::new(ActiveSetSettings::from_options(o)?))
                        as Box<dyn ContactSolver>,
                )
            },
        )
        .expect("built-in names are valid and distinct");
        registry
    }

    /// Adds a solver under `name` with a one-line `summary`, built from its settings by
    /// `factory`.
    ///
    /// # Errors
    /// [`RegistryError::DuplicateName`] if the name is taken, [`RegistryError::InvalidName`].
    pub fn register(
        &mut self,
        name: impl Into<String>,
        summary: impl Into<String>,
        factory: impl Fn(&Options) -> Result<Box<dyn ContactSolver>, OptionsError>
            + Send
            + Sync
            + 'static,
    ) -> Result<(), RegistryError> {
        self.0.register(name, summary, factory).map(|_| ())
    }

    /// The names, in the order of registration.
    pub fn names(&self) -> Vec<&str> {
        self.0.names()
    }

    /// The one-line summary of `name`.
    pub fn summary(&self, name: &str) -> Option<&str> {
        self.0.summary(name)
    }

    /// Whether `name` is registered.
    pub fn contains(&self, name: &str) -> bool {
        self.0.contains(name)
    }

    /// A new solver `name` with the settings `options`.
    ///
    /// # Errors
    /// [`RegistryError::UnknownName`] (listing the known names) or
    /// [`RegistryError::Options`] naming the refused setting.
    pub fn make(
        &self,
        name: &str,
        options: &Options,
    ) -> Result<Box<dyn ContactSolver>, RegistryError> {
        self.0.make(name, options)
    }

    /// The solver of a [`Choice`].
    ///
    /// # Errors
    /// As [`SolverRegistry::make`].
    pub fn make_choice(&self, choice: &Choice) -> Result<Box<dyn ContactSolver>, RegistryError> {
        self.0.make_choice(choice)
    }
}

/// Contact laws by name, in dimension `D`: `"frictionless"`, `"tresca"` (setting
/// `friction_bound`), `"coulomb"` (settings `coefficient`, `fixed_point = { max_iterations,
/// tolerance }`). A law of one's own joins with [`LawRegistry::register`].
///
/// ```
/// use vem_contact::LawRegistry;
/// use vem_space::Options;
/// let laws = LawRegistry::<2>::builtin();
/// let tresca = laws.make("tresca", &Options::new().with("friction_bound", 0.3))?;
/// assert_eq!(tresca.describe(), "tresca, g_F = 0.3");
/// // A setting of another law is refused by the law: misplaced keys are found.
/// let error = laws.make("tresca", &Options::new().with("coefficient", 0.3)).err().unwrap();
/// assert_eq!(error.option_path(), Some("coefficient"));
/// # Ok::<(), vem_contact::RegistryError>(())
/// ```
pub struct LawRegistry<const D: usize = 2>(Registry<Arc<dyn ContactLaw<D>>>);

impl<const D: usize> Clone for LawRegistry<D> {
    fn clone(&self) -> Self {
        Self(self.0.clone())
    }
}

impl<const D: usize> fmt::Debug for LawRegistry<D> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.0.fmt(f)
    }
}

impl<const D: usize> Default for LawRegistry<D> {
    fn default() -> Self {
        Self::builtin()
    }
}

/// The settings of Tresca's law.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct TrescaOptions {
    friction_bound: f64,
}

/// The settings of Coulomb's law.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct CoulombOptions {
    coefficient: f64,
    #[serde(default)]
    fixed_point: FixedPointSettings,
}

impl<const D: usize> LawRegistry<D> {
    /// The name of the default law.
    pub const DEFAULT: &'static str = "frictionless";

    /// A registry without any law.
    pub fn empty() -> Self {
        Self(Registry::empty("law"))
    }

    /// The laws of this crate: [`Frictionless`], [`Tresca`] and [`Coulomb`].
    pub fn builtin() -> Self {
        let mut registry = Self::empty();
        let r = &mut registry.0;
        r.register(
            "frictionless",
            "frictionless (Signorini-type) contact, problem P1",
            |o| {
                o.refuse_all("the frictionless law")?;
                Ok(Arc::new(Frictionless) as Arc<dyn ContactLaw<D>>)
            },
        )
        .expect("built-in names are valid and distinct");
        r.register(
            "tresca",
            "Tresca friction with the bound friction_bound (force per length), problem P2",
            |o| {
                let s: TrescaOptions = o.parse()?;
                Ok(Arc::new(Tresca::<D>::try_new(s.friction_bound)?) as Arc<dyn ContactLaw<D>>)
            },
        )
        .expect("built-in names are valid and distinct");
        r.register(
            "coulomb",
            "Coulomb friction with the coefficient F, by a fixed point of Tresca problems",
            |o| {
                let s: CoulombOptions = o.parse()?;
                let law = Coulomb::try_with(s.coefficient, s.fixed_point).map_err(|e| {
                    let mut e = OptionsError::from(e);
                    if e.path != "coefficient" {
                        e.path = format!("fixed_point.{}", e.path);
                    }
                    e
                })?;
                Ok(Arc::new(law) as Arc<dyn ContactLaw<D>>)
            },
        )
        .expect("built-in names are valid and distinct");
        registry
    }

    /// Adds a law under `name` with a one-line `summary`, built from its settings by
    /// `factory`.
    ///
    /// # Errors
    /// [`RegistryError::DuplicateName`] if the name is taken, [`RegistryError::InvalidName`].
    pub fn register(
        &mut self,
        name: impl Into<String>,
        summary: impl Into<String>,
        factory: impl Fn(&Options) -> Result<Arc<dyn ContactLaw<D>>, OptionsError>
            + Send
            + Sync
            + 'static,
    ) -> Result<(), RegistryError> {
        self.0.register(name, summary, factory).map(|_| ())
    }

    /// The names, in the order of registration.
    pub fn names(&self) -> Vec<&str> {
        self.0.names()
    }

    /// The one-line summary of `name`.
    pub fn summary(&self, name: &str) -> Option<&str> {
        self.0.summary(name)
    }

    /// Whether `name` is registered.
    pub fn contains(&self, name: &str) -> bool {
        self.0.contains(name)
    }

    /// A new law `name` with the settings `options`.
    ///
    /// # Errors
    /// [`RegistryError::UnknownName`] (listing the known names) or
    /// [`RegistryError::Options`] naming the refused setting.
    pub fn make(
        &self,
        name: &str,
        options: &Options,
    ) -> Result<Arc<dyn ContactLaw<D>>, RegistryError> {
        self.0.make(name, options)
    }

    /// The law of a [`Choice`].
    ///
    /// # Errors
    /// As [`LawRegistry::make`].
    pub fn make_choice(&self, choice: &Choice) -> Result<Arc<dyn ContactLaw<D>>, RegistryError> {
        self.0.make_choice(choice)
    }
}

#[cfg(all(test, feature = "clarabel"))]
mod tests {
    use super::*;

    #[test]
    fn builtin_names_make_their_solvers() {
        let registry = SolverRegistry::builtin();
        assert_eq!(
            registry.names(),
            ["condensed", "exact", "penalty", "active-set"]
        );
        for (name, solver) in [
            ("condensed", "condensed (interface Schur complement)"),
            ("exact", "exact (clarabel)"),
            ("penalty", "penalty (semismooth Newton)"),
            ("active-set", "active set (primal-dual)"),
        ] {
            let made = registry.make(name, &Options::new()).unwrap();
            assert_eq!(made.name(), solver);
        }
        assert!(registry.contains(SolverRegistry::DEFAULT));
    }

    #[test]
    fn settings_are_validated_and_unknown_ones_refused_with_their_key() {
        let registry = SolverRegistry::builtin();
        let bad = Options::new().with("tolerance", -1.0);
        let err = registry.make("penalty", &bad).err().unwrap();
        assert_eq!(err.option_path(), Some("tolerance"), "{err}");
        let unused = Options::new().with("penalty", serde_json::json!({ "factor": 1e6 }));
        let err = registry.make("exact", &unused).err().unwrap();
        assert_eq!(err.option_path(), Some("penalty"), "{err}");
        let both = Options::new().with("penalty", serde_json::json!({ "factor": 1, "value": 2 }));
        assert!(registry.make("penalty", &both).is_err());
        let fine = Options::new().with("penalty", serde_json::json!({ "value": 1e6 }));
        assert!(registry.make("penalty", &fine).is_ok());
        let mut registry = registry;
        let duplicate = registry.register("exact", "again", |_| {
            Ok(Box::new(ExactSolver::default()) as Box<dyn ContactSolver>)
        });
        assert!(matches!(
            duplicate,
            Err(RegistryError::DuplicateName { .. })
        ));
    }

    #[test]
    fn laws_read_their_settings() {
        let laws = LawRegistry::<2>::builtin();
        let coulomb = laws
            .make(
                "coulomb",
                &Options::new()
                    .with("coefficient", 0.3)
                    .with("fixed_point", serde_json::json!({ "tolerance": 1e-6 })),
            )
            .unwrap();
        assert_eq!(coulomb.describe(), "coulomb, F = 0.3");
        assert_eq!(coulomb.fixed_point().unwrap().tolerance(), 1e-6);
        let err = laws
            .make(
                "coulomb",
                &Options::new()
                    .with("coefficient", 0.3)
                    .with("fixed_point", serde_json::json!({ "max_iterations": 0 })),
            )
            .err()
            .unwrap();
        assert_eq!(
            err.option_path(),
            Some("fixed_point.max_iterations"),
            "{err}"
        );
        let err = laws
            .make("tresca", &Options::new().with("friction_bound", -1.0))
            .err()
            .unwrap();
        assert_eq!(err.option_path(), Some("friction_bound"), "{err}");
        assert!(laws
            .make("frictionless", &Options::new().with("coefficient", 1))
            .is_err());
    }
}
