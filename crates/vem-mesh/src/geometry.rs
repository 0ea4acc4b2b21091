//! Geometry of one polygon given by its vertex coordinates in order.
//!
//! These functions work on any slice of points, so the element layer (`vem-space`) can use them
//! on a polygon without a mesh.

use crate::{Point, Vector};

/// Signed area by the shoelace formula: positive for a counter-clockwise loop.
pub fn signed_area(vertices: &[Point]) -> f64 {
    signed_area_of(vertices.len(), |i| vertices[i])
}

/// [`signed_area`] of the polygon of `n` corners `corner(0..n)`, without gathering them.
pub(crate) fn signed_area_of(n: usize, corner: impl Fn(usize) -> Point) -> f64 {
    let mut twice_area = 0.0;
    for i in 0..n {
        let a = corner(i);
        let b = corner((i + 1) % n);
        twice_area += a.x * b.y - b.x * a.y;
    }
    0.5 * twice_area
}

/// True when `p` lies inside the polygon `vertices` (crossing number; a point on the boundary
/// may go either way).
#[cfg(feature = "generators")]
pub(crate) fn contains(vertices: &[Point], p: Point) -> bool {
    let m = vertices.len();
    let mut inside = false;
    for k in 0..m {
        let (a, b) = (vertices[k], vertices[(k + 1) % m]);
        if (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x) {
            inside = !inside;
        }
    }
    inside
}

/// Centroid (centre of mass of the polygon's area), exact for any simple polygon.
///
/// Coordinates are taken relative to the first vertex to avoid cancellation far from the
/// origin. A degenerate polygon (zero area) returns the vertex mean.
pub fn centroid(vertices: &[Point]) -> Point {
    let n = vertices.len();
    let origin = vertices[0];
    let mut twice_area = 0.0;
    let mut moment = Vector::zeros();
    for i in 0..n {
        let a = vertices[i] - origin;
        let b = vertices[(i + 1) % n] - origin;
        let cross = a.x * b.y - b.x * a.y;
        twice_area += cross;
        moment += (a + b) * cross;
    }
    if twice_area == 0.0 {
        return vertex_mean(vertices);
    }
    origin + moment / (3.0 * twice_area)
}

/// Arithmetic mean of the vertices.
pub fn vertex_mean(vertices: &[Point]) -> Point {
    let sum = vertices
        .iter()
        .fold(Vector::zeros(), |acc, p| acc + p.coords);
    Point::from(sum / vertices.len() as f64)
}

/// Diameter h_T: the largest distance between two vertices (exact for a polygon).
pub fn diameter(vertices: &[Point]) -> f64 {
    let mut largest: f64 = 0.0;
    for (i, a) in vertices.iter().enumerate() {
        for b in &vertices[i + 1..] {
            largest = largest.max((b - a).norm());
        }
    }
    largest
}

/// Unit outward normal of the edge from `a` to `b` of a counter-clockwise polygon
/// (the interior lies to the left of a -> b, so the outward normal points to the right).
pub fn outward_normal(a: Point, b: Point) -> Vector {
    let t = b - a;
    Vector::new(t.y, -t.x) / t.norm()
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn unit_square() -> Vec<Point> {
        vec![
            Point::new(0.0, 0.0),
            Point::new(1.0, 0.0),
            Point::new(1.0, 1.0),
            Point::new(0.0, 1.0),
        ]
    }

    #[test]
    fn square_area_centroid_diameter() {
        let square = unit_square();
        assert_relative_eq!(signed_area(&square), 1.0);
        let c = centroid(&square);
        assert_relative_eq!(c.x, 0.5);
        assert_relative_eq!(c.y, 0.5);
        assert_relative_eq!(diameter(&square), 2f64.sqrt());
    }

    #[test]
    fn clockwise_loop_has_negative_area() {
        let mut square = unit_square();
        square.reverse();
        assert_relative_eq!(signed_area(&square), -1.0);
    }

    #[test]
    fn l_shape_centroid_matches_decomposition() {
        // L = [0,2]x[0,1] + [0,1]x[1,2]; centroid = area-weighted mean of the two rectangles.
        let l_shape = vec![
            Point::new(0.0, 0.0),
            Point::new(2.0, 0.0),
            Point::new(2.0, 1.0),
            Point::new(1.0, 1.0),
            Point::new(1.0, 2.0),
            Point::new(0.0, 2.0),
        ];
        assert_relative_eq!(signed_area(&l_shape), 3.0);
        let c = centroid(&l_shape);
        let expected_x = (2.0 * 1.0 + 1.0 * 0.5) / 3.0;
        let expected_y = (2.0 * 0.5 + 1.0 * 1.5) / 3.0;
        assert_relative_eq!(c.x, expected_x, epsilon = 1e-15);
        assert_relative_eq!(c.y, expected_y, epsilon = 1e-15);
    }

    #[test]
    fn outward_normal_of_bottom_edge_points_down() {
        let n = outward_normal(Point::new(0.0, 0.0), Point::new(2.0, 0.0));
        assert_relative_eq!(n.x, 0.0);
        assert_relative_eq!(n.y, -1.0);
    }
}
