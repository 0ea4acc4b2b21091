//! The shipped example scenes, run through the library entry point the `vem` binary uses
//! (`vem_cli::run`: load, build, solve, write), with their numbers checked against
//! independent expectations: exact uniform states, Hertz's formulas, equilibrium of the
//! reactions and contact forces, the friction laws node by node.

mod common;

use std::path::{Path, PathBuf};

use common::file_names;

use vem_cli::{Outcome, SolvedBody};
use vem_contact::{InterfaceNode, NodeStatus};
use vem_mesh::Point;

/// The shipped scene `name`.
fn scene(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(format!("{name}.toml"))
}

/// Runs the shipped scene `name` into a fresh temporary directory; returns the outcome and
/// the directory.
fn run(name: &str) -> (Outcome, PathBuf) {
    let dir = std::env::temp_dir().join(format!("vem-cli-scene-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let (outcome, files) = vem_cli::run(&scene(name), Some(&dir)).unwrap();
    for file in &files {
        assert!(file.is_file(), "{} was not written", file.display());
    }
    // A shipped scene is written in today's keys and raises no warning.
    assert!(
        outcome.summary.deprecations.is_empty(),
        "{name}: {:?}",
        outcome.summary.deprecations
    );
    for body in &outcome.summary.bodies {
        assert!(body.warnings.is_empty(), "{name}: {:?}", body.warnings);
    }
    if let Some(contact) = &outcome.summary.contact {
        assert!(
            contact.warnings.is_empty(),
            "{name}: {:?}",
            contact.warnings
        );
    }
    (outcome, dir)
}

/// The rows of `contact.csv` (checking its header), as (numbers from `x` on, status).
fn read_contact_csv(dir: &Path) -> Vec<(Vec<f64>, String)> {
    read_contact_csv_with_pairs(dir)
        .into_iter()
        .map(|(_, numbers, status)| (numbers, status))
        .collect()
}

/// The rows of `contact.csv` (checking its header), as (pair, numbers from `x` on, status).
fn read_contact_csv_with_pairs(dir: &Path) -> Vec<(usize, Vec<f64>, String)> {
    let text = std::fs::read_to_string(dir.join("contact.csv")).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "pair,x,y,nx,ny,initial_gap,normal_jump,normal_force,pressure,consistent_pressure,\
         friction_force,consistent_friction_traction,slip,status"
    );
    lines
        .map(|line| {
            let fields: Vec<&str> = line.split(',').collect();
            assert_eq!(fields.len(), 14, "{line}");
            let numbers = fields[1..13].iter().map(|f| f.parse().unwrap()).collect();
            (fields[0].parse().unwrap(), numbers, fields[13].to_string())
        })
        .collect()
}

#[test]
fn contact_csv_names_the_pair_of_every_row() {
    // The two-pair scene of docs/scenes.md ("Several pairs"): two blocks stacked on a rigid
    // line, the upper one pressed by p = 0.1 over a width of 1. Each pair's rows are its own
    // interface (y = 1 between the blocks, y = 0 on the line), and each pair carries the whole
    // load: the sum of its normal forces is p times the width.
    let dir = std::env::temp_dir().join(format!("vem-cli-two-pairs-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("stacked.toml");
    std::fs::write(
        &path,
        r#"title = "Two blocks stacked on a rigid line"
[[body]]
name = "upper"
mesh = { family = "voronoi", rectangle = [[0, 1], [1, 2]], n = 6 }
material = { E = 100.0, nu = 0.3, plane = "strain" }
dirichlet = [{ part = "left", x = 0.0 }]
traction = [{ part = "top", pressure = 0.1 }]
[[body]]
name = "lower"
mesh = { family = "quads", rectangle = [[0, 0], [1, 1]], n = 5 }
material = { E = 100.0, nu = 0.3, plane = "strain" }
dirichlet = [{ part = "left", x = 0.0 }]
[[contact]]
body = "upper"
part = "bottom"
other_body = "lower"
other_part = "top"
law = { name = "tresca", friction_bound = 0.01 }
[[contact]]
body = "lower"
part = "bottom"
obstacle = { line = { point = [0, 0], normal = [0, 1] } }
"#,
    )
    .unwrap();
    let out = dir.join("out");
    let (outcome, _) = vem_cli::run(&path, Some(&out)).unwrap();
    let rows = read_contact_csv_with_pairs(&out);
    let pairs = &outcome.contact.as_ref().unwrap().model.pairs;
    assert_eq!(pairs.len(), 2);
    for (k, pair) in pairs.iter().enumerate() {
        let mine: Vec<&(usize, Vec<f64>, String)> = rows.iter().filter(|r| r.0 == k).collect();
        assert_eq!(mine.len(), pair.nodes.len(), "pair {k}");
        let y = if k == 0 { 1.0 } else { 0.0 };
        assert!(mine.iter().all(|r| (r.1[1] - y).abs() < 1e-12), "pair {k}");
        let load: f64 = mine.iter().map(|r| r.1[6]).sum();
        assert!((load - 0.1).abs() < 1e-8, "pair {k}: {load}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

fn summary_json(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

fn nodes(outcome: &Outcome) -> &[InterfaceNode] {
    &outcome.contact.as_ref().unwrap().nodes
}

fn body<'a>(outcome: &'a Outcome, name: &str) -> &'a SolvedBody {
    outcome.body(name).unwrap()
}

/// Scene 1: two blocks, non-matching meshes (Voronoi on quadrilaterals), uniform pressure
/// p = 2 on the upper block. The exact solution is linear, so the discrete one is exact:
/// sigma_yy = -p everywhere, contact pressure p at every node, resultant p * width; and the
/// displacement of the upper block's top is the sum of the two blocks' uniform strains.
#[test]
fn patch_test_pressure_is_exact_on_non_matching_meshes() {
    let (outcome, dir) = run("patch");
    let p = 2.0;
    let contact = outcome.contact.as_ref().unwrap();
    assert!(
        contact.model.inserted_nodes > 0,
        "the meshes should not match"
    );
    assert_eq!(
        contact.model.tangential_rows, 0,
        "frictionless: no tangential rows"
    );
    for node in nodes(&outcome) {
        assert!((node.pressure - p).abs() < 1e-9, "{node:?}");
        assert_eq!(node.status, NodeStatus::Contact);
    }
    assert!((contact.normal_resultant() - p * 1.0).abs() < 1e-9);
    // Plane strain, sigma_xx = 0, sigma_yy = -p: eps_yy = -p (1 - nu^2) / E,
    // eps_xx = p nu (1 + nu) / E. Upper: E = 200, nu = 0.3; lower: lambda = 60, mu = 40,
    // i.e. E = 104, nu = 0.3. The lower block's bottom is at rest, its top (y = 0) is the
    // upper block's bottom; the rollers are on x = 0.
    let nu: f64 = 0.3;
    let (e_upper, e_lower) = (200.0, 104.0);
    let settlement = -p * (1.0 - nu * nu) / e_lower * 0.5;
    let eps_yy = -p * (1.0 - nu * nu) / e_upper;
    let eps_xx = p * nu * (1.0 + nu) / e_upper;
    let upper = body(&outcome, "upper");
    let mesh = upper.body.mesh();
    for v in mesh.part_vertices("top").unwrap() {
        let x = mesh.vertex(v);
        let u = upper.solution.vertex_displacement(v);
        assert!((u.y - (settlement + eps_yy * 0.5)).abs() < 1e-9, "{x}: {u}");
        assert!((u.x - eps_xx * x.x).abs() < 1e-9, "{x}: {u}");
    }
    // Uniform stress in every element of both bodies.
    for b in &outcome.bodies {
        for f in &b.fields {
            assert!(
                (f.stress[(1, 1)] + p).abs() < 1e-8 && f.stress[(0, 0)].abs() < 1e-8,
                "{f:?}"
            );
        }
    }
    // The files say the same; the stress recovered at the vertices is the uniform one too.
    for body in ["upper", "lower"] {
        let grid = vem_mesh::io::read_vtu(dir.join(format!("{body}.vtu"))).unwrap();
        let nodal = grid
            .point_data
            .iter()
            .find(|a| a.name == "nodal_stress_xx_yy_xy")
            .unwrap();
        for v in 0..grid.points.len() {
            let yy = nodal.values.get_f64(3 * v + 1).unwrap();
            let xx = nodal.values.get_f64(3 * v).unwrap();
            assert!(
                (yy + p).abs() < 1e-8 && xx.abs() < 1e-8,
                "{body} {v}: {xx} {yy}"
            );
        }
    }
    let rows = read_contact_csv(&dir);
    assert_eq!(rows.len(), nodes(&outcome).len());
    assert!(rows
        .iter()
        .all(|(r, s)| (r[7] - p).abs() < 1e-9 && (r[8] - p).abs() < 1e-9 && s == "contact"));
    let summary = summary_json(&dir);
    assert_eq!(summary["contact"]["model"]["tangential_rows"], 0);
    assert_eq!(
        summary["contact"]["model"]["normal_rows"].as_u64().unwrap() as usize,
        rows.len()
    );
}

/// The error indicators of the patch scene: the discrete solution is the exact linear field,
/// so every indicator (residual, jumps, boundary, stabilisation, contact terms) vanishes to
/// round-off against the energy; the `error_indicator` cell field read back from each body's
/// VTU file is the library's, and the summary's estimate is their root sum of squares.
#[test]
fn patch_error_indicators_vanish_and_are_written() {
    let (outcome, dir) = run("patch");
    let estimate = outcome.summary.error_estimate.unwrap();
    let energy: f64 = outcome
        .bodies
        .iter()
        .map(|b| b.solution.strain_energy())
        .sum();
    assert!(energy > 0.0);
    // Squared quantities against the energy: round-off.
    assert!(
        estimate.estimate.powi(2) < 1e-12 * energy,
        "eta = {:e}, energy {energy:e}",
        estimate.estimate
    );
    assert!((estimate.energy_norm - (2.0 * energy).sqrt()).abs() < 1e-12 * energy.sqrt());
    let mut sum = 0.0;
    for b in &outcome.bodies {
        let name = b.body.name();
        assert_eq!(b.error_indicator.len(), b.body.mesh().n_polygons());
        let grid = vem_mesh::io::read_vtu(dir.join(format!("{name}.vtu"))).unwrap();
        let field = grid
            .cell_data
            .iter()
            .find(|a| a.name == "error_indicator")
            .unwrap();
        for (c, &eta) in b.error_indicator.iter().enumerate() {
            let read = field.values.get_f64(c).unwrap();
            assert!(
                read == eta || (read - eta).abs() <= 1e-15 * eta.abs(),
                "{name} cell {c}: {read:e} written, {eta:e} computed"
            );
            sum += eta * eta;
        }
    }
    assert!((sum.sqrt() - estimate.estimate).abs() <= 1e-12 * estimate.estimate.max(1e-300));
    let summary = summary_json(&dir);
    assert!(summary["error_estimate"]["estimate"].as_f64().is_some());
}

/// The adaptive flat punch: converged to its target of 10 % in nine cycles, and every cycle
/// of `adapt.csv` is the cycle of the library's adaptive loop on the same problem
/// (`cargo xtask adaptivity`, docs/adaptivity.md, flat punch: the same initial meshes, theta
/// and refinement give eta = 4.355e-2 at 102 unknowns down to 6.350e-3 at 3378).
#[test]
fn adaptive_punch_meets_its_target_as_the_library_loop() {
    let (outcome, dir) = run("punch_adapt");
    let adapt = outcome.summary.adaptivity.as_ref().unwrap();
    assert!(adapt.converged() && adapt.warning.is_none(), "{adapt:?}");
    let text = std::fs::read_to_string(dir.join("adapt.csv")).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "cycle,unknowns,cells,estimate,relative_estimate,marked,time_s"
    );
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    // docs/adaptivity.md, flat punch, adaptive series: (N, cells, eta).
    let library = [
        (102, 41, 4.355e-2),
        (132, 50, 3.345e-2),
        (196, 71, 2.678e-2),
        (318, 113, 2.175e-2),
        (504, 185, 1.723e-2),
        (806, 311, 1.346e-2),
        (1300, 521, 1.048e-2),
        (2136, 887, 8.194e-3),
        (3378, 1457, 6.350e-3),
    ];
    assert_eq!(rows.len(), library.len(), "{text}");
    for (row, (n, cells, eta)) in rows.iter().zip(library) {
        assert_eq!((row[1] as usize, row[2] as usize), (n, cells), "{text}");
        assert!((row[3] / eta - 1.0).abs() < 1e-3, "{text}");
    }
    let last = rows.last().unwrap();
    assert!(last[4] <= 0.1 && rows[rows.len() - 2][4] > 0.1);
    // The files are the last cycle's: the cells of the VTU files and their indicators.
    let cells: usize = outcome
        .bodies
        .iter()
        .map(|b| {
            let grid = vem_mesh::io::read_vtu(dir.join(format!("{}.vtu", b.body.name()))).unwrap();
            let field = grid
                .cell_data
                .iter()
                .find(|a| a.name == "error_indicator")
                .unwrap();
            assert_eq!(field.values.get_f64(0).unwrap(), b.error_indicator[0]);
            b.error_indicator.len()
        })
        .sum();
    assert_eq!(cells, 1457);
}

/// Scene 2: the half-disc (R = 1, Gmsh) pressed on a block by a prescribed displacement of
/// its flat top. Hertz's plane-strain cylinder on a half-space for the computed load P:
/// a = sqrt(4 P R / (pi E*)), p0 = 2 P / (pi a), E* = E / (2 (1 - nu^2)) for equal materials.
///
/// Tolerances (measured: a +2.3%, p0 +0.7% on the shipped meshes): the half-width is read
/// from node positions with spacing h = 0.01 at the edge of the contact zone, an error of at
/// most h/2 = 4.5% of a ~ 0.11; Hertz's half-space and a << R idealisations add O((a/R)^2) ~ 1%
/// for this block (4 x 2) and a/R = 0.11. Hence 6% for a. The peak pressure is a nodal value
/// at the centre, where the mesh is uniform; the nodal pressures oscillate by a few percent
/// where inserted nodes give short tributary lengths (towards the edges): 4% for p0.
#[test]
fn hertz_half_width_and_peak_pressure() {
    let (outcome, dir) = run("hertz");
    let contact = outcome.contact.as_ref().unwrap();
    let hertz = &outcome.summary.contact.as_ref().unwrap().hertz[0];
    let (e, nu, radius) = (100.0_f64, 0.3_f64, 1.0);
    let e_star = e / (2.0 * (1.0 - nu * nu));
    assert!((hertz.effective_modulus - e_star).abs() < 1e-9 * e_star);
    // P is the total contact force, which the clamp on the disc's top carries.
    let reaction = outcome
        .body("disc")
        .unwrap()
        .solution
        .reaction("top")
        .unwrap();
    let load = contact.force_on_body_a().norm();
    assert!((reaction.norm() - load).abs() < 1e-9 * load);
    assert!((hertz.load - load).abs() < 1e-12 * load);
    let a = (4.0 * load * radius / (std::f64::consts::PI * e_star)).sqrt();
    let p0 = 2.0 * load / (std::f64::consts::PI * a);
    assert!((hertz.half_width / a - 1.0).abs() < 1e-12);
    assert!((hertz.peak_pressure / p0 - 1.0).abs() < 1e-12);
    let computed_a = hertz.computed_half_width;
    let computed_p0 = nodes(&outcome)
        .iter()
        .map(|n| n.pressure)
        .fold(0.0, f64::max);
    assert_eq!(computed_p0, hertz.computed_peak_pressure);
    assert!(
        (computed_a / a - 1.0).abs() < 0.06,
        "a = {computed_a} vs Hertz {a}"
    );
    assert!(
        (computed_p0 / p0 - 1.0).abs() < 0.04,
        "p0 = {computed_p0} vs Hertz {p0}"
    );
    // The contact zone is centred under the disc.
    assert!(hertz.centre[0].abs() < 0.1 * a);
    // The default normal is the flat block's: every contact force is vertical, the normal
    // forces sum to the load and the frictionless answer has no horizontal force.
    let contact = outcome.contact.as_ref().unwrap();
    assert!(nodes(&outcome)
        .iter()
        .all(|n| n.normal == vem_mesh::Vector::new(0.0, -1.0)));
    assert!((contact.normal_resultant() - load).abs() < 1e-12 * load);
    assert!(contact.force_on_body_a().x.abs() < 1e-12 * load);
    // The consistent pressure: its peak within 1% of Hertz's (measured +0.3%).
    let consistent_p0 = nodes(&outcome)
        .iter()
        .map(|n| n.consistent_pressure)
        .fold(0.0, f64::max);
    assert!(
        (consistent_p0 / p0 - 1.0).abs() < 0.01,
        "consistent p0 = {consistent_p0} vs Hertz {p0}"
    );
    let summary = summary_json(&dir);
    assert!(
        summary["contact"]["hertz"][0]["half_width"]
            .as_f64()
            .unwrap()
            > 0.0
    );
    assert!(dir.join("pressure.svg").is_file() && !dir.join("slip.svg").exists());
    // The interface as a dataset of its own: a point per node with its values, a segment
    // between consecutive nodes; one collection opens it with both bodies.
    let interface = vem_mesh::io::read_vtu(dir.join("interface.vtu")).unwrap();
    let nodes = nodes(&outcome);
    assert_eq!(interface.points.len(), nodes.len());
    assert_eq!(interface.cells.len(), nodes.len() - 1);
    let pressure = interface
        .point_data
        .iter()
        .find(|a| a.name == "pressure")
        .unwrap();
    for (k, n) in nodes.iter().enumerate() {
        assert_eq!(pressure.values.get_f64(k), Some(n.pressure));
    }
    let pvd = std::fs::read_to_string(dir.join("results.pvd")).unwrap();
    for file in ["disc.vtu", "block.vtu", "interface.vtu"] {
        assert!(pvd.contains(&format!("file=\"{file}\"")), "{file}");
    }
}

/// Scene 3: a block pressed (p = 0.2) and sheared (top displaced by 0.02) on a foundation,
/// Tresca bound g = 0.1: stick and slip zones; the friction force is the bound on slipping
/// nodes and below it on sticking ones; the reactions balance the contact forces and the load.
#[test]
fn tresca_stick_and_slip_zones_and_equilibrium() {
    let (outcome, dir) = run("tresca");
    let (p, g, width) = (0.2, 0.1, 1.0);
    let contact = outcome.contact.as_ref().unwrap();
    let counts = contact.status_counts();
    let (stick, slip) = (counts.stick, counts.slip);
    assert!(stick > 0 && slip > 0, "stick {stick}, slip {slip}");
    for n in nodes(&outcome) {
        let bound = g * n.tributary_measure;
        match n.status {
            NodeStatus::Slip => {
                assert!((n.friction_t().abs() - bound).abs() < 1e-6 * bound, "{n:?}")
            }
            NodeStatus::Stick => {
                assert!(n.friction_t().abs() < bound * (1.0 + 1e-9), "{n:?}");
                assert!(n.slip_t().abs() < 1e-8, "{n:?}");
            }
            NodeStatus::Open => assert!(n.normal_force.abs() < 1e-7),
            NodeStatus::Contact => panic!("a Tresca node is stick or slip: {n:?}"),
        }
        // Friction opposes the slip.
        assert!(n.friction_t() * n.slip_t() <= 1e-14, "{n:?}");
    }
    // Equilibrium of the block: contact force + reaction of the top + applied pressure = 0.
    let force = contact.force_on_body_a();
    let top = body(&outcome, "block").solution.reaction("top").unwrap();
    assert!((force.x + top.x).abs() < 1e-9);
    assert!((force.y - p * width).abs() < 1e-9);
    // ... and of the foundation: its support carries what the block exerts on it.
    let bottom = body(&outcome, "foundation")
        .solution
        .reaction("bottom")
        .unwrap();
    assert!((bottom - force).norm() < 1e-9);
    let rows = read_contact_csv(&dir);
    let statuses: Vec<&str> = rows.iter().map(|(_, s)| s.as_str()).collect();
    assert!(statuses.contains(&"stick") && statuses.contains(&"slip"));
    assert!(dir.join("slip.svg").is_file());
    assert_eq!(
        summary_json(&dir)["contact"]["model"]["tangential_rows"]
            .as_u64()
            .unwrap() as usize,
        rows.len()
    );
}

/// Scene 4: a block pressed (p = 0.5) on the rigid line y = 0: uniform pressure equal to the
/// applied one at every node; one body, nothing meshed for the line.
#[test]
fn signorini_block_on_a_rigid_line() {
    let (outcome, dir) = run("signorini");
    let p = 0.5;
    assert_eq!(outcome.bodies.len(), 1, "the obstacle is not a body");
    let contact = outcome.contact.as_ref().unwrap();
    assert!(contact.model.pairs[0].obstacle);
    assert_eq!(contact.model.inserted_nodes, 0);
    assert_eq!(contact.model.tangential_rows, 0);
    let block = body(&outcome, "block");
    let bottom = block.body.mesh().part_vertices("bottom").unwrap();
    assert_eq!(contact.model.normal_rows, bottom.len());
    for n in nodes(&outcome) {
        assert!((n.pressure / p - 1.0).abs() < 1e-6, "{n:?}");
        assert!(n.normal_jump.abs() < 1e-8);
    }
    assert!((contact.normal_resultant() - p * 2.0).abs() < 1e-6);
    // Only the block's mesh is written (the obstacle has none), with the interface.
    let mut vtus: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| {
            let name = e.unwrap().file_name().to_string_lossy().into_owned();
            name.ends_with(".vtu").then_some(name)
        })
        .collect();
    vtus.sort();
    assert_eq!(vtus, ["block.vtu", "interface.vtu"]);
    assert_eq!(
        summary_json(&dir)["contact"]["model"]["pairs"][0]["obstacle"],
        true
    );
}

/// Scene 5: the Hertz geometry with a tangential displacement of the disc and Coulomb
/// friction F = 0.3: the fixed point converges; |friction| <= F * normal force at every node;
/// the contact zone sticks in the middle and slips at both edges.
#[test]
fn coulomb_fixed_point_with_slip_at_the_edges() {
    let (outcome, _dir) = run("coulomb");
    let f = 0.3;
    let contact = outcome.contact.as_ref().unwrap();
    let fixed_point = contact.fixed_point.as_ref().unwrap();
    assert!(fixed_point.residual <= 1e-8, "{fixed_point:?}");
    // The fixed point of k Tresca solves runs on one discretisation: one assembly, one
    // symbolic analysis and one numeric factorisation per body, whatever k (the default
    // solver condenses onto the interface); the counters are in summary.json.
    let work = &outcome.summary().contact.as_ref().unwrap().work;
    assert!(fixed_point.steps > 2, "{fixed_point:?}");
    assert_eq!(work.assemblies, 2, "{work:?}");
    assert_eq!(work.symbolic_analyses, 2, "{work:?}");
    assert_eq!(work.numeric_factorisations, 2, "{work:?}");
    let nodes = nodes(&outcome);
    let largest = nodes.iter().map(|n| n.normal_force).fold(0.0, f64::max);
    // The bounds are F times the normal forces of the previous step, which differ from the
    // final ones by at most the fixed-point residual times the largest normal force.
    let slack = 2.0 * fixed_point.residual * largest + 1e-10 * largest;
    for n in nodes {
        assert!(n.friction_t().abs() <= f * n.normal_force + slack, "{n:?}");
        if n.status == NodeStatus::Slip {
            assert!(
                (n.friction_t().abs() - f * n.normal_force).abs()
                    <= slack + 1e-6 * f * n.normal_force,
                "{n:?}"
            );
        }
    }
    let active: Vec<&InterfaceNode> = nodes
        .iter()
        .filter(|n| n.status != NodeStatus::Open)
        .collect();
    let (first, last) = (active[0], active[active.len() - 1]);
    assert_eq!(first.status, NodeStatus::Slip);
    assert_eq!(last.status, NodeStatus::Slip);
    // The node of largest pressure (the centre) sticks, and the stick zone is one interval.
    let centre = active
        .iter()
        .max_by(|a, b| a.pressure.total_cmp(&b.pressure))
        .unwrap();
    assert_eq!(centre.status, NodeStatus::Stick);
    assert!(centre.position.x.abs() < 0.02);
    let stick: Vec<Point> = active
        .iter()
        .filter(|n| n.status == NodeStatus::Stick)
        .map(|n| n.position)
        .collect();
    let (lo, hi) = (stick[0].x, stick[stick.len() - 1].x);
    // Between the outermost stick nodes every node sticks, except a node whose partner of a
    // close pair (the two sides' nodes less than 1e-3 apart, a tenth of the spacing) sticks:
    // such a pair shares its force unevenly, and one of the two can reach its bound.
    let close_partner_sticks = |x: f64| {
        stick
            .iter()
            .any(|s| (s.x - x).abs() < 1e-3 && (s.x - x).abs() > 0.0)
    };
    assert!(active
        .iter()
        .filter(|n| n.position.x > lo && n.position.x < hi)
        .all(|n| n.status == NodeStatus::Stick || close_partner_sticks(n.position.x)));
    // The tangential load is below the sliding capacity F P.
    let force = contact.force_on_body_a();
    assert!(force.x.abs() < f * force.y);
    let top = body(&outcome, "disc").solution.reaction("top").unwrap();
    assert!((force + top).norm() < 1e-8 * force.norm());
}

/// The element key: the patch scene is solved exactly by every element of the registry that
/// takes its polygons (the D-recipe, shear-scaled and locking-free VEM), and a P1 element on polygons it
/// cannot take is refused before assembly, naming the body and the element.
#[test]
fn element_key_selects_a_registered_element() {
    let path = scene("patch");
    let source = std::fs::read_to_string(&path).unwrap();
    for element in ["vem1-drecipe", "vem1-shear", "vem1-bbar"] {
        let text = source.replacen(
            "[[body]]\nname = \"upper\"",
            &format!("[[body]]\nname = \"upper\"\nelement = \"{element}\""),
            1,
        );
        assert_ne!(text, source, "the patch scene names its upper body 'upper'");
        let parsed = vem_cli::Scene::parse(&path, text).unwrap();
        let outcome = vem_cli::Model::build(&parsed).unwrap().solve().unwrap();
        for node in nodes(&outcome) {
            assert!((node.pressure - 2.0).abs() < 1e-9, "{element}: {node:?}");
        }
    }
    let text = source.replacen(
        "[[body]]\nname = \"upper\"",
        "[[body]]\nname = \"upper\"\nelement = \"p1\"",
        1,
    );
    let parsed = vem_cli::Scene::parse(&path, text).unwrap();
    let error = vem_cli::Model::build(&parsed).unwrap_err().chain();
    assert!(error.contains("p1") && error.contains("upper"), "{error}");
    let text = source.replacen(
        "[[body]]\nname = \"upper\"",
        "[[body]]\nname = \"upper\"\nelement = \"vem2\"",
        1,
    );
    let parsed = vem_cli::Scene::parse(&path, text).unwrap();
    let error = vem_cli::Model::build(&parsed).unwrap_err().to_string();
    assert!(
        error.contains("vem1-drecipe") && error.contains(":"),
        "{error}"
    );
}

/// The Hertz scene under force control: the disc's top is a rigid plate pushed down with
/// 0.5. The load P of the summary (the contact force on the disc along y) is the prescribed
/// resultant, which is the plate's reaction and the block's support reaction; the half-width
/// follows Hertz's formula for that load as in the displacement-controlled scene; the plate's
/// descent is the same at every vertex of the top.
#[test]
fn hertz_under_force_control_carries_the_prescribed_load() {
    let (outcome, dir) = run("hertz_force");
    let load = 0.5;
    let summary = outcome.summary.contact.as_ref().unwrap();
    assert!(
        (summary.resultants.force_on_body_a[1] - load).abs() < 1e-9 * load,
        "{}",
        summary.resultants.force_on_body_a[1]
    );
    let disc = body(&outcome, "disc");
    let plate = disc.solution.reaction("top").unwrap();
    assert!((plate.y + load).abs() < 1e-12 * load, "{plate}");
    let support = body(&outcome, "block").solution.reaction("bottom").unwrap();
    assert!((support.y - load).abs() < 1e-9 * load, "{support}");
    let mesh = disc.body.mesh();
    let top = mesh.part_vertices("top").unwrap();
    let w = disc.solution.vertex_displacement(top[0]).y;
    assert!(w < 0.0);
    for &v in &top {
        assert_eq!(disc.solution.vertex_displacement(v).y, w);
    }
    let hertz = &summary.hertz[0];
    assert!((hertz.load - load).abs() < 1e-6 * load);
    assert!((hertz.computed_half_width / hertz.half_width - 1.0).abs() < 0.06);
    let json = summary_json(&dir);
    assert!(
        (json["contact"]["resultants"]["force_on_body_a"][1]
            .as_f64()
            .unwrap()
            - load)
            .abs()
            < 1e-9 * load
    );
    let reactions = json["bodies"][0]["reactions"].as_array().unwrap();
    assert!(reactions.iter().any(|r| r["rigid_plate"] == true));
}

/// Scene 6: Cattaneo-Mindlin. The Hertz half-disc pressed and sheared below full slip with
/// Coulomb friction F = 0.3 and identical materials: the stick zone is one interval around the
/// centre whose half-width is `c = a sqrt(1 - Q/(F P))` (a the computed contact half-width)
/// within one node spacing; the forces act along the flat block's normal (`normal =
/// "body_b"`), so Q and P are the horizontal and vertical resultants.
#[test]
fn cattaneo_mindlin_stick_zone() {
    let (outcome, dir) = run("cattaneo_mindlin");
    let f = 0.3;
    let contact = outcome.contact.as_ref().unwrap();
    let force = contact.force_on_body_a();
    let (p, q) = (force.y, force.x.abs());
    assert!((contact.normal_resultant() - p).abs() < 1e-12 * p);
    let ratio = q / (f * p);
    assert!(ratio > 0.2 && ratio < 0.8, "Q/(F P) = {ratio}");
    let nodes = nodes(&outcome);
    // Half-length of the run of nodes with `inside` around the centre, ends halfway to the
    // next node, and the node spacing there.
    let zone = |inside: &dyn Fn(&InterfaceNode) -> bool| {
        let centre = (0..nodes.len())
            .filter(|&i| inside(&nodes[i]))
            .min_by(|&i, &j| {
                nodes[i]
                    .position
                    .x
                    .abs()
                    .total_cmp(&nodes[j].position.x.abs())
            })
            .unwrap();
        let (mut first, mut last) = (centre, centre);
        while inside(&nodes[first - 1]) {
            first -= 1;
        }
        while inside(&nodes[last + 1]) {
            last += 1;
        }
        let x = |i: usize| nodes[i].position.x;
        let half = 0.25 * (x(last) + x(last + 1) - x(first) - x(first - 1));
        (half, (x(first) - x(first - 1)).max(x(last + 1) - x(last)))
    };
    let (a, _) = zone(&|n| n.status != NodeStatus::Open);
    let (c, spacing) = zone(&|n| n.status == NodeStatus::Stick);
    let expected = a * (1.0 - ratio).sqrt();
    assert!(
        (c - expected).abs() <= spacing.max(0.01),
        "c = {c}, a sqrt(1 - Q/(F P)) = {expected}, spacing {spacing}"
    );
    // Every stick node is inside the stick zone (one interval).
    let sticking = nodes
        .iter()
        .filter(|n| n.status == NodeStatus::Stick)
        .count();
    assert!(sticking > 2);
    assert!(dir.join("slip.svg").is_file());
    // pressure.svg draws Cattaneo-Mindlin's traction for this load: its legend gives F, the
    // ratio and the stick half-width c = a sqrt(1 - Q/(F P)) of Hertz's a.
    let plot = std::fs::read_to_string(dir.join("pressure.svg")).unwrap();
    let legend = plot
        .split(['<', '>'])
        .map(str::trim)
        .find(|t| t.starts_with("Cattaneo-Mindlin: F = 0.3, Q/(F P) = "))
        .unwrap_or_else(|| panic!("no Cattaneo-Mindlin legend"));
    let number = |key: &str| -> f64 {
        let rest = &legend[legend.find(key).unwrap() + key.len()..];
        rest.split([',', ' ']).next().unwrap().parse().unwrap()
    };
    let hertz = &outcome.summary.contact.as_ref().unwrap().hertz[0];
    let hertz_ratio = q / (f * hertz.load);
    assert!(
        (number("Q/(F P) = ") / hertz_ratio - 1.0).abs() < 1e-3,
        "{legend}"
    );
    let c = hertz.half_width * (1.0 - hertz_ratio).sqrt();
    assert!(
        (number("stick zone c = ") / c - 1.0).abs() < 1e-3,
        "{legend}"
    );
}

/// A penalty answer that penetrates is marked on the deformed picture, one cross per
/// penetrating node, the deepest penetration in the legend; the obstacle (a line 0.002 below
/// the block) is moved by the magnified gap; an exact answer has no marks.
#[test]
fn deformed_picture_marks_penetration() {
    let dir = std::env::temp_dir().join(format!("vem-cli-penetration-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(scene("signorini"))
        .unwrap()
        .replace("point = [0.0, 0.0]", "point = [0.0, -0.002]");
    let marks_of = |name: &str, solver: &str| {
        let path = dir.join(format!("{name}.toml"));
        std::fs::write(&path, format!("{solver}\n{text}")).unwrap();
        let out = dir.join(name);
        let (outcome, _) = vem_cli::run(&path, Some(&out)).unwrap();
        let svg = std::fs::read_to_string(out.join("deformed.svg")).unwrap();
        let document = roxmltree::Document::parse(&svg).unwrap();
        let crosses = document
            .descendants()
            .filter(|n| n.has_tag_name("g") && n.attribute("class") == Some("marks"))
            .map(|g| g.children().filter(|n| n.has_tag_name("path")).count())
            .sum::<usize>();
        let notes: Vec<String> = document
            .descendants()
            .filter(|n| n.attribute("class") == Some("note"))
            .map(|n| n.text().unwrap().to_string())
            .collect();
        (outcome, crosses, notes)
    };
    let (outcome, crosses, notes) = marks_of(
        "penalty",
        "solver = { name = \"penalty\", penalty = { factor = 1 } }",
    );
    let largest = outcome
        .bodies
        .iter()
        .flat_map(|b| b.solution.vertex_displacements())
        .map(|u| u.norm())
        .fold(0.0, f64::max);
    let penetrating = nodes(&outcome)
        .iter()
        .filter(|n| n.normal_jump - n.initial_gap > 1e-3 * largest)
        .count();
    assert!(penetrating > 0);
    assert_eq!(crosses, penetrating);
    assert_eq!(notes[0], "displacements drawn x 20");
    assert_eq!(notes[2], "obstacle moved by 19 x gap");
    let (_, crosses, _) = marks_of("exact", "");
    assert_eq!(crosses, 0);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Scene 9: the fretting cycle, a load history. The disc is pressed, then moved sideways to
/// +d, -d and +d again with Coulomb friction. At every step the tangential force stays within
/// the friction capacity F times the normal load; at the same displacement the force depends
/// on the way the disc came (the hysteresis loop): back at 0 after +d the friction pushes
/// towards +x, after -d towards -x; the cycle is symmetric. Every step is written (the
/// ParaView series lists them at their times).
#[test]
fn fretting_cycle_is_a_hysteresis_loop() {
    let (outcome, dir) = run("fretting");
    let f = 0.3;
    let steps = &outcome.summary.contact.as_ref().unwrap().history;
    assert_eq!(steps.len(), 14);
    assert_eq!(outcome.steps.len(), 13);
    let at = |t: f64| steps.iter().find(|s| s.time == t).unwrap();
    for s in steps {
        let (q, p) = (s.force_on_body_a[0], s.force_on_body_a[1]);
        assert!((p - s.normal_resultant).abs() < 1e-12 * p, "{s:?}");
        assert!(q.abs() <= f * p * (1.0 + 1e-9), "{s:?}");
    }
    // The displacement of the top: the prescribed one.
    assert!((at(3.0).displacement[0] - 0.002).abs() < 1e-15);
    assert!(at(4.0).displacement[0].abs() < 1e-15);
    // At u_x = 0 after +d and after -d: opposite friction forces, a loop.
    let (after_plus, after_minus) = (at(4.0).force_on_body_a[0], at(6.0).force_on_body_a[0]);
    assert!(
        after_plus > 0.0 && after_minus < 0.0,
        "{after_plus:e} {after_minus:e}"
    );
    // The extremes are symmetric, and reloading to +d meets the first loading at +d.
    let (plus, minus) = (at(3.0).force_on_body_a[0], at(5.0).force_on_body_a[0]);
    assert!(
        (plus + minus).abs() < 0.01 * plus.abs(),
        "{plus:e} {minus:e}"
    );
    let again = at(7.0).force_on_body_a[0];
    assert!(
        (again - plus).abs() < 0.01 * plus.abs(),
        "{again:e} {plus:e}"
    );
    // Files: one time series of both bodies and the interface over every step, a contact
    // table per step, the curves.
    let pvd = std::fs::read_to_string(dir.join("results.pvd")).unwrap();
    assert_eq!(pvd.matches("<DataSet ").count(), 3 * 14);
    for file in ["disc_0014.vtu", "block_0001.vtu", "interface_0007.vtu"] {
        assert!(pvd.contains(&format!("file=\"{file}\"")), "{file}");
        assert!(dir.join(file).is_file(), "{file}");
    }
    assert!(pvd.contains("timestep=\"0.5\""));
    assert!(dir.join("contact_0014.csv").is_file() && dir.join("history.svg").is_file());
    let history = std::fs::read_to_string(dir.join("history.csv")).unwrap();
    assert_eq!(history.lines().count(), 15);
}

/// The L-shaped bracket meshed on its polygon: the cells tile the polygon (area 1.75), the
/// parts named after its edges have their edges' lengths, the strip cut out of "inner" by a
/// box lies on the arm's upper face, and the clamp's reaction balances the end load and the
/// strip's pressure.
#[test]
fn bracket_on_a_polygon_balances_its_loads() {
    let (outcome, _dir) = run("bracket");
    let bracket = body(&outcome, "bracket");
    let mesh = bracket.body.mesh();
    let area: f64 = (0..mesh.n_polygons()).map(|p| mesh.area(p)).sum();
    assert!((area - 1.75).abs() < 1e-12 * 1.75, "{area}");
    let length = |part: &str| -> f64 {
        mesh.part(part)
            .unwrap()
            .edges
            .iter()
            .map(|&e| {
                let [a, b] = mesh.edge(e).vertices;
                (mesh.vertex(b) - mesh.vertex(a)).norm()
            })
            .sum()
    };
    for (part, expected) in [
        ("bottom", 2.0),
        ("end", 0.5),
        ("inner", 3.0),
        ("top", 0.5),
        ("back", 2.0),
    ] {
        assert!((length(part) - expected).abs() < 1e-12, "{part}");
    }
    let strip = length("strip");
    assert!(strip > 0.25 && strip <= 0.4 + 1e-12, "{strip}");
    for v in mesh.part_vertices("strip").unwrap() {
        let p = mesh.vertex(v);
        assert!(
            (p.y - 0.5).abs() < 1e-12 && (1.2..=1.6).contains(&p.x),
            "{p}"
        );
    }
    // Loads: (0, -1) on the end (length 0.5), pressure 0.5 on the strip (outward normal +y).
    let reaction = bracket.solution.reaction("top").unwrap();
    let expected = 0.5 + 0.5 * strip;
    assert!(reaction.x.abs() < 1e-10, "{reaction}");
    assert!(
        (reaction.y - expected).abs() < 1e-10 * expected,
        "{reaction}"
    );
}

/// The shipped scene `name` with `output` appended (an `[output]` table; its mesh files found
/// where the scene is) run into a fresh directory of its own, `label` (tests run side by side
/// in one process); returns the outcome and the directory.
fn run_with_output(name: &str, output: &str, label: &str) -> (Outcome, PathBuf) {
    let dir = std::env::temp_dir().join(format!("vem-cli-output-{label}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let scenes = scene(name).parent().unwrap().display().to_string();
    let text = std::fs::read_to_string(scene(name))
        .unwrap()
        .replace("file = \"", &format!("file = \"{scenes}/"));
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, format!("{text}\n[output]\n{output}\n")).unwrap();
    let out = dir.join("out");
    let (outcome, _) = vem_cli::run(&path, Some(&out)).unwrap();
    (outcome, out)
}

/// `[output] files` and `vtu_encoding` change what is written, not what it says: the tables
/// of a run that writes only them are the full run's byte for byte, and the `.vtu` files as
/// text hold the values of the binary ones bit for bit.
#[test]
fn output_files_and_encoding_change_the_files_not_the_results() {
    let (_, full) = run_with_output("signorini", "", "signorini-full");
    assert_eq!(
        file_names(&full),
        [
            "block.vtu",
            "contact.csv",
            "deformed.svg",
            "interface.vtu",
            "pressure.svg",
            "results.pvd",
            "summary.json"
        ]
    );
    let (_, csv) = run_with_output("signorini", "files = [\"csv\"]", "csv");
    assert_eq!(file_names(&csv), ["contact.csv", "summary.json"]);
    let read = |dir: &Path, file: &str| std::fs::read(dir.join(file)).unwrap();
    assert_eq!(read(&csv, "contact.csv"), read(&full, "contact.csv"));
    let (_, none) = run_with_output("signorini", "files = []", "none");
    assert_eq!(file_names(&none), ["summary.json"]);
    for encoding in ["ascii", "compressed"] {
        let (_, text) = run_with_output(
            "signorini",
            &format!("files = [\"vtu\"]\nvtu_encoding = \"{encoding}\""),
            encoding,
        );
        assert_eq!(
            file_names(&text),
            ["block.vtu", "interface.vtu", "results.pvd", "summary.json"]
        );
        for file in ["block.vtu", "interface.vtu"] {
            assert_encoded(&text, &full, file, encoding);
        }
    }
    assert!(String::from_utf8_lossy(&read(&full, "block.vtu")).contains("encoding=\"raw\""));
    // A load history: the tables of every step, without the step's .vtu files or the curves.
    let (_, full) = run_with_output("fretting", "", "fretting-full");
    let (_, csv) = run_with_output("fretting", "files = [\"csv\"]", "fretting");
    let mut expected = vec!["contact.csv".to_string()];
    expected.extend((1..=14).map(|k| format!("contact_{k:04}.csv")));
    expected.extend(["history.csv".to_string(), "summary.json".to_string()]);
    assert_eq!(file_names(&csv), expected);
    for file in ["contact_0007.csv", "history.csv"] {
        assert_eq!(read(&csv, file), read(&full, file), "{file}");
    }
    // The same history's .vtu files as text: every step's hold the binary ones' values.
    let (_, text) = run_with_output(
        "fretting",
        "files = [\"vtu\"]\nvtu_encoding = \"ascii\"",
        "fretting-ascii",
    );
    assert!(!text.join("history.csv").exists() && !text.join("history.svg").exists());
    for file in ["disc_0007.vtu", "block_0014.vtu", "interface_0007.vtu"] {
        assert_encoded(&text, &full, file, "ascii");
    }
    // In space: the body's file as text holds the binary one's values.
    let (_, full) = run_with_output("block3d", "", "block3d-full");
    let (_, text) = run_with_output("block3d", "vtu_encoding = \"ascii\"", "block3d");
    assert_eq!(file_names(&text), file_names(&full));
    assert_encoded(&text, &full, "block.vtu", "ascii");
}

/// `file` of `dir` is written in `encoding` (`"ascii"` or `"compressed"`) and holds the values
/// of the same file of `reference` (another encoding), bit for bit.
fn assert_encoded(dir: &Path, reference: &Path, file: &str, encoding: &str) {
    let bytes = std::fs::read(dir.join(file)).unwrap();
    let written = String::from_utf8_lossy(&bytes);
    let marker = match encoding {
        "ascii" => "format=\"ascii\"",
        _ => "compressor=\"vtkZLibDataCompressor\"",
    };
    assert!(written.contains(marker), "{file}: no {marker}");
    if encoding == "ascii" {
        assert!(!written.contains("AppendedData"), "{file}");
    }
    let grid = |dir: &Path| vem_mesh::io::read_vtu(dir.join(file)).unwrap();
    assert_eq!(grid(dir), grid(reference), "{encoding} {file}");
}
