//! PNG figures for reports and papers: the plotting layer of `softway`.
//!
//! A small, self-contained plotting library on top of [`plotters`]'
//! bitmap backend. It knows nothing about the solver: it takes plain
//! vectors and slices (x–y series, triangle meshes with cell values or
//! nodal vectors) and writes PNG files.
//!
//! # API
//!
//! * [`line_plot`] / [`panels`]: x–y line plots (one [`Panel`] or a grid of
//!   panels whose axes are aligned per row and column) of [`Series`] drawn
//!   in a [`SeriesStyle`], with optional logarithmic axes, reference lines
//!   (horizontal and vertical), shaded bands, a note under the axes
//!   and a legend placed where it hides no data (series, markers, reference lines): inside
//!   if possible, else outside to the right of the axes if there is room, else inside with
//!   head room added above the data (only when the y range is automatic), else under the
//!   axes in as many columns as fit.
//! * [`sig`]: numbers for titles, legends and notes, to a number of significant digits.
//! * [`mesh_color_map`] / [`mesh_color_map_with`]: a scalar per triangle
//!   ([`MeshColorMap`]) drawn as a colour map with a colour bar, equal
//!   aspect ratio.
//! * [`mesh_vector_fields`] / [`mesh_vector_fields_with`]: a grid of small
//!   panels (successive stages), each showing a nodal vector field
//!   ([`MeshVectorField`]) as arrows over its magnitude colour map, with one
//!   shared colour scale.
//! * [`mode_shapes`]: a grid of panels, each a nodal displacement ([`ModeShape`], a mode
//!   shape) drawn as the deformed mesh over the undeformed outline.
//! * [`MeshOptions`] / [`EdgeMode`]: element edges and a fixed colour range
//!   for the mesh plots.
//! * [`PlotError`]: every function returns `Result<(), PlotError>`.
//!
//! ```no_run
//! use softway_plot::{line_plot, Panel, Series, SeriesStyle};
//!
//! let t: Vec<f64> = (0..100).map(|i| 0.01 * f64::from(i)).collect();
//! let u: Vec<f64> = t.iter().map(|t| (6.0 * t).sin()).collect();
//! let mut panel = Panel::new("Free-end displacement", "t [ms]", "u [mm]");
//! panel.series.push(Series::new("u", t, u, SeriesStyle::Line));
//! panel.hlines.push((1.0, "exact amplitude".into()));
//! line_plot("out/u.png".as_ref(), &panel, (1200, 800))?;
//! # Ok::<(), softway_plot::PlotError>(())
//! ```
//!
//! # Conventions
//!
//! All text uses DejaVu Sans, embedded through the `dejavu` crate and
//! registered with plotters' `ab_glyph` support, so no system font is
//! needed. Font sizes and line widths scale with the image size (tick labels
//! are about 20 px high at 1200×800). Tick labels use a common factor such
//! as `×10⁻³` (printed at the end of the axis) for very large or small
//! values. Images must be at least 120×90 pixels; up to 4 megapixels they
//! are rendered 2× super-sampled (anti-aliased). They are written
//! atomically: the PNG is first written to `<path>.tmp.png` and then renamed
//! to `path`, so a failed draw never leaves a half-written figure behind.
//! Missing parent directories of `path` are created.
//!
//! Non-finite values are skipped (a line is broken there); on logarithmic
//! axes non-positive values are skipped as well. Empty input gives
//! [`PlotError::Empty`]; inconsistent input (length mismatches, node indices
//! out of range, a grid too small for the panels) gives [`PlotError::Draw`].
//! No function of this crate panics on bad data.
//!
//! # Regions, clipping and the audit
//!
//! Every figure is drawn in nested regions: the canvas, each panel's cell (title, axis
//! labels, ticks, legend, note), each panel's axes (its data). Data (lines, markers, bands,
//! reference lines, mesh triangles, arrows) is cut to its axes before it reaches plotters,
//! polygon by polygon. Lines are stroked here, each segment a rectangle and each bend a
//! disk of the line's width, so no painted point lies farther than half the width from
//! the data. Text is never cut: a title or axis label too long for its panel is wrapped
//! (titles, notes) or set smaller (down to 60 %, then the lines are allowed to run long),
//! and kept inside its cell. A figure also records anything painted outside its region
//! (a label beyond its panel, a title beyond the canvas): with the environment variable
//! `SOFTWAY_PLOT_STRICT=1` (and in this crate's tests) that is an error naming what and
//! where, instead of a figure written with it. Two defects that are not places fail a strict
//! figure too (issue 48): a legend that found no place free of data, and an automatic axis
//! range set by one isolated point (at most one per series, farther from all the others
//! than three quarters of the range). The tests check the pixels as well: no
//! pixel of a series' colour outside its axes, on spiky data on log axes and data cut by
//! fixed ranges.
//!
//! In a grid of panels ([`panels`]) a legend entry already listed by an earlier panel is
//! not listed again (twenty panels of one comparison share one legend).
//!
//! # Its own axes over plotters' primitives, or plotters' chart API (decided again)
//!
//! Issue 34 put the question with the figures in front of us: lines through the tick
//! labels of `spectrum.png`, `contact_force_zoom.png` and `compare_force.png`, titles cut
//! at the edge, `energy [ J]`. Each defect was traced to its cause before deciding:
//!
//! * The lines outside the axes were not a clipping gap (the series were clipped) but
//!   plotters' wide strokes: `PathElement` with a width above one pixel becomes *one*
//!   polygon offset from the whole path, whose inner joins at a sharp bend (every spike of
//!   a spectrum or of a force history) are not limited, and whose self-intersections fill
//!   the space between spikes. plotters' chart API draws its `LineSeries` with the same
//!   `PathElement`, so moving to it would have kept this defect. Stroking here (rectangles
//!   and round joins, cut to the axes) removed it, and a test pins it (it fails with
//!   plotters' strokes: thirty thousand pixels outside the axes).
//! * `energy [ J]` was plotters' text drawing, which places every glyph's box at the pen
//!   and drops its side bearing (the `J` hooks left of its origin). The chart API draws its
//!   text the same way. Text is drawn here with `ab_glyph` (the rasterizer plotters itself
//!   uses), each glyph at its own bearing.
//! * The cut titles and the repeated legends were layout: fitted text and the shared legend
//!   above. The chart API would have given axes, ticks and legends, but not text that fits
//!   its panel, grids with aligned axes, legends placed where they hide no data, common
//!   factors on the ticks, shaded bands, mesh colour maps and vector fields, which this
//!   crate has and the solver's figures use.
//!
//! So the crate stays, with its clipping, strokes, text and layout tested; plotters
//! remains its pixel backend (bitmap, polygons, PNG encoding).
//!
//! # Why a separate crate
//!
//! The plotting layer is about a fifth of the code of `softway` but has
//! nothing to do with contact mechanics. As its own workspace crate the
//! solver crate reads as a solver (it uses this one as
//! `softway::output::plot`), the plotting code has its own tests, built and
//! run on their own (`cargo test -p softway-plot`), and it can be reused by
//! other tools without the solver. The tests write their figures to a
//! temporary directory; set `SOFTWAY_PLOT_SAMPLE_DIR` to keep them and look
//! at them.
//!
//! # Modules (private)
//!
//! `render` (fonts, super-sampled canvas, atomic PNG writing), `style`
//! (sizes, colours, text), `axes` (ranges, scales, number formatting and
//! ticks), `geom` (pixel geometry, clipping, dashes, drawing primitives),
//! `line` (layout and painting of line-plot panels, legends), `mesh`
//! (colour maps, colour bars, vector fields).

mod audit;
mod axes;
mod geom;
mod line;
mod mesh;
mod render;
mod shape;
mod style;
#[cfg(test)]
mod test_util;

use std::path::{Path, PathBuf};

use geom::Rect;
use line::{draw_no_data, draw_panel, layout_panel, legend_keys, paint_panel, validate_panel};
use mesh::{render_color_map, render_color_map_overlay, render_mode_shapes, render_vector_fields};
use render::{render, save_png, Fail};
use style::Sty;

/// Error returned by the plotting functions.
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// The figure could not be drawn or written (invalid input such as
    /// mismatched lengths, an image too small for the layout, an I/O error).
    #[error("cannot draw {path}: {message}")]
    Draw {
        /// Target file of the figure.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// There is nothing to draw (no series, no finite data, no triangles…).
    #[error("nothing to plot in {path}: {why}")]
    Empty {
        /// Target file of the figure.
        path: PathBuf,
        /// Why the input is considered empty.
        why: String,
    },
}

/// One data series of a line plot.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend label (series with an empty label are left out of the legend).
    pub label: String,
    /// Abscissae; must have the same length as `y`.
    pub x: Vec<f64>,
    /// Ordinates; non-finite values break the line.
    pub y: Vec<f64>,
    /// How the series is drawn. Its colour (and marker shape) is chosen
    /// from a colour-blind-safe qualitative palette by the series index.
    pub style: SeriesStyle,
}

impl Series {
    /// Convenience constructor.
    pub fn new(label: impl Into<String>, x: Vec<f64>, y: Vec<f64>, style: SeriesStyle) -> Self {
        Self {
            label: label.into(),
            x,
            y,
            style,
        }
    }
}

/// Drawing style of a [`Series`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SeriesStyle {
    /// Solid line.
    #[default]
    Line,
    /// Dashed line.
    Dashed,
    /// Markers only, one per data point.
    Markers,
    /// Solid line with markers (at most about 25 markers per series, evenly
    /// spread over the points, so that dense series stay readable).
    LineMarkers,
}

/// One set of axes: title, axis labels, series and reference lines.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Panel {
    /// Title drawn above the axes (may be empty).
    pub title: String,
    /// Label of the x axis, with units, e.g. `"t [ms]"`.
    pub x_label: String,
    /// Label of the y axis, with units, e.g. `"u [mm]"`.
    pub y_label: String,
    /// Logarithmic x axis (non-positive x values are skipped).
    pub x_log: bool,
    /// Logarithmic y axis (non-positive y values are skipped).
    pub y_log: bool,
    /// The data series.
    pub series: Vec<Series>,
    /// Fixed x range `(min, max)`; automatic (data range + 5 %) when `None`.
    pub x_range: Option<(f64, f64)>,
    /// Fixed y range `(min, max)`; automatic (data range + 5 %) when `None`.
    pub y_range: Option<(f64, f64)>,
    /// Horizontal reference lines `(y, label)`, e.g. exact values: drawn thin,
    /// grey and dashed, and listed in the legend (unless the label is empty).
    pub hlines: Vec<(f64, String)>,
    /// Shaded bands of x `(x0, x1, label)`, e.g. the stick zone of a contact patch: filled
    /// in a light tint behind the data (one tint per distinct label, in order of first
    /// appearance), each label listed once in the legend (unless empty).
    pub vspans: Vec<(f64, f64, String)>,
    /// Vertical reference lines `(x, label)`, e.g. the frequencies of a spectrum's
    /// expected components: drawn thin and dashed, one colour per distinct label (in order
    /// of first appearance), each label listed once in the legend (unless empty).
    pub vlines: Vec<(f64, String)>,
    /// A note printed under the axes in a smaller font (wrapped to the panel's width), for
    /// what the reader must know to read the panel: a clipped range, a convention, a
    /// pattern that belongs to the mesh.
    pub note: String,
    /// No legend for this panel (in a grid, a legend equal to an earlier panel's is left
    /// out anyway).
    pub no_legend: bool,
    /// The x axis's labelled ticks at these values (a refinement ladder's rungs, so that
    /// each point is read off its own tick), the automatic ticks becoming unlabelled minor
    /// ones; the automatic ticks when empty, or when these leave the range or their labels
    /// would not fit.
    pub x_ticks: Vec<f64>,
}

impl Panel {
    /// A panel with the given title and axis labels and no data yet.
    pub fn new(
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
    ) -> Self {
        Self {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            ..Self::default()
        }
    }
}

/// A scalar field, constant per triangle, on a 2-D triangle mesh.
#[derive(Debug, Clone)]
pub struct MeshColorMap<'a> {
    /// Node coordinates (in the solver's length unit, e.g. metres).
    pub points: &'a [[f64; 2]],
    /// Triangles as node indices into `points`.
    pub triangles: &'a [[usize; 3]],
    /// One value per triangle (non-finite values are drawn light grey).
    pub cell_values: &'a [f64],
    /// Figure title (may be empty).
    pub title: String,
    /// Colour-bar label with units, e.g. `"J2 [MPa^2]"`.
    pub colorbar_label: String,
    /// Factor applied to coordinates for the axes, e.g. `100.0` for cm
    /// when `points` are in metres (non-positive or non-finite means 1).
    pub length_unit_scale: f64,
    /// Name of the displayed length unit, e.g. `"cm"` (axes become
    /// `x [cm]`, `y [cm]`).
    pub length_unit: String,
    /// A note printed under the figure (may be empty), e.g. how the colour scale is
    /// clipped.
    pub note: String,
}

/// A nodal vector field (e.g. velocity) on a 2-D triangle mesh: one stage
/// of [`mesh_vector_fields`].
#[derive(Debug, Clone)]
pub struct MeshVectorField<'a> {
    /// Node coordinates (in the solver's length unit, e.g. metres).
    pub points: &'a [[f64; 2]],
    /// Triangles as node indices into `points`.
    pub triangles: &'a [[usize; 3]],
    /// One vector per node (same length as `points`).
    pub vectors: &'a [[f64; 2]],
    /// Panel title, e.g. `"t = 0.20 ms"`.
    pub title: String,
    /// Colour-bar label with units, e.g. `"|v| [m/s]"`; the first frame's
    /// label is used for the shared colour bar.
    pub colorbar_label: String,
    /// Factor applied to coordinates for the axes (non-positive means 1).
    pub length_unit_scale: f64,
    /// Name of the displayed length unit, e.g. `"cm"`.
    pub length_unit: String,
    /// Line segments drawn over the frame, in the coordinates of `points` (e.g. the
    /// obstacle in contact), cut to the panel.
    pub overlay: Vec<[[f64; 2]; 2]>,
    /// A note printed under the figure (the first frame's), e.g. an angle's convention.
    pub note: String,
}

/// One panel of [`mode_shapes`]: a nodal displacement (a mode shape) on a 2-D triangle
/// mesh, drawn as the deformed mesh over the undeformed outline.
#[derive(Debug, Clone)]
pub struct ModeShape<'a> {
    /// Undeformed node coordinates (in the solver's length unit, e.g. metres).
    pub points: &'a [[f64; 2]],
    /// Triangles as node indices into `points`.
    pub triangles: &'a [[usize; 3]],
    /// The displacement of each node as it is to be drawn (already scaled for display), in
    /// the unit of `points`; same length as `points`.
    pub displacement: &'a [[f64; 2]],
    /// Material lines drawn deformed (thin, dark), given in undeformed coordinates, e.g.
    /// a few rings and spokes of a wheel so that a torsion shows: each point is carried by
    /// the displacement interpolated linearly in the triangle that holds it (a point in no
    /// triangle breaks its line).
    pub lines: Vec<Vec<[f64; 2]>>,
    /// Panel title, e.g. the mode's frequency and kind: two lines if it holds a `\n`
    /// (each set smaller if it does not fit), else wrapped to two lines if needed.
    pub title: String,
    /// Factor applied to coordinates for the axes (non-positive means 1).
    pub length_unit_scale: f64,
    /// Name of the displayed length unit, e.g. `"cm"`.
    pub length_unit: String,
    /// Colour-bar label (the first panel's is used), e.g. `"|u| / max |u|"`.
    pub colorbar_label: String,
    /// A note printed under the figure (the first panel's), e.g. the displacement scale.
    pub note: String,
}

/// Whether element edges are drawn on mesh plots.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum EdgeMode {
    /// Draw thin edges only when the elements are large enough on screen
    /// for the edges not to hide the colours.
    #[default]
    Auto,
    /// Always draw thin element edges.
    Always,
    /// Never draw element edges (the outline of vector-field meshes is
    /// still drawn).
    Never,
}

/// Extra options for [`mesh_color_map_with`] and
/// [`mesh_vector_fields_with`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MeshOptions {
    /// Element-edge drawing.
    pub edges: EdgeMode,
    /// Fixed colour scale `(min, max)` (for vector fields: of the
    /// magnitude); automatic when `None`. Values outside are clamped.
    pub value_range: Option<(f64, f64)>,
}

/// `v` rounded to `sig` significant digits, for the numbers of titles, legends and notes
/// (`omega = 72.5 rad/s`, not `72.46376811594203`): plain decimals from 10⁻³ to below 10⁶
/// with trailing zeros dropped, else `m×10ⁿ`; a typographic minus. One helper for every
/// figure, so that no caption prints a float as Rust's `{}` does.
///
/// ```
/// assert_eq!(softway_plot::sig(72.463_768_115_942_03, 3), "72.5");
/// assert_eq!(softway_plot::sig(839_812.0, 4), "839800");
/// assert_eq!(softway_plot::sig(1.242e-5, 3), "1.24×10⁻⁵");
/// ```
pub fn sig(v: f64, sig: usize) -> String {
    axes::fmt_sig(v, sig)
}

/// Draws one panel of x–y data into a PNG file of `size` = (width, height)
/// pixels.
///
/// A legend is drawn when there is more than one labelled entry or any
/// labelled reference line (horizontal or vertical).
pub fn line_plot(path: &Path, panel: &Panel, size: (u32, u32)) -> Result<(), PlotError> {
    let run = || -> Result<Vec<u8>, Fail> {
        validate_panel(panel)?;
        render(size, |area, fig| {
            let st = Sty::new(fig, (fig.w, fig.h));
            let cell = Rect::new(0.0, 0.0, fig.w, fig.h);
            draw_panel(area, cell, panel, &st)
        })
    };
    let buf = run().map_err(|f| f.at(path))?;
    save_png(path, size, &buf)
}

/// Draws several panels in a `rows` × `cols` grid (row-major order) into
/// one PNG file of `size` = (width, height) pixels.
///
/// Panels without any plottable data show "no data"; if no panel has data
/// the result is [`PlotError::Empty`].
pub fn panels(
    path: &Path,
    panels: &[Panel],
    rows: usize,
    cols: usize,
    size: (u32, u32),
) -> Result<(), PlotError> {
    let run = || -> Result<Vec<u8>, Fail> {
        if panels.is_empty() {
            return Err(Fail::Empty("no panels".into()));
        }
        if rows == 0 || cols == 0 || rows.saturating_mul(cols) < panels.len() {
            return Err(Fail::Draw(format!(
                "a {rows}x{cols} grid cannot hold {} panels",
                panels.len()
            )));
        }
        let mut any = false;
        for p in panels {
            match validate_panel(p) {
                Ok(()) => any = true,
                Err(Fail::Empty(_)) => {}
                Err(e) => return Err(e),
            }
        }
        if !any {
            return Err(Fail::Empty("no panel has finite data".into()));
        }
        render(size, |area, fig| {
            let cw = fig.w / cols as f64;
            let ch = fig.h / rows as f64;
            let st = Sty::new(fig, (cw / fig.k, ch / fig.k));
            let cell_of = |i: usize| {
                let (r, c) = ((i / cols) as f64, (i % cols) as f64);
                Rect::new(c * cw, r * ch, (c + 1.0) * cw, (r + 1.0) * ch)
            };
            // A legend entry listed by an earlier panel is not repeated.
            let mut listed: Vec<String> = Vec::new();
            let seen: Vec<Vec<String>> = panels
                .iter()
                .map(|p| {
                    let before = listed.clone();
                    // Listed only where a legend is drawn (not for a lone series).
                    let keys = legend_keys(p);
                    let drawn = keys.len() > 1 || !p.hlines.is_empty() || !p.vlines.is_empty();
                    if !p.no_legend && drawn {
                        for k in keys {
                            if !listed.contains(&k) {
                                listed.push(k);
                            }
                        }
                    }
                    before
                })
                .collect();
            // First pass: natural layouts; then align the plot rectangles of
            // each column (left/right) and each row (top/bottom).
            let mut col_x = vec![(f64::NEG_INFINITY, f64::INFINITY); cols];
            let mut row_y = vec![(f64::NEG_INFINITY, f64::INFINITY); rows];
            for (i, p) in panels.iter().enumerate() {
                let cell = cell_of(i);
                match layout_panel(cell, p, &st, None, &seen[i]) {
                    Ok(l) => {
                        let (cx, ry) = (&mut col_x[i % cols], &mut row_y[i / cols]);
                        cx.0 = cx.0.max(l.plot.x0 - cell.x0);
                        cx.1 = cx.1.min(l.plot.x1 - cell.x0);
                        ry.0 = ry.0.max(l.plot.y0 - cell.y0);
                        ry.1 = ry.1.min(l.plot.y1 - cell.y0);
                    }
                    Err(Fail::Empty(_)) => {}
                    Err(e) => return Err(e),
                }
            }
            for (i, p) in panels.iter().enumerate() {
                let cell = cell_of(i);
                let (x0, x1) = col_x[i % cols];
                let (y0, y1) = row_y[i / cols];
                let forced =
                    (x0.is_finite() && y0.is_finite() && x1 - x0 >= 20.0 && y1 - y0 >= 20.0)
                        .then(|| Rect::new(cell.x0 + x0, cell.y0 + y0, cell.x0 + x1, cell.y0 + y1));
                match layout_panel(cell, p, &st, forced, &seen[i]) {
                    Ok(l) => paint_panel(area, cell, p, &st, &l)?,
                    Err(Fail::Empty(_)) => draw_no_data(area, cell, p, &st)?,
                    Err(e) => return Err(e),
                }
            }
            Ok(())
        })
    };
    let buf = run().map_err(|f| f.at(path))?;
    save_png(path, size, &buf)
}

/// Draws a per-triangle scalar field as a colour map (viridis) with a colour
/// bar, equal aspect ratio, into a PNG file of `size` pixels.
///
/// Same as [`mesh_color_map_with`] with default [`MeshOptions`].
pub fn mesh_color_map(path: &Path, map: &MeshColorMap, size: (u32, u32)) -> Result<(), PlotError> {
    mesh_color_map_with(path, map, size, &MeshOptions::default())
}

/// [`mesh_color_map`] with explicit options (edges, fixed colour range).
pub fn mesh_color_map_with(
    path: &Path,
    map: &MeshColorMap,
    size: (u32, u32),
    opts: &MeshOptions,
) -> Result<(), PlotError> {
    let buf = render_color_map(map, size, opts).map_err(|f| f.at(path))?;
    save_png(path, size, &buf)
}

/// [`mesh_color_map_with`] with line segments drawn over the colours (in the coordinates
/// of `map.points`, cut to the plot, in a dark red): an outline to compare the field with,
/// such as Hertz's ellipse on a contact's pressure (say what it is in `map.note`).
pub fn mesh_color_map_overlay(
    path: &Path,
    map: &MeshColorMap,
    overlay: &[[[f64; 2]; 2]],
    size: (u32, u32),
    opts: &MeshOptions,
) -> Result<(), PlotError> {
    let buf = render_color_map_overlay(map, overlay, size, opts).map_err(|f| f.at(path))?;
    save_png(path, size, &buf)
}

/// Draws a grid (`cols` columns, 0 = automatic) of small panels, one per
/// frame in row-major order: the mesh (outline, and edges when visible), the
/// vector magnitude as a colour map (per triangle, mean of its nodes) and
/// arrows, centred on their nodes, on an evenly spread subset of nodes
/// (about 12 across). All frames share the colour scale (0 to the largest
/// magnitude), the arrow scale (the largest arrow over all frames is 1/8 of
/// a panel width), the axes extent (union of all frames) and one colour bar.
/// The length unit, the colour-bar label and the note are taken from the first frame. An
/// arrow of a round value under the grid gives the arrows' scale (in the colour bar's unit,
/// the text between `[` and `]` of its label). Colour maps whose values exceed a fixed
/// colour range show it with a triangle at that end of the colour bar.
pub fn mesh_vector_fields(
    path: &Path,
    frames: &[MeshVectorField],
    cols: usize,
    size: (u32, u32),
) -> Result<(), PlotError> {
    mesh_vector_fields_with(path, frames, cols, size, &MeshOptions::default())
}

/// [`mesh_vector_fields`] with explicit options (edges, fixed magnitude
/// range for the colour scale).
pub fn mesh_vector_fields_with(
    path: &Path,
    frames: &[MeshVectorField],
    cols: usize,
    size: (u32, u32),
    opts: &MeshOptions,
) -> Result<(), PlotError> {
    let buf = render_vector_fields(frames, cols, size, opts).map_err(|f| f.at(path))?;
    save_png(path, size, &buf)
}

/// Draws a grid (`cols` columns, 0 = automatic) of mode shapes, one per panel in row-major
/// order: the undeformed outline (grey, dashed), the deformed mesh (its triangles coloured
/// by the displacement's magnitude over that panel's largest, 0 to 1 on one shared colour
/// bar, its element edges when they are large enough to see, its material lines and its
/// outline dark). All panels
/// share the axes extent (the union of the undeformed and deformed meshes) at an equal
/// aspect ratio. The length unit, the colour-bar label and the note are the first panel's.
pub fn mode_shapes(
    path: &Path,
    shapes: &[ModeShape],
    cols: usize,
    size: (u32, u32),
) -> Result<(), PlotError> {
    let buf = render_mode_shapes(shapes, cols, size).map_err(|f| f.at(path))?;
    save_png(path, size, &buf)
}
