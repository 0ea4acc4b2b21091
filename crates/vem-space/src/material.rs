//! The elasticity tensor in Voigt notation, in two or three dimensions.

use nalgebra::{DMatrix, Matrix3, SMatrix, Vector3};

use crate::SpaceError;

/// The number of independent entries of a symmetric `D x D` tensor: 3 in 2D, 6 in 3D.
pub const fn voigt_len(dimension: usize) -> usize {
    dimension * (dimension + 1) / 2
}

/// The index pairs `(i, j)` of the Voigt entries in order: `[xx, yy, xy]` in 2D,
/// `[xx, yy, zz, yz, xz, xy]` in 3D (normal entries first, then the shears).
pub fn voigt_pairs(dimension: usize) -> &'static [(usize, usize)] {
    match dimension {
        1 => &[(0, 0)],
        2 => &[(0, 0), (1, 1), (0, 1)],
        _ => &[(0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1)],
    }
}

/// A symmetric positive definite elasticity tensor `C` of dimension `D` (2 or 3) in Voigt
/// notation (`sigma = C eps`), the material as the element sees it. Strains carry the
/// engineering shears (`eps = [eps_xx, eps_yy, 2 eps_xy]` in 2D, `[eps_xx, eps_yy, eps_zz,
/// 2 eps_yz, 2 eps_xz, 2 eps_xy]` in 3D), so that `C` is a symmetric `3 x 3` or `6 x 6` matrix.
///
/// ```
/// use vem_space::ElasticityTensor;
/// let c = ElasticityTensor::try_isotropic(2.0, 1.0)?; // lambda = 2, mu = 1 (plane strain)
/// assert_eq!(c.voigt()[(0, 0)], 4.0);           // lambda + 2 mu
/// assert_eq!(c.shear_modulus(), 1.0);
/// # Ok::<(), vem_space::SpaceError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ElasticityTensor<const D: usize = 2> {
    /// The Voigt matrix in the leading `voigt_len(D)` rows and columns.
    voigt: SMatrix<f64, 6, 6>,
}

impl<const D: usize> ElasticityTensor<D> {
    /// The number of Voigt entries, `D (D + 1) / 2`.
    pub const VOIGT_LEN: usize = voigt_len(D);

    /// A general tensor from its Voigt matrix (`VOIGT_LEN x VOIGT_LEN`); it must be finite,
    /// symmetric and positive definite (spec (2.8)).
    pub fn try_from_voigt_matrix(voigt: &DMatrix<f64>) -> Result<Self, SpaceError> {
        let n = Self::VOIGT_LEN;
        if !(2..=3).contains(&D) || voigt.nrows() != n || voigt.ncols() != n {
            return Err(SpaceError::InvalidMaterial {
                reason: format!(
                    "a {D}D elasticity tensor is a {n} x {n} Voigt matrix, got {} x {}",
                    voigt.nrows(),
                    voigt.ncols()
                ),
            });
        }
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
        // Positive definite: a Cholesky factor of the matrix scaled to a largest entry of 1
        // (scale-free, so moduli near the floating-point range do not overflow), with the
        // leading minors for the message.
        let scaled = voigt / scale;
        if scaled.clone().cholesky().is_none() {
            let minors: Vec<f64> = (1..=n)
                .map(|k| scaled.view((0, 0), (k, k)).determinant() * scale.powi(k as i32))
                .collect();
            return Err(SpaceError::InvalidMaterial {
                reason: format!(
                    "the elasticity tensor is not positive definite (leading minors {minors:?})"
                ),
            });
        }
        let mut stored = SMatrix::<f64, 6, 6>::zeros();
        stored.view_mut((0, 0), (n, n)).copy_from(voigt);
        Ok(Self { voigt: stored })
    }

    /// The Voigt matrix (`VOIGT_LEN x VOIGT_LEN`).
    pub fn voigt_matrix(&self) -> DMatrix<f64> {
        let n = Self::VOIGT_LEN;
        DMatrix::from_fn(n, n, |i, j| self.voigt[(i, j)])
    }

    /// The trace of the Voigt matrix (`2 lambda + 5 mu` for an isotropic material in 2D,
    /// `3 lambda + 9 mu` in 3D).
    pub fn trace(&self) -> f64 {
        (0..Self::VOIGT_LEN).map(|i| self.voigt[(i, i)]).sum()
    }

    /// The mean of the shear entries of the diagonal (`mu` for an isotropic material).
    pub fn shear_modulus(&self) -> f64 {
        let shears = D..Self::VOIGT_LEN;
        let count = shears.len() as f64;
        shears.map(|i| self.voigt[(i, i)]).sum::<f64>() / count
    }

    /// The stress tensor `sigma = C eps` of the (symmetric) strain tensor `strain`.
    pub fn stress_tensor(&self, strain: &SMatrix<f64, D, D>) -> SMatrix<f64, D, D> {
        let pairs = voigt_pairs(D);
        // Voigt strain with engineering shears (at most 6 entries: no allocation, the
        // post-processing calls this for every cell).
        let mut eps = [0.0; 6];
        for (e, &(i, j)) in eps.iter_mut().zip(pairs) {
            *e = if i == j {
                strain[(i, j)]
            } else {
                strain[(i, j)] + strain[(j, i)]
            };
        }
        let eps = &eps[..pairs.len()];
        let mut sigma = SMatrix::<f64, D, D>::zeros();
        for (a, &(i, j)) in pairs.iter().enumerate() {
            let value: f64 = eps
                .iter()
                .enumerate()
                .map(|(b, e)| self.voigt[(a, b)] * e)
                .sum();
            sigma[(i, j)] = value;
            sigma[(j, i)] = value;
        }
        sigma
    }
}

impl ElasticityTensor<2> {
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
        Self::try_from_voigt_matrix(&DMatrix::from_column_slice(3, 3, voigt.as_slice()))
    }

    /// The Voigt matrix.
    pub fn voigt(&self) -> Matrix3<f64> {
        self.voigt.fixed_view::<3, 3>(0, 0).into_owned()
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
        p.transpose() * self.voigt() * p
    }

    /// The bulk modulus `kappa = m^T C m / 4` (`m = [1, 1, 0]`): the stress `kappa tr(eps)` of a
    /// pure dilatation `eps = tr(eps) m / 2`, averaged over the two normal directions
    /// (`lambda + mu` for an isotropic plane-strain material). With it,
    /// `trace(C) = trace(C_dev) + 2 kappa` for every tensor (the cross terms `P C m` have no
    /// trace).
    pub fn bulk_modulus(&self) -> f64 {
        let m = Vector3::new(1.0, 1.0, 0.0);
        m.dot(&(self.voigt() * m)) / 4.0
    }

    /// The stress `sigma = C eps` in Voigt notation `[xx, yy, xy]` of a strain
    /// `[eps_xx, eps_yy, 2 eps_xy]` (engineering shear).
    pub fn stress(&self, strain: &Vector3<f64>) -> Vector3<f64> {
        self.voigt() * strain
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
    fn stress_tensor_matches_the_voigt_product() {
        // 2D: the tensor form of C eps agrees with the Voigt product (engineering shear).
        let c = ElasticityTensor::try_isotropic(2.0, 1.0).unwrap();
        let strain = nalgebra::Matrix2::new(0.2, 0.05, 0.05, 0.4);
        let sigma = c.stress_tensor(&strain);
        let voigt = c.stress(&Vector3::new(0.2, 0.4, 0.1));
        assert!(
            (sigma - nalgebra::Matrix2::new(voigt.x, voigt.z, voigt.z, voigt.y)).norm() < 1e-15
        );
        // 3D isotropic: sigma = lambda tr(eps) I + 2 mu eps.
        let (lambda, mu) = (2.0, 1.0);
        let mut m = DMatrix::zeros(6, 6);
        for i in 0..3 {
            for j in 0..3 {
                m[(i, j)] = lambda + if i == j { 2.0 * mu } else { 0.0 };
            }
            m[(i + 3, i + 3)] = mu;
        }
        let c3 = ElasticityTensor::<3>::try_from_voigt_matrix(&m).unwrap();
        assert_eq!(c3.shear_modulus(), mu);
        assert_eq!(c3.trace(), 3.0 * lambda + 9.0 * mu);
        let eps = nalgebra::Matrix3::new(0.1, 0.02, -0.03, 0.02, -0.2, 0.04, -0.03, 0.04, 0.3);
        let expected = nalgebra::Matrix3::identity() * lambda * eps.trace() + eps * 2.0 * mu;
        assert!((c3.stress_tensor(&eps) - expected).norm() < 1e-14);
        assert!(ElasticityTensor::<3>::try_from_voigt_matrix(&DMatrix::zeros(3, 3)).is_err());
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
