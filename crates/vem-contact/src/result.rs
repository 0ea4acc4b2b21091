//! What a contact solve returns: per-body solutions, per-node interface results, resultants,
//! the solver's report and a summary of what was modelled.

use std::ops::Range;
use std::sync::Arc;
use std::time::Duration;

use nalgebra::SMatrix;
use vem_elastic::{AssembledSystem, ElasticBody, Solution};
use vem_mesh::{Point, PointD, Vector, VectorD};

use crate::{frame, SolveReport, Warning, WorkCounters};

/// The contact state of an interface node.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum NodeStatus {
    /// No contact force: the node is (or may be) separated.
    Open,
    /// In contact, friction force strictly below its bound: no slip.
    Stick,
    /// In contact and sliding: frictionless contact, or friction force at its bound.
    Slip,
}

impl NodeStatus {
    /// Lower-case name ("open", "stick", "slip").
    pub fn name(self) -> &'static str {
        match self {
            NodeStatus::Open => "open",
            NodeStatus::Stick => "stick",
            NodeStatus::Slip => "slip",
        }
    }
}

/// Classifies a node from its forces: open when the normal force is at most `force_tolerance`;
/// with friction, stick when the magnitude of the friction force is below its bound by more
/// than `force_tolerance`, else slip; frictionless contact nodes slide freely (slip).
pub(crate) fn classify(
    normal_force: f64,
    force_tolerance: f64,
    friction_force: f64,
    friction_bound: Option<f64>,
    has_friction: bool,
) -> NodeStatus {
    if normal_force <= force_tolerance {
        return NodeStatus::Open;
    }
    match (has_friction, friction_bound) {
        (true, Some(bound)) if friction_force.abs() < bound - force_tolerance => NodeStatus::Stick,
        _ => NodeStatus::Slip,
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
    /// The consistent contact pressure, approximating `-sigma_nu`: in 2D the node's value of
    /// the L2 projection of the nodal normal forces onto the continuous piecewise-linear
    /// functions on the interface spanned by the original (not inserted) nodes of the side
    /// with fewer of them, B on a tie, every node against an obstacle
    /// ([`consistent_traction`]); in 3D the nodal pressure.
    pub consistent_pressure: f64,
    /// Nodal friction force on body A (tangential, `= sigma_1tau l_x`); it opposes the slip.
    pub friction_force: VectorD<D>,
    /// The consistent friction traction, approximating `sigma_1tau` (as for
    /// `consistent_pressure`).
    pub consistent_friction_traction: VectorD<D>,
    /// The slip: the tangential part of `u_A - u_B` (zero for frictionless laws: not
    /// modelled).
    pub slip: VectorD<D>,
    /// Open, stick or slip.
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

/// The L2 projection of nodal forces onto continuous piecewise-linear functions on the
/// polyline through `positions` (consecutive positions joined by straight edges).
///
/// The functions are the hats of the nodes marked in `support` (the first and the last node
/// are always in it), linear in arc length between them. With `s_i` the arc length of node
/// `i` and `phi_k` the hat of support node `k`, the values `p_k` at the support nodes solve
///
/// ```text
/// sum_l M_kl p_l = sum_i forces_i phi_k(s_i),    M_kl = int phi_k phi_l ds
/// ```
///
/// (`M` the consistent mass matrix of the support, tridiagonal: `(L_{k-1} + L_k)/3` on the
/// diagonal, `L_k/6` beside it, `L_k` the arc length between support nodes `k` and `k+1`;
/// solved by the Thomas algorithm, `M` being symmetric positive definite and diagonally
/// dominant), and the result is `p` at every node (interpolated between support nodes).
/// Forces `f_i = sum_j M^h_ij p(s_j)` of a linear traction `p` with the consistent mass
/// matrix `M^h` of all nodes are reproduced exactly, and so is a uniform traction with
/// forces `p0 l_i` (tributary lengths). With every node in `support` this is `M^h p = f`;
/// with fewer nodes (the nodes of the coarser side of a non-matching interface) the
/// node-to-node oscillation that forces show where the two sides' nodes nearly coincide is
/// averaged out. A polyline of fewer than two nodes, or of zero length, has no projection:
/// the forces divided by the `fallback` lengths are returned (0 where a length is 0).
pub fn consistent_traction(
    positions: &[Point],
    forces: &[f64],
    support: &[bool],
    fallback: &[f64],
) -> Vec<f64> {
    let raw = || {
        forces
            .iter()
            .zip(fallback)
            .map(|(f, l)| if *l > 0.0 { f / l } else { 0.0 })
            .collect::<Vec<f64>>()
    };
    let n = positions.len();
    if n < 2 || forces.len() != n || support.len() != n {
        return raw();
    }
    let mut arc = Vec::with_capacity(n);
    let mut s = 0.0;
    arc.push(0.0);
    for w in positions.windows(2) {
        s += (w[1] - w[0]).norm();
        arc.push(s);
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
    let m = nodes.len();
    if m < 2 || arc[n - 1].is_nan() || arc[n - 1] <= 0.0 {
        return raw();
    }
    // Right-hand side: every force distributed to the hats of its support interval.
    let mut rhs = vec![0.0; m];
    let mut k = 0;
    for i in 0..n {
        while k + 2 < m && arc[i] > arc[nodes[k + 1]] {
            k += 1;
        }
        let (s0, s1) = (arc[nodes[k]], arc[nodes[k + 1]]);
        let t = ((arc[i] - s0) / (s1 - s0)).clamp(0.0, 1.0);
        rhs[k] += (1.0 - t) * forces[i];
        rhs[k + 1] += t * forces[i];
    }
    let lengths: Vec<f64> = nodes.windows(2).map(|w| arc[w[1]] - arc[w[0]]).collect();
    // Thomas: forward elimination of the sub-diagonal, back substitution.
    let mut upper = vec![0.0; m];
    let (mut previous_upper, mut previous_value) = (0.0, 0.0);
    for k in 0..m {
        let before = if k > 0 { lengths[k - 1] } else { 0.0 };
        let after = if k + 1 < m { lengths[k] } else { 0.0 };
        let lower = before / 6.0;
        let pivot = (before + after) / 3.0 - lower * previous_upper;
        if pivot.is_nan() || pivot <= 0.0 {
            return raw();
        }
        upper[k] = after / 6.0 / pivot;
        rhs[k] = (rhs[k] - lower * previous_value) / pivot;
        previous_upper = upper[k];
        previous_value = rhs[k];
    }
    for k in (0..m - 1).rev() {
        rhs[k] -= upper[k] * rhs[k + 1];
    }
    // Values at every node.
    let mut values = Vec::with_capacity(n);
    let mut k = 0;
    for i in 0..n {
        while k + 2 < m && arc[i] > arc[nodes[k + 1]] {
            k += 1;
        }
        let (s0, s1) = (arc[nodes[k]], arc[nodes[k + 1]]);
        let t = ((arc[i] - s0) / (s1 - s0)).clamp(0.0, 1.0);
        values.push((1.0 - t) * rhs[k] + t * rhs[k + 1]);
    }
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
    /// What the user should know about this converged answer: the solver's warnings (also in
    /// [`SolveReport::warnings`]) and those about the model (elements far outside A1, a
    /// contact zone at a limit of the interface, an effectively tied friction bound).
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

    /// Number of nodes with each status: (open, stick, slip).
    pub fn status_counts(&self) -> (usize, usize, usize) {
        self.nodes
            .iter()
            .fold((0, 0, 0), |(o, st, sl), n| match n.status {
                NodeStatus::Open => (o + 1, st, sl),
                NodeStatus::Stick => (o, st + 1, sl),
                NodeStatus::Slip => (o, st, sl + 1),
            })
    }
}

impl ContactResult<2> {
    /// Sum of the nodal friction forces on the bodies A along their tangents
    /// (`= int sigma_1tau ds`).
    pub fn tangential_resultant(&self) -> f64 {
        self.nodes.iter().map(InterfaceNode::friction_t).sum()
    }
}
