//! One-dimensional jets: a function value together with its first derivatives at a point
//! (`docs/manufactured.md`, section 4).
//!
//! Every two-body solution of Family A is linear in four functions of x (tangential and
//! vertical traces, shear traction, contact pressure), so adding, scaling and differentiating
//! jets is all the calculus its displacement, gradient, stress and body force need. Products
//! (Leibniz rule) are provided for building data as products of simpler pieces.
//!
//! ```
//! use vem_verify::exact::{Jet, SwitchPower, SwitchSide};
//! // p(x) = ((x_c - x)_+ / x_c)^4 with x_c = 1/2, at x = 1/4: value and three derivatives.
//! let p = SwitchPower::try_new(1.0, SwitchSide::Below, 0.5, 0.5, 4)?;
//! let jet: Jet<4> = p.jet(0.25);
//! assert_eq!(jet.0, [1.0 / 16.0, -1.0, 12.0, -96.0]);
//! // Its derivative as a jet of one order less.
//! let dp: Jet<3> = jet.derivative();
//! assert_eq!(dp.value(), -1.0);
//! # Ok::<(), vem_verify::exact::ExactError>(())
//! ```

use std::ops::{Add, Index, Mul, Neg, Sub};

use super::ExactError;

/// The value and the first `N - 1` derivatives of a function of one variable at a point:
/// `self.0[j]` is the j-th derivative.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Jet<const N: usize>(pub [f64; N]);

impl<const N: usize> Jet<N> {
    /// The zero function.
    pub const ZERO: Self = Self([0.0; N]);

    /// A constant function: value `c`, every derivative zero.
    pub fn constant(c: f64) -> Self {
        let mut jet = Self::ZERO;
        if N > 0 {
            jet.0[0] = c;
        }
        jet
    }

    /// The polynomial `sum_m coefficients[m] x^m` and its derivatives at `x`.
    pub fn polynomial(coefficients: &[f64], x: f64) -> Self {
        let mut jet = Self::ZERO;
        for (j, entry) in jet.0.iter_mut().enumerate() {
            // j-th derivative: sum_{m >= j} c_m m!/(m-j)! x^(m-j), by Horner's rule.
            let mut value = 0.0;
            for m in (j..coefficients.len()).rev() {
                value = value * x + coefficients[m] * falling_factorial(m, j);
            }
            *entry = value;
        }
        jet
    }

    /// The function value.
    pub fn value(&self) -> f64 {
        self.0[0]
    }

    /// The derivative as a jet of order `M <= N - 1` (the entries shifted by one: the value is
    /// dropped). `M >= N` does not compile.
    pub fn derivative<const M: usize>(&self) -> Jet<M> {
        const {
            assert!(
                M < N,
                "the derivative of a Jet<N> has at most N - 1 entries"
            )
        };
        Jet(std::array::from_fn(|j| self.0[j + 1]))
    }

    /// The first `M <= N` entries (forget the highest derivatives). `M > N` does not compile.
    pub fn truncate<const M: usize>(&self) -> Jet<M> {
        const {
            assert!(
                M <= N,
                "a Jet<N> can only be truncated to at most N entries"
            )
        };
        Jet(std::array::from_fn(|j| self.0[j]))
    }

    /// The jet of `c f`.
    pub fn scale(self, c: f64) -> Self {
        Self(self.0.map(|v| c * v))
    }
}

impl<const N: usize> Default for Jet<N> {
    fn default() -> Self {
        Self::ZERO
    }
}

impl<const N: usize> Index<usize> for Jet<N> {
    type Output = f64;

    /// The `j`-th derivative.
    fn index(&self, j: usize) -> &f64 {
        &self.0[j]
    }
}

impl<const N: usize> Add for Jet<N> {
    type Output = Self;

    fn add(self, other: Self) -> Self {
        Self(std::array::from_fn(|j| self.0[j] + other.0[j]))
    }
}

impl<const N: usize> Sub for Jet<N> {
    type Output = Self;

    fn sub(self, other: Self) -> Self {
        Self(std::array::from_fn(|j| self.0[j] - other.0[j]))
    }
}

impl<const N: usize> Neg for Jet<N> {
    type Output = Self;

    fn neg(self) -> Self {
        Self(self.0.map(|v| -v))
    }
}

impl<const N: usize> Mul<f64> for Jet<N> {
    type Output = Self;

    fn mul(self, c: f64) -> Self {
        self.scale(c)
    }
}

impl<const N: usize> Mul for Jet<N> {
    type Output = Self;

    /// The product `f g` by the Leibniz rule `(f g)^(j) = sum_i C(j, i) f^(i) g^(j-i)`
    /// (multiply by a polynomial jet to multiply by a polynomial).
    fn mul(self, other: Self) -> Self {
        Self(std::array::from_fn(|j| {
            let mut binomial = 1.0;
            let mut sum = 0.0;
            for i in 0..=j {
                sum += binomial * self.0[i] * other.0[j - i];
                binomial = binomial * (j - i) as f64 / (i + 1) as f64;
            }
            sum
        }))
    }
}

/// `m!/(m-j)!` (zero when `j > m`).
fn falling_factorial(m: usize, j: usize) -> f64 {
    if j > m {
        return 0.0;
    }
    ((m - j + 1)..=m).map(|i| i as f64).product()
}

/// On which side of its switch point a [`SwitchPower`] is non-zero (the sign `d` of
/// `docs/manufactured.md`, section 4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SwitchSide {
    /// `d = -1`: non-zero for `x < X`.
    Below,
    /// `d = +1`: non-zero for `x > X`.
    Above,
}

impl SwitchSide {
    /// The sign `d` (`-1` or `+1`).
    pub fn sign(self) -> f64 {
        match self {
            SwitchSide::Below => -1.0,
            SwitchSide::Above => 1.0,
        }
    }
}

/// The switch function `PP(c, d, X, L, k)(x) = c ((d (x - X))_+ / L)^k` of `docs/manufactured.md`,
/// section 4: zero on one side of the switch point `X`, a power of the distance to `X` on the
/// other, `C^(k-1)` across `X`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SwitchPower {
    amplitude: f64,
    side: SwitchSide,
    switch_point: f64,
    length: f64,
    power: u32,
}

impl SwitchPower {
    /// `PP(amplitude, side, switch_point, length, power)`; `length` is the distance from the
    /// switch point at which `|PP| = |amplitude|`.
    ///
    /// # Errors
    /// [`ExactError::InvalidSwitchFunction`] if a parameter is not finite, `length <= 0` or
    /// `power == 0`.
    pub fn try_new(
        amplitude: f64,
        side: SwitchSide,
        switch_point: f64,
        length: f64,
        power: u32,
    ) -> Result<Self, ExactError> {
        let reason = if !(amplitude.is_finite() && switch_point.is_finite() && length.is_finite()) {
            Some("every parameter must be finite")
        } else if length <= 0.0 {
            Some("the length L must be positive")
        } else if power == 0 {
            Some("the power k must be at least 1")
        } else {
            None
        };
        match reason {
            Some(reason) => Err(ExactError::InvalidSwitchFunction {
                amplitude,
                switch_point,
                length,
                power,
                reason,
            }),
            None => Ok(Self {
                amplitude,
                side,
                switch_point,
                length,
                power,
            }),
        }
    }

    /// The same as [`SwitchPower::try_new`] for parameters known to be valid, usable in
    /// `const` items, where the check runs at compile time (how the built-in cases define
    /// their switch functions; do the same for a case of your own):
    ///
    /// ```
    /// use vem_verify::exact::{SwitchPower, SwitchSide};
    /// const OPENING: SwitchPower = SwitchPower::from_valid_parts(0.05, SwitchSide::Above, 0.5, 0.5, 5);
    /// assert_eq!(OPENING.jet::<1>(1.0).value(), 0.05);
    /// ```
    ///
    /// # Panics
    /// If a parameter is not finite, `length <= 0` or `power == 0` (in a `const` item this is
    /// a compile error). Use [`SwitchPower::try_new`] for parameters known only at run time.
    pub const fn from_valid_parts(
        amplitude: f64,
        side: SwitchSide,
        switch_point: f64,
        length: f64,
        power: u32,
    ) -> Self {
        assert!(
            amplitude.is_finite() && switch_point.is_finite() && length.is_finite(),
            "switch function parameters must be finite"
        );
        assert!(
            length > 0.0 && power > 0,
            "switch function needs L > 0 and k >= 1"
        );
        Self {
            amplitude,
            side,
            switch_point,
            length,
            power,
        }
    }

    /// The switch point `X`.
    pub fn switch_point(&self) -> f64 {
        self.switch_point
    }

    /// Value and derivatives at `x`:
    /// `j`-th derivative `= c d^j k!/(k-j)! (d (x - X))_+^(k-j) / L^k` for `j <= k`
    /// (with `z_+^0 = [z > 0]`), zero for `j > k`.
    pub fn jet<const N: usize>(&self, x: f64) -> Jet<N> {
        let d = self.side.sign();
        let z = d * (x - self.switch_point);
        let k = self.power as usize;
        let scale = self.amplitude / self.length.powi(self.power as i32);
        Jet(std::array::from_fn(|j| {
            if j > k || z <= 0.0 {
                return 0.0;
            }
            let d_j = if j % 2 == 0 { 1.0 } else { d };
            scale * d_j * falling_factorial(k, j) * z.powi((k - j) as i32)
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn polynomial_derivatives_by_hand() {
        // 1 + 2x + 3x^2 + 4x^3 at x = 2: 49, 2 + 6x + 12x^2 = 62, 6 + 24x = 54, 24, 0.
        let jet: Jet<5> = Jet::polynomial(&[1.0, 2.0, 3.0, 4.0], 2.0);
        assert_eq!(jet.0, [49.0, 62.0, 54.0, 24.0, 0.0]);
    }

    #[test]
    fn leibniz_product_matches_polynomial_product() {
        // (1 + x)(2 - x + x^2) = 2 + x + 0 x^2 + x^3.
        let x = 0.3;
        let f: Jet<4> = Jet::polynomial(&[1.0, 1.0], x);
        let g: Jet<4> = Jet::polynomial(&[2.0, -1.0, 1.0], x);
        let product: Jet<4> = Jet::polynomial(&[2.0, 1.0, 0.0, 1.0], x);
        for j in 0..4 {
            assert!(((f * g)[j] - product[j]).abs() < 1e-15);
        }
    }

    #[test]
    fn switch_power_both_sides() {
        // PP(2, +1, 1, 2, 3) = 2 ((x-1)_+/2)^3 = (x-1)_+^3 / 4.
        let pp = SwitchPower::try_new(2.0, SwitchSide::Above, 1.0, 2.0, 3).unwrap();
        let above: Jet<5> = pp.jet(3.0);
        assert_eq!(above.0, [2.0, 3.0, 3.0, 1.5, 0.0]);
        let below: Jet<5> = pp.jet(0.5);
        assert_eq!(below.0, [0.0; 5]);
        // d = -1: odd derivatives change sign.
        let mirrored = SwitchPower::try_new(2.0, SwitchSide::Below, 1.0, 2.0, 3).unwrap();
        let jet: Jet<4> = mirrored.jet(-1.0);
        assert_eq!(jet.0, [2.0, -3.0, 3.0, -1.5]);
    }

    #[test]
    fn switch_power_rejects_bad_parameters() {
        assert!(SwitchPower::try_new(1.0, SwitchSide::Above, 0.5, 0.0, 3).is_err());
        assert!(SwitchPower::try_new(1.0, SwitchSide::Above, 0.5, 1.0, 0).is_err());
        assert!(SwitchPower::try_new(f64::NAN, SwitchSide::Above, 0.5, 1.0, 2).is_err());
    }
}
