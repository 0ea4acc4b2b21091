//! E1 (docs/manufactured.md section 6): convergence of the energy projection of the discrete
//! solution, O(h) in the broken H1 seminorm and O(h^2) in L2, on several mesh families; and
//! equilibrium of reactions and loads.

mod common;

use common::{fitted_rate, lame, projection_errors, vem, E1, LAME_PAIRS};
use vem_elastic::ElasticBody;
use vem_mesh::generators::{MeshFamily, Rectangle};
use vem_mesh::Vector;

/// Mesh sizes; rates are fitted over the last `FITTED` of them (docs/manufactured.md section 8): the
/// coarsest Voronoi meshes with lambda/mu = 33 are pre-asymptotic in L2.
const SIZES: [usize; 5] = [4, 8, 16, 32, 64];
const FITTED: usize = 3;

fn sci(values: &[f64]) -> String {
    values
        .iter()
        .map(|v| format!("{v:.3e}"))
        .collect::<Vec<_>>()
        .join(" ")
}

fn study(family: MeshFamily, lambda: f64, mu: f64) {
    let (mut h, mut grad, mut l2) = (Vec::new(), Vec::new(), Vec::new());
    for n in SIZES {
        let mesh = family.generate(&Rectangle::unit_square(), n, 11).unwrap();
        let body = ElasticBody::builder("e1", mesh, lame(lambda, mu), vem())
            .clamp("left")
            .clamp("right")
            .clamp("bottom")
            .clamp("top")
            .body_force(E1::force(lambda, mu))
            .build()
            .unwrap();
        let system = body.assemble().unwrap();
        let solution = body
            .solve_system(&system, &mut vem_elastic::CholeskySolver::default())
            .unwrap();
        let errors = projection_errors(&body, solution.displacement(), &E1);
        // The mean cell size sqrt(|Omega| / #cells): the largest diameter of a random Voronoi
        // mesh fluctuates from one mesh to the next.
        h.push((1.0 / body.mesh().n_polygons() as f64).sqrt());
        grad.push(errors.grad);
        l2.push(errors.l2);

        // Equilibrium: the clamps carry the whole load, and the load is int f = (4 (lambda + 3 mu), 0).
        let load = system.load();
        let load_sum = Vector::new(
            load.iter().step_by(2).sum::<f64>(),
            load.iter().skip(1).step_by(2).sum::<f64>(),
        );
        let total = solution.total_reaction() + load_sum;
        assert!(
            total.norm() < 1e-10 * load_sum.norm(),
            "{} n={n}: {total:?}",
            family.name()
        );
        let int_f = Vector::new(4.0 * (lambda + 3.0 * mu), 0.0);
        assert!(
            (load_sum - int_f).norm() < 1e-3 * int_f.norm(),
            "{load_sum:?} vs {int_f:?}"
        );
    }
    let last = SIZES.len() - FITTED;
    let (rate_grad, rate_l2) = (
        fitted_rate(&h[last..], &grad[last..]),
        fitted_rate(&h[last..], &l2[last..]),
    );
    println!(
        "E1 {:>10} lambda={lambda:<4} mu={mu:<4} h=[{}] grad=[{}] l2=[{}] rates: grad {rate_grad:.3} l2 {rate_l2:.3}",
        family.name(),
        sci(&h),
        sci(&grad),
        sci(&l2)
    );
    assert!(rate_grad >= 0.9, "{}: grad rate {rate_grad}", family.name());
    assert!(rate_l2 >= 1.8, "{}: L2 rate {rate_l2}", family.name());
}

#[test]
fn e1_structured_quads() {
    for (lambda, mu) in LAME_PAIRS {
        study(MeshFamily::Quads, lambda, mu);
    }
}

#[test]
fn e1_voronoi() {
    for (lambda, mu) in LAME_PAIRS {
        study(MeshFamily::Voronoi, lambda, mu);
    }
}

#[test]
fn e1_perturbed_quads() {
    for (lambda, mu) in LAME_PAIRS {
        study(
            MeshFamily::PerturbedQuads {
                distortion: MeshFamily::DEFAULT_DISTORTION,
            },
            lambda,
            mu,
        );
    }
}
