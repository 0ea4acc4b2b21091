//! Property tests on random star-shaped polygons (3 to 12 vertices, convex or not, anywhere in
//! the plane, any size) and random isotropic materials: the element test kit (rigid-motion
//! kernel, rank 2n - 3, consistency (3.1) against an independent boundary integration, symmetry,
//! element patch test), and VEM = P1 on triangles.

use std::sync::Arc;

use proptest::prelude::*;
use vem_space::testkit::ElementCheck;
use vem_space::{
    BBar, DRecipe, DofiDofi, ElasticityTensor, ElementSpace, LinearTriangle, LowestOrderVem, Point,
    Stabilisation, StabilisationScaling,
};
/// A polygon with a number of vertices in `sizes`, star-shaped with respect to a random centre:
/// vertices at increasing angles (gaps between 1/2 and 3/2 of their mean) and radii in
/// [0.3, 1] times a size between 1e-3 and 1e3; edges shorter than h/20 are filtered out.
fn star_shaped(sizes: std::ops::RangeInclusive<usize>) -> impl Strategy<Value = Vec<Point>> {
    sizes
        .prop_flat_map(|n| {
            (
                prop::collection::vec((0.5f64..1.5, 0.3f64..1.0), n),
                0.0f64..std::f64::consts::TAU,
                (-100.0f64..100.0, -100.0f64..100.0),
                -3.0f64..3.0,
            )
        })
        .prop_map(|(vertices, phase, (cx, cy), log_size)| {
            let total: f64 = vertices.iter().map(|(gap, _)| gap).sum();
            let size = 10f64.powf(log_size);
            let mut angle = phase;
            vertices
                .iter()
                .map(|&(gap, radius)| {
                    let point = Point::new(
                        cx + size * radius * angle.cos(),
                        cy + size * radius * angle.sin(),
                    );
                    angle += std::f64::consts::TAU * gap / total;
                    point
                })
                .collect()
        })
        .prop_filter("edges may not be too short", |polygon: &Vec<Point>| {
            let h = vem_mesh::geometry::diameter(polygon);
            let n = polygon.len();
            (0..n).all(|k| (polygon[(k + 1) % n] - polygon[k]).norm() > 0.05 * h)
        })
}

fn isotropic() -> impl Strategy<Value = ElasticityTensor> {
    (0.0f64..100.0, 0.1f64..10.0)
        .prop_map(|(lambda, mu)| ElasticityTensor::try_isotropic(lambda, mu).unwrap())
}

fn stabilisation() -> impl Strategy<Value = Arc<dyn Stabilisation>> {
    prop_oneof![
        Just(Arc::new(DofiDofi::default()) as Arc<dyn Stabilisation>),
        Just(Arc::new(DofiDofi::new(StabilisationScaling::ShearModulus)) as Arc<dyn Stabilisation>),
        Just(Arc::new(DRecipe) as Arc<dyn Stabilisation>),
        Just(Arc::new(BBar) as Arc<dyn Stabilisation>),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(192))]

    #[test]
    fn kernel_rank_and_consistency_on_star_shaped_polygons(
        polygon in star_shaped(3..=12),
        material in isotropic(),
        stabilisation in stabilisation(),
    ) {
        // The element test kit on a random polygon: rigid motions, consistency (3.1) against a
        // boundary integration by hand, rank 2n - 3, symmetry, element patch test.
        let element = LowestOrderVem::try_new(stabilisation).unwrap();
        let check = ElementCheck::run(&element, "random", &polygon, &material).unwrap();
        // Vertex data carry an absolute error eps |x|: relative to h that is eps |x| / h.
        let largest = polygon.iter().map(|x| x.coords.norm()).fold(0.0, f64::max);
        let tolerance = 1e-12 * (largest / vem_mesh::geometry::diameter(&polygon)).max(1.0);
        let failures = check.failures(tolerance);
        prop_assert!(failures.is_empty(), "{failures:?}");
    }

    #[test]
    fn vem_equals_p1_on_random_triangles(
        polygon in star_shaped(3..=3),
        material in isotropic(),
        stabilisation in stabilisation(),
    ) {
        let element = LowestOrderVem::try_new(stabilisation).unwrap();
        let vem = element.stiffness(&polygon, &material).unwrap().total();
        let p1 = LinearTriangle.stiffness(&polygon, &material).unwrap().total();
        let difference = (&vem - &p1).norm() / p1.norm();
        prop_assert!(difference < 1e-13, "{difference:e}");
    }
}
