//! Polygonal meshes for the lowest-order virtual element method.
//!
//! A [`Mesh`] holds vertex coordinates, polygons as counter-clockwise vertex loops (compact
//! offsets + indices storage), the edges derived from them with their one or two adjacent
//! polygons, and named boundary parts made of boundary edges. Hanging nodes are plain vertices:
//! a polygon may have collinear consecutive vertices. Every constructor validates.
//!
//! ```
//! use vem_mesh::{Mesh, PartSpec, Point};
//! let vertices = vec![
//!     Point::new(0.0, 0.0), Point::new(1.0, 0.0), Point::new(1.0, 1.0), Point::new(0.0, 1.0),
//! ];
//! let mesh = Mesh::from_polygons(vertices, &[vec![0, 1, 2, 3]], vec![])?;
//! assert_eq!(mesh.area(0), 1.0);
//! # Ok::<(), vem_mesh::MeshError>(())
//! ```
//!
//! # Cargo features
//!
//! The core (meshes, validation, geometry, quality, interface insertion, atomic file writes)
//! needs only `nalgebra`. The rest is behind features, all on by default; the library layers of
//! this workspace turn the defaults off and enable only what they use (the element layer uses
//! none of them):
//!
//! | feature | what it adds | extra dependencies |
//! | --- | --- | --- |
//! | `generators` | [`generators`]: structured, hexagonal, Voronoi, perturbed, ... meshes | `rand`, `rand_chacha` |
//! | `gmsh` | `io::read_gmsh`, `io::read_gmsh_bytes`, `io::read_msh_bytes`: Gmsh `.msh` 4.1 and 2.2 input; `io::read_gmsh_polyhedral`: 3D meshes of tetrahedra, hexahedra, prisms and pyramids | none |
//! | `vtu` | `io::write_vtu`, `io::write_polyhedral_vtu`, `io::UnstructuredGrid`, `io::PvdCollection`: VTK `.vtu` output (ASCII, binary, zlib; polygons and polyhedra) and `.pvd` collections; `io::read_vtu`, `io::read_legacy_vtk`, `io::read_vtk_mesh`: VTK input | `miniz_oxide`, `roxmltree` |
//! | `svg` | `io::write_svg`, `io::write_svg_layers`: SVG pictures of meshes (large ones with an embedded PNG) | `miniz_oxide`, `adler2` |
//!
//! `io::read_polymesher` (PolyMesher/mVEM meshes exported as text) needs no feature.
//!
//! # Polyhedral meshes
//!
//! [`PolyhedralMesh`] (module [`polyhedral`]) is the three-dimensional counterpart: vertices in
//! space, polygonal faces stored once with their one or two cells, cells as lists of oriented
//! faces, derived edges and named boundary parts made of boundary faces; its generators (hexahedra,
//! tetrahedra, perturbed hexahedra, Voronoi, non-convex prisms, octree cubes with hanging nodes)
//! are in `generators::polyhedral` behind the `generators` feature. It is the [`BodyMesh<3>`]
//! of a body in space.
#![deny(missing_docs)]

mod body_mesh;
mod error;
pub mod expression;
#[cfg(feature = "generators")]
pub mod generators;
pub mod geometry;
pub mod interface;
pub mod io;
mod mesh;
pub mod polyhedral;
pub mod quality;
pub mod refine;
pub mod validate;

pub use body_mesh::{morton_key, BodyMesh, PointD, VectorD};
pub use error::MeshError;
pub use interface::{
    boundary_chain, insert_interface_nodes, ChainNode, Interface, InterfaceOptions, InterfacePair,
};
pub use mesh::{BoundaryPart, Edge, Mesh, PartSpec};
pub use polyhedral::overlay::{
    boundary_surface, insert_surface_overlay, SurfaceInterface, SurfaceNode, SurfacePair,
};
pub use polyhedral::{FaceCells, FacePart, FacePartSpec, OrientedFace, PolyhedralMesh};

/// A point of the plane.
pub type Point = nalgebra::Point2<f64>;
/// A vector of the plane.
pub type Vector = nalgebra::Vector2<f64>;

/// A point of space (the vertices of a [`PolyhedralMesh`]).
pub type Point3 = nalgebra::Point3<f64>;
/// A vector of space.
pub type Vector3 = nalgebra::Vector3<f64>;
