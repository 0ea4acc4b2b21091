//! A mesh and its floating-point data as a VTK XML unstructured grid (`.vtu`) for ParaView
//! and VisIt: the simple entry point over [`UnstructuredGrid`](super::UnstructuredGrid).
//!
//! Points are written with z = 0, every polygon as a VTK polygon cell (type 7) through the
//! connectivity / offsets / types arrays; in text, values are written with Rust's shortest
//! round-trip formatting (`{:e}`), so reading a file back gives the same `f64` bit for bit in
//! every encoding.

use std::path::Path;

use super::vtk::{write_document, Column, Document, Source, Values, VtkArray, VtuEncoding};
use super::write_atomically;
use crate::{Mesh, MeshError, Vector};

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

    /// The array as written, borrowed: two components padded to three with zeros.
    fn column(&self) -> Column<'_> {
        let (components, source) = if self.components == 2 {
            (3, Source::Pairs(&self.values))
        } else {
            (self.components, Source::Float64(&self.values))
        };
        Column {
            name: &self.name,
            components,
            source,
        }
    }

    /// The array as written: Float64, two components padded to three with zeros.
    pub fn to_vtk(&self) -> VtkArray {
        if self.components == 2 {
            let values = self
                .values
                .chunks(2)
                .flat_map(|v| [v[0], v.get(1).copied().unwrap_or(0.0), 0.0])
                .collect();
            VtkArray::new(self.name.clone(), 3, Values::Float64(values))
        } else {
            VtkArray::new(
                self.name.clone(),
                self.components,
                Values::Float64(self.values.clone()),
            )
        }
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

/// Writes `mesh` and `data` as a VTK XML unstructured grid (`.vtu`), atomically, in the
/// default encoding: binary ([`VtuEncoding::Binary`], raw appended data), which ParaView and
/// VisIt read fastest, keeps every `f64` bit for bit and takes about a third of the space of
/// text. For text or zlib compression use [`write_vtu_with`].
///
/// Every array is checked before anything is written: 1 to 3 components, one entry per vertex
/// (point data) or per polygon (cell data), finite values, a non-empty name unique within its
/// group. A failed check is [`MeshError::Write`] naming the array.
pub fn write_vtu(path: impl AsRef<Path>, mesh: &Mesh, data: &VtuData) -> Result<(), MeshError> {
    write_vtu_with(path, mesh, data, VtuEncoding::default())
}

/// [`write_vtu`] in a chosen encoding.
pub fn write_vtu_with(
    path: impl AsRef<Path>,
    mesh: &Mesh,
    data: &VtuData,
    encoding: VtuEncoding,
) -> Result<(), MeshError> {
    let path = path.as_ref();
    let fail = |reason| MeshError::Write {
        path: path.to_path_buf(),
        reason,
    };
    check_arrays("point", &data.point_data, mesh.n_vertices(), "vertices").map_err(fail)?;
    check_arrays("cell", &data.cell_data, mesh.n_polygons(), "polygons").map_err(fail)?;
    // The mesh and the arrays go to the file as they are, without a grid of copies (the mesh
    // is valid and the arrays are checked: what `UnstructuredGrid::check` would find holds).
    let mut document = Document::of_mesh(mesh);
    document.point_data = data.point_data.iter().map(DataArray::column).collect();
    document.cell_data = data.cell_data.iter().map(DataArray::column).collect();
    write_atomically(path, |w| write_document(w, &document, encoding))
}

/// Checks the arrays of one group ("point" or "cell") against the number of entries (`what`:
/// "vertices", "polygons", "cells").
pub(super) fn check_arrays(
    group: &str,
    arrays: &[DataArray],
    entries: usize,
    what: &str,
) -> Result<(), String> {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::UnstructuredGrid;
    use crate::Point;

    /// The mesh's own arrays, converted on the way out, give the bytes of the grid that holds
    /// copies of them, in every encoding.
    #[test]
    fn a_mesh_is_written_as_the_grid_of_its_copies() {
        let vertices = vec![
            Point::new(0.0, 0.0),
            Point::new(1.0, 0.0),
            Point::new(2.0, 0.1),
            Point::new(0.0, 1.0),
            Point::new(1.0, 1.0),
            Point::new(2.0, 1.0),
        ];
        let polygons = vec![vec![0, 1, 4, 3], vec![1, 2, 5], vec![1, 5, 4]];
        let mesh = Mesh::from_polygons(vertices, &polygons, Vec::new()).unwrap();
        let data = VtuData::new()
            .with_point_vectors(
                "u",
                &(0..6)
                    .map(|i| Vector::new(i as f64, -0.5 / (1.0 + i as f64)))
                    .collect::<Vec<_>>(),
            )
            .with_point_scalars("p", (0..6).map(|i| 1.0 / (3.0 + i as f64)).collect())
            .with_cell_data(DataArray::new(
                "s",
                3,
                (0..9).map(|i| (i as f64).sqrt()).collect(),
            ))
            .with_cell_scalars("e", vec![1e-300, -2.5, 7.0]);
        let mut grid = UnstructuredGrid::from_mesh(&mesh);
        grid.point_data = data.point_data.iter().map(DataArray::to_vtk).collect();
        grid.cell_data = data.cell_data.iter().map(DataArray::to_vtk).collect();
        for encoding in [
            VtuEncoding::Ascii,
            VtuEncoding::Binary,
            VtuEncoding::Compressed,
        ] {
            let mut document = Document::of_mesh(&mesh);
            document.point_data = data.point_data.iter().map(DataArray::column).collect();
            document.cell_data = data.cell_data.iter().map(DataArray::column).collect();
            let mut direct = Vec::new();
            write_document(&mut direct, &document, encoding).unwrap();
            assert_eq!(direct, grid.to_vtu_bytes(encoding).unwrap(), "{encoding:?}");
        }
    }
}
