//! Line plots: panel validation, layout (ticks, labels, legend placement)
//! and painting.

use plotters::prelude::*;

use crate::audit;
use crate::axes::{extend, given_ticks, make_ticks, resolve_range, valid, Scale, Ticks};
use crate::geom::{
    clip_polylines, clip_segment, dash_polyline, draw_line, draw_marker, draw_polyline, fill_rect,
    stroke_rect, Pt, Rect,
};
use crate::render::{Area, Fail, Res};
use crate::style::{
    draw_text, fit_text, series_color, text_w, Sty, CAP, DESC, GRID_MAJOR, GRID_MINOR, HA, NOTE,
    REF_LINE, TEXT, VA,
};
use crate::{Panel, Series, SeriesStyle};

mod checks;
pub(crate) use checks::validate_panel;
use checks::{isolated_extreme, panel_ranges};
mod layout;
pub(crate) use layout::layout_panel;
mod legend;
use legend::{
    draw_legend, legend_geom, legend_geom_within, legend_overlap, span_color, span_labels,
    vline_color, vline_labels, Entry, EntryKind, LegendGeom,
};

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
pub(crate) fn draw_no_data(area: &Area, cell: Rect, p: &Panel, st: &Sty) -> Res<()> {
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
    let (title, ft) = fit_text(&p.title, st.ft, cell.w() - 2.0 * st.pad, 1);
    draw_text(
        area,
        &title.join(" "),
        (cell.cx(), r.y0 - 0.6 * st.pad),
        ft,
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
pub(crate) struct PanelLayout {
    pub(crate) plot: Rect,
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
    /// An automatic y range set by one isolated point ([`isolated_extreme`]).
    outlier: Option<String>,
    title_top: f64,
    /// The title's lines and font size (wrapped or shrunk to the cell's width).
    title: (Vec<String>, f64),
    /// The axis labels' font sizes (shrunk to fit).
    x_label_fs: f64,
    y_label_fs: f64,
    /// The note's lines and font size.
    note: (Vec<String>, f64),
}

/// The centre nearest `cx` of a text `w` wide kept inside `cell` (less `pad` each side).
fn centre_in(cx: f64, w: f64, cell: &Rect, pad: f64) -> f64 {
    let (lo, hi) = (cell.x0 + pad + 0.5 * w, cell.x1 - pad - 0.5 * w);
    if lo > hi {
        cell.cx()
    } else {
        cx.clamp(lo, hi)
    }
}

/// Line height of text at font size `f`.
fn line_h(f: f64) -> f64 {
    1.15 * (CAP + DESC) * f
}

/// Height of the note block under the x label (0 without a note).
fn note_block(note: &(Vec<String>, f64), pad: f64) -> f64 {
    if note.0.iter().all(|l| l.is_empty()) {
        0.0
    } else {
        note.0.len() as f64 * line_h(note.1) + 0.4 * pad
    }
}

/// The entries of a panel's legend, each as text (equal for equal entries).
pub(crate) fn legend_keys(p: &Panel) -> Vec<String> {
    legend_entries(p).iter().map(|e| format!("{e:?}")).collect()
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
    for (i, l) in span_labels(p).into_iter().enumerate() {
        if !l.is_empty() {
            entries.push(Entry {
                label: l.to_string(),
                kind: EntryKind::Span(span_color(i)),
            });
        }
    }
    for (i, l) in vline_labels(p).into_iter().enumerate() {
        if !l.is_empty() {
            entries.push(Entry {
                label: l.to_string(),
                kind: EntryKind::VLine(vline_color(i)),
            });
        }
    }
    entries
}

pub(crate) fn draw_panel(area: &Area, cell: Rect, p: &Panel, st: &Sty) -> Res<()> {
    let lay = layout_panel(cell, p, st, None, &[])?;
    paint_panel(area, cell, p, st, &lay)
}

pub(crate) fn paint_panel(
    area: &Area,
    cell: Rect,
    p: &Panel,
    st: &Sty,
    lay: &PanelLayout,
) -> Res<()> {
    audit::with_bounds(cell, "its panel", || paint_panel_in(area, cell, p, st, lay))
}

/// The data of a panel: bands, grid, reference lines, series (cut to the plot rectangle).
fn paint_data(area: &Area, p: &Panel, st: &Sty, lay: &PanelLayout) -> Res<()> {
    let (plot, xs, ys, xt, yt) = (lay.plot, &lay.xs, &lay.ys, &lay.xt, &lay.yt);
    // Shaded x bands, behind the grid.
    let labels = span_labels(p);
    for (x0, x1, l) in &p.vspans {
        if !(valid(*x0, p.x_log) && valid(*x1, p.x_log)) {
            continue;
        }
        let (a, b) = (x0.min(*x1).max(xs.lo), x0.max(*x1).min(xs.hi));
        if a < b {
            let i = labels.iter().position(|s| s == l).unwrap_or(0);
            let r = Rect {
                x0: xs.px(a),
                y0: plot.y0,
                x1: xs.px(b),
                y1: plot.y1,
            };
            fill_rect(area, r, span_color(i))?;
        }
    }

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
    let vlabels = vline_labels(p);
    for (x, l) in &p.vlines {
        if valid(*x, p.x_log) && *x >= xs.lo && *x <= xs.hi {
            let xx = xs.px(*x);
            let c = vline_color(vlabels.iter().position(|s| s == l).unwrap_or(0));
            for d in dash_polyline(
                &[(xx, plot.y1), (xx, plot.y0)],
                2.5 * st.thin,
                2.0 * st.thin,
            ) {
                draw_polyline(area, &d, c.to_rgba(), 1.5 * st.thin)?;
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
    Ok(())
}

fn paint_panel_in(area: &Area, cell: Rect, p: &Panel, st: &Sty, lay: &PanelLayout) -> Res<()> {
    let plot = lay.plot;
    audit::with_bounds(plot, "its axes", || {
        audit::with_clip(plot, || paint_data(area, p, st, lay))
    })?;
    paint_frame(area, p, st, lay)?;
    paint_x_texts(area, cell, p, st, lay)?;
    paint_y_texts_and_title(area, cell, p, st, lay)?;
    paint_legend(area, p, st, lay)
}

/// The frame of the axes and their ticks with their labels (the minor ticks on a log
/// axis).
fn paint_frame(area: &Area, p: &Panel, st: &Sty, lay: &PanelLayout) -> Res<()> {
    let (fs, pad, tick) = (st.fs, st.pad, st.tick);
    let (plot, xs, ys, xt, yt) = (lay.plot, &lay.xs, &lay.ys, &lay.xt, &lay.yt);
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
    Ok(())
}

/// The x label under the tick labels, the note under it (both follow the axes, which in a
/// grid are aligned with the row's), and the x axis's common factor.
fn paint_x_texts(area: &Area, cell: Rect, p: &Panel, st: &Sty, lay: &PanelLayout) -> Res<()> {
    let (fs, pad, tick) = (st.fs, st.pad, st.tick);
    let (plot, xt) = (lay.plot, &lay.xt);
    let fl = lay.x_label_fs;
    let ticks_bottom = plot.y1 + tick + 0.6 * pad + CAP * fs;
    let xlabel_base = ticks_bottom + 0.8 * pad + CAP * fl;
    draw_text(
        area,
        &p.x_label,
        (
            centre_in(plot.cx(), text_w(&p.x_label, fl), &cell, pad),
            xlabel_base,
        ),
        fl,
        HA::Center,
        VA::Baseline,
        false,
        TEXT,
    )?;
    let note_top = if p.x_label.is_empty() {
        ticks_bottom
    } else {
        xlabel_base + DESC * fl
    };
    let (note_lines, nf) = &lay.note;
    for (i, l) in note_lines.iter().enumerate() {
        let base = note_top + 0.4 * pad + CAP * nf + i as f64 * line_h(*nf);
        draw_text(
            area,
            l,
            (cell.cx(), base),
            *nf,
            HA::Center,
            VA::Baseline,
            false,
            NOTE,
        )?;
    }
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
    Ok(())
}

/// The y label, the y axis's common factor and the title.
fn paint_y_texts_and_title(
    area: &Area,
    cell: Rect,
    p: &Panel,
    st: &Sty,
    lay: &PanelLayout,
) -> Res<()> {
    let (fs, pad) = (st.fs, st.pad);
    let (plot, yt) = (lay.plot, &lay.yt);
    // The y label centred on the axes when it fits there, else moved to stay in the cell.
    let yl_w = text_w(&p.y_label, lay.y_label_fs);
    let (lo, hi) = (cell.y0 + pad + 0.5 * yl_w, cell.y1 - pad - 0.5 * yl_w);
    let yl_c = if lo > hi {
        cell.cy()
    } else {
        plot.cy().clamp(lo, hi)
    };
    draw_text(
        area,
        &p.y_label,
        (cell.x0 + pad, yl_c),
        lay.y_label_fs,
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
    let (title_lines, tf) = &lay.title;
    // A title centred on the plot when it fits there, else on the cell.
    for (i, l) in title_lines.iter().enumerate() {
        let cx = centre_in(plot.cx(), text_w(l, *tf), &cell, pad);
        draw_text(
            area,
            l,
            (cx, lay.title_top + i as f64 * line_h(*tf)),
            *tf,
            HA::Center,
            VA::Top,
            false,
            TEXT,
        )?;
    }
    Ok(())
}

/// The legend where the layout put it, and the strict figure's flags (a legend over data,
/// an axis range set by one isolated point).
fn paint_legend(area: &Area, p: &Panel, st: &Sty, lay: &PanelLayout) -> Res<()> {
    if let Some(r) = lay.legend {
        draw_legend(area, r, &lay.entries, &lay.lg, st)?;
        if lay.legend_score > 0 {
            audit::flag(|| {
                format!(
                    "the legend of panel {:?} hides data: no room for it outside the data",
                    p.title
                )
            });
        }
    }
    if let Some(o) = &lay.outlier {
        audit::flag(|| o.clone());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_util::{assert_png, decode_png, out_dir};
    use crate::{line_plot, panels, PlotError};
    use std::f64::consts::PI;

    fn sine_panel(n: usize) -> Panel {
        let t: Vec<f64> = (0..n).map(|i| i as f64 / (n - 1) as f64).collect();
        let mut p = Panel::new("Sine and cosine", "t [s]", "u [m]");
        p.series.push(Series::new(
            "sin",
            t.clone(),
            t.iter().map(|t| (2.0 * PI * t).sin()).collect(),
            SeriesStyle::Line,
        ));
        p.series.push(Series::new(
            "cos",
            t.clone(),
            t.iter().map(|t| (2.0 * PI * t).cos()).collect(),
            SeriesStyle::Dashed,
        ));
        p
    }

    /// A contact patch along the rolling direction: a half-ellipse of pressure over a
    /// third of the axis, the bound, the tractions, and long legend labels.
    fn patch_panel() -> Panel {
        let s: Vec<f64> = (0..=60).map(|i| -23.0 + 46.0 * i as f64 / 60.0).collect();
        let p: Vec<f64> = s
            .iter()
            .map(|&x| 9000.0 * (1.0 - (x / 8.5) * (x / 8.5)).max(0.0).sqrt())
            .collect();
        let mut pn = Panel::new(
            "The patch at the last step, along the rolling direction",
            "s [mm] (the wheel's travel over the base: +)",
            "stress [MPa]",
        );
        let series = |label: &str, y: Vec<f64>, style| Series::new(label, s.clone(), y, style);
        pn.series.push(series(
            "p, layer at z = -5 mm",
            p.clone(),
            SeriesStyle::Dashed,
        ));
        pn.series
            .push(series("p, layer at z = 5 mm", p.clone(), SeriesStyle::Line));
        pn.series.push(series(
            "mu p (the bound)",
            p.iter().map(|v| 0.3 * v).collect(),
            SeriesStyle::Dashed,
        ));
        pn.series.push(series(
            "|q|, sticking",
            p.iter().map(|v| (0.3 * v).min(1000.0)).collect(),
            SeriesStyle::Markers,
        ));
        pn.series.push(series(
            "q along the rolling direction",
            s.iter()
                .zip(&p)
                .map(|(x, v)| if *v > 0.0 { 120.0 * x } else { 0.0 })
                .collect(),
            SeriesStyle::Line,
        ));
        pn
    }

    fn count_color(rgb: &[u8], c: RGBColor) -> usize {
        rgb.chunks(3)
            .filter(|p| (p[0], p[1], p[2]) == (c.0, c.1, c.2))
            .count()
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
                    Ok(()) => {
                        assert_png(&path, (300, 200));
                    }
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
    fn line_plot_writes_a_decodable_png_showing_the_series() {
        let dir = out_dir("line_plot_png");
        for size in [(640, 480), (333, 201)] {
            let p = dir.join(format!("sine_{}x{}.png", size.0, size.1));
            line_plot(&p, &sine_panel(200), size).unwrap();
            let img = assert_png(&p, size);
            let n = (size.0 * size.1) as usize;
            // Mostly white background, and both series drawn in their own
            // palette colours (the line interiors keep the exact colour).
            assert!(count_color(&img.rgb, WHITE) > n / 2);
            for i in 0..2 {
                let c = series_color(i);
                let k = count_color(&img.rgb, c);
                assert!(k > size.0 as usize / 4, "series {i}: {k} pixels of {c:?}");
            }
        }
    }

    #[test]
    fn bad_input_gives_typed_errors_and_no_file() {
        let dir = out_dir("bad_input");
        let good = sine_panel(20);
        // A length mismatch in one panel of a grid: a drawing error (not a
        // panic, not "empty"), naming the series.
        let mut bad = sine_panel(20);
        bad.series[1].y.pop();
        let p = dir.join("mismatch.png");
        match panels(&p, &[good.clone(), bad], 1, 2, (600, 400)) {
            Err(PlotError::Draw { message, .. }) => assert!(message.contains("cos"), "{message}"),
            other => panic!("expected PlotError::Draw, got {other:?}"),
        }
        // No series, or no finite point in any panel: empty.
        let mut all_nan = sine_panel(20);
        for s in &mut all_nan.series {
            s.y.iter_mut().for_each(|y| *y = f64::NAN);
        }
        let none = Panel::new("nothing", "x", "y");
        let q = dir.join("empty.png");
        for input in [vec![none.clone()], vec![all_nan.clone(), none]] {
            let r = panels(&q, &input, 1, input.len(), (600, 400));
            assert!(matches!(r, Err(PlotError::Empty { .. })), "{r:?}");
        }
        assert!(matches!(
            line_plot(&q, &all_nan, (600, 400)),
            Err(PlotError::Empty { .. })
        ));
        // One panel with data is enough for a grid; the other shows "no data".
        let r = dir.join("half_empty.png");
        panels(&r, &[good, all_nan], 2, 1, (600, 600)).unwrap();
        assert_png(&r, (600, 600));
        assert!(!p.exists() && !q.exists());
        let names: Vec<_> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, ["half_empty.png"]);
    }

    #[test]
    fn atomic_write_replaces_or_keeps_the_figure() {
        let dir = out_dir("atomic");
        let p = dir.join("sub/dir/fig.png");
        line_plot(&p, &sine_panel(50), (400, 300)).unwrap();
        assert_png(&p, (400, 300));
        // A successful redraw replaces the figure.
        line_plot(&p, &sine_panel(50), (500, 300)).unwrap();
        assert_png(&p, (500, 300));
        let before = std::fs::read(&p).unwrap();
        // A failed draw (too small, or bad data) leaves it untouched.
        assert!(line_plot(&p, &sine_panel(50), (50, 50)).is_err());
        let mut bad = sine_panel(50);
        bad.series[0].x.push(2.0);
        assert!(line_plot(&p, &bad, (400, 300)).is_err());
        assert_eq!(std::fs::read(&p).unwrap(), before);
        let names: Vec<_> = std::fs::read_dir(p.parent().unwrap())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, ["fig.png"], "no temporary file left behind");
    }

    #[test]
    fn non_finite_values_are_skipped() {
        let x = vec![0.0, 1.0, 2.0, 2.5, 3.0, 4.0, f64::INFINITY, 5.0];
        let y = vec![
            0.0,
            0.5,
            f64::NAN,
            f64::INFINITY,
            1.0,
            2.0,
            9.0,
            f64::NEG_INFINITY,
        ];
        let mut p = Panel::new("gaps", "x", "y");
        p.series
            .push(Series::new("a", x.clone(), y.clone(), SeriesStyle::Line));
        // Ranges from the finite points only: x in [0, 4], y in [0, 2].
        let ((x0, x1), (y0, y1)) = panel_ranges(&p).unwrap();
        assert_eq!((x0, x1), auto_range_lin(0.0, 4.0));
        assert_eq!((y0, y1), auto_range_lin(0.0, 2.0));
        // The line is broken at the non-finite points: two pieces, 0-1 and
        // 3-4.
        let plot = Rect::new(0.0, 0.0, 400.0, 300.0);
        let xs = Scale {
            lo: x0,
            hi: x1,
            log: false,
            p_lo: plot.x0,
            p_hi: plot.x1,
        };
        let ys = Scale {
            lo: y0,
            hi: y1,
            log: false,
            p_lo: plot.y1,
            p_hi: plot.y0,
        };
        let sp = series_pixels(&p.series[0], &xs, &ys, &plot, 2.0);
        assert_eq!(sp.lines.len(), 2, "{:?}", sp.lines);
        assert!(sp.lines.iter().all(|l| l.len() == 2));
        assert!(sp
            .lines
            .iter()
            .flatten()
            .all(|q| q.0.is_finite() && q.1.is_finite()));
        // On a log axis non-positive values are skipped as well.
        let mut lg = Panel::new("log", "x", "y");
        lg.y_log = true;
        lg.series.push(Series::new(
            "b",
            vec![0.0, 1.0, 2.0, 3.0, 4.0],
            vec![-1.0, 0.0, 1.0, 10.0, 100.0],
            SeriesStyle::Line,
        ));
        let ((lx0, lx1), (ly0, ly1)) = panel_ranges(&lg).unwrap();
        assert_eq!((lx0, lx1), auto_range_lin(2.0, 4.0));
        assert!((ly0.log10() + 0.1).abs() < 1e-12 && (ly1.log10() - 2.1).abs() < 1e-12);
        // Both draw.
        let dir = out_dir("non_finite");
        for (name, panel) in [("gaps.png", &p), ("log.png", &lg)] {
            let f = dir.join(name);
            line_plot(&f, panel, (400, 300)).unwrap();
            assert_eq!(decode_png(&f).width, 400);
        }
    }

    /// A shaded band tints the columns of its x range inside the plot: with x and y fixed to
    /// 0..1 and the band 0.25..0.5, a row through the middle of the plot has one run of
    /// tinted pixels over a quarter of the plot's width, and the band's label is in the
    /// legend.
    #[test]
    fn vspan_tints_its_x_range() {
        let mut p = Panel::new("", "x", "y");
        p.series.push(Series::new(
            "",
            vec![0.0, 1.0],
            vec![0.05, 0.05],
            SeriesStyle::Line,
        ));
        p.x_range = Some((0.0, 1.0));
        p.y_range = Some((0.0, 1.0));
        let dir = out_dir("vspan");
        let plain = dir.join("plain.png");
        line_plot(&plain, &p, (600, 400)).unwrap();
        p.vspans.push((0.25, 0.5, "stick".into()));
        let shaded = dir.join("shaded.png");
        line_plot(&shaded, &p, (600, 400)).unwrap();
        let (a, b) = (decode_png(&plain), decode_png(&shaded));
        // Rows through the plot differ only where the band lies.
        let y = (a.height / 2) as usize;
        let row = |img: &crate::test_util::Image| -> Vec<[u8; 3]> {
            let w = img.width as usize;
            (0..w)
                .map(|x| {
                    let k = 3 * (y * w + x);
                    [img.rgb[k], img.rgb[k + 1], img.rgb[k + 2]]
                })
                .collect()
        };
        let (ra, rb) = (row(&a), row(&b));
        let changed: Vec<usize> = (0..ra.len()).filter(|&x| ra[x] != rb[x]).collect();
        // A quarter of the plot's width (the plot is most of the 600 px), in one run of
        // columns (grid lines drawn over the tint may interrupt it by a pixel).
        let tinted = changed.len() as f64 / 600.0;
        assert!((0.15..0.25).contains(&tinted), "{changed:?}");
        let span = (changed[changed.len() - 1] - changed[0] + 1) as f64;
        assert!(span <= changed.len() as f64 + 4.0, "{changed:?}");
        assert!(legend_entries(&p).iter().any(|e| e.label == "stick"));
    }

    /// Regression (issue 34: the spectrum's and the contact force's spikes crossed the
    /// axes and the tick labels): no pixel of a series' colour lies outside its axes, on a
    /// spiky series on log axes, a dense zigzag cut by fixed ranges and markers at the
    /// edges. plotters' wide paths (one polygon offset from the whole path) failed this
    /// with spikes reaching the canvas' edge. Every drawing stays in its region too (the
    /// tests draw strictly: a label, legend or title outside its panel is an error).
    #[test]
    fn no_series_pixel_outside_its_axes() {
        let n = 3000;
        let x: Vec<f64> = (0..n).map(|i| 30.0 * 1.003f64.powi(i)).collect();
        // Alternating 1e-3 and 1e3 (six decades) with a few outliers far below the range.
        let y: Vec<f64> = (0..n)
            .map(|i| match i % 7 {
                0 => 1e-9,
                k if k % 2 == 0 => 1e3,
                _ => 1e-3,
            })
            .collect();
        let mut spiky = Panel::new(
            "A spectrum with spikes, and a title long enough to be wrapped onto a second line \
             rather than cut at the right edge of the figure",
            "frequency [Hz]",
            "amplitude [N]",
        );
        spiky.x_log = true;
        spiky.y_log = true;
        spiky.y_range = Some((1e-4, 1e4));
        spiky
            .series
            .push(Series::new("amplitude", x.clone(), y, SeriesStyle::Line));
        spiky.vlines.push((1e3, "a component".into()));
        let t: Vec<f64> = (0..n).map(|i| i as f64 / n as f64).collect();
        let zig: Vec<f64> = (0..n)
            .map(|i| if i % 2 == 0 { -5.0 } else { 5.0 } * (1.0 + (i % 13) as f64))
            .collect();
        let mut cut = Panel::new("Zigzag cut by fixed ranges", "t [s]", "q [-]");
        cut.series.push(Series::new(
            "zigzag",
            t.clone(),
            zig.clone(),
            SeriesStyle::Line,
        ));
        cut.series.push(Series::new(
            "markers",
            t.iter().step_by(50).copied().collect(),
            zig.iter().step_by(50).copied().collect(),
            SeriesStyle::Markers,
        ));
        cut.x_range = Some((0.2, 0.4));
        cut.y_range = Some((-20.0, 20.0));
        let dir = out_dir("no_pixel_outside");
        for (k, p) in [spiky, cut].iter().enumerate() {
            let size = (900, 500);
            let path = dir.join(format!("panel{k}.png"));
            line_plot(&path, p, size).unwrap();
            let img = decode_png(&path);
            // The layout as line_plot made it (super-sampled by 2), in output pixels.
            let fig = crate::render::Fig {
                k: 2.0,
                out: (900.0, 500.0),
                w: 1800.0,
                h: 1000.0,
            };
            let st = Sty::new(&fig, (fig.w, fig.h));
            let lay = layout_panel(Rect::new(0.0, 0.0, fig.w, fig.h), p, &st, None, &[]).unwrap();
            let plot = Rect::new(
                lay.plot.x0 / 2.0,
                lay.plot.y0 / 2.0,
                lay.plot.x1 / 2.0,
                lay.plot.y1 / 2.0,
            )
            .grow(1.0);
            let legend = lay
                .legend
                .map(|r| Rect::new(r.x0 / 2.0, r.y0 / 2.0, r.x1 / 2.0, r.y1 / 2.0).grow(1.0));
            let w = img.width as usize;
            let mut outside = Vec::new();
            for (i, px) in img.rgb.chunks(3).enumerate() {
                let (xx, yy) = ((i % w) as f64 + 0.5, (i / w) as f64 + 0.5);
                let c = RGBColor(px[0], px[1], px[2]);
                let series = (0..p.series.len()).any(|s| series_color(s) == c);
                let in_legend = legend.is_some_and(|r| r.contains((xx, yy)));
                if series && !plot.contains((xx, yy)) && !in_legend {
                    outside.push((xx, yy));
                }
            }
            assert!(
                outside.is_empty(),
                "panel {k}: {} series pixels outside the axes, e.g. {:?}",
                outside.len(),
                &outside[..outside.len().min(5)]
            );
            // Something was drawn inside, and the long title was wrapped, not cut.
            assert!(img
                .rgb
                .chunks(3)
                .any(|px| RGBColor(px[0], px[1], px[2]) == series_color(0)));
            if k == 0 {
                assert_eq!(lay.title.0.len(), 2, "{:?}", lay.title);
            }
        }
    }

    /// A title, an axis label or a note too long for its panel is an error when drawn
    /// strictly, unless fitted: every text of a grid of small panels with long texts stays
    /// inside its panel (the audit records none outside), and the legend shared by all
    /// panels is drawn once.
    #[test]
    fn long_texts_stay_inside_small_panels() {
        let mut ps = Vec::new();
        for i in 0..6 {
            let mut p = sine_panel(50);
            p.title = format!("space-time, mass redistribution, run number {i} with a long title");
            p.x_label = "time since the first impact of the bar on the wall t [s]".into();
            // Longer than the axes are high (the converge figure's max von Mises).
            p.y_label = "max von mises turn average of the rim and the hub [MPa]".into();
            // A note on some panels only: the axes of a row stay aligned, each x label
            // under its own axes.
            if i % 2 == 1 {
                p.note = "not in the asymptotic range: the series is not monotone, so no order and no limit are drawn".into();
            }
            ps.push(p);
        }
        let dir = out_dir("long_texts");
        let path = dir.join("grid.png");
        panels(&path, &ps, 2, 3, (900, 500)).unwrap();
        assert_png(&path, (900, 500));
        // Only the first panel keeps the legend: the others list nothing new.
        let fig = crate::render::Fig {
            k: 2.0,
            out: (900.0, 500.0),
            w: 1800.0,
            h: 1000.0,
        };
        let st = Sty::new(&fig, (600.0, 500.0));
        let cell = Rect::new(0.0, 0.0, 600.0, 500.0);
        let seen = legend_keys(&ps[0]);
        assert!(layout_panel(cell, &ps[0], &st, None, &[])
            .unwrap()
            .legend
            .is_some());
        assert!(layout_panel(cell, &ps[1], &st, None, &seen)
            .unwrap()
            .legend
            .is_none());
    }

    /// The automatic linear range of the data extent `lo..hi`.
    /// A spectrum as `track.png` draws it (issue 48): a fixed log range, a noisy floor, a
    /// strong line near the right end, markers and reference lines, in one panel of a
    /// column of four.
    fn track_like_spectrum() -> Panel {
        let mut p = Panel::new("Contact force spectrum", "wavelength [m]", "amplitude [kN]");
        p.x_log = true;
        p.y_log = true;
        let n = 600;
        let wl: Vec<f64> = (0..n)
            .map(|i| 0.015 * (5.0f64 / 0.015).powf(i as f64 / (n - 1) as f64))
            .collect();
        let amp: Vec<f64> = wl
            .iter()
            .enumerate()
            .map(|(i, &w)| {
                let noise = 0.01 * (1.0 + 0.8 * ((i * 7919) % 13) as f64 / 13.0);
                let line = |c: f64, a: f64| a * (-((w / c).ln() / 0.02).powi(2)).exp();
                noise + line(0.6, 3.0) + line(0.1, 1.2) + line(0.3, 0.3)
            })
            .collect();
        p.series
            .push(Series::new("contact force", wl, amp, SeriesStyle::Line));
        for (what, x, y) in [
            ("sleeper spacing: 0.600 m (46 Hz at 100 km/h)", 0.6, 3.0),
            ("P2: 0.636 m (44 Hz at 100 km/h)", 0.636, 0.5),
            ("rail element: 0.100 m (278 Hz at 100 km/h)", 0.1, 1.2),
        ] {
            p.series
                .push(Series::new(what, vec![x], vec![y], SeriesStyle::Markers));
        }
        p.vlines.push((0.026, "pinned-pinned: 0.026 m".into()));
        p.x_range = Some((0.015, 5.0));
        p.y_range = Some((3e-3, 90.0));
        p
    }

    /// Every pixel a series' segments and markers pass through, densely sampled.
    fn data_points(p: &Panel, lay: &PanelLayout) -> Vec<Pt> {
        let mut out = Vec::new();
        for (s, sp) in p.series.iter().zip(&lay.px) {
            for l in &sp.lines {
                for w in l.windows(2) {
                    let (a, b) = (w[0], w[1]);
                    let k = ((b.0 - a.0).abs().max((b.1 - a.1).abs()) / 2.0)
                        .ceil()
                        .max(1.0);
                    for j in 0..=k as usize {
                        let t = j as f64 / k;
                        out.push((a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1)));
                    }
                }
            }
            out.extend(&sp.markers);
            out.extend(&sp.isolated);
            let _ = s;
        }
        for (x, _) in &p.vlines {
            let xx = lay.xs.px(*x);
            if xx >= lay.plot.x0 && xx <= lay.plot.x1 {
                let mut y = lay.plot.y0;
                while y <= lay.plot.y1 {
                    out.push((xx, y));
                    y += 2.0;
                }
            }
        }
        out
    }

    /// Issue 48's class: a legend drawn over the data it explains (`track.png`'s spectrum:
    /// the legend over the sleeper line and its markers). In a column of panels (the axes
    /// aligned, no room to the right) and alone, with fixed and automatic ranges, every
    /// legend leaves every data pixel visible, checked on the layout against densely
    /// sampled segments, markers and reference lines; and the figures draw strictly.
    #[test]
    fn legend_hides_no_data() {
        use crate::render::render;
        use crate::style::Sty;
        let dir = out_dir("legend_hides_no_data");
        let spectrum = track_like_spectrum();
        let mut auto = spectrum.clone();
        auto.y_range = None;
        let mut force = sine_panel(400);
        force.hlines.push((1.0, "amplitude".into()));
        type Case = (&'static str, Vec<Panel>, usize, usize, (u32, u32));
        let cases: Vec<Case> = vec![
            (
                "column",
                vec![force.clone(), spectrum.clone(), auto.clone(), force.clone()],
                4,
                1,
                (1400, 1500),
            ),
            ("alone_fixed", vec![spectrum.clone()], 1, 1, (1400, 500)),
            ("alone_auto", vec![auto.clone()], 1, 1, (1400, 500)),
            (
                "grid",
                vec![spectrum, auto, force.clone(), force.clone()],
                2,
                2,
                (1700, 1000),
            ),
            // A column whose last panel's legend has room only to the right of the axes
            // (a contact patch's pressure, bound and tractions): the aligned axes leave
            // exactly that room.
            (
                "column_legend_right",
                vec![force.clone(), force, patch_panel()],
                3,
                1,
                (1200, 1500),
            ),
        ];
        for (name, ps, rows, cols, size) in cases {
            // The figure, drawn strictly: a legend over data fails it.
            let path = dir.join(format!("{name}.png"));
            panels(&path, &ps, rows, cols, size).unwrap_or_else(|e| panic!("{name}: {e}"));
            // The layout's legend against the data's pixels, panel by panel (a panel laid
            // out alone in its cell: the grid's alignment only moves the axes).
            render(size, |_, fig| {
                let cw = fig.w / cols as f64;
                let ch = fig.h / rows as f64;
                let st = Sty::new(fig, (cw / fig.k, ch / fig.k));
                for (i, p) in ps.iter().enumerate() {
                    let (r, c) = ((i / cols) as f64, (i % cols) as f64);
                    let cell = Rect::new(c * cw, r * ch, (c + 1.0) * cw, (r + 1.0) * ch);
                    let lay = layout_panel(cell, p, &st, None, &[]).unwrap();
                    let Some(lg) = lay.legend else { continue };
                    let hidden = data_points(p, &lay)
                        .into_iter()
                        .filter(|&q| lg.contains(q))
                        .count();
                    assert_eq!(
                        hidden, 0,
                        "{name}, panel {i}: the legend hides {hidden} data pixels"
                    );
                }
                Ok(())
            })
            .unwrap();
        }
    }

    /// Issue 48's class: an automatic range set by one isolated point (a spectrum's empty
    /// band at -285 dB drew every real curve as a flat line at 0). A strict figure names
    /// the point; without it the figure draws; a sharp resonance (one sample at the top of
    /// a peak its neighbours climb to) is data, not an outlier.
    #[test]
    fn autoscale_set_by_one_point_is_caught() {
        let dir = out_dir("autoscale_outlier");
        let mut p = Panel::new(
            "Roughness spectrum",
            "wavelength [mm]",
            "level [dB re 1 um]",
        );
        p.x_log = true;
        let lam: Vec<f64> = (0..20).map(|i| 4.0 * 1.26f64.powi(i)).collect();
        for pass in 0..4 {
            let mut y: Vec<f64> = (0..20)
                .map(|i| -0.3 * f64::from(pass) * (f64::from(i) / 20.0) + 0.1 * f64::from(i % 3))
                .collect();
            y[0] = -285.0;
            p.series.push(Series::new(
                format!("after {pass} passes"),
                lam.clone(),
                y,
                SeriesStyle::LineMarkers,
            ));
        }
        let path = dir.join("outlier.png");
        match line_plot(&path, &p, (1200, 700)) {
            Err(PlotError::Draw { message, .. }) => {
                assert!(message.contains("isolated point"), "{message}");
                assert!(message.contains("−285"), "{message}");
            }
            other => panic!("the outlier passed: {other:?}"),
        }
        for s in &mut p.series {
            s.y[0] = f64::NAN;
        }
        line_plot(&path, &p, (1200, 700)).unwrap();
        let mut peak = Panel::new("Resonance", "f [Hz]", "A [-]");
        peak.series.push(Series::new(
            "response",
            (0..40).map(f64::from).collect(),
            (0..40)
                .map(|i| 1.0 / (1.0 + (f64::from(i) - 20.0).powi(2)))
                .collect(),
            SeriesStyle::Line,
        ));
        line_plot(&dir.join("peak.png"), &peak, (1200, 700)).unwrap();
        // `softway shakedown`'s first pass above nine flat ones (within 1 %): nothing hidden.
        let mut shake = Panel::new("Plastic strain increment per pass", "pass", "increment");
        shake.y_log = true;
        shake.series.push(Series::new(
            "p0/k = 4.5",
            (1..=10).map(f64::from).collect(),
            (1..=10)
                .map(|i| {
                    if i == 1 {
                        0.0158
                    } else {
                        0.0097 - 1e-5 * f64::from(i)
                    }
                })
                .collect(),
            SeriesStyle::LineMarkers,
        ));
        line_plot(&dir.join("transient.png"), &shake, (1200, 700)).unwrap();
    }

    fn auto_range_lin(lo: f64, hi: f64) -> (f64, f64) {
        crate::axes::auto_range(lo, hi, false)
    }
}
