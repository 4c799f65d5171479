//! `softway compare`: the runs of a bar scenario (combinations of integrator, contact
//! treatment, time step and mesh) side by side against the exact d'Alembert answer: `compare.csv`,
//! `compare.md`, and overlaid plots of the contact force and the total energy.

use super::bar::{simulate, BarSummary, BarTrace};
use super::{RunError, RunOptions, RunReport};
use crate::output::files::write_atomic;
use crate::output::plot::{panels, sig, Panel, Series, SeriesStyle};
use crate::scenario::Scenario;
use std::path::Path;

/// The columns of the comparison, one row per run.
pub const COLUMNS: [&str; 18] = [
    "run",
    "integrator",
    "contact",
    "h_s",
    "elements",
    "contact_duration_error",
    "mean_force_error",
    "rebound_error",
    "left_behind",
    "energy_change",
    "force_chatter",
    "max_penetration_m",
    "penetration_at_release_m",
    "entries",
    "factorizations",
    "steps",
    "wall_time_s",
    "diverged_at_s",
];

fn row(s: &BarSummary) -> Vec<String> {
    let o = |x: Option<f64>| x.map(|v| format!("{v:+.4}")).unwrap_or_else(|| "-".into());
    vec![
        s.label.clone(),
        s.integrator.clone(),
        s.contact.clone(),
        {
            let r = format!("{}", s.h);
            if r.len() > 8 {
                format!("{:.4e}", s.h)
            } else {
                r
            }
        },
        s.elements.to_string(),
        o(s.errors.contact_duration),
        o(s.errors.mean_contact_force),
        format!("{:+.4}", s.errors.rebound_velocity),
        o(s.errors.velocity_left_behind),
        format!("{:+.4}", s.errors.energy),
        s.contact_force_chatter
            .map(|v| format!("{v:.4}"))
            .unwrap_or_else(|| "-".into()),
        format!("{:.2e}", s.max_penetration.max(0.0)),
        format!("{:.2e}", s.penetration_at_release),
        s.entries.to_string(),
        s.factorizations.to_string(),
        s.steps.to_string(),
        format!("{:.4}", s.wall_time_s),
        s.diverged_at_s
            .map(|t| format!("{t:.4e}"))
            .unwrap_or_else(|| "-".into()),
    ]
}

/// A Markdown table padded to its column widths (readable as plain text too).
fn markdown(rows: &[Vec<String>]) -> String {
    let mut w: Vec<usize> = COLUMNS.iter().map(|c| c.len()).collect();
    for r in rows {
        for (i, c) in r.iter().enumerate() {
            w[i] = w[i].max(c.chars().count());
        }
    }
    let line = |cells: &mut dyn Iterator<Item = String>| {
        let v: Vec<String> = cells
            .enumerate()
            .map(|(i, c)| format!("{c:<width$}", width = w[i]))
            .collect();
        format!("| {} |\n", v.join(" | "))
    };
    let mut md = line(&mut COLUMNS.iter().map(|c| c.to_string()));
    md += &line(&mut w.iter().map(|&n| "-".repeat(n)));
    for r in rows {
        md += &line(&mut r.iter().cloned());
    }
    md
}

/// Runs every run of a bar scenario and writes the comparison into `out`.
///
/// # Errors
/// [`RunError`]; a scenario that is not a bar impact.
pub fn compare(sc: &Scenario, out: &Path, opts: &RunOptions) -> Result<RunReport, RunError> {
    std::fs::create_dir_all(out).map_err(|e| RunError::output(out, e))?;
    let mut rows = Vec::new();
    let mut traces: Vec<(String, BarTrace, Option<f64>)> = Vec::new();
    let mut exact = None;
    let mut interrupted = false;
    // The lab shows what each combination does: a run past the guard's bound goes on and
    // its row says when it diverged (`diverged_at_s`).
    let opts = &RunOptions {
        guard: crate::guard::GuardMode::Record,
        ..opts.clone()
    };
    for run in &sc.runs {
        if !crate::kinds::bar::is_bar(&run.model) {
            return Err(RunError::input(
                &sc.path,
                "`softway compare` needs a bar scenario (kind = \"bar_impact\" or \"two_bars\")",
            ));
        }
        let (s, tr) = simulate(run, None, 1, opts)?;
        exact = Some(s.exact);
        rows.push(row(&s));
        traces.push((run.label.clone(), tr, s.diverged_at_s));
        if s.interrupted {
            interrupted = true;
            break;
        }
    }
    let mut csv = crate::output::csv::record(COLUMNS);
    for r in &rows {
        crate::output::csv::push_record(&mut csv, r);
    }
    let md = markdown(&rows);
    let mut report = RunReport {
        interrupted,
        ..RunReport::default()
    };
    for (name, body) in [("compare.csv", &csv), ("compare.md", &md)] {
        let f = out.join(name);
        write_atomic(&f, body.as_bytes()).map_err(|e| RunError::output(&f, e))?;
        report.files.push(f);
    }
    if let (true, false, Some(exact)) = (sc.plots, traces.is_empty(), exact) {
        let (pf, pe, nrows, cols) = comparison_panels(&traces, &exact);
        let size = (1700, (330 * nrows as u32).max(400));
        for (name, ps) in [("compare_force.png", &pf), ("compare_energy.png", &pe)] {
            let f = out.join(name);
            panels(&f, ps, nrows, cols, size).map_err(|e| RunError::output(&f, e))?;
            report.files.push(f);
        }
    }
    report.lines = md.lines().map(String::from).collect();
    Ok(report)
}

/// The panels of `compare_force.png` and `compare_energy.png`, one per run, in a grid of
/// `(rows, cols)`.
///
/// Force (issue 48): the exact force is d'Alembert's pulse, `rho A c v0` from the impact to
/// the release and zero outside (it was drawn as a constant line over the whole run); all
/// panels share one y axis, set by the runs that did not diverge, so that twenty panels
/// compare at a glance; a diverged run's peak off that axis is given in its title. Energy:
/// each panel its own axis (the drifts differ by orders). In both, a diverged run says so in
/// its title and its time after the divergence is shaded.
fn comparison_panels(
    traces: &[(String, BarTrace, Option<f64>)],
    exact: &super::bar::BarExact,
) -> (Vec<Panel>, Vec<Panel>, usize, usize) {
    let cols = traces.len().clamp(1, 4);
    let nrows = traces.len().div_ceil(cols);
    let t_end = traces
        .iter()
        .filter_map(|(_, tr, _)| tr.t.last().copied())
        .fold(0.0, f64::max);
    let pulse_t = vec![
        0.0,
        exact.impact_time,
        exact.impact_time,
        exact.release_time,
        exact.release_time,
        t_end,
    ];
    let f0 = exact.contact_force;
    let pulse_f = vec![0.0, 0.0, f0, f0, 0.0, 0.0];
    // The shared force axis: the runs that stayed within the guard's bound, and the pulse.
    let finite = |v: &[f64]| -> (f64, f64) {
        v.iter()
            .filter(|x| x.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
                (a.min(x), b.max(x))
            })
    };
    let (mut lo, mut hi) = (0.0f64.min(f0), 0.0f64.max(f0));
    for (_, tr, diverged) in traces {
        if diverged.is_none() {
            let (a, b) = finite(&tr.force);
            if a.is_finite() {
                lo = lo.min(a);
                hi = hi.max(b);
            }
        }
    }
    let m = 0.05 * (hi - lo).max(f64::MIN_POSITIVE);
    let (lo, hi) = (lo - m, hi + m);
    let after = "diverged (past the guard's bound)";
    let mut pf = Vec::new();
    let mut pe = Vec::new();
    for (label, tr, diverged) in traces {
        let (fmin, fmax) = finite(&tr.force);
        let title = match diverged {
            Some(t) => {
                let off = if fmax > hi || fmin < lo {
                    format!(
                        ", peak {} N off the axis",
                        sig(if fmax > hi { fmax } else { fmin }, 3)
                    )
                } else {
                    String::new()
                };
                (
                    format!("{label}: DIVERGED at {} s{off}", sig(*t, 3)),
                    format!("{label}: DIVERGED at {} s", sig(*t, 3)),
                )
            }
            None => (label.clone(), label.clone()),
        };
        let mut p = Panel::new(title.0, "t [s]", "F [N]");
        p.series.push(Series::new(
            "contact force",
            tr.t.clone(),
            tr.force.clone(),
            SeriesStyle::Line,
        ));
        p.series.push(Series::new(
            "exact (d'Alembert)",
            pulse_t.clone(),
            pulse_f.clone(),
            SeriesStyle::Dashed,
        ));
        p.y_range = Some((lo, hi));
        let e0 = tr.energy.first().copied().unwrap_or(1.0);
        let mut q = Panel::new(title.1, "t [s]", "E / E0");
        q.series.push(Series::new(
            "total energy",
            tr.t.clone(),
            tr.energy.iter().map(|e| e / e0).collect(),
            SeriesStyle::Line,
        ));
        q.hlines.push((1.0, "E0".into()));
        if let Some(t) = diverged {
            p.vspans.push((*t, t_end, after.into()));
            q.vspans.push((*t, t_end, after.into()));
        }
        pf.push(p);
        pe.push(q);
    }
    (pf, pe, nrows, cols)
}
