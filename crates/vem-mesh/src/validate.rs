//! Mesh validation: every constructor of [`crate::Mesh`] runs these checks.
//!
//! Checks, in the order they run (the first failure is returned):
//!
//! 1. storage: offsets, index range, repeated indices in a loop, at least three vertices per
//!    polygon, finite coordinates ([`MeshError::BadStorage`], [`MeshError::VertexOutOfRange`],
//!    [`MeshError::RepeatedVertex`], [`MeshError::TooFewVertices`],
//!    [`MeshError::NonFiniteVertex`]); edges used by more than two polygons or twice in the same
//!    direction are rejected while the edges are derived ([`MeshError::OverusedEdge`]);
//! 2. duplicate vertices: two distinct vertices used by polygons and closer than the
//!    coincidence tolerance ([`MeshError::DuplicateVertices`]);
//! 3. per polygon: simplicity (no two of its edges cross or touch away from a shared end point,
//!    no edge folds back onto the previous one: [`MeshError::SelfIntersecting`]), then area
//!    ([`MeshError::DegenerateArea`], also for an area that overflows) and orientation ([`MeshError::Clockwise`]);
//! 4. conformity, on the boundary edges (those of one polygon): an end point of one lying in
//!    the interior of another, or two crossing ([`MeshError::NonConforming`],
//!    [`MeshError::Overlapping`]); see "Why the boundary suffices" for the interior edges;
//! 5. wedges: around every vertex, the corners of the polygons meeting there must not overlap
//!    ([`MeshError::Overlapping`]); the same pass notes edges next to each other around a
//!    vertex that come within the coincidence tolerance (see "Tolerances");
//! 6. covering: just to the right of every boundary loop (the side away from its polygons), no
//!    polygon covers the plane ([`MeshError::Overlapping`]).
//!
//! When 4, 5 or 6 fails, or 5 noted edges within the tolerance, the exhaustive forms of 4–6
//! decide: every pair of edges of different polygons (a vertex in the interior of another
//! polygon's edge, a hanging node the neighbour does not list or collinear edges overlapping
//! without shared vertices: [`MeshError::NonConforming`]; two edges crossing:
//! [`MeshError::Overlapping`]), the wedges, and the nesting of connected components (a vertex
//! of one strictly inside a polygon of another: [`MeshError::Overlapping`]). The first error
//! they find is returned, so that the error and the polygons, edges and vertices it names are
//! those of the exhaustive checks. Only when these find nothing is the error of step 6 returned
//! (the polygon of a boundary loop's edge and one that covers the plane beside it); after
//! edges noted within the tolerance, the mesh is then accepted.
//!
//! # Why the boundary suffices
//!
//! Let N(p) be the number of polygons whose interior holds a point p that lies on no edge.
//!
//! - (a) Every polygon is simple, counter-clockwise and of positive area (step 3), so the
//!   winding number of its loop about p is 1 inside it and 0 outside: N(p) is the winding
//!   number about p of the sum of all polygon loops.
//! - (b) Every edge is used by at most two polygons, in opposite directions (the derivation of
//!   the edges): in that sum the interior edges cancel, and N(p) = w(B, p), the winding number
//!   of the boundary edges B, each directed with its polygon on its left.
//! - (d) The boundary edges meet only at shared end vertices (step 4): N is constant on each
//!   face of the plane cut along B, and across a boundary edge it grows by exactly 1 from the
//!   edge's right to its left.
//! - (e) N is 0 just to the right of every boundary loop (step 6). Every face of the plane cut
//!   along B is bordered by some boundary edge and lies on its right (N = 0) or on its left
//!   (N = 0 + 1): N <= 1 everywhere, so no two polygons overlap.
//!
//! One count per loop is enough: where loops meet at a vertex (polygons that share only that
//! vertex), an incoming edge is chained to the first outgoing one counter-clockwise from it,
//! so that the strip just to the right of a loop meets no other loop, and N, constant off B,
//! is the same all along it. The count is the winding number of B at a point just right of
//! the middle of one of the loop's edges (signed crossings of a horizontal ray, with the
//! loops whose boxes meet that edge's).
//!
//! What the exhaustive check finds besides, for exact coordinates, (a), (b), (d) and (e) find
//! too. Two edges crossing make the polygons beside them overlap. A vertex x in the interior
//! of an edge g of another polygon without an overlap: if g had polygons on both sides, those
//! would cover a neighbourhood of g's interior, which x's polygons enter; so g is a boundary
//! edge, and x is on the boundary too (else its polygons cover a disc around it, which meets
//! g's polygon), and a boundary edge ending at x touches g: step 4 on the boundary. The
//! wedges (c, step 5) are not needed for the argument (overlapping corners are overlapping
//! polygons); step 5 keeps its own error and pairs the loops at vertices where several meet.
//! Steps 4 and 6 thus cost O(boundary edges) pair tests instead of O(edges), plus one count
//! per loop (over the loops near it: quadratic only in the number of loops whose boxes nest).
//!
//! The side tests (which side of an edge a point lies, the order of two edges along a line)
//! are floating-point orientation tests, as in the exhaustive check.
//!
//! # Tolerances
//!
//! Coincidence is decided relative to the mesh size: the tolerance is
//! [`COINCIDENCE_RATIO`] times the mean over the polygons of the diagonal of their bounding
//! box (a stand-in for h_T within a factor sqrt 2, computable in linear time). Two vertices
//! closer than it are duplicates; a vertex closer than it to an edge, and farther than it from
//! both end points, lies in the edge's interior. A polygon is degenerate when
//! |area| <= [`DEGENERATE_AREA_RATIO`] times its squared bounding-box diagonal.
//!
//! The exhaustive check also rejects a vertex within the tolerance of another polygon's edge
//! that does not overlap anything exactly, which the argument above does not see unless the
//! two edges are on the boundary (step 4 uses the same tolerance there). Without an overlap,
//! the polygons between the vertex and the edge must be thinner than the tolerance there: in
//! every such case met in random moves of vertices (three in 3000, a triangle with a vertex
//! 1e-10 off its opposite edge, vertices moved onto a neighbour's edge), two edges next to
//! each other around a vertex came within the tolerance (the far end of one within the
//! tolerance of the other's interior), which step 5 notes, sending the mesh to the exhaustive
//! check. This is shown by test, not proved: a vertex within the tolerance of an interior edge
//! of polygons it shares no vertex with, across a polygon thinner than the tolerance, may
//! still be accepted where the exhaustive check rejected it.
//!
//! # Cost
//!
//! Everything is close to linear in the size of the mesh: duplicates by sorting the vertices
//! (a radix sort of one `u64` key) by the coarse cell, a block of 2^16 x 2^16 cells of side
//! 4 x tolerance, that holds them and looking in the neighbouring cells only when the
//! tolerance box reaches them; boundary edge pairs (step 4) through grids of cells, one per
//! class of edge length, each edge filed in the few cells it passes through and the edges
//! visited in the order of a space-filling curve, so that graded meshes cost no more than
//! uniform ones and the work stays in cache; corners by one angle per edge, sorted around each vertex; the covering by
//! chaining the boundary edges and one count per loop. Only polygons that are not convex are
//! checked pair by pair (through a grid when they have more than 64 edges). On a Gmsh mesh of
//! 147 000 triangles, steps 4 and 6 take 10 million instructions, 3 % of a build, where the
//! exhaustive edge-pair check took 713 million, 63 % of a build 2.8 times as costly
//! (docs/benchmarks.md, "Reading and writing meshes"). On meshes of at least 50 000 edges,
//! steps 4–6 run on a second thread beside steps 2 and 3.
//!
//! A vertex within the tolerance of another polygon's edge is found even when it lies just
//! outside the edge's bounding box (a hanging node a hair below a horizontal edge).
//!
//! A mesh made from a valid one by changes at a few vertices (interface node insertion moves
//! and inserts vertices along the interface) is validated near the change only: the same
//! checks, on the polygons with a changed vertex against everything near them.

use crate::{Mesh, MeshError, Point, Vector};

/// Relative area below which a polygon counts as degenerate: |area| <= this * diagonal^2,
/// with the diagonal of the polygon's bounding box.
pub const DEGENERATE_AREA_RATIO: f64 = 1e-12;

/// Relative coincidence tolerance: vertices closer than this times the mean polygon size (mean
/// bounding-box diagonal) are duplicates, and a vertex that close to an edge lies on it.
pub const COINCIDENCE_RATIO: f64 = 1e-10;

/// Polygons with more edges than this are checked for self-intersection through a grid rather
/// than pair by pair.
const BRUTE_FORCE_EDGES: usize = 64;

/// Meshes with at least this many edges check edge pairs (step 4) on a second thread.
const PARALLEL_EDGES: usize = 50_000;

/// Angular slack (radians) when comparing corners around a vertex.
const ANGLE_TOLERANCE: f64 = 1e-9;

/// Checks the compact storage before edges are derived.
pub(crate) fn check_storage(
    vertices: &[Point],
    offsets: &[usize],
    indices: &[usize],
) -> Result<(), MeshError> {
    if vertices.is_empty() || offsets.len() < 2 {
        return Err(MeshError::Empty {
            vertices: vertices.len(),
            polygons: offsets.len().saturating_sub(1),
        });
    }
    if let Some((vertex, p)) = vertices
        .iter()
        .enumerate()
        .find(|(_, p)| !(p.x.is_finite() && p.y.is_finite()))
    {
        return Err(MeshError::NonFiniteVertex {
            vertex,
            x: p.x,
            y: p.y,
        });
    }
    let last = offsets[offsets.len() - 1];
    if offsets[0] != 0 || last != indices.len() {
        return Err(MeshError::BadStorage {
            reason: format!(
                "offsets must start at 0 and end at the number of indices ({}), found {} .. {}",
                indices.len(),
                offsets[0],
                last
            ),
        });
    }
    if let Some(p) = (0..offsets.len() - 1).find(|&p| offsets[p + 1] < offsets[p]) {
        return Err(MeshError::BadStorage {
            reason: format!("offsets decrease at polygon {p}"),
        });
    }
    let mut sorted = Vec::new();
    for p in 0..offsets.len() - 1 {
        let loop_ = &indices[offsets[p]..offsets[p + 1]];
        if loop_.len() < 3 {
            return Err(MeshError::TooFewVertices {
                polygon: p,
                count: loop_.len(),
            });
        }
        if let Some(&vertex) = loop_.iter().find(|&&v| v >= vertices.len()) {
            return Err(MeshError::VertexOutOfRange {
                polygon: p,
                vertex,
                vertex_count: vertices.len(),
            });
        }
        if let Some(vertex) = smallest_repeated(loop_, &mut sorted) {
            return Err(MeshError::RepeatedVertex { polygon: p, vertex });
        }
    }
    Ok(())
}

/// Checks a mesh whose storage and edges are consistent (steps 2–6 of the module docs).
///
/// Steps 4 and 6 run in their boundary form ([`check_boundary_conformity`],
/// [`check_covering`]); when a check of steps 4–6 fails, [`exhaustive_from_step_4`] runs the
/// checks of every edge pair, the corners and the nesting of components, so that the error
/// reported (its kind, the polygons and edges it names) is the one the exhaustive checks find
/// first.
pub(crate) fn validate(mesh: &Mesh) -> Result<(), MeshError> {
    // An extent that overflows leaves the coincidence tests to the area check below.
    let tolerance = coincidence_tolerance(mesh).min(f64::MAX);
    let polygons = || -> Result<(), MeshError> {
        let mut points = Vec::new();
        for p in 0..mesh.n_polygons() {
            points.clear();
            points.extend(mesh.polygon(p).iter().map(|&v| mesh.vertex(v)));
            check_polygon(p, &points, tolerance)?;
        }
        Ok(())
    };
    // Ok(true): passed, but with edges next to each other around a vertex within the
    // tolerance (see `check_corners_at`), for the exhaustive edge-pair check to judge.
    let steps_4_to_6 = || -> Result<bool, MeshError> {
        check_boundary_conformity(mesh, tolerance)?;
        let near = check_corners_at(mesh, None, Some(tolerance))?;
        check_covering(mesh)?;
        Ok(near)
    };
    let judge = |result: Result<bool, MeshError>| match result {
        Ok(false) => Ok(()),
        Ok(true) => check_conformity(mesh, tolerance),
        Err(fast) => exhaustive_from_step_4(mesh, tolerance, fast),
    };
    if mesh.n_edges() < PARALLEL_EDGES {
        check_duplicate_vertices(mesh, tolerance)?;
        polygons()?;
        return judge(steps_4_to_6());
    }
    // Steps 4–6 on a second thread beside steps 2 and 3; the first failure in the order of
    // the steps is returned, as when they run one after the other.
    std::thread::scope(|scope| {
        let after = scope.spawn(steps_4_to_6);
        let before = check_duplicate_vertices(mesh, tolerance).and_then(|()| polygons());
        let after = after
            .join()
            .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
        before.and_then(|()| judge(after))
    })
}

/// Steps 4–6 in their exhaustive form, after the boundary form failed with `fast`: every
/// edge pair ([`check_conformity`]), the corners, the nesting of components. Returns the
/// first error these find, else `fast` (which names the loop that failed).
fn exhaustive_from_step_4(mesh: &Mesh, tolerance: f64, fast: MeshError) -> Result<(), MeshError> {
    check_conformity(mesh, tolerance)?;
    check_corners(mesh)?;
    check_nesting(mesh)?;
    Err(fast)
}

/// Steps 4–6 as they were before their boundary form: every edge pair, the corners, the
/// nesting of components (for tests that compare the two).
#[cfg(test)]
fn validate_exhaustive(mesh: &Mesh) -> Result<(), MeshError> {
    let tolerance = coincidence_tolerance(mesh).min(f64::MAX);
    check_duplicate_vertices(mesh, tolerance)?;
    let mut points = Vec::new();
    for p in 0..mesh.n_polygons() {
        points.clear();
        points.extend(mesh.polygon(p).iter().map(|&v| mesh.vertex(v)));
        check_polygon(p, &points, tolerance)?;
    }
    check_conformity(mesh, tolerance)?;
    check_corners(mesh)?;
    check_nesting(mesh)
}

/// Checks a mesh made from a valid mesh by changes at the vertices `changed` only (vertices
/// moved, or inserted into edges, as interface node insertion does): the checks of
/// [`validate`] that such a change can fail, on what lies near it. A check that involves only
/// polygons without a changed vertex passed on the valid mesh (whose coincidence tolerance
/// differs from this one's by the change of a few polygons' boxes in the mean) and is not
/// repeated:
///
/// - storage (index range, repeats, size), simplicity, area and orientation of the polygons
///   with a changed vertex, finite coordinates of the changed vertices;
/// - duplicates: the changed vertices against every vertex;
/// - conformity: the edges of the polygons with a changed vertex against every edge;
/// - corners: around every vertex of those polygons (the only vertices whose edges moved);
/// - nesting: the exhaustive form of step 6, no component inside a polygon of another (one
///   pass over the polygons; nothing more for a mesh in one piece).
///
/// The work is one pass over the vertices, polygons and edges plus what is near the change,
/// against the grids and sorts of the whole validation.
pub(crate) fn validate_changed(mesh: &Mesh, changed: &[usize]) -> Result<(), MeshError> {
    let n = mesh.n_vertices();
    let mut is_changed = vec![false; n];
    for &v in changed {
        let p = mesh.vertex(v);
        if !(p.x.is_finite() && p.y.is_finite()) {
            return Err(MeshError::NonFiniteVertex {
                vertex: v,
                x: p.x,
                y: p.y,
            });
        }
        is_changed[v] = true;
    }
    let touched: Vec<usize> = (0..mesh.n_polygons())
        .filter(|&p| mesh.polygon(p).iter().any(|&v| is_changed[v]))
        .collect();
    if touched.is_empty() {
        return Ok(());
    }
    let tolerance = coincidence_tolerance(mesh).min(f64::MAX);
    // Step 1 and 3 for the touched polygons.
    let mut points = Vec::new();
    let mut sorted = Vec::new();
    for &p in &touched {
        let loop_ = mesh.polygon(p);
        if loop_.len() < 3 {
            return Err(MeshError::TooFewVertices {
                polygon: p,
                count: loop_.len(),
            });
        }
        if let Some(vertex) = smallest_repeated(loop_, &mut sorted) {
            return Err(MeshError::RepeatedVertex { polygon: p, vertex });
        }
    }
    check_changed_duplicates(mesh, changed, tolerance)?;
    for &p in &touched {
        points.clear();
        points.extend(mesh.polygon(p).iter().map(|&v| mesh.vertex(v)));
        check_polygon(p, &points, tolerance)?;
    }
    check_changed_conformity(mesh, &touched, tolerance)?;
    let mut around = vec![false; n];
    for &p in &touched {
        for &v in mesh.polygon(p) {
            around[v] = true;
        }
    }
    check_corners_at(mesh, Some(&around), None)?;
    check_nesting(mesh)
}

/// Step 2 for the vertices `changed`: none within `tolerance` of another vertex used by a
/// polygon. The changed vertices are sorted by x; every vertex looks for partners in its
/// x-range by binary search.
fn check_changed_duplicates(
    mesh: &Mesh,
    changed: &[usize],
    tolerance: f64,
) -> Result<(), MeshError> {
    let vertices = mesh.vertices();
    let mut used = vec![false; mesh.n_vertices()];
    for &v in mesh.polygon_vertex_indices() {
        used[v] = true;
    }
    let mut by_x: Vec<usize> = changed.iter().copied().filter(|&v| used[v]).collect();
    by_x.sort_by(|&a, &b| vertices[a].x.total_cmp(&vertices[b].x));
    by_x.dedup();
    let Some((&first, &last)) = by_x.first().zip(by_x.last()) else {
        return Ok(());
    };
    let (lo, hi) = (vertices[first].x - tolerance, vertices[last].x + tolerance);
    let mut found: Option<(usize, usize, f64)> = None;
    for (b, pb) in vertices.iter().enumerate() {
        if !used[b] || pb.x < lo || pb.x > hi {
            continue;
        }
        let start = by_x.partition_point(|&a| vertices[a].x < pb.x - tolerance);
        for &a in &by_x[start..] {
            let pa = vertices[a];
            if pa.x > pb.x + tolerance {
                break;
            }
            let distance = (pa - pb).norm();
            if a != b && distance <= tolerance {
                let pair = (a.min(b), a.max(b));
                if found.is_none_or(|(fa, fb, _)| pair < (fa, fb)) {
                    found = Some((pair.0, pair.1, distance));
                }
            }
        }
    }
    match found {
        Some((a, b, distance)) => Err(MeshError::DuplicateVertices {
            a,
            b,
            distance,
            tolerance,
        }),
        None => Ok(()),
    }
}

/// Step 4 for the edges of the polygons `touched` against every edge: the touched edges are
/// filed in a grid, every edge of the mesh near them is tested against those in its cells.
fn check_changed_conformity(
    mesh: &Mesh,
    touched: &[usize],
    tolerance: f64,
) -> Result<(), MeshError> {
    let edges = mesh.edges();
    let mut mine: Vec<usize> = touched
        .iter()
        .flat_map(|&p| mesh.polygon_edges(p).iter().copied())
        .collect();
    mine.sort_unstable();
    mine.dedup();
    let segment = |e: usize| edges[e].vertices.map(|v| mesh.vertex(v));
    let widened = |e: usize| {
        let b = Aabb::of_points(segment(e).into_iter());
        Aabb {
            min: Point::new(b.min.x - tolerance, b.min.y - tolerance),
            max: Point::new(b.max.x + tolerance, b.max.y + tolerance),
        }
    };
    let boxes: Vec<Aabb> = mine.iter().map(|&e| widened(e)).collect();
    let all = Aabb::of_points(boxes.iter().flat_map(|b| [b.min, b.max]));
    let grid = Grid::new(&boxes);
    let mut found: Option<((usize, usize), Conflict)> = None;
    for (f, edge) in edges.iter().enumerate() {
        let b = Aabb::of_points(edge.vertices.map(|v| mesh.vertex(v)).into_iter());
        if !b.intersects(&all) {
            continue;
        }
        grid.for_each_in(&b, |i| {
            let e = mine[i];
            if e == f || !boxes[i].intersects(&b) {
                return;
            }
            let (ea, eb) = (&edges[e], &edges[f]);
            let (pa, qa) = (ea.left, ea.right.unwrap_or(usize::MAX));
            let (pb, qb) = (eb.left, eb.right.unwrap_or(usize::MAX));
            if pa == pb || pa == qb || (qa != usize::MAX && (qa == pb || qa == qb)) {
                return; // a pair within one polygon: checked by `self_intersection`
            }
            let pair = (e.min(f), e.max(f));
            if found.is_some_and(|(best, _)| best <= pair) {
                return;
            }
            let (first, second) = (pair.0, pair.1);
            let conflict = segments_conflict(
                edges[first].vertices,
                segment(first),
                edges[second].vertices,
                segment(second),
                tolerance,
            );
            if conflict != Conflict::None {
                found = Some((pair, conflict));
            }
        });
    }
    conflict_error(mesh, found)
}

/// The coincidence tolerance of `mesh`: [`COINCIDENCE_RATIO`] times the mean bounding-box
/// diagonal of its polygons.
pub fn coincidence_tolerance(mesh: &Mesh) -> f64 {
    let total: f64 = (0..mesh.n_polygons())
        .map(|p| Aabb::of_points(mesh.polygon(p).iter().map(|&v| mesh.vertex(v))).diagonal())
        .sum();
    COINCIDENCE_RATIO * total / mesh.n_polygons() as f64
}

/// The cell (of side 4 * `tolerance`) of the duplicate check that holds (x, y): `as`
/// saturates, so far-away points share border cells, which costs time, not truth. For a
/// tolerance of 0, the coordinates' bits.
fn duplicate_cell(x: f64, y: f64, tolerance: f64) -> (i64, i64) {
    let cell = 4.0 * tolerance;
    if cell > 0.0 {
        (floor_to_i64(x / cell), floor_to_i64(y / cell))
    } else {
        (x.to_bits() as i64, y.to_bits() as i64)
    }
}

/// The duplicate pair `found` (the smallest, with its distance) as the result of step 2.
fn duplicate_error(found: Option<(usize, usize, f64)>, tolerance: f64) -> Result<(), MeshError> {
    match found {
        Some((a, b, distance)) => Err(MeshError::DuplicateVertices {
            a,
            b,
            distance,
            tolerance,
        }),
        None => Ok(()),
    }
}

/// Shift from the cells of [`duplicate_cell`] to the coarse cells of
/// [`check_duplicate_vertices`]: 2^16 fine cells a side, or more when the fine cells of the
/// mesh span more than 2^31 coarse ones along x or y.
const COARSE_SHIFT: u32 = 16;

/// The smallest vertex listed twice in `loop_`: pair by pair in short loops, else by sorting a
/// copy in `sorted` (a buffer reused across loops).
fn smallest_repeated(loop_: &[usize], sorted: &mut Vec<usize>) -> Option<usize> {
    if loop_.len() <= 8 {
        let mut smallest: Option<usize> = None;
        for (i, &u) in loop_.iter().enumerate() {
            if loop_[i + 1..].contains(&u) && smallest.is_none_or(|s| u < s) {
                smallest = Some(u);
            }
        }
        smallest
    } else {
        sorted.clear();
        sorted.extend_from_slice(loop_);
        sorted.sort_unstable();
        sorted.windows(2).find(|w| w[0] == w[1]).map(|w| w[0])
    }
}

/// Step 2: no two distinct vertices used by polygons closer than `tolerance`.
///
/// The pairs tested are those of [`check_duplicate_vertices_fine`]: a vertex a and a vertex
/// b whose fine cell (of side 4 * tolerance, [`duplicate_cell`]) is among those a's
/// tolerance box touches, and the smallest pair (a < b) within the tolerance is reported.
/// They are found through coarse cells, each a block of 2^s x 2^s fine cells (s at least
/// [`COARSE_SHIFT`]), packed into one `u64` key: the vertices sorted by that key, a vertex's
/// partners lie in its own run of the sorted list (no search) and, when its tolerance box
/// reaches a neighbouring coarse cell (a chance of about 2^-17 per axis), in that cell's run,
/// found by binary search. A coarse cell holds one vertex unless vertices are closer than
/// 2^16 tolerances (10^-5 times the mean polygon diameter); when the runs hold too many pairs
/// (clustered vertices, a tolerance of 0, coordinates whose cells saturate), the fine check
/// decides.
fn check_duplicate_vertices(mesh: &Mesh, tolerance: f64) -> Result<(), MeshError> {
    let vertices = mesh.vertices();
    let mut used = vec![false; vertices.len()];
    for &v in mesh.polygon_vertex_indices() {
        used[v] = true;
    }
    // A tolerance of 0 (or NaN) has no cells of positive side.
    let positive = tolerance > 0.0;
    if !positive || u32::try_from(vertices.len()).is_err() {
        return check_duplicate_vertices_fine(mesh, &used, tolerance);
    }
    let fine = |v: usize| duplicate_cell(vertices[v].x, vertices[v].y, tolerance);
    let (mut lo, mut hi) = ((i64::MAX, i64::MAX), (i64::MIN, i64::MIN));
    for v in (0..vertices.len()).filter(|&v| used[v]) {
        let (cx, cy) = fine(v);
        lo = (lo.0.min(cx), lo.1.min(cy));
        hi = (hi.0.max(cx), hi.1.max(cy));
    }
    if lo.0 > hi.0 {
        return Ok(()); // no vertex used (a mesh always uses some)
    }
    // The shift s that makes the coarse cells of the used vertices span less than 2^31 along
    // each axis.
    let bits = |span: u64| 64 - span.leading_zeros();
    let span_of = |lo: i64, hi: i64| hi.wrapping_sub(lo) as u64;
    let span = bits(span_of(lo.0, hi.0).max(span_of(lo.1, hi.1)));
    let shift = COARSE_SHIFT.max(span.saturating_sub(31));
    let (base_x, base_y) = (lo.0 >> shift, lo.1 >> shift);
    let (top_x, top_y) = (hi.0 >> shift, hi.1 >> shift);
    // Coarse cell (clamped to those of the used vertices) -> key, in the order of (x, y).
    let coarse = |c: (i64, i64)| -> (i64, i64) {
        (
            (c.0 >> shift).clamp(base_x, top_x),
            (c.1 >> shift).clamp(base_y, top_y),
        )
    };
    let pack = |c: (i64, i64)| -> u64 {
        ((c.0.wrapping_sub(base_x) as u64) << 32) | (c.1.wrapping_sub(base_y) as u64)
    };
    let mut sorted: Vec<(u64, u32)> = (0..vertices.len())
        .filter(|&v| used[v])
        .map(|v| (pack(coarse(fine(v))), v as u32))
        .collect();
    // By key (y in bits 0..32, x above), ties in the order of the vertices.
    radix_sort(
        &mut sorted,
        &[
            (0, bits(span_of(base_y, top_y))),
            (32, bits(span_of(base_x, top_x))),
        ],
    );
    // Pairs within runs: too many, and the fine check decides.
    let (mut pairs, mut run) = (0usize, 0usize);
    for (i, &(key, _)) in sorted.iter().enumerate() {
        run = if i > 0 && sorted[i - 1].0 == key {
            run + 1
        } else {
            1
        };
        pairs += 2 * run - 1; // run^2 once the run ends
    }
    if pairs > 4 * sorted.len() + 1024 {
        return check_duplicate_vertices_fine(mesh, &used, tolerance);
    }
    let mut found: Option<(usize, usize, f64)> = None;
    let mut run_start = 0;
    for i in 0..sorted.len() {
        let (key, a) = (sorted[i].0, sorted[i].1 as usize);
        if key != sorted[run_start].0 {
            run_start = i;
        }
        let pa = vertices[a];
        let (near_lo, near_hi) = (
            duplicate_cell(pa.x - tolerance, pa.y - tolerance, tolerance),
            duplicate_cell(pa.x + tolerance, pa.y + tolerance, tolerance),
        );
        // b is a partner when its fine cell is among those of a's tolerance box.
        let mut visit = |b: usize| {
            if a >= b {
                return;
            }
            let (cx, cy) = fine(b);
            if (near_lo.0..=near_hi.0).contains(&cx) && (near_lo.1..=near_hi.1).contains(&cy) {
                let distance = (vertices[b] - pa).norm();
                if distance <= tolerance && found.is_none_or(|(fa, fb, _)| (a, b) < (fa, fb)) {
                    found = Some((a, b, distance));
                }
            }
        };
        let (clo, chi) = (coarse(near_lo), coarse(near_hi));
        for cx in clo.0..=chi.0 {
            for cy in clo.1..=chi.1 {
                let k = pack((cx, cy));
                let start = if k == key {
                    run_start
                } else {
                    sorted.partition_point(|&(s, _)| s < k)
                };
                for &(s, b) in &sorted[start..] {
                    if s != k {
                        break;
                    }
                    visit(b as usize);
                }
            }
        }
    }
    duplicate_error(found, tolerance)
}

/// Sorts `items` by their keys, stably (a least-significant-digit radix sort), given the
/// keys' `fields` (first bit, number of bits), least significant first: every bit of a key
/// that may be set lies in one of them.
fn radix_sort(items: &mut Vec<(u64, u32)>, fields: &[(u32, u32)]) {
    const DIGIT: u32 = 12;
    let mut other = vec![(0u64, 0u32); items.len()];
    let mut count = Vec::new();
    for &(first, bits) in fields {
        if bits == 0 {
            continue;
        }
        let passes = bits.div_ceil(DIGIT);
        let width = bits.div_ceil(passes);
        let mask = (1u64 << width) - 1;
        for pass in 0..passes {
            let shift = first + pass * width;
            count.clear();
            count.resize(1usize << width, 0usize);
            for &(key, _) in items.iter() {
                count[((key >> shift) & mask) as usize] += 1;
            }
            let mut total = 0;
            for c in count.iter_mut() {
                let here = *c;
                *c = total;
                total += here;
            }
            for &item in items.iter() {
                let digit = ((item.0 >> shift) & mask) as usize;
                other[count[digit]] = item;
                count[digit] += 1;
            }
            std::mem::swap(items, &mut other);
        }
    }
}

/// [`check_duplicate_vertices`] through the fine cells directly (`used[v]`: vertex v is used
/// by a polygon).
///
/// The vertices are sorted by the cell (of side 4 * tolerance) that holds them; each vertex
/// then looks for partners in the at most 2 x 2 cells its tolerance disc touches, by binary
/// search in the sorted list.
fn check_duplicate_vertices_fine(
    mesh: &Mesh,
    used: &[bool],
    tolerance: f64,
) -> Result<(), MeshError> {
    let vertices = mesh.vertices();
    let key = |x: f64, y: f64| duplicate_cell(x, y, tolerance);
    let mut sorted: Vec<((i64, i64), usize)> = (0..vertices.len())
        .filter(|&v| used[v])
        .map(|v| (key(vertices[v].x, vertices[v].y), v))
        .collect();
    sorted.sort_unstable();
    let mut found: Option<(usize, usize, f64)> = None;
    for &(_, a) in &sorted {
        let pa = vertices[a];
        let (lo, hi) = (
            key(pa.x - tolerance, pa.y - tolerance),
            key(pa.x + tolerance, pa.y + tolerance),
        );
        for cx in lo.0..=hi.0 {
            for cy in lo.1..=hi.1 {
                let start = sorted.partition_point(|&(k, _)| k < (cx, cy));
                for &(k, b) in &sorted[start..] {
                    if k != (cx, cy) {
                        break;
                    }
                    let distance = (vertices[b] - pa).norm();
                    if a < b && distance <= tolerance {
                        let better = found.is_none_or(|(fa, fb, _)| (a, b) < (fa, fb));
                        if better {
                            found = Some((a, b, distance));
                        }
                    }
                }
            }
        }
    }
    duplicate_error(found, tolerance)
}

/// Step 3 for one polygon given by its points: simple, non-degenerate, counter-clockwise.
fn check_polygon(polygon: usize, points: &[Point], tolerance: f64) -> Result<(), MeshError> {
    if let Some((edge_a, edge_b)) = self_intersection(points, tolerance) {
        return Err(MeshError::SelfIntersecting {
            polygon,
            edge_a,
            edge_b,
        });
    }
    let area = crate::geometry::signed_area(points);
    let diagonal = Aabb::of_points(points.iter().copied()).diagonal();
    // A non-finite area (coordinates so large that products overflow) is no usable polygon.
    if !area.is_finite() || area.abs() <= DEGENERATE_AREA_RATIO * diagonal * diagonal {
        return Err(MeshError::DegenerateArea { polygon, area });
    }
    if area < 0.0 {
        return Err(MeshError::Clockwise {
            polygon,
            signed_area: area,
        });
    }
    Ok(())
}

/// The first pair of local edges (k < l; edge k joins points k and k + 1) of the closed loop
/// `points` that cross or touch away from a shared end point, if any.
///
/// A loop whose turns are all strictly left and whose total turning is 2 pi is convex and
/// simple, and is accepted at once; others are checked pair by pair.
pub fn self_intersection(points: &[Point], tolerance: f64) -> Option<(usize, usize)> {
    let m = points.len();
    if is_convex_loop(points) {
        return None;
    }
    let edge = |k: usize| -> ([usize; 2], [Point; 2]) {
        let l = (k + 1) % m;
        ([k, l], [points[k], points[l]])
    };
    let test = |k: usize, l: usize| -> bool {
        let (ia, a) = edge(k);
        let (ib, b) = edge(l);
        segments_conflict(ia, a, ib, b, tolerance) != Conflict::None
    };
    if m <= BRUTE_FORCE_EDGES {
        for k in 0..m {
            for l in k + 1..m {
                if test(k, l) {
                    return Some((k, l));
                }
            }
        }
        return None;
    }
    let boxes: Vec<Aabb> = (0..m)
        .map(|k| Aabb::of_points(edge(k).1.into_iter()))
        .collect();
    let mut found: Option<(usize, usize)> = None;
    Grid::new(&boxes).for_each_pair(&boxes, |k, l| {
        let pair = (k.min(l), k.max(l));
        if found.is_none_or(|f| pair < f) && test(pair.0, pair.1) {
            found = Some(pair);
        }
    });
    found
}

/// True when every turn of the loop is strictly to the left (or straight on) and the total
/// turning is one full turn: the loop is then convex and simple.
///
/// The turning of a closed loop is a whole number of turns, each turn of a loop turning only
/// left is less than half a turn, so a triangle or quadrangle turning only left turns once:
/// its angles need not be summed.
fn is_convex_loop(points: &[Point]) -> bool {
    let m = points.len();
    let mut turning = 0.0;
    let sum_angles = m > 4;
    for k in 0..m {
        let incoming = points[k] - points[if k == 0 { m - 1 } else { k - 1 }];
        let outgoing = points[if k + 1 == m { 0 } else { k + 1 }] - points[k];
        let c = cross(incoming, outgoing);
        let d = incoming.dot(&outgoing);
        if c < 0.0 || (c == 0.0 && d <= 0.0) {
            return false;
        }
        if sum_angles {
            turning += c.atan2(d);
        }
    }
    !sum_angles || (turning - std::f64::consts::TAU).abs() < 1e-6
}

/// Step 4: edges of different polygons neither cross nor touch away from shared vertices.
fn check_conformity(mesh: &Mesh, tolerance: f64) -> Result<(), MeshError> {
    conflict_error(mesh, first_conflict(mesh, None, tolerance))
}

/// Step 4 on the boundary edges only: they neither cross nor touch away from shared vertices
/// (condition (d) of the module docs). A conflict found here is one of
/// [`check_conformity`]'s too (the same test on a subset of the pairs).
fn check_boundary_conformity(mesh: &Mesh, tolerance: f64) -> Result<(), MeshError> {
    let boundary: Vec<usize> = (0..mesh.n_edges())
        .filter(|&e| mesh.edges()[e].right.is_none())
        .collect();
    conflict_error(mesh, first_conflict(mesh, Some(&boundary), tolerance))
}

/// The error for the conflict `found` (the edge pair and how its edges meet), if any.
fn conflict_error(mesh: &Mesh, found: Option<((usize, usize), Conflict)>) -> Result<(), MeshError> {
    let edges = mesh.edges();
    match found {
        None => Ok(()),
        Some(((e, f), conflict)) => {
            let (ea, eb) = (&edges[e], &edges[f]);
            Err(match conflict {
                Conflict::Cross => MeshError::Overlapping {
                    a: ea.left,
                    b: eb.left,
                },
                _ => MeshError::NonConforming {
                    polygon_a: ea.left,
                    a0: ea.vertices[0],
                    a1: ea.vertices[1],
                    polygon_b: eb.left,
                    b0: eb.vertices[0],
                    b1: eb.vertices[1],
                },
            })
        }
    }
}

/// The smallest pair of edges (among `subset`, every edge for `None`) of different polygons
/// that cross or touch away from shared vertices, and how they meet.
fn first_conflict(
    mesh: &Mesh,
    subset: Option<&[usize]>,
    tolerance: f64,
) -> Option<((usize, usize), Conflict)> {
    let edges = mesh.edges();
    let midpoint = |e: usize| {
        let [a, b] = edges[e].vertices.map(|v| mesh.vertex(v));
        Point::new(0.5 * (a.x + b.x), 0.5 * (a.y + b.y))
    };
    // The edges in the order of a space-filling curve through their midpoints, so that edges
    // close in the plane are close in memory (a mesh's own numbering need not be).
    let order: Vec<usize> = match subset {
        None => spatial_order((0..edges.len()).map(midpoint)),
        Some(ids) => spatial_order(ids.iter().map(|&e| midpoint(e)))
            .into_iter()
            .map(|i| ids[i])
            .collect(),
    };
    let segments: Vec<[Point; 2]> = order
        .iter()
        .map(|&e| edges[e].vertices.map(|v| mesh.vertex(v)))
        .collect();
    // The polygons on either side of each edge (`usize::MAX`: none), and its vertices.
    let sides: Vec<[usize; 2]> = order
        .iter()
        .map(|&e| [edges[e].left, edges[e].right.unwrap_or(usize::MAX)])
        .collect();
    let vertices: Vec<[usize; 2]> = order.iter().map(|&e| edges[e].vertices).collect();
    let lengths: Vec<f64> = segments.iter().map(|s| (s[1] - s[0]).norm()).collect();
    // Keep the conflict with the smallest edge pair, so the report does not depend on the
    // order in which pairs are found.
    let mut found: Option<((usize, usize), Conflict)> = None;
    let test = |i: usize, k: usize| {
        let ([pa, qa], [pb, qb]) = (sides[i], sides[k]);
        if pa == pb || pa == qb || (qa != usize::MAX && (qa == pb || qa == qb)) {
            return; // a pair within one polygon: checked by `self_intersection`
        }
        // Segments farther apart than the tolerance in x or y cannot meet.
        let ([a0, a1], [b0, b1]) = (segments[i], segments[k]);
        if a0.x.max(a1.x) + tolerance < b0.x.min(b1.x)
            || b0.x.max(b1.x) + tolerance < a0.x.min(a1.x)
            || a0.y.max(a1.y) + tolerance < b0.y.min(b1.y)
            || b0.y.max(b1.y) + tolerance < a0.y.min(a1.y)
        {
            return;
        }
        let (e, f) = (order[i], order[k]);
        let (first, second) = if e < f { (i, k) } else { (k, i) };
        let pair = (e.min(f), e.max(f));
        if found.is_some_and(|(best, _)| best <= pair) {
            return;
        }
        let conflict = segments_conflict_with_lengths(
            vertices[first],
            segments[first],
            lengths[first],
            vertices[second],
            segments[second],
            lengths[second],
            tolerance,
        );
        if conflict != Conflict::None {
            found = Some((pair, conflict));
        }
    };
    // Segments that conflict come within the tolerance of each other.
    match SegmentGrid::new(&segments, tolerance) {
        Some(grid) => grid.for_each_pair(&segments, test),
        None => {
            let boxes: Vec<Aabb> = segments
                .iter()
                .map(|s| Aabb::of_points(s.iter().copied()))
                .collect();
            Grid::new(&boxes).for_each_pair(&boxes, test);
        }
    }
    found
}

/// Step 5: around each vertex, the polygon corners (angular sectors from the outgoing edge
/// counter-clockwise to the incoming one) do not overlap.
///
/// The direction of every edge is computed once (one `atan2` per edge); a ray from a vertex
/// along an edge takes that angle or the opposite one, so the two corners meeting along an
/// edge see the same angle bit for bit. The corners are computed polygon by polygon and filed
/// under their vertex in compressed storage, then sorted by angle around each vertex.
fn check_corners(mesh: &Mesh) -> Result<(), MeshError> {
    check_corners_at(mesh, None, None).map(|_| ())
}

/// [`check_corners`] around the vertices `v` with `only[v]` (every vertex for `None`).
///
/// With a `tolerance`, also tells whether two edges next to each other around a vertex (the
/// two edges of a corner, or the edges on either side of a gap between corners) come so
/// close that the far end of one lies within the tolerance of the other's interior: a
/// configuration that the exhaustive edge-pair check may reject as non-conforming (through an
/// edge of another polygon at that far end) although no polygons overlap, which the boundary
/// form of steps 4 and 6 does not see. The pairs are filtered by their angle, which must be
/// below pi/2 times the tolerance over the shortest edge of the mesh (a few multiplications per
/// corner; the lengths are computed only for the pairs that pass).
fn check_corners_at(
    mesh: &Mesh,
    only: Option<&[bool]>,
    tolerance: Option<f64>,
) -> Result<bool, MeshError> {
    use std::f64::consts::{FRAC_PI_2, PI, TAU};
    let n = mesh.n_vertices();
    let wanted = |v: usize| only.is_none_or(|only| only[v]);
    let indices = mesh.polygon_vertex_indices();
    let offsets = mesh.polygon_offsets();
    let mut start = vec![0usize; n + 1];
    for &v in indices {
        if wanted(v) {
            start[v + 1] += 1;
        }
    }
    for v in 0..n {
        start[v + 1] += start[v];
    }
    let direction_of = |e: usize| {
        let edge = &mesh.edges()[e];
        let d = mesh.vertex(edge.vertices[1]) - mesh.vertex(edge.vertices[0]);
        d.y.atan2(d.x)
    };
    let length_of = |e: usize| {
        let edge = &mesh.edges()[e];
        (mesh.vertex(edge.vertices[1]) - mesh.vertex(edge.vertices[0])).norm()
    };
    // Every edge's direction once (the whole mesh), or on demand around a few vertices; the
    // shortest edge's squared length in the same pass (for the whole mesh with a tolerance).
    let mut shortest_squared = f64::INFINITY;
    let direction: Vec<f64> = if only.is_none() {
        let with_lengths = tolerance.is_some();
        mesh.edges()
            .iter()
            .map(|edge| {
                let d = mesh.vertex(edge.vertices[1]) - mesh.vertex(edge.vertices[0]);
                if with_lengths {
                    shortest_squared = shortest_squared.min(d.norm_squared());
                }
                d.y.atan2(d.x)
            })
            .collect()
    } else {
        if tolerance.is_some() {
            shortest_squared = mesh
                .edges()
                .iter()
                .map(|edge| {
                    (mesh.vertex(edge.vertices[1]) - mesh.vertex(edge.vertices[0])).norm_squared()
                })
                .fold(f64::INFINITY, f64::min);
        }
        Vec::new()
    };
    // Two edges at a vertex whose far ends come within the tolerance of each other's
    // interior are less than `bound` apart in angle: sin(angle) >= 2 angle / pi below a
    // right angle, and the shorter edge is at least the shortest of the mesh.
    let bound = tolerance.map_or(0.0, |tolerance| {
        (FRAC_PI_2 * tolerance / shortest_squared.sqrt()).min(FRAC_PI_2)
    });
    // The angles of the rays along edge `e` from its end `v` and from its other end, in
    // (-pi, pi].
    let rays = |e: usize, v: usize| -> (f64, f64) {
        let edge = &mesh.edges()[e];
        let along = if direction.is_empty() {
            direction_of(e)
        } else {
            direction[e]
        };
        let back = {
            let angle = along + PI;
            if angle > PI {
                angle - TAU
            } else {
                angle
            }
        };
        if edge.vertices[0] == v {
            (along, back)
        } else {
            (back, along)
        }
    };
    // Whether edges `e` and `f` at a common vertex, `angle` apart, come within the tolerance.
    let close = |e: usize, f: usize, angle: f64| -> bool {
        let Some(tolerance) = tolerance else {
            return false;
        };
        if e == f || angle.abs() > bound {
            return false;
        }
        let (le, lf) = (length_of(e), length_of(f));
        if le.min(lf) * angle.sin().abs() > tolerance {
            return false;
        }
        let edges = mesh.edges();
        let segment = |e: usize| edges[e].vertices.map(|v| mesh.vertex(v));
        let (ve, vf) = (edges[e].vertices, edges[f].vertices);
        segments_conflict_with_lengths(ve, segment(e), le, vf, segment(f), lf, tolerance)
            != Conflict::None
    };
    // (to - from).rem_euclid(TAU) bit for bit, without its division: the angles lie in
    // (-pi, pi], so the difference is above -TAU.
    let opening_of = |from: f64, to: f64| {
        let d = to - from;
        if d < 0.0 {
            d + TAU
        } else {
            d
        }
    };
    let mut near = false;
    // (start angle, end angle, slot of the corner in the polygons' vertex lists), filed by
    // vertex.
    let mut fill = start.clone();
    let mut sectors = vec![(0.0f64, 0.0f64, 0usize); start[n]];
    for (p, &offset) in offsets[..mesh.n_polygons()].iter().enumerate() {
        let loop_ = mesh.polygon(p);
        let loop_edges = mesh.polygon_edges(p);
        let m = loop_.len();
        // With every direction at hand, the ray into corner k along local edge k - 1 (from
        // vertex k) is carried from the previous corner: each local edge is looked at once.
        let carry = !direction.is_empty();
        let mut into_ray = if carry {
            rays(loop_edges[m - 1], loop_[0]).0
        } else {
            0.0
        };
        for (k, &v) in loop_.iter().enumerate() {
            let (out, into) = (
                loop_edges[k],
                loop_edges[if k == 0 { m - 1 } else { k - 1 }],
            );
            let carried = if carry {
                let (from, next_into) = rays(out, v);
                let to = std::mem::replace(&mut into_ray, next_into);
                Some((from, to))
            } else {
                None
            };
            if !wanted(v) {
                continue;
            }
            let single = start[v + 1] - start[v] < 2;
            if single && tolerance.is_none() {
                continue;
            }
            let (from, to) = carried.unwrap_or_else(|| (rays(out, v).0, rays(into, v).0));
            let opening = opening_of(from, to);
            if !near && !(bound..=TAU - bound).contains(&opening) {
                near = close(out, into, opening.min(TAU - opening));
            }
            if !single {
                sectors[fill[v]] = (from, to, offset + k);
                fill[v] += 1;
            }
        }
    }
    let polygon_of = |slot: usize| offsets.partition_point(|&o| o <= slot) - 1;
    // The edges that leave and enter the corner at `slot`.
    let corner_edges = |slot: usize| {
        let p = polygon_of(slot);
        let (k, m) = (slot - offsets[p], offsets[p + 1] - offsets[p]);
        let loop_edges = mesh.polygon_edges(p);
        (
            loop_edges[k],
            loop_edges[if k == 0 { m - 1 } else { k - 1 }],
        )
    };
    for v in 0..n {
        let around = &mut sectors[start[v]..start[v + 1]];
        let count = around.len();
        if count < 2 {
            continue;
        }
        around.sort_by(|a, b| a.0.total_cmp(&b.0));
        for i in 0..count {
            let (from, to, slot) = around[i];
            let opening = opening_of(from, to);
            let (next_start, _, next_slot) = around[if i + 1 == count { 0 } else { i + 1 }];
            let next_from = if i + 1 == count {
                next_start + TAU
            } else {
                next_start
            };
            if from + opening > next_from + ANGLE_TOLERANCE {
                let (p, q) = (polygon_of(slot), polygon_of(next_slot));
                return Err(MeshError::Overlapping {
                    a: p.min(q),
                    b: p.max(q),
                });
            }
            // Corners that meet along an edge see its angle bit for bit: a gap between
            // different edges otherwise.
            if !near && tolerance.is_some() && next_start != to {
                let gap = next_from - (from + opening);
                if gap <= bound {
                    near = close(corner_edges(slot).1, corner_edges(next_slot).0, gap);
                }
            }
        }
    }
    Ok(near)
}

/// Step 6: no connected component (polygons linked through shared vertices) has a vertex
/// strictly inside a polygon of another component.
fn check_nesting(mesh: &Mesh) -> Result<(), MeshError> {
    let mut parent: Vec<usize> = (0..mesh.n_vertices()).collect();
    fn root(parent: &mut [usize], mut v: usize) -> usize {
        while parent[v] != v {
            parent[v] = parent[parent[v]];
            v = parent[v];
        }
        v
    }
    for p in 0..mesh.n_polygons() {
        let loop_ = mesh.polygon(p);
        for &v in &loop_[1..] {
            let (r, first) = (root(&mut parent, v), root(&mut parent, loop_[0]));
            if r != first {
                parent[r.max(first)] = r.min(first);
            }
        }
    }
    // One representative (polygon, vertex) per component, in polygon order.
    let mut representative: Vec<(usize, usize)> = Vec::new();
    let mut seen = vec![false; mesh.n_vertices()];
    for p in 0..mesh.n_polygons() {
        let v = mesh.polygon(p)[0];
        let r = root(&mut parent, v);
        if !seen[r] {
            seen[r] = true;
            representative.push((p, v));
        }
    }
    if representative.len() < 2 {
        return Ok(());
    }
    let boxes: Vec<Aabb> = representative
        .iter()
        .map(|&(_, v)| Aabb::of_points(std::iter::once(mesh.vertex(v))))
        .collect();
    let grid = Grid::new(&boxes);
    let mut points = Vec::new();
    for q in 0..mesh.n_polygons() {
        points.clear();
        points.extend(mesh.polygon(q).iter().map(|&v| mesh.vertex(v)));
        let bounds = Aabb::of_points(points.iter().copied());
        let component = root(&mut parent, mesh.polygon(q)[0]);
        let mut hit = None;
        grid.for_each_in(&bounds, |i| {
            let (p, v) = representative[i];
            if hit.is_none()
                && root(&mut parent, v) != component
                && bounds.contains(mesh.vertex(v))
                && strictly_inside(mesh.vertex(v), &points)
            {
                hit = Some(p);
            }
        });
        if let Some(p) = hit {
            return Err(MeshError::Overlapping {
                a: p.min(q),
                b: p.max(q),
            });
        }
    }
    Ok(())
}

/// Step 6 in its boundary form (condition (e) of the module docs): just to the right of
/// every boundary loop, no polygon covers the plane.
///
/// The boundary edges are chained into loops ([`boundary_loops`]). For each loop, the edge
/// with the largest rise is cut at half its height y0, and the polygons covering a point just
/// to the right of that cut are counted as the winding number there of all boundary edges
/// (the interior edges cancel, see the module docs): the signed crossings of a horizontal ray
/// from the cut away from the mesh, with the loops whose boxes meet the edge's box. Whether
/// another edge crosses the line y = y0 beyond the cut is decided by the side of an end point
/// of one edge with respect to the other (the two do not meet, by step 4 on the boundary), not
/// by computing the crossings.
fn check_covering(mesh: &Mesh) -> Result<(), MeshError> {
    let (loop_start, loop_edges) = boundary_loops(mesh)?;
    let loops = loop_start.len() - 1;
    if loops == 0 {
        // No boundary: the polygons' windings cancel everywhere, impossible for
        // counter-clockwise polygons that do not overlap.
        return Err(MeshError::Overlapping { a: 0, b: 0 });
    }
    let edges = mesh.edges();
    let segment = |e: usize| -> ([usize; 2], [Point; 2]) {
        let vertices = edges[e].vertices;
        (vertices, vertices.map(|v| mesh.vertex(v)))
    };
    let boxes: Vec<Aabb> = (0..loops)
        .map(|l| {
            Aabb::of_points(
                loop_edges[loop_start[l]..loop_start[l + 1]]
                    .iter()
                    .map(|&e| mesh.vertex(edges[e].vertices[0])),
            )
        })
        .collect();
    // Few loops (a mesh in one piece, a few holes): every loop's box is looked at.
    let grid = (loops > 16).then(|| Grid::new(&boxes));
    let mut seen = vec![usize::MAX; loops];
    for l in 0..loops {
        let own = &loop_edges[loop_start[l]..loop_start[l + 1]];
        let rise = |e: usize| {
            let (_, [a, b]) = segment(e);
            (b.y - a.y).abs()
        };
        let cut = own.iter().copied().fold(
            own[0],
            |best, e| if rise(e) > rise(best) { e } else { best },
        );
        let (ie, pe) = segment(cut);
        let y0 = pe[0].y + 0.5 * (pe[1].y - pe[0].y);
        if !(y0 > pe[0].y.min(pe[1].y) && y0 < pe[0].y.max(pe[1].y)) {
            // A loop flat to the last bit: its polygons failed the area check already.
            return Err(covering_error(mesh, cut, y0));
        }
        let reach = Aabb::of_points(pe.into_iter());
        let mut count = 0i64;
        let mut visit = |m: usize| {
            if seen[m] == l || !boxes[m].intersects(&reach) {
                return;
            }
            seen[m] = l;
            for &f in &loop_edges[loop_start[m]..loop_start[m + 1]] {
                if f != cut {
                    let (jf, pf) = segment(f);
                    count += i64::from(ray_crossing(ie, pe, jf, pf, y0));
                }
            }
        };
        match &grid {
            Some(grid) => grid.for_each_in(&reach, &mut visit),
            None => (0..loops).for_each(&mut visit),
        }
        if count != 0 {
            return Err(covering_error(mesh, cut, y0));
        }
    }
    Ok(())
}

/// The signed crossing of the directed segment `f` (vertices `jf`, points `pf`) with the
/// horizontal ray at height `y0` that starts on the directed segment `e` (`ie`, `pe`, which
/// crosses y0 strictly) and runs to the right of `e` (towards +x if `e` rises, -x if it
/// falls): +1 if `f` crosses it in the direction of `e`, -1 in the opposite one, 0 if it does
/// not cross it. `f` counts as crossing the line y = y0 when its ends lie on either side of it
/// with an end exactly on it counted above (the usual half-open rule).
///
/// `e` and `f` are taken not to meet except at a shared end vertex (step 4 on the boundary),
/// so their order in x is the same at every height both span: it is read off at an end point
/// of one that lies in the other's span, as that end point's side of the other segment.
fn ray_crossing(ie: [usize; 2], pe: [Point; 2], jf: [usize; 2], pf: [Point; 2], y0: f64) -> i32 {
    if (pf[0].y > y0) == (pf[1].y > y0) {
        return 0;
    }
    let (e_rises, f_rises) = (pe[1].y > pe[0].y, pf[1].y > pf[0].y);
    // Lower and upper ends (index, point).
    let ends = |i: [usize; 2], p: [Point; 2], rises: bool| {
        if rises {
            ((i[0], p[0]), (i[1], p[1]))
        } else {
            ((i[1], p[1]), (i[0], p[0]))
        }
    };
    let ((e_lo, pe_lo), (e_hi, pe_hi)) = ends(ie, pe, e_rises);
    let ((f_lo, pf_lo), (f_hi, pf_hi)) = ends(jf, pf, f_rises);
    // Side of `p` with respect to the upward segment lo -> hi: > 0 on its left (smaller x).
    let side = |p: Point, lo: Point, hi: Point| cross(hi - lo, p - lo);
    // +1 when f lies at larger x than e, -1 at smaller x, 0 undecided (an end point on the
    // other segment's line: not counted).
    let sign = |value: f64| -> i32 {
        if value > 0.0 {
            1
        } else if value < 0.0 {
            -1
        } else {
            0
        }
    };
    let order = if f_lo == e_lo {
        if f_hi == e_hi {
            return 0;
        }
        if pf_hi.y <= pe_hi.y {
            -sign(side(pf_hi, pe_lo, pe_hi))
        } else {
            sign(side(pe_hi, pf_lo, pf_hi))
        }
    } else if pf_lo.y >= pe_lo.y {
        -sign(side(pf_lo, pe_lo, pe_hi))
    } else {
        sign(side(pe_lo, pf_lo, pf_hi))
    };
    let ray = if e_rises { 1 } else { -1 };
    if order != ray {
        0
    } else if f_rises == e_rises {
        1
    } else {
        -1
    }
}

/// The error of [`check_covering`] for the loop cut at height `y0` on boundary edge `cut`:
/// the polygon of `cut` and one that covers the plane just to the right of the cut (found by
/// the winding number of each polygon's loop there), or the polygon of `cut` twice when none
/// does.
fn covering_error(mesh: &Mesh, cut: usize, y0: f64) -> MeshError {
    let edge = mesh.edges()[cut];
    let (ie, pe) = (edge.vertices, edge.vertices.map(|v| mesh.vertex(v)));
    let covering = (0..mesh.n_polygons()).find(|&q| {
        let loop_ = mesh.polygon(q);
        let m = loop_.len();
        q != edge.left
            && pe[0].y.min(pe[1].y) < y0
            && pe[0].y.max(pe[1].y) > y0
            && (0..m)
                .map(|k| {
                    let jf = [loop_[k], loop_[(k + 1) % m]];
                    ray_crossing(ie, pe, jf, jf.map(|v| mesh.vertex(v)), y0)
                })
                .sum::<i32>()
                != 0
    });
    let other = covering.unwrap_or(edge.left);
    MeshError::Overlapping {
        a: edge.left.min(other),
        b: edge.left.max(other),
    }
}

/// The boundary edges (those with one polygon) chained into closed loops, in compressed
/// storage: loop l is `edges[start[l]..start[l + 1]]`, each edge followed by the next along
/// the boundary with the mesh on the left.
///
/// Where a vertex has one outgoing boundary edge, that edge follows. Where several loops meet
/// at a vertex (polygons that share only the vertex, around an uncovered sector), the edge
/// that follows an incoming one is the first outgoing boundary edge counter-clockwise from it
/// (reversed): the loop turns around the uncovered sector on its right, so that no other
/// boundary edge enters the sector, and the strip just to the right of a loop meets no other
/// loop. An error names two polygons whose boundary edges do not chain so (each vertex has as
/// many incoming as outgoing boundary edges, and corners that do not overlap pair them up).
fn boundary_loops(mesh: &Mesh) -> Result<(Vec<usize>, Vec<usize>), MeshError> {
    use std::f64::consts::TAU;
    let edges = mesh.edges();
    let n = mesh.n_vertices();
    let mut out_start = vec![0usize; n + 1];
    let mut balance = vec![0i64; n];
    let mut count = 0;
    for edge in edges.iter().filter(|e| e.right.is_none()) {
        out_start[edge.vertices[0] + 1] += 1;
        balance[edge.vertices[0]] += 1;
        balance[edge.vertices[1]] -= 1;
        count += 1;
    }
    if let Some(v) = balance.iter().position(|&b| b != 0) {
        // Not a cycle: impossible for edges derived from closed loops, kept as a guard.
        let p = (0..mesh.n_polygons())
            .find(|&p| mesh.polygon(p).contains(&v))
            .unwrap_or(0);
        return Err(MeshError::Overlapping { a: p, b: p });
    }
    for v in 0..n {
        out_start[v + 1] += out_start[v];
    }
    let mut fill = out_start.clone();
    let mut outgoing = vec![0usize; count];
    for (e, edge) in edges.iter().enumerate() {
        if edge.right.is_none() {
            outgoing[fill[edge.vertices[0]]] = e;
            fill[edge.vertices[0]] += 1;
        }
    }
    let angle = |from: usize, to: usize| {
        let d = mesh.vertex(to) - mesh.vertex(from);
        d.y.atan2(d.x)
    };
    let next = |e: usize| -> usize {
        let [from, v] = edges[e].vertices;
        let out = &outgoing[out_start[v]..out_start[v + 1]];
        if out.len() == 1 {
            return out[0];
        }
        let back = angle(v, from);
        let turn = |o: usize| {
            let t = (angle(v, edges[o].vertices[1]) - back).rem_euclid(TAU);
            if t > 0.0 {
                t
            } else {
                TAU
            }
        };
        out.iter().copied().fold(
            out[0],
            |best, o| if turn(o) < turn(best) { o } else { best },
        )
    };
    let mut chained = vec![false; edges.len()];
    let mut start = vec![0];
    let mut loop_edges = Vec::with_capacity(count);
    for first in 0..edges.len() {
        if edges[first].right.is_some() || chained[first] {
            continue;
        }
        let mut e = first;
        loop {
            chained[e] = true;
            loop_edges.push(e);
            let following = next(e);
            if following == first {
                break;
            }
            if chained[following] {
                let (p, q) = (edges[e].left, edges[following].left);
                return Err(MeshError::Overlapping {
                    a: p.min(q),
                    b: p.max(q),
                });
            }
            e = following;
        }
        start.push(loop_edges.len());
    }
    Ok((start, loop_edges))
}

/// The indices of `points` in the order of a Morton (Z-order) curve through their bounding
/// box, at a resolution of about two points per step: points close in the plane come close
/// in the order, so that work done in this order stays in a small part of memory.
pub(crate) fn spatial_order(points: impl ExactSizeIterator<Item = Point> + Clone) -> Vec<usize> {
    let (mut lo, mut hi) = (
        Point::new(f64::INFINITY, f64::INFINITY),
        Point::new(f64::NEG_INFINITY, f64::NEG_INFINITY),
    );
    for p in points.clone() {
        lo = Point::new(lo.x.min(p.x), lo.y.min(p.y));
        hi = Point::new(hi.x.max(p.x), hi.y.max(p.y));
    }
    let span = (hi.x - lo.x).max(hi.y - lo.y);
    let scale = if span > 0.0 && span.is_finite() {
        f64::from(u32::MAX) / span
    } else {
        0.0
    };
    // Spreads the 32 bits of `v` to the even bits of a u64.
    fn spread(v: u32) -> u64 {
        let mut x = u64::from(v);
        x = (x | (x << 16)) & 0x0000_FFFF_0000_FFFF;
        x = (x | (x << 8)) & 0x00FF_00FF_00FF_00FF;
        x = (x | (x << 4)) & 0x0F0F_0F0F_0F0F_0F0F;
        x = (x | (x << 2)) & 0x3333_3333_3333_3333;
        x = (x | (x << 1)) & 0x5555_5555_5555_5555;
        x
    }
    let keys: Vec<u64> = points
        .map(|p| {
            // `as` saturates (and sends NaN to 0).
            let x = ((p.x - lo.x) * scale) as u32;
            let y = ((p.y - lo.y) * scale) as u32;
            spread(x) | (spread(y) << 1)
        })
        .collect();
    // A counting sort on the leading bits of the keys (about two points per bucket): the
    // order within a bucket is that of the indices, close enough for locality.
    let bits = (usize::BITS - keys.len().leading_zeros()).clamp(1, 24);
    let bucket = |key: u64| (key >> (64 - bits)) as usize;
    let mut start = vec![0usize; (1 << bits) + 1];
    for &key in &keys {
        start[bucket(key) + 1] += 1;
    }
    for b in 0..1 << bits {
        start[b + 1] += start[b];
    }
    let mut order = vec![0; keys.len()];
    for (i, &key) in keys.iter().enumerate() {
        let b = bucket(key);
        order[start[b]] = i;
        start[b] += 1;
    }
    order
}

/// Crossing-number test; the point is known not to lie on the loop.
fn strictly_inside(point: Point, loop_: &[Point]) -> bool {
    let m = loop_.len();
    let mut inside = false;
    for k in 0..m {
        let (a, b) = (loop_[k], loop_[(k + 1) % m]);
        if (a.y > point.y) != (b.y > point.y) {
            let x = a.x + (point.y - a.y) / (b.y - a.y) * (b.x - a.x);
            if x > point.x {
                inside = !inside;
            }
        }
    }
    inside
}

/// z-component of the cross product.
fn cross(a: Vector, b: Vector) -> f64 {
    a.x * b.y - a.y * b.x
}

/// How two segments meet.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Conflict {
    /// Only at shared end points, or not at all.
    None,
    /// They cross at a point interior to both.
    Cross,
    /// An end point of one lies in the interior of the other.
    Touch,
}

/// How segments `a` and `b` (with vertex indices `ia`, `ib`) meet, up to `tolerance`.
fn segments_conflict(
    ia: [usize; 2],
    a: [Point; 2],
    ib: [usize; 2],
    b: [Point; 2],
    tolerance: f64,
) -> Conflict {
    let length = |s: [Point; 2]| (s[1] - s[0]).norm();
    segments_conflict_with_lengths(ia, a, length(a), ib, b, length(b), tolerance)
}

/// [`segments_conflict`] for segments of known lengths `la` and `lb`.
fn segments_conflict_with_lengths(
    ia: [usize; 2],
    a: [Point; 2],
    la: f64,
    ib: [usize; 2],
    b: [Point; 2],
    lb: f64,
    tolerance: f64,
) -> Conflict {
    for k in 0..2 {
        if !ia.contains(&ib[k]) && in_segment_interior(b[k], a, la, tolerance) {
            return Conflict::Touch;
        }
        if !ib.contains(&ia[k]) && in_segment_interior(a[k], b, lb, tolerance) {
            return Conflict::Touch;
        }
    }
    let shared = ia.iter().any(|v| ib.contains(v));
    if !shared {
        let side = |s: [Point; 2], p: Point| cross(s[1] - s[0], p - s[0]);
        let (o1, o2) = (side(a, b[0]), side(a, b[1]));
        let (o3, o4) = (side(b, a[0]), side(b, a[1]));
        let opposite = |x: f64, y: f64| (x > 0.0 && y < 0.0) || (x < 0.0 && y > 0.0);
        if opposite(o1, o2) && opposite(o3, o4) {
            return Conflict::Cross;
        }
    }
    Conflict::None
}

/// True when `p` is within `tolerance` of segment `s` (of length `length`) and farther than
/// `tolerance` from both of its end points (measured along the segment).
fn in_segment_interior(p: Point, s: [Point; 2], length: f64, tolerance: f64) -> bool {
    let along = s[1] - s[0];
    if length <= 2.0 * tolerance {
        return false;
    }
    let offset = p - s[0];
    let t = offset.dot(&along) / length;
    t > tolerance && t < length - tolerance && (cross(along, offset) / length).abs() <= tolerance
}

/// An axis-aligned bounding box.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Aabb {
    pub(crate) min: Point,
    pub(crate) max: Point,
}

impl Aabb {
    /// The smallest box holding `points` (an inverted box when there are none).
    pub(crate) fn of_points(points: impl Iterator<Item = Point>) -> Self {
        let mut b = Aabb {
            min: Point::new(f64::INFINITY, f64::INFINITY),
            max: Point::new(f64::NEG_INFINITY, f64::NEG_INFINITY),
        };
        for p in points {
            b.min = Point::new(b.min.x.min(p.x), b.min.y.min(p.y));
            b.max = Point::new(b.max.x.max(p.x), b.max.y.max(p.y));
        }
        b
    }

    pub(crate) fn diagonal(&self) -> f64 {
        (self.max - self.min).norm()
    }

    fn contains(&self, p: Point) -> bool {
        p.x >= self.min.x && p.x <= self.max.x && p.y >= self.min.y && p.y <= self.max.y
    }

    fn intersects(&self, other: &Aabb) -> bool {
        self.min.x <= other.max.x
            && other.min.x <= self.max.x
            && self.min.y <= other.max.y
            && other.min.y <= self.max.y
    }
}

/// A uniform grid of cells over a set of boxes, each box listed in every cell it overlaps
/// (compressed storage: `items[start[c]..start[c + 1]]` are the boxes of cell c).
pub(crate) struct Grid {
    origin: Point,
    cell: f64,
    nx: usize,
    ny: usize,
    start: Vec<usize>,
    items: Vec<usize>,
}

impl Grid {
    /// A grid whose cells are about the mean box size (or finer, so there are about as many
    /// cells as boxes), with at most about 4 * boxes.len() + 4 cells.
    pub(crate) fn new(boxes: &[Aabb]) -> Self {
        let count = boxes.len().max(1);
        let bounds = Aabb {
            min: Point::new(
                boxes.iter().map(|b| b.min.x).fold(f64::INFINITY, f64::min),
                boxes.iter().map(|b| b.min.y).fold(f64::INFINITY, f64::min),
            ),
            max: Point::new(
                boxes
                    .iter()
                    .map(|b| b.max.x)
                    .fold(f64::NEG_INFINITY, f64::max),
                boxes
                    .iter()
                    .map(|b| b.max.y)
                    .fold(f64::NEG_INFINITY, f64::max),
            ),
        };
        let (width, height) = if boxes.is_empty() {
            (0.0, 0.0)
        } else {
            (bounds.max.x - bounds.min.x, bounds.max.y - bounds.min.y)
        };
        let mean_size = boxes
            .iter()
            .map(|b| (b.max.x - b.min.x).max(b.max.y - b.min.y))
            .sum::<f64>()
            / count as f64;
        let even_share = (width * height / count as f64).sqrt();
        let mut cell = mean_size.max(even_share);
        let limit = 2 * (count as f64).sqrt() as usize + 2;
        if !(cell > 0.0 && cell.is_finite()) {
            cell = width.max(height).max(f64::MIN_POSITIVE);
        }
        let dims = |extent: f64| -> usize { ((extent / cell).floor() as usize + 1).min(limit) };
        let (nx, ny) = (dims(width), dims(height));
        // If clamped, widen the cells so the grid still spans the boxes.
        cell = cell
            .max(width / nx as f64)
            .max(height / ny as f64)
            .max(f64::MIN_POSITIVE);
        let mut grid = Grid {
            origin: if boxes.is_empty() {
                Point::origin()
            } else {
                bounds.min
            },
            cell,
            nx,
            ny,
            start: vec![0; nx * ny + 1],
            items: Vec::new(),
        };
        for b in boxes {
            let (i0, i1, j0, j1) = grid.range(b);
            for j in j0..=j1 {
                for i in i0..=i1 {
                    grid.start[j * nx + i + 1] += 1;
                }
            }
        }
        for c in 0..nx * ny {
            grid.start[c + 1] += grid.start[c];
        }
        let mut fill = grid.start.clone();
        grid.items = vec![0; grid.start[nx * ny]];
        for (index, b) in boxes.iter().enumerate() {
            let (i0, i1, j0, j1) = grid.range(b);
            for j in j0..=j1 {
                for i in i0..=i1 {
                    grid.items[fill[j * nx + i]] = index;
                    fill[j * nx + i] += 1;
                }
            }
        }
        grid
    }

    fn index(&self, value: f64, origin: f64, count: usize) -> usize {
        let i = ((value - origin) / self.cell).floor();
        if i <= 0.0 {
            0
        } else {
            (i as usize).min(count - 1)
        }
    }

    /// Cell ranges (i0, i1, j0, j1), inclusive, overlapped by `b`.
    fn range(&self, b: &Aabb) -> (usize, usize, usize, usize) {
        (
            self.index(b.min.x, self.origin.x, self.nx),
            self.index(b.max.x, self.origin.x, self.nx),
            self.index(b.min.y, self.origin.y, self.ny),
            self.index(b.max.y, self.origin.y, self.ny),
        )
    }

    /// Calls `visit(a, b)` once for every pair of boxes (a != b) whose boxes intersect.
    pub(crate) fn for_each_pair(&self, boxes: &[Aabb], mut visit: impl FnMut(usize, usize)) {
        for j in 0..self.ny {
            for i in 0..self.nx {
                let c = j * self.nx + i;
                let here = &self.items[self.start[c]..self.start[c + 1]];
                for (k, &a) in here.iter().enumerate() {
                    for &b in &here[k + 1..] {
                        let (ba, bb) = (&boxes[a], &boxes[b]);
                        if !ba.intersects(bb) {
                            continue;
                        }
                        // Visit the pair only in the cell holding the lower-left corner of the
                        // boxes' intersection, so each pair is seen once.
                        let corner = Aabb {
                            min: Point::new(ba.min.x.max(bb.min.x), ba.min.y.max(bb.min.y)),
                            max: Point::new(ba.min.x.max(bb.min.x), ba.min.y.max(bb.min.y)),
                        };
                        let (ci, _, cj, _) = self.range(&corner);
                        if (ci, cj) == (i, j) {
                            visit(a, b);
                        }
                    }
                }
            }
        }
    }

    /// Calls `visit(a)` for every box listed in a cell that `query` overlaps (a box may be
    /// visited more than once).
    pub(crate) fn for_each_in(&self, query: &Aabb, mut visit: impl FnMut(usize)) {
        let (i0, i1, j0, j1) = self.range(query);
        for j in j0..=j1 {
            for i in i0..=i1 {
                let c = j * self.nx + i;
                for &a in &self.items[self.start[c]..self.start[c + 1]] {
                    visit(a);
                }
            }
        }
    }
}

/// Segments filed by length in a hierarchy of grids, to find the pairs of segments that come
/// close to each other.
///
/// Segments are grouped by length: a segment whose longer coordinate extent is about 2^l is
/// in group l, filed in a grid of cells of side 2^(l - 1) over the group's bounding box, in the
/// cells that the segment, widened by a reach, passes through (two to four cells, not all the
/// cells of its bounding box, so that a cell holds only the few segments that cross it). Two
/// segments that come within twice the reach of each other pass through a common cell of the
/// grid of the longer one's group, so a segment looks for partners in the grids of its own
/// group and of the longer ones only: the work does not grow with the ratio of the longest to
/// the shortest segment (graded meshes), and queries in the order of the segments (the order
/// of the mesh's polygons) stay within a few cells of each other in memory. A pair may be
/// reported more than once: the caller's test decides.
pub(crate) struct SegmentGrid {
    /// One grid per group of segments, in increasing order of length.
    groups: Vec<CellGrid>,
    /// The index in `groups` of each segment's group.
    group_of: Vec<u32>,
    /// How far around each segment its cells reach.
    reach: f64,
}

/// The grid of one group of segments: cell (i, j) holds
/// `items[start[j * nx + i]..start[j * nx + i + 1]]`.
struct CellGrid {
    origin: Point,
    /// The box of the group's widened segments.
    bounds: Aabb,
    /// The inverse of the side of a cell (a power of two).
    inverse: f64,
    nx: usize,
    ny: usize,
    start: Vec<usize>,
    items: Vec<u32>,
}

/// Group numbers (log2 of a length) are clamped to this range, where 2^l is a normal number.
const LEVEL_LIMIT: i32 = 1000;

/// Most pieces a segment is cut into when listing its cells.
const MAX_PIECES: usize = 64;

impl CellGrid {
    /// The cell column or row of coordinate `value` (`origin`: that of the grid), unclamped.
    fn index(&self, value: f64, origin: f64) -> i64 {
        // `as` saturates: far-away values land in far-away (border) cells.
        floor_to_i64((value - origin) * self.inverse)
    }

    /// The cells that `segment` widened by `r` passes through, inside the grid, each once.
    fn cells_of(&self, segment: &[Point; 2], r: f64, cells: &mut Vec<usize>) {
        cells.clear();
        let [p, q] = *segment;
        let d = q - p;
        let extent = d.x.abs().max(d.y.abs());
        let pieces = if extent.is_finite() {
            ((extent * self.inverse).ceil() as usize).clamp(1, MAX_PIECES)
        } else {
            MAX_PIECES
        };
        let (nx, ny) = (self.nx as i64, self.ny as i64);
        // Consecutive pieces share cells: a cell already listed (among the last few) is not
        // listed again.
        let add_box = |lo: Point, hi: Point, cells: &mut Vec<usize>| {
            let i0 = self.index(lo.x - r, self.origin.x).max(0);
            let i1 = self.index(hi.x + r, self.origin.x).min(nx - 1);
            let j0 = self.index(lo.y - r, self.origin.y).max(0);
            let j1 = self.index(hi.y + r, self.origin.y).min(ny - 1);
            let previous = cells.len().saturating_sub(9);
            for j in j0..=j1 {
                for i in i0..=i1 {
                    let c = j as usize * self.nx + i as usize;
                    if !cells[previous..].contains(&c) {
                        cells.push(c);
                    }
                }
            }
        };
        if pieces == MAX_PIECES {
            // Longer than its grid's cells allow (extreme coordinates only): its whole box.
            let lo = Point::new(p.x.min(q.x), p.y.min(q.y));
            let hi = Point::new(p.x.max(q.x), p.y.max(q.y));
            add_box(lo, hi, cells);
        } else {
            for k in 0..pieces {
                let a = p + (k as f64 / pieces as f64) * d;
                let b = if k + 1 == pieces {
                    q
                } else {
                    p + ((k + 1) as f64 / pieces as f64) * d
                };
                let lo = Point::new(a.x.min(b.x), a.y.min(b.y));
                let hi = Point::new(a.x.max(b.x), a.y.max(b.y));
                add_box(lo, hi, cells);
            }
        }
        if pieces == MAX_PIECES {
            cells.sort_unstable();
            cells.dedup();
        }
    }
}

/// `value.floor() as i64` (saturating, NaN to 0) without a call into the maths library.
fn floor_to_i64(value: f64) -> i64 {
    let truncated = value as i64;
    if (truncated as f64) > value {
        truncated.saturating_sub(1)
    } else {
        truncated
    }
}

impl SegmentGrid {
    /// Files `segments`; pairs that come within `2 * reach` of each other are reported.
    /// Returns `None` when there are more than `u32::MAX` segments.
    pub(crate) fn new(segments: &[[Point; 2]], reach: f64) -> Option<Self> {
        u32::try_from(segments.len()).ok()?;
        let reach = if reach.is_finite() {
            reach.max(0.0)
        } else {
            0.0
        };
        let level_of: Vec<i32> = segments.iter().map(|s| Self::level(s, reach)).collect();
        let mut levels = level_of.clone();
        levels.sort_unstable();
        levels.dedup();
        let group_of: Vec<u32> = level_of
            .iter()
            .map(|l| levels.partition_point(|m| m < l) as u32)
            .collect();
        let mut members: Vec<Vec<u32>> = vec![Vec::new(); levels.len()];
        for (item, &g) in group_of.iter().enumerate() {
            members[g as usize].push(item as u32);
        }
        let mut grid = SegmentGrid {
            groups: Vec::with_capacity(levels.len()),
            group_of,
            reach,
        };
        let mut scratch = Vec::new();
        let mut filed: Vec<(usize, u32)> = Vec::new();
        for (&level, items) in levels.iter().zip(&members) {
            let mut cells = grid.empty_grid(segments, items, level);
            filed.clear();
            for &item in items {
                cells.cells_of(
                    &segments[item as usize],
                    grid.widening(&segments[item as usize]),
                    &mut scratch,
                );
                filed.extend(scratch.iter().map(|&c| (c, item)));
            }
            for &(c, _) in &filed {
                cells.start[c + 1] += 1;
            }
            for c in 0..cells.nx * cells.ny {
                cells.start[c + 1] += cells.start[c];
            }
            let mut fill = cells.start.clone();
            cells.items = vec![0; filed.len()];
            for &(c, item) in &filed {
                cells.items[fill[c]] = item;
                fill[c] += 1;
            }
            grid.groups.push(cells);
        }
        Some(grid)
    }

    /// The grid of a group (without its items): cells of side 2^(level - 1), larger when
    /// that would make more than about four cells per segment.
    fn empty_grid(&self, segments: &[[Point; 2]], items: &[u32], level: i32) -> CellGrid {
        let mut lo = Point::new(f64::INFINITY, f64::INFINITY);
        let mut hi = Point::new(f64::NEG_INFINITY, f64::NEG_INFINITY);
        for &item in items {
            let s = &segments[item as usize];
            let r = self.widening(s);
            for p in s {
                lo = Point::new(lo.x.min(p.x - r), lo.y.min(p.y - r));
                hi = Point::new(hi.x.max(p.x + r), hi.y.max(p.y + r));
            }
        }
        let limit = (4 * items.len() + 64) as f64;
        let mut l = (level - 1).clamp(-LEVEL_LIMIT, LEVEL_LIMIT);
        let (width, height) = (hi.x - lo.x, hi.y - lo.y);
        loop {
            let side = f64::from_bits(((1023 + l) as u64) << 52);
            let (fx, fy) = ((width / side).floor() + 1.0, (height / side).floor() + 1.0);
            if (fx * fy <= limit && fx.is_finite() && fy.is_finite()) || l >= LEVEL_LIMIT {
                let clamp = |f: f64| f.clamp(1.0, limit) as usize;
                let (nx, ny) = (clamp(fx), clamp(fy));
                return CellGrid {
                    origin: if lo.x.is_finite() && lo.y.is_finite() {
                        lo
                    } else {
                        Point::origin()
                    },
                    bounds: Aabb { min: lo, max: hi },
                    inverse: f64::from_bits(((1023 - l) as u64) << 52),
                    nx,
                    ny,
                    start: vec![0; nx * ny + 1],
                    items: Vec::new(),
                };
            }
            l += 1;
        }
    }

    /// How far around `segment` its cells must reach: the reach, and a few units in the last
    /// place of its coordinates (the end points of its pieces are rounded).
    fn widening(&self, segment: &[Point; 2]) -> f64 {
        let [p, q] = segment;
        let magnitude = p.x.abs().max(p.y.abs()).max(q.x.abs()).max(q.y.abs());
        self.reach + 4.0 * f64::EPSILON * magnitude
    }

    /// The length group of a segment: the smallest l with 2^l at least its longer coordinate
    /// extent (and twice the reach).
    fn level(segment: &[Point; 2], reach: f64) -> i32 {
        let d = segment[1] - segment[0];
        let size = d.x.abs().max(d.y.abs()).max(2.0 * reach);
        if size > 0.0 && size.is_finite() {
            // ceil(log2(size)) from the bits: the exponent, plus one unless a power of two.
            let bits = size.to_bits();
            let exponent = ((bits >> 52) & 0x7ff) as i32 - 1023;
            let above = i32::from(bits & ((1 << 52) - 1) != 0);
            (exponent + above).clamp(-LEVEL_LIMIT + 1, LEVEL_LIMIT)
        } else if size > 0.0 {
            LEVEL_LIMIT
        } else {
            -LEVEL_LIMIT + 1
        }
    }

    /// Calls `visit(a, b)` (a != b) at least once for every pair of segments that come within
    /// twice the reach of each other.
    pub(crate) fn for_each_pair(
        &self,
        segments: &[[Point; 2]],
        mut visit: impl FnMut(usize, usize),
    ) {
        // Pairs within a group: the pairs of each cell, in the order of the cells.
        for grid in &self.groups {
            for c in 0..grid.nx * grid.ny {
                let items = &grid.items[grid.start[c]..grid.start[c + 1]];
                for (k, &a) in items.iter().enumerate() {
                    for &b in &items[k + 1..] {
                        visit(a as usize, b as usize);
                    }
                }
            }
        }
        // Pairs across groups: each segment looks in the grids of the longer ones.
        let mut cells = Vec::new();
        for (a, segment) in segments.iter().enumerate() {
            let own = self.group_of[a] as usize;
            let r = self.widening(segment);
            let reach = Aabb::of_points(segment.iter().copied());
            for grid in &self.groups[own + 1..] {
                let near = reach.min.x - r <= grid.bounds.max.x
                    && grid.bounds.min.x <= reach.max.x + r
                    && reach.min.y - r <= grid.bounds.max.y
                    && grid.bounds.min.y <= reach.max.y + r;
                if !near {
                    continue;
                }
                grid.cells_of(segment, r, &mut cells);
                for &c in &cells {
                    for &b in &grid.items[grid.start[c]..grid.start[c + 1]] {
                        visit(a, b as usize);
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Uniform numbers in [0, 1) from a linear congruential generator seeded by `seed` (the
    /// tests' random meshes and clouds, the same on every platform).
    fn uniform_stream(seed: u64) -> impl FnMut() -> f64 {
        let mut state = seed;
        move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    fn square() -> Vec<Point> {
        vec![
            Point::new(0.0, 0.0),
            Point::new(1.0, 0.0),
            Point::new(1.0, 1.0),
            Point::new(0.0, 1.0),
        ]
    }

    /// An n x n grid of unit squares with its vertices jittered (deterministically), split
    /// into triangles in every third cell, with the part "bottom".
    fn jittered_grid(n: usize) -> Mesh {
        let mut state = 99u64;
        let mut jitter = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 0.3
        };
        let id = |i: usize, j: usize| j * (n + 1) + i;
        let mut vertices = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                let inner = i > 0 && i < n && j > 0 && j < n;
                let (dx, dy) = if inner {
                    (jitter(), jitter())
                } else {
                    (0.0, 0.0)
                };
                vertices.push(Point::new(i as f64 + dx, j as f64 + dy));
            }
        }
        let mut polygons = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
                if (i + j) % 3 == 0 {
                    polygons.push(vec![a, b, c]);
                    polygons.push(vec![a, c, d]);
                } else {
                    polygons.push(vec![a, b, c, d]);
                }
            }
        }
        let bottom = crate::PartSpec::new("bottom", (0..n).map(|i| [i, i + 1]).collect());
        Mesh::from_polygons(vertices, &polygons, vec![bottom]).unwrap()
    }

    /// Compact storage of a mesh (vertices, offsets, indices, parts) and its changed vertices.
    type Storage = (
        Vec<Point>,
        Vec<usize>,
        Vec<usize>,
        Vec<crate::PartSpec>,
        Vec<usize>,
    );

    /// The mesh with vertex `v` at `to` (storage only, unvalidated), or with the vertex `to`
    /// inserted into the bottom edge from vertex 0 to vertex 1 when `v` is `None`.
    fn changed(mesh: &Mesh, v: Option<usize>, to: Point) -> Storage {
        let mut vertices = mesh.vertices().to_vec();
        let mut offsets = vec![0];
        let mut indices = Vec::new();
        let changed = match v {
            Some(v) => {
                vertices[v] = to;
                for p in 0..mesh.n_polygons() {
                    indices.extend_from_slice(mesh.polygon(p));
                    offsets.push(indices.len());
                }
                vec![v]
            }
            None => {
                // Into the edge (0, 1) of the bottom, traversed 0 -> 1 by its polygon.
                vertices.push(to);
                let new = vertices.len() - 1;
                for p in 0..mesh.n_polygons() {
                    let loop_ = mesh.polygon(p);
                    for (k, &u) in loop_.iter().enumerate() {
                        indices.push(u);
                        if u == 0 && loop_[(k + 1) % loop_.len()] == 1 {
                            indices.push(new);
                        }
                    }
                    offsets.push(indices.len());
                }
                vec![new]
            }
        };
        let parts = mesh
            .part_specs()
            .into_iter()
            .map(|spec| {
                let edges = spec
                    .edges
                    .into_iter()
                    .flat_map(|[a, b]| match (v, a.min(b), a.max(b)) {
                        (None, 0, 1) => vec![[0, vertices.len() - 1], [vertices.len() - 1, 1]],
                        _ => vec![[a, b]],
                    })
                    .collect();
                crate::PartSpec::new(spec.name, edges)
            })
            .collect();
        (vertices, offsets, indices, parts, changed)
    }

    #[test]
    fn validating_near_a_change_agrees_with_the_whole_validation() {
        let n = 8;
        let mesh = jittered_grid(n);
        let mut uniform = uniform_stream(5);
        let (mut valid, mut invalid) = (0, 0);
        let mut kinds: Vec<String> = Vec::new();
        for trial in 0..600 {
            // Moves of every size (most small and valid, some across neighbours, onto another
            // vertex, or outside), and insertions into a bottom edge.
            let (v, to) = if trial % 10 == 9 {
                let x = if trial % 20 == 9 { 0.5 } else { 1e-13 };
                (None, Point::new(x, 0.0))
            } else {
                let v = (uniform() * mesh.n_vertices() as f64) as usize;
                let p = mesh.vertex(v);
                let size = [1e-3, 0.3, 1.0, 2.0, 4.0][trial % 5];
                let to = if trial % 37 == 0 {
                    mesh.vertex((v + 1) % mesh.n_vertices())
                } else {
                    Point::new(
                        p.x + size * (uniform() - 0.5),
                        p.y + size * (uniform() - 0.5),
                    )
                };
                (Some(v), to)
            };
            let (vertices, offsets, indices, parts, changed) = changed(&mesh, v, to);
            let near = Mesh::from_compact_changed(
                vertices.clone(),
                offsets.clone(),
                indices.clone(),
                parts.clone(),
                &changed,
            );
            let whole = Mesh::from_compact(vertices, offsets, indices, parts);
            assert_eq!(
                near.is_ok(),
                whole.is_ok(),
                "trial {trial}: {v:?} to {to:?}: {near:?} against {whole:?}"
            );
            if let (Err(a), Err(b)) = (&near, &whole) {
                // The same kind of failure.
                assert_eq!(
                    std::mem::discriminant(a),
                    std::mem::discriminant(b),
                    "trial {trial}: {a} against {b}"
                );
                let kind = format!("{a:?}");
                let kind = kind.split([' ', '{', '(']).next().unwrap_or("").to_string();
                if !kinds.contains(&kind) {
                    kinds.push(kind);
                }
                invalid += 1;
            } else {
                valid += 1;
            }
        }
        assert!(
            valid > 200 && invalid > 80,
            "{valid} valid, {invalid} invalid"
        );
        assert!(kinds.len() >= 3, "{kinds:?}");
    }

    #[test]
    fn changes_that_overlap_other_polygons_are_found_near_them() {
        // Two triangles sharing vertex 0 (first and third quadrants) and a far-away one.
        let vertices = vec![
            Point::new(0.0, 0.0),
            Point::new(4.0, 0.0),
            Point::new(0.0, 4.0),
            Point::new(-2.0, -1.0),
            Point::new(-1.0, -2.0),
            Point::new(10.0, 10.0),
            Point::new(11.0, 10.0),
            Point::new(10.0, 11.0),
        ];
        let polygons = [vec![0, 1, 2], vec![0, 3, 4], vec![5, 6, 7]];
        let mesh = Mesh::from_polygons(vertices.clone(), &polygons, Vec::new()).unwrap();
        let offsets = mesh.polygon_offsets().to_vec();
        let indices = mesh.polygon_vertex_indices().to_vec();
        let cases: [(&[(usize, Point)], &str); 5] = [
            // Corners overlapping at vertex 0, no edge crossing.
            (
                &[(3, Point::new(1.0, 0.5)), (4, Point::new(0.5, 1.0))],
                "Overlapping",
            ),
            // An edge crossing another polygon's.
            (
                &[(3, Point::new(5.0, 2.0)), (4, Point::new(2.0, 5.0))],
                "Overlapping",
            ),
            // A whole component inside a polygon of another.
            (
                &[
                    (5, Point::new(1.0, 1.0)),
                    (6, Point::new(1.5, 1.0)),
                    (7, Point::new(1.0, 1.5)),
                ],
                "Overlapping",
            ),
            // A vertex in the interior of another polygon's edge.
            (&[(5, Point::new(2.0, 2.0))], "NonConforming"),
            // A valid move.
            (&[(3, Point::new(-2.0, -0.5))], "Ok"),
        ];
        for (moves, expected) in cases {
            let mut moved = vertices.clone();
            for &(v, p) in moves {
                moved[v] = p;
            }
            let changed: Vec<usize> = moves.iter().map(|&(v, _)| v).collect();
            let near = Mesh::from_compact_changed(
                moved.clone(),
                offsets.clone(),
                indices.clone(),
                Vec::new(),
                &changed,
            );
            let whole = Mesh::from_compact(moved, offsets.clone(), indices.clone(), Vec::new());
            let kind = |r: &Result<Mesh, MeshError>| match r {
                Ok(_) => "Ok".to_string(),
                Err(e) => format!("{e:?}")
                    .split([' ', '{', '('])
                    .next()
                    .unwrap()
                    .to_string(),
            };
            assert_eq!(kind(&near), expected, "{moves:?}: {near:?}");
            assert_eq!(kind(&whole), expected, "{moves:?}: {whole:?}");
        }
    }

    /// The mesh of `polygons` over `vertices`, unvalidated (edges derived), or the error of
    /// the edge derivation.
    fn unvalidated(vertices: Vec<Point>, polygons: &[Vec<usize>]) -> Result<Mesh, MeshError> {
        let mut offsets = vec![0];
        let mut indices = Vec::new();
        for p in polygons {
            indices.extend_from_slice(p);
            offsets.push(indices.len());
        }
        Mesh::unvalidated(vertices, offsets, indices)
    }

    /// The validation's verdict on `polygons`, after checking that the exhaustive checks
    /// (all edge pairs, corners, nesting of components) give the same.
    fn verdict(vertices: Vec<Point>, polygons: &[Vec<usize>]) -> Result<(), MeshError> {
        let mesh = unvalidated(vertices, polygons)?;
        let fast = validate(&mesh);
        assert_eq!(fast, validate_exhaustive(&mesh), "{polygons:?}");
        fast
    }

    /// An nx x ny grid of unit squares without the cells `holes` (by (i, j)); vertices
    /// numbered j * (nx + 1) + i, unused ones left in place.
    fn grid_with_holes(
        nx: usize,
        ny: usize,
        holes: &[(usize, usize)],
    ) -> (Vec<Point>, Vec<Vec<usize>>) {
        let id = |i: usize, j: usize| j * (nx + 1) + i;
        let mut vertices = Vec::new();
        for j in 0..=ny {
            for i in 0..=nx {
                vertices.push(Point::new(i as f64, j as f64));
            }
        }
        let mut polygons = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                if !holes.contains(&(i, j)) {
                    polygons.push(vec![id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)]);
                }
            }
        }
        (vertices, polygons)
    }

    /// Appends a square of side `size` at `corner` as a new component.
    fn add_square(
        vertices: &mut Vec<Point>,
        polygons: &mut Vec<Vec<usize>>,
        corner: Point,
        size: f64,
    ) {
        let n = vertices.len();
        for (dx, dy) in [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)] {
            vertices.push(Point::new(corner.x + dx * size, corner.y + dy * size));
        }
        polygons.push(vec![n, n + 1, n + 2, n + 3]);
    }

    #[test]
    fn multiply_connected_meshes_and_islands_in_holes_are_accepted() {
        // A square with two holes (one cell each, and a 2 x 1 one).
        let (vertices, polygons) = grid_with_holes(6, 5, &[(1, 1), (3, 2), (4, 2)]);
        assert_eq!(verdict(vertices.clone(), &polygons), Ok(()));
        // An island in each hole; and holes touching at a corner (a vertex where two
        // uncovered sectors meet).
        let (mut with_islands, mut polygons_islands) = (vertices, polygons);
        add_square(
            &mut with_islands,
            &mut polygons_islands,
            Point::new(1.25, 1.25),
            0.5,
        );
        add_square(
            &mut with_islands,
            &mut polygons_islands,
            Point::new(3.5, 2.25),
            0.5,
        );
        assert_eq!(verdict(with_islands, &polygons_islands), Ok(()));
        let (vertices, polygons) = grid_with_holes(5, 5, &[(1, 1), (2, 2), (3, 1)]);
        assert_eq!(verdict(vertices, &polygons), Ok(()));
        // Two squares meeting at one vertex only, and a ring of four cells around a hole
        // whose corners meet it at vertices only.
        let (vertices, polygons) = grid_with_holes(2, 2, &[(1, 0), (0, 1)]);
        assert_eq!(verdict(vertices, &polygons), Ok(()));
        let (vertices, polygons) = grid_with_holes(3, 3, &[(1, 1), (0, 0), (2, 0), (0, 2), (2, 2)]);
        assert_eq!(verdict(vertices, &polygons), Ok(()));
    }

    #[test]
    fn nested_components_are_rejected() {
        // A square on the mesh (inside a cell, and across interior edges), and a frame over
        // a frame's hole with its own hole.
        for (corner, size) in [(Point::new(1.2, 1.2), 0.5), (Point::new(0.5, 0.5), 2.0)] {
            let (mut vertices, mut polygons) = grid_with_holes(4, 4, &[]);
            add_square(&mut vertices, &mut polygons, corner, size);
            assert!(matches!(
                verdict(vertices, &polygons),
                Err(MeshError::Overlapping { .. })
            ));
        }
        let (mut vertices, mut polygons) = grid_with_holes(3, 3, &[(1, 1)]);
        let (inner, inner_polygons) = grid_with_holes(3, 3, &[(1, 1)]);
        let n = vertices.len();
        vertices.extend(
            inner
                .iter()
                .map(|p| Point::new(0.9 + p.x / 3.0, 0.9 + p.y / 3.0)),
        );
        polygons.extend(
            inner_polygons
                .iter()
                .map(|p| p.iter().map(|v| v + n).collect()),
        );
        assert!(matches!(
            verdict(vertices, &polygons),
            Err(MeshError::Overlapping { .. })
        ));
    }

    #[test]
    fn hanging_nodes_and_holes_the_wrong_way_round_are_rejected() {
        // A hanging node: two cells on top of one, the middle vertex not in the lower cell.
        let vertices = vec![
            Point::new(0.0, 0.0),
            Point::new(2.0, 0.0),
            Point::new(2.0, 1.0),
            Point::new(1.0, 1.0),
            Point::new(0.0, 1.0),
            Point::new(0.0, 2.0),
            Point::new(1.0, 2.0),
            Point::new(2.0, 2.0),
        ];
        let polygons = vec![vec![0, 1, 2, 4], vec![4, 3, 6, 5], vec![3, 2, 7, 6]];
        assert!(matches!(
            verdict(vertices, &polygons),
            Err(MeshError::NonConforming { .. })
        ));
        // A frame whose inner ring of cells is listed the wrong way round (a hole bounded
        // counter-clockwise): clockwise cells, or edges used twice in one direction.
        let (vertices, mut polygons) = grid_with_holes(3, 3, &[(1, 1)]);
        polygons[4].reverse();
        assert!(verdict(vertices, &polygons).is_err());
    }

    /// The annulus 1 <= r <= 2 wound twice: 2n + 1 quadrilaterals over 4 pi, all
    /// counter-clockwise, no two vertices in the same place.
    fn annulus_wound_twice(n: usize) -> (Vec<Point>, Vec<Vec<usize>>) {
        let m = 2 * n + 1;
        let mut vertices = Vec::new();
        for j in 0..m {
            let t = 2.0 * std::f64::consts::TAU * j as f64 / m as f64;
            vertices.push(Point::new(t.cos(), t.sin()));
            vertices.push(Point::new(2.0 * t.cos(), 2.0 * t.sin()));
        }
        let polygons = (0..m)
            .map(|j| {
                let k = (j + 1) % m;
                vec![2 * j, 2 * j + 1, 2 * k + 1, 2 * k]
            })
            .collect();
        (vertices, polygons)
    }

    #[test]
    fn folded_meshes_are_rejected() {
        let (vertices, polygons) = annulus_wound_twice(20);
        assert!(matches!(
            verdict(vertices, &polygons),
            Err(MeshError::Overlapping { .. })
        ));
        // A pleat: a strip of three cells whose middle one is folded back, so that the
        // middle covers its region with the opposite orientation (counts +1, -1, +1). Listed
        // as the strip runs, the middle cell is clockwise; listed counter-clockwise, it uses
        // its shared edges in the same direction as its neighbours: a fold cannot have all
        // cells counter-clockwise and every interior edge used in opposite directions.
        let x = [0.0, 2.0, 1.0, 3.0];
        let vertices: Vec<Point> = (0..8)
            .map(|k| Point::new(x[k % 4], (k / 4) as f64 + 0.1 * (k % 4) as f64))
            .collect();
        let mut polygons = vec![vec![0, 1, 5, 4], vec![1, 2, 6, 5], vec![2, 3, 7, 6]];
        assert!(matches!(
            verdict(vertices.clone(), &polygons),
            Err(MeshError::Clockwise { polygon: 1, .. })
        ));
        polygons[1].reverse();
        assert!(matches!(
            unvalidated(vertices, &polygons),
            Err(MeshError::OverusedEdge { .. })
        ));
    }

    /// The duplicate check through coarse cells gives the error of the check through the fine
    /// cells (the same pairs, the same smallest one) on random clouds of points with
    /// near-duplicates at about the tolerance, points on the borders of coarse cells, unused
    /// points, offsets and scales from tiny to huge, clusters (where the fine check decides)
    /// and tolerances of 0.
    #[test]
    fn the_coarse_duplicate_check_agrees_with_the_fine_one() {
        let mut uniform = uniform_stream(17);
        let mut errors = 0;
        for trial in 0..400 {
            let scale = [1e-9, 1e-3, 1.0, 1e3, 1e12][trial % 5];
            let offset = [0.0, -7.5, 1e6, -3e9][trial / 5 % 4] * scale;
            let tolerance = match trial % 23 {
                0 => 0.0,
                1 => 1e300,
                _ => scale * [1e-10, 1e-8, 1e-7, 1e-3][trial / 20 % 4],
            };
            let n = [3, 40, 300, 2000][trial % 4];
            let mut vertices: Vec<Point> = (0..n)
                .map(|_| Point::new(offset + scale * uniform(), offset + scale * uniform()))
                .collect();
            // Near-duplicates of random points, at 0.5 to 1.5 tolerances.
            for _ in 0..n / 10 + 1 {
                let p = vertices[(uniform() * vertices.len() as f64) as usize];
                let (d, angle) = (
                    tolerance * (0.5 + uniform()),
                    std::f64::consts::TAU * uniform(),
                );
                vertices.push(Point::new(p.x + d * angle.cos(), p.y + d * angle.sin()));
            }
            // Pairs straddling the border of a coarse cell (2^16 fine cells of 4 tolerances).
            let side = 4.0 * tolerance * f64::from(1u32 << COARSE_SHIFT);
            for _ in 0..3 {
                if !(side.is_finite() && side > 0.0) {
                    break;
                }
                let x = (offset / side).floor() * side + side * (uniform() * 3.0).floor();
                let y = offset + scale * uniform();
                let d = tolerance * (0.2 + 0.6 * uniform());
                vertices.push(Point::new(x - d, y));
                vertices.push(Point::new(x + 0.9 * tolerance - d, y + 0.3 * d));
            }
            // A cluster of points within a few tolerances, in some trials.
            if trial % 7 == 3 {
                let c = vertices[0];
                for _ in 0..200 {
                    let d = 4.0 * tolerance * uniform();
                    vertices.push(Point::new(c.x + d, c.y - d * uniform()));
                }
            }
            for i in (1..vertices.len()).rev() {
                let j = (uniform() * (i + 1) as f64) as usize;
                vertices.swap(i, j.min(i));
            }
            // Triangles of consecutive vertices; every fifth vertex unused.
            let used_ones: Vec<usize> = (0..vertices.len()).filter(|v| v % 5 != 4).collect();
            let polygons: Vec<Vec<usize>> = used_ones.chunks_exact(3).map(|c| c.to_vec()).collect();
            let mesh = unvalidated(vertices, &polygons).unwrap();
            let mut used = vec![false; mesh.n_vertices()];
            for &v in mesh.polygon_vertex_indices() {
                used[v] = true;
            }
            let fast = check_duplicate_vertices(&mesh, tolerance);
            let fine = check_duplicate_vertices_fine(&mesh, &used, tolerance);
            assert_eq!(fast, fine, "trial {trial}");
            errors += usize::from(fine.is_err());
        }
        assert!(errors > 200, "{errors} errors");
    }

    /// Vertices moved (far, near other vertices and edges, within a few tolerances of an
    /// edge) in meshes with holes, islands and pinched corners: the boundary form of steps 4
    /// and 6 gives the exhaustive checks' verdict, error for error.
    #[test]
    fn the_boundary_form_agrees_with_the_exhaustive_checks() {
        let mut uniform = uniform_stream(17);
        let mut meshes = Vec::new();
        meshes.push(grid_with_holes(6, 5, &[(1, 1), (3, 2), (4, 2)]));
        meshes.push(grid_with_holes(5, 5, &[(1, 1), (2, 2), (3, 1), (0, 4)]));
        let (mut vertices, mut polygons) = grid_with_holes(4, 4, &[(1, 1)]);
        add_square(&mut vertices, &mut polygons, Point::new(1.25, 1.25), 0.5);
        add_square(&mut vertices, &mut polygons, Point::new(5.0, 0.0), 1.0);
        meshes.push((vertices, polygons));
        let jittered = jittered_grid(5);
        meshes.push((
            jittered.vertices().to_vec(),
            jittered.polygons().map(<[usize]>::to_vec).collect(),
        ));
        let (mut accepted, mut rejected) = (0, 0);
        for trial in 0..3000 {
            let (vertices, polygons) = &meshes[trial % meshes.len()];
            let mut moved = vertices.clone();
            let n = moved.len();
            for _ in 0..1 + trial % 3 {
                let v = (uniform() * n as f64) as usize;
                let to = match trial % 4 {
                    // Anywhere near.
                    0 => moved[v] + Vector::new(3.0 * (uniform() - 0.5), 3.0 * (uniform() - 0.5)),
                    // A little.
                    1 => moved[v] + Vector::new(0.4 * (uniform() - 0.5), 0.4 * (uniform() - 0.5)),
                    // Onto another vertex, give or take a few tolerances.
                    2 => {
                        let w = (uniform() * n as f64) as usize;
                        moved[w] + 1e-10 * Vector::new(4.0 * uniform() - 2.0, 4.0 * uniform() - 2.0)
                    }
                    // Onto a point of another polygon's edge, give or take a few tolerances.
                    _ => {
                        let p = &polygons[(uniform() * polygons.len() as f64) as usize];
                        let k = (uniform() * p.len() as f64) as usize;
                        let (a, b) = (moved[p[k]], moved[p[(k + 1) % p.len()]]);
                        let t = uniform();
                        a + t * (b - a)
                            + 1e-10 * Vector::new(4.0 * uniform() - 2.0, 4.0 * uniform() - 2.0)
                    }
                };
                moved[v] = to;
            }
            let Ok(mesh) = unvalidated(moved, polygons) else {
                continue;
            };
            let fast = validate(&mesh);
            let old = validate_exhaustive(&mesh);
            assert_eq!(fast, old, "trial {trial}");
            if fast.is_ok() {
                accepted += 1;
            } else {
                rejected += 1;
            }
        }
        assert!(
            accepted > 500 && rejected > 500,
            "{accepted} accepted, {rejected} rejected"
        );
    }

    #[test]
    fn convex_and_hanging_loops_are_simple() {
        assert_eq!(self_intersection(&square(), 1e-12), None);
        let mut with_hanging = square();
        with_hanging.insert(1, Point::new(0.5, 0.0));
        assert_eq!(self_intersection(&with_hanging, 1e-12), None);
    }

    #[test]
    fn bowtie_crosses_itself() {
        let bowtie = vec![
            Point::new(0.0, 0.0),
            Point::new(1.0, 1.0),
            Point::new(1.0, 0.0),
            Point::new(0.0, 1.0),
        ];
        assert_eq!(self_intersection(&bowtie, 1e-12), Some((0, 2)));
    }

    #[test]
    fn long_loop_uses_the_grid_and_finds_the_same_pair() {
        // A 200-gon comb whose last tooth pokes through its first edge.
        let mut points: Vec<Point> = (0..200)
            .map(|k| {
                let t = std::f64::consts::TAU * k as f64 / 200.0;
                Point::new(t.cos(), t.sin())
            })
            .collect();
        assert_eq!(self_intersection(&points, 1e-12), None);
        points[100] = Point::new(1.5, 0.001);
        let pair = self_intersection(&points, 1e-12).unwrap();
        assert!(pair.0 == 0 || pair.1 >= 99, "{pair:?}");
    }

    #[test]
    fn grid_pairs_match_brute_force() {
        let boxes: Vec<Aabb> = (0..50)
            .map(|k| {
                let x = (k * 37 % 50) as f64 * 0.1;
                let y = (k * 11 % 50) as f64 * 0.07;
                Aabb {
                    min: Point::new(x, y),
                    max: Point::new(x + 0.3 + (k % 3) as f64, y + 0.2),
                }
            })
            .collect();
        let mut from_grid = Vec::new();
        Grid::new(&boxes).for_each_pair(&boxes, |a, b| from_grid.push((a.min(b), a.max(b))));
        from_grid.sort_unstable();
        let mut brute = Vec::new();
        for a in 0..boxes.len() {
            for b in a + 1..boxes.len() {
                if boxes[a].intersects(&boxes[b]) {
                    brute.push((a, b));
                }
            }
        }
        assert_eq!(from_grid, brute);
    }

    /// The distance between two segments (brute force, for the test).
    fn segment_distance(a: [Point; 2], b: [Point; 2]) -> f64 {
        let point_to = |p: Point, s: [Point; 2]| {
            let d = s[1] - s[0];
            let t = if d.norm_squared() > 0.0 {
                ((p - s[0]).dot(&d) / d.norm_squared()).clamp(0.0, 1.0)
            } else {
                0.0
            };
            (p - (s[0] + t * d)).norm()
        };
        let side = |s: [Point; 2], p: Point| cross(s[1] - s[0], p - s[0]);
        let crossing = side(a, b[0]) * side(a, b[1]) < 0.0 && side(b, a[0]) * side(b, a[1]) < 0.0;
        if crossing {
            return 0.0;
        }
        point_to(a[0], b)
            .min(point_to(a[1], b))
            .min(point_to(b[0], a))
            .min(point_to(b[1], a))
    }

    /// Segments of lengths from 1e-6 to 10 (a graded mesh's edges), some of zero length, one
    /// far away: every pair closer than twice the reach is reported.
    #[test]
    fn segment_grid_finds_every_close_pair_over_many_scales() {
        let mut segments = Vec::new();
        for k in 0..600u64 {
            let r = |s: u64| ((k * 2_654_435_761 + s * 40_503) % 10_007) as f64 / 10_007.0;
            let size = 10f64.powf(-6.0 + 7.0 * r(1));
            let p = Point::new(r(2) * 3.0, r(3) * 3.0);
            let angle = std::f64::consts::TAU * r(4);
            let q = if k % 17 == 0 {
                p
            } else {
                p + size * Vector::new(angle.cos(), angle.sin())
            };
            segments.push([p, q]);
        }
        segments.push([Point::new(1e300, -1e300), Point::new(1e300, -1e299)]);
        for reach in [0.0, 1e-9, 1e-3] {
            let grid = SegmentGrid::new(&segments, reach).unwrap();
            let mut reported = std::collections::HashSet::new();
            grid.for_each_pair(&segments, |a, b| {
                assert_ne!(a, b);
                reported.insert((a.min(b), a.max(b)));
            });
            let mut close = 0;
            for a in 0..segments.len() {
                for b in a + 1..segments.len() {
                    if segment_distance(segments[a], segments[b]) <= 2.0 * reach {
                        close += 1;
                        assert!(reported.contains(&(a, b)), "reach {reach}: pair ({a}, {b})");
                    }
                }
            }
            assert!(close > 10, "{close}");
        }
    }
}
