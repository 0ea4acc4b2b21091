//! Linear elastic materials: isotropic (plane strain or plane stress in 2D, the full law in
//! 3D) and general anisotropic (a 3 x 3 plane law, or a 6 x 6 law in space).

use nalgebra::{Matrix3, Matrix6, Vector3};
use vem_space::ElasticityTensor;

use crate::ElasticError;

/// Which two-dimensional reduction of a three-dimensional isotropic material is meant.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Plane {
    /// Plane strain: `eps_zz = 0`, `sigma_zz = lambda tr(eps)` (thick bodies; the paper's
    /// setting).
    Strain,
    /// Plane stress: `sigma_zz = 0`; the in-plane law uses `lambda* = 2 lambda mu / (lambda + 2 mu)`
    /// (thin plates).
    Stress,
}

/// A linear elastic material, validated when built (spec (2.8)).
///
/// In three dimensions ([`Material::elasticity_tensor`] with `D = 3`) an isotropic material is
/// the full law of its Lame parameters: [`Material::isotropic`] builds one without naming a
/// plane reduction (the reduction only matters for a planar body, where such a material is in
/// plane strain, the exact restriction of the 3D law to `eps_zz = 0`); a material built with
/// [`Plane::Stress`] describes a thin plate and is refused in 3D rather than silently taken as
/// the 3D law. [`Material::general_3d`] is an anisotropic law in space (6 x 6 Voigt matrix).
///
/// ```
/// use vem_elastic::{Material, Plane};
/// let steel = Material::from_young_poisson(210e9, 0.3, Plane::Strain)?;
/// let (lambda, mu) = steel.lame().unwrap();
/// assert!((mu - 210e9 / 2.6).abs() < 1e-3 * mu);
/// assert!((lambda - 210e9 * 0.3 / (1.3 * 0.4)).abs() < 1e-3 * lambda);
/// let c = steel.tensor()?;
/// assert_eq!(c.voigt()[(0, 1)], lambda);
/// # Ok::<(), vem_elastic::ElasticError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    kind: Kind,
}

// A material is a small value copied once per body: the 6 x 6 law inline (288 bytes) keeps it
// `Copy`, which a boxed variant would not.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, Copy, PartialEq)]
enum Kind {
    /// Three-dimensional Lame parameters and the plane reduction.
    Isotropic { lambda: f64, mu: f64, plane: Plane },
    /// A general symmetric positive definite Voigt tensor.
    General { voigt: Matrix3<f64> },
    /// A general symmetric positive definite Voigt tensor in space
    /// (`[xx, yy, zz, yz, xz, xy]`, engineering shears).
    General3 { voigt: Matrix6<f64> },
}

impl Material {
    /// An isotropic material from Young's modulus `e > 0` and Poisson's ratio
    /// `nu` in (-1, 1/2).
    pub fn from_young_poisson(e: f64, nu: f64, plane: Plane) -> Result<Self, ElasticError> {
        if !e.is_finite() || e <= 0.0 {
            return Err(invalid(format!(
                "Young's modulus E = {e} must be finite and positive"
            )));
        }
        if !nu.is_finite() || nu <= -1.0 || nu >= 0.5 {
            return Err(invalid(format!(
                "Poisson's ratio nu = {nu} is outside the open interval (-1, 0.5)"
            )));
        }
        let mu = e / (2.0 * (1.0 + nu));
        let lambda = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
        Self::from_lame(lambda, mu, plane)
    }

    /// An isotropic material of a body in space from Young's modulus `e > 0` and Poisson's
    /// ratio `nu` in (-1, 1/2): the full three-dimensional law, with no plane reduction to
    /// choose. Used by a planar body it is in plane strain (the exact restriction of the 3D law
    /// to `eps_zz = 0`), as [`Material::from_young_poisson`] with [`Plane::Strain`].
    ///
    /// ```
    /// use vem_elastic::Material;
    /// let steel = Material::isotropic(210e9, 0.3)?;
    /// let c = steel.elasticity_tensor::<3>()?;
    /// let (lambda, mu) = steel.lame().unwrap();
    /// assert!((c.voigt_matrix()[(2, 2)] - (lambda + 2.0 * mu)).abs() < 1e-3);
    /// assert!((c.voigt_matrix()[(3, 3)] - mu).abs() < 1e-3);
    /// # Ok::<(), vem_elastic::ElasticError>(())
    /// ```
    pub fn isotropic(e: f64, nu: f64) -> Result<Self, ElasticError> {
        Self::from_young_poisson(e, nu, Plane::Strain)
    }

    /// A general anisotropic material of a body in space from its 6 x 6 Voigt matrix
    /// (`sigma = C eps`, `eps = [eps_xx, eps_yy, eps_zz, 2 eps_yz, 2 eps_xz, 2 eps_xy]`): finite,
    /// symmetric, positive definite. Used by a planar body it is in plane strain: the in-plane
    /// law is the block of rows and columns `[xx, yy, xy]`, and `sigma_zz` follows from the
    /// row `zz`.
    pub fn general_3d(voigt: Matrix6<f64>) -> Result<Self, ElasticError> {
        let matrix = nalgebra::DMatrix::from_column_slice(6, 6, voigt.as_slice());
        ElasticityTensor::<3>::try_from_voigt_matrix(&matrix).map_err(space_invalid)?;
        Ok(Self {
            kind: Kind::General3 { voigt },
        })
    }

    /// An isotropic material from the three-dimensional Lame parameters: `mu > 0` and a
    /// positive bulk modulus `lambda + 2 mu / 3 > 0` (equivalently nu in (-1, 1/2)).
    pub fn from_lame(lambda: f64, mu: f64, plane: Plane) -> Result<Self, ElasticError> {
        if !lambda.is_finite() || !mu.is_finite() {
            return Err(invalid(format!(
                "non-finite Lame parameters lambda = {lambda}, mu = {mu}"
            )));
        }
        if mu <= 0.0 {
            return Err(invalid(format!("shear modulus mu = {mu} must be positive")));
        }
        if 3.0 * lambda + 2.0 * mu <= 0.0 {
            return Err(invalid(format!(
                "lambda = {lambda} with mu = {mu}: the bulk modulus lambda + 2 mu / 3 = {} must be positive",
                lambda + 2.0 * mu / 3.0
            )));
        }
        let (lambda_in_plane, _) = in_plane(lambda, mu, plane);
        let largest = lambda_in_plane + 2.0 * mu;
        if !(largest.is_finite() && lambda_in_plane.is_finite()) {
            return Err(invalid(format!(
                "lambda = {lambda} with mu = {mu}: the elasticity tensor's largest entry \
                 lambda + 2 mu overflows the floating-point range"
            )));
        }
        Ok(Self {
            kind: Kind::Isotropic { lambda, mu, plane },
        })
    }

    /// A general anisotropic material from its Voigt matrix (`sigma = C eps`,
    /// `eps = [eps_xx, eps_yy, 2 eps_xy]`): finite, symmetric, positive definite.
    ///
    /// Such a material is a purely two-dimensional law: it carries no out-of-plane stress
    /// (`sigma_zz = 0` in [`Material::out_of_plane_stress`]).
    pub fn general(voigt: Matrix3<f64>) -> Result<Self, ElasticError> {
        ElasticityTensor::try_from_voigt(voigt).map_err(space_invalid)?;
        Ok(Self {
            kind: Kind::General { voigt },
        })
    }

    /// The three-dimensional Lame parameters `(lambda, mu)` of an isotropic material
    /// (before any plane-stress reduction); `None` for a general tensor.
    pub fn lame(&self) -> Option<(f64, f64)> {
        match self.kind {
            Kind::Isotropic { lambda, mu, .. } => Some((lambda, mu)),
            Kind::General { .. } | Kind::General3 { .. } => None,
        }
    }

    /// The plane reduction of an isotropic material; `None` for a general tensor.
    pub fn plane(&self) -> Option<Plane> {
        match self.kind {
            Kind::Isotropic { plane, .. } => Some(plane),
            Kind::General { .. } | Kind::General3 { .. } => None,
        }
    }

    /// The in-plane Lame parameters that enter `C`: `(lambda, mu)` in plane strain,
    /// `(2 lambda mu / (lambda + 2 mu), mu)` in plane stress; `None` for a general tensor.
    pub fn in_plane_lame(&self) -> Option<(f64, f64)> {
        match self.kind {
            Kind::Isotropic { lambda, mu, plane } => Some(in_plane(lambda, mu, plane)),
            Kind::General { .. } | Kind::General3 { .. } => None,
        }
    }

    /// The elasticity tensor as the element sees it, checked for (2.8).
    pub fn tensor(&self) -> Result<ElasticityTensor, ElasticError> {
        let tensor = match self.kind {
            Kind::Isotropic { lambda, mu, plane } => {
                let (lambda, mu) = in_plane(lambda, mu, plane);
                ElasticityTensor::try_isotropic(lambda, mu)
            }
            Kind::General { voigt } => ElasticityTensor::try_from_voigt(voigt),
            Kind::General3 { voigt } => {
                ElasticityTensor::try_from_voigt(plane_strain_block(&voigt))
            }
        };
        tensor.map_err(space_invalid)
    }

    /// The elasticity tensor of a body in `D` dimensions: the in-plane tensor of
    /// [`Material::tensor`] in 2D; in 3D the isotropic tensor of the Lame parameters or the
    /// 6 x 6 tensor of [`Material::general_3d`]. Refused in 3D: a general 2D Voigt tensor (a
    /// plane law) and an isotropic material in plane stress (a thin-plate law).
    pub fn elasticity_tensor<const D: usize>(&self) -> Result<ElasticityTensor<D>, ElasticError> {
        let voigt = match (D, self.kind) {
            (2, _) => self.tensor()?.voigt_matrix(),
            (
                3,
                Kind::Isotropic {
                    plane: Plane::Stress,
                    ..
                },
            ) => {
                return Err(invalid(
                    "a plane-stress material describes a thin plate, not a body in 3 \
                     dimensions; build it with Material::isotropic (or Plane::Strain)"
                        .into(),
                ))
            }
            (3, Kind::Isotropic { lambda, mu, .. }) => {
                let mut c = nalgebra::DMatrix::zeros(6, 6);
                for i in 0..3 {
                    for j in 0..3 {
                        c[(i, j)] = lambda + if i == j { 2.0 * mu } else { 0.0 };
                    }
                    c[(i + 3, i + 3)] = mu;
                }
                c
            }
            (3, Kind::General3 { voigt }) => {
                nalgebra::DMatrix::from_column_slice(6, 6, voigt.as_slice())
            }
            _ => {
                return Err(invalid(format!(
                    "a general 2D Voigt tensor cannot describe a body in {D} dimensions"
                )))
            }
        };
        ElasticityTensor::<D>::try_from_voigt_matrix(&voigt).map_err(space_invalid)
    }

    /// The three-dimensional stress tensor of a body in `D` dimensions whose strain tensor is
    /// `strain`, with its elasticity tensor `tensor`: in 2D the in-plane stress completed by
    /// the out-of-plane stress ([`Material::out_of_plane_stress`]); in 3D `C eps`.
    pub fn stress_state<const D: usize>(
        &self,
        tensor: &ElasticityTensor<D>,
        strain: &nalgebra::SMatrix<f64, D, D>,
    ) -> Matrix3<f64> {
        let stress = tensor.stress_tensor(strain);
        let mut full = Matrix3::zeros();
        for i in 0..D.min(3) {
            for j in 0..D.min(3) {
                full[(i, j)] = stress[(i, j)];
            }
        }
        if D == 2 {
            let voigt = Vector3::new(strain[(0, 0)], strain[(1, 1)], 2.0 * strain[(0, 1)]);
            full[(2, 2)] = self.out_of_plane_stress(&voigt);
        }
        full
    }

    /// The three-dimensional strain tensor of a body in `D` dimensions whose strain tensor is
    /// `strain`: in 2D the in-plane strain completed by `eps_zz` (zero in plane strain and for
    /// a general tensor, `-lambda / (lambda + 2 mu) (eps_xx + eps_yy)` in plane stress).
    pub fn strain_state<const D: usize>(
        &self,
        strain: &nalgebra::SMatrix<f64, D, D>,
    ) -> Matrix3<f64> {
        let mut full = Matrix3::zeros();
        for i in 0..D.min(3) {
            for j in 0..D.min(3) {
                full[(i, j)] = strain[(i, j)];
            }
        }
        if let (
            2,
            Kind::Isotropic {
                lambda,
                mu,
                plane: Plane::Stress,
            },
        ) = (D, self.kind)
        {
            full[(2, 2)] = -lambda / (lambda + 2.0 * mu) * (full[(0, 0)] + full[(1, 1)]);
        }
        full
    }

    /// The out-of-plane stress `sigma_zz` for an in-plane strain `eps` (Voigt): `lambda tr(eps)`
    /// in plane strain, zero in plane stress and for a general tensor.
    pub fn out_of_plane_stress(&self, strain: &Vector3<f64>) -> f64 {
        match self.kind {
            Kind::Isotropic {
                lambda,
                plane: Plane::Strain,
                ..
            } => lambda * (strain[0] + strain[1]),
            // Plane strain of a 3D law: the zz row on [xx, yy, xy].
            Kind::General3 { voigt } => {
                voigt[(2, 0)] * strain[0] + voigt[(2, 1)] * strain[1] + voigt[(2, 5)] * strain[2]
            }
            _ => 0.0,
        }
    }
}

/// The plane-strain block `[xx, yy, xy]` of a 6 x 6 Voigt matrix.
fn plane_strain_block(voigt: &Matrix6<f64>) -> Matrix3<f64> {
    const IN_PLANE: [usize; 3] = [0, 1, 5];
    Matrix3::from_fn(|i, j| voigt[(IN_PLANE[i], IN_PLANE[j])])
}

/// The in-plane Lame pair of a three-dimensional isotropic material.
fn in_plane(lambda: f64, mu: f64, plane: Plane) -> (f64, f64) {
    match plane {
        Plane::Strain => (lambda, mu),
        Plane::Stress => (2.0 * lambda * mu / (lambda + 2.0 * mu), mu),
    }
}

fn invalid(reason: String) -> ElasticError {
    ElasticError::InvalidMaterial { reason }
}

/// The element layer's refusal of a tensor, as this layer's error (its reason once, not
/// "invalid material: invalid material: ...").
fn space_invalid(error: vem_space::SpaceError) -> ElasticError {
    match error {
        vem_space::SpaceError::InvalidMaterial { reason } => invalid(reason),
        other => invalid(other.to_string()),
    }
}

/// The von Mises equivalent stress `sqrt(3/2 s : s)` of a three-dimensional stress tensor
/// `stress` (`s` its deviatoric part).
pub fn von_mises(stress: &Matrix3<f64>) -> f64 {
    let deviatoric = stress - Matrix3::identity() * (stress.trace() / 3.0);
    (1.5 * deviatoric.component_mul(&deviatoric).sum()).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn young_poisson_to_lame() {
        // E = 8/3, nu = 1/3 gives lambda = 2, mu = 1 (the spec's reference pair).
        let m = Material::from_young_poisson(8.0 / 3.0, 1.0 / 3.0, Plane::Strain).unwrap();
        let (lambda, mu) = m.lame().unwrap();
        assert_relative_eq!(lambda, 2.0, max_relative = 1e-14);
        assert_relative_eq!(mu, 1.0, max_relative = 1e-14);
        let c = m.tensor().unwrap();
        assert_relative_eq!(c.voigt()[(0, 0)], 4.0, max_relative = 1e-14);
    }

    #[test]
    fn plane_stress_reduces_lambda() {
        let m = Material::from_lame(2.0, 1.0, Plane::Stress).unwrap();
        // lambda* = 2 * 2 * 1 / (2 + 2) = 1; C_11 = E / (1 - nu^2) = (8/3) / (8/9) = 3.
        let c = m.tensor().unwrap();
        assert_relative_eq!(c.voigt()[(0, 1)], 1.0, max_relative = 1e-14);
        assert_relative_eq!(c.voigt()[(0, 0)], 3.0, max_relative = 1e-14);
        assert_eq!(m.out_of_plane_stress(&Vector3::new(1.0, 1.0, 0.0)), 0.0);
    }

    #[test]
    fn overflowing_moduli_are_refused_once() {
        // E = 1.5e308: mu and lambda are finite, lambda + 2 mu (2.0e308) is not.
        let err = Material::from_young_poisson(1.5e308, 0.3, Plane::Strain).unwrap_err();
        let text = err.to_string();
        assert!(text.contains("overflows"), "{text}");
        assert_eq!(text.matches("invalid material").count(), 1, "{text}");
        // The largest finite pair below the limit is accepted: C_11 = lambda + 2 mu exactly.
        let m = Material::from_lame(1e307, 1e307, Plane::Strain).unwrap();
        assert_eq!(m.tensor().unwrap().voigt()[(0, 0)], 3e307);
    }

    #[test]
    fn invalid_parameters_name_the_value() {
        let cases = [
            (
                Material::from_young_poisson(1.0, 0.5, Plane::Strain),
                "nu = 0.5",
            ),
            (
                Material::from_young_poisson(1.0, -1.0, Plane::Strain),
                "nu = -1",
            ),
            (
                Material::from_young_poisson(-2.0, 0.3, Plane::Stress),
                "E = -2",
            ),
            (
                Material::from_young_poisson(f64::NAN, 0.3, Plane::Stress),
                "E = NaN",
            ),
            (Material::from_lame(1.0, 0.0, Plane::Strain), "mu = 0"),
            (
                Material::from_lame(f64::INFINITY, 1.0, Plane::Strain),
                "non-finite",
            ),
            (
                Material::from_lame(-1.0, 1.0, Plane::Strain),
                "bulk modulus",
            ),
            (
                Material::general(Matrix3::new(1.0, 2.0, 0.0, 2.0, 1.0, 0.0, 0.0, 0.0, 1.0)),
                "positive definite",
            ),
            (
                Material::general(Matrix3::new(1.0, 0.5, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0)),
                "symmetric",
            ),
        ];
        for (result, needle) in cases {
            let err = result.unwrap_err();
            assert!(matches!(err, ElasticError::InvalidMaterial { .. }));
            assert!(err.to_string().contains(needle), "{err} lacks {needle}");
        }
    }

    #[test]
    fn materials_in_space() {
        // The isotropic law without a plane: lambda, mu from E, nu; the 3D tensor.
        let m = Material::isotropic(8.0 / 3.0, 1.0 / 3.0).unwrap();
        let c = m.elasticity_tensor::<3>().unwrap();
        assert_relative_eq!(c.trace(), 3.0 * 2.0 + 9.0, max_relative = 1e-14);
        // In a planar body it is plane strain.
        let plane_strain = Material::from_young_poisson(8.0 / 3.0, 1.0 / 3.0, Plane::Strain);
        assert_eq!(m.tensor().unwrap(), plane_strain.unwrap().tensor().unwrap());
        // Plane stress is a thin-plate law: refused in space.
        let plate = Material::from_lame(2.0, 1.0, Plane::Stress).unwrap();
        let err = plate.elasticity_tensor::<3>().unwrap_err();
        assert!(err.to_string().contains("thin plate"), "{err}");
        // A general 3D law: the isotropic one entered by hand gives the same tensor, and its
        // plane-strain block and sigma_zz are those of plane strain.
        let voigt = Matrix6::from_fn(|i, j| c.voigt_matrix()[(i, j)]);
        let general = Material::general_3d(voigt).unwrap();
        assert_eq!(general.elasticity_tensor::<3>().unwrap(), c);
        assert_eq!(general.tensor().unwrap(), m.tensor().unwrap());
        let strain = Vector3::new(0.1, -0.2, 0.3);
        assert_relative_eq!(
            general.out_of_plane_stress(&strain),
            m.out_of_plane_stress(&strain),
            max_relative = 1e-14
        );
        let not_definite = Matrix6::from_fn(|i, j| {
            if i == j {
                if i == 4 {
                    -1.0
                } else {
                    1.0
                }
            } else {
                0.0
            }
        });
        let err = Material::general_3d(not_definite).unwrap_err();
        assert!(err.to_string().contains("positive definite"), "{err}");
    }

    #[test]
    fn von_mises_of_uniaxial_and_pure_shear() {
        let uniaxial = Matrix3::new(2.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        assert_relative_eq!(von_mises(&uniaxial), 2.0, max_relative = 1e-15);
        let shear = Matrix3::new(0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        assert_relative_eq!(von_mises(&shear), 3f64.sqrt(), max_relative = 1e-15);
        // A hydrostatic state has no deviatoric part.
        assert!(von_mises(&(Matrix3::identity() * -3.0)).abs() < 1e-15);
        // The plane formula sqrt(((sxx - syy)^2 + (syy - szz)^2 + (szz - sxx)^2) / 2 + 3 sxy^2).
        let (sxx, syy, szz, sxy): (f64, f64, f64, f64) = (1.5, -0.5, 0.3, 0.7);
        let state = Matrix3::new(sxx, sxy, 0.0, sxy, syy, 0.0, 0.0, 0.0, szz);
        let plane = (0.5 * ((sxx - syy).powi(2) + (syy - szz).powi(2) + (szz - sxx).powi(2))
            + 3.0 * sxy * sxy)
            .sqrt();
        assert_relative_eq!(von_mises(&state), plane, max_relative = 1e-14);
    }
}
