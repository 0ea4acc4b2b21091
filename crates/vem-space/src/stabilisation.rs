//! The stabilisation `S_T` of the lowest-order virtual element, an open extension point.
//!
//! [`crate::LowestOrderVem`] computes `K_s = (I - Pi_dof)^T S (I - Pi_dof)` with a diagonal
//! `S` that a [`Stabilisation`] supplies; `K_s` vanishes on linear fields whatever `S` is, so
//! consistency (3.1) holds for every stabilisation, and a positive `S` gives the rank `2n - 3`.
//! Two are built in: [`DofiDofi`] (`S = alpha I`) and [`DRecipe`] (`S = diag(K_c)`). A user's
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
