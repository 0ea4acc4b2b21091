//! Family A: two-body solutions built from interface data (`docs/manufactured.md`, sections 2, 4
//! and 5): the cases M1 (frictionless, contact/separation), M2 (Tresca, stick/slip), M3 (full
//! contact) and M4 (no contact), and [`InterfaceData`], the same construction from data of
//! your own.

use std::f64::consts::FRAC_1_SQRT_2;
use std::sync::Arc;

use nalgebra::Matrix2;
use vem_contact::{ContactLaw, Frictionless, Tresca};
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

/// The interface data of one body of a Family A solution at one abscissa (`docs/manufactured.md`,
/// section 2): tangential trace `alpha = u_x(x, 0)`, vertical trace `phi = u_y(x, 0)`, shear
/// `t = sigma_xy(x, 0)`, pressure `p = -sigma_yy(x, 0)`, each with the derivatives the
/// construction needs (build them with [`Jet::polynomial`], [`SwitchPower::jet`], sums and
/// products).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Traces {
    /// `alpha = u_x(x, 0)` and three derivatives.
    pub alpha: Jet<4>,
    /// `phi = u_y(x, 0)` and three derivatives.
    pub phi: Jet<4>,
    /// `t = sigma_xy(x, 0)` and two derivatives.
    pub shear: Jet<3>,
    /// `p = -sigma_yy(x, 0)` and two derivatives.
    pub pressure: Jet<3>,
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

/// A Family A two-body solution (`docs/manufactured.md`, section 2): body one on `(0,1) x (0,1)`,
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

    fn derived(&self, body: BodyId, x: f64) -> Derived {
        derived(self.traces(body, x), body, self.lame)
    }
}

/// `theta`, `pi` and the orientation of section 2 from the traces of `body`.
fn derived(traces: Traces, body: BodyId, lame: Lame) -> Derived {
    let Traces {
        alpha,
        phi,
        shear,
        pressure,
    } = traces;
    let (lambda, mu) = (lame.lambda(), lame.mu());
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
        family_a_domain(body)
    }

    fn displacement(&self, body: BodyId, x: Point) -> Vector {
        displacement(&self.derived(body, x.x), x)
    }

    fn gradient(&self, body: BodyId, x: Point) -> Matrix2<f64> {
        gradient(&self.derived(body, x.x), x)
    }

    fn body_force(&self, body: BodyId, x: Point) -> Vector {
        body_force(&self.derived(body, x.x), self.lame, x)
    }

    fn dirichlet_sides(&self, body: BodyId) -> Vec<Side> {
        family_a_dirichlet_sides(body)
    }

    fn neumann_sides(&self, _body: BodyId) -> Vec<Side> {
        vec![Side::Left, Side::Right]
    }

    fn contact(&self) -> Option<&dyn ExactContact> {
        Some(self)
    }
}

/// Body one clamped at `y = 1`, body two at `y = -1`.
fn family_a_dirichlet_sides(body: BodyId) -> Vec<Side> {
    match body {
        BodyId::One => vec![Side::Top],
        BodyId::Two => vec![Side::Bottom],
    }
}

/// Body one on `(0,1) x (0,1)`, body two on `(0,1) x (-1,0)`.
fn family_a_domain(body: BodyId) -> Rectangle {
    match body {
        BodyId::One => Rectangle::unit_square(),
        BodyId::Two => Rectangle::new(Point::new(0.0, -1.0), Point::new(1.0, 0.0)),
    }
}

/// The displacement of section 2.
fn displacement(d: &Derived, x: Point) -> Vector {
    let (y2, ys, _) = profiles(d.s, x.y);
    Vector::new(
        y2 * d.alpha[0] + ys * d.theta[0],
        y2 * d.phi[0] - d.kappa * ys * d.pi[0],
    )
}

/// The displacement gradient of section 2.
fn gradient(d: &Derived, x: Point) -> Matrix2<f64> {
    let y = x.y;
    let (y2, ys, dys) = profiles(d.s, y);
    Matrix2::new(
        y2 * d.alpha[1] + ys * d.theta[1],
        -2.0 * y * d.alpha[0] + dys * d.theta[0],
        y2 * d.phi[1] - d.kappa * ys * d.pi[1],
        -2.0 * y * d.phi[0] - d.kappa * dys * d.pi[0],
    )
}

/// The body force of section 2.
fn body_force(d: &Derived, lame: Lame, x: Point) -> Vector {
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
    let (lambda, mu) = (lame.lambda(), lame.mu());
    Vector::new(
        -((lambda + 2.0 * mu) * ux_xx + mu * ux_yy + (lambda + mu) * uy_xy),
        -((lambda + 2.0 * mu) * uy_yy + mu * uy_xx + (lambda + mu) * ux_xy),
    )
}

impl ExactContact for FamilyA {
    fn law(&self) -> Arc<dyn ContactLaw> {
        match self.case {
            Case::M2 => {
                Arc::new(Tresca::try_new(FAMILY_A_FRICTION_BOUND).expect("the bound is positive"))
            }
            Case::M1 | Case::M3 | Case::M4 => Arc::new(Frictionless),
        }
    }

    fn initial_gap(&self, x: f64) -> f64 {
        Jet::<1>::polynomial(&H0, x).value()
    }

    /// The margins of `docs/manufactured.md`, section 8 (they held in the prototype for n = 32, 64
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

/// The interface data of a Family A solution: the [`Traces`] of `body` at abscissa `x`.
pub type TraceData = dyn Fn(BodyId, f64) -> Traces + Send + Sync;

/// A Family A two-body solution built from interface data of your own (`docs/manufactured.md`,
/// section 2): the same domains, boundary sides and construction as [`FamilyA`] (body one on
/// `(0,1) x (0,1)`, body two on `(0,1) x (-1,0)`, clamped at `y = 1` and `y = -1`, tractions on
/// the lateral sides), with the traces, law and initial gap you give.
///
/// The data must satisfy the law on `Gamma_C` (section 3): the built-in cases show how
/// (contact where the pressure is positive, `phi_1 = -w - h0` there; for friction
/// `|t| <= g_F`, with equality where the tangential traces differ).
///
/// ```
/// use std::sync::Arc;
/// use vem_contact::Frictionless;
/// use vem_verify::exact::{
///     BodyId, ExactContact, ExactSolution, FamilyA, InterfaceData, Jet, Lame, Traces,
/// };
/// use vem_mesh::Point;
/// // M3 retyped from its data (section 5): w = (1 + x^2)/20, h0 = (2 + x + x^2)/40,
/// // a1 = x^2/20, a2 = -x/20, no shear, pressure 1 + x/2 - x^2/2.
/// let data = |body: BodyId, x: f64| {
///     let w: Jet<4> = Jet::polynomial(&[0.05, 0.0, 0.05], x);
///     let h0: Jet<4> = Jet::polynomial(&[0.05, 0.025, 0.025], x);
///     let one = body == BodyId::One;
///     Traces {
///         alpha: if one { Jet::polynomial(&[0.0, 0.0, 0.05], x) }
///                else { Jet::polynomial(&[0.0, -0.05], x) },
///         phi: if one { -w - h0 } else { -w },
///         shear: Jet::ZERO,
///         pressure: Jet::polynomial(&[1.0, 0.5, -0.5], x),
///     }
/// };
/// let mine = InterfaceData::new("my M3", Lame::default(), Frictionless,
///     |x| (2.0 + x + x * x) / 40.0, data);
/// let m3 = FamilyA::m3(Lame::default());
/// let p = Point::new(0.3, -0.6);
/// assert!((mine.displacement(BodyId::Two, p) - m3.displacement(BodyId::Two, p)).norm() < 1e-15);
/// assert!((mine.body_force(BodyId::Two, p) - m3.body_force(BodyId::Two, p)).norm() < 1e-13);
/// assert_eq!(mine.contact().unwrap().interface_values(0.4), m3.interface_values(0.4));
/// ```
#[derive(Clone)]
pub struct InterfaceData {
    name: String,
    lame: Lame,
    law: Arc<dyn ContactLaw>,
    initial_gap: Arc<dyn Fn(f64) -> f64 + Send + Sync>,
    traces: Arc<TraceData>,
    expected_sets: Option<ExpectedSets>,
    reference_resultants: Option<Resultants>,
}

impl std::fmt::Debug for InterfaceData {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("InterfaceData")
            .field("name", &self.name)
            .field("lame", &self.lame)
            .field("law", &self.law.describe())
            .field("expected_sets", &self.expected_sets)
            .field("reference_resultants", &self.reference_resultants)
            .finish()
    }
}

impl InterfaceData {
    /// The solution `name` of material `lame` with contact law `law`, initial gap
    /// `initial_gap(x)` and interface data `traces(body, x)`; no expected sets and resultants
    /// by quadrature until given.
    pub fn new(
        name: impl Into<String>,
        lame: Lame,
        law: impl ContactLaw + 'static,
        initial_gap: impl Fn(f64) -> f64 + Send + Sync + 'static,
        traces: impl Fn(BodyId, f64) -> Traces + Send + Sync + 'static,
    ) -> Self {
        Self {
            name: name.into(),
            lame,
            law: Arc::new(law),
            initial_gap: Arc::new(initial_gap),
            traces: Arc::new(traces),
            expected_sets: None,
            reference_resultants: None,
        }
    }

    /// The statuses a discrete solution must reproduce (see [`ExactContact::expected_sets`]).
    pub fn expected_sets(mut self, sets: ExpectedSets) -> Self {
        self.expected_sets = Some(sets);
        self
    }

    /// The resultants in closed form (see [`ExactContact::reference_resultants`]).
    pub fn reference_resultants(mut self, resultants: Resultants) -> Self {
        self.reference_resultants = Some(resultants);
        self
    }

    fn derived(&self, body: BodyId, x: f64) -> Derived {
        derived((self.traces)(body, x), body, self.lame)
    }
}

impl ExactSolution for InterfaceData {
    fn name(&self) -> &str {
        &self.name
    }

    fn lame(&self) -> Lame {
        self.lame
    }

    fn bodies(&self) -> &'static [BodyId] {
        &BodyId::BOTH
    }

    fn domain(&self, body: BodyId) -> Rectangle {
        family_a_domain(body)
    }

    fn displacement(&self, body: BodyId, x: Point) -> Vector {
        displacement(&self.derived(body, x.x), x)
    }

    fn gradient(&self, body: BodyId, x: Point) -> Matrix2<f64> {
        gradient(&self.derived(body, x.x), x)
    }

    fn body_force(&self, body: BodyId, x: Point) -> Vector {
        body_force(&self.derived(body, x.x), self.lame, x)
    }

    fn dirichlet_sides(&self, body: BodyId) -> Vec<Side> {
        family_a_dirichlet_sides(body)
    }

    fn neumann_sides(&self, _body: BodyId) -> Vec<Side> {
        vec![Side::Left, Side::Right]
    }

    fn contact(&self) -> Option<&dyn ExactContact> {
        Some(self)
    }
}

impl ExactContact for InterfaceData {
    fn law(&self) -> Arc<dyn ContactLaw> {
        Arc::clone(&self.law)
    }

    fn initial_gap(&self, x: f64) -> f64 {
        (self.initial_gap)(x)
    }

    fn expected_sets(&self) -> Option<ExpectedSets> {
        self.expected_sets
    }

    fn reference_resultants(&self) -> Option<Resultants> {
        self.reference_resultants
    }
}
