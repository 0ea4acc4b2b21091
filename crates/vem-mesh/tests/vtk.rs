//! VTK files written and read back: every encoding (ASCII, binary appended raw, zlib), every
//! array type and layout, line, polygon and polyhedron cells, `.pvd` collections; polygonal
//! meshes with boundary parts from `.vtu` and legacy `.vtk` files (committed fixtures, among
//! them files written by meshio and compared with meshio's own reading), and truncated or
//! mutated files, which must give located errors and never a panic.

use std::path::{Path, PathBuf};

use vem_mesh::generators::{structured_triangles, voronoi, Rectangle};
use vem_mesh::io::{
    mesh_from_grid, read_legacy_vtk_bytes, read_vtk_mesh, read_vtu, read_vtu_bytes, write_vtu,
    write_vtu_with, CellType, Cells, DataArray, GridMeshOptions, PvdCollection,
    UnstructuredGrid, Values, VtkArray, VtuData, VtuEncoding,
};
use vem_mesh::{Mesh, MeshError, Point, Vector};

const ENCODINGS: [VtuEncoding; 3] = [
    VtuEncoding::Ascii,
    VtuEncoding::Binary,
    VtuEncoding::Compressed,
];

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/vtk")
        .join(name)
}

/// A fresh scratch directory for one test.
fn scratch(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("vem-mesh-vtk-{test}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A grid with every kind of cell and array: the polygons of a mesh, a poly-line and a line
/// along its bottom, a tetrahedron and a polyhedron (a unit cube by its six faces) above it.
fn everything() -> UnstructuredGrid {
    let rect = Rectangle::new(Point::new(-0.3, 0.1), Point::new(1.0 / 3.0, 2.7));
    let mesh = structured_triangles(&rect, 3, 2).unwrap();
    let mut grid = UnstructuredGrid::from_mesh(&mesh);
    let n = grid.points.len();
    // Cube corners 0..8 after the mesh's points.
    for k in 0..8 {
        grid.points.push([
            (k & 1) as f64,
            ((k >> 1) & 1) as f64,
            1.0 + ((k >> 2) & 1) as f64 + 1e-17 * k as f64,
        ]);
    }
    let c = |k: usize| n + k;
    grid.cells.push(CellType::PolyLine, &[0, 1, 2, 3]);
    grid.cells.push(CellType::Line, &[1, 2]);
    grid.cells.push(CellType::Tetra, &[c(0), c(1), c(2), c(4)]);
    let faces: [Vec<usize>; 6] = [
        vec![c(0), c(2), c(3), c(1)],
        vec![c(4), c(5), c(7), c(6)],
        vec![c(0), c(1), c(5), c(4)],
        vec![c(2), c(6), c(7), c(3)],
        vec![c(0), c(4), c(6), c(2)],
        vec![c(1), c(3), c(7), c(5)],
    ];
    let faces: Vec<&[usize]> = faces.iter().map(|f| f.as_slice()).collect();
    grid.cells.push_polyhedron(&faces);
    grid.cells.push(CellType::Vertex, &[c(7)]);
    let points = grid.points.len();
    let cells = grid.cells.len();
    let f = |k: usize| ((k as f64) * 0.37).sin() / 7.0 + 1e-300 * k as f64;
    grid.point_data = vec![
        VtkArray::scalars("pressure <p>", (0..points).map(f).collect()),
        VtkArray::vectors_2d(
            "displacement",
            &(0..points)
                .map(|k| Vector::new(f(k), -std::f64::consts::PI * f(k + 1)))
                .collect::<Vec<_>>(),
        ),
        VtkArray::new("status", 1, Values::UInt8((0..points).map(|k| (k % 3) as u8).collect())),
        VtkArray::new(
            "ids",
            1,
            Values::Int64((0..points).map(|k| (k as i64 - 5) << 40).collect()),
        ),
    ];
    grid.cell_data = vec![
        VtkArray::symmetric_tensors_2d(
            "stress",
            &(0..cells).map(|k| [f(k), f(k + 1), -f(k + 2)]).collect::<Vec<_>>(),
        ),
        VtkArray::tensors("gradient", &(0..cells).map(|k| [f(k); 9]).collect::<Vec<_>>()),
        VtkArray::int32("part", (0..cells).map(|k| k as i32 - 3).collect()),
        VtkArray::new("seven", 7, Values::Float64((0..7 * cells).map(f).collect())),
    ];
    grid.field_data = vec![VtkArray::new("time", 1, Values::Float64(vec![0.25]))];
    grid
}

#[test]
fn every_encoding_reads_back_bit_for_bit() {
    let grid = everything();
    let dir = scratch("round-trip");
    let mut sizes = Vec::new();
    for encoding in ENCODINGS {
        let path = dir.join(format!("everything-{}.vtu", encoding.name()));
        grid.write(&path, encoding).unwrap();
        let back = read_vtu(&path).unwrap_or_else(|e| panic!("{encoding:?}: {e}"));
        assert_eq!(back, grid, "{encoding:?}");
        sizes.push(std::fs::metadata(&path).unwrap().len());
        let bytes = grid.to_vtu_bytes(encoding).unwrap();
        assert_eq!(bytes, std::fs::read(&path).unwrap());
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
