//! Hexagon-dominant meshes: a honeycomb clipped to the rectangle.

use super::{check_size, mesh_with_sides, Rectangle, MAX_CELLS};
use crate::{Mesh, MeshError, Point};

/// A honeycomb of flat-topped hexagons clipped to `rect`, `n` hexagon widths across.
///
/// The honeycomb is built on an integer lattice: with units u = width / (3n) across and
/// v = height / m up, hexagon (i, c) has centre (3i, c) with c of the parity of i, and vertices
/// (3i +- 2, c) and (3i +- 1, c +- 1). The left and right sides of the rectangle run through the
/// centres of the first and last columns (cutting those hexagons in half), and the bottom and
/// top through centres or along edges, so every clipped cell is a hexagon, a pentagon or a
/// quadrilateral with all vertices on the lattice: no short edges appear. m is chosen so that
/// u and v are in the ratio 1 : sqrt 3 of a regular hexagon as closely as an integer allows
/// (m >= 1), so the hexagons are regular up to that rounding.
///
/// ```
/// use vem_mesh::generators::{hexagons, Rectangle};
/// let mesh = hexagons(&Rectangle::unit_square(), 4)?;
/// assert!(mesh.polygons().any(|p| p.len() == 6));
/// let area: f64 = (0..mesh.n_polygons()).map(|p| mesh.area(p)).sum();
/// assert!((area - 1.0).abs() < 1e-14);
/// # Ok::<(), vem_mesh::MeshError>(())
/// ```
pub fn hexagons(rect: &Rectangle, n: usize) -> Result<Mesh, MeshError> {
    const NAME: &str = "hexagons";
    rect.check(NAME)?;
    check_size(NAME, n, 1)?;
    // Regular hexagons: u = a / 2, v = a sqrt(3) / 2, so m = height / v with a = 2 width / (3n).
    let m = (3f64.sqrt() * n as f64 * rect.height() / rect.width())
        .round()
        .max(1.0);
    if n as f64 * m > 2.0 * MAX_CELLS as f64 {
        return Err(MeshError::BadGeneratorParameter {
            generator: NAME,
            reason: format!("size n = {n} asks for more than {MAX_CELLS} cells on this rectangle"),
        });
    }
    let (columns, rows) = (3 * n as i64, m as i64);
    let mut cells: Vec<Vec<(i64, i64)>> = Vec::new();
    for i in 0..=n as i64 {
        let cx = 3 * i;
        // Centres of column i have the parity of i; take every hexagon reaching into (0, rows).
        let mut cy = -1 + (i + 1).rem_euclid(2);
        while cy <= rows + 1 {
            let hexagon = [
                (cx + 2, cy),
                (cx + 1, cy + 1),
                (cx - 1, cy + 1),
                (cx - 2, cy),
                (cx - 1, cy - 1),
                (cx + 1, cy - 1),
            ];
            let cell = clip_to_box(&hexagon, columns, rows);
            if twice_area(&cell) > 0 {
                cells.push(cell);
            }
            cy += 2;
        }
    }
    let mut keys: Vec<(i64, i64)> = cells.iter().flatten().copied().collect();
    keys.sort_unstable();
    keys.dedup();
    let coordinate = |k: i64, count: i64, min: f64, max: f64| -> f64 {
        if k == count {
            max
        } else {
            min + (max - min) * k as f64 / count as f64
        }
    };
    let vertices: Vec<Point> = keys
        .iter()
        .map(|&(x, y)| {
            Point::new(
                coordinate(x, columns, rect.min.x, rect.max.x),
                coordinate(y, rows, rect.min.y, rect.max.y),
            )
        })
        .collect();
    let polygons: Vec<Vec<usize>> = cells
        .iter()
        .map(|cell| {
            cell.iter()
                .map(|key| keys.binary_search(key).unwrap_or_default())
                .collect()
        })
        .collect();
    mesh_with_sides(rect, vertices, &polygons)
}

/// Clips a convex lattice polygon to [0, columns] x [0, rows].
///
/// Every clipping line runs through lattice points of the honeycomb in a way that makes each
/// intersection the midpoint of a horizontal edge (two lattice points two units apart), so the
/// result has integer coordinates and is computed exactly.
fn clip_to_box(polygon: &[(i64, i64)], columns: i64, rows: i64) -> Vec<(i64, i64)> {
    // Half-planes as (a, b, c): keep a x + b y <= c.
    let half_planes = [(-1, 0, 0), (1, 0, columns), (0, -1, 0), (0, 1, rows)];
    let mut current: Vec<(i64, i64)> = polygon.to_vec();
    for (a, b, c) in half_planes {
        let mut next = Vec::with_capacity(current.len() + 2);
        let count = current.len();
        for k in 0..count {
            let (p, q) = (current[k], current[(k + 1) % count]);
            let (sp, sq) = (a * p.0 + b * p.1 - c, a * q.0 + b * q.1 - c);
            if sp <= 0 {
                next.push(p);
            }
            if (sp < 0 && sq > 0) || (sp > 0 && sq < 0) {
                // p + (q - p) sp / (sp - sq): exact here (see above).
                let d = sp - sq;
                next.push((p.0 + (q.0 - p.0) * sp / d, p.1 + (q.1 - p.1) * sp / d));
            }
        }
        next.dedup();
        while next.len() > 1 && next.first() == next.last() {
            next.pop();
        }
        current = next;
    }
    current
}

/// Twice the signed area of a lattice polygon.
fn twice_area(polygon: &[(i64, i64)]) -> i64 {
    let m = polygon.len();
    (0..m)
        .map(|k| {
            let (p, q) = (polygon[k], polygon[(k + 1) % m]);
            p.0 * q.1 - q.0 * p.1
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_column_pair_is_two_half_hexagon_columns() {
        // n = 1 on a unit square: u = 1/3, m = round(sqrt 3) = 2.
        let mesh = hexagons(&Rectangle::unit_square(), 1).unwrap();
        // Column 0 (centres y = 0, 2): two quarter hexagons; column 1 (centre y = 1): a half.
        assert_eq!(mesh.n_polygons(), 3);
        let sizes: Vec<usize> = mesh.polygons().map(<[usize]>::len).collect();
        assert_eq!(sizes, vec![4, 4, 5]);
    }

    #[test]
    fn interior_cells_are_regular_hexagons() {
        // With width 3 * n * (1/2) and height m * sqrt(3)/2 the lattice is exactly regular.
        let n = 6;
        let rect = Rectangle::new(
            Point::new(0.0, 0.0),
            Point::new(1.5 * n as f64, 3f64.sqrt() / 2.0 * 10.0),
        );
        let mesh = hexagons(&rect, n).unwrap();
        let hexagon_area = 1.5 * 3f64.sqrt();
        for p in 0..mesh.n_polygons() {
            if mesh.polygon(p).len() == 6 {
                assert!((mesh.area(p) - hexagon_area).abs() < 1e-12);
                assert!((mesh.diameter(p) - 2.0).abs() < 1e-12);
            }
        }
    }
}
