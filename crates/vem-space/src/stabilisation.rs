//! The stabilisation `S_T` of the lowest-order virtual element, an open extension point.
//!
//! [`crate::LowestOrderVem`] computes `K_s = (I - Pi_dof)^T S (I - Pi_dof)` with a diagonal
//! `S` that a [`Stabilisation`] supplies; `K_s` vanishes on linear fields whatever `S` is, so
//! consistency (3.1) holds for every stabilisation, and a positive `S` gives the rank `2n - 3`.
//! Three are built in: [`DofiDofi`] (`S = alpha I`), [`DRecipe`] (`S = diag(K_c)`) and
//! [`BBar`] (`S = alpha I` with a bulk part bounded independently of lambda: locking-free on
//! nearly incompressible materials). A user's
//! own implements the trait outside this crate and is passed to
//! [`crate::LowestOrderVem::try_new`] (see `docs/elements.md`).

use std::fmt;

use nalgebra::{DMatrix, DVector};

use crate::{ElasticityTensor, PolygonGeometry, SpaceError};

/// The diagonal `S` of the stabilisation `S_T((I - Pi) u, (I - Pi) v) = (I - Pi_dof)^T S
/// (I - Pi_dof)` of [`crate::LowestOrderVem`].
///
/// Dimensions: in 2D `a_T(phi_i, phi_i) ~ C |T| / h^2 ~ C`, so `S` is a material constant times a
/// dimensionless matrix and needs no mesh-size factor. Implementations must be thread-safe
/// (assembly calls them from many threads at once).
///
/// ```
/// use std::sync::Arc;
/// use nalgebra::{DMatrix, DVector};
/// use vem_space::{
///     ElasticityTensor, ElementSpace, LowestOrderVem, Point, PolygonGeometry, SpaceError,
///     Stabilisation,
/// };
///
/// /// `S = mu I`: the dofi-dofi stabilisation scaled by the shear entry alone.
/// #[derive(Debug)]
/// struct ShearOnly;
///
/// impl Stabilisation for ShearOnly {
///     fn name(&self) -> String {
///         "shear-only".into()
///     }
///     fn diagonal(
///         &self,
///         _geometry: &PolygonGeometry,
///         material: &ElasticityTensor,
///         consistency: &DMatrix<f64>,
///     ) -> Result<DVector<f64>, SpaceError> {
///         Ok(DVector::from_element(consistency.nrows(), material.shear_modulus()))
///     }
/// }
///
/// let element = LowestOrderVem::try_new(Arc::new(ShearOnly))?;
/// assert_eq!(element.name(), "vem1-shear-only");
/// let square = [
///     Point::new(0.0, 0.0), Point::new(1.0, 0.0), Point::new(1.0, 1.0), Point::new(0.0, 1.0),
/// ];
/// let local = element.stiffness(&square, &ElasticityTensor::try_isotropic(2.0, 1.0)?)?;
/// // On a square Pi_dof is an orthogonal projector of rank 6 (of 8): K_s = mu (I - Pi_dof)
/// // has the eigenvalue mu = 1 twice.
/// let eigenvalues = local.stabilisation.symmetric_eigenvalues();
/// assert!((eigenvalues.iter().sum::<f64>() - 2.0).abs() < 1e-13);
/// # Ok::<(), SpaceError>(())
/// ```
pub trait Stabilisation: Send + Sync + fmt::Debug {
    /// A short name, used in the element's name (`"vem1-<name>"`) and in reports.
    fn name(&self) -> String;

    /// A one-line description with the values of its parameters, for reports (default: the
    /// name).
    fn description(&self) -> String {
        self.name()
    }

    /// Checks the settings; [`crate::LowestOrderVem::try_new`] calls it once (default: nothing
    /// to check).
    fn validate(&self) -> Result<(), SpaceError> {
        Ok(())
    }

    /// The diagonal of `S` (length `2n`, finite and positive) for the polygon `geometry`, the
    /// material `material` and the polygon's consistency matrix `consistency` (`K_c`, 2n x 2n).
    fn diagonal(
        &self,
        geometry: &PolygonGeometry,
        material: &ElasticityTensor,
        consistency: &DMatrix<f64>,
    ) -> Result<DVector<f64>, SpaceError>;
}

/// Which material constant scales the "dofi-dofi" stabilisation `S = alpha I`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum StabilisationScaling {
    /// `alpha = scale * trace(C)` (Voigt trace, `2 lambda + 5 mu` for an isotropic material).
    /// Contains lambda: stiffens the non-polynomial modes like lambda (spec section 9).
    #[default]
    TraceOfC,
    /// `alpha = scale * 5 C_33` (`5 mu`): the value `trace(C)` takes for an isotropic material
    /// with lambda = 0, so the two scalings agree there and differ only through lambda.
    ShearModulus,
}

impl StabilisationScaling {
    /// The material constant: `trace(C)` or `5 C_33`.
    pub fn constant(&self, material: &ElasticityTensor) -> f64 {
        match self {
            Self::TraceOfC => material.trace(),
            Self::ShearModulus => 5.0 * material.shear_modulus(),
        }
    }

    /// A short name: `"trace"` or `"shear"`.
    pub fn name(&self) -> &'static str {
        match self {
            Self::TraceOfC => "trace",
            Self::ShearModulus => "shear",
        }
    }
}

/// The "dofi-dofi" stabilisation `S = alpha I` (Euclidean product of the DOF vectors),
/// `alpha = scale * constant` with the constant from [`StabilisationScaling`].
///
/// With [`DofiDofi::DEFAULT_SCALE`] = 1/8 and [`StabilisationScaling::TraceOfC`] (the
/// [`Default`]), `alpha = trace(C)/8` is close to the mean diagonal entry of `K_c` on a square,
/// `(C_11 + C_22 + 2 C_33)/8`.
///
/// ```
/// use vem_space::{DofiDofi, Stabilisation, StabilisationScaling};
/// assert_eq!(DofiDofi::default().name(), "trace");
/// assert_eq!(DofiDofi::new(StabilisationScaling::ShearModulus).name(), "shear");
/// assert_eq!(DofiDofi::try_new(StabilisationScaling::TraceOfC, 2.0)?.name(), "trace-x2");
/// assert!(DofiDofi::try_new(StabilisationScaling::TraceOfC, -1.0).is_err());
/// # Ok::<(), vem_space::SpaceError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DofiDofi {
    scaling: StabilisationScaling,
    scale: f64,
}

impl DofiDofi {
    /// The default `scale`, 1/8.
    pub const DEFAULT_SCALE: f64 = 0.125;

    /// `scaling` with the default scale 1/8.
    pub fn new(scaling: StabilisationScaling) -> Self {
        Self {
            scaling,
            scale: Self::DEFAULT_SCALE,
        }
    }

    /// `scaling` with the dimensionless factor `scale`, which must be finite and positive.
    pub fn try_new(scaling: StabilisationScaling, scale: f64) -> Result<Self, SpaceError> {
        let stabilisation = Self { scaling, scale };
        stabilisation.validate()?;
        Ok(stabilisation)
    }

    /// The material constant.
    pub fn scaling(&self) -> StabilisationScaling {
        self.scaling
    }

    /// The dimensionless factor.
    pub fn scale(&self) -> f64 {
        self.scale
    }
}

impl Default for DofiDofi {
    /// `TraceOfC` with scale 1/8.
    fn default() -> Self {
        Self::new(StabilisationScaling::TraceOfC)
    }
}

impl Stabilisation for DofiDofi {
    /// The scaling's name (`"trace"`, `"shear"`), followed by `-x<scale>` when the scale is not
    /// the default.
    fn name(&self) -> String {
        if self.scale == Self::DEFAULT_SCALE {
            self.scaling.name().to_string()
        } else {
            format!("{}-x{}", self.scaling.name(), self.scale)
        }
    }

    fn description(&self) -> String {
        let constant = match self.scaling {
            StabilisationScaling::TraceOfC => "trace(C)",
            StabilisationScaling::ShearModulus => "5 mu",
        };
        format!("dofi-dofi, alpha = {} {constant}", self.scale)
    }

    fn validate(&self) -> Result<(), SpaceError> {
        if self.scale.is_finite() && self.scale > 0.0 {
            Ok(())
        } else {
            Err(SpaceError::InvalidStabilisation {
                stabilisation: "dofi-dofi".into(),
                reason: format!(
                    "the dofi-dofi scale must be finite and positive, got {}",
                    self.scale
                ),
            })
        }
    }

    fn diagonal(
        &self,
        _geometry: &PolygonGeometry,
        material: &ElasticityTensor,
        consistency: &DMatrix<f64>,
    ) -> Result<DVector<f64>, SpaceError> {
        Ok(DVector::from_element(
            consistency.nrows(),
            self.scale * self.scaling.constant(material),
        ))
    }
}

/// The "D-recipe" of Beirão da Veiga, Dassi and Russo (2017): `S` diagonal with
/// `S_ii = max(K_c,ii, floor)`, `floor = DRecipe::FLOOR * trace(C)`. Adapts to the element
/// shape and to the number of vertices; no parameter.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct DRecipe;

impl DRecipe {
    /// The floor of the diagonal, relative to `trace(C)` (only guards against a vanishing
    /// diagonal entry; `K_c,ii > 0` on every valid polygon).
    pub const FLOOR: f64 = 1e-6;
}

impl Stabilisation for DRecipe {
    /// `"drecipe"`.
    fn name(&self) -> String {
        "drecipe".into()
    }

    fn description(&self) -> String {
        "D-recipe".into()
    }

    fn diagonal(
        &self,
        _geometry: &PolygonGeometry,
        material: &ElasticityTensor,
        consistency: &DMatrix<f64>,
    ) -> Result<DVector<f64>, SpaceError> {
        let floor = Self::FLOOR * material.trace();
        Ok(consistency.diagonal().map(|k| k.max(floor)))
    }
}

/// The locking-free stabilisation "bbar": `S = alpha I` with
/// `alpha = min(trace(C), 3 trace(C_dev)) / 8 = (trace(C_dev) + 2 min(kappa, trace(C_dev))) / 8`
/// ([`ElasticityTensor::deviatoric`], [`ElasticityTensor::bulk_modulus`]).
///
/// The consistency part of the lowest-order VEM already sees the volume change only through the
/// cell mean of the divergence (the B-bar idea: the volumetric strain projected on constants,
/// one constraint per cell). What makes the default `alpha = trace(C)/8` lock is its bulk part
/// `2 kappa / 8`: it penalises the non-polynomial modes, whose divergence is not zero pointwise,
/// like lambda. "bbar" keeps the bulk part while it is at most the deviatoric one and bounds it
/// there beyond, so that `3 trace(C_dev)/8 >= alpha >= trace(C_dev)/8` whatever lambda is
/// (isotropic: `9 mu/8 >= alpha >= 3 mu/8`): the stabilisation stays spectrally equivalent to
/// the deviatoric energy, with constants independent of lambda.
///
/// For `kappa <= trace(C_dev)` (isotropic: `lambda <= 2 mu`, Poisson's ratio `<= 1/3`) it is
/// exactly the default [`DofiDofi`], so results there are unchanged; beyond, the element
/// differs from the default only in the stabilisation constant.
///
/// The price: where `lambda` is large and the load drives an O(1) volume change (stress and
/// pressure `lambda div u` growing like `lambda`), the pressure is represented by one constant
/// per cell and the errors grow like `lambda h`; the default, whose stabilisation is scaled
/// by `lambda`, is the more accurate element there (`docs/elements.md`, "The trade-off").
///
/// ```
/// use nalgebra::DMatrix;
/// use vem_space::{BBar, ElasticityTensor, Point, PolygonGeometry, Stabilisation};
/// let square = [
///     Point::new(0.0, 0.0), Point::new(1.0, 0.0), Point::new(1.0, 1.0), Point::new(0.0, 1.0),
/// ];
/// let geometry = PolygonGeometry::try_new(&square)?;
/// let k_c = DMatrix::zeros(8, 8); // not used by "bbar"
/// // lambda = 1.5, mu = 1 (nu = 0.3): alpha = trace(C)/8 = 1, as the default stabilisation.
/// let moderate = ElasticityTensor::try_isotropic(1.5, 1.0)?;
/// assert_eq!(BBar.diagonal(&geometry, &moderate, &k_c)?[0], 1.0);
/// // lambda = 1e6 mu: alpha = 9 mu / 8, not (2 lambda + 5 mu) / 8.
/// let nearly_incompressible = ElasticityTensor::try_isotropic(1e6, 1.0)?;
/// assert!((BBar.diagonal(&geometry, &nearly_incompressible, &k_c)?[0] - 1.125).abs() < 1e-9);
/// # Ok::<(), vem_space::SpaceError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct BBar;

impl BBar {
    /// The scale of `alpha`, as [`DofiDofi::DEFAULT_SCALE`].
    pub const SCALE: f64 = DofiDofi::DEFAULT_SCALE;

    /// `alpha` for the material `material`.
    pub fn alpha(material: &ElasticityTensor) -> f64 {
        Self::SCALE * material.trace().min(3.0 * material.deviatoric().trace())
    }
}

impl Stabilisation for BBar {
    /// `"bbar"`.
    fn name(&self) -> String {
        "bbar".into()
    }

    fn description(&self) -> String {
        "dofi-dofi, alpha = min(trace(C), 3 trace(C_dev))/8 (bulk part bounded)".into()
    }

    fn diagonal(
        &self,
        _geometry: &PolygonGeometry,
        material: &ElasticityTensor,
        consistency: &DMatrix<f64>,
    ) -> Result<DVector<f64>, SpaceError> {
        Ok(DVector::from_element(
            consistency.nrows(),
            Self::alpha(material),
        ))
    }
}

/// `s` as the diagonal of the stabilisation `stabilisation` (its name, asked for only in the
/// error) for `dofs` degrees of freedom: `dofs` finite positive entries, or the error naming
/// what came instead.
pub(crate) fn checked_diagonal(
    stabilisation: impl FnOnce() -> String,
    s: DVector<f64>,
    dofs: usize,
) -> Result<DVector<f64>, SpaceError> {
    if s.len() != dofs || s.iter().any(|s_i| !(s_i.is_finite() && *s_i > 0.0)) {
        return Err(SpaceError::InvalidStabilisation {
            stabilisation: stabilisation(),
            reason: format!(
                "the diagonal of S must have {dofs} finite positive entries, got {}: {:?}",
                s.len(),
                s.as_slice()
            ),
        });
    }
    Ok(s)
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use super::*;
    use crate::{ElementSpace, LowestOrderVem, Point};

    fn hexagon() -> Vec<Point> {
        (0..6)
            .map(|k| {
                let t = std::f64::consts::PI * k as f64 / 3.0;
                Point::new(t.cos(), 0.5 * t.sin())
            })
            .collect()
    }

    #[test]
    fn bbar_is_the_default_up_to_lambda_two_mu_and_bounded_beyond() {
        let vem1 = LowestOrderVem::default();
        let bbar = LowestOrderVem::try_new(Arc::new(BBar)).unwrap();
        assert_eq!(bbar.name(), "vem1-bbar");
        let polygon = hexagon();
        // lambda <= 2 mu: the same matrix, entry by entry.
        for lambda in [0.0, 1.5, 2.0] {
            let c = ElasticityTensor::try_isotropic(lambda, 1.0).unwrap();
            let (a, b) = (
                vem1.stiffness(&polygon, &c).unwrap(),
                bbar.stiffness(&polygon, &c).unwrap(),
            );
            assert_eq!(a, b, "lambda = {lambda}");
        }
        // lambda > 2 mu: the same consistency part; the stabilisation is the one of
        // alpha = 9 mu/8 = trace(C)/8 at lambda = 2 mu, whatever lambda is.
        let reference = vem1
            .stiffness(
                &polygon,
                &ElasticityTensor::try_isotropic(2.0, 1.0).unwrap(),
            )
            .unwrap();
        for lambda in [10.0, 1e6] {
            let c = ElasticityTensor::try_isotropic(lambda, 1.0).unwrap();
            let (a, b) = (
                vem1.stiffness(&polygon, &c).unwrap(),
                bbar.stiffness(&polygon, &c).unwrap(),
            );
            assert_eq!(a.consistency, b.consistency);
            let difference = (&b.stabilisation - &reference.stabilisation).amax();
            assert!(difference < 1e-14, "lambda = {lambda}: {difference}");
            // The default's stabilisation grows like lambda.
            let ratio = a.stabilisation.amax() / b.stabilisation.amax();
            assert!((ratio - (2.0 * lambda + 5.0) / 9.0).abs() < 1e-9 * ratio);
        }
    }
}
