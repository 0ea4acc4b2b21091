//! Element-level checks of the lowest-order VEM (docs/manufactured.md, PT0 companions): rigid-motion
//! kernel, rank, consistency (3.1) against an independent boundary integration, vanishing
//! stabilisation on P1, symmetry, exact projection of linear fields, energy of linear fields,
//! equality with the independent P1 triangle, and the load terms.

use std::sync::Arc;

use nalgebra::{DMatrix, DVector};
use vem_mesh::generators::{structured_quads, structured_triangles, Rectangle};
use vem_space::testkit::{
    self, check_element, linear_fields, standard_materials, voigt_strain, ElementCheck,
};
use vem_space::{
    edge_traction_load, BBar, DRecipe, DofiDofi, ElasticityTensor, ElementSpace, LinearTriangle,
    LowestOrderVem, Point, PolygonGeometry, SpaceError, Stabilisation, StabilisationScaling,
    Vector,
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
    standard_materials()
}

fn elements() -> Vec<LowestOrderVem> {
    let stabilisations: [Arc<dyn Stabilisation>; 5] = [
        Arc::new(DofiDofi::default()),
        Arc::new(DofiDofi::new(StabilisationScaling::ShearModulus)),
        Arc::new(DofiDofi::try_new(StabilisationScaling::TraceOfC, 2.0).unwrap()),
        Arc::new(DRecipe),
        Arc::new(BBar),
    ];
    stabilisations
        .into_iter()
        .map(|s| LowestOrderVem::try_new(s).unwrap())
        .collect()
}

/// Nodal interpolant of x -> f(x), DOFs interleaved by component.
fn interpolant(polygon: &[Point], f: impl Fn(Point) -> Vector) -> DVector<f64> {
    testkit::interpolant(polygon, f)
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
fn the_element_test_kit_passes_on_its_polygons_and_on_these() {
    // The kit's checks (rigid motions in the kernel, consistency (3.1) against a boundary
    // integration by hand, rank 2n - 3, symmetry, element patch test) on the kit's standard
    // polygons and on this file's (slivers, L-shape, far-away cells, mesh cells), for every
    // stabilisation and the P1 triangle.
    let mut worst: f64 = 0.0;
    let p1: Arc<dyn ElementSpace> = Arc::new(LinearTriangle);
    let all: Vec<Arc<dyn ElementSpace>> = elements()
        .into_iter()
        .map(|e| Arc::new(e) as Arc<dyn ElementSpace>)
        .chain([p1])
        .collect();
    for element in &all {
        for check in check_element(&**element).unwrap() {
            assert!(
                check.failures(testkit::DEFAULT_TOLERANCE).is_empty(),
                "{}: {check:?}",
                element.name()
            );
            worst = worst.max(check.worst_error());
        }
        for (name, polygon) in polygons() {
            if !element.supports(polygon.len()) {
                continue;
            }
            // Vertex data carry an absolute error eps |x|, relative to h_T: eps |x| / h_T.
            let tolerance = testkit::DEFAULT_TOLERANCE * conditioning(&polygon);
            for material in materials() {
                let check = ElementCheck::run(&**element, &name, &polygon, &material).unwrap();
                let failures = check.failures(tolerance);
                assert!(failures.is_empty(), "{}: {failures:?}", element.name());
                worst = worst.max(check.worst_error() / conditioning(&polygon));
            }
        }
    }
    println!("worst relative error of the kit's checks (per unit conditioning) = {worst:e}");
}

#[test]
fn energy_of_linear_fields_is_exact() {
    // p_I^T K p_I = |T| eps(p) : C eps(p), with |T| by the shoelace formula.
    for (name, polygon) in polygons() {
        for material in materials() {
            for element in elements() {
                let k = element.stiffness(&polygon, &material).unwrap().total();
                for (a, m) in linear_fields() {
                    let p_i = interpolant(&polygon, |x| a + m * x.coords);
                    let strain = voigt_strain(&m);
                    let energy = p_i.dot(&(&k * &p_i));
                    let exact = area(&polygon) * strain.dot(&material.stress(&strain));
                    let scale = k.norm() * p_i.norm_squared();
                    assert!(
                        (energy - exact).abs() < 1e-12 * scale,
                        "{name}: energy {energy} vs {exact}"
                    );
                }
            }
        }
    }
}

#[test]
fn polygon_geometry_matches_independent_formulas() {
    // Area by the shoelace formula about the first vertex, diameter by vem-mesh, edges and
    // normals from the coordinates, sum_k w_k (x) x_k = I (mean gradient of x).
    for (name, polygon) in polygons() {
        let g = PolygonGeometry::try_new(&polygon).unwrap();
        let n = polygon.len();
        let tolerance = 1e-14 * conditioning(&polygon);
        assert!(
            (g.area() - area(&polygon)).abs() < tolerance * g.area(),
            "{name}"
        );
        let h = vem_mesh::geometry::diameter(&polygon);
        assert!((g.diameter() - h).abs() < tolerance * h, "{name}");
        let mut identity = nalgebra::Matrix2::zeros();
        for k in 0..n {
            let edge = polygon[(k + 1) % n] - polygon[k];
            assert!(
                (g.edge_lengths()[k] - edge.norm()).abs() < tolerance * h,
                "{name}"
            );
            assert!(g.normals()[k].dot(&edge).abs() < tolerance * h, "{name}");
            assert!((g.normals()[k].norm() - 1.0).abs() < 1e-15, "{name}");
            // Outward: the normal points to the right of the counter-clockwise edge.
            assert!(g.normals()[k].perp(&edge) > 0.0, "{name}");
            identity += g.relative_vertices()[k] * g.gradient_weights()[k].transpose();
        }
        assert!(
            (identity - nalgebra::Matrix2::identity()).norm() < tolerance,
            "{name}"
        );
        let centroid = vem_mesh::geometry::centroid(&polygon);
        assert!(
            (g.centroid() - centroid).norm() <= 1e-15 * centroid.coords.norm(),
            "{name}"
        );
    }
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
    let material = ElasticityTensor::try_isotropic(2.0, 1.0).unwrap();
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
    let material = ElasticityTensor::try_isotropic(2.0, 1.0).unwrap();
    let polygon = regular_polygon(7, p(0.5, 0.5), 2.0);
    for (scaling, alpha) in [
        (StabilisationScaling::TraceOfC, 9.0 / 8.0),
        (StabilisationScaling::ShearModulus, 5.0 / 8.0),
    ] {
        let element = LowestOrderVem::try_new(Arc::new(DofiDofi::new(scaling))).unwrap();
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
    let material = ElasticityTensor::try_isotropic(2.0, 1.0).unwrap();
    let element = LowestOrderVem::try_new(Arc::new(DRecipe)).unwrap();
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
    let material = ElasticityTensor::try_isotropic(2.0, 1.0).unwrap();
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
        Err(SpaceError::UnsupportedPolygon { ref element, vertices: 4 }) if element == "p1"
    ));
    for scale in [0.0, -1.0, f64::NAN] {
        assert!(matches!(
            DofiDofi::try_new(StabilisationScaling::TraceOfC, scale),
            Err(SpaceError::InvalidStabilisation { .. })
        ));
    }
}

/// A stabilisation with public settings and a bug that a check must catch: it returns a
/// diagonal with a zero entry or of the wrong length.
#[derive(Debug)]
struct Faulty {
    alpha: f64,
    short: bool,
}

impl Stabilisation for Faulty {
    fn name(&self) -> String {
        "faulty".into()
    }

    fn validate(&self) -> Result<(), SpaceError> {
        if self.alpha.is_nan() {
            return Err(SpaceError::InvalidStabilisation {
                stabilisation: self.name(),
                reason: "alpha is NaN".into(),
            });
        }
        Ok(())
    }

    fn diagonal(
        &self,
        _geometry: &PolygonGeometry,
        _material: &ElasticityTensor,
        consistency: &DMatrix<f64>,
    ) -> Result<DVector<f64>, SpaceError> {
        let n = consistency.nrows() - usize::from(self.short);
        Ok(DVector::from_element(n, self.alpha))
    }
}

#[test]
fn a_stabilisation_is_validated_and_its_diagonal_checked() {
    let material = ElasticityTensor::try_isotropic(2.0, 1.0).unwrap();
    let square = [p(0.0, 0.0), p(1.0, 0.0), p(1.0, 1.0), p(0.0, 1.0)];
    let nan = Faulty {
        alpha: f64::NAN,
        short: false,
    };
    assert!(LowestOrderVem::try_new(Arc::new(nan)).is_err());
    for (alpha, short) in [(0.0, false), (1.0, true), (f64::INFINITY, false)] {
        let element = LowestOrderVem::try_new(Arc::new(Faulty { alpha, short })).unwrap();
        assert_eq!(element.name(), "vem1-faulty");
        let err = element.stiffness(&square, &material).unwrap_err();
        assert!(
            matches!(&err, SpaceError::InvalidStabilisation { stabilisation, .. } if stabilisation == "faulty"),
            "{err}"
        );
    }
}

/// `S = (|T| / h_T^2) trace(C) I`: a stabilisation scaled by the shape of the polygon, written
/// outside the crate; the element built on it passes the test kit without any change to
/// `vem-space`.
#[derive(Debug)]
struct AreaWeighted;

impl Stabilisation for AreaWeighted {
    fn name(&self) -> String {
        "area-weighted".into()
    }

    fn diagonal(
        &self,
        geometry: &PolygonGeometry,
        material: &ElasticityTensor,
        consistency: &DMatrix<f64>,
    ) -> Result<DVector<f64>, SpaceError> {
        let shape = geometry.area() / geometry.diameter().powi(2);
        Ok(DVector::from_element(
            consistency.nrows(),
            shape * material.trace(),
        ))
    }
}

#[test]
fn a_user_stabilisation_plugs_in_and_passes_the_kit() {
    let element = LowestOrderVem::try_new(Arc::new(AreaWeighted)).unwrap();
    assert_eq!(element.name(), "vem1-area-weighted");
    let checks = check_element(&element).unwrap();
    assert_eq!(checks.len(), 14);
    for check in &checks {
        assert!(
            check.failures(testkit::DEFAULT_TOLERANCE).is_empty(),
            "{check:?}"
        );
    }
    // On the unit square |T| / h^2 = 1/2 and Pi_dof is an orthogonal projector of rank 6: K_s
    // has the eigenvalue trace(C)/2 = 4.5 twice (lambda = 2, mu = 1), zero six times.
    let material = ElasticityTensor::try_isotropic(2.0, 1.0).unwrap();
    let square = [p(0.0, 0.0), p(1.0, 0.0), p(1.0, 1.0), p(0.0, 1.0)];
    let s = element.stiffness(&square, &material).unwrap().stabilisation;
    let mut eigenvalues: Vec<f64> = s.symmetric_eigenvalues().iter().copied().collect();
    eigenvalues.sort_by(f64::total_cmp);
    for (i, e) in eigenvalues.iter().enumerate() {
        let expected = if i < 6 { 0.0 } else { 4.5 };
        assert!((e - expected).abs() < 1e-13, "{eigenvalues:?}");
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
