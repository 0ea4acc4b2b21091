//! A contact law of one's own, registered in a `LawRegistry` and solved like the built-in
//! laws.
//!
//! The law, in `custom_law/capped_coulomb.rs`, is Coulomb friction capped by a shear
//! strength: `|sigma_tau| <= min(F |sigma_nu|, cap)`, the nodal bound
//! `b_i = min(F lambda_N,i, l_i cap)`, iterated by the fixed point of Coulomb. It joins the
//! built-in laws under the name "capped-coulomb" with the settings `coefficient`, `cap` and
//! `fixed_point`.
//!
//! The problem: a unit block (12 x 12 quads, Lame (2, 1), plane strain) whose top is moved by
//! `(0.01, -0.02)`, pressed and sheared on the rigid line `y = 0`; `F = 0.3`. Checks:
//!
//! 1. a misspelt or invalid setting is refused with its key (`caps`, `cap`,
//!    `fixed_point.max_iterations`);
//! 2. with a cap above every `F p` (`cap = 1`, where `F p <= 0.04`) the answer is plain
//!    Coulomb's (the built-in law): nodal forces agree to `1e-12` relative;
//! 3. with a cap below every `F p` (`cap = 0.01`) the answer is Tresca's with
//!    `g_F = cap` (the built-in law, one solve): nodal forces agree to `1e-12` relative;
//! 4. with a cap in between (`cap = 0.018`) the cone `|lambda_T| <= min(F lambda_N, l
//!    cap)` holds at every node and is reached at every slipping node, some slipping at
//!    the cap and some at `F lambda_N`, within `1e-6` of the largest normal force (the
//!    fixed point stops when the normal forces change by less than `1e-8`);
//! 5. every answer is in equilibrium: the reaction of the top balances the contact force on
//!    the block to `1e-10` relative.
//!
//! Exits non-zero on failure. Run with
//! `cargo run --release -p vem-contact --example custom_law`; `cargo test -p vem-contact` runs the
//! same checks (the example is a test target too: `test = true` in the crate's Cargo.toml).

#[path = "custom_law/capped_coulomb.rs"]
mod capped_coulomb;

use std::process::ExitCode;
use std::sync::Arc;

use vem_contact::{
    CondensedSolver, ContactLaw, ContactProblem, ContactResult, LawRegistry, NodeStatus, Obstacle,
    RegistryError,
};
use vem_elastic::{Component, Dirichlet, ElasticBody, Material, Plane};
use vem_mesh::generators::{MeshFamily, Rectangle};
use vem_mesh::{Point, Vector};
use vem_space::{LowestOrderVem, Options};

/// The friction coefficient.
const F: f64 = 0.3;

type Error = Box<dyn std::error::Error>;

/// The block pressed and sheared on the rigid line, with the contact law `law`.
fn block_on_line(law: Arc<dyn ContactLaw>) -> Result<ContactResult, Error> {
    let square = Rectangle::new(Point::new(0.0, 0.0), Point::new(1.0, 1.0));
    let mesh = MeshFamily::Quads.generate(&square, 12, 0)?;
    let material = Material::from_lame(2.0, 1.0, Plane::Strain)?;
    let body = ElasticBody::builder("block", mesh, material, Arc::new(LowestOrderVem::default()))
        .dirichlet(Dirichlet::prescribed("top", Component::All, |_| {
            Vector::new(0.01, -0.02)
        }))
        .build()?;
    let line = Obstacle::Line {
        point: Point::new(0.0, 0.0),
        normal: Vector::new(0.0, 1.0),
    };
    let problem = ContactProblem::against_obstacle(body, "bottom", line, law);
    Ok(problem.solve(&mut CondensedSolver::default())?)
}

/// The largest difference of the nodal normal and friction forces of `a` and `b`, relative to
/// the largest normal force of `b`.
fn difference(a: &ContactResult, b: &ContactResult) -> f64 {
    let scale = largest_normal_force(b);
    a.nodes
        .iter()
        .zip(&b.nodes)
        .map(|(a, b)| {
            (a.normal_force - b.normal_force)
                .abs()
                .max((a.friction_t() - b.friction_t()).abs())
        })
        .fold(0.0, f64::max)
        / scale
}

fn largest_normal_force(r: &ContactResult) -> f64 {
    r.nodes.iter().map(|n| n.normal_force).fold(0.0, f64::max)
}

/// `|R_top + contact force on the block| / |R_top|`: zero in equilibrium.
fn equilibrium(r: &ContactResult) -> f64 {
    let reaction = r.bodies[0]
        .solution
        .reaction("top")
        .expect("the top is prescribed");
    (reaction + r.force_on_body(0)).norm() / reaction.norm()
}

/// The settings of the capped law.
fn capped(cap: f64) -> Options {
    Options::new().with("coefficient", F).with("cap", cap)
}

/// Runs every check, printing each; the failures.
fn checks() -> Result<Vec<String>, Error> {
    let mut laws = LawRegistry::<2>::builtin();
    capped_coulomb::register(&mut laws)?;
    println!("laws: {}", laws.names().join(", "));
    let mut failures: Vec<String> = Vec::new();
    let mut check = |ok: bool, what: String| {
        println!("{} {what}", if ok { "ok  " } else { "FAIL" });
        if !ok {
            failures.push(what);
        }
    };

    // 1. Settings refused with their keys.
    let refused = |options: Options| -> Result<RegistryError, Error> {
        match laws.make(capped_coulomb::NAME, &options) {
            Ok(law) => Err(format!("accepted: {}", law.describe()).into()),
            Err(e) => Ok(e),
        }
    };
    for (options, key) in [
        (
            Options::new().with("coefficient", F).with("caps", 0.02),
            "caps",
        ),
        (capped(-1.0), "cap"),
        (
            capped(0.02).with("fixed_point", serde_json::json!({ "max_iterations": 0 })),
            "fixed_point.max_iterations",
        ),
    ] {
        let error = refused(options)?;
        check(
            error.option_path() == Some(key),
            format!("refused at `{key}`: {error}"),
        );
    }

    // The built-in laws, made by name like ours.
    let coulomb = block_on_line(laws.make("coulomb", &Options::new().with("coefficient", F))?)?;
    let largest_fp = coulomb
        .nodes
        .iter()
        .map(|n| F * n.pressure)
        .fold(0.0, f64::max);
    println!(
        "coulomb: F p from {:.4} to {largest_fp:.4}, {} fixed-point steps",
        coulomb
            .nodes
            .iter()
            .map(|n| F * n.pressure)
            .fold(f64::INFINITY, f64::min),
        coulomb.fixed_point.as_ref().map_or(0, |f| f.steps)
    );

    // 2. A cap above every F p: plain Coulomb.
    let high = block_on_line(laws.make(capped_coulomb::NAME, &capped(1.0))?)?;
    let d = difference(&high, &coulomb);
    check(
        largest_fp < 1.0 && d <= 1e-12,
        format!("cap = 1 (above F p <= {largest_fp:.4}): coulomb's answer to {d:.1e}"),
    );

    // 3. A cap below every F p: Tresca with g_F = cap.
    let cap = 0.01;
    let low = block_on_line(laws.make(capped_coulomb::NAME, &capped(cap))?)?;
    let tresca = block_on_line(laws.make("tresca", &Options::new().with("friction_bound", cap))?)?;
    let smallest_fp = low
        .nodes
        .iter()
        .map(|n| F * n.pressure)
        .fold(f64::INFINITY, f64::min);
    let d = difference(&low, &tresca);
    check(
        smallest_fp > cap && d <= 1e-12,
        format!(
            "cap = {cap} (below F p >= {smallest_fp:.4}): tresca's answer to {d:.1e}, {} \
             fixed-point step(s)",
            low.fixed_point.as_ref().map_or(0, |f| f.steps)
        ),
    );

    // 4. A cap in between: the cone min(F lambda_N, l cap), reached where the node slips.
    let cap = 0.018;
    let mixed = block_on_line(laws.make(capped_coulomb::NAME, &capped(cap))?)?;
    let tolerance = 1e-6 * largest_normal_force(&mixed);
    let (mut outside, mut short, mut at_cap, mut at_coulomb) = (0.0f64, 0.0f64, 0, 0);
    for node in &mixed.nodes {
        let (coulomb_bound, cap_bound) = (F * node.normal_force, cap * node.tributary_measure);
        let bound = coulomb_bound.min(cap_bound);
        let friction = node.friction_t().abs();
        outside = outside.max(friction - bound);
        if node.status == NodeStatus::Slip {
            short = short.max(bound - friction);
            if cap_bound < coulomb_bound {
                at_cap += 1;
            } else {
                at_coulomb += 1;
            }
        }
    }
    check(
        outside <= tolerance && short <= tolerance && at_cap > 0 && at_coulomb > 0,
        format!(
            "cap = {cap}: |lambda_T| exceeds min(F lambda_N, l cap) by at most \
             {outside:.1e}, falls short of it at a slipping node by at most {short:.1e} \
             (tolerance {tolerance:.1e}); {at_cap} nodes slip at the cap, {at_coulomb} at F \
             lambda_N, {} stick; {} fixed-point steps",
            mixed.status_counts().stick,
            mixed.fixed_point.as_ref().map_or(0, |f| f.steps)
        ),
    );

    // 5. Equilibrium of every answer.
    for (name, r) in [
        ("coulomb", &coulomb),
        ("cap = 1", &high),
        ("cap = 0.01", &low),
        ("tresca", &tresca),
        ("cap = 0.018", &mixed),
    ] {
        let e = equilibrium(r);
        check(
            e <= 1e-10,
            format!(
                "{name}: friction resultant {:+.6}, equilibrium of the block to {e:.1e}",
                r.tangential_resultant()
            ),
        );
    }

    Ok(failures)
}

fn main() -> Result<ExitCode, Error> {
    let failures = checks()?;
    if failures.is_empty() {
        println!("law '{}': pass", capped_coulomb::NAME);
        Ok(ExitCode::SUCCESS)
    } else {
        eprintln!(
            "law '{}' FAILS:\n- {}",
            capped_coulomb::NAME,
            failures.join("\n- ")
        );
        Ok(ExitCode::FAILURE)
    }
}

/// `cargo test` runs the checks too.
#[test]
fn the_checks_pass() {
    let failures = checks().expect("the problems solve");
    assert!(failures.is_empty(), "{failures:#?}");
}
