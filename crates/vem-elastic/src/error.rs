//! Errors of the elasticity layer.

use vem_mesh::MeshError;
use vem_space::SpaceError;

/// What can go wrong in a linear solver behind [`crate::LinearSolver`], independent of any body.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SolveError {
    /// The matrix is not (numerically) positive definite: a pivot of the Cholesky factorisation
    /// was zero or negative.
    #[error("the matrix is not positive definite (non-positive pivot at elimination step {step})")]
    NotPositiveDefinite {
        /// The elimination step (in the fill-reducing order) at which the pivot failed.
        step: usize,
    },
    /// `factorise` or `solve` was called before the step it depends on.
    #[error("linear solver used out of order: {reason}")]
    OutOfOrder {
        /// What was missing.
        reason: &'static str,
    },
    /// The matrix or right-hand side does not match the analysed pattern.
    #[error("dimension or pattern mismatch: {reason}")]
    Mismatch {
        /// What does not match.
        reason: String,
    },
    /// A solver setting is out of range.
    #[error("invalid solver setting: {reason}")]
    InvalidSetting {
        /// What is wrong, with the offending value.
        reason: String,
    },
    /// The backend failed for a reason of its own (out of memory, ...).
    #[error("linear solver backend failed: {reason}")]
    Backend {
        /// The backend's message.
        reason: String,
    },
}

/// Everything that can go wrong while setting up, assembling, solving or post-processing one
/// elastic body. Variants carry the body's name and, where it applies, the part, polygon or
/// vertex concerned.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ElasticError {
    /// The material parameters are not admissible (spec (2.8)).
    #[error("invalid material: {reason}")]
    InvalidMaterial {
        /// What is wrong, with the offending value.
        reason: String,
    },
    /// A setting is out of its admissible range.
    #[error("invalid setting: {reason}")]
    InvalidSetting {
        /// What is wrong, with the offending value.
        reason: String,
    },
    /// A mesh-level problem, typically a boundary part that does not exist.
    #[error("body '{body}': mesh error")]
    Mesh {
        /// The body's name.
        body: String,
        /// The mesh error (for an unknown part it lists the parts that exist).
        #[source]
        source: MeshError,
    },
    /// The element layer failed on one cell (a polygon in 2D).
    #[error("body '{body}', polygon {polygon}: the element failed")]
    Element {
        /// The body's name.
        body: String,
        /// The polygon index.
        polygon: usize,
        /// The element error.
        #[source]
        source: SpaceError,
    },
    /// The element type cannot be built on a polygon of the mesh (e.g. the linear triangle on a
    /// quadrilateral, or on a triangle that gained a vertex by interface node insertion).
    /// Checked for every polygon before any assembly.
    #[error("body '{body}': element '{element}' does not support polygon {polygon} with {vertices} vertices")]
    UnsupportedPolygon {
        /// The body's name.
        body: String,
        /// The element's name.
        element: String,
        /// The first polygon the element does not support.
        polygon: usize,
        /// Its number of vertices.
        vertices: usize,
    },
    /// An element returned a local matrix or load vector of the wrong size.
    #[error("body '{body}', polygon {polygon}: the element returned {what} of size {found} for {vertices} vertices (expected {expected})")]
    ElementSize {
        /// The body's name.
        body: String,
        /// The polygon index.
        polygon: usize,
        /// The polygon's number of vertices.
        vertices: usize,
        /// Which array.
        what: &'static str,
        /// Its size as returned (rows or length).
        found: usize,
        /// The expected size (the element's degrees of freedom on the cell).
        expected: usize,
    },
    /// A traction failed on one boundary facet (an edge in 2D, a face in 3D).
    #[error("body '{body}', traction on part '{part}', facet {facet:?}: the facet load failed")]
    Traction {
        /// The body's name.
        body: String,
        /// The boundary part.
        part: String,
        /// The vertices of the facet.
        facet: Vec<usize>,
        /// The element error.
        #[source]
        source: SpaceError,
    },
    /// Prescribed displacement data returned a non-finite value.
    #[error("body '{body}', Dirichlet part '{part}': non-finite displacement {value} at vertex {vertex}")]
    NonFiniteDirichlet {
        /// The body's name.
        body: String,
        /// The boundary part.
        part: String,
        /// The vertex at which the data was evaluated.
        vertex: usize,
        /// The value returned.
        value: f64,
    },
    /// Two Dirichlet conditions prescribe different values for the same degree of freedom
    /// (typically at a corner shared by two parts).
    #[error("body '{body}': parts '{first}' and '{second}' prescribe different values ({first_value} and {second_value}) for component {component} of vertex {vertex}")]
    ConflictingDirichlet {
        /// The body's name.
        body: String,
        /// The vertex.
        vertex: usize,
        /// The component (0 = x, 1 = y, 2 = z).
        component: usize,
        /// The part that prescribed it first.
        first: String,
        /// Its value.
        first_value: f64,
        /// The part that prescribes it again.
        second: String,
        /// Its value.
        second_value: f64,
    },
    /// A rigid plate shares a degree of freedom with another condition (a plate's component
    /// cannot also be prescribed, nor tied to a second plate).
    #[error("body '{body}': rigid plate '{plate}' and condition on part '{other}' both constrain component {component} of vertex {vertex}")]
    RigidPlateConflict {
        /// The body's name.
        body: String,
        /// The rigid plate's part.
        plate: String,
        /// The part of the other condition.
        other: String,
        /// The vertex.
        vertex: usize,
        /// The component (0 = x, 1 = y, 2 = z).
        component: usize,
    },
    /// A rigid plate's prescribed resultant is not finite.
    #[error("body '{body}', rigid plate '{part}': non-finite resultant {value} in component {component}")]
    NonFiniteResultant {
        /// The body's name.
        body: String,
        /// The rigid plate's part.
        part: String,
        /// The component (0 = x, 1 = y, 2 = z).
        component: usize,
        /// The value.
        value: f64,
    },
    /// The reduced stiffness is not positive definite: the body can move as a rigid body.
    #[error(
        "singular stiffness: body '{body}' is not held (no or insufficient Dirichlet condition)"
    )]
    SingularStiffness {
        /// The body's name.
        body: String,
    },
    /// The reduced stiffness of a held body (its Dirichlet conditions fix the three rigid
    /// motions) could not be factorised or solved accurately: badly shaped elements make it
    /// too ill-conditioned for double precision. Names the worst element.
    #[error(
        "body '{body}' is held but its stiffness is too ill-conditioned to solve ({reason}); \
         worst element {element}: gamma (A1) = {gamma:.3e}, diameter {diameter:.3e}"
    )]
    IllConditioned {
        /// The body's name.
        body: String,
        /// What failed (the factorisation, or the accuracy of the solve).
        reason: String,
        /// The polygon with the smallest gamma of assumption A1.
        element: usize,
        /// Its gamma (smaller of shortest edge / diameter and star radius / diameter).
        gamma: f64,
        /// Its diameter.
        diameter: f64,
    },
    /// The linear solver failed for another reason.
    #[error("body '{body}': the linear solver failed")]
    Solver {
        /// The body's name.
        body: String,
        /// The solver error.
        #[source]
        source: SolveError,
    },
    /// A vector passed in has the wrong length.
    #[error("body '{body}': {what} has length {found}, expected {expected}")]
    WrongLength {
        /// The body's name.
        body: String,
        /// Which vector.
        what: &'static str,
        /// Its length.
        found: usize,
        /// The expected length.
        expected: usize,
    },
    /// An assembled system was passed to a body it was not built for.
    #[error("body '{body}': the assembled system was built for a different mesh or set of Dirichlet conditions")]
    ForeignSystem {
        /// The body's name.
        body: String,
    },
}

impl ElasticError {
    /// Maps a solver error to the body-level error: a non-positive-definite stiffness is a
    /// body that is not held.
    pub fn from_solver(body: &str, source: SolveError) -> Self {
        match source {
            SolveError::NotPositiveDefinite { .. } => ElasticError::SingularStiffness {
                body: body.to_string(),
            },
            source => ElasticError::Solver {
                body: body.to_string(),
                source,
            },
        }
    }
}
