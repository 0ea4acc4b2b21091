//! The locking study: E_grad and E_0 of the divergence-free cases E2 (one body) and E2c (two
//! bodies in frictionless contact) at Poisson's ratio 0.3 and close to 1/2, for every built-in
//! stabilisation of the lowest-order VEM and every polygonal mesh family; and E1 at 0.3, where a
//! locking-free option must lose nothing. Printed as Markdown tables (docs/elements.md).
//!
//! ```text
//! cargo run --release -p vem-verify --example locking            # sizes 8,16,32,64
//! cargo run --release -p vem-verify --example locking -- 4,8,16  # other sizes
//! ```
//!
//! Material: `mu = 1`, `lambda = 2 nu / (1 - 2 nu)`; nu = 0.49999 is `lambda/mu = 5e4`,
//! nu = 0.4999995 is `lambda/mu = 1e6`. Rates are fitted over the three finest sizes; the
//! ratios divide the finest-size error at each nu by the one at nu = 0.3.

use std::sync::Arc;

use vem_contact::SolverRegistry;
use vem_mesh::generators::MeshFamily;
use vem_space::{ElementRegistry, Options};
use vem_verify::exact::{case_by_name, DivergenceFreeContact, ExactSolution, Lame};
use vem_verify::norms::ErrorNorms;
use vem_verify::problem::{DiscreteProblem, ProblemSettings};
use vem_verify::study::{fitted_rate, same_family, Study, StudyResult};

/// The elements compared.
const ELEMENTS: [&str; 4] = ["vem1", "vem1-shear", "vem1-drecipe", "vem1-bbar"];
/// Poisson's ratios; the first is the reference of the ratios.
const RATIOS: [f64; 3] = [0.3, 0.49999, 0.4999995];

fn families() -> [MeshFamily; 5] {
    [
        MeshFamily::Quads,
        MeshFamily::Voronoi,
        MeshFamily::Hexagons,
        MeshFamily::NonConvex,
        MeshFamily::PerturbedQuads {
            distortion: MeshFamily::DEFAULT_DISTORTION,
        },
    ]
}

fn lame(nu: f64) -> Result<Lame, Box<dyn std::error::Error>> {
    Ok(Lame::try_new(2.0 * nu / (1.0 - 2.0 * nu), 1.0)?)
}

fn case(name: &str, lame: Lame) -> Result<Arc<dyn ExactSolution>, Box<dyn std::error::Error>> {
    Ok(match name {
        "E2c" => Arc::new(DivergenceFreeContact::new(lame)),
        other => case_by_name(other, lame)?.into(),
    })
}

fn study(
    name: &str,
    family: MeshFamily,
    element: &str,
    nu: f64,
    sizes: &[usize],
) -> Result<StudyResult, Box<dyn std::error::Error>> {
    let exact = case(name, lame(nu)?)?;
    let pairing = same_family(&*exact, family);
    Ok(Study::new(exact, pairing)
        .sizes(sizes.to_vec())
        .element(ElementRegistry::builtin().make(element)?)
        .run()?)
}

/// The errors at the finest size and the fitted rates of `E_grad` and `E_0`.
type Measured = (ErrorNorms, Option<f64>, Option<f64>);

/// The result of a run of this example.
type Outcome<T> = Result<T, Box<dyn std::error::Error>>;

/// E2 on `family` with every edge's midpoint inserted: (E_grad, E_0) at the finest size and the
/// fitted rates.
fn midpoint_study(
    family: MeshFamily,
    element: &str,
    nu: f64,
    sizes: &[usize],
) -> Outcome<Measured> {
    let exact = case("E2", lame(nu)?)?;
    let settings = ProblemSettings::builder()
        .element(ElementRegistry::builtin().make(element)?)
        .build()?;
    let (mut h, mut grad, mut l2, mut finest) = (vec![], vec![], vec![], ErrorNorms::default());
    for &n in sizes {
        let mesh = family.generate(
            &exact.domain(vem_verify::exact::BodyId::One),
            n,
            Study::DEFAULT_SEED,
        )?;
        let problem = DiscreteProblem::try_new(
            Arc::clone(&exact),
            vec![mesh.with_edge_midpoints()?],
            &settings,
        )?;
        let mut solver =
            SolverRegistry::builtin().make(SolverRegistry::DEFAULT, &Options::new())?;
        let solution = problem.solve(&mut *solver)?;
        finest = ErrorNorms::combine(&solution.errors(&*exact)?);
        h.push(problem.mesh_size());
        grad.push(finest.grad);
        l2.push(finest.l2);
    }
    let last = sizes.len().saturating_sub(3);
    Ok((
        finest,
        fitted_rate(&h[last..], &grad[last..]),
        fitted_rate(&h[last..], &l2[last..]),
    ))
}

fn rate(r: Option<f64>) -> String {
    r.map_or("-".into(), |r| format!("{r:.2}"))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let sizes: Vec<usize> = match std::env::args().nth(1) {
        Some(text) => text
            .split(',')
            .map(|s| s.trim().parse())
            .collect::<Result<_, _>>()?,
        None => vec![8, 16, 32, 64],
    };
    println!("sizes n = {sizes:?}\n");
    println!(
        "| case | family | element | E_grad, E_0 at nu = 0.3 | rates at 0.3 | \
         E_grad ratio 0.49999 / 0.4999995 | E_0 ratio 0.49999 / 0.4999995 | rates at 0.4999995 |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for name in ["E2", "E2c"] {
        for family in families() {
            for element in ELEMENTS {
                let results = RATIOS
                    .iter()
                    .map(|&nu| study(name, family, element, nu, &sizes))
                    .collect::<Result<Vec<_>, _>>()?;
                let finest: Vec<_> = results
                    .iter()
                    .map(|r| r.finest().map(|f| f.errors).unwrap_or_default())
                    .collect();
                let (reference, last) = (&finest[0], &results[RATIOS.len() - 1]);
                let ratios = |f: fn(&vem_verify::norms::ErrorNorms) -> f64| {
                    finest[1..]
                        .iter()
                        .map(|e| format!("{:.2}", f(e) / f(reference)))
                        .collect::<Vec<_>>()
                        .join(" / ")
                };
                println!(
                    "| {name} | {} | {element} | {:.3e}, {:.3e} | {}, {} | {} | {} | {}, {} |",
                    family.name(),
                    reference.grad,
                    reference.l2,
                    rate(results[0].rates.grad),
                    rate(results[0].rates.l2),
                    ratios(|e| e.grad),
                    ratios(|e| e.l2),
                    rate(last.rates.grad),
                    rate(last.rates.l2),
                );
            }
        }
    }
    println!(
        "\nE1 at nu = 0.3 (lambda = 1.5, mu = 1): errors at the finest size, rates; and the \
         ratio of the errors at nu = 0.49999 to those (not a locking test: div u = O(1))\n"
    );
    println!("| family | element | E_grad | E_0 | rates | E_grad, E_0 ratio at 0.49999 |");
    println!("|---|---|---|---|---|---|");
    for family in families() {
        for element in ELEMENTS {
            let result = study("E1", family, element, 0.3, &sizes)?;
            let errors = result.finest().map(|f| f.errors).unwrap_or_default();
            let stiff = study("E1", family, element, 0.49999, &sizes)?;
            let stiff = stiff.finest().map(|f| f.errors).unwrap_or_default();
            println!(
                "| {} | {element} | {:.4e} | {:.4e} | {}, {} | {:.1}, {:.1} |",
                family.name(),
                errors.grad,
                errors.l2,
                rate(result.rates.grad),
                rate(result.rates.l2),
                stiff.grad / errors.grad,
                stiff.l2 / errors.l2,
            );
        }
    }
    println!(
        "\nE2 with the midpoint of every edge inserted as a vertex (vem1-bbar), against the \
         vertices alone\n"
    );
    println!("| family | vertices | E_grad, E_0 at nu = 0.3 | E_grad, E_0 ratio at 0.4999995 | rates at 0.4999995 |");
    println!("|---|---|---|---|---|");
    for family in [
        MeshFamily::Triangles,
        MeshFamily::Quads,
        MeshFamily::Voronoi,
    ] {
        for midpoints in [false, true] {
            let run = |nu: f64| -> Outcome<Measured> {
                if midpoints {
                    midpoint_study(family, "vem1-bbar", nu, &sizes)
                } else {
                    let r = study("E2", family, "vem1-bbar", nu, &sizes)?;
                    Ok((
                        r.finest().map(|f| f.errors).unwrap_or_default(),
                        r.rates.grad,
                        r.rates.l2,
                    ))
                }
            };
            let (moderate, _, _) = run(0.3)?;
            let (stiff, rate_grad, rate_l2) = run(0.4999995)?;
            println!(
                "| {} | {} | {:.3e}, {:.3e} | {:.2}, {:.2} | {}, {} |",
                family.name(),
                if midpoints {
                    "+ edge midpoints"
                } else {
                    "mesh vertices"
                },
                moderate.grad,
                moderate.l2,
                stiff.grad / moderate.grad,
                stiff.l2 / moderate.l2,
                rate(rate_grad),
                rate(rate_l2),
            );
        }
    }
    Ok(())
}
