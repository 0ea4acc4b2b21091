//! VTK files written and read back: every encoding (ASCII, binary appended raw, zlib), every
//! array type and layout, line, polygon and polyhedron cells, `.pvd` collections; polygonal
//! meshes with boundary parts from `.vtu` and legacy `.vtk` files (committed fixtures, among
//! them files written by meshio and compared with meshio's own reading), and truncated or
//! mutated files, which must give located errors and never a panic.

use std::path::{Path, PathBuf};

use vem_mesh::generators::{structured_triangles, voronoi, Rectangle};
use vem_mesh::io::{
    mesh_from_grid, read_legacy_vtk_bytes, read_vtk_mesh, read_vtu, read_vtu_bytes, write_vtu,
    write_vtu_with, CellType, DataArray, GridMeshOptions, PvdCollection, UnstructuredGrid, Values,
    VtkArray, VtuData, VtuEncoding,
};
use vem_mesh::{MeshError, Point, Vector};

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
        VtkArray::new(
            "status",
            1,
            Values::UInt8((0..points).map(|k| (k % 3) as u8).collect()),
        ),
        VtkArray::new(
            "ids",
            1,
            Values::Int64((0..points).map(|k| (k as i64 - 5) << 40).collect()),
        ),
    ];
    grid.cell_data = vec![
        VtkArray::symmetric_tensors_2d(
            "stress",
            &(0..cells)
                .map(|k| [f(k), f(k + 1), -f(k + 2)])
                .collect::<Vec<_>>(),
        ),
        VtkArray::tensors(
            "gradient",
            &(0..cells).map(|k| [f(k); 9]).collect::<Vec<_>>(),
        ),
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

#[test]
fn write_vtu_writes_binary_by_default_and_reads_back() {
    let mesh = voronoi(&Rectangle::unit_square(), 5, 3).unwrap();
    let u: Vec<Vector> = mesh
        .vertices()
        .iter()
        .map(|p| Vector::new(p.y, -p.x))
        .collect();
    let data = VtuData::new()
        .with_point_vectors("u", &u)
        .with_cell_data(DataArray::new(
            "stress",
            3,
            vec![0.5; 3 * mesh.n_polygons()],
        ));
    let dir = scratch("default");
    let path = dir.join("mesh.vtu");
    write_vtu(&path, &mesh, &data).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    assert!(bytes
        .windows(23)
        .any(|w| w == b"<AppendedData encoding=".as_slice()));
    let grid = read_vtu(&path).unwrap();
    assert_eq!(grid.point_data[0].components, 3);
    let padded: Vec<f64> = u.iter().flat_map(|v| [v.x, v.y, 0.0]).collect();
    assert_eq!(grid.point_data[0].values, Values::Float64(padded));
    // The mesh comes back as it was.
    let back = mesh_from_grid(&grid, &GridMeshOptions::default()).unwrap();
    assert_eq!(back.vertices(), mesh.vertices());
    assert_eq!(back.polygon_vertex_indices(), mesh.polygon_vertex_indices());
    for encoding in ENCODINGS {
        write_vtu_with(&path, &mesh, &data, encoding).unwrap();
        assert_eq!(read_vtu(&path).unwrap(), grid, "{encoding:?}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_mesh_with_parts_survives_a_vtu_of_line_cells() {
    let mesh = voronoi(&Rectangle::unit_square(), 6, 11).unwrap();
    // The mesh's parts as line cells numbered 1, 2, ... by a "part" array.
    let mut grid = UnstructuredGrid::from_mesh(&mesh);
    let mut part = vec![0; mesh.n_polygons()];
    let mut names = std::collections::BTreeMap::new();
    for (k, p) in mesh.parts().iter().enumerate() {
        names.insert(k as i64 + 1, p.name.clone());
        for &e in &p.edges {
            let [a, b] = mesh.edge(e).vertices;
            grid.cells.push(CellType::Line, &[a, b]);
            part.push(k as i32 + 1);
        }
    }
    grid.cell_data.push(VtkArray::int32("part", part));
    let options = GridMeshOptions {
        part_names: names,
        ..GridMeshOptions::default()
    };
    for encoding in ENCODINGS {
        let bytes = grid.to_vtu_bytes(encoding).unwrap();
        let read = read_vtu_bytes(&bytes, "parts.vtu").unwrap();
        let back = mesh_from_grid(&read, &options).unwrap();
        assert_eq!(back.part_names(), mesh.part_names());
        assert_eq!(back.part_specs(), mesh.part_specs(), "{encoding:?}");
        assert_eq!(back, mesh);
    }
}

#[test]
fn the_hand_written_fixture_has_its_named_parts() {
    let mesh = read_vtk_mesh(data("two_squares_parts.vtu")).unwrap();
    assert_eq!(mesh.n_polygons(), 2);
    assert!((0..2).all(|p| (mesh.area(p) - 1.0).abs() < 1e-15));
    assert_eq!(mesh.part_names(), ["bottom", "top"]);
    let length = |name: &str| -> f64 {
        let part = mesh.part(name).unwrap();
        part.edges
            .iter()
            .map(|&e| {
                let [a, b] = mesh.edge(e).vertices;
                (mesh.vertex(a) - mesh.vertex(b)).norm()
            })
            .sum()
    };
    assert_eq!((length("bottom"), length("top")), (2.0, 2.0));
    for v in mesh.part_vertices("top").unwrap() {
        assert_eq!(mesh.vertex(v).y, 1.0);
    }
}

#[test]
fn legacy_polydata_reads_polygons_lines_and_data() {
    let bytes = std::fs::read(data("polydata.vtk")).unwrap();
    let grid = read_legacy_vtk_bytes(&bytes, "polydata.vtk").unwrap();
    // Cells in POLYDATA order: the line first, then the polygons.
    let types: Vec<CellType> = grid.cells.types.clone();
    assert_eq!(
        types,
        [
            CellType::PolyLine,
            CellType::Polygon,
            CellType::Polygon,
            CellType::Polygon
        ]
    );
    assert_eq!(grid.point_data[0].name, "u");
    let mesh = mesh_from_grid(&grid, &GridMeshOptions::default()).unwrap();
    let area: f64 = (0..mesh.n_polygons()).map(|p| mesh.area(p)).sum();
    assert!((area - 2.0).abs() < 1e-12);
    assert_eq!(mesh.part_names(), ["4"]);
    assert_eq!(mesh.part("4").unwrap().edges.len(), 2);
}

/// What meshio reads from each of its fixtures (JSON beside them, scripts/vtk-fixtures.py):
/// the same points, cells (meshio's types), part numbers and point data.
#[test]
fn meshio_fixtures_read_as_meshio_reads_them() {
    let names = [
        "meshio-ascii.vtu",
        "meshio-zlib.vtu",
        "meshio-base64.vtu",
        "meshio-ascii-51.vtk",
        "meshio-binary-51.vtk",
        "meshio-ascii-42.vtk",
    ];
    let meshio_type = |t: CellType| match t {
        CellType::Line => "line",
        CellType::Triangle => "triangle",
        CellType::Quad => "quad",
        CellType::Polygon => "polygon",
        other => panic!("{other:?}"),
    };
    for name in names {
        let path = data(name);
        let bytes = std::fs::read(&path).unwrap();
        let grid = if name.ends_with(".vtk") {
            read_legacy_vtk_bytes(&bytes, name)
        } else {
            read_vtu_bytes(&bytes, name)
        }
        .unwrap_or_else(|e| panic!("{e}"));
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(data(&format!("{name}.json"))).unwrap())
                .unwrap();
        let points: Vec<[f64; 3]> = json["points"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| [0, 1, 2].map(|k| p[k].as_f64().unwrap()))
            .collect();
        assert_eq!(grid.points, points, "{name}");
        let cells: Vec<(String, Vec<usize>)> = json["cells"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| {
                let points = c[1].as_array().unwrap().iter();
                (
                    c[0].as_str().unwrap().to_string(),
                    points.map(|p| p.as_u64().unwrap() as usize).collect(),
                )
            })
            .collect();
        let ours: Vec<(String, Vec<usize>)> = (0..grid.cells.len())
            .map(|c| {
                (
                    meshio_type(grid.cells.types[c]).to_string(),
                    grid.cells.cell(c).to_vec(),
                )
            })
            .collect();
        assert_eq!(ours, cells, "{name}");
        let physical = grid
            .cell_data
            .iter()
            .find(|a| a.name == "gmsh:physical")
            .unwrap();
        let expected: Vec<i64> = json["gmsh:physical"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_i64().unwrap())
            .collect();
        let got: Vec<i64> = (0..physical.values.len())
            .map(|k| physical.values.get_i64(k).unwrap())
            .collect();
        // meshio does not read the cell data back from format 4.2 files.
        if !expected.is_empty() {
            assert_eq!(got, expected, "{name}");
        }
        let temperature = grid
            .point_data
            .iter()
            .find(|a| a.name == "temperature")
            .unwrap();
        let expected: Vec<f64> = json["temperature"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_f64().unwrap())
            .collect();
        assert_eq!(temperature.values, Values::Float64(expected), "{name}");

        // As a mesh: the unit square with its hanging node, parts 1, 2, 3 by length.
        let mesh = mesh_from_grid(&grid, &GridMeshOptions::default()).unwrap();
        assert_eq!(mesh.n_polygons(), 5, "{name}");
        assert!(
            (0..5).all(|p| mesh.area(p) > 0.0),
            "{name}: counter-clockwise"
        );
        let area: f64 = (0..5).map(|p| mesh.area(p)).sum();
        assert!((area - 1.0).abs() < 1e-15, "{name}: {area}");
        assert_eq!(mesh.part_names(), ["1", "2", "3"], "{name}");
        let lengths: Vec<f64> = mesh
            .parts()
            .iter()
            .map(|part| {
                part.edges
                    .iter()
                    .map(|&e| {
                        let [a, b] = mesh.edge(e).vertices;
                        (mesh.vertex(a) - mesh.vertex(b)).norm()
                    })
                    .sum()
            })
            .collect();
        for (length, expected) in lengths.iter().zip([1.0, 2.0, 1.0]) {
            assert!((length - expected).abs() < 1e-15, "{name}: {lengths:?}");
        }
    }
}

#[test]
fn pvd_collections_name_their_datasets() {
    let dir = scratch("pvd");
    let mut pvd = PvdCollection::new();
    pvd.add(0.5, 0, "upper <body>", "a/upper-0.vtu")
        .add(0.5, 1, "interface", "interface-0.vtu")
        .add(1.0, 0, "upper <body>", "a/upper-1.vtu");
    pvd.write(dir.join("run.pvd")).unwrap();
    let text = std::fs::read_to_string(dir.join("run.pvd")).unwrap();
    let document = roxmltree::Document::parse(&text).unwrap();
    let datasets: Vec<(f64, usize, &str, &str)> = document
        .descendants()
        .filter(|n| n.has_tag_name("DataSet"))
        .map(|n| {
            (
                n.attribute("timestep").unwrap().parse().unwrap(),
                n.attribute("part").unwrap().parse().unwrap(),
                n.attribute("name").unwrap(),
                n.attribute("file").unwrap(),
            )
        })
        .collect();
    assert_eq!(
        datasets,
        [
            (0.5, 0, "upper <body>", "a/upper-0.vtu"),
            (0.5, 1, "interface", "interface-0.vtu"),
            (1.0, 0, "upper <body>", "a/upper-1.vtu")
        ]
    );
    let mut bad = PvdCollection::new();
    bad.add(f64::NAN, 0, "x", "x.vtu");
    let err = bad.write(dir.join("bad.pvd")).unwrap_err();
    assert!(
        err.to_string()
            .contains("dataset 0 ('x.vtu') has the time step NaN"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Every defect is an error naming where it is.
#[test]
fn defects_are_located() {
    let reason = |bytes: &[u8], vtk: bool| -> String {
        let result = if vtk {
            read_legacy_vtk_bytes(bytes, "bad")
        } else {
            read_vtu_bytes(bytes, "bad")
        };
        match result.unwrap_err() {
            MeshError::Read { reason, .. } => reason,
            other => panic!("{other}"),
        }
    };
    let fixture = std::fs::read_to_string(data("two_squares_parts.vtu")).unwrap();
    let broken = fixture.replace("0 1 4 3  1 4 5 2", "0 1 4 3  1 4 5 99");
    assert_eq!(
        reason(broken.as_bytes(), false),
        "connectivity entry 7 refers to point 99, but there are 6 points"
    );
    let broken = fixture.replace("0 0 7 9 9", "0 0 7 x 9");
    assert!(
        reason(broken.as_bytes(), false)
            .starts_with("array 'part' (line 23): value 3 is 'x', not a number of the type"),
        "{}",
        reason(broken.as_bytes(), false)
    );
    let broken = fixture.replace("</Cells>", "");
    assert!(
        reason(broken.as_bytes(), false).starts_with("line "),
        "{}",
        reason(broken.as_bytes(), false)
    );
    let legacy = std::fs::read_to_string(data("polydata.vtk")).unwrap();
    let broken = legacy.replace("3 1 2 5", "3 1 2 x");
    assert_eq!(
        reason(broken.as_bytes(), true),
        "line 13: the cell list: value 8 is 'x', not a number of type int"
    );
    // A line along the edge the two squares share is no boundary edge.
    let grid = read_vtu_bytes(fixture.replace("3 4  4 5<", "1 4  4 5<").as_bytes(), "x").unwrap();
    let err = mesh_from_grid(&grid, &GridMeshOptions::default()).unwrap_err();
    assert!(
        err.starts_with("the mesh it describes is invalid: boundary part 'top' names edge (1, 4), which is interior"),
        "{err}"
    );
}

/// Random truncations and byte mutations of every fixture, and of files of every encoding,
/// give errors (or a valid grid), never a panic.
#[test]
fn truncated_and_mutated_files_give_errors_not_panics() {
    let mut inputs: Vec<(String, Vec<u8>)> = Vec::new();
    for entry in std::fs::read_dir(data("")).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        if name.ends_with(".vtu") || name.ends_with(".vtk") {
            inputs.push((name, std::fs::read(&path).unwrap()));
        }
    }
    let grid = everything();
    for encoding in ENCODINGS {
        inputs.push((
            format!("everything.{}.vtu", encoding.name()),
            grid.to_vtu_bytes(encoding).unwrap(),
        ));
    }
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    let mut random = |n: usize| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state % n.max(1) as u64) as usize
    };
    let mut errors = 0;
    for (name, bytes) in &inputs {
        let vtk = name.ends_with(".vtk");
        let read = |b: &[u8]| {
            let grid = if vtk {
                read_legacy_vtk_bytes(b, "fuzz")
            } else {
                read_vtu_bytes(b, "fuzz")
            };
            if let Ok(grid) = grid {
                let _ = mesh_from_grid(&grid, &GridMeshOptions::default());
                false
            } else {
                true
            }
        };
        for _ in 0..60 {
            let cut = random(bytes.len());
            errors += usize::from(read(&bytes[..cut]));
            let mut mutated = bytes.clone();
            for _ in 0..1 + random(4) {
                let at = random(mutated.len());
                mutated[at] = match random(4) {
                    0 => b'9',
                    1 => b'-',
                    2 => random(256) as u8,
                    _ => b' ',
                };
            }
            errors += usize::from(read(&mutated));
        }
    }
    // Most damaged files are refused (some mutations hit comments or values).
    assert!(errors > inputs.len() * 40, "{errors} errors");
}
