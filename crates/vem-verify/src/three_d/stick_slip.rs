//! "M2-3D": Tresca friction between two stacked boxes in full contact, sticking inside a
//! disc and slipping outside it (`docs/manufactured.md`, section 11, "M2-3D"): the analogue in
//! space of M2, built like M1-3D from the interface data (Family A in space), with a friction
//! bound `g_F(x, y)` that varies over the interface and a slip whose direction turns with it.

use std::sync::Arc;

use nalgebra::{Matrix3, Vector2};
use vem_contact::{ContactLaw, Tresca};
use vem_mesh::generators::polyhedral::Cuboid;
use vem_mesh::{Point3, Vector3};

use super::disc_contact::{family_a_in_space, PlaneJet};
use super::exact::{body_force_of, displacement_of, gradient_of, Evaluated, ExactSolution3d};
use super::{DiscContact, InterfaceValues3d, StackedContact};
use crate::exact::{BodyId, Lame, SwitchPower, SwitchSide};

/// `r_s^2 = (sqrt 2 - 1)/2`.
const STICK_RADIUS_SQUARED: f64 = 0.207_106_781_186_547_52;

/// `rho = ((S - s)_+ / S)^4` of `s = r^2`: one at the centre, zero from the circle on.
const STICK_SWITCH: SwitchPower = SwitchPower::from_valid_parts(
    1.0,
    SwitchSide::Below,
    STICK_RADIUS_SQUARED,
    STICK_RADIUS_SQUARED,
    4,
);

/// `sl = s0 ((s - S)_+ / (1/2 - S))^3` (`sl = s0` at the corners, `s = 1/2`).
const SLIP_SWITCH: SwitchPower = SwitchPower::from_valid_parts(
    StickSlipContact::PEAK_SLIP,
    SwitchSide::Above,
    STICK_RADIUS_SQUARED,
    0.5 - STICK_RADIUS_SQUARED,
    3,
);

/// "M2-3D": Tresca friction between the upper box `Omega_1 = (0, 1)^3` and the lower box
/// `Omega_2 = (0, 1)^2 x (-1, 0)` across `z = 0` (`docs/manufactured.md`, section 11), in contact
/// everywhere, sticking inside the disc `r = |(x, y) - c| < r_s` and slipping outside it:
///
/// ```text
/// s = r^2,  S = r_s^2 = (sqrt 2 - 1)/2,  c = (1/2, 1/2)
/// m = g0 (1 + x/2, y - 1/2)                 (g0 = 1/4; never zero on the square)
/// g_F = |m|                                 the friction bound (imposed)
/// rho = ((S - s)_+ / S)^4,   sl = s0 ((s - S)_+ / (1/2 - S))^3     (s0 = 1/20)
/// t = (1 - rho) m                           shear traction sigma_Tz, sigma_1tau = -t
/// alpha_1 = sl m / (2 g0),  alpha_2 = -alpha_1     slip [u]_1tau = sl m / g0
/// p = p0 (1 + (x + y)/2 - (x^2 + y^2)/2)    pressure (p0 = 1; 1 <= p <= 5/4)
/// phi_1 = -w - h0,  phi_2 = -w              (w, h0 those of M1-3D: [u]_nu = h0)
/// ```
///
/// In the stick disc `|sigma_1tau| = (1 - rho) g_F < g_F` and the slip vanishes; outside,
/// `|sigma_1tau| = g_F` and the slip `[u]_1tau = (sl / g0) t = -(sl / g0) sigma_1tau` opposes
/// the friction traction, as Tresca's law asks. The bodies are [`StickSlipContact::body`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StickSlipContact {
    lame: Lame,
}

impl StickSlipContact {
    /// The case's name.
    pub const NAME: &'static str = "M2-3D";
    /// The centre `c` of the stick disc.
    pub const CENTRE: [f64; 2] = [0.5, 0.5];
    /// The radius `r_s = sqrt((sqrt 2 - 1)/2)` of the stick disc; `r_s^2` is irrational, so no
    /// point with rational coordinates lies on the circle.
    pub const STICK_RADIUS: f64 = 0.455_089_860_562_227_34;
    /// The scale `g0` of the friction bound.
    pub const BOUND_SCALE: f64 = 0.25;
    /// The pressure scale `p0`.
    pub const PEAK_PRESSURE: f64 = 1.0;
    /// The amplitude `s0` of the slip function (`sl = s0` at the corners).
    pub const PEAK_SLIP: f64 = 0.05;

    /// The solution for the material `lame`.
    pub fn new(lame: Lame) -> Self {
        Self { lame }
    }

    /// The material.
    pub fn lame(&self) -> Lame {
        self.lame
    }

    /// The body `body` as a solution of elasticity on its box (its contact side free).
    pub fn body(&self, body: BodyId) -> StickSlipBody {
        StickSlipBody {
            solution: *self,
            body,
            name: match body {
                BodyId::One => "M2-3D body 1",
                BodyId::Two => "M2-3D body 2",
            },
        }
    }

    /// The distance `r = |(x, y) - c|` to the centre of the stick disc.
    pub fn radius(x: f64, y: f64) -> f64 {
        (x - Self::CENTRE[0]).hypot(y - Self::CENTRE[1])
    }

    /// The field `m = g0 (1 + x/2, y - 1/2)`: the shear traction in the slip zone.
    pub fn bound_direction(x: f64, y: f64) -> Vector2<f64> {
        Vector2::new(1.0 + 0.5 * x, y - 0.5) * Self::BOUND_SCALE
    }

    /// The friction bound `g_F = |m| >= g0`.
    pub fn friction_bound(x: f64, y: f64) -> f64 {
        Self::bound_direction(x, y).norm()
    }

    /// The contact pressure `p = -sigma_nu`.
    pub fn pressure(x: f64, y: f64) -> f64 {
        Self::PEAK_PRESSURE * (1.0 + 0.5 * (x + y) - 0.5 * (x * x + y * y))
    }

    /// The resultant of the pressure, `int p dA = 7 p0 / 6`.
    pub fn normal_resultant() -> f64 {
        7.0 * Self::PEAK_PRESSURE / 6.0
    }

    /// The resultant of the friction traction on body one, `int sigma_1tau dA = -int t dA =
    /// -m(c) (1 - pi r_s^2 / 5)` (`m` is linear and `rho` radial in a disc inside the square,
    /// `int rho dA = pi S / 5`).
    pub fn friction_resultant() -> Vector2<f64> {
        -Self::bound_direction(Self::CENTRE[0], Self::CENTRE[1])
            * (1.0 - std::f64::consts::PI * STICK_RADIUS_SQUARED / 5.0)
    }

    /// The values on the interface at `(x, y)`, from the traces (not from the fields: the
    /// tests compare the two).
    pub fn interface(&self, x: f64, y: f64) -> InterfaceValues3d {
        let (alpha_1, phi_1) = self.traces(BodyId::One, x, y);
        let (alpha_2, phi_2) = self.traces(BodyId::Two, x, y);
        let t = Self::shear(x, y);
        InterfaceValues3d {
            sigma_nu: -Self::pressure(x, y),
            sigma_1tau: -Vector2::new(t[0].value, t[1].value),
            normal_jump: phi_2.value - phi_1.value,
            tangential_jump: Vector2::new(
                alpha_1[0].value - alpha_2[0].value,
                alpha_1[1].value - alpha_2[1].value,
            ),
            initial_gap: DiscContact::initial_gap(x, y),
        }
    }

    /// The components of `m` as jets.
    fn direction(x: f64, y: f64) -> [PlaneJet; 2] {
        let g0 = Self::BOUND_SCALE;
        [
            PlaneJet::quadratic([g0, 0.5 * g0, 0.0, 0.0, 0.0, 0.0], x, y),
            PlaneJet::quadratic([-0.5 * g0, 0.0, g0, 0.0, 0.0, 0.0], x, y),
        ]
    }

    /// The shear traction `t = (1 - rho) m`.
    fn shear(x: f64, y: f64) -> [PlaneJet; 2] {
        let one = PlaneJet::quadratic([1.0, 0.0, 0.0, 0.0, 0.0, 0.0], x, y);
        let rho = PlaneJet::radial(&STICK_SWITCH, Self::CENTRE, x, y);
        let stick = one + -rho;
        Self::direction(x, y).map(|m| stick.product(&m))
    }

    /// The tangential trace `alpha` and the normal trace `phi` of body `body`.
    fn traces(&self, body: BodyId, x: f64, y: f64) -> ([PlaneJet; 2], PlaneJet) {
        let quadratic = |c| PlaneJet::quadratic(c, x, y);
        let w = quadratic([1.0, 0.0, 0.0, 1.0, 0.0, 1.0]) * (1.0 / 20.0);
        let half_slip = PlaneJet::radial(&SLIP_SWITCH, Self::CENTRE, x, y)
            * (0.5 / Self::BOUND_SCALE)
            * match body {
                BodyId::One => 1.0,
                BodyId::Two => -1.0,
            };
        let alpha = Self::direction(x, y).map(|m| half_slip.product(&m));
        match body {
            BodyId::One => {
                let h0 = quadratic([2.0, 1.0, 1.0, 1.0, 0.0, 1.0]) * (1.0 / 40.0);
                (alpha, -w + -h0)
            }
            BodyId::Two => (alpha, -w),
        }
    }

    /// Value, gradient and Hessian of the three components of `u_body` at `x`.
    fn evaluate(&self, body: BodyId, x: Point3) -> [Evaluated; 3] {
        let (alpha, phi) = self.traces(body, x.x, x.y);
        let p =
            PlaneJet::quadratic([1.0, 0.5, 0.5, -0.5, 0.0, -0.5], x.x, x.y) * Self::PEAK_PRESSURE;
        family_a_in_space(self.lame, body, alpha, phi, Self::shear(x.x, x.y), p, x.z)
    }
}

impl StackedContact for StickSlipContact {
    fn name(&self) -> &'static str {
        Self::NAME
    }

    fn exact_body(&self, body: BodyId) -> Arc<dyn ExactSolution3d> {
        Arc::new(self.body(body))
    }

    fn law(&self) -> Arc<dyn ContactLaw<3>> {
        Arc::new(Tresca::<3>::with_field(|x| {
            StickSlipContact::friction_bound(x.x, x.y)
        }))
    }

    fn imposed_gap(&self) -> Arc<dyn Fn(f64, f64) -> f64 + Send + Sync> {
        Arc::new(DiscContact::initial_gap)
    }

    fn interface_values(&self, x: f64, y: f64) -> InterfaceValues3d {
        self.interface(x, y)
    }

    fn zone_radius(&self) -> f64 {
        Self::STICK_RADIUS
    }

    fn exact_normal_resultant(&self) -> f64 {
        Self::normal_resultant()
    }

    fn exact_friction_resultant(&self) -> Vector2<f64> {
        Self::friction_resultant()
    }
}

/// One body of [`StickSlipContact`] as a solution of elasticity on its box: Dirichlet data on
/// the side away from the interface, tractions on the four lateral sides, the contact side
/// free.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StickSlipBody {
    solution: StickSlipContact,
    body: BodyId,
    name: &'static str,
}

impl StickSlipBody {
    /// Which body.
    pub fn id(&self) -> BodyId {
        self.body
    }
}

impl ExactSolution3d for StickSlipBody {
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
