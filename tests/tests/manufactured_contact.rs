//! The contact cases M1–M4 of docs/manufactured.md solved by the contact layer: active sets,
//! stick/slip sets, the friction law node by node, and resultants against the exact values.

use std::sync::Arc;

use vem_contact::{ContactResult, ContactSolver, ExactSettings, ExactSolver, NodeStatus};
use vem_mesh::generators::MeshFamily;
use vem_verify::exact::{
    case_by_name, ExactSolution, Lame, CONTACT_SWITCH_POINT, STICK_SLIP_POINT,
};
use vem_verify::problem::{DiscreteProblem, ProblemSettings};

fn solver() -> ExactSolver {
    ExactSolver::new(
        ExactSettings::builder()
            .eps_abs(1e-10)
            .eps_rel(1e-10)
            .build()
            .unwrap(),
    )
}

fn discrete(case: &str, upper: (MeshFamily, usize), lower: (MeshFamily, usize)) -> DiscreteProblem {
    let exact: Arc<dyn ExactSolution> = Arc::from(case_by_name(case, Lame::default()).unwrap());
    let meshes = exact
        .bodies()
        .iter()
        .zip([upper, lower])
        .map(|(&body, (family, n))| family.generate(&exact.domain(body), n, 1).unwrap())
        .collect();
    DiscreteProblem::try_new(exact, meshes, &ProblemSettings::default()).unwrap()
}

fn solve(problem: &DiscreteProblem) -> ContactResult {
    problem
        .contact_problem()
        .expect("a contact case")
        .solve(&mut solver() as &mut dyn ContactSolver)
        .unwrap()
}

#[test]
fn m3_every_interface_node_is_active() {
    let result = solve(&discrete(
        "M3",
        (MeshFamily::Quads, 8),
        (MeshFamily::Voronoi, 6),
    ));
    assert!(result.nodes.iter().all(|n| n.status != NodeStatus::Open));
    // sum of nodal forces -> -int sigma_nu ds = 13/12.
    let resultant = result.normal_resultant();
    assert!(
        (resultant - 13.0 / 12.0).abs() < 0.02 * 13.0 / 12.0,
        "resultant {resultant}"
    );
    // Every active node satisfies the constraint with equality (to the solver tolerance).
    for n in &result.nodes {
        assert!((n.normal_jump - n.initial_gap).abs() < 1e-7, "{n:?}");
    }
}

#[test]
fn m4_no_node_is_active_and_the_bodies_solve_separately() {
    let problem = discrete("M4", (MeshFamily::Quads, 8), (MeshFamily::Quads, 8));
    let result = solve(&problem);
    assert!(result.nodes.iter().all(|n| n.status == NodeStatus::Open));
    assert!(result.normal_resultant().abs() < 1e-8);
    // Matching meshes: nothing is inserted, so each body's answer must equal its own
    // elasticity solve with a traction-free Gamma_C.
    assert_eq!(result.model.inserted_nodes, 0);
    for (body, contact) in problem.bodies().iter().zip(&result.bodies) {
        let alone = body.solve().unwrap();
        let scale = alone
            .displacement()
            .iter()
            .fold(0.0_f64, |m, v| m.max(v.abs()));
        for (a, b) in alone
            .displacement()
            .iter()
            .zip(contact.solution.displacement())
        {
            assert!((a - b).abs() <= 1e-8 * scale, "{a} vs {b}");
        }
    }
}

#[test]
fn m1_active_set_away_from_the_switch_point() {
    // h <= 1/32 on both sides, non-matching (32 over 48 cells).
    let result = solve(&discrete(
        "M1",
        (MeshFamily::Quads, 32),
        (MeshFamily::Quads, 48),
    ));
    for n in &result.nodes {
        let x = n.position.x;
        if x <= CONTACT_SWITCH_POINT - 0.2 {
            assert!(
                n.status != NodeStatus::Open,
                "node at x = {x} should be active"
            );
        }
        if x >= CONTACT_SWITCH_POINT + 0.2 {
            assert_eq!(n.status, NodeStatus::Open, "node at x = {x} should be open");
        }
    }
    let exact = 0.123_606_797_749_978_97;
    let error = (result.normal_resultant() - exact).abs();
    assert!(
        error < 0.01 * exact,
        "resultant {} vs {exact}",
        result.normal_resultant()
    );
}

#[test]
fn m1_resultant_converges() {
    let exact = 0.123_606_797_749_978_97;
    let errors: Vec<f64> = [8, 16, 32]
        .iter()
        .map(|&n| {
            let result = solve(&discrete(
                "M1",
                (MeshFamily::Quads, n),
                (MeshFamily::Quads, n),
            ));
            (result.normal_resultant() - exact).abs()
        })
        .collect();
    assert!(errors[2] < errors[0], "{errors:?}");
    assert!(errors[2] < 2e-3 * exact.max(1.0), "{errors:?}");
}

#[test]
fn m2_stick_and_slip_sets_and_the_friction_law_node_by_node() {
    let result = solve(&discrete(
        "M2",
        (MeshFamily::Quads, 32),
        (MeshFamily::Quads, 32),
    ));
    let friction_bound = 0.25;
    for n in &result.nodes {
        let x = n.position.x;
        assert!(
            n.status != NodeStatus::Open,
            "M2 is in contact everywhere (x = {x})"
        );
        if x <= STICK_SLIP_POINT - 0.35 {
            assert_eq!(n.status, NodeStatus::Stick, "x = {x}");
        }
        if x >= STICK_SLIP_POINT + 0.2 {
            assert_eq!(n.status, NodeStatus::Slip, "x = {x}");
            // |friction force| = g_F l on slipping nodes, opposing the slip ([u]_1tau > 0).
            let bound = friction_bound * n.tributary_measure;
            assert!((n.friction_t().abs() - bound).abs() < 1e-6 * bound, "{n:?}");
            assert!(n.friction_t() < 0.0 && n.slip_t() > 0.0, "{n:?}");
        }
        assert!(n.friction_t().abs() <= friction_bound * n.tributary_measure * (1.0 + 1e-6));
    }
    // Resultants: -int sigma_nu = 13/12, int sigma_1tau = -g_F (1 - x_s / 5).
    let tangential = -0.25 * (1.0 - STICK_SLIP_POINT / 5.0);
    assert!(
        (result.normal_resultant() - 13.0 / 12.0).abs() < 0.01,
        "{}",
        result.normal_resultant()
    );
    assert!(
        (result.tangential_resultant() - tangential).abs() < 0.01 * tangential.abs(),
        "{} vs {tangential}",
        result.tangential_resultant()
    );
}
