//! The scene file: the problem description of `vem_scene` written in TOML. Parsing keeps the
//! position of every key, so that any error — of the TOML reader, of the checks, of the
//! libraries — is shown at the file, line and column the user wrote.

use std::path::{Path, PathBuf};

use vem_scene::resources::{LimitOrigin, MemoryLimit};
use vem_scene::toml_file::{self, SpanIndex};
use vem_scene::{KeyPath, SceneError};

use crate::CliError;

/// A parsed scene file: its text, the description and where each key is.
#[derive(Debug, Clone)]
pub struct Scene {
    path: PathBuf,
    source: String,
    description: vem_scene::Scene,
    spans: SpanIndex,
    memory_limit: Option<MemoryLimit>,
}

impl Scene {
    /// Reads and parses the scene file at `path`.
    pub fn load(path: impl AsRef<Path>) -> Result<Self, CliError> {
        let path = path.as_ref();
        let source = std::fs::read_to_string(path).map_err(|source| CliError::Io {
            action: "read",
            path: path.to_path_buf(),
            source,
        })?;
        Self::parse(path, source)
    }

    /// Parses `source`, the text of the scene file `path` (mesh files are looked up relative
    /// to `path`'s directory), and checks what can be checked without meshes.
    pub fn parse(path: impl AsRef<Path>, source: impl Into<String>) -> Result<Self, CliError> {
        let path = path.as_ref().to_path_buf();
        let source = source.into();
        let (description, spans) = toml_file::parse(&source)
            .map_err(|e| CliError::at(&path, &source, e.span, e.message))?;
        let mut scene = Self {
            path,
            source,
            description,
            spans,
            memory_limit: None,
        };
        // Untitled: the file's stem titles the run.
        if scene.description.title.is_none() {
            scene.description.title = Some(scene.stem());
        }
        vem_scene::check::check(&scene.description).map_err(|e| scene.error(e))?;
        Ok(scene)
    }

    /// The same scene with the memory limit `limit` (the command line's `--memory-limit`),
    /// which overrides the scene's `[limits] memory_gib`.
    pub fn with_memory_limit(mut self, limit: MemoryLimit) -> Self {
        self.memory_limit = Some(limit);
        self
    }

    /// The memory the run may plan to use: the command line's limit, else the scene's
    /// `[limits] memory_gib`, else the memory the system reports available.
    pub fn memory_limit(&self) -> MemoryLimit {
        self.memory_limit.unwrap_or_else(|| {
            self.description
                .limits
                .memory_gib
                .and_then(|gib| MemoryLimit::try_from_gib(gib, LimitOrigin::Scene).ok())
                .unwrap_or_else(MemoryLimit::available)
        })
    }

    /// The scene file's path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The file's stem ("hertz" for `scenes/hertz.toml`).
    pub fn stem(&self) -> String {
        self.path
            .file_stem()
            .map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned())
    }

    /// The description read from the file.
    pub fn file(&self) -> &vem_scene::Scene {
        &self.description
    }

    /// The title, or the file stem.
    pub fn title(&self) -> String {
        self.description
            .title
            .clone()
            .unwrap_or_else(|| self.stem())
    }

    /// The folder mesh files are relative to.
    pub fn base(&self) -> PathBuf {
        self.path.parent().unwrap_or(Path::new("")).to_path_buf()
    }

    /// A scene error at the place in the file where its key path was written.
    pub fn error(&self, error: SceneError) -> CliError {
        self.error_at(&error.path, error.message)
    }

    /// An error at the key `path` of the file.
    pub fn error_at(&self, path: &KeyPath, message: impl Into<String>) -> CliError {
        CliError::at(&self.path, &self.source, self.spans.span(path), message)
    }
}
