//! The lowest-order virtual element on one polygon or one polyhedron: geometry, energy
//! projection, stabilisation, load term.
//!
//! This is the place where a contributor adds a new element type: implement [`ElementSpace`]
//! for it. The global assembly (`vem-elastic`) sees elements only through that trait.
//!
//! Conventions used everywhere in the project:
//! - local degrees of freedom are vertex values, interleaved by component:
//!   `[u_x(v0), u_y(v0), u_x(v1), u_y(v1), ...]` (2n for a polygon with n vertices);
//! - strains and stresses in Voigt notation `[xx, yy, xy]` with engineering shear strain
//!   `gamma_xy = 2 eps_xy`, so that `sigma = C eps` with a symmetric 3x3 `C`.
//!
//! Element types: [`LowestOrderVem`] ("vem1", any polygon, with a [`Stabilisation`]: the
//! built-in [`DofiDofi`], [`DRecipe`] and the locking-free [`BBar`] or a user's own) and [`LinearTriangle`] ("p1", the
//! classical linear triangle, an independent check: on a triangle the two agree to round-off),
//! by name from the [`ElementRegistry`]. The validated geometry of one polygon is
//! [`PolygonGeometry`]. Loads: [`ElementSpace::body_load`] and [`edge_traction_load`]; quadrature
//! rules for others to reuse in [`quadrature`]. With the cargo feature `testkit`, the module
//! `testkit` checks any [`ElementSpace`] on a standard set of polygons (rigid motions,
//! consistency, rank, symmetry, patch test); `docs/elements.md` shows how to add an element.
//!
//! In three dimensions: [`PolyhedralElement`] is the element on one polyhedron
//! (`vem_mesh::polyhedral::geometry::Polyhedron`), [`PolyhedralVem`] the lowest-order VEM on
//! polyhedra (Gain, Talischi, Paulino 2014) with the same stabilisations
//! ([`PolyhedralStabilisation`]), [`LinearTetrahedron`] the P1 tetrahedron written independently,
//! [`PolyhedronGeometry`] the validated geometry, [`SolidElement`] the [`MeshElement<3>`] of any
//! of them, [`face_traction_load`] the load of a traction on a face; the module `testkit3d`
//! (feature `testkit`) checks a polyhedral element on a standard set of polyhedra.
//!
//! ```
//! use nalgebra::DVector;
//! use vem_space::{ElasticityTensor, ElementSpace, LowestOrderVem, Point};
//! // A square with a hanging node on its right edge: five vertices, ten DOFs.
//! let polygon = [
//!     Point::new(0.0, 0.0), Point::new(1.0, 0.0), Point::new(1.0, 0.5),
//!     Point::new(1.0, 1.0), Point::new(0.0, 1.0),
//! ];
//! let material = ElasticityTensor::try_isotropic(2.0, 1.0)?;
//! let element = LowestOrderVem::default();
//! let local = element.stiffness(&polygon, &material)?;
//! // The linear field u = (x, 0) has strain (1, 0, 0) and energy |T| C_11 = 4.
//! let u = DVector::from_fn(10, |i, _| if i % 2 == 0 { polygon[i / 2].x } else { 0.0 });
//! let energy = u.dot(&(local.total() * &u));
//! assert!((energy - 4.0).abs() < 1e-13);
//! // ... and the projection reproduces it.
//! let projection = element.projection(&polygon)?;
//! assert!((projection.strain(&u) - nalgebra::Vector3::new(1.0, 0.0, 0.0)).norm() < 1e-14);
//! # Ok::<(), vem_space::SpaceError>(())
//! ```
#![deny(missing_docs)]

mod error;
mod load;
mod material;
mod mesh_element;
mod options;
mod p1;
mod p1_tetrahedron;
mod polygon;
mod polyhedral;
mod polyhedron;
pub mod quadrature;
mod registry;
mod stabilisation;
mod stabilisation3;
#[cfg(feature = "testkit")]
pub mod testkit;
#[cfg(feature = "testkit")]
pub mod testkit3d;
mod vem;
mod vem3;

pub use error::SpaceError;
pub use load::edge_traction_load;
pub use material::{voigt_len, voigt_pairs, ElasticityTensor};
pub use mesh_element::{DofLayout, FieldOf, MeshElement, PlanarElement};
pub use options::{Options, OptionsError};
pub use p1::LinearTriangle;
pub use p1_tetrahedron::LinearTetrahedron;
pub use polygon::PolygonGeometry;
pub use polyhedral::{face_traction_load, PolyhedralElement, SolidElement, SpaceField};
pub use polyhedron::PolyhedronGeometry;
pub use registry::{
    Choice, ElementRegistry, Factory, PolyhedralStabilisationRegistry, Registry, RegistryError,
    StabilisationRegistry,
};
pub use stabilisation::{BBar, DRecipe, DofiDofi, Stabilisation, StabilisationScaling};
pub use stabilisation3::{
    bulk_modulus_3d, deviatoric_part, stabilisation_length, PolyhedralStabilisation,
};
pub use vem::LowestOrderVem;
pub use vem3::PolyhedralVem;

use nalgebra::{DMatrix, DVector, SMatrix};
pub use vem_mesh::{Point, Point3, PointD, Vector, Vector3, VectorD};

/// The local stiffness of one polygon, split into its two parts
/// `K_T = consistency + stabilisation` (spec section 2).
#[derive(Debug, Clone, PartialEq)]
pub struct LocalStiffness {
    /// `a_T(Pi u, Pi v)`: the consistency part, exact on P1 (consistency (3.1)).
    pub consistency: DMatrix<f64>,
    /// `S_T((I - Pi) u, (I - Pi) v)`: the stabilisation part, zero on P1 fields.
    pub stabilisation: DMatrix<f64>,
}

impl LocalStiffness {
    /// The local matrix `consistency + stabilisation`.
    pub fn total(&self) -> DMatrix<f64> {
        &self.consistency + &self.stabilisation
    }
}

/// The energy projection `Pi: V_h(E) -> P1(E)^D` of one cell (a polygon in 2D, a polyhedron in
/// 3D; `D = 2` by default) as a linear map of the local degrees of freedom:
/// `Pi v (x) = value_at_reference + gradient (x - reference)`.
#[derive(Debug, Clone, PartialEq)]
pub struct EnergyProjection<const D: usize = 2> {
    /// The point about which the projected polynomial is expanded.
    pub reference: PointD<D>,
    /// Rows: the `D` values of `Pi v` at the reference point, then its gradient row by row
    /// (`d_j (Pi v)_i` in row `D + D i + j`), as a linear map of the local DOFs: in 2D
    /// `[value_x, value_y, d_x v_x, d_y v_x, d_x v_y, d_y v_y]` (6 x 2n), in 3D 12 x 3n.
    pub coefficients: DMatrix<f64>,
}

impl<const D: usize> EnergyProjection<D> {
    /// The projected polynomial of the DOF vector `dofs`, evaluated at `x`.
    pub fn evaluate(&self, dofs: &DVector<f64>, x: PointD<D>) -> VectorD<D> {
        let c = &self.coefficients * dofs;
        let d = x - self.reference;
        VectorD::<D>::from_fn(|i, _| c[i] + (0..D).map(|j| c[D + D * i + j] * d[j]).sum::<f64>())
    }

    /// The (constant) gradient of `Pi v`: entry (i, j) is d_j (Pi v)_i.
    pub fn gradient(&self, dofs: &DVector<f64>) -> SMatrix<f64, D, D> {
        let c = &self.coefficients * dofs;
        SMatrix::<f64, D, D>::from_fn(|i, j| c[D + D * i + j])
    }
}

impl EnergyProjection<2> {
    /// The (constant) strain of `Pi v` in Voigt notation `[xx, yy, 2 xy]`.
    pub fn strain(&self, dofs: &DVector<f64>) -> SMatrix<f64, 3, 1> {
        let g = self.gradient(dofs);
        SMatrix::<f64, 3, 1>::new(g[(0, 0)], g[(1, 1)], g[(0, 1)] + g[(1, 0)])
    }
}

impl EnergyProjection<3> {
    /// The (constant) strain of `Pi v` in Voigt notation `[xx, yy, zz, 2 yz, 2 xz, 2 xy]`.
    pub fn strain(&self, dofs: &DVector<f64>) -> SMatrix<f64, 6, 1> {
        let g = self.gradient(dofs);
        SMatrix::<f64, 6, 1>::from_column_slice(&[
            g[(0, 0)],
            g[(1, 1)],
            g[(2, 2)],
            g[(1, 2)] + g[(2, 1)],
            g[(0, 2)] + g[(2, 0)],
            g[(0, 1)] + g[(1, 0)],
        ])
    }
}

/// A local element space on one polygon: what a contributor implements to add an element type.
///
/// Implementations must be thread-safe: assembly calls them from many threads at once.
pub trait ElementSpace: Send + Sync {
    /// A short name for reports ("vem1", "p1", ...); for a registered element, its name in the
    /// [`ElementRegistry`].
    fn name(&self) -> &str;

    /// Whether the element can be built on a polygon with `n_vertices` vertices (default: any).
    /// The global assembly checks every polygon before assembling, so that an element that
    /// cannot take, e.g., a vertex inserted on an edge fails early with the polygon named.
    fn supports(&self, n_vertices: usize) -> bool {
        let _ = n_vertices;
        true
    }

    /// The local stiffness of the polygon with vertices `polygon` (counter-clockwise) and
    /// material `material`, split into consistency and stabilisation.
    fn stiffness(
        &self,
        polygon: &[Point],
        material: &ElasticityTensor,
    ) -> Result<LocalStiffness, SpaceError>;

    /// The energy projection of the polygon, for post-processing (strain, stress, errors).
    fn projection(&self, polygon: &[Point]) -> Result<EnergyProjection, SpaceError>;

    /// The local degrees of freedom on a polygon (default: the two displacement values at each
    /// vertex, interleaved by component).
    fn dof_layout(&self) -> DofLayout {
        DofLayout::vertex_values(2)
    }

    /// The local load vector `l_T^h(v)` of a body force `f` (assumption A3), length 2n.
    fn body_load(
        &self,
        polygon: &[Point],
        body_force: &(dyn Fn(Point) -> Vector + Sync),
    ) -> Result<DVector<f64>, SpaceError>;

    /// The strain of `Pi u` in Voigt notation (see [`EnergyProjection::strain`]) and the
    /// stabilisation energy `u' K_s u` (`K_s` the stabilisation of
    /// [`ElementSpace::stiffness`], the energy clamped at zero) of the local degrees of
    /// freedom `u` (length 2n, as for [`ElementSpace::stiffness`]): what the error estimate
    /// needs of a cell. By default from [`ElementSpace::projection`] and
    /// [`ElementSpace::stiffness`]; an element may give both without forming `K_s`.
    fn strain_and_stabilisation_energy(
        &self,
        polygon: &[Point],
        material: &ElasticityTensor,
        u: &DVector<f64>,
    ) -> Result<(SMatrix<f64, 3, 1>, f64), SpaceError> {
        let strain = self.projection(polygon)?.strain(u);
        let stiffness = self.stiffness(polygon, material)?;
        Ok((strain, u.dot(&(&stiffness.stabilisation * u)).max(0.0)))
    }
}
