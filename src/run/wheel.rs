//! The rolling wheel (paper §4, Figs. 10-17): settling, then turns; the contact force over
//! the turns, its spectrum and oscillations per turn, the turn-averaged `J2`, and the
//! velocity field in successive stages.
//!
//! **Oscillations per turn (counting rule).** Within each full turn after settling, the
//! total contact force is smoothed by a centred moving average over the node-passage
//! period `2 pi / (omega N_rim)` (the base passes one rim node in that time: a ripple of the
//! mesh, not of the wheel), then every local maximum whose prominence is at least 10% of the
//! turn's force range counts as one oscillation
//! ([`count_oscillations`]).

use super::{progress_bar, RunError, RunOptions, RunReport, INTERRUPT};
use crate::analysis::signal::{
    amplitude_spectrum, count_oscillations, dominant_peak, moving_average, resample_uniform,
};
use crate::mesh::generators::disk_rings;
use crate::mesh::gmsh::read_msh;
use crate::mesh::Mesh;
use crate::output::files::{write_json, CsvWriter};
use crate::output::plot::{
    line_plot, mesh_color_map_with, mesh_vector_fields, MeshColorMap, MeshOptions, MeshVectorField,
    Panel, Series, SeriesStyle,
};
use crate::output::vtk::{write_vtu, Field, PvdWriter};
use crate::scenario::{MeshSource, Model, Run, Scenario, WheelScenario};
use crate::simulation::Simulation;
use crate::wheel::WheelModel;
use serde::Serialize;
use std::f64::consts::PI;
use std::path::Path;
use std::time::Instant;

/// Key figures of a wheel run (`summary.json`).
#[derive(Debug, Clone, Serialize)]
pub struct WheelSummary {
    /// Label.
    pub label: String,
    /// Wheel spin, rad/s.
    pub omega: f64,
    /// Rim speed `omega R`, km/h.
    pub speed_km_h: f64,
    /// Time step, s.
    pub h: f64,
    /// `alpha`.
    pub alpha: f64,
    /// `gamma` while rolling.
    pub gamma: f64,
    /// Degrees of freedom.
    pub dofs: usize,
    /// Nodes, triangles.
    pub nodes: usize,
    /// Triangles.
    pub triangles: usize,
    /// Turns rolled after settling.
    pub turns: f64,
    /// Steps.
    pub steps: usize,
    /// Mean contact force over the rolling phase, N.
    pub mean_contact_force: f64,
    /// Largest contact force over the rolling phase, N.
    pub max_contact_force: f64,
    /// Smallest contact force over the rolling phase, N.
    pub min_contact_force: f64,
    /// Mean number of rim nodes held.
    pub mean_nodes_in_contact: f64,
    /// Oscillations of the contact force in each full turn (module docs: counting rule).
    pub oscillations_per_turn: Vec<usize>,
    /// Frequency of the largest peak of the contact force's spectrum above the rotation
    /// frequency and away (+-10%) from the node-passing frequency and its harmonics, Hz.
    pub dominant_frequency_hz: Option<f64>,
    /// `dominant_frequency_hz` divided by the rotation frequency: cycles per turn.
    pub dominant_cycles_per_turn: Option<f64>,
    /// Frequency at which the base passes rim nodes, Hz (a mesh ripple).
    pub node_passing_frequency_hz: f64,
    /// Largest penetration seen, m.
    pub max_penetration: f64,
    /// Largest `J2` of the turn average, MPa^2.
    pub max_j2_turn_average_mpa2: f64,
    /// Largest von Mises stress of the turn average of `sqrt(3 J2)`, MPa.
    pub max_von_mises_turn_average_mpa: f64,
    /// Energy (kinetic + strain) at the end of settling and at the end, J.
    pub energy_after_settling: f64,
    /// Energy at the end, J.
    pub energy_final: f64,
    /// Brakings (steps stepped back).
    pub brakings: usize,
    /// Releases.
    pub releases: usize,
    /// Wall-clock time of the time loop, s.
    pub wall_time_s: f64,
    /// Time per step, microseconds.
    pub time_per_step_us: f64,
    /// True when interrupted.
    pub interrupted: bool,
}

/// Builds the wheel model of a scenario.
///
/// # Errors
/// [`RunError`] for a bad mesh or a singular model.
pub fn build(ws: &WheelScenario, sc_path: &Path) -> Result<WheelModel, RunError> {
    let mesh: Mesh = match &ws.mesh {
        MeshSource::Rings(n) => {
            disk_rings(ws.spec.radius, *n).map_err(|e| RunError::input(sc_path, e))?
        }
        MeshSource::Gmsh(p) => read_msh(p).map_err(|e| RunError::Input {
            path: sc_path.to_path_buf(),
            message: e.to_string(),
        })?,
    };
    WheelModel::new(mesh, ws.spec.clone()).map_err(|e| RunError::input(sc_path, e))
}

/// Runs a wheel scenario (its first run; a sweep calls [`simulate`] per value).
///
/// # Errors
/// [`RunError`].
pub fn run(sc: &Scenario, out: &Path, opts: &RunOptions) -> Result<RunReport, RunError> {
    let run = &sc.runs[0];
    let Model::Wheel(ws) = &run.model else {
        unreachable!("wheel job on a wheel scenario")
    };
    let wm = build(ws, &sc.path)?;
    let (summary, files) = simulate(&wm, ws, run, sc, out, opts.progress)?;
    let sj = out.join("summary.json");
    let mut json = serde_json::to_value(&summary).map_err(|e| RunError::output(&sj, e))?;
    if let Some(o) = json.as_object_mut() {
        o.insert("scenario".into(), sc.name.clone().into());
        o.insert("kind".into(), "wheel".into());
        o.insert(
            "units".into(),
            serde_json::json!({"time": "s", "force": "N", "frequency": "Hz", "stress": "MPa", "energy": "J", "omega": "rad/s"}),
        );
    }
    write_json(&sj, &json).map_err(|e| RunError::output(&sj, e))?;
    let mut report = RunReport {
        files,
        interrupted: summary.interrupted,
        ..Default::default()
    };
    report.files.push(sj);
    report.lines = summary_lines(&summary);
    Ok(report)
}

/// Screen lines of a summary.
pub fn summary_lines(s: &WheelSummary) -> Vec<String> {
    vec![
        format!(
            "omega = {} rad/s ({:.0} km/h), {} dofs, {} steps of {:.3e} s in {:.2} s ({:.1} us/step)",
            s.omega, s.speed_km_h, s.dofs, s.steps, s.h, s.wall_time_s, s.time_per_step_us
        ),
        format!(
            "contact force over the turns: mean {:.4e} N, min {:.4e} N, max {:.4e} N; {:.2} nodes in contact on average",
            s.mean_contact_force, s.min_contact_force, s.max_contact_force, s.mean_nodes_in_contact
        ),
        format!(
            "oscillations per turn {:?}; dominant frequency {} ({} cycles per turn); node passing {:.1} Hz",
            s.oscillations_per_turn,
            s.dominant_frequency_hz.map(|f| format!("{f:.1} Hz")).unwrap_or_else(|| "-".into()),
            s.dominant_cycles_per_turn.map(|f| format!("{f:.2}")).unwrap_or_else(|| "-".into()),
            s.node_passing_frequency_hz
        ),
        format!(
            "turn-averaged J2 max {:.4e} MPa^2, von Mises max {:.2} MPa; max penetration {:.2e} m; energy {:.4e} -> {:.4e} J",
            s.max_j2_turn_average_mpa2, s.max_von_mises_turn_average_mpa, s.max_penetration, s.energy_after_settling, s.energy_final
        ),
    ]
}

/// Runs one wheel run and writes its files (history, plots, fields) into `out`.
///
/// # Errors
/// [`RunError`].
pub fn simulate(
    wm: &WheelModel,
    ws: &WheelScenario,
    run: &Run,
    sc: &Scenario,
    out: &Path,
    show_progress: bool,
) -> Result<(WheelSummary, Vec<std::path::PathBuf>), RunError> {
    std::fs::create_dir_all(out).map_err(|e| RunError::output(out, e))?;
    let h = run.params.h;
    let omega = ws.spec.omega;
    let t_settle = ws.spec.flattening.settle_time;
    let turn_time = 2.0 * PI / omega;
    let steps = (ws.duration() / h).round() as usize;
    let gamma_schedule = match ws.settle_gamma {
        Some(g) if t_settle > 0.0 => vec![(0.0, g), (t_settle, run.params.gamma)],
        _ => vec![],
    };
    let problem = wm.problem(run.integrator, h, gamma_schedule, run.contact, steps);
    let mut sim = Simulation::new(problem).map_err(|source| RunError::Simulation {
        run: run.label.clone(),
        source,
    })?;
    let base = wm.base();
    let hist = out.join("history.csv");
    let mut csv = CsvWriter::create(
        &hist,
        &[
            "t_s",
            "base_angle_deg",
            "contact_force_N",
            "nodes_in_contact",
            "kinetic_J",
            "strain_J",
            "total_J",
            "min_gap_m",
        ],
    )
    .map_err(|e| RunError::output(&hist, e))?;
    // Per contact node, long format: one row per node carrying a reaction, per stride.
    let nodes_path = out.join("contact_nodes.csv");
    let mut nodes_csv =
        CsvWriter::create(&nodes_path, &["node", "t_s", "force_N", "gap_m", "held"])
            .map_err(|e| RunError::output(&nodes_path, e))?;
    let node_ids: Vec<String> = wm.rim.iter().map(|n| n.to_string()).collect();
    let n_el = wm.triangles.len();
    let n = wm.mesh.n_dofs();
    // Last full turn: averaging window and snapshots.
    let full_turns = ws.turns.floor().max(1.0);
    let avg_start = t_settle + (full_turns - 1.0) * turn_time;
    let avg_end = t_settle + full_turns * turn_time;
    let n_snap = ws.fields_per_turn;
    let snap_times: Vec<f64> = (0..n_snap)
        .map(|i| avg_start + (i as f64 + 0.5) * turn_time / n_snap as f64)
        .collect();
    let mut snaps_v: Vec<Vec<f64>> = Vec::with_capacity(n_snap);
    let mut snaps_u: Vec<Vec<f64>> = Vec::with_capacity(n_snap);
    let mut snaps_t: Vec<f64> = Vec::with_capacity(n_snap);
    let mut stress = vec![[0.0; 3]; n_el];
    let mut j2_sum = vec![0.0; n_el];
    let mut vm_sum = vec![0.0; n_el];
    let mut n_avg = 0usize;
    let mut force_t = Vec::with_capacity(steps + 1);
    let mut force_y = Vec::with_capacity(steps + 1);
    let mut all_t = Vec::with_capacity(steps + 1);
    let mut all_f = Vec::with_capacity(steps + 1);
    let (mut held_sum, mut max_pen, mut e_settled, mut e_final) = (0.0, 0.0f64, None, 0.0);
    let pb = progress_bar(steps as u64, &run.label, show_progress);
    let stride = sc.history_stride;
    let start = Instant::now();
    let stats = sim
        .run(&INTERRUPT, |s| {
            let st = s.state;
            let t = st.t;
            let min_gap = st.pairs.iter().map(|p| p.gap).fold(f64::INFINITY, f64::min);
            max_pen = max_pen.max(-min_gap);
            let e = s.kinetic + s.strain;
            e_final = e;
            all_t.push(t);
            all_f.push(s.contact_force);
            if t >= t_settle - 0.5 * h {
                if e_settled.is_none() {
                    e_settled = Some(e);
                }
                force_t.push(t);
                force_y.push(s.contact_force);
                held_sum += s.held as f64;
            }
            if t >= avg_start - 0.5 * h && t < avg_end - 0.5 * h {
                wm.stresses_into(&st.u, &mut stress);
                for (e, sg) in stress.iter().enumerate() {
                    let (j2, vm) = wm.j2_vm(*sg);
                    j2_sum[e] += j2;
                    vm_sum[e] += vm;
                }
                n_avg += 1;
            }
            if snaps_t.len() < n_snap && t >= snap_times[snaps_t.len()] - 0.5 * h {
                snaps_t.push(t);
                snaps_v.push(st.v.clone());
                snaps_u.push(st.u.clone());
            }
            if st.k % stride == 0 {
                for (p, ps) in st.pairs.iter().enumerate() {
                    if ps.held || ps.force != 0.0 {
                        let held = if ps.held { 1.0 } else { 0.0 };
                        nodes_csv.row(Some(&node_ids[p]), &[t, ps.force, ps.gap, held])?;
                    }
                }
                csv.row(
                    None,
                    &[
                        t,
                        base.angle(t).to_degrees(),
                        s.contact_force,
                        s.held as f64,
                        s.kinetic,
                        s.strain,
                        e,
                        min_gap,
                    ],
                )?;
            }
            if st.k % 256 == 0 {
                pb.set_position(st.k as u64);
            }
            Ok(())
        })
        .map_err(|source| RunError::Simulation {
            run: run.label.clone(),
            source,
        })?;
    pb.finish_and_clear();
    let wall = start.elapsed().as_secs_f64();
    csv.finish().map_err(|e| RunError::output(&hist, e))?;
    nodes_csv
        .finish()
        .map_err(|e| RunError::output(&nodes_path, e))?;
    let mut files = vec![hist, nodes_path];

    // Contact force statistics over the rolling phase.
    let nf = force_y.len().max(1) as f64;
    let mean = force_y.iter().sum::<f64>() / nf;
    let fmax = force_y.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    let fmin = force_y.iter().cloned().fold(f64::INFINITY, f64::min);
    let n_rim = wm.rim.len().max(1);
    let node_pass_hz = omega * n_rim as f64 / (2.0 * PI);
    let smooth_w = ((1.0 / node_pass_hz) / h).round().max(1.0) as usize;
    let mut osc = Vec::new();
    for k in 0..(ws.turns.floor() as usize) {
        let (a, b) = (
            t_settle + k as f64 * turn_time,
            t_settle + (k + 1) as f64 * turn_time,
        );
        let seg: Vec<f64> = force_t
            .iter()
            .zip(&force_y)
            .filter(|(t, _)| **t >= a - 0.5 * h && **t < b - 0.5 * h)
            .map(|(_, f)| *f)
            .collect();
        if seg.len() > 3 {
            osc.push(count_oscillations(&moving_average(&seg, smooth_w), 0.1));
        }
    }
    let (_, ry) = resample_uniform(&force_t, &force_y, h);
    let spec = amplitude_spectrum(&ry, h);
    let rot_hz = omega / (2.0 * PI);
    // The wheel's own oscillation: the largest peak above the rotation frequency away from
    // the node-passing ripple and its harmonics (+-10%).
    let mut wheel_spec = spec.clone();
    for (f, a) in wheel_spec
        .frequency_hz
        .iter()
        .zip(wheel_spec.amplitude.iter_mut())
    {
        let harmonic = (f / node_pass_hz).round();
        if harmonic >= 1.0 && (f - harmonic * node_pass_hz).abs() < 0.1 * node_pass_hz {
            *a = 0.0;
        }
    }
    let dom = dominant_peak(&wheel_spec, rot_hz);

    // Turn averages.
    let cnt = n_avg.max(1) as f64;
    let j2_avg: Vec<f64> = j2_sum.iter().map(|v| v / cnt / 1e12).collect();
    let vm_avg: Vec<f64> = vm_sum.iter().map(|v| v / cnt / 1e6).collect();
    let summary = WheelSummary {
        label: run.label.clone(),
        omega,
        speed_km_h: omega * ws.spec.radius * 3.6,
        h,
        alpha: run.params.alpha,
        gamma: run.params.gamma,
        dofs: n,
        nodes: wm.mesh.n_nodes(),
        triangles: n_el,
        turns: ws.turns,
        steps: stats.steps,
        mean_contact_force: mean,
        max_contact_force: fmax,
        min_contact_force: fmin,
        mean_nodes_in_contact: held_sum / nf,
        oscillations_per_turn: osc,
        dominant_frequency_hz: dom.map(|d| d.0),
        dominant_cycles_per_turn: dom.map(|d| d.0 / rot_hz),
        node_passing_frequency_hz: node_pass_hz,
        max_penetration: max_pen.max(0.0),
        max_j2_turn_average_mpa2: j2_avg.iter().cloned().fold(0.0, f64::max),
        max_von_mises_turn_average_mpa: vm_avg.iter().cloned().fold(0.0, f64::max),
        energy_after_settling: e_settled.unwrap_or(0.0),
        energy_final: e_final,
        brakings: stats.brakings,
        releases: stats.releases,
        wall_time_s: wall,
        time_per_step_us: wall / stats.steps.max(1) as f64 * 1e6,
        interrupted: stats.interrupted,
    };

    // Fields for ParaView.
    let vtu = out.join("j2_turn_average.vtu");
    write_vtu(
        &vtu,
        &wm.mesh,
        None,
        &[],
        &[
            Field {
                name: "J2_turn_average_MPa2",
                components: 1,
                values: &j2_avg,
            },
            Field {
                name: "von_mises_turn_average_MPa",
                components: 1,
                values: &vm_avg,
            },
        ],
    )
    .map_err(|e| RunError::output(&vtu, e))?;
    files.push(vtu);
    let mut pvd = PvdWriter::new();
    for (i, ((t, v), u)) in snaps_t.iter().zip(&snaps_v).zip(&snaps_u).enumerate() {
        let name = format!("velocity_{i:03}.vtu");
        let p = out.join(&name);
        let speed: Vec<f64> = v
            .chunks(2)
            .map(|c| (c[0] * c[0] + c[1] * c[1]).sqrt())
            .collect();
        write_vtu(
            &p,
            &wm.mesh,
            Some(u),
            &[
                Field {
                    name: "velocity",
                    components: 2,
                    values: v,
                },
                Field {
                    name: "speed",
                    components: 1,
                    values: &speed,
                },
            ],
            &[],
        )
        .map_err(|e| RunError::output(&p, e))?;
        pvd.add(*t, name);
        files.push(p);
    }
    if !pvd.is_empty() {
        let p = out.join("velocity.pvd");
        pvd.write(&p).map_err(|e| RunError::output(&p, e))?;
        files.push(p);
    }

    if sc.plots {
        // Fig. 12: force over the turns.
        let turns_axis: Vec<f64> = all_t.iter().map(|t| (t - t_settle) / turn_time).collect();
        let mut p = Panel::new(
            format!(
                "Contact force, omega = {omega} rad/s ({:.0} km/h)",
                summary.speed_km_h
            ),
            "turns after settling",
            "contact force [N]",
        );
        p.series.push(Series::new(
            "contact force",
            turns_axis.clone(),
            all_f.clone(),
            SeriesStyle::Line,
        ));
        p.hlines
            .push((mean, format!("mean over the turns {mean:.3e} N")));
        let png = out.join("contact_force.png");
        line_plot(&png, &p, (1400, 700)).map_err(|e| RunError::output(&png, e))?;
        files.push(png);
        // Fig. 13: a zoom on a quarter of the last turn.
        let z0 = full_turns - 1.0;
        let mut pz = Panel::new(
            "Contact force (zoom on a quarter turn)",
            "turns after settling",
            "contact force [N]",
        );
        pz.series.push(Series::new(
            "contact force",
            turns_axis,
            all_f,
            SeriesStyle::Line,
        ));
        pz.x_range = Some((z0, z0 + 0.25));
        let png = out.join("contact_force_zoom.png");
        line_plot(&png, &pz, (1400, 700)).map_err(|e| RunError::output(&png, e))?;
        files.push(png);
        // Spectrum.
        if !spec.frequency_hz.is_empty() {
            let (lo, hi) = (0.5 * rot_hz, (20.0 * node_pass_hz).min(0.5 / h));
            let mut ps = Panel::new(
                "Amplitude spectrum of the contact force (rolling phase; largest peak per log bin)",
                "frequency [Hz]",
                "amplitude [N]",
            );
            ps.x_log = true;
            ps.y_log = true;
            ps.x_range = Some((lo, hi));
            let (f, a) = peak_envelope(&spec.frequency_hz, &spec.amplitude, lo, hi, 1200);
            // Five decades below the largest peak.
            let amax = a.iter().cloned().fold(0.0, f64::max);
            let (f, a): (Vec<f64>, Vec<f64>) = f
                .into_iter()
                .zip(a)
                .filter(|(_, x)| *x >= amax * 1e-5)
                .unzip();
            ps.y_range = Some((amax * 1e-5, amax * 2.0));
            ps.series
                .push(Series::new("amplitude", f, a, SeriesStyle::Line));
            let png = out.join("spectrum.png");
            line_plot(&png, &ps, (1400, 700)).map_err(|e| RunError::output(&png, e))?;
            files.push(png);
        }
        // Figs. 14/16: J2 turn average.
        for (name, vals, label, title) in [
            (
                "j2_turn_average.png",
                &j2_avg,
                "J2 [MPa²]",
                "J2 averaged over one full turn",
            ),
            (
                "von_mises_turn_average.png",
                &vm_avg,
                "von Mises [MPa]",
                "von Mises stress averaged over one full turn",
            ),
        ] {
            let png = out.join(name);
            // The point support at the axle concentrates the reaction in its few elements;
            // the colour scale stops at the 97th percentile so that the rim shows.
            let top = percentile(vals, 0.97);
            let vmax = vals.iter().cloned().fold(0.0, f64::max);
            let clipped = vmax > 1.5 * top;
            let opts = MeshOptions {
                value_range: clipped.then_some((0.0, top)),
                ..Default::default()
            };
            let title = format!("{title}, {omega} rad/s");
            let label = if clipped {
                format!("{label}, clipped at {top:.0} (max {vmax:.0})")
            } else {
                label.to_string()
            };
            mesh_color_map_with(
                &png,
                &MeshColorMap {
                    points: &wm.mesh.points,
                    triangles: &wm.triangles,
                    cell_values: vals,
                    title,
                    colorbar_label: label,
                    length_unit_scale: 100.0,
                    length_unit: "cm".into(),
                },
                (1100, 1000),
                &opts,
            )
            .map_err(|e| RunError::output(&png, e))?;
            files.push(png);
        }
        // Fig. 17: velocity fields.
        if !snaps_v.is_empty() {
            let vecs: Vec<Vec<[f64; 2]>> = snaps_v
                .iter()
                .map(|v| v.chunks(2).map(|c| [c[0], c[1]]).collect())
                .collect();
            let frames: Vec<MeshVectorField> = vecs
                .iter()
                .zip(&snaps_t)
                .map(|(v, t)| MeshVectorField {
                    points: &wm.mesh.points,
                    triangles: &wm.triangles,
                    vectors: v,
                    title: format!(
                        "base at {:.0} deg",
                        base.angle(*t).to_degrees().rem_euclid(360.0)
                    ),
                    colorbar_label: "velocity in the wheel's frame [m/s]".into(),
                    length_unit_scale: 100.0,
                    length_unit: "cm".into(),
                })
                .collect();
            let png = out.join("velocity_fields.png");
            mesh_vector_fields(&png, &frames, 4, (1800, 1000))
                .map_err(|e| RunError::output(&png, e))?;
            files.push(png);
        }
    }
    Ok((summary, files))
}

fn percentile(v: &[f64], q: f64) -> f64 {
    let mut s: Vec<f64> = v.iter().cloned().filter(|x| x.is_finite()).collect();
    if s.is_empty() {
        return 0.0;
    }
    s.sort_by(f64::total_cmp);
    s[((s.len() - 1) as f64 * q).round() as usize]
}

/// The largest amplitude in each of `bins` log-spaced frequency bins over `[lo, hi]` (a
/// peak envelope that keeps every peak of a dense spectrum drawable).
fn peak_envelope(f: &[f64], a: &[f64], lo: f64, hi: f64, bins: usize) -> (Vec<f64>, Vec<f64>) {
    let (llo, lhi) = (lo.max(f64::MIN_POSITIVE).ln(), hi.ln());
    let mut best: Vec<Option<(f64, f64)>> = vec![None; bins];
    for (&fi, &ai) in f.iter().zip(a) {
        if fi < lo || fi > hi || ai.is_nan() || ai <= 0.0 {
            continue;
        }
        let k = (((fi.ln() - llo) / (lhi - llo)) * bins as f64)
            .floor()
            .clamp(0.0, (bins - 1) as f64) as usize;
        if best[k].is_none_or(|(_, b)| ai > b) {
            best[k] = Some((fi, ai));
        }
    }
    best.into_iter().flatten().unzip()
}
