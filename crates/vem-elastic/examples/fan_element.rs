//! An element written outside the workspace's crates, run through both test kits: piecewise
//! linear functions on the fan of triangles from the first vertex ("fan-p1"), with the vertex
//! values as degrees of freedom, like the lowest-order VEM.
//!
//! The element is conforming and exact on linear fields wherever the fan is a triangulation
//! (convex polygons), so it passes the element checks there. It cannot take a non-convex
//! polygon whose fan folds over, nor vertices inserted on an edge at the first vertex (a fan
//! triangle of zero area): the kits report those polygons and mesh families by name. That is
//! the reason the project uses the virtual element on meshes with interface nodes.
//!
//! Run with `cargo run -p vem-elastic --example fan_element`.

use std::sync::Arc;

use nalgebra::{DMatrix, DVector};
use vem_elastic::testkit::global_patch_tests;
use vem_space::testkit::{standard_materials, standard_polygons, ElementCheck};
use vem_space::{
    ElasticityTensor, ElementSpace, EnergyProjection, LinearTriangle, LocalStiffness, Point,
    SpaceError, Vector,
};

/// P1 on the fan triangles `(x_0, x_k, x_{k+1})`, `k = 1 .. n-2`.
#[derive(Debug, Clone, Copy, Default)]
struct FanP1;

impl FanP1 {
    /// The fan triangles as (local vertex indices, vertices).
    fn fan(polygon: &[Point]) -> impl Iterator<Item = ([usize; 3], [Point; 3])> + '_ {
        (1..polygon.len() - 1).map(|k| {
            let local = [0, k, k + 1];
            (local, local.map(|i| polygon[i]))
        })
    }

    fn check(polygon: &[Point]) -> Result<(), SpaceError> {
        if polygon.len() < 3 {
            return Err(SpaceError::UnsupportedPolygon {
                element: "fan-p1".into(),
                vertices: polygon.len(),
            });
        }
        Ok(())
    }
}

impl ElementSpace for FanP1 {
    fn name(&self) -> &str {
        "fan-p1"
    }

    fn supports(&self, n_vertices: usize) -> bool {
        n_vertices >= 3
    }

    fn stiffness(
        &self,
        polygon: &[Point],
        material: &ElasticityTensor,
    ) -> Result<LocalStiffness, SpaceError> {
        Self::check(polygon)?;
        let n = polygon.len();
        let mut k = DMatrix::zeros(2 * n, 2 * n);
        for (local, triangle) in Self::fan(polygon) {
            // The P1 matrix of the fan triangle, scattered to the polygon's DOFs.
            let k_t = LinearTriangle.stiffness(&triangle, material)?.consistency;
            for (a, &i) in local.iter().enumerate() {
                for (b, &j) in local.iter().enumerate() {
                    for (c, d) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                        k[(2 * i + c, 2 * j + d)] += k_t[(2 * a + c, 2 * b + d)];
                    }
                }
            }
        }
        Ok(LocalStiffness {
            consistency: k,
            stabilisation: DMatrix::zeros(2 * n, 2 * n),
        })
    }

    fn projection(&self, polygon: &[Point]) -> Result<EnergyProjection, SpaceError> {
        // The area-weighted mean of the fan triangles' gradients and values at the centroid:
        // the L2 projection of the gradient onto constants, exact on linear fields.
        Self::check(polygon)?;
        let n = polygon.len();
        let centroid = vem_mesh::geometry::centroid(polygon);
        let area = vem_mesh::geometry::signed_area(polygon);
        let mut coefficients = DMatrix::zeros(6, 2 * n);
        for (local, triangle) in Self::fan(polygon) {
            let p = LinearTriangle.projection(&triangle)?;
            let weight = vem_mesh::geometry::signed_area(&triangle) / area;
            for (a, &i) in local.iter().enumerate() {
                for row in 0..6 {
                    for c in 0..2 {
                        coefficients[(row, 2 * i + c)] += weight * p.coefficients[(row, 2 * a + c)];
                    }
                }
            }
            // Shift the triangle's value rows from its centroid to the polygon's.
            let shift = centroid - p.reference;
            for (a, &i) in local.iter().enumerate() {
                for c in 0..2 {
                    let (gx, gy) = (
                        p.coefficients[(2 + 2 * c, 2 * a + c)],
                        p.coefficients[(3 + 2 * c, 2 * a + c)],
                    );
                    coefficients[(c, 2 * i + c)] += weight * (gx * shift.x + gy * shift.y);
                }
            }
        }
        Ok(EnergyProjection {
            reference: centroid,
            coefficients,
        })
    }

    fn body_load(
        &self,
        polygon: &[Point],
        body_force: &(dyn Fn(Point) -> Vector + Sync),
    ) -> Result<DVector<f64>, SpaceError> {
        Self::check(polygon)?;
        let mut load = DVector::zeros(2 * polygon.len());
        for (local, triangle) in Self::fan(polygon) {
            let l_t = LinearTriangle.body_load(&triangle, body_force)?;
            for (a, &i) in local.iter().enumerate() {
                load[2 * i] += l_t[2 * a];
                load[2 * i + 1] += l_t[2 * a + 1];
            }
        }
        Ok(load)
    }
}

fn main() {
    let element = FanP1;
    let material = &standard_materials()[1];
    println!(
        "element checks of '{}' (anisotropic material):",
        element.name()
    );
    println!(
        "{:<40} {:>3} {:>10} {:>10} {:>5} {:>10}",
        "polygon", "n", "rigid", "(3.1)", "rank", "patch"
    );
    for polygon in standard_polygons() {
        match ElementCheck::run(&element, polygon.name, &polygon.vertices, material) {
            Ok(c) => println!(
                "{:<40} {:>3} {:>10.1e} {:>10.1e} {:>2}/{:<2} {:>10.1e}",
                c.polygon,
                c.n_vertices,
                c.rigid_motion_residual,
                c.consistency_error,
                c.rank,
                c.expected_rank(),
                c.patch_test_error
            ),
            Err(e) => println!(
                "{:<40} {:>3} fails: {}",
                polygon.name,
                polygon.vertices.len(),
                std::error::Error::source(&e).map_or(e.to_string(), |s| s.to_string())
            ),
        }
    }
    println!("\nglobal patch test (relative nodal error):");
    for (family, result) in global_patch_tests(Arc::new(element)) {
        match result {
            Ok(report) => println!(
                "{:<12} {:>5} polygons {:>10.1e}",
                family.name(),
                report.polygons,
                report.nodal_error
            ),
            Err(e) => {
                let cause = std::error::Error::source(&e).map_or(String::new(), |s| s.to_string());
                println!("{:<12} fails: {e}: {cause}", family.name())
            }
        }
    }
}
