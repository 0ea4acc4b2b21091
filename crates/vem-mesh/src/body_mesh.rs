//! The mesh of one body as the layers above see it, whatever the dimension.
//!
//! The element, assembly, boundary-condition and contact layers are written once for `d = 2`
//! and `d = 3`: they see a mesh through [`BodyMesh<D>`] (vertices as points of `R^D`, cells as
//! lists of vertices, named boundary parts made of facets: edges in 2D, faces in 3D). What
//! differs with the dimension (the cell's geometry as the element needs it, interface
//! insertion) is reached through the concrete mesh type ([`BodyMesh::as_planar`]).
//!
//! ```
//! use vem_mesh::generators::{structured_quads, Rectangle};
//! use vem_mesh::BodyMesh;
//! let mesh = structured_quads(&Rectangle::unit_square(), 2, 2)?;
//! let body: &dyn BodyMesh<2> = &mesh;
//! assert_eq!((body.n_vertices(), body.n_cells()), (9, 4));
//! assert_eq!(body.part_vertices("bottom")?, vec![0, 1, 2]);
//! // The facets of a part are its boundary edges, oriented with the body on their left.
//! assert_eq!(body.part_facets("bottom")?, vec![[0, 1].as_slice(), [1, 2].as_slice()]);
//! # Ok::<(), vem_mesh::MeshError>(())
//! ```

use std::fmt;

use crate::quality::ElementQuality;
use crate::{Mesh, MeshError};

/// A point of `R^D`.
pub type PointD<const D: usize> = nalgebra::Point<f64, D>;
/// A vector of `R^D`.
pub type VectorD<const D: usize> = nalgebra::SVector<f64, D>;

mod sealed {
    pub trait Sealed {}
    impl Sealed for crate::Mesh {}
}

/// The mesh of one body in `R^D`: what assembly, boundary conditions and contact need,
/// independent of the dimension.
///
/// Implemented by this crate's mesh types only ([`Mesh`] for `D = 2`); code that needs the
/// concrete geometry of a cell (the element) reaches it through [`BodyMesh::as_planar`].
pub trait BodyMesh<const D: usize>: Send + Sync + fmt::Debug + sealed::Sealed {
    /// Number of vertices.
    fn n_vertices(&self) -> usize;

    /// All vertex coordinates.
    fn points(&self) -> &[PointD<D>];

    /// Number of cells (polygons in 2D, polyhedra in 3D).
    fn n_cells(&self) -> usize;

    /// The vertices of cell `c`, in the order in which the element numbers its local vertex
    /// degrees of freedom (in 2D the counter-clockwise loop).
    fn cell_vertices(&self, c: usize) -> &[usize];

    /// The names of the boundary parts.
    fn part_names(&self) -> Vec<String>;

    /// The distinct vertices of part `name`, sorted by index; an unknown name is an error that
    /// lists the parts.
    fn part_vertices(&self, name: &str) -> Result<Vec<usize>, MeshError>;

    /// The boundary facets of part `name` (edges in 2D, faces in 3D), each as its vertex loop
    /// oriented with the body on its left in 2D (outward normal to the right of the edge) and
    /// counter-clockwise seen from outside in 3D.
    fn part_facets(&self, name: &str) -> Result<Vec<&[usize]>, MeshError>;

    /// The mesh size `h`: the largest cell diameter.
    fn mesh_size(&self) -> f64;

    /// The shape-regularity figures (assumption A1) of cell `c`.
    fn cell_quality(&self, c: usize) -> ElementQuality;

    /// The polygonal mesh, when this is one (`D = 2`).
    fn as_planar(&self) -> Option<&Mesh> {
        None
    }
}

impl BodyMesh<2> for Mesh {
    fn n_vertices(&self) -> usize {
        Mesh::n_vertices(self)
    }

    fn points(&self) -> &[PointD<2>] {
        self.vertices()
    }

    fn n_cells(&self) -> usize {
        self.n_polygons()
    }

    fn cell_vertices(&self, c: usize) -> &[usize] {
        self.polygon(c)
    }

    fn part_names(&self) -> Vec<String> {
        Mesh::part_names(self)
    }

    fn part_vertices(&self, name: &str) -> Result<Vec<usize>, MeshError> {
        Mesh::part_vertices(self, name)
    }

    fn part_facets(&self, name: &str) -> Result<Vec<&[usize]>, MeshError> {
        let part = self.part(name)?;
        Ok(part
            .edges
            .iter()
            .map(|&e| self.edge(e).vertices.as_slice())
            .collect())
    }

    fn mesh_size(&self) -> f64 {
        Mesh::mesh_size(self)
    }

    fn cell_quality(&self, c: usize) -> ElementQuality {
        self.element_quality(c)
    }

    fn as_planar(&self) -> Option<&Mesh> {
        Some(self)
    }
}
