//! Shape-regularity figures of assumption A1 (spec section 2) per element and per mesh.
//!
//! A1 asks, for one gamma > 0 and every polygon T of every mesh of a family, with
//! h_T = diam T:
//!
//! * every edge of T is at least gamma h_T long (here an edge is the segment between two
//!   consecutive vertices, so a hanging node splits a side into two edges);
//! * T is star-shaped with respect to a ball of radius at least gamma h_T.
//!
//! [`ElementQuality`] gives both ratios for one polygon and [`QualitySummary`] their
//! distribution over a mesh; gamma of a mesh is the smallest of all these ratios.
//!
//! # The star-shaped radius
//!
//! T is star-shaped with respect to a ball B iff B lies in the kernel of T, the intersection of
//! the inner half-planes n_e . x <= n_e . a_e of its edges (n_e the unit outward normal, a_e a
//! point of edge e). The largest such radius is the Chebyshev radius of that half-plane system,
//! the value of the linear programme
//!
//! ```text
//!     maximise r  subject to  n_e . c + r <= n_e . a_e  for every edge e
//! ```
//!
//! in the three unknowns (c, r). A bounded linear programme attains its optimum at a vertex of
//! its feasible set, where three constraints hold as equalities: [`star_radius`] solves every
//! three edges' equalities (a 2 x 2 system for c once r is eliminated) and keeps the largest r
//! among the feasible points, exactly and without allocation, for polygons of up to
//! [`VERTEX_ENUMERATION_MAX_EDGES`] edges (every mesh of the generators and of Gmsh). Larger
//! polygons, and [`star_centre_and_radius`], which also returns a centre, bisect on r: for a
//! trial r the half-planes are shifted inwards by r and intersected (by clipping a box around
//! T, one half-plane at a time); r is feasible iff the intersection is not empty. The feasible
//! set of r is an interval [0, r*], r* <= h_T / 2, and the bisection stops when the bracket is
//! below 1e-14 h_T. A polygon that is not star-shaped has an empty kernel and radius 0 (the
//! programme's optimum is then negative).
//!
//! ```
//! use vem_mesh::{quality, Point};
//! let square = [
//!     Point::new(0.0, 0.0), Point::new(1.0, 0.0), Point::new(1.0, 1.0), Point::new(0.0, 1.0),
//! ];
//! let q = quality::element_quality(&square);
//! assert!((q.shortest_edge_ratio - 1.0 / 2f64.sqrt()).abs() < 1e-14);
//! assert!((q.star_ratio - 0.5 / 2f64.sqrt()).abs() < 1e-12);
//! ```

use std::fmt;

use crate::{geometry, Mesh, Point, Vector};

/// The A1 figures of one polygon.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ElementQuality {
    /// Diameter h_T (largest distance between two vertices).
    pub diameter: f64,
    /// Shortest edge length divided by h_T.
    pub shortest_edge_ratio: f64,
    /// Radius of the largest ball T is star-shaped with respect to, divided by h_T.
    pub star_ratio: f64,
}

impl ElementQuality {
    /// The smaller of the two ratios: the gamma of A1 for this polygon alone.
    pub fn gamma(&self) -> f64 {
        self.shortest_edge_ratio.min(self.star_ratio)
    }
}

/// The A1 figures of a polygon given by its counter-clockwise vertices (consecutive collinear
/// vertices allowed).
pub fn element_quality(vertices: &[Point]) -> ElementQuality {
    let diameter = geometry::diameter(vertices);
    let m = vertices.len();
    let shortest_edge = (0..m)
        .map(|k| (vertices[(k + 1) % m] - vertices[k]).norm())
        .fold(f64::INFINITY, f64::min);
    ElementQuality {
        diameter,
        shortest_edge_ratio: shortest_edge / diameter,
        star_ratio: star_radius(vertices) / diameter,
    }
}

/// Radius of the largest ball the counter-clockwise polygon `vertices` is star-shaped with
/// respect to (the Chebyshev radius of its kernel; see the module docs). 0 when the polygon is
/// not star-shaped.
///
/// Polygons of at most [`VERTEX_ENUMERATION_MAX_EDGES`] edges are solved exactly, at the
/// vertices of the linear programme (see the module docs); larger ones by the bisection of
/// [`star_centre_and_radius`].
pub fn star_radius(vertices: &[Point]) -> f64 {
    if vertices.len() <= VERTEX_ENUMERATION_MAX_EDGES {
        if let Some(radius) = star_radius_by_vertices(vertices) {
            return radius;
        }
    }
    star_centre_and_radius(vertices).1
}

/// Polygons of at most this many edges have their star radius computed at the vertices of the
/// linear programme ([`star_radius`]): `m (m - 1) (m - 2) / 6` candidate vertices of `m` checks
/// each, fewer operations than the bisection's clipping up to about 16 edges.
pub const VERTEX_ENUMERATION_MAX_EDGES: usize = 16;

/// The value of the linear programme `maximise r subject to n_e . c + r <= b_e` (module docs)
/// at its vertices: every three edges whose constraints, taken as equalities, determine
/// `(c, r)`; the largest `r` among the feasible ones (to 1e-13 of the diameter) is the optimum,
/// which a bounded linear programme attains at a vertex. `None` when the polygon has fewer
/// than three edge directions or no vertex is found feasible (the caller then bisects).
fn star_radius_by_vertices(vertices: &[Point]) -> Option<f64> {
    let m = vertices.len();
    if m < 3 {
        return Some(0.0);
    }
    // Relative to the vertex mean, in units of the diameter, for the conditioning.
    let origin = geometry::vertex_mean(vertices);
    let scale = geometry::diameter(vertices);
    if !(scale > 0.0 && scale.is_finite()) {
        return Some(0.0);
    }
    let mut planes = [(0.0_f64, 0.0_f64, 0.0_f64); VERTEX_ENUMERATION_MAX_EDGES];
    let mut count = 0;
    for k in 0..m {
        let a = (vertices[k] - origin) / scale;
        let t = (vertices[(k + 1) % m] - vertices[k]) / scale;
        let length = t.norm();
        if length > 0.0 {
            let (nx, ny) = (t.y / length, -t.x / length);
            planes[count] = (nx, ny, nx * a.x + ny * a.y);
            count += 1;
        }
    }
    let planes = &planes[..count];
    const FEASIBILITY: f64 = 1e-13;
    let mut best: Option<f64> = None;
    for i in 0..count {
        for j in i + 1..count {
            for k in j + 1..count {
                let (pi, pj, pk) = (planes[i], planes[j], planes[k]);
                // (n_i - n_k) . c = b_i - b_k, (n_j - n_k) . c = b_j - b_k.
                let (a11, a12, r1) = (pi.0 - pk.0, pi.1 - pk.1, pi.2 - pk.2);
                let (a21, a22, r2) = (pj.0 - pk.0, pj.1 - pk.1, pj.2 - pk.2);
                let det = a11 * a22 - a12 * a21;
                // Three normals on the unit circle are never on one line unless two coincide
                // (parallel edges of the same direction): no vertex then.
                if det.abs() < 1e-12 {
                    continue;
                }
                let cx = (r1 * a22 - a12 * r2) / det;
                let cy = (a11 * r2 - r1 * a21) / det;
                let r = pk.2 - pk.0 * cx - pk.1 * cy;
                if best.is_some_and(|b| r <= b) {
                    continue;
                }
                let feasible = planes
                    .iter()
                    .all(|&(nx, ny, b)| nx * cx + ny * cy + r <= b + FEASIBILITY);
                if feasible {
                    best = Some(r);
                }
            }
        }
    }
    best.map(|r| r.max(0.0) * scale)
}

/// Centre and radius of a largest ball the counter-clockwise polygon `vertices` is star-shaped
/// with respect to. The centre is a point of the kernel shrunk by the radius; for a polygon
/// that is not star-shaped the radius is 0 and the centre is the vertex mean.
pub fn star_centre_and_radius(vertices: &[Point]) -> (Point, f64) {
    let m = vertices.len();
    if m < 3 {
        return (geometry::vertex_mean(vertices), 0.0);
    }
    // Work relative to the vertex mean to avoid cancellation far from the origin.
    let origin = geometry::vertex_mean(vertices);
    let local: Vec<Vector> = vertices.iter().map(|p| p - origin).collect();
    // Inner half-planes n . x <= offset, n unit outward normal; zero-length edges impose nothing.
    let half_planes: Vec<(Vector, f64)> = (0..m)
        .filter_map(|k| {
            let (a, b) = (local[k], local[(k + 1) % m]);
            let t = b - a;
            let length = t.norm();
            (length > 0.0).then(|| {
                let n = Vector::new(t.y, -t.x) / length;
                (n, n.dot(&a))
            })
        })
        .collect();
    let extent = local.iter().map(|v| v.norm()).fold(0.0, f64::max);
    let diameter = geometry::diameter(vertices);
    let mut clipped = Vec::with_capacity(m + 4);
    let mut scratch = Vec::with_capacity(m + 4);
    let mut kernel_point = |r: f64| -> Option<Vector> {
        clipped.clear();
        let e = 2.0 * extent + 1.0;
        clipped.extend([
            Vector::new(-e, -e),
            Vector::new(e, -e),
            Vector::new(e, e),
            Vector::new(-e, e),
        ]);
        for &(n, offset) in &half_planes {
            clip(&clipped, n, offset - r, &mut scratch);
            std::mem::swap(&mut clipped, &mut scratch);
            if clipped.is_empty() {
                return None;
            }
        }
        let sum = clipped.iter().fold(Vector::zeros(), |acc, v| acc + v);
        Some(sum / clipped.len() as f64)
    };
    let Some(mut centre) = kernel_point(0.0) else {
        return (origin, 0.0);
    };
    let (mut low, mut high) = (0.0, 0.5 * diameter);
    while high - low > 1e-14 * diameter {
        let mid = 0.5 * (low + high);
        match kernel_point(mid) {
            Some(c) => {
                centre = c;
                low = mid;
            }
            None => high = mid,
        }
    }
    (origin + centre, low)
}

/// Sutherland–Hodgman clipping of the convex polygon `polygon` to n . x <= offset, into `out`.
fn clip(polygon: &[Vector], n: Vector, offset: f64, out: &mut Vec<Vector>) {
    out.clear();
    let count = polygon.len();
    for k in 0..count {
        let (a, b) = (polygon[k], polygon[(k + 1) % count]);
        let (sa, sb) = (n.dot(&a) - offset, n.dot(&b) - offset);
        if sa <= 0.0 {
            out.push(a);
        }
        if (sa < 0.0 && sb > 0.0) || (sa > 0.0 && sb < 0.0) {
            out.push(a + (b - a) * (sa / (sa - sb)));
        }
    }
}

/// Minimum, median and maximum of one figure over the elements of a mesh.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spread {
    /// Smallest value.
    pub min: f64,
    /// Median (mean of the two middle values for an even count).
    pub median: f64,
    /// Largest value.
    pub max: f64,
}

impl Spread {
    /// The spread of `values` (all NaN-free); zeros for an empty slice.
    pub fn of(values: &[f64]) -> Self {
        if values.is_empty() {
            return Self {
                min: 0.0,
                median: 0.0,
                max: 0.0,
            };
        }
        let mut sorted = values.to_vec();
        sorted.sort_by(f64::total_cmp);
        let n = sorted.len();
        let median = if n % 2 == 1 {
            sorted[n / 2]
        } else {
            0.5 * (sorted[n / 2 - 1] + sorted[n / 2])
        };
        Self {
            min: sorted[0],
            median,
            max: sorted[n - 1],
        }
    }
}

/// The distribution of the A1 figures over a mesh.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct QualitySummary {
    /// Number of polygons.
    pub elements: usize,
    /// Element diameters h_T; `diameter.max` is the mesh size h.
    pub diameter: Spread,
    /// Shortest edge / h_T.
    pub shortest_edge_ratio: Spread,
    /// Star-shaped radius / h_T.
    pub star_ratio: Spread,
    /// gamma of A1 for this mesh: the smallest of both ratios over all elements.
    pub gamma: f64,
}

impl QualitySummary {
    /// Mesh size h = max h_T.
    pub fn mesh_size(&self) -> f64 {
        self.diameter.max
    }
}

impl fmt::Display for QualitySummary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "{} elements, h = {:.4e}, gamma (A1) = {:.4}",
            self.elements,
            self.mesh_size(),
            self.gamma
        )?;
        writeln!(f, "{:<22}{:>11}{:>11}{:>11}", "", "min", "median", "max")?;
        for (name, s) in [
            ("h_T", self.diameter),
            ("shortest edge / h_T", self.shortest_edge_ratio),
            ("star radius / h_T", self.star_ratio),
        ] {
            writeln!(
                f,
                "{name:<22}{:>11.4e}{:>11.4e}{:>11.4e}",
                s.min, s.median, s.max
            )?;
        }
        Ok(())
    }
}

/// The A1 figures of every polygon of `mesh`, in polygon order (on every thread with the
/// `parallel` feature).
pub fn element_qualities(mesh: &Mesh) -> Vec<ElementQuality> {
    let quality = |points: &mut Vec<Point>, p: usize| {
        points.clear();
        points.extend(mesh.polygon(p).iter().map(|&v| mesh.vertex(v)));
        element_quality(points)
    };
    #[cfg(feature = "parallel")]
    {
        use rayon::prelude::*;
        (0..mesh.n_polygons())
            .into_par_iter()
            .map_init(Vec::new, quality)
            .collect()
    }
    #[cfg(not(feature = "parallel"))]
    {
        let mut points = Vec::new();
        (0..mesh.n_polygons())
            .map(|p| quality(&mut points, p))
            .collect()
    }
}

/// The distribution of the A1 figures over `mesh`.
///
/// ```
/// use vem_mesh::generators::{structured_quads, Rectangle};
/// let mesh = structured_quads(&Rectangle::unit_square(), 4, 4)?;
/// let summary = vem_mesh::quality::summarise(&mesh);
/// assert!((summary.gamma - 0.5 / 2f64.sqrt()).abs() < 1e-12);
/// println!("{summary}");
/// # Ok::<(), vem_mesh::MeshError>(())
/// ```
pub fn summarise(mesh: &Mesh) -> QualitySummary {
    let qualities = element_qualities(mesh);
    let pick = |f: fn(&ElementQuality) -> f64| -> Vec<f64> { qualities.iter().map(f).collect() };
    let shortest_edge_ratio = Spread::of(&pick(|q| q.shortest_edge_ratio));
    let star_ratio = Spread::of(&pick(|q| q.star_ratio));
    QualitySummary {
        elements: qualities.len(),
        diameter: Spread::of(&pick(|q| q.diameter)),
        shortest_edge_ratio,
        star_ratio,
        gamma: shortest_edge_ratio.min.min(star_ratio.min),
    }
}

impl Mesh {
    /// The A1 figures of polygon `p`.
    pub fn element_quality(&self, p: usize) -> ElementQuality {
        element_quality(&self.polygon_points(p))
    }

    /// The distribution of the A1 figures over the mesh (see [`summarise`]).
    pub fn quality(&self) -> QualitySummary {
        summarise(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn l_shape_kernel_is_the_unit_square() {
        // L = [0,2]x[0,1] + [0,1]x[1,2]: kernel [0,1]^2, so the radius is 1/2 at (1/2, 1/2);
        // h_T = |(2,0) - (0,2)| = 2 sqrt 2, shortest edge 1.
        let l_shape = [
            Point::new(0.0, 0.0),
            Point::new(2.0, 0.0),
            Point::new(2.0, 1.0),
            Point::new(1.0, 1.0),
            Point::new(1.0, 2.0),
            Point::new(0.0, 2.0),
        ];
        let (centre, radius) = star_centre_and_radius(&l_shape);
        assert_relative_eq!(radius, 0.5, max_relative = 1e-12);
        assert_relative_eq!(centre.x, 0.5, epsilon = 1e-6);
        assert_relative_eq!(centre.y, 0.5, epsilon = 1e-6);
        let q = element_quality(&l_shape);
        assert_relative_eq!(q.diameter, 2.0 * 2f64.sqrt(), max_relative = 1e-15);
        assert_relative_eq!(
            q.shortest_edge_ratio,
            1.0 / (2.0 * 2f64.sqrt()),
            max_relative = 1e-14
        );
        assert_relative_eq!(
            q.star_ratio,
            0.5 / (2.0 * 2f64.sqrt()),
            max_relative = 1e-12
        );
    }

    #[test]
    fn not_star_shaped_has_radius_zero() {
        // A U shape: no point sees the inner sides of both arms.
        let u_shape = [
            Point::new(0.0, 0.0),
            Point::new(3.0, 0.0),
            Point::new(3.0, 3.0),
            Point::new(2.0, 3.0),
            Point::new(2.0, 1.0),
            Point::new(1.0, 1.0),
            Point::new(1.0, 3.0),
            Point::new(0.0, 3.0),
        ];
        // Kernel: x <= 1 (from the edge (1,1)-(1,3)) and x >= 2 (from (2,3)-(2,1)): empty.
        assert_eq!(star_radius(&u_shape), 0.0);
    }

    #[test]
    fn square_and_equilateral_triangle() {
        // Unit square: shortest edge 1 and inscribed radius 1/2 against h_T = sqrt 2.
        let square = [
            Point::new(0.0, 0.0),
            Point::new(1.0, 0.0),
            Point::new(1.0, 1.0),
            Point::new(0.0, 1.0),
        ];
        let q = element_quality(&square);
        assert_relative_eq!(
            q.shortest_edge_ratio,
            1.0 / 2f64.sqrt(),
            max_relative = 1e-15
        );
        assert_relative_eq!(q.star_ratio, 0.5 / 2f64.sqrt(), max_relative = 1e-12);
        assert_relative_eq!(q.gamma(), 0.5 / 2f64.sqrt(), max_relative = 1e-12);
        // Equilateral triangle of side 1: h_T = 1, inradius 1 / (2 sqrt 3).
        let triangle = [
            Point::new(0.0, 0.0),
            Point::new(1.0, 0.0),
            Point::new(0.5, 3f64.sqrt() / 2.0),
        ];
        let q = element_quality(&triangle);
        assert_relative_eq!(q.shortest_edge_ratio, 1.0, max_relative = 1e-15);
        assert_relative_eq!(
            q.star_ratio,
            1.0 / (2.0 * 3f64.sqrt()),
            max_relative = 1e-12
        );
    }

    #[test]
    fn figures_do_not_depend_on_position_or_scale() {
        let chevron = [
            Point::new(0.0, 0.0),
            Point::new(0.5, 0.25),
            Point::new(1.0, 0.0),
            Point::new(1.0, 1.0),
            Point::new(0.5, 1.25),
            Point::new(0.0, 1.0),
        ];
        let reference = element_quality(&chevron);
        let moved: Vec<Point> = chevron
            .iter()
            .map(|p| Point::new(1e3 + 1e-3 * p.x, -3e2 + 1e-3 * p.y))
            .collect();
        let q = element_quality(&moved);
        assert_relative_eq!(q.diameter, 1e-3 * reference.diameter, max_relative = 1e-8);
        assert_relative_eq!(q.star_ratio, reference.star_ratio, max_relative = 1e-8);
        // Chebyshev radius of the chevron's kernel: 1 / (2 sqrt(1 + 4 s^2)) with s = 1/4.
        assert_relative_eq!(
            star_radius(&chevron),
            1.0 / (2.0 * 1.25f64.sqrt()),
            max_relative = 1e-12
        );
    }

    #[test]
    fn hanging_node_splits_an_edge() {
        // A square with a hanging node in the middle of its bottom side: shortest edge 1/2.
        let square = [
            Point::new(0.0, 0.0),
            Point::new(0.5, 0.0),
            Point::new(1.0, 0.0),
            Point::new(1.0, 1.0),
            Point::new(0.0, 1.0),
        ];
        let q = element_quality(&square);
        assert_relative_eq!(
            q.shortest_edge_ratio,
            0.5 / 2f64.sqrt(),
            max_relative = 1e-15
        );
        assert_relative_eq!(q.star_ratio, 0.5 / 2f64.sqrt(), max_relative = 1e-12);
    }

    #[test]
    fn vertex_enumeration_agrees_with_the_bisection() {
        // Star-shaped, convex and non-star-shaped polygons from a deterministic sequence:
        // radii of a polygon around the origin at increasing angles (some collinear
        // consecutive vertices, some very thin).
        let mut state = 12345_u64;
        let mut uniform = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut checked = 0;
        for case in 0..4000 {
            let m = 3 + case % 14;
            let mut angles: Vec<f64> = (0..m).map(|_| uniform() * std::f64::consts::TAU).collect();
            angles.sort_by(f64::total_cmp);
            let spread = if case % 3 == 0 { 0.9 } else { 0.3 };
            let polygon: Vec<Point> = angles
                .iter()
                .map(|&t| {
                    let r = 1.0 - spread * uniform();
                    Point::new(2.0 + r * t.cos(), -1.0 + 0.5 * r * t.sin())
                })
                .collect();
            if geometry::signed_area(&polygon) <= 0.0 {
                continue;
            }
            let exact = star_radius_by_vertices(&polygon).expect("a vertex");
            let (_, bisected) = star_centre_and_radius(&polygon);
            let h = geometry::diameter(&polygon);
            assert!(
                (exact - bisected).abs() <= 1e-12 * h,
                "{polygon:?}: {exact} against {bisected}"
            );
            checked += 1;
        }
        assert!(checked > 3000, "{checked}");
        // A degenerate polygon: collinear consecutive vertices repeat a normal.
        let square = [
            Point::new(0.0, 0.0),
            Point::new(0.5, 0.0),
            Point::new(1.0, 0.0),
            Point::new(1.0, 0.5),
            Point::new(1.0, 1.0),
            Point::new(0.0, 1.0),
        ];
        assert_relative_eq!(star_radius(&square), 0.5, max_relative = 1e-14);
    }

    #[test]
    fn spread_median_of_even_count() {
        let s = Spread::of(&[4.0, 1.0, 3.0, 2.0]);
        assert_eq!((s.min, s.median, s.max), (1.0, 2.5, 4.0));
    }
}
