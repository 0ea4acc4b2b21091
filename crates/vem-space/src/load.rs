//! Neumann (edge traction) loads.

use crate::quadrature::GaussLegendre;
use crate::{Point, SpaceError, Vector};

/// The load of a traction `g` on the edge from `a` to `b`:
/// `[int g_x phi_a, int g_y phi_a, int g_x phi_b, int g_y phi_b]` with `phi_a`, `phi_b` the
/// linear shape functions of the end points (the trace of every VEM function is linear on an
/// edge), integrated by the `points`-point Gauss–Legendre rule. Exact when `g` is a polynomial
/// of degree <= `2 points - 2` along the edge (the integrand has one degree more).
///
/// Errors: a zero-length or non-finite edge, an unsupported number of points, a non-finite
/// traction value.
///
/// ```
/// use vem_space::{edge_traction_load, Point, Vector};
/// // A constant traction (1, -2) on an edge of length 2: each end point receives half.
/// let load = edge_traction_load(
///     Point::new(0.0, 0.0), Point::new(2.0, 0.0), &|_| Vector::new(1.0, -2.0), 1,
/// )?;
/// assert_eq!(load, [1.0, -2.0, 1.0, -2.0]);
/// # Ok::<(), vem_space::SpaceError>(())
/// ```
pub fn edge_traction_load(
    a: Point,
    b: Point,
    traction: &dyn Fn(Point) -> Vector,
    points: usize,
) -> Result<[f64; 4], SpaceError> {
    let finite = [a.x, a.y, b.x, b.y].iter().all(|c| c.is_finite());
    if !finite || a == b {
        return Err(SpaceError::DegenerateEdge {
            x0: a.x,
            y0: a.y,
            x1: b.x,
            y1: b.y,
        });
    }
    let rule = GaussLegendre::try_new(points)?;
    let mut load = [0.0; 4];
    for (t, q) in rule.on_segment(a, b) {
        let g = traction(q.point);
        if !(g.x.is_finite() && g.y.is_finite()) {
            return Err(SpaceError::NonFiniteLoad {
                x: q.point.x,
                y: q.point.y,
            });
        }
        let (phi_a, phi_b) = (q.weight * (1.0 - t), q.weight * t);
        load[0] += phi_a * g.x;
        load[1] += phi_a * g.y;
        load[2] += phi_b * g.x;
        load[3] += phi_b * g.y;
    }
    Ok(load)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quadratic_traction_is_integrated_exactly_with_two_points() {
        // Edge (1, 1) -> (4, 5), length 5; g(s) = (s^2, 1 - s) in the arc length s in [0, 5].
        // int s^2 (1 - s/5) ds = 125/3 - 125/4 = 125/12,  int s^2 (s/5) ds = 125/4,
        // int (1 - s)(1 - s/5) ds = 5 - 25/2 - 5/2 + 25/3 = -5/3,  int (1 - s)(s/5) = 5/2 - 25/3.
        let (a, b) = (Point::new(1.0, 1.0), Point::new(4.0, 5.0));
        let traction = |x: Point| {
            let s = (x - a).norm();
            Vector::new(s * s, 1.0 - s)
        };
        let expected = [125.0 / 12.0, -5.0 / 3.0, 125.0 / 4.0, 2.5 - 25.0 / 3.0];
        for points in 2..=GaussLegendre::MAX_POINTS {
            let load = edge_traction_load(a, b, &traction, points).unwrap();
            for (l, e) in load.iter().zip(expected) {
                assert!(
                    (l - e).abs() < 1e-13 * e.abs().max(1.0),
                    "{points}: {load:?}"
                );
            }
        }
        // One point is exact only for constants: it misses the quadratic.
        let load = edge_traction_load(a, b, &traction, 1).unwrap();
        assert!((load[0] - expected[0]).abs() > 1.0);
    }

    #[test]
    fn bad_edges_and_values_are_errors() {
        let p = Point::new(1.0, 2.0);
        let constant = |_: Point| Vector::new(1.0, 0.0);
        assert!(matches!(
            edge_traction_load(p, p, &constant, 2),
            Err(SpaceError::DegenerateEdge { .. })
        ));
        let q = Point::new(f64::INFINITY, 0.0);
        assert!(matches!(
            edge_traction_load(p, q, &constant, 2),
            Err(SpaceError::DegenerateEdge { .. })
        ));
        assert!(matches!(
            edge_traction_load(p, Point::new(2.0, 2.0), &constant, 0),
            Err(SpaceError::UnsupportedQuadrature { points: 0, .. })
        ));
        let nan = |x: Point| Vector::new(f64::NAN, x.y);
        let err = edge_traction_load(p, Point::new(2.0, 2.0), &nan, 1).unwrap_err();
        assert_eq!(err, SpaceError::NonFiniteLoad { x: 1.5, y: 2.0 });
    }
}
