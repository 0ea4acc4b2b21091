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
//! ```
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

use vem_elastic::{ElasticBody, ElasticEstimate};
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
    if result.bodies.len() != problem.bodies().len() {
        return Err(ContactError::InvalidSetting {
            reason: format!(
                "the result has {} bodies, the problem {}",
                result.bodies.len(),
                problem.bodies().len()
            ),
        });
    }
    // The contact parts of each body.
    let mut contact_parts: Vec<Vec<&str>> = vec![Vec::new(); result.bodies.len()];
    for pair in problem.pairs() {
        contact_parts[pair.body()].push(pair.part());
        if let Counterpart::Body { body, part } = pair.counterpart() {
            contact_parts[*body].push(part);
        }
    }
    let mut bodies = result
        .bodies
        .iter()
        .zip(&contact_parts)
        .map(|(r, parts)| r.body.estimate(r.solution.displacement(), parts))
        .collect::<Result<Vec<_>, _>>()?;
    let gauss = GaussLegendre::try_new(3).expect("3 Gauss points exist");
    let (mut traction_total, mut complementarity_total) = (0.0, 0.0);
    for (p, pair) in problem.pairs().iter().enumerate() {
        let nodes: Vec<&InterfaceNode> = result.nodes.iter().filter(|n| n.pair == p).collect();
        let mut sides: Vec<(usize, &str, f64)> = vec![(pair.body(), pair.part(), 1.0)];
        if let Counterpart::Body { body, part } = pair.counterpart() {
            sides.push((*body, part, -1.0));
        }
        for &(b, part, sign) in &sides {
            let body: &ElasticBody = &result.bodies[b].body;
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
            let term: f64 = gauss
                .nodes()
                .iter()
                .zip(gauss.weights())
                .map(|(&s, &wt)| {
                    let t = 0.5 * (s + 1.0);
                    let g = (1.0 - t) * g0 + t * g1;
                    let p = (1.0 - t) * p0 + t * p1;
                    0.5 * length * wt * p * g.max(0.0)
                })
                .sum::<f64>()
                .abs();
            if term == 0.0 {
                continue;
            }
            complementarity_total += term;
            let cell_a = edge_cell(
                result.bodies[n0.body_a].body.mesh(),
                pair.part(),
                n0.vertex_a,
                n1.vertex_a,
            );
            let cell_b = match (pair.counterpart(), n0.body_b, n0.vertex_b, n1.vertex_b) {
                (Counterpart::Body { part, .. }, Some(b), Some(v0), Some(v1)) => {
                    edge_cell(result.bodies[b].body.mesh(), part, v0, v1).map(|c| (b, c))
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
    })
}
