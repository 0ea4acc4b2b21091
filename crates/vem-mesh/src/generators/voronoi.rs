//! Centroidal Voronoi meshes clipped to the rectangle.
//!
//! The Voronoi cell of a site is computed directly as the rectangle clipped by the bisector
//! half-planes of the nearby sites (found through a uniform grid of sites, ring by ring, until
//! the next ring is farther than twice the cell's radius); the cells are computed in parallel
//! (rayon) in the order of the grid, and the result does not depend on the number of threads. Lloyd iterations move every site to
//! the exact centroid of its cell. The cells are then made into one conforming mesh: cell
//! vertices closer than 1e-9 of the site spacing are identified (they are the same Voronoi
//! vertex computed from different cells), and edges shorter than [`SHORT_EDGE_RATIO`] h_T are
//! collapsed so that assumption A1 holds with a gamma independent of n.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

use super::{cell_counts, mesh_with_sides, Rectangle};
use crate::{geometry, Mesh, MeshError, Point, Vector};

/// Number of Lloyd iterations [`voronoi`] runs.
pub const LLOYD_ITERATIONS: usize = 30;

/// Edges shorter than this fraction of the larger diameter of the two cells sharing them are
/// collapsed.
pub const SHORT_EDGE_RATIO: f64 = 0.1;

/// Largest number of collapsing passes (each pass collapses non-adjacent short edges).
const MERGE_PASSES: usize = 10;

/// Largest number of Voronoi cells the generator agrees to make: its time grows with the
/// cells times [`LLOYD_ITERATIONS`] (250 000 cells take about half a minute on two cores), so
/// a tall rectangle with a modest `n` (n = 9 on [0, 1] x [0, 1e5] asks for 8.1e6 cells) is
/// refused at once instead of running for many minutes.
pub const MAX_VORONOI_CELLS: usize = 1_000_000;

/// The sites across and up of [`voronoi`], at most [`MAX_VORONOI_CELLS`] in all.
pub(crate) fn voronoi_counts(rect: &Rectangle, n: usize) -> Result<(usize, usize), MeshError> {
    let (nx, ny) = cell_counts("voronoi", rect, n)?;
    if nx * ny > MAX_VORONOI_CELLS {
        return Err(MeshError::BadGeneratorParameter {
            generator: "voronoi",
            reason: format!(
                "size n = {n} asks for {} cells ({nx} x {ny}) on this rectangle, more than the \
                 {MAX_VORONOI_CELLS} the Voronoi generator makes in reasonable time",
                nx * ny
            ),
        });
    }
    Ok((nx, ny))
}

/// A centroidal Voronoi mesh of `rect` with about `n` cells across (`n` x `round(n height /
/// width)` sites drawn uniformly from a `ChaCha8Rng` seeded with `seed`, then
/// [`LLOYD_ITERATIONS`] Lloyd iterations).
///
/// Edges shorter than [`SHORT_EDGE_RATIO`] times the diameter of either adjacent cell are
/// collapsed to a point: the midpoint for two interior vertices, the boundary vertex when one
/// lies on the boundary, the midpoint when both lie on the same side; the corners of the
/// rectangle are always vertices and never move. Collapsing is done on the shared mesh, so
/// neighbours stay conforming.
///
/// ```
/// use vem_mesh::generators::{voronoi, Rectangle};
/// let mesh = voronoi(&Rectangle::unit_square(), 6, 1)?;
/// assert_eq!(mesh.n_polygons(), 36);
/// assert!(mesh.quality().shortest_edge_ratio.min >= vem_mesh::generators::SHORT_EDGE_RATIO / 2.0);
/// # Ok::<(), vem_mesh::MeshError>(())
/// ```
pub fn voronoi(rect: &Rectangle, n: usize, seed: u64) -> Result<Mesh, MeshError> {
    let (nx, ny) = voronoi_counts(rect, n)?;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut sites: Vec<Point> = (0..nx * ny)
        .map(|_| {
            Point::new(
                rng.gen_range(rect.min.x..rect.max.x),
                rng.gen_range(rect.min.y..rect.max.y),
            )
        })
        .collect();
    let grid = SiteGrid::new(rect, nx, ny);
    for _ in 0..LLOYD_ITERATIONS {
        let cells = voronoi_cells(&grid, &sites);
        for (site, cell) in sites.iter_mut().zip(&cells) {
            if cell.len() >= 3 {
                *site = geometry::centroid(cell);
            }
        }
    }
    let cells = voronoi_cells(&grid, &sites);
    let spacing = (rect.width() * rect.height() / sites.len() as f64).sqrt();
    let (vertices, polygons) = conforming(rect, &cells, 1e-9 * spacing);
    let (vertices, polygons) = collapse_short_edges_in(rect, vertices, polygons);
    mesh_with_sides(rect, vertices, &polygons)
}

/// The rectangle cut into nx x ny equal cells, to bucket the sites.
pub(super) struct SiteGrid {
    rect: Rectangle,
    nx: usize,
    ny: usize,
}

impl SiteGrid {
    pub(super) fn new(rect: &Rectangle, nx: usize, ny: usize) -> Self {
        Self {
            rect: *rect,
            nx,
            ny,
        }
    }

    fn cell_of(&self, p: Point) -> (usize, usize) {
        let index = |value: f64, min: f64, extent: f64, count: usize| -> usize {
            let i = ((value - min) / extent * count as f64).floor();
            if i <= 0.0 {
                0
            } else {
                (i as usize).min(count - 1)
            }
        };
        (
            index(p.x, self.rect.min.x, self.rect.width(), self.nx),
            index(p.y, self.rect.min.y, self.rect.height(), self.ny),
        )
    }

    /// Sites per cell, compressed: `items[start[c]..start[c + 1]]` are the sites of cell c.
    fn bucket(&self, sites: &[Point]) -> (Vec<usize>, Vec<usize>) {
        let cells = self.nx * self.ny;
        let mut start = vec![0usize; cells + 1];
        let keys: Vec<usize> = sites
            .iter()
            .map(|&p| {
                let (i, j) = self.cell_of(p);
                j * self.nx + i
            })
            .collect();
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

/// The Voronoi cell of every site, clipped to the rectangle, counter-clockwise.
///
/// The cells are computed bucket by bucket (neighbouring sites one after the other, their
/// neighbours' positions copied next to each other, so the lookups stay in cache) and in
/// parallel. Each cell depends only on the sites (it is clipped by the same sites in the same
/// order whatever the order the cells are computed in), so the result is the same bit for bit
/// whatever the number of threads.
pub(super) fn voronoi_cells(grid: &SiteGrid, sites: &[Point]) -> Vec<Vec<Point>> {
    voronoi_cells_of(grid, sites, sites.len())
}

/// The Voronoi cells of the first `wanted` sites among all `sites` ([`voronoi_cells`]); the
/// cells of the other sites are left empty.
pub(super) fn voronoi_cells_of(grid: &SiteGrid, sites: &[Point], wanted: usize) -> Vec<Vec<Point>> {
    let (start, items) = grid.bucket(sites);
    let bucketed: Vec<Point> = items.iter().map(|&s| sites[s]).collect();
    let computed: Vec<Vec<Point>> = (0..items.len())
        .into_par_iter()
        .map_init(Vec::new, |scratch, k| {
            if items[k] < wanted {
                voronoi_cell(grid, &start, &items, &bucketed, k, scratch)
            } else {
                Vec::new()
            }
        })
        .collect();
    let mut cells = vec![Vec::new(); sites.len()];
    for (&site, cell) in items.iter().zip(computed) {
        cells[site] = cell;
    }
    cells
}

/// The Voronoi cell of the site `items[k]` (at `bucketed[k]`): the rectangle clipped by the
/// bisectors of the sites of the grid cells around it, ring by ring, until the next ring is
/// farther than twice the cell's radius.
fn voronoi_cell(
    grid: &SiteGrid,
    start: &[usize],
    items: &[usize],
    bucketed: &[Point],
    k: usize,
    scratch: &mut Vec<Point>,
) -> Vec<Point> {
    let rect = grid.rect;
    let (hx, hy) = (
        rect.width() / grid.nx as f64,
        rect.height() / grid.ny as f64,
    );
    let max_ring = grid.nx.max(grid.ny);
    let (i, site) = (items[k], bucketed[k]);
    let mut cell = vec![
        rect.min,
        Point::new(rect.max.x, rect.min.y),
        rect.max,
        Point::new(rect.min.x, rect.max.y),
    ];
    let mut radius = cell.iter().map(|v| (v - site).norm()).fold(0.0, f64::max);
    let (ci, cj) = grid.cell_of(site);
    for ring in 0..=max_ring {
        for (gi, gj) in ring_cells(ci, cj, ring, grid.nx, grid.ny) {
            let c = gj * grid.nx + gi;
            for (&other, &position) in items[start[c]..start[c + 1]]
                .iter()
                .zip(&bucketed[start[c]..start[c + 1]])
            {
                // A site at least twice the cell's radius away cannot cut it.
                if other != i && (position - site).norm() < 2.0 * radius {
                    clip_bisector(&cell, site, position, scratch);
                    std::mem::swap(&mut cell, scratch);
                    radius = cell.iter().map(|v| (v - site).norm()).fold(0.0, f64::max);
                }
            }
        }
        // Sites outside the block of cells (ci +- ring, cj +- ring) are at least `reach`
        // away; they cut the cell only if closer than twice its radius.
        let r = ring as f64;
        let reach = [
            site.x - (rect.min.x + (ci as f64 - r) * hx),
            rect.min.x + (ci as f64 + r + 1.0) * hx - site.x,
            site.y - (rect.min.y + (cj as f64 - r) * hy),
            rect.min.y + (cj as f64 + r + 1.0) * hy - site.y,
        ]
        .into_iter()
        .fold(f64::INFINITY, f64::min);
        if reach >= 2.0 * radius {
            break;
        }
    }
    cell
}

/// Grid cells at Chebyshev distance `ring` from (ci, cj), inside the grid.
fn ring_cells(
    ci: usize,
    cj: usize,
    ring: usize,
    nx: usize,
    ny: usize,
) -> impl Iterator<Item = (usize, usize)> {
    let (ci, cj, r) = (ci as i64, cj as i64, ring as i64);
    (cj - r..=cj + r)
        .flat_map(move |j| (ci - r..=ci + r).map(move |i| (i, j)))
        .filter(move |&(i, j)| {
            (i - ci).abs().max((j - cj).abs()) == r
                && i >= 0
                && j >= 0
                && i < nx as i64
                && j < ny as i64
        })
        .map(|(i, j)| (i as usize, j as usize))
}

/// Clips the convex polygon `cell` to the half-plane of points closer to `site` than to
/// `other`, into `out`.
fn clip_bisector(cell: &[Point], site: Point, other: Point, out: &mut Vec<Point>) {
    let normal: Vector = other - site;
    clip_half_plane(cell, site + 0.5 * normal, normal, out);
}

/// Clips the polygon `cell` to the half-plane {x : (x - middle) . normal <= 0}, into `out`
/// (Sutherland-Hodgman: a non-convex polygon cut in several pieces comes out as one loop whose
/// pieces are joined along the line by edges of zero area, so its area and centroid are
/// those of the pieces); a zero `normal` keeps the polygon.
pub(super) fn clip_half_plane(cell: &[Point], middle: Point, normal: Vector, out: &mut Vec<Point>) {
    out.clear();
    if normal == Vector::zeros() {
        out.extend_from_slice(cell);
        return;
    }
    let count = cell.len();
    for k in 0..count {
        let (a, b) = (cell[k], cell[(k + 1) % count]);
        let (sa, sb) = ((a - middle).dot(&normal), (b - middle).dot(&normal));
        if sa <= 0.0 {
            out.push(a);
        }
        if (sa < 0.0 && sb > 0.0) || (sa > 0.0 && sb < 0.0) {
            out.push(a + (b - a) * (sa / (sa - sb)));
        }
    }
}

/// Identifies cell vertices closer than `tolerance` (union of all such pairs) and returns the
/// shared vertices (first member's position, snapped onto the rectangle's sides) and the
/// cells as loops of vertex indices without repeats.
pub(super) fn conforming(
    rect: &Rectangle,
    cells: &[Vec<Point>],
    tolerance: f64,
) -> (Vec<Point>, Vec<Vec<usize>>) {
    let points: Vec<Point> = cells.iter().flatten().copied().collect();
    let mut parent: Vec<usize> = (0..points.len()).collect();
    fn root(parent: &mut [usize], mut v: usize) -> usize {
        while parent[v] != v {
            parent[v] = parent[parent[v]];
            v = parent[v];
        }
        v
    }
    let size = 4.0 * tolerance;
    let key = |p: Point| ((p.x / size).floor() as i64, (p.y / size).floor() as i64);
    let mut sorted: Vec<((i64, i64), usize)> = points
        .iter()
        .enumerate()
        .map(|(k, &p)| (key(p), k))
        .collect();
    sorted.sort_unstable();
    // The root of a cluster is its smallest member whatever the order the pairs are joined
    // in: the points are visited in the order of their keys (neighbours one after the other,
    // their positions side by side, so the searches stay in cache).
    let sorted_points: Vec<Point> = sorted.iter().map(|&(_, k)| points[k]).collect();
    for &(_, a) in &sorted {
        let p = points[a];
        let lo = key(p - Vector::new(tolerance, tolerance));
        let hi = key(p + Vector::new(tolerance, tolerance));
        for cx in lo.0..=hi.0 {
            for cy in lo.1..=hi.1 {
                let from = sorted.partition_point(|&(k, _)| k < (cx, cy));
                for (&(k, b), &q) in sorted[from..].iter().zip(&sorted_points[from..]) {
                    if k != (cx, cy) {
                        break;
                    }
                    if b > a && (q - p).norm() <= tolerance {
                        let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
                        if ra != rb {
                            parent[ra.max(rb)] = ra.min(rb);
                        }
                    }
                }
            }
        }
    }
    // Number the clusters in order of first appearance; the root is the first member.
    let snap_tolerance = 1e-9 * rect.width().max(rect.height());
    let snap = |value: f64, min: f64, max: f64| {
        if (value - min).abs() <= snap_tolerance {
            min
        } else if (value - max).abs() <= snap_tolerance {
            max
        } else {
            value
        }
    };
    let mut number = vec![usize::MAX; points.len()];
    let mut vertices = Vec::new();
    let mut polygons = Vec::with_capacity(cells.len());
    let mut k = 0;
    for cell in cells {
        let mut polygon: Vec<usize> = Vec::with_capacity(cell.len());
        for _ in cell {
            let r = root(&mut parent, k);
            if number[r] == usize::MAX {
                number[r] = vertices.len();
                let p = points[r];
                vertices.push(Point::new(
                    snap(p.x, rect.min.x, rect.max.x),
                    snap(p.y, rect.min.y, rect.max.y),
                ));
            }
            polygon.push(number[r]);
            k += 1;
        }
        polygons.push(without_repeats(polygon));
    }
    (vertices, polygons)
}

/// Removes consecutive repeats of a closed loop (including last = first).
fn without_repeats(mut polygon: Vec<usize>) -> Vec<usize> {
    polygon.dedup();
    while polygon.len() > 1 && polygon.first() == polygon.last() {
        polygon.pop();
    }
    polygon
}

/// Where a vertex lies on the boundary of the domain being meshed, for
/// [`collapse_short_edges`]: inside, on one side (straight), or at a corner where two sides
/// meet.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Place {
    Inside,
    Side(usize),
    Corner(usize, usize),
}

impl Place {
    pub(super) fn on(self, side: usize) -> bool {
        match self {
            Place::Inside => false,
            Place::Side(k) => k == side,
            Place::Corner(k, l) => k == side || l == side,
        }
    }
}

/// Where a vertex lies relative to the rectangle: sides 0 left, 1 right, 2 bottom, 3 top.
fn rectangle_place(rect: &Rectangle, p: Point) -> Place {
    let on = [
        p.x == rect.min.x,
        p.x == rect.max.x,
        p.y == rect.min.y,
        p.y == rect.max.y,
    ];
    let mut sides = (0..4).filter(|&k| on[k]);
    match (sides.next(), sides.next()) {
        (None, _) => Place::Inside,
        (Some(k), None) => Place::Side(k),
        (Some(k), Some(l)) => Place::Corner(k, l),
    }
}

/// The point `p` (near side `side` of the rectangle) moved onto that side.
fn onto_rectangle_side(rect: &Rectangle, side: usize, mut p: Point) -> Point {
    match side {
        0 => p.x = rect.min.x,
        1 => p.x = rect.max.x,
        2 => p.y = rect.min.y,
        _ => p.y = rect.max.y,
    }
    p
}

/// Collapses the short edges ([`collapse_short_edges`]) of a partition of `rect`: its
/// corners never move, its sides' vertices stay on them.
fn collapse_short_edges_in(
    rect: &Rectangle,
    vertices: Vec<Point>,
    polygons: Vec<Vec<usize>>,
) -> (Vec<Point>, Vec<Vec<usize>>) {
    collapse_short_edges(
        |p| rectangle_place(rect, p),
        |side, p| onto_rectangle_side(rect, side, p),
        false,
        vertices,
        polygons,
    )
}

/// Collapses edges shorter than [`SHORT_EDGE_RATIO`] times the largest diameter of the cells
/// sharing them, in passes; each pass collapses the shortest such edges first and leaves the
/// vertices it moved alone until the next pass. An edge is kept when collapsing it would leave
/// a cell with fewer than three vertices, join two vertices a cell does not visit one after
/// the other, or move a corner or a vertex off its side of the domain (`place` tells where a
/// vertex lies, `onto(side, p)` moves a point near a side onto it: the midpoint of two
/// vertices of one side). With `drop_triangles`, a short edge of a triangle is collapsed too
/// when the cells across the triangle's two other edges differ: the triangle vanishes and they
/// share the edge it leaves (a sliver the cut of a polygon left at a corner).
pub(super) fn collapse_short_edges(
    place: impl Fn(Point) -> Place,
    onto: impl Fn(usize, Point) -> Point,
    drop_triangles: bool,
    mut vertices: Vec<Point>,
    mut polygons: Vec<Vec<usize>>,
) -> (Vec<Point>, Vec<Vec<usize>>) {
    for _ in 0..MERGE_PASSES {
        let diameters: Vec<f64> = polygons
            .iter()
            .map(|loop_| {
                let points: Vec<Point> = loop_.iter().map(|&v| vertices[v]).collect();
                geometry::diameter(&points)
            })
            .collect();
        // Polygons around each vertex (compressed).
        let mut start = vec![0usize; vertices.len() + 1];
        for &v in polygons.iter().flatten() {
            start[v + 1] += 1;
        }
        for v in 0..vertices.len() {
            start[v + 1] += start[v];
        }
        let mut fill = start.clone();
        let mut around = vec![0usize; start[vertices.len()]];
        for (p, loop_) in polygons.iter().enumerate() {
            for &v in loop_ {
                around[fill[v]] = p;
                fill[v] += 1;
            }
        }
        // Short edges, shortest (relative) first.
        let mut short: Vec<(f64, usize, usize)> = Vec::new();
        for loop_ in &polygons {
            let m = loop_.len();
            for k in 0..m {
                let (a, b) = (
                    loop_[k].min(loop_[(k + 1) % m]),
                    loop_[k].max(loop_[(k + 1) % m]),
                );
                let shared = around[start[a]..start[a + 1]]
                    .iter()
                    .filter(|p| around[start[b]..start[b + 1]].contains(p));
                let h = shared.map(|&p| diameters[p]).fold(0.0, f64::max);
                let ratio = (vertices[b] - vertices[a]).norm() / h;
                if ratio < SHORT_EDGE_RATIO {
                    short.push((ratio, a, b));
                }
            }
        }
        short.sort_by(|x, y| x.0.total_cmp(&y.0).then((x.1, x.2).cmp(&(y.1, y.2))));
        short.dedup_by(|x, y| (x.1, x.2) == (y.1, y.2));
        let mut touched = vec![false; vertices.len()];
        let mut sizes: Vec<usize> = polygons.iter().map(Vec::len).collect();
        let mut target: Vec<usize> = (0..vertices.len()).collect();
        let mut merged = 0;
        for &(_, a, b) in &short {
            if touched[a] || touched[b] {
                continue;
            }
            let shared: Vec<usize> = around[start[a]..start[a + 1]]
                .iter()
                .copied()
                .filter(|p| around[start[b]..start[b + 1]].contains(p))
                .collect();
            let has_edge = |p: usize, a: usize, b: usize| {
                let loop_ = &polygons[p];
                let m = loop_.len();
                (0..m).any(|k| {
                    let (x, y) = (loop_[k], loop_[(k + 1) % m]);
                    (x, y) == (a, b) || (x, y) == (b, a)
                })
            };
            // A triangle may vanish (when `drop_triangles`) if the cells across its two other
            // edges differ: they then share the edge it leaves.
            let vanishes = |p: usize| {
                let Some(c) = polygons[p].iter().copied().find(|&v| v != a && v != b) else {
                    return false;
                };
                let across = |x: usize| {
                    around[start[c]..start[c + 1]]
                        .iter()
                        .copied()
                        .find(|&q| q != p && has_edge(q, x, c))
                };
                drop_triangles
                    && sizes[p] == 3
                    && polygons[p].len() == 3
                    && match (across(a), across(b)) {
                        (Some(qa), Some(qb)) => qa != qb,
                        _ => true,
                    }
            };
            let triangles = shared.iter().filter(|&&p| sizes[p] <= 3).count();
            if shared
                .iter()
                .any(|&p| !has_edge(p, a, b) || (sizes[p] <= 3 && !vanishes(p)))
                || triangles > 1
            {
                continue;
            }
            let (pa, pb) = (vertices[a], vertices[b]);
            let middle = Point::from((pa.coords + pb.coords) * 0.5);
            let position = match (place(pa), place(pb)) {
                (Place::Inside, Place::Inside) => Some(middle),
                (_, Place::Inside) => Some(pa),
                (Place::Inside, _) => Some(pb),
                (corner @ Place::Corner(..), Place::Side(k)) if corner.on(k) => Some(pa),
                (Place::Side(k), corner @ Place::Corner(..)) if corner.on(k) => Some(pb),
                // Both on one side: the midpoint stays on it.
                (Place::Side(k), Place::Side(l)) if k == l => Some(onto(k, middle)),
                _ => None,
            };
            let Some(position) = position else { continue };
            vertices[a] = position;
            target[b] = a;
            touched[a] = true;
            touched[b] = true;
            for p in shared {
                sizes[p] -= 1;
            }
            merged += 1;
        }
        if merged == 0 {
            break;
        }
        for loop_ in &mut polygons {
            let relabelled: Vec<usize> = loop_.iter().map(|&v| target[v]).collect();
            *loop_ = without_repeats(relabelled);
        }
        polygons.retain(|loop_| loop_.len() >= 3);
    }
    // Drop the vertices no polygon uses any more, keeping the order of the others.
    let mut number = vec![usize::MAX; vertices.len()];
    let mut kept = Vec::with_capacity(vertices.len());
    for loop_ in &mut polygons {
        for v in loop_.iter_mut() {
            if number[*v] == usize::MAX {
                number[*v] = kept.len();
                kept.push(vertices[*v]);
            }
            *v = number[*v];
        }
    }
    (kept, polygons)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cells_of_a_regular_lattice_of_sites_are_squares() {
        let rect = Rectangle::unit_square();
        let grid = SiteGrid::new(&rect, 4, 4);
        let sites: Vec<Point> = (0..16)
            .map(|k| Point::new(0.125 + 0.25 * (k % 4) as f64, 0.125 + 0.25 * (k / 4) as f64))
            .collect();
        for (cell, site) in voronoi_cells(&grid, &sites).iter().zip(&sites) {
            let c = geometry::centroid(cell);
            assert!((c - site).norm() < 1e-15);
            assert!((geometry::signed_area(cell) - 0.0625).abs() < 1e-15);
        }
    }

    #[test]
    fn collapsing_keeps_corners_and_sides() {
        // Two cells split by a nearly vertical polyline with a tiny kink at the bottom side.
        let rect = Rectangle::unit_square();
        let vertices = vec![
            Point::new(0.0, 0.0),
            Point::new(0.5, 0.0),
            Point::new(0.501, 0.0),
            Point::new(1.0, 0.0),
            Point::new(1.0, 1.0),
            Point::new(0.5, 1.0),
            Point::new(0.0, 1.0),
        ];
        let polygons = vec![vec![0, 1, 2, 5, 6], vec![2, 3, 4, 5]];
        let (vertices, polygons) = collapse_short_edges_in(&rect, vertices, polygons);
        assert_eq!(vertices.len(), 6);
        assert_eq!(polygons, vec![vec![0, 1, 2, 3], vec![1, 4, 5, 2]]);
        assert_eq!(vertices[1], Point::new(0.5005, 0.0));
    }
}
