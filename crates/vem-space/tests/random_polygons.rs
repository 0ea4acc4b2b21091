//! Property tests on random star-shaped polygons (3 to 12 vertices, convex or not, anywhere in
//! the plane, any size) and random isotropic materials: rigid-motion kernel, rank 2n - 3,
//! consistency (3.1) against an independent boundary integration, and VEM = P1 on triangles.

use nalgebra::{DVector, Matrix2};
use proptest::prelude::*;
use vem_space::{
    ElasticityTensor, ElementSpace, LinearTriangle, LowestOrderVem, Point, Stabilisation,
    StabilisationScaling, Vector,
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
        .prop_map(|(lambda, mu)| ElasticityTensor::isotropic(lambda, mu).unwrap())
}

fn stabilisation() -> impl Strategy<Value = Stabilisation> {
    prop_oneof![
        Just(Stabilisation::default()),
        Just(Stabilisation::dofi_dofi(StabilisationScaling::ShearModulus)),
        Just(Stabilisation::DRecipe),
    ]
}

/// Vertex values of x -> a + M (x - origin), interleaved.
fn linear_field(polygon: &[Point], origin: Point, a: Vector, m: &Matrix2<f64>) -> DVector<f64> {
    DVector::from_fn(2 * polygon.len(), |i, _| {
        (a + m * (polygon[i / 2] - origin))[i % 2]
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(192))]

    #[test]
    fn kernel_rank_and_consistency_on_star_shaped_polygons(
        polygon in star_shaped(3..=12),
        material in isotropic(),
        stabilisation in stabilisation(),
        gradient in prop::array::uniform4(-1.0f64..1.0),
    ) {
        let n = polygon.len();
        let element = LowestOrderVem::new(stabilisation).unwrap();
        let local = element.stiffness(&polygon, &material).unwrap();
        let k = local.total();
        let origin = polygon[0];
        // Vertex data carry an absolute error eps |x|: relative to h that is eps |x| / h.
        let largest = polygon.iter().map(|x| x.coords.norm()).fold(0.0, f64::max);
        let tolerance = 1e-12 * (largest / vem_mesh::geometry::diameter(&polygon)).max(1.0);
        // Rigid motions (1,0), (0,1) and the rotation (-(y - y0), x - x0).
        let rotation = Matrix2::new(0.0, -1.0, 1.0, 0.0);
        for r in [
            linear_field(&polygon, origin, Vector::new(1.0, 0.0), &Matrix2::zeros()),
            linear_field(&polygon, origin, Vector::new(0.0, 1.0), &Matrix2::zeros()),
            linear_field(&polygon, origin, Vector::zeros(), &rotation),
        ] {
            let residual = (&k * &r).norm() / (k.norm() * r.norm());
            prop_assert!(residual < tolerance, "|K r| = {residual:e}");
        }
        let singular_values = k.singular_values();
        let largest = singular_values.max();
        let rank = singular_values.iter().filter(|&&s| s > 1e-10 * largest).count();
        prop_assert_eq!(rank, 2 * n - 3);
        // Consistency (3.1): K p_I = boundary load of sigma(p) nu (half of |e| sigma nu to each end).
        let m = Matrix2::from_row_slice(&gradient);
        let p_i = linear_field(&polygon, origin, Vector::new(0.3, -0.2), &m);
        let strain = nalgebra::Vector3::new(m[(0, 0)], m[(1, 1)], m[(0, 1)] + m[(1, 0)]);
        let sigma = material.stress(&strain);
        let s = Matrix2::new(sigma[0], sigma[2], sigma[2], sigma[1]);
        let mut expected = DVector::zeros(2 * n);
        for e in 0..n {
            let (a, b) = (polygon[e], polygon[(e + 1) % n]);
            let half = s * Vector::new(b.y - a.y, a.x - b.x) * 0.5;
            for v in [e, (e + 1) % n] {
                expected[2 * v] += half.x;
                expected[2 * v + 1] += half.y;
            }
        }
        let error = (&k * &p_i - &expected).norm() / (k.norm() * p_i.norm());
        prop_assert!(error < tolerance, "(3.1) error {error:e}");
        // The stabilisation does not see linear fields.
        let stab = (&local.stabilisation * &p_i).norm() / (k.norm() * p_i.norm());
        prop_assert!(stab < tolerance, "|S p| = {stab:e}");
    }

    #[test]
    fn vem_equals_p1_on_random_triangles(
        polygon in star_shaped(3..=3),
        material in isotropic(),
        stabilisation in stabilisation(),
    ) {
        let element = LowestOrderVem::new(stabilisation).unwrap();
        let vem = element.stiffness(&polygon, &material).unwrap().total();
        let p1 = LinearTriangle.stiffness(&polygon, &material).unwrap().total();
        let difference = (&vem - &p1).norm() / p1.norm();
        prop_assert!(difference < 1e-13, "{difference:e}");
    }
}
