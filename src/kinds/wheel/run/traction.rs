//! Traction of a wheel rolling with friction (`contact.friction`, `rolling.creepage`): the
//! creep force over time, stick and slip in the patch, the frictional dissipation, and the
//! steady traction profile `p(s)`, `q(s)` across the patch, with Carter's 2D solution
//! beside it.
//!
//! **Signs and coordinates.** `s` is the position of a rim node along the base, measured
//! from the foot of the perpendicular from the axle, positive in the direction in which the
//! contact travels round the rim (the base turns at `+omega` in the wheel's frame): material
//! enters the patch at `s = +a` (the leading edge) and leaves at `s = -a`. The pairs'
//! tangential force is reported along the tangent `t` (the direction of the rail's travel,
//! [`crate::contact::RotatingLine`]), which is `-s`; the traction on the wheel `q` and the
//! creep force `Q` are counted along `+s`, the direction of the vehicle's travel: `Q > 0`
//! drives the wheel forward (creepage `xi > 0`), `Q < 0` brakes it.
//!
//! **Nodal forces to tractions.** A rim node's force over its tributary length (half the
//! arcs to its two neighbours, on the undeformed rim) times the thickness: `p = F_n / (b l)`,
//! `q = F_t / (b l)`, Pa.
//!
//! **The steady profile.** In steady rolling every rim node passes through the patch, so
//! the profile is averaged in the patch's frame: over the averaging window (the last half of
//! the rolling phase), each node's `(s, p, q, stick)` is dropped into bins of a quarter rim
//! pitch; the mean per bin is a profile four times finer than the mesh, free of the
//! node-passing jitter of any single instant.
//!
//! **Carter (1926; Johnson, Contact Mechanics, §8.4), 2D.** For a cylinder of radius `R` on
//! a flat, normal load `P` per unit length, the Hertz half-width is `a = sqrt(4 P R / (pi
//! E*))` and the peak pressure `p0 = 2 P / (pi a)`; with `E* = E / (1 - nu^2)` in plane strain
//! and `E` in plane stress for an elastic wheel on a rigid base. With traction `Q < mu P` the
//! stick zone is at the leading edge with half-width `c = a sqrt(1 - Q / (mu P))`, the
//! traction `q(s) = mu p0 sqrt(1 - s^2/a^2) - (c/a) mu p0 sqrt(1 - (s - a + c)^2 / c^2)` in
//! it (`mu p` in the slip zone), and the creepage `xi = (mu a / R) (1 - sqrt(1 - Q/(mu P)))`
//! (full slip from `xi = mu a / R`). Carter's bodies are elastically similar; on a rigid
//! base the normal and tangential problems couple through Dundurs' `beta = (kappa - 1) /
//! (kappa + 1)`: `(1 - nu) / 2 = 0.35` in plane stress, `(1 - 2 nu) / (2 (1 - nu)) = 0.29` in
//! plane strain for `nu = 0.3` (Johnson §5.4, §8.4; Bentall and Johnson 1967). The pressure
//! strains the wheel's surface and not the base's, so the wheel has a free-rolling creepage
//! of its own, tractions of both signs in free rolling and slip at both edges of the patch:
//! with `beta / mu` of order one the coupled problem is not Carter's. [`carter_traction_ratio`]
//! and
//! [`carter_q`] are the uncoupled solution.

use super::observers::{Observer, Timeline, WheelStep};
use crate::analysis::trace::{Envelope, ENVELOPE_CAP};
use crate::bodies::wheel::WheelModel;
use crate::contact::RotatingLine;
use crate::output::files::CsvWriter;
use crate::output::table::{Columns, Rows};
use crate::run::error::RunError;
use serde::Serialize;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

/// Carter's creep curve: the traction ratio `Q / (mu P)` at creepage `xi` for a cylinder of
/// radius `radius` with Hertz half-width `a` and friction `mu` (module docs; odd in `xi`,
/// saturated at `+-1` from `|xi| = mu a / R`).
pub fn carter_traction_ratio(xi: f64, mu: f64, a: f64, radius: f64) -> f64 {
    let x = (xi.abs() * radius / (mu * a)).min(1.0);
    xi.signum() * (1.0 - (1.0 - x) * (1.0 - x))
}

/// A creepage `xi` referred to the rolling radius `rho` (the rail's speed `V = omega rho (1 -
/// xi)`) referred instead to the undeformed radius `r_s`: `(omega r_s - V) / (omega r_s) =
/// 1 - (rho / r_s) (1 - xi)` (module docs of [`crate::contact::RotatingLine`]).
pub fn creepage_undeformed(xi: f64, rho: f64, r_s: f64) -> f64 {
    1.0 - rho / r_s * (1.0 - xi)
}

/// The largest decay from one quarter of the rolling phase to the next that
/// [`steady_ratio`] extrapolates: a slower transient has not declared its limit within the
/// run (roll longer).
pub const MAX_DECAY: f64 = 0.8;

/// The steady value of a start-up transient that decays geometrically, from its means
/// `m = [m2, m3, m4]` over three successive equal windows (the rolling phase's second,
/// third and fourth quarters): with `m_k = m + A r^k`, Aitken's delta-squared gives
/// `m = m4 - d2^2 / (d2 - d1)` (`d1 = m3 - m2`, `d2 = m4 - m3`, `r = d2 / d1`). Returns
/// `(m, r)` when the differences shrink with one sign (`0 < r <= MAX_DECAY`), else `None`
/// (no transient left above the noise, or one too slow for the run).
///
/// The creep force of a wheel started from its settled state approaches steady rolling so
/// (the traction building up as material crosses the patch, the rim winding up against the
/// hub): on `creep-curve-coupled.toml` at free rolling it decays by about 0.47 a
/// millisecond, and the last half's mean after 8 ms of rolling still lay 2e-3 in `Q/(mu P)`
/// short of it: this extrapolation gives -0.0395 after 4 ms and -0.0393 after 8 ms where
/// that mean is -0.0369; at `Q/(mu P)` about -0.5 it gives -0.5038 after 4 ms, and the mean
/// of a 16 ms run is -0.5034 (`tests/creep.rs`).
pub fn steady_ratio(m: [f64; 3]) -> Option<(f64, f64)> {
    let (d1, d2) = (m[1] - m[0], m[2] - m[1]);
    let r = d2 / d1;
    (r.is_finite() && r > 0.0 && r <= MAX_DECAY).then(|| (m[2] - d2 * d2 / (d2 - d1), r))
}

/// Carter's tangential traction at `s` (module docs) for peak pressure `p0`, half-width `a`,
/// stick half-width `c` (`0 <= c <= a`) and friction `mu`, Pa, for a driving traction (the
/// braking one is its negative).
pub fn carter_q(s: f64, mu: f64, p0: f64, a: f64, c: f64) -> f64 {
    if s.abs() >= a {
        return 0.0;
    }
    let full = mu * p0 * (1.0 - s * s / (a * a)).sqrt();
    let d = s - (a - c);
    if c > 0.0 && d.abs() < c {
        full - (c / a) * mu * p0 * (1.0 - d * d / (c * c)).sqrt()
    } else {
        full
    }
}

/// Hertz's 2D half-width and peak pressure for a load `p_per_length` (N/m) on a cylinder
/// of radius `radius` with plane modulus `e_star` (Pa): `(a, p0)`.
pub fn hertz_2d(p_per_length: f64, radius: f64, e_star: f64) -> (f64, f64) {
    let a = (4.0 * p_per_length * radius / (PI * e_star)).sqrt();
    (a, 2.0 * p_per_length / (PI * a))
}

/// Watches the traction of a rolling wheel with friction (module docs).
#[derive(Debug)]
pub struct TractionWatch {
    /// The wheel's `rolling.coupling`, reported with the figures.
    coupling: crate::bodies::wheel::Coupling,
    timeline: Timeline,
    base: RotatingLine,
    /// Reference positions of the rim nodes (flat x, y per rim pair).
    rim_x: Vec<f64>,
    rim_dofs: Vec<usize>,
    /// Tributary length times thickness per rim pair, m^2.
    area: Vec<f64>,
    /// Averaging window start, s.
    window_start: f64,
    bin: f64,
    half_bins: usize,
    // Per-bin sums over the window.
    bin_p: Vec<f64>,
    bin_q: Vec<f64>,
    bin_stick: Vec<f64>,
    bin_n: Vec<f64>,
    // Time series over the rolling phase.
    sum_stick: f64,
    sum_slip: f64,
    samples: f64,
    window_q: f64,
    window_p: f64,
    window_samples: f64,
    /// Sums of `(Q, P)` over the rolling phase's second, third and fourth quarters (the
    /// start-up transient's extrapolation, [`steady_ratio`]).
    quarters: [[f64; 2]; 3],
    friction_energy: f64,
    /// The least `slip_power / |tangential_force|` of any pair at any step, m/s.
    min_slip_speed: f64,
    /// The largest decrease of the friction energy from one step to the next, J.
    max_energy_drop: f64,
    history: Rows,
    stride: usize,
    /// The history rows kept for the figure, as envelopes of bounded size
    /// ([`crate::analysis::trace`]): normal force, traction, friction energy.
    series: [Envelope; 3],
}

/// The traction figures of a run with friction (`summary.json`, `traction`).
#[derive(Debug, Clone, Serialize)]
pub struct TractionSummary {
    /// The normal and tangential problems coupled or not (`rolling.coupling`).
    pub coupling: crate::bodies::wheel::Coupling,
    /// Coulomb coefficient.
    pub friction: f64,
    /// Creepage `xi = (omega rho - V) / (omega rho)` as given (`rolling.creepage`), referred
    /// to the rolling radius `rho = R_s - d` (the distance from the axle to the base).
    pub creepage: f64,
    /// The same creepage referred to the undeformed radius `R_s` (the rim of the wheel
    /// spinning free, before the contact flattens it): `xi_R = (omega R_s - V) / (omega R_s)
    /// = 1 - (rho / R_s) (1 - xi)`. Carter, Kalker and the half-space codes use this one
    /// (their rigid velocity is `omega R`): it is larger than `xi` by `(d / R_s) (1 - xi)`.
    pub creepage_undeformed: f64,
    /// The rolling radius `rho = R_s - d` at the end of the run, m.
    pub rolling_radius: f64,
    /// The undeformed radius `R_s` (the rim of the wheel spinning free), m.
    pub undeformed_radius: f64,
    /// Wheel radius `R`, m.
    pub radius: f64,
    /// Mean creep force `Q` over the averaging window (last half of the rolling phase), N
    /// (positive: driving).
    pub traction: f64,
    /// Mean normal force `P` over the same window, N.
    pub normal: f64,
    /// `Q / (mu P)`.
    pub traction_ratio: f64,
    /// The steady rolling's `Q / (mu P)`: the start-up transient extrapolated out of the
    /// means over the rolling phase's second, third and fourth quarters ([`steady_ratio`]),
    /// or `traction_ratio` where no decaying transient is seen.
    pub traction_ratio_steady: f64,
    /// The transient's decay from one quarter of the rolling phase to the next (the ratio
    /// of the successive differences of the quarters' means), when it decays (0 to
    /// [`MAX_DECAY`]); `null` otherwise.
    pub transient_decay: Option<f64>,
    /// Mean nodes in stick and in slip over the rolling phase.
    pub mean_stick_nodes: f64,
    /// Mean nodes in slip.
    pub mean_slip_nodes: f64,
    /// Energy dissipated by friction over the run, J.
    pub friction_energy: f64,
    /// The least slip speed that a pair's dissipation implies, `slip_power / |F_t|` over
    /// every pair carrying a friction force at every step, m/s: the dissipation is `-F_t
    /// s_1 >= 0` ([`crate::model::PairState::slip_power`]), so this is `>= 0` but for the
    /// round-off residual `s_1` of a sticking pair (of order `1e-16 omega R`).
    pub min_slip_speed: f64,
    /// The largest decrease of the friction energy from one step to the next over the run,
    /// J (0 when it never decreases: the sum of the pairs' round-off residuals at most).
    pub max_friction_energy_drop: f64,
    /// Hertz half-width for the mean normal force, m.
    pub hertz_half_width: f64,
    /// Hertz peak pressure, Pa.
    pub hertz_peak_pressure: f64,
    /// The measured half-width of the steady profile (outermost bins carrying pressure), m.
    pub measured_half_width: f64,
    /// The measured stick zone: half-width `c`, m (bins in stick more than half the time).
    pub measured_stick_half_width: f64,
    /// Carter's `c = a sqrt(1 - |Q|/(mu P))` for the measured `Q`, m.
    pub carter_stick_half_width: f64,
    /// The measured stick zone's centre along the patch (`s`, the leading edge at `+a`), m.
    pub measured_stick_centre: f64,
    /// Carter's stick zone's centre, `a - c` (the stick zone at the leading edge), m.
    pub carter_stick_centre: f64,
    /// The RMS difference of the steady traction profile `q(s)` from Carter's over the
    /// Hertz patch `|s| < a`, over `mu p0` (0: Carter's profile; 1: off by the full-slip
    /// peak).
    pub carter_traction_rms: f64,
    /// Carter's `Q / (mu P)` at this creepage (uncoupled, with the Hertz `a`).
    pub carter_traction_ratio: f64,
    /// Carter's saturation creepage `mu a / R`.
    pub carter_saturation_creepage: f64,
    /// Rim pitch over the Hertz half-width: the patch's resolution.
    pub pitch_over_half_width: f64,
}

/// The steady traction profile (module docs).
#[derive(Debug, Clone)]
pub struct TractionProfile {
    /// Bin centres, m.
    pub s: Vec<f64>,
    /// Mean pressure, Pa.
    pub p: Vec<f64>,
    /// Mean tangential traction on the wheel along `+s`, Pa.
    pub q: Vec<f64>,
    /// Fraction of the samples in stick (held and not sliding).
    pub stick: Vec<f64>,
    /// The history kept for the figure, `(t s, value)` points of the normal force, the creep
    /// force (N) and the friction energy (J) ([`Envelope::points`]).
    pub history: [(Vec<f64>, Vec<f64>); 3],
}

impl TractionWatch {
    /// The history columns and their units.
    pub const COLUMNS: [(&'static str, &'static str); 7] = [
        ("t_s", "s"),
        ("normal_N", "N"),
        ("traction_N", "N"),
        ("stick_nodes", "1"),
        ("slip_nodes", "1"),
        ("slip_power_W", "W"),
        ("friction_energy_J", "J"),
    ];

    /// A watch over the rim of `wm`, keeping `traction_history.csv`'s rows every `stride`
    /// steps: streamed to `path` when given, else held.
    ///
    /// # Errors
    /// [`RunError::Output`].
    pub fn create(
        wm: &WheelModel,
        timeline: Timeline,
        path: Option<&Path>,
        stride: usize,
    ) -> Result<Self, RunError> {
        let rim_x: Vec<f64> = wm
            .rim
            .iter()
            .flat_map(|&i| &wm.mesh.point(i)[..2])
            .copied()
            .collect();
        let n = wm.rim.len();
        let angle = |k: usize| rim_x[2 * k + 1].atan2(rim_x[2 * k]);
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by(|&a, &b| angle(a).total_cmp(&angle(b)));
        let radius = wm.spec.radius;
        let mut area = vec![0.0; n];
        for (k, &i) in order.iter().enumerate() {
            let prev = order[(k + n - 1) % n];
            let next = order[(k + 1) % n];
            let arc = |a: usize, b: usize| {
                let d = (angle(b) - angle(a)).rem_euclid(2.0 * PI);
                radius * d
            };
            area[i] = 0.5 * (arc(prev, i) + arc(i, next)) * wm.spec.thickness;
        }
        let pitch = 2.0 * PI * radius / n.max(1) as f64;
        // Bins of a quarter pitch over +-radius/4 (the patch is a few per cent of R).
        let bin = pitch / 4.0;
        let half_bins = ((0.25 * radius / bin).ceil() as usize).max(1);
        let (t_end, t_settle) = (
            timeline.t_settle + timeline.turns * timeline.turn_time,
            timeline.t_settle,
        );
        let rows = (timeline.t_settle + timeline.turns * timeline.turn_time)
            / timeline.h
            / stride.max(1) as f64;
        let rows = rows.ceil() as usize + 2;
        let history = Rows::open(Columns::new(&Self::COLUMNS), path, rows)
            .map_err(|e| RunError::output(path.unwrap_or(Path::new("traction_history.csv")), e))?;
        Ok(Self {
            coupling: wm.spec.coupling,
            timeline,
            base: wm.base(),
            rim_dofs: wm.rim.iter().map(|&i| 2 * i).collect(),
            rim_x,
            area,
            window_start: 0.5 * (t_settle + t_end),
            bin,
            half_bins,
            bin_p: vec![0.0; 2 * half_bins + 1],
            bin_q: vec![0.0; 2 * half_bins + 1],
            bin_stick: vec![0.0; 2 * half_bins + 1],
            bin_n: vec![0.0; 2 * half_bins + 1],
            sum_stick: 0.0,
            sum_slip: 0.0,
            samples: 0.0,
            window_q: 0.0,
            window_p: 0.0,
            window_samples: 0.0,
            quarters: [[0.0; 2]; 3],
            friction_energy: 0.0,
            min_slip_speed: f64::INFINITY,
            max_energy_drop: 0.0,
            history,
            stride: stride.max(1),
            series: std::array::from_fn(|_| Envelope::new(ENVELOPE_CAP, rows)),
        })
    }

    /// Closes the history and gives the figures, the profile and the history's table, for
    /// the friction `mu`, the
    /// creepage `xi`, the wheel's `radius`, `thickness` and plane modulus `e_star`.
    ///
    /// # Errors
    /// [`RunError::Output`].
    pub fn finish(
        self,
        mu: f64,
        xi: f64,
        (radius, thickness, e_star): (f64, f64, f64),
    ) -> Result<(TractionSummary, TractionProfile, Columns), RunError> {
        let path = match &self.history {
            Rows::File { path, .. } => path.clone(),
            Rows::Memory(_) => "traction_history.csv".into(),
        };
        let history = self
            .history
            .finish()
            .map_err(|e| RunError::output(&path, e))?;
        let nb = 2 * self.half_bins + 1;
        let mut prof = TractionProfile {
            s: Vec::with_capacity(nb),
            p: Vec::with_capacity(nb),
            q: Vec::with_capacity(nb),
            stick: Vec::with_capacity(nb),
            history: self.series.map(|e| e.points()),
        };
        for b in 0..nb {
            let n = self.bin_n[b];
            if n > 0.0 {
                prof.s.push((b as f64 - self.half_bins as f64) * self.bin);
                prof.p.push(self.bin_p[b] / n);
                prof.q.push(self.bin_q[b] / n);
                prof.stick.push(self.bin_stick[b] / n);
            }
        }
        let ws = self.window_samples.max(1.0);
        let (q, p) = (self.window_q / ws, self.window_p / ws);
        let (a, p0) = hertz_2d(p / thickness, radius, e_star);
        // The loaded extent: bins whose mean pressure exceeds 1% of the peak.
        let pmax = prof.p.iter().cloned().fold(0.0, f64::max);
        let loaded: Vec<f64> = prof
            .s
            .iter()
            .zip(&prof.p)
            .filter(|(_, &pp)| pp > 0.01 * pmax)
            .map(|(&s, _)| s)
            .collect();
        // The extent `(lo, hi)` of a set of bin centres (none: `(0, -bin)`, half-width 0).
        let extent = |v: &[f64]| -> (f64, f64) {
            if v.is_empty() {
                (0.0, -self.bin)
            } else {
                (
                    v.iter().cloned().fold(f64::INFINITY, f64::min),
                    v.iter().cloned().fold(f64::NEG_INFINITY, f64::max),
                )
            }
        };
        let half = |v: &[f64]| {
            let (lo, hi) = extent(v);
            0.5 * (hi - lo + self.bin)
        };
        let stuck: Vec<f64> = prof
            .s
            .iter()
            .zip(&prof.p)
            .zip(&prof.stick)
            .filter(|((_, &pp), &st)| pp > 0.01 * pmax && st > 0.5)
            .map(|((&s, _), _)| s)
            .collect();
        let t_end = self.timeline.t_settle + self.timeline.turns * self.timeline.turn_time;
        let r_s = self.base.radius;
        let rho = r_s - self.base.flattening.at(t_end);
        let ratio = if mu > 0.0 && p > 0.0 {
            q / (mu * p)
        } else {
            0.0
        };
        let c = a * (1.0 - ratio.abs().min(1.0)).sqrt();
        let centre = |v: &[f64]| {
            let (lo, hi) = extent(v);
            if v.is_empty() {
                0.0
            } else {
                0.5 * (lo + hi)
            }
        };
        let (mut sq, mut count) = (0.0, 0usize);
        for (&si, &qi) in prof.s.iter().zip(&prof.q) {
            if si.abs() < a {
                let d = qi - q.signum() * carter_q(si, mu, p0, a, c);
                sq += d * d;
                count += 1;
            }
        }
        let rms = if count > 0 && mu * p0 > 0.0 {
            (sq / count as f64).sqrt() / (mu * p0)
        } else {
            0.0
        };
        let quarter = |k: usize| {
            let [q, p] = self.quarters[k];
            if mu > 0.0 && p > 0.0 {
                q / (mu * p)
            } else {
                0.0
            }
        };
        let transient = steady_ratio([quarter(0), quarter(1), quarter(2)]);
        let summary = TractionSummary {
            coupling: self.coupling,
            friction: mu,
            creepage: xi,
            creepage_undeformed: creepage_undeformed(xi, rho, r_s),
            rolling_radius: rho,
            undeformed_radius: r_s,
            radius,
            traction: q,
            normal: p,
            traction_ratio: ratio,
            traction_ratio_steady: transient.map_or(ratio, |t| t.0),
            transient_decay: transient.map(|t| t.1),
            mean_stick_nodes: self.sum_stick / self.samples.max(1.0),
            mean_slip_nodes: self.sum_slip / self.samples.max(1.0),
            friction_energy: self.friction_energy,
            min_slip_speed: if self.min_slip_speed.is_finite() {
                self.min_slip_speed
            } else {
                0.0
            },
            max_friction_energy_drop: self.max_energy_drop,
            hertz_half_width: a,
            hertz_peak_pressure: p0,
            measured_half_width: half(&loaded),
            measured_stick_half_width: half(&stuck),
            carter_stick_half_width: c,
            measured_stick_centre: centre(&stuck),
            carter_stick_centre: a - c,
            carter_traction_rms: rms,
            carter_traction_ratio: carter_traction_ratio(xi, mu, a, radius),
            carter_saturation_creepage: mu * a / radius,
            pitch_over_half_width: 4.0 * self.bin / a,
        };
        Ok((summary, prof, history))
    }
}

impl Observer for TractionWatch {
    fn observe(&mut self, s: &WheelStep) -> std::io::Result<()> {
        let (mut normal, mut traction, mut stick, mut slip) = (0.0, 0.0, 0usize, 0usize);
        for ps in s.pairs {
            normal += ps.force;
            traction -= ps.tangential_force;
            if ps.tangential_force != 0.0 {
                let speed = ps.slip_power / ps.tangential_force.abs();
                self.min_slip_speed = self.min_slip_speed.min(speed);
            }
            if ps.held {
                if ps.sliding {
                    slip += 1;
                } else {
                    stick += 1;
                }
            }
        }
        let drop = self.friction_energy - s.friction_dissipated;
        self.max_energy_drop = self.max_energy_drop.max(drop);
        self.friction_energy = s.friction_dissipated;
        if s.k % self.stride == 0 {
            self.history.push(
                0,
                &[
                    s.t,
                    normal,
                    traction,
                    stick as f64,
                    slip as f64,
                    s.slip_power,
                    s.friction_dissipated,
                ],
            )?;
            for (e, x) in self
                .series
                .iter_mut()
                .zip([normal, traction, s.friction_dissipated])
            {
                e.push(s.t, x);
            }
        }
        if !self.timeline.rolling(s.t) {
            return Ok(());
        }
        self.samples += 1.0;
        self.sum_stick += stick as f64;
        self.sum_slip += slip as f64;
        let rolled = (s.t - self.timeline.t_settle + 0.5 * self.timeline.h)
            / (self.timeline.turns * self.timeline.turn_time);
        let quarter = (4.0 * rolled).floor();
        if (1.0..4.0).contains(&quarter) {
            let q = &mut self.quarters[quarter as usize - 1];
            q[0] += traction;
            q[1] += normal;
        }
        if s.t < self.window_start {
            return Ok(());
        }
        self.window_samples += 1.0;
        self.window_q += traction;
        self.window_p += normal;
        // The profile in the patch's frame: s = -t . (x - centre), t the base's tangent;
        // with a moving zone the base's direction in the mesh's frame, turned back by the
        // frame's angle.
        let e = self.base.direction(s.t);
        let (c, sn) = (s.frame_angle.cos(), s.frame_angle.sin());
        let e = [c * e[0] + sn * e[1], -sn * e[0] + c * e[1]];
        // t = (-n_y, n_x) with n = -e: t = (e_y, -e_x); the contact travels along -t.
        let along = [-e[1], e[0]];
        for (k, ps) in s.pairs.iter().enumerate() {
            if !(ps.held || ps.force != 0.0) {
                continue;
            }
            let d = self.rim_dofs[k];
            let x = [
                self.rim_x[2 * k] + s.u[d] - self.base.centre[0],
                self.rim_x[2 * k + 1] + s.u[d + 1] - self.base.centre[1],
            ];
            let pos = along[0] * x[0] + along[1] * x[1];
            let b = (pos / self.bin).round() + self.half_bins as f64;
            if b < 0.0 || b >= self.bin_n.len() as f64 {
                continue;
            }
            let b = b as usize;
            let area = self.area[k];
            self.bin_p[b] += ps.force / area;
            self.bin_q[b] -= ps.tangential_force / area;
            self.bin_stick[b] += if ps.held && !ps.sliding { 1.0 } else { 0.0 };
            self.bin_n[b] += 1.0;
        }
        Ok(())
    }
}

/// Writes `traction_profile.csv`: the steady profile with Hertz's pressure and Carter's
/// traction (for the measured creep force) beside it.
///
/// # Errors
/// [`RunError::Output`].
pub fn write_profile(
    out: &Path,
    ts: &TractionSummary,
    prof: &TractionProfile,
) -> Result<PathBuf, RunError> {
    let path = out.join("traction_profile.csv");
    let mut csv = CsvWriter::create(
        &path,
        &[
            "s_m",
            "p_Pa",
            "q_Pa",
            "stick_fraction",
            "hertz_p_Pa",
            "carter_q_Pa",
        ],
    )
    .map_err(|e| RunError::output(&path, e))?;
    let (a, p0, mu) = (ts.hertz_half_width, ts.hertz_peak_pressure, ts.friction);
    let sign = ts.traction.signum();
    for i in 0..prof.s.len() {
        let s = prof.s[i];
        let hertz = if s.abs() < a {
            p0 * (1.0 - s * s / (a * a)).sqrt()
        } else {
            0.0
        };
        csv.row(
            None,
            &[
                s,
                prof.p[i],
                prof.q[i],
                prof.stick[i],
                hertz,
                sign * carter_q(s, mu, p0, a, ts.carter_stick_half_width),
            ],
        )
        .map_err(|e| RunError::output(&path, e))?;
    }
    csv.finish().map_err(|e| RunError::output(&path, e))?;
    Ok(path)
}

/// The figures: `traction.png` (the steady profile against Hertz and Carter, the stick and
/// slip zones shaded) and `traction_history.png` (normal and creep force, friction energy).
///
/// # Errors
/// [`RunError::Output`].
pub fn figures(
    out: &Path,
    ts: &TractionSummary,
    prof: &TractionProfile,
) -> Result<Vec<PathBuf>, RunError> {
    use crate::output::plot::{panels, Panel, Series, SeriesStyle};
    let (a, p0, mu) = (ts.hertz_half_width, ts.hertz_peak_pressure, ts.friction);
    let sign = if ts.traction < 0.0 { -1.0 } else { 1.0 };
    let x: Vec<f64> = prof.s.iter().map(|s| s / a).collect();
    let fine: Vec<f64> = (0..=400).map(|i| -1.5 + 3.0 * i as f64 / 400.0).collect();
    let mut p = Panel::new(
        format!(
            "Steady traction across the patch: mu = {}, creepage {}, Q/(mu P) = {}",
            crate::output::plot::sig(mu, 3),
            crate::output::plot::sig(ts.creepage, 3),
            crate::output::plot::sig(ts.traction_ratio, 3)
        ),
        "s / a  (s along the rolling direction; material enters at +1)",
        "p / p0,  q / (mu p0)",
    );
    p.series.push(Series::new(
        "p / p0, softway",
        x.clone(),
        prof.p.iter().map(|v| v / p0).collect(),
        SeriesStyle::LineMarkers,
    ));
    p.series.push(Series::new(
        "q / (mu p0), softway",
        x.clone(),
        prof.q.iter().map(|v| sign * v / (mu * p0)).collect(),
        SeriesStyle::LineMarkers,
    ));
    p.series.push(Series::new(
        "Hertz p / p0",
        fine.clone(),
        fine.iter()
            .map(|&r| {
                if r.abs() < 1.0 {
                    (1.0 - r * r).sqrt()
                } else {
                    0.0
                }
            })
            .collect(),
        SeriesStyle::Dashed,
    ));
    p.series.push(Series::new(
        format!(
            "Carter q / (mu p0), c/a = {:.2}",
            ts.carter_stick_half_width / a
        ),
        fine.clone(),
        fine.iter()
            .map(|&r| carter_q(r * a, mu, p0, a, ts.carter_stick_half_width) / (mu * p0))
            .collect(),
        SeriesStyle::Dashed,
    ));
    // The zones, shaded: runs of loaded bins in stick (more than half of the samples) or in
    // slip, each bin a quarter pitch wide.
    let pmax = prof.p.iter().cloned().fold(0.0, f64::max);
    // (An empty profile, a patch that no bin saw, shades nothing.)
    let half_bin = match (prof.s.first(), prof.s.get(1)) {
        (Some(s0), Some(s1)) => 0.5 * (s1 - s0).abs() / a,
        _ => 0.0,
    };
    for ((&s, &pp), &st) in x.iter().zip(&prof.p).zip(&prof.stick) {
        if pp > 0.01 * pmax {
            let label = if st > 0.5 { "stick zone" } else { "slip zone" };
            p.vspans
                .push((s - half_bin, s + half_bin, label.to_string()));
        }
    }
    p.x_range = Some((-1.5, 1.5));
    // The range holds every computed value (the traction of a coarse patch can overshoot
    // well below -0.25), with the Hertz and Carter curves' -0.25..1.25 at least.
    let (lo, hi) = p.series[..2]
        .iter()
        .flat_map(|s| s.y.iter().copied())
        .filter(|v| v.is_finite())
        .fold((-0.2f64, 1.2f64), |(a, b), v| (a.min(v), b.max(v)));
    p.y_range = Some((lo - 0.05, hi + 0.05));
    let png = out.join("traction.png");
    panels(&png, &[p], 1, 1, (1100, 650)).map_err(|e| RunError::output(&png, e))?;
    let [normal, traction, energy] = &prof.history;
    let ms = |t: &[f64]| -> Vec<f64> { t.iter().map(|t| t * 1e3).collect() };
    let mut f = Panel::new("Normal and creep force", "t [ms]", "force [N]");
    f.series.push(Series::new(
        "mu P (normal force times mu)",
        ms(&normal.0),
        normal.1.iter().map(|v| mu * v).collect(),
        SeriesStyle::Line,
    ));
    f.series.push(Series::new(
        "Q (creep force on the wheel, + driving)",
        ms(&traction.0),
        traction.1.clone(),
        SeriesStyle::Line,
    ));
    let mut e = Panel::new("Energy dissipated by friction", "t [ms]", "energy [J]");
    e.series.push(Series::new(
        "friction energy",
        ms(&energy.0),
        energy.1.clone(),
        SeriesStyle::Line,
    ));
    let png2 = out.join("traction_history.png");
    panels(&png2, &[f, e], 2, 1, (1100, 900)).map_err(|e| RunError::output(&png2, e))?;
    Ok(vec![png, png2])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The means over three equal windows of `m + A exp(-t / tau)` (any `t0`, window `w`)
    /// give back `m` and the decay `exp(-w / tau)` to round-off; a transient that grows,
    /// changes sign or decays slower than [`MAX_DECAY`] a window is not extrapolated.
    #[test]
    fn steady_ratio_recovers_the_limit_of_a_decaying_transient() {
        let (m, amp, tau, w, t0) = (-0.0392, 0.38, 1.4e-3, 1e-3, 1e-3);
        let mean = |k: f64| {
            let (a, b) = (t0 + k * w, t0 + (k + 1.0) * w);
            m + amp * tau * ((-a / tau).exp() - (-b / tau).exp()) / w
        };
        let (limit, r) = steady_ratio([mean(1.0), mean(2.0), mean(3.0)]).unwrap();
        assert!((limit - m).abs() < 1e-13, "{limit}");
        assert!((r - (-w / tau).exp()).abs() < 1e-12, "{r}");
        // Growing, oscillating, too slow, or no transient at all: no extrapolation.
        assert!(steady_ratio([0.1, 0.2, 0.4]).is_none());
        assert!(steady_ratio([0.1, 0.2, 0.15]).is_none());
        assert!(steady_ratio([0.1, 0.2, 0.29]).is_none());
        assert!(steady_ratio([0.3, 0.3, 0.3]).is_none());
    }

    /// Carter's traction integrates to `Q`: `int q ds = mu P (1 - c^2/a^2)` with `P = pi a
    /// p0 / 2` (per unit length), so `Q/(mu P) = 1 - c^2/a^2`; and its creep curve has the
    /// initial slope `2 R / (mu a)` and saturates at `mu a / R`.
    #[test]
    fn carter_traction_integrates_to_the_creep_force() {
        let (mu, p0, a) = (0.3, 1.0e9, 6e-3);
        for c_over_a in [0.0, 0.3, 0.7, 1.0] {
            let c = c_over_a * a;
            let n = 200_000;
            let ds = 2.0 * a / n as f64;
            let q: f64 = (0..n)
                .map(|i| carter_q(-a + (i as f64 + 0.5) * ds, mu, p0, a, c) * ds)
                .sum();
            let p = PI * a * p0 / 2.0;
            let expect = mu * p * (1.0 - c_over_a * c_over_a);
            assert!(
                (q - expect).abs() < 1e-4 * mu * p,
                "c/a {c_over_a}: {q} vs {expect}"
            );
        }
        let r = 0.1;
        let xi_sat = mu * a / r;
        assert_eq!(carter_traction_ratio(xi_sat, mu, a, r), 1.0);
        assert_eq!(carter_traction_ratio(-2.0 * xi_sat, mu, a, r), -1.0);
        let d = 1e-9;
        let slope = carter_traction_ratio(d, mu, a, r) / d;
        assert!((slope - 2.0 * r / (mu * a)).abs() < 1e-6 * slope);
        // c/a = sqrt(1 - Q/(mu P)) at the creepage that gives Q.
        let xi = 0.4 * xi_sat;
        let ratio = carter_traction_ratio(xi, mu, a, r);
        let c_over_a = (1.0 - ratio).sqrt();
        assert!((xi - mu * a / r * (1.0 - c_over_a)).abs() < 1e-15);
    }

    /// The two references give the same rail speed: `omega rho (1 - xi) = omega R_s (1 -
    /// xi_R)`; free rolling on `rho` is a creepage `d / R_s` on `R_s`.
    #[test]
    fn creepage_on_the_undeformed_radius_gives_the_same_rail_speed() {
        let (r_s, d, omega) = (0.1, 2e-5, 50.0);
        let rho = r_s - d;
        for xi in [-0.01, 0.0, 1e-3, 0.02] {
            let xr = creepage_undeformed(xi, rho, r_s);
            let v_rho = omega * rho * (1.0 - xi);
            let v_r = omega * r_s * (1.0 - xr);
            assert!(
                (v_rho - v_r).abs() < 1e-14 * v_rho,
                "{xi}: {v_rho} vs {v_r}"
            );
        }
        assert!((creepage_undeformed(0.0, rho, r_s) - d / r_s).abs() < 1e-15);
    }

    #[test]
    fn hertz_2d_half_width_carries_the_load() {
        let (a, p0) = hertz_2d(7e7, 0.1, 2.05e11);
        // int p = pi a p0 / 2 = P.
        assert!((PI * a * p0 / 2.0 - 7e7).abs() < 1e-6 * 7e7);
        // p0 = a E* / (2 R).
        assert!((p0 - a * 2.05e11 / 0.2).abs() < 1e-9 * p0);
    }
}
