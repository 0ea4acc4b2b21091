//! Where in a scene, and what: key paths and the errors and notes that carry them.

use std::fmt;

/// One step of a key path: a key of a table or an index of an array.
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Segment {
    /// A key.
    Key(String),
    /// An index (0-based).
    Index(usize),
}

/// The path of a key in a scene: `contact[0].law.friction_bound`. Written the way scene files
/// and Python dicts nest (`body[1].traction[0].pressure`); the front end maps it to a file
/// position.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Default, PartialOrd, Ord)]
pub struct KeyPath(pub Vec<Segment>);

impl KeyPath {
    /// The whole scene.
    pub fn root() -> Self {
        Self::default()
    }

    /// The path of a top-level key.
    pub fn key(name: &str) -> Self {
        Self(vec![Segment::Key(name.to_string())])
    }

    /// This path followed by the key `name`.
    pub fn at(&self, name: &str) -> Self {
        let mut path = self.clone();
        path.0.push(Segment::Key(name.to_string()));
        path
    }

    /// This path followed by the index `index`.
    pub fn index(&self, index: usize) -> Self {
        let mut path = self.clone();
        path.0.push(Segment::Index(index));
        path
    }

    /// This path followed by a dotted sub-path (`"penalty.factor"`, `"[2]"`, as an options
    /// table reports it).
    pub fn join(&self, dotted: &str) -> Self {
        let mut path = self.clone();
        for part in dotted.split('.').filter(|p| !p.is_empty()) {
            let (key, rest) = part.split_once('[').unwrap_or((part, ""));
            if !key.is_empty() {
                path.0.push(Segment::Key(key.to_string()));
            }
            for index in rest.split('[') {
                if let Ok(i) = index.trim_end_matches(']').parse() {
                    path.0.push(Segment::Index(i));
                }
            }
        }
        path
    }

    /// The longest prefix of this path for which `known` is true (the path itself when it is
    /// known; the root when no prefix is).
    pub fn known_prefix(&self, known: impl Fn(&KeyPath) -> bool) -> KeyPath {
        let mut path = self.clone();
        while !path.0.is_empty() && !known(&path) {
            path.0.pop();
        }
        path
    }
}

impl fmt::Display for KeyPath {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (k, segment) in self.0.iter().enumerate() {
            match segment {
                Segment::Key(key) if k == 0 => write!(f, "{key}")?,
                Segment::Key(key) => write!(f, ".{key}")?,
                Segment::Index(i) => write!(f, "[{i}]")?,
            }
        }
        Ok(())
    }
}

/// A scene that cannot be built or solved: where (the key path of the setting at fault, the
/// root when none applies) and what.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{}{message}", if path.0.is_empty() { String::new() } else { format!("{path}: ") })]
pub struct SceneError {
    /// The key at fault.
    pub path: KeyPath,
    /// What is wrong, with the cause told once.
    pub message: String,
}

impl SceneError {
    /// An error at `path`.
    pub fn at(path: KeyPath, message: impl Into<String>) -> Self {
        Self {
            path,
            message: message.into(),
        }
    }
}

/// `error` and its causes on one line ("a: b: c"), each cause once: a cause whose text the
/// error before it already spells out is not repeated.
pub fn one_line(error: &dyn std::error::Error) -> String {
    let mut text = error.to_string();
    let mut source = error.source();
    while let Some(cause) = source {
        let cause_text = cause.to_string();
        if !text.contains(&cause_text) {
            text.push_str(": ");
            text.push_str(&cause_text);
        }
        source = cause.source();
    }
    text
}

/// A scene key that still works but has a new place: the note names both.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub struct Deprecation {
    /// The key as written.
    pub old: String,
    /// Where it goes now, as a scene line.
    pub new: String,
}

impl fmt::Display for Deprecation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "`{}` has a new place: write {}", self.old, self.new)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_read_as_written() {
        let path = KeyPath::key("contact")
            .index(0)
            .at("law")
            .join("fixed_point.tolerance");
        assert_eq!(path.to_string(), "contact[0].law.fixed_point.tolerance");
        assert_eq!(
            KeyPath::key("body").join("[2].mesh").to_string(),
            "body[2].mesh"
        );
        let known = KeyPath::key("contact").index(0);
        assert_eq!(path.known_prefix(|p| *p == known), known);
        assert_eq!(
            SceneError::at(KeyPath::key("solver"), "unknown").to_string(),
            "solver: unknown"
        );
    }
}
