//! Interface insertion in three dimensions: the surface overlay of two facing boundary parts.
//!
//! Two polyhedral bodies whose meshes do not match on their contact surfaces are made
//! node-to-node, as [`crate::interface::insert_interface_nodes`] does for polygons: the faces
//! of one part are cut by the projected faces of the other, each contact face is replaced by
//! the *overlay cells* inside it (coplanar faces of one polyhedron are legal in the VEM), and
//! every point inserted on an edge is also inserted into every other face sharing that edge
//! (lateral faces of the same cell and of its neighbours), so both meshes stay conforming and
//! watertight. No vertex moves: every cell keeps its volume.
//!
//! # The overlay
//!
//! Side **a** (`mesh_a`, `part_a`) is the reference side. The contact faces of both sides must
//! be planar (to [`PLANARITY_RATIO`]); convex faces (collinear vertices, as hanging nodes,
//! allowed) always work, and non-convex ones as long as each overlay cell is star-shaped about
//! the mean of its points (checked; an error names the two faces otherwise): the slightly
//! reflex faces of the Voronoi meshes pass, two chevron tops meeting generally do not.
//!
//! 1. *Search.* Candidate face pairs (face of a, face of b) come from a uniform grid over b's
//!    faces, queried with each face of a swept along its normal by the search distance
//!    (`max_distance`, or the diagonal of the two parts' bounding box); a pair counts when the
//!    outward normals oppose (n_a . n_b < 0). Cost O(n) for n faces of similar sizes.
//! 2. *Vertices of a onto b.* Each vertex x of a is projected along its nodal normal (the
//!    normalised sum of the vector areas of its faces in the part) onto the planes of its
//!    candidate faces of b and located in them: at a vertex (closer than the snap fraction of
//!    the shorter of its two edges), on an edge (closer than the snap fraction of the edge), in
//!    the face, or outside. Projections farther than `max_distance` do not count.
//! 3. *Vertices of b onto a.* Each vertex of b is projected orthogonally onto the planes of its
//!    candidate faces of a and located the same way; it snaps to a vertex of a only when that
//!    vertex snapped to it (snapping to vertices is mutual).
//! 4. *Edge crossings.* An edge e_a = (x_1, x_2) of a and an edge e_b of b cross when the ends
//!    of e_b lie strictly on both sides of the sheet through e_a spanned by its edge normal (the
//!    normalised sum of the unit normals of its faces in the part) at a point strictly inside
//!    e_a, and neither edge has an end snapped onto the other (a snapped end replaces the
//!    crossing: no sliver).
//! 5. *Cells.* The overlay cell of a pair (F_a, F_b) has as vertices the vertices of F_a
//!    located in the closure of F_b, the vertices of F_b located in the closure of F_a, and the
//!    crossings of their edges: for convex faces these are exactly the corners of F_a ∩ F_b and
//!    the points on its sides, which are ordered by angle about their mean in F_a's plane (for
//!    non-convex faces: when F_a ∩ F_b is one piece, star-shaped about that mean). A
//!    pair whose cell has less than [`TOUCH_AREA_RATIO`] of F_a's area (faces touching along an
//!    edge or at a point) has no cell.
//! 6. *Faces.* On side a a cell's points are the vertices of a and the projections of b's
//!    vertices and of the crossings onto a; on side b the vertices of b and the projections of
//!    a's. Each contact face is replaced by its cells and, where the other part does not cover
//!    it, by the rest of it (the face's boundary minus the cells' boundaries, traced as loops;
//!    it must be one or more simple polygons, not a face with a hole; pieces that touch at a
//!    vertex are traced as separate faces). Every inserted point on an edge goes into all
//!    faces around that edge, in order along it.
//!
//! # Parts that cover each other partly
//!
//! Either part may reach beyond the other (a zone larger than the cap facing it), and
//! `max_distance` may leave part of both unpaired: a vertex whose projection misses the other
//! part or lies farther than `max_distance` is no node, so the cells stop at the other part's
//! outline or where the gap passes `max_distance`, and the rest of each face stays as it was.
//! Parts cut out of a surface by a box have jagged outlines: two faces of one part may meet at
//! a corner only, so the rest of a face of the other part may be two pieces touching at that
//! corner, each its own face. What is refused is a part's face that the other part covers
//! only inside (the other part's outline wholly within one face: the rest would have a hole);
//! the error names the face and the part, and a finer mesh of that part, or a larger part of
//! the other side, cures it.
//!
//! # Pairs
//!
//! Every vertex of a cell is a node pair: `node_a` in the new mesh a, `node_b` in the new mesh
//! b (existing vertices where they were snapped, new ones otherwise). The pair normal is the
//! outward unit nodal normal of body a at the point's place on a (area-weighted face normals:
//! the face's normal inside a face, over the one or two part faces of an edge, over the part
//! faces around a vertex). The tributary area is the node's share of the areas of the cells on
//! side a by the fan weights of [`super::geometry::face_vertex_weights`] (positive on convex
//! faces; they integrate every linear function exactly over a planar cell), so over all pairs
//! the tributary areas add up to the area of the overlay (the paired part of side a).
//! `initial_gap = (point_b - point_a) . normal`, positive when open.
//!
//! # Snapping
//!
//! The snap fraction is `max(snap_tolerance, min_edge_fraction)` of [`InterfaceOptions`], of
//! the length of the edge concerned. A vertex that snaps keeps its place: the tangential misfit
//! of its pair is at most that fraction of a neighbouring edge, and the area of the overlay
//! differs from the exact overlap by at most the same order where a vertex of one part snaps
//! onto the rim of the other. `align_snapped_nodes` is not used in three dimensions (moving a
//! vertex would change the volumes of its cells).
//!
//! # Curved surfaces
//!
//! On a curved interface the projections along the normals of neighbouring faces of one part
//! leave thin seams and overlaps near the edges between them: a projected point that falls
//! outside every face by less than [`SEAM_FRACTION`] of the nearest edge, nearest to an edge or
//! vertex inside the part (not on its rim), is placed on that edge or vertex. The face the
//! point misses least decides: a point beyond the part's rim, nearest to a rim edge, is not
//! placed, even when another face it misses by more has an inner edge within reach. The overlay is
//! then consistent to within the faces' deviation from the surface (h^2 times the curvature).
//!
//! ```
//! use vem_mesh::generators::polyhedral::{hexahedra, Cuboid};
//! use vem_mesh::interface::InterfaceOptions;
//! use vem_mesh::polyhedral::overlay::insert_surface_overlay;
//! use vem_mesh::Point3;
//! // Body a under body b, touching at z = 1; 2 x 2 and 3 x 3 faces on the interface.
//! let a = hexahedra(&Cuboid::new(Point3::new(0.0, 0.0, 0.0), Point3::new(1.0, 1.0, 1.0)), 2, 2, 1)?;
//! let b = hexahedra(&Cuboid::new(Point3::new(0.0, 0.0, 1.0), Point3::new(1.0, 1.0, 2.0)), 3, 3, 1)?;
//! let overlay = insert_surface_overlay(&a, "top", &b, "bottom", &InterfaceOptions::default())?;
//! // Lines x, y in {0, 1/3, 1/2, 2/3, 1}: 5 x 5 nodes, 4 x 4 overlay cells of total area 1.
//! assert_eq!(overlay.pairs.len(), 25);
//! let area: f64 = overlay.pairs.iter().map(|p| p.tributary_area).sum();
//! assert!((area - 1.0).abs() < 1e-14);
//! assert!(overlay.pairs.iter().all(|p| p.initial_gap.abs() < 1e-15 && p.normal.z == 1.0));
//! assert_eq!(overlay.mesh_a.part_faces("top")?.len(), 16);
//! # Ok::<(), vem_mesh::MeshError>(())
//! ```

use std::collections::{BTreeMap, HashMap};

use super::geometry;
use super::mesh::{FacePart, FastHasher, OrientedFace};
use super::validate::PLANARITY_RATIO;
use crate::interface::InterfaceOptions;
use crate::{MeshError, Point3, PolyhedralMesh, Vector3};

/// Hash maps keyed by indices, with the mesh's fast hasher (nothing depends on their order).
type Map<K, V> = HashMap<K, V, std::hash::BuildHasherDefault<FastHasher>>;

/// Relative area (of the face of side a) under which the cell of a face pair is a touch along
/// an edge or at a point, not a cell.
pub const TOUCH_AREA_RATIO: f64 = 1e-12;

/// Largest distance (relative to the nearest edge's length) by which a projection may miss
/// every face of a curved part and still be placed on the nearest interior edge or vertex.
pub const SEAM_FRACTION: f64 = 0.25;

/// One vertex of a boundary part with its nodal normal and tributary area (see
/// [`boundary_surface`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceNode {
    /// Vertex index in the mesh.
    pub vertex: usize,
    /// Its coordinates.
    pub point: Point3,
    /// Outward unit nodal normal: the normalised sum of the vector areas of the part's faces
    /// around the vertex (area-weighted face normals).
    pub normal: Vector3,
    /// The vertex's share of the areas of the part's faces around it, by the fan weights of
    /// [`super::geometry::face_vertex_weights`] (exact for linear functions on planar faces).
    pub tributary_area: f64,
}

/// One node-to-node pair of a [`SurfaceInterface`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfacePair {
    /// Vertex of the new mesh a.
    pub node_a: usize,
    /// Vertex of the new mesh b.
    pub node_b: usize,
    /// Coordinates of `node_a`.
    pub point_a: Point3,
    /// Coordinates of `node_b`.
    pub point_b: Point3,
    /// Outward unit nodal normal of body a at `node_a` (area-weighted face normals of part a;
    /// body b's is its negative).
    pub normal: Vector3,
    /// The node's share of the overlay cells' areas on side a (fan weights).
    pub tributary_area: f64,
    /// Geometric initial gap `(point_b - point_a) . normal`; positive when open.
    pub initial_gap: f64,
}

/// Two polyhedral meshes made node-to-node on their facing parts, and the pairing.
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceInterface {
    /// Mesh a with the overlay (old vertex indices unchanged, new ones appended).
    pub mesh_a: PolyhedralMesh,
    /// Mesh b with the overlay (old vertex indices unchanged, new ones appended).
    pub mesh_b: PolyhedralMesh,
    /// Name of the interface part of mesh a.
    pub part_a: String,
    /// Name of the interface part of mesh b.
    pub part_b: String,
    /// The pairs, in increasing order of `node_a`.
    pub pairs: Vec<SurfacePair>,
    /// Number of vertices inserted into mesh a.
    pub inserted_a: usize,
    /// Number of vertices inserted into mesh b.
    pub inserted_b: usize,
}

/// The vertices of boundary part `part` of `mesh`, in increasing order, with their outward
/// nodal normals (area-weighted face normals) and tributary areas (fan weights: each face's
/// area shared so that linear functions are integrated exactly on planar faces; over the part
/// they add up to its area).
///
/// Errors: [`MeshError::UnknownPart`] (listing the parts that exist), or
/// [`MeshError::Interface`] (with `part_a` = `part_b` = `part`) when the part has no faces.
///
/// ```
/// use vem_mesh::generators::polyhedral::{hexahedra, Cuboid};
/// use vem_mesh::polyhedral::overlay::boundary_surface;
/// let mesh = hexahedra(&Cuboid::unit_cube(), 2, 2, 2)?;
/// let top = boundary_surface(&mesh, "top")?;
/// assert_eq!(top.len(), 9);
/// // Corners carry a quarter of a face, the centre four quarters.
/// assert!((top[0].tributary_area - 0.0625).abs() < 1e-15);
/// assert!((top[4].tributary_area - 0.25).abs() < 1e-15);
/// assert!(top.iter().all(|node| node.normal.z == 1.0));
/// # Ok::<(), vem_mesh::MeshError>(())
/// ```
pub fn boundary_surface(mesh: &PolyhedralMesh, part: &str) -> Result<Vec<SurfaceNode>, MeshError> {
    let faces = mesh.part_faces(part)?;
    if faces.is_empty() {
        return Err(MeshError::Interface {
            part_a: part.to_string(),
            part_b: part.to_string(),
            reason: format!("part '{part}' has no faces"),
        });
    }
    let mut nodes: BTreeMap<usize, (Vector3, f64)> = BTreeMap::new();
    for &f in faces {
        let points = mesh.face_points(f);
        let area = geometry::face_vector_area(&points);
        let normal = geometry::face_normal(&points);
        for (&v, w) in mesh
            .face(f)
            .iter()
            .zip(geometry::face_vertex_weights(&points))
        {
            let entry = nodes.entry(v).or_insert((Vector3::zeros(), 0.0));
            entry.0 += area;
            entry.1 += w.dot(&normal);
        }
    }
    Ok(nodes
        .into_iter()
        .map(|(vertex, (sum, tributary_area))| SurfaceNode {
            vertex,
            point: mesh.vertex(vertex),
            normal: unit(sum),
            tributary_area,
        })
        .collect())
}

/// Makes the facing boundary parts `part_a` of `mesh_a` and `part_b` of `mesh_b` node-to-node
/// by their surface overlay (module documentation).
///
/// # Errors
/// - [`MeshError::InvalidOption`] for invalid `options`;
/// - [`MeshError::UnknownPart`] for a part that does not exist (parts are made of boundary
///   faces by construction);
/// - [`MeshError::Interface`] naming both parts when a part is empty, a contact face is warped,
///   an overlay cell of non-convex faces is not star-shaped about its points' mean, the parts do not face each other (no overlay cell: normals not opposed,
///   too far apart, or not overlapping), two vertices of a snap to one vertex of b, the
///   uncovered rest of a face is not a set of simple polygons (a hole), or a new mesh does not
///   validate (the validation error quoted).
pub fn insert_surface_overlay(
    mesh_a: &PolyhedralMesh,
    part_a: &str,
    mesh_b: &PolyhedralMesh,
    part_b: &str,
    options: &InterfaceOptions,
) -> Result<SurfaceInterface, MeshError> {
    let fail = |reason: String| MeshError::Interface {
        part_a: part_a.to_string(),
        part_b: part_b.to_string(),
        reason,
    };
    options.validate()?;
    let side_a = Side::new(mesh_a, part_a, &fail)?;
    let side_b = Side::new(mesh_b, part_b, &fail)?;
    let snap = options.snap_fraction();
    let reach = options.max_distance().unwrap_or_else(|| {
        let (lo, hi) = side_a.bbox.union(&side_b.bbox);
        (hi - lo).norm()
    });
    let max_distance = options.max_distance().unwrap_or(f64::INFINITY);

    // 1. Candidate face pairs (index into side a's charts, into side b's).
    let pairs = candidate_pairs(&side_a, &side_b, reach);
    if pairs.is_empty() {
        return Err(fail(format!(
            "the parts do not face each other: no face of '{part_b}' lies within {reach:e} of \
             a face of '{part_a}' with an opposed normal"
        )));
    }
    let mut candidates_of_a: Map<usize, Vec<usize>> = Map::default();
    let mut candidates_of_b: Map<usize, Vec<usize>> = Map::default();
    for &(ia, ib) in &pairs {
        for &v in mesh_a.face(side_a.charts[ia].face) {
            candidates_of_a.entry(v).or_default().push(ib);
        }
        for &w in mesh_b.face(side_b.charts[ib].face) {
            candidates_of_b.entry(w).or_default().push(ia);
        }
    }
    for list in candidates_of_a
        .values_mut()
        .chain(candidates_of_b.values_mut())
    {
        list.sort_unstable();
        list.dedup();
    }

    // 2. Vertices of a along their nodal normals onto b.
    let mut loc_of_a: Map<usize, Located> = Map::default();
    let mut a_vertices: Vec<usize> = candidates_of_a.keys().copied().collect();
    a_vertices.sort_unstable();
    for &v in &a_vertices {
        let origin = mesh_a.vertex(v);
        let direction = side_a.vertex_normal(v);
        let mut best: Option<(Rank, Option<Located>)> = None;
        for &ib in &candidates_of_a[&v] {
            let chart = &side_b.charts[ib];
            let denominator = direction.dot(&chart.normal);
            if denominator >= 0.0 {
                continue;
            }
            let gap = (chart.centroid - origin).dot(&chart.normal) / denominator;
            if gap.abs() > max_distance {
                continue;
            }
            let hit = origin + gap * direction;
            let place = side_b.locate(ib, hit, snap, &|_| true);
            consider(&mut best, place, gap, ib, hit, &side_b);
        }
        if let Some((_, Some(located))) = best {
            loc_of_a.insert(v, located);
        }
    }
    // Vertex snapping is mutual: b's vertex w snaps to a's vertex v only if v snapped to w.
    let mut partner_of_b: Map<usize, usize> = Map::default();
    for &v in &a_vertices {
        if let Some(Located {
            place: Loc::Vertex(w),
            ..
        }) = loc_of_a.get(&v)
        {
            if let Some(other) = partner_of_b.insert(*w, v) {
                return Err(fail(format!(
                    "vertices {other} and {v} of '{part_a}' both snap to vertex {w} of \
                     '{part_b}'; the meshes' sizes differ by more than 1/min_edge_fraction here"
                )));
            }
        }
    }

    // 3. Vertices of b orthogonally onto a.
    let mut loc_of_b: Map<usize, Located> = Map::default();
    let mut b_vertices: Vec<usize> = candidates_of_b.keys().copied().collect();
    b_vertices.sort_unstable();
    for &w in &b_vertices {
        if let Some(&v) = partner_of_b.get(&w) {
            loc_of_b.insert(
                w,
                Located {
                    place: Loc::Vertex(v),
                    point: mesh_a.vertex(v),
                },
            );
            continue;
        }
        let point = mesh_b.vertex(w);
        let mut best: Option<(Rank, Option<Located>)> = None;
        for &ia in &candidates_of_b[&w] {
            let chart = &side_a.charts[ia];
            let gap = (point - chart.centroid).dot(&chart.normal);
            if gap.abs() > max_distance {
                continue;
            }
            let foot = point - gap * chart.normal;
            let allowed = |v: usize| partner_of_b.get(&w) == Some(&v);
            let place = side_a.locate(ia, foot, snap, &allowed);
            consider(&mut best, place, gap, ia, foot, &side_a);
        }
        if let Some((_, Some(located))) = best {
            loc_of_b.insert(w, located);
        }
    }

    // 4 and 5. Crossings and cells.
    let mut crossings: Map<(usize, usize), Option<Crossing>> = Map::default();
    let mut cells: Vec<(usize, usize, Vec<Key>)> = Vec::new();
    let mut keys: Vec<Key> = Vec::new();
    for &(ia, ib) in &pairs {
        let (fa, fb) = (side_a.charts[ia].face, side_b.charts[ib].face);
        keys.clear();
        for &v in mesh_a.face(fa) {
            if let Some(located) = loc_of_a.get(&v) {
                if side_b.in_closure(located.place, fb) {
                    keys.push(Key::A(v));
                }
            }
        }
        for &w in mesh_b.face(fb) {
            if let Some(located) = loc_of_b.get(&w) {
                if !matches!(located.place, Loc::Vertex(_)) && side_a.in_closure(located.place, fa)
                {
                    keys.push(Key::B(w));
                }
            }
        }
        for &ea in mesh_a.face_edges(fa) {
            for &eb in mesh_b.face_edges(fb) {
                let crossing = *crossings.entry((ea, eb)).or_insert_with(|| {
                    crossing(&side_a, &side_b, &loc_of_a, &loc_of_b, ea, eb, max_distance)
                });
                if crossing.is_some() {
                    keys.push(Key::X(ea, eb));
                }
            }
        }
        keys.sort_unstable();
        keys.dedup();
        if keys.len() < 3 {
            continue;
        }
        let chart = &side_a.charts[ia];
        let point_a = |key: &Key| match *key {
            Key::A(v) => mesh_a.vertex(v),
            Key::B(w) => loc_of_b[&w].point,
            Key::X(ea, eb) => crossings[&(ea, eb)].expect("a crossing").point_a,
        };
        let planar: Vec<[f64; 2]> = keys.iter().map(|k| chart.chart(point_a(k))).collect();
        let n = planar.len() as f64;
        let mean = planar
            .iter()
            .fold([0.0, 0.0], |m, q| [m[0] + q[0] / n, m[1] + q[1] / n]);
        let mut order: Vec<(f64, usize)> = planar
            .iter()
            .enumerate()
            .map(|(k, q)| ((q[1] - mean[1]).atan2(q[0] - mean[0]), k))
            .collect();
        order.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
        let mut area = 0.0;
        for k in 0..order.len() {
            let (p, q) = (planar[order[k].1], planar[order[(k + 1) % order.len()].1]);
            area += 0.5 * (p[0] * q[1] - p[1] * q[0]);
        }
        if area <= TOUCH_AREA_RATIO * chart.area {
            continue;
        }
        // Ordered by angle about their mean, the points bound the cell when it is star-shaped
        // with respect to that mean: always for convex faces, and checked for the others.
        for k in 0..order.len() {
            let (p, q) = (planar[order[k].1], planar[order[(k + 1) % order.len()].1]);
            let fan = (p[0] - mean[0]) * (q[1] - mean[1]) - (p[1] - mean[1]) * (q[0] - mean[0]);
            if fan < -TOUCH_AREA_RATIO * chart.area {
                return Err(fail(format!(
                    "the overlay of face {fa} of '{part_a}' and face {fb} of '{part_b}' is not \
                     star-shaped about the mean of its points: non-convex faces whose overlay \
                     this method does not cover"
                )));
            }
        }
        let loop_: Vec<Key> = order.iter().map(|&(_, k)| keys[k]).collect();
        if !(chart.convex && side_b.charts[ib].convex) {
            // A non-convex pair may meet in several pieces, which the ordering would bridge:
            // every side of the cell must lie in both faces.
            let point_b = |key: &Key| match *key {
                Key::A(v) => loc_of_a[&v].point,
                Key::B(w) => mesh_b.vertex(w),
                Key::X(ea, eb) => crossings[&(ea, eb)].expect("a crossing").point_b,
            };
            let n = loop_.len();
            for k in 0..n {
                let (x, y) = (&loop_[k], &loop_[(k + 1) % n]);
                let mid_a = point_a(x) + 0.5 * (point_a(y) - point_a(x));
                let mid_b = point_b(x) + 0.5 * (point_b(y) - point_b(x));
                if !side_a.contains(ia, mid_a) || !side_b.contains(ib, mid_b) {
                    return Err(fail(format!(
                        "face {fa} of '{part_a}' and face {fb} of '{part_b}' (one of them not \
                         convex) meet in more than one piece, which this overlay does not build"
                    )));
                }
            }
        }
        cells.push((ia, ib, loop_));
    }
    if cells.is_empty() {
        return Err(fail(format!(
            "the parts do not face each other: {} pairs of faces with opposed normals are \
             near, but their projections do not overlap (within max_distance)",
            pairs.len()
        )));
    }

    // 6. Nodes: new vertices on both sides, in order of first appearance.
    let (n_a, n_b) = (mesh_a.n_vertices(), mesh_b.n_vertices());
    let mut nodes: Vec<Node> = Vec::new();
    let mut node_of: Map<Key, usize> = Map::default();
    let (mut points_a, mut points_b) = (Vec::new(), Vec::new());
    let (mut new_loc_a, mut new_loc_b) = (Map::default(), Map::default());
    for (_, _, loop_) in &cells {
        for &key in loop_ {
            if node_of.contains_key(&key) {
                continue;
            }
            let (place_a, point_a, place_b, point_b) = match key {
                Key::A(v) => {
                    let located = loc_of_a[&v];
                    (
                        Loc::Vertex(v),
                        mesh_a.vertex(v),
                        located.place,
                        located.point,
                    )
                }
                Key::B(w) => {
                    let located = loc_of_b[&w];
                    (
                        located.place,
                        located.point,
                        Loc::Vertex(w),
                        mesh_b.vertex(w),
                    )
                }
                Key::X(ea, eb) => {
                    let c = crossings[&(ea, eb)].expect("a crossing");
                    (Loc::Edge(ea, c.t), c.point_a, Loc::Edge(eb, c.s), c.point_b)
                }
            };
            let vertex_a = match place_a {
                Loc::Vertex(v) => v,
                _ => {
                    points_a.push(point_a);
                    new_loc_a.insert(n_a + points_a.len() - 1, place_a);
                    n_a + points_a.len() - 1
                }
            };
            let vertex_b = match place_b {
                Loc::Vertex(w) => w,
                _ => {
                    points_b.push(point_b);
                    new_loc_b.insert(n_b + points_b.len() - 1, place_b);
                    n_b + points_b.len() - 1
                }
            };
            node_of.insert(key, nodes.len());
            nodes.push(Node {
                vertex_a,
                vertex_b,
                place_a,
            });
        }
    }
    let mut node_of_vertex_a: Map<usize, usize> = Map::default();
    let mut node_of_vertex_b: Map<usize, usize> = Map::default();
    for (k, node) in nodes.iter().enumerate() {
        if node_of_vertex_b.insert(node.vertex_b, k).is_some() {
            return Err(fail(format!(
                "vertex {} of '{part_b}' pairs with two points of '{part_a}'",
                node.vertex_b
            )));
        }
        node_of_vertex_a.insert(node.vertex_a, k);
    }
    let mut replaced_a: BTreeMap<usize, Vec<Vec<usize>>> = BTreeMap::new();
    let mut replaced_b: BTreeMap<usize, Vec<Vec<usize>>> = BTreeMap::new();
    for (ia, ib, loop_) in &cells {
        let ids: Vec<usize> = loop_.iter().map(|k| node_of[k]).collect();
        replaced_a
            .entry(side_a.charts[*ia].face)
            .or_default()
            .push(ids.iter().map(|&k| nodes[k].vertex_a).collect());
        replaced_b
            .entry(side_b.charts[*ib].face)
            .or_default()
            .push(ids.iter().rev().map(|&k| nodes[k].vertex_b).collect());
    }
    let inserted_a = points_a.len();
    let inserted_b = points_b.len();
    let (rebuilt_a, rebuilt_b) = std::thread::scope(|scope| {
        let b = scope.spawn(|| rebuild(mesh_b, part_b, points_b, &new_loc_b, replaced_b, &fail));
        let a = rebuild(mesh_a, part_a, points_a, &new_loc_a, replaced_a, &fail);
        (
            a,
            b.join()
                .unwrap_or_else(|panic| std::panic::resume_unwind(panic)),
        )
    });
    let (new_a, cell_loops_a) = rebuilt_a?;
    let (new_b, _) = rebuilt_b?;

    // Tributary areas from the cells of side a.
    let mut tributary = vec![0.0; nodes.len()];
    for loop_ in &cell_loops_a {
        let points: Vec<Point3> = loop_.iter().map(|&v| new_a.vertex(v)).collect();
        let normal = geometry::face_normal(&points);
        for (&v, w) in loop_.iter().zip(geometry::face_vertex_weights(&points)) {
            let k = *node_of_vertex_a.get(&v).ok_or_else(|| {
                fail(format!(
                    "vertex {v} of a cell of '{part_a}' is not an interface node"
                ))
            })?;
            tributary[k] += w.dot(&normal);
        }
    }
    let mut pairs: Vec<SurfacePair> = nodes
        .iter()
        .zip(&tributary)
        .map(|(node, &tributary_area)| {
            let (point_a, point_b) = (new_a.vertex(node.vertex_a), new_b.vertex(node.vertex_b));
            let normal = side_a.normal_at(node.place_a);
            SurfacePair {
                node_a: node.vertex_a,
                node_b: node.vertex_b,
                point_a,
                point_b,
                normal,
                tributary_area,
                initial_gap: (point_b - point_a).dot(&normal),
            }
        })
        .collect();
    pairs.sort_by_key(|p| p.node_a);
    Ok(SurfaceInterface {
        mesh_a: new_a,
        mesh_b: new_b,
        part_a: part_a.to_string(),
        part_b: part_b.to_string(),
        pairs,
        inserted_a,
        inserted_b,
    })
}

/// The unit vector along `v` (zero for zero).
fn unit(v: Vector3) -> Vector3 {
    let norm = v.norm();
    if norm > 0.0 {
        v / norm
    } else {
        v
    }
}

/// A place on a part: at a vertex, on an edge (parameter from the edge's first vertex, as
/// [`PolyhedralMesh::edge`] lists them), or inside a face.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Loc {
    Vertex(usize),
    Edge(usize, f64),
    Face(usize),
}

/// A projected point located on the other part: its place and its coordinates there.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Located {
    place: Loc,
    point: Point3,
}

/// Where a projection falls in one face: on it (snapped or inside), or outside at a distance
/// from its nearest boundary point.
enum Placement {
    On(Loc),
    Outside { distance: f64, nearest: Loc },
}

/// Ranking of candidate placements of one projection: placements on a face first (nearest
/// along the normal), then placements outside every face (nearest to the face first); ties by
/// chart index.
type Rank = (u8, f64, usize);

/// Keeps the better of `best` and the placement `place` of a projection at distance `gap`
/// into chart `chart` of `side` (the point `point` when inside the face). A projection that
/// misses every face is placed by the face it misses least: on that face's nearest edge or
/// vertex when this is a seam within [`SEAM_FRACTION`] of it, and nowhere (`None`) when it is
/// on the part's rim or farther: a point beyond the rim is not rescued onto an inner seam by a
/// face it misses by more.
fn consider(
    best: &mut Option<(Rank, Option<Located>)>,
    place: Placement,
    gap: f64,
    chart: usize,
    point: Point3,
    side: &Side,
) {
    let (rank, place) = match place {
        Placement::On(place) => ((0, gap.abs(), chart), Some(place)),
        Placement::Outside { distance, nearest } => {
            let seam = side.is_seam(nearest) && distance <= SEAM_FRACTION * side.scale_at(nearest);
            ((1, distance, chart), seam.then_some(nearest))
        }
    };
    if best.as_ref().is_none_or(|(r, _)| rank < *r) {
        let located = place.map(|place| Located {
            place,
            point: match place {
                Loc::Face(_) => point,
                _ => side.point_at(place),
            },
        });
        *best = Some((rank, located));
    }
}

/// The points of the overlay, by origin.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
enum Key {
    /// A vertex of a (with its projection on b).
    A(usize),
    /// A vertex of b not snapped to a vertex of a (with its projection on a).
    B(usize),
    /// The crossing of edge .0 of a with edge .1 of b.
    X(usize, usize),
}

/// A node of the overlay: its vertices in the new meshes and its place on a.
struct Node {
    vertex_a: usize,
    vertex_b: usize,
    place_a: Loc,
}

/// A crossing of an edge of a and an edge of b: parameters along each (from the edge's first
/// vertex) and the points on each.
#[derive(Debug, Clone, Copy)]
struct Crossing {
    t: f64,
    s: f64,
    point_a: Point3,
    point_b: Point3,
}

/// The crossing of edge `ea` of a with edge `eb` of b (module documentation, step 4).
fn crossing(
    side_a: &Side,
    side_b: &Side,
    loc_of_a: &Map<usize, Located>,
    loc_of_b: &Map<usize, Located>,
    ea: usize,
    eb: usize,
    max_distance: f64,
) -> Option<Crossing> {
    let [v1, v2] = side_a.mesh.edge(ea);
    let [w1, w2] = side_b.mesh.edge(eb);
    for v in [v1, v2] {
        match loc_of_a.get(&v).map(|l| l.place) {
            Some(Loc::Vertex(w)) if w == w1 || w == w2 => return None,
            Some(Loc::Edge(e, _)) if e == eb => return None,
            _ => {}
        }
    }
    for w in [w1, w2] {
        match loc_of_b.get(&w).map(|l| l.place) {
            Some(Loc::Vertex(v)) if v == v1 || v == v2 => return None,
            Some(Loc::Edge(e, _)) if e == ea => return None,
            _ => {}
        }
    }
    let normal = side_a.edge_normal(ea);
    let (x1, x2) = (side_a.mesh.vertex(v1), side_a.mesh.vertex(v2));
    let (y1, y2) = (side_b.mesh.vertex(w1), side_b.mesh.vertex(w2));
    let d = x2 - x1;
    let across = d.cross(&normal);
    let (d1, d2) = ((y1 - x1).dot(&across), (y2 - x1).dot(&across));
    if !((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0)) {
        return None;
    }
    let s = d1 / (d1 - d2);
    let point_b = y1 + s * (y2 - y1);
    let t = (point_b - x1).dot(&d) / d.norm_squared();
    if !(t > 0.0 && t < 1.0) || (point_b - x1).dot(&normal).abs() > max_distance {
        return None;
    }
    Some(Crossing {
        t,
        s,
        point_a: x1 + t * d,
        point_b,
    })
}

/// Axis-aligned bounding box.
#[derive(Debug, Clone, Copy)]
struct Aabb {
    lo: Point3,
    hi: Point3,
}

impl Aabb {
    fn of(points: impl IntoIterator<Item = Point3>) -> Self {
        let mut b = Aabb {
            lo: Point3::from(Vector3::repeat(f64::INFINITY)),
            hi: Point3::from(Vector3::repeat(f64::NEG_INFINITY)),
        };
        for p in points {
            b.lo = b.lo.inf(&p);
            b.hi = b.hi.sup(&p);
        }
        b
    }

    fn union(&self, other: &Aabb) -> (Point3, Point3) {
        (self.lo.inf(&other.lo), self.hi.sup(&other.hi))
    }

    fn overlaps(&self, other: &Aabb) -> bool {
        (0..3).all(|k| self.lo[k] <= other.hi[k] && other.lo[k] <= self.hi[k])
    }
}

/// One face of a contact part in its plane: an orthonormal chart (u, w) about its centroid.
struct Chart {
    face: usize,
    centroid: Point3,
    normal: Vector3,
    u: Vector3,
    w: Vector3,
    polygon: Vec<[f64; 2]>,
    lengths: Vec<f64>,
    area: f64,
    bbox: Aabb,
    /// True when no corner of the polygon is reflex (collinear corners allowed).
    convex: bool,
}

impl Chart {
    fn chart(&self, p: Point3) -> [f64; 2] {
        let d = p - self.centroid;
        [d.dot(&self.u), d.dot(&self.w)]
    }
}

/// A contact part prepared for the overlay.
struct Side<'m> {
    mesh: &'m PolyhedralMesh,
    charts: Vec<Chart>,
    /// Part faces (chart indices) around each part vertex and each part edge.
    charts_of_vertex: Map<usize, Vec<usize>>,
    charts_of_edge: Map<usize, Vec<usize>>,
    chart_of_face: Map<usize, usize>,
    bbox: Aabb,
}

impl<'m> Side<'m> {
    fn new(
        mesh: &'m PolyhedralMesh,
        part: &str,
        fail: &dyn Fn(String) -> MeshError,
    ) -> Result<Self, MeshError> {
        let faces = mesh.part_faces(part)?;
        if faces.is_empty() {
            return Err(fail(format!("part '{part}' has no faces")));
        }
        let mut charts = Vec::with_capacity(faces.len());
        let mut charts_of_vertex: Map<usize, Vec<usize>> = Map::default();
        let mut charts_of_edge: Map<usize, Vec<usize>> = Map::default();
        for (index, &f) in faces.iter().enumerate() {
            let points = mesh.face_points(f);
            let normal = geometry::face_normal(&points);
            let centroid = geometry::face_centroid(&points);
            let diameter = geometry::diameter(&points);
            if geometry::face_warping(&points) > PLANARITY_RATIO * diameter {
                return Err(fail(format!(
                    "face {f} of '{part}' is warped: the overlay needs planar contact faces"
                )));
            }
            let u = unit(points[1] - points[0]);
            let u = unit(u - u.dot(&normal) * normal);
            let w = normal.cross(&u);
            let mut chart = Chart {
                face: f,
                centroid,
                normal,
                u,
                w,
                polygon: Vec::with_capacity(points.len()),
                lengths: Vec::with_capacity(points.len()),
                area: geometry::face_area(&points),
                bbox: Aabb::of(points.iter().copied()),
                convex: true,
            };
            chart.polygon = points.iter().map(|&p| chart.chart(p)).collect();
            let n = points.len();
            chart.lengths = (0..n)
                .map(|k| (points[(k + 1) % n] - points[k]).norm())
                .collect();
            chart.convex = (0..n).all(|k| {
                let (p, q, r) = (
                    chart.polygon[k],
                    chart.polygon[(k + 1) % n],
                    chart.polygon[(k + 2) % n],
                );
                let turn = (q[0] - p[0]) * (r[1] - q[1]) - (q[1] - p[1]) * (r[0] - q[0]);
                turn >= -1e-12 * chart.lengths[k] * chart.lengths[(k + 1) % n]
            });
            for &v in mesh.face(f) {
                charts_of_vertex.entry(v).or_default().push(index);
            }
            for &e in mesh.face_edges(f) {
                charts_of_edge.entry(e).or_default().push(index);
            }
            charts.push(chart);
        }
        let bbox = Aabb::of(
            charts
                .iter()
                .flat_map(|c| [c.bbox.lo, c.bbox.hi].into_iter()),
        );
        let chart_of_face = charts
            .iter()
            .enumerate()
            .map(|(k, c)| (c.face, k))
            .collect();
        Ok(Self {
            mesh,
            charts,
            charts_of_vertex,
            charts_of_edge,
            chart_of_face,
            bbox,
        })
    }

    /// Outward nodal normal at part vertex `v` (area-weighted face normals).
    fn vertex_normal(&self, v: usize) -> Vector3 {
        unit(
            self.charts_of_vertex[&v]
                .iter()
                .map(|&c| self.charts[c].area * self.charts[c].normal)
                .sum(),
        )
    }

    /// Outward normal of part edge `e` (area-weighted normals of its one or two part faces).
    fn edge_normal(&self, e: usize) -> Vector3 {
        unit(
            self.charts_of_edge[&e]
                .iter()
                .map(|&c| self.charts[c].area * self.charts[c].normal)
                .sum(),
        )
    }

    /// The nodal normal at a place of the part.
    fn normal_at(&self, place: Loc) -> Vector3 {
        match place {
            Loc::Vertex(v) => self.vertex_normal(v),
            Loc::Edge(e, _) => self.edge_normal(e),
            Loc::Face(f) => self.charts[self.chart_of_face[&f]].normal,
        }
    }

    /// Coordinates of a vertex or edge place.
    fn point_at(&self, place: Loc) -> Point3 {
        match place {
            Loc::Vertex(v) => self.mesh.vertex(v),
            Loc::Edge(e, t) => {
                let [p, q] = self.mesh.edge(e);
                let (p, q) = (self.mesh.vertex(p), self.mesh.vertex(q));
                p + t * (q - p)
            }
            Loc::Face(_) => unreachable!("a face place has the projected point"),
        }
    }

    /// True when the place is on a seam of a curved part: not on its rim (an edge with two
    /// part faces, a vertex all of whose part edges have two) and where the part bends (the
    /// faces at the place are not all coplanar). Projections never miss a flat part's faces
    /// between two of them, so nothing is placed on a flat part's edges by this rescue.
    fn is_seam(&self, place: Loc) -> bool {
        let bends = |charts: &[usize]| {
            let first = self.charts[charts[0]].normal;
            charts
                .iter()
                .any(|&c| self.charts[c].normal.dot(&first) < 1.0 - 1e-12)
        };
        match place {
            Loc::Edge(e, _) => {
                self.charts_of_edge[&e].len() == 2 && bends(&self.charts_of_edge[&e])
            }
            Loc::Vertex(v) => {
                bends(&self.charts_of_vertex[&v])
                    && self.charts_of_vertex[&v].iter().all(|&c| {
                        let f = self.charts[c].face;
                        let face = self.mesh.face(f);
                        let k = face
                            .iter()
                            .position(|&x| x == v)
                            .expect("a vertex of the face");
                        let n = face.len();
                        let edges = self.mesh.face_edges(f);
                        self.charts_of_edge[&edges[k]].len() == 2
                            && self.charts_of_edge[&edges[(k + n - 1) % n]].len() == 2
                    })
            }
            Loc::Face(_) => true,
        }
    }

    /// Length scale of a vertex or edge place (shortest edge at a vertex).
    fn scale_at(&self, place: Loc) -> f64 {
        let length = |e: usize| {
            let [p, q] = self.mesh.edge(e);
            (self.mesh.vertex(q) - self.mesh.vertex(p)).norm()
        };
        match place {
            Loc::Edge(e, _) => length(e),
            Loc::Vertex(v) => self.charts_of_vertex[&v]
                .iter()
                .flat_map(|&c| self.mesh.face_edges(self.charts[c].face).iter())
                .filter(|&&e| self.mesh.edge(e).contains(&v))
                .map(|&e| length(e))
                .fold(f64::INFINITY, f64::min),
            Loc::Face(_) => 0.0,
        }
    }

    /// True when `place` lies in the closed face `f`.
    fn in_closure(&self, place: Loc, f: usize) -> bool {
        match place {
            Loc::Vertex(v) => self.mesh.face(f).contains(&v),
            Loc::Edge(e, _) => self.mesh.face_edges(f).contains(&e),
            Loc::Face(g) => g == f,
        }
    }

    /// True when `p` (in the plane of chart `c`) lies in the closed face, to 1e-9 of the
    /// face's longest edge.
    fn contains(&self, c: usize, p: Point3) -> bool {
        let chart = &self.charts[c];
        let q = chart.chart(p);
        let poly = &chart.polygon;
        let n = poly.len();
        let tolerance = 1e-9 * chart.lengths.iter().copied().fold(0.0, f64::max);
        let mut inside = false;
        for k in 0..n {
            let (a, b) = (poly[k], poly[(k + 1) % n]);
            let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
            let (rx, ry) = (q[0] - a[0], q[1] - a[1]);
            let t = ((rx * dx + ry * dy) / (dx * dx + dy * dy)).clamp(0.0, 1.0);
            if ((rx - t * dx).powi(2) + (ry - t * dy).powi(2)).sqrt() <= tolerance {
                return true;
            }
            if (a[1] > q[1]) != (b[1] > q[1]) && q[0] < a[0] + (q[1] - a[1]) / dy * dx {
                inside = !inside;
            }
        }
        inside
    }

    /// Locates the point `p` (in the plane of chart `c`) in its face: at a vertex within `snap`
    /// of the shorter adjacent edge (only vertices `may_snap` accepts), on an edge within `snap`
    /// of its length, inside, or outside.
    fn locate(
        &self,
        c: usize,
        p: Point3,
        snap: f64,
        may_snap: &dyn Fn(usize) -> bool,
    ) -> Placement {
        let chart = &self.charts[c];
        let q = chart.chart(p);
        let face = self.mesh.face(chart.face);
        let edges = self.mesh.face_edges(chart.face);
        let n = face.len();
        let poly = &chart.polygon;
        let mut best: Option<(f64, usize)> = None;
        for k in 0..n {
            let d = ((q[0] - poly[k][0]).powi(2) + (q[1] - poly[k][1]).powi(2)).sqrt();
            let tolerance = snap * chart.lengths[k].min(chart.lengths[(k + n - 1) % n]);
            if d <= tolerance && may_snap(face[k]) && best.is_none_or(|(b, _)| d < b) {
                best = Some((d, k));
            }
        }
        if let Some((_, k)) = best {
            return Placement::On(Loc::Vertex(face[k]));
        }
        let mesh_parameter = |k: usize, t: f64| {
            if self.mesh.edge(edges[k])[0] == face[k] {
                t
            } else {
                1.0 - t
            }
        };
        let mut nearest: Option<(f64, usize, f64)> = None;
        let mut inside = false;
        for k in 0..n {
            let (a, b) = (poly[k], poly[(k + 1) % n]);
            let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
            let (rx, ry) = (q[0] - a[0], q[1] - a[1]);
            // Crossing number of the ray from q along +u (any simple polygon).
            if (a[1] > q[1]) != (b[1] > q[1]) && q[0] < a[0] + (q[1] - a[1]) / dy * dx {
                inside = !inside;
            }
            let t = ((rx * dx + ry * dy) / (dx * dx + dy * dy)).clamp(0.0, 1.0);
            let d = ((rx - t * dx).powi(2) + (ry - t * dy).powi(2)).sqrt();
            if nearest.is_none_or(|(b, _, _)| d < b) {
                nearest = Some((d, k, t));
            }
        }
        let (d, k, t) = nearest.expect("a face has edges");
        if d <= snap * chart.lengths[k] && t > 0.0 && t < 1.0 {
            return Placement::On(Loc::Edge(edges[k], mesh_parameter(k, t)));
        }
        if inside {
            return Placement::On(Loc::Face(chart.face));
        }
        let nearest = if t <= 0.0 {
            Loc::Vertex(face[k])
        } else if t >= 1.0 {
            Loc::Vertex(face[(k + 1) % n])
        } else {
            Loc::Edge(edges[k], mesh_parameter(k, t))
        };
        Placement::Outside {
            distance: d,
            nearest,
        }
    }
}

/// The pairs (chart of a, chart of b) whose faces may overlap: b's faces in a uniform grid,
/// queried with each face of a swept along its normal by `reach`; normals opposed.
fn candidate_pairs(side_a: &Side, side_b: &Side, reach: f64) -> Vec<(usize, usize)> {
    let size = side_b
        .charts
        .iter()
        .map(|c| (c.bbox.hi - c.bbox.lo).norm())
        .sum::<f64>()
        / side_b.charts.len() as f64;
    // Cells of about the mean face size, but no face in more than 17^3 cells.
    let largest = side_b
        .charts
        .iter()
        .map(|c| (c.bbox.hi - c.bbox.lo).norm())
        .fold(0.0, f64::max);
    let size = size.max(largest / 16.0);
    let size = if size > 0.0 && size.is_finite() {
        size
    } else {
        1.0
    };
    let origin = side_b.bbox.lo;
    let key = |p: Point3| -> [i64; 3] {
        let r = (p - origin) / size;
        [r.x.floor() as i64, r.y.floor() as i64, r.z.floor() as i64]
    };
    let limit = key(side_b.bbox.hi);
    let mut grid: Map<[i64; 3], Vec<usize>> = Map::default();
    for (ib, chart) in side_b.charts.iter().enumerate() {
        let (lo, hi) = (key(chart.bbox.lo), key(chart.bbox.hi));
        for i in lo[0]..=hi[0] {
            for j in lo[1]..=hi[1] {
                for k in lo[2]..=hi[2] {
                    grid.entry([i, j, k]).or_default().push(ib);
                }
            }
        }
    }
    let mut pairs = Vec::new();
    let mut found = Vec::new();
    for (ia, chart) in side_a.charts.iter().enumerate() {
        let pad = SEAM_FRACTION * chart.lengths.iter().copied().fold(0.0, f64::max);
        let sweep = chart.normal * reach;
        let swept = Aabb {
            lo: (chart.bbox.lo - sweep.abs()).map(|x| x - pad),
            hi: (chart.bbox.hi + sweep.abs()).map(|x| x + pad),
        };
        let (lo, hi) = (key(swept.lo), key(swept.hi));
        found.clear();
        let (lo, hi) = (
            [lo[0].max(0), lo[1].max(0), lo[2].max(0)],
            [
                hi[0].min(limit[0]),
                hi[1].min(limit[1]),
                hi[2].min(limit[2]),
            ],
        );
        let cells: f64 = (0..3)
            .map(|d| (hi[d] as f64 - lo[d] as f64 + 1.0).max(0.0))
            .product();
        if cells > grid.len() as f64 {
            // A query larger than the occupied grid (far-flung parts): scan what is there.
            for (key, list) in &grid {
                if (0..3).all(|d| key[d] >= lo[d] && key[d] <= hi[d]) {
                    found.extend_from_slice(list);
                }
            }
        } else {
            for i in lo[0]..=hi[0] {
                for j in lo[1]..=hi[1] {
                    for k in lo[2]..=hi[2] {
                        if let Some(list) = grid.get(&[i, j, k]) {
                            found.extend_from_slice(list);
                        }
                    }
                }
            }
        }
        found.sort_unstable();
        found.dedup();
        for &ib in &found {
            let other = &side_b.charts[ib];
            if chart.normal.dot(&other.normal) < 0.0 && swept.overlaps(&other.bbox) {
                pairs.push((ia, ib));
            }
        }
    }
    pairs
}

/// The mesh with the overlay: every face's loop with the points inserted on its edges, each
/// replaced face (key of `replaced`) as its cells (loops of new vertex indices, ordered but
/// not yet with the points on their edges) and the rest of it. Returns the mesh and the cells'
/// loops with the points on their edges.
fn rebuild(
    mesh: &PolyhedralMesh,
    part: &str,
    new_points: Vec<Point3>,
    new_loc: &Map<usize, Loc>,
    replaced: BTreeMap<usize, Vec<Vec<usize>>>,
    fail: &dyn Fn(String) -> MeshError,
) -> Result<(PolyhedralMesh, Vec<Vec<usize>>), MeshError> {
    let n_old = mesh.n_vertices();
    let mut on_edge: Map<usize, Vec<(f64, usize)>> = Map::default();
    for (&v, &place) in new_loc {
        if let Loc::Edge(e, t) = place {
            on_edge.entry(e).or_default().push((t, v));
        }
    }
    for list in on_edge.values_mut() {
        list.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
    }
    let place = |v: usize| {
        if v < n_old {
            Loc::Vertex(v)
        } else {
            new_loc[&v]
        }
    };
    // Parameter of vertex `v` along edge `e`, if it lies on it.
    let along = |v: usize, e: usize| -> Option<f64> {
        let [p, q] = mesh.edge(e);
        match place(v) {
            Loc::Vertex(x) if x == p => Some(0.0),
            Loc::Vertex(x) if x == q => Some(1.0),
            Loc::Edge(f, t) if f == e => Some(t),
            _ => None,
        }
    };
    // The points of edge `e` strictly between parameters `from` and `to`, in that order.
    let between = |e: usize, from: f64, to: f64, out: &mut Vec<usize>| {
        if let Some(list) = on_edge.get(&e) {
            if from < to {
                out.extend(
                    list.iter()
                        .filter(|&&(t, _)| t > from && t < to)
                        .map(|&(_, v)| v),
                );
            } else {
                out.extend(
                    list.iter()
                        .rev()
                        .filter(|&&(t, _)| t < from && t > to)
                        .map(|&(_, v)| v),
                );
            }
        }
    };
    let densify_face = |f: usize| -> Vec<usize> {
        let face = mesh.face(f);
        let mut out = Vec::with_capacity(face.len());
        for (k, &u) in face.iter().enumerate() {
            out.push(u);
            let e = mesh.face_edges(f)[k];
            let [p, _] = mesh.edge(e);
            if u == p {
                between(e, 0.0, 1.0, &mut out);
            } else {
                between(e, 1.0, 0.0, &mut out);
            }
        }
        out
    };
    let densify_cell = |f: usize, loop_: &[usize]| -> Vec<usize> {
        let n = loop_.len();
        let mut out = Vec::with_capacity(n);
        for k in 0..n {
            let (x, y) = (loop_[k], loop_[(k + 1) % n]);
            out.push(x);
            for &e in mesh.face_edges(f) {
                if let (Some(tx), Some(ty)) = (along(x, e), along(y, e)) {
                    between(e, tx, ty, &mut out);
                    break;
                }
            }
        }
        out
    };

    let mut vertices = mesh.vertices().to_vec();
    vertices.extend(new_points);
    let mut face_offsets = Vec::with_capacity(mesh.n_faces() + 1);
    face_offsets.push(0);
    let mut face_vertices = Vec::with_capacity(mesh.face_vertex_indices().len() * 2);
    let mut extra: Vec<(usize, Vec<usize>)> = Vec::new();
    let mut cell_loops = Vec::new();
    for f in 0..mesh.n_faces() {
        let boundary = densify_face(f);
        let loops = match replaced.get(&f) {
            None => vec![boundary],
            Some(cells) => {
                let cells: Vec<Vec<usize>> = cells.iter().map(|c| densify_cell(f, c)).collect();
                let normal = mesh.face_normal(f);
                let rest = remainder(&boundary, &cells, &|v| vertices[v], normal)
                    .map_err(|reason| fail(format!("face {f} of '{part}': {reason}")))?;
                for loop_ in &rest {
                    let points: Vec<Point3> = loop_.iter().map(|&v| vertices[v]).collect();
                    if geometry::face_vector_area(&points).dot(&normal) <= 0.0 {
                        return Err(fail(format!(
                            "face {f} of '{part}': the other part covers an inner region of it \
                             only (the rest would be a face with a hole): refine the mesh of \
                             '{part}' there, or make the other part reach beyond this face"
                        )));
                    }
                }
                cell_loops.extend(cells.iter().cloned());
                if cells.len() == 1 && rest.is_empty() {
                    // One cell covers the face: it is the face's own loop (same start).
                    vec![boundary]
                } else {
                    cells.into_iter().chain(rest).collect()
                }
            }
        };
        let mut loops = loops.into_iter();
        face_vertices.extend(loops.next().expect("one loop at least"));
        face_offsets.push(face_vertices.len());
        extra.extend(loops.map(|l| (f, l)));
    }
    // The extra faces: appended, boundary faces outward for the owner of the face they split.
    let n_faces = mesh.n_faces();
    let mut extra_of_cell: Map<usize, Vec<usize>> = Map::default();
    let mut extra_of_face: Map<usize, Vec<usize>> = Map::default();
    for (k, (f, loop_)) in extra.into_iter().enumerate() {
        face_vertices.extend(loop_);
        face_offsets.push(face_vertices.len());
        extra_of_cell
            .entry(mesh.face_cells(f).owner)
            .or_default()
            .push(n_faces + k);
        extra_of_face.entry(f).or_default().push(n_faces + k);
    }
    let mut cell_offsets = Vec::with_capacity(mesh.n_cells() + 1);
    cell_offsets.push(0);
    let mut cell_faces = Vec::with_capacity(mesh.cell_face_indices().len() + extra_of_face.len());
    for c in 0..mesh.n_cells() {
        cell_faces.extend_from_slice(mesh.cell_faces(c));
        if let Some(list) = extra_of_cell.get(&c) {
            cell_faces.extend(list.iter().map(|&f| OrientedFace::new(f, true)));
        }
        cell_offsets.push(cell_faces.len());
    }
    let parts: Vec<FacePart> = mesh
        .parts()
        .iter()
        .map(|p| {
            let mut faces = p.faces.clone();
            for f in &p.faces {
                if let Some(list) = extra_of_face.get(f) {
                    faces.extend_from_slice(list);
                }
            }
            FacePart::new(p.name.clone(), faces)
        })
        .collect();
    let new_mesh = PolyhedralMesh::from_compact(
        vertices,
        face_offsets,
        face_vertices,
        cell_offsets,
        cell_faces,
        parts,
    )
    .map_err(|e| {
        fail(format!(
            "the mesh of '{part}' with the overlay is not valid: {e}"
        ))
    })?;
    Ok((new_mesh, cell_loops))
}

/// The rest of a face: its boundary loop minus the boundaries of its cells (directed edges
/// that cancel are dropped), traced as loops with the rest on their left (seen along
/// `normal`). Where pieces of the rest touch at a vertex (the other part's outline passes
/// through a vertex, as where two faces of a box-cut part meet at a corner only), the trace
/// leaves the vertex by the first edge clockwise from the one it came in by, so that each
/// piece is its own simple loop. Errors when cells overlap.
fn remainder(
    boundary: &[usize],
    cells: &[Vec<usize>],
    point: &dyn Fn(usize) -> Point3,
    normal: Vector3,
) -> Result<Vec<Vec<usize>>, String> {
    let mut net: BTreeMap<(usize, usize), i32> = BTreeMap::new();
    let mut add = |loop_: &[usize], sign: i32| {
        let n = loop_.len();
        for k in 0..n {
            let (x, y) = (loop_[k], loop_[(k + 1) % n]);
            let (key, value) = if x < y { ((x, y), 1) } else { ((y, x), -1) };
            *net.entry(key).or_default() += sign * value;
        }
    };
    add(boundary, 1);
    for cell in cells {
        add(cell, -1);
    }
    let mut next: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
    for (&(x, y), &value) in &net {
        let (from, to) = match value {
            0 => continue,
            1 => (x, y),
            -1 => (y, x),
            _ => {
                return Err(format!(
                    "overlay cells overlap along the edge ({x}, {y}): the projected surfaces \
                     fold over"
                ))
            }
        };
        next.entry(from).or_default().push(to);
    }
    // Chart of the face's plane for the choice at a vertex where pieces touch.
    let u = {
        let e = if normal.x.abs() < 0.9 {
            Vector3::x()
        } else {
            Vector3::y()
        };
        unit(e - e.dot(&normal) * normal)
    };
    let w = normal.cross(&u);
    let angle = |from: usize, to: usize| {
        let d = point(to) - point(from);
        d.dot(&w).atan2(d.dot(&u))
    };
    let take = |next: &mut BTreeMap<usize, Vec<usize>>,
                from: usize,
                came: Option<usize>|
     -> Option<usize> {
        let list = next.get_mut(&from)?;
        let k = match (came, list.len()) {
            (_, 0) => return None,
            (None, _) | (_, 1) => 0,
            (Some(prev), _) => {
                // The first outgoing edge clockwise from the direction back to `prev`.
                let back = angle(from, prev);
                let turn = |to: usize| (back - angle(from, to)).rem_euclid(std::f64::consts::TAU);
                (0..list.len())
                    .min_by(|&i, &j| turn(list[i]).total_cmp(&turn(list[j])))
                    .expect("a non-empty list")
            }
        };
        let to = list.swap_remove(k);
        if list.is_empty() {
            next.remove(&from);
        }
        Some(to)
    };
    let mut loops = Vec::new();
    while let Some(start) = next.keys().next().copied() {
        let mut loop_ = vec![start];
        let mut previous = start;
        let mut at = take(&mut next, start, None).expect("an outgoing edge");
        while at != start {
            loop_.push(at);
            let to = take(&mut next, at, Some(previous)).ok_or_else(|| {
                format!("the cells' boundaries leave an open chain at vertex {at}")
            })?;
            previous = at;
            at = to;
        }
        if loop_.len() < 3 {
            return Err(format!(
                "a degenerate uncovered piece through vertices {loop_:?}"
            ));
        }
        loops.push(loop_);
    }
    Ok(loops)
}
