//! Frictionless contact in space (`D = 3`): a polyhedral body against a rigid plane or ball,
//! two bodies on matching and non-matching surfaces; every solver of the registry, against exact uniform
//! states, Hertz's theory, each other, a rotation of the whole problem, and the warnings.

use std::sync::Arc;

use nalgebra::{Matrix3, Rotation3};
use vem_contact::{
    ContactNormal, ContactProblem, ContactResult, Frictionless, Obstacle3, SolverRegistry, Warning,
};
use vem_elastic::{Component, Dirichlet, ElasticBody, Material};
use vem_mesh::generators::polyhedral::{hexahedra, tetrahedra, voronoi_polyhedra, Cuboid};
use vem_mesh::{Point3, PolyhedralMesh, Vector3};
use vem_space::{Options, PolyhedralVem};

const E: f64 = 200.0;
const NU: f64 = 0.3;

fn material(e: f64) -> Material {
    Material::isotropic(e, NU).unwrap()
}

fn element() -> Arc<PolyhedralVem> {
    Arc::new(PolyhedralVem::default())
}

/// Every solver of the registry, by name, with its default settings, and the condensed solver
/// with its interface forced to the iterative method (`"condensed-iterative"`; these problems'
/// interfaces are small, so the default chooses the dense one).
fn solvers() -> Vec<(String, Box<dyn vem_contact::ContactSolver>)> {
    let registry = SolverRegistry::builtin();
    let mut solvers: Vec<_> = registry
        .names()
        .into_iter()
        .map(|name| {
            (
                name.to_string(),
                registry.make(name, &Options::new()).unwrap(),
            )
        })
        .collect();
    solvers.push((
        "condensed-iterative".to_string(),
        registry
            .make("condensed", &Options::new().with("interface", "iterative"))
            .unwrap(),
    ));
    solvers
}

/// The tolerance on a nodal force, relative to the largest: the interior point's answer is
/// accurate to its own tolerance, the penalty's to its penetration, the others to round-off.
fn force_tolerance(solver: &str) -> f64 {
    match solver {
        "exact" => 1e-6,
        "penalty" => 1e-2,
        _ => 1e-10,
    }
}

fn assert_certified<const D: usize>(result: &ContactResult<D>, solver: &str) {
    // The residuals the solve recomputed from its answer, in the problem's own scales; the
    // penalty's answer penetrates by design (its own acceptance bounds the penetration).
    let r = &result.report.residuals;
    assert!(
        r.scales.force > 0.0 && r.scales.displacement > 0.0,
        "{solver}"
    );
    let penetration = if solver == "penalty" {
        0.0
    } else {
        r.max_penetration
    };
    for (what, value) in [
        ("stationarity", r.stationarity),
        ("penetration", penetration),
        ("negative force", r.negative_normal_force),
    ] {
        assert!(value < 1e-6, "{solver}: {what} {value:e}");
    }
}

/// A block `[0, 1]^2 x [z0, z0 + h]` whose bottom presses on the rigid plane z = 0: its top is
/// moved down by `d`, its sides x = 0 and y = 0 are symmetry planes.
fn block_on_plane(mesh: PolyhedralMesh, d: f64) -> ContactProblem<3> {
    let body = ElasticBody::builder_polyhedral("block", mesh, material(E), element())
        .dirichlet(Dirichlet::with_values("top", Component::Z, move |_| {
            Vector3::new(0.0, 0.0, -d)
        }))
        .dirichlet(Dirichlet::fixed("left", Component::X))
        .dirichlet(Dirichlet::fixed("front", Component::Y))
        .build()
        .unwrap();
    let plane = Obstacle3::Plane {
        point: Point3::origin(),
        normal: Vector3::z(),
    };
    ContactProblem::against_obstacle(body, "bottom", plane, Frictionless)
}

#[test]
fn a_block_pressed_on_a_plane_takes_the_exact_uniform_state_with_every_solver() {
    // Uniaxial stress: sigma_zz = -E d / h, the pressure on the plane E d / h, the lateral
    // expansion nu d / h. In the discrete space on any mesh: exact to round-off.
    let (d, h) = (0.01, 1.0);
    let pressure = E * d / h;
    let cube = Cuboid::unit_cube();
    for mesh in [
        hexahedra(&cube, 3, 3, 3).unwrap(),
        tetrahedra(&cube, 2, 2, 2).unwrap(),
    ] {
        let cells = mesh.n_cells();
        let problem = block_on_plane(mesh, d);
        for (name, mut solver) in solvers() {
            let result = problem.solve(&mut *solver).unwrap();
            assert_certified(&result, &name);
            let tol = force_tolerance(&name);
            let nodes = result.pair_nodes(0);
            assert!(!nodes.is_empty());
            for node in nodes {
                let exact = pressure * node.tributary_measure;
                assert!(
                    (node.normal_force - exact).abs() < tol * pressure,
                    "{name} ({cells} cells): {} vs {exact} at {:?}",
                    node.normal_force,
                    node.position
                );
                assert!((node.pressure - pressure).abs() < tol * pressure, "{name}");
                assert!(
                    (node.consistent_pressure - pressure).abs() < tol * pressure,
                    "{name}: consistent {}",
                    node.consistent_pressure
                );
                assert!(node.status.is_active());
                assert_eq!(node.normal, Vector3::new(0.0, 0.0, -1.0));
            }
            assert!((result.normal_resultant() - pressure).abs() < tol * pressure);
            let body = &result.bodies[0];
            for (v, x) in body.body.mesh().vertices().iter().enumerate() {
                let u = body.solution.vertex_displacement(v);
                let exact = Vector3::new(NU * d * x.x / h, NU * d * x.y / h, -d * x.z / h);
                assert!((u - exact).norm() < tol * d, "{name}: {u} vs {exact}");
            }
            // The plane's force balances the top's reaction.
            let top = body.solution.reaction("top").unwrap();
            assert!((top.z + pressure).abs() < tol * pressure, "{name}: {top}");
            // The whole part touches, with a uniform pressure on a box side: a model
            // without anything to warn about.
            assert!(result.warnings.is_empty(), "{name}: {:?}", result.warnings);
        }
    }
}

/// A block `[-1, 1]^2 x [-1, 0]` clamped at its bottom, which is moved up by `lift`, against
/// a rigid ball of radius `r` resting on the top's centre (its centre at (0, 0, r + gap)).
fn block_under_ball(mesh: PolyhedralMesh, lift: f64, r: f64, gap: f64) -> ContactProblem<3> {
    let body = ElasticBody::builder_polyhedral("block", mesh, material(E), element())
        .dirichlet(Dirichlet::with_values(
            "bottom",
            Component::All,
            move |_| Vector3::new(0.0, 0.0, lift),
        ))
        .build()
        .unwrap();
    let ball = Obstacle3::Sphere {
        centre: Point3::new(0.0, 0.0, r + gap),
        radius: r,
    };
    ContactProblem::against_obstacle(body, "top", ball, Frictionless)
}

/// The ball of the tests below and how far the block is lifted into it: about nine nodes in
/// contact on the block's 8 x 8 top.
const BALL_RADIUS: f64 = 2.0;
const BALL_LIFT: f64 = 0.1;

fn ball_block() -> PolyhedralMesh {
    let block = Cuboid::new(Point3::new(-1.0, -1.0, -1.0), Point3::new(1.0, 1.0, 0.0));
    hexahedra(&block, 8, 8, 4).unwrap()
}

#[test]
fn every_solver_agrees_on_a_ball_pressed_into_a_block() {
    let problem = block_under_ball(ball_block(), BALL_LIFT, BALL_RADIUS, 0.0);
    let mut answers: Vec<(String, Vec<f64>)> = Vec::new();
    for (name, mut solver) in solvers() {
        let result = problem.solve(&mut *solver).unwrap();
        assert_certified(&result, &name);
        // The clamp carries the contact force: equilibrium of the body.
        let reaction = result.bodies[0].solution.reaction("bottom").unwrap();
        let contact = result.force_on_body(0);
        assert!(
            (reaction + contact).norm() < 1e-8 * contact.norm(),
            "{name}: {reaction} + {contact}"
        );
        // Frictionless: the forces act along the ball's normals, through its centre.
        let active = result.status_counts().active();
        assert!(active > 4 && active < 81, "{name}: {active}");
        answers.push((name, result.nodes.iter().map(|n| n.normal_force).collect()));
    }
    let reference = answers
        .iter()
        .find(|(n, _)| n == "condensed")
        .unwrap()
        .1
        .clone();
    let scale = reference.iter().fold(0.0f64, |a, f| a.max(*f));
    for (name, forces) in &answers {
        let tol = force_tolerance(name).max(1e-9);
        for (a, b) in forces.iter().zip(&reference) {
            assert!((a - b).abs() < tol * scale, "{name}: {a} vs {b}");
        }
    }
}

/// `mesh` with every vertex mapped by `map` (same cells, faces and parts).
fn mapped(mesh: &PolyhedralMesh, map: impl Fn(Point3) -> Point3) -> PolyhedralMesh {
    PolyhedralMesh::from_compact(
        mesh.vertices().iter().map(|&p| map(p)).collect(),
        mesh.face_offsets().to_vec(),
        mesh.face_vertex_indices().to_vec(),
        mesh.cell_offsets().to_vec(),
        mesh.cell_face_indices().to_vec(),
        mesh.parts().to_vec(),
    )
    .unwrap()
}

#[test]
fn a_rotation_of_the_whole_problem_rotates_the_answer_whatever_the_tangents() {
    // The ball problem turned by a rotation R: the nodes' tangent bases are not the turned
    // ones (the frame is built from each normal alone), yet the forces are the same node by
    // node and the displacements turned: the answer does not depend on the tangents.
    let rotation = Rotation3::from_euler_angles(0.4, -0.7, 1.1);
    let r: Matrix3<f64> = *rotation.matrix();
    let (lift, radius) = (BALL_LIFT, BALL_RADIUS);
    let straight = block_under_ball(ball_block(), lift, radius, 0.0);
    let turned_mesh = mapped(&ball_block(), |p| rotation * p);
    let body = ElasticBody::builder_polyhedral("block", turned_mesh, material(E), element())
        .dirichlet(Dirichlet::with_values(
            "bottom",
            Component::All,
            move |_| r * Vector3::new(0.0, 0.0, lift),
        ))
        .build()
        .unwrap();
    let ball = Obstacle3::Sphere {
        centre: rotation * Point3::new(0.0, 0.0, radius),
        radius,
    };
    let turned = ContactProblem::against_obstacle(body, "top", ball, Frictionless);
    for name in ["condensed", "active-set"] {
        let mut solver = SolverRegistry::builtin()
            .make(name, &Options::new())
            .unwrap();
        let a = straight.solve(&mut *solver).unwrap();
        let b = turned.solve(&mut *solver).unwrap();
        let scale = a.nodes.iter().fold(0.0f64, |m, n| m.max(n.normal_force));
        let mut turned_tangents = 0;
        for (x, y) in a.nodes.iter().zip(&b.nodes) {
            assert_eq!(x.vertex_a, y.vertex_a);
            assert!(
                (x.normal_force - y.normal_force).abs() < 1e-10 * scale,
                "{name}"
            );
            assert!((r * x.normal - y.normal).norm() < 1e-12);
            // Two orthonormal tangents per node, orthogonal to the normal.
            let f = y.frame();
            assert!((f.transpose() * f - Matrix3::identity()).norm() < 1e-14);
            let (t1, t1_turned) = (r * x.frame().column(1), f.column(1));
            if (t1 - t1_turned).norm() > 1e-3 {
                turned_tangents += 1;
            }
        }
        assert!(turned_tangents > 0, "the test must turn some tangent basis");
        let (ua, ub) = (&a.bodies[0].solution, &b.bodies[0].solution);
        for v in 0..a.bodies[0].body.mesh().n_vertices() {
            let diff = r * ua.vertex_displacement(v) - ub.vertex_displacement(v);
            assert!(diff.norm() < 1e-10 * lift, "{name}: {diff}");
        }
    }
}

/// Coordinates from 0 to `length`: cells of size `h` up to `fine`, then growing by 1.25 (the
/// last cell shortened to end at `length`, merged with the one before if too short).
fn graded(h: f64, fine: f64, length: f64) -> Vec<f64> {
    let mut x = vec![0.0];
    let mut step = h;
    while *x.last().unwrap() < length - 1e-12 {
        let last = *x.last().unwrap();
        if last >= fine - 1e-12 {
            step *= 1.25;
        }
        x.push((last + step).min(length));
    }
    let n = x.len();
    if n > 2 && x[n - 1] - x[n - 2] < 0.5 * step {
        x.remove(n - 2);
    }
    x
}

#[test]
fn hertz_with_force_control_carries_the_load_and_is_near_the_theory() {
    // A quarter of the block [0, 1]^2 x [-1, 0] (symmetry planes x = 0 and y = 0) under a
    // rigid ball of radius 1 touching the top at the origin; the bottom is a rigid plate pushed
    // up with P/4, P such that Hertz's contact radius is a = 0.1. Hexahedra of size a/4 on
    // [0, 1.5 a] in every direction, growing by 1.25 beyond (3375 cells). The contact forces
    // carry the load to round-off; the peak pressure and the contact radius (from the fit of
    // p^2 = p0^2 (1 - r^2/a^2) near the axis) are within 2.5 % of Hertz's (measured 2.0 % and
    // 0.6 %; docs/contact-3d.md has the finer meshes).
    let (radius, a) = (1.0, 0.1);
    let e_star = E / (1.0 - NU * NU);
    let load = 4.0 * e_star * a * a * a / (3.0 * radius);
    let p0 = 3.0 * load / (2.0 * std::f64::consts::PI * a * a);
    let xs = graded(a / 4.0, 1.5 * a, 1.0);
    let n = xs.len() - 1;
    let index = |s: f64| (s * n as f64).round() as usize;
    let mesh = mapped(&hexahedra(&Cuboid::unit_cube(), n, n, n).unwrap(), |p| {
        Point3::new(xs[index(p.x)], xs[index(p.y)], -xs[n - index(p.z)])
    });
    let body = ElasticBody::builder_polyhedral("block", mesh, material(E), element())
        .dirichlet(Dirichlet::rigid_plate(
            "bottom",
            Component::Z,
            Vector3::new(0.0, 0.0, load / 4.0),
        ))
        .dirichlet(Dirichlet::fixed("left", Component::X))
        .dirichlet(Dirichlet::fixed("front", Component::Y))
        .build()
        .unwrap();
    let ball = Obstacle3::Sphere {
        centre: Point3::new(0.0, 0.0, radius),
        radius,
    };
    let problem = ContactProblem::against_obstacle(body, "top", ball, Frictionless);
    let result = problem
        .solve(
            &mut *SolverRegistry::builtin()
                .make("condensed", &Options::new())
                .unwrap(),
        )
        .unwrap();
    assert_certified(&result, "condensed");
    // The nodal forces act along the ball's normals: their vertical sum is the load.
    let carried = -result.force_on_body(0).z;
    assert!(
        (carried - load / 4.0).abs() < 1e-8 * load,
        "{carried} vs {}",
        load / 4.0
    );
    let r = |n: &vem_contact::InterfaceNode<3>| n.position.x.hypot(n.position.y);
    let centre = result.nodes.iter().find(|n| r(n) < 1e-12).unwrap();
    assert!(
        (centre.consistent_pressure - p0).abs() < 0.025 * p0,
        "p(0) = {} vs {p0}",
        centre.consistent_pressure
    );
    let (mut s1, mut sx, mut sy, mut sxx, mut sxy) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for node in result.nodes.iter().filter(|node| r(node) < 0.7 * a) {
        let (x, y) = (r(node).powi(2), node.consistent_pressure.powi(2));
        s1 += 1.0;
        sx += x;
        sy += y;
        sxx += x * x;
        sxy += x * y;
    }
    let slope = (s1 * sxy - sx * sy) / (s1 * sxx - sx * sx);
    let intercept = (sy - slope * sx) / s1;
    let a_fit = (-intercept / slope).sqrt();
    assert!((a_fit - a).abs() < 0.025 * a, "a = {a_fit} vs {a}");
    // No node beyond a cell of the contact radius is in contact.
    assert!(result
        .nodes
        .iter()
        .filter(|node| node.status.is_active())
        .all(|node| r(node) < a + a / 4.0));
}

fn stacked_blocks(
    upper: PolyhedralMesh,
    lower: PolyhedralMesh,
    d: f64,
    e_upper: f64,
    e_lower: f64,
) -> ContactProblem<3> {
    let sides = |b: vem_elastic::ElasticBodyBuilder<3>| {
        b.dirichlet(Dirichlet::fixed("left", Component::X))
            .dirichlet(Dirichlet::fixed("front", Component::Y))
    };
    let upper = sides(
        ElasticBody::builder_polyhedral("upper", upper, material(e_upper), element()).dirichlet(
            Dirichlet::with_values("top", Component::Z, move |_| Vector3::new(0.0, 0.0, -d)),
        ),
    )
    .build()
    .unwrap();
    let lower = sides(
        ElasticBody::builder_polyhedral("lower", lower, material(e_lower), element())
            .dirichlet(Dirichlet::fixed("bottom", Component::Z)),
    )
    .build()
    .unwrap();
    ContactProblem::two_bodies(upper, "bottom", lower, "top", Frictionless)
}

#[test]
fn the_contact_patch_test_of_two_stacked_blocks_is_exact_on_matching_and_non_matching_surfaces() {
    // Two blocks, one on the other, of different stiffness: the uniform uniaxial stress
    // sigma_zz = -d / (h1 / E1 + h2 / E2) is transmitted through the interface node by node, to
    // round-off, by every solver, for every normal choice: on the same lateral grid, and on
    // non-matching surfaces made node-to-node by the surface overlay (hexahedra on tetrahedra,
    // Voronoi cells on hexahedra, size ratios 1:1 to 1:5).
    let (d, e1, e2) = (0.01, 100.0, 300.0);
    let upper_box = Cuboid::new(Point3::new(0.0, 0.0, 0.0), Point3::new(1.0, 1.0, 1.0));
    let lower_box = Cuboid::new(Point3::new(0.0, 0.0, -0.5), Point3::new(1.0, 1.0, 0.0));
    let pressure = d / (1.0 / e1 + 0.5 / e2);
    let pairs: [(&str, PolyhedralMesh, PolyhedralMesh); 6] = [
        (
            "hexahedra",
            hexahedra(&upper_box, 3, 3, 2).unwrap(),
            hexahedra(&lower_box, 3, 3, 3).unwrap(),
        ),
        (
            "tetrahedra",
            tetrahedra(&upper_box, 2, 2, 2).unwrap(),
            tetrahedra(&lower_box, 2, 2, 1).unwrap(),
        ),
        (
            "hexahedra 3 x 3 on hexahedra 4 x 4",
            hexahedra(&upper_box, 3, 3, 2).unwrap(),
            hexahedra(&lower_box, 4, 4, 2).unwrap(),
        ),
        (
            "hexahedra on tetrahedra",
            hexahedra(&upper_box, 3, 3, 2).unwrap(),
            tetrahedra(&lower_box, 2, 2, 1).unwrap(),
        ),
        (
            "voronoi on hexahedra",
            voronoi_polyhedra(&upper_box, 3, 1).unwrap(),
            hexahedra(&lower_box, 4, 4, 2).unwrap(),
        ),
        (
            "hexahedra 1 x 1 on hexahedra 5 x 5 (1:5)",
            hexahedra(&upper_box, 1, 1, 1).unwrap(),
            hexahedra(&lower_box, 5, 5, 1).unwrap(),
        ),
    ];
    for (family, upper, lower) in pairs {
        for normal in ContactNormal::ALL {
            let problem =
                stacked_blocks(upper.clone(), lower.clone(), d, e1, e2).with_normal(normal);
            for (name, mut solver) in solvers() {
                let result = problem.solve(&mut *solver).unwrap();
                assert_certified(&result, &name);
                let tol = force_tolerance(&name);
                let nodes = result.pair_nodes(0);
                match family {
                    "hexahedra" => assert_eq!(nodes.len(), 16),
                    "tetrahedra" => assert_eq!(nodes.len(), 9),
                    // Every vertex of either side's surface is an interface node.
                    _ => assert!(nodes.len() > upper.part_vertices("bottom").unwrap().len()),
                }
                let area: f64 = nodes.iter().map(|n| n.tributary_measure).sum();
                assert!((area - 1.0).abs() < 1e-12, "{family}: area {area}");
                for node in nodes {
                    let exact = pressure * node.tributary_measure;
                    assert!(
                        (node.normal_force - exact).abs() < tol * pressure,
                        "{family} {normal:?} {name}: {} vs {exact}",
                        node.normal_force
                    );
                    assert!((node.consistent_pressure - pressure).abs() < tol * pressure);
                }
                assert!((result.normal_resultant() - pressure).abs() < tol * pressure);
                for (k, body) in result.bodies.iter().enumerate() {
                    for (v, x) in body.body.mesh().vertices().iter().enumerate() {
                        let u = body.solution.vertex_displacement(v);
                        let e = if k == 0 { e1 } else { e2 };
                        let strain = -pressure / e;
                        let uz = if k == 0 {
                            -0.5 * pressure / e2 + strain * x.z
                        } else {
                            strain * (x.z + 0.5)
                        };
                        let exact = Vector3::new(-NU * strain * x.x, -NU * strain * x.y, uz);
                        assert!(
                            (u - exact).norm() < tol * d,
                            "{family} {name} body {k}: {u} vs {exact}"
                        );
                    }
                }
                // The penalty solver answers the penalised problem: its penetration may be
                // reported (1:5, where the coarse side's node carries a large area).
                let warnings: Vec<&Warning> = result
                    .warnings
                    .iter()
                    .filter(|w| !(name == "penalty" && matches!(w, Warning::Penetration { .. })))
                    .collect();
                assert!(warnings.is_empty(), "{family}: {warnings:?}");
            }
        }
    }
}

#[test]
fn two_blocks_apart_by_a_gap_close_it_first() {
    // The upper block starts 0.002 above the lower one: the gap is closed, then the rest of
    // the push compresses the blocks uniformly.
    let (d, gap, e) = (0.01, 0.002, 100.0);
    let upper_box = Cuboid::new(Point3::new(0.0, 0.0, gap), Point3::new(1.0, 1.0, 1.0 + gap));
    let lower_box = Cuboid::new(Point3::new(0.0, 0.0, -1.0), Point3::new(1.0, 1.0, 0.0));
    let problem = stacked_blocks(
        hexahedra(&upper_box, 2, 2, 2).unwrap(),
        hexahedra(&lower_box, 2, 2, 2).unwrap(),
        d,
        e,
        e,
    );
    let result = problem
        .solve(
            &mut *SolverRegistry::builtin()
                .make("condensed", &Options::new())
                .unwrap(),
        )
        .unwrap();
    let pressure = e * (d - gap) / 2.0;
    for node in result.pair_nodes(0) {
        assert!((node.initial_gap - gap).abs() < 1e-15);
        assert!((node.pressure - pressure).abs() < 1e-10 * pressure);
    }
}

#[test]
fn the_warnings_of_the_plane_apply_in_space() {
    let block = Cuboid::new(Point3::new(-1.0, -1.0, -1.0), Point3::new(1.0, 1.0, 0.0));
    let mesh = || hexahedra(&block, 4, 4, 2).unwrap();
    let mut solver = SolverRegistry::builtin()
        .make("condensed", &Options::new())
        .unwrap();
    let has =
        |result: &ContactResult<3>, kind: fn(&Warning) -> bool| result.warnings.iter().any(kind);
    // The ball far above: no node in contact.
    let far = block_under_ball(mesh(), 0.01, 1.0, 0.5)
        .solve(&mut *solver)
        .unwrap();
    assert!(
        has(&far, |w| matches!(w, Warning::NoContact { .. })),
        "{:?}",
        far.warnings
    );
    // The ball just touching the centre node: one node carries the load.
    let point = block_under_ball(mesh(), 1e-4, 1.0, 0.0)
        .solve(&mut *solver)
        .unwrap();
    assert!(
        has(&point, |w| matches!(
            w,
            Warning::ConcentratedPressure { .. }
        )),
        "{:?}",
        point.warnings
    );
    // The ball sunk into the block at the start: an initial overlap.
    let sunk = block_under_ball(mesh(), 0.0, 1.0, -0.05)
        .solve(&mut *solver)
        .unwrap();
    assert!(
        has(&sunk, |w| matches!(w, Warning::InitialOverlap { .. })),
        "{:?}",
        sunk.warnings
    );
    // A plane pressing the whole top of a part that is a patch of the block's top: the zone
    // reaches the part's rim where the body goes on.
    let m = mesh();
    let top = m.part_faces("top").unwrap().to_vec();
    let (inner, outer): (Vec<usize>, Vec<usize>) = top.iter().partition(|&&f| {
        let c = m.face_centroid(f);
        c.x.abs() < 0.5 && c.y.abs() < 0.5
    });
    let mut parts: Vec<vem_mesh::FacePart> = m
        .parts()
        .iter()
        .filter(|p| p.name != "top")
        .cloned()
        .collect();
    parts.push(vem_mesh::FacePart::new("patch", inner));
    parts.push(vem_mesh::FacePart::new("rest", outer));
    let m = m.with_parts(parts).unwrap();
    let body = ElasticBody::builder_polyhedral("block", m, material(E), element())
        .dirichlet(Dirichlet::with_values("bottom", Component::All, |_| {
            Vector3::new(0.0, 0.0, 0.01)
        }))
        .build()
        .unwrap();
    let plane = Obstacle3::Plane {
        point: Point3::origin(),
        normal: Vector3::new(0.0, 0.0, -1.0),
    };
    let patch = ContactProblem::against_obstacle(body, "patch", plane, Frictionless)
        .solve(&mut *solver)
        .unwrap();
    let limits: Vec<&Warning> = patch
        .warnings
        .iter()
        .filter(|w| matches!(w, Warning::ContactZoneAtLimit { .. }))
        .collect();
    assert_eq!(limits.len(), 1, "{:?}", patch.warnings);
}

#[test]
fn a_small_block_on_a_larger_one_pairs_only_its_own_nodes() {
    // A punch [0, 0.5]^2 x [0, 0.5] (2 x 2 x 2 hexahedra) on a block [0, 1]^2 x [-1, 0]
    // (4 x 4 x 4): the punch's bottom vertices lie on the block's top grid; the block's other
    // top vertices are not interface nodes. The contact forces balance the punch's push, the
    // punch's edges are convex corners (no zone cut short), and every solver agrees.
    let punch = hexahedra(
        &Cuboid::new(Point3::new(0.0, 0.0, 0.0), Point3::new(0.5, 0.5, 0.5)),
        2,
        2,
        2,
    )
    .unwrap();
    let block = hexahedra(
        &Cuboid::new(Point3::new(0.0, 0.0, -1.0), Point3::new(1.0, 1.0, 0.0)),
        4,
        4,
        4,
    )
    .unwrap();
    let problem = stacked_blocks(punch, block, 0.01, E, E);
    let mut reference: Option<Vec<f64>> = None;
    for (name, mut solver) in solvers() {
        let result = problem.solve(&mut *solver).unwrap();
        assert_certified(&result, &name);
        assert_eq!(result.nodes.len(), 9);
        let push = result.bodies[0].solution.reaction("top").unwrap();
        let carried = result.normal_resultant();
        assert!(
            (push.z + carried).abs() < 1e-8 * carried,
            "{name}: {push} {carried}"
        );
        assert!(
            !result
                .warnings
                .iter()
                .any(|w| matches!(w, Warning::ContactZoneAtLimit { .. })),
            "{name}: {:?}",
            result.warnings
        );
        let forces: Vec<f64> = result.nodes.iter().map(|n| n.normal_force).collect();
        match &reference {
            None => reference = Some(forces),
            Some(r) => {
                for (a, b) in forces.iter().zip(r) {
                    assert!((a - b).abs() < force_tolerance(&name) * carried, "{name}");
                }
            }
        }
    }
}

#[test]
fn a_sliver_cell_is_reported_in_space() {
    // One layer of cells 1e-8 thin under the contact part: far outside A1.
    let base = hexahedra(&Cuboid::unit_cube(), 3, 3, 3).unwrap();
    let mesh = mapped(&base, |p| {
        let z = if (p.z - 1.0 / 3.0).abs() < 1e-12 {
            1e-8
        } else {
            p.z
        };
        Point3::new(p.x, p.y, z)
    });
    let result = block_on_plane(mesh, 0.01)
        .solve(
            &mut *SolverRegistry::builtin()
                .make("condensed", &Options::new())
                .unwrap(),
        )
        .unwrap();
    let shapes = result
        .warnings
        .iter()
        .filter(|w| matches!(w, Warning::ElementShape { .. }))
        .count();
    // The five worst of the nine sliver cells.
    assert_eq!(shapes, 5, "{:?}", result.warnings);
}

#[test]
fn every_solver_passes_an_independent_kkt_check_in_the_problems_scales() {
    // The ball problem's system solved directly; the KKT conditions recomputed here from the
    // system and the answer alone, relative to the problem's own force scale
    // F = max(|f|, |K u|, |B' lambda|) and displacement scale U = max(|u|, |g|).
    let discretisation = block_under_ball(ball_block(), BALL_LIFT, BALL_RADIUS, 0.0)
        .discretise()
        .unwrap();
    let system = discretisation.system();
    let inf = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    for (name, mut solver) in solvers() {
        let answer = solver.solve(&system).unwrap();
        assert_eq!(
            answer.report.status,
            vem_contact::SolveStatus::Converged,
            "{name}"
        );
        let (u, lambda) = (&answer.displacement, &answer.normal_force);
        let ku = system.stiffness_apply(u);
        let mut bt_lambda = vec![0.0; u.len()];
        system
            .normal_rows()
            .add_transpose_apply(lambda, &mut bt_lambda);
        let f = system.load();
        let force = inf(f).max(inf(&ku)).max(inf(&bt_lambda));
        let residual: Vec<f64> = (0..u.len()).map(|i| ku[i] - f[i] + bt_lambda[i]).collect();
        let gap = system.gap();
        let jump = system.normal_rows().apply(u);
        let displacement = inf(u).max(inf(gap));
        let penetration = jump.iter().zip(gap).fold(0.0f64, |m, (j, g)| m.max(j - g));
        let complementarity = lambda
            .iter()
            .zip(jump.iter().zip(gap))
            .fold(0.0f64, |m, (l, (j, g))| m.max((l * (g - j)).abs()));
        let negative = lambda.iter().fold(0.0f64, |m, l| m.max(-l));
        let (stat_tol, feas_tol, comp_tol) = match name.as_str() {
            "exact" => (1e-8, 1e-8, 1e-6),
            "penalty" => (1e-8, 1e-2, 1e-2),
            _ => (1e-10, 1e-10, 1e-10),
        };
        assert!(inf(&residual) < stat_tol * force, "{name}: stationarity");
        assert!(penetration < feas_tol * displacement, "{name}: penetration");
        assert!(negative < 1e-12 * force, "{name}: tension");
        assert!(
            complementarity < comp_tol * force * displacement,
            "{name}: complementarity"
        );
        // The solver's own report says the same in the same scales.
        let own = vem_contact::KktResiduals::evaluate(&system, u, lambda, &answer.tangential_force);
        assert!((own.stationarity - answer.report.residuals.stationarity).abs() < 1e-12);
        assert!(lambda.iter().filter(|&&l| l > 0.0).count() > 4, "{name}");
    }
}
