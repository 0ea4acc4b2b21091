//! Quadrature rules shared by the element, load and error-norm code.
//!
//! - [`GaussLegendre`]: `p`-point Gauss–Legendre rules on a segment, `p = 1..=6`, exact for
//!   polynomials of degree `2p - 1` (used for Neumann tractions, [`crate::edge_traction_load`]).
//! - [`TriangleRule`]: the 7-point degree-5 rule of Radon (Dunavant's degree-5 rule) on a
//!   triangle, with positive weights and interior points.
//! - [`polygon_rule`]: a rule on a polygon from the fan of triangles joining the centroid to each
//!   edge (weights carry the signed sub-triangle areas, so polynomials up to the rule's degree
//!   are integrated exactly on any simple polygon, convex or not).
//!
//! ```
//! use vem_space::quadrature::{polygon_rule, TriangleRule};
//! use vem_space::Point;
//! let square = [
//!     Point::new(0.0, 0.0), Point::new(1.0, 0.0), Point::new(1.0, 1.0), Point::new(0.0, 1.0),
//! ];
//! let rule = polygon_rule(&square, &TriangleRule::degree5());
//! // The integral of x^2 y over the unit square is 1/6.
//! let integral: f64 = rule.iter().map(|q| q.weight * q.point.x.powi(2) * q.point.y).sum();
//! assert!((integral - 1.0 / 6.0).abs() < 1e-15);
//! ```

use vem_mesh::geometry;

use crate::{Point, SpaceError};

/// One point of a quadrature rule in physical coordinates with its weight
/// (the integral of `f` is approximated by the sum of `weight * f(point)`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct QuadraturePoint {
    /// Where the integrand is evaluated.
    pub point: Point,
    /// The weight (it includes the length or area of the integration domain).
    pub weight: f64,
}

/// Gauss–Legendre nodes on [-1, 1], one table per number of points (symmetric, increasing).
const GAUSS_LEGENDRE_NODES: [&[f64]; 6] = [
    &[0.0],
    &[-0.5773502691896257, 0.5773502691896257],
    &[-0.7745966692414834, 0.0, 0.7745966692414834],
    &[
        -0.8611363115940526,
        -0.33998104358485626,
        0.33998104358485626,
        0.8611363115940526,
    ],
    &[
        -0.906179845938664,
        -0.5384693101056831,
        0.0,
        0.5384693101056831,
        0.906179845938664,
    ],
    &[
        -0.932469514203152,
        -0.6612093864662645,
        -0.2386191860831969,
        0.2386191860831969,
        0.6612093864662645,
        0.932469514203152,
    ],
];

/// Gauss–Legendre weights on [-1, 1] (they sum to 2), matching [`GAUSS_LEGENDRE_NODES`].
const GAUSS_LEGENDRE_WEIGHTS: [&[f64]; 6] = [
    &[2.0],
    &[1.0, 1.0],
    &[0.5555555555555556, 0.8888888888888888, 0.5555555555555556],
    &[
        0.34785484513745385,
        0.6521451548625461,
        0.6521451548625461,
        0.34785484513745385,
    ],
    &[
        0.23692688505618908,
        0.47862867049936647,
        0.5688888888888889,
        0.47862867049936647,
        0.23692688505618908,
    ],
    &[
        0.17132449237917036,
        0.3607615730481386,
        0.46791393457269104,
        0.46791393457269104,
        0.3607615730481386,
        0.17132449237917036,
    ],
];

/// A Gauss–Legendre rule with `p` points: exact for polynomials of degree `2p - 1` on a segment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GaussLegendre {
    nodes: &'static [f64],
    weights: &'static [f64],
}

impl GaussLegendre {
    /// The largest tabulated number of points.
    pub const MAX_POINTS: usize = GAUSS_LEGENDRE_NODES.len();

    /// The rule with `points` points, `1 <= points <= MAX_POINTS`.
    pub fn try_new(points: usize) -> Result<Self, SpaceError> {
        if points == 0 || points > Self::MAX_POINTS {
            return Err(SpaceError::UnsupportedQuadrature {
                rule: "Gauss-Legendre",
                points,
                max: Self::MAX_POINTS,
            });
        }
        Ok(Self {
            nodes: GAUSS_LEGENDRE_NODES[points - 1],
            weights: GAUSS_LEGENDRE_WEIGHTS[points - 1],
        })
    }

    /// Number of points.
    pub fn points(&self) -> usize {
        self.nodes.len()
    }

    /// Highest polynomial degree integrated exactly, `2p - 1`.
    pub fn degree(&self) -> usize {
        2 * self.nodes.len() - 1
    }

    /// Nodes on the reference interval [-1, 1].
    pub fn nodes(&self) -> &'static [f64] {
        self.nodes
    }

    /// Weights on the reference interval [-1, 1] (they sum to 2).
    pub fn weights(&self) -> &'static [f64] {
        self.weights
    }

    /// The rule on the segment from `a` to `b`: each item is `(t, point, weight)` with
    /// `point = a + t (b - a)`, `t` in (0, 1), and the weights summing to `|b - a|`.
    pub fn on_segment(
        &self,
        a: Point,
        b: Point,
    ) -> impl ExactSizeIterator<Item = (f64, QuadraturePoint)> + '_ {
        let half_length = 0.5 * (b - a).norm();
        self.nodes.iter().zip(self.weights).map(move |(&s, &w)| {
            let t = 0.5 * (1.0 + s);
            (
                t,
                QuadraturePoint {
                    point: a + (b - a) * t,
                    weight: w * half_length,
                },
            )
        })
    }
}

/// Radon's 7-point degree-5 rule (Dunavant 1985, degree 5): barycentric coordinates and
/// weights normalised to sum to 1. Closed forms: centroid with weight 9/40; (a, b, b) and
/// permutations with b = (6 -+ sqrt 15)/21, a = 1 - 2b, weights (155 -+ sqrt 15)/1200.
const DEGREE5_POINTS: [([f64; 3], f64); 7] = {
    const C: f64 = 1.0 / 3.0;
    const A1: f64 = 0.05971587178976982;
    const B1: f64 = 0.4701420641051151;
    const W1: f64 = 0.1323941527885062;
    const A2: f64 = 0.7974269853530873;
    const B2: f64 = 0.10128650732345634;
    const W2: f64 = 0.12593918054482714;
    [
        ([C, C, C], 0.225),
        ([A1, B1, B1], W1),
        ([B1, A1, B1], W1),
        ([B1, B1, A1], W1),
        ([A2, B2, B2], W2),
        ([B2, A2, B2], W2),
        ([B2, B2, A2], W2),
    ]
};

/// A quadrature rule on a triangle in barycentric coordinates (weights sum to 1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TriangleRule {
    points: &'static [([f64; 3], f64)],
    degree: usize,
}

impl TriangleRule {
    /// Radon's 7-point rule, exact for polynomials of degree 5 (positive weights, interior
    /// points). The default rule of the project for loads and error norms.
    pub fn degree5() -> Self {
        Self {
            points: &DEGREE5_POINTS,
            degree: 5,
        }
    }

    /// Highest polynomial degree integrated exactly.
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// The points as `(barycentric coordinates, weight)`, the weights summing to 1.
    pub fn barycentric(&self) -> &'static [([f64; 3], f64)] {
        self.points
    }

    /// The rule on the triangle `(a, b, c)`: the weights sum to its signed area (negative for a
    /// clockwise triangle, which is what a fan over a non-convex polygon needs).
    pub fn on_triangle(
        &self,
        a: Point,
        b: Point,
        c: Point,
    ) -> impl ExactSizeIterator<Item = QuadraturePoint> + '_ {
        let (ab, ac) = (b - a, c - a);
        let signed_area = 0.5 * (ab.x * ac.y - ab.y * ac.x);
        self.points
            .iter()
            .map(move |&([_, lb, lc], w)| QuadraturePoint {
                point: a + ab * lb + ac * lc,
                weight: w * signed_area,
            })
    }
}

/// A rule on the polygon `polygon` (counter-clockwise vertices): `rule` on each triangle of the
/// fan joining the centroid to the edges. The weights are signed sub-areas, so the rule is exact
/// for polynomials of degree `rule.degree()` on any simple polygon; if the polygon is not
/// star-shaped with respect to its centroid some points lie outside it (the integrand must then
/// be defined there).
pub fn polygon_rule(polygon: &[Point], rule: &TriangleRule) -> Vec<QuadraturePoint> {
    let n = polygon.len();
    let centroid = geometry::centroid(polygon);
    let mut points = Vec::with_capacity(n * rule.barycentric().len());
    for k in 0..n {
        points.extend(rule.on_triangle(centroid, polygon[k], polygon[(k + 1) % n]));
    }
    points
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Integral of x^i over [-1, 1].
    fn monomial_on_interval(i: u32) -> f64 {
        if i % 2 == 1 {
            0.0
        } else {
            2.0 / (i as f64 + 1.0)
        }
    }

    fn factorial(k: u32) -> f64 {
        (1..=k).map(f64::from).product()
    }

    #[test]
    fn gauss_legendre_is_exact_to_its_degree_and_not_beyond() {
        for p in 1..=GaussLegendre::MAX_POINTS {
            let rule = GaussLegendre::try_new(p).unwrap();
            assert_eq!(rule.points(), p);
            for i in 0..=rule.degree() as u32 + 1 {
                let approx: f64 = rule
                    .nodes()
                    .iter()
                    .zip(rule.weights())
                    .map(|(x, w)| w * x.powi(i as i32))
                    .sum();
                let error = (approx - monomial_on_interval(i)).abs();
                if i as usize <= rule.degree() {
                    assert!(error < 4e-16, "p = {p}, x^{i}: error {error}");
                } else {
                    // Degree 2p is not integrated exactly (the rule is not over-tabulated).
                    assert!(error > 1e-4, "p = {p}, x^{i}: error {error}");
                }
            }
        }
    }

    #[test]
    fn gauss_legendre_on_a_segment_integrates_a_cubic() {
        // int_0^1 of (1 + 2 t)^3 along a segment of length 5: 5 * (3^4 - 1) / 8 = 50.
        let (a, b) = (Point::new(1.0, -1.0), Point::new(4.0, 3.0));
        let rule = GaussLegendre::try_new(2).unwrap();
        let integral: f64 = rule
            .on_segment(a, b)
            .map(|(t, q)| {
                assert!(((q.point - a) - (b - a) * t).norm() < 1e-15);
                q.weight * (1.0 + 2.0 * t).powi(3)
            })
            .sum();
        assert!((integral - 50.0).abs() < 1e-13, "{integral}");
    }

    #[test]
    fn unsupported_gauss_legendre_sizes_are_errors() {
        for p in [0, GaussLegendre::MAX_POINTS + 1] {
            let err = GaussLegendre::try_new(p).unwrap_err();
            assert!(matches!(err, SpaceError::UnsupportedQuadrature { points, .. } if points == p));
        }
    }

    #[test]
    fn triangle_rule_is_exact_for_degree_five_monomials() {
        // int over the reference triangle of x^i y^j = i! j! / (i + j + 2)!.
        let rule = TriangleRule::degree5();
        let (a, b, c) = (
            Point::new(0.0, 0.0),
            Point::new(1.0, 0.0),
            Point::new(0.0, 1.0),
        );
        let weights: f64 = rule.barycentric().iter().map(|(_, w)| w).sum();
        assert!((weights - 1.0).abs() < 1e-15);
        for i in 0..=5u32 {
            for j in 0..=5 - i {
                let approx: f64 = rule
                    .on_triangle(a, b, c)
                    .map(|q| q.weight * q.point.x.powi(i as i32) * q.point.y.powi(j as i32))
                    .sum();
                let exact = factorial(i) * factorial(j) / factorial(i + j + 2);
                assert!(
                    (approx - exact).abs() < 1e-15,
                    "x^{i} y^{j}: {approx} vs {exact}"
                );
            }
        }
        // x^6 is not exact: the degree is not overstated.
        let approx: f64 = rule
            .on_triangle(a, b, c)
            .map(|q| q.weight * q.point.x.powi(6))
            .sum();
        assert!((approx - factorial(6) / factorial(8)).abs() > 1e-6);
    }

    #[test]
    fn polygon_rule_is_exact_on_a_non_convex_polygon() {
        // L-shape [0,2]x[0,1] + [0,1]x[1,2]: int x^2 y^3 = (8/3)(1/4) + (1/3)(15/4) = 23/12.
        let l_shape = [
            Point::new(0.0, 0.0),
            Point::new(2.0, 0.0),
            Point::new(2.0, 1.0),
            Point::new(1.0, 1.0),
            Point::new(1.0, 2.0),
            Point::new(0.0, 2.0),
        ];
        let rule = polygon_rule(&l_shape, &TriangleRule::degree5());
        let area: f64 = rule.iter().map(|q| q.weight).sum();
        assert!((area - 3.0).abs() < 1e-14);
        let integral: f64 = rule
            .iter()
            .map(|q| q.weight * q.point.x.powi(2) * q.point.y.powi(3))
            .sum();
        assert!((integral - 23.0 / 12.0).abs() < 1e-14, "{integral}");
    }
}
