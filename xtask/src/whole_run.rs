//! The "whole run" rows of `cargo xtask bench`: a scene from its mesh files to every output
//! written, the path `vem run` takes (`Scene::load`, `Model::build`, `Model::solve`,
//! `Outcome::write` of `vem_cli`), stage by stage, against one sparse Cholesky (analyse,
//! factorise, solve) of the same stiffness matrices.
//!
//! Every repetition runs in a child process (`cargo xtask bench-whole`), so that its peak
//! memory (`VmHWM`) and its fresh memory belong to that run alone, and its reference in
//! another (`--reference`: the scene built and discretised as the whole run does it, then the
//! Cholesky timed), so that both start from the same state of a fresh process (memory a
//! process touches for the first time costs several times what it costs again); the report
//! gives the median of every figure over the repetitions.
//!
//! The bench's own case is Hertz-like: a block (0,1) x (0,1) of structured triangles with a
//! parabolic initial gap (an indenter of radius 1 over x = 1/2), its top pushed down by 0.02,
//! on a block (0,1) x (-1,0) of structured quadrilaterals 1.25 times finer across
//! (non-matching), frictionless, E = 100, nu = 0.3, plane strain. Both meshes are written as
//! MSH 4.1 ASCII files with their vertices and elements numbered in a shuffled order (a mesh
//! generator's numbering is not a spatial one), and the scene file beside them; a user's scene
//! (`--scene`) is run as it is.

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Arc;
use std::time::Instant;

use serde::{Deserialize, Serialize};
use vem_elastic::{CholeskySettings, CholeskySolver, LinearSolver};
use vem_mesh::generators::{structured_quads, structured_triangles, Rectangle};
use vem_mesh::{Mesh, Point};

use crate::common::{chain, peak_memory, seconds};

/// Options of the hidden `cargo xtask bench-whole` (one whole run, one JSON line).
#[derive(Debug, clap::Args)]
pub struct BenchWholeArgs {
    /// Approximate number of unknowns of the bench's own case (ignored with `--scene`).
    #[arg(long, default_value_t = 10_000)]
    unknowns: usize,
    /// A scene file to run instead of the bench's own case.
    #[arg(long)]
    scene: Option<PathBuf>,
    /// The folder of the bench's own meshes and scene (made when missing) and of the outputs.
    #[arg(long)]
    dir: PathBuf,
    /// Measure the reference Cholesky instead of the whole run: the scene built and its
    /// stiffness matrices assembled as the whole run assembles them (untimed), then analysed,
    /// factorised and solved.
    #[arg(long)]
    reference: bool,
}

/// One whole run. Times in seconds, sizes in bytes.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct WholeRun {
    /// "hertz-gmsh" (the bench's own case) or the scene file.
    pub case: String,
    /// The unknowns asked for (0 for a scene).
    pub target_unknowns: usize,
    /// Free unknowns of the bodies solved (with the interface nodes).
    pub unknowns: usize,
    /// Bytes of the mesh files read.
    pub mesh_bytes: u64,
    /// Scene file and mesh files read, meshes built and validated.
    pub read: f64,
    /// The rest of `Model::build`: the scene checked, bodies, contact pairs, solver.
    pub build: f64,
    /// Interface node insertion and assembly (the summary's `assembly`).
    pub assembly: f64,
    /// The contact solve (the summary's `solve`).
    pub solve: f64,
    /// Element stresses, quality figures, the contact answer's forces, tractions and
    /// warnings (the summary's `post`).
    pub post: f64,
    /// The residual error estimate (the summary's `estimate`): post-processing too, shown
    /// apart.
    #[serde(default)]
    pub estimate: f64,
    /// Every output file written (`Outcome::write`).
    pub output: f64,
    /// From the start to the last file written.
    pub whole: f64,
    /// What the named stages leave of the whole run (the rest of `Model::solve`: load
    /// history, summary, freeing the model).
    pub other: f64,
    /// Bytes written.
    pub written_bytes: u64,
    /// VmHWM after `Model::build`, after `Model::solve`, after `Outcome::write`.
    pub peak_build: u64,
    pub peak_solve: u64,
    pub peak_output: u64,
    /// The reference: every body on its solved mesh alone, its stiffness analysed, factorised
    /// and solved once by `CholeskySolver` with the default settings.
    pub reference_analyse: f64,
    pub reference_factorise: f64,
    pub reference_solve: f64,
    /// Bytes of the stiffness matrices (values, row indices, column pointers) and of the
    /// Cholesky factors' values of the reference.
    pub stiffness_bytes: u64,
    pub factor_bytes: u64,
    /// The solve's status, or the failure.
    pub status: String,
    pub error: Option<String>,
}

impl WholeRun {
    /// One Cholesky of the reference: analyse + factorise + solve.
    pub fn cholesky(&self) -> f64 {
        self.reference_analyse + self.reference_factorise + self.reference_solve
    }

    /// Whole run / one Cholesky.
    pub fn ratio(&self) -> f64 {
        self.whole / self.cholesky()
    }
}

/// The size parameter n of the bench's own case for about `unknowns` unknowns: (n + 1)^2
/// vertices above, (1.25 n + 1)^2 below, two unknowns each.
fn size_for(unknowns: usize) -> usize {
    ((unknowns as f64 / (2.0 * (1.0 + 1.25 * 1.25)))
        .sqrt()
        .round() as usize)
        .max(2)
}

/// The scene of the bench's own case, relative to its meshes.
const SCENE: &str = r#"title = "Hertz-like whole run: triangles with a parabolic gap (R = 1) pressed on quadrilaterals"

[[body]]
name = "indenter"
mesh = { file = "indenter.msh" }
material = { E = 100.0, nu = 0.3, plane = "strain" }
dirichlet = [{ part = "top", x = 0.0, y = -0.02 }]

[[body]]
name = "block"
mesh = { file = "block.msh" }
material = { E = 100.0, nu = 0.3, plane = "strain" }
dirichlet = [{ part = "bottom", x = 0.0, y = 0.0 }]

[[contact]]
body = "indenter"
part = "bottom"
other_body = "block"
other_part = "top"
law = "frictionless"
imposed_gap = "0.5 * (x - 0.5)^2"
hertz = { radius = 1.0 }
"#;

/// Writes the meshes and the scene of the bench's own case into `dir` (unless a run wrote
/// them already) and returns the scene file.
fn own_case(dir: &Path, unknowns: usize) -> Result<PathBuf, Box<dyn std::error::Error>> {
    let scene = dir.join("hertz.toml");
    if scene.is_file() {
        return Ok(scene);
    }
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let n = size_for(unknowns);
    let m = ((1.25 * n as f64).round() as usize).max(1);
    let upper = Rectangle::new(Point::new(0.0, 0.0), Point::new(1.0, 1.0));
    let lower = Rectangle::new(Point::new(0.0, -1.0), Point::new(1.0, 0.0));
    write_msh(
        &dir.join("indenter.msh"),
        &structured_triangles(&upper, n, n)?,
        1,
    )?;
    write_msh(&dir.join("block.msh"), &structured_quads(&lower, m, m)?, 2)?;
    std::fs::write(&scene, SCENE).map_err(|e| format!("cannot write {}: {e}", scene.display()))?;
    Ok(scene)
}

/// A permutation of 0..n from `seed` (Fisher-Yates with splitmix64).
fn shuffled(n: usize, seed: u64) -> Vec<usize> {
    let mut state = seed;
    let mut next = || {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    };
    let mut order: Vec<usize> = (0..n).collect();
    for i in (1..n).rev() {
        let j = (next() % (i as u64 + 1)) as usize;
        order.swap(i, j);
    }
    order
}

/// `mesh` as an MSH 4.1 ASCII file: every vertex in the surface, one curve per boundary part
/// (physical curve of the part's name) with its edges as 2-node lines, the surface (physical
/// surface "body") with its triangles and quadrilaterals; vertices and elements in a shuffled
/// order (`seed`).
fn write_msh(path: &Path, mesh: &Mesh, seed: u64) -> Result<(), Box<dyn std::error::Error>> {
    let n_vertices = mesh.n_vertices();
    // Vertex v gets the tag tag[v]; the vertices are listed in the order of their tags.
    let order = shuffled(n_vertices, seed);
    let mut tag = vec![0usize; n_vertices];
    for (k, &v) in order.iter().enumerate() {
        tag[v] = k + 1;
    }
    let parts = mesh.parts();
    let mut out = String::with_capacity(64 * n_vertices + 48 * mesh.n_polygons());
    out.push_str("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n");
    writeln!(out, "{}", parts.len() + 1)?;
    for (k, part) in parts.iter().enumerate() {
        writeln!(out, "1 {} \"{}\"", k + 1, part.name)?;
    }
    writeln!(out, "2 {} \"body\"\n$EndPhysicalNames", parts.len() + 1)?;
    let (lo, hi) = mesh.vertices().iter().fold(
        (
            Point::new(f64::MAX, f64::MAX),
            Point::new(f64::MIN, f64::MIN),
        ),
        |(lo, hi), p| {
            (
                Point::new(lo.x.min(p.x), lo.y.min(p.y)),
                Point::new(hi.x.max(p.x), hi.y.max(p.y)),
            )
        },
    );
    let bbox = format!("{} {} 0 {} {} 0", lo.x, lo.y, hi.x, hi.y);
    writeln!(out, "$Entities\n0 {} 1 0", parts.len())?;
    for k in 0..parts.len() {
        writeln!(out, "{} {bbox} 1 {} 0", k + 1, k + 1)?;
    }
    write!(out, "1 {bbox} 1 {} {}", parts.len() + 1, parts.len())?;
    for k in 0..parts.len() {
        write!(out, " {}", k + 1)?;
    }
    out.push_str("\n$EndEntities\n$Nodes\n");
    writeln!(out, "1 {n_vertices} 1 {n_vertices}\n2 1 0 {n_vertices}")?;
    for k in 1..=n_vertices {
        writeln!(out, "{k}")?;
    }
    for &v in &order {
        let p = mesh.vertex(v);
        writeln!(out, "{:?} {:?} 0", p.x, p.y)?;
    }
    out.push_str("$EndNodes\n$Elements\n");
    let lines: usize = parts.iter().map(|p| p.edges.len()).sum();
    let polygons = shuffled(mesh.n_polygons(), seed + 100);
    let triangles: Vec<usize> = polygons
        .iter()
        .copied()
        .filter(|&p| mesh.polygon(p).len() == 3)
        .collect();
    let quads: Vec<usize> = polygons
        .iter()
        .copied()
        .filter(|&p| mesh.polygon(p).len() == 4)
        .collect();
    if triangles.len() + quads.len() != mesh.n_polygons() {
        return Err("only triangles and quadrilaterals can be written as MSH".into());
    }
    let total = lines + mesh.n_polygons();
    let blocks = parts.len() + usize::from(!triangles.is_empty()) + usize::from(!quads.is_empty());
    writeln!(out, "{blocks} {total} 1 {total}")?;
    let mut element = 0;
    for (k, part) in parts.iter().enumerate() {
        writeln!(out, "1 {} 1 {}", k + 1, part.edges.len())?;
        for &e in &part.edges {
            let [a, b] = mesh.edge(e).vertices;
            element += 1;
            writeln!(out, "{element} {} {}", tag[a], tag[b])?;
        }
    }
    for (kind, cells) in [(2, &triangles), (3, &quads)] {
        if cells.is_empty() {
            continue;
        }
        writeln!(out, "2 1 {kind} {}", cells.len())?;
        for &p in cells.iter() {
            element += 1;
            write!(out, "{element}")?;
            for &v in mesh.polygon(p) {
                write!(out, " {}", tag[v])?;
            }
            out.push('\n');
        }
    }
    out.push_str("$EndElements\n");
    std::fs::write(path, out).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    Ok(())
}

/// The bytes of the mesh files a scene names (files that cannot be read count 0).
fn mesh_file_bytes(scene: &vem_cli::Scene) -> u64 {
    scene
        .file()
        .bodies
        .iter()
        .filter_map(|b| b.mesh.file.as_ref())
        .filter_map(|f| std::fs::metadata(scene.base().join(f)).ok())
        .map(|m| m.len())
        .sum()
}

/// The bytes of the files in `dir`.
fn folder_bytes(dir: &Path) -> u64 {
    std::fs::read_dir(dir)
        .map(|entries| {
            entries
                .filter_map(Result::ok)
                .filter_map(|e| e.metadata().ok())
                .filter(|m| m.is_file())
                .map(|m| m.len())
                .sum()
        })
        .unwrap_or(0)
}

/// `cargo xtask bench-whole`: one whole run and its reference; prints one JSON line.
pub fn run_one(args: &BenchWholeArgs) -> Result<bool, Box<dyn std::error::Error>> {
    let (scene_path, case) = match &args.scene {
        Some(scene) => (scene.clone(), scene.display().to_string()),
        None => (
            own_case(&args.dir, args.unknowns)?,
            "hertz-gmsh".to_string(),
        ),
    };
    let mut w = WholeRun {
        case,
        target_unknowns: if args.scene.is_some() {
            0
        } else {
            args.unknowns
        },
        ..WholeRun::default()
    };
    let result = if args.reference {
        reference(&scene_path, &mut w)
    } else {
        whole_run(&scene_path, &args.dir.join("out"), &mut w)
    };
    if let Err(error) = result {
        w.status = "failed".to_string();
        w.error = Some(error);
    }
    let mut stdout = std::io::stdout().lock();
    writeln!(stdout, "{}", serde_json::to_string(&w)?)?;
    Ok(true)
}

/// The whole run of `scene` into `out`.
fn whole_run(scene: &Path, out: &Path, w: &mut WholeRun) -> Result<(), String> {
    let error = |e: vem_cli::CliError| chain(&e);
    let start = Instant::now();
    let scene = vem_cli::Scene::load(scene).map_err(error)?;
    let loaded = start.elapsed();
    let model = vem_cli::Model::build(&scene).map_err(error)?;
    let built = start.elapsed();
    w.peak_build = peak_memory();
    let mesh_time = model.problem().mesh_time();
    w.read = seconds(loaded + mesh_time);
    w.build = seconds(built.saturating_sub(loaded + mesh_time));
    let mut outcome = model.solve().map_err(error)?;
    w.peak_solve = peak_memory();
    let before_output = Instant::now();
    outcome.write(out).map_err(error)?;
    w.output = seconds(before_output.elapsed());
    w.whole = seconds(start.elapsed());
    w.peak_output = peak_memory();
    let times = outcome.summary().times;
    w.assembly = times.assembly_s;
    w.solve = times.solve_s;
    w.post = times.post_s;
    w.estimate = times.estimate_s;
    w.mesh_bytes = mesh_file_bytes(&scene);
    w.written_bytes = folder_bytes(out);
    w.unknowns = outcome.summary().bodies.iter().map(|b| b.free_dofs).sum();
    w.other = w.whole - w.read - w.build - w.assembly - w.solve - w.post - w.estimate - w.output;
    w.status = outcome.summary().contact.as_ref().map_or_else(
        || "elastic".to_string(),
        |c| format!("{:?}", c.report.status),
    );
    Ok(())
}

/// The reference of the whole run of `scene`, in a process of its own so that both start
/// from the same state: the scene built and discretised as the whole run does it (meshes
/// with their interface nodes, stiffness matrices; untimed), then every body's stiffness
/// analysed, factorised and solved once by `CholeskySolver` with the default settings.
fn reference(scene: &Path, w: &mut WholeRun) -> Result<(), String> {
    let error = |e: vem_cli::CliError| chain(&e);
    let scene = vem_cli::Scene::load(scene).map_err(error)?;
    let model = vem_cli::Model::build(&scene).map_err(error)?;
    let problem = model.problem();
    let discretisation = match problem.contact_problem() {
        Some((contact, _)) => Some(contact.discretise().map_err(|e| chain(&e))?),
        None => None,
    };
    let mut systems: Vec<Arc<vem_elastic::AssembledSystem>> = discretisation
        .as_ref()
        .map_or_else(Vec::new, |d| d.systems().to_vec());
    let in_contact: Vec<usize> = problem
        .contact_problem()
        .map_or_else(Vec::new, |(_, indices)| indices.to_vec());
    for (index, body) in problem.bodies().iter().enumerate() {
        if !in_contact.contains(&index) {
            systems.push(Arc::new(body.body.assemble().map_err(|e| chain(&e))?));
        }
    }
    for system in &systems {
        let k = system.stiffness();
        w.unknowns += k.nrows();
        w.stiffness_bytes += (k.val().len() * 16 + k.symbolic().col_ptr().len() * 8) as u64;
        let mut cholesky = CholeskySolver::new(CholeskySettings::default());
        let start = Instant::now();
        cholesky.analyse(k.symbolic()).map_err(|e| chain(&e))?;
        w.reference_analyse += seconds(start.elapsed());
        let start = Instant::now();
        cholesky.factorise(k.as_ref()).map_err(|e| chain(&e))?;
        w.reference_factorise += seconds(start.elapsed());
        w.factor_bytes += 8 * cholesky.factor_len().unwrap_or(0) as u64;
        let start = Instant::now();
        let u = cholesky.solve(system.rhs()).map_err(|e| chain(&e))?;
        w.reference_solve += seconds(start.elapsed());
        std::hint::black_box(u);
    }
    w.status = "reference".to_string();
    Ok(())
}

/// Runs `repeat` whole runs of one size (or of `scene`) in child processes and returns the
/// median run (every figure the median of its own), or the first failure.
pub fn measure(
    unknowns: usize,
    scene: Option<&Path>,
    dir: &Path,
    repeat: usize,
) -> Result<WholeRun, String> {
    let exe = std::env::current_exe().map_err(|e| format!("cannot locate this program: {e}"))?;
    let child = |reference: bool| -> Result<WholeRun, String> {
        let mut command = Command::new(&exe);
        command
            .arg("bench-whole")
            .arg("--dir")
            .arg(dir)
            .args(["--unknowns", &unknowns.to_string()]);
        if let Some(scene) = scene {
            command.arg("--scene").arg(scene);
        }
        if reference {
            command.arg("--reference");
        }
        let output = command
            .output()
            .map_err(|e| format!("cannot start the whole run: {e}"))?;
        let stdout = String::from_utf8_lossy(&output.stdout);
        let parsed = stdout
            .lines()
            .rev()
            .find(|l| l.starts_with('{'))
            .and_then(|line| serde_json::from_str::<WholeRun>(line).ok());
        Ok(parsed.unwrap_or_else(|| {
            let stderr = String::from_utf8_lossy(&output.stderr);
            let reason: Vec<&str> = stderr.lines().filter(|l| !l.trim().is_empty()).collect();
            WholeRun {
                case: scene.map_or_else(|| "hertz-gmsh".to_string(), |s| s.display().to_string()),
                target_unknowns: unknowns,
                status: "failed".to_string(),
                error: Some(format!(
                    "the {} exited with {}: {}",
                    if reference { "reference" } else { "whole run" },
                    output.status,
                    reason.join(" ")
                )),
                ..WholeRun::default()
            }
        }))
    };
    let mut runs = Vec::with_capacity(repeat);
    for _ in 0..repeat.max(1) {
        // The whole run first (it writes the bench's own meshes), then its reference.
        let mut run = child(false)?;
        if run.error.is_some() {
            return Ok(run);
        }
        let reference = child(true)?;
        if reference.error.is_some() {
            return Ok(reference);
        }
        run.reference_analyse = reference.reference_analyse;
        run.reference_factorise = reference.reference_factorise;
        run.reference_solve = reference.reference_solve;
        run.stiffness_bytes = reference.stiffness_bytes;
        run.factor_bytes = reference.factor_bytes;
        runs.push(run);
    }
    Ok(median(&runs))
}

/// Every figure the median of the runs' (the upper median for an even count).
fn median(runs: &[WholeRun]) -> WholeRun {
    let pick = |f: fn(&WholeRun) -> f64| {
        let mut v: Vec<f64> = runs.iter().map(f).collect();
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let pick_u = |f: fn(&WholeRun) -> u64| {
        let mut v: Vec<u64> = runs.iter().map(f).collect();
        v.sort_unstable();
        v[v.len() / 2]
    };
    WholeRun {
        read: pick(|r| r.read),
        build: pick(|r| r.build),
        assembly: pick(|r| r.assembly),
        solve: pick(|r| r.solve),
        post: pick(|r| r.post),
        estimate: pick(|r| r.estimate),
        output: pick(|r| r.output),
        whole: pick(|r| r.whole),
        other: pick(|r| r.other),
        reference_analyse: pick(|r| r.reference_analyse),
        reference_factorise: pick(|r| r.reference_factorise),
        reference_solve: pick(|r| r.reference_solve),
        peak_build: pick_u(|r| r.peak_build),
        peak_solve: pick_u(|r| r.peak_solve),
        peak_output: pick_u(|r| r.peak_output),
        ..runs[0].clone()
    }
}

const GIB: f64 = 1024.0 * 1024.0 * 1024.0;
const MB: f64 = 1e6;

/// The header of the whole-run table.
pub const TABLE_HEADER: &str = "| case | unknowns | mesh files [MB] | read | build | assembly | solve | post | estimate | output | other | whole run | Cholesky: analyse / factorise / solve | whole / Cholesky | assembly, post + estimate, output / Cholesky | read [MB/s] | peak build / solve / output [GiB] | K / L [GiB] | written [MB] | status |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";

/// One row of the whole-run table.
pub fn row(w: &WholeRun) -> String {
    if let Some(error) = &w.error {
        return format!(
            "| {} | ~{} | failed: {} |",
            w.case,
            w.target_unknowns,
            error.replace('|', "/")
        );
    }
    let c = w.cholesky();
    format!(
        "| {} | {} | {:.1} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} / {:.3} / {:.3} | {:.2} | {:.2}, {:.2}, {:.2} | {:.0} | {:.2} / {:.2} / {:.2} | {:.3} / {:.3} | {:.1} | {} |",
        w.case,
        w.unknowns,
        w.mesh_bytes as f64 / MB,
        w.read,
        w.build,
        w.assembly,
        w.solve,
        w.post,
        w.estimate,
        w.output,
        w.other,
        w.whole,
        w.reference_analyse,
        w.reference_factorise,
        w.reference_solve,
        w.ratio(),
        w.assembly / c,
        (w.post + w.estimate) / c,
        w.output / c,
        w.mesh_bytes as f64 / MB / w.read.max(1e-9),
        w.peak_build as f64 / GIB,
        w.peak_solve as f64 / GIB,
        w.peak_output as f64 / GIB,
        w.stiffness_bytes as f64 / GIB,
        w.factor_bytes as f64 / GIB,
        w.written_bytes as f64 / MB,
        w.status,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn written_meshes_read_back_as_the_same_meshes() {
        let dir = std::env::temp_dir().join(format!("whole-run-msh-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let rect = Rectangle::new(Point::new(0.0, 0.0), Point::new(1.0, 1.0));
        for (mesh, seed) in [
            (structured_triangles(&rect, 5, 4).unwrap(), 1),
            (structured_quads(&rect, 3, 6).unwrap(), 2),
        ] {
            let path = dir.join("mesh.msh");
            write_msh(&path, &mesh, seed).unwrap();
            let read = vem_mesh::io::read_gmsh(&path).unwrap();
            assert_eq!(read.n_vertices(), mesh.n_vertices());
            assert_eq!(read.n_polygons(), mesh.n_polygons());
            let area = |m: &Mesh| (0..m.n_polygons()).map(|p| m.area(p)).sum::<f64>();
            assert!((area(&read) - 1.0).abs() < 1e-12);
            for part in mesh.parts() {
                let length = |m: &Mesh| {
                    m.part(&part.name)
                        .unwrap()
                        .edges
                        .iter()
                        .map(|&e| {
                            let [a, b] = m.edge(e).vertices;
                            (m.vertex(a) - m.vertex(b)).norm()
                        })
                        .sum::<f64>()
                };
                assert!(
                    (length(&read) - length(&mesh)).abs() < 1e-12,
                    "{}",
                    part.name
                );
            }
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn shuffles_are_permutations() {
        let mut order = shuffled(1000, 7);
        assert_ne!(order, (0..1000).collect::<Vec<_>>());
        order.sort_unstable();
        assert_eq!(order, (0..1000).collect::<Vec<_>>());
    }
}
