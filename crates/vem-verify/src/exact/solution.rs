//! The exact-solution traits and the small types they speak in.

use nalgebra::Matrix2;
use vem_contact::ContactLaw;
use vem_mesh::generators::Rectangle;
use vem_mesh::{Point, Vector};

use super::ExactError;

/// One of the (at most two) bodies of a problem. Body one is the upper body `Omega_1`, body
/// two the lower body `Omega_2` (`docs/manufactured.md`, section 1).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum BodyId {
    /// The first (upper) body.
    One,
    /// The second (lower) body.
    Two,
}

impl BodyId {
    /// The bodies of a one-body problem.
    pub const SINGLE: [BodyId; 1] = [BodyId::One];
    /// The bodies of a two-body problem.
    pub const BOTH: [BodyId; 2] = [BodyId::One, BodyId::Two];

    /// Zero-based index (0 for body one, 1 for body two).
    pub fn index(self) -> usize {
        match self {
            BodyId::One => 0,
            BodyId::Two => 1,
        }
    }

    /// The body of zero-based index `index`.
    ///
    /// # Errors
    /// [`ExactError::UnknownBody`] unless `index` is 0 or 1.
    pub fn from_index(index: usize) -> Result<Self, ExactError> {
        match index {
            0 => Ok(BodyId::One),
            1 => Ok(BodyId::Two),
            _ => Err(ExactError::UnknownBody { index }),
        }
    }
}

/// A side of a rectangular domain; its [`name`](Side::name) is the boundary part name the mesh
/// generators of `vem_mesh::generators` give it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Side {
    /// `x = x_min`, outward normal `(-1, 0)`.
    Left,
    /// `x = x_max`, outward normal `(1, 0)`.
    Right,
    /// `y = y_min`, outward normal `(0, -1)`.
    Bottom,
    /// `y = y_max`, outward normal `(0, 1)`.
    Top,
}

impl Side {
    /// The four sides.
    pub const ALL: [Side; 4] = [Side::Left, Side::Right, Side::Bottom, Side::Top];

    /// The boundary part name: "left", "right", "bottom" or "top".
    pub fn name(self) -> &'static str {
        match self {
            Side::Left => "left",
            Side::Right => "right",
            Side::Bottom => "bottom",
            Side::Top => "top",
        }
    }

    /// The side called `name` ("left", "right", "bottom", "top").
    ///
    /// # Errors
    /// [`ExactError::UnknownSide`] for any other name.
    pub fn from_name(name: &str) -> Result<Self, ExactError> {
        Side::ALL
            .into_iter()
            .find(|side| side.name() == name)
            .ok_or_else(|| ExactError::UnknownSide {
                name: name.to_owned(),
            })
    }

    /// The unit outward normal of the side.
    pub fn outward_normal(self) -> Vector {
        match self {
            Side::Left => Vector::new(-1.0, 0.0),
            Side::Right => Vector::new(1.0, 0.0),
            Side::Bottom => Vector::new(0.0, -1.0),
            Side::Top => Vector::new(0.0, 1.0),
        }
    }

    /// The end points of the side of `rect`, in counter-clockwise order of the rectangle.
    pub fn end_points(self, rect: &Rectangle) -> [Point; 2] {
        let (a, b) = (rect.min, rect.max);
        match self {
            Side::Left => [Point::new(a.x, b.y), Point::new(a.x, a.y)],
            Side::Right => [Point::new(b.x, a.y), Point::new(b.x, b.y)],
            Side::Bottom => [Point::new(a.x, a.y), Point::new(b.x, a.y)],
            Side::Top => [Point::new(b.x, b.y), Point::new(a.x, b.y)],
        }
    }
}

/// The sides that form the contact interface `Gamma_C`: the bottom side of body one, which
/// coincides with the top side of body two (`docs/manufactured.md`, section 1; outward normals
/// `nu_1 = (0, -1)`, `nu_2 = (0, 1)`).
pub const CONTACT_SIDES: [(BodyId, Side); 2] =
    [(BodyId::One, Side::Bottom), (BodyId::Two, Side::Top)];

/// Validated Lamé parameters of an isotropic plane-strain material,
/// `sigma = lambda tr(eps) I + 2 mu eps`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lame {
    lambda: f64,
    mu: f64,
}

impl Lame {
    /// The reference material of `docs/manufactured.md`, section 10: `lambda = 2`, `mu = 1`
    /// (`lambda != mu`, so that a swapped-constant bug shows).
    pub const REFERENCE: Lame = Lame {
        lambda: 2.0,
        mu: 1.0,
    };

    /// Lamé parameters `lambda`, `mu`.
    ///
    /// # Errors
    /// [`ExactError::InvalidLame`] unless both are finite, `mu > 0` and `lambda + mu > 0`
    /// (the plane-strain energy is then coercive on fields clamped on part of the boundary).
    pub fn try_new(lambda: f64, mu: f64) -> Result<Self, ExactError> {
        let reason = if !(lambda.is_finite() && mu.is_finite()) {
            Some("both parameters must be finite")
        } else if mu <= 0.0 {
            Some("the shear modulus mu must be positive")
        } else if lambda + mu <= 0.0 {
            Some("lambda + mu must be positive (plane-strain coercivity)")
        } else {
            None
        };
        match reason {
            Some(reason) => Err(ExactError::InvalidLame { lambda, mu, reason }),
            None => Ok(Self { lambda, mu }),
        }
    }

    /// The first Lamé parameter `lambda`.
    pub fn lambda(&self) -> f64 {
        self.lambda
    }

    /// The shear modulus `mu`.
    pub fn mu(&self) -> f64 {
        self.mu
    }

    /// The stress `sigma = lambda tr(eps) I + 2 mu eps` of the displacement gradient
    /// `gradient` (`(i, j) = d_j u_i`), with `eps = (gradient + gradient^T) / 2`.
    pub fn stress(&self, gradient: &Matrix2<f64>) -> Matrix2<f64> {
        let strain = (gradient + gradient.transpose()) * 0.5;
        Matrix2::identity() * (self.lambda * strain.trace()) + strain * (2.0 * self.mu)
    }
}

impl Default for Lame {
    /// [`Lame::REFERENCE`].
    fn default() -> Self {
        Self::REFERENCE
    }
}

/// Exact values on `Gamma_C` at one abscissa, in the conventions of `docs/manufactured.md`,
/// section 1 (scalar tangential components on `tau = e_x`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InterfaceValues {
    /// `sigma_nu = (sigma_1 nu_1) . nu_1` (compression is negative).
    pub sigma_nu: f64,
    /// `sigma_1tau = (sigma_1 nu_1) . e_x`.
    pub sigma_1tau: f64,
    /// `[u]_nu = u_1 . nu_1 + u_2 . nu_2`.
    pub normal_jump: f64,
    /// `[u]_1tau = (u_1 - u_2) . e_x`.
    pub tangential_jump: f64,
    /// The initial gap `h0`.
    pub initial_gap: f64,
}

impl InterfaceValues {
    /// The remaining gap `h0 - [u]_nu` (non-negative for an admissible field, zero where the
    /// bodies touch).
    pub fn gap(&self) -> f64 {
        self.initial_gap - self.normal_jump
    }
}

/// Resultants over `Gamma_C` (the sums of nodal contact and friction forces converge to them).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Resultants {
    /// `int_Gamma_C sigma_nu ds`.
    pub normal: f64,
    /// `int_Gamma_C sigma_1tau ds`.
    pub tangential: f64,
}

/// Which interface nodes a discrete solution must find in contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ContactSet {
    /// Every interface node is in contact (with a margin in pressure).
    AllActive,
    /// No interface node is in contact (with a margin in gap).
    NoneActive,
    /// Contact for `x < switch_point`, separation beyond. Nodes with `x <= active_up_to` must
    /// be active and nodes with `x >= inactive_from` inactive; in between the exact margins are
    /// below the discretisation error and either status is acceptable.
    Split {
        /// The exact switch point.
        switch_point: f64,
        /// Nodes at or left of this abscissa must be active.
        active_up_to: f64,
        /// Nodes at or right of this abscissa must be inactive.
        inactive_from: f64,
    },
}

impl ContactSet {
    /// The status a node at abscissa `x` must have: `Some(true)` active, `Some(false)`
    /// inactive, `None` either.
    pub fn expects_active(&self, x: f64) -> Option<bool> {
        match *self {
            ContactSet::AllActive => Some(true),
            ContactSet::NoneActive => Some(false),
            ContactSet::Split {
                active_up_to,
                inactive_from,
                ..
            } => {
                if x <= active_up_to {
                    Some(true)
                } else if x >= inactive_from {
                    Some(false)
                } else {
                    None
                }
            }
        }
    }
}

/// Which interface nodes a discrete Tresca solution must find sticking or slipping.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FrictionSet {
    /// Every interface node sticks (`|sigma_1tau| < g_F` with a margin).
    AllStick,
    /// Every interface node slips (`|sigma_1tau| = g_F`, non-zero slip).
    AllSlip,
    /// Stick for `x < switch_point`, slip beyond. Nodes with `x <= stick_up_to` must stick,
    /// nodes with `x >= slip_from` must slip; in between either status is acceptable.
    Split {
        /// The exact switch point.
        switch_point: f64,
        /// Nodes at or left of this abscissa must stick.
        stick_up_to: f64,
        /// Nodes at or right of this abscissa must slip.
        slip_from: f64,
    },
}

impl FrictionSet {
    /// The status a node at abscissa `x` must have: `Some(true)` slip, `Some(false)` stick,
    /// `None` either.
    pub fn expects_slip(&self, x: f64) -> Option<bool> {
        match *self {
            FrictionSet::AllStick => Some(false),
            FrictionSet::AllSlip => Some(true),
            FrictionSet::Split {
                stick_up_to,
                slip_from,
                ..
            } => {
                if x <= stick_up_to {
                    Some(false)
                } else if x >= slip_from {
                    Some(true)
                } else {
                    None
                }
            }
        }
    }
}

/// The contact and (for Tresca) friction statuses expected of a discrete solution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExpectedSets {
    /// Normal status.
    pub contact: ContactSet,
    /// Tangential status (`None` for frictionless contact).
    pub friction: Option<FrictionSet>,
}

/// An exact solution of a linear-elasticity problem on one rectangle, or of two bodies on
/// stacked rectangles (then possibly in contact: see [`ExactContact`]).
///
/// The fields are smooth extensions defined on the whole plane; they are meaningful on the
/// closed domain of each body. Data of the boundary value problem:
/// `-div sigma = body_force` in the body, `u = displacement` on the
/// [`dirichlet_sides`](ExactSolution::dirichlet_sides) and `sigma nu = traction` on the
/// [`neumann_sides`](ExactSolution::neumann_sides); the remaining sides of a two-body problem
/// form the contact interface ([`CONTACT_SIDES`]).
///
/// Methods taking a `body` expect one of [`bodies`](ExactSolution::bodies); the built-in
/// solutions panic, naming the case, on any other body (a programming error, like an
/// out-of-range index). Use [`BodyId::from_index`] to convert external input.
///
/// Implement it for a solution of your own (see `examples/custom_solution.rs`): the required
/// methods are the name, the material, the bodies with their domains and boundary sides, the
/// displacement, its gradient and the body force; stress and tractions follow by default.
pub trait ExactSolution: Send + Sync {
    /// Short name, e.g. "M1".
    fn name(&self) -> &str;

    /// The (plane-strain) Lamé parameters.
    fn lame(&self) -> Lame;

    /// The bodies: [`BodyId::SINGLE`] or [`BodyId::BOTH`].
    fn bodies(&self) -> &'static [BodyId];

    /// The rectangle occupied by `body`.
    fn domain(&self, body: BodyId) -> Rectangle;

    /// The displacement `u` of `body` at `x`.
    fn displacement(&self, body: BodyId, x: Point) -> Vector;

    /// The displacement gradient, `(i, j) = d_j u_i`.
    fn gradient(&self, body: BodyId, x: Point) -> Matrix2<f64>;

    /// The stress `sigma = lambda tr(eps) I + 2 mu eps`; by default from
    /// [`gradient`](ExactSolution::gradient) and [`lame`](ExactSolution::lame).
    fn stress(&self, body: BodyId, x: Point) -> Matrix2<f64> {
        self.lame().stress(&self.gradient(body, x))
    }

    /// The body force `f = -div sigma`.
    fn body_force(&self, body: BodyId, x: Point) -> Vector;

    /// The sides where `u` is prescribed (the data is [`displacement`](ExactSolution::displacement)).
    fn dirichlet_sides(&self, body: BodyId) -> Vec<Side>;

    /// The sides where the traction is prescribed (the data is
    /// [`traction`](ExactSolution::traction)).
    fn neumann_sides(&self, body: BodyId) -> Vec<Side>;

    /// The traction `sigma nu` on `side` at `x` (`nu` its outward normal); by default from
    /// [`stress`](ExactSolution::stress).
    fn traction(&self, body: BodyId, side: Side, x: Point) -> Vector {
        self.stress(body, x) * side.outward_normal()
    }

    /// The contact description of a two-body contact problem; `None` (the default) for
    /// elasticity problems.
    fn contact(&self) -> Option<&dyn ExactContact> {
        None
    }
}

/// An exact solution of a two-body contact problem on the interface `Gamma_C` of
/// [`CONTACT_SIDES`]: the bottom side of body one, `y = y_C`, `x` in the x-range of body
/// one's domain.
///
/// The law is any [`ContactLaw`] the contact layer solves: frictionless (P1), Tresca (P2) with
/// a constant bound or a bound `g_F(x)` that varies along `Gamma_C`
/// ([`FrictionBound::Field`](vem_contact::FrictionBound::Field), evaluated at the interface
/// nodes of body one), or Coulomb `g_F = F |sigma_nu|`. The discrete problem is built with
/// exactly this law, so the exact solution must satisfy it: on the slip set
/// `|sigma_1tau| = g_F`, on the stick set `|sigma_1tau| <= g_F` and no slip.
///
/// An implementation returns `Some(self)` from [`ExactSolution::contact`].
pub trait ExactContact: ExactSolution {
    /// The contact law the exact solution satisfies (the discrete problem is solved with it).
    fn law(&self) -> std::sync::Arc<dyn ContactLaw>;

    /// The initial gap `h0(x)` on `Gamma_C`.
    fn initial_gap(&self, x: f64) -> f64;

    /// Stresses, jumps and gap at `(x, y_C)` on `Gamma_C`, by default from the fields of the
    /// two bodies with `nu_1 = (0, -1)` and `tau = e_x` (`docs/manufactured.md`, section 1).
    fn interface_values(&self, x: f64) -> InterfaceValues {
        let point = Point::new(x, self.domain(BodyId::One).min.y);
        let nu_1 = Side::Bottom.outward_normal();
        let nu_2 = Side::Top.outward_normal();
        let tau = Vector::new(1.0, 0.0);
        let traction_1 = self.stress(BodyId::One, point) * nu_1;
        let u_1 = self.displacement(BodyId::One, point);
        let u_2 = self.displacement(BodyId::Two, point);
        InterfaceValues {
            sigma_nu: traction_1.dot(&nu_1),
            sigma_1tau: traction_1.dot(&tau),
            normal_jump: u_1.dot(&nu_1) + u_2.dot(&nu_2),
            tangential_jump: (u_1 - u_2).dot(&tau),
            initial_gap: self.initial_gap(x),
        }
    }

    /// The contact (and stick/slip) statuses a discrete solution must reproduce, if known.
    fn expected_sets(&self) -> Option<ExpectedSets> {
        None
    }

    /// The exact resultants `int sigma_nu ds`, `int sigma_1tau ds` over `Gamma_C`, if known in
    /// closed form.
    fn reference_resultants(&self) -> Option<Resultants> {
        None
    }
}
