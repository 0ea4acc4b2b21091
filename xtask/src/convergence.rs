//! `cargo xtask convergence`: the convergence studies of the project (Theorems 4.1 and 4.2 of
//! the paper, `docs/formulation.md` section 3; measurement as in `docs/manufactured.md` section 8)
//! in the plane, and the study of the element on polyhedra in space ([`three_d`],
//! `docs/convergence-3d.md`). One run, one verdict: the exit status is 1 when a study of either
//! part falls short.

mod three_d;

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use clap::Args;
use indicatif::{MultiProgress, ProgressBar, ProgressStyle};
use serde::{Deserialize, Serialize};
use vem_contact::SolverRegistry;
use vem_space::{ElementRegistry, ElementSpace};
use vem_verify::cases::CaseRegistry;
use vem_verify::exact::Lame;
use vem_verify::plan::{planned_studies, PlannedStudy, DEFAULT_CASES};
use vem_verify::report::{study_markdown, summary_markdown, write_json, write_plot, write_text};
use vem_verify::study::{Expectation, MeshPairing, SizeRecord, Study, StudyResult};

/// Options of `cargo xtask convergence`.
#[derive(Debug, Args)]
pub struct ConvergenceArgs {
    /// Run a reduced set of smaller sizes (a minute or two, for CI); the study in space then
    /// judges against the lower thresholds its sizes show (its report says which).
    #[arg(long)]
    quick: bool,
    /// Where the JSON, Markdown and SVG files are written.
    #[arg(long, default_value = "target/convergence")]
    out: PathBuf,
    /// The contact solver: a name of the solver registry (condensed, exact, penalty, active-set).
    #[arg(long, default_value = SolverRegistry::DEFAULT)]
    solver: String,
    /// The element of every body: a name of the element registry (vem1, vem1-shear,
    /// vem1-drecipe, vem1-bbar, p1 on triangles); in space the lowest-order VEM with the same
    /// stabilisation (p1 has none: select cases in the plane).
    #[arg(long, default_value = DEFAULT_ELEMENT)]
    element: String,
    /// Run only the studies of these cases, any name of the case registry (M1..M4, E1, E2,
    /// PT0a, PT0b, PTC1, PTC1h, PTC2, PTC3) or a case in space (E1-3D, E2-3D, PT0-3D);
    /// repeatable. M1, M2, E1 and the three cases in space are the default run.
    #[arg(long = "case", value_name = "CASE")]
    cases: Vec<String>,
    /// Rewrite convergence.md and convergence/*.svg from the studies in the plane of
    /// `<out>/convergence.json`, without running them.
    #[arg(long)]
    report_only: bool,
}

/// The element of the default run.
const DEFAULT_ELEMENT: &str = ElementRegistry::DEFAULT;

/// The planned run: the studies in the plane and the cases in space.
struct Plan {
    /// The studies in the plane, in the order they run.
    studies: Vec<PlannedStudy>,
    /// The cases in space, each once, in the order they run.
    solid: Vec<&'static str>,
}

/// The studies of the cases `wanted` (the default cases in the plane and in space when empty):
/// each case of `cases` on the contact pairings (two bodies) or the elasticity families (one
/// body) ([`planned_studies`]); each case in space on every polyhedral family ([`three_d`]).
fn plan(quick: bool, wanted: &[String], cases: &CaseRegistry) -> Result<Plan, String> {
    let names: Vec<String> = if wanted.is_empty() {
        DEFAULT_CASES
            .iter()
            .chain(&three_d::DEFAULT_CASES)
            .map(|c| c.to_string())
            .collect()
    } else {
        wanted.to_vec()
    };
    let mut studies = Vec::new();
    let mut solid = Vec::new();
    for wanted in &names {
        if let Some(name) = three_d::case_name(wanted) {
            if !solid.contains(&name) {
                solid.push(name);
            }
            continue;
        }
        studies.extend(
            planned_studies(wanted, quick, cases)
                .map_err(|e| format!("{e}; the cases in space are {}", three_d::case_names()))?,
        );
    }
    Ok(Plan { studies, solid })
}

/// The report's text around its tables (`xtask/templates/convergence.md`).
const TEMPLATE: &str = include_str!("../templates/convergence.md");

/// Runs the planned studies, in the plane then in space, prints and writes their reports;
/// `Ok(true)` when every study passes.
pub fn run(args: &ConvergenceArgs) -> Result<bool, Box<dyn std::error::Error>> {
    if args.report_only {
        return report_only(&args.out);
    }
    let start = Instant::now();
    let solvers = SolverRegistry::builtin();
    if !solvers.names().contains(&args.solver.as_str()) {
        return Err(format!(
            "unknown solver {:?}; the solvers are {}",
            args.solver,
            solvers.names().join(", ")
        )
        .into());
    }
    let element = ElementRegistry::builtin().make(&args.element)?;
    let plan = plan(args.quick, &args.cases, &CaseRegistry::builtin())?;
    // The element in space, refused before anything runs when it has no form on polyhedra.
    let solid_element = if plan.solid.is_empty() {
        None
    } else {
        Some(three_d::element(&args.element)?)
    };
    std::fs::create_dir_all(&args.out)
        .map_err(|e| format!("cannot create {}: {e}", args.out.display()))?;
    let bars = MultiProgress::new();
    let style = ProgressStyle::with_template("{prefix:<40} [{bar:30}] {elapsed:>4} {msg}")?
        .progress_chars("=> ");
    let mut parts = Vec::new();
    let mut passed = true;
    if !plan.studies.is_empty() {
        let results = run_studies(&plan.studies, args, &solvers, element, &bars, &style)?;
        passed &= results.iter().all(|r| r.verdict.passed);
        parts.push(format!("{} studies in the plane", results.len()));
    }
    if let Some(element) = solid_element {
        // One line per series was printed as it finished; the tables are in the report.
        let outcome = three_d::run(&plan.solid, args.quick, element, &bars, &style)?;
        if outcome.quick {
            println!("{}\n", three_d::quick_note());
        }
        println!(
            "{} series in space in {:.0} s: {}",
            outcome.series.len(),
            outcome.seconds,
            verdict_line(outcome.passed)
        );
        let default_run =
            plan.solid == three_d::DEFAULT_CASES && !args.quick && args.element == DEFAULT_ELEMENT;
        let options = command_options(args.quick, &args.solver, &args.element, &args.cases);
        three_d::write(&outcome, &args.out, &options, default_run)?;
        println!(
            "the full tables (errors per size, rates per step, times): {}",
            args.out.join("convergence-3d.md").display()
        );
        eprintln!(
            "wrote {}/convergence-3d.md, convergence-3d.json and convergence-3d/*.svg",
            args.out.display()
        );
        passed &= outcome.passed;
        parts.push(format!("{} series in space", outcome.series.len()));
    }
    if parts.len() > 1 {
        println!(
            "{} in {:.0} s: {}",
            parts.join(" and "),
            start.elapsed().as_secs_f64(),
            verdict_line(passed)
        );
    }
    Ok(passed)
}

/// The verdict of a part or of the whole run, on the last line of its output.
fn verdict_line(passed: bool) -> &'static str {
    if passed {
        "all pass"
    } else {
        "SOME FALL SHORT"
    }
}

/// Runs the studies in the plane, prints them and their summary and writes `convergence.md`,
/// `convergence.json` and `convergence/*.svg`.
fn run_studies(
    planned: &[PlannedStudy],
    args: &ConvergenceArgs,
    solvers: &SolverRegistry,
    element: Arc<dyn ElementSpace>,
    bars: &MultiProgress,
    style: &ProgressStyle,
) -> Result<Vec<StudyResult>, Box<dyn std::error::Error>> {
    let start = Instant::now();
    let plots = args.out.join("convergence");
    std::fs::create_dir_all(&plots)
        .map_err(|e| format!("cannot create {}: {e}", plots.display()))?;
    let cases = CaseRegistry::builtin();
    let mut results: Vec<StudyResult> = Vec::with_capacity(planned.len());
    let total = planned.len();
    for (k, p) in planned.iter().enumerate() {
        let exact = cases.make(&p.case, Lame::default())?;
        let pairing: MeshPairing = p.pairing.parse()?;
        let study = Study::new(exact, pairing.clone())
            .sizes(p.sizes)
            .registry(solvers.clone())
            .solver(args.solver.as_str())
            .element(Arc::clone(&element))
            .expect(p.expectation);
        // Work grows like the number of cells: weight each size by it.
        let weight = |n: usize| -> u64 {
            pairing
                .bodies()
                .iter()
                .map(|b| ((b.factor * n) as u64).pow(2))
                .sum()
        };
        let bar = bars.add(ProgressBar::new(p.sizes.iter().map(|&n| weight(n)).sum()));
        bar.set_style(style.clone());
        bar.set_prefix(study.title());
        let label = format!("[{}/{total}] {} on {}", k + 1, p.case, p.pairing);
        bars.suspend(|| eprintln!("{label}: sizes n = {}", join(p.sizes)));
        let result = study.run_with(|record| {
            bar.inc(weight(record.n[0] / pairing.bodies()[0].factor));
            bar.set_message(format!("n = {:?}", record.n));
            bars.suspend(|| eprintln!("{}", progress_line(&label, record)));
        })?;
        bar.finish_with_message(if result.verdict.passed {
            "pass"
        } else {
            "FAIL"
        });
        write_plot(plot_path(&args.out, &result), &result)?;
        results.push(result);
    }
    let seconds = start.elapsed().as_secs_f64();
    let passed = results.iter().all(|r| r.verdict.passed);
    println!("{}", console_summary(&results));
    println!(
        "{} studies in the plane in {seconds:.0} s: {}",
        results.len(),
        verdict_line(passed)
    );
    println!(
        "the full tables (errors per size, contact diagnostics, times): {}",
        args.out.join("convergence.md").display()
    );
    let report = JsonReport {
        quick: args.quick,
        solver: args.solver.clone(),
        element: args.element.clone(),
        cases: args.cases.clone(),
        seconds,
        threads: std::thread::available_parallelism().map_or(1, usize::from),
        passed,
        studies: results,
    };
    write_text(args.out.join("convergence.md"), &markdown(&report)?)?;
    write_json(args.out.join("convergence.json"), &report)?;
    eprintln!(
        "wrote {}/convergence.md, convergence.json and convergence/*.svg",
        args.out.display()
    );
    Ok(report.studies)
}

/// `--report-only`: rewrites `convergence.md` and `convergence/*.svg` in `out` from
/// `out/convergence.json`; `Ok(true)` when every study stored there passed.
fn report_only(out: &Path) -> Result<bool, Box<dyn std::error::Error>> {
    let path = out.join("convergence.json");
    let report: JsonReport = crate::common::read_json(&path)?;
    let plots = out.join("convergence");
    std::fs::create_dir_all(&plots)
        .map_err(|e| format!("cannot create {}: {e}", plots.display()))?;
    for study in &report.studies {
        write_plot(plot_path(out, study), study)?;
    }
    write_text(out.join("convergence.md"), &markdown(&report)?)?;
    eprintln!(
        "rewrote {}/convergence.md and convergence/*.svg from {}",
        out.display(),
        path.display()
    );
    Ok(report.studies.iter().all(|r| r.verdict.passed))
}

/// `out/convergence/<case>-<slug>.svg`: the plot of `study`.
fn plot_path(out: &Path, study: &StudyResult) -> PathBuf {
    out.join("convergence")
        .join(format!("{}-{}.svg", study.case, study.slug))
}

/// `8, 16, 32`.
fn join(sizes: &[usize]) -> String {
    sizes
        .iter()
        .map(usize::to_string)
        .collect::<Vec<_>>()
        .join(", ")
}

/// One line of progress: a size of a study measured, with its time and size.
fn progress_line(label: &str, record: &SizeRecord) -> String {
    let n: Vec<String> = record.n.iter().map(usize::to_string).collect();
    format!(
        "{label}: n = {} done in {:.1} s ({} unknowns, h = {:.3e}, E_grad = {:.3e})",
        n.join("/"),
        record.times.total(),
        record.dofs,
        record.h,
        record.errors.grad
    )
}

/// What a study must show, in a few characters: the least rates of `E_grad`, `E_a`, `E_0`,
/// or the tolerance of a patch test or of the resultants.
fn expected_label(expectation: &Expectation) -> String {
    match *expectation {
        Expectation::Rates { grad, energy, l2 } => format!(">= {grad}, {energy}, {l2}"),
        Expectation::Exact { tolerance } => format!("exact to {tolerance:.0e}"),
        Expectation::Resultants { tolerance } => format!("resultants to {tolerance:.0e}"),
    }
}

/// A fitted rate to two decimals, `-` when undefined.
fn rate_cell(rate: Option<f64>) -> String {
    rate.map_or_else(|| "-".to_string(), |r| format!("{r:.2}"))
}

/// The console's summary of the studies in the plane: per case and meshing the rates fitted
/// over the finest sizes against what the theorems ask, and the verdict, in a table under 100
/// characters wide; what falls short listed below. The wide tables are in the report.
fn console_summary(results: &[StudyResult]) -> String {
    let header = [
        "case", "meshes", "sizes", "E_grad", "E_a", "E_0", "expected", "verdict",
    ];
    let rows: Vec<[String; 8]> = results
        .iter()
        .map(|r| {
            let sizes = match (r.records.first(), r.records.last()) {
                (Some(a), Some(b)) => format!("{}..{}", a.n[0], b.n[0]),
                _ => "-".into(),
            };
            [
                r.case.clone(),
                r.pairing.clone(),
                sizes,
                rate_cell(r.rates.grad),
                rate_cell(r.rates.energy),
                rate_cell(r.rates.l2),
                expected_label(&r.expectation),
                if r.verdict.passed { "pass" } else { "FAIL" }.into(),
            ]
        })
        .collect();
    let widths: Vec<usize> = (0..header.len())
        .map(|c| {
            rows.iter()
                .map(|row| row[c].chars().count())
                .chain([header[c].len()])
                .max()
                .unwrap_or(0)
        })
        .collect();
    let line = |cells: &[String]| -> String {
        let padded: Vec<String> = cells
            .iter()
            .zip(&widths)
            .map(|(cell, &w)| format!("{cell:<w$}"))
            .collect();
        padded.join("  ").trim_end().to_string()
    };
    let mut out = String::from(
        "Rates fitted over the finest sizes (E_grad, E_a, E_0; expected: the least rates of \
         Theorems 4.1/4.2 and of E_0):\n",
    );
    out.push_str(&line(&header.map(String::from)));
    out.push('\n');
    for row in &rows {
        out.push_str(&line(row));
        out.push('\n');
    }
    for r in results.iter().filter(|r| !r.verdict.passed) {
        for shortfall in &r.verdict.shortfalls {
            out.push_str(&format!("  {} on {}: {shortfall}\n", r.case, r.pairing));
        }
    }
    out
}

/// The whole Markdown report: its template (introduction, summary) filled with the summary
/// table and one section per case with its plots.
fn markdown(report: &JsonReport) -> Result<String, String> {
    let results = &report.studies;
    let mut studies = String::new();
    let mut case = "";
    for result in results {
        if result.case != case {
            case = &result.case;
            studies.push_str(&format!("\n## {case}\n"));
        }
        studies.push('\n');
        studies.push_str(&study_markdown(result));
        studies.push_str(&format!(
            "\n![{}](convergence/{}-{}.svg)\n",
            result.title(),
            result.case,
            result.slug
        ));
    }
    // The template supplies the line break that ends the report.
    let studies = studies.strip_suffix('\n').unwrap_or(&studies).to_string();
    crate::common::render(
        "xtask/templates/convergence.md",
        TEMPLATE,
        &[
            (
                "options",
                command_options(report.quick, &report.solver, &report.element, &report.cases),
            ),
            ("study_count", results.len().to_string()),
            ("seconds", format!("{:.0}", report.seconds)),
            ("threads", report.threads.to_string()),
            ("solver", report.solver.clone()),
            (
                "element",
                results
                    .first()
                    .map_or(report.element.as_str(), |r| r.element.as_str())
                    .to_string(),
            ),
            ("summary", summary_markdown(results)),
            ("studies", studies),
        ],
    )
}

/// The options of the run as they were given, e.g. `" --quick --solver penalty --case M1"`.
fn command_options(quick: bool, solver: &str, element: &str, cases: &[String]) -> String {
    let mut options = String::new();
    if quick {
        options.push_str(" --quick");
    }
    if solver != SolverRegistry::DEFAULT {
        options.push_str(&format!(" --solver {solver}"));
    }
    if element != DEFAULT_ELEMENT {
        options.push_str(&format!(" --element {element}"));
    }
    for case in cases {
        options.push_str(&format!(" --case {case}"));
    }
    options
}

/// The JSON form of a run in the plane: its options, time and threads, and every study; what
/// `--report-only` reads back.
#[derive(Serialize, Deserialize)]
struct JsonReport {
    quick: bool,
    solver: String,
    element: String,
    /// The cases asked for (`--case`; empty: the default run).
    #[serde(default)]
    cases: Vec<String>,
    seconds: f64,
    /// The threads the studies ran on.
    threads: usize,
    passed: bool,
    studies: Vec<StudyResult>,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The console's table holds each study's fitted rates as the report has them, the
    /// expected least rates and the verdict, and stays narrow.
    #[test]
    fn the_console_summary_is_a_narrow_table_of_the_rates() {
        let cases = CaseRegistry::builtin();
        let exact = cases.make("E1", Lame::default()).unwrap();
        let pairing: MeshPairing = "quads".parse().unwrap();
        let result = Study::new(exact, pairing)
            .sizes([4, 8, 16])
            .expect(Expectation::OPTIMAL_RATES)
            .run()
            .unwrap();
        let table = console_summary(std::slice::from_ref(&result));
        let lines: Vec<&str> = table.lines().collect();
        assert_eq!(lines.len(), 3, "{table}");
        assert!(lines.iter().all(|l| l.chars().count() < 120), "{table}");
        let cells: Vec<&str> = lines[2].split_whitespace().collect();
        assert_eq!(&cells[..3], ["E1", "quads", "4..16"]);
        let rate = |cell: &str| cell.parse::<f64>().unwrap();
        assert!((rate(cells[3]) - result.rates.grad.unwrap()).abs() <= 0.005);
        assert!((rate(cells[4]) - result.rates.energy.unwrap()).abs() <= 0.005);
        assert!((rate(cells[5]) - result.rates.l2.unwrap()).abs() <= 0.005);
        // E1 on quads converges at the theorem's rate: first order in E_grad.
        assert!((rate(cells[3]) - 1.0).abs() < 0.1, "{table}");
        assert_eq!(&cells[6..], [">=", "0.9,", "0.9,", "1.8", "pass"]);
        assert_eq!(
            expected_label(&Expectation::Exact { tolerance: 1e-10 }),
            "exact to 1e-10"
        );
    }

    /// The committed run in the plane, as `--report-only` reads it.
    fn committed() -> JsonReport {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/convergence.json");
        let text = std::fs::read_to_string(path).expect("docs/convergence.json");
        serde_json::from_str(&text).expect("the committed convergence.json parses")
    }

    /// The report is its template filled from the committed studies: what `--report-only
    /// --out docs` writes is docs/convergence.md, byte for byte.
    #[test]
    fn the_report_of_the_committed_studies_is_docs_convergence_md() {
        let report = committed();
        let markdown = markdown(&report).expect("the report renders");
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/convergence.md");
        let committed = std::fs::read_to_string(path).expect("docs/convergence.md");
        assert!(
            markdown == committed,
            "docs/convergence.md is not the rendered report"
        );
    }

    /// The plots of the committed studies are docs/convergence/*.svg, byte for byte: the
    /// pictures of the report are those of its JSON.
    #[test]
    fn the_plots_of_the_committed_studies_are_docs_convergence_svg() {
        let report = committed();
        assert_eq!(report.studies.len(), 13);
        for study in &report.studies {
            let path = plot_path(
                &Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs"),
                study,
            );
            let committed = std::fs::read_to_string(&path).expect("a committed plot");
            let drawn = vem_verify::report::plot_svg(study).expect("the plot draws");
            assert!(
                drawn == committed,
                "{} is not the drawn plot",
                path.display()
            );
        }
    }

    #[test]
    fn the_cases_select_the_parts_in_the_plane_and_in_space() {
        let cases = CaseRegistry::builtin();
        let names = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        // The default run: M1, M2 (five pairings each), E1 (three families) and every case in
        // space.
        let default = plan(false, &[], &cases).unwrap();
        assert_eq!(default.studies.len(), 13);
        assert_eq!(default.solid, three_d::DEFAULT_CASES);
        // Names of either part, in any case, each case in space once.
        let mixed = plan(true, &names(&["e2-3d", "M1", "E2-3D"]), &cases).unwrap();
        assert_eq!(mixed.solid, ["E2-3D"]);
        assert!(mixed.studies.iter().all(|s| s.case == "M1"));
        assert_eq!(mixed.studies[0].sizes, vem_verify::plan::QUICK_SIZES);
        // A selection of one part runs that part only.
        assert!(plan(false, &names(&["PT0-3D"]), &cases)
            .unwrap()
            .studies
            .is_empty());
        assert!(plan(false, &names(&["E1"]), &cases)
            .unwrap()
            .solid
            .is_empty());
        // An unknown name lists the cases of both parts.
        let unknown = plan(false, &names(&["E3-3D"]), &cases).err().unwrap();
        assert!(
            unknown.contains("\"E3-3D\"") && unknown.contains("M1") && unknown.contains("PT0-3D")
        );
    }
}
