//! Quadrilateral meshes with hanging nodes.

use super::{cell_counts, mesh_with_sides, Rectangle};
use crate::{Mesh, MeshError, Point};

/// The structured quadrilateral mesh (about `n` cells across) with a checkerboard of refined
/// cells: cell (i, j) with i + j even is split into four, and each unsplit neighbour keeps the
/// middle of the shared side as a vertex (a hanging node: three collinear consecutive vertices).
///
/// Unsplit interior cells therefore have eight vertices; for square cells of side h their
/// shortest edge is h/2 against h_T = sqrt 2 h (ratio 1/(2 sqrt 2)), and the split quarters are
/// squares of side h/2 (ratio 1/sqrt 2). The mesh size is set by the unsplit cells, h ~ 1/n.
///
/// ```
/// use vem_mesh::generators::{hanging_nodes, Rectangle};
/// let mesh = hanging_nodes(&Rectangle::unit_square(), 3)?;
/// // 5 split cells (20 quarters) and 4 unsplit cells on the sides, 3 hanging nodes each.
/// assert_eq!(mesh.n_polygons(), 24);
/// assert_eq!(mesh.polygon(20).len(), 7);
/// # Ok::<(), vem_mesh::MeshError>(())
/// ```
pub fn hanging_nodes(rect: &Rectangle, n: usize) -> Result<Mesh, MeshError> {
    let (nx, ny) = cell_counts("hanging_nodes", rect, n)?;
    let split = |i: usize, j: usize| (i + j) % 2 == 0;
    // Work on the lattice of half cells: node (I, J), 0 <= I <= 2 nx, 0 <= J <= 2 ny.
    let (wide, high) = (2 * nx, 2 * ny);
    let used = |ii: usize, jj: usize| -> bool {
        match (ii % 2, jj % 2) {
            (0, 0) => true,
            // Middle of a horizontal side: used if a cell below or above is split.
            (1, 0) => {
                let i = ii / 2;
                (jj > 0 && split(i, jj / 2 - 1)) || (jj < high && split(i, jj / 2))
            }
            // Middle of a vertical side: used if a cell left or right is split.
            (0, _) => {
                let j = jj / 2;
                (ii > 0 && split(ii / 2 - 1, j)) || (ii < wide && split(ii / 2, j))
            }
            // Centre of a cell.
            _ => split(ii / 2, jj / 2),
        }
    };
    let mut index = vec![usize::MAX; (wide + 1) * (high + 1)];
    let mut vertices = Vec::new();
    let coordinate = |k: usize, count: usize, min: f64, max: f64| -> f64 {
        if k == count {
            max
        } else {
            min + (max - min) * k as f64 / count as f64
        }
    };
    for jj in 0..=high {
        for ii in 0..=wide {
            if used(ii, jj) {
                index[jj * (wide + 1) + ii] = vertices.len();
                vertices.push(Point::new(
                    coordinate(ii, wide, rect.min.x, rect.max.x),
                    coordinate(jj, high, rect.min.y, rect.max.y),
                ));
            }
        }
    }
    let node = |ii: usize, jj: usize| index[jj * (wide + 1) + ii];
    let mut polygons = Vec::with_capacity(4 * nx * ny);
    // Split cells first (their quarters), then the unsplit cells with their hanging nodes.
    for j in 0..ny {
        for i in 0..nx {
            if split(i, j) {
                for (di, dj) in [(0, 0), (1, 0), (1, 1), (0, 1)] {
                    let (ii, jj) = (2 * i + di, 2 * j + dj);
                    polygons.push(vec![
                        node(ii, jj),
                        node(ii + 1, jj),
                        node(ii + 1, jj + 1),
                        node(ii, jj + 1),
                    ]);
                }
            }
        }
    }
    for j in 0..ny {
        for i in 0..nx {
            if !split(i, j) {
                let (ii, jj) = (2 * i, 2 * j);
                let boundary = [
                    (ii, jj),
                    (ii + 1, jj),
                    (ii + 2, jj),
                    (ii + 2, jj + 1),
                    (ii + 2, jj + 2),
                    (ii + 1, jj + 2),
                    (ii, jj + 2),
                    (ii, jj + 1),
                ];
                polygons.push(
                    boundary
                        .iter()
                        .filter(|&&(a, b)| used(a, b))
                        .map(|&(a, b)| node(a, b))
                        .collect(),
                );
            }
        }
    }
    mesh_with_sides(rect, vertices, &polygons)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn unsplit_cells_carry_hanging_nodes() {
        let mesh = hanging_nodes(&Rectangle::unit_square(), 4).unwrap();
        // 8 split cells -> 32 quarters, 8 unsplit cells.
        assert_eq!(mesh.n_polygons(), 40);
        let h = 0.25;
        for p in 32..40 {
            let q = mesh.element_quality(p);
            assert_relative_eq!(q.diameter, 2f64.sqrt() * h, max_relative = 1e-14);
            assert_relative_eq!(
                q.shortest_edge_ratio,
                0.5 / 2f64.sqrt(),
                max_relative = 1e-13
            );
            assert_relative_eq!(q.star_ratio, 0.5 / 2f64.sqrt(), max_relative = 1e-12);
        }
        // Interior unsplit cells have all four hanging nodes.
        assert!(mesh.polygons().skip(32).any(|p| p.len() == 8));
    }
}
