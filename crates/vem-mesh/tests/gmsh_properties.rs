//! Properties of the Gmsh reader: a mesh written with any node numbering (tags out of order,
//! with gaps, split into blocks in any order) and any element order reads back as the same
//! mesh, in MSH 2.2 and 4.1; and no input, however mangled, makes the reader panic.

mod common;

use proptest::prelude::*;
use vem_mesh::generators::{structured_quads, structured_triangles, Rectangle};
use vem_mesh::io::{read_gmsh_bytes, read_msh_bytes};
use vem_mesh::Mesh;

/// A random permutation of `0..n` (Fisher-Yates driven by `keys`).
fn permutation(n: usize, keys: &[u64]) -> Vec<usize> {
    let mut p: Vec<usize> = (0..n).collect();
    for i in (1..n).rev() {
        let j = (keys[i % keys.len()].wrapping_mul(i as u64 + 7) % (i as u64 + 1)) as usize;
        p.swap(i, j);
    }
    p
}

/// MSH 2.2 ASCII text of `mesh`: node v gets tag `tags[v]`, nodes are listed in the order
/// `node_order`, polygons in the order `element_order`; parts are named physical curves.
fn msh22(mesh: &Mesh, tags: &[u64], node_order: &[usize], element_order: &[usize]) -> String {
    let parts = mesh.part_specs();
    let mut text = String::from("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n");
    text += &format!("{}\n", parts.len() + 1);
    for (k, part) in parts.iter().enumerate() {
        text += &format!("1 {} \"{}\"\n", k + 1, part.name);
    }
    text += &format!("2 {} \"body\"\n$EndPhysicalNames\n", parts.len() + 1);
    text += &format!("$Nodes\n{}\n", mesh.n_vertices());
    for &v in node_order {
        let p = mesh.vertex(v);
        text += &format!("{} {:?} {:?} 0\n", tags[v], p.x, p.y);
    }
    let n_lines: usize = parts.iter().map(|p| p.edges.len()).sum();
    text += &format!("$EndNodes\n$Elements\n{}\n", n_lines + mesh.n_polygons());
    let mut tag = 1;
    for (k, part) in parts.iter().enumerate() {
        for [a, b] in &part.edges {
            text += &format!("{tag} 1 2 {} {} {} {}\n", k + 1, k + 1, tags[*a], tags[*b]);
            tag += 1;
        }
    }
    for &p in element_order {
        let polygon = mesh.polygon(p);
        let nodes: Vec<String> = polygon.iter().map(|&v| tags[v].to_string()).collect();
        let element_type = if polygon.len() == 3 { 2 } else { 3 };
        let body = parts.len() + 1;
        text += &format!("{tag} {element_type} 2 {body} 1 {}\n", nodes.join(" "));
        tag += 1;
    }
    text + "$EndElements\n"
}

/// MSH 4.1 ASCII text of `mesh`, nodes split into `n_blocks` blocks listed in reverse order.
fn msh41(mesh: &Mesh, tags: &[u64], node_order: &[usize], n_blocks: usize) -> String {
    let parts = mesh.part_specs();
    let mut text = String::from("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n");
    text += &format!("{}\n", parts.len());
    for (k, part) in parts.iter().enumerate() {
        text += &format!("1 {} \"{}\"\n", k + 1, part.name);
    }
    text += &format!("$EndPhysicalNames\n$Entities\n0 {} 1 0\n", parts.len());
    for k in 0..parts.len() {
        text += &format!("{} 0 0 0 1 1 0 1 {} 0\n", k + 1, k + 1);
    }
    text += "1 0 0 0 1 1 0 0 0\n$EndEntities\n";
    let chunks: Vec<&[usize]> = node_order
        .chunks(node_order.len().div_ceil(n_blocks))
        .collect();
    let (min, max) = (tags.iter().min().unwrap(), tags.iter().max().unwrap());
    text += &format!(
        "$Nodes\n{} {} {min} {max}\n",
        chunks.len(),
        mesh.n_vertices()
    );
    for chunk in chunks.iter().rev() {
        text += &format!("2 1 0 {}\n", chunk.len());
        for &v in *chunk {
            text += &format!("{}\n", tags[v]);
        }
        for &v in *chunk {
            let p = mesh.vertex(v);
            text += &format!("{:?} {:?} 0\n", p.x, p.y);
        }
    }
    text += "$EndNodes\n";
    let n_lines: usize = parts.iter().map(|p| p.edges.len()).sum();
    let n = n_lines + mesh.n_polygons();
    let mut blocks = Vec::new();
    let mut tag = 1;
    for (k, part) in parts.iter().enumerate() {
        let mut block = format!("1 {} 1 {}\n", k + 1, part.edges.len());
        for [a, b] in &part.edges {
            block += &format!("{tag} {} {}\n", tags[*a], tags[*b]);
            tag += 1;
        }
        blocks.push(block);
    }
    for size in [3, 4] {
        let polygons: Vec<&[usize]> = mesh.polygons().filter(|p| p.len() == size).collect();
        if polygons.is_empty() {
            continue;
        }
        let mut block = format!("2 1 {} {}\n", size - 1, polygons.len());
        for polygon in polygons {
            let nodes: Vec<String> = polygon.iter().map(|&v| tags[v].to_string()).collect();
            block += &format!("{tag} {}\n", nodes.join(" "));
            tag += 1;
        }
        blocks.push(block);
    }
    text += &format!("$Elements\n{} {n} 1 {}\n", blocks.len(), tag - 1);
    for block in blocks.iter().rev() {
        text += block;
    }
    text + "$EndElements\n"
}

/// Area, and length of every part by name, and the counts: what a renumbering must not change.
fn invariants(mesh: &Mesh) -> (f64, Vec<(String, f64)>, usize, usize) {
    let (area, parts) = common::area_and_part_lengths(mesh);
    (area, parts, mesh.n_vertices(), mesh.n_polygons())
}

fn close(a: &(f64, Vec<(String, f64)>, usize, usize), b: &(f64, Vec<(String, f64)>, usize, usize)) {
    assert!((a.0 - b.0).abs() < 1e-12, "area {} != {}", a.0, b.0);
    assert_eq!((a.2, a.3), (b.2, b.3));
    assert_eq!(a.1.len(), b.1.len());
    for ((n, l), (m, k)) in a.1.iter().zip(&b.1) {
        assert_eq!(n, m);
        assert!((l - k).abs() < 1e-12, "part {n}: {l} != {k}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn any_numbering_reads_back_as_the_same_mesh(
        quads in any::<bool>(),
        nx in 1usize..5,
        ny in 1usize..4,
        keys in prop::collection::vec(any::<u64>(), 1..8),
        gap in 1u64..1000,
        n_blocks in 1usize..4,
    ) {
        let rect = Rectangle::unit_square();
        let mesh = if quads {
            structured_quads(&rect, nx, ny).unwrap()
        } else {
            structured_triangles(&rect, nx, ny).unwrap()
        };
        let n = mesh.n_vertices();
        let order = permutation(n, &keys);
        // Tags: a permutation of 1..=n stretched by `gap`, so they have holes.
        let tags: Vec<u64> = (0..n).map(|v| 1 + order[v] as u64 * gap).collect();
        let node_order = permutation(n, &keys.iter().map(|k| k ^ 0xABCD).collect::<Vec<_>>());
        let element_order = permutation(mesh.n_polygons(), &keys);
        let expected = invariants(&mesh);
        let v2 = read_gmsh_bytes(msh22(&mesh, &tags, &node_order, &element_order).as_bytes(), "v2.msh")
            .unwrap();
        close(&invariants(&v2), &expected);
        let v4 = read_gmsh_bytes(msh41(&mesh, &tags, &node_order, n_blocks).as_bytes(), "v4.msh")
            .unwrap();
        close(&invariants(&v4), &expected);
    }

    #[test]
    fn mangled_files_give_errors_not_panics(
        file in 0usize..3,
        edits in prop::collection::vec((any::<prop::sample::Index>(), any::<u8>(), 0u8..3), 1..6),
    ) {
        let names = ["square_41_binary.msh", "square_shuffled_22_binary.msh", "mixed_41.msh"];
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data/gmsh-corpus")
            .join(names[file]);
        let mut bytes = std::fs::read(path).unwrap();
        for (index, byte, kind) in edits {
            let i = index.index(bytes.len());
            match kind {
                0 => bytes[i] = byte,
                1 => { bytes.remove(i); }
                _ => bytes.truncate(i),
            }
            if bytes.is_empty() {
                break;
            }
        }
        // Either outcome is fine; a panic fails the property.
        let _ = read_msh_bytes(&bytes);
        if let Ok(mesh) = read_gmsh_bytes(&bytes, "mangled.msh") {
            prop_assert!(mesh.vertices().iter().all(|p| p.x.is_finite() && p.y.is_finite()));
        }
    }
}

#[test]
fn duplicated_tags_and_missing_nodes_are_errors_naming_them() {
    let mesh = structured_quads(&Rectangle::unit_square(), 1, 1).unwrap();
    let order: Vec<usize> = (0..4).collect();
    let text = msh22(&mesh, &[5, 9, 5, 2], &order, &[0]);
    let err = read_gmsh_bytes(text.as_bytes(), "dup.msh").unwrap_err();
    assert!(
        err.to_string()
            .starts_with("dup.msh: line 16 (in $Nodes): node tag 5 is defined twice"),
        "{err}"
    );
    let text = msh22(&mesh, &[5, 9, 7, 2], &order, &[0]).replace("\n7 ", "\n8 ");
    let err = read_gmsh_bytes(text.as_bytes(), "missing.msh").unwrap_err();
    assert!(
        err.to_string()
            .contains("refers to node 7, which is not in the $Nodes section"),
        "{err}"
    );
}
