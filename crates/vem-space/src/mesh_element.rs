//! The element as the assembly sees it, whatever the dimension: per cell of a body's mesh, the
//! local degrees of freedom it declares, the local stiffness, the loads and the strain of the
//! projection.
//!
//! Element types are written per dimension, where the geometry differs: [`ElementSpace`] on a
//! polygon in 2D, [`PolyhedralElement`] on a polyhedron in 3D. [`MeshElement<D>`] is the seam
//! the layers above program against, once for `d = 2` and `d = 3`; [`PlanarElement`] makes every
//! [`ElementSpace`] one for `D = 2`, [`crate::SolidElement`] every [`PolyhedralElement`] one for
//! `D = 3`.

use std::fmt;
use std::sync::Arc;

use nalgebra::{DVector, SMatrix};
use vem_mesh::{BodyMesh, Point, PointD, VectorD};

use crate::{
    edge_traction_load, ElasticityTensor, ElementSpace, LocalStiffness, PolyhedralElement,
    SpaceError,
};

/// The local degrees of freedom an element declares on one cell, in its local order.
///
/// Today's elements carry the `components` values of the displacement at every vertex of the
/// cell, interleaved by component: `[u_x(v0), u_y(v0), (u_z(v0),) u_x(v1), ...]`. The global
/// numbering (`vem_elastic::DofMap`) is built from this declaration, so an element that also
/// needs edge or cell degrees of freedom extends this type, not the code above it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DofLayout {
    vertex_components: usize,
}

impl DofLayout {
    /// `components` displacement values at every vertex (the dimension, for elasticity).
    pub const fn vertex_values(components: usize) -> Self {
        Self {
            vertex_components: components,
        }
    }

    /// Values per vertex.
    pub const fn vertex_components(&self) -> usize {
        self.vertex_components
    }

    /// The number of local degrees of freedom of a cell with `vertices` vertices.
    pub const fn cell_dofs(&self, vertices: usize) -> usize {
        self.vertex_components * vertices
    }
}

/// A vector field of position in `R^D` (body force, traction).
pub type FieldOf<'a, const D: usize> = &'a (dyn Fn(PointD<D>) -> VectorD<D> + Sync);

/// An element space on the cells of a mesh in `R^D`: what the assembly, the loads and the
/// post-processing of a body need from it. Implementations must be thread-safe: assembly calls
/// them from many threads at once.
pub trait MeshElement<const D: usize>: Send + Sync {
    /// A short name for reports (the registry name of a registered element).
    fn name(&self) -> &str;

    /// The local degrees of freedom of a cell.
    fn dof_layout(&self) -> DofLayout;

    /// Whether the element can be built on cell `cell`; the assembly checks every cell first,
    /// so that an element that cannot take, e.g., a vertex inserted on an edge fails early
    /// with the cell named.
    fn supports(&self, mesh: &dyn BodyMesh<D>, cell: usize) -> bool;

    /// The local stiffness of cell `cell`, split into consistency and stabilisation, in the
    /// local order of [`MeshElement::dof_layout`] over [`BodyMesh::cell_vertices`].
    fn stiffness(
        &self,
        mesh: &dyn BodyMesh<D>,
        cell: usize,
        material: &ElasticityTensor<D>,
    ) -> Result<LocalStiffness, SpaceError>;

    /// The local load vector of a body force `force` on cell `cell`.
    fn body_load(
        &self,
        mesh: &dyn BodyMesh<D>,
        cell: usize,
        force: FieldOf<'_, D>,
    ) -> Result<DVector<f64>, SpaceError>;

    /// The load of a traction `traction` on one boundary facet (an edge in 2D, a face in 3D)
    /// with vertices `facet`, on the facet's vertex values (interleaved by component), with
    /// `points` quadrature points per direction.
    fn facet_load(
        &self,
        facet: &[PointD<D>],
        traction: FieldOf<'_, D>,
        points: usize,
    ) -> Result<DVector<f64>, SpaceError>;

    /// The (constant) strain tensor of the projection `Pi u_h` on cell `cell`, from the local
    /// degrees of freedom `local`.
    fn strain(
        &self,
        mesh: &dyn BodyMesh<D>,
        cell: usize,
        local: &DVector<f64>,
    ) -> Result<SMatrix<f64, D, D>, SpaceError>;

    /// The strain of `Pi u_h` on cell `cell` (as [`MeshElement::strain`]) and the
    /// stabilisation energy `u' K_s u` of the local degrees of freedom `local` (`K_s` the
    /// stabilisation of [`MeshElement::stiffness`], the energy clamped at zero): what the error
    /// estimate needs of a cell. By default from [`MeshElement::strain`] and
    /// [`MeshElement::stiffness`].
    fn strain_and_stabilisation_energy(
        &self,
        mesh: &dyn BodyMesh<D>,
        cell: usize,
        material: &ElasticityTensor<D>,
        local: &DVector<f64>,
    ) -> Result<(SMatrix<f64, D, D>, f64), SpaceError> {
        let strain = self.strain(mesh, cell, local)?;
        let stiffness = self.stiffness(mesh, cell, material)?;
        Ok((
            strain,
            local.dot(&(&stiffness.stabilisation * local)).max(0.0),
        ))
    }

    /// The polygonal element behind this one, when it is one (`D = 2`): for the code that
    /// needs its energy projection as a polynomial (error norms).
    fn as_planar(&self) -> Option<&dyn ElementSpace> {
        None
    }

    /// The polyhedral element behind this one, when it is one (`D = 3`): for the code that
    /// needs its energy projection as a polynomial (error norms).
    fn as_polyhedral(&self) -> Option<&dyn PolyhedralElement> {
        None
    }
}

/// An [`ElementSpace`] on the polygons of a planar mesh: the [`MeshElement<2>`] of every 2D
/// element type.
#[derive(Clone)]
pub struct PlanarElement(Arc<dyn ElementSpace>);

impl PlanarElement {
    /// The element `element` on planar meshes.
    pub fn new(element: Arc<dyn ElementSpace>) -> Self {
        Self(element)
    }

    /// The polygonal element.
    pub fn element(&self) -> &Arc<dyn ElementSpace> {
        &self.0
    }

    fn polygon(mesh: &dyn BodyMesh<2>, cell: usize) -> Vec<Point> {
        let points = mesh.points();
        mesh.cell_vertices(cell)
            .iter()
            .map(|&v| points[v])
            .collect()
    }
}

impl fmt::Debug for PlanarElement {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_tuple("PlanarElement")
            .field(&self.0.name())
            .finish()
    }
}

impl MeshElement<2> for PlanarElement {
    fn name(&self) -> &str {
        self.0.name()
    }

    fn dof_layout(&self) -> DofLayout {
        self.0.dof_layout()
    }

    fn supports(&self, mesh: &dyn BodyMesh<2>, cell: usize) -> bool {
        self.0.supports(mesh.cell_vertices(cell).len())
    }

    fn stiffness(
        &self,
        mesh: &dyn BodyMesh<2>,
        cell: usize,
        material: &ElasticityTensor<2>,
    ) -> Result<LocalStiffness, SpaceError> {
        self.0.stiffness(&Self::polygon(mesh, cell), material)
    }

    fn body_load(
        &self,
        mesh: &dyn BodyMesh<2>,
        cell: usize,
        force: FieldOf<'_, 2>,
    ) -> Result<DVector<f64>, SpaceError> {
        self.0.body_load(&Self::polygon(mesh, cell), force)
    }

    fn facet_load(
        &self,
        facet: &[Point],
        traction: FieldOf<'_, 2>,
        points: usize,
    ) -> Result<DVector<f64>, SpaceError> {
        let [a, b] = facet else {
            return Err(SpaceError::DegeneratePolygon {
                vertices: facet.len(),
                reason: "a boundary facet in 2D is an edge of two vertices".into(),
            });
        };
        let load = edge_traction_load(*a, *b, &|x| traction(x), points)?;
        Ok(DVector::from_column_slice(&load))
    }

    fn strain(
        &self,
        mesh: &dyn BodyMesh<2>,
        cell: usize,
        local: &DVector<f64>,
    ) -> Result<SMatrix<f64, 2, 2>, SpaceError> {
        let projection = self.0.projection(&Self::polygon(mesh, cell))?;
        Ok(strain_tensor(&projection.strain(local)))
    }

    fn strain_and_stabilisation_energy(
        &self,
        mesh: &dyn BodyMesh<2>,
        cell: usize,
        material: &ElasticityTensor<2>,
        local: &DVector<f64>,
    ) -> Result<(SMatrix<f64, 2, 2>, f64), SpaceError> {
        let (strain, energy) =
            self.0
                .strain_and_stabilisation_energy(&Self::polygon(mesh, cell), material, local)?;
        Ok((strain_tensor(&strain), energy))
    }

    fn as_planar(&self) -> Option<&dyn ElementSpace> {
        Some(&*self.0)
    }
}

/// The strain tensor of a plane strain in Voigt notation `[xx, yy, 2 xy]`.
fn strain_tensor(e: &SMatrix<f64, 3, 1>) -> SMatrix<f64, 2, 2> {
    SMatrix::<f64, 2, 2>::new(e[0], 0.5 * e[2], 0.5 * e[2], e[1])
}
