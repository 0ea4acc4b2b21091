//! Meshes generated on a polygon (vem-mesh `polygon_mesh`: a family's mesh of the bounding
//! rectangle cut by the polygon, or for Voronoi the seeds' cells with reflected seeds) carry the
//! element's guarantees: the linear patch test PT0a is exact on the L-shaped domain for every
//! family, and the energy error of the manufactured solution E1 restricted to the L-shape falls
//! like h (docs/scenes.md, section 3, "Mesh": a generated mesh on a polygon).

mod common;

use common::{fitted_rate, lame, nodal_error, projection_errors, vem, ExactField, Pt0a, E1};
use vem_elastic::{Component, Dirichlet, ElasticBody};
use vem_mesh::generators::{polygon_mesh, MeshFamily, PolygonDomain};
use vem_mesh::{Mesh, Point, Vector};

/// The L-shape (0, 1)^2 without [0.5, 1]^2, all its edges one part "rim".
fn l_shape() -> PolygonDomain {
    let xy = [
        [0.0, 0.0],
        [1.0, 0.0],
        [1.0, 0.5],
        [0.5, 0.5],
        [0.5, 1.0],
        [0.0, 1.0],
    ];
    PolygonDomain::new(xy.iter().map(|p| Point::new(p[0], p[1])).collect())
        .unwrap()
        .with_edge_names(&["rim"; 6])
        .unwrap()
}

/// The body on `mesh` held at `u` on its whole boundary.
fn held_at(
    mesh: Mesh,
    u: impl Fn(Point) -> Vector + Send + Sync + 'static,
    lambda: f64,
    mu: f64,
) -> vem_elastic::ElasticBodyBuilder {
    ElasticBody::builder("l", mesh, lame(lambda, mu), vem()).dirichlet(Dirichlet::prescribed(
        "rim",
        Component::All,
        u,
    ))
}

#[test]
fn pt0a_is_exact_on_the_l_shape_for_every_family() {
    for family in MeshFamily::all() {
        for n in [5, 12] {
            let mesh = polygon_mesh(&l_shape(), family, n, 7).unwrap();
            let body = held_at(mesh, |x| Pt0a.u(x), 2.0, 1.0).build().unwrap();
            let solution = body.solve().unwrap();
            let error = nodal_error(body.mesh(), solution.displacement(), &Pt0a);
            assert!(error < 1e-10, "{family} n = {n}: nodal error {error:e}");
        }
    }
}

/// E1 (smooth) on the L-shape, held at its trace on the whole boundary: the broken H1 error
/// of the projection falls like h (fitted over n = 8, 16, 32 of the bounding square).
#[test]
fn e1_energy_error_on_the_l_shape_falls_like_h() {
    let (lambda, mu) = (1.0, 1.0);
    for family in [MeshFamily::Voronoi, MeshFamily::Hexagons, MeshFamily::Quads] {
        let (mut h, mut grad) = (Vec::new(), Vec::new());
        for n in [8, 16, 32] {
            let mesh = polygon_mesh(&l_shape(), family, n, 11).unwrap();
            let cells = mesh.n_polygons();
            let body = held_at(mesh, |x| E1.u(x), lambda, mu)
                .body_force(E1::force(lambda, mu))
                .build()
                .unwrap();
            let solution = body.solve().unwrap();
            let errors = projection_errors(&body, solution.displacement(), &E1);
            // The mean cell size sqrt(|Omega| / #cells), |Omega| = 0.75.
            h.push((0.75 / cells as f64).sqrt());
            grad.push(errors.grad);
        }
        let rate = fitted_rate(&h, &grad);
        eprintln!("{family}: h {h:.4?} |grad error| {grad:.4?} rate {rate:.3}");
        assert!((0.9..1.3).contains(&rate), "{family}: rate {rate}");
    }
}
