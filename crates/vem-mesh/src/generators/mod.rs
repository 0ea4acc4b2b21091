//! Reproducible mesh generators on a rectangle.
//!
//! Each generator is parameterised by a size `n` (a refinement family: the mesh size falls
//! like 1/n) and, where random, a seed (same seed, same mesh, bit for bit). Every generated mesh
//! names the boundary parts "left", "right", "bottom" and "top".

mod structured;

pub use structured::{structured_quads, structured_triangles};

use crate::{Mesh, MeshError, PartSpec, Point};

/// An axis-aligned rectangle [x0, x1] x [y0, y1].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rectangle {
    /// Lower-left corner.
    pub min: Point,
    /// Upper-right corner.
    pub max: Point,
}

impl Rectangle {
    /// The rectangle with corners `min` and `max`.
    pub fn new(min: Point, max: Point) -> Self {
        Self { min, max }
    }

    /// The unit square (0,1)^2.
    pub fn unit_square() -> Self {
        Self::new(Point::new(0.0, 0.0), Point::new(1.0, 1.0))
    }

    /// Width (x extent).
    pub fn width(&self) -> f64 {
        self.max.x - self.min.x
    }

    /// Height (y extent).
    pub fn height(&self) -> f64 {
        self.max.y - self.min.y
    }

    /// Checks that the rectangle has positive, finite extent.
    pub(crate) fn check(&self, generator: &'static str) -> Result<(), MeshError> {
        let ok = [self.min.x, self.min.y, self.max.x, self.max.y]
            .iter()
            .all(|c| c.is_finite())
            && self.width() > 0.0
            && self.height() > 0.0;
        if ok {
            Ok(())
        } else {
            Err(MeshError::BadGeneratorParameter {
                generator,
                reason: format!(
                    "the rectangle [{}, {}] x [{}, {}] must have positive finite extent",
                    self.min.x, self.max.x, self.min.y, self.max.y
                ),
            })
        }
    }
}

/// Builds a mesh on `rect` and names "left", "right", "bottom", "top" from the boundary edges
/// lying on each side of the rectangle (to a tolerance relative to its size).
pub(crate) fn mesh_with_sides(
    rect: &Rectangle,
    vertices: Vec<Point>,
    polygons: &[Vec<usize>],
) -> Result<Mesh, MeshError> {
    let mesh = Mesh::from_polygons(vertices, polygons, vec![])?;
    let tol = 1e-9 * rect.width().max(rect.height());
    let on = |value: f64, side: f64| (value - side).abs() <= tol;
    let mut parts: Vec<PartSpec> = ["left", "right", "bottom", "top"]
        .iter()
        .map(|name| PartSpec::new(*name, Vec::new()))
        .collect();
    for e in mesh.boundary_edges() {
        let [a, b] = mesh.edge(e).vertices;
        let (pa, pb) = (mesh.vertex(a), mesh.vertex(b));
        let side = if on(pa.x, rect.min.x) && on(pb.x, rect.min.x) {
            0
        } else if on(pa.x, rect.max.x) && on(pb.x, rect.max.x) {
            1
        } else if on(pa.y, rect.min.y) && on(pb.y, rect.min.y) {
            2
        } else if on(pa.y, rect.max.y) && on(pb.y, rect.max.y) {
            3
        } else {
            continue;
        };
        parts[side].edges.push([a, b]);
    }
    let (vertices, offsets, indices) = (
        mesh.vertices().to_vec(),
        mesh.polygon_offsets().to_vec(),
        mesh.polygon_vertex_indices().to_vec(),
    );
    Mesh::from_compact(vertices, offsets, indices, parts)
}

/// Checks a size parameter n >= `min`.
pub(crate) fn check_size(generator: &'static str, n: usize, min: usize) -> Result<(), MeshError> {
    if n < min {
        return Err(MeshError::BadGeneratorParameter {
            generator,
            reason: format!("size n = {n} is too small; it must be at least {min}"),
        });
    }
    Ok(())
}
