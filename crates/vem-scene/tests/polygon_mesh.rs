//! Generated meshes on a polygon (`mesh = { family, polygon, edge_names, n }`): the patch test
//! on the cut mesh of a non-convex polygon with slanted edges reproduces the linear field at
//! every node for every family, parts cut by a box work on the polygon's parts, and a bad
//! polygon is refused at the key of the vertex or edge at fault.

use vem_mesh::generators::MeshFamily;
use vem_scene::toml_file::parse;
use vem_scene::{BuildOptions, KeyPath, Model, Outcome, SceneError};

fn solve(text: &str) -> Result<Outcome, SceneError> {
    let (scene, _) = parse(text).map_err(|e| SceneError::at(KeyPath::root(), e.message))?;
    vem_scene::check::check(&scene)?;
    Model::build(&scene, &BuildOptions::default())?.solve()
}

/// A notched trapezoid (non-convex, slanted edges) meshed by `family`, every edge in one part
/// "rim" held at the linear field u = (0.01 x + 0.02 y, -0.03 x + 0.005 y).
fn notched(family: &str, polygon: &str) -> String {
    format!(
        r#"
[[body]]
name = "plate"
material = {{ E = 100.0, nu = 0.3, plane = "strain" }}
dirichlet = [{{ part = "rim", x = "0.01 * x + 0.02 * y", y = "-0.03 * x + 0.005 * y" }}]

[body.mesh]
family = "{family}"
polygon = {polygon}
edge_names = ["rim", "rim", "rim", "rim", "rim", "rim", "rim"]
n = 12
seed = 5
"#
    )
}

const NOTCHED: &str =
    "[[-0.3, 0.1], [1.7, -0.2], [1.3, 1.1], [0.83, 1.07], [0.61, 0.43], [0.37, 1.13], [0.1, 1.0]]";

#[test]
fn the_patch_test_on_a_notched_polygon_is_exact_for_every_family() {
    for family in MeshFamily::all() {
        let outcome = solve(&notched(family.name(), NOTCHED)).unwrap();
        let body = outcome.body("plate").unwrap();
        let mesh = body.body.mesh();
        let u = body.solution.displacement();
        let mut error: f64 = 0.0;
        for (v, p) in mesh.vertices().iter().enumerate() {
            let exact = [0.01 * p.x + 0.02 * p.y, -0.03 * p.x + 0.005 * p.y];
            error = error.max(
                (u[2 * v] - exact[0])
                    .abs()
                    .max((u[2 * v + 1] - exact[1]).abs()),
            );
        }
        // Relative to the largest displacement (about 0.05).
        assert!(error < 1e-10 * 0.05, "{family}: nodal error {error:e}");
        assert!(
            outcome.summary.bodies[0]
                .mesh
                .contains("on the polygon of 7 vertices"),
            "{}",
            outcome.summary.bodies[0].mesh
        );
    }
}

/// An L-shaped plate on rollers, pulled on a strip of its arm's end cut out of the part "end"
/// by a box: the rollers carry exactly the strip's load.
#[test]
fn parts_cut_by_a_box_out_of_a_polygon_edge() {
    let text = r#"
[[body]]
name = "l"
material = { E = 100.0, nu = 0.3, plane = "strain" }
dirichlet = [{ part = "back", x = 0.0 }, { part = "bottom", y = 0.0 }]
traction = [{ part = "strip", value = [1.0, 0.0] }]

[body.mesh]
family = "quads"
polygon = [[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]]
edge_names = ["bottom", "end", "", "", "", "back"]
n = 10
parts = [{ name = "strip", of = "end", box = [[2, 0.2], [2, 0.6]] }]
"#;
    let outcome = solve(text).unwrap();
    let body = outcome.body("l").unwrap();
    let mesh = body.body.mesh();
    // The unnamed edges keep their default names.
    for part in ["edge2", "edge3", "edge4"] {
        assert!(mesh.part(part).is_ok(), "{part}");
    }
    // Quads of 0.2: the strip is the two edges between y = 0.2 and 0.6.
    assert_eq!(mesh.part("strip").unwrap().edges.len(), 2);
    let back = body.solution.reaction("back").unwrap();
    assert!((back.x + 0.4).abs() < 1e-10, "{back}");
}

#[test]
fn a_bad_polygon_is_refused_at_the_key_of_its_vertex_or_edge() {
    let refused = |text: &str| {
        let e = solve(text).expect_err("refused");
        (e.path.to_string(), e.message)
    };
    // Vertex 4 moved across edge 0: edges 3 and 4 cross edge 0.
    let crossing = NOTCHED.replace("[0.61, 0.43]", "[0.61, -0.5]");
    let (path, message) = refused(&notched("quads", &crossing));
    assert_eq!(path, "body[0].mesh.polygon[0]");
    assert!(
        message.contains("edge 0 (vertex 0 to vertex 1) and edge 3"),
        "{message}"
    );
    // A repeated vertex: edge 2 has zero length.
    let repeated = NOTCHED.replace("[0.83, 1.07]", "[1.3, 1.1]");
    let (path, message) = refused(&notched("quads", &repeated));
    assert_eq!(path, "body[0].mesh.polygon[2]");
    assert!(
        message.contains("edge 2 (vertex 2 to vertex 3) has zero length"),
        "{message}"
    );
    // A point of three coordinates.
    let (path, _) = refused(&notched(
        "quads",
        &NOTCHED.replace("[1.3, 1.1]", "[1.3, 1.1, 0]"),
    ));
    assert_eq!(path, "body[0].mesh.polygon[2]");
    // Clockwise.
    let (path, message) = refused(&notched(
        "quads",
        "[[0, 0], [0, 1], [1, 1], [1, 0], [0.9, 0], [0.5, 0], [0.2, 0]]",
    ));
    assert_eq!(path, "body[0].mesh.polygon");
    assert!(message.contains("clockwise"), "{message}");
    // Edge names that do not fit.
    let few = notched("quads", NOTCHED).replace(
        r#"edge_names = ["rim", "rim", "rim", "rim", "rim", "rim", "rim"]"#,
        r#"edge_names = ["rim"]"#,
    );
    let (path, message) = refused(&few);
    assert_eq!(path, "body[0].mesh.edge_names");
    assert!(message.contains("1 edge names for 7 edges"), "{message}");
    // A family of space, and a polygon with a box.
    let (path, message) = refused(&notched("hexahedra", NOTCHED));
    assert_eq!(path, "body[0].mesh.family");
    assert!(
        message.contains("a `polygon` is meshed in the plane"),
        "{message}"
    );
    let (path, message) = refused(
        &notched("quads", NOTCHED).replace("n = 12", "n = 12\nbox = [[0, 0, 0], [1, 1, 1]]"),
    );
    assert_eq!(path, "body[0].mesh.box");
    assert!(
        message.contains("a `polygon` is a domain in the plane"),
        "{message}"
    );
    // Edge names without a polygon.
    let (path, _) = refused(&notched("quads", NOTCHED).replace(
        &format!("polygon = {NOTCHED}"),
        "rectangle = [[0, 0], [1, 1]]",
    ));
    assert_eq!(path, "body[0].mesh.edge_names");
}
