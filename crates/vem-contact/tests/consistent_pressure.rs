//! The consistent pressure and friction traction (`consistent_traction`: the L2 projection of
//! nodal forces onto piecewise-linear functions on the interface, within a bound, with the
//! forces' resultant) against fields it must reproduce exactly, its optimality conditions,
//! the sign and friction bounds on fields where the plain projection violates them, solved
//! contact problems, and the contact normal choices.

use std::sync::Arc;

use vem_contact::{
    consistent_traction, CondensedSolver, ContactNormal, ContactProblem, ContactResult, Coulomb,
    Frictionless, NodeStatus, Obstacle, TractionBound, Tresca,
};
use vem_elastic::{Component, Dirichlet, ElasticBody, Material, Plane};
use vem_mesh::generators::{hexagons, voronoi, MeshFamily, Rectangle};
use vem_mesh::{Point, Vector};
use vem_space::LowestOrderVem;
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

/// `n + 1` nodes on [0, 1] with a smooth uneven spacing.
fn uneven_line(n: usize) -> Vec<Point> {
    (0..=n)
        .map(|i| {
            let t = i as f64 / n as f64;
            Point::new(t + 0.3 * t * (1.0 - t) * (7.0 * t).sin(), 0.0)
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

/// `int p ds` of the piecewise-linear function with nodal values `p` (exact: the
/// trapezoidal rule on its nodes).
fn integral(arc: &[f64], p: &[f64]) -> f64 {
    (0..p.len() - 1)
        .map(|k| 0.5 * (arc[k + 1] - arc[k]) * (p[k] + p[k + 1]))
        .sum()
}

const BOUNDS: [TractionBound<'static>; 2] = [TractionBound::Unbounded, TractionBound::NonNegative];

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
        for bound in BOUNDS {
            let p = consistent_traction(&points, &forces, support, &lengths, bound);
            for (p, e) in p.iter().zip(&exact) {
                assert!((p - e).abs() < 1e-12, "{bound:?}: {p} vs {e}");
            }
        }
        // A friction traction of the same shape at its bound (full slip, Coulomb): the
        // bound is reached, not crossed, and the traction is still exact.
        let bound = TractionBound::Magnitude(&forces);
        let t = consistent_traction(&points, &forces, support, &lengths, bound);
        for (t, e) in t.iter().zip(&exact) {
            assert!((t - e).abs() < 1e-12, "{t} vs {e}");
        }
    }
}

#[test]
fn a_linear_traction_that_vanishes_at_an_end_is_reproduced() {
    // p = 1 - s on a uniform line: zero at the last node, where a bound is active.
    let points = uneven_line(10);
    let arc = arc_lengths(&points);
    let length = *arc.last().unwrap();
    let exact: Vec<f64> = arc.iter().map(|s| 1.0 - s / length).collect();
    let forces = consistent_forces(&arc, &exact);
    let p = consistent_traction(
        &points,
        &forces,
        &vec![true; points.len()],
        &tributary(&arc),
        TractionBound::NonNegative,
    );
    for (p, e) in p.iter().zip(&exact) {
        assert!((p - e).abs() < 1e-12, "{p} vs {e}");
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
        for bound in BOUNDS {
            let p = consistent_traction(&points, &forces, &support, &lengths, bound);
            assert!(p.iter().all(|p| (p - 0.7).abs() < 1e-12), "{p:?}");
        }
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
    for bound in BOUNDS {
        let p = consistent_traction(&points, &forces, &support, &lengths, bound);
        assert!(p.iter().all(|p| (p - 1.0).abs() < 0.02), "{p:?}");
    }
    let raw: Vec<f64> = forces.iter().zip(&lengths).map(|(f, l)| f / l).collect();
    assert!(raw.iter().any(|r| (r - 1.0).abs() > 0.5), "{raw:?}");
}

#[test]
fn too_few_nodes_fall_back_to_the_raw_values() {
    for bound in BOUNDS {
        let p = consistent_traction(&[Point::new(0.0, 0.0)], &[2.0], &[true], &[0.5], bound);
        assert_eq!(p, [4.0]);
        let p = consistent_traction(&[], &[], &[], &[], bound);
        assert!(p.is_empty());
    }
    // Bounds of the wrong length: no projection either.
    let x = [Point::new(0.0, 0.0), Point::new(1.0, 0.0)];
    let p = consistent_traction(
        &x,
        &[0.5, 0.5],
        &[true, true],
        &[0.5, 0.5],
        TractionBound::Magnitude(&[1.0]),
    );
    assert_eq!(p, [1.0, 1.0]);
}

/// The nodal forces (trapezoidal rule) of a Hertz-like pressure `sqrt(1 - (x/a)^2)` centred
/// at `x = 0.5` on `points`.
fn elliptic_forces(points: &[Point], a: f64) -> Vec<f64> {
    let lengths = tributary(&arc_lengths(points));
    points
        .iter()
        .zip(&lengths)
        .map(|(x, l)| l * (1.0 - ((x.x - 0.5) / a).powi(2)).max(0.0).sqrt())
        .collect()
}

/// The consistent mass matrix of the hats of `support` applied to the support values `c`,
/// minus `r_k = sum_i f_i phi_k(x_i)`: the gradient of the projection's objective, with the
/// hat integrals `m_k` (row sums of the matrix).
fn gradient(
    arc: &[f64],
    support: &[bool],
    c: &[f64],
    forces: &[f64],
) -> (Vec<usize>, Vec<f64>, Vec<f64>) {
    let nodes: Vec<usize> = (0..arc.len()).filter(|&i| support[i]).collect();
    let m = nodes.len();
    let lengths: Vec<f64> = nodes.windows(2).map(|w| arc[w[1]] - arc[w[0]]).collect();
    let mut g = vec![0.0; m];
    let mut hat = vec![0.0; m];
    for k in 0..m - 1 {
        let l = lengths[k];
        g[k] += l * (2.0 * c[k] + c[k + 1]) / 6.0;
        g[k + 1] += l * (c[k] + 2.0 * c[k + 1]) / 6.0;
        hat[k] += 0.5 * l;
        hat[k + 1] += 0.5 * l;
    }
    for (i, f) in forces.iter().enumerate() {
        let k = nodes.partition_point(|&j| arc[j] <= arc[i]).clamp(1, m - 1) - 1;
        let t = ((arc[i] - arc[nodes[k]]) / lengths[k]).clamp(0.0, 1.0);
        g[k] -= (1.0 - t) * f;
        g[k + 1] -= t * f;
    }
    (nodes, g, hat)
}

#[test]
fn the_pressure_of_a_zone_inside_the_interface_is_non_negative_with_the_forces_resultant() {
    // An elliptic pressure on a fifth of an unevenly spaced line, every other node a support
    // node: the plain projection dips below zero next to the zone, the bounded one does not,
    // and both integrate to the resultant of the forces.
    let points = uneven_line(40);
    let arc = arc_lengths(&points);
    let lengths = tributary(&arc);
    let forces = elliptic_forces(&points, 0.1);
    let support: Vec<bool> = (0..points.len()).map(|i| i % 2 == 0).collect();
    let project = |bound| consistent_traction(&points, &forces, &support, &lengths, bound);
    let plain = project(TractionBound::Unbounded);
    let p = project(TractionBound::NonNegative);
    let peak = p.iter().copied().fold(0.0, f64::max);
    let dip = plain.iter().copied().fold(f64::INFINITY, f64::min);
    assert!(
        dip < -0.03 * peak,
        "the plain projection dips: {dip} of {peak}"
    );
    assert!(p.iter().all(|&p| p >= 0.0), "{p:?}");
    let resultant: f64 = forces.iter().sum();
    for values in [&plain, &p] {
        assert!((integral(&arc, values) - resultant).abs() < 1e-14 * resultant);
    }
    // Optimality: with g = M c - r - nu m for the resultant's multiplier nu, g = 0 where
    // c > 0 and g >= 0 where c = 0 (the minimiser of the L2 distance over the non-negative
    // functions with the forces' resultant).
    let c: Vec<f64> = (0..points.len())
        .filter(|&i| support[i])
        .map(|i| p[i])
        .collect();
    let (_, g, hat) = gradient(&arc, &support, &c, &forces);
    let free: Vec<usize> = (0..c.len()).filter(|&k| c[k] > 0.0).collect();
    let nu = g[free[0]] / hat[free[0]];
    let scale = forces.iter().copied().fold(0.0, f64::max);
    for k in 0..c.len() {
        let gk = g[k] - nu * hat[k];
        if c[k] > 0.0 {
            assert!(gk.abs() < 1e-12 * scale, "free {k}: {gk}");
        } else {
            assert!(gk > -1e-12 * scale, "at the bound {k}: {gk}");
        }
    }
    // As close to the elliptic pressure as the plain projection, in L2 over the line.
    let exact: Vec<f64> = points
        .iter()
        .map(|x| (1.0 - ((x.x - 0.5) / 0.1).powi(2)).max(0.0).sqrt())
        .collect();
    let distance = |p: &[f64]| {
        let squares: Vec<f64> = p.iter().zip(&exact).map(|(p, e)| (p - e).powi(2)).collect();
        integral(&arc, &squares).sqrt()
    };
    assert!(
        distance(&p) < 1.05 * distance(&plain),
        "L2 distance to the ellipse: plain {:.4e}, bounded {:.4e}",
        distance(&plain),
        distance(&p)
    );
}

#[test]
fn coulomb_and_tresca_bounds_hold_pointwise() {
    // A friction traction at the bound F p on the zone's left half and below it on the right
    // half: the plain projection crosses F p at the zone's ends, the bounded one stays
    // within, and |t| <= F p holds for the consistent pressure p of the same forces.
    let coefficient = 0.3;
    let points = uneven_line(40);
    let arc = arc_lengths(&points);
    let lengths = tributary(&arc);
    let normal = elliptic_forces(&points, 0.1);
    let friction: Vec<f64> = normal
        .iter()
        .zip(&points)
        .map(|(f, x)| coefficient * f * if x.x < 0.5 { -1.0 } else { 0.6 })
        .collect();
    let bounds: Vec<f64> = normal.iter().map(|f| coefficient * f).collect();
    let support: Vec<bool> = (0..points.len()).map(|i| i % 2 == 0).collect();
    let project =
        |forces: &[f64], bound| consistent_traction(&points, forces, &support, &lengths, bound);
    let p = project(&normal, TractionBound::NonNegative);
    let plain = project(&friction, TractionBound::Unbounded);
    let t = project(&friction, TractionBound::Magnitude(&bounds));
    let scale = coefficient * p.iter().copied().fold(0.0, f64::max);
    let crossing = plain
        .iter()
        .zip(&p)
        .map(|(t, p)| t.abs() - coefficient * p)
        .fold(f64::NEG_INFINITY, f64::max);
    assert!(
        crossing > 0.02 * scale,
        "the plain projection crosses F p: {crossing}"
    );
    for (t, p) in t.iter().zip(&p) {
        assert!(
            t.abs() <= coefficient * p * (1.0 + 1e-12) + 1e-15 * scale,
            "{t} vs F {p}"
        );
    }
    assert!(
        (integral(&arc, &t) - friction.iter().sum::<f64>()).abs() < 1e-13 * scale,
        "the tangential resultant"
    );
    // Tresca with a uniform bound g_F = 0.1 on the whole line (nodal bounds l_i g_F), the
    // friction at the bound on the left and within it on the right: |t| <= g_F at every node.
    let g = 0.1;
    let bounds: Vec<f64> = lengths.iter().map(|l| l * g).collect();
    let friction: Vec<f64> = points
        .iter()
        .zip(&bounds)
        .map(|(x, b)| if x.x < 0.4 { *b } else { -0.2 * b })
        .collect();
    let plain = project(&friction, TractionBound::Unbounded);
    let t = project(&friction, TractionBound::Magnitude(&bounds));
    assert!(plain.iter().any(|t| t.abs() > g * (1.0 + 1e-3)));
    for t in &t {
        assert!(t.abs() <= g * (1.0 + 1e-12), "{t} vs {g}");
    }
    // A bound varying along the line, g_F(x) = 0.1 (1 + x): |t| stays within the same
    // projection beta of the nodal bounds l_i g_F(x_i), which is g_F to second order in the
    // spacing inside the line and to first order at its ends (the trapezoidal nodal bounds
    // of a linear g_F are not its consistent forces).
    let g = |x: &Point| 0.1 * (1.0 + x.x);
    let bounds: Vec<f64> = points.iter().zip(&lengths).map(|(x, l)| l * g(x)).collect();
    let friction: Vec<f64> = points
        .iter()
        .zip(&bounds)
        .map(|(x, b)| if x.x < 0.4 { *b } else { -0.2 * b })
        .collect();
    let t = project(&friction, TractionBound::Magnitude(&bounds));
    let beta = project(&bounds, TractionBound::NonNegative);
    for ((t, beta), x) in t.iter().zip(&beta).zip(&points) {
        assert!(t.abs() <= beta * (1.0 + 1e-12), "{t} vs {beta}");
        assert!((beta - g(x)).abs() < 1e-2 * g(x), "{beta} vs {}", g(x));
    }
}

/// A rigid cylinder (R = 1, touching at the origin) on a Voronoi block `[-1, 1] x [-1, 0]`
/// (n = 60, seed 1, E = 100, nu = 0.3, plane strain) whose bottom is moved up by 0.01: five
/// nodes in contact, the zone about two node spacings wide on each side.
fn cylinder_on_voronoi() -> ContactResult {
    let block = voronoi(
        &Rectangle::new(Point::new(-1.0, -1.0), Point::new(1.0, 0.0)),
        60,
        1,
    )
    .expect("mesh");
    let material = Material::from_young_poisson(100.0, 0.3, Plane::Strain).expect("material");
    let body = ElasticBody::builder(
        "block",
        block,
        material,
        Arc::new(LowestOrderVem::default()),
    )
    .dirichlet(Dirichlet::prescribed("bottom", Component::All, |_| {
        Vector::new(0.0, 0.01)
    }))
    .build()
    .expect("body");
    let cylinder = Obstacle::Circle {
        centre: Point::new(0.0, 1.0),
        radius: 1.0,
    };
    ContactProblem::against_obstacle(body, "top", cylinder, Frictionless)
        .solve(&mut CondensedSolver::default())
        .expect("solve")
}

#[test]
fn a_rigid_cylinder_on_a_voronoi_block_has_a_non_negative_consistent_pressure() {
    let result = cylinder_on_voronoi();
    let counts = result.status_counts();
    assert_eq!(counts.active(), 5, "{counts:?}");
    assert_eq!(
        counts.contact, 5,
        "frictionless nodes in contact are 'contact'"
    );
    let nodes = &result.nodes;
    let positions: Vec<Point> = nodes.iter().map(|n| n.position).collect();
    let forces: Vec<f64> = nodes.iter().map(|n| n.normal_force).collect();
    let lengths: Vec<f64> = nodes.iter().map(|n| n.tributary_measure).collect();
    let plain = consistent_traction(
        &positions,
        &forces,
        &vec![true; nodes.len()],
        &lengths,
        TractionBound::Unbounded,
    );
    let p: Vec<f64> = nodes.iter().map(|n| n.consistent_pressure).collect();
    let peak = p.iter().copied().fold(0.0, f64::max);
    let min_plain = plain.iter().copied().fold(f64::INFINITY, f64::min);
    // The plain projection dips to -20 % of the peak; the consistent pressure is >= 0.
    assert!(min_plain < -0.15 * peak, "{min_plain} of {peak}");
    assert!(p.iter().all(|&p| p >= 0.0), "{p:?}");
    // Both integrate to the load (the trapezoidal rule is exact on the piecewise-linear
    // functions).
    let arc = arc_lengths(&positions);
    let load = result.normal_resultant();
    assert!((integral(&arc, &p) - load).abs() < 1e-12 * load);
    assert!((integral(&arc, &plain) - load).abs() < 1e-12 * load);
    // Against Hertz's rigid cylinder on a half-plane for this load (E* = E / (1 - nu^2)):
    // five nodes cannot resolve the ellipse, the peak is within 10 %.
    let e_star = 100.0 / (1.0 - 0.3 * 0.3);
    let a = (4.0 * load / (std::f64::consts::PI * e_star)).sqrt();
    let p0 = 2.0 * load / (std::f64::consts::PI * a);
    assert!((peak / p0 - 1.0).abs() < 0.1, "peak {peak}, Hertz {p0}");
}

/// The Tresca scene of the command line (`crates/vem-cli/scenes/tresca.toml`): a hexagon
/// block pressed (0.2) and sheared (0.02) on a wider quad foundation, g_F = 0.1.
fn tresca_block() -> ContactResult {
    let element = Arc::new(LowestOrderVem::default());
    let material = Material::from_young_poisson(10.0, 0.3, Plane::Strain).expect("material");
    let block_mesh = hexagons(
        &Rectangle::new(Point::new(0.0, 0.0), Point::new(1.0, 0.25)),
        16,
    )
    .expect("mesh");
    let foundation_mesh = MeshFamily::Quads
        .generate(
            &Rectangle::new(Point::new(-0.25, -0.5), Point::new(1.25, 0.0)),
            18,
            1,
        )
        .expect("mesh");
    let block = ElasticBody::builder("block", block_mesh, material, element.clone())
        .dirichlet(Dirichlet::prescribed("top", Component::X, |_| {
            Vector::new(0.02, 0.0)
        }))
        .traction("top", |_| Vector::new(0.0, -0.2))
        .build()
        .expect("body");
    let foundation = ElasticBody::builder("foundation", foundation_mesh, material, element)
        .clamp("bottom")
        .build()
        .expect("body");
    ContactProblem::two_bodies(
        block,
        "bottom",
        foundation,
        "top",
        Tresca::try_new(0.1).expect("law"),
    )
    .solve(&mut CondensedSolver::default())
    .expect("solve")
}

#[test]
fn tresca_friction_stays_within_its_bound_and_open_nodes_carry_no_force() {
    let result = tresca_block();
    let scale = result
        .nodes
        .iter()
        .fold(0.0_f64, |m, n| m.max(n.normal_force));
    let mut pressureless_friction = 0;
    for n in &result.nodes {
        let g = 0.1;
        assert!(
            n.consistent_friction_t().abs() <= g * (1.0 + 1e-12),
            "{n:?}"
        );
        assert!(n.consistent_pressure >= 0.0, "{n:?}");
        match n.status {
            // Open: no force of any kind.
            NodeStatus::Open => {
                assert!(n.normal_force <= 1e-8 * scale && n.friction_t().abs() <= 1e-8 * scale)
            }
            NodeStatus::Stick | NodeStatus::Slip => {}
            NodeStatus::Contact => panic!("a Tresca node is stick or slip: {n:?}"),
        }
        // Tresca's bound acts whatever the pressure: the block's left corner lifts off
        // (no pressure) and still carries friction; it is stick or slip, not open.
        if n.normal_force <= 1e-8 * scale && n.friction_t().abs() > 1e-8 * scale {
            pressureless_friction += 1;
            assert_ne!(n.status, NodeStatus::Open, "{n:?}");
        }
    }
    assert!(
        pressureless_friction > 0,
        "the corner node carries friction without pressure"
    );
}

#[test]
fn coulomb_friction_stays_within_f_p_at_a_punch_edge() {
    // A rigid flat punch (chamfered edges) pressed into a block and sheared, Coulomb F = 0.3:
    // the pressure peaks at the punch's edges, where the plain projections of the forces and
    // of the bounds dip below zero and the friction traction crosses F p.
    let coefficient = 0.3;
    let block = MeshFamily::Quads
        .generate(
            &Rectangle::new(Point::new(-1.0, -1.0), Point::new(1.0, 0.0)),
            40,
            1,
        )
        .expect("mesh");
    let material = Material::from_young_poisson(100.0, 0.3, Plane::Strain).expect("material");
    let block = ElasticBody::builder(
        "block",
        block,
        material,
        Arc::new(LowestOrderVem::default()),
    )
    .dirichlet(Dirichlet::prescribed("bottom", Component::All, |_| {
        Vector::new(0.004, 0.01)
    }))
    .build()
    .expect("body");
    let punch = Obstacle::Polyline(vec![
        Point::new(0.5, 0.1),
        Point::new(0.25, 0.0),
        Point::new(-0.25, 0.0),
        Point::new(-0.5, 0.1),
    ]);
    let result = ContactProblem::against_obstacle(
        block,
        "top",
        punch,
        Coulomb::try_new(coefficient).expect("law"),
    )
    .solve(&mut CondensedSolver::default())
    .expect("solve");
    let counts = result.status_counts();
    assert!(counts.slip > 0 && counts.stick > 0, "{counts:?}");
    let nodes = &result.nodes;
    let positions: Vec<Point> = nodes.iter().map(|n| n.position).collect();
    let lengths: Vec<f64> = nodes.iter().map(|n| n.tributary_measure).collect();
    let support = vec![true; nodes.len()];
    let plain = |forces: &[f64]| {
        consistent_traction(
            &positions,
            forces,
            &support,
            &lengths,
            TractionBound::Unbounded,
        )
    };
    let p_plain = plain(&nodes.iter().map(|n| n.normal_force).collect::<Vec<_>>());
    let t_plain = plain(&nodes.iter().map(|n| n.friction_t()).collect::<Vec<_>>());
    let peak = nodes
        .iter()
        .fold(0.0_f64, |m, n| m.max(n.consistent_pressure));
    let crossing = t_plain
        .iter()
        .zip(&p_plain)
        .map(|(t, p)| t.abs() - coefficient * p)
        .fold(f64::NEG_INFINITY, f64::max);
    assert!(
        crossing > 0.1 * coefficient * peak,
        "the plain projection crosses F p: {crossing}"
    );
    assert!(p_plain.iter().any(|&p| p < -0.2 * peak));
    let tolerance = result.fixed_point.as_ref().expect("Coulomb").tolerance;
    for n in nodes {
        assert!(n.consistent_pressure >= 0.0, "{n:?}");
        let excess = n.consistent_friction_t().abs() - coefficient * n.consistent_pressure;
        assert!(excess <= 10.0 * tolerance * coefficient * peak, "{n:?}");
    }
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
