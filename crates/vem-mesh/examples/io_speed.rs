//! Reading speed of Gmsh files, stage by stage, in MB/s of the file.
//!
//! For every `.msh` file given (default: every file of `target/mesh-bench`, written by
//! `scripts/mesh-bench.py` with Gmsh itself), prints the best of `--repeat` runs (default 3)
//! of each stage:
//!
//! - `read`: the bytes from the file system (`std::fs::read`; the page cache after the first
//!   run);
//! - `parse`: [`read_msh_bytes`], the file's nodes, elements and groups;
//! - `build`: [`Mesh::from_compact`] on the resulting polygons and parts (edges derived,
//!   parts resolved, the whole validation);
//! - `to mesh`: everything from the bytes to the [`Mesh`] ([`read_gmsh_bytes`]), which is
//!   parse + conversion + build;
//! - `file to mesh`: [`read_gmsh`], the user's view, with the time in seconds.
//!
//! With `--write`, it then measures writing, on meshes of the generators (with the cell and
//! point data the command-line tool writes for a body: a displacement, a stress tensor and
//! five cell scalars, plus two point scalars): the size and speed of `.vtu` files in each
//! encoding, for the mesh of a contact run of 35 000 unknowns (two bodies of Voronoi cells,
//! 17 500 vertices in all), and the size and time of SVG pictures (cells coloured by a value,
//! displaced) of 10^4, 10^5 and 10^6 cells. Files go to `target/io-speed`.
//!
//! ```text
//! cargo run --release -p vem-mesh --example io_speed -- [--repeat N] [--write] [FILE.msh ...]
//! ```

use std::path::{Path, PathBuf};
use std::time::Instant;

use vem_mesh::generators::{structured_quads, voronoi, Rectangle};
use vem_mesh::io::{
    read_gmsh, read_gmsh_bytes, read_msh_bytes, read_vtu, write_svg_layers, write_vtu_with,
    SvgLayer, SvgOptions, VtuData, VtuEncoding,
};
use vem_mesh::{Mesh, Point, Vector};

/// Best wall time of `repeat` runs of `f`, in seconds, and the last result.
fn best<T>(repeat: usize, mut f: impl FnMut() -> T) -> (f64, T) {
    let mut best = f64::INFINITY;
    let mut last = None;
    for _ in 0..repeat.max(1) {
        let start = Instant::now();
        let value = f();
        best = best.min(start.elapsed().as_secs_f64());
        last = Some(value);
    }
    (best, last.expect("at least one run"))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut repeat = 3;
    let mut write = false;
    let mut files: Vec<PathBuf> = Vec::new();
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        if arg == "--write" {
            write = true;
        } else if arg == "--repeat" {
            repeat = args.next().ok_or("--repeat needs a number")?.parse()?;
        } else {
            files.push(arg.into());
        }
    }
    if files.is_empty() && !write {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../target/mesh-bench");
        let entries = std::fs::read_dir(&dir).map_err(|e| {
            format!(
                "{}: {e}; write the meshes with scripts/mesh-bench.py or name files",
                dir.display()
            )
        })?;
        files = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|e| e == "msh"))
            .collect();
        files.sort_by_key(|p| std::fs::metadata(p).map(|m| m.len()).unwrap_or(0));
    }

    println!(
        "| file | MB | nodes | polygons | read MB/s | parse MB/s | build MB/s | to mesh MB/s | \
         file to mesh MB/s | file to mesh s |"
    );
    println!("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |");
    for file in &files {
        let (t_read, bytes) = best(repeat, || std::fs::read(file));
        let bytes = bytes?;
        let mb = bytes.len() as f64 / 1e6;
        let (t_parse, msh) = best(repeat, || read_msh_bytes(&bytes));
        let msh = msh?;
        let (t_mesh, mesh) = best(repeat, || read_gmsh_bytes(&bytes, file));
        let mesh = mesh?;
        let (t_build, rebuilt) = best(repeat, || {
            Mesh::from_compact(
                mesh.vertices().to_vec(),
                mesh.polygon_offsets().to_vec(),
                mesh.polygon_vertex_indices().to_vec(),
                mesh.part_specs(),
            )
        });
        assert_eq!(rebuilt?, mesh);
        let (t_file, read) = best(repeat, || read_gmsh(file));
        read?;
        let name = file.file_name().unwrap_or_default().to_string_lossy();
        println!(
            "| {name} | {mb:.1} | {} | {} | {:.0} | {:.0} | {:.0} | {:.0} | {:.0} | {:.3} |",
            msh.nodes.len(),
            mesh.n_polygons(),
            mb / t_read,
            mb / t_parse,
            mb / t_build,
            mb / t_mesh,
            mb / t_file,
            t_file
        );
    }
    if write {
        writing(repeat)?;
    }
    Ok(())
}

/// The data the command-line tool writes for one body, made up from smooth fields.
fn body_data(mesh: &Mesh) -> VtuData {
    let f = |p: Point| (3.0 * p.x).sin() * (2.0 * p.y).cos();
    let u: Vec<Vector> = mesh
        .vertices()
        .iter()
        .map(|&p| Vector::new(1e-3 * f(p), -2e-3 * p.x * p.y))
        .collect();
    let c: Vec<Point> = (0..mesh.n_polygons()).map(|p| mesh.centroid(p)).collect();
    let cell = |k: f64| c.iter().map(|&p| k * f(p) + 0.1).collect::<Vec<f64>>();
    let stress: Vec<f64> = c.iter().flat_map(|&p| [f(p), -f(p), 0.3 * f(p)]).collect();
    let mut data = VtuData::new()
        .with_point_vectors("displacement", &u)
        .with_cell_data(vem_mesh::io::DataArray::new("stress_xx_yy_xy", 3, stress));
    for (name, k) in [
        ("sigma_zz", 0.3),
        ("von_mises", 1.0),
        ("quality_gamma", 0.01),
        ("shortest_edge_ratio", 0.02),
        ("star_ratio", 0.03),
    ] {
        data = data.with_cell_scalars(name, cell(k));
    }
    let pressure: Vec<f64> = mesh.vertices().iter().map(|&p| f(p).max(0.0)).collect();
    data.with_point_scalars("contact_pressure", pressure.clone())
        .with_point_scalars("consistent_contact_pressure", pressure)
}

/// Sizes and speeds of `.vtu` and SVG output.
fn writing(repeat: usize) -> Result<(), Box<dyn std::error::Error>> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../target/io-speed");
    std::fs::create_dir_all(&dir)?;
    // 35 000 unknowns: two bodies of 8 750 vertices each (Voronoi cells, n = 66: 4 356 cells).
    let upper = voronoi(&Rectangle::unit_square(), 66, 1)?;
    let lower = voronoi(
        &Rectangle::new(Point::new(0.0, -1.0), Point::new(1.0, 0.0)),
        66,
        2,
    )?;
    let unknowns = 2 * (upper.n_vertices() + lower.n_vertices());
    println!();
    println!(
        "VTU of a contact run of {unknowns} unknowns (two bodies, {} + {} cells):",
        upper.n_polygons(),
        lower.n_polygons()
    );
    println!();
    println!("| encoding | size of both files [MB] | write MB/s | read MB/s |");
    println!("| --- | ---: | ---: | ---: |");
    for encoding in [
        VtuEncoding::Ascii,
        VtuEncoding::Binary,
        VtuEncoding::Compressed,
    ] {
        let mut bytes = 0u64;
        let (mut t_write, mut t_read) = (0.0, 0.0);
        for (name, mesh) in [("upper", &upper), ("lower", &lower)] {
            let path = dir.join(format!("{name}-{}.vtu", encoding.name()));
            let data = body_data(mesh);
            let (t, written) = best(repeat, || write_vtu_with(&path, mesh, &data, encoding));
            written?;
            t_write += t;
            let (t, read) = best(repeat, || read_vtu(&path));
            read?;
            t_read += t;
            bytes += std::fs::metadata(&path)?.len();
        }
        let mb = bytes as f64 / 1e6;
        println!(
            "| {} | {mb:.2} | {:.0} | {:.0} |",
            encoding.name(),
            mb / t_write,
            mb / t_read
        );
    }
    println!();
    println!("SVG pictures (cells coloured by a value, displaced, 900 pixels wide):");
    println!();
    println!("| cells | vectors: size [MB] | vectors: s | picture: size [MB] | picture: s |");
    println!("| ---: | ---: | ---: | ---: | ---: |");
    for n in [100, 316, 1000] {
        let mesh = structured_quads(&Rectangle::unit_square(), n, n)?;
        let values: Vec<f64> = (0..mesh.n_polygons())
            .map(|p| {
                let c = mesh.centroid(p);
                (6.0 * c.x).sin() * (4.0 * c.y).cos()
            })
            .collect();
        let u: Vec<Vector> = mesh
            .vertices()
            .iter()
            .map(|p| Vector::new(0.0, -0.05 * p.x * (1.0 - p.x) * p.y))
            .collect();
        let layers = [SvgLayer::new(&mesh)
            .with_cell_values(&values)
            .with_displacement(&u)];
        let mut row = format!("| {} |", mesh.n_polygons());
        for limit in [usize::MAX, 0] {
            if limit == usize::MAX && mesh.n_polygons() > 100_000 {
                row += " (not written) | |";
                continue;
            }
            let options = SvgOptions {
                width: 900.0,
                value_label: "value".into(),
                vector_cell_limit: limit,
                ..SvgOptions::default()
            };
            let kind = if limit == 0 { "picture" } else { "vectors" };
            let path = dir.join(format!("cells-{}-{kind}.svg", mesh.n_polygons()));
            let (t, written) = best(1, || write_svg_layers(&path, &layers, &options));
            written?;
            let mb = std::fs::metadata(&path)?.len() as f64 / 1e6;
            row += &format!(" {mb:.3} | {t:.2} |");
        }
        println!("{row}");
    }
    Ok(())
}
