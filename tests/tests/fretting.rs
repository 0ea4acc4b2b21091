//! Cattaneo-Mindlin loading, unloading and reloading (Johnson, Contact Mechanics, 7.5-7.6) as
//! load histories, in plane strain: two blocks of the same material, the upper one the mirror
//! image of a Gmsh block (non-matching: h_c = 0.01 above, 0.005 below), with the parabolic gap
//! `x^2 / (2R)` of a cylinder on a flat (R = 1), the upper block's top a rigid plate pushed with
//! P and sheared with Q (force control), Coulomb F = 0.3.
//!
//! Checked against the analytic solutions of `vem_verify::exact::HertzContact`: the stick zone
//! `c = a sqrt(1 - Q/(F P))` of the loading, the zone `c' = a sqrt(1 - (Q* - Q)/(2 F P))` that
//! sticks while unloading from Q* and reloading, each within one node spacing; the friction
//! traction within 8 % of `F p0` two node spacings away from the zone ends (measured 1-8 %,
//! the largest in the first loading steps); the loop closing at Q*; and the
//! path dependence: pressed and sheared together (proportionally), the interface sticks
//! everywhere with `q = (Q/P) p`, not Cattaneo-Mindlin's tractions, while frictionless contact
//! reaches the same answer by every path.

use vem_contact::{
    CondensedSolver, ContactProblem, ContactResult, LoadCurve, LoadCurves, LoadFactors,
    LoadHistory, NodeStatus,
};
use vem_mesh::io::read_gmsh;
use vem_space::Choice;
use vem_verify::exact::HertzContact;
use vem_verify::fretting::{
    friction_traction as traction, largest_spacing_within as spacing_in, mesh_file,
    plate_translation, zone_half_width as zone, Drive, FlatBlocks,
};

const F: f64 = 0.3;
const P: f64 = 0.5;
/// The peak tangential load of the cycle, `Q* = 0.8 F P`.
const PEAK: f64 = 0.8;
const SETUP: FlatBlocks = FlatBlocks {
    young: 100.0,
    poisson: 0.3,
    radius: 1.0,
    coefficient: F,
    push: P,
};
const FIRST: vem_contact::LoadCondition = FlatBlocks::PRESS;
const SECOND: vem_contact::LoadCondition = FlatBlocks::SHEAR;

fn path(file: &str) -> String {
    format!("{}/../{file}", env!("CARGO_MANIFEST_DIR"))
}

/// The upper block `[-2, 2] x [0, 2]` (the mirror image of the h_c = 0.01 block) on the lower
/// block `[-2, 2] x [-2, 0]` (h_c = 0.005, its mesh file) clamped at its bottom, with the gap
/// of a cylinder: the contact problem of the scene `FlatBlocks::scene`, the law by name.
fn blocks(drive: Drive, law: Choice) -> ContactProblem {
    let upper = read_gmsh(path("crates/vem-cli/scenes/hertz_block.msh")).unwrap();
    let lower = mesh_file(path("xtask/data/hertz/block_hc0.005.msh"));
    SETUP.problem(&upper, lower, drive, law).unwrap()
}

fn hertz() -> HertzContact {
    SETUP.hertz().unwrap()
}

/// The largest `|q - exact| / (F p0)` over the nodes inside the zones: two spacings away from
/// the contact edge and from every zone end in `ends`.
fn traction_error(result: &ContactResult, exact: impl Fn(f64) -> f64, ends: &[f64]) -> f64 {
    vem_verify::fretting::traction_error(result, &hertz(), F, exact, ends)
}

/// The plate's translation in x.
fn plate_x(result: &ContactResult) -> f64 {
    plate_translation(result).unwrap()
}

#[test]
fn loading_unloading_and_reloading_follow_cattaneo_mindlin_and_the_loop_closes() {
    let d = blocks(Drive::Force, SETUP.coulomb())
        .into_discretisation()
        .unwrap();
    // Pushed during t in [0, 1]; sheared to Q* at t = 2, back to -Q* at t = 4, to Q* at 6.
    let curves = LoadCurves::default()
        .with(
            FIRST,
            LoadCurve::try_new(vec![(0.0, 0.0), (1.0, 1.0)]).unwrap(),
        )
        .with(
            SECOND,
            LoadCurve::try_new(vec![(1.0, 0.0), (2.0, PEAK), (4.0, -PEAK), (6.0, PEAK)]).unwrap(),
        );
    let mut times: Vec<f64> = vec![0.5, 1.0];
    times.extend((1..=20).map(|k| 1.0 + 0.25 * k as f64));
    let history = LoadHistory::from_curves(times, &curves).unwrap();
    let steps = d
        .solve_history(&mut CondensedSolver::default(), &history)
        .unwrap();
    let hertz = hertz();
    let mut worst_zone = 0.0f64;
    let mut worst_traction = 0.0f64;
    for step in steps.iter().filter(|s| s.time > 1.0) {
        let (t, r) = (step.time, step.factors.factor(SECOND));
        let result = &step.result;
        // The plate's force is carried exactly.
        let force = result.force_on_body_a();
        assert!((force.y - P).abs() < 1e-9 * P, "t = {t}: {force}");
        assert!((force.x + r * F * P).abs() < 1e-9 * P, "t = {t}: {force}");
        // The zone that sticks, its analytic half-width and the analytic traction.
        // Measured in the node spacing of the contact zone (a zone end between two nearly
        // coincident nodes of the two sides has a tiny local spacing).
        let c = zone(&result.nodes, |n| n.status == NodeStatus::Stick).0;
        let spacing = spacing_in(&result.nodes, hertz.half_width());
        let c_peak = hertz.stick_half_width(PEAK);
        let (expected, error) = if t <= 2.0 + 1e-9 {
            let c_exact = hertz.stick_half_width(r);
            let e = traction_error(result, |x| hertz.tangential_traction(x, F, r), &[c_exact]);
            (c_exact, e)
        } else if t <= 4.0 + 1e-9 {
            let c_exact = hertz.counter_slip_half_width(PEAK, r);
            let exact = |x| hertz.unloading_traction(x, F, PEAK, r);
            (c_exact, traction_error(result, exact, &[c_exact, c_peak]))
        } else {
            let c_exact = hertz.counter_slip_half_width(PEAK, -r);
            let exact = |x| hertz.reloading_traction(x, F, PEAK, r);
            (c_exact, traction_error(result, exact, &[c_exact, c_peak]))
        };
        eprintln!(
            "t = {t:.2}: Q/(F P) = {r:+.2}, stick half-width {c:.4} (analytic {expected:.4}, \
             spacing {spacing:.4}), traction error {error:.3} F p0"
        );
        assert!(
            (c - expected).abs() <= spacing,
            "t = {t}: stick half-width {c} against {expected} (spacing {spacing})"
        );
        assert!(error < 0.08, "t = {t}: traction error {error} F p0");
        worst_zone = worst_zone.max((c - expected).abs() / spacing);
        worst_traction = worst_traction.max(error);
    }
    eprintln!(
        "largest zone-end error {worst_zone:.2} spacings, traction error {worst_traction:.3} F p0"
    );
    // The loop closes: back at Q* after the cycle, the plate is where it was after the first
    // loading, and the tractions are those of the first loading.
    let first = steps.iter().find(|s| (s.time - 2.0).abs() < 1e-9).unwrap();
    let last = steps.last().unwrap();
    let (x1, x2) = (plate_x(&first.result), plate_x(&last.result));
    assert!((x1 - x2).abs() < 1e-3 * x1.abs(), "{x1} vs {x2}");
    let p0 = hertz.peak_pressure();
    let rms = (first
        .result
        .nodes
        .iter()
        .zip(&last.result.nodes)
        .map(|(a, b)| ((traction(a) - traction(b)) / (F * p0)).powi(2))
        .sum::<f64>()
        / first.result.nodes.len() as f64)
        .sqrt();
    assert!(
        rms < 0.02,
        "tractions after the cycle differ by {rms} F p0 (rms)"
    );
    // Masing: the unloading branch is the mirror image of the reloading one.
    for (down, up) in steps
        .iter()
        .filter(|s| s.time > 2.0 + 1e-9 && s.time <= 4.0 + 1e-9)
        .zip(steps.iter().filter(|s| s.time > 4.0 + 1e-9))
    {
        let (a, b) = (plate_x(&down.result), plate_x(&up.result));
        assert!(
            (a + b).abs() < 5e-3 * x1.abs(),
            "t = {}: {a} vs {b}",
            down.time
        );
    }
}

#[test]
fn pressed_and_sheared_together_the_interface_sticks_with_q_proportional_to_p() {
    let d = blocks(Drive::Force, SETUP.coulomb())
        .into_discretisation()
        .unwrap();
    let ratio = 0.5;
    let final_loads = LoadFactors::uniform(1.0).with(SECOND, ratio);
    // Proportional: P and Q grow together (Mindlin and Deresiewicz: no slip for Q/P < F).
    // The steps of the proportional path: the zone grows by steps, each step's increment of Q
    // acts on the zone of that step, so q approaches (Q/P) p at first order in the step
    // (rms deviation inside 0.9 a measured 0.047, 0.024, 0.011, 0.0054 F p0 for 8 to 64 steps).
    let n = 32;
    let together = LoadHistory::from_steps(
        (1..=n)
            .map(|k| {
                let s = k as f64 / n as f64;
                LoadFactors::uniform(1.0)
                    .with(FIRST, s)
                    .with(SECOND, ratio * s)
            })
            .collect(),
    );
    // Cattaneo-Mindlin: pushed, then sheared.
    let mut one_after_the_other: Vec<LoadFactors> = (1..=4)
        .map(|k| {
            LoadFactors::uniform(1.0)
                .with(FIRST, k as f64 / 4.0)
                .with(SECOND, 0.0)
        })
        .collect();
    one_after_the_other
        .extend((1..=4).map(|k| LoadFactors::uniform(1.0).with(SECOND, ratio * k as f64 / 4.0)));
    let one_after_the_other = LoadHistory::from_steps(one_after_the_other);
    let last = &together.steps().last().unwrap().factors;
    for condition in [FIRST, SECOND] {
        assert_eq!(last.factor(condition), final_loads.factor(condition));
    }
    let proportional = d
        .solve_history(&mut CondensedSolver::default(), &together)
        .unwrap()
        .pop()
        .unwrap()
        .result;
    let sequential = d
        .solve_history(&mut CondensedSolver::default(), &one_after_the_other)
        .unwrap()
        .pop()
        .unwrap()
        .result;
    let hertz = hertz();
    let (a, p0) = (hertz.half_width(), hertz.peak_pressure());
    // The same loads ...
    let (f1, f2) = (proportional.force_on_body_a(), sequential.force_on_body_a());
    assert!((f1 - f2).norm() < 1e-9 * P, "{f1} vs {f2}");
    // ... proportional: no node slipped but within two spacings of the zone's edge (where p
    // vanishes and the last increments of contact are a node wide), q = (Q/P) p inside ...
    let contact = zone(&proportional.nodes, |n| n.status != NodeStatus::Open).0;
    let h = spacing_in(&proportional.nodes, a);
    for n in proportional
        .nodes
        .iter()
        .filter(|n| n.status == NodeStatus::Slip)
    {
        assert!(
            n.position.x.abs() > contact - 2.0 * h,
            "node at {} slips",
            n.position
        );
    }
    let rms = vem_verify::fretting::traction_rms(&proportional, &hertz, F, |x| {
        F * ratio * hertz.pressure(x)
    });
    assert!(rms < 0.02, "q against (Q/P) p: rms {rms} F p0");
    let error = traction_error(&proportional, |x| F * ratio * hertz.pressure(x), &[]);
    assert!(error < 0.06, "q against (Q/P) p: {error} F p0");
    // ... one after the other: Cattaneo-Mindlin, a different traction.
    let c = hertz.stick_half_width(ratio);
    let error = traction_error(
        &sequential,
        |x| hertz.tangential_traction(x, F, ratio),
        &[c],
    );
    assert!(error < 0.06, "q against Cattaneo-Mindlin: {error} F p0");
    let difference = proportional
        .nodes
        .iter()
        .zip(&sequential.nodes)
        .filter(|(n, _)| n.position.x.abs() < 0.9 * a)
        .map(|(x, y)| (traction(x) - traction(y)).abs() / (F * p0))
        .fold(0.0, f64::max);
    assert!(
        difference > 0.2,
        "the paths give the same tractions: {difference}"
    );
}

#[test]
fn without_friction_every_path_reaches_the_same_answer() {
    let (dx, dy) = (0.004, 0.012);
    let d = blocks(Drive::Displacement(dx, dy), Choice::named("frictionless"))
        .into_discretisation()
        .unwrap();
    let path = |factors: &[(f64, f64)]| {
        let steps: Vec<LoadFactors> = factors
            .iter()
            .map(|&(press, shift)| {
                LoadFactors::uniform(1.0)
                    .with(FIRST, press)
                    .with(SECOND, shift)
            })
            .collect();
        d.solve_history(
            &mut CondensedSolver::default(),
            &LoadHistory::from_steps(steps),
        )
        .unwrap()
        .pop()
        .unwrap()
        .result
    };
    let answers = [
        path(&[(0.5, 0.5), (1.0, 1.0)]),
        path(&[(1.0, 0.0), (1.0, 1.0)]),
        path(&[(1.0, 0.0), (1.0, 2.0), (1.0, -1.0), (1.0, 1.0)]),
    ];
    let statically = d.solve(&mut CondensedSolver::default()).unwrap();
    let scale = statically
        .nodes
        .iter()
        .fold(0.0f64, |m, n| m.max(n.normal_force));
    for answer in &answers {
        for (a, b) in answer.nodes.iter().zip(&statically.nodes) {
            assert!((a.normal_force - b.normal_force).abs() < 1e-10 * scale);
            assert_eq!(a.friction_t(), 0.0);
        }
    }
    // With Coulomb friction the same three paths end in three different states.
    let d = blocks(Drive::Displacement(dx, dy), SETUP.coulomb())
        .into_discretisation()
        .unwrap();
    let path = |factors: &[(f64, f64)]| {
        let steps: Vec<LoadFactors> = factors
            .iter()
            .map(|&(press, shift)| {
                LoadFactors::uniform(1.0)
                    .with(FIRST, press)
                    .with(SECOND, shift)
            })
            .collect();
        d.solve_history(
            &mut CondensedSolver::default(),
            &LoadHistory::from_steps(steps),
        )
        .unwrap()
        .pop()
        .unwrap()
        .result
    };
    let answers = [
        path(&[(0.5, 0.5), (1.0, 1.0)]),
        path(&[(1.0, 0.0), (1.0, 1.0)]),
        path(&[(1.0, 0.0), (1.0, 2.0), (1.0, -1.0), (1.0, 1.0)]),
    ];
    for (i, j) in [(0, 1), (1, 2), (0, 2)] {
        let difference = answers[i]
            .nodes
            .iter()
            .zip(&answers[j].nodes)
            .fold(0.0f64, |m, (a, b)| {
                m.max((a.friction_t() - b.friction_t()).abs())
            });
        let largest = answers[i]
            .nodes
            .iter()
            .fold(0.0f64, |m, n| m.max(n.friction_t().abs()));
        assert!(
            difference > 0.05 * largest,
            "paths {i} and {j}: {difference} of {largest}"
        );
    }
}
