//! `softway run` of a track scenario with the wheel ([`crate::bodies::rail::rolling`]): the elastic
//! wheel on its moving hub rolls `settle_bays` bays while its load comes on (over the first
//! half of them) and settles, then the recorded `travel_bays` centred on the track's middle.
//!
//! Files: `history.csv` (every `output.history_stride` steps: time, distance travelled, the
//! rail's abscissa under the axle, a settling flag, the contact force, the rim nodes in
//! contact, the axle's vertical displacement and its drift along the track in the ground,
//! the rail's deflection under the axle, the irregularity there, the nearest pad's force,
//! and with friction the tangential force, the slip power and the friction energy),
//! `track.png` (the contact force against the distance with the static load; the axle and
//! the rail under it; the force's spectrum against the wavelength with the sleeper spacing
//! and its harmonics, the rail elements' length and its half (the mesh's own lines), P2 and
//! pinned-pinned wavelengths at the run's speed marked and labelled; the pad forces; with
//! friction, the tangential force against `mu` times the normal force) and
//! `summary.json` (the passage's force statistics, the measured contact spring, the track's
//! frequencies, the cost per step and per metre; with friction the `traction` figures).
//!
//! **The tangential force** `tangential_force_N` is the rail's force on the wheel along the
//! direction of travel (the ground's +x): `Q = -sum F_t` over the rim's pairs, `F_t` each
//! pair's friction force along its tangent `t = (-1, 0)` on the flat rail
//! ([`crate::bodies::rail::rolling`], Friction and creepage). `Q > 0` drives the wheel forward
//! (creepage `xi > 0`), `Q < 0` brakes it. `slip_power_W` is the pairs' frictional
//! dissipation of the step ([`crate::model::PairState::slip_power`], `>= 0`),
//! `friction_energy_J` its integral since the start.

use crate::analysis::signal::{amplitude_spectrum, dominant_peak, moving_average};
use crate::bodies::rail::receptance::{frequencies, log_frequencies, p2_with, receptance, Wheel};
use crate::bodies::rail::rolling::{wheel_at_speed, Vehicle, WheelOnTrack};
use crate::bodies::wheel::{Support, WheelModel, WheelSpec};
use crate::material::Elastic;
use crate::mesh::generators::{disk_graded, disk_symmetric_rim, DiskOptions};
use crate::output::plot::{sig, Panel, Series, SeriesStyle};
use crate::run::error::RunError;
use crate::run::options::RunOptions;
use crate::run::results::Results;
use crate::scenario::{Model, Run, Scenario, TrackScenario};
use crate::simulation::Simulation;
use std::path::Path;

mod figures;
use figures::Panels;
use std::time::Instant;

/// The columns of `history.csv`: `run` (the run's label), then these.
pub const HISTORY: [(&str, &str); 15] = [
    ("t_s", "s"),
    ("distance_m", "m"),
    ("rail_x_m", "m"),
    ("settling", "1"),
    ("contact_force_N", "N"),
    ("nodes_in_contact", "1"),
    ("axle_displacement_m", "m"),
    ("axle_drift_m", "m"),
    ("rail_deflection_m", "m"),
    ("irregularity_m", "m"),
    ("pad_force_nearest_N", "N"),
    ("nearest_sleeper", "1"),
    ("tangential_force_N", "N"),
    ("slip_power_W", "W"),
    ("friction_energy_J", "J"),
];

/// The columns a run with a second wheel (`vehicle.wheelbase`) adds to [`HISTORY`]: its
/// contact force and its axle's vertical displacement (`contact_force_N` and
/// `axle_displacement_m` are the first wheel's).
pub const HISTORY_TRAILING: [(&str, &str); 2] = [
    ("trailing_contact_force_N", "N"),
    ("trailing_axle_displacement_m", "m"),
];

/// One run's key figures (`summary.json`, `runs[i]`).
#[derive(Debug, Clone, serde::Serialize)]
struct RollingSummary {
    label: String,
    treatment: String,
    h_s: f64,
    steps: usize,
    speed_m_s: f64,
    speed_km_h: f64,
    start_m: f64,
    settle_m: f64,
    travel_m: f64,
    rim_nodes: usize,
    rim_pitch_m: f64,
    steps_per_rim_node: f64,
    wheel_dofs: usize,
    track_dofs: usize,
    wheel_mass_kg: f64,
    axle_mass_kg: f64,
    static_load_n: f64,
    contact_force_mean_n: f64,
    contact_force_min_n: f64,
    contact_force_max_n: f64,
    contact_force_std_n: f64,
    mean_over_static_minus_1: f64,
    dynamic_factor_max: f64,
    nodes_in_contact_mean: f64,
    axle_displacement_mean_m: f64,
    rail_deflection_mean_m: f64,
    /// The measured contact spring, N/m; `None` (null) when the passage's compression is
    /// below what the contact resolves (a wheel carrying about no load).
    contact_stiffness_n_m: Option<f64>,
    axle_drift_max_m: f64,
    sleeper_passing_hz: f64,
    node_passing_hz: f64,
    dominant_frequency_hz: Option<f64>,
    dominant_amplitude_n: Option<f64>,
    p2_hz: Option<f64>,
    p2_above_sleeper_hz: Option<f64>,
    p2_hertz_hz: Option<f64>,
    pinned_pinned_hz: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    traction: Option<TractionSummary>,
    /// The second wheel's passage (`vehicle.wheelbase`).
    #[serde(skip_serializing_if = "Option::is_none")]
    trailing: Option<TrailingSummary>,
    wall_time_s: f64,
    time_per_step_us: f64,
    time_per_metre_s: f64,
    interrupted: bool,
}

/// The second wheel's passage (`summary.json`, `runs[i].trailing`): its contact force over
/// the same whole bays as the first wheel's, which it crosses `wheelbase` later.
#[derive(Debug, Clone, Copy, serde::Serialize)]
struct TrailingSummary {
    wheelbase_m: f64,
    contact_force_mean_n: f64,
    contact_force_min_n: f64,
    contact_force_max_n: f64,
    contact_force_std_n: f64,
    axle_displacement_mean_m: f64,
}

/// The friction figures of a run with friction (`summary.json`, `runs[i].traction`; the
/// means over the passage's whole bays, as the contact force's).
#[derive(Debug, Clone, Copy, serde::Serialize)]
struct TractionSummary {
    /// The static friction coefficient.
    friction: f64,
    /// The creepage `xi`, referred to the spun rim's radius.
    creepage: f64,
    /// The spun rim's radius `R_s`, m.
    radius: f64,
    /// The mean normal (contact) force `P`, N.
    normal: f64,
    /// The mean tangential force `Q` on the wheel along the travel, N (module docs).
    traction: f64,
    /// `Q / (mu P)`.
    traction_ratio: f64,
    /// The imposed slip speed `V xi` of a rim node at rest in the wheel's frame, m/s.
    slip_speed_imposed: f64,
    /// The mean slip power over the passage, W.
    slip_power_mean: f64,
    /// The friction energy at the end, J.
    friction_energy: f64,
    /// The least `slip_power / |F_t|` of any pair at any step, m/s (`>= 0` up to round-off).
    min_slip_speed: f64,
    /// The largest decrease of the friction energy from one step to the next, J.
    max_friction_energy_drop: f64,
    /// The axle's mean drift along the track over the passage, m (`Q / k_s` in the steady
    /// state).
    axle_drift_mean_m: f64,
}

/// One step's record.
#[derive(Debug, Clone, Copy)]
struct Rec {
    distance: f64,
    settling: bool,
    force: f64,
    held: usize,
    axle_y: f64,
    axle_x: f64,
    rail_w: f64,
    pad: f64,
    tangential: f64,
    slip_power: f64,
    friction_energy: f64,
    /// The second wheel's contact force and axle's vertical displacement (NaN with one).
    trailing_force: f64,
    trailing_axle_y: f64,
}

fn track_of(model: &Model) -> &TrackScenario {
    model
        .get::<TrackScenario>()
        .expect("track job on a track scenario")
}

/// The wheel of `ts` turning at `V (1 + xi) / R_s` (`R_s` the spun rim's radius: two
/// rebuilds; `xi` the creepage).
pub(crate) fn wheel_model(ts: &TrackScenario) -> Result<WheelModel, String> {
    wheel_model_with(ts, None)
}

/// The wheel of [`wheel_model`] with its rim nodes moved radially by `rim_profile` (m, one
/// height per rim node in the rim's order; `None`: the smooth wheel): a wheel turned to
/// that shape, stress-free (as the rigid-base wheel's growth study moves its rim,
/// [`crate::kinds::wheel::growth`]).
pub(crate) fn wheel_model_with(
    ts: &TrackScenario,
    rim_profile: Option<&[f64]>,
) -> Result<WheelModel, String> {
    let v = &ts.vehicle;
    let w = &v.wheel;
    let opts = DiskOptions {
        hub: Some(w.hub_radius),
        grading: w.grading,
    };
    let mut mesh = match w.rim_band {
        None => disk_graded(v.wheel_radius, w.rim_nodes, opts),
        Some(band) => disk_symmetric_rim(v.wheel_radius, w.rim_nodes, band, opts),
    }
    .map_err(|e| format!("the wheel's mesh: {e}"))?;
    if let Some(z) = rim_profile {
        let rim = crate::bodies::wheel::rim_nodes(&mesh);
        if rim.len() != z.len() {
            return Err(format!(
                "the wheel's profile has {} heights, its rim {} nodes",
                z.len(),
                rim.len()
            ));
        }
        for (&node, &dz) in rim.iter().zip(z) {
            let (x, y) = (mesh.coords[2 * node], mesh.coords[2 * node + 1]);
            let s = (x.hypot(y) + dz) / x.hypot(y);
            mesh.coords[2 * node] = x * s;
            mesh.coords[2 * node + 1] = y * s;
        }
    }
    let spec = WheelSpec {
        radius: v.wheel_radius,
        thickness: w.thickness,
        plane: w.plane,
        support: Support::Hub {
            radius: w.hub_radius,
        },
        material: Elastic { ..w.material },
        ..WheelSpec::paper()
    };
    wheel_at_speed(mesh, spec, v.speed * (1.0 + v.creepage)).map_err(|e| {
        format!(
            "`vehicle.speed` = {} m/s ({:.1} km/h) with `vehicle.creepage` = {}: {e}",
            v.speed,
            3.6 * v.speed,
            v.creepage
        )
    })
}

/// `softway run` of a track scenario with the wheel (module docs).
///
/// # Errors
/// [`RunError`]: a model that cannot be built, a failed run, a file that cannot be written.
pub(crate) fn record(
    sc: &Scenario,
    stream: Option<&Path>,
    opts: &RunOptions,
) -> Result<Results, RunError> {
    let two_wheels = sc
        .runs
        .iter()
        .any(|r| track_of(&r.model).vehicle.wheelbase.is_some());
    let mut columns = HISTORY.to_vec();
    if two_wheels {
        columns.extend(HISTORY_TRAILING);
    }
    let (mut csv, hist) = crate::run::history::keyed_history(sc, stream, &columns)?;
    let at = |e| RunError::output(&hist, e);
    let first = track_of(&sc.runs[0].model);
    let mut panels = Panels::new(first);
    let mut sums = Vec::new();
    let mut interrupted = false;
    for (ri, run) in sc.runs.iter().enumerate() {
        let ts = track_of(&run.model);
        let mut push = |k: usize, row: &[f64]| {
            if k % sc.history_stride.max(1) == 0 {
                csv.push(ri as u32, row)?;
            }
            Ok(())
        };
        let (sum, recs) = roll(sc, run, ts, opts, (columns.len(), &mut push))?;
        interrupted |= sum.interrupted;
        panels.add(ri, sc.runs.len(), &run.label, ts, &sum, &recs);
        sums.push(sum);
        if interrupted {
            break;
        }
    }
    let history = csv.finish().map_err(at)?;
    // Room for the spectrum's legend under its axes (issue 48).
    let size = if panels.traction.is_some() {
        (1400, 2350)
    } else {
        (1400, 1900)
    };
    let mut json = serde_json::json!({
        "scenario": sc.name, "kind": "track", "vehicle_model": "wheel", "interrupted": interrupted,
        "units": {"time": "s", "length": "m", "force": "N", "frequency": "Hz", "stiffness": "N/m", "mass": "kg"},
        "signs": "displacements and deflections up positive; contact and pad forces in compression",
        "parameters": super::moving::parameters(first),
        "runs": sums,
    });
    super::moving::lift_first_run(&mut json, &sums[0]);
    crate::run::provenance::stamp_provenance(&mut json, sc);
    let lines = sums.iter().map(screen_line).collect();
    Ok(Results::with_panels(
        ("track", json),
        history,
        lines,
        interrupted,
        sc.plots,
        ("track.png", panels.into_vec(), size),
    ))
}

/// The wheel on the track of run `run` of `sc` ready to roll: the model, its simulation (the
/// run's treatment, friction, threads and guard set) and the number of steps. `profile`
/// replaces the scenario's irregularity when given (a growth study's rail profile).
pub(crate) fn passage(
    sc: &Scenario,
    run: &Run,
    ts: &TrackScenario,
    opts: &RunOptions,
    profile: Option<crate::contact::profile::Profile>,
) -> Result<(WheelOnTrack, Simulation, usize), RunError> {
    let input = |e: String| RunError::input(&sc.path, format!("run `{}`: {e}", run.label));
    let v = &ts.vehicle;
    // A creepage slips the rim on the rail, and only friction turns the slip into a force:
    // without it the run is free rolling whatever the creepage (the rigid-base wheel refuses
    // the same, `rolling.creepage`).
    if v.creepage != 0.0 && run.friction.is_none_or(|law| !law.is_active()) {
        return Err(input(format!(
            "`vehicle.creepage` = {}: a creepage transmits a force only through friction: set contact.friction > 0 (with vehicle.suspension_stiffness > 0 and time.gamma > 0, as scenarios/track-traction.toml) or remove vehicle.creepage",
            v.creepage
        )));
    }
    let wheel = wheel_model(ts).map_err(input)?;
    passage_of(sc, run, ts, opts, profile, wheel)
}

/// [`passage`] of the wheel `wheel` (built by [`wheel_model_with`]).
pub(crate) fn passage_of(
    sc: &Scenario,
    run: &Run,
    ts: &TrackScenario,
    opts: &RunOptions,
    profile: Option<crate::contact::profile::Profile>,
    wheel: WheelModel,
) -> Result<(WheelOnTrack, Simulation, usize), RunError> {
    let input = |e: String| RunError::input(&sc.path, format!("run `{}`: {e}", run.label));
    let v = &ts.vehicle;
    let settle_time = 0.5 * ts.settle_distance() / v.speed;
    let vehicle = Vehicle {
        unsprung_mass: v.unsprung_mass,
        axle_load: v.axle_load,
        speed: v.speed,
        suspension_stiffness: v.suspension_stiffness,
        suspension_damping: v.suspension_damping,
        gravity: v.gravity,
        settle: settle_time,
        creepage: v.creepage,
        wheelbase: v.wheelbase,
    };
    let start = ts.start();
    let h = run.params.h;
    let steps = (ts.run_distance() / (v.speed * h)).round().max(1.0) as usize;
    let profile = match profile {
        Some(p) => Some(p),
        None => ts
            .irregularity
            .as_ref()
            .map(|irr| irr.profile((start, start + ts.run_distance() + 1.0)))
            .transpose()
            .map_err(|e| input(e.to_string()))?,
    };
    let wot = WheelOnTrack::new(wheel, &ts.spec, vehicle, start, profile)
        .map_err(|e| input(e.to_string()))?;
    let mut problem = wot.problem(run.integrator, h, steps);
    problem.treatment = run.contact;
    problem.friction = run.friction;
    let sim = Simulation::with_settings(problem, opts.settings()).map_err(|source| {
        RunError::Simulation {
            run: run.label.clone(),
            source,
        }
    })?;
    Ok((wot, sim, steps))
}

/// Where [`roll`] sends each step's history row: `(step, columns)`.
type RowSink<'a> = dyn FnMut(usize, &[f64]) -> std::io::Result<()> + 'a;

/// Runs one wheel passage, calling `row(k, columns)` at every step.
fn roll(
    sc: &Scenario,
    run: &Run,
    ts: &TrackScenario,
    opts: &RunOptions,
    (width, row): (usize, &mut RowSink),
) -> Result<(RollingSummary, Vec<Rec>), RunError> {
    let (wot, mut sim, steps) = passage(sc, run, ts, opts, None)?;
    let start = ts.start();
    let sim_error = |source| RunError::Simulation {
        run: run.label.clone(),
        source,
    };
    let pb = crate::run::options::progress_bar(steps as u64, &run.label, opts);
    let mut recs: Vec<Rec> = Vec::with_capacity(steps + 1);
    let clock = Instant::now();
    let profile_at = |x: f64| {
        wot.interface
            .segment_search()
            .and_then(|s| s.profile())
            .map_or(0.0, |p| p.at(x).0)
    };
    // The dissipation's checks over every pair and step (module docs).
    let (mut min_slip_speed, mut max_drop, mut last_energy) = (f64::INFINITY, 0.0_f64, 0.0);
    let stats = sim
        .run(opts.cancel.flag(), |s| {
            let st = s.state;
            let (t, u, vel) = (st.t, &st.state.u, &st.state.v);
            let x = wot.under_axle(t);
            let axle = wot.axle_ground(t, u);
            let nearest = wot.sleeper_near(x);
            let (first, second) = st.pairs.split_at(wot.rim_pairs().min(st.pairs.len()));
            let trailing_axle = wot.trailing_axle_ground(t, u);
            let mut tangential = 0.0;
            for ps in &st.pairs {
                tangential -= ps.tangential_force;
                if ps.tangential_force != 0.0 {
                    min_slip_speed = min_slip_speed.min(ps.slip_power / ps.tangential_force.abs());
                }
            }
            max_drop = max_drop.max(last_energy - s.friction_dissipated);
            last_energy = s.friction_dissipated;
            let rail_w = wot
                .rail_deflection(x, u)
                .map_err(|e| std::io::Error::other(e.to_string()))?;
            let rec = Rec {
                distance: x - start,
                settling: x - start < ts.settle_distance(),
                force: first.iter().map(|p| p.force).sum(),
                held: s.held,
                axle_y: axle[1],
                axle_x: axle[0],
                rail_w,
                pad: wot.pad_force(nearest, u, vel),
                tangential,
                slip_power: s.slip_power,
                friction_energy: s.friction_dissipated,
                trailing_force: trailing_axle
                    .map_or(f64::NAN, |_| second.iter().map(|p| p.force).sum()),
                trailing_axle_y: trailing_axle.map_or(f64::NAN, |a| a[1]),
            };
            let columns = [
                t,
                rec.distance,
                x,
                f64::from(u8::from(rec.settling)),
                rec.force,
                rec.held as f64,
                rec.axle_y,
                rec.axle_x,
                rec.rail_w,
                profile_at(x),
                rec.pad,
                nearest as f64,
                rec.tangential,
                rec.slip_power,
                rec.friction_energy,
                rec.trailing_force,
                rec.trailing_axle_y,
            ];
            row(st.k, &columns[..width.min(columns.len())])?;
            if st.k % 64 == 0 {
                pb.set_position(st.k as u64);
            }
            recs.push(rec);
            Ok(())
        })
        .map_err(sim_error)?;
    pb.finish_and_clear();
    let wall = clock.elapsed().as_secs_f64();
    let mut sum = summarise(run, ts, &wot, &recs, (stats.interrupted, wall))?;
    if let Some(t) = sum.traction.as_mut() {
        t.min_slip_speed = if min_slip_speed.is_finite() {
            min_slip_speed
        } else {
            0.0
        };
        t.max_friction_energy_drop = max_drop;
    }
    Ok((sum, recs))
}

/// The passage's figures from the records after settling (module docs).
fn summarise(
    run: &Run,
    ts: &TrackScenario,
    wot: &WheelOnTrack,
    recs: &[Rec],
    (interrupted, wall): (bool, f64),
) -> Result<RollingSummary, RunError> {
    let v = &ts.vehicle;
    let s = ts.spec.spacing;
    let h = run.params.h;
    let load = wot.vehicle.static_load();
    let passage: Vec<&Rec> = recs.iter().filter(|r| !r.settling).collect();
    // Whole sleeper bays of the passage for the means.
    // (With a second wheel the passage runs on by the wheelbase: the first wheel's figures
    // stay those of its recorded bays.)
    let bays = (passage.len() as f64 * h * v.speed / s)
        .floor()
        .min(v.travel_bays as f64)
        .max(1.0);
    let whole = ((bays * s / (v.speed * h)).round() as usize).min(passage.len());
    let w = &passage[..whole];
    let n = w.len().max(1) as f64;
    let mean = |f: &dyn Fn(&Rec) -> f64| w.iter().map(|r| f(r)).sum::<f64>() / n;
    let force = mean(&|r| r.force);
    let std = (w.iter().map(|r| (r.force - force).powi(2)).sum::<f64>() / n).sqrt();
    let (fmin, fmax) = w
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), r| {
            (a.min(r.force), b.max(r.force))
        });
    let axle = mean(&|r| r.axle_y);
    let rail = mean(&|r| r.rail_w);
    // The second wheel over the same bays: the records `wheelbase` further on.
    let trailing = v.wheelbase.map(|l| {
        let lag = (l / (v.speed * h)).round() as usize;
        let first = recs.len() - passage.len();
        let w2: Vec<&Rec> = recs.iter().skip(first + lag).take(whole).collect();
        let n2 = w2.len().max(1) as f64;
        let f2 = w2.iter().map(|r| r.trailing_force).sum::<f64>() / n2;
        let (lo, hi) = w2
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), r| {
                (a.min(r.trailing_force), b.max(r.trailing_force))
            });
        TrailingSummary {
            wheelbase_m: l,
            contact_force_mean_n: f2,
            contact_force_min_n: lo,
            contact_force_max_n: hi,
            contact_force_std_n: (w2
                .iter()
                .map(|r| (r.trailing_force - f2).powi(2))
                .sum::<f64>()
                / n2)
                .sqrt(),
            axle_displacement_mean_m: w2.iter().map(|r| r.trailing_axle_y).sum::<f64>() / n2,
        }
    });
    let forces: Vec<f64> = w.iter().map(|r| r.force).collect();
    // The strongest line below half the rim's node-passing frequency (the ripple of the
    // rim's discretisation above it).
    let node_passing = 1.0 / ts.rim_passage();
    let peak = (forces.len() >= 16)
        .then(|| {
            let mut spec = amplitude_spectrum(&forces, h);
            let keep = spec
                .frequency_hz
                .iter()
                .take_while(|&&f| f < 0.5 * node_passing)
                .count();
            spec.frequency_hz.truncate(keep);
            spec.amplitude.truncate(keep);
            dominant_peak(&spec, 0.2 * v.speed / s)
        })
        .flatten();
    // The contact spring the passage measured: the static load over the mean compression
    // of the wheel and the contact (the rail's deflection less the axle's). A compression
    // the contact cannot resolve (below its closing tolerance, 1e-9 of the radius: a wheel
    // carrying about no load) measures no spring (a load of 1 mN gave -4.6e3 N/m).
    let compression = rail - axle;
    let k_c = (compression > 1e-9 * v.wheel_radius)
        .then(|| load / compression)
        .filter(|k| k.is_finite() && *k > 0.0);
    let traction = run.friction.filter(|law| law.is_active()).map(|law| {
        let q = mean(&|r| r.tangential);
        TractionSummary {
            friction: law.static_mu,
            creepage: v.creepage,
            radius: wot.rim_radius,
            normal: force,
            traction: q,
            traction_ratio: q / (law.static_mu * force),
            slip_speed_imposed: v.speed * v.creepage,
            slip_power_mean: mean(&|r| r.slip_power),
            friction_energy: recs.last().map_or(0.0, |r| r.friction_energy),
            min_slip_speed: 0.0,
            max_friction_energy_drop: 0.0,
            axle_drift_mean_m: mean(&|r| r.axle_x),
        }
    });
    // The track's frequencies: the receptance's (Hertz's 3D spring) and P2 on the measured
    // contact spring.
    let err = |e: crate::bodies::rail::TrackError| RunError::Simulation {
        run: run.label.clone(),
        source: crate::simulation::SimError::Unsupported(e.to_string()),
    };
    let track = ts.spec.build().map_err(err)?;
    let r = receptance(&track, &log_frequencies(20.0, 3000.0, 200)).map_err(err)?;
    let f = frequencies(
        &track,
        &r,
        &Wheel {
            unsprung_mass: v.unsprung_mass,
            load: v.axle_load,
            radius: v.wheel_radius,
        },
    )
    .map_err(err)?;
    let (p2, p2_above) = if let Some(k_c) = k_c {
        (
            p2_with(&track, r.mid_span_x, v.unsprung_mass, k_c, 120).map_err(err)?,
            p2_with(&track, r.above_sleeper_x, v.unsprung_mass, k_c, 120).map_err(err)?,
        )
    } else {
        (None, None)
    };
    let rim = v.wheel.rim_nodes;
    let wheels = if wot.trailing.is_some() { 2 } else { 1 };
    let steps = recs.len().saturating_sub(1);
    let travelled = recs.last().map_or(0.0, |r| r.distance);
    Ok(RollingSummary {
        label: run.label.clone(),
        treatment: run.contact.name(),
        h_s: h,
        steps,
        speed_m_s: v.speed,
        speed_km_h: 3.6 * v.speed,
        start_m: ts.start(),
        settle_m: ts.settle_distance(),
        travel_m: ts.travel() - ts.settle_distance(),
        rim_nodes: rim,
        rim_pitch_m: 2.0 * std::f64::consts::PI * wot.rim_radius / rim as f64,
        steps_per_rim_node: ts.rim_passage() / h,
        wheel_dofs: wot.joined.first_dof[1],
        // (Each wheel's dofs and its axle's two out: the rail's and the sleepers'.)
        track_dofs: wot.joined.model.n() - wheels * (wot.joined.first_dof[1] + 2),
        wheel_mass_kg: wot.wheel_mass,
        axle_mass_kg: wot.axle_mass,
        static_load_n: load,
        contact_force_mean_n: force,
        contact_force_min_n: fmin,
        contact_force_max_n: fmax,
        contact_force_std_n: std,
        mean_over_static_minus_1: force / load - 1.0,
        dynamic_factor_max: fmax / load,
        nodes_in_contact_mean: mean(&|r| r.held as f64),
        axle_displacement_mean_m: axle,
        rail_deflection_mean_m: rail,
        contact_stiffness_n_m: k_c,
        axle_drift_max_m: recs.iter().map(|r| r.axle_x.abs()).fold(0.0, f64::max),
        sleeper_passing_hz: v.speed / s,
        node_passing_hz: node_passing,
        dominant_frequency_hz: peak.map(|p| p.0),
        dominant_amplitude_n: peak.map(|p| p.1),
        p2_hz: p2,
        p2_above_sleeper_hz: p2_above,
        p2_hertz_hz: f.p2_hz,
        pinned_pinned_hz: f.pinned_pinned_hz,
        traction,
        trailing,
        wall_time_s: wall,
        time_per_step_us: 1e6 * wall / steps.max(1) as f64,
        time_per_metre_s: wall / travelled.max(1e-12),
        interrupted,
    })
}

/// The screen line of one run.
fn screen_line(s: &RollingSummary) -> String {
    let hz = |f: Option<f64>| f.map_or_else(|| "-".to_string(), |f| format!("{f:.1} Hz"));
    let traction = s.traction.map_or_else(String::new, |t| {
        format!(
            "; creepage {:+.3}%: tangential force {:+.2} kN mean, Q/(mu P) = {:+.4}",
            1e2 * t.creepage,
            1e-3 * t.traction,
            t.traction_ratio
        )
    });
    let trailing = s.trailing.map_or_else(String::new, |t| {
        format!(
            "; the second wheel ({} m behind) {:.2} kN mean, {:.1}-{:.1} kN",
            t.wheelbase_m,
            1e-3 * t.contact_force_mean_n,
            1e-3 * t.contact_force_min_n,
            1e-3 * t.contact_force_max_n
        )
    });
    format!(
        "{:<10} {:.1} km/h over {:.1} m: contact force {:.2} kN mean ({:+.2}% of the static {:.2} kN), {:.1}-{:.1} kN, strongest line {} (sleeper passing {:.1} Hz); P2 {} on the measured contact spring {}{traction}{trailing}; {:.2} ms a step, {:.2} s a metre",
        s.label,
        s.speed_km_h,
        s.travel_m,
        1e-3 * s.contact_force_mean_n,
        1e2 * s.mean_over_static_minus_1,
        1e-3 * s.static_load_n,
        1e-3 * s.contact_force_min_n,
        1e-3 * s.contact_force_max_n,
        hz(s.dominant_frequency_hz),
        s.sleeper_passing_hz,
        hz(s.p2_hz),
        s.contact_stiffness_n_m.map_or_else(
            || "- (no compression measured)".to_string(),
            |k| format!("{k:.3e} N/m")
        ),
        1e-3 * s.time_per_step_us,
        s.time_per_metre_s,
    )
}
