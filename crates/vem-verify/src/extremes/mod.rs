//! Stability at the extremes: rows, each an extreme of the data, the mesh or a solver setting
//! with its independent expected answer, solved by every registered contact solver and judged.
//! `cargo xtask extremes` writes them as `docs/extremes.md`; the workspace test
//! `tests/tests/extremes.rs` runs every group at [`Size::test`].
//!
//! Expected answers come from outside the solvers:
//! - two-body linear patch tests (uniform stress in each body, any Lamé parameters per body):
//!   the lowest-order VEM reproduces them exactly on any mesh, so the nodal displacements and
//!   the normal resultant are known exactly;
//! - invariances: a problem whose lengths are scaled by `s` and moduli by `m` has the
//!   displacement `s u(x/s)` and nodal forces `m s` times those of the unscaled problem;
//!   Tresca with `g_F = 0` is the frictionless problem;
//! - the divergence-free solutions E2 (one body) and E2c (two bodies in contact) of
//!   [`exact`](crate::exact) for the locking measure, and plane-strain Hertz for the shipped
//!   Hertz scene;
//! - in space, the uniform uniaxial (and sheared) state of two stacked blocks and the
//!   divergence-free solution E2-3D of [`three_d`](crate::three_d).
//!
//! The rows in the plane are in [`plane`], those in space in [`space`]; this module holds what
//! both share: the [`Row`], its [`Outcome`]s and their [`Verdict`], the [`Size`] of a run, the
//! tolerances and the judging of a solve.
//!
//! This module needs the `extremes` feature (it builds the shipped Hertz scene with
//! `vem-scene`).
//!
//! ```no_run
//! use vem_verify::extremes::{groups, Size, Verdict};
//! let size = Size::test();
//! for (title, group) in groups() {
//!     let rows = group(&size);
//!     let wrong = rows
//!         .iter()
//!         .flat_map(|r| &r.outcomes)
//!         .filter(|o| o.verdict == Verdict::Wrong)
//!         .count();
//!     println!("{title}: {} rows, {wrong} wrong answers reported as converged", rows.len());
//! }
//! ```

pub mod plane;
pub mod space;

use std::path::PathBuf;

use serde::{Deserialize, Serialize};
use vem_contact::{ContactError, ContactProblem, ContactResult, SolverRegistry};
use vem_mesh::generators::MeshFamily;
use vem_space::Options;

use crate::cases::PATCH_TOLERANCE;

pub use plane::{
    cells, contrast, friction, gaps, incompressible_contact, penalty, poisson, units, Cells,
    CONTACT_POISSON_RATIOS, HERTZ_LOCKING_CHANGE,
};
pub use space::{solid_contact, solid_friction, solid_poisson, SOLID_POISSON_RATIOS};

/// Relative change of an answer allowed under a change of units.
pub const UNITS_TOLERANCE: f64 = 1e-10;
/// Relative difference allowed between two solves of the same mathematical problem posed two
/// ways (Tresca with a zero bound against frictionless): the solvers' tolerances. The interior
/// point of the exact solver certifies less: see [`plane::same_problem_tolerance`].
pub const SAME_PROBLEM_TOLERANCE: f64 = 1e-7;
/// Largest ratio of the E2 errors at a Poisson ratio to those at nu = 0.3 (locking-free
/// means within 2x).
pub const LOCKING_RATIO: f64 = 2.0;
/// Poisson ratios of the locking sweep.
pub const POISSON_RATIOS: [f64; 6] = [0.3, 0.4, 0.49, 0.499, 0.4999, 0.49999];

/// How a row came out for one solver (in JSON: `"Pass"`, `"Wrong"`, or `{"Refused": message}`,
/// `{"Warned": message}`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum Verdict {
    /// The expected answer, within the row's tolerance.
    Pass,
    /// The solver (or the model building) refused with an error: no wrong answer was given.
    Refused(String),
    /// A wrong answer, but reported with a warning.
    Warned(String),
    /// A wrong answer reported as converged without a warning.
    Wrong,
}

impl Verdict {
    /// The word of the report.
    pub fn word(&self) -> &'static str {
        match self {
            Verdict::Pass => "PASS",
            Verdict::Refused(_) => "FAIL (refused: error)",
            Verdict::Warned(_) => "FAIL (warned)",
            Verdict::Wrong => "FAIL (wrong answer reported as converged)",
        }
    }

    /// True unless a wrong answer came without an error or a warning.
    pub fn is_honest(&self) -> bool {
        !matches!(self, Verdict::Wrong)
    }
}

/// One solver's outcome of a row.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Outcome {
    /// Solver name (registry name), or the linear solver for elasticity rows.
    pub solver: String,
    /// What was measured, in words and numbers.
    pub measured: String,
    /// The judgement.
    pub verdict: Verdict,
}

/// One extreme: what is expected and what each solver gave.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Row {
    /// The extreme, e.g. "nu = 0.49999, vem1".
    pub name: String,
    /// The expected answer and its tolerance.
    pub expected: String,
    /// One per solver.
    pub outcomes: Vec<Outcome>,
}

/// Sizes of a run.
#[derive(Debug, Clone)]
pub struct Size {
    /// Cells across each body in the patch tests.
    pub patch: usize,
    /// Cells across each body in the manufactured problems (M1, M2).
    pub manufactured: usize,
    /// Cells across in the locking study (E2).
    pub locking: usize,
    /// Mesh families of the locking study.
    pub locking_families: Vec<MeshFamily>,
    /// Contact solvers (registry names).
    pub solvers: Vec<String>,
    /// Block meshes (files beside the shipped Hertz scene) of the near-incompressible Hertz
    /// rows.
    pub hertz_blocks: Vec<&'static str>,
    /// The directory of the shipped scenes (`hertz.toml` and its block meshes): the
    /// workspace's `crates/vem-cli/scenes` by default.
    pub scenes: PathBuf,
    /// Cells across the unit cube in the locking rows in space (E2-3D).
    pub solid: usize,
    /// Cells across the upper block of the contact patch tests in space.
    pub solid_patch: usize,
}

impl Size {
    /// Sizes for a run: `quick` for CI, otherwise the full report.
    pub fn new(quick: bool) -> Self {
        let all_families = vec![
            MeshFamily::Quads,
            MeshFamily::Voronoi,
            MeshFamily::Hexagons,
            MeshFamily::NonConvex,
            MeshFamily::PerturbedQuads { distortion: 0.3 },
            MeshFamily::Triangles,
        ];
        if quick {
            Self {
                patch: 6,
                manufactured: 8,
                locking: 16,
                locking_families: vec![
                    MeshFamily::Quads,
                    MeshFamily::Voronoi,
                    MeshFamily::Triangles,
                ],
                solvers: solver_names(),
                hertz_blocks: vec!["hertz_block.msh"],
                scenes: shipped_scenes(),
                solid: 4,
                solid_patch: 3,
            }
        } else {
            Self {
                patch: 12,
                manufactured: 16,
                locking: 32,
                locking_families: all_families,
                solvers: solver_names(),
                hertz_blocks: vec!["hertz_block.msh", "hertz_block_triangles.msh"],
                scenes: shipped_scenes(),
                solid: 8,
                solid_patch: 4,
            }
        }
    }

    /// The smallest sizes (for the workspace tests).
    pub fn test() -> Self {
        Self {
            patch: 4,
            manufactured: 6,
            locking: 8,
            locking_families: vec![
                MeshFamily::Quads,
                MeshFamily::Voronoi,
                MeshFamily::Hexagons,
                MeshFamily::NonConvex,
                MeshFamily::PerturbedQuads { distortion: 0.3 },
                MeshFamily::Triangles,
            ],
            solvers: solver_names(),
            hertz_blocks: vec!["hertz_block.msh"],
            scenes: shipped_scenes(),
            solid: 3,
            solid_patch: 3,
        }
    }
}

/// The shipped scenes of the workspace (`crates/vem-cli/scenes`).
fn shipped_scenes() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../vem-cli/scenes")
}

/// The name of the condensed solver with its interface forced to the iterative method (MPGP
/// on the Schur operator, projected Newton steps with friction) in the rows in space, whose
/// interfaces are small enough for the default to choose the dense one.
pub const ITERATIVE_INTERFACE: &str = "condensed-iterative";

/// The solvers of the rows in space: those of `size`, and the condensed solver's iterative
/// interface ([`ITERATIVE_INTERFACE`]) when the condensed solver is among them.
pub(crate) fn space_solvers(size: &Size) -> Vec<String> {
    let mut solvers = size.solvers.clone();
    if solvers.iter().any(|s| s == "condensed") {
        solvers.push(ITERATIVE_INTERFACE.to_string());
    }
    solvers
}

/// Every solver of the registry.
pub fn solver_names() -> Vec<String> {
    SolverRegistry::builtin()
        .names()
        .iter()
        .map(|s| s.to_string())
        .collect()
}

/// A group of rows.
pub type Group = fn(&Size) -> Vec<Row>;

/// The groups, in the order of the report.
pub fn groups() -> Vec<(&'static str, Group)> {
    vec![
        ("Poisson ratio up to 0.49999", poisson as Group),
        ("Near-incompressible contact", incompressible_contact),
        ("Stiffness contrast between the bodies", contrast),
        ("Units: lengths and moduli scaled", units),
        ("Degenerate cells", cells),
        ("Penalty factors", penalty),
        ("Gaps", gaps),
        ("Friction bound 0 and huge", friction),
        ("In space: Poisson ratio up to 0.49999", solid_poisson),
        (
            "In space: the contact patch test at the extremes",
            solid_contact,
        ),
    ]
}

/// An error and its sources, on one line.
pub(crate) fn chain(error: &dyn std::error::Error) -> String {
    let mut text = error.to_string();
    let mut source = error.source();
    while let Some(cause) = source {
        text.push_str(": ");
        text.push_str(&cause.to_string());
        source = cause.source();
    }
    text
}

pub(crate) fn solve<const D: usize>(
    problem: &ContactProblem<D>,
    solver: &str,
    options: &Options,
) -> Result<ContactResult<D>, String> {
    let registry = SolverRegistry::builtin();
    let made = if solver == ITERATIVE_INTERFACE {
        let options = options.clone().with("interface", "iterative");
        registry.make("condensed", &options)
    } else {
        registry.make(solver, options)
    };
    let mut solver = made.map_err(|e| chain(&e))?;
    problem
        .solve(solver.as_mut())
        .map_err(|e: ContactError| chain(&e))
}

/// The verdict of one solve: `check` gives what was measured and whether it is the expected
/// answer.
pub(crate) fn judge<const D: usize>(
    solver: &str,
    outcome: Result<ContactResult<D>, String>,
    check: impl Fn(&ContactResult<D>) -> (String, bool),
) -> Outcome {
    match outcome {
        Err(error) => Outcome {
            solver: solver.to_string(),
            measured: format!("error: {error}"),
            verdict: Verdict::Refused(error),
        },
        Ok(result) => {
            let (measured, ok) = check(&result);
            let verdict = if ok {
                Verdict::Pass
            } else if let Some(w) = result.warnings.first() {
                Verdict::Warned(w.to_string())
            } else {
                Verdict::Wrong
            };
            let measured = match result.warnings.first() {
                Some(w) if !ok => format!("{measured}; warning: {w}"),
                _ => measured,
            };
            Outcome {
                solver: solver.to_string(),
                measured,
                verdict,
            }
        }
    }
}

/// Patch tolerance of a solver: the penalty solver answers the penalised problem, whose
/// error is `O(1 / factor)` (default factor 1e3).
pub(crate) fn patch_tolerance(solver: &str) -> f64 {
    if solver == "penalty" {
        1e-3
    } else {
        PATCH_TOLERANCE
    }
}

/// The row of a locking measure: the relative errors `(E_grad, E_0)` that `errors` gives at
/// each of `ratios` against those at nu = 0.3, within [`LOCKING_RATIO`] to pass; an element
/// that locks is a warning (it answers what it computes; the scene layer warns about it).
/// `None` when the element does not support the cells (p1 on other cells than simplices).
pub(crate) fn locking_row(
    name: String,
    solver: String,
    ratios: &[f64],
    errors: impl Fn(f64) -> Result<(f64, f64), String>,
) -> Option<Row> {
    let expected = format!("relative E_grad and E_0 within {LOCKING_RATIO}x of those at nu = 0.3");
    let (grad, l2) = match errors(0.3) {
        Ok(e) => e,
        Err(error) if error.contains("support") => return None,
        Err(error) => {
            return Some(one_outcome(
                name,
                expected,
                solver,
                format!("error at nu = 0.3: {error}"),
                Verdict::Refused(error),
            ))
        }
    };
    let mut measured = vec![format!("E_grad {grad:.2e}, E_0 {l2:.2e} at 0.3")];
    let mut worst: f64 = 0.0;
    let mut refused = None;
    for &nu in ratios {
        match errors(nu) {
            Ok((g, l)) => {
                let (g, l) = (g / grad, l / l2);
                worst = worst.max(g).max(l);
                measured.push(format!("{nu}: x{g:.2} / x{l:.2}"));
            }
            Err(error) => refused = Some(format!("nu = {nu}: {error}")),
        }
    }
    let verdict = match refused {
        Some(e) => Verdict::Refused(e),
        None if worst <= LOCKING_RATIO => Verdict::Pass,
        None => Verdict::Warned("locking: the element's error grows with lambda".into()),
    };
    Some(one_outcome(
        name,
        expected,
        solver,
        measured.join("; "),
        verdict,
    ))
}

/// A row of one outcome.
pub(crate) fn one_outcome(
    name: String,
    expected: String,
    solver: String,
    measured: String,
    verdict: Verdict,
) -> Row {
    Row {
        name,
        expected,
        outcomes: vec![Outcome {
            solver,
            measured,
            verdict,
        }],
    }
}
