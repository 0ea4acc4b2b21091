//! Contact solvers on tiny problems whose answer is known by hand.

use faer::sparse::{SparseColMat, Triplet};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use vem_contact::{
    ActiveSetSettings, ActiveSetSolver, CondensedSolver, ConstraintRows, ContactSolution,
    ContactSolver, ContactSolverError, ContactSystem, ContactSystemError, ExactSettings,
    ExactSolver, Friction, PenaltyParameter, PenaltySettings, PenaltySolver, SolveStatus,
};

fn matrix(n: usize, entries: &[(usize, usize, f64)]) -> SparseColMat<usize, f64> {
    let triplets: Vec<_> = entries
        .iter()
        .map(|&(i, j, v)| Triplet::new(i, j, v))
        .collect();
    SparseColMat::try_new_from_triplets(n, n, &triplets).expect("valid stiffness triplets")
}

fn rows(nrows: usize, ncols: usize, entries: &[(usize, usize, f64)]) -> ConstraintRows {
    ConstraintRows::try_from_triplets(nrows, ncols, entries).expect("valid rows")
}

fn exact() -> ExactSolver {
    ExactSolver::default()
}

fn active() -> ActiveSetSolver {
    ActiveSetSolver::default()
}

fn condensed() -> CondensedSolver {
    CondensedSolver::default()
}

/// Penalty solver with `eps_N = eps_T = factor x` the largest constrained diagonal of `K`.
fn relative_penalty(factor: f64) -> PenaltySolver {
    PenaltySolver::new(
        PenaltySettings::builder()
            .penalty(PenaltyParameter::RelativeToStiffness(factor))
            .build()
            .expect("valid settings"),
    )
}

fn penalty(eps: f64) -> PenaltySolver {
    PenaltySolver::new(
        PenaltySettings::builder()
            .penalty(PenaltyParameter::Absolute(eps))
            .build()
            .expect("valid settings"),
    )
}

fn solve(solver: &mut dyn ContactSolver, system: &ContactSystem) -> ContactSolution {
    match solver.solve(system) {
        Ok(s) => s,
        Err(e) => panic!("{} failed: {e}", solver.name()),
    }
}

fn assert_close(a: f64, b: f64, tol: f64, what: &str) {
    assert!((a - b).abs() <= tol, "{what}: {a} vs {b} (tol {tol})");
}

/// One spring `k` against a wall at `gap`, load `f`.
fn spring(k: f64, f: f64, gap: f64) -> ContactSystem<'static> {
    ContactSystem::try_new(
        matrix(1, &[(0, 0, k)]),
        vec![f],
        rows(1, 1, &[(0, 0, 1.0)]),
        vec![gap],
        None,
    )
    .expect("valid system")
}

#[test]
fn one_dof_spring_touching_the_wall() {
    let (k, f, g) = (2.0, 3.0, 1.0);
    let s = solve(&mut exact(), &spring(k, f, g));
    assert_close(s.displacement[0], g, 1e-9, "u");
    assert_close(s.normal_force[0], f - k * g, 1e-9, "lambda_N");
    assert_eq!(s.tangential_force, vec![0.0]);
    assert_eq!(s.report.status, SolveStatus::Converged);
    assert!(s.report.residuals.max_violation() < 1e-9);
    assert!(s.report.residuals.stationarity < 1e-9);
    let a = solve(&mut active(), &spring(k, f, g));
    assert_close(a.displacement[0], g, 1e-11, "active-set u");
    assert_close(a.normal_force[0], f - k * g, 1e-10, "active-set lambda_N");
    assert_eq!(a.report.iterations, 2, "one split to find, one to confirm");

    // Penalty: u = (f + eps g) / (k + eps) exactly, lambda = eps (u - g).
    let eps = 1e4;
    let p = solve(&mut penalty(eps), &spring(k, f, g));
    let u = (f + eps * g) / (k + eps);
    assert_close(p.displacement[0], u, 1e-13, "penalty u");
    assert_close(p.normal_force[0], eps * (u - g), 1e-10, "penalty lambda");
    // Relative to the displacement scale U = max(|u|, |g|, |f| / k) = 1.5.
    assert_eq!(p.report.residuals.scales.displacement, f / k);
    assert_close(
        p.report.residuals.max_penetration,
        (u - g) / (f / k),
        1e-13,
        "penetration",
    );
}

#[test]
fn one_dof_spring_short_of_the_wall() {
    let (k, f, g) = (2.0, 1.0, 1.0);
    for solver in [
        &mut exact() as &mut dyn ContactSolver,
        &mut active() as &mut dyn ContactSolver,
        &mut condensed() as &mut dyn ContactSolver,
        &mut penalty(1e3) as &mut dyn ContactSolver,
    ] {
        let s = solve(solver, &spring(k, f, g));
        assert_close(s.displacement[0], f / k, 1e-9, "u");
        assert_close(s.normal_force[0], 0.0, 1e-9, "lambda_N");
    }
}

#[test]
fn negative_gap_pushes_the_spring_back() {
    // The wall stands at -0.5: a spring without load is pushed back to it.
    let (k, g) = (4.0, -0.5);
    for solver in [
        &mut exact() as &mut dyn ContactSolver,
        &mut active() as &mut dyn ContactSolver,
        &mut condensed() as &mut dyn ContactSolver,
    ] {
        let s = solve(solver, &spring(k, 0.0, g));
        assert_close(s.displacement[0], g, 1e-9, "u");
        assert_close(s.normal_force[0], -k * g, 1e-8, "lambda_N");
    }
}

/// Wall - k1 - node 0 - k2 - node 1 - wall at `gap`; load `f` on node 1.
fn two_springs(k1: f64, k2: f64, f: f64, gap: f64) -> ContactSystem<'static> {
    ContactSystem::try_new(
        matrix(2, &[(0, 0, k1 + k2), (0, 1, -k2), (1, 0, -k2), (1, 1, k2)]),
        vec![0.0, f],
        rows(1, 2, &[(0, 1, 1.0)]),
        vec![gap],
        None,
    )
    .expect("valid system")
}

#[test]
fn two_springs_in_series_against_a_wall() {
    let (k1, k2, f) = (3.0, 1.0, 2.0);
    // Free: u1 = f/k1 + f/k2 = 2.6667.
    let free_u1 = f / k1 + f / k2;
    // Penalty error ~ lambda / eps = 1e-8 here.
    for (solver, tol) in [
        (&mut exact() as &mut dyn ContactSolver, 1e-9),
        (&mut active() as &mut dyn ContactSolver, 1e-12),
        (&mut condensed() as &mut dyn ContactSolver, 1e-12),
        (&mut relative_penalty(1e8) as &mut dyn ContactSolver, 1e-7),
    ] {
        let inactive = solve(solver, &two_springs(k1, k2, f, 3.0));
        assert_close(inactive.displacement[0], f / k1, tol, "u0 free");
        assert_close(inactive.displacement[1], free_u1, tol, "u1 free");
        assert_close(inactive.normal_force[0], 0.0, tol, "lambda free");

        let g = 1.0;
        let active = solve(solver, &two_springs(k1, k2, f, g));
        let u0 = k2 * g / (k1 + k2);
        assert_close(active.displacement[0], u0, tol, "u0");
        assert_close(active.displacement[1], g, tol, "u1");
        assert_close(
            active.normal_force[0],
            f - k1 * k2 * g / (k1 + k2),
            tol,
            "lambda",
        );
    }
}

/// Two bodies, each a chain wall - k - a - k - b, whose free ends face each other across a gap:
/// body 1 (unknowns 0, 1) on the left pushed right by `f` at its end 1, body 2 (unknowns 2, 3)
/// on the right pushed left by `f` at its end 2. `[u]_nu = (u_1 - u_2) . nu_1 = u[1] - u[2]`.
fn two_chains(k: f64, f: f64, gap: f64) -> ContactSystem<'static> {
    let stiffness = matrix(
        4,
        &[
            (0, 0, 2.0 * k),
            (0, 1, -k),
            (1, 0, -k),
            (1, 1, k),
            (2, 2, k),
            (2, 3, -k),
            (3, 2, -k),
            (3, 3, 2.0 * k),
        ],
    );
    ContactSystem::try_new(
        stiffness,
        vec![0.0, f, -f, 0.0],
        rows(1, 4, &[(0, 1, 1.0), (0, 2, -1.0)]),
        vec![gap],
        None,
    )
    .expect("valid system")
}

#[test]
fn two_chains_pressed_together() {
    let (k, f, g) = (10.0, 5.0, 0.4);
    // Each chain has end flexibility 2/k: the free jump 4f/k = 2 exceeds g.
    let lambda = f - g * k / 4.0;
    for (solver, tol) in [
        (&mut exact() as &mut dyn ContactSolver, 1e-9),
        (&mut active() as &mut dyn ContactSolver, 1e-12),
        (&mut condensed() as &mut dyn ContactSolver, 1e-12),
        (&mut relative_penalty(1e8) as &mut dyn ContactSolver, 1e-7),
    ] {
        let s = solve(solver, &two_chains(k, f, g));
        let u = &s.displacement;
        assert_close(s.normal_force[0], lambda, tol, "contact force");
        assert_close(u[1] - u[2], g, tol, "closed gap");
        assert_close(u[1], 2.0 * (f - lambda) / k, tol, "body 1 end");
        assert_close(u[2], -2.0 * (f - lambda) / k, tol, "body 2 end");
        // Equal and opposite contact forces on the two bodies: each chain end balances.
        assert_close(
            k * (u[1] - u[0]),
            f - s.normal_force[0],
            tol,
            "body 1 end balance",
        );
        assert_close(
            k * (u[3] - u[2]),
            f - s.normal_force[0],
            tol,
            "body 2 end balance",
        );
        assert_close(
            2.0 * k * u[0] - k * u[1],
            0.0,
            tol,
            "inner node equilibrium",
        );
        assert!(
            s.report.residuals.stationarity < 10.0 * tol,
            "{:?}",
            s.report
        );
    }
    let s = solve(&mut exact(), &two_chains(k, f, g));
    assert!(s.report.residuals.complementarity < 1e-8);
    let s = solve(&mut active(), &two_chains(k, f, g));
    assert!(s.report.residuals.complementarity < 1e-12);
}

/// A block with tangential spring `kx` (unknown 0) and normal spring `ky` (unknown 1) on a
/// rigid foundation: `B_N u = u[1] <= 0`, `B_T u = u[0]`, friction bound `b`.
fn block(kx: f64, ky: f64, load: [f64; 2], b: f64) -> ContactSystem<'static> {
    let mut entries = vec![(1, 1, ky)];
    if kx != 0.0 {
        entries.push((0, 0, kx));
    }
    let friction = Friction::try_new(rows(1, 2, &[(0, 0, 1.0)]), vec![b]).expect("valid friction");
    ContactSystem::try_new(
        matrix(2, &entries),
        load.to_vec(),
        rows(1, 2, &[(0, 1, 1.0)]),
        vec![0.0],
        Some(friction),
    )
    .expect("valid system")
}

#[test]
fn tresca_block_sticks_below_the_bound() {
    let (kx, ky, b) = (4.0, 9.0, 2.0);
    for fx in [1.5, -1.5, 0.0] {
        for solver in [
            &mut exact() as &mut dyn ContactSolver,
            &mut active() as &mut dyn ContactSolver,
            &mut condensed() as &mut dyn ContactSolver,
        ] {
            let s = solve(solver, &block(kx, ky, [fx, 3.0], b));
            assert_close(s.displacement[0], 0.0, 1e-9, "no slip");
            assert_close(s.displacement[1], 0.0, 1e-9, "in contact");
            assert_close(s.tangential_force[0], fx, 1e-8, "lambda_T = load");
            assert_close(s.normal_force[0], 3.0, 1e-8, "lambda_N");
            assert!(s.report.residuals.max_violation() < 1e-8);
        }
    }
    // Penalty: elastic slip fx / (kx + eps) exactly while |eps slip| < b.
    let eps = 1e6;
    let s = solve(&mut penalty(eps), &block(kx, ky, [1.5, 3.0], b));
    assert_close(s.displacement[0], 1.5 / (kx + eps), 1e-15, "elastic slip");
    assert_close(
        s.tangential_force[0],
        eps * 1.5 / (kx + eps),
        1e-10,
        "lambda_T",
    );
}

#[test]
fn tresca_block_slips_above_the_bound() {
    let (kx, ky, b) = (4.0, 9.0, 2.0);
    for fx in [5.0f64, -5.0] {
        let sign = fx.signum();
        let expected_slip = (fx - sign * b) / kx;
        for solver in [
            &mut exact() as &mut dyn ContactSolver,
            &mut active() as &mut dyn ContactSolver,
            &mut condensed() as &mut dyn ContactSolver,
            &mut penalty(1e6) as &mut dyn ContactSolver,
        ] {
            let s = solve(solver, &block(kx, ky, [fx, 3.0], b));
            // The penalty slip is exact: in slip its tangential force is exactly b.
            assert_close(s.displacement[0], expected_slip, 1e-9, "slip");
            assert_eq!(s.displacement[0].signum(), sign, "slip follows the load");
            assert_close(
                s.tangential_force[0],
                sign * b,
                1e-9,
                "lambda_T = b sign(slip)",
            );
            assert!(s.report.residuals.slip_direction_violation < 1e-8);
            assert!(s.report.residuals.friction_bound_violation < 1e-9);
        }
    }
}

#[test]
fn tresca_block_free_tangentially_holds_below_capacity() {
    // kx = 0: only friction holds the block.
    for solver in [
        &mut exact() as &mut dyn ContactSolver,
        &mut active() as &mut dyn ContactSolver,
        &mut condensed() as &mut dyn ContactSolver,
    ] {
        let s = solve(solver, &block(0.0, 9.0, [1.0, 3.0], 2.0));
        assert_close(s.displacement[0], 0.0, 1e-8, "no slip");
        assert_close(s.tangential_force[0], 1.0, 1e-8, "lambda_T");
    }
    let eps = 1e5;
    let p = solve(&mut penalty(eps), &block(0.0, 9.0, [1.0, 3.0], 2.0));
    assert_close(p.displacement[0], 1.0 / eps, 1e-15, "penalty elastic slip");
    assert_close(p.tangential_force[0], 1.0, 1e-10, "penalty lambda_T");
}

#[test]
fn rigid_sliding_is_detected() {
    // kx = 0 and |fx| > b: no equilibrium.
    let (fx, b) = (3.0, 2.0);
    for fxs in [fx, -fx] {
        for solver in [
            &mut exact() as &mut dyn ContactSolver,
            &mut active() as &mut dyn ContactSolver,
            &mut condensed() as &mut dyn ContactSolver,
            &mut penalty(1e3) as &mut dyn ContactSolver,
        ] {
            match solver.solve(&block(0.0, 9.0, [fxs, 3.0], b)) {
                Err(ContactSolverError::RigidSliding {
                    load_along_mode,
                    friction_capacity,
                    report,
                }) => {
                    // Unit-slip mode d = sign(fx) e_0: f.d = |fx|, capacity = b. The figures
                    // come from the detected direction, which may mix in a little of the
                    // normal separation.
                    assert_close(load_along_mode, fx, 1e-2 * fx, "load along mode");
                    assert_close(friction_capacity, b, 1e-9, "capacity");
                    assert!(load_along_mode > friction_capacity);
                    assert_eq!(report.status, SolveStatus::Unbounded);
                }
                other => panic!("{}: expected rigid sliding, got {other:?}", solver.name()),
            }
        }
    }
}

#[test]
fn floating_body_is_unbounded() {
    // Frictionless block, free tangentially, pushed sideways.
    let frictionless = ContactSystem::try_new(
        matrix(2, &[(1, 1, 9.0)]),
        vec![1.0, 3.0],
        rows(1, 2, &[(0, 1, 1.0)]),
        vec![0.0],
        None,
    )
    .expect("valid system");
    // A free body pulled away from the wall.
    let pulled = spring(0.0, -1.0, 0.0);
    for system in [&frictionless, &pulled] {
        for solver in [
            &mut exact() as &mut dyn ContactSolver,
            &mut active() as &mut dyn ContactSolver,
            &mut condensed() as &mut dyn ContactSolver,
            &mut penalty(1e3) as &mut dyn ContactSolver,
        ] {
            match solver.solve(system) {
                Err(ContactSolverError::Unbounded {
                    load_along_mode, ..
                }) => assert_close(load_along_mode, 1.0, 1e-2, "load along mode"),
                other => panic!("{}: expected unbounded, got {other:?}", solver.name()),
            }
        }
    }
    // Pushed against the wall, the free body is held by the contact.
    let pushed = solve(&mut penalty(1e3), &spring(0.0, 1.0, 0.0));
    assert_close(pushed.normal_force[0], 1.0, 1e-10, "wall reaction");
}

/// Least-squares slope of log(y) against log(x).
fn fitted_slope(x: &[f64], y: &[f64]) -> f64 {
    let lx: Vec<f64> = x.iter().map(|v| v.ln()).collect();
    let ly: Vec<f64> = y.iter().map(|v| v.ln()).collect();
    let n = x.len() as f64;
    let (mx, my) = (lx.iter().sum::<f64>() / n, ly.iter().sum::<f64>() / n);
    let sxy: f64 = lx.iter().zip(&ly).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = lx.iter().map(|a| (a - mx) * (a - mx)).sum();
    sxy / sxx
}

#[test]
fn penalty_error_falls_like_one_over_penalty() {
    let chains = two_chains(10.0, 5.0, 0.4);
    let stick = block(4.0, 9.0, [1.5, 3.0], 2.0);
    for system in [&chains, &stick] {
        let reference = solve(&mut exact(), system);
        let factors = [1e2, 1e3, 1e4, 1e5];
        let errors: Vec<f64> = factors
            .iter()
            .map(|&factor| {
                let mut solver = PenaltySolver::new(
                    PenaltySettings::builder()
                        .penalty(PenaltyParameter::RelativeToStiffness(factor))
                        .build()
                        .expect("valid settings"),
                );
                let s = solve(&mut solver, system);
                s.displacement
                    .iter()
                    .zip(&reference.displacement)
                    .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
            })
            .collect();
        let slope = fitted_slope(&factors, &errors);
        assert!(
            (slope + 1.0).abs() < 0.02,
            "slope {slope}, errors {errors:?}"
        );
    }
}

/// A random symmetric banded matrix, strictly diagonally dominant (hence SPD): off-diagonal
/// entries in (-1, 0) within `band - 1` of the diagonal, each diagonal entry the sum of its
/// row's off-diagonal magnitudes plus a draw from `excess`.
fn banded_spd(
    rng: &mut ChaCha8Rng,
    n: usize,
    band: usize,
    excess: std::ops::Range<f64>,
) -> SparseColMat<usize, f64> {
    let mut entries = Vec::new();
    let mut diag = vec![0.0; n];
    for i in 0..n {
        for j in (i + 1)..(i + band).min(n) {
            let v: f64 = rng.gen_range(-1.0..0.0);
            entries.push((i, j, v));
            entries.push((j, i, v));
            diag[i] += v.abs();
            diag[j] += v.abs();
        }
    }
    for (i, d) in diag.iter().enumerate() {
        entries.push((i, i, d + rng.gen_range(excess.clone())));
    }
    matrix(n, &entries)
}

/// A deterministic random problem: SPD banded `K` (n = 60), 20 normal rows with 2-4 entries,
/// optional friction rows and bounds, loads that activate part of the constraints.
fn random_system(seed: u64, with_friction: bool) -> ContactSystem<'static> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let n = 60;
    let m = 20;
    let k = banded_spd(&mut rng, n, 4, 0.1..1.0);
    let random_rows = |rng: &mut ChaCha8Rng| {
        let mut t = Vec::new();
        for r in 0..m {
            let k = rng.gen_range(2..=4);
            for _ in 0..k {
                t.push((r, rng.gen_range(0..n), rng.gen_range(-1.0..1.0)));
            }
        }
        rows(m, n, &t)
    };
    let normal = random_rows(&mut rng);
    let gap: Vec<f64> = (0..m).map(|_| rng.gen_range(0.0..0.5)).collect();
    let load: Vec<f64> = (0..n).map(|_| rng.gen_range(-2.0..2.0)).collect();
    let friction = with_friction.then(|| {
        let tangential = random_rows(&mut rng);
        let bounds: Vec<f64> = (0..m).map(|_| rng.gen_range(0.0..0.5)).collect();
        Friction::try_new(tangential, bounds).expect("valid friction")
    });
    ContactSystem::try_new(k, load, normal, gap, friction).expect("valid system")
}

fn max_difference<'a>(a: impl IntoIterator<Item = (&'a f64, &'a f64)>) -> f64 {
    a.into_iter().fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
}

#[test]
fn exact_penalty_and_active_set_agree_on_a_random_system() {
    for with_friction in [false, true] {
        let system = random_system(7, with_friction);
        let e = solve(&mut exact(), &system);
        let n_active = e.normal_force.iter().filter(|&&l| l > 1e-6).count();
        assert!(
            (3..=17).contains(&n_active),
            "{n_active} active constraints"
        );
        assert!(e.report.residuals.max_violation() < 1e-8, "{:?}", e.report);
        assert!(e.report.residuals.stationarity < 1e-8, "{:?}", e.report);
        let mut p = PenaltySolver::new(
            PenaltySettings::builder()
                .penalty(PenaltyParameter::RelativeToStiffness(1e8))
                .build()
                .expect("valid settings"),
        );
        let s = solve(&mut p, &system);
        // eps = 1e8 x diag: the round-off floor of the gradient is about 1e-8.
        assert!(s.report.residuals.stationarity < 1e-7, "{:?}", s.report);
        let du = e
            .displacement
            .iter()
            .zip(&s.displacement)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        let dl = e
            .normal_force
            .iter()
            .zip(&s.normal_force)
            .chain(e.tangential_force.iter().zip(&s.tangential_force))
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        assert!(
            du < 1e-6 && dl < 1e-5,
            "friction {with_friction}: du {du}, dlambda {dl}"
        );
        // A second solve reuses the symbolic analysis, starts from the first answer and
        // gives it again (to the round-off floor of the stiff penalty's gradient).
        let again = solve(&mut p, &system);
        assert_eq!(again.report.work.symbolic_analyses, 0);
        assert!(again.report.iterations <= 2, "{:?}", again.report);
        let change = max_difference(again.displacement.iter().zip(&s.displacement));
        assert!(change < 1e-8, "warm-started answer moved by {change}");

        let a = solve(&mut active(), &system);
        assert!(a.report.residuals.max_violation() < 1e-10, "{:?}", a.report);
        assert!(a.report.residuals.stationarity < 1e-12, "{:?}", a.report);
        let du = max_difference(e.displacement.iter().zip(&a.displacement));
        let dl = max_difference(
            e.normal_force
                .iter()
                .zip(&a.normal_force)
                .chain(e.tangential_force.iter().zip(&a.tangential_force)),
        );
        assert!(
            du < 1e-7 && dl < 1e-7,
            "friction {with_friction}: du {du}, dlambda {dl}"
        );
    }
}

#[test]
fn forced_non_convergence_carries_the_report() {
    let system = random_system(3, true);
    let exact_1 = ExactSettings::builder()
        .max_iterations(1)
        .build()
        .expect("valid");
    let penalty_1 = PenaltySettings::builder()
        .max_iterations(1)
        .build()
        .expect("valid");
    let active_1 = ActiveSetSettings::builder()
        .max_iterations(1)
        .build()
        .expect("valid");
    for solver in [
        &mut ExactSolver::new(exact_1) as &mut dyn ContactSolver,
        &mut PenaltySolver::new(penalty_1) as &mut dyn ContactSolver,
        &mut ActiveSetSolver::new(active_1) as &mut dyn ContactSolver,
    ] {
        match solver.solve(&system) {
            Err(ContactSolverError::NotConverged { report }) => {
                assert_eq!(report.status, SolveStatus::MaxIterations);
                assert_eq!(report.iterations, 1);
                assert_eq!(report.solver, solver.name());
            }
            other => panic!("{}: expected NotConverged, got {other:?}", solver.name()),
        }
    }
}

#[test]
fn invalid_settings_are_rejected_when_built() {
    let e = ExactSettings::builder().eps_abs(-1.0).build().unwrap_err();
    assert_eq!(e.setting, "eps_abs");
    let e = ExactSettings::builder()
        .max_iterations(0)
        .build()
        .unwrap_err();
    assert_eq!(e.setting, "max_iterations");
    let e = PenaltySettings::builder()
        .normal_penalty(PenaltyParameter::Absolute(f64::NAN))
        .build()
        .unwrap_err();
    assert_eq!(e.setting, "normal_penalty");
    let e = PenaltySettings::builder()
        .tolerance(0.0)
        .build()
        .unwrap_err();
    assert_eq!(e.setting, "tolerance");
}

#[test]
fn invalid_systems_are_rejected() {
    assert!(matches!(
        ConstraintRows::try_from_triplets(1, 2, &[(0, 2, 1.0)]),
        Err(ContactSystemError::ColumnOutOfRange { col: 2, .. })
    ));
    assert!(matches!(
        ConstraintRows::try_from_triplets(1, 2, &[(0, 1, f64::INFINITY)]),
        Err(ContactSystemError::NonFinite { .. })
    ));
    let unsymmetric = matrix(2, &[(0, 0, 1.0), (0, 1, 0.5), (1, 1, 1.0)]);
    assert!(matches!(
        ContactSystem::try_new(
            unsymmetric,
            vec![0.0; 2],
            rows(1, 2, &[(0, 0, 1.0)]),
            vec![0.0],
            None
        ),
        Err(ContactSystemError::StiffnessNotSymmetric { .. })
    ));
    assert!(matches!(
        ContactSystem::try_new(
            matrix(1, &[(0, 0, 1.0)]),
            vec![0.0],
            rows(1, 1, &[(0, 0, 1.0)]),
            vec![0.0, 1.0],
            None
        ),
        Err(ContactSystemError::DimensionMismatch { .. })
    ));
    assert!(matches!(
        Friction::try_new(rows(1, 1, &[(0, 0, 1.0)]), vec![-1.0]),
        Err(ContactSystemError::NegativeFrictionBound { row: 0, .. })
    ));
    // Duplicate triplets are summed.
    let summed = rows(1, 3, &[(0, 2, 1.0), (0, 0, 2.0), (0, 2, 0.5)]);
    assert_eq!(summed.row(0), (&[0usize, 2][..], &[2.0, 1.5][..]));
}

#[test]
fn no_constraints_is_a_linear_solve() {
    // K = [[2, -1], [-1, 2]], f = (1, 0): u = (2/3, 1/3).
    let system = ContactSystem::try_new(
        matrix(2, &[(0, 0, 2.0), (0, 1, -1.0), (1, 0, -1.0), (1, 1, 2.0)]),
        vec![1.0, 0.0],
        rows(0, 2, &[]),
        vec![],
        None,
    )
    .expect("valid system");
    for solver in [
        &mut exact() as &mut dyn ContactSolver,
        &mut active() as &mut dyn ContactSolver,
        &mut condensed() as &mut dyn ContactSolver,
        &mut penalty(1e3) as &mut dyn ContactSolver,
    ] {
        let s = solve(solver, &system);
        assert_close(s.displacement[0], 2.0 / 3.0, 1e-9, "u0");
        assert_close(s.displacement[1], 1.0 / 3.0, 1e-9, "u1");
        assert!(s.normal_force.is_empty());
    }
}

/// A system built around a chosen KKT point: 8 node pairs (normal row `u_4i - u_4i+2`,
/// tangential row `u_4i+1 - u_4i+3`), each strongly active, weakly active (closed gap, zero
/// force) or open, and with friction sticking, slipping or weakly sticking (no slip, force at
/// the bound). The load is `f = K u* + B' lambda*`, so `(u*, lambda*)` is the unique answer.
fn manufactured_system(
    seed: u64,
    with_friction: bool,
) -> (ContactSystem<'static>, Vec<f64>, Vec<f64>, Vec<f64>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (n, m) = (40, 8);
    let k = banded_spd(&mut rng, n, 5, 0.01..1.0);
    let mut u: Vec<f64> = (0..n).map(|_| rng.gen_range(-1.0..1.0)).collect();
    let (mut ln, mut lt, mut gap, mut bounds) =
        (vec![0.0; m], vec![0.0; m], vec![0.0; m], vec![0.0; m]);
    let (mut normal, mut tangential) = (Vec::new(), Vec::new());
    for i in 0..m {
        normal.extend([(i, 4 * i, 1.0), (i, 4 * i + 2, -1.0)]);
        tangential.extend([(i, 4 * i + 1, 1.0), (i, 4 * i + 3, -1.0)]);
        let jump = u[4 * i] - u[4 * i + 2];
        match rng.gen_range(0..3) {
            0 => {
                ln[i] = rng.gen_range(0.5..2.0);
                gap[i] = jump;
            }
            1 => gap[i] = jump,
            _ => gap[i] = jump + rng.gen_range(0.1..1.0),
        }
        if with_friction {
            let b = rng.gen_range(0.1..1.0);
            bounds[i] = b;
            let slip = match rng.gen_range(0..3) {
                0 => {
                    lt[i] = rng.gen_range(-0.9..0.9) * b;
                    0.0
                }
                1 => {
                    let s: f64 =
                        rng.gen_range(0.1..1.0) * if rng.gen_bool(0.5) { 1.0 } else { -1.0 };
                    lt[i] = b * s.signum();
                    s
                }
                _ => {
                    lt[i] = if rng.gen_bool(0.5) { b } else { -b };
                    0.0
                }
            };
            u[4 * i + 3] = u[4 * i + 1] - slip;
        }
    }
    let normal = rows(m, n, &normal);
    let tangential = rows(m, n, &tangential);
    let mut load = vec![0.0; n];
    for (j, uj) in u.iter().enumerate() {
        for (&i, &v) in k.row_idx_of_col_raw(j).iter().zip(k.val_of_col(j)) {
            load[i] += v * uj;
        }
    }
    normal.add_transpose_apply(&ln, &mut load);
    let friction = with_friction.then(|| {
        tangential.add_transpose_apply(&lt, &mut load);
        Friction::try_new(tangential, bounds).expect("valid friction")
    });
    let system = ContactSystem::try_new(k, load, normal, gap, friction).expect("valid system");
    (system, u, ln, lt)
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]
    /// The condensed solver recovers manufactured KKT points with weakly active nodes (both
    /// sides of every switch) to round-off; the exact (interior-point) solver agrees to its
    /// accuracy, which degenerate (weakly active) nodes limit to about 1e-5 here.
    #[test]
    fn condensed_solver_recovers_manufactured_kkt_points(seed in 0u64..1_000_000, with_friction in proptest::bool::ANY) {
        let (system, u, ln, lt) = manufactured_system(seed, with_friction);
        let c = solve(&mut condensed(), &system);
        let e = solve(&mut exact(), &system);
        for (solution, tol) in [(&c, 1e-10), (&e, 1e-4)] {
            let du = max_difference(solution.displacement.iter().zip(&u));
            let dn = max_difference(solution.normal_force.iter().zip(&ln));
            let dt = if with_friction { max_difference(solution.tangential_force.iter().zip(&lt)) } else { 0.0 };
            proptest::prop_assert!(du < tol && dn < tol && dt < tol, "{}: du {du:e} dn {dn:e} dt {dt:e}", solution.report.solver);
        }
    }
}

/// A floating body (two unknowns joined by a spring, no support) pushed towards a wall far
/// away: it must travel 1e6 times its elastic stretch before the wall holds it. The condensed
/// solver's proximal steps move it by equal steps until it touches, which is not a free mode.
#[test]
fn a_floating_body_far_from_the_wall_travels_to_it() {
    let (k, f) = (4.0, 1.0);
    let gap = 1e6 * f / k;
    let system = ContactSystem::try_new(
        matrix(2, &[(0, 0, k), (0, 1, -k), (1, 0, -k), (1, 1, k)]),
        vec![0.0, f],
        rows(1, 2, &[(0, 0, 1.0)]),
        vec![gap],
        None,
    )
    .expect("valid system");
    let s = solve(&mut condensed(), &system);
    assert_eq!(s.report.solver, condensed().name(), "no hand-over");
    assert_close(s.normal_force[0], f, 1e-9 * f, "wall reaction");
    assert_close(s.displacement[0], gap, 1e-9 * gap, "at the wall");
    assert_close(
        s.displacement[1] - s.displacement[0],
        f / k,
        1e-6 * f / k,
        "stretch f / k",
    );
}
