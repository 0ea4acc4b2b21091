//! The 3D Gmsh reader against Gmsh's own: every `.msh` file of `tests/data/gmsh-corpus-3d`
//! (tetrahedra, hexahedra, prisms, pyramids; MSH 4.1 and 2.2, ASCII and binary; tags out of
//! order and with gaps) is read by `read_msh_bytes`, and its nodes, elements and physical groups
//! must be those that Gmsh's Python API reads from the same file (the JSON beside it, written by
//! `scripts/gmsh-reference.py`). Each file must also become a valid polyhedral mesh of the unit
//! cube: volume 1, its parts covering the sides they name with outward normals.

mod common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use common::{gmsh, ours};
use serde_json::Value;
use vem_mesh::io::{read_gmsh_polyhedral_bytes, read_msh_bytes};
use vem_mesh::{PolyhedralMesh, Vector3};

fn corpus() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/gmsh-corpus-3d");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "msh"))
        .collect();
    files.sort();
    files
}

#[test]
fn every_3d_corpus_file_reads_as_gmsh_reads_it() {
    let files = corpus();
    assert!(files.len() >= 12, "{files:?}");
    for file in &files {
        let bytes = std::fs::read(file).unwrap();
        let msh = read_msh_bytes(&bytes).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        let json: Value =
            serde_json::from_str(&std::fs::read_to_string(file.with_extension("json")).unwrap())
                .unwrap();
        let (our_nodes, our_elements, our_groups) = ours(&msh);
        let (nodes, elements, groups) = gmsh(&json);
        let name = file.file_name().unwrap().to_string_lossy();
        assert_eq!(
            our_nodes.keys().collect::<Vec<_>>(),
            nodes.keys().collect::<Vec<_>>(),
            "{name}: node tags"
        );
        for (tag, xyz) in &nodes {
            let ours = our_nodes[tag];
            for k in 0..3 {
                assert!(
                    (ours[k] - xyz[k]).abs() <= 1e-15 * xyz[k].abs().max(1.0),
                    "{name}: node {tag}: {ours:?} != {xyz:?}"
                );
            }
        }
        assert_eq!(our_elements, elements, "{name}: elements");
        assert_eq!(our_groups, groups, "{name}: physical groups");
    }
}

/// The number of cells of each size (vertices), and each part's name and area.
type Shape = (BTreeMap<usize, usize>, Vec<(String, f64)>);

/// The volume, the number of cells of each size (vertices) and each part's name and area.
fn describe(mesh: &PolyhedralMesh) -> (f64, BTreeMap<usize, usize>, Vec<(String, f64)>) {
    let volume = (0..mesh.n_cells()).map(|c| mesh.volume(c)).sum();
    let mut kinds = BTreeMap::new();
    for c in 0..mesh.n_cells() {
        *kinds.entry(mesh.cell_vertices(c).len()).or_insert(0) += 1;
    }
    let parts = mesh
        .parts()
        .iter()
        .map(|p| {
            let area = p.faces.iter().map(|&f| mesh.face_area(f)).sum();
            (p.name.clone(), area)
        })
        .collect();
    (volume, kinds, parts)
}

/// The outward normal of the side named `part` of the unit cube, if it is one side.
fn side_normal(part: &str) -> Option<Vector3> {
    Some(match part {
        "left" | "x = 0" => -Vector3::x(),
        "right" | "x = 1" => Vector3::x(),
        "front" | "y = 0" => -Vector3::y(),
        "back" | "y = 1" => Vector3::y(),
        "bottom" | "z = 0" => -Vector3::z(),
        "top" | "z = 1" => Vector3::z(),
        _ => return None,
    })
}

#[test]
fn every_3d_corpus_file_becomes_a_mesh_of_the_unit_cube() {
    let mut by_model: BTreeMap<String, Shape> = BTreeMap::new();
    for file in corpus() {
        let name = file.file_name().unwrap().to_string_lossy().to_string();
        let mesh = read_gmsh_polyhedral_bytes(&std::fs::read(&file).unwrap(), &name)
            .unwrap_or_else(|e| panic!("{e}"));
        let (volume, kinds, parts) = describe(&mesh);
        assert!((volume - 1.0).abs() < 1e-12, "{name}: volume {volume}");
        assert_eq!(mesh.euler_characteristic(), 1, "{name}");
        // Every side part is flat, outward, and covers its side: area 1; the prisms' groups
        // cover two sides (bottom and top) and four (the sides).
        for part in mesh.parts() {
            if let Some(normal) = side_normal(&part.name) {
                for &f in &part.faces {
                    assert!(
                        (mesh.face_normal(f) - normal).norm() < 1e-12,
                        "{name}: {}",
                        part.name
                    );
                }
            }
        }
        for (part, area) in &parts {
            let expected = match part.as_str() {
                "bottom and top" => 2.0,
                "sides" => 4.0,
                _ => 1.0,
            };
            assert!(
                (area - expected).abs() < 1e-12,
                "{name}: part {part} area {area}"
            );
        }
        // Variants of one model (version, encoding, numbering) give the same mesh.
        let model = name.split('_').take(2).collect::<Vec<_>>().join("_");
        match by_model.get(&model) {
            None => {
                by_model.insert(model, (kinds, parts));
            }
            Some((first_kinds, first_parts)) => {
                assert_eq!(&kinds, first_kinds, "{name}");
                let names: Vec<&String> = parts.iter().map(|p| &p.0).collect();
                let first: Vec<&String> = first_parts.iter().map(|p| &p.0).collect();
                assert_eq!(names, first, "{name}");
            }
        }
    }
    // Each element type is there: tetrahedra (4 vertices), hexahedra (8), prisms (6),
    // pyramids (5).
    assert_eq!(by_model.len(), 4, "{:?}", by_model.keys());
    let hybrid = &by_model["box_hybrid"].0;
    assert!(hybrid.contains_key(&4) && hybrid.contains_key(&5) && hybrid.contains_key(&8));
    assert_eq!(by_model["box_prisms"].0.keys().collect::<Vec<_>>(), [&6]);
    assert_eq!(by_model["box_hexahedra"].0.keys().collect::<Vec<_>>(), [&8]);
}
