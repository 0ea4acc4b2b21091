//! Project tasks, run as `cargo xtask <task>` (an alias of `cargo run --release -p xtask --`).
//!
//! - `convergence`: the convergence studies of Theorems 4.1 and 4.2 (see `docs/convergence.md`).
//! - `bench`: contact solves against one elastic solve from 10^4 to 8 10^6 unknowns (see
//!   `docs/benchmarks.md`).
//! - `tradeoff`: work-precision diagrams of every solver setting, the accuracy presets and the
//!   error model (see `docs/tradeoff.md`).

mod bench;
mod common;
mod convergence;
mod tradeoff;

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
    /// (Theorem 4.2, Tresca) on five mesh pairings and E1 (elasticity) on three families.
    /// Writes JSON, Markdown and SVG plots; exits with status 1 when a study falls short of
    /// the expected rates (E_grad and E_a >= 0.9, E_0 >= 1.8).
    Convergence(convergence::ConvergenceArgs),
    /// Contact solves against one elastic solve of the same meshes (Hertz-like frictionless
    /// and Coulomb, M1, M2), every registered solver, stages, counters and peak memory; each
    /// measurement in a child process. Writes bench.md, bench.json and bench.svg.
    Bench(bench::BenchArgs),
    /// One measurement of `bench`, printed as one JSON line (run by `bench` in a child process).
    #[command(hide = true)]
    BenchOne(bench::BenchOneArgs),
    /// The speed-accuracy trade: M1, M2, Hertz, Coulomb and E1 on several mesh pairings and
    /// sizes, every solver with several settings, one discretisation per mesh for all of them;
    /// errors, stage times, counters, peak memory, work-precision diagrams with the Pareto
    /// front, the presets and the fitted error model. Writes tradeoff.md and tradeoff/.
    Tradeoff(tradeoff::TradeoffArgs),
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
        Task::BenchOne(args) => bench::run_one(&args),
        Task::Tradeoff(args) => tradeoff::run(&args),
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
