//! `cargo xtask extremes`: numerical stability at the extremes. Every row (Poisson ratio up to
//! 0.49999, stiffness contrasts, units, degenerate cells, penalty factors, gaps, friction
//! bounds; in the plane and in space) is solved by every registered solver and judged against
//! an independent expected answer; the rows go to `extremes.json` and the report rendered from
//! it to `target/extremes/extremes.md` beside it (`--out docs/extremes.md` for the tracked
//! one; `--report-only` rewrites the report from the JSON without solving). The rows
//! themselves, with their expected answers, are in `vem_verify::extremes`, shared with the
//! workspace test `tests/tests/extremes.rs`.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Args;
use serde::{Deserialize, Serialize};
use vem_verify::report::write_text;

use crate::common::{read_json, store_json};

use vem_verify::extremes::{self as rows, Row, Size, Verdict};

/// Options of `cargo xtask extremes`.
#[derive(Debug, Args)]
pub struct ExtremesArgs {
    /// Smaller meshes and fewer mesh families in the locking study (under a minute, for CI).
    #[arg(long)]
    quick: bool,
    /// The Markdown report (`--out docs/extremes.md` regenerates the tracked one); the rows
    /// go to `extremes.json` beside it.
    #[arg(long, default_value = "target/extremes/extremes.md")]
    out: PathBuf,
    /// Only the solvers named (registry names: condensed, exact, penalty, active-set);
    /// repeatable. Default: every registered solver.
    #[arg(long = "solver", value_name = "SOLVER")]
    solvers: Vec<String>,
    /// Rewrite the Markdown report `--out` from `extremes.json` beside it, without solving.
    #[arg(long)]
    report_only: bool,
}

/// `extremes.json`: a run's options, sizes and time, and every group's rows as the report
/// prints them.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct Stored {
    /// `--quick`.
    quick: bool,
    /// The sizes of the run.
    size: StoredSize,
    /// Wall-clock seconds of the rows.
    seconds: f64,
    /// The groups, in the order of the report.
    groups: Vec<StoredGroup>,
}

/// The [`Size`] of a run, as the report names it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct StoredSize {
    patch: usize,
    manufactured: usize,
    locking: usize,
    /// Mesh family names of the locking study.
    locking_families: Vec<String>,
    /// Contact solvers (registry names).
    solvers: Vec<String>,
    hertz_blocks: Vec<String>,
    solid: usize,
    solid_patch: usize,
}

impl StoredSize {
    fn new(size: &Size) -> Self {
        Self {
            patch: size.patch,
            manufactured: size.manufactured,
            locking: size.locking,
            locking_families: size
                .locking_families
                .iter()
                .map(|f| f.name().to_string())
                .collect(),
            solvers: size.solvers.clone(),
            hertz_blocks: size.hertz_blocks.iter().map(|b| b.to_string()).collect(),
            solid: size.solid,
            solid_patch: size.solid_patch,
        }
    }
}

/// One group of rows: its title and rows.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct StoredGroup {
    title: String,
    rows: Vec<Row>,
}

/// `extremes.json` beside the report `out`.
fn json_path(out: &Path) -> PathBuf {
    out.with_file_name("extremes.json")
}

/// Runs the rows, writes `extremes.json` and the report rendered from it (with
/// `--report-only`, only the report from the JSON there); `Ok(false)` when an answer was
/// wrong without an error or a warning (a wrong "converged").
pub fn run(args: &ExtremesArgs) -> Result<bool, Box<dyn std::error::Error>> {
    if let Some(dir) = args.out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)
            .map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    }
    let stored = if args.report_only {
        read_json(json_path(&args.out))?
    } else {
        store_json(json_path(&args.out), &solve(args)?)?
    };
    write_text(&args.out, &report(&stored)?)?;
    let count = |f: &dyn Fn(&Verdict) -> bool| {
        stored
            .groups
            .iter()
            .flat_map(|g| g.rows.iter().flat_map(|r| &r.outcomes))
            .filter(|o| f(&o.verdict))
            .count()
    };
    let wrong = count(&|v| matches!(v, Verdict::Wrong));
    eprintln!(
        "{} outcomes: {} pass, {} refused, {} warned, {wrong} wrong without a warning; \
         {:.1} s; {} {} from {}",
        count(&|_| true),
        count(&|v| matches!(v, Verdict::Pass)),
        count(&|v| matches!(v, Verdict::Refused(_))),
        count(&|v| matches!(v, Verdict::Warned(_))),
        stored.seconds,
        if args.report_only { "rewrote" } else { "wrote" },
        args.out.display(),
        json_path(&args.out).display()
    );
    Ok(wrong == 0)
}

/// Solves every group's rows at the run's size.
fn solve(args: &ExtremesArgs) -> Result<Stored, String> {
    let mut size = Size::new(args.quick);
    if !args.solvers.is_empty() {
        let known = rows::solver_names();
        if let Some(unknown) = args.solvers.iter().find(|s| !known.contains(s)) {
            return Err(format!(
                "unknown solver '{unknown}'; known: {}",
                known.join(", ")
            ));
        }
        size.solvers = args.solvers.clone();
    }
    let start = Instant::now();
    let mut groups = Vec::new();
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
        groups.push(StoredGroup {
            title: title.to_string(),
            rows,
        });
    }
    Ok(Stored {
        quick: args.quick,
        size: StoredSize::new(&size),
        seconds: start.elapsed().as_secs_f64(),
        groups,
    })
}

/// The report's text around its tables (`xtask/templates/extremes.md`).
const TEMPLATE: &str = include_str!("../templates/extremes.md");

/// The report: its template filled with the run's sizes and solvers, the summary, the rows
/// that fail and every group's table.
fn report(stored: &Stored) -> Result<String, String> {
    let (size, quick, elapsed) = (&stored.size, stored.quick, stored.seconds);
    let mut summary = String::new();
    let _ = writeln!(
        summary,
        "| group | rows | outcomes | pass | refused | warned | wrong |"
    );
    let _ = writeln!(summary, "|---|---:|---:|---:|---:|---:|---:|");
    for StoredGroup { title, rows } in &stored.groups {
        let outcomes: Vec<&Verdict> = rows
            .iter()
            .flat_map(|r| r.outcomes.iter().map(|o| &o.verdict))
            .collect();
        let n = |f: fn(&Verdict) -> bool| outcomes.iter().filter(|v| f(v)).count();
        let _ = writeln!(
            summary,
            "| {title} | {} | {} | {} | {} | {} | {} |",
            rows.len(),
            outcomes.len(),
            n(|v| matches!(v, Verdict::Pass)),
            n(|v| matches!(v, Verdict::Refused(_))),
            n(|v| matches!(v, Verdict::Warned(_))),
            n(|v| matches!(v, Verdict::Wrong)),
        );
    }
    let failing: Vec<(&Row, &rows::Outcome)> = stored
        .groups
        .iter()
        .flat_map(|g| &g.rows)
        .flat_map(|r| r.outcomes.iter().map(move |o| (r, o)))
        .filter(|(_, o)| o.verdict != Verdict::Pass)
        .collect();
    let mut failing_table = String::new();
    if failing.is_empty() {
        let _ = writeln!(failing_table, "None.");
    } else {
        let _ = writeln!(failing_table, "| row | solver | verdict |");
        let _ = writeln!(failing_table, "|---|---|---|");
        for (row, outcome) in failing {
            let _ = writeln!(
                failing_table,
                "| {} | {} | {} |",
                row.name,
                outcome.solver,
                outcome.verdict.word()
            );
        }
    }
    let mut tables = String::new();
    for StoredGroup { title, rows } in &stored.groups {
        let _ = writeln!(tables, "\n## {title}\n");
        let _ = writeln!(tables, "| row | expected | solver | measured | verdict |");
        let _ = writeln!(tables, "|---|---|---|---|---|");
        for row in rows {
            for (k, outcome) in row.outcomes.iter().enumerate() {
                let (name, expected) = if k == 0 {
                    (row.name.as_str(), row.expected.as_str())
                } else {
                    ("", "")
                };
                let _ = writeln!(
                    tables,
                    "| {name} | {expected} | {} | {} | {} |",
                    outcome.solver,
                    cell(&outcome.measured),
                    outcome.verdict.word()
                );
            }
        }
    }
    // The template supplies the line break that ends the report.
    let tables = tables.strip_suffix('\n').unwrap_or(&tables).to_string();
    crate::common::render(
        "xtask/templates/extremes.md",
        TEMPLATE,
        &[
            ("options", if quick { " --quick" } else { "" }.to_string()),
            ("patch", size.patch.to_string()),
            ("manufactured", size.manufactured.to_string()),
            (
                "manufactured_body_2",
                (size.manufactured + size.manufactured / 2).to_string(),
            ),
            ("locking", size.locking.to_string()),
            ("locking_families", size.locking_families.join(", ")),
            ("solvers", size.solvers.join(", ")),
            ("seconds", format!("{elapsed:.0}")),
            ("table_summary", summary),
            ("failing", failing_table),
            ("groups", tables),
        ],
    )
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

#[cfg(test)]
mod tests {
    use super::*;

    /// `--report-only` from the committed `docs/extremes.json` rewrites the committed
    /// `docs/extremes.md` byte for byte.
    #[test]
    fn the_committed_extremes_report_is_rendered_from_its_json() {
        let docs = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs");
        let stored: Stored = read_json(docs.join("extremes.json")).unwrap();
        assert!(!stored.quick, "docs/extremes.json is of a --quick run");
        let committed = std::fs::read_to_string(docs.join("extremes.md")).unwrap();
        assert!(
            report(&stored).unwrap() == committed,
            "docs/extremes.md is not the report rendered from docs/extremes.json"
        );
    }
}
