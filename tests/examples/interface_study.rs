//! Interface insertion study: the contact patch test PTC1 on every pairing of the seven mesh
//! families at size ratios 1:1, 1:3 and 1:7 (both ways round) with the lower mesh's nodes
//! shifted along the interface by 1e-6, 1e-4 (near coincidences: snapping) and 0.05, with and
//! without aligning snapped nodes. Prints the largest patch-test error and the shortest
//! interface edge over its polygon's diameter (before insertion: the meshes' own).
//!
//! `cargo run --release -p vem-integration-tests --example interface_study [MIN_EDGE_FRACTION]`
//! (default: the default `min_edge_fraction` of `InterfaceOptions`).

#[path = "../tests/support/interface_patch.rs"]
mod support;

use vem_mesh::generators::MeshFamily;
use vem_mesh::interface::InterfaceOptions;

use support::{run, Pairing};

fn main() {
    let coarse = 2;
    let fraction = match std::env::args().nth(1).map(|a| a.parse::<f64>()) {
        None => InterfaceOptions::default().min_edge_fraction(),
        Some(Ok(value)) => value,
        Some(Err(e)) => {
            eprintln!("MIN_EDGE_FRACTION: {e}");
            std::process::exit(2);
        }
    };
    for align in [false, true] {
        let options = match InterfaceOptions::builder()
            .align_snapped_nodes(align)
            .min_edge_fraction(fraction)
            .build()
        {
            Ok(options) => options,
            Err(e) => {
                eprintln!("{e}");
                std::process::exit(2);
            }
        };
        println!("min_edge_fraction = {fraction}");
        let (mut worst, mut shortest, mut shortest_before) = (0.0f64, f64::INFINITY, f64::INFINITY);
        let (mut runs, mut failures) = (0, 0);
        let mut worst_case = None;
        for upper in MeshFamily::all() {
            for lower in MeshFamily::all() {
                for ratio in [1, 3, 7] {
                    for upper_finer in [false, true] {
                        for shift in [1e-6, 1e-4, 0.05] {
                            let (n_upper, n_lower) = if upper_finer {
                                (coarse * ratio, coarse)
                            } else {
                                (coarse, coarse * ratio)
                            };
                            let pairing = Pairing {
                                upper,
                                lower,
                                n_upper,
                                n_lower,
                                seed: 3,
                                shift,
                            };
                            runs += 1;
                            match run(&pairing, options) {
                                Ok(outcome) => {
                                    if outcome.error > worst {
                                        worst = outcome.error;
                                        worst_case = Some(pairing);
                                    }
                                    shortest = shortest.min(outcome.shortest_fraction);
                                    shortest_before =
                                        shortest_before.min(outcome.shortest_fraction_before);
                                }
                                Err(e) => {
                                    failures += 1;
                                    eprintln!("{pairing:?}: {e}");
                                }
                            }
                        }
                    }
                }
            }
        }
        println!(
            "align_snapped_nodes = {align}: {runs} runs, {failures} failed; largest PTC1 error \
             {worst:.2e} ({worst_case:?}); shortest interface edge / h_T {shortest:.2e} after \
             insertion ({shortest_before:.2e} on the meshes as generated)"
        );
    }
}
