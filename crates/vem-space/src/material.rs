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
    fn indefinite_tensor_is_rejected() {
        // lambda = -2 mu: bulk modulus zero in plane strain, not positive definite.
        let err = ElasticityTensor::try_isotropic(-1.0, 1.0).unwrap_err();
        assert!(err.to_string().contains("positive definite"), "{err}");
        let err = ElasticityTensor::try_isotropic(f64::NAN, 1.0).unwrap_err();
        assert!(err.to_string().contains("non-finite"), "{err}");
    }
}
