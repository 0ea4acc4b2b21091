//! The mesh families by name, for command lines and convergence studies.

use std::fmt;
use std::str::FromStr;

use super::voronoi::voronoi_counts;
use super::{
    cell_counts, hanging_nodes, hexagons, nonconvex, perturbed_quads, structured_quads,
    structured_triangles, voronoi, Rectangle, MAX_CELLS,
};
use crate::{Mesh, MeshError};

/// The size of a mesh before it is generated ([`MeshFamily::size`]): upper bounds of its
/// counts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MeshSize {
    /// Polygons.
    pub polygons: usize,
    /// Vertices.
    pub vertices: usize,
    /// Polygon corners: the sum over the polygons of their numbers of vertices.
    pub corners: usize,
}

/// A family of meshes of a rectangle, refined by a size n (h ~ 1/n).
///
/// Names (for [`FromStr`] and [`MeshFamily::name`]): "quads", "triangles", "hexagons",
/// "voronoi", "perturbed" (distortion [`MeshFamily::DEFAULT_DISTORTION`]; "perturbed:0.4"
/// chooses another), "nonconvex", "hanging". [`fmt::Display`] writes a name that parses back
/// to the same family.
///
/// ```
/// use vem_mesh::generators::{MeshFamily, Rectangle};
/// let family: MeshFamily = "perturbed:0.2".parse()?;
/// assert_eq!(family, MeshFamily::PerturbedQuads { distortion: 0.2 });
/// assert_eq!(family.to_string().parse::<MeshFamily>()?, family);
/// let mesh = family.generate(&Rectangle::unit_square(), 8, 1)?;
/// assert_eq!(mesh.n_polygons(), 64);
/// assert!("pentagons".parse::<MeshFamily>().is_err());
/// # Ok::<(), vem_mesh::MeshError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum MeshFamily {
    /// Structured rectangles, n x round(n height / width) ([`structured_quads`]).
    Quads,
    /// Structured right triangles, two per rectangle ([`structured_triangles`]).
    Triangles,
    /// A clipped honeycomb, n hexagons across ([`hexagons`]).
    Hexagons,
    /// Centroidal Voronoi cells, n x round(n height / width) sites ([`voronoi`]; uses the seed);
    /// on a polygon, seeds reflected across its edges ([`super::polygon_voronoi()`]).
    Voronoi,
    /// Rectangles with randomly moved nodes ([`perturbed_quads`]; uses the seed).
    PerturbedQuads {
        /// Largest move as a fraction of the cell size, in [0, 0.5).
        distortion: f64,
    },
    /// Chevron cells, non-convex and star-shaped ([`nonconvex`]).
    NonConvex,
    /// A checkerboard of split squares with hanging nodes ([`hanging_nodes`]).
    HangingNodes,
}

impl MeshFamily {
    /// The distortion of "perturbed" when none is given.
    pub const DEFAULT_DISTORTION: f64 = 0.3;

    /// Every family once (perturbed with [`Self::DEFAULT_DISTORTION`]).
    pub fn all() -> [MeshFamily; 7] {
        [
            MeshFamily::Quads,
            MeshFamily::Triangles,
            MeshFamily::Hexagons,
            MeshFamily::Voronoi,
            MeshFamily::PerturbedQuads {
                distortion: Self::DEFAULT_DISTORTION,
            },
            MeshFamily::NonConvex,
            MeshFamily::HangingNodes,
        ]
    }

    /// The family's name ("quads", "triangles", "hexagons", "voronoi", "perturbed",
    /// "nonconvex", "hanging").
    pub fn name(&self) -> &'static str {
        match self {
            MeshFamily::Quads => "quads",
            MeshFamily::Triangles => "triangles",
            MeshFamily::Hexagons => "hexagons",
            MeshFamily::Voronoi => "voronoi",
            MeshFamily::PerturbedQuads { .. } => "perturbed",
            MeshFamily::NonConvex => "nonconvex",
            MeshFamily::HangingNodes => "hanging",
        }
    }

    /// True for the families whose meshes depend on the seed.
    pub fn is_random(&self) -> bool {
        matches!(
            self,
            MeshFamily::Voronoi | MeshFamily::PerturbedQuads { .. }
        )
    }

    /// How large the mesh of size `n` on `rect` will be, without generating it (an upper
    /// bound of each count, exact for the lattice families); the same parameter errors as
    /// [`MeshFamily::generate`], so that a caller can refuse a mesh larger than its memory
    /// before any of it is allocated.
    ///
    /// ```
    /// use vem_mesh::generators::{MeshFamily, Rectangle};
    /// let rect = Rectangle::unit_square();
    /// let size = MeshFamily::Quads.size(&rect, 8)?;
    /// let mesh = MeshFamily::Quads.generate(&rect, 8, 1)?;
    /// assert_eq!((size.polygons, size.vertices, size.corners), (64, 81, 256));
    /// assert_eq!(mesh.n_vertices(), size.vertices);
    /// # Ok::<(), vem_mesh::MeshError>(())
    /// ```
    pub fn size(&self, rect: &Rectangle, n: usize) -> Result<MeshSize, MeshError> {
        let lattice = |name| cell_counts(name, rect, n).map(|(nx, ny)| (nx as f64, ny as f64));
        let (polygons, vertices, corners) = match *self {
            MeshFamily::Quads | MeshFamily::PerturbedQuads { .. } => {
                let (nx, ny) = lattice("structured_quads")?;
                (nx * ny, (nx + 1.0) * (ny + 1.0), 4.0 * nx * ny)
            }
            MeshFamily::Triangles => {
                let (nx, ny) = lattice("structured_triangles")?;
                (2.0 * nx * ny, (nx + 1.0) * (ny + 1.0), 6.0 * nx * ny)
            }
            MeshFamily::Hexagons => {
                rect.check("hexagons")?;
                let n = n as f64;
                let m = (3f64.sqrt() * n * rect.height() / rect.width())
                    .round()
                    .max(1.0);
                if n * m > 2.0 * MAX_CELLS as f64 {
                    return Err(MeshError::BadGeneratorParameter {
                        generator: "hexagons",
                        reason: format!(
                            "size n = {n} asks for more than {MAX_CELLS} cells on this rectangle"
                        ),
                    });
                }
                let cells = (n + 1.0) * (m + 1.0);
                (cells, 2.0 * cells + 2.0 * (n + m) + 4.0, 6.0 * cells)
            }
            MeshFamily::Voronoi => {
                let (nx, ny) = voronoi_counts(rect, n)?;
                let (nx, ny) = (nx as f64, ny as f64);
                let cells = nx * ny;
                (
                    cells,
                    2.0 * cells + 2.0 * (nx + ny) + 4.0,
                    6.0 * cells + 2.0 * (nx + ny),
                )
            }
            MeshFamily::NonConvex => {
                let (nx, ny) = lattice("nonconvex")?;
                let cells = nx * ny;
                (cells, (nx + 1.0) * (ny + 1.0) + nx * ny, 6.0 * cells)
            }
            MeshFamily::HangingNodes => {
                let (nx, ny) = lattice("hanging_nodes")?;
                let cells = nx * ny;
                (
                    4.0 * cells,
                    (2.0 * nx + 1.0) * (2.0 * ny + 1.0),
                    16.0 * cells,
                )
            }
        };
        Ok(MeshSize {
            polygons: polygons as usize,
            vertices: vertices as usize,
            corners: corners as usize,
        })
    }

    /// The mesh of size `n` of this family on `rect` (`seed` is used by the random families
    /// only).
    pub fn generate(&self, rect: &Rectangle, n: usize, seed: u64) -> Result<Mesh, MeshError> {
        match *self {
            MeshFamily::Quads => {
                let (nx, ny) = cell_counts("structured_quads", rect, n)?;
                structured_quads(rect, nx, ny)
            }
            MeshFamily::Triangles => {
                let (nx, ny) = cell_counts("structured_triangles", rect, n)?;
                structured_triangles(rect, nx, ny)
            }
            MeshFamily::Hexagons => hexagons(rect, n),
            MeshFamily::Voronoi => voronoi(rect, n, seed),
            MeshFamily::PerturbedQuads { distortion } => perturbed_quads(rect, n, distortion, seed),
            MeshFamily::NonConvex => nonconvex(rect, n),
            MeshFamily::HangingNodes => hanging_nodes(rect, n),
        }
    }
}

impl fmt::Display for MeshFamily {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            MeshFamily::PerturbedQuads { distortion } if distortion != Self::DEFAULT_DISTORTION => {
                write!(f, "perturbed:{distortion}")
            }
            _ => f.write_str(self.name()),
        }
    }
}

impl FromStr for MeshFamily {
    type Err = MeshError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let bad = |reason: String| MeshError::BadGeneratorParameter {
            generator: "MeshFamily",
            reason,
        };
        let (name, parameter) = match s.trim().split_once(':') {
            Some((name, parameter)) => (name.trim(), Some(parameter.trim())),
            None => (s.trim(), None),
        };
        if let Some(family) = MeshFamily::all().into_iter().find(|f| f.name() == name) {
            return match (family, parameter) {
                (MeshFamily::PerturbedQuads { .. }, Some(value)) => {
                    let distortion: f64 = value.parse().map_err(|_| {
                        bad(format!("'{value}' in '{s}' is not a number (a distortion)"))
                    })?;
                    if !(0.0..0.5).contains(&distortion) {
                        return Err(bad(format!("distortion {distortion} must lie in [0, 0.5)")));
                    }
                    Ok(MeshFamily::PerturbedQuads { distortion })
                }
                (_, Some(_)) => Err(bad(format!("family '{name}' takes no parameter ('{s}')"))),
                (family, None) => Ok(family),
            };
        }
        let names: Vec<&str> = MeshFamily::all().iter().map(MeshFamily::name).collect();
        Err(bad(format!(
            "unknown mesh family '{name}'; expected one of {}",
            names.join(", ")
        )))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Point;

    /// The size announced before generating bounds the mesh generated, for every family, on
    /// a square and on a wide rectangle; the lattice families' counts are exact.
    #[test]
    fn size_bounds_the_generated_mesh() {
        let rects = [
            Rectangle::unit_square(),
            Rectangle::new(Point::new(-1.0, 0.0), Point::new(2.0, 0.5)),
        ];
        for rect in &rects {
            for family in MeshFamily::all() {
                for n in [1, 3, 8] {
                    let size = family.size(rect, n).unwrap();
                    let mesh = family.generate(rect, n, 7).unwrap();
                    let corners: usize =
                        (0..mesh.n_polygons()).map(|p| mesh.polygon(p).len()).sum();
                    let what = format!("{family} n = {n} on {rect:?}");
                    assert!(mesh.n_polygons() <= size.polygons, "{what}: {size:?}");
                    assert!(mesh.n_vertices() <= size.vertices, "{what}: {size:?}");
                    assert!(corners <= size.corners, "{what}: {size:?} {corners}");
                    if matches!(family, MeshFamily::Quads | MeshFamily::Triangles) {
                        assert_eq!(mesh.n_polygons(), size.polygons, "{what}");
                        assert_eq!(mesh.n_vertices(), size.vertices, "{what}");
                    }
                }
            }
        }
    }

    /// A tall rectangle with a modest n asks the Voronoi generator for 8.1e6 cells: refused
    /// at once, by `size` and by `generate`, naming the count.
    #[test]
    fn voronoi_refuses_too_many_cells_at_once() {
        let tall = Rectangle::new(Point::new(0.0, 0.0), Point::new(1.0, 1e5));
        let size = MeshFamily::Voronoi.size(&tall, 9).unwrap_err().to_string();
        assert!(size.contains("8100000 cells"), "{size}");
        let generate = MeshFamily::Voronoi.generate(&tall, 9, 1).unwrap_err();
        assert_eq!(generate.to_string(), size);
        // Quads on the same rectangle are only counted (8.1e6 <= MAX_CELLS).
        let quads = MeshFamily::Quads.size(&tall, 9).unwrap();
        assert_eq!(quads.polygons, 9 * 900_000);
    }
}
