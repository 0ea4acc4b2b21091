//! The validated geometry of one polygon as the lowest-order virtual element needs it.

use vem_mesh::geometry;

use crate::{Point, SpaceError, Vector};

/// An edge shorter than this fraction of the diameter is a repeated vertex.
const EDGE_TOLERANCE: f64 = 1e-12;
/// An area at most this fraction of `h_T^2` is degenerate (a sliver or a segment).
const AREA_TOLERANCE: f64 = 1e-14;

/// Geometry of a valid polygon: positive area, at least three vertices, no repeated
/// consecutive vertex, finite coordinates. (Self-intersection is the mesh's business:
/// `vem_mesh::validate` checks it.)
#[derive(Debug, Clone)]
pub(crate) struct PolygonGeometry {
    /// |T| (computed in coordinates relative to `reference`, against cancellation).
    pub area: f64,
    /// The vertex mean, about which the energy projection is expanded.
    pub reference: Point,
    /// `x_k - reference` for every vertex.
    pub local: Vec<Vector>,
    /// `w_k = (|e_{k-1}| nu_{k-1} + |e_k| nu_k) / (2 |T|)`: the mean gradient of a field that is
    /// linear on edges is `sum_k v_k (x) w_k` (divergence theorem, exact).
    pub gradient_weights: Vec<Vector>,
}

impl PolygonGeometry {
    /// Validates `polygon` (counter-clockwise) and computes its geometry.
    pub fn new(polygon: &[Point]) -> Result<Self, SpaceError> {
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
        let reference = geometry::vertex_mean(polygon);
        let local_points: Vec<Point> = polygon.iter().map(|p| Point::from(p - reference)).collect();
        let diameter = geometry::diameter(&local_points);
        for k in 0..n {
            let next = (k + 1) % n;
            if (local_points[next] - local_points[k]).norm() <= EDGE_TOLERANCE * diameter {
                return Err(degenerate(format!(
                    "edge {k} (vertices {k} and {next}) has zero length"
                )));
            }
        }
        let area = geometry::signed_area(&local_points);
        if !area.is_finite() || area <= AREA_TOLERANCE * diameter * diameter {
            return Err(degenerate(format!(
                "signed area {area:e} is not positive (clockwise, or degenerate for diameter \
                 {diameter:e})"
            )));
        }
        // |e| nu of the edge from vertex k to k + 1.
        let scaled_normal = |k: usize| {
            let (a, b) = (local_points[k], local_points[(k + 1) % n]);
            geometry::outward_normal(a, b) * (b - a).norm()
        };
        let gradient_weights = (0..n)
            .map(|k| (scaled_normal((k + n - 1) % n) + scaled_normal(k)) / (2.0 * area))
            .collect();
        Ok(Self {
            area,
            reference,
            local: local_points.iter().map(|p| p.coords).collect(),
            gradient_weights,
        })
    }

    /// Number of vertices.
    pub fn n_vertices(&self) -> usize {
        self.local.len()
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
        let g = PolygonGeometry::new(&polygon).unwrap();
        let mut identity = nalgebra::Matrix2::zeros();
        for (w, x) in g.gradient_weights.iter().zip(&polygon) {
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
            let err = PolygonGeometry::new(&polygon).unwrap_err();
            assert!(
                matches!(err, SpaceError::DegeneratePolygon { vertices, .. } if vertices == polygon.len()),
                "{err}"
            );
            assert!(err.to_string().contains(expected), "{err}");
        }
    }
}
