//! A user-defined exact solution: implement [`ExactSolution`] for your own field and hand it to
//! the same tools as the built-in cases.
//!
//! The field is the quadratic `u = (x^2, x y)/10` on the unit square, clamped on the left side
//! (where it vanishes) with tractions `sigma nu` on the other three sides. Its gradient is
//! `[x/5, 0; y/10, x/10]`, `div u = 3x/10`, and the body force
//! `f = -(mu Laplace u + (lambda + mu) grad div u) = (-(3 lambda + 5 mu)/10, 0)` is constant.
//!
//! The example prints the field and its data at a few points, checks the equilibrium by finite
//! differences, then runs a convergence study of the VEM on Voronoi meshes against it (rates
//! 1 in energy, 2 in L2 expected).
//!
//! Run with `cargo run --release -p vem-verify --example custom_solution`.

use std::sync::Arc;

use nalgebra::Matrix2;
use vem_mesh::generators::{MeshFamily, Rectangle};
use vem_mesh::{Point, Vector};
use vem_verify::exact::{BodyId, ExactSolution, Lame, Side};
use vem_verify::report::study_markdown;
use vem_verify::study::{MeshPairing, Study};

/// `u = (x^2, x y)/10` on `(0,1)^2`.
struct QuadraticField {
    lame: Lame,
}

impl ExactSolution for QuadraticField {
    fn name(&self) -> &str {
        "quadratic"
    }

    fn lame(&self) -> Lame {
        self.lame
    }

    fn bodies(&self) -> &'static [BodyId] {
        &BodyId::SINGLE
    }

    fn domain(&self, _body: BodyId) -> Rectangle {
        Rectangle::unit_square()
    }

    fn displacement(&self, _body: BodyId, x: Point) -> Vector {
        Vector::new(x.x * x.x, x.x * x.y) / 10.0
    }

    fn gradient(&self, _body: BodyId, x: Point) -> Matrix2<f64> {
        Matrix2::new(x.x / 5.0, 0.0, x.y / 10.0, x.x / 10.0)
    }

    fn body_force(&self, _body: BodyId, _x: Point) -> Vector {
        let (lambda, mu) = (self.lame.lambda(), self.lame.mu());
        Vector::new(-(3.0 * lambda + 5.0 * mu) / 10.0, 0.0)
    }

    fn dirichlet_sides(&self, _body: BodyId) -> Vec<Side> {
        vec![Side::Left]
    }

    fn neumann_sides(&self, _body: BodyId) -> Vec<Side> {
        vec![Side::Right, Side::Bottom, Side::Top]
    }
    // `stress` and `traction` come from the defaults (Lamé law, sigma nu); `contact` is `None`.
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let solution = QuadraticField {
        lame: Lame::try_new(2.0, 1.0)?,
    };
    let body = BodyId::One;
    println!("exact solution {:?}", solution.name());
    for x in [
        Point::new(0.25, 0.5),
        Point::new(0.5, 0.5),
        Point::new(0.9, 0.1),
    ] {
        let u = solution.displacement(body, x);
        let s = solution.stress(body, x);
        let f = solution.body_force(body, x);
        println!(
            "  at ({:.2}, {:.2}): u = ({:+.5}, {:+.5})  sigma = [{:+.4}, {:+.4}; {:+.4}]  f = ({:+.3}, {:+.3})",
            x.x, x.y, u.x, u.y, s[(0, 0)], s[(0, 1)], s[(1, 1)], f.x, f.y
        );
    }
    for side in solution.neumann_sides(body) {
        let [a, b] = side.end_points(&solution.domain(body));
        let midpoint = Point::from((a.coords + b.coords) / 2.0);
        let g = solution.traction(body, side, midpoint);
        println!(
            "  traction on {:>6} at its midpoint: ({:+.4}, {:+.4})",
            side.name(),
            g.x,
            g.y
        );
    }

    // The body force must balance the stress: -div sigma = f, here by central differences.
    let (x, h) = (Point::new(0.4, 0.6), 1e-5);
    let s = |dx: f64, dy: f64| solution.stress(body, x + Vector::new(dx, dy));
    let div = Vector::new(
        (s(h, 0.0)[(0, 0)] - s(-h, 0.0)[(0, 0)] + s(0.0, h)[(0, 1)] - s(0.0, -h)[(0, 1)])
            / (2.0 * h),
        (s(h, 0.0)[(1, 0)] - s(-h, 0.0)[(1, 0)] + s(0.0, h)[(1, 1)] - s(0.0, -h)[(1, 1)])
            / (2.0 * h),
    );
    let residual = (div + solution.body_force(body, x)).amax();
    println!("  |div sigma + f| by finite differences at (0.4, 0.6): {residual:.1e}");

    // The convergence-study runner takes any `ExactSolution`: it meshes `domain(body)` with a
    // family of `vem_mesh`, clamps the `dirichlet_sides` with `displacement`, loads the
    // `neumann_sides` with `traction` and the body with `body_force`, and measures the errors
    // against `displacement` and `gradient`, exactly as for the built-in cases M1..PTC3.
    let as_trait_object: &dyn ExactSolution = &solution;
    assert!(as_trait_object.contact().is_none());
    let result = Study::new(Arc::new(solution), MeshPairing::single(MeshFamily::Voronoi))
        .sizes([4, 8, 16, 32])
        .run()?;
    println!("\n{}", study_markdown(&result));
    if !result.verdict.passed {
        return Err(format!("the study falls short: {:?}", result.verdict.shortfalls).into());
    }
    Ok(())
}
