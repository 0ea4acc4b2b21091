//! Bodies in space: the generic `ElasticBody<3>` on every polyhedral family against exact
//! uniform states, reactions against loads, rigid plates, and the errors of bad set-ups.

use std::sync::Arc;

use nalgebra::Matrix3;
use vem_elastic::{Component, Dirichlet, ElasticBody, ElasticError, Material};
use vem_mesh::generators::polyhedral::{Cuboid, PolyhedralFamily};
use vem_mesh::{Point3, PolyhedralMesh, Vector3};
use vem_space::{LinearTetrahedron, PolyhedralVem};

const E: f64 = 250.0;
const NU: f64 = 0.3;

fn families() -> Vec<(PolyhedralFamily, PolyhedralMesh)> {
    let cuboid = Cuboid::new(Point3::new(0.0, 0.0, 0.0), Point3::new(1.0, 2.0, 1.5));
    PolyhedralFamily::all()
        .into_iter()
        .map(|family| (family, family.generate(&cuboid, 4, 11).unwrap()))
        .collect()
}

fn vem() -> Arc<PolyhedralVem> {
    Arc::new(PolyhedralVem::default())
}

fn relative_nodal_error(
    body: &ElasticBody<3>,
    displacement: &[f64],
    exact: impl Fn(Point3) -> Vector3,
) -> f64 {
    let mut error: f64 = 0.0;
    let mut scale: f64 = 0.0;
    for (v, p) in body.mesh().vertices().iter().enumerate() {
        let u = Vector3::new(
            displacement[3 * v],
            displacement[3 * v + 1],
            displacement[3 * v + 2],
        );
        error = error.max((u - exact(*p)).norm());
        scale = scale.max(exact(*p).norm());
    }
    error / scale
}

#[test]
fn a_box_on_rollers_under_a_uniform_traction_takes_the_exact_uniform_state() {
    // u_z = 0 on the bottom, u_x = 0 on the left, u_y = 0 on the front, sigma_zz = t on the
    // top: sigma = t e_z e_z, u = (t/E) (-nu x, -nu y, z).
    let t = 3.0;
    let exact = |x: Point3| t / E * Vector3::new(-NU * x.x, -NU * x.y, x.z);
    let material = Material::isotropic(E, NU).unwrap();
    for (family, mesh) in families() {
        let body = ElasticBody::builder_polyhedral("box", mesh, material, vem())
            .dirichlet(Dirichlet::fixed("bottom", Component::Z))
            .dirichlet(Dirichlet::fixed("left", Component::X))
            .dirichlet(Dirichlet::fixed("front", Component::Y))
            .traction("top", move |_| Vector3::new(0.0, 0.0, t))
            .build()
            .unwrap();
        let solution = body.solve().unwrap();
        let error = relative_nodal_error(&body, solution.displacement(), exact);
        assert!(error < 1e-10, "{}: {error:e}", family.name());
        // Every cell carries the uniform stress.
        for field in body.element_fields(solution.displacement()).unwrap() {
            let expected = Matrix3::new(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, t);
            assert!(
                (field.stress - expected).amax() < 1e-9 * t,
                "{}",
                family.name()
            );
            assert!((field.von_mises - t).abs() < 1e-9 * t);
        }
        // The rollers carry the load: the bottom pushes down with t |top| = t 1 x 2.
        let bottom = solution.reaction("bottom").unwrap();
        assert!((bottom.z + 2.0 * t).abs() < 1e-9 * t, "{bottom}");
        // The energy is int sigma : eps / 2 = |E| t^2 / (2 E).
        let energy = 3.0 * t * t / (2.0 * E);
        assert!((solution.strain_energy() - energy).abs() < 1e-10 * energy);
    }
}

#[test]
fn a_general_linear_field_with_tractions_on_three_sides_is_exact() {
    // The 3D PT0b: u linear with every strain component, Dirichlet u on left, front and bottom,
    // traction sigma n on right, back and top.
    let material = Material::isotropic(E, NU).unwrap();
    let (lambda, mu) = material.lame().unwrap();
    let m = Matrix3::new(0.01, 0.02, -0.01, 0.005, -0.02, 0.03, 0.015, 0.01, 0.025);
    let eps = (m + m.transpose()) * 0.5;
    let sigma = Matrix3::identity() * lambda * eps.trace() + eps * 2.0 * mu;
    let exact = move |x: Point3| Vector3::new(0.1, -0.2, 0.05) + m * x.coords;
    for (family, mesh) in families() {
        let mut builder = ElasticBody::builder_polyhedral("box", mesh, material, vem());
        for part in ["left", "front", "bottom"] {
            builder = builder.dirichlet(Dirichlet::with_values(part, Component::All, exact));
        }
        for (part, normal) in [
            ("right", Vector3::x()),
            ("back", Vector3::y()),
            ("top", Vector3::z()),
        ] {
            builder = builder.traction(part, move |_| sigma * normal);
        }
        let body = builder.build().unwrap();
        let solution = body.solve().unwrap();
        let error = relative_nodal_error(&body, solution.displacement(), exact);
        assert!(error < 1e-10, "{}: {error:e}", family.name());
    }
}

#[test]
fn reactions_balance_the_loads_of_a_clamped_body() {
    // Clamped at the bottom; a traction on the top and on the right, a body force: the sum of
    // the reactions and the applied loads vanishes.
    let material = Material::isotropic(E, NU).unwrap();
    let traction = |x: Point3| Vector3::new(0.2 * x.y, -0.1, 1.0 + x.x);
    let force = |x: Point3| Vector3::new(0.0, x.z, -2.0);
    // int over the top (z = 1.5, [0,1] x [0,2]) of g: (0.2 * 2, -0.2, 2 + 1) = (0.4, -0.2, 3).
    let top_load = Vector3::new(0.4, -0.2, 3.0);
    // int over the right (x = 1, [0,2] x [0,1.5]) of (0.5, 0, 0): (1.5, 0, 0).
    let right_load = Vector3::new(1.5, 0.0, 0.0);
    // int over the box (volume 3) of f: (0, 3 * 0.75, -6).
    let body_load = Vector3::new(0.0, 2.25, -6.0);
    for (family, mesh) in families() {
        let body = ElasticBody::builder_polyhedral("block", mesh, material, vem())
            .clamp("bottom")
            .traction("top", traction)
            .traction("right", |_| Vector3::new(0.5, 0.0, 0.0))
            .body_force(force)
            .build()
            .unwrap();
        let solution = body.solve().unwrap();
        let reaction = solution.reaction("bottom").unwrap();
        let balance = reaction + top_load + right_load + body_load;
        assert!(balance.norm() < 1e-10, "{}: {balance}", family.name());
        assert!(solution.strain_energy() > 0.0);
    }
}

#[test]
fn a_rigid_plate_on_top_moves_the_box_by_the_exact_amount() {
    // Rollers as above and a rigid plate on the top pushing down with the resultant -F: the
    // uniform state sigma_zz = -F / |top|, and the plate moves by -F H / (|top| E).
    let (force, area, height) = (12.0, 2.0, 1.5);
    let material = Material::isotropic(E, NU).unwrap();
    for (family, mesh) in families() {
        let body = ElasticBody::builder_polyhedral("box", mesh, material, vem())
            .dirichlet(Dirichlet::fixed("bottom", Component::Z))
            .dirichlet(Dirichlet::fixed("left", Component::X))
            .dirichlet(Dirichlet::fixed("front", Component::Y))
            .dirichlet(Dirichlet::rigid_plate(
                "top",
                Component::Z,
                Vector3::new(0.0, 0.0, -force),
            ))
            .build()
            .unwrap();
        let solution = body.solve().unwrap();
        let expected = -force * height / (area * E);
        for v in body.mesh().part_vertices("top").unwrap() {
            let uz = solution.displacement()[3 * v + 2];
            assert!(
                (uz - expected).abs() < 1e-10 * expected.abs(),
                "{}",
                family.name()
            );
        }
        let plate = solution.reaction("top").unwrap();
        assert!((plate.z + force).abs() < 1e-9 * force, "{plate}");
    }
}

#[test]
fn the_linear_tetrahedron_is_the_vem_on_tetrahedra_and_refuses_other_cells() {
    let material = Material::isotropic(E, NU).unwrap();
    let families = families();
    let tets = families
        .iter()
        .find(|(f, _)| matches!(f, PolyhedralFamily::Tetrahedra))
        .unwrap()
        .1
        .clone();
    let solve = |element: Arc<dyn vem_space::PolyhedralElement>| {
        ElasticBody::builder_polyhedral("tets", tets.clone(), material, element)
            .clamp("bottom")
            .traction("top", |x| Vector3::new(x.y, 0.0, -1.0))
            .build()
            .unwrap()
            .solve()
            .unwrap()
    };
    let (p1, vem) = (solve(Arc::new(LinearTetrahedron)), solve(vem()));
    // The stiffness matrices agree to round-off; the loads are both the fan trace.
    let difference = p1
        .displacement()
        .iter()
        .zip(vem.displacement())
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    let scale = p1.displacement().iter().fold(0.0f64, |m, a| m.max(a.abs()));
    assert!(difference < 1e-12 * scale, "{difference:e}");
    let hexahedra = families[0].1.clone();
    let err =
        ElasticBody::builder_polyhedral("box", hexahedra, material, Arc::new(LinearTetrahedron))
            .clamp("bottom")
            .build()
            .unwrap_err();
    assert_eq!(
        err.to_string(),
        "body 'box': element 'p1' does not support polygon 0 with 8 vertices"
    );
}

#[test]
fn plane_stress_materials_are_refused_in_space() {
    let (_, mesh) = families().remove(0);
    let plate = Material::from_young_poisson(E, NU, vem_elastic::Plane::Stress).unwrap();
    let err = ElasticBody::builder_polyhedral("box", mesh, plate, vem())
        .clamp("bottom")
        .build()
        .unwrap_err();
    assert!(matches!(err, ElasticError::InvalidMaterial { .. }), "{err}");
}

#[test]
fn auto_orders_elasticity_in_space_by_nested_dissection_from_ten_thousand_unknowns() {
    use vem_elastic::{elimination_order, Ordering};
    // A cube of 14^3 hexahedra clamped at the bottom: 3 x 15 x 15 x 14 = 9450 unknowns (AMD),
    // and of 15^3: 11520 (nested dissection). A planar body of 11552 unknowns stays with AMD.
    let material = Material::isotropic(E, NU).unwrap();
    let cube = |n: usize| {
        let mesh = PolyhedralFamily::Hexahedra
            .generate(&Cuboid::unit_cube(), n, 0)
            .unwrap();
        let body = ElasticBody::builder_polyhedral("cube", mesh, material, vem())
            .clamp("bottom")
            .build()
            .unwrap();
        let system = body.assemble().unwrap();
        elimination_order(system.stiffness().symbolic(), &[], Ordering::Auto)
            .unwrap()
            .1
    };
    let expected = if Ordering::nested_dissection_available() {
        Ordering::NestedDissection
    } else {
        Ordering::Amd
    };
    assert_eq!(cube(14), Ordering::Amd);
    assert_eq!(cube(15), expected);
    let square = vem_mesh::generators::structured_quads(
        &vem_mesh::generators::Rectangle::unit_square(),
        76,
        76,
    )
    .unwrap();
    let plate = ElasticBody::builder(
        "plate",
        square,
        Material::from_lame(2.0, 1.0, vem_elastic::Plane::Strain).unwrap(),
        Arc::new(vem_space::LowestOrderVem::default()),
    )
    .clamp("bottom")
    .build()
    .unwrap();
    assert!(plate.dofs().n_free() > 11_000);
    let system = plate.assemble().unwrap();
    let (_, used) = elimination_order(system.stiffness().symbolic(), &[], Ordering::Auto).unwrap();
    assert_eq!(used, Ordering::Amd);
}
