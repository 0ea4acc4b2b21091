//! The files of `vem run`, written as a set, all or nothing: one `.vtu` per body,
//! `contact.csv`, the pictures and plots (SVG) and `summary.json` are written into a fresh
//! temporary folder beside the output folder (`.NAME.PID.N.tmp`), which is then renamed into
//! place; an earlier result in the output folder is replaced as a whole, so a reader never
//! sees new pictures beside an old summary. Temporaries left by killed runs are removed.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

use vem_contact::{InterfaceNode, NodeStatus, Obstacle};
use vem_elastic::ElementField;
use vem_mesh::io::{
    remove_stale_temporaries, temporary_sibling, write_atomically, write_svg_layers,
    write_vtu_with, CellType, Cells, PvdCollection, SvgLayer, SvgMarks, SvgOptions,
    UnstructuredGrid, VtkArray, VtuData,
};
use vem_mesh::{Mesh, PartSpec, Point, Vector};

use crate::plot;
use crate::{CliError, Outcome};
use vem_scene::SolvedBody;

/// The columns of `contact.csv`, in order.
pub const CONTACT_COLUMNS: &str =
    "pair,x,y,nx,ny,initial_gap,normal_jump,normal_force,pressure,consistent_pressure,friction_force,\
     consistent_friction_traction,slip,status";

/// Default width of pictures and plots, in pixels.
pub const DEFAULT_WIDTH: f64 = 900.0;

/// Fraction of the picture's extent that the largest displacement is drawn as, when the
/// scene does not give a magnification.
const AUTO_DISPLACEMENT_FRACTION: f64 = 0.08;

impl Outcome {
    /// Writes every output file into `dir` (created if needed) and returns their paths:
    /// `<body>.vtu` for each body, `deformed.svg`, and with a contact pair `contact.csv`,
    /// `pressure.svg` (and `slip.svg` with friction), with `adapt` `adapt.csv`;
    /// `summary.json` last, with the output and total times. Only the kinds of files of the
    /// scene's `[output] files` ([`Outcome::set_files`]) are written besides the summary.
    ///
    /// The set is written into a fresh folder beside `dir` and renamed into place: `dir`
    /// holds either its earlier contents or the whole new set. `dir` must be new, empty, or
    /// hold only the files of an earlier run (`.vtu`, `.pvd`, `.svg`, `.csv`, `.json`): a folder
    /// holding anything else is refused rather than replaced.
    pub fn write(&mut self, dir: &Path) -> Result<Vec<PathBuf>, CliError> {
        let staging = Staging::begin(dir)?;
        let written = self.write_into(staging.path())?;
        staging.commit()?;
        Ok(written
            .iter()
            .filter_map(|p| p.file_name().map(|name| dir.join(name)))
            .collect())
    }

    /// Writes every output file into the existing folder `dir`.
    fn write_into(&mut self, dir: &Path) -> Result<Vec<PathBuf>, CliError> {
        if self.dimension() == 3 {
            return self.write_into_3d(dir);
        }
        let start = Instant::now();
        let mut written = Vec::new();
        let width = self.width();
        // The bodies' files, then the interface's and the contact's, on a thread of their own
        // beside the picture (independent files; the picture's rasterisation and compression
        // are as long as a large body's file).
        let this = &*self;
        let (data, contact_files, deformed) = std::thread::scope(|scope| {
            let files = scope.spawn(|| {
                let mut data = if this.output.files.vtu {
                    this.write_bodies(dir)?
                } else {
                    Vec::new()
                };
                data.extend(this.write_interface_and_collection(dir)?);
                Ok::<_, CliError>((data, this.write_contact_files(dir, width)))
            });
            let deformed = this.output.files.pictures.then(|| {
                let path = dir.join("deformed.svg");
                this.write_deformed(&path, width)
                    .map(|()| path.clone())
                    .map_err(mesh_error(&path))
            });
            let files = files
                .join()
                .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
            files.map(|(data, contact_files)| (data, contact_files, deformed))
        })?;
        // In the order of the files, the first failure reported.
        written.extend(data);
        written.extend(deformed.transpose()?);
        written.extend(contact_files?);
        written.push(self.write_summary(dir, start)?);
        Ok(written)
    }

    /// `summary.json`, last, with the output time from `start` and the total time.
    pub(crate) fn write_summary(
        &mut self,
        dir: &Path,
        start: Instant,
    ) -> Result<PathBuf, CliError> {
        let path = dir.join("summary.json");
        self.set_output_time(start.elapsed());
        let json = serde_json::to_string_pretty(&self.summary).map_err(|e| CliError::Io {
            action: "serialise",
            path: path.clone(),
            source: e.into(),
        })?;
        write_atomically(&path, |w| writeln!(w, "{json}")).map_err(mesh_error(&path))?;
        Ok(path)
    }

    /// `interface.vtu` with contact, then `results.pvd` (or the files of a load history).
    fn write_interface_and_collection(&self, dir: &Path) -> Result<Vec<PathBuf>, CliError> {
        let mut written = Vec::new();
        if let Some(contact) = self.contact.as_ref().filter(|_| self.output.files.vtu) {
            let path = dir.join("interface.vtu");
            interface_grid(&contact.nodes, &contact.model.pairs)
                .write(&path, self.interface_encoding())
                .map_err(mesh_error(&path))?;
            written.push(path);
        }
        if !self.steps.is_empty() {
            written.extend(self.write_history(dir)?);
        } else if self.output.files.vtu {
            // One collection that opens every body and the interface at once.
            let mut collection = PvdCollection::new();
            for (part, solved) in self.bodies.iter().enumerate() {
                let name = solved.body.name();
                collection.add(0.0, part, name, format!("{name}.vtu"));
            }
            if self.contact.is_some() {
                collection.add(0.0, self.bodies.len(), "interface", "interface.vtu");
            }
            let path = dir.join("results.pvd");
            collection.write(&path).map_err(mesh_error(&path))?;
            written.push(path);
        }
        Ok(written)
    }

    /// With contact `contact.csv`, `pressure.svg` (and `slip.svg` with friction); with `adapt`
    /// `adapt.csv`.
    fn write_contact_files(&self, dir: &Path, width: f64) -> Result<Vec<PathBuf>, CliError> {
        let mut written = Vec::new();
        if let Some(contact) = self.contact.as_ref().filter(|_| self.output.files.csv) {
            let path = dir.join("contact.csv");
            let frictionless = contact.model.tangential_rows == 0;
            write_atomically(&path, |w| {
                write_contact_csv(w, &contact.nodes, &contact.model.pairs, frictionless)
            })
            .map_err(mesh_error(&path))?;
            written.push(path);
        }
        if let Some(contact) = self.contact.as_ref().filter(|_| self.output.files.pictures) {
            let hertz = self.summary.contact.as_ref().and_then(|c| c.hertz.first());
            // Cattaneo-Mindlin beside the friction traction of a Hertz pair with Coulomb
            // friction carrying a tangential load.
            let cattaneo = hertz.and_then(|h| {
                let coefficient = self.coulomb_coefficients.get(h.pair).copied().flatten()?;
                let tangential_load: f64 = contact
                    .nodes
                    .iter()
                    .filter(|n| n.pair == h.pair)
                    .map(|n| n.friction_t())
                    .sum();
                // Along a load history the last state is Cattaneo-Mindlin's only where the
                // tangential load is back at the largest of the history, within 1 % (Mindlin
                // and Deresiewicz: reaching it again erases the unloading's memory).
                let history = self
                    .summary
                    .contact
                    .as_ref()
                    .map_or(&[][..], |c| &c.history[..]);
                let largest = history
                    .iter()
                    .map(|s| s.force_on_body_a.first().copied().unwrap_or(0.0).abs())
                    .fold(0.0, f64::max);
                let back_at_largest = tangential_load.abs() >= (1.0 - 1e-2) * largest;
                (coefficient > 0.0
                    && tangential_load.abs() > 1e-9 * coefficient * h.load
                    && back_at_largest)
                    .then_some(plot::CattaneoMindlin {
                        coefficient,
                        tangential_load,
                    })
            });
            let path = dir.join("pressure.svg");
            plot::pressure(
                &path,
                &self.summary.title,
                &contact.nodes,
                hertz,
                self.friction_bounds.clone(),
                cattaneo,
                width,
            )?;
            written.push(path);
            if contact.model.tangential_rows > 0 {
                let path = dir.join("slip.svg");
                plot::slip(&path, &self.summary.title, &contact.nodes, width)?;
                written.push(path);
            }
        }
        if let Some(adapt) = self
            .summary
            .adaptivity
            .as_ref()
            .filter(|_| self.output.files.csv)
        {
            let path = dir.join("adapt.csv");
            write_atomically(&path, |w| write_adapt_csv(w, &adapt.cycles))
                .map_err(mesh_error(&path))?;
            written.push(path);
        }
        Ok(written)
    }

    /// `<body>.vtu` of every body, each on a thread of its own; the paths in the order of the
    /// bodies.
    fn write_bodies(&self, dir: &Path) -> Result<Vec<PathBuf>, CliError> {
        let nodes = self.contact.as_ref().map_or(&[][..], |c| &c.nodes[..]);
        let pressures = self.pressures(nodes);
        std::thread::scope(|scope| {
            let threads: Vec<_> = self
                .bodies
                .iter()
                .zip(pressures)
                .map(|(solved, pressure)| {
                    scope.spawn(move || {
                        let path = dir.join(format!("{}.vtu", solved.body.name()));
                        let data = vtu_data(
                            solved.solution.vertex_displacements(),
                            &solved.fields,
                            solved,
                            pressure,
                        );
                        write_vtu_with(&path, solved.body.mesh(), &data, self.body_encoding())
                            .map(|()| path.clone())
                            .map_err(|source| CliError::Mesh {
                                context: path.display().to_string(),
                                source,
                            })
                    })
                })
                .collect();
            threads
                .into_iter()
                .map(|t| {
                    t.join()
                        .unwrap_or_else(|panic| std::panic::resume_unwind(panic))
                })
                .collect()
        })
    }

    /// The raw and consistent contact pressure at the interface vertices of every body.
    fn pressures(&self, nodes: &[InterfaceNode]) -> Vec<Option<(Vec<f64>, Vec<f64>)>> {
        let raw = self.contact_pressure_at_vertices(nodes, |n| n.pressure);
        let consistent = self.contact_pressure_at_vertices(nodes, |n| n.consistent_pressure);
        raw.into_iter()
            .zip(consistent)
            .map(|(r, c)| r.zip(c))
            .collect()
    }

    /// The files of a load history of several steps: per step NNNN (from 1) `<body>_NNNN.vtu`
    /// of every body in contact, `interface_NNNN.vtu` and `contact_NNNN.csv`; `results.pvd`,
    /// the ParaView time series of them all at the steps' pseudo-times; `history.csv` and
    /// `history.svg`: the contact force on body A and the load point's displacement at every
    /// step.
    fn write_history(&self, dir: &Path) -> Result<Vec<PathBuf>, CliError> {
        let mut written = Vec::new();
        let Some(last) = &self.contact else {
            return Ok(written);
        };
        let frictionless = last.model.tangential_rows == 0;
        let steps = self
            .summary
            .contact
            .as_ref()
            .map_or(&[][..], |c| &c.history[..]);
        let mut series = PvdCollection::new();
        let count = self.steps.len() + 1;
        for k in 0..count {
            let (nodes, time) = match self.steps.get(k) {
                Some(step) => (&step.result.nodes, step.time),
                None => (&last.nodes, steps.last().map_or(1.0, |s| s.time)),
            };
            let label = format!("{:04}", k + 1);
            if self.output.files.csv {
                let path = dir.join(format!("contact_{label}.csv"));
                write_atomically(&path, |w| {
                    write_contact_csv(w, nodes, &last.model.pairs, frictionless)
                })
                .map_err(mesh_error(&path))?;
                written.push(path);
            }
            if !self.output.files.vtu {
                continue;
            }
            let pressures = self.pressures(nodes);
            for (b, &index) in self.contact_bodies.iter().enumerate() {
                let solved = &self.bodies[index];
                let name = solved.body.name();
                let file = format!("{name}_{label}.vtu");
                let path = dir.join(&file);
                let data = match self.steps.get(k) {
                    Some(step) => {
                        let body = &step.result.bodies[b];
                        let fields = body
                            .body
                            .element_fields(body.solution.displacement())
                            .map_err(|e| CliError::Elastic(Box::new(e)))?;
                        vtu_data(
                            body.solution.vertex_displacements(),
                            &fields,
                            solved,
                            pressures[index].clone(),
                        )
                    }
                    None => vtu_data(
                        solved.solution.vertex_displacements(),
                        &solved.fields,
                        solved,
                        pressures[index].clone(),
                    ),
                };
                write_vtu_with(&path, solved.body.mesh(), &data, self.body_encoding())
                    .map_err(mesh_error(&path))?;
                series.add(time, b, name, file);
                written.push(path);
            }
            let file = format!("interface_{label}.vtu");
            let path = dir.join(&file);
            interface_grid(nodes, &last.model.pairs)
                .write(&path, self.interface_encoding())
                .map_err(mesh_error(&path))?;
            series.add(time, self.contact_bodies.len(), "interface", file);
            written.push(path);
        }
        if self.output.files.vtu {
            let path = dir.join("results.pvd");
            series.write(&path).map_err(mesh_error(&path))?;
            written.push(path);
        }
        if self.output.files.csv {
            let path = dir.join("history.csv");
            write_atomically(&path, |w| write_history_csv(w, steps)).map_err(mesh_error(&path))?;
            written.push(path);
        }
        if self.output.files.pictures {
            let path = dir.join("history.svg");
            plot::history(&path, &self.summary.title, steps, self.width())?;
            written.push(path);
        }
        Ok(written)
    }

    /// Picture width: the scene's `[output] width` or [`DEFAULT_WIDTH`].
    fn width(&self) -> f64 {
        self.output_width.unwrap_or(DEFAULT_WIDTH)
    }

    /// For each body, a nodal value (`value` of each interface node) at its interface vertices
    /// (zero elsewhere).
    fn contact_pressure_at_vertices(
        &self,
        nodes: &[InterfaceNode],
        value: impl Fn(&InterfaceNode) -> f64,
    ) -> Vec<Option<Vec<f64>>> {
        let mut pressure: Vec<Option<Vec<f64>>> = vec![None; self.bodies.len()];
        for node in nodes {
            let sides = [
                (node.body_a, Some(node.vertex_a)),
                (node.body_b.unwrap_or(usize::MAX), node.vertex_b),
            ];
            for (body, vertex) in sides {
                let (Some(&index), Some(v)) = (self.contact_bodies.get(body), vertex) else {
                    continue;
                };
                let values = pressure[index]
                    .get_or_insert_with(|| vec![0.0; self.bodies[index].body.mesh().n_vertices()]);
                values[v] = value(node);
            }
        }
        pressure
    }

    /// The deformed bodies, coloured by von Mises stress, over their undeformed outlines,
    /// with axes, the displacement scale and the obstacles (each moved by the magnified part
    /// of the gap its nodes in contact closed, so that the bodies meet it as they do at true
    /// scale); interface nodes that penetrate are marked.
    fn write_deformed(&self, path: &Path, width: f64) -> Result<(), vem_mesh::MeshError> {
        let displacements: Vec<Vec<Vector>> = self
            .bodies
            .iter()
            .map(|b| b.solution.vertex_displacements())
            .collect();
        let von_mises: Vec<Vec<f64>> = self
            .bodies
            .iter()
            .map(|b| b.fields.iter().map(|f| f.von_mises).collect())
            .collect();
        let (min, max) = bounding_box(self.bodies.iter().map(|b| b.body.mesh()));
        let extent = (max - min).norm();
        let largest = displacements
            .iter()
            .flatten()
            .map(|u| u.norm())
            .fold(0.0, f64::max);
        let magnification = self
            .magnification
            .unwrap_or_else(|| automatic_magnification(extent, largest));
        let mut layers: Vec<SvgLayer> = self
            .bodies
            .iter()
            .zip(&displacements)
            .zip(&von_mises)
            .map(|((b, u), s)| {
                SvgLayer::new(b.body.mesh())
                    .with_label(b.body.name())
                    .with_displacement(u)
                    .with_cell_values(s)
            })
            .collect();
        let nodes = self.contact.as_ref().map_or(&[][..], |c| &c.nodes[..]);
        let shifts: Vec<Vector> = self
            .obstacles
            .iter()
            .map(|(pair, _)| obstacle_shift(nodes, *pair, magnification))
            .collect();
        let outlines: Vec<Mesh> = self
            .obstacles
            .iter()
            .zip(&shifts)
            .filter_map(|((_, o), &shift)| obstacle_outline(&translated(o, shift), min, max))
            .collect();
        for mesh in &outlines {
            layers.push(SvgLayer::new(mesh).with_label("obstacle"));
        }
        let (lo, hi) = von_mises
            .iter()
            .flatten()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
                (lo.min(v), hi.max(v))
            });
        // A uniform stress (to round-off) gets one colour, not a map of its rounding noise.
        let value_range = (hi - lo <= 1e-6 * hi.abs()).then(|| {
            let pad = 0.05 * hi.abs().max(f64::MIN_POSITIVE);
            (lo - pad, hi + pad)
        });
        // Penetration: interface nodes whose normal jump exceeds the initial gap by more than
        // a thousandth of the largest displacement, marked where body A is drawn.
        let tolerance = 1e-3 * largest;
        let mut deepest = 0.0_f64;
        let penetrating: Vec<Point> = nodes
            .iter()
            .filter(|n| n.normal_jump - n.initial_gap > tolerance)
            .filter_map(|n| {
                deepest = deepest.max(n.normal_jump - n.initial_gap);
                let &body = self.contact_bodies.get(n.body_a)?;
                let u = displacements.get(body)?.get(n.vertex_a)?;
                Some(self.bodies[body].body.mesh().vertex(n.vertex_a) + magnification * u)
            })
            .collect();
        let marks = (!penetrating.is_empty()).then(|| SvgMarks {
            label: format!("penetration (deepest {})", four_digits(deepest)),
            points: penetrating,
        });
        let factor = vem_scene::short(magnification);
        let mut notes = vec![
            format!("displacements drawn x {factor}"),
            format!("(largest |u| = {})", four_digits(largest)),
        ];
        if shifts.iter().any(|s| s.norm() > 0.0) {
            notes.push(format!(
                "obstacle moved by {} x gap",
                vem_scene::short(magnification - 1.0)
            ));
        }
        let options = SvgOptions {
            width,
            value_range,
            title: Some(format!(
                "{}: von Mises stress, displacements x {factor}",
                self.summary.title
            )),
            magnification,
            value_label: match &self.stress_unit {
                Some(unit) => format!("von Mises stress [{unit}]"),
                None => "von Mises stress (unit of E)".into(),
            },
            axes: true,
            length_unit: self.length_unit.clone(),
            notes,
            marks,
            ..SvgOptions::default()
        };
        write_svg_layers(path, &layers, &options)
    }
}

/// The error of writing the file `path`, for `map_err`.
pub(crate) fn mesh_error(path: &Path) -> impl FnOnce(vem_mesh::MeshError) -> CliError {
    let context = path.display().to_string();
    move |source| CliError::Mesh { context, source }
}

/// `value` to four significant digits, as the summary prints numbers.
fn four_digits(value: f64) -> String {
    vem_scene::short(format!("{value:.3e}").parse().unwrap_or(value))
}

/// The displacement magnification of `deformed.svg` when the scene gives none: the largest
/// displacement drawn as [`AUTO_DISPLACEMENT_FRACTION`] of the bodies' extent (the diagonal
/// of their box), rounded down to 1, 2 or 5 times a power of ten, and never below 1 (a
/// displacement already that large is drawn at true scale, not shrunk).
fn automatic_magnification(extent: f64, largest: f64) -> f64 {
    if largest > 0.0 && extent > 0.0 {
        round_down_to_nice(AUTO_DISPLACEMENT_FRACTION * extent / largest).max(1.0)
    } else {
        1.0
    }
}

/// The translation of the obstacle of pair `pair` in a picture magnified `magnification`
/// times: `(magnification - 1)` times the mean of `h0 nu` over the pair's nodes in contact.
/// A node that closed its gap `h0` is drawn `magnification h0` along `nu`; the obstacle moved
/// so leaves it touching, and a penetration is drawn magnified like the displacements.
fn obstacle_shift(nodes: &[InterfaceNode], pair: usize, magnification: f64) -> Vector {
    let (sum, count) = nodes
        .iter()
        .filter(|n| n.pair == pair && n.body_b.is_none() && n.status.is_active())
        .fold((Vector::zeros(), 0usize), |(s, c), n| {
            (s + n.initial_gap * n.normal, c + 1)
        });
    if count == 0 {
        return Vector::zeros();
    }
    (magnification - 1.0) * sum / count as f64
}

/// `obstacle` translated by `shift`.
fn translated(obstacle: &Obstacle, shift: Vector) -> Obstacle {
    match obstacle {
        Obstacle::Line { point, normal } => Obstacle::Line {
            point: point + shift,
            normal: *normal,
        },
        Obstacle::Circle { centre, radius } => Obstacle::Circle {
            centre: centre + shift,
            radius: *radius,
        },
        Obstacle::Polyline(points) => {
            Obstacle::Polyline(points.iter().map(|p| p + shift).collect())
        }
    }
}

/// The fresh temporary folder a run's outputs are written into, beside the output folder;
/// removed when dropped unless committed.
struct Staging {
    temporary: PathBuf,
    target: PathBuf,
    committed: bool,
}

/// The extensions of the files a run writes.
const OUTPUT_EXTENSIONS: [&str; 5] = ["vtu", "pvd", "svg", "csv", "json"];

impl Staging {
    /// Checks `target` (new, empty or an earlier run's), removes stale temporaries beside
    /// and in it, and creates the temporary folder.
    fn begin(target: &Path) -> Result<Self, CliError> {
        let io = |action: &'static str, path: &Path| {
            let path = path.to_path_buf();
            move |source| CliError::Io {
                action,
                path,
                source,
            }
        };
        if target.file_name().is_none_or(|n| n == "." || n == "..") {
            return Err(CliError::Usage(format!(
                "output folder '{}': name a folder (not '.' or '..'), e.g. out/run",
                target.display()
            )));
        }
        let parent = match target.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        std::fs::create_dir_all(&parent).map_err(io("create the directory", &parent))?;
        remove_stale_temporaries(&parent).map_err(io("clean the temporaries in", &parent))?;
        if target.is_dir() {
            remove_stale_temporaries(target).map_err(io("clean the temporaries in", target))?;
            let entries = std::fs::read_dir(target).map_err(io("read", target))?;
            for entry in entries {
                let entry = entry.map_err(io("read", target))?;
                let path = entry.path();
                let ours = path.is_file()
                    && path
                        .extension()
                        .and_then(|e| e.to_str())
                        .is_some_and(|e| OUTPUT_EXTENSIONS.contains(&e));
                if !ours {
                    return Err(CliError::Usage(format!(
                        "output folder '{}' holds '{}', which no run writes: the folder is \
                         replaced as a whole, so give a new or empty folder, or one of an \
                         earlier run",
                        target.display(),
                        entry.file_name().to_string_lossy()
                    )));
                }
            }
        } else if target.exists() {
            return Err(CliError::Usage(format!(
                "output folder '{}' is a file",
                target.display()
            )));
        }
        loop {
            let temporary =
                temporary_sibling(target).map_err(io("name a folder beside", target))?;
            match std::fs::create_dir(&temporary) {
                Ok(()) => {
                    return Ok(Self {
                        temporary,
                        target: target.to_path_buf(),
                        committed: false,
                    })
                }
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => continue,
                Err(e) => return Err(io("create the directory", &temporary)(e)),
            }
        }
    }

    fn path(&self) -> &Path {
        &self.temporary
    }

    /// Renames the temporary folder to the target; an earlier target is moved aside first
    /// (to `.NAME.PID.N.old`, removed afterwards) and moved back if the rename fails.
    fn commit(mut self) -> Result<(), CliError> {
        let io = |path: &Path| {
            let path = path.to_path_buf();
            move |source| CliError::Io {
                action: "move the results into",
                path,
                source,
            }
        };
        // `.NAME.PID.N.tmp` -> `.NAME.PID.N.old`.
        let old = self.temporary.with_extension("old");
        let replaced = self.target.exists();
        if replaced {
            std::fs::rename(&self.target, &old).map_err(io(&self.target))?;
        }
        if let Err(e) = std::fs::rename(&self.temporary, &self.target) {
            if replaced {
                let _ = std::fs::rename(&old, &self.target);
            }
            return Err(io(&self.target)(e));
        }
        self.committed = true;
        if replaced {
            // What is left (a failure here) is removed as stale by a later run.
            let _ = std::fs::remove_dir_all(&old);
        }
        Ok(())
    }
}

impl Drop for Staging {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_dir_all(&self.temporary);
        }
    }
}

/// The largest of 1, 2, 5 times a power of ten not above `value` (value > 0).
fn round_down_to_nice(value: f64) -> f64 {
    let power = 10f64.powf(value.log10().floor());
    let mantissa = value / power;
    let nice = if mantissa >= 5.0 {
        5.0
    } else if mantissa >= 2.0 {
        2.0
    } else {
        1.0
    };
    nice * power
}

/// Point data (displacement, raw and consistent contact pressure) and cell data (stress, von Mises, A1 figures,
/// the error indicator) of one body.
fn vtu_data(
    displacements: Vec<Vector>,
    fields: &[ElementField],
    solved: &SolvedBody,
    contact_pressure: Option<(Vec<f64>, Vec<f64>)>,
) -> VtuData {
    let stress: Vec<f64> = fields
        .iter()
        .flat_map(|f| [f.stress[(0, 0)], f.stress[(1, 1)], f.stress[(0, 1)]])
        .collect();
    let mut data = VtuData::new()
        .with_point_vectors("displacement", &displacements)
        .with_cell_data(vem_mesh::io::DataArray::new("stress_xx_yy_xy", 3, stress))
        .with_cell_scalars(
            "sigma_zz",
            fields.iter().map(|f| f.stress[(2, 2)]).collect(),
        )
        .with_cell_scalars("von_mises", fields.iter().map(|f| f.von_mises).collect())
        .with_point_data(vem_mesh::io::DataArray::new(
            "nodal_stress_xx_yy_xy",
            3,
            nodal_stress(solved.body.mesh(), fields),
        ))
        .with_cell_scalars(
            "quality_gamma",
            solved.qualities.iter().map(|q| q.gamma()).collect(),
        )
        .with_cell_scalars(
            "shortest_edge_ratio",
            solved
                .qualities
                .iter()
                .map(|q| q.shortest_edge_ratio)
                .collect(),
        )
        .with_cell_scalars(
            "star_ratio",
            solved.qualities.iter().map(|q| q.star_ratio).collect(),
        );
    if !solved.error_indicator.is_empty() {
        data = data.with_cell_scalars("error_indicator", solved.error_indicator.clone());
    }
    if let Some((raw, consistent)) = contact_pressure {
        data = data
            .with_point_scalars("contact_pressure", raw)
            .with_point_scalars("consistent_contact_pressure", consistent);
    }
    data
}

/// The stress recovered at the vertices: at each vertex the area-weighted mean of the stresses
/// (constant per element) of the elements around it, `xx, yy, xy` per vertex. A smooth field
/// for contour plots beside the cell values; it is not more accurate than they are.
fn nodal_stress(mesh: &Mesh, fields: &[ElementField]) -> Vec<f64> {
    let mut sum = vec![0.0; 3 * mesh.n_vertices()];
    let mut weight = vec![0.0; mesh.n_vertices()];
    for (p, field) in fields.iter().enumerate() {
        let area = mesh.area(p);
        let values = [
            field.stress[(0, 0)],
            field.stress[(1, 1)],
            field.stress[(0, 1)],
        ];
        for &v in mesh.polygon(p) {
            for (c, value) in values.iter().enumerate() {
                sum[3 * v + c] += area * value;
            }
            weight[v] += area;
        }
    }
    for (v, &w) in weight.iter().enumerate() {
        if w > 0.0 {
            for c in 0..3 {
                sum[3 * v + c] /= w;
            }
        }
    }
    sum
}

/// `contact.csv`: one row per interface node, columns [`CONTACT_COLUMNS`] (`pair`: the index of
/// the node's pair, counted from 0 in the order of the `[[contact]]` tables, as the interface
/// dataset's cell data `pair`), numbers in shortest round-trip scientific notation.
/// A node's status as the outputs name it: "open", "stick", "slip", and "contact" for a
/// node in contact without friction (where there is no stick or slip to tell apart).
pub fn status_label(status: NodeStatus, frictionless: bool) -> &'static str {
    match status {
        NodeStatus::Slip if frictionless => "contact",
        other => other.name(),
    }
}

/// The interface as a dataset of its own: per contact pair the segments between its
/// consecutive nodes (in their order along the interface), and at every node the columns of `contact.csv` as point
/// data (vectors in 3 components: `normal`, `friction_force`, `friction_traction` (the
/// consistent one), `slip`), the status as an integer `status` (0 open, 1 contact, 2 stick,
/// 3 slip) and the pair as cell data `pair`.
fn interface_grid(nodes: &[InterfaceNode], pairs: &[vem_contact::PairSummary]) -> UnstructuredGrid {
    let points: Vec<[f64; 3]> = nodes
        .iter()
        .map(|n| [n.position.x, n.position.y, 0.0])
        .collect();
    let mut cells = Cells::new();
    let mut pair_of_cell = Vec::new();
    for (k, pair) in pairs.iter().enumerate() {
        let indices: Vec<usize> = pair.nodes.clone().collect();
        if let [only] = indices[..] {
            cells.push(CellType::Vertex, &[only]);
            pair_of_cell.push(k as i32);
        }
        // Segments rather than one polyline: every reader (meshio too) takes them.
        for segment in indices.windows(2) {
            cells.push(CellType::Line, segment);
            pair_of_cell.push(k as i32);
        }
    }
    let vector = |v: &dyn Fn(&InterfaceNode) -> Vector| -> Vec<[f64; 3]> {
        nodes
            .iter()
            .map(|n| {
                let v = v(n);
                [v.x + 0.0, v.y + 0.0, 0.0]
            })
            .collect()
    };
    let scalar = |f: &dyn Fn(&InterfaceNode) -> f64| -> Vec<f64> {
        nodes.iter().map(|n| f(n) + 0.0).collect()
    };
    let status = |s: NodeStatus| match s {
        NodeStatus::Open => 0,
        NodeStatus::Contact => 1,
        NodeStatus::Stick => 2,
        NodeStatus::Slip => 3,
    };
    UnstructuredGrid::new(points, cells)
        .with_point_data(VtkArray::vectors("normal", &vector(&|n| n.normal)))
        .with_point_data(VtkArray::scalars("initial_gap", scalar(&|n| n.initial_gap)))
        .with_point_data(VtkArray::scalars("normal_jump", scalar(&|n| n.normal_jump)))
        .with_point_data(VtkArray::scalars(
            "normal_force",
            scalar(&|n| n.normal_force),
        ))
        .with_point_data(VtkArray::scalars("pressure", scalar(&|n| n.pressure)))
        .with_point_data(VtkArray::scalars(
            "consistent_pressure",
            scalar(&|n| n.consistent_pressure),
        ))
        .with_point_data(VtkArray::vectors(
            "friction_force",
            &vector(&|n| n.friction_force),
        ))
        .with_point_data(VtkArray::vectors(
            "friction_traction",
            &vector(&|n| n.consistent_friction_traction),
        ))
        .with_point_data(VtkArray::vectors("slip", &vector(&|n| n.slip)))
        .with_point_data(VtkArray::int32(
            "status",
            nodes.iter().map(|n| status(n.status)).collect(),
        ))
        .with_cell_data(VtkArray::int32("pair", pair_of_cell))
}

/// The columns of `adapt.csv`, in order.
pub const ADAPT_COLUMNS: &str = "cycle,unknowns,cells,estimate,relative_estimate,marked,time_s";

/// `adapt.csv`: one row per cycle of an adaptive run, columns [`ADAPT_COLUMNS`].
fn write_adapt_csv(w: &mut dyn Write, cycles: &[vem_scene::AdaptCycle]) -> std::io::Result<()> {
    writeln!(w, "{ADAPT_COLUMNS}")?;
    for c in cycles {
        writeln!(
            w,
            "{},{},{},{:e},{:e},{},{:.6}",
            c.cycle, c.unknowns, c.cells, c.estimate, c.relative_estimate, c.marked, c.time_s
        )?;
    }
    Ok(())
}

/// `history.csv`: one row per step: its pseudo-time, the load point's displacement, the
/// contact force on body A, the sum of the normal forces and the node counts.
fn write_history_csv(w: &mut dyn Write, steps: &[vem_scene::StepSummary]) -> std::io::Result<()> {
    writeln!(
        w,
        "t,ux,uy,force_x,force_y,normal_resultant,open,contact,stick,slip"
    )?;
    for s in steps {
        let at = |v: &[f64], c: usize| v.get(c).copied().unwrap_or(f64::NAN);
        writeln!(
            w,
            "{:e},{:e},{:e},{:e},{:e},{:e},{},{},{},{}",
            s.time,
            at(&s.displacement, 0),
            at(&s.displacement, 1),
            at(&s.force_on_body_a, 0),
            at(&s.force_on_body_a, 1),
            s.normal_resultant,
            s.nodes.open,
            s.nodes.contact,
            s.nodes.stick,
            s.nodes.slip
        )?;
    }
    Ok(())
}

fn write_contact_csv(
    w: &mut dyn Write,
    nodes: &[InterfaceNode],
    pairs: &[vem_contact::PairSummary],
    frictionless: bool,
) -> std::io::Result<()> {
    writeln!(w, "{CONTACT_COLUMNS}")?;
    for (i, n) in nodes.iter().enumerate() {
        let pair = pairs.iter().position(|p| p.nodes.contains(&i)).unwrap_or(0);
        writeln!(
            w,
            "{pair},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{}",
            n.position.x + 0.0,
            n.position.y + 0.0,
            n.normal.x + 0.0,
            n.normal.y + 0.0,
            n.initial_gap + 0.0,
            n.normal_jump + 0.0,
            n.normal_force + 0.0,
            n.pressure + 0.0,
            n.consistent_pressure + 0.0,
            n.friction_t() + 0.0,
            n.consistent_friction_t() + 0.0,
            n.slip_t() + 0.0,
            status_label(n.status, frictionless)
        )?;
    }
    Ok(())
}

/// The bounding box of the vertices of `meshes`.
fn bounding_box<'a>(meshes: impl Iterator<Item = &'a Mesh>) -> (Point, Point) {
    let mut min = Point::new(f64::INFINITY, f64::INFINITY);
    let mut max = Point::new(f64::NEG_INFINITY, f64::NEG_INFINITY);
    for p in meshes.flat_map(|m| m.vertices().iter()) {
        min = Point::new(min.x.min(p.x), min.y.min(p.y));
        max = Point::new(max.x.max(p.x), max.y.max(p.y));
    }
    (min, max)
}

/// An outline of the obstacle near the bodies (box `min`, `max`), as a one-polygon mesh for
/// the picture: a band on the obstacle's side of its surface, whose surface edges form the
/// part "surface"; a small disc is drawn whole. `None` when nothing of it is near the bodies
/// or its band is not a simple polygon (a very sharp polyline).
fn obstacle_outline(obstacle: &Obstacle, min: Point, max: Point) -> Option<Mesh> {
    let extent = (max - min).norm();
    let margin = Vector::new(0.15 * extent, 0.15 * extent);
    let (lo, hi) = (min - margin, max + margin);
    let band = 0.04 * extent;
    let far = 10.0 * extent;
    // The surface as a polyline with the obstacle on its right.
    let surface: Vec<Point> = match obstacle {
        Obstacle::Line { point, normal } => {
            let n = normal / normal.norm();
            let t = Vector::new(n.y, -n.x);
            vec![point - far * t, point + far * t]
        }
        Obstacle::Circle { centre, radius } => {
            let middle = lo + 0.5 * (hi - lo);
            let towards = (middle - centre).y.atan2((middle - centre).x);
            let half_angle = (0.75 * extent / radius).min(std::f64::consts::PI);
            if half_angle >= std::f64::consts::PI {
                return disc(*centre, *radius);
            }
            // Clockwise: the disc is on the right.
            (0..=64)
                .map(|k| {
                    let angle = towards + half_angle - 2.0 * half_angle * k as f64 / 64.0;
                    centre + *radius * Vector::new(angle.cos(), angle.sin())
                })
                .collect()
        }
        Obstacle::Polyline(points) => points.clone(),
    };
    let surface = clip_polyline(&surface, lo, hi);
    if surface.len() < 2 {
        return None;
    }
    // Offset into the obstacle (to the right) by the band width, with averaged normals.
    let right = |a: Point, b: Point| {
        let t = (b - a).normalize();
        Vector::new(t.y, -t.x)
    };
    let m = surface.len();
    let offset: Vec<Point> = (0..m)
        .map(|i| {
            let before = (i > 0).then(|| right(surface[i - 1], surface[i]));
            let after = (i + 1 < m).then(|| right(surface[i], surface[i + 1]));
            let n = match (before, after) {
                (Some(a), Some(b)) => (a + b).normalize(),
                (Some(a), None) | (None, Some(a)) => a,
                (None, None) => Vector::zeros(),
            };
            surface[i] + band * n
        })
        .collect();
    let mut vertices = surface.clone();
    vertices.extend(offset.iter().rev());
    // Surface traversed forwards with the band on its right: clockwise; reverse the loop.
    let polygon: Vec<usize> = (0..vertices.len()).rev().collect();
    let part = PartSpec::new("surface", (0..m - 1).map(|i| [i, i + 1]).collect());
    Mesh::from_polygons(vertices, &[polygon], vec![part]).ok()
}

/// A disc as a 96-gon whose edges form the part "surface".
fn disc(centre: Point, radius: f64) -> Option<Mesh> {
    const SIDES: usize = 96;
    let vertices: Vec<Point> = (0..SIDES)
        .map(|k| {
            let angle = 2.0 * std::f64::consts::PI * k as f64 / SIDES as f64;
            centre + radius * Vector::new(angle.cos(), angle.sin())
        })
        .collect();
    let part = PartSpec::new(
        "surface",
        (0..SIDES).map(|k| [k, (k + 1) % SIDES]).collect(),
    );
    Mesh::from_polygons(vertices, &[(0..SIDES).collect()], vec![part]).ok()
}

/// The pieces of the polyline `points` inside the box `lo`, `hi`, joined in order (points
/// closer than 1e-9 of the box's size to the previous one are dropped).
fn clip_polyline(points: &[Point], lo: Point, hi: Point) -> Vec<Point> {
    let tolerance = 1e-9 * (hi - lo).norm();
    let mut kept: Vec<Point> = Vec::new();
    for w in points.windows(2) {
        let (a, d) = (w[0], w[1] - w[0]);
        // Liang-Barsky: the parameter range of a + s d inside the box.
        let (mut s0, mut s1) = (0.0_f64, 1.0_f64);
        for (p, q) in [
            (-d.x, a.x - lo.x),
            (d.x, hi.x - a.x),
            (-d.y, a.y - lo.y),
            (d.y, hi.y - a.y),
        ] {
            if p == 0.0 {
                if q < 0.0 {
                    s1 = -1.0;
                }
            } else if p < 0.0 {
                s0 = s0.max(q / p);
            } else {
                s1 = s1.min(q / p);
            }
        }
        if s0 < s1 {
            for s in [s0, s1] {
                let x = a + s * d;
                if kept.last().is_none_or(|last| (last - x).norm() > tolerance) {
                    kept.push(x);
                }
            }
        }
    }
    kept
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nice_magnifications() {
        assert_eq!(round_down_to_nice(37.0), 20.0);
        assert_eq!(round_down_to_nice(0.7), 0.5);
        assert_eq!(round_down_to_nice(1.0), 1.0);
        assert!((round_down_to_nice(1.9e3) - 1e3).abs() < 1e-9);
    }

    #[test]
    fn automatic_magnification_draws_the_largest_displacement_visibly() {
        // Extent 2, largest 1e-3: 8 % of 2 is 0.16 = 160 times the displacement, rounded
        // down to 100; the drawn displacement is then 5 % of the extent.
        assert_eq!(automatic_magnification(2.0, 1e-3), 100.0);
        let m = automatic_magnification(2.0, 1e-3);
        assert!(m * 1e-3 <= AUTO_DISPLACEMENT_FRACTION * 2.0);
        assert!(m * 1e-3 > 0.4 * AUTO_DISPLACEMENT_FRACTION * 2.0);
        // Never below 1: a large displacement is drawn at true scale, not shrunk.
        assert_eq!(automatic_magnification(2.0, 0.5), 1.0);
        // Nothing moves: 1.
        assert_eq!(automatic_magnification(2.0, 0.0), 1.0);
    }

    #[test]
    fn obstacles_are_translated_whole() {
        let shift = Vector::new(0.0, -0.25);
        let Obstacle::Circle { centre, radius } = translated(
            &Obstacle::Circle {
                centre: Point::new(1.0, 2.0),
                radius: 3.0,
            },
            shift,
        ) else {
            panic!("a circle stays a circle");
        };
        assert_eq!((centre, radius), (Point::new(1.0, 1.75), 3.0));
        let Obstacle::Polyline(points) = translated(
            &Obstacle::Polyline(vec![Point::new(0.0, 0.0), Point::new(1.0, 0.0)]),
            shift,
        ) else {
            panic!("a polyline stays a polyline");
        };
        assert_eq!(points, [Point::new(0.0, -0.25), Point::new(1.0, -0.25)]);
    }

    #[test]
    fn line_obstacle_is_a_band_below_the_bodies() {
        let floor = Obstacle::Line {
            point: Point::new(0.0, 0.0),
            normal: Vector::new(0.0, 1.0),
        };
        let mesh = obstacle_outline(&floor, Point::new(0.0, 0.0), Point::new(1.0, 1.0)).unwrap();
        assert_eq!(mesh.n_polygons(), 1);
        // The surface is the clipped line y = 0; the band lies below it.
        let surface = mesh.part_vertices("surface").unwrap();
        assert!(surface.iter().all(|&v| mesh.vertex(v).y.abs() < 1e-12));
        assert!(mesh.vertices().iter().all(|p| p.y <= 1e-12));
        let area = mesh.area(0);
        let expected = (1.0 + 2.0 * 0.15 * 2f64.sqrt()) * 0.04 * 2f64.sqrt();
        assert!((area - expected).abs() < 1e-12, "{area} vs {expected}");
    }

    #[test]
    fn circle_obstacle_near_the_bodies_is_an_arc_band() {
        let disc = Obstacle::Circle {
            centre: Point::new(0.0, -1.0),
            radius: 1.0,
        };
        let mesh = obstacle_outline(&disc, Point::new(-1.0, 0.0), Point::new(1.0, 0.5)).unwrap();
        // The surface vertices lie on the circle (the two clipped ends on a chord of the
        // 64-gon, within its sagitta 3e-4), the band inside the disc.
        for v in mesh.part_vertices("surface").unwrap() {
            let r = (mesh.vertex(v) - Point::new(0.0, -1.0)).norm();
            assert!(r <= 1.0 + 1e-12 && r > 1.0 - 3e-4, "{r}");
        }
        assert!(mesh
            .vertices()
            .iter()
            .all(|p| (p - Point::new(0.0, -1.0)).norm() <= 1.0 + 1e-12));
    }

    #[test]
    fn clipping_keeps_the_inside_piece() {
        let clipped = clip_polyline(
            &[Point::new(-5.0, 0.5), Point::new(5.0, 0.5)],
            Point::new(0.0, 0.0),
            Point::new(1.0, 1.0),
        );
        assert_eq!(clipped, vec![Point::new(0.0, 0.5), Point::new(1.0, 0.5)]);
    }
}
