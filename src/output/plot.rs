//! PNG figures for reports and papers.
//!
//! * [`line_plot`] / [`panels`]: x–y line plots (one panel or a grid of
//!   panels whose axes are aligned per row and column), with optional
//!   logarithmic axes, reference lines and a legend placed where it hides
//!   no data: inside if possible, else outside to the right of the axes if
//!   there is room, else inside with head room added above the data (only
//!   when the y range is automatic).
//! * [`mesh_color_map`]: a scalar per triangle drawn as a colour map with a
//!   colour bar, equal aspect ratio.
//! * [`mesh_vector_fields`]: a grid of small panels (successive stages),
//!   each showing a nodal vector field as arrows over its magnitude colour
//!   map, with one shared colour scale.
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
//! No function of this module panics on bad data.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Once;

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::register_font;

// ---------------------------------------------------------------------------
// Public API
// ---------------------------------------------------------------------------

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

/// Draws one panel of x–y data into a PNG file of `size` = (width, height)
/// pixels.
///
/// A legend is drawn when there is more than one labelled entry or any
/// labelled reference line.
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
            // First pass: natural layouts; then align the plot rectangles of
            // each column (left/right) and each row (top/bottom).
            let mut col_x = vec![(f64::NEG_INFINITY, f64::INFINITY); cols];
            let mut row_y = vec![(f64::NEG_INFINITY, f64::INFINITY); rows];
            for (i, p) in panels.iter().enumerate() {
                let cell = cell_of(i);
                match layout_panel(cell, p, &st, None) {
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
                match layout_panel(cell, p, &st, forced) {
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

/// Draws a grid (`cols` columns, 0 = automatic) of small panels, one per
/// frame in row-major order: the mesh (outline, and edges when visible), the
/// vector magnitude as a colour map (per triangle, mean of its nodes) and
/// arrows, centred on their nodes, on an evenly spread subset of nodes
/// (about 12 across). All frames share the colour scale (0 to the largest
/// magnitude), the arrow scale (the largest arrow over all frames is 1/8 of
/// a panel width), the axes extent (union of all frames) and one colour bar.
/// The length unit and the colour-bar label are taken from the first frame.
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

// ---------------------------------------------------------------------------
// Errors, fonts, rendering and atomic writing
// ---------------------------------------------------------------------------

/// Internal error, turned into a [`PlotError`] once the path is known.
#[derive(Debug)]
enum Fail {
    Empty(String),
    Draw(String),
}

impl Fail {
    fn at(self, path: &Path) -> PlotError {
        match self {
            Fail::Empty(why) => PlotError::Empty {
                path: path.to_path_buf(),
                why,
            },
            Fail::Draw(message) => PlotError::Draw {
                path: path.to_path_buf(),
                message,
            },
        }
    }
}

type Res<T> = Result<T, Fail>;
type Area<'a> = DrawingArea<BitMapBackend<'a>, Shift>;

fn de<E: std::fmt::Display>(e: E) -> Fail {
    Fail::Draw(e.to_string())
}

const FONT_FAMILY: &str = "DejaVu Sans";
static FONT_INIT: Once = Once::new();
static FONT_OK: AtomicBool = AtomicBool::new(false);

/// Registers the embedded DejaVu Sans font with plotters (once per process).
fn ensure_fonts() -> Res<()> {
    FONT_INIT.call_once(|| {
        let ok = register_font(FONT_FAMILY, FontStyle::Normal, dejavu::sans::regular()).is_ok()
            && register_font(FONT_FAMILY, FontStyle::Bold, dejavu::sans::bold()).is_ok();
        FONT_OK.store(ok, Ordering::Release);
    });
    if FONT_OK.load(Ordering::Acquire) {
        Ok(())
    } else {
        Err(Fail::Draw(
            "cannot register the embedded DejaVu Sans font".into(),
        ))
    }
}

/// Figure geometry in super-sampled pixels.
#[derive(Debug, Clone, Copy)]
struct Fig {
    /// Super-sampling factor.
    k: f64,
    /// Output size in output pixels.
    out: (f64, f64),
    /// Canvas size in super-sampled pixels.
    w: f64,
    h: f64,
}

const MIN_SIZE: (u32, u32) = (120, 90);
const MAX_PIXELS: u64 = 100_000_000;

/// Renders with `draw` on a white, super-sampled canvas and returns the
/// down-sampled RGB buffer of `size`.
fn render<F>(size: (u32, u32), draw: F) -> Res<Vec<u8>>
where
    F: FnOnce(&Area, &Fig) -> Res<()>,
{
    ensure_fonts()?;
    let (w, h) = size;
    if w < MIN_SIZE.0 || h < MIN_SIZE.1 {
        return Err(Fail::Draw(format!(
            "image size {w}x{h} is too small (minimum {}x{})",
            MIN_SIZE.0, MIN_SIZE.1
        )));
    }
    if u64::from(w) * u64::from(h) > MAX_PIXELS {
        return Err(Fail::Draw(format!("image size {w}x{h} is too large")));
    }
    let k: u32 = if u64::from(w) * u64::from(h) <= 4_000_000 {
        2
    } else {
        1
    };
    let (sw, sh) = (w * k, h * k);
    let mut big = vec![255u8; sw as usize * sh as usize * 3];
    {
        let area = BitMapBackend::with_buffer(&mut big, (sw, sh)).into_drawing_area();
        let fig = Fig {
            k: f64::from(k),
            out: (f64::from(w), f64::from(h)),
            w: f64::from(sw),
            h: f64::from(sh),
        };
        // Last line of defence: plotting must never bring the solver down.
        let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| draw(&area, &fig)));
        match result {
            Ok(r) => r?,
            Err(_) => return Err(Fail::Draw("internal error while drawing".into())),
        }
        area.present().map_err(de)?;
    }
    Ok(downsample(&big, (w, h), k))
}

/// Box-filter down-sampling of an RGB buffer by the integer factor `k`.
fn downsample(big: &[u8], (w, h): (u32, u32), k: u32) -> Vec<u8> {
    if k == 1 {
        return big.to_vec();
    }
    let (w, h, k) = (w as usize, h as usize, k as usize);
    let sw = w * k;
    let n = (k * k) as u32;
    let mut out = vec![0u8; w * h * 3];
    for y in 0..h {
        for x in 0..w {
            for c in 0..3 {
                let mut s = 0u32;
                for dy in 0..k {
                    let row = (y * k + dy) * sw;
                    for dx in 0..k {
                        s += u32::from(big[(row + x * k + dx) * 3 + c]);
                    }
                }
                out[(y * w + x) * 3 + c] = ((s + n / 2) / n) as u8;
            }
        }
    }
    out
}

/// Writes the RGB buffer as PNG to `<path>.tmp.png`, then renames it to
/// `path`.
fn save_png(path: &Path, size: (u32, u32), rgb: &[u8]) -> Result<(), PlotError> {
    let fail = |message: String| PlotError::Draw {
        path: path.to_path_buf(),
        message,
    };
    let name = path
        .file_name()
        .ok_or_else(|| fail("the path has no file name".into()))?;
    if let Some(parent) = path.parent() {
        if !parent.as_os_str().is_empty() {
            std::fs::create_dir_all(parent)
                .map_err(|e| fail(format!("cannot create {}: {e}", parent.display())))?;
        }
    }
    let mut tmp_name = name.to_os_string();
    tmp_name.push(".tmp.png");
    let tmp = path.with_file_name(tmp_name);
    let written = (|| -> Result<(), String> {
        let mut backend = BitMapBackend::new(&tmp, size);
        backend
            .blit_bitmap((0, 0), size, rgb)
            .map_err(|e| e.to_string())?;
        backend.present().map_err(|e| e.to_string())?;
        Ok(())
    })();
    let result = written.and_then(|()| {
        std::fs::rename(&tmp, path).map_err(|e| format!("cannot rename {}: {e}", tmp.display()))
    });
    if let Err(message) = result {
        let _ = std::fs::remove_file(&tmp);
        return Err(fail(message));
    }
    Ok(())
}

// ---------------------------------------------------------------------------
// Styling: sizes, colours, text
// ---------------------------------------------------------------------------

/// Sizes in super-sampled pixels, derived from the figure and cell sizes.
#[derive(Debug, Clone, Copy)]
struct Sty {
    /// Tick-label font size.
    fs: f64,
    /// Axis-label font size.
    fl: f64,
    /// Title font size.
    ft: f64,
    /// Legend font size.
    fleg: f64,
    /// Series line width.
    lw: f64,
    /// Thin lines (grid, ticks, reference lines).
    thin: f64,
    /// Frame line width.
    frame: f64,
    /// Generic padding.
    pad: f64,
    /// Major tick length.
    tick: f64,
}

impl Sty {
    /// `cell` is the size of one panel in output pixels.
    fn new(fig: &Fig, cell: (f64, f64)) -> Self {
        let (w, h) = fig.out;
        let diag = (w * h).sqrt();
        let mut f = diag / 48.0;
        let c = (cell.0 * cell.1).sqrt() / diag;
        if c < 0.7 {
            f *= (c / 0.7).sqrt();
        }
        let f = f.clamp(12.0, 40.0).min(cell.0.min(cell.1) / 14.0).max(7.0);
        let k = fig.k;
        let fs = f * k;
        Sty {
            fs,
            fl: 1.1 * fs,
            ft: 1.2 * fs,
            fleg: 0.95 * fs,
            lw: (f / 10.0).max(1.0) * k,
            thin: (f / 20.0).max(1.0) * k,
            frame: (f / 16.0).max(1.0) * k,
            pad: 0.5 * fs,
            tick: 0.35 * fs,
        }
    }
}

/// Colour-blind-safe qualitative palette (Okabe & Ito), reordered so that
/// the first colours are the most distinct on white.
const PALETTE: [RGBColor; 7] = [
    RGBColor(0, 114, 178),   // blue
    RGBColor(213, 94, 0),    // vermillion
    RGBColor(0, 158, 115),   // bluish green
    RGBColor(204, 121, 167), // reddish purple
    RGBColor(230, 159, 0),   // orange
    RGBColor(86, 180, 233),  // sky blue
    RGBColor(0, 0, 0),       // black
];
const GRID_MAJOR: RGBColor = RGBColor(222, 222, 222);
const GRID_MINOR: RGBColor = RGBColor(244, 244, 244);
const REF_LINE: RGBColor = RGBColor(110, 110, 110);
const TEXT: RGBColor = RGBColor(0, 0, 0);
const NO_DATA: RGBColor = RGBColor(205, 205, 205);

fn series_color(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

/// Viridis (matplotlib's default perceptual colour map), 10 samples.
const VIRIDIS: [(u8, u8, u8); 10] = [
    (0x44, 0x01, 0x54),
    (0x48, 0x28, 0x78),
    (0x3e, 0x4a, 0x89),
    (0x31, 0x68, 0x8e),
    (0x26, 0x82, 0x8e),
    (0x1f, 0x9e, 0x89),
    (0x35, 0xb7, 0x79),
    (0x6d, 0xcd, 0x59),
    (0xb4, 0xde, 0x2c),
    (0xfd, 0xe7, 0x25),
];

fn viridis(t: f64) -> RGBColor {
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let x = t * (VIRIDIS.len() - 1) as f64;
    let i = (x.floor() as usize).min(VIRIDIS.len() - 2);
    let f = x - i as f64;
    let (a, b) = (VIRIDIS[i], VIRIDIS[i + 1]);
    let l = |p: u8, q: u8| (f64::from(p) + f * (f64::from(q) - f64::from(p))).round() as u8;
    RGBColor(l(a.0, b.0), l(a.1, b.1), l(a.2, b.2))
}

fn sw(width: f64) -> u32 {
    width.round().max(1.0) as u32
}

fn ipt((x, y): (f64, f64)) -> (i32, i32) {
    (x.round() as i32, y.round() as i32)
}

/// DejaVu Sans metrics (fractions of the em size).
const CAP: f64 = 0.729;
const DESC: f64 = 0.236;

#[derive(Clone, Copy)]
enum HA {
    Left,
    Center,
    Right,
}

#[derive(Clone, Copy)]
enum VA {
    /// Reference is the top of capitals/digits.
    Top,
    /// Reference is the middle of capitals/digits.
    Center,
    /// Reference is the baseline.
    Baseline,
}

fn font(size: f64) -> FontDesc<'static> {
    FontDesc::new(FontFamily::Name(FONT_FAMILY), size, FontStyle::Normal)
}

/// Advance width of `text` at font size `size`.
fn text_w(text: &str, size: f64) -> f64 {
    match font(size).box_size(text) {
        Ok((w, _)) => f64::from(w),
        Err(_) => 0.6 * size * text.chars().count() as f64,
    }
}

/// Draws `text` with its reference point at `(x, y)`. When `rotated`, the
/// text reads bottom to top (like a y-axis label); `ha` then refers to the
/// direction along the text and `va` to the perpendicular one, where "top"
/// is towards the left.
#[allow(clippy::too_many_arguments)]
fn draw_text(
    area: &Area,
    text: &str,
    (x, y): (f64, f64),
    size: f64,
    ha: HA,
    va: VA,
    rotated: bool,
    color: RGBColor,
) -> Res<()> {
    if text.is_empty() {
        return Ok(());
    }
    let w = text_w(text, size);
    let b = match va {
        VA::Top => CAP * size,
        VA::Center => 0.5 * CAP * size,
        VA::Baseline => 0.0,
    };
    let along = match ha {
        HA::Left => 0.0,
        HA::Center => -0.5 * w,
        HA::Right => -w,
    };
    // plotters' ab_glyph renderer puts the baseline `size / 2` below the
    // anchor of a left/top anchored text.
    let style = TextStyle::from(font(size)).color(&color);
    let (style, px, py) = if rotated {
        (
            style.transform(FontTransform::Rotate270),
            x + b - 0.5 * size,
            y - along,
        )
    } else {
        (style, x + along, y + b - 0.5 * size)
    };
    area.draw_text(text, &style, ipt((px, py))).map_err(de)
}

// ---------------------------------------------------------------------------
// Number formatting and ticks
// ---------------------------------------------------------------------------

fn superscript(n: i32) -> String {
    n.to_string()
        .chars()
        .map(|c| match c {
            '-' => '⁻',
            '0' => '⁰',
            '1' => '¹',
            '2' => '²',
            '3' => '³',
            '4' => '⁴',
            '5' => '⁵',
            '6' => '⁶',
            '7' => '⁷',
            '8' => '⁸',
            '9' => '⁹',
            c => c,
        })
        .collect()
}

/// Replaces a leading hyphen by a typographic minus sign.
fn fix_minus(s: String) -> String {
    match s.strip_prefix('-') {
        Some(r) => format!("−{r}"),
        None => s,
    }
}

fn trim_zeros(s: String) -> String {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// Smallest number of decimals that represents `x` (a tick step) exactly.
fn decimals_needed(x: f64) -> usize {
    let x = x.abs();
    for d in 0..=12 {
        let s = x * 10f64.powi(d);
        if (s - s.round()).abs() <= 1e-6 * s.max(1.0) {
            return d as usize;
        }
    }
    12
}

/// `v` with `d` decimals, no negative zero, typographic minus.
fn fmt_fixed(v: f64, d: usize) -> String {
    let s = format!("{v:.d$}");
    let zero = s
        .trim_start_matches('-')
        .chars()
        .all(|c| c == '0' || c == '.');
    if zero {
        s.trim_start_matches('-').to_string()
    } else {
        fix_minus(s)
    }
}

/// Short general-purpose formatting (up to 6 significant digits), with
/// powers of ten for very large or small magnitudes.
fn fmt_general(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return if v == 0.0 { "0".into() } else { v.to_string() };
    }
    let a = v.abs();
    if (1e-3..1e5).contains(&a) {
        let d = (5 - a.log10().floor() as i32).clamp(0, 9) as usize;
        return fix_minus(trim_zeros(format!("{v:.d$}")));
    }
    fmt_pow(v)
}

/// `m×10ⁿ` (or `10ⁿ`) formatting.
fn fmt_pow(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let a = v.abs();
    let mut e = a.log10().floor() as i32;
    let mut m = v / 10f64.powi(e);
    if (m.abs() * 1000.0).round() >= 10_000.0 {
        e += 1;
        m = v / 10f64.powi(e);
    }
    let ms = trim_zeros(format!("{m:.3}"));
    match ms.as_str() {
        "1" => format!("10{}", superscript(e)),
        "-1" => format!("−10{}", superscript(e)),
        _ => format!("{}×10{}", fix_minus(ms), superscript(e)),
    }
}

/// Labels for equally spaced linear ticks, with a common power-of-ten
/// factor (returned separately, e.g. `×10⁻³`) for very large or small
/// magnitudes.
fn format_linear(values: &[f64], step: f64) -> (Vec<String>, Option<String>) {
    let m = values.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let e = if m > 0.0 && !(1e-2..1e5).contains(&m) {
        m.log10().floor() as i32
    } else {
        0
    };
    let f = 10f64.powi(e);
    let d = decimals_needed(step / f);
    let labels = values.iter().map(|v| fmt_fixed(v / f, d)).collect();
    (labels, (e != 0).then(|| format!("×10{}", superscript(e))))
}

#[derive(Debug, Default, Clone)]
struct Ticks {
    major: Vec<(f64, String)>,
    minor: Vec<f64>,
    /// Common factor of the labels, e.g. `×10⁻³`.
    offset: Option<String>,
}

impl Ticks {
    fn max_label_w(&self, fs: f64) -> f64 {
        self.major
            .iter()
            .map(|(_, l)| text_w(l, fs))
            .fold(0.0, f64::max)
    }
}

/// Minimal pixel distance between tick labels.
fn tick_need(labels: &[String], fs: f64, horizontal: bool) -> f64 {
    if horizontal {
        labels.iter().map(|l| text_w(l, fs)).fold(0.0, f64::max) + 1.2 * fs
    } else {
        2.2 * fs
    }
}

fn linear_ticks(lo: f64, hi: f64, len_px: f64, fs: f64, horizontal: bool) -> Ticks {
    let span = hi - lo;
    if !(span > 0.0 && span.is_finite() && len_px > 0.0) {
        return Ticks::default();
    }
    let max_n = if horizontal { 9 } else { 8 };
    let mut e = (span / 20.0).log10().floor() as i32;
    let mut fallback: Option<Ticks> = None;
    for _ in 0..10 {
        let p = 10f64.powi(e);
        for m in [1.0, 2.0, 2.5, 5.0] {
            let step = m * p;
            let k0 = (lo / step - 1e-9).ceil();
            let k1 = (hi / step + 1e-9).floor();
            if !(k0.is_finite() && k1.is_finite()) {
                continue;
            }
            let nf = if k1 >= k0 { k1 - k0 + 1.0 } else { 0.0 };
            if nf > max_n as f64 {
                continue;
            }
            let n = nf as usize;
            let values: Vec<f64> = (0..n)
                .map(|i| {
                    let v = (k0 + i as f64) * step;
                    if v.abs() < step * 1e-9 {
                        0.0
                    } else {
                        v
                    }
                })
                .collect();
            let (labels, offset) = format_linear(&values, step);
            let spacing = step / span * len_px;
            let fits = spacing >= tick_need(&labels, fs, horizontal);
            let t = Ticks {
                major: values.into_iter().zip(labels).collect(),
                minor: Vec::new(),
                offset,
            };
            if fits {
                return t;
            }
            if fallback.is_none() || n >= 1 {
                fallback = Some(t);
            }
        }
        e += 1;
    }
    fallback.unwrap_or_default()
}

fn log_label(v: f64, pow: bool) -> String {
    if pow {
        fmt_pow(v)
    } else {
        fmt_general(v)
    }
}

fn log_ticks(lo: f64, hi: f64, len_px: f64, fs: f64, horizontal: bool) -> Ticks {
    if !(lo > 0.0 && hi > lo && hi.is_finite() && len_px > 0.0) {
        return Ticks::default();
    }
    let (l0, l1) = (lo.log10(), hi.log10());
    let k0 = (l0 - 1e-9).ceil() as i32;
    let k1 = (l1 + 1e-9).floor() as i32;
    let (dec, sub) = (
        || decade_ticks(lo, hi, len_px, fs, horizontal),
        || sub_decade_ticks(lo, hi, len_px, fs, horizontal),
    );
    // With three or more decades label (some of) the decades; over a
    // shorter range prefer 1-2-5 style values, which say more.
    let t = if k1 - k0 >= 2 {
        dec().or_else(sub)
    } else {
        sub().or_else(dec)
    };
    t.unwrap_or_else(|| linear_ticks(lo, hi, len_px, fs, horizontal))
}

fn in_log_range(v: f64, lo: f64, hi: f64) -> bool {
    v >= lo * (1.0 - 1e-9) && v <= hi * (1.0 + 1e-9)
}

/// Log-axis labels: plain numbers when all values lie in `plain`, else
/// powers of ten.
fn log_labels(vals: &[f64], plain: std::ops::Range<f64>) -> Vec<String> {
    let pow = vals.iter().any(|&v| !plain.contains(&v));
    vals.iter().map(|&v| log_label(v, pow)).collect()
}

/// Every `stride`-th decade as major ticks, the rest (or 2…9) as minor.
fn decade_ticks(lo: f64, hi: f64, len_px: f64, fs: f64, horizontal: bool) -> Option<Ticks> {
    let (l0, l1) = (lo.log10(), hi.log10());
    let k0 = (l0 - 1e-9).ceil() as i32;
    let k1 = (l1 + 1e-9).floor() as i32;
    let px_per_dec = len_px / (l1 - l0);
    for stride in 1..=(k1 - k0).max(1) {
        let ks: Vec<i32> = (k0..=k1).filter(|k| k.rem_euclid(stride) == 0).collect();
        if ks.len() < 2 {
            return None;
        }
        let vals: Vec<f64> = ks.iter().map(|&k| 10f64.powi(k)).collect();
        let labels = log_labels(&vals, 1e-2..1e4);
        if ks.len() <= 10 && f64::from(stride) * px_per_dec >= tick_need(&labels, fs, horizontal) {
            let mut minor = Vec::new();
            if stride == 1 {
                if px_per_dec >= 2.5 * fs {
                    for k in (k0 - 1)..=k1 {
                        for m in 2..=9 {
                            let v = f64::from(m) * 10f64.powi(k);
                            if in_log_range(v, lo, hi) {
                                minor.push(v);
                            }
                        }
                    }
                }
            } else {
                minor = (k0..=k1)
                    .filter(|k| k.rem_euclid(stride) != 0)
                    .map(|k| 10f64.powi(k))
                    .collect();
            }
            return Some(Ticks {
                major: vals.into_iter().zip(labels).collect(),
                minor,
                offset: None,
            });
        }
    }
    None
}

/// Ticks at m·10ᵏ for m in a 1-2-5 style set, densest set that fits.
fn sub_decade_ticks(lo: f64, hi: f64, len_px: f64, fs: f64, horizontal: bool) -> Option<Ticks> {
    let (l0, l1) = (lo.log10(), hi.log10());
    let px = |v: f64| (v.log10() - l0) / (l1 - l0) * len_px;
    let multiples = |set: &[f64]| {
        let mut vals = Vec::new();
        for k in (l0.floor() as i32 - 1)..=(l1.ceil() as i32) {
            for &m in set {
                let v = m * 10f64.powi(k);
                if in_log_range(v, lo, hi) {
                    vals.push(v);
                }
            }
        }
        vals
    };
    const ALL: [f64; 9] = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0];
    let sets: [&[f64]; 5] = [
        &ALL,
        &[1.0, 2.0, 3.0, 5.0],
        &[1.0, 2.0, 5.0],
        &[1.0, 3.0],
        &[1.0],
    ];
    for set in sets {
        let vals = multiples(set);
        if vals.len() < 2 || vals.len() > 10 {
            continue;
        }
        let labels = log_labels(&vals, 1e-3..1e5);
        let min_gap = vals
            .windows(2)
            .map(|w| px(w[1]) - px(w[0]))
            .fold(f64::INFINITY, f64::min);
        if min_gap >= tick_need(&labels, fs, horizontal) {
            let minor = if set.len() < ALL.len() {
                multiples(&ALL)
                    .into_iter()
                    .filter(|v| !vals.iter().any(|w| (v / w - 1.0).abs() < 1e-9))
                    .collect()
            } else {
                Vec::new()
            };
            return Some(Ticks {
                major: vals.into_iter().zip(labels).collect(),
                minor,
                offset: None,
            });
        }
    }
    None
}

fn make_ticks(lo: f64, hi: f64, log: bool, len_px: f64, fs: f64, horizontal: bool) -> Ticks {
    if log {
        log_ticks(lo, hi, len_px, fs, horizontal)
    } else {
        linear_ticks(lo, hi, len_px, fs, horizontal)
    }
}

// ---------------------------------------------------------------------------
// Geometry helpers
// ---------------------------------------------------------------------------

#[derive(Debug, Clone, Copy)]
struct Rect {
    x0: f64,
    y0: f64,
    x1: f64,
    y1: f64,
}

impl Rect {
    fn new(x0: f64, y0: f64, x1: f64, y1: f64) -> Self {
        Rect { x0, y0, x1, y1 }
    }
    fn w(&self) -> f64 {
        self.x1 - self.x0
    }
    fn h(&self) -> f64 {
        self.y1 - self.y0
    }
    fn cx(&self) -> f64 {
        0.5 * (self.x0 + self.x1)
    }
    fn cy(&self) -> f64 {
        0.5 * (self.y0 + self.y1)
    }
    fn grow(&self, d: f64) -> Rect {
        Rect::new(self.x0 - d, self.y0 - d, self.x1 + d, self.y1 + d)
    }
    fn contains(&self, (x, y): (f64, f64)) -> bool {
        x >= self.x0 && x <= self.x1 && y >= self.y0 && y <= self.y1
    }
}

type Pt = (f64, f64);

/// Liang–Barsky clipping of segment `a`–`b` to `r`. Returns the clipped
/// end points and whether each one is the original point.
fn clip_segment(a: Pt, b: Pt, r: &Rect) -> Option<(Pt, Pt, bool, bool)> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let mut t0: f64 = 0.0;
    let mut t1: f64 = 1.0;
    for (p, q) in [
        (-dx, a.0 - r.x0),
        (dx, r.x1 - a.0),
        (-dy, a.1 - r.y0),
        (dy, r.y1 - a.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let t = q / p;
            if p < 0.0 {
                t0 = t0.max(t);
            } else {
                t1 = t1.min(t);
            }
            if t0 > t1 {
                return None;
            }
        }
    }
    let pa = (a.0 + t0 * dx, a.1 + t0 * dy);
    let pb = (a.0 + t1 * dx, a.1 + t1 * dy);
    Some((pa, pb, t0 == 0.0, t1 == 1.0))
}

/// Splits a sequence of optional pixel points into polylines clipped to
/// `r`; `None` breaks the line. Also returns isolated points (valid points
/// without valid neighbours) inside `r`.
fn clip_polylines(pts: &[Option<Pt>], r: &Rect) -> (Vec<Vec<Pt>>, Vec<Pt>) {
    let mut lines = Vec::new();
    let mut isolated = Vec::new();
    let mut cur: Vec<Pt> = Vec::new();
    let flush = |cur: &mut Vec<Pt>, lines: &mut Vec<Vec<Pt>>| {
        if cur.len() >= 2 {
            lines.push(std::mem::take(cur));
        } else {
            cur.clear();
        }
    };
    for (i, p) in pts.iter().enumerate() {
        let prev = if i > 0 { pts[i - 1] } else { None };
        let next = pts.get(i + 1).copied().flatten();
        match (prev, *p) {
            (Some(a), Some(b)) => match clip_segment(a, b, r) {
                Some((ca, cb, a_in, b_in)) => {
                    if cur.is_empty() || !a_in {
                        flush(&mut cur, &mut lines);
                        cur.push(ca);
                    }
                    cur.push(cb);
                    if !b_in {
                        flush(&mut cur, &mut lines);
                    }
                }
                None => flush(&mut cur, &mut lines),
            },
            (None, Some(b)) => {
                flush(&mut cur, &mut lines);
                if next.is_none() && r.contains(b) {
                    isolated.push(b);
                }
            }
            (_, None) => flush(&mut cur, &mut lines),
        }
    }
    flush(&mut cur, &mut lines);
    (lines, isolated)
}

/// Cuts polylines into dashes of length `on` separated by gaps `off`.
fn dash_polyline(pts: &[Pt], on: f64, off: f64) -> Vec<Vec<Pt>> {
    let mut out = Vec::new();
    if pts.len() < 2 || on <= 0.0 || off <= 0.0 {
        return out;
    }
    let mut drawing = true;
    let mut left = on;
    let mut cur = vec![pts[0]];
    for w in pts.windows(2) {
        let (mut a, b) = (w[0], w[1]);
        let mut len = ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt();
        while len > 0.0 {
            if len <= left {
                left -= len;
                len = 0.0;
                if drawing {
                    cur.push(b);
                }
            } else {
                let t = left / len;
                let p = (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1));
                if drawing {
                    cur.push(p);
                    out.push(std::mem::take(&mut cur));
                } else {
                    cur = vec![p];
                }
                len -= left;
                a = p;
                drawing = !drawing;
                left = if drawing { on } else { off };
            }
        }
    }
    if drawing && cur.len() >= 2 {
        out.push(cur);
    }
    out
}

fn draw_polyline(area: &Area, pts: &[Pt], color: RGBAColor, width: f64) -> Res<()> {
    let mut v: Vec<(i32, i32)> = Vec::with_capacity(pts.len());
    for &p in pts {
        let q = ipt(p);
        if v.last() != Some(&q) {
            v.push(q);
        }
    }
    if v.len() < 2 {
        return Ok(());
    }
    let style = ShapeStyle {
        color,
        filled: false,
        stroke_width: sw(width),
    };
    area.draw(&PathElement::new(v, style)).map_err(de)
}

fn draw_line(area: &Area, a: Pt, b: Pt, color: RGBColor, width: f64) -> Res<()> {
    draw_polyline(area, &[a, b], color.to_rgba(), width)
}

fn fill_rect(area: &Area, r: Rect, color: RGBAColor) -> Res<()> {
    area.draw(&Rectangle::new(
        [ipt((r.x0, r.y0)), ipt((r.x1, r.y1))],
        color.filled(),
    ))
    .map_err(de)
}

fn stroke_rect(area: &Area, r: Rect, color: RGBColor, width: f64) -> Res<()> {
    let pts = [
        (r.x0, r.y0),
        (r.x1, r.y0),
        (r.x1, r.y1),
        (r.x0, r.y1),
        (r.x0, r.y0),
    ];
    draw_polyline(area, &pts, color.to_rgba(), width)
}

fn fill_polygon(area: &Area, pts: &[Pt], color: RGBColor) -> Res<()> {
    let v: Vec<(i32, i32)> = pts.iter().map(|&p| ipt(p)).collect();
    area.draw(&Polygon::new(v, color.filled())).map_err(de)
}

/// Filled marker of the given shape index (circle, square, triangle,
/// diamond, inverted triangle) with "radius" `r`.
fn draw_marker(area: &Area, (x, y): Pt, shape: usize, r: f64, color: RGBColor) -> Res<()> {
    match shape % 5 {
        0 => area
            .draw(&Circle::new(
                ipt((x, y)),
                r.round().max(1.0) as i32,
                color.filled(),
            ))
            .map_err(de),
        1 => {
            let h = 0.85 * r;
            fill_rect(area, Rect::new(x - h, y - h, x + h, y + h), color.to_rgba())
        }
        2 => fill_polygon(
            area,
            &[
                (x, y - 1.2 * r),
                (x + 1.05 * r, y + 0.65 * r),
                (x - 1.05 * r, y + 0.65 * r),
            ],
            color,
        ),
        3 => fill_polygon(
            area,
            &[
                (x, y - 1.2 * r),
                (x + 0.95 * r, y),
                (x, y + 1.2 * r),
                (x - 0.95 * r, y),
            ],
            color,
        ),
        _ => fill_polygon(
            area,
            &[
                (x, y + 1.2 * r),
                (x + 1.05 * r, y - 0.65 * r),
                (x - 1.05 * r, y - 0.65 * r),
            ],
            color,
        ),
    }
}

// ---------------------------------------------------------------------------
// Line plots
// ---------------------------------------------------------------------------

/// Data → pixel mapping of one axis.
#[derive(Debug, Clone, Copy)]
struct Scale {
    lo: f64,
    hi: f64,
    log: bool,
    /// Pixel of `lo` and of `hi`.
    p_lo: f64,
    p_hi: f64,
}

impl Scale {
    fn frac(&self, v: f64) -> f64 {
        if self.log {
            (v.ln() - self.lo.ln()) / (self.hi.ln() - self.lo.ln())
        } else {
            // Halved to stay finite for ranges close to ±f64::MAX.
            (0.5 * v - 0.5 * self.lo) / (0.5 * self.hi - 0.5 * self.lo)
        }
    }
    fn px(&self, v: f64) -> f64 {
        self.p_lo + self.frac(v) * (self.p_hi - self.p_lo)
    }
}

fn valid(v: f64, log: bool) -> bool {
    v.is_finite() && (!log || v > 0.0)
}

fn is_const(lo: f64, hi: f64) -> bool {
    hi - lo <= 1e-12 * lo.abs().max(hi.abs())
}

/// Data extent → axis range: 5 % margins; constant data gets some width.
fn auto_range(lo: f64, hi: f64, log: bool) -> (f64, f64) {
    if log {
        let (a, b) = (lo.log10(), hi.log10());
        let (a, b) = if b - a < 1e-9 {
            (a - 0.5, b + 0.5)
        } else {
            let m = 0.05 * (b - a);
            (a - m, b + m)
        };
        (10f64.powf(a), 10f64.powf(b))
    } else if is_const(lo, hi) {
        let c = 0.5 * (lo + hi);
        let h = if c == 0.0 { 1.0 } else { 0.1 * c.abs() };
        (c - h, c + h)
    } else {
        let m = 0.05 * hi - 0.05 * lo;
        ((lo - m).max(f64::MIN), (hi + m).min(f64::MAX))
    }
}

/// A user range if usable, else the automatic range of the data extent.
fn resolve_range(
    user: Option<(f64, f64)>,
    data: Option<(f64, f64)>,
    log: bool,
) -> Option<(f64, f64)> {
    if let Some((a, b)) = user {
        let (a, b) = if a <= b { (a, b) } else { (b, a) };
        if valid(a, log) && valid(b, log) {
            let degenerate = if log {
                b / a < 1.0 + 1e-9
            } else {
                is_const(a, b)
            };
            return Some(if degenerate {
                auto_range(a, b, log)
            } else {
                (a, b)
            });
        }
    }
    data.map(|(a, b)| auto_range(a, b, log))
}

fn extend(r: &mut Option<(f64, f64)>, v: f64) {
    *r = Some(match *r {
        None => (v, v),
        Some((a, b)) => (a.min(v), b.max(v)),
    });
}

fn validate_panel(p: &Panel) -> Res<()> {
    for (i, s) in p.series.iter().enumerate() {
        if s.x.len() != s.y.len() {
            return Err(Fail::Draw(format!(
                "series {i} ({:?}) has {} x values but {} y values",
                s.label,
                s.x.len(),
                s.y.len()
            )));
        }
    }
    let any = p.series.iter().any(|s| {
        s.x.iter()
            .zip(&s.y)
            .any(|(&x, &y)| valid(x, p.x_log) && valid(y, p.y_log))
    });
    if any {
        Ok(())
    } else if p.series.is_empty() {
        Err(Fail::Empty("the panel has no series".into()))
    } else {
        Err(Fail::Empty(format!(
            "no series of panel {:?} has a finite{} point",
            p.title,
            if p.x_log || p.y_log {
                " (positive on log axes)"
            } else {
                ""
            }
        )))
    }
}

/// Axis ranges of a panel (x, y).
fn panel_ranges(p: &Panel) -> Res<((f64, f64), (f64, f64))> {
    let mut dx = None;
    for s in &p.series {
        for (&x, &y) in s.x.iter().zip(&s.y) {
            if valid(x, p.x_log) && valid(y, p.y_log) {
                extend(&mut dx, x);
            }
        }
    }
    let xr = resolve_range(p.x_range, dx, p.x_log)
        .ok_or_else(|| Fail::Empty("no finite data".into()))?;
    let mut dy = None;
    for s in &p.series {
        for (&x, &y) in s.x.iter().zip(&s.y) {
            if valid(x, p.x_log) && valid(y, p.y_log) && x >= xr.0 && x <= xr.1 {
                extend(&mut dy, y);
            }
        }
    }
    for (y, _) in &p.hlines {
        if valid(*y, p.y_log) {
            extend(&mut dy, *y);
        }
    }
    let yr = resolve_range(p.y_range, dy, p.y_log)
        .or_else(|| resolve_range(None, dx.map(|_| (1.0, 1.0)), p.y_log))
        .ok_or_else(|| Fail::Empty("no finite data".into()))?;
    Ok((xr, yr))
}

#[derive(Debug, Clone)]
enum EntryKind {
    Series {
        color: RGBColor,
        style: SeriesStyle,
        shape: usize,
    },
    Reference,
}

#[derive(Debug, Clone)]
struct Entry {
    label: String,
    kind: EntryKind,
}

struct LegendGeom {
    w: f64,
    h: f64,
    row: f64,
    sample: f64,
}

fn legend_geom(entries: &[Entry], st: &Sty) -> LegendGeom {
    let f = st.fleg;
    let sample = 2.4 * f;
    let tw = entries
        .iter()
        .map(|e| text_w(&e.label, f))
        .fold(0.0, f64::max);
    let row = 1.4 * f;
    LegendGeom {
        w: 0.6 * f + sample + 0.5 * f + tw + 0.7 * f,
        h: entries.len() as f64 * row + 0.5 * f,
        row,
        sample,
    }
}

fn draw_legend(area: &Area, r: Rect, entries: &[Entry], g: &LegendGeom, st: &Sty) -> Res<()> {
    fill_rect(area, r, WHITE.mix(0.9))?;
    stroke_rect(area, r, RGBColor(175, 175, 175), st.thin)?;
    let f = st.fleg;
    for (i, e) in entries.iter().enumerate() {
        let cy = r.y0 + 0.25 * f + (i as f64 + 0.5) * g.row;
        let (a, b) = ((r.x0 + 0.6 * f, cy), (r.x0 + 0.6 * f + g.sample, cy));
        match &e.kind {
            EntryKind::Series {
                color,
                style,
                shape,
            } => {
                let c = color.to_rgba();
                match style {
                    SeriesStyle::Line => draw_polyline(area, &[a, b], c, st.lw)?,
                    SeriesStyle::Dashed => {
                        for d in dash_polyline(&[a, b], 3.0 * st.lw, 2.2 * st.lw) {
                            draw_polyline(area, &d, c, st.lw)?;
                        }
                    }
                    SeriesStyle::Markers => {
                        draw_marker(area, (0.5 * (a.0 + b.0), cy), *shape, 2.2 * st.lw, *color)?
                    }
                    SeriesStyle::LineMarkers => {
                        draw_polyline(area, &[a, b], c, st.lw)?;
                        draw_marker(area, (0.5 * (a.0 + b.0), cy), *shape, 2.2 * st.lw, *color)?;
                    }
                }
            }
            EntryKind::Reference => {
                for d in dash_polyline(&[a, b], 4.0 * st.thin, 3.0 * st.thin) {
                    draw_polyline(area, &d, REF_LINE.to_rgba(), 1.3 * st.thin)?;
                }
            }
        }
        draw_text(
            area,
            &e.label,
            (b.0 + 0.5 * f, cy),
            f,
            HA::Left,
            VA::Center,
            false,
            TEXT,
        )?;
    }
    Ok(())
}

/// How much of the data a legend at `r` would hide.
fn legend_overlap(r: &Rect, lines: &[Vec<Pt>], marks: &[Pt], hlines: &[f64]) -> usize {
    let mut n = 0;
    for l in lines {
        for w in l.windows(2) {
            let (a, b) = (w[0], w[1]);
            if a.0.max(b.0) < r.x0
                || a.0.min(b.0) > r.x1
                || a.1.max(b.1) < r.y0
                || a.1.min(b.1) > r.y1
            {
                continue;
            }
            if clip_segment(a, b, r).is_some() {
                n += 1;
            }
        }
    }
    n += marks.iter().filter(|&&p| r.contains(p)).count();
    n += hlines.iter().filter(|&&y| y >= r.y0 && y <= r.y1).count() * 3;
    n
}

/// Pixel-space geometry of one series.
struct SeriesPx {
    lines: Vec<Vec<Pt>>,
    isolated: Vec<Pt>,
    markers: Vec<Pt>,
}

fn series_pixels(s: &Series, xs: &Scale, ys: &Scale, plot: &Rect, lw: f64) -> SeriesPx {
    let pts: Vec<Option<Pt>> =
        s.x.iter()
            .zip(&s.y)
            .map(|(&x, &y)| {
                if !(valid(x, xs.log) && valid(y, ys.log)) {
                    return None;
                }
                let q = (xs.px(x), ys.px(y));
                (q.0.is_finite() && q.1.is_finite()).then_some(q)
            })
            .collect();
    let clip = plot.grow(0.5 * lw);
    let (lines, isolated) = match s.style {
        SeriesStyle::Markers => (Vec::new(), Vec::new()),
        _ => clip_polylines(&pts, &clip),
    };
    let markers: Vec<Pt> = match s.style {
        SeriesStyle::Markers => pts.iter().flatten().copied().collect(),
        SeriesStyle::LineMarkers => {
            let valid_pts: Vec<Pt> = pts.iter().flatten().copied().collect();
            let every = valid_pts.len().div_ceil(25).max(1);
            valid_pts.into_iter().step_by(every).collect()
        }
        _ => Vec::new(),
    }
    .into_iter()
    .filter(|&p| plot.grow(1.0).contains(p))
    .collect();
    SeriesPx {
        lines,
        isolated,
        markers,
    }
}

/// Draws a panel that has no data: frame, title and "no data".
fn draw_no_data(area: &Area, cell: Rect, p: &Panel, st: &Sty) -> Res<()> {
    let r = Rect::new(
        cell.x0 + 4.0 * st.fs,
        cell.y0 + 3.0 * st.fs,
        cell.x1 - 2.0 * st.fs,
        cell.y1 - 3.0 * st.fs,
    );
    if r.w() <= 0.0 || r.h() <= 0.0 {
        return Ok(());
    }
    stroke_rect(area, r, RGBColor(150, 150, 150), st.frame)?;
    draw_text(
        area,
        &p.title,
        (r.cx(), r.y0 - 0.6 * st.pad),
        st.ft,
        HA::Center,
        VA::Baseline,
        false,
        TEXT,
    )?;
    draw_text(
        area,
        "no data",
        (r.cx(), r.cy()),
        st.fl,
        HA::Center,
        VA::Center,
        false,
        RGBColor(120, 120, 120),
    )
}

/// Geometry of one laid-out panel.
struct PanelLayout {
    plot: Rect,
    xt: Ticks,
    yt: Ticks,
    xs: Scale,
    ys: Scale,
    px: Vec<SeriesPx>,
    entries: Vec<Entry>,
    lg: LegendGeom,
    legend: Option<Rect>,
    /// How much data the legend hides (0 when outside or free).
    legend_score: usize,
    title_top: f64,
}

fn legend_entries(p: &Panel) -> Vec<Entry> {
    let mut entries = Vec::new();
    for (i, s) in p.series.iter().enumerate() {
        if !s.label.is_empty() {
            entries.push(Entry {
                label: s.label.clone(),
                kind: EntryKind::Series {
                    color: series_color(i),
                    style: s.style,
                    shape: i,
                },
            });
        }
    }
    for (y, l) in &p.hlines {
        if !l.is_empty() && valid(*y, p.y_log) {
            entries.push(Entry {
                label: l.clone(),
                kind: EntryKind::Reference,
            });
        }
    }
    entries
}

/// Lays out a panel in `cell`. With `forced`, the plot rectangle is given
/// (used to align the axes of a grid of panels); otherwise it is derived
/// from the labels. A legend that would hide data goes outside, to the
/// right, when there is room; else, with an automatic y range, head room is
/// added above the data for it.
fn layout_panel(cell: Rect, p: &Panel, st: &Sty, forced: Option<Rect>) -> Res<PanelLayout> {
    let l = layout_panel_with(cell, p, st, forced, 0.0)?;
    if l.legend_score > 0 && p.y_range.is_none() {
        let h = (l.lg.h + 2.0 * st.pad) / l.plot.h();
        if h < 0.4 {
            return layout_panel_with(cell, p, st, forced, h);
        }
    }
    Ok(l)
}

/// [`layout_panel`] with a fraction `headroom` of the plot height kept free
/// above the data.
fn layout_panel_with(
    cell: Rect,
    p: &Panel,
    st: &Sty,
    forced: Option<Rect>,
    headroom: f64,
) -> Res<PanelLayout> {
    validate_panel(p)?;
    let ((xlo, xhi), (ylo, mut yhi)) = panel_ranges(p)?;
    if headroom > 0.0 {
        yhi = if p.y_log {
            10f64.powf(ylo.log10() + (yhi.log10() - ylo.log10()) / (1.0 - headroom))
        } else {
            ylo + (yhi - ylo) / (1.0 - headroom)
        };
    }
    let (fs, fl, ft, pad, tick) = (st.fs, st.fl, st.ft, st.pad, st.tick);
    let scales = |plot: &Rect| {
        (
            Scale {
                lo: xlo,
                hi: xhi,
                log: p.x_log,
                p_lo: plot.x0,
                p_hi: plot.x1,
            },
            Scale {
                lo: ylo,
                hi: yhi,
                log: p.y_log,
                p_lo: plot.y1,
                p_hi: plot.y0,
            },
        )
    };
    let xticks = |plot: &Rect| make_ticks(xlo, xhi, p.x_log, plot.w(), fs, true);
    let yticks = |plot: &Rect| make_ticks(ylo, yhi, p.y_log, plot.h(), fs, false);
    let title_top = cell.y0 + pad;

    let mut plot = match forced {
        Some(r) => r,
        None => {
            // Vertical layout (independent of the tick labels, except for
            // the band of a common y factor).
            let mut top = title_top;
            if !p.title.is_empty() {
                top += (CAP + DESC) * ft + 0.8 * pad;
            }
            let label_block = if p.x_label.is_empty() {
                0.0
            } else {
                (CAP + DESC) * fl + 0.8 * pad
            };
            let bottom = cell.y1 - pad - label_block - CAP * fs - 0.6 * pad - tick;
            let mut plot = Rect::new(cell.x0, top + 0.5 * CAP * fs, cell.x1, bottom);
            if yticks(&plot).offset.is_some() {
                plot.y0 = top + CAP * fs + 0.8 * pad;
            }
            // Horizontal layout.
            let ylabel_block = if p.y_label.is_empty() {
                0.0
            } else {
                (CAP + DESC) * fl + 0.8 * pad
            };
            plot.x0 =
                cell.x0 + pad + ylabel_block + yticks(&plot).max_label_w(fs) + 0.6 * pad + tick;
            plot.x1 = cell.x1 - pad;
            // Keep the last x tick label inside the cell.
            for _ in 0..2 {
                let (xs, _) = scales(&plot);
                let overhang = xticks(&plot)
                    .major
                    .iter()
                    .map(|(v, l)| xs.px(*v) + 0.5 * text_w(l, fs) - (cell.x1 - 0.3 * pad))
                    .fold(0.0, f64::max);
                if overhang <= 0.0 {
                    break;
                }
                plot.x1 -= overhang;
            }
            plot
        }
    };
    let too_small = |plot: &Rect| {
        if plot.w() < 20.0 || plot.h() < 20.0 {
            Err(Fail::Draw(
                "the image is too small for the axes, labels and legend".into(),
            ))
        } else {
            Ok(())
        }
    };
    too_small(&plot)?;
    let pixels = |plot: &Rect| {
        let (xs, ys) = scales(plot);
        p.series
            .iter()
            .map(|s| series_pixels(s, &xs, &ys, plot, st.lw))
            .collect::<Vec<_>>()
    };
    let mut px = pixels(&plot);

    // Legend placement: the inside position hiding the least data, or
    // outside on the right when every inside position hides something.
    let entries = legend_entries(p);
    let lg = legend_geom(&entries, st);
    let mut legend = None;
    let mut legend_score = 0;
    if !entries.is_empty() && (entries.len() > 1 || !p.hlines.is_empty()) {
        let (_, ys) = scales(&plot);
        let hl: Vec<f64> = p
            .hlines
            .iter()
            .filter(|(y, _)| valid(*y, p.y_log))
            .map(|(y, _)| ys.px(*y))
            .collect();
        let inset = 0.6 * pad;
        let (l, r) = (plot.x0 + inset, plot.x1 - inset - lg.w);
        let (t, b) = (plot.y0 + inset, plot.y1 - inset - lg.h);
        let (cx, cy) = (plot.cx() - 0.5 * lg.w, plot.cy() - 0.5 * lg.h);
        let candidates = [
            (r, t),
            (l, t),
            (r, b),
            (l, b),
            (cx, t),
            (cx, b),
            (r, cy),
            (l, cy),
        ];
        let lines: Vec<Vec<Pt>> = px.iter().flat_map(|s| s.lines.iter().cloned()).collect();
        let marks: Vec<Pt> = px
            .iter()
            .flat_map(|s| s.markers.iter().chain(&s.isolated).copied())
            .collect();
        let fits_inside = lg.w <= plot.w() - 2.0 * inset && lg.h <= plot.h() - 2.0 * inset;
        let mut best = (usize::MAX, candidates[0]);
        if fits_inside {
            for &(x, y) in &candidates {
                let rr = Rect::new(x, y, x + lg.w, y + lg.h).grow(0.5 * pad);
                let score = legend_overlap(&rr, &lines, &marks, &hl);
                if score < best.0 {
                    best = (score, (x, y));
                }
            }
        }
        let outside_at =
            |plot: &Rect| Rect::new(plot.x1 + pad, plot.y0, plot.x1 + pad + lg.w, plot.y0 + lg.h);
        if best.0 > 0 && lg.h <= plot.h() {
            match forced {
                Some(_) if cell.x1 - pad - plot.x1 >= lg.w + pad => {
                    legend = Some(outside_at(&plot));
                }
                None if lg.w + pad < 0.4 * plot.w() => {
                    plot.x1 = cell.x1 - pad - lg.w - pad;
                    too_small(&plot)?;
                    px = pixels(&plot);
                    legend = Some(outside_at(&plot));
                }
                _ => {}
            }
        }
        if legend.is_none() {
            // Inside, even if it hides data (or does not quite fit).
            let (x, y) = best.1;
            legend = Some(Rect::new(x, y, x + lg.w, y + lg.h));
            legend_score = best.0;
        }
    }
    let (xs, ys) = scales(&plot);
    Ok(PanelLayout {
        plot,
        xt: xticks(&plot),
        yt: yticks(&plot),
        xs,
        ys,
        px,
        entries,
        lg,
        legend,
        legend_score,
        title_top,
    })
}

fn draw_panel(area: &Area, cell: Rect, p: &Panel, st: &Sty) -> Res<()> {
    let lay = layout_panel(cell, p, st, None)?;
    paint_panel(area, cell, p, st, &lay)
}

fn paint_panel(area: &Area, cell: Rect, p: &Panel, st: &Sty, lay: &PanelLayout) -> Res<()> {
    let (fs, fl, ft, pad, tick) = (st.fs, st.fl, st.ft, st.pad, st.tick);
    let (plot, xs, ys, xt, yt) = (lay.plot, &lay.xs, &lay.ys, &lay.xt, &lay.yt);

    // Grid.
    for &v in &xt.minor {
        let x = xs.px(v);
        draw_line(area, (x, plot.y0), (x, plot.y1), GRID_MINOR, st.thin)?;
    }
    for &v in &yt.minor {
        let y = ys.px(v);
        draw_line(area, (plot.x0, y), (plot.x1, y), GRID_MINOR, st.thin)?;
    }
    for (v, _) in &xt.major {
        let x = xs.px(*v);
        draw_line(area, (x, plot.y0), (x, plot.y1), GRID_MAJOR, st.thin)?;
    }
    for (v, _) in &yt.major {
        let y = ys.px(*v);
        draw_line(area, (plot.x0, y), (plot.x1, y), GRID_MAJOR, st.thin)?;
    }

    // Reference lines.
    for (y, _) in &p.hlines {
        if valid(*y, p.y_log) && *y >= ys.lo && *y <= ys.hi {
            let yy = ys.px(*y);
            for d in dash_polyline(
                &[(plot.x0, yy), (plot.x1, yy)],
                4.0 * st.thin,
                3.0 * st.thin,
            ) {
                draw_polyline(area, &d, REF_LINE.to_rgba(), 1.3 * st.thin)?;
            }
        }
    }

    // Series.
    for (i, (s, sp)) in p.series.iter().zip(&lay.px).enumerate() {
        let color = series_color(i);
        match s.style {
            SeriesStyle::Dashed => {
                for l in &sp.lines {
                    for d in dash_polyline(l, 3.0 * st.lw, 2.2 * st.lw) {
                        draw_polyline(area, &d, color.to_rgba(), st.lw)?;
                    }
                }
            }
            SeriesStyle::Line | SeriesStyle::LineMarkers => {
                for l in &sp.lines {
                    draw_polyline(area, l, color.to_rgba(), st.lw)?;
                }
            }
            SeriesStyle::Markers => {}
        }
        for &q in &sp.isolated {
            draw_marker(area, q, 0, 0.9 * st.lw, color)?;
        }
        for &q in &sp.markers {
            draw_marker(area, q, i, 2.2 * st.lw, color)?;
        }
    }

    // Frame and ticks.
    stroke_rect(area, plot, TEXT, st.frame)?;
    for (v, l) in &xt.major {
        let x = xs.px(*v);
        draw_line(area, (x, plot.y1), (x, plot.y1 + tick), TEXT, st.thin)?;
        draw_text(
            area,
            l,
            (x, plot.y1 + tick + 0.6 * pad),
            fs,
            HA::Center,
            VA::Top,
            false,
            TEXT,
        )?;
    }
    if p.x_log {
        for &v in &xt.minor {
            let x = xs.px(v);
            draw_line(area, (x, plot.y1), (x, plot.y1 + 0.6 * tick), TEXT, st.thin)?;
        }
    }
    for (v, l) in &yt.major {
        let y = ys.px(*v);
        draw_line(area, (plot.x0 - tick, y), (plot.x0, y), TEXT, st.thin)?;
        draw_text(
            area,
            l,
            (plot.x0 - tick - 0.6 * pad, y),
            fs,
            HA::Right,
            VA::Center,
            false,
            TEXT,
        )?;
    }
    if p.y_log {
        for &v in &yt.minor {
            let y = ys.px(v);
            draw_line(area, (plot.x0 - 0.6 * tick, y), (plot.x0, y), TEXT, st.thin)?;
        }
    }

    // Labels, title, common factors.
    let xlabel_base = cell.y1 - pad - DESC * fl;
    draw_text(
        area,
        &p.x_label,
        (plot.cx(), xlabel_base),
        fl,
        HA::Center,
        VA::Baseline,
        false,
        TEXT,
    )?;
    if let Some(o) = &xt.offset {
        draw_text(
            area,
            o,
            (plot.x1, xlabel_base),
            fs,
            HA::Right,
            VA::Baseline,
            false,
            TEXT,
        )?;
    }
    draw_text(
        area,
        &p.y_label,
        (cell.x0 + pad, plot.cy()),
        fl,
        HA::Center,
        VA::Top,
        true,
        TEXT,
    )?;
    if let Some(o) = &yt.offset {
        draw_text(
            area,
            o,
            (plot.x0, plot.y0 - 0.6 * pad),
            fs,
            HA::Left,
            VA::Baseline,
            false,
            TEXT,
        )?;
    }
    draw_text(
        area,
        &p.title,
        (plot.cx(), lay.title_top),
        ft,
        HA::Center,
        VA::Top,
        false,
        TEXT,
    )?;
    if let Some(r) = lay.legend {
        draw_legend(area, r, &lay.entries, &lay.lg, st)?;
    }
    Ok(())
}

// ---------------------------------------------------------------------------
// Mesh plots
// ---------------------------------------------------------------------------

fn unit_scale(s: f64) -> f64 {
    if s.is_finite() && s > 0.0 {
        s
    } else {
        1.0
    }
}

fn axis_label(name: &str, unit: &str) -> String {
    if unit.is_empty() {
        name.to_string()
    } else {
        format!("{name} [{unit}]")
    }
}

fn check_triangles(points: &[[f64; 2]], triangles: &[[usize; 3]], what: &str) -> Res<()> {
    if let Some((i, t)) = triangles
        .iter()
        .enumerate()
        .find(|(_, t)| t.iter().any(|&n| n >= points.len()))
    {
        return Err(Fail::Draw(format!(
            "{what}: triangle {i} {t:?} refers to a node beyond the {} points",
            points.len()
        )));
    }
    Ok(())
}

fn tri_ok(points: &[[f64; 2]], t: &[usize; 3]) -> bool {
    t.iter()
        .all(|&n| points[n][0].is_finite() && points[n][1].is_finite())
}

/// Bounding box (x0, x1, y0, y1) of the nodes of drawable triangles.
fn mesh_bbox(points: &[[f64; 2]], triangles: &[[usize; 3]], s: f64) -> Option<[f64; 4]> {
    let mut b: Option<[f64; 4]> = None;
    for t in triangles.iter().filter(|t| tri_ok(points, t)) {
        for &n in t {
            let (x, y) = (points[n][0] * s, points[n][1] * s);
            b = Some(match b {
                None => [x, x, y, y],
                Some([a, c, d, e]) => [a.min(x), c.max(x), d.min(y), e.max(y)],
            });
        }
    }
    b
}

/// Adds a margin (`frac` of the larger extent) around a bounding box.
fn pad_bbox([x0, x1, y0, y1]: [f64; 4], frac: f64) -> [f64; 4] {
    let ext = (x1 - x0).max(y1 - y0);
    let m = if ext > 0.0 {
        frac * ext
    } else {
        0.5 * x0.abs().max(y0.abs()).max(1.0)
    };
    [x0 - m, x1 + m, y0 - m, y1 + m]
}

fn value_range(vals: impl Iterator<Item = f64>, user: Option<(f64, f64)>) -> Option<(f64, f64)> {
    if let Some((a, b)) = user {
        let (a, b) = if a <= b { (a, b) } else { (b, a) };
        if a.is_finite() && b.is_finite() {
            return Some(if is_const(a, b) {
                auto_range(a, b, false)
            } else {
                (a, b)
            });
        }
    }
    let mut r = None;
    for v in vals.filter(|v| v.is_finite()) {
        extend(&mut r, v);
    }
    r.map(|(a, b)| {
        if is_const(a, b) {
            auto_range(a, b, false)
        } else {
            (a, b)
        }
    })
}

/// Pixel mapping of a mesh panel (equal aspect).
#[derive(Debug, Clone, Copy)]
struct MeshView {
    /// Displayed data extent (x0, x1, y0, y1).
    bb: [f64; 4],
    /// Plot rectangle in pixels.
    r: Rect,
    /// Length-unit scale applied to the raw coordinates.
    unit: f64,
}

impl MeshView {
    fn px(&self, p: [f64; 2]) -> Pt {
        let s = self.r.w() / (self.bb[1] - self.bb[0]);
        (
            self.r.x0 + (p[0] * self.unit - self.bb[0]) * s,
            self.r.y1 - (p[1] * self.unit - self.bb[2]) * s,
        )
    }
    fn xscale(&self) -> Scale {
        Scale {
            lo: self.bb[0],
            hi: self.bb[1],
            log: false,
            p_lo: self.r.x0,
            p_hi: self.r.x1,
        }
    }
    fn yscale(&self) -> Scale {
        Scale {
            lo: self.bb[2],
            hi: self.bb[3],
            log: false,
            p_lo: self.r.y1,
            p_hi: self.r.y0,
        }
    }
}

/// Triangles filled with one colour each; returns the mean triangle size in
/// pixels.
fn fill_triangles<F>(
    area: &Area,
    v: &MeshView,
    points: &[[f64; 2]],
    triangles: &[[usize; 3]],
    color_of: F,
) -> Res<f64>
where
    F: Fn(usize) -> RGBColor,
{
    let mut area_sum = 0.0;
    let mut n = 0usize;
    for (i, t) in triangles.iter().enumerate() {
        if !tri_ok(points, t) {
            continue;
        }
        let q: Vec<Pt> = t.iter().map(|&k| v.px(points[k])).collect();
        let c = color_of(i);
        fill_polygon(area, &q, c)?;
        // Same-colour outline closes rasterisation cracks between neighbours.
        let closed = [q[0], q[1], q[2], q[0]];
        draw_polyline(area, &closed, c.to_rgba(), 1.0)?;
        area_sum += 0.5
            * ((q[1].0 - q[0].0) * (q[2].1 - q[0].1) - (q[2].0 - q[0].0) * (q[1].1 - q[0].1)).abs();
        n += 1;
    }
    Ok(if n > 0 {
        (2.0 * area_sum / n as f64).sqrt()
    } else {
        0.0
    })
}

/// Element edges (light) and, optionally, the boundary outline (dark).
#[allow(clippy::too_many_arguments)]
fn draw_edges(
    area: &Area,
    v: &MeshView,
    points: &[[f64; 2]],
    triangles: &[[usize; 3]],
    inner: bool,
    outline: bool,
    inner_color: RGBAColor,
    st: &Sty,
) -> Res<()> {
    if !inner && !outline {
        return Ok(());
    }
    let mut count: HashMap<(usize, usize), u32> = HashMap::new();
    for t in triangles.iter().filter(|t| tri_ok(points, t)) {
        for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            *count.entry((a.min(b), a.max(b))).or_insert(0) += 1;
        }
    }
    let mut edges: Vec<_> = count.into_iter().collect();
    edges.sort_unstable();
    if inner {
        for &((a, b), c) in &edges {
            if c > 1 || !outline {
                draw_polyline(
                    area,
                    &[v.px(points[a]), v.px(points[b])],
                    inner_color,
                    st.thin,
                )?;
            }
        }
    }
    if outline {
        for &((a, b), c) in &edges {
            if c == 1 {
                draw_polyline(
                    area,
                    &[v.px(points[a]), v.px(points[b])],
                    RGBColor(60, 60, 60).to_rgba(),
                    st.thin,
                )?;
            }
        }
    }
    Ok(())
}

/// Width needed right of the plot for a colour bar (gap, bar, ticks,
/// labels, rotated title).
fn colorbar_width(t: &Ticks, label: &str, st: &Sty) -> f64 {
    let bar = 1.1 * st.fs;
    let gap = 1.2 * st.fs;
    let lab = if label.is_empty() {
        0.0
    } else {
        0.8 * st.pad + (CAP + DESC) * st.fl
    };
    gap + bar + st.tick + 0.4 * st.pad + t.max_label_w(st.fs) + lab + st.pad
}

/// Draws a vertical colour bar in `r` for values `vmin..vmax`.
fn draw_colorbar(
    area: &Area,
    r: Rect,
    (vmin, vmax): (f64, f64),
    t: &Ticks,
    label: &str,
    st: &Sty,
) -> Res<()> {
    let h = r.h();
    let n = h.ceil().max(1.0) as usize;
    for i in 0..n {
        let y = r.y0 + i as f64;
        let tt = 1.0 - (i as f64 + 0.5) / h;
        let y1 = (y + 1.0).min(r.y1);
        fill_rect(area, Rect::new(r.x0, y, r.x1, y1), viridis(tt).to_rgba())?;
    }
    stroke_rect(area, r, TEXT, st.thin)?;
    let ys = Scale {
        lo: vmin,
        hi: vmax,
        log: false,
        p_lo: r.y1,
        p_hi: r.y0,
    };
    for (v, l) in &t.major {
        let y = ys.px(*v);
        draw_line(area, (r.x1, y), (r.x1 + st.tick, y), TEXT, st.thin)?;
        draw_text(
            area,
            l,
            (r.x1 + st.tick + 0.4 * st.pad, y),
            st.fs,
            HA::Left,
            VA::Center,
            false,
            TEXT,
        )?;
    }
    if let Some(o) = &t.offset {
        draw_text(
            area,
            o,
            (r.x0, r.y0 - 0.6 * st.pad),
            st.fs,
            HA::Left,
            VA::Baseline,
            false,
            TEXT,
        )?;
    }
    let lx = r.x1 + st.tick + 0.4 * st.pad + t.max_label_w(st.fs) + 0.8 * st.pad;
    draw_text(
        area,
        label,
        (lx, r.cy()),
        st.fl,
        HA::Center,
        VA::Top,
        true,
        TEXT,
    )
}

/// Axis tick labels and ticks of a mesh panel.
#[allow(clippy::too_many_arguments)]
fn draw_mesh_axes(
    area: &Area,
    v: &MeshView,
    xt: &Ticks,
    yt: &Ticks,
    x_labels: bool,
    y_labels: bool,
    st: &Sty,
) -> Res<()> {
    let r = v.r;
    stroke_rect(area, r, TEXT, st.thin)?;
    let (xs, ys) = (v.xscale(), v.yscale());
    for (val, l) in &xt.major {
        let x = xs.px(*val);
        draw_line(area, (x, r.y1), (x, r.y1 + st.tick), TEXT, st.thin)?;
        if x_labels {
            draw_text(
                area,
                l,
                (x, r.y1 + st.tick + 0.6 * st.pad),
                st.fs,
                HA::Center,
                VA::Top,
                false,
                TEXT,
            )?;
        }
    }
    for (val, l) in &yt.major {
        let y = ys.px(*val);
        draw_line(area, (r.x0 - st.tick, y), (r.x0, y), TEXT, st.thin)?;
        if y_labels {
            draw_text(
                area,
                l,
                (r.x0 - st.tick - 0.6 * st.pad, y),
                st.fs,
                HA::Right,
                VA::Center,
                false,
                TEXT,
            )?;
        }
    }
    Ok(())
}

fn render_color_map(map: &MeshColorMap, size: (u32, u32), opts: &MeshOptions) -> Res<Vec<u8>> {
    if map.triangles.is_empty() || map.points.is_empty() {
        return Err(Fail::Empty("the mesh has no triangles".into()));
    }
    if map.cell_values.len() != map.triangles.len() {
        return Err(Fail::Draw(format!(
            "{} cell values for {} triangles",
            map.cell_values.len(),
            map.triangles.len()
        )));
    }
    check_triangles(map.points, map.triangles, "colour map")?;
    let unit = unit_scale(map.length_unit_scale);
    let bb0 = mesh_bbox(map.points, map.triangles, unit)
        .ok_or_else(|| Fail::Empty("no triangle has finite coordinates".into()))?;
    let vr = value_range(
        map.triangles
            .iter()
            .zip(map.cell_values)
            .filter(|(t, _)| tri_ok(map.points, t))
            .map(|(_, &v)| v),
        opts.value_range,
    )
    .ok_or_else(|| Fail::Empty("no finite cell value".into()))?;
    let bb = pad_bbox(bb0, 0.03);
    let (dx, dy) = (bb[1] - bb[0], bb[3] - bb[2]);
    let xl = axis_label("x", &map.length_unit);
    let yl = axis_label("y", &map.length_unit);

    render(size, |area, fig| {
        let st = Sty::new(fig, fig.out);
        let (fs, fl, pad, tick) = (st.fs, st.fl, st.pad, st.tick);
        let top = pad
            + if map.title.is_empty() {
                0.5 * CAP * fs
            } else {
                (CAP + DESC) * st.ft + pad
            };
        let bottom = tick + 0.6 * pad + CAP * fs + pad + (CAP + DESC) * fl + pad;
        let mut left_w = pad + (CAP + DESC) * fl + 0.8 * pad + 3.0 * fs + 0.6 * pad + tick;
        let mut cb_w = 6.0 * fs;
        let mut layout = None;
        for _ in 0..3 {
            let avail_w = fig.w - left_w - cb_w - pad;
            let avail_h = fig.h - top - bottom;
            if avail_w <= 20.0 || avail_h <= 20.0 {
                return Err(Fail::Draw(
                    "the image is too small for the colour map".into(),
                ));
            }
            let s = (avail_w / dx).min(avail_h / dy);
            let (pw, ph) = (dx * s, dy * s);
            let x0 = left_w + 0.5 * (avail_w - pw);
            let y0 = top + 0.5 * (avail_h - ph);
            let r = Rect::new(x0, y0, x0 + pw, y0 + ph);
            let xt = linear_ticks(bb[0], bb[1], pw, fs, true);
            let yt = linear_ticks(bb[2], bb[3], ph, fs, false);
            // A slender domain still gets a usable colour bar.
            let cbh = ph.max(0.45 * avail_h).min(avail_h);
            let cb = Rect::new(
                r.x1 + 1.2 * fs,
                r.cy() - 0.5 * cbh,
                r.x1 + 2.3 * fs,
                r.cy() + 0.5 * cbh,
            );
            let ct = linear_ticks(vr.0, vr.1, cbh, fs, false);
            let new_left =
                pad + (CAP + DESC) * fl + 0.8 * pad + yt.max_label_w(fs) + 0.6 * pad + tick;
            let new_cb = colorbar_width(&ct, &map.colorbar_label, &st);
            let done = (new_left - left_w).abs() < 1.0 && (new_cb - cb_w).abs() < 1.0;
            left_w = new_left;
            cb_w = new_cb;
            layout = Some((r, cb, xt, yt, ct));
            if done {
                break;
            }
        }
        let Some((r, cb, xt, yt, ct)) = layout else {
            return Err(Fail::Draw("layout failed".into()));
        };
        let v = MeshView { bb, r, unit };
        let size_px = fill_triangles(area, &v, map.points, map.triangles, |i| {
            let val = map.cell_values[i];
            if val.is_finite() {
                viridis((val - vr.0) / (vr.1 - vr.0))
            } else {
                NO_DATA
            }
        })?;
        let inner = match opts.edges {
            EdgeMode::Always => true,
            EdgeMode::Never => false,
            EdgeMode::Auto => size_px >= 12.0 * fig.k,
        };
        draw_edges(
            area,
            &v,
            map.points,
            map.triangles,
            inner,
            false,
            BLACK.mix(0.3),
            &st,
        )?;
        draw_mesh_axes(area, &v, &xt, &yt, true, true, &st)?;
        // Axis labels and title.
        draw_text(
            area,
            &xl,
            (r.cx(), r.y1 + tick + 0.6 * pad + CAP * fs + pad),
            fl,
            HA::Center,
            VA::Top,
            false,
            TEXT,
        )?;
        let ylx = r.x0 - tick - 0.6 * pad - yt.max_label_w(fs) - 0.8 * pad - (CAP + DESC) * fl;
        draw_text(
            area,
            &yl,
            (ylx, r.cy()),
            fl,
            HA::Center,
            VA::Top,
            true,
            TEXT,
        )?;
        draw_text(
            area,
            &map.title,
            (r.cx(), pad),
            st.ft,
            HA::Center,
            VA::Top,
            false,
            TEXT,
        )?;
        draw_colorbar(area, cb, vr, &ct, &map.colorbar_label, &st)
    })
}

/// Evenly spread subset of the nodes used by drawable triangles: in each
/// cell of a grid of about `n_across` cells over the larger extent, the
/// node closest to the cell centre.
fn arrow_nodes(
    points: &[[f64; 2]],
    triangles: &[[usize; 3]],
    unit: f64,
    bb: [f64; 4],
    n_across: f64,
) -> Vec<usize> {
    let cell = (bb[1] - bb[0]).max(bb[3] - bb[2]) / n_across;
    if cell.is_nan() || cell <= 0.0 {
        return Vec::new();
    }
    let nx = ((bb[1] - bb[0]) / cell).ceil().max(1.0) as usize;
    let ny = ((bb[3] - bb[2]) / cell).ceil().max(1.0) as usize;
    let mut used = vec![false; points.len()];
    for t in triangles.iter().filter(|t| tri_ok(points, t)) {
        for &n in t {
            used[n] = true;
        }
    }
    let mut best: HashMap<(usize, usize), (f64, usize)> = HashMap::new();
    for (n, p) in points.iter().enumerate().filter(|(n, _)| used[*n]) {
        let (x, y) = (p[0] * unit - bb[0], p[1] * unit - bb[2]);
        let (i, j) = (
            ((x / cell) as usize).min(nx - 1),
            ((y / cell) as usize).min(ny - 1),
        );
        let (cx, cy) = ((i as f64 + 0.5) * cell, (j as f64 + 0.5) * cell);
        let d = (x - cx).powi(2) + (y - cy).powi(2);
        let e = best.entry((i, j)).or_insert((f64::INFINITY, n));
        if d < e.0 {
            *e = (d, n);
        }
    }
    let mut nodes: Vec<usize> = best.into_values().map(|(_, n)| n).collect();
    nodes.sort_unstable();
    nodes
}

/// Black arrow with a thin white halo (visible on dark and light colours).
fn draw_arrow(area: &Area, from: Pt, to: Pt, st: &Sty) -> Res<()> {
    let (dx, dy) = (to.0 - from.0, to.1 - from.1);
    let len = (dx * dx + dy * dy).sqrt();
    if len < 0.3 * st.fs {
        return Ok(());
    }
    let (ux, uy) = (dx / len, dy / len);
    let head = (0.35 * len).min(0.5 * st.fs);
    let half = 0.42 * head;
    let base = (to.0 - head * ux, to.1 - head * uy);
    let shaft = 1.1 * st.thin;
    let halo = 0.4 * st.thin + 0.5;
    let tri = |grow: f64| {
        [
            (to.0 + grow * 1.6 * ux, to.1 + grow * 1.6 * uy),
            (
                base.0 - (half + grow) * uy - grow * ux,
                base.1 + (half + grow) * ux - grow * uy,
            ),
            (
                base.0 + (half + grow) * uy - grow * ux,
                base.1 - (half + grow) * ux - grow * uy,
            ),
        ]
    };
    let white = WHITE.mix(0.6);
    draw_polyline(
        area,
        &[(from.0 - halo * ux, from.1 - halo * uy), base],
        white,
        shaft + 2.0 * halo,
    )?;
    area.draw(&Polygon::new(
        tri(halo).iter().map(|&p| ipt(p)).collect::<Vec<_>>(),
        white.filled(),
    ))
    .map_err(de)?;
    draw_polyline(area, &[from, base], BLACK.to_rgba(), shaft)?;
    fill_polygon(area, &tri(0.0), BLACK)
}

fn render_vector_fields(
    frames: &[MeshVectorField],
    cols: usize,
    size: (u32, u32),
    opts: &MeshOptions,
) -> Res<Vec<u8>> {
    if frames.is_empty() {
        return Err(Fail::Empty("no frames".into()));
    }
    for (i, f) in frames.iter().enumerate() {
        if f.vectors.len() != f.points.len() {
            return Err(Fail::Draw(format!(
                "frame {i}: {} vectors for {} points",
                f.vectors.len(),
                f.points.len()
            )));
        }
        check_triangles(f.points, f.triangles, &format!("frame {i}"))?;
    }
    let n = frames.len();
    let cols = if cols == 0 {
        (n as f64).sqrt().ceil() as usize
    } else {
        cols.min(n)
    };
    let rows = n.div_ceil(cols);
    let unit = unit_scale(frames[0].length_unit_scale);
    let mut bb0: Option<[f64; 4]> = None;
    for f in frames {
        if let Some(b) = mesh_bbox(f.points, f.triangles, unit) {
            bb0 = Some(match bb0 {
                None => b,
                Some(a) => [
                    a[0].min(b[0]),
                    a[1].max(b[1]),
                    a[2].min(b[2]),
                    a[3].max(b[3]),
                ],
            });
        }
    }
    // Arrows are centred on their node and at most 1/8 of the panel width
    // long: a margin of 7.5 % keeps them inside the frame.
    let bb = pad_bbox(
        bb0.ok_or_else(|| Fail::Empty("no frame has a drawable triangle".into()))?,
        0.075,
    );
    let mags: Vec<Vec<f64>> = frames
        .iter()
        .map(|f| f.vectors.iter().map(|v| v[0].hypot(v[1])).collect())
        .collect();
    let max_mag = mags
        .iter()
        .flatten()
        .filter(|m| m.is_finite())
        .fold(0.0f64, |a, &m| a.max(m));
    let vr = match opts.value_range {
        Some(_) => value_range(std::iter::empty(), opts.value_range),
        None => None,
    }
    .unwrap_or((0.0, if max_mag > 0.0 { max_mag } else { 1.0 }));
    let (dx, dy) = (bb[1] - bb[0], bb[3] - bb[2]);
    let xl = axis_label("x", &frames[0].length_unit);
    let yl = axis_label("y", &frames[0].length_unit);
    let cb_label = frames[0].colorbar_label.clone();

    render(size, |area, fig| {
        let st = Sty::new(fig, (fig.out.0 / cols as f64, fig.out.1 / rows as f64));
        let (fs, fl, pad, tick) = (st.fs, st.fl, st.pad, st.tick);
        let title_band = if frames.iter().any(|f| !f.title.is_empty()) {
            (CAP + DESC) * fs + 0.6 * pad
        } else {
            0.5 * CAP * fs
        };
        let hgap = 1.2 * fs;
        let vgap = 1.2 * pad;
        let top = pad;
        let bottom = tick + 0.6 * pad + CAP * fs + pad + (CAP + DESC) * fl + pad;
        let mut left_w = pad + (CAP + DESC) * fl + 0.8 * pad + 3.0 * fs + 0.6 * pad + tick;
        let mut cb_w = 6.0 * fs;
        let mut layout = None;
        for _ in 0..3 {
            let avail_w = fig.w - left_w - cb_w - pad - (cols - 1) as f64 * hgap;
            let avail_h =
                fig.h - top - bottom - rows as f64 * title_band - (rows - 1) as f64 * vgap;
            if avail_w <= 20.0 * cols as f64 || avail_h <= 20.0 * rows as f64 {
                return Err(Fail::Draw(
                    "the image is too small for this many frames".into(),
                ));
            }
            let s = (avail_w / (cols as f64 * dx)).min(avail_h / (rows as f64 * dy));
            let (pw, ph) = (dx * s, dy * s);
            let gw = cols as f64 * pw + (cols - 1) as f64 * hgap;
            let gh = rows as f64 * (title_band + ph) + (rows - 1) as f64 * vgap;
            let x0 = left_w + 0.5 * (avail_w + (cols - 1) as f64 * hgap - gw);
            let y0 = top + 0.5 * (fig.h - top - bottom - gh);
            let xt = linear_ticks(bb[0], bb[1], pw, fs, true);
            let yt = linear_ticks(bb[2], bb[3], ph, fs, false);
            let ct = linear_ticks(vr.0, vr.1, gh - title_band, fs, false);
            let new_left =
                pad + (CAP + DESC) * fl + 0.8 * pad + yt.max_label_w(fs) + 0.6 * pad + tick;
            let new_cb = colorbar_width(&ct, &cb_label, &st);
            let done = (new_left - left_w).abs() < 1.0 && (new_cb - cb_w).abs() < 1.0;
            left_w = new_left;
            cb_w = new_cb;
            layout = Some((x0, y0, pw, ph, gw, gh, xt, yt, ct));
            if done {
                break;
            }
        }
        let Some((x0, y0, pw, ph, gw, gh, xt, yt, ct)) = layout else {
            return Err(Fail::Draw("layout failed".into()));
        };
        let arrow_scale = if max_mag > 0.0 {
            pw / 8.0 / max_mag
        } else {
            0.0
        };
        for (i, f) in frames.iter().enumerate() {
            let (r, c) = (i / cols, i % cols);
            let px0 = x0 + c as f64 * (pw + hgap);
            let py0 = y0 + r as f64 * (title_band + ph + vgap) + title_band;
            let v = MeshView {
                bb,
                r: Rect::new(px0, py0, px0 + pw, py0 + ph),
                unit,
            };
            let m = &mags[i];
            let size_px = fill_triangles(area, &v, f.points, f.triangles, |t| {
                let tri = f.triangles[t];
                let mean = (m[tri[0]] + m[tri[1]] + m[tri[2]]) / 3.0;
                if mean.is_finite() {
                    viridis((mean - vr.0) / (vr.1 - vr.0))
                } else {
                    NO_DATA
                }
            })?;
            let inner = match opts.edges {
                EdgeMode::Always => true,
                EdgeMode::Never => false,
                EdgeMode::Auto => size_px >= 10.0 * fig.k,
            };
            draw_edges(
                area,
                &v,
                f.points,
                f.triangles,
                inner,
                true,
                WHITE.mix(0.35),
                &st,
            )?;
            for node in arrow_nodes(f.points, f.triangles, unit, bb, 12.0) {
                let vec = f.vectors[node];
                if !(vec[0].is_finite() && vec[1].is_finite()) {
                    continue;
                }
                let c = v.px(f.points[node]);
                let (hx, hy) = (0.5 * vec[0] * arrow_scale, -0.5 * vec[1] * arrow_scale);
                draw_arrow(area, (c.0 - hx, c.1 - hy), (c.0 + hx, c.1 + hy), &st)?;
            }
            let bottom_of_column = i + cols >= n;
            draw_mesh_axes(area, &v, &xt, &yt, bottom_of_column, c == 0, &st)?;
            draw_text(
                area,
                &f.title,
                (v.r.cx(), py0 - 0.6 * pad - DESC * fs),
                fs,
                HA::Center,
                VA::Baseline,
                false,
                TEXT,
            )?;
        }
        // Shared axis labels and colour bar.
        let grid_bottom = y0 + gh;
        draw_text(
            area,
            &xl,
            (
                x0 + 0.5 * gw,
                grid_bottom + tick + 0.6 * pad + CAP * fs + pad,
            ),
            fl,
            HA::Center,
            VA::Top,
            false,
            TEXT,
        )?;
        let ylx = x0 - tick - 0.6 * pad - yt.max_label_w(fs) - 0.8 * pad - (CAP + DESC) * fl;
        draw_text(
            area,
            &yl,
            (ylx, y0 + title_band + 0.5 * (gh - title_band)),
            fl,
            HA::Center,
            VA::Top,
            true,
            TEXT,
        )?;
        let cb = Rect::new(
            x0 + gw + 1.2 * fs,
            y0 + title_band,
            x0 + gw + 2.3 * fs,
            grid_bottom,
        );
        draw_colorbar(area, cb, vr, &ct, &cb_label, &st)
    })
}

// ---------------------------------------------------------------------------
// Tests
// ---------------------------------------------------------------------------

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashSet;
    use std::f64::consts::PI;

    /// Output directory of the test figures: `$SOFTWAY_PLOT_SAMPLE_DIR/<test>`
    /// if that variable is set (the figures are kept, to look at them), else
    /// a fresh directory under the system temporary directory, removed when
    /// the test ends.
    struct OutDir {
        path: PathBuf,
        keep: bool,
    }

    impl OutDir {
        fn join(&self, name: impl AsRef<Path>) -> PathBuf {
            self.path.join(name)
        }
    }

    impl Drop for OutDir {
        fn drop(&mut self) {
            if !self.keep {
                let _ = std::fs::remove_dir_all(&self.path);
            }
        }
    }

    fn out_dir(test: &str) -> OutDir {
        let (path, keep) = match std::env::var_os("SOFTWAY_PLOT_SAMPLE_DIR") {
            Some(d) => (PathBuf::from(d).join(test), true),
            None => (
                std::env::temp_dir().join(format!("softway-plot-{}-{test}", std::process::id())),
                false,
            ),
        };
        std::fs::create_dir_all(&path).unwrap();
        OutDir { path, keep }
    }

    /// Checks the PNG signature and the IHDR size.
    fn assert_png(path: &Path, size: (u32, u32)) {
        let bytes = std::fs::read(path).unwrap();
        assert!(bytes.len() > 33, "{} too short", path.display());
        assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "not a PNG");
        assert_eq!(&bytes[12..16], b"IHDR");
        let w = u32::from_be_bytes(bytes[16..20].try_into().unwrap());
        let h = u32::from_be_bytes(bytes[20..24].try_into().unwrap());
        assert_eq!((w, h), size);
        let mut tmp = path.as_os_str().to_os_string();
        tmp.push(".tmp.png");
        assert!(!Path::new(&tmp).exists(), "temporary file left behind");
    }

    fn distinct_colors(rgb: &[u8]) -> usize {
        rgb.chunks(3)
            .map(|c| (c[0], c[1], c[2]))
            .collect::<HashSet<_>>()
            .len()
    }

    /// Triangulated disk: centre node plus `rings` rings of 6·i nodes.
    fn disk(radius: f64, rings: usize) -> (Vec<[f64; 2]>, Vec<[usize; 3]>) {
        let mut pts = vec![[0.0, 0.0]];
        let mut ring_start = vec![0usize];
        let mut ring_len = vec![1usize];
        for i in 1..=rings {
            ring_start.push(pts.len());
            let m = 6 * i;
            ring_len.push(m);
            let r = radius * i as f64 / rings as f64;
            for j in 0..m {
                let a = 2.0 * PI * j as f64 / m as f64;
                pts.push([r * a.cos(), r * a.sin()]);
            }
        }
        let mut tris = Vec::new();
        for i in 1..=rings {
            let (sa, na) = (ring_start[i - 1], ring_len[i - 1]);
            let (sb, nb) = (ring_start[i], ring_len[i]);
            let (mut a, mut b) = (0usize, 0usize);
            while a < na || b < nb {
                let ta = (a + 1) as f64 / na as f64;
                let tb = (b + 1) as f64 / nb as f64;
                if na > 1 && a < na && (b >= nb || ta < tb) {
                    tris.push([sa + a % na, sb + b % nb, sa + (a + 1) % na]);
                    a += 1;
                } else {
                    tris.push([sa + a % na, sb + b % nb, sb + (b + 1) % nb]);
                    b += 1;
                    if na == 1 && b >= nb {
                        break;
                    }
                }
            }
        }
        (pts, tris)
    }

    /// Structured triangulation of the rectangle [0, lx] × [0, ly].
    fn rectangle(lx: f64, ly: f64, nx: usize, ny: usize) -> (Vec<[f64; 2]>, Vec<[usize; 3]>) {
        let mut pts = Vec::new();
        for j in 0..=ny {
            for i in 0..=nx {
                pts.push([lx * i as f64 / nx as f64, ly * j as f64 / ny as f64]);
            }
        }
        let id = |i: usize, j: usize| j * (nx + 1) + i;
        let mut tris = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                tris.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                tris.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        (pts, tris)
    }

    fn centroid(p: &[[f64; 2]], t: &[usize; 3]) -> [f64; 2] {
        [
            (p[t[0]][0] + p[t[1]][0] + p[t[2]][0]) / 3.0,
            (p[t[0]][1] + p[t[1]][1] + p[t[2]][1]) / 3.0,
        ]
    }

    #[test]
    fn formatting() {
        let (l, o) = format_linear(&[0.1, 0.2, 0.30000000000000004], 0.1);
        assert_eq!(l, vec!["0.1", "0.2", "0.3"]);
        assert!(o.is_none());
        let (l, _) = format_linear(&[-0.5, -0.0, 0.5], 0.5);
        assert_eq!(l, vec!["−0.5", "0.0", "0.5"]);
        let (l, o) = format_linear(&[0.0, 5e-4, 1e-3], 5e-4);
        assert_eq!(l, vec!["0.0", "0.5", "1.0"]);
        assert_eq!(o.as_deref(), Some("×10⁻³"));
        let (l, o) = format_linear(&[1e5, 1.25e5, 1.5e5], 2.5e4);
        assert_eq!(l, vec!["1.00", "1.25", "1.50"]);
        assert_eq!(o.as_deref(), Some("×10⁵"));
        assert_eq!(fmt_general(0.01), "0.01");
        assert_eq!(fmt_general(1e-5), "10⁻⁵");
        assert_eq!(fmt_general(2.5e7), "2.5×10⁷");
        assert_eq!(fmt_pow(1.0), "10⁰");
        let t = linear_ticks(0.0, 0.3, 800.0, 20.0, true);
        assert!(t.major.iter().all(|(_, l)| l.len() <= 4), "{:?}", t.major);
        let t = log_ticks(1e-6, 1e-1, 800.0, 20.0, true);
        assert!(t.major.len() >= 3);
        let t = log_ticks(2.0, 8.0, 800.0, 20.0, true);
        assert!(t.major.len() >= 2, "{:?}", t.major);
    }

    #[test]
    fn clipping_and_dashes() {
        let r = Rect::new(0.0, 0.0, 10.0, 10.0);
        let pts = [
            Some((-5.0, 5.0)),
            Some((5.0, 5.0)),
            None,
            Some((6.0, 6.0)),
            Some((7.0, 7.0)),
        ];
        let (lines, iso) = clip_polylines(&pts, &r);
        assert_eq!(lines.len(), 2);
        assert_eq!(lines[0][0], (0.0, 5.0));
        assert!(iso.is_empty());
        let d = dash_polyline(&[(0.0, 0.0), (10.0, 0.0)], 2.0, 1.0);
        assert_eq!(d.len(), 4);
    }

    #[test]
    fn line_plot_sample_and_errors() {
        let dir = out_dir("line_plot");
        // Two-panel displacement / velocity plot, three runs and an exact
        // reference value.
        let omega = 2.0 * PI * 0.8; // rad/ms
        let mut disp = Panel::new("Free-end displacement", "t [ms]", "u [mm]");
        let mut vel = Panel::new("Free-end velocity", "t [ms]", "v [m/s]");
        let styles = [
            SeriesStyle::Line,
            SeriesStyle::Dashed,
            SeriesStyle::LineMarkers,
        ];
        for (k, dt) in [0.05f64, 0.02, 0.005].iter().enumerate() {
            let n = (3.0 / dt) as usize + 1;
            let t: Vec<f64> = (0..n).map(|i| i as f64 * dt).collect();
            let damp = 1.0 - 0.3 * dt / 0.05;
            let mut u: Vec<f64> = t
                .iter()
                .map(|&t| 1.2 * (omega * t).sin() * (-0.2 * damp * t).exp())
                .collect();
            let v: Vec<f64> = t
                .iter()
                .map(|&t| 1.2 * omega * (omega * t).cos() * (-0.2 * damp * t).exp())
                .collect();
            if k == 0 {
                u[10] = f64::NAN; // must break the line, not fail
            }
            disp.series.push(Series::new(
                format!("Δt = {dt} ms"),
                t.clone(),
                u,
                styles[k],
            ));
            vel.series
                .push(Series::new(format!("Δt = {dt} ms"), t, v, styles[k]));
        }
        disp.hlines.push((1.2, "exact amplitude".into()));
        vel.hlines.push((0.0, String::new()));
        let p = dir.join("displacement_velocity.png");
        panels(&p, &[disp.clone(), vel.clone()], 2, 1, (1200, 800)).unwrap();
        assert_png(&p, (1200, 800));
        let p = dir.join("displacement_velocity_side_by_side.png");
        panels(&p, &[disp.clone(), vel], 1, 2, (1200, 800)).unwrap();
        assert_png(&p, (1200, 800));
        let p = dir.join("displacement.png");
        line_plot(&p, &disp, (1200, 800)).unwrap();
        assert_png(&p, (1200, 800));

        // Log-x plot (non-positive x values are skipped), small values.
        let mut conv = Panel::new("Energy drift", "Δt [s]", "relative energy error [-]");
        conv.x_log = true;
        let dts: Vec<f64> = vec![0.0, 1e-6, 3e-6, 1e-5, 3e-5, 1e-4, 3e-4, 1e-3];
        conv.series.push(Series::new(
            "velocity formulation",
            dts.clone(),
            dts.iter().map(|d| 2e-3 + 40.0 * d).collect(),
            SeriesStyle::LineMarkers,
        ));
        conv.series.push(Series::new(
            "displacement formulation",
            dts.clone(),
            dts.iter().map(|d| 2.5e-3 + 90.0 * d).collect(),
            SeriesStyle::Markers,
        ));
        let p = dir.join("log_x.png");
        line_plot(&p, &conv, (1200, 800)).unwrap();
        assert_png(&p, (1200, 800));
        // Log-log with a reference.
        let mut ll = Panel::new("Convergence", "h [m]", "error [-]");
        ll.x_log = true;
        ll.y_log = true;
        let hs: Vec<f64> = (0..6).map(|i| 0.1 / 2f64.powi(i)).collect();
        ll.series.push(Series::new(
            "L2 error",
            hs.clone(),
            hs.iter().map(|h| 0.5 * h * h).collect(),
            SeriesStyle::LineMarkers,
        ));
        ll.series.push(Series::new(
            "H1 error",
            hs.clone(),
            hs.iter().map(|h| 0.8 * h).collect(),
            SeriesStyle::LineMarkers,
        ));
        let p = dir.join("log_log.png");
        line_plot(&p, &ll, (1200, 800)).unwrap();
        assert_png(&p, (1200, 800));

        // Constant data, one series: no legend, range gets width.
        let mut c = Panel::new("", "x [m]", "p [Pa]");
        c.series.push(Series::new(
            "p",
            vec![0.0, 1.0, 2.0],
            vec![3e5; 3],
            SeriesStyle::Line,
        ));
        let p = dir.join("constant.png");
        line_plot(&p, &c, (600, 400)).unwrap();
        assert_png(&p, (600, 400));

        // Errors.
        let empty = Panel::new("e", "x", "y");
        assert!(matches!(
            line_plot(&dir.join("e1.png"), &empty, (600, 400)),
            Err(PlotError::Empty { .. })
        ));
        let mut nan = Panel::new("e", "x", "y");
        nan.series.push(Series::new(
            "a",
            vec![f64::NAN],
            vec![1.0],
            SeriesStyle::Line,
        ));
        assert!(matches!(
            line_plot(&dir.join("e2.png"), &nan, (600, 400)),
            Err(PlotError::Empty { .. })
        ));
        let mut neg = Panel::new("e", "x", "y");
        neg.y_log = true;
        neg.series.push(Series::new(
            "a",
            vec![1.0, 2.0],
            vec![-1.0, 0.0],
            SeriesStyle::Line,
        ));
        assert!(matches!(
            line_plot(&dir.join("e3.png"), &neg, (600, 400)),
            Err(PlotError::Empty { .. })
        ));
        assert!(matches!(
            panels(&dir.join("e4.png"), &[], 1, 1, (600, 400)),
            Err(PlotError::Empty { .. })
        ));
        let mut bad = Panel::new("e", "x", "y");
        bad.series.push(Series::new(
            "a",
            vec![1.0, 2.0],
            vec![1.0],
            SeriesStyle::Line,
        ));
        assert!(matches!(
            line_plot(&dir.join("e5.png"), &bad, (600, 400)),
            Err(PlotError::Draw { .. })
        ));
        assert!(matches!(
            panels(
                &dir.join("e6.png"),
                &[c.clone(), c.clone()],
                1,
                1,
                (600, 400)
            ),
            Err(PlotError::Draw { .. })
        ));
        assert!(matches!(
            line_plot(&dir.join("e7.png"), &c, (10, 10)),
            Err(PlotError::Draw { .. })
        ));
        for i in 1..=7 {
            assert!(!dir.join(format!("e{i}.png")).exists());
        }
    }

    #[test]
    fn edge_cases_sample() {
        let dir = out_dir("edge_cases");
        // Large and small magnitudes (common factors), clipped fixed ranges,
        // a dense series, an empty panel and a single series without legend.
        let n = 200_000;
        let t: Vec<f64> = (0..n).map(|i| i as f64 * 1e-8).collect();
        let f: Vec<f64> = t
            .iter()
            .map(|&t| 2.5e8 * (1.0 + (3e3 * t).sin() + 0.1 * (2e5 * t).sin()))
            .collect();
        let mut big = Panel::new("Contact force", "t [s]", "F [N]");
        big.series
            .push(Series::new("dense", t.clone(), f, SeriesStyle::Line));
        let mut clipped = Panel::new("Zoom (fixed ranges)", "t [s]", "F [N]");
        clipped.series.push(big.series[0].clone());
        clipped.x_range = Some((2e-4, 5e-4));
        clipped.y_range = Some((4e8, 6e8));
        let mut small = Panel::new("Gap", "x [m]", "g [m]");
        small.series.push(Series::new(
            "gap",
            (0..50).map(|i| i as f64 * 0.002).collect(),
            (0..50).map(|i| -3e-6 + 1e-7 * i as f64).collect(),
            SeriesStyle::Markers,
        ));
        small.hlines.push((0.0, "contact".into()));
        let empty = Panel::new("Nothing yet", "x", "y");
        let mut semilog = Panel::new("Residual", "iteration [-]", "‖r‖ [N]");
        semilog.y_log = true;
        semilog.series.push(Series::new(
            "Newton",
            (0..8).map(f64::from).collect(),
            vec![1.0, 0.3, 2e-2, 1e-4, 3e-9, 1e-15, 0.0, f64::NAN],
            SeriesStyle::LineMarkers,
        ));
        semilog.series.push(Series::new(
            "modified Newton",
            (0..8).map(f64::from).collect(),
            (0..8).map(|i| 0.5f64.powi(2 * i)).collect(),
            SeriesStyle::Dashed,
        ));
        let mut narrow_log = Panel::new("Narrow log range", "f [Hz]", "A [-]");
        narrow_log.x_log = true;
        narrow_log.series.push(Series::new(
            "spectrum",
            (0..40).map(|i| 200.0 + 15.0 * f64::from(i)).collect(),
            (0..40)
                .map(|i| 1.0 / (1.0 + (f64::from(i) - 20.0).powi(2)))
                .collect(),
            SeriesStyle::Line,
        ));
        let start = std::time::Instant::now();
        let p = dir.join("grid_3x2.png");
        panels(
            &p,
            &[big.clone(), clipped, small, empty, semilog, narrow_log],
            3,
            2,
            (1200, 1200),
        )
        .unwrap();
        assert_png(&p, (1200, 1200));
        let p = dir.join("single_small.png");
        line_plot(&p, &big, (600, 400)).unwrap();
        assert_png(&p, (600, 400));
        assert!(start.elapsed().as_secs() < 60);
    }

    #[test]
    fn hostile_input_does_not_panic() {
        let dir = out_dir("hostile");
        let cases: Vec<(Vec<f64>, Vec<f64>)> = vec![
            (vec![0.0, 1.0], vec![-1e308, 1e308]),
            (vec![0.0, 1.0], vec![f64::MAX, f64::MAX]),
            (vec![0.0, 1e-310], vec![1e-320, 2e-320]),
            (vec![1.0, 1.0, 1.0], vec![0.0, 0.0, 0.0]),
            (
                vec![f64::INFINITY, 1.0, f64::NAN],
                vec![1.0, 2.0, f64::NEG_INFINITY],
            ),
            (vec![1e15, 1e15 + 1.0], vec![1.0, 2.0]),
        ];
        for (i, (x, y)) in cases.into_iter().enumerate() {
            for (xl, yl) in [(false, false), (true, true)] {
                let mut p = Panel::new("hostile", "x", "y");
                p.x_log = xl;
                p.y_log = yl;
                p.series.push(Series::new(
                    "a",
                    x.clone(),
                    y.clone(),
                    SeriesStyle::LineMarkers,
                ));
                p.series
                    .push(Series::new("b", x.clone(), y.clone(), SeriesStyle::Dashed));
                p.hlines.push((f64::NAN, "nan".into()));
                p.x_range = Some((f64::NAN, 3.0));
                let path = dir.join(format!("case{i}_{xl}.png"));
                match line_plot(&path, &p, (300, 200)) {
                    Ok(()) => assert_png(&path, (300, 200)),
                    Err(e) => assert!(!path.exists(), "{e}"),
                }
            }
        }
        // Writing onto a directory fails cleanly, leaving no temporary file.
        let target = dir.join("is_a_dir.png");
        std::fs::create_dir_all(&target).unwrap();
        let mut p = Panel::new("", "x", "y");
        p.series.push(Series::new(
            "",
            vec![0.0, 1.0],
            vec![0.0, 1.0],
            SeriesStyle::Line,
        ));
        let err = line_plot(&target, &p, (300, 200)).unwrap_err();
        assert!(matches!(err, PlotError::Draw { .. }), "{err}");
        assert!(!dir.join("is_a_dir.png.tmp.png").exists());
    }

    #[test]
    fn mesh_color_map_sample() {
        let dir = out_dir("mesh_color_map");
        let (pts, tris) = disk(0.05, 8);
        let vals: Vec<f64> = tris
            .iter()
            .map(|t| {
                let c = centroid(&pts, t);
                let r2 = (c[0] * c[0] + c[1] * c[1]) / 0.0025;
                // J2-like field concentrated near the contact point (bottom).
                let d2 = (c[0] * c[0] + (c[1] + 0.05) * (c[1] + 0.05)) / 0.0025;
                12.0 * (-4.0 * d2).exp() + 0.5 * r2
            })
            .collect();
        let map = MeshColorMap {
            points: &pts,
            triangles: &tris,
            cell_values: &vals,
            title: "von Mises invariant at t = 0.40 ms".into(),
            colorbar_label: "J2 [MPa²]".into(),
            length_unit_scale: 100.0,
            length_unit: "cm".into(),
        };
        let p = dir.join("disk_j2.png");
        mesh_color_map(&p, &map, (1200, 800)).unwrap();
        assert_png(&p, (1200, 800));
        let buf = render_color_map(&map, (1200, 800), &MeshOptions::default()).unwrap();
        assert!(distinct_colors(&buf) > 50);

        // Fine mesh, tiny values (colour-bar factor), no edges.
        let (pts2, tris2) = disk(0.05, 40);
        let vals2: Vec<f64> = tris2
            .iter()
            .map(|t| 3e-6 * centroid(&pts2, t)[0].sin())
            .collect();
        let map2 = MeshColorMap {
            points: &pts2,
            triangles: &tris2,
            cell_values: &vals2,
            title: String::new(),
            colorbar_label: "ε [-]".into(),
            length_unit_scale: 1000.0,
            length_unit: "mm".into(),
        };
        let p = dir.join("disk_fine.png");
        mesh_color_map(&p, &map2, (800, 800)).unwrap();
        assert_png(&p, (800, 800));

        // Slender bar with a signed field.
        let (pb, tb) = rectangle(1.0, 0.1, 60, 6);
        let vb: Vec<f64> = tb
            .iter()
            .map(|t| {
                let c = centroid(&pb, t);
                -80.0 * (PI * c[0]).sin() * (c[1] - 0.05) / 0.05
            })
            .collect();
        let bar = MeshColorMap {
            points: &pb,
            triangles: &tb,
            cell_values: &vb,
            title: "Bending stress".into(),
            colorbar_label: "σxx [MPa]".into(),
            length_unit_scale: 1.0,
            length_unit: "m".into(),
        };
        let p = dir.join("bar.png");
        mesh_color_map(&p, &bar, (1200, 800)).unwrap();
        assert_png(&p, (1200, 800));

        // Errors.
        let empty = MeshColorMap {
            points: &pts,
            triangles: &[],
            cell_values: &[],
            ..map.clone()
        };
        assert!(matches!(
            mesh_color_map(&dir.join("e1.png"), &empty, (600, 400)),
            Err(PlotError::Empty { .. })
        ));
        let short = MeshColorMap {
            cell_values: &vals[1..],
            ..map.clone()
        };
        assert!(matches!(
            mesh_color_map(&dir.join("e2.png"), &short, (600, 400)),
            Err(PlotError::Draw { .. })
        ));
        let bad_tri = [[0usize, 1, 99_999]];
        let bad = MeshColorMap {
            triangles: &bad_tri,
            cell_values: &vals[..1],
            ..map.clone()
        };
        assert!(matches!(
            mesh_color_map(&dir.join("e3.png"), &bad, (600, 400)),
            Err(PlotError::Draw { .. })
        ));
        let nan_vals = vec![f64::NAN; tris.len()];
        let nan = MeshColorMap {
            cell_values: &nan_vals,
            ..map.clone()
        };
        assert!(matches!(
            mesh_color_map(&dir.join("e4.png"), &nan, (600, 400)),
            Err(PlotError::Empty { .. })
        ));
    }

    #[test]
    fn vector_fields_sample() {
        let dir = out_dir("vector_fields");
        let (pts, tris) = disk(0.05, 10);
        let times = [0.0, 0.1, 0.2, 0.3, 0.4, 0.5];
        // Falling disk hitting the ground: uniform downward velocity that is
        // progressively stopped from the contact point upwards, with a
        // slight rebound and rotation.
        let fields: Vec<Vec<[f64; 2]>> = times
            .iter()
            .map(|&t| {
                let front = -0.05 + 0.2 * t; // m
                pts.iter()
                    .map(|p| {
                        let behind = p[1] < front;
                        let vy = if behind { 0.6 * t } else { -1.5 };
                        [0.3 * p[1] / 0.05 * t, vy]
                    })
                    .collect()
            })
            .collect();
        let frames: Vec<MeshVectorField> = times
            .iter()
            .zip(&fields)
            .map(|(t, v)| MeshVectorField {
                points: &pts,
                triangles: &tris,
                vectors: v,
                title: format!("t = {t:.1} ms"),
                colorbar_label: "|v| [m/s]".into(),
                length_unit_scale: 100.0,
                length_unit: "cm".into(),
            })
            .collect();
        let p = dir.join("velocity_2x3.png");
        mesh_vector_fields(&p, &frames, 3, (1200, 800)).unwrap();
        assert_png(&p, (1200, 800));
        let buf = render_vector_fields(&frames, 3, (1200, 800), &MeshOptions::default()).unwrap();
        assert!(distinct_colors(&buf) > 50);
        let p = dir.join("velocity_5_frames.png");
        mesh_vector_fields(&p, &frames[..5], 3, (1200, 800)).unwrap();
        assert_png(&p, (1200, 800));

        // Slender bar, 3 rows x 2 columns, fixed colour range, all edges.
        let (pb, tb) = rectangle(1.0, 0.1, 40, 4);
        let bar_fields: Vec<Vec<[f64; 2]>> = (0..6)
            .map(|k| {
                let x0 = 0.2 * k as f64;
                pb.iter()
                    .map(|p| {
                        let a = (-((p[0] - x0) / 0.08).powi(2)).exp();
                        [2.0 * a, 0.2 * a * (p[1] - 0.05) / 0.05]
                    })
                    .collect()
            })
            .collect();
        let bar_frames: Vec<MeshVectorField> = bar_fields
            .iter()
            .enumerate()
            .map(|(k, v)| MeshVectorField {
                points: &pb,
                triangles: &tb,
                vectors: v,
                title: format!("t = {:.2} ms", 0.05 * k as f64),
                colorbar_label: "|v| [m/s]".into(),
                length_unit_scale: 100.0,
                length_unit: "cm".into(),
            })
            .collect();
        let p = dir.join("bar_3x2.png");
        let opts = MeshOptions {
            edges: EdgeMode::Always,
            value_range: Some((0.0, 2.5)),
        };
        mesh_vector_fields_with(&p, &bar_frames, 2, (1200, 800), &opts).unwrap();
        assert_png(&p, (1200, 800));

        // Errors.
        assert!(matches!(
            mesh_vector_fields(&dir.join("e1.png"), &[], 3, (600, 400)),
            Err(PlotError::Empty { .. })
        ));
        let bad = MeshVectorField {
            vectors: &fields[0][1..],
            ..frames[0].clone()
        };
        assert!(matches!(
            mesh_vector_fields(&dir.join("e2.png"), &[bad], 3, (600, 400)),
            Err(PlotError::Draw { .. })
        ));
        let empty = MeshVectorField {
            triangles: &[],
            ..frames[0].clone()
        };
        assert!(matches!(
            mesh_vector_fields(&dir.join("e3.png"), &[empty], 3, (600, 400)),
            Err(PlotError::Empty { .. })
        ));
    }
}
