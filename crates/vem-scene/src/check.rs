//! Everything that can be checked without meshes, with the key path of every error; the
//! earlier forms of keys folded into their new places, with a note each.

use std::collections::{BTreeMap, HashSet};

use vem_contact::{AccuracyPreset, ErrorModel};
use vem_space::{Choice, Options};

use crate::description::{
    BodyDescription, ContactDescription, LegacyPenalty, LegacyScaling, LegacyStabilisationKind,
    MeshDescription, Scene,
};
use crate::{Deprecation, KeyPath, ScalarValue, SceneError, VectorValue};

/// The largest magnitude of a number of a scene.
pub const LARGEST: f64 = 1e100;
/// The smallest non-zero magnitude of a number of a scene.
pub const SMALLEST: f64 = 1e-100;
/// The largest `[output] width`, in pixels.
pub const MAX_WIDTH: f64 = 20_000.0;
/// The dimension of a scene whose meshes say nothing else (a `rectangle`, a planar file).
pub const DIMENSION: usize = 2;

/// The dimension a body's mesh declares before it is generated or read: 3 for a generated
/// `box` and inline `polyhedra`, 2 for a generated `rectangle` or `polygon`, inline `polygons` and the
/// planar file formats (VTK, PolyMesher);
/// `None` for a Gmsh file, whose elements decide (surfaces in the plane, volumes in space).
pub fn declared_dimension(body: &BodyDescription) -> Option<usize> {
    let mesh = &body.mesh;
    if mesh.cuboid.is_some() {
        return Some(3);
    }
    if mesh.rectangle.is_some() || mesh.polygon.is_some() || mesh.polygons.is_some() {
        return Some(2);
    }
    if mesh.polyhedra.is_some() {
        return Some(3);
    }
    let file = mesh.file.as_deref()?;
    let extension = std::path::Path::new(file)
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match extension.as_deref() {
        Some("msh") => None,
        _ => Some(2),
    }
}

/// A scene in its current form: every earlier key folded into its new place.
#[derive(Debug, Clone)]
pub struct Checked {
    /// The scene, with no earlier keys left.
    pub scene: Scene,
    /// The notes of the earlier keys read.
    pub deprecations: Vec<Deprecation>,
    /// Where a key of the current form was written in the earlier one (new path -> old path),
    /// so that errors point at what the user wrote.
    pub written_at: BTreeMap<KeyPath, KeyPath>,
}

impl Checked {
    /// The path at which the user wrote the key `path` of the current form.
    pub fn written(&self, path: &KeyPath) -> KeyPath {
        // The longest prefix with a recorded place, the rest appended.
        for k in (1..=path.0.len()).rev() {
            let prefix = KeyPath(path.0[..k].to_vec());
            if let Some(old) = self.written_at.get(&prefix) {
                let mut full = old.clone();
                full.0.extend_from_slice(&path.0[k..]);
                return full;
            }
        }
        path.clone()
    }
}

/// Folds the earlier keys and checks what can be checked without meshes.
///
/// # Errors
/// The first problem found, at its key.
pub fn check(scene: &Scene) -> Result<Checked, SceneError> {
    let mut checked = Checked {
        scene: scene.clone(),
        deprecations: Vec::new(),
        written_at: BTreeMap::new(),
    };
    fold_stabilisations(&mut checked)?;
    fold_laws(&mut checked)?;
    fold_solver(&mut checked)?;
    let scene = &checked.scene;
    if scene.bodies.is_empty() {
        return Err(SceneError::at(KeyPath::root(), "the scene has no [[body]]"));
    }
    if let Some(adapt) = &scene.adapt {
        check_adapt(adapt)?;
    }
    let mut names = HashSet::new();
    for (i, body) in scene.bodies.iter().enumerate() {
        let path = KeyPath::key("body").index(i);
        check_body(scene, body, &path)?;
        if !names.insert(body.name.as_str()) {
            return Err(SceneError::at(
                path.at("name"),
                format!("a second body is named '{}'", body.name),
            ));
        }
    }
    let mut sides: Vec<(String, String)> = Vec::new();
    for (k, contact) in scene.contacts.iter().enumerate() {
        let path = KeyPath::key("contact").index(k);
        check_contact(scene, contact, &path)?;
        // The same two sides in contact twice would constrain the same gaps twice.
        let this = (
            format!("body '{}' part '{}'", contact.body, contact.part),
            {
                match (&contact.other_body, &contact.other_part) {
                    (Some(b), Some(p)) => format!("body '{b}' part '{p}'"),
                    _ => serde_json::to_string(&contact.obstacle).unwrap_or_default(),
                }
            },
        );
        if let Some(j) = sides
            .iter()
            .position(|s| *s == this || (s.0 == this.1 && s.1 == this.0))
        {
            return Err(SceneError::at(
                path,
                format!(
                    "this pair repeats contact[{j}]: {} is already in contact with the same \
                     counterpart",
                    this.0
                ),
            ));
        }
        sides.push(this);
    }
    check_accuracy(scene)?;
    if let Some(m) = scene.output.magnification {
        positive(m, &KeyPath::key("output").at("magnification"))?;
    }
    if let Some(w) = scene.output.width {
        if !(w.is_finite() && (200.0..=MAX_WIDTH).contains(&w)) {
            return Err(SceneError::at(
                KeyPath::key("output").at("width"),
                format!("width = {w} pixels: give at least 200 and at most {MAX_WIDTH}"),
            ));
        }
    }
    if let Some(gib) = scene.limits.memory_gib {
        positive(gib, &KeyPath::key("limits").at("memory_gib"))?;
    }
    crate::history::check_history(scene)?;
    let declared: Vec<Option<usize>> = scene.bodies.iter().map(declared_dimension).collect();
    check_one_dimension(scene, &declared)?;
    // Gmsh files tell their dimension when read: the rest is checked then
    // ([`check_dimensions`], by the build).
    if let Some(dimensions) = declared.iter().copied().collect::<Option<Vec<usize>>>() {
        check_dimensions(scene, &dimensions)?;
    }
    check_ranges(&checked)?;
    Ok(checked)
}

/// The bodies of a scene all live in one dimension: the first body of another dimension than
/// the first body's is an error at its mesh (`dimensions[i]`: body i's, `None` when not known
/// yet).
pub fn check_one_dimension(scene: &Scene, dimensions: &[Option<usize>]) -> Result<(), SceneError> {
    let mut first: Option<(usize, usize)> = None;
    for (i, dimension) in dimensions.iter().enumerate() {
        let Some(d) = *dimension else { continue };
        match first {
            None => first = Some((i, d)),
            Some((j, e)) if e != d => {
                return Err(SceneError::at(
                    KeyPath::key("body").index(i).at("mesh"),
                    format!(
                        "body '{}' is {} ({}) but body '{}' is {}: the bodies of a scene live \
                         in one dimension",
                        scene.bodies[i].name,
                        in_words(d),
                        what_decides(&scene.bodies[i]),
                        scene.bodies[j].name,
                        in_words(e)
                    ),
                ))
            }
            Some(_) => {}
        }
    }
    Ok(())
}

/// "in the plane", "in space".
fn in_words(dimension: usize) -> &'static str {
    if dimension == 3 {
        "in space"
    } else {
        "in the plane"
    }
}

/// What decides a body's dimension, for messages.
fn what_decides(body: &BodyDescription) -> &'static str {
    if body.mesh.cuboid.is_some() {
        "its mesh is generated on a `box`"
    } else if body.mesh.rectangle.is_some() {
        "its mesh is generated on a `rectangle`"
    } else if body.mesh.polygon.is_some() {
        "its mesh is generated on a `polygon`"
    } else if body.mesh.polygons.is_some() {
        "its mesh is given as `polygons`"
    } else if body.mesh.polyhedra.is_some() {
        "its mesh is given as `polyhedra`"
    } else {
        "its mesh file"
    }
}

/// The checks that depend on the dimension of the bodies (`dimensions[i]`: body i's, 2 or 3):
/// the length of every point, box and vector; `plane` (required in the plane, refused in
/// space); `z` components (in space only); the coordinates of expressions; the obstacles of
/// contact pairs (`line`, `circle`, `polyline` in the plane, `plane`, `sphere` in space).
///
/// # Errors
/// The first problem found, at its key.
pub fn check_dimensions(scene: &Scene, dimensions: &[usize]) -> Result<(), SceneError> {
    for (i, body) in scene.bodies.iter().enumerate() {
        let path = KeyPath::key("body").index(i);
        let dimension = dimensions.get(i).copied().unwrap_or(DIMENSION);
        check_body_in(body, &path, dimension)?;
        check_body_expressions(body, &path, dimension)?;
    }
    for (k, contact) in scene.contacts.iter().enumerate() {
        let path = KeyPath::key("contact").index(k);
        let dimension = scene
            .bodies
            .iter()
            .position(|b| b.name == contact.body)
            .and_then(|i| dimensions.get(i).copied())
            .unwrap_or(DIMENSION);
        check_contact_in(contact, &path, dimension)?;
        if let Some(gap) = &contact.imposed_gap {
            check_scalar(gap, &path.at("imposed_gap"), dimension)?;
        }
    }
    Ok(())
}

/// `[body.stabilisation]` (earlier form) -> `element = { name = "vem1", stabilisation = .. }`.
fn fold_stabilisations(checked: &mut Checked) -> Result<(), SceneError> {
    for i in 0..checked.scene.bodies.len() {
        let body = &mut checked.scene.bodies[i];
        let Some(legacy) = body.stabilisation.take() else {
            continue;
        };
        let path = KeyPath::key("body").index(i);
        if body.element.is_some() {
            return Err(SceneError::at(
                path.at("element"),
                format!(
                    "body '{}': give `element` (a registered element) or `stabilisation` (of \
                     the lowest-order VEM), not both",
                    body.name
                ),
            ));
        }
        let mut stabilisation = Options::new();
        let name = match legacy.kind {
            LegacyStabilisationKind::DofiDofi => {
                if let Some(scaling) = legacy.scaling {
                    let s = match scaling {
                        LegacyScaling::Trace => "trace",
                        LegacyScaling::Shear => "shear",
                    };
                    stabilisation = stabilisation.with("scaling", s);
                }
                if let Some(scale) = legacy.scale {
                    stabilisation = stabilisation.with("scale", scale);
                }
                "dofi-dofi"
            }
            LegacyStabilisationKind::DRecipe => {
                if legacy.scaling.is_some() || legacy.scale.is_some() {
                    return Err(SceneError::at(
                        path.at("stabilisation"),
                        format!(
                            "body '{}': `scaling` and `scale` apply to kind = \"dofi-dofi\" only",
                            body.name
                        ),
                    ));
                }
                "drecipe"
            }
        };
        let stabilisation = Choice::with_options(name, stabilisation);
        let element =
            Choice::with_options("vem1", Options::new().with("stabilisation", &stabilisation));
        checked.deprecations.push(Deprecation {
            old: path.at("stabilisation").to_string(),
            new: format!("element = {}", inline(&element)),
        });
        body.element = Some(element);
        checked.written_at.insert(
            path.at("element").at("stabilisation"),
            path.at("stabilisation"),
        );
        checked
            .written_at
            .insert(path.at("element"), path.at("stabilisation"));
    }
    Ok(())
}

/// A choice as an inline TOML table for notes.
fn inline(choice: &Choice) -> String {
    fn value(v: &serde_json::Value) -> String {
        match v {
            serde_json::Value::Object(map) => {
                let items: Vec<String> = map
                    .iter()
                    .map(|(k, v)| format!("{k} = {}", value(v)))
                    .collect();
                format!("{{ {} }}", items.join(", "))
            }
            other => other.to_string(),
        }
    }
    let mut items = vec![format!("name = \"{}\"", choice.name)];
    items.extend(
        choice
            .options
            .keys()
            .map(|k| format!("{k} = {}", value(choice.options.get(k).expect("a key"))))
            .collect::<Vec<_>>(),
    );
    if items.len() == 1 {
        format!("\"{}\"", choice.name)
    } else {
        format!("{{ {} }}", items.join(", "))
    }
}

/// The earlier flat law keys of a contact (`friction_bound`, `coefficient`,
/// `fixed_point_*`) -> the law's table.
fn fold_laws(checked: &mut Checked) -> Result<(), SceneError> {
    for k in 0..checked.scene.contacts.len() {
        let path = KeyPath::key("contact").index(k);
        let contact = &mut checked.scene.contacts[k];
        let law_name = contact
            .law
            .as_ref()
            .map_or("frictionless".to_string(), |l| l.name.clone());
        let mut moved: Vec<(&'static str, serde_json::Value)> = Vec::new();
        let mut fixed_point = serde_json::Map::new();
        if let Some(g) = contact.friction_bound.take() {
            moved.push(("friction_bound", g.into()));
        }
        if let Some(f) = contact.coefficient.take() {
            moved.push(("coefficient", f.into()));
        }
        if let Some(m) = contact.fixed_point_max_iterations.take() {
            fixed_point.insert("max_iterations".into(), m.into());
        }
        if let Some(t) = contact.fixed_point_tolerance.take() {
            fixed_point.insert("tolerance".into(), t.into());
        }
        if moved.is_empty() && fixed_point.is_empty() {
            continue;
        }
        // A flat key for another law than the one named is a mistake, not an earlier form.
        let belongs = |key: &str| match key {
            "friction_bound" => law_name == "tresca",
            _ => law_name == "coulomb",
        };
        for (key, _) in &moved {
            if !belongs(key) {
                return Err(SceneError::at(
                    path.at(key),
                    format!("`{key}` does not apply to law = \"{law_name}\""),
                ));
            }
        }
        if !fixed_point.is_empty() && !belongs("fixed_point") {
            let key = if fixed_point.contains_key("max_iterations") {
                "fixed_point_max_iterations"
            } else {
                "fixed_point_tolerance"
            };
            return Err(SceneError::at(
                path.at(key),
                format!("`{key}` does not apply to law = \"{law_name}\""),
            ));
        }
        let law = contact.law.get_or_insert_with(|| Choice::named(&law_name));
        for (key, value) in moved {
            law.options.insert(key, value);
            checked
                .written_at
                .insert(path.at("law").at(key), path.at(key));
        }
        if !fixed_point.is_empty() {
            let written = if fixed_point.contains_key("tolerance") {
                "fixed_point_tolerance"
            } else {
                "fixed_point_max_iterations"
            };
            if fixed_point.contains_key("max_iterations") {
                checked.written_at.insert(
                    path.at("law").at("fixed_point").at("max_iterations"),
                    path.at("fixed_point_max_iterations"),
                );
            }
            if fixed_point.contains_key("tolerance") {
                checked.written_at.insert(
                    path.at("law").at("fixed_point").at("tolerance"),
                    path.at("fixed_point_tolerance"),
                );
            }
            checked
                .written_at
                .insert(path.at("law").at("fixed_point"), path.at(written));
            law.options
                .insert("fixed_point", serde_json::Value::Object(fixed_point));
        }
        checked.deprecations.push(Deprecation {
            old: path.to_string() + " law keys",
            new: format!("law = {}", inline(law)),
        });
    }
    Ok(())
}

/// The earlier solver keys of a contact (`solver`, `tolerance`, `max_iterations`, `penalty`,
/// `augmentation`) -> the scene's `solver`.
fn fold_solver(checked: &mut Checked) -> Result<(), SceneError> {
    let mut folded: Option<(Choice, KeyPath)> = None;
    for k in 0..checked.scene.contacts.len() {
        let path = KeyPath::key("contact").index(k);
        let contact = &mut checked.scene.contacts[k];
        let mut options = Options::new();
        let mut first_key: Option<&'static str> = None;
        let mut note = |key: &'static str, written: &mut BTreeMap<KeyPath, KeyPath>| {
            first_key.get_or_insert(key);
            written.insert(KeyPath::key("solver").at(key), path.at(key));
        };
        if let Some(t) = contact.tolerance.take() {
            options = options.with("tolerance", t);
            note("tolerance", &mut checked.written_at);
        }
        if let Some(m) = contact.max_iterations.take() {
            options = options.with("max_iterations", m);
            note("max_iterations", &mut checked.written_at);
        }
        for (key, legacy) in [
            ("penalty", contact.penalty.take()),
            ("augmentation", contact.augmentation.take()),
        ] {
            if let Some(p) = legacy {
                options = options.with(key, penalty_value(p, &path.at(key))?);
                note(key, &mut checked.written_at);
            }
        }
        let name = contact.solver.take();
        if name.is_none() && first_key.is_none() {
            continue;
        }
        if name.is_some() {
            first_key.get_or_insert("solver");
        }
        let choice = Choice::with_options(
            name.unwrap_or_else(|| vem_contact::SolverRegistry::DEFAULT.to_string()),
            options,
        );
        let where_written = path.at(first_key.unwrap_or("solver"));
        if let Some(existing) = &checked.scene.solver {
            return Err(SceneError::at(
                where_written,
                format!(
                    "the scene's `solver` ({}) and this contact's solver keys both set the \
                     solver: give the scene's `solver` only",
                    existing.name
                ),
            ));
        }
        match &folded {
            Some((earlier, _)) if *earlier != choice => {
                return Err(SceneError::at(
                    where_written,
                    "the contact pairs set different solvers: one solver treats every pair; \
                     give the scene's `solver`",
                ))
            }
            _ => folded = Some((choice, path.clone())),
        }
        checked
            .written_at
            .insert(KeyPath::key("solver"), path.at("solver"));
    }
    if let Some((choice, path)) = folded {
        checked.deprecations.push(Deprecation {
            old: path.to_string() + " solver keys",
            new: format!("solver = {} (at the top of the scene)", inline(&choice)),
        });
        checked.scene.solver = Some(choice);
    }
    Ok(())
}

/// A penalty of the earlier form as the solvers' setting.
fn penalty_value(p: LegacyPenalty, path: &KeyPath) -> Result<serde_json::Value, SceneError> {
    match (p.factor, p.value) {
        (Some(f), None) => Ok(serde_json::json!({ "factor": f })),
        (None, Some(v)) => Ok(serde_json::json!({ "value": v })),
        _ => Err(SceneError::at(
            path.clone(),
            "give either `factor` (relative to the stiffness) or `value` (absolute)",
        )),
    }
}

fn check_body(scene: &Scene, body: &BodyDescription, path: &KeyPath) -> Result<(), SceneError> {
    let name = &body.name;
    let valid = !name.is_empty()
        && !name.starts_with('.')
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.'));
    if !valid {
        return Err(SceneError::at(
            path.at("name"),
            format!(
                "body name '{name}': use letters, digits, '-', '_' and '.' (it names the body's \
                 output files)"
            ),
        ));
    }
    let mesh = &body.mesh;
    let mesh_path = path.at("mesh");
    for (k, part) in mesh.parts.iter().enumerate() {
        exact_len(
            part.bounds.len(),
            2,
            &mesh_path.at("parts").index(k).at("box"),
        )?;
    }
    let inline = mesh.vertices.is_some() || mesh.polygons.is_some() || mesh.polyhedra.is_some();
    let sources = [mesh.family.is_some(), mesh.file.is_some(), inline];
    if sources.iter().filter(|&&given| given).count() != 1 {
        return Err(SceneError::at(
            mesh_path,
            format!(
                "body '{name}': the mesh needs one of `family` (a generator, with `rectangle` or \
                 `box`, and `n`), `file` (a mesh file) or `vertices` (a mesh given inline, with \
                 `polygons` or `polyhedra`)"
            ),
        ));
    }
    let named_parts = !mesh.part_edges.is_empty() || !mesh.part_faces.is_empty();
    if named_parts && !inline {
        let key = if mesh.part_edges.is_empty() {
            "part_faces"
        } else {
            "part_edges"
        };
        return Err(SceneError::at(
            mesh_path.at(key),
            format!(
                "body '{name}': `{key}` names the boundary parts of a mesh given inline \
                 (`vertices`); cut parts out of a generated or read mesh with `parts`"
            ),
        ));
    }
    match (&mesh.family, &mesh.file) {
        _ if inline => check_inline_mesh(mesh, name, &mesh_path)?,
        // Exactly one source, checked above.
        (None, None) | (Some(_), Some(_)) => {}
        (Some(family), None) if mesh.polygon.is_some() => {
            if mesh.rectangle.is_some() || mesh.cuboid.is_some() {
                let (key, what) = if mesh.cuboid.is_some() {
                    (
                        "box",
                        "a `polygon` is a domain in the plane; a mesh in space is generated \
                         on a `box`",
                    )
                } else {
                    ("rectangle", "give `rectangle` or `polygon`, not both")
                };
                return Err(SceneError::at(
                    mesh_path.at(key),
                    format!("body '{name}': {what}"),
                ));
            }
            if let Err(e) = family.parse::<vem_mesh::generators::MeshFamily>() {
                let space = family
                    .parse::<vem_mesh::generators::polyhedral::PolyhedralFamily>()
                    .is_ok();
                let note = if space {
                    " (a family of a `box` in space; a `polygon` is meshed in the plane)"
                } else {
                    ""
                };
                return Err(SceneError::at(mesh_path.at("family"), format!("{e}{note}")));
            }
            polygon_domain(mesh, name, &mesh_path)?;
            check_generated_size(scene, mesh, name, &mesh_path, 2)?;
        }
        (Some(family), None) => {
            if mesh.edge_names.is_some() {
                return Err(SceneError::at(
                    mesh_path.at("edge_names"),
                    format!("body '{name}': `edge_names` names the edges of a `polygon`"),
                ));
            }
            let (domain, key, dimension) = match (&mesh.rectangle, &mesh.cuboid) {
                (Some(rectangle), None) => (rectangle, "rectangle", 2),
                (None, Some(cuboid)) => (cuboid, "box", 3),
                (Some(_), Some(_)) => {
                    return Err(SceneError::at(
                        mesh_path.at("box"),
                        format!(
                            "body '{name}': give `rectangle` (a mesh in the plane) or `box` (a \
                             mesh in space), not both"
                        ),
                    ))
                }
                (None, None) => {
                    return Err(SceneError::at(
                        mesh_path,
                        format!(
                            "body '{name}': a generated mesh needs `rectangle = [[x0, y0], [x1, \
                             y1]]` (in the plane) or `box = [[x0, y0, z0], [x1, y1, z1]]` (in \
                             space)"
                        ),
                    ))
                }
            };
            let parsed = if dimension == 3 {
                family
                    .parse::<vem_mesh::generators::polyhedral::PolyhedralFamily>()
                    .map(|_| ())
                    .map_err(|e| format!("{e} (the families of a `box`)"))
            } else {
                family
                    .parse::<vem_mesh::generators::MeshFamily>()
                    .map(|_| ())
                    .map_err(|e| e.to_string())
            };
            if let Err(e) = parsed {
                return Err(SceneError::at(mesh_path.at("family"), e));
            }
            let corners = mesh_path.at(key);
            exact_len(domain.len(), 2, &corners)?;
            for (k, corner) in domain.iter().enumerate() {
                exact_len(corner.len(), dimension, &corners.index(k))?;
            }
            check_generated_size(scene, mesh, name, &mesh_path, dimension)?;
        }
        (None, Some(_)) => {
            if mesh.rectangle.is_some()
                || mesh.polygon.is_some()
                || mesh.edge_names.is_some()
                || mesh.cuboid.is_some()
                || mesh.n.is_some()
                || mesh.seed.is_some()
            {
                return Err(SceneError::at(
                    mesh_path,
                    format!(
                        "body '{name}': `rectangle`, `polygon`, `edge_names`, `box`, `n` and \
                         `seed` belong to a generated mesh, not to a mesh `file`"
                    ),
                ));
            }
        }
    }
    let m = &body.material;
    let pairs = (
        m.young.is_some() || m.nu.is_some(),
        m.lambda.is_some() || m.mu.is_some(),
    );
    let complete = match pairs {
        (true, false) => m.young.is_some() && m.nu.is_some(),
        (false, true) => m.lambda.is_some() && m.mu.is_some(),
        _ => false,
    };
    if !complete {
        return Err(SceneError::at(
            path.at("material"),
            format!("body '{name}': give the material as `E` and `nu`, or as `lambda` and `mu`"),
        ));
    }
    if let Some(points) = body.traction_points {
        vem_space::quadrature::GaussLegendre::try_new(points).map_err(|_| {
            SceneError::at(
                path.at("traction_points"),
                format!(
                    "body '{name}': traction_points = {points}: give from 1 to {} Gauss-Legendre \
                     points per edge",
                    vem_space::quadrature::GaussLegendre::MAX_POINTS
                ),
            )
        })?;
    }
    for (k, t) in body.traction.iter().enumerate() {
        if t.value.is_some() == t.pressure.is_some() {
            return Err(SceneError::at(
                path.at("traction").index(k),
                format!(
                    "body '{name}': the traction on part '{}' needs either `value = [gx, gy]` \
                     (`[gx, gy, gz]` in space) or `pressure = p`, not both",
                    t.part
                ),
            ));
        }
    }
    Ok(())
}

/// The checks of a generated mesh's size and keys shared by every domain: `n` (or the
/// scene's `accuracy` or `target_error` in the plane), no `part_names`.
fn check_generated_size(
    scene: &Scene,
    mesh: &MeshDescription,
    name: &str,
    mesh_path: &KeyPath,
    dimension: usize,
) -> Result<(), SceneError> {
    if dimension == 3 && mesh.n.is_none() {
        return Err(SceneError::at(
            mesh_path.clone(),
            format!(
                "body '{name}': a generated mesh in space needs `n` (the error model \
                 that chooses it from `accuracy` or `target_error` is fitted in the \
                 plane)"
            ),
        ));
    }
    if mesh.n.is_none() && scene.accuracy.is_none() && scene.target_error.is_none() {
        return Err(SceneError::at(
            mesh_path.clone(),
            format!(
                "body '{name}': a generated mesh needs `n`, or the scene's `accuracy` or \
                 `target_error` to choose it"
            ),
        ));
    }
    if !mesh.part_names.is_empty() {
        return Err(SceneError::at(
            mesh_path.at("part_names"),
            format!("body '{name}': `part_names` belongs to a mesh `file` (VTK)"),
        ));
    }
    Ok(())
}

/// The polygon of a generated mesh (`polygon` with `edge_names`), checked: two coordinates per
/// vertex, a simple counter-clockwise polygon, one name per edge. An error is at the key of
/// the vertex to blame (`body[0].mesh.polygon[3]`) or of `edge_names`.
pub(crate) fn polygon_domain(
    mesh: &MeshDescription,
    name: &str,
    mesh_path: &KeyPath,
) -> Result<vem_mesh::generators::PolygonDomain, SceneError> {
    let at = mesh_path.at("polygon");
    let Some(polygon) = &mesh.polygon else {
        return Err(SceneError::at(at, format!("body '{name}': no `polygon`")));
    };
    for (k, point) in polygon.iter().enumerate() {
        exact_len(point.len(), 2, &at.index(k))?;
    }
    let vertices = polygon
        .iter()
        .map(|p| vem_mesh::Point::new(p[0], p[1]))
        .collect();
    let domain = vem_mesh::generators::PolygonDomain::new(vertices).map_err(|e| {
        let path = match &e {
            vem_mesh::MeshError::BadDomainPolygon {
                vertex: Some(k), ..
            } => at.index(*k),
            _ => at.clone(),
        };
        SceneError::at(path, format!("body '{name}': {e}"))
    })?;
    match &mesh.edge_names {
        Some(names) => domain
            .with_edge_names(names)
            .map_err(|e| SceneError::at(mesh_path.at("edge_names"), format!("body '{name}': {e}"))),
        None => Ok(domain),
    }
}

/// The checks of a mesh given inline (`vertices` with `polygons` or `polyhedra`) that need no
/// mesh: one kind of cells, the points' lengths, the generator's and file's keys left out, the
/// parts' kind. The mesh itself (indices in range, orientation, conformity, parts on the
/// boundary) is validated when it is built, each error naming its cell and vertex.
pub(crate) fn check_inline_mesh(
    mesh: &MeshDescription,
    name: &str,
    mesh_path: &KeyPath,
) -> Result<(), SceneError> {
    let Some(vertices) = &mesh.vertices else {
        return Err(SceneError::at(
            mesh_path.clone(),
            format!(
                "body '{name}': a mesh given inline needs `vertices = [[x, y], ...]` with its \
                 `polygons` (`[[x, y, z], ...]` with its `polyhedra`)"
            ),
        ));
    };
    let dimension = match (&mesh.polygons, &mesh.polyhedra) {
        (Some(_), None) => 2,
        (None, Some(_)) => 3,
        (Some(_), Some(_)) => {
            return Err(SceneError::at(
                mesh_path.at("polyhedra"),
                format!(
                    "body '{name}': give `polygons` (a mesh in the plane) or `polyhedra` (a mesh \
                     in space), not both"
                ),
            ))
        }
        (None, None) => {
            return Err(SceneError::at(
                mesh_path.clone(),
                format!(
                    "body '{name}': the mesh's `vertices` need its cells: `polygons = [[0, 1, \
                     2], ...]` (vertex loops, counter-clockwise) or `polyhedra` (each a list \
                     of outward face loops)"
                ),
            ))
        }
    };
    for (k, point) in vertices.iter().enumerate() {
        exact_len(point.len(), dimension, &mesh_path.at("vertices").index(k))?;
    }
    let foreign = [
        ("rectangle", mesh.rectangle.is_some()),
        ("polygon", mesh.polygon.is_some()),
        ("edge_names", mesh.edge_names.is_some()),
        ("box", mesh.cuboid.is_some()),
        ("n", mesh.n.is_some()),
        ("seed", mesh.seed.is_some()),
        ("part_names", !mesh.part_names.is_empty()),
    ];
    if let Some((key, _)) = foreign.iter().find(|(_, given)| *given) {
        return Err(SceneError::at(
            mesh_path.at(key),
            format!(
                "body '{name}': `{key}` belongs to a generated mesh or a mesh file, not to a mesh \
                 given inline (`vertices`)"
            ),
        ));
    }
    let (wrong, right) = if dimension == 2 {
        ("part_faces", "part_edges")
    } else {
        ("part_edges", "part_faces")
    };
    let given_wrong = if dimension == 2 {
        !mesh.part_faces.is_empty()
    } else {
        !mesh.part_edges.is_empty()
    };
    if given_wrong {
        return Err(SceneError::at(
            mesh_path.at(wrong),
            format!(
                "body '{name}': a mesh {} names its boundary parts by `{right}`",
                in_words(dimension)
            ),
        ));
    }
    Ok(())
}

/// The checks of a body that depend on its dimension (2 or 3).
fn check_body_in(
    body: &BodyDescription,
    path: &KeyPath,
    dimension: usize,
) -> Result<(), SceneError> {
    let name = &body.name;
    let mesh_path = path.at("mesh");
    for (k, part) in body.mesh.parts.iter().enumerate() {
        let corners = mesh_path.at("parts").index(k).at("box");
        for (c, corner) in part.bounds.iter().enumerate() {
            exact_len(corner.len(), dimension, &corners.index(c))?;
        }
        if (0..dimension).any(|i| part.bounds[0][i] > part.bounds[1][i]) {
            return Err(SceneError::at(
                corners,
                format!(
                    "body '{name}': the box of part '{}' has its lower corner above its upper one",
                    part.name
                ),
            ));
        }
    }
    let space = dimension == 3;
    match (body.material.plane.is_some(), space) {
        (false, false) => {
            return Err(SceneError::at(
                path.at("material"),
                format!(
                    "body '{name}': a two-dimensional body needs `plane = \"strain\"` or \
                     `plane = \"stress\"`"
                ),
            ))
        }
        (true, true) => {
            return Err(SceneError::at(
                path.at("material").at("plane"),
                format!(
                    "body '{name}': `plane` applies to a body in the plane; a body in space \
                     ({}) takes the full three-dimensional law: remove `plane`",
                    what_decides(body)
                ),
            ))
        }
        _ => {}
    }
    let components = if space {
        "`x`, `y` or `z`"
    } else {
        "`x`, `y` or both"
    };
    for (k, d) in body.dirichlet.iter().enumerate() {
        let at = path.at("dirichlet").index(k);
        if d.x.is_none() && d.y.is_none() && d.z.is_none() {
            return Err(SceneError::at(
                at,
                format!(
                    "body '{name}': the Dirichlet condition on part '{}' prescribes nothing: give \
                     {components}",
                    d.part
                ),
            ));
        }
        if d.z.is_some() && !space {
            return Err(SceneError::at(
                at.at("z"),
                format!("body '{name}': `z` does not apply to a two-dimensional body"),
            ));
        }
    }
    for (k, r) in body.rigid_plate.iter().enumerate() {
        let at = path.at("rigid_plate").index(k);
        if r.resultant_x.is_none() && r.resultant_y.is_none() && r.resultant_z.is_none() {
            let components = if space {
                "`resultant_x`, `resultant_y` or `resultant_z`"
            } else {
                "`resultant_x`, `resultant_y` or both"
            };
            return Err(SceneError::at(
                at,
                format!(
                    "body '{name}': the rigid plate on part '{}' prescribes nothing: give \
                     {components}",
                    r.part
                ),
            ));
        }
        if r.resultant_z.is_some() && !space {
            return Err(SceneError::at(
                at.at("resultant_z"),
                format!("body '{name}': `resultant_z` does not apply to a two-dimensional body"),
            ));
        }
    }
    for (k, t) in body.traction.iter().enumerate() {
        if let Some(n) = t.value.as_ref().and_then(|v| v.len()) {
            exact_len(n, dimension, &path.at("traction").index(k).at("value"))?;
        }
    }
    if let Some(n) = body.body_force.as_ref().and_then(|v| v.len()) {
        exact_len(n, dimension, &path.at("body_force"))?;
    }
    Ok(())
}

/// An array of `found` entries where `expected` are.
fn exact_len(found: usize, expected: usize, path: &KeyPath) -> Result<(), SceneError> {
    if found == expected {
        Ok(())
    } else {
        Err(SceneError::at(
            path.clone(),
            format!("an array of {found} entries where exactly {expected} are expected"),
        ))
    }
}

fn check_contact(
    scene: &Scene,
    contact: &ContactDescription,
    path: &KeyPath,
) -> Result<(), SceneError> {
    let a = body_index(scene, &contact.body, &path.at("body"))?;
    match (&contact.other_body, &contact.other_part, &contact.obstacle) {
        (Some(other), Some(_), None) => {
            if body_index(scene, other, &path.at("other_body"))? == a {
                return Err(SceneError::at(
                    path.at("other_body"),
                    format!(
                        "`other_body` is '{other}' again: contact of a body with itself is not \
                         supported"
                    ),
                ));
            }
        }
        (None, None, Some(obstacle)) => {
            let given = [
                obstacle.line.is_some(),
                obstacle.circle.is_some(),
                obstacle.polyline.is_some(),
                obstacle.plane.is_some(),
                obstacle.sphere.is_some(),
            ];
            let at = path.at("obstacle");
            if given.iter().filter(|&&g| g).count() != 1 {
                return Err(SceneError::at(
                    at,
                    "an obstacle is exactly one of `line = { point, normal }`, `circle = { \
                     centre, radius }` or `polyline = [[x, y], ...]` in the plane, `plane = { \
                     point, normal }` or `sphere = { centre, radius }` in space",
                ));
            }
            if contact.normal.is_some() {
                return Err(SceneError::at(
                    path.at("normal"),
                    "`normal` does not apply to an obstacle (its own normal is used)",
                ));
            }
        }
        _ => {
            return Err(SceneError::at(
                path.at("body"),
                "a contact pair needs either `other_body` and `other_part`, or an `obstacle`",
            ))
        }
    }
    if let Some(h) = &contact.hertz {
        if !(h.radius.is_finite() && h.radius > 0.0) {
            return Err(SceneError::at(
                path.at("hertz"),
                format!("hertz radius {} must be finite and positive", h.radius),
            ));
        }
    }
    Ok(())
}

/// The checks of a contact pair that depend on the dimension of its bodies.
fn check_contact_in(
    contact: &ContactDescription,
    path: &KeyPath,
    dimension: usize,
) -> Result<(), SceneError> {
    let Some(obstacle) = &contact.obstacle else {
        return Ok(());
    };
    let at = path.at("obstacle");
    // The obstacles of the other dimension, each with its counterpart in this one.
    let foreign = if dimension == 3 {
        [
            (
                "line",
                obstacle.line.is_some(),
                "plane = { point = [x, y, z], normal = [nx, ny, nz] }",
            ),
            (
                "circle",
                obstacle.circle.is_some(),
                "sphere = { centre = [x, y, z], radius = r }",
            ),
            (
                "polyline",
                obstacle.polyline.is_some(),
                "plane = { .. } or sphere = { .. }",
            ),
        ]
    } else {
        [
            (
                "plane",
                obstacle.plane.is_some(),
                "line = { point = [x, y], normal = [nx, ny] }",
            ),
            (
                "sphere",
                obstacle.sphere.is_some(),
                "circle = { centre = [x, y], radius = r }",
            ),
            ("", false, ""),
        ]
    };
    if let Some((key, _, instead)) = foreign.iter().find(|(_, given, _)| *given) {
        return Err(SceneError::at(
            at.at(key),
            format!(
                "body '{}' is {}: `{key}` is an obstacle {}; write `{instead}`",
                contact.body,
                in_words(dimension),
                in_words(if dimension == 3 { 2 } else { 3 })
            ),
        ));
    }
    for (key, line) in [("line", &obstacle.line), ("plane", &obstacle.plane)] {
        if let Some(line) = line {
            exact_len(line.point.len(), dimension, &at.at(key).at("point"))?;
            exact_len(line.normal.len(), dimension, &at.at(key).at("normal"))?;
        }
    }
    for (key, circle) in [("circle", &obstacle.circle), ("sphere", &obstacle.sphere)] {
        if let Some(circle) = circle {
            exact_len(circle.centre.len(), dimension, &at.at(key).at("centre"))?;
        }
    }
    if let Some(points) = &obstacle.polyline {
        for (k, p) in points.iter().enumerate() {
            exact_len(p.len(), dimension, &at.at("polyline").index(k))?;
        }
    }
    Ok(())
}

/// The index of the body named `name`; the error lists the bodies.
pub(crate) fn body_index(scene: &Scene, name: &str, path: &KeyPath) -> Result<usize, SceneError> {
    scene
        .bodies
        .iter()
        .position(|b| b.name == name)
        .ok_or_else(|| {
            let names: Vec<&str> = scene.bodies.iter().map(|b| b.name.as_str()).collect();
            SceneError::at(
                path.clone(),
                format!("no body named '{name}'; the scene has {}", list(&names)),
            )
        })
}

/// `['a', 'b']` for error messages.
pub(crate) fn list<S: AsRef<str>>(names: &[S]) -> String {
    let quoted: Vec<String> = names.iter().map(|n| format!("'{}'", n.as_ref())).collect();
    format!("[{}]", quoted.join(", "))
}

/// `accuracy` names a preset and leaves the solver setting to it; `target_error` is positive,
/// reachable and used by some generated mesh without `n`.
fn check_accuracy(scene: &Scene) -> Result<(), SceneError> {
    if let Some(accuracy) = &scene.accuracy {
        if let Err(e) = accuracy.parse::<AccuracyPreset>() {
            return Err(SceneError::at(KeyPath::key("accuracy"), e.to_string()));
        }
        if scene.solver.is_some() {
            return Err(SceneError::at(
                KeyPath::key("solver"),
                format!(
                    "`solver` and the scene's `accuracy` both set the solver: `accuracy` = \
                     \"{accuracy}\" chooses it; give one of the two"
                ),
            ));
        }
    }
    if let Some(target) = scene.target_error {
        let path = KeyPath::key("target_error");
        positive(target, &path)?;
        if let Err(e) = ErrorModel::LOWEST_ORDER_VEM.try_size_for(target) {
            return Err(SceneError::at(path, e.to_string()));
        }
        let chooses = scene
            .bodies
            .iter()
            .any(|b| b.mesh.family.is_some() && b.mesh.n.is_none());
        if !chooses {
            return Err(SceneError::at(
                path,
                "`target_error` chooses the size of generated meshes without `n`, and every mesh \
                 here has `n` or is a file: drop `target_error` or an `n`",
            ));
        }
    }
    Ok(())
}

fn positive(value: f64, path: &KeyPath) -> Result<(), SceneError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(SceneError::at(
            path.clone(),
            format!("`{}` = {value} must be finite and positive", last_key(path)),
        ))
    }
}

fn last_key(path: &KeyPath) -> String {
    path.0
        .iter()
        .rev()
        .find_map(|s| match s {
            crate::error::Segment::Key(k) => Some(k.clone()),
            crate::error::Segment::Index(_) => None,
        })
        .unwrap_or_default()
}

/// Checks that a number of the scene is finite and, unless zero, of a magnitude between
/// [`SMALLEST`] and [`LARGEST`], so that the products the model forms of moduli, lengths and
/// loads (stiffness entries, resultants, energies) stay finite. `what` names it in the
/// message.
pub fn number(value: f64, path: &KeyPath, what: &str) -> Result<(), SceneError> {
    if !value.is_finite() {
        return Err(SceneError::at(
            path.clone(),
            format!("{what} = {value} must be finite"),
        ));
    }
    let magnitude = value.abs();
    if magnitude != 0.0 && !(SMALLEST..=LARGEST).contains(&magnitude) {
        return Err(SceneError::at(
            path.clone(),
            format!(
                "{what} = {value:e} is out of range: a number of a scene is 0 or of magnitude \
                 {SMALLEST:e} to {LARGEST:e} (products of moduli, lengths and loads must stay \
                 finite); change the units"
            ),
        ));
    }
    Ok(())
}

/// Every number of the scene in range ([`number`]), including those inside the settings
/// tables of elements, laws and the solver.
fn check_ranges(checked: &Checked) -> Result<(), SceneError> {
    let value = serde_json::to_value(&checked.scene).map_err(|e| {
        SceneError::at(
            KeyPath::root(),
            format!("the scene does not serialise (a function of the position?): {e}"),
        )
    });
    // A scene with functions (from Rust) is checked where it has numbers only.
    let Ok(value) = value else {
        return Ok(());
    };
    fn walk(value: &serde_json::Value, path: &KeyPath) -> Result<(), SceneError> {
        match value {
            serde_json::Value::Number(n) => {
                number(n.as_f64().unwrap_or(f64::NAN), path, &format!("`{path}`"))
            }
            serde_json::Value::Array(items) => items
                .iter()
                .enumerate()
                .try_for_each(|(k, v)| walk(v, &path.index(k))),
            serde_json::Value::Object(map) => {
                map.iter().try_for_each(|(k, v)| walk(v, &path.at(k)))
            }
            _ => Ok(()),
        }
    }
    walk(&value, &KeyPath::root()).map_err(|e| SceneError {
        path: checked.written(&e.path),
        ..e
    })
}

/// Every expression of the scene uses only the coordinates of its dimension and no `t`
/// (values change along a load history by their curves).
fn check_scalar(value: &ScalarValue, path: &KeyPath, dimension: usize) -> Result<(), SceneError> {
    if value.dimension_used() > dimension {
        let coordinates = if dimension == 3 { "x, y, z" } else { "x, y" };
        return Err(SceneError::at(
            path.clone(),
            format!(
                "an expression of a coordinate beyond the scene's dimension {dimension} \
                 ({coordinates})"
            ),
        ));
    }
    if value.uses_time() {
        return Err(SceneError::at(
            path.clone(),
            "an expression of `t`: values change along a load history by their `curve = [[t, \
             s], ...]` (and `[history]` times); write the value without `t`",
        ));
    }
    Ok(())
}

fn check_vector(value: &VectorValue, path: &KeyPath, dimension: usize) -> Result<(), SceneError> {
    if let VectorValue::Components(components) = value {
        for (k, c) in components.iter().enumerate() {
            check_scalar(c, &path.index(k), dimension)?;
        }
    }
    Ok(())
}

fn check_body_expressions(
    body: &BodyDescription,
    path: &KeyPath,
    dimension: usize,
) -> Result<(), SceneError> {
    for (k, d) in body.dirichlet.iter().enumerate() {
        let at = path.at("dirichlet").index(k);
        for (key, value) in [("x", &d.x), ("y", &d.y), ("z", &d.z)] {
            if let Some(value) = value {
                check_scalar(value, &at.at(key), dimension)?;
            }
        }
    }
    for (k, t) in body.traction.iter().enumerate() {
        if let Some(value) = &t.value {
            check_vector(value, &path.at("traction").index(k).at("value"), dimension)?;
        }
    }
    if let Some(force) = &body.body_force {
        check_vector(force, &path.at("body_force"), dimension)?;
    }
    Ok(())
}

/// `adapt`: a target in (0, 1), a fraction in (0, 1], limits of at least one.
fn check_adapt(adapt: &crate::description::AdaptDescription) -> Result<(), SceneError> {
    let path = KeyPath::key("adapt");
    if let Some(target) = adapt.target_error {
        if !(target > 0.0 && target < 1.0) {
            return Err(SceneError::at(
                path.at("target_error"),
                format!(
                    "target_error = {target}: give the estimate relative to the energy norm of \
                     the solution to reach, between 0 and 1 (0.05 for 5 %)"
                ),
            ));
        }
    }
    if let Some(theta) = adapt.theta {
        if !(theta > 0.0 && theta <= 1.0) {
            return Err(SceneError::at(
                path.at("theta"),
                format!(
                    "theta = {theta}: Dorfler's fraction of the squared estimate the refined \
                     cells carry is in (0, 1]"
                ),
            ));
        }
    }
    if adapt.max_unknowns == Some(0) {
        return Err(SceneError::at(
            path.at("max_unknowns"),
            "max_unknowns = 0: give the largest number of unknowns a refined mesh may have",
        ));
    }
    if adapt.max_cycles == Some(0) {
        return Err(SceneError::at(
            path.at("max_cycles"),
            "max_cycles = 0: give the largest number of solves (1: no refinement)",
        ));
    }
    Ok(())
}
