//! The lowest-order (k = 1) virtual element for linear elasticity on polyhedra (Gain, Talischi,
//! Paulino, CMAME 282 (2014) 132-160).
//!
//! On a polyhedron `E` with vertices `x_1 .. x_n`, `xbar` their mean and `|E|` the volume, the
//! local space holds the fields that are, on every face, the fan trace (linear on each fan
//! triangle of the face with the mean of the face's vertex values at its centre) and
//! harmonic-like inside; what the element needs of them is computable from the vertex values:
//!
//! - **Energy projection.** The mean gradient is exact:
//!   `G = (1/|E|) int_E grad v = (1/|E|) sum_F int_F v (x) n dS = sum_a v_a (x) q_a`, with the
//!   face weights of [`crate::PolyhedronGeometry`]. Then `Pi v (x) = vbar + G (x - xbar)` with
//!   `vbar` the mean of the vertex values: the symmetric part of `G` is the mean strain, so
//!   `a_E(Pi v, p) = a_E(v, p)` for every `p in P1^3` (consistency), and the vertex mean and
//!   the skew part of `G` fix the six rigid motions, so `Pi p = p` for `p in P1^3`
//!   (`sum_a q_a = 0`, `sum_a (x_a - xbar) (x) q_a = I`).
//! - **Consistency part** `K_c = |E| B^T C B`, `B` (6 x 3n) the Voigt strain
//!   `[xx, yy, zz, 2 yz, 2 xz, 2 xy]` of `Pi`: the block of vertex `a` is
//!   `[[q_x,0,0],[0,q_y,0],[0,0,q_z],[0,q_z,q_y],[q_z,0,q_x],[q_y,q_x,0]]` (`q = q_a`).
//! - **Stabilisation part** `K_s = (I - Pi_dof)^T S (I - Pi_dof)`, `Pi_dof = D Pi` with `D`
//!   (3n x 12) the basis `e_i`, `(x_j - xbar_j) e_i` of `P1^3` at the vertices, `S` diagonal from
//!   the [`PolyhedralStabilisation`] (scaled by a length: entries of `K_c` scale like `C h`).
//!   `K_s` vanishes on linear fields; `K_s = 0` on a tetrahedron, where the space is `P1^3`
//!   and `Pi_dof = I`.
//! - **Load** `l_E(v) = int_E f . Pi v`, by the degree-2 rule on the signed tetrahedra of
//!   [`crate::quadrature::polyhedron_rule`] (exact for a linear `f`): on a tetrahedron, where
//!   `Pi v = v`, this is the consistent load of the linear element. It differs from the 2D
//!   element's `(int_E f) . (Pi v)(x_E)` (the cell mean of `f`) by `int_E (f - fbar) . grad Pi v
//!   (x - x_E) = O(h^2) |f|_1 |v|_1` per cell: both are first-order consistent, and measured on
//!   the families the full projection reaches the asymptotic `E_0` rate at coarser meshes.
//!
//! The cost is dominated by the products with `K_c` and `Pi_dof` (`O(n^2)` with the 12
//! polynomials as inner dimension: `(I - P)^T S (I - P) = S - S P - P^T S + Pi^T (D^T S D) Pi`).

use std::sync::Arc;

use nalgebra::{DMatrix, DVector};
use vem_mesh::polyhedral::geometry::Polyhedron;
use vem_mesh::Vector3;

use crate::quadrature::{polyhedron_rule, TetrahedronRule};
use crate::{
    DofiDofi, ElasticityTensor, EnergyProjection, LocalStiffness, PolyhedralElement,
    PolyhedralStabilisation, PolyhedronGeometry, SpaceError, SpaceField, Stabilisation,
};

/// The lowest-order virtual element for linear elasticity on polyhedra ("vem1" in 3D): vertex
/// DOFs, energy projection from face integrals, a choice of stabilisation (module docs).
///
/// ```
/// use nalgebra::DVector;
/// use vem_mesh::polyhedral::geometry::Polyhedron;
/// use vem_mesh::Point3;
/// use vem_space::{ElasticityTensor, PolyhedralElement, PolyhedralVem};
/// // The unit cube; an isotropic material lambda = 2, mu = 1.
/// let points: Vec<Point3> = (0..8)
///     .map(|k| Point3::new((k & 1) as f64, (k >> 1 & 1) as f64, (k >> 2) as f64))
///     .collect();
/// let faces = vec![
///     vec![0, 4, 6, 2], vec![1, 3, 7, 5], vec![0, 1, 5, 4],
///     vec![2, 6, 7, 3], vec![0, 2, 3, 1], vec![4, 5, 7, 6],
/// ];
/// let cube = Polyhedron::new(points.clone(), &faces);
/// let mut c = nalgebra::DMatrix::zeros(6, 6);
/// for i in 0..3 {
///     for j in 0..3 {
///         c[(i, j)] = 2.0 + if i == j { 2.0 } else { 0.0 };
///     }
///     c[(i + 3, i + 3)] = 1.0;
/// }
/// let material = ElasticityTensor::<3>::try_from_voigt_matrix(&c)?;
/// let k = PolyhedralVem::default().stiffness(&cube, &material)?.total();
/// // u = (x, 0, 0): strain e_xx = 1, energy |E| C_11 = 4.
/// let u = DVector::from_fn(24, |i, _| if i % 3 == 0 { points[i / 3].x } else { 0.0 });
/// assert!((u.dot(&(&k * &u)) - 4.0).abs() < 1e-13);
/// # Ok::<(), vem_space::SpaceError>(())
/// ```
#[derive(Debug, Clone)]
pub struct PolyhedralVem {
    stabilisation: Arc<dyn PolyhedralStabilisation>,
    name: String,
}

impl Default for PolyhedralVem {
    /// "vem1": dofi-dofi scaled by `trace(C)` ([`DofiDofi::default`]).
    fn default() -> Self {
        Self::from_valid(Arc::new(DofiDofi::default()))
    }
}

impl PolyhedralVem {
    /// The element with the stabilisation `stabilisation`, whose settings are checked. Its name
    /// is `"vem1"` for the default dofi-dofi stabilisation and `"vem1-<stabilisation name>"`
    /// otherwise, as in 2D.
    pub fn try_new(stabilisation: Arc<dyn PolyhedralStabilisation>) -> Result<Self, SpaceError> {
        stabilisation.validate()?;
        Ok(Self::from_valid(stabilisation))
    }

    fn from_valid(stabilisation: Arc<dyn PolyhedralStabilisation>) -> Self {
        let suffix = stabilisation.name();
        let name = if suffix == Stabilisation::name(&DofiDofi::default()) {
            "vem1".to_string()
        } else {
            format!("vem1-{suffix}")
        };
        Self {
            stabilisation,
            name,
        }
    }

    /// The stabilisation.
    pub fn stabilisation(&self) -> &dyn PolyhedralStabilisation {
        &*self.stabilisation
    }

    /// The 12 x 3n coefficients of `Pi` (see [`EnergyProjection::coefficients`]): the three
    /// values at `xbar`, then the gradient row by row.
    pub fn projection_coefficients(geometry: &PolyhedronGeometry) -> DMatrix<f64> {
        let n = geometry.n_vertices();
        let mut c = DMatrix::zeros(12, 3 * n);
        let mean = 1.0 / n as f64;
        for (a, q) in geometry.gradient_weights().iter().enumerate() {
            for i in 0..3 {
                c[(i, 3 * a + i)] = mean;
                for j in 0..3 {
                    c[(3 + 3 * i + j, 3 * a + i)] = q[j];
                }
            }
        }
        c
    }

    /// The 6 x 3n Voigt strain `[xx, yy, zz, 2 yz, 2 xz, 2 xy]` of `Pi`.
    pub fn strain_matrix(geometry: &PolyhedronGeometry) -> DMatrix<f64> {
        let n = geometry.n_vertices();
        let mut b = DMatrix::zeros(6, 3 * n);
        for (a, q) in geometry.gradient_weights().iter().enumerate() {
            let (x, y, z) = (3 * a, 3 * a + 1, 3 * a + 2);
            b[(0, x)] = q.x;
            b[(1, y)] = q.y;
            b[(2, z)] = q.z;
            b[(3, y)] = q.z;
            b[(3, z)] = q.y;
            b[(4, x)] = q.z;
            b[(4, z)] = q.x;
            b[(5, x)] = q.y;
            b[(5, y)] = q.x;
        }
        b
    }

    /// `D`: the basis of [`PolyhedralVem::projection_coefficients`] at the vertices (3n x 12;
    /// the stiffness computes with its structure directly, the tests with the matrix).
    #[cfg(test)]
    fn basis_at_vertices(geometry: &PolyhedronGeometry) -> DMatrix<f64> {
        let n = geometry.n_vertices();
        let mut d = DMatrix::zeros(3 * n, 12);
        for (a, r) in geometry.relative_vertices().iter().enumerate() {
            for i in 0..3 {
                d[(3 * a + i, i)] = 1.0;
                for j in 0..3 {
                    d[(3 * a + i, 3 + 3 * i + j)] = r[j];
                }
            }
        }
        d
    }

    /// The local stiffness of a polyhedron whose geometry is known.
    ///
    /// Computed entry by entry on the structure of the matrices of the module docs (the tests
    /// compare with their products): the consistency part from the columns of the Voigt strain
    /// matrix `B` (`[q_x, 0, 0, 0, q_z, q_y]`, `[0, q_y, 0, q_z, 0, q_x]`,
    /// `[0, 0, q_z, q_y, q_x, 0]` for the three values of a vertex with gradient weight `q`),
    /// the stabilisation part from `Pi_dof = D Pi = I_3 (x) Q`, `Q[a][b] = 1/n + r_a . q_b`
    /// (`r_a` the vertex relative to the vertex mean): every component is projected alike, so
    /// `K_s` couples only equal components, `K_s[3a + i][3b + i] = sum_c R[c][a] s_(3c + i)
    /// R[c][b]` with `R = I - Q`. Lower triangles computed and mirrored: both parts are exactly
    /// symmetric.
    pub fn stiffness_of(
        &self,
        geometry: &PolyhedronGeometry,
        material: &ElasticityTensor<3>,
    ) -> Result<LocalStiffness, SpaceError> {
        let n = geometry.n_vertices();
        let dofs = 3 * n;
        let c = material.voigt_matrix();
        let weights = geometry.gradient_weights();
        let column = |j: usize| {
            let q = weights[j / 3];
            match j % 3 {
                0 => [q.x, 0.0, 0.0, 0.0, q.z, q.y],
                1 => [0.0, q.y, 0.0, q.z, 0.0, q.x],
                _ => [0.0, 0.0, q.z, q.y, q.x, 0.0],
            }
        };
        let volume = geometry.volume();
        let mut consistency = DMatrix::zeros(dofs, dofs);
        for j in 0..dofs {
            let b = column(j);
            let mut cb = [0.0; 6];
            for (r, value) in cb.iter_mut().enumerate() {
                *value = (0..6).map(|k| c[(r, k)] * b[k]).sum();
            }
            for i in j..dofs {
                let a = column(i);
                let value = volume * (0..6).map(|k| a[k] * cb[k]).sum::<f64>();
                consistency[(i, j)] = value;
                consistency[(j, i)] = value;
            }
        }
        let s = crate::stabilisation::checked_diagonal(
            || self.stabilisation.name(),
            self.stabilisation
                .polyhedral_diagonal(geometry, material, &consistency)?,
            dofs,
        )?;
        let mean = 1.0 / n as f64;
        // R = I - Q, row-major n x n.
        let mut r = vec![0.0; n * n];
        for (k, x) in geometry.relative_vertices().iter().enumerate() {
            for (m, q) in weights.iter().enumerate() {
                let identity = if k == m { 1.0 } else { 0.0 };
                r[k * n + m] = identity - (mean + x.dot(q));
            }
        }
        let mut stabilisation = DMatrix::zeros(dofs, dofs);
        for component in 0..3 {
            for b in 0..n {
                for a in b..n {
                    let value: f64 = (0..n)
                        .map(|k| r[k * n + a] * s[3 * k + component] * r[k * n + b])
                        .sum();
                    stabilisation[(3 * a + component, 3 * b + component)] = value;
                    stabilisation[(3 * b + component, 3 * a + component)] = value;
                }
            }
        }
        Ok(LocalStiffness {
            consistency,
            stabilisation,
        })
    }
}

/// `(m + m^T) / 2`: removes the round-off asymmetry of a product.
#[cfg(test)]
fn symmetrised(m: DMatrix<f64>) -> DMatrix<f64> {
    (&m + m.transpose()) * 0.5
}

impl PolyhedralElement for PolyhedralVem {
    fn name(&self) -> &str {
        &self.name
    }

    fn stiffness(
        &self,
        polyhedron: &Polyhedron,
        material: &ElasticityTensor<3>,
    ) -> Result<LocalStiffness, SpaceError> {
        self.stiffness_of(&PolyhedronGeometry::try_new(polyhedron)?, material)
    }

    fn projection(&self, polyhedron: &Polyhedron) -> Result<EnergyProjection<3>, SpaceError> {
        let geometry = PolyhedronGeometry::try_new(polyhedron)?;
        Ok(EnergyProjection {
            reference: geometry.vertex_mean(),
            coefficients: Self::projection_coefficients(&geometry),
        })
    }

    fn body_load(
        &self,
        polyhedron: &Polyhedron,
        force: SpaceField<'_>,
    ) -> Result<DVector<f64>, SpaceError> {
        let geometry = PolyhedronGeometry::try_new(polyhedron)?;
        let n = geometry.n_vertices();
        let q = geometry.gradient_weights();
        // int_E f . Pi v with Pi v (x) = sum_a v_a (1/n + q_a . (x - xbar)): vertex a receives
        // sum over the points of w f(x) (1/n + q_a . (x - xbar)).
        let mut integral = Vector3::zeros();
        let mut moment = nalgebra::Matrix3::zeros();
        for point in polyhedron_rule(polyhedron, &TetrahedronRule::degree2()) {
            let f = force(point.point);
            if !f.iter().all(|c| c.is_finite()) {
                return Err(SpaceError::NonFiniteLoadInSpace {
                    x: point.point.x,
                    y: point.point.y,
                    z: point.point.z,
                });
            }
            integral += f * point.weight;
            moment += f * (point.point - geometry.vertex_mean()).transpose() * point.weight;
        }
        // Entry (c, j) of `moment` is int_E f_c (x_j - xbar_j).
        Ok(DVector::from_fn(3 * n, |i, _| {
            let (a, c) = (i / 3, i % 3);
            integral[c] / n as f64 + (0..3).map(|j| moment[(c, j)] * q[a][j]).sum::<f64>()
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testkit3d::{standard_materials, standard_polyhedra};
    use crate::{BBar, DRecipe, DofiDofi};

    /// `K_c = |E| B' C B` and `K_s = (I - D Pi)' S (I - D Pi)` as the matrix products of the
    /// module docs.
    fn by_products(
        element: &PolyhedralVem,
        geometry: &PolyhedronGeometry,
        material: &ElasticityTensor<3>,
    ) -> LocalStiffness {
        let b = PolyhedralVem::strain_matrix(geometry);
        let c = material.voigt_matrix();
        let consistency = symmetrised(b.transpose() * (c * &b) * geometry.volume());
        let dofs = 3 * geometry.n_vertices();
        let projector = PolyhedralVem::basis_at_vertices(geometry)
            * PolyhedralVem::projection_coefficients(geometry);
        let complement = DMatrix::identity(dofs, dofs) - projector;
        let s = element
            .stabilisation()
            .polyhedral_diagonal(geometry, material, &consistency)
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

    #[test]
    fn stiffness_agrees_with_the_matrix_products() {
        let stabilisations: [Arc<dyn PolyhedralStabilisation>; 3] = [
            Arc::new(DofiDofi::default()),
            Arc::new(DRecipe),
            Arc::new(BBar),
        ];
        for stabilisation in stabilisations {
            let element = PolyhedralVem::try_new(stabilisation).unwrap();
            for test in standard_polyhedra() {
                let geometry = PolyhedronGeometry::try_new(&test.polyhedron).unwrap();
                for material in standard_materials() {
                    let fast = element.stiffness_of(&geometry, &material).unwrap();
                    let reference = by_products(&element, &geometry, &material);
                    let scale = reference.consistency.norm();
                    for (a, b) in [
                        (&fast.consistency, &reference.consistency),
                        (&fast.stabilisation, &reference.stabilisation),
                    ] {
                        assert_eq!(a.shape(), b.shape());
                        assert!(
                            (a - b).norm() <= 1e-13 * scale,
                            "{}: {} against {}",
                            test.name,
                            (a - b).norm(),
                            scale
                        );
                        assert_eq!(a, &a.transpose(), "{}: exactly symmetric", test.name);
                    }
                }
            }
        }
    }
}
