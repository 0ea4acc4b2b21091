//! A polyhedral mesh and its data as a VTK XML unstructured grid: every cell a VTK polyhedron
//! (type 42) given by its faces, oriented outward, as ParaView (5.0 and later) and VTK's XML
//! reader read them.

use std::path::Path;

use super::vtk::{CellType, Cells, UnstructuredGrid, VtuEncoding};
use super::vtu::{check_arrays, DataArray, VtuData};
use crate::{MeshError, PolyhedralMesh, Vector3};

impl Cells {
    /// The cells of `mesh` as VTK polyhedra (type 42): for each, its distinct vertices in order
    /// of first appearance in its faces, and its faces as vertex loops oriented outward
    /// ([`PolyhedralMesh::cell_face_loops`]).
    pub fn polyhedra_of(mesh: &PolyhedralMesh) -> Self {
        let mut cells = Cells::new();
        for c in 0..mesh.n_cells() {
            let loops = mesh.cell_face_loops(c);
            let faces: Vec<&[usize]> = loops.iter().map(Vec::as_slice).collect();
            cells.push_polyhedron(&faces);
        }
        cells
    }
}

impl UnstructuredGrid {
    /// The grid of a polyhedral mesh: its vertices and its cells as VTK polyhedra, without
    /// data.
    ///
    /// ```
    /// # #[cfg(feature = "generators")] {
    /// use vem_mesh::generators::polyhedral::{hexahedra, Cuboid};
    /// use vem_mesh::io::{CellType, UnstructuredGrid};
    /// let mesh = hexahedra(&Cuboid::unit_cube(), 2, 2, 2)?;
    /// let grid = UnstructuredGrid::from_polyhedral_mesh(&mesh);
    /// assert_eq!(grid.points.len(), 27);
    /// assert!(grid.cells.types.iter().all(|&t| t == CellType::Polyhedron));
    /// // A hexahedron: 6 faces of 4 points, after the face count: 1 + 6 * 5 entries.
    /// assert_eq!(grid.cells.face_offsets[0], 31);
    /// # }
    /// # Ok::<(), vem_mesh::MeshError>(())
    /// ```
    pub fn from_polyhedral_mesh(mesh: &PolyhedralMesh) -> Self {
        let points = mesh.vertices().iter().map(|p| [p.x, p.y, p.z]).collect();
        Self::new(points, Cells::polyhedra_of(mesh))
    }
}

impl DataArray {
    /// A vector array in space: one vector per point or cell.
    pub fn vectors_3d(name: impl Into<String>, values: &[Vector3]) -> Self {
        Self::new(
            name,
            3,
            values.iter().flat_map(|v| [v.x, v.y, v.z]).collect(),
        )
    }
}

impl VtuData {
    /// Adds a vector point-data array in space (one vector per vertex).
    pub fn with_point_vectors_3d(self, name: impl Into<String>, values: &[Vector3]) -> Self {
        self.with_point_data(DataArray::vectors_3d(name, values))
    }
}

/// Writes the polyhedral mesh `mesh` and `data` (one entry per vertex or per cell) as a VTK
/// XML unstructured grid of polyhedra, atomically, in the default binary encoding; the arrays
/// are checked as by [`super::write_vtu`].
pub fn write_polyhedral_vtu(
    path: impl AsRef<Path>,
    mesh: &PolyhedralMesh,
    data: &VtuData,
) -> Result<(), MeshError> {
    write_polyhedral_vtu_with(path, mesh, data, VtuEncoding::default())
}

/// [`write_polyhedral_vtu`] in a chosen encoding.
pub fn write_polyhedral_vtu_with(
    path: impl AsRef<Path>,
    mesh: &PolyhedralMesh,
    data: &VtuData,
    encoding: VtuEncoding,
) -> Result<(), MeshError> {
    let path = path.as_ref();
    let fail = |reason| MeshError::Write {
        path: path.to_path_buf(),
        reason,
    };
    check_arrays("point", &data.point_data, mesh.n_vertices(), "vertices").map_err(fail)?;
    check_arrays("cell", &data.cell_data, mesh.n_cells(), "cells").map_err(fail)?;
    let mut grid = UnstructuredGrid::from_polyhedral_mesh(mesh);
    grid.point_data = data.point_data.iter().map(DataArray::to_vtk).collect();
    grid.cell_data = data.cell_data.iter().map(DataArray::to_vtk).collect();
    debug_assert!(grid.cells.types.iter().all(|&t| t == CellType::Polyhedron));
    grid.write(path, encoding)
}
