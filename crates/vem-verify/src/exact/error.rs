//! Errors of the exact-solution module.

/// What is wrong with a request for an exact solution or with its parameters.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ExactError {
    /// No built-in case has this name.
    #[error("unknown exact solution {name:?}; the known cases are {known}")]
    UnknownCase {
        /// The name asked for.
        name: String,
        /// The known names, comma separated.
        known: String,
    },
    /// A case registry already has a case of this name (or the name is empty).
    #[error(
        "cannot register the case {name:?}: the name is empty or taken; the cases are {known}"
    )]
    DuplicateCase {
        /// The name given.
        name: String,
        /// The registered names, comma separated.
        known: String,
    },
    /// Lamé parameters that do not define a coercive plane-strain material.
    #[error("invalid Lamé parameters lambda = {lambda}, mu = {mu}: {reason}")]
    InvalidLame {
        /// The first Lamé parameter given.
        lambda: f64,
        /// The shear modulus given.
        mu: f64,
        /// Which condition fails.
        reason: &'static str,
    },
    /// A side name other than "left", "right", "bottom", "top".
    #[error("unknown side {name:?}; the sides are \"left\", \"right\", \"bottom\", \"top\"")]
    UnknownSide {
        /// The name given.
        name: String,
    },
    /// A body index other than 0 or 1.
    #[error("unknown body index {index}; a problem has body 0 and possibly body 1")]
    UnknownBody {
        /// The index given.
        index: usize,
    },
    /// Parameters of a switch function `PP(c, d, X, L, k)` that do not define one.
    #[error(
        "invalid switch function PP(c = {amplitude}, X = {switch_point}, L = {length}, \
         k = {power}): {reason}"
    )]
    InvalidSwitchFunction {
        /// The amplitude `c`.
        amplitude: f64,
        /// The switch point `X`.
        switch_point: f64,
        /// The length `L`.
        length: f64,
        /// The power `k`.
        power: u32,
        /// Which condition fails.
        reason: &'static str,
    },
    /// A parameter of an analytic contact solution (Hertz) that is out of range.
    #[error("invalid parameter {name} = {value}: {reason}")]
    InvalidParameter {
        /// The parameter's name.
        name: &'static str,
        /// The value given.
        value: f64,
        /// Which condition fails.
        reason: &'static str,
    },
}
