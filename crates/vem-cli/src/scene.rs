//! The scene file: what the user writes (TOML), read with serde (`deny_unknown_fields`, so a
//! misspelt key is an error with its line and column) and checked before anything is built.
//!
//! Every key is documented in `docs/scenes.md`. The structures here mirror the file one to
//! one; [`Scene::load`] parses and checks what can be checked without meshes (names, exactly
//! one of two alternatives, values that apply to the chosen law or solver). Checks that need
//! the meshes (part names) are done by [`crate::Model::build`], with the same kind of
//! located error.

use std::collections::HashSet;
use std::path::{Path, PathBuf};

use serde::Deserialize;
use toml::Spanned;

use vem_contact::{AccuracyPreset, ErrorModel, SolverRegistry};

use crate::resources::{LimitOrigin, MemoryLimit};
use crate::CliError;

/// The largest magnitude of a number of a scene (see [`Scene::check_number`]).
pub const LARGEST: f64 = 1e100;

/// The smallest non-zero magnitude of a number of a scene.
pub const SMALLEST: f64 = 1e-100;

/// The largest `[output] width`, in pixels.
pub const MAX_WIDTH: f64 = 20_000.0;

/// The whole scene file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// A title for pictures and reports.
    #[serde(default)]
    pub title: Option<String>,
    /// The bodies (`[[body]]`), at least one.
    #[serde(default, rename = "body")]
    pub bodies: Vec<BodySpec>,
    /// The contact pairs (`[[contact]]`), at most one.
    #[serde(default, rename = "contact")]
    pub contacts: Vec<Spanned<ContactSpec>>,
    /// Output options (`[output]`).
    #[serde(default)]
    pub output: OutputSpec,
    /// Resource limits (`[limits]`).
    #[serde(default)]
    pub limits: LimitsSpec,
    /// An accuracy preset ("draft", "balanced", "reference"): the contact solver's setting
    /// and, for a generated mesh without `n`, the size for the preset's target error.
    #[serde(default)]
    pub accuracy: Option<Spanned<String>>,
    /// A target relative energy error (`E_grad / |u|_1`, e.g. 0.05): generated meshes without
    /// `n` take the size the error model predicts for it, and the contact solver (when the
    /// scene names none) the setting of the matching preset.
    #[serde(default)]
    pub target_error: Option<Spanned<f64>>,
}

/// One elastic body (`[[body]]`).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    /// The body's name: letters, digits, `-`, `_` and `.`; also the name of its `.vtu` file.
    pub name: Spanned<String>,
    /// Its mesh: a generator or a Gmsh file.
    pub mesh: Spanned<MeshSpec>,
    /// Its material.
    pub material: Spanned<MaterialSpec>,
    /// The element by its registry name (`"vem1"`, `"vem1-shear"`, `"vem1-drecipe"`, `"p1"`, or
    /// a user's own); exclusive with `stabilisation`.
    #[serde(default)]
    pub element: Option<Spanned<String>>,
    /// The VEM stabilisation of the lowest-order VEM (default: dofi-dofi, trace of C, scale
    /// 1/8); exclusive with `element`.
    #[serde(default)]
    pub stabilisation: Option<Spanned<StabilisationSpec>>,
    /// Prescribed displacements by part (`[[body.dirichlet]]`).
    #[serde(default)]
    pub dirichlet: Vec<Spanned<DirichletSpec>>,
    /// Rigid plates with prescribed resultants by part (`[[body.rigid_plate]]`): force control.
    #[serde(default)]
    pub rigid_plate: Vec<Spanned<RigidPlateSpec>>,
    /// Tractions by part (`[[body.traction]]`).
    #[serde(default)]
    pub traction: Vec<Spanned<TractionSpec>>,
    /// A constant body force per unit area `[fx, fy]`.
    #[serde(default, deserialize_with = "exact::optional_spanned")]
    pub body_force: Option<Spanned<[f64; 2]>>,
}

/// A mesh: either `family` (with `rectangle`, `n`, optional `seed`) or `file`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeshSpec {
    /// A mesh family name ("quads", "triangles", "hexagons", "voronoi", "perturbed",
    /// "perturbed:0.2", "nonconvex", "hanging").
    #[serde(default)]
    pub family: Option<Spanned<String>>,
    /// The rectangle `[[x0, y0], [x1, y1]]` of a generated mesh.
    #[serde(default, deserialize_with = "exact::optional_spanned_rectangle")]
    pub rectangle: Option<Spanned<[[f64; 2]; 2]>>,
    /// The size parameter of a generated mesh (about `n` cells across); may be left out when
    /// the scene gives `accuracy` or `target_error`.
    #[serde(default)]
    pub n: Option<Spanned<usize>>,
    /// The seed of a random family (default 1).
    #[serde(default)]
    pub seed: Option<u64>,
    /// A Gmsh `.msh` 4.1 file, relative to the scene file.
    #[serde(default)]
    pub file: Option<Spanned<String>>,
}

/// Plane strain or plane stress.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum PlaneSpec {
    /// Plane strain.
    Strain,
    /// Plane stress.
    Stress,
}

/// An isotropic material: `E` and `nu`, or `lambda` and `mu`, and `plane`.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec {
    /// Young's modulus.
    #[serde(default, rename = "E")]
    pub young: Option<f64>,
    /// Poisson's ratio.
    #[serde(default)]
    pub nu: Option<f64>,
    /// First Lamé parameter.
    #[serde(default)]
    pub lambda: Option<f64>,
    /// Shear modulus.
    #[serde(default)]
    pub mu: Option<f64>,
    /// Plane strain or plane stress.
    pub plane: PlaneSpec,
}

/// The stabilisation kind.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum StabilisationKind {
    /// `S = alpha I`.
    DofiDofi,
    /// The diagonal D-recipe.
    DRecipe,
}

/// The material constant of the dofi-dofi stabilisation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ScalingSpec {
    /// `alpha = scale * trace(C)`.
    Trace,
    /// `alpha = scale * 5 mu`.
    Shear,
}

/// `[body.stabilisation]`.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StabilisationSpec {
    /// "dofi-dofi" or "d-recipe".
    pub kind: StabilisationKind,
    /// dofi-dofi only: "trace" (default) or "shear".
    #[serde(default)]
    pub scaling: Option<ScalingSpec>,
    /// dofi-dofi only: the factor (default 1/8).
    #[serde(default)]
    pub scale: Option<f64>,
}

/// `[[body.dirichlet]]`: prescribed displacement components on a part.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DirichletSpec {
    /// The boundary part.
    pub part: Spanned<String>,
    /// `u_x` on the part (absent: free).
    #[serde(default)]
    pub x: Option<f64>,
    /// `u_y` on the part (absent: free).
    #[serde(default)]
    pub y: Option<f64>,
}

/// `[[body.rigid_plate]]`: the part moves as one rigid plate in the given components, pushed
/// with the given resultant (force control); the translation is computed.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RigidPlateSpec {
    /// The boundary part.
    pub part: Spanned<String>,
    /// The resultant force along x the plate applies to the body (absent: x not tied).
    #[serde(default)]
    pub resultant_x: Option<f64>,
    /// The resultant force along y the plate applies to the body (absent: y not tied).
    #[serde(default)]
    pub resultant_y: Option<f64>,
}

/// `[[body.traction]]`: a constant traction vector or a normal pressure on a part.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TractionSpec {
    /// The boundary part.
    pub part: Spanned<String>,
    /// A constant traction `[gx, gy]`.
    #[serde(default, deserialize_with = "exact::optional")]
    pub value: Option<[f64; 2]>,
    /// A normal pressure, positive compressive (along the inward normal of each edge).
    #[serde(default)]
    pub pressure: Option<f64>,
}

/// The contact law.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum LawKind {
    /// Frictionless.
    #[default]
    Frictionless,
    /// Tresca friction (`friction_bound`).
    Tresca,
    /// Coulomb friction (`coefficient`).
    Coulomb,
}

/// Which side gives the contact normal of two bodies (`normal` key).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum NormalKind {
    /// Body A's outward normal.
    BodyA,
    /// Minus body B's outward normal (default).
    #[default]
    BodyB,
    /// The bisector of the two.
    Averaged,
}

impl NormalKind {
    /// The library's choice.
    pub fn choice(self) -> vem_contact::ContactNormal {
        match self {
            NormalKind::BodyA => vem_contact::ContactNormal::BodyA,
            NormalKind::BodyB => vem_contact::ContactNormal::BodyB,
            NormalKind::Averaged => vem_contact::ContactNormal::Averaged,
        }
    }
}

/// A penalty or augmentation parameter: `factor` (times the largest constrained diagonal
/// entry of the stiffness) or an absolute `value`.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PenaltySpec {
    /// Relative to the stiffness.
    #[serde(default)]
    pub factor: Option<f64>,
    /// Absolute (force per length).
    #[serde(default)]
    pub value: Option<f64>,
}

/// `[[contact]]`: one contact pair.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSpec {
    /// Body A.
    pub body: Spanned<String>,
    /// Body A's contact part.
    pub part: Spanned<String>,
    /// Body B.
    #[serde(default)]
    pub other_body: Option<Spanned<String>>,
    /// Body B's contact part.
    #[serde(default)]
    pub other_part: Option<Spanned<String>>,
    /// A rigid obstacle instead of body B.
    #[serde(default)]
    pub obstacle: Option<Spanned<ObstacleSpec>>,
    /// "frictionless" (default), "tresca" or "coulomb".
    #[serde(default)]
    pub law: Option<Spanned<LawKind>>,
    /// Which side gives the contact normal of two bodies: "body_b" (default), "body_a" or
    /// "averaged" (not with an obstacle, whose own normal is used).
    #[serde(default)]
    pub normal: Option<Spanned<NormalKind>>,
    /// Tresca: the friction bound `g_F` (force per length).
    #[serde(default)]
    pub friction_bound: Option<Spanned<f64>>,
    /// Coulomb: the friction coefficient `F`.
    #[serde(default)]
    pub coefficient: Option<Spanned<f64>>,
    /// Coulomb: largest number of Tresca solves (default 50).
    #[serde(default)]
    pub fixed_point_max_iterations: Option<Spanned<usize>>,
    /// Coulomb: relative change of the normal forces at which to stop (default 1e-8).
    #[serde(default)]
    pub fixed_point_tolerance: Option<Spanned<f64>>,
    /// A constant gap imposed on top of the geometric one (the initial gap is their sum).
    #[serde(default)]
    pub imposed_gap: Option<Spanned<f64>>,
    /// Only points of the two sides closer than this (along the normal) are paired.
    #[serde(default)]
    pub max_distance: Option<Spanned<f64>>,
    /// A name of the solver registry: "condensed" (default), "exact", "penalty", "active-set", or a
    /// solver registered by the program that runs the scene.
    #[serde(default)]
    pub solver: Option<Spanned<String>>,
    /// The solver's stopping tolerance (the exact solver's gap and feasibility tolerances).
    #[serde(default)]
    pub tolerance: Option<Spanned<f64>>,
    /// Iteration limit of the solver.
    #[serde(default)]
    pub max_iterations: Option<Spanned<usize>>,
    /// Penalty: the penalty parameter (normal and tangential).
    #[serde(default)]
    pub penalty: Option<Spanned<PenaltySpec>>,
    /// Active set: the augmentation parameter.
    #[serde(default)]
    pub augmentation: Option<Spanned<PenaltySpec>>,
    /// Compare with Hertz's cylinder on a half-space: body A near the contact is a cylinder of
    /// this radius.
    #[serde(default)]
    pub hertz: Option<Spanned<HertzSpec>>,
}

impl ContactSpec {
    /// The contact law (frictionless when not given).
    pub fn law(&self) -> LawKind {
        self.law
            .as_ref()
            .map_or_else(LawKind::default, |l| *l.get_ref())
    }

    /// The contact solver's name ([`SolverRegistry::DEFAULT`] when not given).
    pub fn solver(&self) -> &str {
        self.solver
            .as_ref()
            .map_or(SolverRegistry::DEFAULT, |s| s.get_ref().as_str())
    }
}

/// `hertz = { radius = R }`.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HertzSpec {
    /// Radius of the cylinder (body A).
    pub radius: f64,
}

/// A rigid obstacle: exactly one of `line`, `circle`, `polyline`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObstacleSpec {
    /// A straight line bounding a half-plane.
    #[serde(default)]
    pub line: Option<LineSpec>,
    /// A rigid disc.
    #[serde(default)]
    pub circle: Option<CircleSpec>,
    /// A polyline with the obstacle on its right.
    #[serde(default, deserialize_with = "exact::optional_points")]
    pub polyline: Option<Vec<[f64; 2]>>,
}

/// `line = { point = [x, y], normal = [nx, ny] }`, the normal pointing out of the obstacle.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LineSpec {
    /// A point of the line.
    #[serde(deserialize_with = "exact::pair")]
    pub point: [f64; 2],
    /// The normal pointing out of the obstacle, towards the body.
    #[serde(deserialize_with = "exact::pair")]
    pub normal: [f64; 2],
}

/// `circle = { centre = [x, y], radius = r }`.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CircleSpec {
    /// Centre.
    #[serde(deserialize_with = "exact::pair")]
    pub centre: [f64; 2],
    /// Radius.
    pub radius: f64,
}

/// `[output]`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSpec {
    /// Displacement magnification of the deformed picture (default: the largest displacement
    /// drawn as 8% of the picture's extent).
    #[serde(default)]
    pub magnification: Option<Spanned<f64>>,
    /// Width of the pictures in pixels (default 900, at most [`MAX_WIDTH`]).
    #[serde(default)]
    pub width: Option<Spanned<f64>>,
}

/// `[limits]`: what a run may use.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LimitsSpec {
    /// The memory a run may plan to use, in GiB (default: the memory the system reports
    /// available); meshes and systems estimated larger are refused before they are built.
    #[serde(default)]
    pub memory_gib: Option<Spanned<f64>>,
}

/// A parsed and checked scene file.
#[derive(Debug, Clone)]
pub struct Scene {
    path: PathBuf,
    source: String,
    file: SceneFile,
    memory_limit: Option<MemoryLimit>,
}

impl Scene {
    /// Reads, parses and checks the scene file at `path`.
    pub fn load(path: impl AsRef<Path>) -> Result<Self, CliError> {
        let path = path.as_ref();
        let source = std::fs::read_to_string(path).map_err(|source| CliError::Io {
            action: "read",
            path: path.to_path_buf(),
            source,
        })?;
        Self::parse(path, source)
    }

    /// Parses and checks `source`, the text of the scene file `path` (mesh files are looked
    /// up relative to `path`'s directory).
    pub fn parse(path: impl AsRef<Path>, source: impl Into<String>) -> Result<Self, CliError> {
        let path = path.as_ref().to_path_buf();
        let source = source.into();
        let file: SceneFile = toml::from_str(&source)
            .map_err(|e| CliError::at(&path, &source, e.span(), e.message().trim_end()))?;
        let scene = Self {
            path,
            source,
            file,
            memory_limit: None,
        };
        scene.check()?;
        Ok(scene)
    }

    /// The same scene with the memory limit `limit` (the command line's `--memory-limit`),
    /// which overrides the scene's `[limits] memory_gib`.
    pub fn with_memory_limit(mut self, limit: MemoryLimit) -> Self {
        self.memory_limit = Some(limit);
        self
    }

    /// The memory the run may plan to use: the command line's limit, else the scene's
    /// `[limits] memory_gib`, else the memory the system reports available.
    pub fn memory_limit(&self) -> MemoryLimit {
        if let Some(limit) = self.memory_limit {
            return limit;
        }
        self.file
            .limits
            .memory_gib
            .as_ref()
            .and_then(|gib| MemoryLimit::try_from_gib(*gib.get_ref(), LimitOrigin::Scene).ok())
            .unwrap_or_else(MemoryLimit::available)
    }

    /// The scene file's path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The file's stem ("hertz" for `scenes/hertz.toml`).
    pub fn stem(&self) -> String {
        self.path
            .file_stem()
            .map_or_else(|| "scene".into(), |s| s.to_string_lossy().into_owned())
    }

    /// The parsed contents.
    pub fn file(&self) -> &SceneFile {
        &self.file
    }

    /// The title, or the file stem.
    pub fn title(&self) -> String {
        self.file.title.clone().unwrap_or_else(|| self.stem())
    }

    /// A path given in the scene, relative to the scene file's directory.
    pub fn resolve(&self, relative: &str) -> PathBuf {
        let base = self.path.parent().unwrap_or(Path::new(""));
        base.join(relative)
    }

    /// A located error at `span`.
    pub(crate) fn error(
        &self,
        span: Option<std::ops::Range<usize>>,
        message: impl Into<String>,
    ) -> CliError {
        CliError::at(&self.path, &self.source, span, message)
    }

    /// The index of the body named `name`; the error lists the bodies.
    pub(crate) fn body_index(&self, name: &Spanned<String>) -> Result<usize, CliError> {
        self.file
            .bodies
            .iter()
            .position(|b| b.name.get_ref() == name.get_ref())
            .ok_or_else(|| {
                let names: Vec<&str> = self
                    .file
                    .bodies
                    .iter()
                    .map(|b| b.name.get_ref().as_str())
                    .collect();
                self.error(
                    Some(name.span()),
                    format!(
                        "no body named '{}'; the scene has {}",
                        name.get_ref(),
                        list(&names)
                    ),
                )
            })
    }

    /// Checks everything that does not need the meshes.
    fn check(&self) -> Result<(), CliError> {
        let file = &self.file;
        if file.bodies.is_empty() {
            return Err(self.error(None, "the scene has no [[body]]"));
        }
        let mut names = HashSet::new();
        for body in &file.bodies {
            self.check_body(body)?;
            if !names.insert(body.name.get_ref().as_str()) {
                return Err(self.error(
                    Some(body.name.span()),
                    format!("a second body is named '{}'", body.name.get_ref()),
                ));
            }
        }
        if let Some(second) = file.contacts.get(1) {
            return Err(self.error(
                Some(second.span()),
                "a second [[contact]] pair: one contact pair per scene is supported",
            ));
        }
        if let Some(contact) = file.contacts.first() {
            self.check_contact(contact.get_ref())?;
        }
        self.check_accuracy()?;
        let output = &file.output;
        if let Some(m) = &output.magnification {
            self.positive(m, "magnification")?;
            self.check_number(Some(m.span()), "`magnification`", *m.get_ref())?;
        }
        if let Some(w) = &output.width {
            if !(w.get_ref().is_finite() && (200.0..=MAX_WIDTH).contains(w.get_ref())) {
                return Err(self.error(
                    Some(w.span()),
                    format!(
                        "width = {} pixels: give at least 200 and at most {MAX_WIDTH}",
                        w.get_ref()
                    ),
                ));
            }
        }
        if let Some(limit) = &file.limits.memory_gib {
            self.positive(limit, "memory_gib")?;
            self.check_number(Some(limit.span()), "`memory_gib`", *limit.get_ref())?;
        }
        self.check_ranges()
    }

    /// Checks that a number of the scene is finite and, unless zero, of a magnitude between
    /// [`SMALLEST`] and [`LARGEST`], so that the products the model forms of moduli, lengths
    /// and loads (stiffness entries, resultants, energies) stay finite. `key` names the number
    /// and its owner ("`E` of body 'a'"); `span` is where it is written. A new numeric scene
    /// key is validated by one call of this (or of [`Scene::check_numbers`] for an array) in
    /// the range check that [`Scene::parse`] runs (`Scene::check_ranges`), plus its own sign
    /// or interval check.
    pub fn check_number(
        &self,
        span: Option<std::ops::Range<usize>>,
        key: &str,
        value: f64,
    ) -> Result<(), CliError> {
        let magnitude = value.abs();
        if !value.is_finite() {
            return Err(self.error(span, format!("{key} = {value} must be finite")));
        }
        if magnitude != 0.0 && !(SMALLEST..=LARGEST).contains(&magnitude) {
            return Err(self.error(
                span,
                format!(
                    "{key} = {value:e} is out of range: a number of a scene is 0 or of magnitude \
                     {SMALLEST:e} to {LARGEST:e} (products of moduli, lengths and loads must stay \
                     finite); change the units"
                ),
            ));
        }
        Ok(())
    }

    /// [`Scene::check_number`] for every entry of `values`.
    pub fn check_numbers(
        &self,
        span: Option<std::ops::Range<usize>>,
        key: &str,
        values: &[f64],
    ) -> Result<(), CliError> {
        values
            .iter()
            .try_for_each(|&v| self.check_number(span.clone(), key, v))
    }

    /// The range of every number of the bodies and of the contact pair.
    fn check_ranges(&self) -> Result<(), CliError> {
        for body in &self.file.bodies {
            let name = body.name.get_ref();
            let of = |key: &str| format!("`{key}` of body '{name}'");
            if let Some(r) = &body.mesh.get_ref().rectangle {
                self.check_numbers(Some(r.span()), &of("rectangle"), r.get_ref().as_flattened())?;
            }
            let m = body.material.get_ref();
            let material = Some(body.material.span());
            for (key, value) in [
                ("E", m.young),
                ("nu", m.nu),
                ("lambda", m.lambda),
                ("mu", m.mu),
            ] {
                if let Some(v) = value {
                    self.check_number(material.clone(), &of(key), v)?;
                }
            }
            if let Some(s) = &body.stabilisation {
                if let Some(scale) = s.get_ref().scale {
                    self.check_number(Some(s.span()), &of("stabilisation.scale"), scale)?;
                }
            }
            let on = |table: &str, key: &str, part: &Spanned<String>| {
                format!(
                    "`{key}` of the {table} on part '{}' of body '{name}'",
                    part.get_ref()
                )
            };
            for d in &body.dirichlet {
                let spec = d.get_ref();
                for (key, value) in [("x", spec.x), ("y", spec.y)] {
                    if let Some(v) = value {
                        let key = on("Dirichlet condition", key, &spec.part);
                        self.check_number(Some(d.span()), &key, v)?;
                    }
                }
            }
            for t in &body.traction {
                let spec = t.get_ref();
                if let Some(v) = &spec.value {
                    let key = on("traction", "value", &spec.part);
                    self.check_numbers(Some(t.span()), &key, v)?;
                }
                if let Some(p) = spec.pressure {
                    let key = on("traction", "pressure", &spec.part);
                    self.check_number(Some(t.span()), &key, p)?;
                }
            }
            if let Some(f) = &body.body_force {
                self.check_numbers(Some(f.span()), &of("body_force"), f.get_ref())?;
            }
        }
        let Some(contact) = self.file.contacts.first() else {
            return Ok(());
        };
        let c = contact.get_ref();
        let keyed = [
            ("friction_bound", &c.friction_bound),
            ("coefficient", &c.coefficient),
            ("fixed_point_tolerance", &c.fixed_point_tolerance),
            ("imposed_gap", &c.imposed_gap),
            ("max_distance", &c.max_distance),
            ("tolerance", &c.tolerance),
        ];
        for (key, value) in keyed {
            if let Some(v) = value {
                self.check_number(Some(v.span()), &format!("`{key}`"), *v.get_ref())?;
            }
        }
        for (key, p) in [("penalty", &c.penalty), ("augmentation", &c.augmentation)] {
            if let Some(p) = p {
                let values: Vec<f64> = [p.get_ref().factor, p.get_ref().value]
                    .into_iter()
                    .flatten()
                    .collect();
                self.check_numbers(Some(p.span()), &format!("`{key}`"), &values)?;
            }
        }
        if let Some(h) = &c.hertz {
            self.check_number(Some(h.span()), "hertz `radius`", h.get_ref().radius)?;
        }
        if let Some(o) = &c.obstacle {
            let spec = o.get_ref();
            let span = Some(o.span());
            if let Some(line) = &spec.line {
                self.check_numbers(span.clone(), "obstacle line `point`", &line.point)?;
                self.check_numbers(span.clone(), "obstacle line `normal`", &line.normal)?;
            }
            if let Some(circle) = &spec.circle {
                self.check_numbers(span.clone(), "obstacle circle `centre`", &circle.centre)?;
                self.check_number(span.clone(), "obstacle circle `radius`", circle.radius)?;
            }
            if let Some(points) = &spec.polyline {
                self.check_numbers(span, "obstacle `polyline`", points.as_flattened())?;
            }
        }
        Ok(())
    }

    fn check_body(&self, body: &BodySpec) -> Result<(), CliError> {
        let name = body.name.get_ref();
        let valid = !name.is_empty()
            && !name.starts_with('.')
            && name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.'));
        if !valid {
            return Err(self.error(
                Some(body.name.span()),
                format!(
                    "body name '{name}': use letters, digits, '-', '_' and '.' (it names the \
                     body's .vtu file)"
                ),
            ));
        }
        let mesh = body.mesh.get_ref();
        match (&mesh.family, &mesh.file) {
            (Some(_), Some(_)) | (None, None) => {
                return Err(self.error(
                    Some(body.mesh.span()),
                    format!(
                        "body '{name}': the mesh needs either `family` (a generator, with \
                         `rectangle` and `n`) or `file` (a Gmsh .msh file), not both"
                    ),
                ))
            }
            (Some(family), None) => {
                if let Err(e) = family.get_ref().parse::<vem_mesh::generators::MeshFamily>() {
                    return Err(self.error(Some(family.span()), e.to_string()));
                }
                if mesh.rectangle.is_none() {
                    return Err(self.error(
                        Some(body.mesh.span()),
                        format!("body '{name}': a generated mesh needs `rectangle`"),
                    ));
                }
                if mesh.n.is_none()
                    && self.file.accuracy.is_none()
                    && self.file.target_error.is_none()
                {
                    return Err(self.error(
                        Some(body.mesh.span()),
                        format!(
                            "body '{name}': a generated mesh needs `n`, or the scene's \
                             `accuracy` or `target_error` to choose it"
                        ),
                    ));
                }
            }
            (None, Some(_)) => {
                if mesh.rectangle.is_some() || mesh.n.is_some() || mesh.seed.is_some() {
                    return Err(self.error(
                        Some(body.mesh.span()),
                        format!(
                            "body '{name}': `rectangle`, `n` and `seed` belong to a generated \
                             mesh, not to a mesh `file`"
                        ),
                    ));
                }
            }
        }
        let material = body.material.get_ref();
        let pairs = (
            material.young.is_some() || material.nu.is_some(),
            material.lambda.is_some() || material.mu.is_some(),
        );
        let complete = match pairs {
            (true, false) => material.young.is_some() && material.nu.is_some(),
            (false, true) => material.lambda.is_some() && material.mu.is_some(),
            _ => false,
        };
        if !complete {
            return Err(self.error(
                Some(body.material.span()),
                format!(
                    "body '{name}': give the material as `E` and `nu`, or as `lambda` and `mu`"
                ),
            ));
        }
        if let (Some(element), Some(_)) = (&body.element, &body.stabilisation) {
            return Err(self.error(
                Some(element.span()),
                format!(
                    "body '{name}': give `element` (a registered element) or `stabilisation` \
                     (of the lowest-order VEM), not both"
                ),
            ));
        }
        if let Some(s) = &body.stabilisation {
            let spec = s.get_ref();
            if spec.kind == StabilisationKind::DRecipe
                && (spec.scaling.is_some() || spec.scale.is_some())
            {
                return Err(self.error(
                    Some(s.span()),
                    format!(
                        "body '{name}': `scaling` and `scale` apply to kind = \"dofi-dofi\" only"
                    ),
                ));
            }
        }
        for d in &body.dirichlet {
            let spec = d.get_ref();
            if spec.x.is_none() && spec.y.is_none() {
                return Err(self.error(
                    Some(d.span()),
                    format!(
                        "body '{name}': the Dirichlet condition on part '{}' prescribes nothing: \
                         give `x`, `y` or both",
                        spec.part.get_ref()
                    ),
                ));
            }
        }
        for r in &body.rigid_plate {
            let spec = r.get_ref();
            if spec.resultant_x.is_none() && spec.resultant_y.is_none() {
                return Err(self.error(
                    Some(r.span()),
                    format!(
                        "body '{name}': the rigid plate on part '{}' prescribes nothing: give \
                         `resultant_x`, `resultant_y` or both",
                        spec.part.get_ref()
                    ),
                ));
            }
        }
        for t in &body.traction {
            let spec = t.get_ref();
            if spec.value.is_some() == spec.pressure.is_some() {
                return Err(self.error(
                    Some(t.span()),
                    format!(
                        "body '{name}': the traction on part '{}' needs either `value = [gx, \
                             gy]` or `pressure = p`, not both",
                        spec.part.get_ref()
                    ),
                ));
            }
        }
        Ok(())
    }

    fn check_contact(&self, contact: &ContactSpec) -> Result<(), CliError> {
        let a = self.body_index(&contact.body)?;
        match (&contact.other_body, &contact.other_part, &contact.obstacle) {
            (Some(other), Some(_), None) => {
                if self.body_index(other)? == a {
                    return Err(self.error(
                        Some(other.span()),
                        format!(
                            "`other_body` is '{}' again: contact of a body with itself is not \
                             supported",
                            other.get_ref()
                        ),
                    ));
                }
            }
            (None, None, Some(obstacle)) => {
                self.check_obstacle(obstacle)?;
                if let Some(normal) = &contact.normal {
                    return Err(self.error(
                        Some(normal.span()),
                        "`normal` does not apply to an obstacle (its own normal is used)",
                    ));
                }
            }
            _ => {
                return Err(self.error(
                    Some(contact.body.span()),
                    "a contact pair needs either `other_body` and `other_part`, or an `obstacle`",
                ))
            }
        }
        let law = contact.law();
        let law_span = contact.law.as_ref().map(|l| l.span());
        let misplaced = |value: bool, span: Option<std::ops::Range<usize>>, key: &str| {
            if value {
                Err(self.error(
                    span,
                    format!("`{key}` does not apply to law = \"{}\"", law_name(law)),
                ))
            } else {
                Ok(())
            }
        };
        match law {
            LawKind::Tresca if contact.friction_bound.is_none() => {
                return Err(self.error(
                    law_span,
                    "law = \"tresca\" needs `friction_bound` (force per length)",
                ))
            }
            LawKind::Coulomb if contact.coefficient.is_none() => {
                return Err(self.error(
                    law_span,
                    "law = \"coulomb\" needs the friction `coefficient`",
                ))
            }
            _ => {}
        }
        let spans = |s: &Option<Spanned<f64>>| s.as_ref().map(|s| s.span());
        misplaced(
            law != LawKind::Tresca && contact.friction_bound.is_some(),
            spans(&contact.friction_bound),
            "friction_bound",
        )?;
        misplaced(
            law != LawKind::Coulomb && contact.coefficient.is_some(),
            spans(&contact.coefficient),
            "coefficient",
        )?;
        misplaced(
            law != LawKind::Coulomb && contact.fixed_point_tolerance.is_some(),
            spans(&contact.fixed_point_tolerance),
            "fixed_point_tolerance",
        )?;
        misplaced(
            law != LawKind::Coulomb && contact.fixed_point_max_iterations.is_some(),
            contact
                .fixed_point_max_iterations
                .as_ref()
                .map(|s| s.span()),
            "fixed_point_max_iterations",
        )?;
        for p in [&contact.penalty, &contact.augmentation]
            .into_iter()
            .flatten()
        {
            let spec = p.get_ref();
            if spec.factor.is_some() == spec.value.is_some() {
                return Err(self.error(
                    Some(p.span()),
                    "give either `factor` (relative to the stiffness) or `value` (absolute)",
                ));
            }
        }
        if let Some(h) = &contact.hertz {
            let r = h.get_ref().radius;
            if !(r.is_finite() && r > 0.0) {
                return Err(self.error(
                    Some(h.span()),
                    format!("hertz radius {r} must be finite and positive"),
                ));
            }
        }
        Ok(())
    }

    /// `accuracy` names a preset and leaves the solver setting to it; `target_error` is
    /// positive, reachable and used by some generated mesh without `n`.
    fn check_accuracy(&self) -> Result<(), CliError> {
        let file = &self.file;
        if let Some(accuracy) = &file.accuracy {
            if let Err(e) = accuracy.get_ref().parse::<AccuracyPreset>() {
                return Err(self.error(Some(accuracy.span()), e.to_string()));
            }
            if let Some(contact) = file.contacts.first().map(|c| c.get_ref()) {
                let spans = [
                    ("solver", contact.solver.as_ref().map(|s| s.span())),
                    ("tolerance", contact.tolerance.as_ref().map(|s| s.span())),
                ];
                if let Some((key, span)) = spans.into_iter().find(|(_, s)| s.is_some()) {
                    return Err(self.error(
                        span,
                        format!(
                            "`{key}` and the scene's `accuracy` both set the solver: \
                             `accuracy` = \"{}\" chooses it; give one of the two",
                            accuracy.get_ref()
                        ),
                    ));
                }
            }
        }
        if let Some(target) = &file.target_error {
            self.positive(target, "target_error")?;
            if let Err(e) = ErrorModel::LOWEST_ORDER_VEM.try_size_for(*target.get_ref()) {
                return Err(self.error(Some(target.span()), e.to_string()));
            }
            let chooses = file.bodies.iter().any(|b| {
                let mesh = b.mesh.get_ref();
                mesh.family.is_some() && mesh.n.is_none()
            });
            if !chooses {
                return Err(self.error(
                    Some(target.span()),
                    "`target_error` chooses the size of generated meshes without `n`, and every \
                     mesh here has `n` or is a file: drop `target_error` or an `n`",
                ));
            }
        }
        Ok(())
    }

    /// The target error generated meshes without `n` are sized for: `target_error`, else the
    /// preset's target (`None` without either).
    pub fn target_error(&self) -> Option<f64> {
        let file = &self.file;
        file.target_error
            .as_ref()
            .map(|t| *t.get_ref())
            .or_else(|| {
                file.accuracy
                    .as_ref()
                    .and_then(|a| a.get_ref().parse::<AccuracyPreset>().ok())
                    .map(AccuracyPreset::target_error)
            })
    }

    /// The preset whose solver setting the scene asks for: `accuracy`, else the one matching
    /// `target_error` when the contact pair names no `solver` or `tolerance`.
    pub fn accuracy_preset(&self) -> Option<AccuracyPreset> {
        let file = &self.file;
        if let Some(preset) = file
            .accuracy
            .as_ref()
            .and_then(|a| a.get_ref().parse::<AccuracyPreset>().ok())
        {
            return Some(preset);
        }
        let explicit = file
            .contacts
            .first()
            .is_some_and(|c| c.get_ref().solver.is_some() || c.get_ref().tolerance.is_some());
        match (&file.target_error, explicit) {
            (Some(target), false) => Some(AccuracyPreset::for_target(*target.get_ref())),
            _ => None,
        }
    }

    fn check_obstacle(&self, obstacle: &Spanned<ObstacleSpec>) -> Result<(), CliError> {
        let spec = obstacle.get_ref();
        let given = [
            spec.line.is_some(),
            spec.circle.is_some(),
            spec.polyline.is_some(),
        ];
        if given.iter().filter(|&&g| g).count() != 1 {
            return Err(self.error(
                Some(obstacle.span()),
                "an obstacle is exactly one of `line = { point, normal }`, `circle = { centre, \
                 radius }` or `polyline = [[x, y], ...]`",
            ));
        }
        // The values themselves are checked by the contact library when the obstacle is built.
        Ok(())
    }

    fn positive(&self, value: &Spanned<f64>, key: &str) -> Result<(), CliError> {
        let v = *value.get_ref();
        if v.is_finite() && v > 0.0 {
            Ok(())
        } else {
            Err(self.error(
                Some(value.span()),
                format!("`{key}` = {v} must be finite and positive"),
            ))
        }
    }
}

/// The law's name in the scene file.
pub(crate) fn law_name(law: LawKind) -> &'static str {
    match law {
        LawKind::Frictionless => "frictionless",
        LawKind::Tresca => "tresca",
        LawKind::Coulomb => "coulomb",
    }
}

/// `['a', 'b']` for error messages.
pub(crate) fn list<S: AsRef<str>>(names: &[S]) -> String {
    let quoted: Vec<String> = names.iter().map(|n| format!("'{}'", n.as_ref())).collect();
    format!("[{}]", quoted.join(", "))
}

/// Deserialisers of fixed-length arrays that refuse any other length: serde's own `[T; N]`
/// reads the first `N` entries and ignores the rest, so `[1, 2, 3]` would silently be
/// `[1, 2]`. The error is reported by the TOML parser at the array, with its line.
mod exact {
    use serde::de::Error;
    use serde::{Deserialize, Deserializer};
    use toml::Spanned;

    /// `[T; N]` from an array of exactly `N` entries.
    struct Exact<T, const N: usize>([T; N]);

    impl<'de, T: Deserialize<'de>, const N: usize> Deserialize<'de> for Exact<T, N> {
        fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
            let entries = Vec::<T>::deserialize(deserializer)?;
            let found = entries.len();
            entries.try_into().map(Exact).map_err(|_| {
                D::Error::custom(format!(
                    "an array of {found} entries where exactly {N} are expected"
                ))
            })
        }
    }

    /// A point or vector `[x, y]`: a rectangle corner is a point too.
    type Pair = Exact<f64, 2>;

    /// Two opposite corners of a rectangle.
    type Corners = [[f64; 2]; 2];

    pub(super) fn pair<'de, D: Deserializer<'de>>(d: D) -> Result<[f64; 2], D::Error> {
        Pair::deserialize(d).map(|p| p.0)
    }

    pub(super) fn optional<'de, D: Deserializer<'de>>(d: D) -> Result<Option<[f64; 2]>, D::Error> {
        pair(d).map(Some)
    }

    pub(super) fn optional_spanned<'de, D: Deserializer<'de>>(
        d: D,
    ) -> Result<Option<Spanned<[f64; 2]>>, D::Error> {
        let value = Spanned::<Pair>::deserialize(d)?;
        let span = value.span();
        Ok(Some(Spanned::new(span, value.into_inner().0)))
    }

    pub(super) fn optional_spanned_rectangle<'de, D: Deserializer<'de>>(
        d: D,
    ) -> Result<Option<Spanned<Corners>>, D::Error> {
        let value = Spanned::<Exact<Pair, 2>>::deserialize(d)?;
        let span = value.span();
        let [a, b] = value.into_inner().0;
        Ok(Some(Spanned::new(span, [a.0, b.0])))
    }

    pub(super) fn optional_points<'de, D: Deserializer<'de>>(
        d: D,
    ) -> Result<Option<Vec<[f64; 2]>>, D::Error> {
        let points = Vec::<Pair>::deserialize(d)?;
        Ok(Some(points.into_iter().map(|p| p.0).collect()))
    }
}
