//! The adaptive loop in the plane: solve, estimate, mark, refine (docs/adaptivity.md).
//!
//! Each cycle solves the problem on the current meshes (a contact problem, or bodies without
//! contact), estimates the error cell by cell ([`vem_contact::estimate`]: the residual
//! estimator of the VEM plus the contact terms), marks by Dorfler's bulk criterion over the
//! cells of all bodies together ([`vem_mesh::refine::dorfler_marking`]) and refines the marked
//! cells ([`vem_mesh::refine::refine`]; hanging nodes are plain vertices). With
//! [`AdaptiveSettings::uniform`] every cell is refined instead (the comparison series).
//!
//! # What is rebuilt after a refinement
//!
//! The meshes refined are the bodies' meshes *as solved*, that is enlarged by the interface
//! node insertion of the previous cycle: the other side's nodes are already vertices. The
//! problem is then built again from the refined meshes by the caller's `build` (bodies: degree
//! of freedom maps, assembly patterns and values; contact: the interface insertion, which
//! pairs the nodes that already face each other by snapping and inserts only the new
//! midpoints of the other side, the pairing, the contact discretisation and its condensed
//! operators). Nothing of a previous cycle is reused but the meshes: on meshes that change
//! everywhere near the interface each of these is a new object.
//!
//! # Errors measured
//!
//! With an exact solution the cycle records `E_grad = ||grad(u - Pi u_h)||_{0,h}`
//! ([`crate::norms`]) and the energy error of the projection
//! `E_en = (sum_E int_E (eps(u) - eps(Pi u_h)) : C (eps(u) - eps(Pi u_h)))^(1/2)`, the
//! norm the estimator bounds; the effectivity index is `eta / E_en`. Without one, the error is
//! measured against a reference strain energy `W_ref` of an overkill solution: for a
//! minimisation over a convex set with nested spaces `a(u - u_h, u - u_h) <= 2 (W_h - W_ref)`
//! (equality without contact), so `E_en ~ (2 |W_h - W_ref|)^(1/2)`.

use std::sync::Arc;

use nalgebra::Matrix2;
use rayon::prelude::*;
use vem_contact::estimate::{estimate, ContactEstimate};
use vem_contact::{BodyResult, ContactProblem, ContactSolver, InterfaceNode};
use vem_elastic::{CellIndicator, CholeskySolver, ElasticBody};
use vem_mesh::refine::{dorfler_marking, refine};
use vem_mesh::{quality, Mesh};
use vem_space::ElementSpace;

use crate::exact::{BodyId, ExactSolution};
use crate::norms::{body_errors, quadrature_points};
use crate::problem::{DiscreteProblem, ProblemSettings};
use crate::VerifyError;

/// The band of the effectivity index `eta / E_en` on the smooth cases E1 and M1 on
/// quadrilaterals, triangles and Voronoi meshes of 6 and 12 cells a side: measured 6.1 to 8.3
/// (docs/adaptivity.md); the band leaves room around that, not a factor of ten.
pub const EFFECTIVITY_BAND: (f64, f64) = (4.0, 12.0);

/// The band of the effectivity index on M2 (Tresca friction with stick and slip zones) on
/// quadrilaterals, triangles and Voronoi meshes of 6 and 12 cells a side: measured 5.9 to 6.8
/// (docs/adaptivity.md); the band of the frictionless cases.
pub const FRICTION_EFFECTIVITY_BAND: (f64, f64) = (4.0, 12.0);

/// What one cycle solves.
pub enum Model {
    /// Bodies in contact.
    Contact(ContactProblem),
    /// Bodies without contact, solved one by one.
    Elastic(Vec<ElasticBody>),
}

/// Settings of an adaptive run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AdaptiveSettings {
    /// Dorfler's bulk fraction, in (0, 1].
    pub theta: f64,
    /// The largest number of cycles (solves).
    pub max_cycles: usize,
    /// No further refinement once the unknowns exceed this.
    pub max_unknowns: usize,
    /// Refine every cell (the uniform comparison series).
    pub uniform: bool,
}

impl Default for AdaptiveSettings {
    /// `theta = 0.5`, 12 cycles, 200 000 unknowns, adaptive.
    fn default() -> Self {
        Self {
            theta: 0.5,
            max_cycles: 12,
            max_unknowns: 200_000,
            uniform: false,
        }
    }
}

/// How errors are measured.
#[derive(Clone)]
pub enum Reference {
    /// Against an exact solution (its bodies in the order of the meshes).
    Exact(Arc<dyn ExactSolution>),
    /// Against the total strain energy of an overkill solution.
    Energy(f64),
    /// Not measured.
    None,
}

/// One solve of an adaptive run and what was measured on it.
#[derive(Debug, Clone, PartialEq)]
pub struct CycleRecord {
    /// The cycle, from 0.
    pub cycle: usize,
    /// The unknowns of all bodies (free degrees of freedom).
    pub unknowns: usize,
    /// The cells of all bodies.
    pub cells: usize,
    /// The estimate `eta`.
    pub estimate: f64,
    /// The squared parts of the estimate summed over all cells.
    pub parts: CellIndicator,
    /// `E_grad` (absolute; bodies combined), with an exact solution.
    pub grad_error: Option<f64>,
    /// `E_grad / |u|_1`, with an exact solution.
    pub relative_grad: Option<f64>,
    /// The energy error `E_en` (see the module docs).
    pub energy_error: Option<f64>,
    /// `eta / E_en`.
    pub effectivity: Option<f64>,
    /// The total strain energy `W_h = sum 1/2 a_h(u_h, u_h)`.
    pub strain_energy: f64,
    /// Cells refined after this solve (0 on the last).
    pub refined: usize,
    /// The smallest star-shape ratio (`rho / h_E`) over all cells.
    pub min_star_ratio: f64,
    /// The largest number of vertices of a cell.
    pub max_cell_vertices: usize,
    /// The interface nodes in contact (0 without contact).
    pub active_nodes: usize,
}

/// One solve and its estimate.
#[derive(Debug, Clone)]
pub struct Solved {
    /// Per body: the body on the mesh it was solved on, its system and solution.
    pub bodies: Vec<BodyResult>,
    /// The interface nodes (empty without contact).
    pub nodes: Vec<InterfaceNode>,
    /// The estimate.
    pub estimate: ContactEstimate,
}

impl Solved {
    /// The indicator `eta_E` of every cell of every body: the cell field to write out.
    pub fn cell_indicators(&self) -> Vec<Vec<f64>> {
        self.estimate.indicators()
    }
}

/// The result of an adaptive run.
#[derive(Debug, Clone)]
pub struct AdaptiveRun {
    /// One record per cycle.
    pub records: Vec<CycleRecord>,
    /// The last solve.
    pub last: Solved,
}

fn contact_error(name: &str) -> impl Fn(vem_contact::ContactError) -> VerifyError + '_ {
    move |source| VerifyError::Contact {
        case: name.to_string(),
        source: Box::new(source),
    }
}

/// Solves `model` and estimates its error.
///
/// # Errors
/// The solve's and the estimate's, naming `name`.
pub fn solve_and_estimate(
    name: &str,
    model: &Model,
    solver: &mut dyn ContactSolver,
) -> Result<Solved, VerifyError> {
    match model {
        Model::Contact(problem) => {
            let result = problem.solve(solver).map_err(contact_error(name))?;
            let estimate = estimate(problem, &result).map_err(contact_error(name))?;
            Ok(Solved {
                bodies: result.bodies,
                nodes: result.nodes,
                estimate,
            })
        }
        Model::Elastic(bodies) => {
            let elastic = |source| VerifyError::Elastic {
                case: name.to_string(),
                source: Box::new(source),
            };
            let mut results = Vec::with_capacity(bodies.len());
            let mut estimates = Vec::with_capacity(bodies.len());
            for body in bodies {
                let system = body.assemble().map_err(elastic)?;
                let solution = body
                    .solve_system(&system, &mut CholeskySolver::default())
                    .map_err(elastic)?;
                estimates.push(
                    body.estimate(solution.displacement(), &[])
                        .map_err(elastic)?,
                );
                results.push(BodyResult {
                    body: body.clone(),
                    system: Arc::new(system),
                    solution,
                });
            }
            Ok(Solved {
                bodies: results,
                nodes: Vec::new(),
                estimate: ContactEstimate {
                    bodies: estimates,
                    traction: 0.0,
                    complementarity: 0.0,
                    friction: 0.0,
                },
            })
        }
    }
}

/// The energy error of the projection of one body against `exact` (see the module docs).
///
/// # Errors
/// An element or triangulation failure, naming the polygon.
pub fn projection_energy_error(
    exact: &dyn ExactSolution,
    body: BodyId,
    elastic: &ElasticBody,
    element: &dyn ElementSpace,
    displacement: &[f64],
) -> Result<f64, VerifyError> {
    let label = body.index() + 1;
    let mesh = elastic.mesh();
    let lame = exact.lame();
    let sum = (0..mesh.n_polygons())
        .into_par_iter()
        .map(|p| -> Result<f64, VerifyError> {
            let points = mesh.polygon_points(p);
            let projection =
                element
                    .projection(&points)
                    .map_err(|source| VerifyError::Element {
                        body: label,
                        polygon: p,
                        source: Box::new(source),
                    })?;
            let local = elastic.local_values(p, displacement);
            let gradient_h = projection.gradient(&local);
            let rule = quadrature_points(&points).map_err(|reason| VerifyError::Triangulation {
                body: label,
                polygon: p,
                reason,
            })?;
            Ok(rule
                .iter()
                .map(|q| {
                    let d: Matrix2<f64> = exact.gradient(body, q.point) - gradient_h;
                    let sym = 0.5 * (d + d.transpose());
                    q.weight * lame.stress(&sym).component_mul(&sym).sum()
                })
                .sum())
        })
        .try_reduce(|| 0.0, |a, b| Ok(a + b))?;
    Ok(sum.max(0.0).sqrt())
}

/// Runs the adaptive loop from `meshes` (one per body): `build` makes the problem on given
/// meshes, `element` is the element the bodies use (for the error measures), `reference`
/// how errors are measured.
///
/// # Errors
/// Any error of `build`, of the solves and estimates, of the refinement (naming the cycle).
pub fn run(
    name: &str,
    build: &dyn Fn(Vec<Mesh>) -> Result<Model, VerifyError>,
    mut meshes: Vec<Mesh>,
    element: &dyn ElementSpace,
    reference: &Reference,
    settings: &AdaptiveSettings,
    solver: &mut dyn ContactSolver,
) -> Result<AdaptiveRun, VerifyError> {
    let mut records = Vec::new();
    let mut cycle = 0;
    loop {
        let model = build(meshes)?;
        let solved = solve_and_estimate(name, &model, solver)?;
        let unknowns: usize = solved
            .bodies
            .iter()
            .map(|b| b.body.dofs().n_unknowns())
            .sum();
        let cells: usize = solved
            .bodies
            .iter()
            .map(|b| b.body.mesh().n_polygons())
            .sum();
        let strain_energy: f64 = solved
            .bodies
            .iter()
            .map(|b| b.solution.strain_energy())
            .sum();
        let parts = solved.estimate.bodies.iter().map(|b| b.sum()).fold(
            CellIndicator::default(),
            |a, c| CellIndicator {
                residual: a.residual + c.residual,
                jump: a.jump + c.jump,
                boundary: a.boundary + c.boundary,
                stabilisation: a.stabilisation + c.stabilisation,
                contact: a.contact + c.contact,
            },
        );
        let eta = parts.squared().sqrt();
        let (mut grad_error, mut relative_grad, mut energy_error) = (None, None, None);
        match reference {
            Reference::Exact(exact) => {
                let (mut grad, mut norm, mut energy) = (0.0, 0.0, 0.0);
                for (&id, result) in exact.bodies().iter().zip(&solved.bodies) {
                    let errors = body_errors(
                        &**exact,
                        id,
                        &result.body,
                        &result.system,
                        result.solution.displacement(),
                    )?;
                    grad += errors.grad.powi(2);
                    norm += errors.exact_grad.powi(2);
                    energy += projection_energy_error(
                        &**exact,
                        id,
                        &result.body,
                        element,
                        result.solution.displacement(),
                    )?
                    .powi(2);
                }
                grad_error = Some(grad.sqrt());
                relative_grad = Some(if norm > 0.0 {
                    (grad / norm).sqrt()
                } else {
                    grad.sqrt()
                });
                energy_error = Some(energy.sqrt());
            }
            Reference::Energy(w_ref) => {
                energy_error = Some((2.0 * (strain_energy - w_ref).abs()).sqrt());
            }
            Reference::None => {}
        }
        let mut min_star_ratio = f64::INFINITY;
        let mut max_cell_vertices = 0;
        for b in &solved.bodies {
            let mesh = b.body.mesh();
            for p in 0..mesh.n_polygons() {
                let q = quality::element_quality(&mesh.polygon_points(p));
                min_star_ratio = min_star_ratio.min(q.star_ratio);
                max_cell_vertices = max_cell_vertices.max(mesh.polygon(p).len());
            }
        }
        let active_nodes = solved.nodes.iter().filter(|n| n.status.is_active()).count();
        let mut record = CycleRecord {
            cycle,
            unknowns,
            cells,
            estimate: eta,
            parts,
            grad_error,
            relative_grad,
            energy_error,
            effectivity: energy_error.filter(|e| *e > 0.0).map(|e| eta / e),
            strain_energy,
            refined: 0,
            min_star_ratio,
            max_cell_vertices,
            active_nodes,
        };
        cycle += 1;
        if cycle >= settings.max_cycles || unknowns >= settings.max_unknowns {
            records.push(record);
            return Ok(AdaptiveRun {
                records,
                last: solved,
            });
        }
        // Mark over all bodies together, refine each body's mesh.
        let indicators = solved.cell_indicators();
        let all: Vec<f64> = indicators.iter().flatten().copied().collect();
        let mesh_error = |body: usize| {
            move |source| VerifyError::Mesh {
                case: name.to_string(),
                body: body + 1,
                family: "adaptive refinement".to_string(),
                n: cycle,
                source: Box::new(source),
            }
        };
        let marked = if settings.uniform {
            (0..all.len()).collect()
        } else {
            dorfler_marking(&all, settings.theta).map_err(mesh_error(0))?
        };
        let mut next = Vec::with_capacity(indicators.len());
        let mut offset = 0;
        for (b, result) in solved.bodies.iter().enumerate() {
            let n = indicators[b].len();
            let mine: Vec<usize> = marked
                .iter()
                .filter(|&&c| c >= offset && c < offset + n)
                .map(|&c| c - offset)
                .collect();
            offset += n;
            record.refined += mine.len();
            next.push(
                refine(result.body.mesh(), &mine)
                    .map_err(mesh_error(b))?
                    .mesh,
            );
        }
        records.push(record);
        meshes = next;
    }
}

/// The least-squares slope of `log error` against `log unknowns` over `records` (the rate in
/// unknowns: `-1/2` is optimal for the lowest-order method in the plane), with `error` picked
/// from each record; `None` when fewer than two records have one.
pub fn slope_in_unknowns(
    records: &[CycleRecord],
    error: impl Fn(&CycleRecord) -> Option<f64>,
) -> Option<f64> {
    let (n, e): (Vec<f64>, Vec<f64>) = records
        .iter()
        .filter_map(|r| error(r).map(|e| (r.unknowns as f64, e)))
        .unzip();
    crate::study::fitted_rate(&n, &e)
}

/// The `build` of [`run`] for an exact solution: its bodies on given meshes
/// ([`DiscreteProblem`]), in contact when the case is a contact case.
pub fn case_model(
    exact: Arc<dyn ExactSolution>,
    settings: ProblemSettings,
) -> impl Fn(Vec<Mesh>) -> Result<Model, VerifyError> {
    move |meshes| {
        let problem = DiscreteProblem::try_new(Arc::clone(&exact), meshes, &settings)?;
        Ok(match problem.contact_problem() {
            Some(contact) => Model::Contact(contact),
            None => Model::Elastic(problem.bodies().to_vec()),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exact::{case_by_name, Lame};
    use vem_contact::{CondensedSettings, CondensedSolver};
    use vem_mesh::generators::{structured_quads, structured_triangles, voronoi};
    use vem_space::LowestOrderVem;

    /// The default contact solver: condensed, certified.
    fn solver() -> CondensedSolver {
        CondensedSolver::new(CondensedSettings::default())
    }

    fn case(name: &str) -> Arc<dyn ExactSolution> {
        case_by_name(name, Lame::default()).unwrap().into()
    }

    fn meshes_of(exact: &dyn ExactSolution, family: &str, n: usize) -> Vec<Mesh> {
        exact
            .bodies()
            .iter()
            .enumerate()
            .map(|(k, &id)| {
                let rect = exact.domain(id);
                // Body two one size finer: non-matching on the interface.
                let n = n + k * (n / 4).max(1);
                match family {
                    "quads" => structured_quads(&rect, n, n).unwrap(),
                    "triangles" => structured_triangles(&rect, n, n).unwrap(),
                    _ => voronoi(&rect, n * n, 7 + k as u64).unwrap(),
                }
            })
            .collect()
    }

    /// The two-body patch tests (frictionless and Tresca, slip and stick): the discrete
    /// solution is the linear field, and every term of the estimate, the contact terms
    /// included, vanishes to round-off, also after a refinement with hanging nodes.
    #[test]
    fn estimate_vanishes_on_contact_patch_tests() {
        for name in ["PTC1", "PTC2", "PTC3"] {
            let exact = case(name);
            let build = case_model(Arc::clone(&exact), ProblemSettings::default());
            let mut meshes = meshes_of(&*exact, "quads", 3);
            meshes[0] = refine(&meshes[0], &[0, 4]).unwrap().mesh;
            let model = build(meshes).unwrap();
            let solved = solve_and_estimate(name, &model, &mut solver()).unwrap();
            let energy: f64 = solved
                .bodies
                .iter()
                .map(|b| b.solution.strain_energy())
                .sum();
            let eta = solved.estimate.total();
            // eta^2 is a sum of quadratic forms that vanish: round-off against the energy.
            assert!(
                eta * eta < 1e-12 * energy,
                "{name}: eta {eta:e}, energy {energy:e}"
            );
        }
    }

    /// The effectivity index `eta / E_en` on the smooth cases E1 (elasticity) and M1
    /// (frictionless contact), on three mesh families and two sizes each: it stays in the
    /// band documented in docs/adaptivity.md.
    #[test]
    fn effectivity_stays_in_its_band() {
        let element = LowestOrderVem::default();
        for name in ["E1", "M1"] {
            let exact = case(name);
            let build = case_model(Arc::clone(&exact), ProblemSettings::default());
            for family in ["quads", "triangles", "voronoi"] {
                for n in [6, 12] {
                    let settings = AdaptiveSettings {
                        max_cycles: 1,
                        ..AdaptiveSettings::default()
                    };
                    let run = run(
                        name,
                        &build,
                        meshes_of(&*exact, family, n),
                        &element,
                        &Reference::Exact(Arc::clone(&exact)),
                        &settings,
                        &mut solver(),
                    )
                    .unwrap();
                    let effectivity = run.records[0].effectivity.unwrap();
                    eprintln!("{name} {family} {n}: effectivity {effectivity:.3}");
                    assert!(
                        (EFFECTIVITY_BAND.0..EFFECTIVITY_BAND.1).contains(&effectivity),
                        "{name} {family} {n}: {effectivity}"
                    );
                }
            }
        }
    }

    /// The effectivity index on M2 (Tresca friction, stick and slip zones; exact solution),
    /// where the friction terms of the estimate are active: in [`FRICTION_EFFECTIVITY_BAND`]
    /// on three mesh families and two sizes, and the friction complementarity is part of the
    /// estimate.
    #[test]
    fn effectivity_with_friction_stays_in_its_band() {
        let element = LowestOrderVem::default();
        let exact = case("M2");
        let build = case_model(Arc::clone(&exact), ProblemSettings::default());
        for family in ["quads", "triangles", "voronoi"] {
            for n in [6, 12] {
                let model = build(meshes_of(&*exact, family, n)).unwrap();
                let solved = solve_and_estimate("M2", &model, &mut solver()).unwrap();
                let settings = AdaptiveSettings {
                    max_cycles: 1,
                    ..AdaptiveSettings::default()
                };
                let run = run(
                    "M2",
                    &build,
                    meshes_of(&*exact, family, n),
                    &element,
                    &Reference::Exact(Arc::clone(&exact)),
                    &settings,
                    &mut solver(),
                )
                .unwrap();
                let effectivity = run.records[0].effectivity.unwrap();
                eprintln!(
                    "M2 {family} {n}: effectivity {effectivity:.3}, friction term {:.3e}",
                    solved.estimate.friction
                );
                assert!(
                    (FRICTION_EFFECTIVITY_BAND.0..FRICTION_EFFECTIVITY_BAND.1)
                        .contains(&effectivity),
                    "M2 {family} {n}: {effectivity}"
                );
            }
        }
    }

    /// Five adaptive cycles on M1: every mesh is valid (each refinement is built by the
    /// validating constructor), the error decreases, and the adaptive answer approaches the
    /// uniform one (the strain energies of the finest meshes agree).
    #[test]
    fn adaptive_m1_converges_to_the_uniform_answer() {
        let exact = case("M1");
        let element = LowestOrderVem::default();
        let build = case_model(Arc::clone(&exact), ProblemSettings::default());
        let reference = Reference::Exact(Arc::clone(&exact));
        let adaptive = run(
            "M1",
            &build,
            meshes_of(&*exact, "quads", 4),
            &element,
            &reference,
            &AdaptiveSettings {
                max_cycles: 6,
                theta: 0.5,
                ..AdaptiveSettings::default()
            },
            &mut solver(),
        )
        .unwrap();
        let uniform = run(
            "M1",
            &build,
            meshes_of(&*exact, "quads", 4),
            &element,
            &reference,
            &AdaptiveSettings {
                max_cycles: 4,
                uniform: true,
                ..AdaptiveSettings::default()
            },
            &mut solver(),
        )
        .unwrap();
        let errors: Vec<f64> = adaptive
            .records
            .iter()
            .map(|r| r.grad_error.unwrap())
            .collect();
        assert!(errors.windows(2).all(|w| w[1] < w[0]), "E_grad {errors:?}");
        let (a, u) = (
            adaptive.records.last().unwrap(),
            uniform.records.last().unwrap(),
        );
        assert!(a.refined == 0 && a.min_star_ratio > 0.1);
        // Both approach the exact strain energy: they agree to the size of their errors.
        let gap = (a.strain_energy - u.strain_energy).abs() / u.strain_energy;
        assert!(gap < 0.02, "{} vs {}", a.strain_energy, u.strain_energy);
    }
}
