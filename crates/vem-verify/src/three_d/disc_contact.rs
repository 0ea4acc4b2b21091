//! "M1-3D": frictionless contact of two stacked boxes on a disc (`docs/manufactured.md`,
//! section 11, "M1-3D"): the analogue in space of M1, contact inside the disc
//! `|(x, y) - c| < r_c` of the interface `z = 0`, separation outside, the pressure and the gap
//! both vanishing on the circle with three and four continuous derivatives.
//!
//! Family A of section 2 in space: body `i` (orientation `s_1 = +1` above, `s_2 = -1` below)
//! has the tangential trace `alpha_i(x, y)`, the normal trace `phi_i(x, y)`, the shear traction
//! `t = 0` (frictionless) and the pressure `p(x, y) = -sigma_zz(x, y, 0)`, and
//!
//! ```text
//! u_T = Z2 alpha + Zs theta,        theta = t / mu - grad phi = -grad phi
//! u_z = Z2 phi - kappa Zs pi,       pi = p + lambda div alpha,   kappa = 1 / (lambda + 2 mu)
//! Z2 = 1 - z^2,   Zs = z (1 - s z)
//! ```
//!
//! Every coefficient is a function of `(x, y)` with exact derivatives up to the third (a
//! quadratic polynomial or a power of the switch variable `|(x, y) - c|^2`), so the gradient,
//! the stress and the body force are exact.

use std::ops::{Add, Mul, Neg};
use std::sync::Arc;

use nalgebra::{Matrix2, Matrix3, Vector2};
use vem_contact::{ContactLaw, Frictionless};
use vem_mesh::generators::polyhedral::Cuboid;
use vem_mesh::{Point3, Vector3};

use super::exact::{body_force_of, displacement_of, gradient_of, Evaluated, ExactSolution3d};
use crate::exact::{BodyId, Jet, Lame, SwitchPower, SwitchSide};

/// Value and derivatives up to the third of a function of `(x, y)`.
#[derive(Debug, Clone, Copy)]
pub(super) struct PlaneJet {
    pub(super) value: f64,
    pub(super) gradient: Vector2<f64>,
    pub(super) hessian: Matrix2<f64>,
    /// `third[k]` is `d_k` of the Hessian.
    pub(super) third: [Matrix2<f64>; 2],
}

impl PlaneJet {
    /// `c0 + cx x + cy y + cxx x^2 + cxy x y + cyy y^2` with `c = [c0, cx, cy, cxx, cxy, cyy]`.
    pub(super) fn quadratic(c: [f64; 6], x: f64, y: f64) -> Self {
        Self {
            value: c[0] + c[1] * x + c[2] * y + c[3] * x * x + c[4] * x * y + c[5] * y * y,
            gradient: Vector2::new(
                c[1] + 2.0 * c[3] * x + c[4] * y,
                c[2] + c[4] * x + 2.0 * c[5] * y,
            ),
            hessian: Matrix2::new(2.0 * c[3], c[4], c[4], 2.0 * c[5]),
            third: [Matrix2::zeros(); 2],
        }
    }

    /// `g(|(x, y) - centre|^2)` for the switch function `g` (chain rule with
    /// `v = grad |x - c|^2 = 2 (x - c)`, whose own gradient is `2 I`).
    pub(super) fn radial(g: &SwitchPower, centre: [f64; 2], x: f64, y: f64) -> Self {
        let v = Vector2::new(2.0 * (x - centre[0]), 2.0 * (y - centre[1]));
        let s = 0.25 * v.norm_squared();
        let j: Jet<4> = g.jet(s);
        let delta = |a: usize, b: usize| if a == b { 1.0 } else { 0.0 };
        Self {
            value: j[0],
            gradient: v * j[1],
            hessian: Matrix2::from_fn(|a, b| j[2] * v[a] * v[b] + 2.0 * j[1] * delta(a, b)),
            third: std::array::from_fn(|k| {
                Matrix2::from_fn(|a, b| {
                    j[3] * v[a] * v[b] * v[k]
                        + 2.0
                            * j[2]
                            * (delta(a, b) * v[k] + delta(a, k) * v[b] + delta(b, k) * v[a])
                })
            }),
        }
    }

    /// The partial derivative `d_k`; its third derivatives are not known and are NaN (only
    /// value, gradient and Hessian of a derivative enter the field).
    pub(super) fn partial(&self, k: usize) -> Self {
        Self {
            value: self.gradient[k],
            gradient: self.hessian.column(k).into_owned(),
            hessian: self.third[k],
            third: [Matrix2::from_element(f64::NAN); 2],
        }
    }

    /// The product `f g` by Leibniz's rule, to the third derivatives.
    pub(super) fn product(&self, g: &Self) -> Self {
        let f = self;
        Self {
            value: f.value * g.value,
            gradient: f.gradient * g.value + g.gradient * f.value,
            hessian: Matrix2::from_fn(|a, b| {
                f.hessian[(a, b)] * g.value
                    + f.gradient[a] * g.gradient[b]
                    + f.gradient[b] * g.gradient[a]
                    + f.value * g.hessian[(a, b)]
            }),
            third: std::array::from_fn(|k| {
                Matrix2::from_fn(|a, b| {
                    f.third[k][(a, b)] * g.value
                        + f.hessian[(a, b)] * g.gradient[k]
                        + f.hessian[(a, k)] * g.gradient[b]
                        + f.hessian[(b, k)] * g.gradient[a]
                        + f.gradient[a] * g.hessian[(b, k)]
                        + f.gradient[b] * g.hessian[(a, k)]
                        + f.gradient[k] * g.hessian[(a, b)]
                        + f.value * g.third[k][(a, b)]
                })
            }),
        }
    }
}

impl Add for PlaneJet {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self {
            value: self.value + o.value,
            gradient: self.gradient + o.gradient,
            hessian: self.hessian + o.hessian,
            third: [self.third[0] + o.third[0], self.third[1] + o.third[1]],
        }
    }
}

impl Mul<f64> for PlaneJet {
    type Output = Self;
    fn mul(self, c: f64) -> Self {
        Self {
            value: self.value * c,
            gradient: self.gradient * c,
            hessian: self.hessian * c,
            third: [self.third[0] * c, self.third[1] * c],
        }
    }
}

impl Neg for PlaneJet {
    type Output = Self;
    fn neg(self) -> Self {
        self * -1.0
    }
}

/// `Z(z) C(x, y)` summed into value, gradient and Hessian of a component, with
/// `z_jet = [Z, Z', Z'']`.
fn add_term(out: &mut Evaluated, z_jet: [f64; 3], c: &PlaneJet) {
    let [z, dz, ddz] = z_jet;
    out.value += z * c.value;
    for a in 0..2 {
        out.gradient[a] += z * c.gradient[a];
        for b in 0..2 {
            out.hessian[(a, b)] += z * c.hessian[(a, b)];
        }
        out.hessian[(a, 2)] += dz * c.gradient[a];
        out.hessian[(2, a)] += dz * c.gradient[a];
    }
    out.gradient[2] += dz * c.value;
    out.hessian[(2, 2)] += ddz * c.value;
}

/// Exact values on the interface `z = 0` at one point `(x, y)`, in the conventions of
/// `docs/manufactured.md`, section 1 (`nu_1 = -e_z`, `nu_2 = e_z`; tangential quantities as
/// vectors `(x, y)` of the interface plane).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InterfaceValues3d {
    /// `sigma_nu = (sigma_1 nu_1) . nu_1 = sigma_zz` (compression is negative).
    pub sigma_nu: f64,
    /// The tangential traction on body one, `(sigma_1 nu_1)_T = -(sigma_xz, sigma_yz)`.
    pub sigma_1tau: Vector2<f64>,
    /// `[u]_nu = u_1 . nu_1 + u_2 . nu_2 = u_2z - u_1z`.
    pub normal_jump: f64,
    /// `[u]_1tau = (u_1 - u_2)_T`.
    pub tangential_jump: Vector2<f64>,
    /// The initial gap `h0`.
    pub initial_gap: f64,
}

impl InterfaceValues3d {
    /// The remaining gap `h0 - [u]_nu` (zero where the bodies touch).
    pub fn gap(&self) -> f64 {
        self.initial_gap - self.normal_jump
    }
}

/// A manufactured two-body contact case on the stacked boxes `Omega_1 = (0, 1)^3` (upper) and
/// `Omega_2 = (0, 1)^2 x (-1, 0)` (lower) across the interface `z = 0` ([`DiscContact`],
/// "M1-3D"; [`StickSlipContact`](super::StickSlipContact), "M2-3D"): each body an
/// [`ExactSolution3d`], the contact law and the imposed gap of the pair, the exact interface
/// values and resultants the discrete solves are compared with, and the circle of radius
/// [`StackedContact::zone_radius`] around `(1/2, 1/2)` where the two zones of the interface
/// meet (contact and separation, or stick and slip).
pub trait StackedContact: Send + Sync {
    /// The case's name ("M1-3D", ...).
    fn name(&self) -> &'static str;

    /// Body `body` as a solution of elasticity on its box (its contact side free).
    fn exact_body(&self, body: BodyId) -> Arc<dyn ExactSolution3d>;

    /// The contact law between body one's bottom and body two's top.
    fn law(&self) -> Arc<dyn ContactLaw<3>>;

    /// The gap imposed at `(x, y)` of the interface, as a function (the two sides coincide:
    /// the geometric gap is zero).
    fn imposed_gap(&self) -> Arc<dyn Fn(f64, f64) -> f64 + Send + Sync>;

    /// The exact values on the interface at `(x, y)`.
    fn interface_values(&self, x: f64, y: f64) -> InterfaceValues3d;

    /// The radius of the circle around `(1/2, 1/2)` where the two zones of the interface meet.
    fn zone_radius(&self) -> f64;

    /// The exact resultant of the pressure, `int -sigma_nu dA`.
    fn exact_normal_resultant(&self) -> f64;

    /// The exact resultant of the friction traction on body one, `int sigma_1tau dA` (zero
    /// without friction).
    fn exact_friction_resultant(&self) -> Vector2<f64>;
}

/// "M1-3D": frictionless contact of the upper box `Omega_1 = (0, 1)^2 x (0, 1)` on the lower
/// box `Omega_2 = (0, 1)^2 x (-1, 0)` across `z = 0`, in contact inside the disc
/// `r = |(x, y) - c| < r_c`, separated outside (`docs/manufactured.md`, section 11):
///
/// ```text
/// s = r^2,  S = r_c^2,  c = (1/2, 1/2),  r_c = (3 - sqrt 5)/2
/// p = p0 ((S - s)_+ / S)^4                     pressure (p0 = 1)
/// q = q0 ((s - S)_+ / (1/2 - S))^5             opening (q0 = 1/20)
/// alpha_1 = (x^2, x y)/20,  alpha_2 = (-x/20, -y/40),  t = 0
/// w = (1 + x^2 + y^2)/20,   h0 = (2 + x + y + x^2 + y^2)/40
/// phi_1 = -w - h0 + q,      phi_2 = -w
/// ```
///
/// so that `sigma_nu = -p`, the shear vanishes, `[u]_nu = h0 - q`: the gap `q` is zero where
/// `p > 0` and `p` is zero where `q > 0`. Dirichlet data `u = 0` on the top of body one and the
/// bottom of body two, the tractions `sigma n` on the four lateral sides of each, the body force
/// `-div sigma`. The bodies are [`DiscContact::body`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DiscContact {
    lame: Lame,
}

/// `r_c^2 = (7 - 3 sqrt 5)/2`.
const CONTACT_RADIUS_SQUARED: f64 = 0.145_898_033_750_315_46;

/// The pressure `p = p0 ((S - s)_+ / S)^4` as a function of `s = r^2`.
const PRESSURE: SwitchPower = SwitchPower::from_valid_parts(
    DiscContact::PEAK_PRESSURE,
    SwitchSide::Below,
    CONTACT_RADIUS_SQUARED,
    CONTACT_RADIUS_SQUARED,
    4,
);

/// The opening `q = q0 ((s - S)_+ / (1/2 - S))^5` (`q = q0` at the corners, `s = 1/2`).
const OPENING: SwitchPower = SwitchPower::from_valid_parts(
    DiscContact::OPENING,
    SwitchSide::Above,
    CONTACT_RADIUS_SQUARED,
    0.5 - CONTACT_RADIUS_SQUARED,
    5,
);

impl DiscContact {
    /// The case's name.
    pub const NAME: &'static str = "M1-3D";
    /// The centre `c` of the contact disc.
    pub const CENTRE: [f64; 2] = [0.5, 0.5];
    /// The radius `r_c = (3 - sqrt 5)/2 = 1 - x_c` of the contact disc (`x_c` the switch
    /// point of M1); `r_c^2 = (7 - 3 sqrt 5)/2` is irrational, so the circle passes through no
    /// point with rational coordinates: no vertex of a mesh with rational vertices lies on it.
    pub const CONTACT_RADIUS: f64 = 0.381_966_011_250_105_1;
    /// The pressure at the centre, `p0`.
    pub const PEAK_PRESSURE: f64 = 1.0;
    /// The gap at the corners of the interface, `q0`.
    pub const OPENING: f64 = 0.05;

    /// The solution for the material `lame`.
    pub fn new(lame: Lame) -> Self {
        Self { lame }
    }

    /// The material.
    pub fn lame(&self) -> Lame {
        self.lame
    }

    /// The box of body `body`: `(0, 1)^3` for body one, `(0, 1)^2 x (-1, 0)` for body two.
    pub fn domain(body: BodyId) -> Cuboid {
        match body {
            BodyId::One => Cuboid::unit_cube(),
            BodyId::Two => Cuboid::new(Point3::new(0.0, 0.0, -1.0), Point3::new(1.0, 1.0, 0.0)),
        }
    }

    /// The body `body` as a solution of elasticity on its box (its contact side free).
    pub fn body(&self, body: BodyId) -> DiscContactBody {
        DiscContactBody {
            solution: *self,
            body,
            name: match body {
                BodyId::One => "M1-3D body 1",
                BodyId::Two => "M1-3D body 2",
            },
        }
    }

    /// The distance `r = |(x, y) - c|` to the centre of the contact disc.
    pub fn radius(x: f64, y: f64) -> f64 {
        (x - Self::CENTRE[0]).hypot(y - Self::CENTRE[1])
    }

    /// The initial gap `h0 = (2 + x + y + x^2 + y^2)/40 >= 1/20`.
    pub fn initial_gap(x: f64, y: f64) -> f64 {
        (2.0 + x + y + x * x + y * y) / 40.0
    }

    /// The contact pressure `p = -sigma_nu`.
    pub fn pressure(x: f64, y: f64) -> f64 {
        PlaneJet::radial(&PRESSURE, Self::CENTRE, x, y).value
    }

    /// The remaining gap `q = h0 - [u]_nu`.
    pub fn gap(x: f64, y: f64) -> f64 {
        PlaneJet::radial(&OPENING, Self::CENTRE, x, y).value
    }

    /// The resultant of the pressure, `int p dA = p0 pi r_c^2 / 5` (with `s = r^2`,
    /// `dA = pi ds`): the sum of the nodal contact forces converges to it.
    pub fn normal_resultant() -> f64 {
        Self::PEAK_PRESSURE * std::f64::consts::PI * CONTACT_RADIUS_SQUARED / 5.0
    }

    /// The values on the interface at `(x, y)`, from the traces of section 2 (not from the
    /// fields: the tests compare the two).
    pub fn interface(&self, x: f64, y: f64) -> InterfaceValues3d {
        let (alpha_1, phi_1) = self.traces(BodyId::One, x, y);
        let (alpha_2, phi_2) = self.traces(BodyId::Two, x, y);
        InterfaceValues3d {
            sigma_nu: -Self::pressure(x, y),
            sigma_1tau: Vector2::zeros(),
            normal_jump: phi_2.value - phi_1.value,
            tangential_jump: Vector2::new(
                alpha_1[0].value - alpha_2[0].value,
                alpha_1[1].value - alpha_2[1].value,
            ),
            initial_gap: Self::initial_gap(x, y),
        }
    }

    /// The tangential trace `alpha` and the normal trace `phi` of body `body`.
    fn traces(&self, body: BodyId, x: f64, y: f64) -> ([PlaneJet; 2], PlaneJet) {
        let quadratic = |c| PlaneJet::quadratic(c, x, y);
        let w = quadratic([1.0, 0.0, 0.0, 1.0, 0.0, 1.0]) * (1.0 / 20.0);
        match body {
            BodyId::One => {
                let h0 = quadratic([2.0, 1.0, 1.0, 1.0, 0.0, 1.0]) * (1.0 / 40.0);
                let q = PlaneJet::radial(&OPENING, Self::CENTRE, x, y);
                (
                    [
                        quadratic([0.0, 0.0, 0.0, 1.0 / 20.0, 0.0, 0.0]),
                        quadratic([0.0, 0.0, 0.0, 0.0, 1.0 / 20.0, 0.0]),
                    ],
                    -w + -h0 + q,
                )
            }
            BodyId::Two => (
                [
                    quadratic([0.0, -1.0 / 20.0, 0.0, 0.0, 0.0, 0.0]),
                    quadratic([0.0, 0.0, -1.0 / 40.0, 0.0, 0.0, 0.0]),
                ],
                -w,
            ),
        }
    }

    /// Value, gradient and Hessian of the three components of `u_body` at `x`.
    fn evaluate(&self, body: BodyId, x: Point3) -> [Evaluated; 3] {
        let (alpha, phi) = self.traces(body, x.x, x.y);
        let p = PlaneJet::radial(&PRESSURE, Self::CENTRE, x.x, x.y);
        let zero = PlaneJet::quadratic([0.0; 6], x.x, x.y);
        // Frictionless: t = 0.
        family_a_in_space(self.lame, body, alpha, phi, [zero, zero], p, x.z)
    }
}

/// Family A in space (`docs/manufactured.md`, section 11): value, gradient and Hessian of the
/// three components of `u` of body `body` at height `z` from its interface data at `(x, y)`, the
/// tangential trace `alpha`, the normal trace `phi`, the shear traction `t = sigma_Tz` and the
/// pressure `p = -sigma_zz`:
///
/// ```text
/// u_T = Z2 alpha + Zs theta,   theta = t / mu - grad phi
/// u_z = Z2 phi - kappa Zs pi,  pi = p + lambda div alpha
/// ```
pub(super) fn family_a_in_space(
    lame: Lame,
    body: BodyId,
    alpha: [PlaneJet; 2],
    phi: PlaneJet,
    t: [PlaneJet; 2],
    p: PlaneJet,
    z: f64,
) -> [Evaluated; 3] {
    let (lambda, mu) = (lame.lambda(), lame.mu());
    let kappa = 1.0 / (lambda + 2.0 * mu);
    let theta = [
        t[0] * (1.0 / mu) + -phi.partial(0),
        t[1] * (1.0 / mu) + -phi.partial(1),
    ];
    let pi = p + (alpha[0].partial(0) + alpha[1].partial(1)) * lambda;
    let s = match body {
        BodyId::One => 1.0,
        BodyId::Two => -1.0,
    };
    let z2 = [1.0 - z * z, -2.0 * z, -2.0];
    let zs = [z - s * z * z, 1.0 - 2.0 * s * z, -2.0 * s];
    let terms: [[(&[f64; 3], PlaneJet); 2]; 3] = [
        [(&z2, alpha[0]), (&zs, theta[0])],
        [(&z2, alpha[1]), (&zs, theta[1])],
        [(&z2, phi), (&zs, pi * -kappa)],
    ];
    terms.map(|component| {
        let mut out = Evaluated {
            value: 0.0,
            gradient: Vector3::zeros(),
            hessian: Matrix3::zeros(),
        };
        for (z_jet, c) in &component {
            add_term(&mut out, **z_jet, c);
        }
        out
    })
}

impl StackedContact for DiscContact {
    fn name(&self) -> &'static str {
        Self::NAME
    }

    fn exact_body(&self, body: BodyId) -> Arc<dyn ExactSolution3d> {
        Arc::new(self.body(body))
    }

    fn law(&self) -> Arc<dyn ContactLaw<3>> {
        Arc::new(Frictionless)
    }

    fn imposed_gap(&self) -> Arc<dyn Fn(f64, f64) -> f64 + Send + Sync> {
        Arc::new(DiscContact::initial_gap)
    }

    fn interface_values(&self, x: f64, y: f64) -> InterfaceValues3d {
        self.interface(x, y)
    }

    fn zone_radius(&self) -> f64 {
        Self::CONTACT_RADIUS
    }

    fn exact_normal_resultant(&self) -> f64 {
        Self::normal_resultant()
    }

    fn exact_friction_resultant(&self) -> Vector2<f64> {
        Vector2::zeros()
    }
}

/// One body of [`DiscContact`] as a solution of elasticity on its box: Dirichlet data on the
/// side away from the interface, tractions on the four lateral sides, the contact side free.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DiscContactBody {
    solution: DiscContact,
    body: BodyId,
    name: &'static str,
}

impl DiscContactBody {
    /// Which body.
    pub fn id(&self) -> BodyId {
        self.body
    }
}

impl ExactSolution3d for DiscContactBody {
    fn name(&self) -> &str {
        self.name
    }

    fn lame(&self) -> Lame {
        self.solution.lame
    }

    fn displacement(&self, x: Point3) -> Vector3 {
        displacement_of(&self.solution.evaluate(self.body, x))
    }

    fn gradient(&self, x: Point3) -> Matrix3<f64> {
        gradient_of(&self.solution.evaluate(self.body, x))
    }

    fn displacement_and_gradient(&self, x: Point3) -> (Vector3, Matrix3<f64>) {
        let e = self.solution.evaluate(self.body, x);
        (displacement_of(&e), gradient_of(&e))
    }

    fn body_force(&self, x: Point3) -> Vector3 {
        body_force_of(self.solution.lame, &self.solution.evaluate(self.body, x))
    }

    fn traction_sides(&self) -> &[&'static str] {
        &["left", "right", "front", "back"]
    }

    fn contact_sides(&self) -> &[&'static str] {
        match self.body {
            BodyId::One => &["bottom"],
            BodyId::Two => &["top"],
        }
    }

    fn domain(&self) -> Cuboid {
        DiscContact::domain(self.body)
    }
}
