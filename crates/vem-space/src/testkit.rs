//! A test kit for element types (cargo feature `testkit`): a standard set of polygons and the
//! checks every [`ElementSpace`] for linear elasticity must pass, each returning a number so that
//! a test can state its own tolerance and print what it measured.
//!
//! The checks (spec section 3, docs/manufactured.md PT0), each against an expectation computed here
//! independently of the element:
//! - [`rigid_motion_residual`]: the rigid motions `(1, 0)`, `(0, 1)`, `(-y, x)` are in the kernel
//!   of `K_T`;
//! - [`consistency_error`]: consistency (3.1), `K_T p_I = int_dT sigma(p) nu . phi_i` for linear
//!   `p`, the right side by hand (half of `|e| sigma nu` to each end point of every edge);
//! - [`rank`]: the rank of `K_T` is `2n - 3` (stability: no spurious zero-energy mode);
//! - [`symmetry_error`]: `K_T` is symmetric;
//! - [`patch_test_error`]: the element-level patch test: the projection reproduces linear fields
//!   (`Pi p_I = p` at the vertices and the centroid) and the stabilisation does not see them.
//!
//! [`check_element`] runs them all on [`standard_polygons`] (those the element
//! [`supports`](ElementSpace::supports)) and [`standard_materials`].
//!
//! ```
//! use vem_space::testkit::{check_element, DEFAULT_TOLERANCE};
//! use vem_space::LowestOrderVem;
//! let checks = check_element(&LowestOrderVem::default())?;
//! assert_eq!(checks.len(), 2 * 7); // 7 polygons, 2 materials
//! for check in &checks {
//!     assert!(check.failures(DEFAULT_TOLERANCE).is_empty(), "{check:?}");
//! }
//! # Ok::<(), vem_space::testkit::TestkitError>(())
//! ```

use nalgebra::{DMatrix, DVector, Matrix2, Matrix3, Vector3};

use crate::{ElasticityTensor, ElementSpace, Point, SpaceError, Vector};

/// The relative tolerance the checks of the built-in elements meet on the standard polygons
/// (measured: at most about 1e-15 times a small factor; see `docs/elements.md`).
pub const DEFAULT_TOLERANCE: f64 = 1e-12;

/// A singular value at most this fraction of the largest counts as zero in [`rank`].
pub const RANK_TOLERANCE: f64 = 1e-10;

/// A polygon of the standard set, with the name a report prints.
#[derive(Debug, Clone, PartialEq)]
pub struct TestPolygon {
    /// What kind of polygon it is.
    pub name: &'static str,
    /// The vertices, counter-clockwise.
    pub vertices: Vec<Point>,
}

/// The standard polygons, one of each kind the meshes and interface insertion produce:
/// a triangle, a square, a regular hexagon, a non-convex chevron, a square with a hanging node,
/// a square with collinear vertices inserted on one edge, and a thin cell (aspect ratio 50).
pub fn standard_polygons() -> Vec<TestPolygon> {
    let p = Point::new;
    let hexagon = (0..6)
        .map(|k| {
            let t = std::f64::consts::PI * k as f64 / 3.0 + 0.1;
            p(0.3 + t.cos(), -0.2 + t.sin())
        })
        .collect();
    vec![
        TestPolygon {
            name: "triangle",
            vertices: vec![p(0.1, 0.2), p(1.3, -0.1), p(0.4, 0.9)],
        },
        TestPolygon {
            name: "square",
            vertices: vec![p(0.0, 0.0), p(1.0, 0.0), p(1.0, 1.0), p(0.0, 1.0)],
        },
        TestPolygon {
            name: "regular hexagon",
            vertices: hexagon,
        },
        TestPolygon {
            name: "chevron",
            vertices: vec![p(0.0, 0.0), p(1.0, 0.6), p(2.0, 0.0), p(1.0, 2.0)],
        },
        TestPolygon {
            name: "square with hanging node",
            vertices: vec![
                p(0.0, 0.0),
                p(1.0, 0.0),
                p(1.0, 0.5),
                p(1.0, 1.0),
                p(0.0, 1.0),
            ],
        },
        TestPolygon {
            name: "square with collinear inserted vertices",
            vertices: vec![
                p(0.0, 0.0),
                p(0.13, 0.0),
                p(0.4, 0.0),
                p(0.81, 0.0),
                p(1.0, 0.0),
                p(1.0, 1.0),
                p(0.0, 1.0),
            ],
        },
        TestPolygon {
            name: "thin cell",
            vertices: vec![p(0.0, 0.0), p(1.0, 0.0), p(1.0, 0.02), p(0.0, 0.02)],
        },
    ]
}

/// Two materials: isotropic (lambda = 2, mu = 1) and a fully anisotropic one (every Voigt
/// entry non-zero), so that no check passes because of a zero coupling.
pub fn standard_materials() -> Vec<ElasticityTensor> {
    let anisotropic = Matrix3::new(5.0, 1.5, 0.5, 1.5, 3.0, 0.3, 0.5, 0.3, 1.2);
    vec![
        ElasticityTensor::try_isotropic(2.0, 1.0).expect("lambda = 2, mu = 1 is admissible"),
        ElasticityTensor::try_from_voigt(anisotropic).expect("the matrix is positive definite"),
    ]
}

/// Linear fields `p(x) = a + M (x - x_0)` as `(a, M)`: a general one (with a skew part), a
/// uniaxial stretch, a pure shear and an infinitesimal rotation plus a translation.
pub fn linear_fields() -> Vec<(Vector, Matrix2<f64>)> {
    vec![
        (Vector::new(0.1, 0.2), Matrix2::new(0.2, 0.3, -0.1, 0.4)),
        (Vector::new(-1.0, 0.5), Matrix2::new(1.0, 0.0, 0.0, 0.0)),
        (Vector::new(0.0, 0.0), Matrix2::new(0.0, 1.0, 1.0, 0.0)),
        (Vector::new(2.0, -3.0), Matrix2::new(0.0, -1.0, 1.0, 0.0)),
    ]
}

/// The vertex values of `x -> f(x)`, interleaved by component (the element's DOF layout).
pub fn interpolant(polygon: &[Point], f: impl Fn(Point) -> Vector) -> DVector<f64> {
    DVector::from_fn(2 * polygon.len(), |i, _| f(polygon[i / 2])[i % 2])
}

/// The rigid motions `(1, 0)`, `(0, 1)` and `(-(y - y_0), x - x_0)` at the vertices, with
/// `x_0` the first vertex.
pub fn rigid_motions(polygon: &[Point]) -> [DVector<f64>; 3] {
    let origin = polygon.first().copied().unwrap_or_else(Point::origin);
    [
        interpolant(polygon, |_| Vector::new(1.0, 0.0)),
        interpolant(polygon, |_| Vector::new(0.0, 1.0)),
        interpolant(polygon, |x| Vector::new(origin.y - x.y, x.x - origin.x)),
    ]
}

/// The Voigt strain `[xx, yy, 2 xy]` of the gradient `m`.
pub fn voigt_strain(m: &Matrix2<f64>) -> Vector3<f64> {
    Vector3::new(m[(0, 0)], m[(1, 1)], m[(0, 1)] + m[(1, 0)])
}

/// `int_dT sigma nu . phi_i` for a constant stress `sigma` (Voigt `[xx, yy, xy]`) and the
/// functions `phi_i` linear on every edge: each edge gives half of `|e| sigma nu` to each of its
/// end points. Written by hand (edge normals from the coordinates), independent of any element.
pub fn boundary_load_of_constant_stress(polygon: &[Point], sigma: &Vector3<f64>) -> DVector<f64> {
    let s = Matrix2::new(sigma[0], sigma[2], sigma[2], sigma[1]);
    let n = polygon.len();
    let mut load = DVector::zeros(2 * n);
    for k in 0..n {
        let (a, b) = (polygon[k], polygon[(k + 1) % n]);
        // Counter-clockwise: the outward normal times the length is (dy, -dx).
        let half = s * Vector::new(b.y - a.y, a.x - b.x) * 0.5;
        for v in [k, (k + 1) % n] {
            load[2 * v] += half.x;
            load[2 * v + 1] += half.y;
        }
    }
    load
}

/// The number of singular values of `matrix` above [`RANK_TOLERANCE`] times the largest.
pub fn numerical_rank(matrix: &DMatrix<f64>) -> usize {
    let singular_values = matrix.singular_values();
    let largest = singular_values.max();
    singular_values
        .iter()
        .filter(|&&s| s > RANK_TOLERANCE * largest)
        .count()
}

/// The vertex mean, about which the linear fields of the checks are expanded (so that the
/// checks do not lose digits on a polygon far from the origin).
fn expansion_point(polygon: &[Point]) -> Point {
    vem_mesh::geometry::vertex_mean(polygon)
}

/// `max |K_T r| / (|K_T| |r|)` over the three rigid motions `r` (zero in exact arithmetic).
pub fn rigid_motion_residual(
    element: &dyn ElementSpace,
    polygon: &[Point],
    material: &ElasticityTensor,
) -> Result<f64, SpaceError> {
    let k = element.stiffness(polygon, material)?.total();
    let scale = k.norm();
    Ok(rigid_motions(polygon)
        .iter()
        .map(|r| (&k * r).norm() / (scale * r.norm()))
        .fold(0.0, f64::max))
}

/// Consistency (3.1): `max |K_T p_I - b(p)| / (|K_T| |p_I|)` over [`linear_fields`], with
/// `b(p)` = [`boundary_load_of_constant_stress`] of `sigma(p)` (zero in exact arithmetic).
pub fn consistency_error(
    element: &dyn ElementSpace,
    polygon: &[Point],
    material: &ElasticityTensor,
) -> Result<f64, SpaceError> {
    let k = element.stiffness(polygon, material)?.total();
    let origin = expansion_point(polygon);
    let mut worst: f64 = 0.0;
    for (a, m) in linear_fields() {
        let p_i = interpolant(polygon, |x| a + m * (x - origin));
        let sigma = material.stress(&voigt_strain(&m));
        let expected = boundary_load_of_constant_stress(polygon, &sigma);
        worst = worst.max((&k * &p_i - expected).norm() / (k.norm() * p_i.norm()));
    }
    Ok(worst)
}

/// The numerical rank of `K_T` ([`numerical_rank`]); `2n - 3` for a stable element.
pub fn rank(
    element: &dyn ElementSpace,
    polygon: &[Point],
    material: &ElasticityTensor,
) -> Result<usize, SpaceError> {
    Ok(numerical_rank(
        &element.stiffness(polygon, material)?.total(),
    ))
}

/// `max(|K - K^T|, |K_s - K_s^T|) / |K|` for `K = K_T` and its stabilisation part `K_s`.
pub fn symmetry_error(
    element: &dyn ElementSpace,
    polygon: &[Point],
    material: &ElasticityTensor,
) -> Result<f64, SpaceError> {
    let local = element.stiffness(polygon, material)?;
    let k = local.total();
    let s = &local.stabilisation;
    Ok((&k - k.transpose()).norm().max((s - s.transpose()).norm()) / k.norm())
}

/// The element-level patch test: over [`linear_fields`] `p`, the largest of
/// `|Pi p_I (x) - p(x)| / max(|p(x)|, 1)` at the vertices and the centroid and of
/// `|K_s p_I| / (|K_T| |p_I|)` (the stabilisation part does not see linear fields).
pub fn patch_test_error(
    element: &dyn ElementSpace,
    polygon: &[Point],
    material: &ElasticityTensor,
) -> Result<f64, SpaceError> {
    let local = element.stiffness(polygon, material)?;
    let k_norm = local.total().norm();
    let projection = element.projection(polygon)?;
    let origin = expansion_point(polygon);
    let centroid = vem_mesh::geometry::centroid(polygon);
    let mut worst: f64 = 0.0;
    for (a, m) in linear_fields() {
        let field = |x: Point| a + m * (x - origin);
        let p_i = interpolant(polygon, field);
        for &x in polygon.iter().chain([centroid].iter()) {
            let error = (projection.evaluate(&p_i, x) - field(x)).norm() / field(x).norm().max(1.0);
            worst = worst.max(error);
        }
        worst = worst.max((&local.stabilisation * &p_i).norm() / (k_norm * p_i.norm()));
    }
    Ok(worst)
}

/// What the checks measured on one polygon and material.
#[derive(Debug, Clone, PartialEq)]
pub struct ElementCheck {
    /// The polygon's name.
    pub polygon: String,
    /// Its number of vertices `n`.
    pub n_vertices: usize,
    /// [`rigid_motion_residual`].
    pub rigid_motion_residual: f64,
    /// [`consistency_error`].
    pub consistency_error: f64,
    /// [`rank`].
    pub rank: usize,
    /// [`symmetry_error`].
    pub symmetry_error: f64,
    /// [`patch_test_error`].
    pub patch_test_error: f64,
}

impl ElementCheck {
    /// Runs every check of the kit on `polygon` (named `name`) with `material`.
    pub fn run(
        element: &dyn ElementSpace,
        name: &str,
        polygon: &[Point],
        material: &ElasticityTensor,
    ) -> Result<Self, TestkitError> {
        let wrap = |source| TestkitError {
            element: element.name().to_string(),
            polygon: name.to_string(),
            source,
        };
        Ok(Self {
            polygon: name.to_string(),
            n_vertices: polygon.len(),
            rigid_motion_residual: rigid_motion_residual(element, polygon, material)
                .map_err(wrap)?,
            consistency_error: consistency_error(element, polygon, material).map_err(wrap)?,
            rank: rank(element, polygon, material).map_err(wrap)?,
            symmetry_error: symmetry_error(element, polygon, material).map_err(wrap)?,
            patch_test_error: patch_test_error(element, polygon, material).map_err(wrap)?,
        })
    }

    /// The rank of a stable element, `2n - 3`.
    pub fn expected_rank(&self) -> usize {
        (2 * self.n_vertices).saturating_sub(3)
    }

    /// The largest of the four relative errors (rigid motions, consistency, symmetry, patch
    /// test).
    pub fn worst_error(&self) -> f64 {
        [
            self.rigid_motion_residual,
            self.consistency_error,
            self.symmetry_error,
            self.patch_test_error,
        ]
        .into_iter()
        .fold(0.0, f64::max)
    }

    /// The checks that fail with the relative tolerance `tolerance`, one line each (empty when
    /// the element passes).
    pub fn failures(&self, tolerance: f64) -> Vec<String> {
        let mut failures = Vec::new();
        for (what, value) in [
            ("rigid-motion residual", self.rigid_motion_residual),
            ("consistency error", self.consistency_error),
            ("symmetry error", self.symmetry_error),
            ("patch-test error", self.patch_test_error),
        ] {
            if value.is_nan() || value > tolerance {
                failures.push(format!(
                    "{}: {what} {value:e} > {tolerance:e}",
                    self.polygon
                ));
            }
        }
        if self.rank != self.expected_rank() {
            failures.push(format!(
                "{}: rank {} instead of 2n - 3 = {}",
                self.polygon,
                self.rank,
                self.expected_rank()
            ));
        }
        failures
    }
}

/// A check could not run because the element failed on a polygon of the kit.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("element '{element}' failed on the test polygon '{polygon}'")]
pub struct TestkitError {
    /// The element's name.
    pub element: String,
    /// The polygon's name.
    pub polygon: String,
    /// What the element reported.
    #[source]
    pub source: SpaceError,
}

/// Runs [`ElementCheck::run`] on every polygon of [`standard_polygons`] that `element`
/// supports, with every material of [`standard_materials`] (polygon-major order).
pub fn check_element(element: &dyn ElementSpace) -> Result<Vec<ElementCheck>, TestkitError> {
    let materials = standard_materials();
    let mut checks = Vec::new();
    for polygon in standard_polygons() {
        if !element.supports(polygon.vertices.len()) {
            continue;
        }
        for material in &materials {
            checks.push(ElementCheck::run(
                element,
                polygon.name,
                &polygon.vertices,
                material,
            )?);
        }
    }
    Ok(checks)
}
