//! Rigid plates (force control): a part moved as one rigid translation with a prescribed
//! resultant, against the exact uniform state and against the displacement-controlled run at
//! the translation the force-controlled run found.

use std::sync::Arc;

use vem_elastic::{Component, Dirichlet, ElasticBody, ElasticError, Material, Plane};
use vem_mesh::generators::{perturbed_quads, voronoi, Rectangle};
use vem_mesh::{Mesh, Point, Vector};
use vem_space::LowestOrderVem;

const E: f64 = 200.0;
const NU: f64 = 0.3;

fn material() -> Material {
    Material::from_young_poisson(E, NU, Plane::Strain).unwrap()
}

fn body(mesh: &Mesh, conditions: Vec<Dirichlet>) -> Result<ElasticBody, ElasticError> {
    conditions
        .into_iter()
        .fold(
            ElasticBody::builder(
                "block",
                mesh.clone(),
                material(),
                Arc::new(LowestOrderVem::default()),
            ),
            |builder, condition| builder.dirichlet(condition),
        )
        .build()
}

/// The block `[0, 2] x [0, 1]` on Voronoi cells and perturbed quads.
fn meshes() -> Vec<Mesh> {
    let rect = Rectangle::new(Point::new(0.0, 0.0), Point::new(2.0, 1.0));
    vec![
        voronoi(&rect, 5, 3).unwrap(),
        perturbed_quads(&rect, 6, 0.3, 11).unwrap(),
    ]
}

#[test]
fn a_plate_pushed_with_a_force_compresses_the_block_uniformly() {
    // Roller support at the bottom, x held on the left, a rigid plate on the top pushed down
    // with the resultant -p * width: uniaxial stress sigma_yy = -p, so in plane strain the top
    // moves by -p (1 - nu^2) / E * height, every top vertex alike, and the plate's reaction is
    // the prescribed force.
    let (p, width, height) = (3.0, 2.0, 1.0);
    let force = Vector::new(0.0, -p * width);
    for mesh in meshes() {
        let block = body(
            &mesh,
            vec![
                Dirichlet::fixed("bottom", Component::Y),
                Dirichlet::fixed("left", Component::X),
                Dirichlet::rigid_plate("top", Component::Y, force),
            ],
        )
        .unwrap();
        assert_eq!(block.dofs().n_plates(), 1);
        assert!(block.holds_rigid_motions());
        let solution = block.solve().unwrap();
        let exact = -p * (1.0 - NU * NU) / E * height;
        for v in mesh.part_vertices("top").unwrap() {
            let u = solution.vertex_displacement(v);
            assert!(
                (u.y - exact).abs() < 1e-12,
                "top vertex {v}: {} vs {exact}",
                u.y
            );
        }
        for v in 0..mesh.n_vertices() {
            let y = mesh.vertex(v).y;
            let u = solution.vertex_displacement(v);
            assert!((u.y - exact * y / height).abs() < 1e-12, "vertex {v}");
        }
        let reaction = solution.reaction("top").unwrap();
        assert!(
            (reaction - force).norm() < 1e-12 * force.norm(),
            "{reaction}"
        );
        // Equilibrium: the supports carry the plate's force.
        let bottom = solution.reaction("bottom").unwrap();
        assert!((bottom + force).norm() < 1e-11 * force.norm(), "{bottom}");
    }
}

#[test]
fn force_control_equals_displacement_control_at_the_translation_found() {
    // A clamped block sheared and compressed by a plate with both components prescribed: the
    // displacement-controlled run at the plate's translation gives the same field, and its
    // reaction is the prescribed force.
    let force = Vector::new(0.7, -2.0);
    for mesh in meshes() {
        let by_force = body(
            &mesh,
            vec![
                Dirichlet::fixed("bottom", Component::All),
                Dirichlet::rigid_plate("top", Component::All, force),
            ],
        )
        .unwrap();
        assert_eq!(by_force.dofs().n_plates(), 2);
        let solution = by_force.solve().unwrap();
        let top = mesh.part_vertices("top").unwrap();
        let w = solution.vertex_displacement(top[0]);
        for &v in &top {
            assert!((solution.vertex_displacement(v) - w).norm() < 1e-14 * w.norm());
        }
        assert!((solution.reaction("top").unwrap() - force).norm() < 1e-12 * force.norm());
        let by_displacement = body(
            &mesh,
            vec![
                Dirichlet::fixed("bottom", Component::All),
                Dirichlet::prescribed("top", Component::All, move |_| w),
            ],
        )
        .unwrap();
        let reference = by_displacement.solve().unwrap();
        let reaction = reference.reaction("top").unwrap();
        assert!(
            (reaction - force).norm() < 1e-10 * force.norm(),
            "{reaction} vs {force}"
        );
        let scale = w.norm();
        for v in 0..mesh.n_vertices() {
            let difference = solution.vertex_displacement(v) - reference.vertex_displacement(v);
            assert!(
                difference.norm() < 1e-10 * scale,
                "vertex {v}: {difference}"
            );
        }
        // The energy balance of the plate: 1/2 u^T K u = 1/2 P . w.
        let work = 0.5 * force.dot(&w);
        assert!((solution.strain_energy() - work).abs() < 1e-10 * work.abs());
    }
}

#[test]
fn a_plate_on_a_prescribed_component_is_a_conflict() {
    let mesh = &meshes()[1];
    let err = body(
        mesh,
        vec![
            Dirichlet::fixed("top", Component::Y),
            Dirichlet::rigid_plate("top", Component::Y, Vector::new(0.0, -1.0)),
        ],
    )
    .unwrap_err();
    assert!(
        matches!(&err, ElasticError::RigidPlateConflict { plate, other, component: 1, .. }
            if plate == "top" && other == "top"),
        "{err:?}"
    );
    let err = body(
        mesh,
        vec![Dirichlet::rigid_plate(
            "top",
            Component::Y,
            Vector::new(0.0, f64::NAN),
        )],
    )
    .unwrap_err();
    assert!(
        matches!(err, ElasticError::NonFiniteResultant { .. }),
        "{err:?}"
    );
}

#[test]
fn a_plate_alone_does_not_hold_the_body() {
    // Nothing but the plate resists the vertical motion: the body floats.
    let mesh = &meshes()[1];
    let floating = body(
        mesh,
        vec![
            Dirichlet::fixed("left", Component::X),
            Dirichlet::fixed("bottom", Component::X),
            Dirichlet::rigid_plate("top", Component::Y, Vector::new(0.0, -1.0)),
        ],
    )
    .unwrap();
    assert!(!floating.holds_rigid_motions());
    assert!(matches!(
        floating.solve(),
        Err(ElasticError::SingularStiffness { .. })
    ));
}
