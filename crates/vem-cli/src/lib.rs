//! The `vem` command as a library: contact scenes described in TOML (the problem description
//! of `vem_scene`), solved with the lowest-order virtual element method, written as files one
//! can look at.
//!
//! A run goes through four stages, each a public step so that tests and other programs use
//! exactly what the binary uses:
//!
//! 1. [`Scene::load`] / [`Scene::parse`]: the TOML file read into a `vem_scene::Scene` and
//!    checked; every error names the file, line and column;
//! 2. [`Model::build`]: meshes generated or read, part names checked against them (an unknown
//!    part lists the parts that exist), elastic bodies, the contact problem of every pair and
//!    the solver; only what the scene requires;
//! 3. [`Model::solve`]: the [`Outcome`] with its summary;
//! 4. [`Outcome::write`]: `<body>.vtu`, `contact.csv`, `deformed.svg`, `pressure.svg`,
//!    `slip.svg` (with friction) and `summary.json` (the kinds of files of the scene's
//!    `[output] files`), written as a set, all or nothing.
//!
//! [`run`] does all four with the built-in solvers, elements and laws, [`run_with`] with the
//! [`Registries`] of one's own. The scene format is documented key by key in `docs/scenes.md`.
//!
//! # Example: a block pressed on a rigid line
//!
//! A uniform pressure `p = 0.01` on the top of a block lying on the rigid line `y = 0`
//! (frictionless, the block held sideways by a roller on its left side): the stress is
//! uniform, so the discrete contact pressure is `p` at every node and the resultant is
//! `p` times the width.
//!
//! ```
//! use vem_cli::{Model, Scene};
//!
//! let scene = Scene::parse("block.toml", r#"
//!     solver = { name = "exact", tolerance = 1e-13 }  # forces are checked to 1e-6
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
//! "#)?;
//! let outcome = Model::build(&scene)?.solve()?;
//! let contact = outcome.contact.as_ref().unwrap();
//! for node in &contact.nodes {
//!     assert!((node.pressure / 0.01 - 1.0).abs() < 1e-6, "{}", node.pressure);
//! }
//! assert!((contact.normal_resultant() / 0.02 - 1.0).abs() < 1e-6);
//! // Frictionless against an obstacle: one body, normal rows only.
//! assert_eq!(outcome.summary.bodies.len(), 1);
//! assert_eq!(outcome.summary.contact.as_ref().unwrap().model.tangential_rows, 0);
//! # Ok::<(), vem_cli::CliError>(())
//! ```
#![deny(missing_docs)]

mod error;
mod mesh_command;
mod model;
mod outcome;
mod output;
mod output3d;
mod plot;
pub mod scene;

use std::path::{Path, PathBuf};

pub use error::{CliError, Location};
pub use mesh_command::{convert_mesh, generate_mesh, generate_mesh_within, MeshReport};
pub use model::{CheckReport, CheckedBody, CheckedContact, Model};
pub use outcome::{Outcome, OutputSettings};
pub use output::{status_label, CONTACT_COLUMNS, DEFAULT_WIDTH};
pub use output3d::{CONTACT_COLUMNS_3D, NO_PICTURES_IN_SPACE, REACTION_COLUMNS};
pub use scene::Scene;
pub use vem_scene::resources;
pub use vem_scene::{Registries, RunSummary, SolvedBody};

/// The default output directory of a scene: `out/<scene file stem>` under the current
/// directory.
pub fn default_output_dir(scene: &Scene) -> PathBuf {
    Path::new("out").join(scene.stem())
}

/// Loads, builds, solves and writes the scene at `scene` into `out` (default
/// [`default_output_dir`]) with the built-in solvers; returns the outcome and the files
/// written.
pub fn run(scene: &Path, out: Option<&Path>) -> Result<(Outcome, Vec<PathBuf>), CliError> {
    run_with(scene, out, &Registries::default())
}

/// As [`run`], with the solvers and elements of `registries`: a scene's `solver` and `element`
/// keys may then name a solver or an element of one's own.
pub fn run_with(
    scene: &Path,
    out: Option<&Path>,
    registries: &Registries,
) -> Result<(Outcome, Vec<PathBuf>), CliError> {
    let scene = Scene::load(scene)?;
    let mut outcome = Model::build_with(&scene, registries)?.solve()?;
    let dir = out.map_or_else(|| default_output_dir(&scene), Path::to_path_buf);
    let files = outcome.write(&dir)?;
    Ok((outcome, files))
}
