//! Quadrilateral meshes with randomly perturbed nodes.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::{cell_counts, mesh_with_sides, structured::lattice, Rectangle};
use crate::{Mesh, MeshError};

/// The structured quadrilateral mesh (about `n` cells across) with every node moved at random:
/// interior nodes by up to `distortion * h_x` in x and `distortion * h_y` in y (uniformly,
/// independently; h_x, h_y the cell width and height), boundary nodes only along their side,
/// corners fixed.
///
/// `distortion` must lie in [0, 0.5). Every node then stays in its own box of half-width below
/// h / 2, the boxes of a cell's bottom and top edges (and of its left and right edges) are
/// disjoint, so no cell can fold over: every cell is a simple counter-clockwise quadrilateral.
/// Below 0.25 every cell is convex (in cell units a corner turns reflex only when it crosses
/// the diagonal through its two neighbours; the corner's x + y moves by less than
/// 2 distortion and the diagonal's by less than 2 distortion, and they start 1 apart); from
/// 0.25 on, some cells may be non-convex darts. The nodes are drawn in lattice order from a
/// `ChaCha8Rng` seeded with `seed`.
///
/// ```
/// use vem_mesh::generators::{perturbed_quads, Rectangle};
/// let rect = Rectangle::unit_square();
/// let a = perturbed_quads(&rect, 8, 0.3, 42)?;
/// let b = perturbed_quads(&rect, 8, 0.3, 42)?;
/// assert_eq!(a, b);
/// assert!(perturbed_quads(&rect, 8, 0.5, 42).is_err());
/// # Ok::<(), vem_mesh::MeshError>(())
/// ```
pub fn perturbed_quads(
    rect: &Rectangle,
    n: usize,
    distortion: f64,
    seed: u64,
) -> Result<Mesh, MeshError> {
    const NAME: &str = "perturbed_quads";
    if !(0.0..0.5).contains(&distortion) {
        return Err(MeshError::BadGeneratorParameter {
            generator: NAME,
            reason: format!("distortion {distortion} must lie in [0, 0.5)"),
        });
    }
    let (nx, ny) = cell_counts(NAME, rect, n)?;
    let mut vertices = lattice(rect, nx, ny);
    let (hx, hy) = (rect.width() / nx as f64, rect.height() / ny as f64);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    for j in 0..=ny {
        for i in 0..=nx {
            // Draw both numbers for every node, so a node's move does not depend on which
            // other nodes are on the boundary.
            let dx = distortion * hx * rng.gen_range(-1.0..=1.0);
            let dy = distortion * hy * rng.gen_range(-1.0..=1.0);
            let v = &mut vertices[j * (nx + 1) + i];
            if i > 0 && i < nx {
                v.x += dx;
            }
            if j > 0 && j < ny {
                v.y += dy;
            }
        }
    }
    let row = nx + 1;
    let polygons: Vec<Vec<usize>> = (0..ny)
        .flat_map(|j| {
            (0..nx).map(move |i| {
                let v = j * row + i;
                vec![v, v + 1, v + row + 1, v + row]
            })
        })
        .collect();
    mesh_with_sides(rect, vertices, &polygons)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zero_distortion_is_the_structured_mesh() {
        let rect = Rectangle::unit_square();
        let perturbed = perturbed_quads(&rect, 5, 0.0, 3).unwrap();
        let structured = super::super::structured_quads(&rect, 5, 5).unwrap();
        assert_eq!(perturbed, structured);
    }

    #[test]
    fn small_distortion_keeps_cells_convex() {
        let mesh = perturbed_quads(&Rectangle::unit_square(), 12, 0.24, 9).unwrap();
        for p in 0..mesh.n_polygons() {
            let pts = mesh.polygon_points(p);
            for k in 0..4 {
                let (a, b, c) = (pts[k], pts[(k + 1) % 4], pts[(k + 2) % 4]);
                let turn = (b - a).perp(&(c - b));
                assert!(turn > 0.0, "cell {p} has a reflex corner");
            }
        }
    }
}
