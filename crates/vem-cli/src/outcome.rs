//! Solving a [`Model`] and summarising what was computed: per body (mesh actually solved,
//! DOFs, reactions, stresses, A1 figures), for the contact pair (rows, solver, iterations, KKT
//! residuals, resultants, node statuses, the Hertz comparison), and the times.

use std::fmt;
use std::time::{Duration, Instant};

use serde::Serialize;
use vem_contact::{
    ContactError, ContactNode, ContactResult, ContactSolverError, InterfaceNode, NodeStatus,
    Obstacle,
};
use vem_elastic::{CholeskySolver, Component, ElasticBody, ElementField, Plane, Solution};
use vem_mesh::quality::ElementQuality;

use crate::model::{describe_material, young_poisson, ModelCounterpart};
use crate::{CliError, Model};

/// One body after the solve.
#[derive(Debug, Clone)]
pub struct SolvedBody {
    /// The body on the mesh that was solved (with the inserted interface nodes for a contact
    /// body).
    pub body: ElasticBody,
    /// Displacement, reactions, strain energy.
    pub solution: Solution,
    /// Strain, stress and von Mises stress of every element.
    pub fields: Vec<ElementField>,
    /// The A1 figures of every element.
    pub qualities: Vec<ElementQuality>,
}

/// The result of solving a scene, with its summary.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// Every body, in the order of the scene file.
    pub bodies: Vec<SolvedBody>,
    /// The contact result, when the scene has a contact pair. Its `bodies` have been moved
    /// into [`Outcome::bodies`]; nodes, report, fixed point and model summary are here.
    pub contact: Option<ContactResult>,
    /// The rigid obstacle, if the contact pair has one (for pictures).
    pub obstacle: Option<Obstacle>,
    /// What was computed, as printed and written to `summary.json`.
    pub summary: RunSummary,
    /// Indices into [`Outcome::bodies`] of body A and (if any) body B of the contact pair.
    pub(crate) contact_bodies: Option<Vec<usize>>,
    /// The scene's `[output] magnification`.
    pub(crate) magnification: Option<f64>,
    /// The scene's `[output] width`.
    pub(crate) output_width: Option<f64>,
    pub(crate) started: Instant,
}

/// "initial gaps from g0 to g1 (N nodes)" for an interface without overlap.
fn gap_range(nodes: &[ContactNode]) -> String {
    let (lo, hi) = nodes
        .iter()
        .map(|n| n.initial_gap)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), g| {
            (lo.min(g), hi.max(g))
        });
    if nodes.is_empty() {
        "no interface nodes".to_string()
    } else {
        format!(
            "initial gaps from {lo:.3e} to {hi:.3e} at its {} nodes",
            nodes.len()
        )
    }
}

impl Model {
    /// Solves the scene: the contact pair with its bodies by the contact library, every other
    /// body as plain elasticity (assembly and sparse Cholesky).
    pub fn solve(&self) -> Result<Outcome, CliError> {
        let now = Instant::now();
        let started = now.checked_sub(self.mesh_time()).unwrap_or(now);
        let mut slots: Vec<Option<(ElasticBody, Solution)>> = vec![None; self.bodies().len()];
        let mut times = Times {
            mesh_s: self.mesh_time().as_secs_f64(),
            ..Times::default()
        };
        let mut contact = None;
        let mut obstacle = None;
        let mut contact_bodies = None;
        if let Some(c) = self.contact() {
            let mut solver = self.make_solver(c)?;
            let start = Instant::now();
            let discretisation = c
                .problem
                .discretise()
                .map_err(|e| crate::model::locate_contact(self.scene(), e))?;
            let overlap = vem_contact::Warning::initial_overlap(
                discretisation
                    .nodes()
                    .iter()
                    .map(|n| (n.position, n.normal, n.initial_gap)),
            );
            let mut result =
                discretisation
                    .solve(solver.as_mut())
                    .map_err(|e| match (e, &overlap) {
                        (
                            ContactError::Solver(source @ ContactSolverError::Unbounded { .. }),
                            overlap,
                        ) => CliError::NoSupport {
                            pair: self.describe_contact(c),
                            gaps: overlap.as_ref().map_or_else(
                                || gap_range(discretisation.nodes()),
                                |o| o.to_string(),
                            ),
                            source: Box::new(ContactError::Solver(source)),
                        },
                        (e, _) => crate::model::locate_contact(self.scene(), e),
                    })?;
            let mut work = discretisation.work();
            work += result.work;
            result.work = work;
            result.model.total_time = start.elapsed();
            let stages = result.work.times;
            times.assembly_s += (stages.insertion + stages.assembly).as_secs_f64();
            times.solve_s += stages.contact_solve.as_secs_f64();
            let mut solved = std::mem::take(&mut result.bodies).into_iter();
            let owners = std::iter::once(c.body).chain(match &c.counterpart {
                ModelCounterpart::Body { index, .. } => Some(*index),
                ModelCounterpart::Obstacle(o) => {
                    obstacle = Some(o.clone());
                    None
                }
            });
            let mut indices = Vec::with_capacity(2);
            for index in owners {
                if let Some(b) = solved.next() {
                    slots[index] = Some((b.body, b.solution));
                    indices.push(index);
                }
            }
            contact_bodies = Some(indices);
            contact = Some(result);
        }
        for (index, slot) in slots.iter_mut().enumerate() {
            if slot.is_none() {
                let body = &self.bodies()[index].body;
                let start = Instant::now();
                let system = body
                    .assemble()
                    .map_err(|e| crate::model::locate_elastic(self.scene(), e))?;
                times.assembly_s += start.elapsed().as_secs_f64();
                let start = Instant::now();
                let solution = body
                    .solve_system(&system, &mut CholeskySolver::default())
                    .map_err(|e| crate::model::locate_elastic(self.scene(), e))?;
                times.solve_s += start.elapsed().as_secs_f64();
                *slot = Some((body.clone(), solution));
            }
        }
        let start = Instant::now();
        let bodies = slots
            .into_iter()
            .flatten()
            .map(|(body, solution)| {
                let fields = body
                    .element_fields(solution.displacement())
                    .map_err(|e| crate::model::locate_elastic(self.scene(), e))?;
                let qualities = vem_mesh::quality::element_qualities(body.mesh());
                Ok(SolvedBody {
                    body,
                    solution,
                    fields,
                    qualities,
                })
            })
            .collect::<Result<Vec<_>, CliError>>()?;
        times.post_s = start.elapsed().as_secs_f64();
        let summary = self.summarise(&bodies, contact.as_ref(), times);
        let output = &self.scene().file().output;
        Ok(Outcome {
            bodies,
            contact,
            obstacle,
            summary,
            contact_bodies,
            magnification: output.magnification.as_ref().map(|m| *m.get_ref()),
            output_width: output.width.as_ref().map(|w| *w.get_ref()),
            started,
        })
    }

    fn summarise(
        &self,
        bodies: &[SolvedBody],
        contact: Option<&ContactResult>,
        mut times: Times,
    ) -> RunSummary {
        let body_summaries = bodies
            .iter()
            .zip(self.bodies())
            .map(|(solved, built)| {
                let mesh = solved.body.mesh();
                let dofs = solved.body.dofs();
                let displacements = solved.solution.vertex_displacements();
                BodySummary {
                    name: solved.body.name().to_string(),
                    mesh: built.mesh_source.clone(),
                    predicted_error: built.predicted_error,
                    vertices: mesh.n_vertices(),
                    inserted_vertices: mesh.n_vertices() - built.body.mesh().n_vertices(),
                    polygons: mesh.n_polygons(),
                    free_dofs: dofs.n_free(),
                    prescribed_dofs: dofs.n_prescribed(),
                    material: describe_material(solved.body.material()),
                    mesh_size: solved
                        .qualities
                        .iter()
                        .map(|q| q.diameter)
                        .fold(0.0, f64::max),
                    gamma: solved
                        .qualities
                        .iter()
                        .map(ElementQuality::gamma)
                        .fold(f64::INFINITY, f64::min),
                    strain_energy: solved.solution.strain_energy(),
                    max_displacement: displacements.iter().map(|u| u.norm()).fold(0.0, f64::max),
                    max_von_mises: solved
                        .fields
                        .iter()
                        .map(|f| f.von_mises)
                        .fold(0.0, f64::max),
                    reactions: solved
                        .solution
                        .reactions()
                        .iter()
                        .zip(solved.body.dirichlet())
                        .map(|(r, condition)| ReactionSummary {
                            rigid_plate: condition.is_rigid_plate(),
                            part: r.part.clone(),
                            components: match r.component {
                                Component::All => "x, y",
                                other => other.name(),
                            },
                            force: [tidy(r.force.x), tidy(r.force.y)],
                        })
                        .collect(),
                }
            })
            .collect();
        let contact_summary = match (self.contact(), contact) {
            (Some(c), Some(result)) => {
                let (open, stick, slip) = result.status_counts();
                let report = &result.report;
                let r = &report.residuals;
                let force = result.force_on_body_a();
                let spec = self.scene().file().contacts.first().map(|c| c.get_ref());
                let value = |v: Option<&toml::Spanned<f64>>| v.map(|v| *v.get_ref());
                let (friction_bound, coefficient) = (
                    value(spec.and_then(|s| s.friction_bound.as_ref())),
                    value(spec.and_then(|s| s.coefficient.as_ref())),
                );
                Some(ContactSummary {
                    pair: self.describe_contact(c),
                    law: result.model.pairs[0].law_name.clone(),
                    friction_bound,
                    coefficient,
                    obstacle_meshed: false,
                    normal_rows: result.model.normal_rows,
                    tangential_rows: result.model.tangential_rows,
                    inserted_nodes: result.model.inserted_nodes,
                    solver: report.solver,
                    status: format!("{:?}", report.status),
                    iterations: report.iterations,
                    work: result.work.into(),
                    warnings: result.warnings.iter().map(|w| w.to_string()).collect(),
                    residuals: Residuals {
                        force_scale: r.scales.force,
                        displacement_scale: r.scales.displacement,
                        max_penetration: r.max_penetration,
                        negative_normal_force: r.negative_normal_force,
                        complementarity: r.complementarity,
                        stationarity: r.stationarity,
                        friction_bound_violation: r.friction_bound_violation,
                        slip_direction_violation: r.slip_direction_violation,
                    },
                    fixed_point: result.fixed_point.as_ref().map(|fp| FixedPointSummary {
                        steps: fp.steps,
                        residual: fp.residual,
                        history: fp.history.clone(),
                        solver_iterations: fp.solver_iterations,
                    }),
                    resultants: Resultants {
                        load: tidy(force.y),
                        normal: tidy(result.normal_resultant()),
                        tangential: tidy(result.tangential_resultant()),
                        force_on_body_a: [tidy(force.x), tidy(force.y)],
                    },
                    nodes: if result.model.tangential_rows == 0 {
                        NodeCounts {
                            total: result.nodes.len(),
                            open,
                            stick,
                            slip: 0,
                            contact: slip,
                        }
                    } else {
                        NodeCounts {
                            total: result.nodes.len(),
                            open,
                            stick,
                            slip,
                            contact: 0,
                        }
                    },
                    hertz: c.hertz_radius.map(|radius| {
                        let a = &self.bodies()[c.body].body;
                        let b = match &c.counterpart {
                            ModelCounterpart::Body { index, .. } => {
                                Some(&self.bodies()[*index].body)
                            }
                            ModelCounterpart::Obstacle(_) => None,
                        };
                        HertzComparison::new(radius, a, b, &result.nodes)
                    }),
                })
            }
            _ => None,
        };
        times.total_s = times.mesh_s + times.assembly_s + times.solve_s + times.post_s;
        RunSummary {
            scene: self.scene().path().display().to_string(),
            title: self.scene().title(),
            bodies: body_summaries,
            contact: contact_summary,
            times,
        }
    }
}

impl Outcome {
    /// The summary (its output and total times are set by [`Outcome::write`]).
    pub fn summary(&self) -> &RunSummary {
        &self.summary
    }

    /// The solved body named `name`.
    pub fn body(&self, name: &str) -> Option<&SolvedBody> {
        self.bodies.iter().find(|b| b.body.name() == name)
    }

    pub(crate) fn set_output_time(&mut self, output: Duration) {
        self.summary.times.output_s = output.as_secs_f64();
        self.summary.times.total_s = self.started.elapsed().as_secs_f64();
    }
}

/// `value` with a negative zero turned into 0 (a frictionless law's tangential resultant
/// sums `-0.0` terms), so that reports do not print "-0".
pub(crate) fn tidy(value: f64) -> f64 {
    value + 0.0
}

/// Everything `vem run` reports, printed as text and written as `summary.json`.
#[derive(Debug, Clone, Serialize)]
pub struct RunSummary {
    /// The scene file.
    pub scene: String,
    /// Its title.
    pub title: String,
    /// Every body.
    pub bodies: Vec<BodySummary>,
    /// The contact pair, if any.
    pub contact: Option<ContactSummary>,
    /// Wall-clock times in seconds.
    pub times: Times,
}

/// One body in the summary.
#[derive(Debug, Clone, Serialize)]
pub struct BodySummary {
    /// Name.
    pub name: String,
    /// Where the mesh came from.
    pub mesh: String,
    /// Vertices of the mesh solved (with inserted interface nodes).
    pub vertices: usize,
    /// Vertices inserted by the interface node insertion.
    pub inserted_vertices: usize,
    /// Polygons.
    pub polygons: usize,
    /// Unknowns (free degrees of freedom).
    pub free_dofs: usize,
    /// Prescribed (Dirichlet) degrees of freedom.
    pub prescribed_dofs: usize,
    /// The material.
    pub material: String,
    /// Mesh size h (largest polygon diameter).
    pub mesh_size: f64,
    /// In a scene with `accuracy` or `target_error`, a generated mesh: the relative energy
    /// error `E_grad / |u|_1` the error model predicts for its size.
    pub predicted_error: Option<f64>,
    /// Smallest A1 ratio of the mesh solved.
    pub gamma: f64,
    /// Discrete strain energy.
    pub strain_energy: f64,
    /// Largest vertex displacement.
    pub max_displacement: f64,
    /// Largest element von Mises stress.
    pub max_von_mises: f64,
    /// Reactions of the Dirichlet conditions.
    pub reactions: Vec<ReactionSummary>,
}

/// The reaction of one Dirichlet condition.
#[derive(Debug, Clone, Serialize)]
pub struct ReactionSummary {
    /// The part.
    pub part: String,
    /// The prescribed components ("x", "y", "x, y").
    pub components: &'static str,
    /// True for a rigid plate (force control): `force` is then the prescribed resultant.
    pub rigid_plate: bool,
    /// The force the support exerts on the body.
    pub force: [f64; 2],
}

/// The contact pair in the summary.
#[derive(Debug, Clone, Serialize)]
pub struct ContactSummary {
    /// Which parts face what.
    pub pair: String,
    /// The law.
    pub law: String,
    /// Tresca: the friction bound.
    pub friction_bound: Option<f64>,
    /// Coulomb: the friction coefficient.
    pub coefficient: Option<f64>,
    /// Always false: a rigid obstacle is a gap function.
    pub obstacle_meshed: bool,
    /// Normal constraint rows (one per interface node).
    pub normal_rows: usize,
    /// Tangential rows (zero when frictionless).
    pub tangential_rows: usize,
    /// Vertices inserted to make the interface node-to-node.
    pub inserted_nodes: usize,
    /// The solver.
    pub solver: &'static str,
    /// How its (last) run ended.
    pub status: String,
    /// Its iterations (of the last solve; see `fixed_point` for Coulomb's total).
    pub iterations: usize,
    /// What the contact problem cost, build and every solve together (one assembly per body
    /// and one symbolic analysis for a Coulomb fixed point of any number of steps).
    pub work: Work,
    /// KKT residuals of the answer, relative to the problem's scales.
    pub residuals: Residuals,
    /// Warnings about the answer (solver and model), one sentence each.
    pub warnings: Vec<String>,
    /// Coulomb: the fixed point.
    pub fixed_point: Option<FixedPointSummary>,
    /// Resultant contact forces.
    pub resultants: Resultants,
    /// Node statuses.
    pub nodes: NodeCounts,
    /// The Hertz comparison, if asked for.
    pub hertz: Option<HertzComparison>,
}

/// The work counters of the contact problem (see `vem_contact::WorkCounters`); times in
/// seconds.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Work {
    /// Global assemblies (one per body and build).
    pub assemblies: usize,
    /// Symbolic analyses (or set-ups of an external solver).
    pub symbolic_analyses: usize,
    /// Numeric factorisations (for the interior point: one KKT factorisation per iteration
    /// and the initial one).
    pub numeric_factorisations: usize,
    /// Forward and backward triangular solve pairs (0 where the backend does not tell).
    pub triangular_solves: usize,
    /// Interface node insertion.
    pub insertion_s: f64,
    /// Assembly of stiffness, load and constraint rows.
    pub assembly_s: f64,
    /// Symbolic analyses.
    pub symbolic_s: f64,
    /// Numeric factorisations.
    pub numeric_s: f64,
    /// Triangular solves.
    pub solves_s: f64,
    /// Whole contact solves (including the three stages before).
    pub contact_solve_s: f64,
    /// Post-processing of the contact result.
    pub post_s: f64,
}

impl From<vem_contact::WorkCounters> for Work {
    fn from(w: vem_contact::WorkCounters) -> Self {
        let t = w.times;
        Self {
            assemblies: w.assemblies,
            symbolic_analyses: w.symbolic_analyses,
            numeric_factorisations: w.numeric_factorisations,
            triangular_solves: w.triangular_solves,
            insertion_s: t.insertion.as_secs_f64(),
            assembly_s: t.assembly.as_secs_f64(),
            symbolic_s: t.symbolic.as_secs_f64(),
            numeric_s: t.numeric.as_secs_f64(),
            solves_s: t.solves.as_secs_f64(),
            contact_solve_s: t.contact_solve.as_secs_f64(),
            post_s: t.post.as_secs_f64(),
        }
    }
}

/// KKT residuals (see `vem_contact::KktResiduals`), each relative to the force scale `F` and
/// the displacement scale `U` of the problem (unit free).
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Residuals {
    /// The force scale `F` (in the scene's force units).
    pub force_scale: f64,
    /// The displacement scale `U` (in the scene's length units).
    pub displacement_scale: f64,
    /// Largest penetration / `U`.
    pub max_penetration: f64,
    /// Most negative normal force / `F`.
    pub negative_normal_force: f64,
    /// Normal complementarity / (`F U`).
    pub complementarity: f64,
    /// Stationarity of every body relative to its own force scale.
    pub stationarity: f64,
    /// Friction bound violation / `F`.
    pub friction_bound_violation: f64,
    /// Friction complementarity / (`F U`).
    pub slip_direction_violation: f64,
}

/// The Coulomb fixed point.
#[derive(Debug, Clone, Serialize)]
pub struct FixedPointSummary {
    /// Tresca solves after the frictionless start.
    pub steps: usize,
    /// Last relative change of the normal forces.
    pub residual: f64,
    /// The change at every step.
    pub history: Vec<f64>,
    /// Solver iterations over all solves.
    pub solver_iterations: usize,
}

/// Resultant contact forces.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Resultants {
    /// The load `P`: the global y component of the total contact force on body A, that is
    /// minus the contact force on body B (or on the obstacle) along y; positive when body A is
    /// pushed up, as a body pressed down onto the counterpart is. With a rigid plate prescribing
    /// body A's vertical resultant `R_y`, `P = -R_y` at equilibrium (no other load on A).
    pub load: f64,
    /// Sum of the nodal normal forces (compression positive) along the contact normals: not
    /// the load where the normals tilt (curved contact).
    pub normal: f64,
    /// Sum of the nodal friction forces on body A along the tangent.
    pub tangential: f64,
    /// The total contact force on body A.
    pub force_on_body_a: [f64; 2],
}

/// Interface node statuses.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct NodeCounts {
    /// All interface nodes.
    pub total: usize,
    /// Open (no contact force).
    pub open: usize,
    /// Stick.
    pub stick: usize,
    /// Slip (friction at its bound).
    pub slip: usize,
    /// In contact without friction (frictionless law; stick and slip are then zero).
    pub contact: usize,
}

/// Wall-clock times in seconds.
#[derive(Debug, Clone, Copy, Default, Serialize)]
pub struct Times {
    /// Generating and reading meshes.
    pub mesh_s: f64,
    /// Interface node insertion and assembly.
    pub assembly_s: f64,
    /// Linear or contact solves.
    pub solve_s: f64,
    /// Element fields and quality figures.
    pub post_s: f64,
    /// Writing the output files.
    pub output_s: f64,
    /// From meshing to the last file written.
    pub total_s: f64,
}

/// The computed contact zone against Hertz's solution for a cylinder of radius R (body A) on
/// a half-space (body B or a rigid flat), plane problem, for the computed load P per unit
/// thickness: `a = sqrt(4 P R / (pi E*))`, `p0 = 2 P / (pi a)`, with
/// `1/E* = (1 - nu_A^2)/E_A + (1 - nu_B^2)/E_B` in plane strain (`1/E_A + 1/E_B` in plane
/// stress; a rigid counterpart contributes nothing).
#[derive(Debug, Clone, Copy, Serialize)]
pub struct HertzComparison {
    /// R.
    pub radius: f64,
    /// E*.
    pub effective_modulus: f64,
    /// P: the magnitude of the total contact force on body A.
    pub load: f64,
    /// Hertz's half-width a for P.
    pub half_width: f64,
    /// Hertz's peak pressure p0 for P.
    pub peak_pressure: f64,
    /// Computed half-width: half the length of the contact zone, whose ends are taken halfway
    /// between the outermost node in contact and the next (open) node.
    pub computed_half_width: f64,
    /// Computed peak pressure: the largest nodal pressure.
    pub computed_peak_pressure: f64,
    /// Centre of the computed contact zone along the interface tangent (for plots).
    pub centre: [f64; 2],
}

impl HertzComparison {
    fn new(radius: f64, a: &ElasticBody, b: Option<&ElasticBody>, nodes: &[InterfaceNode]) -> Self {
        let compliance = |body: &ElasticBody| match young_poisson(body.material()) {
            Some((e, nu)) if body.material().plane() == Some(Plane::Strain) => (1.0 - nu * nu) / e,
            Some((e, _)) => 1.0 / e,
            None => 0.0,
        };
        let effective_modulus = 1.0 / (compliance(a) + b.map_or(0.0, compliance));
        let load = nodes
            .iter()
            .map(|n| -n.normal_force * n.normal + n.friction_force)
            .sum::<vem_mesh::Vector>()
            .norm();
        let half_width = (4.0 * load * radius / (std::f64::consts::PI * effective_modulus)).sqrt();
        let peak_pressure = 2.0 * load / (std::f64::consts::PI * half_width);
        let (computed_half_width, centre) = contact_zone(nodes);
        Self {
            radius,
            effective_modulus,
            load,
            half_width,
            peak_pressure,
            computed_half_width,
            computed_peak_pressure: nodes.iter().map(|n| n.pressure).fold(0.0, f64::max),
            centre,
        }
    }

    /// Relative error of the computed half-width.
    pub fn half_width_error(&self) -> f64 {
        self.computed_half_width / self.half_width - 1.0
    }

    /// Relative error of the computed peak pressure.
    pub fn peak_pressure_error(&self) -> f64 {
        self.computed_peak_pressure / self.peak_pressure - 1.0
    }
}

/// Half-length and centre of the contact zone around the node of largest pressure: the run
/// of consecutive nodes in contact, extended on each side halfway to the next open node.
fn contact_zone(nodes: &[InterfaceNode]) -> (f64, [f64; 2]) {
    let Some(peak) =
        (0..nodes.len()).max_by(|&i, &j| nodes[i].pressure.total_cmp(&nodes[j].pressure))
    else {
        return (0.0, [0.0, 0.0]);
    };
    if nodes[peak].status == NodeStatus::Open {
        return (0.0, [nodes[peak].position.x, nodes[peak].position.y]);
    }
    let active = |i: usize| nodes[i].status != NodeStatus::Open;
    let mut first = peak;
    while first > 0 && active(first - 1) {
        first -= 1;
    }
    let mut last = peak;
    while last + 1 < nodes.len() && active(last + 1) {
        last += 1;
    }
    let end = |inner: usize, outer: Option<usize>| match outer {
        Some(o) => nodes[inner].position + 0.5 * (nodes[o].position - nodes[inner].position),
        None => nodes[inner].position,
    };
    let start = end(first, first.checked_sub(1));
    let stop = end(last, (last + 1 < nodes.len()).then_some(last + 1));
    let centre = start + 0.5 * (stop - start);
    (0.5 * (stop - start).norm(), [centre.x, centre.y])
}

impl fmt::Display for RunSummary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "{} ({})", self.title, self.scene)?;
        for b in &self.bodies {
            let inserted = if b.inserted_vertices > 0 {
                format!(" ({} inserted at the interface)", b.inserted_vertices)
            } else {
                String::new()
            };
            writeln!(
                f,
                "  body '{}': {}; {} vertices{inserted}, {} polygons, {} DOFs ({} prescribed); \
                 h = {:.3e}, gamma = {:.3}",
                b.name,
                b.mesh,
                b.vertices,
                b.polygons,
                b.free_dofs,
                b.prescribed_dofs,
                b.mesh_size,
                b.gamma
            )?;
            if let Some(e) = b.predicted_error {
                writeln!(
                    f,
                    "    predicted relative energy error E_grad/|u|_1 = {:.2} % (error model \
                     C/n of docs/tradeoff.md)",
                    100.0 * e
                )?;
            }
            writeln!(
                f,
                "    {}; max |u| = {:.4e}, max von Mises = {:.4e}, strain energy = {:.4e}",
                b.material, b.max_displacement, b.max_von_mises, b.strain_energy
            )?;
            for r in &b.reactions {
                let what = if r.rigid_plate {
                    "rigid plate"
                } else {
                    "reaction"
                };
                writeln!(
                    f,
                    "    {what} on '{}' ({}): ({:.6e}, {:.6e})",
                    r.part, r.components, r.force[0], r.force[1]
                )?;
            }
        }
        match &self.contact {
            None => writeln!(f, "  no contact: plain linear elasticity")?,
            Some(c) => {
                writeln!(f, "  contact: {}, {}", c.pair, c.law)?;
                let tangential = if c.tangential_rows == 0 {
                    "no tangential rows".to_string()
                } else {
                    format!("{} tangential rows", c.tangential_rows)
                };
                writeln!(
                    f,
                    "    {} normal rows, {tangential}, {} vertices inserted",
                    c.normal_rows, c.inserted_nodes
                )?;
                writeln!(
                    f,
                    "    solver {}: {}, {} iterations",
                    c.solver, c.status, c.iterations
                )?;
                let w = &c.work;
                writeln!(
                    f,
                    "    work: {} assemblies, {} symbolic analyses, {} numeric factorisations, \
                     {} triangular solves",
                    w.assemblies,
                    w.symbolic_analyses,
                    w.numeric_factorisations,
                    w.triangular_solves
                )?;
                if let Some(fp) = &c.fixed_point {
                    writeln!(
                        f,
                        "    Coulomb fixed point: {} Tresca solves, last change {:.2e}, {} solver \
                         iterations in all",
                        fp.steps, fp.residual, fp.solver_iterations
                    )?;
                }
                let r = &c.residuals;
                writeln!(
                    f,
                    "    KKT residuals (relative to F = {:.3e}, U = {:.3e}): penetration {:.2e}, \
                     negative force {:.2e}, complementarity {:.2e}, stationarity {:.2e}",
                    r.force_scale,
                    r.displacement_scale,
                    r.max_penetration,
                    r.negative_normal_force,
                    r.complementarity,
                    r.stationarity
                )?;
                if c.tangential_rows > 0 {
                    writeln!(
                        f,
                        "                   friction bound {:.2e}, slip direction {:.2e}",
                        r.friction_bound_violation, r.slip_direction_violation
                    )?;
                }
                writeln!(
                    f,
                    "    load P = {:.6e} (contact force on body A along y); contact force on \
                     body A ({:.6e}, {:.6e})",
                    c.resultants.load,
                    c.resultants.force_on_body_a[0],
                    c.resultants.force_on_body_a[1]
                )?;
                if c.tangential_rows == 0 {
                    writeln!(
                        f,
                        "    nodes: {} ({} open, {} in contact)",
                        c.nodes.total, c.nodes.open, c.nodes.contact
                    )?;
                } else {
                    writeln!(
                        f,
                        "    nodes: {} ({} open, {} stick, {} slip)",
                        c.nodes.total, c.nodes.open, c.nodes.stick, c.nodes.slip
                    )?;
                }
                for warning in &c.warnings {
                    writeln!(f, "    warning: {warning}")?;
                }
                if let Some(h) = &c.hertz {
                    writeln!(
                        f,
                        "    Hertz (R = {}, E* = {:.6e}) for P = {:.6e}:",
                        h.radius, h.effective_modulus, h.load
                    )?;
                    writeln!(
                        f,
                        "      half-width a:     computed {:.5e}, Hertz {:.5e} ({:+.1}%)",
                        h.computed_half_width,
                        h.half_width,
                        100.0 * h.half_width_error()
                    )?;
                    writeln!(
                        f,
                        "      peak pressure p0: computed {:.5e}, Hertz {:.5e} ({:+.1}%)",
                        h.computed_peak_pressure,
                        h.peak_pressure,
                        100.0 * h.peak_pressure_error()
                    )?;
                }
            }
        }
        let t = &self.times;
        writeln!(
            f,
            "  times: mesh {:.3} s, assembly {:.3} s, solve {:.3} s, post {:.3} s, output {:.3} s, \
             total {:.3} s",
            t.mesh_s, t.assembly_s, t.solve_s, t.post_s, t.output_s, t.total_s
        )
    }
}
