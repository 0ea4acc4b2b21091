//! Coulomb friction with the interior-point solver: the fixed point stops at the inner solver's
//! force accuracy instead of stalling above the nominal tolerance.

use std::sync::Arc;

use vem_contact::{ContactProblem, ContactSolver, Coulomb, ExactSolver, NodeStatus, Obstacle};
use vem_elastic::{ElasticBody, Material, Plane};
use vem_mesh::generators::{MeshFamily, Rectangle};
use vem_mesh::{Point, Vector};
use vem_space::LowestOrderVem;

const COEFFICIENT: f64 = 0.3;

#[test]
fn coulomb_converges_with_the_exact_solver_and_respects_the_cone() {
    // A block clamped on top and pressed onto a rigid line: the Poisson expansion pushes the
    // bottom outwards, friction holds the centre (stick) and the corners slip.
    let compression = 0.02;
    let rect = Rectangle::new(Point::new(0.0, 0.0), Point::new(1.0, 1.0));
    let mesh = MeshFamily::Quads.generate(&rect, 12, 0).unwrap();
    let material = Material::from_lame(2.0, 1.0, Plane::Strain).unwrap();
    let body = ElasticBody::builder("block", mesh, material, Arc::new(LowestOrderVem::default()))
        .clamp("top")
        .build()
        .unwrap();
    let obstacle = Obstacle::Line {
        point: Point::new(0.0, compression),
        normal: Vector::new(0.0, 1.0),
    };
    let mut solver = ExactSolver::default();
    let accuracy = solver.force_accuracy();
    assert!(accuracy > 0.0 && accuracy < 1e-3, "{accuracy:e}");
    let result = ContactProblem::against_obstacle(
        body,
        "bottom",
        obstacle,
        Coulomb::try_new(COEFFICIENT).unwrap(),
    )
    .solve(&mut solver)
    .expect("Coulomb converges with the interior-point solver");
    let fixed_point = result.fixed_point.as_ref().unwrap();
    assert_eq!(fixed_point.tolerance, accuracy.max(1e-8));
    assert!(
        fixed_point.residual <= fixed_point.tolerance,
        "{fixed_point:?}"
    );

    let max_force = result
        .nodes
        .iter()
        .fold(0.0_f64, |m, n| m.max(n.normal_force));
    assert!(max_force > 0.0);
    for node in &result.nodes {
        // |lambda_T| <= F lambda_N up to the fixed-point and interior-point accuracy.
        let excess = node.friction_t().abs() - COEFFICIENT * node.normal_force.max(0.0);
        assert!(
            excess <= 10.0 * fixed_point.tolerance * max_force,
            "node at {}: |friction| {:e} > F * normal {:e}",
            node.position,
            node.friction_t().abs(),
            COEFFICIENT * node.normal_force
        );
    }
    let count = |s| result.nodes.iter().filter(|n| n.status == s).count();
    assert!(count(NodeStatus::Stick) > 0, "no stick node");
    assert!(count(NodeStatus::Slip) > 0, "no slip node");
    // Symmetry about x = 1/2: the friction resultant vanishes.
    let friction: f64 = result.nodes.iter().map(|n| n.friction_t()).sum();
    assert!(
        friction.abs() <= 1e-6 * max_force * result.nodes.len() as f64,
        "{friction:e}"
    );
}
