//! Gmsh `.msh` 4.1 input (ASCII and binary), parsed with `mshio`.
//!
//! What becomes what:
//! - every first-order triangle (element type 2) and quadrangle (type 3) becomes a polygon,
//!   oriented counter-clockwise; 2D physical groups are not needed and are ignored;
//! - nodes are renumbered compactly in order of first use by a 2D element; nodes that no 2D
//!   element uses (geometry points, probes) are dropped;
//! - each named physical curve group (dimension 1 in `$PhysicalNames`) becomes a boundary part
//!   made of its line elements (type 2-node line, type 1), each of which must be a boundary edge
//!   of the 2D mesh. Parts come in increasing order of their physical tag;
//! - point elements (type 15) are ignored; any other element type is an error.
//!
//! `mshio` does not read `$PhysicalNames`; this module reads that section itself (it is ASCII
//! text in both ASCII and binary files). When the node tags of a file are dense (exactly
//! `min..=max`), `mshio` does not keep them: nodes then carry the tags `min, min + 1, ...` in
//! the order of the `$Nodes` section, which is how Gmsh writes them.

use std::collections::{BTreeMap, HashMap};
use std::fs;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;

use mshio::{ElementType, MshFile, MshParserError};

use crate::{geometry, Mesh, MeshError, PartSpec, Point};

/// Gmsh's type number of a 2-node line.
const LINE: i32 = 1;
/// Gmsh's type number of a 3-node triangle.
const TRIANGLE: i32 = 2;
/// Gmsh's type number of a 4-node quadrangle.
const QUADRANGLE: i32 = 3;
/// Gmsh's type number of a 1-node point.
const POINT: i32 = 15;

/// Reads a 2D mesh from a Gmsh `.msh` file in format 4.1 (ASCII or binary).
///
/// Triangles and quadrangles become counter-clockwise polygons, named physical curve groups
/// become boundary parts (see the module documentation). Errors are [`MeshError::Read`] naming
/// the file and what is wrong with it: a parse error (with the section and line), an element
/// type other than points, 2-node lines, triangles and quadrangles (with its type number and
/// entity tag; second-order elements are named as such), a physical curve group without a name
/// (with its tag), a line element that is not a boundary edge (with its element tag), no 2D
/// elements, or a mesh that fails validation.
///
/// ```
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/unit_square.msh");
/// let mesh = vem_mesh::io::read_gmsh(path)?;
/// let area: f64 = (0..mesh.n_polygons()).map(|p| mesh.area(p)).sum();
/// assert!((area - 1.0).abs() < 1e-12);
/// assert_eq!(mesh.part_names(), ["bottom", "right", "top", "left"]);
/// # Ok::<(), vem_mesh::MeshError>(())
/// ```
pub fn read_gmsh(path: impl AsRef<Path>) -> Result<Mesh, MeshError> {
    let path = path.as_ref();
    let bytes = fs::read(path).map_err(|e| MeshError::Read {
        path: path.to_path_buf(),
        reason: format!("cannot read the file: {e}"),
    })?;
    read_gmsh_bytes(&bytes, path)
}

/// Reads a 2D mesh from the contents of a Gmsh `.msh` 4.1 file held in memory, exactly as
/// [`read_gmsh`] does; `name` is the file name used in error messages.
pub fn read_gmsh_bytes(bytes: &[u8], name: impl AsRef<Path>) -> Result<Mesh, MeshError> {
    let fail = |reason: String| MeshError::Read {
        path: name.as_ref().to_path_buf(),
        reason,
    };
    // mshio still has a few `unimplemented!` paths for exotic headers: turn a panic into an
    // error rather than taking the caller down.
    let parsed = catch_unwind(AssertUnwindSafe(|| {
        mshio::parse_msh_bytes(bytes).map_err(|e| describe_parse_error(bytes, &e))
    }))
    .map_err(|_| fail("the MSH parser failed on this file (unsupported header?)".into()))?
    .map_err(fail)?;
    let binary = parsed.header.file_type != 0;
    let names = physical_names(bytes, binary).map_err(fail)?;
    convert(&parsed, &names).map_err(fail)
}

/// Turns a parsed MSH file into a mesh; errors are the reason text of [`MeshError::Read`].
fn convert(
    msh: &MshFile<u64, i32, f64>,
    names: &HashMap<(i32, i32), String>,
) -> Result<Mesh, String> {
    let nodes = node_coordinates(msh)?;
    let blocks = msh
        .data
        .elements
        .as_ref()
        .map(|e| e.element_blocks.as_slice())
        .unwrap_or_default();

    // Sort the element blocks: 2D elements become polygons, 2-node lines are kept per curve.
    // Surface blocks are looked at first, so that a second-order mesh is reported by its
    // triangles rather than by its boundary lines.
    let mut faces: Vec<(u64, &[u64])> = Vec::new();
    let mut lines_of_curve: HashMap<i32, Vec<(u64, [u64; 2])>> = HashMap::new();
    let surfaces_first = blocks
        .iter()
        .filter(|b| b.entity_dim == 2)
        .chain(blocks.iter().filter(|b| b.entity_dim != 2));
    for block in surfaces_first {
        let type_number = block.element_type as i32;
        match (block.entity_dim, type_number) {
            (0, POINT) => {}
            (1, LINE) => {
                let lines = lines_of_curve.entry(block.entity_tag).or_default();
                for element in &block.elements {
                    lines.push((element.element_tag, [element.nodes[0], element.nodes[1]]));
                }
            }
            (2, TRIANGLE | QUADRANGLE) => faces.extend(
                block
                    .elements
                    .iter()
                    .map(|e| (e.element_tag, e.nodes.as_slice())),
            ),
            (dim, _) => {
                return Err(unsupported_element(
                    block.element_type,
                    dim,
                    block.entity_tag,
                ))
            }
        }
    }
    if faces.is_empty() {
        return Err(
            "the file contains no 2D elements (3-node triangles or 4-node quadrangles); \
                    when a .geo file defines physical groups, Gmsh saves only the elements of \
                    physical groups: add a Physical Surface"
                .into(),
        );
    }

    // Compact renumbering in order of first use; counter-clockwise loops.
    let mut compact: HashMap<u64, usize> = HashMap::new();
    let mut vertices: Vec<Point> = Vec::new();
    let mut plane_z: Option<(u64, f64)> = None;
    let mut polygons: Vec<Vec<usize>> = Vec::with_capacity(faces.len());
    for &(element_tag, element_nodes) in &faces {
        let mut polygon = Vec::with_capacity(element_nodes.len());
        for &node in element_nodes {
            let index = match compact.get(&node) {
                Some(&index) => index,
                None => {
                    let &[x, y, z] = nodes.get(&node).ok_or_else(|| {
                        format!(
                            "element {element_tag} refers to node {node}, which is not in the \
                             $Nodes section"
                        )
                    })?;
                    match plane_z {
                        None => plane_z = Some((node, z)),
                        Some((first, z0)) if (z - z0).abs() > 1e-9 * (1.0 + z0.abs()) => {
                            return Err(format!(
                                "node {node} has z = {z} but node {first} has z = {z0}: a 2D \
                                 mesh must lie in a plane z = constant"
                            ));
                        }
                        Some(_) => {}
                    }
                    vertices.push(Point::new(x, y));
                    compact.insert(node, vertices.len() - 1);
                    vertices.len() - 1
                }
            };
            polygon.push(index);
        }
        let points: Vec<Point> = polygon.iter().map(|&v| vertices[v]).collect();
        if geometry::signed_area(&points) < 0.0 {
            polygon.reverse();
        }
        polygons.push(polygon);
    }

    let parts = boundary_parts(msh, names, &lines_of_curve, &compact, &polygons)?;
    let n_polygons = polygons.len();
    Mesh::from_polygons(vertices, &polygons, parts).map_err(|e| {
        format!(
            "the mesh it describes is invalid: {e} (polygons are its {n_polygons} triangles and \
             quadrangles numbered from 0 in file order; vertices are its nodes numbered from 0 \
             in order of first use)"
        )
    })
}

/// Coordinates of every node, by node tag.
fn node_coordinates(msh: &MshFile<u64, i32, f64>) -> Result<HashMap<u64, [f64; 3]>, String> {
    let Some(section) = msh.data.nodes.as_ref() else {
        return Ok(HashMap::new());
    };
    let mut nodes = HashMap::with_capacity(section.node_blocks.iter().map(|b| b.nodes.len()).sum());
    let mut next_dense_tag = section.min_node_tag;
    for block in &section.node_blocks {
        let tags: Vec<u64> = match &block.node_tags {
            Some(tag_to_index) => {
                let mut tags = vec![0; block.nodes.len()];
                for (&tag, &index) in tag_to_index {
                    tags[index] = tag;
                }
                tags
            }
            None => {
                let start = next_dense_tag;
                next_dense_tag += block.nodes.len() as u64;
                (start..next_dense_tag).collect()
            }
        };
        for (tag, node) in tags.into_iter().zip(&block.nodes) {
            if nodes.insert(tag, [node.x, node.y, node.z]).is_some() {
                return Err(format!(
                    "node tag {tag} is defined twice in the $Nodes section"
                ));
            }
        }
    }
    Ok(nodes)
}

/// The boundary parts: one per physical curve group, in increasing order of physical tag.
fn boundary_parts(
    msh: &MshFile<u64, i32, f64>,
    names: &HashMap<(i32, i32), String>,
    lines_of_curve: &HashMap<i32, Vec<(u64, [u64; 2])>>,
    compact: &HashMap<u64, usize>,
    polygons: &[Vec<usize>],
) -> Result<Vec<PartSpec>, String> {
    // Physical tag -> curves carrying it.
    let mut curves_of_group: BTreeMap<i32, Vec<i32>> = BTreeMap::new();
    if let Some(entities) = &msh.data.entities {
        for curve in &entities.curves {
            for &physical in &curve.physical_tags {
                // Gmsh writes a negative physical tag for a reversed orientation.
                curves_of_group
                    .entry(physical.abs())
                    .or_default()
                    .push(curve.tag);
            }
        }
    }
    // Named dimension-1 groups with no curve: empty parts (the user asked for the name).
    for &(dim, tag) in names.keys() {
        if dim == 1 {
            curves_of_group.entry(tag).or_default();
        }
    }
    if curves_of_group.is_empty() {
        return Ok(Vec::new());
    }

    let mut uses: HashMap<(usize, usize), usize> = HashMap::new();
    for polygon in polygons {
        for k in 0..polygon.len() {
            let (a, b) = (polygon[k], polygon[(k + 1) % polygon.len()]);
            *uses.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    let mut parts = Vec::with_capacity(curves_of_group.len());
    for (tag, curves) in curves_of_group {
        let name = names.get(&(1, tag)).ok_or_else(|| {
            format!(
                "physical curve group {tag} (curve entities {curves:?}) has no name in \
                 $PhysicalNames; name it in the .geo file, e.g. Physical Curve(\"contact\", {tag})"
            )
        })?;
        let mut edges = Vec::new();
        for curve in curves {
            for &(element_tag, [a, b]) in lines_of_curve.get(&curve).into_iter().flatten() {
                let edge = match (compact.get(&a), compact.get(&b)) {
                    (Some(&a), Some(&b)) if uses.get(&(a.min(b), a.max(b))) == Some(&1) => {
                        Some([a, b])
                    }
                    _ => None,
                };
                edges.push(edge.ok_or_else(|| {
                    format!(
                        "line element {element_tag} (nodes {a} and {b}) of curve entity {curve} \
                         in physical curve group '{name}' is not a boundary edge of the 2D mesh"
                    )
                })?);
            }
        }
        parts.push(PartSpec::new(name.clone(), edges));
    }
    Ok(parts)
}

/// The error for an element block of a type this reader does not take.
fn unsupported_element(element_type: ElementType, dim: i32, entity_tag: i32) -> String {
    let type_number = element_type as i32;
    let entity = match dim {
        0 => "point",
        1 => "curve",
        2 => "surface",
        _ => "volume",
    };
    let corners = match format!("{element_type:?}").get(..3) {
        Some("Lin") => 2,
        Some("Tri") => 3,
        Some("Qua") => 4,
        _ => 0,
    };
    let nodes = element_type.nodes().unwrap_or(0);
    let what = if corners > 0 && nodes > corners {
        let order = match element_type {
            ElementType::Lin3 | ElementType::Tri6 | ElementType::Qua8 | ElementType::Qua9 => {
                "second-order"
            }
            _ => "higher-order",
        };
        format!(
            "{order} elements ({nodes} nodes) are not supported; mesh with element order 1 \
             (gmsh -order 1)"
        )
    } else if dim == 3 {
        "3D elements are not supported; the mesh must be 2D".to_string()
    } else {
        "only points (15), 2-node lines (1), 3-node triangles (2) and 4-node quadrangles (3) \
         are supported"
            .to_string()
    };
    format!("element type {type_number} ({element_type:?}) in {entity} entity {entity_tag}: {what}")
}

/// Reads the `$PhysicalNames` section: (dimension, physical tag) -> name.
///
/// The section is ASCII in both ASCII and binary files. In a binary file the scan stops at the
/// first binary section (`$Entities`, `$Nodes` or `$Elements`); Gmsh writes `$PhysicalNames`
/// before them.
fn physical_names(bytes: &[u8], binary: bool) -> Result<HashMap<(i32, i32), String>, String> {
    let mut names = HashMap::new();
    let mut lines = bytes
        .split(|&b| b == b'\n')
        .enumerate()
        .map(|(i, line)| (i + 1, String::from_utf8_lossy(line).trim().to_string()));
    while let Some((_, line)) = lines.next() {
        if binary && matches!(line.as_str(), "$Entities" | "$Nodes" | "$Elements") {
            break;
        }
        if line != "$PhysicalNames" {
            continue;
        }
        let bad = |line_number: usize, what: &str| {
            format!("$PhysicalNames section, line {line_number}: {what}")
        };
        let (number, count) = lines
            .next()
            .ok_or_else(|| bad(0, "the file ends after the section header"))?;
        let count: usize = count.parse().map_err(|_| {
            bad(
                number,
                &format!("expected the number of names, found '{count}'"),
            )
        })?;
        for _ in 0..count {
            let (number, entry) = lines
                .next()
                .ok_or_else(|| bad(number, "the file ends inside the section"))?;
            let (dim, tag, name) = parse_physical_name(&entry).ok_or_else(|| {
                bad(
                    number,
                    &format!("expected 'dimension tag \"name\"', found '{entry}'"),
                )
            })?;
            names.insert((dim, tag), name);
        }
        match lines.next() {
            Some((_, end)) if end == "$EndPhysicalNames" => {}
            Some((number, other)) => {
                return Err(bad(
                    number,
                    &format!("expected $EndPhysicalNames, found '{other}'"),
                ))
            }
            None => return Err(bad(number, "the file ends before $EndPhysicalNames")),
        }
    }
    Ok(names)
}

/// Parses `dim tag "name"` (the name may contain spaces).
fn parse_physical_name(entry: &str) -> Option<(i32, i32, String)> {
    let mut fields = entry.splitn(3, char::is_whitespace);
    let dim = fields.next()?.parse().ok()?;
    let tag = fields.next()?.parse().ok()?;
    let name = fields.next()?.trim();
    let name = name.strip_prefix('"')?.strip_suffix('"')?;
    Some((dim, tag, name.to_string()))
}

/// A short description of a `mshio` parse error: the sections it occurred in, the error, and
/// the line (counting newlines up to the failing byte; for binary data, also the byte offset).
fn describe_parse_error(bytes: &[u8], error: &MshParserError<&[u8]>) -> String {
    let backtrace = error.filtered_backtrace();
    let Some((innermost_input, innermost)) = backtrace.first() else {
        return "cannot parse the file as MSH 4.1".into();
    };
    if matches!(
        innermost,
        mshio::error::MshParserErrorKind::UnsupportedMshVersion
    ) {
        return "only the MSH 4.1 format is supported; convert the file with \
                `gmsh FILE -save -format msh41 -o NEW.msh`"
            .into();
    }
    let contexts: Vec<String> = backtrace[1..]
        .iter()
        .rev()
        .map(|(_, kind)| kind.to_string())
        .collect();
    let offset = (innermost_input.as_ptr() as usize).saturating_sub(bytes.as_ptr() as usize);
    let offset = offset.min(bytes.len());
    let line = bytes[..offset].iter().filter(|&&b| b == b'\n').count() + 1;
    format!(
        "cannot parse the file as MSH 4.1 at line {line} (byte {offset}), in {}: {innermost}",
        if contexts.is_empty() {
            "the header".to_string()
        } else {
            contexts.join(" > ")
        }
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One quadrangle and one triangle; `elements` is spliced into the $Elements section.
    fn small_msh(elements: &str) -> String {
        format!(
            "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n\
             $Nodes\n1 5 1 5\n2 1 0 5\n1\n2\n3\n4\n5\n\
             0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 0.5 0\n$EndNodes\n\
             $Elements\n{elements}$EndElements\n"
        )
    }

    #[test]
    fn clockwise_elements_are_reversed_and_unused_nodes_dropped() {
        // Quadrangle given clockwise, triangle counter-clockwise; node 5 is shared.
        let text = small_msh("2 2 1 2\n2 1 3 1\n1 1 4 3 2\n2 1 2 1\n2 2 5 3\n");
        let mesh = read_gmsh_bytes(text.as_bytes(), "small.msh").unwrap();
        assert_eq!(mesh.n_polygons(), 2);
        assert_eq!(mesh.n_vertices(), 5);
        assert!((0..2).all(|p| mesh.area(p) > 0.0));
        let total: f64 = (0..2).map(|p| mesh.area(p)).sum();
        assert!((total - 1.5).abs() < 1e-15, "{total}");
    }

    #[test]
    fn tetrahedra_are_rejected_with_type_and_entity() {
        let text = small_msh("1 1 1 1\n3 9 4 1\n1 1 2 3 4\n");
        let err = read_gmsh_bytes(text.as_bytes(), "tet.msh").unwrap_err();
        assert_eq!(
            err.to_string(),
            "tet.msh: element type 4 (Tet4) in volume entity 9: 3D elements are not supported; \
             the mesh must be 2D"
        );
    }

    #[test]
    fn a_file_without_2d_elements_is_an_error() {
        let text = small_msh("1 1 1 1\n1 3 1 1\n1 1 2\n");
        let err = read_gmsh_bytes(text.as_bytes(), "lines.msh").unwrap_err();
        assert!(err
            .to_string()
            .starts_with("lines.msh: the file contains no 2D elements"));
    }

    #[test]
    fn parse_errors_give_the_line() {
        let text = small_msh("1 1 1 1\n2 1 2 1\n1 1 2 x\n");
        let err = read_gmsh_bytes(text.as_bytes(), "bad.msh").unwrap_err();
        let message = err.to_string();
        assert!(
            message.starts_with("bad.msh: cannot parse the file as MSH 4.1 at line 21"),
            "{message}"
        );
        assert!(message.contains("element section"), "{message}");
    }

    #[test]
    fn old_format_versions_are_named() {
        let text = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n";
        let err = read_gmsh_bytes(text.as_bytes(), "old.msh").unwrap_err();
        assert!(
            err.to_string()
                .contains("only the MSH 4.1 format is supported"),
            "{err}"
        );
    }

    #[test]
    fn physical_names_may_contain_spaces() {
        assert_eq!(
            parse_physical_name("1 7 \"contact zone\""),
            Some((1, 7, "contact zone".to_string()))
        );
        assert_eq!(parse_physical_name("1 7 contact"), None);
    }
}
