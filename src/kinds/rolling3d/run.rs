//! `softway run` of a `rolling3d` scenario: the slice is spun up, pressed by the base's
//! flattening over `rolling.settle_ms` and rolled to the run's end.
//!
//! **The forces** are the base's on the wheel, summed over the rim's pairs at each step
//! ([`PatchForce::of`]): the normal force `N`, the creep force `Q` along the rolling
//! direction `-t_b` (the wheel's travel over the base: `Q > 0` drives the wheel, as
//! `xi > 0` asks; the 2D wheel's sign), the lateral force `Q_y` along the axle `+z`, and the
//! spin moment `M_z` about the base's normal `n` through the patch's nominal centre `p0`,
//! `M_z = sum ((x - p0) x f) . n` over the pairs (`x` a rim node's deformed position, `f`
//! its friction force).
//!
//! **The steady state.** The rolling after the ramp and a settling as long again
//! ([`super::Rolling3dScenario::settled`]) is cut into four equal windows; the figures are
//! the last half's means, and the traction ratio's steady value is Aitken's extrapolation
//! of the last three windows' means when they converge geometrically
//! (the 2D wheel's `steady_ratio`, `kinds::wheel::run::traction`), else the last
//! half's mean. The run reports the steady state as reached when the last two windows'
//! means of `Q / (mu N)` and `Q_y / (mu N)` differ by less than [`STEADY_TOLERANCE`] and
//! `N` by less than 1 %.
//!
//! **Cost.** `summary.json`'s `cost` says what the run's step cost against the yardsticks a
//! user compares it with: the set-up (the slice, its matrices and the factor, s), the
//! factor's kind and entries, the free step (the prediction of a step without contact, its
//! right-hand side and solve: the mean of the loop's predictions solved, timed as the loop
//! ran them) and the bytes it reads, whose floor is these over the memory's bandwidth (`softway
//! sweep`'s `cost.md` measures the bandwidth); the loop's step with the contact (the loop's
//! wall time over its steps, the observer's history included) and its ratio to the free
//! step; the free and the columns' solves a step; and `metre_s`, the loop's time for one
//! metre of rolling at the run's speed and step (`step_s / (V h)`), on the run's `threads`.
//!
//! Files: `history.csv` (every `output.history_stride` steps: the forces, the ratios, the
//! nodes in contact and sliding, the frictional power), `patch.csv` (the last step's rim
//! nodes near the patch: position along the rolling direction and the axle, pressure and
//! tractions, stick or slip), `fields.vtu` (the last step: the displacement, the pressure
//! and the traction on the rim, for ParaView), `rolling3d.png` (the creep forces and the
//! normal force against time; the last step's pressure and traction along the rolling
//! direction, stick and slip marked) and `summary.json` (the steady figures, the
//! `traction` object the sweep's creep curve reads, the cost per step).

use super::Rolling3dScenario;
use crate::bodies::rolling3d::{
    friction_force, rail_directions, rail_patch_force, PatchForce, RollingSlice,
};
use crate::bodies::wheel::Coupling;
use crate::contact::pair::tangent_basis;
use crate::contact::Interface;
use crate::contact::{Obstacle, RotatingBase};
use crate::kinds::wheel::run::summarise::STEPS_PER_PASSAGE_MIN;
use crate::kinds::wheel::run::traction::{hertz_2d, steady_ratio};
use crate::model::PairState;
use crate::output::plot::sig;
use crate::output::vtk::{write_vtu, Field};
use crate::run::error::RunError;
use crate::run::options::RunOptions;
use crate::run::results::{Detail, Fields, OwnFiles, Results};
use crate::scenario::Scenario;
use crate::simulation::Simulation;
use std::path::{Path, PathBuf};
use std::time::Instant;

mod figures;

/// The largest change of `Q / (mu N)` (and `Q_y / (mu N)`) between the last two windows
/// of the rolling for the steady state to count as reached (module docs).
pub const STEADY_TOLERANCE: f64 = 0.01;

/// The columns of `history.csv`: `run` (the run's label), then these.
pub const HISTORY: [(&str, &str); 10] = [
    ("t_s", "s"),
    ("normal_force_N", "N"),
    ("creep_force_N", "N"),
    ("lateral_force_N", "N"),
    ("spin_moment_N_m", "N m"),
    ("traction_ratio", "1"),
    ("lateral_ratio", "1"),
    ("nodes_in_contact", "1"),
    ("nodes_sliding", "1"),
    ("slip_power_W", "W"),
];

/// One step's figures.
#[derive(Debug, Clone, Copy, Default)]
struct Rec {
    t: f64,
    normal: f64,
    creep: f64,
    lateral: f64,
    spin: f64,
    held: usize,
    sliding: usize,
}

impl Rec {
    /// `x / (mu N)` at this step (a force over the bound of the coefficient `mu`); `None`
    /// without friction or without contact.
    fn per_mu_n(&self, x: f64, mu: f64) -> Option<f64> {
        (mu > 0.0 && self.normal > 0.0).then(|| x / (mu * self.normal))
    }
}

/// A rim node of the last step's patch.
#[derive(Debug, Clone, Copy)]
pub struct PatchNode {
    /// Position along the rolling direction `-t_b` from the patch's nominal centre, m.
    pub s: f64,
    /// Position along the axle from the wheel's mid-plane, m.
    pub z: f64,
    /// The layer of nodes (0 at `z = 0`).
    pub layer: usize,
    /// The node's normal force, N.
    pub force: f64,
    /// Pressure (the normal force over the node's share of the rim), Pa.
    pub pressure: f64,
    /// Traction along the rolling direction, Pa.
    pub traction: f64,
    /// Traction along the axle, Pa.
    pub lateral: f64,
    /// Sliding.
    pub sliding: bool,
    /// The node.
    pub node: usize,
}

/// `base` as the mesh's frame sees it after a refined zone's relocations have turned that
/// frame by `angle` ([`crate::simulation::StepView::frame_angle`]; 0 without a zone).
fn turned(base: &RotatingBase, angle: f64) -> RotatingBase {
    let mut b = *base;
    b.line.theta0 -= angle;
    b
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The means of `f` over the records in four equal windows of `recs`.
fn quarters(recs: &[Rec], f: impl Fn(&Rec) -> f64) -> [f64; 4] {
    let n = recs.len();
    std::array::from_fn(|q| {
        let w = &recs[q * n / 4..((q + 1) * n / 4).max(q * n / 4 + 1).min(n)];
        w.iter().map(&f).sum::<f64>() / w.len().max(1) as f64
    })
}

/// The ripple of a steady signal sampled every `dt`: its RMS about its mean over `steady`,
/// and the strongest spectral peak of the longer record `all` above four periods of it
/// (`(Hz, amplitude)`, [`crate::analysis::signal::dominant_peak`]; none when `all` has
/// fewer than 8 samples), where the rim's discrete passage shows.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Ripple {
    rms: f64,
    peak: Option<(f64, f64)>,
}

impl Ripple {
    fn of(steady: &[f64], all: &[f64], dt: f64) -> Self {
        let rms = crate::growth::spectrum::rms(steady);
        let peak = (all.len() >= 8).then(|| {
            let spec = crate::analysis::signal::amplitude_spectrum(all, dt);
            crate::analysis::signal::dominant_peak(&spec, 4.0 / (all.len() as f64 * dt))
        });
        Ripple {
            rms,
            peak: peak.flatten(),
        }
    }
}

/// The run's files beyond the history (module docs).
#[derive(Debug)]
struct Rolling3dFiles {
    mesh: crate::mesh::Mesh,
    u: Vec<f64>,
    patch: Vec<PatchNode>,
    mu: f64,
    /// The coefficient falls with the slip speed (`mu` is the static one).
    falling: bool,
    series: Vec<[f64; 4]>,
    settled: f64,
    steady_ratio: f64,
    thickness: f64,
    /// A crowned base's Hertz ellipse at the steady normal force: the semi-axis along the
    /// rolling direction and the peak pressure, m and Pa.
    hertz: Option<(f64, f64)>,
}

/// The summary's `cost` (module docs, Cost): what the run's step costs against a free step
/// and against the memory's floor, and what a metre of rolling costs. `times` are the
/// set-up's and the loop's, s; `run` the threads, the rim's speed (m/s) and the step (s).
fn cost_record(
    sim: &Simulation,
    stats: &crate::simulation::RunStats,
    (setup_s, loop_s): (f64, f64),
    (threads, speed, h): (usize, f64, f64),
) -> serde_json::Value {
    let steps = stats.steps.max(1) as f64;
    let free_step_s = sim.prediction_seconds() / stats.predictions.max(1) as f64;
    let step_s = loop_s / steps;
    let factor = sim.engine().integ.factor_size();
    serde_json::json!({
        "threads": threads,
        "setup_s": setup_s,
        "factor": factor.map(|f| f.kind),
        "factor_nnz": factor.map(|f| f.nnz),
        "free_step_bytes": factor.map(|f| f.free_step_bytes),
        "free_step_s": free_step_s,
        "step_s": step_s,
        "step_over_free_step": step_s / free_step_s,
        "free_solves_per_step": stats.predictions as f64 / steps,
        "column_solves_per_step": stats.column_solves as f64 / steps,
        "metre_s": step_s / (speed * h),
    })
}

/// `softway run` of a `rolling3d` scenario (module docs).
///
/// # Errors
/// [`RunError`]: a slice that cannot be built, a failed run, a file that cannot be written.
pub(crate) fn record(
    sc: &Scenario,
    stream: Option<&Path>,
    opts: &RunOptions,
) -> Result<Results, RunError> {
    let run = &sc.runs[0];
    let Some(m) = run.model.get::<Rolling3dScenario>() else {
        unreachable!("a rolling3d run of a rolling3d scenario")
    };
    let h = run.params.h;
    // The 2D wheel's rule: at least two steps to a rim node's passage under the base, at the
    // finest pitch of the rim (the zone's).
    let passing = m.slice.zone.map_or(m.slice.counts[1], |z| z.sectors) as f64;
    let t_pass = 2.0 * std::f64::consts::PI / (m.slice.omega * passing);
    if h * STEPS_PER_PASSAGE_MIN > t_pass {
        return Err(RunError::input(
            &sc.path,
            format!(
                "run `{}`: the step `{}` = {h:e} s is longer than half a rim node's passage under the base ({t_pass:.3e} s: {passing} rim nodes round the rim{} at `rolling.omega` = {} rad/s): the contact would jump nodes between steps; take h <= {:.3e} s",
                run.label,
                run.step_key,
                if m.slice.zone.is_some() { " in the zone" } else { "" },
                m.slice.omega,
                t_pass / STEPS_PER_PASSAGE_MIN
            ),
        ));
    }
    if m.slice.coupling == Coupling::Uncoupled && !run.friction.is_some_and(|f| f.is_active()) {
        return Err(RunError::input(
            &sc.path,
            format!(
                "run `{}`: `rolling.coupling` = \"uncoupled\" differs from the coupled wheel only through friction: set contact.friction > 0 (or remove rolling.coupling)",
                run.label
            ),
        ));
    }
    // The set-up's time: the slice, its matrices and the factor (the cost record).
    let setup_clock = Instant::now();
    let slice = RollingSlice::new(&m.slice_for(run.t_end))
        .map_err(|e| RunError::input(&sc.path, e.to_string()))?;
    let steps = (run.t_end / h).round().max(1.0) as usize;
    let mu = run.friction.map_or(0.0, |l| l.static_mu);
    // A coefficient falling with the slip speed (the ratios are on `mu_s`).
    let falling = run.friction.filter(|l| l.kinetic != l.static_mu);
    let problem = slice.problem_with((run.integrator, h, steps), run.contact, run.friction);
    let sim_error = |source| RunError::Simulation {
        run: run.label.clone(),
        source,
    };
    let mut sim = Simulation::with_settings(problem, opts.settings()).map_err(sim_error)?;
    if m.cyclic_columns {
        sim.set_cyclic_symmetry(slice.symmetry(m.slice.counts))
            .map_err(sim_error)?;
    }
    if let Some(z) = &slice.zone {
        sim.set_relocation(crate::simulation::Relocation {
            sources: z.sources.clone(),
            step: z.step,
            omega: m.slice.omega,
            angle0: 0.0,
            turned: z.turned,
        })
        .map_err(sim_error)?;
    }
    // A ring shorter than the rolling: its seam kept ahead of the patch.
    if let Some(ring) = slice.rail.as_ref().and_then(|r| r.ring.clone()) {
        sim.set_ring_shift(ring).map_err(sim_error)?;
    }
    // A rail closed on itself: its columns shifted from one station's.
    if let Some((sym, probe)) = slice.rail.as_ref().and_then(|r| r.shift.clone()) {
        sim.set_cyclic_symmetry_at(sym, probe).map_err(sim_error)?;
    }
    let setup_s = setup_clock.elapsed().as_secs_f64();
    let mesh = slice.bodies[0].mesh.clone();
    let x_ref = mesh.reference_positions();
    let rim = slice.rim.clone();
    let base = slice.base;
    let (mut csv, hist) = crate::run::history::keyed_history(sc, stream, &HISTORY)?;
    let stride = sc.history_stride.max(1);
    let pb = crate::run::options::progress_bar(steps as u64, &run.label, opts);
    let mut recs: Vec<Rec> = Vec::with_capacity(steps + 1);
    let clock = Instant::now();
    let mut last_angle = 0.0;
    let stats = sim
        .run(opts.cancel.flag(), |v| {
            let t = v.state.t;
            let pairs = &v.state.pairs;
            // The base as the mesh's frame sees it (turned back by a zone's relocations).
            let base = turned(&base, v.frame_angle);
            last_angle = v.frame_angle;
            let (f, spin) = match v.interfaces.first() {
                Some(rail) => {
                    rail_patch_force(rail, &base, t, pairs, (&rim, &x_ref, &v.state.state.u))
                }
                None => (
                    PatchForce::at(&base, t, pairs, (&rim, &x_ref, &v.state.state.u)),
                    PatchForce::spin_moment(&base, t, pairs, (&rim, &x_ref, &v.state.state.u)),
                ),
            };
            let held = pairs.iter().filter(|p| p.force > 0.0).count();
            let sliding = pairs.iter().filter(|p| p.sliding).count();
            let rec = Rec {
                t,
                normal: f.normal,
                creep: -f.along,
                lateral: f.lateral,
                spin,
                held,
                sliding,
            };
            let ratio = |x: f64| rec.per_mu_n(x, mu).unwrap_or(0.0);
            if v.state.k % stride == 0 {
                csv.push(
                    0,
                    &[
                        t,
                        rec.normal,
                        rec.creep,
                        rec.lateral,
                        rec.spin,
                        ratio(rec.creep),
                        ratio(rec.lateral),
                        held as f64,
                        sliding as f64,
                        v.slip_power,
                    ],
                )?;
            }
            if v.state.k % 32 == 0 {
                pb.set_position(v.state.k as u64);
            }
            recs.push(rec);
            Ok(())
        })
        .map_err(sim_error)?;
    pb.finish_and_clear();
    let wall = clock.elapsed().as_secs_f64();
    let history = csv.finish().map_err(|e| RunError::output(&hist, e))?;
    let last = sim.last_snapshot();
    let patch = patch_nodes(
        m,
        &turned(&base, last_angle),
        last.t,
        (&x_ref, &last.state.u),
        (&rim, &slice, &last.pairs),
        sim.engine().interfaces.first(),
    );
    let last_u = slice.own_state(&last.state.u);
    let settled = m.settled();
    let rolling: Vec<Rec> = recs.iter().copied().filter(|r| r.t >= settled).collect();
    let mut lines = Vec::new();
    let built = m.stations();
    let mut summary = serde_json::json!({
        "scenario": sc.name,
        "kind": "rolling3d",
        "interrupted": stats.interrupted,
        "units": {"force": "N", "moment": "N m", "time": "s", "length": "m"},
        "mesh": m.slice.counts,
        "mesh_built": {"rings": built[0], "stations": built[1], "layers": built[2]},
        "zone": slice.zone.as_ref().map(|z| serde_json::json!({
            "zone_sectors": m.slice.zone.map(|s| s.sectors),
            "width_deg": m.slice.zone.map(|s| s.width.to_degrees()),
            "ring_growth": m.slice.zone.and_then(|s| s.growth),
            "depth_m": m.slice.zone.and_then(|s| s.depth),
            "step_deg": z.step.to_degrees(),
            "nodes_relocated_exactly": z.exact_nodes,
        })),
        "dofs": sim.engine().model.n(),
        "rim_nodes": rim.len(),
        "rail": slice.rail.as_ref().map(|r| serde_json::json!({
            "cells": r.counts,
            "length_m": r.length,
            "block": m.slice.rail.map(|b| serde_json::json!({
                "height_m": b.height, "width_m": b.width, "pitch_m": b.pitch,
                "fine_half_width_m": b.fine_half_width, "fine_depth_m": b.fine_depth,
                "growth": b.growth, "margin_m": b.margin,
            })),
            "closed": r.shift.is_some(),
            "ring": r.ring.is_some(),
            "stations": r.shift.as_ref().map(|(sym, _)| sym.count()),
        })),
        "coupling": m.slice.coupling,
        "steps": recs.len(),
        "h_s": h,
        "omega_rad_s": m.slice.omega,
        "speed_m_s": m.slice.omega * slice.base.line.radius,
        "speed_km_h": 3.6 * m.slice.omega * m.slice.radius,
        "spun_radius_m": slice.spun_radius,
        "creepages": {"longitudinal": m.slice.creepages[0], "lateral": m.slice.creepages[1], "spin_per_m": m.slice.creepages[2]},
        "friction": mu,
        "friction_law": falling.map(|l| serde_json::json!({
            "static": l.static_mu, "kinetic": l.kinetic, "stribeck_velocity_m_s": l.velocity,
            "memory_um": 1e6 * l.memory,
        })),
        "wall_time_s": wall,
        "seconds_per_step": wall / recs.len().max(1) as f64,
        "cost": cost_record(&sim, &stats, (setup_s, wall), (opts.par().count(), slice.base.line.radius * m.slice.omega, h)),
        "counters": stats,
    });
    crate::run::provenance::stamp_provenance(&mut summary, sc);
    // The rim pitch's passage through the patch: the frequency at which the discrete rim
    // modulates the forces (the zone's pitch, else the mesh's sectors).
    let sectors = m.slice.zone.map_or(m.slice.counts[1], |z| z.sectors) as f64;
    let pitch_passage = m.slice.omega * sectors / std::f64::consts::TAU;
    let mut steady_value = f64::NAN;
    let mut hertz_fig = None;
    if rolling.len() >= 8 {
        let half = &rolling[rolling.len() / 2..];
        let mean = |f: &dyn Fn(&Rec) -> f64| half.iter().map(f).sum::<f64>() / half.len() as f64;
        let n = mean(&|r| r.normal);
        let q = mean(&|r| r.creep);
        let ql = mean(&|r| r.lateral);
        let mz = mean(&|r| r.spin);
        let per = |x: f64| {
            if mu > 0.0 && n > 0.0 {
                x / (mu * n)
            } else {
                0.0
            }
        };
        let ratio_q = quarters(&rolling, |r| per(r.creep));
        let ratio_l = quarters(&rolling, |r| per(r.lateral));
        let normal_q = quarters(&rolling, |r| r.normal);
        let change = [
            (ratio_q[3] - ratio_q[2]).abs(),
            (ratio_l[3] - ratio_l[2]).abs(),
            ((normal_q[3] - normal_q[2]) / normal_q[3].abs().max(f64::MIN_POSITIVE)).abs(),
        ];
        let reached =
            change[0] < STEADY_TOLERANCE && change[1] < STEADY_TOLERANCE && change[2] < 0.01;
        let extrapolated = steady_ratio([ratio_q[1], ratio_q[2], ratio_q[3]]);
        steady_value = extrapolated.map_or(per(q), |e| e.0);
        let line = &slice.base.line;
        let rho = line.radius - line.flattening.depth;
        // Two bodies of one material: half the modulus of one on a rigid base.
        let pair = if slice.rail.is_some() { 2.0 } else { 1.0 };
        let hertz3d = m.slice.crown.and_then(|rc| {
            let e = &m.slice.material;
            let e_star = e.young / (1.0 - e.poisson * e.poisson) / pair;
            crate::contact::hertz::Hertz::from_radii(slice.spun_radius, rc, e_star, n).ok()
        });
        let (a, p0) = match &hertz3d {
            None => hertz_2d(
                n / m.slice.thickness,
                m.slice.radius,
                m.slice.material.young / pair,
            ),
            Some(hz) => (hz.semi_axes_xy().0, hz.peak_pressure),
        };
        if let Some(hz) = &hertz3d {
            summary["hertz3d"] = hertz3d_summary(m, hz, &patch, q, pair);
            hertz_fig = Some((hz.semi_axes_xy().0, hz.peak_pressure));
        }
        let stick = half
            .iter()
            .map(|r| (r.held - r.sliding.min(r.held)) as f64)
            .sum::<f64>()
            / half.len() as f64;
        let slip = half.iter().map(|r| r.sliding as f64).sum::<f64>() / half.len() as f64;
        let held = half.iter().map(|r| r.held as f64).sum::<f64>() / half.len() as f64;
        // Each step's Q / (mu N), as history.csv writes it.
        let ratio_of = |rs: &[Rec]| {
            rs.iter()
                .map(|r| r.per_mu_n(r.creep, mu).unwrap_or(0.0))
                .collect::<Vec<_>>()
        };
        let ripple = Ripple::of(&ratio_of(half), &ratio_of(&rolling), h);
        let share_of = |rs: &[Rec]| {
            rs.iter()
                .map(|r| r.sliding.min(r.held) as f64 / r.held.max(1) as f64)
                .collect::<Vec<_>>()
        };
        let share_rms = crate::growth::spectrum::rms(&share_of(half));
        summary["steady"] = serde_json::json!({
            "from_s": settled,
            "reached": reached,
            "window_changes": {"traction_ratio": change[0], "lateral_ratio": change[1], "normal_relative": change[2]},
            "normal_force_N": n,
            "creep_force_N": q,
            "lateral_force_N": ql,
            "spin_moment_N_m": mz,
            "traction_ratio": per(q),
            "lateral_ratio": per(ql),
            "traction_ratio_windows": ratio_q,
            "traction_ratio_ripple": ripple.rms,
            "ripple_peak_hz": ripple.peak.map(|p| p.0),
            "ripple_peak_amplitude": ripple.peak.map(|p| p.1),
            "pitch_passage_hz": pitch_passage,
            "slip_share": if held > 0.0 { slip / held } else { 0.0 },
            "slip_share_ripple": share_rms,
        });
        let xi_r = crate::kinds::wheel::run::traction::creepage_undeformed(
            m.slice.creepages[0],
            rho,
            slice.spun_radius,
        );
        summary["traction"] = serde_json::json!({
            "creepage": m.slice.creepages[0],
            "creepage_undeformed": xi_r,
            "normal": n,
            "traction": q,
            "traction_ratio": per(q),
            "traction_ratio_steady": steady_value,
            "transient_decay": extrapolated.map(|e| e.1),
            "lateral_ratio": per(ql),
            "spin_moment": mz,
            "friction": mu,
            "radius": m.slice.radius,
            "hertz_half_width": a,
            "hertz_peak_pressure": p0,
            "mean_stick_nodes": stick,
            "mean_slip_nodes": slip,
        });
        let reference_line = m.reference.as_ref().map(|rc| {
            if falling.is_some() {
                // The reference is Coulomb's curve, at one coefficient.
                return format!(
                    "{}: the reference ({}) is Coulomb's creep curve: not compared under a coefficient falling with the slip speed (contact.friction_kinetic)",
                    run.label,
                    rc.name()
                );
            }
            // The reference's creepage unit: mu a / R, a Hertz's semi-axis along the rolling.
            let x = xi_r / (mu * a / m.slice.radius);
            summary["traction"]["reference"] = rc.to_json(x);
            match rc.at(x) {
                Some(y) => format!(
                    "{}: the reference ({}) at this creepage ({} mu a / R on the undeformed radius): Q/(mu N) = {}; this run's steady ratio minus it: {:+.4}",
                    run.label,
                    rc.name(),
                    sig(x, 4),
                    sig(y, 4),
                    steady_value - y
                ),
                None => format!(
                    "{}: this creepage ({} mu a / R on the undeformed radius) is outside the reference's ({})",
                    run.label,
                    sig(x, 4),
                    rc.name()
                ),
            }
        });
        lines.push(format!(
            "{}: N = {} kN, Q/(mu N) = {} (steady {}), Q_y/(mu N) = {}, M_z = {} N m over the last {} ms; steady state {} (windows differ by {:.1e}); {} stick, {} slip nodes",
            run.label,
            sig(n / 1e3, 5),
            sig(per(q), 4),
            sig(steady_value, 4),
            sig(per(ql), 3),
            sig(mz, 4),
            sig(1e3 * (half[half.len() - 1].t - half[0].t), 3),
            if reached { "reached" } else { "NOT reached (roll longer: rolling.turns)" },
            change[0].max(change[1]),
            sig(stick, 3),
            sig(slip, 3),
        ));
        lines.extend(reference_line);
    } else {
        lines.push(format!(
            "{}: the run ended before {} ms of rolling after the flattening's settling: no steady figures",
            run.label,
            sig(1e3 * settled, 3)
        ));
    }
    lines.push(format!(
        "{} steps of {} s on {} unknowns in {:.1} s ({:.3} s a step)",
        recs.len(),
        h,
        sim.engine().model.n(),
        wall,
        wall / recs.len().max(1) as f64
    ));
    let series = recs
        .iter()
        .map(|r| {
            let per = |x: f64| r.per_mu_n(x, mu).unwrap_or(f64::NAN);
            [r.t, r.normal, per(r.creep), per(r.lateral)]
        })
        .collect();
    Ok(Results {
        kind: "rolling3d",
        summary,
        history,
        contact_nodes: None,
        traction_history: None,
        rim_profile: None,
        fields: Fields::default(),
        lines,
        interrupted: stats.interrupted,
        warnings: Vec::new(),
        plots: sc.plots,
        detail: Detail::Own(Box::new(Rolling3dFiles {
            mesh,
            u: last_u,
            patch,
            mu,
            falling: falling.is_some(),
            series,
            settled,
            steady_ratio: steady_value,
            thickness: m.slice.thickness,
            hertz: hertz_fig,
        })),
    })
}

/// Hertz's ellipse of a crowned base at the steady normal force `hz` (the wheel's rolling
/// radius along the rolling direction, the crown across it, `E* = E / (1 - nu^2)` on the
/// rigid base), the last step's semi-axes from the patch's second moments of the nodal
/// forces (`a = sqrt(5 sum f s^2 / sum f)`, exact for Hertz's pressure), and the scale of
/// Kalker's creep coefficients, `G c^2` with `c = sqrt(a b)` and `G` the pair's combined
/// modulus `2 / (1/G_1 + 1/G_2)`, `2 G_1` on a rigid base and `G_1` on the elastic rail of
/// the wheel's material (`pair` = 2: Hertz's `E*` halved too): `C_11 = -dF_x / (G c^2 d xi)`
/// from two creepages (the creep force `q` along the rolling direction; its ratio to the
/// creepage in one run carries the free-rolling offset).
fn hertz3d_summary(
    m: &Rolling3dScenario,
    hz: &crate::contact::hertz::Hertz,
    patch: &[PatchNode],
    q: f64,
    pair: f64,
) -> serde_json::Value {
    let (ax, ay) = hz.semi_axes_xy();
    let c2 = ax * ay;
    let e = &m.slice.material;
    let g = 2.0 * e.young / (2.0 * (1.0 + e.poisson)) / pair;
    let f: f64 = patch.iter().map(|p| p.force).sum();
    let moment = |x: &dyn Fn(&PatchNode) -> f64| {
        let mean = patch.iter().map(|p| p.force * x(p)).sum::<f64>() / f;
        (5.0 * patch
            .iter()
            .map(|p| p.force * (x(p) - mean).powi(2))
            .sum::<f64>()
            / f)
            .sqrt()
    };
    let xi = m.slice.creepages[0];
    serde_json::json!({
        "a_rolling_m": ax,
        "b_lateral_m": ay,
        "c_m": c2.sqrt(),
        "peak_pressure_Pa": hz.peak_pressure,
        "approach_m": hz.approach,
        "measured_a_rolling_m": if f > 0.0 { moment(&|p| p.s) } else { f64::NAN },
        "measured_b_lateral_m": if f > 0.0 { moment(&|p| p.z) } else { f64::NAN },
        "combined_shear_modulus_Pa": g,
        "poisson": e.poisson,
        "kalker_scale_N": g * c2,
        "creep_force_over_scale_and_creepage": if xi != 0.0 { q / (g * c2 * xi) } else { f64::NAN },
    })
}

/// The rim nodes of the last step on the base's side of the wheel within three times the
/// loaded arc of the patch's centre (module docs), ordered by layer and position.
fn patch_nodes(
    m: &Rolling3dScenario,
    base: &RotatingBase,
    t: f64,
    (x_ref, u): (&[f64], &[f64]),
    (rim, slice, pairs): (&[usize], &RollingSlice, &[PairState]),
    rail: Option<&Interface>,
) -> Vec<PatchNode> {
    let fr = base.frame(t);
    let tangents = tangent_basis(3, fr.normal);
    // The wheel rolls over the base along -t_b.
    let fwd = fr.travel.map(|c| -c);
    let [_, nt, _] = m.stations();
    let pitch = 2.0 * std::f64::consts::PI * m.slice.radius / nt as f64;
    let mut all: Vec<PatchNode> = rim
        .iter()
        .enumerate()
        .zip(pairs)
        .zip(slice.rim_arc.iter().zip(&slice.rim_width))
        .map(|(((i, &node), ps), (&arc, &width))| {
            let x: [f64; 3] = std::array::from_fn(|c| x_ref[3 * node + c] + u[3 * node + c]);
            let r: [f64; 3] = std::array::from_fn(|c| x[c] - fr.p0[c]);
            let z_ref = x_ref[3 * node + 2];
            // The rim set runs through the stations, layer by layer.
            let layer = i / nt;
            let area = arc * m.slice.radius * width;
            // A crowned base's tangents tilt with its normal across the patch.
            let tg = match (rail, base.crown) {
                (Some(rail), _) => rail_directions(rail, i, t).1,
                (None, None) => tangents,
                (None, Some(_)) => tangent_basis(3, base.half_space(t, x).normal),
            };
            let q = friction_force(tg, ps);
            (
                dot(r, fr.normal).abs(),
                PatchNode {
                    s: dot(r, fwd),
                    z: z_ref - 0.5 * m.slice.thickness,
                    layer,
                    force: ps.force.max(0.0),
                    pressure: ps.force.max(0.0) / area,
                    traction: dot(q, fwd) / area,
                    lateral: q[2] / area,
                    sliding: ps.sliding,
                    node,
                },
            )
        })
        // The rim's nodes near the base (the far side of the wheel projects onto it too).
        .filter(|(d, p)| *d < 0.1 * m.slice.radius && p.s.abs() < 0.25 * m.slice.radius)
        .map(|(_, p)| p)
        .collect();
    let reach = all
        .iter()
        .filter(|p| p.pressure > 0.0)
        .map(|p| p.s.abs())
        .fold(0.0_f64, f64::max)
        .max(2.0 * pitch);
    all.retain(|p| p.s.abs() <= 3.0 * reach);
    all.sort_by(|a, b| a.layer.cmp(&b.layer).then(a.s.total_cmp(&b.s)));
    all
}

impl OwnFiles for Rolling3dFiles {
    fn save(&self, results: &Results, out: &Path) -> Result<Vec<PathBuf>, RunError> {
        let mut files = Vec::new();
        let csv = out.join("patch.csv");
        let mut text = String::from(
            "node,layer,s_mm,z_mm,pressure_MPa,traction_MPa,lateral_traction_MPa,sliding\n",
        );
        for p in &self.patch {
            text.push_str(&format!(
                "{},{},{:.6},{:.6},{:.6},{:.6},{:.6},{}\n",
                p.node,
                p.layer,
                1e3 * p.s,
                1e3 * p.z,
                1e-6 * p.pressure,
                1e-6 * p.traction,
                1e-6 * p.lateral,
                u8::from(p.sliding)
            ));
        }
        crate::output::files::write_atomic(&csv, text.as_bytes())
            .map_err(|e| RunError::output(&csv, e))?;
        files.push(csv);
        let vtu = out.join("fields.vtu");
        let n = self.mesh.n_nodes();
        let (mut pressure, mut traction) = (vec![0.0; n], vec![0.0; 3 * n]);
        for p in &self.patch {
            pressure[p.node] = 1e-6 * p.pressure;
            traction[3 * p.node] = 1e-6 * p.traction;
            traction[3 * p.node + 2] = 1e-6 * p.lateral;
        }
        write_vtu(
            &vtu,
            &self.mesh,
            Some(&self.u),
            &[
                Field {
                    name: "contact_pressure_MPa",
                    components: 1,
                    values: &pressure,
                },
                Field {
                    name: "traction_rolling_0_axle_2_MPa",
                    components: 3,
                    values: &traction,
                },
            ],
            &[],
        )
        .map_err(|e| RunError::output(&vtu, e))?;
        files.push(vtu);
        if results.plots {
            let png = out.join("rolling3d.png");
            crate::output::plot::panels(&png, &self.panels(), 3, 1, (1200, 1500))
                .map_err(|e| RunError::output(&png, e))?;
            files.push(png);
        }
        Ok(files)
    }
}
