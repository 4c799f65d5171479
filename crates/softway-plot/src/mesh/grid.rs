//! The layout that the vector fields and the mode shapes share: panels of one extent in a
//! grid, with shared axis labels, one colour bar beside the grid and the figure's note
//! under it.

use super::*;

/// Columns and rows of a grid of `n` panels: `cols` columns (at most `n`), or about a
/// square for 0.
pub(super) fn grid_shape(n: usize, cols: usize) -> (usize, usize) {
    let cols = if cols == 0 {
        (n as f64).sqrt().ceil() as usize
    } else {
        cols.min(n)
    };
    (cols, n.div_ceil(cols))
}

/// The box holding every box given (`[x0, x1, y0, y1]`), `None` for none.
pub(super) fn bbox_union(boxes: impl IntoIterator<Item = [f64; 4]>) -> Option<[f64; 4]> {
    let mut bb0: Option<[f64; 4]> = None;
    for b in boxes {
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
    bb0
}

/// A figure's note fitted to the canvas (at most three lines): its lines, their size, and
/// the height it takes at the bottom (0 without a note).
pub(super) struct Note {
    pub(super) lines: Vec<String>,
    pub(super) size: f64,
    pub(super) height: f64,
    empty: bool,
}

impl Note {
    pub(super) fn fit(text: &str, fig: &Fig, st: &Sty) -> Self {
        let (lines, size) = fit_text(text, 0.85 * st.fs, fig.w - 2.0 * st.pad, 3);
        let height = if text.is_empty() {
            0.0
        } else {
            lines.len() as f64 * 1.15 * (CAP + DESC) * size + 0.5 * st.pad
        };
        Note {
            lines,
            size,
            height,
            empty: text.is_empty(),
        }
    }

    /// Draws the note at the bottom of the canvas, if there is one.
    pub(super) fn draw(&self, area: &Area, fig: &Fig, st: &Sty) -> Res<()> {
        if self.empty {
            return Ok(());
        }
        draw_note(area, &self.lines, self.size, fig, st)
    }
}

/// The band under a mesh figure's plot: the ticks, their labels, the x axis's label and
/// the note.
pub(super) fn bottom_band(st: &Sty, note: &Note) -> f64 {
    let (fs, fl, pad, tick) = (st.fs, st.fl, st.pad, st.tick);
    tick + 0.6 * pad + CAP * fs + pad + (CAP + DESC) * fl + pad + note.height
}

/// The width left of a plot for the y axis's tick labels of width `label_w` and its label.
pub(super) fn left_band(st: &Sty, label_w: f64) -> f64 {
    let (fl, pad, tick) = (st.fl, st.pad, st.tick);
    pad + (CAP + DESC) * fl + 0.8 * pad + label_w + 0.6 * pad + tick
}

/// Panels of one extent in a grid: where the grid and its panels are and the shared ticks.
pub(super) struct Grid {
    pub(super) cols: usize,
    /// The band above each panel for its title.
    pub(super) title_band: f64,
    pub(super) hgap: f64,
    vgap: f64,
    pub(super) x0: f64,
    pub(super) y0: f64,
    /// A panel's width and height.
    pub(super) pw: f64,
    pub(super) ph: f64,
    /// The grid's width and height (the title bands included).
    pub(super) gw: f64,
    pub(super) gh: f64,
    pub(super) xt: Ticks,
    pub(super) yt: Ticks,
    /// The colour bar's ticks over the values `vr`.
    pub(super) ct: Ticks,
}

/// What a [`Grid`] is fitted to.
pub(super) struct GridSpec<'a> {
    pub(super) cols: usize,
    pub(super) rows: usize,
    /// The panels' extent `[x0, x1, y0, y1]`.
    pub(super) bb: [f64; 4],
    /// The colour bar's range and label.
    pub(super) vr: (f64, f64),
    pub(super) cb_label: &'a str,
    pub(super) title_band: f64,
    pub(super) hgap: f64,
    /// What the panels are, for the error of a canvas too small ("shapes", "frames").
    pub(super) what: &'a str,
}

impl Grid {
    /// The largest panels that fit the canvas beside the y axis's labels and the colour
    /// bar, above the bottom band, centred (the bands' widths found again from the ticks
    /// the panels get, up to three times).
    pub(super) fn fit(fig: &Fig, st: &Sty, g: &GridSpec, note: &Note) -> Res<Grid> {
        let (fs, pad) = (st.fs, st.pad);
        let (cols, rows, bb, vr) = (g.cols, g.rows, g.bb, g.vr);
        let (dx, dy) = (bb[1] - bb[0], bb[3] - bb[2]);
        let (title_band, hgap) = (g.title_band, g.hgap);
        let vgap = 1.2 * pad;
        let top = pad;
        let bottom = bottom_band(st, note);
        let mut left_w = left_band(st, 3.0 * fs);
        let mut cb_w = 6.0 * fs;
        let mut layout = None;
        for _ in 0..3 {
            let avail_w = fig.w - left_w - cb_w - pad - (cols - 1) as f64 * hgap;
            let avail_h =
                fig.h - top - bottom - rows as f64 * title_band - (rows - 1) as f64 * vgap;
            if avail_w <= 20.0 * cols as f64 || avail_h <= 20.0 * rows as f64 {
                return Err(Fail::Draw(format!(
                    "the image is too small for this many {}",
                    g.what
                )));
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
            let new_left = left_band(st, yt.max_label_w(fs));
            let new_cb = colorbar_width(&ct, g.cb_label, st);
            let done = (new_left - left_w).abs() < 1.0 && (new_cb - cb_w).abs() < 1.0;
            left_w = new_left;
            cb_w = new_cb;
            layout = Some(Grid {
                cols,
                title_band,
                hgap,
                vgap,
                x0,
                y0,
                pw,
                ph,
                gw,
                gh,
                xt,
                yt,
                ct,
            });
            if done {
                break;
            }
        }
        layout.ok_or_else(|| Fail::Draw("layout failed".into()))
    }

    /// Panel `i`'s view of the extent `bb` (row by row), and the top of its title band's
    /// bottom: the panel's top.
    pub(super) fn view(&self, i: usize, bb: [f64; 4], unit: f64) -> MeshView {
        let (r, c) = (i / self.cols, i % self.cols);
        let px0 = self.x0 + c as f64 * (self.pw + self.hgap);
        let py0 = self.y0 + r as f64 * (self.title_band + self.ph + self.vgap) + self.title_band;
        MeshView {
            bb,
            r: Rect::new(px0, py0, px0 + self.pw, py0 + self.ph),
            unit,
        }
    }

    /// The axes of panel `i` of `n` with its `view`: the x ticks' labels under the bottom
    /// panel of each column, the y ticks' beside the first column.
    pub(super) fn draw_axes(
        &self,
        area: &Area,
        view: &MeshView,
        (i, n): (usize, usize),
        st: &Sty,
    ) -> Res<()> {
        let bottom_of_column = i + self.cols >= n;
        draw_mesh_axes(
            area,
            view,
            &self.xt,
            &self.yt,
            bottom_of_column,
            i % self.cols == 0,
            st,
        )
    }

    /// The grid's bottom (the last row's panels' bottom).
    pub(super) fn bottom(&self) -> f64 {
        self.y0 + self.gh
    }

    /// The shared axis labels `xl` (under the grid) and `yl` (left of it); the colour
    /// bar's rectangle beside the grid's panels.
    pub(super) fn draw_labels(&self, area: &Area, (xl, yl): (&str, &str), st: &Sty) -> Res<Rect> {
        let (fs, fl, pad, tick) = (st.fs, st.fl, st.pad, st.tick);
        let (x0, y0, gw, gh, title_band) = (self.x0, self.y0, self.gw, self.gh, self.title_band);
        let grid_bottom = self.bottom();
        draw_text(
            area,
            xl,
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
        let ylx = x0 - tick - 0.6 * pad - self.yt.max_label_w(fs) - 0.8 * pad - (CAP + DESC) * fl;
        draw_text(
            area,
            yl,
            (ylx, y0 + title_band + 0.5 * (gh - title_band)),
            fl,
            HA::Center,
            VA::Top,
            true,
            TEXT,
        )?;
        Ok(Rect::new(
            x0 + gw + 1.2 * fs,
            y0 + title_band,
            x0 + gw + 2.3 * fs,
            grid_bottom,
        ))
    }
}
