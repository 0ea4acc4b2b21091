//! Timings and memory of assembly and sparse Cholesky at large sizes.
//!
//! ```text
//! cargo run --release -p vem-elastic --example scaling [-- --family voronoi|quads] [--dofs 1e5,1e6]
//!     [--ordering auto|amd|nd|natural]
//! ```
//!
//! For each target size: a mesh of the unit square, clamped on all sides, loaded by a body
//! force; prints mesh, assembly, symbolic analysis, numeric factorisation, refactorisation (new
//! values, same pattern), solve times, the number of stored entries of `K_ff` and of the
//! factor, the flops of one factorisation, and the process's peak resident memory (VmHWM)
//! after each phase; then one table row (`| family | unknowns | ordering | analyse | factor
//! entries | flops | factorise | solve | peak |`) for `docs/benchmarks.md`. Run one size and
//! ordering per process for a peak that belongs to that ordering alone.

use std::sync::Arc;
use std::time::Instant;

use vem_elastic::{
    CholeskySettings, CholeskySolver, ElasticBody, LinearSolver, Material, Ordering, Plane,
};
use vem_mesh::generators::{MeshFamily, Rectangle};
use vem_mesh::Vector;
use vem_space::LowestOrderVem;

/// Peak resident set size of this process in MiB, from /proc/self/status (Linux).
fn peak_memory_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024.0)
}

fn memory() -> String {
    peak_memory_mib().map_or_else(|| "n/a".to_string(), |m| format!("{m:.0} MiB"))
}

/// The size parameter n of `family` that gives about `dofs` degrees of freedom.
fn size_for(family: MeshFamily, dofs: f64) -> usize {
    let vertices_per_cell = match family {
        MeshFamily::Voronoi | MeshFamily::Hexagons => 2.0,
        _ => 1.0,
    };
    ((dofs / (2.0 * vertices_per_cell)).sqrt().round() as usize).max(2)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut family = MeshFamily::Voronoi;
    let mut targets = vec![1e5, 1e6];
    let mut ordering = Ordering::Auto;
    let mut i = 0;
    while i < args.len() {
        match (args[i].as_str(), args.get(i + 1)) {
            ("--family", Some(name)) => family = name.parse()?,
            ("--dofs", Some(list)) => {
                targets = list
                    .split(',')
                    .map(str::parse::<f64>)
                    .collect::<Result<_, _>>()?;
            }
            ("--ordering", Some(name)) => {
                ordering = match name.as_str() {
                    "auto" => Ordering::Auto,
                    "amd" => Ordering::Amd,
                    "nd" => Ordering::NestedDissection,
                    "natural" => Ordering::Natural,
                    other => return Err(format!("unknown ordering '{other}'").into()),
                }
            }
            (other, _) => return Err(format!("unknown or incomplete argument '{other}'").into()),
        }
        i += 2;
    }
    println!(
        "family {} | rayon threads {} | lowest-order VEM, plane strain lambda = 2, mu = 1",
        family.name(),
        rayon::current_num_threads()
    );
    for target in targets {
        let n = size_for(family, target);
        let clock = Instant::now();
        let mesh = family.generate(&Rectangle::unit_square(), n, 1)?;
        let t_mesh = clock.elapsed().as_secs_f64();
        let body = ElasticBody::builder(
            "plate",
            mesh,
            Material::from_lame(2.0, 1.0, Plane::Strain)?,
            Arc::new(LowestOrderVem::default()),
        )
        .clamp("left")
        .clamp("right")
        .clamp("bottom")
        .clamp("top")
        .body_force(|x| Vector::new(x.y, -1.0))
        .build()?;
        println!(
            "\nn = {n}: {} polygons, {} vertices, {} dofs ({} free); mesh {t_mesh:.2} s, peak {}",
            body.mesh().n_polygons(),
            body.mesh().n_vertices(),
            body.dofs().n_dofs(),
            body.dofs().n_free(),
            memory()
        );

        let clock = Instant::now();
        let mut system = body.assemble()?;
        let t_assembly = clock.elapsed().as_secs_f64();
        let nnz = system.stiffness().val().len();
        println!(
            "  assembly          {t_assembly:8.3} s   nnz(K_ff) = {nnz} ({:.1} MiB values + indices)   peak {}",
            (nnz * 16) as f64 / 1048576.0,
            memory()
        );
        let clock = Instant::now();
        body.reassemble(&mut system)?;
        println!(
            "  reassembly        {:8.3} s   (values only, same pattern)",
            clock.elapsed().as_secs_f64()
        );

        let mut solver =
            CholeskySolver::new(CholeskySettings::builder().ordering(ordering).build()?);
        let clock = Instant::now();
        solver.analyse(system.stiffness().symbolic())?;
        let t_symbolic = clock.elapsed().as_secs_f64();
        let stats = solver.statistics();
        println!(
            "  symbolic ({:?})  {t_symbolic:8.3} s   factor entries {} ({}), flops {:.3e}, peak {}",
            stats.ordering.unwrap_or(ordering),
            stats.factor_entries,
            if solver.is_supernodal() == Some(true) {
                "supernodal"
            } else {
                "simplicial"
            },
            stats.flops,
            memory()
        );
        let clock = Instant::now();
        solver.factorise(system.stiffness().as_ref())?;
        let t_numeric = clock.elapsed().as_secs_f64();
        println!("  numeric           {t_numeric:8.3} s   peak {}", memory());
        let clock = Instant::now();
        solver.factorise(system.stiffness().as_ref())?;
        println!(
            "  refactorisation   {:8.3} s   (symbolic reused)",
            clock.elapsed().as_secs_f64()
        );
        let clock = Instant::now();
        let u_free = solver.solve(system.rhs())?;
        let t_solve = clock.elapsed().as_secs_f64();
        let displacement = system.expand(&u_free)?;
        let energy = system.strain_energy(&displacement)?;
        println!(
            "  solve (Par::Seq)  {t_solve:8.3} s   strain energy {energy:.6e}   peak {}",
            memory()
        );
        println!(
            "| {} | {} | {:?} | {t_symbolic:.2} | {:.3e} | {:.3e} | {t_numeric:.2} | {t_solve:.3} | {:.2} |",
            family.name(),
            body.dofs().n_free(),
            stats.ordering.unwrap_or(ordering),
            stats.factor_entries as f64,
            stats.flops,
            peak_memory_mib().unwrap_or(0.0) / 1024.0
        );
    }
    Ok(())
}
