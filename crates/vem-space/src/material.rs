//! The elasticity tensor in Voigt notation.

use nalgebra::{Matrix3, Vector3};

use crate::SpaceError;

/// A symmetric positive definite elasticity tensor `C` in Voigt notation
/// (`sigma = C eps`, `eps = [eps_xx, eps_yy, 2 eps_xy]`), the material as the element sees it.
///
/// ```
/// use vem_space::ElasticityTensor;
/// let c = ElasticityTensor::try_isotropic(2.0, 1.0)?; // lambda = 2, mu = 1 (plane strain)
/// assert_eq!(c.voigt()[(0, 0)], 4.0);           // lambda + 2 mu
/// assert_eq!(c.shear_modulus(), 1.0);
/// # Ok::<(), vem_space::SpaceError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ElasticityTensor {
    voigt: Matrix3<f64>,
}

impl ElasticityTensor {
    /// The isotropic plane-strain tensor `lambda tr(eps) I + 2 mu eps` (Lame parameters).
    pub fn try_isotropic(lambda: f64, mu: f64) -> Result<Self, SpaceError> {
        Self::try_from_voigt(Matrix3::new(
            lambda + 2.0 * mu,
            lambda,
            0.0,
            lambda,
            lambda + 2.0 * mu,
            0.0,
            0.0,
            0.0,
            mu,
        ))
    }

    /// A general tensor from its Voigt matrix; it must be finite, symmetric and positive
    /// definite (spec (2.8)).
    pub fn try_from_voigt(voigt: Matrix3<f64>) -> Result<Self, SpaceError> {
        if voigt.iter().any(|c| !c.is_finite()) {
            return Err(SpaceError::InvalidMaterial {
                reason: format!("non-finite entry in the elasticity tensor {voigt}"),
            });
        }
        let scale = voigt.abs().max();
        if (voigt - voigt.transpose()).abs().max() > 1e-12 * scale {
            return Err(SpaceError::InvalidMaterial {
                reason: format!("the elasticity tensor is not symmetric: {voigt}"),
            });
        }
        // Sylvester's criterion on the leading minors.
        let minors = [
            voigt[(0, 0)],
            voigt[(0, 0)] * voigt[(1, 1)] - voigt[(0, 1)] * voigt[(1, 0)],
            voigt.determinant(),
        ];
        if minors.iter().any(|&m| m <= 0.0) {
            return Err(SpaceError::InvalidMaterial {
                reason: format!(
                    "the elasticity tensor is not positive definite (leading minors {minors:?})"
                ),
            });
        }
        Ok(Self { voigt })
    }

    /// The Voigt matrix.
    pub fn voigt(&self) -> &Matrix3<f64> {
        &self.voigt
    }

    /// The trace of the Voigt matrix (`2 lambda + 5 mu` for an isotropic material).
    pub fn trace(&self) -> f64 {
        self.voigt.trace()
    }

    /// The shear entry `C_33` (`mu` for an isotropic material).
    pub fn shear_modulus(&self) -> f64 {
        self.voigt[(2, 2)]
    }

    /// The deviatoric part `C_dev = P^T C P` (Voigt), with `P = I - m m^T / 2` the projection
    /// of a Voigt strain `[eps_xx, eps_yy, 2 eps_xy]` onto its trace-free part (`m = [1, 1, 0]`,
    /// `m . eps = tr eps`). For an isotropic material `lambda` drops out:
    /// `C_dev = mu [[1, -1, 0], [-1, 1, 0], [0, 0, 1]]`, of trace `3 mu`.
    ///
    /// ```
    /// use vem_space::ElasticityTensor;
    /// let c = ElasticityTensor::try_isotropic(1e6, 1.0)?;
    /// assert!((c.deviatoric().trace() - 3.0).abs() < 1e-9);
    /// # Ok::<(), vem_space::SpaceError>(())
    /// ```
    pub fn deviatoric(&self) -> Matrix3<f64> {
        let m = Vector3::new(1.0, 1.0, 0.0);
        let p = Matrix3::identity() - m * m.transpose() * 0.5;
        p.transpose() * self.voigt * p
    }

    /// The bulk modulus `kappa = m^T C m / 4` (`m = [1, 1, 0]`): the stress `kappa tr(eps)` of a
    /// pure dilatation `eps = tr(eps) m / 2`, averaged over the two normal directions
    /// (`lambda + mu` for an isotropic plane-strain material). With it,
    /// `trace(C) = trace(C_dev) + 2 kappa` for every tensor (the cross terms `P C m` have no
    /// trace).
    pub fn bulk_modulus(&self) -> f64 {
        let m = Vector3::new(1.0, 1.0, 0.0);
        m.dot(&(self.voigt * m)) / 4.0
    }

    /// The stress `sigma = C eps` in Voigt notation `[xx, yy, xy]` of a strain
    /// `[eps_xx, eps_yy, 2 eps_xy]` (engineering shear).
    pub fn stress(&self, strain: &Vector3<f64>) -> Vector3<f64> {
        self.voigt * strain
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn isotropic_entries_and_scalings() {
        let c = ElasticityTensor::try_isotropic(2.0, 1.0).unwrap();
        assert_eq!(c.voigt()[(0, 1)], 2.0);
        assert_eq!(c.trace(), 2.0 * 2.0 + 5.0 * 1.0);
    }

    #[test]
    fn stress_of_the_pt0a_strain() {
        // PT0a (docs/manufactured.md): eps = (1/5, 2/5, shear 1/10) -> sigma = (1.6, 2.0, 0.2).
        let c = ElasticityTensor::try_isotropic(2.0, 1.0).unwrap();
        let sigma = c.stress(&Vector3::new(0.2, 0.4, 0.2));
        assert!((sigma - Vector3::new(1.6, 2.0, 0.2)).norm() < 1e-15);
    }

    #[test]
    fn deviatoric_and_bulk_split_the_trace() {
        // Isotropic: trace(C_dev) = 3 mu, kappa = lambda + mu, independent of each other.
        let c = ElasticityTensor::try_isotropic(2.0, 1.0).unwrap();
        assert!((c.deviatoric().trace() - 3.0).abs() < 1e-15);
        assert!((c.bulk_modulus() - 3.0).abs() < 1e-15);
        // A fully anisotropic tensor: trace(C) = trace(C_dev) + 2 kappa, C_dev m = 0.
        let c = ElasticityTensor::try_from_voigt(Matrix3::new(
            5.0, 1.5, 0.7, 1.5, 4.0, -0.4, 0.7, -0.4, 2.0,
        ))
        .unwrap();
        let split = c.deviatoric().trace() + 2.0 * c.bulk_modulus();
        assert!((split - c.trace()).abs() < 1e-14);
        assert!((c.deviatoric() * Vector3::new(1.0, 1.0, 0.0)).norm() < 1e-15);
    }

    #[test]
    fn indefinite_tensor_is_rejected() {
        // lambda = -2 mu: bulk modulus zero in plane strain, not positive definite.
        let err = ElasticityTensor::try_isotropic(-1.0, 1.0).unwrap_err();
        assert!(err.to_string().contains("positive definite"), "{err}");
        let err = ElasticityTensor::try_isotropic(f64::NAN, 1.0).unwrap_err();
        assert!(err.to_string().contains("non-finite"), "{err}");
    }
}
