//! `cargo xtask hertz`: the Hertz half-disc on a block (non-matching Gmsh meshes) at three
//! contact mesh sizes with each contact normal choice, against Hertz's plane-strain solution;
//! Coulomb friction at full slip (Q/P against F) and under a partial tangential shift against
//! Cattaneo-Mindlin's stick half-width; friction under force control and along load histories
//! (the `fretting` section: loading, unloading, reloading, path dependence); Cattaneo-Mindlin
//! in space (the `mindlin_3d` section: the stick disc of two blocks with a spherical gap). See
//! `docs/hertz.md`.
//!
//! Every problem is a `vem_scene::Scene` built by `vem_scene::Model::build` (the disc and the
//! block by their Gmsh files, [`disc_scene`]; the flat blocks by `vem_verify::fretting`; the
//! blocks in space given inline), solved with the model's contact problem and solver. Each
//! section writes its rows and the curves of its plots to JSON and renders its Markdown and
//! plots from that JSON, so `--report-only` rewrites them from the JSON without solving.

mod fretting;
mod mindlin_3d;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::common::{read_json, store_json};
use clap::Args;
use serde::{Deserialize, Deserializer, Serialize};
use vem_contact::{
    ContactNormal, ContactProblem, ContactResult, ContactSolver, InterfaceNode, NodeStatus,
};
use vem_scene::{BuildOptions, Model, Scene};
use vem_space::{Choice, Options};
use vem_verify::exact::HertzContact;
use vem_verify::fretting::{mesh_file, zone_half_width};
use vem_verify::plot::{
    chart_svg, Axis, Chart, Color, Glyph, Layer, Palette, Palette99, Pen, BLACK, CAPTION_SIZE,
};
use vem_verify::report::write_text;

type Failure = Box<dyn std::error::Error>;

/// Options of `cargo xtask hertz`.
#[derive(Debug, Args)]
pub struct HertzArgs {
    /// Where results.md, results.json and the SVG plots are written.
    #[arg(long, default_value = "target/hertz")]
    out: PathBuf,
    /// The folder of the meshes `disc_hc<h>.msh` and `block_hc<h>.msh`.
    #[arg(long, default_value = "xtask/data/hertz")]
    meshes: PathBuf,
    /// Contact mesh sizes h_c (the meshes must exist), comma separated.
    #[arg(long, value_delimiter = ',', default_value = "0.08,0.04,0.02,0.01")]
    sizes: Vec<String>,
    /// Only the friction section (force control, load histories): `fretting.md`.
    #[arg(long)]
    friction_only: bool,
    /// Only the section in space (Cattaneo-Mindlin in 3D): `mindlin-3d.md`.
    #[arg(long)]
    space_only: bool,
    /// The section in space at the coarser node spacing a/4 instead of a/6.
    #[arg(long)]
    quick: bool,
    /// Rewrite the Markdown and the plots of the sections asked for (all three, or the one of
    /// `--friction-only`, `--space-only`) from their JSON in `--out` (`results.json`,
    /// `fretting.json`, `mindlin-3d.json`), without solving.
    #[arg(long)]
    report_only: bool,
}

/// Young's modulus and Poisson's ratio of both bodies (plane strain).
const YOUNG: f64 = 100.0;
const POISSON: f64 = 0.3;
/// The indenter's radius.
const RADIUS: f64 = 1.0;
/// The indenter's top moves down by this.
const INDENTATION: f64 = 0.02;
/// Coulomb coefficient of the friction cases.
const COEFFICIENT: f64 = 0.3;
/// Horizontal shift of the indenter's top: full slip, and partial slip (Cattaneo-Mindlin).
const FULL_SLIP_SHIFT: f64 = 0.05;
const PARTIAL_SHIFT: f64 = 0.004;
/// The profile is compared with Hertz's inside this fraction of a.
const PROFILE_FRACTION: f64 = 0.8;

/// One frictionless run.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct Frictionless {
    h_c: String,
    normal: String,
    load: f64,
    hertz_half_width: f64,
    hertz_peak: f64,
    /// sum lambda_N / P - 1.
    normal_sum_error: f64,
    /// Horizontal force / P.
    horizontal_ratio: f64,
    half_width_error: f64,
    peak_error_raw: f64,
    peak_error_consistent: f64,
    /// max |p / p_Hertz - 1| inside 0.8 a.
    profile_raw: f64,
    profile_consistent: f64,
    /// The smallest consistent pressure over p0 (>= 0: it respects the sign).
    min_consistent: f64,
    /// (x / a, p / p0) raw and consistent at every interface node, for the plots.
    curve: Vec<(f64, f64, f64)>,
}

/// One Coulomb run (full slip and partial slip).
#[derive(Debug, Clone, Serialize, Deserialize)]
struct Friction {
    h_c: String,
    normal: String,
    /// Q / P at full slip.
    full_slip_ratio: f64,
    /// Stick nodes at full slip.
    full_slip_stick_nodes: usize,
    /// Q / (F P) of the partial shift.
    partial_ratio: f64,
    /// Computed stick half-width c, Cattaneo-Mindlin's a sqrt(1 - Q/(F P)) with Hertz's a
    /// and with the computed contact half-width, the node spacing at the stick zone's ends.
    stick_half_width: f64,
    stick_half_width_hertz: f64,
    stick_half_width_computed_a: f64,
    spacing: f64,
    /// P of the partial shift: Hertz's solution for it is the one of the traction plot.
    partial_load: f64,
    /// (x / a, |q| / (F p0)) raw and consistent of the partial shift at every interface node.
    curve: Vec<(f64, f64, f64)>,
}

impl Friction {
    /// Hertz's solution for the partial shift's load.
    fn hertz(&self) -> Result<HertzContact, Failure> {
        hertz_for(self.partial_load)
    }
}

/// `results.json`: the rows and curves of the section in the plane.
#[derive(Debug, Serialize, Deserialize)]
struct Results {
    /// Wall-clock seconds of the section.
    seconds: f64,
    frictionless: Vec<Frictionless>,
    coulomb: Vec<Friction>,
}

/// A number that JSON holds as `null` when it is not finite (`serde_json` writes NaN and the
/// infinities so): read back as `missing`.
fn number_or<'de, D: Deserializer<'de>>(d: D, missing: f64) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(missing))
}

/// [`number_or`] NaN.
fn number_or_nan<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    number_or(d, f64::NAN)
}

/// [`number_or`] infinity.
fn number_or_infinity<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    number_or(d, f64::INFINITY)
}

/// Writes the files `(name, text)` into `out`.
fn write_all(out: &Path, files: &[(String, String)]) -> Result<(), Failure> {
    for (name, text) in files {
        write_text(out.join(name), text)?;
    }
    Ok(())
}

/// Runs the study and writes `results.md`, `results.json`, the friction section, the section in
/// space and the plots (or, with `--report-only`, rewrites them from the JSON).
pub fn run(args: &HertzArgs) -> Result<bool, Failure> {
    std::fs::create_dir_all(&args.out)?;
    if args.report_only {
        return report_only(args);
    }
    if args.friction_only {
        let section: fretting::Section =
            store_json(args.out.join("fretting.json"), &fretting::run(args)?)?;
        write_all(&args.out, &fretting::report(&section)?)?;
        println!(
            "wrote {0}/fretting.md, fretting.json and its SVG plots",
            args.out.display()
        );
        return Ok(true);
    }
    if args.space_only {
        return space(args);
    }
    let start = Instant::now();
    let mut frictionless = Vec::new();
    let mut coulomb = Vec::new();
    for h in &args.sizes {
        for normal in ContactNormal::ALL {
            let f = frictionless_run(&args.meshes, h, normal)?;
            eprintln!(
                "h_c = {h} {:>8}: peak {:+.2}% (consistent {:+.2}%), profile {:.2}% ({:.2}%), \
                 min consistent {:+.2}%, a {:+.2}%",
                normal.name(),
                100.0 * f.peak_error_raw,
                100.0 * f.peak_error_consistent,
                100.0 * f.profile_raw,
                100.0 * f.profile_consistent,
                100.0 * f.min_consistent,
                100.0 * f.half_width_error
            );
            frictionless.push(f);
            let c = friction_run(&args.meshes, h, normal)?;
            eprintln!(
                "h_c = {h} {:>8}: full slip Q/P = {:.6}, Q/(FP) = {:.3}, c = {:.4} (CM {:.4}, spacing {:.4})",
                normal.name(),
                c.full_slip_ratio,
                c.partial_ratio,
                c.stick_half_width,
                c.stick_half_width_computed_a,
                c.spacing
            );
            coulomb.push(c);
        }
    }
    let results = Results {
        seconds: start.elapsed().as_secs_f64(),
        frictionless,
        coulomb,
    };
    let results: Results = store_json(args.out.join("results.json"), &results)?;
    write_all(&args.out, &report(&results, &args.out)?)?;
    let section: fretting::Section =
        store_json(args.out.join("fretting.json"), &fretting::run(args)?)?;
    write_all(&args.out, &fretting::report(&section)?)?;
    println!(
        "wrote {0}/results.md, results.json, fretting.md, fretting.json and the SVG plots",
        args.out.display()
    );
    space(args)
}

/// `--report-only`: the sections asked for rewritten from their JSON in `args.out`; false when
/// the section in space stored there falls short.
fn report_only(args: &HertzArgs) -> Result<bool, Failure> {
    let all = !args.friction_only && !args.space_only;
    let mut passed = true;
    let mut files = Vec::new();
    if all {
        let results: Results = read_json(args.out.join("results.json"))?;
        files.extend(report(&results, &args.out)?);
    }
    if all || args.friction_only {
        let section: fretting::Section = read_json(args.out.join("fretting.json"))?;
        files.extend(fretting::report(&section)?);
    }
    if all || args.space_only {
        let section: mindlin_3d::Section = read_json(args.out.join("mindlin-3d.json"))?;
        passed = section.study.shortfalls().is_empty();
        files.extend(mindlin_3d::report(&section)?);
    }
    write_all(&args.out, &files)?;
    let names: Vec<&str> = files.iter().map(|(name, _)| name.as_str()).collect();
    eprintln!(
        "rewrote {} in {} from its JSON",
        names.join(", "),
        args.out.display()
    );
    Ok(passed)
}

/// The section in space: Cattaneo-Mindlin in 3D at the node spacing a/6 (`--quick`: a/4),
/// written to `mindlin-3d.md` and `mindlin-3d.json`; false when it falls short.
fn space(args: &HertzArgs) -> Result<bool, Failure> {
    let start = Instant::now();
    let a = mindlin_3d::hertz()?.contact_radius();
    let study = mindlin_3d::study(a / if args.quick { 4.0 } else { 6.0 })?;
    print!("{}", study.markdown());
    let section = mindlin_3d::Section {
        options: if args.quick { " --quick" } else { "" }.to_string(),
        seconds: start.elapsed().as_secs_f64(),
        study,
    };
    let section: mindlin_3d::Section = store_json(args.out.join("mindlin-3d.json"), &section)?;
    write_all(&args.out, &mindlin_3d::report(&section)?)?;
    println!(
        "wrote {}/mindlin-3d.md and mindlin-3d.json",
        args.out.display()
    );
    Ok(section.study.shortfalls().is_empty())
}

/// How the disc's top is driven.
#[derive(Debug, Clone, Copy)]
enum Top {
    /// Moved by `(shift, -INDENTATION)` (displacement control).
    Moved(f64),
    /// A rigid plate pushed with `push` along -y and sheared with `shear` along +x (force
    /// control): two conditions, the push then the shear.
    Plate { push: f64, shear: f64 },
}

/// The scene of the half-disc (the mesh file `disc`, its contact part "arc") on the block (the
/// mesh file `block`, clamped at its "bottom", its contact part "top"), both of E = YOUNG,
/// nu = POISSON in plane strain, the disc's "top" driven by `top`, the contact law `law` by
/// registry name, the contact normal `normal`, the two sides paired within 0.05.
fn disc_scene(
    disc: &Path,
    block: &Path,
    top: Top,
    law: Choice,
    normal: ContactNormal,
) -> Result<Scene, Failure> {
    let material = serde_json::json!({ "E": YOUNG, "nu": POISSON, "plane": "strain" });
    let (dirichlet, rigid_plate) = match top {
        Top::Moved(shift) => (
            serde_json::json!([{ "part": "top", "x": shift, "y": -INDENTATION }]),
            serde_json::json!([]),
        ),
        Top::Plate { push, shear } => (
            serde_json::json!([]),
            serde_json::json!([
                { "part": "top", "resultant_y": -push },
                { "part": "top", "resultant_x": shear },
            ]),
        ),
    };
    let mut scene = Scene::from_value(serde_json::json!({
        "title": "The Hertz half-disc on a block",
        "body": [
            { "name": "disc", "mesh": {}, "material": material,
              "dirichlet": dirichlet, "rigid_plate": rigid_plate },
            { "name": "block", "mesh": {}, "material": material,
              "dirichlet": [{ "part": "bottom", "x": 0.0, "y": 0.0 }] },
        ],
        "contact": [{
            "body": "disc", "part": "arc", "other_body": "block", "other_part": "top",
            "max_distance": 0.05, "normal": normal.name(),
        }],
    }))?;
    scene.bodies[0].mesh = mesh_file(disc.display().to_string());
    scene.bodies[1].mesh = mesh_file(block.display().to_string());
    scene.contacts[0].law = Some(law);
    Ok(scene)
}

/// Coulomb's law at [`COEFFICIENT`] by its registry name.
fn coulomb() -> Choice {
    Choice::with_options("coulomb", Options::new().with("coefficient", COEFFICIENT))
}

/// The model of `scene` ([`Model::build`], files relative to the current folder) and the
/// scene's contact solver made by the model's registry.
fn model(scene: &Scene) -> Result<(Model, Box<dyn ContactSolver>), Failure> {
    let model = Model::build(scene, &BuildOptions::default())?;
    let solver = model.registries().solvers.make_choice(model.solver())?;
    Ok((model, solver))
}

/// The contact problem of the model of `scene` in the plane, and the scene's solver.
fn model_problem(scene: &Scene) -> Result<(ContactProblem, Box<dyn ContactSolver>), Failure> {
    let (model, solver) = model(scene)?;
    let (problem, _) = model
        .contact_problem()
        .ok_or("the scene has no contact pair")?;
    Ok((problem.clone(), solver))
}

/// The half-disc at h_c = `h` (its top moved by `(shift, -INDENTATION)`) on the block, solved.
fn disc_solve(
    meshes: &Path,
    h: &str,
    normal: ContactNormal,
    law: Choice,
    shift: f64,
) -> Result<ContactResult, Failure> {
    let scene = disc_scene(
        &meshes.join(format!("disc_hc{h}.msh")),
        &meshes.join(format!("block_hc{h}.msh")),
        Top::Moved(shift),
        law,
        normal,
    )?;
    let (problem, mut solver) = model_problem(&scene)?;
    Ok(problem.solve(solver.as_mut())?)
}

/// Hertz's solution for the load P (the vertical force on the disc).
fn hertz_for(load: f64) -> Result<HertzContact, Failure> {
    let e_star = HertzContact::plane_strain_modulus(YOUNG, POISSON, YOUNG, POISSON);
    Ok(HertzContact::try_new(RADIUS, e_star, load)?)
}

fn frictionless_run(
    meshes: &Path,
    h: &str,
    normal: ContactNormal,
) -> Result<Frictionless, Failure> {
    let result = disc_solve(meshes, h, normal, Choice::named("frictionless"), 0.0)?;
    let load = result.force_on_body_a().y;
    let hertz = hertz_for(load)?;
    let (a, p0) = (hertz.half_width(), hertz.peak_pressure());
    let nodes = &result.nodes;
    let peak = |value: fn(&InterfaceNode) -> f64| nodes.iter().map(value).fold(0.0, f64::max);
    let profile = |value: fn(&InterfaceNode) -> f64| {
        nodes
            .iter()
            .filter(|n| n.position.x.abs() <= PROFILE_FRACTION * a)
            .map(|n| (value(n) / hertz.pressure(n.position.x) - 1.0).abs())
            .fold(0.0, f64::max)
    };
    let (zone, _) = zone_half_width(nodes, |n| n.status != NodeStatus::Open);
    Ok(Frictionless {
        h_c: h.to_string(),
        normal: normal.name().to_string(),
        load,
        hertz_half_width: a,
        hertz_peak: p0,
        normal_sum_error: result.normal_resultant() / load - 1.0,
        horizontal_ratio: result.force_on_body_a().x / load,
        half_width_error: zone / a - 1.0,
        peak_error_raw: peak(|n| n.pressure) / p0 - 1.0,
        peak_error_consistent: peak(|n| n.consistent_pressure) / p0 - 1.0,
        profile_raw: profile(|n| n.pressure),
        profile_consistent: profile(|n| n.consistent_pressure),
        min_consistent: nodes
            .iter()
            .map(|n| n.consistent_pressure)
            .fold(f64::INFINITY, f64::min)
            / p0,
        curve: nodes
            .iter()
            .map(|n| {
                (
                    n.position.x / a,
                    n.pressure / p0,
                    n.consistent_pressure / p0,
                )
            })
            .collect(),
    })
}

fn friction_run(meshes: &Path, h: &str, normal: ContactNormal) -> Result<Friction, Failure> {
    let full = disc_solve(meshes, h, normal, coulomb(), FULL_SLIP_SHIFT)?;
    let force = full.force_on_body_a();
    let full_slip_ratio = force.x.abs() / force.y;
    let full_slip_stick_nodes = full.status_counts().stick;
    let partial = disc_solve(meshes, h, normal, coulomb(), PARTIAL_SHIFT)?;
    let force = partial.force_on_body_a();
    let partial_ratio = force.x.abs() / (COEFFICIENT * force.y);
    let hertz = hertz_for(force.y)?;
    let (zone, _) = zone_half_width(&partial.nodes, |n| n.status != NodeStatus::Open);
    let (stick, spacing) = zone_half_width(&partial.nodes, |n| n.status == NodeStatus::Stick);
    let (a, p0) = (hertz.half_width(), hertz.peak_pressure());
    Ok(Friction {
        h_c: h.to_string(),
        normal: normal.name().to_string(),
        full_slip_ratio,
        full_slip_stick_nodes,
        partial_ratio,
        stick_half_width: stick,
        stick_half_width_hertz: hertz.stick_half_width(partial_ratio),
        stick_half_width_computed_a: zone * (1.0 - partial_ratio.clamp(0.0, 1.0)).sqrt(),
        spacing,
        partial_load: force.y,
        curve: partial
            .nodes
            .iter()
            .map(|n| {
                (
                    n.position.x / a,
                    (n.friction_t() / n.tributary_measure).abs() / (COEFFICIENT * p0),
                    n.consistent_friction_t().abs() / (COEFFICIENT * p0),
                )
            })
            .collect(),
    })
}

/// The files of the section in the plane rendered from its JSON: `results.md`, the pressure
/// plot of every h_c, the Cattaneo-Mindlin traction of the finest default normal.
fn report(results: &Results, out: &Path) -> Result<Vec<(String, String)>, Failure> {
    let mut files = vec![("results.md".to_string(), markdown(results, out)?)];
    let mut sizes: Vec<&str> = Vec::new();
    for f in &results.frictionless {
        if !sizes.contains(&f.h_c.as_str()) {
            sizes.push(&f.h_c);
        }
    }
    for h in sizes {
        let runs: Vec<&Frictionless> = results.frictionless.iter().filter(|f| f.h_c == h).collect();
        files.push((format!("pressure_hc{h}.svg"), pressure_svg(h, &runs)?));
    }
    if let Some(c) = results
        .coulomb
        .iter()
        .rev()
        .find(|c| c.normal == ContactNormal::default().name())
    {
        files.push(("cattaneo_mindlin.svg".to_string(), traction_svg(c)?));
    }
    Ok(files)
}

/// The report of the runs: its template (`xtask/templates/hertz.md`) filled with the setup and
/// the tables of the frictionless and the Coulomb runs.
fn markdown(results: &Results, out: &Path) -> Result<String, String> {
    let mut frictionless = String::new();
    for r in &results.frictionless {
        let _ = writeln!(
            frictionless,
            "| {} | {} | {:+.1e} | {:+.1e} | {:+.1}% | {:+.2}% | {:+.2}% | {:.2}% | {:.2}% | {:+.2}% |",
            r.h_c,
            r.normal,
            r.normal_sum_error,
            r.horizontal_ratio,
            100.0 * r.half_width_error,
            100.0 * r.peak_error_raw,
            100.0 * r.peak_error_consistent,
            100.0 * r.profile_raw,
            100.0 * r.profile_consistent,
            100.0 * r.min_consistent
        );
    }
    let mut coulomb = String::new();
    for r in &results.coulomb {
        let _ = writeln!(
            coulomb,
            "| {} | {} | {:.6} | {} | {:.3} | {:.4} | {:.4} | {:.4} | {:.4} |",
            r.h_c,
            r.normal,
            r.full_slip_ratio,
            r.full_slip_stick_nodes,
            r.partial_ratio,
            r.stick_half_width,
            r.stick_half_width_hertz,
            r.stick_half_width_computed_a,
            r.spacing
        );
    }
    // The template supplies the line break that ends the report.
    let coulomb = coulomb.strip_suffix('\n').unwrap_or(&coulomb).to_string();
    crate::common::render(
        "xtask/templates/hertz.md",
        include_str!("../templates/hertz.md"),
        &[
            ("out", out.display().to_string()),
            ("seconds", format!("{:.0}", results.seconds)),
            ("radius", RADIUS.to_string()),
            ("indentation", INDENTATION.to_string()),
            ("young", YOUNG.to_string()),
            ("poisson", POISSON.to_string()),
            ("profile_fraction", PROFILE_FRACTION.to_string()),
            ("table_frictionless", frictionless),
            ("coefficient", COEFFICIENT.to_string()),
            ("full_slip_shift", FULL_SLIP_SHIFT.to_string()),
            ("partial_shift", PARTIAL_SHIFT.to_string()),
            ("table_coulomb", coulomb),
        ],
    )
}

type Plot = Result<String, Failure>;

/// p / p0 against x / a: Hertz, raw dots and consistent lines of each normal choice.
fn pressure_svg(h: &str, runs: &[&Frictionless]) -> Plot {
    let hertz: Vec<(f64, f64)> = (0..=200)
        .map(|k| {
            let s = -1.0 + 2.0 * k as f64 / 200.0;
            (s, (1.0 - s * s).max(0.0).sqrt())
        })
        .collect();
    let mut series = Vec::new();
    for r in runs {
        let raw: Vec<(f64, f64)> = r.curve.iter().map(|&(x, p, _)| (x, p)).collect();
        let consistent: Vec<(f64, f64)> = r.curve.iter().map(|&(x, _, p)| (x, p)).collect();
        series.push((r.normal.to_string(), raw, consistent));
    }
    chart(
        &format!("Hertz, h_c = {h}: contact pressure"),
        "p / p0",
        ("Hertz sqrt(1 - x^2/a^2)", hertz),
        series,
    )
}

/// q / (F p0) against x / a: Cattaneo-Mindlin, raw dots and the consistent line.
fn traction_svg(c: &Friction) -> Plot {
    let hertz = c.hertz()?;
    let a = hertz.half_width();
    let p0 = hertz.peak_pressure();
    let exact: Vec<(f64, f64)> = (0..=400)
        .map(|k| {
            let s = -1.0 + 2.0 * k as f64 / 400.0;
            (
                s,
                hertz.tangential_traction(s * a, COEFFICIENT, c.partial_ratio) / (COEFFICIENT * p0),
            )
        })
        .collect();
    let raw: Vec<(f64, f64)> = c.curve.iter().map(|&(x, q, _)| (x, q)).collect();
    let consistent: Vec<(f64, f64)> = c.curve.iter().map(|&(x, _, q)| (x, q)).collect();
    chart(
        &format!(
            "Cattaneo-Mindlin, h_c = {}, Q/(F P) = {:.3}: friction traction",
            c.h_c, c.partial_ratio
        ),
        "|q| / (F p0)",
        ("Cattaneo-Mindlin", exact),
        vec![(c.normal.to_string(), raw, consistent)],
    )
}

/// `exact` (label, points) as a black line and each of `series` (label, nodal values, consistent
/// values) as dots and a line in a colour of its own, against `x / a` in [-1.5, 1.5].
#[allow(clippy::type_complexity)]
fn chart(
    title: &str,
    y_desc: &str,
    exact: (&str, Vec<(f64, f64)>),
    series: Vec<(String, Vec<(f64, f64)>, Vec<(f64, f64)>)>,
) -> Plot {
    let inside = |p: &(f64, f64)| p.0.abs() <= 1.5;
    let mut layers = vec![Layer::line(exact.1, Pen::new(BLACK, 2)).labelled(exact.0)];
    for (k, (label, raw, consistent)) in series.into_iter().enumerate() {
        let colour = Palette99::pick(k).to_rgba();
        layers.push(
            Layer::line(
                consistent.into_iter().filter(inside).collect(),
                Pen::new(colour, 2),
            )
            .legend(
                format!("{label}: consistent"),
                Glyph::Line(Pen::new(colour, 1)),
            ),
        );
        layers.push(
            Layer::dots(raw.into_iter().filter(inside).collect(), 3, colour)
                .labelled(format!("{label}: nodal (raw)")),
        );
    }
    let chart = Chart::new(
        Axis::linear("x / a", -1.5..1.5),
        Axis::linear(y_desc, 0.0..1.3),
    )
    .caption(title, CAPTION_SIZE)
    .frame(15, (40, 55))
    .light_grid();
    Ok(chart_svg((900, 600), &chart, &layers)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `--report-only` from the committed JSON of `docs/hertz` rewrites every committed report
    /// and plot of the three sections byte for byte.
    #[test]
    fn the_committed_hertz_reports_are_rendered_from_their_json() {
        let docs = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/hertz");
        let out = Path::new("docs/hertz");
        let mut files = report(&read_json(docs.join("results.json")).unwrap(), out).unwrap();
        files.extend(fretting::report(&read_json(docs.join("fretting.json")).unwrap()).unwrap());
        files
            .extend(mindlin_3d::report(&read_json(docs.join("mindlin-3d.json")).unwrap()).unwrap());
        // results.md, four pressure plots, the traction plot; fretting.md and its three plots;
        // mindlin-3d.md.
        assert_eq!(files.len(), 11);
        for (name, text) in &files {
            let committed = std::fs::read_to_string(docs.join(name))
                .unwrap_or_else(|e| panic!("docs/hertz/{name}: {e}"));
            assert!(
                *text == committed,
                "docs/hertz/{name} is not the report rendered from its JSON"
            );
        }
    }
}
