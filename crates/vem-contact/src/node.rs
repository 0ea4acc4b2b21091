//! The geometry of the interface nodes, in any dimension: positions, normals and the tangent
//! bases built from them.

use std::fmt;

use nalgebra::SMatrix;
use vem_mesh::{PointD, Vector, VectorD};

/// The geometry of one interface node of a contact pair: a node pair of two bodies (after
/// insertion the interface is node-to-node) or a body node facing a rigid obstacle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactNode<const D: usize = 2> {
    /// The contact pair (index in the problem's pairs).
    pub pair: usize,
    /// Body A of the pair (index in the problem's bodies).
    pub body_a: usize,
    /// The vertex of body A's (enlarged) mesh.
    pub vertex_a: usize,
    /// Body B of the pair; `None` against an obstacle.
    pub body_b: Option<usize>,
    /// The partner vertex of body B's (enlarged) mesh; `None` against an obstacle.
    pub vertex_b: Option<usize>,
    /// Position (on body A, reference configuration).
    pub position: PointD<D>,
    /// The unit normal `nu` from A to B (of the side chosen by
    /// [`ContactNormal`](crate::ContactNormal); into the obstacle).
    pub normal: VectorD<D>,
    /// The tributary measure `l_x` (length in 2D, area in 3D): the nodal quadrature weight on
    /// `Gamma_C`.
    pub tributary_measure: f64,
    /// The gap the geometry gives along `nu` (zero where the two sides coincide).
    pub geometric_gap: f64,
    /// The initial gap `h0 = geometric gap + imposed gap`.
    pub initial_gap: f64,
}

impl<const D: usize> ContactNode<D> {
    /// The orthonormal frame of the node: column 0 the normal, columns `1..D` the tangents
    /// ([`frame`]).
    pub fn frame(&self) -> SMatrix<f64, D, D> {
        frame(&self.normal)
    }
}

impl ContactNode<2> {
    /// The tangent `tau = (-nu_y, nu_x)`.
    pub fn tangent(&self) -> Vector {
        tangent(self.normal)
    }
}

/// The tangent `tau = (-nu_y, nu_x)` of a planar normal (nu rotated by +90 degrees; `e_x` for
/// `nu = (0, -1)`).
pub fn tangent(normal: Vector) -> Vector {
    Vector::new(-normal.y, normal.x)
}

/// The orthonormal frame of a unit normal `n` in `R^D`: column 0 is `n`, columns `1..D` the
/// tangent directions. In 2D the tangent is `(-n_y, n_x)`; in 3D the branchless basis of Duff et
/// al. (2017), continuous except across the plane `n_z = 0` where its sign flips. Any rotation
/// of the tangents gives the same contact problem.
///
/// ```
/// use vem_contact::frame;
/// use vem_mesh::VectorD;
/// let n = VectorD::<3>::new(1.0, 2.0, 2.0) / 3.0;
/// let f = frame(&n);
/// assert!((f.transpose() * f - nalgebra::Matrix3::identity()).norm() < 1e-15);
/// assert!((f.column(0) - n).norm() < 1e-15);
/// ```
pub fn frame<const D: usize>(normal: &VectorD<D>) -> SMatrix<f64, D, D> {
    let mut f = SMatrix::<f64, D, D>::zeros();
    f.set_column(0, normal);
    match D {
        2 => {
            f[(0, 1)] = -normal[1];
            f[(1, 1)] = normal[0];
        }
        3 => {
            let (x, y, z) = (normal[0], normal[1], normal[2]);
            let sign = 1.0f64.copysign(z);
            let a = -1.0 / (sign + z);
            let b = x * y * a;
            let t1 = [1.0 + sign * x * x * a, sign * b, -sign * x];
            let t2 = [b, sign + y * y * a, -y];
            for k in 0..3 {
                f[(k, 1)] = t1[k];
                f[(k, 2)] = t2[k];
            }
        }
        _ => {}
    }
    f
}

/// A position or direction of any dimension as reports write it: `(x, y)` or `(x, y, z)`.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(transparent))]
pub struct Location(pub Vec<f64>);

impl Location {
    /// The coordinates of `point` (`+ 0.0` writes a negative zero as 0).
    pub fn of<const D: usize>(point: &PointD<D>) -> Self {
        Self(point.coords.iter().map(|c| c + 0.0).collect())
    }

    /// The components of `vector`.
    pub fn of_vector<const D: usize>(vector: &VectorD<D>) -> Self {
        Self(vector.iter().map(|c| c + 0.0).collect())
    }
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("(")?;
        for (k, c) in self.0.iter().enumerate() {
            if k > 0 {
                f.write_str(", ")?;
            }
            write!(f, "{c}")?;
        }
        f.write_str(")")
    }
}
