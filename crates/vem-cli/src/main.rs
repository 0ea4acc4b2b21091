//! `vem`: contact scenes in TOML, solved with the lowest-order virtual element method.

use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Duration;

use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use vem_cli::resources::{LimitOrigin, MemoryLimit};
use vem_cli::{convert_mesh, default_output_dir, generate_mesh_within, CliError, Model, Scene};
use vem_scene::{OutputFiles, VtuEncodingName};

/// Contact of elastic bodies with the lowest-order virtual element method (VEM).
///
/// A scene file (TOML) describes the bodies (mesh, material, boundary conditions by part
/// name) and their contact pairs (another body or a rigid obstacle; frictionless, Tresca or
/// Coulomb), solved together, at once or along a load history. The format is documented key by key in docs/scenes.md; example scenes
/// are in crates/vem-cli/scenes/.
#[derive(Debug, Parser)]
#[command(name = "vem", version, about, long_about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Solve a scene and write its results.
    ///
    /// Writes into DIR: one BODY.vtu per body (displacement; stress, von Mises stress and
    /// the A1 quality figures per element; contact pressure at interface nodes), contact.csv
    /// (one row per interface node), summary.json (what was built, DOFs, constraint rows,
    /// solver, iterations, KKT residuals, resultants, times), deformed.svg (the deformed
    /// bodies, magnified, coloured by von Mises stress, with the obstacle), pressure.svg and,
    /// with friction, slip.svg; with contact, interface.vtu (the interface nodes and their
    /// values) and results.pvd (opens every body and the interface at once); with a load
    /// history of several steps also BODY_NNNN.vtu, interface_NNNN.vtu and contact_NNNN.csv
    /// per step, results.pvd over the steps, history.csv and history.svg (load-displacement
    /// curves). `--files` (or the scene's `[output] files`) keeps fewer kinds of files besides
    /// summary.json; `--vtu-encoding` writes the .vtu files compressed or as text. Prints a
    /// short summary.
    Run {
        /// The scene file (TOML).
        scene: PathBuf,
        /// Output directory [default: out/SCENE_STEM].
        #[arg(long, short, value_name = "DIR")]
        out: Option<PathBuf>,
        /// The memory the run may plan to use, in GiB [default: the scene's `[limits]
        /// memory_gib`, else the memory available].
        #[arg(long, value_name = "GIB")]
        memory_limit: Option<f64>,
        /// Displacement magnification of deformed.svg [default: the scene's `[output]
        /// magnification`, else the largest displacement drawn as 8% of the picture's extent,
        /// rounded down to 1, 2 or 5 times a power of ten, never below 1].
        #[arg(long, value_name = "FACTOR")]
        magnification: Option<f64>,
        /// The encoding of the .vtu files: binary, compressed or ascii [default: the scene's
        /// `[output] vtu_encoding`, else binary: raw appended data, the interface's
        /// zlib-compressed].
        #[arg(long, value_name = "ENCODING", value_parser = parse_encoding)]
        vtu_encoding: Option<VtuEncodingName>,
        /// The kinds of files written besides summary.json, separated by commas: vtu (the
        /// .vtu files and results.pvd), csv (the tables), pictures (the SVG pictures and
        /// plots), or none (the summary alone) [default: the scene's `[output] files`, else
        /// all three].
        #[arg(long, value_name = "KINDS", value_delimiter = ',', value_parser = parse_kind)]
        files: Option<Vec<Option<OutputFiles>>>,
    },
    /// Check a scene without solving it.
    ///
    /// Reads the scene, builds its meshes and checks every name against them; prints the
    /// mesh quality (the A1 figures: shortest edge and star-shapedness radius relative to the
    /// element diameter) of every body and what will be modelled.
    Check {
        /// The scene file (TOML).
        scene: PathBuf,
        /// The memory the run may plan to use, in GiB [default: the scene's `[limits]
        /// memory_gib`, else the memory available].
        #[arg(long, value_name = "GIB")]
        memory_limit: Option<f64>,
    },
    /// Generate a mesh of a family, or convert a Gmsh file, to .vtu and .svg.
    ///
    /// Examples: `vem mesh --family voronoi --n 16 --seed 1 --rect 0,0,1,1` writes
    /// out/mesh/voronoi-16.vtu and .svg; `vem mesh disc.msh` writes out/mesh/disc.vtu and
    /// .svg. Prints the A1 quality figures.
    Mesh {
        /// A Gmsh .msh file (format 4.1) to convert (instead of --family).
        #[arg(conflicts_with = "family", required_unless_present = "family")]
        file: Option<PathBuf>,
        /// Mesh family: quads, triangles, hexagons, voronoi, perturbed (or perturbed:0.2),
        /// nonconvex, hanging.
        #[arg(long)]
        family: Option<String>,
        /// Size: about N cells across the rectangle.
        #[arg(long, default_value_t = 8)]
        n: usize,
        /// Seed of the random families (voronoi, perturbed).
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// The rectangle x0,y0,x1,y1.
        #[arg(long, default_value = "0,0,1,1", value_parser = parse_rectangle)]
        rect: [f64; 4],
        /// Output directory.
        #[arg(long, short, value_name = "DIR", default_value = "out/mesh")]
        out: PathBuf,
        /// The memory the mesh may take, in GiB [default: the memory available].
        #[arg(long, value_name = "GIB")]
        memory_limit: Option<f64>,
    },
}

/// Parses `x0,y0,x1,y1`.
fn parse_rectangle(text: &str) -> Result<[f64; 4], String> {
    let values: Vec<f64> = text
        .split(',')
        .map(|v| v.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|e| format!("'{text}': {e}; expected x0,y0,x1,y1"))?;
    values
        .try_into()
        .map_err(|v: Vec<f64>| format!("'{text}' has {} numbers; expected x0,y0,x1,y1", v.len()))
}

/// A spinner on standard error, hidden when standard error is not a terminal.
fn spinner() -> ProgressBar {
    if !std::io::stderr().is_terminal() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new_spinner();
    if let Ok(style) = ProgressStyle::with_template("{spinner} {msg} ({elapsed})") {
        bar.set_style(style);
    }
    bar.enable_steady_tick(Duration::from_millis(100));
    bar
}

/// The scene at `path` with the command line's memory limit, if any.
fn load(path: &Path, memory_limit: Option<f64>) -> Result<Scene, CliError> {
    let scene = Scene::load(path)?;
    Ok(match memory_limit {
        Some(gib) => scene.with_memory_limit(command_line_limit(gib)?),
        None => scene,
    })
}

/// `--vtu-encoding`.
fn parse_encoding(name: &str) -> Result<VtuEncodingName, String> {
    name.parse()
}

/// A kind of `--files`: `None` for `none` (the summary alone).
fn parse_kind(name: &str) -> Result<Option<OutputFiles>, String> {
    match name {
        "none" => Ok(None),
        kind => kind
            .parse()
            .map(Some)
            .map_err(|e: String| format!("{e} or `none`")),
    }
}

/// The output settings of the command line, over the scene's.
struct OutputArgs {
    magnification: Option<f64>,
    vtu_encoding: Option<VtuEncodingName>,
    files: Option<Vec<Option<OutputFiles>>>,
}

impl OutputArgs {
    /// Checks the settings before the run.
    fn check(&self) -> Result<(), CliError> {
        if let Some(m) = self.magnification {
            if !(m.is_finite() && m > 0.0) {
                return Err(CliError::Usage(format!(
                    "--magnification {m}: give a finite number > 0"
                )));
            }
        }
        if let Some(files) = &self.files {
            if files.contains(&None) && files.iter().any(Option::is_some) {
                return Err(CliError::Usage(
                    "--files: `none` (summary.json alone) cannot be given with other kinds"
                        .to_string(),
                ));
            }
        }
        Ok(())
    }

    /// Applies the settings to `outcome`.
    fn apply(&self, outcome: &mut vem_cli::Outcome) {
        if let Some(m) = self.magnification {
            outcome.set_magnification(m);
        }
        if let Some(encoding) = self.vtu_encoding {
            outcome.set_vtu_encoding(encoding);
        }
        if let Some(files) = &self.files {
            let kinds: Vec<OutputFiles> = files.iter().flatten().copied().collect();
            outcome.set_files(&kinds);
        }
    }
}

fn command_line_limit(gib: f64) -> Result<MemoryLimit, CliError> {
    MemoryLimit::try_from_gib(gib, LimitOrigin::CommandLine).map_err(CliError::Usage)
}

fn run(
    scene: &Path,
    out: Option<PathBuf>,
    memory_limit: Option<f64>,
    output: OutputArgs,
) -> Result<(), CliError> {
    output.check()?;
    let progress = spinner();
    progress.set_message(format!("reading {}", scene.display()));
    let scene = load(scene, memory_limit)?;
    progress.set_message("building meshes and bodies");
    let model = Model::build(&scene)?;
    progress.set_message("solving");
    let mut outcome = model.solve()?;
    output.apply(&mut outcome);
    let dir = out.unwrap_or_else(|| default_output_dir(&scene));
    progress.set_message(format!("writing {}", dir.display()));
    let files = outcome.write(&dir)?;
    progress.finish_and_clear();
    let names: Vec<String> = files
        .iter()
        .filter_map(|f| f.file_name().map(|n| n.to_string_lossy().into_owned()))
        .collect();
    emit(&format!(
        "{}wrote {}: {}\n",
        outcome.summary(),
        dir.display(),
        names.join(", ")
    ))
}

fn check(scene: &Path, memory_limit: Option<f64>) -> Result<(), CliError> {
    let progress = spinner();
    progress.set_message(format!("checking {}", scene.display()));
    let scene = load(scene, memory_limit)?;
    let report = Model::build(&scene)?.check()?;
    progress.finish_and_clear();
    emit(&report.to_string())
}

/// Writes `text` to standard output. A closed pipe (`vem check scene.toml | head`) is not an
/// error: the reader has what it wanted; any other failure (a full disk) is.
fn emit(text: &str) -> Result<(), CliError> {
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(CliError::Io {
            action: "write to",
            path: PathBuf::from("standard output"),
            source: e,
        }),
        _ => Ok(()),
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    // Errors are values; a panic is a bug. The default hook's message and backtrace are not
    // shown (a library may catch a panic of a dependency and return an error instead); an
    // uncaught one is reported below in one line.
    std::panic::set_hook(Box::new(|_| {}));
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| execute(cli)))
        .unwrap_or_else(|payload| {
            let what = payload
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "no message".to_string());
            Err(CliError::Usage(format!(
                "internal error (a bug in vem, please report it with the input): {what}"
            )))
        });
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // Standard error may be closed too: nothing more can be said then.
            let _ = writeln!(std::io::stderr().lock(), "error: {}", e.chain());
            ExitCode::FAILURE
        }
    }
}

/// Runs the command of `cli`.
fn execute(cli: Cli) -> Result<(), CliError> {
    match cli.command {
        Command::Run {
            scene,
            out,
            memory_limit,
            magnification,
            vtu_encoding,
            files,
        } => run(
            &scene,
            out,
            memory_limit,
            OutputArgs {
                magnification,
                vtu_encoding,
                files,
            },
        ),
        Command::Check {
            scene,
            memory_limit,
        } => check(&scene, memory_limit),
        Command::Mesh {
            file,
            family,
            n,
            seed,
            rect,
            out,
            memory_limit,
        } => match (file, family) {
            (Some(file), _) => convert_mesh(&file, &out),
            (None, Some(family)) => memory_limit
                .map_or_else(|| Ok(MemoryLimit::available()), command_line_limit)
                .and_then(|limit| generate_mesh_within(&family, n, seed, rect, &out, limit)),
            (None, None) => Err(CliError::Usage("give a .msh file or --family".to_string())),
        }
        .and_then(|report| emit(&report.to_string())),
    }
}
