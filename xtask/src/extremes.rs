//! `cargo xtask extremes`: numerical stability at the extremes. Every row (Poisson ratio up to
//! 0.49999, stiffness contrasts, units, degenerate cells, penalty factors, gaps, friction
//! bounds; in the plane and in space) is solved by every registered solver and judged against
//! an independent expected answer; the report goes to `target/extremes/extremes.md`
//! (`--out docs/extremes.md` for the tracked one). The rows themselves, with their expected
//! answers, are in `vem_verify::extremes`, shared with the workspace test
//! `tests/tests/extremes.rs`.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use vem_verify::report::write_text;

use vem_verify::extremes::{self as rows, Row, Size, Verdict};

/// Options of `cargo xtask extremes`.
#[derive(Debug, Args)]
pub struct ExtremesArgs {
    /// Smaller meshes and fewer mesh families in the locking study (under a minute, for CI).
    #[arg(long)]
    quick: bool,
    /// The Markdown report (`--out docs/extremes.md` regenerates the tracked one).
    #[arg(long, default_value = "target/extremes/extremes.md")]
    out: PathBuf,
    /// Only the solvers named (registry names: condensed, exact, penalty, active-set);
    /// repeatable. Default: every registered solver.
    #[arg(long = "solver", value_name = "SOLVER")]
    solvers: Vec<String>,
}

/// Runs the rows, writes the report; `Ok(false)` when an answer was wrong without an error or
/// a warning (a wrong "converged").
pub fn run(args: &ExtremesArgs) -> Result<bool, Box<dyn std::error::Error>> {
    let mut size = Size::new(args.quick);
    if !args.solvers.is_empty() {
        let known = rows::solver_names();
        if let Some(unknown) = args.solvers.iter().find(|s| !known.contains(s)) {
            return Err(format!("unknown solver '{unknown}'; known: {}", known.join(", ")).into());
        }
        size.solvers = args.solvers.clone();
    }
    let start = Instant::now();
    let mut all = Vec::new();
    let friction: (&str, rows::Group) =
        ("In space: friction at the extremes", rows::solid_friction);
    for (title, group) in rows::groups().into_iter().chain([friction]) {
        let t = Instant::now();
        let rows = group(&size);
        eprintln!(
            "{title}: {} rows in {:.1} s",
            rows.len(),
            t.elapsed().as_secs_f64()
        );
        all.push((title, rows));
    }
    let elapsed = start.elapsed().as_secs_f64();
    let markdown = report(&all, &size, args.quick, elapsed);
    if let Some(dir) = args.out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)
            .map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    }
    write_text(&args.out, &markdown)?;
    let count = |f: &dyn Fn(&Verdict) -> bool| {
        all.iter()
            .flat_map(|(_, rows)| rows.iter().flat_map(|r| &r.outcomes))
            .filter(|o| f(&o.verdict))
            .count()
    };
    let wrong = count(&|v| matches!(v, Verdict::Wrong));
    eprintln!(
        "{} outcomes: {} pass, {} refused, {} warned, {wrong} wrong without a warning; \
         {elapsed:.1} s; report: {}",
        count(&|_| true),
        count(&|v| matches!(v, Verdict::Pass)),
        count(&|v| matches!(v, Verdict::Refused(_))),
        count(&|v| matches!(v, Verdict::Warned(_))),
        args.out.display()
    );
    Ok(wrong == 0)
}

/// What the report says before the tables.
const INTRODUCTION: &str = r#"# Stability at the extremes

Written by `cargo xtask extremes` (`--quick`: smaller meshes, in CI). Every row is an extreme
of the data, the mesh or a solver setting, solved by every registered contact solver and judged
against an expected answer that does not come from a solver:

- **Patch tests.** Body 1 = (0, 1) x (0, 1) above body 2 = (0, 1) x (-1, 0), uniform stress
  `[[sigma_xx_i, q], [q, -p]]` in body i with its own Lamé parameters, the matching linear
  displacement prescribed on body 1's top and body 2's bottom, the exact tractions on the
  lateral sides, the interface y = 0 in contact with the imposed gap equal to the exact normal
  jump (plus an opening for the open case). The lowest-order VEM reproduces linear fields on
  any mesh, so every nodal displacement and the normal resultant `p` are known exactly. Body
  2 has one cell more across than body 1, so interface nodes are inserted.
- **Invariances.** M1 (frictionless, contact then separation) and M2 (Tresca, stick then slip)
  with every length multiplied by `s` and both moduli by `m` (data transformed accordingly):
  displacements must be `s` times, nodal forces `s m` times those of the unscaled run.
  Tresca with `g_F = 0` must equal the frictionless solve of the same meshes.
- **Locking.** The divergence-free solution E2 at Poisson ratios 0.4 .. 0.49999 against 0.3
  (mu = 1, lambda = 2 nu / (1 - 2 nu), up to lambda/mu = 5e4): relative errors within 2x.
- **Near-incompressible contact.** The two-body divergence-free contact solution E2c on
  non-matching triangles, quadrilaterals and Voronoi cells at nu = 0.49, 0.499, 0.4999 against
  0.3, for every element (and `vem1-bbar` with edge midpoints on triangles, the default's
  choice there): relative errors within 2x. The shipped Hertz scene with nu changed on both
  bodies, with the default element and with `vem1` or `vem1-bbar` forced: the errors of the
  half-width and the peak pressure against plane-strain Hertz within 3 % of those at 0.3; an
  element that misses this must carry the scene's locking warning.
- **In space.** The divergence-free solution E2-3D on hexahedra, Voronoi cells and tetrahedra
  at nu = 0.49, 0.4999, 0.49999 against 0.3, for every element on polyhedra (and `vem1-bbar`
  on tetrahedra with edge midpoints, the default's choice there; one Cholesky solve each):
  relative errors within 2x. The contact patch test of two stacked blocks,
  `[0, 1]^2 x [0, 1]` on `[0, 1]^2 x [-0.5, 0]`, hexahedra on tetrahedra (non-matching: the
  surface overlay makes the interface node-to-node), rollers on the sides x = 0 and y = 0, the
  upper top moved down by d = 0.01: the uniform uniaxial stress `p = d / (h_1/E_1 + h_2/E_2)`
  and its linear displacement, exactly, at stiffness contrasts 1e+-8, lengths 1e+-6 and moduli
  1e-9, nu = 0.49999 (`vem1`, `vem1-bbar`), a lower block 1e-3 and 1e-6 thin (flat
  tetrahedra), and warped hexahedra on Voronoi cells. Friction in space: the same blocks
  pressed (d = 0.01) and sheared (the upper top moved by D = 0.004 along x), the exact
  displacements prescribed on the upper top and the lower bottom and the exact shear tractions
  on the sides x = 0, 1, so that the answer is the uniform state `sigma_zz = -p`,
  `sigma_xz = tau` with `tau` the stick shear `tau_s = D / (h_1/G_1 + h_2/G_2)` or the bound,
  and a uniform slip: Tresca and Coulomb with the bound 0 (free slip), `tau_s / 2` (slip) and
  `1e8 p` (stick), at the stiffness contrasts 1e+-8, lengths 1e+-6 and moduli 1e-9 (`nu = 0`:
  with lateral contraction the two blocks contract alike only for equal `nu / E`), and at
  nu = 0.49999 with `vem1-bbar` and equal moduli; nodal error and resultant errors exact.

Verdicts: **PASS** (the expected answer within the tolerance); **FAIL (refused: error)** (the
solver or the model building returned an error: no answer, but no wrong one);
**FAIL (warned)** (a wrong answer carrying a warning, or an element that locks);
**FAIL (wrong answer reported as converged)** (a wrong answer with neither; `cargo xtask
extremes` exits with status 1 when there is one). The penalty solver answers the penalised
problem: its rows expect an error below `1/factor` (default factor 1e3).

Each row is also a test of the workspace at a small size (`tests/tests/extremes.rs`).
"#;

fn report(groups: &[(&str, Vec<Row>)], size: &Size, quick: bool, elapsed: f64) -> String {
    let mut md = String::from(INTRODUCTION);
    let _ = writeln!(
        md,
        "\nRun: `cargo xtask extremes{}`; patch tests on {} cells across (body 2: one more), \
         M1/M2 on {} / {} quads, E2 on {} cells across ({}); solvers: {}; {elapsed:.0} s \
         (timings are of a shared machine).\n",
        if quick { " --quick" } else { "" },
        size.patch,
        size.manufactured,
        size.manufactured + size.manufactured / 2,
        size.locking,
        size.locking_families
            .iter()
            .map(|f| f.name())
            .collect::<Vec<_>>()
            .join(", "),
        size.solvers.join(", "),
    );
    let _ = writeln!(md, "## Summary\n");
    let _ = writeln!(
        md,
        "| group | rows | outcomes | pass | refused | warned | wrong |"
    );
    let _ = writeln!(md, "|---|---:|---:|---:|---:|---:|---:|");
    for (title, rows) in groups {
        let outcomes: Vec<&Verdict> = rows
            .iter()
            .flat_map(|r| r.outcomes.iter().map(|o| &o.verdict))
            .collect();
        let n = |f: fn(&Verdict) -> bool| outcomes.iter().filter(|v| f(v)).count();
        let _ = writeln!(
            md,
            "| {title} | {} | {} | {} | {} | {} | {} |",
            rows.len(),
            outcomes.len(),
            n(|v| matches!(v, Verdict::Pass)),
            n(|v| matches!(v, Verdict::Refused(_))),
            n(|v| matches!(v, Verdict::Warned(_))),
            n(|v| matches!(v, Verdict::Wrong)),
        );
    }
    let failing: Vec<(&Row, &rows::Outcome)> = groups
        .iter()
        .flat_map(|(_, rows)| rows)
        .flat_map(|r| r.outcomes.iter().map(move |o| (r, o)))
        .filter(|(_, o)| o.verdict != Verdict::Pass)
        .collect();
    let _ = writeln!(md, "\n## Rows that fail\n");
    if failing.is_empty() {
        let _ = writeln!(md, "None.");
    } else {
        let _ = writeln!(md, "| row | solver | verdict |");
        let _ = writeln!(md, "|---|---|---|");
        for (row, outcome) in failing {
            let _ = writeln!(
                md,
                "| {} | {} | {} |",
                row.name,
                outcome.solver,
                outcome.verdict.word()
            );
        }
    }
    for (title, rows) in groups {
        let _ = writeln!(md, "\n## {title}\n");
        let _ = writeln!(md, "| row | expected | solver | measured | verdict |");
        let _ = writeln!(md, "|---|---|---|---|---|");
        for row in rows {
            for (k, outcome) in row.outcomes.iter().enumerate() {
                let (name, expected) = if k == 0 {
                    (row.name.as_str(), row.expected.as_str())
                } else {
                    ("", "")
                };
                let _ = writeln!(
                    md,
                    "| {name} | {expected} | {} | {} | {} |",
                    outcome.solver,
                    cell(&outcome.measured),
                    outcome.verdict.word()
                );
            }
        }
    }
    md
}

/// A table cell: no line breaks or pipes, long messages cut.
fn cell(text: &str) -> String {
    let flat = text.replace(['\n', '|'], " ");
    if flat.chars().count() > 300 {
        let cut: String = flat.chars().take(300).collect();
        format!("{cut} ...")
    } else {
        flat
    }
}
