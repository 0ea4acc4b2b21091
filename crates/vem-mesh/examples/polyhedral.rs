//! Polyhedral mesh families: size, generation time and shape-regularity under refinement.
//!
//! For each family at the given sizes n (default 4, 8, 16) on the unit cube (seed 1), prints the
//! numbers of cells, faces and vertices, the time to generate the (validated) mesh, the time of
//! the quality summary, the mesh size h and the smallest ratios of the shape-regularity figures
//! (star radius / h_E, shortest edge / h_E, smallest face diameter / h_E, face star radius /
//! h_F), gamma (the smallest of them) and the largest face warping.
//!
//! ```text
//! cargo run --release -p vem-mesh --example polyhedral [--family NAME] [n ...]
//! ```

use std::time::Instant;

use vem_mesh::generators::polyhedral::{Cuboid, PolyhedralFamily};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut families: Vec<PolyhedralFamily> = PolyhedralFamily::all().to_vec();
    let mut sizes = Vec::new();
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        if arg == "--family" {
            let name = args.next().ok_or("--family needs a name")?;
            families = vec![name.parse()?];
        } else {
            sizes.push(
                arg.parse::<usize>()
                    .map_err(|e| format!("sizes must be positive integers: {e}"))?,
            );
        }
    }
    if sizes.is_empty() {
        sizes = vec![4, 8, 16];
    }
    let cube = Cuboid::unit_cube();
    println!(
        "| family | n | cells | faces | vertices | generate (s) | quality (s) | h | min star/h_E | min edge/h_E | min h_F/h_E | min face star/h_F | gamma | max warping |"
    );
    println!("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |");
    for family in &families {
        for &n in &sizes {
            let start = Instant::now();
            let mesh = family.generate(&cube, n, 1)?;
            let generate = start.elapsed().as_secs_f64();
            let start = Instant::now();
            let q = mesh.quality();
            let quality = start.elapsed().as_secs_f64();
            println!(
                "| {family} | {n} | {} | {} | {} | {generate:.3} | {quality:.3} | {:.4e} | {:.4} | {:.4} | {:.4} | {:.4} | {:.4} | {:.2e} |",
                mesh.n_cells(),
                mesh.n_faces(),
                mesh.n_vertices(),
                q.mesh_size(),
                q.star_ratio.min,
                q.shortest_edge_ratio.min,
                q.smallest_face_ratio.min,
                q.face_star_ratio.min,
                q.gamma,
                q.face_warping.max,
            );
        }
    }
    Ok(())
}
