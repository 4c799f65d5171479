//! A panel's legend: its entries (series, reference lines, spans), its box and where it
//! goes without covering the data.

use super::*;

#[derive(Debug, Clone)]
pub(super) enum EntryKind {
    Series {
        color: RGBColor,
        style: SeriesStyle,
        shape: usize,
    },
    Reference,
    Span(RGBAColor),
    VLine(RGBColor),
}

/// The colour of the `i`-th distinct vertical-line label.
pub(super) fn vline_color(i: usize) -> RGBColor {
    const C: [RGBColor; 6] = [
        RGBColor(213, 94, 0),
        RGBColor(0, 158, 115),
        RGBColor(204, 121, 167),
        RGBColor(86, 180, 233),
        RGBColor(230, 159, 0),
        RGBColor(120, 120, 120),
    ];
    C[i % C.len()]
}

/// The distinct labels of a panel's vertical lines, in order of first appearance.
pub(super) fn vline_labels(p: &Panel) -> Vec<&str> {
    let mut labels: Vec<&str> = Vec::new();
    for (_, l) in &p.vlines {
        if !labels.contains(&l.as_str()) {
            labels.push(l);
        }
    }
    labels
}

/// The tint of the `i`-th distinct span label: the series palette, light.
pub(super) fn span_color(i: usize) -> RGBAColor {
    let c = series_color(i + 3);
    RGBColor(c.0, c.1, c.2).mix(0.16)
}

/// The distinct labels of a panel's spans, in order of first appearance.
pub(super) fn span_labels(p: &Panel) -> Vec<&str> {
    let mut labels: Vec<&str> = Vec::new();
    for (_, _, l) in &p.vspans {
        if !labels.contains(&l.as_str()) {
            labels.push(l);
        }
    }
    labels
}

#[derive(Debug, Clone)]
pub(super) struct Entry {
    pub(super) label: String,
    pub(super) kind: EntryKind,
}

pub(super) struct LegendGeom {
    pub(super) w: f64,
    pub(super) h: f64,
    pub(super) row: f64,
    pub(super) sample: f64,
    /// Entries per row (1: a column); the entries fill the rows left to right.
    pub(super) cols: usize,
    /// The left edge of each column from the legend's.
    pub(super) col_x: Vec<f64>,
}

/// A legend of one column.
pub(super) fn legend_geom(entries: &[Entry], st: &Sty) -> LegendGeom {
    legend_geom_within(entries, st, 0.0)
}

/// A legend of as many columns as fit in `max_w` (at least one).
pub(super) fn legend_geom_within(entries: &[Entry], st: &Sty, max_w: f64) -> LegendGeom {
    let f = st.fleg;
    let sample = 2.4 * f;
    let row = 1.4 * f;
    let n = entries.len().max(1);
    // Each column as wide as its widest entry; the most columns that fit.
    let widths = |cols: usize| -> Vec<f64> {
        let mut w = vec![0.0f64; cols];
        for (i, e) in entries.iter().enumerate() {
            w[i % cols] = w[i % cols].max(text_w(&e.label, f));
        }
        w.iter()
            .map(|tw| 0.6 * f + sample + 0.5 * f + tw + 0.7 * f)
            .collect()
    };
    let cols = (1..=n)
        .rev()
        .find(|&c| widths(c).iter().sum::<f64>() <= max_w)
        .unwrap_or(1);
    let w = widths(cols);
    let mut col_x = Vec::with_capacity(cols);
    let mut x = 0.0;
    for cw in &w {
        col_x.push(x);
        x += cw;
    }
    LegendGeom {
        w: x,
        h: n.div_ceil(cols) as f64 * row + 0.5 * f,
        row,
        sample,
        cols,
        col_x,
    }
}

pub(super) fn draw_legend(
    area: &Area,
    r: Rect,
    entries: &[Entry],
    g: &LegendGeom,
    st: &Sty,
) -> Res<()> {
    fill_rect(area, r, WHITE.mix(0.9))?;
    stroke_rect(area, r, RGBColor(175, 175, 175), st.thin)?;
    let f = st.fleg;
    for (i, e) in entries.iter().enumerate() {
        let (row, col) = (i / g.cols, i % g.cols);
        let cy = r.y0 + 0.25 * f + (row as f64 + 0.5) * g.row;
        let x0 = r.x0 + g.col_x[col];
        let (a, b) = ((x0 + 0.6 * f, cy), (x0 + 0.6 * f + g.sample, cy));
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
            EntryKind::Span(c) => {
                let r = Rect {
                    x0: a.0,
                    y0: cy - 0.35 * f,
                    x1: b.0,
                    y1: cy + 0.35 * f,
                };
                fill_rect(area, r, *c)?;
            }
            EntryKind::Reference => {
                for d in dash_polyline(&[a, b], 4.0 * st.thin, 3.0 * st.thin) {
                    draw_polyline(area, &d, REF_LINE.to_rgba(), 1.3 * st.thin)?;
                }
            }
            EntryKind::VLine(c) => {
                for d in dash_polyline(&[a, b], 2.5 * st.thin, 2.0 * st.thin) {
                    draw_polyline(area, &d, c.to_rgba(), 1.5 * st.thin)?;
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
pub(super) fn legend_overlap(
    r: &Rect,
    lines: &[Vec<Pt>],
    marks: &[Pt],
    hlines: &[f64],
    vlines: &[f64],
) -> usize {
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
    n += vlines.iter().filter(|&&x| x >= r.x0 && x <= r.x1).count() * 3;
    n
}
