//! An element of one's own with settings, registered with
//! `ElementRegistry::register_with_options` and chosen by a scene:
//! `element = { name = "vem1-weighted", stabilisation = "drecipe", weight = 4 }`.
//!
//! `vem1-weighted` is the lowest-order VEM whose stabilisation, any of the registry's
//! stabilisations named by the same `stabilisation` setting as the built-in `vem1`, is
//! multiplied by `weight`: the knob of a study of how much an answer depends on the
//! stabilisation (`K_T = K_c + weight (I - D Pi)^T S (I - D Pi)`). Checks:
//!
//! 1. a misspelt setting (`wieght`), a weight out of range and an unknown stabilisation are
//!    refused at their keys (`body[0].element.wieght`, `body[0].element.weight`,
//!    `body[0].element.stabilisation`);
//! 2. with `weight = 1` the answer is the built-in `vem1` with the same stabilisation:
//!    displacements agree to `1e-12` relative;
//! 3. the patch test holds whatever the weight (`0.01` and `100`): a linear displacement
//!    prescribed on the boundary of a Voronoi mesh is reproduced at every vertex to `1e-10`
//!    (the stabilisation vanishes on linear fields: consistency does not depend on it);
//! 4. the weight matters elsewhere: a block clamped on top, pressed on a rigid line
//!    (frictionless), for weights 0.25, 1 and 4. Without loads the discrete energy is the
//!    minimum of `1/2 a_h(v, v)` over the admissible displacements, and `a_h` grows with the
//!    weight, so the strain energy must grow with it; and each answer satisfies Clapeyron's
//!    theorem, `2 U = 0.02 R` (the work of the top's reaction `R`, equal to the contact
//!    resultant, over the prescribed 0.02; the contact forces do no work), to `1e-10`.
//!
//! Exits non-zero on failure. Run with
//! `cargo run --release -p vem-scene --example element_options`; `cargo test -p vem-scene`
//! runs the same checks (the example is a test target too: `test = true` in the crate's
//! Cargo.toml).

use std::process::ExitCode;
use std::sync::Arc;

use nalgebra::{DMatrix, DVector};
use serde::Deserialize;
use vem_scene::toml_file::{self, SpanIndex};
use vem_scene::{BuildOptions, Model, Outcome, Registries, SceneError};
use vem_space::{
    Choice, DofiDofi, ElasticityTensor, ElementRegistry, ElementSpace, LowestOrderVem, Options,
    OptionsError, PolygonGeometry, RegistryError, SpaceError, Stabilisation, StabilisationRegistry,
};

type Error = Box<dyn std::error::Error>;

/// A stabilisation multiplied by a weight.
#[derive(Debug)]
struct Weighted {
    inner: Arc<dyn Stabilisation>,
    weight: f64,
}

impl Stabilisation for Weighted {
    fn name(&self) -> String {
        format!("{}-weighted", self.inner.name())
    }

    fn description(&self) -> String {
        format!("{} times {}", self.inner.description(), self.weight)
    }

    fn diagonal(
        &self,
        geometry: &PolygonGeometry,
        material: &ElasticityTensor,
        consistency: &DMatrix<f64>,
    ) -> Result<DVector<f64>, SpaceError> {
        Ok(self.inner.diagonal(geometry, material, consistency)? * self.weight)
    }
}

/// The settings of `vem1-weighted`; any other key is refused with its path.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Settings {
    /// A stabilisation of the registry, as `vem1` names it (default dofi-dofi).
    #[serde(default)]
    stabilisation: Option<Choice>,
    /// The factor of the stabilisation, finite and `> 0`.
    weight: f64,
}

/// Registers `vem1-weighted` in `elements`.
fn register(elements: &mut ElementRegistry) -> Result<(), RegistryError> {
    elements.register_with_options(
        "vem1-weighted",
        "lowest-order VEM with its stabilisation times `weight`",
        |options: &Options, stabilisations: &StabilisationRegistry| {
            let s: Settings = options.parse()?;
            if !(s.weight.is_finite() && s.weight > 0.0) {
                let message = format!("must be finite and > 0, found {}", s.weight);
                return Err(OptionsError::at("weight", message));
            }
            let inner = match s.stabilisation {
                None => Arc::new(DofiDofi::default()) as Arc<dyn Stabilisation>,
                // An error of the stabilisation's own settings is at their path inside it.
                Some(choice) => stabilisations.make_choice(&choice).map_err(|e| {
                    let path = match e.option_path() {
                        Some("") | None => "stabilisation".to_string(),
                        Some(p) => format!("stabilisation.{p}"),
                    };
                    OptionsError::at(path, e.to_string())
                })?,
            };
            let weighted = Weighted {
                inner,
                weight: s.weight,
            };
            let element = LowestOrderVem::try_new(Arc::new(weighted))
                .map_err(|e| OptionsError::at("", e.to_string()))?;
            Ok(Arc::new(element) as Arc<dyn ElementSpace>)
        },
    )?;
    Ok(())
}

/// A block `[0, 2] x [0, 1]` (Voronoi, n = 8) with the element `element`, its top clamped and
/// moved down by 0.02, on the rigid line `y = 0` (frictionless): the top cannot widen, the
/// bottom can, so the field is not linear and the stabilisation matters.
fn pressed_block(element: &str) -> String {
    format!(
        r#"[[body]]
name = "block"
mesh = {{ family = "voronoi", rectangle = [[0, 0], [2, 1]], n = 8, seed = 3 }}
material = {{ E = 100.0, nu = 0.3, plane = "strain" }}
element = {element}
dirichlet = [{{ part = "top", x = 0.0, y = -0.02 }}]

[[contact]]
body = "block"
part = "bottom"
obstacle = {{ line = {{ point = [0, 0], normal = [0, 1] }} }}
"#
    )
}

/// The linear field of the patch test.
const U_X: &str = "0.01 + 0.02 * x - 0.03 * y";
const U_Y: &str = "-0.02 + 0.01 * x + 0.04 * y";

fn linear_field(x: f64, y: f64) -> [f64; 2] {
    [0.01 + 0.02 * x - 0.03 * y, -0.02 + 0.01 * x + 0.04 * y]
}

/// A Voronoi square with the element `element`, the linear field prescribed on its boundary.
fn patch(element: &str) -> String {
    let condition = |part: &str| format!(r#"{{ part = "{part}", x = "{U_X}", y = "{U_Y}" }}"#);
    format!(
        r#"[[body]]
name = "patch"
mesh = {{ family = "voronoi", rectangle = [[0, 0], [1, 1]], n = 10, seed = 7 }}
material = {{ E = 100.0, nu = 0.3, plane = "strain" }}
element = {element}
dirichlet = [{}, {}, {}, {}]
"#,
        condition("left"),
        condition("right"),
        condition("bottom"),
        condition("top")
    )
}

/// The scene `text` built with `registries` and solved, or the error at its line.
fn run(text: &str, registries: &Registries) -> Result<Result<Outcome, String>, Error> {
    let (scene, spans) = toml_file::parse(text).map_err(|e| e.message)?;
    let options = BuildOptions {
        registries: registries.clone(),
        ..BuildOptions::default()
    };
    match Model::build(&scene, &options).and_then(|model| model.solve()) {
        Ok(outcome) => Ok(Ok(outcome)),
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

/// Runs every check, printing each; the failures.
fn checks() -> Result<Vec<String>, Error> {
    let mut registries = Registries::default();
    register(&mut registries.elements)?;
    println!("elements: {}", registries.elements.names().join(", "));
    let mut failures: Vec<String> = Vec::new();
    let mut check = |ok: bool, what: String| {
        println!("{} {what}", if ok { "ok  " } else { "FAIL" });
        if !ok {
            failures.push(what);
        }
    };

    // 1. Refused settings, at their keys.
    for (element, key) in [
        (
            r#"{ name = "vem1-weighted", wieght = 2 }"#,
            "body[0].element.wieght",
        ),
        (
            r#"{ name = "vem1-weighted", weight = -1 }"#,
            "body[0].element.weight",
        ),
        (
            r#"{ name = "vem1-weighted", stabilisation = "dofi", weight = 2 }"#,
            "body[0].element.stabilisation",
        ),
    ] {
        match run(&pressed_block(element), &registries)? {
            Ok(_) => check(false, format!("accepted a scene with an error at {key}")),
            Err(error) => check(error.contains(&format!(": {key}: ")), error),
        }
    }

    // 2. Weight 1: the built-in element with the same stabilisation.
    let builtin = r#"{ name = "vem1", stabilisation = "drecipe" }"#;
    let ours = r#"{ name = "vem1-weighted", stabilisation = "drecipe", weight = 1 }"#;
    let a = run(&pressed_block(builtin), &registries)??;
    let b = run(&pressed_block(ours), &registries)??;
    let (ua, ub) = (
        a.bodies[0].solution.displacement(),
        b.bodies[0].solution.displacement(),
    );
    let scale = ua.iter().fold(0.0f64, |m, u| m.max(u.abs()));
    let d = ua
        .iter()
        .zip(ub)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
        / scale;
    check(
        d <= 1e-12,
        format!(
            "weight 1 ({}): vem1 with the D-recipe to {d:.1e}",
            b.summary.bodies[0].element
        ),
    );

    // 3. The patch test at any weight.
    for weight in [0.01, 100.0] {
        let element = format!(r#"{{ name = "vem1-weighted", weight = {weight} }}"#);
        let outcome = run(&patch(&element), &registries)??;
        let body = &outcome.bodies[0];
        let worst = body
            .body
            .mesh()
            .vertices()
            .iter()
            .zip(body.solution.vertex_displacements())
            .map(|(p, u)| {
                let exact = linear_field(p.x, p.y);
                (u.x - exact[0]).abs().max((u.y - exact[1]).abs())
            })
            .fold(0.0f64, f64::max);
        check(
            worst <= 1e-10,
            format!("weight {weight}: the patch test to {worst:.1e} at every vertex"),
        );
    }

    // 4. The weight elsewhere: the strain energy under the same prescribed displacement, and
    // Clapeyron's theorem.
    let mut energies = Vec::new();
    for weight in [0.25, 1.0, 4.0] {
        let element = format!(r#"{{ name = "vem1-weighted", weight = {weight} }}"#);
        let outcome = run(&pressed_block(&element), &registries)??;
        let energy = outcome.bodies[0].solution.strain_energy();
        let resultant = outcome
            .contact
            .as_ref()
            .map_or(0.0, |c| c.normal_resultant());
        let clapeyron = (2.0 * energy - 0.02 * resultant).abs() / (2.0 * energy);
        check(
            clapeyron <= 1e-10,
            format!(
                "weight {weight}: strain energy {energy:.6e}, contact resultant \
                 {resultant:.6e}, 2 U = 0.02 R to {clapeyron:.1e}"
            ),
        );
        energies.push(energy);
    }
    check(
        energies.windows(2).all(|w| w[1] > w[0]),
        format!(
            "the strain energy grows with the weight: {}",
            energies
                .iter()
                .map(|e| format!("{e:.6e}"))
                .collect::<Vec<_>>()
                .join(" < ")
        ),
    );
    Ok(failures)
}

fn main() -> Result<ExitCode, Error> {
    let failures = checks()?;
    if failures.is_empty() {
        println!("element 'vem1-weighted': pass");
        Ok(ExitCode::SUCCESS)
    } else {
        eprintln!(
            "element 'vem1-weighted' FAILS:\n- {}",
            failures.join("\n- ")
        );
        Ok(ExitCode::FAILURE)
    }
}

/// `cargo test` runs the checks too.
#[test]
fn the_checks_pass() {
    let failures = checks().expect("the scenes solve");
    assert!(failures.is_empty(), "{failures:#?}");
}
