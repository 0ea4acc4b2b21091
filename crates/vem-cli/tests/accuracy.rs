//! The scene keys `accuracy` and `target_error`: a generated mesh without `n` takes the size
//! the error model chooses, the contact solver the preset's setting, the summary reports the
//! predicted error; misuse is a located error.

use std::path::Path;

use vem_cli::{CliError, Model, Scene};
use vem_contact::{AccuracyPreset, ErrorModel};

fn build(text: &str) -> Result<Model, CliError> {
    Scene::parse("accuracy.toml", text).and_then(|scene| Model::build(&scene))
}

const BLOCKS: &str = r#"
[[body]]
name = "upper"
mesh = { family = "quads", rectangle = [[0, 0], [1, 1]] }
material = { E = 100.0, nu = 0.3, plane = "strain" }
[[body.dirichlet]]
part = "top"
y = -0.02
[[body]]
name = "lower"
mesh = { family = "quads", rectangle = [[0, -1], [1, 0]], n = 8 }
material = { E = 100.0, nu = 0.3, plane = "strain" }
[[body.dirichlet]]
part = "bottom"
x = 0.0
y = 0.0
[[contact]]
body = "upper"
part = "bottom"
other_body = "lower"
other_part = "top"
"#;

/// The shipped scene: n = 29 for the draft preset's 10 %, the draft solver setting, and the
/// uniform pressure E/(1 - nu^2) * 0.01 of the two blocks shortened by 0.02 over 2.
#[test]
fn the_accuracy_scene_chooses_the_size_and_the_solver() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/accuracy.toml");
    let dir = std::env::temp_dir().join(format!("vem-cli-accuracy-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let (outcome, _) = vem_cli::run(&path, Some(&dir)).unwrap();
    let summary = outcome.summary();
    let n = ErrorModel::LOWEST_ORDER_VEM
        .try_size_for(AccuracyPreset::Draft.target_error())
        .unwrap();
    assert_eq!(n, 29);
    for body in &summary.bodies {
        assert!(body.mesh.contains("n = 29"), "{}", body.mesh);
        let predicted = body.predicted_error.unwrap();
        assert!((predicted - 2.9 / 29.0).abs() < 1e-12);
        assert!(predicted <= AccuracyPreset::Draft.target_error());
    }
    let pressure = 100.0 / (1.0 - 0.3 * 0.3) * 0.01;
    let contact = outcome.contact.as_ref().unwrap();
    assert!((contact.normal_resultant() - pressure).abs() < 1e-6 * pressure);
    for node in &contact.nodes {
        assert!((node.pressure / pressure - 1.0).abs() < 1e-3, "{node:?}");
    }
}

#[test]
fn a_target_error_sizes_the_meshes_without_n_and_picks_the_solver() {
    let model = build(&format!("target_error = 0.2\n{BLOCKS}")).unwrap();
    let upper = &model.bodies()[0];
    let n = ErrorModel::LOWEST_ORDER_VEM.try_size_for(0.2).unwrap();
    assert_eq!(n, 15);
    assert!(
        upper.mesh_source.contains("n = 15"),
        "{}",
        upper.mesh_source
    );
    assert!(upper.predicted_error.is_some_and(|e| e <= 0.2));
    // The lower mesh gives n = 8: its predicted error is C / 8.
    let lower = &model.bodies()[1];
    let expected = ErrorModel::LOWEST_ORDER_VEM.predicted_error(8);
    assert!(lower
        .predicted_error
        .is_some_and(|e| (e - expected).abs() < 1e-12));
    let solver = model.problem().solver();
    assert_eq!(solver.name, AccuracyPreset::Draft.solver());
    assert_eq!(solver.options, AccuracyPreset::Draft.solver_options());
}

#[test]
fn misuse_of_the_accuracy_keys_is_located() {
    let message = |text: &str| build(text).expect_err("an error").to_string();
    let unknown = message(&format!("accuracy = \"fast\"\n{BLOCKS}"));
    assert!(unknown.contains("draft, balanced, reference"), "{unknown}");
    let both = message(&format!(
        "accuracy = \"draft\"\n{BLOCKS}solver = \"penalty\"\n"
    ));
    assert!(
        both.contains("`solver`") && both.contains("accuracy"),
        "{both}"
    );
    let missing = message(BLOCKS);
    assert!(
        missing.contains("`n`") && missing.contains("target_error"),
        "{missing}"
    );
    let unused = message(&format!(
        "target_error = 0.1\n{}",
        BLOCKS.replace("[[0, 0], [1, 1]] }", "[[0, 0], [1, 1]], n = 4 }")
    ));
    assert!(unused.contains("target_error"), "{unused}");
    let negative = message(&format!("target_error = -0.1\n{BLOCKS}"));
    assert!(negative.contains("target_error"), "{negative}");
}
