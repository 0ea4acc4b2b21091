//! Errors of the discrete problems, error norms, studies and reports.

use std::path::PathBuf;

use vem_contact::{ContactError, RegistryError};
use vem_elastic::ElasticError;
use vem_mesh::MeshError;
use vem_space::SpaceError;

use crate::exact::ExactError;

/// What can go wrong when a discrete problem is built from an exact solution, solved, measured
/// or reported. Variants name the case, body, size, polygon or file concerned; a variant
/// wrapping a lower layer's error names where it happened and leaves the cause to
/// [`source`](std::error::Error::source) (print the chain to see both).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum VerifyError {
    /// A study or problem setting is out of range (no sizes, a size factor of zero, ...).
    #[error("invalid setting: {reason}")]
    InvalidSetting {
        /// What is wrong, with the offending value.
        reason: String,
    },
    /// The exact solution does not fit what was asked of it (a two-body pairing for a
    /// one-body case, a contact case without a contact description, ...).
    #[error("case {case}: {reason}")]
    Case {
        /// The case's name.
        case: String,
        /// What does not fit.
        reason: String,
    },
    /// The exact-solution layer refused a request.
    #[error(transparent)]
    Exact(#[from] ExactError),
    /// Mesh generation failed.
    #[error("case {case}, body {body}: cannot generate the mesh '{family}' of size {n}")]
    Mesh {
        /// The case's name.
        case: String,
        /// The body (1 or 2).
        body: usize,
        /// The mesh family.
        family: String,
        /// The size parameter.
        n: usize,
        /// The mesh error.
        #[source]
        source: Box<MeshError>,
    },
    /// Building, assembling or solving an elastic body failed.
    #[error("case {case}: the elastic problem failed")]
    Elastic {
        /// The case's name.
        case: String,
        /// The elasticity error (it names the body).
        #[source]
        source: Box<ElasticError>,
    },
    /// The scene of the problem was refused when the model was built
    /// ([`vem_scene::Model::build`]): an invalid material or setting, a side the mesh does not
    /// name, inconsistent Dirichlet data, at the scene's key.
    #[error("case {case}: the scene of the problem was refused")]
    Scene {
        /// The case's name.
        case: String,
        /// The scene's error, at its key.
        #[source]
        source: Box<vem_scene::SceneError>,
    },
    /// Building or solving the contact problem failed.
    #[error("case {case}: the contact problem failed")]
    Contact {
        /// The case's name.
        case: String,
        /// The contact error.
        #[source]
        source: Box<ContactError>,
    },
    /// The contact solver could not be made: a name the registry does not know, or options
    /// it refuses.
    #[error("case {case}: no contact solver {name:?}")]
    Solver {
        /// The case's name.
        case: String,
        /// The solver name asked for.
        name: String,
        /// The registry's error (it lists the known names or the refused option).
        #[source]
        source: Box<RegistryError>,
    },
    /// The element layer failed on one polygon while errors were measured.
    #[error("body {body}, polygon {polygon}: the element failed while errors were measured")]
    Element {
        /// The body (1 or 2).
        body: usize,
        /// The polygon index.
        polygon: usize,
        /// The element error.
        #[source]
        source: Box<SpaceError>,
    },
    /// A polygon could not be split into triangles for quadrature (it is not simple).
    #[error("body {body}, polygon {polygon}: no valid triangulation ({reason})")]
    Triangulation {
        /// The body (1 or 2).
        body: usize,
        /// The polygon index.
        polygon: usize,
        /// Why.
        reason: String,
    },
    /// A displacement vector does not match the mesh.
    #[error(
        "body {body}: displacement has {found} entries, the mesh has {expected} degrees of freedom"
    )]
    WrongLength {
        /// The body (1 or 2).
        body: usize,
        /// Entries given.
        found: usize,
        /// Degrees of freedom of the mesh.
        expected: usize,
    },
    /// A measured quantity is not finite (an exact solution or a solve produced NaN or inf).
    #[error("body {body}: {what} is not finite")]
    NonFinite {
        /// The body (1 or 2).
        body: usize,
        /// What was measured.
        what: &'static str,
    },
    /// A report could not be written.
    #[error("cannot write {}: {reason}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// Why.
        reason: String,
    },
}

impl VerifyError {
    /// Wraps a failed atomic write of `vem_mesh::io::write_atomically` (it names the path).
    pub(crate) fn from_write(path: &std::path::Path, error: MeshError) -> Self {
        let reason = match error {
            MeshError::Write { reason, .. } => reason,
            other => other.to_string(),
        };
        VerifyError::Write {
            path: path.to_path_buf(),
            reason,
        }
    }
}
