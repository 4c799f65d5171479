//! A line panel's layout: its ranges and ticks, the plot rectangle left by its texts, and
//! the legend's place (the rule of [`layout_panel`]).

use super::*;

/// Lays out a panel in `cell`. With `forced`, the plot rectangle is given
/// (used to align the axes of a grid of panels); otherwise it is derived
/// from the labels. A legend that would hide data goes outside, to the
/// right, when there is room; else, with an automatic y range, head room is
/// added above the data for it.
///
/// The rule, the same for every figure (issue 48: a spectrum's legend over its strongest
/// line and its markers): a legend never hides data (series, markers, reference lines).
/// It goes, in this order, inside where it hides nothing; outside to the right; inside
/// over head room added above the data (automatic y range only); under the axes, in as
/// many columns as the cell's width holds (in a grid the row's axes make room for it).
/// Only when none of these fits is it drawn inside over data, and a strict figure
/// (`SOFTWAY_PLOT_STRICT`, the tests) fails naming the panel.
pub(crate) fn layout_panel(
    cell: Rect,
    p: &Panel,
    st: &Sty,
    forced: Option<Rect>,
    seen: &[String],
) -> Res<PanelLayout> {
    let l = layout_panel_with(cell, p, st, forced, 0.0, false, seen)?;
    if l.legend_score == 0 {
        return Ok(l);
    }
    let mut best = l;
    if p.y_range.is_none() {
        let h = (best.lg.h + 2.0 * st.pad) / best.plot.h();
        if h < 0.5 {
            let l = layout_panel_with(cell, p, st, forced, h, false, seen)?;
            if l.legend_score == 0 {
                return Ok(l);
            }
            best = l;
        }
    }
    match layout_panel_with(cell, p, st, forced, 0.0, true, seen) {
        Ok(l) if l.legend_score == 0 && l.legend.is_some() => Ok(l),
        _ => Ok(best),
    }
}

/// A panel's ranges (after the head room) and the scales and ticks they give a plot.
struct Ranges {
    x: (f64, f64),
    y: (f64, f64),
    x_log: bool,
    y_log: bool,
    x_ticks: Vec<f64>,
}

impl Ranges {
    /// The panel's ranges with a fraction `headroom` of the plot height kept free above
    /// the data.
    fn of(p: &Panel, headroom: f64) -> Res<Ranges> {
        let ((xlo, xhi), (ylo, mut yhi)) = panel_ranges(p)?;
        if headroom > 0.0 {
            yhi = if p.y_log {
                10f64.powf(ylo.log10() + (yhi.log10() - ylo.log10()) / (1.0 - headroom))
            } else {
                ylo + (yhi - ylo) / (1.0 - headroom)
            };
        }
        Ok(Ranges {
            x: (xlo, xhi),
            y: (ylo, yhi),
            x_log: p.x_log,
            y_log: p.y_log,
            x_ticks: p.x_ticks.clone(),
        })
    }

    fn scales(&self, plot: &Rect) -> (Scale, Scale) {
        (
            Scale {
                lo: self.x.0,
                hi: self.x.1,
                log: self.x_log,
                p_lo: plot.x0,
                p_hi: plot.x1,
            },
            Scale {
                lo: self.y.0,
                hi: self.y.1,
                log: self.y_log,
                p_lo: plot.y1,
                p_hi: plot.y0,
            },
        )
    }

    fn xticks(&self, plot: &Rect, fs: f64) -> Ticks {
        let auto = make_ticks(self.x.0, self.x.1, self.x_log, plot.w(), fs, true);
        if self.x_ticks.is_empty() {
            return auto;
        }
        let fallback = auto.clone();
        given_ticks(
            &self.x_ticks,
            self.x,
            self.x_log,
            plot.w(),
            (fs, true),
            auto,
        )
        .unwrap_or(fallback)
    }

    fn yticks(&self, plot: &Rect, fs: f64) -> Ticks {
        make_ticks(self.y.0, self.y.1, self.y_log, plot.h(), fs, false)
    }

    /// Each series in pixels on `plot`.
    fn pixels(&self, p: &Panel, plot: &Rect, st: &Sty) -> Vec<SeriesPx> {
        let (xs, ys) = self.scales(plot);
        p.series
            .iter()
            .map(|s| series_pixels(s, &xs, &ys, plot, st.lw))
            .collect()
    }
}

/// A panel's texts fitted to its cell: the title, the axis labels' sizes, the note.
struct Texts {
    title_top: f64,
    /// The cell's width for text.
    width: f64,
    title: (Vec<String>, f64),
    x_label_fs: f64,
    y_label_fs: f64,
    note: (Vec<String>, f64),
}

impl Texts {
    fn fit(cell: Rect, p: &Panel, st: &Sty) -> Texts {
        let (fs, fl, ft, pad) = (st.fs, st.fl, st.ft, st.pad);
        let width = cell.w() - 2.0 * pad;
        let note = fit_text(&p.note, 0.85 * fs, width, 4);
        Texts {
            title_top: cell.y0 + pad,
            width,
            title: fit_text(&p.title, ft, width, 3),
            x_label_fs: fit_text(&p.x_label, fl, width, 1).1,
            y_label_fs: fit_text(&p.y_label, fl, cell.h() - 2.0 * pad, 1).1,
            note: if p.note.is_empty() {
                (Vec::new(), note.1)
            } else {
                note
            },
        }
    }
}

/// The plot rectangle derived from the panel's texts and tick labels: under the title,
/// above the ticks' labels, the x label, the note and `below_block` (a legend under the
/// axes), right of the y label and the ticks' labels, the last x tick label in the cell.
fn auto_plot(
    cell: Rect,
    p: &Panel,
    st: &Sty,
    ranges: &Ranges,
    text: &Texts,
    below_block: f64,
) -> Rect {
    let (fs, pad, tick) = (st.fs, st.pad, st.tick);
    // Vertical layout (independent of the tick labels, except for the band of a common y
    // factor).
    let mut top = text.title_top;
    let title = &text.title;
    if !p.title.is_empty() {
        top += title.0.len() as f64 * line_h(title.1) - 0.15 * (CAP + DESC) * title.1 + 0.8 * pad;
    }
    let label_block = if p.x_label.is_empty() {
        0.0
    } else {
        (CAP + DESC) * text.x_label_fs + 0.8 * pad
    };
    let bottom = cell.y1
        - pad
        - below_block
        - note_block(&text.note, pad)
        - label_block
        - CAP * fs
        - 0.6 * pad
        - tick;
    let mut plot = Rect::new(cell.x0, top + 0.5 * CAP * fs, cell.x1, bottom);
    if ranges.yticks(&plot, fs).offset.is_some() {
        plot.y0 = top + CAP * fs + 0.8 * pad;
    }
    // Horizontal layout.
    let ylabel_block = if p.y_label.is_empty() {
        0.0
    } else {
        (CAP + DESC) * text.y_label_fs + 0.8 * pad
    };
    plot.x0 =
        cell.x0 + pad + ylabel_block + ranges.yticks(&plot, fs).max_label_w(fs) + 0.6 * pad + tick;
    plot.x1 = cell.x1 - pad;
    // Keep the last x tick label inside the cell.
    for _ in 0..2 {
        let (xs, _) = ranges.scales(&plot);
        let overhang = ranges
            .xticks(&plot, fs)
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

fn too_small(plot: &Rect) -> Res<()> {
    if plot.w() < 20.0 || plot.h() < 20.0 {
        Err(Fail::Draw(
            "the image is too small for the axes, labels and legend".into(),
        ))
    } else {
        Ok(())
    }
}

/// The legend's entries (those listed by an earlier panel of the grid, `seen`, left out)
/// and whether the panel has a legend.
fn wanted_entries(p: &Panel, seen: &[String]) -> (Vec<Entry>, bool) {
    let all = legend_entries(p);
    let wanted = all.len() > 1 || !p.hlines.is_empty() || !p.vlines.is_empty();
    let entries: Vec<Entry> = all
        .into_iter()
        .filter(|e| !seen.contains(&format!("{e:?}")))
        .collect();
    let has_legend = !p.no_legend && !entries.is_empty() && wanted;
    (entries, has_legend)
}

/// [`layout_panel`] with a fraction `headroom` of the plot height kept free
/// above the data, and with `below` the legend under the axes (its score `usize::MAX` when
/// the cell has no room for it there).
#[allow(clippy::too_many_arguments)]
fn layout_panel_with(
    cell: Rect,
    p: &Panel,
    st: &Sty,
    forced: Option<Rect>,
    headroom: f64,
    below: bool,
    seen: &[String],
) -> Res<PanelLayout> {
    validate_panel(p)?;
    let ranges = Ranges::of(p, headroom)?;
    let outlier = if p.y_range.is_none() {
        isolated_extreme(p, ranges.x)
    } else {
        None
    };
    let text = Texts::fit(cell, p, st);
    let (entries, has_legend) = wanted_entries(p, seen);
    let below = below && has_legend;
    let lg = if below {
        legend_geom_within(&entries, st, text.width)
    } else {
        legend_geom(&entries, st)
    };
    let below_block = if below { lg.h + 0.3 * st.pad } else { 0.0 };
    let mut plot = match forced {
        Some(r) => r,
        None => auto_plot(cell, p, st, &ranges, &text, below_block),
    };
    too_small(&plot)?;
    let mut px = ranges.pixels(p, &plot, st);
    // Legend placement: the inside position hiding the least data, or
    // outside on the right when every inside position hides something; under the axes
    // when asked (`below`).
    let (legend, legend_score) = if below {
        legend_below(cell, p, st, &plot, &text, &lg)
    } else if has_legend {
        let place = Placing {
            cell,
            p,
            st,
            forced,
            ranges: &ranges,
            lg: &lg,
        };
        place.legend(&mut plot, &mut px)?
    } else {
        (None, 0)
    };
    let (xs, ys) = ranges.scales(&plot);
    Ok(PanelLayout {
        plot,
        xt: ranges.xticks(&plot, st.fs),
        yt: ranges.yticks(&plot, st.fs),
        xs,
        ys,
        px,
        entries,
        lg,
        legend,
        legend_score,
        outlier,
        title_top: text.title_top,
        title: text.title,
        x_label_fs: text.x_label_fs,
        y_label_fs: text.y_label_fs,
        note: text.note,
    })
}

/// The legend under the x label and the note, centred on the axes, kept in the cell; its
/// score `usize::MAX` (and no place) when the cell has no room for it there.
fn legend_below(
    cell: Rect,
    p: &Panel,
    st: &Sty,
    plot: &Rect,
    text: &Texts,
    lg: &LegendGeom,
) -> (Option<Rect>, usize) {
    let (fs, pad, tick) = (st.fs, st.pad, st.tick);
    let ticks_bottom = plot.y1 + tick + 0.6 * pad + CAP * fs;
    let note_top = if p.x_label.is_empty() {
        ticks_bottom
    } else {
        ticks_bottom + 0.8 * pad + (CAP + DESC) * text.x_label_fs
    };
    let y0 = note_top + note_block(&text.note, pad) + 0.3 * pad;
    let x0 = centre_in(plot.cx(), lg.w, &cell, pad) - 0.5 * lg.w;
    let r = Rect::new(x0, y0, x0 + lg.w, y0 + lg.h);
    if r.y1 <= cell.y1 - 0.3 * pad && r.x0 >= cell.x0 && r.x1 <= cell.x1 {
        (Some(r), 0)
    } else {
        (None, usize::MAX)
    }
}

/// What the legend's place beside or over the data depends on.
struct Placing<'a> {
    cell: Rect,
    p: &'a Panel,
    st: &'a Sty,
    forced: Option<Rect>,
    ranges: &'a Ranges,
    lg: &'a LegendGeom,
}

impl Placing<'_> {
    /// The inside position of the legend that hides the least data (series, markers,
    /// reference lines) on `plot`, with the count it hides (`usize::MAX` when the legend
    /// does not fit inside).
    fn best_inside(&self, plot: &Rect, px: &[SeriesPx]) -> (usize, (f64, f64)) {
        let (p, lg, pad) = (self.p, self.lg, self.st.pad);
        let (xs, ys) = self.ranges.scales(plot);
        let hl: Vec<f64> = p
            .hlines
            .iter()
            .filter(|(y, _)| valid(*y, p.y_log))
            .map(|(y, _)| ys.px(*y))
            .collect();
        let vl: Vec<f64> = p
            .vlines
            .iter()
            .filter(|(x, _)| valid(*x, p.x_log) && *x >= xs.lo && *x <= xs.hi)
            .map(|(x, _)| xs.px(*x))
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
                let score = legend_overlap(&rr, &lines, &marks, &hl, &vl);
                if score < best.0 {
                    best = (score, (x, y));
                }
            }
        }
        best
    }

    /// The legend inside where it hides nothing; else outside on the right when there is
    /// room (the plot narrowed for it when it was not given); else inside where it hides
    /// least, with that count. `plot` and its pixels `px` follow a narrowing.
    fn legend(&self, plot: &mut Rect, px: &mut Vec<SeriesPx>) -> Res<(Option<Rect>, usize)> {
        let (cell, lg, pad) = (self.cell, self.lg, self.st.pad);
        let best = self.best_inside(plot, px);
        let outside_at =
            |plot: &Rect| Rect::new(plot.x1 + pad, plot.y0, plot.x1 + pad + lg.w, plot.y0 + lg.h);
        if best.0 > 0 && lg.h <= plot.h() {
            match self.forced {
                // The aligned axes of a grid leave exactly the room the natural layout
                // made (`cell.x1 - pad - lg.w - pad`): compared within half a pixel, as
                // the alignment's sums round.
                Some(_) if cell.x1 - pad - plot.x1 >= lg.w + pad - 0.5 => {
                    return Ok((Some(outside_at(plot)), 0));
                }
                None if lg.w + pad < 0.4 * plot.w() => {
                    plot.x1 = cell.x1 - pad - lg.w - pad;
                    too_small(plot)?;
                    *px = self.ranges.pixels(self.p, plot, self.st);
                    return Ok((Some(outside_at(plot)), 0));
                }
                _ => {}
            }
        }
        // Inside, even if it hides data (or does not quite fit).
        let (x, y) = best.1;
        Ok((Some(Rect::new(x, y, x + lg.w, y + lg.h)), best.0))
    }
}
