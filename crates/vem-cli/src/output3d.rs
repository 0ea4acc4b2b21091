//! The files of `vem run` for a scene in space: one `.vtu` of polyhedra per body (VTK type 42,
//! as ParaView, VTK and meshio read it; with contact, the raw and consistent contact pressure
//! at the interface vertices), with contact the contact surface `interface.vtu` (the faces of
//! each pair's body A on its contact part after the surface overlay, as polygons, with the
//! columns of `contact.csv` at their vertices) and `contact.csv` (with z columns),
//! `results.pvd` opening them all, `reactions.csv` and `summary.json`. With contact, the
//! picture of each contact surface (`pressure.svg`: the consistent pressure seen along the
//! pair's normal, and with `hertz` its radial profile against Hertz's); the deformed bodies
//! are drawn in the plane only, and the summary says so.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

use vem_contact::{InterfaceNode, NodeStatus, PairSummary};
use vem_mesh::io::{
    write_atomically, write_polyhedral_vtu_with, write_svg_layers, CellType, Cells, DataArray,
    PvdCollection, SvgLayer, SvgOptions, UnstructuredGrid, VtkArray, VtuData,
};
use vem_mesh::polyhedral::quality::CellQuality;
use vem_mesh::{Point3, Vector3};
use vem_scene::SolvedBody;

use crate::output::{mesh_error, status_label};
use crate::{plot, CliError, Outcome};

/// The columns of `contact.csv` in space, in order.
pub const CONTACT_COLUMNS_3D: &str =
    "pair,x,y,z,nx,ny,nz,initial_gap,normal_jump,normal_force,pressure,consistent_pressure,\
     friction_x,friction_y,friction_z,slip_x,slip_y,slip_z,status";

/// The columns of `reactions.csv`, in order.
pub const REACTION_COLUMNS: &str = "body,part,components,rigid_plate,force_x,force_y,force_z";

/// The note of a run in space about its pictures.
pub const NO_PICTURES_IN_SPACE: &str =
    "no picture of the deformed bodies: deformed.svg is drawn for bodies in the plane only; \
     open results.pvd in ParaView for the bodies in space";

impl Outcome {
    /// Writes the files of a scene in space into the existing folder `dir`.
    pub(crate) fn write_into_3d(&mut self, dir: &Path) -> Result<Vec<PathBuf>, CliError> {
        let start = Instant::now();
        let mut written = Vec::new();
        if self.output.files.vtu {
            written.extend(self.write_vtu_3d(dir)?);
        }
        if let Some(contact) = &self.contact_3d {
            if self.output.files.csv {
                let path = dir.join("contact.csv");
                let frictionless = contact.model.tangential_rows == 0;
                write_atomically(&path, |w| {
                    write_contact_csv_3d(w, &contact.nodes, &contact.model.pairs, frictionless)
                })
                .map_err(mesh_error(&path))?;
                written.push(path);
            }
            if self.output.files.pictures {
                let (pictures, notes) =
                    self.pressure_pictures_3d(dir, &contact.nodes, &contact.model.pairs)?;
                written.extend(pictures);
                for note in notes {
                    if !self.summary.notes.contains(&note) {
                        self.summary.notes.push(note);
                    }
                }
            }
        }
        if self.output.files.csv {
            let path = dir.join("reactions.csv");
            write_atomically(&path, |w| write_reactions_csv(w, self.summary()))
                .map_err(mesh_error(&path))?;
            written.push(path);
        }
        if self.output.files.pictures
            && !self.summary.notes.iter().any(|n| n == NO_PICTURES_IN_SPACE)
        {
            self.summary.notes.push(NO_PICTURES_IN_SPACE.to_string());
        }
        written.push(self.write_summary(dir, start)?);
        Ok(written)
    }

    /// `<body>.vtu` of every body in space, `interface.vtu` with contact and `results.pvd`,
    /// which opens them all at once.
    fn write_vtu_3d(&self, dir: &Path) -> Result<Vec<PathBuf>, CliError> {
        let mut written = Vec::new();
        let mut collection = PvdCollection::new();
        let nodes = self.contact_3d.as_ref().map_or(&[][..], |c| &c.nodes[..]);
        let raw = self.pressure_at_vertices_3d(nodes, |n| n.pressure);
        let consistent = self.pressure_at_vertices_3d(nodes, |n| n.consistent_pressure);
        for (part, ((solved, raw), consistent)) in
            self.bodies_3d.iter().zip(raw).zip(consistent).enumerate()
        {
            let name = solved.body.name();
            let file = format!("{name}.vtu");
            let path = dir.join(&file);
            let mut data = vtu_data_3d(solved);
            if let (Some(raw), Some(consistent)) = (raw, consistent) {
                data = data
                    .with_point_scalars("contact_pressure", raw)
                    .with_point_scalars("consistent_contact_pressure", consistent);
            }
            write_polyhedral_vtu_with(&path, solved.body.mesh(), &data, self.body_encoding())
                .map_err(mesh_error(&path))?;
            collection.add(0.0, part, name, file);
            written.push(path);
        }
        if let Some(contact) = &self.contact_3d {
            let path = dir.join("interface.vtu");
            self.contact_surface(&contact.nodes, &contact.model.pairs)
                .write(&path, self.interface_encoding())
                .map_err(mesh_error(&path))?;
            collection.add(0.0, self.bodies_3d.len(), "interface", "interface.vtu");
            written.push(path);
        }
        let path = dir.join("results.pvd");
        collection.write(&path).map_err(mesh_error(&path))?;
        written.push(path);
        Ok(written)
    }
}

impl Outcome {
    /// For each body in space, a nodal value (`value` of each interface node) at its interface
    /// vertices (zero elsewhere); `None` for a body out of contact.
    fn pressure_at_vertices_3d(
        &self,
        nodes: &[InterfaceNode<3>],
        value: impl Fn(&InterfaceNode<3>) -> f64,
    ) -> Vec<Option<Vec<f64>>> {
        let mut values: Vec<Option<Vec<f64>>> = vec![None; self.bodies_3d.len()];
        for node in nodes {
            let sides = [
                (node.body_a, Some(node.vertex_a)),
                (node.body_b.unwrap_or(usize::MAX), node.vertex_b),
            ];
            for (body, vertex) in sides {
                let (Some(&index), Some(v)) = (self.contact_bodies.get(body), vertex) else {
                    continue;
                };
                let n = self.bodies_3d[index].body.mesh().n_vertices();
                values[index].get_or_insert_with(|| vec![0.0; n])[v] = value(node) + 0.0;
            }
        }
        values
    }

    /// The contact surface as a dataset of its own: per contact pair the faces of body A's
    /// contact part on the mesh solved (after the surface overlay, the overlay cells: every
    /// vertex an interface node), as polygons with cell data `pair`; at every node the columns
    /// of `contact.csv` as point data (`normal`, `friction_force`, `friction_traction` (the
    /// consistent one) and `slip` as vectors), the status as an integer `status` (0 open, 1
    /// contact, 2 stick, 3 slip). A face with a vertex that is not a node of its pair (left
    /// out by `max_distance`) is not drawn; a pair none of whose faces is drawn has its nodes as
    /// vertex cells.
    fn contact_surface(
        &self,
        nodes: &[InterfaceNode<3>],
        pairs: &[PairSummary],
    ) -> UnstructuredGrid {
        let points: Vec<[f64; 3]> = nodes
            .iter()
            .map(|n| [n.position.x, n.position.y, n.position.z])
            .collect();
        let mut cells = Cells::new();
        let mut pair_of_cell = Vec::new();
        for (k, pair) in pairs.iter().enumerate() {
            let range = pair.nodes.clone();
            let mut drawn = 0;
            if let (Some(first), Some(part)) = (nodes.get(range.start), self.contact_parts.get(k)) {
                let body = self
                    .contact_bodies
                    .get(first.body_a)
                    .and_then(|&i| self.bodies_3d.get(i));
                if let Some(body) = body {
                    let mesh = body.body.mesh();
                    let node_of: std::collections::HashMap<usize, usize> =
                        range.clone().map(|i| (nodes[i].vertex_a, i)).collect();
                    for &f in mesh.part_faces(part).unwrap_or_default() {
                        let face: Option<Vec<usize>> = mesh
                            .face(f)
                            .iter()
                            .map(|v| node_of.get(v).copied())
                            .collect();
                        if let Some(face) = face {
                            cells.push(CellType::Polygon, &face);
                            pair_of_cell.push(k as i32);
                            drawn += 1;
                        }
                    }
                }
            }
            if drawn == 0 {
                for i in range {
                    cells.push(CellType::Vertex, &[i]);
                    pair_of_cell.push(k as i32);
                }
            }
        }
        let vector = |v: &dyn Fn(&InterfaceNode<3>) -> Vector3| -> Vec<[f64; 3]> {
            nodes
                .iter()
                .map(|n| {
                    let v = v(n);
                    [v.x + 0.0, v.y + 0.0, v.z + 0.0]
                })
                .collect()
        };
        let scalar = |f: &dyn Fn(&InterfaceNode<3>) -> f64| -> Vec<f64> {
            nodes.iter().map(|n| f(n) + 0.0).collect()
        };
        UnstructuredGrid::new(points, cells)
            .with_point_data(VtkArray::vectors("normal", &vector(&|n| n.normal)))
            .with_point_data(VtkArray::scalars("initial_gap", scalar(&|n| n.initial_gap)))
            .with_point_data(VtkArray::scalars("normal_jump", scalar(&|n| n.normal_jump)))
            .with_point_data(VtkArray::scalars(
                "normal_force",
                scalar(&|n| n.normal_force),
            ))
            .with_point_data(VtkArray::scalars("pressure", scalar(&|n| n.pressure)))
            .with_point_data(VtkArray::scalars(
                "consistent_pressure",
                scalar(&|n| n.consistent_pressure),
            ))
            .with_point_data(VtkArray::scalars(
                "tributary_area",
                scalar(&|n| n.tributary_measure),
            ))
            .with_point_data(VtkArray::vectors(
                "friction_force",
                &vector(&|n| n.friction_force),
            ))
            .with_point_data(VtkArray::vectors(
                "friction_traction",
                &vector(&|n| n.consistent_friction_traction),
            ))
            .with_point_data(VtkArray::vectors("slip", &vector(&|n| n.slip)))
            .with_point_data(VtkArray::int32(
                "status",
                nodes.iter().map(|n| status_code(n.status)).collect(),
            ))
            .with_cell_data(VtkArray::int32("pair", pair_of_cell))
    }
}

/// The status as the interface datasets store it: 0 open, 1 contact, 2 stick, 3 slip.
fn status_code(status: NodeStatus) -> i32 {
    match status {
        NodeStatus::Open => 0,
        NodeStatus::Contact => 1,
        NodeStatus::Stick => 2,
        NodeStatus::Slip => 3,
    }
}

/// `contact.csv` in space: one row per interface node, columns [`CONTACT_COLUMNS_3D`] (`pair`:
/// the index of the node's pair, counted from 0 in the order of the `[[contact]]` tables),
/// numbers in shortest round-trip scientific notation.
fn write_contact_csv_3d(
    w: &mut dyn Write,
    nodes: &[InterfaceNode<3>],
    pairs: &[PairSummary],
    frictionless: bool,
) -> std::io::Result<()> {
    writeln!(w, "{CONTACT_COLUMNS_3D}")?;
    for (i, n) in nodes.iter().enumerate() {
        let pair = pairs.iter().position(|p| p.nodes.contains(&i)).unwrap_or(0);
        let mut row = vec![pair.to_string()];
        let numbers = [
            n.position.x,
            n.position.y,
            n.position.z,
            n.normal.x,
            n.normal.y,
            n.normal.z,
            n.initial_gap,
            n.normal_jump,
            n.normal_force,
            n.pressure,
            n.consistent_pressure,
            n.friction_force.x,
            n.friction_force.y,
            n.friction_force.z,
            n.slip.x,
            n.slip.y,
            n.slip.z,
        ];
        row.extend(numbers.iter().map(|v| format!("{:e}", v + 0.0)));
        row.push(status_label(n.status, frictionless).to_string());
        writeln!(w, "{}", row.join(","))?;
    }
    Ok(())
}

/// Point data `displacement` (3 components); cell data `stress_xx_yy_zz` and
/// `stress_yz_xz_xy` (3 components each), `von_mises`, `quality_gamma`, `star_ratio`,
/// `shortest_edge_ratio`.
fn vtu_data_3d(solved: &SolvedBody<3, CellQuality>) -> VtuData {
    let fields = &solved.fields;
    let stress = |pairs: [(usize, usize); 3]| -> Vec<f64> {
        fields
            .iter()
            .flat_map(|f| pairs.map(|(i, j)| f.stress[(i, j)]))
            .collect()
    };
    let qualities = &solved.qualities;
    VtuData::new()
        .with_point_vectors_3d("displacement", &solved.solution.vertex_displacements())
        .with_cell_data(DataArray::new(
            "stress_xx_yy_zz",
            3,
            stress([(0, 0), (1, 1), (2, 2)]),
        ))
        .with_cell_data(DataArray::new(
            "stress_yz_xz_xy",
            3,
            stress([(1, 2), (0, 2), (0, 1)]),
        ))
        .with_cell_scalars("von_mises", fields.iter().map(|f| f.von_mises).collect())
        .with_cell_scalars(
            "quality_gamma",
            qualities.iter().map(CellQuality::gamma).collect(),
        )
        .with_cell_scalars(
            "star_ratio",
            qualities.iter().map(|q| q.star_ratio).collect(),
        )
        .with_cell_scalars(
            "shortest_edge_ratio",
            qualities.iter().map(|q| q.shortest_edge_ratio).collect(),
        )
}

/// One row per Dirichlet condition or rigid plate of every body: the force the support
/// exerts on the body (the prescribed resultant for a rigid plate), by component.
fn write_reactions_csv(w: &mut dyn Write, summary: &vem_scene::RunSummary) -> std::io::Result<()> {
    writeln!(w, "{REACTION_COLUMNS}")?;
    for body in &summary.bodies {
        for r in &body.reactions {
            let force: Vec<String> = (0..3)
                .map(|i| {
                    r.force
                        .get(i)
                        .map_or_else(String::new, |f| format!("{f:e}"))
                })
                .collect();
            writeln!(
                w,
                "{},{},\"{}\",{},{}",
                body.name,
                r.part,
                r.components,
                r.rigid_plate,
                force.join(",")
            )?;
        }
    }
    Ok(())
}

impl Outcome {
    /// The pictures of the contact surfaces in space: per pair (`pressure.svg` for one pair,
    /// `pressure-<k>.svg` for pair k of several) the consistent pressure as a colour map on
    /// the faces of body A's contact part (the overlay cells, every vertex a node), seen along
    /// the pair's mean normal, with a colour bar from 0 to the pair's largest consistent
    /// pressure; with `hertz = {...}` the radial profile beside it ([`plot::radial_profile`]).
    /// Above [`vem_mesh::io::VECTOR_CELL_LIMIT`] faces the map is an embedded PNG, so that the
    /// file's size is bounded whatever the mesh. A pair whose surface cannot be drawn so (no
    /// face all of whose vertices are nodes, or faces that overlap seen along the normal) has
    /// no picture, and a note (returned) says why.
    fn pressure_pictures_3d(
        &self,
        dir: &Path,
        nodes: &[InterfaceNode<3>],
        pairs: &[PairSummary],
    ) -> Result<(Vec<PathBuf>, Vec<String>), CliError> {
        let mut written = Vec::new();
        let mut notes = Vec::new();
        let width = self.output_width.unwrap_or(crate::output::DEFAULT_WIDTH);
        for (k, pair) in pairs.iter().enumerate() {
            let map = match self.pressure_map(nodes, pair, k) {
                Ok(map) => map,
                Err(reason) => {
                    notes.push(format!("no pressure picture of contact pair {k}: {reason}"));
                    continue;
                }
            };
            let file = if pairs.len() == 1 {
                "pressure.svg".to_string()
            } else {
                format!("pressure-{k}.svg")
            };
            let path = dir.join(file);
            let fail = |reason: String| CliError::Plot {
                path: path.clone(),
                reason,
            };
            let hertz = self
                .summary
                .contact
                .as_ref()
                .and_then(|c| c.hertz.iter().find(|h| h.pair == k));
            let centre = hertz
                .filter(|h| h.centre.len() == 3)
                .map_or(map.centre, |h| {
                    Point3::new(h.centre[0], h.centre[1], h.centre[2])
                });
            let title = &self.summary.title;
            let seen_along = format!(
                "consistent pressure on '{}' of body '{}', seen along ({}, {}, {})",
                map.part,
                map.body,
                rounded(map.view.x),
                rounded(map.view.y),
                rounded(map.view.z)
            );
            // Beside a profile the scene's title heads the whole picture and each panel says
            // what it shows; alone, the map carries the scene's title.
            let options = SvgOptions {
                width: if hertz.is_some() { 0.5 * width } else { width },
                title: Some(if hertz.is_some() {
                    seen_along
                } else {
                    format!("{title}: {seen_along}")
                }),
                parts: false,
                axes: true,
                length_unit: self.length_unit.clone(),
                value_label: "pressure".into(),
                value_range: (map.largest > 0.0).then_some((0.0, map.largest)),
                ..SvgOptions::default()
            };
            write_svg_layers(
                &path,
                &[SvgLayer::new(&map.mesh).with_cell_values(&map.values)],
                &options,
            )
            .map_err(|source| CliError::Mesh {
                context: path.display().to_string(),
                source,
            })?;
            if let Some(hertz) = hertz {
                let picture = std::fs::read_to_string(&path).map_err(|e| fail(e.to_string()))?;
                let (map_width, map_height) = svg_size(&picture)
                    .ok_or_else(|| fail("the map has no width and height".into()))?;
                let size = (
                    (width - map_width).max(300.0).round() as u32,
                    map_height.max(0.6 * (width - map_width)).round() as u32,
                );
                let view = map.view;
                let radius_of = |n: &InterfaceNode<3>| {
                    let d = n.position - centre;
                    (d - d.dot(&view) * view).norm()
                };
                let range = pair.nodes.clone();
                let profile = plot::radial_profile(&nodes[range], &radius_of, Some(hertz), size)
                    .map_err(fail)?;
                let document = side_by_side(title, &picture, map_width, map_height, &profile, size);
                write_atomically(&path, |w| w.write_all(document.as_bytes())).map_err(
                    |source| CliError::Mesh {
                        context: path.display().to_string(),
                        source,
                    },
                )?;
            }
            written.push(path);
        }
        Ok((written, notes))
    }

    /// The faces of body A's contact part of pair `k` all of whose vertices are nodes of the
    /// pair, projected onto the plane of the pair (seen along its mean normal, turned so that
    /// the axes are as close to the coordinate axes as they can be), each with the mean
    /// consistent pressure of its vertices.
    fn pressure_map(
        &self,
        nodes: &[InterfaceNode<3>],
        pair: &PairSummary,
        k: usize,
    ) -> Result<PressureMap, String> {
        let range = pair.nodes.clone();
        let first = nodes.get(range.start).ok_or("the pair has no node")?;
        let part = self.contact_parts.get(k).ok_or("no contact part")?;
        let body = self
            .contact_bodies
            .get(first.body_a)
            .and_then(|&i| self.bodies_3d.get(i))
            .ok_or("body A of the pair was not solved")?;
        let mesh = body.body.mesh();
        let node_of: std::collections::HashMap<usize, usize> =
            range.clone().map(|i| (nodes[i].vertex_a, i)).collect();
        let normal: Vector3 = range
            .clone()
            .map(|i| nodes[i].tributary_measure * nodes[i].normal)
            .sum();
        let normal = normal
            .try_normalize(0.0)
            .ok_or("the nodal normals of the pair add up to zero")?;
        // Seen along the coordinate axis closest to the normal, positive way.
        let axis = (0..3)
            .max_by(|&a, &b| normal[a].abs().total_cmp(&normal[b].abs()))
            .unwrap_or(2);
        let view = if normal[axis] < 0.0 { -normal } else { normal };
        let first_axis = Vector3::ith((axis + 1) % 3, 1.0);
        let u = (first_axis - first_axis.dot(&view) * view)
            .try_normalize(0.0)
            .ok_or("no plane to draw the pair in")?;
        let w = view.cross(&u);
        let mut local: std::collections::HashMap<usize, usize> = Default::default();
        let mut vertices = Vec::new();
        let mut polygons = Vec::new();
        let mut values = Vec::new();
        let mut largest = 0.0_f64;
        let mut weighted = Vector3::zeros();
        let mut weight = 0.0;
        for i in range.clone() {
            largest = largest.max(nodes[i].consistent_pressure);
            weighted += nodes[i].normal_force.abs() * nodes[i].position.coords;
            weight += nodes[i].normal_force.abs();
        }
        for &f in mesh.part_faces(part).unwrap_or_default() {
            let Some(face) = mesh
                .face(f)
                .iter()
                .map(|v| node_of.get(v).copied())
                .collect::<Option<Vec<usize>>>()
            else {
                continue;
            };
            let mut polygon: Vec<usize> = face
                .iter()
                .map(|&i| {
                    *local.entry(i).or_insert_with(|| {
                        let p = nodes[i].position.coords;
                        vertices.push(vem_mesh::Point::new(p.dot(&u), p.dot(&w)));
                        vertices.len() - 1
                    })
                })
                .collect();
            let n = polygon.len();
            let twice_area: f64 = (0..n)
                .map(|j| {
                    let (p, q) = (vertices[polygon[j]], vertices[polygon[(j + 1) % n]]);
                    p.x * q.y - p.y * q.x
                })
                .sum();
            if twice_area < 0.0 {
                polygon.reverse();
            }
            values.push(
                face.iter()
                    .map(|&i| nodes[i].consistent_pressure)
                    .sum::<f64>()
                    / n as f64,
            );
            polygons.push(polygon);
        }
        if polygons.is_empty() {
            return Err(format!(
                "no face of part '{part}' has all its vertices in contact nodes"
            ));
        }
        let mesh = vem_mesh::Mesh::from_polygons(vertices, &polygons, Vec::new()).map_err(|e| {
            format!("its faces seen along the normal do not make a mesh in the plane ({e})")
        })?;
        let centre = if weight > 0.0 {
            Point3::from(weighted / weight)
        } else {
            first.position
        };
        Ok(PressureMap {
            mesh,
            values,
            largest,
            view,
            centre,
            body: body.body.name().to_string(),
            part: part.clone(),
        })
    }
}

/// A contact surface in the plane of its pair, with a pressure per face.
struct PressureMap {
    mesh: vem_mesh::Mesh,
    values: Vec<f64>,
    /// The pair's largest consistent pressure.
    largest: f64,
    /// The direction it is seen along (unit).
    view: Vector3,
    /// The force-weighted centre of the pair's nodes.
    centre: Point3,
    body: String,
    part: String,
}

/// A component of a unit vector to three decimals, without a sign on zero.
fn rounded(value: f64) -> String {
    vem_scene::short((value * 1000.0).round() / 1000.0 + 0.0)
}

/// The `width` and `height` attributes of an SVG document's root element.
fn svg_size(document: &str) -> Option<(f64, f64)> {
    let start = document.find("<svg")?;
    let tag = &document[start..start + document[start..].find('>')?];
    let attribute = |name: &str| -> Option<f64> {
        let at = tag.find(&format!(" {name}=\""))? + name.len() + 3;
        tag[at..at + tag[at..].find('"')?].parse().ok()
    };
    Some((attribute("width")?, attribute("height")?))
}

/// One SVG document headed by `title`, with `left` (of `left_width` x `left_height` pixels)
/// and `right` (of `size`) beside each other below it, each kept as a nested `<svg>` element.
fn side_by_side(
    title: &str,
    left: &str,
    left_width: f64,
    left_height: f64,
    right: &str,
    size: (u32, u32),
) -> String {
    /// The height of the heading line.
    const HEADING: f64 = 36.0;
    let body = |document: &str| -> String {
        let start = document.find("<svg").unwrap_or(0);
        document[start..].trim_end().to_string()
    };
    let left = body(left).replacen("<svg", &format!("<svg y=\"{HEADING:.0}\""), 1);
    let right = body(right).replacen(
        "<svg",
        &format!("<svg x=\"{left_width:.0}\" y=\"{HEADING:.0}\""),
        1,
    );
    let width = left_width + size.0 as f64;
    let height = HEADING + left_height.max(size.1 as f64);
    let title = title
        .replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;");
    format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" \
         xmlns:xlink=\"http://www.w3.org/1999/xlink\" width=\"{width:.0}\" \
         height=\"{height:.0}\" viewBox=\"0 0 {width:.0} {height:.0}\">\n<rect width=\"100%\" \
         height=\"100%\" fill=\"white\"/>\n<text x=\"{:.0}\" y=\"26\" \
         text-anchor=\"middle\" font-family=\"sans-serif\" font-size=\"20\">{title}</text>\n\
         {left}\n{right}\n</svg>\n",
        0.5 * width
    )
}
