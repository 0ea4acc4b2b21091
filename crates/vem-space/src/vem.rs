//! The lowest-order (k = 1) virtual element for linear elasticity (spec section 2).
//!
//! On a polygon `T` with vertices `x_0 .. x_{n-1}` (counter-clockwise), `x_bar` their mean and
//! `|T|` the area:
//!
//! - **Energy projection.** Since `v` is linear on every edge, the mean gradient is exact from
//!   the vertex values: `G = (1/|T|) int_{dT} v (x) nu ds = sum_k v_k (x) w_k` with
//!   `w_k = (|e_{k-1}| nu_{k-1} + |e_k| nu_k) / (2 |T|)` (`e_{k-1}`, `e_k` the two edges at `x_k`).
//!   Then `Pi v (x) = v_bar + G (x - x_bar)` with `v_bar` the mean of the vertex values: the
//!   symmetric part of `G` is the mean strain, so `a_T(Pi v, p) = a_T(v, p)` for every
//!   `p in P1^2` (consistency (3.1)); the vertex-mean condition and the skew part of `G` fix the
//!   rigid motions, so `Pi p = p` for `p in P1^2`. The expansion point is `x_bar`
//!   ([`crate::EnergyProjection::reference`]).
//! - **Consistency part** `K_c = |T| B^T C B`, `B` (3 x 2n) the Voigt strain of `Pi`.
//! - **Stabilisation part** `K_s = (I - Pi_dof)^T S (I - Pi_dof)`, `Pi_dof = D Pi` with `D`
//!   (2n x 6) the P1 basis `(1,0), (0,1), (x - x_bar) e_x, (y - y_bar) e_x, (x - x_bar) e_y,
//!   (y - y_bar) e_y` evaluated at the vertices; `S` from [`Stabilisation`]. `K_s` vanishes on
//!   P1 fields, so (3.1) holds for `K_c + K_s`.
//! - **Load** (A3) `l_T^h(v) = |T| f_bar . (Pi v)(x_c)`, `f_bar` the cell mean of `f` by the
//!   degree-5 rule on the centroid fan ([`crate::quadrature::polygon_rule`]), `x_c` the centroid:
//!   `int_T f_bar . Pi v`, exact for linear `v`. Vertex k receives `|T| f_bar (1/n + w_k . (x_c -
//!   x_bar))`, which is `|T| f_bar / n` when the centroid is the vertex mean (triangles, regular
//!   polygons). The plain vertex mean `v_bar` in place of `(Pi v)(x_c)` is also O(h) in (A3) but
//!   loses the O(h^2) L2 rate on systematically skewed cells (measured: E1 on chevrons).

use std::sync::Arc;

use nalgebra::{DMatrix, DVector};

use crate::quadrature::{polygon_rule, TriangleRule};
use crate::{
    DofiDofi, ElasticityTensor, ElementSpace, EnergyProjection, LocalStiffness, Point,
    PolygonGeometry, SpaceError, Stabilisation, Vector,
};

/// The lowest-order virtual element for linear elasticity ("vem1"): vertex DOFs, energy
/// projection from boundary integrals, a choice of stabilisation (see the module docs).
///
/// ```
/// use vem_space::{ElasticityTensor, ElementSpace, LowestOrderVem, Point};
/// let element = LowestOrderVem::default();
/// let hexagon: Vec<Point> = (0..6)
///     .map(|k| {
///         let t = std::f64::consts::PI * k as f64 / 3.0;
///         Point::new(t.cos(), t.sin())
///     })
///     .collect();
/// let k = element.stiffness(&hexagon, &ElasticityTensor::try_isotropic(2.0, 1.0)?)?.total();
/// // A translation in x is a rigid motion: no force.
/// let translation = nalgebra::DVector::from_fn(12, |i, _| if i % 2 == 0 { 1.0 } else { 0.0 });
/// assert!((&k * translation).norm() < 1e-13 * k.norm());
/// # Ok::<(), vem_space::SpaceError>(())
/// ```
#[derive(Debug, Clone)]
pub struct LowestOrderVem {
    stabilisation: Arc<dyn Stabilisation>,
    name: String,
}

impl Default for LowestOrderVem {
    /// "vem1": dofi-dofi scaled by `trace(C)`, scale 1/8 ([`DofiDofi::default`]).
    fn default() -> Self {
        Self::from_valid(Arc::new(DofiDofi::default()))
    }
}

impl LowestOrderVem {
    /// The element with the stabilisation `stabilisation`, whose settings are checked
    /// ([`Stabilisation::validate`]). Its name is `"vem1"` for the default dofi-dofi
    /// stabilisation (name `"trace"`) and `"vem1-<stabilisation name>"` otherwise
    /// (`"vem1-shear"`, `"vem1-drecipe"`, ...).
    pub fn try_new(stabilisation: Arc<dyn Stabilisation>) -> Result<Self, SpaceError> {
        stabilisation.validate()?;
        Ok(Self::from_valid(stabilisation))
    }

    pub(crate) fn from_valid(stabilisation: Arc<dyn Stabilisation>) -> Self {
        let suffix = stabilisation.name();
        let name = if suffix == DofiDofi::default().name() {
            "vem1".to_string()
        } else {
            format!("vem1-{suffix}")
        };
        Self {
            stabilisation,
            name,
        }
    }

    /// The stabilisation `S_T`.
    pub fn stabilisation(&self) -> &dyn Stabilisation {
        &*self.stabilisation
    }

    /// The shared stabilisation `S_T`.
    pub fn stabilisation_arc(&self) -> &Arc<dyn Stabilisation> {
        &self.stabilisation
    }

    /// The 6 x 2n coefficient matrix of `Pi` (see [`EnergyProjection::coefficients`]).
    fn coefficients(geometry: &PolygonGeometry) -> DMatrix<f64> {
        let n = geometry.n_vertices();
        let mut c = DMatrix::zeros(6, 2 * n);
        let mean = 1.0 / n as f64;
        for (k, w) in geometry.gradient_weights().iter().enumerate() {
            let (x, y) = (2 * k, 2 * k + 1);
            c[(0, x)] = mean;
            c[(1, y)] = mean;
            c[(2, x)] = w.x;
            c[(3, x)] = w.y;
            c[(4, y)] = w.x;
            c[(5, y)] = w.y;
        }
        c
    }

    /// The 3 x 2n Voigt strain `[xx, yy, 2 xy]` of `Pi`.
    fn strain_matrix(geometry: &PolygonGeometry) -> DMatrix<f64> {
        let n = geometry.n_vertices();
        let mut b = DMatrix::zeros(3, 2 * n);
        for (k, w) in geometry.gradient_weights().iter().enumerate() {
            let (x, y) = (2 * k, 2 * k + 1);
            b[(0, x)] = w.x;
            b[(2, x)] = w.y;
            b[(1, y)] = w.y;
            b[(2, y)] = w.x;
        }
        b
    }

    /// `D`: the P1 basis of [`EnergyProjection::coefficients`] at the vertices (2n x 6).
    fn basis_at_vertices(geometry: &PolygonGeometry) -> DMatrix<f64> {
        let n = geometry.n_vertices();
        let mut d = DMatrix::zeros(2 * n, 6);
        for (k, x) in geometry.relative_vertices().iter().enumerate() {
            let (rx, ry) = (2 * k, 2 * k + 1);
            d[(rx, 0)] = 1.0;
            d[(rx, 2)] = x.x;
            d[(rx, 3)] = x.y;
            d[(ry, 1)] = 1.0;
            d[(ry, 4)] = x.x;
            d[(ry, 5)] = x.y;
        }
        d
    }
}

/// `(m + m^T) / 2`: removes the round-off asymmetry of a product `A^T S A`.
fn symmetrised(m: DMatrix<f64>) -> DMatrix<f64> {
    (&m + m.transpose()) * 0.5
}

impl ElementSpace for LowestOrderVem {
    fn name(&self) -> &str {
        &self.name
    }

    /// Every polygon with at least three vertices.
    fn supports(&self, n_vertices: usize) -> bool {
        n_vertices >= 3
    }

    fn stiffness(
        &self,
        polygon: &[Point],
        material: &ElasticityTensor,
    ) -> Result<LocalStiffness, SpaceError> {
        let geometry = PolygonGeometry::try_new(polygon)?;
        // Consistency part: a_T(Pi u, Pi v) = |T| eps(Pi u) . C eps(Pi v).
        let b = Self::strain_matrix(&geometry);
        let c = DMatrix::from_column_slice(3, 3, material.voigt().as_slice());
        let consistency = symmetrised(b.transpose() * (c * &b) * geometry.area());
        // Stabilisation part on (I - Pi_dof), Pi_dof = D Pi.
        let dofs = 2 * geometry.n_vertices();
        let projector = Self::basis_at_vertices(&geometry) * Self::coefficients(&geometry);
        let complement = DMatrix::identity(dofs, dofs) - projector;
        let s = self
            .stabilisation
            .diagonal(&geometry, material, &consistency)?;
        if s.len() != dofs || s.iter().any(|s_i| !(s_i.is_finite() && *s_i > 0.0)) {
            return Err(SpaceError::InvalidStabilisation {
                stabilisation: self.stabilisation.name(),
                reason: format!(
                    "the diagonal of S must have {dofs} finite positive entries, got {}: {:?}",
                    s.len(),
                    s.as_slice()
                ),
            });
        }
        let mut scaled = complement.clone();
        for (mut row, s_i) in scaled.row_iter_mut().zip(s.iter()) {
            row *= *s_i;
        }
        let stabilisation = symmetrised(complement.transpose() * scaled);
        Ok(LocalStiffness {
            consistency,
            stabilisation,
        })
    }

    fn projection(&self, polygon: &[Point]) -> Result<EnergyProjection, SpaceError> {
        let geometry = PolygonGeometry::try_new(polygon)?;
        Ok(EnergyProjection {
            reference: geometry.vertex_mean(),
            coefficients: Self::coefficients(&geometry),
        })
    }

    fn body_load(
        &self,
        polygon: &[Point],
        body_force: &(dyn Fn(Point) -> Vector + Sync),
    ) -> Result<DVector<f64>, SpaceError> {
        let geometry = PolygonGeometry::try_new(polygon)?;
        // |T| f_bar = int_T f, by the degree-5 rule on the centroid fan (A3).
        let mut integral = Vector::zeros();
        for q in polygon_rule(polygon, &TriangleRule::degree5()) {
            let f = body_force(q.point);
            if !(f.x.is_finite() && f.y.is_finite()) {
                return Err(SpaceError::NonFiniteLoad {
                    x: q.point.x,
                    y: q.point.y,
                });
            }
            integral += f * q.weight;
        }
        // l_T^h(v) = int_T f_bar . Pi v = (int_T f) . (Pi v)(x_c), exact for linear v, with
        // (Pi v)(x_c) = v_mean + G (x_c - reference) = sum_k v_k (1/n + w_k . (x_c - reference)).
        // The vertex mean alone would be off by G (x_c - reference) = O(h) |v|_1 on cells whose
        // centroid and vertex mean differ, an O(h) load error that does not cancel on
        // systematically skewed cells (chevrons) and costs the O(h^2) L2 rate.
        let n = geometry.n_vertices();
        let offset = geometry.centroid() - geometry.vertex_mean();
        let weights: Vec<f64> = geometry
            .gradient_weights()
            .iter()
            .map(|w| 1.0 / n as f64 + w.dot(&offset))
            .collect();
        Ok(DVector::from_fn(2 * n, |i, _| {
            integral[i % 2] * weights[i / 2]
        }))
    }
}
