//! Drawing primitives (lines, polygons, rectangles, markers) clipped and audited, over the
//! pixel geometry of [`crate::shape`].

use plotters::prelude::*;

use crate::audit;
use crate::render::{de, Area, Res};
pub(crate) use crate::shape::{
    clip_polygon, clip_polylines, clip_segment, dash_polyline, Pt, Rect,
};
use crate::style::ipt;

/// Fills a polygon, cut to the current clip; records it if it leaves the current bounds.
fn fill_clipped(area: &Area, pts: &[Pt], color: RGBAColor, what: &str) -> Res<()> {
    let clipped;
    let pts = match audit::clip() {
        Some(r) => {
            clipped = clip_polygon(pts, &r);
            &clipped[..]
        }
        None => pts,
    };
    if pts.len() < 3 {
        return Ok(());
    }
    if let Some(b) = Rect::bounding(pts) {
        audit::check(|| what.to_string(), b);
    }
    let v: Vec<(i32, i32)> = pts.iter().map(|&p| ipt(p)).collect();
    area.draw(&Polygon::new(v, color.filled())).map_err(de)
}

/// Drops points closer than half a pixel to the last one kept (the last point is kept):
/// a dense series loses nothing visible and draws in a fraction of the time.
fn thin_out(pts: &[Pt]) -> Vec<Pt> {
    let mut v: Vec<Pt> = Vec::with_capacity(pts.len());
    for (i, &p) in pts.iter().enumerate() {
        match v.last() {
            Some(&q) if (p.0 - q.0).hypot(p.1 - q.1) < 0.5 && i + 1 < pts.len() => {}
            Some(&q) if (p.0 - q.0).hypot(p.1 - q.1) < 0.5 => {
                let n = v.len();
                if n >= 2 {
                    v[n - 1] = p;
                } else {
                    v.push(p);
                }
            }
            _ => v.push(p),
        }
    }
    v
}

/// Strokes a polyline `width` pixels wide: each segment a rectangle, each bend a disk of
/// the same width (a round join), all cut to the current clip. Every painted point is
/// within `width / 2` of the polyline. (plotters' own wide paths are one polygon offset
/// from the whole path, whose joins at sharp bends reach far beyond the data: the spikes
/// of a dense spectrum or force history then crossed the axes and the tick labels.)
pub(crate) fn draw_polyline(area: &Area, pts: &[Pt], color: RGBAColor, width: f64) -> Res<()> {
    let pts = thin_out(pts);
    if pts.len() < 2 {
        return Ok(());
    }
    if width < 1.5 {
        // One pixel wide: plotters' lines (no polygon, nothing to join), cut to the clip.
        let style = ShapeStyle {
            color,
            filled: false,
            stroke_width: 1,
        };
        for w in pts.windows(2) {
            let (a, b) = match audit::clip() {
                Some(r) => match clip_segment(w[0], w[1], &r) {
                    Some((a, b, _, _)) => (a, b),
                    None => continue,
                },
                None => (w[0], w[1]),
            };
            if let Some(bb) = Rect::bounding(&[a, b]) {
                audit::check(|| "a line".to_string(), bb);
            }
            area.draw(&PathElement::new(vec![ipt(a), ipt(b)], style))
                .map_err(de)?;
        }
        return Ok(());
    }
    let hw = 0.5 * width;
    // Joins only where the direction turns by more than ~10 degrees; a translucent line
    // gets none (they would darken its bends).
    let joins = color.3 >= 1.0;
    let mut prev_dir: Option<Pt> = None;
    for w in pts.windows(2) {
        let (a, b) = (w[0], w[1]);
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let len = dx.hypot(dy);
        if len <= 0.0 {
            continue;
        }
        let (ux, uy) = (dx / len, dy / len);
        let (nx, ny) = (-uy * hw, ux * hw);
        let quad = [
            (a.0 + nx, a.1 + ny),
            (b.0 + nx, b.1 + ny),
            (b.0 - nx, b.1 - ny),
            (a.0 - nx, a.1 - ny),
        ];
        fill_clipped(area, &quad, color, "a line")?;
        if let Some((px, py)) = prev_dir {
            if joins && px * ux + py * uy < 0.985 && hw > 0.75 {
                fill_clipped(area, &disk(a, hw), color, "a line")?;
            }
        }
        prev_dir = Some((ux, uy));
    }
    Ok(())
}

/// A regular polygon approximating the disk of radius `r` about `c`.
fn disk(c: Pt, r: f64) -> Vec<Pt> {
    let n = if r < 3.0 { 8 } else { 16 };
    (0..n)
        .map(|k| {
            let t = std::f64::consts::TAU * k as f64 / n as f64;
            (c.0 + r * t.cos(), c.1 + r * t.sin())
        })
        .collect()
}

pub(crate) fn draw_line(area: &Area, a: Pt, b: Pt, color: RGBColor, width: f64) -> Res<()> {
    draw_polyline(area, &[a, b], color.to_rgba(), width)
}

/// Fills `r` (cut to the current clip) as plotters' rectangle: whole pixels, so that
/// translucent rectangles side by side tile without seams.
pub(crate) fn fill_rect(area: &Area, r: Rect, color: RGBAColor) -> Res<()> {
    let r = match audit::clip() {
        Some(c) => r.intersect(&c),
        None => r,
    };
    if r.x1 < r.x0 || r.y1 < r.y0 {
        return Ok(());
    }
    audit::check(|| "a filled rectangle".to_string(), r);
    area.draw(&Rectangle::new(
        [ipt((r.x0, r.y0)), ipt((r.x1, r.y1))],
        color.filled(),
    ))
    .map_err(de)
}

/// The outline of `r`, drawn inside it (`width` inwards from its edges).
pub(crate) fn stroke_rect(area: &Area, r: Rect, color: RGBColor, width: f64) -> Res<()> {
    let c = color.to_rgba();
    let w = width.max(1.0).min(0.5 * r.w().min(r.h()));
    let hw = 0.5 * w;
    // Four bands along the edges, centred on the edges but kept inside `r` by half the
    // width, so that the frame never paints beyond the rectangle it frames.
    let (x0, y0, x1, y1) = (r.x0 + hw, r.y0 + hw, r.x1 - hw, r.y1 - hw);
    for (a, b) in [
        ((x0 - hw, y0), (x1 + hw, y0)),
        ((x1, y0), (x1, y1)),
        ((x1 + hw, y1), (x0 - hw, y1)),
        ((x0, y1), (x0, y0)),
    ] {
        draw_polyline(area, &[a, b], c, w)?;
    }
    Ok(())
}

pub(crate) fn fill_polygon(area: &Area, pts: &[Pt], color: RGBColor) -> Res<()> {
    fill_clipped(area, pts, color.to_rgba(), "a filled polygon")
}

/// [`fill_polygon`] in a translucent colour.
pub(crate) fn fill_polygon_rgba(area: &Area, pts: &[Pt], color: RGBAColor) -> Res<()> {
    fill_clipped(area, pts, color, "a filled polygon")
}

/// Filled marker of the given shape index (circle, square, triangle,
/// diamond, inverted triangle) with "radius" `r`.
pub(crate) fn draw_marker(
    area: &Area,
    (x, y): Pt,
    shape: usize,
    r: f64,
    color: RGBColor,
) -> Res<()> {
    match shape % 5 {
        0 => fill_polygon(area, &disk((x, y), r.max(1.0)), color),
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

#[cfg(test)]
mod tests {
    use super::*;

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
}
