//! A solver of one's own, registered in a `SolverRegistry`, runs scenes like the built-in ones;
//! an unknown solver name is a located error that lists the names.

use vem_cli::{Model, Registries, Scene};
use vem_contact::{ContactSolver, PenaltySettings, PenaltySolver, SolverRegistry};
use vem_space::Options;

/// A Voronoi block pressed by a uniform pressure p = 0.01 on the rigid line y = 0: the contact
/// pressure is p at every node and the resultant p times the width 2.
fn block(solver: &str) -> String {
    format!(
        r#"
[[body]]
name = "block"
mesh = {{ family = "voronoi", rectangle = [[0, 0], [2, 1]], n = 5, seed = 2 }}
material = {{ E = 100.0, nu = 0.3, plane = "strain" }}
dirichlet = [{{ part = "left", x = 0.0 }}]
traction = [{{ part = "top", pressure = 0.01 }}]

[[contact]]
body = "block"
part = "bottom"
obstacle = {{ line = {{ point = [0, 0], normal = [0, 1] }} }}
solver = "{solver}"
tolerance = 1e-12
"#
    )
}

#[test]
fn a_registered_solver_runs_a_scene() {
    let mut registry = SolverRegistry::builtin();
    // "stiff-penalty": the penalty solver with a large penalty factor, taking the scene's
    // tolerance.
    registry
        .register(
            "stiff-penalty",
            "penalty with factor 1e8",
            |options: &Options| {
                // Its one setting: the tolerance; any other key is refused with its path.
                #[derive(serde::Deserialize)]
                #[serde(deny_unknown_fields)]
                struct Settings {
                    tolerance: Option<f64>,
                }
                let settings: Settings = options.parse()?;
                let mut b = PenaltySettings::builder()
                    .penalty(vem_contact::PenaltyParameter::RelativeToStiffness(1e8));
                if let Some(t) = settings.tolerance {
                    b = b.tolerance(t);
                }
                Ok(Box::new(PenaltySolver::new(b.build()?)) as Box<dyn ContactSolver>)
            },
        )
        .unwrap();
    let scene = Scene::parse("block.toml", block("stiff-penalty")).unwrap();
    let outcome = Model::build_with(
        &scene,
        &Registries {
            solvers: registry,
            ..Registries::default()
        },
    )
    .unwrap()
    .solve()
    .unwrap();
    let contact = outcome.contact.as_ref().unwrap();
    for node in &contact.nodes {
        // The penalty solution penetrates by p / (penalty): relative error about 1e-6.
        assert!(
            (node.pressure / 0.01 - 1.0).abs() < 1e-5,
            "{}",
            node.pressure
        );
    }
    assert!((contact.normal_resultant() / 0.02 - 1.0).abs() < 1e-8);
    // The built-in registry does not know the name: the error is at the `solver` key and
    // lists the known names.
    let error = Model::build(&scene).unwrap_err();
    let at = error.location().expect("located");
    assert_eq!(at.text, "solver = \"stiff-penalty\"", "{error}");
    let shown = error.to_string();
    assert!(shown.contains("'stiff-penalty'"), "{shown}");
    assert!(shown.contains("exact, penalty, active-set"), "{shown}");
}
