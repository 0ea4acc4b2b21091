//! Helpers shared by the measuring tasks (`bench`, `tradeoff`): peak memory and CPU time of
//! this process, the machine, an error chain on one line, Markdown templates, a study's JSON
//! written and read back. The plots are drawn by `vem_verify::plot`.

use std::path::Path;
use std::process::Command;
use std::time::Duration;

use serde::de::DeserializeOwned;
use serde::Serialize;
use vem_verify::report::write_json;

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

/// Writes `value` as JSON to `path` (`vem_verify::report::write_json`) and reads it back: a
/// study renders its report from what the file holds, as `--report-only` renders it.
pub fn store_json<T: Serialize + DeserializeOwned>(
    path: impl AsRef<Path>,
    value: &T,
) -> Result<T, Box<dyn std::error::Error>> {
    write_json(path.as_ref(), value)?;
    read_json(path)
}

/// Reads the JSON file `path` (what `--report-only` renders), naming the file in an error.
pub fn read_json<T: DeserializeOwned>(
    path: impl AsRef<Path>,
) -> Result<T, Box<dyn std::error::Error>> {
    let path = path.as_ref();
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    Ok(serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?)
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
