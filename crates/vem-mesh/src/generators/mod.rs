//! Reproducible mesh generators on a rectangle.
//!
//! Each generator is parameterised by a size `n` (a refinement family: the mesh size falls
//! like 1/n) and, where random, a seed (same seed, same mesh, bit for bit: the random numbers
//! come from a `ChaCha8Rng` seeded with the `u64`, and nothing depends on hash-map order).
//! Every generated mesh names the boundary parts "left", "right", "bottom" and "top" and is
//! validated like any other [`Mesh`].
//!
//! | family | function | cells |
//! | --- | --- | --- |
//! | quads | [`structured_quads`] | rectangles |
//! | triangles | [`structured_triangles`] | right triangles |
//! | hexagons | [`hexagons`] | honeycomb, pentagons and quadrilaterals on the boundary |
//! | voronoi | [`voronoi`] | centroidal Voronoi (Lloyd), short edges merged |
//! | perturbed | [`perturbed_quads`] | quadrilaterals with randomly moved nodes |
//! | nonconvex | [`nonconvex`] | chevrons (one reflex vertex each) |
//! | hanging | [`hanging_nodes`] | checkerboard of split squares, hanging nodes |
//!
//! Any family also meshes a simple polygon ([`PolygonDomain`], [`polygon_mesh`]): its mesh of
//! the polygon's bounding rectangle, cut by the polygon, boundary parts named after the
//! polygon's edges; the Voronoi family there makes a centroidal Voronoi mesh of the polygon by
//! reflected seeds instead ([`polygon_voronoi()`], PolyMesher's method), whose cells end on the
//! polygon's edges without being cut.
//!
//! [`MeshFamily`] names them all for command lines and convergence studies:
//!
//! ```
//! use vem_mesh::generators::{MeshFamily, Rectangle};
//! for family in MeshFamily::all() {
//!     let mesh = family.generate(&Rectangle::unit_square(), 4, 7)?;
//!     assert_eq!(family.name().parse::<MeshFamily>()?.name(), family.name());
//!     let area: f64 = (0..mesh.n_polygons()).map(|p| mesh.area(p)).sum();
//!     assert!((area - 1.0).abs() < 1e-12);
//! }
//! # Ok::<(), vem_mesh::MeshError>(())
//! ```

mod family;
mod hanging;
mod hexagons;
mod nonconvex;
mod perturbed;
pub mod polygon;
pub mod polygon_voronoi;
pub mod polyhedral;
mod structured;
mod voronoi;

pub use family::{MeshFamily, MeshSize};
pub use hanging::hanging_nodes;
pub use hexagons::hexagons;
pub use nonconvex::{nonconvex, CHEVRON_RISE};
pub use perturbed::perturbed_quads;
pub use polygon::{cut_to_polygon, polygon_mesh, PolygonDomain, MERGE_AREA_RATIO, SNAP_RATIO};
pub use polygon_voronoi::{polygon_voronoi, PolygonVoronoi, REFLECTION_RATIO};
pub use structured::{structured_quads, structured_triangles};
pub use voronoi::{voronoi, LLOYD_ITERATIONS, MAX_VORONOI_CELLS, SHORT_EDGE_RATIO};

use crate::{Mesh, MeshError, PartSpec, Point};

/// An axis-aligned rectangle [x0, x1] x [y0, y1].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rectangle {
    /// Lower-left corner.
    pub min: Point,
    /// Upper-right corner.
    pub max: Point,
}

impl Rectangle {
    /// The rectangle with corners `min` and `max`.
    pub fn new(min: Point, max: Point) -> Self {
        Self { min, max }
    }

    /// The unit square (0,1)^2.
    pub fn unit_square() -> Self {
        Self::new(Point::new(0.0, 0.0), Point::new(1.0, 1.0))
    }

    /// Width (x extent).
    pub fn width(&self) -> f64 {
        self.max.x - self.min.x
    }

    /// Height (y extent).
    pub fn height(&self) -> f64 {
        self.max.y - self.min.y
    }

    /// Checks that the rectangle has positive, finite extent.
    pub(crate) fn check(&self, generator: &'static str) -> Result<(), MeshError> {
        let ok = [self.min.x, self.min.y, self.max.x, self.max.y]
            .iter()
            .all(|c| c.is_finite())
            && self.width() > 0.0
            && self.height() > 0.0;
        if ok {
            Ok(())
        } else {
            Err(MeshError::BadGeneratorParameter {
                generator,
                reason: format!(
                    "the rectangle [{}, {}] x [{}, {}] must have positive finite extent",
                    self.min.x, self.max.x, self.min.y, self.max.y
                ),
            })
        }
    }
}

/// Builds a mesh on `rect` and names "left", "right", "bottom", "top" from the polygon edges
/// lying on each side of the rectangle (to a tolerance relative to its size).
///
/// In a partition of the rectangle, an edge with both end points on one side lies on that side
/// and is a boundary edge, so the parts are read off the polygon loops and the mesh is built
/// (and validated) once.
pub(crate) fn mesh_with_sides(
    rect: &Rectangle,
    vertices: Vec<Point>,
    polygons: &[Vec<usize>],
) -> Result<Mesh, MeshError> {
    let tol = 1e-9 * rect.width().max(rect.height());
    let on = |value: f64, side: f64| (value - side).abs() <= tol;
    let mut parts: Vec<PartSpec> = ["left", "right", "bottom", "top"]
        .iter()
        .map(|name| PartSpec::new(*name, Vec::new()))
        .collect();
    for polygon in polygons {
        let m = polygon.len();
        for k in 0..m {
            let (a, b) = (polygon[k], polygon[(k + 1) % m]);
            let (Some(pa), Some(pb)) = (vertices.get(a), vertices.get(b)) else {
                continue; // reported by the mesh constructor
            };
            let side = if on(pa.x, rect.min.x) && on(pb.x, rect.min.x) {
                0
            } else if on(pa.x, rect.max.x) && on(pb.x, rect.max.x) {
                1
            } else if on(pa.y, rect.min.y) && on(pb.y, rect.min.y) {
                2
            } else if on(pa.y, rect.max.y) && on(pb.y, rect.max.y) {
                3
            } else {
                continue;
            };
            parts[side].edges.push([a, b]);
        }
    }
    Mesh::from_polygons(vertices, polygons, parts)
}

/// Largest number of cells a generator agrees to make (about 10^8 vertices' worth of memory).
pub const MAX_CELLS: usize = 50_000_000;

/// Cells across and up for a lattice of about `n` >= 1 cells across `rect` with near-square
/// cells: (n, max(1, round(n * height / width))), at most [`MAX_CELLS`] in all.
pub(crate) fn cell_counts(
    generator: &'static str,
    rect: &Rectangle,
    n: usize,
) -> Result<(usize, usize), MeshError> {
    rect.check(generator)?;
    check_size(generator, n, 1)?;
    let ny = (n as f64 * rect.height() / rect.width()).round().max(1.0);
    let cells = n as f64 * ny;
    if cells > MAX_CELLS as f64 {
        return Err(MeshError::BadGeneratorParameter {
            generator,
            reason: format!(
                "size n = {n} asks for {cells:e} cells on this rectangle, more than {MAX_CELLS}"
            ),
        });
    }
    Ok((n, ny as usize))
}

/// Checks a size parameter n >= `min`.
pub(crate) fn check_size(generator: &'static str, n: usize, min: usize) -> Result<(), MeshError> {
    if n < min {
        return Err(MeshError::BadGeneratorParameter {
            generator,
            reason: format!("size n = {n} is too small; it must be at least {min}"),
        });
    }
    Ok(())
}
