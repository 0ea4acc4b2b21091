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
}
