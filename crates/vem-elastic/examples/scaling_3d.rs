//! Timings and memory of a 3D elasticity solve at large sizes, against faer alone on the same
//! matrix (docs/benchmarks.md, "Three dimensions").
//!
//! ```text
//! cargo run --release -p vem-elastic --example scaling_3d -- [--family hexahedra|voronoi|...]
//!     [--dofs 1e5 | --n N] [--ordering auto|amd|nd] [--faer | --faer-nd]
//! ```
//!
//! The unit cube meshed by `family` (about `dofs` unknowns), clamped at its bottom, a traction
//! on its top and a body force; lowest-order VEM, E = 1, nu = 0.3. Prints the mesh generation,
//! body building, assembly, symbolic analysis, numeric factorisation, triangular solve and
//! post-processing times (the steps of `ElasticBody::solve`), the stored entries of `K_ff` and
//! of the factor, and the peak resident memory (VmHWM) after each phase. With `--faer` the same
//! matrix is assembled and then solved by faer alone (`SymbolicLlt::try_new`,
//! `Llt::try_new_with_symbolic`, `solve`, with faer's own defaults: its AMD ordering) instead;
//! with `--faer-nd` by faer's symbolic and numeric Cholesky called directly
//! (`factorize_symbolic_cholesky` with the nested-dissection order of `elimination_order`,
//! `factorize_numeric_llt`, `solve_in_place_with_conj`), the same ordering as the project's
//! solver: what remains is the cost of the project's layers. Run one size and mode per process
//! so that the peak memory belongs to it.

use std::sync::Arc;
use std::time::Instant;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::linalg::solvers::Solve;
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, SymmetricOrdering,
};
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::{Conj, Mat, Par, Side};
use vem_elastic::{
    CholeskySettings, CholeskySolver, ElasticBody, LinearSolver, Material, Ordering,
};
use vem_mesh::generators::polyhedral::{Cuboid, PolyhedralFamily};
use vem_mesh::Vector3;
use vem_space::PolyhedralVem;

/// Peak resident set size of this process in MiB, from /proc/self/status (Linux).
fn peak_memory_mib() -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status
        .lines()
        .find(|l| l.starts_with("VmHWM:"))
        .and_then(|l| l.split_whitespace().nth(1)?.parse::<f64>().ok())
        .map_or(0.0, |kib| kib / 1024.0)
}

/// The size parameter of `family` that gives about `dofs` unknowns (bottom clamped).
fn size_for(family: PolyhedralFamily, dofs: f64) -> usize {
    // Vertices per n^3 of the families (measured at n = 12 and 17): 1 for the boxes, 5 for
    // Voronoi, 8.3 for the octree, 2.3 for the chevron prisms.
    let vertices_per_cell = match family {
        PolyhedralFamily::Voronoi => 5.0,
        PolyhedralFamily::Octree => 8.3,
        PolyhedralFamily::NonConvex => 2.3,
        _ => 1.0,
    };
    ((dofs / (3.0 * vertices_per_cell)).cbrt().round() as usize).max(2)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (mut family, mut dofs, mut ordering, mut faer_only, mut faer_nd) = (
        PolyhedralFamily::Hexahedra,
        1e5,
        Ordering::Auto,
        false,
        false,
    );
    let mut size: Option<usize> = None;
    let mut i = 0;
    while i < args.len() {
        match (args[i].as_str(), args.get(i + 1)) {
            ("--faer", _) => {
                faer_only = true;
                i += 1;
                continue;
            }
            ("--faer-nd", _) => {
                faer_nd = true;
                i += 1;
                continue;
            }
            ("--family", Some(name)) => family = name.parse()?,
            ("--dofs", Some(value)) => dofs = value.parse()?,
            ("--n", Some(value)) => size = Some(value.parse()?),
            ("--ordering", Some(name)) => {
                ordering = match name.as_str() {
                    "auto" => Ordering::Auto,
                    "amd" => Ordering::Amd,
                    "nd" => Ordering::NestedDissection,
                    other => return Err(format!("unknown ordering '{other}'").into()),
                }
            }
            (other, _) => return Err(format!("unknown or incomplete argument '{other}'").into()),
        }
        i += 2;
    }
    let n = size.unwrap_or_else(|| size_for(family, dofs));
    let clock = Instant::now();
    let mesh = family.generate(&Cuboid::unit_cube(), n, 1)?;
    let t_mesh = clock.elapsed().as_secs_f64();
    let (cells, vertices) = (mesh.n_cells(), mesh.n_vertices());
    let clock = Instant::now();
    let body = ElasticBody::builder_polyhedral(
        "cube",
        mesh,
        Material::isotropic(1.0, 0.3)?,
        Arc::new(PolyhedralVem::default()),
    )
    .clamp("bottom")
    .traction("top", |x| Vector3::new(0.1 * x.y, 0.0, -1.0))
    .body_force(|_| Vector3::new(0.0, 0.0, -0.5))
    .build()?;
    let t_build = clock.elapsed().as_secs_f64();
    println!(
        "{} n = {n}: {cells} cells, {vertices} vertices, {} unknowns; rayon threads {}",
        family.name(),
        body.dofs().n_unknowns(),
        rayon::current_num_threads()
    );
    println!(
        "  mesh generation   {t_mesh:8.3} s   peak {:.0} MiB",
        peak_memory_mib()
    );
    println!("  body building     {t_build:8.3} s");
    let clock = Instant::now();
    let system = body.assemble()?;
    let t_assembly = clock.elapsed().as_secs_f64();
    let nnz = system.stiffness().val().len();
    println!(
        "  assembly          {t_assembly:8.3} s   nnz(K_ff) = {nnz}   peak {:.0} MiB",
        peak_memory_mib()
    );

    if faer_nd {
        let k = system.stiffness().as_ref();
        let n = k.nrows();
        let clock = Instant::now();
        let (order, _) =
            vem_elastic::elimination_order(k.symbolic(), &[], Ordering::NestedDissection)?;
        let t_order = clock.elapsed().as_secs_f64();
        let clock = Instant::now();
        let mut inverse = vec![0usize; n];
        for (new, &old) in order.iter().enumerate() {
            inverse[old] = new;
        }
        let symbolic = factorize_symbolic_cholesky(
            k.symbolic(),
            Side::Lower,
            SymmetricOrdering::Custom(PermRef::new_checked(&order, &inverse, n)),
            CholeskySymbolicParams::default(),
        )?;
        let t_symbolic = clock.elapsed().as_secs_f64();
        let par = Par::rayon(0);
        let clock = Instant::now();
        let mut values = vec![0.0f64; symbolic.len_val()];
        let mut scratch = MemBuffer::try_new(
            symbolic.factorize_numeric_llt_scratch::<f64>(par, Default::default()),
        )?;
        let llt = symbolic.factorize_numeric_llt(
            &mut values,
            k,
            Side::Lower,
            LltRegularization::default(),
            par,
            MemStack::new(&mut scratch),
            Default::default(),
        )?;
        let t_numeric = clock.elapsed().as_secs_f64();
        let clock = Instant::now();
        let mut x = Mat::from_fn(n, 1, |i, _| system.rhs()[i]);
        let mut scratch = MemBuffer::try_new(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq))?;
        llt.solve_in_place_with_conj(Conj::No, x.as_mut(), Par::Seq, MemStack::new(&mut scratch));
        let t_solve = clock.elapsed().as_secs_f64();
        let u: Vec<f64> = (0..n).map(|i| x[(i, 0)]).collect();
        let energy = system.strain_energy(&system.expand(&u)?)?;
        println!(
            "  order (ND)        {t_order:8.3} s
  faer symbolic     {t_symbolic:8.3} s   factor entries {}
  faer numeric      {t_numeric:8.3} s   peak {:.0} MiB
  faer solve        {t_solve:8.3} s   strain energy {energy:.9e}",
            symbolic.len_val(),
            peak_memory_mib()
        );
        let faer = t_order + t_symbolic + t_numeric + t_solve;
        println!(
            "| {} | {} | faer, ND order | {t_mesh:.2} | {t_assembly:.2} | {:.2} | {t_numeric:.2} | {t_solve:.3} | - | {faer:.2} | {:.3e} | {:.2} |",
            family.name(),
            body.dofs().n_unknowns(),
            t_order + t_symbolic,
            symbolic.len_val() as f64,
            peak_memory_mib() / 1024.0
        );
        return Ok(());
    }

    if faer_only {
        let k = system.stiffness().as_ref();
        let clock = Instant::now();
        let symbolic = SymbolicLlt::try_new(k.symbolic(), Side::Lower)?;
        let t_symbolic = clock.elapsed().as_secs_f64();
        let clock = Instant::now();
        let llt = Llt::try_new_with_symbolic(symbolic, k, Side::Lower)?;
        let t_numeric = clock.elapsed().as_secs_f64();
        let clock = Instant::now();
        let rhs = Mat::from_fn(system.rhs().len(), 1, |i, _| system.rhs()[i]);
        let x = llt.solve(&rhs);
        let t_solve = clock.elapsed().as_secs_f64();
        let u: Vec<f64> = (0..x.nrows()).map(|i| x[(i, 0)]).collect();
        let energy = system.strain_energy(&system.expand(&u)?)?;
        println!(
            "  faer symbolic     {t_symbolic:8.3} s\n  faer numeric      {t_numeric:8.3} s   peak {:.0} MiB\n  faer solve        {t_solve:8.3} s   strain energy {energy:.9e}",
            peak_memory_mib()
        );
        let faer = t_symbolic + t_numeric + t_solve;
        println!(
            "| {} | {} | faer alone | {t_mesh:.2} | {t_assembly:.2} | {t_symbolic:.2} | {t_numeric:.2} | {t_solve:.3} | - | {faer:.2} | - | {:.2} |",
            family.name(),
            body.dofs().n_unknowns(),
            peak_memory_mib() / 1024.0
        );
        return Ok(());
    }

    // The steps of ElasticBody::solve_system, timed one by one.
    let mut solver = CholeskySolver::new(CholeskySettings::builder().ordering(ordering).build()?);
    let clock = Instant::now();
    solver.analyse(system.stiffness().symbolic())?;
    let t_symbolic = clock.elapsed().as_secs_f64();
    let stats = solver.statistics();
    println!(
        "  symbolic ({:?})  {t_symbolic:8.3} s   factor entries {} ({:.0} MiB), flops {:.3e}   peak {:.0} MiB",
        stats.ordering.unwrap_or(ordering),
        stats.factor_entries,
        stats.factor_entries as f64 * 8.0 / 1048576.0,
        stats.flops,
        peak_memory_mib()
    );
    let clock = Instant::now();
    solver.factorise(system.stiffness().as_ref())?;
    let t_numeric = clock.elapsed().as_secs_f64();
    println!(
        "  numeric           {t_numeric:8.3} s   peak {:.0} MiB",
        peak_memory_mib()
    );
    let clock = Instant::now();
    let u_free = solver.solve(system.rhs())?;
    let t_solve = clock.elapsed().as_secs_f64();
    let clock = Instant::now();
    let displacement = system.expand(&u_free)?;
    let solution = body.solution(&system, displacement)?;
    let t_post = clock.elapsed().as_secs_f64();
    let reaction = solution.reaction("bottom").expect("a Dirichlet part");
    println!(
        "  solve             {t_solve:8.3} s\n  post-processing   {t_post:8.3} s   strain energy {:.9e}, reaction ({:.6}, {:.6}, {:.6})   peak {:.0} MiB",
        solution.strain_energy(),
        reaction.x,
        reaction.y,
        reaction.z,
        peak_memory_mib()
    );
    let whole = t_assembly + t_symbolic + t_numeric + t_solve + t_post;
    println!(
        "| {} | {} | {:?} | {t_mesh:.2} | {t_assembly:.2} | {t_symbolic:.2} | {t_numeric:.2} | {t_solve:.3} | {t_post:.3} | {:.2} | {:.3e} | {:.2} |",
        family.name(),
        body.dofs().n_unknowns(),
        stats.ordering.unwrap_or(ordering),
        t_symbolic + t_numeric + t_solve,
        stats.factor_entries as f64,
        peak_memory_mib() / 1024.0
    );
    println!("  whole solve (assembly to post-processing) {whole:.2} s");
    Ok(())
}
