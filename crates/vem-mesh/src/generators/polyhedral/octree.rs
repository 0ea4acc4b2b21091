//! Cubes refined once in a checkerboard pattern: hanging nodes on faces and edges.

use super::{box_counts, box_faces, mesh_with_box_sides, step, Cuboid, MAX_POLYHEDRAL_CELLS};
use crate::polyhedral::CellsBuilder;
use crate::{MeshError, Point3, PolyhedralMesh};

/// The hexahedral lattice of about `n` cells across with a checkerboard of refined cells: the
/// box (i, j, k) with i + j + k even is split into eight (one octree level), the others are kept
/// whole, so every kept box is surrounded by split ones across its faces.
///
/// A kept box then carries the hanging vertices of its neighbours: each side facing a split box
/// is made of four coplanar square faces (the split neighbour's faces), and every edge of the
/// kept box with a split box around it carries its midpoint as a vertex of every face that has
/// the edge (collinear consecutive vertices). An interior kept box has 24 faces and 26 vertices.
/// For cubic boxes of side h: a kept box has h_E = sqrt 3 h, shortest edge h / 2 (ratio
/// 1 / (2 sqrt 3)), smallest face diameter h / sqrt 2 and star-shaped radius h / 2; the split
/// quarters are cubes of side h / 2.
///
/// ```
/// use vem_mesh::generators::polyhedral::{octree_hexahedra, Cuboid};
/// let mesh = octree_hexahedra(&Cuboid::unit_cube(), 3)?;
/// // 14 split boxes (112 cubes) and 13 kept ones; the centre box is kept, with 24 faces.
/// assert_eq!(mesh.n_cells(), 14 * 8 + 13);
/// assert_eq!(mesh.cell_faces(mesh.n_cells() - 7).len(), 24);
/// assert_eq!(mesh.euler_characteristic(), 1);
/// # Ok::<(), vem_mesh::MeshError>(())
/// ```
pub fn octree_hexahedra(cuboid: &Cuboid, n: usize) -> Result<PolyhedralMesh, MeshError> {
    let counts = box_counts("octree_hexahedra", cuboid, n, MAX_POLYHEDRAL_CELLS / 8)?;
    let [nx, ny, nz] = counts;
    let split = |i: usize, j: usize, k: usize| (i + j + k) % 2 == 0;
    // Fine lattice: node (I, J, K), 0 <= I <= 2 nx, ...
    let fine = [2 * nx, 2 * ny, 2 * nz];
    // Coarse boxes along one axis whose closure holds fine node index `node`.
    let around = |node: usize, count: usize| -> [Option<usize>; 2] {
        if node % 2 == 1 {
            [Some(node / 2), None]
        } else {
            let half = node / 2;
            [half.checked_sub(1), (half < count).then_some(half)]
        }
    };
    let used = |node: [usize; 3]| -> bool {
        if node.iter().all(|&c| c % 2 == 0) {
            return true;
        }
        let [ai, aj, ak] = [
            around(node[0], nx),
            around(node[1], ny),
            around(node[2], nz),
        ];
        ai.iter().flatten().any(|&i| {
            aj.iter()
                .flatten()
                .any(|&j| ak.iter().flatten().any(|&k| split(i, j, k)))
        })
    };
    let index_of = |node: [usize; 3]| node[0] + (fine[0] + 1) * (node[1] + (fine[1] + 1) * node[2]);
    let mut number = vec![usize::MAX; (fine[0] + 1) * (fine[1] + 1) * (fine[2] + 1)];
    let mut vertices = Vec::new();
    for kk in 0..=fine[2] {
        for jj in 0..=fine[1] {
            for ii in 0..=fine[0] {
                if used([ii, jj, kk]) {
                    number[index_of([ii, jj, kk])] = vertices.len();
                    vertices.push(Point3::new(
                        step(ii, fine[0], cuboid.min.x, cuboid.max.x),
                        step(jj, fine[1], cuboid.min.y, cuboid.max.y),
                        step(kk, fine[2], cuboid.min.z, cuboid.max.z),
                    ));
                }
            }
        }
    }
    let node = |p: [usize; 3]| number[index_of(p)];
    // Face `side` of the box of fine size `size` at fine corner `m`, with the midpoints of its
    // edges inserted where they are vertices.
    let face = |m: [usize; 3], size: usize, side: usize, out: &mut Vec<usize>| {
        let corners =
            box_faces(|dx, dy, dz| [m[0] + size * dx, m[1] + size * dy, m[2] + size * dz])[side];
        out.clear();
        for q in 0..4 {
            let (a, b) = (corners[q], corners[(q + 1) % 4]);
            out.push(node(a));
            if size == 2 {
                let middle = [(a[0] + b[0]) / 2, (a[1] + b[1]) / 2, (a[2] + b[2]) / 2];
                if used(middle) {
                    out.push(node(middle));
                }
            }
        }
    };
    let mut builder = CellsBuilder::with_capacity(8 * nx * ny * nz, 6, 4);
    let mut loop_ = Vec::with_capacity(8);
    // Split boxes first (their eight cubes), then the kept boxes.
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                if !split(i, j, k) {
                    continue;
                }
                for (dx, dy, dz) in (0..8).map(|c| (c & 1, c >> 1 & 1, c >> 2)) {
                    let m = [2 * i + dx, 2 * j + dy, 2 * k + dz];
                    for side in 0..6 {
                        face(m, 1, side, &mut loop_);
                        builder.push_face(&loop_);
                    }
                    builder.end_cell();
                }
            }
        }
    }
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                if split(i, j, k) {
                    continue;
                }
                let m = [2 * i, 2 * j, 2 * k];
                for side in 0..6 {
                    let (axis, upper) = (side / 2, side % 2 == 1);
                    let mut across = [i, j, k];
                    let neighbour_split = if upper {
                        across[axis] += 1;
                        across[axis] < counts[axis]
                    } else {
                        across[axis] > 0 && {
                            across[axis] -= 1;
                            true
                        }
                    } && split(across[0], across[1], across[2]);
                    if neighbour_split {
                        // The four faces of the split neighbour's cubes, seen from this box:
                        // faces `side` of the four half-size cubes of this box along it.
                        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
                        for (du, dv) in [(0, 0), (1, 0), (1, 1), (0, 1)] {
                            let mut corner = m;
                            corner[axis] += usize::from(upper);
                            corner[u] += du;
                            corner[v] += dv;
                            face(corner, 1, side, &mut loop_);
                            builder.push_face(&loop_);
                        }
                    } else {
                        face(m, 2, side, &mut loop_);
                        builder.push_face(&loop_);
                    }
                }
                builder.end_cell();
            }
        }
    }
    mesh_with_box_sides(cuboid, vertices, builder)
}
