//! Friction in space (`D = 3`): the nodal friction force is a vector of the tangent plane and
//! Tresca's bound a disk `|lambda_T| <= g_F l_x`. Every solver of the registry against the
//! interior point's second-order cones (the oracle) on problems with stick and slip zones, the
//! independence of the tangent basis, a rigid block held sideways by Coulomb friction below
//! its capacity and refused beyond it (two elastic blocks too, Cattaneo-Mindlin's among them),
//! and uniform sliding (`Q / P = F`).

use std::sync::Arc;

use faer::sparse::{SparseColMat, Triplet};
use vem_contact::{
    CondensedSettings, CondensedSolver, ConstraintRows, ContactError, ContactLaw, ContactPair,
    ContactProblem, ContactResult, ContactSolver, ContactSystem, Coulomb, Friction, Frictionless,
    InterfaceMethod, KktResiduals, Obstacle3, PenaltyParameter, PenaltySettings, PenaltySolver,
    SolverRegistry, Tresca,
};
use vem_elastic::{Component, Dirichlet, ElasticBody, Material};
use vem_mesh::generators::polyhedral::{hexahedra, Cuboid};
use vem_mesh::{Point3, PolyhedralMesh, Vector3};
use vem_space::{Options, PolyhedralVem};

const E: f64 = 200.0;
const NU: f64 = 0.3;

fn material() -> Material {
    Material::isotropic(E, NU).unwrap()
}

/// Without lateral contraction: a block pressed and sheared uniformly takes a uniform state.
fn material_without_poisson() -> Material {
    Material::isotropic(E, 0.0).unwrap()
}

fn element() -> Arc<PolyhedralVem> {
    Arc::new(PolyhedralVem::default())
}

/// Every solver of the registry, by name, with its default settings.
/// The condensed solver with its interface forced to the iterative method is listed as
/// `"condensed-iterative"` (these problems' interfaces are small: the default is dense).
fn solvers() -> Vec<(String, Box<dyn ContactSolver>)> {
    let registry = SolverRegistry::builtin();
    let mut names = registry.names();
    // The regularised answer last.
    names.sort_by_key(|&name| name == "penalty");
    let mut solvers: Vec<_> = names
        .into_iter()
        .map(|name| {
            (
                name.to_string(),
                registry.make(name, &Options::new()).unwrap(),
            )
        })
        .collect();
    solvers.insert(
        1,
        (
            "condensed-iterative".to_string(),
            registry
                .make("condensed", &Options::new().with("interface", "iterative"))
                .unwrap(),
        ),
    );
    solvers
}

fn cube(min: [f64; 3], max: [f64; 3], n: [usize; 3]) -> PolyhedralMesh {
    let cuboid = Cuboid::new(
        Point3::new(min[0], min[1], min[2]),
        Point3::new(max[0], max[1], max[2]),
    );
    hexahedra(&cuboid, n[0], n[1], n[2]).unwrap()
}

/// The top moved by `(sx, sy, -d)`: pressed and sheared obliquely.
const PRESS: f64 = 0.01;
const SHEAR: [f64; 2] = [0.004, 0.0025];

/// A block `[0, 1]^2 x [0, 1/2]` on the rigid plane z = 0, its top moved by the press and the
/// shear (no rigid motion left).
fn block_on_plane(law: impl ContactLaw<3> + 'static, shear: [f64; 2]) -> ContactProblem<3> {
    block_of(law, shear, material())
}

fn block_of(
    law: impl ContactLaw<3> + 'static,
    shear: [f64; 2],
    material: Material,
) -> ContactProblem<3> {
    let body = ElasticBody::builder_polyhedral(
        "block",
        cube([0.0; 3], [1.0, 1.0, 0.5], [4, 4, 2]),
        material,
        element(),
    )
    .dirichlet(Dirichlet::with_values("top", Component::All, move |_| {
        Vector3::new(shear[0], shear[1], -PRESS)
    }))
    .build()
    .unwrap();
    let plane = Obstacle3::Plane {
        point: Point3::origin(),
        normal: Vector3::z(),
    };
    ContactProblem::against_obstacle(body, "bottom", plane, law)
}

/// Two blocks on non-matching grids (4 x 4 on 3 x 3 cells across the interface z = 0): the
/// lower one clamped at its bottom, the upper one's top moved by the press and the shear.
fn stacked_blocks(law: impl ContactLaw<3> + 'static) -> ContactProblem<3> {
    let upper = ElasticBody::builder_polyhedral(
        "upper",
        cube([0.0, 0.0, 0.0], [1.0, 1.0, 0.5], [4, 4, 2]),
        material(),
        element(),
    )
    .dirichlet(Dirichlet::with_values("top", Component::All, move |_| {
        Vector3::new(SHEAR[0], SHEAR[1], -PRESS)
    }))
    .build()
    .unwrap();
    let lower = ElasticBody::builder_polyhedral(
        "lower",
        cube([0.0, 0.0, -0.5], [1.0, 1.0, 0.0], [3, 3, 2]),
        material(),
        element(),
    )
    .clamp("bottom")
    .build()
    .unwrap();
    ContactProblem::two_bodies(upper, "bottom", lower, "top", law)
}

/// A bound that grows across the interface: the nodes at small `x + y` slip, the others stick.
fn variable_tresca() -> Tresca<3> {
    Tresca::with_field(|p: Point3| 0.05 + 0.4 * (p.x + p.y))
}

/// The same for the block on the plane, whose friction traction is larger.
fn steep_tresca() -> Tresca<3> {
    Tresca::with_field(|p: Point3| 0.1 + 1.5 * (p.x + p.y))
}

/// The tangential part of a vector at a node of normal `n`.
fn norm(v: Vector3) -> f64 {
    v.norm()
}

/// Stick and slip nodes of a result (slip: friction at the bound to 1e-6).
fn stick_and_slip(result: &ContactResult<3>) -> (usize, usize) {
    let counts = result.status_counts();
    (counts.stick, counts.slip)
}

/// The solvers of problems with stick and slip zones in space: every solver of the registry
/// (the condensed solver's disk QP, the interior point's second-order cones, the active-set
/// and penalty solvers' Newton steps with the linearised radial return of the sliding nodes).
fn mixed_solvers() -> Vec<(String, Box<dyn ContactSolver>)> {
    solvers()
}

/// Every solver's answer against the interior point's: nodal normal forces and friction
/// vectors to `tolerance` of the largest normal force, displacements to `tolerance` of the
/// largest; the solver's own certificate passed.
fn agree_with_the_oracle(problem: &ContactProblem<3>, tolerance: f64) {
    let oracle = problem
        .solve(&mut vem_contact::ExactSolver::default())
        .unwrap();
    let (stick, slip) = stick_and_slip(&oracle);
    assert!(stick > 0 && slip > 0, "stick {stick}, slip {slip}");
    let force_scale = oracle
        .nodes
        .iter()
        .fold(0.0f64, |m, n| m.max(n.normal_force));
    let u_scale = oracle.bodies.iter().fold(0.0f64, |m, b| {
        (0..b.body.mesh().n_vertices())
            .fold(m, |m, v| m.max(b.solution.vertex_displacement(v).norm()))
    });
    for (name, mut solver) in mixed_solvers() {
        let result = problem
            .solve(&mut *solver)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let r = &result.report.residuals;
        assert!(
            r.friction_bound_violation < 1e-6 && r.stationarity < 1e-6,
            "{name}: {r:?}"
        );
        let tol = if name == "penalty" { 1e-2 } else { tolerance };
        let mut largest = [0.0f64; 3];
        for (a, b) in result.nodes.iter().zip(&oracle.nodes) {
            assert!((a.position - b.position).norm() < 1e-14);
            largest[0] = largest[0].max((a.normal_force - b.normal_force).abs() / force_scale);
            largest[1] = largest[1].max(norm(a.friction_force - b.friction_force) / force_scale);
            // The disk: |friction| <= bound.
            assert!(
                norm(a.friction_force) <= a.friction_bound * (1.0 + 1e-9) + 1e-12 * force_scale,
                "{name}: |friction| {} > bound {}",
                norm(a.friction_force),
                a.friction_bound
            );
        }
        for (a, b) in result.bodies.iter().zip(&oracle.bodies) {
            for v in 0..a.body.mesh().n_vertices() {
                let du = a.solution.vertex_displacement(v) - b.solution.vertex_displacement(v);
                largest[2] = largest[2].max(du.norm() / u_scale);
            }
        }
        println!(
            "{name}: normal {:.1e}, friction {:.1e}, displacement {:.1e} (of the largest), \
             {} iterations, stick/slip {:?}",
            largest[0],
            largest[1],
            largest[2],
            result.report.iterations,
            stick_and_slip(&result)
        );
        for (what, value) in ["normal force", "friction force", "displacement"]
            .iter()
            .zip(largest)
        {
            assert!(value < tol, "{name}: {what} differs by {value:e}");
        }
    }
}

#[test]
fn every_solver_agrees_with_the_second_order_cones_on_a_block_sheared_on_a_plane() {
    agree_with_the_oracle(&block_on_plane(steep_tresca(), SHEAR), 1e-3);
}

#[test]
fn every_solver_agrees_with_the_second_order_cones_on_two_non_matching_blocks() {
    agree_with_the_oracle(&stacked_blocks(variable_tresca()), 1e-3);
}

/// The system `system` with the tangent pair of node `i` turned by the angle `angles[i]`
/// (rows `(t1, t2) -> (c t1 + s t2, -s t1 + c t2)`), as an owned system.
fn turned(system: &ContactSystem<'_>, angles: &[f64]) -> ContactSystem<'static> {
    let n = system.n_dofs();
    let entries: Vec<Triplet<usize, usize, f64>> = system
        .stiffness_entries()
        .map(|(i, j, v)| Triplet::new(i, j, v))
        .collect();
    let stiffness = SparseColMat::try_new_from_triplets(n, n, &entries).unwrap();
    let friction = system.friction().unwrap();
    let rows = friction.tangential_rows();
    let mut triplets = Vec::new();
    for (i, angle) in angles.iter().enumerate() {
        let (s, c) = angle.sin_cos();
        for (k, (a, b)) in [(c, s), (-s, c)].into_iter().enumerate() {
            for (row, coefficient) in [(2 * i, a), (2 * i + 1, b)] {
                let (cols, vals) = rows.row(row);
                for (&col, &v) in cols.iter().zip(vals) {
                    triplets.push((2 * i + k, col, coefficient * v));
                }
            }
        }
    }
    let turned_rows = ConstraintRows::try_from_triplets(rows.nrows(), n, &triplets).unwrap();
    let friction =
        Friction::try_with_rows_per_node(turned_rows, friction.bounds().to_vec(), 2).unwrap();
    ContactSystem::try_new(
        stiffness,
        system.load().to_vec(),
        system.normal_rows().clone(),
        system.gap().to_vec(),
        Some(friction),
    )
    .unwrap()
}

#[test]
fn the_answer_does_not_depend_on_the_tangent_basis() {
    // Every node's tangent pair turned by its own angle: the same problem, so the same
    // displacement (to round-off with the solvers that solve it exactly) and the same
    // certificate.
    for problem in [
        block_on_plane(steep_tresca(), SHEAR),
        stacked_blocks(variable_tresca()),
    ] {
        let discretisation = problem.discretise().unwrap();
        let system = discretisation.system();
        let mut seed = 3u64;
        let angles: Vec<f64> = (0..system.n_constraints())
            .map(|_| {
                seed = seed
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                (seed >> 11) as f64 / (1u64 << 53) as f64 * std::f64::consts::TAU
            })
            .collect();
        let turned = turned(&system, &angles);
        for (name, mut solver) in mixed_solvers() {
            if name == "penalty" {
                // The default penalty is relative to the stiffness of the unknowns the rows
                // touch, which turning the rows changes: the same absolute penalty for both
                // (the same penalised problem).
                let penalty = PenaltyParameter::Absolute(
                    PenaltySettings::default().normal_penalty().value(&system),
                );
                let settings = PenaltySettings::builder().penalty(penalty).build().unwrap();
                solver = Box::new(PenaltySolver::new(settings));
            }
            let a = solver
                .solve(&system)
                .unwrap_or_else(|e| panic!("{name}: {e}"));
            let b = solver
                .solve(&turned)
                .unwrap_or_else(|e| panic!("{name}: {e}"));
            let scale = a.displacement.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            let difference = a
                .displacement
                .iter()
                .zip(&b.displacement)
                .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
            // The turned forces: |lambda_T| is the same node by node.
            let force_scale = a.normal_force.iter().fold(0.0f64, |m, x| m.max(*x));
            let mut largest_force = 0.0f64;
            for i in 0..system.n_constraints() {
                let na = a.tangential_force[2 * i].hypot(a.tangential_force[2 * i + 1]);
                let nb = b.tangential_force[2 * i].hypot(b.tangential_force[2 * i + 1]);
                let tol = if name == "exact" { 1e-5 } else { 1e-9 };
                assert!((na - nb).abs() < tol * force_scale, "{name}: {na} vs {nb}");
                largest_force = largest_force.max((na - nb).abs() / force_scale);
            }
            let residuals = KktResiduals::evaluate(
                &turned,
                &b.displacement,
                &b.normal_force,
                &b.tangential_force,
            );
            println!(
                "{name}: |u - u_turned| = {:.1e} of |u|, |lambda_T| {largest_force:.1e} of the \
                 largest normal force, turned residuals {:.1e}",
                difference / scale,
                residuals.max_violation()
            );
            let tol = match name.as_str() {
                // The interior point's answer is accurate to its own tolerance.
                "exact" => 1e-6,
                _ => 1e-10,
            };
            assert!(
                difference < tol * scale,
                "{name}: {difference:e} of {scale:e}"
            );
        }
    }
}

const COEFFICIENT: f64 = 0.3;
const WEIGHT: f64 = 1.0;

/// A block on the rigid plane z = 0, its top a rigid plate pushed down with `P` and sideways
/// with `Q` along `(cos 30, sin 30)`: held sideways by Coulomb friction alone.
fn plate_on_block(shear: f64) -> ContactProblem<3> {
    let direction = Vector3::new(30f64.to_radians().cos(), 30f64.to_radians().sin(), 0.0);
    let body = ElasticBody::builder_polyhedral(
        "block",
        cube([0.0; 3], [1.0, 1.0, 0.5], [3, 3, 2]),
        material(),
        element(),
    )
    .dirichlet(Dirichlet::rigid_plate(
        "top",
        Component::All,
        direction * shear - Vector3::z() * WEIGHT,
    ))
    .build()
    .unwrap();
    let plane = Obstacle3::Plane {
        point: Point3::origin(),
        normal: Vector3::z(),
    };
    ContactProblem::new(vec![body]).with_pair(ContactPair::against(
        0,
        "bottom",
        plane,
        Coulomb::try_new(COEFFICIENT).unwrap(),
    ))
}

#[test]
fn a_rigid_block_sheared_below_its_capacity_is_held_and_beyond_it_refused() {
    let capacity = COEFFICIENT * WEIGHT;
    for ratio in [0.5, 1.0 - 1e-3] {
        let shear = ratio * capacity;
        let mut solver = CondensedSolver::default();
        let result = plate_on_block(shear)
            .solve(&mut solver)
            .unwrap_or_else(|e| panic!("Q/(F P) = {ratio}: {e}"));
        // The plane pushes up by P and friction holds the block back by Q.
        let force = result.force_on_body_a();
        let direction = Vector3::new(30f64.to_radians().cos(), 30f64.to_radians().sin(), 0.0);
        let friction = result.friction_resultant();
        println!(
            "Q/(F P) = {ratio}: contact force {force}, friction {friction}, stick/slip {:?}, \
             {} Tresca steps, solver {}",
            stick_and_slip(&result),
            result.fixed_point.as_ref().map_or(0, |f| f.steps),
            result.report.solver
        );
        assert!(
            (force - (Vector3::z() * WEIGHT - direction * shear)).norm() <= 1e-8 * WEIGHT,
            "Q/(F P) = {ratio}: {force}"
        );
        // Coulomb's disk node by node, to the fixed point's tolerance (the bounds are F
        // times the normal forces of the last step but one).
        for node in &result.nodes {
            let excess = node.friction_force.norm() - COEFFICIENT * node.normal_force;
            assert!(excess <= 1e-8 * WEIGHT, "{excess:e}");
        }
    }
    let shear = 1.01 * capacity;
    match plate_on_block(shear).solve(&mut CondensedSolver::default()) {
        Err(ContactError::FrictionCapacityExceeded {
            load_along_mode,
            friction_capacity,
            ..
        }) => {
            assert!(
                (load_along_mode - shear).abs() < 1e-6 * shear,
                "{load_along_mode}"
            );
            assert!(
                (friction_capacity - capacity).abs() < 1e-6 * capacity,
                "{friction_capacity}"
            );
        }
        other => panic!("expected a refusal for the capacity, got {other:?}"),
    }
}

#[test]
fn a_block_sliding_on_a_plane_carries_q_over_p_equal_to_the_coefficient() {
    // The top moved sideways far beyond the elastic stick slip (a material without lateral
    // contraction, so that nothing slips but the shear): every node slides the same way,
    // and the friction resultant is F times the normal one.
    for (name, mut solver) in solvers() {
        if name == "exact" {
            // Full slip leaves the interior point short of its tolerance (Clarabel's "almost
            // solved"): take that answer, which the certificate still checks.
            let settings = vem_contact::ExactSettings::builder()
                .accept_reduced_accuracy(true)
                .build()
                .unwrap();
            solver = Box::new(vem_contact::ExactSolver::new(settings));
        }
        let problem = block_of(
            Coulomb::try_new(COEFFICIENT).unwrap(),
            [0.05, 0.03],
            material_without_poisson(),
        );
        let result = problem
            .solve(&mut *solver)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let (stick, slip) = stick_and_slip(&result);
        assert_eq!(stick, 0, "{name}");
        assert!(slip > 0, "{name}");
        // Every node on its disk's rim: sum |lambda_T,i| = F sum lambda_N,i; the resultant's
        // ratio is below F only by the spread of the slip directions near the free edges.
        let q = result
            .nodes
            .iter()
            .map(|n| n.friction_force.norm())
            .sum::<f64>();
        let p = result.normal_resultant();
        let resultant = result.friction_resultant().norm();
        assert!(resultant <= q * (1.0 + 1e-12));
        println!("{name}: |Q|/P - F = {:.1e}", resultant / p - COEFFICIENT);
        let tol = match name.as_str() {
            "exact" => 1e-4,
            "penalty" => 1e-4,
            _ => 1e-6,
        };
        println!(
            "{name}: sum |lambda_T| / P - F = {:.1e}",
            q / p - COEFFICIENT
        );
        assert!(
            (q / p - COEFFICIENT).abs() < tol * COEFFICIENT,
            "{name}: {}",
            q / p
        );
    }
}

#[test]
fn coulomb_in_space_costs_one_factorisation_per_body() {
    let mut solver = CondensedSolver::default();
    let result = stacked_blocks(Coulomb::try_new(COEFFICIENT).unwrap())
        .solve(&mut solver)
        .unwrap();
    let fixed_point = result.fixed_point.as_ref().unwrap();
    println!(
        "Coulomb: {} Tresca steps, residual {:.1e}, stick/slip {:?}",
        fixed_point.steps,
        fixed_point.residual,
        stick_and_slip(&result)
    );
    assert!(fixed_point.steps >= 1);
    // One factorisation per body for the whole fixed point.
    assert_eq!(result.work.numeric_factorisations, 2);
    let scale = result
        .nodes
        .iter()
        .fold(0.0f64, |m, n| m.max(n.normal_force));
    for node in &result.nodes {
        let excess = node.friction_force.norm() - COEFFICIENT * node.normal_force;
        assert!(excess <= 1e-8 * scale, "{excess:e}");
    }
    // The interior point's fixed point finds the same forces.
    let exact = stacked_blocks(Coulomb::try_new(COEFFICIENT).unwrap())
        .solve(&mut vem_contact::ExactSolver::default())
        .unwrap();
    for (a, b) in result.nodes.iter().zip(&exact.nodes) {
        assert!((a.normal_force - b.normal_force).abs() < 1e-3 * scale);
        assert!((a.friction_force - b.friction_force).norm() < 1e-3 * scale);
    }
}

/// The condensed solver's answer with the interface method `interface`.
fn solve_with_interface(
    problem: &ContactProblem<3>,
    interface: InterfaceMethod,
) -> ContactResult<3> {
    let settings = CondensedSettings::builder()
        .interface(interface)
        .build()
        .unwrap();
    problem.solve(&mut CondensedSolver::new(settings)).unwrap()
}

/// The Coulomb fixed point with the iterative interface (projected Newton steps on the Schur
/// operator, warm started from step to step) and with the dense one: the same forces and displacements to
/// the certificate's tolerance, each certified, one factorisation per body either way.
#[test]
fn coulomb_in_space_is_the_same_with_the_iterative_interface() {
    let problem = stacked_blocks(Coulomb::try_new(COEFFICIENT).unwrap());
    let dense = solve_with_interface(&problem, InterfaceMethod::Dense);
    let iterative = solve_with_interface(&problem, InterfaceMethod::Iterative);
    assert_eq!(iterative.work.numeric_factorisations, 2);
    let (largest, largest_u) = largest_differences(&iterative, &dense);
    println!(
        "Coulomb, iterative against dense: forces {largest:.1e}, displacements {largest_u:.1e}; \
         {} against {} Tresca steps, {} against {} interface iterations",
        iterative.fixed_point.as_ref().unwrap().steps,
        dense.fixed_point.as_ref().unwrap().steps,
        iterative.report.iterations,
        dense.report.iterations
    );
    assert!(
        largest < 1e-7 && largest_u < 1e-7,
        "{largest:e} {largest_u:e}"
    );
}

/// The largest differences of two answers of the same problem: nodal normal forces and
/// friction vectors relative to the largest normal force, displacements relative to the
/// largest displacement.
fn largest_differences(a: &ContactResult<3>, b: &ContactResult<3>) -> (f64, f64) {
    let scale = b.nodes.iter().fold(0.0f64, |m, n| m.max(n.normal_force));
    let mut forces = 0.0f64;
    for (x, y) in a.nodes.iter().zip(&b.nodes) {
        forces = forces
            .max((x.normal_force - y.normal_force).abs() / scale)
            .max((x.friction_force - y.friction_force).norm() / scale);
    }
    let u_scale = b.bodies.iter().fold(0.0f64, |m, b| {
        (0..b.body.mesh().n_vertices())
            .fold(m, |m, v| m.max(b.solution.vertex_displacement(v).norm()))
    });
    let mut displacements = 0.0f64;
    for (x, y) in a.bodies.iter().zip(&b.bodies) {
        for v in 0..x.body.mesh().n_vertices() {
            let du = x.solution.vertex_displacement(v) - y.solution.vertex_displacement(v);
            displacements = displacements.max(du.norm() / u_scale);
        }
    }
    (forces, displacements)
}

/// Tresca with stick and slip zones on both problems: the iterative interface (projected
/// Newton steps along the rims, their Newton systems by conjugate gradients on the Schur
/// operator) and the dense one (the same steps with direct Newton systems) give the same
/// forces and displacements to `1e-9` of the largest, each certified.
#[test]
fn tresca_in_space_is_the_same_with_the_iterative_interface() {
    for (name, problem) in [
        ("block on a plane", block_on_plane(steep_tresca(), SHEAR)),
        ("two blocks", stacked_blocks(variable_tresca())),
    ] {
        let dense = solve_with_interface(&problem, InterfaceMethod::Dense);
        let iterative = solve_with_interface(&problem, InterfaceMethod::Iterative);
        let (stick, slip) = stick_and_slip(&iterative);
        assert!(stick > 0 && slip > 0, "{name}: stick {stick}, slip {slip}");
        let (forces, displacements) = largest_differences(&iterative, &dense);
        println!(
            "{name}: forces {forces:.1e}, displacements {displacements:.1e}; {} Newton steps, \
             {} triangular solve pairs",
            iterative.report.iterations, iterative.work.triangular_solves
        );
        assert!(
            forces < 1e-9 && displacements < 1e-9,
            "{name}: {forces:e} {displacements:e}"
        );
    }
}

/// The cost of friction in space against one elastic solve (not a check: figures for
/// `docs/contact-3d.md`). `cargo test -p vem-contact --test friction_3d -- --ignored
/// --nocapture cost` (the test profile is optimised); the sizes `n` (default 8, 16, 24) from
/// the environment variable `FRICTION_COST_SIZES` (comma separated; 40 gives 1.06e5 unknowns).
#[test]
#[ignore = "timing figures, run by hand"]
fn cost_of_friction_in_space() {
    use std::time::Instant;
    let sizes: Vec<usize> = std::env::var("FRICTION_COST_SIZES").map_or_else(
        |_| vec![8, 16, 24],
        |v| v.split(',').map(|n| n.trim().parse().unwrap()).collect(),
    );
    // The interface methods to compare, in the same run (`FRICTION_COST_INTERFACE`, comma
    // separated: dense, iterative, auto; default dense and iterative).
    let methods: Vec<InterfaceMethod> = std::env::var("FRICTION_COST_INTERFACE")
        .unwrap_or_else(|_| "dense,iterative".to_string())
        .split(',')
        .map(|m| match m.trim() {
            "dense" => InterfaceMethod::Dense,
            "iterative" => InterfaceMethod::Iterative,
            _ => InterfaceMethod::Auto,
        })
        .collect();
    // The laws (`FRICTION_COST_LAWS`, comma separated; default all three).
    let laws: Vec<String> = std::env::var("FRICTION_COST_LAWS")
        .unwrap_or_else(|_| "frictionless,tresca,coulomb".to_string())
        .split(',')
        .map(|l| l.trim().to_string())
        .collect();
    println!(
        "| n | 3 x vertices | contact nodes | law | interface | stick, slip | interface steps \
         | Tresca steps | solves | contact s | total s | one elastic solve s | ratio |"
    );
    for n in sizes {
        let mesh = || cube([0.0; 3], [1.0, 1.0, 0.5], [n, n, n / 2]);
        let top = |b: vem_elastic::ElasticBodyBuilder<3>| {
            b.dirichlet(Dirichlet::with_values("top", Component::All, move |_| {
                Vector3::new(SHEAR[0], SHEAR[1], -PRESS)
            }))
        };
        let held = top(ElasticBody::builder_polyhedral(
            "block",
            mesh(),
            material(),
            element(),
        ))
        .clamp("bottom")
        .build()
        .unwrap();
        let start = Instant::now();
        let _ = held.solve().unwrap();
        let elastic = start.elapsed().as_secs_f64();
        let unknowns = 3 * (n + 1) * (n + 1) * (n / 2 + 1);
        for ((law, name), &method) in [
            (
                Arc::new(vem_contact::Frictionless) as Arc<dyn ContactLaw<3>>,
                "frictionless",
            ),
            (Arc::new(steep_tresca()), "tresca"),
            (Arc::new(Coulomb::try_new(COEFFICIENT).unwrap()), "coulomb"),
        ]
        .into_iter()
        .filter(|(_, name)| laws.iter().any(|l| l == name))
        .flat_map(|law| methods.iter().map(move |m| (law.clone(), m)))
        {
            let body = top(ElasticBody::builder_polyhedral(
                "block",
                mesh(),
                material(),
                element(),
            ))
            .build()
            .unwrap();
            let plane = Obstacle3::Plane {
                point: Point3::origin(),
                normal: Vector3::z(),
            };
            let problem = ContactProblem::against_obstacle(body, "bottom", plane, law);
            let start = Instant::now();
            let settings = CondensedSettings::builder()
                .interface(method)
                .build()
                .unwrap();
            let result = match problem.solve(&mut CondensedSolver::new(settings)) {
                Ok(result) => result,
                Err(e) => {
                    println!("| {n} | {unknowns} | | {name} | {method:?} | {e} |");
                    continue;
                }
            };
            let total = start.elapsed().as_secs_f64();
            println!(
                "| {n} | {unknowns} | {} | {name} | {method:?} | {:?} | {} | {} | {} | {:.2} | {:.2} \
                 | {:.2} | {:.2} |",
                result.nodes.len(),
                stick_and_slip(&result),
                result.report.iterations,
                result.fixed_point.as_ref().map_or(0, |f| f.steps),
                result.work.triangular_solves,
                result.work.times.contact_solve.as_secs_f64(),
                total,
                elastic,
                total / elastic
            );
        }
    }
}

/// Two deformable blocks `[-1, 1] x [0, 1] x (0, 1)` (upper) and its mirror image (lower,
/// clamped at its bottom) with the gap `r^2 / 2` between them, the plane y = 0 held (a plane
/// of symmetry); the upper block's top a rigid plate pushed down with `P` and sheared along x
/// with `Q`, Coulomb friction: Cattaneo-Mindlin's setting, the upper block held sideways by
/// friction alone.
fn sheared_blocks(shear: f64) -> ContactProblem<3> {
    let upper = ElasticBody::builder_polyhedral(
        "upper",
        cube([-1.0, 0.0, 0.0], [1.0, 1.0, 1.0], [8, 4, 4]),
        material(),
        element(),
    )
    .dirichlet(Dirichlet::fixed("front", Component::Y))
    .dirichlet(Dirichlet::rigid_plate(
        "top",
        Component::Z,
        Vector3::new(0.0, 0.0, -WEIGHT),
    ))
    .dirichlet(Dirichlet::rigid_plate(
        "top",
        Component::X,
        Vector3::new(shear, 0.0, 0.0),
    ))
    .build()
    .unwrap();
    let lower = ElasticBody::builder_polyhedral(
        "lower",
        cube([-1.0, 0.0, -1.0], [1.0, 1.0, 0.0], [8, 4, 4]),
        material(),
        element(),
    )
    .dirichlet(Dirichlet::fixed("front", Component::Y))
    .clamp("bottom")
    .build()
    .unwrap();
    ContactProblem::two_bodies(
        upper,
        "bottom",
        lower,
        "top",
        Coulomb::try_new(COEFFICIENT).unwrap(),
    )
    .with_imposed_gap(|x| 0.5 * (x.x * x.x + x.y * x.y))
}

/// Two elastic blocks, the upper held sideways by friction alone: refused beyond the capacity
/// by the check of the rigid slide, whatever the solver would answer.
#[test]
fn two_blocks_sheared_beyond_their_capacity_are_refused_with_the_capacity() {
    let capacity = COEFFICIENT * WEIGHT;
    let held = sheared_blocks(0.5 * capacity)
        .solve(&mut CondensedSolver::default())
        .unwrap();
    // Below the capacity the friction carries the shear.
    let friction = held.friction_resultant();
    assert!((friction.x + 0.5 * capacity).abs() < 1e-8, "{friction}");
    let shear = 1.01 * capacity;
    match sheared_blocks(shear).solve(&mut CondensedSolver::default()) {
        Err(ContactError::FrictionCapacityExceeded {
            load_along_mode,
            friction_capacity,
            ..
        }) => {
            println!("load along the mode {load_along_mode}, capacity {friction_capacity}");
            // The mode is the upper block's translation along x: the load along it is Q.
            assert!(
                (load_along_mode - shear).abs() < 1e-6 * shear,
                "{load_along_mode}"
            );
            // F times the normal forces of the held start: F P (measured to 7e-12).
            assert!(
                (friction_capacity - capacity).abs() < 1e-6 * capacity,
                "{friction_capacity}"
            );
        }
        other => panic!("expected a refusal for the capacity, got {other:?}"),
    }
}

/// Coordinates from 0 to `length`: cells of size `h` up to `fine`, then growing by 1.3.
fn graded(h: f64, fine: f64, length: f64) -> Vec<f64> {
    let mut x = vec![0.0];
    let mut step = h;
    while *x.last().unwrap() < length - 1e-12 {
        let last = *x.last().unwrap();
        if last >= fine - 1e-12 {
            step *= 1.3;
        }
        x.push((last + step).min(length));
    }
    let n = x.len();
    if n > 2 && x[n - 1] - x[n - 2] < 0.5 * step {
        x.remove(n - 2);
    }
    x
}

/// The lattice of hexahedra with its vertex `(i, j, k)` at `(xs[i], ys[j], zs[k])`.
fn lattice(xs: &[f64], ys: &[f64], zs: &[f64]) -> PolyhedralMesh {
    let (nx, ny, nz) = (xs.len() - 1, ys.len() - 1, zs.len() - 1);
    let unit = hexahedra(&Cuboid::unit_cube(), nx, ny, nz).unwrap();
    let index = |s: f64, m: usize| (s * m as f64).round() as usize;
    let vertices = unit
        .vertices()
        .iter()
        .map(|p| Point3::new(xs[index(p.x, nx)], ys[index(p.y, ny)], zs[index(p.z, nz)]))
        .collect();
    PolyhedralMesh::from_compact(
        vertices,
        unit.face_offsets().to_vec(),
        unit.face_vertex_indices().to_vec(),
        unit.cell_offsets().to_vec(),
        unit.cell_face_indices().to_vec(),
        unit.parts().to_vec(),
    )
    .unwrap()
}

/// Cattaneo-Mindlin's blocks of `cargo xtask hertz` (section in space) at the node spacing
/// `h`: E = 100, nu = 0.3, the gap `r^2 / 2`, Hertz's contact radius 0.1 under `P`.
fn mindlin_blocks(h: f64, ratio: f64) -> (ContactProblem<3>, f64) {
    let e_star = 100.0 / (2.0 * (1.0 - 0.09));
    let push = 4.0 * e_star * 0.1f64.powi(3) / 3.0;
    let shear = ratio * COEFFICIENT * push;
    let top = [
        Dirichlet::rigid_plate("top", Component::Z, Vector3::new(0.0, 0.0, -0.5 * push)),
        Dirichlet::rigid_plate("top", Component::X, Vector3::new(0.5 * shear, 0.0, 0.0)),
    ];
    let law = Coulomb::try_new(COEFFICIENT).unwrap();
    (graded_blocks(h, top, law), 0.5 * shear)
}

/// The blocks of [`mindlin_blocks`] with the upper block's top held by `top` and the contact
/// law `law`.
fn graded_blocks(
    h: f64,
    top: [Dirichlet<3>; 2],
    law: impl ContactLaw<3> + 'static,
) -> ContactProblem<3> {
    let half = graded(h, 0.13, 1.0);
    let xs: Vec<f64> = half
        .iter()
        .rev()
        .map(|x| -x)
        .chain(half.iter().skip(1).copied())
        .collect();
    let down: Vec<f64> = half.iter().rev().map(|z| -z).collect();
    let material = Material::isotropic(100.0, 0.3).unwrap();
    let [vertical, sideways] = top;
    let upper =
        ElasticBody::builder_polyhedral("upper", lattice(&xs, &half, &half), material, element())
            .dirichlet(Dirichlet::fixed("front", Component::Y))
            .dirichlet(vertical)
            .dirichlet(sideways)
            .build()
            .unwrap();
    let lower =
        ElasticBody::builder_polyhedral("lower", lattice(&xs, &half, &down), material, element())
            .dirichlet(Dirichlet::fixed("front", Component::Y))
            .clamp("bottom")
            .build()
            .unwrap();
    ContactProblem::two_bodies(upper, "bottom", lower, "top", law)
        .with_imposed_gap(|x| 0.5 * (x.x * x.x + x.y * x.y))
}

/// A contact zone of a few nodes on a large face (Cattaneo-Mindlin's blocks, frictionless
/// and Coulomb at `Q = 0.5 F P`): the iterative interface solves on the candidate nodes
/// (`H_CC` by block solves, the dense QP, the check on the whole face) and gives the dense
/// interface's forces and displacements, each answer certified; with Coulomb, the held first
/// step is iterated and the later steps are solved on the candidates.
#[test]
fn a_small_contact_zone_is_solved_on_its_candidate_nodes() {
    let candidates = "condensed (iterative interface, dense on the candidate nodes)";
    // The top pressed down by 0.01, and for Coulomb also moved sideways by 0.001.
    let top = |slide: f64| {
        [
            Dirichlet::with_values("top", Component::Z, |_| Vector3::new(0.0, 0.0, -0.01)),
            Dirichlet::with_values("top", Component::X, move |_| Vector3::new(slide, 0.0, 0.0)),
        ]
    };
    for (name, problem) in [
        ("frictionless", graded_blocks(0.05, top(0.0), Frictionless)),
        (
            "Coulomb",
            graded_blocks(0.05, top(0.001), Coulomb::try_new(COEFFICIENT).unwrap()),
        ),
    ] {
        let dense = solve_with_interface(&problem, InterfaceMethod::Dense);
        let iterative = solve_with_interface(&problem, InterfaceMethod::Iterative);
        assert_eq!(iterative.report.solver, candidates, "{name}");
        let in_contact = iterative
            .nodes
            .iter()
            .filter(|n| n.normal_force > 0.0)
            .count();
        // On the plane of symmetry y = 0 both sides are held in y: the friction force's y
        // component is not determined there (any value within the disk is a minimiser), so it
        // is not compared.
        let mut determined = iterative.clone();
        for (node, other) in determined.nodes.iter_mut().zip(&dense.nodes) {
            if node.position.y == 0.0 {
                node.friction_force.y = other.friction_force.y;
            }
        }
        let (forces, displacements) = largest_differences(&determined, &dense);
        println!(
            "{name}: {in_contact} of {} nodes in contact; forces {forces:.1e}, displacements \
             {displacements:.1e}; {} triangular solve passes",
            iterative.nodes.len(),
            iterative.work.triangular_solves
        );
        assert!(
            4 * in_contact < iterative.nodes.len(),
            "{name}: {in_contact}"
        );
        assert!(
            forces < 1e-8 && displacements < 1e-8,
            "{name}: {forces:e} {displacements:e}"
        );
    }
}

/// Cattaneo-Mindlin's blocks (the quick size of `cargo xtask hertz`, coarser): held at
/// `Q = 0.8 F P`, refused at `Q = 1.01 F P` with the figures of the slide.
#[test]
fn mindlin_blocks_beyond_their_capacity_are_refused_at_the_first_coulomb_step() {
    // Below the capacity the shear is carried.
    let (problem, half_shear) = mindlin_blocks(0.05, 0.8);
    let result = problem.solve(&mut CondensedSolver::default()).unwrap();
    let friction = result.friction_resultant();
    assert!(
        (friction.x + half_shear).abs() <= 1e-8 * half_shear,
        "{friction}"
    );
    // Beyond it (Q = 1.01 F P) the refusal names the load along the upper block's slide and
    // the capacity F P of the normal forces (half of each: the half model).
    let (problem, half_shear) = mindlin_blocks(0.05, 1.01);
    let half_capacity = half_shear / 1.01;
    match problem.solve(&mut CondensedSolver::default()) {
        Err(ContactError::FrictionCapacityExceeded {
            load_along_mode,
            friction_capacity,
            step,
            ..
        }) => {
            println!("load along the mode {load_along_mode}, capacity {friction_capacity}");
            assert_eq!(step, 1);
            assert!(
                (load_along_mode - half_shear).abs() < 1e-9 * half_shear,
                "{load_along_mode}"
            );
            assert!(
                (friction_capacity - half_capacity).abs() < 1e-6 * half_capacity,
                "{friction_capacity}"
            );
        }
        other => panic!("expected a refusal for the capacity, got {other:?}"),
    }
}
