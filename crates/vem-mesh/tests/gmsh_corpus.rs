//! The Gmsh reader against Gmsh's own: every `.msh` file of `tests/data/gmsh-corpus` (MSH 4.1
//! and 2.2, ASCII and binary, tags out of order and with gaps, blocks in any order, physical
//! names) is read by `read_msh_bytes`, and its nodes, elements and physical groups must be
//! those that Gmsh's Python API reads from the same file, committed beside it as JSON by
//! `scripts/gmsh-reference.py`. Each file must also become a valid mesh.

mod common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use common::{gmsh, ours};
use serde_json::Value;
use vem_mesh::io::{read_gmsh_bytes, read_msh_bytes};

fn corpus() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/gmsh-corpus");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "msh"))
        .collect();
    files.sort();
    files
}

#[test]
fn every_corpus_file_reads_as_gmsh_reads_it() {
    let files = corpus();
    assert!(files.len() >= 18, "{files:?}");
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
                // Both sides parse the same decimal or binary number; allow for a last-digit
                // difference of the JSON float parser.
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

#[test]
fn every_corpus_file_becomes_the_same_mesh_as_its_variants() {
    // The area of the domain and the lengths of the parts do not depend on the version, the
    // encoding or the numbering of a file.
    let mut by_shape: BTreeMap<String, (f64, Vec<(String, f64)>)> = BTreeMap::new();
    for file in corpus() {
        let name = file.file_name().unwrap().to_string_lossy().to_string();
        let mesh = read_gmsh_bytes(&std::fs::read(&file).unwrap(), &name)
            .unwrap_or_else(|e| panic!("{e}"));
        let (area, parts) = common::area_and_part_lengths(&mesh);
        let shape = name.split('_').next().unwrap().to_string();
        let expected_area = match shape.as_str() {
            "square" | "mixed" => 1.0,
            // A polygon inscribed in the unit disc.
            _ => std::f64::consts::PI,
        };
        assert!(
            (area - expected_area).abs() < 0.02 * expected_area,
            "{name}: area {area}"
        );
        match by_shape.get(&shape) {
            None => {
                by_shape.insert(shape, (area, parts));
            }
            Some((first_area, first_parts)) => {
                assert!((area - first_area).abs() < 1e-13, "{name}: area {area}");
                assert_eq!(parts.len(), first_parts.len(), "{name}");
                for ((n, l), (m, k)) in parts.iter().zip(first_parts) {
                    assert_eq!(n, m, "{name}");
                    assert!((l - k).abs() < 1e-13, "{name}: part {n}");
                }
            }
        }
    }
    assert_eq!(by_shape.len(), 3);
    assert_eq!(
        by_shape["mixed"]
            .1
            .iter()
            .map(|(n, _)| n.as_str())
            .collect::<Vec<_>>(),
        ["contact zone", "left side"]
    );
}
