//! Shape-regularity figures of polyhedral cells: the three-dimensional analogue of assumption A1
//! (see [`crate::quality`] for the polygonal one).
//!
//! The usual mesh assumptions of the three-dimensional VEM (Beirão da Veiga, Dassi, Russo 2017;
//! Gain, Talischi, Paulino 2014) ask, for one gamma > 0 and every cell E with h_E = diam E:
//!
//! * E is star-shaped with respect to a ball of radius >= gamma h_E;
//! * every face F of E has h_F >= gamma h_E and is star-shaped (in its plane) with respect to a
//!   disc of radius >= gamma h_F;
//! * every edge of E is at least gamma h_E long (an edge joins two consecutive vertices of a
//!   face, so a hanging node splits a side in two).
//!
//! [`CellQuality`] gives these ratios for one cell, [`PolyhedralQualitySummary`] their
//! distribution over a mesh, and gamma of a mesh is the smallest of them all. The warping of
//! the faces (largest distance of a vertex from the face's mean plane over the face's diameter)
//! is reported beside them; it is 0 for planar faces.
//!
//! # The star-shaped radius
//!
//! E (its faces taken as fans, [`super::geometry`]) is star-shaped with respect to a ball B iff
//! B lies in its kernel, the intersection of the inner half-spaces n_T . x <= n_T . p_T of its
//! facets (the planar faces, and the fan triangles of the warped ones). The largest radius is the
//! Chebyshev radius of that system, the value of the linear programme
//!
//! ```text
//!     maximise r  subject to  n_T . c + r <= n_T . p_T  for every facet T
//! ```
//!
//! in the unknowns (c, r), always feasible (r may be negative) and bounded for a closed cell.
//! It is solved exactly, as its dual (minimise sum_T (n_T . p_T) y_T over y >= 0 with
//! sum_T y_T n_T = 0 and sum_T y_T = 1), by a dense two-phase simplex method with Bland's rule;
//! the centre and radius are the dual's multipliers. A negative optimum means the kernel is
//! empty: the cell is not star-shaped and its radius is 0. The same programme in the plane
//! gives each face's disc.
//!
//! ```
//! use vem_mesh::polyhedral::{geometry::Polyhedron, quality};
//! use vem_mesh::Point3;
//! let points: Vec<Point3> = (0..8)
//!     .map(|k| Point3::new((k & 1) as f64, (k >> 1 & 1) as f64, (k >> 2) as f64))
//!     .collect();
//! let faces = vec![
//!     vec![0, 4, 6, 2], vec![1, 3, 7, 5], vec![0, 1, 5, 4],
//!     vec![2, 6, 7, 3], vec![0, 2, 3, 1], vec![4, 5, 7, 6],
//! ];
//! let q = quality::cell_quality(&Polyhedron::new(points, &faces));
//! let h = 3f64.sqrt();
//! assert!((q.star_ratio - 0.5 / h).abs() < 1e-12);
//! assert!((q.shortest_edge_ratio - 1.0 / h).abs() < 1e-15);
//! assert!((q.gamma() - 0.5 / h).abs() < 1e-12);
//! ```

use std::fmt;

use super::geometry::{self, Polyhedron};
use super::validate::{project_on_plane, PLANARITY_RATIO};
use crate::quality::Spread;
use crate::{Point3, PolyhedralMesh, Vector3};

/// The shape-regularity figures of one polyhedral cell.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CellQuality {
    /// Diameter h_E (largest distance between two vertices).
    pub diameter: f64,
    /// Radius of the largest ball E is star-shaped with respect to, divided by h_E.
    pub star_ratio: f64,
    /// Shortest edge length divided by h_E.
    pub shortest_edge_ratio: f64,
    /// Smallest face diameter h_F divided by h_E.
    pub smallest_face_ratio: f64,
    /// Smallest over the faces of the radius of the largest disc the face (projected on its mean
    /// plane) is star-shaped with respect to, divided by h_F.
    pub face_star_ratio: f64,
    /// Largest over the faces of the distance of a vertex from the face's mean plane divided by
    /// h_F (0 when every face is planar).
    pub face_warping: f64,
}

impl CellQuality {
    /// The smallest of the four ratios: gamma of the cell alone.
    pub fn gamma(&self) -> f64 {
        self.star_ratio
            .min(self.shortest_edge_ratio)
            .min(self.smallest_face_ratio)
            .min(self.face_star_ratio)
    }
}

/// Figures of one face: (diameter, star radius / diameter, warping / diameter, shortest edge).
fn face_figures(points: &[Point3]) -> (f64, f64, f64, f64) {
    let diameter = geometry::diameter(points);
    let normal = geometry::face_normal(points);
    let n = points.len();
    let shortest = (0..n)
        .map(|k| (points[(k + 1) % n] - points[k]).norm())
        .fold(f64::INFINITY, f64::min);
    if diameter == 0.0 || normal == Vector3::zeros() {
        return (diameter, 0.0, 0.0, shortest);
    }
    let warping = geometry::face_warping(points) / diameter;
    let projected = project_on_plane(points, normal);
    let radius = polygon_star_radius(&projected);
    (diameter, radius / diameter, warping, shortest)
}

/// The shape-regularity figures of the polyhedron `cell` (faces oriented outward).
pub fn cell_quality(cell: &Polyhedron) -> CellQuality {
    let diameter = cell.diameter();
    let mut q = CellQuality {
        diameter,
        star_ratio: star_radius(cell) / diameter,
        shortest_edge_ratio: f64::INFINITY,
        smallest_face_ratio: f64::INFINITY,
        face_star_ratio: f64::INFINITY,
        face_warping: 0.0,
    };
    for k in 0..cell.n_faces() {
        let (h_f, star, warping, shortest) = face_figures(&cell.face_points(k));
        q.smallest_face_ratio = q.smallest_face_ratio.min(h_f / diameter);
        q.face_star_ratio = q.face_star_ratio.min(star);
        q.face_warping = q.face_warping.max(warping);
        q.shortest_edge_ratio = q.shortest_edge_ratio.min(shortest / diameter);
    }
    q
}

/// Radius of the largest disc the counter-clockwise polygon `points` is star-shaped with respect
/// to (0 when it is not star-shaped): the Chebyshev radius of the intersection of its edges'
/// inner half-planes, by the same linear programme as the cells' (module docs). It agrees with
/// [`crate::quality::star_radius`], which bisects on the radius instead.
pub fn polygon_star_radius(points: &[crate::Point]) -> f64 {
    let m = points.len();
    let centre = crate::geometry::vertex_mean(points);
    let scale = crate::geometry::diameter(points);
    if m < 3 || !(scale > 0.0 && scale.is_finite()) {
        return 0.0;
    }
    let mut normals = Vec::with_capacity(2 * m);
    let mut offsets = Vec::with_capacity(m);
    for k in 0..m {
        let a = (points[k] - centre) / scale;
        let t = (points[(k + 1) % m] - points[k]) / scale;
        let length = t.norm();
        if length > 1e-14 {
            let n = crate::Vector::new(t.y, -t.x) / length;
            normals.extend_from_slice(&[n.x, n.y]);
            offsets.push(n.dot(&a));
        }
    }
    match chebyshev_ball(2, &normals, &offsets) {
        Some((_, radius)) if radius > 0.0 => radius * scale,
        _ => 0.0,
    }
}

/// Radius of the largest ball the polyhedron `cell` is star-shaped with respect to (0 when it
/// is not star-shaped; see the module docs).
pub fn star_radius(cell: &Polyhedron) -> f64 {
    star_centre_and_radius(cell).1
}

/// Centre and radius of a largest ball the polyhedron `cell` is star-shaped with respect to: the
/// Chebyshev centre and radius of its kernel. For a cell that is not star-shaped the radius is
/// 0 and the centre is the vertex mean.
pub fn star_centre_and_radius(cell: &Polyhedron) -> (Point3, f64) {
    let points = cell.points();
    let origin = geometry::vertex_mean(points);
    let scale = cell.diameter();
    if !(scale > 0.0 && scale.is_finite()) {
        return (origin, 0.0);
    }
    // Facets in coordinates relative to the vertex mean, divided by the diameter.
    let local = |p: &Point3| (p - origin) / scale;
    let mut normals: Vec<f64> = Vec::new();
    let mut offsets: Vec<f64> = Vec::new();
    let mut push = |area: Vector3, point: Vector3| {
        let norm = area.norm();
        if norm > 1e-14 {
            let n = area / norm;
            normals.extend_from_slice(&[n.x, n.y, n.z]);
            offsets.push(n.dot(&point));
        }
    };
    for k in 0..cell.n_faces() {
        let face: Vec<Vector3> = cell.face(k).iter().map(|&v| local(&points[v])).collect();
        let face_points: Vec<Point3> = face.iter().map(|v| Point3::from(*v)).collect();
        let centre = geometry::vertex_mean(&face_points).coords;
        let area = geometry::face_vector_area(&face_points);
        let warped = geometry::face_warping(&face_points) > PLANARITY_RATIO * 1.0;
        if !warped {
            push(area, centre);
        } else {
            let n = face.len();
            for j in 0..n {
                let (a, b) = (face[j] - centre, face[(j + 1) % n] - centre);
                push(0.5 * a.cross(&b), face[j]);
            }
        }
    }
    match chebyshev_ball(3, &normals, &offsets) {
        Some((centre, radius)) if radius > 0.0 => (
            origin + scale * Vector3::new(centre[0], centre[1], centre[2]),
            radius * scale,
        ),
        _ => (origin, 0.0),
    }
}

/// The Chebyshev ball of {x in R^d : n_i . x <= b_i}: the centre and radius of a largest ball in
/// it, by the dual simplex method (module docs). `normals` holds the m unit normals row by row
/// (m x d), `offsets` the m right-hand sides. The radius is negative when the set is empty (the
/// value of max_c min_i (b_i - n_i . c)); `None` when the programme is unbounded or the normals
/// are degenerate.
pub(crate) fn chebyshev_ball(
    d: usize,
    normals: &[f64],
    offsets: &[f64],
) -> Option<(Vec<f64>, f64)> {
    let m = offsets.len();
    if m == 0 || normals.len() != m * d {
        return None;
    }
    // Dual: minimise offsets . y subject to A y = e_{d+1}, y >= 0, A = [normals^T; 1^T].
    let rows = d + 1;
    let mut a = vec![0.0; rows * m];
    for i in 0..m {
        for k in 0..d {
            a[k * m + i] = normals[i * d + k];
        }
        a[d * m + i] = 1.0;
    }
    let mut b = vec![0.0; rows];
    b[d] = 1.0;
    let multipliers = simplex_multipliers(&a, rows, m, &b, offsets)?;
    let radius = multipliers[d];
    Some((multipliers[..d].to_vec(), radius))
}

/// Minimises `cost . y` subject to `a y = b` (a: `rows` x `cols`, row-major; b >= 0), y >= 0,
/// by the two-phase tableau simplex method with Bland's rule, and returns the optimal
/// multipliers pi (the solution of the dual: maximise b . pi subject to a^T pi <= cost).
/// `None` when infeasible or unbounded.
fn simplex_multipliers(
    a: &[f64],
    rows: usize,
    cols: usize,
    b: &[f64],
    cost: &[f64],
) -> Option<Vec<f64>> {
    const EPS: f64 = 1e-11;
    let width = cols + rows + 1;
    let rhs = width - 1;
    let mut t = vec![0.0; (rows + 1) * width];
    for i in 0..rows {
        t[i * width..i * width + cols].copy_from_slice(&a[i * cols..(i + 1) * cols]);
        t[i * width + cols + i] = 1.0;
        t[i * width + rhs] = b[i];
    }
    let mut basis: Vec<usize> = (cols..cols + rows).collect();
    let z = rows * width; // the reduced-cost row
                          // Phase 1: minimise the sum of the artificial variables.
    for j in 0..width {
        let is_artificial = j >= cols && j < cols + rows;
        let column_sum: f64 = (0..rows).map(|i| t[i * width + j]).sum();
        t[z + j] = if is_artificial { 0.0 } else { -column_sum };
    }
    run_simplex(&mut t, &mut basis, rows, width, cols + rows, EPS)?;
    if -t[z + rhs] > 1e-9 {
        return None; // infeasible
    }
    // Drive the artificial variables out of the basis where possible.
    for i in 0..rows {
        if basis[i] >= cols {
            if let Some(j) = (0..cols).find(|&j| t[i * width + j].abs() > EPS) {
                pivot(&mut t, rows, width, i, j);
                basis[i] = j;
            }
        }
    }
    // Phase 2: the reduced costs of the true objective (artificial columns cost 0).
    for j in 0..width {
        let own = if j < cols { cost[j] } else { 0.0 };
        let mut r = if j == rhs { 0.0 } else { own };
        for i in 0..rows {
            let cb = if basis[i] < cols { cost[basis[i]] } else { 0.0 };
            r -= cb * t[i * width + j];
        }
        t[z + j] = r;
    }
    run_simplex(&mut t, &mut basis, rows, width, cols, EPS)?;
    // The reduced cost of artificial column i is -pi_i.
    Some((0..rows).map(|i| -t[z + cols + i]).collect())
}

/// Simplex iterations on the tableau `t` (last row: reduced costs, last column: right-hand
/// side) with entering columns among the first `enter_limit`; `None` when unbounded or when
/// it does not terminate in a generous number of pivots.
fn run_simplex(
    t: &mut [f64],
    basis: &mut [usize],
    rows: usize,
    width: usize,
    enter_limit: usize,
    eps: f64,
) -> Option<()> {
    let z = rows * width;
    let rhs = width - 1;
    for _ in 0..50 * (width + rows) {
        // Bland's rule: the first column with a negative reduced cost enters.
        let Some(j) = (0..enter_limit).find(|&j| t[z + j] < -eps) else {
            return Some(());
        };
        let mut leave: Option<(usize, f64)> = None;
        for i in 0..rows {
            let aij = t[i * width + j];
            if aij > eps {
                let ratio = t[i * width + rhs] / aij;
                let better = match leave {
                    None => true,
                    Some((l, best)) => {
                        ratio < best - 1e-14 || (ratio <= best + 1e-14 && basis[i] < basis[l])
                    }
                };
                if better {
                    leave = Some((i, ratio));
                }
            }
        }
        let (i, _) = leave?;
        pivot(t, rows, width, i, j);
        basis[i] = j;
    }
    None
}

fn pivot(t: &mut [f64], rows: usize, width: usize, pr: usize, pc: usize) {
    let p = t[pr * width + pc];
    for j in 0..width {
        t[pr * width + j] /= p;
    }
    for i in 0..=rows {
        if i == pr {
            continue;
        }
        let factor = t[i * width + pc];
        if factor != 0.0 {
            for j in 0..width {
                t[i * width + j] -= factor * t[pr * width + j];
            }
        }
    }
}

/// The distribution of the shape-regularity figures over a polyhedral mesh.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PolyhedralQualitySummary {
    /// Number of cells.
    pub cells: usize,
    /// Cell diameters h_E; `diameter.max` is the mesh size h.
    pub diameter: Spread,
    /// Star-shaped radius / h_E.
    pub star_ratio: Spread,
    /// Shortest edge / h_E.
    pub shortest_edge_ratio: Spread,
    /// Smallest face diameter / h_E.
    pub smallest_face_ratio: Spread,
    /// Smallest face star-shaped radius / h_F.
    pub face_star_ratio: Spread,
    /// Largest face warping / h_F.
    pub face_warping: Spread,
    /// gamma of the mesh: the smallest of the four ratios over all cells.
    pub gamma: f64,
}

impl PolyhedralQualitySummary {
    /// Mesh size h = max h_E.
    pub fn mesh_size(&self) -> f64 {
        self.diameter.max
    }
}

impl fmt::Display for PolyhedralQualitySummary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "{} cells, h = {:.4e}, gamma = {:.4}",
            self.cells,
            self.mesh_size(),
            self.gamma
        )?;
        writeln!(f, "{:<24}{:>11}{:>11}{:>11}", "", "min", "median", "max")?;
        for (name, s) in [
            ("h_E", self.diameter),
            ("star radius / h_E", self.star_ratio),
            ("shortest edge / h_E", self.shortest_edge_ratio),
            ("smallest h_F / h_E", self.smallest_face_ratio),
            ("face star radius / h_F", self.face_star_ratio),
            ("face warping / h_F", self.face_warping),
        ] {
            writeln!(
                f,
                "{name:<24}{:>11.4e}{:>11.4e}{:>11.4e}",
                s.min, s.median, s.max
            )?;
        }
        Ok(())
    }
}

/// The figures of every cell of `mesh`, in cell order.
pub fn cell_qualities(mesh: &PolyhedralMesh) -> Vec<CellQuality> {
    // Face figures once per face, then gathered per cell.
    let faces: Vec<(f64, f64, f64, f64)> = (0..mesh.n_faces())
        .map(|f| face_figures(&mesh.face_points(f)))
        .collect();
    (0..mesh.n_cells())
        .map(|c| {
            let cell = mesh.cell_polyhedron(c);
            let diameter = cell.diameter();
            let mut q = CellQuality {
                diameter,
                star_ratio: star_radius(&cell) / diameter,
                shortest_edge_ratio: f64::INFINITY,
                smallest_face_ratio: f64::INFINITY,
                face_star_ratio: f64::INFINITY,
                face_warping: 0.0,
            };
            for slot in mesh.cell_faces(c) {
                let (h_f, star, warping, shortest) = faces[slot.face];
                q.smallest_face_ratio = q.smallest_face_ratio.min(h_f / diameter);
                q.face_star_ratio = q.face_star_ratio.min(star);
                q.face_warping = q.face_warping.max(warping);
                q.shortest_edge_ratio = q.shortest_edge_ratio.min(shortest / diameter);
            }
            q
        })
        .collect()
}

/// The distribution of the figures over `mesh`.
pub fn summarise(mesh: &PolyhedralMesh) -> PolyhedralQualitySummary {
    let qualities = cell_qualities(mesh);
    let pick = |f: fn(&CellQuality) -> f64| -> Vec<f64> { qualities.iter().map(f).collect() };
    let star_ratio = Spread::of(&pick(|q| q.star_ratio));
    let shortest_edge_ratio = Spread::of(&pick(|q| q.shortest_edge_ratio));
    let smallest_face_ratio = Spread::of(&pick(|q| q.smallest_face_ratio));
    let face_star_ratio = Spread::of(&pick(|q| q.face_star_ratio));
    PolyhedralQualitySummary {
        cells: qualities.len(),
        diameter: Spread::of(&pick(|q| q.diameter)),
        star_ratio,
        shortest_edge_ratio,
        smallest_face_ratio,
        face_star_ratio,
        face_warping: Spread::of(&pick(|q| q.face_warping)),
        gamma: star_ratio
            .min
            .min(shortest_edge_ratio.min)
            .min(smallest_face_ratio.min)
            .min(face_star_ratio.min),
    }
}

impl PolyhedralMesh {
    /// The shape-regularity figures of cell `c`.
    pub fn cell_quality(&self, c: usize) -> CellQuality {
        cell_quality(&self.cell_polyhedron(c))
    }

    /// The distribution of the figures over the mesh (see [`summarise`]).
    pub fn quality(&self) -> PolyhedralQualitySummary {
        summarise(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn chebyshev_ball_of_a_square_and_of_an_empty_set() {
        // [0, 2] x [0, 1]: largest disc radius 1/2, centre y = 1/2.
        let normals = [1.0, 0.0, -1.0, 0.0, 0.0, 1.0, 0.0, -1.0];
        let offsets = [2.0, 0.0, 1.0, 0.0];
        let (centre, radius) = chebyshev_ball(2, &normals, &offsets).unwrap();
        assert_relative_eq!(radius, 0.5, epsilon = 1e-14);
        assert_relative_eq!(centre[1], 0.5, epsilon = 1e-14);
        assert!(centre[0] >= 0.5 - 1e-14 && centre[0] <= 1.5 + 1e-14);
        // x <= 0 and x >= 1 (and y bounded): empty, value -1/2.
        let normals = [1.0, 0.0, -1.0, 0.0, 0.0, 1.0, 0.0, -1.0];
        let offsets = [0.0, -1.0, 1.0, 1.0];
        let (_, radius) = chebyshev_ball(2, &normals, &offsets).unwrap();
        assert_relative_eq!(radius, -0.5, epsilon = 1e-14);
    }

    #[test]
    fn regular_tetrahedron_inradius() {
        // Regular tetrahedron of edge sqrt 8: inradius a / sqrt 24 = 1/sqrt 3, h = a.
        let points = vec![
            Point3::new(1.0, 1.0, 1.0),
            Point3::new(1.0, -1.0, -1.0),
            Point3::new(-1.0, 1.0, -1.0),
            Point3::new(-1.0, -1.0, 1.0),
        ];
        let mut faces = vec![vec![0, 1, 2], vec![0, 3, 1], vec![0, 2, 3], vec![1, 3, 2]];
        let probe = Polyhedron::new(points.clone(), &faces);
        if probe.volume() < 0.0 {
            for f in &mut faces {
                f.reverse();
            }
        }
        let tet = Polyhedron::new(points, &faces);
        let (centre, radius) = star_centre_and_radius(&tet);
        assert_relative_eq!(radius, 1.0 / 3f64.sqrt(), max_relative = 1e-12);
        assert!(centre.coords.norm() < 1e-12);
        let q = cell_quality(&tet);
        assert_relative_eq!(q.diameter, 8f64.sqrt(), max_relative = 1e-15);
        assert_relative_eq!(q.shortest_edge_ratio, 1.0, max_relative = 1e-15);
        // Equilateral faces: inradius / side = 1 / (2 sqrt 3).
        assert_relative_eq!(
            q.face_star_ratio,
            1.0 / (2.0 * 3f64.sqrt()),
            max_relative = 1e-10
        );
        assert!(q.face_warping < 1e-15);
    }
}
