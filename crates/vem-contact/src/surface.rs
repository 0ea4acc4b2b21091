//! The geometry of contact surfaces in space (`D = 3`) that the contact layer adds to the
//! mesh layer's: the rim of a part (where a contact zone may be cut short) and the consistent
//! pressure on a surface. A pair of two bodies is made node-to-node by the surface overlay
//! ([`vem_mesh::polyhedral::overlay::insert_surface_overlay`]); the nodal normals and
//! tributary areas of a part are [`vem_mesh::polyhedral::overlay::boundary_surface`]'s.
//!
//! # Tributary areas
//!
//! The tributary area of a vertex is its weight in the faces of the part:
//! `l_x = sum_F w_x^F . n_F` with the vector weights `w_x^F` of
//! [`vem_mesh::polyhedral::geometry::face_vertex_weights`] (`int_F v . n dS = sum_x v_x . w_x^F`
//! for the face traces of the lowest-order element: linear on each fan triangle, the mean of
//! the vertex values at the fan centre). A uniform pressure `p` then loads vertex `x` with
//! exactly `p l_x`, the areas add up to the part's area, and on squares and triangles they are
//! the equal shares (a quarter, a third of each face).

use std::collections::HashMap;

use vem_mesh::polyhedral::geometry::{face_normal, vertex_mean};
use vem_mesh::{MeshError, Point3, PolyhedralMesh};

/// A part's rim turns into the rest of its body's boundary by at least this angle at a convex
/// edge (45 degrees, as a chain's corner in 2D): the contact must end there.
const CORNER_TURN: f64 = std::f64::consts::FRAC_PI_4;

/// The vertices on the rim of `part` of `mesh` (on an edge that only one face of the part
/// holds) where a contact zone could be cut short by the part's end: at least one of their
/// rim edges meets the rest of the body's boundary without a convex corner (the boundary face
/// beyond it turns by less than 45 degrees away from the part, or towards it). Sorted.
pub(crate) fn open_rim(mesh: &PolyhedralMesh, part: &str) -> Result<Vec<usize>, MeshError> {
    let faces = mesh.part_faces(part)?;
    let in_part: std::collections::HashSet<usize> = faces.iter().copied().collect();
    let mut open = Vec::new();
    for &f in faces {
        let normal = face_normal(&mesh.face_points(f));
        for &e in mesh.face_edges(f) {
            let holders = mesh
                .edge_faces(e)
                .iter()
                .filter(|g| in_part.contains(g))
                .count();
            if holders != 1 {
                continue;
            }
            // The other boundary face at the rim edge.
            let beyond = mesh
                .edge_faces(e)
                .iter()
                .copied()
                .find(|&g| g != f && mesh.is_boundary_face(g) && !in_part.contains(&g));
            let corner = beyond.is_some_and(|g| {
                let points = mesh.face_points(g);
                let other = face_normal(&points);
                let [p, _] = mesh.edge(e);
                // Convex: the face beyond lies on the body's side of the part's plane.
                let below = (vertex_mean(&points) - mesh.vertex(p)).dot(&normal) < 0.0;
                below && normal.dot(&other).clamp(-1.0, 1.0).acos() >= CORNER_TURN
            });
            if !corner {
                open.extend(mesh.edge(e));
            }
        }
    }
    open.sort_unstable();
    open.dedup();
    Ok(open)
}

/// The consistent mass matrix of the face traces on a surface, in the fan space of the
/// lowest-order element (linear on each fan triangle, the vertex mean at the fan centre), over
/// the faces `faces` (loops of node indices `0..n`), as one sorted row of `(column, value)`
/// per node. Its row sums are the tributary areas of the module docs (for planar faces).
pub(crate) fn surface_mass(
    n: usize,
    faces: &[Vec<usize>],
    points: &[Point3],
) -> Vec<Vec<(usize, f64)>> {
    let mut rows: Vec<HashMap<usize, f64>> = vec![HashMap::new(); n];
    for face in faces {
        let m = face.len();
        let corners: Vec<Point3> = face.iter().map(|&i| points[i]).collect();
        let centre = vertex_mean(&corners);
        for k in 0..m {
            let (p, q) = (corners[k], corners[(k + 1) % m]);
            let area = 0.5 * (p - centre).cross(&(q - centre)).norm();
            // Local values: centre = mean of the face's values, then the two vertices; the P1
            // mass matrix of a triangle is area / 12 (1 + delta_ij).
            let local = |node: usize| -> Vec<(usize, f64)> {
                // The weights of the face's nodes in triangle node `node` (0: centre).
                match node {
                    0 => face.iter().map(|&i| (i, 1.0 / m as f64)).collect(),
                    1 => vec![(face[k], 1.0)],
                    _ => vec![(face[(k + 1) % m], 1.0)],
                }
            };
            for a in 0..3 {
                for b in 0..3 {
                    let mab = area / 12.0 * if a == b { 2.0 } else { 1.0 };
                    for (i, wi) in local(a) {
                        for (j, wj) in local(b) {
                            *rows[i].entry(j).or_default() += mab * wi * wj;
                        }
                    }
                }
            }
        }
    }
    rows.into_iter()
        .map(|row| {
            let mut row: Vec<(usize, f64)> = row.into_iter().collect();
            row.sort_unstable_by_key(|&(j, _)| j);
            row
        })
        .collect()
}

/// The consistent pressure on a surface: the L2 projection of the nodal normal forces
/// `forces` onto the non-negative functions of the fan space on the faces `faces` (loops of
/// node indices), `min 1/2 c'Mc - f'c` over `c >= 0` with the mass matrix `M` of
/// [`surface_mass`], by projected Gauss-Seidel from the nodal pressure `f_i / M_i` (`M_i` the
/// row sum). Forces `f_i = p sum_j M_ij c_j` of a non-negative `c` are reproduced (so a uniform
/// pressure, forces `p l_i`, is); where the plain projection would dip below zero (just outside
/// a contact zone) the bounded one is the closest non-negative function in the `M` norm. Nodes
/// on no face keep `f_i / fallback_i`.
pub(crate) fn surface_pressure(
    faces: &[Vec<usize>],
    points: &[Point3],
    forces: &[f64],
    fallback: &[f64],
) -> Vec<f64> {
    let n = forces.len();
    let nodal = |i: usize| {
        if fallback[i] > 0.0 {
            forces[i] / fallback[i]
        } else {
            0.0
        }
    };
    let rows = surface_mass(n, faces, points);
    let mut c: Vec<f64> = (0..n)
        .map(|i| {
            let sum: f64 = rows[i].iter().map(|&(_, v)| v).sum();
            if rows[i].is_empty() || sum <= 0.0 {
                nodal(i)
            } else {
                (forces[i] / sum).max(0.0)
            }
        })
        .collect();
    let scale = c.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    // The Jacobi-scaled mass matrix of fan triangles is well conditioned on any mesh, so the
    // sweeps contract at a rate that does not depend on the mesh size.
    for _ in 0..MAX_SWEEPS {
        let mut change = 0.0f64;
        for i in 0..n {
            if rows[i].is_empty() {
                continue;
            }
            let (mut diagonal, mut off) = (0.0, 0.0);
            for &(j, v) in &rows[i] {
                if j == i {
                    diagonal += v;
                } else {
                    off += v * c[j];
                }
            }
            if diagonal <= 0.0 {
                continue;
            }
            let next = ((forces[i] - off) / diagonal).max(0.0);
            change = change.max((next - c[i]).abs());
            c[i] = next;
        }
        if change <= SWEEP_TOLERANCE * scale || !change.is_finite() {
            break;
        }
    }
    if c.iter().all(|v| v.is_finite()) {
        c
    } else {
        (0..n).map(nodal).collect()
    }
}

/// At most this many Gauss-Seidel sweeps of [`surface_pressure`].
const MAX_SWEEPS: usize = 2000;
/// The sweeps stop when no value changes by more than this fraction of the largest.
const SWEEP_TOLERANCE: f64 = 1e-13;

#[cfg(test)]
mod tests {
    use super::*;
    use vem_mesh::generators::polyhedral::{hexahedra, tetrahedra, Cuboid};
    use vem_mesh::polyhedral::overlay::boundary_surface;
    use vem_mesh::Vector3;

    #[test]
    fn tributary_areas_add_up_and_are_equal_shares_on_squares() {
        let cube = Cuboid::new(Point3::origin(), Point3::new(2.0, 1.0, 1.0));
        for mesh in [
            hexahedra(&cube, 4, 2, 2).unwrap(),
            tetrahedra(&cube, 4, 2, 2).unwrap(),
        ] {
            let top = boundary_surface(&mesh, "top").unwrap();
            let total: f64 = top.iter().map(|s| s.tributary_area).sum();
            assert!((total - 2.0).abs() < 1e-14);
            for s in &top {
                assert!((s.normal - Vector3::z()).norm() < 1e-15);
            }
        }
        let mesh = hexahedra(&cube, 4, 2, 2).unwrap();
        let top = boundary_surface(&mesh, "top").unwrap();
        let max = top.iter().map(|s| s.tributary_area).fold(0.0, f64::max);
        assert!((max - 0.25).abs() < 1e-15);
    }

    #[test]
    fn the_rim_of_a_box_side_is_at_corners_and_that_of_a_patch_is_open() {
        let mesh = hexahedra(&Cuboid::unit_cube(), 3, 3, 3).unwrap();
        assert!(open_rim(&mesh, "top").unwrap().is_empty());
        // The top's middle face only: its rim meets the rest of the flat top.
        let top = mesh.part_faces("top").unwrap().to_vec();
        let middle = top
            .iter()
            .copied()
            .find(|&f| {
                let c = mesh.face_centroid(f);
                (c.x - 0.5).abs() < 1e-12 && (c.y - 0.5).abs() < 1e-12
            })
            .unwrap();
        let rest: Vec<usize> = top.iter().copied().filter(|&f| f != middle).collect();
        let parts = vec![
            vem_mesh::FacePart::new("patch", vec![middle]),
            vem_mesh::FacePart::new("rest", rest),
        ];
        let mesh = mesh.with_parts(parts).unwrap();
        assert_eq!(open_rim(&mesh, "patch").unwrap().len(), 4);
    }

    #[test]
    fn the_projection_reproduces_uniform_and_bilinear_free_forces() {
        let mesh = tetrahedra(&Cuboid::unit_cube(), 3, 3, 1).unwrap();
        let top = boundary_surface(&mesh, "top").unwrap();
        let index: HashMap<usize, usize> =
            top.iter().enumerate().map(|(i, s)| (s.vertex, i)).collect();
        let faces: Vec<Vec<usize>> = mesh
            .part_faces("top")
            .unwrap()
            .iter()
            .map(|&f| mesh.face(f).iter().map(|v| index[v]).collect())
            .collect();
        let points: Vec<Point3> = top.iter().map(|s| s.point).collect();
        let areas: Vec<f64> = top.iter().map(|s| s.tributary_area).collect();
        // Uniform pressure 2.5.
        let forces: Vec<f64> = areas.iter().map(|a| 2.5 * a).collect();
        let p = surface_pressure(&faces, &points, &forces, &areas);
        assert!(p.iter().all(|p| (p - 2.5).abs() < 1e-12), "{p:?}");
        // Forces of a linear non-negative pressure through the mass matrix.
        let rows = surface_mass(points.len(), &faces, &points);
        let exact: Vec<f64> = points.iter().map(|x| 1.0 + x.x + 2.0 * x.y).collect();
        let forces: Vec<f64> = rows
            .iter()
            .map(|row| row.iter().map(|&(j, v)| v * exact[j]).sum())
            .collect();
        let p = surface_pressure(&faces, &points, &forces, &areas);
        for (a, b) in p.iter().zip(&exact) {
            assert!((a - b).abs() < 1e-10, "{a} {b}");
        }
    }
}
