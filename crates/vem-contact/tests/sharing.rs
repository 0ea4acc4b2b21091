//! Solvers of one structure share their factorisation work: the blocks' orders and analyses,
//! the numeric factors of the stiffness, the pattern and analysis of the Newton matrices. The
//! counters of each solve show what it computed; answers do not depend on what was shared.

use std::sync::Arc;

use vem_contact::{
    ActiveSetSolver, CondensedSolver, ContactLaw, ContactProblem, ContactResult, Coulomb,
    PenaltySolver, Tresca,
};
use vem_elastic::{Component, Dirichlet, ElasticBody, Material, Plane};
use vem_mesh::generators::{structured_quads, Rectangle};
use vem_mesh::{Point, Vector};
use vem_space::LowestOrderVem;

/// Two blocks on non-matching meshes, the upper pushed down by 0.03 on its top.
fn blocks(law: impl ContactLaw + 'static) -> ContactProblem {
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
    let upper = ElasticBody::builder("upper", square(0.0, 5), material, element.clone())
        .dirichlet(Dirichlet::prescribed("top", Component::All, |_| {
            Vector::new(0.004, -0.03)
        }))
        .build()
        .unwrap();
    let lower = ElasticBody::builder("lower", square(-1.0, 7), material, element)
        .dirichlet(Dirichlet::prescribed("bottom", Component::All, |_| {
            Vector::zeros()
        }))
        .build()
        .unwrap();
    ContactProblem::two_bodies(upper, "bottom", lower, "top", law)
}

fn largest_force_difference(a: &ContactResult, b: &ContactResult) -> f64 {
    a.nodes
        .iter()
        .zip(&b.nodes)
        .map(|(x, y)| {
            (x.normal_force - y.normal_force)
                .abs()
                .max((x.friction_t() - y.friction_t()).abs())
        })
        .fold(0.0, f64::max)
}

#[test]
fn solvers_of_one_discretisation_share_analyses_and_factors() {
    let mut d = blocks(Tresca::try_new(0.01).unwrap()).discretise().unwrap();
    let mut first = CondensedSolver::default();
    let a = d.solve(&mut first).unwrap();
    assert_eq!(a.work.symbolic_analyses, 2, "{:?}", a.work);
    assert_eq!(a.work.numeric_factorisations, 2, "{:?}", a.work);

    // A second condensed solver finds both factors: nothing analysed or factorised, the same
    // answer bit for bit.
    let mut second = CondensedSolver::default();
    let b = d.solve(&mut second).unwrap();
    assert_eq!(b.work.symbolic_analyses, 0, "{:?}", b.work);
    assert_eq!(b.work.numeric_factorisations, 0, "{:?}", b.work);
    assert_eq!(largest_force_difference(&a, &b), 0.0);

    // The active-set solver analyses the coupled pattern once (on the blocks' shared orders);
    // the penalty solver then finds that analysis too.
    let mut active = ActiveSetSolver::default();
    let c = d.solve(&mut active).unwrap();
    assert_eq!(c.work.symbolic_analyses, 1, "{:?}", c.work);
    assert!(c.work.numeric_factorisations >= 1, "{:?}", c.work);
    let mut penalty = PenaltySolver::default();
    let p = d.solve(&mut penalty).unwrap();
    assert_eq!(p.work.symbolic_analyses, 0, "{:?}", p.work);
    // Two exact methods agree (another algorithm, another matrix, the same orders).
    let scale = a.normal_resultant();
    assert!(
        largest_force_difference(&a, &c) < 1e-9 * scale,
        "{} vs {}",
        largest_force_difference(&a, &c),
        scale
    );

    // New stiffness values: the analyses are kept, the factors are new.
    d.set_material(0, Material::from_lame(1.0, 0.5, Plane::Strain).unwrap())
        .unwrap();
    let refilled = d.solve(&mut first).unwrap();
    assert_eq!(refilled.work.symbolic_analyses, 0, "{:?}", refilled.work);
    assert_eq!(
        refilled.work.numeric_factorisations, 2,
        "{:?}",
        refilled.work
    );
    let again = d.solve(&mut second).unwrap();
    assert_eq!(again.work.numeric_factorisations, 0, "{:?}", again.work);
    assert_eq!(largest_force_difference(&refilled, &again), 0.0);

    // Nothing outlives the solvers that hold it.
    drop((first, second, active, penalty));
    let fresh = d.solve(&mut CondensedSolver::default()).unwrap();
    assert_eq!(fresh.work.symbolic_analyses, 2, "{:?}", fresh.work);
    assert_eq!(fresh.work.numeric_factorisations, 2, "{:?}", fresh.work);
    assert_eq!(largest_force_difference(&refilled, &fresh), 0.0);
}

#[test]
fn a_second_coulomb_fixed_point_costs_no_factorisation() {
    let d = blocks(Coulomb::try_new(0.3).unwrap()).discretise().unwrap();
    let mut first = CondensedSolver::default();
    let a = d.solve(&mut first).unwrap();
    // The held start and at least one Tresca step: two solves or more.
    let steps = a.fixed_point.as_ref().unwrap().steps;
    assert!(steps >= 1, "{:?}", a.fixed_point);
    // One analysis and one factorisation per body for the whole fixed point.
    assert_eq!(a.work.symbolic_analyses, 2, "{:?}", a.work);
    assert_eq!(a.work.numeric_factorisations, 2, "{:?}", a.work);
    // Another solver on the same discretisation (another load factor): none at all.
    let mut second = CondensedSolver::default();
    let b = d.solve_scaled(&mut second, 0.5).unwrap();
    assert_eq!(b.work.symbolic_analyses, 0, "{:?}", b.work);
    assert_eq!(b.work.numeric_factorisations, 0, "{:?}", b.work);
    // The penalty solver's fixed point: one analysis of its coupled pattern, whatever the
    // number of steps.
    let p = d.solve(&mut PenaltySolver::default()).unwrap();
    assert_eq!(p.work.symbolic_analyses, 1, "{:?}", p.work);
    assert!(p.work.numeric_factorisations > steps, "{:?}", p.work);
}
