//! "Converged" means the answer is right: the rows of issue 11 on small two-block problems.
//! Every solver returns either the right answer (checked against an independent expectation:
//! equilibrium, another solver, the unscaled problem) or a clear error; never `Converged`
//! with a wrong answer.

use std::sync::Arc;

use vem_contact::{
    ActiveSetSolver, CondensedSolver, ContactError, ContactLaw, ContactProblem, ContactResult,
    ContactSolver, ContactSolverError, Coulomb, ExactSolver, Frictionless, NodeStatus,
    PenaltyParameter, PenaltySettings, PenaltySolver, SolveStatus, Tresca, Warning,
};
use vem_elastic::{Component, Dirichlet, ElasticBody, Material, Plane};
use vem_mesh::generators::{structured_quads, Rectangle};
use vem_mesh::{Point, Vector};
use vem_space::LowestOrderVem;

/// How the upper block is loaded.
#[derive(Debug, Clone, Copy)]
enum Loading {
    /// Top pushed down by `0.02 - 0.04 x` (lifted at the right): a partial contact zone.
    Tilted,
    /// Top moved by `(0.01, -0.02)`, lower block clamped: Tresca shear, stick and slip.
    Shear,
    /// Uniform pressure `p = 0.01 modulus` on the top; the upper block is held by the contact
    /// in `y` (roller on its left side).
    Pressure(f64),
}

/// Upper block `[0, 1] x [0, 1]` (4 x 4 quads, Lame `(2, 1) modulus`) on a lower block
/// `[0, 1] x [-1, 0]` (5 x 5 quads, `contrast` times stiffer), lengths times `length`.
fn blocks(
    length: f64,
    modulus: f64,
    contrast: f64,
    loading: Loading,
    law: impl ContactLaw + 'static,
) -> ContactProblem {
    let element = Arc::new(LowestOrderVem::default());
    let l = length;
    let upper_mesh = structured_quads(
        &Rectangle::new(Point::new(0.0, 0.0), Point::new(l, l)),
        4,
        4,
    )
    .expect("mesh");
    let lower_mesh = structured_quads(
        &Rectangle::new(Point::new(0.0, -l), Point::new(l, 0.0)),
        5,
        5,
    )
    .expect("mesh");
    let soft = Material::from_lame(2.0 * modulus, modulus, Plane::Strain).expect("material");
    let stiff = Material::from_lame(2.0 * modulus * contrast, modulus * contrast, Plane::Strain)
        .expect("material");
    let upper = ElasticBody::builder("upper", upper_mesh, soft, element.clone());
    let lower = ElasticBody::builder("lower", lower_mesh, stiff, element);
    let (upper, lower) = match loading {
        Loading::Tilted => (
            upper
                .dirichlet(Dirichlet::prescribed("top", Component::Y, move |x| {
                    Vector::new(0.0, l * (-0.02 + 0.04 * x.x / l))
                }))
                .dirichlet(Dirichlet::fixed("left", Component::X)),
            lower
                .dirichlet(Dirichlet::fixed("bottom", Component::Y))
                .dirichlet(Dirichlet::fixed("left", Component::X)),
        ),
        Loading::Shear => (
            upper.dirichlet(Dirichlet::prescribed("top", Component::All, move |_| {
                Vector::new(0.01 * l, -0.02 * l)
            })),
            lower.clamp("bottom"),
        ),
        Loading::Pressure(p) => (
            upper
                .traction("top", move |_| Vector::new(0.0, -p))
                .dirichlet(Dirichlet::fixed("left", Component::X)),
            lower
                .dirichlet(Dirichlet::fixed("bottom", Component::Y))
                .dirichlet(Dirichlet::fixed("left", Component::X)),
        ),
    };
    ContactProblem::two_bodies(
        upper.build().expect("body"),
        "bottom",
        lower.build().expect("body"),
        "top",
        law,
    )
}

fn penalty(factor: f64) -> PenaltySolver {
    PenaltySolver::new(
        PenaltySettings::builder()
            .penalty(PenaltyParameter::RelativeToStiffness(factor))
            .build()
            .expect("settings"),
    )
}

fn solvers() -> Vec<Box<dyn ContactSolver>> {
    vec![
        Box::new(ExactSolver::default()),
        Box::new(penalty(1e3)),
        Box::new(ActiveSetSolver::default()),
        Box::new(CondensedSolver::default()),
    ]
}

/// The index of the default (condensed) solver in [`solvers`].
const CONDENSED: usize = 3;

/// `max |a - b| / max |b|`.
fn relative_difference(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
        / scale
}

/// `max |a - b| / 0.02`: unit-free displacements against the prescribed displacement.
fn displacement_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
        / 0.02
}

/// Nodal normal jumps divided by `length`, normal and friction forces divided by
/// `modulus length` (unit free).
fn unit_free(result: &ContactResult, length: f64, modulus: f64) -> (Vec<f64>, Vec<f64>) {
    let jumps = result
        .nodes
        .iter()
        .flat_map(|n| [n.normal_jump / length, n.slip_t() / length])
        .collect();
    let forces = result
        .nodes
        .iter()
        .flat_map(|n| [n.normal_force, n.friction_t()])
        .map(|f| f / (modulus * length))
        .collect();
    (jumps, forces)
}

/// A solve that converged, or a clear error (not converged, with a report) from a solver
/// allowed to fail on this problem.
fn solved_or_refused(
    problem: &ContactProblem,
    solver: &mut dyn ContactSolver,
    may_fail: bool,
) -> Option<ContactResult> {
    match problem.solve(solver) {
        Ok(result) => {
            assert!(matches!(
                result.report.status,
                SolveStatus::Converged | SolveStatus::ReducedAccuracy
            ));
            Some(result)
        }
        Err(ContactError::Solver(ContactSolverError::NotConverged { report })) if may_fail => {
            assert_ne!(report.status, SolveStatus::Converged);
            None
        }
        Err(e) => panic!("{}: unexpected failure: {e} {:?}", solver.name(), e),
    }
}

/// Frictionless without a bound, Tresca with the bound `g`.
fn shared_law(bound: Option<f64>) -> std::sync::Arc<dyn ContactLaw> {
    match bound {
        None => std::sync::Arc::new(Frictionless),
        Some(g) => std::sync::Arc::new(Tresca::try_new(g).expect("law")),
    }
}

#[test]
fn answers_do_not_depend_on_the_units() {
    let laws = [(Loading::Tilted, None), (Loading::Shear, Some(0.0015))];
    let scalings = [
        (1e-6, 1.0),
        (1e6, 1.0),
        (1.0, 1e-6),
        (1.0, 1e6),
        (1.0, 1e-9),
        (1.0, 1e9),
    ];
    for (loading, law) in &laws {
        for (k, reference_solver) in solvers().iter_mut().enumerate() {
            let tolerance = if k == 0 { 1e-8 } else { 1e-10 };
            let reference = blocks(1.0, 1.0, 1.0, *loading, shared_law(*law))
                .solve(reference_solver.as_mut())
                .expect("reference solve");
            let (u0, f0) = unit_free(&reference, 1.0, 1.0);
            for &(length, modulus) in &scalings {
                // Tresca: the bound is a stress, it scales with the modulus.
                let law = shared_law(law.map(|g| g * modulus));
                let mut solver = solvers().remove(k);
                let result = blocks(length, modulus, 1.0, *loading, law)
                    .solve(solver.as_mut())
                    .unwrap_or_else(|e| panic!("{}: {e}", solver.name()));
                let (u, f) = unit_free(&result, length, modulus);
                let (du, df) = (
                    displacement_difference(&u, &u0),
                    relative_difference(&f, &f0),
                );
                assert!(
                    du <= tolerance && df <= tolerance,
                    "{} {loading:?} at lengths x {length:e}, moduli x {modulus:e}: \
                     displacements {du:.1e}, forces {df:.1e} off the unscaled answer",
                    solver.name()
                );
                assert_eq!(result.status_counts(), reference.status_counts());
            }
        }
    }
}

#[test]
fn a_stiffness_contrast_keeps_the_contact_pressure_and_the_statuses() {
    // Uniform stress sigma_yy = -p in both blocks: every nodal force is p times its tributary
    // length, whatever the materials (equilibrium of the upper block gives sum = p).
    let p = 0.01;
    for contrast in [1e8, 1e-8] {
        let problem = blocks(1.0, 1.0, contrast, Loading::Pressure(p), Frictionless);
        for (k, mut solver) in solvers().into_iter().enumerate() {
            let Some(result) = solved_or_refused(&problem, solver.as_mut(), k == 0) else {
                continue;
            };
            let total = result.normal_resultant();
            assert!(
                (total - p).abs() <= 1e-6 * p,
                "{} at contrast {contrast:e}: sum lambda_N = {total} for p = {p}",
                solver.name()
            );
            // The penalty carries its consistency error O(1 / penalty).
            let tolerance = if k == 1 { 1e-4 } else { 1e-6 };
            for node in &result.nodes {
                assert!(
                    (node.pressure - p).abs() <= tolerance * p,
                    "{} at contrast {contrast:e}: pressure {} at {:?}",
                    solver.name(),
                    node.pressure,
                    node.position
                );
                assert_ne!(node.status, NodeStatus::Open, "{}", solver.name());
            }
        }
    }
}

#[test]
fn a_stiffness_contrast_keeps_tresca_stick_and_slip() {
    for contrast in [1e8f64, 1e-8] {
        // The bound is relative to the softer block's stresses.
        let g = 0.0095 * contrast.min(1.0);
        let problem = blocks(
            1.0,
            1.0,
            contrast,
            Loading::Shear,
            Tresca::try_new(g).expect("law"),
        );
        // Every solver may refuse (the active set may cycle, the interior point may not
        // reach the soft body's accuracy), but those that answer agree.
        let answers: Vec<(usize, ContactResult)> = solvers()
            .into_iter()
            .enumerate()
            .filter_map(|(k, mut solver)| {
                solved_or_refused(&problem, solver.as_mut(), true).map(|r| (k, r))
            })
            .collect();
        // The default solver must answer.
        assert!(
            answers.iter().any(|(k, _)| *k == CONDENSED),
            "the condensed solver refused contrast {contrast:e}"
        );
        for (k, result) in &answers {
            let counts = result.status_counts();
            assert!(
                counts.stick > 0 && counts.slip > 0 && counts.open == 0,
                "{k}: {counts:?}"
            );
            for (l, other) in &answers {
                let (_, f) = unit_free(result, 1.0, 1.0);
                let (_, f0) = unit_free(other, 1.0, 1.0);
                // The penalty carries its consistency error.
                let tolerance = if *k == 1 || *l == 1 { 1e-2 } else { 1e-6 };
                let df = relative_difference(&f, &f0);
                assert!(
                    df <= tolerance,
                    "solvers {k} and {l} at contrast {contrast:e}: forces {df:.1e} apart"
                );
                if *k != 1 && *l != 1 {
                    assert_eq!(result.status_counts(), other.status_counts());
                }
            }
        }
    }
}

#[test]
fn a_zero_load_gives_exactly_zero_forces() {
    for (loading, law) in [
        (Loading::Pressure(0.0), None),
        (Loading::Shear, Some(0.0015)),
    ] {
        let discretisation = blocks(1.0, 1.0, 1.0, loading, shared_law(law))
            .discretise()
            .expect("discretisation");
        for mut solver in solvers() {
            let result = discretisation
                .solve_scaled(solver.as_mut(), 0.0)
                .expect("solve");
            for node in &result.nodes {
                assert_eq!(node.normal_force, 0.0, "{}", solver.name());
                assert_eq!(node.friction_t(), 0.0, "{}", solver.name());
                assert_eq!(node.status, NodeStatus::Open);
            }
        }
    }
}

#[test]
fn a_penalty_in_its_round_off_regime_is_refused_or_right() {
    let problem = blocks(1.0, 1.0, 1.0, Loading::Tilted, Frictionless);
    let reference = problem
        .solve(&mut ActiveSetSolver::default())
        .expect("active set");
    let (_, f0) = unit_free(&reference, 1.0, 1.0);
    for factor in [1e13, 1e14] {
        match problem.solve(&mut penalty(factor)) {
            Ok(result) => {
                let (_, f) = unit_free(&result, 1.0, 1.0);
                let df = relative_difference(&f, &f0);
                assert!(df <= 1e-5, "penalty x {factor:e}: forces {df:.1e} off");
                assert!(result
                    .warnings
                    .iter()
                    .any(|w| matches!(w, Warning::PenaltyRoundOff { .. })));
            }
            Err(ContactError::Solver(ContactSolverError::NotConverged { report })) => {
                assert_eq!(report.status, SolveStatus::FailedCheck);
            }
            Err(e) => panic!("penalty x {factor:e}: {e}"),
        }
    }
}

#[test]
fn a_huge_friction_bound_ties_the_contact() {
    // g_F far above every stress: the answer is the tied (bonded) one, which a bound of
    // 1e6 x the stresses already gives: every node sticks.
    let tied = blocks(
        1.0,
        1.0,
        1.0,
        Loading::Shear,
        Tresca::try_new(1e4).expect("law"),
    )
    .solve(&mut ActiveSetSolver::default())
    .expect("active set");
    let (u0, f0) = unit_free(&tied, 1.0, 1.0);
    assert_eq!(tied.status_counts().slip, 0, "no node slips");
    for g in [1e12, 1e100] {
        let problem = blocks(
            1.0,
            1.0,
            1.0,
            Loading::Shear,
            Tresca::try_new(g).expect("law"),
        );
        for (k, mut solver) in solvers().into_iter().enumerate() {
            let Some(result) = solved_or_refused(&problem, solver.as_mut(), k == 0) else {
                continue;
            };
            let (u, f) = unit_free(&result, 1.0, 1.0);
            let tolerance = if k == 1 { 1e-2 } else { 1e-7 };
            assert!(
                relative_difference(&f, &f0) <= tolerance
                    && displacement_difference(&u, &u0) <= tolerance,
                "{} at g_F = {g:e}",
                solver.name()
            );
            assert_eq!(result.status_counts().slip, 0, "{}", solver.name());
            assert!(result.report.residuals.slip_direction_violation <= 1e-6);
            assert!(
                result
                    .warnings
                    .iter()
                    .any(|w| matches!(w, Warning::EffectivelyTied { .. })),
                "{}: {:?}",
                solver.name(),
                result.warnings
            );
        }
    }
}

/// A structured quad grid over the lines `xs`, `ys`, vertices moved by `map`, with parts
/// "bottom", "top", "left", "right".
fn grid(xs: &[f64], ys: &[f64], map: impl Fn(f64, f64) -> Point) -> vem_mesh::Mesh {
    let (nx, ny) = (xs.len(), ys.len());
    let id = |i: usize, j: usize| nx * j + i;
    let vertices = ys
        .iter()
        .flat_map(|&y| xs.iter().map(move |&x| (x, y)))
        .map(|(x, y)| map(x, y))
        .collect();
    let mut polygons = Vec::new();
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            polygons.push(vec![id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    let part = |name: &str, edges: Vec<[usize; 2]>| vem_mesh::PartSpec::new(name, edges);
    let parts = vec![
        part(
            "bottom",
            (0..nx - 1).map(|i| [id(i, 0), id(i + 1, 0)]).collect(),
        ),
        part(
            "top",
            (0..nx - 1)
                .map(|i| [id(i, ny - 1), id(i + 1, ny - 1)])
                .collect(),
        ),
        part(
            "left",
            (0..ny - 1).map(|j| [id(0, j), id(0, j + 1)]).collect(),
        ),
        part(
            "right",
            (0..ny - 1)
                .map(|j| [id(nx - 1, j), id(nx - 1, j + 1)])
                .collect(),
        ),
    ];
    vem_mesh::Mesh::from_polygons(vertices, &polygons, parts).expect("grid mesh")
}

fn lines(n: usize, from: f64, to: f64) -> Vec<f64> {
    (0..=n)
        .map(|i| from + (to - from) * i as f64 / n as f64)
        .collect()
}

/// An upper block whose bottom rises as `0.1 x` (a wedge opening to the right), pushed down
/// by 0.03 on its top, on a clamped lower block; the contact zone ends inside the interface.
fn wedge(
    options: Option<vem_mesh::interface::InterfaceOptions>,
    upper_ys: &[f64],
) -> ContactProblem {
    let element = Arc::new(LowestOrderVem::default());
    let material = Material::from_lame(2.0, 1.0, Plane::Strain).expect("material");
    let upper_mesh = grid(&lines(10, 0.0, 1.0), upper_ys, |x, y| {
        Point::new(x, y + 0.1 * x * (1.0 - y))
    });
    let lower_mesh = grid(&lines(13, 0.0, 1.0), &lines(4, -1.0, 0.0), Point::new);
    let upper = ElasticBody::builder("upper", upper_mesh, material, element.clone())
        .dirichlet(Dirichlet::prescribed("top", Component::All, |_| {
            Vector::new(0.0, -0.03)
        }))
        .build()
        .expect("body");
    let lower = ElasticBody::builder("lower", lower_mesh, material, element)
        .clamp("bottom")
        .build()
        .expect("body");
    let problem = ContactProblem::two_bodies(upper, "bottom", lower, "top", Frictionless);
    match options {
        Some(options) => problem.with_interface_options(options),
        None => problem,
    }
}

#[test]
fn a_contact_zone_clipped_by_the_pairing_limit_is_a_warning() {
    let clipped = |result: &ContactResult| {
        result.warnings.iter().any(|w| {
            matches!(
                w,
                Warning::ContactZoneAtLimit {
                    limit: vem_contact::ZoneLimit::PairingLimit,
                    ..
                }
            )
        })
    };
    let full = wedge(None, &lines(5, 0.0, 1.0))
        .solve(&mut ActiveSetSolver::default())
        .expect("solve");
    assert!(
        full.status_counts().open > 0,
        "the zone ends inside the interface"
    );
    assert!(!clipped(&full), "{:?}", full.warnings);
    // Pair only nodes closer than 0.015: the zone (gaps up to ~0.03) is cut at x ~ 0.15.
    let options = vem_mesh::interface::InterfaceOptions::builder()
        .max_distance(0.015)
        .build()
        .expect("options");
    let cut = wedge(Some(options), &lines(5, 0.0, 1.0))
        .solve(&mut ActiveSetSolver::default())
        .expect("solve");
    assert!(cut.nodes.len() < full.nodes.len());
    assert!(clipped(&cut), "{:?}", cut.warnings);
}

#[test]
fn elements_far_outside_a1_are_named_in_a_warning() {
    // A row of cells of height 1e-5 under the top of the upper block: gamma ~ 1e-4.
    let mut ys = lines(5, 0.0, 1.0);
    ys.insert(5, 1.0 - 1e-5);
    let result = wedge(None, &ys)
        .solve(&mut ActiveSetSolver::default())
        .expect("solve");
    let named: Vec<&Warning> = result
        .warnings
        .iter()
        .filter(|w| matches!(w, Warning::ElementShape { body, gamma, .. } if body == "upper" && *gamma < 1e-4))
        .collect();
    assert!(!named.is_empty(), "{:?}", result.warnings);
    assert!(named[0].to_string().contains("body 'upper', element"));
    let plain = wedge(None, &lines(5, 0.0, 1.0))
        .solve(&mut ActiveSetSolver::default())
        .expect("solve");
    assert!(!plain
        .warnings
        .iter()
        .any(|w| matches!(w, Warning::ElementShape { .. })));
}

#[test]
fn a_coulomb_fixed_point_stopped_at_the_force_floor_says_so() {
    // Asked for 1e-14, the fixed point over the interior point (force accuracy 1e-4) stops at
    // 1e-4; over the active set (exact forces) it meets the request.
    let settings = vem_contact::FixedPointSettings::builder()
        .tolerance(1e-14)
        .build()
        .expect("settings");
    let problem = blocks(
        1.0,
        1.0,
        1.0,
        Loading::Shear,
        Coulomb::try_with(0.3, settings).expect("law"),
    );
    let floored = |result: &ContactResult| {
        result
            .warnings
            .iter()
            .any(|w| matches!(w, Warning::FixedPointAtForceFloor { .. }))
    };
    let exact = problem.solve(&mut ExactSolver::default()).expect("exact");
    let fixed_point = exact.fixed_point.as_ref().expect("Coulomb");
    assert_eq!(fixed_point.tolerance, 10.0 * 1e-10f64.sqrt());
    assert!(fixed_point.residual > 1e-14, "{fixed_point:?}");
    assert!(floored(&exact), "{:?}", exact.warnings);
    match problem.solve(&mut ActiveSetSolver::default()) {
        Ok(active) => assert!(!floored(&active)),
        Err(ContactError::FixedPointNotConverged { .. }) => {}
        Err(e) => panic!("active set: {e}"),
    }
}
