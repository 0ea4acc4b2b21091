//! Load histories: per-condition factors against problems built with the scaled data, the
//! static problem as the one-step history, friction on the slip increments (path dependence,
//! every solver honouring the reference slip), the work of a step, and the refusals.

use std::sync::Arc;

use vem_contact::{
    ActiveSetSolver, CondensedSolver, ContactError, ContactLaw, ContactProblem, ContactResult,
    ContactSolver, Coulomb, ExactSolver, Frictionless, LoadCondition, LoadCurve, LoadCurves,
    LoadFactors, LoadHistory, LoadPath, PenaltySolver, Tresca,
};
use vem_elastic::{Component, Dirichlet, ElasticBody, Material, Plane};
use vem_mesh::generators::{structured_quads, voronoi, Rectangle};
use vem_mesh::{Point, Vector};
use vem_space::LowestOrderVem;

const PRESS: f64 = 0.01;
const SHIFT: f64 = 0.002;

/// The factors of the upper block's conditions (press, shift, traction, body force); the
/// lower block's clamp has no data.
#[derive(Debug, Clone, Copy)]
struct Factors {
    press: f64,
    shift: f64,
    traction: f64,
    gravity: f64,
}

const PRESS_C: LoadCondition = LoadCondition::Dirichlet { body: 0, index: 0 };
const SHIFT_C: LoadCondition = LoadCondition::Dirichlet { body: 0, index: 1 };
const TRACTION_C: LoadCondition = LoadCondition::Traction { body: 0, index: 0 };
const GRAVITY_C: LoadCondition = LoadCondition::BodyForce { body: 0 };

impl Factors {
    fn load_factors(self) -> LoadFactors {
        LoadFactors::uniform(1.0)
            .with(PRESS_C, self.press)
            .with(SHIFT_C, self.shift)
            .with(TRACTION_C, self.traction)
            .with(GRAVITY_C, self.gravity)
    }
}

/// An upper block `[0, 1] x [0, 1]` (Voronoi cells) pressed down and moved sideways at its top,
/// pulled sideways on its left side and loaded by its weight, on a lower block `[-0.2, 1.2] x
/// [-1, 0]` (quads) clamped at its bottom; each datum scaled by its factor in `f`.
fn blocks(f: Factors, law: impl ContactLaw + 'static) -> ContactProblem {
    let material = Material::from_young_poisson(100.0, 0.3, Plane::Strain).unwrap();
    let element = Arc::new(LowestOrderVem::default());
    let upper_mesh = voronoi(
        &Rectangle::new(Point::new(0.0, 0.0), Point::new(1.0, 1.0)),
        7,
        3,
    )
    .unwrap();
    let lower_mesh = structured_quads(
        &Rectangle::new(Point::new(-0.2, -1.0), Point::new(1.2, 0.0)),
        11,
        8,
    )
    .unwrap();
    let upper = ElasticBody::builder("upper", upper_mesh, material, element.clone())
        .dirichlet(Dirichlet::prescribed("top", Component::Y, move |_| {
            Vector::new(0.0, -f.press * PRESS)
        }))
        .dirichlet(Dirichlet::prescribed("top", Component::X, move |x| {
            Vector::new(f.shift * SHIFT * (1.0 + 0.2 * x.x), 0.0)
        }))
        .traction("left", move |x| Vector::new(0.05 * f.traction * x.y, 0.0))
        .body_force(move |_| Vector::new(0.0, -0.02 * f.gravity))
        .build()
        .unwrap();
    let lower = ElasticBody::builder("lower", lower_mesh, material, element)
        .clamp("bottom")
        .build()
        .unwrap();
    ContactProblem::two_bodies(upper, "bottom", lower, "top", law)
}

/// Largest difference of the nodal forces and of the body displacements (relative to their
/// own scales) between two answers.
fn differences(a: &ContactResult, b: &ContactResult) -> (f64, f64) {
    let scale = a
        .nodes
        .iter()
        .fold(0.0f64, |m, n| m.max(n.normal_force.abs()))
        .max(1e-300);
    let forces = a.nodes.iter().zip(&b.nodes).fold(0.0f64, |m, (x, y)| {
        m.max((x.normal_force - y.normal_force).abs())
            .max((x.friction_force - y.friction_force).norm())
    }) / scale;
    let mut displacement = 0.0f64;
    for (x, y) in a.bodies.iter().zip(&b.bodies) {
        let (u, v) = (x.solution.displacement(), y.solution.displacement());
        let s = u.iter().fold(0.0f64, |m, w| m.max(w.abs())).max(1e-300);
        let d = u
            .iter()
            .zip(v)
            .fold(0.0f64, |m, (p, q)| m.max((p - q).abs()));
        displacement = displacement.max(d / s);
    }
    (forces, displacement)
}

/// The steps of a history: pressing with the weight, then the traction and the shift with
/// curves of their own, the shift back and forth.
fn steps() -> Vec<Factors> {
    vec![
        Factors {
            press: 0.5,
            shift: 0.0,
            traction: 0.0,
            gravity: 1.0,
        },
        Factors {
            press: 1.0,
            shift: 0.0,
            traction: 0.3,
            gravity: 1.0,
        },
        Factors {
            press: 1.0,
            shift: 0.6,
            traction: 1.0,
            gravity: 1.0,
        },
        Factors {
            press: 1.0,
            shift: 1.0,
            traction: -0.5,
            gravity: 1.2,
        },
        Factors {
            press: 0.8,
            shift: -0.4,
            traction: -1.0,
            gravity: 1.2,
        },
        Factors {
            press: 1.2,
            shift: 0.2,
            traction: 0.0,
            gravity: 0.0,
        },
    ]
}

#[test]
fn a_frictionless_history_is_the_static_problem_at_every_step() {
    let discretisation = blocks(
        Factors {
            press: 1.0,
            shift: 1.0,
            traction: 1.0,
            gravity: 1.0,
        },
        Frictionless,
    )
    .discretise()
    .unwrap();
    let history = LoadHistory::from_steps(steps().iter().map(|f| f.load_factors()).collect());
    let answers = discretisation
        .solve_history(&mut CondensedSolver::default(), &history)
        .unwrap();
    for (step, f) in answers.iter().zip(steps()) {
        // The problem built with the scaled data, solved from rest.
        let fresh = blocks(f, Frictionless)
            .solve(&mut CondensedSolver::default())
            .unwrap();
        let (forces, displacement) = differences(&step.result, &fresh);
        assert!(
            forces < 1e-9,
            "step {}: forces differ by {forces:e}",
            step.index
        );
        assert!(
            displacement < 1e-9,
            "step {}: displacements differ by {displacement:e}",
            step.index
        );
        // The reactions too: they balance the scaled loads of the body force and traction.
        for (a, b) in step.result.bodies.iter().zip(&fresh.bodies) {
            for (ra, rb) in a.solution.reactions().iter().zip(b.solution.reactions()) {
                let difference = (ra.force - rb.force).norm();
                assert!(
                    difference < 1e-9 * rb.force.norm().max(1e-3),
                    "step {}: reaction on '{}' {} vs {}",
                    step.index,
                    ra.part,
                    ra.force,
                    rb.force
                );
            }
        }
    }
}

#[test]
fn the_static_problem_is_the_one_step_history() {
    for law in [
        Arc::new(Coulomb::try_new(0.3).unwrap()) as Arc<dyn ContactLaw>,
        Arc::new(Tresca::try_new(0.02).unwrap()),
    ] {
        let f = Factors {
            press: 1.0,
            shift: 1.0,
            traction: 1.0,
            gravity: 1.0,
        };
        let discretisation = blocks(f, Arc::clone(&law)).discretise().unwrap();
        let statically = discretisation
            .solve(&mut CondensedSolver::default())
            .unwrap();
        let steps = discretisation
            .solve_history(&mut CondensedSolver::default(), &LoadHistory::single())
            .unwrap();
        let (forces, displacement) = differences(&statically, &steps[0].result);
        assert!(
            forces < 1e-10 && displacement < 1e-10,
            "{forces:e} {displacement:e}"
        );
        // Uniform factors are the scaled problem.
        let scaled = discretisation
            .solve_scaled(&mut CondensedSolver::default(), 0.7)
            .unwrap();
        let at = discretisation
            .solve_at(&mut CondensedSolver::default(), &LoadFactors::uniform(0.7))
            .unwrap();
        let (forces, displacement) = differences(&scaled, &at);
        assert!(
            forces < 1e-10 && displacement < 1e-10,
            "{forces:e} {displacement:e}"
        );
    }
}

#[test]
fn friction_remembers_the_path_and_frictionless_contact_does_not() {
    // Pressed, moved sideways and back to where it was pressed: with Tresca friction the
    // interface remembers the excursion (its forces differ from the static problem's at the
    // same load, and where it slipped back the friction opposes that last increment);
    // frictionless contact gives the static answer.
    let f = |press: f64, shift: f64| Factors {
        press,
        shift,
        traction: 0.0,
        gravity: 0.0,
    };
    let path = [f(1.0, 0.0), f(1.0, 1.0), f(1.0, 0.0)];
    let history = LoadHistory::from_steps(path.iter().map(|f| f.load_factors()).collect());
    let law = Tresca::try_new(0.01).unwrap();
    let d = blocks(f(1.0, 1.0), law.clone()).discretise().unwrap();
    let steps = d
        .solve_history(&mut CondensedSolver::default(), &history)
        .unwrap();
    let fresh = blocks(f(1.0, 0.0), law)
        .solve(&mut CondensedSolver::default())
        .unwrap();
    let (forces, _) = differences(&steps[2].result, &fresh);
    assert!(forces > 0.01, "the history forgot the shift: {forces:e}");
    // Tresca's law on the increment of the last step: where the interface slipped back, the
    // friction is at its bound and opposes that increment, whatever the total slip.
    let (back, forth) = (&steps[2].result, &steps[1].result);
    let largest = back
        .nodes
        .iter()
        .zip(&forth.nodes)
        .fold(0.0f64, |m, (b, f)| m.max((b.slip_t() - f.slip_t()).abs()));
    let mut slipped_back = 0;
    for (b, f) in back.nodes.iter().zip(&forth.nodes) {
        let increment = b.slip_t() - f.slip_t();
        let bound = 0.01 * b.tributary_measure;
        assert!(b.friction_t().abs() <= bound * (1.0 + 1e-9));
        if increment.abs() > 1e-6 * largest {
            slipped_back += 1;
            assert!((b.friction_t().abs() - bound).abs() <= 1e-9 * bound);
            assert!(
                b.friction_t() * increment < 0.0,
                "friction opposes the increment"
            );
        }
    }
    assert!(slipped_back > 0);
    let d = blocks(f(1.0, 1.0), Frictionless).discretise().unwrap();
    let steps = d
        .solve_history(&mut CondensedSolver::default(), &history)
        .unwrap();
    let fresh = blocks(f(1.0, 0.0), Frictionless)
        .solve(&mut CondensedSolver::default())
        .unwrap();
    let (forces, displacement) = differences(&steps[2].result, &fresh);
    assert!(
        forces < 1e-9 && displacement < 1e-9,
        "{forces:e} {displacement:e}"
    );
}

#[test]
fn every_solver_takes_the_reference_slip() {
    // The second step of a history starts from the first one's tangential jump: each solver
    // gets a system with a reference slip, and they agree on its answer.
    let f = |shift: f64| Factors {
        press: 1.0,
        shift,
        traction: 0.0,
        gravity: 0.0,
    };
    let history = LoadHistory::from_steps(vec![f(1.0).load_factors(), f(0.3).load_factors()]);
    let d = blocks(f(1.0), Tresca::try_new(0.01).unwrap())
        .discretise()
        .unwrap();
    let reference = d
        .solve_history(&mut CondensedSolver::default(), &history)
        .unwrap();
    let reference = &reference[1].result;
    let solvers: [(Box<dyn ContactSolver>, f64); 3] = [
        (Box::new(ExactSolver::default()), 1e-3),
        (Box::new(PenaltySolver::default()), 1e-2),
        (Box::new(ActiveSetSolver::default()), 1e-8),
    ];
    for (mut solver, tolerance) in solvers {
        let name = solver.name();
        match d.solve_history(solver.as_mut(), &history) {
            Ok(steps) => {
                let (forces, _) = differences(reference, &steps[1].result);
                assert!(forces < tolerance, "{name}: forces differ by {forces:e}");
            }
            // The active set may cycle on mixed stick and slip (docs/contact.md): it must
            // then say so, not answer wrongly.
            Err(ContactError::Solver(e)) if name.starts_with("active") => {
                assert!(e.to_string().contains("did not converge"), "{e}")
            }
            Err(e) => panic!("{name}: {e}"),
        }
    }
}

#[test]
fn a_step_reuses_the_factorisations_and_one_back_substitution_per_body() {
    let f = Factors {
        press: 1.0,
        shift: 1.0,
        traction: 1.0,
        gravity: 1.0,
    };
    let d = blocks(f, Coulomb::try_new(0.3).unwrap())
        .discretise()
        .unwrap();
    let shear = LoadCurve::try_new(vec![(1.0, 0.0), (2.0, 1.0), (3.0, -1.0)]).unwrap();
    let curves = LoadCurves::default()
        .with(SHIFT_C, shear)
        .with(TRACTION_C, LoadCurve::constant(0.0).unwrap());
    let history =
        LoadHistory::from_curves(LoadHistory::uniform_times(3.0, 12).unwrap(), &curves).unwrap();
    let steps = d
        .solve_history(&mut CondensedSolver::default(), &history)
        .unwrap();
    for step in &steps {
        let work = step.result.work;
        if step.index == 0 {
            assert_eq!(work.numeric_factorisations, 2, "{work:?}");
            continue;
        }
        assert_eq!(
            work.numeric_factorisations, 0,
            "step {}: {work:?}",
            step.index
        );
        assert_eq!(work.symbolic_analyses, 0, "step {}: {work:?}", step.index);
        // One back substitution per body, and one more solve only when the load leaves the
        // span of the loads solved before.
        assert!(work.triangular_solves <= 3, "step {}: {work:?}", step.index);
        assert!(step.result.fixed_point.as_ref().unwrap().steps >= 1);
    }
    // The upper block's loads span two directions (the press and the weight follow the
    // same default ramp; the shift has its curve; the traction stays 0); the lower block has
    // none: 2 solves for them in the whole history, the rest back substitutions.
    let solves: usize = steps.iter().map(|s| s.result.work.triangular_solves).sum();
    assert_eq!(solves, 2 * steps.len() + 2);
}

#[test]
fn bad_histories_are_refused_and_a_failed_step_changes_nothing() {
    let f = Factors {
        press: 1.0,
        shift: 1.0,
        traction: 1.0,
        gravity: 1.0,
    };
    let d = blocks(f, Tresca::try_new(0.01).unwrap())
        .discretise()
        .unwrap();
    let mut solver = CondensedSolver::default();
    let mut path = LoadPath::new(&d).unwrap();
    let message = |e: ContactError| e.to_string();
    let e = path
        .advance(
            &mut solver,
            1.0,
            &LoadFactors::uniform(1.0).with(LoadCondition::Dirichlet { body: 0, index: 7 }, 1.0),
        )
        .unwrap_err();
    assert!(
        message(e).contains("Dirichlet condition 7 of body 0"),
        "unknown condition"
    );
    let e = path
        .advance(&mut solver, 1.0, &LoadFactors::uniform(f64::NAN))
        .unwrap_err();
    assert!(message(e).contains("not finite"));
    let e = path
        .advance(
            &mut solver,
            1.0,
            &LoadFactors::uniform(1.0).with(LoadCondition::BodyForce { body: 3 }, 1.0),
        )
        .unwrap_err();
    assert!(message(e).contains("2 bodies"));
    assert!(path.time().is_none(), "nothing solved yet");
    let first = path.advance(&mut solver, 1.0, &f.load_factors()).unwrap();
    let e = path
        .advance(&mut solver, 1.0, &f.load_factors())
        .unwrap_err();
    assert!(message(e).contains("exceed the last step"));
    assert_eq!(path.time(), Some(1.0));
    // The same load again: nothing moves, the same answer.
    let again = path.advance(&mut solver, 2.0, &f.load_factors()).unwrap();
    let (forces, displacement) = differences(&first, &again);
    assert!(
        forces < 1e-10 && displacement < 1e-10,
        "{forces:e} {displacement:e}"
    );
    // Curves and times.
    assert!(LoadCurve::try_new(vec![]).is_err());
    assert!(LoadCurve::try_new(vec![(0.0, 1.0), (f64::INFINITY, 0.0)]).is_err());
    assert!(LoadHistory::uniform_times(0.0, 3).is_err());
    assert!(LoadHistory::from_curves([1.0, 0.5], &LoadCurves::default()).is_err());
}
