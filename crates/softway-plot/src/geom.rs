//! Drawing primitives (lines, polygons, rectangles, markers) clipped and audited, over the
//! pixel geometry of [`crate::shape`].

use plotters::element::{Drawable, PointCollection};
use plotters::prelude::*;
use plotters_backend::{BackendCoord, DrawingBackend, DrawingErrorKind};

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
    if v.len() <= CONVEX_MAX && is_convex(&v) {
        return area.draw(&Convex { pts: v, color }).map_err(de);
    }
    area.draw(&Polygon::new(v, color.filled())).map_err(de)
}

/// The most vertices [`Convex`] takes (a stroke's quad, a cell, a join's disk cut to a
/// clip).
const CONVEX_MAX: usize = 40;

/// True when the integer polygon `v` turns one way only (collinear points allowed).
fn is_convex(v: &[(i32, i32)]) -> bool {
    let n = v.len();
    let (mut pos, mut neg) = (false, false);
    for i in 0..n {
        let (a, b, c) = (v[i], v[(i + 1) % n], v[(i + 2) % n]);
        let cross = i64::from(b.0 - a.0) * i64::from(c.1 - b.1)
            - i64::from(b.1 - a.1) * i64::from(c.0 - b.0);
        pos |= cross > 0;
        neg |= cross < 0;
    }
    !(pos && neg)
}

/// A convex polygon filled as plotters fills any polygon (`fill_polygon` of
/// plotters-backend: lines swept along the longer side of the bounding box, each line's
/// span between the edges' crossings drawn solid, its two end pixels in the colour mixed
/// by the crossings' fractions), without its general bookkeeping: for a convex polygon the
/// span of a line is from the least to the largest crossing of the edges that reach it,
/// with no sort and no allocation per line. The figures' strokes and cells (tens of
/// thousands per figure) drew in a third of the time.
struct Convex {
    pts: Vec<(i32, i32)>,
    color: RGBAColor,
}

impl<'a> PointCollection<'a, (i32, i32)> for &'a Convex {
    type Point = &'a (i32, i32);
    type IntoIter = &'a [(i32, i32)];
    fn point_iter(self) -> &'a [(i32, i32)] {
        &self.pts
    }
}

impl<DB: DrawingBackend> Drawable<DB> for Convex {
    fn draw<I: Iterator<Item = BackendCoord>>(
        &self,
        points: I,
        backend: &mut DB,
        _: (u32, u32),
    ) -> Result<(), DrawingErrorKind<DB::ErrorType>> {
        let mut v = [(0i32, 0i32); CONVEX_MAX];
        let mut n = 0;
        for p in points.take(CONVEX_MAX) {
            v[n] = p;
            n += 1;
        }
        fill_convex(backend, &v[..n], self.color)
    }
}

/// The fill of [`Convex`] on the backend's pixels (type docs).
fn fill_convex<DB: DrawingBackend>(
    back: &mut DB,
    v: &[BackendCoord],
    color: RGBAColor,
) -> Result<(), DrawingErrorKind<DB::ErrorType>> {
    let Some(&first) = v.first() else {
        return Ok(());
    };
    let (mut x0, mut x1, mut y0, mut y1) = (first.0, first.0, first.1, first.1);
    for &(x, y) in v {
        (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
    }
    if x0 == x1 || y0 == y1 {
        return back.draw_line((x0, y0), (x1, y1), &color);
    }
    // Sweep along x when the box is wider than high (plotters' choice): `master` is the
    // swept coordinate, `slave` the one along each line.
    let along_x = x1 - x0 > y1 - y0;
    let split = |p: BackendCoord| if along_x { p } else { (p.1, p.0) };
    let (low, high) = if along_x { (x0, x1) } else { (y0, y1) };
    for line in low..=high {
        let (mut from, mut to) = (f64::INFINITY, f64::NEG_INFINITY);
        for i in 0..v.len() {
            let (mut a, mut b) = (split(v[i]), split(v[(i + 1) % v.len()]));
            if a.0 == b.0 {
                continue;
            }
            if a.0 > b.0 {
                std::mem::swap(&mut a, &mut b);
            }
            if line < a.0 || line > b.0 {
                continue;
            }
            let epoch = i64::from(line - a.0);
            let s = f64::from(a.1) + (i64::from(b.1 - a.1) * epoch) as f64 / f64::from(b.0 - a.0);
            from = from.min(s);
            to = to.max(s);
        }
        if from > to {
            continue;
        }
        let place = |m: i32, s: i32| if along_x { (m, s) } else { (s, m) };
        back.draw_line(
            place(line, from.ceil() as i32),
            place(line, to.floor() as i32),
            &color,
        )?;
        back.draw_pixel(
            place(line, from.floor() as i32),
            color.mix(from.ceil() - from).to_backend_color(),
        )?;
        back.draw_pixel(
            place(line, to.ceil() as i32),
            color.mix(to - to.floor()).to_backend_color(),
        )?;
    }
    Ok(())
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

/// A dense series (x never decreasing, more than four points per pixel column) reduced to
/// each column's first, lowest, highest and last points in their order (the M4 reduction
/// of Jugel et al., 2014): the stroke of the reduced line reaches the same extremes in
/// every column and joins the columns where the series does, so it paints what the whole
/// series paints but for the path inside a column, which a stroke as wide as a pixel
/// covers anyway. The paper's wheel's contact force (54,860 steps on 1,400 pixels) drew
/// in a fifth of the time. `None` for any other polyline.
fn by_columns(pts: &[Pt]) -> Option<Vec<Pt>> {
    let (first, last) = (pts.first()?, pts.last()?);
    let columns = (last.0.floor() - first.0.floor()).max(0.0) + 1.0;
    if (pts.len() as f64) <= 4.0 * columns
        || pts
            .windows(2)
            .any(|w| w[1].0.partial_cmp(&w[0].0).is_none_or(|o| o.is_lt()))
    {
        return None;
    }
    let mut out = Vec::with_capacity(4 * columns as usize + 4);
    let mut i = 0;
    while i < pts.len() {
        let col = pts[i].0.floor();
        let mut j = i;
        let (mut lo, mut hi) = (i, i);
        while j < pts.len() && pts[j].0.floor() == col {
            if pts[j].1 < pts[lo].1 {
                lo = j;
            }
            if pts[j].1 > pts[hi].1 {
                hi = j;
            }
            j += 1;
        }
        let (a, b) = (lo.min(hi), lo.max(hi));
        for k in [i, a, b, j - 1] {
            if out.last() != Some(&pts[k]) {
                out.push(pts[k]);
            }
        }
        i = j;
    }
    Some(out)
}

/// Strokes a polyline `width` pixels wide: each segment a rectangle, each bend a disk of
/// the same width (a round join), all cut to the current clip. Every painted point is
/// within `width / 2` of the polyline. (plotters' own wide paths are one polygon offset
/// from the whole path, whose joins at sharp bends reach far beyond the data: the spikes
/// of a dense spectrum or force history then crossed the axes and the tick labels.)
pub(crate) fn draw_polyline(area: &Area, pts: &[Pt], color: RGBAColor, width: f64) -> Res<()> {
    let dense = by_columns(pts);
    let pts = thin_out(dense.as_deref().unwrap_or(pts));
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

    /// Draws `v` black on white on a 64 x 64 bitmap, with [`Convex`] or with plotters'
    /// polygon; the pixels' darkness (0 white, 1 black).
    fn raster(v: &[(i32, i32)], convex: bool) -> Vec<f64> {
        let (w, h) = (64u32, 64u32);
        let mut buf = vec![255u8; (w * h * 3) as usize];
        {
            let area = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
            let color = BLACK.to_rgba();
            if convex {
                area.draw(&Convex {
                    pts: v.to_vec(),
                    color,
                })
                .unwrap();
            } else {
                area.draw(&Polygon::new(v.to_vec(), color.filled()))
                    .unwrap();
            }
            area.present().unwrap();
        }
        buf.chunks(3)
            .map(|p| 1.0 - f64::from(p[0]) / 255.0)
            .collect()
    }

    /// The convex fill against plotters' general one (an independent rasterizer) and
    /// against the exact area, on triangles and quadrilaterals of every slope: the same
    /// solid pixels inside, the ink within a pixel per unit of perimeter of the area.
    #[test]
    fn the_convex_fill_paints_what_plotters_paints() {
        // A small linear congruential sequence: the same shapes on every run.
        let mut seed = 12345u64;
        let mut next = |n: i32| {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 33) % n as u64) as i32
        };
        let mut checked = 0;
        for case in 0..300 {
            let n = 3 + case % 2;
            let v: Vec<(i32, i32)> = (0..n).map(|_| (4 + next(56), 4 + next(56))).collect();
            if !is_convex(&v) {
                continue;
            }
            let area2: i64 = (0..n)
                .map(|i| {
                    let (a, b) = (v[i], v[(i + 1) % n]);
                    i64::from(a.0) * i64::from(b.1) - i64::from(b.0) * i64::from(a.1)
                })
                .sum();
            let area = area2.abs() as f64 / 2.0;
            if area < 20.0 {
                continue;
            }
            let perimeter: f64 = (0..n)
                .map(|i| {
                    let (a, b) = (v[i], v[(i + 1) % n]);
                    f64::from(b.0 - a.0).hypot(f64::from(b.1 - a.1))
                })
                .sum();
            let ours = raster(&v, true);
            let theirs = raster(&v, false);
            // Solid inside for both: the pixels one of them paints fully and the other
            // does not paint at all are few: plotters leaves out the line of an edge
            // along its sweep (two edges ending on one line with more than a pixel
            // between them), which is painted here, being the polygon's boundary.
            let flat: f64 = (0..n)
                .map(|i| {
                    let (a, b) = (v[i], v[(i + 1) % n]);
                    if a.0 == b.0 || a.1 == b.1 {
                        1.0 + f64::from((b.0 - a.0).abs() + (b.1 - a.1).abs())
                    } else {
                        0.0
                    }
                })
                .sum();
            let opposite = ours
                .iter()
                .zip(&theirs)
                .filter(|(a, b)| (**a > 0.99 && **b < 0.01) || (**a < 0.01 && **b > 0.99))
                .count();
            assert!(
                opposite as f64 <= 2.0 + flat + 0.05 * perimeter,
                "case {case}: {v:?}: {opposite} pixels"
            );
            let ink: f64 = ours.iter().sum();
            assert!(
                (ink - area).abs() <= perimeter + 4.0,
                "case {case}: {v:?}: ink {ink}, area {area}"
            );
            checked += 1;
        }
        assert!(checked > 100, "{checked}");
    }
}
