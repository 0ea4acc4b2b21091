//! Load histories in scenes: each condition's curve scales that condition and no other (a
//! frictionless history equals the static scenes at each step's loads, to round-off), Coulomb
//! friction depends on the path (two paths to one load leave different tractions), and a
//! history that cannot be followed is refused at its key.

use vem_scene::toml_file::parse;
use vem_scene::{BuildOptions, Model, Outcome, SceneError};

/// Two blocks on non-matching meshes: the upper one held on its left side and pressed by a
/// pressure on its top, `extra` appended to the upper block's tractions; the lower one
/// clamped at its bottom.
fn blocks(history: &str, law: &str, tractions: &str) -> String {
    format!(
        r#"
{history}

[[body]]
name = "upper"
mesh = {{ family = "voronoi", rectangle = [[0, 0], [1, 0.5]], n = 6, seed = 3 }}
material = {{ E = 100.0, nu = 0.3, plane = "strain" }}
dirichlet = [{{ part = "left", x = 0.0 }}]
{tractions}

[[body]]
name = "lower"
mesh = {{ family = "quads", rectangle = [[-0.2, -0.5], [1.2, 0]], n = 5 }}
material = {{ E = 100.0, nu = 0.3, plane = "strain" }}
dirichlet = [{{ part = "bottom", x = 0.0, y = 0.0 }}]

[[contact]]
body = "upper"
part = "bottom"
other_body = "lower"
other_part = "top"
law = {law}
"#
    )
}

fn solve(text: &str) -> Result<Outcome, SceneError> {
    let (scene, _) =
        parse(text).map_err(|e| SceneError::at(vem_scene::KeyPath::root(), e.message))?;
    Model::build(&scene, &BuildOptions::default())?.solve()
}

/// The largest difference of the normal forces and of the upper block's displacements,
/// relative to the largest of each.
fn difference(
    a: &vem_contact::ContactResult,
    a_u: &[f64],
    b: &vem_contact::ContactResult,
    b_u: &[f64],
) -> f64 {
    let scale = |v: &mut dyn Iterator<Item = f64>| v.fold(0.0_f64, |m, x| m.max(x.abs()));
    let forces = scale(&mut a.nodes.iter().map(|n| n.normal_force));
    let df = scale(
        &mut a
            .nodes
            .iter()
            .zip(&b.nodes)
            .map(|(x, y)| x.normal_force - y.normal_force),
    );
    let u = scale(&mut a_u.iter().copied());
    let du = scale(&mut a_u.iter().zip(b_u).map(|(x, y)| x - y));
    (df / forces).max(du / u)
}

#[test]
fn each_curve_scales_its_condition_and_a_frictionless_history_equals_the_static_scenes() {
    let pressure = r#"traction = [{ part = "top", pressure = 0.5, curve = [[0, 0], [1, 1]] }, { part = "top", value = [0.05, 0.0], curve = [[1, 0], [2, 1]] }]"#;
    let history = blocks("[history]\ntimes = [1, 2]", "\"frictionless\"", pressure);
    let outcome = solve(&history).unwrap();
    assert_eq!(outcome.steps.len(), 1);
    let first = &outcome.steps[0];
    assert_eq!(first.time, 1.0);
    // Step 1: the pressure at full value, the sideways traction not yet applied.
    let pressed = solve(&blocks(
        "",
        "\"frictionless\"",
        r#"traction = [{ part = "top", pressure = 0.5 }]"#,
    ))
    .unwrap();
    let upper = outcome.contact_bodies[0];
    let step_u = first.result.bodies[0].solution.displacement();
    let pressed_u = pressed.bodies[upper].solution.displacement();
    let d1 = difference(
        &first.result,
        step_u,
        pressed.contact.as_ref().unwrap(),
        pressed_u,
    );
    assert!(d1 < 1e-9, "step 1 differs from the pressed block by {d1:e}");
    // Step 2: both at full value.
    let both = solve(&blocks(
        "",
        "\"frictionless\"",
        r#"traction = [{ part = "top", pressure = 0.5 }, { part = "top", value = [0.05, 0.0] }]"#,
    ))
    .unwrap();
    let d2 = difference(
        outcome.contact.as_ref().unwrap(),
        outcome.bodies[upper].solution.displacement(),
        both.contact.as_ref().unwrap(),
        both.bodies[upper].solution.displacement(),
    );
    assert!(d2 < 1e-9, "step 2 differs from the static scene by {d2:e}");
    // The sideways traction moved the block: the two steps are not the same answer.
    let moved = difference(
        &first.result,
        step_u,
        outcome.contact.as_ref().unwrap(),
        outcome.bodies[upper].solution.displacement(),
    );
    assert!(moved > 1e-3, "{moved:e}");
    // The summary has one row per step, at its time.
    let steps = &outcome.summary.contact.as_ref().unwrap().history;
    assert_eq!(steps.iter().map(|s| s.time).collect::<Vec<_>>(), [1.0, 2.0]);
}

#[test]
fn coulomb_friction_depends_on_the_path() {
    // The same final load (pressure 0.5, sideways traction 0.12, F = 0.3) reached
    // proportionally and by pushing first, then shearing.
    let law = "{ name = \"coulomb\", coefficient = 0.3 }";
    let proportional = blocks(
        "[history]\ntimes = [0.5, 1]",
        law,
        r#"traction = [{ part = "top", pressure = 0.5 }, { part = "top", value = [0.12, 0.0] }]"#,
    );
    let push_then_shear = blocks(
        "[history]\ntimes = [1, 2]",
        law,
        r#"traction = [{ part = "top", pressure = 0.5 }, { part = "top", value = [0.12, 0.0], curve = [[1, 0], [2, 1]] }]"#,
    );
    // Held sideways by friction alone.
    let free = |text: &str| text.replace(r#"dirichlet = [{ part = "left", x = 0.0 }]"#, "");
    let a = solve(&free(&proportional)).unwrap();
    let b = solve(&free(&push_then_shear)).unwrap();
    // Pushed only (no tangential load), the friction forces balance: their resultant is zero.
    let pushed = &b.steps[0].result;
    let resultant = pushed.friction_resultant().norm();
    assert!(
        resultant < 1e-9 * pushed.normal_resultant(),
        "{resultant:e}"
    );
    let (a, b) = (a.contact.unwrap(), b.contact.unwrap());
    // Both carry the same loads ...
    let (fa, fb) = (a.force_on_body_a(), b.force_on_body_a());
    assert!((fa - fb).norm() < 1e-8 * fa.norm(), "{fa} {fb}");
    // ... with different friction forces node by node.
    let largest = a
        .nodes
        .iter()
        .map(|n| n.friction_t().abs())
        .fold(0.0, f64::max);
    let change = a
        .nodes
        .iter()
        .zip(&b.nodes)
        .map(|(x, y)| (x.friction_t() - y.friction_t()).abs())
        .fold(0.0, f64::max);
    assert!(change > 1e-2 * largest, "{change:e} of {largest:e}");
    // Without friction (and held on the left) the paths agree.
    let frictionless = |text: &str| {
        solve(&text.replace(law, "\"frictionless\""))
            .unwrap()
            .contact
            .unwrap()
    };
    let (a, b) = (frictionless(&proportional), frictionless(&push_then_shear));
    for (x, y) in a.nodes.iter().zip(&b.nodes) {
        assert!(
            (x.normal_force - y.normal_force).abs() < 1e-10,
            "{x:?} {y:?}"
        );
    }
}

#[test]
fn histories_that_cannot_be_followed_are_refused_at_their_key() {
    let message = |history: &str, tractions: &str| {
        solve(&blocks(history, "\"frictionless\"", tractions))
            .err()
            .map(|e| (e.path.to_string(), e.message))
            .expect("refused")
    };
    let plain = r#"traction = [{ part = "top", pressure = 0.5 }]"#;
    let curved = r#"traction = [{ part = "top", pressure = 0.5, curve = [[0, 0], [1, 1]] }]"#;
    let (path, text) = message("", curved);
    assert_eq!(path, "body[0].traction[0].curve");
    assert!(text.contains("needs a `[history]` with `times`"), "{text}");
    let (path, text) = message("[history]\nsteps = [0.5, 1]", curved);
    assert_eq!(path, "body[0].traction[0].curve", "{text}");
    let (path, text) = message("[history]\nsteps = [1]\ntimes = [1]", plain);
    assert_eq!(path, "history.steps");
    assert!(text.contains("not both"), "{text}");
    let (path, text) = message("[history]\ntimes = [1, 1]", plain);
    assert_eq!(path, "history.times");
    assert!(text.contains("does not exceed"), "{text}");
    let (path, text) = message(
        "[history]\ntimes = [1]",
        r#"traction = [{ part = "top", pressure = 0.5, curve = [[1, 0], [0, 1]] }]"#,
    );
    assert_eq!(path, "body[0].traction[0].curve");
    assert!(text.contains("point 1"), "{text}");
    let (path, text) = message("[history]\nend = 1.0", plain);
    assert_eq!(path, "history");
    assert!(text.contains("`end` with `increments`"), "{text}");
    let (path, text) = message(
        "[history]\nend = 1.0\nincrements = 4",
        r#"traction = [{ part = "top", value = ["0.1 * t", 0] }]"#,
    );
    assert_eq!(path, "body[0].traction[0].value[0]");
    assert!(text.contains("`curve"), "{text}");
}

#[test]
fn expressions_beyond_the_dimension_are_refused() {
    let text = blocks(
        "",
        "\"frictionless\"",
        r#"traction = [{ part = "top", value = ["0.1 * z", 0] }]"#,
    );
    let e = solve(&text).expect_err("refused");
    assert_eq!(e.path.to_string(), "body[0].traction[0].value[0]");
    assert!(e.message.contains("dimension 2"), "{}", e.message);
}
