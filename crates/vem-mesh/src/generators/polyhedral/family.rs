//! The polyhedral mesh families by name.

use std::fmt;
use std::str::FromStr;

use super::{
    box_counts, hexahedra, nonconvex_prisms, octree_hexahedra, perturbed_hexahedra, tetrahedra,
    voronoi_polyhedra, Cuboid, MAX_POLYHEDRAL_CELLS,
};
use crate::{MeshError, PolyhedralMesh};

/// A family of polyhedral meshes of a box, refined by a size n (h ~ 1/n).
///
/// Names (for [`FromStr`] and [`PolyhedralFamily::name`]): "hexahedra", "tetrahedra",
/// "perturbed-hexahedra" (distortion [`PolyhedralFamily::DEFAULT_DISTORTION`];
/// "perturbed-hexahedra:0.1" chooses another), "voronoi", "nonconvex", "octree".
/// [`fmt::Display`] writes a name that parses back to the same family.
///
/// ```
/// use vem_mesh::generators::polyhedral::{Cuboid, PolyhedralFamily};
/// let family: PolyhedralFamily = "perturbed-hexahedra:0.1".parse()?;
/// assert_eq!(family, PolyhedralFamily::PerturbedHexahedra { distortion: 0.1 });
/// assert_eq!(family.to_string().parse::<PolyhedralFamily>()?, family);
/// let mesh = family.generate(&Cuboid::unit_cube(), 3, 1)?;
/// assert_eq!(mesh.n_cells(), 27);
/// assert!("prisms".parse::<PolyhedralFamily>().is_err());
/// # Ok::<(), vem_mesh::MeshError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PolyhedralFamily {
    /// Structured boxes, n x round(n ey / ex) x round(n ez / ex) ([`hexahedra`]).
    Hexahedra,
    /// Six Kuhn tetrahedra per box ([`tetrahedra`]).
    Tetrahedra,
    /// Hexahedra with randomly moved vertices and warped faces ([`perturbed_hexahedra`]; uses
    /// the seed).
    PerturbedHexahedra {
        /// Largest move as a fraction of the cell size, in [0, 0.25].
        distortion: f64,
    },
    /// Centroidal Voronoi polyhedra ([`voronoi_polyhedra`]; uses the seed).
    Voronoi,
    /// Chevron prisms, non-convex and star-shaped ([`nonconvex_prisms`]).
    NonConvex,
    /// A checkerboard of boxes split in eight, with hanging nodes ([`octree_hexahedra`]).
    Octree,
}

impl PolyhedralFamily {
    /// The distortion of "perturbed-hexahedra" when none is given.
    pub const DEFAULT_DISTORTION: f64 = 0.2;

    /// Every family once (perturbed with [`Self::DEFAULT_DISTORTION`]).
    pub fn all() -> [PolyhedralFamily; 6] {
        [
            PolyhedralFamily::Hexahedra,
            PolyhedralFamily::Tetrahedra,
            PolyhedralFamily::PerturbedHexahedra {
                distortion: Self::DEFAULT_DISTORTION,
            },
            PolyhedralFamily::Voronoi,
            PolyhedralFamily::NonConvex,
            PolyhedralFamily::Octree,
        ]
    }

    /// The family's name.
    pub fn name(&self) -> &'static str {
        match self {
            PolyhedralFamily::Hexahedra => "hexahedra",
            PolyhedralFamily::Tetrahedra => "tetrahedra",
            PolyhedralFamily::PerturbedHexahedra { .. } => "perturbed-hexahedra",
            PolyhedralFamily::Voronoi => "voronoi",
            PolyhedralFamily::NonConvex => "nonconvex",
            PolyhedralFamily::Octree => "octree",
        }
    }

    /// True for the families whose meshes depend on the seed.
    pub fn is_random(&self) -> bool {
        matches!(
            self,
            PolyhedralFamily::Voronoi | PolyhedralFamily::PerturbedHexahedra { .. }
        )
    }

    /// The mesh of size `n` of this family on `cuboid` (`seed` is used by the random families
    /// only).
    pub fn generate(
        &self,
        cuboid: &Cuboid,
        n: usize,
        seed: u64,
    ) -> Result<PolyhedralMesh, MeshError> {
        match *self {
            PolyhedralFamily::Hexahedra => {
                let [nx, ny, nz] = box_counts("hexahedra", cuboid, n, MAX_POLYHEDRAL_CELLS)?;
                hexahedra(cuboid, nx, ny, nz)
            }
            PolyhedralFamily::Tetrahedra => {
                let [nx, ny, nz] = box_counts("tetrahedra", cuboid, n, MAX_POLYHEDRAL_CELLS / 6)?;
                tetrahedra(cuboid, nx, ny, nz)
            }
            PolyhedralFamily::PerturbedHexahedra { distortion } => {
                perturbed_hexahedra(cuboid, n, distortion, seed)
            }
            PolyhedralFamily::Voronoi => voronoi_polyhedra(cuboid, n, seed),
            PolyhedralFamily::NonConvex => nonconvex_prisms(cuboid, n),
            PolyhedralFamily::Octree => octree_hexahedra(cuboid, n),
        }
    }
}

impl fmt::Display for PolyhedralFamily {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            PolyhedralFamily::PerturbedHexahedra { distortion }
                if distortion != Self::DEFAULT_DISTORTION =>
            {
                write!(f, "perturbed-hexahedra:{distortion}")
            }
            _ => f.write_str(self.name()),
        }
    }
}

impl FromStr for PolyhedralFamily {
    type Err = MeshError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let bad = |reason: String| MeshError::BadGeneratorParameter {
            generator: "PolyhedralFamily",
            reason,
        };
        let (name, parameter) = match s.trim().split_once(':') {
            Some((name, parameter)) => (name.trim(), Some(parameter.trim())),
            None => (s.trim(), None),
        };
        if let Some(family) = PolyhedralFamily::all()
            .into_iter()
            .find(|f| f.name() == name)
        {
            return match (family, parameter) {
                (PolyhedralFamily::PerturbedHexahedra { .. }, Some(value)) => {
                    let distortion: f64 = value.parse().map_err(|_| {
                        bad(format!("'{value}' in '{s}' is not a number (a distortion)"))
                    })?;
                    if !(0.0..=0.25).contains(&distortion) {
                        return Err(bad(format!(
                            "distortion {distortion} must lie in [0, 0.25]"
                        )));
                    }
                    Ok(PolyhedralFamily::PerturbedHexahedra { distortion })
                }
                (_, Some(_)) => Err(bad(format!("family '{name}' takes no parameter ('{s}')"))),
                (family, None) => Ok(family),
            };
        }
        let names: Vec<&str> = PolyhedralFamily::all()
            .iter()
            .map(PolyhedralFamily::name)
            .collect();
        Err(bad(format!(
            "unknown polyhedral mesh family '{name}'; expected one of {}",
            names.join(", ")
        )))
    }
}
