//! A posteriori error estimation of a planar contact problem: the elastic residual estimator
//! of every body ([`vem_elastic::estimate`]) completed by the contact terms on the interface
//! (after Wohlmuth 2007, two bodies on non-matching meshes).
//!
//! On the contact edges (the edges of the pairs' contact parts on the enlarged meshes, where
//! the elastic estimator leaves the boundary term out) two terms are added to the cell of the
//! edge:
//!
//! ```text
//!   traction:         w h_e || t_h - sigma_E n_e ||_e^2
//!   complementarity:  int_e  p_h (h0 - [u_h]_nu)_+  ds      (half to each side's cell)
//!   friction:         | int_e  b_h |s_h| + t_h,tau s_h  ds |  (half to each side's cell)
//! ```
//!
//! The traction term measures the whole traction, normal and tangential: with friction `t_h`
//! holds the consistent friction traction, so the mismatch of the projected stress's
//! tangential part `tau . sigma_E n_e` against it is in the same term, on both sides. The
//! friction term is the tangential counterpart of the complementarity term: `b_h` is the
//! friction bound per unit length (Tresca `g_F`, Coulomb `F p`; the nodal bound over the
//! tributary length), `t_h,tau` the consistent friction traction on body A along the tangent,
//! `s_h = [u_h]_tau` the slip, all linear between the interface nodes. The discrete friction
//! law makes `t_h,tau s_h = -b_h |s_h|` at every node (the traction opposes the slip and is at
//! its bound where the body slips; the slip is zero where it sticks), so the integrand vanishes
//! at the nodes; it measures where a stick zone ends inside an edge or where the slip changes
//! its direction. It vanishes on uniform stick and uniform slip (the patch tests PTC2, PTC3).
//!
//! `t_h` is the consistent contact traction of the solve, piecewise linear between the
//! interface nodes: on body A `t_h = -p_h nu + t_f` (`p_h` the consistent pressure
//! [`InterfaceNode::consistent_pressure`], `t_f` the consistent friction traction), on body B
//! its opposite; a contact edge beyond the paired range carries `t_h = 0`. `sigma_E n_e` is the
//! traction of the projected stress of the edge's cell (what the elastic estimator's boundary
//! term measures against a prescribed traction). The complementarity term integrates the
//! product of the interpolated pressure and gap `h0 - [u_h]_nu` (both linear between nodes):
//! it is zero at the nodes, where the discrete complementarity holds, and measures where a
//! contact zone ends inside an edge. `w` is the energy weight of the elastic estimator; the
//! complementarity term is an energy already. The integrals are 3-point Gauss rules (exact
//! for these quadratics).

use std::collections::HashMap;

use rayon::prelude::*;

use vem_elastic::{CellIndicator, ElasticBody, ElasticEstimate};
use vem_mesh::{geometry, Mesh, Vector};
use vem_space::quadrature::GaussLegendre;

use crate::{ContactError, ContactProblem, ContactResult, Counterpart, InterfaceNode};

/// The estimate of a planar contact problem.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactEstimate {
    /// Per body (order of the problem's bodies), the elastic estimate with the contact terms
    /// in [`vem_elastic::CellIndicator::contact`].
    pub bodies: Vec<ElasticEstimate>,
    /// The sum over the contact edges of the squared traction terms.
    pub traction: f64,
    /// The sum of the complementarity terms.
    pub complementarity: f64,
    /// The sum of the friction complementarity terms (zero without friction).
    pub friction: f64,
}

impl ContactEstimate {
    /// `eta = (sum over bodies and cells of eta_E^2)^(1/2)`.
    pub fn total(&self) -> f64 {
        self.bodies
            .iter()
            .map(|b| b.sum().squared())
            .sum::<f64>()
            .sqrt()
    }

    /// The squared parts summed over the cells of all bodies (`eta^2` is their sum).
    pub fn sum(&self) -> CellIndicator {
        self.bodies.iter().map(ElasticEstimate::sum).sum()
    }

    /// `eta_E` of every cell of every body (order of the problem's bodies): the cell field to
    /// mark and to write out.
    pub fn indicators(&self) -> Vec<Vec<f64>> {
        self.bodies
            .iter()
            .map(ElasticEstimate::indicators)
            .collect()
    }
}

/// The estimate of the solution `result` of `problem` (see the module docs).
///
/// # Errors
/// A result whose bodies do not match the problem's, any error of
/// [`ElasticBody::estimate`].
pub fn estimate(
    problem: &ContactProblem,
    result: &ContactResult,
) -> Result<ContactEstimate, ContactError> {
    let solved: Vec<(&ElasticBody, &[f64])> = result
        .bodies
        .iter()
        .map(|r| (&r.body, r.solution.displacement()))
        .collect();
    estimate_of(problem, &solved, &result.nodes)
}

/// [`estimate`] of a solution given by its parts: per body of `problem` (in its order) the
/// body on the mesh it was solved on with its displacement (full, in the numbering of
/// [`ElasticBody::dofs`]), and the interface nodes of the solve (a front end that keeps the
/// bodies of a [`ContactResult`] elsewhere passes them so).
///
/// # Errors
/// As [`estimate`].
pub fn estimate_of(
    problem: &ContactProblem,
    solved: &[(&ElasticBody, &[f64])],
    interface: &[InterfaceNode],
) -> Result<ContactEstimate, ContactError> {
    if solved.len() != problem.bodies().len() {
        return Err(ContactError::InvalidSetting {
            reason: format!(
                "the result has {} bodies, the problem {}",
                solved.len(),
                problem.bodies().len()
            ),
        });
    }
    // The contact parts of each body.
    let mut contact_parts: Vec<Vec<&str>> = vec![Vec::new(); solved.len()];
    for pair in problem.pairs() {
        contact_parts[pair.body()].push(pair.part());
        if let Counterpart::Body { body, part } = pair.counterpart() {
            contact_parts[*body].push(part);
        }
    }
    // The bodies side by side (each estimate is parallel over its cells; side by side their
    // sequential stretches, the edges' terms, overlap), the first failing body's error
    // reported.
    let mut bodies = solved
        .par_iter()
        .zip(&contact_parts)
        .map(|((body, displacement), parts)| body.estimate(displacement, parts))
        .collect::<Vec<_>>()
        .into_iter()
        .collect::<Result<Vec<_>, _>>()?;
    let gauss = GaussLegendre::try_new(3).expect("3 Gauss points exist");
    let (mut traction_total, mut complementarity_total, mut friction_total) = (0.0, 0.0, 0.0);
    for (p, pair) in problem.pairs().iter().enumerate() {
        let nodes: Vec<&InterfaceNode> = interface.iter().filter(|n| n.pair == p).collect();
        let mut sides: Vec<(usize, &str, f64)> = vec![(pair.body(), pair.part(), 1.0)];
        if let Counterpart::Body { body, part } = pair.counterpart() {
            sides.push((*body, part, -1.0));
        }
        for &(b, part, sign) in &sides {
            let body: &ElasticBody = solved[b].0;
            let mesh = body.mesh();
            // The traction t_h on this side at each of its interface vertices.
            let mut traction: HashMap<usize, Vector> = HashMap::new();
            for node in &nodes {
                let vertex = if sign > 0.0 {
                    Some(node.vertex_a)
                } else {
                    node.vertex_b
                };
                let t_a =
                    -node.consistent_pressure * node.normal + node.consistent_friction_traction;
                if let Some(v) = vertex {
                    traction.insert(v, sign * t_a);
                }
            }
            let estimate = &mut bodies[b];
            let part_edges = &mesh.part(part).map_err(|source| ContactError::Mesh {
                context: format!("contact estimate of body '{}'", body.name()),
                source,
            })?;
            for &e in &part_edges.edges {
                let edge = mesh.edge(e);
                let [va, vb] = edge.vertices;
                let (pa, pb) = (mesh.vertex(va), mesh.vertex(vb));
                let length = (pb - pa).norm();
                let sigma_n = estimate.stresses[edge.left] * geometry::outward_normal(pa, pb);
                let (ta, tb) = (
                    traction.get(&va).copied().unwrap_or_else(Vector::zeros),
                    traction.get(&vb).copied().unwrap_or_else(Vector::zeros),
                );
                let integral: f64 = gauss
                    .nodes()
                    .iter()
                    .zip(gauss.weights())
                    .map(|(&s, &w)| {
                        let t = ta.lerp(&tb, 0.5 * (s + 1.0));
                        0.5 * length * w * (t - sigma_n).norm_squared()
                    })
                    .sum();
                let term = estimate.weight * length * integral;
                estimate.cells[edge.left].contact += term;
                traction_total += term;
            }
        }
        // Complementarity along consecutive nodes (ordered along side A).
        let edge_cell = |mesh: &Mesh, part: &str, a: usize, b: usize| -> Option<usize> {
            mesh.part(part).ok()?.edges.iter().find_map(|&e| {
                let edge = mesh.edge(e);
                let [p, q] = edge.vertices;
                ((p == a && q == b) || (p == b && q == a)).then_some(edge.left)
            })
        };
        for w in nodes.windows(2) {
            let (n0, n1) = (w[0], w[1]);
            let length = (n1.position - n0.position).norm();
            let (g0, g1) = (
                n0.initial_gap - n0.normal_jump,
                n1.initial_gap - n1.normal_jump,
            );
            let (p0, p1) = (n0.consistent_pressure, n1.consistent_pressure);
            // The friction bound per unit length, the consistent friction traction and the
            // slip along each node's tangent (all zero without friction).
            let bound = |n: &InterfaceNode| {
                if n.tributary_measure > 0.0 {
                    n.friction_bound / n.tributary_measure
                } else {
                    0.0
                }
            };
            let (b0, b1) = (bound(n0), bound(n1));
            let (t0, t1) = (n0.consistent_friction_t(), n1.consistent_friction_t());
            let (s0, s1) = (n0.slip_t(), n1.slip_t());
            let (normal, friction) = gauss.nodes().iter().zip(gauss.weights()).fold(
                (0.0, 0.0),
                |(normal, friction), (&s, &wt)| {
                    let t = 0.5 * (s + 1.0);
                    let lerp = |a: f64, b: f64| (1.0 - t) * a + t * b;
                    let g = lerp(g0, g1);
                    let slip = lerp(s0, s1);
                    (
                        normal + 0.5 * length * wt * lerp(p0, p1) * g.max(0.0),
                        friction
                            + 0.5 * length * wt * (lerp(b0, b1) * slip.abs() + lerp(t0, t1) * slip),
                    )
                },
            );
            let (normal, friction) = (normal.abs(), friction.abs());
            let term = normal + friction;
            if term == 0.0 {
                continue;
            }
            complementarity_total += normal;
            friction_total += friction;
            let cell_a = edge_cell(
                solved[n0.body_a].0.mesh(),
                pair.part(),
                n0.vertex_a,
                n1.vertex_a,
            );
            let cell_b = match (pair.counterpart(), n0.body_b, n0.vertex_b, n1.vertex_b) {
                (Counterpart::Body { part, .. }, Some(b), Some(v0), Some(v1)) => {
                    edge_cell(solved[b].0.mesh(), part, v0, v1).map(|c| (b, c))
                }
                _ => None,
            };
            match (cell_a, cell_b) {
                (Some(ca), Some((b, cb))) => {
                    bodies[n0.body_a].cells[ca].contact += 0.5 * term;
                    bodies[b].cells[cb].contact += 0.5 * term;
                }
                (Some(ca), None) => bodies[n0.body_a].cells[ca].contact += term,
                (None, Some((b, cb))) => bodies[b].cells[cb].contact += term,
                (None, None) => {}
            }
        }
    }
    Ok(ContactEstimate {
        bodies,
        traction: traction_total,
        complementarity: complementarity_total,
        friction: friction_total,
    })
}
