//! The polyhedral mesh: vertices, faces stored once with their one or two cells, cells as
//! oriented faces, derived edges and named boundary parts made of boundary faces.

use std::collections::HashMap;

use super::geometry::{self, Polyhedron};
use super::validate;
use crate::{MeshError, Point3, Vector3};

/// A face as one cell sees it: the face's index and whether the face's stored loop is oriented
/// outward for that cell (its right-hand normal points out of the cell).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct OrientedFace {
    /// Face index.
    pub face: usize,
    /// True when the stored loop's right-hand normal points out of the cell.
    pub outward: bool,
}

impl OrientedFace {
    /// The face `face` seen with the given orientation.
    pub fn new(face: usize, outward: bool) -> Self {
        Self { face, outward }
    }
}

/// The one or two cells of a face.
///
/// The face's stored loop is oriented outward for `owner` (its right-hand normal points out of
/// `owner` and into `neighbour`); on the boundary `neighbour` is `None` and the normal points out
/// of the domain.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FaceCells {
    /// The cell for which the face's loop is outward.
    pub owner: usize,
    /// The cell on the other side, if any.
    pub neighbour: Option<usize>,
}

impl FaceCells {
    /// True when the face bounds only one cell.
    pub fn is_boundary(&self) -> bool {
        self.neighbour.is_none()
    }
}

/// A named set of boundary faces ("bottom", "contact", ...).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FacePart {
    /// The part's name.
    pub name: String,
    /// Indices into the faces of the mesh, all boundary faces, in the order given.
    pub faces: Vec<usize>,
}

impl FacePart {
    /// A part named `name` made of the faces with indices `faces`.
    pub fn new(name: impl Into<String>, faces: Vec<usize>) -> Self {
        Self {
            name: name.into(),
            faces,
        }
    }
}

/// A boundary part as given to [`PolyhedralMesh::from_polyhedra`]: a name and faces given by
/// their vertices (any starting vertex, either orientation).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FacePartSpec {
    /// The part's name.
    pub name: String,
    /// Its faces, each as its vertex loop.
    pub faces: Vec<Vec<usize>>,
}

impl FacePartSpec {
    /// A part named `name` made of `faces` (vertex loops).
    pub fn new(name: impl Into<String>, faces: Vec<Vec<usize>>) -> Self {
        Self {
            name: name.into(),
            faces,
        }
    }
}

/// A validated polyhedral mesh.
///
/// * Vertices are points of space.
/// * Faces are polygons (vertex loops of at least three distinct vertices) stored once, in
///   compact storage: face `f` is `face_vertex_indices()[face_offsets()[f]..face_offsets()[f + 1]]`.
///   Consecutive collinear vertices are allowed (a hanging node is a plain vertex of every face
///   around it), and so are coplanar faces of one cell. A face is planar to
///   [`super::validate::PLANARITY_RATIO`] of its diameter, or a warped face defined by its fan
///   triangulation about its vertex mean ([`super::geometry`]).
/// * Each face knows its one or two cells ([`FaceCells`]): its loop is oriented outward for its
///   `owner`, inward for its `neighbour`; a boundary face's loop is oriented out of the domain.
/// * A cell is a list of [`OrientedFace`]s: a closed, consistently oriented, connected surface
///   of positive volume.
/// * Edges are derived: every pair of consecutive vertices of a face, stored once with its end
///   vertices in increasing order, with the faces around it ([`PolyhedralMesh::edge_faces`]): a
///   point inserted on an edge must be inserted in every one of them.
/// * Named boundary parts are sets of boundary faces ([`FacePart`]).
///
/// A `PolyhedralMesh` is immutable once built: every constructor validates, so every value
/// satisfies the checks listed in [`super::validate`].
///
/// ```
/// use vem_mesh::{FacePartSpec, Point3, PolyhedralMesh};
/// // Two unit cubes side by side along x, each given by its six outward faces.
/// let mut vertices = Vec::new();
/// for z in 0..2 {
///     for y in 0..2 {
///         for x in 0..3 {
///             vertices.push(Point3::new(x as f64, y as f64, z as f64));
///         }
///     }
/// }
/// // Vertex (x, y, z) has index x + 3 y + 6 z.
/// let cube = |x: usize| {
///     let v = |dx: usize, dy: usize, dz: usize| x + dx + 3 * dy + 6 * dz;
///     vec![
///         vec![v(0, 0, 0), v(0, 0, 1), v(0, 1, 1), v(0, 1, 0)], // x = min
///         vec![v(1, 0, 0), v(1, 1, 0), v(1, 1, 1), v(1, 0, 1)], // x = max
///         vec![v(0, 0, 0), v(1, 0, 0), v(1, 0, 1), v(0, 0, 1)], // y = min
///         vec![v(0, 1, 0), v(0, 1, 1), v(1, 1, 1), v(1, 1, 0)], // y = max
///         vec![v(0, 0, 0), v(0, 1, 0), v(1, 1, 0), v(1, 0, 0)], // z = min
///         vec![v(0, 0, 1), v(1, 0, 1), v(1, 1, 1), v(0, 1, 1)], // z = max
///     ]
/// };
/// let left = FacePartSpec::new("left", vec![vec![0, 6, 9, 3]]);
/// let mesh = PolyhedralMesh::from_polyhedra(vertices, &[cube(0), cube(1)], vec![left])?;
/// assert_eq!((mesh.n_cells(), mesh.n_faces(), mesh.n_edges()), (2, 11, 20));
/// assert_eq!(mesh.volume(1), 1.0);
/// assert_eq!(mesh.cell_vertices(1), &[1, 2, 4, 5, 7, 8, 10, 11]);
/// // The shared face is stored once, outward for cell 0.
/// let shared = mesh.cell_faces(0)[1].face;
/// assert_eq!(mesh.face_cells(shared).neighbour, Some(1));
/// assert_eq!(mesh.part_vertices("left")?, vec![0, 3, 6, 9]);
/// // Euler characteristic of a ball: V - E + F - C = 1.
/// assert_eq!(mesh.euler_characteristic(), 1);
/// # Ok::<(), vem_mesh::MeshError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct PolyhedralMesh {
    vertices: Vec<Point3>,
    face_offsets: Vec<usize>,
    face_vertices: Vec<usize>,
    /// Edge index of local edge k of each face (k joins local vertices k and k + 1), parallel
    /// to `face_vertices`.
    face_edges: Vec<usize>,
    face_cells: Vec<FaceCells>,
    cell_offsets: Vec<usize>,
    cell_faces: Vec<OrientedFace>,
    cell_vertex_offsets: Vec<usize>,
    cell_vertices: Vec<usize>,
    edges: Vec<[usize; 2]>,
    edge_face_offsets: Vec<usize>,
    edge_faces: Vec<usize>,
    parts: Vec<FacePart>,
}

impl PolyhedralMesh {
    /// Builds and validates a mesh from compact storage.
    ///
    /// Face `f` is `face_vertices[face_offsets[f]..face_offsets[f + 1]]`; cell `c` is
    /// `cell_faces[cell_offsets[c]..cell_offsets[c + 1]]`; both offset arrays start at 0 and end
    /// at the length of their index array. Every face must belong to one or two cells; a boundary
    /// face that its cell sees inward is stored reversed (so that every boundary face's loop is
    /// oriented out of the domain) and the cell's flag flipped. `parts` name boundary faces by
    /// index.
    pub fn from_compact(
        vertices: Vec<Point3>,
        face_offsets: Vec<usize>,
        mut face_vertices: Vec<usize>,
        cell_offsets: Vec<usize>,
        mut cell_faces: Vec<OrientedFace>,
        parts: Vec<FacePart>,
    ) -> Result<Self, MeshError> {
        validate::check_storage(
            &vertices,
            &face_offsets,
            &face_vertices,
            &cell_offsets,
            &cell_faces,
        )?;
        // Boundary faces that their cell sees inward come back in `reversed`, their cell's flag
        // already flipped: reverse their loops to match.
        let (face_cells, reversed) =
            validate::face_cells(&face_offsets, &cell_offsets, &mut cell_faces)?;
        for &f in &reversed {
            face_vertices[face_offsets[f]..face_offsets[f + 1]].reverse();
        }
        let (edges, face_edges, edge_face_offsets, edge_faces) =
            derive_edges(vertices.len(), &face_offsets, &face_vertices);
        let (cell_vertex_offsets, cell_vertices) =
            cell_vertex_lists(&face_offsets, &face_vertices, &cell_offsets, &cell_faces);
        let mut mesh = PolyhedralMesh {
            vertices,
            face_offsets,
            face_vertices,
            face_edges,
            face_cells,
            cell_offsets,
            cell_faces,
            cell_vertex_offsets,
            cell_vertices,
            edges,
            edge_face_offsets,
            edge_faces,
            parts: Vec::new(),
        };
        validate::validate(&mesh)?;
        mesh.parts = validate::check_parts(&mesh, parts)?;
        Ok(mesh)
    }

    /// Builds and validates a mesh from cells given as lists of faces, each face a vertex loop
    /// oriented outward for that cell (the input of a VTK polyhedron).
    ///
    /// Faces are matched between cells by their vertex sets: the second cell listing a face must
    /// traverse it in the opposite direction. Faces are numbered in the order they first appear.
    /// `parts` name boundary faces by their vertices.
    pub fn from_polyhedra(
        vertices: Vec<Point3>,
        cells: &[Vec<Vec<usize>>],
        parts: Vec<FacePartSpec>,
    ) -> Result<Self, MeshError> {
        let mut builder = CellsBuilder::default();
        for cell in cells {
            for face in cell {
                builder.push_face(face);
            }
            builder.end_cell();
        }
        let matched = builder.match_faces();
        let mut resolved = Vec::with_capacity(parts.len());
        for spec in parts {
            let mut faces = Vec::with_capacity(spec.faces.len());
            for loop_ in &spec.faces {
                match matched.find(loop_) {
                    Some(f) => faces.push(f),
                    None => {
                        return Err(MeshError::UnknownFace {
                            part: spec.name,
                            vertices: loop_.clone(),
                        })
                    }
                }
            }
            resolved.push(FacePart::new(spec.name, faces));
        }
        matched.build(vertices, resolved)
    }

    /// Number of vertices.
    pub fn n_vertices(&self) -> usize {
        self.vertices.len()
    }

    /// Number of faces.
    pub fn n_faces(&self) -> usize {
        self.face_offsets.len() - 1
    }

    /// Number of cells.
    pub fn n_cells(&self) -> usize {
        self.cell_offsets.len() - 1
    }

    /// Number of edges.
    pub fn n_edges(&self) -> usize {
        self.edges.len()
    }

    /// V - E + F - C: 1 for a mesh of a ball (or of any contractible domain).
    pub fn euler_characteristic(&self) -> i64 {
        self.n_vertices() as i64 - self.n_edges() as i64 + self.n_faces() as i64
            - self.n_cells() as i64
    }

    /// All vertex coordinates.
    pub fn vertices(&self) -> &[Point3] {
        &self.vertices
    }

    /// Coordinates of vertex `v`.
    pub fn vertex(&self, v: usize) -> Point3 {
        self.vertices[v]
    }

    /// Vertex loop of face `f`, oriented outward for its owner.
    pub fn face(&self, f: usize) -> &[usize] {
        &self.face_vertices[self.face_offsets[f]..self.face_offsets[f + 1]]
    }

    /// Iterator over all faces' vertex loops.
    pub fn faces(&self) -> impl ExactSizeIterator<Item = &[usize]> + '_ {
        (0..self.n_faces()).map(move |f| self.face(f))
    }

    /// Coordinates of the vertices of face `f`, in loop order.
    pub fn face_points(&self, f: usize) -> Vec<Point3> {
        self.face(f).iter().map(|&v| self.vertices[v]).collect()
    }

    /// The compact face offsets (length `n_faces() + 1`).
    pub fn face_offsets(&self) -> &[usize] {
        &self.face_offsets
    }

    /// The compact vertex indices of all faces, concatenated.
    pub fn face_vertex_indices(&self) -> &[usize] {
        &self.face_vertices
    }

    /// Edge indices of face `f`: entry k is the edge joining its local vertices k and k + 1.
    pub fn face_edges(&self, f: usize) -> &[usize] {
        &self.face_edges[self.face_offsets[f]..self.face_offsets[f + 1]]
    }

    /// The one or two cells of face `f`.
    pub fn face_cells(&self, f: usize) -> FaceCells {
        self.face_cells[f]
    }

    /// True when face `f` bounds only one cell.
    pub fn is_boundary_face(&self, f: usize) -> bool {
        self.face_cells[f].is_boundary()
    }

    /// Indices of the boundary faces.
    pub fn boundary_faces(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.n_faces()).filter(move |&f| self.is_boundary_face(f))
    }

    /// Vector area of face `f` (oriented outward for its owner; see
    /// [`geometry::face_vector_area`]).
    pub fn face_vector_area(&self, f: usize) -> Vector3 {
        geometry::face_vector_area(&self.face_points(f))
    }

    /// Area of face `f`.
    pub fn face_area(&self, f: usize) -> f64 {
        geometry::face_area(&self.face_points(f))
    }

    /// Unit normal of face `f`, pointing out of its owner (out of the domain on the boundary).
    pub fn face_normal(&self, f: usize) -> Vector3 {
        geometry::face_normal(&self.face_points(f))
    }

    /// Centroid of face `f`.
    pub fn face_centroid(&self, f: usize) -> Point3 {
        geometry::face_centroid(&self.face_points(f))
    }

    /// The faces of cell `c`, each with the orientation the cell sees.
    pub fn cell_faces(&self, c: usize) -> &[OrientedFace] {
        &self.cell_faces[self.cell_offsets[c]..self.cell_offsets[c + 1]]
    }

    /// The compact cell offsets (length `n_cells() + 1`) into [`Self::cell_face_indices`].
    pub fn cell_offsets(&self) -> &[usize] {
        &self.cell_offsets
    }

    /// The oriented faces of all cells, concatenated.
    pub fn cell_face_indices(&self) -> &[OrientedFace] {
        &self.cell_faces
    }

    /// The distinct vertices of cell `c`, in increasing order (the local numbering of
    /// [`Self::cell_polyhedron`]).
    pub fn cell_vertices(&self, c: usize) -> &[usize] {
        &self.cell_vertices[self.cell_vertex_offsets[c]..self.cell_vertex_offsets[c + 1]]
    }

    /// The faces of cell `c` as global vertex loops oriented outward for the cell (what a VTK
    /// polyhedron lists).
    pub fn cell_face_loops(&self, c: usize) -> Vec<Vec<usize>> {
        self.cell_faces(c)
            .iter()
            .map(|slot| {
                let mut loop_ = self.face(slot.face).to_vec();
                if !slot.outward {
                    loop_.reverse();
                }
                loop_
            })
            .collect()
    }

    /// Cell `c` as a [`Polyhedron`]: its vertices in the order of [`Self::cell_vertices`] and
    /// its faces as local vertex loops oriented outward, in the order of [`Self::cell_faces`].
    pub fn cell_polyhedron(&self, c: usize) -> Polyhedron {
        let vertices = self.cell_vertices(c);
        let points: Vec<Point3> = vertices.iter().map(|&v| self.vertices[v]).collect();
        let local = |v: usize| vertices.binary_search(&v).expect("a vertex of the cell");
        let mut offsets = Vec::with_capacity(self.cell_faces(c).len() + 1);
        offsets.push(0);
        let mut loops = Vec::new();
        for slot in self.cell_faces(c) {
            let face = self.face(slot.face);
            if slot.outward {
                loops.extend(face.iter().map(|&v| local(v)));
            } else {
                loops.extend(face.iter().rev().map(|&v| local(v)));
            }
            offsets.push(loops.len());
        }
        Polyhedron::from_compact(points, offsets, loops)
    }

    /// Volume of cell `c`.
    pub fn volume(&self, c: usize) -> f64 {
        self.cell_polyhedron(c).volume()
    }

    /// Centroid of cell `c`.
    pub fn centroid(&self, c: usize) -> Point3 {
        self.cell_polyhedron(c).centroid()
    }

    /// Diameter h_E of cell `c` (largest distance between two of its vertices).
    pub fn diameter(&self, c: usize) -> f64 {
        let points: Vec<Point3> = self
            .cell_vertices(c)
            .iter()
            .map(|&v| self.vertices[v])
            .collect();
        geometry::diameter(&points)
    }

    /// Mesh size h: the largest cell diameter.
    pub fn mesh_size(&self) -> f64 {
        (0..self.n_cells())
            .map(|c| self.diameter(c))
            .fold(0.0, f64::max)
    }

    /// All edges, each as its two end vertices in increasing order.
    pub fn edges(&self) -> &[[usize; 2]] {
        &self.edges
    }

    /// End vertices of edge `e` (in increasing order).
    pub fn edge(&self, e: usize) -> [usize; 2] {
        self.edges[e]
    }

    /// The faces that have edge `e` as one of theirs, in increasing order.
    pub fn edge_faces(&self, e: usize) -> &[usize] {
        &self.edge_faces[self.edge_face_offsets[e]..self.edge_face_offsets[e + 1]]
    }

    /// The edge joining vertices `a` and `b`, if there is one.
    pub fn find_edge(&self, a: usize, b: usize) -> Option<usize> {
        let key = [a.min(b), a.max(b)];
        self.edges.binary_search(&key).ok()
    }

    /// All named boundary parts.
    pub fn parts(&self) -> &[FacePart] {
        &self.parts
    }

    /// Names of the boundary parts.
    pub fn part_names(&self) -> Vec<String> {
        self.parts.iter().map(|p| p.name.clone()).collect()
    }

    /// The boundary part named `name`; the error lists the parts that exist.
    pub fn part(&self, name: &str) -> Result<&FacePart, MeshError> {
        self.parts
            .iter()
            .find(|p| p.name == name)
            .ok_or_else(|| MeshError::UnknownPart {
                part: name.to_string(),
                available: self.part_names(),
            })
    }

    /// The faces of part `name`.
    pub fn part_faces(&self, name: &str) -> Result<&[usize], MeshError> {
        Ok(&self.part(name)?.faces)
    }

    /// The distinct vertices of part `name`, sorted by index.
    pub fn part_vertices(&self, name: &str) -> Result<Vec<usize>, MeshError> {
        let part = self.part(name)?;
        let mut vertices: Vec<usize> = part
            .faces
            .iter()
            .flat_map(|&f| self.face(f).iter().copied())
            .collect();
        vertices.sort_unstable();
        vertices.dedup();
        Ok(vertices)
    }

    /// A copy of this mesh with one more boundary part, made of the boundary faces for which
    /// `select(points)` is true (`points`: the face's vertex coordinates in loop order).
    pub fn with_part_where(
        &self,
        name: &str,
        mut select: impl FnMut(&[Point3]) -> bool,
    ) -> Result<Self, MeshError> {
        if self.parts.iter().any(|p| p.name == name) {
            return Err(MeshError::DuplicatePart {
                part: name.to_string(),
            });
        }
        let faces: Vec<usize> = self
            .boundary_faces()
            .filter(|&f| select(&self.face_points(f)))
            .collect();
        let mut mesh = self.clone();
        mesh.parts.push(FacePart::new(name, faces));
        Ok(mesh)
    }

    /// A copy of this mesh with the midpoint of every edge inserted as a vertex: the midpoint of
    /// an edge becomes a vertex of every face around that edge (a hanging node of each, collinear
    /// with the edge's ends), so that a face of `n` vertices becomes one of `2n` (a triangle a
    /// hexagon) and a tetrahedron a polyhedron of 10 vertices. Faces, cells and boundary parts
    /// keep their indices, names and orientations; the new vertices are numbered after the old
    /// ones, in the order of [`Self::edges`]. The three-dimensional counterpart of
    /// [`crate::Mesh::with_edge_midpoints`].
    ///
    /// Nothing of the geometry changes, not even on a warped face: the mean of a face's edge
    /// midpoints is the mean of its vertices, so the fan centre stays where it was and every fan
    /// triangle (x_k, x_{k+1}, xbar_F) splits into the two halves (x_k, m_k, xbar_F) and
    /// (m_k, x_{k+1}, xbar_F) ([`super::geometry`]): face vector areas, volumes, centroids and
    /// part areas are those of the mesh without the midpoints, to round-off.
    ///
    /// On tetrahedra this is the cure of near-incompressible locking of the lowest-order VEM in
    /// space: the virtual element space of a tetrahedron is P1 (its stabilisation vanishes) and
    /// locks at Poisson's ratio close to 1/2 with every stabilisation; with the edge midpoints a
    /// tetrahedron has the 10 vertices (30 displacement degrees of freedom) of a P2 tetrahedron
    /// against one divergence constraint, the count of the P2-P0 pair that is stable in space,
    /// and with the locking-free stabilisation `vem1-bbar` it does not lock (docs/elements.md).
    ///
    /// ```
    /// use vem_mesh::generators::polyhedral::{tetrahedra, Cuboid};
    /// let mesh = tetrahedra(&Cuboid::unit_cube(), 2, 2, 2)?;
    /// let refined = mesh.with_edge_midpoints()?;
    /// assert_eq!(refined.n_vertices(), mesh.n_vertices() + mesh.n_edges());
    /// assert_eq!(refined.n_edges(), 2 * mesh.n_edges());
    /// assert!(refined.faces().all(|f| f.len() == 6));
    /// assert!((0..refined.n_cells()).all(|c| refined.cell_vertices(c).len() == 10));
    /// assert_eq!(refined.part_names(), mesh.part_names());
    /// # Ok::<(), vem_mesh::MeshError>(())
    /// ```
    ///
    /// # Errors
    /// The validation of [`Self::from_compact`] (a valid mesh gives a valid refined one).
    pub fn with_edge_midpoints(&self) -> Result<Self, MeshError> {
        let n = self.vertices.len();
        let mut vertices = Vec::with_capacity(n + self.edges.len());
        vertices.extend_from_slice(&self.vertices);
        vertices.extend(self.edges.iter().map(|&[a, b]| {
            Point3::from((self.vertices[a].coords + self.vertices[b].coords) * 0.5)
        }));
        let mut face_offsets = Vec::with_capacity(self.face_offsets.len());
        face_offsets.push(0);
        let mut face_vertices = Vec::with_capacity(2 * self.face_vertices.len());
        for f in 0..self.n_faces() {
            face_vertices.extend(
                self.face(f)
                    .iter()
                    .zip(self.face_edges(f))
                    .flat_map(|(&v, &e)| [v, n + e]),
            );
            face_offsets.push(face_vertices.len());
        }
        Self::from_compact(
            vertices,
            face_offsets,
            face_vertices,
            self.cell_offsets.clone(),
            self.cell_faces.clone(),
            self.parts.clone(),
        )
    }

    /// This mesh with `parts` (boundary faces by index) in place of its parts, checked like the
    /// parts given to [`Self::from_compact`].
    pub fn with_parts(mut self, parts: Vec<FacePart>) -> Result<Self, MeshError> {
        self.parts = validate::check_parts(&self, parts)?;
        Ok(self)
    }
}

/// Derives the edges (sorted vertex pairs, in increasing order), the edge of every face corner
/// and the faces around every edge.
#[allow(clippy::type_complexity)]
fn derive_edges(
    n_vertices: usize,
    offsets: &[usize],
    indices: &[usize],
) -> (Vec<[usize; 2]>, Vec<usize>, Vec<usize>, Vec<usize>) {
    // (a, b, corner position) for every face corner, a < b, sorted.
    let mut corners: Vec<(usize, usize, usize)> = Vec::with_capacity(indices.len());
    let mut face_of = vec![0usize; indices.len()];
    for f in 0..offsets.len() - 1 {
        let loop_ = &indices[offsets[f]..offsets[f + 1]];
        let n = loop_.len();
        for k in 0..n {
            let (a, b) = (loop_[k], loop_[(k + 1) % n]);
            corners.push((a.min(b), a.max(b), offsets[f] + k));
            face_of[offsets[f] + k] = f;
        }
    }
    debug_assert!(corners.iter().all(|c| c.1 < n_vertices));
    corners.sort_unstable();
    let mut edges: Vec<[usize; 2]> = Vec::with_capacity(indices.len() / 2 + 1);
    let mut face_edges = vec![0usize; indices.len()];
    let mut edge_face_offsets = vec![0usize];
    let mut edge_faces = Vec::with_capacity(indices.len());
    for (a, b, position) in corners {
        if edges.last() != Some(&[a, b]) {
            edges.push([a, b]);
            edge_face_offsets.push(edge_faces.len());
        }
        let e = edges.len() - 1;
        face_edges[position] = e;
        edge_faces.push(face_of[position]);
        *edge_face_offsets.last_mut().expect("pushed") = edge_faces.len();
    }
    // Faces around each edge in increasing order (corners were sorted by position, and faces
    // are numbered in storage order), without repeats.
    let mut compact_offsets = vec![0usize];
    let mut compact = Vec::with_capacity(edge_faces.len());
    for e in 0..edges.len() {
        let start = compact.len();
        for &f in &edge_faces[edge_face_offsets[e]..edge_face_offsets[e + 1]] {
            if compact[start..].last() != Some(&f) {
                compact.push(f);
            }
        }
        compact_offsets.push(compact.len());
    }
    (edges, face_edges, compact_offsets, compact)
}

/// The sorted distinct vertices of every cell, compact.
fn cell_vertex_lists(
    face_offsets: &[usize],
    face_vertices: &[usize],
    cell_offsets: &[usize],
    cell_faces: &[OrientedFace],
) -> (Vec<usize>, Vec<usize>) {
    let mut offsets = Vec::with_capacity(cell_offsets.len());
    offsets.push(0);
    let mut vertices = Vec::new();
    for c in 0..cell_offsets.len() - 1 {
        let start = vertices.len();
        for slot in &cell_faces[cell_offsets[c]..cell_offsets[c + 1]] {
            vertices.extend_from_slice(
                &face_vertices[face_offsets[slot.face]..face_offsets[slot.face + 1]],
            );
        }
        vertices[start..].sort_unstable();
        let mut write = start;
        for read in start..vertices.len() {
            if write == start || vertices[read] != vertices[write - 1] {
                vertices[write] = vertices[read];
                write += 1;
            }
        }
        vertices.truncate(write);
        offsets.push(vertices.len());
    }
    (offsets, vertices)
}

/// Collects cells as lists of outward face loops and matches the loops that are the same face
/// seen from two cells (crate-internal builder of [`PolyhedralMesh::from_polyhedra`] and of the
/// generators).
#[derive(Debug, Default, Clone)]
pub(crate) struct CellsBuilder {
    loop_offsets: Vec<usize>,
    loop_vertices: Vec<usize>,
    cell_offsets: Vec<usize>,
}

impl CellsBuilder {
    #[cfg(feature = "generators")]
    /// A builder with room for about `cells` cells of `faces` faces of `corners` vertices.
    pub(crate) fn with_capacity(cells: usize, faces: usize, corners: usize) -> Self {
        let mut loop_offsets = Vec::with_capacity(cells * faces + 1);
        loop_offsets.push(0);
        let mut cell_offsets = Vec::with_capacity(cells + 1);
        cell_offsets.push(0);
        Self {
            loop_offsets,
            loop_vertices: Vec::with_capacity(cells * faces * corners),
            cell_offsets,
        }
    }

    /// Adds a face (vertex loop, outward) to the current cell.
    pub(crate) fn push_face(&mut self, loop_: &[usize]) {
        if self.loop_offsets.is_empty() {
            self.loop_offsets.push(0);
        }
        self.loop_vertices.extend_from_slice(loop_);
        self.loop_offsets.push(self.loop_vertices.len());
    }

    /// Ends the current cell.
    pub(crate) fn end_cell(&mut self) {
        if self.loop_offsets.is_empty() {
            self.loop_offsets.push(0);
        }
        if self.cell_offsets.is_empty() {
            self.cell_offsets.push(0);
        }
        self.cell_offsets.push(self.loop_offsets.len() - 1);
    }

    /// Matches the loops into faces: loops with the same vertex set and the same cyclic
    /// sequence (either direction) are one face; the first loop of a face is its stored loop.
    pub(crate) fn match_faces(self) -> MatchedFaces {
        let loop_offsets = if self.loop_offsets.is_empty() {
            vec![0]
        } else {
            self.loop_offsets
        };
        let cell_offsets = if self.cell_offsets.is_empty() {
            vec![0]
        } else {
            self.cell_offsets
        };
        let n_loops = loop_offsets.len() - 1;
        let mut sorted = self.loop_vertices.clone();
        for l in 0..n_loops {
            sorted[loop_offsets[l]..loop_offsets[l + 1]].sort_unstable();
        }
        // The first face with each vertex set; faces with the same set but another cycle
        // (invalid, reported by the validation as duplicates) go to `others`.
        let mut face_of_key: HashMap<&[usize], usize, FastHash> =
            HashMap::with_capacity_and_hasher(n_loops, FastHash::default());
        let mut others: Vec<(usize, usize)> = Vec::new();
        let mut face_offsets = vec![0usize];
        let mut face_vertices = Vec::with_capacity(self.loop_vertices.len() / 2 + 8);
        let mut slots = Vec::with_capacity(n_loops);
        for l in 0..n_loops {
            let loop_ = &self.loop_vertices[loop_offsets[l]..loop_offsets[l + 1]];
            let key = &sorted[loop_offsets[l]..loop_offsets[l + 1]];
            let next = face_offsets.len() - 1;
            let first = *face_of_key.entry(key).or_insert(next);
            let mut found = None;
            if first != next {
                let candidates = std::iter::once(first).chain(
                    others
                        .iter()
                        .filter(|&&(f, _)| f == first)
                        .map(|&(_, other)| other),
                );
                for f in candidates {
                    let stored = &face_vertices[face_offsets[f]..face_offsets[f + 1]];
                    if let Some(outward) = same_cycle(stored, loop_) {
                        found = Some(OrientedFace::new(f, outward));
                        break;
                    }
                }
            }
            let slot = match found {
                Some(slot) => slot,
                None => {
                    if first != next {
                        others.push((first, next));
                    }
                    face_vertices.extend_from_slice(loop_);
                    face_offsets.push(face_vertices.len());
                    OrientedFace::new(next, true)
                }
            };
            slots.push(slot);
        }
        MatchedFaces {
            face_offsets,
            face_vertices,
            cell_offsets,
            cell_faces: slots,
            keys: std::cell::OnceCell::new(),
        }
    }
}

/// Faces matched by a [`CellsBuilder`], ready to become a mesh.
pub(crate) struct MatchedFaces {
    pub(crate) face_offsets: Vec<usize>,
    pub(crate) face_vertices: Vec<usize>,
    pub(crate) cell_offsets: Vec<usize>,
    pub(crate) cell_faces: Vec<OrientedFace>,
    /// Face of each sorted vertex set, built on the first call of `find`.
    keys: std::cell::OnceCell<HashMap<Vec<usize>, usize, FastHash>>,
}

impl MatchedFaces {
    /// The face with the vertices of `loop_` (any order), if any.
    pub(crate) fn find(&self, loop_: &[usize]) -> Option<usize> {
        let keys = self.keys.get_or_init(|| {
            let mut keys =
                HashMap::with_capacity_and_hasher(self.face_offsets.len() - 1, FastHash::default());
            for f in 0..self.face_offsets.len() - 1 {
                let mut key = self.face(f).to_vec();
                key.sort_unstable();
                keys.entry(key).or_insert(f);
            }
            keys
        });
        let mut key = loop_.to_vec();
        key.sort_unstable();
        keys.get(&key).copied()
    }

    /// Indices of the faces used by exactly one cell.
    #[cfg(feature = "generators")]
    pub(crate) fn boundary_faces(&self) -> Vec<usize> {
        let mut count = vec![0u8; self.face_offsets.len() - 1];
        for slot in &self.cell_faces {
            count[slot.face] = count[slot.face].saturating_add(1);
        }
        (0..count.len()).filter(|&f| count[f] == 1).collect()
    }

    /// Vertex loop of face `f`.
    pub(crate) fn face(&self, f: usize) -> &[usize] {
        &self.face_vertices[self.face_offsets[f]..self.face_offsets[f + 1]]
    }

    /// The validated mesh.
    pub(crate) fn build(
        self,
        vertices: Vec<Point3>,
        parts: Vec<FacePart>,
    ) -> Result<PolyhedralMesh, MeshError> {
        PolyhedralMesh::from_compact(
            vertices,
            self.face_offsets,
            self.face_vertices,
            self.cell_offsets,
            self.cell_faces,
            parts,
        )
    }
}

/// A fast multiplicative hash for vertex-index keys (lookups only: nothing depends on the
/// iteration order of the maps that use it).
type FastHash = std::hash::BuildHasherDefault<FastHasher>;

/// The hasher of [`FastHash`].
#[derive(Debug, Default, Clone, Copy)]
pub(crate) struct FastHasher(u64);

impl std::hash::Hasher for FastHasher {
    fn finish(&self) -> u64 {
        self.0
    }

    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(u64::from(b));
        }
    }

    fn write_u64(&mut self, x: u64) {
        self.0 = (self.0.rotate_left(5) ^ x).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }

    fn write_usize(&mut self, x: usize) {
        self.write_u64(x as u64);
    }
}

/// `Some(true)` when `b` is the cyclic sequence `a` in the same direction, `Some(false)` when
/// in the opposite direction, `None` otherwise.
fn same_cycle(a: &[usize], b: &[usize]) -> Option<bool> {
    let n = a.len();
    if n != b.len() || n == 0 {
        return None;
    }
    let start = a.iter().position(|&v| v == b[0])?;
    if (0..n).all(|k| a[(start + k) % n] == b[k]) {
        return Some(true);
    }
    if (0..n).all(|k| a[(start + n - k) % n] == b[k]) {
        return Some(false);
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cycles_compare_in_both_directions() {
        assert_eq!(same_cycle(&[1, 2, 3, 4], &[3, 4, 1, 2]), Some(true));
        assert_eq!(same_cycle(&[1, 2, 3, 4], &[3, 2, 1, 4]), Some(false));
        assert_eq!(same_cycle(&[1, 2, 3, 4], &[1, 3, 2, 4]), None);
        assert_eq!(same_cycle(&[1, 2, 3], &[1, 2, 3, 4]), None);
    }
}
