//! The contact patch test PTC1 (frictionless, linear exact state) on two blocks meshed by any
//! two of the seven families, at any size ratio, with the lower mesh's nodes shifted along the
//! interface: the error of the discrete answer and the shortest interface edge it was solved
//! on. Shared by the interface proptest and the `interface_study` example.

use std::sync::Arc;

use vem_contact::{CondensedSolver, ContactProblem, Frictionless};
use vem_elastic::{Component, Dirichlet, ElasticBody, Material, Plane};
use vem_mesh::generators::{MeshFamily, Rectangle};
use vem_mesh::interface::InterfaceOptions;
use vem_mesh::{Mesh, Point, Vector};
use vem_space::LowestOrderVem;

const LAMBDA: f64 = 2.0;
const MU: f64 = 1.0;
/// PTC1: u_1 = (e, -d + beta (1 - y)) above, u_2 = (-e, d - beta (1 + y)) below.
const BETA: f64 = 0.01;
const D: f64 = 0.03;
const E: f64 = 0.02;

/// One pairing of the study.
#[derive(Debug, Clone, Copy)]
pub struct Pairing {
    /// The upper body's family.
    pub upper: MeshFamily,
    /// The lower body's family.
    pub lower: MeshFamily,
    /// Cells across of the upper body.
    pub n_upper: usize,
    /// Cells across of the lower body.
    pub n_lower: usize,
    /// Seed of the random families.
    pub seed: u64,
    /// Shift of the lower mesh's nodes along the interface: x -> x + shift sin(pi x) / pi.
    pub shift: f64,
}

/// What one pairing gave.
#[derive(Debug, Clone, Copy)]
pub struct Outcome {
    /// Largest vertex displacement error relative to the displacement scale, and largest
    /// nodal force error relative to the largest nodal force.
    pub error: f64,
    /// Shortest interface edge over the diameter of its polygon, after insertion.
    pub shortest_fraction: f64,
    /// The same on the meshes as generated (what the meshes bring themselves).
    pub shortest_fraction_before: f64,
}

fn upper_field(x: Point) -> Vector {
    Vector::new(E, -D + BETA * (1.0 - x.y))
}

fn lower_field(x: Point) -> Vector {
    Vector::new(-E, D - BETA * (1.0 + x.y))
}

/// `mesh` with every vertex moved by `x -> x + shift sin(pi x) / pi`: the unit-width block keeps
/// its shape, its nodes slide along the interface by up to `shift / pi`.
fn shifted(mesh: &Mesh, shift: f64) -> Mesh {
    let vertices = mesh
        .vertices()
        .iter()
        .map(|p| {
            Point::new(
                p.x + shift * (std::f64::consts::PI * p.x).sin() / std::f64::consts::PI,
                p.y,
            )
        })
        .collect();
    Mesh::from_compact(
        vertices,
        mesh.polygon_offsets().to_vec(),
        mesh.polygon_vertex_indices().to_vec(),
        mesh.part_specs(),
    )
    .expect("a small monotone shift keeps the mesh valid")
}

/// Shortest edge of part `part` over the diameter of the polygon that owns it.
fn shortest_fraction(mesh: &Mesh, part: &str) -> f64 {
    let mut shortest = f64::INFINITY;
    for &e in &mesh.part(part).expect("the part exists").edges {
        let [a, b] = mesh.edge(e).vertices;
        let length = (mesh.vertex(b) - mesh.vertex(a)).norm();
        let polygon = (0..mesh.n_polygons())
            .find(|&p| {
                let ring = mesh.polygon(p);
                (0..ring.len()).any(|k| ring[k] == a && ring[(k + 1) % ring.len()] == b)
            })
            .expect("a boundary edge has a polygon");
        shortest = shortest.min(length / mesh.element_quality(polygon).diameter);
    }
    shortest
}

fn body(name: &str, mesh: Mesh, upper: bool) -> ElasticBody {
    let material = Material::from_lame(LAMBDA, MU, Plane::Strain).expect("admissible");
    let (clamped, field): (&str, fn(Point) -> Vector) = if upper {
        ("top", upper_field)
    } else {
        ("bottom", lower_field)
    };
    let lb = LAMBDA * BETA;
    ElasticBody::builder(name, mesh, material, Arc::new(LowestOrderVem::default()))
        .dirichlet(Dirichlet::prescribed(clamped, Component::All, field))
        .traction("left", move |_| Vector::new(lb, 0.0))
        .traction("right", move |_| Vector::new(-lb, 0.0))
        .build()
        .expect("valid body")
}

/// Runs PTC1 on `pairing` with the interface options `options`.
pub fn run(pairing: &Pairing, options: InterfaceOptions) -> Result<Outcome, String> {
    let upper_rect = Rectangle::new(Point::new(0.0, 0.0), Point::new(1.0, 1.0));
    let lower_rect = Rectangle::new(Point::new(0.0, -1.0), Point::new(1.0, 0.0));
    let upper = pairing
        .upper
        .generate(&upper_rect, pairing.n_upper, pairing.seed)
        .map_err(|e| e.to_string())?;
    let lower = shifted(
        &pairing
            .lower
            .generate(&lower_rect, pairing.n_lower, pairing.seed + 1)
            .map_err(|e| e.to_string())?,
        pairing.shift,
    );
    let before = shortest_fraction(&upper, "bottom").min(shortest_fraction(&lower, "top"));
    let h0 = 2.0 * (D - BETA);
    let problem = ContactProblem::two_bodies(
        body("upper", upper, true),
        "bottom",
        body("lower", lower, false),
        "top",
        Frictionless,
    )
    .with_imposed_gap(move |_| h0)
    .with_interface_options(options);
    let result = problem
        .solve(&mut CondensedSolver::default())
        .map_err(|e| e.to_string())?;
    let mut error: f64 = 0.0;
    for (k, solved) in result.bodies.iter().enumerate() {
        let mesh = solved.body.mesh();
        for v in 0..mesh.n_vertices() {
            let x = mesh.vertex(v);
            let exact = if k == 0 {
                upper_field(x)
            } else {
                lower_field(x)
            };
            error = error.max((solved.solution.vertex_displacement(v) - exact).norm() / 0.05);
        }
    }
    let sigma_nu = -(LAMBDA + 2.0 * MU) * BETA;
    let largest = result
        .nodes
        .iter()
        .map(|n| n.normal_force.abs())
        .fold(0.0, f64::max);
    for node in &result.nodes {
        let expected = -sigma_nu * node.tributary_measure;
        error = error.max((node.normal_force - expected).abs() / largest);
    }
    let after = shortest_fraction(result.bodies[0].body.mesh(), "bottom")
        .min(shortest_fraction(result.bodies[1].body.mesh(), "top"));
    Ok(Outcome {
        error,
        shortest_fraction: after,
        shortest_fraction_before: before,
    })
}
