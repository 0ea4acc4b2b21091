//! Bodies in space: the entry points of [`ElasticBody<3>`] on a polyhedral mesh.
//!
//! Everything else (degrees of freedom, assembly, Dirichlet conditions, rigid plates,
//! tractions on faces, body forces, solve, reactions, strain and stress per cell) is the
//! dimension-generic code of [`ElasticBody`].

use std::sync::Arc;

use vem_mesh::PolyhedralMesh;
use vem_space::{PolyhedralElement, SolidElement};

use crate::{ElasticBody, ElasticBodyBuilder, ElasticError, Material};

impl ElasticBody<3> {
    /// Starts a body in space named `name` on the polyhedral mesh `mesh`, discretised by the
    /// element `element` on each polyhedron (e.g. [`vem_space::PolyhedralVem`]).
    ///
    /// ```
    /// use std::sync::Arc;
    /// use vem_elastic::{ElasticBody, Material};
    /// use vem_mesh::generators::polyhedral::{hexahedra, Cuboid};
    /// use vem_mesh::Vector3;
    /// use vem_space::PolyhedralVem;
    /// // A unit cube clamped at its bottom, pulled up by a uniform traction 1 on its top.
    /// let mesh = hexahedra(&Cuboid::unit_cube(), 3, 3, 3)?;
    /// let body = ElasticBody::builder_polyhedral(
    ///     "cube",
    ///     mesh,
    ///     Material::isotropic(1000.0, 0.25)?,
    ///     Arc::new(PolyhedralVem::default()),
    /// )
    /// .clamp("bottom")
    /// .traction("top", |_| Vector3::new(0.0, 0.0, 1.0))
    /// .build()?;
    /// let solution = body.solve()?;
    /// // The clamp carries the load.
    /// let reaction = solution.reaction("bottom").unwrap();
    /// assert!((reaction + Vector3::new(0.0, 0.0, 1.0)).norm() < 1e-10);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn builder_polyhedral(
        name: impl Into<String>,
        mesh: impl Into<Arc<PolyhedralMesh>>,
        material: Material,
        element: Arc<dyn PolyhedralElement>,
    ) -> ElasticBodyBuilder<3> {
        let mesh: Arc<PolyhedralMesh> = mesh.into();
        Self::builder_on(name, mesh, material, Arc::new(SolidElement::new(element)))
    }

    /// The polyhedral mesh.
    pub fn mesh(&self) -> &PolyhedralMesh {
        self.body_mesh()
            .as_polyhedral()
            .expect("vem_mesh::PolyhedralMesh is the only BodyMesh<3>")
    }

    /// The same body (material, element, conditions) on another polyhedral mesh with the same
    /// part names; everything is checked again.
    pub fn with_polyhedral_mesh(
        &self,
        mesh: impl Into<Arc<PolyhedralMesh>>,
    ) -> Result<Self, ElasticError> {
        let mesh: Arc<PolyhedralMesh> = mesh.into();
        self.on_mesh(mesh)
    }
}
