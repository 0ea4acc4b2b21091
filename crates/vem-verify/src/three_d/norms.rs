//! Error measures in space: `E_grad = ||grad(u - Pi u_h)||_{0,h}`, `E_0 = ||u - Pi u_h||_0` and
//! `E_a = a_h(u_I - u_h, u_I - u_h)^(1/2)`, as in 2D ([`crate::norms`]).
//!
//! The integrals are taken cell by cell with Walkington's 14-point degree-5 rule on the
//! signed tetrahedra joining the centroid to the fan triangles of every face
//! ([`vem_space::quadrature::polyhedron_rule`]): exact for polynomials of degree 5 on every
//! cell of the families (planar faces; the fan-defined body of warped faces), so the quadrature
//! error is of higher order than `E_0^2 ~ h^4`.

use rayon::prelude::*;
use vem_elastic::{AssembledSystem, ElasticBody};
use vem_mesh::PolyhedralMesh;
use vem_space::quadrature::{polyhedron_rule, TetrahedronRule};
use vem_space::PolyhedralElement;

use super::ExactSolution3d;
use crate::norms::{EnergyError, ErrorNorms, ProjectionErrors};
use crate::VerifyError;

/// The nodal interpolant `u_I` of `exact` on `mesh`: `[u_x(v0), u_y(v0), u_z(v0), u_x(v1), ...]`.
pub fn nodal_interpolant_3d(exact: &dyn ExactSolution3d, mesh: &PolyhedralMesh) -> Vec<f64> {
    mesh.vertices()
        .iter()
        .flat_map(|&x| {
            let u = exact.displacement(x);
            [u.x, u.y, u.z]
        })
        .collect()
}

/// `E_grad` and `E_0` of the full displacement `displacement` (global numbering
/// `3 * vertex + component`) on `mesh`, projected cell by cell by `element`, against `exact`
/// (cells in parallel), with `|u|_1` and `||u||_0` by the same quadrature.
pub fn projection_errors_3d(
    exact: &dyn ExactSolution3d,
    mesh: &PolyhedralMesh,
    element: &dyn PolyhedralElement,
    displacement: &[f64],
) -> Result<ProjectionErrors, VerifyError> {
    if displacement.len() != 3 * mesh.n_vertices() {
        return Err(VerifyError::WrongLength {
            body: 1,
            found: displacement.len(),
            expected: 3 * mesh.n_vertices(),
        });
    }
    let rule = TetrahedronRule::degree5();
    let sums = (0..mesh.n_cells())
        .into_par_iter()
        .map(|c| -> Result<[f64; 4], VerifyError> {
            let polyhedron = mesh.cell_polyhedron(c);
            let projection =
                element
                    .projection(&polyhedron)
                    .map_err(|source| VerifyError::Element {
                        body: 1,
                        polygon: c,
                        source: Box::new(source),
                    })?;
            let local = nalgebra::DVector::from_iterator(
                3 * mesh.cell_vertices(c).len(),
                mesh.cell_vertices(c)
                    .iter()
                    .flat_map(|&v| (0..3).map(move |k| displacement[3 * v + k])),
            );
            // Pi u_h = value + G (x - reference), its coefficients once per cell.
            let c = &projection.coefficients * &local;
            let value = nalgebra::Vector3::new(c[0], c[1], c[2]);
            let gradient = nalgebra::Matrix3::from_fn(|i, j| c[3 + 3 * i + j]);
            let mut sums = [0.0; 4];
            for q in polyhedron_rule(&polyhedron, &rule) {
                let (u, g) = exact.displacement_and_gradient(q.point);
                let projected = value + gradient * (q.point - projection.reference);
                sums[0] += q.weight * (g - gradient).norm_squared();
                sums[1] += q.weight * (u - projected).norm_squared();
                sums[2] += q.weight * g.norm_squared();
                sums[3] += q.weight * u.norm_squared();
            }
            Ok(sums)
        })
        .try_reduce(
            || [0.0; 4],
            |a, b| Ok([a[0] + b[0], a[1] + b[1], a[2] + b[2], a[3] + b[3]]),
        )?;
    if !sums.iter().all(|s| s.is_finite()) {
        return Err(VerifyError::NonFinite {
            body: 1,
            what: "the projection errors",
        });
    }
    let root = |s: f64| s.max(0.0).sqrt();
    Ok(ProjectionErrors {
        grad: root(sums[0]),
        l2: root(sums[1]),
        exact_grad: root(sums[2]),
        exact_l2: root(sums[3]),
    })
}

/// `E_a = a_h(u_I - u_h, u_I - u_h)^(1/2)` and `a_h(u_I, u_I)^(1/2)` with the assembled system
/// of the body.
pub fn energy_error_3d(
    exact: &dyn ExactSolution3d,
    mesh: &PolyhedralMesh,
    system: &AssembledSystem,
    displacement: &[f64],
) -> Result<EnergyError, VerifyError> {
    let interpolant = nodal_interpolant_3d(exact, mesh);
    if displacement.len() != interpolant.len() {
        return Err(VerifyError::WrongLength {
            body: 1,
            found: displacement.len(),
            expected: interpolant.len(),
        });
    }
    let difference: Vec<f64> = interpolant
        .iter()
        .zip(displacement)
        .map(|(a, b)| a - b)
        .collect();
    let elastic = |source| VerifyError::Elastic {
        case: exact.name().to_string(),
        source: Box::new(source),
    };
    let error = 2.0 * system.strain_energy(&difference).map_err(elastic)?;
    let norm = 2.0 * system.strain_energy(&interpolant).map_err(elastic)?;
    if !(error.is_finite() && norm.is_finite()) {
        return Err(VerifyError::NonFinite {
            body: 1,
            what: "the energy error",
        });
    }
    Ok(EnergyError {
        error: error.max(0.0).sqrt(),
        interpolant: norm.max(0.0).sqrt(),
    })
}

/// All measures of a solved body in space (its element must be polyhedral).
pub fn body_errors_3d(
    exact: &dyn ExactSolution3d,
    body: &ElasticBody<3>,
    system: &AssembledSystem,
    displacement: &[f64],
) -> Result<ErrorNorms, VerifyError> {
    let element = body
        .element()
        .as_polyhedral()
        .ok_or_else(|| VerifyError::InvalidSetting {
            reason: format!(
                "body '{}': the error norms need a polyhedral element (its energy projection)",
                body.name()
            ),
        })?;
    let projection = projection_errors_3d(exact, body.mesh(), element, displacement)?;
    let energy = energy_error_3d(exact, body.mesh(), system, displacement)?;
    Ok(ErrorNorms {
        grad: projection.grad,
        l2: projection.l2,
        energy: energy.error,
        exact_grad: projection.exact_grad,
        exact_l2: projection.exact_l2,
        interpolant_energy: energy.interpolant,
    })
}
