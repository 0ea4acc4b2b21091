//! probe
use std::sync::Arc;

use vem_contact::{CondensedSolver, ContactProblem, Coulomb, Tresca};
use vem_elastic::{Component, Dirichlet, ElasticBody, Material, Plane};
use vem_mesh::generators::{perturbed_quads, voronoi, Rectangle};
use vem_mesh::{Point, Vector};
use vem_space::LowestOrderVem;

fn punch(q: f64, law: Arc<dyn vem_contact::ContactLaw>) -> ContactProblem {
    let material = Material::from_young_poisson(200.0, 0.3, Plane::Strain).unwrap();
    let element = Arc::new(LowestOrderVem::default());
    let punch_mesh = voronoi(&Rectangle::new(Point::new(0.3, 0.0), Point::new(0.7, 0.4)), 6, 5).unwrap();
    let block_mesh = perturbed_quads(&Rectangle::new(Point::new(0.0, -1.0), Point::new(1.0, 0.0)), 9, 0.25, 2).unwrap();
    let punch = ElasticBody::builder("punch", punch_mesh, material, element.clone())
        .dirichlet(Dirichlet::rigid_plate("top", Component::All, Vector::new(q, -0.5)))
        .build().unwrap();
    let block = ElasticBody::builder("block", block_mesh, material, element).clamp("bottom").build().unwrap();
    ContactProblem::new(vec![punch, block]).with_pair(vem_contact::ContactPair::between(0, "bottom", 1, "top", law))
}

#[test]
fn probe() {
    for ratio in [0.01, 0.5, 0.99, 1.01] {
        let q = ratio * 0.3 * 0.5;
        let r = punch(q, Arc::new(Coulomb::try_new(0.3).unwrap())).solve(&mut CondensedSolver::default());
        match r {
            Ok(r) => eprintln!("coulomb ratio={ratio}: force {:?} solver {} fp {:?} counts {:?}", r.force_on_body_a(), r.report.solver, r.fixed_point.as_ref().map(|f| (f.steps, f.history.clone())), r.status_counts()),
            Err(e) => eprintln!("coulomb ratio={ratio}: {e}"),
        }
        let r = punch(q, Arc::new(Tresca::try_new(0.3).unwrap())).solve(&mut CondensedSolver::default());
        eprintln!("tresca q={q}: {:?}", r.as_ref().map(|r| (r.force_on_body_a(), r.report.solver)).map_err(|e| e.to_string()));
    }
}
