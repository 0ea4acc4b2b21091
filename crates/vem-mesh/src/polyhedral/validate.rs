//! Validation of polyhedral meshes: every constructor of [`crate::PolyhedralMesh`] runs these
//! checks, and the first failure is returned as a [`MeshError`] naming the cell, face, edge or
//! vertex.
//!
//! Checks, in the order they run:
//!
//! 1. storage: at least one vertex, face and cell ([`MeshError::EmptyPolyhedral`]); finite
//!    coordinates ([`MeshError::NonFiniteVertex3`]); offsets consistent
//!    ([`MeshError::BadStorage`]); every face has at least three vertices, in range, none
//!    repeated ([`MeshError::FaceTooFewVertices`], [`MeshError::FaceVertexOutOfRange`],
//!    [`MeshError::FaceRepeatedVertex`]); every cell has at least four faces, in range, none
//!    repeated ([`MeshError::CellTooFewFaces`], [`MeshError::CellFaceOutOfRange`],
//!    [`MeshError::CellRepeatedFace`]); every vertex belongs to a face
//!    ([`MeshError::UnusedVertex`]);
//! 2. face sharing: every face belongs to one or two cells ([`MeshError::UnusedFace`],
//!    [`MeshError::OverusedFace`]), outward for one and inward for the other
//!    ([`MeshError::FaceSameOrientation`]); no two faces have the same vertex set
//!    ([`MeshError::DuplicateFace`]);
//! 3. cells: the faces of a cell, each oriented as the cell sees it, traverse every edge exactly
//!    once in each direction, so the cell's surface is closed and consistently oriented
//!    ([`MeshError::CellNotClosed`]), and are connected through shared edges
//!    ([`MeshError::DisconnectedCell`]);
//! 4. boundary: nothing left to check, it is a closed surface (the sum of the closed cell
//!    surfaces, in which the interior faces cancel in pairs);
//! 5. coincidence: no two distinct vertices closer than the coincidence tolerance
//!    ([`MeshError::DuplicateVertices`]);
//! 6. faces: positive area ([`MeshError::DegenerateFace`]); a planar face (see below) is a
//!    simple polygon in its plane ([`MeshError::SelfIntersectingFace`]); a warped face's fan
//!    does not fold over ([`MeshError::FoldedFace`]);
//! 7. cells: positive volume ([`MeshError::InvertedCell`] when negative: faces oriented inward;
//!    [`MeshError::DegenerateCell`] when negligible);
//! 8. conformity: no vertex lies on a face, in its interior or on one of its edges, without
//!    being one of its vertices ([`MeshError::HangingVertex`]): a hanging node must be listed by
//!    every face it lies on, and two cells meant to share a face must list the same vertices.
//!    For a warped face only its edges are searched;
//! 9. parts: unique names ([`MeshError::DuplicatePart`]), faces in range
//!    ([`MeshError::PartFaceOutOfRange`]) and on the boundary
//!    ([`MeshError::InteriorFaceInPart`]).
//!
//! # Planar and warped faces
//!
//! A face whose vertices lie within [`PLANARITY_RATIO`] times its diameter of its mean plane
//! (through its vertex mean, normal along its vector area) is *planar*: it may be any simple
//! polygon (convex or not, with collinear vertices), and its geometry is exact. A face farther
//! from planar is *warped*: it is defined as its fan triangulation about its vertex mean (as the
//! element's face integrals are), and it is accepted when that fan does not fold over, i.e. every
//! fan triangle's vector area points to the same side as the face's ([`MeshError::FoldedFace`]
//! otherwise). Perturbed hexahedra have such faces; how warped a mesh's faces are is a quality
//! figure ([`super::quality`]).
//!
//! # What is not checked
//!
//! Cells are checked one by one, through their shared faces, and for vertices lying on faces that
//! do not list them; two cells that overlap in space with no vertex of one on a face of the other
//! (for example, faces crossing each other's interiors), and a cell whose surface intersects
//! itself with all edges paired, are not detected: that needs face-face intersection tests that
//! are not run.
//!
//! # Cost
//!
//! Close to linear in the size of the mesh: sorts, and uniform grids for the coincidence and
//! conformity searches. Building 10^5 hexahedra, validation included, takes about 1 s on one
//! core (`docs/polyhedral.md`).

use super::geometry;
use super::mesh::{FaceCells, FacePart, OrientedFace};
use crate::validate::COINCIDENCE_RATIO;
use crate::{MeshError, Point, Point3, PolyhedralMesh, Vector3};

/// Relative distance from a face's mean plane below which the face counts as planar: a face is
/// planar when every vertex lies within `PLANARITY_RATIO` times the face's diameter of the
/// plane through its vertex mean normal to its vector area.
pub const PLANARITY_RATIO: f64 = 1e-6;

/// Relative area below which a face is degenerate: area <= this * diameter^2.
pub const DEGENERATE_FACE_RATIO: f64 = 1e-12;

/// Relative volume below which a cell is degenerate: |volume| <= this * diagonal^3, with the
/// diagonal of the cell's bounding box.
pub const DEGENERATE_VOLUME_RATIO: f64 = 1e-12;

/// Step 1: the compact storage.
pub(crate) fn check_storage(
    vertices: &[Point3],
    face_offsets: &[usize],
    face_vertices: &[usize],
    cell_offsets: &[usize],
    cell_faces: &[OrientedFace],
) -> Result<(), MeshError> {
    let n_faces = face_offsets.len().saturating_sub(1);
    let n_cells = cell_offsets.len().saturating_sub(1);
    if vertices.is_empty() || n_faces == 0 || n_cells == 0 {
        return Err(MeshError::EmptyPolyhedral {
            vertices: vertices.len(),
            faces: n_faces,
            cells: n_cells,
        });
    }
    if let Some((vertex, p)) = vertices
        .iter()
        .enumerate()
        .find(|(_, p)| !(p.x.is_finite() && p.y.is_finite() && p.z.is_finite()))
    {
        return Err(MeshError::NonFiniteVertex3 {
            vertex,
            x: p.x,
            y: p.y,
            z: p.z,
        });
    }
    check_offsets("face", face_offsets, face_vertices.len())?;
    check_offsets("cell", cell_offsets, cell_faces.len())?;
    let mut sorted = Vec::new();
    let mut used = vec![false; vertices.len()];
    for f in 0..n_faces {
        let loop_ = &face_vertices[face_offsets[f]..face_offsets[f + 1]];
        if loop_.len() < 3 {
            return Err(MeshError::FaceTooFewVertices {
                face: f,
                count: loop_.len(),
            });
        }
        if let Some(&vertex) = loop_.iter().find(|&&v| v >= vertices.len()) {
            return Err(MeshError::FaceVertexOutOfRange {
                face: f,
                vertex,
                vertex_count: vertices.len(),
            });
        }
        sorted.clear();
        sorted.extend_from_slice(loop_);
        sorted.sort_unstable();
        if let Some(w) = sorted.windows(2).find(|w| w[0] == w[1]) {
            return Err(MeshError::FaceRepeatedVertex {
                face: f,
                vertex: w[0],
            });
        }
        for &v in loop_ {
            used[v] = true;
        }
    }
    let mut faces = Vec::new();
    for c in 0..n_cells {
        let slots = &cell_faces[cell_offsets[c]..cell_offsets[c + 1]];
        if slots.len() < 4 {
            return Err(MeshError::CellTooFewFaces {
                cell: c,
                count: slots.len(),
            });
        }
        if let Some(slot) = slots.iter().find(|s| s.face >= n_faces) {
            return Err(MeshError::CellFaceOutOfRange {
                cell: c,
                face: slot.face,
                face_count: n_faces,
            });
        }
        faces.clear();
        faces.extend(slots.iter().map(|s| s.face));
        faces.sort_unstable();
        if let Some(w) = faces.windows(2).find(|w| w[0] == w[1]) {
            return Err(MeshError::CellRepeatedFace {
                cell: c,
                face: w[0],
            });
        }
    }
    if let Some(vertex) = used.iter().position(|&u| !u) {
        return Err(MeshError::UnusedVertex { vertex });
    }
    Ok(())
}

fn check_offsets(what: &str, offsets: &[usize], len: usize) -> Result<(), MeshError> {
    let last = offsets[offsets.len() - 1];
    if offsets[0] != 0 || last != len {
        return Err(MeshError::BadStorage {
            reason: format!(
                "{what} offsets must start at 0 and end at the number of indices ({len}), found {} .. {last}",
                offsets[0]
            ),
        });
    }
    if let Some(k) = (0..offsets.len() - 1).find(|&k| offsets[k + 1] < offsets[k]) {
        return Err(MeshError::BadStorage {
            reason: format!("{what} offsets decrease at {what} {k}"),
        });
    }
    Ok(())
}

/// Step 2 (first half): the one or two cells of every face, outward for the owner. A boundary
/// face that its cell sees inward has the cell's flag flipped here and is listed in the second
/// vector (its loop must be reversed by the caller).
pub(crate) fn face_cells(
    face_offsets: &[usize],
    cell_offsets: &[usize],
    cell_faces: &mut [OrientedFace],
) -> Result<(Vec<FaceCells>, Vec<usize>), MeshError> {
    let n_faces = face_offsets.len() - 1;
    // Up to two users (cell, outward) per face; a third is an error.
    let mut users: Vec<[(usize, bool); 2]> = vec![[(usize::MAX, false); 2]; n_faces];
    let mut count = vec![0u8; n_faces];
    for c in 0..cell_offsets.len() - 1 {
        for slot in &cell_faces[cell_offsets[c]..cell_offsets[c + 1]] {
            let f = slot.face;
            if count[f] >= 2 {
                let mut cells: Vec<usize> = users[f].iter().map(|u| u.0).collect();
                cells.push(c);
                // Name every cell that uses the face.
                for c2 in c + 1..cell_offsets.len() - 1 {
                    if cell_faces[cell_offsets[c2]..cell_offsets[c2 + 1]]
                        .iter()
                        .any(|s| s.face == f)
                    {
                        cells.push(c2);
                    }
                }
                return Err(MeshError::OverusedFace { face: f, cells });
            }
            users[f][count[f] as usize] = (c, slot.outward);
            count[f] += 1;
        }
    }
    let mut result = Vec::with_capacity(n_faces);
    let mut reversed = Vec::new();
    for f in 0..n_faces {
        match count[f] {
            0 => return Err(MeshError::UnusedFace { face: f }),
            1 => {
                let (cell, outward) = users[f][0];
                if !outward {
                    reversed.push(f);
                }
                result.push(FaceCells {
                    owner: cell,
                    neighbour: None,
                });
            }
            _ => {
                let [(a, oa), (b, ob)] = users[f];
                if oa == ob {
                    return Err(MeshError::FaceSameOrientation {
                        face: f,
                        cells: [a, b],
                        outward: oa,
                    });
                }
                let (owner, neighbour) = if oa { (a, b) } else { (b, a) };
                result.push(FaceCells {
                    owner,
                    neighbour: Some(neighbour),
                });
            }
        }
    }
    if !reversed.is_empty() {
        let mut flip = vec![false; n_faces];
        for &f in &reversed {
            flip[f] = true;
        }
        for slot in cell_faces.iter_mut() {
            if flip[slot.face] {
                slot.outward = true;
            }
        }
    }
    Ok((result, reversed))
}

/// Steps 2 (duplicate faces) to 8 on a mesh whose storage and face sharing are consistent.
pub(crate) fn validate(mesh: &PolyhedralMesh) -> Result<(), MeshError> {
    check_duplicate_faces(mesh)?;
    check_cells_closed(mesh)?;
    let tolerance = coincidence_tolerance(mesh).min(f64::MAX);
    check_duplicate_vertices(mesh, tolerance)?;
    for f in 0..mesh.n_faces() {
        check_face(f, &mesh.face_points(f), tolerance)?;
    }
    for c in 0..mesh.n_cells() {
        check_volume(mesh, c)?;
    }
    check_conformity(mesh, tolerance)
}

/// The coincidence tolerance of `mesh`: [`COINCIDENCE_RATIO`] times the mean bounding-box
/// diagonal of its cells.
pub fn coincidence_tolerance(mesh: &PolyhedralMesh) -> f64 {
    let total: f64 = (0..mesh.n_cells())
        .map(|c| bounding_diagonal(mesh.cell_vertices(c).iter().map(|&v| mesh.vertex(v))))
        .sum();
    COINCIDENCE_RATIO * total / mesh.n_cells() as f64
}

fn bounding_diagonal(points: impl Iterator<Item = Point3>) -> f64 {
    let mut min = Vector3::repeat(f64::INFINITY);
    let mut max = Vector3::repeat(f64::NEG_INFINITY);
    for p in points {
        min = min.inf(&p.coords);
        max = max.sup(&p.coords);
    }
    (max - min).norm()
}

/// No two faces with the same vertex set.
fn check_duplicate_faces(mesh: &PolyhedralMesh) -> Result<(), MeshError> {
    let mut keys = mesh.face_vertex_indices().to_vec();
    let offsets = mesh.face_offsets();
    for f in 0..mesh.n_faces() {
        keys[offsets[f]..offsets[f + 1]].sort_unstable();
    }
    let key = |f: usize| &keys[offsets[f]..offsets[f + 1]];
    let mut order: Vec<usize> = (0..mesh.n_faces()).collect();
    order.sort_unstable_by(|&a, &b| key(a).cmp(key(b)).then(a.cmp(&b)));
    let mut found: Option<(usize, usize)> = None;
    for w in order.windows(2) {
        if key(w[0]) == key(w[1]) {
            let pair = (w[0].min(w[1]), w[0].max(w[1]));
            if found.is_none_or(|f| pair < f) {
                found = Some(pair);
            }
        }
    }
    match found {
        Some((a, b)) => Err(MeshError::DuplicateFace { a, b }),
        None => Ok(()),
    }
}

/// Step 3: each cell's oriented faces traverse every edge once in each direction and are
/// connected through their edges.
fn check_cells_closed(mesh: &PolyhedralMesh) -> Result<(), MeshError> {
    // (edge, forward?, slot) for every corner of every face of the cell.
    let mut corners: Vec<(usize, bool, usize)> = Vec::new();
    let mut parent: Vec<usize> = Vec::new();
    for c in 0..mesh.n_cells() {
        corners.clear();
        let slots = mesh.cell_faces(c);
        for (s, slot) in slots.iter().enumerate() {
            let loop_ = mesh.face(slot.face);
            let edges = mesh.face_edges(slot.face);
            let n = loop_.len();
            for k in 0..n {
                // The loop goes loop[k] -> loop[k + 1]; the cell sees the reverse when inward.
                let ascending = loop_[k] < loop_[(k + 1) % n];
                corners.push((edges[k], ascending == slot.outward, s));
            }
        }
        corners.sort_unstable();
        parent.clear();
        parent.extend(0..slots.len());
        let mut i = 0;
        while i < corners.len() {
            let e = corners[i].0;
            let mut j = i;
            while j < corners.len() && corners[j].0 == e {
                j += 1;
            }
            let forward = corners[i..j].iter().filter(|x| x.1).count();
            let backward = j - i - forward;
            if forward != 1 || backward != 1 {
                let [a, b] = mesh.edge(e);
                return Err(MeshError::CellNotClosed {
                    cell: c,
                    a,
                    b,
                    forward,
                    backward,
                });
            }
            union(&mut parent, corners[i].2, corners[i + 1].2);
            i = j;
        }
        let root = find(&mut parent, 0);
        if let Some(s) = (1..slots.len()).find(|&s| find(&mut parent, s) != root) {
            return Err(MeshError::DisconnectedCell {
                cell: c,
                face: slots[s].face,
            });
        }
    }
    Ok(())
}

fn find(parent: &mut [usize], mut v: usize) -> usize {
    while parent[v] != v {
        parent[v] = parent[parent[v]];
        v = parent[v];
    }
    v
}

fn union(parent: &mut [usize], a: usize, b: usize) {
    let (ra, rb) = (find(parent, a), find(parent, b));
    if ra != rb {
        parent[ra.max(rb)] = ra.min(rb);
    }
}

/// Step 5: no two distinct vertices closer than `tolerance` (the vertices sorted by the cell of
/// side 4 x tolerance that holds them; each looks for partners in the cells its tolerance ball
/// touches).
fn check_duplicate_vertices(mesh: &PolyhedralMesh, tolerance: f64) -> Result<(), MeshError> {
    let vertices = mesh.vertices();
    let cell = 4.0 * tolerance;
    let key = |p: Point3| -> (i64, i64, i64) {
        if cell > 0.0 {
            // `as` saturates: far-away points share border cells, which costs time, not truth.
            (
                (p.x / cell).floor() as i64,
                (p.y / cell).floor() as i64,
                (p.z / cell).floor() as i64,
            )
        } else {
            (
                p.x.to_bits() as i64,
                p.y.to_bits() as i64,
                p.z.to_bits() as i64,
            )
        }
    };
    let mut sorted: Vec<((i64, i64, i64), usize)> =
        (0..vertices.len()).map(|v| (key(vertices[v]), v)).collect();
    sorted.sort_unstable();
    let mut found: Option<(usize, usize, f64)> = None;
    let offset = Vector3::repeat(tolerance);
    for &(_, a) in &sorted {
        let pa = vertices[a];
        let (lo, hi) = (key(pa - offset), key(pa + offset));
        for cx in lo.0..=hi.0 {
            for cy in lo.1..=hi.1 {
                for cz in lo.2..=hi.2 {
                    let start = sorted.partition_point(|&(k, _)| k < (cx, cy, cz));
                    for &(k, b) in &sorted[start..] {
                        if k != (cx, cy, cz) {
                            break;
                        }
                        let distance = (vertices[b] - pa).norm();
                        if a < b
                            && distance <= tolerance
                            && found.is_none_or(|(fa, fb, _)| (a, b) < (fa, fb))
                        {
                            found = Some((a, b, distance));
                        }
                    }
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

/// The face loop `points` projected on its mean plane, in a right-handed frame whose third axis
/// is the face normal (so the projection of an outward loop runs counter-clockwise).
pub(crate) fn project_on_plane(points: &[Point3], normal: Vector3) -> Vec<Point> {
    let centre = geometry::vertex_mean(points);
    let helper = if normal.x.abs() <= normal.y.abs() && normal.x.abs() <= normal.z.abs() {
        Vector3::x()
    } else if normal.y.abs() <= normal.z.abs() {
        Vector3::y()
    } else {
        Vector3::z()
    };
    let u = normal.cross(&helper).normalize();
    let v = normal.cross(&u);
    points
        .iter()
        .map(|p| {
            let d = p - centre;
            Point::new(d.dot(&u), d.dot(&v))
        })
        .collect()
}

/// Step 6 for one face.
fn check_face(face: usize, points: &[Point3], tolerance: f64) -> Result<(), MeshError> {
    let diameter = geometry::diameter(points);
    let vector_area = geometry::face_vector_area(points);
    let area = vector_area.norm();
    if !area.is_finite() || area <= DEGENERATE_FACE_RATIO * diameter * diameter {
        return Err(MeshError::DegenerateFace { face, area });
    }
    let normal = vector_area / area;
    let warping = geometry::face_warping(points) / diameter;
    if warping <= PLANARITY_RATIO {
        let projected = project_on_plane(points, normal);
        if let Some((edge_a, edge_b)) = crate::validate::self_intersection(&projected, tolerance) {
            return Err(MeshError::SelfIntersectingFace {
                face,
                edge_a,
                edge_b,
            });
        }
        return Ok(());
    }
    let centre = geometry::vertex_mean(points);
    let n = points.len();
    for k in 0..n {
        let a = (points[k] - centre).cross(&(points[(k + 1) % n] - centre));
        if a.dot(&normal) <= DEGENERATE_FACE_RATIO * diameter * diameter {
            return Err(MeshError::FoldedFace {
                face,
                triangle: k,
                warping,
            });
        }
    }
    Ok(())
}

/// Step 7 for one cell.
fn check_volume(mesh: &PolyhedralMesh, cell: usize) -> Result<(), MeshError> {
    let volume = mesh.volume(cell);
    let diagonal = bounding_diagonal(mesh.cell_vertices(cell).iter().map(|&v| mesh.vertex(v)));
    let threshold = DEGENERATE_VOLUME_RATIO * diagonal * diagonal * diagonal;
    if !volume.is_finite() || volume.abs() <= threshold {
        return Err(MeshError::DegenerateCell { cell, volume });
    }
    if volume < 0.0 {
        return Err(MeshError::InvertedCell { cell, volume });
    }
    Ok(())
}

/// Step 9: parts name boundary faces that exist, under distinct names.
pub(crate) fn check_parts(
    mesh: &PolyhedralMesh,
    parts: Vec<FacePart>,
) -> Result<Vec<FacePart>, MeshError> {
    for (k, part) in parts.iter().enumerate() {
        if parts[..k].iter().any(|p| p.name == part.name) {
            return Err(MeshError::DuplicatePart {
                part: part.name.clone(),
            });
        }
        for &f in &part.faces {
            if f >= mesh.n_faces() {
                return Err(MeshError::PartFaceOutOfRange {
                    part: part.name.clone(),
                    face: f,
                    face_count: mesh.n_faces(),
                });
            }
            let cells = mesh.face_cells(f);
            if let Some(neighbour) = cells.neighbour {
                return Err(MeshError::InteriorFaceInPart {
                    part: part.name.clone(),
                    face: f,
                    cells: [cells.owner, neighbour],
                });
            }
        }
    }
    Ok(parts)
}

/// Step 8: no vertex on a face that does not list it. The vertices are bucketed in a uniform
/// grid of cells about the mean face size; each face looks at the vertices of the cells its
/// bounding box (grown by the tolerance) overlaps.
fn check_conformity(mesh: &PolyhedralMesh, tolerance: f64) -> Result<(), MeshError> {
    let vertices = mesh.vertices();
    let mut low = Vector3::repeat(f64::INFINITY);
    let mut high = Vector3::repeat(f64::NEG_INFINITY);
    for p in vertices {
        low = low.inf(&p.coords);
        high = high.sup(&p.coords);
    }
    let mean_face = (0..mesh.n_faces())
        .map(|f| bounding_diagonal(mesh.face(f).iter().map(|&v| vertices[v])))
        .sum::<f64>()
        / mesh.n_faces() as f64;
    let limit = 2 * (vertices.len() as f64).cbrt() as usize + 2;
    let extent = high - low;
    let mut cell = mean_face;
    if !(cell > 0.0 && cell.is_finite()) {
        cell = extent.max().max(f64::MIN_POSITIVE);
    }
    let dims: [usize; 3] =
        std::array::from_fn(|a| (((extent[a] / cell).floor() as usize) + 1).clamp(1, limit));
    let cell: Vector3 = Vector3::from_fn(|a, _| {
        (extent[a] / dims[a] as f64)
            .max(cell.min(f64::MAX))
            .max(f64::MIN_POSITIVE)
    });
    let index = |value: f64, a: usize| -> usize {
        let i = ((value - low[a]) / cell[a]).floor();
        if i <= 0.0 || i.is_nan() {
            0
        } else {
            (i as usize).min(dims[a] - 1)
        }
    };
    let slot = |i: [usize; 3]| i[0] + dims[0] * (i[1] + dims[1] * i[2]);
    let mut start = vec![0usize; dims[0] * dims[1] * dims[2] + 1];
    let keys: Vec<usize> = vertices
        .iter()
        .map(|p| slot([index(p.x, 0), index(p.y, 1), index(p.z, 2)]))
        .collect();
    for &k in &keys {
        start[k + 1] += 1;
    }
    for c in 0..start.len() - 1 {
        start[c + 1] += start[c];
    }
    let mut fill = start.clone();
    let mut items = vec![0usize; vertices.len()];
    for (v, &k) in keys.iter().enumerate() {
        items[fill[k]] = v;
        fill[k] += 1;
    }
    let mut found: Option<(usize, usize)> = None;
    for f in 0..mesh.n_faces() {
        let face = mesh.face(f);
        let points: Vec<Point3> = face.iter().map(|&v| vertices[v]).collect();
        let (mut lo, mut hi) = (
            Vector3::repeat(f64::INFINITY),
            Vector3::repeat(f64::NEG_INFINITY),
        );
        for p in &points {
            lo = lo.inf(&p.coords);
            hi = hi.sup(&p.coords);
        }
        lo -= Vector3::repeat(tolerance);
        hi += Vector3::repeat(tolerance);
        let planar = PlanarFace::new(&points);
        for k in index(lo.z, 2)..=index(hi.z, 2) {
            for j in index(lo.y, 1)..=index(hi.y, 1) {
                for i in index(lo.x, 0)..=index(hi.x, 0) {
                    let c = slot([i, j, k]);
                    for &v in &items[start[c]..start[c + 1]] {
                        let p = vertices[v];
                        let inside_box = (0..3).all(|a| p[a] >= lo[a] && p[a] <= hi[a]);
                        if !inside_box
                            || face.contains(&v)
                            || found.is_some_and(|best| (v, f) >= best)
                        {
                            continue;
                        }
                        if on_face(&points, planar.as_ref(), p, tolerance) {
                            found = Some((v, f));
                        }
                    }
                }
            }
        }
    }
    match found {
        Some((vertex, face)) => Err(MeshError::HangingVertex { vertex, face }),
        None => Ok(()),
    }
}

/// A planar face's frame: its projection and the distance of its plane from its vertices.
struct PlanarFace {
    centre: Point3,
    normal: Vector3,
    projected: Vec<Point>,
    u: Vector3,
    v: Vector3,
    slack: f64,
}

impl PlanarFace {
    /// The frame of a planar face (`None` for a warped or degenerate one).
    fn new(points: &[Point3]) -> Option<Self> {
        let normal = geometry::face_normal(points);
        let diameter = geometry::diameter(points);
        let warping = geometry::face_warping(points);
        if normal == Vector3::zeros() || warping > PLANARITY_RATIO * diameter {
            return None;
        }
        let projected = project_on_plane(points, normal);
        let centre = geometry::vertex_mean(points);
        // The frame of `project_on_plane`, recomputed for single points.
        let helper = if normal.x.abs() <= normal.y.abs() && normal.x.abs() <= normal.z.abs() {
            Vector3::x()
        } else if normal.y.abs() <= normal.z.abs() {
            Vector3::y()
        } else {
            Vector3::z()
        };
        let u = normal.cross(&helper).normalize();
        let v = normal.cross(&u);
        Some(Self {
            centre,
            normal,
            projected,
            u,
            v,
            slack: warping,
        })
    }
}

/// True when `p` lies on the face `points`: on one of its edges away from the end points (all
/// faces), or inside it (planar faces), to `tolerance`.
fn on_face(points: &[Point3], planar: Option<&PlanarFace>, p: Point3, tolerance: f64) -> bool {
    let n = points.len();
    for k in 0..n {
        let (a, b) = (points[k], points[(k + 1) % n]);
        let along = b - a;
        let length = along.norm();
        if length <= 2.0 * tolerance {
            continue;
        }
        let t = (p - a).dot(&along) / length;
        if t > tolerance && t < length - tolerance {
            let off = (p - a) - along * (t / length);
            if off.norm() <= tolerance {
                return true;
            }
        }
    }
    let Some(face) = planar else {
        return false;
    };
    let d = p - face.centre;
    if d.dot(&face.normal).abs() > tolerance + face.slack {
        return false;
    }
    let q = Point::new(d.dot(&face.u), d.dot(&face.v));
    // Strictly inside (the boundary was handled above): crossing number, and away from the
    // vertices.
    if face
        .projected
        .iter()
        .any(|&corner| (corner - q).norm() <= tolerance)
    {
        return false;
    }
    let mut inside = false;
    let m = face.projected.len();
    for k in 0..m {
        let (a, b) = (face.projected[k], face.projected[(k + 1) % m]);
        if (a.y > q.y) != (b.y > q.y) {
            let x = a.x + (q.y - a.y) / (b.y - a.y) * (b.x - a.x);
            if x > q.x {
                inside = !inside;
            }
        }
    }
    inside
}
