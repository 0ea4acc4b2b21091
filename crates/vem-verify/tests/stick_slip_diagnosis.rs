//! Diagnosis of the rate of M2-3D (`docs/convergence-3d.md`, section "M2-3D"), not run by
//! default: `cargo test -p vem-verify --test stick_slip_diagnosis -- --ignored --nocapture
//! --test-threads 1`. Each test prints its figures; the assertions hold only what the
//! diagnosis relies on.

use std::sync::Arc;

use nalgebra::{DVector, Matrix3, Vector3};
use vem_contact::CondensedSolver;
use vem_mesh::generators::polyhedral::{Cuboid, PolyhedralFamily};
use vem_mesh::{Point3, PolyhedralMesh};
use vem_space::quadrature::{polyhedron_rule, TetrahedronRule};
use vem_space::{PolyhedralElement, PolyhedralVem};
use vem_verify::exact::{BodyId, Lame};
use vem_verify::three_d::{
    nodal_interpolant_3d, projection_errors_3d, solve_disc_contact, solve_solid, ExactSolution3d,
    StackedContact, StickSlipBody, StickSlipContact, SOLID_SEED,
};

fn case() -> StickSlipContact {
    StickSlipContact::new(Lame::try_new(2.0, 1.0).unwrap())
}

/// A body of M2-3D loaded by the exact traction on its contact side too (no contact).
struct Neumann(StickSlipBody);

impl ExactSolution3d for Neumann {
    fn name(&self) -> &str {
        "M2-3D body, Neumann contact side"
    }
    fn lame(&self) -> Lame {
        self.0.lame()
    }
    fn displacement(&self, x: Point3) -> Vector3<f64> {
        self.0.displacement(x)
    }
    fn gradient(&self, x: Point3) -> Matrix3<f64> {
        self.0.gradient(x)
    }
    fn displacement_and_gradient(&self, x: Point3) -> (Vector3<f64>, Matrix3<f64>) {
        self.0.displacement_and_gradient(x)
    }
    fn body_force(&self, x: Point3) -> Vector3<f64> {
        self.0.body_force(x)
    }
    fn traction_sides(&self) -> &[&'static str] {
        match self.0.id() {
            BodyId::One => &["left", "right", "front", "back", "bottom"],
            BodyId::Two => &["left", "right", "front", "back", "top"],
        }
    }
    fn domain(&self) -> Cuboid {
        self.0.domain()
    }
}

/// The regions of a box the error is split over, by a cell's centroid (`h = 1/n`): the layer
/// of cells at the interface within `2h` of the stick circle, the rest of the interface layer,
/// the cells within `2h` of a lateral side, the bulk.
const REGIONS: [&str; 4] = [
    "interface, near circle",
    "interface, rest",
    "lateral",
    "bulk",
];

fn region(c: Point3, h: f64) -> usize {
    let r = StickSlipContact::radius(c.x, c.y);
    let interface = c.z.abs() < 2.0 * h;
    if interface && (r - StickSlipContact::STICK_RADIUS).abs() < 2.0 * h {
        0
    } else if interface {
        1
    } else if c.x.min(1.0 - c.x).min(c.y).min(1.0 - c.y) < 2.0 * h {
        2
    } else {
        3
    }
}

/// `E_grad^2` per region (and the volume of each region).
fn split(
    exact: &dyn ExactSolution3d,
    mesh: &PolyhedralMesh,
    element: &dyn PolyhedralElement,
    displacement: &[f64],
    h: f64,
) -> ([f64; 4], [f64; 4]) {
    let rule = TetrahedronRule::degree5();
    let (mut sums, mut volumes) = ([0.0; 4], [0.0; 4]);
    for c in 0..mesh.n_cells() {
        let polyhedron = mesh.cell_polyhedron(c);
        let projection = element.projection(&polyhedron).unwrap();
        let vertices = mesh.cell_vertices(c);
        let local = DVector::from_iterator(
            3 * vertices.len(),
            vertices
                .iter()
                .flat_map(|&v| (0..3).map(move |k| displacement[3 * v + k])),
        );
        let coefficients = &projection.coefficients * &local;
        let gradient = Matrix3::from_fn(|i, j| coefficients[3 + 3 * i + j]);
        let centroid = vertices
            .iter()
            .fold(Vector3::zeros(), |a, &v| a + mesh.vertices()[v].coords)
            / vertices.len() as f64;
        let k = region(Point3::from(centroid), h);
        for q in polyhedron_rule(&polyhedron, &rule) {
            sums[k] += q.weight * (exact.gradient(q.point) - gradient).norm_squared();
            volumes[k] += q.weight;
        }
    }
    (sums, volumes)
}

fn rate(e: &[f64], h: &[f64]) -> String {
    e.windows(2)
        .zip(h.windows(2))
        .map(|(e, h)| format!("{:.3}", (e[0] / e[1]).ln() / (h[0] / h[1]).ln()))
        .collect::<Vec<_>>()
        .join(", ")
}

/// (d) Each body alone with the exact traction on its contact side, and the interpolant of the
/// exact solution: `E_grad` and its split over the regions, at `n = 8, 12, 16, 20`.
#[test]
#[ignore]
fn m2_3d_bodies_alone_and_interpolant() {
    let exact = case();
    let element = Arc::new(PolyhedralVem::default());
    for (family, id) in [
        (PolyhedralFamily::Hexahedra, BodyId::One),
        (PolyhedralFamily::Tetrahedra, BodyId::Two),
    ] {
        let body = Arc::new(Neumann(exact.body(id)));
        let (mut solved, mut interpolated, mut spacing) = (Vec::new(), Vec::new(), Vec::new());
        for n in [8, 12, 16, 20] {
            let mesh = family.generate(&body.domain(), n, SOLID_SEED).unwrap();
            let h = (1.0 / mesh.n_cells() as f64).cbrt();
            let interpolant = nodal_interpolant_3d(&*body, &mesh);
            let ei = projection_errors_3d(&*body, &mesh, &*element, &interpolant).unwrap();
            let (split_i, _) = split(&*body, &mesh, &*element, &interpolant, 1.0 / n as f64);
            let (solved_body, u, errors) =
                solve_solid(body.clone(), mesh, element.clone()).unwrap();
            let (split_u, volumes) =
                split(&*body, solved_body.mesh(), &*element, &u, 1.0 / n as f64);
            eprintln!(
                "{} body {:?} n = {n}: solve E_grad {:.4e} (rel {:.4e}), interpolant E_grad {:.4e}",
                family.name(),
                id,
                errors.grad,
                errors.relative_grad(),
                ei.grad
            );
            for k in 0..4 {
                eprintln!(
                    "    {:<24} volume {:.3}  solve E_grad^2 {:.3e}  interpolant {:.3e}",
                    REGIONS[k], volumes[k], split_u[k], split_i[k]
                );
            }
            solved.push(errors.grad);
            interpolated.push(ei.grad);
            spacing.push(h);
        }
        eprintln!(
            "{} body {:?}: solve rates {}, interpolant rates {}",
            family.name(),
            id,
            rate(&solved, &spacing),
            rate(&interpolated, &spacing)
        );
    }
}

/// The contact solve on hexahedra over tetrahedra, `E_grad` split over the regions of each
/// body. Sizes from `M2_PAIRS` (default `8/6,12/9,16/12`).
#[test]
#[ignore]
fn m2_3d_contact_error_split() {
    let exact = case();
    let element = Arc::new(PolyhedralVem::default());
    let mut totals = Vec::new();
    let mut spacing = Vec::new();
    let mut by_region = vec![Vec::new(); 4];
    let pairs: Vec<(usize, usize)> = std::env::var("M2_PAIRS")
        .unwrap_or_else(|_| "8/6,12/9,16/12".into())
        .split(',')
        .map(|p| {
            let (a, b) = p.split_once('/').unwrap();
            (a.parse().unwrap(), b.parse().unwrap())
        })
        .collect();
    for (a, b) in pairs {
        let upper = PolyhedralFamily::Hexahedra
            .generate(&exact.body(BodyId::One).domain(), a, SOLID_SEED)
            .unwrap();
        let lower = PolyhedralFamily::Tetrahedra
            .generate(&exact.body(BodyId::Two).domain(), b, SOLID_SEED)
            .unwrap();
        let (result, errors) = solve_disc_contact(
            &exact,
            upper,
            lower,
            element.clone(),
            &mut CondensedSolver::default(),
        )
        .unwrap();
        let mut regions = [0.0; 4];
        for (k, id) in BodyId::BOTH.into_iter().enumerate() {
            let solved = &result.bodies[k];
            let n = if k == 0 { a } else { b };
            let (s, v) = split(
                &*exact.exact_body(id),
                solved.body.mesh(),
                &*element,
                solved.solution.displacement(),
                1.0 / n as f64,
            );
            eprintln!(
                "n = {a}/{b} body {:?}: E_grad {:.4e}; per region {:?} (volumes {:?})",
                id,
                errors[k].grad,
                s.map(|x| format!("{x:.3e}")),
                v.map(|x| format!("{x:.3}"))
            );
            for j in 0..4 {
                regions[j] += s[j];
            }
        }
        let total = errors.iter().map(|e| e.grad * e.grad).sum::<f64>().sqrt();
        let norm = errors
            .iter()
            .map(|e| e.exact_grad * e.exact_grad)
            .sum::<f64>()
            .sqrt();
        let total_l2 = errors.iter().map(|e| e.l2 * e.l2).sum::<f64>().sqrt();
        eprintln!(
            "n = {a}/{b}: E_grad {total:.4e} (relative {:.4e}), E_0 {total_l2:.4e}, {:?}",
            total / norm,
            result.report.status
        );
        totals.push(total);
        spacing.push(1.0 / a as f64);
        for j in 0..4 {
            by_region[j].push(regions[j].sqrt());
        }
    }
    eprintln!("E_grad rates {}", rate(&totals, &spacing));
    for j in 0..4 {
        eprintln!("  {}: {}", REGIONS[j], rate(&by_region[j], &spacing));
    }
}

/// `E_grad` of the nodal interpolant alone (no solve) on hexahedra and tetrahedra far beyond
/// the sizes of the study, for M2-3D and, as the reference, M1-3D.
#[test]
#[ignore]
fn m2_3d_interpolant_far_out() {
    let element = PolyhedralVem::default();
    let lame = Lame::try_new(2.0, 1.0).unwrap();
    let m1 = vem_verify::three_d::DiscContact::new(lame);
    let m2 = case();
    let cases: [(&str, &dyn StackedContact); 2] = [("M1-3D", &m1), ("M2-3D", &m2)];
    for (name, exact) in cases {
        for family in [PolyhedralFamily::Hexahedra, PolyhedralFamily::Tetrahedra] {
            for id in BodyId::BOTH {
                let body = exact.exact_body(id);
                let (mut e, mut h) = (Vec::new(), Vec::new());
                for n in [8, 12, 16, 20, 24, 32, 40, 48] {
                    let mesh = family.generate(&body.domain(), n, SOLID_SEED).unwrap();
                    let interpolant = nodal_interpolant_3d(&*body, &mesh);
                    let errors =
                        projection_errors_3d(&*body, &mesh, &element, &interpolant).unwrap();
                    e.push(errors.grad);
                    h.push((1.0 / mesh.n_cells() as f64).cbrt());
                }
                eprintln!(
                    "{name} {} body {:?}: interpolant E_grad {:?}; rates {}",
                    family.name(),
                    id,
                    e.iter().map(|x| format!("{x:.3e}")).collect::<Vec<_>>(),
                    rate(&e, &h)
                );
            }
        }
    }
}

/// (d) far out: body two alone on tetrahedra and body one alone on hexahedra (the exact
/// traction on the contact side), `E_grad` of the solve and of the interpolant, for M2-3D and
/// M1-3D. Sizes from `M2_SIZES` (default `16,20,24,32`).
#[test]
#[ignore]
fn m2_3d_bodies_alone_far_out() {
    let sizes: Vec<usize> = std::env::var("M2_SIZES")
        .unwrap_or_else(|_| "16,20,24,32".into())
        .split(',')
        .map(|s| s.parse().unwrap())
        .collect();
    let element = Arc::new(PolyhedralVem::default());
    let lame = Lame::try_new(2.0, 1.0).unwrap();
    let m1 = vem_verify::three_d::DiscContact::new(lame);
    for (family, id) in [
        (PolyhedralFamily::Tetrahedra, BodyId::Two),
        (PolyhedralFamily::Hexahedra, BodyId::One),
    ] {
        let bodies: [(&str, Arc<dyn ExactSolution3d>); 2] = [
            ("M2-3D", Arc::new(Neumann(case().body(id)))),
            ("M1-3D", Arc::new(NeumannM1(m1.body(id)))),
        ];
        for (name, body) in bodies {
            let (mut solved, mut interpolated, mut spacing) = (Vec::new(), Vec::new(), Vec::new());
            for &n in &sizes {
                let mesh = family.generate(&body.domain(), n, SOLID_SEED).unwrap();
                let h = (1.0 / mesh.n_cells() as f64).cbrt();
                let interpolant = nodal_interpolant_3d(&*body, &mesh);
                let ei = projection_errors_3d(&*body, &mesh, &*element, &interpolant).unwrap();
                let (_, _, errors) = solve_solid(body.clone(), mesh, element.clone()).unwrap();
                eprintln!(
                    "{name} {} body {:?} n = {n}: solve E_grad {:.4e}, interpolant {:.4e}, E_0 {:.4e}",
                    family.name(),
                    id,
                    errors.grad,
                    ei.grad,
                    errors.l2
                );
                solved.push(errors.grad);
                interpolated.push(ei.grad);
                spacing.push(h);
            }
            eprintln!(
                "{name} {} body {:?}: solve rates {}, interpolant rates {}",
                family.name(),
                id,
                rate(&solved, &spacing),
                rate(&interpolated, &spacing)
            );
        }
    }
}

/// A body of M1-3D loaded by the exact traction on its contact side too (no contact).
struct NeumannM1(vem_verify::three_d::DiscContactBody);

impl ExactSolution3d for NeumannM1 {
    fn name(&self) -> &str {
        "M1-3D body, Neumann contact side"
    }
    fn lame(&self) -> Lame {
        self.0.lame()
    }
    fn displacement(&self, x: Point3) -> Vector3<f64> {
        self.0.displacement(x)
    }
    fn gradient(&self, x: Point3) -> Matrix3<f64> {
        self.0.gradient(x)
    }
    fn displacement_and_gradient(&self, x: Point3) -> (Vector3<f64>, Matrix3<f64>) {
        self.0.displacement_and_gradient(x)
    }
    fn body_force(&self, x: Point3) -> Vector3<f64> {
        self.0.body_force(x)
    }
    fn traction_sides(&self) -> &[&'static str] {
        match self.0.id() {
            BodyId::One => &["left", "right", "front", "back", "bottom"],
            BodyId::Two => &["left", "right", "front", "back", "top"],
        }
    }
    fn domain(&self) -> Cuboid {
        self.0.domain()
    }
}
