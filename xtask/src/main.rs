//! Project tasks, run as `cargo xtask <task>` (an alias of `cargo run --release -p xtask --`).
//!
//! - `convergence`: the convergence studies of Theorems 4.1 and 4.2 (see `docs/convergence.md`).

mod convergence;

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
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let outcome = match cli.task {
        Task::Convergence(args) => convergence::run(&args),
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
