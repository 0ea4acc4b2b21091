//! Centroidal Voronoi polyhedra clipped to a box.
//!
//! The Voronoi cell of a site is computed directly as the box clipped by the bisector
//! half-spaces of the nearby sites (found through a uniform grid of sites, shell by shell, until
//! the next shell is farther than twice the cell's radius): a convex polyhedron clipped by one
//! plane at a time, each face clipped as a polygon and the cut closed by a new face whose loop
//! is chained from the cut segments. Cells are computed in parallel (rayon); each depends only on
//! the sites, so the result does not depend on the number of threads. Lloyd iterations move
//! every site to the exact centroid of its cell.
//!
//! The cells are then made into one conforming mesh: cell vertices closer than 1e-9 of the site
//! spacing are identified (they are the same Voronoi vertex computed from different cells; a
//! near-degenerate vertex where more than four cells meet is computed as a cluster of very close
//! vertices, which are identified too), vertices within that distance of a side of the box are
//! snapped onto it, and faces left with fewer than three vertices disappear. A face shared by
//! two cells then lists the same vertices in both, and is matched by its vertex set.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

use super::{box_counts, mesh_with_box_sides, Cuboid, SIDE_NAMES};
use crate::polyhedral::CellsBuilder;
use crate::{MeshError, Point3, PolyhedralMesh, Vector3};

/// Number of Lloyd iterations [`voronoi_polyhedra`] runs. Measured on the unit cube at n = 16
/// (4096 cells, seed 1): 10 iterations raise the smallest star-shaped ratio from 0.18 to 0.21
/// for 1.6 times the generation time; the edge and face ratios are set by the merge
/// ([`SHORT_EDGE_RATIO_3D`]) either way.
pub const VORONOI_LLOYD_ITERATIONS: usize = 5;

/// Vertices of the Voronoi cells closer than this times the site spacing (the cube root of the
/// volume per site) are merged into one, at their mean: short edges and small faces collapse.
/// The faces around a merged vertex are then warped by up to about this fraction of the
/// spacing; when the merged mesh fails validation, the merge distance is divided by 4 until it
/// passes (at worst down to [`EXACT_MERGE_RATIO`], the exact tessellation).
pub const SHORT_EDGE_RATIO_3D: f64 = 0.1;

/// The merge distance of the exact tessellation, relative to the site spacing: vertices this
/// close are the same Voronoi vertex computed in different cells.
pub const EXACT_MERGE_RATIO: f64 = 1e-9;

/// Largest number of Voronoi polyhedra the generator agrees to make (its time grows with the
/// cells times the Lloyd iterations).
pub const MAX_VORONOI_POLYHEDRA: usize = 1_000_000;

/// A convex polyhedron relative to its site: points and outward face loops (compact).
#[derive(Debug, Clone, Default)]
struct ConvexCell {
    points: Vec<Vector3>,
    face_offsets: Vec<usize>,
    face_vertices: Vec<usize>,
}

/// Work space of one cell computation: candidate sites (squared distance, index, offset) and
/// the clipping buffers.
#[derive(Debug, Default)]
struct Scratch {
    candidates: Vec<(f64, usize, Vector3)>,
    clip: ClipScratch,
}

/// Work space of the clipping.
#[derive(Debug, Default)]
struct ClipScratch {
    other: ConvexCell,
    distance: Vec<f64>,
    remap: Vec<usize>,
    crossings: Vec<(usize, usize, usize)>,
    cap_next: Vec<(usize, usize)>,
}

impl ConvexCell {
    /// The box, relative to `site`.
    fn boxed(cuboid: &Cuboid, site: Point3) -> Self {
        let corner = |dx: usize, dy: usize, dz: usize| dx + 2 * dy + 4 * dz;
        let points = (0..8)
            .map(|c| {
                let pick = |bit: usize, axis: usize| {
                    if c >> bit & 1 == 1 {
                        cuboid.max[axis]
                    } else {
                        cuboid.min[axis]
                    }
                };
                Vector3::new(pick(0, 0), pick(1, 1), pick(2, 2)) - site.coords
            })
            .collect();
        let mut face_offsets = vec![0];
        let mut face_vertices = Vec::with_capacity(24);
        for face in super::box_faces(corner) {
            face_vertices.extend_from_slice(&face);
            face_offsets.push(face_vertices.len());
        }
        Self {
            points,
            face_offsets,
            face_vertices,
        }
    }

    fn n_faces(&self) -> usize {
        self.face_offsets.len() - 1
    }

    fn face(&self, k: usize) -> &[usize] {
        &self.face_vertices[self.face_offsets[k]..self.face_offsets[k + 1]]
    }

    /// Largest distance of a vertex from the site.
    fn radius(&self) -> f64 {
        self.points
            .iter()
            .map(|p| p.norm_squared())
            .fold(0.0, f64::max)
            .sqrt()
    }

    /// Volume and centroid (relative to the site, which lies inside) by tetrahedra from the site
    /// over the faces' fans from their first vertex.
    fn volume_and_centroid(&self) -> (f64, Vector3) {
        let (mut six_volume, mut moment) = (0.0, Vector3::zeros());
        for k in 0..self.n_faces() {
            let face = self.face(k);
            let a = self.points[face[0]];
            for w in face[1..].windows(2) {
                let (b, c) = (self.points[w[0]], self.points[w[1]]);
                let det = a.cross(&b).dot(&c);
                six_volume += det;
                moment += det * (a + b + c);
            }
        }
        if six_volume <= 0.0 {
            return (0.0, Vector3::zeros());
        }
        (six_volume / 6.0, moment / (4.0 * six_volume))
    }

    /// Clips the cell to the half-space of points closer to the site (the origin) than to
    /// `other` (relative to the site). Returns false when the cut could not be closed (a
    /// degenerate configuration); the cell is then left unchanged.
    fn clip(&mut self, other: Vector3, scratch: &mut ClipScratch) -> bool {
        let offset = 0.5 * other.norm_squared();
        let scale = other.norm() * self.radius();
        let eps = 1e-13 * scale;
        // Most candidates do not cut: check that first, without storing anything.
        let highest = self
            .points
            .iter()
            .map(|p| other.dot(p))
            .fold(f64::NEG_INFINITY, f64::max);
        if highest - offset <= eps {
            return true;
        }
        scratch.distance.clear();
        scratch
            .distance
            .extend(self.points.iter().map(|p| other.dot(p) - offset));
        let inside = |d: f64| d <= eps;
        let out = &mut scratch.other;
        out.points.clear();
        out.face_offsets.clear();
        out.face_offsets.push(0);
        out.face_vertices.clear();
        scratch.remap.clear();
        scratch.remap.resize(self.points.len(), usize::MAX);
        for (v, p) in self.points.iter().enumerate() {
            if inside(scratch.distance[v]) {
                scratch.remap[v] = out.points.len();
                out.points.push(*p);
            }
        }
        scratch.crossings.clear();
        scratch.cap_next.clear();
        for k in 0..self.n_faces() {
            let face = &self.face_vertices[self.face_offsets[k]..self.face_offsets[k + 1]];
            let start = out.face_vertices.len();
            let (mut exit, mut entry) = (usize::MAX, usize::MAX);
            let n = face.len();
            for q in 0..n {
                let (a, b) = (face[q], face[(q + 1) % n]);
                let (da, db) = (scratch.distance[a], scratch.distance[b]);
                if inside(da) {
                    out.face_vertices.push(scratch.remap[a]);
                }
                if inside(da) != inside(db) {
                    let key = (a.min(b), a.max(b));
                    let x = match scratch.crossings.iter().find(|c| (c.0, c.1) == key) {
                        Some(c) => c.2,
                        None => {
                            let p = self.points[a]
                                + (self.points[b] - self.points[a]) * (da / (da - db));
                            out.points.push(p);
                            scratch.crossings.push((key.0, key.1, out.points.len() - 1));
                            out.points.len() - 1
                        }
                    };
                    out.face_vertices.push(x);
                    if inside(da) {
                        exit = x;
                    } else {
                        entry = x;
                    }
                }
            }
            if out.face_vertices.len() - start >= 3 {
                out.face_offsets.push(out.face_vertices.len());
            } else {
                out.face_vertices.truncate(start);
            }
            if exit != usize::MAX && entry != usize::MAX {
                scratch.cap_next.push((entry, exit));
            } else if exit != usize::MAX || entry != usize::MAX {
                return false;
            }
        }
        // Chain the cut segments into the cap's loop.
        let segments = scratch.cap_next.len();
        if segments >= 3 {
            let first = scratch.cap_next[0].0;
            let mut current = first;
            let start = out.face_vertices.len();
            for _ in 0..segments {
                out.face_vertices.push(current);
                match scratch.cap_next.iter().find(|s| s.0 == current) {
                    Some(s) => current = s.1,
                    None => return false,
                }
            }
            if current != first || out.face_vertices.len() - start != segments {
                return false;
            }
            out.face_offsets.push(out.face_vertices.len());
        } else if segments > 0 {
            return false;
        }
        std::mem::swap(self, &mut scratch.other);
        true
    }
}

/// The box cut into nx x ny x nz equal cells, to bucket the sites.
struct SiteGrid {
    cuboid: Cuboid,
    counts: [usize; 3],
}

impl SiteGrid {
    fn cell_of(&self, p: Point3) -> [usize; 3] {
        let e = self.cuboid.extent();
        std::array::from_fn(|axis| {
            let count = self.counts[axis];
            let i = ((p[axis] - self.cuboid.min[axis]) / e[axis] * count as f64).floor();
            if i <= 0.0 {
                0
            } else {
                (i as usize).min(count - 1)
            }
        })
    }

    fn index(&self, [i, j, k]: [usize; 3]) -> usize {
        i + self.counts[0] * (j + self.counts[1] * k)
    }

    /// Sites per cell, compressed: `items[start[c]..start[c + 1]]` are the sites of cell c.
    fn bucket(&self, sites: &[Point3]) -> (Vec<usize>, Vec<usize>) {
        let cells = self.counts.iter().product::<usize>();
        let keys: Vec<usize> = sites.iter().map(|&p| self.index(self.cell_of(p))).collect();
        let mut start = vec![0usize; cells + 1];
        for &k in &keys {
            start[k + 1] += 1;
        }
        for c in 0..cells {
            start[c + 1] += start[c];
        }
        let mut fill = start.clone();
        let mut items = vec![0; sites.len()];
        for (site, &k) in keys.iter().enumerate() {
            items[fill[k]] = site;
            fill[k] += 1;
        }
        (start, items)
    }
}

/// The Voronoi cell of site `items[k]` (at `bucketed[k]`), or None when a cut degenerated.
fn voronoi_cell(
    grid: &SiteGrid,
    start: &[usize],
    items: &[usize],
    bucketed: &[Point3],
    k: usize,
    scratch: &mut Scratch,
) -> Option<ConvexCell> {
    let cuboid = grid.cuboid;
    let e = cuboid.extent();
    let h: [f64; 3] = std::array::from_fn(|a| e[a] / grid.counts[a] as f64);
    let (i, site) = (items[k], bucketed[k]);
    let mut cell = ConvexCell::boxed(&cuboid, site);
    let mut radius = cell.radius();
    let centre = grid.cell_of(site);
    let max_ring = grid.counts.into_iter().max().unwrap_or(1);
    // Candidates shell by shell; within a shell, nearest first, so the cell shrinks fast and
    // farther sites are skipped by the radius test.
    let candidates = &mut scratch.candidates;
    for ring in 0..=max_ring {
        let r = ring as i64;
        let lo: [i64; 3] = std::array::from_fn(|a| centre[a] as i64 - r);
        let hi: [i64; 3] = std::array::from_fn(|a| centre[a] as i64 + r);
        candidates.clear();
        for gz in lo[2].max(0)..=hi[2].min(grid.counts[2] as i64 - 1) {
            for gy in lo[1].max(0)..=hi[1].min(grid.counts[1] as i64 - 1) {
                for gx in lo[0].max(0)..=hi[0].min(grid.counts[0] as i64 - 1) {
                    let on_shell = (gx - centre[0] as i64)
                        .abs()
                        .max((gy - centre[1] as i64).abs())
                        .max((gz - centre[2] as i64).abs())
                        == r;
                    if !on_shell {
                        continue;
                    }
                    let c = grid.index([gx as usize, gy as usize, gz as usize]);
                    for (&other, &position) in items[start[c]..start[c + 1]]
                        .iter()
                        .zip(&bucketed[start[c]..start[c + 1]])
                    {
                        let d = position - site;
                        let distance_squared = d.norm_squared();
                        // A site at least twice the cell's radius away cannot cut it.
                        if other != i && distance_squared < 4.0 * radius * radius {
                            candidates.push((distance_squared, other, d));
                        }
                    }
                }
            }
        }
        // Ties broken by site index, so the order (and the cell, bit for bit) is fixed.
        candidates.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        for &(distance_squared, _, d) in candidates.iter() {
            // A site at least twice the cell's radius away cannot cut it.
            if distance_squared < 4.0 * radius * radius {
                if !cell.clip(d, &mut scratch.clip) {
                    return None;
                }
                radius = cell.radius();
            }
        }
        // Sites outside the block of grid cells (centre +- ring) are at least `reach` away.
        let reach = (0..3)
            .flat_map(|a| {
                let low = cuboid.min[a] + (centre[a] as f64 - ring as f64) * h[a];
                let high = cuboid.min[a] + (centre[a] as f64 + ring as f64 + 1.0) * h[a];
                [site[a] - low, high - site[a]]
            })
            .fold(f64::INFINITY, f64::min);
        if reach >= 2.0 * radius {
            break;
        }
    }
    Some(cell)
}

/// The Voronoi cells of all sites (relative to their sites), computed in parallel.
fn voronoi_cells(grid: &SiteGrid, sites: &[Point3]) -> Result<Vec<ConvexCell>, MeshError> {
    let (start, items) = grid.bucket(sites);
    let bucketed: Vec<Point3> = items.iter().map(|&s| sites[s]).collect();
    let computed: Vec<Option<ConvexCell>> = (0..items.len())
        .into_par_iter()
        .map_init(Scratch::default, |scratch, k| {
            voronoi_cell(grid, &start, &items, &bucketed, k, scratch)
        })
        .collect();
    let mut cells = vec![ConvexCell::default(); sites.len()];
    for (&site, cell) in items.iter().zip(computed) {
        cells[site] = cell.ok_or_else(|| MeshError::BadGeneratorParameter {
            generator: "voronoi_polyhedra",
            reason: format!(
                "the Voronoi cell of site {site} at {:?} could not be computed (a degenerate cut)",
                sites[site]
            ),
        })?;
    }
    Ok(cells)
}

/// A mesh of centroidal Voronoi polyhedra of `cuboid`, about `n` cells across: nx x ny x nz
/// sites (the counts of [`super::hexahedra`] for size `n`) drawn uniformly from a `ChaCha8Rng`
/// seeded with `seed`, [`VORONOI_LLOYD_ITERATIONS`] Lloyd iterations, then the conforming mesh
/// of the cells (module docs). The faces are planar (to round-off) and convex; every cell is
/// convex.
///
/// ```
/// use vem_mesh::generators::polyhedral::{voronoi_polyhedra, Cuboid};
/// let mesh = voronoi_polyhedra(&Cuboid::unit_cube(), 4, 1)?;
/// assert_eq!(mesh.n_cells(), 64);
/// let volume: f64 = (0..mesh.n_cells()).map(|c| mesh.volume(c)).sum();
/// assert!((volume - 1.0).abs() < 1e-12);
/// # Ok::<(), vem_mesh::MeshError>(())
/// ```
pub fn voronoi_polyhedra(
    cuboid: &Cuboid,
    n: usize,
    seed: u64,
) -> Result<PolyhedralMesh, MeshError> {
    let counts = box_counts("voronoi_polyhedra", cuboid, n, MAX_VORONOI_POLYHEDRA)?;
    let count = counts.iter().product::<usize>();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut sites: Vec<Point3> = (0..count)
        .map(|_| {
            Point3::new(
                rng.gen_range(cuboid.min.x..cuboid.max.x),
                rng.gen_range(cuboid.min.y..cuboid.max.y),
                rng.gen_range(cuboid.min.z..cuboid.max.z),
            )
        })
        .collect();
    let grid = SiteGrid {
        cuboid: *cuboid,
        counts,
    };
    for _ in 0..VORONOI_LLOYD_ITERATIONS {
        let cells = voronoi_cells(&grid, &sites)?;
        for (site, cell) in sites.iter_mut().zip(&cells) {
            let (volume, centroid) = cell.volume_and_centroid();
            if volume > 0.0 {
                *site += centroid;
            }
        }
    }
    let cells = voronoi_cells(&grid, &sites)?;
    let spacing = (cuboid.volume() / count as f64).cbrt();
    // Collapse short edges: merge vertex clusters of diameter about SHORT_EDGE_RATIO_3D x the
    // spacing; if the merged mesh is not valid, retry with a 4 times smaller merge distance,
    // down to the coincidence of the exact tessellation.
    let mut merge = SHORT_EDGE_RATIO_3D;
    loop {
        let (vertices, builder) = conforming(cuboid, &sites, &cells, merge * spacing);
        let result = mesh_with_box_sides(cuboid, vertices, builder);
        if result.is_ok() || merge <= EXACT_MERGE_RATIO {
            return result;
        }
        merge = (merge / 4.0).max(EXACT_MERGE_RATIO);
    }
}

/// Identifies cell vertices closer than `tolerance` (union of all such pairs), snaps vertices
/// onto the box sides, and returns the shared vertices with the cells' faces as loops of them
/// (consecutive repeats removed, faces of fewer than three vertices dropped).
fn conforming(
    cuboid: &Cuboid,
    sites: &[Point3],
    cells: &[ConvexCell],
    tolerance: f64,
) -> (Vec<Point3>, CellsBuilder) {
    let mut first = Vec::with_capacity(cells.len() + 1);
    first.push(0);
    let mut points: Vec<Point3> = Vec::new();
    for (cell, site) in cells.iter().zip(sites) {
        points.extend(cell.points.iter().map(|p| site + p));
        first.push(points.len());
    }
    let size = 4.0 * tolerance;
    let key = |p: Point3| {
        (
            (p.x / size).floor() as i64,
            (p.y / size).floor() as i64,
            (p.z / size).floor() as i64,
        )
    };
    let mut sorted: Vec<((i64, i64, i64), usize)> = points
        .par_iter()
        .enumerate()
        .map(|(k, &p)| (key(p), k))
        .collect();
    sorted.par_sort_unstable();
    let mut parent: Vec<usize> = (0..points.len()).collect();
    fn root(parent: &mut [usize], mut v: usize) -> usize {
        while parent[v] != v {
            parent[v] = parent[parent[v]];
            v = parent[v];
        }
        v
    }
    let offset = Vector3::repeat(tolerance);
    for (position, &(own, a)) in sorted.iter().enumerate() {
        let p = points[a];
        let (lo, hi) = (key(p - offset), key(p + offset));
        for cx in lo.0..=hi.0 {
            for cy in lo.1..=hi.1 {
                for cz in lo.2..=hi.2 {
                    let target = (cx, cy, cz);
                    // The own cell's members follow this one in the sorted order.
                    let from = if target == own {
                        position + 1
                    } else {
                        sorted.partition_point(|&(k, _)| k < target)
                    };
                    for &(k, b) in &sorted[from..] {
                        if k != target {
                            break;
                        }
                        if b != a && (points[b] - p).norm() <= tolerance {
                            let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
                            if ra != rb {
                                parent[ra.max(rb)] = ra.min(rb);
                            }
                        }
                    }
                }
            }
        }
    }
    // Each cluster at the mean of its members, kept on every side of the box one of them
    // lies on.
    let snap_tolerance = 1e-9 * cuboid.extent().max();
    let mut sum = vec![Vector3::zeros(); points.len()];
    let mut members = vec![0usize; points.len()];
    let mut sides = vec![0u8; points.len()];
    for (k, point) in points.iter().enumerate() {
        let r = root(&mut parent, k);
        sum[r] += point.coords;
        members[r] += 1;
        for (axis, &value) in point.iter().enumerate() {
            if (value - cuboid.min[axis]).abs() <= snap_tolerance {
                sides[r] |= 1 << (2 * axis);
            } else if (value - cuboid.max[axis]).abs() <= snap_tolerance {
                sides[r] |= 2 << (2 * axis);
            }
        }
    }
    let position = |r: usize| {
        let mut p = Point3::from(sum[r] / members[r] as f64);
        for axis in 0..3 {
            if sides[r] >> (2 * axis) & 1 == 1 {
                p[axis] = cuboid.min[axis];
            } else if sides[r] >> (2 * axis) & 2 == 2 {
                p[axis] = cuboid.max[axis];
            }
        }
        p
    };
    let mut number = vec![usize::MAX; points.len()];
    let mut vertices = Vec::new();
    let mut builder = CellsBuilder::with_capacity(cells.len(), 15, 5);
    let mut loop_ = Vec::new();
    for (c, cell) in cells.iter().enumerate() {
        for k in 0..cell.n_faces() {
            loop_.clear();
            for &v in cell.face(k) {
                let r = root(&mut parent, first[c] + v);
                if number[r] == usize::MAX {
                    number[r] = vertices.len();
                    vertices.push(position(r));
                }
                loop_.push(number[r]);
            }
            loop_.dedup();
            while loop_.len() > 1 && loop_.first() == loop_.last() {
                loop_.pop();
            }
            if loop_.len() >= 3 {
                builder.push_face(&loop_);
            }
        }
        builder.end_cell();
    }
    debug_assert_eq!(SIDE_NAMES.len(), 6);
    (vertices, builder)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cells_of_a_regular_lattice_of_sites_are_cubes() {
        let cuboid = Cuboid::unit_cube();
        let grid = SiteGrid {
            cuboid,
            counts: [3, 3, 3],
        };
        let sites: Vec<Point3> = (0..27)
            .map(|k| {
                Point3::new(
                    (k % 3) as f64 / 3.0 + 1.0 / 6.0,
                    (k / 3 % 3) as f64 / 3.0 + 1.0 / 6.0,
                    (k / 9) as f64 / 3.0 + 1.0 / 6.0,
                )
            })
            .collect();
        for cell in voronoi_cells(&grid, &sites).unwrap() {
            let (volume, centroid) = cell.volume_and_centroid();
            assert!((volume - 1.0 / 27.0).abs() < 1e-15);
            assert!(centroid.norm() < 1e-15);
        }
    }
}
