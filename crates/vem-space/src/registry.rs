//! Element types by name: the one list the CLI, the studies and a user's program share.

use std::fmt;
use std::sync::Arc;

use crate::{
    BBar, DRecipe, DofiDofi, ElementSpace, LinearTriangle, LowestOrderVem, StabilisationScaling,
};

/// What builds an element of a registered name.
pub type ElementFactory = Arc<dyn Fn() -> Arc<dyn ElementSpace> + Send + Sync>;

/// What can go wrong with a registry of names (of elements here; the contact layer uses the
/// same error for its solvers).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum RegistryError {
    /// No entry has this name.
    #[error("unknown {kind} '{name}' (known: {})", known.join(", "))]
    UnknownName {
        /// What is looked up ("element", "solver", ...).
        kind: &'static str,
        /// The name asked for.
        name: String,
        /// The registered names, in registration order.
        known: Vec<String>,
    },
    /// An entry with this name exists already.
    #[error("{kind} '{name}' is registered already")]
    DuplicateName {
        /// What is registered ("element", "solver", ...).
        kind: &'static str,
        /// The name.
        name: String,
    },
    /// A name must be non-empty and made of ASCII letters, digits, `-` and `_`.
    #[error("invalid {kind} name '{name}': use ASCII letters, digits, '-' and '_'")]
    InvalidName {
        /// What is registered ("element", "solver", ...).
        kind: &'static str,
        /// The name.
        name: String,
    },
}

/// One registered element type.
#[derive(Clone)]
struct Entry {
    name: String,
    summary: String,
    factory: ElementFactory,
}

/// Element types by name, each with a one-line summary and a factory.
///
/// [`ElementRegistry::builtin`] holds the elements of this crate; a user's own element is
/// added with [`ElementRegistry::register`] and is then available by name wherever the
/// registry is passed (scene files, studies).
///
/// ```
/// use std::sync::Arc;
/// use vem_space::{ElementRegistry, ElementSpace, LinearTriangle, RegistryError};
/// let mut registry = ElementRegistry::builtin();
/// assert_eq!(registry.names(), ["vem1", "vem1-shear", "vem1-drecipe", "vem1-bbar", "p1"]);
/// assert_eq!(registry.make(ElementRegistry::DEFAULT)?.name(), "vem1");
/// registry.register("my-p1", "the linear triangle again", || Arc::new(LinearTriangle))?;
/// assert_eq!(registry.make("my-p1")?.name(), "p1");
/// let unknown = registry.make("vem2").err().expect("no element is named vem2");
/// assert_eq!(
///     unknown.to_string(),
///     "unknown element 'vem2' (known: vem1, vem1-shear, vem1-drecipe, vem1-bbar, p1, my-p1)"
/// );
/// # Ok::<(), RegistryError>(())
/// ```
#[derive(Clone)]
pub struct ElementRegistry {
    entries: Vec<Entry>,
}

impl Default for ElementRegistry {
    /// The built-in elements, as [`ElementRegistry::builtin`] (like the solver registry).
    fn default() -> Self {
        Self::builtin()
    }
}

impl ElementRegistry {
    /// The name of the default element: the lowest-order VEM, dofi-dofi scaled by `trace(C)`.
    pub const DEFAULT: &'static str = "vem1";

    /// A registry without any element.
    pub fn empty() -> Self {
        Self {
            entries: Vec::new(),
        }
    }

    /// The elements of this crate: `"vem1"` (default; dofi-dofi, `trace(C)`), `"vem1-shear"`
    /// (dofi-dofi, shear modulus), `"vem1-drecipe"` (D-recipe), `"vem1-bbar"` (locking-free:
    /// [`BBar`], the bulk part of the stabilisation bounded) and `"p1"` (linear triangle,
    /// triangles only). Each element's [`ElementSpace::name`] is its registry name.
    pub fn builtin() -> Self {
        let mut registry = Self::empty();
        let builtin: [(&str, &str, ElementFactory); 5] = [
            (
                "vem1",
                "lowest-order VEM, any polygon; dofi-dofi stabilisation alpha = trace(C)/8",
                Arc::new(|| Arc::new(LowestOrderVem::default())),
            ),
            (
                "vem1-shear",
                "lowest-order VEM, any polygon; dofi-dofi stabilisation alpha = 5 mu/8",
                Arc::new(|| {
                    Arc::new(LowestOrderVem::from_valid(Arc::new(DofiDofi::new(
                        StabilisationScaling::ShearModulus,
                    ))))
                }),
            ),
            (
                "vem1-drecipe",
                "lowest-order VEM, any polygon; D-recipe stabilisation S = diag(K_c)",
                Arc::new(|| Arc::new(LowestOrderVem::from_valid(Arc::new(DRecipe)))),
            ),
            (
                "vem1-bbar",
                "lowest-order VEM, any polygon; locking-free: alpha = min(trace(C), 3 trace(C_dev))/8",
                Arc::new(|| Arc::new(LowestOrderVem::from_valid(Arc::new(BBar)))),
            ),
            (
                "p1",
                "linear triangle (P1 finite element), triangles only",
                Arc::new(|| Arc::new(LinearTriangle)),
            ),
        ];
        for (name, summary, factory) in builtin {
            registry.entries.push(Entry {
                name: name.to_string(),
                summary: summary.to_string(),
                factory,
            });
        }
        registry
    }

    /// Adds the element `name` with a one-line `summary`, built by `factory`. The name must be
    /// new, non-empty and made of ASCII letters, digits, `-` and `_`.
    pub fn register(
        &mut self,
        name: impl Into<String>,
        summary: impl Into<String>,
        factory: impl Fn() -> Arc<dyn ElementSpace> + Send + Sync + 'static,
    ) -> Result<&mut Self, RegistryError> {
        let name = name.into();
        if name.is_empty()
            || !name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_')
        {
            return Err(RegistryError::InvalidName {
                kind: "element",
                name,
            });
        }
        if self.contains(&name) {
            return Err(RegistryError::DuplicateName {
                kind: "element",
                name,
            });
        }
        self.entries.push(Entry {
            name,
            summary: summary.into(),
            factory: Arc::new(factory),
        });
        Ok(self)
    }

    /// The registered names, in registration order.
    pub fn names(&self) -> Vec<&str> {
        self.entries.iter().map(|e| e.name.as_str()).collect()
    }

    /// Whether `name` is registered.
    pub fn contains(&self, name: &str) -> bool {
        self.entries.iter().any(|e| e.name == name)
    }

    /// The one-line summary of `name`, if registered.
    pub fn summary(&self, name: &str) -> Option<&str> {
        self.entries
            .iter()
            .find(|e| e.name == name)
            .map(|e| e.summary.as_str())
    }

    /// A new element of the type `name`; an unknown name is an error that lists the known
    /// ones.
    pub fn make(&self, name: &str) -> Result<Arc<dyn ElementSpace>, RegistryError> {
        match self.entries.iter().find(|e| e.name == name) {
            Some(entry) => Ok((entry.factory)()),
            None => Err(RegistryError::UnknownName {
                kind: "element",
                name: name.to_string(),
                known: self.entries.iter().map(|e| e.name.clone()).collect(),
            }),
        }
    }
}

impl fmt::Debug for ElementRegistry {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_map()
            .entries(self.entries.iter().map(|e| (&e.name, &e.summary)))
            .finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builtin_names_are_the_element_names() {
        let registry = ElementRegistry::builtin();
        for name in registry.names() {
            assert_eq!(registry.make(name).unwrap().name(), name);
            assert!(!registry.summary(name).unwrap().is_empty());
        }
        assert!(registry.contains(ElementRegistry::DEFAULT));
    }

    #[test]
    fn duplicate_and_invalid_names_are_errors() {
        let mut registry = ElementRegistry::builtin();
        let err = registry
            .register("p1", "again", || Arc::new(LinearTriangle))
            .unwrap_err();
        assert_eq!(
            err,
            RegistryError::DuplicateName {
                kind: "element",
                name: "p1".into()
            }
        );
        for bad in ["", "with space", "é"] {
            assert!(matches!(
                registry.register(bad, "", || Arc::new(LinearTriangle)),
                Err(RegistryError::InvalidName { .. })
            ));
        }
        assert_eq!(registry.names().len(), 5);
        assert_eq!(registry.summary("nothing"), None);
    }
}
