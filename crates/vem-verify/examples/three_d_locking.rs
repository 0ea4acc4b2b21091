//! The locking study in space: E_grad and E_0 of the divergence-free solution E2-3D at Poisson's
//! ratio 0.3 and close to 1/2, for every stabilisation of the lowest-order VEM on polyhedra and
//! every polyhedral family, on the meshes as generated and with the midpoint of every edge
//! inserted as a vertex (`PolyhedralMesh::with_edge_midpoints`, the cure of the tetrahedra).
//! Printed as a Markdown table (docs/elements.md).
//!
//! ```text
//! cargo run --release -p vem-verify --example three_d_locking               # n = 4, 8, 16
//! cargo run --release -p vem-verify --example three_d_locking -- 4,8 hexahedra,voronoi
//! cargo run --release -p vem-verify --example three_d_locking -- 2,4,8 tetrahedra midpoints
//! cargo run --release -p vem-verify --example three_d_locking -- 4,8,16 all plain
//! ```
//!
//! The first argument lists the sizes; the second the families (`all`, the default, for every
//! one); the third chooses the meshes: `plain` (as generated), `midpoints` (with the edge
//! midpoints) or both (`plain,midpoints`, the default); the fourth, if given, keeps only the
//! elements named (`vem1-bbar`, ...).
//!
//! Material: `mu = 1`, `lambda = 2 nu / (1 - 2 nu)`; nu = 0.49999 is `lambda/mu = 5e4`,
//! nu = 0.4999995 is `1e6`. E2-3D does not depend on lambda, so any growth of the error with
//! lambda is locking. Rates are fitted over the sizes given against the mean cell size
//! `(|Omega| / cells)^(1/3)` (the midpoints change no cell); the ratios divide the finest-size
//! error at each nu by the one at nu = 0.3.

use std::sync::Arc;

use vem_mesh::generators::polyhedral::{Cuboid, PolyhedralFamily};
use vem_space::{
    BBar, DRecipe, DofiDofi, PolyhedralElement, PolyhedralStabilisation, PolyhedralVem,
    StabilisationScaling,
};
use vem_verify::exact::Lame;
use vem_verify::norms::ErrorNorms;
use vem_verify::study::fitted_rate;
use vem_verify::three_d::{solve_solid, DivergenceFreeSolid, ExactSolution3d, SOLID_SEED};

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

/// The errors of one (family, element, nu) series at the finest size and their fitted rates.
struct Series {
    /// `E_grad` and `E_0` at the finest size.
    finest: ErrorNorms,
    /// Rate of `E_grad`.
    grad_rate: Option<f64>,
    /// Rate of `E_0`.
    l2_rate: Option<f64>,
}

fn series(
    family: PolyhedralFamily,
    midpoints: bool,
    element: &Arc<dyn PolyhedralElement>,
    nu: f64,
    sizes: &[usize],
) -> Result<Series, Box<dyn std::error::Error>> {
    let lame = Lame::try_new(2.0 * nu / (1.0 - 2.0 * nu), 1.0)?;
    let exact: Arc<dyn ExactSolution3d> = Arc::new(DivergenceFreeSolid::new(lame));
    let (mut spacing, mut errors) = (Vec::new(), Vec::new());
    for &n in sizes {
        let mut mesh = family.generate(&Cuboid::unit_cube(), n, SOLID_SEED)?;
        if midpoints {
            mesh = mesh.with_edge_midpoints()?;
        }
        spacing.push((1.0 / mesh.n_cells() as f64).cbrt());
        let (_, _, e) = solve_solid(Arc::clone(&exact), mesh, Arc::clone(element))?;
        errors.push(e);
    }
    let rate = |f: fn(&ErrorNorms) -> f64| {
        let e: Vec<f64> = errors.iter().map(f).collect();
        fitted_rate(&spacing, &e)
    };
    Ok(Series {
        finest: *errors.last().ok_or("no size given")?,
        grad_rate: rate(|e| e.grad),
        l2_rate: rate(|e| e.l2),
    })
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
        Some(list) if list != "all" => list
            .split(',')
            .map(|s| s.parse())
            .collect::<Result<_, _>>()?,
        _ => PolyhedralFamily::all().to_vec(),
    };
    let meshes: Vec<bool> = match args.get(2).map(String::as_str) {
        None | Some("plain,midpoints") | Some("midpoints,plain") => vec![false, true],
        Some("plain") => vec![false],
        Some("midpoints") => vec![true],
        Some(other) => {
            return Err(format!(
                "meshes '{other}': expected 'plain', 'midpoints' or 'plain,midpoints'"
            )
            .into())
        }
    };
    let only: Option<Vec<String>> = args
        .get(3)
        .map(|list| list.split(',').map(str::to_string).collect());
    let show = |r: Option<f64>| r.map_or("-".to_string(), |r| format!("{r:.2}"));
    println!(
        "| family | element | E_grad, E_0 at nu = 0.3 | rates at 0.3 | E_grad ratio 0.49999 / 0.4999995 | E_0 ratio 0.49999 / 0.4999995 | rates at 0.4999995 |"
    );
    println!("|---|---|---|---|---|---|---|");
    for family in families {
        for &midpoints in &meshes {
            for element in elements()? {
                if only
                    .as_ref()
                    .is_some_and(|only| !only.iter().any(|name| name == element.name()))
                {
                    continue;
                }
                let [reference, nearly, limit] = [
                    series(family, midpoints, &element, RATIOS[0], &sizes)?,
                    series(family, midpoints, &element, RATIOS[1], &sizes)?,
                    series(family, midpoints, &element, RATIOS[2], &sizes)?,
                ];
                println!(
                    "| {}{} | {} | {:.3e}, {:.3e} | {}, {} | {:.2} / {:.2} | {:.2} / {:.2} | {}, {} |",
                    family.name(),
                    if midpoints { " + midpoints" } else { "" },
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
    }
    Ok(())
}
