//! The element seam seen from the assembly: the global patch test of the test kit for every
//! registered element on every mesh family, and the early, named failure of an element that
//! does not support a polygon (a quadrilateral, or a triangle that gained a vertex by interface
//! node insertion).

use std::error::Error;
use std::sync::Arc;

use vem_elastic::testkit::{global_patch_tests, DEFAULT_TOLERANCE};
use vem_elastic::{ElasticBody, ElasticError, Material, Plane};
use vem_mesh::generators::{structured_quads, structured_triangles, Rectangle};
use vem_mesh::interface::{insert_interface_nodes, InterfaceOptions};
use vem_mesh::Point;
use vem_space::{ElementRegistry, ElementSpace, LinearTriangle};

fn material() -> Material {
    Material::from_lame(2.0, 1.0, Plane::Strain).unwrap()
}

#[test]
fn every_registered_element_passes_the_global_patch_test_where_it_applies() {
    let registry = ElementRegistry::builtin();
    let mut worst: f64 = 0.0;
    for name in registry.names() {
        let element = registry.make(name).unwrap();
        for (family, result) in global_patch_tests(Arc::clone(&element)) {
            match result {
                Ok(report) => {
                    assert!(
                        report.nodal_error < DEFAULT_TOLERANCE,
                        "{name} on {family}: {report:?}"
                    );
                    worst = worst.max(report.nodal_error);
                }
                // Only the linear triangle may refuse a family, and only one with a polygon
                // that is not a triangle.
                Err(ElasticError::UnsupportedPolygon {
                    element, vertices, ..
                }) => {
                    assert_eq!(element, "p1", "{name} on {family}");
                    assert_ne!(vertices, 3);
                }
                Err(e) => panic!("{name} on {family}: {e}"),
            }
        }
    }
    println!("worst relative nodal error of the global patch test: {worst:e}");
}

#[test]
fn a_p1_body_on_a_mesh_with_a_quadrilateral_fails_before_assembly() {
    let mesh = structured_quads(&Rectangle::unit_square(), 2, 1).unwrap();
    let err = ElasticBody::builder("plate", mesh, material(), Arc::new(LinearTriangle))
        .clamp("left")
        .build()
        .unwrap_err();
    assert_eq!(
        err,
        ElasticError::UnsupportedPolygon {
            body: "plate".into(),
            element: "p1".into(),
            polygon: 0,
            vertices: 4,
        }
    );
    assert_eq!(
        err.to_string(),
        "body 'plate': element 'p1' does not support polygon 0 with 4 vertices"
    );
}

#[test]
fn a_p1_triangle_mesh_fails_after_a_vertex_insertion() {
    // Two triangle meshes facing at y = 0 with 2 and 3 cells: insertion adds vertices to the
    // triangles along the interface, which the linear triangle cannot take.
    let upper = structured_triangles(
        &Rectangle::new(Point::new(0.0, 0.0), Point::new(1.0, 1.0)),
        2,
        2,
    )
    .unwrap();
    let lower = structured_triangles(
        &Rectangle::new(Point::new(0.0, -1.0), Point::new(1.0, 0.0)),
        3,
        3,
    )
    .unwrap();
    let body = ElasticBody::builder("upper", upper.clone(), material(), Arc::new(LinearTriangle))
        .clamp("top")
        .build()
        .unwrap();
    let interface = insert_interface_nodes(
        &upper,
        "bottom",
        &lower,
        "top",
        &InterfaceOptions::default(),
    )
    .unwrap();
    assert!(interface.inserted_a > 0);
    let err = body.with_mesh(interface.mesh_a.clone()).unwrap_err();
    let ElasticError::UnsupportedPolygon {
        body: name,
        element,
        polygon,
        vertices,
    } = &err
    else {
        panic!("{err}");
    };
    assert_eq!((name.as_str(), element.as_str()), ("upper", "p1"));
    assert_eq!(*vertices, 4);
    assert_eq!(interface.mesh_a.polygon(*polygon).len(), 4);
    // The first polygon with more than three vertices is the one named.
    let first = (0..interface.mesh_a.n_polygons())
        .find(|&p| interface.mesh_a.polygon(p).len() != 3)
        .unwrap();
    assert_eq!(*polygon, first);
    // The lowest-order VEM takes the same mesh.
    let vem: Arc<dyn ElementSpace> = ElementRegistry::builtin().make("vem1").unwrap();
    let body = ElasticBody::builder("upper", upper, material(), vem)
        .clamp("top")
        .build()
        .unwrap();
    assert!(body.with_mesh(interface.mesh_a).is_ok());
}

#[test]
fn errors_name_the_place_and_leave_the_cause_to_the_source() {
    // An element failure: the Display names body and polygon, source() carries the cause, and
    // the cause's text is not repeated.
    let mesh = structured_quads(&Rectangle::unit_square(), 1, 1).unwrap();
    let body = ElasticBody::builder("plate", mesh, material(), Arc::new(Nan))
        .clamp("left")
        .build()
        .unwrap();
    let err = body.assemble().unwrap_err();
    assert!(
        matches!(err, ElasticError::Element { polygon: 0, .. }),
        "{err}"
    );
    let source = err.source().expect("the element error").to_string();
    assert!(!err.to_string().contains(&source), "{err} repeats {source}");
    assert!(err.to_string().contains("body 'plate', polygon 0"), "{err}");
}

/// An element whose every call fails.
struct Nan;

impl ElementSpace for Nan {
    fn name(&self) -> &str {
        "nan"
    }

    fn stiffness(
        &self,
        polygon: &[Point],
        _material: &vem_space::ElasticityTensor,
    ) -> Result<vem_space::LocalStiffness, vem_space::SpaceError> {
        Err(vem_space::SpaceError::UnsupportedPolygon {
            element: "nan".into(),
            vertices: polygon.len(),
        })
    }

    fn projection(
        &self,
        polygon: &[Point],
    ) -> Result<vem_space::EnergyProjection, vem_space::SpaceError> {
        Err(vem_space::SpaceError::UnsupportedPolygon {
            element: "nan".into(),
            vertices: polygon.len(),
        })
    }

    fn body_load(
        &self,
        polygon: &[Point],
        _body_force: &(dyn Fn(Point) -> vem_mesh::Vector + Sync),
    ) -> Result<nalgebra::DVector<f64>, vem_space::SpaceError> {
        Ok(nalgebra::DVector::zeros(2 * polygon.len()))
    }
}
