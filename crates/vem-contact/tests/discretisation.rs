//! One discretisation, many solves: reused solvers agree with fresh ones, load steps scale the
//! answer, refilled values agree with a fresh build, and the counters show what was reused.

use std::sync::Arc;

use vem_contact::{
    ActiveSetSolver, CondensedSolver, ContactLaw, ContactProblem, ContactSolver, Coulomb,
    ExactSettings, ExactSolver, Frictionless, PenaltySolver, Tresca,
};
use vem_elastic::{Component, Dirichlet, ElasticBody, Material, Plane};
use vem_mesh::generators::{structured_quads, Rectangle};
use vem_mesh::{Point, Vector};
use vem_space::LowestOrderVem;

/// Two blocks on non-matching meshes, the upper pushed down by `push` on its top.
fn blocks(law: impl ContactLaw + 'static, push: f64) -> ContactProblem {
    blocks_of(
        law,
        push,
        Material::from_lame(2.0, 1.0, Plane::Strain).unwrap(),
    )
}

/// [`blocks`] with the upper block of `upper_material`.
fn blocks_of(
    law: impl ContactLaw + 'static,
    push: f64,
    upper_material: Material,
) -> ContactProblem {
    let material = Material::from_lame(2.0, 1.0, Plane::Strain).unwrap();
    let element = Arc::new(LowestOrderVem::default());
    let square = |y0: f64, n: usize| {
        structured_quads(
            &Rectangle::new(Point::new(0.0, y0), Point::new(1.0, y0 + 1.0)),
            n,
            n,
        )
        .unwrap()
    };
    let upper = ElasticBody::builder("upper", square(0.0, 3), upper_material, element.clone())
        .dirichlet(Dirichlet::prescribed("top", Component::Y, move |_| {
            Vector::new(0.0, -push)
        }))
        .dirichlet(Dirichlet::prescribed("left", Component::X, |_| {
            Vector::zeros()
        }))
        .traction("right", |x| Vector::new(0.0, 0.02 * x.y))
        .build()
        .unwrap();
    let lower = ElasticBody::builder("lower", square(-1.0, 4), material, element)
        .dirichlet(Dirichlet::prescribed("bottom", Component::Y, |_| {
            Vector::zeros()
        }))
        .dirichlet(Dirichlet::prescribed("left", Component::X, |_| {
            Vector::zeros()
        }))
        .build()
        .unwrap();
    ContactProblem::two_bodies(upper, "bottom", lower, "top", law)
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

fn max_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).fold(0.0, |m, (x, y)| m.max((x - y).abs()))
}

#[test]
fn a_reused_solver_agrees_with_a_fresh_one() {
    let discretisation = blocks(Tresca::try_new(0.004).unwrap(), 0.03)
        .discretise()
        .unwrap();
    let solvers: Vec<(Box<dyn ContactSolver>, Box<dyn ContactSolver>)> = vec![
        (Box::new(tight_exact()), Box::new(tight_exact())),
        (
            Box::new(CondensedSolver::default()),
            Box::new(CondensedSolver::default()),
        ),
        (
            Box::new(PenaltySolver::default()),
            Box::new(PenaltySolver::default()),
        ),
        (
            Box::new(ActiveSetSolver::default()),
            Box::new(ActiveSetSolver::default()),
        ),
    ];
    for (mut reused, mut fresh) in solvers {
        // A first solve at another load leaves work in the reused solver.
        reused
            .solve(&discretisation_scaled(&discretisation, 0.5))
            .unwrap();
        let a = reused.solve(&discretisation.system()).unwrap();
        let b = fresh.solve(&discretisation.system()).unwrap();
        let scale = b.normal_force.iter().fold(0.0_f64, |m, f| m.max(f.abs()));
        assert!(
            max_difference(&a.normal_force, &b.normal_force) < 1e-7 * scale,
            "{}: reused {:?} fresh {:?}",
            a.report.solver,
            a.normal_force,
            b.normal_force
        );
        // The reused Newton solvers analysed the pattern once.
        assert!(a.report.work.symbolic_analyses == 0, "{:?}", a.report.work);
    }
}

fn discretisation_scaled(
    d: &vem_contact::ContactDiscretisation,
    factor: f64,
) -> vem_contact::ContactSystem<'_> {
    let system = d.system();
    let load: Vec<f64> = system.load().iter().map(|f| factor * f).collect();
    system.with_load(load).unwrap()
}

#[test]
fn a_load_step_scales_a_fully_closed_contact() {
    // The blocks touch along the whole interface at every load factor: the problem is linear
    // there, so every force scales with the load factor.
    let d = blocks(Frictionless, 0.03).discretise().unwrap();
    for mut solver in [
        Box::new(ActiveSetSolver::default()) as Box<dyn ContactSolver>,
        Box::new(CondensedSolver::default()),
    ] {
        let solver = &mut *solver;
        let full = d.solve(solver).unwrap();
        let half = d.solve_scaled(solver, 0.5).unwrap();
        let scale = full.normal_resultant();
        for (a, b) in full.nodes.iter().zip(&half.nodes) {
            assert!((0.5 * a.normal_force - b.normal_force).abs() < 1e-12 * scale);
            assert!((0.5 * a.normal_jump - b.normal_jump).abs() < 1e-14);
        }
        // Equilibrium of the upper block at half load: support reaction + contact force + applied
        // traction = 0 (vertical), the traction 0.02 y on x = 1 having resultant 0.01 at full load.
        let upper = &half.bodies[0].solution;
        let support: f64 = upper.reactions().iter().map(|r| r.force.y).sum();
        let contact = half.force_on_body_a().y;
        assert!(
            (support + contact + 0.5 * 0.01).abs() < 1e-12,
            "{support} {contact}"
        );
        // Twice the load: still closed everywhere, every node in contact, forces doubled.
        let double = d.solve_scaled(solver, 2.0).unwrap();
        for (a, b) in full.nodes.iter().zip(&double.nodes) {
            assert_ne!(b.status, vem_contact::NodeStatus::Open, "{b:?}");
            assert!((2.0 * a.normal_force - b.normal_force).abs() < 1e-12 * scale);
        }
        // No assembly and no symbolic analysis for the second solve.
        assert_eq!(half.work.assemblies, 0);
        assert_eq!(half.work.symbolic_analyses, 0);
        if half.report.solver.starts_with("condensed") {
            // Nor any factorisation: only the load changed.
            assert_eq!(half.work.numeric_factorisations, 0);
        } else {
            assert!(half.work.numeric_factorisations >= 1);
        }
    }
}

#[test]
fn coulomb_costs_one_assembly_and_one_symbolic_analysis() {
    let law = Coulomb::try_new(0.3).unwrap();
    for mut solver in [
        Box::new(PenaltySolver::default()) as Box<dyn ContactSolver>,
        Box::new(ActiveSetSolver::default()),
        Box::new(tight_exact()),
        Box::new(CondensedSolver::default()),
    ] {
        let result = blocks(law, 0.03).solve(&mut *solver).unwrap();
        let steps = result.fixed_point.as_ref().unwrap().steps;
        assert!(steps >= 1);
        assert_eq!(result.work.assemblies, 2, "one per body"); // built once
        if result.report.solver.starts_with("condensed") {
            // One analysis and one factorisation per body for the whole fixed point.
            assert_eq!(result.work.symbolic_analyses, 2);
            assert_eq!(result.work.numeric_factorisations, 2);
            continue;
        }
        assert_eq!(result.work.symbolic_analyses, 1, "{}", result.report.solver);
        assert!(result.work.numeric_factorisations > steps);
        // Coulomb's law node by node.
        for node in &result.nodes {
            assert!(node.friction_t().abs() <= 0.3 * node.normal_force * (1.0 + 1e-6) + 1e-12);
        }
    }
}

#[test]
fn a_refilled_material_agrees_with_a_fresh_build() {
    let problem = blocks(Tresca::try_new(0.004).unwrap(), 0.03);
    let mut d = problem.discretise().unwrap();
    let softer = Material::from_lame(1.0, 0.5, Plane::Strain).unwrap();
    let mut solver = ActiveSetSolver::default();
    d.solve(&mut solver).unwrap();
    d.set_material(0, softer).unwrap();
    let refilled = d.solve(&mut solver).unwrap();
    assert_eq!(refilled.work.symbolic_analyses, 0);
    // A fresh build with the softer material on body A.
    let fresh = blocks_of(problem.pairs()[0].law().clone(), 0.03, softer)
        .solve(&mut ActiveSetSolver::default())
        .unwrap();
    let scale = fresh.normal_resultant();
    for (a, b) in refilled.nodes.iter().zip(&fresh.nodes) {
        assert!((a.normal_force - b.normal_force).abs() < 1e-10 * scale);
        assert!((a.friction_t() - b.friction_t()).abs() < 1e-10 * scale);
    }
}

/// At stiffness contrasts of 1e6, 1e7 and 1e8 either way the condensed solver's forces
/// converge to the limit of a rigid body like `1 / contrast`: each tenfold contrast changes
/// them ten times less (round-off would break the sequence). Where the active-set solver
/// converges its answer agrees to its accuracy on such data (1e-3: its stationarity is relative
/// to the stiff body's internal forces); with Tresca friction and a soft upper body its
/// stick/slip split cycles, which the condensed solver cannot do.
#[test]
fn stiffness_contrasts_up_to_1e8_converge_to_the_rigid_limit() {
    for upper_is_stiff in [true, false] {
        let laws: [Arc<dyn ContactLaw>; 2] = [
            Arc::new(Frictionless),
            Arc::new(Tresca::try_new(0.004).unwrap()),
        ];
        for law in laws {
            let forces: Vec<Vec<f64>> = [1e6, 1e7, 1e8]
                .iter()
                .map(|&contrast| {
                    let ratio = if upper_is_stiff {
                        contrast
                    } else {
                        1.0 / contrast
                    };
                    let upper = Material::from_lame(2.0 * ratio, ratio, Plane::Strain).unwrap();
                    let problem = blocks_of(law.clone(), 0.03, upper);
                    let c = problem.solve(&mut CondensedSolver::default()).unwrap();
                    assert!(c.report.residuals.stationarity < 1e-12, "{:?}", c.report);
                    if let Ok(a) = problem.solve(&mut ActiveSetSolver::default()) {
                        let scale = c.nodes.iter().fold(0.0f64, |m, n| m.max(n.normal_force));
                        for (x, y) in c.nodes.iter().zip(&a.nodes) {
                            assert!((x.normal_force - y.normal_force).abs() < 1e-3 * scale);
                            assert!((x.friction_t() - y.friction_t()).abs() < 1e-3 * scale);
                        }
                    }
                    c.nodes
                        .iter()
                        .flat_map(|n| [n.normal_force, n.friction_t()])
                        .collect()
                })
                .collect();
            let change = |a: &[f64], b: &[f64]| {
                a.iter()
                    .zip(b)
                    .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
            };
            let (first, second) = (
                change(&forces[0], &forces[1]),
                change(&forces[1], &forces[2]),
            );
            let ratio = second / first;
            assert!(
                (0.05..0.2).contains(&ratio),
                "upper stiff {upper_is_stiff}, {law:?}: changes {first:e}, {second:e}"
            );
        }
    }
}

#[test]
fn a_problem_given_up_discretises_as_a_borrowed_one() {
    // `into_discretisation` drops the original meshes before the assembly; the system it
    // builds and the forces it gives are those of `discretise`, bit for bit.
    let problem = blocks(Frictionless, 0.03);
    let borrowed = problem.discretise().unwrap();
    let owned = problem.clone().into_discretisation().unwrap();
    assert_eq!(owned.n_dofs(), borrowed.n_dofs());
    assert_eq!(owned.gap(), borrowed.gap());
    for (a, b) in owned.systems().iter().zip(borrowed.systems()) {
        assert_eq!(a.stiffness().val(), b.stiffness().val());
        assert_eq!(a.rhs(), b.rhs());
    }
    let mut solver = ActiveSetSolver::default();
    let (a, b) = (
        owned.solve(&mut solver).unwrap(),
        borrowed.solve(&mut solver).unwrap(),
    );
    for (x, y) in a.nodes.iter().zip(&b.nodes) {
        assert_eq!(x.normal_force, y.normal_force);
    }
}
