//! M2-3D, Tresca friction between two stacked boxes in full contact, sticking inside a disc
//! and slipping outside it (Theorem 4.2 in space): the exact fields against central
//! differences, hand values (computed symbolically by `scripts/manufactured-3d-friction.py`),
//! the boundary conditions and Tresca's conditions pointwise on a grid; the discrete problem on
//! non-matching meshes converges at first order in `E_grad`, finds the stick disc and carries
//! the exact resultants.
// The reference values are printed to 17 digits by the symbolic script.
#![allow(clippy::excessive_precision)]

use std::sync::Arc;

use nalgebra::{Matrix3, Vector2};
use vem_contact::CondensedSolver;
use vem_mesh::generators::polyhedral::PolyhedralFamily;
use vem_mesh::{Point3, Vector3};
use vem_space::PolyhedralVem;
use vem_verify::exact::{BodyId, Lame};
use vem_verify::three_d::{
    run_disc_contact, solid_rates, ExactSolution3d, SolidRun, StackedContact, StickSlipContact,
};

fn case() -> StickSlipContact {
    StickSlipContact::new(Lame::try_new(2.0, 1.0).unwrap())
}

/// Points inside body `id`'s box, inside and outside the stick disc's cylinder, some within
/// 0.01 of it.
fn points(id: BodyId) -> Vec<Point3> {
    let side = if id == BodyId::One { 1.0 } else { -1.0 };
    let r = StickSlipContact::STICK_RADIUS;
    let mut points = vec![
        Point3::new(0.4, 0.55, side / 3.0),
        Point3::new(0.9, 0.2, side * 0.75),
        Point3::new(0.5 + r - 0.01, 0.5, side * 0.1),
        Point3::new(0.5, 0.5 - r - 0.01, side * 0.6),
        Point3::new(0.5, 0.5, side * 0.5),
        Point3::new(0.95, 0.97, side * 0.2),
    ];
    for i in 0..4 {
        let t = |k: usize| 0.13 + 0.17 * ((i * k + 3) % 5) as f64;
        points.push(Point3::new(t(1), t(2), side * t(3)));
    }
    points
}

#[test]
fn m2_3d_is_in_equilibrium_by_central_differences() {
    let exact = case();
    // The slip's third derivatives reach about 100 at the corners: a step of 2e-5 keeps the
    // truncation error of the differences near 1e-8.
    let h = 2e-5;
    for id in BodyId::BOTH {
        let body = exact.body(id);
        for x in points(id) {
            let shifted = |k: usize, s: f64| {
                let mut y = x;
                y[k] += s;
                y
            };
            let g = body.gradient(x);
            let (u, g_too) = body.displacement_and_gradient(x);
            assert_eq!(u, body.displacement(x));
            assert_eq!(g, g_too);
            for j in 0..3 {
                let d = (body.displacement(shifted(j, h)) - body.displacement(shifted(j, -h)))
                    / (2.0 * h);
                for i in 0..3 {
                    assert!(
                        (d[i] - g[(i, j)]).abs() < 1e-7,
                        "{id:?}: d_{j} u_{i} at {x}: {} vs {}",
                        d[i],
                        g[(i, j)]
                    );
                }
            }
            let mut div = Vector3::zeros();
            for j in 0..3 {
                let d = (body.stress(shifted(j, h)) - body.stress(shifted(j, -h))) / (2.0 * h);
                div += d.column(j);
            }
            let f = body.body_force(x);
            assert!(
                (div + f).norm() < 1e-6 * (1.0 + f.norm()),
                "{id:?} at {x}: -div sigma = {} but f = {f}",
                -div
            );
        }
    }
}

/// `(sigma_xx, sigma_yy, sigma_zz, sigma_yz, sigma_xz, sigma_xy)`.
fn voigt(s: &Matrix3<f64>) -> [f64; 6] {
    [
        s[(0, 0)],
        s[(1, 1)],
        s[(2, 2)],
        s[(1, 2)],
        s[(0, 2)],
        s[(0, 1)],
    ]
}

#[test]
fn m2_3d_has_its_symbolic_reference_values() {
    // From scripts/manufactured-3d-friction.py, which types the displacements in directly and
    // differentiates them with sympy (lambda = 2, mu = 1).
    type Reference = (BodyId, [f64; 3], [f64; 3], [f64; 6], [f64; 3]);
    let references: [Reference; 4] = [
        (
            BodyId::One,
            [0.4, 0.55, 1.0 / 3.0],
            [
                0.03358428398933417,
                0.024501197018074111,
                -0.20993055555555556,
            ],
            [
                -0.59274025660534324,
                -0.14429958061741552,
                -0.24040216796314182,
                -0.056025982250666614,
                -0.030734685127109852,
                0.097921217294825641,
            ],
            [
                -6.5204735597524879,
                -2.2309293435979241,
                -3.0407270665273756,
            ],
        ),
        (
            BodyId::One,
            [0.9, 0.2, 0.75],
            [
                0.09801856085905232,
                -0.0037603056949763428,
                -0.13710719264004809,
            ],
            [
                1.2271389684411698,
                1.2693391469740227,
                1.9771438528009617,
                -0.0077075022853515399,
                -0.34072224593994643,
                -0.0026669300509928038,
            ],
            [
                -0.32020384352674047,
                0.087735494124158694,
                -1.64411715937546,
            ],
        ),
        (
            BodyId::Two,
            [0.4, 0.55, -1.0 / 3.0],
            [
                -0.023584283989334175,
                -0.012834530351407442,
                0.0040972222222222226,
            ],
            [
                0.35857358993867655,
                -0.089867086049251144,
                -0.31682005425908039,
                -0.032414871139555504,
                0.0053764259840012596,
                -0.097921217294825641,
            ],
            [6.5704735597524877, 2.2059293435979241, 2.850106266805958],
        ),
        (
            BodyId::Two,
            [0.9, 0.2, -0.75],
            [
                -0.084893560859052322,
                0.010322805694976343,
                0.011564682359951919,
            ],
            [
                -0.31213896844116984,
                -0.35433914697402263,
                -0.22214385280096163,
                0.05322999771464846,
                -0.31259724593994642,
                0.0026669300509928038,
            ],
            [0.44520384352674047, -0.40023549412415871, 3.63963284062454],
        ),
    ];
    let exact = case();
    for (id, x, u, sigma, f) in references {
        let body = exact.body(id);
        let x = Point3::from(x);
        let close = |a: f64, b: f64| (a - b).abs() < 1e-13 * (1.0 + b.abs());
        let (found_u, found_s, found_f) = (
            body.displacement(x),
            voigt(&body.stress(x)),
            body.body_force(x),
        );
        for k in 0..3 {
            assert!(close(found_u[k], u[k]), "{id:?} u at {x}: {found_u}");
            assert!(close(found_f[k], f[k]), "{id:?} f at {x}: {found_f}");
        }
        for k in 0..6 {
            assert!(
                close(found_s[k], sigma[k]),
                "{id:?} sigma at {x}: {found_s:?}"
            );
        }
    }
    // The interface: sticking at (2/5, 11/20), slipping at (9/10, 1/5).
    let close = |a: f64, b: f64| (a - b).abs() < 1e-16 + 1e-14 * b.abs();
    let stick = exact.interface(0.4, 0.55);
    assert!(close(stick.sigma_1tau.x, -0.066129277952003782));
    assert!(close(stick.sigma_1tau.y, -0.0027553865813334908));
    assert_eq!(stick.tangential_jump, Vector2::zeros());
    assert!(close(stick.sigma_nu, -1.24375));
    assert!(close(
        StickSlipContact::friction_bound(0.4, 0.55),
        0.30026030373660784
    ));
    let slip = exact.interface(0.9, 0.2);
    assert!(close(slip.sigma_1tau.x, -0.3625));
    assert!(close(slip.sigma_1tau.y, 0.075));
    assert!(close(slip.tangential_jump.x, 0.00022770678423919571));
    assert!(close(slip.tangential_jump.y, -4.7111748463281868e-05));
    assert!(close(
        StickSlipContact::friction_bound(0.9, 0.2),
        0.37017732237402118
    ));
    assert!(close(slip.sigma_nu, -1.125));
    // The constants: r_s^2 = (sqrt 2 - 1)/2, int p dA = 7/6, int sigma_1tau dA.
    let r_s = StickSlipContact::STICK_RADIUS;
    assert!((r_s * r_s - (2f64.sqrt() - 1.0) / 2.0).abs() < 1e-16);
    assert!(close(StickSlipContact::normal_resultant(), 7.0 / 6.0));
    let resultant = StickSlipContact::friction_resultant();
    assert!(close(resultant.x, -0.27183467860723209) && resultant.y == 0.0);
}

#[test]
fn m2_3d_satisfies_the_boundary_and_tresca_conditions() {
    let exact = case();
    let (one, two) = (exact.body(BodyId::One), exact.body(BodyId::Two));
    assert_eq!(one.contact_sides(), ["bottom"]);
    assert_eq!(two.contact_sides(), ["top"]);
    for body in [&one, &two] {
        assert_eq!(body.traction_sides(), ["left", "right", "front", "back"]);
    }
    let n = 40;
    let (mut sticking, mut slipping) = (0, 0);
    for i in 0..=n {
        for j in 0..=n {
            let (x, y) = (i as f64 / n as f64, j as f64 / n as f64);
            // Clamped: u = 0 on body one's top, body two's bottom.
            assert!(one.displacement(Point3::new(x, y, 1.0)).norm() < 1e-15);
            assert!(two.displacement(Point3::new(x, y, -1.0)).norm() < 1e-15);
            // Both bodies carry the interface values of the traces on z = 0.
            let values = exact.interface(x, y);
            let origin = Point3::new(x, y, 0.0);
            for body in [&one, &two] {
                let s = body.stress(origin);
                // sigma_1tau = (sigma nu_1)_T = -(sigma_xz, sigma_yz) with nu_1 = -e_z.
                let shear = -Vector2::new(s[(0, 2)], s[(1, 2)]);
                assert!((shear - values.sigma_1tau).norm() < 1e-15, "({x}, {y})");
                assert!((s[(2, 2)] - values.sigma_nu).abs() < 1e-14);
            }
            let (u1, u2) = (one.displacement(origin), two.displacement(origin));
            assert!((u2.z - u1.z - values.normal_jump).abs() < 1e-15);
            assert!(((u1 - u2).xy() - values.tangential_jump).norm() < 1e-15);
            // Full contact: compression and no gap.
            assert!(values.sigma_nu <= -1.0 && values.gap().abs() < 1e-15);
            // Tresca: |sigma_1tau| <= g_F; below the bound no slip; at the bound a slip
            // -c sigma_1tau with c >= 0.
            let g = StickSlipContact::friction_bound(x, y);
            let (t, slip) = (values.sigma_1tau, values.tangential_jump);
            assert!(t.norm() <= g * (1.0 + 1e-15), "({x}, {y})");
            let r = StickSlipContact::radius(x, y);
            if r < StickSlipContact::STICK_RADIUS {
                assert!(t.norm() < g, "({x}, {y})");
                assert_eq!(slip, Vector2::zeros(), "({x}, {y})");
                sticking += 1;
            } else {
                assert!((t.norm() - g).abs() < 1e-15, "({x}, {y})");
                let c = -slip.dot(&t) / t.norm_squared();
                assert!(c >= 0.0 && (slip + t * c).norm() < 1e-17, "({x}, {y})");
                slipping += usize::from(c > 0.0);
            }
        }
    }
    assert!(sticking > 900 && slipping > 400, "{sticking}, {slipping}");
}

/// M2-3D on `upper` over `lower` at the sizes `(upper n, lower n)`, with the default
/// (condensed) contact solver.
fn pairing_runs(
    upper: PolyhedralFamily,
    lower: PolyhedralFamily,
    sizes: &[(usize, usize)],
) -> Vec<SolidRun> {
    let exact = case();
    sizes
        .iter()
        .map(|&(a, b)| {
            run_disc_contact(
                &exact,
                (upper, a),
                (lower, b),
                Arc::new(PolyhedralVem::default()),
                &mut CondensedSolver::default(),
            )
            .unwrap()
        })
        .collect()
}

#[test]
fn m2_3d_converges_on_non_matching_meshes_and_carries_the_exact_resultants() {
    // Theorem 4.2 in space on a pairing whose interfaces do not match (hexahedra 4:3 over
    // tetrahedra), at sizes a test can afford. Measured: least-squares E_grad 0.92 (successive
    // 0.90 and 0.95), E_0 1.79 (1.85 and 1.71: the body force jumps across the cylinder
    // r = r_s, docs/manufactured.md, section 11); the full run of `cargo xtask convergence`
    // judges the rate at its larger sizes (docs/convergence-3d.md). The test holds what is
    // measured, with a margin, and that the successive rates of E_grad grow.
    let exact = case();
    let exact_normal = exact.exact_normal_resultant();
    let exact_friction = exact.exact_friction_resultant();
    let runs = pairing_runs(
        PolyhedralFamily::Hexahedra,
        PolyhedralFamily::Tetrahedra,
        &[(8, 6), (12, 9), (16, 12)],
    );
    for run in &runs {
        let contact = run.contact.as_ref().unwrap();
        let friction = contact.friction.as_ref().unwrap();
        let label = format!("{} n = {}/{}", run.family, run.n, contact.lower_n);
        // The default solver certifies its answer by its own KKT check.
        assert_eq!(contact.status, "Converged", "{label}");
        // Full contact; both zones found (measured: 64 .. 313 nodes stick, 153 .. 504 slip).
        assert_eq!(contact.active_nodes, contact.interface_nodes, "{label}");
        assert!(
            friction.stick_nodes > 50 && friction.slip_nodes > 130,
            "{label}"
        );
        // The resultants: int p dA (measured 6.5e-4 .. 6.1e-5) and int sigma_1tau dA (measured
        // 2.0 % .. 0.36 %).
        let normal = (contact.normal_resultant / exact_normal - 1.0).abs();
        assert!(normal < 1e-3, "{label}: normal resultant error {normal}");
        let found = Vector2::from(friction.friction_resultant);
        let tangential = (found - exact_friction).norm() / exact_friction.norm();
        assert!(
            tangential < 0.03,
            "{label}: friction resultant error {tangential}"
        );
    }
    let last = &runs[2];
    let found = Vector2::from(
        last.contact
            .as_ref()
            .unwrap()
            .friction
            .as_ref()
            .unwrap()
            .friction_resultant,
    );
    assert!((found - exact_friction).norm() / exact_friction.norm() < 0.006);
    let rates = solid_rates(&runs, 3).pop().unwrap();
    let grad = rates.grad_rate.unwrap();
    let l2 = rates.l2_rate.unwrap();
    assert!(grad >= 0.88, "{}: E_grad rate {grad}", rates.family);
    assert!(l2 >= 1.7, "{}: E_0 rate {l2}", rates.family);
    let step = |a: &SolidRun, b: &SolidRun| {
        (a.errors.grad / b.errors.grad).ln() / (a.spacing / b.spacing).ln()
    };
    assert!(step(&runs[1], &runs[2]) > step(&runs[0], &runs[1]));
}

/// A diagnosis, not run by default (`cargo test -p vem-verify --test stick_slip -- --ignored
/// --nocapture`): the rates of M2-3D on matching meshes (hexahedra on hexahedra, tetrahedra on
/// tetrahedra: no vertex inserted by the overlay), printed. Measured at 8, 12, 16: E_grad 0.89
/// and 0.82, E_0 1.88 and 1.70; on the tetrahedra most nodes of the outer stick disc slip.
#[test]
#[ignore]
fn m2_3d_rates_on_matching_hexahedra_and_tetrahedra() {
    for (upper, lower, sizes) in [
        (
            PolyhedralFamily::Hexahedra,
            PolyhedralFamily::Hexahedra,
            vec![(8, 8), (12, 12), (16, 16)],
        ),
        (
            PolyhedralFamily::Tetrahedra,
            PolyhedralFamily::Tetrahedra,
            vec![(8, 8), (12, 12), (16, 16)],
        ),
    ] {
        let runs = pairing_runs(upper, lower, &sizes);
        for run in &runs {
            let contact = run.contact.as_ref().unwrap();
            eprintln!(
                "{} n = {}/{}: E_grad {:.4e}, E_0 {:.4e}, {:?}",
                run.family,
                run.n,
                contact.lower_n,
                run.errors.relative_grad(),
                run.errors.relative_l2(),
                contact.friction
            );
        }
        let rates = solid_rates(&runs, 3).pop().unwrap();
        eprintln!(
            "{}: E_grad rate {:.3}, E_0 rate {:.3}",
            rates.family,
            rates.grad_rate.unwrap(),
            rates.l2_rate.unwrap()
        );
    }
}
