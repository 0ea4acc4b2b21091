//! Meshes given inline (`vertices` with `polygons` or `polyhedra`, parts by `part_edges` or
//! `part_faces`): the patch test on a mesh written out by hand reproduces the uniform state
//! exactly, in the plane and in space, and a bad mesh is refused at the key of the polygon,
//! vertex or part at fault.

use vem_scene::toml_file::parse;
use vem_scene::{BuildOptions, KeyPath, Model, Outcome, SceneError};

fn solve(text: &str) -> Result<Outcome, SceneError> {
    let (scene, _) = parse(text).map_err(|e| SceneError::at(KeyPath::root(), e.message))?;
    vem_scene::check::check(&scene)?;
    Model::build(&scene, &BuildOptions::default())?.solve()
}

/// The unit square cut into a quadrilateral, a pentagon and a triangle (vertex 4 at (0.5,
/// 0.4) is interior), on rollers left and bottom, pulled by `p` on the right.
fn square(polygons: &str, part_edges: &str) -> String {
    format!(
        r#"
[[body]]
name = "square"
material = {{ E = 100.0, nu = 0.3, plane = "stress" }}
dirichlet = [{{ part = "left", x = 0.0 }}, {{ part = "bottom", y = 0.0 }}]
traction = [{{ part = "right", value = [2.0, 0.0] }}]

[body.mesh]
vertices = [[0, 0], [1, 0], [1, 1], [0, 1], [0.5, 0.4], [0.5, 0], [0, 0.6]]
polygons = {polygons}
part_edges = {part_edges}
"#
    )
}

const POLYGONS: &str = "[[0, 5, 4, 6], [5, 1, 2, 4], [4, 2, 3, 6]]";
const PARTS: &str = "{ left = [[3, 6], [6, 0]], bottom = [[0, 5], [5, 1]], right = [[1, 2]] }";

#[test]
fn the_patch_test_on_polygons_given_inline_is_exact() {
    let outcome = solve(&square(POLYGONS, PARTS)).unwrap();
    let body = outcome.body("square").unwrap();
    assert_eq!(body.body.mesh().n_polygons(), 3);
    // Plane stress, sigma_xx = 2: eps_xx = 2 / E, eps_yy = -nu 2 / E.
    let (ex, ey) = (2.0 / 100.0, -0.3 * 2.0 / 100.0);
    for (v, p) in body.body.mesh().vertices().iter().enumerate() {
        let u = body.solution.displacement();
        assert!((u[2 * v] - ex * p.x).abs() < 1e-12, "vertex {v}");
        assert!((u[2 * v + 1] - ey * p.y).abs() < 1e-12, "vertex {v}");
    }
    for field in &body.fields {
        assert!((field.stress[(0, 0)] - 2.0).abs() < 1e-10);
        assert!(field.stress[(1, 1)].abs() < 1e-10 && field.stress[(0, 1)].abs() < 1e-10);
    }
    // The reaction on the left carries the pull: -2 times the length 1.
    let left = body.solution.reaction("left").unwrap();
    assert!((left.x + 2.0).abs() < 1e-10, "{left}");
    assert!(outcome.summary.bodies[0].mesh.contains("given inline"));
}

#[test]
fn a_bad_inline_mesh_is_refused_at_the_key_of_its_cell_vertex_or_part() {
    let refused = |polygons: &str, parts: &str| {
        let e = solve(&square(polygons, parts)).expect_err("refused");
        (e.path.to_string(), e.message)
    };
    // A vertex index out of range in polygon 1.
    let (path, message) = refused("[[0, 5, 4, 6], [5, 1, 9, 4], [4, 2, 3, 6]]", PARTS);
    assert_eq!(path, "body[0].mesh.polygons[1]");
    assert!(
        message.contains("polygon 1") && message.contains("vertex 9"),
        "{message}"
    );
    // Polygon 2 clockwise: it runs along the edge (2, 4) the way polygon 1 does.
    let (path, message) = refused("[[0, 5, 4, 6], [5, 1, 2, 4], [6, 3, 2, 4]]", PARTS);
    assert_eq!(path, "body[0].mesh.polygons[2]");
    assert!(message.contains("polygon"), "{message}");
    // A part naming an interior edge.
    let (path, message) = refused(POLYGONS, "{ left = [[3, 6], [6, 0]], bottom = [[5, 4]] }");
    assert_eq!(path, "body[0].mesh.part_edges.bottom");
    assert!(message.contains("interior"), "{message}");
    // Keys that belong to other mesh sources, and points of the wrong length.
    let e = solve(&square(POLYGONS, PARTS).replace("[body.mesh]", "[body.mesh]\nn = 4"))
        .expect_err("refused");
    assert_eq!(e.path.to_string(), "body[0].mesh.n");
    let e = solve(&square(POLYGONS, PARTS).replace("[0.5, 0.4]", "[0.5, 0.4, 0]"))
        .expect_err("refused");
    assert_eq!(e.path.to_string(), "body[0].mesh.vertices[4]");
    let e = solve(
        &square(POLYGONS, "{}").replace("part_edges = {}", "part_faces = { a = [[0, 1, 2]] }"),
    )
    .expect_err("refused");
    assert_eq!(e.path.to_string(), "body[0].mesh.part_faces");
}

/// Two unit cubes side by side along x, each by its six outward faces (vertex (x, y, z) is
/// x + 3 y + 6 z), pulled along x on the right, on rollers left, bottom and front.
#[test]
fn the_patch_test_on_polyhedra_given_inline_is_exact() {
    let v = |x: usize, y: usize, z: usize| x + 3 * y + 6 * z;
    let cube = |x: usize| {
        let w = |dx, dy, dz| v(x + dx, dy, dz);
        vec![
            vec![w(0, 0, 0), w(0, 0, 1), w(0, 1, 1), w(0, 1, 0)],
            vec![w(1, 0, 0), w(1, 1, 0), w(1, 1, 1), w(1, 0, 1)],
            vec![w(0, 0, 0), w(1, 0, 0), w(1, 0, 1), w(0, 0, 1)],
            vec![w(0, 1, 0), w(0, 1, 1), w(1, 1, 1), w(1, 1, 0)],
            vec![w(0, 0, 0), w(0, 1, 0), w(1, 1, 0), w(1, 0, 0)],
            vec![w(0, 0, 1), w(1, 0, 1), w(1, 1, 1), w(0, 1, 1)],
        ]
    };
    let mut vertices = Vec::new();
    for z in 0..2 {
        for y in 0..2 {
            for x in 0..3 {
                vertices.push(format!("[{x}, {y}, {z}]"));
            }
        }
    }
    let faces = |c: &[Vec<Vec<usize>>], k: usize| {
        format!("{:?}", c.iter().map(|f| &f[k]).collect::<Vec<_>>())
    };
    let cubes = [cube(0), cube(1)];
    let text = format!(
        r#"
[[body]]
name = "bar"
material = {{ E = 10.0, nu = 0.25 }}
dirichlet = [{{ part = "left", x = 0.0 }}, {{ part = "bottom", z = 0.0 }}, {{ part = "front", y = 0.0 }}]
traction = [{{ part = "right", value = [3.0, 0.0, 0.0] }}]

[body.mesh]
vertices = [{}]
polyhedra = {:?}
part_faces = {{ left = [{:?}], right = [{:?}], bottom = {}, front = {} }}
"#,
        vertices.join(", "),
        cubes,
        cubes[0][0],
        cubes[1][1],
        faces(&cubes, 4),
        faces(&cubes, 2),
    );
    let outcome = solve(&text).unwrap();
    let bar = outcome.body_3d("bar").unwrap();
    assert_eq!(bar.body.mesh().n_cells(), 2);
    let (ex, ey) = (3.0 / 10.0, -0.25 * 3.0 / 10.0);
    let u = bar.solution.displacement();
    for (k, p) in bar.body.mesh().vertices().iter().enumerate() {
        assert!((u[3 * k] - ex * p.x).abs() < 1e-12, "vertex {k}");
        assert!((u[3 * k + 1] - ey * p.y).abs() < 1e-12, "vertex {k}");
        assert!((u[3 * k + 2] - ey * p.z).abs() < 1e-12, "vertex {k}");
    }
    for field in &bar.fields {
        assert!((field.stress[(0, 0)] - 3.0).abs() < 1e-10);
        assert!(field.stress[(1, 1)].abs() < 1e-10 && field.stress[(2, 2)].abs() < 1e-10);
    }
    let left = bar.solution.reaction("left").unwrap();
    assert!((left.x + 3.0).abs() < 1e-10, "{left}");
}

#[test]
fn generated_meshes_given_back_inline_build_the_same_mesh() {
    use vem_scene::{body_mesh, inline_mesh, BuiltMesh, Scene};
    for (mesh, dimension) in [
        (
            r#"{ family = "voronoi", rectangle = [[0, 0], [2, 1]], n = 6, seed = 3, parts = [{ name = "strip", of = "top", box = [[0.5, 0], [1.5, 1]] }] }"#,
            2,
        ),
        (
            r#"{ family = "voronoi", box = [[0, 0, 0], [1, 1, 1]], n = 3, seed = 2 }"#,
            3,
        ),
    ] {
        let plane = if dimension == 2 {
            ", plane = \"strain\""
        } else {
            ""
        };
        let text = format!(
            "[[body]]\nname = \"a\"\nmesh = {mesh}\nmaterial = {{ E = 1.0, nu = 0.3{plane} }}\n"
        );
        let (scene, _): (Scene, _) = parse(&text).unwrap();
        let (built, source) = body_mesh(&scene, 0, std::path::Path::new("")).unwrap();
        assert!(source.starts_with("voronoi"), "{source}");
        assert_eq!(built.dimension(), dimension);
        let again = inline_mesh(&built.to_inline(), "a", &KeyPath::key("mesh")).unwrap();
        match (&built, &again) {
            (BuiltMesh::Plane(a), BuiltMesh::Plane(b)) => {
                // The same vertices, polygons and edges; the parts the same (in name order).
                assert_eq!(a.vertices(), b.vertices());
                assert!(a.polygons().eq(b.polygons()));
                assert_eq!(a.edges(), b.edges());
                let mut parts = a.parts().to_vec();
                parts.sort_by(|p, q| p.name.cmp(&q.name));
                assert_eq!(parts, b.parts());
                assert!(a.part("strip").is_ok());
            }
            (BuiltMesh::Space(a), BuiltMesh::Space(b)) => {
                assert_eq!(a.vertices(), b.vertices());
                assert_eq!(a.n_cells(), b.n_cells());
                for c in 0..a.n_cells() {
                    assert_eq!(a.cell_face_loops(c), b.cell_face_loops(c), "cell {c}");
                    assert_eq!(a.volume(c), b.volume(c));
                }
                // The same parts (the description lists them in name order).
                let mut names = a.part_names();
                names.sort();
                assert_eq!(names, b.part_names());
                for name in a.part_names() {
                    assert_eq!(
                        a.part_vertices(&name).unwrap(),
                        b.part_vertices(&name).unwrap()
                    );
                }
            }
            _ => panic!("the dimension changed"),
        }
    }
}
