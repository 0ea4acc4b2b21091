//! The mesh of one body as the layers above see it, whatever the dimension.
//!
//! The element, assembly, boundary-condition and contact layers are written once for `d = 2`
//! and `d = 3`: they see a mesh through [`BodyMesh<D>`] (vertices as points of `R^D`, cells as
//! lists of vertices, named boundary parts made of facets: edges in 2D, faces in 3D). What
//! differs with the dimension (the cell's geometry as the element needs it, interface
//! insertion) is reached through the concrete mesh type ([`BodyMesh::as_planar`],
//! [`BodyMesh::as_polyhedral`]).
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
use crate::{Mesh, MeshError, PolyhedralMesh};

/// A point of `R^D`.
pub type PointD<const D: usize> = nalgebra::Point<f64, D>;
/// A vector of `R^D`.
pub type VectorD<const D: usize> = nalgebra::SVector<f64, D>;

/// The position of `point` along the Morton (Z-order) curve of the box from `min` spanning
/// `extent` (every component positive): 16 bits per coordinate, interleaved from the most
/// significant, x in the lowest bit. Points sorted by it lie near their neighbours in the
/// sequence, the numbering the Gmsh reader gives cells and the order assembly visits them in.
/// A point outside the box counts as on its nearest side (a coordinate that is not a number
/// as on its lower side). For `D` up to 4 (the key's 64 bits).
///
/// ```
/// use vem_mesh::{morton_key, PointD, VectorD};
/// let (min, extent) = (PointD::<2>::new(0.0, 0.0), VectorD::<2>::new(1.0, 1.0));
/// let key = |x, y| morton_key(&PointD::<2>::new(x, y), &min, &extent);
/// // The lower left quarter, then the lower right, the upper left and the upper right.
/// assert!(key(0.2, 0.2) < key(0.7, 0.2));
/// assert!(key(0.7, 0.2) < key(0.2, 0.7));
/// assert!(key(0.2, 0.7) < key(0.7, 0.7));
/// ```
pub fn morton_key<const D: usize>(point: &PointD<D>, min: &PointD<D>, extent: &VectorD<D>) -> u64 {
    const BITS: usize = 16;
    const {
        assert!(
            D * BITS <= 64,
            "a Morton key of 64 bits holds up to 4 coordinates"
        )
    };
    let cells = ((1u64 << BITS) - 1) as f64;
    let scaled = (point - min)
        .component_div(extent)
        .map(|t| (t.clamp(0.0, 1.0) * cells) as u64);
    let mut key = 0u64;
    for b in (0..BITS).rev() {
        for k in (0..D).rev() {
            key = (key << 1) | ((scaled[k] >> b) & 1);
        }
    }
    key
}

mod sealed {
    pub trait Sealed {}
    impl Sealed for crate::Mesh {}
    impl Sealed for crate::PolyhedralMesh {}
}

/// The mesh of one body in `R^D`: what assembly, boundary conditions and contact need,
/// independent of the dimension.
///
/// Implemented by this crate's mesh types only ([`Mesh`] for `D = 2`, [`PolyhedralMesh`] for
/// `D = 3`); code that needs the concrete geometry of a cell (the element) reaches it through
/// [`BodyMesh::as_planar`] or [`BodyMesh::as_polyhedral`].
pub trait BodyMesh<const D: usize>: Send + Sync + fmt::Debug + sealed::Sealed {
    /// Number of vertices.
    fn n_vertices(&self) -> usize;

    /// All vertex coordinates.
    fn points(&self) -> &[PointD<D>];

    /// Number of cells (polygons in 2D, polyhedra in 3D).
    fn n_cells(&self) -> usize;

    /// The vertices of cell `c`, in the order in which the element numbers its local vertex
    /// degrees of freedom (in 2D the counter-clockwise loop, in 3D the distinct vertices of
    /// the cell's faces in increasing order: [`PolyhedralMesh::cell_vertices`]).
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

    /// The polyhedral mesh, when this is one (`D = 3`).
    fn as_polyhedral(&self) -> Option<&PolyhedralMesh> {
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

impl BodyMesh<3> for PolyhedralMesh {
    fn n_vertices(&self) -> usize {
        PolyhedralMesh::n_vertices(self)
    }

    fn points(&self) -> &[PointD<3>] {
        self.vertices()
    }

    fn n_cells(&self) -> usize {
        PolyhedralMesh::n_cells(self)
    }

    fn cell_vertices(&self, c: usize) -> &[usize] {
        PolyhedralMesh::cell_vertices(self, c)
    }

    fn part_names(&self) -> Vec<String> {
        PolyhedralMesh::part_names(self)
    }

    fn part_vertices(&self, name: &str) -> Result<Vec<usize>, MeshError> {
        PolyhedralMesh::part_vertices(self, name)
    }

    /// The part's boundary faces, each as its stored loop: oriented out of the domain
    /// (counter-clockwise seen from outside).
    fn part_facets(&self, name: &str) -> Result<Vec<&[usize]>, MeshError> {
        Ok(self
            .part_faces(name)?
            .iter()
            .map(|&f| self.face(f))
            .collect())
    }

    fn mesh_size(&self) -> f64 {
        PolyhedralMesh::mesh_size(self)
    }

    /// The polyhedral figures of [`PolyhedralMesh::cell_quality`] in the planar record: the
    /// star-shaped ratio, and as "shortest edge" the smallest of the shortest-edge, smallest-face
    /// and face star-shaped ratios, so that [`ElementQuality::gamma`] is the cell's
    /// [`crate::polyhedral::quality::CellQuality::gamma`].
    fn cell_quality(&self, c: usize) -> ElementQuality {
        let q = PolyhedralMesh::cell_quality(self, c);
        ElementQuality {
            diameter: q.diameter,
            shortest_edge_ratio: q
                .shortest_edge_ratio
                .min(q.smallest_face_ratio)
                .min(q.face_star_ratio),
            star_ratio: q.star_ratio,
        }
    }

    fn as_polyhedral(&self) -> Option<&PolyhedralMesh> {
        Some(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{FacePartSpec, Point3};

    /// Two unit cubes side by side along x; parts "left" (x = 0) and "right" (x = 2).
    fn two_cubes() -> PolyhedralMesh {
        let mut vertices = Vec::new();
        for z in 0..2 {
            for y in 0..2 {
                for x in 0..3 {
                    vertices.push(Point3::new(x as f64, y as f64, z as f64));
                }
            }
        }
        let cube = |x: usize| {
            let v = |dx: usize, dy: usize, dz: usize| x + dx + 3 * dy + 6 * dz;
            vec![
                vec![v(0, 0, 0), v(0, 0, 1), v(0, 1, 1), v(0, 1, 0)],
                vec![v(1, 0, 0), v(1, 1, 0), v(1, 1, 1), v(1, 0, 1)],
                vec![v(0, 0, 0), v(1, 0, 0), v(1, 0, 1), v(0, 0, 1)],
                vec![v(0, 1, 0), v(0, 1, 1), v(1, 1, 1), v(1, 1, 0)],
                vec![v(0, 0, 0), v(0, 1, 0), v(1, 1, 0), v(1, 0, 0)],
                vec![v(0, 0, 1), v(1, 0, 1), v(1, 1, 1), v(0, 1, 1)],
            ]
        };
        let parts = vec![
            FacePartSpec::new("left", vec![vec![0, 6, 9, 3]]),
            FacePartSpec::new("right", vec![vec![2, 5, 11, 8]]),
        ];
        PolyhedralMesh::from_polyhedra(vertices, &[cube(0), cube(1)], parts).unwrap()
    }

    #[test]
    fn a_polyhedral_mesh_is_a_body_mesh_in_three_dimensions() {
        let mesh = two_cubes();
        let body: &dyn BodyMesh<3> = &mesh;
        assert_eq!((body.n_vertices(), body.n_cells()), (12, 2));
        assert_eq!(body.cell_vertices(1), &[1, 2, 4, 5, 7, 8, 10, 11]);
        assert_eq!(body.part_names(), ["left", "right"]);
        assert_eq!(body.part_vertices("right").unwrap(), vec![2, 5, 8, 11]);
        assert!((body.mesh_size() - 3f64.sqrt()).abs() < 1e-15);
        assert!(body.as_planar().is_none());
        assert!(std::ptr::eq(body.as_polyhedral().unwrap(), &mesh));
        // A part's facets are its faces, oriented out of the domain: the normal of "right"
        // is +x, that of "left" -x.
        for (name, outward) in [("left", -1.0), ("right", 1.0)] {
            let facets = body.part_facets(name).unwrap();
            assert_eq!(facets.len(), 1);
            let points: Vec<Point3> = facets[0].iter().map(|&v| body.points()[v]).collect();
            let normal = crate::polyhedral::geometry::face_normal(&points);
            assert!((normal.x - outward).abs() < 1e-15, "{name}: {normal}");
        }
        // The quality of a unit cube: star radius 1/2 over the diameter sqrt 3.
        let q = body.cell_quality(0);
        assert!((q.star_ratio - 0.5 / 3f64.sqrt()).abs() < 1e-12);
        assert!((q.gamma() - mesh.cell_quality(0).gamma()).abs() < 1e-15);
        let err = body.part_facets("top").unwrap_err();
        assert!(matches!(err, MeshError::UnknownPart { .. }), "{err}");
    }
}
