//! `cargo xtask adaptivity`: adaptive against uniform refinement in the plane - M1
//! (frictionless, smooth, exact solution), M2 (Tresca friction with stick and slip zones,
//! exact solution), the flat punch (frictionless, singular stresses at the punch's corners),
//! the L-shape and Hertz - with the estimator's effectivity and pictures of the adapted
//! meshes. Writes docs/adaptivity.md (or `--out`) and its figures.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use clap::Args;
use serde::{Deserialize, Serialize};
use serde_json::json;
use vem_contact::{CondensedSettings, CondensedSolver};
use vem_mesh::generators::{structured_quads, Rectangle};
use vem_mesh::io::{write_svg_layers, SvgLayer, SvgOptions};
use vem_mesh::{Mesh, PartSpec, Point};
use vem_scene::{body_mesh, BuildOptions, BuiltMesh, MeshDescription, Model, Scene};
use vem_space::LowestOrderVem;
use vem_verify::adaptive::{
    case_model, run as adapt, AdaptiveRun, AdaptiveSettings, CycleRecord, Model as AdaptiveModel,
    Reference,
};
use vem_verify::exact::{case_by_name, Lame};
use vem_verify::plot::{loglog_svg, LogLogPlot};
use vem_verify::problem::ProblemSettings;
use vem_verify::report::{write_json, write_text};
use vem_verify::study::fitted_rate;
use vem_verify::VerifyError;

/// Options of `cargo xtask adaptivity`.
#[derive(Debug, Args)]
pub struct AdaptivityArgs {
    /// The report; its figures go to the folder `adaptivity/` beside it.
    #[arg(long, default_value = "docs/adaptivity.md")]
    out: PathBuf,
    /// A quick run for CI (fewer cycles, a smaller reference), written under target/.
    #[arg(long)]
    quick: bool,
    /// Rewrite the report and its figures from `adaptivity/adaptivity.json` and
    /// `adaptivity/meshes.json` beside it, without solving.
    #[arg(long)]
    report_only: bool,
}

/// Young's modulus and Poisson's ratio of both bodies of the problems without an exact
/// solution (plane strain).
const YOUNG: f64 = 100.0;
const POISSON: f64 = 0.3;
/// The punch's and the L-shape's top moves down by this.
const INDENTATION: f64 = 0.01;
/// Dorfler's bulk fraction.
const THETA: f64 = 0.5;

/// A problem of the study given as a scene: the initial meshes are the scene's (generated, or
/// read from files relative to `base`); after a refinement the same scene is built again with
/// the refined meshes given inline ([`BuiltMesh::to_inline`]).
struct SceneProblem {
    name: &'static str,
    scene: Scene,
    base: PathBuf,
}

impl SceneProblem {
    /// The scene of `value` (its keys as in a scene file), its files relative to `base`.
    fn new(
        name: &'static str,
        value: serde_json::Value,
        base: &str,
    ) -> Result<Self, Box<dyn std::error::Error>> {
        Ok(Self {
            name,
            scene: Scene::from_value(value)?,
            base: PathBuf::from(base),
        })
    }

    /// The initial meshes, as `Model::build` makes them.
    fn meshes(&self) -> Result<Vec<Mesh>, Box<dyn std::error::Error>> {
        (0..self.scene.bodies.len())
            .map(|i| match body_mesh(&self.scene, i, &self.base)?.0 {
                BuiltMesh::Plane(mesh) => Ok(mesh),
                BuiltMesh::Space(_) => Err(format!("{}: a body in space", self.name).into()),
            })
            .collect()
    }

    /// The model of the scene on `meshes` (one per body, in the scene's order).
    fn model(&self, meshes: Vec<Mesh>) -> Result<AdaptiveModel, VerifyError> {
        let invalid = |reason: String| VerifyError::InvalidSetting {
            reason: format!("{}: {reason}", self.name),
        };
        let mut scene = self.scene.clone();
        if meshes.len() != scene.bodies.len() {
            return Err(invalid(format!(
                "{} meshes for {} bodies",
                meshes.len(),
                scene.bodies.len()
            )));
        }
        for (body, mesh) in scene.bodies.iter_mut().zip(meshes) {
            body.mesh = BuiltMesh::Plane(mesh).to_inline();
        }
        let options = BuildOptions {
            base: self.base.clone(),
            ..BuildOptions::default()
        };
        let model = Model::build(&scene, &options).map_err(|e| invalid(e.to_string()))?;
        let (problem, _) = model
            .contact_problem()
            .ok_or_else(|| invalid("no contact pair".to_string()))?;
        Ok(AdaptiveModel::Contact(problem.clone()))
    }
}

/// The material of the problems without an exact solution.
fn material() -> serde_json::Value {
    json!({ "E": YOUNG, "nu": POISSON, "plane": "strain" })
}

/// The flat punch: the punch [-0.25, 0.25] x [0, 0.5] (3 x 3 quads, top moved down by
/// [`INDENTATION`]) on the foundation [-1, 1] x [-1, 0] (8 x 4 quads, bottom clamped), the
/// punch's bottom against the foundation's top, frictionless.
fn punch() -> Result<SceneProblem, Box<dyn std::error::Error>> {
    SceneProblem::new(
        "flat punch",
        json!({
            "title": "flat punch",
            "body": [
                {
                    "name": "punch",
                    "mesh": { "family": "quads", "rectangle": [[-0.25, 0.0], [0.25, 0.5]], "n": 3 },
                    "material": material(),
                    "dirichlet": [{ "part": "top", "x": 0.0, "y": -INDENTATION }],
                },
                {
                    "name": "foundation",
                    "mesh": { "family": "quads", "rectangle": [[-1.0, -1.0], [1.0, 0.0]], "n": 8 },
                    "material": material(),
                    "dirichlet": [{ "part": "bottom", "x": 0.0, "y": 0.0 }],
                },
            ],
            "contact": [{
                "body": "punch", "part": "bottom", "other_body": "foundation",
                "other_part": "top", "law": "frictionless",
            }],
        }),
        ".",
    )
}

/// The L-shaped body `[0, 1]^2` without `(1/2, 1] x (1/2, 1]` (the quads of 4 x 4 cut by the
/// polygon; parts "bottom" at y = 0 and "top" at y = 1), top moved down by [`INDENTATION`],
/// pressed on a block `[-0.5, 1.5] x [-1, 0]` (6 x 3 quads, bottom clamped), frictionless:
/// singular at the re-entrant corner and at the ends of the contact.
fn l_shape() -> Result<SceneProblem, Box<dyn std::error::Error>> {
    SceneProblem::new(
        "L-shape",
        json!({
            "title": "L-shape",
            "body": [
                {
                    "name": "L",
                    "mesh": {
                        "family": "quads",
                        "polygon": [[0.0, 0.0], [1.0, 0.0], [1.0, 0.5], [0.5, 0.5], [0.5, 1.0], [0.0, 1.0]],
                        "edge_names": ["bottom", "free", "free", "free", "top", "free"],
                        "n": 4,
                    },
                    "material": material(),
                    "dirichlet": [{ "part": "top", "x": 0.0, "y": -INDENTATION }],
                },
                {
                    "name": "block",
                    "mesh": { "family": "quads", "rectangle": [[-0.5, -1.0], [1.5, 0.0]], "n": 6 },
                    "material": material(),
                    "dirichlet": [{ "part": "bottom", "x": 0.0, "y": 0.0 }],
                },
            ],
            "contact": [{
                "body": "L", "part": "bottom", "other_body": "block", "other_part": "top",
                "law": "frictionless",
            }],
        }),
        ".",
    )
}

/// The Hertz half-disc of `docs/hertz.md` (radius 1, top moved down by 0.02) on the block
/// (bottom clamped), frictionless, from the meshes of `xtask/data/hertz` at `h_c = 0.08`.
/// The refinement cuts the disc's arc at chord midpoints: the geometry stays the initial
/// polygon, and the reference is that polygon's solution.
fn hertz() -> Result<SceneProblem, Box<dyn std::error::Error>> {
    SceneProblem::new(
        "Hertz",
        json!({
            "title": "Hertz",
            "body": [
                {
                    "name": "disc",
                    "mesh": { "file": "disc_hc0.08.msh" },
                    "material": material(),
                    "dirichlet": [{ "part": "top", "x": 0.0, "y": -0.02 }],
                },
                {
                    "name": "block",
                    "mesh": { "file": "block_hc0.08.msh" },
                    "material": material(),
                    "dirichlet": [{ "part": "bottom", "x": 0.0, "y": 0.0 }],
                },
            ],
            "contact": [{
                "body": "disc", "part": "arc", "other_body": "block", "other_part": "top",
                "law": "frictionless", "max_distance": 0.05,
            }],
        }),
        "xtask/data/hertz",
    )
}

fn m1_meshes() -> Result<Vec<Mesh>, Box<dyn std::error::Error>> {
    Ok(vec![
        structured_quads(&Rectangle::unit_square(), 4, 4)?,
        structured_quads(
            &Rectangle::new(Point::new(0.0, -1.0), Point::new(1.0, 0.0)),
            5,
            5,
        )?,
    ])
}

/// One problem's two series.
struct Study {
    title: &'static str,
    slug: &'static str,
    error_name: &'static str,
    /// The reference solve (unknowns, strain energy), without an exact solution.
    reference: Option<(usize, f64)>,
    adaptive: AdaptiveRun,
    uniform: AdaptiveRun,
    /// A short adaptive run whose last meshes are pictured (a few thousand unknowns).
    picture: AdaptiveRun,
    seconds: f64,
}

/// The adaptive meshes pictured have about this many unknowns.
const PICTURE_UNKNOWNS: usize = 3000;

/// A short adaptive run of `model` for the picture.
fn picture_run(
    name: &str,
    model: &dyn Fn(Vec<Mesh>) -> Result<AdaptiveModel, VerifyError>,
    meshes: Vec<Mesh>,
) -> Result<AdaptiveRun, VerifyError> {
    adapt(
        name,
        model,
        meshes,
        &LowestOrderVem::default(),
        &Reference::None,
        &AdaptiveSettings {
            theta: THETA,
            max_cycles: 60,
            max_unknowns: PICTURE_UNKNOWNS,
            uniform: false,
        },
        &mut CondensedSolver::new(CondensedSettings::default()),
    )
}

/// The report's folder of figures and data beside `out`.
fn folder_of(out: &Path) -> PathBuf {
    out.parent().unwrap_or(Path::new(".")).join("adaptivity")
}

/// The rows of the studies, in `adaptivity/adaptivity.json` beside the report.
const JSON: &str = "adaptivity.json";
/// The pictured meshes with their indicators (inline scene meshes), in
/// `adaptivity/meshes.json` beside the report.
const MESHES_JSON: &str = "meshes.json";

pub fn run(args: &AdaptivityArgs) -> Result<bool, Box<dyn std::error::Error>> {
    let start = Instant::now();
    let out = if args.quick && args.out == Path::new("docs/adaptivity.md") {
        PathBuf::from("target/adaptivity/adaptivity.md")
    } else {
        args.out.clone()
    };
    let folder = folder_of(&out);
    if args.report_only {
        let stored = read_stored(&folder)?;
        let ok = write_report(&out, &stored)?;
        println!(
            "rewrote {} from {}",
            out.display(),
            folder.join(JSON).display()
        );
        return Ok(ok);
    }
    std::fs::create_dir_all(&folder)?;
    let element = LowestOrderVem::default();
    let (cycles, uniform_cycles, reference_cycles) =
        if args.quick { (6, 3, 14) } else { (16, 5, 22) };
    let settings = |uniform: bool, cycles: usize| AdaptiveSettings {
        theta: THETA,
        max_cycles: cycles,
        max_unknowns: 400_000,
        uniform,
    };
    let mut studies = Vec::new();

    // M1 (frictionless) and M2 (Tresca): exact solutions, their data from vem-verify.
    for (name, title, slug) in [
        ("M1", "M1 (frictionless, smooth; exact solution)", "m1"),
        (
            "M2",
            "M2 (Tresca friction, stick and slip; exact solution)",
            "m2",
        ),
    ] {
        let t = Instant::now();
        let exact: Arc<dyn vem_verify::ExactSolution> = case_by_name(name, Lame::default())?.into();
        let build = case_model(Arc::clone(&exact), ProblemSettings::default());
        let reference = Reference::Exact(Arc::clone(&exact));
        let adaptive = adapt(
            name,
            &build,
            m1_meshes()?,
            &element,
            &reference,
            &settings(false, cycles.min(12)),
            &mut CondensedSolver::new(CondensedSettings::default()),
        )?;
        let uniform = adapt(
            name,
            &build,
            m1_meshes()?,
            &element,
            &reference,
            &settings(true, uniform_cycles),
            &mut CondensedSolver::new(CondensedSettings::default()),
        )?;
        studies.push(Study {
            title,
            slug,
            error_name: "E_en (exact)",
            reference: None,
            adaptive,
            uniform,
            picture: picture_run(name, &build, m1_meshes()?)?,
            seconds: t.elapsed().as_secs_f64(),
        });
    }

    studies.push(energy_study(
        "Flat punch (frictionless; corner singularities)",
        "punch",
        &punch()?,
        reference_cycles,
        uniform_cycles,
    )?);
    studies.push(energy_study(
        "L-shaped body on a block (frictionless; re-entrant corner, contact ends)",
        "l-shape",
        &l_shape()?,
        reference_cycles,
        uniform_cycles,
    )?);
    if !args.quick {
        studies.push(energy_study(
            "Hertz half-disc on a block (frictionless; polygonal arc of h_c = 0.08)",
            "hertz",
            &hertz()?,
            reference_cycles,
            uniform_cycles,
        )?);
    }

    let stored = Stored {
        quick: args.quick,
        seconds: start.elapsed().as_secs_f64(),
        theta: THETA,
        studies: studies.iter().map(StoredStudy::of).collect(),
    };
    let pictures: Vec<StoredPicture> = studies.iter().map(StoredPicture::of).collect();
    write_json(folder.join(JSON), &stored)?;
    write_text(
        folder.join(MESHES_JSON),
        &(serde_json::to_string(&pictures)? + "\n"),
    )?;
    // The report of what was stored, as `--report-only` makes it.
    let ok = write_report(&out, &read_stored(&folder)?)?;
    println!("wrote {}", out.display());
    Ok(ok)
}

/// A problem without an exact solution: one adaptive run far beyond the compared cycles,
/// whose last strain energy is the reference `W_ref`; the cycles with at most
/// [`REFERENCE_MARGIN`]^-1 of its unknowns are compared with `E_en = (2 |W_h - W_ref|)^(1/2)`,
/// and a uniform series up to as many unknowns.
fn energy_study(
    title: &'static str,
    slug: &'static str,
    problem: &SceneProblem,
    reference_cycles: usize,
    uniform_cycles: usize,
) -> Result<Study, Box<dyn std::error::Error>> {
    let t = Instant::now();
    let name = problem.name;
    let model = |meshes| problem.model(meshes);
    let element = LowestOrderVem::default();
    let settings = |uniform: bool, cycles: usize, max_unknowns: usize| AdaptiveSettings {
        theta: THETA,
        max_cycles: cycles,
        max_unknowns,
        uniform,
    };
    let mut adaptive = adapt(
        name,
        &model,
        problem.meshes()?,
        &element,
        &Reference::None,
        &settings(false, reference_cycles, 400_000),
        &mut CondensedSolver::new(CondensedSettings::default()),
    )?;
    let finest = adaptive.records.last().expect("one cycle at least").clone();
    println!(
        "{name}: reference {} unknowns, W_ref = {:.12e}",
        finest.unknowns, finest.strain_energy
    );
    let limit = finest.unknowns / REFERENCE_MARGIN;
    adaptive.records.retain(|r| r.unknowns <= limit);
    for r in &mut adaptive.records {
        let e = (2.0 * (r.strain_energy - finest.strain_energy).abs()).sqrt();
        r.energy_error = Some(e);
        r.effectivity = Some(r.estimate / e);
    }
    let uniform = adapt(
        name,
        &model,
        problem.meshes()?,
        &element,
        &Reference::Energy(finest.strain_energy),
        &settings(true, uniform_cycles, limit / 4),
        &mut CondensedSolver::new(CondensedSettings::default()),
    )?;
    Ok(Study {
        title,
        slug,
        error_name: "E_en (reference energy)",
        reference: Some((finest.unknowns, finest.strain_energy)),
        adaptive,
        uniform,
        picture: picture_run(name, &model, problem.meshes()?)?,
        seconds: t.elapsed().as_secs_f64(),
    })
}

/// The reference solve has at least this many times the unknowns of the compared ones.
const REFERENCE_MARGIN: usize = 8;

/// What a run stores in `adaptivity/adaptivity.json`: everything the report and its
/// convergence plots are made of.
#[derive(Debug, Serialize, Deserialize)]
struct Stored {
    quick: bool,
    /// The whole run, seconds.
    seconds: f64,
    /// Dorfler's bulk fraction.
    theta: f64,
    studies: Vec<StoredStudy>,
}

/// One problem's series as stored.
#[derive(Debug, Serialize, Deserialize)]
struct StoredStudy {
    title: String,
    slug: String,
    error_name: String,
    /// The reference solve (unknowns, strain energy), without an exact solution.
    reference: Option<(usize, f64)>,
    /// Both series, seconds.
    seconds: f64,
    adaptive: Vec<Row>,
    uniform: Vec<Row>,
}

impl StoredStudy {
    fn of(study: &Study) -> Self {
        Self {
            title: study.title.to_string(),
            slug: study.slug.to_string(),
            error_name: study.error_name.to_string(),
            reference: study.reference,
            seconds: study.seconds,
            adaptive: study.adaptive.records.iter().map(Row::of).collect(),
            uniform: study.uniform.records.iter().map(Row::of).collect(),
        }
    }
}

/// One cycle as stored: the figures of [`CycleRecord`] the report prints or fits.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct Row {
    cycle: usize,
    unknowns: usize,
    cells: usize,
    estimate: f64,
    energy_error: Option<f64>,
    effectivity: Option<f64>,
    grad_error: Option<f64>,
    /// The squared parts of the estimate summed over all cells.
    residual: f64,
    jump: f64,
    boundary: f64,
    stabilisation: f64,
    contact: f64,
    active_nodes: usize,
    min_star_ratio: f64,
    max_cell_vertices: usize,
}

impl Row {
    fn of(r: &CycleRecord) -> Self {
        Self {
            cycle: r.cycle,
            unknowns: r.unknowns,
            cells: r.cells,
            estimate: r.estimate,
            energy_error: r.energy_error,
            effectivity: r.effectivity,
            grad_error: r.grad_error,
            residual: r.parts.residual,
            jump: r.parts.jump,
            boundary: r.parts.boundary,
            stabilisation: r.parts.stabilisation,
            contact: r.parts.contact,
            active_nodes: r.active_nodes,
            min_star_ratio: r.min_star_ratio,
            max_cell_vertices: r.max_cell_vertices,
        }
    }
}

/// The pictured meshes of one problem as stored: each body's mesh (inline, as a scene gives
/// it) with `log10 eta_E` per cell.
#[derive(Debug, Serialize, Deserialize)]
struct StoredPicture {
    slug: String,
    title: String,
    bodies: Vec<PicturedBody>,
}

#[derive(Debug, Serialize, Deserialize)]
struct PicturedBody {
    name: String,
    mesh: MeshDescription,
    /// The names of the mesh's parts in its order (the inline form keeps them by name), which
    /// the picture draws and colours in this order.
    parts: Vec<String>,
    log_indicator: Vec<f64>,
}

impl PicturedBody {
    /// The pictured mesh: the inline mesh with its parts in their order.
    fn mesh(&self) -> Result<Mesh, Box<dyn std::error::Error>> {
        let (Some(vertices), Some(polygons)) = (&self.mesh.vertices, &self.mesh.polygons) else {
            return Err(format!("{}: not an inline mesh in the plane", self.name).into());
        };
        let vertices = vertices.iter().map(|p| Point::new(p[0], p[1])).collect();
        let parts = self
            .parts
            .iter()
            .map(|name| PartSpec {
                name: name.clone(),
                edges: self.mesh.part_edges.get(name).cloned().unwrap_or_default(),
            })
            .collect();
        Ok(Mesh::from_polygons(vertices, polygons, parts)?)
    }
}

impl StoredPicture {
    fn of(study: &Study) -> Self {
        let last = &study.picture.last;
        let bodies = last
            .bodies
            .iter()
            .zip(last.cell_indicators())
            .map(|(b, values)| PicturedBody {
                name: b.body.name().to_string(),
                mesh: BuiltMesh::Plane(b.body.mesh().clone()).to_inline(),
                parts: b
                    .body
                    .mesh()
                    .part_specs()
                    .into_iter()
                    .map(|p| p.name)
                    .collect(),
                log_indicator: values.iter().map(|e| e.max(1e-300).log10()).collect(),
            })
            .collect();
        Self {
            slug: study.slug.to_string(),
            title: study.title.to_string(),
            bodies,
        }
    }
}

/// The stored rows and pictures in `folder`.
fn read_stored(folder: &Path) -> Result<(Stored, Vec<StoredPicture>), Box<dyn std::error::Error>> {
    Ok((
        crate::common::read_json(folder.join(JSON))?,
        crate::common::read_json(folder.join(MESHES_JSON))?,
    ))
}

/// The report `out` and its figures (in [`folder_of`] `out`) from the stored run; `Ok(true)`
/// when every study passes its check.
fn write_report(
    out: &Path,
    (stored, pictures): &(Stored, Vec<StoredPicture>),
) -> Result<bool, Box<dyn std::error::Error>> {
    let folder = folder_of(out);
    std::fs::create_dir_all(&folder)?;
    let Report { doc, plots, ok } = report(stored)?;
    for (name, svg) in &plots {
        write_text(folder.join(name), svg)?;
    }
    for picture in pictures {
        write_picture(&folder, picture)?;
    }
    write_text(out, &doc)?;
    Ok(ok)
}

/// A stored run's report: the Markdown, the convergence plots (file name, SVG) and whether
/// every study passes its check.
struct Report {
    doc: String,
    plots: Vec<(String, String)>,
    ok: bool,
}

/// The report of a stored run.
fn report(stored: &Stored) -> Result<Report, Box<dyn std::error::Error>> {
    let mut sections = String::new();
    let mut plots = Vec::new();
    let mut ok = true;
    for study in &stored.studies {
        let (passed, plot) = write_study(&mut sections, study)?;
        ok &= passed;
        plots.push(plot);
    }
    let doc = crate::common::render(
        "xtask/templates/adaptivity.md",
        include_str!("../templates/adaptivity.md"),
        &[
            (
                "options",
                if stored.quick { " --quick" } else { "" }.to_string(),
            ),
            ("seconds", format!("{:.0}", stored.seconds)),
            ("theta", stored.theta.to_string()),
            ("studies", sections),
        ],
    )?;
    Ok(Report { doc, plots, ok })
}

fn errors(records: &[Row]) -> Vec<(f64, f64)> {
    records
        .iter()
        .filter_map(|r| r.energy_error.map(|e| (r.unknowns as f64, e)))
        .collect()
}

/// The least-squares slope of `log error` against `log N` over `rows`.
fn slope(rows: &[Row], error: impl Fn(&Row) -> Option<f64>) -> Option<f64> {
    let (n, e): (Vec<f64>, Vec<f64>) = rows
        .iter()
        .filter_map(|r| error(r).map(|e| (r.unknowns as f64, e)))
        .unzip();
    fitted_rate(&n, &e)
}

/// The section of `study` appended to `doc`; whether it passes its check, and its convergence
/// plot (file name, SVG).
fn write_study(
    doc: &mut String,
    study: &StoredStudy,
) -> Result<(bool, (String, String)), Box<dyn std::error::Error>> {
    writeln!(doc, "## {}\n", study.title)?;
    writeln!(doc, "Both series in {:.1} s.\n", study.seconds)?;
    if let Some((unknowns, energy)) = study.reference {
        writeln!(
            doc,
            "Reference: the adaptive series continued to {unknowns} unknowns, \
             W_ref = {energy:.12e}; the cycles shown have at most 1/{REFERENCE_MARGIN} of its \
             unknowns.\n"
        )?;
    }
    let adaptive = &study.adaptive;
    let uniform = &study.uniform;
    // The first cycles are pre-asymptotic.
    let fitted_adaptive: &[Row] = if adaptive.len() > 2 {
        &adaptive[2..]
    } else {
        adaptive
    };
    let slope_a = slope(fitted_adaptive, |r| r.energy_error);
    let slope_u = slope(uniform, |r| r.energy_error);
    let slope_eta_a = slope(fitted_adaptive, |r| Some(r.estimate));
    let slope_eta_u = slope(uniform, |r| Some(r.estimate));
    let fmt = |s: Option<f64>| s.map_or("-".to_string(), |s| format!("{s:.3}"));
    writeln!(
        doc,
        "| series | slope of {} in N | slope of eta in N |\n|---|---|---|\n\
         | adaptive | {} | {} |\n| uniform | {} | {} |\n",
        study.error_name,
        fmt(slope_a),
        fmt(slope_eta_a),
        fmt(slope_u),
        fmt(slope_eta_u)
    )?;
    for (name, records) in [("adaptive", adaptive), ("uniform", uniform)] {
        writeln!(doc, "### {name}\n")?;
        writeln!(
            doc,
            "| cycle | N | cells | eta | E_en | eta/E_en | E_grad | residual | jump | boundary | \
             stab. | contact | active | min star ratio | max vertices |\n\
             |---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
        )?;
        for r in records.iter() {
            let o = |v: Option<f64>, p: usize| v.map_or("-".to_string(), |v| format!("{v:.p$e}"));
            writeln!(
                doc,
                "| {} | {} | {} | {:.3e} | {} | {} | {} | {:.2e} | {:.2e} | {:.2e} | {:.2e} | \
                 {:.2e} | {} | {:.3} | {} |",
                r.cycle,
                r.unknowns,
                r.cells,
                r.estimate,
                o(r.energy_error, 3),
                r.effectivity.map_or("-".to_string(), |e| format!("{e:.2}")),
                o(r.grad_error, 3),
                r.residual.sqrt(),
                r.jump.sqrt(),
                r.boundary.sqrt(),
                r.stabilisation.sqrt(),
                r.contact.sqrt(),
                r.active_nodes,
                r.min_star_ratio,
                r.max_cell_vertices,
            )?;
        }
        writeln!(doc)?;
    }
    // Convergence plot.
    let plot = LogLogPlot {
        caption: &study.title,
        x_desc: "unknowns N",
        y_desc: "error / estimate",
        x_format: |x| format!("{x:.0e}"),
        y_format: |y| format!("{y:.0e}"),
    };
    let series = vec![
        (format!("{} adaptive", study.error_name), errors(adaptive)),
        (format!("{} uniform", study.error_name), errors(uniform)),
        (
            "eta adaptive".to_string(),
            adaptive
                .iter()
                .map(|r| (r.unknowns as f64, r.estimate))
                .collect(),
        ),
        (
            "eta uniform".to_string(),
            uniform
                .iter()
                .map(|r| (r.unknowns as f64, r.estimate))
                .collect(),
        ),
    ];
    let svg = loglog_svg(&plot, &series, None)?;
    let plot_name = format!("{}-convergence.svg", study.slug);
    writeln!(doc, "![convergence](adaptivity/{plot_name})\n")?;
    writeln!(
        doc,
        "![adapted meshes](adaptivity/{}-mesh.svg)\n",
        study.slug
    )?;
    let ok = match (slope_a, slope_u) {
        (Some(a), Some(u)) => a < -0.4 && a <= u + 0.05,
        _ => false,
    };
    writeln!(
        doc,
        "Check (adaptive slope below -0.4 and not worse than uniform): {}\n",
        if ok { "pass" } else { "FAIL" }
    )?;
    Ok((ok, (plot_name, svg)))
}

/// `folder/<slug>-mesh.svg`: the adapted meshes of a study with their indicators.
fn write_picture(folder: &Path, picture: &StoredPicture) -> Result<(), Box<dyn std::error::Error>> {
    let meshes: Vec<Mesh> = picture
        .bodies
        .iter()
        .map(PicturedBody::mesh)
        .collect::<Result<_, _>>()?;
    let cells: usize = meshes.iter().map(Mesh::n_polygons).sum();
    let title = format!("{}: adapted meshes ({cells} cells)", picture.title);
    let layers: Vec<SvgLayer> = picture
        .bodies
        .iter()
        .zip(&meshes)
        .map(|(b, mesh)| {
            SvgLayer::new(mesh)
                .with_label(&b.name)
                .with_cell_values(&b.log_indicator)
        })
        .collect();
    let options = SvgOptions {
        title: Some(title),
        value_label: "log10 eta_E".to_string(),
        width: 900.0,
        ..SvgOptions::default()
    };
    write_svg_layers(
        folder.join(format!("{}-mesh.svg", picture.slug)),
        &layers,
        &options,
    )?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn docs() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs")
    }

    fn read(path: &Path) -> String {
        std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
    }

    /// What `--report-only` makes of the committed rows and meshes is docs/adaptivity.md and
    /// its figures, byte for byte.
    #[test]
    fn the_report_of_the_committed_rows_is_docs_adaptivity_md() {
        let folder = docs().join("adaptivity");
        let (stored, pictures) = read_stored(&folder).expect("the committed rows");
        assert!(!stored.quick, "the committed rows are those of a full run");
        let Report { doc, plots, .. } = report(&stored).expect("the report renders");
        assert!(
            doc == read(&docs().join("adaptivity.md")),
            "docs/adaptivity.md is not the rendered report"
        );
        for (name, svg) in &plots {
            assert!(
                svg == &read(&folder.join(name)),
                "{name} is not the rendered plot"
            );
        }
        let scratch = std::env::temp_dir().join(format!("xtask-adaptivity-{}", std::process::id()));
        std::fs::create_dir_all(&scratch).expect("a scratch folder");
        for picture in &pictures {
            write_picture(&scratch, picture).expect("the picture renders");
            let name = format!("{}-mesh.svg", picture.slug);
            assert!(
                read(&scratch.join(&name)) == read(&folder.join(&name)),
                "{name} is not the rendered picture"
            );
        }
        std::fs::remove_dir_all(&scratch).ok();
    }
}
