//! Mesh validation: every constructor of [`crate::Mesh`] runs these checks.
//!
//! Checks, in the order they run (the first failure is returned):
//!
//! 1. storage: offsets, index range, repeated indices in a loop, at least three vertices per
//!    polygon, finite coordinates ([`MeshError::BadStorage`], [`MeshError::VertexOutOfRange`],
//!    [`MeshError::RepeatedVertex`], [`MeshError::TooFewVertices`],
//!    [`MeshError::NonFiniteVertex`]); edges used by more than two polygons or twice in the same
//!    direction are rejected while the edges are derived ([`MeshError::OverusedEdge`]);
//! 2. duplicate vertices: two distinct vertices used by polygons and closer than the
//!    coincidence tolerance ([`MeshError::DuplicateVertices`]);
//! 3. per polygon: simplicity (no two of its edges cross or touch away from a shared end point,
//!    no edge folds back onto the previous one: [`MeshError::SelfIntersecting`]), then area
//!    ([`MeshError::DegenerateArea`], also for an area that overflows) and orientation ([`MeshError::Clockwise`]);
//! 4. conformity: an end point of one edge lying in the interior of an edge of another polygon
//!    (a hanging node the neighbour does not list, or collinear edges overlapping without
//!    shared vertices: [`MeshError::NonConforming`]); two edges of different polygons crossing
//!    ([`MeshError::Overlapping`]);
//! 5. wedges: around every vertex, the corners of the polygons meeting there must not overlap
//!    ([`MeshError::Overlapping`]);
//! 6. nesting: no connected component of the mesh lies inside a polygon of another component
//!    ([`MeshError::Overlapping`]).
//!
//! Together, 4–6 guarantee that the polygons do not overlap: if two polygons overlapped
//! without any crossing, T-junction or overlapping corner, the boundary of one would lie
//! strictly inside the other, and so would its whole connected component.
//!
//! # Tolerances
//!
//! Coincidence is decided relative to the mesh size: the tolerance is
//! [`COINCIDENCE_RATIO`] times the mean over the polygons of the diagonal of their bounding
//! box (a stand-in for h_T within a factor sqrt 2, computable in linear time). Two vertices
//! closer than it are duplicates; a vertex closer than it to an edge, and farther than it from
//! both end points, lies in the edge's interior. A polygon is degenerate when
//! |area| <= [`DEGENERATE_AREA_RATIO`] times its squared bounding-box diagonal.
//!
//! # Cost
//!
//! Everything is close to linear in the size of the mesh (about 1 s for 10^6 vertices on one
//! core): duplicates by sorting the vertices by the cell of side 4 x tolerance that holds them
//! and searching the neighbouring cells, edge pairs through a uniform grid of cells about the
//! mean edge length, corners by sorting them by angle around each vertex. Only polygons that are not convex are checked pair by pair (through a grid when they
//! have more than 64 edges).

use crate::{Mesh, MeshError, Point, Vector};

/// Relative area below which a polygon counts as degenerate: |area| <= this * diagonal^2,
/// with the diagonal of the polygon's bounding box.
pub const DEGENERATE_AREA_RATIO: f64 = 1e-12;

/// Relative coincidence tolerance: vertices closer than this times the mean polygon size (mean
/// bounding-box diagonal) are duplicates, and a vertex that close to an edge lies on it.
pub const COINCIDENCE_RATIO: f64 = 1e-10;

/// Polygons with more edges than this are checked for self-intersection through a grid rather
/// than pair by pair.
const BRUTE_FORCE_EDGES: usize = 64;

/// Angular slack (radians) when comparing corners around a vertex.
const ANGLE_TOLERANCE: f64 = 1e-9;

/// Checks the compact storage before edges are derived.
pub(crate) fn check_storage(
    vertices: &[Point],
    offsets: &[usize],
    indices: &[usize],
) -> Result<(), MeshError> {
    if vertices.is_empty() || offsets.len() < 2 {
        return Err(MeshError::Empty {
            vertices: vertices.len(),
            polygons: offsets.len().saturating_sub(1),
        });
    }
    if let Some((vertex, p)) = vertices
        .iter()
        .enumerate()
        .find(|(_, p)| !(p.x.is_finite() && p.y.is_finite()))
    {
        return Err(MeshError::NonFiniteVertex {
            vertex,
            x: p.x,
            y: p.y,
        });
    }
    let last = offsets[offsets.len() - 1];
    if offsets[0] != 0 || last != indices.len() {
        return Err(MeshError::BadStorage {
            reason: format!(
                "offsets must start at 0 and end at the number of indices ({}), found {} .. {}",
                indices.len(),
                offsets[0],
                last
            ),
        });
    }
    if let Some(p) = (0..offsets.len() - 1).find(|&p| offsets[p + 1] < offsets[p]) {
        return Err(MeshError::BadStorage {
            reason: format!("offsets decrease at polygon {p}"),
        });
    }
    let mut sorted = Vec::new();
    for p in 0..offsets.len() - 1 {
        let loop_ = &indices[offsets[p]..offsets[p + 1]];
        if loop_.len() < 3 {
            return Err(MeshError::TooFewVertices {
                polygon: p,
                count: loop_.len(),
            });
        }
        if let Some(&vertex) = loop_.iter().find(|&&v| v >= vertices.len()) {
            return Err(MeshError::VertexOutOfRange {
                polygon: p,
                vertex,
                vertex_count: vertices.len(),
            });
        }
        sorted.clear();
        sorted.extend_from_slice(loop_);
        sorted.sort_unstable();
        if let Some(w) = sorted.windows(2).find(|w| w[0] == w[1]) {
            return Err(MeshError::RepeatedVertex {
                polygon: p,
                vertex: w[0],
            });
        }
    }
    Ok(())
}

/// Checks a mesh whose storage and edges are consistent (steps 2–6 of the module docs).
pub(crate) fn validate(mesh: &Mesh) -> Result<(), MeshError> {
    // An extent that overflows leaves the coincidence tests to the area check below.
    let tolerance = coincidence_tolerance(mesh).min(f64::MAX);
    check_duplicate_vertices(mesh, tolerance)?;
    let mut points = Vec::new();
    for p in 0..mesh.n_polygons() {
        points.clear();
        points.extend(mesh.polygon(p).iter().map(|&v| mesh.vertex(v)));
        check_polygon(p, &points, tolerance)?;
    }
    check_conformity(mesh, tolerance)?;
    check_corners(mesh)?;
    check_nesting(mesh)
}

/// The coincidence tolerance of `mesh`: [`COINCIDENCE_RATIO`] times the mean bounding-box
/// diagonal of its polygons.
pub fn coincidence_tolerance(mesh: &Mesh) -> f64 {
    let total: f64 = (0..mesh.n_polygons())
        .map(|p| Aabb::of_points(mesh.polygon(p).iter().map(|&v| mesh.vertex(v))).diagonal())
        .sum();
    COINCIDENCE_RATIO * total / mesh.n_polygons() as f64
}

/// Step 2: no two distinct vertices used by polygons closer than `tolerance`.
///
/// The vertices are sorted by the cell (of side 4 * tolerance) that holds them; each vertex
/// then looks for partners in the at most 2 x 2 cells its tolerance disc touches, by binary
/// search in the sorted list.
fn check_duplicate_vertices(mesh: &Mesh, tolerance: f64) -> Result<(), MeshError> {
    let mut used = vec![false; mesh.n_vertices()];
    for &v in mesh.polygon_vertex_indices() {
        used[v] = true;
    }
    let vertices = mesh.vertices();
    let cell = 4.0 * tolerance;
    let key = |x: f64, y: f64| -> (i64, i64) {
        if cell > 0.0 {
            // `as` saturates: far-away points share border cells, which costs time, not truth.
            ((x / cell).floor() as i64, (y / cell).floor() as i64)
        } else {
            (x.to_bits() as i64, y.to_bits() as i64)
        }
    };
    let mut sorted: Vec<((i64, i64), usize)> = (0..vertices.len())
        .filter(|&v| used[v])
        .map(|v| (key(vertices[v].x, vertices[v].y), v))
        .collect();
    sorted.sort_unstable();
    let mut found: Option<(usize, usize, f64)> = None;
    for &(_, a) in &sorted {
        let pa = vertices[a];
        let (lo, hi) = (
            key(pa.x - tolerance, pa.y - tolerance),
            key(pa.x + tolerance, pa.y + tolerance),
        );
        for cx in lo.0..=hi.0 {
            for cy in lo.1..=hi.1 {
                let start = sorted.partition_point(|&(k, _)| k < (cx, cy));
                for &(k, b) in &sorted[start..] {
                    if k != (cx, cy) {
                        break;
                    }
                    let distance = (vertices[b] - pa).norm();
                    if a < b && distance <= tolerance {
                        let better = found.is_none_or(|(fa, fb, _)| (a, b) < (fa, fb));
                        if better {
                            found = Some((a, b, distance));
                        }
                    }
                }
            }
        }
    }
    match found {
        Some((a, b, distance)) => Err(MeshError::DuplicateVertices {
            a,
            b,
            distance,
            tolerance,
        }),
        None => Ok(()),
    }
}

/// Step 3 for one polygon given by its points: simple, non-degenerate, counter-clockwise.
fn check_polygon(polygon: usize, points: &[Point], tolerance: f64) -> Result<(), MeshError> {
    if let Some((edge_a, edge_b)) = self_intersection(points, tolerance) {
        return Err(MeshError::SelfIntersecting {
            polygon,
            edge_a,
            edge_b,
        });
    }
    let area = crate::geometry::signed_area(points);
    let diagonal = Aabb::of_points(points.iter().copied()).diagonal();
    // A non-finite area (coordinates so large that products overflow) is no usable polygon.
    if !area.is_finite() || area.abs() <= DEGENERATE_AREA_RATIO * diagonal * diagonal {
        return Err(MeshError::DegenerateArea { polygon, area });
    }
    if area < 0.0 {
        return Err(MeshError::Clockwise {
            polygon,
            signed_area: area,
        });
    }
    Ok(())
}

/// The first pair of local edges (k < l; edge k joins points k and k + 1) of the closed loop
/// `points` that cross or touch away from a shared end point, if any.
///
/// A loop whose turns are all strictly left and whose total turning is 2 pi is convex and
/// simple, and is accepted at once; others are checked pair by pair.
pub fn self_intersection(points: &[Point], tolerance: f64) -> Option<(usize, usize)> {
    let m = points.len();
    if is_convex_loop(points) {
        return None;
    }
    let edge = |k: usize| -> ([usize; 2], [Point; 2]) {
        let l = (k + 1) % m;
        ([k, l], [points[k], points[l]])
    };
    let test = |k: usize, l: usize| -> bool {
        let (ia, a) = edge(k);
        let (ib, b) = edge(l);
        segments_conflict(ia, a, ib, b, tolerance) != Conflict::None
    };
    if m <= BRUTE_FORCE_EDGES {
        for k in 0..m {
            for l in k + 1..m {
                if test(k, l) {
                    return Some((k, l));
                }
            }
        }
        return None;
    }
    let boxes: Vec<Aabb> = (0..m)
        .map(|k| Aabb::of_points(edge(k).1.into_iter()))
        .collect();
    let mut found: Option<(usize, usize)> = None;
    Grid::new(&boxes).for_each_pair(&boxes, |k, l| {
        let pair = (k.min(l), k.max(l));
        if found.is_none_or(|f| pair < f) && test(pair.0, pair.1) {
            found = Some(pair);
        }
    });
    found
}

/// True when every turn of the loop is strictly to the left (or straight on) and the total
/// turning is one full turn: the loop is then convex and simple.
fn is_convex_loop(points: &[Point]) -> bool {
    let m = points.len();
    let mut turning = 0.0;
    for k in 0..m {
        let incoming = points[k] - points[(k + m - 1) % m];
        let outgoing = points[(k + 1) % m] - points[k];
        let c = cross(incoming, outgoing);
        let d = incoming.dot(&outgoing);
        if c < 0.0 || (c == 0.0 && d <= 0.0) {
            return false;
        }
        turning += c.atan2(d);
    }
    (turning - std::f64::consts::TAU).abs() < 1e-6
}

/// Step 4: edges of different polygons neither cross nor touch away from shared vertices.
fn check_conformity(mesh: &Mesh, tolerance: f64) -> Result<(), MeshError> {
    let edges = mesh.edges();
    let boxes: Vec<Aabb> = edges
        .iter()
        .map(|e| Aabb::of_points(e.vertices.iter().map(|&v| mesh.vertex(v))))
        .collect();
    // Keep the conflict with the smallest edge pair, so the report does not depend on the grid.
    let mut found: Option<((usize, usize), Conflict)> = None;
    Grid::new(&boxes).for_each_pair(&boxes, |e, f| {
        let pair = (e.min(f), e.max(f));
        if found.is_some_and(|(best, _)| best <= pair) {
            return;
        }
        let (ea, eb) = (&edges[pair.0], &edges[pair.1]);
        let polygons_a = [Some(ea.left), ea.right];
        if polygons_a.contains(&Some(eb.left))
            || (eb.right.is_some() && polygons_a.contains(&eb.right))
        {
            return; // a pair within one polygon: checked by `self_intersection`
        }
        let points = |edge: &crate::Edge| edge.vertices.map(|v| mesh.vertex(v));
        let conflict =
            segments_conflict(ea.vertices, points(ea), eb.vertices, points(eb), tolerance);
        if conflict != Conflict::None {
            found = Some((pair, conflict));
        }
    });
    match found {
        None => Ok(()),
        Some(((e, f), conflict)) => {
            let (ea, eb) = (&edges[e], &edges[f]);
            Err(match conflict {
                Conflict::Cross => MeshError::Overlapping {
                    a: ea.left,
                    b: eb.left,
                },
                _ => MeshError::NonConforming {
                    polygon_a: ea.left,
                    a0: ea.vertices[0],
                    a1: ea.vertices[1],
                    polygon_b: eb.left,
                    b0: eb.vertices[0],
                    b1: eb.vertices[1],
                },
            })
        }
    }
}

/// Step 5: around each vertex, the polygon corners (angular sectors from the outgoing edge
/// counter-clockwise to the incoming one) do not overlap.
fn check_corners(mesh: &Mesh) -> Result<(), MeshError> {
    let n = mesh.n_vertices();
    let mut start = vec![0usize; n + 1];
    for &v in mesh.polygon_vertex_indices() {
        start[v + 1] += 1;
    }
    for v in 0..n {
        start[v + 1] += start[v];
    }
    let mut fill = start.clone();
    let mut corners = vec![(0usize, 0usize); start[n]];
    for p in 0..mesh.n_polygons() {
        for (k, &v) in mesh.polygon(p).iter().enumerate() {
            corners[fill[v]] = (p, k);
            fill[v] += 1;
        }
    }
    // (start angle, opening angle, polygon)
    let mut sectors: Vec<(f64, f64, usize)> = Vec::new();
    for v in 0..n {
        let around = &corners[start[v]..start[v + 1]];
        if around.len() < 2 {
            continue;
        }
        let centre = mesh.vertex(v);
        sectors.clear();
        for &(p, k) in around {
            let loop_ = mesh.polygon(p);
            let m = loop_.len();
            let next = mesh.vertex(loop_[(k + 1) % m]) - centre;
            let prev = mesh.vertex(loop_[(k + m - 1) % m]) - centre;
            let from = next.y.atan2(next.x);
            let opening = (prev.y.atan2(prev.x) - from).rem_euclid(std::f64::consts::TAU);
            sectors.push((from, opening, p));
        }
        sectors.sort_by(|a, b| a.0.total_cmp(&b.0));
        let count = sectors.len();
        for i in 0..count {
            let (from, opening, p) = sectors[i];
            let (next_from, _, q) = sectors[(i + 1) % count];
            let next_from = if i + 1 == count {
                next_from + std::f64::consts::TAU
            } else {
                next_from
            };
            if from + opening > next_from + ANGLE_TOLERANCE {
                return Err(MeshError::Overlapping {
                    a: p.min(q),
                    b: p.max(q),
                });
            }
        }
    }
    Ok(())
}

/// Step 6: no connected component (polygons linked through shared vertices) has a vertex
/// strictly inside a polygon of another component.
fn check_nesting(mesh: &Mesh) -> Result<(), MeshError> {
    let mut parent: Vec<usize> = (0..mesh.n_vertices()).collect();
    fn root(parent: &mut [usize], mut v: usize) -> usize {
        while parent[v] != v {
            parent[v] = parent[parent[v]];
            v = parent[v];
        }
        v
    }
    for p in 0..mesh.n_polygons() {
        let loop_ = mesh.polygon(p);
        for &v in &loop_[1..] {
            let (r, first) = (root(&mut parent, v), root(&mut parent, loop_[0]));
            if r != first {
                parent[r.max(first)] = r.min(first);
            }
        }
    }
    // One representative (polygon, vertex) per component, in polygon order.
    let mut representative: Vec<(usize, usize)> = Vec::new();
    let mut seen = vec![false; mesh.n_vertices()];
    for p in 0..mesh.n_polygons() {
        let v = mesh.polygon(p)[0];
        let r = root(&mut parent, v);
        if !seen[r] {
            seen[r] = true;
            representative.push((p, v));
        }
    }
    if representative.len() < 2 {
        return Ok(());
    }
    let boxes: Vec<Aabb> = representative
        .iter()
        .map(|&(_, v)| Aabb::of_points(std::iter::once(mesh.vertex(v))))
        .collect();
    let grid = Grid::new(&boxes);
    let mut points = Vec::new();
    for q in 0..mesh.n_polygons() {
        points.clear();
        points.extend(mesh.polygon(q).iter().map(|&v| mesh.vertex(v)));
        let bounds = Aabb::of_points(points.iter().copied());
        let component = root(&mut parent, mesh.polygon(q)[0]);
        let mut hit = None;
        grid.for_each_in(&bounds, |i| {
            let (p, v) = representative[i];
            if hit.is_none()
                && root(&mut parent, v) != component
                && bounds.contains(mesh.vertex(v))
                && strictly_inside(mesh.vertex(v), &points)
            {
                hit = Some(p);
            }
        });
        if let Some(p) = hit {
            return Err(MeshError::Overlapping {
                a: p.min(q),
                b: p.max(q),
            });
        }
    }
    Ok(())
}

/// Crossing-number test; the point is known not to lie on the loop.
fn strictly_inside(point: Point, loop_: &[Point]) -> bool {
    let m = loop_.len();
    let mut inside = false;
    for k in 0..m {
        let (a, b) = (loop_[k], loop_[(k + 1) % m]);
        if (a.y > point.y) != (b.y > point.y) {
            let x = a.x + (point.y - a.y) / (b.y - a.y) * (b.x - a.x);
            if x > point.x {
                inside = !inside;
            }
        }
    }
    inside
}

/// z-component of the cross product.
fn cross(a: Vector, b: Vector) -> f64 {
    a.x * b.y - a.y * b.x
}

/// How two segments meet.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Conflict {
    /// Only at shared end points, or not at all.
    None,
    /// They cross at a point interior to both.
    Cross,
    /// An end point of one lies in the interior of the other.
    Touch,
}

/// How segments `a` and `b` (with vertex indices `ia`, `ib`) meet, up to `tolerance`.
fn segments_conflict(
    ia: [usize; 2],
    a: [Point; 2],
    ib: [usize; 2],
    b: [Point; 2],
    tolerance: f64,
) -> Conflict {
    for k in 0..2 {
        if !ia.contains(&ib[k]) && in_segment_interior(b[k], a, tolerance) {
            return Conflict::Touch;
        }
        if !ib.contains(&ia[k]) && in_segment_interior(a[k], b, tolerance) {
            return Conflict::Touch;
        }
    }
    let shared = ia.iter().any(|v| ib.contains(v));
    if !shared {
        let side = |s: [Point; 2], p: Point| cross(s[1] - s[0], p - s[0]);
        let (o1, o2) = (side(a, b[0]), side(a, b[1]));
        let (o3, o4) = (side(b, a[0]), side(b, a[1]));
        let opposite = |x: f64, y: f64| (x > 0.0 && y < 0.0) || (x < 0.0 && y > 0.0);
        if opposite(o1, o2) && opposite(o3, o4) {
            return Conflict::Cross;
        }
    }
    Conflict::None
}

/// True when `p` is within `tolerance` of segment `s` and farther than `tolerance` from both of
/// its end points (measured along the segment).
fn in_segment_interior(p: Point, s: [Point; 2], tolerance: f64) -> bool {
    let along = s[1] - s[0];
    let length = along.norm();
    if length <= 2.0 * tolerance {
        return false;
    }
    let offset = p - s[0];
    let t = offset.dot(&along) / length;
    t > tolerance && t < length - tolerance && (cross(along, offset) / length).abs() <= tolerance
}

/// An axis-aligned bounding box.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Aabb {
    pub(crate) min: Point,
    pub(crate) max: Point,
}

impl Aabb {
    /// The smallest box holding `points` (an inverted box when there are none).
    pub(crate) fn of_points(points: impl Iterator<Item = Point>) -> Self {
        let mut b = Aabb {
            min: Point::new(f64::INFINITY, f64::INFINITY),
            max: Point::new(f64::NEG_INFINITY, f64::NEG_INFINITY),
        };
        for p in points {
            b.min = Point::new(b.min.x.min(p.x), b.min.y.min(p.y));
            b.max = Point::new(b.max.x.max(p.x), b.max.y.max(p.y));
        }
        b
    }

    pub(crate) fn diagonal(&self) -> f64 {
        (self.max - self.min).norm()
    }

    fn contains(&self, p: Point) -> bool {
        p.x >= self.min.x && p.x <= self.max.x && p.y >= self.min.y && p.y <= self.max.y
    }

    fn intersects(&self, other: &Aabb) -> bool {
        self.min.x <= other.max.x
            && other.min.x <= self.max.x
            && self.min.y <= other.max.y
            && other.min.y <= self.max.y
    }
}

/// A uniform grid of cells over a set of boxes, each box listed in every cell it overlaps
/// (compressed storage: `items[start[c]..start[c + 1]]` are the boxes of cell c).
pub(crate) struct Grid {
    origin: Point,
    cell: f64,
    nx: usize,
    ny: usize,
    start: Vec<usize>,
    items: Vec<usize>,
}

impl Grid {
    /// A grid whose cells are about the mean box size (or finer, so there are about as many
    /// cells as boxes), with at most about 4 * boxes.len() + 4 cells.
    pub(crate) fn new(boxes: &[Aabb]) -> Self {
        let count = boxes.len().max(1);
        let bounds = Aabb {
            min: Point::new(
                boxes.iter().map(|b| b.min.x).fold(f64::INFINITY, f64::min),
                boxes.iter().map(|b| b.min.y).fold(f64::INFINITY, f64::min),
            ),
            max: Point::new(
                boxes
                    .iter()
                    .map(|b| b.max.x)
                    .fold(f64::NEG_INFINITY, f64::max),
                boxes
                    .iter()
                    .map(|b| b.max.y)
                    .fold(f64::NEG_INFINITY, f64::max),
            ),
        };
        let (width, height) = if boxes.is_empty() {
            (0.0, 0.0)
        } else {
            (bounds.max.x - bounds.min.x, bounds.max.y - bounds.min.y)
        };
        let mean_size = boxes
            .iter()
            .map(|b| (b.max.x - b.min.x).max(b.max.y - b.min.y))
            .sum::<f64>()
            / count as f64;
        let even_share = (width * height / count as f64).sqrt();
        let mut cell = mean_size.max(even_share);
        let limit = 2 * (count as f64).sqrt() as usize + 2;
        if !(cell > 0.0 && cell.is_finite()) {
            cell = width.max(height).max(f64::MIN_POSITIVE);
        }
        let dims = |extent: f64| -> usize { ((extent / cell).floor() as usize + 1).min(limit) };
        let (nx, ny) = (dims(width), dims(height));
        // If clamped, widen the cells so the grid still spans the boxes.
        cell = cell
            .max(width / nx as f64)
            .max(height / ny as f64)
            .max(f64::MIN_POSITIVE);
        let mut grid = Grid {
            origin: if boxes.is_empty() {
                Point::origin()
            } else {
                bounds.min
            },
            cell,
            nx,
            ny,
            start: vec![0; nx * ny + 1],
            items: Vec::new(),
        };
        for b in boxes {
            let (i0, i1, j0, j1) = grid.range(b);
            for j in j0..=j1 {
                for i in i0..=i1 {
                    grid.start[j * nx + i + 1] += 1;
                }
            }
        }
        for c in 0..nx * ny {
            grid.start[c + 1] += grid.start[c];
        }
        let mut fill = grid.start.clone();
        grid.items = vec![0; grid.start[nx * ny]];
        for (index, b) in boxes.iter().enumerate() {
            let (i0, i1, j0, j1) = grid.range(b);
            for j in j0..=j1 {
                for i in i0..=i1 {
                    grid.items[fill[j * nx + i]] = index;
                    fill[j * nx + i] += 1;
                }
            }
        }
        grid
    }

    fn index(&self, value: f64, origin: f64, count: usize) -> usize {
        let i = ((value - origin) / self.cell).floor();
        if i <= 0.0 {
            0
        } else {
            (i as usize).min(count - 1)
        }
    }

    /// Cell ranges (i0, i1, j0, j1), inclusive, overlapped by `b`.
    fn range(&self, b: &Aabb) -> (usize, usize, usize, usize) {
        (
            self.index(b.min.x, self.origin.x, self.nx),
            self.index(b.max.x, self.origin.x, self.nx),
            self.index(b.min.y, self.origin.y, self.ny),
            self.index(b.max.y, self.origin.y, self.ny),
        )
    }

    /// Calls `visit(a, b)` once for every pair of boxes (a != b) whose boxes intersect.
    pub(crate) fn for_each_pair(&self, boxes: &[Aabb], mut visit: impl FnMut(usize, usize)) {
        for j in 0..self.ny {
            for i in 0..self.nx {
                let c = j * self.nx + i;
                let here = &self.items[self.start[c]..self.start[c + 1]];
                for (k, &a) in here.iter().enumerate() {
                    for &b in &here[k + 1..] {
                        let (ba, bb) = (&boxes[a], &boxes[b]);
                        if !ba.intersects(bb) {
                            continue;
                        }
                        // Visit the pair only in the cell holding the lower-left corner of the
                        // boxes' intersection, so each pair is seen once.
                        let corner = Aabb {
                            min: Point::new(ba.min.x.max(bb.min.x), ba.min.y.max(bb.min.y)),
                            max: Point::new(ba.min.x.max(bb.min.x), ba.min.y.max(bb.min.y)),
                        };
                        let (ci, _, cj, _) = self.range(&corner);
                        if (ci, cj) == (i, j) {
                            visit(a, b);
                        }
                    }
                }
            }
        }
    }

    /// Calls `visit(a)` for every box listed in a cell that `query` overlaps (a box may be
    /// visited more than once).
    pub(crate) fn for_each_in(&self, query: &Aabb, mut visit: impl FnMut(usize)) {
        let (i0, i1, j0, j1) = self.range(query);
        for j in j0..=j1 {
            for i in i0..=i1 {
                let c = j * self.nx + i;
                for &a in &self.items[self.start[c]..self.start[c + 1]] {
                    visit(a);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> Vec<Point> {
        vec![
            Point::new(0.0, 0.0),
            Point::new(1.0, 0.0),
            Point::new(1.0, 1.0),
            Point::new(0.0, 1.0),
        ]
    }

    #[test]
    fn convex_and_hanging_loops_are_simple() {
        assert_eq!(self_intersection(&square(), 1e-12), None);
        let mut with_hanging = square();
        with_hanging.insert(1, Point::new(0.5, 0.0));
        assert_eq!(self_intersection(&with_hanging, 1e-12), None);
    }

    #[test]
    fn bowtie_crosses_itself() {
        let bowtie = vec![
            Point::new(0.0, 0.0),
            Point::new(1.0, 1.0),
            Point::new(1.0, 0.0),
            Point::new(0.0, 1.0),
        ];
        assert_eq!(self_intersection(&bowtie, 1e-12), Some((0, 2)));
    }

    #[test]
    fn long_loop_uses_the_grid_and_finds_the_same_pair() {
        // A 200-gon comb whose last tooth pokes through its first edge.
        let mut points: Vec<Point> = (0..200)
            .map(|k| {
                let t = std::f64::consts::TAU * k as f64 / 200.0;
                Point::new(t.cos(), t.sin())
            })
            .collect();
        assert_eq!(self_intersection(&points, 1e-12), None);
        points[100] = Point::new(1.5, 0.001);
        let pair = self_intersection(&points, 1e-12).unwrap();
        assert!(pair.0 == 0 || pair.1 >= 99, "{pair:?}");
    }

    #[test]
    fn grid_pairs_match_brute_force() {
        let boxes: Vec<Aabb> = (0..50)
            .map(|k| {
                let x = (k * 37 % 50) as f64 * 0.1;
                let y = (k * 11 % 50) as f64 * 0.07;
                Aabb {
                    min: Point::new(x, y),
                    max: Point::new(x + 0.3 + (k % 3) as f64, y + 0.2),
                }
            })
            .collect();
        let mut from_grid = Vec::new();
        Grid::new(&boxes).for_each_pair(&boxes, |a, b| from_grid.push((a.min(b), a.max(b))));
        from_grid.sort_unstable();
        let mut brute = Vec::new();
        for a in 0..boxes.len() {
            for b in a + 1..boxes.len() {
                if boxes[a].intersects(&boxes[b]) {
                    brute.push((a, b));
                }
            }
        }
        assert_eq!(from_grid, brute);
    }
}
