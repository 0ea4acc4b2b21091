//! The model warnings of a converged answer: each fires where its cause is, names body, part
//! and place once, and stays silent on correct examples (bodies that end together, a punch
//! in a block, a fine enough mesh, a penalty large enough, interface insertion's short edges).

use std::sync::Arc;

use vem_contact::{
    CondensedSolver, ContactProblem, ContactResult, ContactSolver, Frictionless, Obstacle,
    PenaltyParameter, PenaltySettings, PenaltySolver, Warning, ZoneLimit,
};
use vem_elastic::{Component, Dirichlet, ElasticBody, Material, Plane};
use vem_mesh::generators::{structured_quads, voronoi, Rectangle};
use vem_mesh::{Mesh, Point, Vector};
use vem_space::LowestOrderVem;

fn material() -> Material {
    Material::from_young_poisson(100.0, 0.3, Plane::Strain).expect("material")
}

fn quads(x0: f64, y0: f64, x1: f64, y1: f64, nx: usize, ny: usize) -> Mesh {
    structured_quads(
        &Rectangle::new(Point::new(x0, y0), Point::new(x1, y1)),
        nx,
        ny,
    )
    .expect("mesh")
}

fn body(name: &str, mesh: Mesh, top: Option<Vector>) -> ElasticBody {
    let builder = ElasticBody::builder(name, mesh, material(), Arc::new(LowestOrderVem::default()));
    match top {
        Some(shift) => {
            builder.dirichlet(Dirichlet::prescribed("top", Component::All, move |_| shift))
        }
        None => builder.clamp("bottom"),
    }
    .build()
    .expect("body")
}

/// An upper block `[0, 1] x [0, 1]` (`n` quads across) whose top is moved by `shift`, on a
/// clamped lower block `[x0, x1] x [-1, 0]` (7 quads across), along the upper block's
/// contact part `part`.
fn blocks(n: usize, part: &str, x0: f64, x1: f64, shift: Vector) -> ContactProblem {
    let upper = quads(0.0, 0.0, 1.0, 1.0, n, n)
        .with_part_where("pad", |a, b| {
            a.y == 0.0 && b.y == 0.0 && a.x.min(b.x) >= 0.25 - 1e-12 && a.x.max(b.x) <= 0.75 + 1e-12
        })
        .expect("part");
    let upper = body("upper", upper, Some(shift));
    let lower = body("lower", quads(x0, -1.0, x1, 0.0, 7, 4), None);
    ContactProblem::two_bodies(upper, part, lower, "top", Frictionless)
}

fn solve(problem: ContactProblem, solver: &mut dyn ContactSolver) -> ContactResult {
    problem.solve(solver).expect("solve")
}

fn zone_warnings(result: &ContactResult) -> Vec<&Warning> {
    result
        .warnings
        .iter()
        .filter(|w| matches!(w, Warning::ContactZoneAtLimit { .. }))
        .collect()
}

#[test]
fn bodies_that_end_together_raise_no_warning() {
    // Flat on flat, non-matching, both blocks ending at x = 0 and x = 1: every node is in
    // contact up to the corners, which are the real ends of the contact.
    let pressed = Vector::new(0.0, -0.01);
    let result = solve(
        blocks(5, "bottom", 0.0, 1.0, pressed),
        &mut CondensedSolver::default(),
    );
    assert_eq!(result.status_counts().open, 0);
    assert!(result.warnings.is_empty(), "{:?}", result.warnings);
    // A block on a wider one (the Tresca scene's shape): the upper block's corners end the
    // contact.
    let result = solve(
        blocks(5, "bottom", -0.5, 1.5, pressed),
        &mut CondensedSolver::default(),
    );
    assert!(result.warnings.is_empty(), "{:?}", result.warnings);
    // A block on a rigid line.
    let block = body("block", quads(0.0, 0.0, 2.0, 1.0, 8, 4), Some(pressed));
    let line = Obstacle::Line {
        point: Point::new(0.0, 0.0),
        normal: Vector::new(0.0, 1.0),
    };
    let result = solve(
        ContactProblem::against_obstacle(block, "bottom", line, Frictionless),
        &mut CondensedSolver::default(),
    );
    assert_eq!(result.status_counts().open, 0);
    assert!(result.warnings.is_empty(), "{:?}", result.warnings);
}

#[test]
fn a_part_that_ends_where_its_body_goes_on_may_clip_the_zone() {
    // The contact part 'pad' is the middle half of the upper block's flat bottom: the zone
    // reaches both of its ends, where the bottom goes on straight.
    let result = solve(
        blocks(8, "pad", 0.0, 1.0, Vector::new(0.0, -0.01)),
        &mut CondensedSolver::default(),
    );
    let zone = zone_warnings(&result);
    assert_eq!(zone.len(), 2, "{:?}", result.warnings);
    let mut ends = Vec::new();
    for w in zone {
        let Warning::ContactZoneAtLimit {
            limit,
            body,
            part,
            at,
            ..
        } = w
        else {
            unreachable!()
        };
        assert_eq!(
            (*limit, body.as_str(), part.as_str()),
            (ZoneLimit::EndOfPart, "upper", "pad")
        );
        ends.push(at.0[0]);
        assert!(w.to_string().contains("body 'upper' part 'pad'"), "{w}");
    }
    ends.sort_by(f64::total_cmp);
    assert_eq!(ends, [0.25, 0.75]);
    // Against a rigid line as well.
    let block = quads(0.0, 0.0, 1.0, 1.0, 8, 4)
        .with_part_where("pad", |a, b| {
            a.y == 0.0 && b.y == 0.0 && a.x.min(b.x) >= 0.25 - 1e-12 && a.x.max(b.x) <= 0.75 + 1e-12
        })
        .expect("part");
    let block = body("block", block, Some(Vector::new(0.0, -0.01)));
    let line = Obstacle::Line {
        point: Point::new(0.0, 0.0),
        normal: Vector::new(0.0, 1.0),
    };
    let result = solve(
        ContactProblem::against_obstacle(block, "pad", line, Frictionless),
        &mut CondensedSolver::default(),
    );
    assert_eq!(zone_warnings(&result).len(), 2, "{:?}", result.warnings);
}

#[test]
fn a_punch_pulled_clear_says_that_no_node_is_in_contact() {
    let result = solve(
        blocks(5, "bottom", 0.0, 1.0, Vector::new(0.0, 0.01)),
        &mut CondensedSolver::default(),
    );
    let counts = result.status_counts();
    assert_eq!(counts.active(), 0);
    let none: Vec<&Warning> = result
        .warnings
        .iter()
        .filter(|w| matches!(w, Warning::NoContact { .. }))
        .collect();
    assert_eq!(none.len(), 1, "{:?}", result.warnings);
    let Warning::NoContact { nodes, gap, .. } = none[0] else {
        unreachable!()
    };
    assert_eq!(*nodes, result.nodes.len());
    // The top moved up by 0.01 carries the block's bottom up by as much (no other load).
    assert!((gap - 0.01).abs() < 1e-9, "{gap}");
    assert!(none[0]
        .to_string()
        .contains("body 'upper' part 'bottom' against body 'lower' part 'top'"));
}

/// A rigid cylinder (R = 1, touching at the origin) on a block `[-1, 1] x [-1, 0]` (`mesh`),
/// pushed up by `lift`.
fn cylinder(block: Mesh, lift: f64) -> ContactResult {
    let block = ElasticBody::builder(
        "block",
        block,
        material(),
        Arc::new(LowestOrderVem::default()),
    )
    .dirichlet(Dirichlet::prescribed("bottom", Component::All, move |_| {
        Vector::new(0.0, lift)
    }))
    .build()
    .expect("body");
    let cylinder = Obstacle::Circle {
        centre: Point::new(0.0, 1.0),
        radius: 1.0,
    };
    solve(
        ContactProblem::against_obstacle(block, "top", cylinder, Frictionless),
        &mut CondensedSolver::default(),
    )
}

#[test]
fn a_contact_zone_of_one_node_is_a_concentrated_pressure() {
    let concentrated = |r: &ContactResult| {
        r.warnings
            .iter()
            .filter(|w| matches!(w, Warning::ConcentratedPressure { .. }))
            .count()
    };
    // Hertz's zone for this load is a fifth of an element wide: one node carries it all.
    let coarse = cylinder(quads(-1.0, -1.0, 1.0, 0.0, 10, 5), 0.002);
    assert_eq!(
        coarse.status_counts().active(),
        1,
        "{:?}",
        coarse.status_counts()
    );
    assert_eq!(concentrated(&coarse), 1, "{:?}", coarse.warnings);
    // Five nodes in contact share it.
    let rect = Rectangle::new(Point::new(-1.0, -1.0), Point::new(1.0, 0.0));
    let fine = cylinder(voronoi(&rect, 60, 1).expect("mesh"), 0.01);
    assert_eq!(fine.status_counts().active(), 5);
    assert!(fine.warnings.is_empty(), "{:?}", fine.warnings);
}

#[test]
fn a_penalty_answer_that_penetrates_far_says_so() {
    let problem = || blocks(5, "bottom", 0.0, 1.0, Vector::new(0.0, -0.01));
    let penalty = |factor: f64| {
        PenaltySolver::new(
            PenaltySettings::builder()
                .penalty(PenaltyParameter::RelativeToStiffness(factor))
                .build()
                .expect("settings"),
        )
    };
    let penetration = |r: &ContactResult| {
        r.warnings
            .iter()
            .filter_map(|w| match w {
                Warning::Penetration { ratio, .. } => Some(*ratio),
                _ => None,
            })
            .collect::<Vec<f64>>()
    };
    let soft = solve(problem(), &mut penalty(1.0));
    let ratios = penetration(&soft);
    assert_eq!(ratios.len(), 1, "{:?}", soft.warnings);
    // The penetration against the displacement scale, recomputed.
    let deepest = soft
        .nodes
        .iter()
        .map(|n| n.normal_jump - n.initial_gap)
        .fold(0.0, f64::max);
    let scale = soft.report.residuals.scales.displacement;
    assert!((ratios[0] - deepest / scale).abs() < 1e-12 * ratios[0]);
    assert!(ratios[0] > 1e-3);
    // The default penalty (1e3) penetrates 1e3 times less: no warning.
    let default = solve(problem(), &mut PenaltySolver::default());
    assert!(penetration(&default).is_empty(), "{:?}", default.warnings);
}

#[test]
fn short_edges_made_by_interface_insertion_are_not_a_shape_warning() {
    // Non-matching blocks whose interface nodes nearly coincide (1e-3 of a spacing apart):
    // insertion cuts edges down to 1e-3 of their cells (gamma 1e-3), which does not matter.
    let upper = quads(0.0, 0.0, 1.0, 1.0, 10, 10);
    let lower = quads(0.0, -1.0, 1.0, 0.0, 10, 5);
    let top: Vec<usize> = lower.part_vertices("top").expect("part");
    let mut vertices = lower.vertices().to_vec();
    for &v in &top {
        if vertices[v].x > 0.0 && vertices[v].x < 1.0 {
            vertices[v].x += 2e-4;
        }
    }
    let polygons: Vec<Vec<usize>> = lower.polygons().map(<[usize]>::to_vec).collect();
    let lower = Mesh::from_polygons(vertices, &polygons, lower.part_specs()).expect("mesh");
    let upper = body("upper", upper, Some(Vector::new(0.0, -0.01)));
    let lower = body("lower", lower, None);
    let result = solve(
        ContactProblem::two_bodies(upper, "bottom", lower, "top", Frictionless),
        &mut CondensedSolver::default(),
    );
    let gamma = result
        .bodies
        .iter()
        .flat_map(|b| {
            let mesh = b.body.body_mesh();
            (0..mesh.n_cells()).map(move |c| mesh.cell_quality(c).gamma())
        })
        .fold(f64::INFINITY, f64::min);
    assert!(gamma < 5e-3, "insertion made short edges: gamma {gamma}");
    assert!(result.warnings.is_empty(), "{:?}", result.warnings);
}
