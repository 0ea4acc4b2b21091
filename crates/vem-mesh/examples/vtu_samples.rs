//! Writes `.vtu` files in every encoding with a JSON description beside each (points, cells,
//! arrays with their types), and a `.pvd` collection of them, for `scripts/check-vtu.py` to read
//! with meshio and with VTK's own XML reader and compare:
//!
//! ```text
//! cargo run --release -p vem-mesh --example vtu_samples -- target/vtu-check
//! target/vtu-check-venv/bin/python scripts/check-vtu.py target/vtu-check
//! ```
//!
//! Samples: a Voronoi mesh with scalar, vector, symmetric-tensor, Int32 and UInt8 data (as
//! `UnstructuredGrid` and through `write_vtu`); a contact interface of line cells; and a grid
//! with poly-lines, a tetrahedron, a polyhedron and a vertex (which meshio does not read: the
//! JSON says so, and only VTK checks it); polyhedral meshes (3D Voronoi cells, octree cubes with
//! hanging nodes) as grids of VTK polyhedra with point vectors and cell tensors, and through
//! `write_polyhedral_vtu_with` (VTK only).

use std::path::PathBuf;

use serde_json::{json, Value};
use vem_mesh::generators::polyhedral::{octree_hexahedra, voronoi_polyhedra, Cuboid};
use vem_mesh::generators::{voronoi, Rectangle};
use vem_mesh::io::{
    write_polyhedral_vtu_with, write_vtu_with, CellType, Cells, PvdCollection, UnstructuredGrid,
    Values, VtkArray, VtuData, VtuEncoding,
};
use vem_mesh::{Vector, Vector3};

fn values_json(values: &Values) -> (&'static str, Value) {
    match values {
        Values::Float64(v) => ("Float64", json!(v)),
        Values::Int32(v) => ("Int32", json!(v)),
        Values::Int64(v) => ("Int64", json!(v)),
        Values::UInt8(v) => ("UInt8", json!(v)),
        _ => ("unknown", Value::Null),
    }
}

fn arrays_json(arrays: &[VtkArray]) -> Value {
    Value::Array(
        arrays
            .iter()
            .map(|a| {
                let (type_name, values) = values_json(&a.values);
                json!({"name": a.name, "type": type_name, "components": a.components, "values": values})
            })
            .collect(),
    )
}

fn describe(grid: &UnstructuredGrid, meshio: bool) -> Value {
    let cells = &grid.cells;
    json!({
        "meshio": meshio,
        "points": grid.points,
        "connectivity": cells.connectivity,
        "offsets": cells.offsets,
        "types": cells.types.iter().map(|t| t.vtk_id()).collect::<Vec<_>>(),
        "faces": cells.faces,
        "face_offsets": cells.face_offsets,
        "point_data": arrays_json(&grid.point_data),
        "cell_data": arrays_json(&grid.cell_data),
    })
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir: PathBuf = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "target/vtu-check".into())
        .into();
    std::fs::create_dir_all(&dir)?;

    let mesh = voronoi(&Rectangle::unit_square(), 12, 7)?;
    let f = |k: usize| ((k as f64) * 0.731).sin() * 1e3 + 1.0 / 3.0;
    let n = mesh.n_vertices();
    let m = mesh.n_polygons();
    let body = UnstructuredGrid::from_mesh(&mesh)
        .with_point_data(VtkArray::vectors_2d(
            "displacement",
            &(0..n)
                .map(|k| Vector::new(f(k), -f(k + 1) * 1e-9))
                .collect::<Vec<_>>(),
        ))
        .with_point_data(VtkArray::scalars("temperature", (0..n).map(f).collect()))
        .with_cell_data(VtkArray::symmetric_tensors_2d(
            "stress",
            &(0..m)
                .map(|k| [f(k), f(k + 7), f(k + 9)])
                .collect::<Vec<_>>(),
        ))
        .with_cell_data(VtkArray::int32("body", vec![1; m]))
        .with_cell_data(VtkArray::uint8(
            "status",
            (0..m).map(|k| (k % 4) as u8).collect(),
        ));

    // The bottom of the mesh as a contact interface of line cells.
    let bottom = mesh.part("bottom")?;
    let mut lines = Cells::new();
    let mut points = Vec::new();
    for &e in &bottom.edges {
        let [a, b] = mesh.edge(e).vertices;
        let first = points.len();
        for v in [a, b] {
            let p = mesh.vertex(v);
            points.push([p.x, p.y, 0.0]);
        }
        lines.push(CellType::Line, &[first, first + 1]);
    }
    let k = points.len();
    let interface = UnstructuredGrid::new(points, lines)
        .with_point_data(VtkArray::scalars("pressure", (0..k).map(f).collect()))
        .with_cell_data(VtkArray::int32("part", vec![7; bottom.edges.len()]));

    // Cells meshio does not read.
    let mut cells = Cells::new();
    cells.push(CellType::PolyLine, &[0, 1, 2, 3]);
    cells.push(CellType::Tetra, &[0, 1, 2, 4]);
    let cube: [&[usize]; 6] = [
        &[0, 2, 3, 1],
        &[4, 5, 7, 6],
        &[0, 1, 5, 4],
        &[2, 6, 7, 3],
        &[0, 4, 6, 2],
        &[1, 3, 7, 5],
    ];
    cells.push_polyhedron(&cube);
    cells.push(CellType::Vertex, &[7]);
    let corners: Vec<[f64; 3]> = (0..8)
        .map(|k| [(k & 1) as f64, ((k >> 1) & 1) as f64, ((k >> 2) & 1) as f64])
        .collect();
    let solids = UnstructuredGrid::new(corners, cells)
        .with_point_data(VtkArray::new(
            "ids",
            1,
            Values::Int64((0..8).map(|k| k << 35).collect()),
        ))
        .with_cell_data(VtkArray::tensors(
            "gradient",
            &[[0.5; 9], [1.5; 9], [2.5; 9], [3.5; 9]],
        ));

    // Polyhedral meshes: Voronoi cells (faces of many sizes) and octree cubes (coplanar faces,
    // hanging nodes), every cell a VTK polyhedron.
    let cells3d = voronoi_polyhedra(&Cuboid::unit_cube(), 3, 5)?;
    let (n3, m3) = (cells3d.n_vertices(), cells3d.n_cells());
    let polyhedra = UnstructuredGrid::from_polyhedral_mesh(&cells3d)
        .with_point_data(VtkArray::vectors(
            "displacement",
            &(0..n3)
                .map(|k| [f(k), -f(k + 1), f(k + 2) * 1e-7])
                .collect::<Vec<_>>(),
        ))
        .with_cell_data(VtkArray::symmetric_tensors(
            "stress",
            &(0..m3)
                .map(|k| [f(k), f(k + 1), f(k + 2), f(k + 3), f(k + 4), f(k + 5)])
                .collect::<Vec<_>>(),
        ));
    let octree = octree_hexahedra(&Cuboid::unit_cube(), 2)?;

    let mut pvd = PvdCollection::new();
    for encoding in [
        VtuEncoding::Ascii,
        VtuEncoding::Binary,
        VtuEncoding::Compressed,
    ] {
        let tag = encoding.name();
        for (name, grid, meshio) in [
            ("body", &body, true),
            ("interface", &interface, true),
            ("solids", &solids, false),
            ("polyhedra", &polyhedra, false),
        ] {
            let file = format!("{name}-{tag}.vtu");
            grid.write(dir.join(&file), encoding)?;
            let mut description = describe(grid, meshio);
            if name == "polyhedra" {
                // The polyhedra fill the unit cube: VTK's own volumes must add up to 1, to the
                // few per mille by which VTK's triangulation of the slightly warped faces of
                // merged Voronoi vertices differs from the fans (the octree below, with planar
                // faces, to round-off).
                description["volume"] = json!(1.0);
                description["volume_tolerance"] = json!(1e-2);
            }
            std::fs::write(
                dir.join(format!("{name}-{tag}.json")),
                serde_json::to_string(&description)?,
            )?;
            pvd.add(pvd.datasets().len() as f64, 0, name, file);
        }
        // The simple entry point: a mesh and its floating-point data.
        let data = VtuData::new()
            .with_point_vectors(
                "u",
                &(0..n)
                    .map(|k| Vector::new(f(k), f(k + 2)))
                    .collect::<Vec<_>>(),
            )
            .with_cell_scalars("energy", (0..m).map(f).collect());
        // The simple entry point of polyhedral meshes.
        let data3d = VtuData::new()
            .with_point_vectors_3d(
                "u",
                &(0..octree.n_vertices())
                    .map(|k| Vector3::new(f(k), f(k + 1), -f(k + 2)))
                    .collect::<Vec<_>>(),
            )
            .with_cell_scalars("energy", (0..octree.n_cells()).map(f).collect());
        let file = format!("octree-{tag}.vtu");
        write_polyhedral_vtu_with(dir.join(&file), &octree, &data3d, encoding)?;
        let mut grid = UnstructuredGrid::from_polyhedral_mesh(&octree);
        grid.point_data = data3d.point_data.iter().map(|a| a.to_vtk()).collect();
        grid.cell_data = data3d.cell_data.iter().map(|a| a.to_vtk()).collect();
        let mut description = describe(&grid, false);
        description["volume"] = json!(1.0);
        std::fs::write(
            dir.join(format!("octree-{tag}.json")),
            serde_json::to_string(&description)?,
        )?;
        pvd.add(pvd.datasets().len() as f64, 0, "octree", file);

        let file = format!("mesh-{tag}.vtu");
        write_vtu_with(dir.join(&file), &mesh, &data, encoding)?;
        let mut grid = UnstructuredGrid::from_mesh(&mesh);
        grid.point_data = data.point_data.iter().map(|a| a.to_vtk()).collect();
        grid.cell_data = data.cell_data.iter().map(|a| a.to_vtk()).collect();
        std::fs::write(
            dir.join(format!("mesh-{tag}.json")),
            serde_json::to_string(&describe(&grid, true))?,
        )?;
    }
    pvd.write(dir.join("samples.pvd"))?;
    println!(
        "vtu_samples: wrote {} files and samples.pvd in {}",
        pvd.datasets().len() + 3,
        dir.display()
    );
    Ok(())
}
