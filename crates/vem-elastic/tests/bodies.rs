//! Body-level behaviour: floating bodies, unknown parts, conflicting data, plane stress versus
//! plane strain in uniaxial tension.

mod common;

use common::{lame, vem};
use vem_elastic::{Component, Dirichlet, ElasticBody, ElasticError, Material, Plane};
use vem_mesh::generators::{structured_quads, structured_triangles, MeshFamily, Rectangle};
use vem_mesh::{MeshError, Point, Vector};

#[test]
fn floating_body_is_a_singular_stiffness_error() {
    // No Dirichlet condition at all, and one that leaves the x-translation free. On the
    // Voronoi mesh faer accepts the round-off pivot of the sliding body (d_k / A_kk ~ 4e-15):
    // the pivot tolerance catches it.
    let square = Rectangle::unit_square();
    let quads = structured_quads(&square, 6, 6).unwrap();
    let voronoi = MeshFamily::Voronoi.generate(&square, 10, 3).unwrap();
    let mut bodies = Vec::new();
    for mesh in [quads, voronoi] {
        let free = ElasticBody::builder("floating", mesh.clone(), lame(2.0, 1.0), vem())
            .traction("right", |_| Vector::new(1.0, 0.0))
            .build()
            .unwrap();
        let sliding = ElasticBody::builder("sliding", mesh, lame(2.0, 1.0), vem())
            .dirichlet(Dirichlet::fixed("bottom", Component::Y))
            .body_force(|_| Vector::new(0.0, -1.0))
            .build()
            .unwrap();
        bodies.extend([(free, "floating"), (sliding, "sliding")]);
    }
    for (body, name) in bodies {
        let err = body.solve().unwrap_err();
        assert_eq!(
            err,
            ElasticError::SingularStiffness {
                body: name.to_string()
            }
        );
        assert_eq!(
            err.to_string(),
            format!("singular stiffness: body '{name}' is not held (no or insufficient Dirichlet condition)")
        );
    }
}

#[test]
fn unknown_part_lists_the_parts_that_exist() {
    let mesh = structured_quads(&Rectangle::unit_square(), 2, 2).unwrap();
    let err = ElasticBody::builder("plate", mesh.clone(), lame(2.0, 1.0), vem())
        .clamp("bottom")
        .traction("east", |_| Vector::new(1.0, 0.0))
        .build()
        .unwrap_err();
    match &err {
        ElasticError::Mesh {
            body,
            source: MeshError::UnknownPart { part, available },
        } => {
            assert_eq!(body, "plate");
            assert_eq!(part, "east");
            assert_eq!(available, &["left", "right", "bottom", "top"]);
        }
        other => panic!("unexpected error {other:?}"),
    }
    // The Display names the body; the cause (with the parts that exist) is the source, not
    // repeated in the Display.
    let cause = std::error::Error::source(&err).unwrap().to_string();
    assert!(err.to_string().contains("body 'plate'") && cause.contains("\"top\""));
    assert!(!err.to_string().contains(&cause), "{err}");
    let err = ElasticBody::builder("plate", mesh, lame(2.0, 1.0), vem())
        .clamp("west")
        .build()
        .unwrap_err();
    let cause = std::error::Error::source(&err).unwrap().to_string();
    assert!(cause.contains("no boundary part named 'west'"), "{cause}");
}

#[test]
fn conflicting_and_non_finite_dirichlet_data_are_errors() {
    let mesh = structured_quads(&Rectangle::unit_square(), 2, 2).unwrap();
    // The corner (0, 0) is on both parts with different prescribed x-displacements.
    let err = ElasticBody::builder("plate", mesh.clone(), lame(2.0, 1.0), vem())
        .clamp("left")
        .dirichlet(Dirichlet::prescribed("bottom", Component::X, |_| {
            Vector::new(0.1, 0.0)
        }))
        .build()
        .unwrap_err();
    assert!(
        matches!(
            err,
            ElasticError::ConflictingDirichlet {
                vertex: 0,
                component: 0,
                ..
            }
        ),
        "{err}"
    );
    let err = ElasticBody::builder("plate", mesh.clone(), lame(2.0, 1.0), vem())
        .dirichlet(Dirichlet::prescribed("left", Component::Y, |_| {
            Vector::new(0.0, f64::NAN)
        }))
        .build()
        .unwrap_err();
    assert!(
        matches!(err, ElasticError::NonFiniteDirichlet { .. }),
        "{err}"
    );
    let err = ElasticBody::builder("plate", mesh, lame(2.0, 1.0), vem())
        .clamp("left")
        .traction_points(0)
        .build()
        .unwrap_err();
    assert!(matches!(err, ElasticError::InvalidSetting { .. }), "{err}");
}

/// A bar (0, L) x (0, H) on rollers (u_x = 0 on the left, u_y = 0 on the bottom) pulled by a
/// uniform traction T on the right: a uniaxial stress state sigma_xx = T. Plane stress gives
/// eps_xx = T / E, eps_yy = -nu T / E; plane strain (eps_zz = 0) gives
/// eps_xx = (1 - nu^2) T / E, eps_yy = -nu (1 + nu) T / E. The field is linear: exact.
#[test]
fn uniaxial_tension_stretch_in_plane_stress_and_plane_strain() {
    let (length, height, e, nu, t) = (4.0, 1.0, 200.0, 0.3, 2.0);
    let rect = Rectangle::new(Point::new(0.0, 0.0), Point::new(length, height));
    for mesh in [
        structured_quads(&rect, 8, 3).unwrap(),
        structured_triangles(&rect, 5, 2).unwrap(),
    ] {
        for (plane, eps_xx, eps_yy) in [
            (Plane::Stress, t / e, -nu * t / e),
            (
                Plane::Strain,
                (1.0 - nu * nu) * t / e,
                -nu * (1.0 + nu) * t / e,
            ),
        ] {
            let material = Material::from_young_poisson(e, nu, plane).unwrap();
            let body = ElasticBody::builder("bar", mesh.clone(), material, vem())
                .dirichlet(Dirichlet::fixed("left", Component::X))
                .dirichlet(Dirichlet::fixed("bottom", Component::Y))
                .traction("right", move |_| Vector::new(t, 0.0))
                .build()
                .unwrap();
            let solution = body.solve().unwrap();
            for v in 0..body.mesh().n_vertices() {
                let x = body.mesh().vertex(v);
                let u = solution.vertex_displacement(v);
                assert!(
                    (u.x - eps_xx * x.x).abs() < 1e-12,
                    "{plane:?}: {u:?} at {x:?}"
                );
                assert!(
                    (u.y - eps_yy * x.y).abs() < 1e-12,
                    "{plane:?}: {u:?} at {x:?}"
                );
            }
            let fields = body.element_fields(solution.displacement()).unwrap();
            let sigma_zz = if plane == Plane::Strain { nu * t } else { 0.0 };
            for f in fields {
                let expected =
                    nalgebra::Matrix3::new(t, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, sigma_zz);
                assert!((f.stress - expected).norm() < 1e-10, "{}", f.stress);
                let von_mises = (t * t + sigma_zz * sigma_zz - t * sigma_zz).sqrt();
                assert!((f.von_mises - von_mises).abs() < 1e-10);
            }
            // Each roller carries the load in its own direction only.
            let left = solution.reaction("left").unwrap();
            assert!(
                (left.x + t * height).abs() < 1e-10 && left.y == 0.0,
                "{left:?}"
            );
            assert!(solution.reaction("bottom").unwrap().norm() < 1e-10);
        }
    }
}

/// The traction load is exact for polynomial tractions of degree 2 points - 2 along an edge:
/// with g = (0, y^2) on x = 1 the nodal loads must reproduce int g_y = 1/3 and the moment
/// int y g_y = 1/4 (the trace y is linear on each edge, so sum_v F_v y_v = int y g_y exactly).
#[test]
fn traction_quadrature_is_exact_for_quadratic_tractions() {
    let mesh = structured_quads(&Rectangle::unit_square(), 2, 3).unwrap();
    let moments = |points: usize| {
        let body = ElasticBody::builder("plate", mesh.clone(), lame(2.0, 1.0), vem())
            .clamp("left")
            .traction("right", |x| Vector::new(0.0, x.y * x.y))
            .traction_points(points)
            .build()
            .unwrap();
        let system = body.assemble().unwrap();
        let load = system.load();
        let (mut force, mut moment) = (0.0, 0.0);
        for v in 0..mesh.n_vertices() {
            force += load[2 * v + 1];
            moment += load[2 * v + 1] * mesh.vertex(v).y;
            assert_eq!(load[2 * v], 0.0);
        }
        (force, moment)
    };
    let (force, moment) = moments(2);
    assert!((force - 1.0 / 3.0).abs() < 1e-15 && (moment - 0.25).abs() < 1e-15);
    // The one-point (midpoint) rule misses the quadratic: sum h y_mid^2 = 35/108.
    let (force, _) = moments(1);
    assert!((force - 35.0 / 108.0).abs() < 1e-15, "{force}");
}

/// `with_mesh` keeps material, element and conditions and checks them on the new mesh.
#[test]
fn with_mesh_rebuilds_the_body_on_another_mesh() {
    let square = Rectangle::unit_square();
    let body = ElasticBody::builder(
        "plate",
        structured_quads(&square, 3, 3).unwrap(),
        lame(2.0, 1.0),
        vem(),
    )
    .clamp("top")
    .traction("right", |x| Vector::new(x.y, 0.0))
    .body_force(|_| Vector::new(0.0, -1.0))
    .build()
    .unwrap();
    let fine = structured_quads(&square, 6, 6).unwrap();
    let moved = body.with_mesh(fine.clone()).unwrap();
    let direct = ElasticBody::builder("plate", fine.clone(), lame(2.0, 1.0), vem())
        .clamp("top")
        .traction("right", |x| Vector::new(x.y, 0.0))
        .body_force(|_| Vector::new(0.0, -1.0))
        .build()
        .unwrap();
    assert_eq!(moved.dofs(), direct.dofs());
    assert_eq!(
        moved.solve().unwrap().displacement(),
        direct.solve().unwrap().displacement()
    );
    // The same polygons without named parts: the conditions cannot be placed.
    let unnamed = vem_mesh::Mesh::from_compact(
        fine.vertices().to_vec(),
        fine.polygon_offsets().to_vec(),
        fine.polygon_vertex_indices().to_vec(),
        vec![],
    )
    .unwrap();
    let err = body.with_mesh(unnamed).unwrap_err();
    assert!(
        matches!(&err, ElasticError::Mesh { source: MeshError::UnknownPart { available, .. }, .. } if available.is_empty()),
        "{err}"
    );
}

/// A 4 x 5 grid of quads on `[0, 1] x [0, 1 + h]` whose middle row has height `h`; parts
/// "bottom" and "top".
fn thin_row_mesh(h: f64) -> vem_mesh::Mesh {
    let ys = [0.0, 0.25, 0.5, 0.5 + h, 0.75 + h, 1.0 + h];
    let mut vertices = Vec::new();
    for &y in &ys {
        for i in 0..5 {
            vertices.push(Point::new(0.25 * i as f64, y));
        }
    }
    let id = |i: usize, j: usize| 5 * j + i;
    let mut polygons = Vec::new();
    for j in 0..ys.len() - 1 {
        for i in 0..4 {
            polygons.push(vec![id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    let top = ys.len() - 1;
    let parts = vec![
        vem_mesh::PartSpec::new("bottom", (0..4).map(|i| [id(i, 0), id(i + 1, 0)]).collect()),
        vem_mesh::PartSpec::new(
            "top",
            (0..4).map(|i| [id(i, top), id(i + 1, top)]).collect(),
        ),
    ];
    vem_mesh::Mesh::from_polygons(vertices, &polygons, parts).unwrap()
}

#[test]
fn a_held_body_with_needle_cells_solves() {
    // A row of cells of aspect ratio 0.25 / h = 2e9 and 4e9 across the body: the body is
    // held, so it must solve (or report ill-conditioning), not claim it is floating. The
    // reaction balances the load (conservation) to the accuracy the conditioning allows.
    for h in [1.25e-10, 6.25e-11] {
        let body = ElasticBody::builder("needles", thin_row_mesh(h), lame(2.0, 1.0), vem())
            .clamp("bottom")
            .traction("top", |_| Vector::new(0.3, -1.0))
            .build()
            .unwrap();
        assert!(body.holds_rigid_motions());
        // The default pivot tolerance refuses the factorisation at 4e9 (smallest relative
        // pivot 1.07e-9 at 2e9)...
        let mut strict = vem_elastic::CholeskySolver::default();
        let system = body.assemble().unwrap();
        use vem_elastic::LinearSolver;
        strict.analyse(system.stiffness().symbolic()).unwrap();
        let strict_result = strict.factorise(system.stiffness().as_ref());
        assert_eq!(strict_result.is_err(), h < 1e-10);
        // ... and the body solves all the same.
        let solution = body.solve().unwrap_or_else(|e| panic!("h = {h:e}: {e}"));
        let reaction = solution.reaction("bottom").unwrap();
        assert!((reaction.x + 0.3).abs() < 1e-6, "{reaction:?}");
        assert!((reaction.y - 1.0).abs() < 1e-6, "{reaction:?}");
    }
}

#[test]
fn rigid_motions_left_free_are_detected() {
    let square = Rectangle::unit_square();
    let mesh = structured_quads(&square, 3, 3).unwrap();
    let build = |conditions: Vec<Dirichlet>| {
        let mut b = ElasticBody::builder("b", mesh.clone(), lame(2.0, 1.0), vem());
        for c in conditions {
            b = b.dirichlet(c);
        }
        b.build().unwrap().holds_rigid_motions()
    };
    // Clamped bottom, or y on the bottom and x on the left side, hold all three rigid motions.
    assert!(build(vec![Dirichlet::fixed("bottom", Component::All)]));
    assert!(build(vec![
        Dirichlet::fixed("bottom", Component::Y),
        Dirichlet::fixed("left", Component::X),
    ]));
    assert!(!build(vec![]));
    assert!(!build(vec![Dirichlet::fixed("bottom", Component::Y)]));
    // x fixed along a vertical line only: the y translation is free.
    assert!(!build(vec![Dirichlet::fixed("left", Component::X)]));
}
