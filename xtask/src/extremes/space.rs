//! The rows of `cargo xtask extremes` in space (`D = 3`), shared with the workspace test
//! `tests/tests/extremes.rs` as [`rows`](super::rows) is:
//!
//! - the locking measure on the divergence-free solution E2-3D (errors at a Poisson ratio close
//!   to 1/2 against those at 0.3) for every element on polyhedra and three families;
//! - the contact patch test of two stacked blocks on non-matching surfaces (hexahedra on
//!   tetrahedra: the surface overlay makes them node-to-node) at the extremes - stiffness
//!   contrast, units, nu = 0.49999, thin and distorted cells - where the exact answer is the
//!   uniform uniaxial stress `sigma_zz = -p`, `p = d / (h_1 / E_1 + h_2 / E_2)`, transmitted node
//!   by node, whatever the scales.

use std::sync::Arc;

use vem_contact::{ContactProblem, ContactResult, Frictionless};
use vem_elastic::{Component, Dirichlet, ElasticBody, Material};
use vem_mesh::generators::polyhedral::{
    hexahedra, perturbed_hexahedra, tetrahedra, voronoi_polyhedra, Cuboid, PolyhedralFamily,
};
use vem_mesh::{Point3, PolyhedralMesh, Vector3};
use vem_space::{Choice, ElementRegistry, Options, PolyhedralElement};
use vem_verify::exact::Lame;
use vem_verify::three_d::{solve_solid, DivergenceFreeSolid, SOLID_SEED};

use super::rows::{chain, judge, locking_row, patch_tolerance, solve, Outcome, Row, Size};

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

    fn problem(&self, n: usize) -> Result<ContactProblem<3>, String> {
        let element = ElementRegistry::builtin()
            .make_polyhedral_choice(&Choice::named(self.element))
            .map_err(|e| chain(&e))?;
        let [upper_mesh, lower_mesh] = self.meshes(n)?;
        let material =
            |e: f64| Material::isotropic(e * self.modulus, self.poisson).map_err(|e| chain(&e));
        let rollers = |b: vem_elastic::ElasticBodyBuilder<3>| {
            b.dirichlet(Dirichlet::fixed("left", Component::X))
                .dirichlet(Dirichlet::fixed("front", Component::Y))
        };
        let d = INDENTATION * self.length;
        let upper = rollers(
            ElasticBody::builder_polyhedral(
                "upper",
                upper_mesh,
                material(self.young[0])?,
                Arc::clone(&element),
            )
            .dirichlet(Dirichlet::with_values("top", Component::Z, move |_| {
                Vector3::new(0.0, 0.0, -d)
            })),
        )
        .build()
        .map_err(|e| chain(&e))?;
        let lower = rollers(
            ElasticBody::builder_polyhedral("lower", lower_mesh, material(self.young[1])?, element)
                .dirichlet(Dirichlet::fixed("bottom", Component::Z)),
        )
        .build()
        .map_err(|e| chain(&e))?;
        Ok(ContactProblem::two_bodies(
            upper,
            "bottom",
            lower,
            "top",
            Frictionless,
        ))
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

fn stack_row(name: String, stack: &Stack, size: &Size) -> Row {
    Row {
        name,
        expected: format!(
            "exact uniaxial field: nodal error / d and resultant error <= {:.0e} (penalty: <= \
             {:.0e} = 1/factor)",
            patch_tolerance(""),
            patch_tolerance("penalty")
        ),
        outcomes: size
            .solvers
            .iter()
            .map(|s| stack.judge(size.solid_patch, s))
            .collect(),
    }
}

/// The contact patch test in space at the extremes, by every solver: stiffness contrast
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
