//! The observers of a wheel run: each watches the final steps of the step loop and keeps
//! what one output needs. The job attaches them to the loop ([`super::simulate`]); each has
//! `observe` (per step, no allocation: every buffer is sized in its constructor) and
//! `finish` (after the loop: its result).
//!
//! | observer | keeps | gives |
//! |---|---|---|
//! | [`HistoryWriter`] | `history.csv`'s rows, one per `stride` steps (held or streamed) | the table |
//! | [`ContactNodesWriter`] | `contact_nodes.csv`'s rows (held or streamed) | the table |
//! | [`ContactForceStats`] | the contact force over time, nodes held, penetration | [`ContactForceSummary`]: mean / min / max over the rolling phase, oscillations per turn, spectrum |
//! | [`EnergyWatch`] | the energy after settling and at the end | the two values |
//! | [`TurnAverage`] | sums of the element `J2` and von Mises over the last full turn | [`TurnAverageFields`] |
//! | [`VelocitySnapshots`] | `u`, `v` at evenly spaced instants of the last full turn | [`Snapshots`] |
//! | [`Progress`] | the progress bar | - |

use crate::analysis::signal::{
    amplitude_spectrum, count_oscillations, dominant_peak, moving_average, resample_uniform,
    Spectrum,
};
use crate::analysis::trace::{Envelope, LatestWindow, ENVELOPE_CAP, SPECTRUM_WINDOW_CAP};
use crate::bodies::wheel::WheelModel;
use crate::contact::{PairState, RotatingLine};
use crate::element::tri3;
use crate::linalg::team::Team;
use crate::output::table::{Columns, Rows};
use crate::run::error::RunError;
use crate::run::options::{progress_bar, RunOptions};
use std::f64::consts::PI;
use std::path::Path;

/// What an observer sees of one final step (made from the driver's view in one place,
/// [`super::drive`]).
#[derive(Debug, Clone, Copy)]
pub struct WheelStep<'a> {
    /// Step index (0: the initial state).
    pub k: usize,
    /// Time, s.
    pub t: f64,
    /// Displacements, m.
    pub u: &'a [f64],
    /// Velocities, m/s.
    pub v: &'a [f64],
    /// Kinetic and strain energy (of the elastic stiffness), J, where they were computed:
    /// every `history_stride`-th step, the first step of the rolling phase and the last.
    pub energy: Option<(f64, f64)>,
    /// Energy stored in penalty springs, J (0 for the other treatments).
    pub penalty: f64,
    /// Total contact force, N.
    pub contact_force: f64,
    /// Rim nodes held on the base.
    pub held: usize,
    /// Smallest gap over the rim nodes, m (negative: penetration).
    pub min_gap: f64,
    /// The rim nodes' contact states, in the order of [`WheelModel::rim`].
    pub pairs: &'a [PairState],
    /// Frictional dissipation of the step, W (0 without friction).
    pub slip_power: f64,
    /// Energy dissipated by friction since the start, J.
    pub friction_dissipated: f64,
    /// The angle the mesh's frame has turned by with a moving refined zone, rad
    /// ([`crate::simulation::StepView::frame_angle`]; 0 without one).
    pub frame_angle: f64,
    /// The run's threads, for an observer whose per-element work divides (none: one
    /// thread).
    pub team: Option<&'a Team>,
}

/// A per-step observer of the wheel run.
pub trait Observer {
    /// Takes note of one final step.
    ///
    /// # Errors
    /// I/O errors of an observer that writes as it goes.
    fn observe(&mut self, s: &WheelStep) -> std::io::Result<()>;
}

/// The phases of a wheel run: settling until `t_settle`, then `turns` turns of
/// `turn_time` each. An instant `t` of the step grid belongs to `[a, b)` when
/// `a - h/2 <= t < b - h/2`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Timeline {
    /// Time step, s.
    pub h: f64,
    /// End of settling, s.
    pub t_settle: f64,
    /// One turn, `2 pi / omega`, s.
    pub turn_time: f64,
    /// Turns after settling.
    pub turns: f64,
}

impl Timeline {
    /// True from the end of settling on.
    pub fn rolling(&self, t: f64) -> bool {
        t >= self.t_settle - 0.5 * self.h
    }

    /// True when `t` is in `[a, b)` (type docs).
    pub fn within(&self, t: f64, a: f64, b: f64) -> bool {
        t >= a - 0.5 * self.h && t < b - 0.5 * self.h
    }

    /// The last full turn (the first one if fewer than one), `(start, end)`, s.
    pub fn last_full_turn(&self) -> (f64, f64) {
        let full_turns = self.full_turns();
        (
            self.t_settle + (full_turns - 1.0) * self.turn_time,
            self.t_settle + full_turns * self.turn_time,
        )
    }

    /// Number of full turns, at least 1.
    pub fn full_turns(&self) -> f64 {
        self.turns.floor().max(1.0)
    }
}

/// The error of a table's file (`path`; `name` when held in memory).
fn table_error(path: Option<&Path>, name: &str, e: std::io::Error) -> RunError {
    RunError::output(path.unwrap_or(Path::new(name)), e)
}

/// `history.csv`: one row every `stride` steps, held or streamed to a file.
#[derive(Debug)]
pub struct HistoryWriter {
    csv: Rows,
    stride: usize,
    base: RotatingLine,
}

impl HistoryWriter {
    /// The columns and their units (`settling`: 1 while the base presses the wheel to its
    /// flattening, before `rolling.settle_time`; 0 in the rolling phase the summary's
    /// figures are taken from).
    pub const COLUMNS: [(&'static str, &'static str); 9] = [
        ("t_s", "s"),
        ("base_angle_deg", "deg"),
        ("contact_force_N", "N"),
        ("nodes_in_contact", "1"),
        ("kinetic_J", "J"),
        ("strain_J", "J"),
        ("total_J", "J"),
        ("min_gap_m", "m"),
        ("settling", "1"),
    ];

    /// Rows streamed to `path` (created now, header written) when given, else held with
    /// room for the rows of `steps` steps; `base` gives the base angle column.
    ///
    /// # Errors
    /// [`RunError::Output`].
    pub fn create(
        path: Option<&Path>,
        stride: usize,
        base: RotatingLine,
        steps: usize,
    ) -> Result<Self, RunError> {
        let stride = stride.max(1);
        let csv = Rows::open(Columns::new(&Self::COLUMNS), path, steps / stride + 1)
            .map_err(|e| table_error(path, "history.csv", e))?;
        Ok(Self { csv, stride, base })
    }

    /// The table (the file closed when streamed).
    ///
    /// # Errors
    /// [`RunError::Output`].
    pub fn finish(self) -> Result<Columns, RunError> {
        finish_rows(self.csv, "history.csv")
    }
}

/// Closes `rows` (named `name` in an error).
fn finish_rows(rows: Rows, name: &str) -> Result<Columns, RunError> {
    let path = match &rows {
        Rows::File { path, .. } => Some(path.clone()),
        Rows::Memory(_) => None,
    };
    rows.finish()
        .map_err(|e| table_error(path.as_deref(), name, e))
}

impl Observer for HistoryWriter {
    fn observe(&mut self, s: &WheelStep) -> std::io::Result<()> {
        if s.k % self.stride == 0 {
            let (kinetic, strain) = s.energy.unwrap_or((f64::NAN, f64::NAN));
            self.csv.push(
                0,
                &[
                    s.t,
                    self.base.angle(s.t).to_degrees(),
                    s.contact_force,
                    s.held as f64,
                    kinetic,
                    strain,
                    kinetic + strain + s.penalty,
                    s.min_gap,
                    if s.t < self.base.flattening.settle_time {
                        1.0
                    } else {
                        0.0
                    },
                ],
            )?;
        }
        Ok(())
    }
}

/// `contact_nodes.csv`: the contact force per contact node, long format: one row per rim
/// node carrying a reaction (or held) every `stride` steps, `node, t_s, force_N, gap_m,
/// held` (node: the mesh's node index); with friction also `tangential_N` (the friction
/// force on the node along the pair's tangent, the direction of the rail's travel) and
/// `sliding` (1 on the Coulomb bound, 0 in stick).
#[derive(Debug)]
pub struct ContactNodesWriter {
    csv: Rows,
    stride: usize,
    friction: bool,
}

impl ContactNodesWriter {
    /// The columns after the key `node` (the mesh's node index) and their units.
    pub const COLUMNS: [(&'static str, &'static str); 4] = [
        ("t_s", "s"),
        ("force_N", "N"),
        ("gap_m", "m"),
        ("held", "1"),
    ];

    /// The columns with friction.
    pub const COLUMNS_FRICTION: [(&'static str, &'static str); 6] = [
        ("t_s", "s"),
        ("force_N", "N"),
        ("gap_m", "m"),
        ("held", "1"),
        ("tangential_N", "N"),
        ("sliding", "1"),
    ];

    /// Rows streamed to `path` (created now, header written) when given, else held; `rim`
    /// are the pairs' nodes, in their order (the key's labels: no formatting of integers
    /// per row); `friction` adds the tangential columns.
    ///
    /// # Errors
    /// [`RunError::Output`].
    pub fn create(
        path: Option<&Path>,
        stride: usize,
        rim: &[usize],
        friction: bool,
    ) -> Result<Self, RunError> {
        let columns: &[(&str, &str)] = if friction {
            &Self::COLUMNS_FRICTION
        } else {
            &Self::COLUMNS
        };
        let ids = rim.iter().map(|n| n.to_string()).collect();
        let csv = Rows::open(Columns::keyed("node", ids, columns), path, 0)
            .map_err(|e| table_error(path, "contact_nodes.csv", e))?;
        Ok(Self {
            csv,
            stride: stride.max(1),
            friction,
        })
    }

    /// The table (the file closed when streamed).
    ///
    /// # Errors
    /// [`RunError::Output`].
    pub fn finish(self) -> Result<Columns, RunError> {
        finish_rows(self.csv, "contact_nodes.csv")
    }
}

impl Observer for ContactNodesWriter {
    fn observe(&mut self, s: &WheelStep) -> std::io::Result<()> {
        if s.k % self.stride == 0 {
            for (p, ps) in s.pairs.iter().enumerate() {
                if ps.held || ps.force != 0.0 {
                    let held = if ps.held { 1.0 } else { 0.0 };
                    if self.friction {
                        let sliding = if ps.sliding { 1.0 } else { 0.0 };
                        self.csv.push(
                            p as u32,
                            &[s.t, ps.force, ps.gap, held, ps.tangential_force, sliding],
                        )?;
                    } else {
                        self.csv.push(p as u32, &[s.t, ps.force, ps.gap, held])?;
                    }
                }
            }
        }
        Ok(())
    }
}

/// The contact force over the run, the nodes held and the largest penetration, in room that
/// does not grow with the run ([`crate::analysis::trace`]): the mean, extremes and nodes held
/// are summed over every rolling step, the plot keeps a min-max envelope of the whole run, and
/// the spectrum and the per-turn counts use the latest [`SPECTRUM_WINDOW_CAP`] rolling steps.
#[derive(Debug)]
pub struct ContactForceStats {
    timeline: Timeline,
    trace: Envelope,
    window: LatestWindow,
    rolling_sum: f64,
    rolling_max: f64,
    rolling_min: f64,
    held_sum: f64,
    max_penetration: f64,
}

/// The contact-force figures of a run (module docs of [`crate::kinds::wheel::run`]: counting rule).
#[derive(Debug, Clone)]
pub struct ContactForceSummary {
    /// Mean force over the rolling phase, N.
    pub mean: f64,
    /// Largest force over the rolling phase, N.
    pub max: f64,
    /// Smallest force over the rolling phase, N.
    pub min: f64,
    /// Mean number of rim nodes held over the rolling phase.
    pub mean_nodes_held: f64,
    /// Oscillations in each full turn.
    pub oscillations_per_turn: Vec<usize>,
    /// Amplitude spectrum of the rolling phase's force.
    pub spectrum: Spectrum,
    /// The largest peak of the spectrum above the rotation frequency, away from the
    /// node-passing harmonics: `(frequency Hz, amplitude N)`.
    pub dominant: Option<(f64, f64)>,
    /// Rotation frequency `omega / (2 pi)`, Hz.
    pub rotation_hz: f64,
    /// Node-passing frequency `omega N_rim / (2 pi)`, Hz.
    pub node_passing_hz: f64,
    /// Largest penetration, m (0 if none).
    pub max_penetration: f64,
    /// The force over the whole run to draw, `(t s, N)`: every step, or a min-max envelope
    /// of at most [`ENVELOPE_CAP`] buckets on a longer run ([`Envelope::points`]).
    pub plot: (Vec<f64>, Vec<f64>),
    /// The rolling steps the spectrum and the per-turn counts were taken from (the latest
    /// [`SPECTRUM_WINDOW_CAP`]), `(t s, N)`.
    pub window: (Vec<f64>, Vec<f64>),
    /// Rolling steps in all (kept in the window or not).
    pub rolling_steps: usize,
}

impl ContactForceStats {
    /// Room for `steps + 1` observations (at most the caps of the module docs).
    pub fn new(timeline: Timeline, steps: usize) -> Self {
        Self {
            timeline,
            trace: Envelope::new(ENVELOPE_CAP, steps + 1),
            window: LatestWindow::new(SPECTRUM_WINDOW_CAP, steps + 1),
            rolling_sum: 0.0,
            rolling_max: f64::NEG_INFINITY,
            rolling_min: f64::INFINITY,
            held_sum: 0.0,
            max_penetration: 0.0,
        }
    }

    /// The figures, for the spin `omega` (rad/s) and `n_rim` rim nodes.
    ///
    /// Oscillations per turn: within each full turn, the force smoothed by a centred moving
    /// average over the node-passage period, local maxima of prominence >= 10% of the
    /// turn's range ([`count_oscillations`]); only the turns within the window are counted.
    pub fn finish(self, omega: f64, n_rim: usize) -> ContactForceSummary {
        let tl = self.timeline;
        let h = tl.h;
        let rolling_steps = self.window.seen();
        let (window_t, window_f) = self.window.into_ordered();
        let (force_t, force_y) = (&window_t, &window_f);
        let nf = rolling_steps.max(1) as f64;
        let mean = self.rolling_sum / nf;
        let (fmax, fmin) = (self.rolling_max, self.rolling_min);
        let n_rim = n_rim.max(1);
        let node_pass_hz = omega * n_rim as f64 / (2.0 * PI);
        let smooth_w = ((1.0 / node_pass_hz) / h).round().max(1.0) as usize;
        let mut osc = Vec::new();
        for k in 0..(tl.turns.floor() as usize) {
            let (a, b) = (
                tl.t_settle + k as f64 * tl.turn_time,
                tl.t_settle + (k + 1) as f64 * tl.turn_time,
            );
            let seg: Vec<f64> = force_t
                .iter()
                .zip(force_y)
                .filter(|(t, _)| tl.within(**t, a, b))
                .map(|(_, f)| *f)
                .collect();
            if seg.len() > 3 {
                osc.push(count_oscillations(&moving_average(&seg, smooth_w), 0.1));
            }
        }
        let (_, ry) = resample_uniform(force_t, force_y, h);
        let spectrum = amplitude_spectrum(&ry, h);
        let rot_hz = omega / (2.0 * PI);
        // The wheel's own oscillation: the largest peak above the rotation frequency away
        // from the node-passing ripple and its harmonics (+-10%).
        let mut wheel_spec = spectrum.clone();
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
        let dominant = dominant_peak(&wheel_spec, rot_hz);
        ContactForceSummary {
            mean,
            max: fmax,
            min: fmin,
            mean_nodes_held: self.held_sum / nf,
            oscillations_per_turn: osc,
            spectrum,
            dominant,
            rotation_hz: rot_hz,
            node_passing_hz: node_pass_hz,
            max_penetration: self.max_penetration.max(0.0),
            plot: self.trace.points(),
            window: (window_t, window_f),
            rolling_steps,
        }
    }
}

impl Observer for ContactForceStats {
    fn observe(&mut self, s: &WheelStep) -> std::io::Result<()> {
        self.max_penetration = self.max_penetration.max(-s.min_gap);
        self.trace.push(s.t, s.contact_force);
        if self.timeline.rolling(s.t) {
            self.window.push(s.t, s.contact_force);
            self.rolling_sum += s.contact_force;
            self.rolling_max = self.rolling_max.max(s.contact_force);
            self.rolling_min = self.rolling_min.min(s.contact_force);
            self.held_sum += s.held as f64;
        }
        Ok(())
    }
}

/// The energy (kinetic + strain + penalty springs, J) at the first step of the rolling phase and at the end.
#[derive(Debug, Clone, Copy)]
pub struct EnergyWatch {
    timeline: Timeline,
    after_settling: Option<f64>,
    last: f64,
}

impl EnergyWatch {
    /// Nothing seen yet.
    pub fn new(timeline: Timeline) -> Self {
        Self {
            timeline,
            after_settling: None,
            last: 0.0,
        }
    }

    /// `(after settling, at the end)`, J (0 for what was not reached).
    pub fn finish(self) -> (f64, f64) {
        (self.after_settling.unwrap_or(0.0), self.last)
    }
}

impl Observer for EnergyWatch {
    fn observe(&mut self, s: &WheelStep) -> std::io::Result<()> {
        if let Some((kinetic, strain)) = s.energy {
            let e = kinetic + strain + s.penalty;
            self.last = e;
            if self.after_settling.is_none() && self.timeline.rolling(s.t) {
                self.after_settling = Some(e);
            }
        }
        Ok(())
    }
}

/// Sums of the element `J2` and von Mises stress over the steps of a window (the last
/// full turn): the turn average of Figs. 14 and 16. Stresses by
/// [`crate::element::tri3::stresses_into`], invariants by
/// [`crate::material::PlaneModel::stress_invariants`].
#[derive(Debug)]
pub struct TurnAverage<'a> {
    model: &'a WheelModel,
    timeline: Timeline,
    window: (f64, f64),
    stress: Vec<[f64; 3]>,
    j2_sum: Vec<f64>,
    von_mises_sum: Vec<f64>,
    count: usize,
    /// The stress of the Green strain (a wheel in large deformation), else the linear one.
    green: bool,
}

/// The turn-averaged element fields.
#[derive(Debug, Clone)]
pub struct TurnAverageFields {
    /// `J2` per element, MPa^2.
    pub j2_mpa2: Vec<f64>,
    /// Von Mises stress per element, MPa (the average of `sqrt(3 J2)`).
    pub von_mises_mpa: Vec<f64>,
}

impl<'a> TurnAverage<'a> {
    /// Averages over `[window.0, window.1)` (s) on the elements of `model`, of the stress
    /// of the Green strain (`green`: a wheel in large deformation,
    /// [`crate::element::tri3::green_stresses_into`], which a rigid rotation leaves alone)
    /// or of the linear strain.
    pub fn new(model: &'a WheelModel, timeline: Timeline, window: (f64, f64), green: bool) -> Self {
        let n_el = model.triangles.len();
        Self {
            model,
            timeline,
            window,
            stress: vec![[0.0; 3]; n_el],
            j2_sum: vec![0.0; n_el],
            von_mises_sum: vec![0.0; n_el],
            count: 0,
            green,
        }
    }

    /// The averages (zero fields when the window was not reached).
    pub fn finish(self) -> TurnAverageFields {
        let cnt = self.count.max(1) as f64;
        TurnAverageFields {
            j2_mpa2: self.j2_sum.iter().map(|v| v / cnt / 1e12).collect(),
            von_mises_mpa: self.von_mises_sum.iter().map(|v| v / cnt / 1e6).collect(),
        }
    }
}

impl Observer for TurnAverage<'_> {
    fn observe(&mut self, s: &WheelStep) -> std::io::Result<()> {
        if !self.timeline.within(s.t, self.window.0, self.window.1) {
            return Ok(());
        }
        let wm = self.model;
        let n = wm.triangles.len();
        // Each element's sums are its own: in two halves side by side (the team's second
        // thread is otherwise idle in a wheel this small), the same bits.
        let sums = (
            &mut self.stress[..],
            &mut self.j2_sum[..],
            &mut self.von_mises_sum[..],
        );
        match s.team.filter(|_| n >= TURN_AVERAGE_HALVES_MIN) {
            Some(team) => {
                let (s0, s1) = sums.0.split_at_mut(n / 2);
                let (j0, j1) = sums.1.split_at_mut(n / 2);
                let (v0, v1) = sums.2.split_at_mut(n / 2);
                team.join(
                    || accumulate_stress(wm, self.green, 0, s.u, (s0, j0, v0)),
                    || accumulate_stress(wm, self.green, n / 2, s.u, (s1, j1, v1)),
                );
            }
            None => accumulate_stress(wm, self.green, 0, s.u, sums),
        }
        self.count += 1;
        Ok(())
    }
}

/// The elements from which [`TurnAverage`] sums its fields in two halves side by side (a
/// half is then some microseconds of work, more than a hand-off to the second thread).
const TURN_AVERAGE_HALVES_MIN: usize = 512;

/// Adds the `J2` and von Mises stress under `u` of the elements `first..` (as many as
/// `stress` holds) to their sums: of the Green strain (`green`) or the linear one.
fn accumulate_stress(
    wm: &WheelModel,
    green: bool,
    first: usize,
    u: &[f64],
    (stress, j2_sum, von_mises_sum): (&mut [[f64; 3]], &mut [f64], &mut [f64]),
) {
    let r = first..first + stress.len();
    if green {
        tri3::green_stresses_into(&wm.geometry[r.clone()], &wm.triangles[r], &wm.d, u, stress);
    } else {
        tri3::stresses_into(&wm.geometry[r.clone()], &wm.triangles[r], &wm.d, u, stress);
    }
    for ((sg, j2s), vms) in stress.iter().zip(j2_sum).zip(von_mises_sum) {
        let (j2, vm) = wm.spec.plane.stress_invariants(&wm.spec.material, *sg);
        *j2s += j2;
        *vms += vm;
    }
}

/// Displacement and velocity at `count` instants evenly spaced over a window (the last
/// full turn), at the middles of its `count` equal parts (Fig. 17).
#[derive(Debug)]
pub struct VelocitySnapshots {
    timeline: Timeline,
    targets: Vec<f64>,
    taken: usize,
    snaps: Snapshots,
}

/// The snapshots taken.
#[derive(Debug, Clone, Default)]
pub struct Snapshots {
    /// Times, s.
    pub t: Vec<f64>,
    /// Displacements, m.
    pub u: Vec<Vec<f64>>,
    /// Velocities, m/s.
    pub v: Vec<Vec<f64>>,
}

impl VelocitySnapshots {
    /// `count` snapshots of `n_dofs` values over `[window.0, window.0 + turn_time)`.
    pub fn new(timeline: Timeline, window_start: f64, count: usize, n_dofs: usize) -> Self {
        let targets = (0..count)
            .map(|i| window_start + (i as f64 + 0.5) * timeline.turn_time / count as f64)
            .collect();
        Self {
            timeline,
            targets,
            taken: 0,
            snaps: Snapshots {
                t: vec![0.0; count],
                u: vec![vec![0.0; n_dofs]; count],
                v: vec![vec![0.0; n_dofs]; count],
            },
        }
    }

    /// The snapshots reached.
    pub fn finish(mut self) -> Snapshots {
        self.snaps.t.truncate(self.taken);
        self.snaps.u.truncate(self.taken);
        self.snaps.v.truncate(self.taken);
        self.snaps
    }
}

impl Observer for VelocitySnapshots {
    fn observe(&mut self, s: &WheelStep) -> std::io::Result<()> {
        let i = self.taken;
        if i < self.targets.len() && s.t >= self.targets[i] - 0.5 * self.timeline.h {
            self.snaps.t[i] = s.t;
            self.snaps.u[i].copy_from_slice(s.u);
            self.snaps.v[i].copy_from_slice(s.v);
            self.taken += 1;
        }
        Ok(())
    }
}

/// The progress bar (hidden off a terminal).
#[derive(Debug)]
pub struct Progress(indicatif::ProgressBar);

impl Progress {
    /// A bar over `steps` steps labelled `label`, shown when `opts.progress` (and watched
    /// through `opts.progress_watch`).
    pub fn new(steps: usize, label: &str, opts: &RunOptions) -> Self {
        Self(progress_bar(steps as u64, label, opts))
    }

    /// Clears the bar.
    pub fn finish(self) {
        self.0.finish_and_clear();
    }
}

impl Observer for Progress {
    fn observe(&mut self, s: &WheelStep) -> std::io::Result<()> {
        if s.k % 256 == 0 {
            self.0.set_position(s.k as u64);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn step(k: usize, t: f64, f: f64, gap: f64) -> WheelStep<'static> {
        WheelStep {
            k,
            t,
            u: &[1.0, 2.0],
            v: &[3.0, 4.0],
            energy: Some((1.0, 2.0)),
            penalty: 0.0,
            contact_force: f,
            held: 1,
            min_gap: gap,
            pairs: &[],
            slip_power: 0.0,
            friction_dissipated: 0.0,
            frame_angle: 0.0,
            team: None,
        }
    }

    const TL: Timeline = Timeline {
        h: 0.1,
        t_settle: 1.0,
        turn_time: 1.0,
        turns: 2.0,
    };

    #[test]
    fn force_energy_and_snapshots_follow_the_timeline() {
        let mut f = ContactForceStats::new(TL, 30);
        let cap = [f.trace.capacity(), f.window.capacity()];
        let mut e = EnergyWatch::new(TL);
        let mut snaps = VelocitySnapshots::new(TL, TL.last_full_turn().0, 4, 2);
        for k in 0..=30 {
            let t = k as f64 * TL.h;
            let s = step(
                k,
                t,
                if t < 0.95 { 0.0 } else { 10.0 + k as f64 },
                -1e-3 * t,
            );
            f.observe(&s).unwrap();
            e.observe(&s).unwrap();
            snaps.observe(&s).unwrap();
        }
        // No reallocation in the loop.
        assert_eq!(cap, [f.trace.capacity(), f.window.capacity()]);
        let r = f.finish(2.0 * PI, 4);
        assert_eq!(r.plot.0.len(), 31);
        assert_eq!((r.window.0.len(), r.rolling_steps), (21, 21));
        // Rolling phase: k = 10..=30, forces 20..=40.
        assert!((r.mean - 30.0).abs() < 1e-12 && r.min == 20.0 && r.max == 40.0);
        assert!((r.max_penetration - 3e-3).abs() < 1e-15);
        assert_eq!(e.finish(), (3.0, 3.0));
        // Last full turn [2, 3): middles of the quarters at 2.125, 2.375, 2.625, 2.875; the
        // first grid time >= target - h/2 is 2.1, 2.4, 2.6, 2.9.
        let sn = snaps.finish();
        for (t, want) in sn.t.iter().zip([2.1, 2.4, 2.6, 2.9]) {
            assert!((t - want).abs() < 1e-12, "{:?}", sn.t);
        }
        assert_eq!(sn.t.len(), 4);
        assert_eq!(sn.v[3], vec![3.0, 4.0]);
    }
}
