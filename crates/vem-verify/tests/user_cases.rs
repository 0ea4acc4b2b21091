//! A user's own cases through the study: a Tresca case with a friction bound g_F(x) that
//! varies along the interface, a Coulomb case, resultant judging and the case registry.
//!
//! Each user case is built from the fields of a built-in one whose exact solution also
//! satisfies the user's law, so the exact answer is known independently:
//! - M2 solves Tresca with any bound `g(x) >= |sigma_1tau(x)|` that equals `g_F = 1/4` on the
//!   slip set `(x_s, 1]`: there `|sigma_1tau| = 1/4`, and on the stick set there is no slip;
//! - PTC2 (constant pressure `(lambda + 2 mu)/100`, `sigma_1tau = -1/4`, slipping) solves
//!   Coulomb with `F = (1/4) / ((lambda + 2 mu)/100)`, for then `F |sigma_nu| = 1/4`.

use std::sync::Arc;

use vem_contact::{ContactLaw, ContactSolver, ExactSettings, FixedPointSettings, FrictionBound};
use vem_mesh::generators::{MeshFamily, Rectangle};
use vem_mesh::{Point, Vector};
use vem_verify::cases::CaseRegistry;
use vem_verify::exact::{
    case_by_name, BodyId, ContactPatch, ExactContact, ExactSolution, ExpectedSets, FamilyA,
    InterfaceValues, Lame, Resultants, Side, CASE_NAMES, FAMILY_A_FRICTION_BOUND,
    STICK_SLIP_POINT,
};
use vem_verify::nalgebra::Matrix2;
use vem_verify::problem::{DiscreteProblem, ProblemSettings};
use vem_verify::study::{Expectation, MeshPairing, SolverChoice, Study};

/// A user's case: the fields of a built-in two-body case `inner`, its own name and law.
struct SameFields<C> {
    name: &'static str,
    inner: C,
    law: ContactLaw,
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
    fn law(&self) -> ContactLaw {
        self.law.clone()
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
        law: ContactLaw::Tresca {
            friction_bound: FrictionBound::Field(Arc::new(|x: Point| variable_bound(x.x))),
        },
    })
}

fn tight_solver() -> SolverChoice {
    SolverChoice::Exact(
        ExactSettings::builder()
            .eps_abs(1e-12)
            .eps_rel(1e-12)
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
    let mut solver = tight_solver().solver();
    let result = problem
        .contact_problem()
        .unwrap()
        .solve(&mut *solver as &mut dyn ContactSolver)
        .unwrap();
    for node in &result.nodes {
        let bound = node.tributary_length * variable_bound(node.position.x);
        assert!(
            node.tangential_force.abs() <= bound * (1.0 + 1e-6),
            "{node:?}"
        );
        if node.position.x < STICK_SLIP_POINT - 0.35 {
            // The exact margin here is at least 2 (x_s - x)^2 > 0.24: far from the bound.
            assert!(node.tangential_force.abs() < 0.5 * bound, "{node:?}");
        }
    }
}

/// Coulomb through the study: the patch test PTC2 is reproduced exactly, every node slips,
/// and the fixed point is reported.
#[test]
fn coulomb_patch_test_is_exact_through_the_study() {
    let lame = Lame::default();
    let pressure = (lame.lambda() + 2.0 * lame.mu()) / 100.0;
    let coefficient = 0.25 / pressure;
    let exact: Arc<dyn ExactSolution> = Arc::new(SameFields {
        name: "PTC2-coulomb",
        inner: ContactPatch::ptc2(lame),
        law: ContactLaw::Coulomb {
            coefficient,
            fixed_point: FixedPointSettings::default(),
        },
    });
    let result = Study::new(exact, "quads/hexagons".parse().unwrap())
        .sizes([2, 4])
        .solver(tight_solver())
        .expect(Expectation::Exact { tolerance: 1e-7 })
        .also_expect(Expectation::Resultants { tolerance: 1e-7 })
        .run()
        .unwrap();
    assert_eq!(result.law, "coulomb");
    assert!(result.verdict.passed, "{:?}", result.verdict);
    for record in &result.records {
        let contact = record.contact.as_ref().unwrap();
        assert_eq!((contact.slip, contact.nodes), (contact.nodes, contact.active));
        let steps = record.fixed_point_steps.expect("a Coulomb record");
        assert!((1..=10).contains(&steps), "{steps} fixed-point steps");
        assert!(record.fixed_point_change.unwrap() < 1e-6, "{record:?}");
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
