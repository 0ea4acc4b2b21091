//! Solves of the exact solutions in space on the polyhedral families, and convergence tables.
//!
//! Every problem is a [`vem_scene::Scene`] built into a [`vem_scene::Model`]
//! ([`solid_scene`], [`disc_contact_scene`]): the meshes inline, the exact data as functions,
//! the element and the contact law registered under the names [`ELEMENT`] and [`LAW`].

use std::sync::Arc;
use std::time::Instant;

use serde::{Deserialize, Serialize};
use vem_contact::{ContactLaw, ContactProblem, ContactResult, ContactSolver, NodeStatus};
use vem_elastic::{CholeskySolver, ElasticBody};
use vem_mesh::generators::polyhedral::PolyhedralFamily;
use vem_mesh::{Point3, PolyhedralMesh, Vector3};
use vem_scene::description::{
    BodyDescription, ContactDescription, DirichletDescription, MaterialDescription,
    TractionDescription,
};
use vem_scene::{BuildOptions, BuiltMesh, Model, Registries, ScalarValue, Scene, VectorValue};
use vem_space::{Choice, PolyhedralElement};

use super::norms::{body_errors_3d, nodal_interpolant_3d};
use super::{ExactSolution3d, StackedContact, CUBE_PARTS};
use crate::exact::BodyId;
use crate::norms::ErrorNorms;
use crate::problem::{scene_name, ELEMENT, LAW};
use crate::study::fitted_rate;
use crate::VerifyError;

/// The seed of the random families (perturbed hexahedra, Voronoi) in the studies.
pub const SOLID_SEED: u64 = 1;

/// One solve of an exact solution in space on one mesh, with what it measured.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SolidRun {
    /// The case ("E1-3D", ...).
    pub case: String,
    /// The mesh family.
    pub family: String,
    /// The element ("vem1", "vem1-bbar", ...).
    pub element: String,
    /// The size parameter (cells across x).
    pub n: usize,
    /// Number of cells.
    pub cells: usize,
    /// Number of vertices.
    pub vertices: usize,
    /// Number of unknowns of the reduced system.
    pub unknowns: usize,
    /// Mesh size `h` (largest cell diameter).
    pub h: f64,
    /// The mean cell size `(|Omega| / cells)^(1/3)`: what the rates are fitted against (the
    /// largest diameter of a random mesh is an outlier statistic that does not halve exactly
    /// when the cells are eight times as many; for the structured families the two are
    /// proportional).
    pub spacing: f64,
    /// `E_grad`, `E_0`, `E_a` and the norms of the exact solution.
    pub errors: ErrorNorms,
    /// `max_v |u_h(v) - u(v)| / max_v |u(v)|` over the vertices.
    pub nodal_error: f64,
    /// Wall-clock seconds of mesh generation, assembly, solve and measures.
    pub seconds: f64,
    /// A two-body contact case: what the contact solve found on the interface (the other
    /// fields then sum or take the largest over both bodies).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact: Option<SolidContact>,
}

/// What a contact solve of a [`StackedContact`] case found on the interface, against the exact
/// zones (M1-3D: the contact disc `r < r_c`; M2-3D: the stick disc `r < r_s`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SolidContact {
    /// The family of the lower body (the upper body's is the run's family's first word).
    pub lower_family: String,
    /// The size of the lower body's mesh.
    pub lower_n: usize,
    /// The contact solver.
    pub solver: String,
    /// How the solve ended, as `vem_contact::SolveStatus` spells it ("Converged", ...).
    pub status: String,
    /// The solver's iterations.
    pub iterations: usize,
    /// Interface nodes (node pairs after the surface overlay).
    pub interface_nodes: usize,
    /// Vertices the overlay inserted into the two meshes.
    pub inserted_nodes: usize,
    /// Interface nodes in contact.
    pub active_nodes: usize,
    /// The largest distance `r` to the disc's centre of a node in contact (0 without any).
    pub outermost_contact: f64,
    /// The smallest distance `r` of a node out of contact (infinite without any).
    pub innermost_open: f64,
    /// The sum of the nodal contact forces.
    pub normal_resultant: f64,
    /// The exact resultant `int p dA` ([`StackedContact::exact_normal_resultant`]).
    pub exact_resultant: f64,
    /// With friction: the stick and slip zones and the friction resultant.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction: Option<SolidFriction>,
}

/// What a contact solve with friction found on the interface, against the exact stick disc.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SolidFriction {
    /// Interface nodes that stick.
    pub stick_nodes: usize,
    /// Interface nodes that slip.
    pub slip_nodes: usize,
    /// The largest distance `r` to the disc's centre of a node that sticks (0 without any).
    pub outermost_stick: f64,
    /// The smallest distance `r` of a node that slips (infinite without any).
    pub innermost_slip: f64,
    /// The sum of the nodal friction forces on body one, `(x, y)` components.
    pub friction_resultant: [f64; 2],
    /// The exact `int sigma_1tau dA` ([`StackedContact::exact_friction_resultant`]).
    pub exact_friction_resultant: [f64; 2],
}

/// The scene's body `name` of `exact` on `mesh` with the element registered as [`ELEMENT`]:
/// its mesh inline, the material of the case (`lambda`, `mu`), the Dirichlet data `u` on every
/// side of its box but the traction and contact sides, `sigma n` on the traction sides, nothing
/// on the contact sides, the body force `f`, all as functions.
fn solid_description(exact: &Arc<dyn ExactSolution3d>, mesh: PolyhedralMesh) -> BodyDescription {
    let lame = exact.lame();
    let mut spec = BodyDescription {
        name: scene_name(exact.name()),
        mesh: BuiltMesh::Space(mesh).to_inline(),
        material: MaterialDescription {
            lambda: Some(lame.lambda()),
            mu: Some(lame.mu()),
            ..MaterialDescription::default()
        },
        element: Some(Choice::named(ELEMENT)),
        ..BodyDescription::default()
    };
    for (part, normal) in CUBE_PARTS {
        if exact.contact_sides().contains(&part) {
            continue;
        }
        if exact.traction_sides().contains(&part) {
            let normal = Vector3::from(normal);
            let exact = Arc::clone(exact);
            spec.traction.push(TractionDescription {
                part: part.to_string(),
                value: Some(VectorValue::function(move |x, _| {
                    (exact.stress(point(x)) * normal).as_slice().to_vec()
                })),
                ..TractionDescription::default()
            });
        } else {
            let component = |k: usize| {
                let exact = Arc::clone(exact);
                Some(ScalarValue::function(move |x, _| {
                    exact.displacement(point(x))[k]
                }))
            };
            spec.dirichlet.push(DirichletDescription {
                part: part.to_string(),
                x: component(0),
                y: component(1),
                z: component(2),
                ..DirichletDescription::default()
            });
        }
    }
    let force = Arc::clone(exact);
    spec.body_force = Some(VectorValue::function(move |x, _| {
        force.body_force(point(x)).as_slice().to_vec()
    }));
    spec
}

/// The point of the coordinates `x` of a scene's function.
fn point(x: &[f64]) -> Point3 {
    Point3::new(x[0], x[1], x[2])
}

/// The registries of a scene in space with `element` registered as [`ELEMENT`] (and, for
/// contact, `law` as [`LAW`]).
fn registries_with(
    element: Arc<dyn PolyhedralElement>,
    law: Option<Arc<dyn ContactLaw<3>>>,
) -> Result<Registries, VerifyError> {
    let invalid = |what: &str, e: vem_space::RegistryError| VerifyError::InvalidSetting {
        reason: format!("{what}: {e}"),
    };
    let mut registries = Registries::default();
    let summary = format!("the element of the study: {}", element.name());
    registries
        .elements
        .register_polyhedral(ELEMENT, summary, move |options, _| {
            options.refuse_all(ELEMENT)?;
            Ok(Arc::clone(&element))
        })
        .map_err(|e| invalid("element", e))?;
    if let Some(law) = law {
        let summary = format!("the law of the study: {}", law.describe());
        registries
            .laws_3d
            .register(LAW, summary, move |options| {
                options.refuse_all(LAW)?;
                Ok(Arc::clone(&law))
            })
            .map_err(|e| invalid("law", e))?;
    }
    Ok(registries)
}

/// The model of `scene` built with `registries`; errors name `case`.
fn build_model(scene: &Scene, registries: Registries, case: &str) -> Result<Model, VerifyError> {
    let options = BuildOptions {
        registries,
        ..BuildOptions::default()
    };
    Model::build(scene, &options).map_err(|source| VerifyError::Scene {
        case: case.to_string(),
        source: Box::new(source),
    })
}

/// The scene of `exact` on `mesh` with `element` (registered as [`ELEMENT`]): one body, see
/// [`solid_body`]. Its functions do not serialise; look at it with `Debug`.
///
/// # Errors
/// [`VerifyError::InvalidSetting`] if the element cannot be registered.
pub fn solid_scene(
    exact: &Arc<dyn ExactSolution3d>,
    mesh: PolyhedralMesh,
    element: Arc<dyn PolyhedralElement>,
) -> Result<(Scene, Registries), VerifyError> {
    let scene = Scene {
        title: Some(exact.name().to_string()),
        bodies: vec![solid_description(exact, mesh)],
        ..Scene::default()
    };
    Ok((scene, registries_with(element, None)?))
}

/// The body of `exact` on `mesh` with `element`, built from its scene ([`solid_scene`]): the
/// material of the case, the Dirichlet data `u` on every side of its box but the traction and
/// contact sides, `sigma n` on the traction sides, nothing on the contact sides, the body
/// force `f`.
///
/// # Errors
/// [`VerifyError::Scene`] for a scene the model refuses (an invalid material, a side the mesh
/// does not name).
pub fn solid_body(
    exact: Arc<dyn ExactSolution3d>,
    mesh: PolyhedralMesh,
    element: Arc<dyn PolyhedralElement>,
) -> Result<ElasticBody<3>, VerifyError> {
    let (scene, registries) = solid_scene(&exact, mesh, element)?;
    let model = build_model(&scene, registries, exact.name())?;
    Ok(model.bodies_3d()[0].body.clone())
}

/// Solves `exact` on `mesh` with `element` and measures the errors.
pub fn solve_solid(
    exact: Arc<dyn ExactSolution3d>,
    mesh: PolyhedralMesh,
    element: Arc<dyn PolyhedralElement>,
) -> Result<(ElasticBody<3>, Vec<f64>, ErrorNorms), VerifyError> {
    let elastic = |source| VerifyError::Elastic {
        case: exact.name().to_string(),
        source: Box::new(source),
    };
    let body = solid_body(Arc::clone(&exact), mesh, element)?;
    let system = body.assemble().map_err(elastic)?;
    let solution = body
        .solve_system(&system, &mut CholeskySolver::default())
        .map_err(elastic)?;
    let displacement = solution.displacement().to_vec();
    let errors = body_errors_3d(&*exact, &body, &system, &displacement)?;
    Ok((body, displacement, errors))
}

/// Generates the mesh of `family` with size `n` on the box of `exact` and solves it there.
pub fn run_solid(
    exact: Arc<dyn ExactSolution3d>,
    family: PolyhedralFamily,
    n: usize,
    element: Arc<dyn PolyhedralElement>,
) -> Result<SolidRun, VerifyError> {
    let start = Instant::now();
    let mesh = family
        .generate(&exact.domain(), n, SOLID_SEED)
        .map_err(|source| VerifyError::Mesh {
            case: exact.name().to_string(),
            body: 1,
            family: family.name().to_string(),
            n,
            source: Box::new(source),
        })?;
    let (cells, vertices, h) = (mesh.n_cells(), mesh.n_vertices(), mesh.mesh_size());
    let element_name = element.name().to_string();
    let (body, displacement, errors) = solve_solid(Arc::clone(&exact), mesh, element)?;
    let interpolant = nodal_interpolant_3d(&*exact, body.mesh());
    Ok(SolidRun {
        case: exact.name().to_string(),
        family: family.name().to_string(),
        element: element_name,
        n,
        cells,
        vertices,
        unknowns: body.dofs().n_unknowns(),
        h,
        spacing: (exact.domain().volume() / cells as f64).cbrt(),
        errors,
        nodal_error: relative_nodal_error(&interpolant, &displacement),
        seconds: start.elapsed().as_secs_f64(),
        contact: None,
    })
}

/// `max_v |u_h(v) - u(v)| / max_v |u(v)|` over the vertices (`interpolant` holds `u(v)`); the
/// absolute value when `u` vanishes at every vertex.
fn relative_nodal_error(interpolant: &[f64], displacement: &[f64]) -> f64 {
    let largest = |v: &mut dyn Iterator<Item = f64>| v.fold(0.0f64, f64::max);
    let difference = largest(
        &mut interpolant
            .chunks(3)
            .zip(displacement.chunks(3))
            .map(|(a, b)| Vector3::from_column_slice(a) - Vector3::from_column_slice(b))
            .map(|d| d.norm()),
    );
    let scale = largest(
        &mut interpolant
            .chunks(3)
            .map(|a| Vector3::from_column_slice(a).norm()),
    );
    if scale > 0.0 {
        difference / scale
    } else {
        difference
    }
}

/// The scene of the contact case `exact` on the meshes `upper` (of body one's box) and `lower`
/// (of body two's box) with `element`: each body's data as in [`solid_scene`], the pair body
/// one's bottom against body two's top with the case's law (registered as [`LAW`]) and
/// imposed gap (the two sides coincide, the geometric gap is zero).
///
/// # Errors
/// [`VerifyError::InvalidSetting`] if the element or the law cannot be registered.
pub fn disc_contact_scene(
    exact: &dyn StackedContact,
    upper: PolyhedralMesh,
    lower: PolyhedralMesh,
    element: Arc<dyn PolyhedralElement>,
) -> Result<(Scene, Registries), VerifyError> {
    let one = solid_description(&exact.exact_body(BodyId::One), upper);
    let two = solid_description(&exact.exact_body(BodyId::Two), lower);
    let gap = exact.imposed_gap();
    let contact = ContactDescription {
        body: one.name.clone(),
        part: "bottom".to_string(),
        other_body: Some(two.name.clone()),
        other_part: Some("top".to_string()),
        law: Some(Choice::named(LAW)),
        imposed_gap: Some(ScalarValue::function(move |x, _| gap(x[0], x[1]))),
        ..ContactDescription::default()
    };
    let scene = Scene {
        title: Some(exact.name().to_string()),
        bodies: vec![one, two],
        contacts: vec![contact],
        ..Scene::default()
    };
    Ok((scene, registries_with(element, Some(exact.law()))?))
}

/// The contact problem of `exact` on the meshes `upper` and `lower` with `element`, built from
/// its scene ([`disc_contact_scene`]).
///
/// # Errors
/// [`VerifyError::Scene`] for a scene the model refuses.
pub fn disc_contact_problem(
    exact: &dyn StackedContact,
    upper: PolyhedralMesh,
    lower: PolyhedralMesh,
    element: Arc<dyn PolyhedralElement>,
) -> Result<ContactProblem<3>, VerifyError> {
    let (scene, registries) = disc_contact_scene(exact, upper, lower, element)?;
    let model = build_model(&scene, registries, exact.name())?;
    let (problem, _) = model
        .contact_problem_3d()
        .expect("the scene has a contact pair");
    Ok(problem.clone())
}

/// Solves the contact problem of `exact` on `upper` and `lower` ([`disc_contact_problem`]) with
/// `solver` and measures the errors of each body on its own mesh after the overlay (the
/// vertices it inserted included), in the order body one, body two.
///
/// # Errors
/// As [`disc_contact_problem`], a failed contact solve, the error measures.
pub fn solve_disc_contact(
    exact: &dyn StackedContact,
    upper: PolyhedralMesh,
    lower: PolyhedralMesh,
    element: Arc<dyn PolyhedralElement>,
    solver: &mut dyn ContactSolver,
) -> Result<(ContactResult<3>, [ErrorNorms; 2]), VerifyError> {
    let problem = disc_contact_problem(exact, upper, lower, element)?;
    let result = problem
        .solve(solver)
        .map_err(|source| VerifyError::Contact {
            case: exact.name().to_string(),
            source: Box::new(source),
        })?;
    let mut errors = [ErrorNorms::default(); 2];
    for (k, id) in BodyId::BOTH.into_iter().enumerate() {
        let solved = &result.bodies[k];
        errors[k] = body_errors_3d(
            &*exact.exact_body(id),
            &solved.body,
            &solved.system,
            solved.solution.displacement(),
        )?;
    }
    Ok((result, errors))
}

/// Generates the upper body's mesh of family `upper.0` with size `upper.1` and the lower body's
/// of `lower.0`, `lower.1` (with [`SOLID_SEED`]), solves the case `exact` on them with `solver`
/// and measures: the run's family is "`upper` over `lower`", its size the upper body's, its
/// cells, vertices and unknowns the sums over both bodies (after the overlay), `h` the larger
/// largest cell diameter, the spacing the larger mean cell size `(|Omega_i| / cells_i)^(1/3)`
/// (`h = max(h_1, h_2)` of Theorem 4.1: the coarser body's), the errors combined over both
/// bodies ([`ErrorNorms::combine`]), [`SolidRun::contact`] what the interface shows.
///
/// # Errors
/// A mesh that cannot be generated, as [`solve_disc_contact`].
pub fn run_disc_contact(
    exact: &dyn StackedContact,
    upper: (PolyhedralFamily, usize),
    lower: (PolyhedralFamily, usize),
    element: Arc<dyn PolyhedralElement>,
    solver: &mut dyn ContactSolver,
) -> Result<SolidRun, VerifyError> {
    let start = Instant::now();
    let mesh = |id: BodyId, (family, n): (PolyhedralFamily, usize)| {
        family
            .generate(&exact.exact_body(id).domain(), n, SOLID_SEED)
            .map_err(|source| VerifyError::Mesh {
                case: exact.name().to_string(),
                body: id.index() + 1,
                family: family.name().to_string(),
                n,
                source: Box::new(source),
            })
    };
    let (upper_mesh, lower_mesh) = (mesh(BodyId::One, upper)?, mesh(BodyId::Two, lower)?);
    let element_name = element.name().to_string();
    let (result, errors) = solve_disc_contact(exact, upper_mesh, lower_mesh, element, solver)?;
    let (mut interpolant, mut displacement) = (Vec::new(), Vec::new());
    let (mut cells, mut vertices, mut unknowns, mut h, mut spacing) = (0, 0, 0, 0.0f64, 0.0f64);
    for (k, id) in BodyId::BOTH.into_iter().enumerate() {
        let solved = &result.bodies[k];
        let mesh = solved.body.mesh();
        interpolant.extend(nodal_interpolant_3d(&*exact.exact_body(id), mesh));
        displacement.extend_from_slice(solved.solution.displacement());
        cells += mesh.n_cells();
        vertices += mesh.n_vertices();
        unknowns += solved.body.dofs().n_unknowns();
        h = h.max(mesh.mesh_size());
        spacing = spacing.max((1.0 / mesh.n_cells() as f64).cbrt());
    }
    let radius = |n: &vem_contact::InterfaceNode<3>| (n.position.x - 0.5).hypot(n.position.y - 0.5);
    let active = result.nodes.iter().filter(|n| n.status.is_active());
    let open = result.nodes.iter().filter(|n| !n.status.is_active());
    let with_status = |status: NodeStatus| result.nodes.iter().filter(move |n| n.status == status);
    let exact_friction = exact.exact_friction_resultant();
    let friction = result.friction_resultant();
    let friction = (exact_friction != nalgebra::Vector2::zeros()).then(|| SolidFriction {
        stick_nodes: with_status(NodeStatus::Stick).count(),
        slip_nodes: with_status(NodeStatus::Slip).count(),
        outermost_stick: with_status(NodeStatus::Stick)
            .map(radius)
            .fold(0.0, f64::max),
        innermost_slip: with_status(NodeStatus::Slip)
            .map(radius)
            .fold(f64::INFINITY, f64::min),
        friction_resultant: [friction.x, friction.y],
        exact_friction_resultant: [exact_friction.x, exact_friction.y],
    });
    let contact = SolidContact {
        lower_family: lower.0.name().to_string(),
        lower_n: lower.1,
        solver: result.report.solver.to_string(),
        status: format!("{:?}", result.report.status),
        iterations: result.report.iterations,
        interface_nodes: result.nodes.len(),
        inserted_nodes: result.model.inserted_nodes,
        active_nodes: active.clone().count(),
        outermost_contact: active.map(radius).fold(0.0, f64::max),
        innermost_open: open.map(radius).fold(f64::INFINITY, f64::min),
        normal_resultant: result.normal_resultant(),
        exact_resultant: exact.exact_normal_resultant(),
        friction,
    };
    Ok(SolidRun {
        case: exact.name().to_string(),
        family: format!("{} over {}", upper.0.name(), lower.0.name()),
        element: element_name,
        n: upper.1,
        cells,
        vertices,
        unknowns,
        h,
        spacing,
        errors: ErrorNorms::combine(&errors),
        nodal_error: relative_nodal_error(&interpolant, &displacement),
        seconds: start.elapsed().as_secs_f64(),
        contact: Some(contact),
    })
}

/// The convergence study in space: every case of `cases` on every family of `families` at
/// every size of `sizes`, with `element`, in that order (case-major). The integrator's entry
/// point for `cargo xtask convergence`; [`solid_rates`] fits the rates of its runs and
/// [`solid_markdown`] prints them.
pub fn three_d_convergence(
    cases: &[Arc<dyn ExactSolution3d>],
    families: &[PolyhedralFamily],
    sizes: &[usize],
    element: Arc<dyn PolyhedralElement>,
) -> Result<Vec<SolidRun>, VerifyError> {
    if sizes.is_empty() {
        return Err(VerifyError::InvalidSetting {
            reason: "the study in space needs at least one size".into(),
        });
    }
    let mut runs = Vec::new();
    for case in cases {
        for &family in families {
            for &n in sizes {
                runs.push(run_solid(
                    Arc::clone(case),
                    family,
                    n,
                    Arc::clone(&element),
                )?);
            }
        }
    }
    Ok(runs)
}

/// The fitted rates of one (case, family, element) series.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SolidRates {
    /// The case.
    pub case: String,
    /// The mesh family.
    pub family: String,
    /// The element.
    pub element: String,
    /// The sizes of the series.
    pub sizes: Vec<usize>,
    /// The errors at the finest size.
    pub finest: ErrorNorms,
    /// The mesh size at the finest size.
    pub h: f64,
    /// The least-squares rate of `E_grad` against the mean cell size over the last `fit` sizes.
    pub grad_rate: Option<f64>,
    /// The rate of `E_0`.
    pub l2_rate: Option<f64>,
    /// The rate of `E_a`.
    pub energy_rate: Option<f64>,
}

/// Groups `runs` by (case, family, element), in order of first appearance, and fits each
/// series' rates against the mean cell size ([`SolidRun::spacing`]) by least squares over its
/// last `fit` sizes (at least 2).
pub fn solid_rates(runs: &[SolidRun], fit: usize) -> Vec<SolidRates> {
    let mut keys: Vec<(&str, &str, &str)> = Vec::new();
    for run in runs {
        let key = (run.case.as_str(), run.family.as_str(), run.element.as_str());
        if !keys.contains(&key) {
            keys.push(key);
        }
    }
    keys.into_iter()
        .map(|(case, family, element)| {
            let series: Vec<&SolidRun> = runs
                .iter()
                .filter(|r| r.case == case && r.family == family && r.element == element)
                .collect();
            let tail = &series[series.len().saturating_sub(fit.max(2))..];
            let h: Vec<f64> = tail.iter().map(|r| r.spacing).collect();
            let rate = |f: fn(&ErrorNorms) -> f64| {
                let e: Vec<f64> = tail.iter().map(|r| f(&r.errors)).collect();
                fitted_rate(&h, &e)
            };
            let last = series.last().expect("a series has a run");
            SolidRates {
                case: case.to_string(),
                family: family.to_string(),
                element: element.to_string(),
                sizes: series.iter().map(|r| r.n).collect(),
                finest: last.errors,
                h: last.h,
                grad_rate: rate(|e| e.grad),
                l2_rate: rate(|e| e.l2),
                energy_rate: rate(|e| e.energy),
            }
        })
        .collect()
}

/// The runs and the fitted rates as Markdown tables: one row per run, then one per series.
pub fn solid_markdown(runs: &[SolidRun], rates: &[SolidRates]) -> String {
    use std::fmt::Write as _;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "| case | family | element | n | cells | unknowns | h | E_grad / abs1 | E_0 / abs0 | E_a | seconds |"
    );
    let _ = writeln!(out, "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|");
    for r in runs {
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {} | {} | {:.4} | {:.3e} | {:.3e} | {:.3e} | {:.1} |",
            r.case,
            r.family,
            r.element,
            r.n,
            r.cells,
            r.unknowns,
            r.h,
            r.errors.relative_grad(),
            r.errors.relative_l2(),
            r.errors.energy,
            r.seconds
        );
    }
    let _ = writeln!(out);
    let _ = writeln!(
        out,
        "| case | family | element | sizes | E_grad rate | E_0 rate | E_a rate | E_grad, E_0 at finest |"
    );
    let _ = writeln!(out, "|---|---|---|---|---:|---:|---:|---|");
    let show = |r: Option<f64>| r.map_or("-".to_string(), |r| format!("{r:.2}"));
    for r in rates {
        let sizes: Vec<String> = r.sizes.iter().map(|n| n.to_string()).collect();
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {} | {} | {} | {:.3e}, {:.3e} |",
            r.case,
            r.family,
            r.element,
            sizes.join(", "),
            show(r.grad_rate),
            show(r.l2_rate),
            show(r.energy_rate),
            r.finest.grad,
            r.finest.l2
        );
    }
    out
}
