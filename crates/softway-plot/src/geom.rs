//! Pixel geometry (rectangles, clipping, dashes) and drawing primitives.

use plotters::prelude::*;

use crate::render::{de, Area, Res};
use crate::style::{ipt, sw};

#[derive(Debug, Clone, Copy)]
pub(crate) struct Rect {
    pub(crate) x0: f64,
    pub(crate) y0: f64,
    pub(crate) x1: f64,
    pub(crate) y1: f64,
}

impl Rect {
    pub(crate) fn new(x0: f64, y0: f64, x1: f64, y1: f64) -> Self {
        Rect { x0, y0, x1, y1 }
    }
    pub(crate) fn w(&self) -> f64 {
        self.x1 - self.x0
    }
    pub(crate) fn h(&self) -> f64 {
        self.y1 - self.y0
    }
    pub(crate) fn cx(&self) -> f64 {
        0.5 * (self.x0 + self.x1)
    }
    pub(crate) fn cy(&self) -> f64 {
        0.5 * (self.y0 + self.y1)
    }
    pub(crate) fn grow(&self, d: f64) -> Rect {
        Rect::new(self.x0 - d, self.y0 - d, self.x1 + d, self.y1 + d)
    }
    pub(crate) fn contains(&self, (x, y): (f64, f64)) -> bool {
        x >= self.x0 && x <= self.x1 && y >= self.y0 && y <= self.y1
    }
}

pub(crate) type Pt = (f64, f64);

/// Liang–Barsky clipping of segment `a`–`b` to `r`. Returns the clipped
/// end points and whether each one is the original point.
pub(crate) fn clip_segment(a: Pt, b: Pt, r: &Rect) -> Option<(Pt, Pt, bool, bool)> {
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
pub(crate) fn clip_polylines(pts: &[Option<Pt>], r: &Rect) -> (Vec<Vec<Pt>>, Vec<Pt>) {
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
pub(crate) fn dash_polyline(pts: &[Pt], on: f64, off: f64) -> Vec<Vec<Pt>> {
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

pub(crate) fn draw_polyline(area: &Area, pts: &[Pt], color: RGBAColor, width: f64) -> Res<()> {
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

pub(crate) fn draw_line(area: &Area, a: Pt, b: Pt, color: RGBColor, width: f64) -> Res<()> {
    draw_polyline(area, &[a, b], color.to_rgba(), width)
}

pub(crate) fn fill_rect(area: &Area, r: Rect, color: RGBAColor) -> Res<()> {
    area.draw(&Rectangle::new(
        [ipt((r.x0, r.y0)), ipt((r.x1, r.y1))],
        color.filled(),
    ))
    .map_err(de)
}

pub(crate) fn stroke_rect(area: &Area, r: Rect, color: RGBColor, width: f64) -> Res<()> {
    let pts = [
        (r.x0, r.y0),
        (r.x1, r.y0),
        (r.x1, r.y1),
        (r.x0, r.y1),
        (r.x0, r.y0),
    ];
    draw_polyline(area, &pts, color.to_rgba(), width)
}

pub(crate) fn fill_polygon(area: &Area, pts: &[Pt], color: RGBColor) -> Res<()> {
    let v: Vec<(i32, i32)> = pts.iter().map(|&p| ipt(p)).collect();
    area.draw(&Polygon::new(v, color.filled())).map_err(de)
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
