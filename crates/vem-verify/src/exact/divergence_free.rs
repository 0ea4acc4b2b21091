//! E2c: a two-body frictionless contact solution that is divergence free in both bodies, the
//! contact analogue of E2 for locking studies: displacement, stress, body force, tractions and
//! contact pressure do not depend on `lambda`.

use nalgebra::Matrix2;
use std::sync::Arc;

use vem_contact::{ContactLaw, Frictionless};
use vem_mesh::generators::Rectangle;
use vem_mesh::{Point, Vector};

use super::solution::{
    BodyId, ContactSet, ExactContact, ExactSolution, ExpectedSets, Lame, Resultants, Side,
};

/// The constant initial gap `h0 = 1/20` of [`DivergenceFreeContact`].
pub const DIVERGENCE_FREE_GAP: f64 = 0.05;

/// E2c: `u_i = curl psi_i = (d_y psi_i, -d_x psi_i)` on body one `(0,1) x (0,1)` and body two
/// `(0,1) x (-1,0)`, clamped at `y = 1` and `y = -1`, tractions on the lateral sides,
/// frictionless contact on `Gamma_C = (0,1) x {0}` with the constant initial gap
/// `h0` ([`DIVERGENCE_FREE_GAP`]):
///
/// ```text
/// psi_1 = F(x) G_1(y) + h0 x K(y),   psi_2 = F(x) G_2(y),
/// F(x) = (1 + x)^3 / 24,
/// G_s(y) = y (1 - s y)^2 (1 + 2 s y) = y - 3 y^3 + 2 s y^4   (s = +1 body one, -1 body two),
/// K(y) = 1 - 4 y^3 + 3 y^4.
/// ```
///
/// `div u = 0` exactly, so `sigma = 2 mu eps(u)` and `f = -mu Laplace(u)`: nothing depends on
/// `lambda`, and any growth of a discrete error with `lambda/mu` is locking. Construction:
/// `G_s(s) = G_s'(s) = K(1) = K'(1) = 0` clamp the outer sides; `G_s(0) = G_s''(0) = 0`,
/// `G_s'(0) = 1` and `K'(0) = K''(0) = 0` give on `Gamma_C` `u_1 = (F, -h0)`, `u_2 = (F, 0)`,
/// `sigma_xy = 0` (frictionless) and `sigma_yy = -2 mu F'(x) < 0` in both bodies (traction
/// continuity): the bodies touch everywhere (`[u]_nu = h0`, gap zero) under the pressure
/// `2 mu F' = mu (1 + x)^2 / 4` and do not slip relative to each other.
///
/// ```
/// use vem_verify::exact::{BodyId, DivergenceFreeContact, ExactContact, ExactSolution, Lame};
/// use vem_mesh::Point;
/// for lambda in [2.0, 1e6] {
///     let e2c = DivergenceFreeContact::new(Lame::try_new(lambda, 1.0)?);
///     let x = Point::new(0.3, 0.6);
///     assert!(e2c.gradient(BodyId::One, x).trace().abs() < 1e-15);
///     let interface = e2c.interface_values(0.5);
///     assert!((interface.sigma_nu + 2.25 / 4.0).abs() < 1e-15);
///     assert!(interface.gap().abs() < 1e-15);
/// }
/// # Ok::<(), vem_verify::exact::ExactError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DivergenceFreeContact {
    lame: Lame,
}

/// The derivatives `psi_x, psi_y, psi_xx, psi_xy, psi_yy, psi_xxx, psi_xxy, psi_xyy, psi_yyy`.
struct StreamDerivatives {
    x: f64,
    y: f64,
    xx: f64,
    xy: f64,
    yy: f64,
    xxx: f64,
    xxy: f64,
    xyy: f64,
    yyy: f64,
}

impl DivergenceFreeContact {
    /// E2c with the material `lame` (only `mu` enters the fields).
    pub fn new(lame: Lame) -> Self {
        Self { lame }
    }

    /// The stream function's derivatives on `body` at `p`.
    fn stream(body: BodyId, p: Point) -> StreamDerivatives {
        let (x, y) = (p.x, p.y);
        // F and three derivatives.
        let t = 1.0 + x;
        let f = [t * t * t / 24.0, t * t / 8.0, t / 4.0, 0.25];
        // G_s and three derivatives.
        let s = match body {
            BodyId::One => 1.0,
            BodyId::Two => -1.0,
        };
        let y2 = y * y;
        let g = [
            y - 3.0 * y * y2 + 2.0 * s * y2 * y2,
            1.0 - 9.0 * y2 + 8.0 * s * y * y2,
            -18.0 * y + 24.0 * s * y2,
            -18.0 + 48.0 * s * y,
        ];
        // h0 K on body one only.
        let k = match body {
            BodyId::One => [
                1.0 - 4.0 * y * y2 + 3.0 * y2 * y2,
                -12.0 * y2 + 12.0 * y * y2,
                -24.0 * y + 36.0 * y2,
                -24.0 + 72.0 * y,
            ]
            .map(|v| DIVERGENCE_FREE_GAP * v),
            BodyId::Two => [0.0; 4],
        };
        StreamDerivatives {
            x: f[1] * g[0] + k[0],
            y: f[0] * g[1] + x * k[1],
            xx: f[2] * g[0],
            xy: f[1] * g[1] + k[1],
            yy: f[0] * g[2] + x * k[2],
            xxx: f[3] * g[0],
            xxy: f[2] * g[1],
            xyy: f[1] * g[2] + k[2],
            yyy: f[0] * g[3] + x * k[3],
        }
    }
}

impl ExactSolution for DivergenceFreeContact {
    /// `"E2c"`.
    fn name(&self) -> &str {
        "E2c"
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
        let psi = Self::stream(body, x);
        Vector::new(psi.y, -psi.x)
    }

    /// `[[psi_xy, psi_yy], [-psi_xx, -psi_xy]]`: its trace is zero in floating point too, so
    /// the stress carries no `lambda` term.
    fn gradient(&self, body: BodyId, x: Point) -> Matrix2<f64> {
        let psi = Self::stream(body, x);
        Matrix2::new(psi.xy, psi.yy, -psi.xx, -psi.xy)
    }

    /// `f = -mu Laplace(u) = -mu (psi_xxy + psi_yyy, -(psi_xxx + psi_xyy))`.
    fn body_force(&self, body: BodyId, x: Point) -> Vector {
        let psi = Self::stream(body, x);
        let mu = self.lame.mu();
        Vector::new(-mu * (psi.xxy + psi.yyy), mu * (psi.xxx + psi.xyy))
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

impl ExactContact for DivergenceFreeContact {
    fn law(&self) -> Arc<dyn ContactLaw> {
        Arc::new(Frictionless)
    }

    fn initial_gap(&self, _x: f64) -> f64 {
        DIVERGENCE_FREE_GAP
    }

    /// Every node active (pressure between `mu/4` and `mu`).
    fn expected_sets(&self) -> Option<ExpectedSets> {
        Some(ExpectedSets {
            contact: ContactSet::AllActive,
            friction: None,
        })
    }

    /// `int sigma_nu ds = -2 mu (F(1) - F(0)) = -7 mu / 12`, no tangential force.
    fn reference_resultants(&self) -> Option<Resultants> {
        Some(Resultants {
            normal: -7.0 * self.lame.mu() / 12.0,
            tangential: 0.0,
        })
    }
}
