//! Accuracy presets and the error model measured by `cargo xtask tradeoff` (the report is
//! `docs/tradeoff.md`).
//!
//! An [`AccuracyPreset`] names a solver setting (a registry name and its
//! [`Options`]) and the relative energy-norm error it aims at when the mesh size is chosen
//! for the user. The study found that the mesh size, not the solver tolerance, sets the error:
//! on one mesh the three presets give the same errors to three digits (the condensed solver's
//! tolerance moves the interface forces far below the discretisation error), so the presets
//! differ chiefly by the mesh size their targets choose. The [`ErrorModel`] turns a target
//! error into the size parameter `n` of a generated mesh (about `n` cells across each body) and
//! a size back into a predicted error, with the constant derived from the study's errors of the
//! manufactured problems M1 and M2 (generated into this crate by the study; a test of the
//! `xtask` crate checks it against `docs/tradeoff/tradeoff.json`).
//!
//! The error is the relative broken energy-norm error `E_grad / |u|_1 =
//! ||grad(u - Pi u_h)||_0 / ||grad u||_0` of the lowest-order VEM, which decreases like `h`
//! (Theorems 4.1 and 4.2 of the contact analysis), so the model is `E = C / n`.
//!
//! ```
//! use vem_contact::{AccuracyPreset, ErrorModel, SolverRegistry};
//! let preset: AccuracyPreset = "balanced".parse()?;
//! let solver = SolverRegistry::builtin().make(preset.solver(), &preset.solver_options());
//! assert!(solver.is_ok());
//! // The size for 10 % and the error predicted there (at most the target).
//! let model = ErrorModel::LOWEST_ORDER_VEM;
//! let n = model.try_size_for(0.1)?;
//! assert_eq!(n, 29);
//! assert!(model.predicted_error(n) <= 0.1 && model.predicted_error(n - 1) > 0.1);
//! assert_eq!(AccuracyPreset::for_target(0.1), AccuracyPreset::Draft);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::fmt;
use std::str::FromStr;

mod fitted;

use crate::solver::SettingsError;
use vem_space::Options;

/// A named solver setting with the error it aims at (see the module docs). Ordered from the
/// cheapest and least accurate to the most expensive and most accurate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum AccuracyPreset {
    /// The condensed solver stopped at a relative interface tolerance of `1e-4`; aims at a 10 %
    /// energy-norm error (`n = 29` by [`ErrorModel::LOWEST_ORDER_VEM`]).
    Draft,
    /// The condensed solver at a tolerance of `1e-8`; aims at 3 % (`n = 97`).
    Balanced,
    /// The condensed solver at its default tolerance `1e-12`; aims at 1 % (`n` about 290).
    Reference,
}

/// Why a preset name was refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown accuracy preset '{name}': the presets are draft, balanced, reference")]
pub struct UnknownPreset {
    /// The name given.
    pub name: String,
}

impl AccuracyPreset {
    /// Every preset, cheapest first.
    pub const ALL: [AccuracyPreset; 3] = [
        AccuracyPreset::Draft,
        AccuracyPreset::Balanced,
        AccuracyPreset::Reference,
    ];

    /// The name in scene files and reports: "draft", "balanced", "reference".
    pub fn name(self) -> &'static str {
        match self {
            Self::Draft => "draft",
            Self::Balanced => "balanced",
            Self::Reference => "reference",
        }
    }

    /// The solver's registry name.
    pub fn solver(self) -> &'static str {
        "condensed"
    }

    /// The solver's stopping tolerance (relative).
    pub fn tolerance(self) -> f64 {
        match self {
            Self::Draft => 1e-4,
            Self::Balanced => 1e-8,
            Self::Reference => 1e-12,
        }
    }

    /// The options the solver is made with.
    pub fn solver_options(self) -> Options {
        Options::new().with("tolerance", self.tolerance())
    }

    /// The relative energy-norm error `E_grad / |u|_1` aimed at when the mesh size is chosen
    /// from the preset (a generated mesh without `n`).
    pub fn target_error(self) -> f64 {
        match self {
            Self::Draft => 0.10,
            Self::Balanced => 0.03,
            Self::Reference => 0.01,
        }
    }

    /// The documented bound of the relative energy-norm error `E_grad / |u|_1` on the
    /// manufactured problems M1 and M2 with matching quadrilateral meshes at `n = 32`
    /// (measured in `docs/tradeoff.md`: 8.09e-2 for M1, 5.36e-2 for M2 with every preset, the
    /// three agreeing to three digits; a test holds the presets to it).
    pub fn bound_at_n32(self) -> f64 {
        0.09
    }

    /// The preset whose solver setting serves a target error: the cheapest one whose own
    /// target is at most `target` (draft for 10 % and above, balanced from 3 %, reference
    /// below).
    pub fn for_target(target: f64) -> Self {
        Self::ALL
            .into_iter()
            .find(|p| p.target_error() <= target)
            .unwrap_or(Self::Reference)
    }
}

impl fmt::Display for AccuracyPreset {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for AccuracyPreset {
    type Err = UnknownPreset;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .into_iter()
            .find(|p| p.name().eq_ignore_ascii_case(s.trim()))
            .ok_or_else(|| UnknownPreset {
                name: s.to_string(),
            })
    }
}

/// The relative energy-norm error `E = C / n^rate` of a generated mesh of size parameter `n`
/// (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ErrorModel {
    constant: f64,
    rate: f64,
}

impl ErrorModel {
    /// The lowest-order VEM: rate 1, the constant derived by `cargo xtask tradeoff` from its
    /// rows of M1 and M2 (reference preset, n >= 8; `docs/tradeoff.md`, generated into
    /// `accuracy/fitted.rs`): [`ErrorModel::MEASURED_BOUND`], the largest measured `E_grad n`,
    /// rounded up to one decimal, so that the prediction is at or above every error it was
    /// derived from. The geometric-mean fit, [`ErrorModel::FITTED_CONSTANT`], is smaller: a
    /// model with it would promise less error than some of those meshes give.
    pub const LOWEST_ORDER_VEM: ErrorModel = ErrorModel {
        constant: fitted::CONSTANT,
        rate: 1.0,
    };

    /// The largest constant `C` of `E_grad/|u|_1 = C / n` fitted by `cargo xtask tradeoff`
    /// (geometric mean of `E_grad n` over n >= 8, reference preset) to M1 and M2 on
    /// quads/quads and voronoi/quads.
    pub const FITTED_CONSTANT: f64 = fitted::FITTED_CONSTANT;

    /// The largest measured `E_grad n` (n >= 8, reference preset) of M1 and M2 on every pairing
    /// of `cargo xtask tradeoff`: the constant of [`ErrorModel::LOWEST_ORDER_VEM`] is this
    /// value rounded up to one decimal.
    pub const MEASURED_BOUND: f64 = fitted::MEASURED_BOUND;

    /// A model `E = constant / n^rate`.
    ///
    /// # Errors
    /// A constant or rate that is not finite and positive.
    pub fn try_new(constant: f64, rate: f64) -> Result<Self, SettingsError> {
        SettingsError::positive("constant", constant)?;
        SettingsError::positive("rate", rate)?;
        Ok(Self { constant, rate })
    }

    /// The constant `C`.
    pub fn constant(&self) -> f64 {
        self.constant
    }

    /// The rate in `n`.
    pub fn rate(&self) -> f64 {
        self.rate
    }

    /// The predicted error at size `n` (`C` for `n = 0`).
    pub fn predicted_error(&self, n: usize) -> f64 {
        self.constant / (n.max(1) as f64).powf(self.rate)
    }

    /// The smallest size `n >= 1` whose predicted error is at most `target`.
    ///
    /// # Errors
    /// A target that is not finite and positive, or one needing more than `10^6` cells across.
    pub fn try_size_for(&self, target: f64) -> Result<usize, SettingsError> {
        SettingsError::positive("target_error", target)?;
        let n = (self.constant / target).powf(1.0 / self.rate);
        if !n.is_finite() || n > 1e6 {
            return Err(SettingsError {
                setting: "target_error",
                value: target,
                requirement: "reachable with at most 10^6 cells across",
            });
        }
        let mut n = (n.ceil() as usize).max(1);
        // Rounding: the smallest n that meets the target.
        while n > 1 && self.predicted_error(n - 1) <= target {
            n -= 1;
        }
        while self.predicted_error(n) > target {
            n += 1;
        }
        Ok(n)
    }
}

#[cfg(test)]
mod tests {
    use super::ErrorModel;

    /// The library's constant is the study's largest measured `E_grad n` rounded up to one
    /// decimal, and so at or above its geometric-mean fit.
    #[test]
    fn the_constant_is_the_measured_bound_rounded_up() {
        let c = ErrorModel::LOWEST_ORDER_VEM.constant();
        assert_eq!(c, (ErrorModel::MEASURED_BOUND * 10.0).ceil() / 10.0);
        assert!(c >= ErrorModel::MEASURED_BOUND && c - ErrorModel::MEASURED_BOUND < 0.1);
        assert!(ErrorModel::MEASURED_BOUND
            .total_cmp(&ErrorModel::FITTED_CONSTANT)
            .is_ge());
    }
}
