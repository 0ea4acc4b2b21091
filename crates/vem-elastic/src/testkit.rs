//! The global patch test for any element type (cargo feature `testkit`), the assembled
//! companion of `vem_space::testkit`.
//!
//! On the unit square meshed by each [`MeshFamily`], the linear field
//! `u(x, y) = ((1 + 2x + 3y)/10, (2 - x + 4y)/10)` (PT0a of docs/manufactured.md, strain with a
//! shear part, plus a rotation) is prescribed as Dirichlet data on the whole boundary, without
//! body force. An element that passes the element-level checks reproduces `u` at every vertex
//! to round-off; [`global_patch_test`] measures by how much it misses.
//!
//! ```
//! use std::sync::Arc;
//! use vem_elastic::testkit::global_patch_test;
//! use vem_mesh::generators::MeshFamily;
//! use vem_space::LowestOrderVem;
//! let report = global_patch_test(Arc::new(LowestOrderVem::default()), MeshFamily::Hexagons)?;
//! assert!(report.nodal_error < 1e-10, "{report:?}");
//! # Ok::<(), vem_elastic::ElasticError>(())
//! ```

use std::sync::Arc;

use vem_mesh::generators::{MeshFamily, Rectangle};
use vem_mesh::{Point, Vector};
use vem_space::ElementSpace;

use crate::{Component, Dirichlet, ElasticBody, ElasticError, Material, Plane};

/// The tolerance the built-in elements meet on the relative nodal error (measured at most
/// about 1e-14, see `docs/elements.md`).
pub const DEFAULT_TOLERANCE: f64 = 1e-10;

/// The number of cells per side of the test meshes (passed to [`MeshFamily::generate`]).
pub const MESH_SIZE: usize = 5;

/// The seed of the random families.
pub const SEED: u64 = 7;

/// The exact linear displacement of the patch test (PT0a).
pub fn linear_displacement(x: Point) -> Vector {
    Vector::new(
        (1.0 + 2.0 * x.x + 3.0 * x.y) / 10.0,
        (2.0 - x.x + 4.0 * x.y) / 10.0,
    )
}

/// What the global patch test measured on one mesh.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GlobalPatchTest {
    /// The mesh family.
    pub family: MeshFamily,
    /// Number of vertices of the mesh.
    pub vertices: usize,
    /// Number of polygons of the mesh.
    pub polygons: usize,
    /// `max_v |u_h(v) - u(v)| / max_v |u(v)|` over all vertices.
    pub nodal_error: f64,
}

/// Solves the patch test with `element` on the [`MESH_SIZE`] mesh of `family` on the unit
/// square (plane strain, lambda = 2, mu = 1) and measures the relative nodal error.
///
/// Errors: those of building and solving the body; in particular
/// [`ElasticError::UnsupportedPolygon`] when the element does not support a polygon of the mesh
/// (the linear triangle on a family with quadrilaterals).
pub fn global_patch_test(
    element: Arc<dyn ElementSpace>,
    family: MeshFamily,
) -> Result<GlobalPatchTest, ElasticError> {
    let mesh = family
        .generate(&Rectangle::unit_square(), MESH_SIZE, SEED)
        .map_err(|source| ElasticError::Mesh {
            body: "patch test".into(),
            source,
        })?;
    let material = Material::from_lame(2.0, 1.0, Plane::Strain)?;
    let mut builder = ElasticBody::builder("patch test", mesh, material, element);
    for side in ["left", "right", "bottom", "top"] {
        builder = builder.dirichlet(Dirichlet::prescribed(
            side,
            Component::All,
            linear_displacement,
        ));
    }
    let body = builder.build()?;
    let solution = body.solve()?;
    let mesh = body.mesh();
    let (mut error, mut scale): (f64, f64) = (0.0, 0.0);
    for v in 0..mesh.n_vertices() {
        let exact = linear_displacement(mesh.vertex(v));
        error = error.max((solution.vertex_displacement(v) - exact).norm());
        scale = scale.max(exact.norm());
    }
    Ok(GlobalPatchTest {
        family,
        vertices: mesh.n_vertices(),
        polygons: mesh.n_polygons(),
        nodal_error: error / scale,
    })
}

/// [`global_patch_test`] on every family of [`MeshFamily::all`], in that order.
pub fn global_patch_tests(
    element: Arc<dyn ElementSpace>,
) -> Vec<(MeshFamily, Result<GlobalPatchTest, ElasticError>)> {
    MeshFamily::all()
        .into_iter()
        .map(|family| (family, global_patch_test(Arc::clone(&element), family)))
        .collect()
}
