//! Coulomb friction under force control: a flat punch (Voronoi cells) on a block (perturbed
//! quads), its top a rigid plate pushed down with P and sheared with Q
//! (`Dirichlet::rigid_plate(.., Component::All, (Q, -P))`): the punch is held sideways by
//! friction alone. Below the friction capacity `F P` every ratio `Q/(F P)` is solved, the
//! contact carries `(Q, P)` exactly and Coulomb's law holds node by node; beyond it the refusal
//! names the load and the capacity; a handover to another solver says so.

use std::sync::Arc;

use vem_contact::{
    CondensedSolver, ContactError, ContactLaw, ContactPair, ContactProblem, ContactResult,
    ContactSolver, ContactSolverError, Coulomb, ExactSolver, NodeStatus, Tresca,
};
use vem_elastic::{Component, Dirichlet, ElasticBody, Material, Plane};
use vem_mesh::generators::{perturbed_quads, voronoi, Rectangle};
use vem_mesh::{Point, Vector};
use vem_space::LowestOrderVem;

const COEFFICIENT: f64 = 0.3;
const PUSH: f64 = 0.5;
/// The friction capacity `F P`.
const CAPACITY: f64 = COEFFICIENT * PUSH;

/// The punch `[0.3, 0.7] x [0, 0.4]` pushed by the plate `(shear, -PUSH)` on the block
/// `[0, 1] x [-1, 0]` clamped at its bottom.
fn punch(shear: f64, law: impl ContactLaw + 'static) -> ContactProblem {
    let material = Material::from_young_poisson(200.0, 0.3, Plane::Strain).unwrap();
    let element = Arc::new(LowestOrderVem::default());
    let punch_mesh = voronoi(
        &Rectangle::new(Point::new(0.3, 0.0), Point::new(0.7, 0.4)),
        6,
        5,
    )
    .unwrap();
    let block_mesh = perturbed_quads(
        &Rectangle::new(Point::new(0.0, -1.0), Point::new(1.0, 0.0)),
        9,
        0.25,
        2,
    )
    .unwrap();
    let punch = ElasticBody::builder("punch", punch_mesh, material, element.clone())
        .dirichlet(Dirichlet::rigid_plate(
            "top",
            Component::All,
            Vector::new(shear, -PUSH),
        ))
        .build()
        .unwrap();
    let block = ElasticBody::builder("block", block_mesh, material, element)
        .clamp("bottom")
        .build()
        .unwrap();
    ContactProblem::new(vec![punch, block])
        .with_pair(ContactPair::between(0, "bottom", 1, "top", law))
}

/// Coulomb's law at every node: `|friction| <= F lambda_N` (to `1e-9` of the push), and where
/// the node slipped (its tangential jump is not round-off), friction at the bound, opposing
/// the slip.
fn check_coulomb_law(result: &ContactResult, tolerance: f64) -> (usize, usize) {
    let largest_slip = result
        .nodes
        .iter()
        .fold(0.0f64, |m, n| m.max(n.slip_t().abs()));
    let (mut slipping, mut sticking) = (0, 0);
    for n in &result.nodes {
        let bound = COEFFICIENT * n.normal_force;
        let friction = n.friction_t();
        assert!(
            friction.abs() <= bound + tolerance * PUSH,
            "node at {}: |friction| {:e} > F lambda_N {:e}",
            n.position,
            friction.abs(),
            bound
        );
        if n.slip_t().abs() > 1e-6 * largest_slip {
            slipping += 1;
            assert!(
                (friction.abs() - bound).abs() <= tolerance * PUSH,
                "slipping node at {}: |friction| {:e} != F lambda_N {:e}",
                n.position,
                friction.abs(),
                bound
            );
            assert!(
                friction * n.slip_t() < 0.0,
                "node at {}: friction opposes the slip",
                n.position
            );
        } else if n.status == NodeStatus::Stick {
            sticking += 1;
        }
    }
    (slipping, sticking)
}

#[test]
fn every_shear_below_the_capacity_is_held_with_coulombs_law_node_by_node() {
    for ratio in [0.01, 0.5, 0.99] {
        let shear = ratio * CAPACITY;
        let mut solver = CondensedSolver::default();
        let result = punch(shear, Coulomb::try_new(COEFFICIENT).unwrap())
            .solve(&mut solver)
            .unwrap_or_else(|e| panic!("Q/(F P) = {ratio}: {e}"));
        // The solver the user chose solved it.
        assert_eq!(result.report.solver, solver.name(), "Q/(F P) = {ratio}");
        // The contact carries the plate's force exactly: the block pushes the punch up by P
        // and friction holds it back by Q.
        let force = result.force_on_body_a();
        assert!(
            (force.x + shear).abs() <= 1e-9 * PUSH,
            "Q/(F P) = {ratio}: {force}"
        );
        assert!(
            (force.y - PUSH).abs() <= 1e-9 * PUSH,
            "Q/(F P) = {ratio}: {force}"
        );
        let (slipping, sticking) = check_coulomb_law(&result, 1e-9);
        // A small shear leaves most nodes stuck; near the capacity most of them slip.
        if ratio < 0.1 {
            assert!(sticking > slipping, "{sticking} stick, {slipping} slip");
        }
        if ratio > 0.9 {
            assert!(slipping > sticking, "{sticking} stick, {slipping} slip");
        }
    }
}

#[test]
fn the_interior_point_solver_finds_the_same_coulomb_answer() {
    let shear = 0.5 * CAPACITY;
    let law = Coulomb::try_new(COEFFICIENT).unwrap();
    let condensed = punch(shear, law)
        .solve(&mut CondensedSolver::default())
        .unwrap();
    let exact = punch(shear, law)
        .solve(&mut ExactSolver::default())
        .unwrap();
    // The interior point is accurate to its force accuracy (1e-4 of the largest force).
    for (a, b) in condensed.nodes.iter().zip(&exact.nodes) {
        assert!(
            (a.normal_force - b.normal_force).abs() < 1e-3 * PUSH,
            "{} vs {}",
            a.normal_force,
            b.normal_force
        );
        assert!(
            (a.friction_t() - b.friction_t()).abs() < 1e-3 * PUSH,
            "{} vs {}",
            a.friction_t(),
            b.friction_t()
        );
    }
    check_coulomb_law(&exact, 1e-4);
}

#[test]
fn a_shear_beyond_the_capacity_is_refused_with_its_figures() {
    let shear = 1.01 * CAPACITY;
    let error = punch(shear, Coulomb::try_new(COEFFICIENT).unwrap())
        .solve(&mut CondensedSolver::default())
        .unwrap_err();
    let message = error.to_string();
    match error {
        ContactError::FrictionCapacityExceeded {
            load_along_mode,
            friction_capacity,
            report,
            ..
        } => {
            // The sliding mode is the punch's translation: the load along it is Q, the
            // capacity F times the normal forces, which carry P.
            assert!(
                (load_along_mode - shear).abs() < 1e-6 * shear,
                "{load_along_mode}"
            );
            assert!(
                (friction_capacity - CAPACITY).abs() < 1e-6 * CAPACITY,
                "{friction_capacity}"
            );
            assert!(report.solver.starts_with("condensed"), "{}", report.solver);
        }
        other => panic!("expected a refusal for the capacity, got {other}"),
    }
    assert!(message.contains("1.515000e-1"), "{message}");
    assert!(message.contains("1.500000e-1"), "{message}");
}

#[test]
fn a_handover_names_the_solver_that_was_chosen() {
    // Tresca with g_F = 0.3 on the punch's 0.4 long side holds 0.12: 0.1485 slides it. The
    // condensed solver's proximal steps do not settle along the free mode; it hands the solve
    // over to the active-set solver, and the message names both.
    let error = punch(0.99 * CAPACITY, Tresca::try_new(0.3).unwrap())
        .solve(&mut CondensedSolver::default())
        .unwrap_err();
    let message = error.to_string();
    let ContactError::Solver(ContactSolverError::RigidSliding {
        load_along_mode,
        friction_capacity,
        report,
    }) = error
    else {
        panic!("expected rigid sliding, got {message}");
    };
    assert!(
        (load_along_mode - 0.99 * CAPACITY).abs() < 1e-6,
        "{message}"
    );
    assert!((friction_capacity - 0.12).abs() < 1e-6, "{message}");
    assert!(report.solver.starts_with("condensed"), "{message}");
    if report.solver.contains("active set") {
        assert!(
            message.contains("handed over to the active set"),
            "{message}"
        );
    }
}
