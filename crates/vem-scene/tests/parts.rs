//! Boundary parts cut out of a mesh's boundary by a box: a strip load on part of an edge
//! carries exactly the load of the strip's length, a partial clamp holds the body, and a part
//! that cannot be made is refused at its key.

use vem_scene::toml_file::parse;
use vem_scene::{BuildOptions, KeyPath, Model, Outcome, SceneError};

fn solve(text: &str) -> Result<Outcome, SceneError> {
    let (scene, _) = parse(text).map_err(|e| SceneError::at(KeyPath::root(), e.message))?;
    Model::build(&scene, &BuildOptions::default())?.solve()
}

/// A block [0, 1] x [0, 0.5] on quads n = 10 (edges of 0.1 on top) with `parts`, clamped on
/// the part `clamp`, pressed by 2 on the part `strip`.
fn block(parts: &str) -> String {
    format!(
        r#"
[[body]]
name = "block"
mesh = {{ family = "quads", rectangle = [[0, 0], [1, 0.5]], n = 10, parts = {parts} }}
material = {{ E = 100.0, nu = 0.3, plane = "strain" }}
dirichlet = [{{ part = "clamp", x = 0.0, y = 0.0 }}]
traction = [{{ part = "strip", pressure = 2.0 }}]
"#
    )
}

#[test]
fn a_strip_load_and_a_partial_clamp_cut_out_by_boxes() {
    let outcome = solve(&block(
        r#"[{ name = "strip", of = "top", box = [[0.4, 0.0], [0.6, 1.0]] }, { name = "clamp", of = "bottom", box = [[0.0, 0.0], [0.3, 0.0]] }]"#,
    ))
    .unwrap();
    let block = outcome.body("block").unwrap();
    let mesh = block.body.mesh();
    // The strip: the two top edges between x = 0.4 and 0.6; the clamp: three bottom edges.
    assert_eq!(mesh.part("strip").unwrap().edges.len(), 2);
    assert_eq!(mesh.part("clamp").unwrap().edges.len(), 3);
    // The clamp carries the strip's load: pressure 2 times the length 0.2 (equilibrium).
    let reaction = block.solution.reaction("clamp").unwrap();
    assert!((reaction.y - 0.4).abs() < 1e-10, "{reaction}");
    assert!(reaction.x.abs() < 1e-10, "{reaction}");
}

#[test]
fn parts_that_cannot_be_made_are_refused_at_their_key() {
    let refused = |parts: &str| {
        let e = solve(&block(parts)).expect_err("refused");
        (e.path.to_string(), e.message)
    };
    let (path, message) = refused(
        r#"[{ name = "strip", of = "top", box = [[2, 2], [3, 3]] }, { name = "clamp", box = [[0, 0], [1, 0]] }]"#,
    );
    assert_eq!(path, "body[0].mesh.parts[0].box");
    assert!(
        message.contains("no boundary edge of part 'top'"),
        "{message}"
    );
    let (path, message) = refused(r#"[{ name = "strip", of = "roof", box = [[0, 0], [1, 1]] }]"#);
    assert_eq!(path, "body[0].mesh.parts[0].of");
    assert!(
        message.contains("'roof'") && message.contains("top"),
        "{message}"
    );
    let (path, message) = refused(r#"[{ name = "top", box = [[0, 0], [1, 1]] }]"#);
    assert_eq!(path, "body[0].mesh.parts[0].name");
    assert!(message.contains("top"), "{message}");
    let (path, _) = refused(r#"[{ name = "strip", box = [[1, 1], [0, 0]] }]"#);
    assert_eq!(path, "body[0].mesh.parts[0].box");
}
