//! Why the L2 rate drops to one on chevron (non-convex) meshes: the body load.
//!
//! `LowestOrderVem::body_load` gives `l_T^h(v) = |T| f_bar . v_bar` with `v_bar` the mean of
//! the vertex values (assumption A3). For a linear `v` this is `|T| f_bar . v(x_bar)` with
//! `x_bar` the vertex mean, while `int_T f . v = |T| f_bar . v(x_T) + O(h^2 |T|)` with `x_T` the
//! centroid: the difference `|T| f_bar . grad v (x_bar - x_T)` is first order. On a chevron
//! mesh every interior cell has `x_bar - x_T = (0, -h/24)` (rise 1/4), so the errors add up
//! instead of cancelling: an O(h) load error, hence O(h) in L2 and in the contact resultant.
//! Theorems 4.1/4.2 (energy O(h)) are unaffected.
//!
//! This example runs the same studies with the element's own load and with the second-order
//! load `l_T^h(v) = int_T f . Pi v` (the energy projection of `v`, integrated by the degree-5
//! rule on the sub-triangulation of `vem_verify::norms`), all else equal.
//!
//! Run with `cargo run --release -p vem-verify --example load_consistency`.

use std::sync::Arc;

use nalgebra::DVector;
use vem_space::{
    ElasticityTensor, ElementSpace, EnergyProjection, LocalStiffness, LowestOrderVem, Point,
    SpaceError, Vector,
};
use vem_verify::exact::{case_by_name, Lame};
use vem_verify::norms::quadrature_points;
use vem_verify::problem::ProblemSettings;
use vem_verify::study::{successive_rates, MeshPairing, Study, StudyResult};

/// An element space with the load `int_T f . Pi v`; stiffness and projection of `inner`.
struct ProjectedLoad<E>(E);

impl<E: ElementSpace> ElementSpace for ProjectedLoad<E> {
    fn name(&self) -> &str {
        "vem1 + projected load"
    }

    fn stiffness(
        &self,
        polygon: &[Point],
        material: &ElasticityTensor,
    ) -> Result<LocalStiffness, SpaceError> {
        self.0.stiffness(polygon, material)
    }

    fn projection(&self, polygon: &[Point]) -> Result<EnergyProjection, SpaceError> {
        self.0.projection(polygon)
    }

    fn body_load(
        &self,
        polygon: &[Point],
        body_force: &(dyn Fn(Point) -> Vector + Sync),
    ) -> Result<DVector<f64>, SpaceError> {
        let projection = self.0.projection(polygon)?;
        let c = &projection.coefficients;
        let rule = quadrature_points(polygon).map_err(|reason| SpaceError::DegeneratePolygon {
            vertices: polygon.len(),
            reason: format!("no sub-triangulation: {reason}"),
        })?;
        let mut load = DVector::zeros(2 * polygon.len());
        for q in rule {
            let f = body_force(q.point);
            let d = q.point - projection.reference;
            // Pi phi_j (x) = (c_0j + c_2j dx + c_3j dy, c_1j + c_4j dx + c_5j dy).
            for j in 0..load.len() {
                let pi_x = c[(0, j)] + c[(2, j)] * d.x + c[(3, j)] * d.y;
                let pi_y = c[(1, j)] + c[(4, j)] * d.x + c[(5, j)] * d.y;
                load[j] += q.weight * (f.x * pi_x + f.y * pi_y);
            }
        }
        Ok(load)
    }
}

fn row(label: &str, result: &StudyResult) {
    let h: Vec<f64> = result.records.iter().map(|r| r.h).collect();
    let l2: Vec<f64> = result.records.iter().map(|r| r.errors.l2).collect();
    let rates = successive_rates(&h, &l2);
    let cells: Vec<String> = l2
        .iter()
        .zip(&rates)
        .map(|(e, r)| match r {
            Some(r) => format!("{e:.3e} ({r:.2})"),
            None => format!("{e:.3e}"),
        })
        .collect();
    let resultant = result
        .finest()
        .and_then(|r| r.contact.as_ref())
        .map_or("—".to_string(), |c| {
            format!("{:.3e}", c.normal_resultant_error)
        });
    println!(
        "| {} | {label} | {} | {:.2} | {resultant} |",
        result.case,
        cells.join(" · "),
        result.rates.grad.unwrap_or(f64::NAN),
    );
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let projected = ProblemSettings {
        element: Arc::new(ProjectedLoad(LowestOrderVem::default())),
        ..ProblemSettings::default()
    };
    println!(
        "| case | load | E_0 (successive rate), n = 8, 16, 32, 64 | E_grad rate | ΔN at n = 64 |"
    );
    println!("|---|---|---|---|---|");
    for (case, pairing) in [
        ("M1", "nonconvex/triangles"),
        ("M2", "nonconvex/triangles"),
        ("M3", "nonconvex/quads"),
        ("E1", "nonconvex"),
    ] {
        let exact: Arc<_> = case_by_name(case, Lame::default())?.into();
        let pairing: MeshPairing = pairing.parse()?;
        let study = Study::new(exact, pairing).sizes([8, 16, 32, 64]);
        row("area x f_bar . vertex mean of v (current)", &study.run()?);
        row("int_T f . Pi v", &study.settings(projected.clone()).run()?);
    }
    Ok(())
}
