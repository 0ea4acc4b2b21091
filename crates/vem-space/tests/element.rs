//! Element-level checks of the lowest-order VEM (manufactured.md, PT0 companions): rigid-motion
//! kernel, rank, consistency (3.1) against an independent boundary integration, vanishing
//! stabilisation on P1, symmetry, exact projection of linear fields, energy of linear fields,
//! equality with the independent P1 triangle, and the load terms.

use nalgebra::{DVector, Matrix2, Matrix3, Vector3};
use vem_mesh::generators::{structured_quads, structured_triangles, Rectangle};
use vem_space::{
    edge_traction_load, ElasticityTensor, ElementSpace, LinearTriangle, LowestOrderVem, Point,
    SpaceError, Stabilisation, StabilisationScaling, Vector,
};

fn p(x: f64, y: f64) -> Point {
    Point::new(x, y)
}

fn regular_polygon(n: usize, centre: Point, radius: f64) -> Vec<Point> {
    (0..n)
        .map(|k| {
            let t = 2.0 * std::f64::consts::PI * k as f64 / n as f64 + 0.1;
            centre + Vector::new(t.cos(), t.sin()) * radius
        })
        .collect()
}

/// Hand-built polygons of every kind the meshes produce, plus cells of the generated meshes.
fn polygons() -> Vec<(String, Vec<Point>)> {
    let mut list: Vec<(String, Vec<Point>)> = vec![
        (
            "triangle".into(),
            vec![p(0.1, 0.2), p(1.3, -0.1), p(0.4, 0.9)],
        ),
        (
            "sliver triangle".into(),
            vec![p(0.0, 0.0), p(1.0, 0.0), p(0.5, 0.02)],
        ),
        (
            "regular hexagon".into(),
            regular_polygon(6, p(0.3, -0.2), 1.0),
        ),
        (
            "L-shape".into(),
            vec![
                p(0.0, 0.0),
                p(2.0, 0.0),
                p(2.0, 1.0),
                p(1.0, 1.0),
                p(1.0, 2.0),
                p(0.0, 2.0),
            ],
        ),
        (
            "chevron".into(),
            vec![p(0.0, 0.0), p(1.0, 0.6), p(2.0, 0.0), p(1.0, 2.0)],
        ),
        (
            "square with hanging node".into(),
            vec![
                p(0.0, 0.0),
                p(1.0, 0.0),
                p(1.0, 0.5),
                p(1.0, 1.0),
                p(0.0, 1.0),
            ],
        ),
        (
            "quad with 7 collinear vertices".into(),
            vec![
                p(0.0, 0.0),
                p(0.13, 0.0),
                p(0.4, 0.0),
                p(0.55, 0.0),
                p(0.81, 0.0),
                p(0.9, 0.0),
                p(1.0, 0.0),
                p(1.0, 1.0),
                p(0.0, 1.0),
            ],
        ),
        (
            "distorted quad".into(),
            vec![p(0.0, 0.0), p(3.0, 0.0), p(3.1, 0.2), p(0.1, 0.4)],
        ),
        (
            "almost-triangle quad".into(),
            vec![p(0.0, 0.0), p(1.0, 0.0), p(0.505, 0.5), p(0.0, 1.0)],
        ),
        (
            "small hexagon far from the origin".into(),
            regular_polygon(6, p(1.0e4, -3.0e4), 1e-3),
        ),
    ];
    let rect = Rectangle::new(p(-1.0, 0.5), p(2.0, 2.5));
    for (family, mesh) in [
        ("structured quads", structured_quads(&rect, 3, 2).unwrap()),
        (
            "structured triangles",
            structured_triangles(&rect, 2, 2).unwrap(),
        ),
    ] {
        for cell in 0..mesh.n_polygons().min(4) {
            list.push((format!("{family} #{cell}"), mesh.polygon_points(cell)));
        }
    }
    list
}

fn materials() -> Vec<ElasticityTensor> {
    vec![
        ElasticityTensor::isotropic(2.0, 1.0).unwrap(),
        ElasticityTensor::from_voigt(Matrix3::new(5.0, 1.5, 0.5, 1.5, 3.0, 0.3, 0.5, 0.3, 1.2))
            .unwrap(),
    ]
}

fn elements() -> Vec<LowestOrderVem> {
    [
        Stabilisation::default(),
        Stabilisation::dofi_dofi(StabilisationScaling::ShearModulus),
        Stabilisation::DofiDofi {
            scaling: StabilisationScaling::TraceOfC,
            scale: 2.0,
        },
        Stabilisation::DRecipe,
    ]
    .into_iter()
    .map(|s| LowestOrderVem::new(s).unwrap())
    .collect()
}

/// Linear fields p(x) = a + M x (the last one a pure rotation plus a translation).
fn linear_fields() -> Vec<(Vector, Matrix2<f64>)> {
    vec![
        (Vector::new(0.1, 0.2), Matrix2::new(0.2, 0.3, -0.1, 0.4)),
        (Vector::new(-1.0, 0.5), Matrix2::new(1.0, 0.0, 0.0, 0.0)),
        (Vector::new(0.0, 0.0), Matrix2::new(0.0, 1.0, 1.0, 0.0)),
        (Vector::new(2.0, -3.0), Matrix2::new(0.0, -1.0, 1.0, 0.0)),
    ]
}

/// Nodal interpolant of x -> f(x), DOFs interleaved by component.
fn interpolant(polygon: &[Point], f: impl Fn(Point) -> Vector) -> DVector<f64> {
    DVector::from_fn(2 * polygon.len(), |i, _| f(polygon[i / 2])[i % 2])
}

/// Rigid motions (1,0), (0,1), (-y, x) at the vertices.
fn rigid_motions(polygon: &[Point]) -> [DVector<f64>; 3] {
    [
        interpolant(polygon, |_| Vector::new(1.0, 0.0)),
        interpolant(polygon, |_| Vector::new(0.0, 1.0)),
        interpolant(polygon, |x| Vector::new(-x.y, x.x)),
    ]
}

/// Voigt strain [xx, yy, 2 xy] of the gradient M.
fn voigt_strain(m: &Matrix2<f64>) -> Vector3<f64> {
    Vector3::new(m[(0, 0)], m[(1, 1)], m[(0, 1)] + m[(1, 0)])
}

/// The boundary load of the constant traction sigma nu: each edge gives half its length times
/// sigma nu to each end point (independent of the element code: edge normals by hand).
fn boundary_load_of_constant_stress(polygon: &[Point], sigma: &Vector3<f64>) -> DVector<f64> {
    let s = Matrix2::new(sigma[0], sigma[2], sigma[2], sigma[1]);
    let n = polygon.len();
    let mut load = DVector::zeros(2 * n);
    for k in 0..n {
        let (a, b) = (polygon[k], polygon[(k + 1) % n]);
        // Counter-clockwise: the outward normal times the length is (dy, -dx).
        let scaled_normal = Vector::new(b.y - a.y, a.x - b.x);
        let half = s * scaled_normal * 0.5;
        for v in [k, (k + 1) % n] {
            load[2 * v] += half.x;
            load[2 * v + 1] += half.y;
        }
    }
    load
}

/// Area by the shoelace formula relative to the first vertex (no cancellation far away).
fn area(polygon: &[Point]) -> f64 {
    let local: Vec<Point> = polygon
        .iter()
        .map(|x| Point::from(x - polygon[0]))
        .collect();
    vem_mesh::geometry::signed_area(&local)
}

/// `max(1, max |x_k| / h_T)`: the relative precision of vertex data is `eps` times this (the
/// coordinates themselves carry an absolute error `eps |x|`), so tolerances scale with it.
fn conditioning(polygon: &[Point]) -> f64 {
    let largest = polygon.iter().map(|x| x.coords.norm()).fold(0.0, f64::max);
    (largest / vem_mesh::geometry::diameter(polygon)).max(1.0)
}

#[test]
fn rigid_motions_are_in_the_kernel_and_the_rank_is_2n_minus_3() {
    let mut worst_kernel: f64 = 0.0;
    let mut worst_gap = f64::INFINITY;
    for (name, polygon) in polygons() {
        let n = polygon.len();
        for material in materials() {
            for element in elements() {
                let local = element.stiffness(&polygon, &material).unwrap();
                let k = local.total();
                let scale = k.norm();
                for r in rigid_motions(&polygon) {
                    let residual = (&k * &r).norm() / (scale * r.norm());
                    worst_kernel = worst_kernel.max(residual);
                    assert!(
                        residual < 1e-12,
                        "{name}, {element:?}: |K r| = {residual:e}"
                    );
                }
                let sv = k.singular_values();
                let mut sorted: Vec<f64> = sv.iter().copied().collect();
                sorted.sort_by(|a, b| b.total_cmp(a));
                let rank = sorted.iter().filter(|&&s| s > 1e-10 * sorted[0]).count();
                assert_eq!(
                    rank,
                    2 * n - 3,
                    "{name}, {element:?}: singular values {sorted:?}"
                );
                worst_gap = worst_gap.min(sorted[2 * n - 4] / sorted[0]);
            }
        }
    }
    println!(
        "worst |K r|/(|K||r|) = {worst_kernel:e}; smallest sigma_(2n-3)/sigma_1 = {worst_gap:e}"
    );
}

#[test]
fn consistency_energy_and_vanishing_stabilisation_on_linear_fields() {
    let mut worst: f64 = 0.0;
    for (name, polygon) in polygons() {
        for material in materials() {
            for element in elements() {
                let local = element.stiffness(&polygon, &material).unwrap();
                let k = local.total();
                assert_eq!(k, k.transpose(), "{name}: K_T is not symmetric");
                assert_eq!(local.stabilisation, local.stabilisation.transpose());
                for (a, m) in linear_fields() {
                    let p_i = interpolant(&polygon, |x| a + m * x.coords);
                    let sigma = material.stress(&voigt_strain(&m));
                    // Consistency (3.1): K p_I = int_dT sigma(p) nu . phi_i.
                    let expected = boundary_load_of_constant_stress(&polygon, &sigma);
                    let error = (&k * &p_i - &expected).norm() / (k.norm() * p_i.norm());
                    worst = worst.max(error);
                    assert!(error < 1e-12, "{name}, {element:?}: (3.1) error {error:e}");
                    // S_T vanishes on P1.
                    let stab = (&local.stabilisation * &p_i).norm() / (k.norm() * p_i.norm());
                    assert!(stab < 1e-12, "{name}, {element:?}: |S p| = {stab:e}");
                    // Energy: p_I^T K p_I = |T| eps(p) : C eps(p).
                    let energy = p_i.dot(&(&k * &p_i));
                    let exact = area(&polygon) * voigt_strain(&m).dot(&sigma);
                    let scale = k.norm() * p_i.norm_squared();
                    assert!(
                        (energy - exact).abs() < 1e-12 * scale,
                        "{name}: energy {energy} vs {exact}"
                    );
                }
            }
        }
    }
    println!("worst relative consistency error = {worst:e}");
}

#[test]
fn projection_reproduces_linear_fields() {
    let element = LowestOrderVem::default();
    for (name, polygon) in polygons() {
        let projection = element.projection(&polygon).unwrap();
        assert_eq!(projection.coefficients.shape(), (6, 2 * polygon.len()));
        let reference = vem_mesh::geometry::vertex_mean(&polygon);
        assert!((projection.reference - reference).norm() <= 1e-15 * reference.coords.norm());
        for (a, m) in linear_fields() {
            let field = |x: Point| a + m * x.coords;
            let p_i = interpolant(&polygon, field);
            // Interpolated values carry an error eps |p(x)|, amplified by |x| / h in the
            // gradient; the tolerance says so.
            let tolerance = 1e-14 * conditioning(&polygon) * (a.norm() + m.norm()).max(1.0);
            let g = projection.gradient(&p_i);
            assert!((g - m).norm() < tolerance, "{name}: {g} vs {m}");
            assert!((projection.strain(&p_i) - voigt_strain(&m)).norm() < tolerance);
            let centroid = vem_mesh::geometry::centroid(&polygon);
            for &x in polygon.iter().chain([centroid].iter()) {
                let error = (projection.evaluate(&p_i, x) - field(x)).norm();
                assert!(
                    error < 1e-12 * field(x).norm().max(1.0),
                    "{name}: {error:e}"
                );
            }
        }
    }
}

#[test]
fn on_triangles_the_vem_is_the_p1_element() {
    for (name, polygon) in polygons().into_iter().filter(|(_, p)| p.len() == 3) {
        for material in materials() {
            let p1 = LinearTriangle
                .stiffness(&polygon, &material)
                .unwrap()
                .total();
            for element in elements() {
                let local = element.stiffness(&polygon, &material).unwrap();
                let difference = (local.total() - &p1).norm() / p1.norm();
                assert!(difference < 1e-13, "{name}, {element:?}: {difference:e}");
                let s = local.stabilisation.norm() / local.consistency.norm();
                assert!(s < 1e-13, "{name}: stabilisation {s:e} on a triangle");
            }
            let vem = LowestOrderVem::default().projection(&polygon).unwrap();
            let fem = LinearTriangle.projection(&polygon).unwrap();
            let scale = fem.coefficients.norm();
            assert!((vem.coefficients - &fem.coefficients).norm() < 1e-13 * scale);
            assert!(
                (vem.reference - fem.reference).norm()
                    < 1e-13 * (1.0 + fem.reference.coords.norm())
            );
        }
        // A constant body force: both loads are |T| f / 3 per vertex.
        let f = |_: Point| Vector::new(1.5, -0.5);
        let vem = LowestOrderVem::default().body_load(&polygon, &f).unwrap();
        let fem = LinearTriangle.body_load(&polygon, &f).unwrap();
        assert!((&vem - &fem).norm() < 1e-14 * fem.norm(), "{name}");
    }
}

#[test]
fn body_load_is_the_cell_mean_against_the_projection_at_the_centroid() {
    // l_T^h(v) = int_T f_bar . Pi v: for a linear field p (Pi p = p) it equals
    // |T| f_bar . p(centroid), with f_bar the cell mean of f and the centroid from vem-mesh's
    // exact formula; for a linear f, f_bar = f(centroid).
    let linear_fields: [fn(Point) -> Vector; 3] = [
        |_| Vector::new(1.0, 0.0),
        |_| Vector::new(0.0, 1.0),
        |x| Vector::new(0.3 + 2.0 * x.x - x.y, -1.0 + 0.5 * x.x + 4.0 * x.y),
    ];
    let forces: [fn(Point) -> Vector; 2] = [
        |_| Vector::new(2.0, -1.0),
        |x| Vector::new(1.0 + x.x - 2.0 * x.y, 3.0 * x.x),
    ];
    for (name, polygon) in polygons() {
        let measure = area(&polygon);
        let centroid = vem_mesh::geometry::centroid(&polygon);
        for f in forces {
            let load = LowestOrderVem::default().body_load(&polygon, &f).unwrap();
            for field in linear_fields {
                let dofs = DVector::from_iterator(
                    2 * polygon.len(),
                    polygon.iter().flat_map(|&x| [field(x).x, field(x).y]),
                );
                let got = load.dot(&dofs);
                let expected = measure * f(centroid).dot(&field(centroid));
                let scale = measure * f(centroid).norm() * field(centroid).norm().max(1.0);
                assert!(
                    (got - expected).abs() < 1e-12 * scale.max(measure),
                    "{name}: {got} vs {expected}"
                );
            }
        }
    }
}

#[test]
fn p1_load_integrates_f_against_the_shape_functions() {
    // f = (x, 0) on the reference triangle: int x phi_i = (1/12, 1/24, 1/24) (phi_1 = x).
    let triangle = [p(0.0, 0.0), p(1.0, 0.0), p(0.0, 1.0)];
    let load = LinearTriangle
        .body_load(&triangle, &|x| Vector::new(x.x, 0.0))
        .unwrap();
    let expected = DVector::from_vec(vec![1.0 / 24.0, 0.0, 1.0 / 12.0, 0.0, 1.0 / 24.0, 0.0]);
    assert!((load - expected).norm() < 1e-16);
}

#[test]
fn stiffness_is_invariant_under_scaling_and_translation() {
    // In 2D a_T is dimensionless in the length: K_T of h T + c equals K_T of T.
    let material = ElasticityTensor::isotropic(2.0, 1.0).unwrap();
    for (name, polygon) in polygons() {
        for element in elements() {
            let k = element.stiffness(&polygon, &material).unwrap().total();
            let moved: Vec<Point> = polygon
                .iter()
                .map(|x| p(1e-3 * x.x + 50.0, 1e-3 * x.y - 20.0))
                .collect();
            let k_moved = element.stiffness(&moved, &material).unwrap().total();
            let difference = (&k - k_moved).norm() / k.norm();
            let tolerance = 1e-14 * conditioning(&polygon).max(conditioning(&moved));
            assert!(
                difference < tolerance,
                "{name}, {element:?}: {difference:e}"
            );
        }
    }
}

#[test]
fn dofi_dofi_constant_is_trace_of_c_over_8_on_regular_polygons() {
    // On a regular polygon the mean-gradient weights are proportional to x_k - x_bar, so Pi_dof
    // is the orthogonal projector onto P1 at the vertices and K_s = alpha (I - Pi_dof) has the
    // eigenvalues 0 (six times) and alpha (2n - 6 times).
    let material = ElasticityTensor::isotropic(2.0, 1.0).unwrap();
    let polygon = regular_polygon(7, p(0.5, 0.5), 2.0);
    for (scaling, alpha) in [
        (StabilisationScaling::TraceOfC, 9.0 / 8.0),
        (StabilisationScaling::ShearModulus, 5.0 / 8.0),
    ] {
        let element = LowestOrderVem::new(Stabilisation::dofi_dofi(scaling)).unwrap();
        let s = element
            .stiffness(&polygon, &material)
            .unwrap()
            .stabilisation;
        let mut eigenvalues: Vec<f64> = s.symmetric_eigenvalues().iter().copied().collect();
        eigenvalues.sort_by(f64::total_cmp);
        for (i, e) in eigenvalues.iter().enumerate() {
            let expected = if i < 6 { 0.0 } else { alpha };
            assert!((e - expected).abs() < 1e-13, "{scaling:?}: {eigenvalues:?}");
        }
    }
}

#[test]
fn d_recipe_weights_the_complement_by_the_consistency_diagonal() {
    // K_s = (I - Pi)^T diag(K_c) (I - Pi): on a P1-free vector e_i - Pi e_i the energy is
    // sum_j K_c,jj (e_i - Pi e_i)_j^2; compare with the projector built from the projection.
    let material = ElasticityTensor::isotropic(2.0, 1.0).unwrap();
    let element = LowestOrderVem::new(Stabilisation::DRecipe).unwrap();
    let polygon = polygons().swap_remove(3).1; // the L-shape
    let local = element.stiffness(&polygon, &material).unwrap();
    let projection = element.projection(&polygon).unwrap();
    let dofs = 2 * polygon.len();
    for i in 0..dofs {
        let mut e = DVector::zeros(dofs);
        e[i] = 1.0;
        // Pi e at the vertices.
        let pi_e = DVector::from_fn(dofs, |j, _| projection.evaluate(&e, polygon[j / 2])[j % 2]);
        let r = &e - pi_e;
        let expected: f64 = (0..dofs)
            .map(|j| local.consistency[(j, j)] * r[j] * r[j])
            .sum();
        let got = local.stabilisation[(i, i)];
        assert!(
            (got - expected).abs() < 1e-13 * expected,
            "{i}: {got} vs {expected}"
        );
    }
}

#[test]
fn invalid_input_is_an_error_not_garbage() {
    let material = ElasticityTensor::isotropic(2.0, 1.0).unwrap();
    let element = LowestOrderVem::default();
    let clockwise = [p(0.0, 0.0), p(0.0, 1.0), p(1.0, 1.0), p(1.0, 0.0)];
    for polygon in [&clockwise[..], &clockwise[..2]] {
        assert!(matches!(
            element.stiffness(polygon, &material),
            Err(SpaceError::DegeneratePolygon { .. })
        ));
        assert!(element.projection(polygon).is_err());
        assert!(element.body_load(polygon, &|_| Vector::zeros()).is_err());
    }
    let square = [p(0.0, 0.0), p(1.0, 0.0), p(1.0, 1.0), p(0.0, 1.0)];
    let err = element
        .body_load(&square, &|x| Vector::new(x.x, f64::NAN))
        .unwrap_err();
    assert!(matches!(err, SpaceError::NonFiniteLoad { .. }), "{err}");
    assert!(matches!(
        LinearTriangle.stiffness(&square, &material),
        Err(SpaceError::UnsupportedPolygon {
            element: "p1",
            vertices: 4
        })
    ));
    for scale in [0.0, -1.0, f64::NAN] {
        let bad = Stabilisation::DofiDofi {
            scaling: StabilisationScaling::TraceOfC,
            scale,
        };
        assert!(LowestOrderVem::new(bad).is_err());
        let literal = LowestOrderVem { stabilisation: bad };
        assert!(matches!(
            literal.stiffness(&square, &material),
            Err(SpaceError::InvalidStabilisation { .. })
        ));
    }
}

#[test]
fn edge_tractions_are_exact_for_quadratics_and_match_constant_stress() {
    // Quadratic traction on a slanted edge against a 6-point rule on the same edge (two
    // different exact rules agree) and against the closed form for a constant.
    let (a, b) = (p(0.5, -1.0), p(2.0, 1.0));
    let g = |x: Point| Vector::new(x.x * x.x - x.y, 2.0 + x.x * x.y);
    let two = edge_traction_load(a, b, &g, 2).unwrap();
    let six = edge_traction_load(a, b, &g, 6).unwrap();
    for (x, y) in two.iter().zip(six) {
        assert!((x - y).abs() < 1e-14 * y.abs().max(1.0));
    }
    let length = (b - a).norm();
    let constant = edge_traction_load(a, b, &|_| Vector::new(3.0, -1.0), 3).unwrap();
    let expected = [1.5 * length, -0.5 * length, 1.5 * length, -0.5 * length];
    for (x, y) in constant.iter().zip(expected) {
        assert!((x - y).abs() < 1e-14 * y.abs());
    }
}
