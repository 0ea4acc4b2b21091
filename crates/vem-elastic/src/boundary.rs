//! Boundary conditions by boundary-part name: prescribed displacements (Dirichlet) and
//! tractions (Neumann), plus the body force.

use std::fmt;
use std::sync::Arc;

use vem_mesh::{Mesh, MeshError, Point, PointD, Vector, VectorD};

/// A vector field of position in `R^D`: body force, traction or prescribed displacement.
pub type VectorField<const D: usize = 2> = Arc<dyn Fn(PointD<D>) -> VectorD<D> + Send + Sync>;

/// Which displacement components a Dirichlet condition prescribes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Component {
    /// `u_x` only (the part may slide in the other directions).
    X,
    /// `u_y` only.
    Y,
    /// `u_z` only (three dimensions).
    Z,
    /// Every component (clamped or fully prescribed).
    All,
}

impl Component {
    /// The component indices (0 = x, 1 = y, 2 = z) this selects in dimension `dimension`.
    pub fn indices(self, dimension: usize) -> &'static [usize] {
        match self {
            Component::X => &[0],
            Component::Y => &[1],
            Component::Z => &[2],
            Component::All => &[0, 1, 2][..dimension.min(3)],
        }
    }

    /// The axis letters this selects ("x", "y", "z", or "all").
    pub fn name(self) -> &'static str {
        match self {
            Component::X => "x",
            Component::Y => "y",
            Component::Z => "z",
            Component::All => "all",
        }
    }
}

/// A prescribed displacement on a boundary part: `u_c = g_c` on the part for the selected
/// components `c`, with `g = 0` (homogeneous) or a given function of position.
///
/// Non-homogeneous data enter the reduced right-hand side through the lifting:
/// `K_ff u_f = f_f - K_fp u_p`.
///
/// ```
/// use vem_elastic::{Component, Dirichlet};
/// use vem_mesh::Vector;
/// let clamp: Dirichlet = Dirichlet::fixed("left", Component::All); // a planar body's
/// let pull = Dirichlet::prescribed("right", Component::X, |_p| Vector::new(0.01, 0.0));
/// assert_eq!(clamp.part(), "left");
/// assert!(clamp.is_homogeneous() && !pull.is_homogeneous());
/// ```
///
/// # Rigid plate (force control)
///
/// [`Dirichlet::rigid_plate`] ties the selected components of every vertex of the part to one
/// unknown translation per component and prescribes the total force instead of the
/// displacement: the part moves as a rigid plate pushed with a given resultant. With the
/// change of unknowns `u = T v` (each tied component of the part's vertices equals the plate's
/// translation `w_c`), the system becomes `T^T K T v = T^T f + P e_c`: symmetric and positive
/// semi-definite like `K`, with one extra unknown per prescribed component. The reaction of
/// the condition ([`crate::Solution::reaction`]) is the prescribed resultant, and the plate's
/// translation is the displacement of any vertex of the part. Components the plate does not
/// tie may be prescribed by an ordinary condition on the same part.
///
/// ```
/// use vem_elastic::{Component, Dirichlet};
/// use vem_mesh::Vector;
/// let push = Dirichlet::rigid_plate("top", Component::Y, Vector::new(0.0, -10.0));
/// assert_eq!(push.resultant(), Some(Vector::new(0.0, -10.0)));
/// assert!(push.is_rigid_plate());
/// ```
#[derive(Clone)]
pub struct Dirichlet<const D: usize = 2> {
    part: String,
    component: Component,
    values: Option<VectorField<D>>,
    resultant: Option<VectorD<D>>,
}

impl<const D: usize> Dirichlet<D> {
    /// Zero displacement of the selected components on `part`.
    pub fn fixed(part: impl Into<String>, component: Component) -> Self {
        Self {
            part: part.into(),
            component,
            values: None,
            resultant: None,
        }
    }

    /// A rigid plate on `part`: the selected components of all the part's vertices move by one
    /// common unknown translation, and the total force the plate applies to the body in those
    /// components is `resultant` (only the selected components are used). See the section on
    /// rigid plates above.
    pub fn rigid_plate(
        part: impl Into<String>,
        component: Component,
        resultant: VectorD<D>,
    ) -> Self {
        Self {
            part: part.into(),
            component,
            values: None,
            resultant: Some(resultant),
        }
    }

    /// Displacement `values(x)` (only the selected components are used) on `part`, in any
    /// dimension ([`Dirichlet::prescribed`] in 2D).
    pub fn with_values(
        part: impl Into<String>,
        component: Component,
        values: impl Fn(PointD<D>) -> VectorD<D> + Send + Sync + 'static,
    ) -> Self {
        Self {
            part: part.into(),
            component,
            values: Some(Arc::new(values)),
            resultant: None,
        }
    }

    /// The boundary part's name.
    pub fn part(&self) -> &str {
        &self.part
    }

    /// The prescribed components.
    pub fn component(&self) -> Component {
        self.component
    }

    /// True when the prescribed values are zero (false for a rigid plate, whose displacement
    /// is an unknown).
    pub fn is_homogeneous(&self) -> bool {
        self.values.is_none() && self.resultant.is_none()
    }

    /// True for a rigid plate ([`Dirichlet::rigid_plate`]).
    pub fn is_rigid_plate(&self) -> bool {
        self.resultant.is_some()
    }

    /// The prescribed resultant of a rigid plate (`None` for a prescribed displacement).
    pub fn resultant(&self) -> Option<VectorD<D>> {
        self.resultant
    }

    /// The prescribed displacement at `x` (zero for a homogeneous condition and for a rigid
    /// plate, whose displacement is an unknown).
    pub fn value_at(&self, x: PointD<D>) -> VectorD<D> {
        self.values.as_ref().map_or_else(VectorD::zeros, |g| g(x))
    }
}

impl Dirichlet<2> {
    /// Displacement `values(x)` (only the selected components are used) on `part` of a planar
    /// body.
    pub fn prescribed(
        part: impl Into<String>,
        component: Component,
        values: impl Fn(Point) -> Vector + Send + Sync + 'static,
    ) -> Self {
        Self::with_values(part, component, values)
    }
}

impl<const D: usize> fmt::Debug for Dirichlet<D> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Dirichlet")
            .field("part", &self.part)
            .field("component", &self.component)
            .field("homogeneous", &self.is_homogeneous())
            .field("resultant", &self.resultant)
            .finish()
    }
}

/// A surface traction `g = sigma nu` on a boundary part, a function of position, integrated
/// facet by facet (edge by edge in 2D) against the trace of the test functions (spec
/// section 2).
#[derive(Clone)]
pub struct Traction<const D: usize = 2> {
    part: String,
    traction: VectorField<D>,
}

impl<const D: usize> Traction<D> {
    /// The traction `g(x)` on `part`, in any dimension ([`Traction::new`] in 2D).
    pub fn field(
        part: impl Into<String>,
        traction: impl Fn(PointD<D>) -> VectorD<D> + Send + Sync + 'static,
    ) -> Self {
        Self {
            part: part.into(),
            traction: Arc::new(traction),
        }
    }

    /// The boundary part's name.
    pub fn part(&self) -> &str {
        &self.part
    }

    /// The traction at `x`.
    pub fn value_at(&self, x: PointD<D>) -> VectorD<D> {
        (self.traction)(x)
    }
}

impl Traction<2> {
    /// The traction `g(x)` on `part` of a planar body.
    pub fn new(
        part: impl Into<String>,
        traction: impl Fn(Point) -> Vector + Send + Sync + 'static,
    ) -> Self {
        Self::field(part, traction)
    }

    /// A normal pressure `pressure` on the boundary part `part` of `mesh`: the traction
    /// `g = -p nu` with `nu` the outward unit normal of the part, so that `p > 0` pushes into
    /// the body and `p < 0` pulls on it.
    ///
    /// The part is a polygonal chain, so `nu` is constant on each of its edges: at a point `x`
    /// the traction uses the normal of the part's edge nearest to `x`. Tractions are evaluated
    /// at Gauss points inside the edges, where that edge is the nearest one. An edge split later
    /// (interface node insertion puts vertices on existing edges) keeps its normal, so the
    /// traction is unchanged on the enlarged mesh.
    ///
    /// ```
    /// use vem_elastic::Traction;
    /// use vem_mesh::{Mesh, PartSpec, Point, Vector};
    /// let square = Mesh::from_polygons(
    ///     vec![Point::new(0.0, 0.0), Point::new(1.0, 0.0), Point::new(1.0, 1.0), Point::new(0.0, 1.0)],
    ///     &[vec![0, 1, 2, 3]],
    ///     vec![PartSpec::new("top", vec![[2, 3]])],
    /// )?;
    /// let pressure = Traction::try_normal_pressure(&square, "top", 2.0)?;
    /// // The outward normal of the top is (0, 1): a positive pressure pushes down.
    /// assert_eq!(pressure.value_at(Point::new(0.5, 1.0)), Vector::new(0.0, -2.0));
    /// # Ok::<(), vem_mesh::MeshError>(())
    /// ```
    ///
    /// # Errors
    /// [`MeshError::UnknownPart`] when `mesh` has no part named `part` (it lists the parts).
    /// A non-finite `pressure` is reported, like any non-finite traction, when the body's load
    /// is assembled.
    pub fn try_normal_pressure(
        mesh: &Mesh,
        part: impl Into<String>,
        pressure: f64,
    ) -> Result<Self, MeshError> {
        let part = part.into();
        let edges: Vec<(Point, Vector, Vector)> = mesh
            .part(&part)?
            .edges
            .iter()
            .map(|&e| {
                // The polygon lies to the left of a -> b: the outward normal is on the right.
                let [a, b] = mesh.edge(e).vertices;
                let (start, end) = (mesh.vertex(a), mesh.vertex(b));
                let tangent = end - start;
                let outward = Vector::new(tangent.y, -tangent.x) / tangent.norm();
                (start, tangent, outward)
            })
            .collect();
        Ok(Self::new(part, move |x| {
            let nearest = edges.iter().min_by(|(a1, t1, _), (a2, t2, _)| {
                distance_squared(x, *a1, *t1).total_cmp(&distance_squared(x, *a2, *t2))
            });
            nearest.map_or_else(Vector::zeros, |&(_, _, outward)| -pressure * outward)
        }))
    }
}

/// Squared distance from `x` to the segment from `start` to `start + tangent`.
fn distance_squared(x: Point, start: Point, tangent: Vector) -> f64 {
    let s = ((x - start).dot(&tangent) / tangent.norm_squared()).clamp(0.0, 1.0);
    (x - (start + s * tangent)).norm_squared()
}

impl<const D: usize> fmt::Debug for Traction<D> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Traction")
            .field("part", &self.part)
            .finish_non_exhaustive()
    }
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use vem_mesh::PartSpec;

    use super::*;

    /// The resultant `sum over edges of |e| g(midpoint)` of a traction on a part (exact for a
    /// traction constant on each edge).
    fn resultant(mesh: &Mesh, traction: &Traction) -> Vector {
        mesh.part(traction.part())
            .unwrap()
            .edges
            .iter()
            .map(|&e| {
                let [a, b] = mesh.edge(e).vertices;
                let (pa, pb) = (mesh.vertex(a), mesh.vertex(b));
                (pb - pa).norm() * traction.value_at(pa + 0.5 * (pb - pa))
            })
            .sum()
    }

    /// The half-disc of radius `r` centred at (0, r) below its flat top (the line y = r), as
    /// `segments` triangles fanned from the centre; parts "arc" and "top".
    fn half_disc(r: f64, segments: usize) -> Mesh {
        let mut vertices = vec![Point::new(0.0, r)];
        for k in 0..=segments {
            let theta = PI + PI * k as f64 / segments as f64;
            vertices.push(Point::new(r * theta.cos(), r + r * theta.sin()));
        }
        let polygons: Vec<Vec<usize>> = (1..=segments).map(|k| vec![0, k, k + 1]).collect();
        let arc = (1..=segments).map(|k| [k, k + 1]).collect();
        let top = vec![[segments + 1, 0], [0, 1]];
        Mesh::from_polygons(
            vertices,
            &polygons,
            vec![PartSpec::new("arc", arc), PartSpec::new("top", top)],
        )
        .unwrap()
    }

    #[test]
    fn pressure_on_a_half_circle_has_the_closed_form_resultant() {
        // On the lower half circle of radius r the inward normals add up to (0, 2 r): a
        // pressure p pushes up with 2 p r. The chords end on the circle, so the polygonal arc
        // has the same resultant exactly.
        let (r, p) = (0.75, 3.0);
        let mesh = half_disc(r, 24);
        let arc = Traction::try_normal_pressure(&mesh, "arc", p).unwrap();
        let total = resultant(&mesh, &arc);
        assert!(
            (total - Vector::new(0.0, 2.0 * p * r)).norm() < 1e-12,
            "{total}"
        );
        // Pointwise: at each chord's midpoint the traction is p times the direction to the
        // centre (the chord's inward normal).
        let centre = Point::new(0.0, r);
        for &e in &mesh.part("arc").unwrap().edges {
            let [a, b] = mesh.edge(e).vertices;
            let midpoint = mesh.vertex(a) + 0.5 * (mesh.vertex(b) - mesh.vertex(a));
            let inward = (centre - midpoint).normalize();
            assert!((arc.value_at(midpoint) - p * inward).norm() < 1e-12);
        }
    }

    #[test]
    fn pressure_on_a_flat_side_is_the_pressure_times_its_length() {
        // The flat top (length 2 r, outward normal (0, 1)), split at the centre: a suction
        // p < 0 pulls it up with |p| 2 r.
        let (r, p) = (0.75, -0.5);
        let mesh = half_disc(r, 8);
        let top = Traction::try_normal_pressure(&mesh, "top", p).unwrap();
        let total = resultant(&mesh, &top);
        // (The end points come from sin(pi) and sin(2 pi): the top is level to rounding.)
        assert!(
            (total - Vector::new(0.0, -p * 2.0 * r)).norm() < 1e-14,
            "{total}"
        );
        let g = top.value_at(Point::new(0.3, r));
        assert!((g - Vector::new(0.0, 0.5)).norm() < 1e-14, "{g}");
    }

    #[test]
    fn pressure_on_an_unknown_part_lists_the_parts() {
        let err = Traction::try_normal_pressure(&half_disc(1.0, 4), "rim", 1.0).unwrap_err();
        assert_eq!(
            err,
            MeshError::UnknownPart {
                part: "rim".into(),
                available: vec!["arc".into(), "top".into()],
            }
        );
    }
}
