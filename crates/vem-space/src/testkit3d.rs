//! The element test kit in three dimensions (cargo feature `testkit`): a standard set of
//! polyhedra and the checks every [`PolyhedralElement`] for linear elasticity must pass, each
//! returning a number (the counterpart of [`crate::testkit`]).
//!
//! The checks, each against an expectation computed here independently of the element:
//! - [`rigid_motion_residual`]: the six rigid motions (three translations, three rotations)
//!   are in the kernel of `K_E`;
//! - [`consistency_error`]: `K_E p_I = int_dE sigma(p) n . phi_a` for linear `p`, the right
//!   side by hand on the fan triangles of every face (a third of `sigma a_T` to each of the two
//!   vertices of the triangle, a third spread evenly over the face's vertices through the fan
//!   centre);
//! - [`rank`]: the rank of `K_E` is `3n - 6`;
//! - [`symmetry_error`]: `K_E` is symmetric;
//! - [`linear_energy_error`]: the energy of a linear field is `|E| eps : C eps`, with `|E|`
//!   from the closed form of each standard polyhedron;
//! - [`patch_test_error`]: the projection reproduces linear fields at the vertices and the
//!   centroid, and the stabilisation does not see them.
//!
//! [`check_element`] runs them all on [`standard_polyhedra`] (those the element supports) and
//! [`standard_materials`].
//!
//! ```
//! use vem_space::testkit3d::{check_element, DEFAULT_TOLERANCE};
//! use vem_space::PolyhedralVem;
//! let checks = check_element(&PolyhedralVem::default())?;
//! assert_eq!(checks.len(), 2 * 10); // 10 polyhedra, 2 materials
//! for check in &checks {
//!     assert!(check.failures(DEFAULT_TOLERANCE).is_empty(), "{check:?}");
//! }
//! # Ok::<(), vem_space::testkit3d::TestkitError>(())
//! ```

use nalgebra::{DMatrix, DVector, Matrix3, SMatrix, SVector};
use vem_mesh::polyhedral::geometry::{self, Polyhedron};
use vem_mesh::{Point3, Vector3};

use crate::{ElasticityTensor, PolyhedralElement, SpaceError};

/// The relative tolerance the checks of the built-in elements meet on the standard polyhedra.
pub const DEFAULT_TOLERANCE: f64 = 1e-12;

/// A singular value at most this fraction of the largest counts as zero in [`rank`].
pub const RANK_TOLERANCE: f64 = 1e-10;

/// A polyhedron of the standard set, with its name and its volume computed by hand (closed
/// forms; the divergence theorem for the warped hexahedron).
#[derive(Debug, Clone, PartialEq)]
pub struct TestPolyhedron {
    /// What kind of polyhedron it is.
    pub name: &'static str,
    /// The polyhedron (faces oriented outward).
    pub polyhedron: Polyhedron,
    /// Its volume, from a closed form (base times height, ...).
    pub volume: f64,
}

/// The faces of the convex hull of `points` with the outward directions `normals`: for each,
/// the points farthest along it (to 1e-12), ordered counter-clockwise seen from outside.
fn convex_faces(points: &[Point3], normals: &[Vector3]) -> Vec<Vec<usize>> {
    normals
        .iter()
        .map(|n| {
            let top = points
                .iter()
                .map(|p| p.coords.dot(n))
                .fold(f64::NEG_INFINITY, f64::max);
            let mut face: Vec<usize> = (0..points.len())
                .filter(|&k| (points[k].coords.dot(n) - top).abs() < 1e-12)
                .collect();
            let centre = face
                .iter()
                .fold(Vector3::zeros(), |s, &k| s + points[k].coords)
                / face.len() as f64;
            let u = (points[face[0]].coords - centre).normalize();
            let v = n.normalize().cross(&u);
            let angle = |k: usize| {
                let d = points[k].coords - centre;
                d.dot(&v).atan2(d.dot(&u))
            };
            face.sort_by(|&a, &b| angle(a).total_cmp(&angle(b)));
            face
        })
        .collect()
}

/// The box `[0, a] x [0, b] x [0, c]` shifted by `origin`, corner `k` at
/// `(k & 1, k >> 1 & 1, k >> 2)` times the sides.
fn box_points(origin: Vector3, a: f64, b: f64, c: f64) -> Vec<Point3> {
    (0..8)
        .map(|k| {
            Point3::from(
                origin
                    + Vector3::new(
                        a * (k & 1) as f64,
                        b * (k >> 1 & 1) as f64,
                        c * (k >> 2) as f64,
                    ),
            )
        })
        .collect()
}

/// The six outward faces of a box of [`box_points`].
fn box_faces() -> Vec<Vec<usize>> {
    vec![
        vec![0, 4, 6, 2],
        vec![1, 3, 7, 5],
        vec![0, 1, 5, 4],
        vec![2, 6, 7, 3],
        vec![0, 2, 3, 1],
        vec![4, 5, 7, 6],
    ]
}

/// The prism over the counter-clockwise polygon `base` (in the plane z = 0) of height `height`.
fn prism(base: &[(f64, f64)], height: f64) -> Polyhedron {
    let m = base.len();
    let mut points: Vec<Point3> = base.iter().map(|&(x, y)| Point3::new(x, y, 0.0)).collect();
    points.extend(base.iter().map(|&(x, y)| Point3::new(x, y, height)));
    let mut faces = vec![(0..m).rev().collect::<Vec<_>>(), (m..2 * m).collect()];
    for k in 0..m {
        faces.push(vec![k, (k + 1) % m, m + (k + 1) % m, m + k]);
    }
    Polyhedron::new(points, &faces)
}

/// The standard polyhedra, one of each kind the meshes produce: a general tetrahedron, a cube,
/// a hexahedron with warped faces (its volume by the divergence theorem on its fan triangles), a triangular prism, a pyramid, a non-convex L-shaped prism,
/// a cube with one face split in four (octree hanging nodes), a thin plate (aspect ratio 50),
/// a truncated octahedron (a Voronoi-like cell, 14 faces) and a small cube far from the
/// origin.
pub fn standard_polyhedra() -> Vec<TestPolyhedron> {
    let mut set = Vec::new();
    // A general tetrahedron: volume det(b - a, c - a, d - a)/6 by hand.
    let tet = [
        Point3::new(0.1, 0.2, 0.0),
        Point3::new(1.3, -0.1, 0.2),
        Point3::new(0.4, 0.9, -0.1),
        Point3::new(0.3, 0.4, 1.1),
    ];
    let tet_volume = Matrix3::from_columns(&[tet[1] - tet[0], tet[2] - tet[0], tet[3] - tet[0]])
        .determinant()
        / 6.0;
    set.push(TestPolyhedron {
        name: "tetrahedron",
        polyhedron: Polyhedron::new(
            tet.to_vec(),
            &[vec![0, 2, 1], vec![0, 1, 3], vec![0, 3, 2], vec![1, 2, 3]],
        ),
        volume: tet_volume,
    });
    set.push(TestPolyhedron {
        name: "cube",
        polyhedron: Polyhedron::new(box_points(Vector3::zeros(), 1.0, 1.0, 1.0), &box_faces()),
        volume: 1.0,
    });
    // The unit cube with its top corners moved in x and y: the side faces warp (each is the
    // fan of four triangles about its vertex mean), the bottom and top stay planar.
    let mut warped = box_points(Vector3::zeros(), 1.0, 1.0, 1.0);
    for (k, d) in [
        (4, (0.1, -0.05)),
        (5, (0.0, 0.1)),
        (6, (-0.1, 0.05)),
        (7, (0.05, 0.0)),
    ] {
        warped[k].x += d.0;
        warped[k].y += d.1;
    }
    let warped = Polyhedron::new(warped, &box_faces());
    set.push(TestPolyhedron {
        name: "hexahedron with warped faces",
        volume: divergence_volume(&warped),
        polyhedron: warped,
    });
    set.push(TestPolyhedron {
        name: "triangular prism",
        polyhedron: prism(&[(0.0, 0.0), (1.2, 0.1), (0.3, 0.8)], 0.7),
        volume: 0.5 * (1.2 * 0.8 - 0.3 * 0.1) * 0.7,
    });
    // A square pyramid with its apex off-centre: volume base x height / 3.
    let mut pyramid = box_points(Vector3::zeros(), 1.0, 1.0, 1.0)[..4].to_vec();
    pyramid.push(Point3::new(0.3, 0.6, 0.8));
    set.push(TestPolyhedron {
        name: "pyramid",
        polyhedron: Polyhedron::new(
            pyramid,
            &[
                vec![0, 2, 3, 1],
                vec![0, 1, 4],
                vec![1, 3, 4],
                vec![3, 2, 4],
                vec![2, 0, 4],
            ],
        ),
        volume: 0.8 / 3.0,
    });
    set.push(TestPolyhedron {
        name: "L-shaped prism",
        polyhedron: prism(
            &[
                (0.0, 0.0),
                (2.0, 0.0),
                (2.0, 1.0),
                (1.0, 1.0),
                (1.0, 2.0),
                (0.0, 2.0),
            ],
            0.5,
        ),
        volume: 3.0 * 0.5,
    });
    // The unit cube whose face x = 1 is split in four squares (an octree neighbour): corners
    // 0..8 as a box, then the edge midpoints 8..12 and the centre 12 of the face x = 1.
    let mut refined = box_points(Vector3::zeros(), 1.0, 1.0, 1.0);
    for (y, z) in [(0.5, 0.0), (1.0, 0.5), (0.5, 1.0), (0.0, 0.5), (0.5, 0.5)] {
        refined.push(Point3::new(1.0, y, z));
    }
    // Face x = 1, outward +x: loops counter-clockwise seen from +x (y right, z up).
    let mut faces = box_faces();
    faces.remove(1);
    // The four sides touching x = 1 get the midpoints of their edges on it.
    faces[1] = vec![0, 1, 11, 5, 4]; // y = 0 (was [0, 1, 5, 4])
    faces[2] = vec![2, 6, 7, 9, 3]; // y = 1
    faces[3] = vec![0, 2, 3, 8, 1]; // z = 0
    faces[4] = vec![4, 5, 10, 7, 6]; // z = 1
    faces.extend([
        vec![1, 8, 12, 11],
        vec![8, 3, 9, 12],
        vec![12, 9, 7, 10],
        vec![11, 12, 10, 5],
    ]);
    set.push(TestPolyhedron {
        name: "cube with a split face",
        polyhedron: Polyhedron::new(refined, &faces),
        volume: 1.0,
    });
    set.push(TestPolyhedron {
        name: "thin plate",
        polyhedron: Polyhedron::new(box_points(Vector3::zeros(), 1.0, 1.0, 0.02), &box_faces()),
        volume: 0.02,
    });
    // Truncated octahedron: the permutations of (0, +-1, +-2), edge sqrt 2, volume 8 sqrt 2
    // (sqrt 2)^3 = 32; faces: 6 squares (normals +-e_i), 8 hexagons (normals (+-1, +-1, +-1)).
    let mut points = Vec::new();
    for perm in [
        [0, 1, 2],
        [0, 2, 1],
        [1, 0, 2],
        [1, 2, 0],
        [2, 0, 1],
        [2, 1, 0],
    ] {
        for s1 in [-1.0, 1.0] {
            for s2 in [-1.0, 1.0] {
                let values = [0.0, s1, 2.0 * s2];
                let mut p = [0.0; 3];
                for (i, &k) in perm.iter().enumerate() {
                    p[k] = values[i];
                }
                points.push(Point3::new(p[0], p[1], p[2]));
            }
        }
    }
    let mut normals = Vec::new();
    for i in 0..3 {
        for s in [-1.0, 1.0] {
            let mut n = Vector3::zeros();
            n[i] = s;
            normals.push(n);
        }
    }
    for k in 0..8 {
        let s = |bit: usize| if k >> bit & 1 == 1 { 1.0 } else { -1.0 };
        normals.push(Vector3::new(s(0), s(1), s(2)));
    }
    let faces = convex_faces(&points, &normals);
    set.push(TestPolyhedron {
        name: "truncated octahedron",
        polyhedron: Polyhedron::new(points, &faces),
        volume: 32.0,
    });
    set.push(TestPolyhedron {
        name: "small cube far from the origin",
        polyhedron: Polyhedron::new(
            box_points(
                Vector3::new(1024.0, -2048.0, 512.0),
                1.0 / 64.0,
                1.0 / 64.0,
                1.0 / 64.0,
            ),
            &box_faces(),
        ),
        volume: 1.0 / 262_144.0,
    });
    set
}

/// The volume of the fan-defined body of `polyhedron` by the divergence theorem with the field
/// `(0, 0, z)`: `|E| = sum over fan triangles T of zbar_T (a_T)_z` (exact: `z` is linear on each
/// triangle), independent of the tetrahedra the mesh layer sums.
fn divergence_volume(polyhedron: &Polyhedron) -> f64 {
    let points = polyhedron.points();
    let mut volume = 0.0;
    for face in polyhedron.faces() {
        let m = face.len();
        let centre = face
            .iter()
            .fold(Vector3::zeros(), |s, &v| s + points[v].coords)
            / m as f64;
        for k in 0..m {
            let (a, b) = (points[face[k]].coords, points[face[(k + 1) % m]].coords);
            let area_z = 0.5 * (a - centre).cross(&(b - centre)).z;
            volume += (a.z + b.z + centre.z) / 3.0 * area_z;
        }
    }
    volume
}

/// Two materials: isotropic (lambda = 2, mu = 1) and a fully anisotropic one (every Voigt
/// entry non-zero).
pub fn standard_materials() -> Vec<ElasticityTensor<3>> {
    let mut isotropic = DMatrix::zeros(6, 6);
    for i in 0..3 {
        for j in 0..3 {
            isotropic[(i, j)] = 2.0 + if i == j { 2.0 } else { 0.0 };
        }
        isotropic[(i + 3, i + 3)] = 1.0;
    }
    let a = DMatrix::from_fn(6, 6, |i, j| 0.2 + 0.1 * ((3 * i + 5 * j) % 7) as f64);
    let anisotropic = a.transpose() * &a + DMatrix::identity(6, 6) * 2.0;
    vec![
        ElasticityTensor::<3>::try_from_voigt_matrix(&isotropic)
            .expect("lambda = 2, mu = 1 is admissible"),
        ElasticityTensor::<3>::try_from_voigt_matrix(&anisotropic)
            .expect("A^T A + 2 I is positive definite"),
    ]
}

/// Linear fields `p(x) = a + M (x - x_0)` as `(a, M)`: a general one, a uniaxial stretch, a pure
/// shear, and an infinitesimal rotation plus a translation.
pub fn linear_fields() -> Vec<(Vector3, Matrix3<f64>)> {
    vec![
        (
            Vector3::new(0.1, 0.2, -0.3),
            Matrix3::new(0.2, 0.3, -0.1, 0.4, -0.2, 0.5, 0.1, 0.6, 0.3),
        ),
        (
            Vector3::new(-1.0, 0.5, 0.0),
            Matrix3::new(1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
        ),
        (
            Vector3::zeros(),
            Matrix3::new(0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0),
        ),
        (
            Vector3::new(2.0, -3.0, 1.0),
            Matrix3::new(0.0, -1.0, 0.5, 1.0, 0.0, -2.0, -0.5, 2.0, 0.0),
        ),
    ]
}

/// The vertex values of `x -> f(x)`, interleaved by component (the element's DOF layout).
pub fn interpolant(points: &[Point3], f: impl Fn(Point3) -> Vector3) -> DVector<f64> {
    DVector::from_fn(3 * points.len(), |i, _| f(points[i / 3])[i % 3])
}

/// The six rigid motions at the vertices: the translations `e_x`, `e_y`, `e_z` and the
/// rotations `e_i x (x - x_0)`, with `x_0` the first vertex.
pub fn rigid_motions(points: &[Point3]) -> Vec<DVector<f64>> {
    let origin = points.first().copied().unwrap_or_else(Point3::origin);
    let mut motions = Vec::new();
    for i in 0..3 {
        let e = Vector3::ith(i, 1.0);
        motions.push(interpolant(points, |_| e));
    }
    for i in 0..3 {
        let e = Vector3::ith(i, 1.0);
        motions.push(interpolant(points, |x| e.cross(&(x - origin))));
    }
    motions
}

/// The Voigt strain `[xx, yy, zz, 2 yz, 2 xz, 2 xy]` of the gradient `m`.
pub fn voigt_strain(m: &Matrix3<f64>) -> SVector<f64, 6> {
    SVector::<f64, 6>::from_column_slice(&[
        m[(0, 0)],
        m[(1, 1)],
        m[(2, 2)],
        m[(1, 2)] + m[(2, 1)],
        m[(0, 2)] + m[(2, 0)],
        m[(0, 1)] + m[(1, 0)],
    ])
}

/// The stress tensor `C eps` of the gradient `m`, from the Voigt matrix.
fn stress_of(material: &ElasticityTensor<3>, m: &Matrix3<f64>) -> Matrix3<f64> {
    let voigt = material.voigt_matrix();
    let c = SMatrix::<f64, 6, 6>::from_fn(|i, j| voigt[(i, j)]);
    let s = c * voigt_strain(m);
    Matrix3::new(s[0], s[5], s[4], s[5], s[1], s[3], s[4], s[3], s[2])
}

/// `int_dE sigma n . phi_a` for a constant stress `sigma` and the fan traces `phi_a`: on each fan
/// triangle `T = (x_k, x_{k+1}, xbar_F)` of vector area `a_T`, a third of `sigma a_T` to `x_k`
/// and to `x_{k+1}`, and a third spread evenly over the face's vertices (the fan centre carries
/// their mean). Written by hand, independent of the element.
pub fn boundary_load_of_constant_stress(
    polyhedron: &Polyhedron,
    sigma: &Matrix3<f64>,
) -> DVector<f64> {
    let points = polyhedron.points();
    let mut load = DVector::zeros(3 * points.len());
    for face in polyhedron.faces() {
        let m = face.len();
        let centre = face
            .iter()
            .fold(Vector3::zeros(), |s, &v| s + points[v].coords)
            / m as f64;
        for k in 0..m {
            let (a, b) = (
                points[face[k]].coords - centre,
                points[face[(k + 1) % m]].coords - centre,
            );
            let third = sigma * (0.5 * a.cross(&b)) / 3.0;
            for c in 0..3 {
                load[3 * face[k] + c] += third[c];
                load[3 * face[(k + 1) % m] + c] += third[c];
                for &v in face {
                    load[3 * v + c] += third[c] / m as f64;
                }
            }
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

/// `max |K_E r| / (|K_E| |r|)` over the six rigid motions `r`.
pub fn rigid_motion_residual(
    element: &dyn PolyhedralElement,
    polyhedron: &Polyhedron,
    material: &ElasticityTensor<3>,
) -> Result<f64, SpaceError> {
    let k = element.stiffness(polyhedron, material)?.total();
    let scale = k.norm();
    Ok(rigid_motions(polyhedron.points())
        .iter()
        .map(|r| (&k * r).norm() / (scale * r.norm()))
        .fold(0.0, f64::max))
}

/// `max |K_E p_I - b(p)| / (|K_E| |p_I|)` over [`linear_fields`], `b(p)` =
/// [`boundary_load_of_constant_stress`] of `sigma(p)`.
pub fn consistency_error(
    element: &dyn PolyhedralElement,
    polyhedron: &Polyhedron,
    material: &ElasticityTensor<3>,
) -> Result<f64, SpaceError> {
    let k = element.stiffness(polyhedron, material)?.total();
    let origin = geometry::vertex_mean(polyhedron.points());
    let mut worst: f64 = 0.0;
    for (a, m) in linear_fields() {
        let p_i = interpolant(polyhedron.points(), |x| a + m * (x - origin));
        let expected = boundary_load_of_constant_stress(polyhedron, &stress_of(material, &m));
        worst = worst.max((&k * &p_i - expected).norm() / (k.norm() * p_i.norm()));
    }
    Ok(worst)
}

/// The numerical rank of `K_E`; `3n - 6` for a stable element.
pub fn rank(
    element: &dyn PolyhedralElement,
    polyhedron: &Polyhedron,
    material: &ElasticityTensor<3>,
) -> Result<usize, SpaceError> {
    Ok(numerical_rank(
        &element.stiffness(polyhedron, material)?.total(),
    ))
}

/// `max(|K - K^T|, |K_s - K_s^T|) / |K|`.
pub fn symmetry_error(
    element: &dyn PolyhedralElement,
    polyhedron: &Polyhedron,
    material: &ElasticityTensor<3>,
) -> Result<f64, SpaceError> {
    let local = element.stiffness(polyhedron, material)?;
    let k = local.total();
    let s = &local.stabilisation;
    Ok((&k - k.transpose()).norm().max((s - s.transpose()).norm()) / k.norm())
}

/// `max |p_I^T K_E p_I - volume eps(p) : C eps(p)| / (volume |C| |eps|^2)` over the gradients
/// `M` of [`linear_fields`] (the fields `M (x - xbar)`: a translation adds nothing to the energy
/// but round-off), with the closed-form `volume`.
pub fn linear_energy_error(
    element: &dyn PolyhedralElement,
    polyhedron: &Polyhedron,
    volume: f64,
    material: &ElasticityTensor<3>,
) -> Result<f64, SpaceError> {
    let k = element.stiffness(polyhedron, material)?.total();
    let c = material.voigt_matrix();
    let origin = geometry::vertex_mean(polyhedron.points());
    let mut worst: f64 = 0.0;
    for (_, m) in linear_fields() {
        let p_i = interpolant(polyhedron.points(), |x| m * (x - origin));
        let eps = voigt_strain(&m);
        let eps = DVector::from_column_slice(eps.as_slice());
        let exact = volume * eps.dot(&(&c * &eps));
        let scale = volume * c.norm() * eps.norm_squared();
        if scale > 0.0 {
            worst = worst.max((p_i.dot(&(&k * &p_i)) - exact).abs() / scale);
        }
    }
    Ok(worst)
}

/// The element-level patch test: over [`linear_fields`] `p`, the largest of
/// `|Pi p_I (x) - p(x)| / max(|p(x)|, 1)` at the vertices and the centroid and of
/// `|K_s p_I| / (|K_E| |p_I|)`.
pub fn patch_test_error(
    element: &dyn PolyhedralElement,
    polyhedron: &Polyhedron,
    material: &ElasticityTensor<3>,
) -> Result<f64, SpaceError> {
    let local = element.stiffness(polyhedron, material)?;
    let k_norm = local.total().norm();
    let projection = element.projection(polyhedron)?;
    let points = polyhedron.points();
    let origin = geometry::vertex_mean(points);
    let centroid = polyhedron.centroid();
    let mut worst: f64 = 0.0;
    for (a, m) in linear_fields() {
        let field = |x: Point3| a + m * (x - origin);
        let p_i = interpolant(points, field);
        for &x in points.iter().chain([centroid].iter()) {
            let error = (projection.evaluate(&p_i, x) - field(x)).norm() / field(x).norm().max(1.0);
            worst = worst.max(error);
        }
        worst = worst.max((&local.stabilisation * &p_i).norm() / (k_norm * p_i.norm()));
    }
    Ok(worst)
}

/// What the checks measured on one polyhedron and material.
#[derive(Debug, Clone, PartialEq)]
pub struct PolyhedronCheck {
    /// The polyhedron's name.
    pub polyhedron: String,
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
    /// [`linear_energy_error`].
    pub linear_energy_error: f64,
    /// [`patch_test_error`].
    pub patch_test_error: f64,
}

impl PolyhedronCheck {
    /// Runs every check of the kit on `polyhedron` with `material`.
    pub fn run(
        element: &dyn PolyhedralElement,
        polyhedron: &TestPolyhedron,
        material: &ElasticityTensor<3>,
    ) -> Result<Self, TestkitError> {
        let wrap = |source| TestkitError {
            element: element.name().to_string(),
            polyhedron: polyhedron.name.to_string(),
            source,
        };
        let p = &polyhedron.polyhedron;
        Ok(Self {
            polyhedron: polyhedron.name.to_string(),
            n_vertices: p.points().len(),
            rigid_motion_residual: rigid_motion_residual(element, p, material).map_err(wrap)?,
            consistency_error: consistency_error(element, p, material).map_err(wrap)?,
            rank: rank(element, p, material).map_err(wrap)?,
            symmetry_error: symmetry_error(element, p, material).map_err(wrap)?,
            linear_energy_error: linear_energy_error(element, p, polyhedron.volume, material)
                .map_err(wrap)?,
            patch_test_error: patch_test_error(element, p, material).map_err(wrap)?,
        })
    }

    /// The rank of a stable element, `3n - 6`.
    pub fn expected_rank(&self) -> usize {
        (3 * self.n_vertices).saturating_sub(6)
    }

    /// The largest of the relative errors.
    pub fn worst_error(&self) -> f64 {
        [
            self.rigid_motion_residual,
            self.consistency_error,
            self.symmetry_error,
            self.linear_energy_error,
            self.patch_test_error,
        ]
        .into_iter()
        .fold(0.0, f64::max)
    }

    /// The checks that fail with the relative tolerance `tolerance`, one line each.
    pub fn failures(&self, tolerance: f64) -> Vec<String> {
        let mut failures = Vec::new();
        for (what, value) in [
            ("rigid-motion residual", self.rigid_motion_residual),
            ("consistency error", self.consistency_error),
            ("symmetry error", self.symmetry_error),
            ("linear-energy error", self.linear_energy_error),
            ("patch-test error", self.patch_test_error),
        ] {
            if value.is_nan() || value > tolerance {
                failures.push(format!(
                    "{}: {what} {value:e} > {tolerance:e}",
                    self.polyhedron
                ));
            }
        }
        if self.rank != self.expected_rank() {
            failures.push(format!(
                "{}: rank {} instead of 3n - 6 = {}",
                self.polyhedron,
                self.rank,
                self.expected_rank()
            ));
        }
        failures
    }
}

/// A check could not run because the element failed on a polyhedron of the kit.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("element '{element}' failed on the test polyhedron '{polyhedron}'")]
pub struct TestkitError {
    /// The element's name.
    pub element: String,
    /// The polyhedron's name.
    pub polyhedron: String,
    /// What the element reported.
    #[source]
    pub source: SpaceError,
}

/// Runs [`PolyhedronCheck::run`] on every polyhedron of [`standard_polyhedra`] that `element`
/// supports, with every material of [`standard_materials`] (polyhedron-major order).
pub fn check_element(
    element: &dyn PolyhedralElement,
) -> Result<Vec<PolyhedronCheck>, TestkitError> {
    let materials = standard_materials();
    let mut checks = Vec::new();
    for polyhedron in standard_polyhedra() {
        if !element.supports(&polyhedron.polyhedron) {
            continue;
        }
        for material in &materials {
            checks.push(PolyhedronCheck::run(element, &polyhedron, material)?);
        }
    }
    Ok(checks)
}
