//! Element-level patch-test companions (docs/manufactured.md, PT0) on every polygon of a small mesh
//! of every generator family, by the element test kit: rigid-motion kernel, rank 2n - 3,
//! consistency (3.1), symmetry, element patch test (exact projection of linear fields,
//! vanishing stabilisation on them); P1 where the cells are triangles; and the sum of the body
//! loads.

use std::sync::Arc;

use vem_mesh::generators::{MeshFamily, Rectangle};
use vem_space::testkit::{ElementCheck, DEFAULT_TOLERANCE};
use vem_space::{
    BBar, DRecipe, DofiDofi, ElasticityTensor, ElementSpace, LinearTriangle, LowestOrderVem, Point,
    Stabilisation, StabilisationScaling, Vector,
};

#[test]
fn every_polygon_of_every_family_passes_the_element_patch_test() {
    let rect = Rectangle::new(Point::new(-0.5, 0.0), Point::new(1.5, 1.0));
    let material = ElasticityTensor::try_isotropic(2.0, 1.0).unwrap();
    let stabilisations: [Arc<dyn Stabilisation>; 4] = [
        Arc::new(DofiDofi::default()),
        Arc::new(DofiDofi::new(StabilisationScaling::ShearModulus)),
        Arc::new(DRecipe),
        Arc::new(BBar),
    ];
    let mut elements: Vec<Arc<dyn ElementSpace>> = stabilisations
        .into_iter()
        .map(|s| Arc::new(LowestOrderVem::try_new(s).unwrap()) as Arc<dyn ElementSpace>)
        .collect();
    elements.push(Arc::new(LinearTriangle));
    let mut worst: f64 = 0.0;
    let mut polygons = 0;
    for family in MeshFamily::all() {
        let mesh = family.generate(&rect, 6, 11).unwrap();
        let mut total_load = Vector::zeros();
        for cell in 0..mesh.n_polygons() {
            let polygon = mesh.polygon_points(cell);
            let name = format!("{family} #{cell}");
            for element in elements.iter().filter(|e| e.supports(polygon.len())) {
                let check = ElementCheck::run(&**element, &name, &polygon, &material).unwrap();
                let failures = check.failures(DEFAULT_TOLERANCE);
                assert!(failures.is_empty(), "{}: {failures:?}", element.name());
                worst = worst.max(check.worst_error());
            }
            if polygon.len() == 3 {
                let p1 = LinearTriangle
                    .stiffness(&polygon, &material)
                    .unwrap()
                    .total();
                let vem = elements[0].stiffness(&polygon, &material).unwrap().total();
                assert!((&vem - &p1).norm() < 1e-13 * p1.norm(), "{name}");
            }
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
    println!("{polygons} polygons, worst relative error of the kit's checks {worst:e}");
}
