//! The cost of a load history against one elastic solve of the same meshes: the Hertz scene
//! (a half-disc of radius 1 on a block, Gmsh meshes, Coulomb F = 0.3) followed through 100
//! load steps: 20 steps pressing the disc's top down by 0.02, then 80 steps moving it sideways
//! forth and back (+-0.004, Cattaneo-Mindlin partial slip, two reversals).
//!
//! ```sh
//! scripts/hertz-meshes.sh 0.002 0.0125 0.039 target/fretting/disc_1e5 target/fretting/block_1e5
//! cargo run --release -p vem-integration-tests --example history_speed -- \
//!     target/fretting/disc_1e5.msh target/fretting/block_1e5.msh [STEPS]
//! ```
//!
//! Prints the discretisation, the history (total, per step, and the work counters), the elastic
//! reference (every body alone with its Dirichlet data on the enlarged meshes: assembly,
//! analysis, factorisation, one solve, as `cargo xtask bench` measures it; the median of three
//! runs before the history and three after) and the ratio.

use std::sync::Arc;
use std::time::Instant;

use vem_contact::{
    CondensedSolver, ContactProblem, Coulomb, LoadCondition, LoadCurve, LoadCurves, LoadHistory,
    LoadPath,
};
use vem_elastic::{
    CholeskySolver, Component, Dirichlet, ElasticBody, LinearSolver, Material, Plane,
};
use vem_mesh::interface::InterfaceOptions;
use vem_mesh::io::read_gmsh;
use vem_mesh::Vector;
use vem_space::LowestOrderVem;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (Some(disc), Some(block)) = (args.first(), args.get(1)) else {
        return Err("usage: history_speed DISC.msh BLOCK.msh [STEPS]".into());
    };
    let steps: usize = args.get(2).map_or(Ok(100), |s| s.parse())?;
    let material = Material::from_young_poisson(100.0, 0.3, Plane::Strain)?;
    let element = Arc::new(LowestOrderVem::default());
    let start = Instant::now();
    let disc = ElasticBody::builder("disc", read_gmsh(disc)?, material, element.clone())
        .dirichlet(Dirichlet::prescribed("top", Component::Y, |_| {
            Vector::new(0.0, -0.02)
        }))
        .dirichlet(Dirichlet::prescribed("top", Component::X, |_| {
            Vector::new(0.004, 0.0)
        }))
        .build()?;
    let block = ElasticBody::builder("block", read_gmsh(block)?, material, element)
        .clamp("bottom")
        .build()?;
    let problem = ContactProblem::two_bodies(disc, "arc", block, "top", Coulomb::try_new(0.3)?)
        .with_interface_options(InterfaceOptions::builder().max_distance(0.05).build()?);
    let read = start.elapsed().as_secs_f64();
    let start = Instant::now();
    let discretisation = problem.into_discretisation()?;
    let build = start.elapsed().as_secs_f64();
    println!(
        "meshes read in {read:.2} s; discretised in {build:.2} s: {} unknowns, {} interface nodes",
        discretisation.n_dofs(),
        discretisation.nodes().len()
    );

    // The elastic reference, measured three times before the history and three times after
    // it (the machine may be shared): their median.
    let elastic_solve = || -> Result<f64, Box<dyn std::error::Error>> {
        let mut seconds = 0.0;
        for body in discretisation.bodies() {
            let start = Instant::now();
            let system = body.assemble()?;
            let mut cholesky = CholeskySolver::default();
            cholesky.analyse(system.stiffness().symbolic())?;
            cholesky.factorise(system.stiffness().as_ref())?;
            let u = cholesky.solve(system.rhs())?;
            std::hint::black_box(u);
            seconds += start.elapsed().as_secs_f64();
        }
        Ok(seconds)
    };
    let mut elastic_times = Vec::new();
    for _ in 0..3 {
        elastic_times.push(elastic_solve()?);
    }

    // 20 % of the steps pressing, then the shift 0 -> 1 -> -1 -> 1 (in units of 0.004).
    let press = LoadCondition::Dirichlet { body: 0, index: 0 };
    let shear = LoadCondition::Dirichlet { body: 0, index: 1 };
    let curves = LoadCurves::default()
        .with(press, LoadCurve::try_new(vec![(0.0, 0.0), (1.0, 1.0)])?)
        .with(
            shear,
            LoadCurve::try_new(vec![(1.0, 0.0), (2.0, 1.0), (4.0, -1.0), (5.0, 1.0)])?,
        );
    let pressing = steps / 5;
    let times: Vec<f64> = (1..=steps)
        .map(|k| {
            if k <= pressing {
                k as f64 / pressing as f64
            } else {
                1.0 + 4.0 * (k - pressing) as f64 / (steps - pressing) as f64
            }
        })
        .collect();
    let history = LoadHistory::from_curves(times, &curves)?;
    let mut solver = CondensedSolver::default();
    let mut path = LoadPath::new(&discretisation)?;
    let start = Instant::now();
    let mut work = vem_contact::WorkCounters::default();
    let (mut fixed_point_steps, mut iterations) = (0, 0);
    let mut slowest = (0.0f64, 0usize);
    for (k, step) in history.steps().iter().enumerate() {
        let t = Instant::now();
        let result = path.advance(&mut solver, step.time, &step.factors)?;
        let seconds = t.elapsed().as_secs_f64();
        if seconds > slowest.0 {
            slowest = (seconds, k);
        }
        work += result.work;
        if let Some(f) = &result.fixed_point {
            fixed_point_steps += f.steps;
            iterations += f.solver_iterations;
        }
        if k + 1 == steps {
            let counts = result.status_counts();
            let (open, stick, slip) = (counts.open, counts.stick, counts.slip);
            let force = result.force_on_body_a();
            println!(
                "last step: P = {:.6}, Q = {:.6}, open / stick / slip nodes {open} / {stick} / {slip}",
                force.y,
                force.x.abs()
            );
        }
    }
    let history_time = start.elapsed().as_secs_f64();
    for _ in 0..3 {
        elastic_times.push(elastic_solve()?);
    }
    elastic_times.sort_by(f64::total_cmp);
    let elastic = 0.5 * (elastic_times[2] + elastic_times[3]);
    println!(
        "one elastic solve of the same meshes: {elastic:.3} s (median of 6: {:.3} to {:.3} s)",
        elastic_times[0], elastic_times[5]
    );
    println!(
        "{steps} steps in {history_time:.3} s ({:.1} ms per step, slowest {:.1} ms at step {}): \
         {:.2} x one elastic solve",
        1e3 * history_time / steps as f64,
        1e3 * slowest.0,
        slowest.1,
        history_time / elastic
    );
    println!(
        "fixed-point steps {fixed_point_steps} ({:.1} per load step), interface iterations \
         {iterations}; work: {} symbolic analyses, {} factorisations, {} triangular solves; \
         times: symbolic {:.3} s, numeric {:.3} s, solves {:.3} s, contact solve {:.3} s, post {:.3} s",
        fixed_point_steps as f64 / steps as f64,
        work.symbolic_analyses,
        work.numeric_factorisations,
        work.triangular_solves,
        work.times.symbolic.as_secs_f64(),
        work.times.numeric.as_secs_f64(),
        work.times.solves.as_secs_f64(),
        work.times.contact_solve.as_secs_f64(),
        work.times.post.as_secs_f64()
    );
    Ok(())
}
