//! Family A: two-body solutions built from interface data (`manufactured.md`, sections 2, 4
//! and 5): the cases M1 (frictionless, contact/separation), M2 (Tresca, stick/slip), M3 (full
//! contact) and M4 (no contact).

use std::f64::consts::FRAC_1_SQRT_2;

use nalgebra::Matrix2;
use vem_contact::{ContactLaw, FrictionBound};
use vem_mesh::generators::Rectangle;
use vem_mesh::{Point, Vector};

use super::jet::{Jet, SwitchPower, SwitchSide};
use super::solution::{
    BodyId, ContactSet, ExactContact, ExactSolution, ExpectedSets, FrictionSet, Lame, Resultants,
    Side,
};

/// The contact/separation point of M1, `x_c = (sqrt(5) - 1)/2` (irrational: never a vertex of
/// a mesh with rational coordinates).
pub const CONTACT_SWITCH_POINT: f64 = 0.618_033_988_749_894_9;
/// The stick/slip point of M2, `x_s = sqrt(2)/2`.
pub const STICK_SLIP_POINT: f64 = FRAC_1_SQRT_2;
/// The friction bound `g_F = g0 = 1/4` of M2.
pub const FAMILY_A_FRICTION_BOUND: f64 = 0.25;

/// Amplitudes `p0`, `q0`, `s0` of section 1.
const P0: f64 = 1.0;
const Q0: f64 = 1.0 / 20.0;
const S0: f64 = 1.0 / 20.0;

// Polynomials of section 4, coefficients in ascending powers of x.
/// `w = (1 + x^2)/20`.
const W: [f64; 3] = [1.0 / 20.0, 0.0, 1.0 / 20.0];
/// `h0 = (2 + x + x^2)/40`, the initial gap.
const H0: [f64; 3] = [2.0 / 40.0, 1.0 / 40.0, 1.0 / 40.0];
/// `a1 = x^2/20`.
const A1: [f64; 3] = [0.0, 0.0, 1.0 / 20.0];
/// `a2 = -x/20`.
const A2: [f64; 2] = [0.0, -1.0 / 20.0];
/// `pf = p0 (1 + x/2 - x^2/2)`.
const PF: [f64; 3] = [P0, P0 / 2.0, -P0 / 2.0];
/// `q4 = (1 + x)/20`.
const Q4: [f64; 2] = [1.0 / 20.0, 1.0 / 20.0];

/// M1 pressure `p = PP(p0, -1, x_c, x_c, 4)`.
const M1_PRESSURE: SwitchPower = SwitchPower::from_valid_parts(
    P0,
    SwitchSide::Below,
    CONTACT_SWITCH_POINT,
    CONTACT_SWITCH_POINT,
    4,
);
/// M1 opening `q = PP(q0, +1, x_c, 1 - x_c, 5)`.
const M1_OPENING: SwitchPower = SwitchPower::from_valid_parts(
    Q0,
    SwitchSide::Above,
    CONTACT_SWITCH_POINT,
    1.0 - CONTACT_SWITCH_POINT,
    5,
);
/// M2 `rho = PP(1, -1, x_s, x_s, 4)` (shear `t = g_F (1 - rho)`).
const M2_RHO: SwitchPower = SwitchPower::from_valid_parts(
    1.0,
    SwitchSide::Below,
    STICK_SLIP_POINT,
    STICK_SLIP_POINT,
    4,
);
/// M2 slip `sl = PP(s0, +1, x_s, 1 - x_s, 5)`.
const M2_SLIP: SwitchPower = SwitchPower::from_valid_parts(
    S0,
    SwitchSide::Above,
    STICK_SLIP_POINT,
    1.0 - STICK_SLIP_POINT,
    5,
);

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Case {
    M1,
    M2,
    M3,
    M4,
}

/// The interface data of one body at one abscissa: tangential trace `alpha = u_x(x, 0)`,
/// vertical trace `phi = u_y(x, 0)`, shear `t = sigma_xy(x, 0)`, pressure
/// `p = -sigma_yy(x, 0)`, each with the derivatives section 2 needs.
struct Traces {
    alpha: Jet<4>,
    phi: Jet<4>,
    shear: Jet<3>,
    pressure: Jet<3>,
}

/// The derived one-dimensional functions of section 2 for one body at one abscissa.
struct Derived {
    /// Orientation `s_i` (+1 for body one, -1 for body two).
    s: f64,
    alpha: Jet<4>,
    phi: Jet<4>,
    /// `theta = t/mu - phi'`.
    theta: Jet<3>,
    /// `pi = p + lambda alpha'`.
    pi: Jet<3>,
    /// `kappa = 1/(lambda + 2 mu)`.
    kappa: f64,
}

/// A Family A two-body solution (`manufactured.md`, section 2): body one on `(0,1) x (0,1)`,
/// body two on `(0,1) x (-1,0)`, clamped at `y = 1` and `y = -1`, tractions on the lateral
/// sides, contact on `Gamma_C = (0,1) x {0}`.
///
/// ```
/// use vem_verify::exact::{ExactContact, ExactSolution, FamilyA, Lame};
/// let m1 = FamilyA::m1(Lame::default());
/// let interface = m1.contact().unwrap().interface_values(0.25);
/// assert!(interface.sigma_nu < 0.0 && interface.gap().abs() < 1e-15);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FamilyA {
    case: Case,
    lame: Lame,
}

impl FamilyA {
    /// M1: frictionless, contact on `[0, x_c)`, separation on `(x_c, 1]`.
    pub fn m1(lame: Lame) -> Self {
        Self {
            case: Case::M1,
            lame,
        }
    }

    /// M2: Tresca with `g_F = 1/4`, contact everywhere, stick on `[0, x_s)`, slip on `(x_s, 1]`.
    pub fn m2(lame: Lame) -> Self {
        Self {
            case: Case::M2,
            lame,
        }
    }

    /// M3: frictionless, contact everywhere (polynomial).
    pub fn m3(lame: Lame) -> Self {
        Self {
            case: Case::M3,
            lame,
        }
    }

    /// M4: frictionless, separated everywhere (polynomial; two independent elasticity
    /// problems with traction-free `Gamma_C`).
    pub fn m4(lame: Lame) -> Self {
        Self {
            case: Case::M4,
            lame,
        }
    }

    /// The interface data of section 5 for `body` at `x`.
    fn traces(&self, body: BodyId, x: f64) -> Traces {
        let w: Jet<4> = Jet::polynomial(&W, x);
        let h0: Jet<4> = Jet::polynomial(&H0, x);
        let (a1, a2): (Jet<4>, Jet<4>) = (Jet::polynomial(&A1, x), Jet::polynomial(&A2, x));
        let one = body == BodyId::One;
        match self.case {
            Case::M1 => Traces {
                alpha: if one { a1 } else { a2 },
                phi: if one { -w - h0 + M1_OPENING.jet(x) } else { -w },
                shear: Jet::ZERO,
                pressure: M1_PRESSURE.jet(x),
            },
            Case::M2 => {
                let half_slip = M2_SLIP.jet::<4>(x).scale(0.5);
                Traces {
                    alpha: if one { half_slip } else { -half_slip },
                    phi: if one { -w - h0 } else { -w },
                    shear: (Jet::constant(1.0) - M2_RHO.jet(x)).scale(FAMILY_A_FRICTION_BOUND),
                    pressure: Jet::polynomial(&PF, x),
                }
            }
            Case::M3 => Traces {
                alpha: if one { a1 } else { a2 },
                phi: if one { -w - h0 } else { -w },
                shear: Jet::ZERO,
                pressure: Jet::polynomial(&PF, x),
            },
            Case::M4 => Traces {
                alpha: if one { a1 } else { a2 },
                phi: if one {
                    -w - h0 + Jet::polynomial(&Q4, x)
                } else {
                    -w
                },
                shear: Jet::ZERO,
                pressure: Jet::ZERO,
            },
        }
    }

    /// `theta`, `pi` and the orientation of section 2.
    fn derived(&self, body: BodyId, x: f64) -> Derived {
        let Traces {
            alpha,
            phi,
            shear,
            pressure,
        } = self.traces(body, x);
        let (lambda, mu) = (self.lame.lambda(), self.lame.mu());
        Derived {
            s: match body {
                BodyId::One => 1.0,
                BodyId::Two => -1.0,
            },
            alpha,
            phi,
            theta: shear.scale(1.0 / mu) - phi.derivative(),
            pi: pressure + alpha.derivative().scale(lambda),
            kappa: 1.0 / (lambda + 2.0 * mu),
        }
    }
}

/// The y-profiles `Y2 = 1 - y^2`, `Ys = y (1 - s y)` and `dYs = 1 - 2 s y` of section 2.
fn profiles(s: f64, y: f64) -> (f64, f64, f64) {
    (1.0 - y * y, y * (1.0 - s * y), 1.0 - 2.0 * s * y)
}

impl ExactSolution for FamilyA {
    fn name(&self) -> &str {
        match self.case {
            Case::M1 => "M1",
            Case::M2 => "M2",
            Case::M3 => "M3",
            Case::M4 => "M4",
        }
    }

    fn lame(&self) -> Lame {
        self.lame
    }

    fn bodies(&self) -> &'static [BodyId] {
        &BodyId::BOTH
    }

    fn domain(&self, body: BodyId) -> Rectangle {
        match body {
            BodyId::One => Rectangle::unit_square(),
            BodyId::Two => Rectangle::new(Point::new(0.0, -1.0), Point::new(1.0, 0.0)),
        }
    }

    fn displacement(&self, body: BodyId, x: Point) -> Vector {
        let d = self.derived(body, x.x);
        let (y2, ys, _) = profiles(d.s, x.y);
        Vector::new(
            y2 * d.alpha[0] + ys * d.theta[0],
            y2 * d.phi[0] - d.kappa * ys * d.pi[0],
        )
    }

    fn gradient(&self, body: BodyId, x: Point) -> Matrix2<f64> {
        let d = self.derived(body, x.x);
        let y = x.y;
        let (y2, ys, dys) = profiles(d.s, y);
        Matrix2::new(
            y2 * d.alpha[1] + ys * d.theta[1],
            -2.0 * y * d.alpha[0] + dys * d.theta[0],
            y2 * d.phi[1] - d.kappa * ys * d.pi[1],
            -2.0 * y * d.phi[0] - d.kappa * dys * d.pi[0],
        )
    }

    fn body_force(&self, body: BodyId, x: Point) -> Vector {
        let d = self.derived(body, x.x);
        let y = x.y;
        let (y2, ys, dys) = profiles(d.s, y);
        let (k, s) = (d.kappa, d.s);
        // Second derivatives (section 2).
        let ux_xx = y2 * d.alpha[2] + ys * d.theta[2];
        let ux_xy = -2.0 * y * d.alpha[1] + dys * d.theta[1];
        let ux_yy = -2.0 * d.alpha[0] - 2.0 * s * d.theta[0];
        let uy_xx = y2 * d.phi[2] - k * ys * d.pi[2];
        let uy_xy = -2.0 * y * d.phi[1] - k * dys * d.pi[1];
        let uy_yy = -2.0 * d.phi[0] + 2.0 * s * k * d.pi[0];
        let (lambda, mu) = (self.lame.lambda(), self.lame.mu());
        Vector::new(
            -((lambda + 2.0 * mu) * ux_xx + mu * ux_yy + (lambda + mu) * uy_xy),
            -((lambda + 2.0 * mu) * uy_yy + mu * uy_xx + (lambda + mu) * ux_xy),
        )
    }

    fn dirichlet_sides(&self, body: BodyId) -> Vec<Side> {
        match body {
            BodyId::One => vec![Side::Top],
            BodyId::Two => vec![Side::Bottom],
        }
    }

    fn neumann_sides(&self, _body: BodyId) -> Vec<Side> {
        vec![Side::Left, Side::Right]
    }

    fn contact(&self) -> Option<&dyn ExactContact> {
        Some(self)
    }
}

impl ExactContact for FamilyA {
    fn law(&self) -> ContactLaw {
        match self.case {
            Case::M2 => ContactLaw::Tresca {
                friction_bound: FrictionBound::Constant(FAMILY_A_FRICTION_BOUND),
            },
            Case::M1 | Case::M3 | Case::M4 => ContactLaw::Frictionless,
        }
    }

    fn initial_gap(&self, x: f64) -> f64 {
        Jet::<1>::polynomial(&H0, x).value()
    }

    /// The margins of `manufactured.md`, section 8 (they held in the prototype for n = 32, 64
    /// on uniform and perturbed meshes).
    fn expected_sets(&self) -> Option<ExpectedSets> {
        Some(match self.case {
            Case::M1 => ExpectedSets {
                contact: ContactSet::Split {
                    switch_point: CONTACT_SWITCH_POINT,
                    active_up_to: CONTACT_SWITCH_POINT - 0.2,
                    inactive_from: CONTACT_SWITCH_POINT + 0.2,
                },
                friction: None,
            },
            Case::M2 => ExpectedSets {
                contact: ContactSet::AllActive,
                friction: Some(FrictionSet::Split {
                    switch_point: STICK_SLIP_POINT,
                    stick_up_to: STICK_SLIP_POINT - 0.35,
                    slip_from: STICK_SLIP_POINT + 0.2,
                }),
            },
            Case::M3 => ExpectedSets {
                contact: ContactSet::AllActive,
                friction: None,
            },
            Case::M4 => ExpectedSets {
                contact: ContactSet::NoneActive,
                friction: None,
            },
        })
    }

    /// Section 5: M1 `-p0 x_c/5`; M2 `-13 p0/12` and `-g_F (1 - x_s/5)`; M3 `-13 p0/12`;
    /// M4 zero.
    fn reference_resultants(&self) -> Option<Resultants> {
        let (normal, tangential) = match self.case {
            Case::M1 => (-P0 * CONTACT_SWITCH_POINT / 5.0, 0.0),
            Case::M2 => (
                -13.0 * P0 / 12.0,
                -FAMILY_A_FRICTION_BOUND * (1.0 - STICK_SLIP_POINT / 5.0),
            ),
            Case::M3 => (-13.0 * P0 / 12.0, 0.0),
            Case::M4 => (0.0, 0.0),
        };
        Some(Resultants { normal, tangential })
    }
}
