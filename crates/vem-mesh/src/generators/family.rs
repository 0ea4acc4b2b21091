//! The mesh families by name, for command lines and convergence studies.

use std::fmt;
use std::str::FromStr;

use super::{
    cell_counts, hanging_nodes, hexagons, nonconvex, perturbed_quads, structured_quads,
    structured_triangles, voronoi, Rectangle,
};
use crate::{Mesh, MeshError};

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
    /// Centroidal Voronoi cells, n x round(n height / width) sites ([`voronoi`]; uses the seed).
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
