//! The elastic bar striking a rigid wall (paper §3.1, Figs. 8-9), against the exact
//! d'Alembert solution: contact from `t = gap / v0` for `2 L / c`, constant force
//! `rho A c v0`, rebound at `v0`, energy kept.

use super::{progress_bar, RunError, RunOptions, RunReport, INTERRUPT};
use crate::output::files::{write_json, CsvWriter};
use crate::output::plot::{panels, Panel, Series, SeriesStyle};
use crate::problems::BarImpact;
use crate::scenario::{Model, Run, Scenario};
use crate::simulation::Simulation;
use serde::Serialize;
use std::path::Path;
use std::time::Instant;

/// Key figures of one bar run (`summary.json`).
#[derive(Debug, Clone, Serialize)]
pub struct BarSummary {
    /// Run label.
    pub label: String,
    /// Time step, s.
    pub h: f64,
    /// `alpha`.
    pub alpha: f64,
    /// `gamma`.
    pub gamma: f64,
    /// `beta`.
    pub beta: f64,
    /// Elements.
    pub elements: usize,
    /// Contact method.
    pub method: crate::contact::ContactMethod,
    /// First instant the head is held on the wall, s (None: no contact).
    pub impact_time: Option<f64>,
    /// Last instant the head is held on the wall, s.
    pub release_time: Option<f64>,
    /// `release_time - impact_time + h` (the held steps times h), s.
    pub contact_duration: Option<f64>,
    /// Mean contact force over the held steps, N.
    pub mean_contact_force: Option<f64>,
    /// Largest contact force over the held steps, N.
    pub peak_contact_force: Option<f64>,
    /// Largest braking force, N.
    pub peak_braking_force: Option<f64>,
    /// Standard deviation of the contact force over the held steps, relative to the exact force.
    pub contact_force_chatter: Option<f64>,
    /// Centre-of-mass velocity away from the wall at the end of the run, m/s (exact: v0).
    pub rebound_velocity: f64,
    /// Total energy at the start, J.
    pub energy_initial: f64,
    /// Total energy at the end, J.
    pub energy_final: f64,
    /// Largest penetration seen, m.
    pub max_penetration: f64,
    /// Steps.
    pub steps: usize,
    /// Brakings (steps stepped back).
    pub brakings: usize,
    /// Releases.
    pub releases: usize,
    /// Wall-clock time of the run, s.
    pub wall_time_s: f64,
    /// Exact values.
    pub exact: BarExact,
    /// Errors against the exact values (relative, except times: absolute, s).
    pub errors: BarErrors,
    /// True when interrupted.
    pub interrupted: bool,
}

/// The exact d'Alembert answers.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct BarExact {
    /// `gap / v0`, s.
    pub impact_time: f64,
    /// `impact_time + 2 L / c`, s.
    pub release_time: f64,
    /// `2 L / c`, s.
    pub contact_duration: f64,
    /// `rho A c v0`, N.
    pub contact_force: f64,
    /// `v0`, m/s.
    pub rebound_velocity: f64,
    /// `rho A L v0^2 / 2`, J.
    pub energy: f64,
}

/// Errors against [`BarExact`].
#[derive(Debug, Clone, Copy, Serialize, Default)]
pub struct BarErrors {
    /// `impact_time - exact`, s.
    pub impact_time: Option<f64>,
    /// `contact_duration / exact - 1`.
    pub contact_duration: Option<f64>,
    /// `mean_contact_force / exact - 1`.
    pub mean_contact_force: Option<f64>,
    /// `rebound_velocity / v0 - 1`.
    pub rebound_velocity: f64,
    /// `energy_final / energy_initial - 1`.
    pub energy: f64,
}

/// The per-step trace of the head kept for plots.
#[derive(Debug, Clone, Default)]
pub struct BarTrace {
    /// Times, s.
    pub t: Vec<f64>,
    /// Head displacement, m.
    pub u: Vec<f64>,
    /// Head velocity, m/s.
    pub v: Vec<f64>,
    /// Total contact force, N.
    pub force: Vec<f64>,
    /// Total energy, J.
    pub energy: Vec<f64>,
}

/// Runs one bar run; rows go to `csv` (if given) with the run label.
///
/// # Errors
/// [`RunError`].
pub fn simulate(
    run: &Run,
    bar: &BarImpact,
    csv: Option<&mut CsvWriter>,
    stride: usize,
    show_progress: bool,
) -> Result<(BarSummary, BarTrace), RunError> {
    let (mesh, problem) = bar.problem(run.params, run.method, run.t_end);
    let head = mesh.n_nodes() - 1;
    let mass_rows = {
        let ones = vec![1.0; problem.model.n()];
        let mut r = vec![0.0; problem.model.n()];
        crate::linalg::spmv_into(problem.model.pattern(), &problem.model.m, &ones, &mut r);
        r
    };
    let total_mass: f64 = mass_rows.iter().sum();
    let steps = problem.steps;
    let mut sim = Simulation::new(problem).map_err(|source| RunError::Simulation {
        run: run.label.clone(),
        source,
    })?;
    let pb = progress_bar(steps as u64, &run.label, show_progress);
    let start = Instant::now();
    let mut trace = BarTrace::default();
    let (mut first, mut last) = (None, None);
    let (mut fsum, mut f2sum, mut nheld, mut fpeak, mut bpeak) =
        (0.0, 0.0, 0usize, f64::NEG_INFINITY, f64::NEG_INFINITY);
    let (mut e0, mut e1, mut vcm, mut max_pen) = (None, 0.0, 0.0, 0.0f64);
    let mut csv = csv;
    let stats = sim
        .run(&INTERRUPT, |s| {
            let st = &s.state;
            let pair = &st.pairs[0];
            let e = s.kinetic + s.strain;
            if e0.is_none() {
                e0 = Some(e);
            }
            e1 = e;
            vcm = mass_rows.iter().zip(&st.v).map(|(m, v)| m * v).sum::<f64>() / total_mass;
            max_pen = max_pen.max(-pair.gap);
            if pair.held {
                if first.is_none() {
                    first = Some(st.t);
                }
                last = Some(st.t);
                fsum += pair.force;
                f2sum += pair.force * pair.force;
                nheld += 1;
                fpeak = fpeak.max(pair.force);
            }
            if pair.braked {
                bpeak = bpeak.max(pair.force);
            }
            trace.t.push(st.t);
            trace.u.push(st.u[head]);
            trace.v.push(st.v[head]);
            trace.force.push(s.contact_force);
            trace.energy.push(e);
            if st.k % 64 == 0 {
                pb.set_position(st.k as u64);
            }
            if let Some(w) = csv.as_deref_mut() {
                if st.k % stride == 0 {
                    let state = if pair.held {
                        2.0
                    } else if pair.braked {
                        1.0
                    } else {
                        0.0
                    };
                    w.row(
                        Some(&run.label),
                        &[
                            st.t,
                            st.u[head],
                            st.v[head],
                            s.contact_force,
                            s.kinetic,
                            s.strain,
                            e,
                            state,
                        ],
                    )?;
                }
            }
            Ok(())
        })
        .map_err(|source| RunError::Simulation {
            run: run.label.clone(),
            source,
        })?;
    pb.finish_and_clear();
    let wall = start.elapsed().as_secs_f64();
    let h = run.params.h;
    let exact = BarExact {
        impact_time: bar.exact_impact_time(),
        release_time: bar.exact_impact_time() + bar.exact_contact_duration(),
        contact_duration: bar.exact_contact_duration(),
        contact_force: bar.exact_contact_force(),
        rebound_velocity: bar.speed,
        energy: 0.5 * bar.rho_a * bar.length * bar.speed * bar.speed,
    };
    let duration = match (first, last) {
        (Some(a), Some(b)) => Some(b - a + h),
        _ => None,
    };
    let mean = (nheld > 0).then(|| fsum / nheld as f64);
    let chatter =
        mean.map(|m| ((f2sum / nheld as f64 - m * m).max(0.0)).sqrt() / exact.contact_force);
    let rebound = -vcm;
    let e0 = e0.unwrap_or(0.0);
    let summary = BarSummary {
        label: run.label.clone(),
        h,
        alpha: run.params.alpha,
        gamma: run.params.gamma,
        beta: run.params.beta(),
        elements: bar.elements,
        method: run.method,
        impact_time: first,
        release_time: last,
        contact_duration: duration,
        mean_contact_force: mean,
        peak_contact_force: (nheld > 0).then_some(fpeak),
        peak_braking_force: bpeak.is_finite().then_some(bpeak),
        contact_force_chatter: chatter,
        rebound_velocity: rebound,
        energy_initial: e0,
        energy_final: e1,
        max_penetration: max_pen,
        steps: stats.steps,
        brakings: stats.brakings,
        releases: stats.releases,
        wall_time_s: wall,
        exact,
        errors: BarErrors {
            impact_time: first.map(|t| t - exact.impact_time),
            contact_duration: duration.map(|d| d / exact.contact_duration - 1.0),
            mean_contact_force: mean.map(|m| m / exact.contact_force - 1.0),
            rebound_velocity: rebound / exact.rebound_velocity - 1.0,
            energy: if e0 > 0.0 { e1 / e0 - 1.0 } else { 0.0 },
        },
        interrupted: stats.interrupted,
    };
    Ok((summary, trace))
}

/// Runs all runs of a bar scenario and writes `history.csv`, `summary.json` and
/// `bar_head.png`.
///
/// # Errors
/// [`RunError`].
pub fn run(sc: &Scenario, out: &Path, opts: &RunOptions) -> Result<RunReport, RunError> {
    let hist = out.join("history.csv");
    let mut csv = CsvWriter::create(
        &hist,
        &[
            "run",
            "t_s",
            "head_u_m",
            "head_v_m_s",
            "contact_force_N",
            "kinetic_J",
            "strain_J",
            "total_J",
            "contact_state",
        ],
    )
    .map_err(|e| RunError::output(&hist, e))?;
    let mut summaries = Vec::new();
    let mut traces = Vec::new();
    let mut report = RunReport::default();
    for run in &sc.runs {
        let Model::BarImpact(bar) = &run.model else {
            unreachable!("bar job on a bar scenario")
        };
        let (s, tr) = simulate(run, bar, Some(&mut csv), sc.history_stride, opts.progress)?;
        let interrupted = s.interrupted;
        summaries.push(s);
        traces.push((run.label.clone(), tr));
        if interrupted {
            report.interrupted = true;
            break;
        }
    }
    csv.finish().map_err(|e| RunError::output(&hist, e))?;
    report.files.push(hist);
    let mut json = serde_json::json!({
        "scenario": sc.name,
        "kind": "bar_impact",
        "units": {"time": "s", "length": "m", "velocity": "m/s", "force": "N", "energy": "J"},
        "interrupted": report.interrupted,
        "runs": summaries,
    });
    if summaries.len() == 1 {
        if let (Some(obj), Ok(serde_json::Value::Object(one))) =
            (json.as_object_mut(), serde_json::to_value(&summaries[0]))
        {
            for (k, v) in one {
                obj.entry(k).or_insert(v);
            }
        }
    }
    let sj = out.join("summary.json");
    write_json(&sj, &json).map_err(|e| RunError::output(&sj, e))?;
    report.files.push(sj);
    if sc.plots && !traces.is_empty() {
        let png = out.join("bar_head.png");
        plot_traces(&png, &traces, &summaries[0].exact)?;
        report.files.push(png);
    }
    for s in &summaries {
        report.lines.push(format!(
            "{:<14} h = {:<6} impact {:>7} release {:>7} duration {:>7} (exact {:.4}) mean force {:>8} (exact {:.4}) rebound {:.4} m/s (exact {:.4}) energy {:.4} -> {:.4} J, {} steps, {:.3} s",
            s.label,
            s.h,
            fmt_opt(s.impact_time),
            fmt_opt(s.release_time),
            fmt_opt(s.contact_duration),
            s.exact.contact_duration,
            fmt_opt(s.mean_contact_force),
            s.exact.contact_force,
            s.rebound_velocity,
            s.exact.rebound_velocity,
            s.energy_initial,
            s.energy_final,
            s.steps,
            s.wall_time_s
        ));
    }
    Ok(report)
}

fn fmt_opt(x: Option<f64>) -> String {
    x.map(|v| format!("{v:.4}")).unwrap_or_else(|| "-".into())
}

fn plot_traces(
    png: &Path,
    traces: &[(String, BarTrace)],
    exact: &BarExact,
) -> Result<(), RunError> {
    let style = |i: usize| {
        if i == 0 {
            SeriesStyle::Line
        } else if i % 2 == 1 {
            SeriesStyle::Dashed
        } else {
            SeriesStyle::Line
        }
    };
    let mk = |title: &str, ylab: &str, pick: &dyn Fn(&BarTrace) -> &Vec<f64>| {
        let mut p = Panel::new(title, "time t [s]", ylab);
        for (i, (label, tr)) in traces.iter().enumerate() {
            p.series.push(Series::new(
                label.clone(),
                tr.t.clone(),
                pick(tr).clone(),
                style(i),
            ));
        }
        p
    };
    let mut pu = mk("Displacement of the head A", "u_A [m]", &|t| &t.u);
    let mut pv = mk("Velocity of the head A", "v_A [m/s]", &|t| &t.v);
    let mut pf = mk("Contact force (braking included)", "F [N]", &|t| &t.force);
    pu.hlines
        .push((exact.impact_time * exact.rebound_velocity, "wall".into()));
    pv.hlines.push((exact.rebound_velocity, "v0".into()));
    pv.hlines
        .push((-exact.rebound_velocity, "-v0 (exact rebound)".into()));
    pf.hlines
        .push((exact.contact_force, "exact rho A c v0".into()));
    panels(png, &[pu, pv, pf], 3, 1, (1200, 1500)).map_err(|e| RunError::output(png, e))
}
