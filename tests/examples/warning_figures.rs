//! The figures behind two warning thresholds of the contact layer (docs/contact.md, section
//! 4.4). Run with
//!
//! ```text
//! cargo run --release -p vem-integration-tests --example warning_figures
//! ```
//!
//! * Short edges (`Warning::ElementShape` floors): the shape figures of the Hertz meshes before
//!   and after interface node insertion, and M1 (quads, n = 32) with the lower body's
//!   interface nodes shifted by `eps h` (no snapping), so that insertion makes edges of
//!   `eps h` on both sides: the errors with the condensed and the exact solver against the
//!   matching meshes.
//! * Penetration (`Warning::Penetration`): M2 (quads, n = 64) with the penalty solver at
//!   factors 1 to 1e6, the largest penetration against the displacement scale and the energy
//!   error against the condensed solver's.

use std::error::Error;
use std::path::Path;
use std::sync::Arc;

use vem_contact::{
    CondensedSolver, ContactResult, ContactSolver, ExactSolver, PenaltyParameter, PenaltySettings,
    PenaltySolver, Warning,
};
use vem_mesh::generators::MeshFamily;
use vem_mesh::interface::{insert_interface_nodes, InterfaceOptions};
use vem_mesh::io::read_gmsh;
use vem_mesh::Mesh;
use vem_verify::exact::{case_by_name, ExactSolution, Lame};
use vem_verify::norms::ErrorNorms;
use vem_verify::problem::{DiscreteProblem, DiscreteSolution, ProblemSettings};

type Res<T> = Result<T, Box<dyn Error>>;

/// The smallest (gamma, shortest edge / diameter, star radius / diameter) over the cells.
fn figures(mesh: &Mesh) -> (f64, f64, f64) {
    (0..mesh.n_polygons()).fold((1.0f64, 1.0f64, 1.0f64), |(g, e, s), c| {
        let q = mesh.element_quality(c);
        (
            g.min(q.gamma()),
            e.min(q.shortest_edge_ratio),
            s.min(q.star_ratio),
        )
    })
}

fn errors(result: &ContactResult, exact: &dyn ExactSolution) -> Res<ErrorNorms> {
    let solution = DiscreteSolution {
        bodies: result.bodies.clone(),
        interface: None,
        work: result.work,
        assembly_time: Default::default(),
        solve_time: Default::default(),
    };
    Ok(ErrorNorms::combine(&solution.errors(exact)?))
}

fn hertz_meshes() -> Res<()> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    for (disc, block) in [
        (
            "crates/vem-cli/scenes/hertz_disc.msh",
            "crates/vem-cli/scenes/hertz_block.msh",
        ),
        (
            "xtask/data/hertz/disc_hc0.02.msh",
            "xtask/data/hertz/block_hc0.02.msh",
        ),
    ] {
        let (a, b) = (read_gmsh(root.join(disc))?, read_gmsh(root.join(block))?);
        let options = InterfaceOptions::builder().max_distance(0.05).build()?;
        let interface = insert_interface_nodes(&a, "arc", &b, "top", &options)?;
        for (name, before, after) in [
            (disc, &a, &interface.mesh_a),
            (block, &b, &interface.mesh_b),
        ] {
            let (g0, e0, s0) = figures(before);
            let (g1, e1, s1) = figures(after);
            println!(
                "{name}: gamma {g0:.3} (edge {e0:.3}, star {s0:.3}) before insertion, \
                 {g1:.1e} (edge {e1:.1e}, star {s1:.3}) after"
            );
        }
    }
    Ok(())
}

fn short_edges() -> Res<()> {
    let n = 32;
    let exact: Arc<dyn ExactSolution> = Arc::from(case_by_name("M1", Lame::default())?);
    let options = InterfaceOptions::builder()
        .min_edge_fraction(1e-10)
        .snap_tolerance(1e-10)
        .build()?;
    for eps in [0.0, 1e-2, 1e-4, 1e-6, 1e-8] {
        let mut meshes = exact
            .bodies()
            .iter()
            .map(|&b| MeshFamily::Quads.generate(&exact.domain(b), n, 1))
            .collect::<Result<Vec<Mesh>, _>>()?;
        let lower = &meshes[1];
        let mut vertices = lower.vertices().to_vec();
        for v in lower.part_vertices("top")? {
            if vertices[v].x > 1e-12 && vertices[v].x < 1.0 - 1e-12 {
                vertices[v].x += eps / n as f64;
            }
        }
        let polygons: Vec<Vec<usize>> = lower.polygons().map(<[usize]>::to_vec).collect();
        meshes[1] = Mesh::from_polygons(vertices, &polygons, lower.part_specs())?;
        let problem = DiscreteProblem::try_new(exact.clone(), meshes, &ProblemSettings::default())?;
        let solvers: [(&str, Box<dyn ContactSolver>); 2] = [
            ("condensed", Box::new(CondensedSolver::default())),
            ("exact", Box::new(ExactSolver::default())),
        ];
        for (name, mut solver) in solvers {
            let result = problem
                .contact_problem()
                .ok_or("a contact case")?
                .with_interface_options(options)
                .solve(solver.as_mut())?;
            let edge = result
                .bodies
                .iter()
                .filter_map(|b| b.body.body_mesh().as_planar().map(|m| figures(m).1))
                .fold(1.0f64, f64::min);
            let e = errors(&result, exact.as_ref())?;
            let shape = result
                .warnings
                .iter()
                .filter(|w| matches!(w, Warning::ElementShape { .. }))
                .count();
            println!(
                "M1 quads n = {n}, interface shifted by {eps:.0e} h, {name}: shortest edge / \
                 diameter {edge:.1e}, E_grad/|u|_1 {:.5e}, E_0/|u|_0 {:.5e}, shape warnings {shape}",
                e.grad / e.exact_grad,
                e.l2 / e.exact_l2,
            );
        }
    }
    Ok(())
}

fn penetration() -> Res<()> {
    let n = 64;
    let exact: Arc<dyn ExactSolution> = Arc::from(case_by_name("M2", Lame::default())?);
    let meshes = exact
        .bodies()
        .iter()
        .map(|&b| MeshFamily::Quads.generate(&exact.domain(b), n, 1))
        .collect::<Result<Vec<Mesh>, _>>()?;
    let problem = DiscreteProblem::try_new(exact.clone(), meshes, &ProblemSettings::default())?;
    let solve = |solver: &mut dyn ContactSolver| -> Res<ContactResult> {
        Ok(problem
            .contact_problem()
            .ok_or("a contact case")?
            .solve(solver)?)
    };
    let reference = errors(&solve(&mut CondensedSolver::default())?, exact.as_ref())?;
    for factor in [1.0, 1e1, 1e2, 1e3, 1e4, 1e6] {
        let settings = PenaltySettings::builder()
            .penalty(PenaltyParameter::RelativeToStiffness(factor))
            .build()?;
        let result = solve(&mut PenaltySolver::new(settings))?;
        let e = errors(&result, exact.as_ref())?;
        let warned = result
            .warnings
            .iter()
            .any(|w| matches!(w, Warning::Penetration { .. }));
        println!(
            "M2 quads n = {n}, penalty factor {factor:.0e}: penetration / U {:.1e}, energy \
             error {:.3e} ({:.3} x the condensed solver's), penetration warning {warned}",
            result.report.residuals.max_penetration,
            e.energy / e.interpolant_energy,
            e.energy / reference.energy
        );
    }
    Ok(())
}

fn main() -> Res<()> {
    hertz_meshes()?;
    short_edges()?;
    penetration()
}
