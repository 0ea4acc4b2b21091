//! One registry of contact solvers for every tool: the scene files of `vem run`, `cargo xtask`
//! and the verification studies take solver names from a [`SolverRegistry`], and a user's own
//! solver joins them by [`SolverRegistry::register`].
//!
//! ```
//! use vem_contact::{ContactSolver, ExactSolver, SolverOptions, SolverRegistry};
//! let mut registry = SolverRegistry::builtin();
//! assert!(registry.names().contains(&"active-set"));
//! // A solver of one's own (here the exact solver under another name).
//! registry.register("my-qp", "my QP solver", |_options: &SolverOptions| {
//!     Ok(Box::new(ExactSolver::default()) as Box<dyn ContactSolver>)
//! })?;
//! let solver = registry.make("my-qp", &SolverOptions::default())?;
//! assert_eq!(solver.name(), "exact (clarabel)");
//! // An unknown name lists the known ones.
//! let error = registry.make("newton", &SolverOptions::default()).err().unwrap();
//! assert!(error.to_string().contains("active-set"));
//! # Ok::<(), vem_contact::RegistryError>(())
//! ```

use std::fmt;
use std::sync::Arc;

use crate::solver::{
    ActiveSetSettings, ActiveSetSolver, CondensedSettings, CondensedSolver, ContactSolver,
    PenaltyParameter, PenaltySettings, PenaltySolver, SettingsError,
};
#[cfg(feature = "clarabel")]
use crate::solver::{ExactSettings, ExactSolver};

/// Settings a solver may take from a scene or a command line; every one is optional (the
/// solver's default applies) and each solver's builder validates the values it uses. A solver
/// given an option it has no use for refuses it ([`SolverOptions::refuse`]), so that no setting
/// is silently ignored.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SolverOptions {
    tolerance: Option<f64>,
    max_iterations: Option<usize>,
    penalty: Option<PenaltyParameter>,
    augmentation: Option<PenaltyParameter>,
}

impl SolverOptions {
    /// The solver's stopping tolerance (relative; for the exact solver its gap and feasibility
    /// tolerances).
    pub fn tolerance(mut self, value: f64) -> Self {
        self.tolerance = Some(value);
        self
    }

    /// The solver's iteration limit.
    pub fn max_iterations(mut self, value: usize) -> Self {
        self.max_iterations = Some(value);
        self
    }

    /// The penalty parameter (penalty solvers).
    pub fn penalty(mut self, value: PenaltyParameter) -> Self {
        self.penalty = Some(value);
        self
    }

    /// The augmentation parameter (augmented-Lagrangian and active-set solvers).
    pub fn augmentation(mut self, value: PenaltyParameter) -> Self {
        self.augmentation = Some(value);
        self
    }

    /// The tolerance, if given.
    pub fn tolerance_value(&self) -> Option<f64> {
        self.tolerance
    }

    /// The iteration limit, if given.
    pub fn max_iterations_value(&self) -> Option<usize> {
        self.max_iterations
    }

    /// The penalty parameter, if given.
    pub fn penalty_value(&self) -> Option<PenaltyParameter> {
        self.penalty
    }

    /// The augmentation parameter, if given.
    pub fn augmentation_value(&self) -> Option<PenaltyParameter> {
        self.augmentation
    }

    /// Fails with a [`SettingsError`] naming the first of `unused` ("tolerance",
    /// "max_iterations", "penalty", "augmentation") that is set: for a solver factory to refuse
    /// the options its solver has no use for.
    ///
    /// # Errors
    /// The first unused option that is set.
    pub fn refuse(&self, unused: &[&'static str]) -> Result<(), SettingsError> {
        for &name in unused {
            let value = match name {
                "tolerance" => self.tolerance,
                "max_iterations" => self.max_iterations.map(|m| m as f64),
                "penalty" => self.penalty.map(PenaltyParameter::number),
                "augmentation" => self.augmentation.map(PenaltyParameter::number),
                _ => None,
            };
            if let Some(value) = value {
                return Err(SettingsError {
                    setting: name,
                    value,
                    requirement: "unset: this solver does not use it",
                });
            }
        }
        Ok(())
    }
}

/// A function making a solver from options.
pub type SolverFactory =
    Arc<dyn Fn(&SolverOptions) -> Result<Box<dyn ContactSolver>, SettingsError> + Send + Sync>;

/// Why a registry refused a name.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum RegistryError {
    /// No solver has this name.
    #[error("unknown solver '{name}'; known solvers: {}", known.join(", "))]
    UnknownName {
        /// The name asked for.
        name: String,
        /// The names the registry knows.
        known: Vec<String>,
    },
    /// A solver with this name is registered already.
    #[error("a solver named '{name}' is registered already")]
    Duplicate {
        /// The name.
        name: String,
    },
    /// The solver refused its options.
    #[error("solver '{name}': invalid options")]
    Settings {
        /// The solver's name.
        name: String,
        /// The option it refused.
        #[source]
        source: SettingsError,
    },
}

struct Entry {
    name: String,
    summary: String,
    factory: SolverFactory,
}

/// Solvers by name (see the module docs).
#[derive(Clone)]
pub struct SolverRegistry {
    entries: Vec<Arc<Entry>>,
}

impl fmt::Debug for SolverRegistry {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("SolverRegistry")
            .field("names", &self.names())
            .finish()
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
        Self {
            entries: Vec::new(),
        }
    }

    /// The solvers of this crate: `"exact"` (`ExactSolver`, with the `clarabel` feature),
    /// `"penalty"` ([`PenaltySolver`]) and `"active-set"` ([`ActiveSetSolver`]).
    pub fn builtin() -> Self {
        let mut registry = Self::empty();
        #[allow(unused_mut)]
        let mut builtin: Vec<(&str, &str, SolverFactory)> = vec![
            (
                "condensed",
                "condensation onto the interface: one factorisation, exact dense interface problem",
                Arc::new(|o: &SolverOptions| {
                    o.refuse(&["penalty", "augmentation"])?;
                    let mut b = CondensedSettings::builder();
                    if let Some(t) = o.tolerance {
                        b = b.tolerance(t);
                    }
                    if let Some(m) = o.max_iterations {
                        b = b.max_iterations(m);
                    }
                    Ok(Box::new(CondensedSolver::new(b.build()?)) as Box<dyn ContactSolver>)
                }),
            ),
            (
                "penalty",
                "penalty method, semismooth Newton with exact line search",
                Arc::new(|o: &SolverOptions| {
                    o.refuse(&["augmentation"])?;
                    let mut b = PenaltySettings::builder();
                    if let Some(t) = o.tolerance {
                        b = b.tolerance(t);
                    }
                    if let Some(m) = o.max_iterations {
                        b = b.max_iterations(m);
                    }
                    if let Some(p) = o.penalty {
                        b = b.penalty(p);
                    }
                    Ok(Box::new(PenaltySolver::new(b.build()?)) as Box<dyn ContactSolver>)
                }),
            ),
            (
                "active-set",
                "primal-dual active set on the exact KKT conditions",
                Arc::new(|o: &SolverOptions| {
                    o.refuse(&["penalty"])?;
                    let mut b = ActiveSetSettings::builder();
                    if let Some(t) = o.tolerance {
                        b = b.tolerance(t);
                    }
                    if let Some(m) = o.max_iterations {
                        b = b.max_iterations(m);
                    }
                    if let Some(a) = o.augmentation {
                        b = b.augmentation(a);
                    }
                    Ok(Box::new(ActiveSetSolver::new(b.build()?)) as Box<dyn ContactSolver>)
                }),
            ),
        ];
        #[cfg(feature = "clarabel")]
        builtin.insert(
            1,
            (
                "exact",
                "convex QP by Clarabel's interior point (tolerance: gap and feasibility)",
                Arc::new(|o: &SolverOptions| {
                    o.refuse(&["penalty", "augmentation"])?;
                    let mut b = ExactSettings::builder();
                    if let Some(t) = o.tolerance {
                        b = b.eps_abs(t).eps_rel(t);
                    }
                    if let Some(m) = o.max_iterations {
                        b = b.max_iterations(m);
                    }
                    Ok(Box::new(ExactSolver::new(b.build()?)) as Box<dyn ContactSolver>)
                }),
            ),
        );
        for (name, summary, factory) in builtin {
            registry.entries.push(Arc::new(Entry {
                name: name.to_string(),
                summary: summary.to_string(),
                factory,
            }));
        }
        registry
    }

    /// Adds a solver under `name` with a one-line `summary`.
    ///
    /// # Errors
    /// [`RegistryError::Duplicate`] if the name is taken.
    pub fn register(
        &mut self,
        name: impl Into<String>,
        summary: impl Into<String>,
        factory: impl Fn(&SolverOptions) -> Result<Box<dyn ContactSolver>, SettingsError>
            + Send
            + Sync
            + 'static,
    ) -> Result<(), RegistryError> {
        let name = name.into();
        if self.entries.iter().any(|e| e.name == name) {
            return Err(RegistryError::Duplicate { name });
        }
        self.entries.push(Arc::new(Entry {
            name,
            summary: summary.into(),
            factory: Arc::new(factory),
        }));
        Ok(())
    }

    /// The names, in the order of registration.
    pub fn names(&self) -> Vec<&str> {
        self.entries.iter().map(|e| e.name.as_str()).collect()
    }

    /// The one-line summary of `name`.
    pub fn summary(&self, name: &str) -> Option<&str> {
        self.entry(name).map(|e| e.summary.as_str())
    }

    /// Whether `name` is registered.
    pub fn contains(&self, name: &str) -> bool {
        self.entry(name).is_some()
    }

    /// A new solver `name` with `options`.
    ///
    /// # Errors
    /// [`RegistryError::UnknownName`] (listing the known names) or
    /// [`RegistryError::Settings`] naming the refused option.
    pub fn make(
        &self,
        name: &str,
        options: &SolverOptions,
    ) -> Result<Box<dyn ContactSolver>, RegistryError> {
        let entry = self.entry(name).ok_or_else(|| RegistryError::UnknownName {
            name: name.to_string(),
            known: self.names().into_iter().map(String::from).collect(),
        })?;
        (entry.factory)(options).map_err(|source| RegistryError::Settings {
            name: name.to_string(),
            source,
        })
    }

    fn entry(&self, name: &str) -> Option<&Entry> {
        self.entries.iter().find(|e| e.name == name).map(|e| &**e)
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
            let made = registry.make(name, &SolverOptions::default()).unwrap();
            assert_eq!(made.name(), solver);
        }
        assert!(registry.contains(SolverRegistry::DEFAULT));
    }

    #[test]
    fn options_are_validated_and_unused_ones_refused() {
        let registry = SolverRegistry::builtin();
        let bad = SolverOptions::default().tolerance(-1.0);
        match registry.make("penalty", &bad) {
            Err(RegistryError::Settings { source, .. }) => assert_eq!(source.setting, "tolerance"),
            other => panic!(
                "expected a settings error, got {:?}",
                other.map(|s| s.name())
            ),
        }
        let unused = SolverOptions::default().penalty(PenaltyParameter::Absolute(1e6));
        match registry.make("exact", &unused) {
            Err(RegistryError::Settings { source, .. }) => assert_eq!(source.setting, "penalty"),
            other => panic!("expected a refusal, got {:?}", other.map(|s| s.name())),
        }
        let mut registry = registry;
        let duplicate = registry.register("exact", "again", |_| {
            Ok(Box::new(ExactSolver::default()) as Box<dyn ContactSolver>)
        });
        assert!(matches!(duplicate, Err(RegistryError::Duplicate { .. })));
    }
}
