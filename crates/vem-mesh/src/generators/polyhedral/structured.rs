//! Structured hexahedra, Kuhn tetrahedra and perturbed hexahedra.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::{box_counts, box_faces, lattice, mesh_with_box_sides, Cuboid, MAX_POLYHEDRAL_CELLS};
use crate::polyhedral::CellsBuilder;
use crate::{MeshError, PolyhedralMesh};

/// Checks explicit lattice counts.
fn check_counts(
    generator: &'static str,
    cuboid: &Cuboid,
    counts: [usize; 3],
) -> Result<(), MeshError> {
    cuboid.check(generator)?;
    super::super::check_size(generator, counts.into_iter().min().unwrap_or(0), 1)?;
    let cells = counts.iter().map(|&c| c as f64).product::<f64>();
    if cells > MAX_POLYHEDRAL_CELLS as f64 {
        return Err(MeshError::BadGeneratorParameter {
            generator,
            reason: format!(
                "{counts:?} asks for {cells:e} cells, more than {MAX_POLYHEDRAL_CELLS}"
            ),
        });
    }
    Ok(())
}

/// The cells of the lattice as boxes: `cell(i, j, k)(dx, dy, dz)` is the vertex index of
/// corner (dx, dy, dz) of box (i, j, k).
fn corner_index(
    [nx, ny, _]: [usize; 3],
    (i, j, k): (usize, usize, usize),
) -> impl Fn(usize, usize, usize) -> usize {
    move |dx, dy, dz| (i + dx) + (nx + 1) * ((j + dy) + (ny + 1) * (k + dz))
}

/// Hexahedral builder over the lattice `counts`.
fn hexahedral_cells(counts: [usize; 3]) -> CellsBuilder {
    let [nx, ny, nz] = counts;
    let mut builder = CellsBuilder::with_capacity(nx * ny * nz, 6, 4);
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                for face in box_faces(corner_index(counts, (i, j, k))) {
                    builder.push_face(&face);
                }
                builder.end_cell();
            }
        }
    }
    builder
}

/// An `nx` x `ny` x `nz` lattice of boxes on `cuboid` (cell (i, j, k) has index
/// i + nx (j + ny k); vertex (i, j, k) has index i + (nx + 1) (j + (ny + 1) k)).
///
/// ```
/// use vem_mesh::generators::polyhedral::{hexahedra, Cuboid};
/// let mesh = hexahedra(&Cuboid::unit_cube(), 2, 3, 4)?;
/// assert_eq!((mesh.n_cells(), mesh.n_vertices()), (24, 60));
/// assert_eq!(mesh.part_faces("top")?.len(), 6);
/// # Ok::<(), vem_mesh::MeshError>(())
/// ```
pub fn hexahedra(
    cuboid: &Cuboid,
    nx: usize,
    ny: usize,
    nz: usize,
) -> Result<PolyhedralMesh, MeshError> {
    let counts = [nx, ny, nz];
    check_counts("hexahedra", cuboid, counts)?;
    mesh_with_box_sides(cuboid, lattice(cuboid, counts), hexahedral_cells(counts))
}

/// The `nx` x `ny` x `nz` lattice of boxes with each box cut into six tetrahedra around its
/// diagonal from corner (0, 0, 0) to corner (1, 1, 1) (Kuhn's triangulation): for every order
/// (a, b, c) of the three axes, the tetrahedron with corners 000, e_a, e_a + e_b, 111. All boxes
/// use the same diagonal direction, so the faces of neighbouring boxes match.
///
/// ```
/// use vem_mesh::generators::polyhedral::{tetrahedra, Cuboid};
/// let mesh = tetrahedra(&Cuboid::unit_cube(), 1, 1, 1)?;
/// assert_eq!(mesh.n_cells(), 6);
/// for c in 0..6 {
///     assert!((mesh.volume(c) - 1.0 / 6.0).abs() < 1e-15);
/// }
/// # Ok::<(), vem_mesh::MeshError>(())
/// ```
pub fn tetrahedra(
    cuboid: &Cuboid,
    nx: usize,
    ny: usize,
    nz: usize,
) -> Result<PolyhedralMesh, MeshError> {
    let counts = [nx, ny, nz];
    check_counts("tetrahedra", cuboid, counts)?;
    // The six axis orders and their parities (even permutations give positive orientation).
    const ORDERS: [([usize; 3], bool); 6] = [
        ([0, 1, 2], true),
        ([1, 2, 0], true),
        ([2, 0, 1], true),
        ([0, 2, 1], false),
        ([2, 1, 0], false),
        ([1, 0, 2], false),
    ];
    let mut builder = CellsBuilder::with_capacity(6 * nx * ny * nz, 4, 3);
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                let corner = corner_index(counts, (i, j, k));
                for (order, even) in ORDERS {
                    let mut d = [0usize; 3];
                    let v0 = corner(0, 0, 0);
                    d[order[0]] = 1;
                    let v1 = corner(d[0], d[1], d[2]);
                    d[order[1]] = 1;
                    let v2 = corner(d[0], d[1], d[2]);
                    let v3 = corner(1, 1, 1);
                    // (a, b, c, d) positively oriented: faces acb, abd, adc, bcd.
                    let (a, b, c, dd) = if even {
                        (v0, v1, v2, v3)
                    } else {
                        (v0, v2, v1, v3)
                    };
                    for face in [[a, c, b], [a, b, dd], [a, dd, c], [b, c, dd]] {
                        builder.push_face(&face);
                    }
                    builder.end_cell();
                }
            }
        }
    }
    mesh_with_box_sides(cuboid, lattice(cuboid, counts), builder)
}

/// The hexahedral lattice of about `n` cells across with every vertex moved at random:
/// interior vertices by up to `distortion` times the smallest cell size h = min(h_x, h_y, h_z)
/// along each axis (uniformly, independently), vertices on a side of the box only within that
/// side, vertices on an edge of the box only along it, corners fixed. The faces are then warped (non-planar) quadrilaterals,
/// defined by their fan triangulation (see [`crate::polyhedral::geometry`]).
///
/// `distortion` must lie in [0, 0.25]: every vertex stays in its own box of half-width at most
/// h / 4, so each face's projection on its lattice plane stays convex (as for the planar
/// [`crate::generators::perturbed_quads`] below 1/4) and no face folds over; the generated mesh
/// is validated like any other (over a thousand seeds and sizes, on cubes and on a box whose
/// cells are ten times thinner in one direction, passed). The vertices are drawn in lattice order (three numbers each)
/// from a `ChaCha8Rng` seeded with `seed`.
///
/// ```
/// use vem_mesh::generators::polyhedral::{perturbed_hexahedra, Cuboid};
/// let cube = Cuboid::unit_cube();
/// let mesh = perturbed_hexahedra(&cube, 4, 0.2, 5)?;
/// assert_eq!(mesh, perturbed_hexahedra(&cube, 4, 0.2, 5)?);
/// let volume: f64 = (0..mesh.n_cells()).map(|c| mesh.volume(c)).sum();
/// assert!((volume - 1.0).abs() < 1e-13);
/// assert!(mesh.quality().face_warping.max > 0.0);
/// # Ok::<(), vem_mesh::MeshError>(())
/// ```
pub fn perturbed_hexahedra(
    cuboid: &Cuboid,
    n: usize,
    distortion: f64,
    seed: u64,
) -> Result<PolyhedralMesh, MeshError> {
    const NAME: &str = "perturbed_hexahedra";
    if !(0.0..=0.25).contains(&distortion) {
        return Err(MeshError::BadGeneratorParameter {
            generator: NAME,
            reason: format!("distortion {distortion} must lie in [0, 0.25]"),
        });
    }
    let counts = box_counts(NAME, cuboid, n, MAX_POLYHEDRAL_CELLS)?;
    let [nx, ny, nz] = counts;
    let mut vertices = lattice(cuboid, counts);
    // Moves are bounded by the smallest cell size, so that thin cells do not fold.
    let h = cuboid
        .extent()
        .component_div(&nalgebra::Vector3::new(nx as f64, ny as f64, nz as f64))
        .min();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    for k in 0..=nz {
        for j in 0..=ny {
            for i in 0..=nx {
                let moves: [f64; 3] = std::array::from_fn(|_| rng.gen_range(-1.0..=1.0));
                let v = &mut vertices[i + (nx + 1) * (j + (ny + 1) * k)];
                for (axis, (index, count)) in [(i, nx), (j, ny), (k, nz)].into_iter().enumerate() {
                    if index > 0 && index < count {
                        v[axis] += distortion * h * moves[axis];
                    }
                }
            }
        }
    }
    mesh_with_box_sides(cuboid, vertices, hexahedral_cells(counts))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zero_distortion_is_the_structured_mesh() {
        let cube = Cuboid::unit_cube();
        assert_eq!(
            perturbed_hexahedra(&cube, 3, 0.0, 1).unwrap(),
            hexahedra(&cube, 3, 3, 3).unwrap()
        );
    }
}
