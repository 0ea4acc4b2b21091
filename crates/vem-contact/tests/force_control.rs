//! Force control: a flat punch pushed by a rigid plate with a prescribed resultant
//! ([`Dirichlet::rigid_plate`]) on a block, on non-matching meshes. The contact forces carry the
//! prescribed resultant, the plate's reaction is it, and the displacement-controlled run at
//! the translation the force-controlled run found gives the same answer.

use std::sync::Arc;

use vem_contact::{CondensedSolver, ContactProblem, ContactResult, ExactSolver, Frictionless};
use vem_elastic::{Component, Dirichlet, ElasticBody, Material, Plane};
use vem_mesh::generators::{perturbed_quads, voronoi, Rectangle};
use vem_mesh::{Point, Vector};
use vem_space::LowestOrderVem;

const LOAD: f64 = 0.8;

/// A punch `[0.3, 0.7] x [0, 0.4]` (Voronoi cells) whose top is held in x and moved in y by
/// `top_y`, on a block `[0, 1] x [-1, 0]` (perturbed quads) clamped at its bottom.
fn punch(top_y: Dirichlet) -> ContactProblem {
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
        .dirichlet(Dirichlet::fixed("top", Component::X))
        .dirichlet(top_y)
        .build()
        .unwrap();
    let block = ElasticBody::builder("block", block_mesh, material, element)
        .clamp("bottom")
        .build()
        .unwrap();
    ContactProblem::two_bodies(punch, "bottom", block, "top", Frictionless)
}

/// The vertical contact force on the punch (body A): up, it balances the plate's push.
fn contact_force_on_punch(result: &ContactResult) -> f64 {
    result.force_on_body_a().y
}

#[test]
fn the_plate_force_is_carried_by_the_contact_forces_and_is_the_reaction() {
    let by_force = punch(Dirichlet::rigid_plate(
        "top",
        Component::Y,
        Vector::new(0.0, -LOAD),
    ));
    // The condensed solver solves the equilibrium to round-off; the interior-point solver to
    // its own accuracy.
    for (solver, tolerance) in [
        (
            &mut CondensedSolver::default() as &mut dyn vem_contact::ContactSolver,
            1e-10,
        ),
        (&mut ExactSolver::default(), 1e-7),
    ] {
        let result = by_force.solve(solver).unwrap();
        let punch = &result.bodies[0];
        // The block pushes the punch up with the prescribed load.
        let carried = contact_force_on_punch(&result);
        assert!((carried - LOAD).abs() < tolerance * LOAD, "{carried}");
        // The plate's reaction (the force it exerts on the punch) is the prescribed force, and
        // the block's support takes it back.
        let reaction = punch.solution.reaction("top").unwrap();
        assert!((reaction.y + LOAD).abs() < 1e-12 * LOAD, "{reaction}");
        let support = result.bodies[1].solution.reaction("bottom").unwrap();
        assert!((support.y - LOAD).abs() < tolerance * LOAD, "{support}");
        // Every top vertex moved by the same translation.
        let mesh = punch.body.mesh();
        let top = mesh.part_vertices("top").unwrap();
        let w = punch.solution.vertex_displacement(top[0]).y;
        assert!(w < 0.0);
        for &v in &top {
            assert_eq!(punch.solution.vertex_displacement(v).y, w);
        }
    }
}

#[test]
fn force_control_equals_displacement_control_at_the_translation_found() {
    let by_force = punch(Dirichlet::rigid_plate(
        "top",
        Component::Y,
        Vector::new(0.0, -LOAD),
    ))
    .solve(&mut CondensedSolver::default())
    .unwrap();
    let punch_solution = &by_force.bodies[0];
    let top = punch_solution.body.mesh().part_vertices("top").unwrap();
    let w = punch_solution.solution.vertex_displacement(top[0]).y;
    let by_displacement = punch(Dirichlet::prescribed("top", Component::Y, move |_| {
        Vector::new(0.0, w)
    }))
    .solve(&mut CondensedSolver::default())
    .unwrap();
    // The same contact force, node by node, and the same displacement.
    assert_eq!(by_force.nodes.len(), by_displacement.nodes.len());
    for (a, b) in by_force.nodes.iter().zip(&by_displacement.nodes) {
        assert!(
            (a.normal_force - b.normal_force).abs() < 1e-8 * LOAD,
            "{} vs {}",
            a.normal_force,
            b.normal_force
        );
    }
    let carried = contact_force_on_punch(&by_displacement);
    assert!((carried - LOAD).abs() < 1e-8 * LOAD, "{carried}");
    for (a, b) in by_force.bodies.iter().zip(&by_displacement.bodies) {
        let (ua, ub) = (a.solution.displacement(), b.solution.displacement());
        let scale = ub.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let difference = ua
            .iter()
            .zip(ub)
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
        assert!(difference < 1e-8 * scale, "{difference} vs {scale}");
    }
}
