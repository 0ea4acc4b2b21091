//! A registry of exact solutions by name: the built-in cases and a user's own, each with what
//! a study of it must show. Tools that take a case name (`cargo xtask convergence --case`)
//! look it up here, so a case registered by a user is run like a built-in one.
//!
//! ```
//! use std::sync::Arc;
//! use vem_verify::cases::CaseRegistry;
//! use vem_verify::exact::{FamilyA, Lame};
//! use vem_verify::study::Expectation;
//! let mut cases = CaseRegistry::builtin();
//! assert!(cases.names().contains(&"M2"));
//! // A user case under its own name (here M3 at another material, for brevity).
//! cases.register(
//!     "M3-soft",
//!     "M3 with lambda = 10, mu = 1/2",
//!     Expectation::OPTIMAL_RATES,
//!     |_| Arc::new(FamilyA::m3(Lame::try_new(10.0, 0.5).expect("valid"))),
//! )?;
//! let case = cases.make("m3-SOFT", Lame::default())?;
//! assert_eq!(case.lame().mu(), 0.5);
//! assert!(cases.register("M3-soft", "again", Expectation::OPTIMAL_RATES,
//!     |l| Arc::new(FamilyA::m3(l))).is_err());
//! # Ok::<(), vem_verify::exact::ExactError>(())
//! ```

use std::fmt;
use std::sync::Arc;

use crate::exact::{ExactError, ExactSolution, Lame, CASES};
use crate::study::Expectation;

/// Relative error the patch tests must stay below in a study with the default solvers (their
/// discrete solution is the exact one up to the solvers' accuracy).
pub const PATCH_TOLERANCE: f64 = 1e-6;

/// Builds a case for the given material.
pub type CaseFactory = dyn Fn(Lame) -> Arc<dyn ExactSolution> + Send + Sync;

/// One registered case.
#[derive(Clone)]
struct Entry {
    name: String,
    summary: String,
    expectation: Expectation,
    factory: Arc<CaseFactory>,
}

/// Exact solutions by name (ASCII case-insensitive), each with a one-line summary and the
/// [`Expectation`] a study of it must meet.
#[derive(Clone, Default)]
pub struct CaseRegistry {
    entries: Vec<Entry>,
}

impl fmt::Debug for CaseRegistry {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("CaseRegistry")
            .field("names", &self.names())
            .finish()
    }
}

/// The summary and expectation of a built-in case.
fn builtin_entry(name: &str) -> (&'static str, Expectation) {
    let exact = Expectation::Exact {
        tolerance: PATCH_TOLERANCE,
    };
    match name {
        "M1" => (
            "two bodies, frictionless: contact then separation (Theorem 4.1)",
            Expectation::OPTIMAL_RATES,
        ),
        "M2" => (
            "two bodies, Tresca g_F = 1/4: full contact, stick then slip (Theorem 4.2)",
            Expectation::OPTIMAL_RATES,
        ),
        "M3" => (
            "two bodies, frictionless, full contact",
            Expectation::OPTIMAL_RATES,
        ),
        "M4" => (
            "two bodies, frictionless, no contact",
            Expectation::OPTIMAL_RATES,
        ),
        "E1" => (
            "one clamped body, trigonometric",
            Expectation::OPTIMAL_RATES,
        ),
        "E2" => (
            "one clamped body, divergence free",
            Expectation::OPTIMAL_RATES,
        ),
        "PT0a" | "PT0b" => ("one body, linear patch test", exact),
        _ => ("two bodies, linear contact patch test", exact),
    }
}

impl CaseRegistry {
    /// An empty registry.
    pub fn new() -> Self {
        Self::default()
    }

    /// The built-in cases ([`CASE_NAMES`](crate::exact::CASE_NAMES)): M1–M4, E1, E2
    /// expected at the optimal rates ([`Expectation::OPTIMAL_RATES`]), the patch tests exact
    /// within [`PATCH_TOLERANCE`].
    pub fn builtin() -> Self {
        let entries = CASES
            .iter()
            .map(|&(name, construct)| {
                let (summary, expectation) = builtin_entry(name);
                let factory: Arc<CaseFactory> = Arc::new(move |lame| Arc::from(construct(lame)));
                Entry {
                    name: name.to_string(),
                    summary: summary.to_string(),
                    expectation,
                    factory,
                }
            })
            .collect();
        Self { entries }
    }

    /// Adds the case `name` built by `factory` from the material of a study.
    ///
    /// # Errors
    /// [`ExactError::DuplicateCase`] when the name (ASCII case-insensitive) is taken or
    /// empty.
    pub fn register(
        &mut self,
        name: impl Into<String>,
        summary: impl Into<String>,
        expectation: Expectation,
        factory: impl Fn(Lame) -> Arc<dyn ExactSolution> + Send + Sync + 'static,
    ) -> Result<(), ExactError> {
        let name = name.into();
        if name.trim().is_empty() || self.entry(&name).is_some() {
            return Err(ExactError::DuplicateCase {
                name,
                known: self.names().join(", "),
            });
        }
        self.entries.push(Entry {
            name,
            summary: summary.into(),
            expectation,
            factory: Arc::new(factory),
        });
        Ok(())
    }

    fn entry(&self, name: &str) -> Option<&Entry> {
        self.entries
            .iter()
            .find(|e| e.name.eq_ignore_ascii_case(name))
    }

    /// The names, in the order of registration (built-in cases first).
    pub fn names(&self) -> Vec<&str> {
        self.entries.iter().map(|e| e.name.as_str()).collect()
    }

    /// The one-line summary of the case `name`.
    pub fn summary(&self, name: &str) -> Option<&str> {
        self.entry(name).map(|e| e.summary.as_str())
    }

    /// What a study of the case `name` must show.
    pub fn expectation(&self, name: &str) -> Option<Expectation> {
        self.entry(name).map(|e| e.expectation)
    }

    /// The case `name` with the material `lame`.
    ///
    /// # Errors
    /// [`ExactError::UnknownCase`] listing the registered names.
    pub fn make(&self, name: &str, lame: Lame) -> Result<Arc<dyn ExactSolution>, ExactError> {
        let entry = self.entry(name).ok_or_else(|| ExactError::UnknownCase {
            name: name.to_owned(),
            known: self.names().join(", "),
        })?;
        Ok((entry.factory)(lame))
    }
}
