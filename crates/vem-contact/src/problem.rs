//! The contact problem P1^h / P2^h of any number of bodies and contact pairs. Its
//! discretisation ([`ContactDiscretisation`], built once) hands out
//! [`ContactSystem`](crate::ContactSystem)s to the solvers.
//!
//! Discretisation:
//! 1. every pair of two bodies: the nodes of each contact side are inserted into the other
//!    side's boundary cells ([`vem_mesh::interface::insert_interface_nodes`] in 2D, the surface
//!    overlay [`vem_mesh::polyhedral::overlay::insert_surface_overlay`] in 3D), so the
//!    interface is node-to-node; a pair against a rigid obstacle: the nodes of the body's
//!    contact part, nothing meshed. The pairs are inserted one after the other;
//! 2. each body is assembled on its (enlarged) mesh with Dirichlet conditions eliminated; the
//!    unknowns are the free degrees of freedom of the bodies, one after the other;
//! 3. one normal row per interface node, `[u]_nu = (u_A - u_B) . nu` with `nu` pointing from A
//!    to B, the nodal normal of the side chosen by [`ContactNormal`] (for an obstacle:
//!    `u_A . nu`, `nu` into the obstacle), bounded by the total initial gap
//!    `h0 = geometric gap + imposed gap`; prescribed (Dirichlet) values move to the bound.
//!    Where some pair's law has friction, `D - 1` tangential rows per node
//!    `[u]_tau = (u_A - u_B) . tau_k` (the tangents of [`frame`](crate::frame)), with the nodal
//!    bounds of each pair's law (nodal quadrature of `j_h`; zero for a frictionless pair).

use std::sync::Arc;
use std::time::Instant;

use vem_elastic::ElasticBody;
use vem_mesh::interface::InterfaceOptions;
use vem_mesh::{PointD, VectorD};

use crate::result::ContactResult;
use crate::{
    ContactDiscretisation, ContactError, ContactLaw, ContactSolver, RigidObstacle, ScalarField,
};

/// Which side's geometry gives the contact normal `nu` at a node pair of two bodies (the
/// tangents are those of [`frame`](crate::frame), so the tangential rows follow the choice).
/// Nodal normals are the normalised mean of the outward normals of the interface facets next
/// to the node, on each side's enlarged mesh. Against a rigid obstacle the normal is
/// always the obstacle's own and this choice does not apply.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ContactNormal {
    /// The outward nodal normal of body A.
    BodyA,
    /// Minus the outward nodal normal of body B (the default): a curved body A pressed on a
    /// flat body B then carries forces along B's normal, so the forces of a frictionless
    /// answer are normal to the flat side and `sum lambda_N` is the load.
    #[default]
    BodyB,
    /// The normalised difference `n_A - n_B` of the two outward nodal normals (their
    /// bisector).
    Averaged,
}

impl ContactNormal {
    /// The name used in scenes and reports: `"body_a"`, `"body_b"`, `"averaged"`.
    pub fn name(self) -> &'static str {
        match self {
            ContactNormal::BodyA => "body_a",
            ContactNormal::BodyB => "body_b",
            ContactNormal::Averaged => "averaged",
        }
    }

    /// Every choice, in the order of the enum.
    pub const ALL: [ContactNormal; 3] = [
        ContactNormal::BodyA,
        ContactNormal::BodyB,
        ContactNormal::Averaged,
    ];

    /// The unit normal `nu` at a pair from the outward unit nodal normals `n_a` and `n_b` of
    /// the two sides (`n_b` opposes `n_a` where the sides fit).
    pub fn combine<const D: usize>(self, n_a: VectorD<D>, n_b: VectorD<D>) -> VectorD<D> {
        match self {
            ContactNormal::BodyA => n_a,
            ContactNormal::BodyB => -n_b,
            ContactNormal::Averaged => {
                let sum: VectorD<D> = n_a - n_b;
                let norm = sum.norm();
                if norm > 0.0 {
                    sum / norm
                } else {
                    n_a
                }
            }
        }
    }
}

/// What body A of a contact pair is in contact with.
#[derive(Debug, Clone)]
pub enum Counterpart<const D: usize = 2> {
    /// Another elastic body of the problem and its contact part.
    Body {
        /// Index of the body in the problem.
        body: usize,
        /// Its boundary part facing body A.
        part: String,
    },
    /// A rigid obstacle: a gap function, nothing meshed or assembled.
    Obstacle(Arc<dyn RigidObstacle<D>>),
}

/// One contact pair: body A's contact part, what it faces, the law on the interface, an
/// optional extra initial gap `h0(x)` (added to the geometric gap), interface options and the
/// normal choice.
#[derive(Clone)]
pub struct ContactPair<const D: usize = 2> {
    body: usize,
    part: String,
    counterpart: Counterpart<D>,
    law: Arc<dyn ContactLaw<D>>,
    imposed_gap: Option<ScalarField<D>>,
    interface_options: InterfaceOptions,
    normal: ContactNormal,
}

impl<const D: usize> std::fmt::Debug for ContactPair<D> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ContactPair")
            .field("body", &self.body)
            .field("part", &self.part)
            .field("counterpart", &self.counterpart)
            .field("law", &self.law.describe())
            .field("imposed_gap", &self.imposed_gap.is_some())
            .field("normal", &self.normal)
            .finish()
    }
}

impl<const D: usize> ContactPair<D> {
    /// Part `part_a` of body `body_a` against part `part_b` of body `body_b` (indices in the
    /// problem's bodies), with the law `law`.
    pub fn between(
        body_a: usize,
        part_a: impl Into<String>,
        body_b: usize,
        part_b: impl Into<String>,
        law: impl ContactLaw<D> + 'static,
    ) -> Self {
        Self::new(
            body_a,
            part_a.into(),
            Counterpart::Body {
                body: body_b,
                part: part_b.into(),
            },
            Arc::new(law),
        )
    }

    /// Part `part` of body `body` against the rigid obstacle `obstacle`, with the law `law`.
    pub fn against(
        body: usize,
        part: impl Into<String>,
        obstacle: impl RigidObstacle<D> + 'static,
        law: impl ContactLaw<D> + 'static,
    ) -> Self {
        Self::new(
            body,
            part.into(),
            Counterpart::Obstacle(Arc::new(obstacle)),
            Arc::new(law),
        )
    }

    /// A pair from its parts, the law shared.
    pub fn new(
        body: usize,
        part: String,
        counterpart: Counterpart<D>,
        law: Arc<dyn ContactLaw<D>>,
    ) -> Self {
        Self {
            body,
            part,
            counterpart,
            law,
            imposed_gap: None,
            interface_options: InterfaceOptions::default(),
            normal: ContactNormal::default(),
        }
    }

    /// Adds a user initial gap `h0(x)` to the geometric gap (e.g. the paper's setting, where
    /// the two contact parts coincide and the physical gap is a given function).
    pub fn with_imposed_gap(
        mut self,
        gap: impl Fn(PointD<D>) -> f64 + Send + Sync + 'static,
    ) -> Self {
        self.imposed_gap = Some(Arc::new(gap));
        self
    }

    /// Sets the interface node insertion options.
    pub fn with_interface_options(mut self, options: InterfaceOptions) -> Self {
        self.interface_options = options;
        self
    }

    /// Sets which side gives the contact normal ([`ContactNormal`]; ignored against an
    /// obstacle, whose own normal is used).
    pub fn with_normal(mut self, normal: ContactNormal) -> Self {
        self.normal = normal;
        self
    }

    /// Replaces the law.
    pub fn with_law(mut self, law: Arc<dyn ContactLaw<D>>) -> Self {
        self.law = law;
        self
    }

    /// Body A (index in the problem's bodies).
    pub fn body(&self) -> usize {
        self.body
    }

    /// Body A's contact part.
    pub fn part(&self) -> &str {
        &self.part
    }

    /// What body A is in contact with.
    pub fn counterpart(&self) -> &Counterpart<D> {
        &self.counterpart
    }

    /// The contact law.
    pub fn law(&self) -> &Arc<dyn ContactLaw<D>> {
        &self.law
    }

    /// The imposed gap added to the geometric gap, if any.
    pub fn imposed_gap(&self) -> Option<&ScalarField<D>> {
        self.imposed_gap.as_ref()
    }

    /// The interface node insertion options.
    pub fn interface_options(&self) -> &InterfaceOptions {
        &self.interface_options
    }

    /// Which side gives the contact normal.
    pub fn normal(&self) -> ContactNormal {
        self.normal
    }
}

/// A contact problem: elastic bodies in `R^D` and the contact pairs between them (or against
/// rigid obstacles). The solvers treat every pair together: one system, one answer.
///
/// # Example: two blocks on non-matching meshes, pressed together
///
/// The upper block (3 x 3 quads) is pushed down by 0.03 on its top, the lower one (5 x 5
/// quads) clamped at its bottom; the interface nodes of each side are inserted into the other.
/// Laterally free blocks of equal material are compressed uniformly: the strain is
/// -0.03 / 2 and, in plane strain with `sigma_xx = 0`, the contact pressure is
/// `E' 0.015` with `E' = 4 mu (lambda + mu) / (lambda + 2 mu) = 3`, at every node.
///
/// ```
/// use std::sync::Arc;
/// use vem_contact::{ContactProblem, ExactSolver, Frictionless};
/// use vem_elastic::{Component, Dirichlet, ElasticBody, Material, Plane};
/// use vem_mesh::generators::{structured_quads, Rectangle};
/// use vem_mesh::{Point, Vector};
/// use vem_space::LowestOrderVem;
///
/// let material = Material::from_lame(2.0, 1.0, Plane::Strain)?;
/// let element = Arc::new(LowestOrderVem::default());
/// let upper_mesh = structured_quads(&Rectangle::new(Point::new(0.0, 0.0), Point::new(1.0, 1.0)), 3, 3)?;
/// let lower_mesh = structured_quads(&Rectangle::new(Point::new(0.0, -1.0), Point::new(1.0, 0.0)), 5, 5)?;
/// let upper = ElasticBody::builder("upper", upper_mesh, material, element.clone())
///     .dirichlet(Dirichlet::prescribed("top", Component::Y, |_| Vector::new(0.0, -0.03)))
///     .dirichlet(Dirichlet::prescribed("left", Component::X, |_| Vector::zeros()))
///     .build()?;
/// let lower = ElasticBody::builder("lower", lower_mesh, material, element)
///     .dirichlet(Dirichlet::prescribed("bottom", Component::Y, |_| Vector::zeros()))
///     .dirichlet(Dirichlet::prescribed("left", Component::X, |_| Vector::zeros()))
///     .build()?;
/// let problem = ContactProblem::two_bodies(upper, "bottom", lower, "top", Frictionless);
/// let result = problem.solve(&mut ExactSolver::default())?;
/// assert_eq!(result.nodes.len(), 6 + 4 - 2); // x = i/3 and j/5: 8 distinct positions
/// for node in &result.nodes {
///     assert!((node.pressure - 3.0 * 0.015).abs() < 1e-7);
/// }
/// assert!((result.normal_resultant() - 0.045).abs() < 1e-8);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone, Debug)]
pub struct ContactProblem<const D: usize = 2> {
    bodies: Vec<ElasticBody<D>>,
    pairs: Vec<ContactPair<D>>,
}

impl<const D: usize> ContactProblem<D> {
    /// The bodies `bodies` without any contact pair yet ([`ContactProblem::with_pair`]).
    pub fn new(bodies: Vec<ElasticBody<D>>) -> Self {
        Self {
            bodies,
            pairs: Vec::new(),
        }
    }

    /// Adds a contact pair (its body indices are checked when the problem is discretised).
    pub fn with_pair(mut self, pair: ContactPair<D>) -> Self {
        self.pairs.push(pair);
        self
    }

    /// Two elastic bodies in contact on `part_a` of `body_a` and `part_b` of `body_b`; the
    /// normal `nu` points from A to B, taken from the side chosen by
    /// [`ContactProblem::with_normal`] (B's by default).
    pub fn two_bodies(
        body_a: ElasticBody<D>,
        part_a: impl Into<String>,
        body_b: ElasticBody<D>,
        part_b: impl Into<String>,
        law: impl ContactLaw<D> + 'static,
    ) -> Self {
        Self::new(vec![body_a, body_b]).with_pair(ContactPair::between(0, part_a, 1, part_b, law))
    }

    /// One elastic body against a rigid obstacle on its part `part`.
    pub fn against_obstacle(
        body: ElasticBody<D>,
        part: impl Into<String>,
        obstacle: impl RigidObstacle<D> + 'static,
        law: impl ContactLaw<D> + 'static,
    ) -> Self {
        Self::new(vec![body]).with_pair(ContactPair::against(0, part, obstacle, law))
    }

    /// Adds a user initial gap `h0(x)` to the geometric gap of the last pair added.
    pub fn with_imposed_gap(self, gap: impl Fn(PointD<D>) -> f64 + Send + Sync + 'static) -> Self {
        self.map_last(|pair| pair.with_imposed_gap(gap))
    }

    /// Sets the interface node insertion options of the last pair added.
    pub fn with_interface_options(self, options: InterfaceOptions) -> Self {
        self.map_last(|pair| pair.with_interface_options(options))
    }

    /// Sets which side gives the contact normal of the last pair added ([`ContactNormal`];
    /// ignored against an obstacle, whose own normal is used).
    pub fn with_normal(self, normal: ContactNormal) -> Self {
        self.map_last(|pair| pair.with_normal(normal))
    }

    fn map_last(mut self, f: impl FnOnce(ContactPair<D>) -> ContactPair<D>) -> Self {
        if let Some(last) = self.pairs.pop() {
            self.pairs.push(f(last));
        }
        self
    }

    /// The bodies, in the order given.
    pub fn bodies(&self) -> &[ElasticBody<D>] {
        &self.bodies
    }

    /// The contact pairs, in the order given.
    pub fn pairs(&self) -> &[ContactPair<D>] {
        &self.pairs
    }

    /// Takes the bodies and pairs apart.
    pub(crate) fn into_parts(self) -> (Vec<ElasticBody<D>>, Vec<ContactPair<D>>) {
        (self.bodies, self.pairs)
    }

    /// The discretisation of this problem: interface node insertion, assembly, constraint
    /// rows, built once; solve it as often as needed
    /// ([`ContactDiscretisation::solve`], [`ContactDiscretisation::solve_scaled`]).
    ///
    /// # Errors
    /// A pair naming a body that does not exist, a failed insertion, an invalid body on the
    /// enlarged mesh, an assembly failure, a law's data, Dirichlet data prescribing the slip
    /// of a contact node (friction).
    pub fn discretise(&self) -> Result<ContactDiscretisation<D>, ContactError> {
        ContactDiscretisation::try_new(self.clone())
    }

    /// As [`ContactProblem::discretise`], giving up the problem: the bodies on their original
    /// meshes are dropped once the interface nodes are inserted, before the assembly, which
    /// lowers the peak memory of the build by the original meshes (when nothing else holds
    /// them).
    ///
    /// # Errors
    /// As [`ContactProblem::discretise`].
    pub fn into_discretisation(self) -> Result<ContactDiscretisation<D>, ContactError> {
        ContactDiscretisation::try_new(self)
    }

    /// Discretises and solves the problem with `solver`: a thin driver over
    /// [`ContactProblem::discretise`] and [`ContactDiscretisation::solve`]. The result's
    /// [`work`](ContactResult::work) counts the build (insertion, assembly) and the solve.
    ///
    /// # Errors
    /// As [`ContactProblem::discretise`] and [`ContactDiscretisation::solve`].
    pub fn solve(&self, solver: &mut dyn ContactSolver) -> Result<ContactResult<D>, ContactError> {
        let start = Instant::now();
        let discretisation = self.discretise()?;
        let mut result = discretisation.solve(solver)?;
        let mut work = discretisation.work();
        work += result.work;
        result.work = work;
        result.model.total_time = start.elapsed();
        Ok(result)
    }
}
