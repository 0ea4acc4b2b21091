//! Quadrature rules shared by the element, load and error-norm code.
//!
//! - [`GaussLegendre`]: `p`-point Gauss–Legendre rules on a segment, `p = 1..=6`, exact for
//!   polynomials of degree `2p - 1` (used for Neumann tractions, [`crate::edge_traction_load`]).
//! - [`TriangleRule`]: the 7-point degree-5 rule of Radon (Dunavant's degree-5 rule) on a
//!   triangle, with positive weights and interior points.
//! - [`polygon_rule`]: a rule on a polygon from the fan of triangles joining the centroid to each
//!   edge (weights carry the signed sub-triangle areas, so polynomials up to the rule's degree
//!   are integrated exactly on any simple polygon, convex or not).
//! - In space: [`TetrahedronRule`] (a 4-point degree-2 rule, Walkington's 14-point degree-5
//!   rule and the conical products of Gauss–Legendre rules, degree `2p - 3`), [`polyhedron_rule`] (the rule on the signed
//!   tetrahedra joining the centroid to the fan triangles of every face, exact on any polyhedron
//!   with planar faces, convex or not) and [`face_rule`] (a triangle rule on the fan triangles of
//!   a face in space).
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

use crate::{Point, PointD, SpaceError};

/// One point of a quadrature rule in physical coordinates of `R^D` (`D = 2` by default) with
/// its weight (the integral of `f` is approximated by the sum of `weight * f(point)`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct QuadraturePoint<const D: usize = 2> {
    /// Where the integrand is evaluated.
    pub point: PointD<D>,
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
    let mut points = Vec::with_capacity(polygon.len() * rule.barycentric().len());
    points.extend(polygon_points(polygon, rule));
    points
}

/// The points of [`polygon_rule`], in the same order, without collecting them (the load of
/// every cell of an assembly sums over them).
pub(crate) fn polygon_points<'a>(
    polygon: &'a [Point],
    rule: &'a TriangleRule,
) -> impl Iterator<Item = QuadraturePoint> + 'a {
    let n = polygon.len();
    let centroid = geometry::centroid(polygon);
    (0..n).flat_map(move |k| rule.on_triangle(centroid, polygon[k], polygon[(k + 1) % n]))
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

/// A quadrature rule on a tetrahedron in barycentric coordinates (weights sum to 1).
///
/// ```
/// use vem_space::quadrature::TetrahedronRule;
/// use vem_mesh::Point3;
/// let rule = TetrahedronRule::conical(4)?; // degree 5
/// let [a, b, c, d] = [
///     Point3::new(0.0, 0.0, 0.0), Point3::new(1.0, 0.0, 0.0),
///     Point3::new(0.0, 1.0, 0.0), Point3::new(0.0, 0.0, 1.0),
/// ];
/// // int x^2 y z over the unit tetrahedron = 2! 1! 1! / 7! = 1/2520.
/// let integral: f64 = rule
///     .on_tetrahedron(a, b, c, d)
///     .map(|q| q.weight * q.point.x.powi(2) * q.point.y * q.point.z)
///     .sum();
/// assert!((integral - 1.0 / 2520.0).abs() < 1e-17);
/// # Ok::<(), vem_space::SpaceError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct TetrahedronRule {
    points: Vec<([f64; 4], f64)>,
    degree: usize,
}

impl TetrahedronRule {
    /// The symmetric 4-point rule of degree 2: the points `(a, b, b, b)` and permutations with
    /// `b = (5 - sqrt 5)/20`, `a = 1 - 3 b`, equal weights (Keast's rule of degree 2).
    pub fn degree2() -> Self {
        let b = (5.0 - 5f64.sqrt()) / 20.0;
        let a = 1.0 - 3.0 * b;
        Self {
            points: vec![
                ([a, b, b, b], 0.25),
                ([b, a, b, b], 0.25),
                ([b, b, a, b], 0.25),
                ([b, b, b, a], 0.25),
            ],
            degree: 2,
        }
    }

    /// Walkington's symmetric 14-point rule of degree 5 ("Quadrature on simplices of arbitrary
    /// dimension", CMU 2000): positive weights, interior points; the orbits
    /// `(a, a, a, 1 - 3a)` for `a = 0.31088591926330061` and `a = 0.092735250310891226`, and
    /// `(b, b, 1/2 - b, 1/2 - b)` for `b = 0.045503704125649649`. The rule of the error norms.
    pub fn degree5() -> Self {
        let mut points = Vec::with_capacity(14);
        for (a, w) in [
            (0.310_885_919_263_300_6, 0.112_687_925_718_015_85),
            (0.092_735_250_310_891_23, 0.073_493_043_116_361_95),
        ] {
            for k in 0..4 {
                let mut l = [a; 4];
                l[k] = 1.0 - 3.0 * a;
                points.push((l, w));
            }
        }
        let (b, w) = (0.045_503_704_125_649_65, 0.042_546_020_777_081_466);
        for i in 0..4 {
            for j in i + 1..4 {
                let mut l = [b; 4];
                l[i] = 0.5 - b;
                l[j] = 0.5 - b;
                points.push((l, w));
            }
        }
        Self { points, degree: 5 }
    }

    /// The conical product of `p`-point Gauss–Legendre rules (`p^3` points, positive weights,
    /// interior points), exact for polynomials of degree `2p - 3`: the collapsed coordinates
    /// `x = u`, `y = (1 - u) v`, `z = (1 - u)(1 - v) w` with the Jacobian `(1 - u)^2 (1 - v)`.
    pub fn conical(p: usize) -> Result<Self, SpaceError> {
        let rule = GaussLegendre::try_new(p)?;
        if p < 2 {
            return Err(SpaceError::UnsupportedQuadrature {
                rule: "conical tetrahedron (p >= 2)",
                points: p,
                max: GaussLegendre::MAX_POINTS,
            });
        }
        let unit = |s: f64| 0.5 * (1.0 + s);
        let mut points = Vec::with_capacity(p * p * p);
        for (&su, &wu) in rule.nodes().iter().zip(rule.weights()) {
            for (&sv, &wv) in rule.nodes().iter().zip(rule.weights()) {
                for (&sw, &ww) in rule.nodes().iter().zip(rule.weights()) {
                    let (u, v, w) = (unit(su), unit(sv), unit(sw));
                    let (x, y, z) = (u, (1.0 - u) * v, (1.0 - u) * (1.0 - v) * w);
                    // Reference volume 1/6; each unit-interval weight is w/2.
                    let weight = 6.0 * wu * wv * ww / 8.0 * (1.0 - u).powi(2) * (1.0 - v);
                    points.push(([1.0 - x - y - z, x, y, z], weight));
                }
            }
        }
        Ok(Self {
            points,
            degree: 2 * p - 3,
        })
    }

    /// Highest polynomial degree integrated exactly.
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// The points as `(barycentric coordinates, weight)`, the weights summing to 1.
    pub fn barycentric(&self) -> &[([f64; 4], f64)] {
        &self.points
    }

    /// The rule on the tetrahedron `(a, b, c, d)`: the weights sum to its signed volume
    /// `det(b - a, c - a, d - a)/6` (negative when the corners are ordered left-handed, which
    /// is what a decomposition of a non-convex polyhedron needs).
    pub fn on_tetrahedron(
        &self,
        a: PointD<3>,
        b: PointD<3>,
        c: PointD<3>,
        d: PointD<3>,
    ) -> impl ExactSizeIterator<Item = QuadraturePoint<3>> + '_ {
        let (ab, ac, ad) = (b - a, c - a, d - a);
        let volume = ab.cross(&ac).dot(&ad) / 6.0;
        self.points
            .iter()
            .map(move |&([_, lb, lc, ld], w)| QuadraturePoint {
                point: a + ab * lb + ac * lc + ad * ld,
                weight: w * volume,
            })
    }
}

/// A rule on the polyhedron `polyhedron` (faces oriented outward): `rule` on each signed
/// tetrahedron joining the centroid to a fan triangle `(x_k, x_{k+1}, xbar_F)` of a face (on a
/// tetrahedron, `rule` on the tetrahedron itself). The
/// weights carry the signed volumes, so the rule is exact for polynomials of degree
/// `rule.degree()` on any polyhedron with planar faces (and on the fan-defined body of warped
/// faces); points lie outside a polyhedron that is not star-shaped with respect to its centroid.
pub fn polyhedron_rule(
    polyhedron: &vem_mesh::polyhedral::geometry::Polyhedron,
    rule: &TetrahedronRule,
) -> Vec<QuadraturePoint<3>> {
    // A tetrahedron is its own decomposition: the rule once instead of on twelve pieces.
    if let ([a, b, c, d], 4) = (polyhedron.points(), polyhedron.n_faces()) {
        if polyhedron.faces().all(|f| f.len() == 3) {
            let volume = (b - a).cross(&(c - a)).dot(&(d - a));
            // Corners in a right-handed order, so that the weights are positive.
            let (b, c) = if volume >= 0.0 { (*b, *c) } else { (*c, *b) };
            return rule.on_tetrahedron(*a, b, c, *d).collect();
        }
    }
    let centre = polyhedron.centroid();
    let mut points = Vec::new();
    let mut face = Vec::new();
    for loop_ in polyhedron.faces() {
        face.clear();
        face.extend(loop_.iter().map(|&v| polyhedron.points()[v]));
        let mean = vem_mesh::polyhedral::geometry::vertex_mean(&face);
        let n = face.len();
        for i in 0..n {
            points.extend(rule.on_tetrahedron(centre, face[i], face[(i + 1) % n], mean));
        }
    }
    points
}

/// A rule on the face `face` (a vertex loop in space): `rule` on each fan triangle
/// `(x_k, x_{k+1}, xbar_F)` about the vertex mean, each weighted by its area with the sign of
/// its orientation against the face's normal (so that a planar face of any shape is integrated
/// exactly to the rule's degree). The item also tells the fan triangle `k` and the barycentric
/// coordinates `(l_k, l_{k+1}, l_mean)` of the point, from which the fan trace of a field is
/// evaluated.
pub fn face_rule<'a>(
    face: &'a [PointD<3>],
    rule: &'a TriangleRule,
) -> impl Iterator<Item = (usize, [f64; 3], QuadraturePoint<3>)> + 'a {
    let mean = vem_mesh::polyhedral::geometry::vertex_mean(face);
    let normal = vem_mesh::polyhedral::geometry::face_normal(face);
    let n = face.len();
    (0..n).flat_map(move |k| {
        let (a, b) = (face[k], face[(k + 1) % n]);
        let vector_area = 0.5 * (a - mean).cross(&(b - mean));
        let signed_area = vector_area.norm().copysign(vector_area.dot(&normal));
        rule.barycentric().iter().map(move |&(l, w)| {
            (
                k,
                l,
                QuadraturePoint {
                    point: PointD::<3>::from(
                        l[0] * a.coords + l[1] * b.coords + l[2] * mean.coords,
                    ),
                    weight: w * signed_area,
                },
            )
        })
    })
}

/// The conical product of `p`-point Gauss–Legendre rules on a triangle (`p^2` points, positive
/// weights), exact for polynomials of degree `2p - 2`: `x = u`, `y = (1 - u) v`, Jacobian
/// `1 - u`. With [`TriangleRule`], this gives rules of any degree up to 10 on the fan
/// triangles of faces in space.
pub fn conical_triangle_rule(p: usize) -> Result<TriangleRule, SpaceError> {
    GaussLegendre::try_new(p)?;
    // The six tables are built once and live as long as the program (as the other tables).
    static RULES: std::sync::OnceLock<Vec<TriangleRule>> = std::sync::OnceLock::new();
    let rules = RULES.get_or_init(|| {
        (1..=GaussLegendre::MAX_POINTS)
            .map(|p| {
                let rule = GaussLegendre::try_new(p).expect("tabulated");
                let unit = |s: f64| 0.5 * (1.0 + s);
                let mut points = Vec::with_capacity(p * p);
                for (&su, &wu) in rule.nodes().iter().zip(rule.weights()) {
                    for (&sv, &wv) in rule.nodes().iter().zip(rule.weights()) {
                        let (u, v) = (unit(su), unit(sv));
                        let (x, y) = (u, (1.0 - u) * v);
                        // Reference area 1/2; each unit-interval weight is w/2.
                        points.push(([1.0 - x - y, x, y], 2.0 * wu * wv / 4.0 * (1.0 - u)));
                    }
                }
                TriangleRule {
                    points: Box::leak(points.into_boxed_slice()),
                    degree: 2 * p - 2,
                }
            })
            .collect()
    });
    Ok(rules[p - 1])
}

#[cfg(test)]
mod solid_tests {
    use super::*;
    use vem_mesh::polyhedral::geometry::Polyhedron;
    use vem_mesh::Point3;

    fn factorial(k: u32) -> f64 {
        (1..=k).map(f64::from).product()
    }

    /// int over the unit tetrahedron of x^i y^j z^k = i! j! k! / (i + j + k + 3)!.
    fn monomial_on_tetrahedron(i: u32, j: u32, k: u32) -> f64 {
        factorial(i) * factorial(j) * factorial(k) / factorial(i + j + k + 3)
    }

    #[test]
    fn tetrahedron_rules_are_exact_to_their_degree() {
        let mut rules = vec![TetrahedronRule::degree2(), TetrahedronRule::degree5()];
        for p in 2..=GaussLegendre::MAX_POINTS {
            rules.push(TetrahedronRule::conical(p).unwrap());
        }
        let corners = [
            Point3::origin(),
            Point3::new(1.0, 0.0, 0.0),
            Point3::new(0.0, 1.0, 0.0),
            Point3::new(0.0, 0.0, 1.0),
        ];
        for rule in &rules {
            let total: f64 = rule.barycentric().iter().map(|p| p.1).sum();
            assert!((total - 1.0).abs() < 1e-14);
            assert!(rule.barycentric().iter().all(|p| p.1 > 0.0));
            let d = rule.degree() as u32;
            for i in 0..=d {
                for j in 0..=d - i {
                    for k in 0..=d - i - j {
                        let integral: f64 = rule
                            .on_tetrahedron(corners[0], corners[1], corners[2], corners[3])
                            .map(|q| {
                                q.weight
                                    * q.point.x.powi(i as i32)
                                    * q.point.y.powi(j as i32)
                                    * q.point.z.powi(k as i32)
                            })
                            .sum();
                        let exact = monomial_on_tetrahedron(i, j, k);
                        assert!(
                            (integral - exact).abs() < 1e-14 * exact.max(1e-3),
                            "degree {d}: x^{i} y^{j} z^{k}: {integral} vs {exact}"
                        );
                    }
                }
            }
        }
        // One degree more is not exact for the conical rules (x^(2p - 2)).
        let rule = TetrahedronRule::conical(3).unwrap();
        let integral: f64 = rule
            .on_tetrahedron(corners[0], corners[1], corners[2], corners[3])
            .map(|q| q.weight * q.point.x.powi(4))
            .sum();
        assert!((integral - monomial_on_tetrahedron(4, 0, 0)).abs() > 1e-8);
    }

    #[test]
    fn triangle_rules_in_space_are_exact_to_their_degree() {
        for p in 1..=GaussLegendre::MAX_POINTS {
            let rule = conical_triangle_rule(p).unwrap();
            let d = rule.degree() as i32;
            // The unit triangle in the plane z = 2, tilted copies would scale by the area.
            let face = [
                Point3::new(0.0, 0.0, 2.0),
                Point3::new(1.0, 0.0, 2.0),
                Point3::new(0.0, 1.0, 2.0),
            ];
            for i in 0..=d {
                for j in 0..=d - i {
                    let integral: f64 = face_rule(&face, &rule)
                        .map(|(_, _, q)| q.weight * q.point.x.powi(i) * q.point.y.powi(j))
                        .sum();
                    let exact = factorial(i as u32) * factorial(j as u32)
                        / factorial(i as u32 + j as u32 + 2);
                    assert!(
                        (integral - exact).abs() < 1e-14,
                        "p = {p}: x^{i} y^{j}: {integral} vs {exact}"
                    );
                }
            }
        }
    }

    #[test]
    fn polyhedron_rule_integrates_a_non_convex_prism() {
        // An L-shaped prism of height 2: the L of area 3 in z = 0 and z = 2.
        let l = [
            (0.0, 0.0),
            (2.0, 0.0),
            (2.0, 1.0),
            (1.0, 1.0),
            (1.0, 2.0),
            (0.0, 2.0),
        ];
        let mut points: Vec<Point3> = l.iter().map(|&(x, y)| Point3::new(x, y, 0.0)).collect();
        points.extend(l.iter().map(|&(x, y)| Point3::new(x, y, 2.0)));
        let mut faces = vec![(0..6).rev().collect::<Vec<_>>(), (6..12).collect()];
        for k in 0..6 {
            faces.push(vec![k, (k + 1) % 6, 6 + (k + 1) % 6, 6 + k]);
        }
        let prism = Polyhedron::new(points, &faces);
        let rule = polyhedron_rule(&prism, &TetrahedronRule::conical(4).unwrap());
        let volume: f64 = rule.iter().map(|q| q.weight).sum();
        assert!((volume - 6.0).abs() < 1e-13);
        // int x^2 z^3 = (int_L x^2) (int_0^2 z^3) = (8/3 + 1/3 ... ) computed by hand:
        // int_L x^2 = int_0^2 x^2 dx int_0^1 dy + int_0^1 x^2 dx int_1^2 dy = 8/3 + 1/3 = 3.
        let integral: f64 = rule
            .iter()
            .map(|q| q.weight * q.point.x.powi(2) * q.point.z.powi(3))
            .sum();
        assert!((integral - 3.0 * 4.0).abs() < 1e-12, "{integral}");
    }
}
