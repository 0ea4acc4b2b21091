//! Solving a [`Model`] and summarising what was computed: per body (mesh solved, DOFs,
//! reactions, stresses, A1 figures), for the contact pairs (the library's own reports: rows,
//! solver, iterations, KKT residuals, work, fixed point; resultants, node statuses, the Hertz
//! comparison), and the times.

use std::fmt;
use std::time::{Duration, Instant};

use rayon::prelude::*;
use serde::Serialize;
use vem_contact::{
    ContactError, ContactProblem, ContactResult, ContactSolverError, FixedPointReport, HistoryStep,
    InterfaceNode, ModelSummary, NodeStatus, SolveReport, StatusCounts, Warning, WorkCounters,
};
use vem_elastic::{
    CellIndicator, CholeskySolver, Component, ElasticBody, ElasticEstimate, ElementField, Plane,
    Solution,
};
use vem_mesh::polyhedral::quality::CellQuality;
use vem_mesh::quality::ElementQuality;
use vem_mesh::VectorD;
use vem_space::Choice;

use crate::adapt::AdaptSummary;
use crate::build::{locate_contact, locate_elastic, Model, ModelBody};
use crate::error::one_line;
use crate::{Deprecation, KeyPath, SceneError};

/// One body after the solve: in the plane (`SolvedBody`), or in space with the figures of its
/// polyhedra (`SolvedBody<3, CellQuality>`).
#[derive(Debug, Clone)]
pub struct SolvedBody<const D: usize = 2, Q = ElementQuality> {
    /// The body on the mesh that was solved (with the inserted interface nodes for a body in
    /// contact).
    pub body: ElasticBody<D>,
    /// Displacement, reactions, strain energy.
    pub solution: Solution<D>,
    /// Strain, stress and von Mises stress of every element.
    pub fields: Vec<ElementField>,
    /// The shape-regularity figures of every element (A1 in the plane).
    pub qualities: Vec<Q>,
    /// In the plane, the error indicator `eta_E` of every element (the square root of its
    /// share of the estimate's square, in energy units; see [`ErrorEstimate`]); empty in
    /// space.
    pub error_indicator: Vec<f64>,
}

/// The result of solving a scene, with its summary.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// Every body in the plane, in the order of the scene (none in a scene in space).
    pub bodies: Vec<SolvedBody>,
    /// Every body in space, in the order of the scene (none in a scene in the plane).
    pub bodies_3d: Vec<SolvedBody<3, CellQuality>>,
    /// The contact result of the bodies in contact (its `bodies` have been moved into
    /// [`Outcome::bodies`]; nodes, report, fixed point and model summary are here).
    pub contact: Option<ContactResult>,
    /// The contact result of the bodies in space in contact (its `bodies` moved into
    /// [`Outcome::bodies_3d`]).
    pub contact_3d: Option<ContactResult<3>>,
    /// For each body of the contact result, its index in [`Outcome::bodies`] (in
    /// [`Outcome::bodies_3d`] in space).
    pub contact_bodies: Vec<usize>,
    /// With a load history of several steps: every step before the last, each with its
    /// contact result and body solutions (the last step is [`Outcome::contact`] and
    /// [`Outcome::bodies`]).
    pub steps: Vec<HistoryStep>,
    /// The same in space.
    pub steps_3d: Vec<HistoryStep<3>>,
    /// What was computed.
    pub summary: RunSummary,
    pub(crate) started: Instant,
}

impl Outcome {
    /// The solved body in the plane named `name`.
    pub fn body(&self, name: &str) -> Option<&SolvedBody> {
        self.bodies.iter().find(|b| b.body.name() == name)
    }

    /// The solved body in space named `name`.
    pub fn body_3d(&self, name: &str) -> Option<&SolvedBody<3, CellQuality>> {
        self.bodies_3d.iter().find(|b| b.body.name() == name)
    }

    /// The dimension of the bodies: 2 (in the plane) or 3 (in space).
    pub fn dimension(&self) -> usize {
        self.summary.dimension
    }

    /// Sets the time spent writing outputs and the total time (from the start of the mesh
    /// generation).
    pub fn set_output_time(&mut self, output: Duration) {
        self.summary.times.output_s = output.as_secs_f64();
        self.summary.times.total_s = self.started.elapsed().as_secs_f64();
    }
}

/// Everything a run reports, printed as text and written as `summary.json`: the scene-level
/// figures, and the contact library's own reports.
#[derive(Debug, Clone, Serialize)]
pub struct RunSummary {
    /// The scene's title.
    pub title: String,
    /// The dimension of the bodies: 2 (in the plane) or 3 (in space; `polygons` of a body are
    /// then its polyhedra).
    pub dimension: usize,
    /// Every body.
    pub bodies: Vec<BodySummary>,
    /// The contact pairs, if any.
    pub contact: Option<ContactSummary>,
    /// In the plane, the a posteriori error estimate of the solution (all bodies together).
    pub error_estimate: Option<ErrorEstimate>,
    /// With `adapt`, the cycles of the adaptive refinement and what stopped it.
    pub adaptivity: Option<AdaptSummary>,
    /// Earlier keys of the scene and their new places.
    pub deprecations: Vec<Deprecation>,
    /// Notes about the run, one sentence each (outputs left out and why).
    pub notes: Vec<String>,
    /// Wall-clock times.
    pub times: RunTimes,
}

/// One body in the summary.
#[derive(Debug, Clone, Serialize)]
pub struct BodySummary {
    /// Name.
    pub name: String,
    /// Where the mesh came from.
    pub mesh: String,
    /// The element.
    pub element: String,
    /// Vertices of the mesh solved (with inserted interface nodes).
    pub vertices: usize,
    /// Vertices inserted by the interface node insertion.
    pub inserted_vertices: usize,
    /// Polygons (polyhedra in space).
    pub polygons: usize,
    /// Unknowns (free degrees of freedom).
    pub free_dofs: usize,
    /// Prescribed (Dirichlet) degrees of freedom.
    pub prescribed_dofs: usize,
    /// The material.
    pub material: String,
    /// Mesh size h (largest polygon diameter).
    pub mesh_size: f64,
    /// With `accuracy` or `target_error`, a generated mesh: the relative energy error
    /// `E_grad / |u|_1` the error model predicts for its size.
    pub predicted_error: Option<f64>,
    /// Smallest A1 ratio of the mesh solved (the smaller of the shortest-edge and star ratios
    /// over its cells).
    pub gamma: f64,
    /// Smallest star ratio of the mesh solved: the radius of the largest ball a cell is
    /// star-shaped with respect to, over the cell's diameter. Interface insertion shortens
    /// edges, which lowers `gamma` but not this figure.
    pub star_ratio: f64,
    /// Discrete strain energy.
    pub strain_energy: f64,
    /// Largest vertex displacement.
    pub max_displacement: f64,
    /// Largest element von Mises stress.
    pub max_von_mises: f64,
    /// Reactions of the Dirichlet conditions and rigid plates.
    pub reactions: Vec<ReactionSummary>,
    /// Warnings about the body's model (a locking element close to incompressibility), one
    /// sentence each.
    pub warnings: Vec<String>,
}

/// The reaction of one Dirichlet condition or rigid plate.
#[derive(Debug, Clone, Serialize)]
pub struct ReactionSummary {
    /// The part.
    pub part: String,
    /// The prescribed components ("x", "y", "x, y").
    pub components: String,
    /// True for a rigid plate (force control): `force` is then the prescribed resultant.
    pub rigid_plate: bool,
    /// The force the support exerts on the body, by component.
    pub force: Vec<f64>,
}

/// The contact pairs in the summary: the library's reports, and what follows from them.
#[derive(Debug, Clone, Serialize)]
pub struct ContactSummary {
    /// What was modelled: bodies, pairs (law, parts, nodes), rows, inserted vertices.
    pub model: ModelSummary,
    /// The solver as chosen (registry name and settings).
    pub solver: Choice,
    /// The report of the (last) contact solve: status, iterations, KKT residuals, warnings.
    pub report: SolveReport,
    /// What the contact problem cost, build and every solve together.
    pub work: WorkCounters,
    /// Laws iterated by a fixed point (Coulomb): its report.
    pub fixed_point: Option<FixedPointReport>,
    /// Resultant contact forces.
    pub resultants: Resultants,
    /// Node statuses.
    pub nodes: StatusCounts,
    /// Warnings about the answer (solver and model), one sentence each.
    pub warnings: Vec<String>,
    /// The Hertz comparison of every pair that asks for it.
    pub hertz: Vec<HertzComparison>,
    /// With a load history: the load factor, normal resultant and statuses of every step.
    pub history: Vec<StepSummary>,
}

/// One step of a load history.
#[derive(Debug, Clone, Serialize)]
pub struct StepSummary {
    /// The step's pseudo-time (with `steps = [factors]`: 1, 2, ...).
    pub time: f64,
    /// Sum of the nodal normal forces.
    pub normal_resultant: f64,
    /// The total contact force on body A of the first pair (a vector).
    pub force_on_body_a: Vec<f64>,
    /// The load point's displacement: the mean displacement of the part of body A's (first
    /// pair) first Dirichlet condition or rigid plate (empty when it has none).
    pub displacement: Vec<f64>,
    /// Node statuses.
    pub nodes: StatusCounts,
}

/// Resultant contact forces.
#[derive(Debug, Clone, Serialize)]
pub struct Resultants {
    /// Sum of the nodal normal forces (compression positive) along the contact normals: not
    /// a load component where the normals tilt (curved contact).
    pub normal: f64,
    /// Sum of the nodal friction forces on the bodies A (a vector).
    pub friction: Vec<f64>,
    /// The total contact force on body A of the first pair (a vector; its y component is the
    /// load `P` of a body pressed down onto its counterpart).
    pub force_on_body_a: Vec<f64>,
}

/// The residual error estimate of a solution in the plane (docs/adaptivity.md): `eta =
/// (sum_E eta_E^2)^(1/2)` over the elements of all bodies, each part the square root of its
/// sum over the elements (`eta^2` is the sum of the parts' squares). An estimate of the
/// energy norm of the error, `a(u - u_h, u - u_h)^(1/2)`, up to a constant of the meshes'
/// shape (the effectivity `eta / error`, measured in docs/adaptivity.md at 2.6 to 8.2).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ErrorEstimate {
    /// `eta`.
    pub estimate: f64,
    /// `eta / ||u_h||`: the estimate relative to the energy norm of the solution,
    /// `||u_h|| = (sum over bodies of 2 W_h)^(1/2)` with `W_h` the strain energy.
    pub relative: f64,
    /// `||u_h||`, the energy norm of the solution.
    pub energy_norm: f64,
    /// The element residual part (body forces).
    pub residual: f64,
    /// The traction jumps across interior edges.
    pub jump: f64,
    /// The traction mismatch on the Neumann and free edges.
    pub boundary: f64,
    /// The stabilisation part `S_E((I - Pi) u_h, (I - Pi) u_h)`.
    pub stabilisation: f64,
    /// The contact part (traction mismatch against the consistent contact traction, and the
    /// complementarity term).
    pub contact: f64,
}

impl ErrorEstimate {
    /// The estimate of the squared parts `parts` (summed over all elements) of a solution
    /// whose strain energies sum to `strain_energy`.
    pub fn new(parts: &vem_elastic::CellIndicator, strain_energy: f64) -> Self {
        let estimate = parts.squared().sqrt();
        let energy_norm = (2.0 * strain_energy).max(0.0).sqrt();
        Self {
            estimate,
            relative: if energy_norm > 0.0 {
                estimate / energy_norm
            } else {
                estimate
            },
            energy_norm,
            residual: parts.residual.sqrt(),
            jump: parts.jump.sqrt(),
            boundary: parts.boundary.sqrt(),
            stabilisation: parts.stabilisation.sqrt(),
            contact: parts.contact.sqrt(),
        }
    }
}

/// Wall-clock times in seconds.
#[derive(Debug, Clone, Copy, Default, Serialize)]
pub struct RunTimes {
    /// Generating and reading meshes.
    pub mesh_s: f64,
    /// Interface node insertion and assembly.
    pub assembly_s: f64,
    /// Linear or contact solves.
    pub solve_s: f64,
    /// Element fields and quality figures, and the contact answer's forces, tractions and
    /// warnings.
    pub post_s: f64,
    /// The error estimate (in the plane; with `adapt`, every cycle's).
    pub estimate_s: f64,
    /// Writing the output files.
    pub output_s: f64,
    /// From meshing to the last file written.
    pub total_s: f64,
}

/// The computed contact zone against Hertz's solution for the computed load P, body A near
/// the contact a cylinder (in the plane) or a sphere (in space) of radius R on a half-space
/// (body B or a rigid flat):
///
/// - in the plane, per unit thickness: half-width `a = sqrt(4 P R / (pi E*))`, peak pressure
///   `p0 = 2 P / (pi a)`, with `1/E* = (1 - nu_A^2)/E_A + (1 - nu_B^2)/E_B` in plane strain
///   (`1/E_A + 1/E_B` in plane stress);
/// - in space: contact radius `a = (3 P R / (4 E*))^(1/3)`, peak pressure
///   `p0 = 3 P / (2 pi a^2)`, with `1/E*` as in plane strain.
///
/// A rigid counterpart contributes nothing to `1/E*`.
#[derive(Debug, Clone, Serialize)]
pub struct HertzComparison {
    /// The contact pair (index in the scene).
    pub pair: usize,
    /// R.
    pub radius: f64,
    /// E*.
    pub effective_modulus: f64,
    /// P: the magnitude of the total contact force on body A along the mean contact normal.
    pub load: f64,
    /// Hertz's half-width a for P (in space: the contact radius).
    pub half_width: f64,
    /// Hertz's peak pressure p0 for P.
    pub peak_pressure: f64,
    /// Computed half-width: half the length of the contact zone, whose ends are taken halfway
    /// between the outermost node in contact and the next (open) node. In space the computed
    /// contact radius: `sqrt(A / pi)` of the area `A` of the nodes in contact (the sum of their
    /// tributary areas; the whole zone modelled, no symmetry plane through it).
    pub computed_half_width: f64,
    /// Computed peak pressure: the largest nodal pressure. In space, where the nodal pressure
    /// of the overlay cells of two unrelated surface meshes scatters by about 10 % from node
    /// to node, the mean pressure over the central disc `r < a/2` (`a` the computed radius:
    /// the sum of the normal forces over the sum of the tributary areas of the nodes in it),
    /// divided by Hertz's ratio of that mean to the peak, `(2 / (3 s^2)) (1 - (1 - s^2)^(3/2))
    /// = 0.935` at `s = 1/2`.
    pub computed_peak_pressure: f64,
    /// Centre of the computed contact zone (for plots; in space the force-weighted mean of the
    /// nodes in contact).
    pub centre: Vec<f64>,
}

/// The radius of the central disc of the peak pressure in space, as a fraction of the contact
/// radius.
const CENTRAL_DISC: f64 = 0.5;

impl HertzComparison {
    fn new<const D: usize>(
        pair: usize,
        radius: f64,
        a: &ElasticBody<D>,
        b: Option<&ElasticBody<D>>,
        nodes: &[InterfaceNode<D>],
    ) -> Self {
        let compliance = |body: &ElasticBody<D>| match young_poisson(body) {
            Some((e, nu)) if D == 3 || body.material().plane() == Some(Plane::Strain) => {
                (1.0 - nu * nu) / e
            }
            Some((e, _)) => 1.0 / e,
            None => 0.0,
        };
        let effective_modulus = 1.0 / (compliance(a) + b.map_or(0.0, compliance));
        // P: the pair's contact force on A along the mean contact normal (friction, which
        // acts across it, is not part of Hertz's load).
        let force = nodes
            .iter()
            .map(|n| n.friction_force - n.normal * n.normal_force)
            .fold(VectorD::<D>::zeros(), |s, f| s + f);
        let normal = nodes
            .iter()
            .map(|n| n.normal)
            .fold(VectorD::<D>::zeros(), |s, f| s + f);
        let load = if normal.norm() > 0.0 {
            force.dot(&normal).abs() / normal.norm()
        } else {
            force.norm()
        };
        let pi = std::f64::consts::PI;
        if D == 3 {
            let contact_radius = (3.0 * load * radius / (4.0 * effective_modulus)).cbrt();
            let area: f64 = nodes
                .iter()
                .filter(|n| n.status != NodeStatus::Open)
                .map(|n| n.tributary_measure)
                .sum();
            let weight: f64 = nodes.iter().map(|n| n.normal_force.max(0.0)).sum();
            let centre = nodes
                .iter()
                .map(|n| n.position.coords * n.normal_force.max(0.0))
                .fold(VectorD::<D>::zeros(), |s, f| s + f)
                / weight.max(f64::MIN_POSITIVE);
            let computed_radius = (area / pi).sqrt();
            // The mean pressure over the central disc r < a/2 (forces over tributary areas of
            // the nodes in it), divided by Hertz's ratio of that mean to the peak.
            let s = CENTRAL_DISC;
            let ratio = 2.0 / (3.0 * s * s) * (1.0 - (1.0 - s * s).powf(1.5));
            let (force, area) = nodes
                .iter()
                .filter(|n| (n.position.coords - centre).norm() < s * computed_radius)
                .fold((0.0, 0.0), |(f, a), n| {
                    (f + n.normal_force, a + n.tributary_measure)
                });
            let computed_peak_pressure = if area > 0.0 {
                force / area / ratio
            } else {
                nodes.iter().map(|n| n.pressure).fold(0.0, f64::max)
            };
            return Self {
                pair,
                radius,
                effective_modulus,
                load,
                half_width: contact_radius,
                peak_pressure: 3.0 * load / (2.0 * pi * contact_radius * contact_radius),
                computed_half_width: computed_radius,
                computed_peak_pressure,
                centre: centre.iter().copied().collect(),
            };
        }
        let half_width = (4.0 * load * radius / (pi * effective_modulus)).sqrt();
        let peak_pressure = 2.0 * load / (pi * half_width);
        let (computed_half_width, centre) = contact_zone(nodes);
        Self {
            pair,
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

    /// Relative error of the computed half-width (in space: contact radius).
    pub fn half_width_error(&self) -> f64 {
        self.computed_half_width / self.half_width - 1.0
    }

    /// Relative error of the computed peak pressure.
    pub fn peak_pressure_error(&self) -> f64 {
        self.computed_peak_pressure / self.peak_pressure - 1.0
    }
}

/// Half-length and centre of the contact zone around the node of largest pressure: the run
/// of consecutive nodes in contact (along a chain in the plane), extended on each side halfway
/// to the next open node.
fn contact_zone<const D: usize>(nodes: &[InterfaceNode<D>]) -> (f64, Vec<f64>) {
    let Some(peak) =
        (0..nodes.len()).max_by(|&i, &j| nodes[i].pressure.total_cmp(&nodes[j].pressure))
    else {
        return (0.0, vec![0.0; D]);
    };
    if nodes[peak].status == NodeStatus::Open {
        return (0.0, nodes[peak].position.iter().copied().collect());
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
    (
        0.5 * (stop - start).norm(),
        centre.iter().copied().collect(),
    )
}

/// Young's modulus and Poisson's ratio of an isotropic body.
pub fn young_poisson<const D: usize>(body: &ElasticBody<D>) -> Option<(f64, f64)> {
    body.material().lame().map(|(lambda, mu)| {
        (
            mu * (3.0 * lambda + 2.0 * mu) / (lambda + mu),
            lambda / (2.0 * (lambda + mu)),
        )
    })
}

/// "E = 1, nu = 0.3, plane strain" (isotropic) for reports; "E = 1, nu = 0.3, in space" for a
/// body in space.
pub fn describe_material<const D: usize>(body: &ElasticBody<D>) -> String {
    let plane = match body.material().plane() {
        _ if D == 3 => "in space",
        Some(Plane::Strain) => "plane strain",
        Some(Plane::Stress) => "plane stress",
        None => "general",
    };
    match young_poisson(body) {
        Some((e, nu)) => format!("E = {}, nu = {}, {plane}", short(e), short(nu)),
        None => plane.to_string(),
    }
}

/// A number to six significant digits without trailing zeros: "100", "0.3", "2.1e11".
pub fn short(value: f64) -> String {
    let magnitude = value.abs();
    if magnitude == 0.0 {
        return "0".into();
    }
    let trim = |text: &str| {
        if text.contains('.') {
            text.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            text.to_string()
        }
    };
    if (1e-3..1e6).contains(&magnitude) {
        let digits = (5 - magnitude.log10().floor() as i32).max(0) as usize;
        trim(&format!("{value:.digits$}"))
    } else {
        let text = format!("{value:.5e}");
        let (mantissa, exponent) = text.split_once('e').unwrap_or((&text, "0"));
        format!("{}e{exponent}", trim(mantissa))
    }
}

/// `value` with a negative zero turned into 0, so that reports do not print "-0".
pub(crate) fn tidy(value: f64) -> f64 {
    value + 0.0
}

/// The mean displacement of the part of the first Dirichlet condition or rigid plate of body
/// A of the first pair (the load point of a load-displacement curve); empty without one.
pub fn load_point_displacement<const D: usize>(result: &ContactResult<D>) -> Vec<f64> {
    let Some(pair) = result.model.pairs.first() else {
        return Vec::new();
    };
    let a = result.nodes.get(pair.nodes.start).map_or(0, |n| n.body_a);
    let Some(body) = result.bodies.get(a) else {
        return Vec::new();
    };
    let Some(condition) = body.body.dirichlet().first() else {
        return Vec::new();
    };
    let Ok(vertices) = body.body.mesh_arc().part_vertices(condition.part()) else {
        return Vec::new();
    };
    if vertices.is_empty() {
        return Vec::new();
    }
    let sum = vertices
        .iter()
        .fold(vem_mesh::VectorD::<D>::zeros(), |s, &v| {
            s + body.solution.vertex_displacement(v)
        });
    let mean = sum / vertices.len() as f64;
    mean.iter().map(|&u| tidy(u)).collect()
}

/// "initial gaps from g0 to g1 at its N nodes" for an interface without overlap.
fn gap_range<const D: usize>(nodes: &[vem_contact::ContactNode<D>]) -> String {
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
    /// Solves the scene: the bodies in contact by the contact library (every pair together),
    /// every other body as plain elasticity (assembly and sparse Cholesky). With a load
    /// history, every step in order; the outcome is the last step's.
    ///
    /// # Errors
    /// A [`SceneError`] at the key at fault where one is (a body's condition, a pair), at the
    /// root otherwise (a solver's failure carries its figures in the message).
    pub fn solve(&self) -> Result<Outcome, SceneError> {
        let now = Instant::now();
        let started = now.checked_sub(self.mesh_time).unwrap_or(now);
        if self.dimension() == 3 {
            return crate::space::solve(self, started);
        }
        match self.scene().adapt {
            Some(adapt) => crate::adapt::solve(self, &adapt, started),
            None => self.solve_plane(started),
        }
    }

    /// Solves the scene in the plane on the model's meshes, with the error estimate.
    pub(crate) fn solve_plane(&self, started: Instant) -> Result<Outcome, SceneError> {
        let scene = self.scene();
        let mut slots: Vec<Option<(ElasticBody, Solution)>> = vec![None; self.bodies.len()];
        let mut times = RunTimes {
            mesh_s: self.mesh_time.as_secs_f64(),
            ..RunTimes::default()
        };
        let mut contact = None;
        let mut contact_bodies = Vec::new();
        let mut history = Vec::new();
        let mut earlier_steps = Vec::new();
        let located = |e: SceneError| SceneError {
            path: self.written(&e.path),
            ..e
        };
        if let Some((problem, indices)) = &self.problem {
            let run = self.solve_contact(problem, indices, &mut times)?;
            for (b, &index) in run.bodies.into_iter().zip(indices) {
                slots[index] = Some(b);
            }
            history = run.history;
            earlier_steps = run.earlier;
            contact_bodies = indices.clone();
            contact = Some(run.result);
        }
        for (index, slot) in slots.iter_mut().enumerate() {
            if slot.is_none() {
                let load_factor = crate::history::final_factor(scene, index).map_err(located)?;
                let body = &self.bodies[index].body;
                let elastic = |e| {
                    located(locate_elastic(scene, e).unwrap_or_else(|text| {
                        SceneError::at(KeyPath::key("body").index(index), text)
                    }))
                };
                let start = Instant::now();
                let system = body.assemble().map_err(elastic)?;
                times.assembly_s += start.elapsed().as_secs_f64();
                let start = Instant::now();
                let solution = body
                    .solve_system(&system, &mut CholeskySolver::default())
                    .map_err(elastic)?;
                // Linear elasticity: the answer at a load factor is the factor times the one
                // at full load.
                let solution = if load_factor == 1.0 {
                    solution
                } else {
                    let scaled: Vec<f64> = solution
                        .displacement()
                        .iter()
                        .map(|u| load_factor * u)
                        .collect();
                    body.solution_scaled(&system, scaled, load_factor)
                        .map_err(elastic)?
                };
                times.solve_s += start.elapsed().as_secs_f64();
                *slot = Some((body.clone(), solution));
            }
        }
        let solved: Vec<(ElasticBody, Solution)> = slots
            .into_iter()
            .map(|slot| slot.expect("every body is solved"))
            .collect();
        let start = Instant::now();
        let estimates = self.estimate_plane(&solved, contact.as_ref())?;
        times.estimate_s = start.elapsed().as_secs_f64();
        let strain_energy: f64 = solved.iter().map(|(_, s)| s.strain_energy()).sum();
        let parts: CellIndicator = estimates.iter().map(ElasticEstimate::sum).sum();
        let error_estimate = ErrorEstimate::new(&parts, strain_energy);
        let start = Instant::now();
        let bodies = solved
            .into_iter()
            .zip(estimates)
            .map(|((body, solution), estimate)| {
                // The fields of the strains the estimate's pass over the cells computed.
                let fields = estimate
                    .strains
                    .par_iter()
                    .map(|strain| ElementField::from_strain(strain, body.tensor(), body.material()))
                    .collect();
                let qualities = vem_mesh::quality::element_qualities(body.mesh());
                SolvedBody {
                    body,
                    solution,
                    fields,
                    qualities,
                    error_indicator: estimate.indicators(),
                }
            })
            .collect::<Vec<_>>();
        times.post_s += start.elapsed().as_secs_f64();
        times.total_s =
            times.mesh_s + times.assembly_s + times.solve_s + times.post_s + times.estimate_s;
        let mut summary = self.summarise(&bodies, contact.as_ref(), times, history);
        summary.error_estimate = Some(error_estimate);
        Ok(Outcome {
            bodies,
            bodies_3d: Vec::new(),
            contact,
            contact_3d: None,
            contact_bodies,
            steps: earlier_steps,
            steps_3d: Vec::new(),
            summary,
            started,
        })
    }

    /// The residual error estimate of every body of the scene in the plane (in its order)
    /// solved as `solved`: the bodies in contact with the contact terms of their pairs
    /// ([`vem_contact::estimate`]), the others alone ([`ElasticBody::estimate`]). The loads
    /// are measured at their full value (the last step of a history that ends at factor 1).
    fn estimate_plane(
        &self,
        solved: &[(ElasticBody, Solution)],
        contact: Option<&ContactResult>,
    ) -> Result<Vec<ElasticEstimate>, SceneError> {
        let scene = self.scene();
        let located = |e: SceneError| SceneError {
            path: self.written(&e.path),
            ..e
        };
        let mut estimates: Vec<Option<ElasticEstimate>> = vec![None; solved.len()];
        if let (Some((problem, indices)), Some(result)) = (&self.problem, contact) {
            let parts: Vec<(&ElasticBody, &[f64])> = indices
                .iter()
                .map(|&i| (&solved[i].0, solved[i].1.displacement()))
                .collect();
            let estimate = vem_contact::estimate::estimate_of(problem, &parts, &result.nodes)
                .map_err(|e| located(locate_contact(scene, e)))?;
            for (body, &index) in estimate.bodies.into_iter().zip(indices) {
                estimates[index] = Some(body);
            }
        }
        estimates
            .into_iter()
            .zip(solved)
            .enumerate()
            .map(|(index, (estimate, (body, solution)))| match estimate {
                Some(estimate) => Ok(estimate),
                None => body.estimate(solution.displacement(), &[]).map_err(|e| {
                    located(locate_elastic(scene, e).unwrap_or_else(|text| {
                        SceneError::at(KeyPath::key("body").index(index), text)
                    }))
                }),
            })
            .collect()
    }

    /// Solves the contact problem `problem` of the bodies `indices` (in the plane or in space)
    /// along the scene's load history: the last step's result (its bodies taken out), the
    /// earlier steps, a summary of every step; the times of insertion, assembly and the
    /// contact solves added to `times`.
    pub(crate) fn solve_contact<const D: usize>(
        &self,
        problem: &ContactProblem<D>,
        indices: &[usize],
        times: &mut RunTimes,
    ) -> Result<ContactRun<D>, SceneError> {
        let scene = self.scene();
        let located = |e: SceneError| SceneError {
            path: self.written(&e.path),
            ..e
        };
        let mut history = Vec::new();
        let mut solver = self
            .registries
            .solvers
            .make_choice(&self.solver)
            .map_err(|e| located(crate::build::registry_error(e, &KeyPath::key("solver"))))?;
        let start = Instant::now();
        let discretisation = problem
            .discretise()
            .map_err(|e| located(locate_contact(scene, e)))?;
        let load_history = crate::history::load_history(scene, indices).map_err(located)?;
        let overlap = Warning::initial_overlap(
            discretisation
                .nodes()
                .iter()
                .map(|n| (n.position, n.normal, n.initial_gap)),
        );
        let mut work = discretisation.work();
        let steps = discretisation
            .solve_history(solver.as_mut(), &load_history)
            .map_err(|e| match e {
                ContactError::Solver(source @ ContactSolverError::Unbounded { .. }) => {
                    let pairs: Vec<&str> = self
                        .contacts
                        .iter()
                        .map(|c| c.description.as_str())
                        .collect();
                    SceneError::at(
                        KeyPath::key("contact"),
                        format!(
                            "the contact of {} gives the body no support under its load ({}): \
                             hold the body by a Dirichlet condition, or check that the contact \
                             part faces its counterpart: {}",
                            pairs.join("; "),
                            overlap.as_ref().map_or_else(
                                || gap_range(discretisation.nodes()),
                                |o| o.to_string()
                            ),
                            one_line(&source)
                        ),
                    )
                }
                e => located(locate_contact(scene, e)),
            })?;
        for step in &steps {
            let result = &step.result;
            work += result.work;
            history.push(StepSummary {
                time: step.time,
                normal_resultant: tidy(result.normal_resultant()),
                force_on_body_a: result.force_on_body_a().iter().map(|&f| tidy(f)).collect(),
                displacement: load_point_displacement(result),
                nodes: result.status_counts(),
            });
        }
        let mut steps = steps;
        let mut result = steps.pop().expect("a history has at least one step").result;
        result.work = work;
        result.model.total_time = start.elapsed();
        let stages = result.work.times;
        times.assembly_s += (stages.insertion + stages.assembly).as_secs_f64();
        times.solve_s += stages.contact_solve.as_secs_f64();
        times.post_s += stages.post.as_secs_f64();
        let bodies = std::mem::take(&mut result.bodies)
            .into_iter()
            .map(|b| (b.body, b.solution))
            .collect();
        Ok(ContactRun {
            result,
            bodies,
            earlier: steps,
            history,
        })
    }

    fn summarise(
        &self,
        bodies: &[SolvedBody],
        contact: Option<&ContactResult>,
        times: RunTimes,
        history: Vec<StepSummary>,
    ) -> RunSummary {
        let body_summaries = bodies
            .iter()
            .zip(&self.bodies)
            .map(|(solved, built)| {
                let mesh = solved.body.mesh();
                let dofs = solved.body.dofs();
                let displacements = solved.solution.vertex_displacements();
                BodySummary {
                    name: solved.body.name().to_string(),
                    mesh: built.mesh_source.clone(),
                    element: built.element.clone(),
                    predicted_error: built.predicted_error,
                    vertices: mesh.n_vertices(),
                    inserted_vertices: mesh.n_vertices() - built.body.mesh().n_vertices(),
                    polygons: mesh.n_polygons(),
                    free_dofs: dofs.n_free(),
                    prescribed_dofs: dofs.n_prescribed(),
                    material: describe_material(&solved.body),
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
                    star_ratio: solved
                        .qualities
                        .iter()
                        .map(|q| q.star_ratio)
                        .fold(f64::INFINITY, f64::min),
                    strain_energy: solved.solution.strain_energy(),
                    max_displacement: displacements.iter().map(|u| u.norm()).fold(0.0, f64::max),
                    max_von_mises: solved
                        .fields
                        .iter()
                        .map(|f| f.von_mises)
                        .fold(0.0, f64::max),
                    reactions: reaction_summaries(&solved.solution, &solved.body),
                    warnings: built.warnings.clone(),
                }
            })
            .collect();
        let contact_summary =
            contact.map(|result| self.contact_summary(result, &self.bodies, history));
        RunSummary {
            title: self
                .scene()
                .title
                .clone()
                .unwrap_or_else(|| "scene".to_string()),
            dimension: 2,
            bodies: body_summaries,
            contact: contact_summary,
            error_estimate: None,
            adaptivity: None,
            deprecations: self.deprecations().to_vec(),
            notes: Vec::new(),
            times,
        }
    }
}

impl Model {
    /// The summary of a contact result in the plane or in space (`bodies`: the scene's
    /// bodies of that dimension, as built).
    pub(crate) fn contact_summary<const D: usize>(
        &self,
        result: &ContactResult<D>,
        bodies: &[ModelBody<D>],
        history: Vec<StepSummary>,
    ) -> ContactSummary {
        let force = result.force_on_body_a();
        let hertz = self
            .contacts
            .iter()
            .enumerate()
            .filter_map(|(k, c)| {
                let radius = c.hertz_radius?;
                let a = &bodies[c.body].body;
                let b = c.other.map(|o| &bodies[o].body);
                Some(HertzComparison::new(k, radius, a, b, result.pair_nodes(k)))
            })
            .collect();
        ContactSummary {
            model: result.model.clone(),
            solver: self.solver.clone(),
            report: result.report.clone(),
            work: result.work,
            fixed_point: result.fixed_point.clone(),
            resultants: Resultants {
                normal: tidy(result.normal_resultant()),
                friction: result
                    .friction_resultant()
                    .iter()
                    .map(|&f| tidy(f))
                    .collect(),
                force_on_body_a: force.iter().map(|&f| tidy(f)).collect(),
            },
            nodes: result.status_counts(),
            warnings: result.warnings.iter().map(|w| w.to_string()).collect(),
            hertz,
            history: if history.len() > 1 {
                history
            } else {
                Vec::new()
            },
        }
    }
}

/// What [`Model::solve_contact`] gives.
pub(crate) struct ContactRun<const D: usize> {
    /// The last step's result, its bodies taken out.
    pub(crate) result: ContactResult<D>,
    /// The bodies of the problem on the meshes solved, with their solutions, in the order of
    /// the problem.
    pub(crate) bodies: Vec<(ElasticBody<D>, Solution<D>)>,
    /// Every step before the last.
    pub(crate) earlier: Vec<HistoryStep<D>>,
    /// Every step's summary.
    pub(crate) history: Vec<StepSummary>,
}

/// "1 iteration", "3 iterations".
fn count(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

impl fmt::Display for RunSummary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "{}", self.title)?;
        for note in &self.deprecations {
            writeln!(f, "  note: {note}")?;
        }
        let cells = if self.dimension == 3 {
            "polyhedra"
        } else {
            "polygons"
        };
        for b in &self.bodies {
            let inserted = if b.inserted_vertices > 0 {
                format!(" ({} inserted at the interface)", b.inserted_vertices)
            } else {
                String::new()
            };
            writeln!(
                f,
                "  body '{}': {}; {} vertices{inserted}, {} {cells}, {} DOFs ({} prescribed); \
                 h = {:.3e}, gamma = {:.3} (star ratio {:.3})",
                b.name,
                b.mesh,
                b.vertices,
                b.polygons,
                b.free_dofs,
                b.prescribed_dofs,
                b.mesh_size,
                b.gamma,
                b.star_ratio
            )?;
            writeln!(f, "    element {}", b.element)?;
            for warning in &b.warnings {
                writeln!(f, "    warning: {warning}")?;
            }
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
                    "rigid plate force"
                } else {
                    "reaction"
                };
                let force: Vec<String> = r.force.iter().map(|v| format!("{v:.6e}")).collect();
                writeln!(
                    f,
                    "    {what} on '{}' ({}): ({})",
                    r.part,
                    r.components,
                    force.join(", ")
                )?;
            }
        }
        let Some(c) = &self.contact else {
            writeln!(f, "  no contact: plain linear elasticity")?;
            for note in &self.notes {
                writeln!(f, "  note: {note}")?;
            }
            return self.write_times(f);
        };
        for pair in &c.model.pairs {
            writeln!(f, "  contact: {}, {}", pair.description, pair.law)?;
        }
        let tangential = if c.model.tangential_rows == 0 {
            "no tangential rows".to_string()
        } else {
            count(c.model.tangential_rows, "tangential row", "tangential rows")
        };
        writeln!(
            f,
            "    {}, {tangential}, {} inserted",
            count(c.model.normal_rows, "normal row", "normal rows"),
            count(c.model.inserted_nodes, "vertex", "vertices")
        )?;
        writeln!(
            f,
            "    solver {}: {}, {}",
            c.report.solver,
            c.report.status.describe(),
            count(c.report.iterations, "iteration", "iterations")
        )?;
        let w = &c.work;
        writeln!(
            f,
            "    work: {}, {}, {}, {}",
            count(w.assemblies, "assembly", "assemblies"),
            count(
                w.symbolic_analyses,
                "symbolic analysis",
                "symbolic analyses"
            ),
            count(
                w.numeric_factorisations,
                "numeric factorisation",
                "numeric factorisations"
            ),
            count(w.triangular_solves, "triangular solve", "triangular solves")
        )?;
        if let Some(fp) = &c.fixed_point {
            writeln!(
                f,
                "    Coulomb fixed point: {}, last change {:.2e}, {} in all",
                count(fp.steps, "Tresca solve", "Tresca solves"),
                fp.residual,
                count(
                    fp.solver_iterations,
                    "solver iteration",
                    "solver iterations"
                )
            )?;
        }
        let r = &c.report.residuals;
        writeln!(
            f,
            "    KKT residuals (relative to F = {:.3e}, U = {:.3e}): penetration {:.2e}, negative \
             force {:.2e}, complementarity {:.2e}, stationarity {:.2e}",
            r.scales.force,
            r.scales.displacement,
            r.max_penetration,
            r.negative_normal_force,
            r.complementarity,
            r.stationarity
        )?;
        if c.model.tangential_rows > 0 {
            writeln!(
                f,
                "                   friction bound {:.2e}, slip direction {:.2e}",
                r.friction_bound_violation, r.slip_direction_violation
            )?;
        }
        let force: Vec<String> = c
            .resultants
            .force_on_body_a
            .iter()
            .map(|v| format!("{v:.6e}"))
            .collect();
        writeln!(
            f,
            "    contact force on body A: ({}); sum of normal forces {:.6e}",
            force.join(", "),
            c.resultants.normal
        )?;
        let n = &c.nodes;
        // The states the pairs' laws have: contact without friction, stick and slip with it.
        let mut states = vec![format!("{} open", n.open)];
        if n.contact > 0 || c.model.tangential_rows == 0 {
            states.push(format!("{} in contact", n.contact));
        }
        if c.model.tangential_rows > 0 {
            states.push(format!("{} stick, {} slip", n.stick, n.slip));
        }
        writeln!(f, "    nodes: {} ({})", n.total(), states.join(", "))?;
        for step in &c.history {
            writeln!(
                f,
                "    t = {}: sum of normal forces {:.6e}, {} open",
                step.time, step.normal_resultant, step.nodes.open
            )?;
        }
        for warning in &c.warnings {
            writeln!(f, "    warning: {warning}")?;
        }
        for h in &c.hertz {
            writeln!(
                f,
                "    Hertz (R = {}, E* = {:.6e}) for the load magnitude P = {:.6e}:",
                h.radius, h.effective_modulus, h.load
            )?;
            let what = if self.dimension == 3 {
                "contact radius a:"
            } else {
                "half-width a:    "
            };
            writeln!(
                f,
                "      {what} computed {:.5e}, Hertz {:.5e} ({:+.1}%)",
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
        for note in &self.notes {
            writeln!(f, "  note: {note}")?;
        }
        self.write_times(f)
    }
}

impl RunSummary {
    fn write_times(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(e) = &self.error_estimate {
            writeln!(
                f,
                "  error estimate eta = {:.4e} ({:.3} % of the energy norm {:.4e}): element \
                 residual {:.3e}, jumps {:.3e}, boundary {:.3e}, stabilisation {:.3e}, contact \
                 {:.3e}",
                e.estimate,
                100.0 * e.relative,
                e.energy_norm,
                e.residual,
                e.jump,
                e.boundary,
                e.stabilisation,
                e.contact
            )?;
        }
        if let Some(a) = &self.adaptivity {
            let last = a.cycles.last();
            let stop = match a.stop {
                crate::AdaptStop::Converged => "converged",
                crate::AdaptStop::MaxUnknowns => "stopped by max_unknowns",
                crate::AdaptStop::MaxCycles => "stopped by max_cycles",
                crate::AdaptStop::NothingToRefine => "stopped: nothing to refine",
            };
            writeln!(
                f,
                "  adaptive refinement (theta = {}): {stop} after {} ({} unknowns, relative \
                 estimate {:.3} %{})",
                a.theta,
                count(a.cycles.len(), "cycle", "cycles"),
                last.map_or(0, |c| c.unknowns),
                100.0 * last.map_or(0.0, |c| c.relative_estimate),
                a.target_error
                    .map_or_else(String::new, |t| format!(", target {:.3} %", 100.0 * t))
            )?;
            if let Some(warning) = &a.warning {
                writeln!(f, "    warning: {warning}")?;
            }
        }
        let t = &self.times;
        writeln!(
            f,
            "  times: mesh {:.3} s, assembly {:.3} s, solve {:.3} s, estimate {:.3} s, post {:.3} \
             s, output {:.3} s, total {:.3} s",
            t.mesh_s, t.assembly_s, t.solve_s, t.estimate_s, t.post_s, t.output_s, t.total_s
        )
    }
}

/// The reactions of every Dirichlet condition of `body` in `solution`, as the summary lists
/// them (components `x, y` or `x, y, z` for a condition on all of them).
pub(crate) fn reaction_summaries<const D: usize>(
    solution: &Solution<D>,
    body: &ElasticBody<D>,
) -> Vec<ReactionSummary> {
    solution
        .reactions()
        .iter()
        .zip(body.dirichlet())
        .map(|(r, condition)| ReactionSummary {
            rigid_plate: condition.is_rigid_plate(),
            part: r.part.clone(),
            components: match r.component {
                Component::All => ["x", "y", "z"][..D].join(", "),
                other => other.name().to_string(),
            },
            force: r.force.iter().map(|&f| tidy(f)).collect(),
        })
        .collect()
}
