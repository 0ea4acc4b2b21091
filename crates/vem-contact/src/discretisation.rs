//! The contact problem discretised once, solved many times.
//!
//! A [`ContactDiscretisation`] owns everything that depends only on geometry and topology:
//! the meshes enlarged by interface node insertion, the bodies on them with their degrees of
//! freedom, the assembled stiffness blocks (patterns built once, values refillable), the offsets
//! of the bodies in the combined numbering, the node geometry of the interface (normals,
//! tangents, tributary lengths, gaps) and the constraint rows `B_N` (and `B_T` when the law has
//! friction). Every [`ContactSystem`] it hands out borrows these (no copy of `K`) and carries the
//! discretisation's [`PatternId`], so a solver keeps its symbolic work from one solve to the next:
//! a Coulomb fixed point of `k` Tresca steps costs one assembly and one symbolic analysis.
//!
//! Values are refilled without rebuilding anything: [`ContactDiscretisation::set_material`]
//! (stiffness and load), [`ContactDiscretisation::set_law`] (friction bound, coefficient),
//! [`ContactDiscretisation::solve_scaled`] (load steps: body forces, tractions and prescribed
//! displacements scaled together).
//!
//! ```
//! use std::sync::Arc;
//! use vem_contact::{ActiveSetSolver, ContactLaw, ContactProblem};
//! use vem_elastic::{Component, Dirichlet, ElasticBody, Material, Plane};
//! use vem_mesh::generators::{structured_quads, Rectangle};
//! use vem_mesh::{Point, Vector};
//! use vem_space::LowestOrderVem;
//!
//! let material = Material::from_lame(2.0, 1.0, Plane::Strain)?;
//! let element = Arc::new(LowestOrderVem::default());
//! let square = |y0: f64, n: usize| {
//!     structured_quads(&Rectangle::new(Point::new(0.0, y0), Point::new(1.0, y0 + 1.0)), n, n)
//! };
//! let upper = ElasticBody::builder("upper", square(0.0, 3)?, material, element.clone())
//!     .dirichlet(Dirichlet::prescribed("top", Component::Y, |_| Vector::new(0.0, -0.03)))
//!     .dirichlet(Dirichlet::prescribed("left", Component::X, |_| Vector::zeros()))
//!     .build()?;
//! let lower = ElasticBody::builder("lower", square(-1.0, 4)?, material, element)
//!     .dirichlet(Dirichlet::prescribed("bottom", Component::Y, |_| Vector::zeros()))
//!     .dirichlet(Dirichlet::prescribed("left", Component::X, |_| Vector::zeros()))
//!     .build()?;
//! let problem = ContactProblem::two_bodies(upper, "bottom", lower, "top", ContactLaw::Frictionless);
//! let discretisation = problem.discretise()?;
//! let mut solver = ActiveSetSolver::default();
//! // Load steps: the contact force grows linearly with the prescribed displacement (the
//! // blocks are pressed together from the start, so the contact set does not change).
//! let full = discretisation.solve(&mut solver)?.normal_resultant();
//! let half = discretisation.solve_scaled(&mut solver, 0.5)?.normal_resultant();
//! assert!((half - 0.5 * full).abs() < 1e-12 * full);
//! // One assembly (per body) for both solves; the second reused the symbolic analysis.
//! assert_eq!(discretisation.work().assemblies, 2);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::borrow::{Borrow, Cow};
use std::sync::Arc;
use std::time::{Duration, Instant};

use vem_elastic::{AssembledSystem, DofStatus, ElasticBody, Material};
use vem_mesh::interface::{boundary_chain, insert_interface_nodes};
use vem_mesh::{Point, Vector};

use crate::problem::{tangent, Counterpart, FrictionBound};
use crate::result::{
    classify, consistent_traction, BodyResult, BodySummary, ContactResult, FixedPointReport,
    InterfaceNode, ModelSummary,
};
use crate::solver::borrowed_block;
use crate::solver::ForceScales;
use crate::warning::{Warning, ZoneLimit};
use crate::{
    ConstraintRows, ContactError, ContactLaw, ContactNormal, ContactProblem, ContactSolution,
    ContactSolver, ContactSystem, FixedPointSettings, Friction, PatternId, WorkCounters,
};

/// The geometry of one interface node: a node pair of the two bodies (after insertion the
/// interface is node-to-node) or a body node facing a rigid obstacle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactNode {
    /// The vertex of body A's (enlarged) mesh.
    pub vertex_a: usize,
    /// The partner vertex of body B's (enlarged) mesh; `None` against an obstacle.
    pub vertex_b: Option<usize>,
    /// Position (on body A, reference configuration).
    pub position: Point,
    /// The unit normal `nu` from A to B (of the side chosen by
    /// [`ContactNormal`](crate::ContactNormal); into the obstacle).
    pub normal: Vector,
    /// The tributary length `l_x` (nodal quadrature weight on `Gamma_C`).
    pub tributary_length: f64,
    /// The gap the geometry gives along `nu` (zero where the two sides coincide).
    pub geometric_gap: f64,
    /// The initial gap `h0 = geometric gap + imposed gap`.
    pub initial_gap: f64,
}

impl ContactNode {
    /// The tangent `tau = (-nu_y, nu_x)`.
    pub fn tangent(&self) -> Vector {
        tangent(self.normal)
    }
}

/// The discretised contact problem (see the module docs).
#[derive(Debug, Clone)]
pub struct ContactDiscretisation {
    pattern: PatternId,
    stiffness_version: u64,
    law: ContactLaw,
    obstacle: bool,
    normal_choice: ContactNormal,
    /// Vertices of each body's mesh before the interface insertion (the vertices of the
    /// enlarged meshes below these are original).
    original_vertices: Vec<usize>,
    bodies: Vec<ElasticBody>,
    systems: Vec<Arc<AssembledSystem>>,
    offsets: Vec<usize>,
    nodes: Vec<ContactNode>,
    inserted_nodes: usize,
    normal_rows: ConstraintRows,
    /// The part of `[u]_nu` carried by prescribed degrees of freedom, at full load.
    normal_lifting: Vec<f64>,
    tangential_rows: Option<ConstraintRows>,
    /// Tresca: `b_i = l_i g_F(x_i)`.
    friction_bounds: Option<Vec<f64>>,
    load: Vec<f64>,
    /// What lies beyond the first and the last interface node.
    zone_ends: [ZoneLimit; 2],
    work: WorkCounters,
}

impl ContactDiscretisation {
    /// Inserts the interface nodes (two bodies) or extracts the contact chain (obstacle),
    /// assembles every body on its enlarged mesh and builds the constraint rows. A problem
    /// given by value is dropped once the interface is inserted, before the assembly: the
    /// original meshes and the stiffness are never held together.
    pub(crate) fn try_new(problem: impl Borrow<ContactProblem>) -> Result<Self, ContactError> {
        let problem_ref = problem.borrow();
        problem_ref.law().validate()?;
        let mut work = WorkCounters::default();
        let start = Instant::now();
        let (bodies, nodes, inserted_nodes, zone_ends) = interface(problem_ref)?;
        let law = problem_ref.law().clone();
        let obstacle = matches!(problem_ref.counterpart(), Counterpart::Obstacle(_));
        let normal_choice = problem_ref.normal();
        let mut original_vertices = vec![problem_ref.body().mesh().n_vertices()];
        if let Counterpart::Body { body, .. } = problem_ref.counterpart() {
            original_vertices.push(body.mesh().n_vertices());
        }
        drop(problem);
        work.times.insertion = start.elapsed();
        let start = Instant::now();
        let systems = bodies
            .iter()
            .map(|body| body.assemble().map(Arc::new))
            .collect::<Result<Vec<_>, _>>()?;
        work.assemblies = systems.len();
        let mut offsets = Vec::with_capacity(systems.len() + 1);
        let mut total = 0;
        for system in &systems {
            offsets.push(total);
            total += system.dofs().n_unknowns();
        }
        offsets.push(total);
        let load = concatenated_load(&systems);
        let mut discretisation = Self {
            pattern: PatternId::fresh(),
            stiffness_version: 0,
            law,
            obstacle,
            normal_choice,
            original_vertices,
            bodies,
            systems,
            offsets,
            nodes,
            inserted_nodes,
            normal_rows: ConstraintRows::try_from_triplets(0, 0, &[])?,
            normal_lifting: Vec::new(),
            tangential_rows: None,
            friction_bounds: None,
            load,
            zone_ends,
            work,
        };
        let (normal_rows, normal_lifting) = discretisation.jump_rows(|node| node.normal)?;
        discretisation.normal_rows = normal_rows;
        discretisation.normal_lifting = normal_lifting;
        if discretisation.law.has_friction() {
            discretisation.tangential_rows = Some(discretisation.tangential_rows_checked()?);
        }
        discretisation.friction_bounds = discretisation.tresca_bounds()?;
        discretisation.work.times.assembly = start.elapsed();
        Ok(discretisation)
    }

    /// The identity of the structure shared by every system this discretisation hands out.
    pub fn pattern(&self) -> PatternId {
        self.pattern
    }

    /// The contact law.
    pub fn law(&self) -> &ContactLaw {
        &self.law
    }

    /// Which side gives the contact normal of two bodies (against an obstacle its own normal
    /// is used whatever this says).
    pub fn normal_choice(&self) -> ContactNormal {
        self.normal_choice
    }

    /// The bodies on their enlarged meshes: A first, then B (absent against an obstacle).
    pub fn bodies(&self) -> &[ElasticBody] {
        &self.bodies
    }

    /// The assembled (reduced) system of each body.
    pub fn systems(&self) -> &[Arc<AssembledSystem>] {
        &self.systems
    }

    /// First unknown of each body in the combined numbering, and the total at the end.
    pub fn offsets(&self) -> &[usize] {
        &self.offsets
    }

    /// Number of unknowns (free degrees of freedom of all bodies).
    pub fn n_dofs(&self) -> usize {
        *self.offsets.last().unwrap_or(&0)
    }

    /// The interface nodes, ordered along body A's contact part.
    pub fn nodes(&self) -> &[ContactNode] {
        &self.nodes
    }

    /// Vertices inserted by the interface node insertion (both sides).
    pub fn inserted_nodes(&self) -> usize {
        self.inserted_nodes
    }

    /// The normal rows `B_N` (`(B_N u)_i = [u]_nu` over the free unknowns at node `i`).
    pub fn normal_rows(&self) -> &ConstraintRows {
        &self.normal_rows
    }

    /// The tangential rows `B_T` (only for laws with friction).
    pub fn tangential_rows(&self) -> Option<&ConstraintRows> {
        self.tangential_rows.as_ref()
    }

    /// The load `f` of the free unknowns (body force, tractions and the Dirichlet lifting).
    pub fn load(&self) -> &[f64] {
        &self.load
    }

    /// The gaps `g = h0 - (prescribed part of [u]_nu)` at full load.
    pub fn gap(&self) -> Vec<f64> {
        self.gap_scaled(1.0)
    }

    /// What building and refilling this discretisation computed (assemblies, times).
    pub fn work(&self) -> WorkCounters {
        self.work
    }

    /// The contact system at full load with the law's friction bounds (Tresca), zero bounds
    /// (the first step of a Coulomb fixed point) or no friction (frictionless).
    pub fn system(&self) -> ContactSystem<'_> {
        let bounds = self.friction_bounds.as_deref().map(Cow::Borrowed);
        self.system_with(1.0, bounds)
    }

    /// The contact system with the loads and prescribed displacements scaled by `load_factor`
    /// and the friction bounds `bounds` (ignored without tangential rows; zero bounds when
    /// `None` and the law has friction).
    fn system_with<'s>(
        &'s self,
        load_factor: f64,
        bounds: Option<Cow<'s, [f64]>>,
    ) -> ContactSystem<'s> {
        let blocks = self
            .systems
            .iter()
            .zip(&self.offsets)
            .map(|(system, &offset)| borrowed_block(offset, system.stiffness()))
            .collect();
        let load = if load_factor == 1.0 {
            Cow::Borrowed(&self.load[..])
        } else {
            Cow::Owned(self.load.iter().map(|f| load_factor * f).collect())
        };
        let friction = self.tangential_rows.as_ref().map(|rows| {
            let bounds = bounds.unwrap_or_else(|| Cow::Owned(vec![0.0; rows.nrows()]));
            Friction::try_new(rows, bounds).expect("bounds checked when they were made")
        });
        ContactSystem::try_from_parts(
            self.pattern,
            self.stiffness_version,
            blocks,
            load,
            Cow::Borrowed(&self.normal_rows),
            Cow::Owned(self.gap_scaled(load_factor)),
            friction,
        )
        .expect("a discretisation's parts are consistent")
    }

    fn gap_scaled(&self, load_factor: f64) -> Vec<f64> {
        self.nodes
            .iter()
            .zip(&self.normal_lifting)
            .map(|(node, lifting)| node.initial_gap - load_factor * lifting)
            .collect()
    }

    /// Solves with `solver` at full load (see [`ContactDiscretisation::solve_scaled`]).
    ///
    /// # Errors
    /// The solver's failure (with its report), a Coulomb fixed point that does not settle,
    /// post-processing failures.
    pub fn solve(&self, solver: &mut dyn ContactSolver) -> Result<ContactResult, ContactError> {
        self.solve_scaled(solver, 1.0)
    }

    /// Solves with every load (body forces, tractions) and every prescribed displacement
    /// scaled by `load_factor` (a load step; the gaps are not scaled). Coulomb friction runs
    /// Tresca solves with `g_F = F |sigma_nu|` frozen from the previous step (the first step
    /// has no friction) until the normal forces settle. The result's
    /// [`work`](ContactResult::work) counts this solve only (no assembly).
    ///
    /// # Errors
    /// As [`ContactDiscretisation::solve`]; a non-finite `load_factor` is an
    /// [`ContactError::InvalidSetting`].
    pub fn solve_scaled(
        &self,
        solver: &mut dyn ContactSolver,
        load_factor: f64,
    ) -> Result<ContactResult, ContactError> {
        if !load_factor.is_finite() {
            return Err(ContactError::InvalidSetting {
                reason: format!("load factor {load_factor} is not finite"),
            });
        }
        let start = Instant::now();
        let (solution, fixed_point, mut work) = match &self.law {
            ContactLaw::Coulomb {
                coefficient,
                fixed_point,
            } => self.coulomb_fixed_point(solver, load_factor, *coefficient, fixed_point)?,
            _ => {
                let system = self.system_with(
                    load_factor,
                    self.friction_bounds.as_deref().map(Cow::Borrowed),
                );
                let solution = solver.solve(&system)?;
                let work = solution.report.work;
                (solution, None, work)
            }
        };
        let post = Instant::now();
        let mut result =
            self.collect(load_factor, solution, fixed_point, solver.force_accuracy())?;
        work.times.post = post.elapsed();
        result.work = work;
        result.model.total_time = start.elapsed();
        Ok(result)
    }

    /// Replaces the material of body `body` (0: A, 1: B) and refills the stiffness and load
    /// values on the existing patterns (nothing is rebuilt; solvers keep their symbolic work).
    ///
    /// # Errors
    /// A body index out of range, an invalid material, an element failure.
    pub fn set_material(&mut self, body: usize, material: Material) -> Result<(), ContactError> {
        let Some(current) = self.bodies.get(body) else {
            return Err(ContactError::InvalidSetting {
                reason: format!(
                    "body index {body}: the discretisation has {} bodies",
                    self.bodies.len()
                ),
            });
        };
        let start = Instant::now();
        let updated = current.with_material(material)?;
        updated.reassemble(Arc::make_mut(&mut self.systems[body]))?;
        self.bodies[body] = updated;
        self.load = concatenated_load(&self.systems);
        self.normal_lifting = self.jump_rows(|node| node.normal)?.1;
        self.stiffness_version += 1;
        self.work.assemblies += 1;
        self.work.times.assembly += start.elapsed();
        Ok(())
    }

    /// Replaces the contact law by one of the same kind of rows: a law with friction needs a
    /// discretisation built with friction (tangential rows), a frictionless law one without.
    ///
    /// # Errors
    /// An invalid law, or one that needs other rows than those built.
    pub fn set_law(&mut self, law: ContactLaw) -> Result<(), ContactError> {
        law.validate()?;
        if law.has_friction() != self.tangential_rows.is_some() {
            return Err(ContactError::InvalidSetting {
                reason: format!(
                    "the law '{}' needs {} tangential rows; this discretisation was built for '{}'",
                    law.name(),
                    if law.has_friction() { "" } else { "no" },
                    self.law.name()
                ),
            });
        }
        self.law = law;
        self.friction_bounds = self.tresca_bounds()?;
        Ok(())
    }

    /// Tresca: the nodal bounds `b_i = l_i g_F(x_i)`, checked.
    fn tresca_bounds(&self) -> Result<Option<Vec<f64>>, ContactError> {
        let ContactLaw::Tresca { friction_bound } = &self.law else {
            return Ok(None);
        };
        self.nodes
            .iter()
            .map(|node| {
                let g = match friction_bound {
                    FrictionBound::Constant(g) => *g,
                    FrictionBound::Field(g) => g(node.position),
                };
                if g.is_finite() && g >= 0.0 {
                    Ok(node.tributary_length * g)
                } else {
                    Err(ContactError::InvalidSetting {
                        reason: format!(
                            "friction bound g_F = {g} at ({}, {}) must be finite and >= 0",
                            node.position.x, node.position.y
                        ),
                    })
                }
            })
            .collect::<Result<Vec<_>, _>>()
            .map(Some)
    }

    /// Rows `d . (u_A - u_B)` at every node for the node direction `direction(node)`, and the
    /// part of `d . (u_A - u_B)` carried by prescribed degrees of freedom.
    fn jump_rows(
        &self,
        direction: impl Fn(&ContactNode) -> Vector,
    ) -> Result<(ConstraintRows, Vec<f64>), ContactError> {
        let mut triplets = Vec::with_capacity(4 * self.nodes.len());
        let mut prescribed_jump = vec![0.0; self.nodes.len()];
        for (row, node) in self.nodes.iter().enumerate() {
            let d = direction(node);
            let sides = [(0, node.vertex_a, 1.0)]
                .into_iter()
                .chain(node.vertex_b.map(|v| (1, v, -1.0)));
            for (body, vertex, sign) in sides {
                let dofs = self.systems[body].dofs();
                for component in 0..2 {
                    let coefficient = sign * d[component];
                    let global = 2 * vertex + component;
                    match (dofs.unknown_index(global), dofs.status(global)) {
                        // A free value or a rigid plate's translation.
                        (Some(i), _) => triplets.push((row, self.offsets[body] + i, coefficient)),
                        (None, DofStatus::Prescribed(k)) => {
                            prescribed_jump[row] += coefficient * dofs.prescribed_values()[k]
                        }
                        (None, DofStatus::Free(_)) => {}
                    }
                }
            }
        }
        let rows = ConstraintRows::try_from_triplets(self.nodes.len(), self.n_dofs(), &triplets)?;
        Ok((rows, prescribed_jump))
    }

    /// Tangential rows `[u]_1tau` of the free unknowns. The prescribed part of the slip is not
    /// representable in `j_h(B_T u)`: it is rejected unless it vanishes.
    fn tangential_rows_checked(&self) -> Result<ConstraintRows, ContactError> {
        let (rows, prescribed) = self.jump_rows(|node| node.tangent())?;
        if let Some((node, p)) = self
            .nodes
            .iter()
            .zip(&prescribed)
            .find(|(_, p)| p.abs() > 0.0)
        {
            return Err(ContactError::InvalidSetting {
                reason: format!(
                    "the tangential jump at the interface node ({}, {}) is prescribed by Dirichlet \
                     data ({p:e}); friction needs a free tangential motion at every contact node",
                    node.position.x, node.position.y
                ),
            });
        }
        Ok(rows)
    }

    /// Coulomb's law by a fixed point of Tresca problems: `b_i = F lambda_N,i` from the
    /// previous step (the nodal form of `g_F = F |sigma_nu|` times the tributary length),
    /// starting from zero bounds (the frictionless solution). Every step solves a system of
    /// the same structure: the solver keeps its symbolic work.
    fn coulomb_fixed_point(
        &self,
        solver: &mut dyn ContactSolver,
        load_factor: f64,
        coefficient: f64,
        settings: &FixedPointSettings,
    ) -> Result<(ContactSolution, Option<FixedPointReport>, WorkCounters), ContactError> {
        let tolerance = settings.tolerance().max(solver.force_accuracy());
        let mut solution = solver.solve(&self.system_with(load_factor, None))?;
        let mut work = solution.report.work;
        let mut iterations = solution.report.iterations;
        let mut history = Vec::with_capacity(settings.max_iterations());
        for step in 1..=settings.max_iterations() {
            let bounds: Vec<f64> = solution
                .normal_force
                .iter()
                .map(|&f| coefficient * f.max(0.0))
                .collect();
            let system = self.system_with(load_factor, Some(Cow::Borrowed(&bounds)));
            let next = solver.solve(&system)?;
            work += next.report.work;
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
                if change > settings.tolerance() {
                    solution
                        .report
                        .warnings
                        .push(Warning::FixedPointAtForceFloor {
                            solver: solution.report.solver,
                            force_accuracy: solver.force_accuracy(),
                            tolerance: settings.tolerance(),
                            change,
                        });
                }
                let report = FixedPointReport {
                    steps: step,
                    residual: change,
                    tolerance,
                    history,
                    solver_iterations: iterations,
                    final_bounds: bounds,
                };
                return Ok((solution, Some(report), work));
            }
        }
        Err(ContactError::FixedPointNotConverged {
            steps: settings.max_iterations(),
            residual: *history.last().unwrap_or(&f64::INFINITY),
            tolerance,
            report: Box::new(solution.report),
        })
    }

    /// Per-body solutions, per-node results, resultants, warnings. Statuses are decided in
    /// the force scales of the acceptance test: node `i` is open when
    /// `lambda_N,i <= theta F_i` and sticks when `|lambda_T,i| < b_i - theta F_i`, with `F_i`
    /// the force scale of its bodies ([`KktResiduals`](crate::KktResiduals)) and
    /// `theta = max(force_accuracy, 1e-8)` (the solver's force accuracy).
    fn collect(
        &self,
        load_factor: f64,
        solution: ContactSolution,
        fixed_point: Option<FixedPointReport>,
        force_accuracy: f64,
    ) -> Result<ContactResult, ContactError> {
        let u = &solution.displacement;
        let normal_jump_free = self.normal_rows.apply(u);
        let slip_free = self.tangential_rows.as_ref().map(|rows| rows.apply(u));
        let bounds = fixed_point
            .as_ref()
            .map(|fp| fp.final_bounds.as_slice())
            .or(self.friction_bounds.as_deref());
        let system = self.system_with(load_factor, bounds.map(Cow::Borrowed));
        let forces = ForceScales::of(
            &system,
            u,
            &system.stiffness_apply(u),
            &solution.normal_force,
            &solution.tangential_force,
        );
        let theta = force_accuracy.max(1e-8);
        let nodes: Vec<InterfaceNode> = self
            .nodes
            .iter()
            .enumerate()
            .map(|(i, node)| {
                // [u]_nu = B_N u_free + prescribed part.
                let normal_jump = normal_jump_free[i] + load_factor * self.normal_lifting[i];
                let slip = slip_free.as_ref().map_or(0.0, |s| s[i]);
                let normal_force = solution.normal_force[i];
                let friction = -solution.tangential_force[i];
                let status = classify(
                    normal_force,
                    theta * forces.rows[i],
                    friction,
                    bounds.map(|b| b[i]),
                    self.law.has_friction(),
                );
                InterfaceNode {
                    position: node.position,
                    normal: node.normal,
                    tangent: node.tangent(),
                    tributary_length: node.tributary_length,
                    initial_gap: node.initial_gap,
                    normal_jump,
                    normal_force,
                    pressure: normal_force / node.tributary_length,
                    consistent_pressure: 0.0,
                    consistent_friction_traction: 0.0,
                    friction_force: friction,
                    slip,
                    status,
                    vertex_a: node.vertex_a,
                    vertex_b: node.vertex_b,
                }
            })
            .collect();
        let mut nodes = nodes;
        let positions: Vec<Point> = nodes.iter().map(|n| n.position).collect();
        let lengths: Vec<f64> = nodes.iter().map(|n| n.tributary_length).collect();
        let normal_forces: Vec<f64> = nodes.iter().map(|n| n.normal_force).collect();
        let friction_forces: Vec<f64> = nodes.iter().map(|n| n.friction_force).collect();
        let support = self.projection_support();
        let pressures = consistent_traction(&positions, &normal_forces, &support, &lengths);
        let tractions = consistent_traction(&positions, &friction_forces, &support, &lengths);
        for ((node, p), t) in nodes.iter_mut().zip(pressures).zip(tractions) {
            node.consistent_pressure = p;
            node.consistent_friction_traction = t;
        }
        let mut warnings = solution.report.warnings.clone();
        warnings.extend(self.model_warnings(&nodes, bounds, forces.global()));
        let mut bodies = Vec::with_capacity(self.bodies.len());
        for (k, (body, system)) in self.bodies.iter().zip(&self.systems).enumerate() {
            let free = &u[self.offsets[k]..self.offsets[k + 1]];
            let displacement = system.expand_scaled(free, load_factor)?;
            let body_solution = body.solution_scaled(system, displacement, load_factor)?;
            bodies.push(BodyResult {
                body: body.clone(),
                system: Arc::clone(system),
                solution: body_solution,
            });
        }
        let model = ModelSummary {
            law: self.law.name(),
            solver: solution.report.solver,
            bodies: bodies
                .iter()
                .map(|b| BodySummary {
                    name: b.body.name().to_string(),
                    vertices: b.body.mesh().n_vertices(),
                    polygons: b.body.mesh().n_polygons(),
                    free_dofs: b.system.dofs().n_free(),
                    prescribed_dofs: b.system.dofs().n_prescribed(),
                })
                .collect(),
            obstacle: self.obstacle,
            normal_rows: self.normal_rows.nrows(),
            tangential_rows: self
                .tangential_rows
                .as_ref()
                .map_or(0, ConstraintRows::nrows),
            inserted_nodes: self.inserted_nodes,
            total_time: Duration::ZERO,
        };
        let mut result = ContactResult::new(bodies, nodes, solution.report, fixed_point, model);
        result.warnings = warnings;
        Ok(result)
    }

    /// The nodes whose hats span the space of the consistent pressure: the original nodes
    /// (not inserted) of the side with fewer of them on the interface (B on a tie); every
    /// node against an obstacle.
    fn projection_support(&self) -> Vec<bool> {
        let original_a: Vec<bool> = self
            .nodes
            .iter()
            .map(|n| n.vertex_a < self.original_vertices[0])
            .collect();
        let Some(&limit_b) = self.original_vertices.get(1) else {
            return vec![true; self.nodes.len()];
        };
        let original_b: Vec<bool> = self
            .nodes
            .iter()
            .map(|n| n.vertex_b.is_some_and(|v| v < limit_b))
            .collect();
        let count = |v: &[bool]| v.iter().filter(|&&b| b).count();
        if count(&original_a) < count(&original_b) {
            original_a
        } else {
            original_b
        }
    }

    /// Warnings about the model behind a converged answer: elements far outside A1, a contact
    /// zone at a limit of the interface, an initial overlap, an effectively tied friction
    /// bound.
    fn model_warnings(
        &self,
        nodes: &[InterfaceNode],
        bounds: Option<&[f64]>,
        force_scale: f64,
    ) -> Vec<Warning> {
        let mut warnings = Vec::new();
        for body in &self.bodies {
            let mesh = body.mesh();
            let mut poor: Vec<(usize, vem_mesh::quality::ElementQuality)> = (0..mesh.n_polygons())
                .map(|p| (p, mesh.element_quality(p)))
                .filter(|(_, q)| q.gamma() < ELEMENT_GAMMA_FLOOR || q.gamma().is_nan())
                .collect();
            poor.sort_by(|a, b| a.1.gamma().total_cmp(&b.1.gamma()));
            for (element, q) in poor.into_iter().take(MAX_ELEMENT_WARNINGS) {
                warnings.push(Warning::ElementShape {
                    body: body.name().to_string(),
                    element,
                    gamma: q.gamma(),
                    shortest_edge_ratio: q.shortest_edge_ratio,
                    star_ratio: q.star_ratio,
                    diameter: q.diameter,
                });
            }
        }
        let ends = [nodes.first(), nodes.last()];
        for (k, (node, limit)) in ends.iter().zip(self.zone_ends).enumerate() {
            if k == 1 && nodes.len() == 1 {
                break;
            }
            if let Some(node) = node {
                if node.status != crate::NodeStatus::Open {
                    warnings.push(Warning::ContactZoneAtLimit {
                        limit,
                        x: node.position.x,
                        y: node.position.y,
                        normal_force: node.normal_force,
                    });
                }
            }
        }
        warnings.extend(Warning::initial_overlap(
            nodes.iter().map(|n| (n.position, n.normal, n.initial_gap)),
        ));
        if let (Some(bounds), ContactLaw::Tresca { .. }) = (bounds, &self.law) {
            // The smallest bound among the nodes in contact: if even it exceeds every force
            // by far, no node can slip.
            let tied = nodes
                .iter()
                .zip(bounds)
                .filter(|(n, _)| n.status != crate::NodeStatus::Open)
                .min_by(|a, b| a.1.total_cmp(b.1));
            if let Some((node, &bound)) = tied {
                if bound > TIED_RATIO * force_scale && force_scale > 0.0 {
                    warnings.push(Warning::EffectivelyTied {
                        x: node.position.x,
                        y: node.position.y,
                        bound,
                        ratio: bound / force_scale,
                    });
                }
            }
        }
        warnings
    }
}

/// Elements whose gamma (A1) is below this are reported ([`Warning::ElementShape`]).
const ELEMENT_GAMMA_FLOOR: f64 = 1e-4;
/// At most this many element warnings per body (the worst first).
const MAX_ELEMENT_WARNINGS: usize = 5;
/// A friction bound this many times the force scale makes the contact effectively tied.
const TIED_RATIO: f64 = 1e6;

/// The load vectors of the bodies, one after the other.
fn concatenated_load(systems: &[Arc<AssembledSystem>]) -> Vec<f64> {
    systems
        .iter()
        .flat_map(|s| s.rhs().iter().copied())
        .collect()
}

/// Interface insertion (two bodies) or chain extraction (obstacle): the bodies on their
/// (enlarged) meshes, the node geometry with the imposed gap added, the inserted node count.
#[allow(clippy::type_complexity)]
fn interface(
    problem: &ContactProblem,
) -> Result<(Vec<ElasticBody>, Vec<ContactNode>, usize, [ZoneLimit; 2]), ContactError> {
    let (body, part) = (problem.body(), problem.part());
    let (bodies, mut nodes, inserted, zone_ends) = match problem.counterpart() {
        Counterpart::Body {
            body: other,
            part: other_part,
        } => {
            let interface = insert_interface_nodes(
                body.mesh(),
                part,
                other.mesh(),
                other_part,
                problem.interface_options(),
            )
            .map_err(|source| ContactError::Mesh {
                context: format!(
                    "interface between '{part}' of body '{}' and '{other_part}' of body '{}'",
                    body.name(),
                    other.name()
                ),
                source,
            })?;
            let inserted = interface.inserted_a + interface.inserted_b;
            // A paired end that is not an end of body A's chain: the nodes beyond were left
            // unpaired (beyond the pairing limit, or beyond the end of the other part).
            let chain =
                boundary_chain(&interface.mesh_a, part).map_err(|source| ContactError::Mesh {
                    context: format!("contact part of body '{}'", body.name()),
                    source,
                })?;
            let chain_ends = [
                chain.first().map(|c| c.vertex),
                chain.last().map(|c| c.vertex),
            ];
            let beyond = |vertex: Option<usize>| {
                if vertex.is_some() && chain_ends.contains(&vertex) {
                    ZoneLimit::EndOfPart
                } else if problem.interface_options().max_distance().is_some() {
                    ZoneLimit::PairingLimit
                } else {
                    ZoneLimit::EndOfPart
                }
            };
            let zone_ends = [
                beyond(interface.pairs.first().map(|p| p.node_a)),
                beyond(interface.pairs.last().map(|p| p.node_a)),
            ];
            // Body B's outward nodal normals on its enlarged chain, for the normal choice.
            let chain_b = boundary_chain(&interface.mesh_b, other_part).map_err(|source| {
                ContactError::Mesh {
                    context: format!("contact part of body '{}'", other.name()),
                    source,
                }
            })?;
            let normal_b: std::collections::HashMap<usize, Vector> =
                chain_b.iter().map(|c| (c.vertex, c.normal)).collect();
            let choice = problem.normal();
            let nodes: Vec<ContactNode> = interface
                .pairs
                .iter()
                .map(|pair| {
                    let n_b = normal_b.get(&pair.node_b).copied().unwrap_or(-pair.normal);
                    let normal = choice.combine(pair.normal, n_b);
                    let gap = (pair.point_b - pair.point_a).dot(&normal);
                    ContactNode {
                        vertex_a: pair.node_a,
                        vertex_b: Some(pair.node_b),
                        position: pair.point_a,
                        normal,
                        tributary_length: pair.tributary_length,
                        geometric_gap: gap,
                        initial_gap: gap,
                    }
                })
                .collect();
            let body_a = body.with_mesh(interface.mesh_a)?;
            let body_b = other.with_mesh(interface.mesh_b)?;
            (vec![body_a, body_b], nodes, inserted, zone_ends)
        }
        Counterpart::Obstacle(obstacle) => {
            obstacle.validate()?;
            let chain = boundary_chain(body.mesh(), part).map_err(|source| ContactError::Mesh {
                context: format!("contact part of body '{}'", body.name()),
                source,
            })?;
            let nodes: Vec<ContactNode> = chain
                .iter()
                .map(|node| {
                    let contact = obstacle.gap_at(node.point);
                    ContactNode {
                        vertex_a: node.vertex,
                        vertex_b: None,
                        position: node.point,
                        normal: contact.normal,
                        tributary_length: node.tributary_length,
                        geometric_gap: contact.gap,
                        initial_gap: contact.gap,
                    }
                })
                .collect();
            (
                vec![body.clone()],
                nodes,
                0,
                [ZoneLimit::EndOfPart, ZoneLimit::EndOfPart],
            )
        }
    };
    if let Some(imposed) = problem.imposed_gap() {
        for node in &mut nodes {
            let h0: f64 = imposed(node.position);
            if !h0.is_finite() {
                return Err(ContactError::InvalidSetting {
                    reason: format!(
                        "imposed gap {h0} at ({}, {}) is not finite",
                        node.position.x, node.position.y
                    ),
                });
            }
            node.initial_gap += h0;
        }
    }
    Ok((bodies, nodes, inserted, zone_ends))
}
