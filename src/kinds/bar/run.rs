//! The elastic bar striking a rigid wall (paper §3.1, Figs. 8-9), against the exact
//! d'Alembert solution: contact from `t = gap / v0` for `2 L / c`, constant force
//! `rho A c v0`, rebound at `v0`, energy kept.

use crate::bodies::bar::{BarImpact, TwoBars};
use crate::output::plot::{Panel, Series, SeriesStyle};
use crate::output::table::Rows;
use crate::run::error::RunError;
use crate::run::options::{progress_bar, RunOptions};
use crate::run::results::Results;
use crate::scenario::{Run, Scenario};
use crate::simulation::Simulation;
use serde::Serialize;
use std::path::Path;
use std::time::Instant;

/// Key figures of one bar run (`summary.json`).
#[derive(Debug, Clone, Serialize)]
pub struct BarSummary {
    /// Run label.
    pub label: String,
    /// The case: `bar_impact` (a bar against a wall) or `two_bars`.
    pub case: &'static str,
    /// Time step, s.
    pub h: f64,
    /// The integrator (e.g. `space_time(0.8,0)`, `newmark`).
    pub integrator: String,
    /// `alpha` of the space-time scheme.
    pub alpha: f64,
    /// `gamma` of the space-time scheme.
    pub gamma: f64,
    /// `beta` of the space-time scheme.
    pub beta: f64,
    /// Elements (per bar).
    pub elements: usize,
    /// Contact treatment.
    pub contact: String,
    /// First instant the contact carries a reaction, s (None: no contact).
    pub impact_time: Option<f64>,
    /// Last instant the contact carries a reaction, s.
    pub release_time: Option<f64>,
    /// `release_time - impact_time + h` (the steps in contact times h), s.
    pub contact_duration: Option<f64>,
    /// Mean contact force over the steps in contact, N.
    pub mean_contact_force: Option<f64>,
    /// Largest contact force over the steps in contact, N.
    pub peak_contact_force: Option<f64>,
    /// Largest braking force (soft way), N.
    pub peak_braking_force: Option<f64>,
    /// Standard deviation of the contact force over the steps in contact, relative to the
    /// exact force.
    pub contact_force_chatter: Option<f64>,
    /// One bar: the centre-of-mass velocity away from the wall at the end (exact: v0).
    /// Two bars: bar B's centre-of-mass velocity at the end (exact: v0), m/s.
    pub rebound_velocity: f64,
    /// Two bars: bar A's centre-of-mass velocity at the end (exact: 0), m/s.
    pub velocity_left_behind: Option<f64>,
    /// Total energy at the start, J.
    pub energy_initial: f64,
    /// Total energy at the end, J.
    pub energy_final: f64,
    /// Largest penetration seen, m.
    pub max_penetration: f64,
    /// Penetration at the last step in contact, m.
    pub penetration_at_release: f64,
    /// Steps.
    pub steps: usize,
    /// Brakings (soft way: steps stepped back).
    pub brakings: usize,
    /// Entries into contact (output steps where the contact starts carrying a reaction).
    pub entries: usize,
    /// Releases.
    pub releases: usize,
    /// Factorizations of a system matrix.
    pub factorizations: usize,
    /// Wall-clock time of the run, s.
    pub wall_time_s: f64,
    /// Exact values.
    pub exact: BarExact,
    /// Errors against the exact values (relative, except times: absolute, s).
    pub errors: BarErrors,
    /// True when interrupted.
    pub interrupted: bool,
    /// When the divergence guard found the energy past its bound (`softway compare` lets
    /// such runs go on and marks them; every other job stops them), s.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub diverged_at_s: Option<f64>,
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
    /// `rho A c v0` (two bars: half of it), N.
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
    /// Two bars: `velocity_left_behind / v0`.
    pub velocity_left_behind: Option<f64>,
    /// `energy_final / energy_initial - 1`.
    pub energy: f64,
}

/// Most samples a [`BarTrace`] keeps: beyond, it keeps every other one and samples half as
/// often from then on, so a long run's memory stays flat (the plots have far fewer pixels).
pub const TRACE_CAP: usize = 1 << 17;

/// The per-step trace kept for plots: every step up to [`TRACE_CAP`] samples, then every
/// `2^k`-th step (the summary's figures are accumulated over every step, not from here).
#[derive(Debug, Clone, Default)]
pub struct BarTrace {
    /// Times, s.
    pub t: Vec<f64>,
    /// Displacement of the contact node (one bar: the head; two bars: A's head), m.
    pub u: Vec<f64>,
    /// Its velocity, m/s.
    pub v: Vec<f64>,
    /// Total contact force, N.
    pub force: Vec<f64>,
    /// Total energy, J.
    pub energy: Vec<f64>,
    /// Steps between kept samples (1 until the trace first fills).
    every: usize,
    /// Steps seen.
    seen: usize,
}

impl BarTrace {
    /// Keeps the sample `(t, u, v, force, energy)` of the next step if it falls on the
    /// current sampling, halving the kept samples when the trace is full.
    fn record(&mut self, sample: [f64; 5]) {
        let every = self.every.max(1);
        let keep = self.seen % every == 0;
        self.seen += 1;
        if !keep {
            return;
        }
        if self.t.len() == TRACE_CAP {
            for v in [
                &mut self.t,
                &mut self.u,
                &mut self.v,
                &mut self.force,
                &mut self.energy,
            ] {
                let n = v.len().div_ceil(2);
                for i in 0..n {
                    v[i] = v[2 * i];
                }
                v.truncate(n);
            }
            self.every = every * 2;
            if (self.seen - 1) % self.every != 0 {
                return;
            }
        }
        for (v, x) in [
            &mut self.t,
            &mut self.u,
            &mut self.v,
            &mut self.force,
            &mut self.energy,
        ]
        .into_iter()
        .zip(sample)
        {
            v.push(x);
        }
    }
}

/// What one step end gives the recorder.
struct Sample<'a> {
    k: usize,
    t: f64,
    u: &'a [f64],
    v: &'a [f64],
    kinetic: f64,
    strain: f64,
    penalty: f64,
    force: f64,
    gap: f64,
    in_contact: bool,
    braked: bool,
}

/// The figures accumulated over a run.
struct Recorder<'a> {
    head: usize,
    /// Mass of each dof (row sums of M) and the dofs of each body.
    mass_rows: Vec<f64>,
    bodies: Vec<std::ops::Range<usize>>,
    trace: BarTrace,
    first: Option<f64>,
    last: Option<f64>,
    fsum: f64,
    f2sum: f64,
    nheld: usize,
    fpeak: f64,
    bpeak: f64,
    e0: Option<f64>,
    e1: f64,
    vcm: Vec<f64>,
    max_pen: f64,
    pen_last: f64,
    entries: usize,
    was_in_contact: bool,
    /// The history's rows and this run's key (label index) in them.
    csv: Option<(&'a mut Rows, u32)>,
    stride: usize,
    pb: indicatif::ProgressBar,
}

impl<'a> Recorder<'a> {
    fn new(
        head: usize,
        model: &crate::time::step::LinearModel,
        bodies: Vec<std::ops::Range<usize>>,
        csv: Option<(&'a mut Rows, u32)>,
        stride: usize,
        pb: indicatif::ProgressBar,
    ) -> Self {
        let n = model.n();
        let mut mass_rows = vec![0.0; n];
        crate::linalg::spmv_into(model.pattern(), &model.m, &vec![1.0; n], &mut mass_rows);
        let nb = bodies.len();
        Self {
            head,
            mass_rows,
            bodies,
            trace: BarTrace::default(),
            first: None,
            last: None,
            fsum: 0.0,
            f2sum: 0.0,
            nheld: 0,
            fpeak: f64::NEG_INFINITY,
            bpeak: f64::NEG_INFINITY,
            e0: None,
            e1: 0.0,
            vcm: vec![0.0; nb],
            max_pen: 0.0,
            pen_last: 0.0,
            entries: 0,
            was_in_contact: false,
            csv,
            stride,
            pb,
        }
    }

    fn record(&mut self, s: &Sample) -> Result<(), std::io::Error> {
        let e = s.kinetic + s.strain + s.penalty;
        if self.e0.is_none() {
            self.e0 = Some(e);
        }
        self.e1 = e;
        for (b, r) in self.bodies.iter().enumerate() {
            let (mut p, mut m) = (0.0, 0.0);
            for i in r.clone() {
                p += self.mass_rows[i] * s.v[i];
                m += self.mass_rows[i];
            }
            self.vcm[b] = p / m;
        }
        self.max_pen = self.max_pen.max(-s.gap);
        if s.in_contact && !self.was_in_contact {
            self.entries += 1;
        }
        self.was_in_contact = s.in_contact;
        if s.in_contact {
            if self.first.is_none() {
                self.first = Some(s.t);
            }
            self.last = Some(s.t);
            self.fsum += s.force;
            self.f2sum += s.force * s.force;
            self.nheld += 1;
            self.fpeak = self.fpeak.max(s.force);
            self.pen_last = (-s.gap).max(0.0);
        }
        if s.braked {
            self.bpeak = self.bpeak.max(s.force);
        }
        self.trace
            .record([s.t, s.u[self.head], s.v[self.head], s.force, e]);
        if s.k % 64 == 0 {
            self.pb.set_position(s.k as u64);
        }
        if let Some((w, key)) = self.csv.as_mut() {
            if s.k % self.stride == 0 {
                let state = if s.in_contact {
                    2.0
                } else if s.braked {
                    1.0
                } else {
                    0.0
                };
                w.push(
                    *key,
                    &[
                        s.t,
                        s.u[self.head],
                        s.v[self.head],
                        s.force,
                        s.kinetic,
                        s.strain,
                        e,
                        state,
                        s.gap,
                    ],
                )?;
            }
        }
        Ok(())
    }
}

/// Counters common to both drivers.
struct Counts {
    steps: usize,
    brakings: usize,
    releases: usize,
    factorizations: usize,
    interrupted: bool,
    diverged_at_s: Option<f64>,
}

/// Runs one run of a bar scenario (`bar_impact` or `two_bars`) with its integrator and
/// contact treatment through the driver ([`Simulation`]); rows go to `csv` (if given: the
/// history's rows and this run's key in them, see [`HISTORY`]).
///
/// # Errors
/// [`RunError`].
pub fn simulate(
    run: &Run,
    csv: Option<(&mut Rows, u32)>,
    stride: usize,
    opts: &RunOptions,
) -> Result<(BarSummary, BarTrace), RunError> {
    let h = run.params.h;
    let sim_err = |source: crate::simulation::SimError| RunError::Simulation {
        run: run.label.clone(),
        source,
    };
    // The exact answers of bar A (against a wall, or against bar B: half the force).
    let one = run.model.get::<BarImpact>();
    let two = run.model.get::<TwoBars>();
    let (case, a, force, elements) = match (one, two) {
        (Some(b), _) => ("bar_impact", *b, b.exact_contact_force(), b.elements),
        (_, Some(b)) => ("two_bars", b.bar_a(), b.exact_contact_force(), b.elements),
        _ => unreachable!("bar job on a bar scenario"),
    };
    let exact = BarExact {
        impact_time: a.exact_impact_time(),
        release_time: a.exact_impact_time() + a.exact_contact_duration(),
        contact_duration: a.exact_contact_duration(),
        contact_force: force,
        rebound_velocity: a.speed,
        energy: 0.5 * a.rho_a * a.length * a.speed * a.speed,
    };
    let steps = (run.t_end / h).round() as usize;
    let pb = progress_bar(steps as u64, &run.label, opts);
    let start = Instant::now();
    let (mesh, problem, bodies) = match (one, two) {
        (Some(b), _) => {
            let (m, p) = b.problem(run.integrator, run.contact, h, run.t_end);
            let n = p.model.n();
            (m, p, vec![std::ops::Range { start: 0, end: n }])
        }
        (_, Some(b)) => {
            let (m, p) = b.problem(run.integrator, run.contact, h, run.t_end);
            let n = p.model.n();
            (m, p, vec![0..n / 2, n / 2..n])
        }
        _ => unreachable!("bar job on a bar scenario"),
    };
    let head = mesh
        .node_sets
        .get("a_head")
        .or(mesh.node_sets.get("head"))
        .map(|v| v[0])
        .unwrap_or(0);
    let mut sim = Simulation::with_settings(problem, opts.settings()).map_err(sim_err)?;
    let mut rec = Recorder::new(head, &sim.engine().model, bodies, csv, stride, pb);
    let stats = sim
        .run(opts.cancel.flag(), |s| {
            let st = &s.state;
            let pair = &st.pairs[0];
            rec.record(&Sample {
                k: st.k,
                t: st.t,
                u: &st.u,
                v: &st.v,
                kinetic: s.kinetic(),
                strain: s.strain(),
                penalty: s.penalty,
                force: s.contact_force,
                gap: pair.gap,
                in_contact: pair.held,
                braked: pair.braked,
            })
        })
        .map_err(sim_err)?;
    let counts = Counts {
        steps: stats.steps,
        brakings: stats.brakings,
        releases: stats.releases,
        factorizations: stats.factorizations,
        interrupted: stats.interrupted,
        diverged_at_s: stats.diverged_at_s,
    };
    rec.pb.finish_and_clear();
    let wall = start.elapsed().as_secs_f64();
    let duration = match (rec.first, rec.last) {
        (Some(a), Some(b)) => Some(b - a + h),
        _ => None,
    };
    let nheld = rec.nheld;
    let mean = (nheld > 0).then(|| rec.fsum / nheld as f64);
    let chatter =
        mean.map(|m| ((rec.f2sum / nheld as f64 - m * m).max(0.0)).sqrt() / exact.contact_force);
    let (rebound, left) = if rec.vcm.len() == 2 {
        (rec.vcm[1], Some(rec.vcm[0]))
    } else {
        (-rec.vcm[0], None)
    };
    let e0 = rec.e0.unwrap_or(0.0);
    let summary = BarSummary {
        label: run.label.clone(),
        case,
        h,
        integrator: run.integrator.name(),
        alpha: run.params.alpha,
        gamma: run.params.gamma,
        beta: run.params.beta(),
        elements,
        contact: run.contact.name(),
        impact_time: rec.first,
        release_time: rec.last,
        contact_duration: duration,
        mean_contact_force: mean,
        peak_contact_force: (nheld > 0).then_some(rec.fpeak),
        peak_braking_force: rec.bpeak.is_finite().then_some(rec.bpeak),
        contact_force_chatter: chatter,
        rebound_velocity: rebound,
        velocity_left_behind: left,
        energy_initial: e0,
        energy_final: rec.e1,
        max_penetration: rec.max_pen,
        penetration_at_release: rec.pen_last,
        steps: counts.steps,
        brakings: counts.brakings,
        entries: rec.entries,
        releases: counts.releases,
        factorizations: counts.factorizations,
        wall_time_s: wall,
        exact,
        errors: BarErrors {
            impact_time: rec.first.map(|t| t - exact.impact_time),
            contact_duration: duration.map(|d| d / exact.contact_duration - 1.0),
            mean_contact_force: mean.map(|m| m / exact.contact_force - 1.0),
            rebound_velocity: rebound / exact.rebound_velocity - 1.0,
            velocity_left_behind: left.map(|v| v / exact.rebound_velocity),
            energy: if e0 > 0.0 { rec.e1 / e0 - 1.0 } else { 0.0 },
        },
        interrupted: counts.interrupted,
        diverged_at_s: counts.diverged_at_s,
    };
    Ok((summary, rec.trace))
}

/// The columns of `history.csv`: `run` (the run's label), then these (`contact_state`: 0
/// free, 1 braked, 2 held).
pub const HISTORY: [(&str, &str); 9] = [
    ("t_s", "s"),
    ("head_u_m", "m"),
    ("head_v_m_s", "m/s"),
    ("contact_force_N", "N"),
    ("kinetic_J", "J"),
    ("strain_J", "J"),
    ("total_J", "J"),
    ("contact_state", "1"),
    ("gap_m", "m"),
];

/// Runs all runs of a bar scenario; the history is streamed to `stream` (`history.csv`)
/// when given, else held. The figure (`bar_head.png`) is drawn by [`Results::save`].
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
    let mut summaries = Vec::new();
    let mut traces = Vec::new();
    let mut interrupted = false;
    for (key, run) in sc.runs.iter().enumerate() {
        let (s, tr) = simulate(run, Some((&mut csv, key as u32)), sc.history_stride, opts)?;
        let stopped = s.interrupted;
        summaries.push(s);
        traces.push((run.label.clone(), tr));
        if stopped {
            interrupted = true;
            break;
        }
    }
    let history = csv.finish().map_err(at)?;
    let kind = summaries.first().map(|s| s.case).unwrap_or("bar_impact");
    let mut json = serde_json::json!({
        "scenario": sc.name,
        "kind": kind,
        "units": {"time": "s", "length": "m", "velocity": "m/s", "force": "N", "energy": "J"},
        "interrupted": interrupted,
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
    crate::run::provenance::stamp_provenance(&mut json, sc);
    let lines = summaries.iter().map(summary_line).collect();
    let panes = match summaries.first() {
        Some(s) if !traces.is_empty() => trace_panels(&traces, &s.exact, kind == "two_bars"),
        _ => Vec::new(),
    };
    Ok(Results::with_panels(
        (kind, json),
        history,
        lines,
        interrupted,
        sc.plots,
        ("bar_head.png", panes, (1200, 1500)),
    ))
}

/// The screen line of a run.
fn summary_line(s: &BarSummary) -> String {
    format!(
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
    )
}

fn fmt_opt(x: Option<f64>) -> String {
    x.map(|v| format!("{v:.4}")).unwrap_or_else(|| "-".into())
}

/// The panels of `bar_head.png`: displacement, velocity and contact force of the head
/// against the exact values.
fn trace_panels(traces: &[(String, BarTrace)], exact: &BarExact, two_bars: bool) -> Vec<Panel> {
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
    let gap = exact.impact_time * exact.rebound_velocity;
    pv.hlines.push((exact.rebound_velocity, "v0".into()));
    if two_bars {
        pu.hlines.push((gap, "bar B's end at rest".into()));
        pv.hlines.push((
            0.5 * exact.rebound_velocity,
            "v0/2 (exact, in contact)".into(),
        ));
        pv.hlines.push((0.0, "0 (exact, after the impact)".into()));
    } else {
        pu.hlines.push((gap, "wall".into()));
        pv.hlines
            .push((-exact.rebound_velocity, "-v0 (exact rebound)".into()));
    }
    pf.hlines.push((exact.contact_force, "exact force".into()));
    vec![pu, pv, pf]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Past the cap the trace keeps every other sample and samples half as often: after
    /// `3 CAP` steps it holds the steps `0, 4, 8, ...` (every 4th), at most `CAP` of them,
    /// each sample still the one of its step.
    #[test]
    fn trace_memory_stays_flat_and_keeps_evenly_spaced_steps() {
        let mut tr = BarTrace::default();
        let steps = 3 * TRACE_CAP;
        for k in 0..steps {
            let x = k as f64;
            tr.record([x, 2.0 * x, 3.0 * x, 4.0 * x, 5.0 * x]);
        }
        assert!(tr.t.len() <= TRACE_CAP);
        assert_eq!(tr.every, 4);
        for (i, &t) in tr.t.iter().enumerate() {
            assert_eq!(t, (4 * i) as f64);
            assert_eq!(tr.energy[i], 5.0 * t);
        }
        assert_eq!(tr.t.len(), steps / 4);
    }
}
