//! Time of the surface overlay (interface insertion in three dimensions) at growing sizes.
//!
//! Body a is a one-layer slab of the given family on [0, 1]^2 x [0, 0.1] with n x n cells
//! across (its top has about n^2 faces, 2 n^2 for tetrahedra); body b a slab of the other
//! family above it, about 1.3 times finer and shifted by (0.013, 0.021), so that nothing
//! matches. Prints the faces of each contact part, the pairs, the inserted vertices and the
//! time of `insert_surface_overlay` (best of three runs, validation of both new meshes
//! included), and that time per face of the two parts.
//!
//! ```text
//! cargo run --profile test -p vem-mesh --example overlay_speed [--family-a NAME] [--family-b NAME] [n ...]
//! ```

use std::time::Instant;

use vem_mesh::generators::polyhedral::{Cuboid, PolyhedralFamily};
use vem_mesh::interface::InterfaceOptions;
use vem_mesh::polyhedral::overlay::insert_surface_overlay;
use vem_mesh::Point3;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut family_a = PolyhedralFamily::Hexahedra;
    let mut family_b = PolyhedralFamily::Tetrahedra;
    let mut sizes = Vec::new();
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--family-a" => family_a = args.next().ok_or("--family-a needs a name")?.parse()?,
            "--family-b" => family_b = args.next().ok_or("--family-b needs a name")?.parse()?,
            _ => sizes.push(
                arg.parse::<usize>()
                    .map_err(|e| format!("sizes must be positive integers: {e}"))?,
            ),
        }
    }
    if sizes.is_empty() {
        sizes = vec![25, 50, 100];
    }
    println!("| a | b | n | faces a | faces b | pairs | inserted a | inserted b | overlay (s) | per face (us) |");
    println!("| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |");
    for n in sizes {
        let a = family_a.generate(
            &Cuboid::new(
                Point3::new(0.0, 0.0, 0.0),
                Point3::new(1.0, 1.0, 1.0 / n as f64),
            ),
            n,
            1,
        )?;
        let m = (1.3 * n as f64).round() as usize;
        let b = family_b.generate(
            &Cuboid::new(
                Point3::new(0.013, 0.021, 1.0 / n as f64),
                Point3::new(1.013, 1.021, 2.0 / n as f64),
            ),
            m,
            2,
        )?;
        let options = InterfaceOptions::default();
        let mut best = f64::INFINITY;
        let mut result = None;
        for _ in 0..3 {
            let start = Instant::now();
            let overlay = insert_surface_overlay(&a, "top", &b, "bottom", &options)?;
            best = best.min(start.elapsed().as_secs_f64());
            result = Some(overlay);
        }
        let overlay = result.expect("three runs");
        let (fa, fb) = (a.part_faces("top")?.len(), b.part_faces("bottom")?.len());
        println!(
            "| {family_a} | {family_b} | {n} | {fa} | {fb} | {} | {} | {} | {best:.3} | {:.1} |",
            overlay.pairs.len(),
            overlay.inserted_a,
            overlay.inserted_b,
            1e6 * best / (fa + fb) as f64
        );
    }
    Ok(())
}
