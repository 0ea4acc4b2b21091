//! The description of a problem: what a scene file, a Python dict or a study writes. Every key
//! is documented in `docs/scenes.md`; the types mirror the keys one to one.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};
use vem_space::Choice;

use crate::{ScalarValue, VectorValue};

/// A whole problem: bodies, contact pairs, the contact solver, accuracy, load history, outputs
/// and resource limits.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// A title for pictures and reports.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub title: Option<String>,
    /// The bodies (`[[body]]`), at least one.
    #[serde(default, rename = "body")]
    pub bodies: Vec<BodyDescription>,
    /// The contact pairs (`[[contact]]`): any number; the solver treats them together.
    #[serde(default, rename = "contact", skip_serializing_if = "Vec::is_empty")]
    pub contacts: Vec<ContactDescription>,
    /// The contact solver by registry name, with its settings: `solver = "active-set"` or
    /// `solver = { name = "penalty", penalty = { factor = 1e4 } }` (default `"condensed"`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub solver: Option<Choice>,
    /// An accuracy preset (`"draft"`, `"balanced"`, `"reference"`): the solver's setting and,
    /// for a generated mesh without `n`, the size for the preset's target error.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub accuracy: Option<String>,
    /// A target relative energy error (`E_grad / |u|_1`): generated meshes without `n` take the
    /// size the error model predicts for it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub target_error: Option<f64>,
    /// A load history: the loads, prescribed displacements and gaps' prescribed parts scaled
    /// step by step (the static problem is one step of factor 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub history: Option<LoadHistory>,
    /// Adaptive refinement in the plane (`adapt = { target_error = 0.05 }`): solve, estimate,
    /// mark, refine until the estimate relative to the solution's energy norm is below the
    /// target, or a limit is reached; the outputs are those of the last mesh.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub adapt: Option<AdaptDescription>,
    /// Outputs (`[output]`).
    #[serde(default)]
    pub output: OutputDescription,
    /// Resource limits (`[limits]`).
    #[serde(default)]
    pub limits: LimitsDescription,
}

impl Scene {
    /// Reads a scene from a JSON value (the form of a Python dict): the same keys and types
    /// as a scene file, every error at the key path of the value at fault.
    ///
    /// ```
    /// use vem_scene::Scene;
    /// let value = serde_json::json!({ "body": [{ "name": "a", "mesh": { "familly": "quads" } }] });
    /// let error = Scene::from_value(value).unwrap_err();
    /// assert_eq!(error.path.to_string(), "body[0].mesh.familly");
    /// assert!(error.message.contains("familly"), "{}", error.message);
    /// ```
    ///
    /// # Errors
    /// [`SceneError`](crate::SceneError) for an unknown key, a value of the wrong type, a
    /// missing key; the checks of [`crate::check::check`] are separate.
    pub fn from_value(value: serde_json::Value) -> Result<Self, crate::SceneError> {
        serde_path_to_error::deserialize(value).map_err(|e| {
            let mut path = crate::KeyPath::root();
            for segment in e.path().iter() {
                match segment {
                    serde_path_to_error::Segment::Seq { index } => path = path.index(*index),
                    serde_path_to_error::Segment::Map { key } => path = path.at(key),
                    serde_path_to_error::Segment::Enum { variant } => path = path.at(variant),
                    serde_path_to_error::Segment::Unknown => {}
                }
            }
            crate::SceneError::at(path, e.inner().to_string())
        })
    }
}

/// One elastic body (`[[body]]`).
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodyDescription {
    /// The body's name: letters, digits, `-`, `_` and `.`; also the name of its output files.
    pub name: String,
    /// Its mesh: a generator or a file.
    pub mesh: MeshDescription,
    /// Its material.
    pub material: MaterialDescription,
    /// The element by registry name, with its settings: `element = "vem1-bbar"` or
    /// `element = { name = "vem1", stabilisation = "drecipe" }` (default `"vem1"`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub element: Option<Choice>,
    /// Earlier form of `element = { name = "vem1", stabilisation = ... }`: still read, with a
    /// note naming the new key.
    #[serde(default, skip_serializing)]
    pub stabilisation: Option<LegacyStabilisation>,
    /// Prescribed displacements by part (`[[body.dirichlet]]`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub dirichlet: Vec<DirichletDescription>,
    /// Rigid plates with prescribed resultants by part (`[[body.rigid_plate]]`): force control.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub rigid_plate: Vec<RigidPlateDescription>,
    /// Tractions by part (`[[body.traction]]`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub traction: Vec<TractionDescription>,
    /// Gauss–Legendre points per boundary edge (in space: per direction of a face's
    /// triangles) for its tractions, from 1 to
    /// [`GaussLegendre::MAX_POINTS`](vem_space::quadrature::GaussLegendre::MAX_POINTS)
    /// (default 2, exact for tractions quadratic along an edge).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub traction_points: Option<usize>,
    /// A body force per unit area (per unit volume in 3D): `[fx, fy]` (`[fx, fy, fz]`),
    /// numbers or expressions.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub body_force: Option<VectorValue>,
    /// The load curve of the body force along the history (as a condition's `curve`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub body_force_curve: Option<Vec<[f64; 2]>>,
}

/// A mesh: generated (`family` with `rectangle` or `polygon` in the plane or `box` in space,
/// `n`, `seed`), read (`file`) or given inline (`vertices` with `polygons` in the plane or
/// `polyhedra` in space, boundary parts by `part_edges` or `part_faces`). The mesh decides the
/// dimension of its body: a `rectangle`, a `polygon`, a planar file or `polygons` give a body
/// in the plane, a `box`, a Gmsh file of volume elements or `polyhedra` a body in space.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeshDescription {
    /// A mesh family name: of a `rectangle` or a `polygon` "quads", "triangles", "hexagons",
    /// "voronoi", "perturbed", "perturbed:0.2", "nonconvex", "hanging"; of a `box` "hexahedra",
    /// "tetrahedra", "perturbed-hexahedra", "perturbed-hexahedra:0.2", "voronoi", "nonconvex",
    /// "octree".
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub family: Option<String>,
    /// The rectangle `[[x0, y0], [x1, y1]]` of a generated mesh in the plane.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rectangle: Option<Vec<Vec<f64>>>,
    /// The polygon `[[x, y], ...]` of a generated mesh in the plane: a simple polygon, its
    /// vertices counter-clockwise, possibly non-convex (an L-shaped bracket, a notched
    /// block). The family's mesh of its bounding rectangle is cut by it; the boundary edges on
    /// its edge k form the part named `edge_names[k]` (default `"edge<k>"`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub polygon: Option<Vec<Vec<f64>>>,
    /// The names of the edges of `polygon`, one per edge (edge k from vertex k to vertex
    /// k + 1, the last back to vertex 0); an empty name keeps `"edge<k>"`, edges sharing a
    /// name make one part.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub edge_names: Option<Vec<String>>,
    /// The box `[[x0, y0, z0], [x1, y1, z1]]` of a generated mesh in space.
    #[serde(default, rename = "box", skip_serializing_if = "Option::is_none")]
    pub cuboid: Option<Vec<Vec<f64>>>,
    /// The size parameter of a generated mesh (about `n` cells across); may be left out when
    /// the scene gives `accuracy` or `target_error`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub n: Option<usize>,
    /// The seed of a random family (default 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub seed: Option<u64>,
    /// A mesh file, relative to the scene file: Gmsh `.msh` (4.1, 2.2; of surface elements in
    /// the plane, of volume elements in space), VTK `.vtu` or legacy `.vtk` (polygons; boundary
    /// parts from line cells), or the PolyMesher/mVEM text layout (`.txt`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub file: Option<String>,
    /// VTK files: the names of the part numbers of the line cells (`{ 1 = "bottom" }`).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub part_names: BTreeMap<String, String>,
    /// The vertices of a mesh given inline: `[[x, y], ...]` with `polygons`, `[[x, y, z], ...]`
    /// with `polyhedra`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vertices: Option<Vec<Vec<f64>>>,
    /// The cells of an inline mesh in the plane: each a loop of vertex indices (from 0),
    /// counter-clockwise.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub polygons: Option<Vec<Vec<usize>>>,
    /// The cells of an inline mesh in space: each a list of faces, each face a loop of vertex
    /// indices oriented outward for that cell (a face shared by two cells is listed by both,
    /// in opposite directions).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub polyhedra: Option<Vec<Vec<Vec<usize>>>>,
    /// The boundary parts of an inline mesh in the plane: each part's boundary edges as pairs of
    /// vertex indices (`part_edges = { bottom = [[0, 1], [1, 2]] }`).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub part_edges: BTreeMap<String, Vec<[usize; 2]>>,
    /// The boundary parts of an inline mesh in space: each part's boundary faces as vertex
    /// loops (any starting vertex, either orientation: `part_faces = { left = [[0, 6, 9, 3]] }`).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub part_faces: BTreeMap<String, Vec<Vec<usize>>>,
    /// Further boundary parts cut out of the mesh's boundary (a strip load, a partial clamp, a
    /// contact zone on part of an edge): `parts = [{ name = "strip", of = "top", box =
    /// [[0.4, 0.9], [0.6, 1.1]] }]`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub parts: Vec<SubPartDescription>,
}

/// A boundary part made of the boundary edges (faces in space) whose end points (vertices) all
/// lie in a box (closed, to a round-off of the box's size), optionally only among the edges
/// (faces) of an existing part.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SubPartDescription {
    /// The new part's name (not a name the mesh has).
    pub name: String,
    /// The part its edges are taken from (default: the whole boundary).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub of: Option<String>,
    /// The box `[[x0, y0], [x1, y1]]` the edges' end points lie in (`[[x0, y0, z0], [x1, y1,
    /// z1]]` the faces' vertices lie in, in space).
    #[serde(rename = "box")]
    pub bounds: Vec<Vec<f64>>,
}

/// An isotropic material: `E` and `nu`, or `lambda` and `mu`, and `plane` in the plane (a body
/// in space takes the full three-dimensional law, without `plane`).
#[derive(Debug, Clone, Copy, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialDescription {
    /// Young's modulus.
    #[serde(default, rename = "E", skip_serializing_if = "Option::is_none")]
    pub young: Option<f64>,
    /// Poisson's ratio.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub nu: Option<f64>,
    /// First Lame parameter.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lambda: Option<f64>,
    /// Shear modulus.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mu: Option<f64>,
    /// Plane strain or plane stress (two-dimensional bodies only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub plane: Option<PlaneDescription>,
}

/// Plane strain or plane stress.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum PlaneDescription {
    /// Plane strain.
    Strain,
    /// Plane stress.
    Stress,
}

/// Earlier form of the stabilisation of the lowest-order VEM (`[body.stabilisation]`).
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LegacyStabilisation {
    /// "dofi-dofi" or "d-recipe".
    pub kind: LegacyStabilisationKind,
    /// dofi-dofi only: "trace" (default) or "shear".
    #[serde(default)]
    pub scaling: Option<LegacyScaling>,
    /// dofi-dofi only: the factor (default 1/8).
    #[serde(default)]
    pub scale: Option<f64>,
}

/// The stabilisation kinds of the earlier form.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum LegacyStabilisationKind {
    /// `S = alpha I`.
    DofiDofi,
    /// The diagonal D-recipe.
    DRecipe,
}

/// The dofi-dofi scalings of the earlier form.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum LegacyScaling {
    /// `alpha = scale * trace(C)`.
    Trace,
    /// `alpha = scale * 5 mu`.
    Shear,
}

/// `[[body.dirichlet]]`: prescribed displacement components on a part (absent: free).
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DirichletDescription {
    /// The boundary part.
    pub part: String,
    /// `u_x` on the part.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub x: Option<ScalarValue>,
    /// `u_y` on the part.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub y: Option<ScalarValue>,
    /// `u_z` on the part (3D).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub z: Option<ScalarValue>,
    /// Its load curve along the history, `[[t, s], ...]`: the factor `s(t)` of its values,
    /// piecewise linear (default: the history's ramp `[[0, 0], [1, 1]]`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub curve: Option<Vec<[f64; 2]>>,
}

/// `[[body.rigid_plate]]`: the part moves as one rigid plate in the given components, pushed
/// with the given resultant (force control); the translation is computed.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RigidPlateDescription {
    /// The boundary part.
    pub part: String,
    /// The resultant along x the plate applies to the body (absent: x not tied).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub resultant_x: Option<f64>,
    /// The resultant along y.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub resultant_y: Option<f64>,
    /// The resultant along z (3D).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub resultant_z: Option<f64>,
    /// Its load curve along the history, `[[t, s], ...]`: the factor `s(t)` of its values,
    /// piecewise linear (default: the history's ramp `[[0, 0], [1, 1]]`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub curve: Option<Vec<[f64; 2]>>,
}

/// `[[body.traction]]`: a traction vector or a normal pressure on a part.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TractionDescription {
    /// The boundary part.
    pub part: String,
    /// A traction `[gx, gy]` (`[gx, gy, gz]` in space): numbers or expressions.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub value: Option<VectorValue>,
    /// A normal pressure, positive compressive (a number).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pressure: Option<f64>,
    /// Its load curve along the history, `[[t, s], ...]`: the factor `s(t)` of its values,
    /// piecewise linear (default: the history's ramp `[[0, 0], [1, 1]]`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub curve: Option<Vec<[f64; 2]>>,
}

/// Which side gives the contact normal of two bodies (`normal` key).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum NormalDescription {
    /// Body A's outward normal.
    BodyA,
    /// Minus body B's outward normal (default).
    #[default]
    BodyB,
    /// The bisector of the two.
    Averaged,
}

/// A penalty or augmentation parameter of the earlier form: `factor` or `value`.
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LegacyPenalty {
    /// Relative to the stiffness.
    #[serde(default)]
    pub factor: Option<f64>,
    /// Absolute.
    #[serde(default)]
    pub value: Option<f64>,
}

/// `[[contact]]`: one contact pair.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactDescription {
    /// Body A.
    pub body: String,
    /// Body A's contact part.
    pub part: String,
    /// Body B.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub other_body: Option<String>,
    /// Body B's contact part.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub other_part: Option<String>,
    /// A rigid obstacle instead of body B.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub obstacle: Option<ObstacleDescription>,
    /// The contact law by registry name, with its settings: `law = "frictionless"` (default),
    /// `law = { name = "tresca", friction_bound = 0.3 }`,
    /// `law = { name = "coulomb", coefficient = 0.3 }`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub law: Option<Choice>,
    /// Which side gives the contact normal of two bodies: "body_b" (default), "body_a" or
    /// "averaged" (not with an obstacle, whose own normal is used).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub normal: Option<NormalDescription>,
    /// A gap imposed on top of the geometric one (the initial gap is their sum): a number or
    /// an expression.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub imposed_gap: Option<ScalarValue>,
    /// Only points of the two sides closer than this (along the normal) are paired.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_distance: Option<f64>,
    /// Compare with Hertz's solution: body A near the contact is a cylinder (in the plane) or a
    /// sphere (in space) of this radius, its counterpart a half-space.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hertz: Option<HertzDescription>,
    /// Earlier form of `law = { name = "tresca", friction_bound = .. }`.
    #[serde(default, skip_serializing)]
    pub friction_bound: Option<f64>,
    /// Earlier form of `law = { name = "coulomb", coefficient = .. }`.
    #[serde(default, skip_serializing)]
    pub coefficient: Option<f64>,
    /// Earlier form of `law = { .., fixed_point = { max_iterations = .. } }`.
    #[serde(default, skip_serializing)]
    pub fixed_point_max_iterations: Option<usize>,
    /// Earlier form of `law = { .., fixed_point = { tolerance = .. } }`.
    #[serde(default, skip_serializing)]
    pub fixed_point_tolerance: Option<f64>,
    /// Earlier form of the scene's `solver`.
    #[serde(default, skip_serializing)]
    pub solver: Option<String>,
    /// Earlier form of `solver = { .., tolerance = .. }`.
    #[serde(default, skip_serializing)]
    pub tolerance: Option<f64>,
    /// Earlier form of `solver = { .., max_iterations = .. }`.
    #[serde(default, skip_serializing)]
    pub max_iterations: Option<usize>,
    /// Earlier form of `solver = { .., penalty = { .. } }`.
    #[serde(default, skip_serializing)]
    pub penalty: Option<LegacyPenalty>,
    /// Earlier form of `solver = { .., augmentation = { .. } }`.
    #[serde(default, skip_serializing)]
    pub augmentation: Option<LegacyPenalty>,
}

/// `hertz = { radius = R }`.
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HertzDescription {
    /// Radius of the cylinder (in space: the sphere) of body A.
    pub radius: f64,
}

/// A rigid obstacle: exactly one of `line`, `circle`, `polyline` (in the plane) or `plane`,
/// `sphere` (in space).
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObstacleDescription {
    /// A straight line bounding a half-plane.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub line: Option<LineDescription>,
    /// A rigid disc.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub circle: Option<CircleDescription>,
    /// A polyline with the obstacle on its right.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub polyline: Option<Vec<Vec<f64>>>,
    /// In space: a plane bounding a half-space, `plane = { point = [x, y, z], normal = [nx,
    /// ny, nz] }`, the normal pointing out of the obstacle (the keys of `line`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub plane: Option<LineDescription>,
    /// In space: a rigid ball, `sphere = { centre = [x, y, z], radius = r }` (the keys of
    /// `circle`); the body lies outside it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sphere: Option<CircleDescription>,
}

/// `line = { point = [x, y], normal = [nx, ny] }` (in space `plane = { point = [x, y, z],
/// normal = [nx, ny, nz] }`), the normal pointing out of the obstacle.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LineDescription {
    /// A point of the line.
    pub point: Vec<f64>,
    /// The normal pointing out of the obstacle, towards the body.
    pub normal: Vec<f64>,
}

/// `circle = { centre = [x, y], radius = r }` (in space `sphere = { centre = [x, y, z], radius
/// = r }`).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CircleDescription {
    /// Centre.
    pub centre: Vec<f64>,
    /// Radius.
    pub radius: f64,
}

/// `[history]`: a load history in pseudo-time `t`, solved step by step on one discretisation
/// (friction incremental from step to step). Either
/// - `steps = [0.25, 0.5, 1.0]`: the load factors of the steps, each scaling every load,
///   prescribed displacement and rigid-plate force (steps at `t` = 1, 2, ...); or
/// - `times = [...]` (increasing), or `end` with `increments` (evenly spaced times in
///   `(0, end]`): at each time every condition is scaled by its `curve` (default: the ramp
///   `[[0, 0], [1, 1]]`, constant after its last point).
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LoadHistory {
    /// The load factors, in order.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub steps: Option<Vec<f64>>,
    /// The times of the steps, increasing.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub times: Option<Vec<f64>>,
    /// The last time of evenly spaced steps (with `increments`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub end: Option<f64>,
    /// The number of evenly spaced steps up to `end`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub increments: Option<usize>,
}

/// `adapt = { target_error = .., max_unknowns = .., theta = .., max_cycles = .. }`: adaptive
/// refinement of the bodies in the plane (docs/adaptivity.md).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AdaptDescription {
    /// The target of the estimate relative to the energy norm of the solution,
    /// `eta / (sum 2 W_h)^(1/2)`, in (0, 1) (absent: refine until a limit).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub target_error: Option<f64>,
    /// No refinement whose mesh would have more unknowns than this (default 200 000).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_unknowns: Option<usize>,
    /// Dorfler's bulk fraction: the cells refined carry at least this fraction of `eta^2`, in
    /// (0, 1] (default 0.5; 1 refines every cell with a nonzero indicator).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub theta: Option<f64>,
    /// The largest number of solves, the first included (default 12).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_cycles: Option<usize>,
}

impl AdaptDescription {
    /// The default of `max_unknowns`.
    pub const MAX_UNKNOWNS: usize = 200_000;
    /// The default of `theta`.
    pub const THETA: f64 = 0.5;
    /// The default of `max_cycles`.
    pub const MAX_CYCLES: usize = 12;
}

/// `[output]`.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputDescription {
    /// Displacement magnification of the deformed picture (default: the largest displacement
    /// drawn as 8% of the picture's extent).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub magnification: Option<f64>,
    /// Width of the pictures in pixels (default 900, at most 20000).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub width: Option<f64>,
    /// The unit of the meshes' coordinates, written on the pictures' axes ("mm"); default:
    /// none written.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub length_unit: Option<String>,
    /// The unit of stresses (that of the Young's moduli), written on the colour bar and the
    /// plots ("MPa"); default: none written.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stress_unit: Option<String>,
    /// The encoding of the `.vtu` files (default [`VtuEncodingName::Binary`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vtu_encoding: Option<VtuEncodingName>,
    /// The kinds of files written besides `summary.json` (default: every kind).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub files: Option<Vec<OutputFiles>>,
}

/// `[output] vtu_encoding`: how the arrays of the `.vtu` files are stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum VtuEncodingName {
    /// Binary appended data, as ParaView writes it: raw for the bodies, zlib-compressed for
    /// the interface.
    #[default]
    Binary,
    /// Binary appended data, every array zlib-compressed.
    Compressed,
    /// Text, every value written out.
    Ascii,
}

impl std::str::FromStr for VtuEncodingName {
    type Err = String;

    /// The encoding named `name`, as a scene writes it.
    fn from_str(name: &str) -> Result<Self, String> {
        from_scene_name(name)
    }
}

/// `[output] files`: a kind of output file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum OutputFiles {
    /// The `.vtu` files of the bodies and the interface and `results.pvd` (every step's with
    /// a load history).
    Vtu,
    /// `contact.csv` (and every step's, `history.csv`, `adapt.csv`).
    Csv,
    /// The pictures and plots: `deformed.svg`, `pressure.svg`, `slip.svg`, `history.svg`.
    Pictures,
}

impl std::str::FromStr for OutputFiles {
    type Err = String;

    /// The kind named `name`, as a scene writes it.
    fn from_str(name: &str) -> Result<Self, String> {
        from_scene_name(name)
    }
}

/// The value of a unit-variant enum named `name` as in a scene (its serde names, so that a
/// name is spelt in one place); the error lists the names.
fn from_scene_name<T: serde::de::DeserializeOwned>(name: &str) -> Result<T, String> {
    let name = serde::de::value::StrDeserializer::<serde::de::value::Error>::new(name);
    T::deserialize(name).map_err(|e| e.to_string())
}

/// `[limits]`: what a run may use.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LimitsDescription {
    /// The memory a run may plan to use, in GiB (default: the memory the system reports
    /// available).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub memory_gib: Option<f64>,
}
