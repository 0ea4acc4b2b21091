//! M1-3D, frictionless contact of two stacked boxes on a disc (Theorem 4.1 in space): the exact
//! fields against central differences, hand values (computed symbolically by
//! `scripts/manufactured-3d-contact.py`), the boundary and interface conditions; the discrete
//! problem on non-matching meshes converges at first order in `E_grad`, finds the contact disc
//! and carries the exact resultant.
// The reference values are printed to 17 digits by the symbolic script.
#![allow(clippy::excessive_precision)]

use std::sync::Arc;

use nalgebra::Matrix3;
use vem_contact::CondensedSolver;
use vem_mesh::generators::polyhedral::PolyhedralFamily;
use vem_mesh::{Point3, Vector3};
use vem_space::PolyhedralVem;
use vem_verify::exact::{BodyId, Lame};
use vem_verify::three_d::{
    run_disc_contact, solid_rates, DiscContact, ExactSolution3d, SolidRun, CUBE_PARTS,
};

fn case() -> DiscContact {
    DiscContact::new(Lame::try_new(2.0, 1.0).unwrap())
}

/// Points inside body `id`'s box, inside and outside the contact disc's cylinder, some within
/// 0.01 of it.
fn points(id: BodyId) -> Vec<Point3> {
    let side = if id == BodyId::One { 1.0 } else { -1.0 };
    let r = DiscContact::CONTACT_RADIUS;
    let mut points = vec![
        Point3::new(0.4, 0.55, side / 3.0),
        Point3::new(0.9, 0.2, side * 0.75),
        Point3::new(0.5 + r - 0.01, 0.5, side * 0.1),
        Point3::new(0.5, 0.5 + r + 0.01, side * 0.6),
        Point3::new(0.5, 0.5, side * 0.5),
    ];
    for i in 0..4 {
        let t = |k: usize| 0.13 + 0.17 * ((i * k + 3) % 5) as f64;
        points.push(Point3::new(t(1), t(2), side * t(3)));
    }
    points
}

#[test]
fn m1_3d_is_in_equilibrium_by_central_differences() {
    let exact = case();
    let h = 1e-4;
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
fn m1_3d_has_its_symbolic_reference_values() {
    // From scripts/manufactured-3d-contact.py, which types the displacements in directly and
    // differentiates them with sympy (lambda = 2, mu = 1).
    type Reference = (BodyId, [f64; 3], [f64; 3], [f64; 6], [f64; 3]);
    let references: [Reference; 4] = [
        (
            BodyId::One,
            [0.4, 0.55, 1.0 / 3.0],
            [0.026, 0.033666666666666664, -0.18632642927380894],
            [
                0.45254848995635094,
                0.41699293440079538,
                0.38954142435714628,
                0.049367237741327306,
                -0.30206780881598794,
                0.024444444444444446,
            ],
            [
                0.64991625078305681,
                -0.50190256983597292,
                -6.1663753496174136,
            ],
        ),
        (
            BodyId::One,
            [0.9, 0.2, 0.75],
            [
                0.046927661072579452,
                0.014843316695565411,
                -0.096280085217520017,
            ],
            [
                0.87005280122529127,
                0.85195548767613916,
                1.428563542098755,
                -0.06802908347782706,
                -0.22085705536289726,
                0.040851033915739264,
            ],
            [3.8149926872666371, -3.4848382654499779, -1.3138684623563115],
        ),
        (
            BodyId::Two,
            [0.4, 0.55, -1.0 / 3.0],
            [
                -0.026666666666666668,
                -0.024444444444444446,
                -0.034506904059524383,
            ],
            [
                -0.54453484337698244,
                -0.50009039893253793,
                -0.60018079786507594,
                -0.15614501551910509,
                0.19729003103821016,
                0.0,
            ],
            [1.0078051396719458, -0.55140256983597291, 3.9883197940618578],
        ),
        (
            BodyId::Two,
            [0.9, 0.2, -0.75],
            [-0.0365625, -0.0059375, -0.0475],
            [-0.536875, -0.515, -0.770625, -0.02625, -0.151875, 0.0],
            [0.135, 0.04, -0.315],
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
    // The interface: in the disc at (2/5, 11/20), out of it at (9/10, 1/5).
    let inside = exact.interface(0.4, 0.55);
    assert!((inside.sigma_nu + 0.69887572692856104).abs() < 1e-15);
    assert!((inside.normal_jump - 0.0853125).abs() < 1e-15);
    assert!(inside.gap().abs() < 1e-16);
    let outside = exact.interface(0.9, 0.2);
    assert_eq!(outside.sigma_nu, 0.0);
    assert!((outside.normal_jump - 0.098640194782902896).abs() < 1e-15);
    assert!((outside.gap() - 0.00010980521709711091).abs() < 1e-16);
    assert!((DiscContact::gap(0.9, 0.2) - 0.00010980521709711091).abs() < 1e-19);
    // The constants: r_c = (3 - sqrt 5)/2, int p dA = pi r_c^2 / 5.
    assert_eq!(DiscContact::CONTACT_RADIUS, (3.0 - 5f64.sqrt()) / 2.0);
    assert!((DiscContact::normal_resultant() - 0.091670438200637349).abs() < 1e-16);
}

#[test]
fn m1_3d_satisfies_the_boundary_and_signorini_conditions() {
    let exact = case();
    let (one, two) = (exact.body(BodyId::One), exact.body(BodyId::Two));
    assert_eq!(one.contact_sides(), ["bottom"]);
    assert_eq!(two.contact_sides(), ["top"]);
    for body in [&one, &two] {
        assert_eq!(body.traction_sides(), ["left", "right", "front", "back"]);
        // The Dirichlet side is the one neither traction nor contact side.
        let dirichlet: Vec<&str> = CUBE_PARTS
            .iter()
            .map(|(p, _)| *p)
            .filter(|p| !body.traction_sides().contains(p) && !body.contact_sides().contains(p))
            .collect();
        assert_eq!(dirichlet.len(), 1);
    }
    let n = 40;
    let mut in_contact = 0;
    for i in 0..=n {
        for j in 0..=n {
            let (x, y) = (i as f64 / n as f64, j as f64 / n as f64);
            // Clamped: u = 0 on body one's top, body two's bottom.
            assert!(one.displacement(Point3::new(x, y, 1.0)).norm() < 1e-15);
            assert!(two.displacement(Point3::new(x, y, -1.0)).norm() < 1e-15);
            // Both bodies: no shear, sigma_zz = sigma_nu on z = 0.
            let values = exact.interface(x, y);
            let origin = Point3::new(x, y, 0.0);
            for body in [&one, &two] {
                let s = body.stress(origin);
                assert!(s[(0, 2)].abs() < 1e-15 && s[(1, 2)].abs() < 1e-15);
                assert!((s[(2, 2)] - values.sigma_nu).abs() < 1e-14);
            }
            let (u1, u2) = (one.displacement(origin), two.displacement(origin));
            assert!((u2.z - u1.z - values.normal_jump).abs() < 1e-15);
            assert!(((u1 - u2).xy() - values.tangential_jump).norm() < 1e-15);
            // Signorini: sigma_nu <= 0, gap >= 0, one of them zero; contact inside the disc.
            let r = DiscContact::radius(x, y);
            let (pressure, gap) = (-values.sigma_nu, values.gap());
            assert!(pressure >= 0.0 && gap >= -1e-16 && pressure * gap.abs() < 1e-16);
            assert_eq!(
                pressure > 0.0,
                r < DiscContact::CONTACT_RADIUS,
                "({x}, {y})"
            );
            assert!((gap - DiscContact::gap(x, y)).abs() < 1e-16);
            assert_eq!(
                DiscContact::gap(x, y) > 0.0,
                r > DiscContact::CONTACT_RADIUS,
                "({x}, {y})"
            );
            in_contact += usize::from(pressure > 0.0);
        }
    }
    assert!(in_contact > 100, "{in_contact}");
}

/// M1-3D on `upper` over `lower` at the sizes `(upper n, lower n)`, with the default
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
fn m1_3d_converges_at_first_order_on_non_matching_meshes_and_finds_the_disc() {
    // Theorem 4.1 in space: E_grad = O(h) on two pairings whose interfaces do not match
    // (hexahedra 4:3 over tetrahedra; perturbed hexahedra over octree cubes with hanging
    // nodes), at the smallest sizes past the early slopes (measured: least-squares rates 0.98
    // and 0.94; successive 0.95, 1.01 and 0.91, 0.98; docs/convergence-3d.md has the larger
    // sizes).
    let r_c = DiscContact::CONTACT_RADIUS;
    let exact_resultant = DiscContact::normal_resultant();
    for (upper, lower, sizes, least) in [
        (
            PolyhedralFamily::Hexahedra,
            PolyhedralFamily::Tetrahedra,
            [(8, 6), (12, 9), (16, 12)],
            0.95,
        ),
        (
            PolyhedralFamily::PerturbedHexahedra {
                distortion: PolyhedralFamily::DEFAULT_DISTORTION,
            },
            PolyhedralFamily::Octree,
            [(8, 4), (12, 6), (16, 8)],
            0.92,
        ),
    ] {
        let runs = pairing_runs(upper, lower, &sizes);
        let mut resultant_error = f64::INFINITY;
        for run in &runs {
            let contact = run.contact.as_ref().unwrap();
            let label = format!("{} n = {}/{}", run.family, run.n, contact.lower_n);
            // The default solver certifies its answer by its own KKT check.
            assert_eq!(contact.status, "Converged", "{label}");
            // Every node well inside the disc is in contact, every node well outside is not.
            // The band is wide because the exact solution is flat at the circle by design: the
            // pressure vanishes like (r_c - r)^4, the gap opens like (r - r_c)^5, so near the
            // circle either is far below the discretisation error (measured: nodes open from
            // r = 0.236 = r_c - 0.146, in contact up to r = 0.603 = r_c + 0.221).
            assert!(contact.innermost_open > r_c - 0.16, "{label}: {contact:?}");
            assert!(
                contact.outermost_contact < r_c + 0.25,
                "{label}: {contact:?}"
            );
            assert!(contact.active_nodes > 50, "{label}");
            // The nodal forces converge to int p dA.
            let error = (contact.normal_resultant / exact_resultant - 1.0).abs();
            assert!(error < resultant_error, "{label}: resultant error {error}");
            resultant_error = error;
        }
        assert!(resultant_error < 0.03, "{resultant_error}");
        let rates = solid_rates(&runs, 3).pop().unwrap();
        let grad = rates.grad_rate.unwrap();
        let l2 = rates.l2_rate.unwrap();
        assert!(grad >= least, "{}: E_grad rate {grad}", rates.family);
        assert!(l2 >= 1.7, "{}: E_0 rate {l2}", rates.family);
    }
}
