//! Errors of the mesh layer.

use std::path::PathBuf;

/// Everything that can be wrong with a mesh or with the input it was built from.
///
/// Every variant names where the problem is (polygon, vertex, edge, part, file), so that a
/// user can find it in their own data.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum MeshError {
    /// The mesh has no vertices or no polygons.
    #[error("the mesh is empty ({vertices} vertices, {polygons} polygons)")]
    Empty {
        /// Number of vertices given.
        vertices: usize,
        /// Number of polygons given.
        polygons: usize,
    },
    /// A vertex coordinate is NaN or infinite.
    #[error("vertex {vertex} has a non-finite coordinate ({x}, {y})")]
    NonFiniteVertex {
        /// Vertex index.
        vertex: usize,
        /// Its x coordinate.
        x: f64,
        /// Its y coordinate.
        y: f64,
    },
    /// The polygon storage is inconsistent (offsets not increasing, or not ending at the
    /// number of indices).
    #[error("polygon storage is inconsistent: {reason}")]
    BadStorage {
        /// What is wrong.
        reason: String,
    },
    /// A polygon has fewer than three vertices.
    #[error("polygon {polygon} has {count} vertices; at least 3 are needed")]
    TooFewVertices {
        /// Polygon index.
        polygon: usize,
        /// Its number of vertices.
        count: usize,
    },
    /// A polygon refers to a vertex that does not exist.
    #[error(
        "polygon {polygon} refers to vertex {vertex}, but the mesh has {vertex_count} vertices"
    )]
    VertexOutOfRange {
        /// Polygon index.
        polygon: usize,
        /// The offending vertex index.
        vertex: usize,
        /// Number of vertices of the mesh.
        vertex_count: usize,
    },
    /// A polygon lists the same vertex twice.
    #[error("polygon {polygon} lists vertex {vertex} more than once")]
    RepeatedVertex {
        /// Polygon index.
        polygon: usize,
        /// The repeated vertex.
        vertex: usize,
    },
    /// A polygon's vertex loop runs clockwise (its signed area is negative).
    #[error("polygon {polygon} is clockwise (signed area {signed_area:e}); vertex loops must run counter-clockwise")]
    Clockwise {
        /// Polygon index.
        polygon: usize,
        /// Its signed area.
        signed_area: f64,
    },
    /// A polygon has zero area (relative to its diameter squared).
    #[error("polygon {polygon} has zero or negligible area ({area:e})")]
    DegenerateArea {
        /// Polygon index.
        polygon: usize,
        /// Its signed area.
        area: f64,
    },
    /// Two edges of one polygon cross or touch away from their shared vertex.
    #[error("polygon {polygon} intersects itself: its edges {edge_a} and {edge_b} (local numbering) cross")]
    SelfIntersecting {
        /// Polygon index.
        polygon: usize,
        /// Local index of the first edge (edge k joins local vertices k and k+1).
        edge_a: usize,
        /// Local index of the second edge.
        edge_b: usize,
    },
    /// Two distinct vertices are closer than the tolerance.
    #[error(
        "vertices {a} and {b} are {distance:e} apart, closer than the tolerance {tolerance:e}"
    )]
    DuplicateVertices {
        /// First vertex.
        a: usize,
        /// Second vertex.
        b: usize,
        /// Their distance.
        distance: f64,
        /// The tolerance in force.
        tolerance: f64,
    },
    /// An edge is used by more than two polygons, or twice in the same direction.
    #[error("edge ({a}, {b}) is used {count} times (polygons {polygons:?}); an edge may border at most two polygons, in opposite directions")]
    OverusedEdge {
        /// First vertex of the edge.
        a: usize,
        /// Second vertex of the edge.
        b: usize,
        /// How many polygons use it.
        count: usize,
        /// The polygons using it.
        polygons: Vec<usize>,
    },
    /// An edge of one polygon overlaps an edge of another polygon without sharing its
    /// vertices (a hanging node that the neighbour does not list as a vertex).
    #[error("non-conforming edges: edge ({a0}, {a1}) of polygon {polygon_a} overlaps edge ({b0}, {b1}) of polygon {polygon_b} without sharing its vertices")]
    NonConforming {
        /// Polygon owning the first edge.
        polygon_a: usize,
        /// First vertex of the first edge.
        a0: usize,
        /// Second vertex of the first edge.
        a1: usize,
        /// Polygon owning the second edge.
        polygon_b: usize,
        /// First vertex of the second edge.
        b0: usize,
        /// Second vertex of the second edge.
        b1: usize,
    },
    /// Polygons overlap (an interior point of one lies inside another).
    #[error("polygons {a} and {b} overlap")]
    Overlapping {
        /// First polygon.
        a: usize,
        /// Second polygon.
        b: usize,
    },
    /// A polyhedral mesh has no vertices, faces or cells.
    #[error("the polyhedral mesh is empty ({vertices} vertices, {faces} faces, {cells} cells)")]
    EmptyPolyhedral {
        /// Number of vertices given.
        vertices: usize,
        /// Number of faces given.
        faces: usize,
        /// Number of cells given.
        cells: usize,
    },
    /// A vertex of a polyhedral mesh has a NaN or infinite coordinate.
    #[error("vertex {vertex} has a non-finite coordinate ({x}, {y}, {z})")]
    NonFiniteVertex3 {
        /// Vertex index.
        vertex: usize,
        /// Its x coordinate.
        x: f64,
        /// Its y coordinate.
        y: f64,
        /// Its z coordinate.
        z: f64,
    },
    /// A face of a polyhedral mesh has fewer than three vertices.
    #[error("face {face} has {count} vertices; at least 3 are needed")]
    FaceTooFewVertices {
        /// Face index.
        face: usize,
        /// Its number of vertices.
        count: usize,
    },
    /// A face refers to a vertex that does not exist.
    #[error("face {face} refers to vertex {vertex}, but the mesh has {vertex_count} vertices")]
    FaceVertexOutOfRange {
        /// Face index.
        face: usize,
        /// The offending vertex index.
        vertex: usize,
        /// Number of vertices of the mesh.
        vertex_count: usize,
    },
    /// A face lists the same vertex twice.
    #[error("face {face} lists vertex {vertex} more than once")]
    FaceRepeatedVertex {
        /// Face index.
        face: usize,
        /// The repeated vertex.
        vertex: usize,
    },
    /// A cell refers to a face that does not exist.
    #[error("cell {cell} refers to face {face}, but the mesh has {face_count} faces")]
    CellFaceOutOfRange {
        /// Cell index.
        cell: usize,
        /// The offending face index.
        face: usize,
        /// Number of faces of the mesh.
        face_count: usize,
    },
    /// A cell has fewer than four faces.
    #[error("cell {cell} has {count} faces; a polyhedron needs at least 4")]
    CellTooFewFaces {
        /// Cell index.
        cell: usize,
        /// Its number of faces.
        count: usize,
    },
    /// A cell lists the same face twice.
    #[error("cell {cell} lists face {face} more than once")]
    CellRepeatedFace {
        /// Cell index.
        cell: usize,
        /// The repeated face.
        face: usize,
    },
    /// A face belongs to no cell.
    #[error("face {face} belongs to no cell")]
    UnusedFace {
        /// Face index.
        face: usize,
    },
    /// A face belongs to more than two cells.
    #[error("face {face} belongs to {} cells ({cells:?}); a face may bound at most two", cells.len())]
    OverusedFace {
        /// Face index.
        face: usize,
        /// The cells using it.
        cells: Vec<usize>,
    },
    /// The two cells of an interior face see it with the same orientation (both outward or
    /// both inward), so they lie on the same side of it.
    #[error("face {face} is seen {} by both its cells {cells:?}; an interior face must be outward for one cell and inward for the other", if *outward { "outward" } else { "inward" })]
    FaceSameOrientation {
        /// Face index.
        face: usize,
        /// The two cells.
        cells: [usize; 2],
        /// How both see it.
        outward: bool,
    },
    /// Two faces have the same vertices.
    #[error("faces {a} and {b} have the same vertices")]
    DuplicateFace {
        /// First face.
        a: usize,
        /// Second face.
        b: usize,
    },
    /// A vertex belongs to no face.
    #[error("vertex {vertex} belongs to no face")]
    UnusedVertex {
        /// Vertex index.
        vertex: usize,
    },
    /// A cell's faces, oriented as the cell sees them, do not close up consistently: some edge
    /// is not traversed exactly once in each direction.
    #[error("cell {cell} is not a closed, consistently oriented surface: its faces traverse edge ({a}, {b}) {forward} time(s) from {a} to {b} and {backward} time(s) back")]
    CellNotClosed {
        /// Cell index.
        cell: usize,
        /// First vertex of the edge.
        a: usize,
        /// Second vertex of the edge.
        b: usize,
        /// Traversals from a to b.
        forward: usize,
        /// Traversals from b to a.
        backward: usize,
    },
    /// A cell's faces form more than one connected surface.
    #[error(
        "cell {cell} is not connected: face {face} shares no chain of edges with its first face"
    )]
    DisconnectedCell {
        /// Cell index.
        cell: usize,
        /// A face unreachable from the cell's first face.
        face: usize,
    },
    /// A vertex lies on a face (in its interior or on one of its edges) without being one of
    /// its vertices: a hanging node that the face does not list, or two cells overlapping.
    #[error("vertex {vertex} lies on face {face} but is not one of its vertices: a hanging node must be a vertex of every face it lies on (faces meant to be shared must list the same vertices)")]
    HangingVertex {
        /// The vertex.
        vertex: usize,
        /// The face it lies on.
        face: usize,
    },
    /// A cell has a negative volume: its faces are oriented inwards.
    #[error("cell {cell} is inverted (volume {volume:e}): its faces must be oriented outwards")]
    InvertedCell {
        /// Cell index.
        cell: usize,
        /// Its signed volume.
        volume: f64,
    },
    /// A cell has zero volume (relative to its size cubed).
    #[error("cell {cell} has zero or negligible volume ({volume:e})")]
    DegenerateCell {
        /// Cell index.
        cell: usize,
        /// Its signed volume.
        volume: f64,
    },
    /// A face has zero area (relative to its size squared).
    #[error("face {face} has zero or negligible area ({area:e})")]
    DegenerateFace {
        /// Face index.
        face: usize,
        /// Its area.
        area: f64,
    },
    /// Two edges of a planar face cross or touch away from their shared vertex.
    #[error(
        "face {face} intersects itself: its edges {edge_a} and {edge_b} (local numbering) cross"
    )]
    SelfIntersectingFace {
        /// Face index.
        face: usize,
        /// Local index of the first edge (edge k joins local vertices k and k+1).
        edge_a: usize,
        /// Local index of the second edge.
        edge_b: usize,
    },
    /// A warped (non-planar) face whose fan triangulation about its vertex mean folds over:
    /// seen along the face's mean normal, its fan triangle `triangle` (local vertices
    /// `triangle` and `triangle + 1` with the mean) is reversed or flat.
    #[error("face {face} is warped (out of plane by {warping:e} of its diameter) and its fan triangle {triangle} folds over")]
    FoldedFace {
        /// Face index.
        face: usize,
        /// Local index of the folded fan triangle.
        triangle: usize,
        /// Largest distance of a vertex from the face's mean plane, divided by its diameter.
        warping: f64,
    },
    /// A boundary part of a polyhedral mesh names a face index that does not exist.
    #[error("boundary part '{part}' names face {face}, but the mesh has {face_count} faces")]
    PartFaceOutOfRange {
        /// The part's name.
        part: String,
        /// The face index.
        face: usize,
        /// Number of faces of the mesh.
        face_count: usize,
    },
    /// A boundary part of a polyhedral mesh names a face (by its vertices) that is not a face of
    /// the mesh.
    #[error("boundary part '{part}' names the face with vertices {vertices:?}, which is not a face of the mesh")]
    UnknownFace {
        /// The part's name.
        part: String,
        /// The vertices given.
        vertices: Vec<usize>,
    },
    /// A boundary part of a polyhedral mesh names an interior face.
    #[error(
        "boundary part '{part}' names face {face}, which is interior (shared by cells {cells:?})"
    )]
    InteriorFaceInPart {
        /// The part's name.
        part: String,
        /// The face index.
        face: usize,
        /// Its two cells.
        cells: [usize; 2],
    },
    /// A boundary part names an edge that is not an edge of the mesh.
    #[error("boundary part '{part}' names ({a}, {b}), which is not an edge of the mesh")]
    UnknownEdge {
        /// The part's name.
        part: String,
        /// First vertex.
        a: usize,
        /// Second vertex.
        b: usize,
    },
    /// A boundary part names an interior edge.
    #[error("boundary part '{part}' names edge ({a}, {b}), which is interior (shared by polygons {left} and {right})")]
    InteriorEdgeInPart {
        /// The part's name.
        part: String,
        /// First vertex.
        a: usize,
        /// Second vertex.
        b: usize,
        /// One adjacent polygon.
        left: usize,
        /// The other adjacent polygon.
        right: usize,
    },
    /// Two boundary parts share a name.
    #[error("boundary part '{part}' is defined twice")]
    DuplicatePart {
        /// The part's name.
        part: String,
    },
    /// A boundary part with this name does not exist.
    #[error("no boundary part named '{part}'; the mesh has {available:?}")]
    UnknownPart {
        /// The requested name.
        part: String,
        /// The names that exist.
        available: Vec<String>,
    },
    /// A generator was given parameters it cannot use.
    #[error("generator '{generator}': {reason}")]
    BadGeneratorParameter {
        /// The generator's name.
        generator: &'static str,
        /// What is wrong.
        reason: String,
    },
    /// The polygon of a generated mesh's domain is not a simple counter-clockwise polygon
    /// (too few vertices, a non-finite coordinate, a zero-length edge, edges that cross or
    /// touch, clockwise or zero area) or its edge names do not fit it.
    #[error("domain polygon: {reason}")]
    BadDomainPolygon {
        /// The vertex where the problem is (edge k starts at vertex k), if one is to blame.
        vertex: Option<usize>,
        /// What is wrong, naming the vertex or edge.
        reason: String,
    },
    /// A setting (of [`crate::InterfaceOptions`]) is outside its range.
    #[error("{setting} = {value} must be {requirement}")]
    InvalidOption {
        /// The setting's name, as its field is spelt.
        setting: &'static str,
        /// The rejected value.
        value: f64,
        /// What it must satisfy.
        requirement: &'static str,
    },
    /// Interface node insertion failed.
    #[error("interface between '{part_a}' and '{part_b}': {reason}")]
    Interface {
        /// Part on the first mesh.
        part_a: String,
        /// Part on the second mesh.
        part_b: String,
        /// What went wrong.
        reason: String,
    },
    /// Reading a mesh file failed.
    #[error("{}: {reason}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// What went wrong (with the entity or line where known).
        reason: String,
    },
    /// Writing a file failed.
    #[error("cannot write {}: {reason}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        reason: String,
    },
}
