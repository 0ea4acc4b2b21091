//! A contact law of one's own named by a scene: `law = { name = "capped-coulomb", ... }`
//! reaches the law of `crates/vem-contact/examples/custom_law/capped_coulomb.rs` once it is
//! registered in the `laws` of the `Registries` the scene is built with.
//!
//! The scene: a unit block (12 x 12 quads, E = 8/3, nu = 1/3, plane strain: Lame (2, 1))
//! whose top is moved by `(0.01, -0.02)`, pressed and sheared on the rigid line `y = 0`,
//! `F = 0.3`. Checks:
//!
//! 1. without the law registered, the scene is refused at `contact[0].law`, the error listing
//!    the known laws; a misspelt setting of the law (`caps`) and of the solver (`tolerence`)
//!    are refused at their keys, shown at their line of the scene text;
//! 2. with a cap below every `F p` (`cap = 0.01`) the scene's answer is that of the same scene
//!    with the built-in `law = { name = "tresca", friction_bound = 0.01 }`: nodal forces agree
//!    to `1e-12` relative;
//! 3. with a cap in between (`cap = 0.018`) the friction stays within
//!    `min(F lambda_N, l cap)` at every node and reaches it at every slipping node, within
//!    `1e-6` of the largest normal force, and the run's summary names the law.
//!
//! Exits non-zero on failure. Run with
//! `cargo run --release -p vem-scene --example custom_law_scene`; `cargo test -p vem-scene` runs the
//! same checks (the example is a test target too: `test = true` in the crate's Cargo.toml).

#[path = "../../vem-contact/examples/custom_law/capped_coulomb.rs"]
mod capped_coulomb;

use std::process::ExitCode;

use vem_contact::{ContactResult, NodeStatus};
use vem_scene::toml_file::{self, SpanIndex};
use vem_scene::{BuildOptions, Model, Registries, SceneError};

type Error = Box<dyn std::error::Error>;

/// The friction coefficient.
const F: f64 = 0.3;

/// The scene with the contact law `law` and the solver `solver` (TOML values).
fn scene(law: &str, solver: &str) -> String {
    format!(
        r#"title = "a block pressed and sheared on a rigid line"
solver = {solver}

[[body]]
name = "block"
mesh = {{ family = "quads", rectangle = [[0, 0], [1, 1]], n = 12 }}
material = {{ E = 2.6666666666666665, nu = 0.3333333333333333, plane = "strain" }}
dirichlet = [{{ part = "top", x = 0.01, y = -0.02 }}]

[[contact]]
body = "block"
part = "bottom"
obstacle = {{ line = {{ point = [0, 0], normal = [0, 1] }} }}
law = {law}
"#
    )
}

/// The law `capped-coulomb` with `F` and the cap `cap`, as a scene writes it.
fn capped(cap: f64) -> String {
    format!(r#"{{ name = "capped-coulomb", coefficient = {F}, cap = {cap} }}"#)
}

/// The scene `text` built with `registries` and solved, or the error as the `vem` command
/// shows it: `scene.toml:LINE: key path: message`.
fn run(text: &str, registries: &Registries) -> Result<Result<ContactResult, String>, Error> {
    let (scene, spans) = toml_file::parse(text).map_err(|e| e.message)?;
    let options = BuildOptions {
        registries: registries.clone(),
        ..BuildOptions::default()
    };
    match Model::build(&scene, &options).and_then(|model| model.solve()) {
        Ok(outcome) => Ok(Ok(outcome.contact.ok_or("no contact result")?)),
        Err(error) => Ok(Err(located(text, &spans, &error))),
    }
}

/// `scene.toml:LINE: error`, the line of the key at fault.
fn located(text: &str, spans: &SpanIndex, error: &SceneError) -> String {
    let line = spans
        .span(&error.path)
        .map_or(0, |span| text[..span.start].lines().count());
    format!("scene.toml:{line}: {error}")
}

/// The largest normal force of `r`.
fn largest_normal_force(r: &ContactResult) -> f64 {
    r.nodes.iter().map(|n| n.normal_force).fold(0.0, f64::max)
}

/// Runs every check, printing each; the failures.
fn checks() -> Result<Vec<String>, Error> {
    // The built-in names and the law of one's own.
    let mut registries = Registries::default();
    capped_coulomb::register(&mut registries.laws)?;
    println!("laws: {}", registries.laws.names().join(", "));
    let condensed = r#""condensed""#;
    let mut failures: Vec<String> = Vec::new();
    let mut check = |ok: bool, what: String| {
        println!("{} {what}", if ok { "ok  " } else { "FAIL" });
        if !ok {
            failures.push(what);
        }
    };

    // 1. Refused names and settings, at their keys.
    let builtin = Registries::default();
    let misspelt_law = r#"{ name = "capped-coulomb", coefficient = 0.3, caps = 0.018 }"#;
    let misspelt_solver = r#"{ name = "condensed", tolerence = 1e-10 }"#;
    for (text, registries, key) in [
        (scene(&capped(0.018), condensed), &builtin, "contact[0].law"),
        (
            scene(misspelt_law, condensed),
            &registries,
            "contact[0].law.caps",
        ),
        (
            scene(&capped(0.018), misspelt_solver),
            &registries,
            "solver.tolerence",
        ),
    ] {
        match run(&text, registries)? {
            Ok(_) => check(false, format!("accepted a scene with an error at {key}")),
            Err(error) => check(error.contains(&format!(": {key}: ")), error),
        }
    }

    // 2. A cap below every F p: the built-in Tresca law with that bound.
    let low = run(&scene(&capped(0.01), condensed), &registries)??;
    let tresca_law = r#"{ name = "tresca", friction_bound = 0.01 }"#;
    let tresca = run(&scene(tresca_law, condensed), &registries)??;
    let d = low
        .nodes
        .iter()
        .zip(&tresca.nodes)
        .map(|(a, b)| {
            (a.normal_force - b.normal_force)
                .abs()
                .max((a.friction_t() - b.friction_t()).abs())
        })
        .fold(0.0, f64::max)
        / largest_normal_force(&tresca);
    let smallest_fp = low
        .nodes
        .iter()
        .map(|n| F * n.pressure)
        .fold(f64::INFINITY, f64::min);
    check(
        smallest_fp > 0.01 && d <= 1e-12,
        format!("cap = 0.01 (below F p >= {smallest_fp:.4}): tresca's answer to {d:.1e}"),
    );

    // 3. A cap in between: on the cone min(F lambda_N, l cap) where the node slips.
    let cap = 0.018;
    let mixed = run(&scene(&capped(cap), condensed), &registries)??;
    let tolerance = 1e-6 * largest_normal_force(&mixed);
    let (mut worst, mut at_cap, mut at_coulomb) = (0.0f64, 0, 0);
    for node in &mixed.nodes {
        let (coulomb, capped) = (F * node.normal_force, cap * node.tributary_measure);
        let friction = node.friction_t().abs();
        worst = worst.max(friction - coulomb.min(capped));
        if node.status == NodeStatus::Slip {
            worst = worst.max(coulomb.min(capped) - friction);
            if capped < coulomb {
                at_cap += 1;
            } else {
                at_coulomb += 1;
            }
        }
    }
    let law = &mixed.model.pairs[0].law;
    check(
        worst <= tolerance
            && at_cap > 0
            && at_coulomb > 0
            && law == &format!("capped coulomb, F = {F}, cap = {cap}"),
        format!(
            "cap = {cap} (law: {law}): friction off the cone by at most {worst:.1e} \
             (tolerance {tolerance:.1e}); {at_cap} nodes slip at the cap, {at_coulomb} at F \
             lambda_N; friction resultant {:+.6}",
            mixed.tangential_resultant()
        ),
    );

    Ok(failures)
}

fn main() -> Result<ExitCode, Error> {
    let failures = checks()?;
    if failures.is_empty() {
        println!("scene with law '{}': pass", capped_coulomb::NAME);
        Ok(ExitCode::SUCCESS)
    } else {
        eprintln!(
            "scene with law '{}' FAILS:\n- {}",
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
