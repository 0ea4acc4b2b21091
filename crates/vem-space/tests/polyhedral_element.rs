//! The element on polyhedra against the 3D test kit, every stabilisation, and the linear
//! tetrahedron: on a tetrahedron the VEM is P1 to round-off.

use std::sync::Arc;

use nalgebra::DVector;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use vem_mesh::polyhedral::geometry::Polyhedron;
use vem_mesh::{Point3, Vector3};
use vem_space::testkit3d::{
    check_element, interpolant, standard_materials, standard_polyhedra, DEFAULT_TOLERANCE,
};
use vem_space::{
    BBar, DRecipe, DofiDofi, LinearTetrahedron, PolyhedralElement, PolyhedralStabilisation,
    PolyhedralVem, StabilisationScaling,
};

fn elements() -> Vec<PolyhedralVem> {
    let stabilisations: Vec<Arc<dyn PolyhedralStabilisation>> = vec![
        Arc::new(DofiDofi::default()),
        Arc::new(DofiDofi::new(StabilisationScaling::ShearModulus)),
        Arc::new(DRecipe),
        Arc::new(BBar),
    ];
    stabilisations
        .into_iter()
        .map(|s| PolyhedralVem::try_new(s).unwrap())
        .collect()
}

#[test]
fn every_stabilisation_passes_the_kit_on_every_standard_polyhedron() {
    let mut worst: f64 = 0.0;
    for element in elements() {
        let checks = check_element(&element).unwrap();
        assert_eq!(checks.len(), 20, "{}", element.name());
        for check in &checks {
            let failures = check.failures(DEFAULT_TOLERANCE);
            assert!(failures.is_empty(), "{}: {failures:?}", element.name());
            worst = worst.max(check.worst_error());
            println!(
                "{:>14} {:34} rigid {:.1e} cons {:.1e} rank {}/{} sym {:.1e} energy {:.1e} patch {:.1e}",
                element.name(),
                check.polyhedron,
                check.rigid_motion_residual,
                check.consistency_error,
                check.rank,
                check.expected_rank(),
                check.symmetry_error,
                check.linear_energy_error,
                check.patch_test_error
            );
        }
    }
    println!("worst relative error of the kit over every stabilisation: {worst:.1e}");
    let names: Vec<String> = elements().iter().map(|e| e.name().to_string()).collect();
    assert_eq!(names, ["vem1", "vem1-shear", "vem1-drecipe", "vem1-bbar"]);
}

#[test]
fn the_linear_tetrahedron_passes_the_kit_on_the_tetrahedron_only() {
    let checks = check_element(&LinearTetrahedron).unwrap();
    assert_eq!(checks.len(), 2);
    for check in &checks {
        assert_eq!(check.polyhedron, "tetrahedron");
        assert!(check.failures(DEFAULT_TOLERANCE).is_empty(), "{check:?}");
    }
    let cube = &standard_polyhedra()[1];
    assert!(!LinearTetrahedron.supports(&cube.polyhedron));
    let err = LinearTetrahedron
        .stiffness(&cube.polyhedron, &standard_materials()[0])
        .unwrap_err();
    assert_eq!(
        err.to_string(),
        "element 'p1' does not support a polyhedron with 8 vertices and 6 faces"
    );
}

/// A random tetrahedron, its vertices in a random order, faces outward.
fn random_tetrahedron(rng: &mut ChaCha8Rng) -> Polyhedron {
    loop {
        let mut points: Vec<Point3> = (0..4)
            .map(|_| Point3::new(rng.gen(), rng.gen(), rng.gen()) * 2.0)
            .collect();
        let det = (points[1] - points[0])
            .cross(&(points[2] - points[0]))
            .dot(&(points[3] - points[0]));
        if det.abs() < 0.05 {
            continue;
        }
        if det < 0.0 {
            points.swap(2, 3);
        }
        return Polyhedron::new(
            points,
            &[vec![0, 2, 1], vec![0, 1, 3], vec![0, 3, 2], vec![1, 2, 3]],
        );
    }
}

#[test]
fn on_a_tetrahedron_every_vem_is_p1_to_round_off() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut worst: f64 = 0.0;
    for _ in 0..50 {
        let tet = random_tetrahedron(&mut rng);
        for material in standard_materials() {
            let p1 = LinearTetrahedron.stiffness(&tet, &material).unwrap();
            for element in elements() {
                let vem = element.stiffness(&tet, &material).unwrap();
                let scale = p1.consistency.norm();
                let difference = (&vem.total() - &p1.consistency).norm() / scale;
                assert!(difference < 1e-13, "{}: {difference:e}", element.name());
                assert!(vem.stabilisation.norm() < 1e-13 * scale);
                worst = worst.max(difference);
            }
            // The projections agree too: P1 reproduces itself.
            let u = DVector::from_fn(12, |i, _| ((i * 7 % 5) as f64 - 2.0) * 0.1);
            let (a, b) = (
                PolyhedralVem::default().projection(&tet).unwrap(),
                LinearTetrahedron.projection(&tet).unwrap(),
            );
            let x = Point3::new(0.3, 0.7, 1.1);
            assert!((a.evaluate(&u, x) - b.evaluate(&u, x)).norm() < 1e-12);
        }
    }
    println!("VEM against P1 on 50 random tetrahedra: relative difference {worst:.1e}");
}

#[test]
fn the_load_of_a_linear_force_is_exact_on_every_standard_polyhedron() {
    // l_E(v) = int_E f . Pi v is exact for a constant force and linear v:
    // int_E f . v = |E| f . v(x_E).
    let f = Vector3::new(1.0, -2.0, 0.5);
    let v = |x: Point3| Vector3::new(0.3 * x.x - x.z, 1.0 + x.y, 2.0 * x.x + 0.1 * x.z);
    for test in standard_polyhedra() {
        let p = &test.polyhedron;
        let load = PolyhedralVem::default().body_load(p, &|_| f).unwrap();
        let v_i = interpolant(p.points(), v);
        let expected = test.volume * f.dot(&v(p.centroid()));
        let scale = test.volume * f.norm() * v(p.centroid()).norm().max(1.0);
        assert!(
            (load.dot(&v_i) - expected).abs() < 1e-12 * scale,
            "{}: {} vs {expected}",
            test.name,
            load.dot(&v_i)
        );
    }
}

#[test]
fn on_a_tetrahedron_the_vem_load_of_a_linear_force_is_the_p1_load() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let force = |x: Point3| Vector3::new(1.0 + x.y, -2.0 * x.x + x.z, 0.5 - x.z);
    for _ in 0..20 {
        let tet = random_tetrahedron(&mut rng);
        let vem = PolyhedralVem::default().body_load(&tet, &force).unwrap();
        let p1 = LinearTetrahedron.body_load(&tet, &force).unwrap();
        assert!((&vem - &p1).norm() < 1e-13 * p1.norm(), "{vem} {p1}");
    }
}
