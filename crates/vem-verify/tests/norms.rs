//! Error measures against hand-computed and tabulated values (`docs/manufactured.md`, section 10).
// Reference values are copied verbatim from docs/manufactured.md, section 10.
#![allow(clippy::excessive_precision)]

use std::sync::Arc;

use vem_mesh::generators::{MeshFamily, Rectangle};
use vem_mesh::{Mesh, Point};
use vem_space::LowestOrderVem;
use vem_verify::exact::{case_by_name, BodyId, ExactSolution, Lame};
use vem_verify::norms::{
    energy_error, nodal_interpolant, projection_errors, quadrature_points, sub_triangles,
    ErrorNorms,
};
use vem_verify::problem::{DiscreteProblem, ProblemSettings};
use vem_verify::VerifyError;

fn case(name: &str) -> Arc<dyn ExactSolution> {
    case_by_name(name, Lame::default()).unwrap().into()
}

fn mesh(exact: &dyn ExactSolution, body: BodyId, family: MeshFamily, n: usize) -> Mesh {
    family.generate(&exact.domain(body), n, 5).unwrap()
}

fn relative(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// With `u_h = 0` the projection errors are the norms of `u`: `||u||_0^2` and `|u|_1^2` of
/// section 10, for the two bodies of M1 (piecewise polynomial, switch line inside elements),
/// E1 (trigonometric) and PT0a (linear: integrated exactly on a non-convex mesh).
#[test]
fn zero_solution_gives_the_tabulated_norms_of_u() {
    let element = LowestOrderVem::default();
    let table = [
        (
            "M1",
            BodyId::One,
            MeshFamily::Quads,
            0.012476509794967739,
            0.11779433615398217,
            1e-7,
        ),
        (
            "M1",
            BodyId::Two,
            MeshFamily::Voronoi,
            3.5675388758912553e-3,
            0.023778888228177323,
            1e-7,
        ),
        (
            "E1",
            BodyId::One,
            MeshFamily::Voronoi,
            0.5,
            17.271807701906378,
            1e-6,
        ),
        ("PT0a", BodyId::One, MeshFamily::NonConvex, 0.27, 0.3, 1e-13),
    ];
    for (name, body, family, l2_squared, h1_squared, tolerance) in table {
        let exact = case(name);
        let mesh = mesh(&*exact, body, family, 16);
        let zero = vec![0.0; 2 * mesh.n_vertices()];
        let errors = projection_errors(&*exact, body, &mesh, &element, &zero).unwrap();
        assert!(
            relative(errors.l2.powi(2), l2_squared) < tolerance,
            "{name} {body:?}: ||u||_0^2 = {} vs {l2_squared}",
            errors.l2.powi(2)
        );
        assert!(
            relative(errors.grad.powi(2), h1_squared) < tolerance,
            "{name} {body:?}: |u|_1^2 = {} vs {h1_squared}",
            errors.grad.powi(2)
        );
        assert_eq!(
            (errors.l2, errors.grad),
            (errors.exact_l2, errors.exact_grad)
        );
    }
}

/// The energy projection reproduces linear fields: the interpolant of PT0a has zero
/// projection error on every family, including chevrons (non-convex) and hanging nodes.
#[test]
fn interpolant_of_a_linear_field_has_zero_projection_error() {
    let exact = case("PT0a");
    for family in MeshFamily::all() {
        let mesh = mesh(&*exact, BodyId::One, family, 6);
        let interpolant = nodal_interpolant(&*exact, BodyId::One, &mesh);
        let errors = projection_errors(
            &*exact,
            BodyId::One,
            &mesh,
            &LowestOrderVem::default(),
            &interpolant,
        )
        .unwrap();
        assert!(
            errors.grad < 1e-13 && errors.l2 < 1e-13,
            "{}: {errors:?}",
            family.name()
        );
    }
}

/// `E_a` of `u_h = 0` is `a_h(u_I, u_I)^(1/2)`, which for the linear PT0a equals
/// `a(u, u)^(1/2) = 1.16^(1/2)` (consistency (3.1)); `E_a` of `u_h = u_I` is zero.
#[test]
fn energy_error_of_the_linear_patch_field() {
    let exact = case("PT0a");
    let mesh = mesh(&*exact, BodyId::One, MeshFamily::Voronoi, 7);
    let problem =
        DiscreteProblem::try_new(Arc::clone(&exact), vec![mesh], &ProblemSettings::default())
            .unwrap();
    let body = &problem.bodies()[0];
    let system = body.assemble().unwrap();
    let interpolant = nodal_interpolant(&*exact, BodyId::One, body.mesh());
    let at_interpolant =
        energy_error(&*exact, BodyId::One, body.mesh(), &system, &interpolant).unwrap();
    assert!(at_interpolant.error < 1e-14, "{at_interpolant:?}");
    assert!(relative(at_interpolant.interpolant.powi(2), 1.16) < 1e-12);
    let zero = vec![0.0; interpolant.len()];
    let at_zero = energy_error(&*exact, BodyId::One, body.mesh(), &system, &zero).unwrap();
    assert!(relative(at_zero.error.powi(2), 1.16) < 1e-12, "{at_zero:?}");
}

#[test]
fn combined_norms_are_roots_of_sums_of_squares() {
    let a = ErrorNorms {
        grad: 3.0,
        l2: 1.0,
        energy: 6.0,
        exact_grad: 1.0,
        exact_l2: 2.0,
        interpolant_energy: 4.0,
    };
    let b = ErrorNorms {
        grad: 4.0,
        l2: 0.0,
        energy: 8.0,
        exact_grad: 0.0,
        exact_l2: 0.0,
        interpolant_energy: 3.0,
    };
    let c = ErrorNorms::combine(&[a, b]);
    assert_eq!((c.grad, c.l2, c.energy), (5.0, 1.0, 10.0));
    assert_eq!(
        (c.exact_grad, c.exact_l2, c.interpolant_energy),
        (1.0, 2.0, 5.0)
    );
    assert_eq!(
        (c.relative_grad(), c.relative_l2(), c.relative_energy()),
        (5.0, 0.5, 2.0)
    );
}

/// Integral of `x^a y^b` over the axis-aligned box [x0, x1] x [y0, y1].
fn box_moment(a: i32, b: i32, [x0, x1, y0, y1]: [f64; 4]) -> f64 {
    let int = |p: i32, lo: f64, hi: f64| (hi.powi(p + 1) - lo.powi(p + 1)) / f64::from(p + 1);
    int(a, x0, x1) * int(b, y0, y1)
}

/// A U-shaped polygon whose centroid lies in its notch (the fan is not valid), a square with
/// hanging nodes and an interior chevron: positive triangles covering the polygon, and the
/// degree-5 rule exact for `x^2 y^3`.
#[test]
fn sub_triangles_cover_non_star_shaped_polygons() {
    let u_shape = vec![
        Point::new(0.0, 0.0),
        Point::new(3.0, 0.0),
        Point::new(3.0, 3.0),
        Point::new(2.0, 3.0),
        Point::new(2.0, 0.2),
        Point::new(1.0, 0.2),
        Point::new(1.0, 3.0),
        Point::new(0.0, 3.0),
    ];
    let u_moment = box_moment(2, 3, [0.0, 3.0, 0.0, 3.0]) - box_moment(2, 3, [1.0, 2.0, 0.2, 3.0]);
    let hanging = vec![
        Point::new(0.0, 0.0),
        Point::new(0.5, 0.0),
        Point::new(1.0, 0.0),
        Point::new(1.0, 0.5),
        Point::new(1.0, 1.0),
        Point::new(0.0, 1.0),
    ];
    let hanging_moment = box_moment(2, 3, [0.0, 1.0, 0.0, 1.0]);
    let chevrons = MeshFamily::NonConvex
        .generate(&Rectangle::unit_square(), 3, 0)
        .unwrap();
    // The interior chevron: a hexagon with one reflex vertex.
    let chevron = (0..chevrons.n_polygons())
        .map(|p| chevrons.polygon_points(p))
        .find(|p| p.len() == 6)
        .unwrap();
    let chevron_area = vem_mesh::geometry::signed_area(&chevron);
    for (polygon, moment) in [
        (u_shape, Some(u_moment)),
        (hanging, Some(hanging_moment)),
        (chevron, None),
    ] {
        let area = vem_mesh::geometry::signed_area(&polygon);
        let triangles = sub_triangles(&polygon).unwrap();
        let mut total = 0.0;
        for [a, b, c] in &triangles {
            let t = 0.5 * (b - a).perp(&(c - a));
            assert!(t > 0.0, "{polygon:?}: triangle {a:?} {b:?} {c:?}");
            total += t;
        }
        assert!(relative(total, area) < 1e-14, "{total} vs {area}");
        let rule = quadrature_points(&polygon).unwrap();
        assert!(rule.iter().all(|q| q.weight > 0.0));
        if let Some(moment) = moment {
            let integral: f64 = rule
                .iter()
                .map(|q| q.weight * q.point.x.powi(2) * q.point.y.powi(3))
                .sum();
            assert!(relative(integral, moment) < 1e-13, "{integral} vs {moment}");
        }
    }
    assert!(chevron_area > 0.0);
    // Clockwise or degenerate polygons are refused.
    let clockwise = [
        Point::new(0.0, 0.0),
        Point::new(0.0, 1.0),
        Point::new(1.0, 0.0),
    ];
    assert!(sub_triangles(&clockwise).is_err());
    assert!(sub_triangles(&clockwise[..2]).is_err());
}

#[test]
fn a_displacement_of_the_wrong_length_is_an_error() {
    let exact = case("E1");
    let mesh = mesh(&*exact, BodyId::One, MeshFamily::Quads, 2);
    let err = projection_errors(
        &*exact,
        BodyId::One,
        &mesh,
        &LowestOrderVem::default(),
        &[0.0; 3],
    )
    .unwrap_err();
    assert!(
        matches!(
            err,
            VerifyError::WrongLength {
                body: 1,
                found: 3,
                expected: 18
            }
        ),
        "{err}"
    );
}
