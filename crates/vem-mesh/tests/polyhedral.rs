//! Polyhedral meshes: geometry against closed forms, every generated family against the
//! conservation laws of a partition of the box (volume, side areas, Euler characteristic, face
//! sharing, the divergence theorem per cell), shape-regularity against closed forms, and
//! validation against every kind of corrupted mesh (the right located error, never a panic).

use proptest::prelude::*;
use vem_mesh::generators::polyhedral::{
    extrude, hexahedra, nonconvex_prisms, octree_hexahedra, perturbed_hexahedra, tetrahedra,
    voronoi_polyhedra, Cuboid, PolyhedralFamily, SIDE_NAMES,
};
use vem_mesh::polyhedral::geometry::{self, Polyhedron};
use vem_mesh::polyhedral::quality;
use vem_mesh::{
    FacePart, FacePartSpec, MeshError, OrientedFace, Point, Point3, PolyhedralMesh, Vector3,
};

// ---------------------------------------------------------------------------------------------
// Helpers

/// The eight corners of the box [o, o + size] (corner k has bits x, y, z).
fn box_points(origin: Vector3, size: Vector3) -> Vec<Point3> {
    (0..8)
        .map(|k| {
            Point3::from(
                origin
                    + size.component_mul(&Vector3::new(
                        (k & 1) as f64,
                        (k >> 1 & 1) as f64,
                        (k >> 2) as f64,
                    )),
            )
        })
        .collect()
}

/// Outward faces of a box with corners numbered as in [`box_points`], offset by `base`.
fn box_loops(base: usize) -> Vec<Vec<usize>> {
    vec![
        vec![0, 4, 6, 2],
        vec![1, 3, 7, 5],
        vec![0, 1, 5, 4],
        vec![2, 6, 7, 3],
        vec![0, 2, 3, 1],
        vec![4, 5, 7, 6],
    ]
    .into_iter()
    .map(|f| f.into_iter().map(|v| v + base).collect())
    .collect()
}

fn unit_cube_mesh() -> PolyhedralMesh {
    PolyhedralMesh::from_polyhedra(
        box_points(Vector3::zeros(), Vector3::repeat(1.0)),
        &[box_loops(0)],
        vec![],
    )
    .unwrap()
}

/// Two unit cubes along x sharing the face x = 1: vertices x + 3 y + 6 z.
fn two_cubes() -> (Vec<Point3>, Vec<Vec<Vec<usize>>>) {
    let mut vertices = Vec::new();
    for z in 0..2 {
        for y in 0..2 {
            for x in 0..3 {
                vertices.push(Point3::new(x as f64, y as f64, z as f64));
            }
        }
    }
    let cube = |x: usize| -> Vec<Vec<usize>> {
        let v = |dx: usize, dy: usize, dz: usize| x + dx + 3 * dy + 6 * dz;
        vec![
            vec![v(0, 0, 0), v(0, 0, 1), v(0, 1, 1), v(0, 1, 0)],
            vec![v(1, 0, 0), v(1, 1, 0), v(1, 1, 1), v(1, 0, 1)],
            vec![v(0, 0, 0), v(1, 0, 0), v(1, 0, 1), v(0, 0, 1)],
            vec![v(0, 1, 0), v(0, 1, 1), v(1, 1, 1), v(1, 1, 0)],
            vec![v(0, 0, 0), v(0, 1, 0), v(1, 1, 0), v(1, 0, 0)],
            vec![v(0, 0, 1), v(1, 0, 1), v(1, 1, 1), v(0, 1, 1)],
        ]
    };
    (vertices, vec![cube(0), cube(1)])
}

/// An L-shaped prism: L = [0,2]x[0,1] + [0,1]x[1,2] extruded over z in [0, 1], shifted by
/// `origin`.
fn l_prism(origin: Vector3) -> Polyhedron {
    let l = [
        (0.0, 0.0),
        (2.0, 0.0),
        (2.0, 1.0),
        (1.0, 1.0),
        (1.0, 2.0),
        (0.0, 2.0),
    ];
    let mut points = Vec::new();
    for z in [0.0, 1.0] {
        for &(x, y) in &l {
            points.push(Point3::from(origin + Vector3::new(x, y, z)));
        }
    }
    let mut faces = vec![(0..6).rev().collect::<Vec<usize>>(), (6..12).collect()];
    for k in 0..6 {
        let next = (k + 1) % 6;
        faces.push(vec![k, next, next + 6, k + 6]);
    }
    Polyhedron::new(points, &faces)
}

fn cuboids() -> [Cuboid; 2] {
    [
        Cuboid::unit_cube(),
        Cuboid::new(Point3::new(-1.0, 0.5, 2.0), Point3::new(2.0, 2.5, 3.5)),
    ]
}

fn total_volume(mesh: &PolyhedralMesh) -> f64 {
    (0..mesh.n_cells()).map(|c| mesh.volume(c)).sum()
}

// ---------------------------------------------------------------------------------------------
// Geometry against closed forms

#[test]
fn unit_cube_and_l_prism_far_from_the_origin() {
    for origin in [Vector3::zeros(), Vector3::new(1e6, -2e6, 3e5)] {
        let cube = Polyhedron::new(box_points(origin, Vector3::repeat(1.0)), &box_loops(0));
        let (volume, centroid) = cube.volume_and_centroid();
        assert!((volume - 1.0).abs() < 1e-9, "{volume}");
        assert!((centroid - (Point3::from(origin) + Vector3::repeat(0.5))).norm() < 1e-9);
        let l = l_prism(origin);
        let (volume, centroid) = l.volume_and_centroid();
        assert!((volume - 3.0).abs() < 1e-9, "{volume}");
        let expected = Point3::from(origin) + Vector3::new(5.0 / 6.0, 5.0 / 6.0, 0.5);
        assert!((centroid - expected).norm() < 1e-9, "{centroid}");
        // Kernel of the L prism: [0,1]^2 x [0,1], largest ball radius 1/2 (diameter 3).
        let q = quality::cell_quality(&l);
        assert!((q.diameter - 3.0).abs() < 1e-9);
        assert!((q.star_ratio - 0.5 / 3.0).abs() < 1e-9, "{q:?}");
        assert!(l.total_vector_area().norm() < 1e-6);
    }
}

#[test]
fn tetrahedron_and_triangular_prism() {
    // Tetrahedron (0, e1, e2, e3): volume 1/6, centroid (1/4, 1/4, 1/4).
    let points = vec![
        Point3::origin(),
        Point3::new(1.0, 0.0, 0.0),
        Point3::new(0.0, 1.0, 0.0),
        Point3::new(0.0, 0.0, 1.0),
    ];
    let tet = Polyhedron::new(
        points,
        &[vec![0, 2, 1], vec![0, 1, 3], vec![0, 3, 2], vec![1, 2, 3]],
    );
    let (volume, centroid) = tet.volume_and_centroid();
    assert!((volume - 1.0 / 6.0).abs() < 1e-16);
    assert!((centroid - Point3::new(0.25, 0.25, 0.25)).norm() < 1e-16);
    // Its inradius: 3 V / area = (1/2) / (3/2 + sqrt 3 / 2).
    let inradius = 0.5 / (1.5 + 3f64.sqrt() / 2.0);
    assert!((quality::star_radius(&tet) - inradius).abs() < 1e-14);
    // Triangular prism: triangle (0,0), (2,0), (0,1) over z in [0, 3]: volume 3, centroid
    // (2/3, 1/3, 3/2).
    let mut points = Vec::new();
    for z in [0.0, 3.0] {
        points.extend([
            Point3::new(0.0, 0.0, z),
            Point3::new(2.0, 0.0, z),
            Point3::new(0.0, 1.0, z),
        ]);
    }
    let prism = Polyhedron::new(
        points,
        &[
            vec![0, 2, 1],
            vec![3, 4, 5],
            vec![0, 1, 4, 3],
            vec![1, 2, 5, 4],
            vec![2, 0, 3, 5],
        ],
    );
    let (volume, centroid) = prism.volume_and_centroid();
    assert!((volume - 3.0).abs() < 1e-15);
    assert!((centroid - Point3::new(2.0 / 3.0, 1.0 / 3.0, 1.5)).norm() < 1e-15);
}

#[test]
fn polygon_star_radius_agrees_with_the_planar_bisection() {
    // Two independent computations of the planar kernel's Chebyshev radius.
    let shapes: Vec<Vec<Point>> = vec![
        vec![
            Point::new(0.0, 0.0),
            Point::new(2.0, 0.0),
            Point::new(2.0, 1.0),
            Point::new(1.0, 1.0),
            Point::new(1.0, 2.0),
            Point::new(0.0, 2.0),
        ],
        vec![
            Point::new(0.0, 0.0),
            Point::new(0.5, 0.25),
            Point::new(1.0, 0.0),
            Point::new(1.0, 1.0),
            Point::new(0.5, 1.25),
            Point::new(0.0, 1.0),
        ],
        (0..7)
            .map(|k| {
                let t = std::f64::consts::TAU * k as f64 / 7.0;
                let r = if k % 2 == 0 { 1.0 } else { 0.6 };
                Point::new(r * t.cos(), r * t.sin())
            })
            .collect(),
    ];
    for shape in &shapes {
        let lp = quality::polygon_star_radius(shape);
        let bisection = vem_mesh::quality::star_radius(shape);
        assert!((lp - bisection).abs() < 1e-10, "{lp} {bisection}");
        assert!(lp > 0.0);
    }
}

// ---------------------------------------------------------------------------------------------
// Generated families: a partition of the box

fn families() -> Vec<PolyhedralFamily> {
    PolyhedralFamily::all().to_vec()
}

/// Every family on two boxes and two sizes: the cells fill the box, the side parts cover the
/// sides exactly, V - E + F - C = 1, interior faces join two cells with opposite orientations,
/// every boundary face lies in exactly one side part.
#[test]
fn generated_meshes_partition_the_box() {
    for cuboid in cuboids() {
        let e = cuboid.extent();
        let side_areas = [
            e.y * e.z,
            e.y * e.z,
            e.x * e.z,
            e.x * e.z,
            e.x * e.y,
            e.x * e.y,
        ];
        for family in families() {
            for n in [1, 2, 5] {
                let what = format!("{family} n = {n} on {cuboid:?}");
                let mesh = family.generate(&cuboid, n, 11).unwrap();
                let volume = total_volume(&mesh);
                assert!(
                    ((volume - cuboid.volume()) / cuboid.volume()).abs() < 1e-12,
                    "{what}: {volume}"
                );
                assert_eq!(mesh.euler_characteristic(), 1, "{what}");
                let mut in_parts = vec![0; mesh.n_faces()];
                for (side, name) in SIDE_NAMES.iter().enumerate() {
                    let faces = mesh.part_faces(name).unwrap();
                    let area: f64 = faces.iter().map(|&f| mesh.face_area(f)).sum();
                    assert!(
                        ((area - side_areas[side]) / side_areas[side]).abs() < 1e-12,
                        "{what}: {name} {area}"
                    );
                    let axis = side / 2;
                    let sign = if side % 2 == 0 { -1.0 } else { 1.0 };
                    for &f in faces {
                        in_parts[f] += 1;
                        // Boundary faces point out of the box.
                        assert!(mesh.face_normal(f)[axis] * sign > 0.99, "{what}: face {f}");
                    }
                }
                for (f, &count) in in_parts.iter().enumerate() {
                    let cells = mesh.face_cells(f);
                    let expected = usize::from(cells.is_boundary());
                    assert_eq!(count, expected, "{what}: face {f}");
                    if let Some(neighbour) = cells.neighbour {
                        let sees = |c: usize| {
                            mesh.cell_faces(c)
                                .iter()
                                .find(|s| s.face == f)
                                .map(|s| s.outward)
                        };
                        assert_eq!(sees(cells.owner), Some(true), "{what}");
                        assert_eq!(sees(neighbour), Some(false), "{what}");
                    }
                }
            }
        }
    }
}

/// The divergence theorem per cell with the fan weights: sum over the cell's faces and vertices
/// of x_a (x) w_a = |E| I, exactly (to round-off) for planar and warped faces alike, because the
/// fan weights integrate the fan-linear field x and the volume is the fan's.
#[test]
fn vertex_weights_satisfy_the_divergence_theorem_in_every_cell() {
    let cuboid = cuboids()[1];
    for family in families() {
        let mesh = family.generate(&cuboid, 3, 5).unwrap();
        for c in 0..mesh.n_cells() {
            let cell = mesh.cell_polyhedron(c);
            let centre = geometry::vertex_mean(cell.points());
            let mut gradient = nalgebra::Matrix3::<f64>::zeros();
            for k in 0..cell.n_faces() {
                let points = cell.face_points(k);
                for (p, w) in points.iter().zip(geometry::face_vertex_weights(&points)) {
                    gradient += (p - centre) * w.transpose();
                }
            }
            let volume = cell.volume();
            let error = (gradient - volume * nalgebra::Matrix3::identity()).norm();
            assert!(
                error < 1e-12 * volume.abs().max(1e-3),
                "{family} cell {c}: {error}"
            );
        }
    }
}

/// Every face corner's edge lists the face among its faces; the faces around an edge contain
/// both of its end vertices consecutively.
#[test]
fn edges_know_their_faces() {
    let mesh = octree_hexahedra(&Cuboid::unit_cube(), 3).unwrap();
    for f in 0..mesh.n_faces() {
        for &e in mesh.face_edges(f) {
            assert!(mesh.edge_faces(e).contains(&f));
        }
    }
    for e in 0..mesh.n_edges() {
        let [a, b] = mesh.edge(e);
        assert_eq!(mesh.find_edge(b, a), Some(e));
        for &f in mesh.edge_faces(e) {
            let face = mesh.face(f);
            let n = face.len();
            assert!((0..n).any(|k| {
                let (x, y) = (face[k], face[(k + 1) % n]);
                (x, y) == (a, b) || (x, y) == (b, a)
            }));
        }
    }
    // A hanging midpoint: the edges of a kept box's side split in two; each half is shared
    // by the faces of all the cells around it (three or four faces).
    let hanging = (0..mesh.n_vertices())
        .find(|&v| {
            let p = mesh.vertex(v);
            (p.x - 0.5).abs() < 1e-12 && (p.y - 1.0 / 3.0).abs() < 1e-12 && p.z == 1.0 / 3.0
        })
        .expect("the midpoint of an edge of a kept box");
    let around = (0..mesh.n_edges())
        .filter(|&e| mesh.edge(e).contains(&hanging))
        .count();
    assert!(around >= 4, "{around}");
}

/// The edge midpoints inserted as vertices on every family (hexahedra, tetrahedra, warped
/// perturbed hexahedra, Voronoi, non-convex prisms, octree with hanging nodes): V grows by E,
/// every face doubles its vertices (the old ones in their old order, every other one, each
/// midpoint halfway along its edge), E doubles, F and C stay, so V - E + F - C stays 1; every
/// cell's volume and centroid, every face's vector area and every part's area are unchanged to
/// round-off (the fan centre of a face is the mean of its edge midpoints too); on tetrahedra
/// every face is a hexagon and every cell has 10 vertices.
#[test]
fn edge_midpoints_keep_the_geometry_and_the_parts() {
    let cuboid = cuboids()[1];
    for family in families() {
        for n in [1, 3] {
            let what = format!("{family} n = {n}");
            let mesh = family.generate(&cuboid, n, 7).unwrap();
            let refined = mesh.with_edge_midpoints().unwrap();
            assert_eq!(
                refined.n_vertices(),
                mesh.n_vertices() + mesh.n_edges(),
                "{what}"
            );
            assert_eq!(refined.n_edges(), 2 * mesh.n_edges(), "{what}");
            assert_eq!(refined.n_faces(), mesh.n_faces(), "{what}");
            assert_eq!(refined.n_cells(), mesh.n_cells(), "{what}");
            assert_eq!(refined.euler_characteristic(), 1, "{what}");
            let scale = cuboid.extent().norm();
            for f in 0..mesh.n_faces() {
                let (old, new) = (mesh.face(f), refined.face(f));
                assert_eq!(new.len(), 2 * old.len(), "{what}: face {f}");
                let corners: Vec<usize> = new.iter().copied().step_by(2).collect();
                assert_eq!(corners, old, "{what}: face {f}");
                for k in 0..old.len() {
                    let (a, b) = (mesh.vertex(old[k]), mesh.vertex(old[(k + 1) % old.len()]));
                    let m = refined.vertex(new[2 * k + 1]);
                    assert!(
                        (m - Point3::from((a.coords + b.coords) / 2.0)).norm() < 1e-15 * scale,
                        "{what}: face {f}"
                    );
                }
                let area = mesh.face_vector_area(f);
                assert!(
                    (refined.face_vector_area(f) - area).norm() <= 1e-13 * area.norm(),
                    "{what}: face {f}"
                );
                assert_eq!(
                    refined.face_cells(f),
                    mesh.face_cells(f),
                    "{what}: face {f}"
                );
            }
            for c in 0..mesh.n_cells() {
                let volume = mesh.volume(c);
                assert!(
                    (refined.volume(c) - volume).abs() <= 1e-12 * volume,
                    "{what}: cell {c}"
                );
                assert!(
                    (refined.centroid(c) - mesh.centroid(c)).norm() <= 1e-12 * scale,
                    "{what}: cell {c}"
                );
                assert_eq!(
                    refined.cell_faces(c),
                    mesh.cell_faces(c),
                    "{what}: cell {c}"
                );
            }
            assert!(
                ((total_volume(&refined) - cuboid.volume()) / cuboid.volume()).abs() < 1e-12,
                "{what}"
            );
            assert_eq!(refined.part_names(), mesh.part_names(), "{what}");
            for part in mesh.parts() {
                let faces = refined.part_faces(&part.name).unwrap();
                assert_eq!(faces, part.faces.as_slice(), "{what}: {}", part.name);
                let area =
                    |m: &PolyhedralMesh| -> f64 { faces.iter().map(|&f| m.face_area(f)).sum() };
                assert!(
                    (area(&refined) - area(&mesh)).abs() <= 1e-12 * area(&mesh),
                    "{what}: {}",
                    part.name
                );
                // Every midpoint of a part's edge is a vertex of the part.
                let vertices = refined.part_vertices(&part.name).unwrap();
                let old = mesh.part_vertices(&part.name).unwrap();
                let edges: std::collections::BTreeSet<usize> = faces
                    .iter()
                    .flat_map(|&f| mesh.face_edges(f).iter().copied())
                    .collect();
                assert_eq!(vertices.len(), old.len() + edges.len(), "{what}");
            }
            if family == PolyhedralFamily::Tetrahedra {
                assert!(refined.faces().all(|f| f.len() == 6), "{what}");
                assert!(
                    (0..refined.n_cells()).all(|c| refined.cell_vertices(c).len() == 10),
                    "{what}"
                );
            }
        }
    }
}

#[test]
fn random_families_are_reproducible_and_depend_on_the_seed() {
    let cube = Cuboid::unit_cube();
    for family in families().into_iter().filter(|f| f.is_random()) {
        let a = family.generate(&cube, 3, 1).unwrap();
        assert_eq!(a, family.generate(&cube, 3, 1).unwrap(), "{family}");
        assert_ne!(a, family.generate(&cube, 3, 2).unwrap(), "{family}");
    }
}

#[test]
fn family_names_round_trip_and_bad_ones_are_refused() {
    for family in families() {
        assert_eq!(
            family.to_string().parse::<PolyhedralFamily>().unwrap(),
            family
        );
    }
    for bad in [
        "cubes",
        "perturbed-hexahedra:0.3",
        "voronoi:2",
        "perturbed-hexahedra:x",
    ] {
        let err = bad.parse::<PolyhedralFamily>().unwrap_err();
        assert!(
            matches!(err, MeshError::BadGeneratorParameter { .. }),
            "{bad}"
        );
    }
    let flat = Cuboid::new(Point3::origin(), Point3::new(1.0, 1.0, 0.0));
    assert!(hexahedra(&flat, 2, 2, 2).is_err());
    assert!(perturbed_hexahedra(&Cuboid::unit_cube(), 2, 0.3, 1).is_err());
    assert!(hexahedra(&Cuboid::unit_cube(), 0, 2, 2).is_err());
    assert!(hexahedra(&Cuboid::unit_cube(), 1000, 1000, 1000).is_err());
}

// ---------------------------------------------------------------------------------------------
// Quality against closed forms

#[test]
fn quality_of_the_lattice_families() {
    let cube = Cuboid::unit_cube();
    let s3 = 3f64.sqrt();
    // Cubes: star radius h/2, edge h, face diameter sqrt 2 h, face disc h/2, h_E = sqrt 3 h.
    let q = hexahedra(&cube, 4, 4, 4).unwrap().quality();
    assert!((q.star_ratio.min - 0.5 / s3).abs() < 1e-12);
    assert!((q.shortest_edge_ratio.min - 1.0 / s3).abs() < 1e-12);
    assert!((q.smallest_face_ratio.min - 2f64.sqrt() / s3).abs() < 1e-12);
    assert!((q.face_star_ratio.min - 0.5 / 2f64.sqrt()).abs() < 1e-12);
    assert_eq!(q.face_warping.max, 0.0);
    // Kuhn tetrahedra: inradius 3 V / area = (1/2) / (1 + sqrt 2), h_E = sqrt 3.
    let q = tetrahedra(&cube, 2, 2, 2).unwrap().quality();
    let inradius = 0.5 / (1.0 + 2f64.sqrt());
    assert!((q.star_ratio.min - inradius / s3).abs() < 1e-12);
    assert!((q.star_ratio.max - inradius / s3).abs() < 1e-12);
    // Octree: kept boxes and split cubes both have star ratio 1/(2 sqrt 3); the kept boxes' half
    // edges give 1/(2 sqrt 3) and their quarter faces sqrt 2 h / 2 / (sqrt 3 h).
    let q = octree_hexahedra(&cube, 4).unwrap().quality();
    assert!((q.gamma - 0.5 / s3).abs() < 1e-12);
    assert!((q.smallest_face_ratio.min - 2f64.sqrt() / 2.0 / s3).abs() < 1e-12);
    // Chevron prisms: an interior cell's kernel is the chevron's kernel times the layer, radius
    // h / (2 sqrt(1 + 4 s^2)) = h / sqrt 5 for s = 1/4.
    let mesh = nonconvex_prisms(&cube, 4).unwrap();
    let interior = (0..mesh.n_cells())
        .find(|&c| {
            mesh.cell_faces(c).len() == 8
                && mesh
                    .cell_faces(c)
                    .iter()
                    .all(|s| !mesh.is_boundary_face(s.face))
        })
        .expect("an interior chevron prism");
    let q = mesh.cell_quality(interior);
    assert!((q.star_ratio - 1.0 / 15f64.sqrt()).abs() < 1e-10, "{q:?}");
}

#[test]
fn quality_is_bounded_under_refinement() {
    // gamma does not decay for the refined families (seed 1, n = 2, 4, 8).
    let cube = Cuboid::unit_cube();
    for family in families() {
        let gammas: Vec<f64> = [2, 4, 8]
            .iter()
            .map(|&n| family.generate(&cube, n, 1).unwrap().quality().gamma)
            .collect();
        assert!(gammas.iter().all(|&g| g > 0.005), "{family}: {gammas:?}");
    }
    // The Voronoi merge keeps edges and faces from collapsing.
    let q = voronoi_polyhedra(&cube, 6, 3).unwrap().quality();
    assert!(q.shortest_edge_ratio.min > 0.02, "{q}");
    assert!(q.smallest_face_ratio.min > 0.02, "{q}");
    assert!(q.star_ratio.min > 0.1, "{q}");
}

// ---------------------------------------------------------------------------------------------
// Constructors and accessors

#[test]
fn two_cubes_share_one_face() {
    let (vertices, cells) = two_cubes();
    let mesh = PolyhedralMesh::from_polyhedra(vertices, &cells, vec![]).unwrap();
    assert_eq!((mesh.n_faces(), mesh.n_edges()), (11, 20));
    assert_eq!(mesh.boundary_faces().count(), 10);
    let shared = (0..mesh.n_faces())
        .find(|&f| !mesh.is_boundary_face(f))
        .unwrap();
    assert_eq!(mesh.face_normal(shared), Vector3::x());
    assert_eq!(mesh.face_cells(shared).owner, 0);
    assert_eq!(mesh.cell_vertices(0), &[0, 1, 3, 4, 6, 7, 9, 10]);
    assert!((mesh.centroid(1) - Point3::new(1.5, 0.5, 0.5)).norm() < 1e-15);
    assert_eq!(mesh.mesh_size(), 3f64.sqrt());
    // The VTK polyhedron's faces: outward loops of global vertices.
    for c in 0..2 {
        let loops = mesh.cell_face_loops(c);
        let points: Vec<Point3> = mesh.vertices().to_vec();
        let cell = Polyhedron::new(points, &loops);
        assert!((cell.volume() - 1.0).abs() < 1e-15);
    }
    // Parts by predicate.
    let mesh = mesh
        .with_part_where("end", |points| points.iter().all(|p| p.x == 2.0))
        .unwrap();
    assert_eq!(mesh.part_vertices("end").unwrap(), vec![2, 5, 8, 11]);
    let err = mesh.part("nowhere").unwrap_err();
    assert!(err.to_string().contains("\"end\""), "{err}");
}

#[test]
fn extruded_planar_meshes_keep_their_parts() {
    use vem_mesh::generators::{voronoi, Rectangle};
    let planar = voronoi(&Rectangle::unit_square(), 4, 2).unwrap();
    let mesh = extrude(&planar, -1.0, 1.0, 3).unwrap();
    assert!((total_volume(&mesh) - 2.0).abs() < 1e-13);
    for name in SIDE_NAMES {
        let area: f64 = mesh
            .part_faces(name)
            .unwrap()
            .iter()
            .map(|&f| mesh.face_area(f))
            .sum();
        let expected = if name == "bottom" || name == "top" {
            1.0
        } else {
            2.0
        };
        assert!((area - expected).abs() < 1e-13, "{name}: {area}");
    }
}

// ---------------------------------------------------------------------------------------------
// Validation: each defect, its located error

fn polyhedra_error(vertices: Vec<Point3>, cells: &[Vec<Vec<usize>>]) -> MeshError {
    PolyhedralMesh::from_polyhedra(vertices, cells, vec![]).unwrap_err()
}

#[test]
fn storage_defects_are_located() {
    let points = box_points(Vector3::zeros(), Vector3::repeat(1.0));
    let mut cells = vec![box_loops(0)];
    cells[0][2] = vec![0, 1, 9, 4];
    assert_eq!(
        polyhedra_error(points.clone(), &cells),
        MeshError::FaceVertexOutOfRange {
            face: 2,
            vertex: 9,
            vertex_count: 8
        }
    );
    let mut cells = vec![box_loops(0)];
    cells[0][3] = vec![2, 6];
    assert_eq!(
        polyhedra_error(points.clone(), &cells),
        MeshError::FaceTooFewVertices { face: 3, count: 2 }
    );
    let mut cells = vec![box_loops(0)];
    cells[0][1] = vec![1, 3, 7, 3];
    assert_eq!(
        polyhedra_error(points.clone(), &cells),
        MeshError::FaceRepeatedVertex { face: 1, vertex: 3 }
    );
    let mut bad = points.clone();
    bad[5].y = f64::NAN;
    assert!(matches!(
        polyhedra_error(bad, &[box_loops(0)]),
        MeshError::NonFiniteVertex3 { vertex: 5, .. }
    ));
    let mut extra = points.clone();
    extra.push(Point3::new(5.0, 5.0, 5.0));
    assert_eq!(
        polyhedra_error(extra, &[box_loops(0)]),
        MeshError::UnusedVertex { vertex: 8 }
    );
    let cells = vec![box_loops(0)[..3].to_vec()];
    assert_eq!(
        polyhedra_error(points.clone(), &cells),
        MeshError::CellTooFewFaces { cell: 0, count: 3 }
    );
    assert!(matches!(
        polyhedra_error(vec![], &[]),
        MeshError::EmptyPolyhedral { .. }
    ));
    // Compact storage: offsets, face and cell indices.
    let cube = unit_cube_mesh();
    let compact = |face_offsets: Vec<usize>, cell_faces: Vec<OrientedFace>| {
        PolyhedralMesh::from_compact(
            cube.vertices().to_vec(),
            face_offsets,
            cube.face_vertex_indices().to_vec(),
            vec![0, cell_faces.len()],
            cell_faces,
            vec![],
        )
        .unwrap_err()
    };
    let faces: Vec<OrientedFace> = cube.cell_faces(0).to_vec();
    let mut offsets = cube.face_offsets().to_vec();
    offsets[6] = 23;
    assert!(matches!(
        compact(offsets, faces.clone()),
        MeshError::BadStorage { .. }
    ));
    let mut out_of_range = faces.clone();
    out_of_range[4].face = 6;
    assert_eq!(
        compact(cube.face_offsets().to_vec(), out_of_range),
        MeshError::CellFaceOutOfRange {
            cell: 0,
            face: 6,
            face_count: 6
        }
    );
    let mut repeated = faces.clone();
    repeated[5] = repeated[0];
    assert_eq!(
        compact(cube.face_offsets().to_vec(), repeated),
        MeshError::CellRepeatedFace { cell: 0, face: 0 }
    );
    let unused = faces[..5].to_vec();
    let err = compact(cube.face_offsets().to_vec(), unused);
    assert_eq!(err, MeshError::UnusedFace { face: 5 });
}

#[test]
fn sharing_defects_are_located() {
    let (vertices, cells) = two_cubes();
    // The second cube turned inside out: both cells see the shared face outward.
    let mut inverted = cells.clone();
    for face in &mut inverted[1] {
        face.reverse();
    }
    let err = polyhedra_error(vertices.clone(), &inverted);
    assert!(
        matches!(
            err,
            MeshError::FaceSameOrientation {
                cells: [0, 1],
                outward: true,
                ..
            }
        ),
        "{err}"
    );
    // One cube alone turned inside out: inverted.
    let mut single = box_loops(0);
    for face in &mut single {
        face.reverse();
    }
    let err = polyhedra_error(
        box_points(Vector3::zeros(), Vector3::repeat(1.0)),
        &[single],
    );
    assert!(
        matches!(err, MeshError::InvertedCell { cell: 0, .. }),
        "{err}"
    );
    // A face used by three cells (compact storage).
    let mesh = PolyhedralMesh::from_polyhedra(vertices.clone(), &cells, vec![]).unwrap();
    let mut cell_faces = mesh.cell_face_indices().to_vec();
    let shared = (0..mesh.n_faces())
        .find(|&f| !mesh.is_boundary_face(f))
        .unwrap();
    let mut offsets = mesh.cell_offsets().to_vec();
    cell_faces.extend(mesh.cell_faces(0).iter().copied().map(|mut s| {
        if s.face == shared {
            s.outward = false;
        }
        s
    }));
    offsets.push(cell_faces.len());
    let err = PolyhedralMesh::from_compact(
        mesh.vertices().to_vec(),
        mesh.face_offsets().to_vec(),
        mesh.face_vertex_indices().to_vec(),
        offsets,
        cell_faces,
        vec![],
    )
    .unwrap_err();
    assert_eq!(
        err,
        MeshError::OverusedFace {
            face: shared,
            cells: vec![0, 1, 2]
        }
    );
    // Two faces with the same vertices (the shared face stored twice, once per cube).
    let mut face_offsets = mesh.face_offsets().to_vec();
    let mut face_vertices = mesh.face_vertex_indices().to_vec();
    face_vertices.extend(mesh.face(shared).iter().rev());
    face_offsets.push(face_vertices.len());
    let mut cell_faces = mesh.cell_face_indices().to_vec();
    for s in &mut cell_faces[6..] {
        if s.face == shared {
            *s = OrientedFace::new(mesh.n_faces(), true);
        }
    }
    let err = PolyhedralMesh::from_compact(
        mesh.vertices().to_vec(),
        face_offsets,
        face_vertices,
        mesh.cell_offsets().to_vec(),
        cell_faces,
        vec![],
    )
    .unwrap_err();
    assert_eq!(
        err,
        MeshError::DuplicateFace {
            a: shared,
            b: mesh.n_faces()
        }
    );
}

#[test]
fn closure_defects_are_located() {
    let points = box_points(Vector3::zeros(), Vector3::repeat(1.0));
    // A missing face: the cell is open along the edges of that face.
    let mut open = box_loops(0);
    open.pop();
    open.push(vec![4, 5, 7]); // a triangle cannot close the top
    let err = polyhedra_error(points.clone(), &[open]);
    assert!(
        matches!(err, MeshError::CellNotClosed { cell: 0, .. }),
        "{err}"
    );
    // One face reversed: two of its edges are traversed twice in the same direction.
    let mut flipped = box_loops(0);
    flipped[5].reverse();
    let err = polyhedra_error(points.clone(), &[flipped]);
    assert!(
        matches!(
            err,
            MeshError::CellNotClosed {
                cell: 0,
                forward: 2,
                backward: 0,
                ..
            } | MeshError::CellNotClosed {
                cell: 0,
                forward: 0,
                backward: 2,
                ..
            }
        ),
        "{err}"
    );
    // The same hanging node missing in the first cube's own bottom face: its faces do not close.
    let (mut vertices, mut cells) = two_cubes();
    vertices.push(Point3::new(1.0, 0.5, 0.0));
    cells[0][1] = vec![1, 12, 4, 10, 7];
    let err = polyhedra_error(vertices, &cells);
    assert!(
        matches!(err, MeshError::CellNotClosed { cell: 0, .. }),
        "{err}"
    );
    // A vertex inside a face that does not list it: the octree's coarse side kept whole
    // while the fine cubes split it.
    let (mut vertices, cells) = two_cubes();
    vertices.push(Point3::new(1.0, 0.5, 0.5));
    let centre = vertices.len() - 1;
    let mut cells = cells;
    // A third cell: a pyramid on the shared face's far side would be a different mesh; here a
    // tetrahedron inside the second cube touching the face x = 1 at its centre.
    vertices.extend([
        Point3::new(1.5, 0.4, 0.4),
        Point3::new(1.5, 0.6, 0.4),
        Point3::new(1.5, 0.5, 0.6),
    ]);
    let t = centre + 1;
    cells.push(vec![
        vec![centre, t + 1, t],
        vec![centre, t, t + 2],
        vec![centre, t + 2, t + 1],
        vec![t, t + 1, t + 2],
    ]);
    let err = polyhedra_error(vertices, &cells);
    assert!(
        matches!(err, MeshError::HangingVertex { vertex, .. } if vertex == centre),
        "{err}"
    );
    // Two disjoint boxes listed as one cell.
    let mut two = points.clone();
    two.extend(box_points(
        Vector3::new(3.0, 0.0, 0.0),
        Vector3::repeat(1.0),
    ));
    let mut loops = box_loops(0);
    loops.extend(box_loops(8));
    let err = polyhedra_error(two, &[loops]);
    assert!(
        matches!(err, MeshError::DisconnectedCell { cell: 0, .. }),
        "{err}"
    );
    // A hanging node the neighbour does not list: the first cube's shared face and its
    // neighbour carry the midpoint m of the edge (1,0,0)-(1,1,0), the second cube's faces do
    // not: m lies on two faces of the second cube that do not list it.
    let (mut vertices, mut cells) = two_cubes();
    vertices.push(Point3::new(1.0, 0.5, 0.0));
    let m = vertices.len() - 1;
    // Cube 0: face x = 1 is [1, 4, 10, 7]; bottom is [0, 3, 4, 1]: add m between 4 and 1.
    cells[0][1] = vec![1, m, 4, 10, 7];
    cells[0][4] = vec![0, 3, 4, m, 1];
    let err = polyhedra_error(vertices, &cells);
    assert!(
        matches!(err, MeshError::HangingVertex { vertex, .. } if vertex == m),
        "{err}"
    );
}

#[test]
fn geometric_defects_are_located() {
    // Coincident vertices.
    let mut points = box_points(Vector3::zeros(), Vector3::repeat(1.0));
    points[7] = points[6];
    let err = polyhedra_error(points, &[box_loops(0)]);
    assert!(
        matches!(err, MeshError::DuplicateVertices { a: 6, b: 7, .. }),
        "{err}"
    );
    // A planar face that crosses itself (listed first, so it is face 0): the top face's
    // vertices moved in its plane into a bow tie.
    let mut points = box_points(Vector3::zeros(), Vector3::repeat(1.0));
    points[5] = Point3::new(2.0, 0.0, 1.0);
    points[7] = Point3::new(0.0, 1.0, 1.0);
    points[6] = Point3::new(1.0, 1.0, 1.0);
    let mut loops = box_loops(0);
    loops.rotate_right(1);
    let err = polyhedra_error(points, &[loops]);
    assert!(
        matches!(err, MeshError::SelfIntersectingFace { face: 0, .. }),
        "{err}"
    );
    // A warped face whose fan folds over: the top face's vertex 7 pulled across its diagonal
    // and up.
    let mut points = box_points(Vector3::zeros(), Vector3::repeat(1.0));
    points[7] = Point3::new(-0.3, -0.3, 1.2);
    let mut loops = box_loops(0);
    loops.rotate_right(1);
    let err = polyhedra_error(points, &[loops]);
    assert!(
        matches!(err, MeshError::FoldedFace { face: 0, .. }),
        "{err}"
    );
    // A flattened box: faces of zero area.
    let points = box_points(Vector3::zeros(), Vector3::new(1.0, 1.0, 0.0));
    let err = polyhedra_error(points, &[box_loops(0)]);
    assert!(
        matches!(
            err,
            MeshError::DuplicateVertices { .. } | MeshError::DegenerateFace { .. }
        ),
        "{err}"
    );
    let points = box_points(Vector3::zeros(), Vector3::new(1.0, 1.0, 1e-14));
    let err = polyhedra_error(points, &[box_loops(0)]);
    assert!(
        matches!(
            err,
            MeshError::DegenerateFace { .. } | MeshError::DuplicateVertices { .. }
        ),
        "{err}"
    );
}

#[test]
fn part_defects_are_located() {
    let (vertices, cells) = two_cubes();
    let err = PolyhedralMesh::from_polyhedra(
        vertices.clone(),
        &cells,
        vec![FacePartSpec::new("mid", vec![vec![1, 7, 10, 4]])],
    )
    .unwrap_err();
    assert!(
        matches!(err, MeshError::InteriorFaceInPart { ref part, cells: [0, 1], .. } if part == "mid"),
        "{err}"
    );
    let err = PolyhedralMesh::from_polyhedra(
        vertices.clone(),
        &cells,
        vec![FacePartSpec::new("x", vec![vec![0, 1, 2]])],
    )
    .unwrap_err();
    assert_eq!(
        err,
        MeshError::UnknownFace {
            part: "x".into(),
            vertices: vec![0, 1, 2]
        }
    );
    let left = vec![vec![0, 6, 9, 3]];
    let err = PolyhedralMesh::from_polyhedra(
        vertices.clone(),
        &cells,
        vec![
            FacePartSpec::new("left", left.clone()),
            FacePartSpec::new("left", left),
        ],
    )
    .unwrap_err();
    assert_eq!(
        err,
        MeshError::DuplicatePart {
            part: "left".into()
        }
    );
    let mesh = PolyhedralMesh::from_polyhedra(vertices, &cells, vec![]).unwrap();
    let err = mesh
        .clone()
        .with_parts(vec![FacePart::new("far", vec![99])])
        .unwrap_err();
    assert_eq!(
        err,
        MeshError::PartFaceOutOfRange {
            part: "far".into(),
            face: 99,
            face_count: 11
        }
    );
}

// ---------------------------------------------------------------------------------------------
// Property tests

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    /// Random seeds and sizes give valid meshes that fill the box.
    #[test]
    fn random_meshes_are_valid(
        seed in 0u64..1_000_000,
        n in 1usize..5,
        distortion in 0.0f64..=0.25,
        which in 0usize..3,
    ) {
        // Two boxes of near-cubic cells and a slab whose cells are ten times thinner in y.
        let slab = Cuboid::new(Point3::origin(), Point3::new(1.0, 0.1, 3.0));
        let cuboid = [cuboids()[0], cuboids()[1], slab][which];
        for mesh in [
            voronoi_polyhedra(&cuboid, n, seed).unwrap(),
            perturbed_hexahedra(&cuboid, n, distortion, seed).unwrap(),
        ] {
            let volume = total_volume(&mesh);
            prop_assert!(((volume - cuboid.volume()) / cuboid.volume()).abs() < 1e-12);
            prop_assert_eq!(mesh.euler_characteristic(), 1);
            for c in 0..mesh.n_cells() {
                prop_assert!(mesh.volume(c) > 0.0);
                prop_assert!(mesh.cell_quality(c).star_ratio > 0.0);
            }
        }
    }

    /// Random corruptions of a valid mesh's storage give a valid mesh or an error, never a
    /// panic; an accepted mesh has finite positive volumes.
    #[test]
    fn corrupted_storage_never_panics(
        seed in 0u64..1000,
        edits in proptest::collection::vec((0usize..6, any::<usize>(), any::<usize>(), -2.0f64..2.0), 1..4),
    ) {
        let mesh = perturbed_hexahedra(&Cuboid::unit_cube(), 2, 0.2, seed).unwrap();
        let mut vertices = mesh.vertices().to_vec();
        let mut face_offsets = mesh.face_offsets().to_vec();
        let mut face_vertices = mesh.face_vertex_indices().to_vec();
        let cell_offsets = mesh.cell_offsets().to_vec();
        let mut cell_faces = mesh.cell_face_indices().to_vec();
        for (kind, a, b, x) in edits {
            match kind {
                0 => { let k = a % face_vertices.len(); face_vertices[k] = b % (vertices.len() + 2); }
                1 => { let k = a % cell_faces.len(); cell_faces[k].outward = !cell_faces[k].outward; }
                2 => { let k = a % cell_faces.len(); cell_faces[k].face = b % (face_offsets.len() + 1); }
                3 => { let v = a % vertices.len(); vertices[v][b % 3] += x; }
                4 => { let k = 1 + a % (face_offsets.len() - 1); face_offsets[k] = face_offsets[k].saturating_sub(b % 3); }
                _ => { let v = a % vertices.len(); vertices[v] = vertices[b % vertices.len()]; }
            }
        }
        if let Ok(mesh) = PolyhedralMesh::from_compact(vertices, face_offsets, face_vertices, cell_offsets, cell_faces, vec![]) {
            for c in 0..mesh.n_cells() {
                let v = mesh.volume(c);
                prop_assert!(v.is_finite() && v > 0.0);
                let q = mesh.cell_quality(c);
                prop_assert!(q.gamma().is_finite());
            }
        }
    }
}
