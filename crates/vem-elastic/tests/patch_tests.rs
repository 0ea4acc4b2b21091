//! Linear patch tests PT0a and PT0b (docs/manufactured.md section 6): on any polygonal mesh the
//! discrete solution equals the exact linear field at the nodes, the projection reproduces it
//! in every element, and a_h(u_h, u_h) = a(u, u).

mod common;

use common::{lame, nodal_error, vem, ExactField, Pt0a, Pt0b, LAME_PAIRS};
use nalgebra::Vector3;
use vem_elastic::{Component, Dirichlet, ElasticBody};
use vem_mesh::generators::{structured_quads, structured_triangles, MeshFamily, Rectangle};
use vem_mesh::{Mesh, Vector};

/// Every test mesh: structured quads and triangles plus every generator family.
fn meshes() -> Vec<(String, Mesh)> {
    let square = Rectangle::unit_square();
    let mut meshes = vec![
        (
            "quads 3x3".to_string(),
            structured_quads(&square, 3, 3).unwrap(),
        ),
        (
            "quads 5x4".to_string(),
            structured_quads(&square, 5, 4).unwrap(),
        ),
        (
            "triangles 4x4".to_string(),
            structured_triangles(&square, 4, 4).unwrap(),
        ),
    ];
    for family in MeshFamily::all() {
        meshes.push((
            format!("{} n=5", family.name()),
            family.generate(&square, 5, 7).unwrap(),
        ));
    }
    meshes
}

/// Voigt strain `[eps_xx, eps_yy, 2 eps_xy]` of a field.
fn voigt_strain(field: &dyn ExactField) -> Vector3<f64> {
    let g = field.grad(vem_mesh::Point::origin());
    Vector3::new(g[(0, 0)], g[(1, 1)], g[(0, 1)] + g[(1, 0)])
}

/// a(u, u) over the unit square for a field with constant strain: lambda tr^2 + 2 mu eps:eps.
fn exact_energy_norm(field: &dyn ExactField, lambda: f64, mu: f64) -> f64 {
    let e = voigt_strain(field);
    let trace = e[0] + e[1];
    lambda * trace * trace + 2.0 * mu * (e[0] * e[0] + e[1] * e[1] + 0.5 * e[2] * e[2])
}

fn check_exact(name: &str, body: &ElasticBody, field: &dyn ExactField, lambda: f64, mu: f64) {
    let solution = body.solve().unwrap();
    let u = solution.displacement();
    let nodal = nodal_error(body.mesh(), u, field);
    assert!(nodal < 1e-10, "{name}: nodal error {nodal:e}");
    let expected = voigt_strain(field);
    for (p, fields) in body.element_fields(u).unwrap().iter().enumerate() {
        // The in-plane Voigt strain [xx, yy, 2 xy] of the strain tensor.
        let strain = nalgebra::Vector3::new(
            fields.strain[(0, 0)],
            fields.strain[(1, 1)],
            2.0 * fields.strain[(0, 1)],
        );
        assert!(
            (strain - expected).norm() < 1e-10 * expected.norm(),
            "{name}: polygon {p} strain {:?}",
            fields.strain
        );
    }
    // a_h(u_h, u_h) = 2 * strain energy = a(u, u).
    let a_exact = exact_energy_norm(field, lambda, mu);
    let a_h = 2.0 * solution.strain_energy();
    assert!(
        (a_h - a_exact).abs() < 1e-10 * a_exact,
        "{name}: a_h = {a_h}, a = {a_exact}"
    );
}

#[test]
fn reference_energies_of_section_10() {
    // docs/manufactured.md section 10, lambda = 2, mu = 1.
    assert!((exact_energy_norm(&Pt0a, 2.0, 1.0) - 1.16).abs() < 1e-14);
    assert!((exact_energy_norm(&Pt0b, 2.0, 1.0) - 0.02).abs() < 1e-15);
}

#[test]
fn pt0a_dirichlet_everywhere_is_exact_on_every_mesh() {
    for (name, mesh) in meshes() {
        for (lambda, mu) in LAME_PAIRS {
            let mut builder = ElasticBody::builder("pt0a", mesh.clone(), lame(lambda, mu), vem());
            for side in ["left", "right", "bottom", "top"] {
                builder =
                    builder.dirichlet(Dirichlet::prescribed(side, Component::All, |x| Pt0a.u(x)));
            }
            let body = builder.build().unwrap();
            check_exact(
                &format!("PT0a {name} lambda={lambda}"),
                &body,
                &Pt0a,
                lambda,
                mu,
            );
        }
    }
}

#[test]
fn pt0b_tractions_are_exact_and_in_equilibrium() {
    for (name, mesh) in meshes() {
        for (lambda, mu) in LAME_PAIRS {
            let body = ElasticBody::builder("pt0b", mesh.clone(), lame(lambda, mu), vem())
                .clamp("top")
                .traction("left", move |_| Vector::new(-lambda / 20.0, mu / 10.0))
                .traction("right", move |_| Vector::new(lambda / 20.0, -mu / 10.0))
                .traction("bottom", move |_| {
                    Vector::new(mu / 10.0, -(lambda + 2.0 * mu) / 20.0)
                })
                .build()
                .unwrap();
            let name = format!("PT0b {name} lambda={lambda}");
            check_exact(&name, &body, &Pt0b, lambda, mu);
            // The clamp's reaction balances the applied tractions, and equals int sigma nu
            // over the top: (sigma_xy, sigma_yy) = (-mu/10, (lambda + 2 mu)/20).
            let solution = body.solve().unwrap();
            let applied = Vector::new(mu / 10.0, -(lambda + 2.0 * mu) / 20.0);
            let reaction = solution.reaction("top").unwrap();
            assert!(
                (reaction + applied).norm() < 1e-12,
                "{name}: reaction {reaction:?}"
            );
            let system = body.assemble().unwrap();
            let load = system.load();
            let load_sum = Vector::new(
                load.iter().step_by(2).sum::<f64>(),
                load.iter().skip(1).step_by(2).sum::<f64>(),
            );
            assert!(
                (load_sum - applied).norm() < 1e-14,
                "{name}: load {load_sum:?}"
            );
        }
    }
}
