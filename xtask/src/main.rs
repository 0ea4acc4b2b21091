//! Project tasks, run as `cargo xtask <task>` (an alias of `cargo run --release -p xtask --`).
//!
//! - `convergence`: the convergence studies of Theorems 4.1 and 4.2 and of 3D elasticity (see
//!   `docs/convergence.md`, `docs/convergence-3d.md`).
//! - `bench`: contact solves against one elastic solve from 10^4 to 8 10^6 unknowns, and whole
//!   runs (mesh files in, every output written) against one Cholesky (see
//!   `docs/benchmarks.md`).
//! - `hertz`: the Hertz half-disc with each contact normal, the consistent pressure and
//!   Cattaneo-Mindlin's stick zone (see `docs/hertz.md`).
//! - `extremes`: stability at the extremes, every solver against independent answers (see
//!   `target/extremes/extremes.md` and `extremes.json`; `--out docs/extremes.md` regenerates the
//!   tracked report, `--report-only` rewrites it from its JSON).
//! - `fuzz`: mutation fuzzing of the scene parser, the Gmsh reader, mesh validation and
//!   interface insertion (see `docs/fuzzing.md`).
//! - `adaptivity`: adaptive against uniform refinement for 2D contact, the estimator's
//!   effectivity and the adapted meshes (see `docs/adaptivity.md`).
//! - `tradeoff`: work-precision diagrams of every solver setting, the accuracy presets and the
//!   error model (see `docs/tradeoff.md`).

mod adaptivity;
mod bench;
mod common;
mod convergence;
mod extremes;
mod fuzz;
mod hertz;
mod tradeoff;
mod whole_run;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// Project tasks of the VEM contact workspace.
#[derive(Debug, Parser)]
#[command(name = "cargo xtask", version, about)]
struct Cli {
    #[command(subcommand)]
    task: Task,
}

#[derive(Debug, Subcommand)]
enum Task {
    /// Convergence studies by manufactured solutions: M1 (Theorem 4.1, frictionless), M2
    /// (Theorem 4.2, Tresca) on five mesh pairings and E1 (elasticity) on three families; in
    /// 3D, E1-3D, E2-3D and the patch test PT0-3D on six polyhedral families. Writes JSON,
    /// Markdown and SVG plots; exits with status 1 when a study falls short of the expected
    /// rates (2D: E_grad and E_a >= 0.9, E_0 >= 1.8; 3D: E_grad >= 0.95, E_0 >= 1.9).
    Convergence(convergence::ConvergenceArgs),
    /// Contact solves against one elastic solve of the same meshes (Hertz-like frictionless
    /// and Coulomb, M1, M2), every registered solver, stages, counters and peak memory; each
    /// measurement in a child process; whole runs of a scene (mesh files in, every output
    /// written) against one Cholesky. Writes bench.json, then bench.md and bench.svg from it
    /// (`--report-only`: from the bench.json in `--out`, without measuring).
    Bench(bench::BenchArgs),
    /// The Hertz half-disc on a block at h_c = 0.08, 0.04, 0.02 with each contact normal
    /// choice (peak, profile, half-width, resultants) and Coulomb friction (Q/P at full slip,
    /// Cattaneo-Mindlin's stick zone). Writes results.md, results.json and SVG plots.
    Hertz(hertz::HertzArgs),
    /// Stability at the extremes: Poisson ratio up to 0.49999 for every element, stiffness
    /// contrasts, units scaled, degenerate cells, penalty factors, gaps, friction bounds; every
    /// solver against an independent expected answer. Writes target/extremes/extremes.json and
    /// extremes.md rendered from it (or `--out`; `--report-only` rewrites the Markdown from the
    /// JSON); exits with status 1 when a wrong answer came without an error or a warning.
    Extremes(extremes::ExtremesArgs),
    /// Mutation fuzzing of the scene parser, the Gmsh reader, mesh validation and interface
    /// insertion: `--minutes N` or `--seconds N` in all, `--target NAME` for one. Failing
    /// inputs are minimised and written to `--out`; exits with status 1 when any was found.
    Fuzz(fuzz::FuzzArgs),
    /// One measurement of `bench`, printed as one JSON line (run by `bench` in a child process).
    #[command(hide = true)]
    BenchOne(bench::BenchOneArgs),
    /// One whole run of `bench` (scene and mesh files in, every output written) and its
    /// reference Cholesky, printed as one JSON line (run by `bench` in a child process).
    #[command(hide = true)]
    BenchWhole(whole_run::BenchWholeArgs),
    /// The speed-accuracy trade: M1, M2, Hertz, Coulomb and E1 on several mesh pairings and
    /// sizes, every solver with several settings, one discretisation per mesh for all of them;
    /// errors, stage times, counters, peak memory, work-precision diagrams with the Pareto
    /// front, the presets and the fitted error model. Writes tradeoff.md and tradeoff/.
    Tradeoff(tradeoff::TradeoffArgs),
    /// Adaptive against uniform refinement in the plane: M1 (exact solution) and the flat
    /// punch (corner singularities), frictionless; the estimator's effectivity, fitted slopes
    /// in the unknowns and pictures of the adapted meshes. Writes docs/adaptivity.md (or
    /// `--out`; `--quick` writes target/adaptivity/) with its rows and pictured meshes in
    /// adaptivity/*.json (`--report-only`: the report from them, without solving); exits with
    /// status 1 when an adaptive slope is above -0.4 or worse than the uniform one.
    Adaptivity(adaptivity::AdaptivityArgs),
    /// One group of `tradeoff`, one JSON line per setting (run by `tradeoff` in a child
    /// process).
    #[command(hide = true)]
    TradeoffOne(tradeoff::TradeoffOneArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let outcome = match cli.task {
        Task::Convergence(args) => convergence::run(&args),
        Task::Bench(args) => bench::run(&args),
        Task::Extremes(args) => extremes::run(&args),
        Task::BenchOne(args) => bench::run_one(&args),
        Task::BenchWhole(args) => whole_run::run_one(&args),
        Task::Hertz(args) => hertz::run(&args),
        Task::Fuzz(args) => fuzz::run(&args),
        Task::Tradeoff(args) => tradeoff::run(&args),
        Task::Adaptivity(args) => adaptivity::run(&args),
        Task::TradeoffOne(args) => tradeoff::run_one(&args),
    };
    match outcome {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::from(1),
        Err(error) => {
            eprintln!("error: {error}");
            let mut source = std::error::Error::source(&*error);
            while let Some(cause) = source {
                eprintln!("  caused by: {cause}");
                source = cause.source();
            }
            ExitCode::from(2)
        }
    }
}
