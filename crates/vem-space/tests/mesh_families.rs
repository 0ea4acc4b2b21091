//! Element-level patch-test companions (manufactured.md, PT0) on every polygon of a small mesh
//! of every generator family: rigid-motion kernel, rank 2n - 3, consistency (3.1), vanishing
//! stabilisation on P1, exact projection of a linear field, and the sum of the body loads.

use nalgebra::{DVector, Matrix2, Vector3};
use vem_mesh::generators::{MeshFamily, Rectangle};
use vem_space::{
    ElasticityTensor, ElementSpace, LinearTriangle, LowestOrderVem, Point, Stabilisation,
    StabilisationScaling, Vector,
};

#[test]
fn every_polygon_of_every_family_passes_the_element_patch_test() {
    let rect = Rectangle::new(Point::new(-0.5, 0.0), Point::new(1.5, 1.0));
    let material = ElasticityTensor::isotropic(2.0, 1.0).unwrap();
    let elements = [
        Stabilisation::default(),
        Stabilisation::dofi_dofi(StabilisationScaling::ShearModulus),
        Stabilisation::DRecipe,
    ]
    .map(|s| LowestOrderVem::new(s).unwrap());
    // p(x) = a + M x, M with a skew part, and its constant stress.
    let (a, m) = (Vector::new(0.1, -0.3), Matrix2::new(0.2, 0.5, -0.1, 0.4));
    let sigma = material.stress(&Vector3::new(m[(0, 0)], m[(1, 1)], m[(0, 1)] + m[(1, 0)]));
    let s = Matrix2::new(sigma[0], sigma[2], sigma[2], sigma[1]);
    let mut worst: f64 = 0.0;
    let mut polygons = 0;
    for family in MeshFamily::all() {
        let mesh = family.generate(&rect, 6, 11).unwrap();
        let mut total_load = Vector::zeros();
        for cell in 0..mesh.n_polygons() {
            let polygon = mesh.polygon_points(cell);
            let n = polygon.len();
            let p_i = DVector::from_fn(2 * n, |i, _| (a + m * polygon[i / 2].coords)[i % 2]);
            // Boundary load of sigma(p) nu, by hand: half of |e| sigma nu to each end point.
            let mut expected = DVector::zeros(2 * n);
            for e in 0..n {
                let (x0, x1) = (polygon[e], polygon[(e + 1) % n]);
                let half = s * Vector::new(x1.y - x0.y, x0.x - x1.x) * 0.5;
                for v in [e, (e + 1) % n] {
                    expected[2 * v] += half.x;
                    expected[2 * v + 1] += half.y;
                }
            }
            for element in &elements {
                let local = element.stiffness(&polygon, &material).unwrap();
                let k = local.total();
                let scale = k.norm();
                let rigid = [
                    DVector::from_fn(2 * n, |i, _| if i % 2 == 0 { 1.0 } else { 0.0 }),
                    DVector::from_fn(2 * n, |i, _| if i % 2 == 0 { 0.0 } else { 1.0 }),
                    DVector::from_fn(2 * n, |i, _| {
                        let x = polygon[i / 2];
                        if i % 2 == 0 {
                            -x.y
                        } else {
                            x.x
                        }
                    }),
                ];
                for r in &rigid {
                    let residual = (&k * r).norm() / (scale * r.norm());
                    assert!(residual < 1e-12, "{family} #{cell}: |K r| = {residual:e}");
                }
                let singular_values = k.singular_values();
                let largest = singular_values.max();
                let rank = singular_values
                    .iter()
                    .filter(|&&s| s > 1e-10 * largest)
                    .count();
                assert_eq!(rank, 2 * n - 3, "{family} #{cell}");
                let error = (&k * &p_i - &expected).norm() / (scale * p_i.norm());
                worst = worst.max(error);
                assert!(error < 1e-12, "{family} #{cell}: (3.1) error {error:e}");
                let stab = (&local.stabilisation * &p_i).norm() / (scale * p_i.norm());
                assert!(stab < 1e-12, "{family} #{cell}: |S p| = {stab:e}");
                if n == 3 {
                    let p1 = LinearTriangle
                        .stiffness(&polygon, &material)
                        .unwrap()
                        .total();
                    assert!((&k - &p1).norm() < 1e-13 * p1.norm(), "{family} #{cell}");
                }
            }
            let projection = elements[0].projection(&polygon).unwrap();
            assert!(
                (projection.gradient(&p_i) - m).norm() < 1e-13,
                "{family} #{cell}"
            );
            let load = elements[0]
                .body_load(&polygon, &|_| Vector::new(1.0, -2.0))
                .unwrap();
            total_load += Vector::new(
                load.iter().step_by(2).sum(),
                load.iter().skip(1).step_by(2).sum(),
            );
            polygons += 1;
        }
        // The loads of a constant f add up to |Omega| f (|Omega| = 2).
        assert!(
            (total_load - Vector::new(2.0, -4.0)).norm() < 1e-13,
            "{family}"
        );
    }
    println!("{polygons} polygons, worst relative consistency error {worst:e}");
}
