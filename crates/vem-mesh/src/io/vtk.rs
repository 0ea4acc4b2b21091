//! VTK XML unstructured grids (`.vtu`) as ParaView and VisIt read them, and `.pvd` collections.
//!
//! An [`UnstructuredGrid`] is points in 3D, a block of [`Cells`] of any VTK type (polygons,
//! lines and poly-lines for contact interfaces, triangles, quadrangles, and polyhedra with
//! their faces), and point and cell data arrays ([`VtkArray`]) of any number of components
//! (scalars, vectors, tensors in VTK's 9-component or 6-component symmetric layout) of type
//! Float64, Int32, Int64 or UInt8. [`UnstructuredGrid::write`] writes it as
//!
//! - [`VtuEncoding::Binary`] (the default): every array in one `<AppendedData encoding="raw">`
//!   block after the XML, each preceded by its byte count as a `UInt64` (`header_type="UInt64"`);
//!   bit-exact, about a third of the ASCII size, and written at the speed of the disk;
//! - [`VtuEncoding::Compressed`]: the same, each array cut into blocks of 32 KiB compressed by
//!   zlib (`compressor="vtkZLibDataCompressor"`, the compressor ParaView offers), smaller still
//!   where values repeat (connectivity, offsets, cell types, integer data);
//! - [`VtuEncoding::Ascii`]: text, every `f64` in Rust's shortest round-trip form, for reading
//!   by eye and for diffs.
//!
//! ```
//! # #[cfg(feature = "generators")] {
//! use vem_mesh::generators::{structured_quads, Rectangle};
//! use vem_mesh::io::{CellType, Cells, UnstructuredGrid, VtkArray, VtuEncoding};
//!
//! let mesh = structured_quads(&Rectangle::unit_square(), 2, 2)?;
//! let stress: Vec<[f64; 3]> = vec![[1.0, 2.0, 0.5]; mesh.n_polygons()];
//! let grid = UnstructuredGrid::from_mesh(&mesh)
//!     .with_point_data(VtkArray::scalars("x", mesh.vertices().iter().map(|p| p.x).collect()))
//!     .with_cell_data(VtkArray::symmetric_tensors_2d("stress", &stress));
//! // A contact interface: one poly-line through points 0, 1, 2 with a point array.
//! let mut lines = Cells::new();
//! lines.push(CellType::PolyLine, &[0, 1, 2]);
//! let interface = UnstructuredGrid::new(vec![[0.0, 0.0, 0.0], [0.5, 0.0, 0.0], [1.0, 0.0, 0.0]], lines)
//!     .with_point_data(VtkArray::scalars("pressure", vec![0.0, 2.0, 0.0]));
//! let dir = std::env::temp_dir().join(format!("vem-mesh-vtk-doc-{}", std::process::id()));
//! std::fs::create_dir_all(&dir).unwrap();
//! grid.write(dir.join("body.vtu"), VtuEncoding::Compressed)?;
//! interface.write(dir.join("interface.vtu"), VtuEncoding::Binary)?;
//! # std::fs::remove_dir_all(&dir).unwrap();
//! # }
//! # Ok::<(), vem_mesh::MeshError>(())
//! ```

use std::fmt::Write as _;
use std::io::{self, Write};
use std::path::{Path, PathBuf};

use super::{write_atomically, xml_escape};
use crate::{Mesh, MeshError, Vector};

/// How the arrays of a `.vtu` file are stored.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum VtuEncoding {
    /// Text inside each `<DataArray>`.
    Ascii,
    /// Raw little-endian binary in one `<AppendedData encoding="raw">` block (the default).
    #[default]
    Binary,
    /// Like [`VtuEncoding::Binary`], each array compressed by zlib in blocks of 32 KiB.
    Compressed,
}

impl VtuEncoding {
    /// The encoding named `ascii`, `binary` or `compressed` (for settings files and command
    /// lines).
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "ascii" => Some(VtuEncoding::Ascii),
            "binary" => Some(VtuEncoding::Binary),
            "compressed" | "zlib" => Some(VtuEncoding::Compressed),
            _ => None,
        }
    }

    /// The name [`VtuEncoding::from_name`] takes.
    pub fn name(self) -> &'static str {
        match self {
            VtuEncoding::Ascii => "ascii",
            VtuEncoding::Binary => "binary",
            VtuEncoding::Compressed => "compressed",
        }
    }
}

/// A VTK cell type, with the number VTK gives it (`vtkCellType.h`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[non_exhaustive]
pub enum CellType {
    /// A single point (1).
    Vertex,
    /// A segment of two points (3).
    Line,
    /// A chain of segments through its points in order (4).
    PolyLine,
    /// A triangle (5).
    Triangle,
    /// A polygon, its points in order around it (7).
    Polygon,
    /// An axis-aligned rectangle, its points in lexicographic order (8).
    Pixel,
    /// A quadrangle, its points in order around it (9).
    Quad,
    /// A tetrahedron (10).
    Tetra,
    /// A hexahedron (12).
    Hexahedron,
    /// A wedge, or triangular prism (13).
    Wedge,
    /// A pyramid (14).
    Pyramid,
    /// A polyhedron given by its faces (42): see [`Cells::push_polyhedron`].
    Polyhedron,
}

impl CellType {
    /// VTK's number of the type.
    pub fn vtk_id(self) -> u8 {
        match self {
            CellType::Vertex => 1,
            CellType::Line => 3,
            CellType::PolyLine => 4,
            CellType::Triangle => 5,
            CellType::Polygon => 7,
            CellType::Pixel => 8,
            CellType::Quad => 9,
            CellType::Tetra => 10,
            CellType::Hexahedron => 12,
            CellType::Wedge => 13,
            CellType::Pyramid => 14,
            CellType::Polyhedron => 42,
        }
    }

    /// The type with VTK's number `id`, `None` for a number this module does not know.
    pub fn from_vtk_id(id: u8) -> Option<Self> {
        Some(match id {
            1 => CellType::Vertex,
            3 => CellType::Line,
            4 => CellType::PolyLine,
            5 => CellType::Triangle,
            7 => CellType::Polygon,
            8 => CellType::Pixel,
            9 => CellType::Quad,
            10 => CellType::Tetra,
            12 => CellType::Hexahedron,
            13 => CellType::Wedge,
            14 => CellType::Pyramid,
            42 => CellType::Polyhedron,
            _ => return None,
        })
    }

    /// The number of points a cell of this type has, `None` when any number may do (poly-line,
    /// polygon, polyhedron).
    pub fn fixed_points(self) -> Option<usize> {
        match self {
            CellType::Vertex => Some(1),
            CellType::Line => Some(2),
            CellType::Triangle => Some(3),
            CellType::Pixel | CellType::Quad | CellType::Tetra => Some(4),
            CellType::Pyramid => Some(5),
            CellType::Wedge => Some(6),
            CellType::Hexahedron => Some(8),
            CellType::PolyLine | CellType::Polygon | CellType::Polyhedron => None,
        }
    }

    /// The dimension of a cell of this type (0 to 3).
    pub fn dimension(self) -> usize {
        match self {
            CellType::Vertex => 0,
            CellType::Line | CellType::PolyLine => 1,
            CellType::Triangle | CellType::Polygon | CellType::Pixel | CellType::Quad => 2,
            _ => 3,
        }
    }
}

/// The cells of an unstructured grid, in VTK's layout: the points of cell `c` are
/// `connectivity[offsets[c]..offsets[c + 1]]` and its type `types[c]`.
///
/// Polyhedra also have faces: `face_offsets[c]` is, for a polyhedron, the end of its entry in
/// `faces` (the number of faces, then for each face its number of points and the points), and
/// -1 for any other cell; `faces` and `face_offsets` stay empty while the block holds no
/// polyhedron. A cell block of any mix of types is built by [`Cells::push`] and
/// [`Cells::push_polyhedron`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Cells {
    /// The points of all cells, one cell after the other.
    pub connectivity: Vec<usize>,
    /// `offsets[c]..offsets[c + 1]` is cell `c` in `connectivity`; starts with 0.
    pub offsets: Vec<usize>,
    /// The type of each cell.
    pub types: Vec<CellType>,
    /// The faces of the polyhedra, in VTK's layout (empty without polyhedra).
    pub faces: Vec<usize>,
    /// For each cell, the end of its faces in `faces`, or -1 (empty without polyhedra).
    pub face_offsets: Vec<i64>,
}

impl Default for Cells {
    fn default() -> Self {
        Self::new()
    }
}

impl Cells {
    /// No cells.
    pub fn new() -> Self {
        Cells {
            connectivity: Vec::new(),
            offsets: vec![0],
            types: Vec::new(),
            faces: Vec::new(),
            face_offsets: Vec::new(),
        }
    }

    /// The polygons of `mesh`, as VTK polygons (type 7).
    pub fn polygons_of(mesh: &Mesh) -> Self {
        Cells {
            connectivity: mesh.polygon_vertex_indices().to_vec(),
            offsets: mesh.polygon_offsets().to_vec(),
            types: vec![CellType::Polygon; mesh.n_polygons()],
            faces: Vec::new(),
            face_offsets: Vec::new(),
        }
    }

    /// The number of cells.
    pub fn len(&self) -> usize {
        self.types.len()
    }

    /// True when there are no cells.
    pub fn is_empty(&self) -> bool {
        self.types.is_empty()
    }

    /// The points of cell `c`.
    pub fn cell(&self, c: usize) -> &[usize] {
        &self.connectivity[self.offsets[c]..self.offsets[c + 1]]
    }

    /// Appends a cell of type `cell_type` through `points` (indices into the grid's points).
    /// For a polyhedron use [`Cells::push_polyhedron`]; whether the number of points suits the
    /// type is checked when the grid is written.
    pub fn push(&mut self, cell_type: CellType, points: &[usize]) {
        self.connectivity.extend_from_slice(points);
        self.offsets.push(self.connectivity.len());
        self.types.push(cell_type);
        if !self.face_offsets.is_empty() {
            self.face_offsets.push(-1);
        }
    }

    /// Appends a polyhedron given by its faces, each a loop of points (indices into the grid's
    /// points) ordered counter-clockwise seen from outside. Its points are the distinct points
    /// of its faces in order of first appearance.
    pub fn push_polyhedron(&mut self, faces: &[&[usize]]) {
        if self.face_offsets.is_empty() {
            self.face_offsets = vec![-1; self.types.len()];
        }
        let first = self.connectivity.len();
        for face in faces {
            for &p in *face {
                if !self.connectivity[first..].contains(&p) {
                    self.connectivity.push(p);
                }
            }
        }
        self.offsets.push(self.connectivity.len());
        self.types.push(CellType::Polyhedron);
        self.faces.push(faces.len());
        for face in faces {
            self.faces.push(face.len());
            self.faces.extend_from_slice(face);
        }
        self.face_offsets.push(self.faces.len() as i64);
    }
}

/// The values of a data array.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum Values {
    /// 64-bit floating-point numbers (`Float64`).
    Float64(Vec<f64>),
    /// 32-bit signed integers (`Int32`).
    Int32(Vec<i32>),
    /// 64-bit signed integers (`Int64`).
    Int64(Vec<i64>),
    /// Bytes (`UInt8`): flags, statuses.
    UInt8(Vec<u8>),
}

impl Values {
    /// The number of values.
    pub fn len(&self) -> usize {
        match self {
            Values::Float64(v) => v.len(),
            Values::Int32(v) => v.len(),
            Values::Int64(v) => v.len(),
            Values::UInt8(v) => v.len(),
        }
    }

    /// True when there are no values.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// VTK's name of the type (`Float64`, ...).
    pub fn type_name(&self) -> &'static str {
        match self {
            Values::Float64(_) => "Float64",
            Values::Int32(_) => "Int32",
            Values::Int64(_) => "Int64",
            Values::UInt8(_) => "UInt8",
        }
    }

    /// Value `k` as an `f64` (exact for every type but Int64 beyond 2^53).
    pub fn get_f64(&self, k: usize) -> Option<f64> {
        match self {
            Values::Float64(v) => v.get(k).copied(),
            Values::Int32(v) => v.get(k).map(|&x| f64::from(x)),
            Values::Int64(v) => v.get(k).map(|&x| x as f64),
            Values::UInt8(v) => v.get(k).map(|&x| f64::from(x)),
        }
    }

    /// Value `k` as an `i64`, `None` for a floating-point value that is not a whole number.
    pub fn get_i64(&self, k: usize) -> Option<i64> {
        match self {
            Values::Float64(v) => v
                .get(k)
                .filter(|x| x.fract() == 0.0 && x.abs() < 9.0e15)
                .map(|&x| x as i64),
            Values::Int32(v) => v.get(k).map(|&x| i64::from(x)),
            Values::Int64(v) => v.get(k).copied(),
            Values::UInt8(v) => v.get(k).map(|&x| i64::from(x)),
        }
    }
}

/// A named data array of points or cells: `components` values per point (or cell), one
/// point after the other.
#[derive(Debug, Clone, PartialEq)]
pub struct VtkArray {
    /// The name shown in the viewer.
    pub name: String,
    /// Number of components per point or cell (1: scalar, 3: vector, 6: symmetric tensor
    /// XX YY ZZ XY YZ XZ, 9: tensor by rows, or any other number).
    pub components: usize,
    /// The values, `components` per point or cell.
    pub values: Values,
}

impl VtkArray {
    /// An array of `components` values per entry.
    pub fn new(name: impl Into<String>, components: usize, values: Values) -> Self {
        VtkArray {
            name: name.into(),
            components,
            values,
        }
    }

    /// One `f64` per entry.
    pub fn scalars(name: impl Into<String>, values: Vec<f64>) -> Self {
        Self::new(name, 1, Values::Float64(values))
    }

    /// One plane vector per entry, written as a 3D vector with z = 0 (so that ParaView can warp
    /// by it).
    pub fn vectors_2d(name: impl Into<String>, values: &[Vector]) -> Self {
        let values = values.iter().flat_map(|v| [v.x, v.y, 0.0]).collect();
        Self::new(name, 3, Values::Float64(values))
    }

    /// One 3D vector per entry.
    pub fn vectors(name: impl Into<String>, values: &[[f64; 3]]) -> Self {
        Self::new(name, 3, Values::Float64(values.concat()))
    }

    /// One symmetric plane tensor `[xx, yy, xy]` per entry (a stress in plane strain without
    /// its zz component), written in VTK's 6-component symmetric layout XX YY ZZ XY YZ XZ with
    /// zeros for ZZ, YZ and XZ.
    pub fn symmetric_tensors_2d(name: impl Into<String>, values: &[[f64; 3]]) -> Self {
        let values = values
            .iter()
            .flat_map(|&[xx, yy, xy]| [xx, yy, 0.0, xy, 0.0, 0.0])
            .collect();
        Self::new(name, 6, Values::Float64(values))
    }

    /// One symmetric tensor per entry in VTK's 6-component layout XX YY ZZ XY YZ XZ.
    pub fn symmetric_tensors(name: impl Into<String>, values: &[[f64; 6]]) -> Self {
        Self::new(name, 6, Values::Float64(values.concat()))
    }

    /// One full tensor per entry, 9 components by rows (XX XY XZ YX YY YZ ZX ZY ZZ).
    pub fn tensors(name: impl Into<String>, values: &[[f64; 9]]) -> Self {
        Self::new(name, 9, Values::Float64(values.concat()))
    }

    /// One `i32` per entry (part numbers, body numbers).
    pub fn int32(name: impl Into<String>, values: Vec<i32>) -> Self {
        Self::new(name, 1, Values::Int32(values))
    }

    /// One `u8` per entry (flags, contact statuses).
    pub fn uint8(name: impl Into<String>, values: Vec<u8>) -> Self {
        Self::new(name, 1, Values::UInt8(values))
    }

    /// The number of entries (points or cells) the values cover.
    pub fn entries(&self) -> usize {
        self.values.len() / self.components.max(1)
    }
}

/// A VTK unstructured grid: points in 3D, cells, and point and cell data.
#[derive(Debug, Clone, PartialEq)]
pub struct UnstructuredGrid {
    /// The points.
    pub points: Vec<[f64; 3]>,
    /// The cells, through indices into `points`.
    pub cells: Cells,
    /// Arrays with one entry per point.
    pub point_data: Vec<VtkArray>,
    /// Arrays with one entry per cell.
    pub cell_data: Vec<VtkArray>,
    /// Arrays of the whole dataset, of any length (a time, names of parts as meshio writes
    /// them).
    pub field_data: Vec<VtkArray>,
}

impl UnstructuredGrid {
    /// A grid of `points` and `cells`, without data.
    pub fn new(points: Vec<[f64; 3]>, cells: Cells) -> Self {
        UnstructuredGrid {
            points,
            cells,
            point_data: Vec::new(),
            cell_data: Vec::new(),
            field_data: Vec::new(),
        }
    }

    /// The mesh's vertices (z = 0) and polygons.
    pub fn from_mesh(mesh: &Mesh) -> Self {
        let points = mesh.vertices().iter().map(|p| [p.x, p.y, 0.0]).collect();
        Self::new(points, Cells::polygons_of(mesh))
    }

    /// Adds a point-data array.
    pub fn with_point_data(mut self, array: VtkArray) -> Self {
        self.point_data.push(array);
        self
    }

    /// Adds a cell-data array.
    pub fn with_cell_data(mut self, array: VtkArray) -> Self {
        self.cell_data.push(array);
        self
    }

    /// Checks what a reader relies on: finite point coordinates, cells through existing
    /// points with a number of points that suits their type, well-formed faces of polyhedra,
    /// and data arrays with a non-empty name unique within their group, at least one
    /// component, one entry per point (or cell) and finite values. The error names the cell,
    /// point or array.
    pub fn check(&self) -> Result<(), String> {
        if let Some(p) = self
            .points
            .iter()
            .position(|p| !p.iter().all(|x| x.is_finite()))
        {
            return Err(format!(
                "point {p} has a non-finite coordinate {:?}",
                self.points[p]
            ));
        }
        let cells = &self.cells;
        let n = cells.len();
        let offsets_ok = cells.offsets.len() == n + 1
            && cells.offsets[0] == 0
            && cells.offsets[n] == cells.connectivity.len()
            && cells.offsets.windows(2).all(|w| w[0] <= w[1]);
        if !offsets_ok {
            return Err(format!(
                "the cell offsets ({} of them) do not describe {n} cells of {} points in all",
                cells.offsets.len(),
                cells.connectivity.len()
            ));
        }
        if !(cells.face_offsets.is_empty() || cells.face_offsets.len() == n) {
            return Err(format!(
                "{} face offsets for {n} cells",
                cells.face_offsets.len()
            ));
        }
        for c in 0..n {
            let points = cells.cell(c);
            let cell_type = cells.types[c];
            if let Some(&p) = points.iter().find(|&&p| p >= self.points.len()) {
                return Err(format!(
                    "cell {c} refers to point {p}, but there are {} points",
                    self.points.len()
                ));
            }
            let count_ok = match cell_type.fixed_points() {
                Some(k) => points.len() == k,
                None => points.len() >= if cell_type == CellType::Polygon { 3 } else { 2 },
            };
            if !count_ok {
                return Err(format!(
                    "cell {c} of type {cell_type:?} has {} points",
                    points.len()
                ));
            }
            let face_end = cells.face_offsets.get(c).copied().unwrap_or(-1);
            if (cell_type == CellType::Polyhedron) != (face_end >= 0) {
                return Err(format!(
                    "cell {c} of type {cell_type:?} has face offset {face_end}"
                ));
            }
        }
        self.check_faces()?;
        check_arrays("point", &self.point_data, self.points.len())?;
        check_arrays("cell", &self.cell_data, n)?;
        for array in &self.field_data {
            check_arrays("field", std::slice::from_ref(array), array.entries())?;
        }
        Ok(())
    }

    /// The faces of the polyhedra: each entry within `faces`, its faces through points of the
    /// cell.
    fn check_faces(&self) -> Result<(), String> {
        let cells = &self.cells;
        let mut at = 0usize;
        for (c, &end) in cells.face_offsets.iter().enumerate() {
            if end < 0 {
                continue;
            }
            let end = end as usize;
            let bad = |why: &str| format!("the faces of polyhedron {c} {why}");
            if end > cells.faces.len() || end <= at {
                return Err(bad("end outside the face list"));
            }
            let entry = &cells.faces[at..end];
            let (&n_faces, mut rest) = entry.split_first().ok_or_else(|| bad("are empty"))?;
            for _ in 0..n_faces {
                let (&k, tail) = rest
                    .split_first()
                    .ok_or_else(|| bad("are fewer than announced"))?;
                if k < 3 || tail.len() < k {
                    return Err(bad("hold a face of fewer than 3 points or cut short"));
                }
                if let Some(&p) = tail[..k].iter().find(|p| !cells.cell(c).contains(p)) {
                    return Err(bad(&format!(
                        "use point {p}, which is not a point of the cell"
                    )));
                }
                rest = &tail[k..];
            }
            if !rest.is_empty() {
                return Err(bad("hold more numbers than their faces use"));
            }
            at = end;
        }
        Ok(())
    }

    /// Writes the grid to `path` as a `.vtu` file in `encoding`, atomically (whole or not at
    /// all). The grid is checked first ([`UnstructuredGrid::check`]); a failed check is
    /// [`MeshError::Write`] naming what is wrong.
    pub fn write(&self, path: impl AsRef<Path>, encoding: VtuEncoding) -> Result<(), MeshError> {
        let path = path.as_ref();
        self.check().map_err(|reason| MeshError::Write {
            path: path.to_path_buf(),
            reason,
        })?;
        write_atomically(path, |w| {
            write_document(w, &Document::of_grid(self), encoding)
        })
    }

    /// The `.vtu` file of the grid in `encoding`, in memory (checked as by
    /// [`UnstructuredGrid::write`]; the error is the reason).
    pub fn to_vtu_bytes(&self, encoding: VtuEncoding) -> Result<Vec<u8>, String> {
        self.check()?;
        let mut bytes = Vec::new();
        write_document(&mut bytes, &Document::of_grid(self), encoding)
            .map_err(|e| e.to_string())?;
        Ok(bytes)
    }
}

/// Checks the arrays of one group ("point" or "cell") against the number of entries.
fn check_arrays(group: &str, arrays: &[VtkArray], entries: usize) -> Result<(), String> {
    for (i, array) in arrays.iter().enumerate() {
        let label = format!("{group}-data array '{}'", array.name);
        if array.name.trim().is_empty() {
            return Err(format!("{group}-data array {i} has an empty name"));
        }
        if arrays[..i].iter().any(|other| other.name == array.name) {
            return Err(format!("{label} is given twice"));
        }
        if array.components == 0 {
            return Err(format!("{label} has 0 components"));
        }
        let expected = array.components.checked_mul(entries);
        if expected != Some(array.values.len()) {
            return Err(format!(
                "{label} has {} values, expected {} ({} per {group} for {entries} {group}s)",
                array.values.len(),
                array.components.saturating_mul(entries),
                array.components,
            ));
        }
        if let Values::Float64(values) = &array.values {
            if let Some(k) = values.iter().position(|v| !v.is_finite()) {
                return Err(format!(
                    "{label} has the non-finite value {} at entry {} (component {})",
                    values[k],
                    k / array.components,
                    k % array.components
                ));
            }
        }
    }
    Ok(())
}

/// Uncompressed bytes per zlib block (VTK's default).
const BLOCK_SIZE: usize = 1 << 15;

/// Bytes of raw binary data encoded at a time on their way to the file (the scratch buffer
/// stays in cache; the file sees a few large writes).
const BINARY_CHUNK: usize = 1 << 18;

/// zlib's compression level (1 fastest, 9 smallest): 1 compresses integer arrays nearly as
/// well as 6 at several times the speed (floating-point values compress little at any level).
const COMPRESSION_LEVEL: u8 = 1;

/// Where the values of one array of a document come from: borrowed from the caller's data
/// and converted to their type in the file on the way out (no copy of a whole array).
#[derive(Clone, Copy)]
pub(super) enum Source<'a> {
    /// `Float64` values as they are.
    Float64(&'a [f64]),
    /// `Float64` pairs, each written with a third component 0.
    Pairs(&'a [f64]),
    /// Points in space (`Float64`, three per point).
    Points(&'a [[f64; 3]]),
    /// Points in the plane, written with z = 0.
    PlanePoints(&'a [crate::Point]),
    /// Indices, written as `Int64`.
    Indices(&'a [usize]),
    /// `Int64` values.
    Int64(&'a [i64]),
    /// `Int32` values.
    Int32(&'a [i32]),
    /// `UInt8` values.
    UInt8(&'a [u8]),
    /// Cell types, written as their `UInt8` VTK numbers.
    Types(&'a [CellType]),
    /// One cell type `count` times.
    Repeated(CellType, usize),
}

/// One value of a [`Source`], for text.
enum Number {
    Float(f64),
    Integer(i64),
}

impl<'a> Source<'a> {
    /// The values of an array.
    fn of(values: &'a Values) -> Self {
        match values {
            Values::Float64(v) => Source::Float64(v),
            Values::Int32(v) => Source::Int32(v),
            Values::Int64(v) => Source::Int64(v),
            Values::UInt8(v) => Source::UInt8(v),
        }
    }

    /// The number of values written (components included).
    fn len(&self) -> usize {
        match *self {
            Source::Int32(v) => v.len(),
            Source::UInt8(v) => v.len(),
            Source::Float64(v) => v.len(),
            Source::Pairs(v) => v.len() / 2 * 3,
            Source::Points(v) => 3 * v.len(),
            Source::PlanePoints(v) => 3 * v.len(),
            Source::Indices(v) => v.len(),
            Source::Int64(v) => v.len(),
            Source::Types(v) => v.len(),
            Source::Repeated(_, count) => count,
        }
    }

    /// VTK's name of the type written.
    fn type_name(&self) -> &'static str {
        match *self {
            Source::Int32(_) => "Int32",
            Source::Float64(_) | Source::Pairs(_) | Source::Points(_) | Source::PlanePoints(_) => {
                "Float64"
            }
            Source::Indices(_) | Source::Int64(_) => "Int64",
            Source::UInt8(_) | Source::Types(_) | Source::Repeated(..) => "UInt8",
        }
    }

    /// Bytes per value in binary.
    fn value_bytes(&self) -> usize {
        match *self {
            Source::Int32(_) => 4,
            Source::UInt8(_) | Source::Types(_) | Source::Repeated(..) => 1,
            _ => 8,
        }
    }

    /// Value `k`, for text.
    fn number(&self, k: usize) -> Number {
        let plane = |x: f64, y: f64, c: usize| match c {
            0 => x,
            1 => y,
            _ => 0.0,
        };
        match *self {
            Source::Float64(v) => Number::Float(v[k]),
            Source::Int32(v) => Number::Integer(i64::from(v[k])),
            Source::Int64(v) => Number::Integer(v[k]),
            Source::UInt8(v) => Number::Integer(i64::from(v[k])),
            Source::Pairs(v) => {
                let (i, c) = (k / 3, k % 3);
                Number::Float(plane(v[2 * i], v[2 * i + 1], c))
            }
            Source::Points(v) => Number::Float(v[k / 3][k % 3]),
            Source::PlanePoints(v) => {
                let p = v[k / 3];
                Number::Float(plane(p.x, p.y, k % 3))
            }
            Source::Indices(v) => Number::Integer(v[k] as i64),
            Source::Types(v) => Number::Integer(i64::from(v[k].vtk_id())),
            Source::Repeated(t, _) => Number::Integer(i64::from(t.vtk_id())),
        }
    }

    /// Appends the values as text, separated by spaces, `per_line` to a line.
    fn write_text(&self, out: &mut String, per_line: usize) {
        let per_line = per_line.max(1);
        for k in 0..self.len() {
            out.push_str(if k % per_line == 0 {
                "\n          "
            } else {
                " "
            });
            match self.number(k) {
                Number::Float(x) => write!(out, "{x:e}"),
                Number::Integer(i) => write!(out, "{i}"),
            }
            .expect("writing to a String cannot fail");
        }
        out.push_str("\n        ");
    }

    /// Hands the values as little-endian bytes to `sink`, in pieces of `chunk` bytes (a
    /// multiple of 8; the last piece shorter), encoded into `scratch`.
    fn for_each_chunk(
        &self,
        chunk: usize,
        scratch: &mut Vec<u8>,
        sink: &mut dyn FnMut(&[u8]) -> io::Result<()>,
    ) -> io::Result<()> {
        /// Encodes `count` items of `N` bytes each (`at(k)`), handing `chunk` bytes at a time.
        fn encode<const N: usize>(
            count: usize,
            at: impl Fn(usize) -> [u8; N],
            chunk: usize,
            scratch: &mut Vec<u8>,
            sink: &mut dyn FnMut(&[u8]) -> io::Result<()>,
        ) -> io::Result<()> {
            let per_chunk = chunk / N;
            let mut k = 0;
            while k < count {
                let end = (k + per_chunk).min(count);
                scratch.clear();
                for i in k..end {
                    scratch.extend_from_slice(&at(i));
                }
                sink(scratch)?;
                k = end;
            }
            Ok(())
        }
        let plane = |x: f64, y: f64, c: usize| match c {
            0 => x,
            1 => y,
            _ => 0.0,
        };
        match *self {
            Source::Float64(v) => encode(v.len(), |k| v[k].to_le_bytes(), chunk, scratch, sink),
            Source::Int32(v) => encode(v.len(), |k| v[k].to_le_bytes(), chunk, scratch, sink),
            Source::Int64(v) => encode(v.len(), |k| v[k].to_le_bytes(), chunk, scratch, sink),
            Source::UInt8(v) => v.chunks(chunk).try_for_each(sink),
            Source::Pairs(v) => encode(
                self.len(),
                |k| plane(v[2 * (k / 3)], v[2 * (k / 3) + 1], k % 3).to_le_bytes(),
                chunk,
                scratch,
                sink,
            ),
            Source::Points(v) => encode(
                self.len(),
                |k| v[k / 3][k % 3].to_le_bytes(),
                chunk,
                scratch,
                sink,
            ),
            Source::PlanePoints(v) => encode(
                self.len(),
                |k| plane(v[k / 3].x, v[k / 3].y, k % 3).to_le_bytes(),
                chunk,
                scratch,
                sink,
            ),
            Source::Indices(v) => encode(
                v.len(),
                |k| (v[k] as i64).to_le_bytes(),
                chunk,
                scratch,
                sink,
            ),
            Source::Types(v) => encode(v.len(), |k| [v[k].vtk_id()], chunk, scratch, sink),
            Source::Repeated(t, count) => encode(count, |_| [t.vtk_id()], chunk, scratch, sink),
        }
    }
}

/// One array of a document: its name, components per entry and values.
pub(super) struct Column<'a> {
    pub(super) name: &'a str,
    pub(super) components: usize,
    pub(super) source: Source<'a>,
}

impl<'a> Column<'a> {
    fn of(array: &'a VtkArray) -> Self {
        Column {
            name: &array.name,
            components: array.components,
            source: Source::of(&array.values),
        }
    }
}

/// What a `.vtu` file holds, borrowed from the caller: the arrays are converted on their way
/// to the file.
pub(super) struct Document<'a> {
    pub(super) n_points: usize,
    pub(super) n_cells: usize,
    /// The point coordinates (three components).
    pub(super) points: Source<'a>,
    /// connectivity, offsets, types (and faces, faceoffsets for polyhedra).
    pub(super) cells: Vec<Column<'a>>,
    pub(super) field_data: Vec<Column<'a>>,
    pub(super) point_data: Vec<Column<'a>>,
    pub(super) cell_data: Vec<Column<'a>>,
}

impl<'a> Document<'a> {
    /// The document of `grid`.
    fn of_grid(grid: &'a UnstructuredGrid) -> Self {
        let cells = &grid.cells;
        let mut columns = vec![
            Column {
                name: "connectivity",
                components: 1,
                source: Source::Indices(&cells.connectivity),
            },
            Column {
                name: "offsets",
                components: 1,
                source: Source::Indices(&cells.offsets[1..]),
            },
            Column {
                name: "types",
                components: 1,
                source: Source::Types(&cells.types),
            },
        ];
        if !cells.face_offsets.is_empty() {
            columns.push(Column {
                name: "faces",
                components: 1,
                source: Source::Indices(&cells.faces),
            });
            columns.push(Column {
                name: "faceoffsets",
                components: 1,
                source: Source::Int64(&cells.face_offsets),
            });
        }
        Document {
            n_points: grid.points.len(),
            n_cells: cells.len(),
            points: Source::Points(&grid.points),
            cells: columns,
            field_data: grid.field_data.iter().map(Column::of).collect(),
            point_data: grid.point_data.iter().map(Column::of).collect(),
            cell_data: grid.cell_data.iter().map(Column::of).collect(),
        }
    }

    /// The document of a planar mesh's vertices (z = 0) and polygons, without data.
    pub(super) fn of_mesh(mesh: &'a Mesh) -> Self {
        Document {
            n_points: mesh.n_vertices(),
            n_cells: mesh.n_polygons(),
            points: Source::PlanePoints(mesh.vertices()),
            cells: vec![
                Column {
                    name: "connectivity",
                    components: 1,
                    source: Source::Indices(mesh.polygon_vertex_indices()),
                },
                Column {
                    name: "offsets",
                    components: 1,
                    source: Source::Indices(&mesh.polygon_offsets()[1..]),
                },
                Column {
                    name: "types",
                    components: 1,
                    source: Source::Repeated(CellType::Polygon, mesh.n_polygons()),
                },
            ],
            field_data: Vec::new(),
            point_data: Vec::new(),
            cell_data: Vec::new(),
        }
    }
}

/// Writes the whole document. In binary the XML comes first, with the offsets of the arrays
/// computed from their sizes, then every array is encoded straight into `w`.
pub(super) fn write_document(
    w: &mut dyn Write,
    document: &Document,
    encoding: VtuEncoding,
) -> io::Result<()> {
    let point_coordinates = [Column {
        name: "Points",
        components: 3,
        source: document.points,
    }];
    let mut xml = String::new();
    let compressor = if encoding == VtuEncoding::Compressed {
        " compressor=\"vtkZLibDataCompressor\""
    } else {
        ""
    };
    writeln!(xml, "<?xml version=\"1.0\"?>").unwrap_or(());
    writeln!(
        xml,
        "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" \
         header_type=\"UInt64\"{compressor}>"
    )
    .unwrap_or(());
    writeln!(xml, "  <UnstructuredGrid>").unwrap_or(());
    let mut sections: Vec<(&str, String, &[Column])> = vec![
        (
            "PointData",
            active_attributes(&document.point_data),
            &document.point_data,
        ),
        (
            "CellData",
            active_attributes(&document.cell_data),
            &document.cell_data,
        ),
        ("Points", String::new(), &point_coordinates),
        ("Cells", String::new(), &document.cells),
    ];
    if !document.field_data.is_empty() {
        sections.insert(0, ("FieldData", String::new(), &document.field_data));
    }
    // Compressed: the appended blocks, in the order of the arrays in the XML. Binary: the
    // arrays in that order, written after the XML.
    let mut compressed: Vec<u8> = Vec::new();
    let mut binary: Vec<&Source> = Vec::new();
    let mut binary_offset = 0usize;
    let mut scratch = Vec::new();
    for (tag, attributes, columns) in &sections {
        if *tag == "PointData" {
            writeln!(
                xml,
                "    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">",
                document.n_points, document.n_cells
            )
            .unwrap_or(());
        }
        writeln!(xml, "      <{tag}{attributes}>").unwrap_or(());
        for column in columns.iter() {
            let source = &column.source;
            write!(
                xml,
                "        <DataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\"",
                source.type_name(),
                xml_escape(column.name),
                column.components
            )
            .unwrap_or(());
            if *tag == "FieldData" {
                write!(
                    xml,
                    " NumberOfTuples=\"{}\"",
                    source.len() / column.components.max(1)
                )
                .unwrap_or(());
            }
            match encoding {
                VtuEncoding::Ascii => {
                    xml.push_str(" format=\"ascii\">");
                    source.write_text(&mut xml, text_per_line(column.components));
                    xml.push_str("</DataArray>\n");
                }
                VtuEncoding::Binary => {
                    writeln!(xml, " format=\"appended\" offset=\"{binary_offset}\"/>")
                        .unwrap_or(());
                    binary_offset += 8 + source.len() * source.value_bytes();
                    binary.push(source);
                }
                VtuEncoding::Compressed => {
                    writeln!(
                        xml,
                        " format=\"appended\" offset=\"{}\"/>",
                        compressed.len()
                    )
                    .unwrap_or(());
                    compressed_block(source, &mut scratch, &mut compressed)?;
                }
            }
        }
        writeln!(xml, "      </{tag}>").unwrap_or(());
    }
    writeln!(xml, "    </Piece>").unwrap_or(());
    writeln!(xml, "  </UnstructuredGrid>").unwrap_or(());
    w.write_all(xml.as_bytes())?;
    if encoding != VtuEncoding::Ascii {
        w.write_all(b"  <AppendedData encoding=\"raw\">\n   _")?;
        if encoding == VtuEncoding::Binary {
            for source in binary {
                let bytes = (source.len() * source.value_bytes()) as u64;
                w.write_all(&bytes.to_le_bytes())?;
                source
                    .for_each_chunk(BINARY_CHUNK, &mut scratch, &mut |piece| w.write_all(piece))?;
            }
        } else {
            w.write_all(&compressed)?;
        }
        w.write_all(b"\n  </AppendedData>\n")?;
    }
    w.write_all(b"</VTKFile>\n")
}

/// Values per line of text: one entry of a multi-component array, else 12 numbers.
fn text_per_line(components: usize) -> usize {
    if components > 1 {
        components
    } else {
        12
    }
}

/// The `Scalars`/`Vectors`/`Tensors` attributes of `<PointData>` or `<CellData>`: the first
/// array with 1, 3 and 9 (or 6) components, so that viewers colour, warp and glyph by them
/// without a choice.
fn active_attributes(arrays: &[Column]) -> String {
    let mut active = String::new();
    let pick = |components: &[usize]| arrays.iter().find(|a| components.contains(&a.components));
    for (attribute, components) in [
        ("Scalars", &[1][..]),
        ("Vectors", &[3]),
        ("Tensors", &[9, 6]),
    ] {
        if let Some(a) = pick(components) {
            write!(active, " {attribute}=\"{}\"", xml_escape(a.name)).unwrap_or(());
        }
    }
    active
}

/// Appends the values of `source` compressed in VTK's block layout: a header of UInt64
/// (number of blocks, uncompressed block size, uncompressed size of the last block if partial
/// else 0, then the compressed size of each block) followed by the zlib streams of the blocks.
fn compressed_block(source: &Source, scratch: &mut Vec<u8>, out: &mut Vec<u8>) -> io::Result<()> {
    let mut blocks: Vec<Vec<u8>> = Vec::new();
    source.for_each_chunk(BLOCK_SIZE, scratch, &mut |block| {
        blocks.push(miniz_oxide::deflate::compress_to_vec_zlib(
            block,
            COMPRESSION_LEVEL,
        ));
        Ok(())
    })?;
    let raw_len = source.len() * source.value_bytes();
    let header = [
        blocks.len() as u64,
        BLOCK_SIZE as u64,
        (raw_len % BLOCK_SIZE) as u64,
    ];
    for value in header
        .into_iter()
        .chain(blocks.iter().map(|b| b.len() as u64))
    {
        out.extend_from_slice(&value.to_le_bytes());
    }
    for block in &blocks {
        out.extend_from_slice(block);
    }
    Ok(())
}

/// One dataset of a `.pvd` collection: a file for a time step and a part.
#[derive(Debug, Clone, PartialEq)]
pub struct PvdDataSet {
    /// The time (or load step) the file belongs to.
    pub timestep: f64,
    /// The part number (one per body, interface, ...) within a time step.
    pub part: usize,
    /// The name of the part, shown by ParaView as the block name.
    pub name: String,
    /// The file, relative to the `.pvd` file's folder (as ParaView resolves it).
    pub file: PathBuf,
}

/// A ParaView collection (`.pvd`): several datasets (bodies, interfaces) at several time steps,
/// opened in ParaView as one source with a time slider.
///
/// ```
/// use vem_mesh::io::PvdCollection;
/// let mut pvd = PvdCollection::new();
/// for (step, load) in [0.5, 1.0].into_iter().enumerate() {
///     pvd.add(load, 0, "block", format!("block-{step}.vtu"));
///     pvd.add(load, 1, "interface", format!("interface-{step}.vtu"));
/// }
/// assert_eq!(pvd.datasets().len(), 4);
/// let text = pvd.to_xml();
/// assert!(text.contains("<DataSet timestep=\"1\" part=\"1\" name=\"interface\" file=\"interface-1.vtu\"/>"));
/// ```
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PvdCollection {
    datasets: Vec<PvdDataSet>,
}

impl PvdCollection {
    /// An empty collection.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds the dataset `file` (relative to the `.pvd` file's folder) as part `part` named
    /// `name` at time `timestep`.
    pub fn add(
        &mut self,
        timestep: f64,
        part: usize,
        name: impl Into<String>,
        file: impl Into<PathBuf>,
    ) -> &mut Self {
        self.datasets.push(PvdDataSet {
            timestep,
            part,
            name: name.into(),
            file: file.into(),
        });
        self
    }

    /// The datasets, in the order added.
    pub fn datasets(&self) -> &[PvdDataSet] {
        &self.datasets
    }

    /// The `.pvd` document.
    pub fn to_xml(&self) -> String {
        let mut xml = String::from(
            "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" \
             byte_order=\"LittleEndian\">\n  <Collection>\n",
        );
        for d in &self.datasets {
            writeln!(
                xml,
                "    <DataSet timestep=\"{}\" part=\"{}\" name=\"{}\" file=\"{}\"/>",
                d.timestep,
                d.part,
                xml_escape(&d.name),
                xml_escape(&d.file.to_string_lossy().replace('\\', "/"))
            )
            .unwrap_or(());
        }
        xml.push_str("  </Collection>\n</VTKFile>\n");
        xml
    }

    /// Writes the collection to `path`, atomically. Every time step must be finite and every
    /// file name relative (ParaView resolves it against the `.pvd` file's folder); the error is
    /// [`MeshError::Write`] naming the dataset.
    pub fn write(&self, path: impl AsRef<Path>) -> Result<(), MeshError> {
        let path = path.as_ref();
        let fail = |reason: String| MeshError::Write {
            path: path.to_path_buf(),
            reason,
        };
        for (k, d) in self.datasets.iter().enumerate() {
            if !d.timestep.is_finite() {
                return Err(fail(format!(
                    "dataset {k} ('{}') has the time step {}",
                    d.file.display(),
                    d.timestep
                )));
            }
            if d.file.is_absolute() || d.file.as_os_str().is_empty() {
                return Err(fail(format!(
                    "dataset {k} names the file '{}'; give it relative to the .pvd file",
                    d.file.display()
                )));
            }
        }
        let xml = self.to_xml();
        write_atomically(path, |w| w.write_all(xml.as_bytes()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every kind of source, pieces of 16 bytes joined, gives the little-endian bytes of its
    /// values one by one.
    #[test]
    fn sources_in_small_pieces_give_their_values_bytes() {
        let floats = [1.5, -0.0, 1e-300, 7.0, f64::MAX];
        let points = [[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]];
        let plane = [crate::Point::new(0.25, -8.0), crate::Point::new(3.0, 1e10)];
        let indices = [0usize, 7, 1 << 40];
        let types = [CellType::Polygon, CellType::Line, CellType::Polyhedron];
        let int32 = Values::Int32(vec![-3, 5, 1 << 30]);
        let bytes_of =
            |values: &[f64]| -> Vec<u8> { values.iter().flat_map(|x| x.to_le_bytes()).collect() };
        let cases: Vec<(Source, Vec<u8>)> = vec![
            (Source::Float64(&floats), bytes_of(&floats)),
            (
                Source::Pairs(&floats[..4]),
                bytes_of(&[1.5, -0.0, 0.0, 1e-300, 7.0, 0.0]),
            ),
            (
                Source::Points(&points),
                bytes_of(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0]),
            ),
            (
                Source::PlanePoints(&plane),
                bytes_of(&[0.25, -8.0, 0.0, 3.0, 1e10, 0.0]),
            ),
            (
                Source::Indices(&indices),
                indices
                    .iter()
                    .flat_map(|&i| (i as i64).to_le_bytes())
                    .collect(),
            ),
            (Source::Types(&types), vec![7, 3, 42]),
            (Source::Repeated(CellType::Polygon, 3), vec![7, 7, 7]),
            (
                Source::of(&int32),
                [-3i32, 5, 1 << 30]
                    .iter()
                    .flat_map(|x| x.to_le_bytes())
                    .collect(),
            ),
        ];
        for (source, expected) in cases {
            assert_eq!(source.len() * source.value_bytes(), expected.len());
            let mut joined = Vec::new();
            let mut scratch = Vec::new();
            source
                .for_each_chunk(16, &mut scratch, &mut |piece| {
                    assert!(piece.len() <= 16);
                    joined.extend_from_slice(piece);
                    Ok(())
                })
                .unwrap();
            assert_eq!(joined, expected, "{}", source.type_name());
        }
    }

    /// Arrays longer than a zlib block and than a binary piece read back bit for bit.
    #[test]
    fn long_arrays_read_back_in_every_encoding() {
        let n = 40_000;
        let mut cells = Cells::new();
        for p in 0..n {
            cells.push(CellType::Vertex, &[p]);
        }
        let f = |k: usize| ((k as f64) * 0.37).sin() * 1e3 + 1e-300 * k as f64;
        let grid =
            UnstructuredGrid::new((0..n).map(|k| [f(k), f(k + 1), f(k + 2)]).collect(), cells)
                .with_point_data(VtkArray::scalars("a", (0..n).map(f).collect()))
                .with_cell_data(VtkArray::new(
                    "b",
                    1,
                    Values::UInt8((0..n).map(|k| (k % 251) as u8).collect()),
                ));
        for encoding in [
            VtuEncoding::Ascii,
            VtuEncoding::Binary,
            VtuEncoding::Compressed,
        ] {
            let bytes = grid.to_vtu_bytes(encoding).unwrap();
            let back = crate::io::read_vtu_bytes(&bytes, "long.vtu").unwrap();
            assert_eq!(back, grid, "{encoding:?}");
        }
    }
}
