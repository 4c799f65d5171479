//! Styling: sizes derived from the figure, colours, text placement.

use plotters::prelude::*;

use crate::audit;
use crate::render::{de, Area, Fail, Fig, Res, FONT_FAMILY};
use crate::shape::Rect;
use ab_glyph::{point, Font, FontRef, ScaleFont};
use std::sync::OnceLock;

/// Sizes in super-sampled pixels, derived from the figure and cell sizes.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Sty {
    /// Tick-label font size.
    pub(crate) fs: f64,
    /// Axis-label font size.
    pub(crate) fl: f64,
    /// Title font size.
    pub(crate) ft: f64,
    /// Legend font size.
    pub(crate) fleg: f64,
    /// Series line width.
    pub(crate) lw: f64,
    /// Thin lines (grid, ticks, reference lines).
    pub(crate) thin: f64,
    /// Frame line width.
    pub(crate) frame: f64,
    /// Generic padding.
    pub(crate) pad: f64,
    /// Major tick length.
    pub(crate) tick: f64,
}

impl Sty {
    /// `cell` is the size of one panel in output pixels.
    pub(crate) fn new(fig: &Fig, cell: (f64, f64)) -> Self {
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
pub(crate) const GRID_MAJOR: RGBColor = RGBColor(222, 222, 222);
pub(crate) const GRID_MINOR: RGBColor = RGBColor(244, 244, 244);
pub(crate) const REF_LINE: RGBColor = RGBColor(110, 110, 110);
pub(crate) const TEXT: RGBColor = RGBColor(0, 0, 0);
pub(crate) const NOTE: RGBColor = RGBColor(70, 70, 70);
pub(crate) const NO_DATA: RGBColor = RGBColor(205, 205, 205);

pub(crate) fn series_color(i: usize) -> RGBColor {
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

pub(crate) fn viridis(t: f64) -> RGBColor {
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

pub(crate) fn ipt((x, y): (f64, f64)) -> (i32, i32) {
    (x.round() as i32, y.round() as i32)
}

/// DejaVu Sans metrics (fractions of the em size).
pub(crate) const CAP: f64 = 0.729;
pub(crate) const DESC: f64 = 0.236;
/// Height of the tallest letters above the baseline (ascenders, accents on capitals
/// excepted).
pub(crate) const ASC: f64 = 0.76;

#[derive(Clone, Copy)]
pub(crate) enum HA {
    Left,
    Center,
    Right,
}

#[derive(Clone, Copy)]
pub(crate) enum VA {
    /// Reference is the top of capitals/digits.
    Top,
    /// Reference is the middle of capitals/digits.
    Center,
    /// Reference is the baseline.
    Baseline,
}

pub(crate) fn font(size: f64) -> FontDesc<'static> {
    FontDesc::new(FontFamily::Name(FONT_FAMILY), size, FontStyle::Normal)
}

/// Advance width of `text` at font size `size`.
pub(crate) fn text_w(text: &str, size: f64) -> f64 {
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
pub(crate) fn draw_text(
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
    let bbox = if rotated {
        let base = x + b;
        Rect::new(
            base - ASC * size,
            y - along - w,
            base + DESC * size,
            y - along,
        )
    } else {
        let base = y + b;
        Rect::new(
            x + along,
            base - ASC * size,
            x + along + w,
            base + DESC * size,
        )
    };
    audit::check(|| format!("the text {text:?}"), bbox);
    let (bx, by) = if rotated {
        (x + b, y - along)
    } else {
        (x + along, y + b)
    };
    draw_glyphs(area, text, (bx, by), size, rotated, color)
}

/// The embedded DejaVu Sans, parsed once.
fn text_font() -> Option<&'static FontRef<'static>> {
    static FONT: OnceLock<Option<FontRef<'static>>> = OnceLock::new();
    FONT.get_or_init(|| FontRef::try_from_slice(dejavu::sans::regular()).ok())
        .as_ref()
}

/// Draws `text` with its pen starting at `(bx, by)` on the baseline: each glyph's coverage
/// blended at its place, its side bearing included (horizontal, or reading bottom to top
/// when `rotated`).
fn draw_glyphs(
    area: &Area,
    text: &str,
    (bx, by): (f64, f64),
    size: f64,
    rotated: bool,
    color: RGBColor,
) -> Res<()> {
    let font = text_font().ok_or_else(|| Fail::Draw("cannot read the embedded font".into()))?;
    let scaled = font.as_scaled(size as f32);
    let (bx, by) = (bx as f32, by as f32);
    let mut pen = 0f32;
    let mut prev = None;
    let mut failed = None;
    for c in text.chars() {
        let id = scaled.glyph_id(c);
        if let Some(p) = prev {
            pen += scaled.kern(p, id);
        }
        let glyph = id.with_scale_and_position(size as f32, point(pen, 0.0));
        if let Some(outline) = scaled.outline_glyph(glyph) {
            let r = outline.px_bounds();
            outline.draw(|gx, gy, cov| {
                let (u, v) = (r.min.x + gx as f32, r.min.y + gy as f32);
                let (px, py) = if rotated {
                    (bx + v, by - u)
                } else {
                    (bx + u, by + v)
                };
                if cov > 0.0 && failed.is_none() {
                    let at = (px.round() as i32, py.round() as i32);
                    if let Err(e) = area.draw_pixel(at, &color.mix(f64::from(cov.min(1.0)))) {
                        failed = Some(de(e));
                    }
                }
            });
        }
        pen += scaled.h_advance(id);
        prev = Some(id);
    }
    failed.map_or(Ok(()), Err)
}

/// `text` set in lines no wider than `max_w` at font size `size`: as it is if it fits;
/// else broken at spaces into as few lines as fit (at most `max_lines`); a line that still
/// does not fit (one long word, or more text than lines) shrinks the font, down to 60 % of
/// `size`. Returns the lines and the font size. A title is never cut at the edge of its
/// figure.
pub(crate) fn fit_text(text: &str, size: f64, max_w: f64, max_lines: usize) -> (Vec<String>, f64) {
    if text.is_empty() || max_w <= 0.0 {
        return (vec![text.to_string()], size);
    }
    if text_w(text, size) <= max_w {
        return (vec![text.to_string()], size);
    }
    let words: Vec<&str> = text.split(' ').collect();
    let wrap = |size: f64| -> Vec<String> {
        let mut lines: Vec<String> = Vec::new();
        let mut cur = String::new();
        for w in &words {
            let cand = if cur.is_empty() {
                (*w).to_string()
            } else {
                format!("{cur} {w}")
            };
            if cur.is_empty() || text_w(&cand, size) <= max_w {
                cur = cand;
            } else {
                lines.push(std::mem::take(&mut cur));
                cur = (*w).to_string();
            }
        }
        lines.push(cur);
        lines
    };
    let fits = |lines: &[String], size: f64| {
        lines.len() <= max_lines.max(1) && lines.iter().all(|l| text_w(l, size) <= max_w)
    };
    let mut s = size;
    loop {
        let lines = wrap(s);
        if fits(&lines, s) || s <= 0.6 * size {
            if !fits(&lines, s) {
                // Still too long at the smallest size: the lines allowed, the font shrunk
                // to the widest.
                let mut lines = lines;
                let keep = max_lines.max(1);
                if lines.len() > keep {
                    let tail = lines.split_off(keep - 1).join(" ");
                    lines.push(tail);
                }
                let widest = lines.iter().map(|l| text_w(l, s)).fold(0.0, f64::max);
                let s = s * (max_w / widest).min(1.0);
                return (lines, s);
            }
            return (lines, s);
        }
        s *= 0.93;
    }
}
