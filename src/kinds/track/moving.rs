//! The track's jobs ([`crate::bodies::rail`]): a constant load moving over the middle bays through
//! the driver (`softway run`: `history.csv`, `track.png`, `summary.json`), and the rail's
//! receptance with its frequencies (`softway receptance`: `receptance.csv`,
//! `receptance.png`, `summary.json`).

use crate::bodies::rail::moving::{self, MovingLoad, Passage, Sample};
use crate::bodies::rail::receptance::{
    frequencies, log_frequencies, Frequencies, Receptance, Wheel,
};
use crate::bodies::rail::{hertz, Ends, Track, TrackSpec};
use crate::output::plot::{Panel, Series, SeriesStyle};
use crate::run::error::RunError;
use crate::run::options::RunOptions;
use crate::run::results::Results;
use crate::scenario::{Model, Scenario, TrackScenario};
use faer::c64;
use std::path::{Path, PathBuf};

/// The columns of `history.csv`: `run` (the run's label), then these.
pub const HISTORY: [(&str, &str); 7] = [
    ("t_s", "s"),
    ("x_m", "m"),
    ("deflection_m", "m"),
    ("static_deflection_m", "m"),
    ("pad_force_nearest_N", "N"),
    ("nearest_sleeper", "1"),
    ("pad_force_middle_N", "N"),
];

/// The track's data as `summary.json` records it.
pub(crate) fn parameters(ts: &TrackScenario) -> serde_json::Value {
    let s: &TrackSpec = &ts.spec;
    let (ends, end_bays, end_damping) = match s.ends {
        Ends::Free => ("free", None, None),
        Ends::Absorbing { bays, damping } => ("absorbing", Some(bays), Some(damping)),
    };
    serde_json::json!({
        "track": {
            "set": ts.set,
            "theory": format!("{:?}", s.theory),
            "young_Pa": s.section.young,
            "shear_modulus_Pa": s.section.shear_modulus,
            "shear_coefficient": s.section.shear_coefficient,
            "area_m2": s.section.area,
            "inertia_m4": s.section.inertia,
            "density_kg_m3": s.section.density,
            "pad_stiffness_N_m": s.pad_stiffness,
            "pad_damping_N_s_m": s.pad_damping,
            "sleeper_mass_kg": s.sleeper_mass,
            "ballast_stiffness_N_m": s.ballast_stiffness,
            "ballast_damping_N_s_m": s.ballast_damping,
            "spacing_m": s.spacing,
            "bays": s.bays,
            "elements_per_bay": s.elements_per_bay,
            "ends": ends,
            "end_bays": end_bays,
            "end_damping_1_s": end_damping,
            "head_radius_m": s.head_radius,
            "poisson": s.poisson,
        },
        "vehicle": ts.vehicle,
        "receptance": ts.receptance,
    })
}

/// Copies the numbers of the first run's summary `first` to the top level of `json` (the
/// columns of `softway sweep`'s table), but its step count.
pub(super) fn lift_first_run(json: &mut serde_json::Value, first: &impl serde::Serialize) {
    if let (Some(o), Ok(serde_json::Value::Object(first))) =
        (json.as_object_mut(), serde_json::to_value(first))
    {
        for (k, v) in first {
            if v.is_number() && k != "steps" {
                o.insert(k, v);
            }
        }
    }
}

/// The track scenario of a run.
fn track_of(model: &Model) -> &TrackScenario {
    model
        .get::<TrackScenario>()
        .expect("track job on a track scenario")
}

/// One run's key figures.
#[derive(Debug, Clone, serde::Serialize)]
struct PassageSummary {
    label: String,
    h: f64,
    steps: usize,
    speed_m_s: f64,
    start_m: f64,
    travel_m: f64,
    sleeper_passing_hz: f64,
    deflection_mean_m: f64,
    deflection_min_m: f64,
    deflection_max_m: f64,
    static_deflection_min_m: f64,
    static_deflection_max_m: f64,
    dynamic_over_static_max: f64,
    dominant_frequency_hz: Option<f64>,
    dominant_amplitude_m: Option<f64>,
    #[serde(rename = "pad_force_nearest_max_N")]
    pad_force_nearest_max: f64,
    #[serde(rename = "pad_force_middle_max_N")]
    pad_force_middle_max: f64,
    interrupted: bool,
}

/// `softway run` of a track scenario under a moving load: each run's passage (module
/// docs); the history streamed to `stream` when given. The rolling wheel's:
/// [`super::track_rolling::record`].
///
/// # Errors
/// [`RunError`]: a track that cannot be built, a failed run, a file that cannot be written.
pub(crate) fn record(
    sc: &Scenario,
    stream: Option<&Path>,
    opts: &RunOptions,
) -> Result<Results, RunError> {
    let (mut csv, hist) = crate::run::history::keyed_history(sc, stream, &HISTORY)?;
    let at = |e| RunError::output(&hist, e);
    let mut sums = Vec::new();
    let mut deflection = Panel::new(
        format!(
            "Rail deflection under a moving load of {} kN",
            crate::output::plot::sig(1e-3 * track_of(&sc.runs[0].model).vehicle.axle_load, 4)
        ),
        "load position x [m]",
        "deflection under the load [mm]",
    );
    let mut pads = Panel::new(
        "Pad forces",
        "load position x [m]",
        "pad force (compression) [kN]",
    );
    let mut interrupted = false;
    let first = track_of(&sc.runs[0].model);
    for (ri, run) in sc.runs.iter().enumerate() {
        let ts = track_of(&run.model);
        let track = ts.spec.build().map_err(|e| RunError::input(&sc.path, e))?;
        let passage = Passage {
            load: MovingLoad {
                force: ts.vehicle.axle_load,
                speed: ts.vehicle.speed,
                start: ts.start(),
            },
            distance: ts.travel(),
            integrator: run.integrator,
            h: run.params.h,
            static_reference: true,
        };
        let mut samples: Vec<Sample> = Vec::with_capacity(passage.steps() + 1);
        let stride = sc.history_stride;
        let mut k = 0usize;
        let stats = moving::run(&track, &passage, opts.settings(), opts.cancel.flag(), |s| {
            if k % stride == 0 {
                csv.push(
                    ri as u32,
                    &[
                        s.t,
                        s.x,
                        s.deflection,
                        s.static_deflection,
                        s.pad_force_nearest,
                        s.nearest as f64,
                        s.pad_force_middle,
                    ],
                )?;
            }
            k += 1;
            samples.push(*s);
            Ok(())
        })
        .map_err(|e| RunError::input(&sc.path, format!("run `{}`: {e}", run.label)))?;
        interrupted |= stats.interrupted;
        let sum = summarise(&run.label, &track, &passage, &samples, stats.interrupted);
        plot_run(
            (&mut deflection, &mut pads),
            (ri, sc.runs.len()),
            &run.label,
            ts.vehicle.speed,
            &track,
            &samples,
        );
        sums.push(sum);
        if interrupted {
            break;
        }
    }
    let history = csv.finish().map_err(at)?;
    let mut json = serde_json::json!({
        "scenario": sc.name, "kind": "track", "interrupted": interrupted,
        "units": {"time": "s", "length": "m", "force": "N", "frequency": "Hz"},
        "deflection": "downwards positive, under the load; pad forces in compression",
        "parameters": parameters(first),
        "runs": sums,
    });
    lift_first_run(&mut json, &sums[0]);
    crate::run::provenance::stamp_provenance(&mut json, sc);
    let lines = sums.iter().map(screen_line).collect();
    Ok(Results::with_panels(
        ("track", json),
        history,
        lines,
        interrupted,
        sc.plots,
        ("track.png", vec![deflection, pads], (1400, 1100)),
    ))
}

/// Adds run `ri` (of `runs`, labelled `label`, at `speed` m/s) to the two panels: the
/// deflection under the load against the static one, the pad forces; and sets their
/// ranges with room for the legends.
fn plot_run(
    (deflection, pads): (&mut Panel, &mut Panel),
    (ri, runs): (usize, usize),
    label: &str,
    speed: f64,
    track: &Track,
    samples: &[Sample],
) {
    let style = if ri % 2 == 0 {
        SeriesStyle::Line
    } else {
        SeriesStyle::Dashed
    };
    let xs: Vec<f64> = samples.iter().map(|s| s.x).collect();
    let mm = |f: fn(&Sample) -> f64| samples.iter().map(|s| 1e3 * f(s)).collect::<Vec<_>>();
    let kn = |f: fn(&Sample) -> f64| samples.iter().map(|s| 1e-3 * f(s)).collect::<Vec<_>>();
    let name = |what: &str| {
        if runs > 1 {
            format!("{label}: {what}")
        } else {
            what.to_string()
        }
    };
    deflection.series.push(Series::new(
        name(&format!(
            "moving at {} m/s",
            crate::output::plot::sig(speed, 4)
        )),
        xs.clone(),
        mm(|s| s.deflection),
        style,
    ));
    deflection.series.push(Series::new(
        name("static, standing there"),
        xs.clone(),
        mm(|s| s.static_deflection),
        SeriesStyle::Dashed,
    ));
    pads.series.push(Series::new(
        name("pad nearest the load"),
        xs.clone(),
        kn(|s| s.pad_force_nearest),
        style,
    ));
    pads.series.push(Series::new(
        name(&format!(
            "pad of the middle sleeper (x = {:.2} m)",
            track.middle()
        )),
        xs,
        kn(|s| s.pad_force_middle),
        SeriesStyle::Dashed,
    ));
    let top = samples
        .iter()
        .map(|s| s.pad_force_nearest.max(s.pad_force_middle))
        .fold(0.0, f64::max);
    // Head room for the legends above the curves.
    pads.y_range = Some((0.0, 1.4e-3 * top));
    let (lo, hi) = samples
        .iter()
        .flat_map(|s| [s.deflection, s.static_deflection])
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), d| {
            (a.min(d), b.max(d))
        });
    let span = (hi - lo).max(1e-3 * hi.abs()).max(1e-12);
    deflection.y_range = Some((1e3 * (lo - 0.05 * span), 1e3 * (hi + 0.6 * span)));
}

/// The screen line of one run.
fn screen_line(s: &PassageSummary) -> String {
    format!(
        "{:<10} {} m/s over {:.2} m: deflection under the load {:.4} mm mean ({:.4}-{:.4}), static {:.4}-{:.4} mm, dynamic/static {:.4}; strongest component {} (sleeper passing {:.2} Hz); pad force up to {:.1} kN",
        s.label,
        s.speed_m_s,
        s.travel_m,
        1e3 * s.deflection_mean_m,
        1e3 * s.deflection_min_m,
        1e3 * s.deflection_max_m,
        1e3 * s.static_deflection_min_m,
        1e3 * s.static_deflection_max_m,
        s.dynamic_over_static_max,
        s.dominant_frequency_hz
            .map(|f| format!("{f:.2} Hz"))
            .unwrap_or_else(|| "-".into()),
        s.sleeper_passing_hz,
        1e-3 * s.pad_force_nearest_max
    )
}

/// One run's key figures from its samples; the spectrum of the deflection under the load
/// after its first two bays (the start's transient).
fn summarise(
    label: &str,
    track: &Track,
    passage: &Passage,
    samples: &[Sample],
    interrupted: bool,
) -> PassageSummary {
    let v = passage.load.speed;
    let fold = |f: fn(&Sample) -> f64, init: f64, g: fn(f64, f64) -> f64| {
        samples.iter().map(f).fold(init, g)
    };
    let n = samples.len().max(1) as f64;
    let settled = passage.load.start + 2.0 * track.spec.spacing;
    let from = samples
        .iter()
        .position(|s| s.x >= settled)
        .unwrap_or(samples.len());
    let tail: Vec<f64> = samples[from..].iter().map(|s| s.deflection).collect();
    let peak = if tail.len() >= 8 {
        let spec = crate::analysis::signal::amplitude_spectrum(&tail, passage.h);
        crate::analysis::signal::dominant_peak(&spec, 0.1 * v / track.spec.spacing)
    } else {
        None
    };
    let ratio = samples
        .iter()
        .filter(|s| s.static_deflection.abs() > 0.0)
        .map(|s| s.deflection / s.static_deflection)
        .fold(0.0, f64::max);
    PassageSummary {
        label: label.to_string(),
        h: passage.h,
        steps: samples.len().saturating_sub(1),
        speed_m_s: v,
        start_m: passage.load.start,
        travel_m: passage.distance,
        sleeper_passing_hz: v / track.spec.spacing,
        deflection_mean_m: samples.iter().map(|s| s.deflection).sum::<f64>() / n,
        deflection_min_m: fold(|s| s.deflection, f64::INFINITY, f64::min),
        deflection_max_m: fold(|s| s.deflection, f64::NEG_INFINITY, f64::max),
        static_deflection_min_m: fold(|s| s.static_deflection, f64::INFINITY, f64::min),
        static_deflection_max_m: fold(|s| s.static_deflection, f64::NEG_INFINITY, f64::max),
        dynamic_over_static_max: ratio,
        dominant_frequency_hz: peak.map(|p| p.0),
        dominant_amplitude_m: peak.map(|p| p.1),
        pad_force_nearest_max: fold(|s| s.pad_force_nearest, f64::NEG_INFINITY, f64::max),
        pad_force_middle_max: fold(|s| s.pad_force_middle, f64::NEG_INFINITY, f64::max),
        interrupted,
    }
}

/// What `softway receptance` reports.
#[derive(Debug, Clone)]
pub(crate) struct ReceptanceReport {
    /// Lines for the screen.
    pub lines: Vec<String>,
    /// Files written.
    pub files: Vec<PathBuf>,
    /// Stopped by a signal before the last frequency.
    pub interrupted: bool,
}

/// The track's receptance study (`softway receptance`, [`receptance_job`]).
#[derive(Debug, Clone, Copy)]
pub struct TrackReceptance;

impl crate::scenario::kind::Study for TrackReceptance {
    fn run(
        &self,
        sc: &Scenario<crate::scenario::RunSpec>,
        opts: &crate::scenario::kind::StudyOptions,
        dir: &Path,
    ) -> Result<crate::scenario::kind::StudyReport, RunError> {
        let r = receptance_job(sc, dir, opts.plots, opts.cancel)?;
        Ok(crate::scenario::kind::StudyReport {
            lines: r.lines,
            files: r.files,
            interrupted: r.interrupted.then(|| {
                "interrupted: receptance.csv holds the frequencies computed so far".to_string()
            }),
        })
    }
}

/// `softway receptance`: the receptance of the scenario's track (its first run's) at
/// mid-span and above the middle sleeper, its frequencies, written into `out`.
///
/// # Errors
/// [`RunError`]: not a track scenario, a failed solve, a file that cannot be written.
pub(crate) fn receptance_job(
    sc: &Scenario<crate::scenario::RunSpec>,
    out: &Path,
    plots: bool,
    interrupt: &std::sync::atomic::AtomicBool,
) -> Result<ReceptanceReport, RunError> {
    let Some(ts) = sc.runs[0].model.get::<TrackScenario>() else {
        return Err(RunError::input(
            &sc.path,
            "`softway receptance` needs a track scenario (kind = \"track\")",
        ));
    };
    let input = |e: crate::bodies::rail::TrackError| RunError::input(&sc.path, e);
    let track = ts.spec.build().map_err(input)?;
    let range = ts.receptance;
    let freqs = log_frequencies(range.f_min, range.f_max, range.points);
    let r = crate::bodies::rail::receptance::receptance_until(&track, &freqs, interrupt)
        .map_err(input)?;
    if r.frequency_hz.len() < freqs.len() {
        return interrupted_receptance(sc, out, &r, freqs.len());
    }
    let wheel = Wheel {
        unsprung_mass: ts.vehicle.unsprung_mass,
        load: ts.vehicle.axle_load,
        radius: ts.vehicle.wheel_radius,
    };
    check_finite(sc, &r)?;
    let f = frequencies(&track, &r, &wheel).map_err(input)?;
    check_frequencies(sc, &f)?;
    let contact = hertz::contact(
        wheel.load,
        wheel.radius,
        ts.spec.head_radius,
        ts.spec.section.young,
        ts.spec.poisson,
    );
    std::fs::create_dir_all(out).map_err(|e| RunError::output(out, e))?;
    let mut files = Vec::new();
    let csv = out.join("receptance.csv");
    write_csv(&csv, &r).map_err(|e| RunError::output(&csv, e))?;
    files.push(csv);
    if plots {
        let png = out.join("receptance.png");
        plot(&png, &track, &r, &f).map_err(|e| RunError::output(&png, e))?;
        files.push(png);
    }
    let mut json = serde_json::json!({
        "scenario": sc.name,
        "kind": "track_receptance",
        "units": {"frequency": "Hz", "receptance": "m/N", "stiffness": "N/m", "phase": "deg"},
        "pinned_pinned_hz": f.pinned_pinned_hz,
        "track_resonance_hz": f.track_resonance_hz,
        "p2_hz": f.p2_hz,
        "frequencies": f,
        "not_in_range": range_notes(&f, range.f_min),
        "hertz": contact,
        "mid_span_x_m": r.mid_span_x,
        "above_sleeper_x_m": r.above_sleeper_x,
        "parameters": parameters(ts),
    });
    if let Some(o) = json.as_object_mut() {
        o.insert(
            "softway_version".into(),
            env!("CARGO_PKG_VERSION").to_string().into(),
        );
        o.insert("scenario_sha256".into(), sc.source_sha256.clone().into());
    }
    let sj = out.join("summary.json");
    crate::output::files::write_json(&sj, &json).map_err(|e| RunError::output(&sj, e))?;
    files.push(sj);
    let hz = |q: Option<f64>| q.map_or_else(|| "-".to_string(), |q| format!("{q:.1} Hz"));
    let mut lines = vec![
        format!(
            "{} points, {} to {} Hz, at x = {:.2} m (mid-span) and {:.2} m (above the middle sleeper)",
            range.points, range.f_min, range.f_max, r.mid_span_x, r.above_sleeper_x
        ),
        format!(
            "pinned-pinned {} (the span's simply supported {:.1} Hz), anti-resonance above the sleeper {}",
            hz(f.pinned_pinned_hz),
            f.simply_supported_hz,
            hz(f.above_sleeper_antiresonance_hz)
        ),
        format!("track resonance {}", hz(f.track_resonance_hz)),
        format!(
            "P2 {} at mid-span ({} above the sleeper; single dof {:.1} Hz): k_H {:.3e} N/m, track {:.3e} N/m static at mid-span; second coupled minimum {}",
            hz(f.p2_hz),
            hz(f.p2_above_sleeper_hz),
            f.p2_single_dof_hz,
            f.hertz_stiffness,
            f.static_stiffness_mid_span,
            hz(f.second_coupled_hz)
        ),
    ];
    lines.extend(range_notes(&f, range.f_min));
    Ok(ReceptanceReport {
        lines,
        files,
        interrupted: false,
    })
}

/// What the range of `[receptance]`, from `f_min`, did not hold (the frequencies left
/// `None`: [`crate::bodies::rail::receptance`], A range that misses a frequency), one line each.
fn range_notes(f: &Frequencies, f_min: f64) -> Vec<String> {
    let mut notes = Vec::new();
    if f.p2_below_range {
        notes.push(format!(
            "no P2 read: the range starts above it (receptance.f_min = {f_min} Hz; |D| still falls there): lower receptance.f_min"
        ));
    }
    if f.track_resonance_below_range {
        notes.push(format!(
            "no track resonance read: the range starts above it (receptance.f_min = {f_min} Hz; the mid-span receptance no longer rises there): lower receptance.f_min"
        ));
    }
    notes
}

/// The keys that set the track's dynamic stiffness, for the messages of a result that is
/// not a number.
const TRACK_KEYS: &str = "track.pad_stiffness, track.ballast_stiffness, track.sleeper_mass, track.young, track.density, track.area, track.inertia, receptance.f_min, receptance.f_max";

/// Refuses a receptance with a value that is not a finite number (an ill-conditioned
/// track: issue 47's NaN written with exit 0), naming the frequency and the keys.
fn check_finite(sc: &Scenario<crate::scenario::RunSpec>, r: &Receptance) -> Result<(), RunError> {
    let bad = r
        .frequency_hz
        .iter()
        .zip(r.mid_span.iter().zip(&r.above_sleeper))
        .find(|(_, (a, b))| {
            !(a.re.is_finite() && a.im.is_finite() && b.re.is_finite() && b.im.is_finite())
        });
    match bad {
        None => Ok(()),
        Some((f, _)) => Err(RunError::input(
            &sc.path,
            format!(
                "the track's receptance at {f:e} Hz is not a number (the dynamic stiffness cannot be solved in floating point): the track's values are out of proportion; check {TRACK_KEYS}"
            ),
        )),
    }
}

/// Refuses frequencies whose static stiffnesses are not finite and positive (a track that
/// floats: its ballast too soft for the solve to see it) or whose single-dof estimate is not
/// a number.
fn check_frequencies(
    sc: &Scenario<crate::scenario::RunSpec>,
    f: &Frequencies,
) -> Result<(), RunError> {
    for (what, k) in [
        ("at mid-span", f.static_stiffness_mid_span),
        ("above the sleeper", f.static_stiffness_above_sleeper),
    ] {
        if !(k.is_finite() && k > 0.0) {
            return Err(RunError::input(
                &sc.path,
                format!(
                    "the track's static stiffness {what} is {k:e} N/m, not a finite stiffness > 0 (the track's supports are out of proportion with its rail); check {TRACK_KEYS}"
                ),
            ));
        }
    }
    if !f.p2_single_dof_hz.is_finite() {
        return Err(RunError::input(
            &sc.path,
            format!(
                "the single-dof P2 estimate is {} Hz (the wheel on the contact and the track's static stiffness); check vehicle.unsprung_mass, vehicle.axle_load, {TRACK_KEYS}",
                f.p2_single_dof_hz
            ),
        ));
    }
    Ok(())
}

/// The files of a receptance stopped by a signal after `r`'s frequencies of `points`: the
/// table of those, and a summary that says so (no frequency is read off a part of the
/// range: a minimum at its end need not be one).
fn interrupted_receptance(
    sc: &Scenario<crate::scenario::RunSpec>,
    out: &Path,
    r: &Receptance,
    points: usize,
) -> Result<ReceptanceReport, RunError> {
    std::fs::create_dir_all(out).map_err(|e| RunError::output(out, e))?;
    let csv = out.join("receptance.csv");
    write_csv(&csv, r).map_err(|e| RunError::output(&csv, e))?;
    let json = serde_json::json!({
        "scenario": sc.name,
        "kind": "track_receptance",
        "interrupted": true,
        "frequencies_computed": r.frequency_hz.len(),
        "frequencies_asked": points,
        "softway_version": env!("CARGO_PKG_VERSION"),
        "scenario_sha256": sc.source_sha256,
    });
    let sj = out.join("summary.json");
    crate::output::files::write_json(&sj, &json).map_err(|e| RunError::output(&sj, e))?;
    Ok(ReceptanceReport {
        lines: vec![format!(
            "{} of {} frequencies computed before the interruption; no frequency is read off a part of the range",
            r.frequency_hz.len(),
            points
        )],
        files: vec![csv, sj],
        interrupted: true,
    })
}

/// The phase of a receptance, degrees.
fn phase_deg(z: c64) -> f64 {
    z.im.atan2(z.re).to_degrees()
}

/// `receptance.csv`: frequency, and the magnitude and phase at the two points.
fn write_csv(path: &Path, r: &Receptance) -> std::io::Result<()> {
    let mut t = crate::output::table::Columns::new(&[
        ("frequency_Hz", "Hz"),
        ("mid_span_magnitude_m_per_N", "m/N"),
        ("mid_span_phase_deg", "deg"),
        ("above_sleeper_magnitude_m_per_N", "m/N"),
        ("above_sleeper_phase_deg", "deg"),
    ]);
    for i in 0..r.frequency_hz.len() {
        t.push(
            0,
            &[
                r.frequency_hz[i],
                r.mid_span[i].norm(),
                phase_deg(r.mid_span[i]),
                r.above_sleeper[i].norm(),
                phase_deg(r.above_sleeper[i]),
            ],
        );
    }
    t.write_csv(path)
}

/// `receptance.png`: the magnitudes (log-log) with the three frequencies marked, and the
/// phases. The curves pass through the refined extrema (their points added to the grid's).
fn plot(
    path: &Path,
    track: &Track,
    r: &Receptance,
    f: &Frequencies,
) -> Result<(), Box<dyn std::error::Error>> {
    let mut pencil = crate::bodies::rail::receptance::Pencil::new(track)?;
    let mut at = |x: f64, q: f64| -> Result<c64, crate::bodies::rail::TrackError> {
        pencil.factor(2.0 * std::f64::consts::PI * q)?;
        pencil.point_receptance(track, x)
    };
    // The grid with the refined extrema inserted.
    let mut points: Vec<(f64, c64, c64)> = (0..r.frequency_hz.len())
        .map(|i| (r.frequency_hz[i], r.mid_span[i], r.above_sleeper[i]))
        .collect();
    let extra = [
        f.pinned_pinned_hz,
        f.above_sleeper_antiresonance_hz,
        f.track_resonance_hz,
        f.p2_hz,
    ];
    for q in extra.into_iter().flatten() {
        points.push((q, at(r.mid_span_x, q)?, at(r.above_sleeper_x, q)?));
    }
    points.sort_by(|a, b| a.0.total_cmp(&b.0));
    let fs: Vec<f64> = points.iter().map(|p| p.0).collect();
    let s = &track.spec;
    let mut mag = Panel::new(
        format!(
            "Rail point receptance: pads {} MN/m, sleepers {} m apart, ballast {} MN/m",
            crate::output::plot::sig(1e-6 * s.pad_stiffness, 3),
            crate::output::plot::sig(s.spacing, 3),
            crate::output::plot::sig(1e-6 * s.ballast_stiffness, 3)
        ),
        "frequency [Hz]",
        "receptance magnitude [m/N]",
    );
    mag.x_log = true;
    mag.y_log = true;
    mag.series.push(Series::new(
        format!("mid-span (x = {:.2} m)", r.mid_span_x),
        fs.clone(),
        points.iter().map(|p| p.1.norm()).collect(),
        SeriesStyle::Line,
    ));
    mag.series.push(Series::new(
        format!("above a sleeper (x = {:.2} m)", r.above_sleeper_x),
        fs.clone(),
        points.iter().map(|p| p.2.norm()).collect(),
        SeriesStyle::Dashed,
    ));
    let marks = [
        ("track resonance", f.track_resonance_hz, r.mid_span_x),
        ("pinned-pinned", f.pinned_pinned_hz, r.mid_span_x),
        ("P2 (wheel on track)", f.p2_hz, r.mid_span_x),
    ];
    for (name, q, x) in marks {
        if let Some(q) = q {
            mag.series.push(Series::new(
                format!("{name}: {q:.0} Hz"),
                vec![q],
                vec![at(x, q)?.norm()],
                SeriesStyle::Markers,
            ));
        }
    }
    let mut phase = Panel::new("Phase", "frequency [Hz]", "phase [deg]");
    phase.x_log = true;
    phase.y_range = Some((-180.0, 0.0));
    phase.series.push(Series::new(
        "mid-span",
        fs.clone(),
        points.iter().map(|p| phase_deg(p.1)).collect(),
        SeriesStyle::Line,
    ));
    phase.series.push(Series::new(
        "above a sleeper",
        fs,
        points.iter().map(|p| phase_deg(p.2)).collect(),
        SeriesStyle::Dashed,
    ));
    crate::output::plot::panels(path, &[mag, phase], 2, 1, (1400, 1400))?;
    Ok(())
}
