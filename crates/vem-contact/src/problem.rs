//! The contact problem P1^h / P2^h of the spec: bodies, the contact pair, the law; its
//! discretisation into a [`ContactSystem`] and the solve.
//!
//! Discretisation (spec section 2):
//! 1. two bodies: the nodes of each contact side are inserted into the other side's boundary
//!    polygons ([`vem_mesh::interface::insert_interface_nodes`]), so the interface is
//!    node-to-node; a rigid obstacle: the nodes of the body's contact part, nothing meshed;
//! 2. each body is assembled on its (enlarged) mesh with Dirichlet conditions eliminated; the
//!    unknowns are the free degrees of freedom of body A followed by those of body B;
//! 3. one normal row per interface node, `[u]_nu = (u_A - u_B) . nu` with `nu` the outward
//!    normal of body A (for an obstacle: `u_A . nu`, `nu` into the obstacle), bounded by the
//!    total initial gap `h0 = geometric gap + user gap`; prescribed (Dirichlet) values move
//!    to the bound. Tangential rows `[u]_1tau = (u_A - u_B) . tau`, `tau = (-nu_y, nu_x)`, are
//!    built only for Tresca and Coulomb, with nodal bounds `b = l_x g_F(x)` (nodal quadrature of
//!    `j_h`, spec section 2).

use std::sync::Arc;
use std::time::{Duration, Instant};

use faer::sparse::{SparseColMat, SymbolicSparseColMat};
use vem_elastic::{AssembledSystem, DofStatus, ElasticBody};
use vem_mesh::interface::{boundary_chain, insert_interface_nodes, InterfaceOptions};
use vem_mesh::{Point, Vector};

use crate::result::{BodyResult, ContactResult, FixedPointReport, InterfaceNode, ModelSummary};
use crate::{
    ConstraintRows, ContactError, ContactSolution, ContactSolver, ContactSystem, Friction, Obstacle,
};

/// A scalar field of position (friction bound, extra gap).
pub type ScalarField = Arc<dyn Fn(Point) -> f64 + Send + Sync>;

/// The friction bound `g_F` of Tresca's law: a constant or a function of position.
#[derive(Clone)]
pub enum FrictionBound {
    /// The same bound everywhere.
    Constant(f64),
    /// A bound depending on the position on the interface (evaluated at the nodes of body A).
    Field(ScalarField),
}

impl FrictionBound {
    fn at(&self, x: Point) -> f64 {
        match self {
            FrictionBound::Constant(g) => *g,
            FrictionBound::Field(g) => g(x),
        }
    }
}

impl std::fmt::Debug for FrictionBound {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            FrictionBound::Constant(g) => write!(f, "Constant({g})"),
            FrictionBound::Field(_) => write!(f, "Field(..)"),
        }
    }
}

/// Settings of the Coulomb fixed point of Tresca problems.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FixedPointSettings {
    /// Largest number of Tresca solves.
    pub max_steps: usize,
    /// Stop when the largest change of a nodal normal force, relative to the largest normal
    /// force, falls below this, or below the force accuracy of the inner solver
    /// ([`ContactSolver::force_accuracy`], `1e-4` for the default interior-point
    /// [`ExactSolver`](crate::solver::ExactSolver), `0` for the penalty and active-set solvers),
    /// whichever is larger: changes below the inner accuracy are noise of the inner solves and
    /// the fixed point would stall there. The tolerance used is in
    /// [`FixedPointReport::tolerance`].
    pub tolerance: f64,
}

impl Default for FixedPointSettings {
    fn default() -> Self {
        Self {
            max_steps: 50,
            tolerance: 1e-8,
        }
    }
}

/// The contact law on the interface.
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
        /// Steps and tolerance of the fixed point.
        fixed_point: FixedPointSettings,
    },
}

impl ContactLaw {
    /// Tresca with a constant bound.
    pub fn tresca(friction_bound: f64) -> Self {
        ContactLaw::Tresca {
            friction_bound: FrictionBound::Constant(friction_bound),
        }
    }

    /// Coulomb with default fixed-point settings.
    pub fn coulomb(coefficient: f64) -> Self {
        ContactLaw::Coulomb {
            coefficient,
            fixed_point: FixedPointSettings::default(),
        }
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

    fn validate(&self) -> Result<(), ContactError> {
        match self {
            ContactLaw::Tresca {
                friction_bound: FrictionBound::Constant(g),
            } if !(g.is_finite() && *g >= 0.0) => Err(ContactError::InvalidSetting {
                reason: format!("friction bound g_F = {g} must be finite and >= 0"),
            }),
            ContactLaw::Coulomb {
                coefficient,
                fixed_point,
            } => {
                if !(coefficient.is_finite() && *coefficient >= 0.0) {
                    return Err(ContactError::InvalidSetting {
                        reason: format!(
                            "friction coefficient F = {coefficient} must be finite and >= 0"
                        ),
                    });
                }
                if fixed_point.max_steps == 0
                    || !(fixed_point.tolerance.is_finite() && fixed_point.tolerance > 0.0)
                {
                    return Err(ContactError::InvalidSetting {
                        reason: format!(
                            "Coulomb fixed point needs max_steps >= 1 and a positive tolerance, got {fixed_point:?}"
                        ),
                    });
                }
                Ok(())
            }
            _ => Ok(()),
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
    extra_gap: Option<ScalarField>,
    interface_options: InterfaceOptions,
}

impl std::fmt::Debug for ContactProblem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ContactProblem")
            .field("body", &self.body.name())
            .field("part", &self.part)
            .field("counterpart", &self.counterpart)
            .field("law", &self.law)
            .field("extra_gap", &self.extra_gap.is_some())
            .finish()
    }
}

/// The geometry of one interface node pair (or body node facing an obstacle).
#[derive(Debug, Clone, Copy)]
struct NodeGeometry {
    vertex_a: usize,
    vertex_b: Option<usize>,
    point: Point,
    normal: Vector,
    tributary_length: f64,
    initial_gap: f64,
}

/// The discretised problem: bodies on their enlarged meshes, assembled, and the interface.
struct Discretisation {
    bodies: Vec<ElasticBody>,
    systems: Vec<AssembledSystem>,
    /// First unknown of each body in the combined numbering.
    offsets: Vec<usize>,
    nodes: Vec<NodeGeometry>,
    inserted_nodes: usize,
    stiffness: SparseColMat<usize, f64>,
    load: Vec<f64>,
    assembly_time: Duration,
}

impl ContactProblem {
    /// Two elastic bodies in contact on `part_a` of `body_a` and `part_b` of `body_b`; the
    /// normal `nu` is the outward normal of body A.
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
            extra_gap: None,
            interface_options: InterfaceOptions::default(),
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
            extra_gap: None,
            interface_options: InterfaceOptions::default(),
        }
    }

    /// Adds a user initial gap `h0(x)` to the geometric gap (e.g. the paper's setting, where the
    /// two contact parts coincide and the physical gap is a given function).
    pub fn with_initial_gap(mut self, gap: impl Fn(Point) -> f64 + Send + Sync + 'static) -> Self {
        self.extra_gap = Some(Arc::new(gap));
        self
    }

    /// Sets the interface node insertion options.
    pub fn with_interface_options(mut self, options: InterfaceOptions) -> Self {
        self.interface_options = options;
        self
    }

    /// The contact law.
    pub fn law(&self) -> &ContactLaw {
        &self.law
    }

    /// Discretises and solves the problem with `solver`.
    ///
    /// Coulomb friction runs Tresca solves with `g_F = F |sigma_nu|` frozen from the previous
    /// step (the first step is frictionless) until the normal forces settle.
    pub fn solve(&self, solver: &mut dyn ContactSolver) -> Result<ContactResult, ContactError> {
        self.law.validate()?;
        let start = Instant::now();
        let discrete = self.discretise()?;
        let (normal_rows, gap) = self.normal_rows(&discrete)?;
        let tangential_rows = if self.law.has_friction() {
            Some(self.tangential_rows(&discrete)?)
        } else {
            None
        };
        let solve_start = Instant::now();
        let (solution, fixed_point) = match &self.law {
            ContactLaw::Frictionless => {
                let system = ContactSystem::try_new(
                    discrete.stiffness.clone(),
                    discrete.load.clone(),
                    normal_rows.clone(),
                    gap.clone(),
                    None,
                )?;
                (solver.solve(&system)?, None)
            }
            ContactLaw::Tresca { friction_bound } => {
                let bounds = discrete
                    .nodes
                    .iter()
                    .map(|node| {
                        let g = friction_bound.at(node.point);
                        if g.is_finite() && g >= 0.0 {
                            Ok(node.tributary_length * g)
                        } else {
                            Err(ContactError::InvalidSetting {
                                reason: format!(
                                    "friction bound g_F = {g} at ({}, {}) must be finite and >= 0",
                                    node.point.x, node.point.y
                                ),
                            })
                        }
                    })
                    .collect::<Result<Vec<f64>, _>>()?;
                let rows = tangential_rows.clone().expect("friction law has rows");
                let system = ContactSystem::try_new(
                    discrete.stiffness.clone(),
                    discrete.load.clone(),
                    normal_rows.clone(),
                    gap.clone(),
                    Some(Friction::try_new(rows, bounds)?),
                )?;
                (solver.solve(&system)?, None)
            }
            ContactLaw::Coulomb {
                coefficient,
                fixed_point,
            } => {
                let rows = tangential_rows.clone().expect("friction law has rows");
                let (solution, report) = coulomb_fixed_point(
                    solver,
                    &discrete,
                    &normal_rows,
                    &gap,
                    rows,
                    *coefficient,
                    fixed_point,
                )?;
                (solution, Some(report))
            }
        };
        let solve_time = solve_start.elapsed();
        self.collect(
            discrete,
            &normal_rows,
            &gap,
            tangential_rows.as_ref(),
            solution,
            fixed_point,
            solve_time,
            start.elapsed(),
        )
    }

    /// Interface insertion (two bodies) or chain extraction (obstacle), then assembly.
    fn discretise(&self) -> Result<Discretisation, ContactError> {
        let start = Instant::now();
        let mut inserted_nodes = 0;
        let (bodies, nodes) = match &self.counterpart {
            Counterpart::Body { body, part } => {
                let interface = insert_interface_nodes(
                    self.body.mesh(),
                    &self.part,
                    body.mesh(),
                    part,
                    &self.interface_options,
                )
                .map_err(|source| ContactError::Mesh {
                    context: format!(
                        "interface between '{}' of body '{}' and '{}' of body '{}'",
                        self.part,
                        self.body.name(),
                        part,
                        body.name()
                    ),
                    source,
                })?;
                inserted_nodes = interface.inserted_a + interface.inserted_b;
                let body_a = self.body.with_mesh(interface.mesh_a)?;
                let body_b = body.with_mesh(interface.mesh_b)?;
                let nodes = interface
                    .pairs
                    .iter()
                    .map(|pair| NodeGeometry {
                        vertex_a: pair.node_a,
                        vertex_b: Some(pair.node_b),
                        point: pair.point_a,
                        normal: pair.normal,
                        tributary_length: pair.tributary_length,
                        initial_gap: pair.initial_gap,
                    })
                    .collect();
                (vec![body_a, body_b], nodes)
            }
            Counterpart::Obstacle(obstacle) => {
                obstacle.validate()?;
                let chain = boundary_chain(self.body.mesh(), &self.part).map_err(|source| {
                    ContactError::Mesh {
                        context: format!("contact part of body '{}'", self.body.name()),
                        source,
                    }
                })?;
                let nodes = chain
                    .iter()
                    .map(|node| {
                        let contact = obstacle.gap_at(node.point);
                        NodeGeometry {
                            vertex_a: node.vertex,
                            vertex_b: None,
                            point: node.point,
                            normal: contact.normal,
                            tributary_length: node.tributary_length,
                            initial_gap: contact.gap,
                        }
                    })
                    .collect();
                (vec![self.body.clone()], nodes)
            }
        };
        let mut nodes: Vec<NodeGeometry> = nodes;
        if let Some(extra) = &self.extra_gap {
            for node in &mut nodes {
                let h0 = extra(node.point);
                if !h0.is_finite() {
                    return Err(ContactError::InvalidSetting {
                        reason: format!(
                            "initial gap h0 = {h0} at ({}, {}) is not finite",
                            node.point.x, node.point.y
                        ),
                    });
                }
                node.initial_gap += h0;
            }
        }
        let systems = bodies
            .iter()
            .map(ElasticBody::assemble)
            .collect::<Result<Vec<_>, _>>()?;
        let mut offsets = Vec::with_capacity(systems.len() + 1);
        let mut total = 0;
        for system in &systems {
            offsets.push(total);
            total += system.dofs().n_free();
        }
        offsets.push(total);
        let stiffness = block_diagonal(systems.iter().map(AssembledSystem::stiffness));
        let load: Vec<f64> = systems
            .iter()
            .flat_map(|s| s.rhs().iter().copied())
            .collect();
        Ok(Discretisation {
            bodies,
            systems,
            offsets,
            nodes,
            inserted_nodes,
            stiffness,
            load,
            assembly_time: start.elapsed(),
        })
    }

    /// Rows `d . (u_A - u_B)` at every node for the node direction `direction(node)`, and the
    /// part of `d . (u_A - u_B)` carried by prescribed degrees of freedom.
    fn jump_rows(
        &self,
        discrete: &Discretisation,
        direction: impl Fn(&NodeGeometry) -> Vector,
    ) -> Result<(ConstraintRows, Vec<f64>), ContactError> {
        let mut triplets = Vec::with_capacity(4 * discrete.nodes.len());
        let mut prescribed_jump = vec![0.0; discrete.nodes.len()];
        for (row, node) in discrete.nodes.iter().enumerate() {
            let d = direction(node);
            let sides = [(0, node.vertex_a, 1.0)]
                .into_iter()
                .chain(node.vertex_b.map(|v| (1, v, -1.0)));
            for (body, vertex, sign) in sides {
                let dofs = discrete.systems[body].dofs();
                for component in 0..2 {
                    let coefficient = sign * d[component];
                    match dofs.status(2 * vertex + component) {
                        DofStatus::Free(i) => {
                            triplets.push((row, discrete.offsets[body] + i, coefficient))
                        }
                        DofStatus::Prescribed(k) => {
                            prescribed_jump[row] += coefficient * dofs.prescribed_values()[k]
                        }
                    }
                }
            }
        }
        let n = *discrete.offsets.last().expect("offsets end with the total");
        let rows = ConstraintRows::try_from_triplets(discrete.nodes.len(), n, &triplets)?;
        Ok((rows, prescribed_jump))
    }

    /// Normal rows and bounds: `B_N u_free <= h0 - (prescribed part of [u]_nu)`.
    fn normal_rows(
        &self,
        discrete: &Discretisation,
    ) -> Result<(ConstraintRows, Vec<f64>), ContactError> {
        let (rows, prescribed) = self.jump_rows(discrete, |node| node.normal)?;
        let gap = discrete
            .nodes
            .iter()
            .zip(prescribed)
            .map(|(node, p)| node.initial_gap - p)
            .collect();
        Ok((rows, gap))
    }

    /// Tangential rows `[u]_1tau` of the free unknowns. The prescribed part of the slip is not
    /// representable in `j_h(B_T u)`: it is rejected unless it vanishes.
    fn tangential_rows(&self, discrete: &Discretisation) -> Result<ConstraintRows, ContactError> {
        let (rows, prescribed) = self.jump_rows(discrete, |node| tangent(node.normal))?;
        if let Some((node, p)) = discrete
            .nodes
            .iter()
            .zip(&prescribed)
            .find(|(_, p)| p.abs() > 0.0)
        {
            return Err(ContactError::InvalidSetting {
                reason: format!(
                    "the tangential jump at the interface node ({}, {}) is prescribed by Dirichlet \
                     data ({p:e}); friction needs a free tangential motion at every contact node",
                    node.point.x, node.point.y
                ),
            });
        }
        Ok(rows)
    }

    /// Per-body solutions, per-node results, resultants.
    #[allow(clippy::too_many_arguments)]
    fn collect(
        &self,
        discrete: Discretisation,
        normal_rows: &ConstraintRows,
        gap: &[f64],
        tangential_rows: Option<&ConstraintRows>,
        solution: ContactSolution,
        fixed_point: Option<FixedPointReport>,
        solve_time: Duration,
        total_time: Duration,
    ) -> Result<ContactResult, ContactError> {
        let u = &solution.displacement;
        let normal_jump_free = normal_rows.apply(u);
        let slip_free = tangential_rows.map(|rows| rows.apply(u));
        let bounds = fixed_point
            .as_ref()
            .map(|fp| fp.final_bounds.clone())
            .or_else(|| match &self.law {
                ContactLaw::Tresca { friction_bound } => Some(
                    discrete
                        .nodes
                        .iter()
                        .map(|n| n.tributary_length * friction_bound.at(n.point))
                        .collect(),
                ),
                _ => None,
            });
        // A node is open when its force is negligible against the largest of the contact forces
        // and the nodal loads (an interior-point solver leaves ~1e-10 relative on open nodes).
        let force_scale = solution
            .normal_force
            .iter()
            .chain(&discrete.load)
            .fold(0.0_f64, |m, &f| m.max(f.abs()));
        let force_tolerance = 1e-6 * force_scale.max(f64::MIN_POSITIVE);
        let nodes: Vec<InterfaceNode> = discrete
            .nodes
            .iter()
            .enumerate()
            .map(|(i, node)| {
                // [u]_nu = B_N u_free + prescribed part = B_N u_free + (h0 - bound).
                let normal_jump = normal_jump_free[i] + (node.initial_gap - gap[i]);
                let slip = slip_free.as_ref().map_or(0.0, |s| s[i]);
                let normal_force = solution.normal_force[i];
                let friction = -solution.tangential_force[i];
                let status = crate::result::classify(
                    normal_force,
                    force_tolerance,
                    friction,
                    bounds.as_ref().map(|b| b[i]),
                    self.law.has_friction(),
                );
                InterfaceNode {
                    position: node.point,
                    normal: node.normal,
                    tangent: tangent(node.normal),
                    tributary_length: node.tributary_length,
                    initial_gap: node.initial_gap,
                    normal_jump,
                    normal_force,
                    pressure: normal_force / node.tributary_length,
                    tangential_force: friction,
                    slip,
                    status,
                    vertex_a: node.vertex_a,
                    vertex_b: node.vertex_b,
                }
            })
            .collect();
        let mut bodies = Vec::with_capacity(discrete.bodies.len());
        for (k, (body, system)) in discrete
            .bodies
            .into_iter()
            .zip(discrete.systems)
            .enumerate()
        {
            let free = &u[discrete.offsets[k]..discrete.offsets[k + 1]];
            let displacement = system.expand(free)?;
            let body_solution = body.solution(&system, displacement)?;
            bodies.push(BodyResult {
                body,
                system,
                solution: body_solution,
            });
        }
        let model = ModelSummary {
            law: self.law.name(),
            solver: solution.report.solver,
            bodies: bodies
                .iter()
                .map(|b| crate::result::BodySummary {
                    name: b.body.name().to_string(),
                    vertices: b.body.mesh().n_vertices(),
                    polygons: b.body.mesh().n_polygons(),
                    free_dofs: b.system.dofs().n_free(),
                    prescribed_dofs: b.system.dofs().n_prescribed(),
                })
                .collect(),
            obstacle: matches!(self.counterpart, Counterpart::Obstacle(_)),
            normal_rows: normal_rows.nrows(),
            tangential_rows: tangential_rows.map_or(0, ConstraintRows::nrows),
            inserted_nodes: discrete.inserted_nodes,
            assembly_time: discrete.assembly_time,
            solve_time,
            total_time,
        };
        Ok(ContactResult::new(
            bodies,
            nodes,
            solution.report,
            fixed_point,
            model,
        ))
    }
}

/// The tangent `tau = (-nu_y, nu_x)` (nu rotated by +90 degrees; `e_x` for `nu = (0, -1)`).
pub fn tangent(normal: Vector) -> Vector {
    Vector::new(-normal.y, normal.x)
}

/// Coulomb's law by a fixed point of Tresca problems: `b_i = F lambda_N,i` from the previous
/// step (the nodal form of `g_F = F |sigma_nu|` times the tributary length), starting from the
/// frictionless solution.
fn coulomb_fixed_point(
    solver: &mut dyn ContactSolver,
    discrete: &Discretisation,
    normal_rows: &ConstraintRows,
    gap: &[f64],
    tangential_rows: ConstraintRows,
    coefficient: f64,
    settings: &FixedPointSettings,
) -> Result<(ContactSolution, FixedPointReport), ContactError> {
    let system = |friction: Option<Friction>| {
        ContactSystem::try_new(
            discrete.stiffness.clone(),
            discrete.load.clone(),
            normal_rows.clone(),
            gap.to_vec(),
            friction,
        )
    };
    let tolerance = settings.tolerance.max(solver.force_accuracy());
    let mut solution = solver.solve(&system(None)?)?;
    let mut iterations = solution.report.iterations;
    let mut history = Vec::with_capacity(settings.max_steps);
    for step in 1..=settings.max_steps {
        let bounds: Vec<f64> = solution
            .normal_force
            .iter()
            .map(|&f| coefficient * f.max(0.0))
            .collect();
        let friction = Friction::try_new(tangential_rows.clone(), bounds.clone())?;
        let next = solver.solve(&system(Some(friction))?)?;
        iterations += next.report.iterations;
        let scale = next
            .normal_force
            .iter()
            .fold(0.0_f64, |m, &f| m.max(f.abs()))
            .max(f64::MIN_POSITIVE);
        let change = next
            .normal_force
            .iter()
            .zip(&solution.normal_force)
            .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()))
            / scale;
        history.push(change);
        solution = next;
        if change <= tolerance {
            let report = FixedPointReport {
                steps: step,
                residual: change,
                tolerance,
                history,
                solver_iterations: iterations,
                final_bounds: bounds,
            };
            return Ok((solution, report));
        }
    }
    Err(ContactError::FixedPointNotConverged {
        steps: settings.max_steps,
        residual: *history.last().unwrap_or(&f64::INFINITY),
        tolerance,
        report: Box::new(solution.report),
    })
}

/// The block-diagonal matrix of the given square blocks (full storage kept).
fn block_diagonal<'a>(
    blocks: impl Iterator<Item = &'a SparseColMat<usize, f64>> + Clone,
) -> SparseColMat<usize, f64> {
    let n: usize = blocks.clone().map(|b| b.ncols()).sum();
    let nnz: usize = blocks.clone().map(|b| b.val().len()).sum();
    let mut col_ptr = Vec::with_capacity(n + 1);
    let mut row_idx = Vec::with_capacity(nnz);
    let mut values = Vec::with_capacity(nnz);
    col_ptr.push(0);
    let mut offset = 0;
    for block in blocks {
        let symbolic = block.symbolic();
        for j in 0..block.ncols() {
            let range = symbolic.col_ptr()[j]..symbolic.col_ptr()[j + 1];
            row_idx.extend(
                symbolic.row_idx()[range.clone()]
                    .iter()
                    .map(|&i| i + offset),
            );
            values.extend_from_slice(&block.val()[range]);
            col_ptr.push(row_idx.len());
        }
        offset += block.ncols();
    }
    let symbolic = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
    SparseColMat::new(symbolic, values)
}
