//! Shared helpers of the integration tests: exact fields (docs/manufactured.md section 6), error
//! norms of the energy projection, least-squares rates.
#![allow(dead_code)]

use std::f64::consts::PI;
use std::sync::Arc;

use nalgebra::{DVector, Matrix2};
use vem_elastic::{ElasticBody, Material, Plane};
use vem_mesh::{Mesh, Point, Vector};
use vem_space::quadrature::{polygon_rule, TriangleRule};
use vem_space::{ElementSpace, LowestOrderVem};

/// The Lame pairs every exact test runs with: the reference pair and a second one with
/// lambda >> mu (a lambda/mu swap would show).
pub const LAME_PAIRS: [(f64, f64); 2] = [(2.0, 1.0), (10.0, 0.3)];

/// The lowest-order VEM with default stabilisation.
pub fn vem() -> Arc<dyn ElementSpace> {
    Arc::new(LowestOrderVem::default())
}

/// Plane-strain material from Lame parameters.
pub fn lame(lambda: f64, mu: f64) -> Material {
    Material::from_lame(lambda, mu, Plane::Strain).unwrap()
}

/// An exact displacement field with its gradient (entry (i, j) = d_j u_i).
pub trait ExactField: Sync {
    /// u(x).
    fn u(&self, x: Point) -> Vector;
    /// grad u(x).
    fn grad(&self, x: Point) -> Matrix2<f64>;
}

/// PT0a: u = ((1 + 2x + 3y)/10, (2 - x + 4y)/10), f = 0 (docs/manufactured.md section 6).
pub struct Pt0a;

impl ExactField for Pt0a {
    fn u(&self, x: Point) -> Vector {
        Vector::new(
            (1.0 + 2.0 * x.x + 3.0 * x.y) / 10.0,
            (2.0 - x.x + 4.0 * x.y) / 10.0,
        )
    }
    fn grad(&self, _: Point) -> Matrix2<f64> {
        Matrix2::new(0.2, 0.3, -0.1, 0.4)
    }
}

/// PT0b: u = (1 - y) (1/10, -1/20), f = 0.
pub struct Pt0b;

impl ExactField for Pt0b {
    fn u(&self, x: Point) -> Vector {
        Vector::new((1.0 - x.y) / 10.0, -(1.0 - x.y) / 20.0)
    }
    fn grad(&self, _: Point) -> Matrix2<f64> {
        Matrix2::new(0.0, -0.1, 0.0, 0.05)
    }
}

/// E1: u = (sin(pi x) sin(pi y), sin(2 pi x) sin(pi y)), zero on the boundary of (0,1)^2.
pub struct E1;

impl ExactField for E1 {
    fn u(&self, x: Point) -> Vector {
        let (sx, sy) = ((PI * x.x).sin(), (PI * x.y).sin());
        Vector::new(sx * sy, (2.0 * PI * x.x).sin() * sy)
    }
    fn grad(&self, x: Point) -> Matrix2<f64> {
        let (px, py) = (PI * x.x, PI * x.y);
        Matrix2::new(
            PI * px.cos() * py.sin(),
            PI * px.sin() * py.cos(),
            2.0 * PI * (2.0 * px).cos() * py.sin(),
            PI * (2.0 * px).sin() * py.cos(),
        )
    }
}

impl E1 {
    /// The body force of E1 for (lambda, mu).
    pub fn force(lambda: f64, mu: f64) -> impl Fn(Point) -> Vector + Send + Sync + 'static {
        move |x: Point| {
            let (px, py) = (PI * x.x, PI * x.y);
            let p2 = PI * PI;
            Vector::new(
                (lambda + 3.0 * mu) * p2 * px.sin() * py.sin()
                    - 2.0 * (lambda + mu) * p2 * (2.0 * px).cos() * py.cos(),
                (lambda + 6.0 * mu) * p2 * (2.0 * px).sin() * py.sin()
                    - (lambda + mu) * p2 * px.cos() * py.cos(),
            )
        }
    }
}

/// Errors of the energy projection of a discrete displacement against an exact field.
#[derive(Debug, Clone, Copy)]
pub struct ProjectionErrors {
    /// || grad(u - Pi u_h) ||_0, broken (element by element).
    pub grad: f64,
    /// || u - Pi u_h ||_0.
    pub l2: f64,
}

/// The errors of `Pi u_h` on every polygon, integrated with the degree-5 rule on the centroid
/// fan of each polygon.
pub fn projection_errors(
    body: &ElasticBody,
    displacement: &[f64],
    exact: &dyn ExactField,
) -> ProjectionErrors {
    let mesh = body.mesh();
    let rule = TriangleRule::degree5();
    let (mut grad, mut l2) = (0.0, 0.0);
    for p in 0..mesh.n_polygons() {
        let points = mesh.polygon_points(p);
        let projection = body
            .element()
            .as_planar()
            .unwrap()
            .projection(&points)
            .unwrap();
        let local = local_dofs(mesh, p, displacement);
        let g_h = projection.gradient(&local);
        for q in polygon_rule(&points, &rule) {
            let e = exact.u(q.point) - projection.evaluate(&local, q.point);
            l2 += q.weight * e.norm_squared();
            grad += q.weight * (exact.grad(q.point) - g_h).norm_squared();
        }
    }
    ProjectionErrors {
        grad: grad.sqrt(),
        l2: l2.sqrt(),
    }
}

/// The local DOF vector of polygon `p`.
pub fn local_dofs(mesh: &Mesh, p: usize, displacement: &[f64]) -> DVector<f64> {
    DVector::from_iterator(
        2 * mesh.polygon(p).len(),
        mesh.polygon(p)
            .iter()
            .flat_map(|&v| [displacement[2 * v], displacement[2 * v + 1]]),
    )
}

/// Least-squares slope of log(error) against log(h).
pub fn fitted_rate(h: &[f64], error: &[f64]) -> f64 {
    let n = h.len() as f64;
    let x: Vec<f64> = h.iter().map(|v| v.ln()).collect();
    let y: Vec<f64> = error.iter().map(|v| v.ln()).collect();
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxy: f64 = x.iter().zip(&y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx) * (a - mx)).sum();
    sxy / sxx
}

/// The largest nodal error |u_h(v) - u(v)| over the vertices, relative to max |u(v)|.
pub fn nodal_error(mesh: &Mesh, displacement: &[f64], exact: &dyn ExactField) -> f64 {
    let (mut error, mut scale) = (0.0f64, 0.0f64);
    for v in 0..mesh.n_vertices() {
        let u = exact.u(mesh.vertex(v));
        let u_h = Vector::new(displacement[2 * v], displacement[2 * v + 1]);
        error = error.max((u_h - u).norm());
        scale = scale.max(u.norm());
    }
    error / scale
}
