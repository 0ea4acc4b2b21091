//! The polygonal mesh: vertices, counter-clockwise polygons in compact storage, derived edges
//! and named boundary parts.

use std::collections::HashMap;

use crate::{geometry, validate, MeshError, Point};

/// An edge of the mesh, derived from the polygons.
///
/// `vertices` are in the order in which the polygon `left` traverses the edge (counter-clockwise),
/// so the polygon lies to the left of `vertices[0] -> vertices[1]`; `right` is the polygon on the
/// other side, `None` on the boundary.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Edge {
    /// End vertices, in the direction of the `left` polygon's counter-clockwise loop.
    pub vertices: [usize; 2],
    /// The polygon that traverses the edge as `vertices[0] -> vertices[1]`.
    pub left: usize,
    /// The polygon on the other side, if any.
    pub right: Option<usize>,
}

impl Edge {
    /// True when the edge borders only one polygon.
    pub fn is_boundary(&self) -> bool {
        self.right.is_none()
    }
}

/// A named set of boundary edges ("bottom", "contact", ...).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BoundaryPart {
    /// The part's name.
    pub name: String,
    /// Indices into [`Mesh::edges`], all boundary edges, in the order given.
    pub edges: Vec<usize>,
}

/// A boundary part as given to a constructor: a name and edges as vertex pairs (either order).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PartSpec {
    /// The part's name.
    pub name: String,
    /// Its edges, each as the two end vertices.
    pub edges: Vec<[usize; 2]>,
}

impl PartSpec {
    /// A part named `name` made of `edges`.
    pub fn new(name: impl Into<String>, edges: Vec<[usize; 2]>) -> Self {
        Self {
            name: name.into(),
            edges,
        }
    }
}

/// A validated polygonal mesh.
///
/// Polygons are counter-clockwise vertex loops stored compactly: polygon `p` is
/// `polygon_vertex_indices()[offsets[p]..offsets[p + 1]]`. Consecutive collinear vertices are
/// allowed (hanging nodes are plain vertices). A `Mesh` is immutable once built: every
/// constructor validates, so any `Mesh` value satisfies the checks of [`crate::validate`].
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    vertices: Vec<Point>,
    polygon_offsets: Vec<usize>,
    polygon_vertices: Vec<usize>,
    /// Edge index of local edge k of each polygon (k joins local vertices k and k + 1),
    /// stored parallel to `polygon_vertices`.
    polygon_edges: Vec<usize>,
    edges: Vec<Edge>,
    parts: Vec<BoundaryPart>,
}

impl Mesh {
    /// Builds and validates a mesh from polygons given as vertex loops.
    ///
    /// ```
    /// use vem_mesh::{Mesh, PartSpec, Point};
    /// // Two unit squares side by side.
    /// let vertices = vec![
    ///     Point::new(0.0, 0.0), Point::new(1.0, 0.0), Point::new(2.0, 0.0),
    ///     Point::new(0.0, 1.0), Point::new(1.0, 1.0), Point::new(2.0, 1.0),
    /// ];
    /// let polygons = vec![vec![0, 1, 4, 3], vec![1, 2, 5, 4]];
    /// let bottom = PartSpec::new("bottom", vec![[0, 1], [1, 2]]);
    /// let mesh = Mesh::from_polygons(vertices, &polygons, vec![bottom])?;
    /// assert_eq!(mesh.n_edges(), 7);
    /// assert_eq!(mesh.part("bottom")?.edges.len(), 2);
    /// # Ok::<(), vem_mesh::MeshError>(())
    /// ```
    pub fn from_polygons(
        vertices: Vec<Point>,
        polygons: &[Vec<usize>],
        parts: Vec<PartSpec>,
    ) -> Result<Self, MeshError> {
        let mut offsets = Vec::with_capacity(polygons.len() + 1);
        offsets.push(0);
        let mut indices = Vec::with_capacity(polygons.iter().map(Vec::len).sum());
        for polygon in polygons {
            indices.extend_from_slice(polygon);
            offsets.push(indices.len());
        }
        Self::from_compact(vertices, offsets, indices, parts)
    }

    /// Builds and validates a mesh from compact storage: `offsets` has one entry per polygon
    /// plus one, starts at 0 and ends at `indices.len()`.
    pub fn from_compact(
        vertices: Vec<Point>,
        polygon_offsets: Vec<usize>,
        polygon_vertices: Vec<usize>,
        parts: Vec<PartSpec>,
    ) -> Result<Self, MeshError> {
        let mut mesh = Self::unvalidated(vertices, polygon_offsets, polygon_vertices)?;
        mesh.parts = resolve_parts(&mesh, parts)?;
        validate::validate(&mesh)?;
        Ok(mesh)
    }

    /// The mesh of compact storage with its edges (storage checked, edges derived), without
    /// parts and without the checks of `validate` (which [`Mesh::from_compact`] runs next, and
    /// tests run themselves).
    pub(crate) fn unvalidated(
        vertices: Vec<Point>,
        polygon_offsets: Vec<usize>,
        polygon_vertices: Vec<usize>,
    ) -> Result<Self, MeshError> {
        validate::check_storage(&vertices, &polygon_offsets, &polygon_vertices)?;
        let (edges, polygon_edges) = derive_edges(&polygon_offsets, &polygon_vertices)?;
        Ok(Mesh {
            vertices,
            polygon_offsets,
            polygon_vertices,
            polygon_edges,
            edges,
            parts: Vec::new(),
        })
    }

    /// [`Mesh::from_compact`] for a mesh made from a valid mesh by changes at the vertices
    /// `changed` only (moved, or inserted into edges): the polygons near the change are
    /// validated, not the whole mesh again (see `validate::validate_changed`).
    pub(crate) fn from_compact_changed(
        vertices: Vec<Point>,
        polygon_offsets: Vec<usize>,
        polygon_vertices: Vec<usize>,
        parts: Vec<PartSpec>,
        changed: &[usize],
    ) -> Result<Self, MeshError> {
        let storage = |reason: &str| MeshError::BadStorage {
            reason: reason.to_string(),
        };
        if polygon_offsets.first() != Some(&0)
            || polygon_offsets.last() != Some(&polygon_vertices.len())
            || polygon_offsets.windows(2).any(|w| w[1] < w[0])
        {
            return Err(storage(
                "offsets must increase from 0 to the number of indices",
            ));
        }
        if let Some(k) = polygon_vertices.iter().position(|&v| v >= vertices.len()) {
            let (vertex, polygon) = (
                polygon_vertices[k],
                polygon_offsets.partition_point(|&o| o <= k) - 1,
            );
            return Err(MeshError::VertexOutOfRange {
                polygon,
                vertex,
                vertex_count: vertices.len(),
            });
        }
        let (edges, polygon_edges) = derive_edges(&polygon_offsets, &polygon_vertices)?;
        let mut mesh = Mesh {
            vertices,
            polygon_offsets,
            polygon_vertices,
            polygon_edges,
            edges,
            parts: Vec::new(),
        };
        mesh.parts = resolve_parts(&mesh, parts)?;
        validate::validate_changed(&mesh, changed)?;
        Ok(mesh)
    }

    /// Number of vertices.
    pub fn n_vertices(&self) -> usize {
        self.vertices.len()
    }

    /// Number of polygons.
    pub fn n_polygons(&self) -> usize {
        self.polygon_offsets.len() - 1
    }

    /// Number of edges.
    pub fn n_edges(&self) -> usize {
        self.edges.len()
    }

    /// All vertex coordinates.
    pub fn vertices(&self) -> &[Point] {
        &self.vertices
    }

    /// Coordinates of vertex `v`.
    pub fn vertex(&self, v: usize) -> Point {
        self.vertices[v]
    }

    /// Vertex indices of polygon `p`, counter-clockwise.
    pub fn polygon(&self, p: usize) -> &[usize] {
        &self.polygon_vertices[self.polygon_offsets[p]..self.polygon_offsets[p + 1]]
    }

    /// Iterator over all polygons' vertex loops.
    pub fn polygons(&self) -> impl ExactSizeIterator<Item = &[usize]> + '_ {
        (0..self.n_polygons()).map(move |p| self.polygon(p))
    }

    /// Coordinates of the vertices of polygon `p`, counter-clockwise.
    pub fn polygon_points(&self, p: usize) -> Vec<Point> {
        self.polygon(p).iter().map(|&v| self.vertices[v]).collect()
    }

    /// Edge indices of polygon `p`: entry k is the edge joining its local vertices k and k + 1.
    pub fn polygon_edges(&self, p: usize) -> &[usize] {
        &self.polygon_edges[self.polygon_offsets[p]..self.polygon_offsets[p + 1]]
    }

    /// The compact offsets (length `n_polygons() + 1`).
    pub fn polygon_offsets(&self) -> &[usize] {
        &self.polygon_offsets
    }

    /// The compact vertex indices of all polygons, concatenated.
    pub fn polygon_vertex_indices(&self) -> &[usize] {
        &self.polygon_vertices
    }

    /// All edges.
    pub fn edges(&self) -> &[Edge] {
        &self.edges
    }

    /// Edge `e`.
    pub fn edge(&self, e: usize) -> &Edge {
        &self.edges[e]
    }

    /// Indices of the boundary edges.
    pub fn boundary_edges(&self) -> impl Iterator<Item = usize> + '_ {
        self.edges
            .iter()
            .enumerate()
            .filter(|(_, e)| e.is_boundary())
            .map(|(i, _)| i)
    }

    /// All named boundary parts.
    pub fn parts(&self) -> &[BoundaryPart] {
        &self.parts
    }

    /// Names of the boundary parts.
    pub fn part_names(&self) -> Vec<String> {
        self.parts.iter().map(|p| p.name.clone()).collect()
    }

    /// The boundary part named `name`; the error lists the parts that exist.
    pub fn part(&self, name: &str) -> Result<&BoundaryPart, MeshError> {
        self.parts
            .iter()
            .find(|p| p.name == name)
            .ok_or_else(|| MeshError::UnknownPart {
                part: name.to_string(),
                available: self.part_names(),
            })
    }

    /// The distinct vertices of part `name`, sorted by index.
    pub fn part_vertices(&self, name: &str) -> Result<Vec<usize>, MeshError> {
        let part = self.part(name)?;
        let mut vertices: Vec<usize> = part
            .edges
            .iter()
            .flat_map(|&e| self.edges[e].vertices)
            .collect();
        vertices.sort_unstable();
        vertices.dedup();
        Ok(vertices)
    }

    /// A copy of this mesh with one more boundary part, made of the boundary edges for which
    /// `select(a, b)` is true (a, b: the edge's end points).
    pub fn with_part_where(
        &self,
        name: &str,
        mut select: impl FnMut(Point, Point) -> bool,
    ) -> Result<Self, MeshError> {
        if self.parts.iter().any(|p| p.name == name) {
            return Err(MeshError::DuplicatePart {
                part: name.to_string(),
            });
        }
        let edges: Vec<usize> = self
            .boundary_edges()
            .filter(|&e| {
                let [a, b] = self.edges[e].vertices;
                select(self.vertices[a], self.vertices[b])
            })
            .collect();
        let mut mesh = self.clone();
        mesh.parts.push(BoundaryPart {
            name: name.to_string(),
            edges,
        });
        Ok(mesh)
    }

    /// The part specifications of this mesh (vertex pairs), e.g. to rebuild it after a change.
    pub fn part_specs(&self) -> Vec<PartSpec> {
        self.parts
            .iter()
            .map(|part| PartSpec {
                name: part.name.clone(),
                edges: part.edges.iter().map(|&e| self.edges[e].vertices).collect(),
            })
            .collect()
    }

    /// A copy of this mesh with the midpoint of every edge inserted as a vertex: a polygon of
    /// `n` vertices becomes one of `2n` (the new vertices collinear with their edge's ends),
    /// every boundary-part edge two edges of the same part, in the same order. Areas, part
    /// lengths and the domain are unchanged; the new vertices are numbered after the old ones,
    /// in the order of [`Mesh::edges`].
    ///
    /// On triangles this is the locking-free element of the lowest-order VEM: a triangle with
    /// its edge midpoints has six displacement degrees of freedom against one pressure
    /// (divergence) mode, so the discrete divergence-free space is rich enough at Poisson's
    /// ratio close to 1/2 (docs/elements.md).
    ///
    /// ```
    /// use vem_mesh::generators::{structured_triangles, Rectangle};
    /// let mesh = structured_triangles(&Rectangle::unit_square(), 2, 2)?;
    /// let refined = mesh.with_edge_midpoints()?;
    /// assert_eq!(refined.n_vertices(), mesh.n_vertices() + mesh.n_edges());
    /// assert!(refined.polygons().all(|p| p.len() == 6));
    /// # Ok::<(), vem_mesh::MeshError>(())
    /// ```
    ///
    /// # Errors
    /// The validation of [`Mesh::from_polygons`] (a valid mesh gives a valid refined one).
    pub fn with_edge_midpoints(&self) -> Result<Self, MeshError> {
        let n = self.vertices.len();
        let mut vertices = self.vertices.clone();
        vertices.extend(self.edges.iter().map(|edge| {
            let [a, b] = edge.vertices;
            Point::from((self.vertices[a].coords + self.vertices[b].coords) * 0.5)
        }));
        let polygons: Vec<Vec<usize>> = (0..self.n_polygons())
            .map(|p| {
                self.polygon(p)
                    .iter()
                    .zip(self.polygon_edges(p))
                    .flat_map(|(&v, &e)| [v, n + e])
                    .collect()
            })
            .collect();
        let parts = self
            .parts
            .iter()
            .map(|part| {
                let edges = part
                    .edges
                    .iter()
                    .flat_map(|&e| {
                        let [a, b] = self.edges[e].vertices;
                        [[a, n + e], [n + e, b]]
                    })
                    .collect();
                PartSpec::new(part.name.clone(), edges)
            })
            .collect();
        Self::from_polygons(vertices, &polygons, parts)
    }

    /// Area of polygon `p`.
    pub fn area(&self, p: usize) -> f64 {
        let polygon = self.polygon(p);
        geometry::signed_area_of(polygon.len(), |i| self.vertices[polygon[i]])
    }

    /// Centroid of polygon `p`.
    pub fn centroid(&self, p: usize) -> Point {
        geometry::centroid(&self.polygon_points(p))
    }

    /// Diameter h_T of polygon `p`.
    pub fn diameter(&self, p: usize) -> f64 {
        geometry::diameter(&self.polygon_points(p))
    }

    /// Mesh size h: the largest polygon diameter.
    pub fn mesh_size(&self) -> f64 {
        (0..self.n_polygons())
            .map(|p| self.diameter(p))
            .fold(0.0, f64::max)
    }
}

/// Derives the edges from the polygon loops; an edge used twice in the same direction or by
/// more than two polygons is an error.
///
/// Edges are numbered in order of first appearance along the loops. Each edge is filed under
/// its smaller end vertex in a compressed table with one slot per loop side having that vertex
/// as its smaller end (an upper bound), so that finding the edge of a loop side is a scan of
/// the few edges of one vertex: linear time, no hashing.
fn derive_edges(
    offsets: &[usize],
    indices: &[usize],
) -> Result<(Vec<Edge>, Vec<usize>), MeshError> {
    let n_vertices = indices.iter().max().map_or(0, |&v| v + 1);
    // Slots of two u32 (half the memory) when every vertex and edge index fits (there are no
    // more edges than loop sides).
    if u32::try_from(n_vertices.max(indices.len())).is_ok() {
        derive_edges_with::<(u32, u32)>(offsets, indices, n_vertices)
    } else {
        derive_edges_with::<(usize, usize)>(offsets, indices, n_vertices)
    }
}

/// A slot of [`derive_edges`]: an edge and its larger end vertex.
trait EdgeSlot: Copy {
    const EMPTY: Self;
    fn new(high: usize, edge: usize) -> Self;
    fn high(self) -> usize;
    fn edge(self) -> usize;
}

impl EdgeSlot for (u32, u32) {
    const EMPTY: Self = (u32::MAX, u32::MAX);
    fn new(high: usize, edge: usize) -> Self {
        (high as u32, edge as u32)
    }
    fn high(self) -> usize {
        self.0 as usize
    }
    fn edge(self) -> usize {
        self.1 as usize
    }
}

impl EdgeSlot for (usize, usize) {
    const EMPTY: Self = (usize::MAX, usize::MAX);
    fn new(high: usize, edge: usize) -> Self {
        (high, edge)
    }
    fn high(self) -> usize {
        self.0
    }
    fn edge(self) -> usize {
        self.1
    }
}

/// [`derive_edges`] with slots of type `S` (which must hold every vertex and edge index),
/// for vertices below `n_vertices`.
fn derive_edges_with<S: EdgeSlot>(
    offsets: &[usize],
    indices: &[usize],
    n_vertices: usize,
) -> Result<(Vec<Edge>, Vec<usize>), MeshError> {
    let side = |p: usize, k: usize| -> (usize, usize) {
        let (start, end) = (offsets[p], offsets[p + 1]);
        let a = indices[start + k];
        let b = if start + k + 1 == end {
            indices[start]
        } else {
            indices[start + k + 1]
        };
        (a, b)
    };
    // start[v]..start[v + 1]: the slots of the edges whose smaller end is v.
    let mut start = vec![0usize; n_vertices + 1];
    for p in 0..offsets.len() - 1 {
        for k in 0..offsets[p + 1] - offsets[p] {
            let (a, b) = side(p, k);
            start[a.min(b) + 1] += 1;
        }
    }
    for v in 0..n_vertices {
        start[v + 1] += start[v];
    }
    // (larger end vertex, edge) of the edges filed so far, the rest of a vertex's slots
    // empty: the search for a loop side's edge reads this table only (and the slots' start),
    // not the edges themselves (which lie in the mesh's order).
    let mut slots = vec![S::EMPTY; indices.len()];
    // E = (sides + boundary sides) / 2: room for a boundary of up to an eighth of the sides
    // (any mesh but a strip), so that the edges, which live as long as the mesh, are not
    // reallocated to twice their size near the end.
    let mut edges: Vec<Edge> = Vec::with_capacity(indices.len() / 2 + indices.len() / 16 + 16);
    let mut polygon_edges = vec![0; indices.len()];
    for p in 0..offsets.len() - 1 {
        for k in 0..offsets[p + 1] - offsets[p] {
            let (a, b) = side(p, k);
            let (low, high) = (a.min(b), a.max(b));
            // The side's edge among those filed under `low`, or the first empty slot (there
            // are as many slots as sides whose smaller end is `low`).
            let (first, end) = (start[low], start[low + 1]);
            let mut at = first;
            while at < end && slots[at].high() != high && slots[at].high() != S::EMPTY.high() {
                at += 1;
            }
            let existing = (at < end && slots[at].high() == high).then(|| slots[at].edge());
            let e = match existing {
                None => {
                    edges.push(Edge {
                        vertices: [a, b],
                        left: p,
                        right: None,
                    });
                    let e = edges.len() - 1;
                    slots[at] = S::new(high, e);
                    e
                }
                Some(e) => {
                    let edge = &mut edges[e];
                    if edge.right.is_some() || edge.vertices != [b, a] {
                        let mut polygons = vec![edge.left];
                        polygons.extend(edge.right);
                        polygons.push(p);
                        return Err(MeshError::OverusedEdge {
                            a,
                            b,
                            count: polygons.len(),
                            polygons,
                        });
                    }
                    edge.right = Some(p);
                    e
                }
            };
            polygon_edges[offsets[p] + k] = e;
        }
    }
    Ok((edges, polygon_edges))
}

/// Turns part specifications (vertex pairs) into edge indices, checking that each names a
/// boundary edge and that names are unique.
fn resolve_parts(mesh: &Mesh, specs: Vec<PartSpec>) -> Result<Vec<BoundaryPart>, MeshError> {
    let mut edge_of_pair: HashMap<(usize, usize), usize> = HashMap::new();
    for e in mesh.boundary_edges() {
        let [a, b] = mesh.edges[e].vertices;
        edge_of_pair.insert((a.min(b), a.max(b)), e);
    }
    let mut parts: Vec<BoundaryPart> = Vec::with_capacity(specs.len());
    for spec in specs {
        if parts.iter().any(|p| p.name == spec.name) {
            return Err(MeshError::DuplicatePart { part: spec.name });
        }
        let mut edges = Vec::with_capacity(spec.edges.len());
        for [a, b] in spec.edges {
            match edge_of_pair.get(&(a.min(b), a.max(b))) {
                Some(&e) => edges.push(e),
                None => {
                    let interior = mesh
                        .edges
                        .iter()
                        .find(|edge| edge.vertices == [a, b] || edge.vertices == [b, a]);
                    return Err(match interior {
                        Some(edge) => MeshError::InteriorEdgeInPart {
                            part: spec.name,
                            a,
                            b,
                            left: edge.left,
                            right: edge.right.unwrap_or(edge.left),
                        },
                        None => MeshError::UnknownEdge {
                            part: spec.name,
                            a,
                            b,
                        },
                    });
                }
            }
        }
        parts.push(BoundaryPart {
            name: spec.name,
            edges,
        });
    }
    Ok(parts)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn two_squares() -> (Vec<Point>, Vec<Vec<usize>>) {
        let vertices = vec![
            Point::new(0.0, 0.0),
            Point::new(1.0, 0.0),
            Point::new(2.0, 0.0),
            Point::new(0.0, 1.0),
            Point::new(1.0, 1.0),
            Point::new(2.0, 1.0),
        ];
        (vertices, vec![vec![0, 1, 4, 3], vec![1, 2, 5, 4]])
    }

    #[test]
    fn edge_midpoints_keep_areas_parts_and_validity() {
        use crate::generators::{structured_triangles, voronoi, Rectangle};
        let rect = Rectangle::new(Point::new(-1.0, 0.0), Point::new(2.0, 1.5));
        for mesh in [
            structured_triangles(&rect, 5, 4).unwrap(),
            voronoi(&rect, 30, 7).unwrap(),
        ] {
            let refined = mesh.with_edge_midpoints().unwrap();
            assert_eq!(refined.n_vertices(), mesh.n_vertices() + mesh.n_edges());
            assert_eq!(refined.n_polygons(), mesh.n_polygons());
            assert_eq!(refined.n_edges(), 2 * mesh.n_edges());
            let (mut total, mut total_refined) = (0.0, 0.0);
            for p in 0..mesh.n_polygons() {
                assert_eq!(refined.polygon(p).len(), 2 * mesh.polygon(p).len());
                // The old vertices in their old order, every other one.
                let corners: Vec<usize> = refined.polygon(p).iter().copied().step_by(2).collect();
                assert_eq!(corners, mesh.polygon(p));
                assert!((refined.area(p) - mesh.area(p)).abs() <= 1e-12 * mesh.area(p));
                assert!(
                    refined
                        .centroid(p)
                        .coords
                        .metric_distance(&mesh.centroid(p).coords)
                        < 1e-12
                );
                total += mesh.area(p);
                total_refined += refined.area(p);
            }
            // The whole domain: 3 x 1.5.
            assert!((total - 4.5).abs() < 1e-12 && (total_refined - 4.5).abs() < 1e-12);
            let length = |m: &Mesh, part: &BoundaryPart| -> f64 {
                part.edges
                    .iter()
                    .map(|&e| {
                        let [a, b] = m.edge(e).vertices;
                        (m.vertex(a) - m.vertex(b)).norm()
                    })
                    .sum()
            };
            assert_eq!(refined.part_names(), mesh.part_names());
            assert!(!mesh.parts().is_empty());
            for (old, new) in mesh.parts().iter().zip(refined.parts()) {
                assert_eq!(new.edges.len(), 2 * old.edges.len());
                assert!(new.edges.iter().all(|&e| refined.edge(e).is_boundary()));
                let (l_old, l_new) = (length(&mesh, old), length(&refined, new));
                assert!(
                    (l_old - l_new).abs() <= 1e-12 * l_old,
                    "{}: {l_old} {l_new}",
                    old.name
                );
            }
            // Every new vertex halves its edge.
            for (e, edge) in mesh.edges().iter().enumerate() {
                let [a, b] = edge.vertices;
                let m = refined.vertex(mesh.n_vertices() + e);
                assert!(((m - mesh.vertex(a)) - (mesh.vertex(b) - m)).norm() < 1e-14);
            }
            crate::validate::validate(&refined).unwrap();
        }
    }

    #[test]
    fn edges_and_adjacency_are_derived() {
        let (vertices, polygons) = two_squares();
        let mesh = Mesh::from_polygons(vertices, &polygons, vec![]).unwrap();
        assert_eq!(mesh.n_edges(), 7);
        assert_eq!(mesh.boundary_edges().count(), 6);
        let shared: Vec<&Edge> = mesh.edges().iter().filter(|e| !e.is_boundary()).collect();
        assert_eq!(shared.len(), 1);
        assert_eq!(shared[0].vertices, [1, 4]);
        assert_eq!((shared[0].left, shared[0].right), (0, Some(1)));
        // Euler: V - E + F = 1 for a connected planar mesh without holes.
        assert_eq!(
            mesh.n_vertices() as i64 - mesh.n_edges() as i64 + mesh.n_polygons() as i64,
            1
        );
        assert_eq!(mesh.mesh_size(), 2f64.sqrt());
    }

    #[test]
    fn interior_edge_in_part_is_rejected() {
        let (vertices, polygons) = two_squares();
        let err = Mesh::from_polygons(
            vertices,
            &polygons,
            vec![PartSpec::new("mid", vec![[4, 1]])],
        )
        .unwrap_err();
        assert!(matches!(err, MeshError::InteriorEdgeInPart { .. }), "{err}");
    }

    #[test]
    fn unknown_part_lists_existing_parts() {
        let (vertices, polygons) = two_squares();
        let mesh = Mesh::from_polygons(
            vertices,
            &polygons,
            vec![PartSpec::new("bottom", vec![[0, 1], [1, 2]])],
        )
        .unwrap();
        let err = mesh.part("top").unwrap_err();
        assert_eq!(
            err.to_string(),
            "no boundary part named 'top'; the mesh has [\"bottom\"]"
        );
        assert_eq!(mesh.part_vertices("bottom").unwrap(), vec![0, 1, 2]);
    }

    #[test]
    fn part_where_selects_boundary_edges() {
        let (vertices, polygons) = two_squares();
        let mesh = Mesh::from_polygons(vertices, &polygons, vec![]).unwrap();
        let mesh = mesh
            .with_part_where("top", |a, b| a.y == 1.0 && b.y == 1.0)
            .unwrap();
        assert_eq!(mesh.part_vertices("top").unwrap(), vec![3, 4, 5]);
    }

    #[test]
    fn same_direction_edge_is_overused() {
        let (vertices, _) = two_squares();
        // Second square traverses 1 -> 4 like the first: overlapping polygons.
        let polygons = vec![vec![0, 1, 4, 3], vec![1, 4, 5, 2]];
        let err = Mesh::from_polygons(vertices, &polygons, vec![]).unwrap_err();
        assert!(
            matches!(
                err,
                MeshError::OverusedEdge { .. } | MeshError::Clockwise { .. }
            ),
            "{err}"
        );
    }
}
