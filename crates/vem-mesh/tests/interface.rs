//! Interface node insertion (spec section 2, "Non-matching interfaces"), checked against
//! hand-counted positions, exact gaps and analytic distances on a circular indenter.

use std::collections::HashMap;

use approx::assert_relative_eq;
use vem_mesh::generators::{structured_quads, structured_triangles, Rectangle};
use vem_mesh::interface::{boundary_chain, insert_interface_nodes, Interface, InterfaceOptions};
use vem_mesh::{Mesh, MeshError, Point, Vector};

fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Rectangle {
    Rectangle::new(Point::new(x0, y0), Point::new(x1, y1))
}

/// Body 1 of the spec: (0,1)x(0,1), contact part "bottom".
fn body_1(n: usize) -> Mesh {
    structured_quads(&rect(0.0, 0.0, 1.0, 1.0), n, 2).unwrap()
}

/// Body 2 of the spec: (0,1)x(-1,0), contact part "top", triangles.
fn body_2(n: usize) -> Mesh {
    structured_triangles(&rect(0.0, -1.0, 1.0, 0.0), n, 2).unwrap()
}

fn pair_up(a: &Mesh, part_a: &str, b: &Mesh, part_b: &str) -> Interface {
    insert_interface_nodes(a, part_a, b, part_b, &InterfaceOptions::default()).unwrap()
}

fn gcd(a: usize, b: usize) -> usize {
    if b == 0 {
        a
    } else {
        gcd(b, a % b)
    }
}

fn total_area(mesh: &Mesh) -> f64 {
    (0..mesh.n_polygons()).map(|p| mesh.area(p)).sum()
}

fn total_tributary(interface: &Interface) -> f64 {
    interface.pairs.iter().map(|p| p.tributary_length).sum()
}

/// Every vertex of `part` appears exactly once among `nodes` (and nothing else does).
fn assert_each_node_once(mesh: &Mesh, part: &str, nodes: impl Iterator<Item = usize>) {
    let mut count: HashMap<usize, usize> = HashMap::new();
    for v in nodes {
        *count.entry(v).or_default() += 1;
    }
    let chain = boundary_chain(mesh, part).unwrap();
    assert_eq!(
        count.len(),
        chain.len(),
        "paired nodes vs chain of '{part}'"
    );
    for node in chain {
        assert_eq!(count.get(&node.vertex), Some(&1), "vertex {}", node.vertex);
    }
}

/// Shortest edge of all polygons.
fn shortest_edge(mesh: &Mesh) -> f64 {
    mesh.edges()
        .iter()
        .map(|e| (mesh.vertex(e.vertices[1]) - mesh.vertex(e.vertices[0])).norm())
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn boundary_chain_runs_counter_clockwise_with_trapezoidal_lengths() {
    let mesh = structured_quads(&rect(0.0, 0.0, 2.0, 1.0), 4, 2).unwrap();
    let left = boundary_chain(&mesh, "left").unwrap();
    // Counter-clockwise: the left side runs downwards, its normal is -x.
    let ys: Vec<f64> = left.iter().map(|n| n.point.y).collect();
    assert_eq!(ys, vec![1.0, 0.5, 0.0]);
    assert!(left.iter().all(|n| n.normal.x == -1.0 && n.normal.y == 0.0));
    let lengths: Vec<f64> = left.iter().map(|n| n.tributary_length).collect();
    assert_eq!(lengths, vec![0.25, 0.5, 0.25]);
    let bottom = boundary_chain(&mesh, "bottom").unwrap();
    let total: f64 = bottom.iter().map(|n| n.tributary_length).sum();
    assert_relative_eq!(total, 2.0, max_relative = 1e-15);
    assert_eq!(bottom.first().unwrap().point.x, 0.0);
}

#[test]
fn matching_meshes_pair_node_to_node_without_insertion() {
    for n in [1, 4, 7] {
        let (a, b) = (body_1(n), body_2(n));
        let interface = pair_up(&a, "bottom", &b, "top");
        assert_eq!((interface.inserted_a, interface.inserted_b), (0, 0));
        assert_eq!(interface.mesh_a, a);
        assert_eq!(interface.mesh_b, b);
        assert_eq!(interface.pairs.len(), n + 1);
        let h = 1.0 / n as f64;
        for (i, pair) in interface.pairs.iter().enumerate() {
            // Structured numbering: bottom vertex i of body 1, top vertex i of body 2.
            assert_eq!(pair.node_a, i);
            assert_eq!(pair.node_b, 2 * (n + 1) + i);
            assert_eq!(pair.point_a, pair.point_b);
            assert_eq!(pair.initial_gap, 0.0);
            assert_eq!((pair.normal.x, pair.normal.y), (0.0, -1.0));
            let expected = if i == 0 || i == n { 0.5 * h } else { h };
            assert_relative_eq!(pair.tributary_length, expected, max_relative = 1e-14);
        }
        assert_relative_eq!(total_tributary(&interface), 1.0, max_relative = 1e-14);
    }
}

#[test]
fn one_to_three_ratio_inserts_two_nodes_per_coarse_edge() {
    for n in [1, 2, 5] {
        for coarse_on_a in [true, false] {
            let (n_a, n_b) = if coarse_on_a { (n, 3 * n) } else { (3 * n, n) };
            let (a, b) = (body_1(n_a), body_2(n_b));
            let interface = pair_up(&a, "bottom", &b, "top");
            let (gain_a, gain_b) = if coarse_on_a { (2 * n, 0) } else { (0, 2 * n) };
            assert_eq!(
                (interface.inserted_a, interface.inserted_b),
                (gain_a, gain_b)
            );
            assert_eq!(interface.pairs.len(), 3 * n + 1);
            let (new_a, new_b) = (&interface.mesh_a, &interface.mesh_b);
            assert_eq!(new_a.n_vertices(), a.n_vertices() + gain_a);
            assert_eq!(new_b.n_vertices(), b.n_vertices() + gain_b);
            assert_eq!(new_a.n_polygons(), a.n_polygons());
            assert_each_node_once(new_a, "bottom", interface.pairs.iter().map(|p| p.node_a));
            assert_each_node_once(new_b, "top", interface.pairs.iter().map(|p| p.node_b));
            for (mesh, old) in [(new_a, &a), (new_b, &b)] {
                // Rebuilding validates again; areas do not change.
                let rebuilt = Mesh::from_compact(
                    mesh.vertices().to_vec(),
                    mesh.polygon_offsets().to_vec(),
                    mesh.polygon_vertex_indices().to_vec(),
                    mesh.part_specs(),
                )
                .unwrap();
                assert_eq!(&rebuilt, mesh);
                assert_relative_eq!(total_area(mesh), total_area(old), max_relative = 1e-14);
                assert_relative_eq!(total_area(mesh), 1.0, max_relative = 1e-14);
            }
            assert_relative_eq!(total_tributary(&interface), 1.0, max_relative = 1e-14);
            for (k, pair) in interface.pairs.iter().enumerate() {
                assert_relative_eq!(pair.point_a.x, k as f64 / (3 * n) as f64, epsilon = 1e-15);
                assert!(pair.initial_gap.abs() <= 1e-15);
                assert!((pair.point_a - pair.point_b).norm() <= 1e-15);
            }
        }
    }
}

#[test]
fn non_nested_ratios_pair_every_distinct_position() {
    // 4 vs 7 cells: positions i/4 and j/7 share only 0 and 1: 5 + 8 - 2 = 11 pairs.
    let interface = pair_up(&body_1(4), "bottom", &body_2(7), "top");
    assert_eq!(interface.pairs.len(), 11);
    assert_eq!((interface.inserted_a, interface.inserted_b), (6, 3));
    let mut expected: Vec<f64> = (0..=4)
        .map(|i| i as f64 / 4.0)
        .chain((1..7).map(|j| j as f64 / 7.0))
        .collect();
    expected.sort_by(f64::total_cmp);
    for (pair, x) in interface.pairs.iter().zip(&expected) {
        assert_relative_eq!(pair.point_a.x, *x, epsilon = 1e-15);
        assert_relative_eq!(pair.point_b.x, *x, epsilon = 1e-15);
        assert!(pair.initial_gap.abs() <= 1e-15);
    }
    // Every pair of sizes: |{i/n_a} u {j/n_b}| = n_a + n_b + 1 - gcd(n_a, n_b).
    for n_a in 1..=9 {
        for n_b in 1..=9 {
            let interface = pair_up(&body_1(n_a), "bottom", &body_2(n_b), "top");
            let expected = n_a + n_b + 1 - gcd(n_a, n_b);
            assert_eq!(interface.pairs.len(), expected, "{n_a} vs {n_b}");
            assert_eq!(interface.inserted_a, expected - (n_a + 1));
            assert_eq!(interface.inserted_b, expected - (n_b + 1));
            assert_relative_eq!(total_tributary(&interface), 1.0, max_relative = 1e-14);
            assert_each_node_once(
                &interface.mesh_a,
                "bottom",
                interface.pairs.iter().map(|p| p.node_a),
            );
            assert_each_node_once(
                &interface.mesh_b,
                "top",
                interface.pairs.iter().map(|p| p.node_b),
            );
        }
    }
}

/// `mesh` with vertex `v` moved by `shift`, parts kept.
fn moved(mesh: &Mesh, v: usize, shift: [f64; 2]) -> Mesh {
    let mut vertices = mesh.vertices().to_vec();
    vertices[v].x += shift[0];
    vertices[v].y += shift[1];
    Mesh::from_compact(
        vertices,
        mesh.polygon_offsets().to_vec(),
        mesh.polygon_vertex_indices().to_vec(),
        mesh.part_specs(),
    )
    .unwrap()
}

#[test]
fn nearly_coincident_nodes_snap_instead_of_leaving_slivers() {
    let a = body_1(4);
    // Top vertex at x = 1/2 of body 2 (2 rows of triangles, rows of 5 vertices).
    let middle = 2 * 5 + 2;
    assert_eq!(body_2(4).vertex(middle), Point::new(0.5, 0.0));
    for shift in [1e-9, -1e-9, 1e-4] {
        let b = moved(&body_2(4), middle, [shift, 0.0]);
        let interface = pair_up(&a, "bottom", &b, "top");
        assert_eq!(
            (interface.inserted_a, interface.inserted_b),
            (0, 0),
            "{shift}"
        );
        assert_eq!(interface.pairs.len(), 5);
        let pair = interface.pairs[2];
        assert_eq!((pair.node_a, pair.node_b), (2, middle));
        // The straight side b's node slid back onto a's node: no misfit, no sliver.
        assert_eq!(pair.point_b, pair.point_a);
        assert_eq!(interface.mesh_b.vertex(middle), Point::new(0.5, 0.0));
        assert!(shortest_edge(&interface.mesh_a) >= 0.25 - 1e-12);
        assert!(shortest_edge(&interface.mesh_b) >= 0.25 - 1e-12);
        // Without the alignment both nodes stay: the misfit is the offset.
        let kept = InterfaceOptions::builder()
            .align_snapped_nodes(false)
            .build()
            .unwrap();
        let interface = insert_interface_nodes(&a, "bottom", &b, "top", &kept).unwrap();
        let pair = interface.pairs[2];
        assert_relative_eq!(pair.point_b.x - pair.point_a.x, shift, max_relative = 1e-6);
        assert!(shortest_edge(&interface.mesh_b) >= 0.25 - 2e-4);
    }
    // Without the sliver guard, a 1e-4 offset (4e-4 of the edge) is inserted on both sides.
    let b = moved(&body_2(4), middle, [1e-4, 0.0]);
    let exact = InterfaceOptions::builder()
        .min_edge_fraction(0.0)
        .build()
        .unwrap();
    let interface = insert_interface_nodes(&a, "bottom", &b, "top", &exact).unwrap();
    assert_eq!((interface.inserted_a, interface.inserted_b), (1, 1));
    assert_eq!(interface.pairs.len(), 6);
    assert_relative_eq!(shortest_edge(&interface.mesh_a), 1e-4, max_relative = 1e-9);
    // A 1e-9 offset still snaps (snap_tolerance 1e-6 of the edge).
    let b = moved(&body_2(4), middle, [1e-9, 0.0]);
    let interface = insert_interface_nodes(&a, "bottom", &b, "top", &exact).unwrap();
    assert_eq!(interface.pairs.len(), 5);
}

#[test]
fn separated_flat_sides_have_the_separation_as_gap() {
    let a = body_1(3);
    let b = structured_triangles(&rect(0.0, -1.0, 1.0, -0.01), 5, 2).unwrap();
    let interface = pair_up(&a, "bottom", &b, "top");
    // Positions: 0, 1/5, 1/3, 2/5, 3/5, 2/3, 4/5, 1.
    assert_eq!(interface.pairs.len(), 8);
    for pair in &interface.pairs {
        assert_relative_eq!(pair.initial_gap, 0.01, max_relative = 1e-12);
        assert_eq!((pair.normal.x, pair.normal.y), (0.0, -1.0));
        assert_relative_eq!(pair.point_a.x, pair.point_b.x, epsilon = 1e-15);
    }
    // Closer than 0.01 only: nothing faces.
    let near = InterfaceOptions::builder()
        .max_distance(0.005)
        .build()
        .unwrap();
    let err = insert_interface_nodes(&a, "bottom", &b, "top", &near).unwrap_err();
    let text = err.to_string();
    assert!(
        text.contains("do not face") && text.contains("max_distance"),
        "{text}"
    );
    // Overlapping bodies (penetration 0.02): negative gaps.
    let b = structured_quads(&rect(0.0, -1.0, 1.0, 0.02), 2, 2).unwrap();
    let interface = pair_up(&a, "bottom", &b, "top");
    assert!(interface
        .pairs
        .iter()
        .all(|p| (p.initial_gap + 0.02).abs() < 1e-12));
}

/// Radius, bottom clearance, half opening angle and cells of the circular indenter.
const R: f64 = 1.0;
const CLEARANCE: f64 = 0.01;
const OPENING: f64 = 0.4;
const ARC_CELLS: usize = 6;

/// A circular indenter: the arc x = R sin(theta), y = CLEARANCE + R (1 - cos(theta)),
/// |theta| <= OPENING, as the part "bottom", below a flat top; centre (0, CLEARANCE + R).
fn indenter() -> Mesh {
    let unit = structured_quads(&Rectangle::unit_square(), ARC_CELLS, 2).unwrap();
    let top = CLEARANCE + R + 0.2;
    let vertices: Vec<Point> = unit
        .vertices()
        .iter()
        .map(|p| {
            let theta = -OPENING + 2.0 * OPENING * p.x;
            let bottom = CLEARANCE + R - R * theta.cos();
            Point::new(R * theta.sin(), bottom + p.y * (top - bottom))
        })
        .collect();
    Mesh::from_compact(
        vertices,
        unit.polygon_offsets().to_vec(),
        unit.polygon_vertex_indices().to_vec(),
        unit.part_specs(),
    )
    .unwrap()
}

#[test]
fn circular_indenter_gaps_match_the_analytic_distances() {
    let a = indenter();
    let b = structured_quads(&rect(-0.6, -0.5, 0.6, 0.0), 9, 2).unwrap();
    let interface = pair_up(&a, "bottom", &b, "top");
    let centre = Point::new(0.0, CLEARANCE + R);
    let step = 2.0 * OPENING / ARC_CELLS as f64;
    let angle = |i: usize| -OPENING + step * i as f64;
    // Flat nodes x_j = -0.6 + 1.2 j / 9 face the arc when atan(x_j / (R + CLEARANCE)) lies
    // within the opening: |x_j| < 0.427, i.e. j = 2..=7 (six nodes), none at an arc node.
    assert_eq!(interface.pairs.len(), (ARC_CELLS + 1) + 6);
    assert_eq!(interface.inserted_a, 6);
    assert_eq!(interface.inserted_b, ARC_CELLS + 1);
    let old_a = a.n_vertices();
    let mut checked = [0, 0, 0];
    for pair in &interface.pairs {
        if pair.node_a < old_a {
            // An arc node: vertex i of the bottom row.
            let i = pair.node_a;
            let theta = angle(i);
            let (normal_angle, expected_gap) = if i == 0 || i == ARC_CELLS {
                // End node: the normal of its only edge, radial at the edge's mid angle;
                // the ray falls a height y_a at slope cos(mid).
                let mid = if i == 0 {
                    angle(0) + 0.5 * step
                } else {
                    angle(ARC_CELLS) - 0.5 * step
                };
                checked[0] += 1;
                (mid, pair.point_a.y / mid.cos())
            } else {
                // Interior node: radial normal; the radial ray meets y = 0 at
                // t = (R + CLEARANCE) / cos(theta) - R.
                checked[1] += 1;
                (theta, (R + CLEARANCE) / theta.cos() - R)
            };
            assert_relative_eq!(pair.normal.x, normal_angle.sin(), epsilon = 1e-13);
            assert_relative_eq!(pair.normal.y, -normal_angle.cos(), epsilon = 1e-13);
            assert_relative_eq!(pair.initial_gap, expected_gap, epsilon = 1e-12);
            assert!(pair.point_b.y.abs() < 1e-15);
        } else {
            // A flat node x_b projected onto a chord along a's interpolated normal field,
            // which is radial on an inscribed polygon: x_a is where the line from the centre
            // to x_b crosses the chord.
            let to_b = pair.point_b - centre;
            let (rho, phi) = (to_b.norm(), to_b.x.atan2(-to_b.y));
            let cell = ((phi + OPENING) / step).floor() as usize;
            if cell == 0 || cell + 1 == ARC_CELLS {
                // On an end edge the field is not radial; only check that the gap is sane.
                assert!(pair.initial_gap > CLEARANCE && pair.initial_gap < 0.1);
                continue;
            }
            let mid = angle(cell) + 0.5 * step;
            let r = R * (0.5 * step).cos() / (phi - mid).cos();
            let expected_a = centre + r * Vector::new(phi.sin(), -phi.cos());
            assert_relative_eq!(pair.point_a.x, expected_a.x, epsilon = 1e-13);
            assert_relative_eq!(pair.point_a.y, expected_a.y, epsilon = 1e-13);
            assert_relative_eq!(pair.normal.x, mid.sin(), epsilon = 1e-13);
            assert_relative_eq!(pair.normal.y, -mid.cos(), epsilon = 1e-13);
            assert_relative_eq!(
                pair.initial_gap,
                (rho - r) * (phi - mid).cos(),
                epsilon = 1e-12
            );
            checked[2] += 1;
        }
    }
    assert_eq!(checked, [2, ARC_CELLS - 1, 4]);
    // The tributary lengths add up to the length of the polygonal arc.
    let chord = 2.0 * R * (0.5 * step).sin();
    assert_relative_eq!(
        total_tributary(&interface),
        ARC_CELLS as f64 * chord,
        max_relative = 1e-13
    );
    assert_each_node_once(
        &interface.mesh_a,
        "bottom",
        interface.pairs.iter().map(|p| p.node_a),
    );
}

#[test]
fn flat_nodes_on_the_indenter_rays_project_back_onto_its_nodes() {
    // The projection of b onto a (along a's interpolated normal field) inverts the ray cast
    // of a's nodes: a flat whose nodes sit where those rays land pairs without insertion.
    let a = indenter();
    let chain = boundary_chain(&a, "bottom").unwrap();
    let mut xs = vec![-0.6];
    for node in &chain {
        let t = -node.point.y / node.normal.y;
        xs.push(node.point.x + t * node.normal.x);
    }
    xs.push(0.6);
    let cells = xs.len() - 1;
    let unit = structured_quads(&Rectangle::unit_square(), cells, 1).unwrap();
    let vertices: Vec<Point> = unit
        .vertices()
        .iter()
        .map(|p| Point::new(xs[(p.x * cells as f64).round() as usize], 0.5 * (p.y - 1.0)))
        .collect();
    let b = Mesh::from_compact(
        vertices,
        unit.polygon_offsets().to_vec(),
        unit.polygon_vertex_indices().to_vec(),
        unit.part_specs(),
    )
    .unwrap();
    let exact = InterfaceOptions::builder()
        .min_edge_fraction(0.0)
        .build()
        .unwrap();
    let interface = insert_interface_nodes(&a, "bottom", &b, "top", &exact).unwrap();
    assert_eq!((interface.inserted_a, interface.inserted_b), (0, 0));
    assert_eq!(interface.pairs.len(), ARC_CELLS + 1);
    for (pair, node) in interface.pairs.iter().zip(&chain) {
        assert_eq!(pair.node_a, node.vertex);
        assert_relative_eq!(
            pair.initial_gap,
            (pair.point_b - pair.point_a).norm(),
            max_relative = 1e-13
        );
    }
}

#[test]
fn different_extents_pair_only_the_overlap() {
    // Body 1 on (0.25, 0.75) with 3 cells above body 2 on (0, 1) with 8 cells.
    let a = structured_quads(&rect(0.25, 0.0, 0.75, 1.0), 3, 2).unwrap();
    let b = body_2(8);
    let interface = pair_up(&a, "bottom", &b, "top");
    // Positions 1/4, 3/8, 5/12, 1/2, 7/12, 5/8, 3/4.
    let expected = [0.25, 0.375, 5.0 / 12.0, 0.5, 7.0 / 12.0, 0.625, 0.75];
    assert_eq!(interface.pairs.len(), expected.len());
    for (pair, x) in interface.pairs.iter().zip(expected) {
        assert_relative_eq!(pair.point_a.x, x, epsilon = 1e-15);
        assert_relative_eq!(pair.point_b.x, x, epsilon = 1e-15);
    }
    assert_eq!((interface.inserted_a, interface.inserted_b), (3, 2));
    assert_relative_eq!(total_tributary(&interface), 0.5, max_relative = 1e-14);
    // End lengths: half of the first and last paired edges (1/8 wide each).
    assert_relative_eq!(
        interface.pairs[0].tributary_length,
        1.0 / 16.0,
        epsilon = 1e-15
    );
    assert_relative_eq!(
        interface.pairs[6].tributary_length,
        1.0 / 16.0,
        epsilon = 1e-15
    );
    assert!(interface
        .pairs
        .iter()
        .all(|p| p.point_b.x >= 0.25 - 1e-15 && p.point_b.x <= 0.75 + 1e-15));

    // Ends that fall inside the other side's edges are inserted there.
    for swap in [false, true] {
        let short = structured_quads(&rect(0.3, 0.0, 0.7, 1.0), 2, 2).unwrap();
        let long = body_2(4);
        let interface = if swap {
            // a = long (top of body 2), b = short (bottom of body 1).
            pair_up(&long, "top", &short, "bottom")
        } else {
            pair_up(&short, "bottom", &long, "top")
        };
        // 0.3 and 0.7 go into the long side; 0.5 coincides.
        assert_eq!(interface.pairs.len(), 3);
        let (into_short, into_long) = (0, 2);
        let inserted = if swap {
            (into_long, into_short)
        } else {
            (into_short, into_long)
        };
        assert_eq!((interface.inserted_a, interface.inserted_b), inserted);
        assert_relative_eq!(total_tributary(&interface), 0.4, max_relative = 1e-14);
    }
}

#[test]
fn swapping_roles_keeps_pairs_and_gaps_and_flips_normals() {
    let a = body_1(4);
    for b in [
        structured_triangles(&rect(0.0, -1.0, 1.0, 0.0), 7, 2).unwrap(),
        structured_triangles(&rect(0.0, -1.0, 1.0, -0.01), 7, 2).unwrap(),
        structured_quads(&rect(0.2, -1.0, 1.4, -0.03), 5, 1).unwrap(),
    ] {
        let forward = pair_up(&a, "bottom", &b, "top");
        let backward = pair_up(&b, "top", &a, "bottom");
        assert_eq!(forward.pairs.len(), backward.pairs.len());
        assert_eq!(forward.inserted_a, backward.inserted_b);
        assert_eq!(forward.inserted_b, backward.inserted_a);
        // The chain of b runs the other way: compare in reverse.
        for (f, g) in forward.pairs.iter().zip(backward.pairs.iter().rev()) {
            assert_relative_eq!(f.initial_gap, g.initial_gap, epsilon = 1e-15);
            assert_eq!(f.normal, -g.normal);
            assert_relative_eq!(f.point_a.x, g.point_b.x, epsilon = 1e-15);
            assert_eq!(f.point_a.y, g.point_b.y);
        }
        assert_relative_eq!(
            total_tributary(&forward),
            total_tributary(&backward),
            max_relative = 1e-14
        );
    }
}

#[test]
fn bad_input_is_reported_with_names() {
    let (a, b) = (body_1(4), body_2(4));
    let options = InterfaceOptions::default();
    let err = insert_interface_nodes(&a, "contact", &b, "top", &options).unwrap_err();
    match &err {
        MeshError::UnknownPart { part, available } => {
            assert_eq!(part, "contact");
            assert_eq!(available, &["left", "right", "bottom", "top"]);
        }
        other => panic!("unexpected error {other}"),
    }
    assert!(err.to_string().contains("\"bottom\""), "{err}");

    // The bottom without its middle edges: two pieces.
    let broken = a
        .with_part_where("broken", |p, q| {
            p.y == 0.0 && q.y == 0.0 && p.x.max(q.x) != 0.75
        })
        .unwrap();
    let err = insert_interface_nodes(&broken, "broken", &b, "top", &options).unwrap_err();
    assert!(
        matches!(&err, MeshError::Interface { reason, .. } if reason.contains("2 disjoint pieces")),
        "{err}"
    );
    // The whole boundary: a closed loop.
    let all = a.with_part_where("all", |_, _| true).unwrap();
    let err = boundary_chain(&all, "all").unwrap_err();
    assert!(err.to_string().contains("closed loop"), "{err}");

    // Top of body 1 against top of body 2: the normals point the same way.
    let err = insert_interface_nodes(&a, "top", &b, "top", &options).unwrap_err();
    assert!(err.to_string().contains("do not oppose"), "{err}");
    // Sides that do not overlap.
    let far = structured_quads(&rect(2.0, -1.0, 3.0, 0.0), 2, 1).unwrap();
    let err = insert_interface_nodes(&a, "bottom", &far, "top", &options).unwrap_err();
    assert!(err.to_string().contains("do not face"), "{err}");
    // Touching in a single point only.
    let next = structured_quads(&rect(1.0, -1.0, 2.0, 0.0), 2, 1).unwrap();
    let err = insert_interface_nodes(&a, "bottom", &next, "top", &options).unwrap_err();
    assert!(err.to_string().contains("single point"), "{err}");

    // A notch 0.1 deep under x = 1/2 with max_distance 0.05: a node inside the overlap misses.
    let notched = moved(
        &structured_quads(&rect(0.0, -1.0, 1.0, 0.0), 4, 4).unwrap(),
        22,
        [0.0, -0.1],
    );
    let near = InterfaceOptions::builder()
        .max_distance(0.05)
        .build()
        .unwrap();
    let err = insert_interface_nodes(&a, "bottom", &notched, "top", &near).unwrap_err();
    assert!(
        err.to_string()
            .contains("vertex 2 of 'bottom' at (0.5, 0) does not project onto 'top'"),
        "{err}"
    );

    // Invalid settings are refused when the options are built, naming the setting.
    let builder = InterfaceOptions::builder();
    for (bad, setting) in [
        (builder.snap_tolerance(0.0).build(), "snap_tolerance"),
        (builder.min_edge_fraction(0.5).build(), "min_edge_fraction"),
        (builder.max_distance(f64::NAN).build(), "max_distance"),
    ] {
        let err = bad.unwrap_err();
        assert!(err.to_string().contains("must"), "{err}");
        assert!(
            matches!(err, MeshError::InvalidOption { setting: s, .. } if s == setting),
            "{err:?}"
        );
    }
}

/// Distinct x positions of the nodes of two horizontal chains, and the smallest distance
/// between two distinct ones.
fn distinct_positions(a: &Mesh, part_a: &str, b: &Mesh, part_b: &str) -> (Vec<f64>, f64) {
    let mut xs: Vec<f64> = boundary_chain(a, part_a)
        .unwrap()
        .iter()
        .chain(&boundary_chain(b, part_b).unwrap())
        .map(|node| node.point.x)
        .collect();
    xs.sort_by(f64::total_cmp);
    xs.dedup_by(|x, y| (*x - *y).abs() <= 1e-12);
    let closest = xs
        .windows(2)
        .map(|w| w[1] - w[0])
        .fold(f64::INFINITY, f64::min);
    (xs, closest)
}

#[test]
fn every_mesh_family_pairs_with_quads_at_all_distinct_positions() {
    use vem_mesh::generators::{voronoi, MeshFamily};
    let quads = body_2(5);
    let mut cases: Vec<(String, Mesh, Mesh)> = Vec::new();
    for family in MeshFamily::all() {
        for (n, seed) in [(4, 1), (7, 2), (10, 3)] {
            let a = family.generate(&rect(0.0, 0.0, 1.0, 1.0), n, seed).unwrap();
            cases.push((format!("{} n = {n}", family.name()), a, quads.clone()));
        }
    }
    // Voronoi over Voronoi, different sizes and seeds.
    let upper = voronoi(&rect(0.0, 0.0, 1.0, 1.0), 6, 11).unwrap();
    let lower = voronoi(&rect(0.0, -1.0, 1.0, 0.0), 9, 12).unwrap();
    cases.push(("voronoi over voronoi".into(), upper, lower));
    for (name, a, b) in &cases {
        let interface = pair_up(a, "bottom", b, "top");
        let (xs, closest) = distinct_positions(a, "bottom", b, "top");
        // No two distinct positions are within the snapping distance, so none merge.
        assert!(closest > 1e-3, "{name}: {closest}");
        assert_eq!(interface.pairs.len(), xs.len(), "{name}");
        for (pair, x) in interface.pairs.iter().zip(&xs) {
            assert_relative_eq!(pair.point_a.x, *x, epsilon = 1e-14);
            assert!(pair.initial_gap.abs() <= 1e-15, "{name}");
        }
        assert_eq!(
            interface.inserted_a + interface.inserted_b,
            2 * xs.len()
                - a.part_vertices("bottom").unwrap().len()
                - b.part_vertices("top").unwrap().len(),
            "{name}"
        );
        assert_relative_eq!(total_tributary(&interface), 1.0, max_relative = 1e-13);
        assert_relative_eq!(
            total_area(&interface.mesh_a),
            total_area(a),
            max_relative = 1e-13
        );
        assert_relative_eq!(
            total_area(&interface.mesh_b),
            total_area(b),
            max_relative = 1e-13
        );
        assert_each_node_once(
            &interface.mesh_a,
            "bottom",
            interface.pairs.iter().map(|p| p.node_a),
        );
        assert_each_node_once(
            &interface.mesh_b,
            "top",
            interface.pairs.iter().map(|p| p.node_b),
        );
    }
}
