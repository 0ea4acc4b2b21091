//! Prisms: extruded polygonal meshes, and the non-convex chevron prisms.

use super::{box_counts, step, Cuboid, MAX_POLYHEDRAL_CELLS};
use crate::generators::{nonconvex, Rectangle};
use crate::polyhedral::CellsBuilder;
use crate::{FacePart, Mesh, MeshError, Point, Point3, PolyhedralMesh};

/// The prisms over the polygons of `mesh` (in the xy plane) between z = `z0` and z = `z1`, in
/// `nz` equal layers: polygon p of layer l is cell p + n_polygons l; vertex v of level l is
/// vertex v + n_vertices l.
///
/// Parts: each part of `mesh` becomes the lateral faces over its edges, under the same name,
/// except that the planar `bottom` and `top` (the sides y = min, y = max of the generators'
/// rectangles) become `front` and `back`, the names of the y sides in three dimensions; the
/// faces at z = `z0` and z = `z1` form the parts `bottom` and `top`. A polygonal mesh of a
/// rectangle from [`crate::generators`] thus becomes a mesh of a box with the six side names of
/// [`super`].
///
/// ```
/// use vem_mesh::generators::{hexagons, polyhedral::extrude, Rectangle};
/// let planar = hexagons(&Rectangle::unit_square(), 3)?;
/// let mesh = extrude(&planar, 0.0, 0.5, 2)?;
/// assert_eq!(mesh.n_cells(), 2 * planar.n_polygons());
/// let volume: f64 = (0..mesh.n_cells()).map(|c| mesh.volume(c)).sum();
/// assert!((volume - 0.5).abs() < 1e-14);
/// assert_eq!(mesh.part_faces("front")?.len(), 2 * planar.part("bottom")?.edges.len());
/// # Ok::<(), vem_mesh::MeshError>(())
/// ```
pub fn extrude(mesh: &Mesh, z0: f64, z1: f64, nz: usize) -> Result<PolyhedralMesh, MeshError> {
    const NAME: &str = "extrude";
    super::super::check_size(NAME, nz, 1)?;
    if !(z0.is_finite() && z1.is_finite() && z1 > z0) {
        return Err(MeshError::BadGeneratorParameter {
            generator: NAME,
            reason: format!("the layer [{z0}, {z1}] must have positive finite thickness"),
        });
    }
    let cells = mesh.n_polygons() as f64 * nz as f64;
    if cells > MAX_POLYHEDRAL_CELLS as f64 {
        return Err(MeshError::BadGeneratorParameter {
            generator: NAME,
            reason: format!("{cells:e} prisms are more than {MAX_POLYHEDRAL_CELLS}"),
        });
    }
    let nv = mesh.n_vertices();
    let mut vertices = Vec::with_capacity(nv * (nz + 1));
    for l in 0..=nz {
        let z = step(l, nz, z0, z1);
        vertices.extend(
            mesh.vertices()
                .iter()
                .map(|p: &Point| Point3::new(p.x, p.y, z)),
        );
    }
    let mut builder = CellsBuilder::with_capacity(mesh.n_polygons() * nz, 8, 4);
    let mut reversed = Vec::new();
    let mut shifted = Vec::new();
    for l in 0..nz {
        for polygon in mesh.polygons() {
            let (low, high) = (l * nv, (l + 1) * nv);
            reversed.clear();
            reversed.extend(polygon.iter().rev().map(|&v| v + low));
            builder.push_face(&reversed);
            shifted.clear();
            shifted.extend(polygon.iter().map(|&v| v + high));
            builder.push_face(&shifted);
            let m = polygon.len();
            for k in 0..m {
                let (a, b) = (polygon[k], polygon[(k + 1) % m]);
                builder.push_face(&[a + low, b + low, b + high, a + high]);
            }
            builder.end_cell();
        }
    }
    let matched = builder.match_faces();
    let mut parts = Vec::with_capacity(mesh.parts().len() + 2);
    for part in mesh.parts() {
        let name = match part.name.as_str() {
            "bottom" => "front",
            "top" => "back",
            other => other,
        };
        let mut faces = Vec::with_capacity(part.edges.len() * nz);
        for l in 0..nz {
            for &e in &part.edges {
                let [a, b] = mesh.edge(e).vertices;
                let (low, high) = (l * nv, (l + 1) * nv);
                if let Some(f) = matched.find(&[a + low, b + low, b + high, a + high]) {
                    faces.push(f);
                }
            }
        }
        parts.push(FacePart::new(name, faces));
    }
    for (name, level) in [("bottom", 0), ("top", nz)] {
        let faces = mesh
            .polygons()
            .filter_map(|polygon| {
                let loop_: Vec<usize> = polygon.iter().map(|&v| v + level * nv).collect();
                matched.find(&loop_)
            })
            .collect();
        parts.push(FacePart::new(name, faces));
    }
    matched.build(vertices, parts)
}

/// Chevron prisms tiling `cuboid`, about `n` cells across: the planar chevron mesh of
/// [`crate::generators::nonconvex`] on the box's xy rectangle, extruded in round(n ez / ex)
/// layers ([`extrude`]).
///
/// Interior cells are hexagonal prisms with one reflex edge (over the chevron's reflex vertex):
/// non-convex and star-shaped. For cubic lattice cells of side h, rise s =
/// [`crate::generators::CHEVRON_RISE`] = 1/4: h_E = sqrt 3 h, and the kernel is the planar
/// kernel times the layer, so the star-shaped radius is min(h / (2 sqrt(1 + 4 s^2)), h / 2) =
/// h / sqrt 5 (ratio 1 / sqrt 15 ~ 0.258).
///
/// ```
/// use vem_mesh::generators::polyhedral::{nonconvex_prisms, Cuboid};
/// let mesh = nonconvex_prisms(&Cuboid::unit_cube(), 4)?;
/// assert_eq!(mesh.n_cells(), 64);
/// assert_eq!(mesh.cell_faces(21).len(), 8); // an interior chevron prism
/// # Ok::<(), vem_mesh::MeshError>(())
/// ```
pub fn nonconvex_prisms(cuboid: &Cuboid, n: usize) -> Result<PolyhedralMesh, MeshError> {
    let [_, _, nz] = box_counts("nonconvex_prisms", cuboid, n, MAX_POLYHEDRAL_CELLS)?;
    let rect = Rectangle::new(
        Point::new(cuboid.min.x, cuboid.min.y),
        Point::new(cuboid.max.x, cuboid.max.y),
    );
    extrude(&nonconvex(&rect, n)?, cuboid.min.z, cuboid.max.z, nz)
}
