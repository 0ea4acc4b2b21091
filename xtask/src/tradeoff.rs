//! `cargo xtask tradeoff`: the speed-accuracy trade of every solver setting, as work-precision
//! diagrams (error against time, one curve per setting across mesh sizes, the Pareto front
//! marked), tables, the fitted error model and the measured accuracy presets.
//!
//! A measurement group is one problem on one mesh pairing at one size: a child process
//! (`cargo xtask tradeoff-one`, the same binary re-invoked, so that its peak memory is its
//! own) generates the meshes, discretises once (`ContactDiscretisation`: interface insertion,
//! assembly, constraint rows) and solves with every solver setting on that one discretisation,
//! printing one JSON line per setting. The Hertz and Coulomb problems have no exact solution:
//! a fine reference group is solved first and its interface (pressure, statuses) written to a
//! file that the other groups compare with.

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use clap::{Args, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use serde::{Deserialize, Serialize};
use vem_contact::{
    AccuracyPreset, ContactDiscretisation, ContactResult, ErrorModel, SolverRegistry, WorkCounters,
};
use vem_verify::plot::{loglog_svg, LogLogPlot, Overlay};
use vem_verify::report::{write_json, write_text};
use vem_verify::study::fitted_rate;
use vem_verify::tradeoff::{
    pressure_errors, ContactErrors, SolidGroup, SolverSetting, TradeoffGroup, E2C_POISSON_RATIO,
    FULL_SETTINGS, QUICK_SETTINGS,
};

use crate::bench::{self, Case};
use crate::common::{chain, cpu_seconds, machine, peak_memory, render, seconds};

/// The problems of the study.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Serialize, Deserialize)]
pub enum Problem {
    /// M1: frictionless manufactured solution (contact then separation).
    #[value(name = "M1")]
    M1,
    /// M2: Tresca manufactured solution (stick then slip).
    #[value(name = "M2")]
    M2,
    /// Two-body non-matching Hertz problem (Voronoi indenter with a parabolic gap, R = 1, over
    /// a block of quads 1.25 times finer), frictionless.
    Hertz,
    /// The same pair sheared sideways, Coulomb friction F = 0.3.
    Coulomb,
    /// E1: elasticity baseline (one clamped body, no contact).
    #[value(name = "E1")]
    E1,
    /// E2c at nu = 0.4999: the divergence-free two-body contact solution close to
    /// incompressibility (what the locking-free choice costs).
    #[value(name = "E2c")]
    E2c,
    /// M1-3D: frictionless two-body contact in space (contact inside a disc).
    #[value(name = "M1-3D")]
    M1Space,
    /// E1-3D: elasticity baseline in space (one body).
    #[value(name = "E1-3D")]
    E1Space,
    /// E2-3D at nu = 0.4999: the divergence-free solution in space close to
    /// incompressibility.
    #[value(name = "E2-3D")]
    E2Space,
}

impl Problem {
    fn name(self) -> &'static str {
        match self {
            Self::M1 => "M1",
            Self::M2 => "M2",
            Self::Hertz => "hertz",
            Self::Coulomb => "coulomb",
            Self::E1 => "E1",
            Self::E2c => "E2c",
            Self::M1Space => "M1-3D",
            Self::E1Space => "E1-3D",
            Self::E2Space => "E2-3D",
        }
    }

    fn manufactured(self) -> bool {
        !matches!(self, Self::Hertz | Self::Coulomb)
    }

    /// The error plotted against time.
    fn primary_error(self) -> &'static str {
        if self.manufactured() {
            "E_grad / \\|u\\|_1"
        } else {
            "pressure error against the reference (relative L2)"
        }
    }
}

/// The elements of the near-incompressible group: the earlier default, the locking-free
/// element, and the locking-free element with every edge's midpoint inserted (the default
/// that a scene chooses on triangles close to incompressibility).
const E2C_ELEMENTS: [&str; 3] = ["vem1", "vem1-bbar", "vem1-bbar+midpoints"];

/// The non-matching pairings of M1-3D (the lower box's size the upper's times the factor), as
/// in the convergence study.
const SPACE_PAIRINGS: [&str; 2] = ["hexahedra/tetrahedra*0.75", "voronoi/hexahedra*0.875"];

/// Options of `cargo xtask tradeoff`.
#[derive(Debug, Args)]
pub struct TradeoffArgs {
    /// Fewer problems, sizes and settings (under a minute, for CI).
    #[arg(long)]
    quick: bool,
    /// Where tradeoff.md and the folder tradeoff/ (JSON, SVG) are written; `--out docs`
    /// regenerates docs/tradeoff.md.
    #[arg(long, default_value = "target/tradeoff")]
    out: PathBuf,
    /// The slow settings (the exact solver, the active set with augmentation) only up to this
    /// many unknowns.
    #[arg(long, default_value_t = 20_000)]
    slow_max_unknowns: usize,
    /// Measure nothing: rewrite tradeoff.md and the plots from the tradeoff/tradeoff.json of
    /// an earlier run in the same `--out`.
    #[arg(long)]
    report_only: bool,
    /// Measure only the groups of this problem and keep every other row of the
    /// tradeoff/tradeoff.json of an earlier run in the same `--out` (re-measure one group).
    #[arg(long, value_enum)]
    only: Option<Problem>,
}

/// Options of the hidden `cargo xtask tradeoff-one` (one group, one JSON line per setting).
#[derive(Debug, Args)]
pub struct TradeoffOneArgs {
    /// The problem.
    #[arg(long, value_enum)]
    problem: Problem,
    /// The mesh pairing (manufactured problems), e.g. "quads/quads*3".
    #[arg(long, default_value = "quads/quads")]
    pairing: String,
    /// The element's registry name, with `+midpoints` to insert every edge's midpoint.
    #[arg(long, default_value = "vem1")]
    element: String,
    /// The size parameter.
    #[arg(long)]
    n: usize,
    /// Solver settings (comma separated): a preset name or `solver[@tol=|factor=|aug=VALUE]`.
    #[arg(long, value_delimiter = ',')]
    settings: Vec<String>,
    /// Leave the slow settings (exact solver, active set with augmentation) out above this
    /// many unknowns.
    #[arg(long, default_value_t = 20_000)]
    slow_max_unknowns: usize,
    /// Hertz and Coulomb: the reference interface to compare with.
    #[arg(long)]
    reference: Option<PathBuf>,
    /// Hertz and Coulomb: write this group's interface (first setting) as the reference.
    #[arg(long)]
    write_reference: Option<PathBuf>,
}

/// One interface node of a reference solution.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct ReferenceNode {
    x: f64,
    pressure: f64,
    status: String,
}

/// One measurement: one group, one setting. Times in seconds, memory in bytes, errors
/// relative unless said otherwise.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct Row {
    problem: String,
    pairing: String,
    element: String,
    n: usize,
    /// Mesh size (largest polygon diameter).
    h: f64,
    unknowns: usize,
    contact_rows: usize,
    setting: String,
    solver: String,
    /// "reference" for the group giving the reference of Hertz and Coulomb.
    role: String,
    status: String,
    error: Option<String>,
    /// `E_grad / |u|_1` (manufactured).
    e_grad: Option<f64>,
    /// `E_0 / ||u||_0` (manufactured).
    e_0: Option<f64>,
    /// `E_a / |u_I|_a` (manufactured).
    e_a: Option<f64>,
    /// Nodal pressure against the exact one (manufactured) or against Hertz: discrete L2 on
    /// Gamma_C relative to the exact pressure's.
    pressure_l2: Option<f64>,
    /// The same in the max norm, relative to the exact peak pressure.
    pressure_max: Option<f64>,
    /// Normal resultant against the exact (or reference) one, relative.
    resultant: Option<f64>,
    /// Interface nodes whose status contradicts the exact sets (or the reference's).
    misclassified: Option<usize>,
    /// Hertz and Coulomb: pressure against the reference, relative discrete L2.
    reference_pressure_l2: Option<f64>,
    /// Hertz and Coulomb: the same in the max norm.
    reference_pressure_max: Option<f64>,
    mesh_generation: f64,
    /// Interface insertion and assembly (once per group, shared by its settings).
    discretisation: f64,
    /// Wall time of this setting's solve.
    solve_wall: f64,
    /// CPU time (user + system, all threads) of this setting's solve.
    solve_cpu: f64,
    /// Time of the error measures.
    errors_time: f64,
    iterations: usize,
    fixed_point_steps: usize,
    /// What the build and this setting's solve computed, with the library's stage times.
    work: WorkCounters,
    /// VmHWM of the group's process after this setting.
    peak_memory: u64,
}

impl Row {
    /// The cost of this setting at this size: meshes, discretisation and its solve.
    fn total_time(&self) -> f64 {
        self.mesh_generation + self.discretisation + self.solve_wall
    }

    /// The error of the work-precision diagram.
    fn primary(&self) -> Option<f64> {
        if self.error.is_some() {
            return None;
        }
        self.e_grad.or(self.reference_pressure_l2)
    }
}

/// One group of the plan.
#[derive(Debug, Clone)]
struct Group {
    problem: Problem,
    pairing: String,
    element: String,
    n: usize,
    settings: Vec<String>,
    reference: bool,
}

impl Group {
    fn key(&self) -> String {
        format!("{} {} {}", self.problem.name(), self.pairing, self.element)
    }
}

fn reference_path(out: &Path, problem: Problem) -> PathBuf {
    out.join("tradeoff")
        .join(format!("reference-{}.json", problem.name()))
}

struct Plan {
    groups: Vec<Group>,
}

fn plan(args: &TradeoffArgs) -> Plan {
    let settings: Vec<String> = if args.quick {
        QUICK_SETTINGS.iter().map(|s| s.to_string()).collect()
    } else {
        FULL_SETTINGS.iter().map(|s| s.to_string()).collect()
    };
    let mut groups = Vec::new();
    let mut add = |problem, pairing: &str, element: &str, sizes: &[usize], settings: &[String]| {
        for &n in sizes {
            groups.push(Group {
                problem,
                pairing: pairing.to_string(),
                element: element.to_string(),
                n,
                settings: settings.to_vec(),
                reference: false,
            });
        }
    };
    let one = vec![AccuracyPreset::Reference.name().to_string()];
    if args.quick {
        for problem in [Problem::M1, Problem::M2] {
            add(problem, "quads/quads", "vem1", &[8, 16, 32], &settings);
        }
        add(Problem::M1, "voronoi/quads", "vem1", &[8, 16], &settings);
        add(Problem::E1, "quads", "vem1", &[8, 16, 32], &one);
        for problem in [Problem::Hertz, Problem::Coulomb] {
            add(problem, "voronoi/quads", "vem1", &[8, 16], &settings);
        }
        for element in E2C_ELEMENTS {
            add(Problem::E2c, "triangles/triangles", element, &[8, 16], &one);
        }
        add(
            Problem::M1Space,
            SPACE_PAIRINGS[0],
            "vem1",
            &[4, 6],
            &settings,
        );
        add(Problem::E1Space, "hexahedra", "vem1", &[4, 8], &one);
    } else {
        let sizes = [4, 8, 16, 32, 64, 128];
        for problem in [Problem::M1, Problem::M2] {
            for pairing in ["quads/quads", "voronoi/quads"] {
                add(problem, pairing, "vem1", &sizes, &settings);
            }
            // 1:3 non-matching: n = 64 has 82k unknowns already.
            add(
                problem,
                "quads/quads*3",
                "vem1",
                &[4, 8, 16, 32, 48, 64],
                &settings,
            );
        }
        // The stabilisations, with the reference preset.
        for element in ["vem1-shear", "vem1-drecipe", "vem1-bbar"] {
            add(Problem::M1, "quads/quads", element, &sizes, &one);
            add(Problem::M1, "voronoi/quads", element, &sizes, &one);
        }
        add(Problem::E1, "quads", "vem1", &sizes, &one);
        add(Problem::E1, "voronoi", "vem1", &sizes, &one);
        // Near incompressibility on triangles: what the locking-free choice costs.
        for element in E2C_ELEMENTS {
            add(
                Problem::E2c,
                "triangles/triangles",
                element,
                &[4, 8, 16, 32, 64],
                &one,
            );
        }
        for problem in [Problem::Hertz, Problem::Coulomb] {
            add(
                problem,
                "voronoi/quads",
                "vem1",
                &[8, 12, 16, 24, 32, 48],
                &settings,
            );
        }
        // In space: contact with every setting, elasticity on two families, and what the
        // locking-free choice costs on tetrahedra.
        // The interior point factorises the whole KKT system of every iteration, whose fill
        // in space makes it hundreds of times the condensed solver from 1e4 unknowns
        // (docs/benchmarks.md): the exact settings up to n = 8 only.
        let without_exact: Vec<String> = settings
            .iter()
            .filter(|s| !s.starts_with("exact"))
            .cloned()
            .collect();
        for pairing in SPACE_PAIRINGS {
            add(Problem::M1Space, pairing, "vem1", &[4, 6, 8], &settings);
            add(Problem::M1Space, pairing, "vem1", &[12, 16], &without_exact);
        }
        for family in ["hexahedra", "voronoi"] {
            add(Problem::E1Space, family, "vem1", &[4, 8, 12, 16, 24], &one);
        }
        for element in E2C_ELEMENTS {
            add(
                Problem::E2Space,
                "tetrahedra",
                element,
                &[4, 6, 8, 12],
                &one,
            );
        }
    }
    // The references first.
    let reference_n = if args.quick { 32 } else { 96 };
    for problem in [Problem::Coulomb, Problem::Hertz] {
        groups.insert(
            0,
            Group {
                problem,
                pairing: "voronoi/quads".to_string(),
                element: "vem1".to_string(),
                n: reference_n,
                settings: one.clone(),
                reference: true,
            },
        );
    }
    if let Some(only) = args.only {
        groups.retain(|g| g.problem == only);
    }
    Plan { groups }
}

/// The discretisation of a group, with what the errors need.
struct Built {
    /// The manufactured problems in the plane: the library's measurement group.
    group: Option<TradeoffGroup>,
    /// The manufactured problems in space.
    solid: Option<SolidGroup>,
    /// Hertz and Coulomb: their discretisation.
    discretisation: Option<ContactDiscretisation>,
    h: f64,
    mesh_generation: f64,
}

impl Built {
    /// The contact discretisation to solve with every setting (`None` for elasticity).
    fn discretisation(&self) -> Option<&ContactDiscretisation> {
        match &self.group {
            Some(group) => group.discretisation(),
            None => self.discretisation.as_ref(),
        }
    }
}

fn build(args: &TradeoffOneArgs) -> Result<Built, Box<dyn std::error::Error>> {
    let start = Instant::now();
    match args.problem {
        Problem::Hertz | Problem::Coulomb => {
            let case = if args.problem == Problem::Hertz {
                Case::Hertz
            } else {
                Case::Coulomb
            };
            let problem = bench::problem(case, args.n)?;
            let mesh_generation = seconds(start.elapsed());
            let discretisation = problem.into_discretisation()?;
            let h = discretisation
                .bodies()
                .iter()
                .map(|b| b.mesh().mesh_size())
                .fold(0.0, f64::max);
            Ok(Built {
                group: None,
                solid: None,
                discretisation: Some(discretisation),
                h,
                mesh_generation,
            })
        }
        Problem::M1 | Problem::M2 | Problem::E1 | Problem::E2c => {
            let group =
                TradeoffGroup::build(args.problem.name(), &args.pairing, &args.element, args.n)?;
            Ok(Built {
                h: group.h,
                mesh_generation: group.mesh_generation,
                group: Some(group),
                solid: None,
                discretisation: None,
            })
        }
        Problem::M1Space | Problem::E1Space | Problem::E2Space => {
            let solid =
                SolidGroup::build(args.problem.name(), &args.pairing, &args.element, args.n)?;
            Ok(Built {
                h: solid.h,
                mesh_generation: solid.mesh_generation,
                group: None,
                solid: Some(solid),
                discretisation: None,
            })
        }
    }
}

/// Linear interpolation of the reference pressure at `x` (constant beyond the ends).
fn interpolate(reference: &[ReferenceNode], x: f64) -> f64 {
    match reference.iter().position(|r| r.x >= x) {
        None => reference.last().map_or(0.0, |r| r.pressure),
        Some(0) => reference[0].pressure,
        Some(k) => {
            let (a, b) = (&reference[k - 1], &reference[k]);
            let t = if b.x > a.x {
                (x - a.x) / (b.x - a.x)
            } else {
                0.0
            };
            a.pressure + t * (b.pressure - a.pressure)
        }
    }
}

/// Plane-strain Hertz pressure of the Hertz problem (two identical bodies E = 100, nu = 0.3,
/// parabolic gap of radius 1 over x = 1/2) carrying the load `p` per unit length.
fn hertz_pressure(load: f64) -> impl Fn(f64) -> f64 {
    let (young, nu, radius) = (100.0_f64, 0.3_f64, 1.0_f64);
    let effective = young / (2.0 * (1.0 - nu * nu));
    let a = (4.0 * load.max(0.0) * radius / (std::f64::consts::PI * effective)).sqrt();
    let p0 = if a > 0.0 {
        2.0 * load / (std::f64::consts::PI * a)
    } else {
        0.0
    };
    move |x| {
        let s = (x - 0.5) / a;
        if a > 0.0 && s.abs() < 1.0 {
            p0 * (1.0 - s * s).sqrt()
        } else {
            0.0
        }
    }
}

/// The errors of a contact result against the exact solution or the reference.
fn contact_errors(
    row: &mut Row,
    args: &TradeoffOneArgs,
    built: &Built,
    result: ContactResult,
    reference: Option<&[ReferenceNode]>,
) -> Result<(), Box<dyn std::error::Error>> {
    if let Some(group) = &built.group {
        fill_errors(row, &group.errors(result)?);
        return Ok(());
    }
    // Hertz and Coulomb.
    let load = result.normal_resultant();
    if args.problem == Problem::Hertz {
        let hertz = hertz_pressure(load);
        let (l2, max) = pressure_errors(&result, |p| hertz(p.x));
        row.pressure_l2 = Some(l2);
        row.pressure_max = Some(max);
    }
    if let Some(path) = &args.write_reference {
        let nodes: Vec<ReferenceNode> = result
            .nodes
            .iter()
            .map(|n| ReferenceNode {
                x: n.position.x,
                pressure: n.pressure,
                status: n.status.name().to_string(),
            })
            .collect();
        write_json(path, &nodes)?;
    }
    if let Some(reference) = reference.filter(|r| !r.is_empty()) {
        let (l2, max) = pressure_errors(&result, |p| interpolate(reference, p.x));
        row.reference_pressure_l2 = Some(l2);
        row.reference_pressure_max = Some(max);
        let reference_load: f64 = reference
            .windows(2)
            .map(|w| 0.5 * (w[1].x - w[0].x) * (w[0].pressure + w[1].pressure))
            .sum();
        if reference_load > 0.0 {
            row.resultant = Some((load - reference_load).abs() / reference_load);
        }
        let nearest = |x: f64| {
            reference
                .iter()
                .min_by(|a, b| (a.x - x).abs().total_cmp(&(b.x - x).abs()))
                .map(|r| r.status.as_str())
        };
        row.misclassified = Some(
            result
                .nodes
                .iter()
                .filter(|n| nearest(n.position.x).is_some_and(|s| s != n.status.name()))
                .count(),
        );
    }
    Ok(())
}

/// `cargo xtask tradeoff-one`: one group, one JSON line per setting (a failing setting is a
/// line with `error` set).
pub fn run_one(args: &TradeoffOneArgs) -> Result<bool, Box<dyn std::error::Error>> {
    let settings = args
        .settings
        .iter()
        .map(|s| s.parse::<SolverSetting>())
        .collect::<Result<Vec<_>, _>>()?;
    let reference: Option<Vec<ReferenceNode>> = match &args.reference {
        Some(path) => {
            let text = std::fs::read_to_string(path)
                .map_err(|e| format!("cannot read the reference {}: {e}", path.display()))?;
            let mut nodes: Vec<ReferenceNode> = serde_json::from_str(&text)
                .map_err(|e| format!("reference {}: {e}", path.display()))?;
            nodes.sort_by(|a, b| a.x.total_cmp(&b.x));
            Some(nodes)
        }
        None => None,
    };
    let built = build(args)?;
    let base = Row {
        problem: args.problem.name().to_string(),
        pairing: args.pairing.clone(),
        element: args.element.clone(),
        n: args.n,
        h: built.h,
        role: if args.write_reference.is_some() {
            "reference".to_string()
        } else {
            "measured".to_string()
        },
        mesh_generation: built.mesh_generation,
        ..Row::default()
    };
    if let Some(solid) = &built.solid {
        return run_solid(solid, &settings, args, base);
    }
    let Some(discretisation) = built.discretisation() else {
        // Elasticity: one Cholesky solve per body.
        let group = built
            .group
            .as_ref()
            .ok_or("an elasticity group without its problem")?;
        let problem = group.problem();
        let cpu = cpu_seconds();
        let solution = problem.solve(&mut vem_contact::CondensedSolver::default())?;
        let mut row = base;
        row.solve_cpu = cpu_seconds() - cpu;
        row.setting = "cholesky".to_string();
        row.solver = "cholesky".to_string();
        row.discretisation = seconds(solution.assembly_time);
        row.solve_wall = seconds(solution.solve_time);
        row.unknowns = solution
            .bodies
            .iter()
            .map(|b| b.system.dofs().n_free())
            .sum();
        row.work = solution.work;
        let start = Instant::now();
        let errors = group.elasticity_errors(&solution)?;
        row.errors_time = seconds(start.elapsed());
        row.e_grad = Some(errors.e_grad);
        row.e_0 = Some(errors.e_0);
        row.e_a = Some(errors.e_a);
        row.status = "Solved".to_string();
        row.peak_memory = peak_memory();
        println!("{}", serde_json::to_string(&row)?);
        return Ok(true);
    };
    solve_settings(discretisation, &settings, args, &base, |row, result| {
        contact_errors(row, args, &built, result, reference.as_deref())
    })
}

/// The errors of a manufactured case in a row.
fn fill_errors(row: &mut Row, errors: &ContactErrors) {
    row.pressure_l2 = errors.pressure_l2;
    row.pressure_max = errors.pressure_max;
    row.resultant = errors.resultant;
    row.misclassified = errors.misclassified;
    row.e_grad = Some(errors.e_grad);
    row.e_0 = Some(errors.e_0);
    row.e_a = Some(errors.e_a);
}

/// A group in space: every setting on the contact case's discretisation, or one Cholesky
/// solve of an elasticity case.
fn run_solid(
    solid: &SolidGroup,
    settings: &[SolverSetting],
    args: &TradeoffOneArgs,
    base: Row,
) -> Result<bool, Box<dyn std::error::Error>> {
    if let Some(discretisation) = solid.discretisation() {
        return solve_settings(discretisation, settings, args, &base, |row, result| {
            fill_errors(row, &solid.errors(result)?);
            Ok(())
        });
    }
    let cpu = cpu_seconds();
    let solved = solid.solve_elasticity()?;
    let mut row = base;
    row.solve_cpu = cpu_seconds() - cpu;
    row.setting = "cholesky".to_string();
    row.solver = "cholesky".to_string();
    row.discretisation = solved.assembly;
    row.solve_wall = solved.solve;
    row.unknowns = solved.unknowns;
    // One assembly, one sparse Cholesky (analysis and factorisation), one pair of triangular
    // solves.
    row.work.assemblies = 1;
    row.work.symbolic_analyses = 1;
    row.work.numeric_factorisations = 1;
    row.work.triangular_solves = 1;
    fill_errors(&mut row, &solved.errors);
    row.status = "Solved".to_string();
    row.peak_memory = peak_memory();
    println!("{}", serde_json::to_string(&row)?);
    Ok(true)
}

/// Solves `discretisation` with every setting (one unmeasured solve first), one JSON line per
/// setting, with the errors `errors` fills in.
fn solve_settings<const D: usize>(
    discretisation: &ContactDiscretisation<D>,
    settings: &[SolverSetting],
    args: &TradeoffOneArgs,
    base: &Row,
    mut errors: impl FnMut(&mut Row, ContactResult<D>) -> Result<(), Box<dyn std::error::Error>>,
) -> Result<bool, Box<dyn std::error::Error>> {
    let mut stdout = std::io::stdout().lock();
    let build_work = discretisation.work();
    let registry = SolverRegistry::builtin();
    // One unmeasured solve first: otherwise the first timed setting alone pays the process's
    // first-touch costs (page faults of the factors' memory, cold caches).
    let reference_preset = vem_contact::AccuracyPreset::Reference;
    let mut warm_up = registry.make(
        reference_preset.solver(),
        &reference_preset.solver_options(),
    )?;
    discretisation.solve(warm_up.as_mut()).ok();
    for setting in settings {
        let mut row = Row {
            setting: setting.label.clone(),
            solver: setting.solver.clone(),
            unknowns: discretisation.n_dofs(),
            contact_rows: discretisation.normal_rows().nrows(),
            discretisation: seconds(build_work.times.insertion + build_work.times.assembly),
            work: build_work,
            ..base.clone()
        };
        let slow = setting.solver == "exact" || setting.label.starts_with("active-set@aug");
        if slow && row.unknowns > args.slow_max_unknowns {
            continue;
        }
        let mut solver = registry.make(&setting.solver, &setting.options)?;
        let cpu = cpu_seconds();
        let start = Instant::now();
        match discretisation.solve(solver.as_mut()) {
            Ok(result) => {
                row.solve_wall = seconds(start.elapsed());
                row.solve_cpu = cpu_seconds() - cpu;
                row.work += result.work;
                row.iterations = result
                    .fixed_point
                    .as_ref()
                    .map_or(result.report.iterations, |fp| fp.solver_iterations);
                row.fixed_point_steps = result.fixed_point.as_ref().map_or(0, |fp| fp.steps);
                row.status = format!("{:?}", result.report.status);
                let start = Instant::now();
                errors(&mut row, result)?;
                row.errors_time = seconds(start.elapsed());
            }
            Err(error) => {
                row.solve_wall = seconds(start.elapsed());
                row.status = "failed".to_string();
                row.error = Some(chain(&error));
            }
        }
        row.peak_memory = peak_memory();
        writeln!(stdout, "{}", serde_json::to_string(&row)?)?;
        stdout.flush()?;
    }
    Ok(true)
}

/// Runs one group in a child process; a child that fails gives one row with the error.
fn measure(group: &Group, args: &TradeoffArgs) -> Result<Vec<Row>, String> {
    let exe = std::env::current_exe().map_err(|e| format!("cannot locate this program: {e}"))?;
    let mut command = Command::new(exe);
    command
        .args(["tradeoff-one", "--problem", group.problem.name()])
        .args(["--pairing", &group.pairing, "--element", &group.element])
        .args(["--n", &group.n.to_string()])
        .args(["--settings", &group.settings.join(",")])
        .args(["--slow-max-unknowns", &args.slow_max_unknowns.to_string()]);
    if !group.problem.manufactured() {
        let path = reference_path(&args.out, group.problem);
        if group.reference {
            command.arg("--write-reference").arg(path);
        } else {
            command.arg("--reference").arg(path);
        }
    }
    let output = command
        .output()
        .map_err(|e| format!("cannot start the measurement: {e}"))?;
    let stdout = String::from_utf8_lossy(&output.stdout);
    let rows: Vec<Row> = stdout
        .lines()
        .filter(|l| l.starts_with('{'))
        .filter_map(|l| serde_json::from_str(l).ok())
        .collect();
    if !rows.is_empty() && output.status.success() {
        return Ok(rows);
    }
    let stderr = String::from_utf8_lossy(&output.stderr);
    let reason = stderr
        .lines()
        .filter(|l| !l.trim().is_empty())
        .collect::<Vec<_>>()
        .join(" ");
    let mut rows = rows;
    rows.push(Row {
        problem: group.problem.name().to_string(),
        pairing: group.pairing.clone(),
        element: group.element.clone(),
        n: group.n,
        setting: "(group)".to_string(),
        status: "failed".to_string(),
        error: Some(format!(
            "the measurement exited with {}: {reason}",
            output.status
        )),
        ..Row::default()
    });
    Ok(rows)
}

/// The JSON form of a run.
#[derive(Serialize)]
struct JsonReport<'a> {
    quick: bool,
    seconds: f64,
    machine: String,
    model: FittedModel,
    rows: &'a [Row],
}

/// What `--report-only` reads back of a [`JsonReport`].
#[derive(Deserialize)]
struct StoredReport {
    quick: bool,
    seconds: f64,
    machine: String,
    rows: Vec<Row>,
}

/// The error model of the library against the one fitted now.
#[derive(Debug, Clone, Serialize)]
struct FittedModel {
    library_constant: f64,
    /// Per manufactured contact group.
    fits: Vec<Fit>,
    /// The largest fitted constant of M1 and M2 on quads/quads and voronoi/quads.
    fitted_constant: Option<f64>,
    /// The largest measured `E_grad n` (n >= 8, reference preset) of M1 and M2, every pairing.
    measured_bound: Option<f64>,
}

/// The error model fitted to one manufactured contact group.
#[derive(Debug, Clone, Serialize)]
struct Fit {
    /// Problem and pairing.
    group: String,
    /// Rate in h by least squares over all sizes.
    rate: Option<f64>,
    /// The constant C of E = C / n (geometric mean of E n over n >= 8).
    constant: Option<f64>,
    /// The smallest and largest ratio measured / predicted by the library's model (n >= 8).
    ratios: Option<(f64, f64)>,
}

/// `cargo xtask tradeoff`.
pub fn run(args: &TradeoffArgs) -> Result<bool, Box<dyn std::error::Error>> {
    let started = Instant::now();
    let plan = plan(args);
    let folder = args.out.join("tradeoff");
    if args.report_only {
        let path = folder.join("tradeoff.json");
        let text = std::fs::read_to_string(&path)
            .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
        let stored: StoredReport =
            serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
        let model = fit_model(&stored.rows);
        let quick = TradeoffArgs {
            quick: stored.quick,
            out: args.out.clone(),
            slow_max_unknowns: args.slow_max_unknowns,
            report_only: true,
            only: None,
        };
        let (markdown, plots) = report(
            &stored.rows,
            &model,
            &quick,
            stored.seconds,
            &stored.machine,
        )?;
        for (name, svg) in &plots {
            write_text(folder.join(name), svg)?;
        }
        write_text(args.out.join("tradeoff.md"), &markdown)?;
        if !stored.quick {
            write_fitted_source(&model)?;
        }
        eprintln!(
            "rewrote {}/tradeoff.md from {}",
            args.out.display(),
            path.display()
        );
        return Ok(true);
    }
    std::fs::create_dir_all(&folder)
        .map_err(|e| format!("cannot create {}: {e}", folder.display()))?;
    let weight = |g: &Group| (g.n * g.n * g.settings.len()) as u64 / 16 + 1;
    let bar = ProgressBar::new(plan.groups.iter().map(weight).sum());
    bar.set_style(
        ProgressStyle::with_template("{prefix:<8} [{bar:30}] {elapsed:>4} (eta {eta}) {msg}")?
            .progress_chars("=> "),
    );
    bar.set_prefix("tradeoff");
    let mut rows: Vec<Row> = Vec::new();
    for group in &plan.groups {
        bar.set_message(format!("{} n = {}", group.key(), group.n));
        let measured = measure(group, args)?;
        for row in &measured {
            bar.suspend(|| eprintln!("{}", short_line(row)));
        }
        rows.extend(measured);
        bar.inc(weight(group));
    }
    bar.finish_with_message("done");
    let mut seconds = started.elapsed().as_secs_f64();
    if let Some(only) = args.only {
        // Keep every other group of the earlier run.
        let path = folder.join("tradeoff.json");
        let text = std::fs::read_to_string(&path).map_err(|e| {
            format!(
                "--only keeps the other groups of {}, which cannot be read: {e}",
                path.display()
            )
        })?;
        let stored: StoredReport =
            serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
        if stored.quick != args.quick {
            return Err(format!(
                "--only: {} holds a run with quick = {}, this one has quick = {}",
                path.display(),
                stored.quick,
                args.quick
            )
            .into());
        }
        let mut kept: Vec<Row> = stored
            .rows
            .into_iter()
            .filter(|r| r.problem != only.name())
            .collect();
        kept.append(&mut rows);
        rows = kept;
        seconds += stored.seconds;
    }
    let model = fit_model(&rows);
    if !args.quick {
        write_fitted_source(&model)?;
    }
    let (markdown, plots) = report(&rows, &model, args, seconds, &machine())?;
    for (name, svg) in &plots {
        write_text(folder.join(name), svg)?;
    }
    write_text(args.out.join("tradeoff.md"), &markdown)?;
    write_json(
        folder.join("tradeoff.json"),
        &JsonReport {
            quick: args.quick,
            seconds,
            machine: machine(),
            model,
            rows: &rows,
        },
    )?;
    eprintln!(
        "wrote {0}/tradeoff.md and {1}/ (tradeoff.json, {2} plots) in {seconds:.0} s",
        args.out.display(),
        folder.display(),
        plots.len()
    );
    let failed = rows.iter().filter(|r| r.setting == "(group)").count();
    Ok(failed == 0)
}

fn short_line(row: &Row) -> String {
    match &row.error {
        Some(e) => format!(
            "{} {} n={} {}: failed: {e}",
            row.problem, row.pairing, row.n, row.setting
        ),
        None => format!(
            "{} {} {} n={} {}: error {} in {:.3} s ({} factorisations)",
            row.problem,
            row.pairing,
            row.element,
            row.n,
            row.setting,
            row.primary()
                .or(row.pressure_l2)
                .map_or_else(|| "—".to_string(), |e| format!("{e:.3e}")),
            row.total_time(),
            row.work.numeric_factorisations
        ),
    }
}

/// The diagram groups: problem, pairing, element, in the order of the rows.
fn diagram_keys(rows: &[Row]) -> Vec<(String, String, String)> {
    let mut keys: Vec<(String, String, String)> = Vec::new();
    for r in rows.iter().filter(|r| r.role != "reference") {
        let key = (r.problem.clone(), r.pairing.clone(), r.element.clone());
        if !keys.contains(&key) {
            keys.push(key);
        }
    }
    keys
}

fn of_key<'a>(rows: &'a [Row], key: &(String, String, String)) -> Vec<&'a Row> {
    rows.iter()
        .filter(|r| {
            r.role != "reference" && r.problem == key.0 && r.pairing == key.1 && r.element == key.2
        })
        .collect()
}

/// Errors closer than this (relative) are the same error: the settings that solve the same
/// discretisation to within their tolerances differ in the last digits, and a slower one
/// whose error is smaller only there is not more accurate (the tables print three digits).
const SAME_ERROR: f64 = 1e-3;

/// The rows on the Pareto front of (total time, primary error): no other row is both faster
/// and more accurate (by more than [`SAME_ERROR`]). Sorted by time.
fn pareto<'a>(rows: &[&'a Row]) -> Vec<&'a Row> {
    let mut valid: Vec<&Row> = rows
        .iter()
        .copied()
        .filter(|r| r.primary().is_some_and(|e| e > 0.0))
        .collect();
    valid.sort_by(|a, b| a.total_time().total_cmp(&b.total_time()));
    let mut front = Vec::new();
    let mut best = f64::INFINITY;
    for r in valid {
        let e = r.primary().unwrap_or(f64::INFINITY);
        if e < best * (1.0 - SAME_ERROR) {
            best = e;
            front.push(r);
        }
    }
    front
}

/// Fits `E_grad = C n^-rate` per manufactured contact group with the reference preset, and
/// `C` with the rate 1 (geometric mean of `E n` over the sizes n >= 8).
fn fit_model(rows: &[Row]) -> FittedModel {
    let mut fits = Vec::new();
    let mut fitted_constant: Option<f64> = None;
    let mut measured_bound: Option<f64> = None;
    for key in diagram_keys(rows) {
        if !(key.0 == "M1" || key.0 == "M2") || key.2 != "vem1" {
            continue;
        }
        let mut points: Vec<(usize, f64, f64)> = of_key(rows, &key)
            .into_iter()
            .filter(|r| r.setting == AccuracyPreset::Reference.name())
            .filter_map(|r| Some((r.n, r.h, r.e_grad?)))
            .collect();
        points.sort_by_key(|p| p.0);
        let h: Vec<f64> = points.iter().map(|p| p.1).collect();
        let e: Vec<f64> = points.iter().map(|p| p.2).collect();
        let rate = fitted_rate(&h, &e);
        let logs: Vec<f64> = points
            .iter()
            .filter(|p| p.0 >= 8 && p.2 > 0.0)
            .map(|p| (p.2 * p.0 as f64).ln())
            .collect();
        let constant =
            (!logs.is_empty()).then(|| (logs.iter().sum::<f64>() / logs.len() as f64).exp());
        for p in points.iter().filter(|p| p.0 >= 8) {
            let product = p.2 * p.0 as f64;
            measured_bound = Some(measured_bound.map_or(product, |m: f64| m.max(product)));
        }
        if key.1 == "quads/quads" || key.1 == "voronoi/quads" {
            if let Some(c) = constant {
                fitted_constant = Some(fitted_constant.map_or(c, |f: f64| f.max(c)));
            }
        }
        let library = ErrorModel::LOWEST_ORDER_VEM;
        let ratios = points
            .iter()
            .filter(|p| p.0 >= 8)
            .map(|p| p.2 / library.predicted_error(p.0))
            .fold(None, |acc: Option<(f64, f64)>, r| {
                Some(acc.map_or((r, r), |(lo, hi)| (lo.min(r), hi.max(r))))
            });
        fits.push(Fit {
            group: format!("{} {}", key.0, key.1),
            rate,
            constant,
            ratios,
        });
    }
    FittedModel {
        library_constant: ErrorModel::LOWEST_ORDER_VEM.constant(),
        fits,
        fitted_constant,
        measured_bound,
    }
}

/// The source file of the library's error model that the study generates, relative to the
/// workspace.
const FITTED_SOURCE: &str = "crates/vem-contact/src/accuracy/fitted.rs";

/// The library's constant `C` from the largest measured `E_grad n`: rounded up to one decimal,
/// so that the model's prediction is at or above every error it is derived from.
fn library_constant(measured_bound: f64) -> f64 {
    (measured_bound * 10.0).ceil() / 10.0
}

/// The text of [`FITTED_SOURCE`] for `model` (a full run's: the quick sizes stay below n = 8).
fn fitted_source(model: &FittedModel) -> Result<String, String> {
    let (Some(fitted), Some(bound)) = (model.fitted_constant, model.measured_bound) else {
        return Err("no error of M1 or M2 at n >= 8 to fit the error model to".into());
    };
    Ok(format!(
        "// Generated by `cargo xtask tradeoff` from its rows (docs/tradeoff/tradeoff.json); do not\n\
         // edit. A test of the xtask crate checks it against that file.\n\
         \n\
         /// The largest constant `C` of `E_grad/|u|_1 = C / n` fitted to M1 and M2 on quads/quads and\n\
         /// voronoi/quads (reference preset, geometric mean of `E_grad n` over n >= 8).\n\
         pub(super) const FITTED_CONSTANT: f64 = {fitted:?};\n\
         \n\
         /// The largest measured `E_grad n` (n >= 8, reference preset) of M1 and M2, every pairing.\n\
         pub(super) const MEASURED_BOUND: f64 = {bound:?};\n\
         \n\
         /// The library's constant: [`MEASURED_BOUND`] rounded up to one decimal.\n\
         pub(super) const CONSTANT: f64 = {:?};\n",
        library_constant(bound)
    ))
}

/// Writes [`FITTED_SOURCE`] for `model` into the workspace.
fn write_fitted_source(model: &FittedModel) -> Result<(), Box<dyn std::error::Error>> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join(FITTED_SOURCE);
    write_text(&path, &fitted_source(model)?)?;
    eprintln!("wrote {FITTED_SOURCE} (the library's error model)");
    Ok(())
}

fn opt(value: Option<f64>) -> String {
    value.map_or_else(|| "—".to_string(), |v| format!("{v:.2e}"))
}

fn slug(key: &(String, String, String)) -> String {
    let mut s = format!("{}-{}", key.0, key.1.replace('/', "-").replace('*', "x"));
    if key.2 != "vem1" {
        s.push('-');
        s.push_str(&key.2);
    }
    s
}

/// The Markdown report and the SVG plots (file name, content).
#[allow(clippy::type_complexity)]
fn report(
    rows: &[Row],
    model: &FittedModel,
    args: &TradeoffArgs,
    seconds: f64,
    machine: &str,
) -> Result<(String, Vec<(String, String)>), Box<dyn std::error::Error>> {
    let options = format!(
        "{}{}",
        if args.quick { " --quick" } else { "" },
        if args.out == Path::new("docs") {
            " --out docs".to_string()
        } else {
            format!(" --out {}", args.out.display())
        }
    );
    let group_count = rows
        .iter()
        .map(|r| (&r.problem, &r.pairing, &r.element, r.n))
        .collect::<std::collections::HashSet<_>>()
        .len();
    // Presets.
    let mut presets = String::new();
    for preset in AccuracyPreset::ALL {
        for r in rows.iter().filter(|r| {
            r.setting == preset.name()
                && r.pairing == "quads/quads"
                && r.element == "vem1"
                && r.n == 32
                && (r.problem == "M1" || r.problem == "M2")
        }) {
            presets.push_str(&format!(
                "| {} | {} {:.0e} | {:.0} % (n = {}) | {:.0} % | {} | {} | {} | {} | {} | {} | {} | {:.3} |\n",
                preset.name(),
                preset.solver(),
                preset.tolerance(),
                100.0 * preset.target_error(),
                ErrorModel::LOWEST_ORDER_VEM
                    .try_size_for(preset.target_error())
                    .map_or_else(|e| e.to_string(), |n| n.to_string()),
                100.0 * preset.bound_at_n32(),
                r.problem,
                opt(r.e_grad),
                opt(r.e_a),
                opt(r.pressure_l2),
                opt(r.resultant),
                r.iterations,
                r.work.numeric_factorisations,
                r.solve_wall
            ));
        }
    }
    let mut fits = String::new();
    for fit in &model.fits {
        fits.push_str(&format!(
            "| {} | {} | {} | {} |\n",
            fit.group,
            fit.rate
                .map_or_else(|| "—".to_string(), |r| format!("{r:.2}")),
            opt(fit.constant),
            fit.ratios
                .map_or_else(|| "—".to_string(), |(lo, hi)| format!("{lo:.2} .. {hi:.2}"))
        ));
    }
    // Diagrams, answers and tables per group.
    let mut plots = Vec::new();
    let (mut answers, mut trades, mut tables) = (String::new(), String::new(), String::new());
    for key in diagram_keys(rows) {
        let group = of_key(rows, &key);
        let problem = group.first().map_or("", |r| r.problem.as_str());
        let primary = match problem {
            "hertz" | "coulomb" => Problem::Hertz.primary_error(),
            _ => Problem::M1.primary_error(),
        };
        let mut series: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
        for r in &group {
            let Some(e) = r.primary() else { continue };
            let point = (r.total_time(), e);
            match series.iter_mut().find(|(l, _)| *l == r.setting) {
                Some((_, p)) => p.push(point),
                None => series.push((r.setting.clone(), vec![point])),
            }
        }
        let front = pareto(&group);
        let front_points: Vec<(f64, f64)> = front
            .iter()
            .filter_map(|r| Some((r.total_time(), r.primary()?)))
            .collect();
        let name = format!("{}.svg", slug(&key));
        let caption = format!("{} on {} ({}): error against time", key.0, key.1, key.2);
        let svg = loglog_svg(
            &LogLogPlot {
                caption: &caption,
                x_desc: "total time [s] (meshes + discretisation + solve)",
                y_desc: if primary.starts_with("E_grad") {
                    "E_grad / |u|_1"
                } else {
                    "pressure error vs reference"
                },
                x_format: |x| format!("{x:.0e}"),
                y_format: |y| format!("{y:.0e}"),
            },
            &series,
            Some(Overlay::Front("Pareto front", &front_points)),
        )?;
        plots.push((name.clone(), svg));
        let reach = |target: f64| {
            group
                .iter()
                .filter(|r| r.primary().is_some_and(|e| e <= target))
                .min_by(|a, b| a.total_time().total_cmp(&b.total_time()))
                .map_or_else(
                    || "—".to_string(),
                    |r| format!("{} n={} ({:.2} s)", r.setting, r.n, r.total_time()),
                )
        };
        let mut pareto_settings: Vec<&str> = front.iter().map(|r| r.setting.as_str()).collect();
        pareto_settings.sort_unstable();
        pareto_settings.dedup();
        answers.push_str(&format!(
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
            key.0,
            key.1,
            key.2,
            primary,
            reach(0.1),
            reach(0.03),
            reach(0.01),
            reach(0.003),
            pareto_settings.join(", ")
        ));
        // The trade at the two finest sizes.
        let mut sizes: Vec<usize> = group.iter().map(|r| r.n).collect();
        sizes.sort_unstable();
        sizes.dedup();
        if let [.., coarse, fine] = sizes[..] {
            let find = |setting: &str, n: usize| {
                group
                    .iter()
                    .find(|r| r.setting == setting && r.n == n && r.primary().is_some())
            };
            if let (Some(d), Some(r), Some(df)) = (
                find("draft", coarse),
                find("reference", coarse),
                find("draft", fine),
            ) {
                let (ed, er, edf) = (
                    d.primary().unwrap_or(f64::NAN),
                    r.primary().unwrap_or(f64::NAN),
                    df.primary().unwrap_or(f64::NAN),
                );
                trades.push_str(&format!(
                    "- {} on {}: at n = {coarse}, draft {ed:.3e} in {:.3} s; reference {er:.3e} \
                     in {:.3} s (error x{:.3}, time x{:.2}); draft at n = {fine}: {edf:.3e} in \
                     {:.3} s (error x{:.3}, time x{:.2}).\n",
                    key.0,
                    key.1,
                    d.total_time(),
                    r.total_time(),
                    er / ed,
                    r.total_time() / d.total_time(),
                    df.total_time(),
                    edf / ed,
                    df.total_time() / d.total_time(),
                ));
            }
        }
        tables.push_str(&format!(
            "\n### {} on {} ({})\n\n![{}](tradeoff/{name})\n\n",
            key.0, key.1, key.2, key.0
        ));
        tables.push_str(
            "| n | unknowns | setting | status | E_grad | E_0 | E_a | p L2 | p max | p L2 ref | p max ref | resultant | misclassified | meshes | discretisation | solve (CPU) | sym/num/solves | iterations (steps) | assemblies / factorisations / solves | peak [MiB] | Pareto |\n\
             |---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
        );
        let on_front = |r: &Row| front.iter().any(|f| std::ptr::eq(*f, r));
        for r in &group {
            let status = match &r.error {
                Some(e) => format!("failed: {}", e.replace('|', "/")),
                None => r.status.clone(),
            };
            tables.push_str(&format!(
                "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.3} | {:.3} | {:.3} ({:.3}) | {:.3}/{:.3}/{:.3} | {} ({}) | {} / {} / {} | {:.0} | {} |\n",
                r.n,
                r.unknowns,
                r.setting,
                status,
                opt(r.e_grad),
                opt(r.e_0),
                opt(r.e_a),
                opt(r.pressure_l2),
                opt(r.pressure_max),
                opt(r.reference_pressure_l2),
                opt(r.reference_pressure_max),
                opt(r.resultant),
                r.misclassified
                    .map_or_else(|| "—".to_string(), |m| m.to_string()),
                r.mesh_generation,
                r.discretisation,
                r.solve_wall,
                r.solve_cpu,
                r.work.times.symbolic.as_secs_f64(),
                r.work.times.numeric.as_secs_f64(),
                r.work.times.solves.as_secs_f64(),
                r.iterations,
                r.fixed_point_steps,
                r.work.assemblies,
                r.work.numeric_factorisations,
                r.work.triangular_solves,
                r.peak_memory as f64 / 1024.0 / 1024.0,
                if on_front(r) { "yes" } else { "" },
            ));
        }
    }
    let references: Vec<&Row> = rows.iter().filter(|r| r.role == "reference").collect();
    if !references.is_empty() {
        tables.push_str(
            "\n## References of Hertz and Coulomb\n\n| problem | n | unknowns | setting | status | \
             p L2 vs Hertz | p max vs Hertz | solve [s] |\n|---|---|---|---|---|---|---|---|\n",
        );
        for r in references {
            tables.push_str(&format!(
                "| {} | {} | {} | {} | {} | {} | {} | {:.3} |\n",
                r.problem,
                r.n,
                r.unknowns,
                r.setting,
                r.error.as_deref().unwrap_or(&r.status).replace('|', "/"),
                opt(r.pressure_l2),
                opt(r.pressure_max),
                r.solve_wall
            ));
        }
    }
    // The template supplies the line break that ends the report.
    let measurements = tables.strip_suffix('\n').unwrap_or(&tables).to_string();
    let out = render(
        "xtask/templates/tradeoff.md",
        TEMPLATE,
        &[
            ("options", options),
            ("measurement_count", rows.len().to_string()),
            ("group_count", group_count.to_string()),
            ("seconds", format!("{seconds:.0}")),
            ("machine", machine.to_string()),
            ("findings", findings(rows)),
            ("locking_free_cost", locking_free_cost(rows, Problem::E2c)),
            (
                "locking_free_cost_in_space",
                locking_free_cost(rows, Problem::E2Space),
            ),
            ("table_presets", presets),
            ("library_constant", format!("{:.3}", model.library_constant)),
            ("fit_constant", opt(model.fitted_constant)),
            ("table_fits", fits),
            ("table_answers", answers),
            ("trades", trades),
            ("measurements", measurements),
        ],
    )?;
    Ok((out, plots))
}

/// The median of `values` (`None` when empty).
fn median(mut values: Vec<f64>) -> Option<f64> {
    values.retain(|v| v.is_finite());
    values.sort_by(f64::total_cmp);
    (!values.is_empty()).then(|| values[values.len() / 2])
}

/// The plain answer, computed from the rows: what the tolerance changes, what the mesh
/// changes, which solvers reach the Pareto fronts, what each setting costs against the default
/// and which settings failed.
fn findings(rows: &[Row]) -> String {
    let keys = diagram_keys(rows);
    let mut out = String::from("\n## The answer in short\n\n");
    // The tolerance: draft against reference on the same mesh.
    let mut tolerance_change: f64 = 0.0;
    let mut refinement: Vec<f64> = Vec::new();
    for key in &keys {
        let group = of_key(rows, key);
        for d in group.iter().filter(|r| r.setting == "draft") {
            if let Some(r) = group
                .iter()
                .find(|r| r.setting == "reference" && r.n == d.n)
            {
                if let (Some(ed), Some(er)) = (d.primary(), r.primary()) {
                    tolerance_change = tolerance_change.max((ed - er).abs() / er);
                }
            }
            if let Some(f) = group
                .iter()
                .find(|r| r.setting == "draft" && r.n == 2 * d.n)
            {
                if let (Some(ec), Some(ef)) = (d.primary(), f.primary()) {
                    if d.problem != "hertz" && d.problem != "coulomb" {
                        refinement.push(ef / ec);
                    }
                }
            }
        }
    }
    out.push_str(&format!(
        "- **The mesh decides the error, not the solver tolerance.** On the same mesh the draft \
         preset (tolerance 1e-4) and the reference preset (1e-12) give errors that differ by at \
         most {:.1e} (relative, over every group and size), while halving h multiplies the \
         error by {} (median over the manufactured groups). A cheaper mesh never loses to a \
         tighter tolerance: to gain accuracy, refine.\n",
        tolerance_change,
        median(refinement).map_or_else(|| "—".to_string(), |m| format!("{m:.2}"))
    ));
    // Who is on the fronts.
    let solvers = ["condensed", "exact", "penalty", "active-set"];
    let mut front_counts = vec![(0usize, 0usize); solvers.len()];
    let elasticity = [Problem::E1, Problem::E1Space, Problem::E2Space].map(Problem::name);
    for key in keys.iter().filter(|k| !elasticity.contains(&k.0.as_str())) {
        let group = of_key(rows, key);
        let front = pareto(&group);
        for (k, solver) in solvers.iter().enumerate() {
            if group
                .iter()
                .any(|r| r.solver == *solver && r.primary().is_some())
            {
                front_counts[k].1 += 1;
                if front.iter().any(|r| r.solver == *solver) {
                    front_counts[k].0 += 1;
                }
            }
        }
    }
    let fronts: Vec<String> = solvers
        .iter()
        .zip(&front_counts)
        .map(|(s, (on, of))| format!("{s} on {on} of {of}"))
        .collect();
    out.push_str(&format!(
        "- **Pareto fronts** (contact groups; the presets are the condensed solver): {}. Where \
         another solver reaches a front, it is at a size where all settings give the same \
         error and the times differ by the noise of the machine.\n",
        fronts.join(", ")
    ));
    // Cost of each setting against the reference preset on the same mesh.
    let mut costs = Vec::new();
    for label in FULL_SETTINGS {
        let ratios: Vec<f64> = rows
            .iter()
            .filter(|r| r.setting == label && r.error.is_none() && r.role != "reference")
            .filter_map(|r| {
                let reference = rows.iter().find(|q| {
                    q.setting == "reference"
                        && q.error.is_none()
                        && q.role != "reference"
                        && (&q.problem, &q.pairing, &q.element, q.n)
                            == (&r.problem, &r.pairing, &r.element, r.n)
                })?;
                (reference.solve_wall > 0.0).then(|| r.solve_wall / reference.solve_wall)
            })
            .collect();
        let factorisations: Vec<f64> = rows
            .iter()
            .filter(|r| r.setting == label && r.error.is_none() && r.role != "reference")
            .map(|r| r.work.numeric_factorisations as f64)
            .collect();
        let failed = rows
            .iter()
            .filter(|r| r.setting == label && r.error.is_some())
            .count();
        // The largest error against the reference preset's on the same mesh.
        let worst = rows
            .iter()
            .filter(|r| r.setting == label && r.role != "reference")
            .filter_map(|r| {
                let reference = rows.iter().find(|q| {
                    q.setting == "reference"
                        && q.role != "reference"
                        && (&q.problem, &q.pairing, &q.element, q.n)
                            == (&r.problem, &r.pairing, &r.element, r.n)
                })?;
                Some(r.primary()? / reference.primary()?)
            })
            .fold(0.0_f64, f64::max);
        if let Some(m) = median(ratios) {
            costs.push(format!(
                "{label} x{m:.2} (median {} factorisations, error up to x{worst:.2}{})",
                median(factorisations).map_or(0.0, |f| f),
                if failed > 0 {
                    format!(", {failed} failed")
                } else {
                    String::new()
                }
            ));
        }
    }
    out.push_str(&format!(
        "- **Cost against the reference preset on the same mesh** (median ratio of the solve \
         times, wall times, so noisy; the largest ratio of the plotted error to the reference \
         preset's on the same mesh): {}.\n",
        costs.join("; ")
    ));
    out.push_str(
        "- **Which setting for which accuracy.** Any preset; choose the mesh for the error \
         (the table below gives the cheapest measured row per error level, the error model \
         `C / n` the size for a target). `draft` costs the least iterations, `reference` is the \
         default of the library and gives the exact answer of the discrete problem; the \
         penalty, active-set and exact solvers buy nothing here and cost more, and a loose \
         exact solver (`exact@tol=1e-4`) loses accuracy (the exact solver is the independent \
         oracle of the tests, not a production setting).\n",
    );
    out
}

/// A near-incompressible group (E2c at nu = 0.4999 on non-matching triangles, or E2-3D on
/// tetrahedra): error and cost of each element at each size, and what the locking-free default
/// costs against the earlier default.
fn locking_free_cost(rows: &[Row], problem: Problem) -> String {
    let group: Vec<&Row> = rows
        .iter()
        .filter(|r| r.problem == problem.name() && r.role != "reference")
        .collect();
    if group.is_empty() {
        return String::new();
    }
    let mut out = if problem == Problem::E2c {
        format!(
            "\n## What the locking-free choice costs\n\nE2c (the divergence-free two-body \
             contact solution) at nu = {E2C_POISSON_RATIO} on non-matching triangles, the \
             reference preset: `vem1` (the earlier default), `vem1-bbar` on the plain \
             triangles, and `vem1-bbar+midpoints` (every edge's midpoint inserted: the default a \
             scene chooses on triangles for nu > 0.45). Time: mesh generation, discretisation \
             and solve.\n\n"
        )
    } else {
        format!(
            "\n## What the locking-free choice costs in space\n\nE2-3D (the divergence-free \
             solution on the unit cube, clamped all round) at nu = {E2C_POISSON_RATIO} on \
             tetrahedra (Kuhn split of cubes), one Cholesky solve: `vem1`, `vem1-bbar` on the \
             plain tetrahedra (the stabilisation vanishes on a tetrahedron: both are the P1 \
             element and lock), and `vem1-bbar+midpoints` (every edge's midpoint inserted into \
             every face around the edge: the default a scene chooses on tetrahedra for \
             nu > 0.45). Time: mesh generation, assembly and solve.\n\n"
        )
    };
    out.push_str(
        "| n | element | unknowns | E_grad / \\|u\\|_1 | E_0 / \\|u\\|_0 | time (s) | peak memory (MiB) |\n\
         |---|---|---|---|---|---|---|\n",
    );
    let mut sizes: Vec<usize> = group.iter().map(|r| r.n).collect();
    sizes.sort_unstable();
    sizes.dedup();
    for n in &sizes {
        for element in E2C_ELEMENTS {
            if let Some(r) = group.iter().find(|r| r.n == *n && r.element == element) {
                out.push_str(&format!(
                    "| {n} | {element} | {} | {} | {} | {:.3} | {:.0} |\n",
                    r.unknowns,
                    opt(r.e_grad),
                    opt(r.e_0),
                    r.total_time(),
                    r.peak_memory as f64 / (1024.0 * 1024.0)
                ));
            }
        }
    }
    // The finest size: what the default buys and costs against the earlier default.
    let finest = sizes.last().copied();
    let at = |element: &str| {
        group
            .iter()
            .find(|r| Some(r.n) == finest && r.element == element)
    };
    if let (Some(n), Some(default), Some(earlier)) =
        (finest, at(E2C_ELEMENTS[2]), at(E2C_ELEMENTS[0]))
    {
        let ratio = |a: Option<f64>, b: Option<f64>| match (a, b) {
            (Some(a), Some(b)) if b > 0.0 => format!("{:.2}", a / b),
            _ => "—".to_string(),
        };
        let remark = if problem == Problem::E2c {
            "On these triangles `vem1` locks only mildly (docs/extremes.md: E_grad x1.24 from \
             nu = 0.3 to 0.4999), so the midpoints buy little here; where locking is strong - \
             Hertz on Gmsh triangles, where `vem1` misses the peak pressure by 60 % at \
             nu = 0.499 (docs/elements.md) - they are what makes the answer right."
        } else {
            "On plain tetrahedra every element locks (an error near 100 % at every size), so \
             the midpoints are what makes an answer at all; for the same unknowns a hexahedral \
             or Voronoi mesh with `vem1-bbar` needs no midpoints (docs/elements.md)."
        };
        out.push_str(&format!(
            "\nAt n = {n}, `vem1-bbar+midpoints` against `vem1`: E_grad x{}, E_0 x{}, unknowns \
             x{:.1}, time x{:.1}. {remark}\n",
            ratio(default.e_grad, earlier.e_grad),
            ratio(default.e_0, earlier.e_0),
            default.unknowns as f64 / earlier.unknowns.max(1) as f64,
            default.total_time() / earlier.total_time().max(1e-12),
        ));
    }
    out
}

/// The report's text around its tables (`xtask/templates/tradeoff.md`).
const TEMPLATE: &str = include_str!("../templates/tradeoff.md");

#[cfg(test)]
mod tests {
    use super::*;

    /// The rows of the committed study.
    fn committed() -> StoredReport {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/tradeoff/tradeoff.json");
        let text = std::fs::read_to_string(&path).expect("docs/tradeoff/tradeoff.json");
        serde_json::from_str(&text).expect("the committed tradeoff.json parses")
    }

    /// The library's error model is the one the committed study derives: its generated source
    /// is what the study writes from docs/tradeoff/tradeoff.json, byte for byte (a regeneration
    /// that changes the fit cannot be forgotten), the constants agree with the JSON's printed
    /// model, and the library's constant bounds every measured `E_grad n` it is derived from.
    #[test]
    fn the_library_error_model_is_the_committed_studys() {
        let stored = committed();
        assert!(!stored.quick);
        let model = fit_model(&stored.rows);
        let source = fitted_source(&model).expect("the committed rows fit");
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("..")
            .join(FITTED_SOURCE);
        let committed_source = std::fs::read_to_string(&path).expect(FITTED_SOURCE);
        assert_eq!(
            committed_source, source,
            "{FITTED_SOURCE} is not what `cargo xtask tradeoff --report-only --out docs` writes"
        );
        let text = std::fs::read_to_string(
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/tradeoff/tradeoff.json"),
        )
        .expect("tradeoff.json");
        let json: serde_json::Value = serde_json::from_str(&text).expect("JSON");
        let printed = json["model"]["fitted_constant"]
            .as_f64()
            .expect("fitted_constant");
        assert!((ErrorModel::FITTED_CONSTANT - printed).abs() <= 1e-12 * printed);
        let c = ErrorModel::LOWEST_ORDER_VEM.constant();
        assert_eq!(c, library_constant(ErrorModel::MEASURED_BOUND));
        // Every ratio measured / predicted that the study printed is at most 1.
        for fit in json["model"]["fits"].as_array().expect("fits") {
            let largest = fit["ratios"][1].as_f64().expect("ratios");
            let printed_with = json["model"]["library_constant"].as_f64().expect("C");
            assert!(largest * printed_with / c <= 1.0, "{fit}");
        }
    }

    /// The report is its template filled from the committed rows: what `--report-only --out
    /// docs` writes is docs/tradeoff.md, byte for byte.
    #[test]
    fn the_report_of_the_committed_rows_is_docs_tradeoff_md() {
        let stored = committed();
        let args = TradeoffArgs {
            quick: stored.quick,
            out: PathBuf::from("docs"),
            slow_max_unknowns: 20_000,
            report_only: true,
            only: None,
        };
        let model = fit_model(&stored.rows);
        let (markdown, _) = report(&stored.rows, &model, &args, stored.seconds, &stored.machine)
            .expect("the report renders");
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/tradeoff.md");
        let committed = std::fs::read_to_string(path).expect("docs/tradeoff.md");
        assert!(
            markdown == committed,
            "docs/tradeoff.md is not the rendered report"
        );
    }
}
