//! Reading VTK files: XML unstructured grids (`.vtu`: ASCII, inline base64, appended raw or
//! base64, zlib-compressed, UInt32 or UInt64 headers, either byte order) and legacy files
//! (`.vtk`: ASCII or binary, POLYDATA or UNSTRUCTURED_GRID, formats 2 to 5.1), into an
//! [`UnstructuredGrid`]; and a polygonal [`Mesh`] with boundary parts from such a grid.
//!
//! Whatever meshio can read, it can write as `.vtu` or `.vtk`, so these readers bring any mesh
//! format within reach. Every defect is an error naming where it is: the line and column of
//! the XML, the array, the byte offset in appended data, the line of a legacy file, the cell
//! or the point; no input makes a reader panic or allocate more than the file can describe.

use std::collections::BTreeMap;
use std::path::Path;

use super::vtk::{CellType, Cells, UnstructuredGrid, Values, VtkArray};
use crate::{geometry, Mesh, MeshError, PartSpec, Point};

/// Reads a `.vtu` file (VTK XML unstructured grid).
///
/// Errors are [`MeshError::Read`] naming the file and, in the reason, where the defect is.
pub fn read_vtu(path: impl AsRef<Path>) -> Result<UnstructuredGrid, MeshError> {
    let path = path.as_ref();
    let bytes = read_file(path)?;
    read_vtu_bytes(&bytes, path)
}

/// Reads the contents of a `.vtu` file held in memory; `name` is the file name used in
/// error messages.
pub fn read_vtu_bytes(bytes: &[u8], name: impl AsRef<Path>) -> Result<UnstructuredGrid, MeshError> {
    xml_grid(bytes).map_err(|reason| MeshError::Read {
        path: name.as_ref().to_path_buf(),
        reason,
    })
}

/// Reads a legacy `.vtk` file (ASCII or binary; POLYDATA or UNSTRUCTURED_GRID).
pub fn read_legacy_vtk(path: impl AsRef<Path>) -> Result<UnstructuredGrid, MeshError> {
    let path = path.as_ref();
    let bytes = read_file(path)?;
    read_legacy_vtk_bytes(&bytes, path)
}

/// Reads the contents of a legacy `.vtk` file held in memory; `name` is the file name used
/// in error messages.
pub fn read_legacy_vtk_bytes(
    bytes: &[u8],
    name: impl AsRef<Path>,
) -> Result<UnstructuredGrid, MeshError> {
    Legacy::new(bytes).grid().map_err(|reason| MeshError::Read {
        path: name.as_ref().to_path_buf(),
        reason,
    })
}

/// Reads a polygonal mesh from a `.vtu` or legacy `.vtk` file (by its extension), as
/// [`mesh_from_grid`] builds it with default [`GridMeshOptions`].
///
/// ```
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/vtk/two_squares_parts.vtu");
/// let mesh = vem_mesh::io::read_vtk_mesh(path)?;
/// assert_eq!(mesh.n_polygons(), 2);
/// assert_eq!(mesh.part_names(), ["bottom", "top"]);
/// # Ok::<(), vem_mesh::MeshError>(())
/// ```
pub fn read_vtk_mesh(path: impl AsRef<Path>) -> Result<Mesh, MeshError> {
    let path = path.as_ref();
    let grid = match path.extension().and_then(|e| e.to_str()) {
        Some("vtk") => read_legacy_vtk(path)?,
        _ => read_vtu(path)?,
    };
    mesh_from_grid(&grid, &GridMeshOptions::default()).map_err(|reason| MeshError::Read {
        path: path.to_path_buf(),
        reason,
    })
}

fn read_file(path: &Path) -> Result<Vec<u8>, MeshError> {
    std::fs::read(path).map_err(|e| MeshError::Read {
        path: path.to_path_buf(),
        reason: format!("cannot read the file: {e}"),
    })
}

/// How [`mesh_from_grid`] finds the boundary parts of a grid.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct GridMeshOptions {
    /// The integer cell-data array that numbers the parts of the line cells. `None`: the first
    /// of `part`, `gmsh:physical` (as meshio writes Gmsh's physical groups) and `CellEntityIds`
    /// that the grid has.
    pub part_array: Option<String>,
    /// Names of part numbers; a number without a name is named by its digits ("3"). Names
    /// also come from the grid's field data as meshio writes Gmsh's physical names (arrays of
    /// two integers, tag and dimension 1); these take precedence.
    pub part_names: BTreeMap<i64, String>,
}

/// The names of the cell-data arrays tried, in order, for part numbers.
const PART_ARRAYS: [&str; 3] = ["part", "gmsh:physical", "CellEntityIds"];

/// Builds a polygonal mesh from a grid:
///
/// - its 2D cells (triangles, quadrangles, pixels, polygons) become polygons, in their order,
///   turned counter-clockwise when given clockwise;
/// - its vertices are the points that 2D cells use, in the order of the points (all of them,
///   numbered as in the file, when every point is used); all must lie in one plane z = c;
/// - its line and poly-line cells become boundary parts by the integer cell-data array of
///   [`GridMeshOptions::part_array`]: one part per number, in increasing order, named by
///   [`GridMeshOptions::part_names`] (or the grid's field data) or by the number. Without such
///   an array all lines form one part named `lines`. Every segment must be a boundary edge;
/// - vertex cells are ignored; 3D cells are an error.
///
/// The error names the cell (numbered from 0 in the file's order) or point at fault.
pub fn mesh_from_grid(grid: &UnstructuredGrid, options: &GridMeshOptions) -> Result<Mesh, String> {
    let cells = &grid.cells;
    let mut used = vec![false; grid.points.len()];
    let mut polygon_cells = Vec::new();
    for c in 0..cells.len() {
        let cell_type = cells.types[c];
        match cell_type.dimension() {
            2 => {
                for &p in cells.cell(c) {
                    *used.get_mut(p).ok_or_else(|| {
                        format!(
                            "cell {c} refers to point {p}, but there are {} points",
                            grid.points.len()
                        )
                    })? = true;
                }
                polygon_cells.push(c);
            }
            3 => {
                return Err(format!(
                    "cell {c} is a 3D cell ({cell_type:?}); a polygonal mesh has 2D cells only"
                ))
            }
            _ => {}
        }
    }
    if polygon_cells.is_empty() {
        return Err("the file has no 2D cells (triangles, quadrangles or polygons)".into());
    }
    // Points used by 2D cells, in file order.
    let mut vertex_of = vec![usize::MAX; grid.points.len()];
    let mut vertices = Vec::new();
    let mut plane: Option<(usize, f64)> = None;
    for (p, point) in grid.points.iter().enumerate() {
        if !used[p] {
            continue;
        }
        let [x, y, z] = *point;
        if !(x.is_finite() && y.is_finite() && z.is_finite()) {
            return Err(format!("point {p} has a non-finite coordinate {point:?}"));
        }
        match plane {
            None => plane = Some((p, z)),
            Some((first, z0)) if (z - z0).abs() > 1e-9 * (1.0 + z0.abs()) => {
                return Err(format!(
                    "point {p} has z = {z} but point {first} has z = {z0}: a 2D mesh must lie \
                     in a plane z = constant"
                ))
            }
            Some(_) => {}
        }
        vertex_of[p] = vertices.len();
        vertices.push(Point::new(x, y));
    }
    let mut offsets = vec![0];
    let mut indices = Vec::new();
    for &c in &polygon_cells {
        let start = indices.len();
        let points = cells.cell(c);
        if cells.types[c] == CellType::Pixel {
            // A pixel lists its corners in lexicographic order: 0 1 3 2 around it.
            if let [a, b, d, e] = points {
                indices.extend([vertex_of[*a], vertex_of[*b], vertex_of[*e], vertex_of[*d]]);
            }
        } else {
            indices.extend(points.iter().map(|&p| vertex_of[p]));
        }
        let loop_: Vec<Point> = indices[start..].iter().map(|&v| vertices[v]).collect();
        if geometry::signed_area(&loop_) < 0.0 {
            indices[start..].reverse();
        }
        offsets.push(indices.len());
    }
    let parts = grid_parts(grid, options, &vertex_of)?;
    let n_polygons = polygon_cells.len();
    Mesh::from_compact(vertices, offsets, indices, parts).map_err(|e| {
        format!(
            "the mesh it describes is invalid: {e} (polygons are its {n_polygons} 2D cells \
             numbered from 0 in file order; vertices are the points they use, numbered from 0 \
             in file order)"
        )
    })
}

/// The boundary parts of a grid: its line cells grouped by part number.
fn grid_parts(
    grid: &UnstructuredGrid,
    options: &GridMeshOptions,
    vertex_of: &[usize],
) -> Result<Vec<PartSpec>, String> {
    let cells = &grid.cells;
    let lines: Vec<usize> = (0..cells.len())
        .filter(|&c| cells.types[c].dimension() == 1)
        .collect();
    if lines.is_empty() {
        return Ok(Vec::new());
    }
    let array =
        match &options.part_array {
            Some(name) => Some(grid.cell_data.iter().find(|a| &a.name == name).ok_or_else(
                || format!("the file has no cell-data array '{name}' of part numbers"),
            )?),
            None => PART_ARRAYS
                .iter()
                .find_map(|name| grid.cell_data.iter().find(|a| a.name == *name)),
        };
    let mut by_number: BTreeMap<i64, Vec<[usize; 2]>> = BTreeMap::new();
    for &c in &lines {
        let number = match array {
            Some(array) => {
                if array.components != 1 {
                    return Err(format!(
                        "the part array '{}' has {} components; one integer per cell is needed",
                        array.name, array.components
                    ));
                }
                array.values.get_i64(c).ok_or_else(|| {
                    format!(
                        "cell {c}: the part array '{}' holds {:?}, not an integer",
                        array.name,
                        array.values.get_f64(c)
                    )
                })?
            }
            None => 0,
        };
        let points = cells.cell(c);
        let part = by_number.entry(number).or_default();
        for pair in points.windows(2) {
            let (a, b) = (vertex_of[pair[0]], vertex_of[pair[1]]);
            if a == usize::MAX || b == usize::MAX {
                return Err(format!(
                    "line cell {c} (points {} and {}) is not a boundary edge of the 2D cells: \
                     a point of it is on no 2D cell",
                    pair[0], pair[1]
                ));
            }
            part.push([a, b]);
        }
    }
    let field_names = field_part_names(grid);
    Ok(by_number
        .into_iter()
        .map(|(number, edges)| {
            let name = match array {
                None => "lines".to_string(),
                Some(_) => field_names
                    .get(&number)
                    .or_else(|| options.part_names.get(&number))
                    .cloned()
                    .unwrap_or_else(|| number.to_string()),
            };
            PartSpec::new(name, edges)
        })
        .collect())
}

/// Part names in the grid's field data as meshio writes Gmsh's physical names: an integer
/// array of two values (physical tag, dimension) named after the group; dimension 1 only.
fn field_part_names(grid: &UnstructuredGrid) -> BTreeMap<i64, String> {
    let mut names = BTreeMap::new();
    for array in &grid.field_data {
        if array.values.len() == 2 && array.values.get_i64(1) == Some(1) {
            if let Some(tag) = array.values.get_i64(0) {
                names.insert(tag, array.name.clone());
            }
        }
    }
    names
}

// ---------------------------------------------------------------------------------------------
// XML

/// The parsed description of one data array, before its values are decoded.
struct ArraySpec<'x> {
    name: String,
    type_name: String,
    components: usize,
    format: String,
    offset: Option<usize>,
    text: &'x str,
    /// Line and column of the `<DataArray>` element.
    at: (u32, u32),
}

/// The description of the `<DataArray>` element `node`.
fn array_spec<'a, 'input>(
    node: roxmltree::Node<'a, 'input>,
    document: &roxmltree::Document<'input>,
) -> Result<ArraySpec<'a>, String> {
    let p = document.text_pos_at(node.range().start);
    let here = format!("line {}, column {}", p.row, p.col);
    let name = node.attribute("Name").unwrap_or("").to_string();
    let components = match node.attribute("NumberOfComponents") {
        None => 1,
        Some(c) => c
            .trim()
            .parse()
            .ok()
            .filter(|&c: &usize| c > 0)
            .ok_or_else(|| format!("{here}: array '{name}' has NumberOfComponents '{c}'"))?,
    };
    let offset = match node.attribute("offset") {
        None => None,
        Some(o) => Some(
            o.trim()
                .parse()
                .map_err(|_| format!("{here}: array '{name}' has offset '{o}'"))?,
        ),
    };
    Ok(ArraySpec {
        type_name: node.attribute("type").unwrap_or("").to_string(),
        components,
        format: node.attribute("format").unwrap_or("ascii").to_string(),
        offset,
        text: node.text().unwrap_or(""),
        at: (p.row, p.col),
        name,
    })
}

/// The settings of the file that decoding needs.
struct Encoding<'b> {
    little_endian: bool,
    header_bytes: usize,
    compressed: bool,
    /// The appended data after its `_`, its offset in the file, and whether it is base64.
    appended: Option<(&'b [u8], usize, bool)>,
}

fn xml_grid(bytes: &[u8]) -> Result<UnstructuredGrid, String> {
    // Raw appended data is not XML: parse what comes before it, closed.
    let marker = b"<AppendedData";
    let appended_at = bytes.windows(marker.len()).position(|w| w == marker);
    let (xml_bytes, appended) = match appended_at {
        Some(at) => {
            let close = bytes[at..]
                .iter()
                .position(|&b| b == b'>')
                .map(|k| at + k)
                .ok_or_else(|| format!("byte {at}: the <AppendedData> tag is not closed"))?;
            let tag = String::from_utf8_lossy(&bytes[at..close]).into_owned();
            let base64 = if tag.contains("encoding=\"raw\"") || tag.contains("encoding='raw'") {
                false
            } else if tag.contains("base64") {
                true
            } else {
                return Err(format!(
                    "byte {at}: <AppendedData> has no encoding \"raw\" or \"base64\""
                ));
            };
            let underscore = bytes[close..]
                .iter()
                .position(|&b| b == b'_')
                .map(|k| close + k)
                .ok_or_else(|| format!("byte {close}: the appended data has no leading '_'"))?;
            let start = underscore + 1;
            (&bytes[..at], Some((&bytes[start..], start, base64)))
        }
        None => (bytes, None),
    };
    let mut text = std::str::from_utf8(xml_bytes)
        .map_err(|e| format!("byte {}: the XML is not UTF-8 text", e.valid_up_to()))?
        .to_string();
    if appended.is_some() {
        text.push_str("</VTKFile>");
    }
    let document = roxmltree::Document::parse(&text).map_err(|e| {
        let p = e.pos();
        format!(
            "line {}, column {}: the XML is malformed: {e}",
            p.row, p.col
        )
    })?;
    let root = document.root_element();
    let position = |node: roxmltree::Node| {
        let p = document.text_pos_at(node.range().start);
        (p.row, p.col)
    };
    let here = |node: roxmltree::Node| {
        let (row, col) = position(node);
        format!("line {row}, column {col}")
    };
    if !root.has_tag_name("VTKFile") {
        return Err(format!(
            "{}: the root element is <{}>, not <VTKFile>",
            here(root),
            root.tag_name().name()
        ));
    }
    match root.attribute("type") {
        Some("UnstructuredGrid") => {}
        other => {
            return Err(format!(
                "{}: VTKFile type {other:?} is not supported (only UnstructuredGrid, .vtu); \
                 convert the file with meshio (meshio convert IN OUT.vtu)",
                here(root)
            ))
        }
    }
    let little_endian = match root.attribute("byte_order") {
        None | Some("LittleEndian") => true,
        Some("BigEndian") => false,
        Some(other) => return Err(format!("{}: unknown byte_order '{other}'", here(root))),
    };
    let header_bytes = match root.attribute("header_type") {
        None | Some("UInt32") => 4,
        Some("UInt64") => 8,
        Some(other) => return Err(format!("{}: unknown header_type '{other}'", here(root))),
    };
    let compressed = match root.attribute("compressor") {
        None | Some("") => false,
        Some("vtkZLibDataCompressor") => true,
        Some(other) => {
            return Err(format!(
                "{}: the compressor {other} is not supported (only vtkZLibDataCompressor); \
                 save the file uncompressed or with zlib",
                here(root)
            ))
        }
    };
    let encoding = Encoding {
        little_endian,
        header_bytes,
        compressed,
        appended,
    };
    let grid_node = root
        .children()
        .find(|n| n.has_tag_name("UnstructuredGrid"))
        .ok_or_else(|| format!("{}: no <UnstructuredGrid> element", here(root)))?;
    let pieces: Vec<_> = grid_node
        .children()
        .filter(|n| n.has_tag_name("Piece"))
        .collect();
    let piece = match pieces.as_slice() {
        [piece] => *piece,
        [] => return Err(format!("{}: no <Piece> element", here(grid_node))),
        _ => {
            return Err(format!(
                "{}: {} pieces; only files of one piece are supported (merge them in ParaView \
                 or meshio)",
                here(grid_node),
                pieces.len()
            ))
        }
    };
    let count = |attribute: &str| -> Result<usize, String> {
        let text = piece
            .attribute(attribute)
            .ok_or_else(|| format!("{}: <Piece> has no {attribute}", here(piece)))?;
        text.trim()
            .parse()
            .map_err(|_| format!("{}: {attribute} is '{text}', not a count", here(piece)))
    };
    let (n_points, n_cells) = (count("NumberOfPoints")?, count("NumberOfCells")?);
    let spec = |node| array_spec(node, &document);
    let section = |tag: &str| piece.children().find(|n| n.has_tag_name(tag));
    let arrays_of = |tag: &str| -> Result<Vec<ArraySpec>, String> {
        match section(tag) {
            None => Ok(Vec::new()),
            Some(node) => node
                .children()
                .filter(|n| n.has_tag_name("DataArray"))
                .map(spec)
                .collect(),
        }
    };

    // Points.
    let points_specs = arrays_of("Points")?;
    let points = match points_specs.first() {
        None if n_points == 0 => Vec::new(),
        None => return Err(format!("{}: no <Points> array", here(piece))),
        Some(s) => {
            if s.components != 3 {
                return Err(format!(
                    "line {}: the points have {} components, not 3",
                    s.at.0, s.components
                ));
            }
            let values = decode(s, &encoding, Some(3 * n_points))?;
            let values = as_f64(&values);
            values.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect()
        }
    };

    // Cells.
    let cell_specs = arrays_of("Cells")?;
    let find = |name: &str| cell_specs.iter().find(|s| s.name == name);
    let integers = |name: &str, expected: Option<usize>| -> Result<Option<Vec<i64>>, String> {
        match find(name) {
            None => Ok(None),
            Some(s) => {
                let values = decode(s, &encoding, expected)?;
                as_i64(&values).map(Some).map_err(|k| {
                    format!(
                        "line {}: array '{name}' holds a non-integer at entry {k}",
                        s.at.0
                    )
                })
            }
        }
    };
    let missing = |name: &str| format!("{}: <Cells> has no '{name}' array", here(piece));
    let connectivity = integers("connectivity", None)?;
    let offsets = integers("offsets", Some(n_cells))?;
    let types = integers("types", Some(n_cells))?;
    let cells = if n_cells == 0 {
        Cells::new()
    } else {
        let connectivity = connectivity.ok_or_else(|| missing("connectivity"))?;
        let offsets = offsets.ok_or_else(|| missing("offsets"))?;
        let types = types.ok_or_else(|| missing("types"))?;
        let faces = integers("faces", None)?;
        let face_offsets = integers("faceoffsets", Some(n_cells))?;
        build_cells(
            &connectivity,
            &offsets,
            &types,
            faces.as_deref(),
            face_offsets.as_deref(),
            n_points,
        )?
    };

    // Data.
    let data = |tag: &str, entries: usize| -> Result<Vec<VtkArray>, String> {
        let mut arrays = Vec::new();
        for s in arrays_of(tag)? {
            if s.type_name == "String" {
                continue;
            }
            let values = decode(&s, &encoding, Some(entries * s.components))?;
            arrays.push(VtkArray::new(s.name, s.components, values));
        }
        Ok(arrays)
    };
    let point_data = data("PointData", n_points)?;
    let cell_data = data("CellData", n_cells)?;
    let mut field_data = Vec::new();
    if let Some(node) = grid_node.children().find(|n| n.has_tag_name("FieldData")) {
        for child in node.children().filter(|n| n.has_tag_name("DataArray")) {
            let s = spec(child)?;
            if s.type_name == "String" {
                continue;
            }
            let values = decode(&s, &encoding, None)?;
            field_data.push(VtkArray::new(s.name, s.components, values));
        }
    }
    let grid = UnstructuredGrid {
        points,
        cells,
        point_data,
        cell_data,
        field_data,
    };
    grid.check()?;
    Ok(grid)
}

/// Builds and checks the cell block from VTK's arrays.
fn build_cells(
    connectivity: &[i64],
    offsets: &[i64],
    types: &[i64],
    faces: Option<&[i64]>,
    face_offsets: Option<&[i64]>,
    n_points: usize,
) -> Result<Cells, String> {
    let n = types.len();
    if offsets.len() != n {
        return Err(format!("{} offsets for {n} cells", offsets.len()));
    }
    let index = |v: i64, what: &str| -> Result<usize, String> {
        usize::try_from(v).map_err(|_| format!("{what} is {v}"))
    };
    let mut cells = Cells::new();
    cells.connectivity = Vec::with_capacity(connectivity.len());
    for (k, &p) in connectivity.iter().enumerate() {
        let p = index(p, &format!("connectivity entry {k}"))?;
        if p >= n_points {
            return Err(format!(
                "connectivity entry {k} refers to point {p}, but there are {n_points} points"
            ));
        }
        cells.connectivity.push(p);
    }
    let mut previous = 0;
    cells.offsets = Vec::with_capacity(n + 1);
    cells.offsets.push(0);
    for (c, &end) in offsets.iter().enumerate() {
        let end = index(end, &format!("the offset of cell {c}"))?;
        if end < previous || end > connectivity.len() {
            return Err(format!(
                "the offset of cell {c} is {end}, outside {previous}..={}",
                connectivity.len()
            ));
        }
        cells.offsets.push(end);
        previous = end;
    }
    if previous != connectivity.len() {
        return Err(format!(
            "the cells use {previous} connectivity entries of {}",
            connectivity.len()
        ));
    }
    for (c, &t) in types.iter().enumerate() {
        let cell_type = u8::try_from(t)
            .ok()
            .and_then(CellType::from_vtk_id)
            .ok_or_else(|| {
                format!("cell {c} has VTK cell type {t}, which this reader does not know")
            })?;
        cells.types.push(cell_type);
    }
    if let (Some(faces), Some(face_offsets)) = (faces, face_offsets) {
        if face_offsets.len() != n {
            return Err(format!("{} face offsets for {n} cells", face_offsets.len()));
        }
        cells.faces = faces
            .iter()
            .enumerate()
            .map(|(k, &v)| index(v, &format!("faces entry {k}")))
            .collect::<Result<_, _>>()?;
        cells.face_offsets = face_offsets.to_vec();
    }
    Ok(cells)
}

/// The values of an array: floats as Float64, UInt8 as UInt8, other integers as Int32 when
/// every type value fits (Int8, Int16, UInt16, Int32) and Int64 otherwise.
fn decode(
    spec: &ArraySpec,
    encoding: &Encoding,
    expected: Option<usize>,
) -> Result<Values, String> {
    let where_ = format!("array '{}' (line {})", spec.name, spec.at.0);
    let (size, kind) = match spec.type_name.as_str() {
        "Float32" => (4, 'f'),
        "Float64" => (8, 'f'),
        "Int8" => (1, 'i'),
        "UInt8" => (1, 'u'),
        "Int16" => (2, 'i'),
        "UInt16" => (2, 'u'),
        "Int32" => (4, 'i'),
        "UInt32" => (4, 'u'),
        "Int64" => (8, 'i'),
        "UInt64" => (8, 'u'),
        other => return Err(format!("{where_}: unknown type '{other}'")),
    };
    let values = match spec.format.as_str() {
        "ascii" => ascii_values(spec.text, size, kind).map_err(|e| format!("{where_}: {e}"))?,
        "binary" => {
            let text: Vec<u8> = spec
                .text
                .bytes()
                .filter(|b| !b.is_ascii_whitespace())
                .collect();
            let raw = inline_binary(&text, encoding).map_err(|e| format!("{where_}: {e}"))?;
            binary_values(&raw, size, kind, encoding.little_endian)
                .map_err(|e| format!("{where_}: {e}"))?
        }
        "appended" => {
            let (data, start, base64) = encoding
                .appended
                .ok_or_else(|| format!("{where_}: format \"appended\" but no <AppendedData>"))?;
            let offset = spec
                .offset
                .ok_or_else(|| format!("{where_}: format \"appended\" without an offset"))?;
            if offset > data.len() {
                return Err(format!(
                    "{where_}: offset {offset} is beyond the {} bytes of appended data",
                    data.len()
                ));
            }
            let at = start + offset;
            let raw = if base64 {
                let text: Vec<u8> = data[offset..]
                    .iter()
                    .copied()
                    .take_while(|&b| b != b'<')
                    .filter(|b| !b.is_ascii_whitespace())
                    .collect();
                inline_binary(&text, encoding)
            } else {
                raw_block(&data[offset..], encoding)
            }
            .map_err(|e| format!("{where_}, appended data at byte {at}: {e}"))?;
            binary_values(&raw, size, kind, encoding.little_endian)
                .map_err(|e| format!("{where_}: {e}"))?
        }
        other => return Err(format!("{where_}: unknown format '{other}'")),
    };
    if let Some(expected) = expected {
        if values.len() != expected {
            return Err(format!(
                "{where_}: {} values, expected {expected}",
                values.len()
            ));
        }
    }
    Ok(values)
}

/// Numbers written as text.
fn ascii_values(text: &str, size: usize, kind: char) -> Result<Values, String> {
    let tokens = text.split_ascii_whitespace();
    let bad =
        |k: usize, t: &str| format!("value {k} is '{}', not a number of the type", shorten(t));
    if kind == 'f' {
        let mut v = Vec::new();
        for (k, t) in tokens.enumerate() {
            let x: f64 = t.parse().map_err(|_| bad(k, t))?;
            v.push(x);
        }
        return Ok(Values::Float64(v));
    }
    let (lo, hi) = integer_range(size, kind);
    let mut v: Vec<i64> = Vec::new();
    for (k, t) in tokens.enumerate() {
        match t.parse::<i64>() {
            Ok(x) if (lo..=hi).contains(&x) => v.push(x),
            // Out of the type's range (or a UInt64 beyond i64): not a value of the type.
            _ => return Err(bad(k, t)),
        }
    }
    Ok(integer_values(v, size, kind))
}

/// The range of an integer type of `size` bytes, signed (`kind` 'i') or not ('u'), within
/// i64.
fn integer_range(size: usize, kind: char) -> (i64, i64) {
    match (kind, size) {
        ('u', 8) => (0, i64::MAX),
        ('u', _) => (0, (1i64 << (8 * size)) - 1),
        (_, 8) => (i64::MIN, i64::MAX),
        _ => (-(1i64 << (8 * size - 1)), (1i64 << (8 * size - 1)) - 1),
    }
}

/// Integers as the type declares them: UInt8 as UInt8, the others that fit in Int32 (Int8,
/// Int16, UInt16, Int32) as Int32, the rest (UInt32, Int64, UInt64) as Int64.
fn integer_values(v: Vec<i64>, size: usize, kind: char) -> Values {
    match (kind, size) {
        ('u', 1) => Values::UInt8(v.into_iter().map(|x| x as u8).collect()),
        ('u', 2) | ('i', 1 | 2 | 4) => Values::Int32(v.into_iter().map(|x| x as i32).collect()),
        _ => Values::Int64(v),
    }
}

/// Numbers from raw bytes.
fn binary_values(raw: &[u8], size: usize, kind: char, little: bool) -> Result<Values, String> {
    if raw.len() % size != 0 {
        return Err(format!(
            "{} bytes of data, not a whole number of {size}-byte values",
            raw.len()
        ));
    }
    let word = |chunk: &[u8]| -> u64 {
        let mut bytes = [0u8; 8];
        if little {
            bytes[..size].copy_from_slice(chunk);
            u64::from_le_bytes(bytes)
        } else {
            bytes[8 - size..].copy_from_slice(chunk);
            u64::from_be_bytes(bytes)
        }
    };
    let chunks = raw.chunks_exact(size);
    Ok(match (kind, size) {
        ('f', 4) => Values::Float64(
            chunks
                .map(|c| f64::from(f32::from_bits(word(c) as u32)))
                .collect(),
        ),
        ('f', _) => Values::Float64(chunks.map(|c| f64::from_bits(word(c))).collect()),
        ('u', 8) => {
            let mut v = Vec::with_capacity(raw.len() / 8);
            for (k, c) in chunks.enumerate() {
                v.push(i64::try_from(word(c)).map_err(|_| {
                    format!(
                        "value {k} is {}, beyond the integers this reader keeps",
                        word(c)
                    )
                })?);
            }
            Values::Int64(v)
        }
        ('u', _) => integer_values(chunks.map(|c| word(c) as i64).collect(), size, kind),
        (_, _) => {
            // Sign-extend from `size` bytes.
            let shift = 64 - 8 * size as u32;
            integer_values(
                chunks
                    .map(|c| ((word(c) << shift) as i64) >> shift)
                    .collect(),
                size,
                kind,
            )
        }
    })
}

/// A raw appended block: header then data, or compressed blocks.
fn raw_block(data: &[u8], encoding: &Encoding) -> Result<Vec<u8>, String> {
    let h = encoding.header_bytes;
    let header_word = |bytes: &[u8], k: usize| -> Result<usize, String> {
        let chunk = bytes
            .get(k * h..(k + 1) * h)
            .ok_or_else(|| "the data ends inside its header".to_string())?;
        let mut word = [0u8; 8];
        let value = if encoding.little_endian {
            word[..h].copy_from_slice(chunk);
            u64::from_le_bytes(word)
        } else {
            word[8 - h..].copy_from_slice(chunk);
            u64::from_be_bytes(word)
        };
        usize::try_from(value).map_err(|_| format!("a header value {value} is too large"))
    };
    if !encoding.compressed {
        let n = header_word(data, 0)?;
        let body = data
            .get(h..)
            .and_then(|rest| rest.get(..n))
            .ok_or_else(|| format!("the header announces {n} bytes, more than the file holds"))?;
        return Ok(body.to_vec());
    }
    let n_blocks = header_word(data, 0)?;
    if n_blocks > data.len() / h {
        return Err(format!(
            "the header announces {n_blocks} blocks, more than the file holds"
        ));
    }
    let block_size = header_word(data, 1)?;
    let last = header_word(data, 2)?;
    let mut sizes = Vec::with_capacity(n_blocks);
    for k in 0..n_blocks {
        sizes.push(header_word(data, 3 + k)?);
    }
    let mut at = (3 + n_blocks) * h;
    let mut out = Vec::new();
    for (k, &size) in sizes.iter().enumerate() {
        let block = data
            .get(at..)
            .and_then(|rest| rest.get(..size))
            .ok_or_else(|| {
                format!("compressed block {k} ({size} bytes) runs past the end of the file")
            })?;
        let expected = if k + 1 == n_blocks && last != 0 {
            last
        } else {
            block_size
        };
        let inflated = miniz_oxide::inflate::decompress_to_vec_zlib_with_limit(block, expected)
            .map_err(|e| {
                format!(
                    "compressed block {k} is not valid zlib data ({:?})",
                    e.status
                )
            })?;
        if inflated.len() != expected {
            return Err(format!(
                "compressed block {k} holds {} bytes, the header announces {expected}",
                inflated.len()
            ));
        }
        out.extend_from_slice(&inflated);
        at += size;
    }
    Ok(out)
}

/// Base64 data (inline `format="binary"`, or appended base64): uncompressed, one stream of
/// header and data; compressed, the header encoded on its own, then the blocks.
fn inline_binary(text: &[u8], encoding: &Encoding) -> Result<Vec<u8>, String> {
    let h = encoding.header_bytes;
    if !encoding.compressed {
        // Enough characters to decode the header first, then the announced length.
        let first = base64_decode(text.get(..base64_len(h)).unwrap_or(text))?;
        if first.len() < h {
            return Err("the data ends inside its header".into());
        }
        let n = header_value(&first[..h], encoding)?;
        let total = n
            .checked_add(h)
            .filter(|&t| base64_len(t) <= text.len())
            .ok_or_else(|| format!("the header announces {n} bytes, more than the text holds"))?;
        let all = base64_decode(&text[..base64_len(total)])?;
        return Ok(all[h..total].to_vec());
    }
    let head = base64_decode(text.get(..base64_len(3 * h)).unwrap_or(text))?;
    if head.len() < 3 * h {
        return Err("the data ends inside its header".into());
    }
    let n_blocks = header_value(&head[..h], encoding)?;
    let header_len = n_blocks
        .checked_add(3)
        .and_then(|k| k.checked_mul(h))
        .filter(|&l| base64_len(l) <= text.len())
        .ok_or_else(|| {
            format!("the header announces {n_blocks} blocks, more than the text holds")
        })?;
    let header_chars = base64_len(header_len);
    let mut raw = base64_decode(&text[..header_chars])?;
    raw.truncate(header_len);
    raw.extend(base64_decode(&text[header_chars..])?);
    raw_block(&raw, encoding)
}

fn header_value(bytes: &[u8], encoding: &Encoding) -> Result<usize, String> {
    let mut word = [0u8; 8];
    let h = bytes.len();
    let value = if encoding.little_endian {
        word[..h].copy_from_slice(bytes);
        u64::from_le_bytes(word)
    } else {
        word[8 - h..].copy_from_slice(bytes);
        u64::from_be_bytes(word)
    };
    usize::try_from(value).map_err(|_| format!("a header value {value} is too large"))
}

/// Characters of base64 text for `bytes` bytes (with padding).
fn base64_len(bytes: usize) -> usize {
    bytes.div_ceil(3).saturating_mul(4)
}

/// Decodes base64 (standard alphabet, with or without padding; whitespace removed before).
fn base64_decode(text: &[u8]) -> Result<Vec<u8>, String> {
    let value = |c: u8| -> Option<u32> {
        Some(match c {
            b'A'..=b'Z' => c - b'A',
            b'a'..=b'z' => c - b'a' + 26,
            b'0'..=b'9' => c - b'0' + 52,
            b'+' => 62,
            b'/' => 63,
            _ => return None,
        } as u32)
    };
    let mut out = Vec::with_capacity(text.len() / 4 * 3);
    let mut buffer = 0u32;
    let mut bits = 0;
    for (k, &c) in text.iter().enumerate() {
        if c == b'=' {
            // Padding ends a quantum; decoding goes on after it (VTK concatenates streams).
            buffer = 0;
            bits = 0;
            continue;
        }
        let v = value(c).ok_or_else(|| {
            format!(
                "character {k} of the base64 data is {:?}, not base64",
                c as char
            )
        })?;
        buffer = (buffer << 6) | v;
        bits += 6;
        if bits >= 8 {
            bits -= 8;
            out.push((buffer >> bits) as u8);
            buffer &= (1 << bits) - 1;
        }
    }
    Ok(out)
}

fn as_f64(values: &Values) -> Vec<f64> {
    (0..values.len())
        .filter_map(|k| values.get_f64(k))
        .collect()
}

/// The values as integers; the error is the index of the first that is not one.
fn as_i64(values: &Values) -> Result<Vec<i64>, usize> {
    (0..values.len())
        .map(|k| values.get_i64(k).ok_or(k))
        .collect()
}

/// At most 40 characters of `text`, for error messages.
fn shorten(text: &str) -> String {
    let head: String = text.chars().take(40).collect();
    if head.len() < text.len() {
        format!("{head}...")
    } else {
        head
    }
}

// ---------------------------------------------------------------------------------------------
// Legacy VTK

/// A reading position in a legacy file.
struct Legacy<'a> {
    bytes: &'a [u8],
    pos: usize,
    binary: bool,
}

impl<'a> Legacy<'a> {
    fn new(bytes: &'a [u8]) -> Self {
        Legacy {
            bytes,
            pos: 0,
            binary: false,
        }
    }

    fn line_at(&self, at: usize) -> usize {
        self.bytes[..at.min(self.bytes.len())]
            .iter()
            .filter(|&&b| b == b'\n')
            .count()
            + 1
    }

    fn error(&self, at: usize, reason: impl std::fmt::Display) -> String {
        format!("line {}: {reason}", self.line_at(at))
    }

    /// The next line (without its end), and where it starts.
    fn line(&mut self) -> Option<(&'a str, usize)> {
        if self.pos >= self.bytes.len() {
            return None;
        }
        let start = self.pos;
        let end = self.bytes[start..]
            .iter()
            .position(|&b| b == b'\n')
            .map_or(self.bytes.len(), |k| start + k);
        self.pos = (end + 1).min(self.bytes.len());
        let line = &self.bytes[start..end];
        let line = line.strip_suffix(b"\r").unwrap_or(line);
        Some((std::str::from_utf8(line).unwrap_or("\u{fffd}"), start))
    }

    /// The next line that is not blank.
    fn content_line(&mut self) -> Option<(&'a str, usize)> {
        loop {
            let (line, at) = self.line()?;
            if !line.trim().is_empty() {
                return Some((line, at));
            }
        }
    }

    fn skip_whitespace(&mut self) {
        while self.pos < self.bytes.len() && self.bytes[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
    }

    /// `count` numbers of the named legacy type: text tokens, or big-endian binary.
    fn numbers(&mut self, count: usize, type_name: &str, what: &str) -> Result<Values, String> {
        let (size, kind) = match type_name.to_ascii_lowercase().as_str() {
            "float" => (4, 'f'),
            "double" => (8, 'f'),
            "char" => (1, 'i'),
            "unsigned_char" => (1, 'u'),
            "short" => (2, 'i'),
            "unsigned_short" => (2, 'u'),
            "int" | "vtktypeint32" => (4, 'i'),
            "unsigned_int" | "vtktypeuint32" => (4, 'u'),
            "long" | "vtkidtype" | "vtktypeint64" => (8, 'i'),
            "unsigned_long" | "vtktypeuint64" => (8, 'u'),
            other => {
                return Err(self.error(self.pos, format!("{what}: unknown data type '{other}'")))
            }
        };
        if self.binary {
            let bytes = count
                .checked_mul(size)
                .filter(|&b| b <= self.bytes.len() - self.pos)
                .ok_or_else(|| {
                    self.error(
                        self.pos,
                        format!("{what}: {count} binary values do not fit in the rest of the file"),
                    )
                })?;
            let raw = &self.bytes[self.pos..self.pos + bytes];
            self.pos += bytes;
            return binary_values(raw, size, kind, false).map_err(|e| self.error(self.pos, e));
        }
        // Every text number takes at least two bytes (a digit and a separator).
        if count > (self.bytes.len() - self.pos) / 2 + 1 {
            return Err(self.error(
                self.pos,
                format!("{what}: {count} values do not fit in the rest of the file"),
            ));
        }
        let mut floats = Vec::new();
        let mut ints = Vec::new();
        for k in 0..count {
            self.skip_whitespace();
            let start = self.pos;
            while self.pos < self.bytes.len() && !self.bytes[self.pos].is_ascii_whitespace() {
                self.pos += 1;
            }
            let token = std::str::from_utf8(&self.bytes[start..self.pos]).unwrap_or("\u{fffd}");
            if token.is_empty() {
                return Err(self.error(
                    start,
                    format!("{what}: the file ends after {k} of {count} values"),
                ));
            }
            let bad = || {
                self.error(
                    start,
                    format!(
                        "{what}: value {k} is '{}', not a number of type {type_name}",
                        shorten(token)
                    ),
                )
            };
            if kind == 'f' {
                floats.push(token.parse::<f64>().map_err(|_| bad())?);
            } else {
                let (lo, hi) = integer_range(size, kind);
                match token.parse::<i64>() {
                    Ok(x) if (lo..=hi).contains(&x) => ints.push(x),
                    _ => return Err(bad()),
                }
            }
        }
        Ok(if kind == 'f' {
            Values::Float64(floats)
        } else {
            integer_values(ints, size, kind)
        })
    }

    /// A count in a header line.
    fn count(&self, token: Option<&str>, at: usize, what: &str) -> Result<usize, String> {
        let token = token.ok_or_else(|| self.error(at, format!("{what} is missing")))?;
        token
            .parse()
            .map_err(|_| self.error(at, format!("{what} is '{}', not a count", shorten(token))))
    }

    fn grid(mut self) -> Result<UnstructuredGrid, String> {
        let (first, _) = self.line().ok_or("the file is empty")?;
        if !first.trim_start().starts_with("# vtk DataFile Version") {
            return Err(format!(
                "line 1: expected '# vtk DataFile Version ...', found '{}'",
                shorten(first.trim())
            ));
        }
        let version: f64 = first
            .trim()
            .rsplit(' ')
            .next()
            .and_then(|v| v.parse().ok())
            .unwrap_or(3.0);
        self.line()
            .ok_or("line 2: the file ends before its title")?;
        let (format, at) = self
            .content_line()
            .ok_or("the file ends before ASCII or BINARY")?;
        self.binary = match format.trim().to_ascii_uppercase().as_str() {
            "ASCII" => false,
            "BINARY" => true,
            other => {
                return Err(self.error(
                    at,
                    format!("expected ASCII or BINARY, found '{}'", shorten(other)),
                ))
            }
        };
        let (dataset, at) = self.content_line().ok_or("the file ends before DATASET")?;
        let mut words = dataset.split_whitespace();
        let kind = match (words.next(), words.next()) {
            (Some(d), Some(kind)) if d.eq_ignore_ascii_case("DATASET") => kind.to_ascii_uppercase(),
            _ => {
                return Err(self.error(
                    at,
                    format!("expected DATASET, found '{}'", shorten(dataset)),
                ))
            }
        };
        if kind != "POLYDATA" && kind != "UNSTRUCTURED_GRID" {
            return Err(self.error(
                at,
                format!(
                    "DATASET {kind} is not supported (only POLYDATA and UNSTRUCTURED_GRID); \
                     convert the file with meshio"
                ),
            ));
        }
        let mut points: Vec<[f64; 3]> = Vec::new();
        // POLYDATA cells come in the order VERTICES, LINES, POLYGONS whatever the file order.
        let mut poly_blocks: BTreeMap<u8, (CellType, Vec<Vec<usize>>)> = BTreeMap::new();
        let mut ug_cells: Option<Vec<Vec<usize>>> = None;
        let mut ug_types: Option<Vec<i64>> = None;
        let mut point_data = Vec::new();
        let mut cell_data = Vec::new();
        let mut field_data = Vec::new();
        // Which data group the attributes belong to: (is point data, entries).
        let mut group: Option<(bool, usize)> = None;
        while let Some((line, at)) = self.content_line() {
            let mut words = line.split_whitespace();
            let keyword = words.next().unwrap_or("").to_ascii_uppercase();
            match keyword.as_str() {
                "POINTS" => {
                    let n = self.count(words.next(), at, "the number of points")?;
                    let type_name = words.next().unwrap_or("float").to_string();
                    let values = self.numbers(3 * n, &type_name, "POINTS")?;
                    points = as_f64(&values)
                        .chunks_exact(3)
                        .map(|c| [c[0], c[1], c[2]])
                        .collect();
                }
                "VERTICES" | "LINES" | "POLYGONS" | "CELLS" => {
                    let n = self.count(words.next(), at, "the number of cells")?;
                    let size = self.count(words.next(), at, "the size of the cell list")?;
                    let cells = self.cell_list(n, size, version, at)?;
                    match keyword.as_str() {
                        "VERTICES" => {
                            poly_blocks.insert(0, (CellType::Vertex, cells));
                        }
                        "LINES" => {
                            poly_blocks.insert(1, (CellType::PolyLine, cells));
                        }
                        "POLYGONS" => {
                            poly_blocks.insert(2, (CellType::Polygon, cells));
                        }
                        _ => ug_cells = Some(cells),
                    }
                }
                "TRIANGLE_STRIPS" => {
                    return Err(self.error(
                        at,
                        "triangle strips are not supported; convert them to triangles",
                    ))
                }
                "CELL_TYPES" => {
                    let n = self.count(words.next(), at, "the number of cell types")?;
                    let values = self.numbers(n, "int", "CELL_TYPES")?;
                    ug_types =
                        Some(as_i64(&values).map_err(|k| {
                            self.error(at, format!("cell type {k} is not an integer"))
                        })?);
                }
                "POINT_DATA" | "CELL_DATA" => {
                    let n = self.count(words.next(), at, "the number of entries")?;
                    group = Some((keyword == "POINT_DATA", n));
                }
                "SCALARS"
                | "VECTORS"
                | "NORMALS"
                | "TENSORS"
                | "COLOR_SCALARS"
                | "TEXTURE_COORDINATES" => {
                    let (is_point, entries) = group.ok_or_else(|| {
                        self.error(at, format!("{keyword} before POINT_DATA or CELL_DATA"))
                    })?;
                    let name = words.next().unwrap_or("").to_string();
                    let (components, type_name) = match keyword.as_str() {
                        "SCALARS" => {
                            let type_name = words.next().unwrap_or("float").to_string();
                            let k = match words.next() {
                                Some(k) => self.count(Some(k), at, "the number of components")?,
                                None => 1,
                            };
                            // A lookup table line follows.
                            let here = self.pos;
                            match self.content_line() {
                                Some((l, _))
                                    if l.trim_start()
                                        .to_ascii_uppercase()
                                        .starts_with("LOOKUP_TABLE") => {}
                                _ => self.pos = here,
                            }
                            (k, type_name)
                        }
                        "VECTORS" | "NORMALS" => (3, words.next().unwrap_or("float").to_string()),
                        "TENSORS" => (9, words.next().unwrap_or("float").to_string()),
                        "COLOR_SCALARS" => {
                            let k = self.count(words.next(), at, "the number of components")?;
                            (
                                k,
                                if self.binary {
                                    "unsigned_char"
                                } else {
                                    "float"
                                }
                                .to_string(),
                            )
                        }
                        _ => {
                            let k = self.count(words.next(), at, "the number of components")?;
                            (k, words.next().unwrap_or("float").to_string())
                        }
                    };
                    let count = entries
                        .checked_mul(components)
                        .ok_or_else(|| self.error(at, "too many values"))?;
                    let values = self.numbers(count, &type_name, &keyword)?;
                    let array = VtkArray::new(name, components, values);
                    if is_point {
                        point_data.push(array);
                    } else {
                        cell_data.push(array);
                    }
                }
                "FIELD" => {
                    let n = self.count(words.nth(1), at, "the number of field arrays")?;
                    for _ in 0..n {
                        let (header, at) = self
                            .content_line()
                            .ok_or_else(|| self.error(self.pos, "the file ends inside FIELD"))?;
                        let mut w = header.split_whitespace();
                        let name = w.next().unwrap_or("").to_string();
                        let k = self.count(w.next(), at, "the number of components")?;
                        let tuples = self.count(w.next(), at, "the number of tuples")?;
                        let type_name = w.next().unwrap_or("float").to_string();
                        let count = k
                            .checked_mul(tuples)
                            .ok_or_else(|| self.error(at, "too many values"))?;
                        let values = self.numbers(count, &type_name, &name)?;
                        let array = VtkArray::new(name, k, values);
                        match group {
                            Some((true, _)) => point_data.push(array),
                            Some((false, _)) => cell_data.push(array),
                            None => field_data.push(array),
                        }
                    }
                }
                "METADATA" => {
                    // Information for VTK's own pipeline: up to the next blank line.
                    while let Some((l, _)) = self.line() {
                        if l.trim().is_empty() {
                            break;
                        }
                    }
                }
                "LOOKUP_TABLE" => {
                    let n = self.count(words.nth(1), at, "the size of the lookup table")?;
                    let count = n
                        .checked_mul(4)
                        .ok_or_else(|| self.error(at, "too many values"))?;
                    self.numbers(
                        count,
                        if self.binary {
                            "unsigned_char"
                        } else {
                            "float"
                        },
                        "LOOKUP_TABLE",
                    )?;
                }
                other => {
                    return Err(self.error(at, format!("unknown keyword '{}'", shorten(other))));
                }
            }
        }
        let mut cells = Cells::new();
        if kind == "POLYDATA" {
            for (_, (cell_type, list)) in poly_blocks {
                for points in list {
                    let cell_type = match (cell_type, points.len()) {
                        (CellType::PolyLine, 2) => CellType::Line,
                        (CellType::Vertex, k) if k > 1 => CellType::PolyLine,
                        (t, _) => t,
                    };
                    cells.push(cell_type, &points);
                }
            }
        } else {
            let list = ug_cells.unwrap_or_default();
            let types = ug_types.unwrap_or_default();
            if list.len() != types.len() {
                return Err(format!(
                    "{} cells but {} cell types",
                    list.len(),
                    types.len()
                ));
            }
            for (c, (points, &t)) in list.iter().zip(&types).enumerate() {
                let cell_type = u8::try_from(t)
                    .ok()
                    .and_then(CellType::from_vtk_id)
                    .ok_or_else(|| {
                        format!("cell {c} has VTK cell type {t}, which this reader does not know")
                    })?;
                if cell_type == CellType::Polyhedron {
                    return Err(format!(
                        "cell {c} is a polyhedron; read polyhedra from .vtu files"
                    ));
                }
                cells.push(cell_type, points);
            }
        }
        let grid = UnstructuredGrid {
            points,
            cells,
            point_data,
            cell_data,
            field_data,
        };
        grid.check()?;
        Ok(grid)
    }

    /// A cell list: `n` cells of `size` numbers in all; in formats before 5, each cell as its
    /// number of points then the points; from 5 on, OFFSETS then CONNECTIVITY arrays.
    fn cell_list(
        &mut self,
        n: usize,
        size: usize,
        version: f64,
        at: usize,
    ) -> Result<Vec<Vec<usize>>, String> {
        let index = |v: i64, what: &str| -> Result<usize, String> {
            usize::try_from(v).map_err(|_| format!("{what} is {v}"))
        };
        if version >= 5.0 {
            // CELLS n_offsets n_connectivity, then OFFSETS type / CONNECTIVITY type.
            let (line, at) = self
                .content_line()
                .ok_or_else(|| self.error(at, "the file ends before OFFSETS"))?;
            let mut w = line.split_whitespace();
            if !w.next().is_some_and(|k| k.eq_ignore_ascii_case("OFFSETS")) {
                return Err(self.error(at, format!("expected OFFSETS, found '{}'", shorten(line))));
            }
            let offsets = self.numbers(n, w.next().unwrap_or("vtktypeint64"), "OFFSETS")?;
            let (line, at2) = self
                .content_line()
                .ok_or_else(|| self.error(at, "the file ends before CONNECTIVITY"))?;
            let mut w = line.split_whitespace();
            if !w
                .next()
                .is_some_and(|k| k.eq_ignore_ascii_case("CONNECTIVITY"))
            {
                return Err(self.error(
                    at2,
                    format!("expected CONNECTIVITY, found '{}'", shorten(line)),
                ));
            }
            let connectivity =
                self.numbers(size, w.next().unwrap_or("vtktypeint64"), "CONNECTIVITY")?;
            let offsets = as_i64(&offsets)
                .map_err(|k| self.error(at, format!("offset {k} is not an integer")))?;
            let connectivity = as_i64(&connectivity).map_err(|k| {
                self.error(at2, format!("connectivity entry {k} is not an integer"))
            })?;
            let mut cells = Vec::with_capacity(n.saturating_sub(1));
            for c in 0..n.saturating_sub(1) {
                let (s, e) = (
                    index(offsets[c], "an offset").map_err(|e| self.error(at, e))?,
                    index(offsets[c + 1], "an offset").map_err(|e| self.error(at, e))?,
                );
                if s > e || e > connectivity.len() {
                    return Err(self.error(
                        at,
                        format!(
                            "cell {c} spans entries {s}..{e} of {} connectivity entries",
                            connectivity.len()
                        ),
                    ));
                }
                cells.push(
                    connectivity[s..e]
                        .iter()
                        .map(|&p| index(p, "a point index").map_err(|e| self.error(at2, e)))
                        .collect::<Result<_, _>>()?,
                );
            }
            return Ok(cells);
        }
        let values = self.numbers(size, "int", "the cell list")?;
        let values =
            as_i64(&values).map_err(|k| self.error(at, format!("entry {k} is not an integer")))?;
        let mut cells = Vec::with_capacity(n.min(size));
        let mut k = 0;
        for c in 0..n {
            let count = values
                .get(k)
                .ok_or_else(|| self.error(at, format!("the cell list ends before cell {c}")))
                .and_then(|&v| {
                    index(v, &format!("the size of cell {c}")).map_err(|e| self.error(at, e))
                })?;
            let points = values
                .get(k + 1..)
                .and_then(|rest| rest.get(..count))
                .ok_or_else(|| {
                    self.error(
                        at,
                        format!("cell {c} of {count} points runs past the cell list"),
                    )
                })?;
            cells.push(
                points
                    .iter()
                    .map(|&p| index(p, "a point index").map_err(|e| self.error(at, e)))
                    .collect::<Result<_, _>>()?,
            );
            k += 1 + count;
        }
        if k != size {
            return Err(self.error(
                at,
                format!("the cell list has {size} numbers, its cells use {k}"),
            ));
        }
        Ok(cells)
    }
}
