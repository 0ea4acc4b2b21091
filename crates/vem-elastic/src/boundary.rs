//! Boundary conditions by boundary-part name: prescribed displacements (Dirichlet) and
//! tractions (Neumann), plus the body force.

use std::fmt;
use std::sync::Arc;

use vem_mesh::{Point, Vector};

/// A vector field of position: body force, traction or prescribed displacement.
pub type VectorField = Arc<dyn Fn(Point) -> Vector + Send + Sync>;

/// Which displacement components a Dirichlet condition prescribes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Component {
    /// `u_x` only (the part may slide in y).
    X,
    /// `u_y` only (the part may slide in x).
    Y,
    /// Both components (clamped or fully prescribed).
    Both,
}

impl Component {
    /// The component indices (0 = x, 1 = y) this selects.
    pub fn indices(self) -> &'static [usize] {
        match self {
            Component::X => &[0],
            Component::Y => &[1],
            Component::Both => &[0, 1],
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
/// let clamp = Dirichlet::fixed("left", Component::Both);
/// let pull = Dirichlet::prescribed("right", Component::X, |_p| Vector::new(0.01, 0.0));
/// assert_eq!(clamp.part(), "left");
/// assert!(clamp.is_homogeneous() && !pull.is_homogeneous());
/// ```
#[derive(Clone)]
pub struct Dirichlet {
    part: String,
    component: Component,
    values: Option<VectorField>,
}

impl Dirichlet {
    /// Zero displacement of the selected components on `part`.
    pub fn fixed(part: impl Into<String>, component: Component) -> Self {
        Self {
            part: part.into(),
            component,
            values: None,
        }
    }

    /// Displacement `values(x)` (only the selected components are used) on `part`.
    pub fn prescribed(
        part: impl Into<String>,
        component: Component,
        values: impl Fn(Point) -> Vector + Send + Sync + 'static,
    ) -> Self {
        Self {
            part: part.into(),
            component,
            values: Some(Arc::new(values)),
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

    /// True when the prescribed values are zero.
    pub fn is_homogeneous(&self) -> bool {
        self.values.is_none()
    }

    /// The prescribed displacement at `x` (zero for a homogeneous condition).
    pub fn value_at(&self, x: Point) -> Vector {
        self.values.as_ref().map_or_else(Vector::zeros, |g| g(x))
    }
}

impl fmt::Debug for Dirichlet {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Dirichlet")
            .field("part", &self.part)
            .field("component", &self.component)
            .field("homogeneous", &self.is_homogeneous())
            .finish()
    }
}

/// A surface traction `g = sigma nu` on a boundary part, a function of position, integrated
/// edge by edge against the linear trace of the test functions (spec section 2).
#[derive(Clone)]
pub struct Traction {
    part: String,
    traction: VectorField,
}

impl Traction {
    /// The traction `g(x)` on `part`.
    pub fn new(
        part: impl Into<String>,
        traction: impl Fn(Point) -> Vector + Send + Sync + 'static,
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
    pub fn value_at(&self, x: Point) -> Vector {
        (self.traction)(x)
    }
}

impl fmt::Debug for Traction {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Traction")
            .field("part", &self.part)
            .finish_non_exhaustive()
    }
}
