//! Gmsh `.msh` input in three dimensions (MSH 4.1 and 2.2, ASCII and binary): from a file to a
//! [`PolyhedralMesh`].
//!
//! What becomes what:
//! - every first-order tetrahedron (element type 4), hexahedron (5), prism (6) and pyramid (7)
//!   becomes a cell, in file order, its faces those of Gmsh's reference element (triangles and
//!   quadrangles, oriented outward); an element whose nodes are numbered as the mirror image of
//!   the reference (negative volume) is turned outside in, as the 2D reader turns clockwise
//!   polygons;
//! - nodes are found by their tags (any order, gaps, several blocks) and renumbered compactly in
//!   order of first use by a volume element; nodes no volume element uses are dropped;
//! - each physical surface group (dimension 2) becomes a boundary part made of the triangles
//!   (type 2) and quadrangles (type 3) of its surfaces, each of which must be a boundary face of
//!   the volume mesh; the group must have a name in `$PhysicalNames`. Parts come in increasing
//!   order of their physical tag; a named surface group without elements is an empty part;
//! - points (15), lines (1) and surface elements of no physical group are ignored; any other
//!   element type (second order, ...) is an error.
//!
//! Errors name the file and, where they can, the element by its tag and entity and the node by
//! its tag: a repeated node in an element, a degenerate (flat) element, two elements with the
//! same nodes, a face shared by more than two elements, a surface element that is not a boundary
//! face. A warped quadrangle (a bilinear face) is read as the mesh layer takes it, a fan surface,
//! unless its fan folds over or it crosses itself (a hexahedron with its nodes out of order). What the mesh validation finds beyond that (non-conforming faces, folded warped faces,
//! ...) is reported with the cells and vertices it names translated into element and node tags.

use std::collections::{BTreeMap, HashMap, HashSet};
use std::fs;
use std::path::Path;

use super::gmsh::TagIndex;
use super::msh::{element_type_name, read_msh_bytes, MshFile};
use crate::polyhedral::geometry::Polyhedron;
use crate::{FacePartSpec, MeshError, Point3, PolyhedralMesh};

/// Gmsh's type number of a 2-node line.
const LINE: i32 = 1;
/// Gmsh's type number of a 3-node triangle.
const TRIANGLE: i32 = 2;
/// Gmsh's type number of a 4-node quadrangle.
const QUADRANGLE: i32 = 3;
/// Gmsh's type number of a 4-node tetrahedron.
const TETRAHEDRON: i32 = 4;
/// Gmsh's type number of an 8-node hexahedron.
const HEXAHEDRON: i32 = 5;
/// Gmsh's type number of a 6-node prism.
const PRISM: i32 = 6;
/// Gmsh's type number of a 5-node pyramid.
const PYRAMID: i32 = 7;
/// Gmsh's type number of a 1-node point.
const POINT: i32 = 15;

/// Volumes at most this fraction of the cube of an element's diameter count as zero.
const VOLUME_TOLERANCE: f64 = 1e-12;

/// The faces of Gmsh's reference elements as loops of local node indices, oriented outward
/// (right-hand normal out of the element) for the reference numbering.
fn reference_faces(element_type: i32) -> &'static [&'static [usize]] {
    match element_type {
        TETRAHEDRON => &[&[0, 2, 1], &[0, 1, 3], &[0, 3, 2], &[1, 2, 3]],
        HEXAHEDRON => &[
            &[0, 3, 2, 1],
            &[4, 5, 6, 7],
            &[0, 1, 5, 4],
            &[1, 2, 6, 5],
            &[2, 3, 7, 6],
            &[3, 0, 4, 7],
        ],
        PRISM => &[
            &[0, 2, 1],
            &[3, 4, 5],
            &[0, 1, 4, 3],
            &[1, 2, 5, 4],
            &[2, 0, 3, 5],
        ],
        PYRAMID => &[
            &[0, 3, 2, 1],
            &[0, 1, 4],
            &[1, 2, 4],
            &[2, 3, 4],
            &[3, 0, 4],
        ],
        _ => &[],
    }
}

/// Reads a 3D mesh from a Gmsh `.msh` file in format 4.1 or 2.2 (ASCII or binary).
///
/// Tetrahedra, hexahedra, prisms and pyramids become polyhedral cells, named physical surface
/// groups become boundary parts (see the module documentation). Errors are [`MeshError::Read`]
/// naming the file and what is wrong with it, with the element or node tag where there is one.
///
/// ```
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/gmsh-corpus-3d/box_tetrahedra_41.msh");
/// let mesh = vem_mesh::io::read_gmsh_polyhedral(path)?;
/// let volume: f64 = (0..mesh.n_cells()).map(|c| mesh.volume(c)).sum();
/// assert!((volume - 1.0).abs() < 1e-12);
/// assert_eq!(mesh.part_names(), ["left", "right", "front", "back", "bottom", "top"]);
/// # Ok::<(), vem_mesh::MeshError>(())
/// ```
pub fn read_gmsh_polyhedral(path: impl AsRef<Path>) -> Result<PolyhedralMesh, MeshError> {
    let path = path.as_ref();
    let bytes = fs::read(path).map_err(|e| MeshError::Read {
        path: path.to_path_buf(),
        reason: format!("cannot read the file: {e}"),
    })?;
    read_gmsh_polyhedral_bytes(&bytes, path)
}

/// Reads a 3D mesh from the contents of a Gmsh `.msh` file held in memory, exactly as
/// [`read_gmsh_polyhedral`] does; `name` is the file name used in error messages.
pub fn read_gmsh_polyhedral_bytes(
    bytes: &[u8],
    name: impl AsRef<Path>,
) -> Result<PolyhedralMesh, MeshError> {
    let parsed = read_msh_bytes(bytes).map_err(|e| MeshError::Read {
        path: name.as_ref().to_path_buf(),
        reason: e.to_string(),
    })?;
    polyhedral_mesh_from_msh(&parsed, name)
}

/// The 3D mesh of an already parsed Gmsh file, exactly as [`read_gmsh_polyhedral_bytes`]
/// makes it from the file's bytes; `name` is the file name used in error messages.
pub fn polyhedral_mesh_from_msh(
    msh: &MshFile,
    name: impl AsRef<Path>,
) -> Result<PolyhedralMesh, MeshError> {
    convert(msh).map_err(|reason| MeshError::Read {
        path: name.as_ref().to_path_buf(),
        reason,
    })
}

/// A volume element of the file, as read.
struct Volume<'a> {
    tag: u64,
    element_type: i32,
    entity: i32,
    nodes: &'a [u64],
}

impl Volume<'_> {
    /// "volume element 12 (Hex8) of volume entity 3".
    fn describe(&self) -> String {
        let name = element_type_name(self.element_type).map_or("?", |(name, _)| name);
        format!(
            "volume element {} ({name}) of volume entity {}",
            self.tag, self.entity
        )
    }
}

/// Turns a parsed MSH file into a polyhedral mesh; errors are the reason text of
/// [`MeshError::Read`].
fn convert(msh: &MshFile) -> Result<PolyhedralMesh, String> {
    let nodes = TagIndex::new(&msh.nodes)?;

    // Volume elements become cells; surface elements are kept per surface entity. Volumes are
    // looked at first, so that a second-order mesh is reported by its volume elements.
    let mut volumes: Vec<Volume> = Vec::new();
    let mut surfaces: BTreeMap<i32, Vec<(u64, &[u64])>> = BTreeMap::new();
    let volumes_first = msh
        .elements
        .iter()
        .filter(|e| e.entity_dim == 3)
        .chain(msh.elements.iter().filter(|e| e.entity_dim != 3));
    for element in volumes_first {
        match (element.entity_dim, element.element_type) {
            (0, POINT) | (1, LINE) => {}
            (2, TRIANGLE | QUADRANGLE) => surfaces
                .entry(element.entity_tag)
                .or_default()
                .push((element.tag, &element.nodes)),
            (3, TETRAHEDRON | HEXAHEDRON | PRISM | PYRAMID) => volumes.push(Volume {
                tag: element.tag,
                element_type: element.element_type,
                entity: element.entity_tag,
                nodes: &element.nodes,
            }),
            (dim, element_type) => {
                return Err(unsupported_element(element_type, dim, element.entity_tag))
            }
        }
    }
    if volumes.is_empty() {
        return Err(
            "the file contains no 3D elements (4-node tetrahedra, 8-node hexahedra, 6-node \
             prisms or 5-node pyramids); when a .geo file defines physical groups, Gmsh saves \
             only the elements of physical groups: add a Physical Volume"
                .into(),
        );
    }

    // Compact renumbering in order of first use; `node_tags[v]` is the tag of vertex v.
    let mut compact = vec![usize::MAX; msh.nodes.len()];
    let mut vertices: Vec<Point3> = Vec::new();
    let mut node_tags: Vec<u64> = Vec::new();
    let mut cells: Vec<Vec<Vec<usize>>> = Vec::with_capacity(volumes.len());
    let mut same_nodes: HashMap<Vec<usize>, u64> = HashMap::with_capacity(volumes.len());
    for volume in &volumes {
        let mut local = Vec::with_capacity(volume.nodes.len());
        for &node in volume.nodes {
            let position = nodes.get(node).ok_or_else(|| {
                format!(
                    "{} refers to node {node}, which is not in the $Nodes section",
                    volume.describe()
                )
            })?;
            if compact[position] == usize::MAX {
                let [x, y, z] = msh.nodes[position].xyz;
                vertices.push(Point3::new(x, y, z));
                node_tags.push(node);
                compact[position] = vertices.len() - 1;
            }
            let v = compact[position];
            if local.contains(&v) {
                return Err(format!("{} lists node {node} twice", volume.describe()));
            }
            local.push(v);
        }
        let mut key = local.clone();
        key.sort_unstable();
        if let Some(first) = same_nodes.insert(key, volume.tag) {
            return Err(format!(
                "{} has the same nodes as volume element {first}",
                volume.describe()
            ));
        }
        let mut faces: Vec<Vec<usize>> = reference_faces(volume.element_type)
            .iter()
            .map(|face| face.iter().map(|&k| local[k]).collect())
            .collect();
        // The orientation of the node numbering: the signed volume of the reference faces.
        let points: Vec<Point3> = local.iter().map(|&v| vertices[v]).collect();
        let local_faces: Vec<Vec<usize>> = reference_faces(volume.element_type)
            .iter()
            .map(|face| face.to_vec())
            .collect();
        let cell = Polyhedron::new(points, &local_faces);
        let (signed, diameter) = (cell.volume(), cell.diameter());
        if !(signed.is_finite() && signed.abs() > VOLUME_TOLERANCE * diameter.powi(3)) {
            return Err(format!(
                "{} is degenerate: volume {signed:e} for diameter {diameter:e}",
                volume.describe()
            ));
        }
        if signed < 0.0 {
            faces.iter_mut().for_each(|face| face.reverse());
        }
        cells.push(faces);
    }

    // The cells around every face (by vertex set), to find faces of more than two cells and to
    // tell boundary faces.
    let mut cells_of_face: HashMap<Vec<usize>, Vec<usize>> = HashMap::new();
    let mut face_order: Vec<Vec<usize>> = Vec::new();
    for (c, cell) in cells.iter().enumerate() {
        for face in cell {
            let mut key = face.clone();
            key.sort_unstable();
            let entry = cells_of_face.entry(key.clone()).or_default();
            if entry.is_empty() {
                face_order.push(key);
            }
            entry.push(c);
            if entry.len() > 2 {
                let tags: Vec<u64> = entry.iter().map(|&c| volumes[c].tag).collect();
                let face_nodes: Vec<u64> = face.iter().map(|&v| node_tags[v]).collect();
                return Err(format!(
                    "the face with nodes {face_nodes:?} is a face of the volume elements \
                     {tags:?}; a face bounds at most two elements (overlapping or duplicated \
                     elements)"
                ));
            }
        }
    }

    let parts = boundary_parts(msh, &surfaces, &nodes, &compact, &cells_of_face)?;
    let n_cells = cells.len();
    PolyhedralMesh::from_polyhedra(vertices, &cells, parts).map_err(|e| {
        let located = locate(&e, &volumes, &node_tags, &face_order, &cells_of_face);
        format!(
            "the mesh it describes is invalid: {e}{located} (cells are its {n_cells} volume \
             elements numbered from 0 in file order; vertices are its nodes numbered from 0 in \
             order of first use)"
        )
    })
}

/// The cells and vertices a validation error names, as element and node tags.
fn locate(
    error: &MeshError,
    volumes: &[Volume],
    node_tags: &[u64],
    face_order: &[Vec<usize>],
    cells_of_face: &HashMap<Vec<usize>, Vec<usize>>,
) -> String {
    let cell = |c: usize| {
        volumes
            .get(c)
            .map_or(String::new(), |v| format!("cell {c} is {}", v.describe()))
    };
    let vertex = |v: usize| {
        node_tags
            .get(v)
            .map_or(String::new(), |t| format!("vertex {v} is node {t}"))
    };
    let face = |f: usize| {
        face_order.get(f).map_or(String::new(), |key| {
            let tags: Vec<u64> = key.iter().map(|&v| node_tags[v]).collect();
            let elements: Vec<u64> = cells_of_face
                .get(key)
                .map(|cells| cells.iter().map(|&c| volumes[c].tag).collect())
                .unwrap_or_default();
            format!("face {f} has the nodes {tags:?} and bounds the volume elements {elements:?}")
        })
    };
    let notes: Vec<String> = match error {
        MeshError::InvertedCell { cell: c, .. }
        | MeshError::DegenerateCell { cell: c, .. }
        | MeshError::CellNotClosed { cell: c, .. } => vec![cell(*c)],
        MeshError::DisconnectedCell {
            cell: c, face: f, ..
        } => vec![cell(*c), face(*f)],
        MeshError::HangingVertex {
            vertex: v, face: f, ..
        } => vec![vertex(*v), face(*f)],
        MeshError::DuplicateVertices { a, b, .. } => vec![vertex(*a), vertex(*b)],
        MeshError::DegenerateFace { face: f, .. }
        | MeshError::SelfIntersectingFace { face: f, .. }
        | MeshError::FoldedFace { face: f, .. }
        | MeshError::OverusedFace { face: f, .. }
        | MeshError::FaceSameOrientation { face: f, .. } => vec![face(*f)],
        MeshError::DuplicateFace { a, b } => vec![face(*a), face(*b)],
        _ => Vec::new(),
    };
    let notes: Vec<String> = notes.into_iter().filter(|n| !n.is_empty()).collect();
    if notes.is_empty() {
        String::new()
    } else {
        format!(" ({})", notes.join("; "))
    }
}

/// The boundary parts: one per physical surface group, in increasing order of physical tag.
fn boundary_parts(
    msh: &MshFile,
    surfaces: &BTreeMap<i32, Vec<(u64, &[u64])>>,
    nodes: &TagIndex,
    compact: &[usize],
    cells_of_face: &HashMap<Vec<usize>, Vec<usize>>,
) -> Result<Vec<FacePartSpec>, String> {
    let mut entities_of_group: BTreeMap<i32, Vec<i32>> = msh
        .physical_groups()
        .into_iter()
        .filter(|&((dim, _), _)| dim == 2)
        .map(|((_, tag), entities)| (tag, entities))
        .collect();
    for &(dim, tag) in msh.physical_names.keys() {
        if dim == 2 {
            entities_of_group.entry(tag).or_default();
        }
    }
    let vertex_of = |tag: u64| {
        nodes
            .get(tag)
            .map(|i| compact[i])
            .filter(|&v| v != usize::MAX)
    };
    let mut parts = Vec::with_capacity(entities_of_group.len());
    for (tag, entities) in entities_of_group {
        let name = msh.physical_names.get(&(2, tag)).ok_or_else(|| {
            format!(
                "physical surface group {tag} (surface entities {entities:?}) has no name in \
                 $PhysicalNames; name it in the .geo file, e.g. Physical Surface(\"contact\", \
                 {tag})"
            )
        })?;
        // MSH 2 writes an element once per physical group it is in: a part is a set of faces.
        let mut faces = Vec::new();
        let mut seen = HashSet::new();
        for entity in entities {
            for &(element_tag, element_nodes) in surfaces.get(&entity).into_iter().flatten() {
                let loop_: Option<Vec<usize>> =
                    element_nodes.iter().map(|&n| vertex_of(n)).collect();
                let boundary = loop_.filter(|l| {
                    let mut key = l.clone();
                    key.sort_unstable();
                    cells_of_face
                        .get(&key)
                        .is_some_and(|cells| cells.len() == 1)
                });
                let loop_ = boundary.ok_or_else(|| {
                    format!(
                        "surface element {element_tag} (nodes {element_nodes:?}) of surface \
                         entity {entity} in physical surface group '{name}' is not a boundary \
                         face of the volume elements"
                    )
                })?;
                let mut key = loop_.clone();
                key.sort_unstable();
                if seen.insert(key) {
                    faces.push(loop_);
                }
            }
        }
        parts.push(FacePartSpec::new(name.clone(), faces));
    }
    Ok(parts)
}

/// The error for an element of a type this reader does not take.
fn unsupported_element(element_type: i32, dim: i32, entity_tag: i32) -> String {
    let entity = match dim {
        0 => "point",
        1 => "curve",
        2 => "surface",
        _ => "volume",
    };
    let (name, nodes) = element_type_name(element_type).unwrap_or(("unknown", 0));
    let corners = match name.get(..3) {
        Some("Lin") => 2,
        Some("Tri") => 3,
        Some("Qua") => 4,
        Some("Tet") => 4,
        Some("Hex") => 8,
        Some("Pri") => 6,
        Some("Pyr") => 5,
        _ => 0,
    };
    let what = if corners > 0 && nodes > corners {
        format!(
            "higher-order elements ({nodes} nodes) are not supported; mesh with element order \
             1 (gmsh -order 1)"
        )
    } else {
        "only points (15), 2-node lines (1), 3-node triangles (2), 4-node quadrangles (3) and \
         the volume elements 4-node tetrahedra (4), 8-node hexahedra (5), 6-node prisms (6) and \
         5-node pyramids (7) are supported"
            .to_string()
    };
    format!("element type {element_type} ({name}) in {entity} entity {entity_tag}: {what}")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit cube of one hexahedron (nodes 1..8 at the corners, Gmsh's numbering) and the
    /// node 9 at (2, 0, 0); `elements` is spliced into the $Elements section (MSH 2.2).
    fn cube_msh(elements: &str, names: &str) -> String {
        format!(
            "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n{names}\
             $Nodes\n9\n1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 0 0 1\n6 1 0 1\n7 1 1 1\n8 0 1 1\n\
             9 2 0 0\n$EndNodes\n$Elements\n{elements}$EndElements\n"
        )
    }

    fn error(text: &str) -> String {
        read_gmsh_polyhedral_bytes(text.as_bytes(), "cube.msh")
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn a_hexahedron_and_a_named_face() {
        let names = "$PhysicalNames\n1\n2 4 \"bottom face\"\n$EndPhysicalNames\n";
        let text = cube_msh("2\n7 5 2 1 1 1 2 3 4 5 6 7 8\n8 3 2 4 1 1 4 3 2\n", names);
        let mesh = read_gmsh_polyhedral_bytes(text.as_bytes(), "cube.msh").unwrap();
        assert_eq!(
            (mesh.n_cells(), mesh.n_vertices(), mesh.n_faces()),
            (1, 8, 6)
        );
        assert!((mesh.volume(0) - 1.0).abs() < 1e-15);
        assert_eq!(mesh.part_names(), ["bottom face"]);
        let face = mesh.part_faces("bottom face").unwrap()[0];
        assert!((mesh.face_normal(face) - crate::Vector3::new(0.0, 0.0, -1.0)).norm() < 1e-15);
    }

    #[test]
    fn a_mirrored_element_is_turned_outside_in() {
        // Nodes 1 2 3 4 5 6 7 8 with top and bottom swapped: the mirror image.
        let text = cube_msh("1\n7 5 2 1 1 5 6 7 8 1 2 3 4\n", "");
        let mesh = read_gmsh_polyhedral_bytes(text.as_bytes(), "cube.msh").unwrap();
        assert!((mesh.volume(0) - 1.0).abs() < 1e-15);
    }

    #[test]
    fn bad_elements_are_named_by_their_tags() {
        assert_eq!(
            error(&cube_msh("1\n7 5 2 1 3 1 2 3 4 5 6 7 7\n", "")),
            "cube.msh: volume element 7 (Hex8) of volume entity 3 lists node 7 twice"
        );
        assert_eq!(
            error(&cube_msh("2\n7 4 2 1 1 1 2 4 5\n8 4 2 1 1 2 4 1 5\n", "")),
            "cube.msh: volume element 8 (Tet4) of volume entity 1 has the same nodes as volume \
             element 7"
        );
        // A flat tetrahedron: nodes 1, 2, 3, 4 all in z = 0.
        assert!(error(&cube_msh("1\n7 4 2 1 1 1 2 3 4\n", ""))
            .starts_with("cube.msh: volume element 7 (Tet4) of volume entity 1 is degenerate"));
        // Three tetrahedra on the face (1, 2, 5).
        let three = "3\n7 4 2 1 1 1 2 4 5\n8 4 2 1 1 1 2 5 7\n9 4 2 1 1 1 2 5 8\n";
        let message = error(&cube_msh(three, ""));
        assert!(
            message.contains("is a face of the volume elements [7, 8, 9]"),
            "{message}"
        );
        // A surface element that is not a boundary face.
        let names = "$PhysicalNames\n1\n2 4 \"inside\"\n$EndPhysicalNames\n";
        let two = "3\n7 4 2 1 1 1 2 4 5\n8 4 2 1 1 2 3 4 7\n9 2 2 4 2 2 4 9\n";
        let message = error(&cube_msh(two, names));
        assert!(
            message.contains("surface element 9 (nodes [2, 4, 9]) of surface entity 2 in physical surface group 'inside' is not a boundary face"),
            "{message}"
        );
        // Second order and unknown types.
        let message = error(&cube_msh("1\n7 11 2 1 1 1 2 3 4 5 6 7 8 9 1\n", ""));
        assert!(
            message.contains("element type 11 (Tet10) in volume entity 1: higher-order"),
            "{message}"
        );
        let message = error(&cube_msh("1\n7 15 2 1 1 1\n", ""));
        assert!(
            message.starts_with("cube.msh: the file contains no 3D elements"),
            "{message}"
        );
    }

    #[test]
    fn elements_with_nodes_out_of_order_are_located() {
        // Nodes 3 and 4 swapped, and 7 and 8: the bottom and the top cross themselves.
        let message = error(&cube_msh("1\n7 5 2 1 1 1 2 4 3 5 6 8 7\n", ""));
        assert!(message.contains("volume element 7 (Hex8)"), "{message}");
        // The top turned by half a turn: the four sides cross themselves.
        let message = error(&cube_msh("1\n7 5 2 1 1 1 2 3 4 7 8 5 6\n", ""));
        assert!(
            message
                .contains("face 2 has the nodes [1, 2, 7, 8] and bounds the volume elements [7]"),
            "{message}"
        );
    }

    #[test]
    fn an_unnamed_surface_group_is_an_error() {
        let text = cube_msh("2\n7 5 2 1 1 1 2 3 4 5 6 7 8\n8 3 2 4 1 1 4 3 2\n", "");
        assert!(
            error(&text).contains("physical surface group 4 (surface entities [1]) has no name")
        );
    }

    #[test]
    fn validation_errors_are_located_by_element_and_node_tags() {
        // Two hexahedra side by side whose shared side does not match: the second has a node
        // in the middle of the first's face (a hanging node the first does not list).
        let text = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n13\n\
            1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 0 0 1\n6 1 0 1\n7 1 1 1\n8 0 1 1\n\
            10 2 0 0\n11 2 1 0\n12 2 0 1\n13 2 1 1\n14 1 0.5 0.5\n$EndNodes\n\
            $Elements\n3\n1 5 2 1 1 1 2 3 4 5 6 7 8\n\
            2 7 2 1 1 2 10 11 3 14\n3 4 2 1 1 2 10 12 14\n$EndElements\n";
        let message = error(text);
        assert!(message.contains("node 14"), "{message}");
        assert!(message.contains("the volume elements [1]"), "{message}");
    }
}
