//! Verification in space: the exact solutions against central differences and hand values, the
//! patch test on every polyhedral family and stabilisation, and the convergence rates of the
//! lowest-order VEM on every family at small sizes.

use std::sync::Arc;

use vem_mesh::generators::polyhedral::PolyhedralFamily;
use vem_mesh::{Point3, Vector3};
use vem_space::{
    BBar, DRecipe, DofiDofi, PolyhedralElement, PolyhedralStabilisation, PolyhedralVem,
    StabilisationScaling,
};
use vem_verify::exact::Lame;
use vem_verify::three_d::{
    run_solid, solid_case_by_name, solid_rates, three_d_convergence, DivergenceFreeSolid,
    ExactSolution3d, LinearSolid, SmoothSolid, CUBE_PARTS, SOLID_CASE_NAMES,
};

/// Points inside the unit cube, away from its sides.
fn interior_points() -> Vec<Point3> {
    let mut points = Vec::new();
    for i in 0..5 {
        let t = |k: usize| 0.13 + 0.17 * ((i * k + 3) % 5) as f64;
        points.push(Point3::new(t(1), t(2), t(3)));
    }
    points.push(Point3::new(0.5, 0.5, 0.5));
    points
}

#[test]
fn every_solution_is_in_equilibrium_by_central_differences() {
    let lame = Lame::try_new(2.0, 1.0).unwrap();
    let h = 1e-4;
    for name in SOLID_CASE_NAMES {
        let case = solid_case_by_name(name, lame).unwrap();
        assert_eq!(case.name(), name);
        for x in interior_points() {
            let shifted = |k: usize, s: f64| {
                let mut y = x;
                y[k] += s;
                y
            };
            // The gradient: (i, j) = d_j u_i.
            let g = case.gradient(x);
            for j in 0..3 {
                let d = (case.displacement(shifted(j, h)) - case.displacement(shifted(j, -h)))
                    / (2.0 * h);
                for i in 0..3 {
                    assert!(
                        (d[i] - g[(i, j)]).abs() < 1e-6 * (1.0 + g.amax()),
                        "{name}: d_{j} u_{i} at {x}: {} vs {}",
                        d[i],
                        g[(i, j)]
                    );
                }
            }
            // -div sigma = f.
            let mut div = Vector3::zeros();
            for j in 0..3 {
                let d = (case.stress(shifted(j, h)) - case.stress(shifted(j, -h))) / (2.0 * h);
                div += d.column(j);
            }
            let f = case.body_force(x);
            assert!(
                (div + f).norm() < 1e-5 * (1.0 + f.norm()),
                "{name} at {x}: -div sigma = {} but f = {f}",
                -div
            );
        }
    }
}

#[test]
fn the_solutions_have_their_hand_values_and_boundary_data() {
    let lame = Lame::try_new(2.0, 1.0).unwrap();
    let pi2 = std::f64::consts::PI.powi(2);
    // E1-3D at the centre: u = (1, 0, 0); f_x = (lambda + 4 mu) pi^2 (Laplace u_x = -3 pi^2 u_x,
    // d_x div u = d_xx u_x = -pi^2), f_y = f_z = 0 by symmetry of the sines about 1/2.
    let smooth = SmoothSolid::new(lame);
    let centre = Point3::new(0.5, 0.5, 0.5);
    assert!((smooth.displacement(centre) - Vector3::new(1.0, 0.0, 0.0)).norm() < 1e-15);
    let f = smooth.body_force(centre);
    assert!(
        (f - Vector3::new(6.0 * pi2, 0.0, 0.0)).norm() < 1e-12,
        "{f}"
    );
    // Its traction on the top at (1/2, 1/2, 1): sigma_xz = -pi mu, sigma_yz = 0,
    // sigma_zz = 2 pi (lambda + 2 mu).
    let pi = std::f64::consts::PI;
    let top = smooth.stress(Point3::new(0.5, 0.5, 1.0)) * Vector3::z();
    assert!(
        (top - Vector3::new(-pi, 0.0, 8.0 * pi)).norm() < 1e-12,
        "{top}"
    );
    // E2-3D: divergence free, lambda-free, zero on the boundary; at (1/4, 1/2, 3/4):
    // P(1/4) = P(3/4) = 9/256, P(1/2) = 1/16, P'(1/4) = 3/16, P'(1/2) = 0, P'(3/4) = -3/16, so
    // u_x = A (P P' P - P P P') = A (9/256) (1/16) (3/16) = 100 * 27/65536.
    let free = DivergenceFreeSolid::new(lame);
    let x = Point3::new(0.25, 0.5, 0.75);
    let expected_x = 100.0 * 27.0 / 65536.0;
    assert!((free.displacement(x).x - expected_x).abs() < 1e-15);
    let other = DivergenceFreeSolid::new(Lame::try_new(1e6, 1.0).unwrap());
    for x in interior_points() {
        assert!(free.gradient(x).trace().abs() < 1e-14);
        // f = -mu Laplace u whatever lambda: (lambda + mu) grad div u vanishes to round-off.
        let (f, g) = (free.body_force(x), other.body_force(x));
        assert!((f - g).norm() < 1e-8 * (1.0 + f.norm()), "{f} vs {g}");
    }
    // Boundary data: E2-3D vanishes on every side, E1-3D on every side (its top carries a
    // traction), PT0-3D is the linear field.
    for (part, normal) in CUBE_PARTS {
        let normal = Vector3::from(normal);
        for s in [0.2, 0.5, 0.9] {
            // A point of the side: coordinates s, 1 - s in the tangential directions.
            let mut p = Point3::new(s, 1.0 - s, 0.5 * s + 0.1);
            for k in 0..3 {
                if normal[k] != 0.0 {
                    p[k] = if normal[k] > 0.0 { 1.0 } else { 0.0 };
                }
            }
            assert!(free.displacement(p).norm() < 1e-16, "{part}");
            assert!(smooth.displacement(p).norm() < 1e-15, "{part}");
        }
    }
    assert_eq!(smooth.traction_sides(), ["top"]);
    let patch = LinearSolid::new(lame);
    assert_eq!(patch.body_force(x), Vector3::zeros());
    assert!(solid_case_by_name("E9-3D", lame).is_none());
}

fn stabilisations() -> Vec<Arc<dyn PolyhedralElement>> {
    let s: Vec<Arc<dyn PolyhedralStabilisation>> = vec![
        Arc::new(DofiDofi::default()),
        Arc::new(DofiDofi::new(StabilisationScaling::ShearModulus)),
        Arc::new(DRecipe),
        Arc::new(BBar),
    ];
    s.into_iter()
        .map(|s| Arc::new(PolyhedralVem::try_new(s).unwrap()) as Arc<dyn PolyhedralElement>)
        .collect()
}

#[test]
fn the_patch_test_is_exact_on_every_family_with_every_stabilisation() {
    // A nearly incompressible material too: the patch test does not depend on lambda.
    for lame in [Lame::REFERENCE, Lame::try_new(5e4, 1.0).unwrap()] {
        let case: Arc<dyn ExactSolution3d> = Arc::new(LinearSolid::new(lame));
        for family in PolyhedralFamily::all() {
            for element in stabilisations() {
                let run = run_solid(Arc::clone(&case), family, 3, Arc::clone(&element)).unwrap();
                assert!(
                    run.nodal_error < 1e-10 && run.errors.relative_grad() < 1e-10,
                    "{} with {}: nodal {:e}, E_grad {:e}",
                    family.name(),
                    element.name(),
                    run.nodal_error,
                    run.errors.relative_grad()
                );
                assert!(run.errors.relative_l2() < 1e-10);
            }
        }
    }
}

#[test]
fn every_family_converges_at_the_optimal_rates() {
    // For each family the two smallest sizes (n, then the finer one) already in the asymptotic
    // range of both solutions (docs/convergence-3d.md: coarser pairs give the
    // lower pre-asymptotic slopes listed there); rates against the mean cell size.
    let plan = [
        (PolyhedralFamily::Hexahedra, [6, 12]),
        (PolyhedralFamily::Tetrahedra, [16, 24]),
        (
            PolyhedralFamily::PerturbedHexahedra {
                distortion: PolyhedralFamily::DEFAULT_DISTORTION,
            },
            [8, 16],
        ),
        (PolyhedralFamily::Voronoi, [8, 12]),
        (PolyhedralFamily::NonConvex, [12, 18]),
        (PolyhedralFamily::Octree, [8, 12]),
    ];
    let lame = Lame::REFERENCE;
    let cases: Vec<Arc<dyn ExactSolution3d>> = vec![
        Arc::new(SmoothSolid::new(lame)),
        Arc::new(DivergenceFreeSolid::new(lame)),
    ];
    let element: Arc<dyn PolyhedralElement> = Arc::new(PolyhedralVem::default());
    for (family, sizes) in plan {
        let runs = three_d_convergence(&cases, &[family], &sizes, Arc::clone(&element)).unwrap();
        for rates in solid_rates(&runs, 2) {
            let (grad, l2) = (rates.grad_rate.unwrap(), rates.l2_rate.unwrap());
            println!(
                "{} on {} (n = {:?}): E_grad rate {grad:.3}, E_0 rate {l2:.3}",
                rates.case, rates.family, rates.sizes
            );
            assert!(
                grad >= 0.95 && l2 >= 1.9,
                "{} on {}: rates {grad:.3}, {l2:.3}",
                rates.case,
                rates.family
            );
        }
    }
}

#[test]
fn the_loads_are_the_formulas_of_the_documentation() {
    // docs/manufactured.md, section 11, typed in by hand.
    let (lambda, mu) = (2.0, 1.0);
    let lame = Lame::try_new(lambda, mu).unwrap();
    let pi = std::f64::consts::PI;
    let s = |k: f64, t: f64| (k * pi * t).sin();
    let c = |k: f64, t: f64| (k * pi * t).cos();
    let e1 = |p: Point3| {
        let (x, y, z) = (p.x, p.y, p.z);
        let pi2 = pi * pi;
        Vector3::new(
            3.0 * mu * pi2 * s(1.0, x) * s(1.0, y) * s(1.0, z)
                - (lambda + mu)
                    * pi2
                    * (-s(1.0, x) * s(1.0, y) * s(1.0, z)
                        + 2.0 * c(2.0, x) * c(1.0, y) * s(1.0, z)
                        + 2.0 * c(1.0, x) * s(1.0, y) * c(2.0, z)),
            6.0 * mu * pi2 * s(2.0, x) * s(1.0, y) * s(1.0, z)
                - (lambda + mu)
                    * pi2
                    * (c(1.0, x) * c(1.0, y) * s(1.0, z) - s(2.0, x) * s(1.0, y) * s(1.0, z)
                        + 2.0 * s(1.0, x) * c(1.0, y) * c(2.0, z)),
            6.0 * mu * pi2 * s(1.0, x) * s(1.0, y) * s(2.0, z)
                - (lambda + mu)
                    * pi2
                    * (c(1.0, x) * s(1.0, y) * c(1.0, z) + s(2.0, x) * c(1.0, y) * c(1.0, z)
                        - 4.0 * s(1.0, x) * s(1.0, y) * s(2.0, z)),
        )
    };
    let p = |t: f64| t * t * (1.0 - t) * (1.0 - t);
    let p1 = |t: f64| 2.0 * t - 6.0 * t * t + 4.0 * t.powi(3);
    let p2 = |t: f64| 2.0 - 12.0 * t + 12.0 * t * t;
    let p3 = |t: f64| -12.0 + 24.0 * t;
    let a = DivergenceFreeSolid::AMPLITUDE;
    let f_x = |x: f64, y: f64, z: f64| {
        -mu * a
            * (p2(x) * p1(y) * p(z) + p(x) * p3(y) * p(z) + p(x) * p1(y) * p2(z)
                - p2(x) * p(y) * p1(z)
                - p(x) * p2(y) * p1(z)
                - p(x) * p(y) * p3(z))
    };
    let e2 = |q: Point3| Vector3::new(f_x(q.x, q.y, q.z), f_x(q.y, q.z, q.x), f_x(q.z, q.x, q.y));
    let (smooth, free) = (SmoothSolid::new(lame), DivergenceFreeSolid::new(lame));
    for x in interior_points() {
        let (a, b) = (smooth.body_force(x), e1(x));
        assert!(
            (a - b).norm() < 1e-12 * (1.0 + b.norm()),
            "E1-3D at {x}: {a} vs {b}"
        );
        let (a, b) = (free.body_force(x), e2(x));
        assert!(
            (a - b).norm() < 1e-12 * (1.0 + b.norm()),
            "E2-3D at {x}: {a} vs {b}"
        );
    }
}
