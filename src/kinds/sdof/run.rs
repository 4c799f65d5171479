//! The one-degree-of-freedom oscillator `m x'' + k x = 0` by the scheme of Eqs. (9)-(10),
//! against the exact solution `x = x0 cos(omega t) + v0/omega sin(omega t)`.

use crate::output::plot::{Panel, Series, SeriesStyle};
use crate::run::error::RunError;
use crate::run::options::RunOptions;
use crate::run::results::Results;
use crate::scenario::Scenario;
use crate::time::sdof::{amplification, step};
use serde::Serialize;
use std::path::Path;

/// Key figures of one run.
#[derive(Debug, Clone, Serialize)]
pub struct SdofSummary {
    /// Label.
    pub label: String,
    /// Time step, s.
    pub h: f64,
    /// `alpha`.
    pub alpha: f64,
    /// `gamma`.
    pub gamma: f64,
    /// `omega h`.
    pub omega_h: f64,
    /// Exact period `2 pi / omega`, s.
    pub period_exact: f64,
    /// Period measured from upward zero crossings, s (None: fewer than two crossings).
    pub period_measured: Option<f64>,
    /// Relative period error predicted by the amplification matrix.
    pub period_error_predicted: f64,
    /// Spectral radius per step.
    pub spectral_radius: f64,
    /// Largest `|x - x_exact|` over the run, m.
    pub max_displacement_error: f64,
    /// Energy at the start and at the end, J.
    pub energy_initial: f64,
    /// Energy at the end, J.
    pub energy_final: f64,
    /// Steps.
    pub steps: usize,
}

/// The columns of `history.csv`: `run` (the run's label), then these.
pub const HISTORY: [(&str, &str); 6] = [
    ("t_s", "s"),
    ("x_m", "m"),
    ("v_m_s", "m/s"),
    ("x_exact_m", "m"),
    ("v_exact_m_s", "m/s"),
    ("energy_J", "J"),
];

/// Runs all runs; the history is streamed to `stream` (`history.csv`) when given, else
/// held. The figure (`sdof.png`) is drawn by [`Results::save`].
///
/// # Errors
/// [`RunError`].
pub(crate) fn record(
    sc: &Scenario,
    stream: Option<&Path>,
    opts: &RunOptions,
) -> Result<Results, RunError> {
    let (mut csv, hist) = crate::run::history::keyed_history(sc, stream, &HISTORY)?;
    let at = |e| RunError::output(&hist, e);
    let mut interrupted = false;
    let mut sums = Vec::new();
    let mut px = Panel::new(
        "One degree of freedom: displacement (Eqs. 9-10)",
        "time t [s]",
        "x [m]",
    );
    let mut pe = Panel::new(
        "Error against the exact solution",
        "time t [s]",
        "x - x_exact [m]",
    );
    for (ri, run) in sc.runs.iter().enumerate() {
        let Some(&o) = run.model.get::<crate::scenario::Sdof>() else {
            unreachable!("sdof job on a sdof scenario")
        };
        let w = (o.stiffness / o.mass).sqrt();
        let n = (run.t_end / run.params.h).round() as usize;
        let (mut x, mut v) = (o.x0, o.v0);
        let energy = |x: f64, v: f64| 0.5 * o.mass * v * v + 0.5 * o.stiffness * x * x;
        let exact = |t: f64| {
            (
                o.x0 * (w * t).cos() + o.v0 / w * (w * t).sin(),
                -o.x0 * w * (w * t).sin() + o.v0 * (w * t).cos(),
            )
        };
        let (mut ts, mut xs, mut es) = (Vec::new(), Vec::new(), Vec::new());
        let mut crossings = Vec::new();
        let mut max_err = 0.0f64;
        let mut steps = 0;
        for k in 0..=n {
            let t = k as f64 * run.params.h;
            let (xe, ve) = exact(t);
            max_err = max_err.max((x - xe).abs());
            if k % sc.history_stride == 0 {
                csv.push(ri as u32, &[t, x, v, xe, ve, energy(x, v)])
                    .map_err(at)?;
            }
            ts.push(t);
            xs.push(x);
            es.push(x - xe);
            if k == n || opts.cancel.is_cancelled() {
                interrupted |= k < n;
                break;
            }
            let (x1, v1) = step(o.mass, o.stiffness, 0.0, run.params, x, v);
            if x < 0.0 && x1 >= 0.0 {
                crossings.push(t + run.params.h * x / (x - x1));
            }
            (x, v) = (x1, v1);
            steps += 1;
        }
        let period = (crossings.len() >= 2).then(|| {
            (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64
        });
        let amp = amplification(run.params.alpha, run.params.gamma, w * run.params.h);
        let style = if ri % 2 == 0 {
            SeriesStyle::Line
        } else {
            SeriesStyle::Dashed
        };
        px.series
            .push(Series::new(run.label.clone(), ts.clone(), xs, style));
        pe.series
            .push(Series::new(run.label.clone(), ts, es, style));
        sums.push(SdofSummary {
            label: run.label.clone(),
            h: run.params.h,
            alpha: run.params.alpha,
            gamma: run.params.gamma,
            omega_h: w * run.params.h,
            period_exact: 2.0 * std::f64::consts::PI / w,
            period_measured: period,
            period_error_predicted: amp.period_error,
            spectral_radius: amp.spectral_radius,
            max_displacement_error: max_err,
            energy_initial: energy(o.x0, o.v0),
            energy_final: energy(x, v),
            steps,
        });
        if interrupted {
            break;
        }
    }
    let history = csv.finish().map_err(at)?;
    let mut json = serde_json::json!({
        "scenario": sc.name, "kind": "sdof", "interrupted": interrupted,
        "units": {"time": "s", "length": "m", "energy": "J"}, "runs": sums,
    });
    crate::run::provenance::stamp_provenance(&mut json, sc);
    let mut lines = Vec::new();
    for s in &sums {
        lines.push(format!(
            "{:<12} omega h = {:.4}: period {} s (exact {:.6}, predicted error {:+.3e}), max |x - x_exact| = {:.3e} m, energy {:.6} -> {:.6} J",
            s.label,
            s.omega_h,
            s.period_measured.map(|p| format!("{p:.6}")).unwrap_or_else(|| "-".into()),
            s.period_exact,
            s.period_error_predicted,
            s.max_displacement_error,
            s.energy_initial,
            s.energy_final
        ));
    }
    Ok(Results::with_panels(
        ("sdof", json),
        history,
        lines,
        interrupted,
        sc.plots,
        ("sdof.png", vec![px, pe], (1200, 1100)),
    ))
}
