//! Every mesh family on simple polygons (an L-shaped bracket, a notched trapezoid with slanted
//! edges): the cells tile the polygon (their areas sum to its area), each boundary part is
//! exactly its polygon edges (lengths), the mesh is valid and shape-regular with a gamma that
//! does not decay under refinement, and bad polygons are refused naming the vertex or edge.

use vem_mesh::generators::{polygon_mesh, MeshFamily, PolygonDomain};
use vem_mesh::quality::summarise;
use vem_mesh::{Mesh, MeshError, Point};

fn points(xy: &[[f64; 2]]) -> Vec<Point> {
    xy.iter().map(|p| Point::new(p[0], p[1])).collect()
}

/// The L-shaped bracket (0, 2)^2 without [1, 2]^2, the legs named.
fn l_shape() -> PolygonDomain {
    PolygonDomain::new(points(&[
        [0.0, 0.0],
        [2.0, 0.0],
        [2.0, 1.0],
        [1.0, 1.0],
        [1.0, 2.0],
        [0.0, 2.0],
    ]))
    .unwrap()
    .with_edge_names(&["bottom", "end", "inner", "inner", "top", "left"])
    .unwrap()
}

/// A trapezoid with slanted sides and a V notch in its top: non-convex, no edge on a grid line.
fn notched_trapezoid() -> PolygonDomain {
    PolygonDomain::new(points(&[
        [-0.3, 0.1],
        [1.7, -0.2],
        [1.3, 1.1],
        [0.83, 1.07],
        [0.61, 0.43],
        [0.37, 1.13],
        [0.1, 1.0],
    ]))
    .unwrap()
}

fn part_length(mesh: &Mesh, name: &str) -> f64 {
    mesh.part(name)
        .unwrap()
        .edges
        .iter()
        .map(|&e| {
            let [a, b] = mesh.edge(e).vertices;
            (mesh.vertex(b) - mesh.vertex(a)).norm()
        })
        .sum()
}

/// Areas sum to the polygon's, each part's length is the length of its polygon edges, and
/// every boundary edge belongs to one part.
#[test]
fn cells_tile_the_polygon_and_parts_are_its_edges() {
    for domain in [l_shape(), notched_trapezoid()] {
        let m = domain.vertices().len();
        for family in MeshFamily::all() {
            for n in [2, 5, 16, 40] {
                let mesh = polygon_mesh(&domain, family, n, 3)
                    .unwrap_or_else(|e| panic!("{family} n = {n}: {e}"));
                let what = format!("{family} n = {n} on {:?}", domain.vertices()[1]);
                let area: f64 = (0..mesh.n_polygons()).map(|p| mesh.area(p)).sum();
                assert!(
                    (area - domain.area()).abs() <= 1e-12 * domain.area(),
                    "{what}: area {area} against {}",
                    domain.area()
                );
                let mut names: Vec<&String> = domain.edge_names().iter().collect();
                names.dedup();
                for name in names {
                    let expected: f64 = (0..m)
                        .filter(|&k| &domain.edge_names()[k] == name)
                        .map(|k| {
                            let [a, b] = domain.edge(k);
                            (b - a).norm()
                        })
                        .sum();
                    let length = part_length(&mesh, name);
                    assert!(
                        (length - expected).abs() <= 1e-12 * expected,
                        "{what}: part {name} has length {length}, its edges {expected}"
                    );
                }
                let in_parts: usize = mesh.parts().iter().map(|p| p.edges.len()).sum();
                assert_eq!(in_parts, mesh.boundary_edges().count(), "{what}");
            }
        }
    }
}

/// The cut cells keep the families' shape regularity (docs/meshes.md, "Meshes of a
/// polygon"): on the L-shape gamma (the smaller of the shortest-edge and star ratios) stays
/// above 0.035 for every family and size; on the notched trapezoid the median star ratio stays
/// that of the family's cells and every cell is star-shaped with ratio at least 0.045 (a cut
/// cell around the notch's reflex corner that no merge makes star-shaped is split: the chevron
/// family at n = 20 had a cell of star ratio 0 before).
#[test]
fn cut_meshes_are_shape_regular() {
    for (shape, domain) in [("L", l_shape()), ("notched", notched_trapezoid())] {
        for family in MeshFamily::all() {
            for n in [10, 20, 40] {
                let mesh = polygon_mesh(&domain, family, n, 3).unwrap();
                let q = summarise(&mesh);
                let what = format!("{shape} {family} n = {n}: {q:?}");
                eprintln!(
                    "{shape:>8} {family:>10} n = {n:>2} cells {:>5} gamma {:.3} star ratio min \
                     {:.3} median {:.3} shortest-edge ratio min {:.3}",
                    q.elements,
                    q.gamma,
                    q.star_ratio.min,
                    q.star_ratio.median,
                    q.shortest_edge_ratio.min
                );
                assert!(q.star_ratio.median >= 0.2, "{what}");
                if shape == "L" {
                    assert!(q.gamma >= 0.035, "{what}");
                } else {
                    assert!(q.star_ratio.min >= 0.045, "{what}");
                    assert!(q.shortest_edge_ratio.min >= 0.01, "{what}");
                }
            }
        }
    }
}

/// Bad polygons are refused, the error naming the vertex or edge to blame.
#[test]
fn bad_polygons_are_refused_with_their_place() {
    type Case<'a> = (&'a [[f64; 2]], Option<usize>, &'a str);
    let cases: [Case; 6] = [
        (&[[0.0, 0.0], [1.0, 0.0]], None, "2 vertices; at least 3"),
        (
            &[[0.0, 0.0], [1.0, 0.0], [1.0, 0.0], [0.0, 1.0]],
            Some(1),
            "edge 1 (vertex 1 to vertex 2) has zero length",
        ),
        (
            &[[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [1.0, -1.0], [0.0, 2.0]],
            Some(0),
            "edge 0 (vertex 0 to vertex 1) and edge 2 (vertex 2 to vertex 3) cross",
        ),
        (
            &[[0.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, 0.0]],
            None,
            "clockwise",
        ),
        (
            &[[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]],
            Some(0),
            "edge 0 (vertex 0 to vertex 1) and edge 2 (vertex 2 to vertex 0) cross or touch",
        ),
        (
            &[[0.0, 0.0], [f64::NAN, 0.0], [1.0, 1.0]],
            Some(1),
            "vertex 1 has a non-finite coordinate",
        ),
    ];
    for (xy, vertex, words) in cases {
        let error = PolygonDomain::new(points(xy)).unwrap_err();
        let MeshError::BadDomainPolygon { vertex: at, .. } = &error else {
            panic!("{xy:?}: {error}");
        };
        assert_eq!(*at, vertex, "{error}");
        assert!(error.to_string().contains(words), "{error}");
    }
    // A touching (not crossing) pair of edges: vertex 4 lies on edge 1.
    let touching = points(&[
        [0.0, 0.0],
        [2.0, 0.0],
        [2.0, 2.0],
        [1.0, 2.0],
        [2.0, 1.0],
        [0.0, 2.0],
    ]);
    let error = PolygonDomain::new(touching).unwrap_err();
    assert!(error.to_string().contains("cross or touch"), "{error}");
    let error = l_shape().with_edge_names(&["a", "b"]).unwrap_err();
    assert!(
        error.to_string().contains("2 edge names for 6 edges"),
        "{error}"
    );
}

/// A mesh that does not cover the polygon is refused by the cut.
#[test]
fn a_mesh_not_covering_the_polygon_is_refused() {
    use vem_mesh::generators::{cut_to_polygon, structured_quads, Rectangle};
    let small = structured_quads(&Rectangle::unit_square(), 4, 4).unwrap();
    let error = cut_to_polygon(&small, &l_shape()).unwrap_err();
    assert!(error.to_string().contains("must cover"), "{error}");
}
