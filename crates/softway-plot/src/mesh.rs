//! Mesh plots: colour maps, colour bars and vector fields on triangle
//! meshes.

use std::collections::HashMap;

use plotters::prelude::*;

use crate::audit;
use crate::axes::{auto_range, extend, is_const, linear_ticks, Scale, Ticks};
use crate::geom::{
    draw_line, draw_polyline, fill_polygon, fill_polygon_rgba, fill_rect, stroke_rect, Pt, Rect,
};
use crate::render::Fig;
use crate::render::{render, Area, Fail, Res};
use crate::style::{
    draw_text, fit_text, text_w, viridis, Sty, CAP, DESC, HA, NOTE, NO_DATA, TEXT, VA,
};

mod grid;
mod modes;
mod vectors;
pub(crate) use modes::render_mode_shapes;
pub(crate) use vectors::render_vector_fields;

/// Colour of the overlay segments (the obstacle), a dark red.
const OVERLAY: RGBColor = RGBColor(200, 30, 30);

/// A round value printed short: `0.5`, `2`, `1e-3`.
fn fmt_value(v: f64) -> String {
    if (1e-3..1e5).contains(&v.abs()) {
        let s = format!("{v:.6}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        format!("{v:e}")
    }
}
use crate::{EdgeMode, MeshColorMap, MeshOptions, MeshVectorField, ModeShape};

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

/// Checks frames of a per-point field (mode shapes, vector fields): some frames, each with
/// one value per point (`values`: its count) and triangles on its points; `kind` names a
/// frame (`"shape"`, `"frame"`), `values` the field (`"displacements"`, `"vectors"`).
fn check_per_point<'a>(
    frames: impl ExactSizeIterator<Item = (usize, &'a [[f64; 2]], &'a [[usize; 3]])>,
    (empty, kind, values): (&str, &str, &str),
) -> Res<()> {
    if frames.len() == 0 {
        return Err(Fail::Empty(empty.into()));
    }
    for (i, (n, points, triangles)) in frames.enumerate() {
        if n != points.len() {
            return Err(Fail::Draw(format!(
                "{kind} {i}: {n} {values} for {} points",
                points.len()
            )));
        }
        check_triangles(points, triangles, &format!("{kind} {i}"))?;
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
/// `extend`: values below / above the range are drawn in its end colours, shown (as
/// matplotlib does) by a triangle at that end of the bar.
fn draw_colorbar(
    area: &Area,
    r: Rect,
    (vmin, vmax): (f64, f64),
    t: &Ticks,
    label: &str,
    extend: (bool, bool),
    st: &Sty,
) -> Res<()> {
    let tri_h = 0.9 * r.w();
    if extend.1 {
        fill_polygon(
            area,
            &[(r.x0, r.y0), (r.x1, r.y0), (r.cx(), r.y0 - tri_h)],
            viridis(1.0),
        )?;
    }
    if extend.0 {
        fill_polygon(
            area,
            &[(r.x0, r.y1), (r.x1, r.y1), (r.cx(), r.y1 + tri_h)],
            viridis(0.0),
        )?;
    }
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
        let above = if extend.1 { tri_h } else { 0.0 };
        draw_text(
            area,
            o,
            (r.x0, r.y0 - above - 0.6 * st.pad),
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

/// Checks a colour map's mesh and values: triangles on its points, a value per triangle.
fn check_color_map(map: &MeshColorMap) -> Res<()> {
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
    check_triangles(map.points, map.triangles, "colour map")
}

pub(crate) fn render_color_map(
    map: &MeshColorMap,
    size: (u32, u32),
    opts: &MeshOptions,
) -> Res<Vec<u8>> {
    render_color_map_overlay(map, &[], size, opts)
}

/// [`render_color_map`] with line segments drawn over the cells (in the coordinates of
/// the map's points, cut to the plot), in the overlay's dark red.
pub(crate) fn render_color_map_overlay(
    map: &MeshColorMap,
    overlay: &[[[f64; 2]; 2]],
    size: (u32, u32),
    opts: &MeshOptions,
) -> Res<Vec<u8>> {
    check_color_map(map)?;
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
    let xl = axis_label("x", &map.length_unit);
    let yl = axis_label("y", &map.length_unit);

    render(size, |area, fig| {
        let st = Sty::new(fig, fig.out);
        let (title, ft) = fit_text(&map.title, st.ft, fig.w - 2.0 * st.pad, 2);
        let top = st.pad
            + if map.title.is_empty() {
                0.5 * CAP * st.fs
            } else {
                title.len() as f64 * 1.15 * (CAP + DESC) * ft + st.pad
            };
        let note = grid::Note::fit(&map.note, fig, &st);
        let lay = MapLayout::fit(fig, &st, (top, &note), bb, vr, &map.colorbar_label)?;
        let v = MeshView { bb, r: lay.r, unit };
        audit::with_clip(lay.r, || {
            draw_cells(area, &v, map, vr, opts, fig, &st)?;
            for seg in overlay {
                let (a, b) = (v.px(seg[0]), v.px(seg[1]));
                if a.0.is_finite() && a.1.is_finite() && b.0.is_finite() && b.1.is_finite() {
                    draw_polyline(area, &[a, b], OVERLAY.to_rgba(), 2.5 * st.thin)?;
                }
            }
            Ok(())
        })?;
        draw_mesh_axes(area, &v, &lay.xt, &lay.yt, true, true, &st)?;
        draw_map_labels(area, &lay, (&xl, &yl), (&title, ft), fig, &st)?;
        note.draw(area, fig, &st)?;
        let finite = || map.cell_values.iter().filter(|v| v.is_finite());
        let extend = (
            finite().any(|&v| v < vr.0 - 1e-9 * vr.0.abs()),
            finite().any(|&v| v > vr.1 + 1e-9 * vr.1.abs()),
        );
        draw_colorbar(area, lay.cb, vr, &lay.ct, &map.colorbar_label, extend, &st)
    })
}

/// Where a colour map's plot and colour bar are, with their ticks.
struct MapLayout {
    r: Rect,
    cb: Rect,
    xt: Ticks,
    yt: Ticks,
    ct: Ticks,
}

impl MapLayout {
    /// The largest plot of the extent `bb` that fits the canvas under the title band
    /// (`top`) and above the bottom band (with the `note`), beside the y axis's labels and
    /// the colour bar, centred (the bands' widths found again from the ticks the plot gets,
    /// up to three times).
    fn fit(
        fig: &Fig,
        st: &Sty,
        (top, note): (f64, &grid::Note),
        bb: [f64; 4],
        vr: (f64, f64),
        cb_label: &str,
    ) -> Res<MapLayout> {
        let (fs, pad) = (st.fs, st.pad);
        let (dx, dy) = (bb[1] - bb[0], bb[3] - bb[2]);
        let bottom = grid::bottom_band(st, note);
        let mut left_w = grid::left_band(st, 3.0 * fs);
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
            let new_left = grid::left_band(st, yt.max_label_w(fs));
            let new_cb = colorbar_width(&ct, cb_label, st);
            let done = (new_left - left_w).abs() < 1.0 && (new_cb - cb_w).abs() < 1.0;
            left_w = new_left;
            cb_w = new_cb;
            layout = Some(MapLayout { r, cb, xt, yt, ct });
            if done {
                break;
            }
        }
        layout.ok_or_else(|| Fail::Draw("layout failed".into()))
    }
}

/// The colour map's cells in its plot `v`, coloured over `vr`, with their edges.
fn draw_cells(
    area: &Area,
    v: &MeshView,
    map: &MeshColorMap,
    vr: (f64, f64),
    opts: &MeshOptions,
    fig: &Fig,
    st: &Sty,
) -> Res<()> {
    let size_px = fill_triangles(area, v, map.points, map.triangles, |i| {
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
        v,
        map.points,
        map.triangles,
        inner,
        false,
        BLACK.mix(0.3),
        st,
    )
}

/// The colour map's axis labels `xl` and `yl` beside its plot, and its title lines (of
/// size `ft`) at the top of the canvas.
fn draw_map_labels(
    area: &Area,
    lay: &MapLayout,
    (xl, yl): (&str, &str),
    (title, ft): (&[String], f64),
    fig: &Fig,
    st: &Sty,
) -> Res<()> {
    let (fs, fl, pad, tick) = (st.fs, st.fl, st.pad, st.tick);
    let r = lay.r;
    draw_text(
        area,
        xl,
        (r.cx(), r.y1 + tick + 0.6 * pad + CAP * fs + pad),
        fl,
        HA::Center,
        VA::Top,
        false,
        TEXT,
    )?;
    let ylx = r.x0 - tick - 0.6 * pad - lay.yt.max_label_w(fs) - 0.8 * pad - (CAP + DESC) * fl;
    draw_text(area, yl, (ylx, r.cy()), fl, HA::Center, VA::Top, true, TEXT)?;
    for (i, l) in title.iter().enumerate() {
        draw_text(
            area,
            l,
            (0.5 * fig.w, pad + i as f64 * 1.15 * (CAP + DESC) * ft),
            ft,
            HA::Center,
            VA::Top,
            false,
            TEXT,
        )?;
    }
    Ok(())
}

/// The lines of a figure's note, centred at the bottom of the canvas.
fn draw_note(area: &Area, lines: &[String], nf: f64, fig: &Fig, st: &Sty) -> Res<()> {
    for (i, l) in lines.iter().enumerate() {
        let base =
            fig.h - st.pad - DESC * nf - (lines.len() - 1 - i) as f64 * 1.15 * (CAP + DESC) * nf;
        draw_text(
            area,
            l,
            (0.5 * fig.w, base),
            nf,
            HA::Center,
            VA::Baseline,
            false,
            NOTE,
        )?;
    }
    Ok(())
}

/// A round value (1, 2 or 5 times a power of ten) at most `v`.
fn round_below(v: f64) -> f64 {
    if !(v > 0.0 && v.is_finite()) {
        return 0.0;
    }
    let p = 10f64.powf(v.log10().floor());
    [5.0, 2.0, 1.0]
        .into_iter()
        .map(|m| m * p)
        .find(|&x| x <= v * (1.0 + 1e-12))
        .unwrap_or(p)
}

/// The text between `[` and `]` of a label (its unit), or empty.
fn unit_of(label: &str) -> &str {
    match (label.rfind('['), label.rfind(']')) {
        (Some(a), Some(b)) if b > a => &label[a + 1..b],
        _ => "",
    }
}

#[cfg(test)]
mod tests {
    use super::modes::{boundary_loops, displacement_at};
    use super::*;
    use crate::test_util::{assert_png, centroid, disk, distinct_colors, out_dir, rectangle};
    use crate::{
        mesh_color_map, mesh_vector_fields, mesh_vector_fields_with, mode_shapes, PlotError,
    };
    use std::f64::consts::PI;

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
            note: String::new(),
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
            note: String::new(),
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
            note: String::new(),
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
                note: String::new(),
                overlay: Vec::new(),
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
                note: String::new(),
                overlay: Vec::new(),
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

    #[test]
    fn non_finite_cell_values_are_drawn_as_no_data() {
        let (pts, tris) = rectangle(2.0, 1.0, 4, 2);
        let vals: Vec<f64> = (0..tris.len()).map(|i| i as f64).collect();
        let map = MeshColorMap {
            points: &pts,
            triangles: &tris,
            cell_values: &vals,
            title: String::new(),
            colorbar_label: "s [-]".into(),
            length_unit_scale: 1.0,
            length_unit: "m".into(),
            note: String::new(),
        };
        let grey = |buf: &[u8]| {
            buf.chunks(3)
                .filter(|p| (p[0], p[1], p[2]) == (NO_DATA.0, NO_DATA.1, NO_DATA.2))
                .count()
        };
        let opts = MeshOptions::default();
        let clean = render_color_map(&map, (400, 300), &opts).unwrap();
        let before = grey(&clean);
        // Two cells without a value: grey, and the colour scale is that of
        // the finite values (the full viridis range is still used).
        let mut holes = vals.clone();
        holes[0] = f64::NAN;
        holes[5] = f64::INFINITY;
        let map = MeshColorMap {
            cell_values: &holes,
            ..map
        };
        let buf = render_color_map(&map, (400, 300), &opts).unwrap();
        assert!(
            grey(&buf) > before + 500,
            "{} -> {} grey pixels",
            before,
            grey(&buf)
        );
        for end in [viridis(0.0), viridis(1.0)] {
            assert!(
                buf.chunks(3)
                    .any(|p| (p[0], p[1], p[2]) == (end.0, end.1, end.2)),
                "{end:?} missing"
            );
        }
    }

    /// The boundary of a disk is one closed loop through its rim nodes (of a rectangle one
    /// loop too); a mode-shape figure of a disk's
    /// ovalisation and breathing draws strictly (nothing outside its panels) and refuses
    /// displacements of the wrong length.
    #[test]
    fn mode_shapes_sample() {
        let dir = out_dir("mode_shapes");
        let (pts, tris) = disk(0.25, 8);
        let loops = boundary_loops(&pts, &tris);
        assert_eq!(loops.len(), 1);
        let l = &loops[0];
        assert_eq!(l.first(), l.last());
        let rim: Vec<usize> = (0..pts.len())
            .filter(|&k| (pts[k][0].hypot(pts[k][1]) - 0.25).abs() < 1e-9)
            .collect();
        assert_eq!(l.len(), rim.len() + 1);
        assert!(rim.iter().all(|k| l.contains(k)));
        let (pb, tb) = rectangle(1.0, 0.1, 10, 2);
        assert_eq!(boundary_loops(&pb, &tb).len(), 1);

        // u_r = a r/R cos(n theta), n = 2 (ovalisation) and 0 (breathing), a = R / 10.
        let shape = |n: f64| -> Vec<[f64; 2]> {
            pts.iter()
                .map(|p| {
                    let (r, th) = (p[0].hypot(p[1]), p[1].atan2(p[0]));
                    let ur = 0.025 * r / 0.25 * (n * th).cos();
                    [ur * th.cos(), ur * th.sin()]
                })
                .collect()
        };
        let (oval, breathing) = (shape(2.0), shape(0.0));
        let frames: Vec<ModeShape> = [(&oval, "n = 2"), (&breathing, "n = 0")]
            .iter()
            .map(|(d, t)| ModeShape {
                points: &pts,
                triangles: &tris,
                displacement: d,
                lines: vec![
                    (0..=40)
                        .map(|k| [0.0, -0.26 + 0.013 * f64::from(k)])
                        .collect(),
                    (0..=64)
                        .map(|k| {
                            let a = f64::from(k) * PI / 32.0;
                            [0.15 * a.cos(), 0.15 * a.sin()]
                        })
                        .collect(),
                ],
                title: if t.contains('2') {
                    format!("mode: 1234.5 Hz, {t}, a title long enough to wrap")
                } else {
                    format!("mode: 1234.5 Hz\n{t}")
                },
                length_unit_scale: 100.0,
                length_unit: "cm".into(),
                colorbar_label: "|u| / max |u|".into(),
                note: "Displacements scaled: the largest is 10 % of the radius.".into(),
            })
            .collect();
        let p = dir.join("modes.png");
        mode_shapes(&p, &frames, 2, (1400, 800)).unwrap();
        assert_png(&p, (1400, 800));
        let buf = render_mode_shapes(&frames, 0, (1400, 800)).unwrap();
        assert!(distinct_colors(&buf) > 50);
        // A point at a node moves with it; between nodes, linearly; outside, nowhere.
        let k = 5;
        let at = displacement_at(pts[k], &pts, &tris, &oval).unwrap();
        assert!((at[0] - oval[k][0]).abs() < 1e-15 && (at[1] - oval[k][1]).abs() < 1e-15);
        let t = tris[7];
        let c = [
            (pts[t[0]][0] + pts[t[1]][0] + pts[t[2]][0]) / 3.0,
            (pts[t[0]][1] + pts[t[1]][1] + pts[t[2]][1]) / 3.0,
        ];
        let want = [
            (oval[t[0]][0] + oval[t[1]][0] + oval[t[2]][0]) / 3.0,
            (oval[t[0]][1] + oval[t[1]][1] + oval[t[2]][1]) / 3.0,
        ];
        let got = displacement_at(c, &pts, &tris, &oval).unwrap();
        assert!((got[0] - want[0]).abs() < 1e-15 && (got[1] - want[1]).abs() < 1e-15);
        assert_eq!(displacement_at([0.3, 0.0], &pts, &tris, &oval), None);
        let bad = ModeShape {
            displacement: &oval[1..],
            ..frames[0].clone()
        };
        assert!(matches!(
            mode_shapes(&dir.join("e.png"), &[bad], 1, (600, 400)),
            Err(PlotError::Draw { .. })
        ));
        assert!(matches!(
            mode_shapes(&dir.join("e.png"), &[], 1, (600, 400)),
            Err(PlotError::Empty { .. })
        ));
    }
}
