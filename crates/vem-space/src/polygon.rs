//! The validated geometry of one polygon as the lowest-order virtual element needs it.

use vem_mesh::geometry;

use crate::{Point, SpaceError, Vector};

/// The validated geometry of one polygon, as an element needs it: area, centroid, vertex mean,
/// diameter, edges (lengths and outward unit normals) and the mean-gradient weights.
///
/// A valid polygon has at least three vertices, finite coordinates, no repeated consecutive
/// vertex and a positive area (vertices counter-clockwise). Self-intersection is the mesh's
/// business (`vem_mesh::validate` checks it). Quantities that cancel far from the origin (area,
/// diameter, edges) are computed in coordinates relative to the vertex mean.
///
/// ```
/// use vem_space::{Point, PolygonGeometry, Vector};
/// // The right triangle (0,0), (4,0), (0,3), by hand: area 6, centroid (4/3, 1), diameter 5,
/// // edges of length 4, 5, 3 with outward normals (0,-1), (3,4)/5, (-1,0).
/// let triangle = [Point::new(0.0, 0.0), Point::new(4.0, 0.0), Point::new(0.0, 3.0)];
/// let g = PolygonGeometry::try_new(&triangle)?;
/// assert_eq!(g.n_vertices(), 3);
/// assert!((g.area() - 6.0).abs() < 1e-15);
/// assert!((g.centroid() - Point::new(4.0 / 3.0, 1.0)).norm() < 1e-15);
/// assert!((g.vertex_mean() - Point::new(4.0 / 3.0, 1.0)).norm() < 1e-15);
/// assert!((g.diameter() - 5.0).abs() < 1e-15);
/// for (length, expected) in g.edge_lengths().iter().zip([4.0, 5.0, 3.0]) {
///     assert!((length - expected).abs() < 1e-15);
/// }
/// let normals = [Vector::new(0.0, -1.0), Vector::new(0.6, 0.8), Vector::new(-1.0, 0.0)];
/// for (normal, expected) in g.normals().iter().zip(normals) {
///     assert!((normal - expected).norm() < 1e-15);
/// }
/// // w_0 = (|e_2| nu_2 + |e_0| nu_0) / (2 |T|) = ((-3, 0) + (0, -4)) / 12 = (-1/4, -1/3):
/// // the gradient of the hat function of vertex 0.
/// assert!((g.gradient_weights()[0] - Vector::new(-0.25, -1.0 / 3.0)).norm() < 1e-15);
/// # Ok::<(), vem_space::SpaceError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct PolygonGeometry {
    vertices: Vec<Point>,
    area: f64,
    centroid: Point,
    vertex_mean: Point,
    diameter: f64,
    relative: Vec<Vector>,
    edge_lengths: Vec<f64>,
    normals: Vec<Vector>,
    gradient_weights: Vec<Vector>,
}

impl PolygonGeometry {
    /// An edge shorter than this fraction of the diameter is a repeated vertex.
    pub const EDGE_TOLERANCE: f64 = 1e-12;
    /// An area at most this fraction of `h_T^2` is degenerate (a sliver or a segment).
    pub const AREA_TOLERANCE: f64 = 1e-14;

    /// Validates `polygon` (vertices counter-clockwise) and computes its geometry.
    ///
    /// Errors: [`SpaceError::DegeneratePolygon`] with the reason (fewer than three vertices, a
    /// non-finite vertex, a zero-length edge, a non-positive area).
    pub fn try_new(polygon: &[Point]) -> Result<Self, SpaceError> {
        let n = polygon.len();
        let degenerate = |reason: String| SpaceError::DegeneratePolygon {
            vertices: n,
            reason,
        };
        if n < 3 {
            return Err(degenerate("a polygon needs at least 3 vertices".into()));
        }
        if let Some((k, p)) = polygon
            .iter()
            .enumerate()
            .find(|(_, p)| !(p.x.is_finite() && p.y.is_finite()))
        {
            return Err(degenerate(format!(
                "vertex {k} has non-finite coordinates ({}, {})",
                p.x, p.y
            )));
        }
        let vertex_mean = geometry::vertex_mean(polygon);
        let local_points: Vec<Point> = polygon
            .iter()
            .map(|p| Point::from(p - vertex_mean))
            .collect();
        let diameter = geometry::diameter(&local_points);
        let mut edge_lengths = Vec::with_capacity(n);
        for k in 0..n {
            let next = (k + 1) % n;
            let length = (local_points[next] - local_points[k]).norm();
            if length <= Self::EDGE_TOLERANCE * diameter {
                return Err(degenerate(format!(
                    "edge {k} (vertices {k} and {next}) has zero length"
                )));
            }
            edge_lengths.push(length);
        }
        let area = geometry::signed_area(&local_points);
        if !area.is_finite() || area <= Self::AREA_TOLERANCE * diameter * diameter {
            return Err(degenerate(format!(
                "signed area {area:e} is not positive (clockwise, or degenerate for diameter \
                 {diameter:e})"
            )));
        }
        let normals: Vec<Vector> = (0..n)
            .map(|k| geometry::outward_normal(local_points[k], local_points[(k + 1) % n]))
            .collect();
        // |e| nu of the edge from vertex k to k + 1.
        let scaled_normal = |k: usize| normals[k] * edge_lengths[k];
        let gradient_weights = (0..n)
            .map(|k| (scaled_normal((k + n - 1) % n) + scaled_normal(k)) / (2.0 * area))
            .collect();
        Ok(Self {
            vertices: polygon.to_vec(),
            area,
            centroid: geometry::centroid(polygon),
            vertex_mean,
            diameter,
            relative: local_points.iter().map(|p| p.coords).collect(),
            edge_lengths,
            normals,
            gradient_weights,
        })
    }

    /// Number of vertices `n`.
    pub fn n_vertices(&self) -> usize {
        self.vertices.len()
    }

    /// The vertices `x_0 .. x_{n-1}`, counter-clockwise, as given.
    pub fn vertices(&self) -> &[Point] {
        &self.vertices
    }

    /// The area `|T|` (positive).
    pub fn area(&self) -> f64 {
        self.area
    }

    /// The centroid `x_T = (1/|T|) int_T x`.
    pub fn centroid(&self) -> Point {
        self.centroid
    }

    /// The vertex mean `x_bar = (1/n) sum_k x_k` (equal to the centroid on triangles and
    /// regular polygons, not in general).
    pub fn vertex_mean(&self) -> Point {
        self.vertex_mean
    }

    /// The diameter `h_T`: the largest distance between two vertices.
    pub fn diameter(&self) -> f64 {
        self.diameter
    }

    /// `x_k - x_bar` for every vertex (the vertices relative to [`PolygonGeometry::vertex_mean`]).
    pub fn relative_vertices(&self) -> &[Vector] {
        &self.relative
    }

    /// `|e_k|`, the length of edge `e_k` from vertex `k` to vertex `k + 1 (mod n)`.
    pub fn edge_lengths(&self) -> &[f64] {
        &self.edge_lengths
    }

    /// `nu_k`, the outward unit normal of edge `e_k` (from vertex `k` to `k + 1 (mod n)`).
    pub fn normals(&self) -> &[Vector] {
        &self.normals
    }

    /// `w_k = (|e_{k-1}| nu_{k-1} + |e_k| nu_k) / (2 |T|)`: the mean gradient of a field that is
    /// linear on every edge is `sum_k v_k (x) w_k` (divergence theorem, exact).
    pub fn gradient_weights(&self) -> &[Vector] {
        &self.gradient_weights
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gradient_weights_recover_the_identity() {
        // sum_k w_k (x) x_k = mean gradient of x = I, on a non-convex pentagon.
        let polygon = [
            Point::new(0.0, 0.0),
            Point::new(3.0, 0.5),
            Point::new(1.5, 1.0),
            Point::new(2.5, 2.0),
            Point::new(-0.5, 1.5),
        ];
        let g = PolygonGeometry::try_new(&polygon).unwrap();
        let mut identity = nalgebra::Matrix2::zeros();
        for (w, x) in g.gradient_weights().iter().zip(&polygon) {
            identity += x.coords * w.transpose();
        }
        assert!((identity - nalgebra::Matrix2::identity()).norm() < 1e-14);
    }

    #[test]
    fn invalid_polygons_are_rejected_with_a_reason() {
        let p = |x, y| Point::new(x, y);
        let cases: Vec<(Vec<Point>, &str)> = vec![
            (vec![p(0.0, 0.0), p(1.0, 0.0)], "at least 3"),
            (
                vec![p(0.0, 0.0), p(1.0, 0.0), p(f64::NAN, 1.0)],
                "vertex 2 has non-finite",
            ),
            (vec![p(0.0, 0.0), p(0.0, 1.0), p(1.0, 0.0)], "not positive"),
            (vec![p(0.0, 0.0), p(1.0, 0.0), p(2.0, 0.0)], "not positive"),
            (
                vec![p(0.0, 0.0), p(1.0, 0.0), p(1.0, 0.0), p(0.0, 1.0)],
                "edge 1 (vertices 1 and 2) has zero length",
            ),
        ];
        for (polygon, expected) in cases {
            let err = PolygonGeometry::try_new(&polygon).unwrap_err();
            assert!(
                matches!(err, SpaceError::DegeneratePolygon { vertices, .. } if vertices == polygon.len()),
                "{err}"
            );
            assert!(err.to_string().contains(expected), "{err}");
        }
    }
}
