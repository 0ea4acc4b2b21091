//! Shape-regularity (assumption A1) of every mesh family under refinement.
//!
//! For each family at n = 8, 32, 128 on the unit square (seed 1), prints the number of
//! elements, the mesh size h = max h_T, the minimum and median of shortest edge / h_T and of
//! star radius / h_T, and gamma = the smallest of all these ratios. A1 holds for a family when
//! gamma stays bounded away from zero as n grows.
//!
//! ```text
//! cargo run --release -p vem-mesh --example quality [n ...]
//! ```

use vem_mesh::generators::{MeshFamily, Rectangle};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let sizes: Vec<usize> = {
        let given: Result<Vec<usize>, _> = std::env::args().skip(1).map(|a| a.parse()).collect();
        let given = given.map_err(|e| format!("sizes must be positive integers: {e}"))?;
        if given.is_empty() {
            vec![8, 32, 128]
        } else {
            given
        }
    };
    let rect = Rectangle::unit_square();
    let seed = 1;
    println!(
        "| family | n | elements | h | min edge/h_T | median edge/h_T | min star/h_T | median star/h_T | gamma |"
    );
    println!("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |");
    for family in MeshFamily::all() {
        for &n in &sizes {
            let mesh = family.generate(&rect, n, seed)?;
            let q = mesh.quality();
            println!(
                "| {family} | {n} | {} | {:.4e} | {:.4} | {:.4} | {:.4} | {:.4} | {:.4} |",
                q.elements,
                q.mesh_size(),
                q.shortest_edge_ratio.min,
                q.shortest_edge_ratio.median,
                q.star_ratio.min,
                q.star_ratio.median,
                q.gamma
            );
        }
    }
    Ok(())
}
