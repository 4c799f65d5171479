//! `softway compare`: the runs of a bar scenario (combinations of contact treatment and
//! time step on one mesh) side by side against the exact d'Alembert answer: `compare.csv`,
//! `compare.md`, and overlaid plots of the contact force and the total energy.

use super::bar::{simulate, BarSummary, BarTrace};
use super::{RunError, RunOptions, RunReport};
use crate::output::files::write_atomic;
use crate::output::plot::{line_plot, Panel, Series, SeriesStyle};
use crate::scenario::{Model, Scenario};
use std::fmt::Write as _;
use std::path::Path;

/// The columns of the comparison, one row per run.
pub const COLUMNS: [&str; 13] = [
    "run",
    "integrator",
    "contact",
    "h_s",
    "contact_duration_error",
    "mean_force_error",
    "rebound_error",
    "energy_change",
    "force_chatter",
    "max_penetration_m",
    "brakings",
    "steps",
    "wall_time_s",
];

fn row(s: &BarSummary) -> Vec<String> {
    let o = |x: Option<f64>| x.map(|v| format!("{v:+.4}")).unwrap_or_else(|| "-".into());
    vec![
        s.label.clone(),
        "space_time".into(),
        serde_json::to_value(s.method)
            .ok()
            .and_then(|v| v.as_str().map(String::from))
            .unwrap_or_default(),
        format!("{}", s.h),
        o(s.errors.contact_duration),
        o(s.errors.mean_contact_force),
        format!("{:+.4}", s.errors.rebound_velocity),
        format!("{:+.4}", s.errors.energy),
        s.contact_force_chatter
            .map(|v| format!("{v:.4}"))
            .unwrap_or_else(|| "-".into()),
        format!("{:.2e}", s.max_penetration.max(0.0)),
        s.brakings.to_string(),
        s.steps.to_string(),
        format!("{:.4}", s.wall_time_s),
    ]
}

/// Runs every run of a bar scenario and writes the comparison into `out`.
///
/// # Errors
/// [`RunError`]; a scenario that is not a bar impact.
pub fn compare(sc: &Scenario, out: &Path, opts: &RunOptions) -> Result<RunReport, RunError> {
    std::fs::create_dir_all(out).map_err(|e| RunError::output(out, e))?;
    let mut rows = Vec::new();
    let mut traces: Vec<(String, BarTrace)> = Vec::new();
    let mut exact_force = 0.0;
    for run in &sc.runs {
        let Model::BarImpact(bar) = &run.model else {
            return Err(RunError::input(
                &sc.path,
                "`softway compare` needs a bar scenario (kind = \"bar_impact\")",
            ));
        };
        let (s, tr) = simulate(run, bar, None, 1, opts.progress)?;
        exact_force = s.exact.contact_force;
        rows.push(row(&s));
        traces.push((run.label.clone(), tr));
        if s.interrupted {
            break;
        }
    }
    let mut csv = format!("{}\n", COLUMNS.join(","));
    let mut md = format!(
        "| {} |\n|{}|\n",
        COLUMNS.join(" | "),
        vec!["---"; COLUMNS.len()].join("|")
    );
    for r in &rows {
        let _ = writeln!(csv, "{}", r.join(","));
        let _ = writeln!(md, "| {} |", r.join(" | "));
    }
    let mut report = RunReport::default();
    for (name, body) in [("compare.csv", &csv), ("compare.md", &md)] {
        let f = out.join(name);
        write_atomic(&f, body.as_bytes()).map_err(|e| RunError::output(&f, e))?;
        report.files.push(f);
    }
    if sc.plots {
        let style = |i: usize| {
            if i % 2 == 0 {
                SeriesStyle::Line
            } else {
                SeriesStyle::Dashed
            }
        };
        let mut pf = Panel::new("Contact force, all runs", "time t [s]", "contact force [N]");
        let mut pe = Panel::new("Total energy, all runs", "time t [s]", "energy [J]");
        for (i, (label, tr)) in traces.iter().enumerate() {
            pf.series.push(Series::new(
                label.clone(),
                tr.t.clone(),
                tr.force.clone(),
                style(i),
            ));
            pe.series.push(Series::new(
                label.clone(),
                tr.t.clone(),
                tr.energy.clone(),
                style(i),
            ));
        }
        pf.hlines.push((exact_force, "exact rho A c v0".into()));
        for (name, p) in [("compare_force.png", &pf), ("compare_energy.png", &pe)] {
            let f = out.join(name);
            line_plot(&f, p, (1400, 800)).map_err(|e| RunError::output(&f, e))?;
            report.files.push(f);
        }
    }
    report.lines = md.lines().map(String::from).collect();
    Ok(report)
}
