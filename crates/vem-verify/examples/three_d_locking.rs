//! The locking study in space: E_grad and E_0 of the divergence-free solution E2-3D at Poisson's
//! ratio 0.3 and close to 1/2, for every stabilisation of the lowest-order VEM on polyhedra and
//! every polyhedral family. Printed as a Markdown table (docs/elements.md).
//!
//! ```text
//! cargo run --release -p vem-verify --example three_d_locking               # n = 4, 8, 16
//! cargo run --release -p vem-verify --example three_d_locking -- 4,8 hexahedra,voronoi
//! ```
//!
//! Material: `mu = 1`, `lambda = 2 nu / (1 - 2 nu)`; nu = 0.49999 is `lambda/mu = 5e4`,
//! nu = 0.4999995 is `1e6`. E2-3D does not depend on lambda, so any growth of the error with
//! lambda is locking. Rates are fitted over the sizes given; the ratios divide the finest-size
//! error at each nu by the one at nu = 0.3.

use std::sync::Arc;

use vem_mesh::generators::polyhedral::PolyhedralFamily;
use vem_space::{
    BBar, DRecipe, DofiDofi, PolyhedralElement, PolyhedralStabilisation, PolyhedralVem,
    StabilisationScaling,
};
use vem_verify::exact::Lame;
use vem_verify::three_d::{solid_rates, three_d_convergence, DivergenceFreeSolid, SolidRates};

/// Poisson's ratios; the first is the reference of the ratios.
const RATIOS: [f64; 3] = [0.3, 0.49999, 0.4999995];

fn elements() -> Result<Vec<Arc<dyn PolyhedralElement>>, Box<dyn std::error::Error>> {
    let stabilisations: Vec<Arc<dyn PolyhedralStabilisation>> = vec![
        Arc::new(DofiDofi::default()),
        Arc::new(DofiDofi::new(StabilisationScaling::ShearModulus)),
        Arc::new(DRecipe),
        Arc::new(BBar),
    ];
    let mut elements: Vec<Arc<dyn PolyhedralElement>> = Vec::new();
    for s in stabilisations {
        elements.push(Arc::new(PolyhedralVem::try_new(s)?));
    }
    Ok(elements)
}

fn series(
    family: PolyhedralFamily,
    element: &Arc<dyn PolyhedralElement>,
    nu: f64,
    sizes: &[usize],
) -> Result<SolidRates, Box<dyn std::error::Error>> {
    let lame = Lame::try_new(2.0 * nu / (1.0 - 2.0 * nu), 1.0)?;
    let runs = three_d_convergence(
        &[Arc::new(DivergenceFreeSolid::new(lame))],
        &[family],
        sizes,
        Arc::clone(element),
    )?;
    Ok(solid_rates(&runs, sizes.len()).remove(0))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let sizes: Vec<usize> = match args.first() {
        Some(list) => list
            .split(',')
            .map(|s| s.parse())
            .collect::<Result<_, _>>()?,
        None => vec![4, 8, 16],
    };
    let families: Vec<PolyhedralFamily> = match args.get(1) {
        Some(list) => list
            .split(',')
            .map(|s| s.parse())
            .collect::<Result<_, _>>()?,
        None => PolyhedralFamily::all().to_vec(),
    };
    let show = |r: Option<f64>| r.map_or("-".to_string(), |r| format!("{r:.2}"));
    println!(
        "| family | element | E_grad, E_0 at nu = 0.3 | rates at 0.3 | E_grad ratio 0.49999 / 0.4999995 | E_0 ratio 0.49999 / 0.4999995 | rates at 0.4999995 |"
    );
    println!("|---|---|---|---|---|---|---|");
    for family in families {
        for element in elements()? {
            let [reference, nearly, limit] = [
                series(family, &element, RATIOS[0], &sizes)?,
                series(family, &element, RATIOS[1], &sizes)?,
                series(family, &element, RATIOS[2], &sizes)?,
            ];
            println!(
                "| {} | {} | {:.3e}, {:.3e} | {}, {} | {:.2} / {:.2} | {:.2} / {:.2} | {}, {} |",
                family.name(),
                element.name(),
                reference.finest.grad,
                reference.finest.l2,
                show(reference.grad_rate),
                show(reference.l2_rate),
                nearly.finest.grad / reference.finest.grad,
                limit.finest.grad / reference.finest.grad,
                nearly.finest.l2 / reference.finest.l2,
                limit.finest.l2 / reference.finest.l2,
                show(limit.grad_rate),
                show(limit.l2_rate),
            );
        }
    }
    Ok(())
}
