//! What a contact solve returns: per-body solutions, per-node interface results, resultants,
//! the solver's report and a summary of what was modelled.

use std::ops::Range;
use std::sync::Arc;
use std::time::Duration;

use nalgebra::SMatrix;
use vem_elastic::{AssembledSystem, ElasticBody, Solution};
use vem_mesh::{Point, PointD, Vector, VectorD};

use crate::{frame, SolveReport, Warning, WorkCounters};

/// The contact state of an interface node: one name per state, `Stick` and `Slip` only where
/// the pair's law has friction.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum NodeStatus {
    /// No contact force, normal or tangential: the node is (or may be) separated.
    Open,
    /// In contact without friction (the pair's law is frictionless): a normal force only.
    Contact,
    /// With friction, the friction force strictly below its bound: no slip.
    Stick,
    /// With friction, the friction force at its bound: the node slides.
    Slip,
}

impl NodeStatus {
    /// Lower-case name ("open", "contact", "stick", "slip").
    pub fn name(self) -> &'static str {
        match self {
            NodeStatus::Open => "open",
            NodeStatus::Contact => "contact",
            NodeStatus::Stick => "stick",
            NodeStatus::Slip => "slip",
        }
    }

    /// True unless open: the node carries a contact force.
    pub fn is_active(self) -> bool {
        self != NodeStatus::Open
    }
}

/// How many interface nodes are in each [`NodeStatus`].
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct StatusCounts {
    /// Open nodes.
    pub open: usize,
    /// Nodes in contact without friction.
    pub contact: usize,
    /// Sticking nodes (friction below its bound).
    pub stick: usize,
    /// Slipping nodes (friction at its bound).
    pub slip: usize,
}

impl StatusCounts {
    /// The counts of `statuses`.
    ///
    /// ```
    /// use vem_contact::{NodeStatus, StatusCounts};
    /// let counts = StatusCounts::of([NodeStatus::Open, NodeStatus::Stick, NodeStatus::Slip]);
    /// assert_eq!((counts.open, counts.contact, counts.stick, counts.slip), (1, 0, 1, 1));
    /// assert_eq!(counts.active(), 2);
    /// ```
    pub fn of(statuses: impl IntoIterator<Item = NodeStatus>) -> Self {
        let mut counts = Self::default();
        for status in statuses {
            match status {
                NodeStatus::Open => counts.open += 1,
                NodeStatus::Contact => counts.contact += 1,
                NodeStatus::Stick => counts.stick += 1,
                NodeStatus::Slip => counts.slip += 1,
            }
        }
        counts
    }

    /// Nodes that carry a contact force (every state but open).
    pub fn active(&self) -> usize {
        self.contact + self.stick + self.slip
    }

    /// All nodes.
    pub fn total(&self) -> usize {
        self.open + self.active()
    }
}

/// Classifies a node from its forces, `force_tolerance` deciding what is zero. Without
/// friction (`friction_bound` is `None`): open when the normal force is at most the
/// tolerance, else in contact. With friction: open only when neither the normal force nor
/// the magnitude of the friction force exceeds the tolerance (a Tresca bound acts whatever
/// the pressure: a node may carry friction without pressure, and then it is not open); else
/// stick when the friction force is below its bound by more than the tolerance, slip
/// otherwise.
pub(crate) fn classify(
    normal_force: f64,
    friction_force: f64,
    friction_bound: Option<f64>,
    force_tolerance: f64,
) -> NodeStatus {
    let pressed = normal_force > force_tolerance;
    match friction_bound {
        None if pressed => NodeStatus::Contact,
        None => NodeStatus::Open,
        Some(_) if !pressed && friction_force.abs() <= force_tolerance => NodeStatus::Open,
        Some(bound) if friction_force.abs() < bound - force_tolerance => NodeStatus::Stick,
        Some(_) => NodeStatus::Slip,
    }
}

/// The result at one interface node (a node pair of two bodies, or a body node facing an
/// obstacle) of a body in `R^D`. Signs follow the spec: `nu` points from body A to body B (the
/// nodal normal of the side chosen by [`ContactNormal`](crate::ContactNormal); into the
/// obstacle); the tangential quantities are vectors of the tangent plane (`D - 1` dimensional)
/// in global coordinates. In 2D, `tau = (-nu_y, nu_x)` and [`InterfaceNode::friction_t`],
/// [`InterfaceNode::slip_t`] give their components along `tau`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct InterfaceNode<const D: usize = 2> {
    /// The contact pair the node belongs to.
    pub pair: usize,
    /// Position (on body A, reference configuration).
    pub position: PointD<D>,
    /// The normal `nu`.
    pub normal: VectorD<D>,
    /// Tributary measure `l_x` of the node (length in 2D, area in 3D).
    pub tributary_measure: f64,
    /// Total initial gap `h0` (geometric gap plus the imposed gap).
    pub initial_gap: f64,
    /// The normal jump `[u]_nu = (u_A - u_B) . nu` (`u_A . nu` against an obstacle);
    /// `[u]_nu <= h0`.
    pub normal_jump: f64,
    /// Nodal contact force `lambda_N >= 0` (compression), `= -sigma_nu l_x`.
    pub normal_force: f64,
    /// Contact pressure `lambda_N / l_x` (the raw nodal value), approximating `-sigma_nu`.
    pub pressure: f64,
    /// The consistent contact pressure, approximating `-sigma_nu`, `>= 0`: in 2D the node's
    /// value of the L2 projection of the nodal normal forces onto the non-negative continuous
    /// piecewise-linear functions on the interface spanned by the original (not inserted)
    /// nodes of the side with fewer of them, B on a tie, every node against an obstacle
    /// ([`consistent_traction`] with [`TractionBound::NonNegative`]); in 3D the L2 projection
    /// onto the non-negative functions of the face-trace space of the element on the faces of
    /// body A's contact part (linear on each fan triangle of a face, the mean of the face's
    /// vertex values at its centre), every node in the support (docs/contact-3d.md).
    pub consistent_pressure: f64,
    /// Nodal friction force on body A (tangential, `= sigma_1tau l_x`); it opposes the slip.
    pub friction_force: VectorD<D>,
    /// The consistent friction traction, approximating `sigma_1tau`: in 2D the same
    /// projection of the friction forces within the projection of the nodal friction bounds
    /// ([`TractionBound::Magnitude`]: `|t| <= F p` for Coulomb), along the tangent; in 3D the
    /// nodal value.
    pub consistent_friction_traction: VectorD<D>,
    /// The nodal friction bound `b_i` the last solve used (a force: Tresca `g_F l_x`, Coulomb
    /// `F lambda_N` of the fixed point's last step, a law of one's own its own; the disk's
    /// radius in 3D); 0 without friction.
    pub friction_bound: f64,
    /// The slip: the tangential part of `u_A - u_B` (zero for frictionless laws: not
    /// modelled).
    pub slip: VectorD<D>,
    /// Open, contact (frictionless), stick or slip.
    pub status: NodeStatus,
    /// Body A of the pair (index in the problem's bodies).
    pub body_a: usize,
    /// The vertex of body A's (enlarged) mesh.
    pub vertex_a: usize,
    /// Body B of the pair; `None` against an obstacle.
    pub body_b: Option<usize>,
    /// The partner vertex of body B's (enlarged) mesh; `None` against an obstacle.
    pub vertex_b: Option<usize>,
}

impl<const D: usize> InterfaceNode<D> {
    /// The orthonormal frame of the node: column 0 the normal, then the tangents
    /// ([`frame`]).
    pub fn frame(&self) -> SMatrix<f64, D, D> {
        frame(&self.normal)
    }
}

impl InterfaceNode<2> {
    /// The tangent `tau = (-nu_y, nu_x)`.
    pub fn tangent(&self) -> Vector {
        crate::tangent(self.normal)
    }

    /// The friction force on body A along `tau`.
    pub fn friction_t(&self) -> f64 {
        self.friction_force.dot(&self.tangent())
    }

    /// The consistent friction traction along `tau`.
    pub fn consistent_friction_t(&self) -> f64 {
        self.consistent_friction_traction.dot(&self.tangent())
    }

    /// The slip `[u]_1tau = (u_A - u_B) . tau`.
    pub fn slip_t(&self) -> f64 {
        self.slip.dot(&self.tangent())
    }
}

/// What a consistent traction must respect (see [`consistent_traction`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TractionBound<'a> {
    /// Nothing: the plain L2 projection, which overshoots at a kink of the traction (just
    /// outside a contact zone it dips below zero).
    Unbounded,
    /// A traction `p >= 0` (a contact pressure): the L2 projection onto the non-negative
    /// functions of the space.
    NonNegative,
    /// A traction `|t| <= beta` with `beta` the non-negative projection of the given nodal
    /// bound forces `b_i` (a friction traction and its nodal friction bounds: Coulomb's
    /// `F lambda_N,i`, Tresca's `l_i g_F(x_i)`): the L2 projection onto the functions within
    /// that bound.
    Magnitude(&'a [f64]),
}

/// Sweeps of the projected Gauss-Seidel iteration at most (each one contracts the error by at
/// least one half: 60 reach round-off from any start).
const MAX_SWEEPS: usize = 200;

/// The continuous piecewise-linear functions on the polyline through the interface nodes
/// (linear in arc length between support nodes) and the L2 projection of nodal forces onto
/// them, plain or bounded. Built once per interface; see [`consistent_traction`].
#[derive(Debug, Clone)]
struct TractionSpace {
    /// For every node: its support interval `k` (between support nodes `k` and `k + 1`) and
    /// its coordinate `t` in it (`phi_k = 1 - t`, `phi_{k+1} = t` there).
    location: Vec<(usize, f64)>,
    /// Arc length between consecutive support nodes (all `> 0`).
    lengths: Vec<f64>,
}

impl TractionSpace {
    /// The space of the nodes at `positions` with the hats of the nodes marked in `support`
    /// (the first and the last node are always support nodes); `None` for fewer than two
    /// nodes, inconsistent lengths or a polyline of zero or non-finite length.
    fn new(positions: &[Point], support: &[bool]) -> Option<Self> {
        let n = positions.len();
        if n < 2 || support.len() != n {
            return None;
        }
        let mut arc = Vec::with_capacity(n);
        let mut s = 0.0;
        arc.push(0.0);
        for w in positions.windows(2) {
            s += (w[1] - w[0]).norm();
            arc.push(s);
        }
        if !s.is_finite() || s <= 0.0 {
            return None;
        }
        // Support nodes (ends included) at strictly increasing arc length.
        let mut nodes: Vec<usize> = Vec::new();
        for i in 0..n {
            let marked = support[i] || i == 0 || i + 1 == n;
            if marked && nodes.last().is_none_or(|&k| arc[i] > arc[k]) {
                nodes.push(i);
            } else if i + 1 == n && nodes.len() > 1 {
                // The last node at the arc length of the previous support node: replace it.
                let last = nodes.len() - 1;
                nodes[last] = i;
            }
        }
        if nodes.len() < 2 {
            return None;
        }
        let lengths: Vec<f64> = nodes.windows(2).map(|w| arc[w[1]] - arc[w[0]]).collect();
        let mut location = Vec::with_capacity(n);
        let mut k = 0;
        for &s in &arc {
            while k + 2 < nodes.len() && s > arc[nodes[k + 1]] {
                k += 1;
            }
            let t = ((s - arc[nodes[k]]) / lengths[k]).clamp(0.0, 1.0);
            location.push((k, t));
        }
        Some(Self { location, lengths })
    }

    fn n_support(&self) -> usize {
        self.lengths.len() + 1
    }

    /// `M_kk`, the diagonal of the consistent mass matrix of the support hats (`M_k,k+1 =
    /// L_k / 6` beside it).
    fn diagonal(&self, k: usize) -> f64 {
        let before = if k > 0 { self.lengths[k - 1] } else { 0.0 };
        let after = self.lengths.get(k).copied().unwrap_or(0.0);
        (before + after) / 3.0
    }

    /// `r_k = sum_i forces_i phi_k(x_i)`: every force distributed to the hats of its interval.
    fn load(&self, forces: &[f64]) -> Vec<f64> {
        let mut rhs = vec![0.0; self.n_support()];
        for (&(k, t), f) in self.location.iter().zip(forces) {
            rhs[k] += (1.0 - t) * f;
            rhs[k + 1] += t * f;
        }
        rhs
    }

    /// `M^-1 r` by the Thomas algorithm (`M` is symmetric positive definite and strictly
    /// diagonally dominant: no pivoting needed).
    fn solve_mass(&self, rhs: &[f64]) -> Vec<f64> {
        let m = self.n_support();
        let mut x = rhs.to_vec();
        let mut upper = vec![0.0; m];
        let (mut previous_upper, mut previous_value) = (0.0, 0.0);
        for k in 0..m {
            let lower = if k > 0 {
                self.lengths[k - 1] / 6.0
            } else {
                0.0
            };
            let pivot = self.diagonal(k) - lower * previous_upper;
            upper[k] = self.lengths.get(k).map_or(0.0, |l| l / 6.0) / pivot;
            x[k] = (x[k] - lower * previous_value) / pivot;
            previous_upper = upper[k];
            previous_value = x[k];
        }
        for k in (0..m - 1).rev() {
            x[k] -= upper[k] * x[k + 1];
        }
        x
    }

    /// `int phi_k ds = (L_{k-1} + L_k) / 2`, the row sums of `M`.
    fn hat_integral(&self, k: usize) -> f64 {
        1.5 * self.diagonal(k)
    }

    /// `(M c)_k`.
    fn mass_apply(&self, c: &[f64], k: usize) -> f64 {
        let mut y = self.diagonal(k) * c[k];
        if k > 0 {
            y += self.lengths[k - 1] / 6.0 * c[k - 1];
        }
        if k + 1 < c.len() {
            y += self.lengths[k] / 6.0 * c[k + 1];
        }
        y
    }

    /// The minimiser of `1/2 c'Mc - (r + nu m)'c` over `lower <= c <= upper` (`m_k = int
    /// phi_k`), by projected Gauss-Seidel from `c` (clamped), in place. `M` is diagonally
    /// dominant by a factor two (`sum_{j != k} |M_kj| = M_kk / 2`), so each sweep contracts
    /// the error in the maximum norm by at least one half, whatever the spacing: the sweeps
    /// stop when one changes no coefficient by more than a few units of round-off of the
    /// largest.
    fn box_minimiser(&self, rhs: &[f64], nu: f64, lower: &[f64], upper: &[f64], c: &mut [f64]) {
        let m = c.len();
        for k in 0..m {
            c[k] = c[k].clamp(lower[k], upper[k]);
        }
        for _ in 0..MAX_SWEEPS {
            let (mut change, mut scale) = (0.0f64, 0.0f64);
            for k in 0..m {
                let off = self.mass_apply(c, k) - self.diagonal(k) * c[k];
                let target = rhs[k] + nu * self.hat_integral(k);
                let value = ((target - off) / self.diagonal(k)).clamp(lower[k], upper[k]);
                change = change.max((value - c[k]).abs());
                scale = scale.max(value.abs());
                c[k] = value;
            }
            if change <= 4.0 * f64::EPSILON * scale || !change.is_finite() {
                break;
            }
        }
    }

    /// The minimiser of `1/2 c'Mc - r'c` over `lower <= c <= upper` (the bounds ordered,
    /// `lower` finite) with the resultant of the forces, `int p_h ds = sum_k m_k c_k =
    /// sum_k r_k` (when the bounds allow it). The unconstrained solution `M c = r` has that
    /// resultant (the hats sum to one): when it lies within the bounds it is the answer.
    /// Otherwise the resultant is a multiplier `nu`: the minimiser `c(nu)` of the bounded
    /// problem with the linear term `r + nu m` has a resultant non-decreasing in `nu`
    /// (piecewise linear), and the root is bracketed between the `nu` that put every
    /// coefficient at one bound and found by the Illinois variant of regula falsi.
    fn solve_bounded(&self, rhs: &[f64], lower: &[f64], upper: &[f64]) -> Vec<f64> {
        let mut c = self.solve_mass(rhs);
        let within = |c: &[f64]| {
            c.iter()
                .zip(lower.iter().zip(upper))
                .all(|(c, (lo, hi))| lo <= c && c <= hi)
        };
        if within(&c) {
            return c;
        }
        let m = c.len();
        let total: f64 = rhs.iter().sum();
        let resultant =
            |c: &[f64]| (0..m).map(|k| self.hat_integral(k) * c[k]).sum::<f64>() - total;
        self.box_minimiser(rhs, 0.0, lower, upper, &mut c);
        let tolerance = 1e-14 * rhs.iter().map(|r| r.abs()).sum::<f64>();
        let g0 = resultant(&c);
        // The multipliers that put every coefficient at its lower (upper) bound.
        let at_bound = |bound: &[f64], pick: fn(f64, f64) -> f64, start: f64| {
            (0..m).fold(start, |acc, k| {
                pick(
                    acc,
                    (self.mass_apply(bound, k) - rhs[k]) / self.hat_integral(k),
                )
            })
        };
        let (mut a, mut b) = if g0 > tolerance {
            (at_bound(lower, f64::min, 0.0), 0.0)
        } else if g0 < -tolerance && upper.iter().all(|u| u.is_finite()) {
            (0.0, at_bound(upper, f64::max, 0.0))
        } else {
            return c;
        };
        if !(a.is_finite() && b.is_finite()) {
            return c;
        }
        let (mut ga, mut gb) = if a < 0.0 {
            (resultant(lower), g0)
        } else {
            (g0, resultant(upper))
        };
        if ga > tolerance || gb < -tolerance {
            // The bounds do not allow the resultant (forces of the wrong sign): keep nu = 0.
            return c;
        }
        let mut side = 0;
        for _ in 0..100 {
            let nu = if gb > ga {
                (a * gb - b * ga) / (gb - ga)
            } else {
                0.5 * (a + b)
            };
            self.box_minimiser(rhs, nu, lower, upper, &mut c);
            let g = resultant(&c);
            if g.abs() <= tolerance || b - a <= 4.0 * f64::EPSILON * a.abs().max(b.abs()) {
                break;
            }
            if g < 0.0 {
                a = nu;
                ga = g;
                if side == -1 {
                    gb *= 0.5;
                }
                side = -1;
            } else {
                b = nu;
                gb = g;
                if side == 1 {
                    ga *= 0.5;
                }
                side = 1;
            }
        }
        c
    }

    /// The function with support values `c` at every node.
    fn values(&self, c: &[f64]) -> Vec<f64> {
        self.location
            .iter()
            .map(|&(k, t)| (1.0 - t) * c[k] + t * c[k + 1])
            .collect()
    }

    /// The support values of the projection of `forces` within `bound`.
    fn coefficients(&self, forces: &[f64], bound: TractionBound<'_>) -> Vec<f64> {
        let m = self.n_support();
        let rhs = self.load(forces);
        match bound {
            TractionBound::Unbounded => self.solve_mass(&rhs),
            TractionBound::NonNegative => {
                self.solve_bounded(&rhs, &vec![0.0; m], &vec![f64::INFINITY; m])
            }
            TractionBound::Magnitude(bounds) => {
                let beta = self.coefficients(bounds, TractionBound::NonNegative);
                let lower: Vec<f64> = beta.iter().map(|b| -b).collect();
                self.solve_bounded(&rhs, &lower, &beta)
            }
        }
    }
}

/// The consistent traction of nodal forces on a planar interface: their L2 projection onto
/// continuous piecewise-linear functions on the polyline through `positions` (consecutive
/// positions joined by straight edges), within `bound`.
///
/// The functions are the hats of the nodes marked in `support` (the first and the last node
/// are always in it), linear in arc length between them. With `s_i` the arc length of node
/// `i`, `phi_k` the hat of support node `k` and `M_kl = int phi_k phi_l ds` the consistent
/// mass matrix of the support (tridiagonal: `(L_{k-1} + L_k)/3` on the diagonal, `L_k/6`
/// beside it, `L_k` the arc length between support nodes `k` and `k+1`), the values `c_k` at
/// the support nodes minimise
///
/// ```text
/// 1/2 c'Mc - r'c,   r_k = sum_i forces_i phi_k(s_i),   over the c within the bound
/// ```
///
/// and the result is the function at every node (interpolated between support nodes).
/// Without a bound this is `M c = r`, the plain L2 projection (Thomas algorithm). A bound
/// restricts the coefficients, and so the function everywhere (it is linear between them):
/// [`TractionBound::NonNegative`] keeps a pressure `>= 0`; [`TractionBound::Magnitude`] keeps
/// a friction traction within the non-negative projection `beta` of the nodal friction
/// bounds, so that Coulomb's `|t| <= F p` holds pointwise for the consistent pressure `p` when
/// the bounds are `F lambda_N` (the projection is positively homogeneous: `beta = F p`), and
/// Tresca's `|t| <= g_F` when `g_F` is linear along the interface (`beta` then is `g_F`). The
/// bounded problem is solved from the plain projection by projected Gauss-Seidel, which
/// contracts by one half per sweep (`M` is diagonally dominant by a factor two).
///
/// Where the plain projection already satisfies the bound it is the answer: forces
/// `f_i = sum_j M^h_ij p(s_j)` of a linear traction `p` with the consistent mass matrix `M^h`
/// of all nodes are reproduced exactly, and so is a uniform traction with forces `p0 l_i`
/// (tributary lengths), on any support. With fewer support nodes than nodes (the nodes of
/// the coarser side of a non-matching interface) the node-to-node oscillation that forces
/// show where the two sides' nodes nearly coincide is averaged out. Where the plain
/// projection violates the bound (it overshoots at a kink: just outside a contact zone, at a
/// punch's edge) the bounded one is the closest function in L2 that satisfies it.
///
/// A polyline of fewer than two nodes, or of zero length, or slices of different lengths,
/// have no projection: the forces divided by the `fallback` lengths are returned (0 where a
/// length is 0), and so they are if the projection is not finite.
///
/// ```
/// use vem_contact::{consistent_traction, TractionBound};
/// use vem_mesh::Point;
/// // Five nodes 0.25 apart; the forces of a pressure that ends at the middle node.
/// let x: Vec<Point> = (0..5).map(|i| Point::new(0.25 * i as f64, 0.0)).collect();
/// let forces = [0.125, 0.25, 0.125, 0.0, 0.0];
/// let lengths = [0.125, 0.25, 0.25, 0.25, 0.125];
/// let support = [true; 5];
/// let plain = consistent_traction(&x, &forces, &support, &lengths, TractionBound::Unbounded);
/// let p = consistent_traction(&x, &forces, &support, &lengths, TractionBound::NonNegative);
/// assert!(plain[3] < 0.0);
/// assert!(p.iter().all(|&p| p >= 0.0));
/// # assert!((p[0] - 1.0).abs() < 0.2 && p[4] == 0.0);
/// ```
pub fn consistent_traction(
    positions: &[Point],
    forces: &[f64],
    support: &[bool],
    fallback: &[f64],
    bound: TractionBound<'_>,
) -> Vec<f64> {
    let raw = || {
        forces
            .iter()
            .zip(fallback)
            .map(|(f, l)| if *l > 0.0 { f / l } else { 0.0 })
            .collect::<Vec<f64>>()
    };
    let n = positions.len();
    let consistent = forces.len() == n
        && match bound {
            TractionBound::Magnitude(bounds) => bounds.len() == n,
            _ => true,
        };
    let Some(space) = TractionSpace::new(positions, support).filter(|_| consistent) else {
        return raw();
    };
    let values = space.values(&space.coefficients(forces, bound));
    if values.iter().all(|v| v.is_finite()) {
        values
    } else {
        raw()
    }
}

/// One body after the solve: the body on its enlarged mesh, its assembled system and its
/// solution (displacement, reactions, strain energy).
#[derive(Debug, Clone)]
pub struct BodyResult<const D: usize = 2> {
    /// The body, on the mesh with the inserted interface nodes.
    pub body: ElasticBody<D>,
    /// Its assembled (reduced) system, shared with the discretisation it was solved on.
    pub system: Arc<AssembledSystem>,
    /// Its solution.
    pub solution: Solution<D>,
}

/// Size and content of one modelled body.
#[derive(Debug, Clone, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct BodySummary {
    /// The body's name.
    pub name: String,
    /// Vertices of its enlarged mesh.
    pub vertices: usize,
    /// Cells (polygons in 2D).
    pub polygons: usize,
    /// Unknowns.
    pub free_dofs: usize,
    /// Dirichlet degrees of freedom.
    pub prescribed_dofs: usize,
}

/// One contact pair as modelled.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct PairSummary {
    /// The law with its parameters ([`ContactLaw::describe`](crate::ContactLaw::describe)).
    pub law: String,
    /// The law's name ("frictionless", "tresca", "coulomb", ...).
    pub law_name: String,
    /// Which parts face what ("body 'disc' part 'arc' against body 'block' part 'top'").
    pub description: String,
    /// True when the counterpart is a rigid obstacle (nothing meshed for it).
    pub obstacle: bool,
    /// The pair's interface nodes in [`ContactResult::nodes`].
    pub nodes: Range<usize>,
    /// Vertices inserted by the pair's interface node insertion (both sides).
    pub inserted_nodes: usize,
}

/// What was built for the solve: only what the problem requires.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct ModelSummary {
    /// The contact solver.
    pub solver: &'static str,
    /// The bodies.
    pub bodies: Vec<BodySummary>,
    /// The contact pairs.
    pub pairs: Vec<PairSummary>,
    /// Normal constraint rows (one per interface node).
    pub normal_rows: usize,
    /// Tangential rows (`D - 1` per interface node; zero when no pair carries friction).
    pub tangential_rows: usize,
    /// Vertices inserted by the interface node insertions (all pairs, both sides).
    pub inserted_nodes: usize,
    /// Wall-clock time of the whole call (the stages are in [`ContactResult::work`]).
    #[cfg_attr(feature = "serde", serde(serialize_with = "crate::seconds"))]
    pub total_time: Duration,
}

/// How the fixed point of Tresca problems (Coulomb) went.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct FixedPointReport {
    /// Tresca solves after the initial one.
    pub steps: usize,
    /// The last relative change of the normal forces.
    pub residual: f64,
    /// The stopping tolerance used: the larger of the laws' [`FixedPointSettings::tolerance`]
    /// and the inner solver's force accuracy.
    ///
    /// [`FixedPointSettings::tolerance`]: crate::FixedPointSettings::tolerance
    pub tolerance: f64,
    /// The relative change at every step.
    pub history: Vec<f64>,
    /// Solver iterations summed over all solves.
    pub solver_iterations: usize,
    /// Nodal friction bounds of the last Tresca step.
    pub final_bounds: Vec<f64>,
}

/// The result of a contact solve.
#[derive(Debug, Clone)]
pub struct ContactResult<const D: usize = 2> {
    /// The bodies, in the order of the problem.
    pub bodies: Vec<BodyResult<D>>,
    /// The interface nodes of every pair, pair after pair, each pair's ordered along the
    /// contact part of its body A (2D).
    pub nodes: Vec<InterfaceNode<D>>,
    /// The report of the (last) contact solve.
    pub report: SolveReport,
    /// Laws with a fixed point (Coulomb): its report.
    pub fixed_point: Option<FixedPointReport>,
    /// What was modelled.
    pub model: ModelSummary,
    /// What the call computed: assemblies (when it built the discretisation), symbolic
    /// analyses, numeric factorisations, triangular solves, and the time of each stage.
    pub work: WorkCounters,
    /// What the user should know about this converged answer, each once: the solver's
    /// warnings (also in [`SolveReport::warnings`]) and those about the model (elements far
    /// outside A1, a contact zone cut short by a limit of the interface, a pair with no node
    /// in contact, a normal force concentrated on one node, a large penetration, an initial
    /// overlap, an effectively tied friction bound). A correct, well-resolved answer has none.
    pub warnings: Vec<Warning>,
}

impl<const D: usize> ContactResult<D> {
    pub(crate) fn new(
        bodies: Vec<BodyResult<D>>,
        nodes: Vec<InterfaceNode<D>>,
        report: SolveReport,
        fixed_point: Option<FixedPointReport>,
        model: ModelSummary,
    ) -> Self {
        Self {
            bodies,
            nodes,
            report,
            fixed_point,
            model,
            work: WorkCounters::default(),
            warnings: Vec::new(),
        }
    }

    /// The interface nodes of pair `pair`.
    pub fn pair_nodes(&self, pair: usize) -> &[InterfaceNode<D>] {
        self.model
            .pairs
            .get(pair)
            .map_or(&[][..], |p| &self.nodes[p.nodes.clone()])
    }

    /// Sum of the nodal contact forces `sum lambda_N` over every pair (= `-int sigma_nu` in
    /// the limit).
    pub fn normal_resultant(&self) -> f64 {
        self.nodes.iter().map(|n| n.normal_force).sum()
    }

    /// Sum of the nodal friction forces on the bodies A.
    pub fn friction_resultant(&self) -> VectorD<D> {
        self.nodes
            .iter()
            .fold(VectorD::zeros(), |acc, n| acc + n.friction_force)
    }

    /// The total contact force exerted on body `body` by every pair it belongs to
    /// (`sum (-lambda_N nu + t)` over its nodes as body A, the opposite as body B).
    pub fn force_on_body(&self, body: usize) -> VectorD<D> {
        self.nodes.iter().fold(VectorD::zeros(), |acc, n| {
            let on_a = n.friction_force - n.normal * n.normal_force;
            if n.body_a == body {
                acc + on_a
            } else if n.body_b == Some(body) {
                acc - on_a
            } else {
                acc
            }
        })
    }

    /// The total contact force exerted on body A of the first pair.
    pub fn force_on_body_a(&self) -> VectorD<D> {
        self.nodes
            .first()
            .map_or(VectorD::zeros(), |n| self.force_on_body(n.body_a))
    }

    /// The number of nodes in each state.
    pub fn status_counts(&self) -> StatusCounts {
        StatusCounts::of(self.nodes.iter().map(|n| n.status))
    }
}

impl ContactResult<2> {
    /// Sum of the nodal friction forces on the bodies A along their tangents
    /// (`= int sigma_1tau ds`).
    pub fn tangential_resultant(&self) -> f64 {
        self.nodes.iter().map(InterfaceNode::friction_t).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_name_per_state() {
        let tol = 1e-9;
        // Frictionless: contact or open, never stick or slip.
        assert_eq!(classify(1.0, 0.0, None, tol), NodeStatus::Contact);
        assert_eq!(classify(1e-12, 0.0, None, tol), NodeStatus::Open);
        // With friction: stick below the bound, slip at it.
        assert_eq!(classify(1.0, 0.1, Some(0.3), tol), NodeStatus::Stick);
        assert_eq!(classify(1.0, 0.3, Some(0.3), tol), NodeStatus::Slip);
        assert_eq!(classify(1.0, -0.3, Some(0.3), tol), NodeStatus::Slip);
        // A Tresca node without pressure but with friction is not open.
        assert_eq!(classify(0.0, 0.1, Some(0.3), tol), NodeStatus::Stick);
        assert_eq!(classify(0.0, 0.3, Some(0.3), tol), NodeStatus::Slip);
        // Neither force: open, whatever the law.
        assert_eq!(classify(0.0, 0.0, Some(0.3), tol), NodeStatus::Open);
        let names: Vec<&str> = [
            NodeStatus::Open,
            NodeStatus::Contact,
            NodeStatus::Stick,
            NodeStatus::Slip,
        ]
        .iter()
        .map(|s| s.name())
        .collect();
        assert_eq!(names, ["open", "contact", "stick", "slip"]);
    }
}
