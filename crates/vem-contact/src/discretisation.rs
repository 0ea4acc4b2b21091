//! The contact problem discretised once, solved many times.
//!
//! A [`ContactDiscretisation`] owns everything that depends only on geometry and topology:
//! the meshes enlarged by interface node insertion, the bodies on them with their degrees of
//! freedom, the assembled stiffness blocks (patterns built once, values refillable), the offsets
//! of the bodies in the combined numbering, the node geometry of every pair's interface
//! (normals, tangents, tributary measures, gaps) and the constraint rows `B_N` (and `B_T` when a
//! law has friction). Every [`ContactSystem`] it hands out borrows these (no copy of `K`) and
//! carries the discretisation's [`PatternId`], so a solver keeps its symbolic work from one
//! solve to the next: a Coulomb fixed point of `k` Tresca steps costs one assembly and one
//! symbolic analysis.
//!
//! Values are refilled without rebuilding anything: [`ContactDiscretisation::set_material`]
//! (stiffness and load), [`ContactDiscretisation::set_law`] (friction bound, coefficient),
//! [`ContactDiscretisation::solve_scaled`] (load steps: body forces, tractions and prescribed
//! displacements scaled together).
//!
//! ```
//! use std::sync::Arc;
//! use vem_contact::{ActiveSetSolver, ContactProblem, Frictionless};
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
//! let problem = ContactProblem::two_bodies(upper, "bottom", lower, "top", Frictionless);
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

use std::borrow::Cow;
use std::ops::Range;
use std::sync::{Arc, OnceLock};
use std::time::{Duration, Instant};

use rayon::prelude::*;

use vem_elastic::{AssembledSystem, DofStatus, ElasticBody, Material};
use vem_mesh::{Point, VectorD};

use crate::history::{NodeState, PathState};
use crate::law::LawState;
use crate::load::{LoadLevel, LoadParts, Scaling};
use crate::pairing::{pair_geometry, ZoneEnd};
use crate::problem::Counterpart;
use crate::result::{
    classify, consistent_traction, BodyResult, BodySummary, ContactResult, FixedPointReport,
    InterfaceNode, ModelSummary, PairSummary, TractionBound,
};
use crate::solver::ForceScales;
use crate::solver::{check_finite, checked_block, matrix_diagonal};
use crate::warning::Warning;
use crate::{
    ConstraintRows, ContactError, ContactLaw, ContactNode, ContactProblem, ContactSolution,
    ContactSolver, ContactSolverError, ContactSystem, FixedPointSettings, Friction, HistoryStep,
    KktResiduals, LoadCondition, LoadFactors, LoadHistory, LoadPath, Location, PatternId,
    SolveReport, SolveStatus, WorkCounters,
};

/// One contact pair as discretised: its law, its nodes in the discretisation's list, and what
/// the reports need.
#[derive(Debug, Clone)]
struct PairData<const D: usize> {
    law: Arc<dyn ContactLaw<D>>,
    nodes: Range<usize>,
    obstacle: bool,
    description: String,
    inserted: usize,
    /// Body A and its contact part.
    body: usize,
    part: String,
    /// The ends of the modelled interface that may cut a contact zone short.
    zone_ends: Vec<ZoneEnd>,
    /// Whether the nodes form a chain (2D), along which the consistent traction is projected.
    chain: bool,
    /// In 3D, the faces (loops of the pair's node indices) on which the consistent pressure is
    /// projected.
    surface: Option<Vec<Vec<usize>>>,
}

/// The discretised contact problem (see the module docs).
#[derive(Debug, Clone)]
pub struct ContactDiscretisation<const D: usize = 2> {
    pattern: PatternId,
    stiffness_version: u64,
    /// Vertices of each body's mesh before the interface insertions (the vertices of the
    /// enlarged meshes below these are original).
    original_vertices: Vec<usize>,
    bodies: Vec<ElasticBody<D>>,
    systems: Vec<Arc<AssembledSystem>>,
    offsets: Vec<usize>,
    pairs: Vec<PairData<D>>,
    nodes: Vec<ContactNode<D>>,
    normal_rows: ConstraintRows,
    /// The part of `[u]_nu` carried by prescribed degrees of freedom, at full load.
    normal_lifting: Vec<f64>,
    /// `D - 1` rows per node (node after node), when some law has friction.
    tangential_rows: Option<ConstraintRows>,
    /// The nodal friction bounds of the first solve (every pair's law without a state); the
    /// bounds of every solve when no law iterates.
    start_bounds: Option<Vec<f64>>,
    load: Vec<f64>,
    /// The diagonal of every body's stiffness (its values checked finite).
    diagonals: Vec<Vec<f64>>,
    /// The warnings about element shapes (see
    /// [`ContactDiscretisation::element_shape_warnings`]).
    element_warnings: Vec<Warning>,
    /// Per body, the rigid translations along the axes that its boundary conditions leave
    /// free and that move no gap (see [`ContactDiscretisation::sliding_beyond_capacity`]):
    /// found at the first Coulomb step, kept until the stiffness changes.
    sliding_modes: OnceLock<Vec<Vec<SlidingMode>>>,
    work: WorkCounters,
}

/// A translation `d` of one body along a coordinate axis, free of boundary conditions, resisted
/// by no stiffness (`K d = 0`) and moving no gap (`B_N d = 0`).
#[derive(Debug, Clone)]
struct SlidingMode {
    /// The system's unknowns `d` moves (by 1 each; a rigid plate's once).
    unknowns: Vec<usize>,
    /// Its tangential jumps `B_T d`.
    slip: Vec<f64>,
}

impl<const D: usize> ContactDiscretisation<D> {
    /// Inserts the interface nodes of every pair (one after the other) or extracts the contact
    /// nodes (obstacle), assembles every body on its enlarged mesh and builds the constraint
    /// rows. The problem is dropped once the interfaces are inserted, before the assembly: the
    /// original meshes and the stiffness are never held together.
    pub(crate) fn try_new(problem: ContactProblem<D>) -> Result<Self, ContactError> {
        let mut work = WorkCounters::default();
        let start = Instant::now();
        let (mut bodies, pairs) = problem.into_parts();
        let original_vertices: Vec<usize> =
            bodies.iter().map(|b| b.body_mesh().n_vertices()).collect();
        check_disjoint_parts(&bodies, &pairs)?;
        let mut nodes = Vec::new();
        let mut pair_data = Vec::with_capacity(pairs.len());
        for (index, pair) in pairs.iter().enumerate() {
            let geometry = pair_geometry(&mut bodies, pair, index)?;
            let first = nodes.len();
            nodes.extend(geometry.nodes);
            let a = bodies[pair.body()].name();
            let description = match pair.counterpart() {
                Counterpart::Body { body, part } => format!(
                    "body '{a}' part '{}' against body '{}' part '{part}'",
                    pair.part(),
                    bodies[*body].name()
                ),
                Counterpart::Obstacle(o) => {
                    format!(
                        "body '{a}' part '{}' against a rigid {}",
                        pair.part(),
                        o.name()
                    )
                }
            };
            pair_data.push(PairData {
                law: Arc::clone(pair.law()),
                nodes: first..nodes.len(),
                obstacle: matches!(pair.counterpart(), Counterpart::Obstacle(_)),
                description,
                inserted: geometry.inserted,
                body: pair.body(),
                part: pair.part().to_string(),
                zone_ends: geometry.zone_ends,
                chain: geometry.chain,
                surface: geometry.surface,
            });
        }
        drop(pairs);
        // The original meshes and the insertion's work are freed: their pages go back to the
        // system before the stiffness is allocated beside the enlarged meshes.
        vem_elastic::release_free_memory();
        work.times.insertion = start.elapsed();
        let start = Instant::now();
        // The bodies side by side (each assembly is parallel itself; side by side their
        // sequential stretches overlap), the first failing body's error reported.
        let systems = bodies
            .par_iter()
            .map(|body| body.assemble().map(Arc::new))
            .collect::<Vec<_>>()
            .into_iter()
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
            original_vertices,
            bodies,
            systems,
            offsets,
            pairs: pair_data,
            nodes,
            normal_rows: ConstraintRows::try_from_triplets(0, 0, &[])?,
            normal_lifting: Vec::new(),
            tangential_rows: None,
            start_bounds: None,
            load,
            diagonals: Vec::new(),
            element_warnings: Vec::new(),
            sliding_modes: OnceLock::new(),
            work,
        };
        discretisation.diagonals = checked_diagonals(&discretisation.systems)?;
        let (normal_rows, normal_lifting) = discretisation.jump_rows(0)?;
        discretisation.normal_rows = normal_rows;
        discretisation.normal_lifting = normal_lifting;
        if discretisation.pairs.iter().any(|p| p.law.has_friction()) {
            discretisation.tangential_rows = Some(discretisation.tangential_rows_checked()?);
        }
        discretisation.start_bounds = discretisation.bounds(None)?;
        discretisation.element_warnings = discretisation.element_shape_warnings();
        discretisation.work.times.assembly = start.elapsed();
        Ok(discretisation)
    }

    /// The identity of the structure shared by every system this discretisation hands out.
    pub fn pattern(&self) -> PatternId {
        self.pattern
    }

    /// The law of pair `pair`.
    pub fn law(&self, pair: usize) -> Option<&Arc<dyn ContactLaw<D>>> {
        self.pairs.get(pair).map(|p| &p.law)
    }

    /// The number of contact pairs.
    pub fn n_pairs(&self) -> usize {
        self.pairs.len()
    }

    /// The nodes of pair `pair` in [`ContactDiscretisation::nodes`].
    pub fn pair_nodes(&self, pair: usize) -> Range<usize> {
        self.pairs.get(pair).map_or(0..0, |p| p.nodes.clone())
    }

    /// The bodies on their enlarged meshes, in the order of the problem.
    pub fn bodies(&self) -> &[ElasticBody<D>] {
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

    /// The interface nodes, pair after pair (each pair's ordered along body A's contact part in
    /// 2D).
    pub fn nodes(&self) -> &[ContactNode<D>] {
        &self.nodes
    }

    /// Vertices inserted by the interface node insertions (all pairs, both sides).
    pub fn inserted_nodes(&self) -> usize {
        self.pairs.iter().map(|p| p.inserted).sum()
    }

    /// The normal rows `B_N` (`(B_N u)_i = [u]_nu` over the free unknowns at node `i`).
    pub fn normal_rows(&self) -> &ConstraintRows {
        &self.normal_rows
    }

    /// The tangential rows `B_T` (`D - 1` per node; only when some law has friction).
    pub fn tangential_rows(&self) -> Option<&ConstraintRows> {
        self.tangential_rows.as_ref()
    }

    /// The load `f` of the free unknowns (body force, tractions and the Dirichlet lifting).
    pub fn load(&self) -> &[f64] {
        &self.load
    }

    /// The gaps `g = h0 - (prescribed part of [u]_nu)` at full load.
    pub fn gap(&self) -> Vec<f64> {
        self.gap_of(&self.normal_lifting)
    }

    /// What building and refilling this discretisation computed (assemblies, times).
    pub fn work(&self) -> WorkCounters {
        self.work
    }

    /// The contact system at full load with the laws' friction bounds of a first solve from
    /// rest (Tresca's bounds; the nodes of a Coulomb pair held, by a bound far above every force
    /// of the problem: the start of its fixed point) or no friction.
    pub fn system(&self) -> ContactSystem<'_> {
        self.system_from(
            Cow::Borrowed(&self.load[..]),
            self.gap_of(&self.normal_lifting),
            self.start_bounds.as_deref().map(Cow::Borrowed),
            None,
        )
    }

    /// The contact system of the level `level` with the friction bounds `bounds` and the
    /// reference slip `reference` (see [`ContactDiscretisation::system_from`]).
    fn system_at<'s>(
        &'s self,
        level: &'s LoadLevel<'_>,
        bounds: Option<Cow<'s, [f64]>>,
        reference: Option<&'s [f64]>,
    ) -> ContactSystem<'s> {
        self.system_from(
            Cow::Borrowed(&level.load[..]),
            self.gap_of(&level.lifting),
            bounds,
            reference,
        )
    }

    /// The contact system with the load `load`, the gaps `gap`, the friction bounds `bounds`
    /// (ignored without tangential rows; zero bounds when `None` and there are tangential rows;
    /// an infinite bound, a held node, becomes [`ContactDiscretisation::hold_bound`]) and the
    /// reference slip `reference` of the friction term (`None`: zero).
    fn system_from<'s>(
        &'s self,
        load: Cow<'s, [f64]>,
        gap: Vec<f64>,
        bounds: Option<Cow<'s, [f64]>>,
        reference: Option<&'s [f64]>,
    ) -> ContactSystem<'s> {
        let blocks = self
            .systems
            .iter()
            .zip(&self.offsets)
            .zip(&self.diagonals)
            .map(|((system, &offset), diagonal)| {
                checked_block(offset, system.stiffness(), diagonal)
            })
            .collect();
        let friction = self.tangential_rows.as_ref().map(|rows| {
            let mut bounds = bounds.unwrap_or_else(|| Cow::Owned(vec![0.0; self.nodes.len()]));
            if bounds.iter().any(|b| b.is_infinite()) {
                let hold = self.hold_bound(&load, &gap, reference);
                for b in bounds.to_mut().iter_mut().filter(|b| b.is_infinite()) {
                    *b = hold;
                }
            }
            let friction = Friction::try_with_rows_per_node(rows, bounds, D - 1)
                .expect("bounds checked when they were made");
            match reference {
                Some(slip) => friction
                    .with_reference_slip(slip)
                    .expect("one finite reference slip per tangential row"),
                None => friction,
            }
        });
        ContactSystem::try_from_parts(
            self.pattern,
            self.stiffness_version,
            blocks,
            load,
            Cow::Borrowed(&self.normal_rows),
            Cow::Owned(gap),
            friction,
        )
        .expect("a discretisation's parts are consistent")
    }

    /// The bound of a held node (a law's `+inf`): `1e6` times the force scale
    /// `sum_j |f_j| + k (sum_i |g_i| + sum_i |s_i|)` (`k` the largest diagonal entry of the
    /// stiffness: the forces that would close every gap and undo every reference slip at the
    /// stiffest unknown), far above any force of the problem, so that the node sticks.
    fn hold_bound(&self, load: &[f64], gap: &[f64], reference: Option<&[f64]>) -> f64 {
        let k = self
            .diagonals
            .iter()
            .flatten()
            .fold(0.0f64, |a, d| a.max(d.abs()));
        let sum = |v: &[f64]| v.iter().map(|x| x.abs()).sum::<f64>();
        let scale = sum(load) + k * (sum(gap) + reference.map_or(0.0, sum));
        HOLD_RATIO * scale.max(f64::MIN_POSITIVE)
    }

    /// The gaps `g = h0 - (prescribed part of [u]_nu)` for the prescribed normal jumps
    /// `lifting`.
    fn gap_of(&self, lifting: &[f64]) -> Vec<f64> {
        self.nodes
            .iter()
            .zip(lifting)
            .map(|(node, lifting)| node.initial_gap - lifting)
            .collect()
    }

    /// The level with every load and prescribed displacement scaled by `load_factor`.
    fn uniform_level(&self, load_factor: f64) -> LoadLevel<'_> {
        let scaled = |v: &[f64]| v.iter().map(|x| load_factor * x).collect::<Vec<f64>>();
        let (load, lifting) = if load_factor == 1.0 {
            (
                Cow::Borrowed(&self.load[..]),
                Cow::Borrowed(&self.normal_lifting[..]),
            )
        } else {
            (
                Cow::Owned(scaled(&self.load)),
                Cow::Owned(scaled(&self.normal_lifting)),
            )
        };
        LoadLevel {
            load,
            lifting,
            scaling: Scaling::Uniform(load_factor),
        }
    }

    /// The nodal friction bounds of every node from each pair's law (given the state `state`
    /// of every node, `None` before any solve), or `None` without tangential rows. A bound may
    /// be `+inf` (a held node).
    fn bounds(&self, state: Option<&NodeState<'_>>) -> Result<Option<Vec<f64>>, ContactError> {
        if self.tangential_rows.is_none() {
            return Ok(None);
        }
        let t = D - 1;
        let mut bounds = Vec::with_capacity(self.nodes.len());
        for pair in &self.pairs {
            let r = pair.nodes.clone();
            let tangential = t * r.start..t * r.end;
            let law_state = state.map(|state| LawState {
                normal_forces: &state.normal_force[r.clone()],
                tangential_forces: &state.tangential_force[tangential.clone()],
                normal_jumps: &state.normal_jump[r.clone()],
                slips: &state.slip[tangential.clone()],
            });
            let values = pair
                .law
                .friction_bounds(&self.nodes[r.clone()], law_state.as_ref())?;
            let values =
                crate::law::checked_bounds(&self.nodes[r.clone()], values, "friction bound", true)?;
            bounds.extend(values);
        }
        Ok(Some(bounds))
    }

    /// Solves with `solver` at full load (see [`ContactDiscretisation::solve_scaled`]).
    ///
    /// # Errors
    /// The solver's failure (with its report), a fixed point that does not settle,
    /// post-processing failures.
    pub fn solve(&self, solver: &mut dyn ContactSolver) -> Result<ContactResult<D>, ContactError> {
        self.solve_scaled(solver, 1.0)
    }

    /// Solves from rest with every load (body forces, tractions, rigid-plate resultants) and
    /// every prescribed displacement scaled by `load_factor` (the gaps are not scaled): the
    /// static problem at that load, whatever was solved before (for a loading whose answer
    /// depends on the path, follow a [`LoadHistory`](crate::LoadHistory) with
    /// [`ContactDiscretisation::solve_history`]). A law whose bounds depend on the state
    /// (Coulomb) is iterated: Tresca solves with the bounds frozen from the previous step (the
    /// first step with the laws' starting bounds: a Coulomb pair's nodes held) until the
    /// normal forces settle. The result's [`work`](ContactResult::work) counts this solve only
    /// (no assembly).
    ///
    /// # Errors
    /// As [`ContactDiscretisation::solve`]; a non-finite `load_factor` is an
    /// [`ContactError::InvalidSetting`].
    pub fn solve_scaled(
        &self,
        solver: &mut dyn ContactSolver,
        load_factor: f64,
    ) -> Result<ContactResult<D>, ContactError> {
        if !load_factor.is_finite() {
            return Err(ContactError::InvalidSetting {
                reason: format!("load factor {load_factor} is not finite"),
            });
        }
        let start = Instant::now();
        let level = self.uniform_level(load_factor);
        let (mut result, _) = self.solve_level(solver, &level, None)?;
        result.model.total_time = start.elapsed();
        Ok(result)
    }

    /// Solves from rest with the loads and prescribed displacements of each condition scaled by
    /// its factor in `factors` (a one-step history, see [`LoadPath`]).
    ///
    /// # Errors
    /// As [`LoadPath::advance`].
    pub fn solve_at(
        &self,
        solver: &mut dyn ContactSolver,
        factors: &LoadFactors,
    ) -> Result<ContactResult<D>, ContactError> {
        LoadPath::new(self)?.advance(solver, 1.0, factors)
    }

    /// Follows the load history `history` from rest, one step after the other, with friction
    /// on the slip increments (see [`LoadPath`]); the answer of every step (each with the
    /// body solutions: for a long history of a large model, step with
    /// [`LoadPath::advance`] and keep what is needed).
    ///
    /// # Errors
    /// As [`LoadPath::run`].
    pub fn solve_history(
        &self,
        solver: &mut dyn ContactSolver,
        history: &LoadHistory,
    ) -> Result<Vec<HistoryStep<D>>, ContactError> {
        LoadPath::new(self)?.run(solver, history)
    }

    /// The conditions a load history can scale ([`LoadCondition`]), each with a description
    /// naming its body, kind and part (`"body 'disc': Dirichlet condition 1 on part 'top'
    /// (x)"`), in the order of the bodies and, per body, body force, Dirichlet conditions,
    /// tractions.
    pub fn load_conditions(&self) -> Vec<(LoadCondition, String)> {
        let mut conditions = Vec::new();
        for (b, body) in self.bodies.iter().enumerate() {
            let name = body.name();
            if body.has_body_force() {
                conditions.push((
                    LoadCondition::BodyForce { body: b },
                    format!("body '{name}': body force"),
                ));
            }
            for (index, condition) in body.dirichlet().iter().enumerate() {
                let kind = if condition.is_rigid_plate() {
                    "rigid plate"
                } else {
                    "Dirichlet condition"
                };
                conditions.push((
                    LoadCondition::Dirichlet { body: b, index },
                    format!(
                        "body '{name}': {kind} {index} on part '{}' ({})",
                        condition.part(),
                        condition.component().name()
                    ),
                ));
            }
            for (index, traction) in body.tractions().iter().enumerate() {
                conditions.push((
                    LoadCondition::Traction { body: b, index },
                    format!(
                        "body '{name}': traction {index} on part '{}'",
                        traction.part()
                    ),
                ));
            }
        }
        conditions
    }

    /// The per-condition parts of the load and of the prescribed normal jumps.
    pub(crate) fn load_parts(&self) -> Result<LoadParts, ContactError> {
        LoadParts::new(&self.bodies, &self.systems, self.lifting_parts())
    }

    /// Solves at the level `level` from the state `previous` at the end of the last step
    /// (`None`: from rest), with the friction on the slip since `previous`; the result and the
    /// state at its end.
    pub(crate) fn solve_level(
        &self,
        solver: &mut dyn ContactSolver,
        level: &LoadLevel<'_>,
        previous: Option<&PathState>,
    ) -> Result<(ContactResult<D>, PathState), ContactError> {
        let start = Instant::now();
        let reference = previous
            .filter(|_| self.tangential_rows.is_some())
            .map(|p| &p.slip[..]);
        let iterated =
            FixedPointSettings::strictest(self.pairs.iter().filter_map(|p| p.law.fixed_point()));
        let (solution, fixed_point, mut work, bounds) = match iterated {
            Some(settings) => self.fixed_point(solver, level, reference, previous, &settings)?,
            None => {
                // A law that does not iterate sees the state at the end of the last step.
                let bounds = match previous {
                    Some(p) => self.bounds(Some(&p.node_state()))?,
                    None => self.start_bounds.clone(),
                };
                let system = self.system_at(level, bounds.as_deref().map(Cow::Borrowed), reference);
                let solution = solver.solve(&system)?;
                let work = solution.report.work;
                (solution, None, work, bounds)
            }
        };
        let state = self.path_state(&solution, &level.lifting);
        let post = Instant::now();
        let mut result = self.collect(
            level,
            solution,
            fixed_point,
            bounds.as_deref(),
            solver.force_accuracy(),
        )?;
        work.times.post = post.elapsed();
        result.work = work;
        result.model.total_time = start.elapsed();
        Ok((result, state))
    }

    /// The state at the end of a step from its answer.
    fn path_state(&self, solution: &ContactSolution, lifting: &[f64]) -> PathState {
        let u = &solution.displacement;
        let mut normal_jump = self.normal_rows.apply(u);
        for (j, l) in normal_jump.iter_mut().zip(lifting) {
            *j += l;
        }
        let (tangential_force, slip) = match &self.tangential_rows {
            Some(rows) => (solution.tangential_force.clone(), rows.apply(u)),
            None => (Vec::new(), Vec::new()),
        };
        PathState {
            normal_force: solution.normal_force.clone(),
            tangential_force,
            normal_jump,
            slip,
        }
    }

    /// Replaces the material of body `body` and refills the stiffness and load values on the
    /// existing patterns (nothing is rebuilt; solvers keep their symbolic work).
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
        self.diagonals = checked_diagonals(&self.systems)?;
        self.load = concatenated_load(&self.systems);
        self.normal_lifting = self.jump_rows(0)?.1;
        self.sliding_modes = OnceLock::new();
        self.stiffness_version += 1;
        self.work.assemblies += 1;
        self.work.times.assembly += start.elapsed();
        Ok(())
    }

    /// Replaces the law of pair `pair`. A law with friction needs tangential rows: a
    /// discretisation built with friction on some pair.
    ///
    /// # Errors
    /// A pair out of range, a law whose data are invalid at the pair's nodes, a law with
    /// friction on a discretisation built without tangential rows.
    pub fn set_law(
        &mut self,
        pair: usize,
        law: Arc<dyn ContactLaw<D>>,
    ) -> Result<(), ContactError> {
        let n_pairs = self.pairs.len();
        let Some(data) = self.pairs.get_mut(pair) else {
            return Err(ContactError::InvalidSetting {
                reason: format!("pair index {pair}: the discretisation has {n_pairs} pairs"),
            });
        };
        if law.has_friction() && self.tangential_rows.is_none() {
            return Err(ContactError::InvalidSetting {
                reason: format!(
                    "the law '{}' needs tangential rows; this discretisation was built without \
                     friction",
                    law.name()
                ),
            });
        }
        let previous = std::mem::replace(&mut data.law, law);
        match self.bounds(None) {
            Ok(bounds) => {
                self.start_bounds = bounds;
                Ok(())
            }
            Err(e) => {
                self.pairs[pair].law = previous;
                Err(e)
            }
        }
    }

    /// Rows `d_k . (u_A - u_B)` at every node for the `k`-th column `d_k` of the node's frame
    /// (0: the normal, `1..D`: the tangents), and the part carried by prescribed degrees of
    /// freedom.
    fn jump_rows(&self, k: usize) -> Result<(ConstraintRows, Vec<f64>), ContactError> {
        self.frame_rows(k..k + 1)
    }

    /// Rows for the frame columns `columns` at every node (node after node, the columns of a
    /// node consecutive), and their prescribed parts.
    fn frame_rows(
        &self,
        columns: Range<usize>,
    ) -> Result<(ConstraintRows, Vec<f64>), ContactError> {
        let per_node = columns.len();
        let mut triplets = Vec::with_capacity(2 * D * per_node * self.nodes.len());
        let mut prescribed_jump = vec![0.0; per_node * self.nodes.len()];
        for (i, node) in self.nodes.iter().enumerate() {
            let frame = node.frame();
            let sides = [(node.body_a, node.vertex_a, 1.0)]
                .into_iter()
                .chain(node.body_b.zip(node.vertex_b).map(|(b, v)| (b, v, -1.0)));
            for (body, vertex, sign) in sides {
                let dofs = self.systems[body].dofs();
                for (c, global) in dofs.vertex_dofs(vertex).enumerate() {
                    for (j, k) in columns.clone().enumerate() {
                        let row = per_node * i + j;
                        let coefficient = sign * frame[(c, k)];
                        match (dofs.unknown_index(global), dofs.status(global)) {
                            // A free value or a rigid plate's translation.
                            (Some(u), _) => {
                                triplets.push((row, self.offsets[body] + u, coefficient))
                            }
                            (None, DofStatus::Prescribed(p)) => {
                                prescribed_jump[row] += coefficient * dofs.prescribed_values()[p]
                            }
                            (None, DofStatus::Free(_)) => {}
                        }
                    }
                }
            }
        }
        let rows = ConstraintRows::try_from_triplets(
            per_node * self.nodes.len(),
            self.n_dofs(),
            &triplets,
        )?;
        Ok((rows, prescribed_jump))
    }

    /// The prescribed part of `[u]_nu` at every node, per Dirichlet condition that prescribes
    /// a value at an interface node: `(body, condition index, values)`. Their sum is
    /// [`ContactDiscretisation::frame_rows`]' prescribed part of the normal rows.
    fn lifting_parts(&self) -> Vec<(usize, usize, Vec<f64>)> {
        let mut parts: Vec<(usize, usize, Vec<f64>)> = Vec::new();
        for (i, node) in self.nodes.iter().enumerate() {
            let normal = node.frame().column(0).into_owned();
            let sides = [(node.body_a, node.vertex_a, 1.0)]
                .into_iter()
                .chain(node.body_b.zip(node.vertex_b).map(|(b, v)| (b, v, -1.0)));
            for (body, vertex, sign) in sides {
                let dofs = self.systems[body].dofs();
                for (c, global) in dofs.vertex_dofs(vertex).enumerate() {
                    if let (None, DofStatus::Prescribed(p)) =
                        (dofs.unknown_index(global), dofs.status(global))
                    {
                        let owner = dofs.prescribed_owners()[p];
                        let value = sign * normal[c] * dofs.prescribed_values()[p];
                        if value == 0.0 {
                            continue;
                        }
                        let k = match parts.iter().position(|&(b, o, _)| b == body && o == owner) {
                            Some(k) => k,
                            None => {
                                parts.push((body, owner, vec![0.0; self.nodes.len()]));
                                parts.len() - 1
                            }
                        };
                        parts[k].2[i] += value;
                    }
                }
            }
        }
        parts
    }

    /// Tangential rows `[u]_tau` of the free unknowns. The prescribed part of the slip is not
    /// representable in `j_h(B_T u)`: it is rejected unless it vanishes.
    fn tangential_rows_checked(&self) -> Result<ConstraintRows, ContactError> {
        let (rows, prescribed) = self.frame_rows(1..D)?;
        if let Some((row, p)) = prescribed.iter().enumerate().find(|(_, p)| p.abs() > 0.0) {
            let node = &self.nodes[row / (D - 1)];
            return Err(ContactError::InvalidSetting {
                reason: format!(
                    "the tangential jump at the interface node {} is prescribed by Dirichlet \
                     data ({p:e}); friction needs a free tangential motion at every contact node",
                    Location::of(&node.position)
                ),
            });
        }
        Ok(rows)
    }

    /// The rigid sliding of a body along the interface against the friction capacity of the
    /// bounds of `system`: for every body whose boundary conditions leave some translations
    /// free (each degree of freedom of the component free or tied to a rigid plate) that the
    /// stiffness does not resist (`K d = 0`) and that open or close no gap (`B_N d = 0`), the
    /// translation `d` along the load's component in their span, scaled to a largest nodal slip
    /// of 1. `Some((f . d, sum_i b_i |(B_T d)_i|))` when the load along `d` exceeds that capacity
    /// (by more than a relative `1e-9`): then no equilibrium exists, since `K d = 0` and
    /// `B_N d = 0` leave `f . d = lambda_T . B_T d <= sum_i b_i |(B_T d)_i|`.
    fn sliding_beyond_capacity(&self, system: &ContactSystem<'_>) -> Option<(f64, f64)> {
        let friction = system.friction()?;
        let t = friction.rows_per_node();
        let modes = self
            .sliding_modes
            .get_or_init(|| self.find_sliding_modes(system));
        for body_modes in modes {
            let loads: Vec<f64> = body_modes
                .iter()
                .map(|mode| mode.unknowns.iter().map(|&u| system.load()[u]).sum())
                .collect();
            let norm = loads.iter().map(|f| f * f).sum::<f64>().sqrt();
            if norm == 0.0 {
                continue;
            }
            let mut slip = vec![0.0; friction.tangential_rows().nrows()];
            for (mode, f) in body_modes.iter().zip(&loads) {
                for (s, m) in slip.iter_mut().zip(&mode.slip) {
                    *s += m * f / norm;
                }
            }
            let nodal: Vec<f64> = slip
                .chunks(t)
                .map(|s| s.iter().map(|x| x * x).sum::<f64>().sqrt())
                .collect();
            let scale = nodal.iter().fold(0.0f64, |m, &x| m.max(x));
            if scale <= 1e-12 {
                continue;
            }
            let load_along_mode = norm / scale;
            let friction_capacity = friction
                .bounds()
                .iter()
                .zip(&nodal)
                .map(|(b, s)| b * s / scale)
                .sum::<f64>();
            if load_along_mode > friction_capacity * (1.0 + 1e-9) {
                return Some((load_along_mode, friction_capacity));
            }
        }
        None
    }

    /// The [`SlidingMode`]s of every body (what [`Self::sliding_beyond_capacity`] checks the
    /// load along): they depend on the structure and the stiffness only, not on the load or
    /// the bounds.
    fn find_sliding_modes(&self, system: &ContactSystem<'_>) -> Vec<Vec<SlidingMode>> {
        let n = system.n_dofs();
        let inf = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let Some(friction) = system.friction() else {
            return Vec::new();
        };
        self.bodies
            .iter()
            .enumerate()
            .map(|(k, body)| {
                let dofs = body.dofs();
                let stiffness_scale = inf(&self.diagonals[k]);
                let mut modes = Vec::new();
                for c in 0..D {
                    let mut unknowns = Vec::new();
                    let mut admissible = true;
                    for dof in 0..dofs.n_dofs() {
                        if dofs.vertex_of(dof).1 != c {
                            continue;
                        }
                        match dofs.unknown_index(dof) {
                            Some(u) => unknowns.push(self.offsets[k] + u),
                            None => {
                                admissible = false;
                                break;
                            }
                        }
                    }
                    if !admissible {
                        continue;
                    }
                    // The degrees of freedom tied to a rigid plate share its unknown.
                    unknowns.sort_unstable();
                    unknowns.dedup();
                    let mut d = vec![0.0; n];
                    for &u in &unknowns {
                        d[u] = 1.0;
                    }
                    let rigid = inf(&system.stiffness_apply(&d)) <= 1e-9 * stiffness_scale;
                    let sliding = inf(&system.normal_rows().apply(&d)) <= 1e-9;
                    if rigid && sliding {
                        let slip = friction.tangential_rows().apply(&d);
                        modes.push(SlidingMode { unknowns, slip });
                    }
                }
                modes
            })
            .collect()
    }

    /// The fixed point of Tresca problems of the laws whose bounds depend on the state
    /// (Coulomb: `b_i = F lambda_N,i` from the previous solve) at the level `level`, with the
    /// friction on the slip since `reference`.
    ///
    /// It starts from the laws' bounds of the state `previous` at the end of the last step (a
    /// history's warm start) when that state carries a normal force, else from their starting
    /// bounds (a Coulomb node held: the stick predictor, which gives the normal forces of the
    /// first Coulomb bounds whatever holds the bodies sideways). A warm start whose solve fails
    /// (its bounds cannot hold the new load) starts again from the held state. The steps between the start
    /// and the last solve ask the solver for the forces only
    /// ([`ContactSolver::solve_forces`]); every step solves a system of the same structure, so
    /// the solver keeps its factorisations.
    #[allow(clippy::type_complexity)]
    fn fixed_point(
        &self,
        solver: &mut dyn ContactSolver,
        level: &LoadLevel<'_>,
        reference: Option<&[f64]>,
        previous: Option<&PathState>,
        settings: &FixedPointSettings,
    ) -> Result<
        (
            ContactSolution,
            Option<FixedPointReport>,
            WorkCounters,
            Option<Vec<f64>>,
        ),
        ContactError,
    > {
        let tolerance = settings.tolerance().max(solver.force_accuracy());
        let warm = previous.filter(|p| p.normal_force.iter().any(|&f| f > 0.0));
        let mut bounds = match warm {
            Some(p) => self.bounds(Some(&p.node_state()))?,
            None => self.bounds(None)?,
        };
        // The normal forces the bounds were made from (`None`: the laws' starting bounds).
        let mut source: Option<Vec<f64>> = warm.map(|p| p.normal_force.clone());
        let mut held = warm.is_none();
        // The relative accuracy asked of the next step's forces (an inexact fixed point: a
        // step far from the fixed point only makes the next step's bounds); exact from a
        // refusal on forces solved loosely on, so that a refusal's figures are exact.
        let mut inexact = true;
        let mut accuracy = FIRST_STEP_ACCURACY;
        // Whether `source` was solved loosely.
        let mut source_loose = false;
        let mut work = WorkCounters::default();
        let (mut iterations, mut steps) = (0, 0);
        let mut history = Vec::with_capacity(settings.max_iterations());
        loop {
            let system = self.system_at(level, bounds.as_deref().map(Cow::Borrowed), reference);
            if source.is_some() {
                // Bounds from normal forces: the load along a rigid sliding mode must not exceed
                // their capacity, or no equilibrium exists (whatever the solver would answer).
                if let Some((load_along_mode, friction_capacity)) =
                    self.sliding_beyond_capacity(&system)
                {
                    if !held || source_loose {
                        // The last step's normal forces cannot carry this step's load: start
                        // again from the held state, whose normal forces decide (exactly, when
                        // they were solved loosely).
                        inexact &= !source_loose;
                        held = true;
                        bounds = self.bounds(None)?;
                        source = None;
                        accuracy = if inexact { FIRST_STEP_ACCURACY } else { 0.0 };
                        continue;
                    }
                    let (n, m) = (system.n_dofs(), system.n_constraints());
                    let residuals = KktResiduals::evaluate(
                        &system,
                        &vec![0.0; n],
                        &vec![0.0; m],
                        &vec![0.0; system.n_tangential()],
                    );
                    return Err(ContactError::FrictionCapacityExceeded {
                        load_along_mode,
                        friction_capacity,
                        step: steps + 1,
                        report: Box::new(SolveReport {
                            solver: solver.name(),
                            status: SolveStatus::Unbounded,
                            iterations,
                            work,
                            wall_time: Duration::ZERO,
                            residuals,
                            warnings: Vec::new(),
                        }),
                    });
                }
            }
            let mut forces = match solver.solve_forces(&system, accuracy) {
                Ok(forces) => forces,
                Err(_) if !held || source_loose => {
                    // The last step's normal forces cannot hold this step's load (the solver
                    // finds the rigid sliding, or fails to converge on a problem without
                    // enough friction capacity): start again from the held state (exactly,
                    // when they were solved loosely), whose error, if any, is the one reported.
                    inexact &= !source_loose;
                    held = true;
                    bounds = self.bounds(None)?;
                    source = None;
                    accuracy = if inexact { FIRST_STEP_ACCURACY } else { 0.0 };
                    continue;
                }
                Err(ContactSolverError::RigidSliding {
                    load_along_mode,
                    friction_capacity,
                    report,
                }) if source.is_some() => {
                    return Err(ContactError::FrictionCapacityExceeded {
                        load_along_mode,
                        friction_capacity,
                        step: steps + 1,
                        report,
                    });
                }
                Err(e) => return Err(e.into()),
            };
            work += forces.work;
            iterations += forces.iterations;
            let mut step_loose = accuracy > 0.0;
            if let Some(source) = &source {
                steps += 1;
                let scale = forces
                    .normal_force
                    .iter()
                    .fold(0.0_f64, |m, &f| m.max(f.abs()))
                    .max(f64::MIN_POSITIVE);
                let change_of = |normal_force: &[f64]| {
                    normal_force
                        .iter()
                        .zip(source)
                        .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()))
                        / scale
                };
                let mut change = change_of(&forces.normal_force);
                if change <= tolerance && step_loose {
                    // A step solved loosely within the tolerance: solved again exactly (warm,
                    // interface work only), whose change decides.
                    forces = solver.solve_forces(&system, 0.0)?;
                    work += forces.work;
                    iterations += forces.iterations;
                    step_loose = false;
                    change = change_of(&forces.normal_force);
                }
                if change <= tolerance {
                    let mut solution = match forces.solution {
                        Some(solution) => solution,
                        None => {
                            let solution = solver.solve(&system)?;
                            work += solution.report.work;
                            solution
                        }
                    };
                    history.push(change);
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
                        steps,
                        residual: change,
                        tolerance,
                        history,
                        solver_iterations: iterations,
                        final_bounds: bounds.clone().unwrap_or_default(),
                    };
                    return Ok((solution, Some(report), work, bounds));
                }
                history.push(change);
                accuracy = if inexact {
                    INEXACT_FRACTION * change
                } else {
                    0.0
                };
                if steps >= settings.max_iterations() {
                    // The report of a complete solve of the last step.
                    let report = match forces.solution {
                        Some(solution) => solution.report,
                        None => solver.solve(&system)?.report,
                    };
                    return Err(ContactError::FixedPointNotConverged {
                        steps,
                        residual: change,
                        tolerance,
                        report: Box::new(report),
                    });
                }
            }
            let next_source = forces.normal_force;
            let mut normal_jump = forces.normal_rows;
            for (j, l) in normal_jump.iter_mut().zip(level.lifting.iter()) {
                *j += l;
            }
            bounds = self.bounds(Some(&NodeState {
                normal_force: &next_source,
                tangential_force: &forces.tangential_force,
                normal_jump: &normal_jump,
                slip: &forces.tangential_rows,
            }))?;
            source = Some(next_source);
            source_loose = step_loose;
        }
    }

    /// Per-body solutions, per-node results, resultants, warnings. Statuses are decided in
    /// the force scales of the acceptance test: node `i` is open when
    /// `lambda_N,i <= theta F_i` and sticks when `|lambda_T,i| < b_i - theta F_i`, with `F_i`
    /// the force scale of its bodies ([`KktResiduals`](crate::KktResiduals)) and
    /// `theta = max(force_accuracy, 1e-8)` (the solver's force accuracy).
    fn collect(
        &self,
        level: &LoadLevel<'_>,
        solution: ContactSolution,
        fixed_point: Option<FixedPointReport>,
        bounds: Option<&[f64]>,
        force_accuracy: f64,
    ) -> Result<ContactResult<D>, ContactError> {
        let t = D - 1;
        let u = &solution.displacement;
        let normal_jump_free = self.normal_rows.apply(u);
        let slip_free = self.tangential_rows.as_ref().map(|rows| rows.apply(u));
        let system = self.system_at(level, bounds.map(Cow::Borrowed), None);
        // The force scales (a product with the whole stiffness) beside the bodies' solutions
        // (each its reactions and energy: a product with its own stiffness), the bodies side
        // by side.
        let ((forces, _), bodies) = rayon::join(
            || {
                ForceScales::of_answer(
                    &system,
                    u,
                    &solution.normal_force,
                    &solution.tangential_force,
                )
            },
            || {
                self.bodies
                    .par_iter()
                    .zip(&self.systems)
                    .enumerate()
                    .map(|(k, (body, system))| {
                        let free = &u[self.offsets[k]..self.offsets[k + 1]];
                        Ok(BodyResult {
                            body: body.clone(),
                            system: Arc::clone(system),
                            solution: level.body_solution(k, body, system, free)?,
                        })
                    })
                    .collect::<Vec<Result<_, ContactError>>>()
            },
        );
        // The first failing body's error, whatever the order the threads finished in.
        let bodies = bodies.into_iter().collect::<Result<Vec<_>, _>>()?;
        let theta = force_accuracy.max(1e-8);
        let mut nodes: Vec<InterfaceNode<D>> = Vec::with_capacity(self.nodes.len());
        for (i, node) in self.nodes.iter().enumerate() {
            let frame = node.frame();
            // [u]_nu = B_N u_free + prescribed part.
            let normal_jump = normal_jump_free[i] + level.lifting[i];
            let normal_force = solution.normal_force[i];
            let (mut slip, mut friction) = (VectorD::<D>::zeros(), VectorD::<D>::zeros());
            if let Some(slips) = &slip_free {
                for k in 0..t {
                    let tangent = frame.column(k + 1).into_owned();
                    slip += tangent * slips[t * i + k];
                    // The friction force on body A opposes the multiplier's slip sign.
                    friction -= tangent * solution.tangential_force[t * i + k];
                }
            }
            let friction_bound = bounds
                .filter(|_| self.pairs[node.pair].law.has_friction())
                .map(|b| b[i]);
            let status = classify(
                normal_force,
                friction.norm(),
                friction_bound,
                theta * forces.rows[i],
            );
            nodes.push(InterfaceNode {
                pair: node.pair,
                position: node.position,
                normal: node.normal,
                tributary_measure: node.tributary_measure,
                initial_gap: node.initial_gap,
                normal_jump,
                normal_force,
                pressure: normal_force / node.tributary_measure,
                consistent_pressure: normal_force / node.tributary_measure,
                friction_force: friction,
                consistent_friction_traction: friction / node.tributary_measure,
                friction_bound: friction_bound.unwrap_or(0.0),
                slip,
                status,
                body_a: node.body_a,
                vertex_a: node.vertex_a,
                body_b: node.body_b,
                vertex_b: node.vertex_b,
            });
        }
        for pair in &self.pairs {
            if pair.chain {
                let friction_bounds = bounds
                    .filter(|_| pair.law.has_friction())
                    .map(|b| &b[pair.nodes.clone()]);
                self.project_tractions(&mut nodes[pair.nodes.clone()], friction_bounds);
            } else if let Some(faces) = &pair.surface {
                project_surface_pressure(&mut nodes[pair.nodes.clone()], faces);
            }
        }
        let mut warnings = solution.report.warnings.clone();
        warnings.extend(self.model_warnings(&nodes, bounds, forces.global(), &solution.report));
        let model = ModelSummary {
            solver: solution.report.solver,
            bodies: bodies
                .iter()
                .map(|b| BodySummary {
                    name: b.body.name().to_string(),
                    vertices: b.body.body_mesh().n_vertices(),
                    polygons: b.body.body_mesh().n_cells(),
                    free_dofs: b.system.dofs().n_free(),
                    prescribed_dofs: b.system.dofs().n_prescribed(),
                })
                .collect(),
            pairs: self
                .pairs
                .iter()
                .map(|p| PairSummary {
                    law: p.law.describe(),
                    law_name: p.law.name().to_string(),
                    description: p.description.clone(),
                    obstacle: p.obstacle,
                    nodes: p.nodes.clone(),
                    inserted_nodes: p.inserted,
                })
                .collect(),
            normal_rows: self.normal_rows.nrows(),
            tangential_rows: self
                .tangential_rows
                .as_ref()
                .map_or(0, ConstraintRows::nrows),
            inserted_nodes: self.inserted_nodes(),
            total_time: Duration::ZERO,
        };
        let mut result = ContactResult::new(bodies, nodes, solution.report, fixed_point, model);
        result.warnings = warnings;
        Ok(result)
    }

    /// The consistent pressure and friction traction of the nodes of one planar pair, projected
    /// along their chain ([`consistent_traction`]): the pressure non-negative, the friction
    /// traction within the projection of the pair's nodal friction bounds `friction_bounds`
    /// (`None` without friction: the friction traction stays zero).
    fn project_tractions(&self, nodes: &mut [InterfaceNode<D>], friction_bounds: Option<&[f64]>) {
        if D != 2 {
            return;
        }
        let positions: Vec<Point> = nodes
            .iter()
            .map(|n| Point::new(n.position[0], n.position[1]))
            .collect();
        let lengths: Vec<f64> = nodes.iter().map(|n| n.tributary_measure).collect();
        let normal_forces: Vec<f64> = nodes.iter().map(|n| n.normal_force).collect();
        let support = self.projection_support(nodes);
        let pressures = consistent_traction(
            &positions,
            &normal_forces,
            &support,
            &lengths,
            TractionBound::NonNegative,
        );
        for (node, p) in nodes.iter_mut().zip(pressures) {
            node.consistent_pressure = p;
        }
        let Some(friction_bounds) = friction_bounds else {
            return;
        };
        // The friction force along the tangent tau = (-nu_y, nu_x).
        let tangent = |n: &InterfaceNode<D>| {
            let mut tau = VectorD::<D>::zeros();
            tau[0] = -n.normal[1];
            tau[1] = n.normal[0];
            tau
        };
        let friction_forces: Vec<f64> = nodes
            .iter()
            .map(|n| n.friction_force.dot(&tangent(n)))
            .collect();
        let tractions = consistent_traction(
            &positions,
            &friction_forces,
            &support,
            &lengths,
            TractionBound::Magnitude(friction_bounds),
        );
        for (node, t) in nodes.iter_mut().zip(tractions) {
            node.consistent_friction_traction = tangent(node) * t;
        }
    }

    /// The nodes whose hats span the space of the consistent pressure of one pair: the
    /// original nodes (not inserted) of the side with fewer of them on the interface (B on a
    /// tie); every node against an obstacle.
    fn projection_support(&self, nodes: &[InterfaceNode<D>]) -> Vec<bool> {
        let original_a: Vec<bool> = nodes
            .iter()
            .map(|n| n.vertex_a < self.original_vertices[n.body_a])
            .collect();
        if nodes.iter().any(|n| n.body_b.is_none()) {
            return vec![true; nodes.len()];
        }
        let original_b: Vec<bool> = nodes
            .iter()
            .map(|n| {
                n.body_b
                    .zip(n.vertex_b)
                    .is_some_and(|(b, v)| v < self.original_vertices[b])
            })
            .collect();
        let count = |v: &[bool]| v.iter().filter(|&&b| b).count();
        if count(&original_a) < count(&original_b) {
            original_a
        } else {
            original_b
        }
    }

    /// The elements far outside A1 (the five worst per body, [`Warning::ElementShape`]): they
    /// depend on the meshes only, and are found once, when the discretisation is built.
    fn element_shape_warnings(&self) -> Vec<Warning> {
        let mut warnings = Vec::new();
        for body in &self.bodies {
            warnings.extend(element_warnings(body));
        }
        warnings
    }

    /// Warnings about the model behind a converged answer, each once: elements far outside
    /// A1 (found at build), and per pair a contact zone at a limit of the interface that is not
    /// a geometric end of the contact, no node in contact, the normal force concentrated on one
    /// node, a penetration large against the displacement scale, an initial overlap, an
    /// effectively tied friction bound.
    fn model_warnings(
        &self,
        nodes: &[InterfaceNode<D>],
        bounds: Option<&[f64]>,
        force_scale: f64,
        report: &crate::SolveReport,
    ) -> Vec<Warning> {
        let mut warnings = self.element_warnings.clone();
        let name = |body: usize| self.bodies[body].name().to_string();
        for pair in &self.pairs {
            let pair_nodes = &nodes[pair.nodes.clone()];
            let mut warned: Vec<usize> = Vec::new();
            // On a surface (3D) the rim has many nodes: one warning per pair, at the rim node
            // with the largest normal force.
            let mut ends: Vec<&ZoneEnd> = pair.zone_ends.iter().collect();
            if !pair.chain {
                ends = ends
                    .into_iter()
                    .filter(|end| pair_nodes[end.node].status.is_active())
                    .max_by(|a, b| {
                        pair_nodes[a.node]
                            .normal_force
                            .total_cmp(&pair_nodes[b.node].normal_force)
                    })
                    .into_iter()
                    .collect();
            }
            for end in ends {
                let node = &pair_nodes[end.node];
                if node.status.is_active() && !warned.contains(&end.node) {
                    warned.push(end.node);
                    warnings.push(Warning::ContactZoneAtLimit {
                        limit: end.limit,
                        body: name(end.body),
                        part: end.part.clone(),
                        at: Location::of(&node.position),
                        normal_force: node.normal_force,
                    });
                }
            }
            let active = pair_nodes.iter().filter(|n| n.status.is_active()).count();
            let gap = |n: &InterfaceNode<D>| n.initial_gap - n.normal_jump;
            if active == 0 {
                if let Some(closest) = pair_nodes.iter().min_by(|a, b| gap(a).total_cmp(&gap(b))) {
                    warnings.push(Warning::NoContact {
                        pair: pair.description.clone(),
                        nodes: pair_nodes.len(),
                        gap: gap(closest),
                        at: Location::of(&closest.position),
                    });
                }
            }
            let resultant: f64 = pair_nodes.iter().map(|n| n.normal_force.max(0.0)).sum();
            let peak = pair_nodes
                .iter()
                .max_by(|a, b| a.normal_force.total_cmp(&b.normal_force));
            if let Some(peak) = peak.filter(|_| pair_nodes.len() >= CONCENTRATION_MIN_NODES) {
                let fraction = peak.normal_force / resultant;
                if resultant > 0.0 && fraction > CONCENTRATION_FRACTION {
                    warnings.push(Warning::ConcentratedPressure {
                        body: name(pair.body),
                        part: pair.part.clone(),
                        at: Location::of(&peak.position),
                        fraction,
                        active,
                    });
                }
            }
            let scale = report.residuals.scales.displacement;
            let deepest = pair_nodes
                .iter()
                .max_by(|a, b| (-gap(a)).total_cmp(&(-gap(b))))
                .filter(|n| -gap(n) > PENETRATION_RATIO * scale && scale > 0.0);
            if let Some(node) = deepest {
                warnings.push(Warning::Penetration {
                    solver: report.solver,
                    body: name(pair.body),
                    part: pair.part.clone(),
                    at: Location::of(&node.position),
                    penetration: -gap(node),
                    displacement_scale: scale,
                    ratio: -gap(node) / scale,
                });
            }
            warnings.extend(Warning::initial_overlap(
                pair_nodes
                    .iter()
                    .map(|n| (n.position, n.normal, n.initial_gap)),
            ));
            let tresca_like = pair.law.has_friction() && pair.law.fixed_point().is_none();
            if let (Some(bounds), true) = (bounds, tresca_like) {
                // The smallest bound among the nodes in contact: if even it exceeds every
                // force by far, no node can slip.
                let tied = pair_nodes
                    .iter()
                    .zip(&bounds[pair.nodes.clone()])
                    .filter(|(n, _)| n.status.is_active())
                    .min_by(|a, b| a.1.total_cmp(b.1));
                if let Some((node, &bound)) = tied {
                    if bound > TIED_RATIO * force_scale && force_scale > 0.0 {
                        warnings.push(Warning::EffectivelyTied {
                            body: name(pair.body),
                            part: pair.part.clone(),
                            at: Location::of(&node.position),
                            bound,
                            ratio: bound / force_scale,
                        });
                    }
                }
            }
        }
        warnings
    }
}

/// The consistent pressure of the nodes of one pair in space, projected on the faces `faces`
/// (loops of the pair's node indices; [`crate::surface::surface_pressure`]).
fn project_surface_pressure<const D: usize>(nodes: &mut [InterfaceNode<D>], faces: &[Vec<usize>]) {
    if D != 3 {
        return;
    }
    let points: Vec<vem_mesh::Point3> = nodes
        .iter()
        .map(|n| vem_mesh::Point3::new(n.position[0], n.position[1], n.position[2]))
        .collect();
    let forces: Vec<f64> = nodes.iter().map(|n| n.normal_force).collect();
    let areas: Vec<f64> = nodes.iter().map(|n| n.tributary_measure).collect();
    let pressures = crate::surface::surface_pressure(faces, &points, &forces, &areas);
    for (node, p) in nodes.iter_mut().zip(pressures) {
        node.consistent_pressure = p;
    }
}

/// The elements of `body` far outside A1 where it matters ([`Warning::ElementShape`]): a star
/// ratio below [`STAR_RATIO_FLOOR`] or an edge ratio below [`EDGE_RATIO_FLOOR`], the worst
/// [`MAX_ELEMENT_WARNINGS`] first.
fn element_warnings<const D: usize>(body: &ElasticBody<D>) -> Vec<Warning> {
    let mesh = body.body_mesh();
    let mut poor: Vec<(usize, vem_mesh::quality::ElementQuality)> = (0..mesh.n_cells())
        .into_par_iter()
        .map(|c| (c, mesh.cell_quality(c)))
        .filter(|(_, q)| {
            !(q.star_ratio >= STAR_RATIO_FLOOR && q.shortest_edge_ratio >= EDGE_RATIO_FLOOR)
        })
        .collect();
    // The worst relative to its floor first.
    let badness = |q: &vem_mesh::quality::ElementQuality| {
        (q.star_ratio / STAR_RATIO_FLOOR).min(q.shortest_edge_ratio / EDGE_RATIO_FLOOR)
    };
    poor.sort_by(|a, b| badness(&a.1).total_cmp(&badness(&b.1)));
    poor.into_iter()
        .take(MAX_ELEMENT_WARNINGS)
        .map(|(element, q)| {
            let vertices = mesh.cell_vertices(element);
            let points = mesh.points();
            let centroid = vertices
                .iter()
                .fold(VectorD::<D>::zeros(), |acc, &v| acc + points[v].coords)
                / vertices.len().max(1) as f64;
            Warning::ElementShape {
                body: body.name().to_string(),
                element,
                at: Location::of_vector(&centroid),
                gamma: q.gamma(),
                shortest_edge_ratio: q.shortest_edge_ratio,
                star_ratio: q.star_ratio,
                diameter: q.diameter,
            }
        })
        .collect()
}

/// The relative accuracy asked of the forces of a fixed point's first step (from the held
/// start, or from the last load step's state): they only make the first bounds.
const FIRST_STEP_ACCURACY: f64 = 1e-4;
/// A later step asks for its forces to this fraction of the last step's change (at least the
/// solver's own accuracy); a step whose change is within the tolerance is solved completely
/// and judged on that solve.
const INEXACT_FRACTION: f64 = 1e-2;

/// Elements star-shaped only with respect to a ball smaller than this fraction of their
/// diameter are reported ([`Warning::ElementShape`]); the meshes of the generators and of Gmsh
/// give 0.17 to 0.35.
const STAR_RATIO_FLOOR: f64 = 1e-3;
/// Elements with an edge shorter than this fraction of their diameter are reported
/// ([`Warning::ElementShape`]): far below what interface node insertion makes (its
/// `min_edge_fraction`, 1e-3 of the edge it cuts); measured harmless down to 7e-9 on the
/// interface, an interior point solver lost accuracy on meshes of such cells only.
const EDGE_RATIO_FLOOR: f64 = 1e-6;
/// At most this many element warnings per body (the worst first).
const MAX_ELEMENT_WARNINGS: usize = 5;
/// A pair of at least this many nodes whose largest nodal normal force exceeds this fraction
/// of their resultant concentrates its pressure on one node ([`Warning::ConcentratedPressure`]).
const CONCENTRATION_MIN_NODES: usize = 3;
const CONCENTRATION_FRACTION: f64 = 0.5;
/// A penetration above this fraction of the displacement scale is reported
/// ([`Warning::Penetration`]): on M2 (quads, n = 64) the penalty's energy error is 9 times the
/// exact answer's at 2e-2, 1.35 times at 2e-3, 1.004 times at 2e-4.
const PENETRATION_RATIO: f64 = 1e-3;
/// A friction bound this many times the force scale makes the contact effectively tied.
const TIED_RATIO: f64 = 1e6;
/// The bound of a held node, relative to the force scale of
/// [`ContactDiscretisation::hold_bound`].
const HOLD_RATIO: f64 = 1e6;

/// The diagonal of every body's stiffness, after checking that its values are finite.
fn checked_diagonals(systems: &[Arc<AssembledSystem>]) -> Result<Vec<Vec<f64>>, ContactError> {
    systems
        .iter()
        .map(|system| {
            let k = system.stiffness();
            check_finite("stiffness values", k.val()).map_err(ContactError::System)?;
            Ok(matrix_diagonal(k.as_ref()))
        })
        .collect()
}

/// The load vectors of the bodies, one after the other.
fn concatenated_load(systems: &[Arc<AssembledSystem>]) -> Vec<f64> {
    systems
        .iter()
        .flat_map(|s| s.rhs().iter().copied())
        .collect()
}

/// Two pairs may share a body but not a vertex of their contact parts on it (a later insertion
/// would change the earlier pair's geometry).
fn check_disjoint_parts<const D: usize>(
    bodies: &[ElasticBody<D>],
    pairs: &[crate::ContactPair<D>],
) -> Result<(), ContactError> {
    let mut sides: Vec<(usize, &str, usize)> = Vec::new();
    for (k, pair) in pairs.iter().enumerate() {
        sides.push((pair.body(), pair.part(), k));
        if let Counterpart::Body { body, part } = pair.counterpart() {
            sides.push((*body, part, k));
        }
    }
    for (i, &(body, part, k)) in sides.iter().enumerate() {
        let Some(mesh) = bodies.get(body).map(|b| b.body_mesh()) else {
            continue; // reported by the pairing
        };
        let Ok(first) = mesh.part_vertices(part) else {
            continue; // reported by the pairing, with the parts listed
        };
        for &(other_body, other_part, l) in &sides[i + 1..] {
            if other_body != body || l == k {
                continue;
            }
            let Ok(second) = mesh.part_vertices(other_part) else {
                continue;
            };
            if let Some(v) = first.iter().find(|v| second.binary_search(v).is_ok()) {
                return Err(ContactError::InvalidSetting {
                    reason: format!(
                        "contact pairs {k} and {l} share vertex {v} of body '{}' (parts \
                         '{part}' and '{other_part}'): contact parts of one body must not touch",
                        bodies[body].name()
                    ),
                });
            }
        }
    }
    Ok(())
}
