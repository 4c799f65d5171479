//! Parameter sweeps: one scenario over a list of values of one key, run in parallel, with a
//! table (`sweep.csv`, `sweep.md`) and, for the wheel, the paper's Fig. 15 (`sweep.png`:
//! oscillations per turn and maximal contact force against omega). A sweep may also run in
//! slices on several machines ([`shard`]: `softway sweep --shard I/N`) and be assembled
//! into the same table and plot (`softway gather`).

pub mod cost;
pub mod creep;
mod figures;
pub mod kalker;
pub mod shard;
pub mod slip_history;
pub mod speed;
use figures::{creep_curve, force_panel, oscillations_panel, sweep_axis};
pub(crate) use figures::{steady_traction_ratio, traction_figure};

use super::{run_scenario, Cancel, Par, RunError, RunOptions};
use crate::build::resolve;
use crate::output::files::write_atomic;
use crate::output::plot::{panels, Panel, Series, SeriesStyle};
use crate::scenario::overrides::read_with;
pub use crate::scenario::Override;
use rayon::prelude::*;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// One point of a sweep.
#[derive(Debug, Clone)]
pub struct SweepPoint {
    /// The values of the swept keys at this point (`--set` overrides, in the keys' order).
    pub sets: Vec<Override>,
    /// The values (TOML literals), comma-separated in the keys' order.
    pub value: String,
    /// Its output folder.
    pub dir: PathBuf,
    /// Its `summary.json`.
    pub summary: serde_json::Value,
    /// Its run's warnings ([`super::RunReport::warnings`]).
    pub warnings: Vec<String>,
    /// Whether its run completed: the table's `status` column; the figures of a point
    /// that did not complete are left empty in the table and out of the plot.
    pub status: PointStatus,
}

/// How a sweep's point ended (the table's `status` column).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum PointStatus {
    /// The run reached its end: its figures are results.
    Complete,
    /// Stopped (SIGINT, SIGTERM) before its end, or not started: its figures are not
    /// results.
    Interrupted,
    /// The run failed (the divergence guard, an output error): the message.
    Failed(String),
}

impl PointStatus {
    /// [`PointStatus::Complete`] or [`PointStatus::Interrupted`] as a point's
    /// `summary.json` records it (its `interrupted` flag; a summary without the flag is an
    /// older one, written only at a run's end).
    pub fn of_summary(summary: &serde_json::Value) -> Self {
        if summary["interrupted"].as_bool() == Some(true) {
            Self::Interrupted
        } else {
            Self::Complete
        }
    }

    /// True for [`PointStatus::Complete`].
    pub fn is_complete(&self) -> bool {
        *self == Self::Complete
    }
}

impl std::fmt::Display for PointStatus {
    /// `complete`, `interrupted` or `failed: <message>` (one line).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Complete => f.write_str("complete"),
            Self::Interrupted => f.write_str("interrupted"),
            Self::Failed(m) => write!(f, "failed: {}", m.replace(['\n', '\r'], " ")),
        }
    }
}

impl std::str::FromStr for PointStatus {
    type Err = String;

    /// The inverse of `Display`.
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "complete" => Ok(Self::Complete),
            "interrupted" => Ok(Self::Interrupted),
            _ => s
                .strip_prefix("failed: ")
                .map(|m| Self::Failed(m.to_string()))
                .ok_or_else(|| {
                    format!("status `{s}`: expected complete, interrupted or failed: MESSAGE")
                }),
        }
    }
}

impl SweepPoint {
    /// `key = value, key = value` of the point, for messages.
    pub fn label(&self) -> String {
        point_label(&self.sets)
    }
}

/// `key = value, ...` of a point's overrides.
fn point_label(sets: &[Override]) -> String {
    sets.iter()
        .map(|o| format!("{} = {}", o.key, o.value))
        .collect::<Vec<_>>()
        .join(", ")
}

/// Errors of a sweep.
#[derive(Debug, thiserror::Error)]
pub enum SweepError {
    /// The key cannot be set or the result is not a valid scenario.
    #[error("{key} = {value}: {message}")]
    Value {
        /// Key (the keys of a grid's point, comma-separated).
        key: String,
        /// Value.
        value: String,
        /// Cause.
        message: String,
    },
    /// A run failed.
    #[error(transparent)]
    Run(#[from] RunError),
}

/// [`run_points`] over the values of one key.
///
/// # Errors
/// [`SweepError`].
pub fn run_ladder(
    path: &Path,
    text: &str,
    key: &str,
    values: &[String],
    out: &Path,
    cancel: &Cancel,
) -> Result<Vec<SweepPoint>, SweepError> {
    let points: Vec<Vec<Override>> = values
        .iter()
        .map(|v| {
            vec![Override {
                key: key.to_string(),
                value: v.clone(),
            }]
        })
        .collect();
    run_points(path, text, &points, out, cancel)
}

/// Why [`check_points`] refused a point of a sweep.
#[derive(Debug)]
pub enum PointRefused {
    /// The point's folder: a name longer than a folder's name may be, or the name of an
    /// earlier point (a value given twice).
    Folder {
        /// The point's index.
        point: usize,
        /// The one-line message.
        message: String,
    },
    /// The scenario with the point's values set in is refused (the key at fault in it).
    Scenario {
        /// The point's index.
        point: usize,
        /// The validation's error.
        error: crate::scenario::ScenarioError,
    },
}

impl PointRefused {
    /// The index of the point refused.
    pub fn point(&self) -> usize {
        match self {
            Self::Folder { point, .. } | Self::Scenario { point, .. } => *point,
        }
    }

    /// The one-line message.
    pub fn message(&self) -> String {
        match self {
            Self::Folder { message, .. } => message.clone(),
            Self::Scenario { error, .. } => error.to_string(),
        }
    }
}

/// Validates and builds the scenario text at `path` (named so in messages) for every
/// point (its overrides written into the text as `--set` writes them), as `run_points`
/// does before any run starts: each point's folder name ([`point_dir_name`]) short enough
/// and given once, each point's scenario valid. Returns the built scenarios in the points'
/// order. The Python package's sweeps call it before they dispatch any point.
///
/// # Errors
/// [`PointRefused`]: the first point refused.
pub fn check_points(
    path: &Path,
    text: &str,
    points: &[Vec<Override>],
) -> Result<Vec<crate::scenario::Scenario>, PointRefused> {
    let mut scs = Vec::with_capacity(points.len());
    let mut dirs = std::collections::BTreeSet::new();
    for (point, sets) in points.iter().enumerate() {
        let name = point_dir_name(sets);
        if name.len() > crate::output::staging::NAME_MAX {
            return Err(PointRefused::Folder {
                point,
                message: format!(
                    "{}: the point's folder `<key>=<value>` would have a name of {} bytes, more than the {} a folder's name may have: sweep shorter values",
                    path.display(),
                    name.len(),
                    crate::output::staging::NAME_MAX
                ),
            });
        }
        if !dirs.insert(name) {
            return Err(PointRefused::Folder {
                point,
                message: "given twice: give every value once".into(),
            });
        }
        let sc = read_with(text, path, sets, &crate::kinds::Registry::builtin())
            .and_then(|(sc, _)| resolve(&sc))
            .map_err(|error| PointRefused::Scenario { point, error })?;
        scs.push(sc);
    }
    Ok(scs)
}

/// Validates and builds the scenario text at `path` for every point (its overrides written
/// into the text as `--set` writes them; all before any run starts), then runs them in
/// parallel (rayon, in the caller's pool; each run on the cores over the runs at once,
/// [`Par::threads`]: one thread each when the pool fills the cores) into
/// `out/<key>=<value>,.../`; returns the points in their order, each with its
/// [`PointStatus`]. `cancel` stops every run at its next step; a point not started by then
/// is not run (interrupted, no folder). A run that fails is that point's status (its
/// message naming files relative to `out`), not an error of the sweep: the other points
/// go on.
///
/// # Errors
/// [`SweepError`]: a point that cannot be set or built (before any run starts), `out` not
/// created.
pub fn run_points(
    path: &Path,
    text: &str,
    points: &[Vec<Override>],
    out: &Path,
    cancel: &Cancel,
) -> Result<Vec<SweepPoint>, SweepError> {
    let scs: Vec<(Vec<Override>, crate::scenario::Scenario)> = check_points(path, text, points)
        .map_err(|r| {
            let sets = &points[r.point()];
            let join =
                |f: &dyn Fn(&Override) -> &str| sets.iter().map(f).collect::<Vec<_>>().join(",");
            SweepError::Value {
                key: join(&|o| o.key.as_str()),
                value: join(&|o| o.value.as_str()),
                message: r.message(),
            }
        })?
        .into_iter()
        .zip(points)
        .map(|(sc, sets)| (sets.clone(), sc))
        .collect();
    std::fs::create_dir_all(out).map_err(|e| RunError::output(out, e))?;
    // The runs share the cores: each on its share of them (one thread, no helper for its
    // split solves, when as many run at once as there are cores; both threads of two
    // cores with `--jobs 1`). The same bits on any threads.
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let at_once = rayon::current_num_threads().min(scs.len()).max(1);
    let opts = RunOptions {
        progress: false,
        par: Some(Par::threads(cores / at_once)),
        cancel: cancel.clone(),
        ..RunOptions::default()
    };
    // One run at a time: each summary's peak memory is its run's, the peak reset before it;
    // runs at once share the process's.
    let alone = at_once == 1;
    let results: Vec<SweepPoint> = scs
        .par_iter()
        .map(|(sets, sc)| {
            let dir = out.join(point_dir_name(sets));
            let mut point = SweepPoint {
                sets: sets.clone(),
                value: sets
                    .iter()
                    .map(|o| o.value.as_str())
                    .collect::<Vec<_>>()
                    .join(","),
                dir: dir.clone(),
                summary: serde_json::Value::Null,
                warnings: Vec::new(),
                status: PointStatus::Interrupted,
            };
            if cancel.is_cancelled() {
                crate::output::note(format_args!("  {}: not started", point_label(sets)));
                return point;
            }
            let own = alone && crate::run::provenance::reset_peak_rss();
            match crate::run::provenance::with_peak_scope(!own, || run_scenario(sc, &dir, &opts)) {
                Ok(rep) => {
                    point.summary = std::fs::read_to_string(dir.join("summary.json"))
                        .ok()
                        .and_then(|s| serde_json::from_str(&s).ok())
                        .unwrap_or(serde_json::Value::Null);
                    point.warnings = rep.warnings;
                    point.status = if rep.interrupted {
                        PointStatus::Interrupted
                    } else {
                        PointStatus::Complete
                    };
                }
                Err(e) => {
                    // Paths inside the sweep's folder named from it (the folder may be a
                    // staging folder renamed at the end); what the run wrote before it
                    // failed is not a result.
                    let m = e.to_string().replace(&format!("{}/", out.display()), "");
                    point.status = PointStatus::Failed(m);
                    let _ = std::fs::remove_dir_all(&dir);
                }
            }
            crate::output::note(format_args!(
                "  {}: {}",
                point_label(sets),
                match &point.status {
                    PointStatus::Complete => "done".to_string(),
                    s => s.to_string(),
                }
            ));
            point
        })
        .collect();
    Ok(results)
}

/// The folder of one point, `<key>=<value>,<key>=<value>` (quotes trimmed, path separators
/// replaced by `_` so that a value never leads out of the sweep's folder).
pub fn point_dir_name(sets: &[Override]) -> String {
    sets.iter()
        .map(|o| format!("{}={}", o.key, o.value.trim_matches('"')))
        .collect::<Vec<_>>()
        .join(",")
        .replace(['/', '\\'], "_")
}

/// Runs the scenario text at `path` at every point of a grid ([`crate::scenario::overrides::grid`]),
/// in parallel (rayon), into `out/<key>=<value>,.../`; writes the table (a column per key)
/// and, when one key varies and its values are numbers, the plot into `out`.
///
/// # Errors
/// [`SweepError`]; every point is validated and built before any run starts.
pub fn sweep(
    path: &Path,
    text: &str,
    points: &[Vec<Override>],
    out: &Path,
    cancel: &Cancel,
) -> Result<(Vec<SweepPoint>, Vec<PathBuf>), SweepError> {
    let points = run_points(path, text, points, out, cancel)?;
    let files = write_sweep(out, &points)?;
    Ok((points, files))
}

/// Writes `text` atomically to `out/name`; returns the file.
///
/// # Errors
/// [`SweepError`] when the file cannot be written.
pub(crate) fn write_text(out: &Path, name: &str, text: &str) -> Result<PathBuf, SweepError> {
    let f = out.join(name);
    write_atomic(&f, text.as_bytes()).map_err(|e| RunError::output(&f, e))?;
    Ok(f)
}

/// Writes a sweep's table (`sweep.csv`, `sweep.md`; a column per key) and plot
/// (`sweep.png`, Fig. 15, for wheels over the one key that varies; `creep_curve.png` and
/// `.csv` over `rolling.creepage` with friction; `speed_effect.*` for the 3D rolling over
/// its speed, [`speed`]; `cost.*` for any 3D rolling sweep, [`cost`]) into `out`, from the
/// points' summaries in
/// the order given; returns the files.
///
/// # Errors
/// [`SweepError`] when a file cannot be written.
pub fn write_sweep(out: &Path, points: &[SweepPoint]) -> Result<Vec<PathBuf>, SweepError> {
    let keys: Vec<String> = points
        .first()
        .map(|p| p.sets.iter().map(|o| o.key.clone()).collect())
        .unwrap_or_default();
    let (is_wheel, with_traction) = model_of(points);
    let cols = table_columns(points, is_wheel, with_traction);
    let mut files = write_tables(out, &keys, &cols, points)?;
    // The 3D rolling runs' cost: the step against the free step and the memory's floor.
    if cost::applies(points) {
        files.extend(cost::cost(out, points)?);
    }
    // Fig. 15 for wheels, over the one key that varies.
    let varying: Vec<usize> = (0..keys.len())
        .filter(|&i| {
            points
                .iter()
                .any(|p| p.sets[i].value != points[0].sets[i].value)
        })
        .collect();
    // The 3D rolling over its speed (alone, or with a ladder or creepages): what inertia
    // changes.
    if let Some((_, other)) = speed::study_keys(points, &keys, &varying) {
        if points.iter().any(|p| p.status.is_complete()) {
            files.extend(speed::speed_effect(out, points, other)?);
        }
        return Ok(files);
    }
    // The 3D rolling on a crowned base over its creepages: Kalker's coefficients. A sweep
    // of the longitudinal creepage goes on to the creep curve.
    if let Some(study) = kalker::study_keys(points, &keys, &varying) {
        if points.iter().any(|p| p.status.is_complete()) {
            files.extend(kalker::coefficients(out, points, &study)?);
        }
        if study.creepages != [0] {
            return Ok(files);
        }
    }
    // The 3D rolling under refinement of its mesh, its step or both: the steady figures,
    // the slip area's history and the ripple.
    if slip_history::applies(points, &keys, &varying) {
        if points.iter().any(|p| p.status.is_complete()) {
            files.extend(slip_history::slip_history(out, points)?);
        }
        return Ok(files);
    }
    // A creepage sweep on a refinement ladder: the creep curve per rung and its limit.
    if let [i, j] = varying[..] {
        let numeric = |k: usize| {
            points
                .iter()
                .all(|p| p.sets[k].value.trim_matches('"').parse::<f64>().is_ok())
        };
        let creep = |k: usize| keys[k] == "rolling.creepage";
        if with_traction && numeric(i) && numeric(j) && (creep(i) || creep(j)) {
            let (c, r) = if creep(i) { (i, j) } else { (j, i) };
            if points.iter().any(|p| p.status.is_complete()) {
                files.extend(creep::creep_ladder(out, points, c, r)?);
            }
        }
        return Ok(files);
    }
    let [i] = varying[..] else {
        return Ok(files);
    };
    let key = keys[i].as_str();
    let x_of = |p: &SweepPoint| p.sets[i].value.trim_matches('"').parse::<f64>().ok();
    if points.iter().any(|p| x_of(p).is_none()) {
        return Ok(files);
    }
    // The figures draw the points that completed; the others are marked where they are
    // (a dashed line) and named in a note, never drawn as values.
    let shown: Vec<SweepPoint> = points
        .iter()
        .filter(|p| p.status.is_complete())
        .cloned()
        .collect();
    let xs: Vec<f64> = shown.iter().filter_map(x_of).collect();
    let left_out: Vec<(f64, &PointStatus, &str)> = points
        .iter()
        .filter(|p| !p.status.is_complete())
        .filter_map(|p| Some((x_of(p)?, &p.status, p.sets[i].value.as_str())))
        .collect();
    if shown.is_empty() {
        return Ok(files);
    }
    let mark = |panel: &mut Panel, to_axis: &dyn Fn(f64) -> f64| {
        mark_left_out(panel, key, &left_out, to_axis);
    };
    if with_traction && key == "rolling.creepage" {
        files.extend(creep_curve(out, &shown, &xs, &|p| mark(p, &|x| x))?);
    } else if is_wheel {
        let png = out.join("sweep.png");
        // The axis of a sweep of omega is the speed: omega's points at the same scale.
        let (axis, _) = sweep_axis(key, &shown, &xs);
        let scale = axis[0] / xs[0];
        let to_axis = |x: f64| if scale.is_finite() { x * scale } else { x };
        let mut panes = [
            oscillations_panel(key, &shown, &xs),
            force_panel(key, &shown, &xs),
        ];
        for p in &mut panes {
            mark(p, &to_axis);
        }
        panels(&png, &panes, 2, 1, (1200, 1100)).map_err(|e| RunError::output(&png, e))?;
        files.push(png);
    }
    Ok(files)
}

/// The CSV (and Markdown) names of the tables' columns whose summary key does not name its
/// unit: `(summary key, column)`, the column the key with its unit appended as
/// `history.csv` writes units (`_N`, `_J`, `_m`, `_Pa`, `_s`, `_m_s`, `_rad_s`). A key not
/// listed keeps its name: it names its unit already (`wall_time_s`, `speed_km_h`,
/// `bounce_frequency_hz`, `max_von_mises_turn_average_mpa`, the track's `_n`, `_m`, `_hz`),
/// or it is a count or a ratio (`steps`, `dofs`, `mean_nodes_in_contact`,
/// `traction/traction_ratio`, `errors.*` relative errors, ...). `sweep.csv` and
/// `converge.csv` (its `figure` column) both rename through this one list.
pub const COLUMN_NAMES: [(&str, &str); 41] = [
    // The wheel (and the wheel on a block).
    ("mean_contact_force", "mean_contact_force_N"),
    ("min_contact_force", "min_contact_force_N"),
    ("max_contact_force", "max_contact_force_N"),
    ("contact_force_ripple", "contact_force_ripple_N"),
    ("energy_after_settling", "energy_after_settling_J"),
    ("energy_initial", "energy_initial_J"),
    ("energy_final", "energy_final_J"),
    ("omega", "omega_rad_s"),
    ("h", "h_s"),
    // With friction.
    ("traction/normal", "traction/normal_N"),
    ("traction/traction", "traction/traction_N"),
    (
        "traction/measured_stick_half_width",
        "traction/measured_stick_half_width_m",
    ),
    ("traction/hertz_half_width", "traction/hertz_half_width_m"),
    ("traction/friction_energy", "traction/friction_energy_J"),
    // The wheel on a block.
    ("block_speed", "block_speed_m_s"),
    ("block_length", "block_length_m"),
    ("block_depth", "block_depth_m"),
    ("block_young", "block_young_Pa"),
    ("contact_modulus", "contact_modulus_Pa"),
    ("mean_half_width", "mean_half_width_m"),
    ("hertz_half_width", "hertz_half_width_m"),
    // The bars (one run's figures in `converge.csv`).
    ("impact_time", "impact_time_s"),
    ("release_time", "release_time_s"),
    ("contact_duration", "contact_duration_s"),
    ("peak_contact_force", "peak_contact_force_N"),
    ("peak_braking_force", "peak_braking_force_N"),
    ("rebound_velocity", "rebound_velocity_m_s"),
    ("velocity_left_behind", "velocity_left_behind_m_s"),
    ("max_penetration", "max_penetration_m"),
    ("penetration_at_release", "penetration_at_release_m"),
    ("errors.impact_time", "errors.impact_time_s"),
    // The oscillator.
    ("period_exact", "period_exact_s"),
    ("period_measured", "period_measured_s"),
    ("max_displacement_error", "max_displacement_error_m"),
    // Inputs a sweep may carry in its summaries.
    ("speed", "speed_m_s"),
    ("gap", "gap_m"),
    ("length", "length_m"),
    ("radius", "radius_m"),
    ("flattening", "flattening_m"),
    ("load", "load_N"),
    ("t_end", "t_end_s"),
];

/// The units of the scenario keys a sweep or a ladder may vary, `(key, unit suffix)`: the
/// swept key's column is `<key>_<unit>` (`time.h_s`, `rolling.omega_rad_s`). A key not
/// listed names its unit (`rolling.speed_km_h`) or has none (`wheel.rings`,
/// `rolling.creepage`, `contact.friction`).
pub const KEY_UNITS: [(&str, &str); 22] = [
    ("time.h", "s"),
    ("time.t_end", "s"),
    ("rolling.omega", "rad_s"),
    ("rolling.flattening", "m"),
    ("rolling.settle_time", "s"),
    ("wheel.radius", "m"),
    ("wheel.thickness", "m"),
    ("wheel.hub_radius", "m"),
    ("wheel.load", "N"),
    ("wheel.zone_width", "m"),
    ("wheel.zone_depth", "m"),
    ("material.young", "Pa"),
    ("material.density", "kg_m3"),
    ("material.yield_stress", "Pa"),
    ("bar.length", "m"),
    ("bar.speed", "m_s"),
    ("bar.gap", "m"),
    ("sdof.mass", "kg"),
    ("sdof.stiffness", "N_m"),
    ("vehicle.speed", "m_s"),
    ("vehicle.axle_load", "N"),
    ("track.spacing", "m"),
];

/// The column name of a summary key ([`COLUMN_NAMES`]).
pub fn column_name(key: &str) -> &str {
    COLUMN_NAMES
        .iter()
        .find(|(k, _)| *k == key)
        .map_or(key, |(_, c)| c)
}

/// The column name of a swept scenario key, with its unit ([`KEY_UNITS`]).
pub fn key_column(key: &str) -> String {
    KEY_UNITS
        .iter()
        .find(|(k, _)| *k == key)
        .map_or_else(|| key.to_string(), |(k, u)| format!("{k}_{u}"))
}

/// Marks the points of a sweep that did not complete on a panel: a dashed vertical line
/// at each (`to_axis` maps the swept value to the panel's x) and a note naming them.
fn mark_left_out(
    panel: &mut Panel,
    key: &str,
    left_out: &[(f64, &PointStatus, &str)],
    to_axis: &dyn Fn(f64) -> f64,
) {
    if left_out.is_empty() {
        return;
    }
    for (x, status, _) in left_out {
        let what = match status {
            PointStatus::Failed(_) => "failed run (no result)",
            _ => "interrupted run (no result)",
        };
        panel.vlines.push((to_axis(*x), what.to_string()));
    }
    let names: Vec<String> = left_out
        .iter()
        .map(|(_, s, v)| match s {
            PointStatus::Failed(_) => format!("{v} (failed)"),
            _ => format!("{v} ({s})"),
        })
        .collect();
    let note = format!(
        "Not drawn: {key} = {}: these runs did not complete (status column of sweep.csv).",
        names.join(", ")
    );
    panel.note = if panel.note.is_empty() {
        note
    } else {
        format!("{} {note}", panel.note)
    };
}

/// Whether the points are wheels, and wheels (2D, or the 3D `rolling3d`) with friction, by
/// the summaries they have (a point that failed or was not started has none): the table's
/// key figures (wheel), or every scalar number of the summaries; with friction the traction
/// figures (nested in the summary's `traction`).
fn model_of(points: &[SweepPoint]) -> (bool, bool) {
    let run: Vec<&SweepPoint> = points.iter().filter(|p| p.summary.is_object()).collect();
    let all_of = |kind: &str| !run.is_empty() && run.iter().all(|p| p.summary["kind"] == kind);
    let is_wheel = all_of("wheel");
    // The 3D wheel on its base writes the same traction figures (kinds::rolling3d::run).
    let with_traction =
        (is_wheel || all_of("rolling3d")) && run.iter().all(|p| p.summary["traction"].is_object());
    (is_wheel, with_traction)
}

/// The table's columns: the wheel's key figures (and with friction its traction figures,
/// `traction/...`), or every scalar number of the summaries of other models.
fn table_columns(points: &[SweepPoint], is_wheel: bool, with_traction: bool) -> Vec<String> {
    let mut cols: Vec<String> = if is_wheel {
        [
            "speed_km_h",
            "mean_contact_force",
            "min_contact_force",
            "max_contact_force",
            "oscillations_per_turn",
            "fixed_frequency_cycles_per_turn",
            "bounce_frequency_hz",
            "max_von_mises_turn_average_mpa",
            "energy_after_settling",
            "energy_final",
            "steps",
            "wall_time_s",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect()
    } else {
        Vec::new()
    };
    if with_traction {
        for c in [
            "traction/creepage",
            "traction/creepage_undeformed",
            "traction/normal",
            "traction/traction",
            "traction/traction_ratio",
            "traction/traction_ratio_steady",
            "traction/transient_decay",
            "traction/carter_traction_ratio",
            "traction/mean_stick_nodes",
            "traction/mean_slip_nodes",
            "traction/measured_stick_half_width",
            "traction/hertz_half_width",
            "traction/friction_energy",
        ] {
            cols.push(c.to_string());
        }
    }
    for p in points.iter().filter(|_| !is_wheel) {
        if let Some(o) = p.summary.as_object() {
            for (k, v) in o {
                if (v.is_number() || k == "oscillations_per_turn") && !cols.contains(k) {
                    cols.push(k.clone());
                }
            }
        }
    }
    cols
}

/// The table's cell of point `p` in column `c` (a path `a/b` into the summary's nested
/// objects): a float to five decimals (below 0.01, to six significant digits: a step of
/// 2.5e-6 s is not 0.00000), an array as JSON (`[3,4,4]`; quoted in the CSV), nothing for
/// the rest.
fn table_cell(p: &SweepPoint, c: &str) -> String {
    let v = if c.contains('/') {
        p.summary
            .pointer(&format!("/{c}"))
            .unwrap_or(&serde_json::Value::Null)
    } else {
        &p.summary[c]
    };
    match v {
        serde_json::Value::Number(n) => match n.as_f64() {
            Some(x) if n.is_f64() && x != 0.0 && x.abs() < 1e-2 => format!("{x:.5e}"),
            Some(x) if n.is_f64() => format!("{x:.5}"),
            _ => n.to_string(),
        },
        serde_json::Value::Array(_) => v.to_string(),
        _ => String::new(),
    }
}

/// Writes the table, a row per point (a column per swept key, the point's `status`
/// ([`PointStatus`]), then the figures: empty cells for a point that did not complete, whose
/// numbers are not results), as `sweep.csv` and `sweep.md` into `out`.
fn write_tables(
    out: &Path,
    keys: &[String],
    cols: &[String],
    points: &[SweepPoint],
) -> Result<Vec<PathBuf>, RunError> {
    let mut files = Vec::new();
    let status = ["status".to_string()];
    let head: Vec<String> = keys
        .iter()
        .map(|k| key_column(k))
        .chain(status.iter().cloned())
        .chain(cols.iter().map(|c| column_name(c).to_string()))
        .collect();
    let mut csv = crate::output::csv::record(&head);
    let mut md = format!(
        "| {} |\n|{}|\n",
        head.join(" | "),
        vec!["---"; head.len()].join("|")
    );
    for p in points {
        let row: Vec<String> = p
            .sets
            .iter()
            .map(|o| o.value.clone())
            .chain([p.status.to_string()])
            .chain(cols.iter().map(|c| {
                if p.status.is_complete() {
                    table_cell(p, c)
                } else {
                    String::new()
                }
            }))
            .collect();
        crate::output::csv::push_record(&mut csv, &row);
        let md_row: Vec<String> = row.iter().map(|c| c.replace('|', "\\|")).collect();
        let _ = writeln!(md, "| {} |", md_row.join(" | "));
    }
    for (name, body) in [("sweep.csv", csv), ("sweep.md", md)] {
        let f = out.join(name);
        write_atomic(&f, body.as_bytes()).map_err(|e| RunError::output(&f, e))?;
        files.push(f);
    }
    Ok(files)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every column of a wheel sweep with friction names its unit, or is a count or a
    /// ratio; no two keys share a column; the swept step and spin carry theirs.
    #[test]
    fn every_wheel_column_names_its_unit() {
        let units = [
            "_N",
            "_J",
            "_m",
            "_s",
            "_us",
            "_hz",
            "_mpa",
            "_km_h",
            "_per_turn",
        ];
        let unitless = [
            "steps",
            "oscillations_per_turn",
            "traction/creepage",
            "traction/creepage_undeformed",
            "traction/traction_ratio",
            "traction/traction_ratio_steady",
            "traction/transient_decay",
            "traction/carter_traction_ratio",
            "traction/mean_stick_nodes",
            "traction/mean_slip_nodes",
        ];
        let point = SweepPoint {
            sets: Vec::new(),
            value: String::new(),
            dir: PathBuf::new(),
            summary: serde_json::json!({"kind": "wheel", "traction": {}}),
            warnings: Vec::new(),
            status: PointStatus::Complete,
        };
        for c in table_columns(&[point], true, true) {
            let name = column_name(&c);
            assert!(
                units.iter().any(|u| name.ends_with(u)) || unitless.contains(&name),
                "{c} -> {name}"
            );
        }
        let mut names: Vec<&str> = COLUMN_NAMES.iter().map(|(_, c)| *c).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), COLUMN_NAMES.len());
        assert!(COLUMN_NAMES.iter().all(|(k, c)| c.starts_with(k) && c != k));
        assert_eq!(key_column("time.h"), "time.h_s");
        assert_eq!(key_column("rolling.omega"), "rolling.omega_rad_s");
        assert_eq!(key_column("rolling.speed_km_h"), "rolling.speed_km_h");
        assert_eq!(key_column("wheel.rings"), "wheel.rings");
    }
}
