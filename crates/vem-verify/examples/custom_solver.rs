//! A contact solver written outside the workspace, registered under a name and run by a
//! convergence study like the built-in ones.
//!
//! `DualGaussSeidel` solves the discrete contact problem on its dual: with the constraint
//! rows `B = [B_N; B_T]` and `u = K^-1 (f - B' lambda)`, the multipliers minimise
//! `1/2 lambda' S lambda - lambda' d` with `S = B K^-1 B'`, `d = B K^-1 f - (g, s)` (`s` the
//! reference slip of a load history's step, zero from rest), over
//! `lambda_N >= 0`, `|lambda_T| <= b` (frictionless: no `B_T`). It factorises `K` once
//! (`vem_elastic::CholeskySolver`), forms the small dense `S` from one solve per interface
//! row, and sweeps projected Gauss-Seidel over the multipliers until they stop changing,
//! then recovers `u` with one more solve. Nothing in it is private to the workspace.
//!
//! The example registers it as "dual-gauss-seidel" in a `SolverRegistry` next to the built-in
//! solvers, runs the frictionless case M1 on quads over 1:3 quads at n = 8, 16, 32 with it and
//! with "exact", and checks: the study's verdict (rates and expected sets), and that the two
//! solvers agree on every error measure and on the normal resultant to 1e-4 relative, the
//! force accuracy of the default interior-point solver (`ContactSolver::force_accuracy`).
//! Exits non-zero on failure.
//!
//! Run with `cargo run --release -p vem-verify --example custom_solver`.

use std::process::ExitCode;
use std::sync::Arc;
use std::time::Instant;

use vem_contact::{
    ContactSolution, ContactSolver, ContactSolverError, ContactSystem, KktResiduals, KktTolerance,
    PatternId, SolveReport, SolveStatus, SolverRegistry, WorkCounters,
};
use vem_elastic::{CholeskySettings, CholeskySolver, LinearSolver};
use vem_space::{Options, OptionsError};
use vem_verify::exact::{case_by_name, ExactSolution, Lame};
use vem_verify::report::study_markdown;
use vem_verify::study::{MeshPairing, Study, StudyResult};

/// Projected Gauss-Seidel on the dual of the contact problem.
struct DualGaussSeidel {
    /// Stop when no multiplier changes by more than this, relative to the largest.
    tolerance: f64,
    /// Largest number of sweeps.
    max_sweeps: usize,
    /// The Cholesky factors of the stiffness blocks, kept while the system's pattern and
    /// stiffness values stay the same (a Coulomb fixed point, a load step).
    factors: Option<Factors>,
}

/// Factors of the stiffness blocks of one pattern and one set of stiffness values.
struct Factors {
    pattern: PatternId,
    stiffness_version: u64,
    /// First unknown, size and factor of each block.
    blocks: Vec<(usize, usize, CholeskySolver)>,
}

const NAME: &str = "dual-gauss-seidel";

/// The largest relative difference to the exact solver accepted: its force accuracy.
const ACCURACY: f64 = 1e-4;

fn backend(detail: impl std::fmt::Display) -> ContactSolverError {
    ContactSolverError::Backend {
        solver: NAME,
        detail: detail.to_string(),
    }
}

impl DualGaussSeidel {
    /// The solver with its settings table (`tolerance`, `max_iterations`); any other key is
    /// refused with its path.
    fn new(options: &Options) -> Result<Self, OptionsError> {
        #[derive(serde::Deserialize)]
        #[serde(deny_unknown_fields)]
        struct Settings {
            tolerance: Option<f64>,
            max_iterations: Option<usize>,
        }
        let settings: Settings = options.parse()?;
        Ok(Self {
            tolerance: settings.tolerance.unwrap_or(1e-13),
            max_sweeps: settings.max_iterations.unwrap_or(200_000),
            factors: None,
        })
    }

    /// Factorises the stiffness blocks unless the kept factors are those of `system`'s
    /// stiffness; a new pattern also needs a new symbolic analysis.
    fn factorise(
        &mut self,
        system: &ContactSystem,
        work: &mut WorkCounters,
    ) -> Result<(), ContactSolverError> {
        let (pattern, version) = (system.pattern(), system.stiffness_version());
        match &mut self.factors {
            Some(f) if f.pattern == pattern && f.stiffness_version == version => {}
            Some(f) if f.pattern == pattern => {
                for ((_, _, cholesky), block) in f.blocks.iter_mut().zip(system.stiffness_blocks())
                {
                    cholesky.factorise(block.matrix()).map_err(backend)?;
                    work.numeric_factorisations += 1;
                }
                f.stiffness_version = version;
            }
            _ => {
                let mut blocks = Vec::new();
                for block in system.stiffness_blocks() {
                    let matrix = block.matrix();
                    let mut cholesky = CholeskySolver::new(CholeskySettings::default());
                    cholesky.analyse(matrix.symbolic()).map_err(backend)?;
                    cholesky.factorise(matrix).map_err(backend)?;
                    work.symbolic_analyses += 1;
                    work.numeric_factorisations += 1;
                    blocks.push((block.offset(), matrix.nrows(), cholesky));
                }
                self.factors = Some(Factors {
                    pattern,
                    stiffness_version: version,
                    blocks,
                });
            }
        }
        Ok(())
    }

    /// `K^-1 rhs`, block by block.
    fn solve_k(
        &self,
        rhs: &[f64],
        work: &mut WorkCounters,
    ) -> Result<Vec<f64>, ContactSolverError> {
        let mut x = rhs.to_vec();
        for (offset, size, cholesky) in self.factors.iter().flat_map(|f| &f.blocks) {
            let range = *offset..offset + size;
            let part = cholesky.solve(&rhs[range.clone()]).map_err(backend)?;
            x[range].copy_from_slice(&part);
            work.triangular_solves += 1;
        }
        Ok(x)
    }
}

impl ContactSolver for DualGaussSeidel {
    fn name(&self) -> &'static str {
        NAME
    }

    fn solve(&mut self, system: &ContactSystem) -> Result<ContactSolution, ContactSolverError> {
        let start = Instant::now();
        let mut work = WorkCounters::default();
        let (n, m) = (system.n_dofs(), system.n_constraints());
        self.factorise(system, &mut work)?;
        // The rows of B (normal rows, then tangential rows), their bounds and K^-1 B'.
        let mut rows = vec![system.normal_rows()];
        let mut lower = vec![0.0; m];
        let mut upper = vec![f64::INFINITY; m];
        if let Some(friction) = system.friction() {
            rows.push(friction.tangential_rows());
            lower.extend(friction.bounds().iter().map(|b| -b));
            upper.extend_from_slice(friction.bounds());
        }
        let r = lower.len();
        let mut k_inv_bt = Vec::with_capacity(r);
        for i in 0..r {
            let mut column = vec![0.0; n];
            let (index, value) = rows[i / m].row(i % m);
            for (&j, &v) in index.iter().zip(value) {
                column[j] = v;
            }
            k_inv_bt.push(self.solve_k(&column, &mut work)?);
        }
        let u_free = self.solve_k(system.load(), &mut work)?;
        let dot_row = |i: usize, x: &[f64]| rows[i / m].row_dot(i % m, x);
        let s: Vec<Vec<f64>> = (0..r)
            .map(|i| (0..r).map(|j| dot_row(i, &k_inv_bt[j])).collect())
            .collect();
        let reference = system.friction().and_then(|f| f.reference_slip());
        let d: Vec<f64> = (0..r)
            .map(|i| {
                dot_row(i, &u_free)
                    - if i < m {
                        system.gap()[i]
                    } else {
                        reference.map_or(0.0, |s| s[i - m])
                    }
            })
            .collect();
        // Projected Gauss-Seidel sweeps.
        let mut lambda = vec![0.0; r];
        let mut sweeps = 0;
        let converged = loop {
            sweeps += 1;
            let mut change = 0.0f64;
            for i in 0..r {
                let gradient: f64 =
                    s[i].iter().zip(&lambda).map(|(a, l)| a * l).sum::<f64>() - d[i];
                let new = (lambda[i] - gradient / s[i][i]).clamp(lower[i], upper[i]);
                change = change.max((new - lambda[i]).abs());
                lambda[i] = new;
            }
            let largest = lambda.iter().fold(0.0f64, |a, l| a.max(l.abs()));
            if change <= self.tolerance * largest.max(f64::MIN_POSITIVE) {
                break true;
            }
            if sweeps >= self.max_sweeps {
                break false;
            }
        };
        // u = K^-1 f - sum_i lambda_i K^-1 b_i.
        let mut displacement = u_free;
        for (l, column) in lambda.iter().zip(&k_inv_bt) {
            for (u, c) in displacement.iter_mut().zip(column) {
                *u -= l * c;
            }
        }
        let normal_force = lambda[..m].to_vec();
        let tangential_force = if r > m {
            lambda[m..].to_vec()
        } else {
            vec![0.0; m]
        };
        work.times.contact_solve = start.elapsed();
        // The library's acceptance test: converged only if the KKT residuals, relative to the
        // problem's own scales, pass the tolerance.
        let residuals =
            KktResiduals::evaluate(system, &displacement, &normal_force, &tangential_force);
        let accepted = residuals.passes(&KktTolerance::from(1e-8));
        let report = SolveReport {
            solver: NAME,
            status: match (converged, accepted) {
                (true, true) => SolveStatus::Converged,
                (true, false) => SolveStatus::FailedCheck,
                (false, _) => SolveStatus::MaxIterations,
            },
            iterations: sweeps,
            work,
            wall_time: start.elapsed(),
            residuals,
            warnings: Vec::new(),
        };
        if !(converged && accepted) {
            return Err(ContactSolverError::NotConverged {
                report: Box::new(report),
            });
        }
        Ok(ContactSolution {
            displacement,
            normal_force,
            tangential_force,
            report,
        })
    }
}

/// M1 on quads over 1:3 quads, n = 8, 16, 32, solved by the solver `name` of `solvers`.
fn study(
    exact: &Arc<dyn ExactSolution>,
    solvers: &SolverRegistry,
    name: &str,
) -> Result<StudyResult, Box<dyn std::error::Error>> {
    let pairing: MeshPairing = "quads/quads*3".parse()?;
    Ok(Study::new(Arc::clone(exact), pairing)
        .sizes([8, 16, 32])
        .registry(solvers.clone())
        .solver(name)
        .run()?)
}

fn main() -> Result<ExitCode, Box<dyn std::error::Error>> {
    // The built-in solvers and ours, under one name like theirs.
    let mut solvers = SolverRegistry::builtin();
    solvers.register(
        NAME,
        "projected Gauss-Seidel on the dual, dense Schur complement (example)",
        |options: &Options| Ok(Box::new(DualGaussSeidel::new(options)?) as Box<dyn ContactSolver>),
    )?;
    println!("solvers: {}", solvers.names().join(", "));
    let m1: Arc<dyn ExactSolution> = case_by_name("M1", Lame::default())?.into();
    let ours = study(&m1, &solvers, NAME)?;
    let reference = study(&m1, &solvers, "exact")?;
    println!("{}", study_markdown(&ours));
    let mut failures: Vec<String> = ours.verdict.shortfalls.clone();
    let relative = |a: f64, b: f64| (a - b).abs() / b.abs().max(f64::MIN_POSITIVE);
    for (a, b) in ours.records.iter().zip(&reference.records) {
        let (ca, cb) = (a.contact.as_ref(), b.contact.as_ref());
        let resultant = match (ca, cb) {
            (Some(ca), Some(cb)) => relative(ca.normal_resultant, cb.normal_resultant),
            _ => f64::NAN,
        };
        let worst = [
            relative(a.errors.grad, b.errors.grad),
            relative(a.errors.energy, b.errors.energy),
            relative(a.errors.l2, b.errors.l2),
            resultant,
        ]
        .into_iter()
        .fold(0.0f64, f64::max);
        println!(
            "n = {:?}: {} sweeps ({:.2} s) against exact ({} iterations, {:.2} s); largest \
             relative difference of E_grad, E_a, E_0, sum lambda_N: {worst:.1e}",
            a.n,
            a.solver_iterations.unwrap_or(0),
            a.times.solve,
            b.solver_iterations.unwrap_or(0),
            b.times.solve,
        );
        if worst.is_nan() || worst > ACCURACY {
            failures.push(format!("n = {:?}: differs from exact by {worst:.1e}", a.n));
        }
    }
    if failures.is_empty() {
        println!("solver '{}' on M1: pass", ours.solver);
        Ok(ExitCode::SUCCESS)
    } else {
        eprintln!(
            "solver '{}' FAILS:\n- {}",
            ours.solver,
            failures.join("\n- ")
        );
        Ok(ExitCode::FAILURE)
    }
}
