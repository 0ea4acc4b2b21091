//! Mesh validation: every constructor of [`crate::Mesh`] runs these checks.
//!
//! Checks, in order: storage (offsets, index range, repeated indices, at least three vertices,
//! finite coordinates), orientation and area of every polygon.

use crate::{geometry, Mesh, MeshError, Point};

/// Relative area below which a polygon counts as degenerate: |area| < this * diameter^2.
pub const DEGENERATE_AREA_RATIO: f64 = 1e-12;

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
    if offsets[0] != 0 || *offsets.last().unwrap() != indices.len() {
        return Err(MeshError::BadStorage {
            reason: format!(
                "offsets must start at 0 and end at the number of indices ({}), found {} .. {}",
                indices.len(),
                offsets[0],
                offsets.last().unwrap()
            ),
        });
    }
    for p in 0..offsets.len() - 1 {
        if offsets[p + 1] < offsets[p] {
            return Err(MeshError::BadStorage {
                reason: format!("offsets decrease at polygon {p}"),
            });
        }
        let loop_ = &indices[offsets[p]..offsets[p + 1]];
        if loop_.len() < 3 {
            return Err(MeshError::TooFewVertices {
                polygon: p,
                count: loop_.len(),
            });
        }
        for (k, &v) in loop_.iter().enumerate() {
            if v >= vertices.len() {
                return Err(MeshError::VertexOutOfRange {
                    polygon: p,
                    vertex: v,
                    vertex_count: vertices.len(),
                });
            }
            if loop_[..k].contains(&v) {
                return Err(MeshError::RepeatedVertex {
                    polygon: p,
                    vertex: v,
                });
            }
        }
    }
    Ok(())
}

/// Checks a mesh whose storage and edges are consistent.
pub(crate) fn validate(mesh: &Mesh) -> Result<(), MeshError> {
    for p in 0..mesh.n_polygons() {
        let points = mesh.polygon_points(p);
        let signed_area = geometry::signed_area(&points);
        let diameter = geometry::diameter(&points);
        if signed_area.abs() <= DEGENERATE_AREA_RATIO * diameter * diameter {
            return Err(MeshError::DegenerateArea {
                polygon: p,
                area: signed_area,
            });
        }
        if signed_area < 0.0 {
            return Err(MeshError::Clockwise {
                polygon: p,
                signed_area,
            });
        }
    }
    Ok(())
}
