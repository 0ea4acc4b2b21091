//! Rigid obstacles: a gap function, not a mesh.
//!
//! A body pressed against a rigid obstacle is the one-body contact problem: nothing is meshed
//! or assembled for the obstacle. At each contact node `x` of the body the obstacle gives a
//! contact direction `nu` (unit, pointing from the body into the obstacle) and the gap `g(x)`
//! along it; the nodal constraint is `u(x) . nu <= g(x)` (the linearised non-penetration
//! condition, exact for a straight obstacle).
//!
//! An obstacle is anything that implements [`RigidObstacle`]; [`Obstacle`] holds the planar
//! ones built in (a line, a disc, a polyline), [`Obstacle3`] those in space (a plane, a ball).

use std::fmt;

use vem_mesh::{Point, Point3, PointD, Vector, Vector3, VectorD};

use crate::ContactError;

/// A rigid obstacle in `R^D`: at every point of a body's contact part, the direction from the
/// body into the obstacle and the gap along it.
pub trait RigidObstacle<const D: usize = 2>: Send + Sync + fmt::Debug {
    /// A short name for reports ("line", "circle", ...).
    fn name(&self) -> &str;

    /// Checks the obstacle's data.
    ///
    /// # Errors
    /// [`ContactError::InvalidObstacle`] naming what is wrong.
    fn validate(&self) -> Result<(), ContactError>;

    /// The unit contact direction `nu` (from the body into the obstacle) and the signed gap
    /// along it at the body point `x` (negative: `x` starts inside the obstacle).
    fn gap_at(&self, x: PointD<D>) -> ObstacleGap<D>;
}

/// A rigid obstacle.
#[derive(Debug, Clone, PartialEq)]
pub enum Obstacle {
    /// The straight line through `point` bounding the half-plane obstacle; `normal` is the unit
    /// normal pointing out of the obstacle, towards the body.
    Line {
        /// A point of the line.
        point: Point,
        /// Outward normal of the obstacle (normalised on use).
        normal: Vector,
    },
    /// A rigid disc; the body lies outside it.
    Circle {
        /// Centre of the disc.
        centre: Point,
        /// Radius (> 0).
        radius: f64,
    },
    /// A polyline (at least two distinct points); the obstacle lies to the RIGHT of the
    /// direction of travel, so its outward normal is the left normal of each segment.
    Polyline(Vec<Point>),
}

/// What an obstacle says at one body node: the contact direction and the gap along it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ObstacleGap<const D: usize = 2> {
    /// Unit contact direction `nu`, from the body into the obstacle.
    pub normal: VectorD<D>,
    /// Signed gap along `nu` (negative: the node starts inside the obstacle).
    pub gap: f64,
}

impl RigidObstacle<2> for Obstacle {
    fn name(&self) -> &str {
        match self {
            Obstacle::Line { .. } => "line",
            Obstacle::Circle { .. } => "circle",
            Obstacle::Polyline(_) => "polyline",
        }
    }

    /// Checks the obstacle's data (finite values, positive radius, non-degenerate line).
    fn validate(&self) -> Result<(), ContactError> {
        let bad = |reason: String| Err(ContactError::InvalidObstacle { reason });
        match self {
            Obstacle::Line { point, normal } => {
                if !(point
                    .coords
                    .iter()
                    .chain(normal.iter())
                    .all(|c| c.is_finite()))
                {
                    return bad(format!(
                        "line through {point} with normal {normal} is not finite"
                    ));
                }
                if normal.norm() == 0.0 {
                    return bad("line normal is the zero vector".into());
                }
            }
            Obstacle::Circle { centre, radius } => {
                if !(centre.coords.iter().all(|c| c.is_finite()) && radius.is_finite()) {
                    return bad(format!(
                        "circle at {centre} with radius {radius} is not finite"
                    ));
                }
                if *radius <= 0.0 {
                    return bad(format!("circle radius {radius} must be positive"));
                }
            }
            Obstacle::Polyline(points) => {
                if points.len() < 2 {
                    return bad(format!(
                        "a polyline needs at least 2 points, got {}",
                        points.len()
                    ));
                }
                if let Some((i, p)) = points
                    .iter()
                    .enumerate()
                    .find(|(_, p)| !p.coords.iter().all(|c| c.is_finite()))
                {
                    return bad(format!("polyline point {i} ({p}) is not finite"));
                }
                if let Some(i) = points.windows(2).position(|w| w[0] == w[1]) {
                    return bad(format!("polyline points {i} and {} coincide", i + 1));
                }
            }
        }
        Ok(())
    }

    /// Contact direction and gap at the body point `x` (see the module docs).
    fn gap_at(&self, x: Point) -> ObstacleGap {
        match self {
            Obstacle::Line { point, normal } => {
                let n = normal / normal.norm();
                ObstacleGap {
                    normal: -n,
                    gap: (x - point).dot(&n),
                }
            }
            Obstacle::Circle { centre, radius } => {
                let to_centre = centre - x;
                let distance = to_centre.norm();
                ObstacleGap {
                    normal: to_centre / distance,
                    gap: distance - radius,
                }
            }
            Obstacle::Polyline(points) => polyline_gap(points, x),
        }
    }
}

/// A rigid obstacle in space.
///
/// ```
/// use vem_contact::{Obstacle3, RigidObstacle};
/// use vem_mesh::{Point3, Vector3};
/// // A rigid ball of radius 2 centred 3 above the origin: the origin is 1 below its surface.
/// let ball = Obstacle3::Sphere { centre: Point3::new(0.0, 0.0, 3.0), radius: 2.0 };
/// ball.validate()?;
/// let at = ball.gap_at(Point3::origin());
/// assert!((at.gap - 1.0).abs() < 1e-15);
/// assert_eq!(at.normal, Vector3::new(0.0, 0.0, 1.0));
/// # Ok::<(), vem_contact::ContactError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub enum Obstacle3 {
    /// The plane through `point` bounding the half-space obstacle; `normal` is the normal
    /// pointing out of the obstacle, towards the body (normalised on use).
    Plane {
        /// A point of the plane.
        point: Point3,
        /// Outward normal of the obstacle.
        normal: Vector3,
    },
    /// A rigid ball; the body lies outside it. The contact direction at a body point `x` is
    /// towards the centre and the gap is `|c - x| - R`, the distance to the sphere: near the
    /// point of first contact of a flat body it is `r^2 / (2 R)` to leading order in the
    /// distance `r` from that point, the gap of Hertz's theory.
    Sphere {
        /// Centre of the ball.
        centre: Point3,
        /// Radius (> 0).
        radius: f64,
    },
}

impl RigidObstacle<3> for Obstacle3 {
    fn name(&self) -> &str {
        match self {
            Obstacle3::Plane { .. } => "plane",
            Obstacle3::Sphere { .. } => "sphere",
        }
    }

    /// Checks the obstacle's data (finite values, positive radius, non-zero normal).
    fn validate(&self) -> Result<(), ContactError> {
        let bad = |reason: String| Err(ContactError::InvalidObstacle { reason });
        match self {
            Obstacle3::Plane { point, normal } => {
                if !point.iter().chain(normal.iter()).all(|c| c.is_finite()) {
                    return bad(format!(
                        "plane through {} with normal {} is not finite",
                        crate::Location::of(point),
                        crate::Location::of_vector(normal)
                    ));
                }
                if normal.norm() == 0.0 {
                    return bad("plane normal is the zero vector".into());
                }
            }
            Obstacle3::Sphere { centre, radius } => {
                if !(centre.iter().all(|c| c.is_finite()) && radius.is_finite()) {
                    return bad(format!(
                        "sphere at {} with radius {radius} is not finite",
                        crate::Location::of(centre)
                    ));
                }
                if *radius <= 0.0 {
                    return bad(format!("sphere radius {radius} must be positive"));
                }
            }
        }
        Ok(())
    }

    /// Contact direction and gap at the body point `x` (see the module docs). At the centre
    /// of a ball the direction is undefined; `+z` is taken there.
    fn gap_at(&self, x: Point3) -> ObstacleGap<3> {
        match self {
            Obstacle3::Plane { point, normal } => {
                let n = normal / normal.norm();
                ObstacleGap {
                    normal: -n,
                    gap: (x - point).dot(&n),
                }
            }
            Obstacle3::Sphere { centre, radius } => {
                let to_centre = centre - x;
                let distance = to_centre.norm();
                let normal = if distance > 0.0 {
                    to_centre / distance
                } else {
                    Vector3::z()
                };
                ObstacleGap {
                    normal,
                    gap: distance - radius,
                }
            }
        }
    }
}

/// Closest-point projection onto a polyline whose obstacle side is to the right.
fn polyline_gap(points: &[Point], x: Point) -> ObstacleGap {
    let mut best: Option<(f64, Point, Vector, bool)> = None; // (distance, closest, left normal, at an end)
    for w in points.windows(2) {
        let (a, b) = (w[0], w[1]);
        let t = b - a;
        let s = ((x - a).dot(&t) / t.norm_squared()).clamp(0.0, 1.0);
        let q = a + t * s;
        let d = (x - q).norm();
        let left = Vector::new(-t.y, t.x) / t.norm();
        if best.is_none_or(|(bd, ..)| d < bd) {
            best = Some((d, q, left, s == 0.0 || s == 1.0));
        }
    }
    let (distance, closest, left, at_vertex) = best.expect("validated polyline has a segment");
    let signed = (x - closest).dot(&left);
    if at_vertex && distance > 0.0 && signed > 0.0 {
        // Outside a convex corner: the closest point is the vertex; contact along x -> q.
        ObstacleGap {
            normal: (closest - x) / distance,
            gap: distance,
        }
    } else {
        ObstacleGap {
            normal: -left,
            gap: signed,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_gap_is_signed_distance() {
        let floor = Obstacle::Line {
            point: Point::new(0.0, -0.5),
            normal: Vector::new(0.0, 2.0),
        };
        let g = floor.gap_at(Point::new(3.0, 0.25));
        assert_eq!(g.normal, Vector::new(0.0, -1.0));
        assert!((g.gap - 0.75).abs() < 1e-15);
    }

    #[test]
    fn circle_gap_is_distance_to_surface() {
        let disc = Obstacle::Circle {
            centre: Point::new(0.0, 0.0),
            radius: 1.0,
        };
        let g = disc.gap_at(Point::new(3.0, 4.0));
        assert!((g.gap - 4.0).abs() < 1e-15);
        assert!((g.normal - Vector::new(-0.6, -0.8)).norm() < 1e-15);
    }

    #[test]
    fn polyline_matches_line_on_a_segment_and_corner_distance() {
        // Obstacle below the polyline (to the right of travel in +x).
        let ground = Obstacle::Polyline(vec![Point::new(0.0, 0.0), Point::new(1.0, 0.0)]);
        let g = ground.gap_at(Point::new(0.3, 0.2));
        assert!((g.gap - 0.2).abs() < 1e-15);
        assert_eq!(g.normal, Vector::new(0.0, -1.0));
        let corner = ground.gap_at(Point::new(1.3, 0.4));
        assert!((corner.gap - 0.5).abs() < 1e-15);
        assert!((corner.normal - Vector::new(-0.6, -0.8)).norm() < 1e-15);
        let inside = ground.gap_at(Point::new(0.5, -0.1));
        assert!((inside.gap + 0.1).abs() < 1e-15);
    }

    #[test]
    fn plane_and_sphere_gaps() {
        let floor = Obstacle3::Plane {
            point: Point3::new(0.0, 0.0, -0.5),
            normal: Vector3::new(0.0, 0.0, 2.0),
        };
        let g = floor.gap_at(Point3::new(3.0, -1.0, 0.25));
        assert_eq!(g.normal, Vector3::new(0.0, 0.0, -1.0));
        assert!((g.gap - 0.75).abs() < 1e-15);
        let ball = Obstacle3::Sphere {
            centre: Point3::new(1.0, 2.0, 2.0),
            radius: 1.0,
        };
        let g = ball.gap_at(Point3::origin());
        assert!((g.gap - 2.0).abs() < 1e-15);
        assert!((g.normal - Vector3::new(1.0, 2.0, 2.0) / 3.0).norm() < 1e-15);
        let bad = Obstacle3::Sphere {
            centre: Point3::origin(),
            radius: -1.0,
        };
        assert!(bad.validate().unwrap_err().to_string().contains("radius"));
        let flat = Obstacle3::Plane {
            point: Point3::origin(),
            normal: Vector3::zeros(),
        };
        assert!(flat.validate().unwrap_err().to_string().contains("zero"));
    }

    #[test]
    fn bad_obstacles_are_errors() {
        let zero = Obstacle::Circle {
            centre: Point::origin(),
            radius: 0.0,
        };
        assert!(zero.validate().unwrap_err().to_string().contains("radius"));
        let short = Obstacle::Polyline(vec![Point::origin()]);
        assert!(short.validate().is_err());
    }
}
