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
use vem_contact::{law::Frictionless, CondensedSettings, CondensedSolver, ContactProblem};
use vem_elastic::{Component, Dirichlet, ElasticBody, Material, Plane};
use vem_mesh::generators::{structured_quads, Rectangle};
use vem_mesh::interface::InterfaceOptions;
use vem_mesh::io::{read_gmsh, write_svg_layers, SvgLayer, SvgOptions};
use vem_mesh::{Mesh, Point, Vector};
use vem_space::{ElementSpace, LowestOrderVem};
use vem_verify::adaptive::{
    case_model, run as adapt, slope_in_unknowns, AdaptiveRun, AdaptiveSettings, CycleRecord, Model,
    Reference,
};
use vem_verify::exact::{case_by_name, Lame};
use vem_verify::problem::ProblemSettings;
use vem_verify::report::write_text;
use vem_verify::VerifyError;

use vem_verify::plot::{loglog_svg, LogLogPlot};

/// Options of `cargo xtask adaptivity`.
#[derive(Debug, Args)]
pub struct AdaptivityArgs {
    /// The report; its figures go to the folder `adaptivity/` beside it.
    #[arg(long, default_value = "docs/adaptivity.md")]
    out: PathBuf,
    /// A quick run for CI (fewer cycles, a smaller reference), written under target/.
    #[arg(long)]
    quick: bool,
}

/// Young's modulus and Poisson's ratio of both bodies of the punch (plane strain).
const YOUNG: f64 = 100.0;
const POISSON: f64 = 0.3;
/// The punch's top moves down by this.
const INDENTATION: f64 = 0.01;
/// Dorfler's bulk fraction.
const THETA: f64 = 0.5;

/// The flat punch on given meshes: `meshes[0]` the punch [-0.25, 0.25] x [0, 0.5] (top moved
/// down by [`INDENTATION`]), `meshes[1]` the foundation [-1, 1] x [-1, 0] (bottom clamped),
/// the punch's bottom against the foundation's top, frictionless.
fn punch_model(meshes: Vec<Mesh>) -> Result<Model, VerifyError> {
    let element: Arc<dyn ElementSpace> = Arc::new(LowestOrderVem::default());
    let elastic = |source| VerifyError::Elastic {
        case: "flat punch".to_string(),
        source: Box::new(source),
    };
    let material = Material::from_young_poisson(YOUNG, POISSON, Plane::Strain).map_err(elastic)?;
    let mut meshes = meshes.into_iter();
    let (punch, foundation) = (meshes.next(), meshes.next());
    let (Some(punch), Some(foundation)) = (punch, foundation) else {
        return Err(VerifyError::InvalidSetting {
            reason: "the flat punch has two bodies".to_string(),
        });
    };
    let punch = ElasticBody::builder("punch", punch, material, Arc::clone(&element))
        .dirichlet(Dirichlet::prescribed("top", Component::All, |_| {
            Vector::new(0.0, -INDENTATION)
        }))
        .build()
        .map_err(elastic)?;
    let foundation = ElasticBody::builder("foundation", foundation, material, element)
        .clamp("bottom")
        .build()
        .map_err(elastic)?;
    Ok(Model::Contact(ContactProblem::two_bodies(
        punch,
        "bottom",
        foundation,
        "top",
        Frictionless,
    )))
}

fn punch_meshes() -> Result<Vec<Mesh>, Box<dyn std::error::Error>> {
    let punch = Rectangle::new(Point::new(-0.25, 0.0), Point::new(0.25, 0.5));
    let foundation = Rectangle::new(Point::new(-1.0, -1.0), Point::new(1.0, 0.0));
    Ok(vec![
        structured_quads(&punch, 3, 3)?,
        structured_quads(&foundation, 8, 4)?,
    ])
}

/// The L-shaped body `[0, 1]^2` without `(1/2, 1] x (1/2, 1]` on `n x n` squares (`n` even),
/// with the parts "bottom" (y = 0) and "top" (y = 1).
fn l_shape(n: usize) -> Result<Mesh, Box<dyn std::error::Error>> {
    let square = structured_quads(&Rectangle::unit_square(), n, n)?;
    let kept: Vec<usize> = (0..square.n_polygons())
        .filter(|&p| {
            let c = square.centroid(p);
            !(c.x > 0.5 && c.y > 0.5)
        })
        .collect();
    let mut renumber = vec![usize::MAX; square.n_vertices()];
    let mut vertices = Vec::new();
    let mut polygons = Vec::with_capacity(kept.len());
    for &p in &kept {
        let polygon: Vec<usize> = square
            .polygon(p)
            .iter()
            .map(|&v| {
                if renumber[v] == usize::MAX {
                    renumber[v] = vertices.len();
                    vertices.push(square.vertex(v));
                }
                renumber[v]
            })
            .collect();
        polygons.push(polygon);
    }
    Ok(Mesh::from_polygons(vertices, &polygons, vec![])?
        .with_part_where("bottom", |a, b| a.y == 0.0 && b.y == 0.0)?
        .with_part_where("top", |a, b| a.y == 1.0 && b.y == 1.0)?)
}

/// The L-shaped body (top moved down by [`INDENTATION`]) pressed on a block
/// `[-0.5, 1.5] x [-1, 0]` (bottom clamped), frictionless: singular at the re-entrant corner
/// and at the ends of the contact.
fn l_model(meshes: Vec<Mesh>) -> Result<Model, VerifyError> {
    let element: Arc<dyn ElementSpace> = Arc::new(LowestOrderVem::default());
    let elastic = |source| VerifyError::Elastic {
        case: "L-shape".to_string(),
        source: Box::new(source),
    };
    let material = Material::from_young_poisson(YOUNG, POISSON, Plane::Strain).map_err(elastic)?;
    let mut meshes = meshes.into_iter();
    let (Some(l), Some(block)) = (meshes.next(), meshes.next()) else {
        return Err(VerifyError::InvalidSetting {
            reason: "the L-shape problem has two bodies".to_string(),
        });
    };
    let l = ElasticBody::builder("L", l, material, Arc::clone(&element))
        .dirichlet(Dirichlet::prescribed("top", Component::All, |_| {
            Vector::new(0.0, -INDENTATION)
        }))
        .build()
        .map_err(elastic)?;
    let block = ElasticBody::builder("block", block, material, element)
        .clamp("bottom")
        .build()
        .map_err(elastic)?;
    Ok(Model::Contact(ContactProblem::two_bodies(
        l,
        "bottom",
        block,
        "top",
        Frictionless,
    )))
}

fn l_meshes() -> Result<Vec<Mesh>, Box<dyn std::error::Error>> {
    let block = Rectangle::new(Point::new(-0.5, -1.0), Point::new(1.5, 0.0));
    Ok(vec![l_shape(4)?, structured_quads(&block, 6, 3)?])
}

/// The Hertz half-disc of `docs/hertz.md` (radius 1, top moved down by 0.02) on the block
/// (bottom clamped), frictionless, from the meshes of `xtask/data/hertz` at `h_c = 0.08`.
/// The refinement cuts the disc's arc at chord midpoints: the geometry stays the initial
/// polygon, and the reference is that polygon's solution.
fn hertz_model(meshes: Vec<Mesh>) -> Result<Model, VerifyError> {
    let element: Arc<dyn ElementSpace> = Arc::new(LowestOrderVem::default());
    let elastic = |source| VerifyError::Elastic {
        case: "Hertz".to_string(),
        source: Box::new(source),
    };
    let material = Material::from_young_poisson(YOUNG, POISSON, Plane::Strain).map_err(elastic)?;
    let mut meshes = meshes.into_iter();
    let (Some(disc), Some(block)) = (meshes.next(), meshes.next()) else {
        return Err(VerifyError::InvalidSetting {
            reason: "the Hertz problem has two bodies".to_string(),
        });
    };
    let disc = ElasticBody::builder("disc", disc, material, Arc::clone(&element))
        .dirichlet(Dirichlet::prescribed("top", Component::All, |_| {
            Vector::new(0.0, -0.02)
        }))
        .build()
        .map_err(elastic)?;
    let block = ElasticBody::builder("block", block, material, element)
        .clamp("bottom")
        .build()
        .map_err(elastic)?;
    let options = InterfaceOptions::builder()
        .max_distance(0.05)
        .build()
        .map_err(|e| VerifyError::InvalidSetting {
            reason: e.to_string(),
        })?;
    Ok(Model::Contact(
        ContactProblem::two_bodies(disc, "arc", block, "top", Frictionless)
            .with_interface_options(options),
    ))
}

fn hertz_meshes() -> Result<Vec<Mesh>, Box<dyn std::error::Error>> {
    let folder = Path::new("xtask/data/hertz");
    Ok(vec![
        read_gmsh(folder.join("disc_hc0.08.msh"))?,
        read_gmsh(folder.join("block_hc0.08.msh"))?,
    ])
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
    model: &dyn Fn(Vec<Mesh>) -> Result<Model, VerifyError>,
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

pub fn run(args: &AdaptivityArgs) -> Result<bool, Box<dyn std::error::Error>> {
    let start = Instant::now();
    let out = if args.quick && args.out == Path::new("docs/adaptivity.md") {
        PathBuf::from("target/adaptivity/adaptivity.md")
    } else {
        args.out.clone()
    };
    let folder = out.parent().unwrap_or(Path::new(".")).join("adaptivity");
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

    // M1 (frictionless) and M2 (Tresca): exact solutions.
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
        "flat punch",
        "Flat punch (frictionless; corner singularities)",
        "punch",
        &punch_model,
        punch_meshes,
        reference_cycles,
        uniform_cycles,
    )?);
    studies.push(energy_study(
        "L-shape",
        "L-shaped body on a block (frictionless; re-entrant corner, contact ends)",
        "l-shape",
        &l_model,
        l_meshes,
        reference_cycles,
        uniform_cycles,
    )?);
    if !args.quick {
        studies.push(energy_study(
            "Hertz",
            "Hertz half-disc on a block (frictionless; polygonal arc of h_c = 0.08)",
            "hertz",
            &hertz_model,
            hertz_meshes,
            reference_cycles,
            uniform_cycles,
        )?);
    }

    let mut sections = String::new();
    let mut ok = true;
    for study in &studies {
        ok &= write_study(&mut sections, &folder, study)?;
    }
    let doc = crate::common::render(
        "xtask/templates/adaptivity.md",
        include_str!("../templates/adaptivity.md"),
        &[
            (
                "options",
                if args.quick { " --quick" } else { "" }.to_string(),
            ),
            ("seconds", format!("{:.0}", start.elapsed().as_secs_f64())),
            ("theta", THETA.to_string()),
            ("studies", sections),
        ],
    )?;
    write_text(&out, &doc)?;
    println!("wrote {}", out.display());
    Ok(ok)
}

/// A problem without an exact solution: one adaptive run far beyond the compared cycles,
/// whose last strain energy is the reference `W_ref`; the cycles with at most
/// [`REFERENCE_MARGIN`]^-1 of its unknowns are compared with `E_en = (2 |W_h - W_ref|)^(1/2)`,
/// and a uniform series up to as many unknowns.
fn energy_study(
    name: &'static str,
    title: &'static str,
    slug: &'static str,
    model: &dyn Fn(Vec<Mesh>) -> Result<Model, VerifyError>,
    meshes: fn() -> Result<Vec<Mesh>, Box<dyn std::error::Error>>,
    reference_cycles: usize,
    uniform_cycles: usize,
) -> Result<Study, Box<dyn std::error::Error>> {
    let t = Instant::now();
    let element = LowestOrderVem::default();
    let settings = |uniform: bool, cycles: usize, max_unknowns: usize| AdaptiveSettings {
        theta: THETA,
        max_cycles: cycles,
        max_unknowns,
        uniform,
    };
    let mut adaptive = adapt(
        name,
        model,
        meshes()?,
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
        model,
        meshes()?,
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
        picture: picture_run(name, model, meshes()?)?,
        seconds: t.elapsed().as_secs_f64(),
    })
}

/// The reference solve has at least this many times the unknowns of the compared ones.
const REFERENCE_MARGIN: usize = 8;

fn errors(records: &[CycleRecord]) -> Vec<(f64, f64)> {
    records
        .iter()
        .filter_map(|r| r.energy_error.map(|e| (r.unknowns as f64, e)))
        .collect()
}

fn write_study(
    doc: &mut String,
    folder: &Path,
    study: &Study,
) -> Result<bool, Box<dyn std::error::Error>> {
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
    let adaptive = &study.adaptive.records;
    let uniform = &study.uniform.records;
    // The first cycles are pre-asymptotic.
    let fitted_adaptive: &[CycleRecord] = if adaptive.len() > 2 {
        &adaptive[2..]
    } else {
        adaptive
    };
    let slope_a = slope_in_unknowns(fitted_adaptive, |r| r.energy_error);
    let slope_u = slope_in_unknowns(uniform, |r| r.energy_error);
    let slope_eta_a = slope_in_unknowns(fitted_adaptive, |r| Some(r.estimate));
    let slope_eta_u = slope_in_unknowns(uniform, |r| Some(r.estimate));
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
                r.parts.residual.sqrt(),
                r.parts.jump.sqrt(),
                r.parts.boundary.sqrt(),
                r.parts.stabilisation.sqrt(),
                r.parts.contact.sqrt(),
                r.active_nodes,
                r.min_star_ratio,
                r.max_cell_vertices,
            )?;
        }
        writeln!(doc)?;
    }
    // Convergence plot.
    let plot = LogLogPlot {
        caption: study.title,
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
    write_text(folder.join(&plot_name), &svg)?;
    writeln!(doc, "![convergence](adaptivity/{plot_name})\n")?;
    // The adapted meshes with their indicators.
    let last = &study.picture.last;
    let indicators = last.cell_indicators();
    let logs: Vec<Vec<f64>> = indicators
        .iter()
        .map(|v| v.iter().map(|e| e.max(1e-300).log10()).collect())
        .collect();
    let layers: Vec<SvgLayer> = last
        .bodies
        .iter()
        .zip(&logs)
        .map(|(b, values)| {
            SvgLayer::new(b.body.mesh())
                .with_label(b.body.name())
                .with_cell_values(values)
        })
        .collect();
    let options = SvgOptions {
        title: Some(format!(
            "{}: adapted meshes ({} cells)",
            study.title,
            last.bodies
                .iter()
                .map(|b| b.body.mesh().n_polygons())
                .sum::<usize>()
        )),
        value_label: "log10 eta_E".to_string(),
        width: 900.0,
        ..SvgOptions::default()
    };
    let mesh_name = format!("{}-mesh.svg", study.slug);
    write_svg_layers(folder.join(&mesh_name), &layers, &options)?;
    writeln!(doc, "![adapted meshes](adaptivity/{mesh_name})\n")?;
    let ok = match (slope_a, slope_u) {
        (Some(a), Some(u)) => a < -0.4 && a <= u + 0.05,
        _ => false,
    };
    writeln!(
        doc,
        "Check (adaptive slope below -0.4 and not worse than uniform): {}\n",
        if ok { "pass" } else { "FAIL" }
    )?;
    Ok(ok)
}
