//! `cargo xtask fuzz`: an in-process mutation fuzzer for the input paths of the workspace, on
//! stable Rust (no coverage instrumentation).
//!
//! Targets (`--target NAME`, all by default, the time shared equally):
//! - `scene`: parsing and checking a scene file (`vem_cli::Scene::parse`); seeds: the shipped
//!   scenes of `crates/vem-cli/scenes`;
//! - `gmsh`: the Gmsh reader and the mesh it builds (`vem_mesh::io::read_gmsh_bytes`); seeds:
//!   every `.msh` file of the repository (test corpus, fixtures, scenes);
//! - `validate`: mesh validation (`Mesh::from_polygons`) and element quality on meshes written
//!   as text (`v x y`, `p i j k ...`, `e part a b` lines); seeds: generated meshes;
//! - `interface`: interface node insertion (`insert_interface_nodes`) between two text meshes
//!   (a first line `parts A B`, the meshes separated by a line `---`); seeds: pairs of generated
//!   meshes of different sizes facing each other.
//! - `polyhedral`: polyhedral mesh validation (`PolyhedralMesh::from_polyhedra`), cell quality
//!   and the element on polyhedra (`PolyhedralVem`) on meshes written as text (`v x y z`
//!   vertices, `f i j k ...` faces of the current cell, `c` ending a cell, `b part i j k ...`
//!   part faces), and the 3D Gmsh reader (`read_gmsh_polyhedral_bytes`) on inputs that start
//!   with `$MeshFormat`; seeds: generated polyhedral meshes of every family and the 3D Gmsh
//!   corpus.
//! - `overlay`: the surface overlay (`insert_surface_overlay`) between two polyhedral text
//!   meshes (a first line `parts A B`, the meshes in the `polyhedral` target's form separated by
//!   a line `---`), the enlarged meshes checked as in `polyhedral`; seeds: pairs of generated
//!   blocks of different families and sizes, shifted, touching, apart and overlapping.
//!
//! Each input is a seed changed by one to four byte or structure mutations (bit flips, random
//! bytes, deletions, duplications, splices with another seed, lines deleted, duplicated or
//! swapped, numbers replaced by extreme values); inputs a target accepts join the pool. Every
//! input runs on its own thread under `catch_unwind` and a time limit. A failure is a panic, a
//! hang (over the time limit) or an accepted input whose outputs are not finite; it is minimised
//! (panics and non-finite outputs: chunks deleted while the same failure remains) and written
//! to `<out>/<target>/`. Committed failures live in `tests/fuzz-regressions/<target>/` and are
//! replayed by this module's tests.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::sync::Mutex;
use std::time::{Duration, Instant};

use clap::Args;
use vem_mesh::generators::{structured_quads, structured_triangles, voronoi, Rectangle};
use vem_mesh::{insert_interface_nodes, InterfaceOptions, Mesh, PartSpec, Point};

/// Options of `cargo xtask fuzz`.
#[derive(Debug, Args)]
pub struct FuzzArgs {
    /// Minutes to fuzz in all (shared by the targets).
    #[arg(long, conflicts_with = "seconds")]
    pub minutes: Option<f64>,
    /// Seconds to fuzz in all (shared by the targets); 60 when neither this nor --minutes is
    /// given.
    #[arg(long)]
    pub seconds: Option<f64>,
    /// Fuzz only this target: scene, gmsh, validate, interface or polyhedral.
    #[arg(long)]
    pub target: Option<String>,
    /// Seed of the mutation generator (runs with the same seed and the same number of inputs
    /// are identical).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Where failing inputs are written (one folder per target).
    #[arg(long, default_value = "target/fuzz")]
    pub out: PathBuf,
    /// Time limit of one input, in seconds; an input that runs longer is a hang.
    #[arg(long, default_value_t = 5.0)]
    pub timeout: f64,
}

/// What a target made of an input.
#[derive(Debug, Clone, PartialEq)]
pub enum Verdict {
    /// The input was accepted and every output is finite.
    Accepted,
    /// The input was rejected with an error (the expected outcome for bad input).
    Rejected,
    /// The input was accepted but an output is not finite (what and where).
    NonFinite(String),
}

/// A fuzz target: a name, the function under test and its seeds.
pub struct Target {
    /// The name given to `--target`.
    pub name: &'static str,
    /// Runs one input.
    pub run: fn(&[u8]) -> Verdict,
    /// The seed inputs.
    pub seeds: fn() -> Vec<Vec<u8>>,
}

/// The fuzz targets.
pub fn targets() -> Vec<Target> {
    vec![
        Target {
            name: "scene",
            run: run_scene,
            seeds: scene_seeds,
        },
        Target {
            name: "gmsh",
            run: run_gmsh,
            seeds: gmsh_seeds,
        },
        Target {
            name: "validate",
            run: run_validate,
            seeds: validate_seeds,
        },
        Target {
            name: "interface",
            run: run_interface,
            seeds: interface_seeds,
        },
        Target {
            name: "polyhedral",
            run: run_polyhedral,
            seeds: polyhedral_seeds,
        },
        Target {
            name: "overlay",
            run: run_overlay,
            seeds: overlay_seeds,
        },
    ]
}

fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("xtask lies in the workspace")
        .to_path_buf()
}

// ---------------------------------------------------------------------------------------------
// Targets

fn run_scene(input: &[u8]) -> Verdict {
    let path = workspace_root().join("crates/vem-cli/scenes/fuzz.toml");
    let text = String::from_utf8_lossy(input).into_owned();
    match vem_cli::Scene::parse(path, text) {
        Ok(_) => Verdict::Accepted,
        Err(_) => Verdict::Rejected,
    }
}

fn scene_seeds() -> Vec<Vec<u8>> {
    files_with_extension(&workspace_root().join("crates/vem-cli/scenes"), "toml")
}

fn run_gmsh(input: &[u8]) -> Verdict {
    match vem_mesh::io::read_gmsh_bytes(input, "fuzz.msh") {
        Ok(mesh) => check_mesh(&mesh, "mesh"),
        Err(_) => Verdict::Rejected,
    }
}

fn gmsh_seeds() -> Vec<Vec<u8>> {
    let root = workspace_root();
    let mut seeds = files_with_extension(&root.join("crates/vem-mesh/tests/data"), "msh");
    seeds.extend(files_with_extension(
        &root.join("crates/vem-mesh/tests/data/gmsh-corpus"),
        "msh",
    ));
    seeds.extend(files_with_extension(
        &root.join("crates/vem-cli/scenes"),
        "msh",
    ));
    seeds
}

fn run_validate(input: &[u8]) -> Verdict {
    let Some((vertices, polygons, parts)) = decode_mesh(&String::from_utf8_lossy(input)) else {
        return Verdict::Rejected;
    };
    match Mesh::from_polygons(vertices, &polygons, parts) {
        Ok(mesh) => check_mesh(&mesh, "mesh"),
        Err(_) => Verdict::Rejected,
    }
}

fn validate_seeds() -> Vec<Vec<u8>> {
    generated_meshes()
        .iter()
        .map(|m| encode_mesh(m).into_bytes())
        .collect()
}

fn run_interface(input: &[u8]) -> Verdict {
    let text = String::from_utf8_lossy(input);
    let mut lines = text.lines();
    let Some(header) = lines.next() else {
        return Verdict::Rejected;
    };
    let names: Vec<&str> = header.split_whitespace().collect();
    let [_, part_a, part_b] = names.as_slice() else {
        return Verdict::Rejected;
    };
    let rest: Vec<&str> = lines.collect();
    let rest = rest.join("\n");
    let Some((text_a, text_b)) = rest.split_once("\n---\n") else {
        return Verdict::Rejected;
    };
    let build = |text: &str| {
        let (vertices, polygons, parts) = decode_mesh(text)?;
        Mesh::from_polygons(vertices, &polygons, parts).ok()
    };
    let (Some(mesh_a), Some(mesh_b)) = (build(text_a), build(text_b)) else {
        return Verdict::Rejected;
    };
    match insert_interface_nodes(
        &mesh_a,
        part_a,
        &mesh_b,
        part_b,
        &InterfaceOptions::default(),
    ) {
        Ok(interface) => {
            for (k, pair) in interface.pairs.iter().enumerate() {
                let values = [
                    pair.point_a.x,
                    pair.point_a.y,
                    pair.point_b.x,
                    pair.point_b.y,
                    pair.normal.x,
                    pair.normal.y,
                    pair.tributary_length,
                ];
                if values.iter().any(|v| !v.is_finite()) {
                    return Verdict::NonFinite(format!("pair {k}: {pair:?}"));
                }
            }
            match check_mesh(&interface.mesh_a, "mesh a") {
                Verdict::Accepted => check_mesh(&interface.mesh_b, "mesh b"),
                other => other,
            }
        }
        Err(_) => Verdict::Rejected,
    }
}

fn interface_seeds() -> Vec<Vec<u8>> {
    let lower = Rectangle::new(Point::new(0.0, 0.0), Point::new(1.0, 1.0));
    let upper = Rectangle::new(Point::new(0.2, 1.0), Point::new(0.8, 1.5));
    let gap = Rectangle::new(Point::new(0.0, 1.01), Point::new(1.0, 1.5));
    let pairs = [
        (
            structured_quads(&lower, 3, 2),
            structured_quads(&upper, 2, 1),
        ),
        (
            structured_triangles(&lower, 2, 2),
            structured_quads(&gap, 3, 1),
        ),
        (voronoi(&lower, 3, 1), structured_triangles(&upper, 3, 1)),
    ];
    pairs
        .into_iter()
        .map(|(a, b)| {
            let (a, b) = (a.expect("seed mesh"), b.expect("seed mesh"));
            format!(
                "parts top bottom\n{}---\n{}",
                encode_mesh(&a),
                encode_mesh(&b)
            )
            .into_bytes()
        })
        .collect()
}

/// Finite vertices, areas and element qualities of an accepted mesh.
fn check_mesh(mesh: &Mesh, what: &str) -> Verdict {
    for (v, p) in mesh.vertices().iter().enumerate() {
        if !(p.x.is_finite() && p.y.is_finite()) {
            return Verdict::NonFinite(format!("{what}: vertex {v} at ({}, {})", p.x, p.y));
        }
    }
    for p in 0..mesh.n_polygons() {
        let area = mesh.area(p);
        let diameter = mesh.diameter(p);
        if !(area.is_finite() && area > 0.0 && diameter.is_finite()) {
            return Verdict::NonFinite(format!(
                "{what}: polygon {p} has area {area} and diameter {diameter}"
            ));
        }
        let quality = vem_mesh::quality::element_quality(&mesh.polygon_points(p));
        if !quality.gamma().is_finite() {
            return Verdict::NonFinite(format!("{what}: polygon {p} has quality {quality:?}"));
        }
    }
    Verdict::Accepted
}

/// The text form of a mesh used by the `validate` and `interface` targets.
fn encode_mesh(mesh: &Mesh) -> String {
    let mut text = String::new();
    for p in mesh.vertices() {
        text += &format!("v {:?} {:?}\n", p.x, p.y);
    }
    for polygon in mesh.polygons() {
        let indices: Vec<String> = polygon.iter().map(|v| v.to_string()).collect();
        text += &format!("p {}\n", indices.join(" "));
    }
    for part in mesh.part_specs() {
        for [a, b] in &part.edges {
            text += &format!("e {} {a} {b}\n", part.name);
        }
    }
    text
}

type Decoded = (Vec<Point>, Vec<Vec<usize>>, Vec<PartSpec>);

/// Reads the text form of [`encode_mesh`]; lines it cannot read are skipped (the decoder is the
/// harness, not the code under test). `None` when it holds more than 10^5 items.
fn decode_mesh(text: &str) -> Option<Decoded> {
    let mut vertices = Vec::new();
    let mut polygons = Vec::new();
    let mut parts: Vec<(String, Vec<[usize; 2]>)> = Vec::new();
    for line in text.lines().take(100_000) {
        let fields: Vec<&str> = line.split_whitespace().collect();
        match fields.as_slice() {
            ["v", x, y] => {
                if let (Ok(x), Ok(y)) = (x.parse(), y.parse()) {
                    vertices.push(Point::new(x, y));
                }
            }
            ["p", indices @ ..] => {
                let polygon: Result<Vec<usize>, _> = indices.iter().map(|i| i.parse()).collect();
                if let Ok(polygon) = polygon {
                    polygons.push(polygon);
                }
            }
            ["e", name, a, b] => {
                if let (Ok(a), Ok(b)) = (a.parse(), b.parse()) {
                    match parts.iter_mut().find(|(n, _)| n == name) {
                        Some((_, edges)) => edges.push([a, b]),
                        None => parts.push((name.to_string(), vec![[a, b]])),
                    }
                }
            }
            _ => {}
        }
    }
    let parts = parts
        .into_iter()
        .map(|(name, edges)| PartSpec::new(name, edges))
        .collect();
    Some((vertices, polygons, parts))
}

fn generated_meshes() -> Vec<Mesh> {
    let square = Rectangle::unit_square();
    [
        structured_quads(&square, 2, 2),
        structured_triangles(&square, 2, 1),
        vem_mesh::generators::hexagons(&square, 2),
        vem_mesh::generators::nonconvex(&square, 2),
        vem_mesh::generators::hanging_nodes(&square, 2),
        voronoi(&square, 4, 7),
    ]
    .into_iter()
    .map(|m| m.expect("seed mesh"))
    .collect()
}

fn run_polyhedral(input: &[u8]) -> Verdict {
    if input.starts_with(b"$MeshFormat") {
        return match vem_mesh::io::read_gmsh_polyhedral_bytes(input, "fuzz.msh") {
            Ok(mesh) => check_polyhedral(&mesh),
            Err(_) => Verdict::Rejected,
        };
    }
    let (vertices, cells, parts) = decode_polyhedral(&String::from_utf8_lossy(input));
    match vem_mesh::PolyhedralMesh::from_polyhedra(vertices, &cells, parts) {
        Ok(mesh) => check_polyhedral(&mesh),
        Err(_) => Verdict::Rejected,
    }
}

/// Every cell of an accepted polyhedral mesh has a finite positive volume, finite quality
/// figures, and a finite local stiffness of the element (or a clear element error).
fn check_polyhedral(mesh: &vem_mesh::PolyhedralMesh) -> Verdict {
    use vem_space::PolyhedralElement;
    let element = vem_space::PolyhedralVem::default();
    let identity = vem_verify::nalgebra::DMatrix::identity(6, 6);
    let material = vem_space::ElasticityTensor::<3>::try_from_voigt_matrix(&identity)
        .expect("the identity is an admissible tensor");
    for c in 0..mesh.n_cells() {
        let polyhedron = mesh.cell_polyhedron(c);
        let (volume, centroid) = polyhedron.volume_and_centroid();
        if !(volume.is_finite() && volume > 0.0 && centroid.iter().all(|x| x.is_finite())) {
            return Verdict::NonFinite(format!("cell {c}: volume {volume}, centroid {centroid}"));
        }
        let quality = mesh.cell_quality(c);
        if !(quality.gamma().is_finite() && quality.face_warping.is_finite()) {
            return Verdict::NonFinite(format!("cell {c}: quality {quality:?}"));
        }
        if let Ok(local) = element.stiffness(&polyhedron, &material) {
            if !local.total().iter().all(|k| k.is_finite()) {
                return Verdict::NonFinite(format!("cell {c}: the local stiffness"));
            }
        }
    }
    Verdict::Accepted
}

fn polyhedral_seeds() -> Vec<Vec<u8>> {
    use vem_mesh::generators::polyhedral::{Cuboid, PolyhedralFamily};
    PolyhedralFamily::all()
        .iter()
        .map(|family| {
            let mesh = family
                .generate(&Cuboid::unit_cube(), 2, 3)
                .expect("seed mesh");
            encode_polyhedral(&mesh).into_bytes()
        })
        .chain(files_with_extension(
            &workspace_root().join("crates/vem-mesh/tests/data/gmsh-corpus-3d"),
            "msh",
        ))
        .collect()
}

/// The surface overlay of two polyhedral meshes: a header `parts <part a> <part b>`, then mesh
/// a and mesh b in the text form of [`encode_polyhedral`], separated by a line `---`. Accepted
/// overlays must have finite pairs with positive tributary areas and two meshes that pass
/// [`check_polyhedral`].
fn run_overlay(input: &[u8]) -> Verdict {
    let text = String::from_utf8_lossy(input);
    let Some((header, rest)) = text.split_once('\n') else {
        return Verdict::Rejected;
    };
    let names: Vec<&str> = header.split_whitespace().collect();
    let [_, part_a, part_b] = names.as_slice() else {
        return Verdict::Rejected;
    };
    let Some((text_a, text_b)) = rest.split_once("\n---\n") else {
        return Verdict::Rejected;
    };
    let build = |text: &str| {
        let (vertices, cells, parts) = decode_polyhedral(text);
        vem_mesh::PolyhedralMesh::from_polyhedra(vertices, &cells, parts).ok()
    };
    let (Some(mesh_a), Some(mesh_b)) = (build(text_a), build(text_b)) else {
        return Verdict::Rejected;
    };
    match vem_mesh::insert_surface_overlay(
        &mesh_a,
        part_a,
        &mesh_b,
        part_b,
        &InterfaceOptions::default(),
    ) {
        Ok(overlay) => {
            for (k, pair) in overlay.pairs.iter().enumerate() {
                let finite = pair
                    .point_a
                    .iter()
                    .chain(pair.point_b.iter())
                    .chain(pair.normal.iter())
                    .chain([pair.tributary_area, pair.initial_gap].iter())
                    .all(|v| v.is_finite());
                if !finite || pair.tributary_area <= 0.0 {
                    return Verdict::NonFinite(format!("pair {k}: {pair:?}"));
                }
            }
            match check_polyhedral(&overlay.mesh_a) {
                Verdict::Accepted => check_polyhedral(&overlay.mesh_b),
                other => other,
            }
        }
        Err(_) => Verdict::Rejected,
    }
}

fn overlay_seeds() -> Vec<Vec<u8>> {
    use vem_mesh::generators::polyhedral::{Cuboid, PolyhedralFamily};
    use vem_mesh::Point3;
    let below = Cuboid::new(Point3::new(0.0, 0.0, 0.0), Point3::new(1.0, 1.0, 0.5));
    let above = |dx: f64, dy: f64, gap: f64| {
        Cuboid::new(
            Point3::new(dx, dy, 0.5 + gap),
            Point3::new(1.0 + dx, 1.0 + dy, 1.0 + gap),
        )
    };
    let perturbed = PolyhedralFamily::PerturbedHexahedra { distortion: 0.2 };
    [
        (
            PolyhedralFamily::Hexahedra,
            2,
            PolyhedralFamily::Tetrahedra,
            3,
            above(0.1, 0.2, 0.0),
        ),
        (
            PolyhedralFamily::Voronoi,
            2,
            perturbed,
            3,
            above(-0.15, 0.05, 0.01),
        ),
        (
            PolyhedralFamily::Octree,
            2,
            PolyhedralFamily::Hexahedra,
            3,
            above(0.0, 0.0, -0.01),
        ),
    ]
    .into_iter()
    .map(|(family_a, n_a, family_b, n_b, cuboid_b)| {
        let a = family_a.generate(&below, n_a, 1).expect("seed mesh");
        let b = family_b.generate(&cuboid_b, n_b, 2).expect("seed mesh");
        format!(
            "parts top bottom\n{}---\n{}",
            encode_polyhedral(&a),
            encode_polyhedral(&b)
        )
        .into_bytes()
    })
    .collect()
}

/// The text form of a polyhedral mesh used by the `polyhedral` target.
fn encode_polyhedral(mesh: &vem_mesh::PolyhedralMesh) -> String {
    let mut text = String::new();
    for p in mesh.vertices() {
        text += &format!("v {:?} {:?} {:?}\n", p.x, p.y, p.z);
    }
    let join = |loop_: &[usize]| -> String {
        loop_
            .iter()
            .map(|v| v.to_string())
            .collect::<Vec<_>>()
            .join(" ")
    };
    for c in 0..mesh.n_cells() {
        for face in mesh.cell_face_loops(c) {
            text += &format!("f {}\n", join(&face));
        }
        text += "c\n";
    }
    for part in mesh.parts() {
        for &f in &part.faces {
            text += &format!("b {} {}\n", part.name, join(mesh.face(f)));
        }
    }
    text
}

type DecodedPolyhedral = (
    Vec<vem_mesh::Point3>,
    Vec<Vec<Vec<usize>>>,
    Vec<vem_mesh::FacePartSpec>,
);

/// Reads the text form of [`encode_polyhedral`]; lines it cannot read are skipped, and at most
/// 10^5 lines are read.
fn decode_polyhedral(text: &str) -> DecodedPolyhedral {
    let mut vertices = Vec::new();
    let mut cells = Vec::new();
    let mut current: Vec<Vec<usize>> = Vec::new();
    let mut parts: Vec<vem_mesh::FacePartSpec> = Vec::new();
    let indices =
        |fields: &[&str]| -> Option<Vec<usize>> { fields.iter().map(|i| i.parse().ok()).collect() };
    for line in text.lines().take(100_000) {
        let fields: Vec<&str> = line.split_whitespace().collect();
        match fields.as_slice() {
            ["v", x, y, z] => {
                if let (Ok(x), Ok(y), Ok(z)) = (x.parse(), y.parse(), z.parse()) {
                    vertices.push(vem_mesh::Point3::new(x, y, z));
                }
            }
            ["f", rest @ ..] => current.extend(indices(rest)),
            ["c"] => cells.push(std::mem::take(&mut current)),
            ["b", name, rest @ ..] => {
                if let Some(face) = indices(rest) {
                    match parts.iter_mut().find(|p| p.name == *name) {
                        Some(part) => part.faces.push(face),
                        None => parts.push(vem_mesh::FacePartSpec::new(*name, vec![face])),
                    }
                }
            }
            _ => {}
        }
    }
    (vertices, cells, parts)
}

fn files_with_extension(dir: &Path, extension: &str) -> Vec<Vec<u8>> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|entries| entries.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    paths.retain(|p| p.extension().is_some_and(|e| e == extension));
    paths.sort();
    paths.iter().filter_map(|p| std::fs::read(p).ok()).collect()
}

// ---------------------------------------------------------------------------------------------
// Running inputs

/// The outcome of one input.
#[derive(Debug, Clone, PartialEq)]
pub enum Outcome {
    /// The target returned a verdict.
    Done(Verdict),
    /// The target panicked: the message and where.
    Panic(String),
    /// The target ran past the time limit.
    Hang,
}

/// The message and location of the last panic on each thread, kept by the fuzzer's hook.
static LAST_PANIC: Mutex<Option<String>> = Mutex::new(None);

/// Replaces the panic hook by one that records the message quietly (restored on drop).
struct QuietPanics;

impl QuietPanics {
    fn install() -> Self {
        std::panic::set_hook(Box::new(|info| {
            let message = info
                .payload()
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| info.payload().downcast_ref::<String>().cloned())
                .unwrap_or_default();
            let location = info
                .location()
                .map(|l| format!("{}:{}", l.file(), l.line()))
                .unwrap_or_default();
            if let Ok(mut last) = LAST_PANIC.lock() {
                *last = Some(format!("{location}: {message}"));
            }
        }));
        QuietPanics
    }
}

impl Drop for QuietPanics {
    fn drop(&mut self) {
        let _ = std::panic::take_hook();
    }
}

/// Runs `input` through `run` on a thread of its own, under `catch_unwind` and `timeout`. A
/// thread past the limit is left behind (it cannot be stopped); the caller stops after a few.
pub fn run_one(run: fn(&[u8]) -> Verdict, input: &[u8], timeout: Duration) -> Outcome {
    let (send, receive) = mpsc::channel();
    let input = input.to_vec();
    let spawned = std::thread::Builder::new()
        .stack_size(16 << 20)
        .spawn(move || {
            let result = catch_unwind(AssertUnwindSafe(|| run(&input)));
            let outcome = match result {
                Ok(verdict) => Outcome::Done(verdict),
                Err(_) => Outcome::Panic(
                    LAST_PANIC
                        .lock()
                        .ok()
                        .and_then(|mut last| last.take())
                        .unwrap_or_else(|| "panic".into()),
                ),
            };
            let _ = send.send(outcome);
        });
    if spawned.is_err() {
        return Outcome::Hang;
    }
    match receive.recv_timeout(timeout) {
        Ok(outcome) => outcome,
        Err(_) => Outcome::Hang,
    }
}

/// Whether an outcome is a failure, and its kind for minimisation (same kind = same failure).
fn failure_kind(outcome: &Outcome) -> Option<String> {
    match outcome {
        Outcome::Done(Verdict::Accepted | Verdict::Rejected) => None,
        Outcome::Done(Verdict::NonFinite(_)) => Some("non-finite".into()),
        // The location (file:line) identifies a panic; the message may carry input values.
        Outcome::Panic(message) => Some(format!(
            "panic {}",
            message.split(": ").next().unwrap_or_default()
        )),
        Outcome::Hang => Some("hang".into()),
    }
}

/// Deletes chunks of `input` while the same failure remains (at most `budget` runs).
fn minimise(
    run: fn(&[u8]) -> Verdict,
    input: &[u8],
    kind: &str,
    timeout: Duration,
    budget: usize,
) -> Vec<u8> {
    let mut best = input.to_vec();
    let mut runs = 0;
    let mut chunk = best.len().div_ceil(2).max(1);
    while chunk >= 1 && runs < budget {
        let mut start = 0;
        while start < best.len() && runs < budget {
            let end = (start + chunk).min(best.len());
            let mut candidate = best[..start].to_vec();
            candidate.extend_from_slice(&best[end..]);
            runs += 1;
            if failure_kind(&run_one(run, &candidate, timeout)).as_deref() == Some(kind) {
                best = candidate;
            } else {
                start = end;
            }
        }
        if chunk == 1 {
            break;
        }
        chunk /= 2;
    }
    best
}

/// A small deterministic generator (SplitMix64).
pub struct Rng(u64);

impl Rng {
    /// A generator started at `seed`.
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }

    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    fn below(&mut self, n: usize) -> usize {
        if n == 0 {
            0
        } else {
            (self.next() % n as u64) as usize
        }
    }
}

/// Values that break parsers and arithmetic.
const INTERESTING: &[&str] = &[
    "0",
    "-1",
    "1",
    "2",
    "-0",
    "1e308",
    "-1e308",
    "1e-320",
    "nan",
    "inf",
    "-inf",
    "2147483647",
    "2147483648",
    "4294967296",
    "18446744073709551615",
    "9223372036854775807",
    "0.5",
    "\"\"",
    "[]",
    "[1,2,3]",
    "=",
    "\n",
    "$EndNodes",
    "$Nodes",
    "$EndElements",
];

/// The largest input the mutator makes.
const MAX_INPUT: usize = 1 << 20;

/// One to four mutations of `input`; `pool` gives material to splice in.
pub fn mutate(input: &[u8], pool: &[Vec<u8>], rng: &mut Rng) -> Vec<u8> {
    let mut data = input.to_vec();
    for _ in 0..1 + rng.below(4) {
        let len = data.len();
        match rng.below(11) {
            0 if len > 0 => {
                let i = rng.below(len);
                data[i] ^= 1 << rng.below(8);
            }
            1 if len > 0 => {
                let i = rng.below(len);
                data[i] = rng.next() as u8;
            }
            2 => {
                let i = rng.below(len + 1);
                data.insert(i, rng.next() as u8);
            }
            3 if len > 0 => {
                let i = rng.below(len);
                let n = 1 + rng.below((len - i).min(64));
                data.drain(i..i + n);
            }
            4 if len > 0 => {
                let i = rng.below(len);
                let n = 1 + rng.below((len - i).min(256));
                let copy = data[i..i + n].to_vec();
                let at = rng.below(len + 1);
                data.splice(at..at, copy);
            }
            5 if !pool.is_empty() => {
                let other = &pool[rng.below(pool.len())];
                if !other.is_empty() {
                    let i = rng.below(other.len());
                    let n = 1 + rng.below((other.len() - i).min(512));
                    let at = rng.below(len + 1);
                    data.splice(at..at, other[i..i + n].iter().copied());
                }
            }
            6 => {
                let token = INTERESTING[rng.below(INTERESTING.len())].as_bytes();
                let at = rng.below(len + 1);
                data.splice(at..at, token.iter().copied());
            }
            7 => replace_number(&mut data, rng),
            8 => line_mutation(&mut data, rng),
            9 if len > 0 => {
                // Truncate.
                data.truncate(rng.below(len));
            }
            _ => replace_number(&mut data, rng),
        }
        data.truncate(MAX_INPUT);
    }
    data
}

/// Replaces a number of the text by an interesting value.
fn replace_number(data: &mut Vec<u8>, rng: &mut Rng) {
    let starts: Vec<usize> = (0..data.len())
        .filter(|&i| data[i].is_ascii_digit() && (i == 0 || !data[i - 1].is_ascii_alphanumeric()))
        .collect();
    if starts.is_empty() {
        return;
    }
    let start = starts[rng.below(starts.len())];
    let mut end = start;
    while end < data.len() && (data[end].is_ascii_alphanumeric() || data[end] == b'.') {
        end += 1;
    }
    let value = INTERESTING[rng.below(INTERESTING.len())].as_bytes();
    data.splice(start..end, value.iter().copied());
}

/// Deletes, duplicates or swaps lines.
fn line_mutation(data: &mut Vec<u8>, rng: &mut Rng) {
    let mut lines: Vec<Vec<u8>> = data.split(|&b| b == b'\n').map(|l| l.to_vec()).collect();
    if lines.is_empty() {
        return;
    }
    let i = rng.below(lines.len());
    let j = rng.below(lines.len());
    match rng.below(3) {
        0 => {
            lines.remove(i);
        }
        1 => {
            let copy = lines[i].clone();
            lines.insert(j, copy);
        }
        _ => lines.swap(i, j),
    }
    *data = lines.join(&b'\n');
}

/// Figures of one target's run.
#[derive(Debug, Default, Clone)]
pub struct Figures {
    /// Inputs run.
    pub runs: usize,
    /// Of which accepted.
    pub accepted: usize,
    /// Panics found.
    pub panics: usize,
    /// Hangs found.
    pub hangs: usize,
    /// Accepted inputs with non-finite outputs.
    pub non_finite: usize,
    /// Inputs that missed the time limit once but finished within four times the limit.
    pub slow: usize,
    /// Seconds spent.
    pub seconds: f64,
}

/// Fuzzes `target` for `duration` or `max_runs` inputs, whichever ends first; failures are
/// minimised and written to `out` when it is given.
pub fn fuzz_target(
    target: &Target,
    duration: Duration,
    max_runs: usize,
    seed: u64,
    timeout: Duration,
    out: Option<&Path>,
) -> Figures {
    let _quiet = QuietPanics::install();
    let started = Instant::now();
    let seeds = (target.seeds)();
    let mut pool = seeds.clone();
    let mut rng = Rng::new(seed ^ (target.name.len() as u64).wrapping_mul(0x1234_5678_9ABC));
    let mut figures = Figures::default();
    let mut known = std::collections::HashSet::new();
    while started.elapsed() < duration && figures.runs < max_runs && !pool.is_empty() {
        let parent = &pool[rng.below(pool.len())];
        let input = mutate(parent, &seeds, &mut rng);
        let mut outcome = run_one(target.run, &input, timeout);
        if outcome == Outcome::Hang {
            // On a loaded machine a normal input can miss the limit once: a hang is an input
            // that also misses four times the limit.
            figures.slow += 1;
            outcome = run_one(target.run, &input, 4 * timeout);
        }
        figures.runs += 1;
        if outcome == Outcome::Done(Verdict::Accepted) {
            figures.accepted += 1;
            if pool.len() < 2000 {
                pool.push(input);
            }
            continue;
        }
        let Some(kind) = failure_kind(&outcome) else {
            continue;
        };
        match outcome {
            Outcome::Hang => figures.hangs += 1,
            Outcome::Panic(_) => figures.panics += 1,
            _ => figures.non_finite += 1,
        }
        let minimal = if kind == "hang" {
            input
        } else {
            minimise(target.run, &input, &kind, timeout, 2000)
        };
        let message = match run_one(target.run, &minimal, timeout) {
            Outcome::Panic(message) => message,
            Outcome::Done(Verdict::NonFinite(what)) => what,
            Outcome::Hang => format!("ran past {:?} twice (the second time 4x)", timeout),
            other => format!("{other:?}"),
        };
        let fresh = known.insert(kind.clone());
        if fresh {
            eprintln!("fuzz {}: {kind}: {message}", target.name);
        }
        if let Some(out) = out {
            let dir = out.join(target.name);
            let _ = std::fs::create_dir_all(&dir);
            let name = format!(
                "{}-{:016x}",
                kind.replace([' ', '/', ':'], "_"),
                fnv(&minimal)
            );
            let _ = std::fs::write(dir.join(&name), &minimal);
            let _ = std::fs::write(dir.join(format!("{name}.txt")), &message);
        }
        if figures.hangs >= 3 {
            eprintln!(
                "fuzz {}: stopping after 3 hangs (their threads still run)",
                target.name
            );
            break;
        }
    }
    figures.seconds = started.elapsed().as_secs_f64();
    figures
}

fn fnv(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ b as u64).wrapping_mul(0x0100_0000_01b3)
    })
}

/// Runs `cargo xtask fuzz`; `Ok(false)` when a failure was found.
pub fn run(args: &FuzzArgs) -> Result<bool, Box<dyn std::error::Error>> {
    let total = match (args.minutes, args.seconds) {
        (Some(m), _) => m * 60.0,
        (None, Some(s)) => s,
        (None, None) => 60.0,
    };
    let positive = |x: f64| x.is_finite() && x > 0.0;
    if !positive(total) || !positive(args.timeout) {
        return Err(format!(
            "the fuzzing time ({total} s) and --timeout ({} s) must be positive",
            args.timeout
        )
        .into());
    }
    let all = targets();
    let chosen: Vec<&Target> = match &args.target {
        Some(name) => {
            let target = all.iter().find(|t| t.name == name).ok_or_else(|| {
                let names: Vec<&str> = all.iter().map(|t| t.name).collect();
                format!("no fuzz target '{name}'; the targets are {names:?}")
            })?;
            vec![target]
        }
        None => all.iter().collect(),
    };
    let share = Duration::from_secs_f64(total / chosen.len() as f64);
    let timeout = Duration::from_secs_f64(args.timeout);
    println!("| target | runs | accepted | seconds | panics | hangs | non-finite | slow |");
    println!("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |");
    let mut clean = true;
    for target in chosen {
        let f = fuzz_target(
            target,
            share,
            usize::MAX,
            args.seed,
            timeout,
            Some(&args.out),
        );
        clean &= f.panics == 0 && f.hangs == 0 && f.non_finite == 0;
        println!(
            "| {} | {} | {} | {:.1} | {} | {} | {} | {} |",
            target.name, f.runs, f.accepted, f.seconds, f.panics, f.hangs, f.non_finite, f.slow
        );
    }
    if !clean {
        println!(
            "failing inputs (minimised) are in {}; commit each as a regression case in \
             tests/fuzz-regressions/<target>/",
            args.out.display()
        );
    }
    Ok(clean)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every committed regression input runs to a verdict that is not a failure.
    #[test]
    fn committed_regressions_do_not_fail() {
        let root = workspace_root().join("tests/fuzz-regressions");
        let mut replayed = 0;
        for target in targets() {
            let dir = root.join(target.name);
            let Ok(entries) = std::fs::read_dir(&dir) else {
                continue;
            };
            let _quiet = QuietPanics::install();
            for entry in entries {
                let path = entry.unwrap().path();
                if path.extension().is_some_and(|e| e == "txt") {
                    continue;
                }
                let input = std::fs::read(&path).unwrap();
                let outcome = run_one(target.run, &input, Duration::from_secs(20));
                assert!(
                    failure_kind(&outcome).is_none(),
                    "{}: {outcome:?}",
                    path.display()
                );
                replayed += 1;
            }
        }
        assert!(replayed > 0, "no regression inputs in {}", root.display());
    }

    /// A short deterministic run of every target finds no failure, and each target accepts
    /// most of its seeds.
    #[test]
    fn a_short_run_of_every_target_finds_nothing() {
        for target in targets() {
            let seeds = (target.seeds)();
            assert!(!seeds.is_empty(), "{}", target.name);
            // Some Gmsh fixtures are bad on purpose (second-order elements, ...).
            let accepted = seeds
                .iter()
                .filter(|seed| (target.run)(seed) == Verdict::Accepted)
                .count();
            assert!(
                2 * accepted > seeds.len(),
                "{}: {accepted} of {} seeds accepted",
                target.name,
                seeds.len()
            );
            let f = fuzz_target(
                &target,
                Duration::from_secs(60),
                150,
                7,
                Duration::from_secs(20),
                None,
            );
            assert_eq!(f.runs, 150, "{}", target.name);
            assert_eq!(
                (f.panics, f.hangs, f.non_finite),
                (0, 0, 0),
                "{}",
                target.name
            );
        }
    }

    #[test]
    fn minimisation_keeps_the_failure_and_shrinks_the_input() {
        fn run(input: &[u8]) -> Verdict {
            if input.windows(3).any(|w| w == b"bad") {
                Verdict::NonFinite("bad".into())
            } else {
                Verdict::Rejected
            }
        }
        let input = b"a long input with bad inside of it".to_vec();
        let minimal = minimise(run, &input, "non-finite", Duration::from_secs(5), 1000);
        assert_eq!(minimal, b"bad");
    }
}
