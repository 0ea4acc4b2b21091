//! Error measures of a discrete solution against an exact one (`docs/manufactured.md`, section 8;
//! `docs/formulation.md`, section 3).
//!
//! The virtual solution `u_h` is not known inside the elements; what is computable per body is
//!
//! - `E_grad = ||grad(u - Pi u_h)||_{0,h}`: the broken H1 seminorm of the error of the energy
//!   projection, element by element (`Pi u_h` is linear on each polygon, its gradient constant);
//! - `E_0 = ||u - Pi u_h||_0`: the L2 error of the projection;
//! - `E_a = a_h(u_I - u_h, u_I - u_h)^(1/2)`: the discrete energy error against the nodal
//!   interpolant `u_I` (vertex values of `u`), with the assembled VEM stiffness.
//!
//! The two integrals use a sub-triangulation of each polygon ([`sub_triangles`]: the fan from
//! the centroid when the polygon is star-shaped with respect to it, ear clipping otherwise) and
//! the degree-5 triangle rule of `vem_space::quadrature`: the quadrature error is of higher
//! order than `E_0^2 ~ h^4`, also on the elements cut by a switch line, where the built-in
//! solutions are at least C^1. Over several bodies the measures combine as the square root of
//! the sum of squares ([`ErrorNorms::combine`]).
//!
//! ```
//! use vem_mesh::generators::{structured_quads, Rectangle};
//! use vem_space::LowestOrderVem;
//! use vem_verify::exact::{case_by_name, BodyId, Lame};
//! use vem_verify::norms::projection_errors;
//! // With u_h = 0 the measures are the norms of u itself: ||u||_0^2 = 1/2 for E1.
//! let e1 = case_by_name("E1", Lame::default())?;
//! let mesh = structured_quads(&Rectangle::unit_square(), 8, 8)?;
//! let zero = vec![0.0; 2 * mesh.n_vertices()];
//! let errors = projection_errors(&*e1, BodyId::One, &mesh, &LowestOrderVem::default(), &zero)?;
//! assert!((errors.l2.powi(2) - 0.5).abs() < 1e-6);
//! assert_eq!(errors.l2, errors.exact_l2);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use nalgebra::DVector;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use vem_elastic::{AssembledSystem, ElasticBody};
use vem_mesh::geometry;
use vem_mesh::{Mesh, Point};
use vem_space::quadrature::{QuadraturePoint, TriangleRule};
use vem_space::ElementSpace;

use crate::exact::{BodyId, ExactSolution};
use crate::VerifyError;

/// The error measures of one body, or of several combined, with the matching norms of the
/// exact solution (for relative errors).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct ErrorNorms {
    /// `E_grad = ||grad(u - Pi u_h)||_{0,h}` (broken H1 seminorm).
    pub grad: f64,
    /// `E_0 = ||u - Pi u_h||_0`.
    pub l2: f64,
    /// `E_a = a_h(u_I - u_h, u_I - u_h)^(1/2)`.
    pub energy: f64,
    /// `|u|_1 = ||grad u||_0`, by the same quadrature.
    pub exact_grad: f64,
    /// `||u||_0`, by the same quadrature.
    pub exact_l2: f64,
    /// `a_h(u_I, u_I)^(1/2)`, the discrete energy norm of the interpolant.
    pub interpolant_energy: f64,
}

impl ErrorNorms {
    /// The measures of several bodies together: each the square root of the sum of squares.
    pub fn combine(parts: &[ErrorNorms]) -> ErrorNorms {
        let root_sum =
            |f: fn(&ErrorNorms) -> f64| parts.iter().map(|e| f(e).powi(2)).sum::<f64>().sqrt();
        ErrorNorms {
            grad: root_sum(|e| e.grad),
            l2: root_sum(|e| e.l2),
            energy: root_sum(|e| e.energy),
            exact_grad: root_sum(|e| e.exact_grad),
            exact_l2: root_sum(|e| e.exact_l2),
            interpolant_energy: root_sum(|e| e.interpolant_energy),
        }
    }

    /// `E_grad / |u|_1` (zero for a vanishing exact solution with zero error).
    pub fn relative_grad(&self) -> f64 {
        relative(self.grad, self.exact_grad)
    }

    /// `E_0 / ||u||_0`.
    pub fn relative_l2(&self) -> f64 {
        relative(self.l2, self.exact_l2)
    }

    /// `E_a / a_h(u_I, u_I)^(1/2)`.
    pub fn relative_energy(&self) -> f64 {
        relative(self.energy, self.interpolant_energy)
    }
}

fn relative(error: f64, norm: f64) -> f64 {
    if norm > 0.0 {
        error / norm
    } else {
        error
    }
}

/// The projection errors `E_grad`, `E_0` of one body with the norms of `u`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ProjectionErrors {
    /// `||grad(u - Pi u_h)||_{0,h}`.
    pub grad: f64,
    /// `||u - Pi u_h||_0`.
    pub l2: f64,
    /// `|u|_1`.
    pub exact_grad: f64,
    /// `||u||_0`.
    pub exact_l2: f64,
}

/// The energy error `E_a` of one body with the energy norm of the interpolant.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct EnergyError {
    /// `a_h(u_I - u_h, u_I - u_h)^(1/2)`.
    pub error: f64,
    /// `a_h(u_I, u_I)^(1/2)`.
    pub interpolant: f64,
}

/// Splits the simple, counter-clockwise polygon `polygon` into triangles for quadrature: the
/// fan joining the centroid to every edge when each of its triangles has positive area (the
/// polygon is star-shaped with respect to its centroid: convex cells, chevrons, cells with
/// hanging nodes), otherwise an ear-clipping triangulation of the vertices. Every triangle is
/// counter-clockwise and the areas sum to the polygon's.
///
/// # Errors
/// A message when the polygon has fewer than three vertices, non-positive area, or is not
/// simple (no ear can be clipped).
///
/// ```
/// use vem_mesh::Point;
/// use vem_verify::norms::sub_triangles;
/// // A U whose centroid (1.5, 1.45) lies in its notch: the fan is invalid, ear clipping is used.
/// let u = [
///     Point::new(0.0, 0.0), Point::new(3.0, 0.0), Point::new(3.0, 3.0), Point::new(2.0, 3.0),
///     Point::new(2.0, 0.2), Point::new(1.0, 0.2), Point::new(1.0, 3.0), Point::new(0.0, 3.0),
/// ];
/// let triangles = sub_triangles(&u).unwrap();
/// assert_eq!(triangles.len(), 6); // ear clipping: n - 2 triangles
/// let area: f64 = triangles.iter().map(|[a, b, c]| 0.5 * (b - a).perp(&(c - a))).sum();
/// assert!((area - (9.0 - 2.8)).abs() < 1e-12);
/// ```
pub fn sub_triangles(polygon: &[Point]) -> Result<Vec<[Point; 3]>, String> {
    let n = polygon.len();
    if n < 3 {
        return Err(format!("{n} vertices"));
    }
    let area = geometry::signed_area(polygon);
    if area.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return Err(format!("signed area {area:e} is not positive"));
    }
    let centroid = geometry::centroid(polygon);
    let fan: Vec<[Point; 3]> = (0..n)
        .map(|k| [centroid, polygon[k], polygon[(k + 1) % n]])
        .collect();
    if fan.iter().all(|t| orientation(t[0], t[1], t[2]) > 0.0) {
        return Ok(fan);
    }
    ear_clipping(polygon, area)
}

/// Twice the signed area of the triangle `(a, b, c)`.
fn orientation(a: Point, b: Point, c: Point) -> f64 {
    (b - a).perp(&(c - a))
}

/// Ear clipping of a simple counter-clockwise polygon of area `area`. Vertices between two
/// collinear neighbours (hanging nodes) are dropped as zero-area ears.
fn ear_clipping(polygon: &[Point], area: f64) -> Result<Vec<[Point; 3]>, String> {
    // Orientation values below this (twice an area) count as collinear.
    let tolerance = 1e-12 * area;
    let mut remaining: Vec<usize> = (0..polygon.len()).collect();
    let mut triangles = Vec::with_capacity(polygon.len() - 2);
    while remaining.len() > 3 {
        let m = remaining.len();
        let corner = |i: usize| {
            (
                polygon[remaining[(i + m - 1) % m]],
                polygon[remaining[i]],
                polygon[remaining[(i + 1) % m]],
            )
        };
        let is_ear = |i: usize| {
            let (a, b, c) = corner(i);
            orientation(a, b, c) > tolerance
                && remaining.iter().enumerate().all(|(j, &v)| {
                    let p = polygon[v];
                    j == i
                        || j == (i + m - 1) % m
                        || j == (i + 1) % m
                        || !(orientation(a, b, p) > tolerance
                            && orientation(b, c, p) > tolerance
                            && orientation(c, a, p) > tolerance)
                })
        };
        let is_straight = |i: usize| {
            let (a, b, c) = corner(i);
            orientation(a, b, c).abs() <= tolerance && (a - b).dot(&(c - b)) < 0.0
        };
        if let Some(i) = (0..m).find(|&i| is_straight(i)) {
            remaining.remove(i);
        } else if let Some(i) = (0..m).find(|&i| is_ear(i)) {
            let (a, b, c) = corner(i);
            triangles.push([a, b, c]);
            remaining.remove(i);
        } else {
            return Err(format!(
                "no ear among the {m} remaining vertices: the polygon is not simple"
            ));
        }
    }
    let (a, b, c) = (
        polygon[remaining[0]],
        polygon[remaining[1]],
        polygon[remaining[2]],
    );
    if orientation(a, b, c) > tolerance {
        triangles.push([a, b, c]);
    }
    Ok(triangles)
}

/// Quadrature points of degree 5 on the polygon `polygon`, on the triangles of
/// [`sub_triangles`] (positive weights, all points inside the polygon).
///
/// # Errors
/// As [`sub_triangles`].
pub fn quadrature_points(polygon: &[Point]) -> Result<Vec<QuadraturePoint>, String> {
    let rule = TriangleRule::degree5();
    Ok(sub_triangles(polygon)?
        .into_iter()
        .flat_map(|[a, b, c]| rule.on_triangle(a, b, c))
        .collect())
}

/// The nodal interpolant `u_I` of body `body` of `exact` on `mesh`: the full displacement
/// vector `[u_x(v0), u_y(v0), u_x(v1), ...]` of the vertex values of `u`.
pub fn nodal_interpolant(exact: &dyn ExactSolution, body: BodyId, mesh: &Mesh) -> Vec<f64> {
    mesh.vertices()
        .iter()
        .flat_map(|&x| {
            let u = exact.displacement(body, x);
            [u.x, u.y]
        })
        .collect()
}

/// `E_grad` and `E_0` of the full displacement `displacement` (global numbering
/// `2 * vertex + component`) of body `body` on `mesh`, projected element by element by
/// `element`, against `exact` (polygons in parallel).
///
/// # Errors
/// A displacement of the wrong length, a polygon the element or the triangulation rejects, a
/// non-finite result.
pub fn projection_errors(
    exact: &dyn ExactSolution,
    body: BodyId,
    mesh: &Mesh,
    element: &dyn ElementSpace,
    displacement: &[f64],
) -> Result<ProjectionErrors, VerifyError> {
    let label = body.index() + 1;
    if displacement.len() != 2 * mesh.n_vertices() {
        return Err(VerifyError::WrongLength {
            body: label,
            found: displacement.len(),
            expected: 2 * mesh.n_vertices(),
        });
    }
    // Squared integrals: [grad error, l2 error, grad u, u].
    let sums = (0..mesh.n_polygons())
        .into_par_iter()
        .map(|p| -> Result<[f64; 4], VerifyError> {
            let points = mesh.polygon_points(p);
            let projection =
                element
                    .projection(&points)
                    .map_err(|source| VerifyError::Element {
                        body: label,
                        polygon: p,
                        source: Box::new(source),
                    })?;
            let dofs = DVector::from_iterator(
                2 * points.len(),
                mesh.polygon(p)
                    .iter()
                    .flat_map(|&v| [displacement[2 * v], displacement[2 * v + 1]]),
            );
            let gradient_h = projection.gradient(&dofs);
            let rule = quadrature_points(&points).map_err(|reason| VerifyError::Triangulation {
                body: label,
                polygon: p,
                reason,
            })?;
            let mut sums = [0.0; 4];
            for q in rule {
                let u = exact.displacement(body, q.point);
                let gradient = exact.gradient(body, q.point);
                sums[0] += q.weight * (gradient - gradient_h).norm_squared();
                sums[1] += q.weight * (u - projection.evaluate(&dofs, q.point)).norm_squared();
                sums[2] += q.weight * gradient.norm_squared();
                sums[3] += q.weight * u.norm_squared();
            }
            Ok(sums)
        })
        .try_reduce(
            || [0.0; 4],
            |a, b| Ok([a[0] + b[0], a[1] + b[1], a[2] + b[2], a[3] + b[3]]),
        )?;
    if sums.iter().any(|s| !s.is_finite()) {
        return Err(VerifyError::NonFinite {
            body: label,
            what: "the projection error",
        });
    }
    Ok(ProjectionErrors {
        grad: sums[0].sqrt(),
        l2: sums[1].sqrt(),
        exact_grad: sums[2].sqrt(),
        exact_l2: sums[3].sqrt(),
    })
}

/// `E_a = a_h(u_I - u_h, u_I - u_h)^(1/2)` of the full displacement `displacement` of body
/// `body` with the assembled `system` of `mesh`. Prescribed degrees of freedom carry the exact
/// data, so `u_I - u_h` vanishes there and only the reduced stiffness `K_ff` contributes.
///
/// # Errors
/// A displacement that does not match the system, a non-finite result.
pub fn energy_error(
    exact: &dyn ExactSolution,
    body: BodyId,
    mesh: &Mesh,
    system: &AssembledSystem,
    displacement: &[f64],
) -> Result<EnergyError, VerifyError> {
    let label = body.index() + 1;
    let interpolant = nodal_interpolant(exact, body, mesh);
    if displacement.len() != interpolant.len() {
        return Err(VerifyError::WrongLength {
            body: label,
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
    // strain_energy = 1/2 a_h(v, v).
    let error = 2.0 * system.strain_energy(&difference).map_err(elastic)?;
    let norm = 2.0 * system.strain_energy(&interpolant).map_err(elastic)?;
    if !(error.is_finite() && norm.is_finite()) {
        return Err(VerifyError::NonFinite {
            body: label,
            what: "the energy error",
        });
    }
    Ok(EnergyError {
        error: error.max(0.0).sqrt(),
        interpolant: norm.max(0.0).sqrt(),
    })
}

/// All measures of one solved body: the projection errors on the body's mesh with its element,
/// and the energy error with its assembled system.
///
/// # Errors
/// As [`projection_errors`] and [`energy_error`].
pub fn body_errors(
    exact: &dyn ExactSolution,
    body: BodyId,
    elastic: &ElasticBody,
    system: &AssembledSystem,
    displacement: &[f64],
) -> Result<ErrorNorms, VerifyError> {
    let element = elastic
        .element()
        .as_planar()
        .ok_or_else(|| VerifyError::InvalidSetting {
            reason: format!(
                "body '{}': the error norms need a polygonal element (its energy projection)",
                elastic.name()
            ),
        })?;
    let projection = projection_errors(exact, body, elastic.mesh(), element, displacement)?;
    let energy = energy_error(exact, body, elastic.mesh(), system, displacement)?;
    Ok(ErrorNorms {
        grad: projection.grad,
        l2: projection.l2,
        energy: energy.error,
        exact_grad: projection.exact_grad,
        exact_l2: projection.exact_l2,
        interpolant_energy: energy.interpolant,
    })
}
