//! h-refinement without constraints: Dorfler marking, and the refinement of any polygon into
//! one quadrilateral-like child per corner, its neighbours gaining the new points as plain
//! vertices (hanging nodes are vertices of the lowest-order VEM; nothing is constrained).
//!
//! # Corners, sides, midpoints
//!
//! A vertex of a polygon is a *corner* when the boundary turns there; a vertex between two
//! collinear edges (a hanging node, an inserted interface node) is not. The polygon's *sides*
//! join consecutive corners; a side may hold any number of hanging nodes. A refined polygon
//! with corners `c_0 .. c_{m-1}` is cut through a centre `z` and the side midpoints
//! `M_i = (c_i + c_{i+1}) / 2`: child `i` is the loop
//!
//! ```text
//!     c_i, (side i up to M_i), M_i, z, M_{i-1}, (side i-1 after M_{i-1})
//! ```
//!
//! so a polygon of `m` corners has `m` children (a quadrilateral when the sides hold no
//! other vertices; a triangle gives three, a quadrilateral four similar ones). The old
//! hanging nodes of a side go to the child they fall in. A side that already holds a vertex
//! within [`MIDPOINT_SNAP`] of its length from `M_i` (the midpoint a refined neighbour
//! inserted earlier, say) uses that vertex: no short edge is created beside it.
//!
//! # The centre
//!
//! `z` is the centroid of the polygon when the centroid lies in the polygon's kernel with a
//! margin of [`CENTRE_MARGIN`] of the diameter from every side line; otherwise (a non-convex
//! polygon whose centroid does not see its whole boundary) `z` is the Chebyshev centre of the
//! kernel ([`crate::quality::star_centre_and_radius`]), the centre of the largest ball the
//! polygon is star-shaped with respect to. Each child is then the union of the triangles from
//! `z` to its boundary pieces: a simple polygon, star-shaped with respect to `z`. A polygon
//! that is not star-shaped at all (empty kernel) is refused with an error naming it.
//!
//! # Neighbours and parts
//!
//! A midpoint that is not already a vertex is inserted into the mesh edge it falls on, and so
//! into the loops of both polygons of that edge: an unrefined neighbour gains a collinear
//! vertex, nothing else. A boundary-part edge that gains points becomes the pieces between
//! them, in the same part. Vertices keep their indices; new vertices are appended.
//!
//! ```
//! use vem_mesh::generators::{structured_quads, Rectangle};
//! use vem_mesh::refine::{dorfler_marking, refine};
//! let mesh = structured_quads(&Rectangle::unit_square(), 2, 2)?;
//! // Refine the cell with the largest indicator.
//! let marked = dorfler_marking(&[0.1, 0.1, 1.0, 0.1], 0.5)?;
//! assert_eq!(marked, vec![2]);
//! let refinement = refine(&mesh, &marked)?;
//! assert_eq!(refinement.mesh.n_polygons(), 3 + 4);
//! // Two neighbours gained a hanging node each.
//! assert_eq!(refinement.mesh.polygons().filter(|p| p.len() == 5).count(), 2);
//! let area: f64 = (0..refinement.mesh.n_polygons()).map(|p| refinement.mesh.area(p)).sum();
//! assert!((area - 1.0).abs() < 1e-15);
//! # Ok::<(), vem_mesh::MeshError>(())
//! ```

use std::collections::HashMap;

use crate::{geometry, quality, Mesh, MeshError, PartSpec, Point};

/// A vertex whose two edges turn by less than this sine of an angle is not a corner.
pub const COLLINEAR_SINE: f64 = 1e-9;

/// A side vertex closer to the side's midpoint than this fraction of the side's length is
/// used as the midpoint.
pub const MIDPOINT_SNAP: f64 = 0.1;

/// The centroid is the centre of a refined polygon when it is at least this fraction of the
/// polygon's diameter inside every side line; otherwise the kernel's Chebyshev centre is.
pub const CENTRE_MARGIN: f64 = 0.02;

/// The result of [`refine`]: the refined mesh and where its polygons come from.
#[derive(Debug, Clone, PartialEq)]
pub struct Refinement {
    /// The refined mesh (old vertices keep their indices, new ones are appended).
    pub mesh: Mesh,
    /// For each polygon of the refined mesh, the polygon of the old mesh it lies in.
    pub parent: Vec<usize>,
    /// Number of polygons refined.
    pub refined: usize,
    /// Number of refined polygons whose centre is the kernel's Chebyshev centre rather than
    /// the centroid (non-convex polygons whose centroid is too close to a side line).
    pub kernel_centres: usize,
}

/// Dorfler (bulk) marking: the smallest set of cells `M` whose squared indicators hold the
/// fraction `theta` of the total, `sum_{E in M} eta_E^2 >= theta sum_E eta_E^2`, taken in
/// decreasing order of `eta_E`. Returns the cells sorted by index (empty if every indicator
/// is 0).
///
/// # Errors
/// [`MeshError::InvalidOption`] when `theta` is not in (0, 1];
/// [`MeshError::BadGeneratorParameter`] naming the first cell whose indicator is negative or
/// not finite.
pub fn dorfler_marking(indicators: &[f64], theta: f64) -> Result<Vec<usize>, MeshError> {
    if !(theta > 0.0 && theta <= 1.0) {
        return Err(MeshError::InvalidOption {
            setting: "theta",
            value: theta,
            requirement: "in (0, 1]",
        });
    }
    if let Some(c) = indicators
        .iter()
        .position(|e| !(e.is_finite() && *e >= 0.0))
    {
        return Err(MeshError::BadGeneratorParameter {
            generator: "dorfler_marking",
            reason: format!(
                "the indicator of cell {c} is {}; indicators must be finite and >= 0",
                indicators[c]
            ),
        });
    }
    let total: f64 = indicators.iter().map(|e| e * e).sum();
    if total == 0.0 {
        return Ok(Vec::new());
    }
    let mut order: Vec<usize> = (0..indicators.len()).collect();
    order.sort_by(|&a, &b| indicators[b].total_cmp(&indicators[a]).then(a.cmp(&b)));
    let mut marked = Vec::new();
    let mut sum = 0.0;
    for c in order {
        if sum >= theta * total {
            break;
        }
        sum += indicators[c] * indicators[c];
        marked.push(c);
    }
    marked.sort_unstable();
    Ok(marked)
}

/// The local indices of the corners of the counter-clockwise loop `points` (the vertices
/// where the boundary turns; see the module docs).
pub fn corners(points: &[Point]) -> Vec<usize> {
    let n = points.len();
    (0..n)
        .filter(|&k| {
            let (a, b, c) = (points[(k + n - 1) % n], points[k], points[(k + 1) % n]);
            let (u, v) = (b - a, c - b);
            let cross = u.perp(&v);
            cross.abs() > COLLINEAR_SINE * u.norm() * v.norm() || u.dot(&v) <= 0.0
        })
        .collect()
}

/// Refines the polygons `marked` of `mesh` (see the module docs); the other polygons only
/// gain the new midpoints on their edges as vertices.
///
/// # Errors
/// [`MeshError::BadGeneratorParameter`] for a marked index out of range or a marked polygon
/// that is not star-shaped; the validation of [`Mesh::from_polygons`] (a valid mesh gives a
/// valid refined one).
pub fn refine(mesh: &Mesh, marked: &[usize]) -> Result<Refinement, MeshError> {
    let fail = |reason: String| MeshError::BadGeneratorParameter {
        generator: "refine",
        reason,
    };
    let n_polygons = mesh.n_polygons();
    let mut is_marked = vec![false; n_polygons];
    for &p in marked {
        if p >= n_polygons {
            return Err(fail(format!(
                "marked polygon {p}, but the mesh has {n_polygons} polygons"
            )));
        }
        is_marked[p] = true;
    }
    let mut vertices = mesh.vertices().to_vec();
    // Points inserted into each old edge: (parameter from edge.vertices[0], new vertex).
    let mut inserted: HashMap<usize, Vec<(f64, usize)>> = HashMap::new();
    // The midpoint vertex of each side of each marked polygon, keyed by (polygon, corner k).
    let mut midpoints: HashMap<(usize, usize), usize> = HashMap::new();
    for p in (0..n_polygons).filter(|&p| is_marked[p]) {
        let loop_vertices = mesh.polygon(p);
        let points = mesh.polygon_points(p);
        let loop_edges = mesh.polygon_edges(p);
        let n = points.len();
        let corner = corners(&points);
        let m = corner.len();
        if m < 3 {
            return Err(fail(format!("polygon {p} has {m} corners")));
        }
        for i in 0..m {
            let (start, end) = (corner[i], corner[(i + 1) % m]);
            let (a, b) = (points[start], points[end]);
            let length = (b - a).norm();
            let middle = Point::from((a.coords + b.coords) * 0.5);
            // Local vertices strictly inside the side, in order.
            let inner: Vec<usize> = (1..)
                .map(|j| (start + j) % n)
                .take_while(|&k| k != end)
                .collect();
            let nearest = inner
                .iter()
                .map(|&k| (k, (points[k] - middle).norm()))
                .min_by(|x, y| x.1.total_cmp(&y.1));
            if let Some((k, distance)) = nearest {
                if distance <= MIDPOINT_SNAP * length {
                    midpoints.insert((p, i), loop_vertices[k]);
                    continue;
                }
            }
            // The loop edge (local k -> k + 1) of the side that holds the midpoint.
            let t_side = |k: usize| (points[k] - a).dot(&(b - a)) / (length * length);
            let k = std::iter::once(start)
                .chain(inner.iter().copied())
                .find(|&k| {
                    let next = (k + 1) % n;
                    next == end || t_side(next) > 0.5
                })
                .unwrap_or(start);
            let e = loop_edges[k];
            let [e0, e1] = mesh.edge(e).vertices;
            let (q0, q1) = (mesh.vertex(e0), mesh.vertex(e1));
            let t = (middle - q0).dot(&(q1 - q0)) / (q1 - q0).norm_squared();
            let list = inserted.entry(e).or_default();
            let tolerance = 1e-12;
            let v = match list.iter().find(|(s, _)| (s - t).abs() <= tolerance) {
                Some(&(_, v)) => v,
                None => {
                    vertices.push(middle);
                    let v = vertices.len() - 1;
                    list.push((t, v));
                    v
                }
            };
            midpoints.insert((p, i), v);
        }
    }
    for list in inserted.values_mut() {
        list.sort_by(|x, y| x.0.total_cmp(&y.0));
    }
    // The loop of polygon p with the inserted points.
    let augmented = |p: usize| -> Vec<usize> {
        let mut out = Vec::with_capacity(mesh.polygon(p).len() + 4);
        for (&v, &e) in mesh.polygon(p).iter().zip(mesh.polygon_edges(p)) {
            out.push(v);
            if let Some(list) = inserted.get(&e) {
                if mesh.edge(e).vertices[0] == v {
                    out.extend(list.iter().map(|&(_, w)| w));
                } else {
                    out.extend(list.iter().rev().map(|&(_, w)| w));
                }
            }
        }
        out
    };
    let mut polygons: Vec<Vec<usize>> = Vec::with_capacity(n_polygons + 3 * marked.len());
    let mut parent = Vec::with_capacity(n_polygons + 3 * marked.len());
    let mut kernel_centres = 0;
    for p in 0..n_polygons {
        let full = augmented(p);
        if !is_marked[p] {
            polygons.push(full);
            parent.push(p);
            continue;
        }
        let points = mesh.polygon_points(p);
        let corner_vertices: Vec<usize> = corners(&points)
            .into_iter()
            .map(|k| mesh.polygon(p)[k])
            .collect();
        let m = corner_vertices.len();
        let (centre, by_kernel) = centre_of(&points).ok_or_else(|| {
            fail(format!(
                "polygon {p} is not star-shaped (its kernel is empty): it cannot be refined \
                 through a centre"
            ))
        })?;
        kernel_centres += usize::from(by_kernel);
        vertices.push(centre);
        let z = vertices.len() - 1;
        let position = |v: usize| full.iter().position(|&w| w == v).expect("loop vertex");
        let corner_at: Vec<usize> = corner_vertices.iter().map(|&v| position(v)).collect();
        let middle_at: Vec<usize> = (0..m).map(|i| position(midpoints[&(p, i)])).collect();
        let len = full.len();
        // The loop from local position `from` to `to`, both included, counter-clockwise.
        let walk = |from: usize, to: usize| -> Vec<usize> {
            let mut out = vec![full[from]];
            let mut k = from;
            while k != to {
                k = (k + 1) % len;
                out.push(full[k]);
            }
            out
        };
        for i in 0..m {
            let before = (i + m - 1) % m;
            let mut child = walk(middle_at[before], corner_at[i]);
            child.extend(walk(corner_at[i], middle_at[i]).into_iter().skip(1));
            child.push(z);
            polygons.push(child);
            parent.push(p);
        }
    }
    let parts = mesh
        .parts()
        .iter()
        .map(|part| {
            let edges = part
                .edges
                .iter()
                .flat_map(|&e| {
                    let [a, b] = mesh.edge(e).vertices;
                    let mut chain = vec![a];
                    if let Some(list) = inserted.get(&e) {
                        chain.extend(list.iter().map(|&(_, w)| w));
                    }
                    chain.push(b);
                    chain.windows(2).map(|w| [w[0], w[1]]).collect::<Vec<_>>()
                })
                .collect();
            PartSpec::new(part.name.clone(), edges)
        })
        .collect();
    let refined = is_marked.iter().filter(|&&m| m).count();
    let mesh = Mesh::from_polygons(vertices, &polygons, parts)?;
    Ok(Refinement {
        mesh,
        parent,
        refined,
        kernel_centres,
    })
}

/// [`refine`] every polygon.
///
/// # Errors
/// As [`refine`].
pub fn refine_uniformly(mesh: &Mesh) -> Result<Refinement, MeshError> {
    let all: Vec<usize> = (0..mesh.n_polygons()).collect();
    refine(mesh, &all)
}

/// The centre of a refined polygon (see the module docs) and whether it is the kernel's
/// Chebyshev centre; `None` when the polygon is not star-shaped.
fn centre_of(points: &[Point]) -> Option<(Point, bool)> {
    let centroid = geometry::centroid(points);
    let diameter = geometry::diameter(points);
    let n = points.len();
    let inside = (0..n).all(|k| {
        let (a, b) = (points[k], points[(k + 1) % n]);
        let t = b - a;
        t.perp(&(centroid - a)) / t.norm() >= CENTRE_MARGIN * diameter
    });
    if inside {
        return Some((centroid, false));
    }
    let (centre, radius) = quality::star_centre_and_radius(points);
    (radius > 0.0).then_some((centre, true))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generators::{
        hexagons, nonconvex, perturbed_quads, structured_quads, structured_triangles, voronoi,
        Rectangle,
    };
    use crate::quality::element_quality;

    fn total_area(mesh: &Mesh) -> f64 {
        (0..mesh.n_polygons()).map(|p| mesh.area(p)).sum()
    }

    fn part_length(mesh: &Mesh, name: &str) -> f64 {
        mesh.part(name)
            .unwrap()
            .edges
            .iter()
            .map(|&e| {
                let [a, b] = mesh.edge(e).vertices;
                (mesh.vertex(a) - mesh.vertex(b)).norm()
            })
            .sum()
    }

    #[test]
    fn dorfler_marks_the_smallest_bulk() {
        // Squares 16, 9, 4, 1, 0: theta = 0.5 of 30 needs 16 (one cell).
        assert_eq!(
            dorfler_marking(&[1.0, 0.0, 4.0, 3.0, 2.0], 0.5).unwrap(),
            [2]
        );
        // theta = 0.8 of 30 = 24 needs 16 + 9 = 25.
        assert_eq!(
            dorfler_marking(&[1.0, 0.0, 4.0, 3.0, 2.0], 0.8).unwrap(),
            [2, 3]
        );
        assert_eq!(
            dorfler_marking(&[1.0, 0.0, 4.0, 3.0, 2.0], 1.0).unwrap(),
            [0, 2, 3, 4]
        );
        assert!(dorfler_marking(&[0.0; 3], 0.5).unwrap().is_empty());
        assert!(matches!(
            dorfler_marking(&[1.0], 0.0),
            Err(MeshError::InvalidOption {
                setting: "theta",
                ..
            })
        ));
        let err = dorfler_marking(&[1.0, f64::NAN], 0.5).unwrap_err();
        assert!(err.to_string().contains("cell 1"), "{err}");
    }

    #[test]
    fn a_square_gives_four_similar_squares_and_neighbours_gain_vertices() {
        let mesh = structured_quads(&Rectangle::unit_square(), 3, 3).unwrap();
        let r = refine(&mesh, &[4]).unwrap();
        assert_eq!(r.mesh.n_polygons(), 8 + 4);
        assert_eq!(r.refined, 1);
        assert_eq!(r.kernel_centres, 0);
        // Children of the middle cell: squares of side 1/6.
        for (child, _) in r.parent.iter().enumerate().filter(|(_, &p)| p == 4) {
            assert_eq!(r.mesh.polygon(child).len(), 4);
            assert!((r.mesh.area(child) - 1.0 / 36.0).abs() < 1e-15);
        }
        // The four edge neighbours have five vertices, the corners four.
        let fives = r.mesh.polygons().filter(|p| p.len() == 5).count();
        assert_eq!(fives, 4);
        assert_eq!(r.mesh.n_vertices(), 16 + 4 + 1);
    }

    /// Ten cycles of refinement of the cells near a corner, on six families: the mesh stays
    /// valid, the area and the part lengths are kept, and the refined cells' children keep a
    /// star-shape ratio bounded below.
    #[test]
    fn ten_cycles_keep_area_parts_and_shape() {
        let rect = Rectangle::new(Point::new(-1.0, 0.0), Point::new(1.0, 1.5));
        let families: Vec<(&str, Mesh)> = vec![
            ("quads", structured_quads(&rect, 4, 3).unwrap()),
            ("triangles", structured_triangles(&rect, 4, 3).unwrap()),
            ("voronoi", voronoi(&rect, 20, 3).unwrap()),
            ("hexagons", hexagons(&rect, 4).unwrap()),
            ("nonconvex", nonconvex(&rect, 4).unwrap()),
            ("perturbed", perturbed_quads(&rect, 4, 0.3, 5).unwrap()),
        ];
        for (name, mut mesh) in families {
            let parts: Vec<(String, f64)> = mesh
                .part_names()
                .into_iter()
                .map(|p| {
                    let l = part_length(&mesh, &p);
                    (p, l)
                })
                .collect();
            let mut worst_child_star = f64::INFINITY;
            let mut first_star = f64::INFINITY;
            for p in 0..mesh.n_polygons() {
                first_star = first_star.min(element_quality(&mesh.polygon_points(p)).star_ratio);
            }
            for _cycle in 0..10 {
                // Mark the cells within a shrinking distance of the corner (1, 0).
                let target = Point::new(1.0, 0.0);
                let indicators: Vec<f64> = (0..mesh.n_polygons())
                    .map(|p| 1.0 / (1e-3 + (mesh.centroid(p) - target).norm()))
                    .collect();
                let marked = dorfler_marking(&indicators, 0.3).unwrap();
                let r = refine(&mesh, &marked).unwrap();
                crate::validate::validate(&r.mesh).unwrap();
                assert!(
                    (total_area(&r.mesh) - 3.0).abs() < 1e-12,
                    "{name}: area {}",
                    total_area(&r.mesh)
                );
                for (child, &p) in r.parent.iter().enumerate() {
                    if marked.binary_search(&p).is_ok() {
                        let q = element_quality(&r.mesh.polygon_points(child));
                        worst_child_star = worst_child_star.min(q.star_ratio);
                    }
                }
                for (part, length) in &parts {
                    let l = part_length(&r.mesh, part);
                    assert!((l - length).abs() < 1e-12, "{name}: {part} {l} {length}");
                }
                mesh = r.mesh;
            }
            eprintln!(
                "{name}: {} cells after ten cycles, children's star ratio >= {worst_child_star:.3} \
                 (initial mesh >= {first_star:.3})",
                mesh.n_polygons()
            );
            assert!(
                worst_child_star > 0.1 * first_star.min(0.2),
                "{name}: children's star ratio {worst_child_star}, initial {first_star}"
            );
        }
    }

    #[test]
    fn area_is_conserved_cell_by_cell() {
        let mesh = voronoi(&Rectangle::unit_square(), 30, 11).unwrap();
        let r = refine_uniformly(&mesh).unwrap();
        let mut sums = vec![0.0; mesh.n_polygons()];
        for (child, &p) in r.parent.iter().enumerate() {
            sums[p] += r.mesh.area(child);
        }
        for (p, sum) in sums.iter().enumerate() {
            assert!(
                (sum - mesh.area(p)).abs() <= 1e-14 * mesh.area(p).max(1.0),
                "{p}"
            );
        }
    }

    #[test]
    fn out_of_range_and_not_star_shaped_are_refused() {
        let mesh = structured_quads(&Rectangle::unit_square(), 1, 1).unwrap();
        let err = refine(&mesh, &[3]).unwrap_err();
        assert!(err.to_string().contains("marked polygon 3"), "{err}");
        // A comb: three teeth, no point sees all of it.
        let points = vec![
            Point::new(0.0, 0.0),
            Point::new(5.0, 0.0),
            Point::new(5.0, 3.0),
            Point::new(4.0, 3.0),
            Point::new(4.0, 0.2),
            Point::new(3.0, 0.2),
            Point::new(3.0, 3.0),
            Point::new(2.0, 3.0),
            Point::new(2.0, 0.2),
            Point::new(1.0, 0.2),
            Point::new(1.0, 3.0),
            Point::new(0.0, 3.0),
        ];
        let comb = Mesh::from_polygons(points, &[(0..12).collect()], vec![]).unwrap();
        let err = refine(&comb, &[0]).unwrap_err();
        assert!(
            err.to_string().contains("polygon 0 is not star-shaped"),
            "{err}"
        );
    }
}
