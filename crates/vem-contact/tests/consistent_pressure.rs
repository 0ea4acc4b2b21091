//! The consistent pressure (`consistent_traction`, an L2 projection of nodal forces onto
//! piecewise-linear functions on the interface) against fields it must reproduce exactly, and
//! the contact normal choices.

use vem_contact::{consistent_traction, ContactNormal};
use vem_mesh::{Point, Vector};

/// Nodes on a polyline with uneven spacing (close pairs included), along a bent line.
fn polyline() -> Vec<Point> {
    let s = [
        0.0, 0.1, 0.1007, 0.23, 0.31, 0.3102, 0.45, 0.6, 0.62, 0.8, 1.0,
    ];
    s.iter()
        .map(|&s| {
            if s <= 0.5 {
                Point::new(s, 0.0)
            } else {
                // A kink at s = 0.5: the second half goes up at 45 degrees.
                let t = (s - 0.5) / 2f64.sqrt();
                Point::new(0.5 + t, t)
            }
        })
        .collect()
}

fn arc_lengths(points: &[Point]) -> Vec<f64> {
    let mut arc = vec![0.0];
    for w in points.windows(2) {
        arc.push(arc.last().unwrap() + (w[1] - w[0]).norm());
    }
    arc
}

/// Nodal forces of the piecewise-linear traction with nodal values `p`: `M^h p` with the
/// consistent mass matrix of all nodes.
fn consistent_forces(arc: &[f64], p: &[f64]) -> Vec<f64> {
    let mut f = vec![0.0; p.len()];
    for k in 0..p.len() - 1 {
        let l = arc[k + 1] - arc[k];
        f[k] += l * (2.0 * p[k] + p[k + 1]) / 6.0;
        f[k + 1] += l * (p[k] + 2.0 * p[k + 1]) / 6.0;
    }
    f
}

fn tributary(arc: &[f64]) -> Vec<f64> {
    let n = arc.len();
    (0..n)
        .map(|i| {
            let before = if i > 0 { arc[i] - arc[i - 1] } else { 0.0 };
            let after = if i + 1 < n { arc[i + 1] - arc[i] } else { 0.0 };
            0.5 * (before + after)
        })
        .collect()
}

#[test]
fn a_linear_traction_is_reproduced_on_every_support() {
    let points = polyline();
    let arc = arc_lengths(&points);
    let exact: Vec<f64> = arc.iter().map(|s| 2.0 - 1.5 * s).collect();
    let forces = consistent_forces(&arc, &exact);
    let lengths = tributary(&arc);
    let every = vec![true; points.len()];
    // A coarse support: every third node (the ends are always in it).
    let coarse: Vec<bool> = (0..points.len()).map(|i| i % 3 == 0).collect();
    for support in [&every, &coarse] {
        let p = consistent_traction(&points, &forces, support, &lengths);
        for (p, e) in p.iter().zip(&exact) {
            assert!((p - e).abs() < 1e-12, "{p} vs {e}");
        }
    }
}

#[test]
fn a_uniform_traction_with_tributary_forces_is_reproduced() {
    let points = polyline();
    let arc = arc_lengths(&points);
    let lengths = tributary(&arc);
    let forces: Vec<f64> = lengths.iter().map(|l| 0.7 * l).collect();
    let coarse: Vec<bool> = (0..points.len()).map(|i| i % 2 == 1).collect();
    for support in [vec![true; points.len()], coarse] {
        let p = consistent_traction(&points, &forces, &support, &lengths);
        assert!(p.iter().all(|p| (p - 0.7).abs() < 1e-12), "{p:?}");
    }
}

#[test]
fn a_close_pair_split_unevenly_is_averaged_on_the_coarse_support() {
    // A uniform traction whose close pairs (nodes 1-2 and 4-5) carry their joint force 80/20:
    // the raw values oscillate by +-60 %, the projection on the support without the second
    // node of each pair is uniform again away from the pairs and close to it at them.
    let points = polyline();
    let arc = arc_lengths(&points);
    let lengths = tributary(&arc);
    let mut forces: Vec<f64> = lengths.clone();
    for (i, j) in [(1, 2), (4, 5)] {
        let joint = forces[i] + forces[j];
        forces[i] = 0.8 * joint;
        forces[j] = 0.2 * joint;
    }
    let support: Vec<bool> = (0..points.len()).map(|i| i != 2 && i != 5).collect();
    let p = consistent_traction(&points, &forces, &support, &lengths);
    assert!(p.iter().all(|p| (p - 1.0).abs() < 0.02), "{p:?}");
    let raw: Vec<f64> = forces.iter().zip(&lengths).map(|(f, l)| f / l).collect();
    assert!(raw.iter().any(|r| (r - 1.0).abs() > 0.5), "{raw:?}");
}

#[test]
fn too_few_nodes_fall_back_to_the_raw_values() {
    let p = consistent_traction(&[Point::new(0.0, 0.0)], &[2.0], &[true], &[0.5]);
    assert_eq!(p, [4.0]);
    let p = consistent_traction(&[], &[], &[], &[]);
    assert!(p.is_empty());
}

#[test]
fn the_normal_choices_combine_the_two_sides() {
    let n_a = Vector::new(0.0, -1.0);
    let tilt = 0.1_f64;
    let n_b = Vector::new(tilt.sin(), tilt.cos());
    assert_eq!(ContactNormal::BodyA.combine(n_a, n_b), n_a);
    assert_eq!(ContactNormal::BodyB.combine(n_a, n_b), -n_b);
    let averaged = ContactNormal::Averaged.combine(n_a, n_b);
    // The bisector: unit, at half the angle from each side.
    assert!((averaged.norm() - 1.0).abs() < 1e-15);
    assert!((averaged.dot(&n_a) - (0.5 * tilt).cos()).abs() < 1e-15);
    assert!((averaged.dot(&-n_b) - (0.5 * tilt).cos()).abs() < 1e-15);
    assert_eq!(ContactNormal::default(), ContactNormal::BodyB);
    let names: Vec<&str> = ContactNormal::ALL.iter().map(|n| n.name()).collect();
    assert_eq!(names, ["body_a", "body_b", "averaged"]);
}
