//! Interface node insertion without misfit: the contact patch test PTC1 is exact to round-off
//! on every pairing of the seven mesh families, at size ratios 1:1 to 1:7 either way round,
//! with the lower mesh's nodes shifted along the interface by random amounts (from 1e-7, which
//! makes nodes nearly coincide and snap, to 1e-1), and no interface edge is shorter than the
//! snapping fraction allows.

#[path = "support/interface_patch.rs"]
mod support;

use proptest::prelude::*;
use vem_mesh::generators::MeshFamily;
use vem_mesh::interface::InterfaceOptions;

use support::{run, Pairing};

fn family() -> impl Strategy<Value = MeshFamily> {
    (0..7usize).prop_map(|k| MeshFamily::all()[k])
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 40, ..ProptestConfig::default() })]

    #[test]
    fn ptc1_is_exact_on_every_pairing(
        upper in family(),
        lower in family(),
        ratio in 1usize..=7,
        upper_finer in any::<bool>(),
        seed in 0u64..1000,
        exponent in -7.0f64..-1.0,
        negative in any::<bool>(),
    ) {
        let coarse = 2;
        let (n_upper, n_lower) = if upper_finer {
            (coarse * ratio, coarse)
        } else {
            (coarse, coarse * ratio)
        };
        let magnitude = 10f64.powf(exponent);
        let shift = if negative { -magnitude } else { magnitude };
        let pairing = Pairing { upper, lower, n_upper, n_lower, seed, shift };
        let options = InterfaceOptions::default();
        let outcome = run(&pairing, options).map_err(|e| TestCaseError::fail(format!("{pairing:?}: {e}")))?;
        prop_assert!(outcome.error < 1e-10, "{pairing:?}: error {:e}", outcome.error);
        // Insertion leaves no interface edge shorter than the snapping fraction of the edge
        // it cuts, nor than the meshes' own interface edges: at least that fraction of the
        // shortest of them, relative to the polygon's diameter.
        let floor = options.min_edge_fraction() * outcome.shortest_fraction_before;
        prop_assert!(
            outcome.shortest_fraction >= floor * (1.0 - 1e-9),
            "{pairing:?}: shortest {:e} below {floor:e}", outcome.shortest_fraction
        );
    }
}
