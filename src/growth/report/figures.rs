//! The growth study's figures: `spectrum.png`, `growth_rate.png`, `profile.png`,
//! `orders.png`, each drawn from one [`FigureInputs`].

use super::*;

pub(super) fn plot_all(
    out: &Path,
    state: &StudyState,
    s: &GrowthSummary,
    f: &Figures,
) -> Result<Vec<PathBuf>, GrowthError> {
    let lam_mm: Vec<f64> = f.bands.iter().map(|b| b.centre * 1e3).collect();
    let held = held_bands(f);
    let inputs = FigureInputs {
        out,
        state,
        s,
        f,
        lam_mm: &lam_mm,
        held: &held,
    };
    let mut files = Vec::new();
    for figure in [spectrum_png, growth_rate_png, profile_png, orders_png] {
        files.extend(figure(&inputs)?);
    }
    Ok(files)
}

/// What each of the study's figures is drawn from.
#[derive(Clone, Copy)]
struct FigureInputs<'a> {
    /// The study's folder.
    out: &'a Path,
    /// The study.
    state: &'a StudyState,
    /// Its summary.
    s: &'a GrowthSummary,
    /// Its bands' and orders' figures.
    f: &'a Figures,
    /// The bands' centre wavelengths, mm.
    lam_mm: &'a [f64],
    /// Whether each band holds a level ([`held_bands`]).
    held: &'a [bool],
}

/// `spectrum.png` (its section's comment).
fn spectrum_png(figure: &FigureInputs) -> Result<Vec<PathBuf>, GrowthError> {
    let FigureInputs {
        out,
        s,
        f,
        lam_mm,
        held,
        ..
    } = *figure;
    let mut files = Vec::new();
    let png = |name: &str| out.join(name);
    let level = |q: usize| -> Vec<f64> {
        f.levels[q]
            .iter()
            .zip(held)
            .map(|(&l, &h)| if h { l } else { f64::NAN })
            .collect()
    };
    // spectrum.png: the band levels, initial, a few passes between and the last; under
    // them each one's change since the initial profile (issue 48: the passes' levels lie
    // within a fraction of a dB of each other, on top of each other on a level axis).
    let mut p = Panel::new(
        format!(
            "Roughness spectrum over {} passes ({} real passes)",
            s.passes,
            sig(s.real_passes, 3)
        ),
        "wavelength [mm] (one-third-octave band centres)",
        "level [dB re 1 um]",
    );
    p.x_log = true;
    let mut pd = Panel::new(
        "Change of each band's level since the initial profile",
        "wavelength [mm] (one-third-octave band centres)",
        "level - initial level [dB]",
    );
    pd.x_log = true;
    let last = f.levels.len() - 1;
    let mut shown: Vec<usize> = vec![0];
    for q in [last / 3, 2 * last / 3, last] {
        if !shown.contains(&q) {
            shown.push(q);
        }
    }
    let initial = level(0);
    for &q in &shown {
        let l = level(q);
        let label = format!(
            "after {q} passes ({} real)",
            sig(q as f64 * s.passes_per_pass, 3)
        );
        pd.series.push(Series::new(
            label.clone(),
            lam_mm.to_vec(),
            l.iter().zip(&initial).map(|(a, b)| a - b).collect(),
            SeriesStyle::LineMarkers,
        ));
        p.series.push(Series::new(
            label,
            lam_mm.to_vec(),
            l,
            SeriesStyle::LineMarkers,
        ));
    }
    pd.hlines.push((0.0, String::new()));
    let longest_band = lam_mm.iter().copied().fold(0.0, f64::max);
    if !s.periodic && longest_band > s.length_m / OPEN_MIN_PERIODS * 1e3 {
        pd.vspans.push((
            s.length_m / OPEN_MIN_PERIODS * 1e3,
            longest_band * 1.12,
            format!("under {OPEN_MIN_PERIODS:.0} periods in the record: the ends' levels"),
        ));
    }
    let empty = held.iter().filter(|h| !**h).count();
    pd.note = format!(
        "V = {} m/s; frequency = V / wavelength. Wear smoothed over {} mm (triangle of twice {} \
         samples), cut below {} mm.{}",
        sig(s.speed_m_s, 3),
        sig(s.smoothing_m * 1e3, 3),
        s.smoothing_samples,
        sig(s.cutoff_m * 1e3, 3),
        if empty > 0 {
            format!(
                " {empty} band(s) the initial profile leaves empty (over 180 dB below its \
                 loudest) are not drawn."
            )
        } else {
            String::new()
        }
    );
    let path = png("spectrum.png");
    // No band the initial profile holds (a study from a smooth surface): nothing to draw,
    // as growth_rate.png (it failed the study after its tables were written).
    if !held.iter().any(|h| *h) {
        return Ok(files);
    }
    panels(&path, &[p, pd], 2, 1, (1200, 1000)).map_err(|e| GrowthError::output(&path, e))?;
    files.push(path);
    Ok(files)
}

/// `growth_rate.png`, when a rate is finite.
fn growth_rate_png(figure: &FigureInputs) -> Result<Vec<PathBuf>, GrowthError> {
    let FigureInputs { out, s, lam_mm, .. } = *figure;
    let mut files = Vec::new();
    let png = |name: &str| out.join(name);
    // growth_rate.png: the rate per band (and per order) against wavelength, when there is
    // one (a study from a smooth surface, `roughness = "none"`, has no level to grow from
    // until its profile has one: its rates are not finite).
    let finite_rate = s.bands.iter().any(|b| b.rate_db_per_1e5.is_finite())
        || s.orders.iter().any(|o| o.rate_db_per_1e5.is_finite());
    if s.passes >= 1 && finite_rate {
        let mut p = Panel::new(
            "Growth rate against wavelength",
            "wavelength [mm]",
            "growth rate [dB per 1e5 real passes]",
        );
        p.x_log = true;
        // On an open profile a band longer than the record's eighth is the ends' (issue
        // 48: the 5 m band of a 4.8 m rail set the axis): drawn apart, left out of the
        // axis range, its value given when off the axis.
        let few = if s.periodic {
            f64::INFINITY
        } else {
            s.length_m / OPEN_MIN_PERIODS * 1e3
        };
        let rate = |b: &BandFigures| b.rate_db_per_1e5;
        type Points = Vec<(f64, f64)>;
        let (reliable, unreliable): (Points, Points) = s
            .bands
            .iter()
            .map(|b| (b.centre_wavelength_m * 1e3, rate(b)))
            .partition(|(l, _)| *l <= few);
        let (rx, ry): (Vec<f64>, Vec<f64>) = reliable.iter().copied().unzip();
        p.series.push(Series::new(
            "one-third-octave bands",
            rx,
            ry.clone(),
            SeriesStyle::LineMarkers,
        ));
        let mut range_of: Vec<f64> = ry.iter().copied().filter(|r| r.is_finite()).collect();
        if !s.orders.is_empty() {
            let oy: Vec<f64> = s.orders.iter().map(|o| o.rate_db_per_1e5).collect();
            range_of.extend(oy.iter().copied().filter(|r| r.is_finite()));
            p.series.push(Series::new(
                "polygon orders",
                s.orders.iter().map(|o| o.wavelength_m * 1e3).collect(),
                oy,
                SeriesStyle::Markers,
            ));
        }
        let mut off_scale = Vec::new();
        if !unreliable.is_empty() {
            let lo = range_of.iter().copied().fold(0.0, f64::min);
            let hi = range_of.iter().copied().fold(0.0, f64::max);
            let m = 0.08 * (hi - lo).max(1e-9);
            let (lo, hi) = (lo - m, hi + m);
            p.y_range = Some((lo, hi));
            for &(l, r) in &unreliable {
                if r.is_finite() && !(lo..=hi).contains(&r) {
                    off_scale.push(format!("{} mm: {}", sig(l, 3), sig(r, 3)));
                }
            }
            let (ux, uy): (Vec<f64>, Vec<f64>) = unreliable.into_iter().unzip();
            p.series.push(Series::new(
                "the bands there (not counted; off the axis: see the note)",
                ux,
                uy,
                SeriesStyle::Markers,
            ));
        }
        p.hlines.push((0.0, String::new()));
        if let Some(b) = &s.fastest_band {
            p.vlines.push((
                b.centre_wavelength_m * 1e3,
                format!(
                    "{}: the {} mm band ({} Hz)",
                    if b.rate_db_per_1e5 > 0.0 {
                        "fastest growth"
                    } else {
                        "slowest decay (no band grows)"
                    },
                    sig(b.centre_wavelength_m * 1e3, 4),
                    sig(b.frequency_hz, 3)
                ),
            ));
        }
        if s.smoothing_m > 0.0 {
            p.vlines
                .push((s.smoothing_m * 1e3, "smoothing width".into()));
        }
        if s.cutoff_m > 0.0 {
            p.vlines
                .push((s.cutoff_m * 1e3, "cutoff (wear removed below)".into()));
        }
        let longest_band = lam_mm.iter().copied().fold(0.0, f64::max);
        if longest_band > few {
            p.vspans.push((
                few,
                longest_band * 1.12,
                format!("under {OPEN_MIN_PERIODS:.0} periods in the record: the ends' rates"),
            ));
        }
        p.note = format!(
            "Least-squares slope of each level over {} passes of {} real passes each.{}",
            s.passes,
            sig(s.passes_per_pass, 3),
            if off_scale.is_empty() {
                String::new()
            } else {
                format!(" Off the axis (the ends' rates): {}.", off_scale.join("; "))
            }
        );
        let path = png("growth_rate.png");
        line_plot(&path, &p, (1200, 700)).map_err(|e| GrowthError::output(&path, e))?;
        files.push(path);
    }
    Ok(files)
}

/// `profile.png`.
fn profile_png(figure: &FigureInputs) -> Result<Vec<PathBuf>, GrowthError> {
    let FigureInputs { out, state, s, .. } = *figure;
    let mut files = Vec::new();
    let png = |name: &str| out.join(name);
    // profile.png: the initial and the current profile, and under them what changed: the
    // change since the initial profile and the last pass's wear step (the wear the book,
    // docs/src/growth.md, says the figure shows).
    let profiles = state.profiles();
    let length = state.n as f64 * state.dx.0[0];
    let (scale, unit) = if length > 2.0 {
        (1.0, "m")
    } else {
        (1e3, "mm")
    };
    let x: Vec<f64> = (0..state.n)
        .map(|i| (state.x0.0[0] + i as f64 * state.dx.0[0]) * scale)
        .collect();
    let x_label = format!("x [{unit}] (rolling coordinate)");
    let mut p = Panel::new(
        "Surface profile (mean removed; the uniform loss is reported apart)",
        x_label.clone(),
        "z [um]",
    );
    let (z0, zl) = (profiles[0], profiles[profiles.len() - 1]);
    p.series.push(Series::new(
        "initial",
        x.clone(),
        z0.iter().map(|z| z * 1e6).collect(),
        SeriesStyle::Line,
    ));
    p.series.push(Series::new(
        format!("after {} passes", s.passes),
        x.clone(),
        zl.iter().map(|z| z * 1e6).collect(),
        SeriesStyle::Line,
    ));
    p.note = format!(
        "RMS {} um -> {} um; uniform loss {} um over {} real passes.",
        sig(s.rms_initial_m * 1e6, 4),
        sig(s.rms_final_m * 1e6, 4),
        sig(s.uniform_loss_m * 1e6, 3),
        sig(s.real_passes, 3)
    );
    let mut pw = Panel::new("What the passes changed", x_label, "profile change [um]");
    pw.series.push(Series::new(
        "since the initial profile, z - z0",
        x.clone(),
        zl.iter().zip(z0).map(|(a, b)| (a - b) * 1e6).collect(),
        SeriesStyle::Line,
    ));
    if let Some(last_pass) = state.passes.last() {
        let w = &last_pass.wear.0;
        let mean = if w.is_empty() {
            0.0
        } else {
            w.iter().sum::<f64>() / w.len() as f64
        };
        pw.series.push(Series::new(
            format!(
                "the last pass's wear step, -N_w (w - mean w), N_w = {}",
                sig(s.passes_per_pass, 3)
            ),
            x,
            w.iter()
                .map(|w| -s.passes_per_pass * (w - mean) * 1e6)
                .collect(),
            SeriesStyle::Line,
        ));
    }
    pw.hlines.push((0.0, String::new()));
    pw.note = "w: the depth one simulated pass wears (smoothed, cut below the cutoff, the \
               reference's pattern taken off), N_w the real passes it stands for; z - z0 \
               also holds any plastic flow."
        .into();
    let path = png("profile.png");
    panels(&path, &[p, pw], 2, 1, (1200, 900)).map_err(|e| GrowthError::output(&path, e))?;
    files.push(path);
    Ok(files)
}

/// `orders.png`, when an order's rate is finite.
fn orders_png(figure: &FigureInputs) -> Result<Vec<PathBuf>, GrowthError> {
    let FigureInputs { out, s, .. } = *figure;
    let mut files = Vec::new();
    let png = |name: &str| out.join(name);
    // orders.png
    let finite_order = s
        .orders
        .iter()
        .any(|o| o.rate_db_per_1e5.is_finite() || o.rate_last_db_per_1e5.is_finite());
    if finite_order && s.passes >= 1 {
        let mut p = Panel::new(
            "Polygon orders: growth rate",
            "order (harmonics per revolution)",
            "growth rate [dB per 1e5 real passes]",
        );
        p.series.push(Series::new(
            "over all passes",
            s.orders.iter().map(|o| o.order as f64).collect(),
            s.orders.iter().map(|o| o.rate_db_per_1e5).collect(),
            SeriesStyle::LineMarkers,
        ));
        p.series.push(Series::new(
            "last pass",
            s.orders.iter().map(|o| o.order as f64).collect(),
            s.orders.iter().map(|o| o.rate_last_db_per_1e5).collect(),
            SeriesStyle::Dashed,
        ));
        p.hlines.push((0.0, String::new()));
        // Orders shorter than the cutoff are not worn (their rate is 0 by construction).
        let top = s.orders.last().map(|o| o.order as f64).unwrap_or(0.0);
        if s.cutoff_m > 0.0 && s.length_m / s.cutoff_m < top {
            p.vspans.push((
                s.length_m / s.cutoff_m,
                top + 1.0,
                format!(
                    "under the cutoff ({} mm): not worn, rate 0 by construction",
                    sig(s.cutoff_m * 1e3, 3)
                ),
            ));
        }
        if let Some(o) = &s.fastest_order {
            p.vlines.push((
                o.order as f64,
                format!(
                    "{}: order {} ({} mm, {} Hz)",
                    if o.rate_db_per_1e5 > 0.0 {
                        "fastest growth"
                    } else {
                        "slowest decay (no order grows)"
                    },
                    o.order,
                    sig(o.wavelength_m * 1e3, 4),
                    sig(o.frequency_hz, 3)
                ),
            ));
        }
        p.note = format!(
            "Amplitudes by DFT of the rim profile; V = {} m/s.",
            sig(s.speed_m_s, 3)
        );
        let path = png("orders.png");
        line_plot(&path, &p, (1200, 700)).map_err(|e| GrowthError::output(&path, e))?;
        files.push(path);
    }
    Ok(files)
}
