//! Mesh validation: one hand-made mesh per error kind gives that error; valid meshes with
//! hanging nodes and non-convex cells pass; random loops and polygon soups never panic, and
//! whatever is accepted is a true partition (no probe point lies inside two polygons).

use proptest::prelude::*;
use vem_mesh::generators::{structured_quads, Rectangle};
use vem_mesh::{Mesh, MeshError, PartSpec, Point};

fn points(coordinates: &[(f64, f64)]) -> Vec<Point> {
    coordinates.iter().map(|&(x, y)| Point::new(x, y)).collect()
}

fn build(coordinates: &[(f64, f64)], polygons: &[Vec<usize>]) -> Result<Mesh, MeshError> {
    Mesh::from_polygons(points(coordinates), polygons, vec![])
}

/// Two unit squares side by side: vertices 0..6, bottom row then top row.
const TWO_SQUARES: [(f64, f64); 6] = [
    (0.0, 0.0),
    (1.0, 0.0),
    (2.0, 0.0),
    (0.0, 1.0),
    (1.0, 1.0),
    (2.0, 1.0),
];

#[test]
fn valid_two_squares_pass() {
    let mesh = build(&TWO_SQUARES, &[vec![0, 1, 4, 3], vec![1, 2, 5, 4]]).unwrap();
    assert_eq!(mesh.n_edges(), 7);
}

#[test]
fn empty_mesh() {
    let err = build(&[], &[]).unwrap_err();
    assert_eq!(
        err,
        MeshError::Empty {
            vertices: 0,
            polygons: 0
        }
    );
}

#[test]
fn non_finite_vertex() {
    let mut coordinates = TWO_SQUARES.to_vec();
    coordinates[4].1 = f64::NAN;
    let err = build(&coordinates, &[vec![0, 1, 4, 3]]).unwrap_err();
    assert!(
        matches!(err, MeshError::NonFiniteVertex { vertex: 4, .. }),
        "{err}"
    );
}

#[test]
fn bad_storage() {
    let err = Mesh::from_compact(
        points(&TWO_SQUARES),
        vec![0, 4, 3],
        vec![0, 1, 4, 3],
        vec![],
    )
    .unwrap_err();
    assert!(matches!(err, MeshError::BadStorage { .. }), "{err}");
    let err =
        Mesh::from_compact(points(&TWO_SQUARES), vec![0, 3], vec![0, 1, 4, 3], vec![]).unwrap_err();
    assert!(matches!(err, MeshError::BadStorage { .. }), "{err}");
}

#[test]
fn too_few_vertices() {
    let err = build(&TWO_SQUARES, &[vec![0, 1, 4, 3], vec![1, 2]]).unwrap_err();
    assert_eq!(
        err,
        MeshError::TooFewVertices {
            polygon: 1,
            count: 2
        }
    );
}

#[test]
fn vertex_out_of_range() {
    let err = build(&TWO_SQUARES, &[vec![0, 1, 9, 3]]).unwrap_err();
    assert_eq!(
        err,
        MeshError::VertexOutOfRange {
            polygon: 0,
            vertex: 9,
            vertex_count: 6
        }
    );
}

#[test]
fn repeated_vertex() {
    let err = build(&TWO_SQUARES, &[vec![0, 1, 4, 1, 3]]).unwrap_err();
    assert_eq!(
        err,
        MeshError::RepeatedVertex {
            polygon: 0,
            vertex: 1
        }
    );
}

#[test]
fn clockwise_polygon() {
    let err = build(&TWO_SQUARES, &[vec![0, 3, 4, 1]]).unwrap_err();
    assert!(
        matches!(err, MeshError::Clockwise { polygon: 0, signed_area } if signed_area == -1.0),
        "{err}"
    );
}

#[test]
fn degenerate_polygon() {
    // Three collinear vertices: a triangle of zero area.
    let err = build(&[(0.0, 0.0), (1.0, 0.0), (3.0, 0.0)], &[vec![0, 1, 2]]).unwrap_err();
    assert!(
        matches!(
            err,
            MeshError::DegenerateArea { polygon: 0, .. } | MeshError::SelfIntersecting { .. }
        ),
        "{err}"
    );
    // A sliver far below the relative threshold.
    let err = build(&[(0.0, 0.0), (1.0, 0.0), (0.5, 1e-13)], &[vec![0, 1, 2]]).unwrap_err();
    assert!(
        matches!(err, MeshError::DegenerateArea { polygon: 0, .. }),
        "{err}"
    );
}

#[test]
fn self_intersecting_bowtie() {
    // 0 -> 1 -> 4 -> 3 with 1 and 4 swapped in space: edges 0 (0-1) and 2 (4-3) cross.
    let coordinates = [(0.0, 0.0), (1.0, 1.0), (1.0, 0.0), (0.0, 1.0)];
    let err = build(&coordinates, &[vec![0, 1, 2, 3]]).unwrap_err();
    assert_eq!(
        err,
        MeshError::SelfIntersecting {
            polygon: 0,
            edge_a: 0,
            edge_b: 2
        }
    );
}

#[test]
fn self_touching_polygon() {
    // An arrow whose tip (vertex 4) touches the opposite edge 0 -> 1 (edge 0) at (1, 0).
    let coordinates = [
        (0.0, 0.0),
        (2.0, 0.0),
        (2.0, 2.0),
        (1.5, 2.0),
        (1.0, 0.0),
        (0.5, 2.0),
        (0.0, 2.0),
    ];
    let err = build(&coordinates, &[vec![0, 1, 2, 3, 4, 5, 6]]).unwrap_err();
    assert!(
        matches!(
            err,
            MeshError::SelfIntersecting {
                polygon: 0,
                edge_a: 0,
                ..
            }
        ),
        "{err}"
    );
}

#[test]
fn polygon_folding_back_on_itself() {
    // A spike: 2 -> 3 goes out and 3 -> 4 comes back along the same line.
    let coordinates = [
        (0.0, 0.0),
        (1.0, 0.0),
        (1.0, 1.0),
        (1.0, 2.0),
        (1.0, 1.5),
        (0.0, 1.0),
    ];
    let err = build(&coordinates, &[vec![0, 1, 2, 3, 4, 5]]).unwrap_err();
    assert!(
        matches!(err, MeshError::SelfIntersecting { polygon: 0, .. }),
        "{err}"
    );
}

#[test]
fn duplicate_vertices() {
    // The right square uses its own copies (6, 7) of the shared vertices 1 and 4.
    let mut coordinates = TWO_SQUARES.to_vec();
    coordinates.push((1.0, 0.0));
    coordinates.push((1.0, 1.0 + 1e-12));
    let err = build(&coordinates, &[vec![0, 1, 4, 3], vec![6, 2, 5, 7]]).unwrap_err();
    match err {
        MeshError::DuplicateVertices {
            a,
            b,
            distance,
            tolerance,
        } => {
            assert_eq!((a, b), (1, 6));
            assert_eq!(distance, 0.0);
            // 1e-10 times the mean bounding-box diagonal sqrt 2.
            assert!((tolerance / (1e-10 * 2f64.sqrt()) - 1.0).abs() < 1e-9);
        }
        other => panic!("{other}"),
    }
}

#[test]
fn vertices_above_the_tolerance_are_distinct() {
    // Two triangles whose apexes are 1e-6 apart: a valid (if poor) mesh.
    let coordinates = [
        (0.0, 0.0),
        (1.0, 0.0),
        (0.5, 1.0),
        (0.5 + 1e-6, 1.0),
        (1.5, 1.0),
    ];
    let mesh = build(&coordinates, &[vec![0, 1, 2], vec![1, 4, 3]]).unwrap();
    assert_eq!(mesh.n_polygons(), 2);
}

/// A unit square (left) beside two half squares (right): vertices 0..8, vertex 7 = (1, 0.5)
/// is the middle of the shared side.
const HANGING: [(f64, f64); 8] = [
    (0.0, 0.0),
    (1.0, 0.0),
    (2.0, 0.0),
    (0.0, 1.0),
    (1.0, 1.0),
    (2.0, 1.0),
    (2.0, 0.5),
    (1.0, 0.5),
];

#[test]
fn listed_hanging_node_is_conforming() {
    let polygons = [vec![0, 1, 7, 4, 3], vec![1, 2, 6, 7], vec![7, 6, 5, 4]];
    let mesh = build(&HANGING, &polygons).unwrap();
    assert_eq!(mesh.polygon(0).len(), 5);
    assert_eq!(
        mesh.n_vertices() as i64 - mesh.n_edges() as i64 + mesh.n_polygons() as i64,
        1
    );
}

#[test]
fn unlisted_hanging_node_is_non_conforming() {
    let polygons = [vec![0, 1, 4, 3], vec![1, 2, 6, 7], vec![7, 6, 5, 4]];
    let err = build(&HANGING, &polygons).unwrap_err();
    match err {
        MeshError::NonConforming {
            polygon_a,
            a0,
            a1,
            polygon_b,
            ..
        } => {
            // The square's side 1 -> 4 holds vertex 7, which it does not list.
            assert_eq!((polygon_a, a0, a1), (0, 1, 4));
            assert!(polygon_b == 1 || polygon_b == 2);
        }
        other => panic!("{other}"),
    }
}

#[test]
fn overlapping_collinear_edges_are_non_conforming() {
    // The right square is shifted up by half: its left side (1, .5)-(1, 1.5) overlaps the left
    // square's right side (1, 0)-(1, 1), and no vertex is shared.
    let coordinates = [
        (0.0, 0.0),
        (1.0, 0.0),
        (1.0, 1.0),
        (0.0, 1.0),
        (1.0, 0.5),
        (2.0, 0.5),
        (2.0, 1.5),
        (1.0, 1.5),
    ];
    let err = build(&coordinates, &[vec![0, 1, 2, 3], vec![4, 5, 6, 7]]).unwrap_err();
    assert!(matches!(err, MeshError::NonConforming { .. }), "{err}");
}

#[test]
fn crossing_polygons_overlap() {
    let coordinates = [
        (0.0, 0.0),
        (1.0, 0.0),
        (1.0, 1.0),
        (0.0, 1.0),
        (0.5, 0.3),
        (1.5, 0.3),
        (1.5, 1.3),
        (0.5, 1.3),
    ];
    let err = build(&coordinates, &[vec![0, 1, 2, 3], vec![4, 5, 6, 7]]).unwrap_err();
    assert_eq!(err, MeshError::Overlapping { a: 0, b: 1 });
}

#[test]
fn nested_polygon_overlaps() {
    let coordinates = [
        (0.0, 0.0),
        (3.0, 0.0),
        (3.0, 3.0),
        (0.0, 3.0),
        (1.0, 1.0),
        (2.0, 1.0),
        (2.0, 2.0),
        (1.0, 2.0),
    ];
    let err = build(&coordinates, &[vec![0, 1, 2, 3], vec![4, 5, 6, 7]]).unwrap_err();
    assert_eq!(err, MeshError::Overlapping { a: 0, b: 1 });
    // Side by side (disjoint) components are fine.
    let apart = [
        (0.0, 0.0),
        (1.0, 0.0),
        (1.0, 1.0),
        (0.0, 1.0),
        (2.0, 0.0),
        (3.0, 0.0),
        (3.0, 1.0),
        (2.0, 1.0),
    ];
    assert!(build(&apart, &[vec![0, 1, 2, 3], vec![4, 5, 6, 7]]).is_ok());
}

#[test]
fn corners_overlapping_at_a_shared_vertex() {
    // A small triangle inside a large one, touching it only at the shared vertex 0.
    let coordinates = [(0.0, 0.0), (2.0, 0.0), (0.0, 2.0), (0.5, 0.2), (0.2, 0.5)];
    let err = build(&coordinates, &[vec![0, 1, 2], vec![0, 3, 4]]).unwrap_err();
    assert_eq!(err, MeshError::Overlapping { a: 0, b: 1 });
    // The same triangle outside the large one shares the vertex legitimately.
    let outside = [
        (0.0, 0.0),
        (2.0, 0.0),
        (0.0, 2.0),
        (-0.5, -0.2),
        (-0.2, -0.5),
    ];
    assert!(build(&outside, &[vec![0, 1, 2], vec![0, 3, 4]]).is_ok());
}

#[test]
fn edge_shared_by_three_polygons() {
    let coordinates = [(0.0, 0.0), (1.0, 0.0), (0.5, 1.0), (0.5, -1.0), (0.5, 2.0)];
    let err = build(&coordinates, &[vec![0, 1, 2], vec![1, 0, 3], vec![0, 1, 4]]).unwrap_err();
    assert!(
        matches!(err, MeshError::OverusedEdge { a: 0, b: 1, .. }),
        "{err}"
    );
}

#[test]
fn part_errors() {
    let polygons = [vec![0, 1, 4, 3], vec![1, 2, 5, 4]];
    let with = |parts: Vec<PartSpec>| Mesh::from_polygons(points(&TWO_SQUARES), &polygons, parts);
    let err = with(vec![PartSpec::new("mid", vec![[1, 4]])]).unwrap_err();
    assert!(matches!(err, MeshError::InteriorEdgeInPart { .. }), "{err}");
    let err = with(vec![PartSpec::new("diag", vec![[0, 4]])]).unwrap_err();
    assert!(
        matches!(err, MeshError::UnknownEdge { a: 0, b: 4, .. }),
        "{err}"
    );
    let err = with(vec![
        PartSpec::new("bottom", vec![[0, 1]]),
        PartSpec::new("bottom", vec![[1, 2]]),
    ])
    .unwrap_err();
    assert!(matches!(err, MeshError::DuplicatePart { .. }), "{err}");
}

#[test]
fn non_convex_star_shaped_cells_pass() {
    // Two chevrons stacked: the shared polyline bends up at x = 1/2.
    let coordinates = [
        (0.0, 0.0),
        (1.0, 0.0),
        (1.0, 1.0),
        (0.5, 1.25),
        (0.0, 1.0),
        (1.0, 2.0),
        (0.0, 2.0),
    ];
    let mesh = build(&coordinates, &[vec![0, 1, 2, 3, 4], vec![4, 3, 2, 5, 6]]).unwrap();
    let area: f64 = (0..2).map(|p| mesh.area(p)).sum();
    assert!((area - 2.0).abs() < 1e-15);
}

#[test]
fn huge_and_tiny_coordinates_do_not_panic() {
    for scale in [1e-300, 1e-150, 1e150, 1e300, f64::MAX / 2.0] {
        let coordinates: Vec<(f64, f64)> = TWO_SQUARES
            .iter()
            .map(|&(x, y)| (scale * x, scale * y))
            .collect();
        let result = build(&coordinates, &[vec![0, 1, 4, 3], vec![1, 2, 5, 4]]);
        match result {
            // Representable areas: a valid mesh.
            Ok(mesh) => assert!(mesh.area(0).is_finite() && mesh.area(0) > 0.0),
            // Areas that underflow or overflow: a degenerate polygon, not a panic.
            Err(err) => {
                assert!(!(scale * scale).is_normal(), "scale {scale:e}: {err}");
                assert!(matches!(err, MeshError::DegenerateArea { .. }), "{err}");
            }
        }
    }
}

// ---------------------------------------------------------------- property tests

/// Probe points on a fine lattice: in a valid mesh none lies strictly inside two polygons.
fn covered_twice(mesh: &Mesh) -> Option<(usize, usize)> {
    let (mut lo, mut hi) = (mesh.vertex(0), mesh.vertex(0));
    for p in mesh.vertices() {
        lo = Point::new(lo.x.min(p.x), lo.y.min(p.y));
        hi = Point::new(hi.x.max(p.x), hi.y.max(p.y));
    }
    let steps = 37;
    for i in 0..=steps {
        for j in 0..=steps {
            // Irrational-ish offsets keep probes off the lattice lines of the inputs.
            let probe = Point::new(
                lo.x + (hi.x - lo.x) * (i as f64 + 0.3179) / (steps as f64 + 1.0),
                lo.y + (hi.y - lo.y) * (j as f64 + 0.2713) / (steps as f64 + 1.0),
            );
            let inside: Vec<usize> = (0..mesh.n_polygons())
                .filter(|&p| crossing_inside(probe, &mesh.polygon_points(p)))
                .collect();
            if inside.len() > 1 {
                return Some((inside[0], inside[1]));
            }
        }
    }
    None
}

fn crossing_inside(point: Point, polygon: &[Point]) -> bool {
    let m = polygon.len();
    let mut inside = false;
    for k in 0..m {
        let (a, b) = (polygon[k], polygon[(k + 1) % m]);
        if (a.y > point.y) != (b.y > point.y) {
            let x = a.x + (point.y - a.y) / (b.y - a.y) * (b.x - a.x);
            if x > point.x {
                inside = !inside;
            }
        }
    }
    inside
}

/// Coordinates on a coarse lattice (many coincidences and collinear triples) or anywhere.
fn coordinate() -> impl Strategy<Value = f64> {
    prop_oneof![(0i32..5).prop_map(|k| k as f64 * 0.5), -1.0f64..3.0]
}

fn point() -> impl Strategy<Value = (f64, f64)> {
    (coordinate(), coordinate())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    /// Any single loop of points: an error or a simple counter-clockwise polygon.
    #[test]
    fn random_loops_never_panic(coordinates in prop::collection::vec(point(), 1..12)) {
        let n = coordinates.len();
        let result = build(&coordinates, &[(0..n).collect()]);
        if let Ok(mesh) = result {
            prop_assert!(mesh.area(0) > 0.0);
            // Independent simplicity check: no two non-adjacent edges properly cross.
            let pts = mesh.polygon_points(0);
            let cross = |o: Point, a: Point, b: Point| (a - o).perp(&(b - o));
            for k in 0..n {
                for l in k + 2..n {
                    if k == 0 && l == n - 1 {
                        continue;
                    }
                    let (a0, a1, b0, b1) = (pts[k], pts[(k + 1) % n], pts[l], pts[(l + 1) % n]);
                    let straddles = |p: f64, q: f64| (p > 0.0 && q < 0.0) || (p < 0.0 && q > 0.0);
                    prop_assert!(
                        !(straddles(cross(a0, a1, b0), cross(a0, a1, b1))
                            && straddles(cross(b0, b1, a0), cross(b0, b1, a1))),
                        "edges {k} and {l} cross"
                    );
                }
            }
        }
    }

    /// Star polygons around the origin (angles increasing by less than pi, radii positive)
    /// are always valid.
    #[test]
    fn star_polygons_are_accepted(
        jitter in prop::collection::vec((0.0f64..0.9, 0.2f64..1.0), 4..20)
    ) {
        let m = jitter.len();
        let coordinates: Vec<(f64, f64)> = jitter
            .iter()
            .enumerate()
            .map(|(k, &(da, r))| {
                let angle = std::f64::consts::TAU * (k as f64 + da) / m as f64;
                (r * angle.cos(), r * angle.sin())
            })
            .collect();
        let mesh = build(&coordinates, &[(0..m).collect()]);
        prop_assert!(mesh.is_ok(), "{:?}", mesh);
    }

    /// Random polygon soups: an error or a true partition.
    #[test]
    fn random_polygon_soups_never_panic(
        coordinates in prop::collection::vec(point(), 1..14),
        polygons in prop::collection::vec(prop::collection::vec(0usize..15, 0..7), 0..5),
    ) {
        if let Ok(mesh) = build(&coordinates, &polygons) {
            prop_assert!((0..mesh.n_polygons()).all(|p| mesh.area(p) > 0.0));
            prop_assert_eq!(covered_twice(&mesh), None);
        }
    }

    /// A structured mesh with a few vertices moved anywhere: folded or overlapping cells are
    /// rejected, whatever is accepted still covers every point at most once.
    #[test]
    fn moved_vertices_are_caught(
        moves in prop::collection::vec((0usize..16, -0.5f64..3.5, -0.5f64..3.5), 1..4)
    ) {
        let rect = Rectangle::new(Point::new(0.0, 0.0), Point::new(3.0, 3.0));
        let mesh = structured_quads(&rect, 3, 3).unwrap();
        let mut vertices = mesh.vertices().to_vec();
        for (vertex, x, y) in moves {
            vertices[vertex] = Point::new(x, y);
        }
        let moved = Mesh::from_compact(
            vertices,
            mesh.polygon_offsets().to_vec(),
            mesh.polygon_vertex_indices().to_vec(),
            vec![],
        );
        if let Ok(moved) = moved {
            prop_assert_eq!(covered_twice(&moved), None);
        }
    }
}
