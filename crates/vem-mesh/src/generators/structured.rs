//! Structured quadrilateral and triangle meshes.

use super::{check_size, mesh_with_sides, Rectangle};
use crate::{Mesh, MeshError, Point};

/// Vertices of an (nx + 1) x (ny + 1) lattice on `rect`, row by row from the bottom;
/// vertex (i, j) has index j * (nx + 1) + i.
pub(crate) fn lattice(rect: &Rectangle, nx: usize, ny: usize) -> Vec<Point> {
    let mut vertices = Vec::with_capacity((nx + 1) * (ny + 1));
    for j in 0..=ny {
        for i in 0..=nx {
            vertices.push(Point::new(
                rect.min.x + rect.width() * i as f64 / nx as f64,
                rect.min.y + rect.height() * j as f64 / ny as f64,
            ));
        }
    }
    vertices
}

/// An `nx` x `ny` grid of rectangles on `rect` (quadrilateral cells, counter-clockwise).
///
/// ```
/// use vem_mesh::generators::{structured_quads, Rectangle};
/// let mesh = structured_quads(&Rectangle::unit_square(), 4, 2)?;
/// assert_eq!(mesh.n_polygons(), 8);
/// assert_eq!(mesh.part_vertices("bottom")?.len(), 5);
/// # Ok::<(), vem_mesh::MeshError>(())
/// ```
pub fn structured_quads(rect: &Rectangle, nx: usize, ny: usize) -> Result<Mesh, MeshError> {
    rect.check("structured_quads")?;
    check_size("structured_quads", nx.min(ny), 1)?;
    let row = nx + 1;
    let polygons: Vec<Vec<usize>> = (0..ny)
        .flat_map(|j| {
            (0..nx).map(move |i| {
                let v = j * row + i;
                vec![v, v + 1, v + row + 1, v + row]
            })
        })
        .collect();
    mesh_with_sides(rect, lattice(rect, nx, ny), &polygons)
}

/// An `nx` x `ny` grid of rectangles on `rect`, each cut into two triangles along alternating
/// diagonals (a criss-cross-free, direction-balanced triangulation).
pub fn structured_triangles(rect: &Rectangle, nx: usize, ny: usize) -> Result<Mesh, MeshError> {
    rect.check("structured_triangles")?;
    check_size("structured_triangles", nx.min(ny), 1)?;
    let row = nx + 1;
    let mut polygons = Vec::with_capacity(2 * nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            let (a, b, c, d) = (
                j * row + i,
                j * row + i + 1,
                (j + 1) * row + i + 1,
                (j + 1) * row + i,
            );
            if (i + j) % 2 == 0 {
                polygons.push(vec![a, b, c]);
                polygons.push(vec![a, c, d]);
            } else {
                polygons.push(vec![a, b, d]);
                polygons.push(vec![b, c, d]);
            }
        }
    }
    mesh_with_sides(rect, lattice(rect, nx, ny), &polygons)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn quads_cover_the_rectangle_and_satisfy_euler() {
        let rect = Rectangle::new(Point::new(-1.0, 2.0), Point::new(2.0, 4.0));
        for (nx, ny) in [(1, 1), (3, 2), (8, 8)] {
            let mesh = structured_quads(&rect, nx, ny).unwrap();
            let area: f64 = (0..mesh.n_polygons()).map(|p| mesh.area(p)).sum();
            assert_relative_eq!(area, 6.0, max_relative = 1e-14);
            let euler = mesh.n_vertices() as i64 - mesh.n_edges() as i64 + mesh.n_polygons() as i64;
            assert_eq!(euler, 1);
            assert_eq!(mesh.part_vertices("left").unwrap().len(), ny + 1);
            assert_eq!(mesh.part_vertices("top").unwrap().len(), nx + 1);
        }
    }

    #[test]
    fn triangles_cover_the_rectangle() {
        let mesh = structured_triangles(&Rectangle::unit_square(), 5, 3).unwrap();
        assert_eq!(mesh.n_polygons(), 30);
        let area: f64 = (0..mesh.n_polygons()).map(|p| mesh.area(p)).sum();
        assert_relative_eq!(area, 1.0, max_relative = 1e-14);
        let boundary: usize = mesh.parts().iter().map(|p| p.edges.len()).sum();
        assert_eq!(boundary, 2 * (5 + 3));
    }

    #[test]
    fn zero_size_is_an_error() {
        let err = structured_quads(&Rectangle::unit_square(), 0, 3).unwrap_err();
        assert!(err.to_string().contains("too small"), "{err}");
    }
}
