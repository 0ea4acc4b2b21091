//! Why the body load must be taken against the projection: the L2 rate on chevron
//! (non-convex) meshes.
//!
//! The minimal load of assumption A3, `l_T^h(v) = |T| f_bar . v_bar` with `v_bar` the mean of
//! the vertex values, is `|T| f_bar . v(x_bar)` for a linear `v`, `x_bar` the vertex mean, while
//! `int_T f . v = |T| f_bar . v(x_T) + O(h^2 |T|)` with `x_T` the centroid: the difference
//! `|T| f_bar . grad v (x_bar - x_T)` is first order. On a chevron mesh every interior cell has
//! `x_bar - x_T = (0, -h/24)` (rise 1/4), so these errors add up instead of cancelling: an O(h)
//! load error, hence O(h) in L2 and in the contact resultant (Theorems 4.1/4.2, energy O(h),
//! are unaffected). `LowestOrderVem::body_load` now uses `|T| f_bar . (Pi v)(x_T)`, exact on
//! linear fields.
//!
//! This example runs the same studies with the element's load and with the vertex-mean load,
//! all else equal: the convergence study found the drop (`docs/convergence.md`).
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

/// An element space with the vertex-mean load `|T| f_bar . v_bar`; stiffness and projection
/// of `inner`.
struct VertexMeanLoad<E>(E);

impl<E: ElementSpace> ElementSpace for VertexMeanLoad<E> {
    fn name(&self) -> &str {
        "vem1 + vertex-mean load"
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
        let rule = quadrature_points(polygon).map_err(|reason| SpaceError::DegeneratePolygon {
            vertices: polygon.len(),
            reason: format!("no sub-triangulation: {reason}"),
        })?;
        // |T| f_bar = int_T f, shared equally by the vertices.
        let integral: Vector = rule.iter().map(|q| body_force(q.point) * q.weight).sum();
        let share = integral / polygon.len() as f64;
        Ok(DVector::from_fn(2 * polygon.len(), |i, _| share[i % 2]))
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
    let vertex_mean = ProblemSettings::builder()
        .element(Arc::new(VertexMeanLoad(LowestOrderVem::default())))
        .build()?;
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
        row("area x f_bar . (Pi v)(centroid) (element)", &study.run()?);
        row(
            "area x f_bar . vertex mean of v",
            &study.settings(vertex_mean.clone()).run()?,
        );
    }
    Ok(())
}
