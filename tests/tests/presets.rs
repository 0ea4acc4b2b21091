//! The accuracy presets and the error model against the manufactured solutions M1 and M2: each
//! preset stays within its documented bound at n = 32, the presets are ordered in error and in
//! cost (iterations and factorisations, not time), and a target error chooses a size whose
//! measured error is within a factor 2 of the predicted one.

use std::sync::Arc;

use vem_contact::{AccuracyPreset, ContactDiscretisation, ErrorModel, SolveStatus, SolverRegistry};
use vem_verify::exact::{case_by_name, ExactSolution, Lame};
use vem_verify::norms::ErrorNorms;
use vem_verify::problem::{DiscreteProblem, DiscreteSolution, InterfaceOutcome, ProblemSettings};
use vem_verify::study::{MeshPairing, Study};

/// The problem of `case` on `pairing` at size `n`, and its discretisation (built once).
fn discretise(case: &str, pairing: &str, n: usize) -> (DiscreteProblem, ContactDiscretisation) {
    let exact: Arc<dyn ExactSolution> =
        Arc::from(case_by_name(case, Lame::default()).expect("a built-in case"));
    let pairing: MeshPairing = pairing.parse().expect("a valid pairing");
    let meshes = pairing
        .generate(&*exact, n, Study::DEFAULT_SEED)
        .expect("meshes");
    let problem =
        DiscreteProblem::try_new(exact, meshes, &ProblemSettings::default()).expect("problem");
    let discretisation = problem
        .contact_problem()
        .expect("a contact case")
        .discretise()
        .expect("discretisation");
    (problem, discretisation)
}

/// What one preset measured: `E_grad / |u|_1`, iterations, factorisations.
struct Measured {
    error: f64,
    iterations: usize,
    factorisations: usize,
}

fn solve(
    problem: &DiscreteProblem,
    discretisation: &ContactDiscretisation,
    preset: AccuracyPreset,
) -> Measured {
    let mut solver = SolverRegistry::builtin()
        .make(preset.solver(), &preset.solver_options())
        .expect("the preset's solver");
    let result = discretisation.solve(solver.as_mut()).expect("a solution");
    assert!(
        result.report.status == SolveStatus::Converged,
        "{} with {preset}: {:?}",
        problem.exact().name(),
        result.report.status
    );
    let (iterations, factorisations) =
        (result.report.iterations, result.work.numeric_factorisations);
    let solution = DiscreteSolution {
        bodies: result.bodies,
        interface: Some(InterfaceOutcome {
            nodes: result.nodes,
            report: result.report,
            fixed_point: result.fixed_point,
            inserted_nodes: result.model.inserted_nodes,
        }),
        work: result.work,
        assembly_time: result.work.times.assembly,
        solve_time: result.work.times.contact_solve,
    };
    let errors = solution.errors(&**problem.exact()).expect("errors");
    Measured {
        error: ErrorNorms::combine(&errors).relative_grad(),
        iterations,
        factorisations,
    }
}

#[test]
fn presets_within_their_bounds_and_ordered_at_n32() {
    for case in ["M1", "M2"] {
        let (problem, discretisation) = discretise(case, "quads/quads", 32);
        let measured: Vec<Measured> = AccuracyPreset::ALL
            .iter()
            .map(|&preset| solve(&problem, &discretisation, preset))
            .collect();
        for (preset, m) in AccuracyPreset::ALL.iter().zip(&measured) {
            assert!(
                m.error <= preset.bound_at_n32(),
                "{case} {preset}: E_grad/|u|_1 = {:.3e} > {}",
                m.error,
                preset.bound_at_n32()
            );
        }
        for (pair, m) in AccuracyPreset::ALL.windows(2).zip(measured.windows(2)) {
            // A tighter preset is at least as accurate (to the rounding of the error measure,
            // or to the looser preset's own tolerance: an answer stopped at a relative
            // tolerance t differs from the converged one by O(t), and so does its error, of
            // either sign) and costs at least as many iterations and factorisations.
            let slack = pair[0].tolerance().max(1e-6);
            assert!(
                m[1].error <= m[0].error * (1.0 + slack),
                "{case}: {} error {:.6e} > {} error {:.6e}",
                pair[1],
                m[1].error,
                pair[0],
                m[0].error
            );
            assert!(
                m[1].iterations >= m[0].iterations && m[1].factorisations >= m[0].factorisations,
                "{case}: {} costs {} iterations / {} factorisations, {} {} / {}",
                pair[1],
                m[1].iterations,
                m[1].factorisations,
                pair[0],
                m[0].iterations,
                m[0].factorisations
            );
        }
    }
}

#[test]
fn a_target_error_chooses_a_size_predicted_within_a_factor_two() {
    let model = ErrorModel::LOWEST_ORDER_VEM;
    for (case, pairing, target) in [
        ("M1", "quads/quads", 0.2),
        ("M1", "quads/quads", 0.1),
        ("M2", "quads/quads", 0.2),
        ("M2", "quads/quads", 0.1),
        ("M1", "voronoi/quads", 0.2),
    ] {
        let n = model.try_size_for(target).expect("a reachable target");
        let predicted = model.predicted_error(n);
        assert!(predicted <= target);
        let preset = AccuracyPreset::for_target(target);
        let (problem, discretisation) = discretise(case, pairing, n);
        let measured = solve(&problem, &discretisation, preset).error;
        let ratio = measured / predicted;
        assert!(
            (0.5..=2.0).contains(&ratio),
            "{case} on {pairing}, target {target}: n = {n}, predicted {predicted:.3e}, \
             measured {measured:.3e} (ratio {ratio:.2})"
        );
    }
}
