//! Two-body contact patch tests PTC1, PTC1h, PTC2, PTC3 (docs/manufactured.md section 6): linear
//! fields are in the discrete space on any mesh, also on elements enlarged by inserted
//! interface nodes, so the discrete contact solution is exact (to the solver tolerance) on
//! matching and non-matching meshes, node by node, and so are the nodal forces.

use std::sync::Arc;

use vem_contact::{
    CondensedSolver, ContactLaw, ContactProblem, ContactResult, ContactSolver, Coulomb,
    ExactSettings, ExactSolver, Frictionless, NodeStatus, Obstacle, PenaltyParameter,
    PenaltySettings, PenaltySolver, Tresca,
};
use vem_elastic::{Component, Dirichlet, ElasticBody, Material, Plane};
use vem_mesh::generators::{MeshFamily, Rectangle};
use vem_mesh::{Mesh, Point, Vector};
use vem_space::LowestOrderVem;

const LAMBDA: f64 = 2.0;
const MU: f64 = 1.0;
const FRICTION_BOUND: f64 = 0.25;

/// The linear two-body state of docs/manufactured.md: u_1 = (e - gamma (1 - y), -d + beta (1 - y)),
/// u_2 = (-e + gamma (1 + y), d - beta (1 + y)).
#[derive(Debug, Clone, Copy)]
struct Patch {
    beta: f64,
    d: f64,
    e: f64,
    gamma: f64,
    law: Law,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Law {
    Frictionless,
    Tresca,
}

impl Patch {
    fn ptc1() -> Self {
        Self {
            beta: 0.01,
            d: 0.03,
            e: 0.02,
            gamma: 0.0,
            law: Law::Frictionless,
        }
    }
    fn ptc1h() -> Self {
        Self {
            beta: 0.01,
            d: 0.0,
            e: 0.0,
            gamma: 0.0,
            law: Law::Frictionless,
        }
    }
    fn ptc2() -> Self {
        let gamma = FRICTION_BOUND / MU;
        Self {
            beta: 0.01,
            d: 0.03,
            e: gamma + 0.02,
            gamma,
            law: Law::Tresca,
        }
    }
    fn ptc3() -> Self {
        let gamma = FRICTION_BOUND / (2.0 * MU);
        Self {
            beta: 0.01,
            d: 0.03,
            e: gamma,
            gamma,
            law: Law::Tresca,
        }
    }

    fn upper(&self, x: Point) -> Vector {
        Vector::new(
            self.e - self.gamma * (1.0 - x.y),
            -self.d + self.beta * (1.0 - x.y),
        )
    }
    fn lower(&self, x: Point) -> Vector {
        Vector::new(
            -self.e + self.gamma * (1.0 + x.y),
            self.d - self.beta * (1.0 + x.y),
        )
    }
    fn initial_gap(&self) -> f64 {
        2.0 * (self.d - self.beta)
    }
    /// sigma_nu = -(lambda + 2 mu) beta; sigma_1tau = -mu gamma.
    fn sigma_nu(&self) -> f64 {
        -(LAMBDA + 2.0 * MU) * self.beta
    }
    fn sigma_1tau(&self) -> f64 {
        -MU * self.gamma
    }

    fn body(&self, name: &str, mesh: Mesh, upper: bool) -> ElasticBody {
        let material = Material::from_lame(LAMBDA, MU, Plane::Strain).unwrap();
        let element = Arc::new(LowestOrderVem::default());
        let p = *self;
        let (clamped, field): (&str, fn(&Patch, Point) -> Vector) = if upper {
            ("top", Patch::upper)
        } else {
            ("bottom", Patch::lower)
        };
        let (lb, g) = (LAMBDA * p.beta, MU * p.gamma);
        ElasticBody::builder(name, mesh, material, element)
            .dirichlet(Dirichlet::prescribed(clamped, Component::All, move |x| {
                field(&p, x)
            }))
            .traction("left", move |_| Vector::new(lb, -g))
            .traction("right", move |_| Vector::new(-lb, g))
            .build()
            .unwrap()
    }

    fn problem(&self, upper: Mesh, lower: Mesh) -> ContactProblem {
        let law = match self.law {
            Law::Frictionless => Arc::new(Frictionless) as Arc<dyn ContactLaw>,
            Law::Tresca => Arc::new(Tresca::try_new(FRICTION_BOUND).unwrap()),
        };
        let h0 = self.initial_gap();
        ContactProblem::two_bodies(
            self.body("upper", upper, true),
            "bottom",
            self.body("lower", lower, false),
            "top",
            law,
        )
        .with_imposed_gap(move |_| h0)
    }
}

fn upper_rect() -> Rectangle {
    Rectangle::new(Point::new(0.0, 0.0), Point::new(1.0, 1.0))
}
fn lower_rect() -> Rectangle {
    Rectangle::new(Point::new(0.0, -1.0), Point::new(1.0, 0.0))
}

fn tight_exact() -> ExactSolver {
    ExactSolver::new(
        ExactSettings::builder()
            .eps_abs(1e-12)
            .eps_rel(1e-12)
            .build()
            .unwrap(),
    )
}

/// Checks the result of a patch test against the linear exact state, node by node.
fn check_exact(patch: &Patch, result: &ContactResult, tolerance: f64, label: &str) {
    let scale = 0.3; // displacement magnitude of the patch fields
    for (k, body) in result.bodies.iter().enumerate() {
        let mesh = body.body.mesh();
        for v in 0..mesh.n_vertices() {
            let x = mesh.vertex(v);
            let exact = if k == 0 {
                patch.upper(x)
            } else {
                patch.lower(x)
            };
            let error = (body.solution.vertex_displacement(v) - exact).norm();
            assert!(
                error <= tolerance * scale,
                "{label}: body {k} vertex {v} at {x}: error {error:e}"
            );
        }
    }
    for node in &result.nodes {
        assert!(
            node.status != NodeStatus::Open,
            "{label}: open node at {}",
            node.position
        );
        let expected_normal = -patch.sigma_nu() * node.tributary_measure;
        assert!(
            (node.normal_force - expected_normal).abs() <= tolerance,
            "{label}: normal force {} vs {expected_normal} at {}",
            node.normal_force,
            node.position
        );
        let expected_friction = patch.sigma_1tau() * node.tributary_measure;
        assert!(
            (node.friction_t() - expected_friction).abs() <= tolerance * 10.0,
            "{label}: friction force {} vs {expected_friction} at {}",
            node.friction_t(),
            node.position
        );
        assert!(
            (node.pressure + patch.sigma_nu()).abs() <= 1e3 * tolerance,
            "{label}: pressure"
        );
        let expected_slip = if patch.law == Law::Tresca {
            2.0 * (patch.e - patch.gamma)
        } else {
            0.0
        };
        assert!(
            (node.slip_t() - expected_slip).abs() <= tolerance,
            "{label}: slip {}",
            node.slip_t()
        );
    }
    // Resultants: sum of nodal forces = -int sigma_nu ds, int sigma_1tau ds (|Gamma_C| = 1).
    assert!(
        (result.normal_resultant() + patch.sigma_nu()).abs() <= 10.0 * tolerance,
        "{label}"
    );
    assert!(
        (result.tangential_resultant() - patch.sigma_1tau()).abs() <= 10.0 * tolerance,
        "{label}"
    );
}

fn pairings() -> Vec<(&'static str, Mesh, Mesh)> {
    let quads = |rect: &Rectangle, n| MeshFamily::Quads.generate(rect, n, 0).unwrap();
    vec![
        (
            "matching quads 4/4",
            quads(&upper_rect(), 4),
            quads(&lower_rect(), 4),
        ),
        (
            "quads 1:3",
            quads(&upper_rect(), 3),
            quads(&lower_rect(), 9),
        ),
        (
            "quads over Voronoi",
            quads(&upper_rect(), 5),
            MeshFamily::Voronoi.generate(&lower_rect(), 6, 7).unwrap(),
        ),
        (
            "non-convex over triangles",
            MeshFamily::NonConvex.generate(&upper_rect(), 4, 0).unwrap(),
            MeshFamily::Triangles.generate(&lower_rect(), 7, 0).unwrap(),
        ),
    ]
}

#[test]
fn contact_patch_tests_are_exact_on_matching_and_non_matching_meshes() {
    for (name, patch) in [
        ("PTC1", Patch::ptc1()),
        ("PTC1h", Patch::ptc1h()),
        ("PTC2", Patch::ptc2()),
        ("PTC3", Patch::ptc3()),
    ] {
        for (pairing, upper, lower) in pairings() {
            let label = format!("{name} on {pairing}");
            let problem = patch.problem(upper, lower);
            let result = problem
                .solve(&mut tight_exact())
                .unwrap_or_else(|e| panic!("{label}: {e}"));
            check_exact(&patch, &result, 1e-9, &label);
            // The condensed solver is exact up to round-off.
            let condensed = problem
                .solve(&mut CondensedSolver::default())
                .unwrap_or_else(|e| panic!("{label}, condensed: {e}"));
            check_exact(&patch, &condensed, 1e-11, &label);
            let expected_status = match (patch.law, name) {
                (Law::Tresca, "PTC3") => NodeStatus::Stick,
                (Law::Tresca, _) => NodeStatus::Slip,
                (Law::Frictionless, _) => NodeStatus::Contact,
            };
            assert!(
                result.nodes.iter().all(|n| n.status == expected_status),
                "{label}: statuses {:?}",
                result.nodes.iter().map(|n| n.status).collect::<Vec<_>>()
            );
        }
    }
}

#[test]
fn frictionless_builds_no_tangential_rows() {
    let (_, upper, lower) = pairings().remove(1);
    let result = Patch::ptc1()
        .problem(upper, lower)
        .solve(&mut tight_exact())
        .unwrap();
    assert_eq!(result.model.tangential_rows, 0);
    assert_eq!(result.model.normal_rows, 10); // 1:3 with 3 and 9 cells: 10 distinct nodes
    assert_eq!(result.model.inserted_nodes, 6);
    let (_, upper, lower) = pairings().remove(1);
    let result = Patch::ptc2()
        .problem(upper, lower)
        .solve(&mut tight_exact())
        .unwrap();
    assert_eq!(result.model.tangential_rows, 10);
}

#[test]
fn swapping_the_bodies_gives_the_same_physical_answer() {
    // Body roles swapped: A = lower body with contact part "top", nu = (0, 1).
    let patch = Patch::ptc2();
    let quads = |rect: &Rectangle, n| MeshFamily::Quads.generate(rect, n, 0).unwrap();
    let h0 = patch.initial_gap();
    let swapped = ContactProblem::two_bodies(
        patch.body("lower", quads(&lower_rect(), 9), false),
        "top",
        patch.body("upper", quads(&upper_rect(), 3), true),
        "bottom",
        Tresca::try_new(FRICTION_BOUND).unwrap(),
    )
    .with_imposed_gap(move |_| h0)
    .solve(&mut tight_exact())
    .unwrap();
    for node in &swapped.nodes {
        assert!((node.normal - Vector::new(0.0, 1.0)).norm() < 1e-14);
        // Same compression, friction on the lower body = -(friction on the upper body) along
        // e_x; with tau = (-1, 0) here its component along tau is the same number.
        assert!((node.pressure + patch.sigma_nu()).abs() < 1e-7);
        assert!((node.friction_t() - patch.sigma_1tau() * node.tributary_measure).abs() < 1e-9);
        // [u]_1tau = (u_lower - u_upper) . (-e_x) = the same slip as before.
        assert!((node.slip_t() - 2.0 * (patch.e - patch.gamma)).abs() < 1e-9);
    }
    let upper = &swapped.bodies[1];
    for v in 0..upper.body.mesh().n_vertices() {
        let x = upper.body.mesh().vertex(v);
        assert!((upper.solution.vertex_displacement(v) - patch.upper(x)).norm() < 1e-9);
    }
}

#[test]
fn penalty_error_falls_like_one_over_the_penalty() {
    let patch = Patch::ptc1();
    let quads = |rect: &Rectangle, n| MeshFamily::Quads.generate(rect, n, 0).unwrap();
    let mut errors = Vec::new();
    let penalties: [f64; 4] = [1e1, 1e2, 1e3, 1e4];
    for &relative in &penalties {
        let mut solver = PenaltySolver::new(
            PenaltySettings::builder()
                .penalty(PenaltyParameter::RelativeToStiffness(relative))
                .build()
                .unwrap(),
        );
        let result = patch
            .problem(quads(&upper_rect(), 3), quads(&lower_rect(), 4))
            .solve(&mut solver as &mut dyn ContactSolver)
            .unwrap();
        let error = result
            .nodes
            .iter()
            .map(|n| (n.normal_jump - patch.initial_gap()).abs())
            .fold(0.0, f64::max);
        errors.push(error);
    }
    // Penetration ~ |sigma_nu| / eps: slope -1 in log-log over three decades.
    let slope = (errors[3].ln() - errors[0].ln()) / (penalties[3].ln() - penalties[0].ln());
    assert!(
        (slope + 1.0).abs() < 0.05,
        "slope {slope}, errors {errors:?}"
    );
}

#[test]
fn block_on_a_rigid_line_is_compressed_uniformly() {
    // Signorini: a block clamped on top, pushed up by 0.02 at its bottom by a rigid line: the
    // exact field is u = (0, 0.02 (1 - y)), sigma_xx = -lambda 0.02, sigma_yy = -(lambda + 2 mu)
    // 0.02, carried on the lateral sides by the tractions sigma n.
    let compression = 0.02;
    let mesh = MeshFamily::Voronoi.generate(&upper_rect(), 5, 3).unwrap();
    let material = Material::from_lame(LAMBDA, MU, Plane::Strain).unwrap();
    let body = ElasticBody::builder("block", mesh, material, Arc::new(LowestOrderVem::default()))
        .clamp("top")
        .traction("left", move |_| Vector::new(LAMBDA * compression, 0.0))
        .traction("right", move |_| Vector::new(-LAMBDA * compression, 0.0))
        .build()
        .unwrap();
    // The obstacle surface lies at y = 0 but the body must be pushed in: a line at y = 0.02
    // whose outward normal points up; the gap at y = 0 is -0.02.
    let obstacle = Obstacle::Line {
        point: Point::new(0.0, compression),
        normal: Vector::new(0.0, 1.0),
    };
    let result = ContactProblem::against_obstacle(body, "bottom", obstacle, Frictionless)
        .solve(&mut tight_exact())
        .unwrap();
    assert_eq!(result.bodies.len(), 1);
    assert!(result.model.pairs[0].obstacle);
    let mesh = result.bodies[0].body.mesh();
    for v in 0..mesh.n_vertices() {
        let x = mesh.vertex(v);
        let exact = Vector::new(0.0, compression * (1.0 - x.y));
        let error = (result.bodies[0].solution.vertex_displacement(v) - exact).norm();
        assert!(error < 1e-9, "vertex {v} at {x}: error {error:e}");
    }
    let pressure = (LAMBDA + 2.0 * MU) * compression;
    for node in &result.nodes {
        assert!(
            (node.pressure - pressure).abs() < 1e-7,
            "pressure {} at {}",
            node.pressure,
            node.position
        );
    }
    assert!((result.normal_resultant() - pressure).abs() < 1e-9);
}

#[test]
fn coulomb_fixed_point_reproduces_the_sticking_patch() {
    // PTC3 sticks with |sigma_1tau| = g_F / 2 = 0.125 under sigma_nu = -0.04: any coefficient
    // F > 0.125 / 0.04 = 3.125 gives the same (sticking) Coulomb solution.
    let patch = Patch::ptc3();
    let quads = |rect: &Rectangle, n| MeshFamily::Quads.generate(rect, n, 0).unwrap();
    let h0 = patch.initial_gap();
    let result = ContactProblem::two_bodies(
        patch.body("upper", quads(&upper_rect(), 3), true),
        "bottom",
        patch.body("lower", quads(&lower_rect(), 5), false),
        "top",
        Coulomb::try_new(6.25).unwrap(),
    )
    .with_imposed_gap(move |_| h0)
    .solve(&mut tight_exact())
    .unwrap();
    check_exact(&patch, &result, 1e-8, "Coulomb PTC3");
    let fixed_point = result
        .fixed_point
        .as_ref()
        .expect("Coulomb reports its fixed point");
    assert!(
        fixed_point.steps >= 1 && fixed_point.residual <= 1e-8,
        "{fixed_point:?}"
    );
    assert!(result.nodes.iter().all(|n| n.status == NodeStatus::Stick));
}

#[test]
fn tresca_rigid_sliding_is_an_error_not_a_number() {
    // The upper block is held only vertically on top (u_y = -0.03, u_x free) and pushed sideways
    // by a total force 1 > the friction capacity g_F |Gamma_C| = 0.25: no equilibrium exists.
    let quads = |rect: &Rectangle, n| MeshFamily::Quads.generate(rect, n, 0).unwrap();
    let material = Material::from_lame(LAMBDA, MU, Plane::Strain).unwrap();
    let element = Arc::new(LowestOrderVem::default());
    let upper = ElasticBody::builder("upper", quads(&upper_rect(), 3), material, element.clone())
        .dirichlet(Dirichlet::prescribed("top", Component::Y, |_| {
            Vector::new(0.0, -0.03)
        }))
        .traction("left", |_| Vector::new(1.0, 0.0))
        .build()
        .unwrap();
    let lower = ElasticBody::builder("lower", quads(&lower_rect(), 4), material, element)
        .clamp("bottom")
        .build()
        .unwrap();
    let error = ContactProblem::two_bodies(
        upper,
        "bottom",
        lower,
        "top",
        Tresca::try_new(0.25).unwrap(),
    )
    .solve(&mut tight_exact())
    .unwrap_err();
    match &error {
        vem_contact::ContactError::Solver(vem_contact::ContactSolverError::RigidSliding {
            load_along_mode,
            friction_capacity,
            ..
        }) => assert!(load_along_mode.abs() > *friction_capacity, "{error}"),
        other => panic!("expected rigid sliding, got {other}"),
    }
    // Below the capacity the same set-up is in equilibrium and the friction carries the load.
    let upper = ElasticBody::builder(
        "upper",
        quads(&upper_rect(), 3),
        material,
        Arc::new(LowestOrderVem::default()),
    )
    .dirichlet(Dirichlet::prescribed("top", Component::Y, |_| {
        Vector::new(0.0, -0.03)
    }))
    .traction("left", |_| Vector::new(0.1, 0.0))
    .build()
    .unwrap();
    let lower = ElasticBody::builder(
        "lower",
        quads(&lower_rect(), 4),
        material,
        Arc::new(LowestOrderVem::default()),
    )
    .clamp("bottom")
    .build()
    .unwrap();
    let result = ContactProblem::two_bodies(
        upper,
        "bottom",
        lower,
        "top",
        Tresca::try_new(0.25).unwrap(),
    )
    .solve(&mut tight_exact())
    .unwrap();
    // Horizontal equilibrium of the upper body: the friction balances the applied 0.1.
    assert!(
        (result.tangential_resultant() + 0.1).abs() < 1e-8,
        "{}",
        result.tangential_resultant()
    );
}
