//! The stabilisations of the lowest-order virtual element on polyhedra.
//!
//! The same three recipes as in 2D ([`crate::Stabilisation`]), with what changes in 3D: the
//! entries of the consistency matrix scale like `C h` (not `C`), so a material constant needs a
//! length, and the deviatoric and bulk parts of `C` are those of a 3D tensor.
//!
//! **Dofi-dofi** ([`DofiDofi`]): `S = alpha I` with
//!
//! ```text
//! alpha = scale * constant(C) * l_E / 6,     l_E = h_E / sqrt(3)
//! ```
//!
//! `l_E` is the side of the cube of diameter `h_E` (the side itself on a cube, a tetrahedron
//! of a Kuhn split of that cube has the same `l_E`). With the default scale 1/8 and
//! `constant(C) = trace(C)`, `alpha = trace(C) h / 48` on a cube of side `h`, the analogue of
//! `trace(C)/8` on a square: there the mean diagonal entry of `K_c` is
//! `(C_11 + C_22 + C_33 + 2 (C_44 + C_55 + C_66)) h / 48` (each corner's `q_a = (+-1, +-1, +-1)/(4 h)`),
//! as it is `(C_11 + C_22 + 2 C_33)/8` on a square. The shear scaling takes `9 mu`
//! (`9 x` the mean shear entry), the value `trace(C) = 3 lambda + 9 mu` takes at `lambda = 0`.
//!
//! **D-recipe** ([`DRecipe`]): `S_ii = max(K_c,ii, FLOOR trace(C) l_E / 6)`.
//!
//! **Locking-free** ([`BBar`]): `S = alpha I` with
//!
//! ```text
//! alpha = min(trace(C), 3 trace(C_dev)) l_E / 48
//!       = (trace(C_dev) + min(3 kappa, 2 trace(C_dev))) l_E / 48
//! ```
//!
//! where `C_dev = P^T C P`, `P = I - m m^T / 3`, `m = [1, 1, 1, 0, 0, 0]` (the projection of a
//! Voigt strain onto its trace-free part) and `kappa = m^T C m / 9` (the bulk modulus:
//! `lambda + 2 mu / 3` for an isotropic material). The identity `trace(C) = trace(C_dev) +
//! 3 kappa` holds for every tensor (`trace(C P) = trace(C) - m^T C m / 3`, `P` symmetric and
//! idempotent). The 2D rule bounds the bulk part `2 kappa` of `trace(C)` by twice the
//! deviatoric part; here the bulk part is `3 kappa`, bounded by the same `2 trace(C_dev)`, which
//! gives the same formula `min(trace(C), 3 trace(C_dev))`. For an isotropic material
//! `trace(C_dev) = 7 mu` (`4 mu` from the normal block, `3 mu` from the shears): `alpha` is the
//! default's for `3 lambda + 9 mu <= 21 mu`, i.e. `lambda <= 4 mu` (Poisson's ratio `<= 0.4`),
//! and `21 mu l_E / 48` beyond, whatever `lambda`: between `trace(C_dev)` and
//! `3 trace(C_dev)` (times `l_E / 48`), spectrally equivalent to the deviatoric energy with
//! constants free of `lambda`.

use nalgebra::{DMatrix, DVector, SMatrix, SVector};

use crate::{
    BBar, DRecipe, DofiDofi, ElasticityTensor, PolyhedronGeometry, SpaceError, Stabilisation,
    StabilisationScaling,
};

/// A stabilisation that also serves the element on polyhedra ([`crate::PolyhedralVem`]): the
/// diagonal `S` of `(I - Pi_dof)^T S (I - Pi_dof)` on a polyhedron. Its name, description and
/// settings are those of the [`Stabilisation`] it extends.
pub trait PolyhedralStabilisation: Stabilisation {
    /// The diagonal of `S` (length `3n`, finite and positive) for the polyhedron `geometry`, the
    /// material `material` and the consistency matrix `consistency` (`K_c`, 3n x 3n).
    fn polyhedral_diagonal(
        &self,
        geometry: &PolyhedronGeometry,
        material: &ElasticityTensor<3>,
        consistency: &DMatrix<f64>,
    ) -> Result<DVector<f64>, SpaceError>;
}

/// The length `l_E / 6 = h_E / (6 sqrt 3)` that turns a material constant into a stabilisation
/// entry on a polyhedron (module docs).
pub fn stabilisation_length(geometry: &PolyhedronGeometry) -> f64 {
    geometry.diameter() / (6.0 * 3f64.sqrt())
}

/// The deviatoric part `C_dev = P^T C P` of a 3D tensor (Voigt, `P = I - m m^T / 3`,
/// `m = [1, 1, 1, 0, 0, 0]`). For an isotropic material `lambda` drops out and
/// `trace(C_dev) = 7 mu`.
pub fn deviatoric_part(material: &ElasticityTensor<3>) -> SMatrix<f64, 6, 6> {
    let m = SVector::<f64, 6>::new(1.0, 1.0, 1.0, 0.0, 0.0, 0.0);
    let p = SMatrix::<f64, 6, 6>::identity() - m * m.transpose() / 3.0;
    let voigt = material.voigt_matrix();
    let c = SMatrix::<f64, 6, 6>::from_fn(|i, j| voigt[(i, j)]);
    p.transpose() * c * p
}

/// The bulk modulus `kappa = m^T C m / 9` of a 3D tensor (`lambda + 2 mu / 3` for an isotropic
/// material): `trace(C) = trace(C_dev) + 3 kappa`.
pub fn bulk_modulus_3d(material: &ElasticityTensor<3>) -> f64 {
    let c = material.voigt_matrix();
    (0..3)
        .flat_map(|i| (0..3).map(move |j| (i, j)))
        .map(|(i, j)| c[(i, j)])
        .sum::<f64>()
        / 9.0
}

/// The material constant of a dofi-dofi scaling in 3D: `trace(C)`, or `9 x` the mean shear
/// entry (the value of `trace(C)` at `lambda = 0`).
fn constant_3d(scaling: StabilisationScaling, material: &ElasticityTensor<3>) -> f64 {
    match scaling {
        StabilisationScaling::TraceOfC => material.trace(),
        StabilisationScaling::ShearModulus => 9.0 * material.shear_modulus(),
    }
}

impl PolyhedralStabilisation for DofiDofi {
    fn polyhedral_diagonal(
        &self,
        geometry: &PolyhedronGeometry,
        material: &ElasticityTensor<3>,
        consistency: &DMatrix<f64>,
    ) -> Result<DVector<f64>, SpaceError> {
        let alpha =
            self.scale() * constant_3d(self.scaling(), material) * stabilisation_length(geometry);
        Ok(DVector::from_element(consistency.nrows(), alpha))
    }
}

impl PolyhedralStabilisation for DRecipe {
    fn polyhedral_diagonal(
        &self,
        geometry: &PolyhedronGeometry,
        material: &ElasticityTensor<3>,
        consistency: &DMatrix<f64>,
    ) -> Result<DVector<f64>, SpaceError> {
        let floor = Self::FLOOR * material.trace() * stabilisation_length(geometry);
        Ok(consistency.diagonal().map(|k| k.max(floor)))
    }
}

impl BBar {
    /// `alpha / l_E * 6` on a polyhedron: `min(trace(C), 3 trace(C_dev)) / 8` with the 3D
    /// deviatoric part (module docs of the polyhedral stabilisations).
    pub fn polyhedral_alpha(material: &ElasticityTensor<3>) -> f64 {
        Self::SCALE
            * material
                .trace()
                .min(3.0 * deviatoric_part(material).trace())
    }
}

impl PolyhedralStabilisation for BBar {
    fn polyhedral_diagonal(
        &self,
        geometry: &PolyhedronGeometry,
        material: &ElasticityTensor<3>,
        consistency: &DMatrix<f64>,
    ) -> Result<DVector<f64>, SpaceError> {
        Ok(DVector::from_element(
            consistency.nrows(),
            Self::polyhedral_alpha(material) * stabilisation_length(geometry),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn isotropic(lambda: f64, mu: f64) -> ElasticityTensor<3> {
        let mut c = DMatrix::zeros(6, 6);
        for i in 0..3 {
            for j in 0..3 {
                c[(i, j)] = lambda + if i == j { 2.0 * mu } else { 0.0 };
            }
            c[(i + 3, i + 3)] = mu;
        }
        ElasticityTensor::<3>::try_from_voigt_matrix(&c).unwrap()
    }

    #[test]
    fn the_3d_split_of_the_trace_holds_for_isotropic_and_anisotropic_tensors() {
        let c = isotropic(2.0, 1.0);
        assert!((deviatoric_part(&c).trace() - 7.0).abs() < 1e-14);
        assert!((bulk_modulus_3d(&c) - (2.0 + 2.0 / 3.0)).abs() < 1e-14);
        // A fully anisotropic positive definite tensor: A^T A + I.
        let a = DMatrix::from_fn(6, 6, |i, j| ((i * 7 + j * 3) % 5) as f64 * 0.3 - 0.4);
        let voigt = a.transpose() * &a + DMatrix::identity(6, 6);
        let c = ElasticityTensor::<3>::try_from_voigt_matrix(&voigt).unwrap();
        let split = deviatoric_part(&c).trace() + 3.0 * bulk_modulus_3d(&c);
        assert!((split - c.trace()).abs() < 1e-13 * c.trace());
        // C_dev annihilates the volumetric direction m.
        let m = SVector::<f64, 6>::new(1.0, 1.0, 1.0, 0.0, 0.0, 0.0);
        assert!((deviatoric_part(&c) * m).norm() < 1e-13);
    }

    #[test]
    fn bbar_is_the_default_up_to_lambda_four_mu_and_bounded_beyond() {
        for lambda in [0.0, 1.0, 4.0] {
            let c = isotropic(lambda, 1.0);
            let default = DofiDofi::DEFAULT_SCALE * c.trace();
            assert!(
                (BBar::polyhedral_alpha(&c) - default).abs() < 1e-14,
                "{lambda}"
            );
        }
        for lambda in [4.5, 1e3, 1e9] {
            let c = isotropic(lambda, 1.0);
            assert!(
                (BBar::polyhedral_alpha(&c) - 21.0 / 8.0).abs() < 1e-6,
                "{lambda}"
            );
        }
    }
}
