//! Elements on polyhedra: the three-dimensional counterpart of [`crate::ElementSpace`].
//!
//! [`PolyhedralElement`] is what an element type implements on one polyhedron
//! ([`vem_mesh::polyhedral::geometry::Polyhedron`]: its vertices and its faces as outward loops
//! of local vertex indices); [`SolidElement`] makes every one of them a
//! [`MeshElement<3>`](crate::MeshElement) for the layers above, as [`crate::PlanarElement`]
//! does in 2D. The local degrees of freedom are the three displacement values at each vertex,
//! interleaved by component, `[u_x(x_0), u_y(x_0), u_z(x_0), u_x(x_1), ...]`, in the order of
//! the polyhedron's vertices (for a cell of a [`vem_mesh::PolyhedralMesh`]: its
//! [`cell_vertices`](vem_mesh::PolyhedralMesh::cell_vertices), increasing).
//!
//! Tractions on a boundary face are integrated against the trace of the element's functions,
//! which for every element here is the *fan trace*: linear on each fan triangle
//! `(x_k, x_{k+1}, xbar_F)` with the mean of the vertex values at the fan centre `xbar_F`
//! ([`face_traction_load`]). Its weights are those of the face geometry
//! ([`vem_mesh::polyhedral::geometry::face_vertex_weights`]), so a constant traction on a planar
//! face gives exactly the boundary term of the consistency condition: the patch test holds.

use std::fmt;
use std::sync::Arc;

use nalgebra::{DVector, SMatrix};
use vem_mesh::polyhedral::geometry::{self, Polyhedron};
use vem_mesh::{BodyMesh, Point3, PointD, Vector3};

use crate::quadrature::{conical_triangle_rule, face_rule};
use crate::{
    DofLayout, ElasticityTensor, EnergyProjection, FieldOf, LocalStiffness, MeshElement, SpaceError,
};

/// A body force or traction in space.
pub type SpaceField<'a> = &'a (dyn Fn(Point3) -> Vector3 + Sync);

/// A local element space on one polyhedron: what a contributor implements to add a
/// three-dimensional element type (the counterpart of [`crate::ElementSpace`]).
///
/// Implementations must be thread-safe: assembly calls them from many threads at once.
pub trait PolyhedralElement: Send + Sync {
    /// A short name for reports ("vem1", "p1", ...).
    fn name(&self) -> &str;

    /// Whether the element can be built on `polyhedron` (default: any).
    fn supports(&self, polyhedron: &Polyhedron) -> bool {
        let _ = polyhedron;
        true
    }

    /// The local stiffness of `polyhedron` (faces oriented outward) for the material
    /// `material`, split into consistency and stabilisation, `3n x 3n`.
    fn stiffness(
        &self,
        polyhedron: &Polyhedron,
        material: &ElasticityTensor<3>,
    ) -> Result<LocalStiffness, SpaceError>;

    /// The energy projection `Pi: V_h(E) -> P1(E)^3` as a linear map of the local degrees of
    /// freedom (12 x 3n), for post-processing (strain, stress, error norms).
    fn projection(&self, polyhedron: &Polyhedron) -> Result<EnergyProjection<3>, SpaceError>;

    /// The local degrees of freedom (default: the three displacement values at each vertex).
    fn dof_layout(&self) -> DofLayout {
        DofLayout::vertex_values(3)
    }

    /// The local load vector of a body force `force` (per unit volume), length `3n`.
    fn body_load(
        &self,
        polyhedron: &Polyhedron,
        force: SpaceField<'_>,
    ) -> Result<DVector<f64>, SpaceError>;

    /// The load of a traction on the boundary face `face` (its vertices in loop order), on the
    /// face's vertex values (default: [`face_traction_load`], the fan trace).
    fn face_load(
        &self,
        face: &[Point3],
        traction: SpaceField<'_>,
        points: usize,
    ) -> Result<DVector<f64>, SpaceError> {
        face_traction_load(face, traction, points)
    }
}

/// The load `int_F g . phi_a dS` of a traction `g` on the face `face` (a vertex loop in space,
/// planar or warped), for the fan trace `phi_a` of every vertex (module docs): each fan triangle
/// by the conical product of `points + 1` Gauss–Legendre points (at most 6), exact for a
/// traction that is a polynomial of degree `<= 2 min(points + 1, 6) - 3` on a planar face (the
/// integrand has one degree more). Returns `3n` values interleaved by component.
///
/// Errors: fewer than three vertices, a non-finite vertex, a face of zero area, an
/// unsupported number of points, a non-finite traction value.
///
/// ```
/// use vem_mesh::{Point3, Vector3};
/// use vem_space::face_traction_load;
/// // A constant traction (0, 0, -2) on the unit square: each corner receives a quarter.
/// let square = [
///     Point3::new(0.0, 0.0, 1.0), Point3::new(1.0, 0.0, 1.0),
///     Point3::new(1.0, 1.0, 1.0), Point3::new(0.0, 1.0, 1.0),
/// ];
/// let load = face_traction_load(&square, &|_| Vector3::new(0.0, 0.0, -2.0), 2)?;
/// for a in 0..4 {
///     assert!((load[3 * a + 2] + 0.5).abs() < 1e-15);
/// }
/// # Ok::<(), vem_space::SpaceError>(())
/// ```
pub fn face_traction_load(
    face: &[Point3],
    traction: SpaceField<'_>,
    points: usize,
) -> Result<DVector<f64>, SpaceError> {
    let n = face.len();
    let degenerate = |reason: String| SpaceError::DegenerateFace {
        vertices: n,
        reason,
    };
    if n < 3 {
        return Err(degenerate("a face needs at least 3 vertices".into()));
    }
    if let Some((k, p)) = face
        .iter()
        .enumerate()
        .find(|(_, p)| !p.coords.iter().all(|c| c.is_finite()))
    {
        return Err(degenerate(format!(
            "vertex {k} has non-finite coordinates ({}, {}, {})",
            p.x, p.y, p.z
        )));
    }
    let area = geometry::face_area(face);
    let diameter = geometry::diameter(face);
    if !(area.is_finite() && area > 1e-14 * diameter * diameter) {
        return Err(degenerate(format!(
            "area {area:e} is zero for diameter {diameter:e}"
        )));
    }
    crate::quadrature::GaussLegendre::try_new(points)?;
    let rule =
        conical_triangle_rule((points + 1).min(crate::quadrature::GaussLegendre::MAX_POINTS))?;
    let mut load = DVector::zeros(3 * n);
    let mean_weight = 1.0 / n as f64;
    for (k, l, q) in face_rule(face, &rule) {
        let g = traction(q.point);
        if !g.iter().all(|c| c.is_finite()) {
            return Err(SpaceError::NonFiniteLoadInSpace {
                x: q.point.x,
                y: q.point.y,
                z: q.point.z,
            });
        }
        // Fan trace: l_k at x_k, l_{k+1} at x_{k+1}, and l_mean spread as 1/n on every vertex.
        let next = (k + 1) % n;
        for a in 0..n {
            let mut phi = l[2] * mean_weight;
            if a == k {
                phi += l[0];
            }
            if a == next {
                phi += l[1];
            }
            if phi != 0.0 {
                for c in 0..3 {
                    load[3 * a + c] += q.weight * phi * g[c];
                }
            }
        }
    }
    Ok(load)
}

/// A [`PolyhedralElement`] on the cells of a polyhedral mesh: the [`MeshElement<3>`] of every
/// three-dimensional element type (as [`crate::PlanarElement`] is in 2D).
///
/// ```
/// use std::sync::Arc;
/// use vem_space::{MeshElement, PolyhedralVem, SolidElement};
/// let element = SolidElement::new(Arc::new(PolyhedralVem::default()));
/// assert_eq!(MeshElement::<3>::name(&element), "vem1");
/// assert!(element.as_polyhedral().is_some());
/// ```
#[derive(Clone)]
pub struct SolidElement(Arc<dyn PolyhedralElement>);

impl SolidElement {
    /// The element `element` on polyhedral meshes.
    pub fn new(element: Arc<dyn PolyhedralElement>) -> Self {
        Self(element)
    }

    /// The polyhedral element.
    pub fn element(&self) -> &Arc<dyn PolyhedralElement> {
        &self.0
    }

    /// Cell `cell` of `mesh` as a polyhedron.
    fn polyhedron(mesh: &dyn BodyMesh<3>, cell: usize) -> Result<Polyhedron, SpaceError> {
        match mesh.as_polyhedral() {
            Some(mesh) => Ok(mesh.cell_polyhedron(cell)),
            None => Err(SpaceError::DegeneratePolyhedron {
                vertices: mesh.cell_vertices(cell).len(),
                faces: 0,
                reason: "the mesh does not describe the faces of its cells".into(),
            }),
        }
    }
}

impl fmt::Debug for SolidElement {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_tuple("SolidElement").field(&self.0.name()).finish()
    }
}

impl MeshElement<3> for SolidElement {
    fn name(&self) -> &str {
        self.0.name()
    }

    fn dof_layout(&self) -> DofLayout {
        self.0.dof_layout()
    }

    fn supports(&self, mesh: &dyn BodyMesh<3>, cell: usize) -> bool {
        Self::polyhedron(mesh, cell).is_ok_and(|p| self.0.supports(&p))
    }

    fn stiffness(
        &self,
        mesh: &dyn BodyMesh<3>,
        cell: usize,
        material: &ElasticityTensor<3>,
    ) -> Result<LocalStiffness, SpaceError> {
        self.0.stiffness(&Self::polyhedron(mesh, cell)?, material)
    }

    fn body_load(
        &self,
        mesh: &dyn BodyMesh<3>,
        cell: usize,
        force: FieldOf<'_, 3>,
    ) -> Result<DVector<f64>, SpaceError> {
        self.0
            .body_load(&Self::polyhedron(mesh, cell)?, &|x| force(x))
    }

    fn facet_load(
        &self,
        facet: &[PointD<3>],
        traction: FieldOf<'_, 3>,
        points: usize,
    ) -> Result<DVector<f64>, SpaceError> {
        self.0.face_load(facet, &|x| traction(x), points)
    }

    fn strain(
        &self,
        mesh: &dyn BodyMesh<3>,
        cell: usize,
        local: &DVector<f64>,
    ) -> Result<SMatrix<f64, 3, 3>, SpaceError> {
        let projection = self.0.projection(&Self::polyhedron(mesh, cell)?)?;
        let g = projection.gradient(local);
        Ok((g + g.transpose()) * 0.5)
    }

    fn as_polyhedral(&self) -> Option<&dyn PolyhedralElement> {
        Some(&*self.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_fan_trace_load_of_a_constant_traction_is_the_face_weight() {
        // An L-shaped face, non-convex: the load of a constant g is g (x) the scalar weights
        // of face_vertex_weights (their normal components).
        let l = [
            Point3::new(0.0, 0.0, 1.0),
            Point3::new(2.0, 0.0, 1.0),
            Point3::new(2.0, 1.0, 1.0),
            Point3::new(1.0, 1.0, 1.0),
            Point3::new(1.0, 2.0, 1.0),
            Point3::new(0.0, 2.0, 1.0),
        ];
        let g = Vector3::new(0.3, -1.0, 2.0);
        let weights = geometry::face_vertex_weights(&l);
        for points in 1..=6 {
            let load = face_traction_load(&l, &|_| g, points).unwrap();
            for (a, w) in weights.iter().enumerate() {
                for c in 0..3 {
                    assert!((load[3 * a + c] - g[c] * w.z).abs() < 1e-14, "{points}");
                }
            }
        }
        // A linear traction on the face: the total is int_F g = |F| g(centroid).
        let linear = |x: Point3| Vector3::new(x.x, x.y - 2.0 * x.x, 1.0);
        let load = face_traction_load(&l, &linear, 2).unwrap();
        let centroid = geometry::face_centroid(&l);
        for c in 0..3 {
            let total: f64 = (0..6).map(|a| load[3 * a + c]).sum();
            assert!((total - 3.0 * linear(centroid)[c]).abs() < 1e-13, "{c}");
        }
    }

    #[test]
    fn degenerate_faces_and_loads_are_errors() {
        let line = [
            Point3::origin(),
            Point3::new(1.0, 0.0, 0.0),
            Point3::new(2.0, 0.0, 0.0),
        ];
        let err = face_traction_load(&line, &|_| Vector3::zeros(), 2).unwrap_err();
        assert!(err.to_string().contains("area 0"), "{err}");
        let triangle = [
            Point3::origin(),
            Point3::new(1.0, 0.0, 0.0),
            Point3::new(0.0, 1.0, 0.0),
        ];
        let err =
            face_traction_load(&triangle, &|_| Vector3::new(f64::NAN, 0.0, 0.0), 2).unwrap_err();
        assert!(
            matches!(err, SpaceError::NonFiniteLoadInSpace { .. }),
            "{err}"
        );
        let err = face_traction_load(&triangle, &|_| Vector3::zeros(), 0).unwrap_err();
        assert!(
            matches!(err, SpaceError::UnsupportedQuadrature { .. }),
            "{err}"
        );
    }
}
