//! A user's own cases through the study: a Tresca case with a friction bound g_F(x) that
//! varies along the interface, a Coulomb case, resultant judging and the case registry.
//!
//! Each user case is built from the fields of a built-in one whose exact solution also
//! satisfies the user's law, so the exact answer is known independently:
//! - M2 solves Tresca with any bound `g(x) >= |sigma_1tau(x)|` that equals `g_F = 1/4` on the
//!   slip set `(x_s, 1]`: there `|sigma_1tau| = 1/4`, and on the stick set there is no slip;
//! - a linear patch like PTC2 with constant pressure `p = (lambda + 2 mu) beta` and shear
//!   `sigma_1tau = -mu gamma`, slipping, solves Coulomb with `F = mu gamma / p`, for then
//!   `F |sigma_nu| = |sigma_1tau|` (PTC2 itself needs `F = 6.25`, beyond the reach of the
//!   fixed point of Tresca problems: it oscillates; `F = 0.1` here).

use std::sync::Arc;

use vem_contact::{
    ContactLaw, ContactSolver, Coulomb, ExactSettings, ExactSolver, FixedPointSettings, Tresca,
};
use vem_mesh::generators::{MeshFamily, Rectangle};
use vem_mesh::{Point, Vector};
use vem_verify::cases::CaseRegistry;
use vem_verify::exact::{
    case_by_name, BodyId, ContactSet, ExactContact, ExactSolution, ExpectedSets, FamilyA,
    FrictionSet, InterfaceValues, Lame, Resultants, Side, CASE_NAMES, FAMILY_A_FRICTION_BOUND,
    STICK_SLIP_POINT,
};
use vem_verify::nalgebra::Matrix2;
use vem_verify::problem::{DiscreteProblem, ProblemSettings};
use vem_verify::study::{Expectation, MeshPairing, Study};

/// A user's case: the fields of a built-in two-body case `inner`, its own name and law.
struct SameFields<C> {
    name: &'static str,
    inner: C,
    law: Arc<dyn ContactLaw>,
}

impl<C: ExactContact> ExactSolution for SameFields<C> {
    fn name(&self) -> &str {
        self.name
    }
    fn lame(&self) -> Lame {
        self.inner.lame()
    }
    fn bodies(&self) -> &'static [BodyId] {
        self.inner.bodies()
    }
    fn domain(&self, body: BodyId) -> Rectangle {
        self.inner.domain(body)
    }
    fn displacement(&self, body: BodyId, x: Point) -> Vector {
        self.inner.displacement(body, x)
    }
    fn gradient(&self, body: BodyId, x: Point) -> Matrix2<f64> {
        self.inner.gradient(body, x)
    }
    fn body_force(&self, body: BodyId, x: Point) -> Vector {
        self.inner.body_force(body, x)
    }
    fn dirichlet_sides(&self, body: BodyId) -> Vec<Side> {
        self.inner.dirichlet_sides(body)
    }
    fn neumann_sides(&self, body: BodyId) -> Vec<Side> {
        self.inner.neumann_sides(body)
    }
    fn contact(&self) -> Option<&dyn ExactContact> {
        Some(self)
    }
}

impl<C: ExactContact> ExactContact for SameFields<C> {
    fn law(&self) -> Arc<dyn ContactLaw> {
        Arc::clone(&self.law)
    }
    fn initial_gap(&self, x: f64) -> f64 {
        self.inner.initial_gap(x)
    }
    fn interface_values(&self, x: f64) -> InterfaceValues {
        self.inner.interface_values(x)
    }
    fn expected_sets(&self) -> Option<ExpectedSets> {
        self.inner.expected_sets()
    }
    fn reference_resultants(&self) -> Option<Resultants> {
        self.inner.reference_resultants()
    }
}

/// `g(x) = 1/4 + 2 (x_s - x)_+^2`: M2's bound on the slip set, larger on the stick set.
fn variable_bound(x: f64) -> f64 {
    FAMILY_A_FRICTION_BOUND + 2.0 * (STICK_SLIP_POINT - x).max(0.0).powi(2)
}

fn m2_with_variable_bound() -> Arc<dyn ExactSolution> {
    Arc::new(SameFields {
        name: "M2-variable-gF",
        inner: FamilyA::m2(Lame::default()),
        law: Arc::new(Tresca::with_field(|x: Point| variable_bound(x.x))),
    })
}

/// Clarabel with tolerances `eps`.
fn exact_solver(eps: f64) -> ExactSolver {
    ExactSolver::new(
        ExactSettings::builder()
            .eps_abs(eps)
            .eps_rel(eps)
            .build()
            .unwrap(),
    )
}

/// The variable bound goes through the study: M2's rates and sets, and the resultants of M2
/// in closed form (`-13/12`, `-g_F (1 - x_s/5)`).
#[test]
fn tresca_with_a_variable_bound_converges_to_m2() {
    let result = Study::new(m2_with_variable_bound(), "quads/quads".parse().unwrap())
        .sizes([8, 16, 32])
        .also_expect(Expectation::Resultants { tolerance: 1e-3 })
        .run()
        .unwrap();
    assert_eq!(result.law, "tresca");
    assert!(result.verdict.passed, "{:?}", result.verdict);
    let finest = result.finest().unwrap().contact.as_ref().unwrap();
    assert!((finest.normal_resultant_exact - 13.0 / 12.0).abs() < 1e-15);
    let tangential = -0.25 * (1.0 - STICK_SLIP_POINT / 5.0);
    assert!(
        (finest.tangential_resultant - tangential).abs() < 1e-3 * 13.0 / 12.0,
        "{finest:?}"
    );
    assert!(finest.stick > 0 && finest.slip > 0, "{finest:?}");
    // The errors of the plain M2 study on the same meshes: the same exact solution, the
    // same discretisation away from the stick zone; the errors agree to a few per cent.
    let m2 = Study::new(
        case_by_name("M2", Lame::default()).unwrap().into(),
        "quads/quads".parse().unwrap(),
    )
    .sizes([32])
    .run()
    .unwrap();
    let (a, b) = (result.finest().unwrap().errors, m2.finest().unwrap().errors);
    assert!((a.grad / b.grad - 1.0).abs() < 0.05, "{a:?} against {b:?}");
}

/// Node by node the discrete friction forces respect the nodal bound `l_x g(x)` of the field,
/// reaching it only where the exact solution slips.
#[test]
fn the_field_bound_is_applied_at_every_node() {
    let exact = m2_with_variable_bound();
    let meshes = MeshPairing::pair(MeshFamily::Quads, 1, MeshFamily::Quads, 1)
        .generate(&*exact, 16, 1)
        .unwrap();
    let problem = DiscreteProblem::try_new(exact, meshes, &ProblemSettings::default()).unwrap();
    let mut solver = exact_solver(1e-12);
    let result = problem
        .contact_problem()
        .unwrap()
        .solve(&mut solver as &mut dyn ContactSolver)
        .unwrap();
    for node in &result.nodes {
        let bound = node.tributary_measure * variable_bound(node.position.x);
        assert!(node.friction_t().abs() <= bound * (1.0 + 1e-6), "{node:?}");
        if node.position.x < STICK_SLIP_POINT - 0.35 {
            // The exact margin here is at least 2 (x_s - x)^2 > 0.24: far from the bound.
            assert!(node.friction_t().abs() < 0.5 * bound, "{node:?}");
        }
    }
}

/// A slipping linear contact patch under Coulomb friction (the construction of PTC2):
/// `u_1 = (e - gamma (1 - y), -d + beta (1 - y))`, `u_2 = (-e + gamma (1 + y), d - beta (1 + y))`
/// on the unit squares above and below `y = 0`, clamped at `y = +-1`, gap `h0 = 2 (d - beta)`,
/// slip `[u]_1tau = 2 (e - gamma) > 0`, stress `[-lambda beta, mu gamma; mu gamma,
/// -(lambda + 2 mu) beta]`.
struct CoulombPatch {
    lame: Lame,
    beta: f64,
    d: f64,
    e: f64,
    gamma: f64,
}

impl CoulombPatch {
    const BETA: f64 = 0.05;
    const GAMMA: f64 = 0.02;

    fn new() -> Self {
        Self {
            lame: Lame::default(),
            beta: Self::BETA,
            d: 0.06,
            e: Self::GAMMA + 0.01,
            gamma: Self::GAMMA,
        }
    }

    /// `F = mu gamma / ((lambda + 2 mu) beta)`.
    fn coefficient(&self) -> f64 {
        let (lambda, mu) = (self.lame.lambda(), self.lame.mu());
        mu * self.gamma / ((lambda + 2.0 * mu) * self.beta)
    }
}

impl ExactSolution for CoulombPatch {
    fn name(&self) -> &str {
        "coulomb-patch"
    }
    fn lame(&self) -> Lame {
        self.lame
    }
    fn bodies(&self) -> &'static [BodyId] {
        &BodyId::BOTH
    }
    fn domain(&self, body: BodyId) -> Rectangle {
        match body {
            BodyId::One => Rectangle::unit_square(),
            BodyId::Two => Rectangle::new(Point::new(0.0, -1.0), Point::new(1.0, 0.0)),
        }
    }
    fn displacement(&self, body: BodyId, x: Point) -> Vector {
        let (beta, d, e, gamma) = (self.beta, self.d, self.e, self.gamma);
        match body {
            BodyId::One => Vector::new(e - gamma * (1.0 - x.y), -d + beta * (1.0 - x.y)),
            BodyId::Two => Vector::new(-e + gamma * (1.0 + x.y), d - beta * (1.0 + x.y)),
        }
    }
    fn gradient(&self, _body: BodyId, _x: Point) -> Matrix2<f64> {
        Matrix2::new(0.0, self.gamma, 0.0, -self.beta)
    }
    fn body_force(&self, _body: BodyId, _x: Point) -> Vector {
        Vector::zeros()
    }
    fn dirichlet_sides(&self, body: BodyId) -> Vec<Side> {
        match body {
            BodyId::One => vec![Side::Top],
            BodyId::Two => vec![Side::Bottom],
        }
    }
    fn neumann_sides(&self, _body: BodyId) -> Vec<Side> {
        vec![Side::Left, Side::Right]
    }
    fn contact(&self) -> Option<&dyn ExactContact> {
        Some(self)
    }
}

impl ExactContact for CoulombPatch {
    fn law(&self) -> Arc<dyn ContactLaw> {
        Arc::new(Coulomb::try_with(self.coefficient(), FixedPointSettings::default()).expect("law"))
    }
    fn initial_gap(&self, _x: f64) -> f64 {
        2.0 * (self.d - self.beta)
    }
    fn expected_sets(&self) -> Option<ExpectedSets> {
        Some(ExpectedSets {
            contact: ContactSet::AllActive,
            friction: Some(FrictionSet::AllSlip),
        })
    }
}

/// Coulomb through the study: the slipping patch is reproduced exactly, every node slips at
/// `F lambda_N`, and the fixed point is reported.
#[test]
fn coulomb_patch_test_is_exact_through_the_study() {
    let patch = CoulombPatch::new();
    let coefficient = patch.coefficient();
    assert!((coefficient - 0.1).abs() < 1e-15);
    // The exact values the law is checked against: sigma_nu = -(lambda + 2 mu) beta = -0.2,
    // sigma_1tau = -mu gamma = -0.02 = -F |sigma_nu|, slip 2 (e - gamma) = 0.02.
    let v = patch.interface_values(0.3);
    assert!((v.sigma_nu + 0.2).abs() < 1e-15 && (v.sigma_1tau + 0.02).abs() < 1e-15);
    assert!((v.tangential_jump - 0.02).abs() < 1e-15 && v.gap().abs() < 1e-15);
    let exact: Arc<dyn ExactSolution> = Arc::new(patch);
    // The active-set solver: its forces are exact up to rounding, so the fixed point runs
    // to its own tolerance (the interior-point solver stops it at its force accuracy, 1e-4 at
    // 1e-10, which leaves relative errors near 1e-5).
    let result = Study::new(exact, "quads/hexagons".parse().unwrap())
        .sizes([2, 4])
        .solver("active-set")
        .expect(Expectation::Exact { tolerance: 1e-9 })
        .also_expect(Expectation::Resultants { tolerance: 1e-9 })
        .run()
        .unwrap();
    assert_eq!(
        (result.law.as_str(), result.solver.as_str()),
        ("coulomb", "active-set")
    );
    assert!(result.verdict.passed, "{:?}", result.verdict);
    for record in &result.records {
        let contact = record.contact.as_ref().unwrap();
        assert_eq!(
            (contact.slip, contact.nodes),
            (contact.nodes, contact.active)
        );
        let steps = record.fixed_point_steps.expect("a Coulomb record");
        assert!((1..=10).contains(&steps), "{steps} fixed-point steps");
        assert!(record.fixed_point_change.unwrap() < 1e-6, "{record:?}");
        // k Tresca steps on one discretisation: one assembly per body, one symbolic analysis.
        assert_eq!(record.work.assemblies, 2, "{:?}", record.work);
        assert_eq!(record.work.symbolic_analyses, 1, "{:?}", record.work);
        assert!(
            record.work.numeric_factorisations > steps,
            "{:?}",
            record.work
        );
    }
}

/// Resultant judging: M3's closed-form resultants (`-int sigma_nu = 13/12`, no friction) are
/// met within 1e-2 at n = 8 and refused at 1e-9.
#[test]
fn resultants_are_judged_against_the_closed_form() {
    let m3: Arc<dyn ExactSolution> = case_by_name("M3", Lame::default()).unwrap().into();
    let study = Study::new(m3, "quads/quads".parse().unwrap()).sizes([4, 8]);
    let loose = study
        .clone()
        .expect(Expectation::Resultants { tolerance: 1e-2 })
        .run()
        .unwrap();
    assert!(loose.verdict.passed, "{:?}", loose.verdict);
    let c = loose.finest().unwrap().contact.clone().unwrap();
    assert!((c.normal_resultant_exact - 13.0 / 12.0).abs() < 1e-15);
    assert!(c.normal_resultant_error > 1e-9);
    let tight = study
        .expect(Expectation::Resultants { tolerance: 1e-9 })
        .run()
        .unwrap();
    assert!(!tight.verdict.passed);
    assert!(tight.verdict.shortfalls[0].contains("normal resultant"));
    // An elasticity case has no resultants to judge.
    let e1: Arc<dyn ExactSolution> = case_by_name("E1", Lame::default()).unwrap().into();
    let result = Study::new(e1, MeshPairing::single(MeshFamily::Quads))
        .sizes([2, 4])
        .expect(Expectation::Resultants { tolerance: 1.0 })
        .run()
        .unwrap();
    assert!(!result.verdict.passed);
}

/// The registry holds the built-in names in order, takes a user case once, and a user case
/// runs like a built-in one.
#[test]
fn case_registry_names_and_user_cases() {
    let mut cases = CaseRegistry::builtin();
    assert_eq!(cases.names(), CASE_NAMES.to_vec());
    assert_eq!(cases.expectation("M1"), Some(Expectation::OPTIMAL_RATES));
    assert!(matches!(
        cases.expectation("ptc2"),
        Some(Expectation::Exact { .. })
    ));
    cases
        .register(
            "M2-variable-gF",
            "M2 with g_F(x) = 1/4 + 2 (x_s - x)_+^2",
            Expectation::OPTIMAL_RATES,
            |_| m2_with_variable_bound(),
        )
        .unwrap();
    assert!(cases
        .register("m1", "a second M1", Expectation::OPTIMAL_RATES, |l| {
            Arc::new(FamilyA::m1(l))
        })
        .is_err());
    assert!(cases.names().ends_with(&["M2-variable-gF"]));
    let user = cases.make("m2-variable-gf", Lame::default()).unwrap();
    assert_eq!(user.name(), "M2-variable-gF");
    // Same fields as M2 at any point.
    let m2 = cases.make("M2", Lame::default()).unwrap();
    let x = Point::new(0.3, 0.4);
    assert_eq!(
        user.displacement(BodyId::One, x),
        m2.displacement(BodyId::One, x)
    );
    let unknown = cases.make("M9", Lame::default()).err().unwrap().to_string();
    assert!(unknown.contains("M2-variable-gF"), "{unknown}");
}
