//! Centroidal Voronoi meshes of an L-shape and a notched trapezoid by reflected seeds, against
//! the Voronoi mesh of the bounding rectangle cut by the polygon: quality (smallest star and
//! shortest-edge ratios) at n = 10, 20, 40, generation times at n = 40 and 200, and SVG
//! pictures of both at n = 12.
//!
//! ```text
//! cargo run --release -p vem-mesh --example polygon_voronoi [-- OUT_DIR]
//! ```
//!
//! OUT_DIR defaults to `target/polygon_voronoi`; seed 3 as in `tests/polygon_domains.rs`.

use std::error::Error;
use std::path::PathBuf;
use std::time::Instant;

use vem_mesh::generators::{cut_to_polygon, polygon_mesh, voronoi, MeshFamily, PolygonDomain};
use vem_mesh::io::{write_svg, SvgOptions};
use vem_mesh::quality::summarise;
use vem_mesh::{Mesh, MeshError, Point};

const SEED: u64 = 3;

fn domain(xy: &[[f64; 2]]) -> PolygonDomain {
    PolygonDomain::new(xy.iter().map(|p| Point::new(p[0], p[1])).collect()).unwrap()
}

fn cut(domain: &PolygonDomain, n: usize) -> Result<Mesh, MeshError> {
    cut_to_polygon(&voronoi(&domain.bounding_rectangle(), n, SEED)?, domain)
}

fn main() -> Result<(), Box<dyn Error>> {
    let out_dir = std::env::args_os()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("target/polygon_voronoi"));
    std::fs::create_dir_all(&out_dir)?;
    let domains = [
        (
            "L",
            domain(&[
                [0.0, 0.0],
                [2.0, 0.0],
                [2.0, 1.0],
                [1.0, 1.0],
                [1.0, 2.0],
                [0.0, 2.0],
            ]),
        ),
        (
            "notched",
            domain(&[
                [-0.3, 0.1],
                [1.7, -0.2],
                [1.3, 1.1],
                [0.83, 1.07],
                [0.61, 0.43],
                [0.37, 1.13],
                [0.1, 1.0],
            ]),
        ),
    ];
    println!("domain   method     n  cells  star min  shortest-edge min");
    for (name, domain) in &domains {
        for n in [10, 20, 40] {
            for (method, mesh) in [
                ("cut", cut(domain, n)?),
                (
                    "reflected",
                    polygon_mesh(domain, MeshFamily::Voronoi, n, SEED)?,
                ),
            ] {
                let q = summarise(&mesh);
                println!(
                    "{name:<8} {method:<9} {n:>3} {:>6} {:>9.3} {:>18.3}",
                    q.elements, q.star_ratio.min, q.shortest_edge_ratio.min
                );
            }
        }
    }
    println!("\ndomain      n  cut [s]  reflected [s]");
    for (name, domain) in &domains {
        for n in [40, 200] {
            let start = Instant::now();
            cut(domain, n)?;
            let cut_time = start.elapsed().as_secs_f64();
            let start = Instant::now();
            polygon_mesh(domain, MeshFamily::Voronoi, n, SEED)?;
            let reflected_time = start.elapsed().as_secs_f64();
            println!("{name:<8} {n:>4} {cut_time:>8.3} {reflected_time:>14.3}");
        }
    }
    for (name, domain) in &domains {
        for (method, mesh) in [
            ("cut", cut(domain, 12)?),
            (
                "reflected",
                polygon_mesh(domain, MeshFamily::Voronoi, 12, SEED)?,
            ),
        ] {
            let path = out_dir.join(format!("{name}-{method}-12.svg"));
            let options = SvgOptions {
                title: Some(format!("{name}, Voronoi by {method}, n = 12")),
                vertex_dots: true,
                parts: true,
                ..SvgOptions::default()
            };
            write_svg(&path, &mesh, &options)?;
            println!("wrote {}", path.display());
        }
    }
    Ok(())
}
