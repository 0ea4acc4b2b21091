//! Polyhedral meshes through VTU and back: every family written as VTK polyhedra in every
//! encoding, read back by this crate's VTU reader, rebuilt as a polyhedral mesh from the face
//! streams, gives the same vertices, cell volumes and point data bit for bit. (VTK's own reader
//! checks the same files: `scripts/check-vtu.sh`.)

use vem_mesh::generators::polyhedral::{Cuboid, PolyhedralFamily};
use vem_mesh::io::{read_vtu, write_polyhedral_vtu_with, Values, VtuData, VtuEncoding};
use vem_mesh::{MeshError, Point3, PolyhedralMesh, Vector3};

#[test]
fn every_family_round_trips_through_vtu() {
    let dir = std::env::temp_dir().join(format!("vem-mesh-vtu-polyhedral-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for family in PolyhedralFamily::all() {
        let mesh = family.generate(&Cuboid::unit_cube(), 3, 2).unwrap();
        let u: Vec<Vector3> = mesh
            .vertices()
            .iter()
            .map(|p| Vector3::new(p.x.sin(), p.y * p.z, -1.0 / 3.0))
            .collect();
        let data = VtuData::new()
            .with_point_vectors_3d("u", &u)
            .with_cell_scalars("cell", (0..mesh.n_cells()).map(|c| c as f64).collect());
        for encoding in [
            VtuEncoding::Ascii,
            VtuEncoding::Binary,
            VtuEncoding::Compressed,
        ] {
            let path = dir.join(format!("{}-{}.vtu", family.name(), encoding.name()));
            write_polyhedral_vtu_with(&path, &mesh, &data, encoding).unwrap();
            let grid = read_vtu(&path).unwrap();
            let points: Vec<Point3> = grid
                .points
                .iter()
                .map(|p| Point3::new(p[0], p[1], p[2]))
                .collect();
            assert_eq!(points, mesh.vertices(), "{}", family.name());
            // The face streams: [faces, (size, points...)...] per cell.
            let mut cells = Vec::new();
            let mut start = 0usize;
            for &end in &grid.cells.face_offsets {
                let stream = &grid.cells.faces[start..end as usize];
                let mut faces = Vec::new();
                let mut k = 1;
                for _ in 0..stream[0] {
                    let size = stream[k];
                    faces.push(stream[k + 1..k + 1 + size].to_vec());
                    k += 1 + size;
                }
                cells.push(faces);
                start = end as usize;
            }
            let back = PolyhedralMesh::from_polyhedra(points, &cells, vec![]).unwrap();
            assert_eq!(back.n_cells(), mesh.n_cells());
            for c in 0..mesh.n_cells() {
                assert_eq!(back.volume(c), mesh.volume(c), "{} cell {c}", family.name());
            }
            let read_u = match &grid.point_data[0].values {
                Values::Float64(v) => v.clone(),
                other => panic!("{other:?}"),
            };
            let written: Vec<f64> = u.iter().flat_map(|v| [v.x, v.y, v.z]).collect();
            assert_eq!(read_u, written);
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn arrays_of_the_wrong_length_name_the_cells() {
    let mesh = PolyhedralFamily::Hexahedra
        .generate(&Cuboid::unit_cube(), 2, 0)
        .unwrap();
    let data = VtuData::new().with_cell_scalars("energy", vec![1.0; 3]);
    let path = std::env::temp_dir().join(format!("vem-mesh-bad-{}.vtu", std::process::id()));
    let err = write_polyhedral_vtu_with(&path, &mesh, &data, VtuEncoding::Ascii).unwrap_err();
    match err {
        MeshError::Write { reason, .. } => {
            assert_eq!(
                reason,
                "cell-data array 'energy' has 3 values, expected 8 (1 per entry for 8 cells)"
            )
        }
        other => panic!("{other}"),
    }
    assert!(!path.exists());
}
