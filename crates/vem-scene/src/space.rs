//! Bodies in space: the meshes, bodies, solves and summaries of a scene in three dimensions.
//!
//! A scene is in space when its meshes are: generated on a `box` (the polyhedral families of
//! `vem_mesh::generators::polyhedral`) or read from a Gmsh file of volume elements (its named
//! physical surfaces are the parts). The keys are those of the plane with a third component:
//! `z` of a Dirichlet condition, `resultant_z` of a rigid plate, `[gx, gy, gz]` of a traction and
//! a body force, expressions of `x, y, z`; the material is the full three-dimensional law (no
//! `plane`); the elements are the registry's elements on polyhedra under the planar names.
//! Everything above the element is the dimension-generic code of `vem_elastic::ElasticBody`.

use std::path::Path;
use std::time::Instant;

use vem_elastic::{CholeskySolver, Component, Dirichlet, ElasticBody, Material, Plane, Solution};
use vem_mesh::generators::polyhedral::{Cuboid, PolyhedralFamily};
use vem_mesh::polyhedral::quality::{cell_qualities, CellQuality};
use vem_mesh::{Mesh, MeshError, Point3, PolyhedralMesh, Vector3};
use vem_space::ElementRegistry;

use crate::build::{
    element_choice, locate_elastic, locking_warning, nearly_incompressible, registry_error,
    ModelBody,
};
use crate::check::list;
use crate::description::{BodyDescription, Scene};
use crate::solve::{
    describe_material, reaction_summaries, BodySummary, RunSummary, RunTimes, SolvedBody,
};
use crate::{KeyPath, Model, Outcome, SceneError};

/// A body's mesh as generated, read or given inline: in the plane or in space.
#[derive(Debug, Clone)]
pub enum BuiltMesh {
    /// Polygons.
    Plane(Mesh),
    /// Polyhedra.
    Space(PolyhedralMesh),
}

impl BuiltMesh {
    /// 2 or 3.
    pub fn dimension(&self) -> usize {
        match self {
            BuiltMesh::Plane(_) => 2,
            BuiltMesh::Space(_) => 3,
        }
    }

    /// The mesh as the keys of a mesh given inline: `vertices`, the cells (`polygons`, or
    /// `polyhedra` as outward face loops) and the boundary parts (`part_edges`, or
    /// `part_faces` as face loops). [`crate::inline_mesh`] of it builds the same mesh: the
    /// same vertices and cells in the same order (in space, faces numbered as they first
    /// appear in the cells).
    pub fn to_inline(&self) -> crate::MeshDescription {
        let mut description = crate::MeshDescription::default();
        match self {
            BuiltMesh::Plane(mesh) => {
                description.vertices =
                    Some(mesh.vertices().iter().map(|p| vec![p.x, p.y]).collect());
                description.polygons = Some(mesh.polygons().map(<[usize]>::to_vec).collect());
                description.part_edges = mesh
                    .part_specs()
                    .into_iter()
                    .map(|part| (part.name, part.edges))
                    .collect();
            }
            BuiltMesh::Space(mesh) => {
                description.vertices = Some(
                    mesh.vertices()
                        .iter()
                        .map(|p| vec![p.x, p.y, p.z])
                        .collect(),
                );
                description.polyhedra = Some(
                    (0..mesh.n_cells())
                        .map(|c| mesh.cell_face_loops(c))
                        .collect(),
                );
                description.part_faces = mesh
                    .parts()
                    .iter()
                    .map(|part| {
                        let faces = part.faces.iter().map(|&f| mesh.face(f).to_vec()).collect();
                        (part.name.clone(), faces)
                    })
                    .collect();
            }
        }
        description
    }

    /// Number of simplices: triangles in the plane, tetrahedra in space (the cells whose
    /// virtual element space is P1, on which every lowest-order element locks close to
    /// incompressibility).
    pub(crate) fn n_simplices(&self) -> usize {
        match self {
            BuiltMesh::Plane(mesh) => mesh.polygons().filter(|p| p.len() == 3).count(),
            BuiltMesh::Space(mesh) => tetrahedra(mesh),
        }
    }

    /// The mesh with the midpoint of every edge inserted as a vertex
    /// ([`Mesh::with_edge_midpoints`], [`PolyhedralMesh::with_edge_midpoints`]).
    pub(crate) fn with_edge_midpoints(&self) -> Result<Self, MeshError> {
        Ok(match self {
            BuiltMesh::Plane(mesh) => BuiltMesh::Plane(mesh.with_edge_midpoints()?),
            BuiltMesh::Space(mesh) => BuiltMesh::Space(mesh.with_edge_midpoints()?),
        })
    }
}

/// Number of tetrahedra (cells of four vertices) of `mesh`.
fn tetrahedra(mesh: &PolyhedralMesh) -> usize {
    (0..mesh.n_cells())
        .filter(|&c| mesh.cell_vertices(c).len() == 4)
        .count()
}

/// A Gmsh file: of volume elements, a polyhedral mesh; otherwise a planar one (whose reader
/// reports what it refuses).
pub(crate) fn read_gmsh(path: &Path) -> Result<BuiltMesh, MeshError> {
    let bytes = std::fs::read(path).map_err(|e| MeshError::Read {
        path: path.to_path_buf(),
        reason: format!("cannot read the file: {e}"),
    })?;
    // Parsed once: the elements decide which reader turns the file into a mesh.
    let file = vem_mesh::io::read_msh_bytes(&bytes).map_err(|e| MeshError::Read {
        path: path.to_path_buf(),
        reason: e.to_string(),
    })?;
    if file.elements.iter().any(|e| e.entity_dim == 3) {
        vem_mesh::io::polyhedral_mesh_from_msh(&file, path).map(BuiltMesh::Space)
    } else {
        vem_mesh::io::mesh_from_msh(&file, path).map(BuiltMesh::Plane)
    }
}

/// The polyhedral mesh of a body generated on a `box` (checked by `check`), and where it came
/// from.
pub(crate) fn generate(
    spec: &BodyDescription,
    path: &KeyPath,
) -> Result<(PolyhedralMesh, String), SceneError> {
    let name = &spec.name;
    let mesh = &spec.mesh;
    let (Some(family), Some(corners), Some(n)) = (&mesh.family, &mesh.cuboid, mesh.n) else {
        return Err(SceneError::at(path.at("mesh"), "incomplete mesh"));
    };
    let family: PolyhedralFamily = family
        .parse()
        .map_err(|e: MeshError| SceneError::at(path.at("mesh").at("family"), e.to_string()))?;
    let corner = |k: usize| Point3::new(corners[k][0], corners[k][1], corners[k][2]);
    let (a, b) = (corner(0), corner(1));
    if (0..3).any(|i| a[i] >= b[i]) {
        return Err(SceneError::at(
            path.at("mesh").at("box"),
            format!("body '{name}': the box needs its first corner below its second in x, y and z"),
        ));
    }
    let seed = mesh.seed.unwrap_or(1);
    let generated = family
        .generate(&Cuboid::new(a, b), n, seed)
        .map_err(|e| SceneError::at(path.at("mesh"), format!("body '{name}': {e}")))?;
    let random = if family.is_random() {
        format!(", seed {seed}")
    } else {
        String::new()
    };
    Ok((
        generated,
        format!(
            "{family}, n = {n}{random}, on [{}, {}] x [{}, {}] x [{}, {}]",
            a.x, b.x, a.y, b.y, a.z, b.z
        ),
    ))
}

/// `mesh` with the body's further parts (`mesh.parts`): the boundary faces whose vertices all
/// lie in each part's box (widened by 1e-9 of its size), among the faces of `of` when given.
pub(crate) fn with_sub_parts(
    mut mesh: PolyhedralMesh,
    spec: &BodyDescription,
    path: &KeyPath,
) -> Result<PolyhedralMesh, SceneError> {
    let name = &spec.name;
    for (k, part) in spec.mesh.parts.iter().enumerate() {
        let at = path.at("mesh").at("parts").index(k);
        let of: Option<Vec<usize>> = match &part.of {
            Some(of) => {
                check_part(&mesh, name, of, &at.at("of"))?;
                let mut faces = mesh
                    .part_faces(of)
                    .map(<[usize]>::to_vec)
                    .unwrap_or_default();
                faces.sort_unstable();
                Some(faces)
            }
            None => None,
        };
        let (lo, hi) = (&part.bounds[0], &part.bounds[1]);
        let size = (0..3)
            .map(|i| (hi[i] - lo[i]).abs())
            .fold(f64::MIN_POSITIVE, f64::max);
        let slack = 1e-9 * size;
        let inside = |p: &Point3| (0..3).all(|i| p[i] >= lo[i] - slack && p[i] <= hi[i] + slack);
        // The faces of `of` by their vertex coordinates (the selector sees coordinates).
        let of_faces: Option<Vec<Vec<Point3>>> = of
            .as_ref()
            .map(|faces| faces.iter().map(|&f| mesh.face_points(f)).collect());
        let cut = mesh
            .with_part_where(&part.name, |points| {
                points.iter().all(inside)
                    && of_faces
                        .as_ref()
                        .is_none_or(|faces| faces.iter().any(|f| f.as_slice() == points))
            })
            .map_err(|e| SceneError::at(at.at("name"), format!("body '{name}': {e}")))?;
        if cut.part_faces(&part.name).map_or(0, <[usize]>::len) == 0 {
            return Err(SceneError::at(
                at.at("box"),
                format!(
                    "body '{name}': part '{}' has no boundary face{} with all its vertices in its \
                     box",
                    part.name,
                    part.of
                        .as_ref()
                        .map_or(String::new(), |of| format!(" of part '{of}'"))
                ),
            ));
        }
        mesh = cut;
    }
    Ok(mesh)
}

/// Checks that `part` names a boundary part of `mesh`; the error lists the parts.
fn check_part(
    mesh: &PolyhedralMesh,
    body: &str,
    part: &str,
    path: &KeyPath,
) -> Result<(), SceneError> {
    if mesh.part(part).is_ok() {
        return Ok(());
    }
    Err(SceneError::at(
        path.clone(),
        format!(
            "body '{body}' has no boundary part named '{part}'; its mesh has {}",
            list(&mesh.part_names())
        ),
    ))
}

/// As [`check_part`], and the part must have a face: an empty part (a physical surface group
/// of the mesh file `source` without elements) is named with its mesh.
fn check_faces(
    mesh: &PolyhedralMesh,
    body: &str,
    source: &str,
    part: &str,
    path: &KeyPath,
) -> Result<(), SceneError> {
    check_part(mesh, body, part, path)?;
    if mesh.part_faces(part).is_ok_and(<[usize]>::is_empty) {
        return Err(SceneError::at(
            path.clone(),
            format!(
                "body '{body}': part '{part}' of its mesh ({source}) is empty: a physical \
                 surface group without elements; give the group elements in the mesh, or name \
                 another part"
            ),
        ));
    }
    Ok(())
}

/// The material of a body in space: `E` and `nu`, or `lambda` and `mu` (checked by `check`).
fn material(spec: &BodyDescription, path: &KeyPath) -> Result<Material, SceneError> {
    let m = spec.material;
    match (m.young, m.nu, m.lambda, m.mu) {
        (Some(e), Some(nu), None, None) => Material::isotropic(e, nu),
        (None, None, Some(lambda), Some(mu)) => Material::from_lame(lambda, mu, Plane::Strain),
        _ => return Err(SceneError::at(path.at("material"), "incomplete material")),
    }
    .map_err(|e| SceneError::at(path.at("material"), format!("body '{}': {e}", spec.name)))
}

/// The body in space of `spec` on `mesh`: material, element (by the registry's elements on
/// polyhedra, and the rule of the plane: the locking-free default close to incompressibility,
/// with the edge midpoints the scene inserted on a mesh with tetrahedra when `midpoints`),
/// conditions by part.
pub(crate) fn build_body(
    spec: &BodyDescription,
    mesh: PolyhedralMesh,
    source: String,
    midpoints: bool,
    elements: &ElementRegistry,
    scene: &Scene,
    path: &KeyPath,
) -> Result<ModelBody<3>, SceneError> {
    let name = spec.name.clone();
    let material = material(spec, path)?;
    let nearly = nearly_incompressible(&material);
    let simplices = tetrahedra(&mesh);
    let (choice, why) = element_choice(spec, nearly, midpoints, 3);
    let element = elements
        .make_polyhedral_choice(&choice)
        .map_err(|e| registry_error(e, &path.at("element")))?;
    let description = match (why, elements.polyhedral_summary(&choice.name)) {
        (Some(why), Some(s)) => format!("{why} ({s})"),
        (Some(why), None) => why,
        (None, Some(s)) => format!("{}: {s}", element.name()),
        (None, None) => element.name().to_string(),
    };
    let warnings: Vec<String> = locking_warning(spec, element.name(), nearly, simplices, 3)
        .into_iter()
        .collect();
    for (k, d) in spec.dirichlet.iter().enumerate() {
        check_faces(
            &mesh,
            &name,
            &source,
            &d.part,
            &path.at("dirichlet").index(k).at("part"),
        )?;
    }
    for (k, r) in spec.rigid_plate.iter().enumerate() {
        check_faces(
            &mesh,
            &name,
            &source,
            &r.part,
            &path.at("rigid_plate").index(k).at("part"),
        )?;
    }
    let mut pressures = Vec::new();
    for (k, t) in spec.traction.iter().enumerate() {
        let at = path.at("traction").index(k);
        check_faces(&mesh, &name, &source, &t.part, &at.at("part"))?;
        if let Some(p) = t.pressure {
            pressures.push(-p * planar_normal(&mesh, &name, &t.part, &at.at("pressure"))?);
        }
    }
    let t = 1.0;
    let mut builder = ElasticBody::builder_polyhedral(name.clone(), mesh, material, element);
    if let Some(points) = spec.traction_points {
        builder = builder.traction_points(points);
    }
    for d in &spec.dirichlet {
        let values = [d.x.clone(), d.y.clone(), d.z.clone()];
        let given: Vec<usize> = (0..3).filter(|&i| values[i].is_some()).collect();
        let value = move |p: Point3| {
            let at = [p.x, p.y, p.z];
            Vector3::from_fn(|i, _| values[i].as_ref().map_or(0.0, |v| v.at(&at, t)))
        };
        let value = std::sync::Arc::new(value);
        if given.len() == 3 {
            let value = std::sync::Arc::clone(&value);
            builder = builder.dirichlet(Dirichlet::with_values(
                d.part.clone(),
                Component::All,
                move |p| value(p),
            ));
        } else {
            for &i in &given {
                let value = std::sync::Arc::clone(&value);
                builder = builder.dirichlet(Dirichlet::with_values(
                    d.part.clone(),
                    component(i),
                    move |p| value(p),
                ));
            }
        }
    }
    for r in &spec.rigid_plate {
        let resultants = [r.resultant_x, r.resultant_y, r.resultant_z];
        let resultant = Vector3::from_fn(|i, _| resultants[i].unwrap_or(0.0));
        let given: Vec<usize> = (0..3).filter(|&i| resultants[i].is_some()).collect();
        if given.len() == 3 {
            builder = builder.dirichlet(Dirichlet::rigid_plate(
                r.part.clone(),
                Component::All,
                resultant,
            ));
        } else {
            for &i in &given {
                builder = builder.dirichlet(Dirichlet::rigid_plate(
                    r.part.clone(),
                    component(i),
                    resultant,
                ));
            }
        }
    }
    let mut pressures = pressures.into_iter();
    for traction in &spec.traction {
        builder = match &traction.value {
            Some(value) => {
                let value = value.clone();
                builder.traction(traction.part.clone(), move |p| {
                    let at = [p.x, p.y, p.z];
                    Vector3::from_fn(|i, _| value.at(&at, t, i))
                })
            }
            None => match pressures.next() {
                Some(g) => builder.traction(traction.part.clone(), move |_| g),
                None => builder,
            },
        };
    }
    if let Some(force) = &spec.body_force {
        let force = force.clone();
        builder = builder.body_force(move |p| {
            let at = [p.x, p.y, p.z];
            Vector3::from_fn(|i, _| force.at(&at, t, i))
        });
    }
    let body = builder.build().map_err(|e| {
        locate_elastic(scene, e).unwrap_or_else(|e| SceneError::at(path.clone(), e))
    })?;
    Ok(ModelBody {
        body,
        mesh_source: source,
        element: description,
        predicted_error: None,
        warnings,
    })
}

/// The single component `i` (0, 1, 2).
fn component(i: usize) -> Component {
    match i {
        0 => Component::X,
        1 => Component::Y,
        _ => Component::Z,
    }
}

/// The outward unit normal of a planar part (all its faces with one normal, to 1e-9): a
/// normal pressure in space is taken on such parts.
fn planar_normal(
    mesh: &PolyhedralMesh,
    body: &str,
    part: &str,
    path: &KeyPath,
) -> Result<Vector3, SceneError> {
    let faces = mesh.part_faces(part).unwrap_or_default();
    let Some(&first) = faces.first() else {
        return Err(SceneError::at(
            path.clone(),
            format!("body '{body}': part '{part}' has no face to press on"),
        ));
    };
    let normal = mesh.face_normal(first);
    if let Some(&other) = faces
        .iter()
        .find(|&&f| (mesh.face_normal(f) - normal).norm() > 1e-9)
    {
        let n = mesh.face_normal(other);
        return Err(SceneError::at(
            path.clone(),
            format!(
                "body '{body}': a normal pressure in space is taken on a planar part for now, and \
                 part '{part}' turns (face normals ({:.3}, {:.3}, {:.3}) and ({:.3}, {:.3}, \
                 {:.3})): give the traction as `value = [gx, gy, gz]`, or cut the part into \
                 planar ones (`mesh.parts`)",
                normal.x, normal.y, normal.z, n.x, n.y, n.z
            ),
        ));
    }
    Ok(normal)
}

/// Solves the scene in space: the bodies in contact by the contact library (every pair
/// together, along the load history, as in the plane), every other body as plain elasticity
/// (assembly and sparse Cholesky), and summarises.
pub(crate) fn solve(model: &Model, started: Instant) -> Result<Outcome, SceneError> {
    let scene = model.scene();
    let located = |e: SceneError| SceneError {
        path: model.written(&e.path),
        ..e
    };
    let mut times = RunTimes {
        mesh_s: model.mesh_time().as_secs_f64(),
        ..RunTimes::default()
    };
    let mut slots: Vec<Option<(ElasticBody<3>, Solution<3>)>> = vec![None; model.bodies_3d().len()];
    let mut contact = None;
    let mut contact_bodies = Vec::new();
    let mut history = Vec::new();
    let mut earlier_steps = Vec::new();
    if let Some((problem, indices)) = model.contact_problem_3d() {
        let run = model.solve_contact(problem, indices, &mut times)?;
        for (b, &index) in run.bodies.into_iter().zip(indices) {
            slots[index] = Some(b);
        }
        history = run.history;
        earlier_steps = run.earlier;
        contact_bodies = indices.to_vec();
        contact = Some(run.result);
    }
    let mut bodies = Vec::with_capacity(model.bodies_3d().len());
    for (index, (built, slot)) in model.bodies_3d().iter().zip(slots).enumerate() {
        let elastic = |e| {
            located(
                locate_elastic(scene, e)
                    .unwrap_or_else(|text| SceneError::at(KeyPath::key("body").index(index), text)),
            )
        };
        let (body, solution) = match slot {
            Some(solved) => solved,
            None => {
                let body = &built.body;
                let load_factor = crate::history::final_factor(scene, index).map_err(located)?;
                let start = Instant::now();
                let system = body.assemble().map_err(elastic)?;
                times.assembly_s += start.elapsed().as_secs_f64();
                let start = Instant::now();
                let solution = body
                    .solve_system(&system, &mut CholeskySolver::default())
                    .map_err(elastic)?;
                let solution = if load_factor == 1.0 {
                    solution
                } else {
                    let scaled: Vec<f64> = solution
                        .displacement()
                        .iter()
                        .map(|u| load_factor * u)
                        .collect();
                    body.solution_scaled(&system, scaled, load_factor)
                        .map_err(elastic)?
                };
                times.solve_s += start.elapsed().as_secs_f64();
                (body.clone(), solution)
            }
        };
        let start = Instant::now();
        let fields = body
            .element_fields(solution.displacement())
            .map_err(elastic)?;
        let qualities = cell_qualities(body.mesh());
        times.post_s += start.elapsed().as_secs_f64();
        bodies.push(SolvedBody {
            body,
            solution,
            fields,
            qualities,
            error_indicator: Vec::new(),
        });
    }
    times.total_s = times.mesh_s + times.assembly_s + times.solve_s + times.post_s;
    let mut summary = summarise(model, &bodies, times);
    summary.contact = contact
        .as_ref()
        .map(|result| model.contact_summary(result, model.bodies_3d(), history));
    Ok(Outcome {
        bodies: Vec::new(),
        bodies_3d: bodies,
        contact: None,
        contact_3d: contact,
        contact_bodies,
        steps: Vec::new(),
        steps_3d: earlier_steps,
        summary,
        started,
    })
}

/// The summary of a scene in space.
fn summarise(model: &Model, bodies: &[SolvedBody<3, CellQuality>], times: RunTimes) -> RunSummary {
    let body_summaries = bodies
        .iter()
        .zip(model.bodies_3d())
        .map(|(solved, built)| {
            let mesh = solved.body.mesh();
            let dofs = solved.body.dofs();
            BodySummary {
                name: solved.body.name().to_string(),
                mesh: built.mesh_source.clone(),
                element: built.element.clone(),
                predicted_error: None,
                vertices: mesh.n_vertices(),
                inserted_vertices: mesh.n_vertices() - built.body.mesh().n_vertices(),
                polygons: mesh.n_cells(),
                free_dofs: dofs.n_free(),
                prescribed_dofs: dofs.n_prescribed(),
                material: describe_material(&solved.body),
                mesh_size: solved
                    .qualities
                    .iter()
                    .map(|q| q.diameter)
                    .fold(0.0, f64::max),
                gamma: solved
                    .qualities
                    .iter()
                    .map(CellQuality::gamma)
                    .fold(f64::INFINITY, f64::min),
                star_ratio: solved
                    .qualities
                    .iter()
                    .map(|q| q.star_ratio)
                    .fold(f64::INFINITY, f64::min),
                strain_energy: solved.solution.strain_energy(),
                max_displacement: solved
                    .solution
                    .vertex_displacements()
                    .iter()
                    .map(|u| u.norm())
                    .fold(0.0, f64::max),
                max_von_mises: solved
                    .fields
                    .iter()
                    .map(|f| f.von_mises)
                    .fold(0.0, f64::max),
                reactions: reaction_summaries(&solved.solution, &solved.body),
                warnings: built.warnings.clone(),
            }
        })
        .collect();
    RunSummary {
        title: model
            .scene()
            .title
            .clone()
            .unwrap_or_else(|| "scene".to_string()),
        dimension: 3,
        bodies: body_summaries,
        contact: None,
        error_estimate: None,
        adaptivity: None,
        deprecations: model.deprecations().to_vec(),
        notes: Vec::new(),
        times,
    }
}
