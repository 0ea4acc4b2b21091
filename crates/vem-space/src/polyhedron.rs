//! The validated geometry of one polyhedron, as the three-dimensional element needs it.
//!
//! For a polyhedron `E` with vertices `x_1 .. x_n` and faces given as vertex loops oriented
//! outward, every face is taken as its fan triangulation about its vertex mean
//! ([`vem_mesh::polyhedral::geometry`]). For a field `v` linear on each fan triangle and equal at
//! the fan centre to the mean of the face's vertex values (the trace of every function of the
//! lowest-order space, see [`crate::PolyhedralVem`]),
//!
//! ```text
//! int_F v (x) n dS = sum_{a in F} v_a (x) w_a^F,      w_a^F = (a_{T_{a-1}} + a_{T_a}) / 3 + S_F / (3 n_F)
//! ```
//!
//! with `a_T` the vector areas of the fan triangles and `S_F` their sum, so that the mean
//! gradient of `v` is
//!
//! ```text
//! (1/|E|) int_E grad v = (1/|E|) sum_F int_F v (x) n dS = sum_a v_a (x) q_a,    q_a = (1/|E|) sum_{F ni a} w_a^F
//! ```
//!
//! [`PolyhedronGeometry::gradient_weights`] are the `q_a`. Two identities hold for every closed,
//! consistently oriented fan surface and are checked here: `sum_a q_a = 0` (the faces close)
//! and `sum_a (x_a - xbar) (x) q_a = I` (the divergence theorem for `v = x`; it fails when a face
//! is oriented inward or missing).

use nalgebra::Matrix3;
use vem_mesh::polyhedral::geometry::{self, Polyhedron};

use crate::SpaceError;
use vem_mesh::{Point3, Vector3};

/// The validated geometry of one polyhedron: volume, centroid, vertex mean, diameter and the
/// weights `q_a` of the mean gradient (module docs).
///
/// ```
/// use vem_mesh::polyhedral::geometry::Polyhedron;
/// use vem_mesh::Point3;
/// use vem_space::PolyhedronGeometry;
/// // The unit cube: each corner carries a quarter of each of its three faces.
/// let points: Vec<Point3> = (0..8)
///     .map(|k| Point3::new((k & 1) as f64, (k >> 1 & 1) as f64, (k >> 2) as f64))
///     .collect();
/// let faces = vec![
///     vec![0, 4, 6, 2], vec![1, 3, 7, 5], vec![0, 1, 5, 4],
///     vec![2, 6, 7, 3], vec![0, 2, 3, 1], vec![4, 5, 7, 6],
/// ];
/// let cube = PolyhedronGeometry::try_new(&Polyhedron::new(points, &faces))?;
/// assert!((cube.volume() - 1.0).abs() < 1e-15);
/// assert!((cube.gradient_weights()[0] + nalgebra::Vector3::repeat(0.25)).norm() < 1e-15);
/// # Ok::<(), vem_space::SpaceError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct PolyhedronGeometry {
    points: Vec<Point3>,
    n_faces: usize,
    volume: f64,
    centroid: Point3,
    vertex_mean: Point3,
    diameter: f64,
    relative: Vec<Vector3>,
    gradient_weights: Vec<Vector3>,
}

impl PolyhedronGeometry {
    /// Volumes at most this fraction of `h_E^3` count as zero.
    pub const VOLUME_TOLERANCE: f64 = 1e-13;

    /// Relative tolerance of the closure checks (`|sum_F S_F|` against the faces' total area,
    /// `sum_a (x_a - xbar) (x) q_a = I` entry by entry).
    pub const CLOSURE_TOLERANCE: f64 = 1e-9;

    /// Checks `polyhedron` and computes its geometry. Errors
    /// ([`SpaceError::DegeneratePolyhedron`], naming the vertex or face): fewer than 4 vertices
    /// or 4 faces, a face with fewer than 3 vertices, a vertex index out of range or repeated in
    /// a face, a vertex on no face, non-finite coordinates, a zero diameter, a volume that is not
    /// positive (inverted or flat), faces that do not close or are not consistently oriented.
    pub fn try_new(polyhedron: &Polyhedron) -> Result<Self, SpaceError> {
        let points = polyhedron.points();
        let (n, n_faces) = (points.len(), polyhedron.n_faces());
        let degenerate = |reason: String| SpaceError::DegeneratePolyhedron {
            vertices: n,
            faces: n_faces,
            reason,
        };
        if n < 4 || n_faces < 4 {
            return Err(degenerate(
                "a polyhedron needs at least 4 vertices and 4 faces".into(),
            ));
        }
        if let Some((k, p)) = points
            .iter()
            .enumerate()
            .find(|(_, p)| !p.coords.iter().all(|c| c.is_finite()))
        {
            return Err(degenerate(format!(
                "vertex {k} has non-finite coordinates ({}, {}, {})",
                p.x, p.y, p.z
            )));
        }
        let mut used = vec![false; n];
        for (k, face) in polyhedron.faces().enumerate() {
            if face.len() < 3 {
                return Err(degenerate(format!(
                    "face {k} has {} vertices (at least 3 needed)",
                    face.len()
                )));
            }
            for (i, &v) in face.iter().enumerate() {
                if v >= n {
                    return Err(degenerate(format!(
                        "face {k} refers to vertex {v}, but there are {n} vertices"
                    )));
                }
                if face[..i].contains(&v) {
                    return Err(degenerate(format!("face {k} lists vertex {v} twice")));
                }
                used[v] = true;
            }
        }
        if let Some(v) = used.iter().position(|u| !u) {
            return Err(degenerate(format!("vertex {v} lies on no face")));
        }
        let vertex_mean = geometry::vertex_mean(points);
        let relative: Vec<Vector3> = points.iter().map(|p| p - vertex_mean).collect();
        let local_points: Vec<Point3> = relative.iter().map(|r| Point3::from(*r)).collect();
        let diameter = geometry::diameter(&local_points);
        if !(diameter.is_finite() && diameter > 0.0) {
            return Err(degenerate(format!("diameter {diameter:e} is not positive")));
        }
        // Geometry relative to the vertex mean: no cancellation far from the origin.
        let local = Polyhedron::from_compact(
            local_points,
            face_offsets(polyhedron),
            polyhedron.faces().flatten().copied().collect(),
        );
        let (volume, local_centroid) = local.volume_and_centroid();
        if !(volume.is_finite() && volume > Self::VOLUME_TOLERANCE * diameter.powi(3)) {
            return Err(degenerate(format!(
                "volume {volume:e} is not positive (inverted, or flat for diameter {diameter:e})"
            )));
        }
        let mut q = vec![Vector3::zeros(); n];
        let (mut closure, mut total_area) = (Vector3::zeros(), 0.0);
        // One buffer each for the faces' points and weights, reused face after face.
        let (mut face_points, mut weights) = (Vec::new(), Vec::new());
        for face in local.faces() {
            face_points.clear();
            face_points.extend(face.iter().map(|&v| local.points()[v]));
            let vector_area = geometry::face_vector_area(&face_points);
            closure += vector_area;
            total_area += vector_area.norm();
            geometry::face_vertex_weights_into(&face_points, &mut weights);
            for (&v, w) in face.iter().zip(&weights) {
                q[v] += w / volume;
            }
        }
        if closure.norm() > Self::CLOSURE_TOLERANCE * total_area {
            return Err(degenerate(format!(
                "the faces do not close: their vector areas add up to ({:.3e}, {:.3e}, {:.3e}) \
                 (total area {total_area:.3e}); a face is missing or oriented inward",
                closure.x, closure.y, closure.z
            )));
        }
        let identity: Matrix3<f64> = relative
            .iter()
            .zip(&q)
            .map(|(r, q)| r * q.transpose())
            .sum();
        let defect = (identity - Matrix3::identity()).amax();
        if !(defect.is_finite() && defect <= Self::CLOSURE_TOLERANCE) {
            return Err(degenerate(format!(
                "the faces are not a consistently oriented closed surface: the divergence \
                 theorem for v = x is off by {defect:.3e}"
            )));
        }
        Ok(Self {
            points: points.to_vec(),
            n_faces,
            volume,
            centroid: vertex_mean + local_centroid.coords,
            vertex_mean,
            diameter,
            relative,
            gradient_weights: q,
        })
    }

    /// Number of vertices `n`.
    pub fn n_vertices(&self) -> usize {
        self.points.len()
    }

    /// Number of faces.
    pub fn n_faces(&self) -> usize {
        self.n_faces
    }

    /// The vertices, as given.
    pub fn vertices(&self) -> &[Point3] {
        &self.points
    }

    /// The volume `|E|` (positive).
    pub fn volume(&self) -> f64 {
        self.volume
    }

    /// The centroid `(1/|E|) int_E x`.
    pub fn centroid(&self) -> Point3 {
        self.centroid
    }

    /// The vertex mean `xbar = (1/n) sum_a x_a`: the expansion point of the projection.
    pub fn vertex_mean(&self) -> Point3 {
        self.vertex_mean
    }

    /// The diameter `h_E` (largest distance between two vertices).
    pub fn diameter(&self) -> f64 {
        self.diameter
    }

    /// `x_a - xbar` for every vertex.
    pub fn relative_vertices(&self) -> &[Vector3] {
        &self.relative
    }

    /// The weights `q_a` of the mean gradient: `(1/|E|) int_E grad v = sum_a v_a (x) q_a`
    /// (module docs).
    pub fn gradient_weights(&self) -> &[Vector3] {
        &self.gradient_weights
    }
}

/// The face offsets of `polyhedron` in compact storage.
fn face_offsets(polyhedron: &Polyhedron) -> Vec<usize> {
    let mut offsets = Vec::with_capacity(polyhedron.n_faces() + 1);
    offsets.push(0);
    for face in polyhedron.faces() {
        offsets.push(offsets.last().copied().unwrap_or(0) + face.len());
    }
    offsets
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube_faces() -> Vec<Vec<usize>> {
        vec![
            vec![0, 4, 6, 2],
            vec![1, 3, 7, 5],
            vec![0, 1, 5, 4],
            vec![2, 6, 7, 3],
            vec![0, 2, 3, 1],
            vec![4, 5, 7, 6],
        ]
    }

    fn cube_points(origin: Vector3, side: f64) -> Vec<Point3> {
        (0..8)
            .map(|k| {
                Point3::from(
                    origin
                        + side * Vector3::new((k & 1) as f64, (k >> 1 & 1) as f64, (k >> 2) as f64),
                )
            })
            .collect()
    }

    #[test]
    fn cube_far_from_the_origin_has_exact_weights() {
        let side = 0.125;
        let origin = Vector3::new(1e5, -2e4, 3e6);
        let cube = Polyhedron::new(cube_points(origin, side), &cube_faces());
        let g = PolyhedronGeometry::try_new(&cube).unwrap();
        assert!((g.volume() - side.powi(3)).abs() < 1e-12 * side.powi(3));
        for (k, q) in g.gradient_weights().iter().enumerate() {
            let sign = |bit: usize| if k >> bit & 1 == 1 { 1.0 } else { -1.0 };
            let expected = Vector3::new(sign(0), sign(1), sign(2)) / (4.0 * side);
            assert!((q - expected).norm() < 1e-9 / side, "{k}: {q}");
        }
    }

    #[test]
    fn an_inward_face_is_refused_with_a_reason() {
        let mut faces = cube_faces();
        faces[2].reverse();
        let cube = Polyhedron::new(cube_points(Vector3::zeros(), 1.0), &faces);
        let err = PolyhedronGeometry::try_new(&cube).unwrap_err();
        assert!(err.to_string().contains("do not close"), "{err}");
        // Every face reversed: an inverted cell.
        let inverted: Vec<Vec<usize>> = cube_faces()
            .into_iter()
            .map(|mut f| {
                f.reverse();
                f
            })
            .collect();
        let cube = Polyhedron::new(cube_points(Vector3::zeros(), 1.0), &inverted);
        let err = PolyhedronGeometry::try_new(&cube).unwrap_err();
        assert!(err.to_string().contains("volume -1"), "{err}");
    }

    #[test]
    fn open_and_malformed_polyhedra_are_refused() {
        let points = cube_points(Vector3::zeros(), 1.0);
        let open = Polyhedron::new(points.clone(), &cube_faces()[..5]);
        let err = PolyhedronGeometry::try_new(&open).unwrap_err();
        assert!(err.to_string().contains("do not close"), "{err}");
        let mut faces = cube_faces();
        faces[0] = vec![0, 4, 4, 2];
        let err =
            PolyhedronGeometry::try_new(&Polyhedron::new(points.clone(), &faces)).unwrap_err();
        assert!(
            err.to_string().contains("face 0 lists vertex 4 twice"),
            "{err}"
        );
        let mut faces = cube_faces();
        faces[5] = vec![4, 5, 9];
        let err =
            PolyhedronGeometry::try_new(&Polyhedron::new(points.clone(), &faces)).unwrap_err();
        assert!(err.to_string().contains("vertex 9"), "{err}");
        let mut nan = points;
        nan[3].y = f64::NAN;
        let err = PolyhedronGeometry::try_new(&Polyhedron::new(nan, &cube_faces())).unwrap_err();
        assert!(err.to_string().contains("vertex 3 has non-finite"), "{err}");
    }
}
