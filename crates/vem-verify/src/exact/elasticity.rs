//! One-body elasticity solutions on the unit square (`docs/manufactured.md`, section 6): E1
//! (trigonometric), E2 (divergence free, for the locking study) and the linear patch tests
//! PT0a, PT0b.

use std::f64::consts::PI;

use nalgebra::Matrix2;
use vem_mesh::generators::Rectangle;
use vem_mesh::{Point, Vector};

use super::solution::{BodyId, ExactSolution, Lame, Side};

/// Checks that a one-body solution is asked about its only body.
///
/// # Panics
/// If `body` is not [`BodyId::One`] (a programming error of the caller).
fn expect_single_body(name: &str, body: BodyId) {
    assert!(
        body == BodyId::One,
        "the exact solution {name} has a single body; {body:?} does not exist"
    );
}

/// E1: `u = (sin(pi x) sin(pi y), sin(2 pi x) sin(pi y))` on `(0,1)^2`, clamped on the whole
/// boundary; body force `~ lambda`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct E1 {
    lame: Lame,
}

impl E1 {
    /// E1 with the material `lame`.
    pub fn new(lame: Lame) -> Self {
        Self { lame }
    }
}

impl ExactSolution for E1 {
    fn name(&self) -> &str {
        "E1"
    }

    fn lame(&self) -> Lame {
        self.lame
    }

    fn bodies(&self) -> &'static [BodyId] {
        &BodyId::SINGLE
    }

    fn domain(&self, body: BodyId) -> Rectangle {
        expect_single_body(self.name(), body);
        Rectangle::unit_square()
    }

    fn displacement(&self, body: BodyId, x: Point) -> Vector {
        expect_single_body(self.name(), body);
        let sin_y = (PI * x.y).sin();
        Vector::new((PI * x.x).sin() * sin_y, (2.0 * PI * x.x).sin() * sin_y)
    }

    fn gradient(&self, body: BodyId, x: Point) -> Matrix2<f64> {
        expect_single_body(self.name(), body);
        let (sx, cx) = (PI * x.x).sin_cos();
        let (s2x, c2x) = (2.0 * PI * x.x).sin_cos();
        let (sy, cy) = (PI * x.y).sin_cos();
        Matrix2::new(
            PI * cx * sy,
            PI * sx * cy,
            2.0 * PI * c2x * sy,
            PI * s2x * cy,
        )
    }

    fn body_force(&self, body: BodyId, x: Point) -> Vector {
        expect_single_body(self.name(), body);
        let (lambda, mu) = (self.lame.lambda(), self.lame.mu());
        let (sx, cx) = (PI * x.x).sin_cos();
        let (s2x, c2x) = (2.0 * PI * x.x).sin_cos();
        let (sy, cy) = (PI * x.y).sin_cos();
        let pi2 = PI * PI;
        Vector::new(
            (lambda + 3.0 * mu) * pi2 * sx * sy - 2.0 * (lambda + mu) * pi2 * c2x * cy,
            (lambda + 6.0 * mu) * pi2 * s2x * sy - (lambda + mu) * pi2 * cx * cy,
        )
    }

    fn dirichlet_sides(&self, body: BodyId) -> Vec<Side> {
        expect_single_body(self.name(), body);
        Side::ALL.to_vec()
    }

    fn neumann_sides(&self, body: BodyId) -> Vec<Side> {
        expect_single_body(self.name(), body);
        Vec::new()
    }
}

/// `A(t) = t^2 (1-t)^2` and its first two derivatives.
fn bubble(t: f64) -> [f64; 3] {
    let s = 1.0 - t;
    [
        t * t * s * s,
        2.0 * t * s * (1.0 - 2.0 * t),
        2.0 - 12.0 * t + 12.0 * t * t,
    ]
}

/// E2: the divergence-free field `u = curl psi`, `psi = x^2 (1-x)^2 y^2 (1-y)^2`, clamped on
/// the whole boundary: `u`, `sigma = 2 mu eps(u)` and `f` do not depend on `lambda`, so any
/// growth of the discrete error with `lambda` is locking.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct E2 {
    lame: Lame,
}

impl E2 {
    /// E2 with the material `lame`.
    pub fn new(lame: Lame) -> Self {
        Self { lame }
    }
}

impl ExactSolution for E2 {
    fn name(&self) -> &str {
        "E2"
    }

    fn lame(&self) -> Lame {
        self.lame
    }

    fn bodies(&self) -> &'static [BodyId] {
        &BodyId::SINGLE
    }

    fn domain(&self, body: BodyId) -> Rectangle {
        expect_single_body(self.name(), body);
        Rectangle::unit_square()
    }

    fn displacement(&self, body: BodyId, x: Point) -> Vector {
        expect_single_body(self.name(), body);
        let (ax, ay) = (bubble(x.x), bubble(x.y));
        // u_x = 2 x^2 (1-x)^2 y (1-y) (1-2y) = A(x) A'(y), u_y = -A'(x) A(y).
        Vector::new(ax[0] * ay[1], -ax[1] * ay[0])
    }

    fn gradient(&self, body: BodyId, x: Point) -> Matrix2<f64> {
        expect_single_body(self.name(), body);
        let (ax, ay) = (bubble(x.x), bubble(x.y));
        Matrix2::new(ax[1] * ay[1], ax[0] * ay[2], -ax[2] * ay[0], -ax[1] * ay[1])
    }

    fn body_force(&self, body: BodyId, x: Point) -> Vector {
        expect_single_body(self.name(), body);
        let mu = self.lame.mu();
        let (x, y) = (x.x, x.y);
        Vector::new(
            -4.0 * mu
                * (1.0 - 2.0 * y)
                * ((1.0 - 6.0 * x + 6.0 * x * x) * y * (1.0 - y)
                    - 3.0 * x * x * (1.0 - x) * (1.0 - x)),
            4.0 * mu
                * (1.0 - 2.0 * x)
                * ((1.0 - 6.0 * y + 6.0 * y * y) * x * (1.0 - x)
                    - 3.0 * y * y * (1.0 - y) * (1.0 - y)),
        )
    }

    fn dirichlet_sides(&self, body: BodyId) -> Vec<Side> {
        expect_single_body(self.name(), body);
        Side::ALL.to_vec()
    }

    fn neumann_sides(&self, body: BodyId) -> Vec<Side> {
        expect_single_body(self.name(), body);
        Vec::new()
    }
}

/// The linear patch tests PT0a and PT0b: an affine field `u = u_0 + G x` on `(0,1)^2` with
/// zero body force and constant stress, which the lowest-order VEM reproduces exactly on any
/// polygonal mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct AffinePatch {
    name: &'static str,
    lame: Lame,
    offset: Vector,
    gradient: Matrix2<f64>,
    dirichlet: &'static [Side],
    neumann: &'static [Side],
}

impl AffinePatch {
    /// PT0a: `u = ((1 + 2x + 3y)/10, (2 - x + 4y)/10)`, Dirichlet data on the whole boundary.
    pub fn pt0a(lame: Lame) -> Self {
        Self {
            name: "PT0a",
            lame,
            offset: Vector::new(0.1, 0.2),
            gradient: Matrix2::new(0.2, 0.3, -0.1, 0.4),
            dirichlet: &Side::ALL,
            neumann: &[],
        }
    }

    /// PT0b: `u = (1 - y) (1/10, -1/20)`, clamped top, constant tractions on the left, right
    /// and bottom sides.
    pub fn pt0b(lame: Lame) -> Self {
        Self {
            name: "PT0b",
            lame,
            offset: Vector::new(0.1, -0.05),
            gradient: Matrix2::new(0.0, -0.1, 0.0, 0.05),
            dirichlet: &[Side::Top],
            neumann: &[Side::Left, Side::Right, Side::Bottom],
        }
    }
}

impl ExactSolution for AffinePatch {
    fn name(&self) -> &str {
        self.name
    }

    fn lame(&self) -> Lame {
        self.lame
    }

    fn bodies(&self) -> &'static [BodyId] {
        &BodyId::SINGLE
    }

    fn domain(&self, body: BodyId) -> Rectangle {
        expect_single_body(self.name, body);
        Rectangle::unit_square()
    }

    fn displacement(&self, body: BodyId, x: Point) -> Vector {
        expect_single_body(self.name, body);
        self.offset + self.gradient * x.coords
    }

    fn gradient(&self, body: BodyId, _x: Point) -> Matrix2<f64> {
        expect_single_body(self.name, body);
        self.gradient
    }

    fn body_force(&self, body: BodyId, _x: Point) -> Vector {
        expect_single_body(self.name, body);
        Vector::zeros()
    }

    fn dirichlet_sides(&self, body: BodyId) -> Vec<Side> {
        expect_single_body(self.name, body);
        self.dirichlet.to_vec()
    }

    fn neumann_sides(&self, body: BodyId) -> Vec<Side> {
        expect_single_body(self.name, body);
        self.neumann.to_vec()
    }
}
