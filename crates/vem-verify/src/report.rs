//! Reports of convergence studies: Markdown tables, log-log SVG plots with reference slopes
//! (drawn with [`crate::plot`]), JSON. Files are written whole or not at all (`vem_mesh::io::write_atomically`).
//!
//! ```
//! use std::sync::Arc;
//! use vem_mesh::generators::MeshFamily;
//! use vem_verify::exact::{case_by_name, Lame};
//! # #[cfg(feature = "plots")]
//! use vem_verify::report::plot_svg;
//! use vem_verify::report::study_markdown;
//! use vem_verify::study::{MeshPairing, Study};
//! let e1: Arc<_> = case_by_name("E1", Lame::default())?.into();
//! let result = Study::new(e1, MeshPairing::single(MeshFamily::Quads)).sizes([2, 4]).run()?;
//! assert!(study_markdown(&result).contains("| n | h |"));
//! # #[cfg(feature = "plots")]
//! assert!(plot_svg(&result)?.starts_with("<svg"));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::path::Path;

use serde::Serialize;

use crate::study::{successive_rates, Expectation, SizeRecord, StudyResult};
use crate::VerifyError;

#[cfg(feature = "plots")]
/// The reference slopes are drawn this factor below the finest error they start from.
const REFERENCE_OFFSET: f64 = 0.5;
#[cfg(feature = "plots")]
/// Dashes of a reference slope.
const REFERENCE_DASHES: usize = 24;

#[cfg(feature = "plots")]
/// Width and height of the plots, in pixels.
const PLOT_SIZE: (u32, u32) = (720, 540);

fn sci(value: f64) -> String {
    format!("{value:.3e}")
}

fn rate(rate: Option<f64>) -> String {
    rate.map_or_else(|| "—".to_string(), |r| format!("{r:.2}"))
}

fn passed(passed: bool) -> &'static str {
    if passed {
        "pass"
    } else {
        "FAIL"
    }
}

/// The Markdown section of one study: a heading, the per-size table (errors with the rate
/// between successive sizes; for contact cases the resultant errors, the discrete switch point
/// and the number of nodes contradicting the expected sets), the fitted rates and the verdict.
pub fn study_markdown(study: &StudyResult) -> String {
    let records = &study.records;
    let h: Vec<f64> = records.iter().map(|r| r.h).collect();
    let series = |f: fn(&SizeRecord) -> f64| -> (Vec<f64>, Vec<Option<f64>>) {
        let e: Vec<f64> = records.iter().map(f).collect();
        let rates = successive_rates(&h, &e);
        (e, rates)
    };
    let (grad, grad_rates) = series(|r| r.errors.grad);
    let (energy, energy_rates) = series(|r| r.errors.energy);
    let (l2, l2_rates) = series(|r| r.errors.l2);
    let contact = records.iter().any(|r| r.contact.is_some());
    let mut out = String::new();
    out.push_str(&format!("### {}\n\n", study.title()));
    let mut header = "| n | h | DOFs | E_grad | rate | E_a | rate | E_0 | rate |".to_string();
    let mut rule = "|---|---|---|---|---|---|---|---|---|".to_string();
    if contact {
        header.push_str(" ΔN | ΔT | switch x_h (dist.) | set viol. |");
        rule.push_str("---|---|---|---|");
    }
    header.push_str(" asm / sym / num / solves | time [s] |\n");
    rule.push_str("---|---|\n");
    out.push_str(&header);
    out.push_str(&rule);
    for (k, record) in records.iter().enumerate() {
        let n: Vec<String> = record.n.iter().map(usize::to_string).collect();
        out.push_str(&format!(
            "| {} | {:.4} | {} | {} | {} | {} | {} | {} | {} |",
            n.join("/"),
            record.h,
            record.dofs,
            sci(grad[k]),
            rate(grad_rates[k]),
            sci(energy[k]),
            rate(energy_rates[k]),
            sci(l2[k]),
            rate(l2_rates[k]),
        ));
        if contact {
            match &record.contact {
                Some(c) => {
                    let switch = c.contact_switch.or(c.slip_switch).map_or_else(
                        || "—".to_string(),
                        |s| match (s.discrete, s.distance) {
                            (Some(x), Some(d)) => format!("{x:.3} ({d:.3})"),
                            _ => "none".to_string(),
                        },
                    );
                    out.push_str(&format!(
                        " {} | {} | {} | {} |",
                        sci(c.normal_resultant_error),
                        sci(c.tangential_resultant_error),
                        switch,
                        c.set_violations.len()
                    ));
                }
                None => out.push_str(" — | — | — | — |"),
            }
        }
        let w = &record.work;
        out.push_str(&format!(
            " {} / {} / {} / {} | {:.2} |\n",
            w.assemblies,
            w.symbolic_analyses,
            w.numeric_factorisations,
            w.triangular_solves,
            record.times.total()
        ));
    }
    let r = &study.rates;
    out.push_str(&format!(
        "\nFitted rates (least squares over the {} finest sizes): E_grad {}, E_a {}, E_0 {}. ",
        r.fitted,
        rate(r.grad),
        rate(r.energy),
        rate(r.l2)
    ));
    match study.expectation {
        Expectation::Rates { grad, energy, l2 } => out.push_str(&format!(
            "Expected at least {grad}, {energy}, {l2}: **{}**",
            passed(study.verdict.passed)
        )),
        Expectation::Exact { tolerance } => out.push_str(&format!(
            "Expected relative errors <= {tolerance:e} at every size: **{}**",
            passed(study.verdict.passed)
        )),
        Expectation::Resultants { tolerance } => out.push_str(&format!(
            "Expected relative resultant errors <= {tolerance:e} on the finest mesh: **{}**",
            passed(study.verdict.passed)
        )),
    }
    for shortfall in &study.verdict.shortfalls {
        out.push_str(&format!("\n- {shortfall}"));
    }
    if let Some(c) = study.finest().and_then(|r| r.contact.as_ref()) {
        out.push_str(&format!(
            "\n\nFinest size: {} interface nodes, {} active ({}); \
             sum of nodal contact forces {:.6} (exact {:.6}), of friction forces {:.6} (exact {:.6}); \
             nodal pressure error {}.",
            c.nodes,
            c.active,
            if c.stick + c.slip == 0 {
                "frictionless".to_string()
            } else {
                format!("{} stick, {} slip", c.stick, c.slip)
            },
            c.normal_resultant,
            c.normal_resultant_exact,
            c.tangential_resultant,
            c.tangential_resultant_exact,
            sci(c.pressure_error),
        ));
        if let Some(s) = c.contact_switch {
            out.push_str(&format!(
                " Exact contact/separation point x_c = {:.4}.",
                s.exact
            ));
        }
        if let Some(s) = c.slip_switch {
            out.push_str(&format!(" Exact stick/slip point x_s = {:.4}.", s.exact));
        }
        if let Some(v) = c.set_violations.first() {
            out.push_str(&format!(
                " First node contradicting the expected sets: x = {:.4}, expected {}, found {}.",
                v.x, v.expected, v.found
            ));
        }
    }
    out.push_str(&format!("\n\nStudy time {:.1} s.\n", study.seconds));
    out
}

/// One summary row per study: case, meshing, sizes, fitted rates, resultant errors and
/// switch-point distance at the finest size, verdict.
pub fn summary_markdown(studies: &[StudyResult]) -> String {
    let mut out = String::from(
        "| case | meshes (body 1/body 2) | n | E_grad rate | E_a rate | E_0 rate | ΔN | ΔT | switch dist. | verdict |\n\
         |---|---|---|---|---|---|---|---|---|---|\n",
    );
    for study in studies {
        let sizes = match (study.records.first(), study.records.last()) {
            (Some(a), Some(b)) => {
                let join =
                    |n: &[usize]| n.iter().map(usize::to_string).collect::<Vec<_>>().join("/");
                format!("{}..{}", join(&a.n), join(&b.n))
            }
            _ => "—".to_string(),
        };
        let contact = study.finest().and_then(|r| r.contact.as_ref());
        let (normal, tangential, switch) = match contact {
            Some(c) => (
                sci(c.normal_resultant_error),
                sci(c.tangential_resultant_error),
                c.contact_switch
                    .or(c.slip_switch)
                    .and_then(|s| s.distance)
                    .map_or_else(|| "—".to_string(), |d| format!("{d:.3}")),
            ),
            None => ("—".to_string(), "—".to_string(), "—".to_string()),
        };
        out.push_str(&format!(
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
            study.case,
            study.pairing_label,
            sizes,
            rate(study.rates.grad),
            rate(study.rates.energy),
            rate(study.rates.l2),
            normal,
            tangential,
            switch,
            passed(study.verdict.passed),
        ));
    }
    out
}

#[cfg(feature = "plots")]
/// The log-log plot of `E_grad`, `E_a` and `E_0` against `h` with reference slopes 1 and 2
/// (dashed, starting half a step below the finest `E_grad` and `E_0`), as an SVG document.
///
/// # Errors
/// A study without positive errors to plot, or a drawing failure.
pub fn plot_svg(study: &StudyResult) -> Result<String, VerifyError> {
    use crate::plot::{
        chart_svg, three_digits, Axis, Chart, Layer, LegendPosition, Pen, REFERENCE_GREY,
        SERIES_COLOURS,
    };
    let plot_error = |reason: String| VerifyError::InvalidSetting {
        reason: format!("plot of {}: {reason}", study.title()),
    };
    let series = [
        ("E_grad", points(study, |r| r.errors.grad)),
        ("E_a", points(study, |r| r.errors.energy)),
        ("E_0", points(study, |r| r.errors.l2)),
    ];
    let all: Vec<(f64, f64)> = series.iter().flat_map(|s| s.1.iter().copied()).collect();
    if all.is_empty() {
        return Err(plot_error("no positive errors".to_string()));
    }
    let (h_min, h_max) = bounds(all.iter().map(|p| p.0));
    let (e_min, e_max) = bounds(all.iter().map(|p| p.1));
    let x_range = (h_min / 1.3)..(h_max * 1.3);
    let y_range = (e_min / 3.0)..(e_max * 3.0);
    let mut layers = Vec::new();
    for (k, (name, data)) in series.iter().enumerate() {
        if data.is_empty() {
            continue;
        }
        let colour = SERIES_COLOURS[k];
        layers.push(Layer::line(data.clone(), Pen::new(colour, 2)).labelled(*name));
        layers.push(Layer::dots(data.clone(), 4, colour));
    }
    // Reference slopes below the finest E_grad (slope 1) and E_0 (slope 2), dashed in
    // data coordinates (dashes of equal length in log h).
    for (slope, anchor, label) in [
        (1.0, series[0].1.last(), "O(h)"),
        (2.0, series[2].1.last(), "O(h^2)"),
    ] {
        let Some(&(h0, e0)) = anchor else { continue };
        let e0 = e0 * REFERENCE_OFFSET;
        let (t0, t1) = (h0.ln(), h_max.ln());
        let dashes = (2 * REFERENCE_DASHES) as f64;
        let at = |k: f64| {
            let h = (t0 + (t1 - t0) * k / dashes).exp();
            (h, e0 * (h / h0).powf(slope))
        };
        let segments = (0..REFERENCE_DASHES)
            .map(|k| {
                let k = 2.0 * k as f64;
                [at(k), at(k + 1.0)]
            })
            .collect();
        layers.push(Layer::segments(segments, Pen::new(REFERENCE_GREY, 1)).labelled(label));
    }
    let (x_format, y_format) = (|v: &f64| three_digits(*v), |v: &f64| format!("{v:.0e}"));
    let title = study.title();
    let chart = Chart::new(
        Axis::log("h (largest element diameter)", x_range, h_ticks(&all)).format(&x_format),
        Axis::log("error", y_range.clone(), crate::plot::log_ticks(y_range)).format(&y_format),
    )
    .caption(&title, 20)
    .frame(16, (44, 70))
    .legend(Some(LegendPosition::LowerRight));
    chart_svg(PLOT_SIZE, &chart, &layers).map_err(|e| plot_error(e.to_string()))
}

#[cfg(feature = "plots")]
/// The distinct mesh sizes of the plotted points: the ticks of the h axis.
fn h_ticks(points: &[(f64, f64)]) -> Vec<f64> {
    let mut h: Vec<f64> = points.iter().map(|p| p.0).collect();
    h.sort_by(f64::total_cmp);
    h.dedup_by(|a, b| (*a - *b).abs() <= 1e-9 * b.abs());
    h
}

#[cfg(feature = "plots")]
/// The positive points `(h, error)` of a study.
fn points(study: &StudyResult, error: fn(&SizeRecord) -> f64) -> Vec<(f64, f64)> {
    study
        .records
        .iter()
        .map(|r| (r.h, error(r)))
        .filter(crate::plot::positive)
        .collect()
}

#[cfg(feature = "plots")]
fn bounds(values: impl Iterator<Item = f64>) -> (f64, f64) {
    values.fold((f64::INFINITY, 0.0_f64), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    })
}

/// Writes `text` to `path` atomically.
///
/// # Errors
/// [`VerifyError::Write`] naming the file.
pub fn write_text(path: impl AsRef<Path>, text: &str) -> Result<(), VerifyError> {
    let path = path.as_ref();
    vem_mesh::io::write_atomically(path, |w| w.write_all(text.as_bytes()))
        .map_err(|e| VerifyError::from_write(path, e))
}

/// Writes `value` as pretty-printed JSON to `path` atomically.
///
/// # Errors
/// [`VerifyError::Write`] naming the file.
pub fn write_json(path: impl AsRef<Path>, value: &impl Serialize) -> Result<(), VerifyError> {
    let path = path.as_ref();
    let text = serde_json::to_string_pretty(value).map_err(|e| VerifyError::Write {
        path: path.to_path_buf(),
        reason: e.to_string(),
    })?;
    write_text(path, &(text + "\n"))
}

#[cfg(feature = "plots")]
/// Writes the plot of [`plot_svg`] to `path` atomically.
///
/// # Errors
/// As [`plot_svg`] and [`write_text`].
pub fn write_plot(path: impl AsRef<Path>, study: &StudyResult) -> Result<(), VerifyError> {
    write_text(path, &plot_svg(study)?)
}
