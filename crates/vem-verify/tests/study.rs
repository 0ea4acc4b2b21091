//! Studies through the whole path (meshes, problem, solve, measures, rates, report): rates of
//! E1, exact patch tests, contact diagnostics, report round trips.

use std::sync::Arc;

use vem_contact::{ContactSolver, ExactSettings, ExactSolver, SolverRegistry};
use vem_mesh::generators::MeshFamily;
use vem_space::Options;
use vem_verify::exact::{case_by_name, ExactSolution, Lame};
use vem_verify::report::{plot_svg, study_markdown, summary_markdown, write_json};
use vem_verify::study::{
    fitted_rate, successive_rates, Expectation, MeshPairing, Study, StudyResult,
};
use vem_verify::VerifyError;

fn case(name: &str) -> Arc<dyn ExactSolution> {
    case_by_name(name, Lame::default()).unwrap().into()
}

/// The built-in solvers and "exact-tight": Clarabel with tight tolerances, for the patch tests
/// are exact up to the solver's accuracy (`docs/manufactured.md`, section 7).
fn tight_solver() -> SolverRegistry {
    let mut solvers = SolverRegistry::builtin();
    solvers
        .register("exact-tight", "Clarabel at 1e-12", |options: &Options| {
            options.refuse_all("exact-tight")?;
            let settings = ExactSettings::builder()
                .eps_abs(1e-12)
                .eps_rel(1e-12)
                .build()?;
            Ok(Box::new(ExactSolver::new(settings)) as Box<dyn ContactSolver>)
        })
        .unwrap();
    solvers
}

#[test]
fn e1_converges_at_the_optimal_rates_on_quads() {
    let result = Study::new(case("E1"), MeshPairing::single(MeshFamily::Quads))
        .sizes([4, 8, 16])
        .run()
        .unwrap();
    assert!(result.verdict.passed, "{:?}", result.verdict);
    let rates = result.rates;
    assert_eq!(rates.fitted, 3);
    assert!(
        rates.grad.unwrap() > 0.95 && rates.grad.unwrap() < 1.1,
        "{rates:?}"
    );
    assert!(rates.l2.unwrap() > 1.9, "{rates:?}");
    // The errors halve (E_grad) and quarter (E_0) with h; h halves exactly on quads.
    let [a, b, c] = [0, 1, 2].map(|k| &result.records[k]);
    assert_eq!((a.h / b.h, b.h / c.h), (2.0, 2.0));
    assert_eq!((a.n.clone(), c.n.clone()), (vec![4], vec![16]));
    assert_eq!(c.dofs, 2 * 15 * 15);
    assert!(result.records.iter().all(|r| r.contact.is_none()));
}

/// PT0a (linear, Dirichlet all round) is reproduced to round-off on Voronoi cells.
#[test]
fn pt0a_is_exact_through_the_study() {
    let result = Study::new(case("PT0a"), MeshPairing::single(MeshFamily::Voronoi))
        .sizes([2, 4, 8])
        .expect(Expectation::Exact { tolerance: 1e-10 })
        .run()
        .unwrap();
    assert!(result.verdict.passed, "{:?}", result.verdict);
    for record in &result.records {
        let e = record.errors;
        assert!(e.grad < 1e-10 && e.energy < 1e-10 && e.l2 < 1e-10, "{e:?}");
        assert!((e.exact_l2.powi(2) - 0.27).abs() < 1e-12);
    }
}

/// The contact patch test PTC1 (frictionless, pushed together, free slip) on non-matching
/// meshes, quads with 2n over quads with 3n cells across: the discrete solution is the exact
/// linear field, every node is active and the nodal forces sum to the exact resultant
/// `-int sigma_nu = 0.04`.
///
/// (The pairing has no nearly coincident nodes: interface insertion snaps a node closer than
/// 1e-3 edge lengths to an existing one, and the patch test is then exact only up to that
/// misfit, e.g. a relative error 8e-6 for Voronoi over 1:3 quads at n = 2, where a Voronoi
/// node at x = 0.5000072 snaps to 0.5.)
#[test]
fn ptc1_is_exact_through_the_study_on_non_matching_meshes() {
    let pairing: MeshPairing = "quads*2/quads*3".parse().unwrap();
    let result = Study::new(case("PTC1"), pairing)
        .sizes([2, 3])
        .registry(tight_solver())
        .solver("exact-tight")
        .expect(Expectation::Exact { tolerance: 1e-9 })
        .run()
        .unwrap();
    assert!(result.verdict.passed, "{:?}", result.verdict);
    for record in &result.records {
        assert!(
            record.inserted_nodes.unwrap() > 0,
            "the meshes must not match"
        );
        let contact = record.contact.as_ref().unwrap();
        assert_eq!(contact.active, contact.nodes);
        assert!(
            contact.set_violations.is_empty(),
            "{:?}",
            contact.set_violations
        );
        assert!((contact.normal_resultant_exact - 0.04).abs() < 1e-15);
        assert!(contact.normal_resultant_error < 1e-9, "{contact:?}");
        assert!(contact.tangential_resultant_error < 1e-9, "{contact:?}");
        assert!(contact.pressure_error < 1e-8, "{contact:?}");
    }
}

/// The Tresca patch test PTC2 (full slip): friction forces at their bound, exact field.
#[test]
fn ptc2_slips_everywhere_exactly() {
    let result = Study::new(case("PTC2"), "quads/hexagons".parse().unwrap())
        .sizes([2, 4])
        .registry(tight_solver())
        .solver("exact-tight")
        .expect(Expectation::Exact { tolerance: 1e-9 })
        .run()
        .unwrap();
    assert!(result.verdict.passed, "{:?}", result.verdict);
    let contact = result.finest().unwrap().contact.as_ref().unwrap();
    assert_eq!((contact.slip, contact.stick), (contact.nodes, 0));
    // int sigma_1tau = -g_F = -1/4 over the unit interface.
    assert!(
        (contact.tangential_resultant + 0.25).abs() < 1e-8,
        "{contact:?}"
    );
}

/// M1 and M2 on coarse matching quads: the contact diagnostics have the signs and sizes of
/// the exact solution, the resultant errors fall with h, the switch points are found.
#[test]
fn contact_diagnostics_of_m1_and_m2_converge() {
    for (name, normal, tangential) in [
        ("M1", (5f64.sqrt() - 1.0) / 10.0, 0.0),
        (
            "M2",
            13.0 / 12.0,
            -0.25 * (1.0 - std::f64::consts::FRAC_1_SQRT_2 / 5.0),
        ),
    ] {
        let result = Study::new(case(name), "quads/quads".parse().unwrap())
            .sizes([8, 16, 32])
            .run()
            .unwrap();
        assert!(result.verdict.passed, "{name}: {:?}", result.verdict);
        let diagnostics: Vec<_> = result
            .records
            .iter()
            .map(|r| r.contact.clone().unwrap())
            .collect();
        for d in &diagnostics {
            assert!((d.normal_resultant_exact - normal).abs() < 1e-12);
            assert!((d.tangential_resultant_exact - tangential).abs() < 1e-12);
            assert!(d.normal_resultant > 0.0);
        }
        let errors: Vec<f64> = diagnostics
            .iter()
            .map(|d| d.normal_resultant_error)
            .collect();
        assert!(
            errors[2] < errors[1] && errors[1] < errors[0],
            "{name}: {errors:?}"
        );
        let finest = diagnostics.last().unwrap();
        assert!(finest.normal_resultant_error < 1e-2 * normal, "{finest:?}");
        assert!(
            finest.set_violations.is_empty(),
            "{name}: {:?}",
            finest.set_violations
        );
        let switch = finest.contact_switch.or(finest.slip_switch).unwrap();
        assert!(switch.distance.unwrap() < 0.35, "{name}: {switch:?}");
        if name == "M2" {
            assert!(finest.tangential_resultant < 0.0);
            assert!(finest.tangential_resultant_error < 1e-3, "{finest:?}");
            assert!(finest.stick > 0 && finest.slip > 0);
        }
    }
}

/// On the coarse 8 x 8 quads the flat M1 transition leaves the node at x = 7/8 (beyond
/// x_c + 0.2) in contact: the verdict names it.
#[test]
fn a_node_contradicting_the_expected_sets_fails_the_verdict() {
    let result = Study::new(case("M1"), "quads/quads".parse().unwrap())
        .sizes([4, 8])
        .run()
        .unwrap();
    let violations = &result
        .finest()
        .unwrap()
        .contact
        .as_ref()
        .unwrap()
        .set_violations;
    assert_eq!(violations.len(), 1, "{violations:?}");
    assert_eq!(
        (violations[0].x, violations[0].expected.as_str()),
        (0.875, "open")
    );
    assert!(!result.verdict.passed);
    assert!(
        result
            .verdict
            .shortfalls
            .iter()
            .any(|s| s.contains("expected sets") && s.contains("x = 0.8750")),
        "{:?}",
        result.verdict
    );
}

#[test]
fn rates_of_exact_power_laws() {
    let h = [0.4, 0.2, 0.1, 0.05];
    let e: Vec<f64> = h.iter().map(|h| 0.3 * h * h).collect();
    assert!((fitted_rate(&h, &e).unwrap() - 2.0).abs() < 1e-12);
    let rates = successive_rates(&h, &e);
    assert_eq!(rates[0], None);
    assert!(rates[1..].iter().all(|r| (r.unwrap() - 2.0).abs() < 1e-12));
    assert_eq!(fitted_rate(&h[..1], &e[..1]), None);
    assert_eq!(fitted_rate(&[0.1, 0.1], &[1.0, 2.0]), None);
    assert_eq!(fitted_rate(&[0.2, 0.1], &[f64::NAN, 2.0]), None);
}

#[test]
fn invalid_studies_are_refused() {
    let e1 = case("E1");
    let quads = MeshPairing::single(MeshFamily::Quads);
    let refused = |study: Study| match study.run() {
        Err(error @ (VerifyError::InvalidSetting { .. } | VerifyError::Case { .. })) => {
            error.to_string()
        }
        other => panic!("{other:?}"),
    };
    assert!(refused(Study::new(e1.clone(), quads.clone()).sizes([])).contains("no sizes"));
    assert!(refused(Study::new(e1.clone(), quads.clone()).sizes([8, 4])).contains("increasing"));
    assert!(refused(Study::new(e1.clone(), quads.clone()).fitted(1)).contains("2 fitted"));
    let pair = MeshPairing::pair(MeshFamily::Quads, 1, MeshFamily::Quads, 1);
    assert!(refused(Study::new(e1, pair)).contains("1 bodies"));
    for bad in ["quads/quads*0", "quads*x", "pentagons", "quads/quads/quads"] {
        assert!(bad.parse::<MeshPairing>().is_err(), "{bad}");
    }
}

#[test]
fn reports_round_trip() {
    let result = Study::new(case("M2"), "perturbed/quads*2".parse().unwrap())
        .sizes([2, 4])
        .run()
        .unwrap();
    let markdown = study_markdown(&result);
    assert!(markdown.starts_with("### M2 (tresca) on perturbed/quads (n/2n)"));
    // Header, rule and one row per size.
    assert_eq!(markdown.lines().filter(|l| l.starts_with('|')).count(), 4);
    assert!(markdown.contains("| 4/8 |"));
    let summary = summary_markdown(std::slice::from_ref(&result));
    assert_eq!(summary.lines().count(), 3);
    let svg = plot_svg(&result).unwrap();
    assert!(svg.starts_with("<svg") && svg.contains("E_grad") && svg.contains("O(h^2)"));
    let dir = std::env::temp_dir().join(format!("vem-verify-study-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("study.json");
    write_json(&path, &result).unwrap();
    let back: StudyResult = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    assert_eq!(back, result);
    std::fs::remove_dir_all(&dir).unwrap();
    // A file in a missing directory is an error naming it.
    let err = write_json(dir.join("missing").join("x.json"), &result).unwrap_err();
    assert!(err.to_string().contains("x.json"), "{err}");
}

/// A law in place of the case's own: M1 (frictionless) solved under Tresca with the bound 0
/// is the same problem, so the same errors to the solver's accuracy; the result names the law.
/// A Coulomb case records the tolerance its fixed point stopped at. A criterion of one's own
/// enters the verdict with its name.
#[test]
fn law_override_fixed_point_tolerance_and_criteria_of_ones_own() {
    let pairing = MeshPairing::pair(MeshFamily::Quads, 1, MeshFamily::Quads, 1);
    let study = |law: Option<Arc<dyn vem_contact::ContactLaw>>| {
        let mut s = Study::new(case("M1"), pairing.clone())
            .sizes([4, 8])
            .fitted(2);
        if let Some(law) = law {
            s = s.law(law);
        }
        s.run().unwrap()
    };
    let frictionless = study(None);
    let tresca = study(Some(Arc::new(vem_contact::Tresca::try_new(0.0).unwrap())));
    assert_eq!(
        (frictionless.law.as_str(), tresca.law.as_str()),
        ("frictionless", "tresca")
    );
    for (a, b) in frictionless.records.iter().zip(&tresca.records) {
        let (ea, eb) = (a.errors.relative_grad(), b.errors.relative_grad());
        assert!((ea - eb).abs() <= 1e-8 * ea, "{ea:e} {eb:e}");
        assert_eq!(a.fixed_point_tolerance, None);
    }
    // Coulomb (a bound F p that the fixed point iterates): its tolerance is recorded.
    let coulomb = Study::new(case("M1"), pairing.clone())
        .sizes([4, 8])
        .fitted(2)
        .law(Arc::new(vem_contact::Coulomb::try_new(0.3).unwrap()))
        .run()
        .unwrap();
    assert_eq!(coulomb.law, "coulomb");
    for record in &coulomb.records {
        let tolerance = record.fixed_point_tolerance.expect("a fixed point");
        assert!(tolerance >= 1e-8, "{tolerance:e}");
        assert!(record.fixed_point_change.unwrap() <= tolerance);
    }
    // A criterion that the first size's error falls by at least 1.5 to the second, and one
    // that cannot hold.
    let halves = vem_verify::study::Criterion::new("error halves", |records, _| {
        let (coarse, fine) = (&records[0].errors, &records[1].errors);
        if coarse.relative_grad() >= 1.5 * fine.relative_grad() {
            Vec::new()
        } else {
            vec!["the error did not fall".to_string()]
        }
    });
    let never = vem_verify::study::Criterion::new("never", |_, _| vec!["by design".to_string()]);
    let judged = Study::new(case("M1"), pairing)
        .sizes([4, 8])
        .fitted(2)
        .also_check(halves)
        .also_check(never)
        .run()
        .unwrap();
    assert!(!judged.verdict.passed);
    let shortfalls = &judged.verdict.shortfalls;
    assert!(
        shortfalls.iter().any(|s| s == "never: by design"),
        "{shortfalls:?}"
    );
    assert!(
        !shortfalls.iter().any(|s| s.starts_with("error halves")),
        "{shortfalls:?}"
    );
    assert_eq!(judged.criteria, ["error halves", "never"]);
}

/// A study's problem is a scene: the meshes inline, the exact data as functions, a user's
/// element and law registered under `ELEMENT` and `LAW` and named by the scene; the contact
/// problem solved is the model's.
#[test]
fn a_study_problem_is_a_scene_with_the_users_element_and_law() {
    use vem_verify::problem::{ELEMENT, LAW};
    let pairing = MeshPairing::pair(MeshFamily::Quads, 1, MeshFamily::Quads, 2);
    let element = Arc::new(vem_space::LowestOrderVem::default());
    let law = Arc::new(vem_contact::Tresca::try_new(0.0).unwrap());
    let study = Study::new(case("M1"), pairing.clone())
        .element(element)
        .law(law);
    let problem = study.problem(4).unwrap();
    let scene = problem.scene();
    assert_eq!(scene.bodies.len(), 2);
    for (body, id) in scene.bodies.iter().zip(["M1-body-1", "M1-body-2"]) {
        assert_eq!(body.name, id);
        assert_eq!(
            body.element.as_ref().map(|c| c.name.as_str()),
            Some(ELEMENT)
        );
        assert_eq!(body.traction_points, Some(4));
        assert!(body.mesh.vertices.is_some() && body.mesh.polygons.is_some());
        assert_eq!(format!("{:?}", body.body_force), "Some(<function>)");
    }
    let contact = &scene.contacts[0];
    assert_eq!(contact.law.as_ref().map(|c| c.name.as_str()), Some(LAW));
    assert_eq!(
        (contact.part.as_str(), contact.other_part.as_deref()),
        ("bottom", Some("top"))
    );
    let registries = problem.model().registries();
    assert!(registries.elements.contains(ELEMENT));
    assert!(registries.laws.names().contains(&LAW));
    // Functions do not serialise.
    assert!(serde_json::to_string(scene).is_err());
    // The default element is the built-in vem1, by name.
    let default = Study::new(case("M1"), pairing).problem(4).unwrap();
    let element = default.scene().bodies[0].element.clone().unwrap();
    assert_eq!(element.name, "vem1");
    let (contact, _) = default.model().contact_problem().unwrap();
    assert_eq!(contact.bodies().len(), 2);
}
