//! The friction section of `cargo xtask hertz`: Coulomb friction under force control and
//! followed along load histories, against Cattaneo-Mindlin (Johnson, Contact Mechanics,
//! 7.5-7.6). Writes `fretting.md`, `fretting.json` and the plots `fretting_tractions.svg`,
//! `fretting_loop.svg`, `fretting_paths.svg` (see `docs/hertz.md`, section 4).
//!
//! 1. The half-disc on the block (h_c = 0.02), its top a rigid plate pushed with P = 0.5 and
//!    sheared with Q: held sideways by friction alone, stick zone against `a sqrt(1 - Q/(F P))`,
//!    and the refusal beyond `F P`.
//! 2. Two flat blocks with the gap `x^2 / (2R)` (the upper one the mirror image of a block
//!    mesh: h_c = 0.01 over 0.005, and 0.005 over 0.0025), pushed then sheared through the
//!    cycle `0 -> Q* -> -Q* -> Q*` (`Q* = 0.8 F P`): the zone that sticks against `c` and `c'`,
//!    the tractions against the loading, unloading and reloading solutions, the loop.
//! 3. Two paths to the same load (proportional, and pushed then sheared): different tractions
//!    with friction, the same answer without.
//! 4. The friction traction that pushing alone leaves on the curved disc (its surface tilts by
//!    `x / R` against the flat block's normal), absent from Cattaneo-Mindlin's half-planes.

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use serde::{Deserialize, Serialize};
use vem_contact::{ContactDiscretisation, ContactResult, HistoryStep, NodeStatus};
use vem_mesh::io::read_gmsh;
use vem_scene::description::LoadHistory;
use vem_scene::Scene;
use vem_space::Choice;
use vem_verify::exact::HertzContact;
use vem_verify::fretting::{
    self, friction_traction as traction, largest_spacing_within as spacing_in, mesh_file,
    plate_translation, zone_half_width as zone, Drive, FlatBlocks,
};
use vem_verify::plot::{
    chart_svg, Axis, Chart, Glyph, Layer, LegendPosition, Pen, RGBColor, CAPTION_SIZE,
};

use super::{
    disc_scene, model, number_or_nan, HertzArgs, Top, COEFFICIENT as F, POISSON, RADIUS, YOUNG,
};

/// The push P of the force-controlled problems.
const PUSH: f64 = 0.5;
/// The flat blocks of the cycles and the paths.
const SETUP: FlatBlocks = FlatBlocks {
    young: YOUNG,
    poisson: POISSON,
    radius: RADIUS,
    coefficient: F,
    push: PUSH,
};
/// The peak of the tangential cycle, `Q* / (F P)`.
const PEAK: f64 = 0.8;
/// The scene meshes (h_c = 0.01).
const SCENES: &str = "crates/vem-cli/scenes";

type Failure = Box<dyn std::error::Error>;
/// A labelled profile: computed points and the analytic curve, `(x / a, q / (F p0))`.
type Profile = (String, Vec<(f64, f64)>, Vec<(f64, f64)>);

/// One ratio of the disc under force control.
#[derive(Debug, Serialize, Deserialize)]
struct DiscRow {
    ratio: f64,
    /// `Q` and `P` carried by the contact, relative to the plate's.
    #[serde(deserialize_with = "number_or_nan")]
    shear_error: f64,
    #[serde(deserialize_with = "number_or_nan")]
    push_error: f64,
    #[serde(deserialize_with = "number_or_nan")]
    stick_half_width: f64,
    #[serde(deserialize_with = "number_or_nan")]
    cattaneo_mindlin: f64,
    #[serde(deserialize_with = "number_or_nan")]
    spacing: f64,
    /// The refusal beyond the capacity.
    refusal: Option<String>,
}

/// One step of a cycle.
#[derive(Debug, Serialize, Deserialize)]
struct CycleRow {
    time: f64,
    branch: String,
    ratio: f64,
    stick_half_width: f64,
    analytic: f64,
    spacing: f64,
    /// Largest `|q - q_exact| / (F p0)` two spacings away from the zone ends.
    traction_error: f64,
    plate_x: f64,
    seconds: f64,
}

/// A cycle on one mesh pair.
#[derive(Debug, Serialize, Deserialize)]
struct Cycle {
    meshes: String,
    unknowns: usize,
    nodes: usize,
    rows: Vec<CycleRow>,
    /// Largest zone-end error in node spacings (the largest spacing of the interface nodes in
    /// the contact zone), largest traction error.
    zone_error: f64,
    traction_error: f64,
    /// Back at Q* after the cycle: plate displacement change (relative), rms traction change.
    closure_plate: f64,
    closure_traction: f64,
    /// Largest `|x_down(Q) + x_up(-Q)| / x(Q*)` (Masing).
    masing: f64,
    /// The tractions at t = 2, 3, 4, 5 (`fretting_tractions.svg` of the finest cycle).
    profiles: Vec<Profile>,
    /// `(plate x, Q / (F P))` of every step after the push (`fretting_loop.svg`).
    loop_curve: Vec<(f64, f64)>,
}

/// The path-dependence study.
#[derive(Debug, Serialize, Deserialize)]
struct Paths {
    /// rms of `q - (Q/P) p` (proportional) and of `q - q_CM` (pushed then sheared) inside
    /// 0.9 a, in `F p0`, and the largest difference between the two paths.
    proportional_rms: f64,
    sequential_rms: f64,
    difference: f64,
    /// Frictionless: the largest difference of the normal forces between three paths and the
    /// static answer, relative.
    frictionless_difference: f64,
    /// The two paths' tractions (`fretting_paths.svg`).
    profiles: Vec<Profile>,
}

/// `fretting.json`: the rows of the section and the curves of its plots.
#[derive(Debug, Serialize, Deserialize)]
pub(super) struct Section {
    /// Wall-clock seconds of the section.
    seconds: f64,
    disc: Vec<DiscRow>,
    cycles: Vec<Cycle>,
    paths: Paths,
    pushing_alone: Vec<(String, f64)>,
}

/// Runs the section.
pub(super) fn run(args: &HertzArgs) -> Result<Section, Failure> {
    let start = Instant::now();
    let hertz = SETUP.hertz()?;
    let disc = disc_rows(args, &hertz)?;
    let mut cycles = Vec::new();
    for (upper, lower) in [
        (format!("{SCENES}/hertz_block.msh"), "block_hc0.005.msh"),
        (
            args.meshes.join("block_hc0.005.msh").display().to_string(),
            "block_hc0.0025.msh",
        ),
    ] {
        let lower = args.meshes.join(lower).display().to_string();
        let cycle = cycle(&upper, &lower, &hertz)?;
        eprintln!(
            "cycle {}: zone ends within {:.2} spacings, tractions within {:.3} F p0, closure \
             {:.1e} / {:.1e}",
            cycle.meshes,
            cycle.zone_error,
            cycle.traction_error,
            cycle.closure_plate,
            cycle.closure_traction
        );
        cycles.push(cycle);
    }
    let lower = args.meshes.join("block_hc0.005.msh").display().to_string();
    let paths = paths(&format!("{SCENES}/hertz_block.msh"), &lower, &hertz)?;
    let pushing_alone = pushing_alone(args, &hertz)?;
    Ok(Section {
        seconds: start.elapsed().as_secs_f64(),
        disc,
        cycles,
        paths,
        pushing_alone,
    })
}

/// The files of the section rendered from its JSON: `fretting.md` and its three plots.
pub(super) fn report(section: &Section) -> Result<Vec<(String, String)>, Failure> {
    let finest = section.cycles.last().ok_or("no cycle")?;
    Ok(vec![
        ("fretting.md".to_string(), markdown(section)?),
        (
            "fretting_tractions.svg".to_string(),
            profile_svg(
                &format!(
                    "Cattaneo-Mindlin cycle, {}: friction traction",
                    finest.meshes
                ),
                &finest.profiles,
                -1.75..1.15,
            )?,
        ),
        ("fretting_loop.svg".to_string(), loop_svg(&section.cycles)?),
        (
            "fretting_paths.svg".to_string(),
            profile_svg(
                "Two paths to Q = 0.5 F P: friction traction",
                &section.paths.profiles,
                -0.1..1.0,
            )?,
        ),
    ])
}

/// `scene` followed along the pseudo-times `times`, its upper body's first two conditions
/// (the push and the shear: the disc's and the flat blocks' rigid plates, or the flat blocks'
/// prescribed displacements) scaled by the load curves `press` and `shear`.
fn along(mut scene: Scene, times: Vec<f64>, press: &[(f64, f64)], shear: &[(f64, f64)]) -> Scene {
    let curve = |points: &[(f64, f64)]| Some(points.iter().map(|&(t, s)| [t, s]).collect());
    let body = &mut scene.bodies[0];
    if body.rigid_plate.len() == 2 {
        body.rigid_plate[0].curve = curve(press);
        body.rigid_plate[1].curve = curve(shear);
    } else {
        body.dirichlet[0].curve = curve(press);
        body.dirichlet[1].curve = curve(shear);
    }
    scene.history = Some(LoadHistory {
        times: Some(times),
        ..LoadHistory::default()
    });
    scene
}

/// The steps of the load history of `scene`, solved on its model's contact problem with its
/// solver.
fn steps(scene: &Scene) -> Result<Vec<HistoryStep>, Failure> {
    let (model, mut solver) = model(scene)?;
    let (problem, _) = model.contact_problem().ok_or("no contact pair")?;
    Ok(problem
        .discretise()?
        .solve_history(solver.as_mut(), &model.load_history()?)?)
}

/// The last step of the load history of `scene`.
fn last_step(scene: &Scene) -> Result<ContactResult, Failure> {
    Ok(steps(scene)?.pop().ok_or("no step")?.result)
}

/// The half-disc (the mesh file `disc`) on the block (`block`), the disc's top a rigid plate
/// with the resultant `(shear, -push)` (two conditions: the push, then the shear), Coulomb
/// friction.
fn disc(disc: &Path, block: &Path, push: f64, shear: f64) -> Result<Scene, Failure> {
    disc_scene(
        disc,
        block,
        Top::Plate { push, shear },
        SETUP.coulomb(),
        Default::default(),
    )
}

fn disc_rows(args: &HertzArgs, hertz: &HertzContact) -> Result<Vec<DiscRow>, Failure> {
    let mut rows = Vec::new();
    for ratio in [0.01, 0.2, 0.5, 0.8, 0.99, 1.01] {
        let shear = ratio * F * PUSH;
        let scene = disc(
            &args.meshes.join("disc_hc0.02.msh"),
            &args.meshes.join("block_hc0.02.msh"),
            PUSH,
            shear,
        )?;
        let (model, mut solver) = model(&scene)?;
        let (problem, _) = model.contact_problem().ok_or("no contact pair")?;
        match problem.solve(solver.as_mut()) {
            Ok(result) => {
                let force = result.force_on_body_a();
                let (c, spacing) = zone(&result.nodes, |n| n.status == NodeStatus::Stick);
                rows.push(DiscRow {
                    ratio,
                    shear_error: (force.x + shear).abs() / shear,
                    push_error: (force.y - PUSH).abs() / PUSH,
                    stick_half_width: c,
                    cattaneo_mindlin: hertz.stick_half_width(ratio),
                    spacing,
                    refusal: None,
                });
            }
            Err(e) => rows.push(DiscRow {
                ratio,
                shear_error: f64::NAN,
                push_error: f64::NAN,
                stick_half_width: f64::NAN,
                cattaneo_mindlin: f64::NAN,
                spacing: f64::NAN,
                refusal: Some(e.to_string()),
            }),
        }
    }
    Ok(rows)
}

/// The two flat blocks: the mirror image of the mesh file `upper` on the mesh file `lower`.
fn blocks(upper: &str, lower: &str, drive: Drive, law: Choice) -> Result<Scene, Failure> {
    Ok(SETUP.scene(&read_gmsh(upper)?, mesh_file(lower), drive, law)?)
}

fn traction_error(
    result: &ContactResult,
    hertz: &HertzContact,
    exact: impl Fn(f64) -> f64,
    ends: &[f64],
) -> f64 {
    fretting::traction_error(result, hertz, F, exact, ends)
}

fn traction_rms(result: &ContactResult, hertz: &HertzContact, exact: impl Fn(f64) -> f64) -> f64 {
    fretting::traction_rms(result, hertz, F, exact)
}

/// `(x / a, q / (F p0))` computed, and the analytic curve `exact`.
#[allow(clippy::type_complexity)]
fn profile(
    result: &ContactResult,
    hertz: &HertzContact,
    exact: impl Fn(f64) -> f64,
) -> (Vec<(f64, f64)>, Vec<(f64, f64)>) {
    let (a, p0) = (hertz.half_width(), hertz.peak_pressure());
    let computed = result
        .nodes
        .iter()
        .filter(|n| n.position.x.abs() <= 1.3 * a)
        .map(|n| (n.position.x / a, traction(n) / (F * p0)))
        .collect();
    let analytic = (0..=400)
        .map(|k| {
            let s = -1.2 + 2.4 * k as f64 / 400.0;
            (s, exact(s * a) / (F * p0))
        })
        .collect();
    (computed, analytic)
}

fn cycle(upper: &str, lower: &str, hertz: &HertzContact) -> Result<Cycle, Failure> {
    let name = |p: &str| {
        Path::new(p)
            .file_name()
            .map_or(p.to_string(), |f| f.to_string_lossy().to_string())
    };
    // Pushed during t in [0, 1]; sheared to Q* at t = 2, back to -Q* at t = 4, to Q* at 6.
    let mut times = vec![0.5, 1.0];
    times.extend((1..=40).map(|k| 1.0 + 0.125 * k as f64));
    let scene = along(
        blocks(upper, lower, Drive::Force, SETUP.coulomb())?,
        times,
        &[(0.0, 0.0), (1.0, 1.0)],
        &[(1.0, 0.0), (2.0, PEAK), (4.0, -PEAK), (6.0, PEAK)],
    );
    let (model, mut solver) = model(&scene)?;
    let history = model.load_history()?;
    let d: ContactDiscretisation = model
        .contact_problem()
        .ok_or("no contact pair")?
        .0
        .discretise()?;
    let mut path = vem_contact::LoadPath::new(&d)?;
    let c_peak = hertz.stick_half_width(PEAK);
    let (mut rows, mut profiles, mut loop_curve) = (Vec::new(), Vec::new(), Vec::new());
    let (mut at_peak, mut last) = (None, None);
    for step in history.steps() {
        let t0 = Instant::now();
        let result = path.advance(solver.as_mut(), step.time, &step.factors)?;
        let seconds = t0.elapsed().as_secs_f64();
        let (t, r) = (step.time, step.factors.factor(FlatBlocks::SHEAR));
        if t <= 1.0 {
            continue;
        }
        let (branch, analytic, error, exact): (_, _, _, Box<dyn Fn(f64) -> f64>) =
            if t <= 2.0 + 1e-9 {
                let c = hertz.stick_half_width(r);
                let exact = move |x| hertz.tangential_traction(x, F, r);
                (
                    "loading",
                    c,
                    traction_error(&result, hertz, exact, &[c]),
                    Box::new(exact),
                )
            } else if t <= 4.0 + 1e-9 {
                let c = hertz.counter_slip_half_width(PEAK, r);
                let exact = move |x| hertz.unloading_traction(x, F, PEAK, r);
                let e = traction_error(&result, hertz, exact, &[c, c_peak]);
                ("unloading", c, e, Box::new(exact))
            } else {
                let c = hertz.counter_slip_half_width(PEAK, -r);
                let exact = move |x| hertz.reloading_traction(x, F, PEAK, r);
                let e = traction_error(&result, hertz, exact, &[c, c_peak]);
                ("reloading", c, e, Box::new(exact))
            };
        let c = zone(&result.nodes, |n| n.status == NodeStatus::Stick).0;
        let spacing = spacing_in(&result.nodes, hertz.half_width());
        let x = plate_translation(&result)?;
        loop_curve.push((x, r));
        if [2.0, 3.0, 4.0, 5.0].iter().any(|s| (t - s).abs() < 1e-9) {
            let (computed, analytic) = profile(&result, hertz, &exact);
            profiles.push((format!("{branch}, Q/(F P) = {r:+.1}"), computed, analytic));
        }
        rows.push(CycleRow {
            time: t,
            branch: branch.to_string(),
            ratio: r,
            stick_half_width: c,
            analytic,
            spacing,
            traction_error: error,
            plate_x: x,
            seconds,
        });
        if (t - 2.0).abs() < 1e-9 {
            at_peak = Some(result.clone());
        }
        last = Some(result);
    }
    let (first, last) = (at_peak.ok_or("no peak")?, last.ok_or("no step")?);
    let (x1, x2) = (plate_translation(&first)?, plate_translation(&last)?);
    let p0 = hertz.peak_pressure();
    let closure_traction = (first
        .nodes
        .iter()
        .zip(&last.nodes)
        .map(|(a, b)| ((traction(a) - traction(b)) / (F * p0)).powi(2))
        .sum::<f64>()
        / first.nodes.len() as f64)
        .sqrt();
    let down: Vec<&CycleRow> = rows.iter().filter(|r| r.branch == "unloading").collect();
    let up: Vec<&CycleRow> = rows.iter().filter(|r| r.branch == "reloading").collect();
    let masing = down
        .iter()
        .zip(&up)
        .map(|(a, b)| (a.plate_x + b.plate_x).abs() / x1.abs())
        .fold(0.0, f64::max);
    Ok(Cycle {
        meshes: format!("{} mirrored over {}", name(upper), name(lower)),
        unknowns: d.n_dofs(),
        nodes: d.nodes().len(),
        zone_error: rows
            .iter()
            .map(|r| (r.stick_half_width - r.analytic).abs() / r.spacing)
            .fold(0.0, f64::max),
        traction_error: rows.iter().map(|r| r.traction_error).fold(0.0, f64::max),
        closure_plate: (x1 - x2).abs() / x1.abs(),
        closure_traction,
        masing,
        rows,
        profiles,
        loop_curve,
    })
}

/// The pseudo-times `1/n, 2/n, ..., m/n`.
fn times(m: usize, n: usize) -> Vec<f64> {
    (1..=m).map(|k| k as f64 / n as f64).collect()
}

fn paths(upper: &str, lower: &str, hertz: &HertzContact) -> Result<Paths, Failure> {
    let ratio = 0.5;
    let scene = blocks(upper, lower, Drive::Force, SETUP.coulomb())?;
    // Pushed and sheared together in 32 steps; pushed in 4 steps, then sheared in 4.
    let proportional = last_step(&along(
        scene.clone(),
        times(32, 32),
        &[(0.0, 0.0), (1.0, 1.0)],
        &[(0.0, 0.0), (1.0, ratio)],
    ))?;
    let sequential = last_step(&along(
        scene,
        times(8, 4),
        &[(0.0, 0.0), (1.0, 1.0)],
        &[(1.0, 0.0), (2.0, ratio)],
    ))?;
    let proportional_exact = |x: f64| F * ratio * hertz.pressure(x);
    let sequential_exact = |x: f64| hertz.tangential_traction(x, F, ratio);
    let a = hertz.half_width();
    let p0 = hertz.peak_pressure();
    let difference = proportional
        .nodes
        .iter()
        .zip(&sequential.nodes)
        .filter(|(n, _)| n.position.x.abs() < 0.9 * a)
        .map(|(x, y)| (traction(x) - traction(y)).abs() / (F * p0))
        .fold(0.0, f64::max);
    let (p_computed, p_analytic) = profile(&proportional, hertz, proportional_exact);
    let (s_computed, s_analytic) = profile(&sequential, hertz, sequential_exact);
    // Frictionless: three paths of the displacement-driven problem and the static answer.
    let scene = blocks(
        upper,
        lower,
        Drive::Displacement(0.004, 0.012),
        Choice::named("frictionless"),
    )?;
    let (model, mut solver) = model(&scene)?;
    let statically = model
        .contact_problem()
        .ok_or("no contact pair")?
        .0
        .solve(solver.as_mut())?;
    let scale = statically
        .nodes
        .iter()
        .fold(0.0f64, |m, n| m.max(n.normal_force));
    let mut frictionless_difference = 0.0f64;
    for path in [
        vec![(0.5, 0.5), (1.0, 1.0)],
        vec![(1.0, 0.0), (1.0, 1.0)],
        vec![(1.0, 0.0), (1.0, 2.0), (1.0, -1.0), (1.0, 1.0)],
    ] {
        // Step k at t = k with the factors (press, shift) of `path`.
        let at = |f: fn(&(f64, f64)) -> f64| -> Vec<(f64, f64)> {
            path.iter()
                .enumerate()
                .map(|(k, p)| ((k + 1) as f64, f(p)))
                .collect()
        };
        let answer = last_step(&along(
            scene.clone(),
            times(path.len(), 1),
            &at(|p| p.0),
            &at(|p| p.1),
        ))?;
        for (x, y) in answer.nodes.iter().zip(&statically.nodes) {
            frictionless_difference =
                frictionless_difference.max((x.normal_force - y.normal_force).abs() / scale);
        }
    }
    Ok(Paths {
        proportional_rms: traction_rms(&proportional, hertz, proportional_exact),
        sequential_rms: traction_rms(&sequential, hertz, sequential_exact),
        difference,
        frictionless_difference,
        profiles: vec![
            (
                "pushed and sheared together (32 steps): (Q/P) p".to_string(),
                p_computed,
                p_analytic,
            ),
            (
                "pushed, then sheared (4 + 4 steps): Cattaneo-Mindlin".to_string(),
                s_computed,
                s_analytic,
            ),
        ],
    })
}

/// Pushing alone (4 steps to P, no shear): the largest consistent friction traction it
/// leaves, in `F p0`, on the curved disc and on the flat blocks.
fn pushing_alone(args: &HertzArgs, hertz: &HertzContact) -> Result<Vec<(String, f64)>, Failure> {
    let push = |scene: Scene| {
        along(
            scene,
            times(4, 4),
            &[(0.0, 0.0), (1.0, 1.0)],
            &[(0.0, 0.0), (1.0, 0.0)],
        )
    };
    let p0 = hertz.peak_pressure();
    let largest =
        |r: &ContactResult| r.nodes.iter().fold(0.0f64, |m, n| m.max(traction(n).abs())) / (F * p0);
    let mut rows = Vec::new();
    for (label, disc_mesh, block_mesh) in [
        (
            "half-disc on the block, h_c = 0.02",
            args.meshes.join("disc_hc0.02.msh"),
            args.meshes.join("block_hc0.02.msh"),
        ),
        (
            "half-disc on the block, h_c = 0.01",
            Path::new(SCENES).join("hertz_disc.msh"),
            Path::new(SCENES).join("hertz_block.msh"),
        ),
    ] {
        let scene = disc(&disc_mesh, &block_mesh, PUSH, F * PUSH)?;
        rows.push((label.to_string(), largest(&last_step(&push(scene))?)));
    }
    let lower = args.meshes.join("block_hc0.005.msh").display().to_string();
    let scene = blocks(
        &format!("{SCENES}/hertz_block.msh"),
        &lower,
        Drive::Force,
        SETUP.coulomb(),
    )?;
    rows.push((
        "flat blocks, h_c = 0.01 over 0.005".to_string(),
        largest(&last_step(&push(scene))?),
    ));
    Ok(rows)
}

/// The section's report: its template (`xtask/templates/fretting.md`) filled with the setup,
/// the tables and the values of the path study.
fn markdown(section: &Section) -> Result<String, String> {
    let Section {
        seconds,
        disc,
        cycles,
        paths,
        pushing_alone: pushing,
    } = section;
    let mut disc_table = String::new();
    for r in disc {
        match &r.refusal {
            None => {
                let _ = writeln!(
                    disc_table,
                    "| {} | {:.1e} | {:.1e} | {:.4} | {:.4} | {:.4} |",
                    r.ratio,
                    r.shear_error,
                    r.push_error,
                    r.stick_half_width,
                    r.cattaneo_mindlin,
                    r.spacing
                );
            }
            Some(message) => {
                let message = message.replace('|', "\\|");
                let _ = writeln!(disc_table, "| {} | refused: {message} | | | | |", r.ratio);
            }
        }
    }
    let mut cycle_table = String::new();
    for c in cycles {
        let _ = writeln!(
            cycle_table,
            "| {} | {} | {} | {:.2} | {:.3} | {:.1e} | {:.1e} | {:.1e} |",
            c.meshes,
            c.unknowns,
            c.nodes,
            c.zone_error,
            c.traction_error,
            c.closure_plate,
            c.closure_traction,
            c.masing
        );
    }
    let mut steps = String::new();
    if let Some(c) = cycles.last() {
        let _ = writeln!(steps, "\nSteps of the cycle on {}:\n", c.meshes);
        steps.push_str("| t | branch | Q/(F P) | zone that sticks | analytic | node spacing in the zone | tractions (F p0) | plate x | seconds |\n");
        steps.push_str("|---|---|---|---|---|---|---|---|---|\n");
        for r in &c.rows {
            let _ = writeln!(
                steps,
                "| {:.3} | {} | {:+.2} | {:.4} | {:.4} | {:.4} | {:.3} | {:.4e} | {:.3} |",
                r.time,
                r.branch,
                r.ratio,
                r.stick_half_width,
                r.analytic,
                r.spacing,
                r.traction_error,
                r.plate_x,
                r.seconds
            );
        }
    }
    let mut pushing_table = String::new();
    for (label, value) in pushing {
        let _ = writeln!(pushing_table, "| {label} | {value:.3} |");
    }
    // The template supplies the line break that ends the report.
    let pushing_table = pushing_table
        .strip_suffix('\n')
        .unwrap_or(&pushing_table)
        .to_string();
    crate::common::render(
        "xtask/templates/fretting.md",
        include_str!("../../templates/fretting.md"),
        &[
            ("seconds", format!("{seconds:.0}")),
            ("coefficient", F.to_string()),
            ("young", YOUNG.to_string()),
            ("poisson", POISSON.to_string()),
            ("radius", RADIUS.to_string()),
            ("push", PUSH.to_string()),
            ("table_disc", disc_table),
            ("peak", PEAK.to_string()),
            ("table_cycles", cycle_table),
            ("steps", steps),
            ("proportional_rms", format!("{:.3}", paths.proportional_rms)),
            ("sequential_rms", format!("{:.3}", paths.sequential_rms)),
            ("difference", format!("{:.2}", paths.difference)),
            (
                "frictionless_difference",
                format!("{:.1e}", paths.frictionless_difference),
            ),
            ("table_pushing", pushing_table),
        ],
    )
}

type Plot = Result<String, Failure>;

/// Distinct colours, readable on white.
const COLOURS: [RGBColor; 4] = [
    RGBColor(200, 30, 60),
    RGBColor(40, 150, 60),
    RGBColor(220, 140, 0),
    RGBColor(30, 90, 200),
];

/// Computed dots and analytic lines of several profiles, `q / (F p0)` against `x / a`.
fn profile_svg(title: &str, series: &[Profile], y: std::ops::Range<f64>) -> Plot {
    let mut layers = Vec::new();
    for (k, (label, computed, analytic)) in series.iter().enumerate() {
        let colour = COLOURS[k % COLOURS.len()];
        layers.push(Layer::line(analytic.clone(), Pen::new(colour, 2)).legend(
            format!("{label}: analytic"),
            Glyph::Line(Pen::new(colour, 1)),
        ));
        layers.push(
            Layer::dots(computed.clone(), 3, colour)
                .labelled(format!("{label}: computed (consistent)")),
        );
    }
    let chart = Chart::new(
        Axis::linear("x / a", -1.25..1.25),
        Axis::linear("q / (F p0)", y),
    )
    .caption(title, CAPTION_SIZE)
    .frame(15, (40, 55))
    .light_grid()
    .legend(Some(LegendPosition::LowerRight));
    Ok(chart_svg((900, 600), &chart, &layers)?)
}

/// The hysteresis loop: `Q / (F P)` against the plate's displacement less its stick part
/// `C0 Q` (`C0` the compliance of the first shear step, where nearly the whole interface
/// sticks), one curve per cycle.
fn loop_svg(cycles: &[Cycle]) -> Plot {
    let curves: Vec<Vec<(f64, f64)>> = cycles
        .iter()
        .map(|c| {
            let (x0, r0) = c.loop_curve.first().copied().unwrap_or((0.0, 1.0));
            let compliance = x0 / r0;
            c.loop_curve
                .iter()
                .map(|&(x, r)| (x - compliance * r, r))
                .collect()
        })
        .collect();
    let extent = curves
        .iter()
        .flatten()
        .fold(0.0f64, |m, p| m.max(p.0.abs()))
        * 1.1;
    let mut layers = Vec::new();
    for (k, (c, curve)) in cycles.iter().zip(&curves).enumerate() {
        let colour = COLOURS[k % COLOURS.len()];
        layers.push(
            Layer::line(curve.clone(), Pen::new(colour, 2))
                .legend(c.meshes.clone(), Glyph::Line(Pen::new(colour, 1))),
        );
        layers.push(Layer::dots(curve.clone(), 3, colour));
    }
    let chart = Chart::new(
        Axis::linear(
            "plate displacement in x less C0 Q (the slip part)",
            -extent..extent,
        ),
        Axis::linear("Q / (F P)", -1.0..1.0),
    )
    .caption(
        "Cattaneo-Mindlin cycle on flat blocks: tangential load against the plate's displacement",
        18,
    )
    .frame(15, (40, 55))
    .light_grid()
    .legend(Some(LegendPosition::UpperLeft));
    Ok(chart_svg((900, 600), &chart, &layers)?)
}
