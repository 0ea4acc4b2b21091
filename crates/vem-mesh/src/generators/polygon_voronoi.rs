//! Centroidal Voronoi meshes of a polygon by reflected seeds (PolyMesher's method, Talischi et
//! al. 2012), made exact at the polygon's boundary by the cut of [`super::polygon`].
//!
//! # Method
//!
//! 1. Seeds: as many as the Voronoi family puts on the same area of the bounding rectangle
//!    (`n` across its width; the count times the polygon's share of the rectangle's area),
//!    drawn uniformly in the polygon (rejection from the rectangle, a `ChaCha8Rng` seeded with
//!    `seed`).
//! 2. Reflections (PolyMesher's `PolyMshr_Rflct`): a seed closer than [`REFLECTION_RATIO`]
//!    times the seed spacing to an edge of the polygon, on its inner side, is mirrored across
//!    the edge's line; the mirror image is kept when it lies outside the polygon at least
//!    0.9 times the seed's distance to that line away from it (a mirror image across an edge
//!    next to a reflex corner can fall back into the polygon, or close to it: it is dropped).
//!    The bisector of a seed and its image is the edge's line, so the seed's cell ends on the
//!    edge without any cut.
//! 3. Lloyd: the Voronoi cells of the seeds among seeds, images and filler sites (a coarse
//!    lattice far outside the polygon, in the holes of its bounding rectangle, so that no
//!    cell there is large) are computed as in [`super::voronoi`] (the box around the polygon
//!    clipped by bisectors found through a site grid, in parallel, independent of the thread
//!    count); each seed moves to the centroid of its cell intersected with the polygon (a cell
//!    whose bisectors all land on the boundary is inside already; one poking out, at a reflex
//!    corner or where an image was dropped, counts only its part in the polygon); a centroid
//!    outside the polygon (around a reflex corner) leaves the seed where it is.
//!    [`LLOYD_ITERATIONS`] iterations, as on a rectangle.
//! 4. The cells of all sites of the last diagram make a mesh of the box, which the polygon
//!    cuts ([`cut_to_polygon`]): the cells whose edges land on the boundary are unchanged
//!    (the boundary runs along their edges; their vertices there are moved onto it by
//!    round-off only), a cell of a seed poking out of the polygon is clipped, and the pieces of
//!    mirror images' cells reaching into the polygon around a reflex corner are merged into
//!    their neighbours (or split) by the cut's rules. The cut is what makes the result robust
//!    where reflection alone is not (PolyMesher's cells near a reflex corner do not close on
//!    the boundary; it relies on the distance function there): the cells tile the polygon
//!    exactly, every corner of the polygon is a vertex, and the boundary parts are named after
//!    the polygon's edges.
//! 5. A cell holding no seed (a piece of an image's cell the cut kept) joins the neighbouring
//!    seed's cell along whose edges their union is the most star-shaped, when that union is
//!    more star-shaped than the piece: the smallest star ratio never falls, and the cells are
//!    the seeds'.
//! 6. Edges shorter than [`SHORT_EDGE_RATIO`](super::SHORT_EDGE_RATIO) times the diameter of
//!    their cells are collapsed as on a rectangle, the polygon's corners fixed and its edges'
//!    vertices kept on them; a triangle with such an edge (a sliver the cut left at a corner)
//!    vanishes, its neighbours sharing the edge it leaves.
//!
//! Should the cells of the sites not make a valid mesh (sites so close that their computed
//! cells disagree; seen only with a handful of seeds, the L-shape at n = 2), the mesh is the
//! rectangle's Voronoi mesh cut by the polygon ([`PolygonVoronoi::by_reflection`] false).

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

use super::polygon::{
    cut_to_polygon, distance_to_segment, named_parts, parameter_on, PolygonDomain, CUT_TOLERANCE,
};
use super::voronoi::{
    clip_half_plane, collapse_short_edges, conforming, voronoi_cells, voronoi_cells_of,
    voronoi_counts, Place, SiteGrid, LLOYD_ITERATIONS,
};
use super::{voronoi, Rectangle};
use crate::quality::element_quality;
use crate::{geometry, Mesh, MeshError, Point, Vector};

/// A seed closer than this many seed spacings to an edge of the polygon is reflected across
/// it (PolyMesher's `c` in `alpha = c sqrt(area / seeds)`).
pub const REFLECTION_RATIO: f64 = 1.5;

/// A reflected seed is kept when it lies at least this fraction of the seed's distance to the
/// edge's line outside the polygon (PolyMesher's `eta`).
const REFLECTION_KEPT: f64 = 0.9;

/// An image closer than this many seed spacings to its seed (a seed on the boundary to
/// round-off) is left out: the bisector of two so close sites is known too poorly for the
/// cells around it to agree; the seed's cell is clipped by the cut instead.
const CLOSEST_IMAGE: f64 = 1e-3;

/// Filler sites lie at least this many reflection distances outside the polygon.
const FILLER_DISTANCE: f64 = 3.0;

/// A centroidal Voronoi mesh of a polygon ([`polygon_voronoi()`]) with its seeds.
#[derive(Debug, Clone)]
pub struct PolygonVoronoi {
    /// The mesh, boundary parts named after the polygon's edges.
    pub mesh: Mesh,
    /// The seeds of the last Voronoi diagram (after the Lloyd iterations), inside the polygon.
    pub seeds: Vec<Point>,
    /// The number of mirror images of seeds in the last diagram.
    pub reflections: usize,
    /// The seed spacing: `sqrt(area of the bounding rectangle / sites of the Voronoi family
    /// on it)`.
    pub spacing: f64,
    /// False when the cells of the sites did not make a valid mesh (sites too close to one
    /// another, seen only with a handful of seeds) and the mesh is the Voronoi mesh of the
    /// bounding rectangle cut by the polygon ([`cut_to_polygon`]); the seeds are then not
    /// its cells' seeds.
    pub by_reflection: bool,
}

/// The centroidal Voronoi mesh of size `n` of the polygon `domain` by reflected seeds (the
/// method of the [module](self)): about `n` cells across the bounding rectangle's width,
/// the same density as [`super::voronoi`] on it; same `seed`, same mesh, bit for bit, whatever
/// the number of threads.
///
/// ```
/// use vem_mesh::generators::{polygon_voronoi, PolygonDomain};
/// use vem_mesh::Point;
/// let l_shape = PolygonDomain::new(vec![
///     Point::new(0.0, 0.0), Point::new(2.0, 0.0), Point::new(2.0, 1.0),
///     Point::new(1.0, 1.0), Point::new(1.0, 2.0), Point::new(0.0, 2.0),
/// ])?;
/// let voronoi = polygon_voronoi(&l_shape, 10, 1)?;
/// assert_eq!(voronoi.seeds.len(), 75); // 10 x 10 on the square, 3/4 of it in the L
/// let area: f64 = (0..voronoi.mesh.n_polygons()).map(|p| voronoi.mesh.area(p)).sum();
/// assert!((area - 3.0).abs() < 1e-12);
/// # Ok::<(), vem_mesh::MeshError>(())
/// ```
///
/// # Errors
/// [`MeshError::BadGeneratorParameter`] for a size the Voronoi family refuses on the bounding
/// rectangle, or a polygon so thin in its rectangle that its seeds cannot be drawn; the cut's
/// errors (not expected: the cells cover a box around the polygon).
pub fn polygon_voronoi(
    domain: &PolygonDomain,
    n: usize,
    seed: u64,
) -> Result<PolygonVoronoi, MeshError> {
    let rect = domain.bounding_rectangle();
    let (nx, ny) = voronoi_counts(&rect, n)?;
    let rect_area = rect.width() * rect.height();
    let spacing = (rect_area / (nx * ny) as f64).sqrt();
    let count = ((nx * ny) as f64 * domain.area() / rect_area)
        .round()
        .max(1.0) as usize;
    let mut seeds = draw_seeds(domain, &rect, count, seed)?;
    let alpha = REFLECTION_RATIO * spacing;

    // The box holding the seeds' images (within alpha of the polygon), with fillers in its
    // parts far from the polygon.
    let margin = 2.0 * alpha;
    let bounds = Rectangle::new(
        rect.min - Vector::new(margin, margin),
        rect.max + Vector::new(margin, margin),
    );
    let fillers = fillers(domain, &bounds, 2.0 * spacing, FILLER_DISTANCE * alpha);
    let closest = CLOSEST_IMAGE * spacing;
    let grid = SiteGrid::new(
        &bounds,
        (bounds.width() / spacing).ceil() as usize,
        (bounds.height() / spacing).ceil() as usize,
    );
    for _ in 0..LLOYD_ITERATIONS {
        let (sites, distances) = sites(domain, &seeds, [alpha, closest], &fillers);
        let cells = voronoi_cells_of(&grid, &sites, seeds.len());
        seeds = seeds
            .par_iter()
            .zip(&cells)
            .zip(&distances)
            .map(|((&site, cell), &distance)| {
                let centroid = centroid_in(domain, cell, site, distance);
                if domain.contains(centroid) {
                    centroid
                } else {
                    site
                }
            })
            .collect();
    }
    let (sites, _) = sites(domain, &seeds, [alpha, closest], &fillers);
    let reflections = sites.len() - seeds.len() - fillers.len();
    let cells = voronoi_cells(&grid, &sites);
    let (vertices, polygons) = conforming(&bounds, &cells, 1e-9 * spacing);
    let (vertices, polygons) = used(&vertices, polygons.into_iter().filter(|p| p.len() >= 3));
    let Ok(background) = Mesh::from_polygons(vertices, &polygons, Vec::new()) else {
        // Sites so close that their cells disagree (seen only with a handful of seeds, each
        // mirrored across most edges): the Voronoi mesh of the rectangle, cut.
        return Ok(PolygonVoronoi {
            mesh: cut_to_polygon(&voronoi(&rect, n, seed)?, domain)?,
            seeds,
            reflections,
            spacing,
            by_reflection: false,
        });
    };
    let cut = cut_to_polygon(&background, domain)?;
    let mesh = collapsed(domain, &cut, &seeds, spacing).unwrap_or(cut);
    Ok(PolygonVoronoi {
        mesh,
        seeds,
        reflections,
        spacing,
        by_reflection: true,
    })
}

/// `count` points drawn uniformly in the polygon: uniform in its bounding rectangle, those
/// outside rejected.
fn draw_seeds(
    domain: &PolygonDomain,
    rect: &Rectangle,
    count: usize,
    seed: u64,
) -> Result<Vec<Point>, MeshError> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut seeds = Vec::with_capacity(count);
    // The polygon covers at least area / rectangle of the draws; 1000 times fewer is a
    // polygon too thin to seed.
    let limit = 1000 * count.max(1000);
    let mut draws = 0usize;
    while seeds.len() < count {
        draws += 1;
        if draws > limit {
            return Err(MeshError::BadGeneratorParameter {
                generator: "polygon_voronoi",
                reason: format!(
                    "{draws} random points of the bounding rectangle gave {} of the {count} \
                     seeds in the polygon: it is too thin in its rectangle",
                    seeds.len()
                ),
            });
        }
        let p = Point::new(
            rng.gen_range(rect.min.x..rect.max.x),
            rng.gen_range(rect.min.y..rect.max.y),
        );
        if domain.contains(p) {
            seeds.push(p);
        }
    }
    Ok(seeds)
}

/// The points of a lattice of step `step` in `bounds` farther than `distance` outside the
/// polygon: sites that bound the cells of the images in the holes of the bounding rectangle
/// and never own a point of the polygon.
fn fillers(domain: &PolygonDomain, bounds: &Rectangle, step: f64, distance: f64) -> Vec<Point> {
    let (nx, ny) = (
        (bounds.width() / step).floor() as usize,
        (bounds.height() / step).floor() as usize,
    );
    (0..ny)
        .flat_map(|j| (0..nx).map(move |i| (i, j)))
        .map(|(i, j)| bounds.min + Vector::new((i as f64 + 0.5) * step, (j as f64 + 0.5) * step))
        .filter(|&p| !domain.contains(p) && domain.closest_on_boundary(p).0 >= distance)
        .collect()
}

/// The sites of a diagram (the seeds, their images in the order of the seeds, the fillers)
/// and each seed's distance to the boundary.
fn sites(
    domain: &PolygonDomain,
    seeds: &[Point],
    reach: [f64; 2],
    fillers: &[Point],
) -> (Vec<Point>, Vec<f64>) {
    let images: Vec<(f64, Vec<Point>)> = seeds
        .par_iter()
        .map(|&seed| reflections(domain, seed, reach))
        .collect();
    let mut sites = seeds.to_vec();
    sites.extend(images.iter().flat_map(|(_, points)| points.iter().copied()));
    sites.extend_from_slice(fillers);
    (sites, images.iter().map(|(d, _)| *d).collect())
}

/// The mirror images of `seed` across the edges of the polygon closer than `alpha`
/// (PolyMesher's rule, the [module](self)'s step 2; images closer than `closest` to the seed
/// are left out) and its distance to the boundary.
fn reflections(
    domain: &PolygonDomain,
    seed: Point,
    [alpha, closest]: [f64; 2],
) -> (f64, Vec<Point>) {
    let mut nearest = f64::INFINITY;
    let mut images = Vec::new();
    for k in 0..domain.vertices().len() {
        let [a, b] = domain.edge(k);
        let (distance, _) = distance_to_segment(seed, a, b);
        nearest = nearest.min(distance);
        if distance >= alpha {
            continue;
        }
        let normal = geometry::outward_normal(a, b);
        // Negative on the inner side of the edge's line.
        let line = (seed - a).dot(&normal);
        if line >= 0.0 || 2.0 * line.abs() < closest {
            continue;
        }
        let image = seed - 2.0 * line * normal;
        if domain.contains(image)
            || domain.closest_on_boundary(image).0 < REFLECTION_KEPT * line.abs()
        {
            continue;
        }
        images.push(image);
    }
    (nearest, images)
}

/// The centroid of the convex `cell` of `site` intersected with the polygon (`distance` the
/// site's distance to the boundary: a cell within it is inside the polygon).
fn centroid_in(domain: &PolygonDomain, cell: &[Point], site: Point, distance: f64) -> Point {
    if cell.len() < 3 {
        return site;
    }
    let radius = cell.iter().map(|v| (v - site).norm()).fold(0.0, f64::max);
    if radius < distance {
        return geometry::centroid(cell);
    }
    let mut clipped = domain.vertices().to_vec();
    let mut scratch = Vec::new();
    let m = cell.len();
    for i in 0..m {
        let (a, b) = (cell[i], cell[(i + 1) % m]);
        let t = b - a;
        // The direction of an edge of round-off length is round-off: the half-planes of its
        // neighbours bound the cell there.
        if t.norm() <= 1e-6 * radius {
            continue;
        }
        clip_half_plane(&clipped, a, Vector::new(t.y, -t.x), &mut scratch);
        std::mem::swap(&mut clipped, &mut scratch);
        if clipped.is_empty() {
            return site;
        }
    }
    if geometry::signed_area(&clipped) <= 0.0 {
        return site;
    }
    geometry::centroid(&clipped)
}

/// The vertices used by `polygons`, renumbered in order of first use.
fn used(
    vertices: &[Point],
    polygons: impl Iterator<Item = Vec<usize>>,
) -> (Vec<Point>, Vec<Vec<usize>>) {
    let mut number = vec![usize::MAX; vertices.len()];
    let mut kept = Vec::new();
    let polygons = polygons
        .map(|mut polygon| {
            for v in polygon.iter_mut() {
                if number[*v] == usize::MAX {
                    number[*v] = kept.len();
                    kept.push(vertices[*v]);
                }
                *v = number[*v];
            }
            polygon
        })
        .collect();
    (kept, polygons)
}

/// Where `p` lies on the polygon's boundary (to the cut's round-off `tolerance`).
fn place(domain: &PolygonDomain, tolerance: f64, p: Point) -> Place {
    let corners = domain.vertices();
    let m = corners.len();
    if let Some(k) = corners.iter().position(|c| (p - c).norm() <= tolerance) {
        return Place::Corner((k + m - 1) % m, k);
    }
    (0..m)
        .find(|&k| {
            let [a, b] = domain.edge(k);
            distance_to_segment(p, a, b).0 <= tolerance
        })
        .map_or(Place::Inside, Place::Side)
}

/// The cut mesh with its cells holding no seed joined to a neighbour ([`join_orphans`]), its
/// short edges collapsed (the corners fixed, the vertices on an edge kept on it) and its parts
/// named again; `None` when the result is not a valid mesh (not expected; the cut mesh is kept
/// then).
fn collapsed(domain: &PolygonDomain, cut: &Mesh, seeds: &[Point], spacing: f64) -> Option<Mesh> {
    let rect = domain.bounding_rectangle();
    let tolerance = CUT_TOLERANCE * (rect.max - rect.min).norm();
    let at = |p: Point| place(domain, tolerance, p);
    let onto = |k: usize, p: Point| {
        let [a, b] = domain.edge(k);
        a + (b - a) * parameter_on(p, a, b)
    };
    let polygons: Vec<Vec<usize>> = cut.polygons().map(<[usize]>::to_vec).collect();
    let polygons = join_orphans(cut.vertices(), polygons, seeds, &rect, spacing);
    let (vertices, polygons) =
        collapse_short_edges(at, onto, true, cut.vertices().to_vec(), polygons);
    // A mesh edge with both ends on polygon edge k lies on it: a boundary edge of part k.
    let places: Vec<Place> = vertices.iter().map(|&p| at(p)).collect();
    let mut boundary = Vec::new();
    for polygon in &polygons {
        let m = polygon.len();
        for i in 0..m {
            let (u, v) = (polygon[i], polygon[(i + 1) % m]);
            let shared = (0..domain.vertices().len()).find(|&k| places[u].on(k) && places[v].on(k));
            if let Some(k) = shared {
                boundary.push((k, [u, v]));
            }
        }
    }
    Mesh::from_polygons(vertices, &polygons, named_parts(domain, boundary)).ok()
}

/// The cells holding no seed (pieces of the cells of mirror images reaching into the polygon
/// around a reflex corner, which the cut kept) joined each to the neighbour, holding a seed,
/// along whose edges their union is the most star-shaped, when that union is more star-shaped
/// than the piece alone (the smallest star ratio of the mesh never falls): the cells are
/// then those of the seeds, as in PolyMesher.
fn join_orphans(
    vertices: &[Point],
    mut polygons: Vec<Vec<usize>>,
    seeds: &[Point],
    rect: &Rectangle,
    spacing: f64,
) -> Vec<Vec<usize>> {
    let points = |loop_: &[usize]| -> Vec<Point> { loop_.iter().map(|&v| vertices[v]).collect() };
    // The seeds bucketed on a grid of the seed spacing.
    let (nx, ny) = (
        (rect.width() / spacing).ceil().max(1.0) as usize,
        (rect.height() / spacing).ceil().max(1.0) as usize,
    );
    let bucket = |p: Point| {
        let i = (((p.x - rect.min.x) / spacing).floor().max(0.0) as usize).min(nx - 1);
        let j = (((p.y - rect.min.y) / spacing).floor().max(0.0) as usize).min(ny - 1);
        (i, j)
    };
    let mut buckets: Vec<Vec<usize>> = vec![Vec::new(); nx * ny];
    for (k, &seed) in seeds.iter().enumerate() {
        let (i, j) = bucket(seed);
        buckets[j * nx + i].push(k);
    }
    let holds_seed = |loop_: &[usize]| {
        let polygon = points(loop_);
        let (mut lo, mut hi) = (polygon[0], polygon[0]);
        for p in &polygon {
            lo = Point::new(lo.x.min(p.x), lo.y.min(p.y));
            hi = Point::new(hi.x.max(p.x), hi.y.max(p.y));
        }
        let ((i0, j0), (i1, j1)) = (bucket(lo), bucket(hi));
        (j0..=j1).any(|j| {
            (i0..=i1).any(|i| {
                buckets[j * nx + i]
                    .iter()
                    .any(|&k| geometry::contains(&polygon, seeds[k]))
            })
        })
    };
    let orphans: Vec<usize> = (0..polygons.len())
        .filter(|&p| !holds_seed(&polygons[p]))
        .collect();
    if orphans.is_empty() {
        return polygons;
    }
    let mut around: Vec<Vec<usize>> = vec![Vec::new(); vertices.len()];
    for (p, loop_) in polygons.iter().enumerate() {
        for &v in loop_ {
            around[v].push(p);
        }
    }
    let mut alive = vec![true; polygons.len()];
    let mut is_orphan = vec![false; polygons.len()];
    for &p in &orphans {
        is_orphan[p] = true;
    }
    for &p in &orphans {
        let own = element_quality(&points(&polygons[p])).star_ratio;
        let mut neighbours: Vec<usize> = polygons[p]
            .iter()
            .flat_map(|&v| around[v].iter().copied())
            .filter(|&q| q != p && alive[q] && !is_orphan[q])
            .collect();
        neighbours.sort_unstable();
        neighbours.dedup();
        let best = neighbours
            .into_iter()
            .filter_map(|q| {
                let joined = union(&polygons[p], &polygons[q])?;
                let star = element_quality(&points(&joined)).star_ratio;
                Some((star, q, joined))
            })
            .max_by(|a, b| a.0.total_cmp(&b.0).then(b.1.cmp(&a.1)));
        if let Some((star, q, joined)) = best {
            if star > own {
                for &v in &polygons[p] {
                    if !around[v].contains(&q) {
                        around[v].push(q);
                    }
                }
                polygons[q] = joined;
                alive[p] = false;
            }
        }
    }
    polygons
        .into_iter()
        .zip(alive)
        .filter_map(|(loop_, alive)| alive.then_some(loop_))
        .collect()
}

/// The union of two counter-clockwise cells sharing one connected run of edges and no other
/// vertex; `None` otherwise.
fn union(p: &[usize], q: &[usize]) -> Option<Vec<usize>> {
    let m = p.len();
    let k = q.len();
    let in_q = |x: usize, y: usize| (0..k).any(|i| q[i] == y && q[(i + 1) % k] == x);
    let run: Vec<bool> = (0..m).map(|i| in_q(p[i], p[(i + 1) % m])).collect();
    let ends: Vec<usize> = (0..m).filter(|&i| run[i] && !run[(i + 1) % m]).collect();
    let length = run.iter().filter(|&&r| r).count();
    let common = p.iter().filter(|v| q.contains(v)).count();
    if ends.len() != 1 || length >= m || length >= k || common != length + 1 {
        return None;
    }
    // p from the run's last vertex round to its first, then q after the run's first vertex
    // (where q leaves the run) round to before its last.
    let last = (ends[0] + 1) % m;
    let mut joined: Vec<usize> = (0..=m - length).map(|i| p[(last + i) % m]).collect();
    let first = p[(last + m - length) % m];
    let start = q.iter().position(|&v| v == first)?;
    joined.extend((1..k - length).map(|i| q[(start + i) % k]));
    Some(joined)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A seed near an edge is reflected across it; near a reflex corner, the image across the
    /// edge that would fall back into the polygon is dropped.
    #[test]
    fn seeds_near_edges_are_reflected_outside_only() {
        let l_shape = PolygonDomain::new(vec![
            Point::new(0.0, 0.0),
            Point::new(2.0, 0.0),
            Point::new(2.0, 1.0),
            Point::new(1.0, 1.0),
            Point::new(1.0, 2.0),
            Point::new(0.0, 2.0),
        ])
        .unwrap();
        let (d, images) = reflections(&l_shape, Point::new(0.5, 0.1), [0.3, 1e-3]);
        assert!((d - 0.1).abs() < 1e-15);
        assert_eq!(images.len(), 1);
        assert!((images[0] - Point::new(0.5, -0.1)).norm() < 1e-15);
        // Near the corner (0, 0): across both edges.
        let (_, images) = reflections(&l_shape, Point::new(0.1, 0.2), [0.3, 1e-3]);
        assert_eq!(images.len(), 2);
        // Below edge 2 (y = 1, x in [1, 2]) by 0.1: the image (1.5, 1.1) is 0.1 outside.
        let (_, images) = reflections(&l_shape, Point::new(1.5, 0.9), [0.3, 1e-3]);
        assert_eq!(images, vec![Point::new(1.5, 1.1)]);
        // The same near the reflex corner (1, 1): the image (1.05, 1.1) is only 0.05 from
        // edge 3 (x = 1), less than 0.9 times 0.1, and dropped; the seed lies on the outer side
        // of edge 3's line.
        let (_, images) = reflections(&l_shape, Point::new(1.05, 0.9), [0.3, 1e-3]);
        assert!(images.is_empty(), "{images:?}");
    }

    /// Two squares side by side sharing an edge make a rectangle of six vertices; an L of
    /// three squares joined along two edges; cells meeting at a vertex only do not join.
    #[test]
    fn union_of_cells_along_a_run_of_edges() {
        // 3 - 4 - 5
        // |   |   |
        // 0 - 1 - 2
        assert_eq!(
            union(&[0, 1, 4, 3], &[1, 2, 5, 4]),
            Some(vec![4, 3, 0, 1, 2, 5])
        );
        // p = 0 1 6 4 3 (a pentagon with 6 between 1 and 4), q = 1 2 5 4 6.
        assert_eq!(
            union(&[0, 1, 6, 4, 3], &[1, 2, 5, 4, 6]),
            Some(vec![4, 3, 0, 1, 2, 5])
        );
        assert_eq!(union(&[0, 1, 4, 3], &[4, 5, 7, 6]), None);
    }
}
