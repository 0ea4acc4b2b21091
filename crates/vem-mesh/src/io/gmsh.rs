//! Gmsh `.msh` input (MSH 4.1 and 2.2, ASCII and binary): from a file to a [`Mesh`].
//!
//! What becomes what:
//! - every first-order triangle (element type 2) and quadrangle (type 3) becomes a polygon,
//!   oriented counter-clockwise; the polygons are numbered along a space-filling curve (the
//!   Morton order of their centroids), not in file order, so that cells close in the plane are
//!   close in memory whatever order the mesher wrote them in (docs/benchmarks.md: the
//!   assembly of a Hertz scene of 10^6 unknowns 1.6x faster than in Gmsh's order);
//! - nodes are found by their tags (any order, gaps, several blocks) and renumbered compactly
//!   in order of first use by a polygon along that curve; nodes that no 2D element uses
//!   (geometry points, probes) are dropped;
//! - errors name elements and nodes by their tags; an invalid mesh's error names its
//!   polygons and vertices in this numbering, each with its element or node tag;
//! - each physical curve group (dimension 1) becomes a boundary part made of the line elements
//!   (2-node lines, type 1) of its curves, each of which must be a boundary edge of the 2D
//!   mesh; the group must have a name in `$PhysicalNames`. Parts come in increasing order of
//!   their physical tag. A named curve group without elements is an empty part;
//! - point elements (type 15) are ignored; any other element type is an error.
//!
//! Once a `.geo` file defines any physical group, Gmsh saves only the elements of physical
//! groups: a mesh with named boundary curves then also needs a physical surface (any name),
//! or its triangles are not in the file.
//!
//! The format itself is read by [`read_msh_bytes`](super::read_msh_bytes).

use std::collections::BTreeMap;
use std::fs;
use std::path::Path;

use super::msh::{element_type_name, read_msh_bytes, MshFile};
use crate::{morton_key, Mesh, MeshError, PartSpec, Point};

/// Gmsh's type number of a 2-node line.
const LINE: i32 = 1;
/// Gmsh's type number of a 3-node triangle.
const TRIANGLE: i32 = 2;
/// Gmsh's type number of a 4-node quadrangle.
const QUADRANGLE: i32 = 3;
/// Gmsh's type number of a 1-node point.
const POINT: i32 = 15;

/// Reads a 2D mesh from a Gmsh `.msh` file in format 4.1 or 2.2 (ASCII or binary).
///
/// Triangles and quadrangles become counter-clockwise polygons, named physical curve groups
/// become boundary parts (see the module documentation). Errors are [`MeshError::Read`] naming
/// the file and what is wrong with it: a format error (with the line, or the byte offset in
/// binary data, and the section), an element
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

/// Reads a 2D mesh from the contents of a Gmsh `.msh` file held in memory, exactly as
/// [`read_gmsh`] does; `name` is the file name used in error messages.
pub fn read_gmsh_bytes(bytes: &[u8], name: impl AsRef<Path>) -> Result<Mesh, MeshError> {
    let parsed = read_msh_bytes(bytes).map_err(|e| MeshError::Read {
        path: name.as_ref().to_path_buf(),
        reason: e.to_string(),
    })?;
    mesh_from_msh(&parsed, name)
}

/// The 2D mesh of an already parsed Gmsh file, exactly as [`read_gmsh_bytes`] makes it from
/// the file's bytes (for a caller that parsed the file to look at it first, so that it is not
/// parsed twice); `name` is the file name used in error messages.
pub fn mesh_from_msh(msh: &MshFile, name: impl AsRef<Path>) -> Result<Mesh, MeshError> {
    convert(msh).map_err(|reason| MeshError::Read {
        path: name.as_ref().to_path_buf(),
        reason,
    })
}

/// Node tags to positions in the `$Nodes` section: a table indexed by tag when the tags are
/// dense (as Gmsh writes them), else the tags sorted for binary search.
pub(super) enum TagIndex {
    Dense(Vec<u32>),
    Sorted(Vec<(u64, u32)>),
}

impl TagIndex {
    /// The index of `nodes` (whose tags are distinct: the parser checks).
    pub(super) fn new(nodes: &[super::MshNode]) -> Result<Self, String> {
        if u32::try_from(nodes.len()).is_err() {
            return Err(format!(
                "{} nodes are more than this reader takes",
                nodes.len()
            ));
        }
        let largest = nodes.iter().map(|n| n.tag).max().unwrap_or(0);
        if largest <= 4 * nodes.len() as u64 + 1024 {
            let mut table = vec![u32::MAX; largest as usize + 1];
            for (i, node) in nodes.iter().enumerate() {
                table[node.tag as usize] = i as u32;
            }
            Ok(TagIndex::Dense(table))
        } else {
            let mut sorted: Vec<(u64, u32)> = nodes
                .iter()
                .enumerate()
                .map(|(i, n)| (n.tag, i as u32))
                .collect();
            sorted.sort_unstable();
            Ok(TagIndex::Sorted(sorted))
        }
    }

    /// The position of the node with tag `tag`.
    pub(super) fn get(&self, tag: u64) -> Option<usize> {
        match self {
            TagIndex::Dense(table) => match table.get(usize::try_from(tag).ok()?) {
                Some(&i) if i != u32::MAX => Some(i as usize),
                _ => None,
            },
            TagIndex::Sorted(sorted) => sorted
                .binary_search_by_key(&tag, |&(t, _)| t)
                .ok()
                .map(|k| sorted[k].1 as usize),
        }
    }
}

/// Turns a parsed MSH file into a mesh; errors are the reason text of [`MeshError::Read`].
fn convert(msh: &MshFile) -> Result<Mesh, String> {
    let nodes = TagIndex::new(&msh.nodes)?;

    // 2D elements become polygons, 2-node lines are kept per curve. Surface elements are looked
    // at first, so that a second-order mesh is reported by its triangles rather than by its
    // boundary lines.
    let mut faces: Vec<(u64, &[u64])> = Vec::new();
    let mut lines_of_curve: BTreeMap<i32, Vec<(u64, [u64; 2])>> = BTreeMap::new();
    let surfaces_first = msh
        .elements
        .iter()
        .filter(|e| e.entity_dim == 2)
        .chain(msh.elements.iter().filter(|e| e.entity_dim != 2));
    for element in surfaces_first {
        match (element.entity_dim, element.element_type) {
            (0, POINT) => {}
            (1, LINE) => lines_of_curve
                .entry(element.entity_tag)
                .or_default()
                .push((element.tag, [element.nodes[0], element.nodes[1]])),
            (2, TRIANGLE | QUADRANGLE) => faces.push((element.tag, &element.nodes)),
            (dim, element_type) => {
                return Err(unsupported_element(element_type, dim, element.entity_tag))
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

    // The nodes of every face as positions in the $Nodes section, counter-clockwise, and the
    // face's centroid, in file order (a missing node and a node off the plane are reported as
    // the file's first). The coordinates are read here only: the passes below go through the
    // faces in another order, and the nodes in theirs.
    let mut positions: Vec<usize> = Vec::with_capacity(faces.iter().map(|f| f.1.len()).sum());
    let mut face_start = Vec::with_capacity(faces.len() + 1);
    face_start.push(0);
    let mut centroids: Vec<Point> = Vec::with_capacity(faces.len());
    let mut plane_z: Option<(u64, f64)> = None;
    let mut corners: Vec<Point> = Vec::with_capacity(4);
    for &(element_tag, element_nodes) in &faces {
        let mut sum = Point::origin();
        corners.clear();
        for &node in element_nodes {
            let position = nodes.get(node).ok_or_else(|| {
                format!(
                    "element {element_tag} refers to node {node}, which is not in the $Nodes \
                     section"
                )
            })?;
            let [x, y, z] = msh.nodes[position].xyz;
            match plane_z {
                None => plane_z = Some((node, z)),
                Some((first, z0)) if (z - z0).abs() > 1e-9 * (1.0 + z0.abs()) => {
                    return Err(format!(
                        "node {node} has z = {z} but node {first} has z = {z0}: a 2D mesh \
                         must lie in a plane z = constant"
                    ));
                }
                Some(_) => {}
            }
            sum.x += x;
            sum.y += y;
            corners.push(Point::new(x, y));
            positions.push(position);
        }
        if crate::geometry::signed_area(&corners) < 0.0 {
            let start = face_start[face_start.len() - 1];
            positions[start..].reverse();
        }
        face_start.push(positions.len());
        centroids.push(sum / element_nodes.len() as f64);
    }
    // The faces along a space-filling curve (Morton order of their centroids), so that cells
    // near each other in the plane are near each other in the mesh's numbering, whatever
    // the file's order: every later pass over cells and vertices (edges, validation,
    // assembly) then reads memory in order rather than at random.
    let order = morton_order(&centroids);
    drop(centroids);

    // Compact renumbering in order of first use along the curve (`compact[node position]`,
    // `usize::MAX` unused), then the coordinates and tags of the vertices in the nodes' order.
    let mut compact = vec![usize::MAX; msh.nodes.len()];
    let mut used = 0;
    let mut offsets = Vec::with_capacity(faces.len() + 1);
    offsets.push(0);
    let mut indices: Vec<usize> = Vec::with_capacity(positions.len());
    for &f in &order {
        for &position in &positions[face_start[f]..face_start[f + 1]] {
            if compact[position] == usize::MAX {
                compact[position] = used;
                used += 1;
            }
            indices.push(compact[position]);
        }
        offsets.push(indices.len());
    }
    drop(positions);
    let mut vertices = vec![Point::origin(); used];
    let mut node_tags = vec![0; used];
    for (node, &v) in msh.nodes.iter().zip(&compact) {
        if v != usize::MAX {
            vertices[v] = Point::new(node.xyz[0], node.xyz[1]);
            node_tags[v] = node.tag;
        }
    }

    let parts = boundary_parts(msh, &lines_of_curve, &nodes, &compact, &offsets, &indices)?;
    Mesh::from_compact(vertices, offsets, indices, parts).map_err(|e| {
        let element_tags: Vec<u64> = order.iter().map(|&f| faces[f].0).collect();
        format!(
            "the mesh it describes is invalid: {e}{} (polygons are its triangles and \
             quadrangles, vertices its nodes, numbered from 0 along a space-filling curve)",
            locate(&e, &element_tags, &node_tags)
        )
    })
}

/// The polygons and vertices a validation error names, as element and node tags: `" (polygon
/// 3 is element 17; ...)"`, or nothing when it names none.
fn locate(error: &MeshError, element_tags: &[u64], node_tags: &[u64]) -> String {
    let polygon = |p: &usize| {
        element_tags
            .get(*p)
            .map(|t| format!("polygon {p} is element {t}"))
    };
    let vertex = |v: &usize| node_tags.get(*v).map(|t| format!("vertex {v} is node {t}"));
    let notes: Vec<Option<String>> = match error {
        MeshError::NonFiniteVertex { vertex: v, .. } => vec![vertex(v)],
        MeshError::TooFewVertices { polygon: p, .. }
        | MeshError::VertexOutOfRange { polygon: p, .. }
        | MeshError::Clockwise { polygon: p, .. }
        | MeshError::DegenerateArea { polygon: p, .. }
        | MeshError::SelfIntersecting { polygon: p, .. } => vec![polygon(p)],
        MeshError::RepeatedVertex {
            polygon: p,
            vertex: v,
        } => vec![polygon(p), vertex(v)],
        MeshError::DuplicateVertices { a, b, .. } | MeshError::UnknownEdge { a, b, .. } => {
            vec![vertex(a), vertex(b)]
        }
        MeshError::OverusedEdge { a, b, polygons, .. } => [vertex(a), vertex(b)]
            .into_iter()
            .chain(polygons.iter().map(polygon))
            .collect(),
        MeshError::NonConforming {
            polygon_a,
            a0,
            a1,
            polygon_b,
            b0,
            b1,
        } => vec![
            polygon(polygon_a),
            polygon(polygon_b),
            vertex(a0),
            vertex(a1),
            vertex(b0),
            vertex(b1),
        ],
        MeshError::Overlapping { a, b } => vec![polygon(a), polygon(b)],
        MeshError::InteriorEdgeInPart {
            a, b, left, right, ..
        } => vec![vertex(a), vertex(b), polygon(left), polygon(right)],
        _ => Vec::new(),
    };
    let notes: Vec<String> = notes.into_iter().flatten().collect();
    if notes.is_empty() {
        String::new()
    } else {
        format!(" ({})", notes.join("; "))
    }
}

/// The indices of `points` sorted along the Morton curve of their bounding box
/// ([`morton_key`]; ties in index order).
fn morton_order(points: &[Point]) -> Vec<usize> {
    let finite = || points.iter().filter(|p| p.x.is_finite() && p.y.is_finite());
    let Some(&first) = finite().next() else {
        return (0..points.len()).collect();
    };
    let (mut min, mut max) = (first, first);
    for p in finite() {
        min = min.inf(p);
        max = max.sup(p);
    }
    let extent = (max - min).map(|e| if e > 0.0 { e } else { 1.0 });
    let mut keyed: Vec<(u64, usize)> = points
        .iter()
        .enumerate()
        .map(|(i, p)| (morton_key(p, &min, &extent), i))
        .collect();
    keyed.sort_unstable();
    keyed.into_iter().map(|(_, i)| i).collect()
}

/// The boundary parts: one per physical curve group, in increasing order of physical tag.
fn boundary_parts(
    msh: &MshFile,
    lines_of_curve: &BTreeMap<i32, Vec<(u64, [u64; 2])>>,
    nodes: &TagIndex,
    compact: &[usize],
    offsets: &[usize],
    indices: &[usize],
) -> Result<Vec<PartSpec>, String> {
    // Physical tag -> curves carrying it.
    let mut curves_of_group: BTreeMap<i32, Vec<i32>> = msh
        .physical_groups()
        .into_iter()
        .filter(|&((dim, _), _)| dim == 1)
        .map(|((_, tag), curves)| (tag, curves))
        .collect();
    // Named dimension-1 groups with no curve: empty parts (the user asked for the name).
    for &(dim, tag) in msh.physical_names.keys() {
        if dim == 1 {
            curves_of_group.entry(tag).or_default();
        }
    }
    if curves_of_group.is_empty() {
        return Ok(Vec::new());
    }

    // The polygons around each vertex (compressed), to count the polygons using an edge.
    let n_vertices = compact.iter().filter(|&&v| v != usize::MAX).count();
    let mut start = vec![0usize; n_vertices + 1];
    for &v in indices {
        start[v + 1] += 1;
    }
    for v in 0..n_vertices {
        start[v + 1] += start[v];
    }
    let mut fill = start.clone();
    let mut around = vec![(0usize, 0usize); indices.len()];
    for p in 0..offsets.len() - 1 {
        for k in offsets[p]..offsets[p + 1] {
            around[fill[indices[k]]] = (p, k);
            fill[indices[k]] += 1;
        }
    }
    // How many polygons have the edge (a, b) as a side.
    let uses = |a: usize, b: usize| -> usize {
        around[start[a]..start[a + 1]]
            .iter()
            .filter(|&&(p, k)| {
                let (first, last) = (offsets[p], offsets[p + 1] - 1);
                let next = if k == last {
                    indices[first]
                } else {
                    indices[k + 1]
                };
                let previous = if k == first {
                    indices[last]
                } else {
                    indices[k - 1]
                };
                next == b || previous == b
            })
            .count()
    };
    let vertex_of = |tag: u64| {
        nodes
            .get(tag)
            .map(|i| compact[i])
            .filter(|&v| v != usize::MAX)
    };

    let mut parts = Vec::with_capacity(curves_of_group.len());
    for (tag, curves) in curves_of_group {
        let name = msh.physical_names.get(&(1, tag)).ok_or_else(|| {
            format!(
                "physical curve group {tag} (curve entities {curves:?}) has no name in \
                 $PhysicalNames; name it in the .geo file, e.g. Physical Curve(\"contact\", {tag})"
            )
        })?;
        // MSH 2 writes an element once per physical group it is in (with a new tag each time),
        // so the same edge can come several times: a part is a set of edges.
        let mut edges = Vec::new();
        let mut seen = std::collections::HashSet::new();
        for curve in curves {
            for &(element_tag, [a, b]) in lines_of_curve.get(&curve).into_iter().flatten() {
                let edge = match (vertex_of(a), vertex_of(b)) {
                    (Some(a), Some(b)) if a != b && uses(a, b) == 1 => Some([a, b]),
                    _ => None,
                };
                let [a, b] = edge.ok_or_else(|| {
                    format!(
                        "line element {element_tag} (nodes {a} and {b}) of curve entity {curve} \
                         in physical curve group '{name}' is not a boundary edge of the 2D mesh"
                    )
                })?;
                if seen.insert((a.min(b), a.max(b))) {
                    edges.push([a, b]);
                }
            }
        }
        parts.push(PartSpec::new(name.clone(), edges));
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
        _ => 0,
    };
    let what = if corners > 0 && nodes > corners {
        let order = match name {
            "Lin3" | "Tri6" | "Qua8" | "Qua9" => "second-order",
            _ => "higher-order",
        };
        format!(
            "{order} elements ({nodes} nodes) are not supported; mesh with element order 1 \
             (gmsh -order 1)"
        )
    } else if dim == 3 {
        "3D elements are not supported here; the mesh must be 2D (read a 3D mesh with \
         read_gmsh_polyhedral)"
            .to_string()
    } else {
        "only points (15), 2-node lines (1), 3-node triangles (2) and 4-node quadrangles (3) \
         are supported"
            .to_string()
    };
    format!("element type {element_type} ({name}) in {entity} entity {entity_tag}: {what}")
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

    /// A structured mesh of `n x n` unit squares, each cut into two triangles, as MSH 4.1
    /// text with its elements in the order `order` gives (of the 2 n^2 triangles) and tags
    /// `100 + k` for the k-th triangle.
    fn triangles_msh(n: usize, order: &[usize]) -> String {
        let node = |i: usize, j: usize| 1 + i + (n + 1) * j;
        let mut nodes = String::new();
        for j in 0..=n {
            for i in 0..=n {
                nodes += &format!("{}\n", node(i, j));
            }
        }
        for j in 0..=n {
            for i in 0..=n {
                nodes += &format!("{i} {j} 0\n");
            }
        }
        let mut triangles = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let (a, b, c, d) = (
                    node(i, j),
                    node(i + 1, j),
                    node(i + 1, j + 1),
                    node(i, j + 1),
                );
                triangles.push([a, b, c]);
                triangles.push([a, c, d]);
            }
        }
        let m = (n + 1) * (n + 1);
        let mut elements = format!("1 {0} 100 {1}\n2 1 2 {0}\n", order.len(), 99 + order.len());
        for &k in order {
            let [a, b, c] = triangles[k];
            elements += &format!("{} {a} {b} {c}\n", 100 + k);
        }
        format!(
            "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 {m} 1 {m}\n2 1 0 {m}\n{nodes}\
             $EndNodes\n$Elements\n{elements}$EndElements\n"
        )
    }

    #[test]
    fn the_numbering_follows_the_plane_not_the_file() {
        // The same triangles in file order and shuffled: the same mesh, vertex for vertex and
        // polygon for polygon, numbered along the Morton curve.
        let n = 32;
        let in_order: Vec<usize> = (0..2 * n * n).collect();
        let mut shuffled = in_order.clone();
        let mut state = 5u64;
        for i in (1..shuffled.len()).rev() {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1);
            shuffled.swap(i, (state >> 33) as usize % (i + 1));
        }
        let a = read_gmsh_bytes(triangles_msh(n, &in_order).as_bytes(), "a.msh").unwrap();
        let b = read_gmsh_bytes(triangles_msh(n, &shuffled).as_bytes(), "b.msh").unwrap();
        assert_eq!(a.vertices(), b.vertices());
        assert!((0..a.n_polygons()).all(|p| a.polygon(p) == b.polygon(p)));
        // Along the curve: the first polygons lie in the lower left quarter, the last in the
        // upper right one.
        let quarter = a.n_polygons() / 4;
        let half = n as f64 / 2.0;
        assert!((0..quarter).all(|p| {
            let c = a.centroid(p);
            c.x < half && c.y < half
        }));
        assert!((3 * quarter..a.n_polygons()).all(|p| {
            let c = a.centroid(p);
            c.x > half && c.y > half
        }));
        // Neighbours in the plane are near in the numbering: the vertices of most polygons
        // lie within a few indices of each other (a number that does not grow with n), where
        // the file's row-by-row numbering puts every triangle's n + 1 or n + 2 apart.
        let mut spreads: Vec<usize> = (0..a.n_polygons())
            .map(|p| {
                let loop_ = a.polygon(p);
                loop_.iter().max().unwrap() - loop_.iter().min().unwrap()
            })
            .collect();
        spreads.sort_unstable();
        let median = spreads[spreads.len() / 2];
        assert!(4 * median <= n + 1, "median spread {median}");
    }

    #[test]
    fn an_invalid_mesh_names_its_elements_and_nodes_by_tag() {
        // The first triangle twice, as element 100 and (retagged below) element 200: the two
        // use the same edges.
        let text = triangles_msh(2, &[0, 0, 1, 2, 3, 4, 5, 6, 7]);
        let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
        // Retag the duplicate: element tags must be unique.
        let at = lines.iter().rposition(|l| l.starts_with("100 ")).unwrap();
        lines[at] = lines[at].replacen("100 ", "200 ", 1);
        let text = (lines.join("\n") + "\n").replace("1 9 100 108\n", "1 9 100 200\n");
        let err = read_gmsh_bytes(text.as_bytes(), "twice.msh").unwrap_err();
        let message = err.to_string();
        assert!(
            message.contains("is element 100") && message.contains("is element 200"),
            "{message}"
        );
        assert!(message.contains("vertex 0 is node 1"), "{message}");
        assert!(
            message.contains("numbered from 0 along a space-filling curve"),
            "{message}"
        );
    }

    #[test]
    fn tetrahedra_are_rejected_with_type_and_entity() {
        let text = small_msh("1 1 1 1\n3 9 4 1\n1 1 2 3 4\n");
        let err = read_gmsh_bytes(text.as_bytes(), "tet.msh").unwrap_err();
        assert_eq!(
            err.to_string(),
            "tet.msh: element type 4 (Tet4) in volume entity 9: 3D elements are not supported \
             here; the mesh must be 2D (read a 3D mesh with read_gmsh_polyhedral)"
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
            message.starts_with(
                "bad.msh: line 21 (in $Elements): expected a node tag of an element, found 'x'"
            ),
            "{message}"
        );
    }

    #[test]
    fn old_format_versions_are_named() {
        let text = "$MeshFormat\n3.0 0 8\n$EndMeshFormat\n";
        let err = read_gmsh_bytes(text.as_bytes(), "old.msh").unwrap_err();
        assert!(
            err.to_string()
                .contains("MSH format version '3.0' is not supported (only 4.1 and 2.2)"),
            "{err}"
        );
    }
}
