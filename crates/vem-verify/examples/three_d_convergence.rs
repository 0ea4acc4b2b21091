//! The convergence study in space: the exact solutions E1-3D (smooth, a traction side) and
//! E2-3D (divergence free) and the patch test PT0-3D on every polyhedral family, with the
//! lowest-order VEM; prints the runs and the fitted rates as Markdown (docs/convergence-3d.md).
//!
//! ```text
//! cargo run --release -p vem-verify --example three_d_convergence              # n = 4, 8, 16
//! cargo run --release -p vem-verify --example three_d_convergence -- 4,8,16,24 vem1-bbar
//! cargo run --release -p vem-verify --example three_d_convergence -- 8,16,32 vem1 tetrahedra,voronoi
//! ```
//!
//! Material: `lambda = 2`, `mu = 1` (the reference of docs/manufactured.md). Rates are fitted by
//! least squares over the three finest sizes.

use std::sync::Arc;

use vem_mesh::generators::polyhedral::PolyhedralFamily;
use vem_space::{BBar, DRecipe, DofiDofi, PolyhedralElement, PolyhedralVem, StabilisationScaling};
use vem_verify::exact::Lame;
use vem_verify::three_d::{
    solid_markdown, solid_rates, three_d_convergence, DivergenceFreeSolid, ExactSolution3d,
    LinearSolid, SmoothSolid,
};

fn element(name: &str) -> Result<Arc<dyn PolyhedralElement>, Box<dyn std::error::Error>> {
    Ok(Arc::new(match name {
        "vem1" => PolyhedralVem::default(),
        "vem1-shear" => {
            PolyhedralVem::try_new(Arc::new(DofiDofi::new(StabilisationScaling::ShearModulus)))?
        }
        "vem1-drecipe" => PolyhedralVem::try_new(Arc::new(DRecipe))?,
        "vem1-bbar" => PolyhedralVem::try_new(Arc::new(BBar))?,
        other => return Err(format!("unknown element {other:?}").into()),
    }))
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
    let element = element(args.get(1).map_or("vem1", String::as_str))?;
    let lame = Lame::REFERENCE;
    let cases: Vec<Arc<dyn ExactSolution3d>> = vec![
        Arc::new(SmoothSolid::new(lame)),
        Arc::new(DivergenceFreeSolid::new(lame)),
    ];
    let families: Vec<PolyhedralFamily> = match args.get(2) {
        Some(list) => list
            .split(',')
            .map(|s| s.parse())
            .collect::<Result<_, _>>()?,
        None => PolyhedralFamily::all().to_vec(),
    };
    let runs = three_d_convergence(&cases, &families, &sizes, Arc::clone(&element))?;
    let rates = solid_rates(&runs, 3);
    println!("{}", solid_markdown(&runs, &rates));
    // The patch test at the finest size on every family.
    let patch: Vec<Arc<dyn ExactSolution3d>> = vec![Arc::new(LinearSolid::new(lame))];
    let finest = [*sizes.last().expect("at least one size")];
    println!("| family | n | cells | PT0-3D relative nodal error | E_grad / abs1 |");
    println!("|---|---:|---:|---:|---:|");
    for run in three_d_convergence(&patch, &families, &finest, element)? {
        println!(
            "| {} | {} | {} | {:.1e} | {:.1e} |",
            run.family,
            run.n,
            run.cells,
            run.nodal_error,
            run.errors.relative_grad()
        );
    }
    Ok(())
}
