//! Cattaneo-Mindlin in plane strain on two flat blocks: the setup that the friction study of
//! `cargo xtask hertz` and the workspace's fretting tests share, and the measures of a contact
//! zone along the interface that they compare with [`HertzContact`]'s analytic answers.
//!
//! The setup is a [`Scene`] ([`FlatBlocks::scene`]), built by [`Model::build`]
//! ([`FlatBlocks::problem`]): the upper block is the mirror image `(x, y) -> (x, -y)` of a block
//! mesh (so that its "bottom" part lies at its top), given inline; the lower block, any mesh
//! description (a file, a generator, inline), is clamped at its bottom; both of one material;
//! the gap `x^2 / (2R)` of a cylinder of radius R on a flat is imposed on the interface y = 0,
//! as in Cattaneo-Mindlin's half-planes (Johnson, Contact Mechanics, 7.5-7.6). The upper
//! block's top is driven by a rigid plate with the resultant `(F P, -P)` ([`Drive::Force`]) or
//! by prescribed displacements ([`Drive::Displacement`]); its two conditions are
//! [`FlatBlocks::PRESS`] and [`FlatBlocks::SHEAR`], which a load history (the scene's
//! `history` with the conditions' `curve`s, or the contact library's own) scales separately.
//!
//! ```
//! use vem_contact::{CondensedSolver, LoadFactors, NodeStatus};
//! use vem_mesh::generators::{structured_quads, Rectangle};
//! use vem_mesh::Point;
//! use vem_verify::fretting::{lower_block, zone_half_width, Drive, FlatBlocks};
//!
//! let setup = FlatBlocks { young: 100.0, poisson: 0.3, radius: 1.0, coefficient: 0.3, push: 0.5 };
//! let block = |n| {
//!     let rectangle = Rectangle::new(Point::new(-0.25, -0.25), Point::new(0.25, 0.0));
//!     structured_quads(&rectangle, n, n / 2)
//! };
//! // Pressed with P and sheared with Q = F P / 2 at once from rest: a proportional load, under
//! // which most of the contact zone sticks (q = (Q/P) p stays below F p), unlike
//! // Cattaneo-Mindlin's press-then-shear; the contact carries the plate's resultant.
//! let lower = lower_block(&block(48)?);
//! let problem = setup.problem(&block(40)?, lower, Drive::Force, setup.coulomb())?;
//! let factors = LoadFactors::uniform(1.0).with(FlatBlocks::SHEAR, 0.5);
//! let result = problem.into_discretisation()?.solve_at(&mut CondensedSolver::default(), &factors)?;
//! let force = result.force_on_body_a();
//! assert!((force.y - 0.5).abs() < 1e-8 && (force.x + 0.075).abs() < 1e-8, "{force:?}");
//! let (stick, _) = zone_half_width(&result.nodes, |n| n.status == NodeStatus::Stick);
//! let (contact, spacing) = zone_half_width(&result.nodes, |n| n.status.is_active());
//! assert!(contact > 2.0 * spacing && stick > 0.5 * contact);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use vem_contact::{ContactProblem, ContactResult, InterfaceNode, LoadCondition};
use vem_mesh::{Mesh, Point};
use vem_scene::description::MeshDescription;
use vem_scene::{BuildOptions, BuiltMesh, Model, ScalarValue, Scene};
use vem_space::{Choice, Options};

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

    /// Hertz's answer for a cylinder of radius R pressed with P on a half-plane of the same
    /// material (plane strain): the contact half-width, the pressure, and Cattaneo-Mindlin's
    /// tangential tractions.
    pub fn hertz(&self) -> Result<HertzContact, VerifyError> {
        let e_star =
            HertzContact::plane_strain_modulus(self.young, self.poisson, self.young, self.poisson);
        Ok(HertzContact::try_new(self.radius, e_star, self.push)?)
    }

    /// Coulomb's law at the coefficient F, by its registry name: `law = { name = "coulomb",
    /// coefficient = F }`.
    pub fn coulomb(&self) -> Choice {
        Choice::with_options(
            "coulomb",
            Options::new().with("coefficient", self.coefficient),
        )
    }

    /// The scene: the mirror image of `upper` (given inline, its "bottom" part at its top)
    /// above the block `lower` (any mesh description: a file, a generator, inline; clamped at
    /// its "bottom"), both of the blocks' material in plane strain, the upper block's top
    /// driven by `drive` (its two conditions [`FlatBlocks::PRESS`] and [`FlatBlocks::SHEAR`],
    /// in this order), the contact of their "top" parts with the law `law` (by registry name),
    /// paired within 0.05, with the cylinder's gap `x^2 / (2R)` imposed.
    ///
    /// # Errors
    /// [`VerifyError::Case`] when the mirror image is not a mesh or the scene's keys are
    /// refused.
    pub fn scene(
        &self,
        upper: &Mesh,
        lower: MeshDescription,
        drive: Drive,
        law: Choice,
    ) -> Result<Scene, VerifyError> {
        let material =
            serde_json::json!({ "E": self.young, "nu": self.poisson, "plane": "strain" });
        // The mirrored block's "bottom" is its top side.
        let (rigid_plate, dirichlet) = match drive {
            Drive::Force => (
                serde_json::json!([
                    { "part": "bottom", "resultant_y": -self.push },
                    { "part": "bottom", "resultant_x": self.coefficient * self.push },
                ]),
                serde_json::json!([]),
            ),
            Drive::Displacement(dx, dy) => (
                serde_json::json!([]),
                serde_json::json!([
                    { "part": "bottom", "y": -dy },
                    { "part": "bottom", "x": dx },
                ]),
            ),
        };
        let mut scene = Scene::from_value(serde_json::json!({
            "title": "Cattaneo-Mindlin: two flat blocks under a cylinder's gap",
            "body": [
                { "name": "upper", "mesh": {}, "material": material,
                  "dirichlet": dirichlet, "rigid_plate": rigid_plate },
                { "name": "lower", "mesh": {}, "material": material,
                  "dirichlet": [{ "part": "bottom", "x": 0.0, "y": 0.0 }] },
            ],
            "contact": [{
                "body": "upper", "part": "top", "other_body": "lower", "other_part": "top",
                "max_distance": 0.05,
            }],
        }))
        .map_err(|e| case(e.to_string()))?;
        scene.bodies[0].mesh = BuiltMesh::Plane(mirror_image(upper)?).to_inline();
        scene.bodies[1].mesh = lower;
        let radius = self.radius;
        let contact = &mut scene.contacts[0];
        contact.law = Some(law);
        contact.imposed_gap = Some(ScalarValue::function(move |x, _| {
            x[0] * x[0] / (2.0 * radius)
        }));
        Ok(scene)
    }

    /// The contact problem of [`FlatBlocks::scene`] as [`Model::build`] makes it.
    ///
    /// # Errors
    /// Those of [`FlatBlocks::scene`], and the scene's refusal when it is built.
    pub fn problem(
        &self,
        upper: &Mesh,
        lower: MeshDescription,
        drive: Drive,
        law: Choice,
    ) -> Result<ContactProblem, VerifyError> {
        let scene = self.scene(upper, lower, drive, law)?;
        contact_problem(&scene)
    }
}

/// The contact problem of a scene in the plane with contact, as [`Model::build`] makes it
/// (files relative to the current folder).
///
/// # Errors
/// [`VerifyError::Scene`] with the scene's refusal at its key; [`VerifyError::Case`] when the
/// scene has no contact pair.
pub fn contact_problem(scene: &Scene) -> Result<ContactProblem, VerifyError> {
    let model =
        Model::build(scene, &BuildOptions::default()).map_err(|source| VerifyError::Scene {
            case: CASE.to_string(),
            source: Box::new(source),
        })?;
    model
        .contact_problem()
        .map(|(problem, _)| problem.clone())
        .ok_or_else(|| case("the scene has no contact pair".to_string()))
}

/// The lower block of [`FlatBlocks::scene`] given inline: the keys of `mesh`
/// ([`BuiltMesh::to_inline`]).
pub fn lower_block(mesh: &Mesh) -> MeshDescription {
    BuiltMesh::Plane(mesh.clone()).to_inline()
}

/// A mesh file as the scene's `mesh = { file = ".." }` (relative to the current folder).
pub fn mesh_file(path: impl Into<String>) -> MeshDescription {
    MeshDescription {
        file: Some(path.into()),
        ..MeshDescription::default()
    }
}

fn case(reason: String) -> VerifyError {
    VerifyError::Case {
        case: CASE.to_string(),
        reason,
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
