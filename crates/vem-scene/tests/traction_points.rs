//! A body's `traction_points`: the Gauss–Legendre points per edge (per face direction in space)
//! of its tractions reach the elastic body, 2 by default; 0 and counts beyond the tabulated
//! rules are refused at the key.

use vem_scene::toml_file::parse;
use vem_scene::{BuildOptions, Model, SceneError};
use vem_space::quadrature::GaussLegendre;

fn build(text: &str) -> Result<Model, SceneError> {
    let (scene, _) = parse(text).map_err(|e| panic!("{}", e.message)).unwrap();
    Model::build(&scene, &BuildOptions::default())
}

/// A block in the plane (`space` false) or in space pulled on its right side, with
/// `points` (a line of TOML, possibly empty).
fn block(space: bool, points: &str) -> String {
    let (mesh, material, pull) = if space {
        (
            r#"{ family = "hexahedra", box = [[0, 0, 0], [1, 1, 1]], n = 2 }"#,
            "{ E = 1.0, nu = 0.3 }",
            r#"["0.1 * sin(y)", 0, 0]"#,
        )
    } else {
        (
            r#"{ family = "quads", rectangle = [[0, 0], [1, 1]], n = 2 }"#,
            r#"{ E = 1.0, nu = 0.3, plane = "strain" }"#,
            r#"["0.1 * sin(y)", 0]"#,
        )
    };
    format!(
        r#"
[[body]]
name = "block"
mesh = {mesh}
material = {material}
{points}
dirichlet = [{{ part = "left", x = 0, y = 0{z} }}]
traction = [{{ part = "right", value = {pull} }}]
"#,
        z = if space { ", z = 0" } else { "" }
    )
}

fn points_of(model: &Model) -> usize {
    match model.dimension() {
        2 => model.bodies()[0].body.traction_points(),
        _ => model.bodies_3d()[0].body.traction_points(),
    }
}

#[test]
fn the_points_reach_the_body_in_the_plane_and_in_space() {
    for space in [false, true] {
        let default = build(&block(space, "")).unwrap();
        assert_eq!(points_of(&default), 2);
        let four = build(&block(space, "traction_points = 4")).unwrap();
        assert_eq!(points_of(&four), 4);
        assert_eq!(four.scene().bodies[0].traction_points, Some(4));
    }
}

#[test]
fn zero_or_too_many_points_are_refused_at_the_key() {
    for space in [false, true] {
        for points in [0, GaussLegendre::MAX_POINTS + 1, 1000] {
            let error = build(&block(space, &format!("traction_points = {points}"))).unwrap_err();
            assert_eq!(error.path.to_string(), "body[0].traction_points");
            assert!(
                error.message.contains(&format!(
                    "traction_points = {points}: give from 1 to {}",
                    GaussLegendre::MAX_POINTS
                )),
                "{}",
                error.message
            );
        }
    }
}
