//! Exact solutions of linear elasticity on the unit cube (`docs/manufactured.md`, section 11).
//!
//! Every solution here is a sum of separable terms `c f(x) g(y) h(z)` per component, with each
//! one-dimensional factor a [`Jet`] (value and three derivatives): the gradient and the second
//! derivatives of the displacement are exact, so are the stress and the body force
//! `f = -div sigma = -[(lambda + mu) grad div u + mu Laplace u]`.

use nalgebra::Matrix3;
use vem_mesh::generators::polyhedral::Cuboid;
use vem_mesh::{Point3, Vector3};

use crate::exact::{Jet, Lame};

/// The boundary parts of the unit cube as the polyhedral generators name them, with their
/// outward normals.
pub const CUBE_PARTS: [(&str, [f64; 3]); 6] = [
    ("left", [-1.0, 0.0, 0.0]),
    ("right", [1.0, 0.0, 0.0]),
    ("front", [0.0, -1.0, 0.0]),
    ("back", [0.0, 1.0, 0.0]),
    ("bottom", [0.0, 0.0, -1.0]),
    ("top", [0.0, 0.0, 1.0]),
];

/// An exact solution of linear elasticity on a box (the unit cube `(0, 1)^3` unless
/// [`domain`](ExactSolution3d::domain) says otherwise): displacement, gradient and body force for
/// an isotropic material, which sides carry a traction, which lie on a contact interface (the
/// others carry the Dirichlet data `u`).
pub trait ExactSolution3d: Send + Sync {
    /// The case's name ("E1-3D", ...).
    fn name(&self) -> &str;

    /// The material.
    fn lame(&self) -> Lame;

    /// The displacement `u(x)`.
    fn displacement(&self, x: Point3) -> Vector3;

    /// The displacement gradient, `(i, j) = d_j u_i`.
    fn gradient(&self, x: Point3) -> Matrix3<f64>;

    /// The body force `f = -div sigma`.
    fn body_force(&self, x: Point3) -> Vector3;

    /// The sides of [`CUBE_PARTS`] that carry the traction `sigma n` (default: none; every side
    /// then carries `u`).
    fn traction_sides(&self) -> &[&'static str] {
        &[]
    }

    /// The sides of [`CUBE_PARTS`] on a contact interface (default: none): they carry neither
    /// Dirichlet data nor a traction, the contact problem imposes their conditions (the bodies
    /// of [`DiscContact`](super::DiscContact)).
    fn contact_sides(&self) -> &[&'static str] {
        &[]
    }

    /// The box the solution lives on (default: the unit cube `(0, 1)^3`), whose sides the
    /// polyhedral generators name as [`CUBE_PARTS`] does.
    fn domain(&self) -> Cuboid {
        Cuboid::unit_cube()
    }

    /// The displacement and its gradient together (default: [`Self::displacement`] and
    /// [`Self::gradient`]; solutions that share work between them override it). The error
    /// norms call this at every quadrature point.
    fn displacement_and_gradient(&self, x: Point3) -> (Vector3, Matrix3<f64>) {
        (self.displacement(x), self.gradient(x))
    }

    /// The stress `lambda tr(eps) I + 2 mu eps`.
    fn stress(&self, x: Point3) -> Matrix3<f64> {
        let lame = self.lame();
        let g = self.gradient(x);
        let strain = (g + g.transpose()) * 0.5;
        Matrix3::identity() * (lame.lambda() * strain.trace()) + strain * (2.0 * lame.mu())
    }
}

/// A one-dimensional factor of a separable term.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Factor {
    /// `sin(k pi t)`.
    SinPi(f64),
    /// The `derivative`-th derivative of the polynomial with these coefficients (increasing
    /// powers).
    Polynomial {
        coefficients: &'static [f64],
        derivative: usize,
    },
}

impl Factor {
    /// Value and three derivatives at `t`.
    fn jet(self, t: f64) -> Jet<4> {
        match self {
            Factor::SinPi(k) => {
                let w = k * std::f64::consts::PI;
                let (s, c) = (w * t).sin_cos();
                Jet([s, w * c, -w * w * s, -w * w * w * c])
            }
            Factor::Polynomial {
                coefficients,
                derivative,
            } => {
                let full: Jet<5> = Jet::polynomial(coefficients, t);
                Jet(std::array::from_fn(|j| full.0[j + derivative]))
            }
        }
    }
}

/// `c f(x) g(y) h(z)`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Term {
    coefficient: f64,
    factors: [Factor; 3],
}

/// Value, gradient and Hessian of one scalar field at a point.
pub(super) struct Evaluated {
    pub(super) value: f64,
    pub(super) gradient: Vector3,
    pub(super) hessian: Matrix3<f64>,
}

/// The displacement of the three evaluated components.
pub(super) fn displacement_of(e: &[Evaluated; 3]) -> Vector3 {
    Vector3::new(e[0].value, e[1].value, e[2].value)
}

/// The displacement gradient, `(i, j) = d_j u_i`, of the three evaluated components.
pub(super) fn gradient_of(e: &[Evaluated; 3]) -> Matrix3<f64> {
    Matrix3::from_fn(|i, j| e[i].gradient[j])
}

/// The body force `-[(lambda + mu) grad div u + mu Laplace u]` of the three evaluated
/// components.
pub(super) fn body_force_of(lame: Lame, e: &[Evaluated; 3]) -> Vector3 {
    Vector3::from_fn(|i, _| {
        // d_i div u = sum_j d_i d_j u_j.
        let grad_div: f64 = (0..3).map(|j| e[j].hessian[(i, j)]).sum();
        let laplace = e[i].hessian.trace();
        -((lame.lambda() + lame.mu()) * grad_div + lame.mu() * laplace)
    })
}

/// A vector field whose every component is a sum of separable terms.
#[derive(Debug, Clone, PartialEq)]
struct Separable {
    components: [Vec<Term>; 3],
}

impl Separable {
    /// Value, gradient and Hessian of every component at `x`, each distinct one-dimensional
    /// factor evaluated once.
    fn evaluate_all(&self, x: Point3) -> [Evaluated; 3] {
        let coordinates = [x.x, x.y, x.z];
        let mut cache: Vec<(usize, Factor, Jet<4>)> = Vec::with_capacity(9);
        let mut jet = |axis: usize, factor: Factor| -> Jet<4> {
            if let Some(&(_, _, j)) = cache.iter().find(|(a, f, _)| *a == axis && *f == factor) {
                return j;
            }
            let j = factor.jet(coordinates[axis]);
            cache.push((axis, factor, j));
            j
        };
        std::array::from_fn(|i| {
            let mut out = Evaluated {
                value: 0.0,
                gradient: Vector3::zeros(),
                hessian: Matrix3::zeros(),
            };
            for term in &self.components[i] {
                let jets = [
                    jet(0, term.factors[0]),
                    jet(1, term.factors[1]),
                    jet(2, term.factors[2]),
                ];
                // d^(a+b+c) / dx^a dy^b dz^c of the product.
                let d = |orders: [usize; 3]| {
                    term.coefficient * jets[0][orders[0]] * jets[1][orders[1]] * jets[2][orders[2]]
                };
                out.value += d([0, 0, 0]);
                for j in 0..3 {
                    let mut orders = [0; 3];
                    orders[j] = 1;
                    out.gradient[j] += d(orders);
                    for k in j..3 {
                        let mut orders = [0; 3];
                        orders[j] += 1;
                        orders[k] += 1;
                        let value = d(orders);
                        out.hessian[(j, k)] += value;
                        if k != j {
                            out.hessian[(k, j)] += value;
                        }
                    }
                }
            }
            out
        })
    }

    fn displacement(&self, x: Point3) -> Vector3 {
        displacement_of(&self.evaluate_all(x))
    }

    fn gradient(&self, x: Point3) -> Matrix3<f64> {
        gradient_of(&self.evaluate_all(x))
    }

    fn displacement_and_gradient(&self, x: Point3) -> (Vector3, Matrix3<f64>) {
        let e = self.evaluate_all(x);
        (displacement_of(&e), gradient_of(&e))
    }

    /// `-[(lambda + mu) grad div u + mu Laplace u]`.
    fn body_force(&self, lame: Lame, x: Point3) -> Vector3 {
        body_force_of(lame, &self.evaluate_all(x))
    }
}

/// "PT0-3D": the linear patch test in space, `u = a + M x` with every strain component,
/// `f = 0`, Dirichlet data `u` on the whole boundary:
///
/// ```text
/// u = (1, -2, 1/2)/10 + M x,   M = [[2, 1, -1], [1/2, -2, 3], [3/2, 1, 5/2]] / 100
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearSolid {
    lame: Lame,
}

impl LinearSolid {
    /// The patch test for the material `lame`.
    pub fn new(lame: Lame) -> Self {
        Self { lame }
    }

    /// The constant gradient `M`.
    pub fn gradient_matrix() -> Matrix3<f64> {
        Matrix3::new(2.0, 1.0, -1.0, 0.5, -2.0, 3.0, 1.5, 1.0, 2.5) / 100.0
    }
}

impl ExactSolution3d for LinearSolid {
    fn name(&self) -> &str {
        "PT0-3D"
    }

    fn lame(&self) -> Lame {
        self.lame
    }

    fn displacement(&self, x: Point3) -> Vector3 {
        Vector3::new(0.1, -0.2, 0.05) + Self::gradient_matrix() * x.coords
    }

    fn gradient(&self, _x: Point3) -> Matrix3<f64> {
        Self::gradient_matrix()
    }

    fn body_force(&self, _x: Point3) -> Vector3 {
        Vector3::zeros()
    }
}

/// "E1-3D": a smooth solution, zero on five sides of the cube and with a traction on the top:
///
/// ```text
/// u_x = sin(pi x) sin(pi y) sin(pi z)
/// u_y = sin(2 pi x) sin(pi y) sin(pi z)
/// u_z = sin(pi x) sin(pi y) sin(2 pi z)
/// ```
///
/// Dirichlet data `u = 0` on left, right, front, back and bottom; the traction `sigma e_z` on
/// the top (`u = 0` there too, but its traction is not: `sigma_zz = 2 pi (lambda + 2 mu) sin(pi
/// x) sin(pi y)` at `z = 1`, from `d_z u_z`, `sigma_xz = -pi mu sin(pi x) sin(pi y)` from
/// `d_z u_x`). The body force (`docs/manufactured.md`, section 11) grows like `lambda`.
#[derive(Debug, Clone, PartialEq)]
pub struct SmoothSolid {
    lame: Lame,
    field: Separable,
}

impl SmoothSolid {
    /// The solution for the material `lame`.
    pub fn new(lame: Lame) -> Self {
        let term = |a: f64, b: f64, c: f64| Term {
            coefficient: 1.0,
            factors: [Factor::SinPi(a), Factor::SinPi(b), Factor::SinPi(c)],
        };
        Self {
            lame,
            field: Separable {
                components: [
                    vec![term(1.0, 1.0, 1.0)],
                    vec![term(2.0, 1.0, 1.0)],
                    vec![term(1.0, 1.0, 2.0)],
                ],
            },
        }
    }
}

impl ExactSolution3d for SmoothSolid {
    fn name(&self) -> &str {
        "E1-3D"
    }

    fn lame(&self) -> Lame {
        self.lame
    }

    fn displacement(&self, x: Point3) -> Vector3 {
        self.field.displacement(x)
    }

    fn gradient(&self, x: Point3) -> Matrix3<f64> {
        self.field.gradient(x)
    }

    fn displacement_and_gradient(&self, x: Point3) -> (Vector3, Matrix3<f64>) {
        self.field.displacement_and_gradient(x)
    }

    fn body_force(&self, x: Point3) -> Vector3 {
        self.field.body_force(self.lame, x)
    }

    fn traction_sides(&self) -> &[&'static str] {
        &["top"]
    }
}

/// `P(t) = t^2 (1 - t)^2 = t^2 - 2 t^3 + t^4`.
const BUBBLE: [f64; 5] = [0.0, 0.0, 1.0, -2.0, 1.0];

/// "E2-3D": a divergence-free solution for the locking study, zero on the whole boundary:
/// `u = A curl(phi, phi, phi)` with `phi = P(x) P(y) P(z)`, `P(t) = t^2 (1 - t)^2`, `A = 100`:
///
/// ```text
/// u_x = A (d_y phi - d_z phi),  u_y = A (d_z phi - d_x phi),  u_z = A (d_x phi - d_y phi)
/// ```
///
/// `div u = 0` exactly, `phi` and its gradient vanish on the boundary (so does `u`),
/// `sigma = 2 mu eps(u)` and `f = -mu Laplace u` do not depend on `lambda`: any growth of the
/// error with `lambda / mu` is locking.
#[derive(Debug, Clone, PartialEq)]
pub struct DivergenceFreeSolid {
    lame: Lame,
    field: Separable,
}

impl DivergenceFreeSolid {
    /// The amplitude `A`.
    pub const AMPLITUDE: f64 = 100.0;

    /// The solution for the material `lame` (only `mu` enters the load).
    pub fn new(lame: Lame) -> Self {
        let p = Factor::Polynomial {
            coefficients: &BUBBLE,
            derivative: 0,
        };
        let dp = Factor::Polynomial {
            coefficients: &BUBBLE,
            derivative: 1,
        };
        let a = Self::AMPLITUDE;
        // d_x phi = P' P P, d_y phi = P P' P, d_z phi = P P P'.
        let d = |axis: usize, sign: f64| {
            let mut factors = [p; 3];
            factors[axis] = dp;
            Term {
                coefficient: sign * a,
                factors,
            }
        };
        Self {
            lame,
            field: Separable {
                components: [
                    vec![d(1, 1.0), d(2, -1.0)],
                    vec![d(2, 1.0), d(0, -1.0)],
                    vec![d(0, 1.0), d(1, -1.0)],
                ],
            },
        }
    }
}

impl ExactSolution3d for DivergenceFreeSolid {
    fn name(&self) -> &str {
        "E2-3D"
    }

    fn lame(&self) -> Lame {
        self.lame
    }

    fn displacement(&self, x: Point3) -> Vector3 {
        self.field.displacement(x)
    }

    fn gradient(&self, x: Point3) -> Matrix3<f64> {
        self.field.gradient(x)
    }

    fn displacement_and_gradient(&self, x: Point3) -> (Vector3, Matrix3<f64>) {
        self.field.displacement_and_gradient(x)
    }

    fn body_force(&self, x: Point3) -> Vector3 {
        self.field.body_force(self.lame, x)
    }
}

/// The names of the built-in solutions in space, in the order of [`solid_case_by_name`].
pub const SOLID_CASE_NAMES: [&str; 3] = ["PT0-3D", "E1-3D", "E2-3D"];

/// The built-in solution in space named `name` (see [`SOLID_CASE_NAMES`]) for the material
/// `lame`; `None` for an unknown name.
pub fn solid_case_by_name(name: &str, lame: Lame) -> Option<Box<dyn ExactSolution3d>> {
    Some(match name {
        "PT0-3D" => Box::new(LinearSolid::new(lame)),
        "E1-3D" => Box::new(SmoothSolid::new(lame)),
        "E2-3D" => Box::new(DivergenceFreeSolid::new(lame)),
        _ => return None,
    })
}
