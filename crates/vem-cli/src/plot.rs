//! Plots along the contact interface (SVG, drawn with `vem_verify::plot`): the contact pressure (with the Hertz
//! curve when asked for, and the friction traction against its bound with friction), and the
//! slip coloured by node status.
//!
//! The horizontal axis is the coordinate (x or y) along which the interface runs furthest,
//! so that a flat or gently curved interface reads left to right.

use std::ops::Range;
use std::path::Path;

use vem_contact::{InterfaceNode, NodeStatus};
use vem_mesh::io::write_atomically;
use vem_verify::plot::{
    draw_chart, svg_document, titled, Area, Axis, Chart, Color, Layer, Pen, PlotError, RGBColor,
    BLACK, SERIES_COLOURS,
};

use crate::CliError;
use vem_scene::HertzComparison;

/// Points of a curve.
type Curve = Vec<(f64, f64)>;

/// The Cattaneo-Mindlin tangential traction for a Hertz pair under a tangential load: what
/// the pressure plot draws beside the computed friction traction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct CattaneoMindlin {
    /// The Coulomb coefficient `F`.
    pub coefficient: f64,
    /// The tangential load `Q` on body A, signed along the interface's tangent (the sum of
    /// the pair's nodal friction forces).
    pub tangential_load: f64,
}

impl CattaneoMindlin {
    /// `Q / (F P)` for Hertz's load `P`.
    pub(crate) fn ratio(&self, hertz: &HertzComparison) -> f64 {
        self.tangential_load.abs() / (self.coefficient * hertz.load)
    }

    /// The analytic traction along the tangent at 201 points across Hertz's zone (centred
    /// where the computed zone is), signed as `Q`: `q(s) = F p0 (sqrt(1 - s^2/a^2) - (c/a)
    /// sqrt(1 - s^2/c^2))`, the second term only inside the stick zone `|s| < c`,
    /// `c = a sqrt(1 - Q/(F P))`; and `c`. `None` when Hertz's values are not positive.
    pub(crate) fn curve(&self, hertz: &HertzComparison, c: usize) -> Option<(Curve, f64)> {
        let exact = vem_verify::exact::HertzContact::try_new(
            hertz.radius,
            hertz.effective_modulus,
            hertz.load,
        )
        .ok()?;
        let ratio = self.ratio(hertz);
        let sign = self.tangential_load.signum();
        let a = exact.half_width();
        let points = (0..=200)
            .map(|k| {
                let s = a * (-1.0 + 2.0 * k as f64 / 200.0);
                (
                    hertz.centre[c] + s,
                    sign * exact.tangential_traction(s, self.coefficient, ratio),
                )
            })
            .collect();
        Some((points, exact.stick_half_width(ratio)))
    }
}

const PRESSURE: RGBColor = SERIES_COLOURS[0];
const HERTZ: RGBColor = SERIES_COLOURS[2];
const FRICTION: RGBColor = SERIES_COLOURS[1];
const CATTANEO: RGBColor = SERIES_COLOURS[3];
const BOUND: RGBColor = SERIES_COLOURS[8];
const STICK: RGBColor = SERIES_COLOURS[0];
const SLIP: RGBColor = SERIES_COLOURS[2];
const OPEN: RGBColor = RGBColor(170, 170, 170);

/// Which coordinate the interface runs along: 0 for x, 1 for y.
fn axis(nodes: &[InterfaceNode]) -> usize {
    let extent = |c: usize| {
        let values = nodes.iter().map(|n| n.position[c]);
        values.clone().fold(f64::NEG_INFINITY, f64::max) - values.fold(f64::INFINITY, f64::min)
    };
    usize::from(extent(1) > extent(0))
}

/// `lo..hi` padded by 5% below and `top` (a fraction of the span) above, or a unit range
/// around a single value.
fn padded(values: impl Iterator<Item = f64>, top: f64) -> Range<f64> {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if lo > hi {
        return 0.0..1.0;
    }
    let span = hi - lo;
    if span <= 1e-300 {
        let half = if lo.abs() > 0.0 { 0.5 * lo.abs() } else { 1.0 };
        return (lo - half)..(hi + half);
    }
    (lo - 0.05 * span)..(hi + top * span)
}

/// Room above the curves for the legend, as a fraction of the value span.
const LEGEND_ROOM: f64 = 0.35;
/// Room above the curves for the legend of a pressure plot with friction (twice the rows:
/// the friction traction, its nodal values, the bound and Cattaneo-Mindlin's curve), so that
/// the legend stays clear of the pressure's peak.
const FRICTION_LEGEND_ROOM: f64 = 0.55;

/// Renders `draw` into an SVG document and writes it atomically to `path`.
fn svg_file(
    path: &Path,
    width: f64,
    draw: impl FnOnce(&Area<'_>) -> Result<(), PlotError>,
) -> Result<(), CliError> {
    let size = (width.round() as u32, (0.6 * width).round() as u32);
    let document = svg_document(size, draw).map_err(|e| CliError::Plot {
        path: path.to_path_buf(),
        reason: e.0,
    })?;
    write_atomically(path, |w| w.write_all(document.as_bytes())).map_err(|source| CliError::Mesh {
        context: path.display().to_string(),
        source,
    })
}

/// `pressure.svg`: the consistent contact pressure along the interface (line) and the raw
/// nodal values `lambda_N / l_x` (dots); with `hertz`, Hertz's elliptical distribution for the
/// same load; with `friction_bound` (per node, per unit length), the consistent friction
/// traction (line), the raw `friction_force / l_x` (dots) and the bound `±g`.
pub(crate) fn pressure(
    path: &Path,
    title: &str,
    nodes: &[InterfaceNode],
    hertz: Option<&HertzComparison>,
    friction_bound: Option<Vec<f64>>,
    cattaneo: Option<CattaneoMindlin>,
    width: f64,
) -> Result<(), CliError> {
    let c = axis(nodes);
    let cattaneo_curve: Option<(Curve, String)> = hertz
        .zip(cattaneo)
        .filter(|_| friction_bound.is_some())
        .and_then(|(h, cm)| {
            let (points, stick) = cm.curve(h, c)?;
            let four = |v: f64| vem_scene::short(format!("{v:.3e}").parse().unwrap_or(v));
            let label = format!(
                "Cattaneo-Mindlin: F = {}, Q/(F P) = {}, stick zone c = {}",
                four(cm.coefficient),
                four(cm.ratio(h)),
                four(stick)
            );
            Some((points, label))
        });
    let name = ["x", "y"][c];
    let position = |n: &InterfaceNode| n.position[c];
    let pressure: Vec<(f64, f64)> = nodes.iter().map(|n| (position(n), n.pressure)).collect();
    let consistent: Vec<(f64, f64)> = nodes
        .iter()
        .map(|n| (position(n), n.consistent_pressure))
        .collect();
    let hertz_curve: Vec<(f64, f64)> = hertz
        .filter(|h| h.half_width > 0.0)
        .map(|h| {
            let (centre, a) = (h.centre[c], h.half_width);
            (0..=200)
                .map(|k| {
                    let s = -1.0 + 2.0 * k as f64 / 200.0;
                    (
                        centre + s * a,
                        h.peak_pressure * (1.0 - s * s).max(0.0).sqrt(),
                    )
                })
                .collect()
        })
        .unwrap_or_default();
    let friction: Option<(Curve, Curve, Curve)> = friction_bound.map(|bound| {
        let traction = nodes
            .iter()
            .map(|n| (position(n), n.friction_t() / n.tributary_measure))
            .collect();
        let consistent_traction = nodes
            .iter()
            .map(|n| (position(n), n.consistent_friction_t()))
            .collect();
        let bounds = nodes
            .iter()
            .zip(bound)
            .map(|(n, g)| (position(n), g))
            .collect();
        (traction, consistent_traction, bounds)
    });
    // Zoomed to the contact zone (its active nodes, a fifth of its width and two node
    // spacings on each side, and Hertz's zone), the whole interface when nothing touches.
    let active: Vec<f64> = nodes
        .iter()
        .filter(|n| n.status.is_active())
        .map(position)
        .collect();
    let x_range = if active.is_empty() {
        padded(pressure.iter().chain(&hertz_curve).map(|p| p.0), 0.05)
    } else {
        let lo = active.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = active.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let spacing = 2.0 * (hi - lo).max(f64::MIN_POSITIVE) / active.len().max(1) as f64;
        let margin = (0.2 * (hi - lo)).max(2.0 * spacing);
        let (all_lo, all_hi) = pressure
            .iter()
            .map(|p| p.0)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
                (a.min(x), b.max(x))
            });
        let (h_lo, h_hi) = hertz_curve
            .iter()
            .map(|p| p.0)
            .fold((lo, hi), |(a, b), x| (a.min(x), b.max(x)));
        (h_lo - margin).max(all_lo)..(h_hi + margin).min(all_hi)
    };
    let in_view = |p: &&(f64, f64)| x_range.contains(&p.0);
    let y_range = padded(
        pressure
            .iter()
            .filter(in_view)
            .chain(consistent.iter().filter(in_view))
            .chain(&hertz_curve)
            .chain(cattaneo_curve.iter().flat_map(|(points, _)| points))
            .map(|p| p.1)
            .chain(friction.iter().flat_map(|(t, c, b)| {
                t.iter()
                    .chain(c)
                    .map(|p| p.1)
                    .chain(b.iter().flat_map(|p| [p.1, -p.1]))
            }))
            .chain([0.0]),
        if friction.is_some() {
            FRICTION_LEGEND_ROOM
        } else {
            LEGEND_ROOM
        },
    );
    let hertz_label = hertz.map_or_else(String::new, |h| {
        // Four significant digits, as the summary prints them.
        let four = |v: f64| vem_scene::short(format!("{v:.3e}").parse().unwrap_or(v));
        format!(
            "Hertz: p0 sqrt(1 - (x - c)^2 / a^2), p0 = {}, a = {}",
            four(h.peak_pressure),
            four(h.half_width)
        )
    });
    let mut layers = Vec::new();
    if !hertz_curve.is_empty() {
        layers.push(Layer::line(hertz_curve, Pen::new(HERTZ, 2)).labelled(hertz_label));
    }
    let visible =
        |points: &[(f64, f64)]| -> Curve { points.iter().filter(in_view).copied().collect() };
    layers.push(
        Layer::line(visible(&consistent), Pen::new(PRESSURE, 2))
            .labelled("consistent pressure (projection of the normal forces, >= 0)"),
    );
    layers.push(
        Layer::dots(visible(&pressure), 2, PRESSURE.mix(0.5))
            .labelled("nodal pressure (normal force / tributary length)"),
    );
    if let Some((points, label)) = cattaneo_curve {
        layers.push(Layer::line(points, Pen::new(CATTANEO, 2)).labelled(label));
    }
    let y_desc = if friction.is_some() {
        "pressure, friction traction"
    } else {
        "contact pressure"
    };
    if let Some((traction, consistent_traction, bounds)) = &friction {
        layers.push(
            Layer::line(visible(consistent_traction), Pen::new(FRICTION, 2))
                .labelled("consistent friction traction (projection within the bound)"),
        );
        layers.push(
            Layer::dots(visible(traction), 2, FRICTION.mix(0.5))
                .labelled("nodal friction traction (friction force / tributary length)"),
        );
        let bounds = visible(bounds);
        let below = bounds.iter().map(|&(x, g)| (x, -g)).collect();
        layers.push(Layer::line(bounds, Pen::new(BOUND, 1)).labelled("+/- friction bound"));
        layers.push(Layer::line(below, Pen::new(BOUND, 1)));
    }
    let chart = Chart::new(
        Axis::linear(name, x_range.clone()),
        Axis::linear(y_desc, y_range),
    );
    svg_file(path, width, |root| {
        let area = titled(root, &format!("{title}: contact pressure"))?;
        draw_chart(&area, &chart, &layers)
    })
}

/// `slip.svg`: the slip `[u]_tau` along the interface, each node marked by its status.
pub(crate) fn slip(
    path: &Path,
    title: &str,
    nodes: &[InterfaceNode],
    width: f64,
) -> Result<(), CliError> {
    let c = axis(nodes);
    let points: Vec<(f64, f64)> = nodes.iter().map(|n| (n.position[c], n.slip_t())).collect();
    let x_range = padded(points.iter().map(|p| p.0), 0.05);
    let y_range = padded(points.iter().map(|p| p.1).chain([0.0]), LEGEND_ROOM);
    let mut layers = vec![Layer::line(points.clone(), Pen::new(BLACK.mix(0.4), 1))];
    for (status, colour) in [
        (NodeStatus::Stick, STICK),
        (NodeStatus::Slip, SLIP),
        (NodeStatus::Open, OPEN),
    ] {
        let marked: Curve = nodes
            .iter()
            .zip(&points)
            .filter(|(n, _)| n.status == status)
            .map(|(_, &p)| p)
            .collect();
        if !marked.is_empty() {
            layers.push(Layer::dots(marked, 3, colour).labelled(status.name()));
        }
    }
    let chart = Chart::new(
        Axis::linear(["x", "y"][c], x_range),
        Axis::linear("slip [u]_tau", y_range),
    )
    .frame(12, (40, 80));
    svg_file(path, width, |root| {
        let area = titled(root, &format!("{title}: slip"))?;
        draw_chart(&area, &chart, &layers)
    })
}

/// `history.svg`: along a load history, the load-displacement curve (the normal contact
/// force `F_y` on body A of the first pair against the load point's `u_y`) and the tangential
/// force-displacement curve (`F_x` against `u_x`) side by side, one dot per step joined in the
/// order of the steps, so that an unloading and reloading shows its loop. The load point is
/// [`vem_scene::StepSummary::displacement`]; without one, both against the pseudo-time.
pub(crate) fn history(
    path: &Path,
    title: &str,
    steps: &[vem_scene::StepSummary],
    width: f64,
) -> Result<(), CliError> {
    let against_time = steps.iter().any(|s| s.displacement.len() < 2);
    let curve = |c: usize| -> Curve {
        steps
            .iter()
            .map(|s| {
                let x = if against_time {
                    s.time
                } else {
                    s.displacement[c]
                };
                (x, s.force_on_body_a.get(c).copied().unwrap_or(0.0))
            })
            .collect()
    };
    let panels = [
        (curve(1), PRESSURE, "normal", "F_y", "u_y"),
        (curve(0), FRICTION, "tangential", "F_x", "u_x"),
    ];
    svg_file(path, width, |root| {
        let area = titled(root, &format!("{title}: load history"))?;
        let (left, right) = area.split_horizontally(area.dim_in_pixel().0 / 2);
        for (area, (points, colour, kind, force, displacement)) in [left, right].iter().zip(&panels)
        {
            let x_desc = if against_time {
                "pseudo-time t".to_string()
            } else {
                format!("load point displacement {displacement}")
            };
            let caption = format!("{kind} force {force} on body A");
            let chart = Chart::new(
                Axis::linear(&x_desc, padded(points.iter().map(|p| p.0), 0.05)).labels(5),
                Axis::linear(force, padded(points.iter().map(|p| p.1).chain([0.0]), 0.05)),
            )
            .caption(&caption, 16)
            .legend(None);
            let layers = [
                Layer::line(points.clone(), Pen::new(*colour, 1)),
                Layer::dots(points.clone(), 3, *colour),
            ];
            draw_chart(area, &chart, &layers)?;
        }
        Ok(())
    })
}

/// The radial profile of a contact surface in space, as an SVG document of `width` x
/// `height` pixels: the consistent pressure of every node against its distance `r` from the
/// centre of the contact zone in the plane of the pair (dots), and with `hertz` Hertz's
/// `p0 sqrt(1 - r^2/a^2)` for the same load (line). `radius_of` gives a node's `r`.
pub(crate) fn radial_profile(
    nodes: &[InterfaceNode<3>],
    radius_of: &dyn Fn(&InterfaceNode<3>) -> f64,
    hertz: Option<&HertzComparison>,
    (width, height): (u32, u32),
) -> Result<String, String> {
    let points: Curve = nodes
        .iter()
        .map(|n| (radius_of(n), n.consistent_pressure))
        .collect();
    let hertz_curve: Curve = hertz
        .filter(|h| h.half_width > 0.0)
        .map(|h| {
            (0..=200)
                .map(|k| {
                    let s = k as f64 / 200.0;
                    (
                        s * h.half_width,
                        h.peak_pressure * (1.0 - s * s).max(0.0).sqrt(),
                    )
                })
                .collect()
        })
        .unwrap_or_default();
    // Out to twice the contact radius (Hertz's or that of the nodes in contact), or over
    // every node when nothing touches.
    let reach = hertz
        .map(|h| h.half_width.max(h.computed_half_width))
        .filter(|&a| a > 0.0)
        .map_or_else(
            || points.iter().map(|p| p.0).fold(0.0, f64::max),
            |a| 2.0 * a,
        );
    let reach = if reach > 0.0 { reach } else { 1.0 };
    let in_view: Curve = points.into_iter().filter(|p| p.0 <= reach).collect();
    let top = in_view
        .iter()
        .chain(&hertz_curve)
        .map(|p| p.1)
        .fold(0.0, f64::max);
    let top = if top > 0.0 { top } else { 1.0 };
    let hertz_label = hertz.map_or_else(String::new, |h| {
        let four = |v: f64| vem_scene::short(format!("{v:.3e}").parse().unwrap_or(v));
        format!(
            "Hertz: p0 sqrt(1 - r^2 / a^2), p0 = {}, a = {}",
            four(h.peak_pressure),
            four(h.half_width)
        )
    });
    let mut layers = vec![
        Layer::dots(in_view, 2, PRESSURE.mix(0.6)).labelled("consistent pressure at the nodes")
    ];
    if !hertz_curve.is_empty() {
        layers.push(Layer::line(hertz_curve, Pen::new(HERTZ, 2)).labelled(hertz_label));
    }
    let chart = Chart::new(
        Axis::linear(
            "r (distance from the centre of the contact zone, in its plane)",
            0.0..reach * 1.02,
        ),
        Axis::linear("contact pressure", 0.0..top * (1.0 + LEGEND_ROOM)),
    )
    .frame(12, (40, 55));
    svg_document((width, height), |root| {
        let area = titled(root, "pressure against r")?;
        draw_chart(&area, &chart, &layers)
    })
    .map_err(|e| e.0)
}
