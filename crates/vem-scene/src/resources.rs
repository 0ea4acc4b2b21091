//! The memory a run plans to use, estimated before its meshes are generated, its interface
//! nodes inserted and its systems assembled, and held against a limit: the memory the
//! system reports available (`MemAvailable` of `/proc/meminfo`) unless the scene (`[limits]
//! memory_gib`) or the command line (`--memory-limit`) sets another. A scene too large for
//! the machine is refused with the estimate, instead of being killed by the system (or
//! aborting on a failed allocation) after minutes of work.
//!
//! The estimate is a model of what a run holds at its peak, first fitted to the peak of
//! `cargo xtask bench` at 8.0e6 unknowns of quads (20.0 GiB, about 1.3x below the estimate)
//! and kept above the peaks of `vem run` measured since (docs/benchmarks.md, "8·10^6
//! unknowns": 1.36-1.39x for Voronoi cells, the tightest family, 1.68x for quads, 1.94x for
//! triangles on quads; a model of these terms cannot be lower for quads without being too low
//! for Voronoi cells): the meshes ([`MESH_BYTES_PER_CORNER`] per polygon corner,
//! [`BYTES_PER_VERTEX`] per vertex), the unknowns' vectors and the factor's fill
//! ([`BYTES_PER_UNKNOWN`]) and the stiffness matrix with its factor
//! ([`BYTES_PER_ELEMENT_ENTRY`] per entry of the element matrices, `(2k)^2` for a polygon
//! of `k` vertices).

use std::fmt;

use vem_mesh::generators::MeshSize;
use vem_mesh::Mesh;

/// Bytes per polygon corner of a mesh (its connectivity, edges, parts and the generator's
/// scratch).
pub const MESH_BYTES_PER_CORNER: f64 = 64.0;
/// Bytes per vertex of a mesh (coordinates and adjacency).
pub const BYTES_PER_VERTEX: f64 = 48.0;
/// Bytes per unknown (two per vertex) of a solve: vectors, permutations and the factor's
/// fill.
///
/// A bound, not a fit written by a study: `cargo xtask bench` measures one peak per run (the
/// process's `VmHWM`), which this constant shares with the three others of the model, so no
/// measurement isolates it; the four are chosen together so that the estimate stays above the
/// measured peaks (the test of this module holds it above the bench's 8.0e6 unknowns).
pub const BYTES_PER_UNKNOWN: f64 = 1400.0;
/// Bytes per entry of the element matrices: the stiffness matrix and its share of the
/// factor.
pub const BYTES_PER_ELEMENT_ENTRY: f64 = 54.0;

const GIB: f64 = 1024.0 * 1024.0 * 1024.0;

/// What a mesh costs: its counts and the entries of its element matrices.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Footprint {
    /// Polygons.
    pub polygons: f64,
    /// Vertices.
    pub vertices: f64,
    /// Polygon corners (sum of the polygons' vertex counts).
    pub corners: f64,
    /// Entries of the element stiffness matrices, `sum (2 k)^2`.
    pub element_entries: f64,
}

impl Footprint {
    /// The footprint of a mesh about to be generated (the element entries from the mean
    /// polygon: exact for the families of one polygon shape).
    pub fn of_size(size: &MeshSize) -> Self {
        let polygons = size.polygons as f64;
        let corners = size.corners as f64;
        Self {
            polygons,
            vertices: size.vertices as f64,
            corners,
            element_entries: if polygons > 0.0 {
                4.0 * corners * corners / polygons
            } else {
                0.0
            },
        }
    }

    /// The footprint of a mesh in memory.
    pub fn of_mesh(mesh: &Mesh) -> Self {
        let (corners, entries) = (0..mesh.n_polygons())
            .map(|p| mesh.polygon(p).len() as f64)
            .fold((0.0, 0.0), |(c, e), k| (c + k, e + 4.0 * k * k));
        Self {
            polygons: mesh.n_polygons() as f64,
            vertices: mesh.n_vertices() as f64,
            corners,
            element_entries: entries,
        }
    }

    /// The footprint of a polyhedral mesh in memory, in the terms of the planar model: the
    /// cells as polygons, their vertices as corners, `(3 k)^2` entries for a cell of `k`
    /// vertices, and 3/2 planar vertices per vertex (three unknowns, not two). The model's
    /// constants are fitted to planar runs; a factor in space fills more per unknown, so this
    /// is a floor, not the measured peak of a run in space.
    pub fn of_polyhedral_mesh(mesh: &vem_mesh::PolyhedralMesh) -> Self {
        let (corners, entries) = (0..mesh.n_cells())
            .map(|c| mesh.cell_vertices(c).len() as f64)
            .fold((0.0, 0.0), |(c, e), k| (c + k, e + 9.0 * k * k));
        Self {
            polygons: mesh.n_cells() as f64,
            vertices: 1.5 * mesh.n_vertices() as f64,
            corners,
            element_entries: entries,
        }
    }

    /// Bytes to hold the mesh.
    pub fn mesh_bytes(&self) -> f64 {
        MESH_BYTES_PER_CORNER * self.corners + BYTES_PER_VERTEX * self.vertices
    }

    /// Bytes to hold the mesh and to assemble and solve its body.
    pub fn run_bytes(&self) -> f64 {
        self.mesh_bytes()
            + BYTES_PER_UNKNOWN * 2.0 * self.vertices
            + BYTES_PER_ELEMENT_ENTRY * self.element_entries
    }
}

impl std::ops::Add for Footprint {
    type Output = Self;

    fn add(self, other: Self) -> Self {
        Self {
            polygons: self.polygons + other.polygons,
            vertices: self.vertices + other.vertices,
            corners: self.corners + other.corners,
            element_entries: self.element_entries + other.element_entries,
        }
    }
}

/// Where a memory limit comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LimitOrigin {
    /// The memory the system reports available when the run starts.
    Available,
    /// The system does not say (no `/proc/meminfo`): no limit.
    Unknown,
    /// The scene's `[limits] memory_gib`.
    Scene,
    /// The command line's `--memory-limit`.
    CommandLine,
}

/// The memory a run may plan to use.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MemoryLimit {
    bytes: f64,
    origin: LimitOrigin,
}

impl MemoryLimit {
    /// The memory the system reports available (`MemAvailable` of `/proc/meminfo`); no limit
    /// where the system does not say.
    pub fn available() -> Self {
        let available = std::fs::read_to_string("/proc/meminfo")
            .ok()
            .as_deref()
            .and_then(mem_available_bytes);
        match available {
            Some(bytes) => Self {
                bytes,
                origin: LimitOrigin::Available,
            },
            None => Self {
                bytes: f64::INFINITY,
                origin: LimitOrigin::Unknown,
            },
        }
    }

    /// A limit of `gib` GiB (finite and positive) set by `origin`.
    pub fn try_from_gib(gib: f64, origin: LimitOrigin) -> Result<Self, String> {
        if !(gib.is_finite() && gib > 0.0) {
            return Err(format!(
                "memory limit {gib} GiB: give a finite positive number of GiB"
            ));
        }
        Ok(Self {
            bytes: gib * GIB,
            origin,
        })
    }

    /// The limit in bytes (infinite when unknown).
    pub fn bytes(&self) -> f64 {
        self.bytes
    }

    /// Where the limit comes from.
    pub fn origin(&self) -> LimitOrigin {
        self.origin
    }

    /// `Err` with a sentence saying what `what` (for example "generating the mesh of body
    /// 'a'") needs against the limit when `bytes` exceeds it.
    pub fn check(&self, bytes: f64, what: &str) -> Result<(), String> {
        if bytes <= self.bytes {
            return Ok(());
        }
        let how = match self.origin {
            LimitOrigin::Available | LimitOrigin::Unknown => {
                "the memory the system reports available"
            }
            LimitOrigin::Scene => "`[limits] memory_gib` of the scene",
            LimitOrigin::CommandLine => "--memory-limit",
        };
        Err(format!(
            "{what} needs about {}, more than the limit of {} ({how}); make the mesh coarser, \
             or raise the limit with `[limits] memory_gib` in the scene or --memory-limit GIB",
            Bytes(bytes),
            Bytes(self.bytes)
        ))
    }
}

/// `MemAvailable` of the text of `/proc/meminfo`, in bytes.
fn mem_available_bytes(meminfo: &str) -> Option<f64> {
    meminfo.lines().find_map(|line| {
        let kib = line
            .strip_prefix("MemAvailable:")?
            .trim()
            .strip_suffix("kB")?;
        kib.trim().parse::<f64>().ok().map(|k| 1024.0 * k)
    })
}

/// A byte count for people: "3.2 GiB", "540 MiB".
struct Bytes(f64);

impl fmt::Display for Bytes {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let b = self.0;
        if b >= GIB {
            write!(f, "{:.1} GiB", b / GIB)
        } else {
            write!(f, "{:.0} MiB", (b / (1024.0 * 1024.0)).max(1.0))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use vem_mesh::generators::{MeshFamily, Rectangle};

    #[test]
    fn reads_mem_available() {
        let text = "MemTotal:       24576000 kB\nMemFree:  100 kB\nMemAvailable:   2048 kB\n";
        assert_eq!(mem_available_bytes(text), Some(2048.0 * 1024.0));
        assert_eq!(mem_available_bytes("MemTotal: 1 kB\n"), None);
    }

    /// The estimate of a generated mesh equals the footprint of the mesh generated (quads:
    /// every polygon has four corners), and is above the measured peak of the benchmark:
    /// 20.0 GiB for 8.0e6 unknowns (two bodies of 1414 x 1414 quads).
    #[test]
    fn estimate_matches_the_mesh_and_bounds_the_measured_peak() {
        let rect = Rectangle::unit_square();
        let size = MeshFamily::Quads.size(&rect, 12).unwrap();
        let mesh = MeshFamily::Quads.generate(&rect, 12, 1).unwrap();
        assert_eq!(Footprint::of_size(&size), Footprint::of_mesh(&mesh));
        let body = Footprint::of_size(&MeshSize {
            polygons: 1414 * 1414,
            vertices: 1415 * 1415,
            corners: 4 * 1414 * 1414,
        });
        let gib = (body + body).run_bytes() / GIB;
        assert!((20.0..1.5 * 20.0).contains(&gib), "{gib}");
    }

    #[test]
    fn limit_names_its_origin_and_the_sizes() {
        let limit = MemoryLimit::try_from_gib(1.0, LimitOrigin::CommandLine).unwrap();
        assert!(limit.check(GIB, "x").is_ok());
        let refused = limit.check(3.5 * GIB, "solving").unwrap_err();
        assert!(
            refused.starts_with(
                "solving needs about 3.5 GiB, more than the limit of 1.0 GiB (--memory-limit)"
            ),
            "{refused}"
        );
        assert!(MemoryLimit::try_from_gib(0.0, LimitOrigin::Scene).is_err());
        assert!(MemoryLimit::try_from_gib(f64::INFINITY, LimitOrigin::Scene).is_err());
    }
}
