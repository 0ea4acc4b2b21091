//! Helpers shared by the Gmsh reader's tests.

use vem_mesh::Mesh;

/// The area of a mesh and the length of each boundary part by name: what neither the version,
/// the encoding nor the numbering of a file may change.
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
