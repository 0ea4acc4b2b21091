//! The two-body contact patch tests PTC1, PTC1h, PTC2, PTC3 (`docs/manufactured.md`, section 6):
//! linear fields, zero body force and constant stress, in full contact, which a node-to-node
//! VEM contact discretisation reproduces exactly on matching and non-matching meshes.

use nalgebra::Matrix2;
use std::sync::Arc;

use vem_contact::{ContactLaw, Frictionless, Tresca};
use vem_mesh::generators::Rectangle;
use vem_mesh::{Point, Vector};

use super::solution::{
    BodyId, ContactSet, ExactContact, ExactSolution, ExpectedSets, FrictionSet, Lame, Resultants,
    Side,
};

/// The friction bound `g_F = 1/4` of PTC2 and PTC3.
pub const PATCH_FRICTION_BOUND: f64 = 0.25;

/// A contact patch test:
/// `u_1 = (e - gamma (1 - y), -d + beta (1 - y))` on `(0,1) x (0,1)`,
/// `u_2 = (-e + gamma (1 + y), d - beta (1 + y))` on `(0,1) x (-1,0)`,
/// Dirichlet data `u_1(x, 1) = (e, -d)`, `u_2(x, -1) = (-e, d)`, constant lateral tractions,
/// constant gap `h0 = 2 (d - beta)` and stress
/// `sigma = [-lambda beta, mu gamma; mu gamma, -(lambda + 2 mu) beta]` in both bodies.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactPatch {
    name: &'static str,
    lame: Lame,
    beta: f64,
    d: f64,
    e: f64,
    gamma: f64,
    /// The Tresca bound `g_F` (`None`: frictionless).
    friction_bound: Option<f64>,
    friction_status: Option<FrictionSet>,
}

impl ContactPatch {
    /// PTC1: frictionless, pushed together by the Dirichlet data, free slip
    /// (`beta = 1/100`, `d = 3/100`, `e = 1/50`, `gamma = 0`; `h0 = 1/25`).
    pub fn ptc1(lame: Lame) -> Self {
        Self {
            name: "PTC1",
            lame,
            beta: 0.01,
            d: 0.03,
            e: 0.02,
            gamma: 0.0,
            friction_bound: None,
            friction_status: None,
        }
    }

    /// PTC1h: frictionless with homogeneous Dirichlet data: an interference fit
    /// (`beta = 1/100`, `d = e = gamma = 0`; `h0 = -1/50`).
    pub fn ptc1h(lame: Lame) -> Self {
        Self {
            name: "PTC1h",
            lame,
            beta: 0.01,
            d: 0.0,
            e: 0.0,
            gamma: 0.0,
            friction_bound: None,
            friction_status: None,
        }
    }

    /// PTC2: Tresca (`g_F = 1/4`), full slip: `gamma = g_F/mu`, `e = gamma + 1/50`,
    /// `beta = 1/100`, `d = 3/100` (`sigma_1tau = -g_F`, slip `1/25`).
    pub fn ptc2(lame: Lame) -> Self {
        let gamma = PATCH_FRICTION_BOUND / lame.mu();
        Self {
            name: "PTC2",
            lame,
            beta: 0.01,
            d: 0.03,
            e: gamma + 0.02,
            gamma,
            friction_bound: Some(PATCH_FRICTION_BOUND),
            friction_status: Some(FrictionSet::AllSlip),
        }
    }

    /// PTC3: Tresca (`g_F = 1/4`), full stick: `gamma = g_F/(2 mu)`, `e = gamma`,
    /// `beta = 1/100`, `d = 3/100` (`|sigma_1tau| = g_F/2`, no slip).
    pub fn ptc3(lame: Lame) -> Self {
        let gamma = PATCH_FRICTION_BOUND / (2.0 * lame.mu());
        Self {
            name: "PTC3",
            lame,
            beta: 0.01,
            d: 0.03,
            e: gamma,
            gamma,
            friction_bound: Some(PATCH_FRICTION_BOUND),
            friction_status: Some(FrictionSet::AllStick),
        }
    }
}

impl ExactSolution for ContactPatch {
    fn name(&self) -> &str {
        self.name
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
        let (beta, d, e, gamma) = (self.beta, self.d, self.e, self.gamma);
        match body {
            BodyId::One => Vector::new(e - gamma * (1.0 - x.y), -d + beta * (1.0 - x.y)),
            BodyId::Two => Vector::new(-e + gamma * (1.0 + x.y), d - beta * (1.0 + x.y)),
        }
    }

    fn gradient(&self, _body: BodyId, _x: Point) -> Matrix2<f64> {
        Matrix2::new(0.0, self.gamma, 0.0, -self.beta)
    }

    fn body_force(&self, _body: BodyId, _x: Point) -> Vector {
        Vector::zeros()
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

impl ExactContact for ContactPatch {
    fn law(&self) -> Arc<dyn ContactLaw> {
        match self.friction_bound {
            None => Arc::new(Frictionless),
            Some(g) => Arc::new(Tresca::try_new(g).expect("a patch test's bound is positive")),
        }
    }

    fn initial_gap(&self, _x: f64) -> f64 {
        2.0 * (self.d - self.beta)
    }

    /// Every node active (pressure `(lambda + 2 mu)/100`); PTC2 all slip, PTC3 all stick.
    fn expected_sets(&self) -> Option<ExpectedSets> {
        Some(ExpectedSets {
            contact: ContactSet::AllActive,
            friction: self.friction_status,
        })
    }

    /// `int sigma_nu ds = -(lambda + 2 mu) beta`, `int sigma_1tau ds = -mu gamma` (unit
    /// interface length).
    fn reference_resultants(&self) -> Option<Resultants> {
        let (lambda, mu) = (self.lame.lambda(), self.lame.mu());
        Some(Resultants {
            normal: -(lambda + 2.0 * mu) * self.beta,
            tangential: -mu * self.gamma,
        })
    }
}
