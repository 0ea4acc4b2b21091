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

use nalgebra::{DMatrix, DVector, SMatrix};

use crate::quadrature::{polygon_points, TriangleRule};
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

    /// What the stiffness needs: the consistency part, the diagonal `s` of the stabilisation
    /// and `R = I - Q` (row-major n x n; see [`ElementSpace::stiffness`]).
    fn parts(
        &self,
        geometry: &PolygonGeometry,
        material: &ElasticityTensor,
    ) -> Result<StiffnessParts, SpaceError> {
        let n = geometry.n_vertices();
        let (consistency, s) = self.consistency_and_diagonal(geometry, material)?;
        // Stabilisation part on (I - Pi_dof), Pi_dof = D Pi. Both components of a vertex
        // value are projected alike: Pi_dof = I_2 (x) Q with Q[k][m] = 1/n + r_k . w_m (r_k the
        // vertex relative to the vertex mean, w_m the gradient weights; `basis_at_vertices`
        // times `coefficients`), so K_s = (I - Pi_dof)' S (I - Pi_dof) couples only equal
        // components: K_s[2a + c][2b + c] = sum_k R[k][a] s_(2k + c) R[k][b], R = I - Q.
        let weights = geometry.gradient_weights();
        let relative = geometry.relative_vertices();
        let mean = 1.0 / n as f64;
        // R = I - Q, row-major n x n.
        let mut r = vec![0.0; n * n];
        for (k, x) in relative.iter().enumerate() {
            for (m, w) in weights.iter().enumerate() {
                let identity = if k == m { 1.0 } else { 0.0 };
                r[k * n + m] = identity - (mean + x.x * w.x + x.y * w.y);
            }
        }
        Ok(StiffnessParts {
            consistency,
            diagonal: s,
            complement: r,
        })
    }

    /// The consistency part `K_c` of the stiffness and the diagonal `s` of the stabilisation.
    fn consistency_and_diagonal(
        &self,
        geometry: &PolygonGeometry,
        material: &ElasticityTensor,
    ) -> Result<(DMatrix<f64>, DVector<f64>), SpaceError> {
        let n = geometry.n_vertices();
        let dofs = 2 * n;
        // Consistency part: a_T(Pi u, Pi v) = |T| eps(Pi u) . C eps(Pi v), entry by entry from
        // the columns of the Voigt strain matrix B (3 x 2n: [w_x, 0, w_y] for the x value of
        // a vertex, [0, w_y, w_x] for its y value; see `strain_matrix`), the lower triangle
        // computed and mirrored, so that K_c is exactly symmetric. The matrices are small
        // (2n <= 30 or so): plain loops, no general matrix product and its workspace.
        let c = material.voigt();
        let weights = geometry.gradient_weights();
        let column = |j: usize| {
            let w = weights[j / 2];
            if j % 2 == 0 {
                [w.x, 0.0, w.y]
            } else {
                [0.0, w.y, w.x]
            }
        };
        let area = geometry.area();
        let mut consistency = DMatrix::zeros(dofs, dofs);
        for j in 0..dofs {
            let b = column(j);
            let cb = [
                c[(0, 0)] * b[0] + c[(0, 1)] * b[1] + c[(0, 2)] * b[2],
                c[(1, 0)] * b[0] + c[(1, 1)] * b[1] + c[(1, 2)] * b[2],
                c[(2, 0)] * b[0] + c[(2, 1)] * b[1] + c[(2, 2)] * b[2],
            ];
            for i in j..dofs {
                let a = column(i);
                let value = area * (a[0] * cb[0] + a[1] * cb[1] + a[2] * cb[2]);
                consistency[(i, j)] = value;
                consistency[(j, i)] = value;
            }
        }
        let s = crate::stabilisation::checked_diagonal(
            || self.stabilisation.name(),
            self.stabilisation
                .diagonal(geometry, material, &consistency)?,
            dofs,
        )?;
        Ok((consistency, s))
    }

    /// The energy projection of a polygon of geometry `geometry`.
    fn projection_of(geometry: &PolygonGeometry) -> EnergyProjection {
        EnergyProjection {
            reference: geometry.vertex_mean(),
            coefficients: Self::coefficients(geometry),
        }
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

    /// The 3 x 2n Voigt strain `[xx, yy, 2 xy]` of `Pi` (the stiffness computes with its
    /// columns directly; the tests compare with the matrix products).
    #[cfg(test)]
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
    #[cfg(test)]
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

/// The consistency part of a polygon's stiffness, the diagonal `s` of its stabilisation and
/// `R = I - Q` (see [`LowestOrderVem::parts`]).
struct StiffnessParts {
    consistency: DMatrix<f64>,
    diagonal: DVector<f64>,
    complement: Vec<f64>,
}

/// `(m + m^T) / 2`: removes the round-off asymmetry of a product `A^T S A`.
#[cfg(test)]
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
        let parts = self.parts(&geometry, material)?;
        let n = geometry.n_vertices();
        let (r, s) = (&parts.complement, &parts.diagonal);
        let mut stabilisation = DMatrix::zeros(2 * n, 2 * n);
        for component in 0..2 {
            for b in 0..n {
                for a in b..n {
                    let value: f64 = (0..n)
                        .map(|k| r[k * n + a] * s[2 * k + component] * r[k * n + b])
                        .sum();
                    let (i, j) = (2 * a + component, 2 * b + component);
                    stabilisation[(i, j)] = value;
                    stabilisation[(j, i)] = value;
                }
            }
        }
        Ok(LocalStiffness {
            consistency: parts.consistency,
            stabilisation,
        })
    }

    /// The energy `u' K_s u = sum_k s_k ((I - Pi_dof) u)_k^2` with the diagonal `s`, without
    /// forming `K_s` or `R = I - Q`: `Pi u` is the linear function of vertex mean `u_bar` and
    /// gradient `G = sum_m u_m w_m'`, so `((I - Pi_dof) u)_k = u_k - u_bar - G r_k` (O(n) per
    /// cell); the strain is the symmetric part of the same `G`.
    fn strain_and_stabilisation_energy(
        &self,
        polygon: &[Point],
        material: &ElasticityTensor,
        u: &DVector<f64>,
    ) -> Result<(SMatrix<f64, 3, 1>, f64), SpaceError> {
        let geometry = PolygonGeometry::try_new(polygon)?;
        let n = geometry.n_vertices();
        let (_, s) = self.consistency_and_diagonal(&geometry, material)?;
        // G = [gx'; gy'] (the gradients of the two components) and the vertex means.
        let (mut gx, mut gy) = (Vector::zeros(), Vector::zeros());
        let (mut mean_x, mut mean_y) = (0.0, 0.0);
        for (m, w) in geometry.gradient_weights().iter().enumerate() {
            gx += w * u[2 * m];
            gy += w * u[2 * m + 1];
            mean_x += u[2 * m];
            mean_y += u[2 * m + 1];
        }
        let (mean_x, mean_y) = (mean_x / n as f64, mean_y / n as f64);
        let mut energy = 0.0;
        for (k, r) in geometry.relative_vertices().iter().enumerate() {
            let residual_x = u[2 * k] - mean_x - gx.dot(r);
            let residual_y = u[2 * k + 1] - mean_y - gy.dot(r);
            energy += s[2 * k] * residual_x * residual_x + s[2 * k + 1] * residual_y * residual_y;
        }
        let strain = SMatrix::<f64, 3, 1>::new(gx.x, gy.y, gx.y + gy.x);
        Ok((strain, energy.max(0.0)))
    }

    fn projection(&self, polygon: &[Point]) -> Result<EnergyProjection, SpaceError> {
        Ok(Self::projection_of(&PolygonGeometry::try_new(polygon)?))
    }

    fn body_load(
        &self,
        polygon: &[Point],
        body_force: &(dyn Fn(Point) -> Vector + Sync),
    ) -> Result<DVector<f64>, SpaceError> {
        let geometry = PolygonGeometry::try_new(polygon)?;
        // |T| f_bar = int_T f, by the degree-5 rule on the centroid fan (A3).
        let mut integral = Vector::zeros();
        for q in polygon_points(polygon, &TriangleRule::degree5()) {
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
        let weights = geometry.gradient_weights();
        Ok(DVector::from_fn(2 * n, |i, _| {
            integral[i % 2] * (1.0 / n as f64 + weights[i / 2].dot(&offset))
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::DRecipe;

    /// `K_c = |T| B' C B` and `K_s = (I - D Pi)' S (I - D Pi)` as the matrix products of the
    /// module docs.
    fn by_products(
        element: &LowestOrderVem,
        polygon: &[Point],
        material: &ElasticityTensor,
    ) -> LocalStiffness {
        let geometry = PolygonGeometry::try_new(polygon).unwrap();
        let b = LowestOrderVem::strain_matrix(&geometry);
        let c = DMatrix::from_column_slice(3, 3, material.voigt().as_slice());
        let consistency = symmetrised(b.transpose() * (c * &b) * geometry.area());
        let dofs = 2 * geometry.n_vertices();
        let projector =
            LowestOrderVem::basis_at_vertices(&geometry) * LowestOrderVem::coefficients(&geometry);
        let complement = DMatrix::identity(dofs, dofs) - projector;
        let s = element
            .stabilisation()
            .diagonal(&geometry, material, &consistency)
            .unwrap();
        let mut scaled = complement.clone();
        for (mut row, s_i) in scaled.row_iter_mut().zip(s.iter()) {
            row *= *s_i;
        }
        LocalStiffness {
            consistency,
            stabilisation: symmetrised(complement.transpose() * scaled),
        }
    }

    /// A triangle, a non-convex hexagon and a star-shaped 9-gon far from the origin.
    fn three_polygons() -> Vec<Vec<Point>> {
        vec![
            vec![
                Point::new(0.1, 0.0),
                Point::new(1.0, 0.2),
                Point::new(0.3, 0.9),
            ],
            vec![
                Point::new(0.0, 0.0),
                Point::new(2.0, 0.0),
                Point::new(2.0, 1.0),
                Point::new(1.0, 1.0),
                Point::new(1.0, 2.0),
                Point::new(0.0, 2.0),
            ],
            (0..9)
                .map(|k| {
                    let t = std::f64::consts::TAU * k as f64 / 9.0;
                    let r = if k % 2 == 0 { 1.0 } else { 0.7 };
                    Point::new(5.0 + r * t.cos(), -3.0 + 0.4 * r * t.sin())
                })
                .collect(),
        ]
    }

    #[test]
    fn stiffness_agrees_with_the_matrix_products() {
        let material = ElasticityTensor::try_isotropic(3.0, 1.5).unwrap();
        let polygons = three_polygons();
        let stabilisations: [Arc<dyn Stabilisation>; 2] =
            [Arc::new(DofiDofi::default()), Arc::new(DRecipe)];
        for stabilisation in stabilisations {
            let element = LowestOrderVem::try_new(stabilisation).unwrap();
            for polygon in &polygons {
                let fast = element.stiffness(polygon, &material).unwrap();
                let reference = by_products(&element, polygon, &material);
                // The stabilisation of a triangle is round-off (Pi_dof = I): relative to K_c.
                let scale = reference.consistency.norm();
                for (a, b) in [
                    (&fast.consistency, &reference.consistency),
                    (&fast.stabilisation, &reference.stabilisation),
                ] {
                    assert_eq!(a.shape(), b.shape());
                    assert!((a - b).norm() <= 1e-14 * scale, "{a} against {b}");
                    assert_eq!(a, &a.transpose(), "exactly symmetric");
                }
            }
        }
    }

    #[test]
    fn strain_and_stabilisation_energy_agree_with_the_projection_and_the_matrix() {
        let material = ElasticityTensor::try_isotropic(3.0, 1.5).unwrap();
        let polygons = three_polygons();
        let stabilisations: [Arc<dyn Stabilisation>; 3] = [
            Arc::new(DofiDofi::default()),
            Arc::new(DRecipe),
            Arc::new(crate::BBar),
        ];
        for stabilisation in stabilisations {
            let element = LowestOrderVem::try_new(stabilisation).unwrap();
            for polygon in &polygons {
                let u = DVector::from_fn(2 * polygon.len(), |i, _| {
                    (1.7 * i as f64 + 0.3).sin() + 0.1 * i as f64
                });
                let (strain, energy) = element
                    .strain_and_stabilisation_energy(polygon, &material, &u)
                    .unwrap();
                let expected_strain = element.projection(polygon).unwrap().strain(&u);
                assert!((strain - expected_strain).norm() <= 1e-14 * expected_strain.norm());
                let stiffness = element.stiffness(polygon, &material).unwrap();
                let expected = u.dot(&(&stiffness.stabilisation * &u)).max(0.0);
                let scale = u.dot(&(&stiffness.consistency * &u)) + expected;
                assert!(
                    (energy - expected).abs() <= 1e-13 * scale,
                    "{energy} against {expected}"
                );
            }
        }
    }
}
