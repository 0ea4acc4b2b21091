//! Geometry of polygonal faces in space and of the polyhedra they bound.
//!
//! # Faces are fans
//!
//! A face with vertices x_0, ..., x_{n-1} (a closed loop) is taken as its *fan triangulation*
//! about its vertex mean xbar_F = (1/n) sum_a x_a: the triangles T_k = (x_k, x_{k+1}, xbar_F).
//! For a planar face this is exact (the signed fan areas add up to the polygon's area whatever
//! the shape, convex or not); for a warped face it is the definition of the face's surface.
//! With a_T = (1/2) (x_k - xbar_F) x (x_{k+1} - xbar_F) the vector area of T_k:
//!
//! * the face's vector area S_F = sum_T a_T = (1/2) sum_k x_k x x_{k+1} (independent of the
//!   fan centre), its area |S_F| (the exact area of a planar face; the area of the projection
//!   on the mean plane for a warped one) and its unit normal n_F = S_F / |S_F|;
//! * for a field v linear on each fan triangle with v(xbar_F) = mean of the vertex values,
//!   int_F v n dS = sum_a v_a w_a with the vector weights
//!   w_a = (a_{T_{a-1}} + a_{T_a}) / 3 + S_F / (3 n) ([`face_vertex_weights`]); they add up
//!   to S_F.
//!
//! # Volume and centroid
//!
//! By the divergence theorem over the fan triangles: with o the polyhedron's vertex mean, every
//! fan triangle (x_k, x_{k+1}, xbar_F) of an outward face spans with o a signed tetrahedron of
//! volume (1/6) det(x_k - o, x_{k+1} - o, xbar_F - o) and centroid the mean of its four
//! corners; the polyhedron's volume and first moments are the sums. This is exact for planar
//! faces of any shape and for any polyhedron (convex or not: the signed tetrahedra outside it
//! cancel), and working relative to o avoids the cancellation of coordinates far from the
//! origin.
//!
//! ```
//! use vem_mesh::polyhedral::geometry::Polyhedron;
//! use vem_mesh::Point3;
//! // The unit cube, faces oriented outward.
//! let points: Vec<Point3> = (0..8)
//!     .map(|k| Point3::new((k & 1) as f64, (k >> 1 & 1) as f64, (k >> 2) as f64))
//!     .collect();
//! let faces = vec![
//!     vec![0, 4, 6, 2], vec![1, 3, 7, 5], vec![0, 1, 5, 4],
//!     vec![2, 6, 7, 3], vec![0, 2, 3, 1], vec![4, 5, 7, 6],
//! ];
//! let cube = Polyhedron::new(points, &faces);
//! let (volume, centroid) = cube.volume_and_centroid();
//! assert!((volume - 1.0).abs() < 1e-15);
//! assert!((centroid - Point3::new(0.5, 0.5, 0.5)).norm() < 1e-15);
//! ```

use crate::{Point3, Vector3};

/// Arithmetic mean of the points (the fan centre of a face).
pub fn vertex_mean(points: &[Point3]) -> Point3 {
    let sum = points
        .iter()
        .fold(Vector3::zeros(), |acc, p| acc + p.coords);
    Point3::from(sum / points.len() as f64)
}

/// Vector area S_F of the face loop `points`: the sum of the vector areas of its fan
/// triangles, (1/2) sum_k x_k x x_{k+1}; its direction is the right-hand normal of the loop.
pub fn face_vector_area(points: &[Point3]) -> Vector3 {
    let centre = vertex_mean(points);
    let n = points.len();
    let mut sum = Vector3::zeros();
    for k in 0..n {
        let (a, b) = (points[k] - centre, points[(k + 1) % n] - centre);
        sum += a.cross(&b);
    }
    0.5 * sum
}

/// Area |S_F| of the face loop `points` (exact for a planar face; the projected area on the mean
/// plane for a warped one).
pub fn face_area(points: &[Point3]) -> f64 {
    face_vector_area(points).norm()
}

/// Unit normal S_F / |S_F| of the face loop `points` (right-hand rule); zero for a face of zero
/// area.
pub fn face_normal(points: &[Point3]) -> Vector3 {
    let s = face_vector_area(points);
    let norm = s.norm();
    if norm > 0.0 {
        s / norm
    } else {
        Vector3::zeros()
    }
}

/// Centroid of the face loop `points`: the fan triangles' centroids weighted by their areas
/// projected on the face normal (the exact centroid of a planar face, convex or not); the vertex
/// mean for a face of zero area.
pub fn face_centroid(points: &[Point3]) -> Point3 {
    let centre = vertex_mean(points);
    let normal = face_normal(points);
    let n = points.len();
    let (mut weight, mut moment) = (0.0, Vector3::zeros());
    for k in 0..n {
        let (a, b) = (points[k] - centre, points[(k + 1) % n] - centre);
        let w = 0.5 * a.cross(&b).dot(&normal);
        weight += w;
        moment += w * (a + b) / 3.0;
    }
    if weight == 0.0 {
        return centre;
    }
    centre + moment / weight
}

/// The vector weights w_a of the face loop `points` (one per vertex, in order): for every field
/// v linear on each fan triangle and equal at the fan centre to the mean of its vertex values,
/// int_F v n dS = sum_a v_a w_a (see the module docs). They add up to the vector area S_F.
pub fn face_vertex_weights(points: &[Point3]) -> Vec<Vector3> {
    let mut weights = Vec::with_capacity(points.len());
    face_vertex_weights_into(points, &mut weights);
    weights
}

/// [`face_vertex_weights`] written into `weights` (cleared first), so that a pass over many
/// faces (the geometry of every cell of an assembly) reuses one buffer.
pub fn face_vertex_weights_into(points: &[Point3], weights: &mut Vec<Vector3>) {
    weights.clear();
    let n = points.len();
    if n == 0 {
        return;
    }
    let centre = vertex_mean(points);
    // The vector areas of the fan triangles first; then, from the last vertex back, each
    // weight from the areas of its two triangles (the first vertex's other triangle is the
    // last, kept before it is overwritten).
    weights
        .extend((0..n).map(|k| 0.5 * (points[k] - centre).cross(&(points[(k + 1) % n] - centre))));
    let total: Vector3 = weights.iter().sum();
    let share = total / (3.0 * n as f64);
    let last = weights[n - 1];
    for a in (1..n).rev() {
        weights[a] = (weights[a - 1] + weights[a]) / 3.0 + share;
    }
    weights[0] = (last + weights[0]) / 3.0 + share;
}

/// Largest distance of a vertex of the face loop `points` from the plane through its vertex mean
/// with normal [`face_normal`] (0 for a planar face).
pub fn face_warping(points: &[Point3]) -> f64 {
    let centre = vertex_mean(points);
    let normal = face_normal(points);
    points
        .iter()
        .map(|p| (p - centre).dot(&normal).abs())
        .fold(0.0, f64::max)
}

/// Diameter: the largest distance between two of the points (exact for a polygon or a
/// polyhedron given by its vertices).
pub fn diameter(points: &[Point3]) -> f64 {
    let mut largest: f64 = 0.0;
    for (i, a) in points.iter().enumerate() {
        for b in &points[i + 1..] {
            largest = largest.max((b - a).norm_squared());
        }
    }
    largest.sqrt()
}

/// A polyhedron given by its vertices and its faces as loops of local vertex indices oriented
/// outward (right-hand normal pointing out), in compact storage: face `k` is
/// `face_vertices[face_offsets[k]..face_offsets[k + 1]]`.
///
/// This is the shape the element layer works on: [`crate::PolyhedralMesh::cell_polyhedron`]
/// returns one per cell. Nothing is checked here; the mesh validates its cells.
#[derive(Debug, Clone, PartialEq)]
pub struct Polyhedron {
    points: Vec<Point3>,
    face_offsets: Vec<usize>,
    face_vertices: Vec<usize>,
}

impl Polyhedron {
    /// The polyhedron with vertices `points` and outward faces `faces` (local vertex loops).
    pub fn new(points: Vec<Point3>, faces: &[Vec<usize>]) -> Self {
        let mut face_offsets = Vec::with_capacity(faces.len() + 1);
        face_offsets.push(0);
        let mut face_vertices = Vec::new();
        for face in faces {
            face_vertices.extend_from_slice(face);
            face_offsets.push(face_vertices.len());
        }
        Self {
            points,
            face_offsets,
            face_vertices,
        }
    }

    /// The polyhedron from compact storage (`face_offsets` starts at 0 and ends at
    /// `face_vertices.len()`).
    pub fn from_compact(
        points: Vec<Point3>,
        face_offsets: Vec<usize>,
        face_vertices: Vec<usize>,
    ) -> Self {
        Self {
            points,
            face_offsets,
            face_vertices,
        }
    }

    /// The vertices.
    pub fn points(&self) -> &[Point3] {
        &self.points
    }

    /// Number of faces.
    pub fn n_faces(&self) -> usize {
        self.face_offsets.len() - 1
    }

    /// Local vertex loop of face `k`, oriented outward.
    pub fn face(&self, k: usize) -> &[usize] {
        &self.face_vertices[self.face_offsets[k]..self.face_offsets[k + 1]]
    }

    /// Iterator over the faces' local vertex loops.
    pub fn faces(&self) -> impl ExactSizeIterator<Item = &[usize]> + '_ {
        (0..self.n_faces()).map(move |k| self.face(k))
    }

    /// Coordinates of the vertices of face `k`, in loop order.
    pub fn face_points(&self, k: usize) -> Vec<Point3> {
        self.face(k).iter().map(|&v| self.points[v]).collect()
    }

    /// Volume and centroid by the divergence theorem over the fan triangles (module docs).
    /// A polyhedron of zero volume has its vertex mean as centroid.
    pub fn volume_and_centroid(&self) -> (f64, Point3) {
        let origin = vertex_mean(&self.points);
        let mut six_volume = 0.0;
        let mut moment = Vector3::zeros();
        for face in self.faces() {
            let n = face.len();
            let centre = face
                .iter()
                .fold(Vector3::zeros(), |acc, &v| acc + (self.points[v] - origin))
                / n as f64;
            for k in 0..n {
                let a = self.points[face[k]] - origin;
                let b = self.points[face[(k + 1) % n]] - origin;
                let det = a.cross(&b).dot(&centre);
                six_volume += det;
                moment += det * (a + b + centre);
            }
        }
        let volume = six_volume / 6.0;
        if six_volume == 0.0 || !six_volume.is_finite() {
            return (volume, origin);
        }
        // Tetrahedron centroids are (o + a + b + c) / 4 relative to o: (a + b + c) / 4.
        (volume, origin + moment / (4.0 * six_volume))
    }

    /// Signed volume (positive for outward faces).
    pub fn volume(&self) -> f64 {
        self.volume_and_centroid().0
    }

    /// Centroid (centre of mass of the volume).
    pub fn centroid(&self) -> Point3 {
        self.volume_and_centroid().1
    }

    /// Diameter h_E: the largest distance between two vertices.
    pub fn diameter(&self) -> f64 {
        diameter(&self.points)
    }

    /// Sum of the faces' vector areas: zero (to round-off) for a closed surface.
    pub fn total_vector_area(&self) -> Vector3 {
        (0..self.n_faces())
            .map(|k| face_vector_area(&self.face_points(k)))
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn cube(origin: Vector3, side: f64) -> Polyhedron {
        let points: Vec<Point3> = (0..8)
            .map(|k| {
                Point3::from(
                    origin
                        + side * Vector3::new((k & 1) as f64, (k >> 1 & 1) as f64, (k >> 2) as f64),
                )
            })
            .collect();
        let faces = vec![
            vec![0, 4, 6, 2],
            vec![1, 3, 7, 5],
            vec![0, 1, 5, 4],
            vec![2, 6, 7, 3],
            vec![0, 2, 3, 1],
            vec![4, 5, 7, 6],
        ];
        Polyhedron::new(points, &faces)
    }

    #[test]
    fn cube_far_from_the_origin() {
        // Coordinates exactly representable, so any error is the algorithm's.
        let origin = Vector3::new(1e6, -3e5, 2e7);
        let side = 1.0 / 64.0;
        let c = cube(origin, side);
        let (volume, centroid) = c.volume_and_centroid();
        assert_relative_eq!(volume, side.powi(3), max_relative = 1e-12);
        let expected = Point3::from(origin + Vector3::repeat(side / 2.0));
        assert!(
            (centroid - expected).norm() < 1e-12 * side + 4e-9,
            "{centroid}"
        );
        assert!(c.total_vector_area().norm() < 1e-15);
        assert_relative_eq!(c.diameter(), 3f64.sqrt() * side, max_relative = 1e-12);
    }

    #[test]
    fn face_quantities_of_a_square() {
        let square = [
            Point3::new(0.0, 0.0, 2.0),
            Point3::new(2.0, 0.0, 2.0),
            Point3::new(2.0, 2.0, 2.0),
            Point3::new(0.0, 2.0, 2.0),
        ];
        assert_relative_eq!(face_area(&square), 4.0);
        assert_relative_eq!(face_normal(&square), Vector3::z());
        assert_relative_eq!(face_centroid(&square), Point3::new(1.0, 1.0, 2.0));
        assert_eq!(face_warping(&square), 0.0);
        let weights = face_vertex_weights(&square);
        // Symmetric square: each vertex carries a quarter of the vector area.
        for w in &weights {
            assert_relative_eq!(*w, Vector3::new(0.0, 0.0, 1.0), epsilon = 1e-15);
        }
    }

    #[test]
    fn vertex_weights_integrate_linear_fields_on_an_l_shaped_face() {
        // Planar L-shaped face in the plane z = 1 (normal +z); for v = x, int_F x dS = |F| c_x.
        let l_shape = [
            Point3::new(0.0, 0.0, 1.0),
            Point3::new(2.0, 0.0, 1.0),
            Point3::new(2.0, 1.0, 1.0),
            Point3::new(1.0, 1.0, 1.0),
            Point3::new(1.0, 2.0, 1.0),
            Point3::new(0.0, 2.0, 1.0),
        ];
        let weights = face_vertex_weights(&l_shape);
        let area = face_area(&l_shape);
        assert_relative_eq!(area, 3.0, max_relative = 1e-15);
        let centroid = face_centroid(&l_shape);
        assert_relative_eq!(centroid.x, 5.0 / 6.0, max_relative = 1e-14);
        assert_relative_eq!(centroid.y, 5.0 / 6.0, max_relative = 1e-14);
        for field in [
            |p: &Point3| p.x,
            |p: &Point3| p.y,
            |p: &Point3| 3.0 - p.x + 2.0 * p.y,
        ] {
            let by_weights: Vector3 = l_shape
                .iter()
                .zip(&weights)
                .map(|(p, w)| field(p) * w)
                .sum();
            let exact = field(&centroid) * area;
            assert_relative_eq!(by_weights.z, exact, max_relative = 1e-14);
            assert!(by_weights.xy().norm() < 1e-14);
        }
    }

    #[test]
    fn warped_quad_weights_add_up_to_the_vector_area() {
        let warped = [
            Point3::new(0.0, 0.0, 0.0),
            Point3::new(1.0, 0.0, 0.1),
            Point3::new(1.0, 1.0, 0.0),
            Point3::new(0.0, 1.0, 0.1),
        ];
        let total: Vector3 = face_vertex_weights(&warped).iter().sum();
        assert_relative_eq!(total, face_vector_area(&warped), epsilon = 1e-15);
        assert_relative_eq!(face_warping(&warped), 0.05, max_relative = 1e-12);
    }
}
