//! Polyhedral meshes: the mesh layer of the three-dimensional virtual element method.
//!
//! * [`PolyhedralMesh`]: vertices in space, polygonal faces stored once with their one or two
//!   cells, cells as lists of oriented faces, derived edges with the faces around them, named
//!   boundary parts made of boundary faces; every constructor validates;
//! * [`geometry`]: face vector areas, normals, centroids and vertex weights of the fan
//!   triangulation, volumes and centroids of polyhedra by the divergence theorem;
//! * [`validate`]: the checks every mesh passes, each failure a located [`crate::MeshError`];
//! * [`overlay`]: the surface overlay that makes two facing boundary parts node-to-node
//!   (interface insertion in three dimensions);
//! * [`quality`]: the shape-regularity figures (star-shaped ball, shortest edge, smallest face,
//!   face discs, warping) per cell and over a mesh.
//!
//! Generators (hexahedra, tetrahedra, perturbed hexahedra, Voronoi polyhedra, non-convex prisms,
//! octree cubes with hanging nodes) are in `generators::polyhedral` (feature `generators`).

pub mod geometry;
mod mesh;
pub mod overlay;
pub mod quality;
pub mod validate;

#[cfg(feature = "generators")]
pub(crate) use mesh::CellsBuilder;
pub use mesh::{FaceCells, FacePart, FacePartSpec, OrientedFace, PolyhedralMesh};
