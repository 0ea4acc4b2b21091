//! SVG pictures of meshes: polygons, boundary parts with a legend, optional vertex dots,
//! per-cell colours with a colour bar, and deformed meshes drawn over the undeformed ones.
//!
//! One picture may hold several meshes ([`SvgLayer`]s, e.g. two bodies in contact); they share
//! one scale, one colour range and one displacement magnification, so that what is drawn can be
//! compared across bodies.

use std::fmt::Write as _;
use std::path::Path;

use super::raster::{base64, Palette, Raster};
use super::{write_atomically, xml_escape};
use crate::{Mesh, MeshError, Point, Vector};

/// Colours of the boundary parts, in order (repeated after ten parts).
const PART_COLOURS: [&str; 10] = [
    "#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf",
    "#bcbd22", "#7f7f7f",
];

/// Control points of the colour map (viridis, sampled at 0, 1/8, ..., 1), interpolated
/// linearly in RGB.
const COLOUR_MAP: [[f64; 3]; 9] = [
    [68.0, 1.0, 84.0],
    [71.0, 44.0, 122.0],
    [59.0, 81.0, 139.0],
    [44.0, 113.0, 142.0],
    [33.0, 144.0, 141.0],
    [39.0, 173.0, 129.0],
    [92.0, 200.0, 99.0],
    [170.0, 220.0, 50.0],
    [253.0, 231.0, 37.0],
];

/// The default [`SvgOptions::vector_cell_limit`]: under 1 MB of SVG drawn as vectors.
pub const VECTOR_CELL_LIMIT: usize = 5_000;

/// Raster pixels per picture pixel for large meshes (sharp on high-density screens).
const RASTER_SCALE: f64 = 2.0;

/// Height of the title line, in pixels.
const TITLE_HEIGHT: f64 = 28.0;
/// Height of one legend entry, in pixels.
const LEGEND_ROW: f64 = 18.0;
/// Height of the colour bar, in pixels.
const COLOUR_BAR_HEIGHT: f64 = 200.0;
/// Height of each further line of a wrapped title, in pixels.
const TITLE_LINE: f64 = 20.0;
/// Room left of the drawing for the y axis (ticks, labels, name), in pixels.
const AXIS_LEFT: f64 = 76.0;
/// Room below the drawing for the x axis (ticks, labels, name), in pixels.
const AXIS_BOTTOM: f64 = 44.0;
/// Fill of cells without values whose edges are not drawn.
const UNCOLOURED: &str = "#e4e4e4";
/// [`UNCOLOURED`] as red, green and blue.
const UNCOLOURED_RGB: [u8; 3] = [0xe4, 0xe4, 0xe4];
/// The ink of the edges in a raster picture: dark grey, alpha 150.
const EDGE_INK: [u8; 4] = [48, 48, 48, 150];
/// Colour of the marked points.
const MARK_COLOUR: &str = "#e8112d";
/// The default [`SvgOptions::edge_min_pixels`].
pub const EDGE_MIN_PIXELS: f64 = 6.0;

/// One mesh in a picture, with what to draw on it.
#[derive(Debug, Clone, Copy)]
pub struct SvgLayer<'a> {
    /// The mesh.
    pub mesh: &'a Mesh,
    /// Name of the mesh in the legend ("upper body"), prefixed to its part names.
    pub label: Option<&'a str>,
    /// One value per polygon: polygons are filled by the colour map, with a colour bar.
    pub cell_values: Option<&'a [f64]>,
    /// One displacement per vertex: the mesh is drawn at `x + magnification * u` over its
    /// undeformed outline (dashed grey).
    pub displacement: Option<&'a [Vector]>,
}

impl<'a> SvgLayer<'a> {
    /// The mesh alone: outlines and boundary parts.
    pub fn new(mesh: &'a Mesh) -> Self {
        Self {
            mesh,
            label: None,
            cell_values: None,
            displacement: None,
        }
    }

    /// Names the mesh in the legend.
    pub fn with_label(mut self, label: &'a str) -> Self {
        self.label = Some(label);
        self
    }

    /// Fills polygon `p` with the colour of `values[p]`.
    pub fn with_cell_values(mut self, values: &'a [f64]) -> Self {
        self.cell_values = Some(values);
        self
    }

    /// Draws the mesh displaced by `displacement` (one vector per vertex).
    pub fn with_displacement(mut self, displacement: &'a [Vector]) -> Self {
        self.displacement = Some(displacement);
        self
    }
}

/// How to draw a picture (shared by all its layers).
#[derive(Debug, Clone, PartialEq)]
pub struct SvgOptions {
    /// Width of the picture in pixels; the height follows from the meshes' aspect ratio.
    pub width: f64,
    /// Blank border around the drawing, in pixels.
    pub margin: f64,
    /// Title written above the drawing.
    pub title: Option<String>,
    /// Draw a dot at every vertex.
    pub vertex_dots: bool,
    /// Draw the boundary parts in distinct colours, with a legend.
    pub parts: bool,
    /// Displacements are drawn multiplied by this factor.
    pub magnification: f64,
    /// Title of the colour bar.
    pub value_label: String,
    /// Values mapped to the two ends of the colour map; `None`: the smallest and largest
    /// cell value over all layers.
    pub value_range: Option<(f64, f64)>,
    /// Pictures of more polygons than this (over all layers) draw the cells as an embedded PNG
    /// at twice the picture's resolution, with the boundaries and parts as vectors above it,
    /// so that the file's size depends on the picture, not on the mesh (vertex dots are then
    /// left out). Below it every polygon is an SVG element.
    pub vector_cell_limit: usize,
    /// Axes below and left of the drawing, with ticks at round values of the meshes'
    /// coordinates (as drawn: displaced positions are read on the same axes).
    pub axes: bool,
    /// The unit of length written after the axes' names (`x [mm]`); `None`: `x` and `y`.
    pub length_unit: Option<String>,
    /// Lines of text written below the legend and colour bar (e.g. the displacement scale).
    pub notes: Vec<String>,
    /// Points marked by crosses, with a legend entry.
    pub marks: Option<SvgMarks>,
    /// A layer's interior edges are drawn only when its cells are at least this many pixels
    /// across (the square root of their mean area), and then only the edges at least half
    /// as long: finer meshes (or the fine parts of graded ones) are drawn as their colours and
    /// boundary, not as a mesh of lines that hides them.
    pub edge_min_pixels: f64,
}

/// Points marked by crosses in a picture (e.g. where a constraint is violated), at the
/// coordinates they are drawn at.
#[derive(Debug, Clone, PartialEq)]
pub struct SvgMarks {
    /// The legend entry of the marks.
    pub label: String,
    /// Where the crosses are drawn, in the meshes' coordinates.
    pub points: Vec<Point>,
}

impl Default for SvgOptions {
    /// 800 pixels wide, 20 pixels margin, parts with a legend, no dots, magnification 1,
    /// vectors up to [`VECTOR_CELL_LIMIT`] polygons, no axes, interior edges from
    /// [`EDGE_MIN_PIXELS`] pixels.
    fn default() -> Self {
        Self {
            width: 800.0,
            margin: 20.0,
            title: None,
            vertex_dots: false,
            parts: true,
            magnification: 1.0,
            value_label: "value".into(),
            value_range: None,
            vector_cell_limit: VECTOR_CELL_LIMIT,
            axes: false,
            length_unit: None,
            notes: Vec::new(),
            marks: None,
            edge_min_pixels: EDGE_MIN_PIXELS,
        }
    }
}

/// Writes a picture of `mesh` (polygons and, per `options`, boundary parts and vertex dots).
///
/// The drawing maps the mesh's bounding box, y pointing up, onto a box `options.margin` pixels
/// inside the picture (below the title), keeping the aspect ratio. For cell colours or a
/// displacement use [`write_svg_layers`] with one [`SvgLayer`].
pub fn write_svg(
    path: impl AsRef<Path>,
    mesh: &Mesh,
    options: &SvgOptions,
) -> Result<(), MeshError> {
    write_svg_layers(path, &[SvgLayer::new(mesh)], options)
}

/// Writes a picture of several meshes drawn over one another in the given order, at one
/// scale (e.g. two bodies in contact, each with its displacement).
///
/// ```
/// use vem_mesh::generators::{structured_quads, Rectangle};
/// use vem_mesh::io::{write_svg_layers, SvgLayer, SvgOptions};
/// use vem_mesh::{Point, Vector};
///
/// let foundation = structured_quads(&Rectangle::new(Point::new(0.0, -1.0), Point::new(2.0, 0.0)), 4, 2)?;
/// let punch = structured_quads(&Rectangle::new(Point::new(0.5, 0.0), Point::new(1.5, 0.5)), 2, 1)?;
/// let settlement = vec![Vector::new(0.0, -1e-3); punch.n_vertices()];
/// let depth: Vec<f64> = (0..foundation.n_polygons()).map(|p| foundation.centroid(p).y).collect();
/// let layers = [
///     SvgLayer::new(&foundation).with_label("foundation").with_cell_values(&depth),
///     SvgLayer::new(&punch).with_label("punch").with_displacement(&settlement),
/// ];
/// let options = SvgOptions { magnification: 100.0, value_label: "depth".into(), ..SvgOptions::default() };
/// let path = std::env::temp_dir().join(format!("vem-mesh-layers-doc-{}.svg", std::process::id()));
/// write_svg_layers(&path, &layers, &options)?;
/// # std::fs::remove_file(&path).unwrap();
/// # Ok::<(), vem_mesh::MeshError>(())
/// ```
///
/// Checks before writing (a failure is [`MeshError::Write`] naming the layer): at least one
/// layer, one finite cell value per polygon, one finite displacement per vertex, a finite
/// magnification, a finite increasing value range, a width that leaves room for the drawing.
pub fn write_svg_layers(
    path: impl AsRef<Path>,
    layers: &[SvgLayer],
    options: &SvgOptions,
) -> Result<(), MeshError> {
    let path = path.as_ref();
    let document = render(layers, options).map_err(|reason| MeshError::Write {
        path: path.to_path_buf(),
        reason,
    })?;
    write_atomically(path, |w| w.write_all(document.as_bytes()))
}

/// The positions drawn for one layer (displaced when it has a displacement).
struct Drawn<'a> {
    layer: &'a SvgLayer<'a>,
    positions: Vec<Point>,
}

/// The SVG document, or the reason why the input cannot be drawn.
fn render(layers: &[SvgLayer], options: &SvgOptions) -> Result<String, String> {
    check(layers, options)?;
    let drawn: Vec<Drawn> = layers
        .iter()
        .map(|layer| Drawn {
            layer,
            positions: match layer.displacement {
                Some(u) => layer
                    .mesh
                    .vertices()
                    .iter()
                    .zip(u)
                    .map(|(p, u)| p + options.magnification * u)
                    .collect(),
                None => layer.mesh.vertices().to_vec(),
            },
        })
        .collect();

    // Legend entries: (colour, dashed, text).
    let mut legend: Vec<(String, bool, String)> = Vec::new();
    if layers.iter().any(|l| l.displacement.is_some()) {
        legend.push(("#9a9a9a".into(), true, "undeformed".into()));
    }
    let mut part_colours: Vec<Vec<&str>> = Vec::with_capacity(layers.len());
    let mut next_colour = 0;
    for layer in layers {
        let mut colours = Vec::new();
        if options.parts {
            for part in layer.mesh.parts() {
                let colour = PART_COLOURS[next_colour % PART_COLOURS.len()];
                next_colour += 1;
                colours.push(colour);
                let text = match layer.label {
                    Some(label) => format!("{label}: {}", part.name),
                    None => part.name.clone(),
                };
                legend.push((colour.into(), false, text));
            }
        }
        part_colours.push(colours);
    }
    let marks = options.marks.as_ref().filter(|m| !m.points.is_empty());
    let value_range = value_range(layers, options);

    // Layout: title lines on top, the drawing (with its axes) on the left, legend, marks,
    // colour bar and notes in a panel on the right.
    let longest = legend
        .iter()
        .map(|(_, _, text)| text.chars().count())
        .chain(marks.map(|m| m.label.chars().count()))
        .chain(value_range.map(|_| options.value_label.chars().count()))
        .chain(options.notes.iter().map(|n| n.chars().count()))
        .max();
    let panel_width = longest.map_or(0.0, |chars| (chars as f64 * 7.0 + 40.0).max(110.0));
    let title_lines = options
        .title
        .as_deref()
        .map(|t| wrap(t, title_room(options.width - 2.0 * options.margin)))
        .unwrap_or_default();
    let title_height = if title_lines.is_empty() {
        0.0
    } else {
        TITLE_HEIGHT + TITLE_LINE * (title_lines.len() - 1) as f64
    };
    let (axis_left, axis_bottom) = if options.axes {
        (AXIS_LEFT, AXIS_BOTTOM)
    } else {
        (0.0, 0.0)
    };
    let drawing_width = options.width - 2.0 * options.margin - panel_width - axis_left;
    if drawing_width < 10.0 {
        return Err(format!(
            "a width of {} pixels leaves no room for the drawing (margins {}, legend \
             {panel_width} and axes {axis_left})",
            options.width, options.margin
        ));
    }
    let (min, max) = bounding_box(layers, &drawn);
    let scale = (drawing_width / (max.x - min.x)).min(
        // Tall meshes: at most twice as high as the picture is wide.
        2.0 * options.width / (max.y - min.y),
    );
    let top = options.margin + title_height;
    let left = options.margin + axis_left;
    let to_picture = |p: Point| (left + (p.x - min.x) * scale, top + (max.y - p.y) * scale);
    let panel_height = legend.len() as f64 * LEGEND_ROW
        + marks.map_or(0.0, |_| LEGEND_ROW)
        + value_range.map_or(0.0, |_| COLOUR_BAR_HEIGHT + 60.0)
        + options.notes.len() as f64 * LEGEND_ROW;
    let height = (top + (max.y - min.y) * scale + axis_bottom + options.margin)
        .max(top + panel_height + options.margin);
    // Line widths follow the picture's size (a 900-pixel picture: boundary 1, edges 0.5).
    let line = (options.width / 900.0).clamp(0.5, 4.0);

    let mut svg = String::new();
    let out = &mut svg;
    emit(
        out,
        format_args!("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"),
    );
    emit(
        out,
        format_args!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" \
             xmlns:xlink=\"http://www.w3.org/1999/xlink\" width=\"{w:.0}\" height=\"{height:.0}\" \
             viewBox=\"0 0 {w:.0} {height:.0}\" font-family=\"sans-serif\" font-size=\"12\">\n",
            w = options.width
        ),
    );
    emit(
        out,
        format_args!("<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"),
    );
    for (k, text) in title_lines.iter().enumerate() {
        emit(
            out,
            format_args!(
                "<text class=\"title\" x=\"{:.2}\" y=\"{:.2}\" font-size=\"16\">{}</text>\n",
                options.margin,
                options.margin + 14.0 + TITLE_LINE * k as f64,
                xml_escape(text)
            ),
        );
    }

    let n_polygons: usize = layers.iter().map(|l| l.mesh.n_polygons()).sum();
    let raster = n_polygons > options.vector_cell_limit;
    // Interior edges only where the cells are large enough for them to be seen.
    let edges_shown: Vec<bool> = layers
        .iter()
        .map(|l| cell_size_in_pixels(l.mesh, scale) >= options.edge_min_pixels)
        .collect();
    // The undeformed outlines below the cells: in a raster picture before its image.
    let undeformed_outline = |out: &mut String, mesh: &Mesh| {
        boundary_path(
            out,
            mesh,
            mesh.vertices(),
            &to_picture,
            "undeformed",
            &format!(
                "stroke=\"#9a9a9a\" stroke-width=\"{:.2}\" stroke-dasharray=\"3 2\"",
                0.8 * line
            ),
        );
    };
    if raster {
        for d in drawn.iter().filter(|d| d.layer.displacement.is_some()) {
            undeformed_outline(out, d.layer.mesh);
        }
        raster_cells(
            out,
            &drawn,
            &edges_shown,
            value_range,
            &to_picture,
            (options.width, height),
        );
    }
    for (index, d) in drawn.iter().enumerate() {
        let mesh = d.layer.mesh;
        let edges = edges_shown[index];
        emit(out, format_args!("<g id=\"layer-{index}\">\n"));
        if d.layer.displacement.is_some() && !raster {
            if edges {
                emit(
                    out,
                    format_args!(
                        "<g class=\"undeformed\" fill=\"none\" stroke=\"#9a9a9a\" \
                         stroke-width=\"{:.2}\" stroke-dasharray=\"3 2\">\n",
                        0.6 * line
                    ),
                );
                for polygon in mesh.polygons() {
                    polygon_element(out, polygon, mesh.vertices(), &to_picture, None);
                }
                emit(out, format_args!("</g>\n"));
            } else {
                undeformed_outline(out, mesh);
            }
        }
        if !raster {
            // Cells filled (stroked in their own colour, which closes the seams between
            // them); without values, outlines only when the edges are drawn, else grey.
            emit(
                out,
                format_args!(
                    "<g class=\"cells\" fill=\"none\" stroke-width=\"{:.2}\" stroke-linejoin=\"round\">\n",
                    0.5 * line
                ),
            );
            for (p, polygon) in mesh.polygons().enumerate() {
                let fill = match (d.layer.cell_values, value_range) {
                    (Some(values), Some(range)) => Some(colour_of(values[p], range)),
                    _ if edges => None,
                    _ => Some(UNCOLOURED.to_string()),
                };
                polygon_element(out, polygon, &d.positions, &to_picture, fill);
            }
            emit(out, format_args!("</g>\n"));
            if edges {
                // Where a graded mesh is finer than the rule, its short edges are left out.
                let mut path = String::new();
                for edge in mesh.edges() {
                    let [a, b] = edge.vertices;
                    let (xa, ya) = to_picture(d.positions[a]);
                    let (xb, yb) = to_picture(d.positions[b]);
                    if (xb - xa).hypot(yb - ya) >= 0.5 * options.edge_min_pixels {
                        emit(&mut path, format_args!("M{xa:.2} {ya:.2}L{xb:.2} {yb:.2}"));
                    }
                }
                let width = if d.layer.cell_values.is_some() {
                    0.5 * line
                } else {
                    0.7 * line
                };
                emit(
                    out,
                    format_args!(
                        "<path class=\"edges\" d=\"{path}\" fill=\"none\" stroke=\"#303030\" \
                         stroke-opacity=\"0.8\" stroke-width=\"{width:.2}\" \
                         stroke-linecap=\"round\"/>\n"
                    ),
                );
            }
        }
        boundary_path(
            out,
            mesh,
            &d.positions,
            &to_picture,
            "boundary",
            &format!("stroke=\"#303030\" stroke-width=\"{:.2}\"", line),
        );
        for (part, colour) in mesh.parts().iter().zip(&part_colours[index]) {
            let mut path = String::new();
            for &e in &part.edges {
                let [a, b] = mesh.edge(e).vertices;
                let (xa, ya) = to_picture(d.positions[a]);
                let (xb, yb) = to_picture(d.positions[b]);
                emit(&mut path, format_args!("M{xa:.2} {ya:.2}L{xb:.2} {yb:.2}"));
            }
            emit(
                out,
                format_args!(
                    "<path class=\"part\" data-part=\"{}\" d=\"{path}\" fill=\"none\" \
                     stroke=\"{colour}\" stroke-width=\"{:.2}\" stroke-linecap=\"round\"/>\n",
                    xml_escape(&part.name),
                    2.5 * line
                ),
            );
        }
        if options.vertex_dots && !raster {
            emit(
                out,
                format_args!("<g class=\"vertices\" fill=\"#000000\">\n"),
            );
            for &p in &d.positions {
                let (x, y) = to_picture(p);
                emit(
                    out,
                    format_args!("<circle cx=\"{x:.2}\" cy=\"{y:.2}\" r=\"1.6\"/>\n"),
                );
            }
            emit(out, format_args!("</g>\n"));
        }
        emit(out, format_args!("</g>\n"));
    }
    if let Some(marks) = marks {
        emit(
            out,
            format_args!(
                "<g class=\"marks\" stroke=\"{MARK_COLOUR}\" stroke-width=\"{:.2}\">\n",
                1.5 * line
            ),
        );
        let r = 4.0 * line;
        for &p in &marks.points {
            let (x, y) = to_picture(p);
            emit(out, format_args!("{}\n", cross(x, y, r)));
        }
        emit(out, format_args!("</g>\n"));
    }
    if options.axes {
        axes(out, options, min, max, &to_picture);
    }

    // Legend, marks, colour bar and notes.
    let panel_x = options.width - options.margin - panel_width + 16.0;
    let mut y = top + 8.0;
    for (colour, dashed, text) in &legend {
        let dash = if *dashed {
            " stroke-dasharray=\"3 2\""
        } else {
            ""
        };
        emit(
            out,
            format_args!(
                "<line x1=\"{panel_x:.2}\" y1=\"{y:.2}\" x2=\"{:.2}\" y2=\"{y:.2}\" \
                 stroke=\"{colour}\" stroke-width=\"3\"{dash}/>\n\
                 <text x=\"{:.2}\" y=\"{:.2}\">{}</text>\n",
                panel_x + 20.0,
                panel_x + 26.0,
                y + 4.0,
                xml_escape(text)
            ),
        );
        y += LEGEND_ROW;
    }
    if let Some(marks) = marks {
        emit(
            out,
            format_args!(
                "<g stroke=\"{MARK_COLOUR}\" stroke-width=\"1.5\">{}</g>\n\
                 <text x=\"{:.2}\" y=\"{:.2}\">{}</text>\n",
                cross(panel_x + 10.0, y, 4.0),
                panel_x + 26.0,
                y + 4.0,
                xml_escape(&marks.label)
            ),
        );
        y += LEGEND_ROW;
    }
    if let Some((lo, hi)) = value_range {
        colour_bar(out, panel_x, y + 10.0, (lo, hi), &options.value_label);
        y += COLOUR_BAR_HEIGHT + 60.0;
    }
    for note in &options.notes {
        emit(
            out,
            format_args!(
                "<text class=\"note\" x=\"{panel_x:.2}\" y=\"{:.2}\">{}</text>\n",
                y + 4.0,
                xml_escape(note)
            ),
        );
        y += LEGEND_ROW;
    }
    emit(out, format_args!("</svg>\n"));
    Ok(svg)
}

/// A cross of half-size `r` centred at `(x, y)`, as a `<path>`.
fn cross(x: f64, y: f64, r: f64) -> String {
    format!(
        "<path d=\"M{:.2} {:.2}L{:.2} {:.2}M{:.2} {:.2}L{:.2} {:.2}\"/>",
        x - r,
        y - r,
        x + r,
        y + r,
        x - r,
        y + r,
        x + r,
        y - r
    )
}

/// The number of characters of 16-pixel sans-serif that fit on a title line `width` pixels
/// wide (about 8.5 pixels a character).
fn title_room(width: f64) -> usize {
    (width / 8.5).max(20.0) as usize
}

/// `text` broken at spaces into lines of at most `room` characters (a longer word on a line
/// of its own): nothing is cut. The titles of every picture and plot of the workspace wrap so.
///
/// ```
/// assert_eq!(vem_mesh::io::wrap("one two three", 7), vec!["one two", "three"]);
/// ```
pub fn wrap(text: &str, room: usize) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    for word in text.split_whitespace() {
        match lines.last_mut() {
            Some(line) if line.chars().count() + 1 + word.chars().count() <= room => {
                line.push(' ');
                line.push_str(word);
            }
            _ => lines.push(word.to_string()),
        }
    }
    lines
}

/// The mean size of the cells of `mesh` in pixels at `scale` pixels per unit of length: the
/// square root of their mean area.
fn cell_size_in_pixels(mesh: &Mesh, scale: f64) -> f64 {
    let n = mesh.n_polygons().max(1);
    let area: f64 = (0..mesh.n_polygons()).map(|p| mesh.area(p).abs()).sum();
    (area / n as f64).sqrt() * scale
}

/// Ticks at multiples of 1, 2 or 5 times a power of ten in `[lo, hi]`, the step nearest
/// `(hi - lo) / count`, and the step.
fn nice_ticks(lo: f64, hi: f64, count: usize) -> (Vec<f64>, f64) {
    let span = hi - lo;
    if !(span > 0.0 && span.is_finite()) {
        return (vec![lo], 1.0);
    }
    let raw = span / count.max(1) as f64;
    let power = 10f64.powf(raw.log10().floor());
    // The round step nearest the even one (in ratio).
    let step = [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * power)
        .min_by(|a, b| (a / raw).ln().abs().total_cmp(&(b / raw).ln().abs()))
        .unwrap_or(power);
    let first = (lo / step - 1e-9).ceil() as i64;
    let last = (hi / step + 1e-9).floor() as i64;
    let ticks = (first..=last).map(|k| k as f64 * step).collect();
    (ticks, step)
}

/// A tick label of `value` on a scale of step `step`: as many decimals as the step needs,
/// scientific notation for very small or large values.
fn axis_label(value: f64, step: f64) -> String {
    let value = if value.abs() < 1e-9 * step {
        0.0
    } else {
        value
    };
    let magnitude = value.abs().max(step);
    if (1e-4..1e5).contains(&magnitude) {
        let decimals = (-step.log10().floor()).max(0.0) as usize;
        format!("{value:.decimals$}")
    } else {
        let digits = ((magnitude.log10().floor() - step.log10().floor()).max(0.0) as usize).min(6);
        format!("{value:.digits$e}")
    }
}

/// Axes below and left of the drawing box (the bounding box `min`, `max`): ticks at nice
/// values in the meshes' coordinates, their labels and the axes' names with the unit.
fn axes(
    out: &mut String,
    options: &SvgOptions,
    min: Point,
    max: Point,
    to_picture: &impl Fn(Point) -> (f64, f64),
) {
    let (x0, y0) = to_picture(min);
    let (x1, y1) = to_picture(max);
    let unit = options
        .length_unit
        .as_deref()
        .map_or(String::new(), |u| format!(" [{}]", xml_escape(u)));
    let (bottom, side) = (y0 + 8.0, x0 - 8.0);
    emit(
        out,
        format_args!(
            "<g class=\"axes\" stroke=\"#000000\" stroke-width=\"1\">\n\
             <path class=\"axis-x\" d=\"M{x0:.2} {bottom:.2}L{x1:.2} {bottom:.2}\"/>\n\
             <path class=\"axis-y\" d=\"M{side:.2} {y0:.2}L{side:.2} {y1:.2}\"/>\n"
        ),
    );
    let count = |pixels: f64| ((pixels / 80.0).round() as usize).clamp(3, 8);
    let (xs, x_step) = nice_ticks(min.x, max.x, count(x1 - x0));
    let (ys, y_step) = nice_ticks(min.y, max.y, count(y0 - y1));
    let mut labels = String::new();
    for &x in &xs {
        let (px, _) = to_picture(Point::new(x, min.y));
        emit(
            out,
            format_args!(
                "<path d=\"M{px:.2} {bottom:.2}L{px:.2} {:.2}\"/>\n",
                bottom + 5.0
            ),
        );
        emit(
            &mut labels,
            format_args!(
                "<text class=\"tick-x\" x=\"{px:.2}\" y=\"{:.2}\" text-anchor=\"middle\">{}</text>\n",
                bottom + 17.0,
                axis_label(x, x_step)
            ),
        );
    }
    for &y in &ys {
        let (_, py) = to_picture(Point::new(min.x, y));
        emit(
            out,
            format_args!(
                "<path d=\"M{side:.2} {py:.2}L{:.2} {py:.2}\"/>\n",
                side - 5.0
            ),
        );
        emit(
            &mut labels,
            format_args!(
                "<text class=\"tick-y\" x=\"{:.2}\" y=\"{:.2}\" text-anchor=\"end\">{}</text>\n",
                side - 7.0,
                py + 4.0,
                axis_label(y, y_step)
            ),
        );
    }
    emit(out, format_args!("</g>\n{labels}"));
    let middle_y = 0.5 * (y0 + y1);
    emit(
        out,
        format_args!(
            "<text class=\"axis-name\" x=\"{:.2}\" y=\"{:.2}\" text-anchor=\"middle\">x{unit}</text>\n\
             <text class=\"axis-name\" x=\"{:.2}\" y=\"{middle_y:.2}\" text-anchor=\"middle\" \
             transform=\"rotate(-90 {:.2} {middle_y:.2})\">y{unit}</text>\n",
            0.5 * (x0 + x1),
            bottom + 32.0,
            options.margin + 10.0,
            options.margin + 10.0,
        ),
    );
}

/// Appends formatted text to the document (writing to a `String` cannot fail).
fn emit(out: &mut String, args: std::fmt::Arguments) {
    out.write_fmt(args)
        .expect("writing to a String cannot fail");
}

/// Draws the cells of every layer into one image at [`RASTER_SCALE`] times the picture's
/// resolution and appends it as an `<image>` covering the picture: cells filled by their
/// value's colour (light grey without values), the edges of a layer drawn when
/// `edges_shown` says so.
fn raster_cells(
    out: &mut String,
    drawn: &[Drawn],
    edges_shown: &[bool],
    value_range: Option<(f64, f64)>,
    to_picture: &(impl Fn(Point) -> (f64, f64) + Sync),
    (width, height): (f64, f64),
) {
    // At most about 16 million pixels, whatever the picture's size.
    let scale = RASTER_SCALE.min((16.0e6 / (width * height).max(1.0)).sqrt());
    let (w, h) = (
        (width * scale).ceil().max(1.0) as usize,
        (height * scale).ceil().max(1.0) as usize,
    );
    // The colour map in as many levels as the palette holds beside the uncoloured grey,
    // from its first colour to its last (each value drawn in the nearest level), and an ink
    // for the edges.
    let levels = Palette::MAX_FILLS - 1;
    let mut fills = vec![UNCOLOURED_RGB];
    if let Some((lo, hi)) = value_range {
        fills.extend((0..levels).map(|k| {
            let t = k as f64 / (levels - 1) as f64;
            colour_components(lo + t * (hi - lo), (lo, hi))
        }));
    }
    let palette = Palette::new(&fills, EDGE_INK);
    let uncoloured = palette.fill(0);
    let lowest_level = usize::from(uncoloured) + 1;
    let level_of = |value: f64, (lo, hi): (f64, f64)| {
        let t = if hi > lo {
            ((value - lo) / (hi - lo)).clamp(0.0, 1.0)
        } else {
            0.5
        };
        (lowest_level + (t * (levels - 1) as f64).round() as usize) as u8
    };
    let mut image = Raster::new(w, h, palette);
    let to_pixels = |p: Point| {
        let (x, y) = to_picture(p);
        (x * scale, y * scale)
    };
    // Every band draws the cells (and edges) straight from the meshes, in order: no list of
    // shapes is gathered first (gathered on one thread, the 70 000 cells of the whole-run
    // picture at 10^5 unknowns took 11-14 ms before the bands could start).
    image.draw_with(|band| {
        let mut corners = Vec::new();
        for (d, &edges) in drawn.iter().zip(edges_shown) {
            let mesh = d.layer.mesh;
            for (p, polygon) in mesh.polygons().enumerate() {
                corners.clear();
                corners.extend(polygon.iter().map(|&v| to_pixels(d.positions[v])));
                let colour = match (d.layer.cell_values, value_range) {
                    (Some(values), Some(range)) => level_of(values[p], range),
                    _ => uncoloured,
                };
                band.fill_polygon(&corners, colour);
            }
            if edges {
                for edge in mesh.edges() {
                    let [a, b] = edge.vertices.map(|v| to_pixels(d.positions[v]));
                    band.segment(a, b);
                }
            }
        }
    });
    let png = image.to_png();
    emit(
        out,
        format_args!(
            "<image class=\"cells-raster\" x=\"0\" y=\"0\" width=\"{width:.0}\" \
             height=\"{height:.0}\" preserveAspectRatio=\"none\" \
             xlink:href=\"data:image/png;base64,{}\"/>\n",
            base64(&png)
        ),
    );
}

/// The boundary edges of `mesh` at `positions` as one `<path>` of class `class`.
fn boundary_path(
    out: &mut String,
    mesh: &Mesh,
    positions: &[Point],
    to_picture: &impl Fn(Point) -> (f64, f64),
    class: &str,
    style: &str,
) {
    let mut path = String::new();
    for e in mesh.boundary_edges() {
        let [a, b] = mesh.edge(e).vertices;
        let (xa, ya) = to_picture(positions[a]);
        let (xb, yb) = to_picture(positions[b]);
        emit(&mut path, format_args!("M{xa:.2} {ya:.2}L{xb:.2} {yb:.2}"));
    }
    emit(
        out,
        format_args!(
            "<path class=\"{class}\" d=\"{path}\" fill=\"none\" {style} \
             stroke-linecap=\"round\"/>\n"
        ),
    );
}

/// Appends one `<polygon>` with the given vertex positions and optional fill colour (the
/// outline stroked in the same colour, which closes the seams between neighbours).
fn polygon_element(
    out: &mut String,
    polygon: &[usize],
    positions: &[Point],
    to_picture: &impl Fn(Point) -> (f64, f64),
    fill: Option<String>,
) {
    out.push_str("<polygon points=\"");
    for (k, &v) in polygon.iter().enumerate() {
        let (x, y) = to_picture(positions[v]);
        let separator = if k == 0 { "" } else { " " };
        emit(out, format_args!("{separator}{x:.2},{y:.2}"));
    }
    match fill {
        Some(colour) => emit(
            out,
            format_args!("\" fill=\"{colour}\" stroke=\"{colour}\"/>\n"),
        ),
        None => out.push_str("\"/>\n"),
    }
}

/// A vertical colour bar with its title, its two ends labelled with the range's values (the
/// rectangle carries them as `data-min` and `data-max`) and ticks at round values between.
fn colour_bar(out: &mut String, x: f64, y: f64, (lo, hi): (f64, f64), label: &str) {
    emit(
        out,
        format_args!(
            "<text x=\"{x:.2}\" y=\"{:.2}\">{}</text>\n\
             <defs><linearGradient id=\"colour-map\" x1=\"0\" y1=\"1\" x2=\"0\" y2=\"0\">\n",
            y + 4.0,
            xml_escape(label)
        ),
    );
    for (i, rgb) in COLOUR_MAP.iter().enumerate() {
        emit(
            out,
            format_args!(
                "<stop offset=\"{:.4}\" stop-color=\"{}\"/>\n",
                i as f64 / (COLOUR_MAP.len() - 1) as f64,
                hex(*rgb)
            ),
        );
    }
    let top = y + 16.0;
    emit(
        out,
        format_args!(
            "</linearGradient></defs>\n<rect class=\"colour-bar\" data-min=\"{lo:e}\" \
             data-max=\"{hi:e}\" x=\"{x:.2}\" y=\"{top:.2}\" width=\"18\" \
             height=\"{COLOUR_BAR_HEIGHT}\" fill=\"url(#colour-map)\" stroke=\"#303030\" \
             stroke-width=\"0.5\"/>\n"
        ),
    );
    let at = |value: f64| top + (hi - value) / (hi - lo) * COLOUR_BAR_HEIGHT;
    let mut ticks = vec![
        (top, tick_label(hi)),
        (top + COLOUR_BAR_HEIGHT, tick_label(lo)),
    ];
    if hi > lo {
        let (between, step) = nice_ticks(lo, hi, 5);
        for value in between {
            let y = at(value);
            // Not over the end labels.
            if y - top >= 14.0 && top + COLOUR_BAR_HEIGHT - y >= 14.0 {
                ticks.push((y, axis_label(value, step)));
            }
        }
    }
    for (y, text) in ticks {
        emit(
            out,
            format_args!(
                "<path d=\"M{:.2} {y:.2}L{:.2} {y:.2}\" stroke=\"#303030\" stroke-width=\"0.8\"/>\n\
                 <text class=\"colour-tick\" x=\"{:.2}\" y=\"{:.2}\">{text}</text>\n",
                x + 18.0,
                x + 22.0,
                x + 25.0,
                y + 4.0,
            ),
        );
    }
}

/// The colour of `value` in the range `(lo, hi)` (clamped; the middle of the map when the
/// range is a single value).
fn colour_of(value: f64, range: (f64, f64)) -> String {
    hex(colour_components(value, range).map(f64::from))
}

/// The red, green and blue of `value` in the colour map over `(lo, hi)` (see [`colour_of`]).
fn colour_components(value: f64, (lo, hi): (f64, f64)) -> [u8; 3] {
    let t = if hi > lo {
        ((value - lo) / (hi - lo)).clamp(0.0, 1.0)
    } else {
        0.5
    };
    let position = t * (COLOUR_MAP.len() - 1) as f64;
    let k = (position.floor() as usize).min(COLOUR_MAP.len() - 2);
    let s = position - k as f64;
    let (a, b) = (COLOUR_MAP[k], COLOUR_MAP[k + 1]);
    [0, 1, 2].map(|c| (a[c] + s * (b[c] - a[c])).round().clamp(0.0, 255.0) as u8)
}

/// `#rrggbb` of an RGB triple in 0..=255.
fn hex(rgb: [f64; 3]) -> String {
    let [r, g, b] = rgb.map(|c| c.round().clamp(0.0, 255.0) as u8);
    format!("#{r:02x}{g:02x}{b:02x}")
}

/// A short label for a colour-bar value: fixed notation for moderate magnitudes, scientific
/// otherwise.
fn tick_label(value: f64) -> String {
    let magnitude = value.abs();
    if magnitude == 0.0 {
        "0".into()
    } else if (1e-3..1e4).contains(&magnitude) {
        let fixed = format!("{value:.4}");
        fixed
            .trim_end_matches('0')
            .trim_end_matches('.')
            .to_string()
    } else {
        format!("{value:.3e}")
    }
}

/// The value range of the colour map: given, or the extent of all cell values.
fn value_range(layers: &[SvgLayer], options: &SvgOptions) -> Option<(f64, f64)> {
    let mut values = layers
        .iter()
        .filter_map(|l| l.cell_values)
        .flatten()
        .peekable();
    values.peek()?;
    Some(options.value_range.unwrap_or_else(|| {
        values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(v), hi.max(v))
        })
    }))
}

/// The bounding box of everything drawn: undeformed and displaced positions of every layer.
fn bounding_box(layers: &[SvgLayer], drawn: &[Drawn]) -> (Point, Point) {
    let mut min = Point::new(f64::INFINITY, f64::INFINITY);
    let mut max = Point::new(f64::NEG_INFINITY, f64::NEG_INFINITY);
    let undeformed = layers.iter().map(|l| l.mesh.vertices());
    let displaced = drawn.iter().map(|d| d.positions.as_slice());
    for p in undeformed.chain(displaced).flatten() {
        min = Point::new(min.x.min(p.x), min.y.min(p.y));
        max = Point::new(max.x.max(p.x), max.y.max(p.y));
    }
    (min, max)
}

/// Checks layers and options; the error names the layer and what is wrong.
fn check(layers: &[SvgLayer], options: &SvgOptions) -> Result<(), String> {
    if layers.is_empty() {
        return Err("there is nothing to draw (no layers)".into());
    }
    let width_ok = options.width.is_finite() && options.width > 0.0;
    let margin_ok = options.margin.is_finite() && options.margin >= 0.0;
    if !(width_ok && margin_ok) {
        return Err(format!(
            "width {} and margin {} must be finite, the width positive and the margin \
             non-negative",
            options.width, options.margin
        ));
    }
    if !options.magnification.is_finite() {
        return Err(format!(
            "the magnification {} is not finite",
            options.magnification
        ));
    }
    if let Some((lo, hi)) = options.value_range {
        if !(lo.is_finite() && hi.is_finite() && lo < hi) {
            return Err(format!(
                "the value range ({lo}, {hi}) must be finite and increasing"
            ));
        }
    }
    for (index, layer) in layers.iter().enumerate() {
        let name = match layer.label {
            Some(label) => format!("layer {index} ('{label}')"),
            None => format!("layer {index}"),
        };
        let mesh = layer.mesh;
        if let Some(values) = layer.cell_values {
            if values.len() != mesh.n_polygons() {
                return Err(format!(
                    "{name}: {} cell values for {} polygons",
                    values.len(),
                    mesh.n_polygons()
                ));
            }
            if let Some(p) = values.iter().position(|v| !v.is_finite()) {
                return Err(format!(
                    "{name}: the cell value of polygon {p} is {}",
                    values[p]
                ));
            }
        }
        if let Some(u) = layer.displacement {
            if u.len() != mesh.n_vertices() {
                return Err(format!(
                    "{name}: {} displacements for {} vertices",
                    u.len(),
                    mesh.n_vertices()
                ));
            }
            if let Some(v) = u.iter().position(|u| !(u.x.is_finite() && u.y.is_finite())) {
                return Err(format!(
                    "{name}: the displacement of vertex {v} is ({}, {})",
                    u[v].x, u[v].y
                ));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colour_map_ends_and_middle() {
        assert_eq!(colour_of(0.0, (0.0, 1.0)), "#440154");
        assert_eq!(colour_of(1.0, (0.0, 1.0)), "#fde725");
        assert_eq!(colour_of(0.5, (0.0, 1.0)), "#21908d");
        // Clamped outside the range, middle colour for a single value.
        assert_eq!(colour_of(-3.0, (0.0, 1.0)), "#440154");
        assert_eq!(colour_of(2.0, (2.0, 2.0)), "#21908d");
    }

    #[test]
    fn ticks_are_round_and_inside() {
        let (ticks, step) = nice_ticks(0.0, 1.0, 5);
        assert_eq!(step, 0.2);
        assert_eq!(ticks.len(), 6);
        assert!((ticks[5] - 1.0).abs() < 1e-15);
        // A step of 0.02125 rounds to 0.02, not up to 0.05.
        let (ticks, step) = nice_ticks(-0.013, 0.072, 4);
        assert_eq!(step, 0.02);
        assert_eq!(ticks, [0.0, 0.02, 0.04, 0.06]);
        assert_eq!(axis_label(0.05, 0.05), "0.05");
        assert_eq!(axis_label(-2.0, 1.0), "-2");
        assert_eq!(axis_label(3.0e-6, 1.0e-6), "3e-6");
        assert_eq!(axis_label(1.5e5, 5.0e4), "1.5e5");
    }

    #[test]
    fn titles_wrap_without_losing_words() {
        let lines = wrap("one two three four", 9);
        assert_eq!(lines, ["one two", "three", "four"]);
        assert_eq!(
            wrap("averyveryverylongword x", 5),
            ["averyveryverylongword", "x"]
        );
    }

    #[test]
    fn tick_labels_are_short() {
        assert_eq!(tick_label(0.0), "0");
        assert_eq!(tick_label(0.25), "0.25");
        assert_eq!(tick_label(-12.0), "-12");
        assert_eq!(tick_label(1.5e-6), "1.500e-6");
        assert_eq!(tick_label(2.0e5), "2.000e5");
    }
}
