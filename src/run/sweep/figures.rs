//! The sweep's figures: Fig. 15 (the oscillations and the contact force against the swept
//! key) and the creep curve of a creepage sweep, with its table.

use super::*;

/// Fig. 15's upper panel: the oscillations of the contact force per turn against the
/// swept values `xs` (peaks counted, the bounce rolling and held, the strongest locked
/// component).
pub(super) fn oscillations_panel(key: &str, points: &[SweepPoint], xs: &[f64]) -> Panel {
    let osc: Vec<f64> = points
        .iter()
        .map(|p| {
            let v: Vec<f64> = p.summary["oscillations_per_turn"]
                .as_array()
                .map(|a| a.iter().skip(1).filter_map(|x| x.as_f64()).collect())
                .unwrap_or_default();
            if v.is_empty() {
                f64::NAN
            } else {
                v.iter().sum::<f64>() / v.len() as f64
            }
        })
        .collect();
    let num = |p: &SweepPoint, k: &str| p.summary[k].as_f64().unwrap_or(f64::NAN);
    // The fixed-frequency component (the bounce), counted per turn.
    let fixed: Vec<f64> = points
        .iter()
        .map(|p| num(p, "fixed_frequency_cycles_per_turn"))
        .collect();
    // The bounce computed with the contact held, as cycles per turn: f_b 2 pi / omega.
    let held: Vec<f64> = points
        .iter()
        .map(|p| num(p, "bounce_frequency_hz") * 2.0 * std::f64::consts::PI / num(p, "omega"))
        .collect();
    // The strongest component locked to the rotation.
    let locked: Vec<f64> = points
        .iter()
        .map(|p| {
            p.summary["spectral_components"]
                .as_array()
                .and_then(|cs| cs.iter().find(|c| c["kind"]["type"] == "locked"))
                .and_then(|c| c["kind"]["cycles_per_turn"].as_f64())
                .unwrap_or(f64::NAN)
        })
        .collect();
    let (xs, x_label) = sweep_axis(key, points, xs);
    let xs = &xs[..];
    let mut p1 = Panel::new(
        "Oscillations of the contact force per turn (Fig. 15)",
        x_label,
        "cycles per turn",
    );
    // A component found at some speeds only is drawn as points, not as a broken line,
    // and the note says where it is missing.
    let found = |v: &[f64]| v.iter().filter(|x| x.is_finite()).count();
    let style_of = |v: &[f64]| {
        if found(v) == v.len() {
            SeriesStyle::LineMarkers
        } else {
            SeriesStyle::Markers
        }
    };
    let mut missing = Vec::new();
    for (what, v) in [
        (
            "the bounce rolling (fixed_frequency_cycles_per_turn)",
            &fixed,
        ),
        ("a component locked to the rotation", &locked),
    ] {
        if found(v) < v.len() {
            missing.push(format!("{what} at {} of {} points", found(v), v.len()));
        }
    }
    if !missing.is_empty() {
        p1.note = format!(
            "Found: {}; at the other points the contact force's spectrum has no such \
             component above the classification's threshold (null in summary.json), so \
             those series are drawn as points.",
            missing.join(", ")
        );
    }
    let (fixed_style, locked_style) = (style_of(&fixed), style_of(&locked));
    p1.series.push(Series::new(
        "peaks counted (the paper's rule, mean of turns 2..)",
        xs.to_vec(),
        osc,
        SeriesStyle::LineMarkers,
    ));
    p1.series.push(Series::new(
        "fixed-frequency component (bounce), rolling",
        xs.to_vec(),
        fixed,
        fixed_style,
    ));
    p1.series.push(Series::new(
        "bounce with the contact held, f_b 2 pi / omega",
        xs.to_vec(),
        held,
        SeriesStyle::Line,
    ));
    p1.series.push(Series::new(
        "strongest component locked to the rotation",
        xs.to_vec(),
        locked,
        locked_style,
    ));
    p1
}

/// The x axis of the wheel's sweep figure: the speed in km/h (with the spin's range in
/// rad/s) for a sweep of `rolling.omega`, else the swept values under the key's name.
pub(super) fn sweep_axis(key: &str, points: &[SweepPoint], xs: &[f64]) -> (Vec<f64>, String) {
    let kmh: Vec<f64> = points
        .iter()
        .map(|p| p.summary["speed_km_h"].as_f64().unwrap_or(f64::NAN))
        .collect();
    if key == "rolling.omega" && kmh.iter().all(|v| v.is_finite()) {
        let (lo, hi) = xs
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
                (a.min(x), b.max(x))
            });
        (
            kmh,
            format!("rolling speed [km/h] (spin omega = {lo} ... {hi} rad/s, rolling.omega)"),
        )
    } else {
        (xs.to_vec(), axis_label(key))
    }
}

/// The swept key with its unit, for an axis.
pub(super) fn axis_label(key: &str) -> String {
    match key {
        "rolling.omega" => format!("{key} [rad/s]"),
        "rolling.speed_km_h" => format!("{key} [km/h]"),
        _ => key.to_string(),
    }
}

/// Fig. 15's lower panel: the maximal contact force over the turns against the swept
/// values `xs`, with the mean and the minimum beside it.
pub(super) fn force_panel(key: &str, points: &[SweepPoint], xs: &[f64]) -> Panel {
    let force = |k: &str| -> Vec<f64> {
        points
            .iter()
            .map(|p| p.summary[k].as_f64().unwrap_or(f64::NAN))
            .collect()
    };
    // The maximal force with the mean and the minimum beside it, so that its change with
    // the speed reads against the force itself.
    let (xs, x_label) = sweep_axis(key, points, xs);
    let xs = &xs[..];
    let mut p2 = Panel::new(
        "Contact force over the turns: maximum, mean and minimum",
        x_label,
        "contact force [N]",
    );
    for (label, k) in [
        ("max over the turns", "max_contact_force"),
        ("mean", "mean_contact_force"),
        ("min over the turns", "min_contact_force"),
    ] {
        p2.series.push(Series::new(
            label,
            xs.to_vec(),
            force(k),
            SeriesStyle::LineMarkers,
        ));
    }
    p2
}

/// The creep curve of a creepage sweep (`creep_curve.png`, `creep_curve.csv`): the traction
/// ratio `Q / (mu P)` of steady rolling (`traction.traction_ratio_steady`, the start-up
/// transient extrapolated) against the creepage, with Carter's curve
/// ([`crate::kinds::wheel::run::traction::carter_traction_ratio`], the Hertz half-width of the mean
/// normal force) twice: as it stands, and shifted to the measured free-rolling creepage
/// `xi0` (where `Q` crosses zero, linearly interpolated), which an elastic wheel on a rigid
/// base has and Carter's elastically similar bodies do not. The CSV gives every creepage
/// and `xi0` in both references: `creepage` on the rolling radius `rho = R_s - d` (the
/// scenario's `rolling.creepage`), `creepage_undeformed` on the undeformed radius `R_s`
/// (Carter's, Kalker's and the half-space codes': their rigid velocity is `omega R`).
pub(super) fn creep_curve(
    out: &Path,
    points: &[SweepPoint],
    xs: &[f64],
    mark: &dyn Fn(&mut Panel),
) -> Result<Vec<PathBuf>, SweepError> {
    use crate::analysis::reference_curve::ReferenceCurve;
    use crate::kinds::wheel::run::traction::carter_traction_ratio;
    let num = traction_figure;
    let mut pts: Vec<(f64, f64, f64, f64)> = points
        .iter()
        .zip(xs)
        .map(|(p, &x)| {
            (
                x,
                steady_traction_ratio(p),
                num(p, "friction"),
                num(p, "hertz_half_width"),
            )
        })
        .collect();
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    let radius = points.first().map_or(f64::NAN, |p| num(p, "radius"));
    let xi0 = free_rolling_creepage(&pts.iter().map(|p| (p.0, p.1)).collect::<Vec<_>>());
    // Carter with the mean half-width of the sweep (it changes little with the creepage).
    let n = pts.len().max(1) as f64;
    let (mu, a) = (
        pts.iter().map(|p| p.2).sum::<f64>() / n,
        pts.iter().map(|p| p.3).sum::<f64>() / n,
    );
    let (lo, hi) = (pts[0].0, pts[pts.len() - 1].0);
    let fine: Vec<f64> = (0..=400)
        .map(|i| lo + (hi - lo) * i as f64 / 400.0)
        .collect();
    let uncoupled = points.iter().any(|p| {
        p.summary
            .pointer("/traction/coupling")
            .and_then(|v| v.as_str())
            == Some("uncoupled")
    });
    let mut panel = Panel::new(
        format!(
            "Creep curve{}: mu = {}, Hertz half-width a = {} mm, R = {} m",
            if uncoupled {
                " (normal and tangential problems uncoupled)"
            } else {
                ""
            },
            crate::output::plot::sig(mu, 3),
            crate::output::plot::sig(a * 1e3, 3),
            crate::output::plot::sig(radius, 3)
        ),
        "creepage xi = (omega rho - V) / (omega rho)",
        "Q / (mu P)",
    );
    panel.series.push(Series::new(
        "softway (steady rolling)",
        pts.iter().map(|p| p.0).collect(),
        pts.iter().map(|p| p.1).collect(),
        SeriesStyle::LineMarkers,
    ));
    panel.series.push(Series::new(
        "Carter (elastically similar bodies)",
        fine.clone(),
        fine.iter()
            .map(|&x| carter_traction_ratio(x, mu, a, radius))
            .collect(),
        SeriesStyle::Dashed,
    ));
    if let Some(x0) = xi0 {
        panel.series.push(Series::new(
            format!(
                "Carter shifted to the free-rolling creepage xi0 = {}",
                crate::output::plot::sig(x0, 3)
            ),
            fine.clone(),
            fine.iter()
                .map(|&x| carter_traction_ratio(x - x0, mu, a, radius))
                .collect(),
            SeriesStyle::Line,
        ));
    }
    // Another code's curve (`traction.reference`, in mu a / R on the undeformed radius),
    // drawn on this figure's creepage (on rho) through the points' mean rho / R_s.
    let reference = points
        .iter()
        .find_map(|p| ReferenceCurve::from_summary(&p.summary));
    let rho_over_r = {
        let k: Vec<f64> = points
            .iter()
            .zip(xs)
            .map(|(p, &x)| (1.0 - num(p, "creepage_undeformed")) / (1.0 - x))
            .filter(|k| k.is_finite())
            .collect();
        k.iter().sum::<f64>() / k.len().max(1) as f64
    };
    let unit = mu * a / radius;
    let to_rho = |x: f64| 1.0 - (1.0 - x * unit) / rho_over_r;
    if let Some(rc) = &reference {
        panel.series.push(reference_series(rc, (lo, hi), to_rho));
    }
    panel.hlines = vec![(1.0, "full slip, Q = mu P".into()), (-1.0, String::new())];
    panel.y_range = Some((-1.15, 1.15));
    mark(&mut panel);
    let png = out.join("creep_curve.png");
    panels(&png, &[panel], 1, 1, (1100, 700)).map_err(|e| RunError::output(&png, e))?;
    // The creepage referred to the undeformed radius (the half-space codes' and Carter's
    // reference) beside the one given (referred to the rolling radius rho = R_s - d).
    let mut on_r: Vec<(f64, f64)> = points
        .iter()
        .zip(xs)
        .map(|(p, &x)| {
            let xr = num(p, "creepage_undeformed");
            (x, if xr.is_finite() { xr } else { x })
        })
        .collect();
    on_r.sort_by(|a, b| a.0.total_cmp(&b.0));
    let xi0_r = free_rolling_creepage(
        &on_r
            .iter()
            .zip(&pts)
            .map(|(r, p)| (r.1, p.1))
            .collect::<Vec<_>>(),
    );
    let mut csv = crate::output::csv::record([
        "creepage",
        "creepage_undeformed",
        "traction_ratio",
        "carter",
        "carter_shifted",
        "free_rolling_creepage",
        "free_rolling_creepage_undeformed",
        "reference",
    ]);
    for (p, r) in pts.iter().zip(&on_r) {
        let shifted = xi0.map_or(f64::NAN, |x0| {
            carter_traction_ratio(p.0 - x0, mu, a, radius)
        });
        crate::output::csv::push_record(
            &mut csv,
            [
                p.0,
                r.1,
                p.1,
                carter_traction_ratio(p.0, mu, a, radius),
                shifted,
                xi0.unwrap_or(f64::NAN),
                xi0_r.unwrap_or(f64::NAN),
                reference
                    .as_ref()
                    .and_then(|rc| rc.at(r.1 / unit))
                    .unwrap_or(f64::NAN),
            ]
            .map(|x| format!("{x:e}")),
        );
    }
    let f = out.join("creep_curve.csv");
    write_atomic(&f, csv.as_bytes()).map_err(|e| RunError::output(&f, e))?;
    Ok(vec![png, f])
}

/// The reference curve `rc` as a dashed series over the sweep's creepages `lo..hi` and a
/// quarter of their span beyond, its creepages (`mu a / R`) mapped by `to_x` onto the
/// figure's axis.
pub(super) fn reference_series(
    rc: &crate::analysis::reference_curve::ReferenceCurve,
    (lo, hi): (f64, f64),
    to_x: impl Fn(f64) -> f64,
) -> Series {
    let m = 0.25 * (hi - lo);
    let shown: Vec<(f64, f64)> = rc
        .points
        .iter()
        .map(|p| (to_x(p.0), p.1))
        .filter(|p| p.0 >= lo - m && p.0 <= hi + m)
        .collect();
    Series::new(
        format!("reference: {}", rc.name()),
        shown.iter().map(|p| p.0).collect(),
        shown.iter().map(|p| p.1).collect(),
        SeriesStyle::Dashed,
    )
}

/// The figure `k` of a point's `traction` block (NaN where it has none).
pub(crate) fn traction_figure(p: &SweepPoint, k: &str) -> f64 {
    p.summary
        .pointer(&format!("/traction/{k}"))
        .and_then(|v| v.as_f64())
        .unwrap_or(f64::NAN)
}

/// A point's steady `Q / (mu P)` (`traction_ratio_steady`; the window's mean
/// `traction_ratio` in a summary written before it existed).
pub(crate) fn steady_traction_ratio(p: &SweepPoint) -> f64 {
    let steady = traction_figure(p, "traction_ratio_steady");
    if steady.is_finite() {
        steady
    } else {
        traction_figure(p, "traction_ratio")
    }
}

/// The creepage where the traction ratio crosses zero, by linear interpolation between the
/// two neighbouring points of `(creepage, ratio)` sorted by creepage; `None` without a sign
/// change.
pub fn free_rolling_creepage(pts: &[(f64, f64)]) -> Option<f64> {
    pts.windows(2).find_map(|w| {
        let ((x0, y0), (x1, y1)) = (w[0], w[1]);
        (y0 <= 0.0 && y1 > 0.0).then(|| x0 - y0 * (x1 - x0) / (y1 - y0))
    })
}
