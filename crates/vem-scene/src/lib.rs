//! The problem as data: one description of a contact problem that the command line, the
//! studies and the Python package share.
//!
//! A [`Scene`] holds bodies (mesh, material, element, Dirichlet conditions, rigid plates,
//! tractions, body force), contact pairs (another body or a rigid obstacle, with a contact law
//! by registry name and its settings), the contact solver by registry name and its settings,
//! an accuracy preset, a load history, outputs and limits. It is plain serde data: a TOML scene
//! file ([`toml_file::parse`]), a JSON document or a Python dict read the same keys, documented
//! in `docs/scenes.md`. Values that may vary over a body are numbers, expressions of `x, y, z,
//! t` ([`ScalarValue`]) or, from Rust, functions.
//!
//! A run goes through three steps, each public:
//!
//! 1. [`Model::build`]: the scene checked (every error at its [`KeyPath`], such as
//!    `contact[0].law.friction_bound`), meshes generated or read, part names checked against
//!    them, the elastic bodies, the contact problem of every pair and the solver's choice, with
//!    the elements, laws and solvers of the [`Registries`];
//! 2. [`Model::solve`]: the [`Outcome`] with its [`RunSummary`], the contact library's own
//!    reports serialised as they are;
//! 3. writing files is the tools' business (the `vem` command writes VTU, CSV, SVG, JSON).
//!
//! Earlier forms of keys (a contact's `friction_bound`, `solver` or `tolerance`, a body's
//! `stabilisation`) are still read; each gives a [`Deprecation`] note naming the new key.
//!
//! # Example: a block pressed on a rigid line
//!
//! A uniform pressure `p = 0.01` on the top of a block lying on the rigid line `y = 0`
//! (frictionless, held sideways by a roller on its left side): the stress is uniform, so the
//! contact pressure is `p` at every node and the resultant is `p` times the width.
//!
//! ```
//! use vem_scene::{toml_file, BuildOptions, Model};
//!
//! let (scene, _) = toml_file::parse(r#"
//!     solver = { name = "exact", tolerance = 1e-13 }
//!
//!     [[body]]
//!     name = "block"
//!     mesh = { family = "voronoi", rectangle = [[0, 0], [2, 1]], n = 6, seed = 3 }
//!     material = { E = 100.0, nu = 0.3, plane = "strain" }
//!     dirichlet = [{ part = "left", x = 0.0 }]
//!     traction = [{ part = "top", pressure = 0.01 }]
//!
//!     [[contact]]
//!     body = "block"
//!     part = "bottom"
//!     obstacle = { line = { point = [0, 0], normal = [0, 1] } }
//! "#).map_err(|e| e.message)?;
//! let outcome = Model::build(&scene, &BuildOptions::default())?.solve()?;
//! let contact = outcome.contact.as_ref().unwrap();
//! for node in &contact.nodes {
//!     assert!((node.pressure / 0.01 - 1.0).abs() < 1e-6, "{}", node.pressure);
//! }
//! assert!((contact.normal_resultant() / 0.02 - 1.0).abs() < 1e-6);
//! // Frictionless against an obstacle: one body, normal rows only.
//! assert_eq!(outcome.summary.contact.as_ref().unwrap().model.tangential_rows, 0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![deny(missing_docs)]

mod adapt;
mod build;
pub mod check;
pub mod description;
mod error;
mod history;
pub mod resources;
mod solve;
mod space;
#[cfg(feature = "toml")]
pub mod toml_file;
mod value;

pub use adapt::{AdaptCycle, AdaptStop, AdaptSummary};
pub use build::{
    body_mesh, inline_mesh, BuildOptions, Model, ModelBody, ModelContact, Registries, LOCKING_FREE,
    NEARLY_INCOMPRESSIBLE,
};
pub use description::{MeshDescription, OutputFiles, Scene, VtuEncodingName};
pub use error::{one_line, Deprecation, KeyPath, SceneError, Segment};
pub use history::MAX_STEPS;
pub use solve::{
    describe_material, short, young_poisson, BodySummary, ContactSummary, ErrorEstimate,
    HertzComparison, Outcome, ReactionSummary, Resultants, RunSummary, RunTimes, SolvedBody,
    StepSummary,
};
pub use space::BuiltMesh;
pub use value::{ScalarFunction, ScalarValue, VectorFunction, VectorValue};
