//! Meshes of a simple polygon, of any family: the family's mesh of the polygon's bounding
//! rectangle, cut by the polygon; for the Voronoi family, a centroidal Voronoi mesh of the
//! polygon by reflected seeds.
//!
//! # Which family uses which method
//!
//! | family | method of [`polygon_mesh`] |
//! | --- | --- |
//! | voronoi | reflected seeds ([`polygon_voronoi()`], PolyMesher's method): seeds drawn in the polygon, mirrored across the edges they are near, Lloyd iterations; the cells of the seeds end on the polygon's edges, and the cut below only clips what reflection leaves open (around reflex corners, where an image was dropped) |
//! | quads, triangles, hexagons, perturbed, nonconvex, hanging | the family's mesh of the bounding rectangle cut by the polygon (below) |
//!
//! The Voronoi mesh of the rectangle cut by the polygon is still [`cut_to_polygon`] of
//! [`super::voronoi`]'s mesh; it leaves cut cells along the whole boundary (smallest star ratio
//! 0.050 to 0.15, shortest edges down to 0.018 of their cells on the polygons of
//! `tests/polygon_domains.rs`, n = 10 to 40), where the reflected seeds give 0.13 to 0.30
//! and at least 0.10.
//!
//! # Method of the cut
//!
//! 1. The family generates its mesh of size `n` on the bounding rectangle of the polygon
//!    (the same cells as on that rectangle: `n` cells across its width).
//! 2. Snap: a vertex of that mesh closer than [`SNAP_RATIO`] times the typical cell size
//!    `s = sqrt(area of the rectangle / number of cells)` to the polygon's boundary moves onto
//!    it (onto a corner of the polygon when one is that close, one vertex per corner), unless
//!    the move exceeds a quarter of its shortest edge: no cut then leaves an edge or a cell
//!    much smaller than `s` near a vertex.
//! 3. Cut: the mesh edges and the polygon's edges are split where they cross or touch (to a
//!    round-off of the polygon's size); the pieces of mesh edges inside the polygon and the
//!    pieces of its edges form a planar graph whose bounded faces are the cells. A cell cut
//!    into several pieces gives several cells; a cut cell may be non-convex (the virtual
//!    element allows it).
//! 4. Merge: a cut cell smaller than [`MERGE_AREA_RATIO`] times the cell it was cut from joins
//!    the neighbour with which it shares the longest stretch of edges (when they share one
//!    connected stretch and no other vertex), so that no sliver is left.
//! 5. Split: a cut cell still much less star-shaped than the cell it was cut from (a chevron
//!    around a reflex corner of the polygon that no merge made star-shaped) is split in two
//!    by the diagonal from one of its reflex vertices whose halves are best shaped.
//!
//! The cells then tile the polygon exactly (their areas sum to its area up to round-off), and
//! the boundary edges on polygon edge `k` form the boundary part named after that edge
//! ([`PolygonDomain::edge_names`]; consecutive edges with one name make one part).
//!
//! ```
//! use vem_mesh::generators::{polygon_mesh, MeshFamily, PolygonDomain};
//! use vem_mesh::Point;
//! // An L-shaped bracket: the square (0, 2)^2 without (1, 2)^2.
//! let l_shape = PolygonDomain::new(vec![
//!     Point::new(0.0, 0.0), Point::new(2.0, 0.0), Point::new(2.0, 1.0),
//!     Point::new(1.0, 1.0), Point::new(1.0, 2.0), Point::new(0.0, 2.0),
//! ])?
//! .with_edge_names(&["bottom", "end", "", "", "top", "left"])?;
//! let mesh = polygon_mesh(&l_shape, MeshFamily::Voronoi, 8, 1)?;
//! let area: f64 = (0..mesh.n_polygons()).map(|p| mesh.area(p)).sum();
//! assert!((area - 3.0).abs() < 1e-12);
//! let length = |part: &str| -> f64 {
//!     mesh.part(part).unwrap().edges.iter().map(|&e| {
//!         let [a, b] = mesh.edge(e).vertices;
//!         (mesh.vertex(b) - mesh.vertex(a)).norm()
//!     }).sum()
//! };
//! assert!((length("end") - 1.0).abs() < 1e-12);
//! assert!((length("edge2") + length("edge3") - 2.0).abs() < 1e-12);
//! # Ok::<(), vem_mesh::MeshError>(())
//! ```

use std::collections::HashMap;

use super::polygon_voronoi::polygon_voronoi;
use super::{MeshFamily, Rectangle};
use crate::quality::element_quality;
use crate::validate::self_intersection;
use crate::{geometry, Mesh, MeshError, PartSpec, Point, Vector};

/// A cut cell smaller than this fraction of the area of the cell it was cut from is merged
/// into a neighbour.
pub const MERGE_AREA_RATIO: f64 = 0.3;

/// Mesh vertices closer than this fraction of the typical cell size to the polygon's boundary
/// are moved onto it before the cut.
pub const SNAP_RATIO: f64 = 0.1;

/// Round-off of the cut, relative to the diagonal of the polygon's bounding rectangle: points
/// closer than this are one point, a point closer than this to an edge lies on it.
pub(super) const CUT_TOLERANCE: f64 = 1e-9;

/// The domain of a generated mesh: a simple polygon with named edges.
///
/// Its vertices run counter-clockwise; it may be non-convex. Edge `k` joins vertex `k` to
/// vertex `k + 1` (the last edge back to vertex 0); its name defaults to `"edge<k>"`.
#[derive(Debug, Clone, PartialEq)]
pub struct PolygonDomain {
    vertices: Vec<Point>,
    edge_names: Vec<String>,
}

impl PolygonDomain {
    /// The polygon with these vertices (counter-clockwise) and the default edge names.
    ///
    /// # Errors
    /// [`MeshError::BadDomainPolygon`], naming the vertex or edge, for fewer than 3 vertices,
    /// a non-finite coordinate, a zero-length edge, two edges that cross or touch away from a
    /// shared end point, a clockwise loop or a zero area.
    ///
    /// ```
    /// use vem_mesh::generators::PolygonDomain;
    /// use vem_mesh::{MeshError, Point};
    /// // A bow tie: edges 0 and 2 cross.
    /// let bow_tie = vec![
    ///     Point::new(0.0, 0.0), Point::new(1.0, 1.0), Point::new(1.0, 0.0), Point::new(0.0, 1.0),
    /// ];
    /// let error = PolygonDomain::new(bow_tie).unwrap_err();
    /// assert!(matches!(error, MeshError::BadDomainPolygon { vertex: Some(0), .. }));
    /// assert!(error.to_string().contains("edge 0 (vertex 0 to vertex 1) and edge 2"), "{error}");
    /// ```
    pub fn new(vertices: Vec<Point>) -> Result<Self, MeshError> {
        let bad =
            |vertex: Option<usize>, reason: String| MeshError::BadDomainPolygon { vertex, reason };
        let m = vertices.len();
        if m < 3 {
            return Err(bad(
                None,
                format!("it has {m} vertices; at least 3 are needed"),
            ));
        }
        if let Some(k) = vertices
            .iter()
            .position(|p| !(p.x.is_finite() && p.y.is_finite()))
        {
            let p = vertices[k];
            return Err(bad(
                Some(k),
                format!("vertex {k} has a non-finite coordinate ({}, {})", p.x, p.y),
            ));
        }
        let rect = bounding_rectangle(&vertices);
        let diagonal = (rect.max - rect.min).norm();
        let tolerance = CUT_TOLERANCE * diagonal;
        let edge = |k: usize| format!("edge {k} (vertex {k} to vertex {})", (k + 1) % m);
        for k in 0..m {
            let length = (vertices[(k + 1) % m] - vertices[k]).norm();
            if length <= tolerance {
                return Err(bad(
                    Some(k),
                    format!(
                        "{} has zero length ({length:e}): vertex {} repeats vertex {k}",
                        edge(k),
                        (k + 1) % m
                    ),
                ));
            }
        }
        if let Some((k, l)) = self_intersection(&vertices, tolerance) {
            return Err(bad(
                Some(k),
                format!(
                    "{} and {} cross or touch: the polygon must be simple",
                    edge(k),
                    edge(l)
                ),
            ));
        }
        let area = geometry::signed_area(&vertices);
        if area.abs() <= 1e-12 * diagonal * diagonal {
            return Err(bad(None, format!("its area {area:e} is zero")));
        }
        if area < 0.0 {
            return Err(bad(
                None,
                format!(
                    "its vertices run clockwise (signed area {area:e}); list them \
                     counter-clockwise"
                ),
            ));
        }
        let edge_names = (0..m).map(|k| format!("edge{k}")).collect();
        Ok(Self {
            vertices,
            edge_names,
        })
    }

    /// The same polygon with edge `k` named `names[k]`; an empty name keeps the default
    /// `"edge<k>"`. Several edges may share a name: they make one boundary part.
    ///
    /// # Errors
    /// [`MeshError::BadDomainPolygon`] when there is not one name per edge.
    pub fn with_edge_names<S: AsRef<str>>(mut self, names: &[S]) -> Result<Self, MeshError> {
        let m = self.vertices.len();
        if names.len() != m {
            return Err(MeshError::BadDomainPolygon {
                vertex: None,
                reason: format!(
                    "{} edge names for {m} edges; give one per edge (an empty name keeps \
                     \"edge<k>\")",
                    names.len()
                ),
            });
        }
        for (k, name) in names.iter().enumerate() {
            let name = name.as_ref().trim();
            if !name.is_empty() {
                self.edge_names[k] = name.to_string();
            }
        }
        Ok(self)
    }

    /// The vertices, counter-clockwise.
    pub fn vertices(&self) -> &[Point] {
        &self.vertices
    }

    /// The name of every edge (edge `k` from vertex `k` to vertex `k + 1`).
    pub fn edge_names(&self) -> &[String] {
        &self.edge_names
    }

    /// The end points of edge `k`.
    pub fn edge(&self, k: usize) -> [Point; 2] {
        [
            self.vertices[k],
            self.vertices[(k + 1) % self.vertices.len()],
        ]
    }

    /// The area (positive).
    pub fn area(&self) -> f64 {
        geometry::signed_area(&self.vertices)
    }

    /// The smallest axis-aligned rectangle holding the polygon.
    pub fn bounding_rectangle(&self) -> Rectangle {
        bounding_rectangle(&self.vertices)
    }

    /// True when `p` lies inside the polygon (crossing number; a point on the boundary may
    /// go either way).
    pub fn contains(&self, p: Point) -> bool {
        geometry::contains(&self.vertices, p)
    }

    /// The distance from `p` to the boundary, with the edge and the closest point.
    pub(super) fn closest_on_boundary(&self, p: Point) -> (f64, usize, Point) {
        let mut best = (f64::INFINITY, 0, p);
        for k in 0..self.vertices.len() {
            let [a, b] = self.edge(k);
            let t = parameter_on(p, a, b).clamp(0.0, 1.0);
            let q = a + (b - a) * t;
            let d = (p - q).norm();
            if d < best.0 {
                best = (d, k, q);
            }
        }
        best
    }
}

fn bounding_rectangle(vertices: &[Point]) -> Rectangle {
    let (mut min, mut max) = (vertices[0], vertices[0]);
    for p in vertices {
        min = Point::new(min.x.min(p.x), min.y.min(p.y));
        max = Point::new(max.x.max(p.x), max.y.max(p.y));
    }
    Rectangle::new(min, max)
}

/// The parameter t of the projection a + t (b - a) of `p` on the line through a and b.
pub(super) fn parameter_on(p: Point, a: Point, b: Point) -> f64 {
    let d = b - a;
    (p - a).dot(&d) / d.norm_squared()
}

/// The distance from `p` to the segment [a, b] and the parameter of its projection.
pub(super) fn distance_to_segment(p: Point, a: Point, b: Point) -> (f64, f64) {
    let t = parameter_on(p, a, b);
    let q = a + (b - a) * t.clamp(0.0, 1.0);
    ((p - q).norm(), t)
}

fn cross(a: Vector, b: Vector) -> f64 {
    a.x * b.y - a.y * b.x
}

/// The mesh of size `n` of `family` on the polygon `domain` (`seed` for the random families):
/// for [`MeshFamily::Voronoi`] the centroidal Voronoi mesh of the polygon by reflected seeds
/// ([`polygon_voronoi()`]), for the other families their mesh of the bounding rectangle cut by
/// the polygon ([`cut_to_polygon`]).
///
/// # Errors
/// The family's errors for its size; [`cut_to_polygon`]'s; [`polygon_voronoi()`]'s.
pub fn polygon_mesh(
    domain: &PolygonDomain,
    family: MeshFamily,
    n: usize,
    seed: u64,
) -> Result<Mesh, MeshError> {
    if family == MeshFamily::Voronoi {
        return polygon_voronoi(domain, n, seed).map(|voronoi| voronoi.mesh);
    }
    let background = family.generate(&domain.bounding_rectangle(), n, seed)?;
    cut_to_polygon(&background, domain)
}

/// Cuts a mesh covering the polygon `domain` to it (the method of the [module](self)): the
/// cells inside, cut cells merged when small, boundary parts named after the polygon's edges.
/// The parts of `background` are dropped.
///
/// # Errors
/// [`MeshError::BadGeneratorParameter`] when the mesh does not cover the polygon (the cells'
/// areas do not sum to its area); the validation errors of the mesh built (not expected).
pub fn cut_to_polygon(background: &Mesh, domain: &PolygonDomain) -> Result<Mesh, MeshError> {
    let snapped = cut(background, domain, true, true);
    match snapped {
        Ok(mesh) => Ok(mesh),
        // Snapping and merging never make an invalid mesh in the families' meshes tested; if
        // they did, the plain cut is still a valid mesh.
        Err(MeshError::BadGeneratorParameter { .. }) => snapped,
        Err(_) => cut(background, domain, false, false),
    }
}

/// The label of an edge of the cut graph.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Piece {
    /// A piece of mesh edge `edge`; `forward` when its key (lower vertex, higher vertex) runs
    /// along the edge.
    Mesh { edge: usize, forward: bool },
    /// A piece of polygon edge k.
    Boundary(usize),
    /// A diagonal splitting a cut cell that no merge made star-shaped.
    Diagonal,
}

pub(super) fn cut(
    background: &Mesh,
    domain: &PolygonDomain,
    snap: bool,
    merge: bool,
) -> Result<Mesh, MeshError> {
    let rect = domain.bounding_rectangle();
    let diagonal = (rect.max - rect.min).norm();
    let tol = CUT_TOLERANCE * diagonal;
    let cells = background.n_polygons().max(1);
    let cell_size = (rect.width() * rect.height() / cells as f64).sqrt();
    let corners = domain.vertices();
    let m = corners.len();

    // 1. Snap mesh vertices near the boundary onto it.
    let mut points: Vec<Point> = background.vertices().to_vec();
    if snap {
        let reach = SNAP_RATIO * cell_size;
        let mut shortest = vec![f64::INFINITY; points.len()];
        for edge in background.edges() {
            let [a, b] = edge.vertices;
            let length = (points[b] - points[a]).norm();
            shortest[a] = shortest[a].min(length);
            shortest[b] = shortest[b].min(length);
        }
        // The background's boundary stays where it is (it must keep covering the polygon).
        let mut claimed = vec![false; points.len()];
        for e in background.boundary_edges() {
            for v in background.edge(e).vertices {
                shortest[v] = 0.0;
            }
        }
        // Corners first, each to its closest mesh vertex.
        for &corner in corners {
            let mut best: Option<(f64, usize)> = None;
            for (v, p) in points.iter().enumerate() {
                let d = (p - corner).norm();
                if d < reach
                    && d <= 0.25 * shortest[v]
                    && shortest[v] > 0.0
                    && best.is_none_or(|(e, _)| d < e)
                {
                    best = Some((d, v));
                }
            }
            if let Some((_, v)) = best {
                if !claimed[v] {
                    points[v] = corner;
                    claimed[v] = true;
                }
            }
        }
        for v in 0..points.len() {
            if claimed[v] {
                continue;
            }
            let (d, _, q) = domain.closest_on_boundary(points[v]);
            let near_corner = corners.iter().any(|c| (q - c).norm() < reach);
            if d < reach && d <= 0.25 * shortest[v] && shortest[v] > 0.0 && !near_corner {
                points[v] = q;
            }
        }
    }

    // 2. The polygon's corners: a mesh vertex when one is there, else new points.
    let mut corner_ids = Vec::with_capacity(m);
    for &corner in corners {
        let found = points.iter().position(|p| (p - corner).norm() <= tol);
        corner_ids.push(found.unwrap_or_else(|| {
            points.push(corner);
            points.len() - 1
        }));
    }

    // 3. Split points on the polygon's edges and on the mesh edges.
    let edges = background.edges();
    let mut boundary_splits: Vec<Vec<(f64, usize)>> = (0..m)
        .map(|k| vec![(0.0, corner_ids[k]), (1.0, corner_ids[(k + 1) % m])])
        .collect();
    let mut mesh_splits: Vec<Vec<(f64, usize)>> = edges
        .iter()
        .map(|e| vec![(0.0, e.vertices[0]), (1.0, e.vertices[1])])
        .collect();
    let is_corner: Vec<bool> = {
        let mut flags = vec![false; points.len()];
        for &c in &corner_ids {
            flags[c] = true;
        }
        flags
    };
    // Mesh vertices on the polygon's edges.
    for v in 0..background.n_vertices() {
        if is_corner[v] {
            continue;
        }
        for (k, splits) in boundary_splits.iter_mut().enumerate() {
            let [a, b] = domain.edge(k);
            let (d, t) = distance_to_segment(points[v], a, b);
            if d <= tol && t > 0.0 && t < 1.0 {
                splits.push((t, v));
            }
        }
    }
    for (e, edge) in edges.iter().enumerate() {
        let [ia, ib] = edge.vertices;
        let (a, b) = (points[ia], points[ib]);
        let (lo, hi) = (
            Point::new(a.x.min(b.x) - tol, a.y.min(b.y) - tol),
            Point::new(a.x.max(b.x) + tol, a.y.max(b.y) + tol),
        );
        let ab = b - a;
        let length = ab.norm();
        // Corners on the mesh edge.
        for (k, &c) in corner_ids.iter().enumerate() {
            let p = corners[k];
            if c == ia || c == ib || p.x < lo.x || p.x > hi.x || p.y < lo.y || p.y > hi.y {
                continue;
            }
            let (d, t) = distance_to_segment(p, a, b);
            if d <= tol && t > 0.0 && t < 1.0 {
                mesh_splits[e].push((t, c));
            }
        }
        // Proper crossings.
        for (k, splits) in boundary_splits.iter_mut().enumerate() {
            let [pa, pb] = domain.edge(k);
            if pa.x.max(pb.x) < lo.x
                || pa.x.min(pb.x) > hi.x
                || pa.y.max(pb.y) < lo.y
                || pa.y.min(pb.y) > hi.y
            {
                continue;
            }
            let side = pb - pa;
            let side_length = side.norm();
            let da = cross(side, a - pa) / side_length;
            let db = cross(side, b - pa) / side_length;
            let dpa = cross(ab, pa - a) / length;
            let dpb = cross(ab, pb - a) / length;
            let opposite = |x: f64, y: f64| (x > tol && y < -tol) || (x < -tol && y > tol);
            if opposite(da, db) && opposite(dpa, dpb) {
                let t = da / (da - db);
                let x = a + ab * t;
                points.push(x);
                let id = points.len() - 1;
                mesh_splits[e].push((t, id));
                splits.push((parameter_on(x, pa, pb), id));
            }
        }
    }

    // 4. The graph of the pieces: the polygon's edges and the mesh edges inside.
    let mut graph: HashMap<(usize, usize), Piece> = HashMap::new();
    let mut order: Vec<(usize, usize)> = Vec::new();
    let mut add = |u: usize, v: usize, piece: Piece, graph: &mut HashMap<_, _>| {
        if u == v {
            return;
        }
        let key = (u.min(v), u.max(v));
        if let std::collections::hash_map::Entry::Vacant(slot) = graph.entry(key) {
            slot.insert(piece);
            order.push(key);
        }
    };
    for (k, splits) in boundary_splits.iter_mut().enumerate() {
        splits.sort_by(|x, y| x.0.total_cmp(&y.0));
        for w in splits.windows(2) {
            add(w[0].1, w[1].1, Piece::Boundary(k), &mut graph);
        }
    }
    for (e, splits) in mesh_splits.iter_mut().enumerate() {
        splits.sort_by(|x, y| x.0.total_cmp(&y.0));
        for w in splits.windows(2) {
            let (u, v) = (w[0].1, w[1].1);
            if u == v {
                continue;
            }
            let mid = Point::from((points[u].coords + points[v].coords) * 0.5);
            let (d, _, _) = domain.closest_on_boundary(mid);
            if d > tol && domain.contains(mid) {
                if edges[e].is_boundary() {
                    return Err(MeshError::BadGeneratorParameter {
                        generator: "cut_to_polygon",
                        reason: format!(
                            "the mesh's boundary passes inside the polygon (at ({}, {})): the \
                             mesh must cover the whole polygon",
                            mid.x, mid.y
                        ),
                    });
                }
                // The key (min, max) runs along the mesh edge when u < v.
                let forward = u < v;
                add(u, v, Piece::Mesh { edge: e, forward }, &mut graph);
            }
        }
    }
    let mut pieces: Vec<([usize; 2], Piece)> = order
        .iter()
        .map(|&(u, v)| ([u, v], graph[&(u, v)]))
        .collect();

    // 5. Faces, then merges of small cut cells, round after round, then the split of the cut
    //    cells still misshapen.
    let mut removed = vec![false; pieces.len()];
    let mut faces = loop {
        let faces = Faces::of(&points, &pieces, &removed)?;
        if !merge || !faces.merge_small(&points, &pieces, background, &mut removed) {
            break faces;
        }
    };
    if merge {
        let diagonals = faces.split_misshapen(&points, &pieces, background);
        if !diagonals.is_empty() {
            for diagonal in diagonals {
                pieces.push((diagonal, Piece::Diagonal));
                removed.push(false);
            }
            faces = Faces::of(&points, &pieces, &removed)?;
        }
    }

    // 6. The mesh: used vertices renumbered, parts by edge name.
    let mut new_id = vec![usize::MAX; points.len()];
    let mut vertices = Vec::new();
    let mut polygons = Vec::with_capacity(faces.cells.len());
    for cell in &faces.cells {
        let loop_: Vec<usize> = cell
            .iter()
            .map(|&h| {
                let v = faces.origin(&pieces, h);
                if new_id[v] == usize::MAX {
                    new_id[v] = vertices.len();
                    vertices.push(points[v]);
                }
                new_id[v]
            })
            .collect();
        polygons.push(loop_);
    }
    let parts = named_parts(
        domain,
        pieces
            .iter()
            .zip(&removed)
            .filter_map(|(([u, v], piece), &removed)| match piece {
                Piece::Boundary(k) if !removed => Some((*k, [new_id[*u], new_id[*v]])),
                _ => None,
            }),
    );
    let mesh = Mesh::from_polygons(vertices, &polygons, parts)?;
    let area: f64 = (0..mesh.n_polygons()).map(|p| mesh.area(p)).sum();
    if (area - domain.area()).abs() > 1e-9 * domain.area() {
        return Err(MeshError::BadGeneratorParameter {
            generator: "cut_to_polygon",
            reason: format!(
                "the mesh covers {area} of the polygon's area {}: it must cover the whole \
                 polygon",
                domain.area()
            ),
        });
    }
    Ok(mesh)
}

/// The boundary parts of a mesh of `domain` from its boundary edges `(k, [u, v])` (the edge
/// from vertex u to vertex v lies on polygon edge k): one part per edge name, in the order of
/// the polygon's edges.
pub(super) fn named_parts(
    domain: &PolygonDomain,
    edges: impl IntoIterator<Item = (usize, [usize; 2])>,
) -> Vec<PartSpec> {
    let mut parts: Vec<PartSpec> = Vec::new();
    for (k, edge) in edges {
        let name = &domain.edge_names()[k];
        match parts.iter_mut().find(|p| &p.name == name) {
            Some(part) => part.edges.push(edge),
            None => parts.push(PartSpec::new(name.clone(), vec![edge])),
        }
    }
    let rank = |name: &str| domain.edge_names().iter().position(|n| n == name);
    parts.sort_by_key(|p| rank(&p.name));
    parts
}

/// The bounded faces of the cut graph, each a loop of half-edges (half-edge `2 i` runs along
/// piece i from its first vertex to its second, `2 i + 1` back).
struct Faces {
    /// Counter-clockwise loops of half-edges.
    cells: Vec<Vec<usize>>,
    /// The face on the left of each half-edge (`usize::MAX` for the outer face or a removed
    /// piece).
    face_of: Vec<usize>,
    /// The cells' areas.
    areas: Vec<f64>,
}

impl Faces {
    fn origin(&self, pieces: &[([usize; 2], Piece)], h: usize) -> usize {
        pieces[h / 2].0[h % 2]
    }

    fn of(
        points: &[Point],
        pieces: &[([usize; 2], Piece)],
        removed: &[bool],
    ) -> Result<Self, MeshError> {
        let origin = |h: usize| pieces[h / 2].0[h % 2];
        let target = |h: usize| pieces[h / 2].0[1 - h % 2];
        // Outgoing half-edges of every vertex, counter-clockwise.
        let mut outgoing: Vec<Vec<(f64, usize)>> = vec![Vec::new(); points.len()];
        for (i, _) in pieces.iter().enumerate() {
            if removed[i] {
                continue;
            }
            for h in [2 * i, 2 * i + 1] {
                let d = points[target(h)] - points[origin(h)];
                outgoing[origin(h)].push((d.y.atan2(d.x), h));
            }
        }
        let mut slot = vec![0usize; 2 * pieces.len()];
        for list in &mut outgoing {
            list.sort_by(|a, b| a.0.total_cmp(&b.0));
            for (s, &(_, h)) in list.iter().enumerate() {
                slot[h] = s;
            }
        }
        // The face on the left of u -> v continues with the half-edge out of v just clockwise
        // of v -> u.
        let next = |h: usize| {
            let twin = h ^ 1;
            let v = origin(twin);
            let list = &outgoing[v];
            list[(slot[twin] + list.len() - 1) % list.len()].1
        };
        let mut face_of = vec![usize::MAX; 2 * pieces.len()];
        let mut seen = vec![false; 2 * pieces.len()];
        let (mut cells, mut areas) = (Vec::new(), Vec::new());
        let mut outer = 0;
        for start in 0..2 * pieces.len() {
            if removed[start / 2] || seen[start] {
                continue;
            }
            let mut loop_ = Vec::new();
            let mut h = start;
            while !seen[h] {
                seen[h] = true;
                loop_.push(h);
                h = next(h);
            }
            let loop_points: Vec<Point> = loop_.iter().map(|&h| points[origin(h)]).collect();
            let area = geometry::signed_area(&loop_points);
            if area > 0.0 {
                for &h in &loop_ {
                    face_of[h] = cells.len();
                }
                cells.push(loop_);
                areas.push(area);
            } else {
                outer += 1;
            }
        }
        if outer != 1 {
            return Err(MeshError::BadGeneratorParameter {
                generator: "cut_to_polygon",
                reason: format!(
                    "the cut left {outer} separate pieces; the mesh must cover the polygon"
                ),
            });
        }
        Ok(Self {
            cells,
            face_of,
            areas,
        })
    }

    /// Marks for removal the edges between each cut cell to be merged and its chosen
    /// neighbour (at most one merge per cell in a round); true when a merge was made.
    ///
    /// A cut cell is merged when it is small (below [`MERGE_AREA_RATIO`] of the area of the
    /// cell it was cut from) or misshapen (its star ratio below half that cell's); it joins the
    /// neighbour with which it shares the longest connected stretch of edges (and no other
    /// vertex) whose union with it is star-shaped with at least half the neighbour's star ratio
    /// (and, for a misshapen cell that is not small, a better star ratio than its own).
    fn merge_small(
        &self,
        points: &[Point],
        pieces: &[([usize; 2], Piece)],
        background: &Mesh,
        removed: &mut [bool],
    ) -> bool {
        let origin = |h: usize| pieces[h / 2].0[h % 2];
        let star = |loop_: &[usize]| -> f64 {
            let polygon: Vec<Point> = loop_.iter().map(|&v| points[v]).collect();
            element_quality(&polygon).star_ratio
        };
        let face_star = |f: usize| -> f64 {
            let loop_: Vec<usize> = self.cells[f].iter().map(|&h| origin(h)).collect();
            star(&loop_)
        };
        // (area, face, small, own star ratio)
        let mut candidates: Vec<(f64, usize, bool, f64)> = Vec::new();
        for (f, cell) in self.cells.iter().enumerate() {
            let Some(reference) = reference_cell(background, pieces, cell) else {
                continue; // the polygon inside one cell
            };
            let cut = cell
                .iter()
                .any(|&h| matches!(pieces[h / 2].1, Piece::Boundary(_)));
            if !cut {
                continue;
            }
            let small = self.areas[f] < MERGE_AREA_RATIO * background.area(reference);
            let own = face_star(f);
            let misshapen =
                own < 0.5 * element_quality(&background.polygon_points(reference)).star_ratio;
            if small || misshapen {
                candidates.push((self.areas[f], f, small, own));
            }
        }
        candidates.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut touched = vec![false; self.cells.len()];
        let mut merged = false;
        for &(_, f, small, own) in &candidates {
            if touched[f] {
                continue;
            }
            let cell = &self.cells[f];
            // Shared length with each neighbour.
            let mut shared: Vec<(usize, f64)> = Vec::new();
            for &h in cell {
                let g = self.face_of[h ^ 1];
                if g == usize::MAX {
                    continue;
                }
                let length = (points[origin(h ^ 1)] - points[origin(h)]).norm();
                match shared.iter_mut().find(|s| s.0 == g) {
                    Some(s) => s.1 += length,
                    None => shared.push((g, length)),
                }
            }
            shared.sort_by(|a, b| b.1.total_cmp(&a.1));
            for &(g, _) in &shared {
                if touched[g] {
                    continue;
                }
                let m = cell.len();
                let run: Vec<bool> = cell.iter().map(|&h| self.face_of[h ^ 1] == g).collect();
                let ends: Vec<usize> = (0..m).filter(|&i| run[i] && !run[(i + 1) % m]).collect();
                let run_length = run.iter().filter(|&&r| r).count();
                if ends.len() != 1 {
                    continue;
                }
                let vf: Vec<usize> = cell.iter().map(|&h| origin(h)).collect();
                let other = &self.cells[g];
                let common = other.iter().filter(|&&h| vf.contains(&origin(h))).count();
                if common != run_length + 1 {
                    continue;
                }
                // The union's loop: f after its run, then g after the twins of the run.
                let mut union: Vec<usize> = (1..=m - run_length)
                    .map(|i| vf[(ends[0] + i) % m])
                    .collect();
                let k = other.len();
                let g_run: Vec<bool> = other.iter().map(|&h| self.face_of[h ^ 1] == f).collect();
                let Some(g_end) = (0..k).find(|&i| g_run[i] && !g_run[(i + 1) % k]) else {
                    continue;
                };
                union.extend((1..=k - run_length).map(|i| origin(other[(g_end + i) % k])));
                let joined = star(&union);
                if joined < 0.5 * face_star(g) || (!small && joined <= own) {
                    continue;
                }
                for (i, &h) in cell.iter().enumerate() {
                    if run[i] {
                        removed[h / 2] = true;
                    }
                }
                touched[f] = true;
                touched[g] = true;
                merged = true;
                break;
            }
        }
        merged
    }

    /// The diagonals that split each cut cell still misshapen after the merges (its star ratio
    /// below half that of the cell it was cut from: a chevron around a reflex corner of the
    /// polygon that no union with a neighbour made star-shaped) in two: from a reflex vertex
    /// of the cell to another of its vertices, inside it, both halves more star-shaped than
    /// the cell: of those the one whose halves have the largest smaller gamma (the smaller of
    /// the shortest-edge and star ratios), taken when that is at least the cell's own gamma.
    fn split_misshapen(
        &self,
        points: &[Point],
        pieces: &[([usize; 2], Piece)],
        background: &Mesh,
    ) -> Vec<[usize; 2]> {
        let quality = |loop_: &[usize]| {
            let polygon: Vec<Point> = loop_.iter().map(|&v| points[v]).collect();
            element_quality(&polygon)
        };
        let mut diagonals = Vec::new();
        for cell in &self.cells {
            let cut = cell
                .iter()
                .any(|&h| matches!(pieces[h / 2].1, Piece::Boundary(_)));
            // The background cells it was cut from (the left side of its mesh pieces).
            let reference = reference_cell(background, pieces, cell);
            let (true, Some(reference)) = (cut, reference) else {
                continue;
            };
            let loop_: Vec<usize> = cell.iter().map(|&h| self.origin(pieces, h)).collect();
            let polygon: Vec<Point> = loop_.iter().map(|&v| points[v]).collect();
            let own = element_quality(&polygon);
            let reference_star = element_quality(&background.polygon_points(reference)).star_ratio;
            if own.star_ratio >= 0.5 * reference_star {
                continue;
            }
            let m = loop_.len();
            let mut best: Option<(f64, [usize; 2])> = None;
            for i in 0..m {
                let (prev, here, next) =
                    (polygon[(i + m - 1) % m], polygon[i], polygon[(i + 1) % m]);
                if cross(here - prev, next - here) >= 0.0 {
                    continue; // not reflex
                }
                for j in 0..m {
                    if j == i || j == (i + 1) % m || (j + 1) % m == i {
                        continue;
                    }
                    if !is_inner_diagonal(&polygon, i, j) {
                        continue;
                    }
                    let first: Vec<usize> = (0..m)
                        .map(|k| loop_[(i + k) % m])
                        .take((j + m - i) % m + 1)
                        .collect();
                    let second: Vec<usize> = (0..m)
                        .map(|k| loop_[(j + k) % m])
                        .take((i + m - j) % m + 1)
                        .collect();
                    let (a, b) = (quality(&first), quality(&second));
                    if a.star_ratio.min(b.star_ratio) <= own.star_ratio {
                        continue;
                    }
                    let worse = a.gamma().min(b.gamma());
                    if best.is_none_or(|(g, _)| worse > g) {
                        best = Some((worse, [loop_[i], loop_[j]]));
                    }
                }
            }
            if let Some((worse, diagonal)) = best {
                if worse >= own.gamma() {
                    diagonals.push(diagonal);
                }
            }
        }
        diagonals
    }
}

/// The background cell on the left of half-edge `h` when it is a piece of a mesh edge.
fn cell_left(background: &Mesh, pieces: &[([usize; 2], Piece)], h: usize) -> Option<usize> {
    let Piece::Mesh { edge, forward } = pieces[h / 2].1 else {
        return None;
    };
    // Half-edge 2 i runs along the key order, which runs along the mesh edge when `forward`.
    let e = &background.edges()[edge];
    if forward == (h % 2 == 0) {
        Some(e.left)
    } else {
        e.right
    }
}

/// The background cell a cut cell (a loop of half-edges) was cut from: the largest of the
/// cells on the left of its mesh pieces (`None` for the polygon inside one cell).
fn reference_cell(
    background: &Mesh,
    pieces: &[([usize; 2], Piece)],
    cell: &[usize],
) -> Option<usize> {
    cell.iter()
        .filter_map(|&h| cell_left(background, pieces, h))
        .max_by(|&a, &b| background.area(a).total_cmp(&background.area(b)))
}

/// True when the segment from vertex `i` to vertex `j` of the counter-clockwise simple polygon
/// `polygon` lies inside it: it leaves `i` into the polygon's angle there and crosses or
/// touches no edge but those at its ends.
fn is_inner_diagonal(polygon: &[Point], i: usize, j: usize) -> bool {
    let m = polygon.len();
    let (a, b) = (polygon[i], polygon[j]);
    let d = b - a;
    // Inside the angle at i (reflex: outside the cone of the exterior).
    let (prev, next) = (polygon[(i + m - 1) % m], polygon[(i + 1) % m]);
    let (to_next, to_prev) = (next - a, prev - a);
    let inside_angle = if cross(a - prev, next - a) >= 0.0 {
        cross(to_next, d) > 0.0 && cross(d, to_prev) > 0.0
    } else {
        !(cross(to_prev, d) >= 0.0 && cross(d, to_next) >= 0.0)
    };
    if !inside_angle {
        return false;
    }
    for k in 0..m {
        let l = (k + 1) % m;
        if k == i || l == i || k == j || l == j {
            continue;
        }
        let (p, q) = (polygon[k], polygon[l]);
        let side = |o: Point, u: Point, w: Point| cross(u - o, w - o);
        let (s1, s2) = (side(a, b, p), side(a, b, q));
        let (s3, s4) = (side(p, q, a), side(p, q, b));
        // Any contact (crossing or touching) disqualifies the diagonal.
        if s1 * s2 <= 0.0 && s3 * s4 <= 0.0 {
            return false;
        }
    }
    true
}
