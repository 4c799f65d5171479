//! Convergence studies: one scenario over a refinement ladder of one key (the mesh, e.g.
//! `wheel.rings` or `bar.elements`, or the step `time.h`), with the observed order of every
//! key figure (`converge.csv`, `converge.md`, `converge.png`).
//!
//! For a figure `F` computed at the rungs `x_0, x_1, ...` of a geometric ladder (constant
//! ratio `r = x_{i+1} / x_i`, refining or coarsening), the successive differences
//! `d_i = F_{i+1} - F_i` of a quantity converging as `F(x) = F* + C e(x)^p` (`e` the mesh
//! size or the step) fall by `r^p` from one pair of rungs to the next, so the observed order
//! at rung `i + 1` is
//! $$p_i = \frac{\ln |d_{i-1} / d_i|}{|\ln r_i|},\qquad r_i = x_{i+1}/x_i,$$
//! and, once `p > 0`, the Richardson estimate of the limit is
//! `F* ~ F_{n} + d_{n-1} / (r^p - 1)` (reported as `extrapolated`). A figure whose
//! differences do not shrink has no order (`-`): it is not converging on this ladder (or
//! sits at round-off). The figures are the summary's numbers: for the wheel the contact force
//! (mean, min, max, ripple max - min), nodes in contact, the bounce frequency and the
//! fixed-frequency cycles per turn, the turn-averaged von Mises maximum, energy, cost; for one-run bar and
//! oscillator scenarios every number of the run.

use super::sweep::{run_ladder, SweepError, SweepPoint};
use super::{Cancel, RunError};
use crate::output::files::write_atomic;
use crate::output::plot::{panels, Panel, Series, SeriesStyle};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The figures of a wheel run that a convergence study reports.
const WHEEL_FIGURES: [&str; 11] = [
    "mean_contact_force",
    "min_contact_force",
    "max_contact_force",
    "mean_nodes_in_contact",
    "bounce_frequency_hz",
    "fixed_frequency_cycles_per_turn",
    "max_von_mises_turn_average_mpa",
    "energy_after_settling",
    "energy_final",
    "time_per_step_us",
    "dofs",
];

/// Figures kept in the tables but not plotted: inputs and costs, not results.
const NOT_PLOTTED: [&str; 10] = [
    "alpha",
    "gamma",
    "h",
    "omega_h",
    "steps",
    "dofs",
    "nodes",
    "triangles",
    "wall_time_s",
    "time_per_step_us",
];

/// One figure along the ladder.
#[derive(Debug, Clone, serde::Serialize)]
pub struct FigureLadder {
    /// The summary key.
    pub name: String,
    /// Its value at each rung (NaN where missing).
    pub values: Vec<f64>,
    /// The observed order at each rung from the third on (`None`: the differences do not
    /// shrink, or a difference is zero).
    pub orders: Vec<Option<f64>>,
    /// The Richardson estimate of the limit from the last three rungs, when the last order
    /// is positive.
    pub extrapolated: Option<f64>,
}

pub use crate::analysis::richardson::{extrapolate, observed_orders};

/// The numeric figures of one summary: the wheel's key figures, or every number of the only
/// run of a bar or oscillator scenario.
fn figures(summary: &serde_json::Value) -> Vec<(String, f64)> {
    if summary["kind"] == "wheel" {
        let get = |k: &str| summary[k].as_f64().unwrap_or(f64::NAN);
        let mut f: Vec<(String, f64)> = WHEEL_FIGURES
            .iter()
            .map(|k| (k.to_string(), get(k)))
            .collect();
        // The ripple of the force over the rolling phase (max - min), N.
        f.insert(
            3,
            (
                "contact_force_ripple".into(),
                get("max_contact_force") - get("min_contact_force"),
            ),
        );
        return f;
    }
    let run = summary["runs"].get(0).unwrap_or(summary);
    let mut out = Vec::new();
    let mut visit = |prefix: &str, o: &serde_json::Map<String, serde_json::Value>| {
        for (k, v) in o {
            if let Some(x) = v.as_f64() {
                out.push((format!("{prefix}{k}"), x));
            }
        }
    };
    if let Some(o) = run.as_object() {
        visit("", o);
        if let Some(e) = run["errors"].as_object() {
            visit("errors.", e);
        }
    }
    out
}

/// What [`converge`] returns: the ladders, the files written and the runs' warnings.
pub type Converged = (Vec<FigureLadder>, Vec<PathBuf>, Vec<String>, Option<String>);

/// Runs the ladder and writes `converge.csv`, `converge.md` and `converge.png` into `out`;
/// returns the ladders, the files, the runs' warnings (each prefixed with its rung) and the
/// first rung that failed, when one did (the table then holds the rungs before it; the
/// command line exits 2 naming it, as a sweep with a failed point does).
/// `cancel` stops every run at its next step.
///
/// # Errors
/// [`SweepError`]; a scenario with several runs (each rung must be one run), a ladder of
/// fewer than three rungs or non-numeric values are refused before anything runs.
pub fn converge(
    path: &Path,
    text: &str,
    key: &str,
    values: &[String],
    out: &Path,
    cancel: &Cancel,
) -> Result<Converged, SweepError> {
    let bad = |message: String| SweepError::Value {
        key: key.into(),
        value: values.join(","),
        message,
    };
    let xs = crate::scenario::overrides::ladder_rungs(values, 3).map_err(bad)?;
    let runs = crate::scenario::Scenario::from_str(text, path)
        .map(|sc| sc.runs.len())
        .unwrap_or(1);
    if runs > 1 {
        return Err(bad(format!(
            "{} has {runs} [[runs]]: a convergence study needs one run per rung",
            path.display()
        )));
    }
    let mut points = run_ladder(path, text, key, values, out, cancel)?;
    // A rung cut short (Ctrl-C) or failed (the guard, a run error) is no rung of the
    // ladder: no order from it or after it.
    let complete = points
        .iter()
        .take_while(|p| {
            p.status == super::sweep::PointStatus::Complete
                && p.summary["interrupted"] != serde_json::Value::Bool(true)
        })
        .count();
    let mut cut = Vec::new();
    let mut failed = None;
    if complete < points.len() {
        let why = match &points[complete].status {
            super::sweep::PointStatus::Failed(m) => {
                let m = format!(
                    "{key} = {}: failed: {}",
                    points[complete].value,
                    m.replace(['\n', '\r'], " ")
                );
                failed = Some(m.clone());
                m
            }
            _ => "interrupted".to_string(),
        };
        cut.push(if failed.is_some() {
            format!("{why}; it and the rungs after it are left out of the orders")
        } else {
            format!(
                "{key} = {}: {why}; it and the rungs after it are left out of the orders",
                points[complete].value
            )
        });
        points.truncate(complete);
    }
    // A ladder left with no rung has no table to write: the study failed.
    if points.is_empty() && !cancel.is_cancelled() {
        return Err(bad(cut.concat()));
    }
    let xs = &xs[..points.len()];
    let warnings = cut
        .into_iter()
        .chain(points.iter().flat_map(|p| {
            p.warnings
                .iter()
                .map(|w| format!("{key} = {}: {w}", p.value))
        }))
        .collect();
    let per_rung: Vec<Vec<(String, f64)>> = points.iter().map(|p| figures(&p.summary)).collect();
    let names: Vec<String> = per_rung
        .first()
        .map(|f| f.iter().map(|(k, _)| k.clone()).collect())
        .unwrap_or_default();
    let ladders: Vec<FigureLadder> = names
        .iter()
        .map(|name| {
            let vals: Vec<f64> = per_rung
                .iter()
                .map(|f| {
                    f.iter()
                        .find(|(k, _)| k == name)
                        .map_or(f64::NAN, |(_, v)| *v)
                })
                .collect();
            let orders = observed_orders(xs, &vals);
            FigureLadder {
                name: name.clone(),
                extrapolated: extrapolate(xs, &vals, &orders),
                values: vals,
                orders,
            }
        })
        .collect();
    let files = write_tables(out, key, &values[..points.len()], xs, &ladders, &points)?;
    Ok((ladders, files, warnings, failed))
}

fn write_tables(
    out: &Path,
    key: &str,
    values: &[String],
    xs: &[f64],
    ladders: &[FigureLadder],
    points: &[SweepPoint],
) -> Result<Vec<PathBuf>, RunError> {
    let fmt = |x: f64| {
        if x.is_nan() {
            "-".to_string()
        } else {
            format!("{x:.6e}")
        }
    };
    let order = |o: Option<f64>| o.map_or("-".to_string(), |p| format!("{p:.2}"));
    let mut head = vec!["figure".to_string()];
    let key_col = super::sweep::key_column(key);
    head.extend(values.iter().map(|v| format!("{key_col}={v}")));
    head.extend((2..values.len()).map(|i| format!("order@{}", values[i])));
    head.push("extrapolated".into());
    let mut csv = crate::output::csv::record(&head);
    let mut md = format!(
        "| {} |\n|{}|\n",
        head.join(" | "),
        vec!["---"; head.len()].join("|")
    );
    for l in ladders {
        let mut row = vec![super::sweep::column_name(&l.name).to_string()];
        row.extend(l.values.iter().map(|&x| fmt(x)));
        row.extend(l.orders.iter().map(|&o| order(o)));
        row.push(l.extrapolated.map_or("-".into(), fmt));
        crate::output::csv::push_record(&mut csv, &row);
        let _ = writeln!(md, "| {} |", row.join(" | "));
    }
    let mut files = Vec::new();
    for (name, body) in [("converge.csv", csv), ("converge.md", md)] {
        let f = out.join(name);
        write_atomic(&f, body.as_bytes()).map_err(|e| RunError::output(&f, e))?;
        files.push(f);
    }
    // One panel per figure that varies along the ladder (those with an observed order
    // first): its value against the rung (log axis), and the extrapolated limit.
    let varies = |l: &&FigureLadder| {
        let (lo, hi) = l
            .values
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                (a.min(v), b.max(v))
            });
        l.values.iter().all(|v| v.is_finite()) && hi - lo > 1e-12 * hi.abs().max(lo.abs())
    };
    let mut shown: Vec<&FigureLadder> = ladders
        .iter()
        .filter(varies)
        .filter(|l| !NOT_PLOTTED.contains(&l.name.as_str()))
        .collect();
    shown.sort_by_key(|l| l.extrapolated.is_none());
    shown.truncate(9);
    if !shown.is_empty() && points.len() == xs.len() {
        let mut ps = Vec::new();
        for l in &shown {
            let mut p = Panel::new(l.name.clone(), rung_label(key), figure_label(&l.name));
            p.x_log = true;
            p.series.push(Series::new(
                "computed",
                xs.to_vec(),
                l.values.clone(),
                SeriesStyle::LineMarkers,
            ));
            match (l.extrapolated, asymptotic(l)) {
                (Some(e), Ok(())) => {
                    let p_last = order(*l.orders.last().unwrap_or(&None));
                    p.hlines
                        .push((e, format!("Richardson limit (observed order {p_last})")));
                }
                (_, Err(why)) => {
                    p.note =
                        format!("not in the asymptotic range ({why}): no order or limit drawn");
                }
                (None, Ok(())) => {}
            }
            ps.push(p);
        }
        let cols = 3.min(ps.len());
        let rows = ps.len().div_ceil(cols);
        let png = out.join("converge.png");
        panels(
            &png,
            &ps,
            rows,
            cols,
            (500 * cols as u32, 380 * rows as u32 + 60),
        )
        .map_err(|e| RunError::output(&png, e))?;
        files.push(png);
    }
    Ok(files)
}

/// Whether a ladder is in its asymptotic range, where an observed order and a Richardson
/// limit mean something: the values monotone in the rung, the differences shrinking, the
/// last two observed orders (with four rungs or more) within a factor 1.5 of each other,
/// and the limit of the same sign as values that all share one. Else why not, in words
/// (the figure says so instead of drawing a limit; the tables keep the numbers).
fn asymptotic(l: &FigureLadder) -> Result<(), String> {
    let d: Vec<f64> = l.values.windows(2).map(|w| w[1] - w[0]).collect();
    if d.iter().any(|x| !x.is_finite()) {
        return Err("a rung has no value".into());
    }
    let up = d.iter().all(|&x| x > 0.0);
    let down = d.iter().all(|&x| x < 0.0);
    if !(up || down) {
        return Err("not monotone".into());
    }
    if d.windows(2).any(|w| w[1].abs() >= w[0].abs()) {
        return Err("the differences do not shrink".into());
    }
    let known: Vec<f64> = l.orders.iter().flatten().copied().collect();
    if let [.., a, b] = known[..] {
        if (b / a).ln().abs() > 1.5f64.ln() {
            return Err(format!("observed orders {a:.2} and {b:.2} disagree"));
        }
    }
    if let Some(e) = l.extrapolated {
        let pos = l.values.iter().all(|&v| v > 0.0);
        let neg = l.values.iter().all(|&v| v < 0.0);
        if (pos && e <= 0.0) || (neg && e >= 0.0) {
            return Err(format!("the limit {e:.3e} changes sign"));
        }
    }
    Ok(())
}

/// The x axis of a ladder: the swept key in words with its unit.
fn rung_label(key: &str) -> String {
    match key {
        "wheel.rim_nodes" => "rim nodes (wheel.rim_nodes)".into(),
        "time.h" => "time step h [s] (time.h)".into(),
        "rolling.omega" => "spin omega [rad/s] (rolling.omega)".into(),
        k if k.ends_with("elements") => format!("elements ({k})"),
        k => k.to_string(),
    }
}

/// The y axis of a figure of the summary: its name with the unit its name or kind implies.
fn figure_label(name: &str) -> String {
    let unit = if name.ends_with("_hz") {
        "Hz"
    } else if name.ends_with("_mpa2") {
        "MPa²"
    } else if name.ends_with("_mpa") {
        "MPa"
    } else if name.ends_with("_us") {
        "µs"
    } else if name.ends_with("_s") {
        "s"
    } else if name.ends_with("_m") || name.ends_with("penetration") {
        "m"
    } else if name.contains("contact_force") || name.ends_with("force") {
        "N"
    } else if name.starts_with("energy") {
        "J"
    } else if name.ends_with("per_turn") {
        "cycles per turn"
    } else if name.contains("nodes") {
        "nodes"
    } else {
        "-"
    };
    // The unit's suffix is not repeated in words.
    let stem = ["_hz", "_mpa2", "_mpa", "_us", "_s", "_m"]
        .iter()
        .find_map(|suffix| name.strip_suffix(suffix))
        .unwrap_or(name);
    format!("{} [{unit}]", stem.replace('_', " "))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn observed_order_of_a_second_order_sequence() {
        // F(h) = 1 + 3 h^2 on h = 0.4, 0.2, 0.1, 0.05.
        let xs = [0.4, 0.2, 0.1, 0.05];
        let f: Vec<f64> = xs.iter().map(|h| 1.0 + 3.0 * h * h).collect();
        let o = observed_orders(&xs, &f);
        assert_eq!(o.len(), 2);
        for p in &o {
            assert!((p.unwrap() - 2.0).abs() < 1e-10, "{o:?}");
        }
        let e = extrapolate(&xs, &f, &o).unwrap();
        assert!((e - 1.0).abs() < 1e-12, "{e}");
        // Refining by rung count (elements 10, 20, 40): F = 2 - 5/N.
        let ns = [10.0, 20.0, 40.0];
        let g: Vec<f64> = ns.iter().map(|n| 2.0 - 5.0 / n).collect();
        let o = observed_orders(&ns, &g);
        assert!((o[0].unwrap() - 1.0).abs() < 1e-10);
        assert!((extrapolate(&ns, &g, &o).unwrap() - 2.0).abs() < 1e-12);
        // Differences that grow: no order.
        assert_eq!(observed_orders(&ns, &[1.0, 1.1, 1.5]), vec![None]);
    }

    /// The axes say what and in which unit, the unit's suffix not repeated.
    #[test]
    fn axis_labels_carry_units() {
        assert_eq!(
            figure_label("max_von_mises_turn_average_mpa"),
            "max von mises turn average [MPa]"
        );
        assert_eq!(figure_label("bounce_frequency_hz"), "bounce frequency [Hz]");
        assert_eq!(
            figure_label("contact_force_ripple"),
            "contact force ripple [N]"
        );
        assert_eq!(figure_label("energy_final"), "energy final [J]");
        assert_eq!(rung_label("wheel.rim_nodes"), "rim nodes (wheel.rim_nodes)");
    }

    /// The figure draws a limit only in the asymptotic range: a second-order sequence is
    /// in it; the bounce of issue 34 (7,263 -> 7,324 -> 7,301 Hz, not monotone), a ladder
    /// whose orders disagree (0.76 then 2.35) and one whose limit changes sign are not.
    #[test]
    fn asymptotic_range_of_a_ladder() {
        let ladder = |xs: &[f64], v: &[f64]| {
            let orders = observed_orders(xs, v);
            FigureLadder {
                name: "f".into(),
                extrapolated: extrapolate(xs, v, &orders),
                values: v.to_vec(),
                orders,
            }
        };
        let ns = [72.0, 144.0, 288.0, 576.0];
        let second: Vec<f64> = ns.iter().map(|n| 5.0 + 1e3 / (n * n)).collect();
        assert_eq!(asymptotic(&ladder(&ns, &second)), Ok(()));
        let bounce = ladder(&ns[..3], &[7263.3, 7324.3, 7301.2]);
        assert!(asymptotic(&bounce).unwrap_err().contains("monotone"));
        let ripple = ladder(&ns, &[1.42909e5, 6.081452e4, 1.249262e4, 2.984398e3]);
        assert!(asymptotic(&ripple).unwrap_err().contains("disagree"));
        // Positive values whose differences shrink too slowly for a positive limit.
        let sign = ladder(&ns[..3], &[10.0, 4.0, 0.5]);
        let e = sign.extrapolated.unwrap();
        assert!(e < 0.0, "{e}");
        assert!(asymptotic(&sign).unwrap_err().contains("sign"));
    }
}
