//! Plots as SVG documents (plotters), written once for every plot of the workspace: the
//! convergence plots of [`crate::report`], the plots of the studies of `cargo xtask` and the
//! interface plots of `vem run`. A plot is a [`Chart`] (caption, margins, axes, grid, legend)
//! and its [`Layer`]s (lines, dashed lines, dots, squares, each with an optional legend entry),
//! drawn in order on a white [`svg_document`]; [`loglog_svg`] is the log-log plot of the
//! studies (series of points with an optional [`Overlay`]).
//!
//! ```
//! use vem_verify::plot::{chart_svg, Axis, Chart, Layer, Pen, SERIES_COLOURS};
//! let chart = Chart::new(Axis::linear("x", 0.0..1.0), Axis::linear("y", 0.0..1.0));
//! let line = Layer::line(vec![(0.0, 0.0), (1.0, 1.0)], Pen::new(SERIES_COLOURS[0], 2))
//!     .labelled("y = x");
//! let svg = chart_svg((400, 300), &chart, &[line])?;
//! assert!(svg.starts_with("<svg") && svg.contains("y = x"));
//! # Ok::<(), vem_verify::plot::PlotError>(())
//! ```

use std::ops::Range;

use plotters::coord::ranged1d::{Ranged, ValueFormatter};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;

pub use plotters::chart::SeriesLabelPosition as LegendPosition;
pub use plotters::style::{Color, Palette, Palette99, RGBAColor, RGBColor, BLACK, WHITE};

/// A drawing area of an SVG document.
pub type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;

/// A point of a plot, in data coordinates.
pub type Point = (f64, f64);

/// A failure to draw, as text.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct PlotError(pub String);

impl<E: std::error::Error + Send + Sync> From<DrawingAreaErrorKind<E>> for PlotError {
    fn from(error: DrawingAreaErrorKind<E>) -> Self {
        Self(error.to_string())
    }
}

/// The colours of the series, in order (Tableau's ten, readable on white; no yellow).
pub const SERIES_COLOURS: [RGBColor; 10] = [
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

/// The grey of reference lines (slopes, bounds drawn for comparison).
pub const REFERENCE_GREY: RGBColor = RGBColor(90, 90, 90);

/// Font of captions and titles.
const FONT: &str = "sans-serif";
/// Font size of a plot's caption and title lines, in pixels.
pub const CAPTION_SIZE: u32 = 20;
/// Length of a line's sample in the legend, in pixels.
const LEGEND_SAMPLE: i32 = 20;

/// An SVG document of `size` pixels: a white page that `draw` draws on.
///
/// # Errors
/// What `draw` returns, or a drawing failure.
pub fn svg_document(
    size: (u32, u32),
    draw: impl FnOnce(&Area<'_>) -> Result<(), PlotError>,
) -> Result<String, PlotError> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE)?;
        draw(&root)?;
        root.present()?;
    }
    Ok(svg)
}

/// `area` below the title `text` (20-pixel sans-serif), wrapped at word boundaries into lines
/// that fit the area's width (about 10 pixels a character), never cut.
///
/// # Errors
/// A drawing failure.
pub fn titled<'a>(area: &Area<'a>, text: &str) -> Result<Area<'a>, PlotError> {
    let room = ((area.dim_in_pixel().0 as f64 - 40.0) / 10.0).max(20.0) as usize;
    let mut below = area.clone();
    for line in &vem_mesh::io::wrap(text, room) {
        below = below.titled(line, (FONT, CAPTION_SIZE))?;
    }
    Ok(below)
}

/// How an axis maps its values.
#[derive(Debug, Clone, PartialEq)]
pub enum Scale {
    /// Linear, with plotters' ticks.
    Linear,
    /// Logarithmic, with these ticks (e.g. [`log_ticks`]).
    Log(Vec<f64>),
}

/// An axis of a [`Chart`].
pub struct Axis<'a> {
    /// The axis' description.
    pub desc: &'a str,
    /// The range of values shown.
    pub range: Range<f64>,
    /// Linear or logarithmic.
    pub scale: Scale,
    /// Tick labels (plotters' default when `None`).
    pub format: Option<&'a dyn Fn(&f64) -> String>,
    /// The number of tick labels (plotters' default when `None`).
    pub labels: Option<usize>,
}

impl<'a> Axis<'a> {
    /// A linear axis over `range`.
    pub fn linear(desc: &'a str, range: Range<f64>) -> Self {
        Self {
            desc,
            range,
            scale: Scale::Linear,
            format: None,
            labels: None,
        }
    }

    /// A logarithmic axis over `range` with the ticks `ticks`.
    pub fn log(desc: &'a str, range: Range<f64>, ticks: Vec<f64>) -> Self {
        Self {
            scale: Scale::Log(ticks),
            ..Self::linear(desc, range)
        }
    }

    /// Tick labels written by `format`.
    #[must_use]
    pub fn format(mut self, format: &'a dyn Fn(&f64) -> String) -> Self {
        self.format = Some(format);
        self
    }

    /// About `count` tick labels.
    #[must_use]
    pub fn labels(mut self, count: usize) -> Self {
        self.labels = Some(count);
        self
    }
}

/// The frame of a plot: caption, margins, axes, grid and legend.
pub struct Chart<'a> {
    /// The caption above the plot and its font size, if any.
    pub caption: Option<(&'a str, u32)>,
    /// Margin around the plot, in pixels.
    pub margin: u32,
    /// Height of the x labels' area and width of the y labels' area, in pixels.
    pub label_areas: (u32, u32),
    /// The horizontal axis.
    pub x: Axis<'a>,
    /// The vertical axis.
    pub y: Axis<'a>,
    /// Light grid lines between the ticks' bold ones.
    pub light_grid: bool,
    /// Where the legend goes (none when `None`).
    pub legend: Option<LegendPosition>,
}

impl<'a> Chart<'a> {
    /// A chart of the axes `x` and `y` without caption, margin 12, label areas 40 x 70
    /// pixels, without light grid lines, the legend upper right.
    pub fn new(x: Axis<'a>, y: Axis<'a>) -> Self {
        Self {
            caption: None,
            margin: 12,
            label_areas: (40, 70),
            x,
            y,
            light_grid: false,
            legend: Some(LegendPosition::UpperRight),
        }
    }

    /// With the caption `text` in `size`-pixel sans-serif.
    #[must_use]
    pub fn caption(mut self, text: &'a str, size: u32) -> Self {
        self.caption = Some((text, size));
        self
    }

    /// With the margin `margin` and the label areas `(x, y)` (pixels).
    #[must_use]
    pub fn frame(mut self, margin: u32, label_areas: (u32, u32)) -> Self {
        self.margin = margin;
        self.label_areas = label_areas;
        self
    }

    /// With plotters' light grid lines between the ticks.
    #[must_use]
    pub fn light_grid(mut self) -> Self {
        self.light_grid = true;
        self
    }

    /// With the legend at `position`, or none.
    #[must_use]
    pub fn legend(mut self, position: Option<LegendPosition>) -> Self {
        self.legend = position;
        self
    }
}

/// The stroke of a line: colour and width in pixels.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pen {
    /// The colour.
    pub colour: RGBAColor,
    /// The width, in pixels.
    pub width: u32,
}

impl Pen {
    /// A pen of `colour` and `width` pixels.
    pub fn new(colour: impl Color, width: u32) -> Self {
        Self {
            colour: colour.to_rgba(),
            width,
        }
    }

    fn style(self) -> ShapeStyle {
        self.colour.stroke_width(self.width)
    }
}

/// What a layer draws.
#[derive(Debug, Clone, PartialEq)]
pub enum Mark {
    /// A line through the points, in order.
    Line(Vec<Point>, Pen),
    /// A dashed line through the points: dashes of `dash` pixels, `gap` pixels apart.
    Dashed {
        /// The points, in order.
        points: Vec<Point>,
        /// The stroke.
        pen: Pen,
        /// Length of a dash, in pixels.
        dash: u32,
        /// Length of a gap, in pixels.
        gap: u32,
    },
    /// Straight segments (e.g. dashes laid out in data coordinates).
    Segments(Vec<[Point; 2]>, Pen),
    /// A filled circle of the radius (pixels) at each point.
    Dots(Vec<Point>, u32, RGBAColor),
    /// A filled square of the half side (pixels) at each point.
    Squares(Vec<Point>, i32, RGBAColor),
    /// A filled [`Marker`] of the radius (pixels) at each point.
    Markers(Vec<Point>, Marker, u32, RGBAColor),
}

/// The shape of a point marker: series of one colour told apart by their shape.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Marker {
    /// A disc.
    Circle,
    /// A square on its side.
    Square,
    /// A triangle, tip up.
    Triangle,
    /// A square on its corner.
    Diamond,
    /// A triangle, tip down.
    InvertedTriangle,
    /// A regular pentagon.
    Pentagon,
    /// A six-pointed star.
    Star,
    /// A plus sign as a filled cross.
    Plus,
}

impl Marker {
    /// Every shape, in the order series take them.
    pub const ALL: [Marker; 8] = [
        Marker::Circle,
        Marker::Square,
        Marker::Triangle,
        Marker::Diamond,
        Marker::InvertedTriangle,
        Marker::Pentagon,
        Marker::Star,
        Marker::Plus,
    ];

    /// The outline of the shape of radius `radius` pixels about the origin (y down, as on
    /// the page), as a closed polygon: shapes of one radius look about equally heavy.
    fn outline(self, radius: u32) -> Vec<(i32, i32)> {
        let r = f64::from(radius);
        let round = |points: Vec<(f64, f64)>| -> Vec<(i32, i32)> {
            points
                .into_iter()
                .map(|(x, y)| (x.round() as i32, y.round() as i32))
                .collect()
        };
        // `n` points at radius `r`, the first at the angle `start` (radians from up).
        let regular = |n: usize, r: f64, start: f64| -> Vec<(f64, f64)> {
            (0..n)
                .map(|k| {
                    let angle = start + std::f64::consts::TAU * k as f64 / n as f64;
                    (r * angle.sin(), -r * angle.cos())
                })
                .collect()
        };
        match self {
            Marker::Circle => round(regular(16, r, 0.0)),
            Marker::Square => round(regular(4, 1.35 * r, std::f64::consts::FRAC_PI_4)),
            Marker::Triangle => round(regular(3, 1.3 * r, 0.0)),
            Marker::Diamond => round(regular(4, 1.3 * r, 0.0)),
            Marker::InvertedTriangle => round(regular(3, 1.3 * r, std::f64::consts::PI)),
            Marker::Pentagon => round(regular(5, 1.15 * r, 0.0)),
            Marker::Star => {
                let outer = regular(6, 1.4 * r, 0.0);
                let inner = regular(6, 0.7 * r, std::f64::consts::PI / 6.0);
                round(
                    outer
                        .into_iter()
                        .zip(inner)
                        .flat_map(|(o, i)| [o, i])
                        .collect(),
                )
            }
            Marker::Plus => {
                let (a, b) = (1.3 * r, 0.45 * r);
                round(vec![
                    (-b, -a),
                    (b, -a),
                    (b, -b),
                    (a, -b),
                    (a, b),
                    (b, b),
                    (b, a),
                    (-b, a),
                    (-b, b),
                    (-a, b),
                    (-a, -b),
                    (-b, -b),
                ])
            }
        }
    }
}

/// The sample of a layer in the legend.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Glyph {
    /// A short line.
    Line(Pen),
    /// A filled circle of the radius (pixels).
    Dot(u32, RGBAColor),
    /// A short line of the pen with a filled [`Marker`] of the radius (pixels) on it.
    LineMarker(Pen, Marker, u32),
}

/// One layer of a plot: a [`Mark`] and its legend entry, if any.
#[derive(Debug, Clone, PartialEq)]
pub struct Layer {
    /// What is drawn.
    pub mark: Mark,
    /// The legend entry: label and sample.
    pub legend: Option<(String, Glyph)>,
}

impl Layer {
    fn of(mark: Mark) -> Self {
        Self { mark, legend: None }
    }

    /// A line through `points`.
    pub fn line(points: Vec<Point>, pen: Pen) -> Self {
        Self::of(Mark::Line(points, pen))
    }

    /// A dashed line through `points` (dashes of `dash` pixels, `gap` apart).
    pub fn dashed(points: Vec<Point>, pen: Pen, dash: u32, gap: u32) -> Self {
        Self::of(Mark::Dashed {
            points,
            pen,
            dash,
            gap,
        })
    }

    /// Straight segments.
    pub fn segments(segments: Vec<[Point; 2]>, pen: Pen) -> Self {
        Self::of(Mark::Segments(segments, pen))
    }

    /// A filled circle of `radius` pixels at each point.
    pub fn dots(points: Vec<Point>, radius: u32, colour: impl Color) -> Self {
        Self::of(Mark::Dots(points, radius, colour.to_rgba()))
    }

    /// A filled square of half side `half` pixels at each point.
    pub fn squares(points: Vec<Point>, half: i32, colour: impl Color) -> Self {
        Self::of(Mark::Squares(points, half, colour.to_rgba()))
    }

    /// A filled `marker` of `radius` pixels at each point.
    pub fn markers(points: Vec<Point>, marker: Marker, radius: u32, colour: impl Color) -> Self {
        Self::of(Mark::Markers(points, marker, radius, colour.to_rgba()))
    }

    /// In the legend as `label`, with a sample as drawn (a line with its pen, a dot).
    #[must_use]
    pub fn labelled(self, label: impl Into<String>) -> Self {
        let glyph = match &self.mark {
            Mark::Line(_, pen) | Mark::Dashed { pen, .. } | Mark::Segments(_, pen) => {
                Glyph::Line(*pen)
            }
            Mark::Dots(_, radius, colour) => Glyph::Dot(*radius, *colour),
            Mark::Squares(_, half, colour) => Glyph::Line(Pen::new(*colour, 2 * *half as u32)),
            Mark::Markers(_, marker, radius, colour) => {
                Glyph::LineMarker(Pen::new(*colour, 0), *marker, *radius)
            }
        };
        self.legend(label, glyph)
    }

    /// In the legend as `label` with the sample `glyph`.
    #[must_use]
    pub fn legend(mut self, label: impl Into<String>, glyph: Glyph) -> Self {
        self.legend = Some((label.into(), glyph));
        self
    }
}

/// `chart` and its `layers` on a white SVG document of `size` pixels.
///
/// # Errors
/// A drawing failure.
pub fn chart_svg(
    size: (u32, u32),
    chart: &Chart<'_>,
    layers: &[Layer],
) -> Result<String, PlotError> {
    svg_document(size, |root| draw_chart(root, chart, layers))
}

/// Draws `chart` and its `layers` (in order, then the legend) on `area`.
///
/// # Errors
/// A drawing failure.
pub fn draw_chart(area: &Area<'_>, chart: &Chart<'_>, layers: &[Layer]) -> Result<(), PlotError> {
    let mut builder = ChartBuilder::on(area);
    if let Some((text, size)) = chart.caption {
        builder.caption(text, (FONT, size));
    }
    builder
        .margin(chart.margin)
        .x_label_area_size(chart.label_areas.0)
        .y_label_area_size(chart.label_areas.1);
    let (x, y) = (&chart.x, &chart.y);
    let linear = |axis: &Axis<'_>| -> RangedCoordf64 { axis.range.clone().into() };
    match (&x.scale, &y.scale) {
        (Scale::Linear, Scale::Linear) => draw_on(
            builder.build_cartesian_2d(linear(x), linear(y))?,
            chart,
            layers,
        ),
        (Scale::Log(tx), Scale::Log(ty)) => draw_on(
            builder.build_cartesian_2d(
                x.range.clone().log_scale().with_key_points(tx.clone()),
                y.range.clone().log_scale().with_key_points(ty.clone()),
            )?,
            chart,
            layers,
        ),
        (Scale::Linear, Scale::Log(ty)) => draw_on(
            builder.build_cartesian_2d(
                linear(x),
                y.range.clone().log_scale().with_key_points(ty.clone()),
            )?,
            chart,
            layers,
        ),
        (Scale::Log(tx), Scale::Linear) => draw_on(
            builder.build_cartesian_2d(
                x.range.clone().log_scale().with_key_points(tx.clone()),
                linear(y),
            )?,
            chart,
            layers,
        ),
    }
}

/// The mesh, the layers and the legend of a built chart.
fn draw_on<'a, 'b: 'a, X, Y>(
    mut context: ChartContext<'a, SVGBackend<'b>, Cartesian2d<X, Y>>,
    chart: &Chart<'_>,
    layers: &[Layer],
) -> Result<(), PlotError>
where
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    {
        let mut mesh = context.configure_mesh();
        mesh.x_desc(chart.x.desc).y_desc(chart.y.desc);
        if !chart.light_grid {
            mesh.max_light_lines(0);
        }
        if let Some(format) = chart.x.format {
            mesh.x_label_formatter(format);
        }
        if let Some(format) = chart.y.format {
            mesh.y_label_formatter(format);
        }
        if let Some(count) = chart.x.labels {
            mesh.x_labels(count);
        }
        if let Some(count) = chart.y.labels {
            mesh.y_labels(count);
        }
        mesh.draw()?;
    }
    for layer in layers {
        let annotation = match &layer.mark {
            Mark::Line(points, pen) => {
                context.draw_series(LineSeries::new(points.iter().copied(), pen.style()))?
            }
            Mark::Dashed {
                points,
                pen,
                dash,
                gap,
            } => context.draw_series(DashedLineSeries::new(
                points.iter().copied(),
                *dash,
                *gap,
                pen.style(),
            ))?,
            Mark::Segments(segments, pen) => context.draw_series(
                segments
                    .iter()
                    .map(|s| PathElement::new(s.to_vec(), pen.style())),
            )?,
            Mark::Dots(points, radius, colour) => context.draw_series(
                points
                    .iter()
                    .map(|&p| Circle::new(p, *radius, colour.filled())),
            )?,
            Mark::Squares(points, half, colour) => {
                let half = *half;
                context.draw_series(points.iter().map(|&p| {
                    EmptyElement::at(p)
                        + Rectangle::new([(-half, -half), (half, half)], colour.filled())
                }))?
            }
            Mark::Markers(points, marker, radius, colour) => {
                let outline = marker.outline(*radius);
                context.draw_series(points.iter().map(|&p| {
                    EmptyElement::at(p) + Polygon::new(outline.clone(), colour.filled())
                }))?
            }
        };
        if let Some((label, glyph)) = &layer.legend {
            annotation.label(label.as_str());
            match *glyph {
                Glyph::Line(pen) => annotation.legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + LEGEND_SAMPLE, y)], pen.style())
                }),
                Glyph::Dot(radius, colour) => annotation.legend(move |(x, y)| {
                    Circle::new((x + LEGEND_SAMPLE / 2, y), radius, colour.filled())
                }),
                Glyph::LineMarker(pen, marker, radius) => {
                    let outline: Vec<(i32, i32)> = marker
                        .outline(radius)
                        .into_iter()
                        .map(|(dx, dy)| (dx + LEGEND_SAMPLE / 2, dy))
                        .collect();
                    annotation.legend(move |(x, y)| {
                        EmptyElement::at((x, y))
                            + PathElement::new(vec![(0, 0), (LEGEND_SAMPLE, 0)], pen.style())
                            + Polygon::new(outline.clone(), pen.colour.filled())
                    })
                }
            };
        }
    }
    if let Some(position) = &chart.legend {
        context
            .configure_series_labels()
            .position(position.clone())
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()?;
    }
    Ok(())
}

/// Ticks of a logarithmic axis: the powers of ten in `range`, and 2 and 5 times them when the
/// range touches fewer than four decades; every integer multiple when that still leaves fewer
/// than three ticks (a range within about a decade).
///
/// ```
/// use vem_verify::plot::log_ticks;
/// assert_eq!(log_ticks(0.03..0.7), vec![0.05, 0.1, 0.2, 0.5]);
/// assert_eq!(log_ticks(1e-6..2e-1), vec![1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 1e-1]);
/// assert_eq!(log_ticks(9e-3..0.3).len(), 5); // 0.01, 0.02, 0.05, 0.1, 0.2
/// assert_eq!(log_ticks(0.66..1.5).len(), 4); // 0.7, 0.8, 0.9, 1
/// ```
pub fn log_ticks(range: Range<f64>) -> Vec<f64> {
    let (low, high) = (
        range.start.log10().floor() as i32,
        range.end.log10().ceil() as i32,
    );
    let ticks = |mantissas: &[f64]| -> Vec<f64> {
        (low..=high)
            .flat_map(|k| mantissas.iter().map(move |m| m * 10f64.powi(k)))
            .filter(|v| range.contains(v))
            .collect()
    };
    if high - low >= 4 {
        return ticks(&[1.0]);
    }
    let coarse = ticks(&[1.0, 2.0, 5.0]);
    if coarse.len() >= 3 {
        coarse
    } else {
        // Less than a decade: every integer mantissa.
        ticks(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0])
    }
}

/// `v` with three significant digits in fixed notation (0.354, 0.0221).
pub fn three_digits(v: f64) -> String {
    let precision = (2 - v.abs().log10().floor() as i32).max(0) as usize;
    format!("{v:.precision$}")
}

/// Whether both coordinates of `p` are positive and finite: what a log-log plot can show.
pub fn positive(p: &Point) -> bool {
    p.0 > 0.0 && p.1 > 0.0 && p.0.is_finite() && p.1.is_finite()
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
    Front(&'a str, &'a [Point]),
    /// A thin dashed grey line without markers: a reference slope `C h^p`.
    Reference(&'a str, &'a [Point]),
}

/// A log-log plot (900 x 600 SVG) of `series` (label, points; non-positive values are left
/// out), each a line with dots in [`SERIES_COLOURS`], and an optional [`Overlay`]; the ranges
/// reach a factor 1.5 beyond the points, the ticks are [`log_ticks`].
///
/// # Errors
/// A drawing failure.
pub fn loglog_svg(
    plot: &LogLogPlot<'_>,
    series: &[(String, Vec<Point>)],
    overlay: Option<Overlay<'_>>,
) -> Result<String, PlotError> {
    let styled: Vec<StyledSeries<'_>> = series
        .iter()
        .enumerate()
        .map(|(k, (label, points))| StyledSeries {
            label,
            points,
            colour: SERIES_COLOURS[k % SERIES_COLOURS.len()],
            marker: None,
        })
        .collect();
    loglog_styled_svg(plot, &styled, overlay)
}

/// A series of a [`loglog_styled_svg`] plot: its label, points, colour and marker.
#[derive(Debug, Clone, Copy)]
pub struct StyledSeries<'a> {
    /// The legend's label.
    pub label: &'a str,
    /// The points (non-positive ones are left out).
    pub points: &'a [Point],
    /// The colour of its line and markers.
    pub colour: RGBColor,
    /// The marker at its points; `None`: a dot.
    pub marker: Option<Marker>,
}

/// [`loglog_svg`] with the colour and the marker of every series chosen by the caller: many
/// series told apart by two properties (e.g. the colour for a solver, the marker for a case).
///
/// # Errors
/// A drawing failure.
pub fn loglog_styled_svg(
    plot: &LogLogPlot<'_>,
    series: &[StyledSeries<'_>],
    overlay: Option<Overlay<'_>>,
) -> Result<String, PlotError> {
    let overlaid = overlay.map(|o| match o {
        Overlay::Front(label, p) | Overlay::Reference(label, p) => (label, sorted_positive(p)),
    });
    let mut layers = Vec::new();
    for s in series {
        let points = sorted_positive(s.points);
        let (colour, pen) = (s.colour, Pen::new(s.colour, 1));
        let (glyph, marks) = match s.marker {
            None => (Glyph::Line(pen), Layer::dots(points.clone(), 3, colour)),
            Some(marker) => (
                Glyph::LineMarker(pen, marker, 4),
                Layer::markers(points.clone(), marker, 4, colour),
            ),
        };
        layers.push(Layer::line(points, Pen::new(colour, 2)).legend(s.label, glyph));
        layers.push(marks);
    }
    match (overlay, overlaid) {
        (Some(Overlay::Front(..)), Some((label, points))) => {
            layers.push(Layer::line(points.clone(), Pen::new(BLACK, 3)).labelled(label));
            layers.push(Layer::squares(points, 4, BLACK));
        }
        (Some(Overlay::Reference(..)), Some((label, points))) => {
            layers.push(Layer::dashed(points, Pen::new(REFERENCE_GREY, 1), 10, 6).labelled(label));
        }
        _ => {}
    }
    let all = layers.iter().flat_map(|l| match &l.mark {
        Mark::Line(p, _) | Mark::Dashed { points: p, .. } => p.as_slice(),
        _ => &[],
    });
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
    let chart = Chart::new(
        Axis::log(plot.x_desc, x_lo..x_hi, log_ticks(x_lo..x_hi)).format(&plot.x_format),
        Axis::log(plot.y_desc, y_lo..y_hi, log_ticks(y_lo..y_hi)).format(&plot.y_format),
    )
    .caption(plot.caption, CAPTION_SIZE)
    .frame(15, (40, 55));
    chart_svg((900, 600), &chart, &layers)
}

/// The positive points of `points` (see [`positive`]), sorted by x.
fn sorted_positive(points: &[Point]) -> Vec<Point> {
    let mut points: Vec<Point> = points.iter().filter(|p| positive(p)).copied().collect();
    points.sort_by(|a, b| a.0.total_cmp(&b.0));
    points
}

#[cfg(test)]
mod tests {
    use super::Marker;

    /// The signed area (shoelace, y down) and the centroid of a closed polygon.
    fn area_and_centroid(outline: &[(i32, i32)]) -> (f64, (f64, f64)) {
        let (mut area, mut cx, mut cy) = (0.0, 0.0, 0.0);
        for (k, &(x0, y0)) in outline.iter().enumerate() {
            let (x1, y1) = outline[(k + 1) % outline.len()];
            let cross = f64::from(x0 * y1 - x1 * y0);
            area += cross / 2.0;
            cx += f64::from(x0 + x1) * cross / 6.0;
            cy += f64::from(y0 + y1) * cross / 6.0;
        }
        (area, (cx / area, cy / area))
    }

    /// Every marker is a polygon centred on its point (centroid within a pixel), turning one
    /// way, about as heavy as the disc of its radius (0.5 to 1.3 of its area), and the shapes
    /// are all different.
    #[test]
    fn markers_are_centred_and_about_equally_heavy() {
        let radius = 8;
        let disc = std::f64::consts::PI * f64::from(radius * radius);
        for marker in Marker::ALL {
            let outline = marker.outline(radius);
            let (area, (cx, cy)) = area_and_centroid(&outline);
            assert!(
                (0.5..1.3).contains(&(area.abs() / disc)),
                "{marker:?}: area {area} against the disc's {disc}"
            );
            assert!(
                cx.abs() < 1.0 && cy.abs() < 1.0,
                "{marker:?}: centroid ({cx}, {cy})"
            );
        }
        for (i, a) in Marker::ALL.iter().enumerate() {
            for b in &Marker::ALL[i + 1..] {
                assert_ne!(a.outline(radius), b.outline(radius), "{a:?} and {b:?}");
            }
        }
    }
}
