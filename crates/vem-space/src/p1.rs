//! The classical linear triangle (P1 finite element), written independently of the VEM code so
//! that the equivalence "VEM on a triangle = P1" is tested, not assumed.

use nalgebra::{DMatrix, DVector, Matrix3, SMatrix};

use crate::quadrature::TriangleRule;
use crate::{
    ElasticityTensor, ElementSpace, EnergyProjection, LocalStiffness, Point, SpaceError, Vector,
};

/// The linear triangle ("p1"): `K = A B^T C B` with the textbook strain matrix
/// `B = 1/(2A) [b_i 0; 0 c_i; c_i b_i]`, `b_i = y_j - y_k`, `c_i = x_k - x_j` (`(i, j, k)` cyclic),
/// no stabilisation, and the consistent load `int_T f phi_i` by the degree-5 rule (exact for `f`
/// of degree <= 4; for a constant `f` it equals the VEM load `|T| f / 3` per vertex).
///
/// ```
/// use vem_space::{ElasticityTensor, ElementSpace, LinearTriangle, Point};
/// let triangle = [Point::new(0.0, 0.0), Point::new(1.0, 0.0), Point::new(0.0, 1.0)];
/// let k = LinearTriangle.stiffness(&triangle, &ElasticityTensor::try_isotropic(2.0, 1.0)?)?;
/// assert_eq!(k.stabilisation.norm(), 0.0);
/// # Ok::<(), vem_space::SpaceError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct LinearTriangle;

/// The checked vertices of a triangle, its area and the `b_i`, `c_i` of the gradient formula.
struct Triangle {
    vertices: [Point; 3],
    area: f64,
    b: [f64; 3],
    c: [f64; 3],
}

impl Triangle {
    fn new(polygon: &[Point]) -> Result<Self, SpaceError> {
        let vertices: [Point; 3] =
            polygon
                .try_into()
                .map_err(|_| SpaceError::UnsupportedPolygon {
                    element: "p1".into(),
                    vertices: polygon.len(),
                })?;
        let [p1, p2, p3] = vertices;
        let b = [p2.y - p3.y, p3.y - p1.y, p1.y - p2.y];
        let c = [p3.x - p2.x, p1.x - p3.x, p2.x - p1.x];
        // 2A = (x2 - x1)(y3 - y1) - (x3 - x1)(y2 - y1).
        let area = 0.5 * ((p2.x - p1.x) * (p3.y - p1.y) - (p3.x - p1.x) * (p2.y - p1.y));
        if !(area.is_finite() && area > 0.0) {
            return Err(SpaceError::DegeneratePolygon {
                vertices: 3,
                reason: format!("triangle area {area:e} is not positive and finite"),
            });
        }
        Ok(Self {
            vertices,
            area,
            b,
            c,
        })
    }

    /// The 3 x 6 strain matrix.
    fn strain_matrix(&self) -> SMatrix<f64, 3, 6> {
        let mut m = SMatrix::<f64, 3, 6>::zeros();
        for i in 0..3 {
            m[(0, 2 * i)] = self.b[i];
            m[(1, 2 * i + 1)] = self.c[i];
            m[(2, 2 * i)] = self.c[i];
            m[(2, 2 * i + 1)] = self.b[i];
        }
        m / (2.0 * self.area)
    }
}

impl ElementSpace for LinearTriangle {
    fn name(&self) -> &str {
        "p1"
    }

    /// Triangles only.
    fn supports(&self, n_vertices: usize) -> bool {
        n_vertices == 3
    }

    fn stiffness(
        &self,
        polygon: &[Point],
        material: &ElasticityTensor,
    ) -> Result<LocalStiffness, SpaceError> {
        let triangle = Triangle::new(polygon)?;
        let b = triangle.strain_matrix();
        let c: Matrix3<f64> = material.voigt();
        let k = b.transpose() * c * b * triangle.area;
        let k = (k + k.transpose()) * 0.5;
        Ok(LocalStiffness {
            consistency: DMatrix::from_column_slice(6, 6, k.as_slice()),
            stabilisation: DMatrix::zeros(6, 6),
        })
    }

    fn projection(&self, polygon: &[Point]) -> Result<EnergyProjection, SpaceError> {
        // The P1 function itself, expanded about the centroid where its value is the vertex mean.
        let triangle = Triangle::new(polygon)?;
        let [p1, p2, p3] = triangle.vertices;
        let reference = Point::from((p1.coords + p2.coords + p3.coords) / 3.0);
        let mut coefficients = DMatrix::zeros(6, 6);
        let scale = 1.0 / (2.0 * triangle.area);
        for i in 0..3 {
            let (x, y) = (2 * i, 2 * i + 1);
            coefficients[(0, x)] = 1.0 / 3.0;
            coefficients[(1, y)] = 1.0 / 3.0;
            coefficients[(2, x)] = triangle.b[i] * scale;
            coefficients[(3, x)] = triangle.c[i] * scale;
            coefficients[(4, y)] = triangle.b[i] * scale;
            coefficients[(5, y)] = triangle.c[i] * scale;
        }
        Ok(EnergyProjection {
            reference,
            coefficients,
        })
    }

    fn body_load(
        &self,
        polygon: &[Point],
        body_force: &(dyn Fn(Point) -> Vector + Sync),
    ) -> Result<DVector<f64>, SpaceError> {
        let triangle = Triangle::new(polygon)?;
        let [p1, p2, p3] = triangle.vertices;
        let mut load = DVector::zeros(6);
        for &(phi, weight) in TriangleRule::degree5().barycentric() {
            let point = Point::from(phi[0] * p1.coords + phi[1] * p2.coords + phi[2] * p3.coords);
            let f = body_force(point);
            if !(f.x.is_finite() && f.y.is_finite()) {
                return Err(SpaceError::NonFiniteLoad {
                    x: point.x,
                    y: point.y,
                });
            }
            for i in 0..3 {
                let w = weight * triangle.area * phi[i];
                load[2 * i] += w * f.x;
                load[2 * i + 1] += w * f.y;
            }
        }
        Ok(load)
    }
}
