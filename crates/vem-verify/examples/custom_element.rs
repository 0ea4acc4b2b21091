//! An element space written outside the workspace, plugged into a convergence study.
//!
//! `TraceVem` is the lowest-order virtual element for plane elasticity written from scratch
//! with nothing but the public `vem_space` types: the energy projection from the boundary
//! integral `int_T grad v = int_dT v (x) n ds`, the consistency `|T| B^T C B`, and a
//! stabilisation that none of the built-in elements has: `S = tau (I - D Pi)^T (I - D Pi)`
//! with `tau = trace(K_c) / (2n)`, the mean diagonal entry of the element's own consistency
//! matrix (`D Pi` maps the vertex values to the vertex values of the projection).
//!
//! The study runs the elasticity case E1 on Voronoi meshes, n = 8, 16, 32, 64, through
//! `Study::element`, and checks: the rates (`E_grad`, `E_a` >= 0.9, `E_0` >= 1.8), and that
//! its errors are within a factor 2 of the built-in `vem1` element on the same meshes (the
//! consistency parts coincide; only the stabilisations differ: measured, `E_grad` agrees to
//! 2% and `E_0` is about a third smaller with this stabilisation). Exits non-zero on failure.
//!
//! Run with `cargo run --release -p vem-verify --example custom_element`.

use std::process::ExitCode;
use std::sync::Arc;

use nalgebra::{DMatrix, DVector};
use vem_mesh::generators::MeshFamily;
use vem_space::{
    ElasticityTensor, ElementSpace, EnergyProjection, LocalStiffness, Point, SpaceError, Vector,
};
use vem_verify::exact::{case_by_name, Lame};
use vem_verify::report::study_markdown;
use vem_verify::study::{MeshPairing, Study, StudyResult};

/// The lowest-order VEM with the "mean diagonal of the consistency" stabilisation.
struct TraceVem;

/// Area, vertex mean and the 6 x 2n projection coefficients of a counter-clockwise polygon.
fn projection_of(polygon: &[Point]) -> Result<(f64, Point, DMatrix<f64>), SpaceError> {
    let n = polygon.len();
    let degenerate = |reason: &str| SpaceError::DegeneratePolygon {
        vertices: n,
        reason: reason.to_string(),
    };
    if n < 3 {
        return Err(degenerate("fewer than three vertices"));
    }
    let area = 0.5
        * (0..n)
            .map(|k| {
                let (a, b) = (polygon[k], polygon[(k + 1) % n]);
                a.x * b.y - b.x * a.y
            })
            .sum::<f64>();
    if !(area.is_finite() && area > 0.0) {
        return Err(degenerate("not counter-clockwise, or zero area"));
    }
    let mean = polygon.iter().fold(Vector::zeros(), |s, p| s + p.coords) / n as f64;
    // Rows [value_x, value_y, d_x v_x, d_y v_x, d_x v_y, d_y v_y] about the vertex mean.
    let mut c = DMatrix::zeros(6, 2 * n);
    for k in 0..n {
        c[(0, 2 * k)] = 1.0 / n as f64;
        c[(1, 2 * k + 1)] = 1.0 / n as f64;
        // Vertex k carries half of the outward normals (times lengths) of its two edges:
        // for the edge a -> b, n |e| = (b_y - a_y, a_x - b_x).
        let (prev, next) = (polygon[(k + n - 1) % n], polygon[(k + 1) % n]);
        let normal = Vector::new(next.y - prev.y, prev.x - next.x) / (2.0 * area);
        for component in 0..2 {
            c[(2 + 2 * component, 2 * k + component)] = normal.x;
            c[(3 + 2 * component, 2 * k + component)] = normal.y;
        }
    }
    Ok((area, Point::from(mean), c))
}

impl ElementSpace for TraceVem {
    fn name(&self) -> &str {
        "vem1-trace (example)"
    }

    fn stiffness(
        &self,
        polygon: &[Point],
        material: &ElasticityTensor,
    ) -> Result<LocalStiffness, SpaceError> {
        let n = polygon.len();
        let (area, reference, pi) = projection_of(polygon)?;
        // Voigt strain [xx, yy, 2 xy] of the projection, a 3 x 2n map.
        let mut b = DMatrix::zeros(3, 2 * n);
        for j in 0..2 * n {
            b[(0, j)] = pi[(2, j)];
            b[(1, j)] = pi[(5, j)];
            b[(2, j)] = pi[(3, j)] + pi[(4, j)];
        }
        let c = DMatrix::from_iterator(3, 3, material.voigt().iter().copied());
        let consistency = (b.transpose() * c * &b) * area;
        // D Pi: the projection evaluated at the vertices, a 2n x 2n map.
        let mut d_pi = DMatrix::zeros(2 * n, 2 * n);
        for (k, x) in polygon.iter().enumerate() {
            let d = x - reference;
            for component in 0..2 {
                let row = pi.row(component)
                    + pi.row(2 + 2 * component) * d.x
                    + pi.row(3 + 2 * component) * d.y;
                d_pi.set_row(2 * k + component, &row);
            }
        }
        let residual = DMatrix::identity(2 * n, 2 * n) - d_pi;
        let tau = consistency.trace() / (2 * n) as f64;
        let stabilisation = residual.transpose() * residual * tau;
        Ok(LocalStiffness {
            consistency,
            stabilisation,
        })
    }

    fn projection(&self, polygon: &[Point]) -> Result<EnergyProjection, SpaceError> {
        let (_, reference, coefficients) = projection_of(polygon)?;
        Ok(EnergyProjection {
            reference,
            coefficients,
        })
    }

    /// `|T| f(x_T) . (Pi v)(x_T)` with `x_T` the centroid: exact for a constant force and a
    /// linear `v`, which is all the O(h) rate asks (assumption A3).
    fn body_load(
        &self,
        polygon: &[Point],
        body_force: &(dyn Fn(Point) -> Vector + Sync),
    ) -> Result<DVector<f64>, SpaceError> {
        let n = polygon.len();
        let (area, reference, pi) = projection_of(polygon)?;
        let mut moment = Vector::zeros();
        for k in 0..n {
            let (a, b) = (polygon[k], polygon[(k + 1) % n]);
            moment += (a.coords + b.coords) * (a.x * b.y - b.x * a.y);
        }
        let centroid = Point::from(moment / (6.0 * area));
        let f = body_force(centroid);
        if !(f.x.is_finite() && f.y.is_finite()) {
            return Err(SpaceError::NonFiniteLoad {
                x: centroid.x,
                y: centroid.y,
            });
        }
        let d = centroid - reference;
        let value_x = pi.row(0) + pi.row(2) * d.x + pi.row(3) * d.y;
        let value_y = pi.row(1) + pi.row(4) * d.x + pi.row(5) * d.y;
        Ok(((value_x * f.x + value_y * f.y) * area).transpose())
    }
}

fn study(element: Arc<dyn ElementSpace>) -> Result<StudyResult, Box<dyn std::error::Error>> {
    let e1 = case_by_name("E1", Lame::default())?;
    Ok(
        Study::new(e1.into(), MeshPairing::single(MeshFamily::Voronoi))
            .sizes([8, 16, 32, 64])
            .element(element)
            .run()?,
    )
}

fn main() -> Result<ExitCode, Box<dyn std::error::Error>> {
    let ours = study(Arc::new(TraceVem))?;
    let builtin = study(Arc::new(vem_space::LowestOrderVem::default()))?;
    println!("{}", study_markdown(&ours));
    let mut failures = Vec::new();
    if !ours.verdict.passed {
        failures.extend(ours.verdict.shortfalls.iter().cloned());
    }
    for (a, b) in ours.records.iter().zip(&builtin.records) {
        for (name, x, y) in [
            ("E_grad", a.errors.grad, b.errors.grad),
            ("E_0", a.errors.l2, b.errors.l2),
        ] {
            let ratio = x / y;
            println!(
                "n = {:?}: {name} {x:.3e} against vem1 {y:.3e} (ratio {ratio:.3})",
                a.n
            );
            if !(0.5..2.0).contains(&ratio) {
                failures.push(format!("n = {:?}: {name} ratio {ratio:.3} to vem1", a.n));
            }
        }
    }
    if failures.is_empty() {
        println!(
            "custom element '{}': rates E_grad {:.2}, E_a {:.2}, E_0 {:.2}: pass",
            ours.element,
            ours.rates.grad.unwrap_or(f64::NAN),
            ours.rates.energy.unwrap_or(f64::NAN),
            ours.rates.l2.unwrap_or(f64::NAN)
        );
        Ok(ExitCode::SUCCESS)
    } else {
        eprintln!("custom element FAILS:\n- {}", failures.join("\n- "));
        Ok(ExitCode::FAILURE)
    }
}
