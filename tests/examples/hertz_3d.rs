//! Hertz in space: a rigid ball of radius R pressed with a force P into an elastic block, and
//! the cost of the condensed solver in 3D. Run with
//!
//! ```text
//! cargo run --release -p vem-integration-tests --example hertz_3d -- hertz [h/a ...]
//! cargo run --release -p vem-integration-tests --example hertz_3d -- hertz-zone h/a ...
//! cargo run --release -p vem-integration-tests --example hertz_3d -- cost [n ...]
//! ```
//!
//! `hertz`: a quarter of the block `[0, 1]^2 x [-1, 0]` (symmetry planes x = 0 and y = 0),
//! E = 200, nu = 0.3, under a rigid ball of radius R = 1 touching the top at the origin; the
//! bottom is a rigid plate pushed up with the force P/4 (force control), P chosen so that
//! Hertz's contact radius is a = 0.1. The hexahedra are uniform of size h on `[0, 1.5 a]` in
//! x, y and depth and grow by 1.25 per cell beyond. Printed per h/a: the mesh, the resultant
//! check, the contact radius and peak pressure against Hertz, the pressure's relative L2 error
//! on the contact part, the times. `hertz-zone`: the same with the contact part only the top's
//! faces within 2a of the axis (the rest of the top free).
//!
//! `cost`: a cube `[0, 1]^3` of n^3 hexahedra clamped at its bottom, lifted into a rigid ball of
//! radius 2 by 0.05 on its whole top (`(n + 1)^2` interface nodes): the condensed solver's
//! time against one elastic solve of the same body (its top held instead), and the
//! interface size.

use std::error::Error;
use std::sync::Arc;
use std::time::Instant;

use vem_contact::{
    CondensedSolver, ContactProblem, ContactResult, ContactSolver, Frictionless, Obstacle3,
};
use vem_elastic::{Component, Dirichlet, ElasticBody, Material};
use vem_mesh::generators::polyhedral::{hexahedra, Cuboid};
use vem_mesh::{Point3, PolyhedralMesh, Vector3};
use vem_space::PolyhedralVem;
use vem_verify::exact::HertzSphere;

const E: f64 = 200.0;
const NU: f64 = 0.3;
const RADIUS: f64 = 1.0;
const CONTACT_RADIUS: f64 = 0.1;
const GROWTH: f64 = 1.25;

/// Coordinates from 0 to `length`: cells of size `h` up to `fine`, then growing by `GROWTH`
/// (the last cell shortened to end at `length`, merged with the one before if too short).
fn graded(h: f64, fine: f64, length: f64) -> Vec<f64> {
    let mut x = vec![0.0];
    let mut step = h;
    while *x.last().unwrap() < length - 1e-12 {
        let last = *x.last().unwrap();
        if last >= fine - 1e-12 {
            step *= GROWTH;
        }
        x.push((last + step).min(length));
    }
    let n = x.len();
    if n > 2 && x[n - 1] - x[n - 2] < 0.5 * step {
        x.remove(n - 2);
    }
    x
}

/// The lattice `hexahedra` with its vertex (i, j, k) moved to `(xs[i], ys[j], -zs[nz - k])`.
fn graded_block(xs: &[f64], zs: &[f64]) -> Result<PolyhedralMesh, Box<dyn Error>> {
    let (n, nz) = (xs.len() - 1, zs.len() - 1);
    let lattice = hexahedra(&Cuboid::unit_cube(), n, n, nz)?;
    let index = |s: f64, m: usize| (s * m as f64).round() as usize;
    let vertices = lattice
        .vertices()
        .iter()
        .map(|p| {
            Point3::new(
                xs[index(p.x, n)],
                xs[index(p.y, n)],
                -zs[nz - index(p.z, nz)],
            )
        })
        .collect();
    // The box sides keep their names: x = 0 left, y = 0 front, z = 0 top, z = -1 bottom.
    Ok(PolyhedralMesh::from_compact(
        vertices,
        lattice.face_offsets().to_vec(),
        lattice.face_vertex_indices().to_vec(),
        lattice.cell_offsets().to_vec(),
        lattice.cell_face_indices().to_vec(),
        lattice.parts().to_vec(),
    )?)
}

fn solve(problem: &ContactProblem<3>) -> Result<(ContactResult<3>, f64, f64), Box<dyn Error>> {
    let start = Instant::now();
    let discretisation = problem.discretise()?;
    let build = start.elapsed().as_secs_f64();
    let mut solver = CondensedSolver::default();
    let start = Instant::now();
    let result = discretisation.solve(&mut solver as &mut dyn ContactSolver)?;
    Ok((result, build, start.elapsed().as_secs_f64()))
}

fn hertz(levels: &[f64], zone: bool) -> Result<(), Box<dyn Error>> {
    let e_star = HertzSphere::rigid_ball_modulus(E, NU);
    let load = 4.0 * e_star * CONTACT_RADIUS.powi(3) / (3.0 * RADIUS);
    let exact = HertzSphere::try_new(RADIUS, e_star, load)?;
    let (a, p0) = (exact.contact_radius(), exact.peak_pressure());
    println!("Hertz: R = {RADIUS}, E* = {e_star:.4}, P = {load:.6e}, a = {a:.6}, p0 = {p0:.6}");
    println!(
        "| h/a | cells | unknowns | contact part nodes | sum F_z / (P/4) - 1 | farthest node in contact / a \
         | a fit error | p(0) error | p0 fit error | pressure L2 error | build s | solve s |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    for &ratio in levels {
        let h = ratio * a;
        let xs = graded(h, 1.5 * a, 1.0);
        let mut mesh = graded_block(&xs, &xs)?;
        let part = if zone {
            // The contact part: the top's faces within 2 a of the axis (in x and y).
            let top = mesh.part_faces("top")?.to_vec();
            let (near, far): (Vec<usize>, Vec<usize>) = top.iter().partition(|&&f| {
                let c = mesh.face_centroid(f);
                c.x < 2.0 * a && c.y < 2.0 * a
            });
            let mut parts: Vec<vem_mesh::FacePart> = mesh.parts().to_vec();
            parts.push(vem_mesh::FacePart::new("zone", near));
            parts.push(vem_mesh::FacePart::new("outside", far));
            parts.retain(|p| p.name != "top");
            mesh = mesh.with_parts(parts)?;
            "zone"
        } else {
            "top"
        };
        let cells = mesh.n_cells();
        let body = ElasticBody::builder_polyhedral(
            "block",
            mesh,
            Material::isotropic(E, NU)?,
            Arc::new(PolyhedralVem::default()),
        )
        .dirichlet(Dirichlet::rigid_plate(
            "bottom",
            Component::Z,
            Vector3::new(0.0, 0.0, load / 4.0),
        ))
        .dirichlet(Dirichlet::fixed("left", Component::X))
        .dirichlet(Dirichlet::fixed("front", Component::Y))
        .build()?;
        let ball = Obstacle3::Sphere {
            centre: Point3::new(0.0, 0.0, RADIUS),
            radius: RADIUS,
        };
        let problem = ContactProblem::against_obstacle(body, part, ball, Frictionless);
        let (result, build, time) = solve(&problem)?;
        let unknowns: usize = result.model.bodies.iter().map(|b| b.free_dofs).sum();
        let resultant = -result.force_on_body(0).z;
        let balance = resultant / (load / 4.0) - 1.0;
        let r = |n: &vem_contact::InterfaceNode<3>| n.position.x.hypot(n.position.y);
        let centre = result
            .nodes
            .iter()
            .find(|n| r(n) < 1e-12)
            .ok_or("no node at the axis")?;
        // The nodes along the x axis; the farthest node in contact.
        let mut axis: Vec<&vem_contact::InterfaceNode<3>> = result
            .nodes
            .iter()
            .filter(|n| n.position.y.abs() < 1e-12)
            .collect();
        axis.sort_by(|p, q| p.position.x.total_cmp(&q.position.x));
        let reach = result
            .nodes
            .iter()
            .filter(|n| n.status.is_active())
            .map(r)
            .fold(0.0f64, f64::max);
        // p0 and a from the least-squares fit of p^2 = p0^2 (1 - r^2/a^2) over r < 0.7 a.
        let (mut s1, mut sx, mut sy, mut sxx, mut sxy) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for n in result.nodes.iter().filter(|n| r(n) < 0.7 * a) {
            let (x, y) = (r(n).powi(2), n.consistent_pressure.powi(2));
            s1 += 1.0;
            sx += x;
            sy += y;
            sxx += x * x;
            sxy += x * y;
        }
        let slope = (s1 * sxy - sx * sy) / (s1 * sxx - sx * sx);
        let intercept = (sy - slope * sx) / s1;
        let p0_fit = intercept.sqrt();
        let a_fit = (-intercept / slope).sqrt();
        // The relative L2 error of the consistent pressure (nodal quadrature on the top).
        let (mut num, mut den) = (0.0, 0.0);
        for n in &result.nodes {
            let e = exact.pressure(r(n));
            num += n.tributary_measure * (n.consistent_pressure - e).powi(2);
            den += n.tributary_measure * e * e;
        }
        println!(
            "| {ratio} | {cells} | {unknowns} | {} | {balance:.1e} | {:.3} | {:+.2} % | {:+.2} % | \
             {:+.2} % | {:.2} % | {build:.2} | {time:.2} |",
            result.nodes.len(),
            reach / a,
            100.0 * (a_fit / a - 1.0),
            100.0 * (centre.consistent_pressure / p0 - 1.0),
            100.0 * (p0_fit / p0 - 1.0),
            100.0 * (num / den).sqrt(),
        );
        if std::env::var_os("HERTZ_PROFILE").is_some() {
            for n in &axis {
                println!(
                    "profile {ratio} {:.6} {:.6} {:.6} {:.6}",
                    n.position.x,
                    n.consistent_pressure,
                    n.pressure,
                    exact.pressure(n.position.x)
                );
            }
        }
    }
    Ok(())
}

fn cost(sizes: &[usize]) -> Result<(), Box<dyn Error>> {
    println!(
        "| n | unknowns | interface nodes | build s | contact solve s | numeric s | solves s | \
         dense interface s | one elastic solve s | ratio |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for &n in sizes {
        let mesh = hexahedra(&Cuboid::unit_cube(), n, n, n)?;
        let lift = 0.05;
        let builder = |mesh: PolyhedralMesh| {
            ElasticBody::builder_polyhedral(
                "cube",
                mesh,
                Material::isotropic(E, NU).expect("valid"),
                Arc::new(PolyhedralVem::default()),
            )
            .dirichlet(Dirichlet::with_values(
                "bottom",
                Component::All,
                move |_| Vector3::new(0.0, 0.0, lift),
            ))
        };
        // One elastic solve of the same body with its top held: factorisation and solve.
        let held = builder(mesh.clone()).clamp("top").build()?;
        let start = Instant::now();
        let _ = held.solve()?;
        let elastic = start.elapsed().as_secs_f64();
        let ball = Obstacle3::Sphere {
            centre: Point3::new(0.5, 0.5, 1.0 + 2.0),
            radius: 2.0,
        };
        let problem =
            ContactProblem::against_obstacle(builder(mesh).build()?, "top", ball, Frictionless);
        let (result, build, time) = solve(&problem)?;
        let t = result.report.work.times;
        let dense =
            time - t.numeric.as_secs_f64() - t.symbolic.as_secs_f64() - t.solves.as_secs_f64();
        let unknowns: usize = result.model.bodies.iter().map(|b| b.free_dofs).sum();
        println!(
            "| {n} | {unknowns} | {} | {build:.2} | {time:.2} | {:.2} | {:.2} | {dense:.2} | \
             {elastic:.2} | {:.2} |",
            result.nodes.len(),
            t.numeric.as_secs_f64() + t.symbolic.as_secs_f64(),
            t.solves.as_secs_f64(),
            time / elastic,
        );
    }
    Ok(())
}

fn main() -> Result<(), Box<dyn Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mode = args.first().map_or("hertz", String::as_str);
    match mode {
        "hertz" => {
            let levels: Vec<f64> = if args.len() > 1 {
                args[1..]
                    .iter()
                    .map(|s| s.parse())
                    .collect::<Result<_, _>>()?
            } else {
                vec![0.4, 0.2, 0.1]
            };
            hertz(&levels, false)
        }
        "hertz-zone" => {
            let levels: Vec<f64> = args[1..]
                .iter()
                .map(|s| s.parse())
                .collect::<Result<_, _>>()?;
            hertz(&levels, true)
        }
        "cost" => {
            let sizes: Vec<usize> = if args.len() > 1 {
                args[1..]
                    .iter()
                    .map(|s| s.parse())
                    .collect::<Result<_, _>>()?
            } else {
                vec![8, 16, 24]
            };
            cost(&sizes)
        }
        other => Err(format!("unknown mode '{other}' (hertz, hertz-zone or cost)").into()),
    }
}
