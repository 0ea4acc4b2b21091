//! A posteriori error estimation of a planar body: the residual estimator of the lowest-order
//! VEM for linear elasticity, cell by cell (Beirao da Veiga, Manzini 2015; Cangiani,
//! Georgoulis, Pryer, Sutton 2017).
//!
//! With `sigma_E = C eps(Pi u_h)` the (constant) stress of the energy projection on cell `E`,
//! the squared indicator of `E` is the sum of four parts:
//!
//! ```text
//!   eta_E^2 =  w h_E^2 ||f + div sigma_E||_E^2                     (residual; div sigma_E = 0)
//!            + w sum_{e interior, e in dE} 1/2 h_e ||[[sigma n]]_e||_e^2         (jump)
//!            + w sum_{e Neumann,  e in dE}     h_e ||g - sigma_E n||_e^2        (boundary)
//!            + S_E((I - Pi) u_h, (I - Pi) u_h)                       (stabilisation)
//! ```
//!
//! `[[sigma n]]_e = (sigma_L - sigma_R) n_L` is the jump of the traction across an interior
//! edge (half of its term goes to each of its two cells); a hanging node splits a side into
//! edges like any vertex, so nothing is special about it. The boundary term is taken on every
//! boundary edge that is not on a Dirichlet part (a free edge has `g = 0`), in the components
//! the Dirichlet conditions leave free (a roller's tangential component); rigid-plate parts
//! and the parts named as contact parts are left to the layer that knows their traction (the
//! contact terms are in `vem-contact`). The stabilisation term is `u_E^T S_E u_E` with the
//! element's stabilisation matrix (which is `(I - Pi)^T S (I - Pi)`): it vanishes on linear
//! fields, as do the jumps and the residual of a body without body force.
//!
//! The stress terms are measured in energy: `w = 1 / c_min`, with `c_min` the smallest
//! eigenvalue of the elasticity tensor as a map of symmetric tensors (the Mandel matrix; `2 mu`
//! for an isotropic material), so that `eta = (sum_E eta_E^2)^(1/2)` bounds the error in the
//! energy norm `a(u - u_h, u - u_h)^(1/2)` up to a constant of the mesh's shape regularity
//! (the effectivity `eta / error` is measured in docs/adaptivity.md). `h_E` is the cell's
//! diameter, `h_e` the edge's length; the integrals are Gauss rules (the residual on the fan
//! of the cell from its centroid with the degree-5 triangle rule, the boundary term with three
//! points per edge).
//!
//! ```
//! use std::sync::Arc;
//! use vem_elastic::{Component, Dirichlet, ElasticBody, Material, Plane};
//! use vem_mesh::generators::{voronoi, Rectangle};
//! use vem_mesh::Vector;
//! use vem_space::LowestOrderVem;
//! // A linear field (uniform tension) is reproduced: every part of the estimate vanishes.
//! let mesh = voronoi(&Rectangle::unit_square(), 20, 1)?;
//! let body = ElasticBody::builder(
//!     "plate", mesh, Material::from_young_poisson(100.0, 0.3, Plane::Strain)?,
//!     Arc::new(LowestOrderVem::default()),
//! )
//! .dirichlet(Dirichlet::fixed("left", Component::X))
//! .dirichlet(Dirichlet::fixed("bottom", Component::Y))
//! .traction("right", |_| Vector::new(1.0, 0.0))
//! .build()?;
//! let u = body.solve()?;
//! let estimate = body.estimate(u.displacement(), &[])?;
//! assert!(estimate.total().powi(2) < 1e-12 * u.strain_energy(), "{}", estimate.total());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use nalgebra::{Matrix2, Matrix3, SymmetricEigen};
use rayon::prelude::*;
use vem_mesh::{geometry, Point, Vector};
use vem_space::quadrature::{polygon_rule, GaussLegendre, TriangleRule};

use crate::{ElasticBody, ElasticError};

/// The squared parts of one cell's indicator (see the module docs).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct CellIndicator {
    /// `w h_E^2 ||f||_E^2`.
    pub residual: f64,
    /// Half the weighted squared traction jumps of the cell's interior edges.
    pub jump: f64,
    /// The weighted squared traction mismatch on the cell's Neumann and free edges.
    pub boundary: f64,
    /// `S_E((I - Pi) u_h, (I - Pi) u_h)`.
    pub stabilisation: f64,
    /// Terms added by another layer (the contact terms on the cell's contact edges).
    pub contact: f64,
}

impl std::ops::Add for CellIndicator {
    type Output = Self;

    /// The parts added one by one (the indicator of the union of two sets of cells).
    fn add(self, other: Self) -> Self {
        CellIndicator {
            residual: self.residual + other.residual,
            jump: self.jump + other.jump,
            boundary: self.boundary + other.boundary,
            stabilisation: self.stabilisation + other.stabilisation,
            contact: self.contact + other.contact,
        }
    }
}

impl std::iter::Sum for CellIndicator {
    fn sum<I: Iterator<Item = Self>>(cells: I) -> Self {
        cells.fold(CellIndicator::default(), |a, c| a + c)
    }
}

impl CellIndicator {
    /// `eta_E^2`: the sum of the parts.
    pub fn squared(&self) -> f64 {
        self.residual + self.jump + self.boundary + self.stabilisation + self.contact
    }

    /// `eta_E`.
    pub fn value(&self) -> f64 {
        self.squared().sqrt()
    }
}

/// The estimate of one planar body: the indicator of every cell, with what the contact terms
/// need (the stresses and the energy weight).
#[derive(Debug, Clone, PartialEq)]
pub struct ElasticEstimate {
    /// Per cell, its squared parts.
    pub cells: Vec<CellIndicator>,
    /// Per cell, the strain `eps(Pi u_h)` (a tensor), the one the element fields
    /// ([`crate::ElementField::from_strain`]) are made of: a run needs one pass over the
    /// cells for both.
    pub strains: Vec<Matrix2<f64>>,
    /// Per cell, the in-plane stress `sigma_E = C eps(Pi u_h)`.
    pub stresses: Vec<Matrix2<f64>>,
    /// The energy weight `w = 1 / c_min` of the stress terms.
    pub weight: f64,
}

impl ElasticEstimate {
    /// `eta_E` of every cell (for marking and for output as a cell field).
    pub fn indicators(&self) -> Vec<f64> {
        self.cells.iter().map(CellIndicator::value).collect()
    }

    /// The sum of the parts over the cells (each a squared quantity).
    pub fn sum(&self) -> CellIndicator {
        self.cells.iter().copied().sum()
    }

    /// `eta = (sum_E eta_E^2)^(1/2)`.
    pub fn total(&self) -> f64 {
        self.sum().squared().sqrt()
    }
}

/// The smallest eigenvalue of a planar elasticity tensor given by its Voigt matrix
/// (engineering shear), as a map of symmetric tensors: the eigenvalues of its Mandel matrix
/// `S C S`, `S = diag(1, 1, sqrt 2)`. `2 mu` for an isotropic material.
pub fn coercivity(voigt: &Matrix3<f64>) -> f64 {
    let s = Matrix3::from_diagonal(&nalgebra::Vector3::new(1.0, 1.0, std::f64::consts::SQRT_2));
    let mandel = s * voigt * s;
    SymmetricEigen::new(mandel).eigenvalues.min()
}

impl ElasticBody<2> {
    /// The residual estimate of the displacement `displacement` (full, in the numbering of
    /// [`ElasticBody::dofs`]) of this body (see [`crate::estimate`]); the boundary edges of
    /// the parts `contact_parts` get no boundary term (their traction is the contact layer's).
    ///
    /// # Errors
    /// A displacement of the wrong length, a part that does not exist, an element failure.
    pub fn estimate(
        &self,
        displacement: &[f64],
        contact_parts: &[&str],
    ) -> Result<ElasticEstimate, ElasticError> {
        let mesh = self.mesh();
        let name = self.name().to_string();
        if displacement.len() != self.dofs().n_dofs() {
            return Err(ElasticError::WrongLength {
                body: name,
                what: "displacement",
                found: displacement.len(),
                expected: self.dofs().n_dofs(),
            });
        }
        let element_error = |polygon: usize| {
            let name = name.clone();
            move |source| ElasticError::Element {
                body: name,
                polygon,
                source,
            }
        };
        let weight = 1.0 / coercivity(&self.tensor().voigt());
        let n_cells = mesh.n_polygons();
        let rule = TriangleRule::degree5();
        // Each cell on its own: its stress, its stabilisation term and its residual (on every
        // thread; the element gives the strain and the stabilisation energy in one pass).
        let per_cell = (0..n_cells)
            .into_par_iter()
            .map(|c| {
                let local = self.local_values(c, displacement);
                let (strain, stabilisation) = self
                    .element()
                    .strain_and_stabilisation_energy(self.body_mesh(), c, self.tensor(), &local)
                    .map_err(element_error(c))?;
                let mut cell = CellIndicator {
                    stabilisation,
                    ..CellIndicator::default()
                };
                if let Some(force) = self.body_force() {
                    let points = mesh.polygon_points(c);
                    let h = geometry::diameter(&points);
                    let integral: f64 = polygon_rule(&points, &rule)
                        .iter()
                        .map(|q| q.weight * force(q.point).norm_squared())
                        .sum();
                    cell.residual = weight * h * h * integral.max(0.0);
                }
                Ok((cell, strain))
            })
            .collect::<Result<Vec<_>, ElasticError>>()?;
        let (mut cells, strains): (Vec<CellIndicator>, Vec<Matrix2<f64>>) =
            per_cell.into_iter().unzip();
        let stresses: Vec<Matrix2<f64>> = strains
            .iter()
            .map(|strain| self.tensor().stress_tensor(strain))
            .collect();
        // Boundary edges: prescribed components, tractions, contact.
        let mut prescribed = vec![[false; 2]; mesh.n_edges()];
        let mesh_error = |source| ElasticError::Mesh {
            body: self.name().to_string(),
            source,
        };
        for condition in self.dirichlet() {
            let part = mesh.part(condition.part()).map_err(mesh_error)?;
            for &e in &part.edges {
                for &k in condition.component().indices(2) {
                    prescribed[e][k] = true;
                }
            }
        }
        let mut skipped = vec![false; mesh.n_edges()];
        for name in contact_parts {
            for &e in &mesh.part(name).map_err(mesh_error)?.edges {
                skipped[e] = true;
            }
        }
        let mut tractions: Vec<Vec<usize>> = vec![Vec::new(); mesh.n_edges()];
        for (t, traction) in self.tractions().iter().enumerate() {
            for &e in &mesh.part(traction.part()).map_err(mesh_error)?.edges {
                tractions[e].push(t);
            }
        }
        let gauss = GaussLegendre::try_new(3).expect("3 Gauss points exist");
        for (e, edge) in mesh.edges().iter().enumerate() {
            let [a, b] = edge.vertices;
            let (pa, pb) = (mesh.vertex(a), mesh.vertex(b));
            let length = (pb - pa).norm();
            let normal = geometry::outward_normal(pa, pb);
            match edge.right {
                Some(right) => {
                    let jump = (stresses[edge.left] - stresses[right]) * normal;
                    let term = 0.5 * weight * length * length * jump.norm_squared();
                    cells[edge.left].jump += term;
                    cells[right].jump += term;
                }
                None => {
                    if skipped[e] || prescribed[e] == [true, true] {
                        continue;
                    }
                    let sigma_n = stresses[edge.left] * normal;
                    let held = prescribed[e];
                    let integral: f64 = gauss
                        .nodes()
                        .iter()
                        .zip(gauss.weights())
                        .map(|(&s, &w)| {
                            let x = Point::from(pa.coords.lerp(&pb.coords, 0.5 * (s + 1.0)));
                            let g = tractions[e]
                                .iter()
                                .fold(Vector::zeros(), |g, &t| g + self.tractions()[t].value_at(x));
                            let r = g - sigma_n;
                            let r = Vector::new(
                                if held[0] { 0.0 } else { r.x },
                                if held[1] { 0.0 } else { r.y },
                            );
                            0.5 * length * w * r.norm_squared()
                        })
                        .sum();
                    cells[edge.left].boundary += weight * length * integral;
                }
            }
        }
        Ok(ElasticEstimate {
            cells,
            strains,
            stresses,
            weight,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;

    use crate::{Component, Dirichlet, Material, Plane};
    use vem_mesh::generators::{hexagons, nonconvex, structured_triangles, voronoi, Rectangle};
    use vem_mesh::Mesh;
    use vem_space::LowestOrderVem;

    fn isotropic() -> Material {
        Material::from_lame(2.0, 1.0, Plane::Strain).unwrap()
    }

    #[test]
    fn coercivity_of_an_isotropic_tensor_is_two_mu() {
        let body = ElasticBody::builder(
            "b",
            structured_triangles(&Rectangle::unit_square(), 1, 1).unwrap(),
            isotropic(),
            Arc::new(LowestOrderVem::default()),
        )
        .build()
        .unwrap();
        assert!((coercivity(&body.tensor().voigt()) - 2.0).abs() < 1e-14);
    }

    /// The patch test: a linear displacement prescribed on the whole boundary (and with its
    /// constant traction on part of it) is reproduced, and every part of the estimate is zero
    /// to round-off, on meshes with hanging nodes too.
    #[test]
    fn estimate_vanishes_on_linear_fields() {
        let rect = Rectangle::unit_square();
        let mut meshes: Vec<Mesh> = vec![
            voronoi(&rect, 25, 4).unwrap(),
            hexagons(&rect, 4).unwrap(),
            nonconvex(&rect, 4).unwrap(),
        ];
        let refined = vem_mesh::refine::refine(&meshes[0], &[0, 3, 7])
            .unwrap()
            .mesh;
        meshes.push(refined);
        // u = (0.1 x + 0.3 y, -0.2 x + 0.05 y); eps = [[0.1, 0.05], [0.05, 0.05]].
        let u = |x: Point| Vector::new(0.1 * x.x + 0.3 * x.y, -0.2 * x.x + 0.05 * x.y);
        let (lambda, mu) = (2.0, 1.0);
        let tr = 0.15;
        let sigma = Matrix2::new(
            lambda * tr + 2.0 * mu * 0.1,
            2.0 * mu * 0.05,
            2.0 * mu * 0.05,
            lambda * tr + 2.0 * mu * 0.05,
        );
        for mesh in meshes {
            let body = ElasticBody::builder(
                "patch",
                mesh,
                isotropic(),
                Arc::new(LowestOrderVem::default()),
            )
            .dirichlet(Dirichlet::prescribed("left", Component::All, u))
            .dirichlet(Dirichlet::prescribed("bottom", Component::All, u))
            .dirichlet(Dirichlet::prescribed("top", Component::Y, u))
            .traction("right", move |_| sigma * Vector::new(1.0, 0.0))
            .traction("top", move |_| sigma * Vector::new(0.0, 1.0))
            .build()
            .unwrap();
            let solution = body.solve().unwrap();
            let estimate = body.estimate(solution.displacement(), &[]).unwrap();
            let sum = estimate.sum();
            // Squared quantities against the strain energy: round-off (a quadratic form of a
            // vector that vanishes to round-off is of the order of eps times the energy).
            for (what, value) in [
                ("residual", sum.residual),
                ("jump", sum.jump),
                ("boundary", sum.boundary),
                ("stabilisation", sum.stabilisation),
            ] {
                assert!(
                    value < 1e-12 * solution.strain_energy(),
                    "{what}: {value:e} against {:e}",
                    solution.strain_energy()
                );
            }
            for s in &estimate.stresses {
                assert!((s - sigma).norm() < 1e-12);
            }
            // The strains the element fields are made of: the exact strain, and those of
            // `element_fields` (its own pass over the cells).
            let epsilon = Matrix2::new(0.1, 0.05, 0.05, 0.05);
            let fields = body.element_fields(solution.displacement()).unwrap();
            assert_eq!(estimate.strains.len(), fields.len());
            for (strain, field) in estimate.strains.iter().zip(&fields) {
                assert!((strain - epsilon).norm() < 1e-12);
                assert!((field.strain.fixed_view::<2, 2>(0, 0) - strain).norm() < 1e-15);
            }
        }
    }

    #[test]
    fn a_wrong_length_is_named() {
        let body = ElasticBody::builder(
            "b",
            structured_triangles(&Rectangle::unit_square(), 2, 2).unwrap(),
            isotropic(),
            Arc::new(LowestOrderVem::default()),
        )
        .clamp("left")
        .build()
        .unwrap();
        let err = body.estimate(&[0.0; 3], &[]).unwrap_err();
        assert!(err.to_string().contains("'b'"), "{err}");
        let err = body.estimate(&[0.0; 18], &["contact"]).unwrap_err();
        assert!(matches!(err, ElasticError::Mesh { .. }), "{err}");
    }
}
