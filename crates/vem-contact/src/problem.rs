//! The contact problem P1^h / P2^h: bodies, the contact pair, the law. Its discretisation
//! ([`ContactDiscretisation`], built once) hands out [`ContactSystem`](crate::ContactSystem)s
//! to the solvers.
//!
//! Discretisation:
//! 1. two bodies: the nodes of each contact side are inserted into the other side's boundary
//!    polygons ([`vem_mesh::interface::insert_interface_nodes`]), so the interface is
//!    node-to-node; a rigid obstacle: the nodes of the body's contact part, nothing meshed;
//! 2. each body is assembled on its (enlarged) mesh with Dirichlet conditions eliminated; the
//!    unknowns are the free degrees of freedom of body A followed by those of body B;
//! 3. one normal row per interface node, `[u]_nu = (u_A - u_B) . nu` with `nu` pointing from A
//!    to B, the nodal normal of the side chosen by [`ContactNormal`] (for an obstacle:
//!    `u_A . nu`, `nu` into the obstacle), bounded by the
//!    total initial gap `h0 = geometric gap + imposed gap`; prescribed (Dirichlet) values move
//!    to the bound. Tangential rows `[u]_1tau = (u_A - u_B) . tau`, `tau = (-nu_y, nu_x)`, are
//!    built only for Tresca and Coulomb, with nodal bounds `b = l_x g_F(x)` (nodal quadrature of
//!    `j_h`).

use std::sync::Arc;
use std::time::Instant;

use vem_elastic::ElasticBody;
use vem_mesh::interface::InterfaceOptions;
use vem_mesh::{Point, Vector};

use crate::result::ContactResult;
use crate::{ContactDiscretisation, ContactError, ContactSolver, Obstacle, SettingsError};

/// A scalar field of position (friction bound, imposed gap).
pub type ScalarField = Arc<dyn Fn(Point) -> f64 + Send + Sync>;

/// The friction bound `g_F` of Tresca's law: a constant or a function of position.
#[derive(Clone)]
pub enum FrictionBound {
    /// The same bound everywhere.
    Constant(f64),
    /// A bound depending on the position on the interface (evaluated at the nodes of body A).
    Field(ScalarField),
}

impl std::fmt::Debug for FrictionBound {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            FrictionBound::Constant(g) => write!(f, "Constant({g})"),
            FrictionBound::Field(_) => write!(f, "Field(..)"),
        }
    }
}

/// Settings of the Coulomb fixed point of Tresca problems; build them with
/// [`FixedPointSettings::builder`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FixedPointSettings {
    max_iterations: usize,
    tolerance: f64,
}

impl Default for FixedPointSettings {
    /// At most 50 Tresca solves, tolerance `1e-8`.
    fn default() -> Self {
        Self {
            max_iterations: 50,
            tolerance: 1e-8,
        }
    }
}

impl FixedPointSettings {
    /// A builder starting from the defaults.
    pub fn builder() -> FixedPointSettingsBuilder {
        FixedPointSettingsBuilder {
            settings: Self::default(),
        }
    }

    /// Largest number of Tresca solves.
    pub fn max_iterations(&self) -> usize {
        self.max_iterations
    }

    /// Stop when the largest change of a nodal normal force, relative to the largest normal
    /// force, falls below this, or below the force accuracy of the inner solver
    /// ([`ContactSolver::force_accuracy`], `1e-4` for the default interior-point
    /// [`ExactSolver`](crate::solver::ExactSolver), `0` for the penalty and active-set solvers),
    /// whichever is larger: changes below the inner accuracy are noise of the inner solves and
    /// the fixed point would stall there. The tolerance used is in
    /// [`FixedPointReport::tolerance`](crate::FixedPointReport::tolerance).
    pub fn tolerance(&self) -> f64 {
        self.tolerance
    }
}

/// Builder of [`FixedPointSettings`]; values are checked by
/// [`FixedPointSettingsBuilder::build`].
#[derive(Debug, Clone, Copy)]
pub struct FixedPointSettingsBuilder {
    settings: FixedPointSettings,
}

impl FixedPointSettingsBuilder {
    /// Largest number of Tresca solves, `>= 1`.
    pub fn max_iterations(mut self, value: usize) -> Self {
        self.settings.max_iterations = value;
        self
    }

    /// Relative change of the normal forces at which to stop, finite and `> 0`.
    pub fn tolerance(mut self, value: f64) -> Self {
        self.settings.tolerance = value;
        self
    }

    /// Validates the settings.
    ///
    /// # Errors
    /// [`SettingsError`] naming the first invalid setting.
    pub fn build(self) -> Result<FixedPointSettings, SettingsError> {
        let s = self.settings;
        SettingsError::at_least_one("max_iterations", s.max_iterations)?;
        SettingsError::positive("tolerance", s.tolerance)?;
        Ok(s)
    }
}

/// The contact law on the interface. The validated constructors [`ContactLaw::try_tresca`] and
/// [`ContactLaw::try_coulomb`] reject a negative or non-finite bound or coefficient at
/// construction; a law built from the variants directly is checked when it is discretised.
#[derive(Debug, Clone)]
pub enum ContactLaw {
    /// Frictionless (Signorini-type) contact, problem P1: no tangential rows are built.
    Frictionless,
    /// Tresca friction with bound `g_F`, problem P2.
    Tresca {
        /// The friction bound `g_F >= 0`.
        friction_bound: FrictionBound,
    },
    /// Coulomb friction `g_F = F |sigma_nu|`, by a fixed point of Tresca problems with the bound
    /// frozen at each step (the paper's remark).
    Coulomb {
        /// The friction coefficient `F >= 0`.
        coefficient: f64,
        /// Iterations and tolerance of the fixed point.
        fixed_point: FixedPointSettings,
    },
}

impl ContactLaw {
    /// Tresca with a constant bound `g_F`.
    ///
    /// # Errors
    /// [`SettingsError`] for a bound that is negative or not finite.
    pub fn try_tresca(friction_bound: f64) -> Result<Self, SettingsError> {
        SettingsError::non_negative("friction_bound", friction_bound)?;
        Ok(ContactLaw::Tresca {
            friction_bound: FrictionBound::Constant(friction_bound),
        })
    }

    /// Coulomb with friction coefficient `F` and default fixed-point settings.
    ///
    /// # Errors
    /// [`SettingsError`] for a coefficient that is negative or not finite.
    pub fn try_coulomb(coefficient: f64) -> Result<Self, SettingsError> {
        Self::try_coulomb_with(coefficient, FixedPointSettings::default())
    }

    /// Coulomb with friction coefficient `F` and the given fixed-point settings.
    ///
    /// # Errors
    /// [`SettingsError`] for a coefficient that is negative or not finite.
    pub fn try_coulomb_with(
        coefficient: f64,
        fixed_point: FixedPointSettings,
    ) -> Result<Self, SettingsError> {
        SettingsError::non_negative("coefficient", coefficient)?;
        Ok(ContactLaw::Coulomb {
            coefficient,
            fixed_point,
        })
    }

    /// True when the law needs tangential rows.
    pub fn has_friction(&self) -> bool {
        !matches!(self, ContactLaw::Frictionless)
    }

    /// A short name for reports.
    pub fn name(&self) -> &'static str {
        match self {
            ContactLaw::Frictionless => "frictionless",
            ContactLaw::Tresca { .. } => "tresca",
            ContactLaw::Coulomb { .. } => "coulomb",
        }
    }

    /// Checks a law built from the variants (the constructors check already).
    pub(crate) fn validate(&self) -> Result<(), SettingsError> {
        match self {
            ContactLaw::Tresca {
                friction_bound: FrictionBound::Constant(g),
            } => SettingsError::non_negative("friction_bound", *g).map(|_| ()),
            ContactLaw::Coulomb {
                coefficient,
                fixed_point,
            } => {
                SettingsError::non_negative("coefficient", *coefficient)?;
                FixedPointSettings::builder()
                    .max_iterations(fixed_point.max_iterations)
                    .tolerance(fixed_point.tolerance)
                    .build()
                    .map(|_| ())
            }
            _ => Ok(()),
        }
    }
}

/// Which side's geometry gives the contact normal `nu` at a node pair of two bodies (the
/// tangent is always `tau = (-nu_y, nu_x)`, so the tangential rows follow the choice). Nodal
/// normals are the normalised mean of the outward normals of the one or two interface edges
/// next to the node, on each side's enlarged mesh. Against a rigid obstacle the normal is
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
    pub fn combine(self, n_a: Vector, n_b: Vector) -> Vector {
        match self {
            ContactNormal::BodyA => n_a,
            ContactNormal::BodyB => -n_b,
            ContactNormal::Averaged => {
                let sum = n_a - n_b;
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

/// What body A is in contact with.
#[derive(Debug, Clone)]
pub enum Counterpart {
    /// A second elastic body and its contact part.
    Body {
        /// The body.
        body: Box<ElasticBody>,
        /// Its boundary part facing body A.
        part: String,
    },
    /// A rigid obstacle: a gap function, nothing meshed or assembled.
    Obstacle(Obstacle),
}

/// A contact problem: body A with its contact part, the counterpart, the law, an optional
/// extra initial gap `h0(x)` (added to the geometric gap), and interface options.
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
/// use vem_contact::{ContactLaw, ContactProblem, ExactSolver};
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
/// let problem = ContactProblem::two_bodies(upper, "bottom", lower, "top", ContactLaw::Frictionless);
/// let result = problem.solve(&mut ExactSolver::default())?;
/// assert_eq!(result.nodes.len(), 6 + 4 - 2); // x = i/3 and j/5: 8 distinct positions
/// for node in &result.nodes {
///     assert!((node.pressure - 3.0 * 0.015).abs() < 1e-7);
/// }
/// assert!((result.normal_resultant() - 0.045).abs() < 1e-8);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Clone)]
pub struct ContactProblem {
    body: ElasticBody,
    part: String,
    counterpart: Counterpart,
    law: ContactLaw,
    imposed_gap: Option<ScalarField>,
    interface_options: InterfaceOptions,
    normal: ContactNormal,
}

impl std::fmt::Debug for ContactProblem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ContactProblem")
            .field("body", &self.body.name())
            .field("part", &self.part)
            .field("counterpart", &self.counterpart)
            .field("law", &self.law)
            .field("imposed_gap", &self.imposed_gap.is_some())
            .field("normal", &self.normal)
            .finish()
    }
}

impl ContactProblem {
    /// Two elastic bodies in contact on `part_a` of `body_a` and `part_b` of `body_b`; the
    /// normal `nu` points from A to B, taken from the side chosen by
    /// [`ContactProblem::with_normal`] (B's by default).
    pub fn two_bodies(
        body_a: ElasticBody,
        part_a: impl Into<String>,
        body_b: ElasticBody,
        part_b: impl Into<String>,
        law: ContactLaw,
    ) -> Self {
        Self {
            body: body_a,
            part: part_a.into(),
            counterpart: Counterpart::Body {
                body: Box::new(body_b),
                part: part_b.into(),
            },
            law,
            imposed_gap: None,
            interface_options: InterfaceOptions::default(),
            normal: ContactNormal::default(),
        }
    }

    /// One elastic body against a rigid obstacle on its part `part`.
    pub fn against_obstacle(
        body: ElasticBody,
        part: impl Into<String>,
        obstacle: Obstacle,
        law: ContactLaw,
    ) -> Self {
        Self {
            body,
            part: part.into(),
            counterpart: Counterpart::Obstacle(obstacle),
            law,
            imposed_gap: None,
            interface_options: InterfaceOptions::default(),
            normal: ContactNormal::default(),
        }
    }

    /// Adds a user initial gap `h0(x)` to the geometric gap (e.g. the paper's setting, where the
    /// two contact parts coincide and the physical gap is a given function).
    pub fn with_imposed_gap(mut self, gap: impl Fn(Point) -> f64 + Send + Sync + 'static) -> Self {
        self.imposed_gap = Some(Arc::new(gap));
        self
    }

    /// Sets the interface node insertion options.
    pub fn with_interface_options(mut self, options: InterfaceOptions) -> Self {
        self.interface_options = options;
        self
    }

    /// Sets which side gives the contact normal of two bodies ([`ContactNormal`]; ignored
    /// against an obstacle, whose own normal is used).
    pub fn with_normal(mut self, normal: ContactNormal) -> Self {
        self.normal = normal;
        self
    }

    /// Which side gives the contact normal.
    pub fn normal(&self) -> ContactNormal {
        self.normal
    }

    /// The contact law.
    pub fn law(&self) -> &ContactLaw {
        &self.law
    }

    /// The discretisation of this problem: interface node insertion, assembly, constraint
    /// rows, built once; solve it as often as needed
    /// ([`ContactDiscretisation::solve`], [`ContactDiscretisation::solve_scaled`]).
    ///
    /// # Errors
    /// An invalid law, a failed insertion, an invalid body on the enlarged mesh, an assembly
    /// failure, Dirichlet data prescribing the slip of a contact node (friction).
    pub fn discretise(&self) -> Result<ContactDiscretisation, ContactError> {
        ContactDiscretisation::try_new(self)
    }

    /// As [`ContactProblem::discretise`], giving up the problem: the bodies on their original
    /// meshes are dropped once the interface nodes are inserted, before the assembly, which
    /// lowers the peak memory of the build by the original meshes (when nothing else holds
    /// them).
    ///
    /// # Errors
    /// As [`ContactProblem::discretise`].
    pub fn into_discretisation(self) -> Result<ContactDiscretisation, ContactError> {
        ContactDiscretisation::try_new(self)
    }

    /// Discretises and solves the problem with `solver`: a thin driver over
    /// [`ContactProblem::discretise`] and [`ContactDiscretisation::solve`]. The result's
    /// [`work`](ContactResult::work) counts the build (insertion, assembly) and the solve.
    ///
    /// Coulomb friction runs Tresca solves with `g_F = F |sigma_nu|` frozen from the previous
    /// step (the first step is frictionless) until the normal forces settle.
    ///
    /// # Errors
    /// As [`ContactProblem::discretise`] and [`ContactDiscretisation::solve`].
    pub fn solve(&self, solver: &mut dyn ContactSolver) -> Result<ContactResult, ContactError> {
        let start = Instant::now();
        let discretisation = self.discretise()?;
        let mut result = discretisation.solve(solver)?;
        let mut work = discretisation.work();
        work += result.work;
        result.work = work;
        result.model.total_time = start.elapsed();
        Ok(result)
    }

    /// Body A.
    pub fn body(&self) -> &ElasticBody {
        &self.body
    }

    /// Body A's contact part.
    pub fn part(&self) -> &str {
        &self.part
    }

    /// What body A is in contact with.
    pub fn counterpart(&self) -> &Counterpart {
        &self.counterpart
    }

    /// The interface node insertion options.
    pub fn interface_options(&self) -> &InterfaceOptions {
        &self.interface_options
    }

    /// The imposed gap added to the geometric gap, if any.
    pub fn imposed_gap(&self) -> Option<&ScalarField> {
        self.imposed_gap.as_ref()
    }
}

/// The tangent `tau = (-nu_y, nu_x)` (nu rotated by +90 degrees; `e_x` for `nu = (0, -1)`).
pub fn tangent(normal: Vector) -> Vector {
    Vector::new(-normal.y, normal.x)
}
