//! The rows in space (`D = 3`):
//!
//! - the locking measure on the divergence-free solution E2-3D (errors at a Poisson ratio close
//!   to 1/2 against those at 0.3) for every element on polyhedra and three families;
//! - the contact patch test of two stacked blocks on non-matching surfaces (hexahedra on
//!   tetrahedra: the surface overlay makes them node-to-node) at the extremes - stiffness
//!   contrast, units, nu = 0.49999, thin and distorted cells - where the exact answer is the
//!   uniform uniaxial stress `sigma_zz = -p`, `p = d / (h_1 / E_1 + h_2 / E_2)`, transmitted node
//!   by node, whatever the scales.

use std::sync::Arc;

use super::{chain, judge, locking_row, patch_tolerance, solve, space_solvers, Outcome, Row, Size};
use crate::exact::Lame;
use crate::three_d::{solve_solid, DivergenceFreeSolid, SOLID_SEED};
use vem_contact::{ContactProblem, ContactResult};
use vem_mesh::generators::polyhedral::{
    hexahedra, perturbed_hexahedra, tetrahedra, voronoi_polyhedra, Cuboid, PolyhedralFamily,
};
use vem_mesh::{Point3, PolyhedralMesh, Vector3};
use vem_scene::description::{
    BodyDescription, ContactDescription, DirichletDescription, MaterialDescription,
    TractionDescription,
};
use vem_scene::{BuildOptions, BuiltMesh, Model, ScalarValue, Scene, VectorValue};
use vem_space::{Choice, ElementRegistry, Options, PolyhedralElement};

/// Poisson's ratios of the locking rows in space, each against nu = 0.3.
pub const SOLID_POISSON_RATIOS: [f64; 3] = [0.49, 0.4999, 0.49999];

/// The families of the locking rows in space.
const LOCKING_FAMILIES: [PolyhedralFamily; 3] = [
    PolyhedralFamily::Hexahedra,
    PolyhedralFamily::Voronoi,
    PolyhedralFamily::Tetrahedra,
];

/// Locking in space: E2-3D for every element on polyhedra on hexahedra, Voronoi cells and
/// tetrahedra, and `vem1-bbar` on tetrahedra with every edge's midpoint inserted (the choice of
/// a scene there): the errors at each nu of [`SOLID_POISSON_RATIOS`] against nu = 0.3 (one
/// Cholesky solve each).
pub fn solid_poisson(size: &Size) -> Vec<Row> {
    let registry = ElementRegistry::builtin();
    let mut rows = Vec::new();
    for name in registry.polyhedral_names() {
        let element = registry
            .make_polyhedral_choice(&Choice::named(name))
            .expect("a registered element");
        for family in LOCKING_FAMILIES {
            if let Some(row) = solid_locking(name, &element, family, size.solid, false) {
                rows.push(row);
            }
        }
    }
    // What a scene chooses on tetrahedra close to incompressibility.
    let bbar = registry
        .make_polyhedral_choice(&Choice::named("vem1-bbar"))
        .expect("a registered element");
    rows.extend(solid_locking(
        "vem1-bbar with edge midpoints",
        &bbar,
        PolyhedralFamily::Tetrahedra,
        size.solid,
        true,
    ));
    rows
}

fn solid_locking(
    name: &str,
    element: &Arc<dyn PolyhedralElement>,
    family: PolyhedralFamily,
    n: usize,
    midpoints: bool,
) -> Option<Row> {
    let errors = |nu: f64| -> Result<(f64, f64), String> {
        let lame = Lame::try_new(2.0 * nu / (1.0 - 2.0 * nu), 1.0).map_err(|e| chain(&e))?;
        let mut mesh = family
            .generate(&Cuboid::unit_cube(), n, SOLID_SEED)
            .map_err(|e| chain(&e))?;
        if midpoints {
            mesh = mesh.with_edge_midpoints().map_err(|e| chain(&e))?;
        }
        let (_, _, errors) = solve_solid(
            Arc::new(DivergenceFreeSolid::new(lame)),
            mesh,
            Arc::clone(element),
        )
        .map_err(|e| chain(&e))?;
        Ok((errors.relative_grad(), errors.relative_l2()))
    };
    let last = SOLID_POISSON_RATIOS[SOLID_POISSON_RATIOS.len() - 1];
    let row_name = format!(
        "{name}: E2-3D on {} (n = {n}), nu = 0.3 .. {last}",
        family.name()
    );
    locking_row(
        row_name,
        "cholesky".to_string(),
        &SOLID_POISSON_RATIOS,
        errors,
    )
}

/// The cells of a stacked-blocks patch test.
#[derive(Debug, Clone, Copy, PartialEq)]
enum StackCells {
    /// Hexahedra on top of Kuhn tetrahedra (non-matching: the overlay inserts nodes).
    HexahedraOnTetrahedra,
    /// Perturbed hexahedra (warped faces) on top of Voronoi cells.
    PerturbedOnVoronoi,
}

/// Two blocks `[0, s]^2 x [0, s h_1]` (upper) and `[0, s]^2 x [-s h_2, 0]` (lower), rollers on
/// the sides x = 0 and y = 0, the lower's bottom held in z and the upper's top moved down by
/// `s d`: the uniform uniaxial stress `sigma_zz = -p` with `p = d / (h_1 / E_1 + h_2 / E_2)`.
#[derive(Debug, Clone)]
struct Stack {
    cells: StackCells,
    /// Heights (before the length scale).
    heights: [f64; 2],
    /// Young's moduli (before the modulus scale), upper and lower.
    young: [f64; 2],
    poisson: f64,
    /// The element's registry name.
    element: &'static str,
    /// Lengths are multiplied by this.
    length: f64,
    /// Moduli are multiplied by this.
    modulus: f64,
}

/// The indentation (before the length scale).
const INDENTATION: f64 = 0.01;

impl Stack {
    fn new(cells: StackCells) -> Self {
        Self {
            cells,
            heights: [1.0, 0.5],
            young: [100.0, 300.0],
            poisson: 0.3,
            element: "vem1",
            length: 1.0,
            modulus: 1.0,
        }
    }

    /// The transmitted pressure, in the scaled units.
    fn pressure(&self) -> f64 {
        let [h1, h2] = self.heights;
        let [e1, e2] = self.young.map(|e| e * self.modulus);
        INDENTATION / (h1 / e1 + h2 / e2)
    }

    fn meshes(&self, n: usize) -> Result<[PolyhedralMesh; 2], String> {
        let s = self.length;
        let [h1, h2] = self.heights;
        let upper = Cuboid::new(Point3::new(0.0, 0.0, 0.0), Point3::new(s, s, s * h1));
        let lower = Cuboid::new(Point3::new(0.0, 0.0, -s * h2), Point3::new(s, s, 0.0));
        // Cells across z: about as many as the height allows, at least one.
        let across = |h: f64, m: usize| ((h * m as f64).round() as usize).max(1);
        let meshes = match self.cells {
            StackCells::HexahedraOnTetrahedra => [
                hexahedra(&upper, n, n, across(h1, n)),
                tetrahedra(&lower, n - 1, n - 1, across(h2, n - 1)),
            ],
            StackCells::PerturbedOnVoronoi => [
                perturbed_hexahedra(&upper, n, 0.25, 1),
                voronoi_polyhedra(&lower, n - 1, 2),
            ],
        };
        let [a, b] = meshes;
        Ok([a.map_err(|e| chain(&e))?, b.map_err(|e| chain(&e))?])
    }

    /// The two blocks as bodies of a scene, "upper" and "lower": the meshes inline, the
    /// material (`E`, `nu`) and the element by its registry name; no conditions.
    fn bodies(&self, n: usize) -> Result<[BodyDescription; 2], String> {
        let [upper, lower] = self.meshes(n)?;
        let body = |name: &str, mesh: PolyhedralMesh, young: f64| BodyDescription {
            name: name.to_string(),
            mesh: BuiltMesh::Space(mesh).to_inline(),
            material: MaterialDescription {
                young: Some(young * self.modulus),
                nu: Some(self.poisson),
                ..MaterialDescription::default()
            },
            element: Some(Choice::named(self.element)),
            ..BodyDescription::default()
        };
        Ok([
            body("upper", upper, self.young[0]),
            body("lower", lower, self.young[1]),
        ])
    }

    /// The scene: rollers on the sides x = 0 and y = 0, the upper's top moved down by `s d`,
    /// the lower's bottom held in z, frictionless contact.
    fn problem(&self, n: usize) -> Result<ContactProblem<3>, String> {
        let [mut upper, mut lower] = self.bodies(n)?;
        let held = |part: &str, k: usize, value: f64| {
            let mut d = DirichletDescription {
                part: part.to_string(),
                ..DirichletDescription::default()
            };
            *[&mut d.x, &mut d.y, &mut d.z][k] = Some(ScalarValue::Constant(value));
            d
        };
        let d = INDENTATION * self.length;
        upper.dirichlet = vec![
            held("top", 2, -d),
            held("left", 0, 0.0),
            held("front", 1, 0.0),
        ];
        lower.dirichlet = vec![
            held("bottom", 2, 0.0),
            held("left", 0, 0.0),
            held("front", 1, 0.0),
        ];
        stack_problem([upper, lower], Choice::named("frictionless"))
    }

    /// The largest nodal displacement error relative to the indentation, and the resultant's
    /// error relative to the exact one.
    fn errors(&self, result: &ContactResult<3>) -> (f64, f64) {
        let p = self.pressure();
        let (s, nu) = (self.length, self.poisson);
        let [_, h2] = self.heights;
        let [e1, e2] = self.young.map(|e| e * self.modulus);
        let mut largest: f64 = 0.0;
        for (k, body) in result.bodies.iter().enumerate() {
            let strain = -p / if k == 0 { e1 } else { e2 };
            for (v, x) in body.body.mesh().vertices().iter().enumerate() {
                let uz = if k == 0 {
                    -p * s * h2 / e2 + strain * x.z
                } else {
                    strain * (x.z + s * h2)
                };
                let exact = Vector3::new(-nu * strain * x.x, -nu * strain * x.y, uz);
                let u = body.solution.vertex_displacement(v);
                largest = largest.max((u - exact).norm());
            }
        }
        let resultant = p * s * s;
        (
            largest / (INDENTATION * s),
            (result.normal_resultant() - resultant).abs() / resultant,
        )
    }

    fn judge(&self, n: usize, solver: &str) -> Outcome {
        let tolerance = patch_tolerance(solver);
        let outcome = self
            .problem(n)
            .and_then(|problem| solve(&problem, solver, &Options::new()));
        judge(solver, outcome, |r| {
            let (u, f) = self.errors(r);
            (
                format!("max nodal error {u:.1e}, resultant error {f:.1e}"),
                u <= tolerance && f <= tolerance,
            )
        })
    }
}

/// The contact problem of the scene of the two blocks `bodies` ("upper" over "lower"), the
/// upper's bottom against the lower's top with the law `law` (a registry name with its
/// settings).
fn stack_problem(bodies: [BodyDescription; 2], law: Choice) -> Result<ContactProblem<3>, String> {
    let scene = Scene {
        bodies: bodies.into(),
        contacts: vec![ContactDescription {
            body: "upper".to_string(),
            part: "bottom".to_string(),
            other_body: Some("lower".to_string()),
            other_part: Some("top".to_string()),
            law: Some(law),
            ..ContactDescription::default()
        }],
        ..Scene::default()
    };
    let model = Model::build(&scene, &BuildOptions::default()).map_err(|e| chain(&e))?;
    let (problem, _) = model.contact_problem_3d().ok_or("no contact pair")?;
    Ok(problem.clone())
}

fn stack_row(name: String, stack: &Stack, size: &Size) -> Row {
    Row {
        name,
        expected: format!(
            "exact uniaxial field: nodal error / d and resultant error <= {:.0e} (penalty: <= \
             {:.0e} = 1/factor)",
            patch_tolerance(""),
            patch_tolerance("penalty")
        ),
        outcomes: space_solvers(size)
            .iter()
            .map(|s| stack.judge(size.solid_patch, s))
            .collect(),
    }
}

/// The contact patch test in space at the extremes, by every solver (and the condensed
/// solver's iterative interface, [`super::ITERATIVE_INTERFACE`]): stiffness contrast
/// 1e+-8, lengths 1e+-6 and moduli 1e-9, nu = 0.49999, thin blocks (flat cells of aspect
/// 1e-3 and 1e-6), distorted cells (warped hexahedra on Voronoi cells).
pub fn solid_contact(size: &Size) -> Vec<Row> {
    let mut rows = Vec::new();
    let base = Stack::new(StackCells::HexahedraOnTetrahedra);
    rows.push(stack_row(
        "hexahedra on tetrahedra (non-matching), E_1/E_2 = 1/3".into(),
        &base,
        size,
    ));
    for c in [1e8, 1e-8] {
        let stack = Stack {
            young: [100.0 * c, 100.0],
            ..base.clone()
        };
        rows.push(stack_row(format!("E_1/E_2 = {c:.0e}"), &stack, size));
    }
    for (length, modulus) in [(1e6, 1.0), (1e-6, 1.0), (1.0, 1e-9), (1e-6, 1e-9)] {
        let stack = Stack {
            length,
            modulus,
            ..base.clone()
        };
        rows.push(stack_row(
            format!("lengths x {length:.0e}, moduli x {modulus:.0e}"),
            &stack,
            size,
        ));
    }
    for element in ["vem1", "vem1-bbar"] {
        let stack = Stack {
            poisson: 0.49999,
            element,
            ..base.clone()
        };
        rows.push(stack_row(format!("{element}, nu = 0.49999"), &stack, size));
    }
    for h in [1e-3, 1e-6] {
        let stack = Stack {
            heights: [1.0, h],
            ..base.clone()
        };
        rows.push(stack_row(
            format!("a lower block {h:.0e} thin (flat tetrahedra)"),
            &stack,
            size,
        ));
    }
    rows.push(stack_row(
        "perturbed hexahedra (distortion 0.25, warped faces) on Voronoi cells".into(),
        &Stack::new(StackCells::PerturbedOnVoronoi),
        size,
    ));
    rows
}

// ---------------------------------------------------------------------------------------------
// Friction in space

/// The friction law of a row of [`solid_friction`].
#[derive(Debug, Clone, Copy, PartialEq)]
enum FrictionLaw {
    /// Tresca with the bound `g_F = factor * tau_stick` (a stress).
    Tresca(f64),
    /// Coulomb with the coefficient `F = factor * tau_stick / p`.
    Coulomb(f64),
}

/// A bound huge against every traction of the problem (`1e8 P`).
const HUGE: f64 = 1e8;

/// Two blocks pressed and sheared with friction, the exact answer a uniform state: the upper
/// block `[0, s]^2 x [0, s h_1]` on the lower `[0, s]^2 x [-s h_2, 0]` (hexahedra on
/// tetrahedra, non-matching), `sigma_zz = -p` and `sigma_xz = tau` in both,
/// `p = d / (h_1/E_1 + h_2/E_2)`; the shear stress `tau` is the stick one
/// `tau_s = D / (h_1/G_1 + h_2/G_2)` when the bound allows it, else the bound (Tresca's `g_F`,
/// Coulomb's `F p`), and the upper block slips by `D - tau (h_1/G_1 + h_2/G_2)` (lengths times
/// `s`). The exact displacements are prescribed on the upper's top and the lower's bottom
/// (every component), the tractions `(0, 0, -+tau)` on the sides x = 0 and x = s. With lateral
/// contraction the two blocks contract alike only when `nu / E` is the same in both: the rows
/// with a stiffness contrast have `nu = 0`, the row at `nu = 0.49999` equal moduli.
#[derive(Debug, Clone)]
struct ShearedStack {
    stack: Stack,
    law: FrictionLaw,
}

/// The shift `D` of the upper block's top (before the length scale).
const SHIFT: f64 = 0.004;

impl ShearedStack {
    fn moduli(&self) -> [(f64, f64); 2] {
        let nu = self.stack.poisson;
        self.stack
            .young
            .map(|e| e * self.stack.modulus)
            .map(|e| (e, e / (2.0 * (1.0 + nu))))
    }

    /// `p`, `tau_s`, the bound's shear stress and the realised `tau`, the slip.
    fn state(&self) -> (f64, f64, f64, f64) {
        let s = self.stack.length;
        let [h1, h2] = self.stack.heights.map(|h| h * s);
        let [(_, g1), (_, g2)] = self.moduli();
        let p = self.stack.pressure();
        let compliance = h1 / g1 + h2 / g2;
        let stick = SHIFT * s / compliance;
        let bound = match self.law {
            FrictionLaw::Tresca(f) | FrictionLaw::Coulomb(f) => f * stick,
        };
        let tau = stick.min(bound);
        (p, stick, tau, SHIFT * s - tau * compliance)
    }

    /// The exact displacement of body `k` (0 upper, 1 lower) at `x`.
    fn exact(&self, k: usize, x: Point3) -> Vector3 {
        let s = self.stack.length;
        let h2 = self.stack.heights[1] * s;
        let nu = self.stack.poisson;
        let (p, _, tau, slip) = self.state();
        let [(e1, g1), (e2, g2)] = self.moduli();
        let lower_top = Vector3::new(tau / g2 * h2, 0.0, -p * h2 / e2);
        if k == 1 {
            let z = x.z + h2;
            Vector3::new(
                nu * p / e2 * x.x + tau / g2 * z,
                nu * p / e2 * x.y,
                -p / e2 * z,
            )
        } else {
            Vector3::new(
                nu * p / e1 * x.x + tau / g1 * x.z + lower_top.x + slip,
                nu * p / e1 * x.y,
                -p / e1 * x.z + lower_top.z,
            )
        }
    }

    /// The scene: the exact displacement on the upper's top and the lower's bottom, the
    /// tractions `(0, 0, -+tau)` on the sides x = 0 and x = s, the friction law.
    fn problem(&self, n: usize) -> Result<ContactProblem<3>, String> {
        let (p, stick, tau, _) = self.state();
        let bodies = self.stack.bodies(n)?;
        let [upper, lower] = [(0, "top"), (1, "bottom")]
            .into_iter()
            .zip(bodies)
            .map(|((k, held), mut body)| {
                let component = |i: usize| {
                    let exact = self.clone();
                    Some(ScalarValue::function(move |x, _| {
                        exact.exact(k, Point3::new(x[0], x[1], x[2]))[i]
                    }))
                };
                body.dirichlet = vec![DirichletDescription {
                    part: held.to_string(),
                    x: component(0),
                    y: component(1),
                    z: component(2),
                    ..DirichletDescription::default()
                }];
                let traction = |part: &str, gz: f64| TractionDescription {
                    part: part.to_string(),
                    value: Some(VectorValue::constant(&[0.0, 0.0, gz])),
                    ..TractionDescription::default()
                };
                body.traction = vec![traction("left", -tau), traction("right", tau)];
                body
            })
            .collect::<Vec<_>>()
            .try_into()
            .expect("two bodies");
        let law = match self.law {
            FrictionLaw::Tresca(f) => {
                Choice::with_options("tresca", Options::new().with("friction_bound", f * stick))
            }
            FrictionLaw::Coulomb(f) => {
                Choice::with_options("coulomb", Options::new().with("coefficient", f * stick / p))
            }
        };
        stack_problem([upper, lower], law)
    }

    /// The largest nodal displacement error relative to the press and the shift, and the
    /// errors of the normal and the friction resultants relative to `p s^2`.
    fn errors(&self, result: &ContactResult<3>) -> (f64, f64, f64) {
        let s = self.stack.length;
        let (p, _, tau, _) = self.state();
        let mut largest: f64 = 0.0;
        for (k, body) in result.bodies.iter().enumerate() {
            for (v, x) in body.body.mesh().vertices().iter().enumerate() {
                let u = body.solution.vertex_displacement(v);
                largest = largest.max((u - self.exact(k, *x)).norm());
            }
        }
        let force = p * s * s;
        let friction = result.friction_resultant();
        (
            largest / (INDENTATION.max(SHIFT) * s),
            (result.normal_resultant() - force).abs() / force,
            (friction - Vector3::new(-tau * s * s, 0.0, 0.0)).norm() / force,
        )
    }

    fn judge(&self, n: usize, solver: &str) -> Outcome {
        let tolerance = patch_tolerance(solver);
        let outcome = self
            .problem(n)
            .and_then(|problem| solve(&problem, solver, &Options::new()));
        judge(solver, outcome, |r| {
            let (u, normal, friction) = self.errors(r);
            (
                format!(
                    "max nodal error {u:.1e}, resultant errors {normal:.1e} (normal), \
                     {friction:.1e} (friction)"
                ),
                u <= tolerance && normal <= tolerance && friction <= tolerance,
            )
        })
    }
}

/// The laws of the friction rows: Tresca and Coulomb with the bound 0 (free slip), half the
/// stick shear (slip) and huge (`1e8` times the pressure: stick).
const FRICTION_LAWS: [(&str, FrictionLaw); 6] = [
    ("Tresca g_F = 0", FrictionLaw::Tresca(0.0)),
    ("Tresca g_F = tau_s / 2 (slip)", FrictionLaw::Tresca(0.5)),
    ("Tresca g_F huge (stick)", FrictionLaw::Tresca(f64::NAN)),
    ("Coulomb F = 0", FrictionLaw::Coulomb(0.0)),
    ("Coulomb F p = tau_s / 2 (slip)", FrictionLaw::Coulomb(0.5)),
    ("Coulomb F huge (stick)", FrictionLaw::Coulomb(f64::NAN)),
];

/// Friction in space at the extremes, by every solver (and the condensed solver's iterative
/// interface): the stacked non-matching blocks pressed
/// and sheared (the exact answer: the uniform state `sigma_zz = -p`, `sigma_xz = tau` with the
/// stick shear or the bound), Tresca and Coulomb with the bound 0, half the stick shear and
/// `1e8 p`, at stiffness contrast 1e+-8, lengths 1e+-6 and moduli 1e-9, and nu = 0.49999 with
/// the locking-free element `vem1-bbar`.
pub fn solid_friction(size: &Size) -> Vec<Row> {
    let base = Stack {
        poisson: 0.0,
        ..Stack::new(StackCells::HexahedraOnTetrahedra)
    };
    let mut stacks = vec![("E_1/E_2 = 1/3, nu = 0".to_string(), base.clone())];
    for c in [1e8, 1e-8] {
        stacks.push((
            format!("E_1/E_2 = {c:.0e}, nu = 0"),
            Stack {
                young: [100.0 * c, 100.0],
                ..base.clone()
            },
        ));
    }
    for (length, modulus) in [(1e6, 1.0), (1e-6, 1.0), (1.0, 1e-9), (1e-6, 1e-9)] {
        stacks.push((
            format!("lengths x {length:.0e}, moduli x {modulus:.0e}, nu = 0"),
            Stack {
                length,
                modulus,
                ..base.clone()
            },
        ));
    }
    stacks.push((
        "vem1-bbar, nu = 0.49999, E_1 = E_2".to_string(),
        Stack {
            poisson: 0.49999,
            element: "vem1-bbar",
            young: [100.0, 100.0],
            ..base.clone()
        },
    ));
    let mut rows = Vec::new();
    for (name, stack) in &stacks {
        for (law_name, law) in FRICTION_LAWS {
            // The huge bound: 1e8 P over the stick shear.
            let law = match law {
                FrictionLaw::Tresca(f) if f.is_nan() => {
                    let sheared = ShearedStack {
                        stack: stack.clone(),
                        law: FrictionLaw::Tresca(1.0),
                    };
                    let (p, stick, ..) = sheared.state();
                    FrictionLaw::Tresca(HUGE * p / stick)
                }
                FrictionLaw::Coulomb(f) if f.is_nan() => {
                    let sheared = ShearedStack {
                        stack: stack.clone(),
                        law: FrictionLaw::Coulomb(1.0),
                    };
                    let (p, stick, ..) = sheared.state();
                    FrictionLaw::Coulomb(HUGE * p / stick)
                }
                other => other,
            };
            let sheared = ShearedStack {
                stack: stack.clone(),
                law,
            };
            rows.push(Row {
                name: format!("{name}, {law_name}"),
                expected: format!(
                    "exact uniform press and shear (stick or slip): nodal error / max(d, D) and \
                     resultant errors / P <= {:.0e} (penalty: <= {:.0e} = 1/factor)",
                    patch_tolerance(""),
                    patch_tolerance("penalty")
                ),
                outcomes: space_solvers(size)
                    .iter()
                    .map(|s| sheared.judge(size.solid_patch, s))
                    .collect(),
            });
        }
    }
    rows
}
