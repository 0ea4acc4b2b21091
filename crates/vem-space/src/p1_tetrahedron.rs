//! The classical linear tetrahedron (P1 finite element), written independently of the VEM code
//! so that the equivalence "VEM on a tetrahedron = P1" is tested, not assumed.

use nalgebra::{DMatrix, DVector, Matrix3};
use vem_mesh::polyhedral::geometry::Polyhedron;
use vem_mesh::{Point3, Vector3};

use crate::quadrature::TetrahedronRule;
use crate::{
    ElasticityTensor, EnergyProjection, LocalStiffness, PolyhedralElement, SpaceError, SpaceField,
};

/// The linear tetrahedron ("p1"): barycentric gradients from the inverse of the edge matrix
/// `A = [x_1 - x_0, x_2 - x_0, x_3 - x_0]` (`grad lambda_i` is row `i` of `A^-1`,
/// `grad lambda_0 = -sum`), `K = V B^T C B` with the textbook 6 x 12 strain matrix, no
/// stabilisation, and the consistent load `int_T f lambda_a` by the degree-5 conical rule. It
/// supports polyhedra with four vertices and four triangular faces, in any vertex order.
///
/// ```
/// use vem_mesh::polyhedral::geometry::Polyhedron;
/// use vem_mesh::Point3;
/// use vem_space::{ElasticityTensor, LinearTetrahedron, PolyhedralElement};
/// let points = vec![
///     Point3::new(0.0, 0.0, 0.0), Point3::new(1.0, 0.0, 0.0),
///     Point3::new(0.0, 1.0, 0.0), Point3::new(0.0, 0.0, 1.0),
/// ];
/// let faces = vec![vec![0, 2, 1], vec![0, 1, 3], vec![0, 3, 2], vec![1, 2, 3]];
/// let tetrahedron = Polyhedron::new(points, &faces);
/// let c = ElasticityTensor::<3>::try_from_voigt_matrix(&nalgebra::DMatrix::identity(6, 6))?;
/// let k = LinearTetrahedron.stiffness(&tetrahedron, &c)?;
/// assert_eq!(k.stabilisation.norm(), 0.0);
/// # Ok::<(), vem_space::SpaceError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct LinearTetrahedron;

/// The checked corners of a tetrahedron, its volume and the barycentric gradients.
struct Tetrahedron {
    corners: [Point3; 4],
    volume: f64,
    gradients: [Vector3; 4],
}

impl Tetrahedron {
    fn new(polyhedron: &Polyhedron) -> Result<Self, SpaceError> {
        let unsupported = || SpaceError::UnsupportedPolyhedron {
            element: "p1".into(),
            vertices: polyhedron.points().len(),
            faces: polyhedron.n_faces(),
        };
        let corners: [Point3; 4] = polyhedron.points().try_into().map_err(|_| unsupported())?;
        if polyhedron.n_faces() != 4 || polyhedron.faces().any(|f| f.len() != 3) {
            return Err(unsupported());
        }
        let degenerate = |reason: String| SpaceError::DegeneratePolyhedron {
            vertices: 4,
            faces: 4,
            reason,
        };
        // The faces must bound the tetrahedron outward: their signed volume is the volume.
        let oriented = polyhedron.volume();
        let a = Matrix3::from_columns(&[
            corners[1] - corners[0],
            corners[2] - corners[0],
            corners[3] - corners[0],
        ]);
        let volume = a.determinant().abs() / 6.0;
        let scale = (0..4)
            .flat_map(|i| (i + 1..4).map(move |j| (i, j)))
            .map(|(i, j)| (corners[i] - corners[j]).norm())
            .fold(0.0, f64::max);
        if !(volume.is_finite() && volume > 1e-13 * scale.powi(3)) {
            return Err(degenerate(format!(
                "volume {volume:e} is not positive for diameter {scale:e}"
            )));
        }
        if !(oriented.is_finite() && (oriented - volume).abs() <= 1e-10 * volume) {
            return Err(degenerate(format!(
                "the faces are not oriented outward (their signed volume is {oriented:e}, the \
                 corners span {volume:e})"
            )));
        }
        let inverse = a.try_inverse().ok_or_else(|| degenerate("flat".into()))?;
        let row = |i: usize| Vector3::new(inverse[(i, 0)], inverse[(i, 1)], inverse[(i, 2)]);
        let (g1, g2, g3) = (row(0), row(1), row(2));
        Ok(Self {
            corners,
            volume,
            gradients: [-(g1 + g2 + g3), g1, g2, g3],
        })
    }

    /// The 6 x 12 strain matrix `[xx, yy, zz, 2 yz, 2 xz, 2 xy]`.
    fn strain_matrix(&self) -> DMatrix<f64> {
        let mut b = DMatrix::zeros(6, 12);
        for (a, g) in self.gradients.iter().enumerate() {
            let (x, y, z) = (3 * a, 3 * a + 1, 3 * a + 2);
            b[(0, x)] = g.x;
            b[(1, y)] = g.y;
            b[(2, z)] = g.z;
            b[(3, y)] = g.z;
            b[(3, z)] = g.y;
            b[(4, x)] = g.z;
            b[(4, z)] = g.x;
            b[(5, x)] = g.y;
            b[(5, y)] = g.x;
        }
        b
    }
}

impl PolyhedralElement for LinearTetrahedron {
    fn name(&self) -> &str {
        "p1"
    }

    /// Tetrahedra: four vertices, four triangular faces.
    fn supports(&self, polyhedron: &Polyhedron) -> bool {
        polyhedron.points().len() == 4
            && polyhedron.n_faces() == 4
            && polyhedron.faces().all(|f| f.len() == 3)
    }

    fn stiffness(
        &self,
        polyhedron: &Polyhedron,
        material: &ElasticityTensor<3>,
    ) -> Result<LocalStiffness, SpaceError> {
        let tetrahedron = Tetrahedron::new(polyhedron)?;
        let b = tetrahedron.strain_matrix();
        let k = b.transpose() * material.voigt_matrix() * &b * tetrahedron.volume;
        Ok(LocalStiffness {
            consistency: (&k + k.transpose()) * 0.5,
            stabilisation: DMatrix::zeros(12, 12),
        })
    }

    /// The field itself, expanded about the vertex mean (the centroid).
    fn projection(&self, polyhedron: &Polyhedron) -> Result<EnergyProjection<3>, SpaceError> {
        let tetrahedron = Tetrahedron::new(polyhedron)?;
        let mut c = DMatrix::zeros(12, 12);
        for (a, g) in tetrahedron.gradients.iter().enumerate() {
            for i in 0..3 {
                c[(i, 3 * a + i)] = 0.25;
                for j in 0..3 {
                    c[(3 + 3 * i + j, 3 * a + i)] = g[j];
                }
            }
        }
        let sum = tetrahedron
            .corners
            .iter()
            .fold(Vector3::zeros(), |s, p| s + p.coords);
        Ok(EnergyProjection {
            reference: Point3::from(sum / 4.0),
            coefficients: c,
        })
    }

    fn body_load(
        &self,
        polyhedron: &Polyhedron,
        force: SpaceField<'_>,
    ) -> Result<DVector<f64>, SpaceError> {
        let tetrahedron = Tetrahedron::new(polyhedron)?;
        let [p0, p1, p2, p3] = tetrahedron.corners;
        let rule = TetrahedronRule::conical(4)?;
        let mut load = DVector::zeros(12);
        for &(lambda, weight) in rule.barycentric() {
            let point = Point3::from(
                lambda[0] * p0.coords
                    + lambda[1] * p1.coords
                    + lambda[2] * p2.coords
                    + lambda[3] * p3.coords,
            );
            let f = force(point);
            if !f.iter().all(|c| c.is_finite()) {
                return Err(SpaceError::NonFiniteLoadInSpace {
                    x: point.x,
                    y: point.y,
                    z: point.z,
                });
            }
            for (a, l) in lambda.iter().enumerate() {
                let w = weight * tetrahedron.volume * l;
                for c in 0..3 {
                    load[3 * a + c] += w * f[c];
                }
            }
        }
        Ok(load)
    }
}
