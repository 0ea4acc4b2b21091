//! Errors of the element layer.

/// What can go wrong on one polygon or with a material.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SpaceError {
    /// The polygon cannot carry an element (too few vertices, zero or negative area).
    #[error("degenerate polygon with {vertices} vertices: {reason}")]
    DegeneratePolygon {
        /// Number of vertices.
        vertices: usize,
        /// What is wrong.
        reason: String,
    },
    /// The elasticity tensor is not admissible (spec (2.8)).
    #[error("invalid material: {reason}")]
    InvalidMaterial {
        /// What is wrong.
        reason: String,
    },
    /// A body force or traction returned a non-finite value.
    #[error("non-finite load value at ({x}, {y})")]
    NonFiniteLoad {
        /// x of the evaluation point.
        x: f64,
        /// y of the evaluation point.
        y: f64,
    },
    /// The element type cannot handle this polygon (e.g. a P1 triangle given a quadrilateral).
    #[error("element '{element}' does not support a polygon with {vertices} vertices")]
    UnsupportedPolygon {
        /// Name of the element type.
        element: String,
        /// Number of vertices of the polygon.
        vertices: usize,
    },
    /// An edge (of a Neumann boundary) has zero length or non-finite end points.
    #[error("degenerate edge from ({x0}, {y0}) to ({x1}, {y1})")]
    DegenerateEdge {
        /// x of the first end point.
        x0: f64,
        /// y of the first end point.
        y0: f64,
        /// x of the second end point.
        x1: f64,
        /// y of the second end point.
        y1: f64,
    },
    /// A quadrature rule with this number of points is not tabulated.
    #[error("no {rule} rule with {points} points (supported: 1 to {max})")]
    UnsupportedQuadrature {
        /// Which family of rules.
        rule: &'static str,
        /// Number of points asked for.
        points: usize,
        /// Largest tabulated number of points.
        max: usize,
    },
    /// The polyhedron cannot carry an element (too few vertices or faces, faces that do not
    /// close or are not consistently oriented, a volume that is not positive, ...).
    #[error("degenerate polyhedron with {vertices} vertices and {faces} faces: {reason}")]
    DegeneratePolyhedron {
        /// Number of vertices.
        vertices: usize,
        /// Number of faces.
        faces: usize,
        /// What is wrong, naming the vertex or face.
        reason: String,
    },
    /// The element type cannot handle this polyhedron (e.g. a linear tetrahedron given a
    /// hexahedron).
    #[error("element '{element}' does not support a polyhedron with {vertices} vertices and {faces} faces")]
    UnsupportedPolyhedron {
        /// Name of the element type.
        element: String,
        /// Number of vertices of the polyhedron.
        vertices: usize,
        /// Number of faces of the polyhedron.
        faces: usize,
    },
    /// A body force or traction returned a non-finite value at a point of space.
    #[error("non-finite load value at ({x}, {y}, {z})")]
    NonFiniteLoadInSpace {
        /// x of the evaluation point.
        x: f64,
        /// y of the evaluation point.
        y: f64,
        /// z of the evaluation point.
        z: f64,
    },
    /// A boundary face (of a traction) has fewer than three vertices, non-finite vertices or
    /// zero area.
    #[error("degenerate face with {vertices} vertices: {reason}")]
    DegenerateFace {
        /// Number of vertices.
        vertices: usize,
        /// What is wrong.
        reason: String,
    },
    /// The stabilisation's settings or values are not admissible (a non-positive or non-finite
    /// scale, a diagonal of the wrong length or with a non-positive entry).
    #[error("invalid stabilisation '{stabilisation}': {reason}")]
    InvalidStabilisation {
        /// The stabilisation's name.
        stabilisation: String,
        /// What is wrong.
        reason: String,
    },
}
