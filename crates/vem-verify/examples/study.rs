//! A convergence study of one built-in case on one mesh pairing, printed as a Markdown table.
//!
//! ```text
//! cargo run --release -p vem-verify --example study -- [CASE] [PAIRING] [SIZES] [SOLVER]
//! cargo run --release -p vem-verify --example study -- M1 quads/quads*3 4,8,16,32
//! cargo run --release -p vem-verify --example study -- E1 voronoi 8,16,32,64
//! ```
//!
//! CASE is one of M1..M4, E1, E2, PT0a, PT0b, PTC1, PTC1h, PTC2, PTC3 (default M1); PAIRING is
//! `family[*factor]` per body separated by `/` (default: quads for every body); SIZES a
//! comma-separated list (default 4,8,16,32); SOLVER a name of the solver registry (exact,
//! penalty, active-set; default exact). For the full study of the project run `cargo xtask convergence`.

use std::sync::Arc;

use vem_contact::SolverRegistry;
use vem_mesh::generators::MeshFamily;
use vem_verify::exact::{case_by_name, Lame};
use vem_verify::report::study_markdown;
use vem_verify::study::{same_family, MeshPairing, Study};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let case: Arc<_> =
        case_by_name(args.first().map_or("M1", String::as_str), Lame::default())?.into();
    let pairing: MeshPairing = match args.get(1) {
        Some(text) => text.parse()?,
        None => same_family(&*case, MeshFamily::Quads),
    };
    let sizes: Vec<usize> = match args.get(2) {
        Some(text) => text
            .split(',')
            .map(|s| s.trim().parse())
            .collect::<Result<_, _>>()?,
        None => Study::DEFAULT_SIZES.to_vec(),
    };
    let solver = args.get(3).map_or(SolverRegistry::DEFAULT, String::as_str);
    let study = Study::new(case, pairing).sizes(sizes).solver(solver);
    eprintln!("{} ...", study.title());
    let result = study.run_with(|record| {
        eprintln!(
            "  n = {:?}: h = {:.4}, {} DOFs, E_grad = {:.3e}, E_a = {:.3e}, E_0 = {:.3e}, \
             times mesh/assembly/solve/errors = {:.2}/{:.2}/{:.2}/{:.2} s",
            record.n,
            record.h,
            record.dofs,
            record.errors.grad,
            record.errors.energy,
            record.errors.l2,
            record.times.mesh,
            record.times.assembly,
            record.times.solve,
            record.times.errors,
        );
    })?;
    println!("{}", study_markdown(&result));
    Ok(())
}
