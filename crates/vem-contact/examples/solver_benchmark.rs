//! Times the contact solvers on a synthetic two-body system.
//!
//! Two square grids of `side x side` nodes with two unknowns per node and a 5-point
//! Laplacian stiffness per component (a stand-in for assembled elasticity), clamped on their
//! far rows, pressed together across a curved gap along their facing rows (node-to-node
//! normal and tangential rows) and sheared. Run with
//!
//! ```text
//! cargo run --release -p vem-contact --example solver_benchmark -- [side] [friction_bound] [gap_curvature]
//! ```
//!
//! (`side = 50` gives about 10^4 unknowns; the gap is `gap_curvature (x - 1/2)^2`, 0 for no
//! friction.)

use std::error::Error;

use faer::sparse::{SparseColMat, Triplet};
use vem_contact::{
    ActiveSetSolver, ConstraintRows, ContactSolution, ContactSolver, ContactSystem, ExactSolver,
    Friction, PenaltySolver,
};

/// Unknown index of component `c` of grid node `(i, j)` of body `body`, or `None` on the
/// clamped row (row 0 of body 0, row `side - 1` of body 1).
fn dof(side: usize, body: usize, i: usize, j: usize, c: usize) -> Option<usize> {
    let clamped = if body == 0 { 0 } else { side - 1 };
    if j == clamped {
        return None;
    }
    let j_free = if body == 0 { j - 1 } else { j };
    Some(((body * (side - 1) + j_free) * side + i) * 2 + c)
}

fn build(
    side: usize,
    friction_bound: f64,
    curvature: f64,
) -> Result<ContactSystem<'static>, Box<dyn Error>> {
    let n = 2 * 2 * side * (side - 1);
    let mut triplets = Vec::new();
    let mut load = vec![0.0; n];
    for body in 0..2 {
        for j in 0..side {
            for i in 0..side {
                for c in 0..2 {
                    let Some(p) = dof(side, body, i, j, c) else {
                        continue;
                    };
                    let neighbours = [
                        (i.wrapping_sub(1), j),
                        (i + 1, j),
                        (i, j.wrapping_sub(1)),
                        (i, j + 1),
                    ];
                    let mut diag = 0.0;
                    for (ni, nj) in neighbours {
                        if ni >= side || nj >= side {
                            continue;
                        }
                        diag += 1.0;
                        if let Some(q) = dof(side, body, ni, nj, c) {
                            triplets.push(Triplet::new(p, q, -1.0));
                        }
                    }
                    triplets.push(Triplet::new(p, p, diag));
                    let h = 1.0 / side as f64;
                    // Body 0 pushed up (+y) and right, body 1 down and left.
                    let sign = if body == 0 { 1.0 } else { -1.0 };
                    load[p] = sign * h * h * if c == 1 { 20.0 } else { 2.0 };
                }
            }
        }
    }
    let stiffness = SparseColMat::try_new_from_triplets(n, n, &triplets)?;
    // Facing rows: top row of body 0 (j = side - 1) and bottom row of body 1 (j = 0).
    let (mut normal, mut tangential, mut gap) = (Vec::new(), Vec::new(), Vec::new());
    for i in 0..side {
        let (Some(a_x), Some(a_y), Some(b_x), Some(b_y)) = (
            dof(side, 0, i, side - 1, 0),
            dof(side, 0, i, side - 1, 1),
            dof(side, 1, i, 0, 0),
            dof(side, 1, i, 0, 1),
        ) else {
            continue;
        };
        // nu_1 = +y: [u]_nu = (u_1 - u_2) . nu_1, tangent +x.
        normal.extend([(i, a_y, 1.0), (i, b_y, -1.0)]);
        tangential.extend([(i, a_x, 1.0), (i, b_x, -1.0)]);
        let x = i as f64 / (side - 1) as f64;
        gap.push(curvature * (x - 0.5) * (x - 0.5));
    }
    let m = gap.len();
    let normal = ConstraintRows::try_from_triplets(m, n, &normal)?;
    let friction = (friction_bound > 0.0)
        .then(|| {
            let rows = ConstraintRows::try_from_triplets(m, n, &tangential)?;
            Friction::try_new(rows, vec![friction_bound / side as f64; m])
        })
        .transpose()?;
    Ok(ContactSystem::try_new(
        stiffness, load, normal, gap, friction,
    )?)
}

fn main() -> Result<(), Box<dyn Error>> {
    let args: Vec<String> = std::env::args().collect();
    let side: usize = args.get(1).map_or(Ok(50), |s| s.parse())?;
    let friction_bound: f64 = args.get(2).map_or(Ok(0.5), |s| s.parse())?;
    let curvature: f64 = args.get(3).map_or(Ok(20.0), |s| s.parse())?;
    let system = build(side, friction_bound, curvature)?;
    println!(
        "unknowns n = {}, interface nodes m = {}, friction bound per node {:.3e}",
        system.n_dofs(),
        system.n_constraints(),
        friction_bound / side as f64
    );
    let mut solvers: Vec<Box<dyn ContactSolver>> = vec![
        Box::new(ExactSolver::default()),
        Box::new(PenaltySolver::default()),
        Box::new(ActiveSetSolver::default()),
    ];
    let mut reference: Option<ContactSolution> = None;
    let header = [
        "iter", "fact", "time [s]", "penetr.", "tension", "compl.", "station.", "bound",
        "slip dir", "du/|u|", "dlambda",
    ];
    print!("{:<28}", "solver");
    for h in header {
        print!(" {h:>9}");
    }
    println!();
    let max = |a: &[f64], b: &[f64]| {
        a.iter()
            .zip(b)
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
    };
    for solver in &mut solvers {
        let s = solver.solve(&system)?;
        let r = &s.report;
        let (du, dl) = reference.as_ref().map_or((0.0, 0.0), |e| {
            let u_inf = e.displacement.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            (
                max(&e.displacement, &s.displacement) / u_inf,
                max(&e.normal_force, &s.normal_force)
                    .max(max(&e.tangential_force, &s.tangential_force)),
            )
        });
        let k = &r.residuals;
        print!(
            "{:<28} {:>9} {:>9} {:>9.4}",
            r.solver,
            r.iterations,
            r.work.numeric_factorisations,
            r.wall_time.as_secs_f64()
        );
        for v in [
            k.max_penetration,
            k.negative_normal_force,
            k.complementarity,
            k.stationarity,
            k.friction_bound_violation,
            k.slip_direction_violation,
            du,
            dl,
        ] {
            print!(" {v:>9.1e}");
        }
        println!();
        if reference.is_none() {
            let active = s.normal_force.iter().filter(|&&l| l > 1e-9).count();
            let bound = friction_bound / side as f64;
            let sliding = s
                .tangential_force
                .iter()
                .filter(|&&l| bound > 0.0 && (l.abs() - bound).abs() < 1e-9)
                .count();
            println!("  exact answer: {active} nodes in contact, {sliding} at the friction bound");
            reference = Some(s);
        }
    }
    Ok(())
}
