//! Meshes of non-convex, star-shaped chevron cells.

use super::{cell_counts, mesh_with_sides, structured::lattice, Rectangle};
use crate::{Mesh, MeshError, Point};

/// Rise of a chevron's middle vertices, as a fraction of the cell height.
pub const CHEVRON_RISE: f64 = 0.25;

/// A mesh of chevron (arrow) cells tiling `rect` exactly, about `n` cells across.
///
/// Start from the structured `nx` x `ny` lattice and bend every interior horizontal lattice line
/// upwards at the middle of each cell: cell (i, j) gains a vertex at the middle of its bottom
/// side raised by [`CHEVRON_RISE`] h_y (unless the bottom side lies on the rectangle) and one
/// at the middle of its top side raised alike (unless the top side lies on the rectangle).
/// Interior cells are hexagons with one reflex vertex (the bottom middle); they are star-shaped,
/// and for square cells of side h and rise s = [`CHEVRON_RISE`]:
///
/// * h_T = sqrt 2 h (the diagonal), shortest edge sqrt(1/4 + s^2) h,
/// * the kernel is bounded by the lines of the two bottom edges and of the two top edges and by
///   the sides; by symmetry its Chebyshev centre is (h/2, (1/2 + s) h) and its radius
///   h / (2 sqrt(1 + 4 s^2)).
///
/// The bottom row cells are convex pentagons, the top row non-convex pentagons (for `ny` = 1
/// the cells are rectangles).
///
/// ```
/// use vem_mesh::generators::{nonconvex, Rectangle};
/// let mesh = nonconvex(&Rectangle::unit_square(), 4)?;
/// assert_eq!(mesh.polygon(5).len(), 6); // an interior chevron
/// let area: f64 = (0..mesh.n_polygons()).map(|p| mesh.area(p)).sum();
/// assert!((area - 1.0).abs() < 1e-14);
/// # Ok::<(), vem_mesh::MeshError>(())
/// ```
pub fn nonconvex(rect: &Rectangle, n: usize) -> Result<Mesh, MeshError> {
    let (nx, ny) = cell_counts("nonconvex", rect, n)?;
    let row = nx + 1;
    let mut vertices = lattice(rect, nx, ny);
    let first_middle = vertices.len();
    // Middle vertex of the cell side between lattice nodes (i, j) and (i + 1, j), 0 < j < ny.
    let middle = |i: usize, j: usize| first_middle + (j - 1) * nx + i;
    let hy = rect.height() / ny as f64;
    for j in 1..ny {
        for i in 0..nx {
            let (a, b) = (vertices[j * row + i], vertices[j * row + i + 1]);
            vertices.push(Point::new(0.5 * (a.x + b.x), a.y + CHEVRON_RISE * hy));
        }
    }
    let mut polygons = Vec::with_capacity(nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            let v = j * row + i;
            let mut cell = vec![v];
            if j > 0 {
                cell.push(middle(i, j));
            }
            cell.extend([v + 1, v + row + 1]);
            if j + 1 < ny {
                cell.push(middle(i, j + 1));
            }
            cell.push(v + row);
            polygons.push(cell);
        }
    }
    mesh_with_sides(rect, vertices, &polygons)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn interior_chevrons_have_the_hand_computed_figures() {
        let mesh = nonconvex(&Rectangle::unit_square(), 4).unwrap();
        let s = CHEVRON_RISE;
        let h = 0.25;
        let mut chevrons = 0;
        for p in 0..mesh.n_polygons() {
            if mesh.polygon(p).len() != 6 {
                continue;
            }
            chevrons += 1;
            let q = mesh.element_quality(p);
            assert_relative_eq!(q.diameter, 2f64.sqrt() * h, max_relative = 1e-14);
            assert_relative_eq!(
                q.shortest_edge_ratio,
                (0.25 + s * s).sqrt() / 2f64.sqrt(),
                max_relative = 1e-13
            );
            assert_relative_eq!(
                q.star_ratio,
                1.0 / (2.0 * (1.0 + 4.0 * s * s).sqrt() * 2f64.sqrt()),
                max_relative = 1e-12
            );
        }
        assert_eq!(chevrons, 4 * 2);
    }
}
