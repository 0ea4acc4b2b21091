//! Reproducible polyhedral mesh generators on a box [x0, x1] x [y0, y1] x [z0, z1].
//!
//! Each generator is parameterised by a size `n` (about `n` cells across the x extent; the
//! other directions get `round(n * extent / x extent)` cells, at least one, so that cells are
//! near cubes) and, where random, a seed (same seed, same mesh, bit for bit: the random numbers
//! come from a `ChaCha8Rng` seeded with the `u64`, and nothing depends on hash-map order or on
//! the number of threads).
//!
//! Every generated mesh names six boundary parts, one per side of the box:
//!
//! | part | side | outward normal |
//! | --- | --- | --- |
//! | `left` | x = x0 | -x |
//! | `right` | x = x1 | +x |
//! | `front` | y = y0 | -y |
//! | `back` | y = y1 | +y |
//! | `bottom` | z = z0 | -z |
//! | `top` | z = z1 | +z |
//!
//! (z is up, as gravity and contact problems usually have it; the two-dimensional generators'
//! `bottom` and `top` are their y sides, which become `front` and `back` when a planar mesh is
//! extruded by [`extrude`].)
//!
//! | family | function | cells |
//! | --- | --- | --- |
//! | hexahedra | [`hexahedra`] | cubes (boxes) of a structured lattice |
//! | tetrahedra | [`tetrahedra`] | each lattice box cut into 6 tetrahedra (Kuhn) |
//! | perturbed-hexahedra | [`perturbed_hexahedra`] | hexahedra with randomly moved vertices, warped faces |
//! | voronoi | [`voronoi_polyhedra`] | centroidal Voronoi polyhedra clipped to the box |
//! | nonconvex | [`nonconvex_prisms`] | chevron prisms (one reflex edge each) |
//! | octree | [`octree_hexahedra`] | a checkerboard of cubes split in 8: hanging nodes |
//!
//! [`PolyhedralFamily`] names them for command lines and studies:
//!
//! ```
//! use vem_mesh::generators::polyhedral::{Cuboid, PolyhedralFamily};
//! for family in PolyhedralFamily::all() {
//!     let mesh = family.generate(&Cuboid::unit_cube(), 3, 7)?;
//!     assert_eq!(family.name().parse::<PolyhedralFamily>()?.name(), family.name());
//!     let volume: f64 = (0..mesh.n_cells()).map(|c| mesh.volume(c)).sum();
//!     assert!((volume - 1.0).abs() < 1e-12);
//!     assert_eq!(mesh.euler_characteristic(), 1);
//! }
//! # Ok::<(), vem_mesh::MeshError>(())
//! ```

mod family;
mod nonconvex;
mod octree;
mod structured;
mod voronoi;

pub use family::PolyhedralFamily;
pub use nonconvex::{extrude, nonconvex_prisms};
pub use octree::octree_hexahedra;
pub use structured::{hexahedra, perturbed_hexahedra, tetrahedra};
pub use voronoi::{
    voronoi_polyhedra, EXACT_MERGE_RATIO, MAX_VORONOI_POLYHEDRA, SHORT_EDGE_RATIO_3D,
    VORONOI_LLOYD_ITERATIONS,
};

use crate::polyhedral::CellsBuilder;
use crate::{FacePart, MeshError, Point3, PolyhedralMesh, Vector3};

/// An axis-aligned box [x0, x1] x [y0, y1] x [z0, z1].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cuboid {
    /// Corner with the smallest coordinates.
    pub min: Point3,
    /// Corner with the largest coordinates.
    pub max: Point3,
}

/// Names of the box sides, in the order x0, x1, y0, y1, z0, z1.
pub const SIDE_NAMES: [&str; 6] = ["left", "right", "front", "back", "bottom", "top"];

impl Cuboid {
    /// The box with corners `min` and `max`.
    pub fn new(min: Point3, max: Point3) -> Self {
        Self { min, max }
    }

    /// The unit cube (0, 1)^3.
    pub fn unit_cube() -> Self {
        Self::new(Point3::origin(), Point3::new(1.0, 1.0, 1.0))
    }

    /// Extents along x, y and z.
    pub fn extent(&self) -> Vector3 {
        self.max - self.min
    }

    /// Volume.
    pub fn volume(&self) -> f64 {
        let e = self.extent();
        e.x * e.y * e.z
    }

    /// Checks that the box has positive, finite extent.
    pub(crate) fn check(&self, generator: &'static str) -> Result<(), MeshError> {
        let e = self.extent();
        let ok = self
            .min
            .iter()
            .chain(self.max.iter())
            .all(|c| c.is_finite())
            && e.iter().all(|&x| x > 0.0 && x.is_finite());
        if ok {
            Ok(())
        } else {
            Err(MeshError::BadGeneratorParameter {
                generator,
                reason: format!(
                    "the box [{}, {}] x [{}, {}] x [{}, {}] must have positive finite extent",
                    self.min.x, self.max.x, self.min.y, self.max.y, self.min.z, self.max.z
                ),
            })
        }
    }
}

/// Largest number of cells a polyhedral generator agrees to make (about 10^8 face corners'
/// worth of memory).
pub const MAX_POLYHEDRAL_CELLS: usize = 5_000_000;

/// Cells along x, y, z for about `n` >= 1 cells across the box: (n, round(n ey / ex),
/// round(n ez / ex)), each at least 1, at most `max_cells` in all.
pub(crate) fn box_counts(
    generator: &'static str,
    cuboid: &Cuboid,
    n: usize,
    max_cells: usize,
) -> Result<[usize; 3], MeshError> {
    cuboid.check(generator)?;
    super::check_size(generator, n, 1)?;
    let e = cuboid.extent();
    let count = |extent: f64| (n as f64 * extent / e.x).round().max(1.0);
    let (ny, nz) = (count(e.y), count(e.z));
    let cells = n as f64 * ny * nz;
    if cells > max_cells as f64 {
        return Err(MeshError::BadGeneratorParameter {
            generator,
            reason: format!(
                "size n = {n} asks for {cells:e} cells on this box, more than {max_cells}"
            ),
        });
    }
    Ok([n, ny as usize, nz as usize])
}

/// Coordinate k of `count` equal steps from `min` to `max`, exact at both ends.
pub(crate) fn step(k: usize, count: usize, min: f64, max: f64) -> f64 {
    if k == count {
        max
    } else {
        min + (max - min) * k as f64 / count as f64
    }
}

/// Vertices of an (nx + 1) x (ny + 1) x (nz + 1) lattice on the box; vertex (i, j, k) has
/// index i + (nx + 1) (j + (ny + 1) k).
pub(crate) fn lattice(cuboid: &Cuboid, [nx, ny, nz]: [usize; 3]) -> Vec<Point3> {
    let mut vertices = Vec::with_capacity((nx + 1) * (ny + 1) * (nz + 1));
    for k in 0..=nz {
        let z = step(k, nz, cuboid.min.z, cuboid.max.z);
        for j in 0..=ny {
            let y = step(j, ny, cuboid.min.y, cuboid.max.y);
            for i in 0..=nx {
                vertices.push(Point3::new(step(i, nx, cuboid.min.x, cuboid.max.x), y, z));
            }
        }
    }
    vertices
}

/// The outward faces of the box with corners `corner(dx, dy, dz)` (dx, dy, dz in {0, 1}), in
/// the order of [`SIDE_NAMES`].
pub(crate) fn box_faces<T: Copy>(corner: impl Fn(usize, usize, usize) -> T) -> [[T; 4]; 6] {
    let c = corner;
    [
        [c(0, 0, 0), c(0, 0, 1), c(0, 1, 1), c(0, 1, 0)],
        [c(1, 0, 0), c(1, 1, 0), c(1, 1, 1), c(1, 0, 1)],
        [c(0, 0, 0), c(1, 0, 0), c(1, 0, 1), c(0, 0, 1)],
        [c(0, 1, 0), c(0, 1, 1), c(1, 1, 1), c(1, 1, 0)],
        [c(0, 0, 0), c(0, 1, 0), c(1, 1, 0), c(1, 0, 0)],
        [c(0, 0, 1), c(1, 0, 1), c(1, 1, 1), c(0, 1, 1)],
    ]
}

/// Matches the cells' faces, names the six box sides from the boundary faces lying on each
/// (every vertex within 1e-9 of the box size of the side's plane) and builds the mesh.
pub(crate) fn mesh_with_box_sides(
    cuboid: &Cuboid,
    vertices: Vec<Point3>,
    builder: CellsBuilder,
) -> Result<PolyhedralMesh, MeshError> {
    let matched = builder.match_faces();
    let tol = 1e-9 * cuboid.extent().max();
    let mut parts: Vec<FacePart> = SIDE_NAMES
        .iter()
        .map(|name| FacePart::new(*name, Vec::new()))
        .collect();
    for f in matched.boundary_faces() {
        let face = matched.face(f);
        let Some(points) = face
            .iter()
            .map(|&v| vertices.get(v).copied())
            .collect::<Option<Vec<Point3>>>()
        else {
            continue; // reported by the mesh constructor
        };
        for (side, part) in parts.iter_mut().enumerate() {
            let axis = side / 2;
            let plane = if side % 2 == 0 {
                cuboid.min[axis]
            } else {
                cuboid.max[axis]
            };
            if points.iter().all(|p| (p[axis] - plane).abs() <= tol) {
                part.faces.push(f);
                break;
            }
        }
    }
    matched.build(vertices, parts)
}
