//! A solved scene with what its pictures need: the `vem_scene` outcome (bodies, contact
//! result, summary), the obstacles and the picture settings of the scene.

use std::ops::{Deref, DerefMut};

use vem_contact::Obstacle;
use vem_mesh::io::VtuEncoding;
use vem_scene::{OutputFiles, RunSummary, VtuEncodingName};

/// The result of solving a scene: the outcome of `vem_scene` (its fields read through this
/// value) and what the output files need.
#[derive(Debug, Clone)]
pub struct Outcome {
    inner: vem_scene::Outcome,
    /// The rigid obstacles of the contact pairs (for pictures), each with the index of its
    /// pair.
    pub(crate) obstacles: Vec<(usize, Obstacle)>,
    /// The friction bound per unit length of every interface node (Tresca `g_F`, Coulomb
    /// `F p`), `None` without friction: the plots draw it.
    pub(crate) friction_bounds: Option<Vec<f64>>,
    /// The scene's `[output] magnification`.
    pub(crate) magnification: Option<f64>,
    /// The scene's `[output] width`.
    pub(crate) output_width: Option<f64>,
    /// The Coulomb coefficient of every contact pair whose law is `coulomb` (`None` for the
    /// others), for the Cattaneo-Mindlin curve of the pressure plot.
    pub(crate) coulomb_coefficients: Vec<Option<f64>>,
    /// The scene's `[output] length_unit`.
    pub(crate) length_unit: Option<String>,
    /// The scene's `[output] stress_unit`.
    pub(crate) stress_unit: Option<String>,
    /// Body A's contact part of every pair, in the order of the scene (the contact surface of
    /// a scene in space is drawn on its faces).
    pub(crate) contact_parts: Vec<String>,
    /// The scene's `[output] vtu_encoding` and `files`.
    pub(crate) output: OutputSettings,
}

/// Which files [`Outcome::write`] writes and how: the scene's `[output] vtu_encoding` and
/// `files`, or what replaced them ([`Outcome::set_vtu_encoding`], [`Outcome::set_files`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct OutputSettings {
    pub(crate) vtu_encoding: VtuEncodingName,
    pub(crate) files: OutputSelection,
}

/// The kinds of files a run writes besides `summary.json` (`[output] files`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct OutputSelection {
    pub(crate) vtu: bool,
    pub(crate) csv: bool,
    pub(crate) pictures: bool,
}

impl OutputSelection {
    /// The kinds named in `files`; every kind when `files` is `None`.
    fn of(files: Option<&[OutputFiles]>) -> Self {
        let has = |kind| files.is_none_or(|f| f.contains(&kind));
        Self {
            vtu: has(OutputFiles::Vtu),
            csv: has(OutputFiles::Csv),
            pictures: has(OutputFiles::Pictures),
        }
    }
}

impl Outcome {
    /// The outcome `inner` of solving `model`, ready to be written ([`Outcome::write`]): the
    /// way other front ends (the Python package) write what they solved with `vem_scene`.
    pub fn new(inner: vem_scene::Outcome, model: &vem_scene::Model) -> Self {
        let obstacles = model
            .contacts()
            .iter()
            .enumerate()
            .filter_map(|(pair, c)| c.obstacle.clone().map(|o| (pair, o)))
            .collect();
        // The bound per unit length at every node, as the solve used it (any law).
        let friction_bounds = inner.contact.as_ref().and_then(|contact| {
            (contact.model.tangential_rows > 0).then(|| {
                contact
                    .nodes
                    .iter()
                    .map(|n| n.friction_bound / n.tributary_measure)
                    .collect()
            })
        });
        let coulomb_coefficients = model
            .scene()
            .contacts
            .iter()
            .map(|c| {
                let law = c.law.as_ref().filter(|law| law.name == "coulomb")?;
                law.options
                    .get("coefficient")
                    .and_then(|v| v.as_f64())
                    .or(c.coefficient)
            })
            .collect();
        let output = &model.scene().output;
        Self {
            inner,
            obstacles,
            friction_bounds,
            coulomb_coefficients,
            magnification: output.magnification,
            output_width: output.width,
            length_unit: output.length_unit.clone(),
            stress_unit: output.stress_unit.clone(),
            contact_parts: model
                .scene()
                .contacts
                .iter()
                .map(|c| c.part.clone())
                .collect(),
            output: OutputSettings {
                vtu_encoding: output.vtu_encoding.unwrap_or_default(),
                files: OutputSelection::of(output.files.as_deref()),
            },
        }
    }

    /// Writes the `.vtu` files in `encoding` (instead of the scene's `[output] vtu_encoding`).
    pub fn set_vtu_encoding(&mut self, encoding: VtuEncodingName) {
        self.output.vtu_encoding = encoding;
    }

    /// Writes only the kinds of files in `files` besides `summary.json` (instead of the
    /// scene's `[output] files`).
    pub fn set_files(&mut self, files: &[OutputFiles]) {
        self.output.files = OutputSelection::of(Some(files));
    }

    /// The output settings [`Outcome::write`] follows (to set back after a write with other
    /// settings: [`Outcome::set_output_settings`]).
    pub fn output_settings(&self) -> OutputSettings {
        self.output
    }

    /// Follows `settings` (taken from [`Outcome::output_settings`]).
    pub fn set_output_settings(&mut self, settings: OutputSettings) {
        self.output = settings;
    }

    /// The encoding of the bodies' `.vtu` files.
    pub(crate) fn body_encoding(&self) -> VtuEncoding {
        match self.output.vtu_encoding {
            VtuEncodingName::Binary => VtuEncoding::Binary,
            VtuEncodingName::Compressed => VtuEncoding::Compressed,
            VtuEncodingName::Ascii => VtuEncoding::Ascii,
        }
    }

    /// The encoding of the interface's `.vtu` files: compressed where the bodies' are raw
    /// binary (small files, with integer arrays that compress well), the bodies' otherwise.
    pub(crate) fn interface_encoding(&self) -> VtuEncoding {
        match self.body_encoding() {
            VtuEncoding::Binary => VtuEncoding::Compressed,
            other => other,
        }
    }

    /// Draws the displacements of `deformed.svg` magnified `magnification` times (instead of
    /// the scene's `[output] magnification` or the automatic factor).
    pub fn set_magnification(&mut self, magnification: f64) {
        self.magnification = Some(magnification);
    }

    /// The summary (its output and total times are set by [`Outcome::write`]).
    pub fn summary(&self) -> &RunSummary {
        &self.inner.summary
    }
}

impl Deref for Outcome {
    type Target = vem_scene::Outcome;

    fn deref(&self) -> &Self::Target {
        &self.inner
    }
}

impl DerefMut for Outcome {
    fn deref_mut(&mut self) -> &mut Self::Target {
        &mut self.inner
    }
}
