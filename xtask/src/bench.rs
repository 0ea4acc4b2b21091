//! `cargo xtask bench`: the cost of contact against one elastic solve of the same meshes.
//!
//! Every measurement (one case, one size, one solver) runs in a child process (`cargo xtask
//! bench-one`, the same binary re-invoked) so that the peak memory the OS reports (`VmHWM` of
//! `/proc/self/status`, a process high-water mark) belongs to that measurement alone. The child
//! builds the model (the Hertz-like cases from their [`Scene`] by `Model::build`: generated
//! meshes, bodies, contact pair, law and solver by registry name; M1 and M2 from vem-verify's
//! manufactured solutions), discretises (interface insertion, assembly, constraint rows),
//! solves the contact problem, then assembles, analyses, factorises and solves every body alone
//! with its Dirichlet data (the elastic reference) and prints one JSON line.
//!
//! The run writes its rows to `bench.json` and makes `bench.md` and `bench.svg` from that file;
//! `--report-only` makes them again from it without measuring.

use std::io::Write as _;
use std::path::PathBuf;
use std::process::Command;
use std::sync::Arc;
use std::time::Instant;

use clap::{Args, ValueEnum};

use crate::common::{chain, machine, peak_memory, read_json, render, seconds, store_json};
use crate::whole_run::{self, WholeRun};
use indicatif::{ProgressBar, ProgressStyle};
use serde::{Deserialize, Serialize};
use serde_json::json;
use vem_contact::{ContactProblem, ContactSolver, SolverRegistry};
use vem_elastic::{CholeskySettings, CholeskySolver, ElasticBody, LinearSolver};
use vem_mesh::generators::MeshFamily;
use vem_mesh::Mesh;
use vem_scene::resources::{LimitOrigin, MemoryLimit};
use vem_scene::{BuildOptions, Model, Scene};
use vem_space::Choice;
use vem_verify::exact::{case_by_name, ExactSolution, Lame};
use vem_verify::plot::{
    loglog_styled_svg, LogLogPlot, Marker, Point, StyledSeries, SERIES_COLOURS,
};
use vem_verify::problem::{DiscreteProblem, ProblemSettings};
use vem_verify::report::write_text;

/// The cases of the benchmark.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Serialize, Deserialize)]
pub enum Case {
    /// Hertz-like: a CVT (Voronoi) block with a parabolic gap (R = 1) pressed 0.02 onto a
    /// block of structured quads (1.25 times finer across), frictionless.
    Hertz,
    /// The same, sheared 0.006 sideways, Coulomb friction F = 0.3.
    Coulomb,
    /// M1 of vem-verify (frictionless manufactured solution), quads on both bodies.
    #[value(name = "M1")]
    M1,
    /// M2 of vem-verify (Tresca manufactured solution), quads on both bodies.
    #[value(name = "M2")]
    M2,
    /// Hertz-like in space: a block of Voronoi polyhedra with a paraboloid gap (R = 1) pressed
    /// 0.02 onto a block of hexahedra (1.25 times finer across), frictionless; the surface
    /// overlay makes the non-matching interface node-to-node.
    #[value(name = "hertz-3d")]
    Hertz3d,
    /// The same with hexahedra on both sides (the indenter's n across, the block's 1.25 n):
    /// the case in space whose factors fit this machine's memory at 1e6 unknowns (Voronoi
    /// polyhedra fill the factor 2.4 times as much as hexahedra).
    #[value(name = "hertz-3d-hex")]
    Hertz3dHex,
    /// [`Case::Hertz3dHex`] with the indenter's top also moved 0.006 sideways (x) and Tresca
    /// friction, the bound `g_F` = 0.1 on the whole contact face
    /// (`TRESCA_3D_BOUND`): stick and slip.
    #[value(name = "tresca-3d-hex")]
    Tresca3dHex,
    /// [`Case::Hertz3dHex`] with the indenter's top also moved 0.006 sideways (x) and Coulomb
    /// friction F = 0.3: the fixed point of Tresca problems.
    #[value(name = "coulomb-3d-hex")]
    Coulomb3dHex,
}

impl Case {
    /// The cases of a run without `--cases` ([`Case::Hertz3dHex`] is the size study's case in
    /// space: on request).
    const ALL: [Case; 5] = [
        Case::Hertz,
        Case::Coulomb,
        Case::M1,
        Case::M2,
        Case::Hertz3d,
    ];
    /// The largest default size of the case in space (the dense interface Schur complement of
    /// the condensed solver grows with the square of the interface: docs/contact-3d.md).
    const SPACE_MAX_UNKNOWNS: usize = 100_000;
    /// The exact solver's limit in space: the interior point factorises the whole KKT system
    /// of every iteration, whose fill in 3D makes it 500 times the condensed solver at 2.5e4
    /// unknowns (docs/benchmarks.md).
    const SPACE_EXACT_MAX_UNKNOWNS: usize = 5_000;

    pub(crate) fn name(self) -> &'static str {
        match self {
            Case::Hertz => "hertz",
            Case::Coulomb => "coulomb",
            Case::M1 => "M1",
            Case::M2 => "M2",
            Case::Hertz3d => "hertz-3d",
            Case::Hertz3dHex => "hertz-3d-hex",
            Case::Tresca3dHex => "tresca-3d-hex",
            Case::Coulomb3dHex => "coulomb-3d-hex",
        }
    }

    fn describe(self) -> &'static str {
        match self {
            Case::Hertz => "Hertz-like, frictionless (voronoi / quads)",
            Case::Coulomb => "Hertz-like, Coulomb F = 0.3 (voronoi / quads)",
            Case::M1 => "M1 frictionless (quads / quads)",
            Case::M2 => "M2 Tresca (quads / quads)",
            Case::Hertz3d => "Hertz-like in space, frictionless (voronoi polyhedra / hexahedra)",
            Case::Hertz3dHex => "Hertz-like in space, frictionless (hexahedra / hexahedra)",
            Case::Tresca3dHex => "Hertz-like in space, sheared, Tresca (hexahedra / hexahedra)",
            Case::Coulomb3dHex => {
                "Hertz-like in space, sheared, Coulomb F = 0.3 (hexahedra / hexahedra)"
            }
        }
    }

    /// The size parameter n giving about `unknowns` free unknowns.
    fn size_for(self, unknowns: usize) -> usize {
        // Voronoi: about 2 vertices per cell; quads 1.25 n across: (1.25 n)^2 vertices.
        let per_n2 = match self {
            Case::Hertz | Case::Coulomb => 2.0 * (2.0 + 1.25 * 1.25),
            Case::M1 | Case::M2 => 4.0,
            Case::Hertz3d => {
                // Voronoi polyhedra: about 4.9 vertices per cell (n^3 cells); hexahedra
                // (1.25 n)^3 vertices; three unknowns per vertex.
                let per_n3 = 3.0 * (4.9 + 1.25f64.powi(3));
                return ((unknowns as f64 / per_n3).cbrt().round() as usize).max(2);
            }
            Case::Hertz3dHex | Case::Tresca3dHex | Case::Coulomb3dHex => {
                // Hexahedra: n^3 and (1.25 n)^3 vertices.
                let per_n3 = 3.0 * (1.0 + 1.25f64.powi(3));
                return ((unknowns as f64 / per_n3).cbrt().round() as usize).max(2);
            }
        };
        ((unknowns as f64 / per_n2).sqrt().round() as usize).max(2)
    }

    /// True for the cases in space.
    fn in_space(self) -> bool {
        matches!(
            self,
            Case::Hertz3d | Case::Hertz3dHex | Case::Tresca3dHex | Case::Coulomb3dHex
        )
    }
}

/// Parallelism of the elastic reference's factorisation (to measure the choice of the
/// default).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Serialize, Deserialize)]
pub enum Parallelism {
    /// The default of `CholeskySettings`.
    Default,
    /// Sequential.
    Seq,
    /// All rayon threads.
    Rayon,
}

/// The ladder of sizes (unknowns) the benchmark takes its sizes from.
const LADDER: [usize; 8] = [
    10_000, 30_000, 100_000, 300_000, 1_000_000, 2_000_000, 4_000_000, 8_000_000,
];
/// Sizes of `--quick`.
const QUICK_SIZES: [usize; 2] = [5_000, 10_000];

/// Options of `cargo xtask bench`.
#[derive(Debug, Args)]
pub struct BenchArgs {
    /// Small sizes only (5 10^3 and 10^4 unknowns; under a minute, for CI).
    #[arg(long)]
    quick: bool,
    /// Where bench.md, bench.json and bench.svg are written.
    #[arg(long, default_value = "target/bench")]
    out: PathBuf,
    /// Largest size of the ladder 1e4, 3e4, 1e5, 3e5, 1e6, 2e6, 4e6, 8e6 (unknowns).
    #[arg(long, default_value_t = 1_000_000)]
    max_unknowns: usize,
    /// The whole ladder up to 8e6 unknowns (the same as `--max-unknowns 8000000`).
    #[arg(long)]
    full: bool,
    /// Explicit sizes (approximate numbers of unknowns, comma separated); overrides the ladder.
    #[arg(long, value_delimiter = ',')]
    sizes: Vec<usize>,
    /// Solvers by registry name (comma separated); default: every registered solver.
    #[arg(long, value_delimiter = ',')]
    solvers: Vec<String>,
    /// The exact solver (registry name "exact") only up to this many unknowns.
    #[arg(long, default_value_t = 200_000)]
    exact_max_unknowns: usize,
    /// Cases (comma separated); default all.
    #[arg(long, value_delimiter = ',', value_enum)]
    cases: Vec<Case>,
    /// Parallelism of the elastic reference's factorisation.
    #[arg(long, value_enum, default_value = "default")]
    parallelism: Parallelism,
    /// Sizes (unknowns, comma separated) of the whole runs (mesh files in, every output
    /// written) of the Hertz case with Gmsh meshes; default 1e5 and 1e6 up to
    /// `--max-unknowns` (1e4 with `--quick`); 0: none.
    #[arg(long, value_delimiter = ',')]
    whole_run: Vec<usize>,
    /// A scene file whose whole run is measured too (one row).
    #[arg(long)]
    scene: Option<PathBuf>,
    /// Repetitions of every whole run (the medians are reported).
    #[arg(long, default_value_t = 3)]
    repeat: usize,
    /// Only the whole runs (no contact solver rows).
    #[arg(long)]
    whole_run_only: bool,
    /// Rewrite bench.md and bench.svg in `--out` from its bench.json, without measuring.
    #[arg(long)]
    report_only: bool,
}

/// Sizes of the whole runs: the default ones (8e6 only when `--whole-run` asks for it: the
/// whole run holds the model beside the solve, about 20 GiB there), and `--quick`'s.
const WHOLE_RUN_SIZES: [usize; 2] = [100_000, 1_000_000];
const QUICK_WHOLE_RUN_SIZES: [usize; 1] = [10_000];

/// Options of the hidden `cargo xtask bench-one` (one measurement, one JSON line).
#[derive(Debug, Args)]
pub struct BenchOneArgs {
    /// The case.
    #[arg(long, value_enum)]
    case: Case,
    /// Approximate number of unknowns.
    #[arg(long)]
    unknowns: usize,
    /// The solver's registry name.
    #[arg(long)]
    solver: String,
    /// Parallelism of the elastic reference's factorisation.
    #[arg(long, value_enum, default_value = "default")]
    parallelism: Parallelism,
    /// Measure the model building only (meshes, discretisation): no contact solve, no
    /// elastic reference.
    #[arg(long)]
    model_only: bool,
    /// Stop after the contact solve: no elastic reference (for memory profiles of the solve).
    #[arg(long)]
    contact_only: bool,
}

/// One measurement, as the child prints it and the reports carry it. Times in seconds, memory
/// in bytes.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct Measurement {
    case: String,
    target_unknowns: usize,
    solver: String,
    /// The size parameter n of the meshes.
    n: usize,
    unknowns: usize,
    contact_rows: usize,
    mesh_generation: f64,
    insertion: f64,
    assembly: f64,
    symbolic: f64,
    numeric: f64,
    solves: f64,
    contact_solve: f64,
    iterations: usize,
    fixed_point_steps: usize,
    symbolic_analyses: usize,
    factorisations: usize,
    triangular_solves: usize,
    status: String,
    normal_resultant: f64,
    /// VmHWM after the meshes are generated.
    peak_meshes: u64,
    /// VmHWM after discretising.
    peak_build: u64,
    /// VmHWM after the contact solve.
    peak_contact: u64,
    /// VmHWM at the end (elastic reference included).
    peak_total: u64,
    /// Bytes of the stiffness matrices (values, row indices, column pointers).
    stiffness_bytes: u64,
    /// Bytes of the Cholesky factors' values of the elastic reference.
    factor_bytes: u64,
    elastic_assembly: f64,
    elastic_analyse: f64,
    elastic_factorise: f64,
    elastic_solve: f64,
    /// The failure, when the solve (or the child) failed.
    error: Option<String>,
}

impl Measurement {
    fn elastic_total(&self) -> f64 {
        self.elastic_assembly + self.elastic_analyse + self.elastic_factorise + self.elastic_solve
    }

    fn ratio(&self) -> Option<f64> {
        (self.error.is_none() && self.elastic_total() > 0.0)
            .then(|| self.contact_solve / self.elastic_total())
    }
}

/// The friction bound `g_F` of [`Case::Tresca3dHex`] (a force per area), on the whole face as in
/// Tresca's problem (also where the gap is open): at n = 16, 926 of the face's 1089 nodes stick
/// and 163 slip, the tangential load 0.044 against the face's capacity 0.1.
const TRESCA_3D_BOUND: f64 = 0.1;

/// The scene of a Hertz-like case at size `n` with the contact solver `solver`: the two
/// meshes by the scene's generators (the indenter's Voronoi cells, seed 1; the block's quads
/// 1.25 n across), the law and the solver by registry name, the gap an expression.
pub(crate) fn scene(
    case: Case,
    n: usize,
    solver: &str,
) -> Result<Scene, Box<dyn std::error::Error>> {
    let m = ((1.25 * n as f64).round() as usize).max(1);
    let value = match case {
        Case::Hertz | Case::Coulomb => {
            let (shift, law) = if case == Case::Coulomb {
                (0.006, json!({ "name": "coulomb", "coefficient": 0.3 }))
            } else {
                (0.0, json!("frictionless"))
            };
            let material = json!({ "E": 100.0, "nu": 0.3, "plane": "strain" });
            json!({
                "title": case.describe(),
                "solver": solver,
                "body": [
                    {
                        "name": "indenter",
                        "mesh": { "family": "voronoi", "rectangle": [[0.0, 0.0], [1.0, 1.0]], "n": n, "seed": 1 },
                        "material": material,
                        "dirichlet": [{ "part": "top", "x": shift, "y": -0.02 }],
                    },
                    {
                        "name": "block",
                        "mesh": { "family": "quads", "rectangle": [[0.0, -1.0], [1.0, 0.0]], "n": m },
                        "material": material,
                        "dirichlet": [{ "part": "bottom", "x": 0.0, "y": 0.0 }],
                    },
                ],
                // A parabolic indenter of radius 1 over x = 1/2.
                "contact": [{
                    "body": "indenter", "part": "bottom", "other_body": "block", "other_part": "top",
                    "law": law, "imposed_gap": "0.5 * (x - 0.5) * (x - 0.5)",
                }],
            })
        }
        Case::Hertz3d | Case::Hertz3dHex | Case::Tresca3dHex | Case::Coulomb3dHex => {
            let family = if case == Case::Hertz3d {
                "voronoi"
            } else {
                "hexahedra"
            };
            let (shift, law) = match case {
                Case::Tresca3dHex => (
                    0.006,
                    json!({ "name": "tresca", "friction_bound": TRESCA_3D_BOUND }),
                ),
                Case::Coulomb3dHex => (0.006, json!({ "name": "coulomb", "coefficient": 0.3 })),
                _ => (0.0, json!("frictionless")),
            };
            let material = json!({ "E": 100.0, "nu": 0.3 });
            json!({
                "title": case.describe(),
                "solver": solver,
                "body": [
                    {
                        "name": "indenter",
                        "mesh": { "family": family, "box": [[0.0, 0.0, 0.0], [1.0, 1.0, 1.0]], "n": n, "seed": 1 },
                        "material": material,
                        "dirichlet": [{ "part": "top", "x": shift, "y": 0.0, "z": -0.02 }],
                    },
                    {
                        "name": "block",
                        "mesh": { "family": "hexahedra", "box": [[0.0, 0.0, -1.0], [1.0, 1.0, 0.0]], "n": m },
                        "material": material,
                        "dirichlet": [{ "part": "bottom", "x": 0.0, "y": 0.0, "z": 0.0 }],
                    },
                ],
                // A paraboloid indenter of radius 1 over (1/2, 1/2).
                "contact": [{
                    "body": "indenter", "part": "bottom", "other_body": "block", "other_part": "top",
                    "law": law,
                    "imposed_gap": "0.5 * ((x - 0.5) * (x - 0.5) + (y - 0.5) * (y - 0.5))",
                }],
            })
        }
        Case::M1 | Case::M2 => {
            return Err(format!("{} is built by vem-verify, not by a scene", case.name()).into())
        }
    };
    Ok(Scene::from_value(value)?)
}

/// The options of the bench's builds: the built-in registries, no memory check.
fn build_options() -> Result<BuildOptions, Box<dyn std::error::Error>> {
    Ok(BuildOptions {
        memory_limit: Some(no_memory_check()?),
        ..BuildOptions::default()
    })
}

/// The bench's memory limit: none in effect (the bench measures the memory itself, up to sizes
/// the estimate of a run refuses on a smaller machine).
fn no_memory_check() -> Result<MemoryLimit, Box<dyn std::error::Error>> {
    Ok(MemoryLimit::try_from_gib(1e9, LimitOrigin::CommandLine)?)
}

/// The manufactured case `case` (M1, M2) at size `n`: quads on both bodies, the exact
/// solution's data (vem-verify's `DiscreteProblem`).
fn manufactured(case: Case, n: usize) -> Result<ContactProblem, Box<dyn std::error::Error>> {
    let exact: Arc<dyn ExactSolution> = Arc::from(case_by_name(case.name(), Lame::default())?);
    let meshes: Vec<Mesh> = exact
        .bodies()
        .iter()
        .map(|&b| MeshFamily::Quads.generate(&exact.domain(b), n, 1))
        .collect::<Result<_, _>>()?;
    let settings = ProblemSettings::builder()
        .memory_limit(no_memory_check()?)
        .build()?;
    let discrete = DiscreteProblem::try_new(Arc::clone(&exact), meshes, &settings)?;
    discrete
        .contact_problem()
        .ok_or_else(|| format!("{} is not a contact case", case.name()).into())
}

/// The contact problem of `case` at size `n` in the plane: the scene's model for the
/// Hertz-like cases, vem-verify's for M1 and M2.
pub(crate) fn problem(case: Case, n: usize) -> Result<ContactProblem, Box<dyn std::error::Error>> {
    match case {
        Case::M1 | Case::M2 => manufactured(case, n),
        _ => {
            let model = Model::build(&scene(case, n, SolverRegistry::DEFAULT)?, &build_options()?)?;
            let (problem, _) = model
                .contact_problem()
                .ok_or_else(|| format!("{} is a problem in space", case.name()))?;
            Ok(problem.clone())
        }
    }
}

/// `cargo xtask bench-one`: measures and prints one JSON line; a failing solve is a line with
/// `error` set. The model is built (the scene's `Model::build`: meshes, bodies, contact pairs;
/// vem-verify's for M1, M2) and the solver made in the stage `mesh_generation`; the model's
/// copy of the contact problem is taken and the model dropped before the discretisation, so
/// that the stages after it measure what they measured when the problem was built by hand.
pub fn run_one(args: &BenchOneArgs) -> Result<bool, Box<dyn std::error::Error>> {
    let n = args.case.size_for(args.unknowns);
    let m = Measurement {
        case: args.case.name().to_string(),
        target_unknowns: args.unknowns,
        solver: args.solver.clone(),
        n,
        ..Measurement::default()
    };
    let start = Instant::now();
    let solver_choice = Choice::named(args.solver.clone());
    match args.case {
        Case::M1 | Case::M2 => {
            let problem = manufactured(args.case, n)?;
            let solver = SolverRegistry::builtin().make_choice(&solver_choice)?;
            measure_problem(problem, solver, args, m, start)
        }
        case => {
            let model = Model::build(&scene(case, n, &args.solver)?, &build_options()?)?;
            let solver = model.registries().solvers.make_choice(model.solver())?;
            if case.in_space() {
                let (problem, _) = model
                    .contact_problem_3d()
                    .ok_or("the scene has no contact pair")?;
                let problem = problem.clone();
                drop(model);
                measure_problem(problem, solver, args, m, start)
            } else {
                let (problem, _) = model
                    .contact_problem()
                    .ok_or("the scene has no contact pair")?;
                let problem = problem.clone();
                drop(model);
                measure_problem(problem, solver, args, m, start)
            }
        }
    }
}

/// The measurement of `problem` (built since `start`): discretisation, contact solve, the
/// elastic reference; prints one JSON line.
fn measure_problem<const D: usize>(
    problem: ContactProblem<D>,
    mut solver: Box<dyn ContactSolver>,
    args: &BenchOneArgs,
    mut m: Measurement,
    start: Instant,
) -> Result<bool, Box<dyn std::error::Error>> {
    m.mesh_generation = seconds(start.elapsed());
    m.peak_meshes = peak_memory();
    // By value: the original meshes are dropped before the assembly.
    let discretisation = problem.into_discretisation()?;
    m.peak_build = peak_memory();
    let build = discretisation.work();
    m.insertion = seconds(build.times.insertion);
    m.assembly = seconds(build.times.assembly);
    m.unknowns = discretisation.n_dofs();
    m.contact_rows = discretisation.normal_rows().nrows();
    m.stiffness_bytes = discretisation
        .systems()
        .iter()
        .map(|s| {
            let k = s.stiffness();
            (k.val().len() * 16 + k.symbolic().col_ptr().len() * 8) as u64
        })
        .sum();
    if args.model_only {
        m.status = "model only".to_string();
        println!("{}", serde_json::to_string(&m)?);
        return Ok(true);
    }
    let start = Instant::now();
    match discretisation.solve(solver.as_mut()) {
        Ok(result) => {
            let work = result.work;
            m.symbolic = seconds(work.times.symbolic);
            m.numeric = seconds(work.times.numeric);
            m.solves = seconds(work.times.solves);
            m.contact_solve = seconds(work.times.contact_solve.max(start.elapsed()));
            m.symbolic_analyses = work.symbolic_analyses;
            m.factorisations = work.numeric_factorisations;
            m.triangular_solves = work.triangular_solves;
            m.iterations = result
                .fixed_point
                .as_ref()
                .map_or(result.report.iterations, |fp| fp.solver_iterations);
            m.fixed_point_steps = result.fixed_point.as_ref().map_or(0, |fp| fp.steps);
            m.status = format!("{:?}", result.report.status);
            m.normal_resultant = result.normal_resultant();
        }
        Err(error) => {
            m.contact_solve = seconds(start.elapsed());
            m.status = "failed".to_string();
            m.error = Some(chain(&error));
        }
    }
    m.peak_contact = peak_memory();
    if args.contact_only {
        println!("{}", serde_json::to_string(&m)?);
        return Ok(true);
    }
    // The elastic reference: every body alone with its Dirichlet data, on the enlarged meshes.
    let settings = match args.parallelism {
        Parallelism::Default => CholeskySettings::default(),
        Parallelism::Seq => CholeskySettings::builder()
            .factorisation_parallelism(faer::Par::Seq)
            .build()?,
        Parallelism::Rayon => CholeskySettings::builder()
            .factorisation_parallelism(faer::Par::rayon(0))
            .build()?,
    };
    let bodies: Vec<ElasticBody<D>> = discretisation.bodies().to_vec();
    // The contact solver's factors and the discretisation go before the reference factorises.
    drop(solver);
    drop(discretisation);
    for body in &bodies {
        let start = Instant::now();
        let system = body.assemble()?;
        m.elastic_assembly += seconds(start.elapsed());
        let mut cholesky = CholeskySolver::new(settings);
        let start = Instant::now();
        cholesky.analyse(system.stiffness().symbolic())?;
        m.elastic_analyse += seconds(start.elapsed());
        let start = Instant::now();
        cholesky.factorise(system.stiffness().as_ref())?;
        m.elastic_factorise += seconds(start.elapsed());
        m.factor_bytes += 8 * cholesky.factor_len().unwrap_or(0) as u64;
        let start = Instant::now();
        let u = cholesky.solve(system.rhs())?;
        m.elastic_solve += seconds(start.elapsed());
        std::hint::black_box(u);
    }
    m.peak_total = peak_memory();
    let mut stdout = std::io::stdout().lock();
    writeln!(stdout, "{}", serde_json::to_string(&m)?)?;
    Ok(true)
}

/// One planned measurement.
struct Planned {
    case: Case,
    unknowns: usize,
    solver: String,
}

fn plan(args: &BenchArgs) -> Result<Vec<Planned>, String> {
    let registry = SolverRegistry::builtin();
    let solvers: Vec<String> = if args.solvers.is_empty() {
        registry.names().into_iter().map(String::from).collect()
    } else {
        args.solvers.clone()
    };
    if let Some(unknown) = solvers.iter().find(|s| !registry.contains(s)) {
        return Err(format!(
            "unknown solver {unknown:?}; the solvers are {}",
            registry.names().join(", ")
        ));
    }
    let max = if args.full {
        LADDER[7]
    } else {
        args.max_unknowns
    };
    let sizes: Vec<usize> = if !args.sizes.is_empty() {
        args.sizes.clone()
    } else if args.quick {
        QUICK_SIZES.to_vec()
    } else {
        LADDER.iter().copied().filter(|&s| s <= max).collect()
    };
    let cases: Vec<Case> = if args.cases.is_empty() {
        Case::ALL.to_vec()
    } else {
        args.cases.clone()
    };
    let mut planned = Vec::new();
    if args.whole_run_only {
        return Ok(planned);
    }
    for &case in &cases {
        for &unknowns in &sizes {
            // The case in space up to its own limit unless the sizes are explicit.
            if case.in_space() && args.sizes.is_empty() && unknowns > Case::SPACE_MAX_UNKNOWNS {
                continue;
            }
            for solver in &solvers {
                let exact_max = if case.in_space() {
                    args.exact_max_unknowns.min(Case::SPACE_EXACT_MAX_UNKNOWNS)
                } else {
                    args.exact_max_unknowns
                };
                if solver == "exact" && unknowns > exact_max {
                    continue;
                }
                planned.push(Planned {
                    case,
                    unknowns,
                    solver: solver.clone(),
                });
            }
        }
    }
    Ok(planned)
}

/// Runs one measurement in a child process; a child that fails gives a row with the error.
fn measure(p: &Planned, parallelism: Parallelism) -> Result<Measurement, String> {
    let exe = std::env::current_exe().map_err(|e| format!("cannot locate this program: {e}"))?;
    let parallelism = parallelism
        .to_possible_value()
        .map_or_else(|| "default".to_string(), |v| v.get_name().to_string());
    let output = Command::new(exe)
        .args(["bench-one", "--case", p.case.name(), "--solver", &p.solver])
        .args(["--unknowns", &p.unknowns.to_string()])
        .args(["--parallelism", &parallelism])
        .output()
        .map_err(|e| format!("cannot start the measurement: {e}"))?;
    let stdout = String::from_utf8_lossy(&output.stdout);
    if let Some(line) = stdout.lines().rev().find(|l| l.starts_with('{')) {
        if let Ok(m) = serde_json::from_str::<Measurement>(line) {
            return Ok(m);
        }
    }
    let stderr = String::from_utf8_lossy(&output.stderr);
    let reason = stderr
        .lines()
        .filter(|l| !l.trim().is_empty())
        .collect::<Vec<_>>()
        .join(" ");
    Ok(Measurement {
        case: p.case.name().to_string(),
        target_unknowns: p.unknowns,
        solver: p.solver.clone(),
        status: "failed".to_string(),
        error: Some(format!(
            "the measurement exited with {}: {reason}",
            output.status
        )),
        ..Measurement::default()
    })
}

/// `cargo xtask bench`.
pub fn run(args: &BenchArgs) -> Result<bool, Box<dyn std::error::Error>> {
    if args.report_only {
        let path = args.out.join("bench.json");
        write_report(&args.out, &read_json(&path)?)?;
        eprintln!(
            "rewrote {0}/bench.md and {0}/bench.svg from {1}",
            args.out.display(),
            path.display()
        );
        return Ok(true);
    }
    let started = Instant::now();
    let planned = plan(args)?;
    std::fs::create_dir_all(&args.out)
        .map_err(|e| format!("cannot create {}: {e}", args.out.display()))?;
    let weight = |p: &Planned| (p.unknowns as u64 / 1000).max(1);
    let bar = ProgressBar::new(planned.iter().map(weight).sum());
    bar.set_style(
        ProgressStyle::with_template("{prefix:<8} [{bar:30}] {elapsed:>4} (eta {eta}) {msg}")?
            .progress_chars("=> "),
    );
    bar.set_prefix("bench");
    let mut rows = Vec::with_capacity(planned.len());
    for p in &planned {
        bar.set_message(format!(
            "{} ~{} unknowns, {}",
            p.case.name(),
            p.unknowns,
            p.solver
        ));
        let m = measure(p, args.parallelism)?;
        bar.suspend(|| eprintln!("{}", row_line(&m, None)));
        rows.push(m);
        bar.inc(weight(p));
    }
    bar.finish_with_message("done");
    let whole_runs = whole_runs(args)?;
    let stored = JsonReport {
        quick: args.quick,
        options: options(args),
        repeat: args.repeat,
        seconds: started.elapsed().as_secs_f64(),
        machine: machine(),
        measurements: rows,
        whole_runs,
    };
    let stored = store_json(args.out.join("bench.json"), &stored)?;
    let markdown = write_report(&args.out, &stored)?;
    println!("{markdown}");
    eprintln!(
        "wrote {0}/bench.md, {0}/bench.json and {0}/bench.svg",
        args.out.display()
    );
    Ok(true)
}

/// Writes bench.md and bench.svg of `stored` into `out`; returns the Markdown.
fn write_report(
    out: &std::path::Path,
    stored: &JsonReport,
) -> Result<String, Box<dyn std::error::Error>> {
    let markdown = markdown(stored)?;
    write_text(out.join("bench.md"), &markdown)?;
    write_text(out.join("bench.svg"), &plot_svg(&stored.measurements)?)?;
    Ok(markdown)
}

/// The JSON form of a run: everything its report and plot are made of.
#[derive(Serialize, Deserialize)]
struct JsonReport {
    quick: bool,
    /// The options of the run, as the report prints them (` --quick`).
    #[serde(default)]
    options: String,
    /// Repetitions of every whole run.
    #[serde(default = "default_repeat")]
    repeat: usize,
    seconds: f64,
    machine: String,
    measurements: Vec<Measurement>,
    whole_runs: Vec<WholeRun>,
}

/// The default of `--repeat`.
fn default_repeat() -> usize {
    3
}

/// The sizes of the whole runs `args` ask for.
fn whole_run_sizes(args: &BenchArgs) -> Vec<usize> {
    if !args.whole_run.is_empty() {
        return args.whole_run.iter().copied().filter(|&s| s > 0).collect();
    }
    if args.quick {
        return QUICK_WHOLE_RUN_SIZES.to_vec();
    }
    let max = if args.full {
        LADDER[7]
    } else {
        args.max_unknowns
    };
    WHOLE_RUN_SIZES
        .iter()
        .copied()
        .filter(|&s| s <= max)
        .collect()
}

/// The whole runs (each size, then `--scene`), every one printed as it comes.
fn whole_runs(args: &BenchArgs) -> Result<Vec<WholeRun>, Box<dyn std::error::Error>> {
    let mut runs = Vec::new();
    let planned: Vec<(usize, Option<&std::path::Path>)> = whole_run_sizes(args)
        .into_iter()
        .map(|s| (s, None))
        .chain(args.scene.as_deref().map(|s| (0, Some(s))))
        .collect();
    for (unknowns, scene) in planned {
        let dir = match scene {
            Some(_) => args.out.join("whole-scene"),
            None => args.out.join(format!("whole-{unknowns}")),
        };
        eprintln!(
            "whole run {} ({} repetitions)",
            scene.map_or_else(
                || format!("~{unknowns} unknowns"),
                |s| s.display().to_string()
            ),
            args.repeat
        );
        let run = whole_run::measure(unknowns, scene, &dir, args.repeat)?;
        eprintln!("{}", whole_run::row(&run));
        runs.push(run);
    }
    Ok(runs)
}

/// The section of the whole runs: its template (`xtask/templates/bench-whole-runs.md`) and
/// table.
fn whole_run_markdown(runs: &[WholeRun], repeat: usize) -> Result<String, String> {
    let mut table = whole_run::TABLE_HEADER.to_string();
    for run in runs {
        table.push_str(&whole_run::row(run));
        table.push('\n');
    }
    // The template supplies the line break that ends the section.
    let table = table.strip_suffix('\n').unwrap_or(&table).to_string();
    render(
        "xtask/templates/bench-whole-runs.md",
        include_str!("../templates/bench-whole-runs.md"),
        &[("repeat", repeat.to_string()), ("table", table)],
    )
}

const GIB: f64 = 1024.0 * 1024.0 * 1024.0;

/// The contact solve time of the exact solver on the same case and size.
fn exact_time(rows: &[Measurement], m: &Measurement) -> Option<f64> {
    rows.iter()
        .find(|r| {
            r.solver == "exact"
                && r.case == m.case
                && r.target_unknowns == m.target_unknowns
                && r.error.is_none()
        })
        .map(|r| r.contact_solve)
}

fn row_line(m: &Measurement, exact: Option<f64>) -> String {
    if let Some(error) = &m.error {
        if m.unknowns == 0 {
            return format!(
                "| {} | ~{} | {} | failed: {} |",
                m.case,
                m.target_unknowns,
                m.solver,
                error.replace('|', "/")
            );
        }
    }
    let ratio = m
        .ratio()
        .map_or_else(|| "—".to_string(), |r| format!("{r:.2}"));
    let exact_ratio = exact
        .filter(|_| m.error.is_none() && m.contact_solve > 0.0)
        .map_or_else(
            || "—".to_string(),
            |e| format!("{:.1}", e / m.contact_solve),
        );
    let status = match &m.error {
        Some(error) => format!("failed: {}", error.replace('|', "/")),
        None => m.status.clone(),
    };
    format!(
        "| {} | {} | {} | {} | {:.2} | {:.2} / {:.2} | {:.2} / {:.2} / {:.2} | {:.2} | {} | {} ({}) | {} / {} | {:.2} | {} | {:.2} / {:.2} / {:.2} | {:.3} / {:.3} | {} |",
        m.case,
        m.unknowns,
        m.contact_rows,
        m.solver,
        m.mesh_generation,
        m.insertion,
        m.assembly,
        m.symbolic,
        m.numeric,
        m.solves,
        m.contact_solve,
        ratio,
        m.iterations,
        m.fixed_point_steps,
        m.factorisations,
        m.triangular_solves,
        m.elastic_total(),
        exact_ratio,
        m.peak_build as f64 / GIB,
        m.peak_contact as f64 / GIB,
        m.peak_total as f64 / GIB,
        m.stiffness_bytes as f64 / GIB,
        m.factor_bytes as f64 / GIB,
        status,
    )
}

/// The Markdown report: its template (`xtask/templates/bench.md`) filled with the run, the
/// cases, the table of the measurements and the section of the whole runs (if any).
fn markdown(stored: &JsonReport) -> Result<String, String> {
    let rows = &stored.measurements;
    let whole_runs = &stored.whole_runs;
    let mut table = String::new();
    for m in rows {
        table.push_str(&row_line(m, exact_time(rows, m)));
        table.push('\n');
    }
    let whole_runs = if whole_runs.is_empty() {
        String::new()
    } else {
        whole_run_markdown(whole_runs, stored.repeat)?
    };
    render(
        "xtask/templates/bench.md",
        include_str!("../templates/bench.md"),
        &[
            ("options", stored.options.clone()),
            ("measurement_count", rows.len().to_string()),
            ("seconds", format!("{:.0}", stored.seconds)),
            ("machine", stored.machine.clone()),
            (
                "cases",
                Case::ALL
                    .iter()
                    .map(|c| format!("`{}` {}", c.name(), c.describe()))
                    .collect::<Vec<_>>()
                    .join("; "),
            ),
            ("table", table),
            ("whole_runs", whole_runs),
        ],
    )
}

fn options(args: &BenchArgs) -> String {
    let mut o = String::new();
    if args.quick {
        o.push_str(" --quick");
    }
    if args.full {
        o.push_str(" --full");
    } else if args.max_unknowns != 1_000_000 {
        o.push_str(&format!(" --max-unknowns {}", args.max_unknowns));
    }
    if !args.sizes.is_empty() {
        let s: Vec<String> = args.sizes.iter().map(usize::to_string).collect();
        o.push_str(&format!(" --sizes {}", s.join(",")));
    }
    if !args.solvers.is_empty() {
        o.push_str(&format!(" --solvers {}", args.solvers.join(",")));
    }
    if args.exact_max_unknowns != 200_000 {
        o.push_str(&format!(
            " --exact-max-unknowns {}",
            args.exact_max_unknowns
        ));
    }
    if !args.cases.is_empty() {
        let c: Vec<&str> = args.cases.iter().map(|c| c.name()).collect();
        o.push_str(&format!(" --cases {}", c.join(",")));
    }
    if !args.whole_run.is_empty() {
        let s: Vec<String> = args.whole_run.iter().map(usize::to_string).collect();
        o.push_str(&format!(" --whole-run {}", s.join(",")));
    }
    if let Some(scene) = &args.scene {
        o.push_str(&format!(" --scene {}", scene.display()));
    }
    if args.repeat != 3 {
        o.push_str(&format!(" --repeat {}", args.repeat));
    }
    if args.whole_run_only {
        o.push_str(" --whole-run-only");
    }
    if args.parallelism != Parallelism::Default {
        o.push_str(&format!(" --parallelism {:?}", args.parallelism).to_lowercase());
    }
    o
}

/// Log-log plot of contact solve / elastic solve against unknowns, one series per case and
/// solver: the colour tells the solver, the marker the case.
fn plot_svg(rows: &[Measurement]) -> Result<String, Box<dyn std::error::Error>> {
    // (case, solver, points) in the order of first appearance.
    let mut series: Vec<(&str, &str, Vec<Point>)> = Vec::new();
    for m in rows {
        let Some(r) = m.ratio().filter(|&r| r > 0.0 && m.unknowns > 0) else {
            continue;
        };
        let point = (m.unknowns as f64, r);
        match series
            .iter_mut()
            .find(|(case, solver, _)| *case == m.case && *solver == m.solver)
        {
            Some((.., p)) => p.push(point),
            None => series.push((&m.case, &m.solver, vec![point])),
        }
    }
    let labels: Vec<String> = series.iter().map(|(c, s, _)| format!("{c} {s}")).collect();
    let index_of = |names: &mut Vec<String>, name: &str| match names.iter().position(|n| n == name)
    {
        Some(k) => k,
        None => {
            names.push(name.to_string());
            names.len() - 1
        }
    };
    let (mut solvers, mut cases) = (Vec::new(), Vec::new());
    let styled: Vec<StyledSeries<'_>> = series
        .iter()
        .zip(&labels)
        .map(|((case, solver, points), label)| StyledSeries {
            label,
            points,
            colour: SERIES_COLOURS[index_of(&mut solvers, solver) % SERIES_COLOURS.len()],
            marker: Some(Marker::ALL[index_of(&mut cases, case) % Marker::ALL.len()]),
        })
        .collect();
    Ok(loglog_styled_svg(
        &LogLogPlot {
            caption: "contact solve / one elastic solve",
            x_desc: "unknowns",
            y_desc: "contact / elastic",
            x_format: |x| format!("{x:.0e}"),
            y_format: |y| format!("{y:.2}"),
        },
        &styled,
        None,
    )?)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What `--report-only --out docs/benchmarks` makes of the committed rows is
    /// docs/benchmarks/bench.md and bench.svg, byte for byte.
    #[test]
    fn the_report_of_the_committed_rows_is_docs_benchmarks_bench_md() {
        let folder = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/benchmarks");
        let read = |name: &str| {
            std::fs::read_to_string(folder.join(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
        };
        let stored: JsonReport = serde_json::from_str(&read("bench.json")).expect("bench.json");
        let markdown = markdown(&stored).expect("the report renders");
        assert!(
            markdown == read("bench.md"),
            "bench.md is not the rendered report"
        );
        let svg = plot_svg(&stored.measurements).expect("the plot renders");
        assert!(
            svg == read("bench.svg"),
            "bench.svg is not the rendered plot"
        );
    }
}
