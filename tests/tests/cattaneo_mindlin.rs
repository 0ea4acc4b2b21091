//! Cattaneo-Mindlin: two blocks of the same material with a parabolic initial gap
//! `h0 = x^2 / (2R)` (a cylinder of radius R on a flat, as Hertz's theory models it) pressed
//! together and sheared with Coulomb friction. For identical materials the normal pressure does
//! not depend on the tangential load, and a tangential load `Q < F P` leaves a central stick
//! zone of half-width `c = a sqrt(1 - Q/(F P))`; at full slip `Q = F P`. The Hertz geometry
//! (the half-disc on the block of `cargo xtask hertz`) under force control, its top a rigid
//! plate pushed and sheared, shows the same stick zone: the disc is held sideways by friction
//! alone.

use std::sync::Arc;

use vem_contact::{
    CondensedSolver, ContactNormal, ContactProblem, ContactResult, ContactSolver, Coulomb,
    NodeStatus,
};
use vem_elastic::{Component, Dirichlet, ElasticBody, Material, Plane};
use vem_mesh::generators::{structured_quads, Rectangle};
use vem_mesh::interface::InterfaceOptions;
use vem_mesh::io::read_gmsh;
use vem_mesh::{Point, Vector};
use vem_space::LowestOrderVem;
use vem_verify::exact::HertzContact;
use vem_verify::fretting::zone_half_width as zone;

const RADIUS: f64 = 1.0;
const COEFFICIENT: f64 = 0.3;
const INDENTATION: f64 = 0.03;

/// The upper block [-1, 1] x [0, 1] (64 x 32 quads) with its top moved by (shift, -0.03)
/// on the lower block [-1, 1] x [-1, 0] (80 x 40 quads, bottom fixed): non-matching sides.
fn solve(shift: f64, normal: ContactNormal) -> ContactResult {
    let material = Material::from_young_poisson(100.0, 0.3, Plane::Strain).unwrap();
    let element = Arc::new(LowestOrderVem::default());
    let rect = |y0: f64| Rectangle::new(Point::new(-1.0, y0), Point::new(1.0, y0 + 1.0));
    let upper = ElasticBody::builder(
        "upper",
        structured_quads(&rect(0.0), 64, 32).unwrap(),
        material,
        element.clone(),
    )
    .dirichlet(Dirichlet::prescribed("top", Component::All, move |_| {
        Vector::new(shift, -INDENTATION)
    }))
    .build()
    .unwrap();
    let lower = ElasticBody::builder(
        "lower",
        structured_quads(&rect(-1.0), 80, 40).unwrap(),
        material,
        element,
    )
    .dirichlet(Dirichlet::prescribed("bottom", Component::All, |_| {
        Vector::zeros()
    }))
    .build()
    .unwrap();
    let law = Coulomb::try_new(COEFFICIENT).unwrap();
    ContactProblem::two_bodies(upper, "bottom", lower, "top", law)
        .with_imposed_gap(|x| x.x * x.x / (2.0 * RADIUS))
        .with_normal(normal)
        .solve(&mut CondensedSolver::default())
        .unwrap()
}

/// (P, Q) from the force on the upper body.
fn loads(result: &ContactResult) -> (f64, f64) {
    let force = result.force_on_body_a();
    (force.y, force.x.abs())
}

#[test]
fn partial_slip_leaves_the_stick_zone_of_cattaneo_mindlin() {
    let result = solve(0.004, ContactNormal::default());
    let (p, q) = loads(&result);
    let ratio = q / (COEFFICIENT * p);
    assert!(
        ratio > 0.2 && ratio < 0.8,
        "Q/(F P) = {ratio}: partial slip"
    );
    let (a, spacing_a) = zone(&result.nodes, |n| n.status != NodeStatus::Open);
    let (c, spacing_c) = zone(&result.nodes, |n| n.status == NodeStatus::Stick);
    // The contact half-width against Hertz's for the computed P (finite blocks: a few %).
    let e_star = HertzContact::plane_strain_modulus(100.0, 0.3, 100.0, 0.3);
    let hertz = HertzContact::try_new(RADIUS, e_star, p).unwrap();
    assert!(
        (a - hertz.half_width()).abs() <= spacing_a,
        "a = {a}, Hertz {}, spacing {spacing_a}",
        hertz.half_width()
    );
    // Cattaneo-Mindlin's stick zone within one node spacing.
    let expected = a * (1.0 - ratio).sqrt();
    eprintln!(
        "P = {p:.6}, Q/(F P) = {ratio:.4}, a = {a:.4} (Hertz {:.4}), c = {c:.4}, \
         a sqrt(1 - Q/(F P)) = {expected:.4}, spacing {spacing_c:.4}",
        hertz.half_width()
    );
    assert!(
        (c - expected).abs() <= spacing_c,
        "c = {c}, a sqrt(1 - Q/(F P)) = {expected}, spacing {spacing_c}, Q/(F P) = {ratio}"
    );
    // Friction below its bound everywhere, at the bound outside the stick zone.
    for n in &result.nodes {
        assert!(n.friction_t().abs() <= COEFFICIENT * n.normal_force * (1.0 + 1e-9) + 1e-12);
    }
}

#[test]
fn full_slip_carries_the_coulomb_force_and_the_same_pressure() {
    let sheared = solve(0.05, ContactNormal::default());
    let (p, q) = loads(&sheared);
    assert_eq!(sheared.status_counts().stick, 0, "no node sticks");
    assert!((q / p - COEFFICIENT).abs() < 1e-6, "Q/P = {}", q / p);
    // Identical materials: the normal load hardly depends on the tangential one (exactly
    // for half-planes; the finite blocks couple them by 1e-4 here).
    let pressed = solve(0.0, ContactNormal::default());
    let (p0, _) = loads(&pressed);
    assert!((p - p0).abs() < 1e-3 * p0, "P sheared {p}, pressed {p0}");
}

/// The half-disc (R = 1) of the Hertz study at h_c = 0.02, its top a rigid plate with the
/// resultant `(shear, -push)`, on the block clamped at its bottom.
fn hertz_under_force_control(push: f64, shear: f64) -> ContactResult {
    let material = Material::from_young_poisson(100.0, 0.3, Plane::Strain).unwrap();
    let element = Arc::new(LowestOrderVem::default());
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../xtask/data/hertz");
    let disc = read_gmsh(format!("{root}/disc_hc0.02.msh")).unwrap();
    let block = read_gmsh(format!("{root}/block_hc0.02.msh")).unwrap();
    let disc = ElasticBody::builder("disc", disc, material, element.clone())
        .dirichlet(Dirichlet::rigid_plate(
            "top",
            Component::All,
            Vector::new(shear, -push),
        ))
        .build()
        .unwrap();
    let block = ElasticBody::builder("block", block, material, element)
        .clamp("bottom")
        .build()
        .unwrap();
    let mut solver = CondensedSolver::default();
    let result = ContactProblem::two_bodies(
        disc,
        "arc",
        block,
        "top",
        Coulomb::try_new(COEFFICIENT).unwrap(),
    )
    .with_interface_options(
        InterfaceOptions::builder()
            .max_distance(0.05)
            .build()
            .unwrap(),
    )
    .solve(&mut solver)
    .unwrap();
    assert_eq!(result.report.solver, solver.name());
    result
}

#[test]
fn the_hertz_disc_held_by_friction_alone_leaves_the_stick_zone_of_cattaneo_mindlin() {
    let push = 0.5;
    let e_star = HertzContact::plane_strain_modulus(100.0, 0.3, 100.0, 0.3);
    let hertz = HertzContact::try_new(RADIUS, e_star, push).unwrap();
    for ratio in [0.2, 0.5, 0.8] {
        let shear = ratio * COEFFICIENT * push;
        let result = hertz_under_force_control(push, shear);
        // The plate's force is carried exactly.
        let force = result.force_on_body_a();
        assert!((force.x + shear).abs() < 1e-9 * push, "{force}");
        assert!((force.y - push).abs() < 1e-9 * push, "{force}");
        let (c, spacing) = zone(&result.nodes, |n| n.status == NodeStatus::Stick);
        let expected = hertz.stick_half_width(ratio);
        eprintln!(
            "Q/(F P) = {ratio}: c = {c:.4}, a sqrt(1 - Q/(F P)) = {expected:.4} (Hertz's a \
             {:.4}), spacing {spacing:.4}",
            hertz.half_width()
        );
        assert!(
            (c - expected).abs() <= spacing,
            "Q/(F P) = {ratio}: c = {c}, Cattaneo-Mindlin {expected}, spacing {spacing}"
        );
        // Coulomb's bound at every node, to the fixed point's tolerance (1e-8 of the largest
        // normal force).
        let largest = result
            .nodes
            .iter()
            .fold(0.0f64, |m, n| m.max(n.normal_force));
        for n in &result.nodes {
            let excess = n.friction_t().abs() - COEFFICIENT * n.normal_force;
            assert!(excess <= 1e-7 * COEFFICIENT * largest, "{excess:e}");
        }
    }
}
