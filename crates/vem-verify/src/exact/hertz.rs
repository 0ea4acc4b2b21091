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
//! Call this distribution `q_c(x)` (`q_a = 0`, `q_0 = F p`). Unloading from `Q*` (ratio
//! `r* = Q*/(F P)`) to `Q` (ratio `r`, `-r* <= r <= r*`) slips backwards in the outer zones
//! `c' <= |x| <= a` and sticks inside (Johnson, Contact Mechanics, 7.6; Mindlin and
//! Deresiewicz): the change is minus twice a Cattaneo-Mindlin distribution,
//!
//! ```text
//! c' = a sqrt(1 - (r* - r) / 2),    q(x) = q_c*(x) - 2 q_c'(x),
//! ```
//!
//! and reloading from `-Q*` back to `Q` is its mirror image, `q(x) = -q_c*(x) + 2 q_c''(x)`
//! with `c'' = a sqrt(1 - (r* + r) / 2)`: at `Q = Q*` it is `q_c*` again, the hysteresis loop
//! closes. Tractions are signed along the first load `Q*`.
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
        self.stick_distribution(x, coefficient, self.stick_half_width(q_ratio))
    }

    /// `q_c(x)`: the Cattaneo-Mindlin traction with the stick half-width `c` (module docs).
    fn stick_distribution(&self, x: f64, coefficient: f64, c: f64) -> f64 {
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

    /// Unloading from `Q*` (`peak_ratio = Q*/(F P)`, in `[0, 1]`) to `Q` (`q_ratio = Q/(F P)`,
    /// clamped to `[-peak_ratio, peak_ratio]`): the half-width `c' = a sqrt(1 - (r* - r)/2)`
    /// of the zone that sticks, outside which the contact slips backwards (module docs).
    pub fn counter_slip_half_width(&self, peak_ratio: f64, q_ratio: f64) -> f64 {
        let peak = peak_ratio.clamp(0.0, 1.0);
        let r = q_ratio.clamp(-peak, peak);
        self.half_width() * (1.0 - 0.5 * (peak - r)).sqrt()
    }

    /// Unloading from `Q*` to `Q` (ratios as in
    /// [`HertzContact::counter_slip_half_width`]): the tangential traction at `x`, signed along
    /// `Q*`, `q_c*(x) - 2 q_c'(x)`.
    pub fn unloading_traction(
        &self,
        x: f64,
        coefficient: f64,
        peak_ratio: f64,
        q_ratio: f64,
    ) -> f64 {
        let c_peak = self.stick_half_width(peak_ratio);
        let c_back = self.counter_slip_half_width(peak_ratio, q_ratio);
        self.stick_distribution(x, coefficient, c_peak)
            - 2.0 * self.stick_distribution(x, coefficient, c_back)
    }

    /// Reloading from `-Q*` to `Q` (ratios as in [`HertzContact::counter_slip_half_width`]),
    /// after unloading from `Q*` to `-Q*`: the tangential traction at `x`, signed along `Q*`,
    /// `-q_c*(x) + 2 q_c''(x)` with `c'' = a sqrt(1 - (r* + r)/2)`; the zone that sticks is
    /// `counter_slip_half_width(peak_ratio, -q_ratio)`.
    pub fn reloading_traction(
        &self,
        x: f64,
        coefficient: f64,
        peak_ratio: f64,
        q_ratio: f64,
    ) -> f64 {
        -self.unloading_traction(x, coefficient, peak_ratio, -q_ratio)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The integral of a traction over the contact zone (midpoint rule).
    fn resultant(hertz: &HertzContact, traction: impl Fn(f64) -> f64) -> f64 {
        let (a, n) = (hertz.half_width(), 200_000);
        let h = 2.0 * a / n as f64;
        (0..n)
            .map(|k| traction(-a + (k as f64 + 0.5) * h) * h)
            .sum()
    }

    /// The unloading and reloading tractions carry the loads they are for, stay within
    /// `F p`, and reloading to `Q*` closes the loop.
    #[test]
    fn unloading_and_reloading_carry_their_loads_and_close_the_loop() {
        let hertz = HertzContact::try_new(1.0, 100.0, 2.0).unwrap();
        let (f, peak) = (0.3, 0.8);
        let fp = f * hertz.load();
        for r in [0.8, 0.5, 0.0, -0.4, -0.8] {
            let unloaded = resultant(&hertz, |x| hertz.unloading_traction(x, f, peak, r));
            assert!(
                (unloaded / fp - r).abs() < 1e-4,
                "unloading to {r}: {}",
                unloaded / fp
            );
            let reloaded = resultant(&hertz, |x| hertz.reloading_traction(x, f, peak, r));
            assert!(
                (reloaded / fp - r).abs() < 1e-4,
                "reloading to {r}: {}",
                reloaded / fp
            );
            for k in 0..=100 {
                let x = hertz.half_width() * (-1.0 + 0.02 * k as f64);
                let bound = f * hertz.pressure(x) * (1.0 + 1e-12) + 1e-15;
                assert!(hertz.unloading_traction(x, f, peak, r).abs() <= bound);
                assert!(hertz.reloading_traction(x, f, peak, r).abs() <= bound);
            }
        }
        // Unloading to -Q*: the counter-slip zone reaches the stick zone of the loading.
        let c = hertz.stick_half_width(peak);
        assert!((hertz.counter_slip_half_width(peak, -peak) - c).abs() < 1e-15);
        for k in 0..=100 {
            let x = hertz.half_width() * (-1.0 + 0.02 * k as f64);
            let loaded = hertz.tangential_traction(x, f, peak);
            assert!((hertz.unloading_traction(x, f, peak, peak) - loaded).abs() < 1e-14);
            assert!((hertz.reloading_traction(x, f, peak, peak) - loaded).abs() < 1e-14);
            assert!((hertz.unloading_traction(x, f, peak, -peak) + loaded).abs() < 1e-14);
        }
    }
}

/// Hertz's contact of a sphere on a half-space: a rigid or elastic ball of radius `R` pressed
/// by a load `P` on an elastic half-space (`1/E* = (1 - nu_1^2)/E_1 + (1 - nu_2^2)/E_2`; a
/// rigid ball has `1/E_1 = 0`) touches it on a disc of radius `a`, with
///
/// ```text
/// a = (3 P R / (4 E*))^(1/3),   p(r) = p0 sqrt(1 - r^2/a^2),   p0 = 3 P / (2 pi a^2),
/// ```
///
/// and approach `delta = a^2 / R` (Johnson, Contact Mechanics, 4.2).
///
/// ```
/// use vem_verify::exact::HertzSphere;
/// let hertz = HertzSphere::try_new(2.0, 100.0, 3.0)?;
/// let (a, p0) = (hertz.contact_radius(), hertz.peak_pressure());
/// // The pressure integrates to the load: int_0^a p 2 pi r dr = 2 pi p0 a^2 / 3.
/// assert!((2.0 * std::f64::consts::PI * p0 * a * a / 3.0 - 3.0).abs() < 1e-12);
/// assert!((hertz.approach() - a * a / 2.0).abs() < 1e-15);
/// assert_eq!(hertz.pressure(1.01 * a), 0.0);
/// # Ok::<(), vem_verify::exact::ExactError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HertzSphere {
    radius: f64,
    effective_modulus: f64,
    load: f64,
}

impl HertzSphere {
    /// Radius `R`, effective modulus `E*` and load `P`, each finite and positive.
    ///
    /// # Errors
    /// [`ExactError::InvalidParameter`] naming the first value that is not.
    pub fn try_new(radius: f64, effective_modulus: f64, load: f64) -> Result<Self, ExactError> {
        let HertzContact {
            radius,
            effective_modulus,
            load,
        } = HertzContact::try_new(radius, effective_modulus, load)?;
        Ok(Self {
            radius,
            effective_modulus,
            load,
        })
    }

    /// `E*` of a rigid ball on a half-space of modulus `e`, Poisson ratio `nu`:
    /// `e / (1 - nu^2)`.
    pub fn rigid_ball_modulus(e: f64, nu: f64) -> f64 {
        e / (1.0 - nu * nu)
    }

    /// The radius `R` of the ball.
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// The effective modulus `E*`.
    pub fn effective_modulus(&self) -> f64 {
        self.effective_modulus
    }

    /// The load `P`.
    pub fn load(&self) -> f64 {
        self.load
    }

    /// The contact radius `a = (3 P R / (4 E*))^(1/3)`.
    pub fn contact_radius(&self) -> f64 {
        (3.0 * self.load * self.radius / (4.0 * self.effective_modulus)).cbrt()
    }

    /// The peak pressure `p0 = 3 P / (2 pi a^2)`.
    pub fn peak_pressure(&self) -> f64 {
        let a = self.contact_radius();
        3.0 * self.load / (2.0 * std::f64::consts::PI * a * a)
    }

    /// The pressure at distance `r` from the axis (zero outside the contact disc).
    pub fn pressure(&self, r: f64) -> f64 {
        let a = self.contact_radius();
        let s = 1.0 - (r / a).powi(2);
        if s > 0.0 {
            self.peak_pressure() * s.sqrt()
        } else {
            0.0
        }
    }

    /// The approach of distant points of the two bodies, `delta = a^2 / R`.
    pub fn approach(&self) -> f64 {
        self.contact_radius().powi(2) / self.radius
    }

    /// Cattaneo-Mindlin in space (Johnson, Contact Mechanics, 7.2): the ball pressed by `P`,
    /// then sheared by `Q < F P` with Coulomb's coefficient `F`, sticks on the disc of radius
    /// `c = a (1 - Q/(F P))^(1/3)` and slips on the annulus `c < r < a`; `q_ratio = Q/(F P)` is
    /// clamped to `[0, 1]` (full stick at 0, full slip at 1). Mindlin's solution neglects the
    /// coupling of the normal and tangential problems (exact for elastically similar bodies of
    /// incompressible material, a close approximation otherwise).
    pub fn stick_radius(&self, q_ratio: f64) -> f64 {
        self.contact_radius() * (1.0 - q_ratio.clamp(0.0, 1.0)).cbrt()
    }

    /// Cattaneo-Mindlin in space: the magnitude of the tangential traction at distance `r` from
    /// the axis for the coefficient `coefficient` and `q_ratio = Q/(F P)`, along the shear,
    ///
    /// ```text
    /// q(r) = F p0 sqrt(1 - r^2/a^2) - F p0 (c/a) sqrt(1 - r^2/c^2)   (r < c, stick)
    /// q(r) = F p(r)                                                 (c <= r, slip)
    /// ```
    ///
    /// which integrates to `Q` over the contact disc.
    pub fn tangential_traction(&self, r: f64, coefficient: f64, q_ratio: f64) -> f64 {
        let (a, c) = (self.contact_radius(), self.stick_radius(q_ratio));
        let slip = coefficient * self.pressure(r);
        if r.abs() < c {
            let s = r / c;
            slip - coefficient * self.peak_pressure() * (c / a) * (1.0 - s * s).max(0.0).sqrt()
        } else {
            slip
        }
    }
}

#[cfg(test)]
mod sphere_tests {
    use super::*;

    /// Hand values of Cattaneo-Mindlin in space: with `R = 1`, `E* = 3/4`, `P = 1` the
    /// contact radius is `a = 1` and `p0 = 3/(2 pi)`; at `Q/(F P) = 7/8` the stick radius is
    /// `c = a (1/8)^(1/3) = 1/2`; the traction integrates to `Q`.
    #[test]
    fn mindlin_stick_radius_and_traction_have_their_hand_values() {
        let hertz = HertzSphere::try_new(1.0, 0.75, 1.0).unwrap();
        let (f, q) = (0.4, 0.875);
        let p0 = 1.5 / std::f64::consts::PI;
        assert!((hertz.contact_radius() - 1.0).abs() < 1e-15);
        assert!((hertz.stick_radius(q) - 0.5).abs() < 1e-15);
        assert_eq!(hertz.stick_radius(0.0), hertz.contact_radius());
        assert_eq!(hertz.stick_radius(1.5), 0.0);
        // At the axis: F p0 (1 - c/a) = F p0 / 2.
        assert!((hertz.tangential_traction(0.0, f, q) - 0.5 * f * p0).abs() < 1e-15);
        // At r = 1/4: F p0 (sqrt(15/16) - sqrt(3/4)/2).
        let quarter = f * p0 * ((15.0f64 / 16.0).sqrt() - 0.5 * 0.75f64.sqrt());
        assert!((hertz.tangential_traction(0.25, f, q) - quarter).abs() < 1e-15);
        // In the slip annulus the traction is at its bound F p.
        assert_eq!(
            hertz.tangential_traction(0.75, f, q),
            f * hertz.pressure(0.75)
        );
        assert_eq!(hertz.tangential_traction(1.2, f, q), 0.0);
        // int q 2 pi r dr = Q = (Q/(F P)) F P, for every ratio (midpoint rule).
        for ratio in [0.2, 0.5, 0.8, 0.875] {
            let n = 200_000;
            let h = hertz.contact_radius() / n as f64;
            let resultant: f64 = (0..n)
                .map(|k| {
                    let r = (k as f64 + 0.5) * h;
                    hertz.tangential_traction(r, f, ratio) * 2.0 * std::f64::consts::PI * r * h
                })
                .sum();
            assert!(
                (resultant - ratio * f * hertz.load()).abs() < 1e-6,
                "{ratio}: {resultant}"
            );
        }
    }
}
