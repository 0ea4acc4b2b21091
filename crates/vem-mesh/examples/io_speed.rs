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
//! ```text
//! cargo run --release -p vem-mesh --example io_speed -- [--repeat N] [FILE.msh ...]
//! ```

use std::path::{Path, PathBuf};
use std::time::Instant;

use vem_mesh::io::{read_gmsh, read_gmsh_bytes, read_msh_bytes};
use vem_mesh::Mesh;

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
    let mut files: Vec<PathBuf> = Vec::new();
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        if arg == "--repeat" {
            repeat = args.next().ok_or("--repeat needs a number")?.parse()?;
        } else {
            files.push(arg.into());
        }
    }
    if files.is_empty() {
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
    Ok(())
}
