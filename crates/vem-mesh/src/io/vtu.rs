//! VTK XML unstructured grid output (`.vtu`, ASCII) for ParaView and VisIt.
//!
//! Points are written with z = 0, every polygon as a VTK polygon cell (type 7) through the
//! connectivity / offsets / types arrays. Values are written with Rust's shortest round-trip
//! formatting (`{:e}`), so reading a file back gives the same `f64` bit for bit.

use std::fmt::Write as _;
use std::io::{self, Write};
use std::path::Path;

use super::{write_atomically, xml_escape};
use crate::{Mesh, MeshError, Vector};

/// VTK's cell type number of a polygon.
const VTK_POLYGON: u8 = 7;

/// A named array of values attached to the points or to the cells of a mesh.
///
/// `values` holds `components` numbers per point (or cell), one point after the other.
/// Two-component arrays (plane vectors such as displacements) are written with a third
/// component 0, so that ParaView can warp the mesh by them.
#[derive(Debug, Clone, PartialEq)]
pub struct DataArray {
    /// The name shown in the viewer.
    pub name: String,
    /// Number of components per point or cell: 1 (scalar), 2 (plane vector) or 3.
    pub components: usize,
    /// The values, `components` per point or cell, interleaved.
    pub values: Vec<f64>,
}

impl DataArray {
    /// An array of `components` values per entry (interleaved).
    pub fn new(name: impl Into<String>, components: usize, values: Vec<f64>) -> Self {
        Self {
            name: name.into(),
            components,
            values,
        }
    }

    /// A scalar array: one value per point or cell.
    pub fn scalars(name: impl Into<String>, values: Vec<f64>) -> Self {
        Self::new(name, 1, values)
    }

    /// A plane vector array: one vector per point or cell.
    pub fn vectors(name: impl Into<String>, values: &[Vector]) -> Self {
        Self::new(name, 2, values.iter().flat_map(|v| [v.x, v.y]).collect())
    }
}

/// The data written with a mesh by [`write_vtu`]: named point-data and cell-data arrays.
///
/// ```
/// use vem_mesh::io::VtuData;
/// use vem_mesh::Vector;
/// let data = VtuData::new()
///     .with_point_vectors("displacement", &[Vector::new(0.0, -1e-3); 4])
///     .with_cell_scalars("von_mises", vec![2.5]);
/// assert_eq!(data.point_data[0].components, 2);
/// ```
#[derive(Debug, Clone, Default, PartialEq)]
pub struct VtuData {
    /// Arrays with one entry per mesh vertex.
    pub point_data: Vec<DataArray>,
    /// Arrays with one entry per polygon.
    pub cell_data: Vec<DataArray>,
}

impl VtuData {
    /// No data: the mesh alone.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a point-data array.
    pub fn with_point_data(mut self, array: DataArray) -> Self {
        self.point_data.push(array);
        self
    }

    /// Adds a cell-data array.
    pub fn with_cell_data(mut self, array: DataArray) -> Self {
        self.cell_data.push(array);
        self
    }

    /// Adds a scalar point-data array (one value per vertex).
    pub fn with_point_scalars(self, name: impl Into<String>, values: Vec<f64>) -> Self {
        self.with_point_data(DataArray::scalars(name, values))
    }

    /// Adds a vector point-data array (one plane vector per vertex).
    pub fn with_point_vectors(self, name: impl Into<String>, values: &[Vector]) -> Self {
        self.with_point_data(DataArray::vectors(name, values))
    }

    /// Adds a scalar cell-data array (one value per polygon).
    pub fn with_cell_scalars(self, name: impl Into<String>, values: Vec<f64>) -> Self {
        self.with_cell_data(DataArray::scalars(name, values))
    }

    /// Adds a vector cell-data array (one plane vector per polygon).
    pub fn with_cell_vectors(self, name: impl Into<String>, values: &[Vector]) -> Self {
        self.with_cell_data(DataArray::vectors(name, values))
    }
}

/// Writes `mesh` and `data` as a VTK XML unstructured grid (`.vtu`, ASCII), atomically.
///
/// Every array is checked before anything is written: 1 to 3 components, one entry per vertex
/// (point data) or per polygon (cell data), finite values, a non-empty name unique within its
/// group. A failed check is [`MeshError::Write`] naming the array.
pub fn write_vtu(path: impl AsRef<Path>, mesh: &Mesh, data: &VtuData) -> Result<(), MeshError> {
    let path = path.as_ref();
    check_arrays("point", &data.point_data, mesh.n_vertices()).map_err(|reason| {
        MeshError::Write {
            path: path.to_path_buf(),
            reason,
        }
    })?;
    check_arrays("cell", &data.cell_data, mesh.n_polygons()).map_err(|reason| {
        MeshError::Write {
            path: path.to_path_buf(),
            reason,
        }
    })?;
    write_atomically(path, |w| write_document(w, mesh, data))
}

/// Checks the arrays of one group ("point" or "cell") against the number of entries.
fn check_arrays(group: &str, arrays: &[DataArray], entries: usize) -> Result<(), String> {
    let what = if group == "point" {
        "vertices"
    } else {
        "polygons"
    };
    for (i, array) in arrays.iter().enumerate() {
        let label = format!("{group}-data array '{}'", array.name);
        if array.name.trim().is_empty() {
            return Err(format!("{group}-data array {i} has an empty name"));
        }
        if arrays[..i].iter().any(|other| other.name == array.name) {
            return Err(format!("{label} is given twice"));
        }
        if !(1..=3).contains(&array.components) {
            return Err(format!(
                "{label} has {} components; 1, 2 or 3 are supported",
                array.components
            ));
        }
        let expected = array.components * entries;
        if array.values.len() != expected {
            return Err(format!(
                "{label} has {} values, expected {expected} ({} per entry for {entries} {what})",
                array.values.len(),
                array.components,
            ));
        }
        if let Some(k) = array.values.iter().position(|v| !v.is_finite()) {
            return Err(format!(
                "{label} has the non-finite value {} at entry {} (component {})",
                array.values[k],
                k / array.components,
                k % array.components
            ));
        }
    }
    Ok(())
}

/// Writes the whole XML document.
fn write_document(w: &mut dyn Write, mesh: &Mesh, data: &VtuData) -> io::Result<()> {
    writeln!(w, "<?xml version=\"1.0\"?>")?;
    writeln!(
        w,
        "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" \
         header_type=\"UInt64\">"
    )?;
    writeln!(w, "  <UnstructuredGrid>")?;
    writeln!(
        w,
        "    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">",
        mesh.n_vertices(),
        mesh.n_polygons()
    )?;
    write_data_group(w, "PointData", &data.point_data)?;
    write_data_group(w, "CellData", &data.cell_data)?;

    writeln!(w, "      <Points>")?;
    writeln!(
        w,
        "        <DataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\" \
         format=\"ascii\">"
    )?;
    for p in mesh.vertices() {
        writeln!(w, "          {:e} {:e} 0e0", p.x, p.y)?;
    }
    writeln!(w, "        </DataArray>")?;
    writeln!(w, "      </Points>")?;

    writeln!(w, "      <Cells>")?;
    writeln!(
        w,
        "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">"
    )?;
    let mut line = String::new();
    for polygon in mesh.polygons() {
        line.clear();
        for v in polygon {
            write!(line, " {v}").expect("writing to a String cannot fail");
        }
        writeln!(w, "         {line}")?;
    }
    writeln!(w, "        </DataArray>")?;
    writeln!(
        w,
        "        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">"
    )?;
    write_rows(w, mesh.polygon_offsets()[1..].iter())?;
    writeln!(w, "        </DataArray>")?;
    writeln!(
        w,
        "        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">"
    )?;
    write_rows(w, std::iter::repeat_n(VTK_POLYGON, mesh.n_polygons()))?;
    writeln!(w, "        </DataArray>")?;
    writeln!(w, "      </Cells>")?;
    writeln!(w, "    </Piece>")?;
    writeln!(w, "  </UnstructuredGrid>")?;
    writeln!(w, "</VTKFile>")
}

/// Writes `<PointData>` or `<CellData>` with its arrays; the first scalar and the first vector
/// array are marked active, so that viewers colour and warp by them without a choice.
fn write_data_group(w: &mut dyn Write, tag: &str, arrays: &[DataArray]) -> io::Result<()> {
    let mut active = String::new();
    if let Some(a) = arrays.iter().find(|a| a.components == 1) {
        write!(active, " Scalars=\"{}\"", xml_escape(&a.name)).expect("String write");
    }
    if let Some(a) = arrays.iter().find(|a| a.components > 1) {
        write!(active, " Vectors=\"{}\"", xml_escape(&a.name)).expect("String write");
    }
    writeln!(w, "      <{tag}{active}>")?;
    for array in arrays {
        let written_components = if array.components == 1 { 1 } else { 3 };
        writeln!(
            w,
            "        <DataArray type=\"Float64\" Name=\"{}\" NumberOfComponents=\"{written_components}\" \
             format=\"ascii\">",
            xml_escape(&array.name)
        )?;
        let mut line = String::new();
        for entry in array.values.chunks(array.components) {
            line.clear();
            for value in entry {
                write!(line, " {value:e}").expect("writing to a String cannot fail");
            }
            if entry.len() == 2 {
                line.push_str(" 0e0");
            }
            writeln!(w, "         {line}")?;
        }
        writeln!(w, "        </DataArray>")?;
    }
    writeln!(w, "      </{tag}>")
}

/// Writes integers, 16 to a line.
fn write_rows<T: std::fmt::Display>(
    w: &mut dyn Write,
    values: impl Iterator<Item = T>,
) -> io::Result<()> {
    let mut line = String::new();
    for (i, value) in values.enumerate() {
        write!(line, " {value}").expect("writing to a String cannot fail");
        if i % 16 == 15 {
            writeln!(w, "         {line}")?;
            line.clear();
        }
    }
    if !line.is_empty() {
        writeln!(w, "         {line}")?;
    }
    Ok(())
}
