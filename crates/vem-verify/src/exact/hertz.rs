//! Plane contact of a cylinder on a half-plane: Hertz's pressure and the Cattaneo-Mindlin
//! partial slip under a tangential load (identical materials, Coulomb friction).
//!
//! A cylinder of radius `R` pressed on a half-plane by a load `P` per unit thickness, both
//! elastic with `1/E* = (1 - nu_1^2)/E_1 + (1 - nu_2^2)/E_2` (plane strain), touches it on
//! `|x| <= a` with
//!
//! ```text
//! a = sqrt(4 P R / (pi E*)),   p(x) = p0 sqrt(1 - x^2/a^2),   p0 = 2 P / (pi a).
//! ```
//!
//! With identical materials the normal and tangential problems decouple. A tangential load
//! `Q < F P` with Coulomb coefficient `F` then leaves a central stick zone `|x| < c`,
//!
//! ```text
//! c = a sqrt(1 - Q / (F P)),
//! q(x) = F p0 sqrt(1 - x^2/a^2) - F p0 (c/a) sqrt(1 - x^2/c^2)   (|x| < c; the second
//!        term only inside the stick zone), q = F p in the slip zones c <= |x| <= a.
//! ```
//!
//! ```
//! use vem_verify::exact::HertzContact;
//!
//! let hertz = HertzContact::try_new(1.0, 100.0, 2.0)?;
//! let a = hertz.half_width();
//! // The pressure integrates to the load (midpoint rule).
//! let n = 20_000;
//! let total: f64 = (0..n)
//!     .map(|k| hertz.pressure(-a + (k as f64 + 0.5) * 2.0 * a / n as f64) * 2.0 * a / n as f64)
//!     .sum();
//! assert!((total / 2.0 - 1.0).abs() < 1e-5);
//! // Half the friction capacity leaves a stick zone of half-width a / sqrt(2).
//! assert!((hertz.stick_half_width(0.5) - a / 2f64.sqrt()).abs() < 1e-15);
//! # Ok::<(), vem_verify::exact::ExactError>(())
//! ```

use super::ExactError;

/// Hertz's plane contact of a cylinder on a half-plane (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HertzContact {
    radius: f64,
    effective_modulus: f64,
    load: f64,
}

impl HertzContact {
    /// Radius `R`, effective modulus `E*` and load `P` per unit thickness, each finite and
    /// positive.
    ///
    /// # Errors
    /// [`ExactError::InvalidParameter`] naming the first value that is not.
    pub fn try_new(radius: f64, effective_modulus: f64, load: f64) -> Result<Self, ExactError> {
        for (name, value) in [
            ("radius", radius),
            ("effective_modulus", effective_modulus),
            ("load", load),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(ExactError::InvalidParameter {
                    name,
                    value,
                    reason: "must be finite and positive",
                });
            }
        }
        Ok(Self {
            radius,
            effective_modulus,
            load,
        })
    }

    /// The plane-strain effective modulus `E*` of two isotropic bodies `(E_1, nu_1)`,
    /// `(E_2, nu_2)`: `1/E* = (1 - nu_1^2)/E_1 + (1 - nu_2^2)/E_2`.
    pub fn plane_strain_modulus(e1: f64, nu1: f64, e2: f64, nu2: f64) -> f64 {
        1.0 / ((1.0 - nu1 * nu1) / e1 + (1.0 - nu2 * nu2) / e2)
    }

    /// `R`.
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// `E*`.
    pub fn effective_modulus(&self) -> f64 {
        self.effective_modulus
    }

    /// `P`.
    pub fn load(&self) -> f64 {
        self.load
    }

    /// The half-width `a = sqrt(4 P R / (pi E*))`.
    pub fn half_width(&self) -> f64 {
        (4.0 * self.load * self.radius / (std::f64::consts::PI * self.effective_modulus)).sqrt()
    }

    /// The peak pressure `p0 = 2 P / (pi a)`.
    pub fn peak_pressure(&self) -> f64 {
        2.0 * self.load / (std::f64::consts::PI * self.half_width())
    }

    /// The pressure `p(x) = p0 sqrt(1 - x^2/a^2)` at distance `x` from the centre (0 outside).
    pub fn pressure(&self, x: f64) -> f64 {
        let s = x / self.half_width();
        self.peak_pressure() * (1.0 - s * s).max(0.0).sqrt()
    }

    /// Cattaneo-Mindlin: the stick half-width `c = a sqrt(1 - Q/(F P))` for the ratio
    /// `q_ratio = Q/(F P)` (clamped to `[0, 1]`: full stick at 0, full slip at 1).
    pub fn stick_half_width(&self, q_ratio: f64) -> f64 {
        self.half_width() * (1.0 - q_ratio.clamp(0.0, 1.0)).sqrt()
    }

    /// Cattaneo-Mindlin: the magnitude of the tangential traction at `x` for the coefficient
    /// `coefficient` and `q_ratio = Q/(F P)` (module docs).
    pub fn tangential_traction(&self, x: f64, coefficient: f64, q_ratio: f64) -> f64 {
        let c = self.stick_half_width(q_ratio);
        let slip = coefficient * self.pressure(x);
        if x.abs() < c {
            let s = x / c;
            slip - coefficient
                * self.peak_pressure()
                * (c / self.half_width())
                * (1.0 - s * s).max(0.0).sqrt()
        } else {
            slip
        }
    }
}
