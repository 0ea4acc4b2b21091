//! Helpers shared by the Gmsh reader's tests.

use std::collections::BTreeMap;

use serde_json::Value;
use vem_mesh::io::MshFile;
use vem_mesh::Mesh;

/// The area of a mesh and the length of each boundary part by name: what neither the version,
/// the encoding nor the numbering of a file may change.
#[allow(dead_code)]
pub fn area_and_part_lengths(mesh: &Mesh) -> (f64, Vec<(String, f64)>) {
    let area = (0..mesh.n_polygons()).map(|p| mesh.area(p)).sum();
    let parts = mesh
        .parts()
        .iter()
        .map(|part| {
            let length = part
                .edges
                .iter()
                .map(|&e| {
                    let [a, b] = mesh.edge(e).vertices;
                    (mesh.vertex(a) - mesh.vertex(b)).norm()
                })
                .sum();
            (part.name.clone(), length)
        })
        .collect();
    (area, parts)
}

/// (nodes as tag -> xyz, elements as tag -> (type, dim, entity, nodes), physical groups as
/// (dim, tag) -> (name, entities)).
#[allow(dead_code)]
pub type Description = (
    BTreeMap<u64, [f64; 3]>,
    BTreeMap<u64, (i32, i32, i32, Vec<u64>)>,
    BTreeMap<(i32, i32), (String, Vec<i32>)>,
);

#[allow(dead_code)]
pub fn ours(msh: &MshFile) -> Description {
    let nodes = msh.nodes.iter().map(|n| (n.tag, n.xyz)).collect();
    let elements = msh
        .elements
        .iter()
        .map(|e| {
            let value = (e.element_type, e.entity_dim, e.entity_tag, e.nodes.clone());
            (e.tag, value)
        })
        .collect();
    let groups = msh
        .physical_groups()
        .into_iter()
        .map(|(key, entities)| {
            let name = msh.physical_names.get(&key).cloned().unwrap_or_default();
            (key, (name, entities))
        })
        .collect();
    (nodes, elements, groups)
}

#[allow(dead_code)]
pub fn gmsh(json: &Value) -> Description {
    let int = |v: &Value| v.as_i64().unwrap();
    let nodes = json["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|row| {
            let f = |k: usize| row[k].as_f64().unwrap();
            (int(&row[0]) as u64, [f(1), f(2), f(3)])
        })
        .collect();
    let elements = json["elements"]
        .as_array()
        .unwrap()
        .iter()
        .map(|row| {
            let nodes = row[4].as_array().unwrap().iter().map(|v| int(v) as u64);
            let value = (
                int(&row[1]) as i32,
                int(&row[2]) as i32,
                int(&row[3]) as i32,
                nodes.collect(),
            );
            (int(&row[0]) as u64, value)
        })
        .collect();
    let groups = json["physical_groups"]
        .as_array()
        .unwrap()
        .iter()
        .map(|row| {
            let entities = row[3].as_array().unwrap().iter().map(|v| int(v) as i32);
            let key = (int(&row[0]) as i32, int(&row[1]) as i32);
            (
                key,
                (row[2].as_str().unwrap().to_string(), entities.collect()),
            )
        })
        .collect();
    (nodes, elements, groups)
}
