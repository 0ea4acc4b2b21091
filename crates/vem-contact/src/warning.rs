//! Warnings that travel with a converged answer: what its user should know about the model or
//! the solve although every check passed.

use vem_mesh::{PointD, VectorD};

use crate::Location;

/// Why a limit of the contact zone was reached (see [`Warning::ContactZoneAtLimit`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum ZoneLimit {
    /// A contact part ends there while its body's boundary goes on (no convex corner): the
    /// zone may extend beyond the part.
    EndOfPart,
    /// The nodes beyond were left unpaired: farther than the pairing limit `max_distance`
    /// from the other side, or their projection misses it. The zone may be clipped by the
    /// limit.
    PairingLimit,
}

impl ZoneLimit {
    fn describe(self) -> &'static str {
        match self {
            ZoneLimit::EndOfPart => "the end of the contact part, where the body goes on",
            ZoneLimit::PairingLimit => "the pairing limit (max_distance)",
        }
    }
}

/// Something a user should know about a result whose solve converged. Each names what and
/// where, with the figures that triggered it.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(tag = "kind", rename_all = "snake_case"))]
#[non_exhaustive]
pub enum Warning {
    /// The penalty is so large that the gradient of the penalised energy cannot be evaluated
    /// to the solver's tolerance (its round-off floor is above it); the answer passed the KKT
    /// check at the floor. A smaller penalty is as accurate and better conditioned.
    #[error(
        "{solver}: the penalty {penalty:.3e} (x {penalty_factor:.1e} the softest constrained stiffness) \
         is in its round-off regime: the gradient is known only to {noise_floor:.1e} relative, \
         above the tolerance {tolerance:.1e}"
    )]
    PenaltyRoundOff {
        /// The solver.
        solver: &'static str,
        /// The normal penalty.
        penalty: f64,
        /// The penalty divided by the constrained stiffness of the softest body
        /// ([`ContactSystem::softest_constrained_diagonal`](crate::ContactSystem::softest_constrained_diagonal)).
        penalty_factor: f64,
        /// The relative round-off floor of the gradient.
        noise_floor: f64,
        /// The requested relative gradient tolerance.
        tolerance: f64,
    },
    /// A friction bound exceeds every force of the problem by far: friction never reaches it,
    /// the interface is effectively tied (bonded) wherever it is in contact.
    #[error(
        "body '{body}' part '{part}': friction bound b = {bound:.3e} at {at} is {ratio:.1e} \
         times the largest force of the problem: the contact is effectively tied (no node can \
         slip)"
    )]
    EffectivelyTied {
        /// Body A of the pair.
        body: String,
        /// Its contact part.
        part: String,
        /// Position of the node in contact with the smallest bound.
        at: Location,
        /// Its nodal bound `b_i = l_i g_F(x_i)`.
        bound: f64,
        /// `b_i / F` with `F` the force scale of the answer.
        ratio: f64,
    },
    /// An element is far outside the shape-regularity assumption A1 where it matters: it is
    /// star-shaped only with respect to a ball of radius below `1e-3` of its diameter (the
    /// meshes of the generators and of Gmsh give 0.17 to 0.35), or it has an edge shorter
    /// than `1e-6` of its diameter (interface node insertion cuts edges only down to its
    /// `min_edge_fraction`, `1e-3` of the edge it cuts, and edges down to `7e-9` of the
    /// diameter were measured not to change the answer; an interior point solver lost
    /// accuracy on meshes made only of such cells). The error estimates do not hold for it.
    #[error(
        "body '{body}', element {element} at {at}: {} (gamma (A1) = {gamma:.3e}: shortest edge \
         / diameter {shortest_edge_ratio:.3e}, star radius / diameter {star_ratio:.3e}, \
         diameter {diameter:.3e}), far outside assumption A1",
        if *star_ratio < *shortest_edge_ratio { "a flat or non-star-shaped element" } else { "an edge far shorter than the element" }
    )]
    ElementShape {
        /// The body.
        body: String,
        /// The polygon index in the body's (enlarged) mesh.
        element: usize,
        /// The element's centroid.
        at: Location,
        /// Its gamma.
        gamma: f64,
        /// Shortest edge / diameter.
        shortest_edge_ratio: f64,
        /// Star radius / diameter.
        star_ratio: f64,
        /// Diameter.
        diameter: f64,
    },
    /// The contact zone reaches a limit of the modelled interface that is not a geometric
    /// end of the contact: the zone (and the pressure near it) may be clipped.
    #[error(
        "body '{body}' part '{part}': the contact zone reaches {} at the node {at} (normal \
         force {normal_force:.3e}): it may be clipped",
        limit.describe()
    )]
    ContactZoneAtLimit {
        /// Which limit.
        limit: ZoneLimit,
        /// The body whose part ends there (body A at the pairing limit).
        body: String,
        /// Its contact part.
        part: String,
        /// Position of the node in contact at the limit.
        at: Location,
        /// Its normal force.
        normal_force: f64,
    },
    /// No node of a contact pair is in contact: the bodies do not touch (or touch only
    /// beyond the modelled interface).
    #[error("{pair}: no node is in contact ({nodes} open); the smallest gap is {gap:.3e} at {at}")]
    NoContact {
        /// The pair ("body 'punch' part 'bottom' against body 'block' part 'top'").
        pair: String,
        /// Its interface nodes (all open).
        nodes: usize,
        /// The smallest gap of the answer, `h0 - [u]_nu`.
        gap: f64,
        /// Where.
        at: Location,
    },
    /// One node carries most of a pair's normal force: the contact zone is not resolved by
    /// the mesh (or a load concentrates there), and the pressure profile means little.
    #[error(
        "body '{body}' part '{part}': the node at {at} carries {:.0}% of the pair's normal \
         force ({active} nodes in contact): the contact zone is not resolved by the mesh \
         there; refine it",
        100.0 * fraction
    )]
    ConcentratedPressure {
        /// Body A of the pair.
        body: String,
        /// Its contact part.
        part: String,
        /// The node.
        at: Location,
        /// Its normal force over the pair's normal resultant.
        fraction: f64,
        /// Nodes of the pair in contact.
        active: usize,
    },
    /// The answer penetrates by a sizeable fraction of the problem's displacement scale (a
    /// penalty answer's consistency error, `O(1 / penalty)`): its displacements and stresses
    /// carry that error on top of the discretisation's.
    #[error(
        "body '{body}' part '{part}': the answer penetrates by {penetration:.3e} at {at}, \
         {ratio:.1e} of the displacement scale {displacement_scale:.3e} ({solver}); a larger \
         penalty reduces it in proportion"
    )]
    Penetration {
        /// The solver.
        solver: &'static str,
        /// Body A of the pair.
        body: String,
        /// Its contact part.
        part: String,
        /// The node of the largest penetration.
        at: Location,
        /// `[u]_nu - h0 > 0` there.
        penetration: f64,
        /// The displacement scale `U` of the acceptance test ([`KktScales`](crate::KktScales)).
        displacement_scale: f64,
        /// `penetration / U`.
        ratio: f64,
    },
    /// The two sides overlap before any load: some initial gaps are negative (an
    /// interference fit, solved as the sides pressed apart; or a contact part that faces away
    /// from its counterpart, whose gaps are measured through the body).
    #[error(
        "initial overlap: {nodes} of {total} interface nodes have a negative initial gap, down \
         to {gap:.3e} at {at} (outward normal {normal}); solved as an \
         interference fit; if the contact part faces away from its counterpart, choose the \
         part that faces it"
    )]
    InitialOverlap {
        /// Nodes with a negative initial gap.
        nodes: usize,
        /// All interface nodes.
        total: usize,
        /// The most negative initial gap.
        gap: f64,
        /// Position of its node.
        at: Location,
        /// The contact normal at that node.
        normal: Location,
    },
    /// The Coulomb fixed point stopped at the inner solver's force accuracy, above the
    /// requested tolerance: the friction bounds are settled only to that accuracy.
    #[error(
        "Coulomb fixed point stopped at the force accuracy {force_accuracy:.1e} of {solver}, \
         above the requested tolerance {tolerance:.1e} (last change {change:.1e})"
    )]
    FixedPointAtForceFloor {
        /// The inner solver.
        solver: &'static str,
        /// Its force accuracy.
        force_accuracy: f64,
        /// The requested fixed-point tolerance.
        tolerance: f64,
        /// The last relative change of the normal forces.
        change: f64,
    },
}

impl Warning {
    /// [`Warning::InitialOverlap`] of the interface nodes `(position, normal, initial gap)`, if
    /// any initial gap is negative.
    ///
    /// ```
    /// use vem_contact::{Location, Warning};
    /// use vem_mesh::{Point, Vector};
    /// let up = Vector::new(0.0, 1.0);
    /// let nodes = [(Point::new(0.0, 0.0), up, 0.1), (Point::new(1.0, 0.0), up, -0.2)];
    /// let Some(Warning::InitialOverlap { nodes, total, gap, at, .. }) = Warning::initial_overlap(nodes) else {
    ///     panic!("an overlap")
    /// };
    /// assert_eq!((nodes, total, gap, at), (1, 2, -0.2, Location(vec![1.0, 0.0])));
    /// assert!(Warning::initial_overlap([(Point::new(0.0, 0.0), up, 0.0)]).is_none());
    /// ```
    pub fn initial_overlap<const D: usize>(
        nodes: impl IntoIterator<Item = (PointD<D>, VectorD<D>, f64)>,
    ) -> Option<Self> {
        let mut total = 0;
        let mut count = 0;
        let mut deepest: Option<(f64, PointD<D>, VectorD<D>)> = None;
        for (position, normal, gap) in nodes {
            total += 1;
            if gap < 0.0 {
                count += 1;
                if deepest.is_none_or(|(g, _, _)| gap < g) {
                    deepest = Some((gap, position, normal));
                }
            }
        }
        deepest.map(|(gap, position, normal)| Warning::InitialOverlap {
            nodes: count,
            total,
            gap,
            at: Location::of(&position),
            normal: Location::of_vector(&normal),
        })
    }
}
