//! Helpers shared by the measuring tasks (`bench`, `tradeoff`): peak memory and CPU time of
//! this process, the machine, an error chain on one line, log-log SVG plots.

use std::process::Command;
use std::time::Duration;

use plotters::prelude::*;
use vem_verify::report::log_ticks;

/// `VmHWM` of this process in bytes (0 where /proc is not available).
pub fn peak_memory() -> u64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|status| {
            status.lines().find_map(|line| {
                let kb = line.strip_prefix("VmHWM:")?.trim().strip_suffix("kB")?;
                kb.trim().parse::<u64>().ok()
            })
        })
        .map_or(0, |kb| 1024 * kb)
}

/// User plus system CPU seconds of this process so far (`/proc/self/stat`, clock ticks of
/// 1/100 s; 0 where /proc is not available).
pub fn cpu_seconds() -> f64 {
    std::fs::read_to_string("/proc/self/stat")
        .ok()
        .and_then(|stat| {
            // The fields after the command name (in parentheses): utime and stime are the
            // 12th and 13th of them.
            let rest = &stat[stat.rfind(')')? + 2..];
            let fields: Vec<&str> = rest.split_whitespace().collect();
            let utime: f64 = fields.get(11)?.parse().ok()?;
            let stime: f64 = fields.get(12)?.parse().ok()?;
            Some((utime + stime) / 100.0)
        })
        .unwrap_or(0.0)
}

/// Seconds of a duration.
pub fn seconds(d: Duration) -> f64 {
    d.as_secs_f64()
}

/// An error and its causes on one line.
pub fn chain(error: &dyn std::error::Error) -> String {
    let mut text = error.to_string();
    let mut source = error.source();
    while let Some(cause) = source {
        text.push_str(": ");
        text.push_str(&cause.to_string());
        source = cause.source();
    }
    text
}

/// The machine: CPU model and cores, memory, rustc.
pub fn machine() -> String {
    let cpuinfo = std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
    let model = cpuinfo
        .lines()
        .find_map(|l| l.strip_prefix("model name"))
        .map_or("unknown CPU", |l| l.trim_start_matches([' ', '\t', ':']));
    let cores = cpuinfo
        .lines()
        .filter(|l| l.starts_with("processor"))
        .count();
    let memory = std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|m| {
            m.lines().find_map(|l| {
                let kb = l.strip_prefix("MemTotal:")?.trim().strip_suffix("kB")?;
                kb.trim().parse::<f64>().ok()
            })
        })
        .map_or_else(
            || "unknown memory".to_string(),
            |kb| format!("{:.1} GiB", kb / 1024.0 / 1024.0),
        );
    let rustc = Command::new(std::env::var("RUSTC").unwrap_or_else(|_| "rustc".to_string()))
        .arg("--version")
        .output()
        .ok()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .unwrap_or_default();
    format!("{model}, {cores} logical cores, {memory}, {rustc}")
}

/// Captions and tick formats of a [`loglog_svg`] plot.
pub struct LogLogPlot<'a> {
    /// The caption.
    pub caption: &'a str,
    /// The x axis.
    pub x_desc: &'a str,
    /// The y axis.
    pub y_desc: &'a str,
    /// Tick labels of x.
    pub x_format: fn(&f64) -> String,
    /// Tick labels of y.
    pub y_format: fn(&f64) -> String,
}

/// A line drawn over the series of a [`loglog_svg`] plot: a label and its points.
#[derive(Debug, Clone, Copy)]
pub enum Overlay<'a> {
    /// A thick black line with squares: a Pareto front.
    Front(&'a str, &'a [(f64, f64)]),
    /// A thin dashed grey line without markers: a reference slope `C h^p`.
    Reference(&'a str, &'a [(f64, f64)]),
}

/// The colours of the series, in order (Tableau's ten, readable on white; no yellow): the
/// same as the convergence plots of `vem_verify::report`.
const SERIES_COLOURS: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(23, 190, 207),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
];

/// A log-log plot (900 x 600 SVG) of `series` (label, points; non-positive values are left
/// out), each a line with dots, and an optional [`Overlay`].
pub fn loglog_svg(
    plot: &LogLogPlot<'_>,
    series: &[(String, Vec<(f64, f64)>)],
    highlight: Option<Overlay<'_>>,
) -> Result<String, Box<dyn std::error::Error>> {
    let positive = |p: &&(f64, f64)| p.0 > 0.0 && p.1 > 0.0 && p.0.is_finite() && p.1.is_finite();
    let all = series
        .iter()
        .flat_map(|(_, p)| p.iter())
        .chain(highlight.into_iter().flat_map(|o| match o {
            Overlay::Front(_, p) | Overlay::Reference(_, p) => p.iter(),
        }))
        .filter(positive);
    let (mut x_lo, mut x_hi, mut y_lo, mut y_hi) = (f64::INFINITY, 0.0_f64, f64::INFINITY, 0.0_f64);
    for &(x, y) in all {
        (x_lo, x_hi, y_lo, y_hi) = (x_lo.min(x), x_hi.max(x), y_lo.min(y), y_hi.max(y));
    }
    let (x_lo, x_hi) = if x_lo.is_finite() {
        (x_lo / 1.5, x_hi * 1.5)
    } else {
        (1e3, 1e7)
    };
    let (y_lo, y_hi) = if y_lo.is_finite() {
        (y_lo / 1.5, y_hi * 1.5)
    } else {
        (0.1, 100.0)
    };
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (900, 600)).into_drawing_area();
        let draw = |e: &dyn std::fmt::Display| format!("plot: {e}");
        root.fill(&WHITE).map_err(|e| draw(&e))?;
        let mut chart = ChartBuilder::on(&root)
            .caption(plot.caption, ("sans-serif", 20))
            .margin(15)
            .x_label_area_size(40)
            .y_label_area_size(55)
            .build_cartesian_2d(
                (x_lo..x_hi)
                    .log_scale()
                    .with_key_points(log_ticks(x_lo..x_hi)),
                (y_lo..y_hi)
                    .log_scale()
                    .with_key_points(log_ticks(y_lo..y_hi)),
            )
            .map_err(|e| draw(&e))?;
        chart
            .configure_mesh()
            .x_desc(plot.x_desc)
            .y_desc(plot.y_desc)
            .max_light_lines(0)
            .x_label_formatter(&plot.x_format)
            .y_label_formatter(&plot.y_format)
            .draw()
            .map_err(|e| draw(&e))?;
        for (k, (label, pts)) in series.iter().enumerate() {
            let mut pts: Vec<(f64, f64)> = pts.iter().filter(positive).copied().collect();
            pts.sort_by(|a, b| a.0.total_cmp(&b.0));
            let colour = SERIES_COLOURS[k % SERIES_COLOURS.len()].to_rgba();
            chart
                .draw_series(LineSeries::new(pts.clone(), colour.stroke_width(2)))
                .map_err(|e| draw(&e))?
                .label(label.clone())
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour));
            chart
                .draw_series(pts.into_iter().map(|p| Circle::new(p, 3, colour.filled())))
                .map_err(|e| draw(&e))?;
        }
        match highlight {
            Some(Overlay::Front(label, pts)) => {
                let mut pts: Vec<(f64, f64)> = pts.iter().filter(positive).copied().collect();
                pts.sort_by(|a, b| a.0.total_cmp(&b.0));
                chart
                    .draw_series(LineSeries::new(pts.clone(), BLACK.stroke_width(3)))
                    .map_err(|e| draw(&e))?
                    .label(label)
                    .legend(|(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], BLACK.stroke_width(3))
                    });
                chart
                    .draw_series(pts.into_iter().map(|p| {
                        EmptyElement::at(p) + Rectangle::new([(-4, -4), (4, 4)], BLACK.filled())
                    }))
                    .map_err(|e| draw(&e))?;
            }
            Some(Overlay::Reference(label, pts)) => {
                let mut pts: Vec<(f64, f64)> = pts.iter().filter(positive).copied().collect();
                pts.sort_by(|a, b| a.0.total_cmp(&b.0));
                let grey = RGBColor(90, 90, 90);
                chart
                    .draw_series(DashedLineSeries::new(pts, 10, 6, grey.stroke_width(1)))
                    .map_err(|e| draw(&e))?
                    .label(label)
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], grey));
            }
            None => {}
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(|e| draw(&e))?;
        root.present().map_err(|e| draw(&e))?;
    }
    Ok(svg)
}

/// Fills the named placeholders `{{name}}` of the Markdown template `template` (called `name`
/// in errors, e.g. `templates/tradeoff.md`) with `values`. Refused: a placeholder of the
/// template without a value (named with its line), a value for a placeholder the template does
/// not have, and a `{{` without its `}}`.
pub fn render(name: &str, template: &str, values: &[(&str, String)]) -> Result<String, String> {
    let mut out = String::with_capacity(template.len());
    let mut used = vec![false; values.len()];
    let mut rest = template;
    let line_of = |rest: &str| {
        template[..template.len() - rest.len()]
            .matches('\n')
            .count()
            + 1
    };
    while let Some(start) = rest.find("{{") {
        out.push_str(&rest[..start]);
        let after = &rest[start + 2..];
        let Some(end) = after.find("}}") else {
            return Err(format!(
                "{name}:{}: '{{{{' without its '}}}}'",
                line_of(&rest[start..])
            ));
        };
        let key = &after[..end];
        match values.iter().position(|(k, _)| *k == key) {
            Some(i) => {
                out.push_str(&values[i].1);
                used[i] = true;
            }
            None => {
                return Err(format!(
                    "{name}:{}: the placeholder {{{{{key}}}}} has no value",
                    line_of(&rest[start..])
                ))
            }
        }
        rest = &after[end + 2..];
    }
    out.push_str(rest);
    if let Some(i) = used.iter().position(|u| !u) {
        return Err(format!(
            "{name}: a value for {{{{{}}}}}, which the template does not have",
            values[i].0
        ));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::render;

    #[test]
    fn a_template_is_filled_and_a_missing_or_extra_value_is_named() {
        let template = "# Title\n\nC = {{c}}; n = {{n}}.\n{{table}}";
        let values = |extra: bool| {
            let mut v = vec![
                ("c", "2.9".to_string()),
                ("n", "29".to_string()),
                ("table", "| a |\n".to_string()),
            ];
            if extra {
                v.push(("rate", "1".to_string()));
            }
            v
        };
        assert_eq!(
            render("t.md", template, &values(false)).unwrap(),
            "# Title\n\nC = 2.9; n = 29.\n| a |\n"
        );
        let unfilled = render("t.md", template, &values(false)[..2]).unwrap_err();
        assert!(
            unfilled.contains("t.md:4") && unfilled.contains("{{table}}"),
            "{unfilled}"
        );
        let unknown = render("t.md", template, &values(true)).unwrap_err();
        assert!(unknown.contains("{{rate}}"), "{unknown}");
        let open = render("t.md", "a\n{{c", &values(false)).unwrap_err();
        assert!(open.contains("t.md:2"), "{open}");
    }
}
