//! `cargo xtask hertz`: the Hertz half-disc on a block (non-matching Gmsh meshes) at three
//! contact mesh sizes with each contact normal choice, against Hertz's plane-strain solution;
//! Coulomb friction at full slip (Q/P against F) and under a partial tangential shift against
//! Cattaneo-Mindlin's stick half-width; friction under force control and along load histories
//! (the `fretting` section: loading, unloading, reloading, path dependence); Cattaneo-Mindlin
//! in space (the `mindlin_3d` section: the stick disc of two blocks with a spherical gap). See
//! `docs/hertz.md`.

mod fretting;
mod mindlin_3d;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use clap::Args;
use serde::Serialize;
use vem_contact::{
    CondensedSolver, ContactLaw, ContactNormal, ContactProblem, ContactResult, Coulomb,
    InterfaceNode, NodeStatus,
};
use vem_elastic::{Component, Dirichlet, ElasticBody, Material, Plane};
use vem_mesh::interface::InterfaceOptions;
use vem_mesh::io::read_gmsh;
use vem_mesh::Vector;
use vem_space::LowestOrderVem;
use vem_verify::exact::HertzContact;
use vem_verify::fretting::zone_half_width;
use vem_verify::plot::{
    chart_svg, Axis, Chart, Color, Glyph, Layer, Palette, Palette99, Pen, BLACK, CAPTION_SIZE,
};
use vem_verify::report::write_text;

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
#[derive(Debug, Clone, Serialize)]
struct Frictionless {
    h_c: String,
    normal: &'static str,
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
    /// (x / a, p / p0) raw and consistent, for the plots.
    #[serde(skip)]
    curve: Vec<(f64, f64, f64)>,
}

/// One Coulomb run (full slip and partial slip).
#[derive(Debug, Clone, Serialize)]
struct Friction {
    h_c: String,
    normal: &'static str,
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
    /// Slip nodes with no tangential load (the frictionless answer's tangential forces).
    #[serde(skip)]
    curve: Vec<(f64, f64, f64)>,
    #[serde(skip)]
    hertz: Option<HertzContact>,
}

/// Runs the study and writes `hertz.md`, `hertz.json` and the plots.
pub fn run(args: &HertzArgs) -> Result<bool, Box<dyn std::error::Error>> {
    let start = Instant::now();
    std::fs::create_dir_all(&args.out)?;
    if args.friction_only {
        fretting::run(args)?;
        println!(
            "wrote {0}/fretting.md, fretting.json and its SVG plots",
            args.out.display()
        );
        return Ok(true);
    }
    if args.space_only {
        return space(args);
    }
    let mut frictionless = Vec::new();
    let mut friction = Vec::new();
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
            friction.push(c);
        }
    }
    let md = markdown(
        &frictionless,
        &friction,
        args,
        start.elapsed().as_secs_f64(),
    )?;
    write_text(args.out.join("results.md"), &md)?;
    let json = serde_json::json!({ "frictionless": frictionless, "coulomb": friction });
    write_text(
        args.out.join("results.json"),
        &serde_json::to_string_pretty(&json)?,
    )?;
    for h in &args.sizes {
        let runs: Vec<&Frictionless> = frictionless.iter().filter(|f| &f.h_c == h).collect();
        write_text(
            args.out.join(format!("pressure_hc{h}.svg")),
            &pressure_svg(h, &runs)?,
        )?;
    }
    if let Some(c) = friction
        .iter()
        .rev()
        .find(|c| c.normal == ContactNormal::default().name())
    {
        write_text(args.out.join("cattaneo_mindlin.svg"), &traction_svg(c)?)?;
    }
    fretting::run(args)?;
    println!(
        "wrote {0}/results.md, results.json, fretting.md, fretting.json and the SVG plots",
        args.out.display()
    );
    space(args)
}

/// The section in space: Cattaneo-Mindlin in 3D at the node spacing a/6 (`--quick`: a/4),
/// written to `mindlin-3d.md` and `mindlin-3d.json`; false when it falls short.
fn space(args: &HertzArgs) -> Result<bool, Box<dyn std::error::Error>> {
    let start = Instant::now();
    let a = mindlin_3d::hertz()?.contact_radius();
    let study = mindlin_3d::study(a / if args.quick { 4.0 } else { 6.0 })?;
    let shortfalls = study.shortfalls();
    let md = crate::common::render(
        "xtask/templates/mindlin-3d.md",
        include_str!("../templates/mindlin-3d.md"),
        &[
            (
                "options",
                if args.quick { " --quick" } else { "" }.to_string(),
            ),
            ("seconds", format!("{:.0}", start.elapsed().as_secs_f64())),
            ("study", study.markdown()),
            (
                "verdict",
                if shortfalls.is_empty() {
                    "pass (every stick radius within one node spacing of Mindlin's, the load \
                     carried to 1e-8, the refusal beyond the capacity)."
                        .to_string()
                } else {
                    format!("FAIL\n\n- {}", shortfalls.join("\n- "))
                },
            ),
        ],
    )?;
    print!("{}", study.markdown());
    write_text(args.out.join("mindlin-3d.md"), &md)?;
    write_text(
        args.out.join("mindlin-3d.json"),
        &serde_json::to_string_pretty(&study)?,
    )?;
    println!(
        "wrote {}/mindlin-3d.md and mindlin-3d.json",
        args.out.display()
    );
    Ok(shortfalls.is_empty())
}

/// The problem: the half-disc (top moved by `(shift, -INDENTATION)`) on the block.
fn problem(
    meshes: &Path,
    h: &str,
    normal: ContactNormal,
    law: impl ContactLaw + 'static,
    shift: f64,
) -> Result<ContactProblem, Box<dyn std::error::Error>> {
    let material = Material::from_young_poisson(YOUNG, POISSON, Plane::Strain)?;
    let element = Arc::new(LowestOrderVem::default());
    let disc = read_gmsh(meshes.join(format!("disc_hc{h}.msh")))?;
    let block = read_gmsh(meshes.join(format!("block_hc{h}.msh")))?;
    let disc = ElasticBody::builder("disc", disc, material, element.clone())
        .dirichlet(Dirichlet::prescribed("top", Component::All, move |_| {
            Vector::new(shift, -INDENTATION)
        }))
        .build()?;
    let block = ElasticBody::builder("block", block, material, element)
        .dirichlet(Dirichlet::prescribed("bottom", Component::All, |_| {
            Vector::zeros()
        }))
        .build()?;
    Ok(ContactProblem::two_bodies(disc, "arc", block, "top", law)
        .with_interface_options(InterfaceOptions::builder().max_distance(0.05).build()?)
        .with_normal(normal))
}

/// P (the vertical force on the disc) and Hertz's solution for it.
fn hertz_for(result: &ContactResult) -> Result<(f64, HertzContact), Box<dyn std::error::Error>> {
    let load = result.force_on_body_a().y;
    let e_star = HertzContact::plane_strain_modulus(YOUNG, POISSON, YOUNG, POISSON);
    Ok((load, HertzContact::try_new(RADIUS, e_star, load)?))
}

fn frictionless_run(
    meshes: &Path,
    h: &str,
    normal: ContactNormal,
) -> Result<Frictionless, Box<dyn std::error::Error>> {
    let result = problem(meshes, h, normal, vem_contact::Frictionless, 0.0)?
        .solve(&mut CondensedSolver::default())?;
    let (load, hertz) = hertz_for(&result)?;
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
        normal: normal.name(),
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

fn friction_run(
    meshes: &Path,
    h: &str,
    normal: ContactNormal,
) -> Result<Friction, Box<dyn std::error::Error>> {
    let law = Coulomb::try_new(COEFFICIENT)?;
    let mut solver = CondensedSolver::default();
    let full = problem(meshes, h, normal, law, FULL_SLIP_SHIFT)?.solve(&mut solver)?;
    let force = full.force_on_body_a();
    let full_slip_ratio = force.x.abs() / force.y;
    let full_slip_stick_nodes = full.status_counts().stick;
    let partial = problem(meshes, h, normal, law, PARTIAL_SHIFT)?.solve(&mut solver)?;
    let force = partial.force_on_body_a();
    let partial_ratio = force.x.abs() / (COEFFICIENT * force.y);
    let (_, hertz) = hertz_for(&partial)?;
    let (zone, _) = zone_half_width(&partial.nodes, |n| n.status != NodeStatus::Open);
    let (stick, spacing) = zone_half_width(&partial.nodes, |n| n.status == NodeStatus::Stick);
    let (a, p0) = (hertz.half_width(), hertz.peak_pressure());
    Ok(Friction {
        h_c: h.to_string(),
        normal: normal.name(),
        full_slip_ratio,
        full_slip_stick_nodes,
        partial_ratio,
        stick_half_width: stick,
        stick_half_width_hertz: hertz.stick_half_width(partial_ratio),
        stick_half_width_computed_a: zone * (1.0 - partial_ratio.clamp(0.0, 1.0)).sqrt(),
        spacing,
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
        hertz: Some(hertz),
    })
}

/// The report of the runs: its template (`xtask/templates/hertz.md`) filled with the setup and
/// the tables of the frictionless and the Coulomb runs.
fn markdown(
    f: &[Frictionless],
    c: &[Friction],
    args: &HertzArgs,
    seconds: f64,
) -> Result<String, String> {
    let mut frictionless = String::new();
    for r in f {
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
    for r in c {
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
            ("out", args.out.display().to_string()),
            ("seconds", format!("{seconds:.0}")),
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

type Plot = Result<String, Box<dyn std::error::Error>>;

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
    let hertz = c.hertz.ok_or("no Hertz solution")?;
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
