//! Cattaneo-Mindlin in plane strain on two flat blocks: the setup that the friction study of
//! `cargo xtask hertz` and the workspace's fretting tests share, and the measures of a contact
//! zone along the interface that they compare with [`HertzContact`]'s analytic answers.
//!
//! The upper block is the mirror image `(x, y) -> (x, -y)` of a block mesh (so that its "bottom"
//! part lies at its top), the lower block is clamped at its bottom, both of one material; the
//! gap `x^2 / (2R)` of a cylinder of radius R on a flat is imposed on the interface y = 0, as
//! in Cattaneo-Mindlin's half-planes (Johnson, Contact Mechanics, 7.5-7.6). The upper block's
//! top is driven by a rigid plate with the resultant `(F P, -P)` ([`Drive::Force`]) or by
//! prescribed displacements ([`Drive::Displacement`]); its two conditions are
//! [`FlatBlocks::PRESS`] and [`FlatBlocks::SHEAR`], which a load history scales separately.
//!
//! ```
//! use vem_contact::{CondensedSolver, Coulomb, LoadFactors, NodeStatus};
//! use vem_mesh::generators::{structured_quads, Rectangle};
//! use vem_mesh::Point;
//! use vem_verify::fretting::{zone_half_width, Drive, FlatBlocks};
//!
//! let setup = FlatBlocks { young: 100.0, poisson: 0.3, radius: 1.0, coefficient: 0.3, push: 0.5 };
//! let block = |n| {
//!     let rectangle = Rectangle::new(Point::new(-0.25, -0.25), Point::new(0.25, 0.0));
//!     structured_quads(&rectangle, n, n / 2)
//! };
//! // Pressed with P and sheared with Q = F P / 2 at once from rest: a proportional load, under
//! // which most of the contact zone sticks (q = (Q/P) p stays below F p), unlike
//! // Cattaneo-Mindlin's press-then-shear; the contact carries the plate's resultant.
//! let problem = setup.problem(&block(40)?, block(48)?, Drive::Force, Coulomb::try_new(0.3)?)?;
//! let factors = LoadFactors::uniform(1.0).with(FlatBlocks::SHEAR, 0.5);
//! let result = problem.into_discretisation()?.solve_at(&mut CondensedSolver::default(), &factors)?;
//! let force = result.force_on_body_a();
//! assert!((force.y - 0.5).abs() < 1e-8 && (force.x + 0.075).abs() < 1e-8, "{force:?}");
//! let (stick, _) = zone_half_width(&result.nodes, |n| n.status == NodeStatus::Stick);
//! let (contact, spacing) = zone_half_width(&result.nodes, |n| n.status.is_active());
//! assert!(contact > 2.0 * spacing && stick > 0.5 * contact);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::sync::Arc;

use vem_contact::{ContactLaw, ContactProblem, ContactResult, InterfaceNode, LoadCondition};
use vem_elastic::{Component, Dirichlet, ElasticBody, Material, Plane};
use vem_mesh::interface::InterfaceOptions;
use vem_mesh::{Mesh, Point, Vector};
use vem_space::LowestOrderVem;

use crate::exact::HertzContact;
use crate::VerifyError;

/// The case name the errors of this module carry.
const CASE: &str = "Cattaneo-Mindlin blocks";

/// How the upper block's top (its mirrored "bottom" part) is driven.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Drive {
    /// A rigid plate with the resultant `(F P, -P)`: condition [`FlatBlocks::PRESS`] the push
    /// `-P` along y, [`FlatBlocks::SHEAR`] the shear `F P` along x (a load history scales each
    /// to the load it wants).
    Force,
    /// Prescribed displacements: [`FlatBlocks::PRESS`] moves the top by `-dy` along y,
    /// [`FlatBlocks::SHEAR`] by `dx` along x; the fields are `(dx, dy)`.
    Displacement(f64, f64),
}

/// The two flat blocks of one material under a cylinder's gap.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlatBlocks {
    /// Young's modulus of both blocks.
    pub young: f64,
    /// Poisson's ratio of both blocks (plane strain).
    pub poisson: f64,
    /// The radius R of the gap `x^2 / (2R)`.
    pub radius: f64,
    /// The friction coefficient F that [`Drive::Force`]'s shear `F P` is scaled by.
    pub coefficient: f64,
    /// The push P of [`Drive::Force`].
    pub push: f64,
}

impl FlatBlocks {
    /// The first condition of the upper block: the push (or the press of the displacement).
    pub const PRESS: LoadCondition = LoadCondition::Dirichlet { body: 0, index: 0 };
    /// The second condition of the upper block: the shear (or the shift).
    pub const SHEAR: LoadCondition = LoadCondition::Dirichlet { body: 0, index: 1 };

    /// The blocks' material (plane strain).
    pub fn material(&self) -> Result<Material, VerifyError> {
        Material::from_young_poisson(self.young, self.poisson, Plane::Strain).map_err(|e| {
            VerifyError::Elastic {
                case: CASE.to_string(),
                source: Box::new(e),
            }
        })
    }

    /// Hertz's answer for a cylinder of radius R pressed with P on a half-plane of the same
    /// material (plane strain): the contact half-width, the pressure, and Cattaneo-Mindlin's
    /// tangential tractions.
    pub fn hertz(&self) -> Result<HertzContact, VerifyError> {
        let e_star =
            HertzContact::plane_strain_modulus(self.young, self.poisson, self.young, self.poisson);
        Ok(HertzContact::try_new(self.radius, e_star, self.push)?)
    }

    /// The contact problem: the mirror image of `upper` above `lower` (clamped at its
    /// "bottom"), the interface their "top" parts, paired within 0.05, with the cylinder's gap.
    pub fn problem(
        &self,
        upper: &Mesh,
        lower: Mesh,
        drive: Drive,
        law: impl ContactLaw + 'static,
    ) -> Result<ContactProblem, VerifyError> {
        let elastic = |e| VerifyError::Elastic {
            case: CASE.to_string(),
            source: Box::new(e),
        };
        let material = self.material()?;
        let element = Arc::new(LowestOrderVem::default());
        let upper = ElasticBody::builder("upper", mirror_image(upper)?, material, element.clone());
        // The mirrored block's "bottom" is its top side.
        let upper = match drive {
            Drive::Force => upper
                .dirichlet(Dirichlet::rigid_plate(
                    "bottom",
                    Component::Y,
                    Vector::new(0.0, -self.push),
                ))
                .dirichlet(Dirichlet::rigid_plate(
                    "bottom",
                    Component::X,
                    Vector::new(self.coefficient * self.push, 0.0),
                )),
            Drive::Displacement(dx, dy) => upper
                .dirichlet(Dirichlet::prescribed("bottom", Component::Y, move |_| {
                    Vector::new(0.0, -dy)
                }))
                .dirichlet(Dirichlet::prescribed("bottom", Component::X, move |_| {
                    Vector::new(dx, 0.0)
                })),
        }
        .build()
        .map_err(elastic)?;
        let lower = ElasticBody::builder("lower", lower, material, element)
            .clamp("bottom")
            .build()
            .map_err(elastic)?;
        let interface = InterfaceOptions::builder()
            .max_distance(0.05)
            .build()
            .map_err(|e| VerifyError::InvalidSetting {
                reason: e.to_string(),
            })?;
        let radius = self.radius;
        Ok(ContactProblem::two_bodies(upper, "top", lower, "top", law)
            .with_imposed_gap(move |x| x.x * x.x / (2.0 * radius))
            .with_interface_options(interface))
    }
}

/// The mirror image `(x, y) -> (x, -y)` of a mesh: every polygon's vertex order reversed so
/// that it stays counter-clockwise; the parts keep their names.
pub fn mirror_image(mesh: &Mesh) -> Result<Mesh, VerifyError> {
    let vertices: Vec<Point> = mesh
        .vertices()
        .iter()
        .map(|p| Point::new(p.x, -p.y))
        .collect();
    let polygons: Vec<Vec<usize>> = mesh
        .polygons()
        .map(|p| p.iter().rev().copied().collect())
        .collect();
    Mesh::from_polygons(vertices, &polygons, mesh.part_specs()).map_err(|e| VerifyError::Case {
        case: CASE.to_string(),
        reason: format!("the mirror image of the upper mesh is not a mesh: {e}"),
    })
}

/// The consistent friction traction that body A exerts on body B along +x (signed along the
/// shear of [`Drive::Force`]; the friction on body A opposes it).
pub fn friction_traction(node: &InterfaceNode) -> f64 {
    -node.consistent_friction_t()
}

/// The largest spacing of consecutive interface nodes (in the order of `nodes`) whose first
/// lies within `|x| < half_width`.
pub fn largest_spacing_within(nodes: &[InterfaceNode], half_width: f64) -> f64 {
    nodes
        .windows(2)
        .filter(|w| w[0].position.x.abs() < half_width)
        .map(|w| (w[1].position.x - w[0].position.x).abs())
        .fold(0.0, f64::max)
}

/// Half-length of the run of consecutive nodes with `inside` around the one nearest to x = 0,
/// its ends halfway to the next node outside (or at the last node where the interface ends),
/// and the larger spacing of the nodes at its two ends. `(0, 0)` when no node is inside.
pub fn zone_half_width(
    nodes: &[InterfaceNode],
    inside: impl Fn(&InterfaceNode) -> bool,
) -> (f64, f64) {
    let Some(centre) = (0..nodes.len())
        .filter(|&i| inside(&nodes[i]))
        .min_by(|&i, &j| {
            nodes[i]
                .position
                .x
                .abs()
                .total_cmp(&nodes[j].position.x.abs())
        })
    else {
        return (0.0, 0.0);
    };
    let (mut first, mut last) = (centre, centre);
    while first > 0 && inside(&nodes[first - 1]) {
        first -= 1;
    }
    while last + 1 < nodes.len() && inside(&nodes[last + 1]) {
        last += 1;
    }
    let x = |i: usize| nodes[i].position.x;
    let start = if first > 0 {
        0.5 * (x(first) + x(first - 1))
    } else {
        x(first)
    };
    let stop = if last + 1 < nodes.len() {
        0.5 * (x(last) + x(last + 1))
    } else {
        x(last)
    };
    let spacing_at = |i: usize, j: Option<usize>| j.map_or(0.0, |j| (x(i) - x(j)).abs());
    let spacing = spacing_at(first, first.checked_sub(1)).max(spacing_at(
        last,
        (last + 1 < nodes.len()).then_some(last + 1),
    ));
    ((stop - start).abs() / 2.0, spacing)
}

/// The largest `|q - exact(x)| / (F p0)` of the [`friction_traction`] q over the nodes two
/// node spacings inside Hertz's contact edge and two spacings away from every zone end in
/// `ends` (where the exact traction has a square-root kink).
pub fn traction_error(
    result: &ContactResult,
    hertz: &HertzContact,
    coefficient: f64,
    exact: impl Fn(f64) -> f64,
    ends: &[f64],
) -> f64 {
    let (a, p0) = (hertz.half_width(), hertz.peak_pressure());
    let h = largest_spacing_within(&result.nodes, a);
    result
        .nodes
        .iter()
        .filter(|n| {
            let x = n.position.x.abs();
            x < a - 2.0 * h && ends.iter().all(|e| (x - e).abs() > 2.0 * h)
        })
        .map(|n| (friction_traction(n) - exact(n.position.x)).abs() / (coefficient * p0))
        .fold(0.0, f64::max)
}

/// The root mean square of `(q - exact(x)) / (F p0)` over the nodes within `|x| < 0.9 a`.
pub fn traction_rms(
    result: &ContactResult,
    hertz: &HertzContact,
    coefficient: f64,
    exact: impl Fn(f64) -> f64,
) -> f64 {
    let (a, p0) = (hertz.half_width(), hertz.peak_pressure());
    let inside: Vec<&InterfaceNode> = result
        .nodes
        .iter()
        .filter(|n| n.position.x.abs() < 0.9 * a)
        .collect();
    (inside
        .iter()
        .map(|n| ((friction_traction(n) - exact(n.position.x)) / (coefficient * p0)).powi(2))
        .sum::<f64>()
        / inside.len().max(1) as f64)
        .sqrt()
}

/// The plate's translation along x: the x displacement of the upper block's driven top.
pub fn plate_translation(result: &ContactResult) -> Result<f64, VerifyError> {
    let upper = result.bodies.first().ok_or_else(|| VerifyError::Case {
        case: CASE.to_string(),
        reason: "the result has no body".to_string(),
    })?;
    let top = upper
        .body
        .mesh()
        .part_vertices("bottom")
        .map_err(|e| VerifyError::Case {
            case: CASE.to_string(),
            reason: e.to_string(),
        })?;
    let v = top.first().ok_or_else(|| VerifyError::Case {
        case: CASE.to_string(),
        reason: "the driven top has no vertex".to_string(),
    })?;
    Ok(upper.solution.vertex_displacement(*v).x)
}
