//! Errors of the `vem` command: every one names the file and, where it comes from the scene,
//! the line and column of the offending key.

use std::fmt;
use std::path::{Path, PathBuf};

use vem_contact::ContactError;
use vem_elastic::ElasticError;
use vem_mesh::MeshError;

/// A position in a scene file, 1-based, with the text of its line for the caret display.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Location {
    /// Line number, from 1.
    pub line: usize,
    /// Column number in characters, from 1.
    pub column: usize,
    /// The text of the line.
    pub text: String,
    /// Width of the marked range in characters (at least 1).
    pub width: usize,
}

impl Location {
    /// The location of the byte range `span` in `source` (clamped to the text).
    pub fn of_span(source: &str, span: std::ops::Range<usize>) -> Self {
        let start = floor_char_boundary(source, span.start.min(source.len()));
        let end = floor_char_boundary(source, span.end.clamp(start, source.len()));
        let line_start = source[..start].rfind('\n').map_or(0, |i| i + 1);
        let line_end = source[start..]
            .find('\n')
            .map_or(source.len(), |i| start + i);
        let text = source[line_start..line_end].trim_end_matches('\r');
        let line = source[..start].matches('\n').count() + 1;
        let column = source[line_start..start].chars().count() + 1;
        let width = source[start..end.min(line_end)].chars().count().max(1);
        Self {
            line,
            column,
            text: text.to_string(),
            width,
        }
    }
}

/// The largest char boundary of `text` at or before `index`.
fn floor_char_boundary(text: &str, mut index: usize) -> usize {
    while !text.is_char_boundary(index) {
        index -= 1;
    }
    index
}

/// Everything that can go wrong in the `vem` command.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum CliError {
    /// A file could not be read, a directory not created or a report not serialised (the
    /// cause is the source).
    #[error("cannot {action} {}", path.display())]
    Io {
        /// What was being done: "read", "create the directory", "serialise".
        action: &'static str,
        /// The file or directory.
        path: PathBuf,
        /// The failure.
        #[source]
        source: std::io::Error,
    },
    /// The scene file is not valid: TOML syntax, an unknown key, a wrong type, a missing or
    /// contradictory setting, an unknown body or part. Displayed as
    /// `file:line:column: message` followed by the line and a caret.
    #[error("{}", SceneDisplay(self))]
    Scene {
        /// The scene file.
        path: PathBuf,
        /// Where in it, when known.
        location: Option<Location>,
        /// What is wrong.
        message: String,
    },
    /// A mesh could not be generated, read or written (what is wrong is the source).
    #[error("{context}")]
    Mesh {
        /// Which body or file.
        context: String,
        /// The mesh error.
        #[source]
        source: MeshError,
    },
    /// Assembling, solving or post-processing an elastic body failed (the error names the
    /// body).
    #[error(transparent)]
    Elastic(Box<ElasticError>),
    /// The contact problem failed (interface, solver, fixed point); the error names the stage.
    #[error(transparent)]
    Contact(#[from] ContactError),
    /// The contact pair holds nothing: the solve found the energy unbounded along a mode the
    /// contact does not stop (a body pulled away from its counterpart, a contact part facing
    /// away from it, a body held only by the contact). Names the pair and its initial gaps;
    /// the solver's figures are the source.
    #[error(
        "the contact of {pair} gives the body no support under its load ({gaps}): hold the \
         body by a Dirichlet condition, or check that the contact part faces its counterpart"
    )]
    NoSupport {
        /// Which parts face what.
        pair: String,
        /// The initial gaps of the interface, or its overlap.
        gaps: String,
        /// The solver's failure.
        #[source]
        source: Box<ContactError>,
    },
    /// A picture or plot could not be drawn.
    #[error("cannot draw {}: {reason}", path.display())]
    Plot {
        /// The picture file.
        path: PathBuf,
        /// What failed.
        reason: String,
    },
    /// A command-line argument is not usable.
    #[error("{0}")]
    Usage(String),
}

impl CliError {
    /// The error and its causes, one per line: the error itself, then `caused by: ...` for
    /// each source in turn (each cause printed once).
    pub fn chain(&self) -> String {
        let mut text = self.to_string();
        let mut source = std::error::Error::source(self);
        while let Some(cause) = source {
            text.push_str("\n  caused by: ");
            text.push_str(&cause.to_string());
            source = cause.source();
        }
        text
    }

    /// A scene error at byte range `span` of `source` (the text of the scene file `path`).
    pub fn at(
        path: &Path,
        source: &str,
        span: Option<std::ops::Range<usize>>,
        message: impl Into<String>,
    ) -> Self {
        CliError::Scene {
            path: path.to_path_buf(),
            location: span.map(|s| Location::of_span(source, s)),
            message: message.into(),
        }
    }

    /// The location in the scene file, for scene errors that have one.
    pub fn location(&self) -> Option<&Location> {
        match self {
            CliError::Scene { location, .. } => location.as_ref(),
            _ => None,
        }
    }
}

/// `file:line:column: message`, then the line with a caret under the offending text.
struct SceneDisplay<'a>(&'a CliError);

impl fmt::Display for SceneDisplay<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let CliError::Scene {
            path,
            location,
            message,
        } = self.0
        else {
            return Ok(());
        };
        match location {
            None => write!(f, "{}: {message}", path.display()),
            Some(at) => {
                let number = at.line.to_string();
                let pad = " ".repeat(number.len());
                write!(
                    f,
                    "{}:{}:{}: {message}\n {pad} |\n {number} | {}\n {pad} | {}{}",
                    path.display(),
                    at.line,
                    at.column,
                    at.text,
                    " ".repeat(at.column - 1),
                    "^".repeat(at.width)
                )
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn location_counts_lines_and_characters() {
        let text = "a = 1\nname = \"é\"\nbad = x\n";
        let start = text.find("x").unwrap();
        let at = Location::of_span(text, start..start + 1);
        assert_eq!((at.line, at.column, at.width), (3, 7, 1));
        assert_eq!(at.text, "bad = x");
        // A multi-byte character before the column counts once.
        let quote = text.rfind('"').unwrap();
        assert_eq!(Location::of_span(text, quote..quote + 1).column, 10);
    }

    #[test]
    fn scene_error_shows_file_line_column_and_caret() {
        let text = "[[body]]\nnmae = \"x\"\n";
        let start = text.find("nmae").unwrap();
        let err = CliError::at(
            Path::new("s.toml"),
            text,
            Some(start..start + 4),
            "unknown field",
        );
        assert_eq!(
            err.to_string(),
            "s.toml:2:1: unknown field\n   |\n 2 | nmae = \"x\"\n   | ^^^^"
        );
    }
}
