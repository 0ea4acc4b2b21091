//! The rows of `cargo xtask extremes` at a small size: every solver at the extremes must give the
//! expected answer (an exact patch-test field, an invariance) or a clear error or warning, never
//! a wrong answer reported as converged; and the default solver must give the expected answer
//! wherever it does today.

use vem_contact::SolverRegistry;
use vem_verify::extremes::{self as rows, Row, Size, Verdict};

/// Runs `group` at the test size and checks: no outcome is a wrong "converged"; the default
/// solver passes every row but those whose name contains one of `default_may_refuse` (there it
/// must refuse with an error); rows whose name contains one of `all_pass` pass for every solver.
fn check(group: rows::Group, default_may_refuse: &[&str], all_pass: &[&str]) -> Vec<Row> {
    let rows = group(&Size::test());
    assert!(!rows.is_empty());
    let mut problems = Vec::new();
    for row in &rows {
        for outcome in &row.outcomes {
            let here = format!(
                "{} / {}: {} ({})",
                row.name,
                outcome.solver,
                outcome.verdict.word(),
                outcome.measured
            );
            if !outcome.verdict.is_honest() {
                problems.push(format!("wrong answer without error or warning: {here}"));
            }
            let exempt = default_may_refuse.iter().any(|n| row.name.contains(n));
            if outcome.solver == SolverRegistry::DEFAULT {
                let ok = outcome.verdict == Verdict::Pass
                    || (exempt && matches!(outcome.verdict, Verdict::Refused(_)));
                if !ok {
                    problems.push(format!("default solver: {here}"));
                }
            }
            if all_pass.iter().any(|n| row.name.contains(n)) && outcome.verdict != Verdict::Pass {
                problems.push(format!("expected to pass for every solver: {here}"));
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
    rows
}

#[test]
fn poisson_ratio_up_to_0_49999_patch_tests_exact_and_the_locking_free_elements_do_not_lock() {
    let rows = check(rows::poisson, &[], &["contact patch test"]);
    // Every registered element has its patch rows (a new element is one more registry entry).
    for element in vem_space::ElementRegistry::builtin().names() {
        let patch_rows = rows
            .iter()
            .filter(|r| {
                r.name
                    .starts_with(&format!("{element}: contact patch test"))
            })
            .count();
        assert_eq!(patch_rows, rows::POISSON_RATIOS.len() - 1, "{element}");
    }
    // The shear-modulus stabilisation and the locking-free element do not lock on E2, on any
    // polygonal family (errors at nu = 0.49999 within 2x of those at 0.3).
    for element in ["vem1-shear", "vem1-bbar"] {
        for family in ["quads", "voronoi", "hexagons", "nonconvex", "perturbed"] {
            let row = rows
                .iter()
                .find(|r| {
                    r.name
                        .starts_with(&format!("{element}: locking on E2, {family}"))
                })
                .unwrap_or_else(|| panic!("the {element} locking row on {family}"));
            assert_eq!(row.outcomes[0].verdict, Verdict::Pass, "{row:?}");
        }
    }
    // The trace-scaled default stabilisation locks at nu = 0.49999 (the measure sees it).
    let default = rows
        .iter()
        .find(|r| r.name.starts_with("vem1: locking on E2, quads"))
        .expect("the vem1 locking row");
    assert!(
        matches!(default.outcomes[0].verdict, Verdict::Warned(_)),
        "{default:?}"
    );
}

#[test]
fn near_incompressible_contact_the_default_choices_do_not_lock_and_the_others_say_so() {
    let rows = check(rows::incompressible_contact, &[], &[]);
    let row = |start: &str| {
        rows.iter()
            .find(|r| r.name.starts_with(start))
            .unwrap_or_else(|| panic!("the row '{start}'"))
    };
    // What the default chooses (vem1-bbar; with the edge midpoints on triangles) keeps E2c's
    // errors at nu = 0.4999 within 2x of those at 0.3 on the non-matching pairs, and the
    // Hertz scene's a and p0 within 3 % of theirs.
    for start in [
        "vem1-bbar: E2c contact on quads",
        "vem1-bbar: E2c contact on voronoi",
        "vem1-bbar with edge midpoints: E2c contact on triangles",
        "default element: Hertz scene",
    ] {
        assert_eq!(
            row(start).outcomes[0].verdict,
            Verdict::Pass,
            "{:?}",
            row(start)
        );
    }
    // The plain element locks on both, and the scene warns where a user forces it.
    for start in ["vem1: E2c contact on quads", "vem1: Hertz scene"] {
        assert!(
            matches!(row(start).outcomes[0].verdict, Verdict::Warned(_)),
            "{:?}",
            row(start)
        );
    }
}

#[test]
fn stiffness_contrasts_1e4_and_1e8_either_way() {
    check(rows::contrast, &[], &[]);
}

#[test]
fn lengths_and_moduli_scaled_change_no_answer() {
    check(rows::units, &[], &["M1", "M2"]);
}

#[test]
fn degenerate_cells_give_the_patch_field_or_a_clear_error() {
    // Tiny edges on a non-matching interface: the interface insertion refuses points closer
    // than 1e-3 of an edge (a clear error naming the points).
    let rows = check(
        rows::cells,
        &[
            "edges 1e-8 of the diameter, frictionless",
            "edges 1e-8 of the diameter, Tresca",
        ],
        &[],
    );
    assert!(rows.iter().any(|r| r.name.contains("slivers")));
    assert!(rows.iter().any(|r| r.name.contains("aspect ratio 1e9")));
}

#[test]
fn penalty_factors_1e0_to_1e14() {
    let rows = check(rows::penalty, &[], &[]);
    assert_eq!(rows.len(), 16);
    // The patch test's penalised answer is within 1/factor for every factor.
    for row in rows.iter().filter(|r| r.name.starts_with("penalty factor")) {
        assert_eq!(row.outcomes[0].verdict, Verdict::Pass, "{row:?}");
    }
}

#[test]
fn gaps_zero_tiny_touching_and_open() {
    let rows = check(rows::gaps, &[], &["gap 0", "gap 1e-12", "no contact"]);
    // Touching at zero load: the only forces on the lower body are round-off of the upper
    // body's; the default solver's answer is exact and passes its check at that floor (the
    // active set passes too on 6 cells and more; on 4 it stops at its iteration limit, an
    // error).
    let touching = rows
        .iter()
        .find(|r| r.name.starts_with("touching"))
        .expect("the touching row");
    for outcome in &touching.outcomes {
        if outcome.solver == SolverRegistry::DEFAULT {
            assert_eq!(outcome.verdict, Verdict::Pass, "{touching:?}");
        }
    }
}

#[test]
fn friction_bound_zero_is_frictionless_and_huge_is_tied() {
    check(rows::friction, &[], &["g_F = 0", "tied"]);
}

#[test]
fn in_space_the_locking_free_elements_do_not_lock_and_the_others_say_so() {
    // E2-3D at nu up to 0.49999 against 0.3: vem1-shear and vem1-bbar within 2x on hexahedra and
    // Voronoi cells. (Tetrahedra lock with every element - P1, the stabilisation vanishes - which
    // the full-size rows report as a warning; at this size the growth stays below 2x.)
    let rows = check(rows::solid_poisson, &[], &[]);
    for row in &rows {
        let verdict = &row.outcomes[0].verdict;
        let free = row.name.starts_with("vem1-shear") || row.name.starts_with("vem1-bbar");
        if free && !row.name.contains("tetrahedra") {
            assert_eq!(*verdict, Verdict::Pass, "{}: {:?}", row.name, row.outcomes);
        }
    }
}

#[test]
fn in_space_the_contact_patch_test_is_exact_at_the_extremes() {
    // Two stacked blocks on non-matching surfaces: the uniform uniaxial stress at stiffness
    // contrasts 1e+-8, lengths 1e+-6 and moduli 1e-9, nu = 0.49999, thin and warped cells. No
    // wrong answer reported as converged; the default solver gives the exact field everywhere
    // but on the flat tetrahedra of aspect 1e-6, where a warning names the element; every
    // solver passes the scaled units and the warped cells.
    let rows = rows::solid_contact(&Size::test());
    assert_eq!(rows.len(), 12);
    for row in &rows {
        for outcome in &row.outcomes {
            let here = format!("{} / {}: {}", row.name, outcome.solver, outcome.measured);
            assert!(outcome.verdict.is_honest(), "{here}");
            if outcome.solver == SolverRegistry::DEFAULT {
                let ok = outcome.verdict == Verdict::Pass
                    || (row.name.contains("1e-6 thin")
                        && matches!(outcome.verdict, Verdict::Warned(_)));
                assert!(ok, "default solver: {here}");
            }
            if row.name.contains("lengths x") || row.name.contains("perturbed") {
                assert_eq!(outcome.verdict, Verdict::Pass, "{here}");
            }
        }
    }
}

#[test]
fn friction_in_space_at_the_extremes_is_exact_or_refused() {
    // The sheared blocks (8 rows) for each of the six laws: Tresca and Coulomb with the bound 0,
    // half the stick shear and 1e8 p. No wrong answer reported as converged, and the default
    // solver gives the exact uniform state everywhere.
    let rows = rows::solid_friction(&Size::test());
    assert_eq!(rows.len(), 8 * 6);
    let mut problems = Vec::new();
    for row in &rows {
        for outcome in &row.outcomes {
            let here = format!(
                "{} / {}: {} ({})",
                row.name,
                outcome.solver,
                outcome.verdict.word(),
                outcome.measured
            );
            if !outcome.verdict.is_honest() {
                problems.push(format!("wrong answer without error or warning: {here}"));
            }
            if outcome.solver == SolverRegistry::DEFAULT && outcome.verdict != Verdict::Pass {
                problems.push(format!("default solver: {here}"));
            }
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}
