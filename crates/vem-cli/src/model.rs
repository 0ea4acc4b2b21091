//! From a parsed [`Scene`] to the problem built by `vem_scene`, and what `vem check` reports
//! of it.

use std::fmt;

use vem_mesh::interface::{boundary_chain, insert_interface_nodes};
use vem_scene::{BuildOptions, KeyPath, ModelBody, Registries};

use crate::{CliError, Outcome, Scene};

/// A scene built into library objects, ready to solve.
#[derive(Debug, Clone)]
pub struct Model {
    scene: Scene,
    model: vem_scene::Model,
}

impl Model {
    /// The interface nodes of the pair `c` in space: the node pairs of the surface overlay of
    /// two bodies, or the vertices of the contact part facing an obstacle.
    fn interface_nodes_3d(
        &self,
        c: &vem_scene::ModelContact,
        spec: &vem_scene::description::ContactDescription,
        path: &KeyPath,
    ) -> Result<usize, CliError> {
        let a = &self.model.bodies_3d()[c.body].body;
        let mesh_error = |context: String| move |source| CliError::Mesh { context, source };
        match c.other {
            Some(other) => {
                let b = &self.model.bodies_3d()[other].body;
                let mut options = vem_mesh::interface::InterfaceOptions::builder();
                if let Some(d) = spec.max_distance {
                    options = options.max_distance(d);
                }
                let options = options.build().map_err(|e| {
                    self.scene
                        .error_at(&self.model.written(&path.at("max_distance")), e.to_string())
                })?;
                let other_part = spec.other_part.as_deref().unwrap_or_default();
                vem_mesh::polyhedral::overlay::insert_surface_overlay(
                    a.mesh(),
                    &spec.part,
                    b.mesh(),
                    other_part,
                    &options,
                )
                .map(|overlay| overlay.pairs.len())
                .map_err(mesh_error(format!("interface of {}", c.description)))
            }
            None => vem_mesh::polyhedral::overlay::boundary_surface(a.mesh(), &spec.part)
                .map(|nodes| nodes.len())
                .map_err(mesh_error(format!("contact part of '{}'", a.name()))),
        }
    }

    /// Generates or reads every mesh, checks every part name against its mesh and builds the
    /// bodies, the contact problem and the solver's choice, with the built-in solvers, elements
    /// and laws.
    pub fn build(scene: &Scene) -> Result<Self, CliError> {
        Self::build_with(scene, &Registries::default())
    }

    /// As [`Model::build`], with the solvers, elements and laws of `registries`: the scene's
    /// `solver`, `element` and `law` keys may name one's own.
    pub fn build_with(scene: &Scene, registries: &Registries) -> Result<Self, CliError> {
        let options = BuildOptions {
            base: scene.base(),
            registries: registries.clone(),
            memory_limit: Some(scene.memory_limit()),
        };
        let model = vem_scene::Model::build(scene.file(), &options).map_err(|e| scene.error(e))?;
        Ok(Self {
            scene: scene.clone(),
            model,
        })
    }

    /// The scene this model was built from.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The problem as built by `vem_scene`.
    pub fn problem(&self) -> &vem_scene::Model {
        &self.model
    }

    /// The bodies in the plane, in the order of the scene file (none in a scene in space).
    pub fn bodies(&self) -> &[ModelBody] {
        self.model.bodies()
    }

    /// The bodies in space, in the order of the scene file (none in a scene in the plane).
    pub fn bodies_3d(&self) -> &[ModelBody<3>] {
        self.model.bodies_3d()
    }

    /// Solves the scene.
    pub fn solve(&self) -> Result<Outcome, CliError> {
        let outcome = self.model.solve().map_err(|e| self.scene.error(e))?;
        Ok(Outcome::new(outcome, &self.model))
    }

    /// A description of what will be modelled, with the A1 quality figures of every mesh and
    /// the size of every contact interface, without solving (`vem check`).
    pub fn check(&self) -> Result<CheckReport, CliError> {
        let scene = self.model.scene();
        let bodies = self
            .model
            .bodies()
            .iter()
            .zip(&scene.bodies)
            .map(|(b, spec)| {
                let mesh = b.body.mesh();
                CheckedBody {
                    name: b.body.name().to_string(),
                    mesh_source: b.mesh_source.clone(),
                    vertices: mesh.n_vertices(),
                    polygons: mesh.n_polygons(),
                    parts: mesh
                        .parts()
                        .iter()
                        .map(|p| (p.name.clone(), p.edges.len()))
                        .collect(),
                    quality: mesh.quality(),
                    material: vem_scene::describe_material(&b.body),
                    element: b.element.clone(),
                    conditions: describe_conditions(spec),
                    warnings: b.warnings.clone(),
                }
            })
            .collect();
        let bodies_3d = self
            .model
            .bodies_3d()
            .iter()
            .zip(&scene.bodies)
            .map(|(b, spec)| {
                let mesh = b.body.mesh();
                CheckedBody {
                    name: b.body.name().to_string(),
                    mesh_source: b.mesh_source.clone(),
                    vertices: mesh.n_vertices(),
                    polygons: mesh.n_cells(),
                    parts: mesh
                        .parts()
                        .iter()
                        .map(|p| (p.name.clone(), p.faces.len()))
                        .collect(),
                    quality: mesh.quality(),
                    material: vem_scene::describe_material(&b.body),
                    element: b.element.clone(),
                    conditions: describe_conditions(spec),
                    warnings: b.warnings.clone(),
                }
            })
            .collect();
        let mut contacts = Vec::new();
        for (k, (c, spec)) in self
            .model
            .contacts()
            .iter()
            .zip(&scene.contacts)
            .enumerate()
        {
            let path = KeyPath::key("contact").index(k);
            let interface_nodes = if self.model.dimension() == 3 {
                self.interface_nodes_3d(c, spec, &path)?
            } else {
                let a = &self.model.bodies()[c.body].body;
                match c.other {
                    Some(other) => {
                        let b = &self.model.bodies()[other].body;
                        let mut options = vem_mesh::interface::InterfaceOptions::builder();
                        if let Some(d) = spec.max_distance {
                            options = options.max_distance(d);
                        }
                        let options = options.build().map_err(|e| {
                            self.scene.error_at(
                                &self.model.written(&path.at("max_distance")),
                                e.to_string(),
                            )
                        })?;
                        let other_part = spec.other_part.as_deref().unwrap_or_default();
                        insert_interface_nodes(a.mesh(), &spec.part, b.mesh(), other_part, &options)
                            .map_err(|source| CliError::Mesh {
                                context: format!("interface of {}", c.description),
                                source,
                            })?
                            .pairs
                            .len()
                    }
                    None => boundary_chain(a.mesh(), &spec.part)
                        .map_err(|source| CliError::Mesh {
                            context: format!("contact part of '{}'", a.name()),
                            source,
                        })?
                        .len(),
                }
            };
            // The law as built (the scene's pairs are the problem's, in order).
            let k = contacts.len();
            let built = self
                .model
                .contact_problem()
                .and_then(|(problem, _)| problem.pairs().get(k))
                .map(|pair| (pair.law().has_friction(), pair.law().describe()))
                .or_else(|| {
                    self.model
                        .contact_problem_3d()
                        .and_then(|(problem, _)| problem.pairs().get(k))
                        .map(|pair| (pair.law().has_friction(), pair.law().describe()))
                });
            contacts.push(CheckedContact {
                description: c.description.clone(),
                friction: built.as_ref().is_some_and(|(friction, _)| *friction),
                law: built.map_or_else(|| "frictionless".to_string(), |(_, law)| law),
                interface_nodes,
            });
        }
        Ok(CheckReport {
            scene: self.scene.path().display().to_string(),
            title: self.scene.title(),
            bodies,
            bodies_3d,
            contacts,
            solver: self.model.solver().name.clone(),
            notes: self
                .model
                .deprecations()
                .iter()
                .map(ToString::to_string)
                .collect(),
        })
    }
}

/// The boundary conditions of a body as written in the scene.
fn describe_conditions(spec: &vem_scene::description::BodyDescription) -> Vec<String> {
    let mut lines = Vec::new();
    for d in &spec.dirichlet {
        let parts: Vec<String> = [("x", &d.x), ("y", &d.y), ("z", &d.z)]
            .into_iter()
            .filter_map(|(c, v)| v.as_ref().map(|v| format!("u_{c} = {v}")))
            .collect();
        lines.push(format!("dirichlet on '{}': {}", d.part, parts.join(", ")));
    }
    for r in &spec.rigid_plate {
        let parts: Vec<String> = [
            ("x", r.resultant_x),
            ("y", r.resultant_y),
            ("z", r.resultant_z),
        ]
        .into_iter()
        .filter_map(|(c, v)| v.map(|v| format!("R_{c} = {v}")))
        .collect();
        lines.push(format!("rigid plate on '{}': {}", r.part, parts.join(", ")));
    }
    for t in &spec.traction {
        match (&t.value, t.pressure) {
            (Some(value), _) => lines.push(format!("traction on '{}': {value:?}", t.part)),
            (None, Some(p)) => lines.push(format!("pressure on '{}': {p}", t.part)),
            (None, None) => {}
        }
    }
    if let Some(f) = &spec.body_force {
        lines.push(format!("body force: {f:?}"));
    }
    lines
}

/// What `vem check` reports for one body: in the plane, or in space with the figures of
/// polyhedra (`CheckedBody<PolyhedralQualitySummary>`; `polygons` are then its polyhedra and
/// the parts count faces).
#[derive(Debug, Clone)]
pub struct CheckedBody<Q = vem_mesh::quality::QualitySummary> {
    /// Name.
    pub name: String,
    /// Where the mesh came from.
    pub mesh_source: String,
    /// Vertices.
    pub vertices: usize,
    /// Polygons.
    pub polygons: usize,
    /// Boundary parts and their numbers of edges (faces in space).
    pub parts: Vec<(String, usize)>,
    /// A1 figures (shape-regularity figures of the polyhedra in space).
    pub quality: Q,
    /// The material.
    pub material: String,
    /// The element (and its stabilisation).
    pub element: String,
    /// Boundary conditions and body force.
    pub conditions: Vec<String>,
    /// Warnings about the body's model (a locking element close to incompressibility).
    pub warnings: Vec<String>,
}

/// One body of `vem check`; `words`: what its parts count, what its cells are, the title of
/// its quality figures.
fn write_body<Q: fmt::Display>(
    f: &mut fmt::Formatter<'_>,
    b: &CheckedBody<Q>,
    words: [&str; 3],
) -> fmt::Result {
    let [pieces, cells, quality] = words;
    writeln!(f, "\nbody '{}': {}", b.name, b.mesh_source)?;
    let parts: Vec<String> = b
        .parts
        .iter()
        .map(|(name, count)| format!("{name} ({count} {pieces})"))
        .collect();
    writeln!(
        f,
        "  {} vertices, {} {cells}; parts: {}",
        b.vertices,
        b.polygons,
        parts.join(", ")
    )?;
    writeln!(f, "  material: {}; element: {}", b.material, b.element)?;
    for warning in &b.warnings {
        writeln!(f, "  warning: {warning}")?;
    }
    for c in &b.conditions {
        writeln!(f, "  {c}")?;
    }
    writeln!(f, "  {quality}:")?;
    for line in b.quality.to_string().lines() {
        writeln!(f, "    {line}")?;
    }
    Ok(())
}

/// What `vem check` reports for a contact pair.
#[derive(Debug, Clone)]
pub struct CheckedContact {
    /// Which parts face what.
    pub description: String,
    /// The law's name.
    pub law: String,
    /// True when tangential rows will be built.
    pub friction: bool,
    /// Interface nodes (node pairs, or body nodes facing the obstacle): one normal row each.
    pub interface_nodes: usize,
}

/// What `vem check` prints: the meshes, their quality and what will be modelled.
#[derive(Debug, Clone)]
pub struct CheckReport {
    /// The scene file.
    pub scene: String,
    /// Its title.
    pub title: String,
    /// Every body in the plane.
    pub bodies: Vec<CheckedBody>,
    /// Every body in space.
    pub bodies_3d: Vec<CheckedBody<vem_mesh::polyhedral::quality::PolyhedralQualitySummary>>,
    /// Every contact pair.
    pub contacts: Vec<CheckedContact>,
    /// The contact solver's registry name.
    pub solver: String,
    /// Notes about earlier keys of the scene and their new places.
    pub notes: Vec<String>,
}

impl fmt::Display for CheckReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "scene {} ({}): valid", self.scene, self.title)?;
        for note in &self.notes {
            writeln!(f, "note: {note}")?;
        }
        for b in &self.bodies {
            write_body(f, b, ["edges", "polygons", "mesh quality (A1)"])?;
        }
        for b in &self.bodies_3d {
            write_body(f, b, ["faces", "polyhedra", "mesh quality"])?;
        }
        writeln!(f)?;
        if self.contacts.is_empty() {
            return writeln!(
                f,
                "model: no contact pair: each body is solved as plain linear elasticity"
            );
        }
        let any_friction = self.contacts.iter().any(|c| c.friction);
        for c in &self.contacts {
            writeln!(f, "model: {}, law {}", c.description, c.law)?;
            // Tangential rows are built for every node of a problem with friction somewhere
            // (a frictionless pair's bounds are 0).
            let tangential = if any_friction {
                format!("{} tangential rows", c.interface_nodes)
            } else {
                "no tangential rows (frictionless)".to_string()
            };
            writeln!(
                f,
                "  {} interface nodes: {} normal rows, {tangential}",
                c.interface_nodes, c.interface_nodes
            )?;
        }
        writeln!(f, "solver: {}", self.solver)
    }
}
