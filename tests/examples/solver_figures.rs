//! Iterations and times of the contact solvers on M1 (frictionless) and M2 (Tresca) at about
//! 10^4 and 10^5 unknowns (structured quads, both bodies n x n).
//!
//! `cargo run --release -p vem-integration-tests --example solver_figures [-- N ...]`

use std::sync::Arc;
use std::time::Instant;

use vem_contact::{ActiveSetSolver, CondensedSolver, ContactSolver, ExactSolver, PenaltySolver};
use vem_mesh::generators::MeshFamily;
use vem_verify::exact::{case_by_name, ExactSolution, Lame};
use vem_verify::problem::{DiscreteProblem, ProblemSettings};

fn main() {
    let sizes: Vec<usize> = std::env::args()
        .skip(1)
        .map(|a| a.parse().expect("sizes are whole numbers"))
        .collect();
    let sizes = if sizes.is_empty() {
        vec![50, 160]
    } else {
        sizes
    };
    println!("| case | n | unknowns | rows | solver | iterations | assemblies / symbolic / numeric / solves | symbolic / numeric / solves [s] | solve time [s] | total [s] | stationarity | max penetration | sum lambda_N | sum friction |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for case in ["M1", "M2"] {
        let exact: Arc<dyn ExactSolution> = Arc::from(case_by_name(case, Lame::default()).unwrap());
        for &n in &sizes {
            let meshes = exact
                .bodies()
                .iter()
                .map(|&b| MeshFamily::Quads.generate(&exact.domain(b), n, 1).unwrap())
                .collect();
            let problem =
                DiscreteProblem::try_new(Arc::clone(&exact), meshes, &ProblemSettings::default())
                    .unwrap()
                    .contact_problem()
                    .unwrap();
            let solvers: Vec<Box<dyn ContactSolver>> = vec![
                Box::new(CondensedSolver::default()),
                Box::new(ExactSolver::default()),
                Box::new(PenaltySolver::default()),
                Box::new(ActiveSetSolver::default()),
            ];
            for mut solver in solvers {
                let start = Instant::now();
                match problem.solve(solver.as_mut()) {
                    Ok(result) => {
                        let unknowns: usize = result.model.bodies.iter().map(|b| b.free_dofs).sum();
                        let r = &result.report;
                        println!(
                            "| {case} | {n} | {unknowns} | {} | {} | {} | {} / {} / {} / {} | {:.3} / {:.3} / {:.3} | {:.3} | {:.3} | {:.1e} | {:.1e} | {:.6} | {:.6} |",
                            result.model.normal_rows,
                            r.solver,
                            r.iterations,
                            result.work.assemblies,
                            result.work.symbolic_analyses,
                            result.work.numeric_factorisations,
                            result.work.triangular_solves,
                            result.work.times.symbolic.as_secs_f64(),
                            result.work.times.numeric.as_secs_f64(),
                            result.work.times.solves.as_secs_f64(),
                            result.work.times.contact_solve.as_secs_f64(),
                            start.elapsed().as_secs_f64(),
                            r.residuals.stationarity,
                            r.residuals.max_penetration,
                            result.normal_resultant(),
                            result.tangential_resultant(),
                        );
                    }
                    Err(error) => {
                        println!("| {case} | {n} | | | {} | failed: {error} |", solver.name())
                    }
                }
            }
        }
    }
}
