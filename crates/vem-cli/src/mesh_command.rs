//! `vem mesh`: generate a mesh of a family or convert a Gmsh file, write it as `.vtu` (with
//! the A1 figures of every element) and `.svg` (with its boundary parts), and report its
//! quality.

use std::fmt;
use std::path::{Path, PathBuf};

use vem_mesh::generators::{MeshFamily, Rectangle};
use vem_mesh::io::{write_svg, write_vtu, SvgOptions, VtuData};
use vem_mesh::quality::QualitySummary;
use vem_mesh::{Mesh, Point};

use crate::resources::{Footprint, MemoryLimit};
use crate::CliError;

/// What `vem mesh` made and wrote.
#[derive(Debug, Clone)]
pub struct MeshReport {
    /// Where the mesh came from.
    pub source: String,
    /// Vertices.
    pub vertices: usize,
    /// Polygons.
    pub polygons: usize,
    /// Boundary part names.
    pub parts: Vec<String>,
    /// The A1 figures.
    pub quality: QualitySummary,
    /// The files written.
    pub files: Vec<PathBuf>,
}

impl fmt::Display for MeshReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "{}: {} vertices, {} polygons, parts [{}]",
            self.source,
            self.vertices,
            self.polygons,
            self.parts.join(", ")
        )?;
        write!(f, "{}", self.quality)?;
        for file in &self.files {
            writeln!(f, "wrote {}", file.display())?;
        }
        Ok(())
    }
}

/// Generates the mesh of `family` (a [`MeshFamily`] name) of size `n` on `rect`
/// (`[x0, y0, x1, y1]`) and writes `<family>-<n>.vtu` and `.svg` into `out`.
///
/// A mesh larger than the memory the system reports available is refused before it is
/// generated ([`generate_mesh_within`] takes another limit).
pub fn generate_mesh(
    family: &str,
    n: usize,
    seed: u64,
    rect: [f64; 4],
    out: &Path,
) -> Result<MeshReport, CliError> {
    generate_mesh_within(family, n, seed, rect, out, MemoryLimit::available())
}

/// As [`generate_mesh`], refusing a mesh estimated larger than `limit` before generating it.
pub fn generate_mesh_within(
    family: &str,
    n: usize,
    seed: u64,
    rect: [f64; 4],
    out: &Path,
    limit: MemoryLimit,
) -> Result<MeshReport, CliError> {
    let parsed: MeshFamily = family
        .parse()
        .map_err(|e: vem_mesh::MeshError| CliError::Usage(e.to_string()))?;
    let rectangle = Rectangle::new(Point::new(rect[0], rect[1]), Point::new(rect[2], rect[3]));
    let mesh_error = |source| CliError::Mesh {
        context: format!("family '{family}'"),
        source,
    };
    let size = parsed.size(&rectangle, n).map_err(mesh_error)?;
    limit
        .check(
            Footprint::of_size(&size).mesh_bytes(),
            &format!(
                "the mesh {family}, n = {n} ({} polygons, {} vertices)",
                size.polygons, size.vertices
            ),
        )
        .map_err(CliError::Usage)?;
    let mesh = parsed
        .generate(&rectangle, n, seed)
        .map_err(|source| CliError::Mesh {
            context: format!("family '{family}'"),
            source,
        })?;
    let random = if parsed.is_random() {
        format!(", seed {seed}")
    } else {
        String::new()
    };
    let source = format!(
        "{parsed}, n = {n}{random}, on [{}, {}] x [{}, {}]",
        rect[0], rect[2], rect[1], rect[3]
    );
    write_mesh(mesh, source, out, &format!("{}-{n}", parsed.name()))
}

/// Reads the Gmsh `.msh` file `file` and writes `<file stem>.vtu` and `.svg` into `out`.
pub fn convert_mesh(file: &Path, out: &Path) -> Result<MeshReport, CliError> {
    let mesh = vem_mesh::io::read_gmsh(file).map_err(|source| CliError::Mesh {
        context: "reading a Gmsh file".into(),
        source,
    })?;
    let stem = file
        .file_stem()
        .map_or_else(|| "mesh".into(), |s| s.to_string_lossy().into_owned());
    write_mesh(mesh, format!("Gmsh file {}", file.display()), out, &stem)
}

fn write_mesh(mesh: Mesh, source: String, out: &Path, stem: &str) -> Result<MeshReport, CliError> {
    std::fs::create_dir_all(out).map_err(|source| CliError::Io {
        action: "create the directory",
        path: out.to_path_buf(),
        source,
    })?;
    vem_mesh::io::remove_stale_temporaries(out).map_err(|source| CliError::Io {
        action: "clean the temporaries in",
        path: out.to_path_buf(),
        source,
    })?;
    let qualities = vem_mesh::quality::element_qualities(&mesh);
    let data = VtuData::new()
        .with_cell_scalars(
            "quality_gamma",
            qualities.iter().map(|q| q.gamma()).collect(),
        )
        .with_cell_scalars(
            "shortest_edge_ratio",
            qualities.iter().map(|q| q.shortest_edge_ratio).collect(),
        )
        .with_cell_scalars(
            "star_ratio",
            qualities.iter().map(|q| q.star_ratio).collect(),
        );
    let vtu = out.join(format!("{stem}.vtu"));
    let svg = out.join(format!("{stem}.svg"));
    let failed = |path: &Path| {
        let context = path.display().to_string();
        move |source| CliError::Mesh { context, source }
    };
    write_vtu(&vtu, &mesh, &data).map_err(failed(&vtu))?;
    let options = SvgOptions {
        title: Some(source.clone()),
        ..SvgOptions::default()
    };
    write_svg(&svg, &mesh, &options).map_err(failed(&svg))?;
    Ok(MeshReport {
        source,
        vertices: mesh.n_vertices(),
        polygons: mesh.n_polygons(),
        parts: mesh.part_names(),
        quality: mesh.quality(),
        files: vec![vtu, svg],
    })
}
