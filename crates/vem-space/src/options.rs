//! The settings of a registered item (an element, a stabilisation, a contact solver, a law) as
//! a table of named values, whatever wrote it: a scene file, a Python dict, a command line.
//! Each factory deserialises its own settings from the table, so a new setting is one field of
//! one type; an unknown or misplaced key is refused by the deserialisation with the path of the
//! key inside the table.
//!
//! ```
//! use serde::Deserialize;
//! use vem_space::Options;
//!
//! #[derive(Debug, Deserialize, PartialEq)]
//! #[serde(deny_unknown_fields)]
//! struct Settings {
//!     tolerance: f64,
//!     #[serde(default)]
//!     max_iterations: Option<usize>,
//! }
//! let options = Options::new().with("tolerance", 1e-8);
//! assert_eq!(options.parse::<Settings>()?, Settings { tolerance: 1e-8, max_iterations: None });
//! let err = Options::new().with("tolerance", 1e-8).with("tol", 2).parse::<Settings>().unwrap_err();
//! assert_eq!(err.path, "tol");
//! assert!(err.message.contains("unknown field `tol`"), "{}", err.message);
//! # Ok::<(), vem_space::OptionsError>(())
//! ```

use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};

/// A table of named settings (see the module docs).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct Options(Map<String, Value>);

/// Why a table of settings was refused: the path of the key inside the table (`"penalty.factor"`,
/// empty for the table as a whole) and what is wrong.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{}{message}", if path.is_empty() { String::new() } else { format!("`{path}`: ") })]
pub struct OptionsError {
    /// The key, as a dotted path inside the table (empty: the table itself).
    pub path: String,
    /// What is wrong.
    pub message: String,
}

impl OptionsError {
    /// An error at `path`.
    pub fn at(path: impl Into<String>, message: impl Into<String>) -> Self {
        Self {
            path: path.into(),
            message: message.into(),
        }
    }
}

impl Options {
    /// An empty table: every setting at its default.
    pub fn new() -> Self {
        Self::default()
    }

    /// The table of a JSON-like value; anything but a table (object) is an error.
    ///
    /// # Errors
    /// [`OptionsError`] when `value` is not a table.
    pub fn from_value(value: Value) -> Result<Self, OptionsError> {
        match value {
            Value::Object(map) => Ok(Self(map)),
            Value::Null => Ok(Self::new()),
            other => Err(OptionsError::at(
                "",
                format!("expected a table of settings, found {other}"),
            )),
        }
    }

    /// The table with the setting `key` set to `value`.
    ///
    /// # Panics
    /// If `value` does not serialise (never for numbers, strings, booleans, tables).
    pub fn with(mut self, key: impl Into<String>, value: impl Serialize) -> Self {
        let value = serde_json::to_value(value).expect("a setting serialises");
        self.0.insert(key.into(), value);
        self
    }

    /// Sets `key` to `value` (replacing any earlier value).
    pub fn insert(&mut self, key: impl Into<String>, value: Value) {
        self.0.insert(key.into(), value);
    }

    /// Removes `key`, returning its value.
    pub fn remove(&mut self, key: &str) -> Option<Value> {
        self.0.remove(key)
    }

    /// The value of `key`, if set.
    pub fn get(&self, key: &str) -> Option<&Value> {
        self.0.get(key)
    }

    /// True when no setting is given.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// The keys that are set, in order.
    pub fn keys(&self) -> impl Iterator<Item = &str> {
        self.0.keys().map(String::as_str)
    }

    /// The table as a JSON value.
    pub fn to_value(&self) -> Value {
        Value::Object(self.0.clone())
    }

    /// The settings of type `T` read from the table; errors name the key's path.
    ///
    /// # Errors
    /// [`OptionsError`] for an unknown key, a value of the wrong type, a missing required key.
    pub fn parse<T: DeserializeOwned>(&self) -> Result<T, OptionsError> {
        let value = self.to_value();
        serde_path_to_error::deserialize(value).map_err(|e| {
            let path = e.path().to_string();
            let path = if path == "." { String::new() } else { path };
            OptionsError {
                path,
                message: e.inner().to_string(),
            }
        })
    }

    /// Refuses every setting: for an item that takes none.
    ///
    /// # Errors
    /// [`OptionsError`] at the first key given.
    pub fn refuse_all(&self, item: &str) -> Result<(), OptionsError> {
        match self.keys().next() {
            None => Ok(()),
            Some(key) => Err(OptionsError::at(key, format!("{item} takes no settings"))),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, Deserialize)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)]
    struct Inner {
        factor: f64,
    }

    #[derive(Debug, Deserialize)]
    #[serde(deny_unknown_fields)]
    #[allow(dead_code)]
    struct Outer {
        penalty: Inner,
    }

    #[test]
    fn errors_carry_the_path_of_the_key() {
        let bad_type = Options::new().with("penalty", serde_json::json!({ "factor": "big" }));
        let err = bad_type.parse::<Outer>().unwrap_err();
        assert_eq!(err.path, "penalty.factor");
        let unknown = Options::new().with("penalty", serde_json::json!({ "value": 1.0 }));
        let err = unknown.parse::<Outer>().unwrap_err();
        assert_eq!(err.path, "penalty.value");
        let missing = Options::new().parse::<Outer>().unwrap_err();
        assert_eq!(missing.path, "");
        assert!(missing.message.contains("missing field `penalty`"));
        assert!(Options::from_value(Value::from(3)).is_err());
        assert_eq!(
            Options::new()
                .with("x", 1)
                .refuse_all("p1")
                .unwrap_err()
                .to_string(),
            "`x`: p1 takes no settings"
        );
    }
}
