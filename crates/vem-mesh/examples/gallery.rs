//! Writes one mesh of every generator family at n = 8 as `.vtu` (for ParaView) and `.svg`.
//!
//! ```text
//! cargo run --release -p vem-mesh --example gallery [-- OUT_DIR]
//! ```
//!
//! OUT_DIR defaults to `target/gallery`; the random families use seed 1. The VTU files carry the cell data `area`,
//! `diameter` and `vertices` (number of vertices of each polygon); the SVG pictures show the
//! polygons, the named boundary parts and the vertices.

use std::error::Error;
use std::path::PathBuf;

use vem_mesh::generators::{MeshFamily, Rectangle};
use vem_mesh::io::{write_svg, write_vtu, SvgOptions, VtuData};

/// Size parameter of every family.
const N: usize = 8;
/// Seed of the random families.
const SEED: u64 = 1;

fn main() -> Result<(), Box<dyn Error>> {
    let out_dir = std::env::args_os()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("target/gallery"));
    std::fs::create_dir_all(&out_dir)
        .map_err(|e| format!("cannot create {}: {e}", out_dir.display()))?;
    let rect = Rectangle::unit_square();
    for family in MeshFamily::all() {
        let name = family.name();
        let mesh = &family.generate(&rect, N, SEED)?;
        let polygons = 0..mesh.n_polygons();
        let data = VtuData::new()
            .with_cell_scalars("area", polygons.clone().map(|p| mesh.area(p)).collect())
            .with_cell_scalars(
                "diameter",
                polygons.clone().map(|p| mesh.diameter(p)).collect(),
            )
            .with_cell_scalars(
                "vertices",
                polygons.map(|p| mesh.polygon(p).len() as f64).collect(),
            );
        let vtu = out_dir.join(format!("{name}.vtu"));
        write_vtu(&vtu, mesh, &data)?;
        let svg = out_dir.join(format!("{name}.svg"));
        let options = SvgOptions {
            title: Some(format!(
                "{name}, n = {N}: {} polygons, {} vertices",
                mesh.n_polygons(),
                mesh.n_vertices()
            )),
            vertex_dots: true,
            ..SvgOptions::default()
        };
        write_svg(&svg, mesh, &options)?;
        println!(
            "{name:<10} {:>5} elements {:>5} vertices  {}  {}",
            mesh.n_polygons(),
            mesh.n_vertices(),
            vtu.display(),
            svg.display()
        );
    }
    Ok(())
}
