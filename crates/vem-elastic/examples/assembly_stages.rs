//! The assembly of one body stage by stage (docs/benchmarks.md, "Assembly, stage by stage").
//!
//! ```text
//! cargo run --release -p vem-elastic --example assembly_stages -- [--dim 2|3] [--dofs 1e5]
//!     [--family hexahedra|voronoi] [--repeat 5]
//! ```
//!
//! In the plane, the two bodies of the whole-run bench's own case (`cargo xtask bench`): the
//! unit square of structured triangles and the one below it of structured quadrilaterals 1.25
//! times finer, their vertices and polygons numbered in a shuffled order (as a mesh
//! generator's numbering is not a spatial one), bottoms clamped; in space the unit cube of
//! `family`, bottom clamped. Prints the medians of the wall times over the repetitions and
//! the means of the CPU times (every thread; /proc/self/stat, 10 ms ticks):
//!
//! - `assemble`: `ElasticBody::assemble` (pattern, element matrices, scatter, right-hand side);
//! - `reassemble`: `ElasticBody::reassemble` on the same pattern (element matrices, scatter);
//! - `element work`: the element stiffness and body load of every cell alone, in parallel (as
//!   the assembly computes them), summed and dropped;
//! - and what the differences leave: the pattern (`assemble - reassemble`) and the scatter
//!   (`reassemble - element work`), with the entries of `K_ff` and its bytes, and a checksum
//!   (FNV-1a) of the three blocks' patterns and values and of the right-hand sides: equal
//!   checksums are systems equal bit for bit.

use std::sync::Arc;
use std::time::Instant;

use rayon::prelude::*;
use vem_elastic::{ElasticBody, Material, Plane};
use vem_mesh::generators::polyhedral::{Cuboid, PolyhedralFamily};
use vem_mesh::generators::{structured_quads, structured_triangles, Rectangle};
use vem_mesh::{Mesh, PartSpec, Point, PointD, VectorD};
use vem_space::{LowestOrderVem, PolyhedralVem};

/// A permutation of 0..n from `seed` (Fisher-Yates with splitmix64).
fn shuffled(n: usize, seed: u64) -> Vec<usize> {
    let mut state = seed;
    let mut next = || {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    };
    let mut order: Vec<usize> = (0..n).collect();
    for i in (1..n).rev() {
        let j = (next() % (i as u64 + 1)) as usize;
        order.swap(i, j);
    }
    order
}

/// `mesh` with its vertices and polygons numbered in a shuffled order.
fn renumbered(mesh: &Mesh, seed: u64) -> Result<Mesh, Box<dyn std::error::Error>> {
    let order = shuffled(mesh.n_vertices(), seed);
    let mut new_of = vec![0; order.len()];
    for (k, &v) in order.iter().enumerate() {
        new_of[v] = k;
    }
    let vertices: Vec<Point> = order.iter().map(|&v| mesh.vertex(v)).collect();
    let polygons: Vec<Vec<usize>> = shuffled(mesh.n_polygons(), seed + 100)
        .into_iter()
        .map(|p| mesh.polygon(p).iter().map(|&v| new_of[v]).collect())
        .collect();
    let parts = mesh
        .parts()
        .iter()
        .map(|part| {
            let edges = part
                .edges
                .iter()
                .map(|&e| mesh.edge(e).vertices.map(|v| new_of[v]))
                .collect();
            PartSpec::new(part.name.clone(), edges)
        })
        .collect();
    Ok(Mesh::from_polygons(vertices, &polygons, parts)?)
}

/// The CPU time (user + system, every thread) of this process so far in seconds, from
/// /proc/self/stat (Linux; in clock ticks of 10 ms).
fn cpu_time() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    // The fields after the command name (in parentheses): utime and stime are the 12th and
    // 13th.
    let after = stat.rsplit(')').next().unwrap_or("");
    let fields: Vec<&str> = after.split_whitespace().collect();
    let ticks = |k: usize| {
        fields
            .get(k)
            .and_then(|f| f.parse::<f64>().ok())
            .unwrap_or(0.0)
    };
    (ticks(11) + ticks(12)) / 100.0
}

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

/// Times the stages of `bodies` (medians over `repeat`) and prints them.
fn measure<const D: usize>(
    bodies: &[ElasticBody<D>],
    force: &(dyn Fn(PointD<D>) -> VectorD<D> + Sync),
    repeat: usize,
) -> Result<(), Box<dyn std::error::Error>> {
    let (mut assemble, mut reassemble, mut elements) = (Vec::new(), Vec::new(), Vec::new());
    let (mut entries, mut checksum) = (0, 0u64);
    let mut cpu = [0.0; 3];
    for _ in 0..repeat {
        let clock = Instant::now();
        let cpu_start = cpu_time();
        let mut systems = bodies
            .iter()
            .map(ElasticBody::assemble)
            .collect::<Result<Vec<_>, _>>()?;
        assemble.push(clock.elapsed().as_secs_f64());
        cpu[0] += cpu_time() - cpu_start;
        entries = systems.iter().map(|s| s.stiffness().val().len()).sum();
        checksum = systems.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, s| {
            let words = [s.stiffness(), s.coupling(), s.prescribed_block()]
                .into_iter()
                .flat_map(|m| {
                    let (pattern, values) = m.parts();
                    (pattern
                        .col_ptr()
                        .iter()
                        .chain(pattern.row_idx())
                        .map(|&i| i as u64))
                    .chain(values.iter().map(|v| v.to_bits()))
                })
                .chain(s.rhs().iter().map(|v| v.to_bits()));
            words.fold(h, |h, w| (h ^ w).wrapping_mul(0x100_0000_01b3))
        });
        let clock = Instant::now();
        let cpu_start = cpu_time();
        for (body, system) in bodies.iter().zip(&mut systems) {
            body.reassemble(system)?;
        }
        reassemble.push(clock.elapsed().as_secs_f64());
        cpu[1] += cpu_time() - cpu_start;
        drop(systems);
        let clock = Instant::now();
        let cpu_start = cpu_time();
        let mut trace = 0.0;
        for body in bodies {
            let mesh = body.body_mesh();
            trace += (0..mesh.n_cells())
                .into_par_iter()
                .map(|c| {
                    let k = body.element().stiffness(mesh, c, body.tensor())?;
                    let load = body.element().body_load(mesh, c, force)?;
                    Ok((&k.consistency + &k.stabilisation).trace() + load.sum().abs())
                })
                .collect::<Result<Vec<f64>, vem_space::SpaceError>>()?
                .iter()
                .sum::<f64>();
        }
        elements.push(clock.elapsed().as_secs_f64());
        cpu[2] += cpu_time() - cpu_start;
        assert!(trace > 0.0);
    }
    let (a, r, e) = (median(assemble), median(reassemble), median(elements));
    let [ca, cr, ce] = cpu.map(|t| t / repeat as f64);
    println!("                    wall [s]  CPU [s] (mean)");
    println!("  assemble          {a:8.4}  {ca:8.3}");
    println!("  reassemble        {r:8.4}  {cr:8.3}");
    println!("  element work      {e:8.4}  {ce:8.3}");
    println!("  pattern (a - r)   {:8.4}  {:8.3}", a - r, ca - cr);
    println!("  scatter (r - e)   {:8.4}  {:8.3}", r - e, cr - ce);
    println!(
        "  K_ff: {entries} entries ({:.1} MB with row indices); checksum of the patterns, \
         values and right-hand sides {checksum:016x}",
        entries as f64 * 16e-6
    );
    Ok(())
}

fn force_2d(_: Point) -> vem_mesh::Vector {
    vem_mesh::Vector::new(0.0, -1.0)
}

fn force_3d(_: vem_mesh::Point3) -> vem_mesh::Vector3 {
    vem_mesh::Vector3::new(0.0, 0.0, -0.5)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (mut dim, mut dofs, mut repeat) = (2usize, 1e5f64, 5usize);
    let mut family = PolyhedralFamily::Hexahedra;
    let mut i = 0;
    while i < args.len() {
        match (args[i].as_str(), args.get(i + 1)) {
            ("--dim", Some(v)) => dim = v.parse()?,
            ("--dofs", Some(v)) => dofs = v.parse()?,
            ("--repeat", Some(v)) => repeat = v.parse::<usize>()?.max(1),
            ("--family", Some(v)) => family = v.parse()?,
            (other, _) => return Err(format!("unknown or incomplete argument '{other}'").into()),
        }
        i += 2;
    }
    let load = Instant::now();
    let material = Material::from_young_poisson(100.0, 0.3, Plane::Strain)?;
    if dim == 2 {
        // (n + 1)^2 vertices above, (1.25 n + 1)^2 below, two unknowns each.
        let n = ((dofs / (2.0 * (1.0 + 1.25 * 1.25))).sqrt().round() as usize).max(2);
        let m = ((1.25 * n as f64).round() as usize).max(1);
        let upper = Rectangle::new(Point::new(0.0, 0.0), Point::new(1.0, 1.0));
        let lower = Rectangle::new(Point::new(0.0, -1.0), Point::new(1.0, 0.0));
        let meshes = [
            renumbered(&structured_triangles(&upper, n, n)?, 1)?,
            renumbered(&structured_quads(&lower, m, m)?, 2)?,
        ];
        let bodies = meshes
            .into_iter()
            .enumerate()
            .map(|(k, mesh)| {
                ElasticBody::builder(
                    format!("body {k}"),
                    mesh,
                    material,
                    Arc::new(LowestOrderVem::default()),
                )
                .clamp("bottom")
                .body_force(force_2d)
                .build()
            })
            .collect::<Result<Vec<_>, _>>()?;
        let unknowns: usize = bodies.iter().map(|b| b.dofs().n_unknowns()).sum();
        println!(
            "plane, bench case n = {n}: {} + {} cells, {unknowns} unknowns; rayon threads {}; \
             set up in {:.2} s",
            bodies[0].body_mesh().n_cells(),
            bodies[1].body_mesh().n_cells(),
            rayon::current_num_threads(),
            load.elapsed().as_secs_f64()
        );
        measure(&bodies, &force_2d, repeat)
    } else {
        let n = ((dofs / 3.0).cbrt().round() as usize).max(2);
        let n = if family == PolyhedralFamily::Voronoi {
            ((dofs / 15.0).cbrt().round() as usize).max(2)
        } else {
            n
        };
        let mesh = family.generate(&Cuboid::unit_cube(), n, 1)?;
        let body = ElasticBody::builder_polyhedral(
            "cube",
            mesh,
            Material::isotropic(1.0, 0.3)?,
            Arc::new(PolyhedralVem::default()),
        )
        .clamp("bottom")
        .body_force(force_3d)
        .build()?;
        println!(
            "space, {} n = {n}: {} cells, {} unknowns; rayon threads {}",
            family.name(),
            body.body_mesh().n_cells(),
            body.dofs().n_unknowns(),
            rayon::current_num_threads()
        );
        measure(&[body], &force_3d, repeat)
    }
}
