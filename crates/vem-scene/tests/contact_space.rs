//! Contact in space through scene files: the contact patch test of two stacked blocks on
//! non-matching meshes (a uniform pressure transmitted node by node), a block pressed on a
//! rigid plane, a block lifted into a rigid sphere with friction, and bad input in space, each
//! error at its key.

use std::path::Path;

use vem_scene::toml_file::parse;
use vem_scene::{BuildOptions, KeyPath, Model, Outcome, SceneError};

fn build(text: &str) -> Result<Model, SceneError> {
    let (scene, _) = parse(text).map_err(|e| SceneError::at(KeyPath::root(), e.message))?;
    let options = BuildOptions {
        base: Path::new(env!("CARGO_MANIFEST_DIR")).to_path_buf(),
        ..BuildOptions::default()
    };
    Model::build(&scene, &options)
}

fn solve(text: &str) -> Result<Outcome, SceneError> {
    build(text)?.solve()
}

fn error_of(text: &str) -> SceneError {
    match solve(text) {
        Ok(_) => panic!("the scene was accepted:\n{text}"),
        Err(e) => e,
    }
}

/// Two blocks of moduli `E1 = 100` (upper, `[0, 1]^2 x [0, 1]`) and `E2 = 300` (lower,
/// `[0, 1]^2 x [-1, 0]`) on rollers (left x, front y), the lower one on rollers at its bottom,
/// the upper one's top moved down by `D`: uniaxial stress `sigma = -D / (1/E1 + 1/E2)` in both,
/// transmitted through the interface whatever the two meshes.
const D: f64 = 0.01;

fn stacked(upper: &str, lower: &str, law: &str, normal: &str) -> String {
    format!(
        r#"
title = "two stacked blocks"
[[body]]
name = "upper"
mesh = {upper}
material = {{ E = 100.0, nu = 0.3 }}
dirichlet = [{{ part = "left", x = 0.0 }}, {{ part = "front", y = 0.0 }}, {{ part = "top", z = -{D} }}]

[[body]]
name = "lower"
mesh = {lower}
material = {{ E = 300.0, nu = 0.3 }}
dirichlet = [{{ part = "left", x = 0.0 }}, {{ part = "front", y = 0.0 }}, {{ part = "bottom", z = 0.0 }}]

[[contact]]
body = "upper"
part = "bottom"
other_body = "lower"
other_part = "top"
law = {law}
{normal}
"#
    )
}

const HEXAHEDRA_3: &str = r#"{ family = "hexahedra", box = [[0, 0, 0], [1, 1, 1]], n = 3 }"#;
const TETRAHEDRA_4: &str = r#"{ family = "tetrahedra", box = [[0, 0, -1], [1, 1, 0]], n = 4 }"#;
const VORONOI_3: &str = r#"{ family = "voronoi", box = [[0, 0, 0], [1, 1, 1]], n = 3, seed = 2 }"#;
const HEXAHEDRA_5: &str = r#"{ family = "hexahedra", box = [[0, 0, -1], [1, 1, 0]], n = 5 }"#;

#[test]
fn the_contact_patch_test_through_a_scene_file_transmits_the_uniform_pressure() {
    let sigma = D / (1.0 / 100.0 + 1.0 / 300.0);
    for (upper, lower) in [(HEXAHEDRA_3, TETRAHEDRA_4), (VORONOI_3, HEXAHEDRA_5)] {
        for normal in ["", "normal = \"body_a\"", "normal = \"averaged\""] {
            let text = stacked(upper, lower, "\"frictionless\"", normal);
            let outcome = solve(&text).unwrap_or_else(|e| panic!("{e}\n{text}"));
            assert_eq!(outcome.dimension(), 3);
            let contact = outcome.contact_3d.as_ref().expect("a contact result");
            assert!(contact.nodes.len() > 16, "{}", contact.nodes.len());
            for node in &contact.nodes {
                assert!(
                    (node.pressure / sigma - 1.0).abs() < 1e-10,
                    "{upper} on {lower} {normal}: node at {:?}: {} against {sigma}",
                    node.position,
                    node.pressure
                );
                assert!((node.consistent_pressure / sigma - 1.0).abs() < 1e-10);
            }
            // The interface's area is 1: the resultant is sigma, and the force on the upper
            // block is -sigma along z (it is pushed up).
            let summary = outcome.summary.contact.as_ref().expect("a summary");
            assert!((summary.resultants.normal / sigma - 1.0).abs() < 1e-10);
            let force = &summary.resultants.force_on_body_a;
            assert_eq!(force.len(), 3);
            assert!((force[2] / sigma - 1.0).abs() < 1e-10, "{force:?}");
            assert!(force[0].abs() < 1e-10 * sigma && force[1].abs() < 1e-10 * sigma);
            assert_eq!(summary.nodes.open, 0);
            assert!(summary.report.residuals.stationarity < 1e-8);
            // The top's reaction balances the transmitted force.
            let upper_body = &outcome.summary.bodies[0];
            let top = upper_body
                .reactions
                .iter()
                .find(|r| r.part == "top")
                .expect("the top's reaction");
            assert!((top.force[2] / sigma + 1.0).abs() < 1e-9, "{:?}", top.force);
            assert!(upper_body.inserted_vertices > 0 || upper == HEXAHEDRA_3);
            if upper == HEXAHEDRA_3 {
                // Cubes: the star ratio is the inradius over the diagonal, 1/(2 sqrt 3), even
                // with the other side's nodes inserted in their faces (the shape is the same),
                // while gamma falls with the short edges they make.
                let cube = 1.0 / (2.0 * 3f64.sqrt());
                assert!(
                    (upper_body.star_ratio - cube).abs() < 1e-9,
                    "{upper_body:?}"
                );
                assert!(upper_body.gamma <= upper_body.star_ratio);
            }
            // Both bodies' displacements: u_z linear in z, the upper top at -D.
            let lower_body = outcome.body_3d("lower").expect("the lower body");
            let strain = sigma / 300.0;
            for (v, p) in lower_body.body.mesh().vertices().iter().enumerate() {
                let u = lower_body.solution.vertex_displacement(v);
                assert!((u.z + strain * (p.z + 1.0)).abs() < 1e-10, "{u:?} at {p:?}");
            }
        }
    }
}

#[test]
fn a_block_pressed_on_a_rigid_plane_carries_the_pressure_at_every_node() {
    let p = 0.2;
    let text = format!(
        r#"
[[body]]
name = "block"
mesh = {{ family = "voronoi", box = [[0, 0, 0], [2, 1, 1]], n = 4, seed = 3 }}
material = {{ E = 100.0, nu = 0.3 }}
dirichlet = [{{ part = "left", x = 0.0 }}, {{ part = "front", y = 0.0 }}]
traction = [{{ part = "top", pressure = {p} }}]

[[contact]]
body = "block"
part = "bottom"
obstacle = {{ plane = {{ point = [0, 0, 0], normal = [0, 0, 1] }} }}
"#
    );
    let outcome = solve(&text).unwrap_or_else(|e| panic!("{e}"));
    let contact = outcome.contact_3d.as_ref().expect("a contact result");
    for node in &contact.nodes {
        // The body is held along z by the contact alone: the solve leaves 1e-10 of p.
        assert!((node.pressure / p - 1.0).abs() < 1e-9, "{}", node.pressure);
        // The gap closed: no penetration beyond 1e-8 of the compression p h / E.
        assert!(
            node.normal_jump.abs() < 1e-8 * p / 100.0,
            "{}",
            node.normal_jump
        );
    }
    let summary = outcome.summary.contact.as_ref().expect("a summary");
    // The bottom's area is 2.
    assert!((summary.resultants.normal / (2.0 * p) - 1.0).abs() < 1e-10);
    assert_eq!(summary.model.tangential_rows, 0);
    assert!(summary.model.pairs[0].description.contains("rigid plane"));
    let model = build(&text).expect("the model");
    assert!(model.contacts()[0].obstacle_3d.is_some());
}

#[test]
fn friction_in_space_holds_a_block_lifted_into_a_sphere() {
    // A block clamped at its bottom lifted by 0.02 into a rigid ball: Tresca and Coulomb with
    // a large bound stick everywhere and give the frictionless normal forces' sum within the
    // tangential force's effect; the KKT certificate holds and the rows are those of friction.
    let scene = |law: &str| {
        format!(
            r#"
solver = "condensed"
[[body]]
name = "block"
mesh = {{ family = "hexahedra", box = [[-1, -1, -1], [1, 1, 0]], n = 4 }}
material = {{ E = 100.0, nu = 0.3 }}
dirichlet = [{{ part = "bottom", x = 0.0, y = 0.0, z = 0.02 }}]

[[contact]]
body = "block"
part = "top"
obstacle = {{ sphere = {{ centre = [0, 0, 2], radius = 2.0 }} }}
law = {law}
"#
        )
    };
    let frictionless = solve(&scene("\"frictionless\"")).unwrap_or_else(|e| panic!("{e}"));
    let normal = frictionless
        .summary
        .contact
        .as_ref()
        .unwrap()
        .resultants
        .normal;
    assert!(normal > 0.0);
    for law in [
        r#"{ name = "tresca", friction_bound = 0.5 }"#,
        r#"{ name = "coulomb", coefficient = 0.3 }"#,
    ] {
        let outcome = solve(&scene(law)).unwrap_or_else(|e| panic!("{law}: {e}"));
        let summary = outcome.summary.contact.as_ref().unwrap();
        assert_eq!(
            summary.model.tangential_rows,
            2 * summary.model.normal_rows,
            "{law}"
        );
        let r = &summary.report.residuals;
        assert!(
            r.stationarity < 1e-6 && r.friction_bound_violation < 1e-6,
            "{law}: {r:?}"
        );
        // The force on the block: along -z by symmetry, its magnitude the clamp's reaction.
        let force = &summary.resultants.force_on_body_a;
        let reaction = &outcome.summary.bodies[0].reactions[0].force;
        for i in 0..3 {
            assert!(
                (force[i] + reaction[i]).abs() < 1e-8 * normal,
                "{law}: {force:?} {reaction:?}"
            );
        }
        assert!(force[0].abs() < 1e-8 * normal && force[1].abs() < 1e-8 * normal);
    }
}

/// The stacked blocks of the patch test with `edit` applied: the error's key path and words.
fn assert_error(text: &str, path: &str, words: &str) {
    let error = error_of(text);
    assert_eq!(error.path.to_string(), path, "{error}\n{text}");
    assert!(error.message.contains(words), "{}\n{text}", error.message);
}

#[test]
fn bad_contact_input_in_space_is_refused_at_its_key() {
    let good = stacked(HEXAHEDRA_3, HEXAHEDRA_5, "\"frictionless\"", "");
    // A contact part the mesh does not have lists the parts.
    assert_error(
        &good.replace("part = \"bottom\"\nother_body", "part = \"botom\"\nother_body"),
        "contact[0].part",
        "body 'upper' has no boundary part named 'botom'; its mesh has ['left', 'right', 'front', 'back', 'bottom', 'top']",
    );
    assert_error(
        &good.replace("other_part = \"top\"", "other_part = \"tp\""),
        "contact[0].other_part",
        "body 'lower' has no boundary part named 'tp'",
    );
    // Friction keys on a frictionless law.
    assert_error(
        &good.replace(
            "law = \"frictionless\"",
            "law = { name = \"frictionless\", friction_bound = 0.3 }",
        ),
        "contact[0].law.friction_bound",
        "friction_bound",
    );
    // The obstacle keys of the plane in space.
    let obstacle = r#"
[[body]]
name = "block"
mesh = { family = "hexahedra", box = [[0, 0, 0], [1, 1, 1]], n = 2 }
material = { E = 100.0, nu = 0.3 }
dirichlet = [{ part = "top", z = -0.01 }]

[[contact]]
body = "block"
part = "bottom"
"#;
    assert_error(
        &format!("{obstacle}obstacle = {{ circle = {{ centre = [0, 0], radius = 1.0 }} }}\n"),
        "contact[0].obstacle.circle",
        "`circle` is an obstacle in the plane; write `sphere = { centre = [x, y, z], radius = r }`",
    );
    assert_error(
        &format!("{obstacle}obstacle = {{ polyline = [[0, 0], [1, 0]] }}\n"),
        "contact[0].obstacle.polyline",
        "`polyline` is an obstacle in the plane",
    );
    // A plane of the wrong length, a sphere without a radius.
    assert_error(
        &format!("{obstacle}obstacle = {{ plane = {{ point = [0, 0], normal = [0, 0, 1] }} }}\n"),
        "contact[0].obstacle.plane.point",
        "an array of 2 entries where exactly 3 are expected",
    );
    assert_error(
        &format!("{obstacle}obstacle = {{ sphere = {{ centre = [0, 0, 2], radius = -1.0 }} }}\n"),
        "contact[0].obstacle",
        "radius",
    );
    // `normal` against an obstacle.
    assert_error(
        &format!(
            "{obstacle}obstacle = {{ plane = {{ point = [0, 0, 0], normal = [0, 0, 1] }} }}\nnormal = \"body_a\"\n"
        ),
        "contact[0].normal",
        "`normal` does not apply to an obstacle",
    );
    // The obstacles of space in the plane.
    let plane = r#"
[[body]]
name = "block"
mesh = { family = "quads", rectangle = [[0, 0], [1, 1]], n = 2 }
material = { E = 100.0, nu = 0.3, plane = "strain" }
dirichlet = [{ part = "top", y = -0.01 }]

[[contact]]
body = "block"
part = "bottom"
obstacle = { sphere = { centre = [0, -1, 0], radius = 1.0 } }
"#;
    assert_error(
        plane,
        "contact[0].obstacle.sphere",
        "body 'block' is in the plane: `sphere` is an obstacle in space; write `circle = { centre = [x, y], radius = r }`",
    );
}

#[test]
fn two_bodies_whose_parts_never_face_each_other_are_refused_at_the_pair() {
    // The lower block's bottom is far below and faces away from the upper block's bottom: the
    // overlay finds no cell in common.
    let text = stacked(HEXAHEDRA_3, HEXAHEDRA_5, "\"frictionless\"", "")
        .replace("other_part = \"top\"", "other_part = \"bottom\"");
    let error = error_of(&text);
    assert_eq!(error.path.to_string(), "contact[0]", "{error}");
    assert!(
        error.message.contains("upper") && error.message.contains("lower"),
        "{}",
        error.message
    );
}
