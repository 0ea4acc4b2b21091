//! Scene files in TOML: the [`Scene`] read with serde (`deny_unknown_fields`, so a misspelt or
//! misplaced key is an error at its position) and an index from every key path to its place in
//! the text, so that an error found later (a part the mesh lacks, a refused setting) is shown
//! at the key the user wrote.

use std::collections::BTreeMap;
use std::ops::Range;

use toml::de::{DeTable, DeValue};

use crate::{KeyPath, Scene};

/// Where each key of a TOML text is: the span of its value.
#[derive(Debug, Clone, Default)]
pub struct SpanIndex {
    spans: BTreeMap<KeyPath, Range<usize>>,
}

/// A TOML text that is not a scene: the span at fault and what is wrong.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TomlError {
    /// Where in the text (byte offsets), when the parser says.
    pub span: Option<Range<usize>>,
    /// What is wrong.
    pub message: String,
}

impl SpanIndex {
    /// The index of the TOML text `source` (empty when it does not parse).
    pub fn of(source: &str) -> Self {
        let mut index = Self::default();
        if let Ok(table) = DeTable::parse(source) {
            index.table(table.get_ref(), &KeyPath::root());
        }
        index
    }

    fn table(&mut self, table: &DeTable<'_>, path: &KeyPath) {
        for (key, value) in table {
            let at = path.at(key.get_ref());
            self.value(value.get_ref(), value.span(), &at);
        }
    }

    fn value(&mut self, value: &DeValue<'_>, span: Range<usize>, path: &KeyPath) {
        self.spans.insert(path.clone(), span);
        match value {
            DeValue::Table(table) => self.table(table, path),
            DeValue::Array(items) => {
                for (k, item) in items.iter().enumerate() {
                    self.value(item.get_ref(), item.span(), &path.index(k));
                }
            }
            _ => {}
        }
    }

    /// The key path at the byte range `span` of `source` (the text this index was made of):
    /// the innermost written value that holds it, followed by the key written at `span` when
    /// `span` marks a key rather than a value (an unknown key, as the TOML reader reports
    /// it). The root when no value holds it.
    ///
    /// ```
    /// use vem_scene::toml_file::{parse, SpanIndex};
    /// let text = "[[body]]\nname = \"a\"\nmesh = { familly = \"quads\" }\n";
    /// let error = parse(text).unwrap_err();
    /// let path = SpanIndex::of(text).path_at(text, error.span.unwrap());
    /// assert_eq!(path.to_string(), "body[0].mesh.familly");
    /// ```
    pub fn path_at(&self, source: &str, span: Range<usize>) -> KeyPath {
        let holds = |r: &Range<usize>| r.start <= span.start && span.end <= r.end;
        let Some((path, range)) = self
            .spans
            .iter()
            .filter(|(_, r)| holds(r))
            .min_by_key(|(p, r)| (r.end - r.start, std::cmp::Reverse(p.0.len())))
        else {
            return KeyPath::root();
        };
        let mut path = path.clone();
        if *range != span {
            let key = source.get(span.clone()).unwrap_or_default().trim();
            let bare = !key.is_empty()
                && key
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
            if bare {
                path.0.push(crate::Segment::Key(key.to_string()));
            }
        }
        path
    }

    /// The span of the value at `path`, or of the nearest enclosing key that is written.
    pub fn span(&self, path: &KeyPath) -> Option<Range<usize>> {
        let known = path.known_prefix(|p| self.spans.contains_key(p));
        self.spans.get(&known).cloned()
    }
}

/// Reads a scene from TOML text, with the index of its keys.
///
/// ```
/// use vem_scene::{toml_file::parse, KeyPath};
/// let text = "[[body]]\nname = \"a\"\nmesh = { family = \"quads\", rectangle = [[0, 0], [1, 1]], n = 2 }\nmaterial = { E = 1.0, nu = 0.3, plane = \"strain\" }\n";
/// let (scene, spans) = parse(text).unwrap();
/// assert_eq!(scene.bodies[0].name, "a");
/// let at = spans.span(&KeyPath::key("body").index(0).at("material")).unwrap();
/// assert!(text[at].starts_with("{ E = 1.0"));
/// let bad = parse(&text.replace("family", "familly")).unwrap_err();
/// assert!(bad.message.contains("unknown field `familly`"));
/// ```
///
/// # Errors
/// [`TomlError`] for a syntax error, an unknown key, a value of the wrong type, a number that
/// is not finite (`nan`, `inf`: TOML has them, a scene has no use for them).
pub fn parse(source: &str) -> Result<(Scene, SpanIndex), TomlError> {
    let scene: Scene = toml::from_str(source).map_err(|e| TomlError {
        span: e.span(),
        message: e.message().trim_end().to_string(),
    })?;
    if let Ok(table) = DeTable::parse(source) {
        non_finite_in_table(table.get_ref(), &KeyPath::root())?;
    }
    Ok((scene, SpanIndex::of(source)))
}

/// The first float of `table` written `nan` or `inf` as an error at its place.
fn non_finite_in_table(table: &DeTable<'_>, path: &KeyPath) -> Result<(), TomlError> {
    for (key, value) in table {
        non_finite_in(value.get_ref(), value.span(), &path.at(key.get_ref()))?;
    }
    Ok(())
}

fn non_finite_in(value: &DeValue<'_>, span: Range<usize>, path: &KeyPath) -> Result<(), TomlError> {
    match value {
        DeValue::Float(float) => {
            let text = float.as_str();
            if text.contains("nan") || text.contains("inf") {
                return Err(TomlError {
                    span: Some(span),
                    message: format!("`{path}` = {text} must be finite"),
                });
            }
            Ok(())
        }
        DeValue::Table(table) => non_finite_in_table(table, path),
        DeValue::Array(items) => items
            .iter()
            .enumerate()
            .try_for_each(|(k, item)| non_finite_in(item.get_ref(), item.span(), &path.index(k))),
        _ => Ok(()),
    }
}
