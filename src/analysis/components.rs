//! The spectral components of a signal recorded on a rotating body (the wheel's contact
//! force), each with its frequency, amplitude and kind.
//!
//! The contact force of a wheel rolling at spin $\omega$ holds components of three kinds:
//!
//! 1. **locked to the rotation**: a whole number $m$ of cycles per turn, at
//!    $f = m\,f_r$ with $f_r = |\omega| / 2\pi$ (mesh symmetry, out-of-round);
//! 2. **node passing**: the base passing from one rim node to the next, at
//!    $f = h\,N_\text{rim}\,f_r$, $h = 1, 2, \dots$ (a ripple of the mesh);
//! 3. **fixed frequency**: a mode of the wheel on its support and contact, whose frequency
//!    does not change with $\omega$, so that counted per turn it falls as $1/\omega$.
//!
//! [`spectral_components`] lists the peaks of the spectrum and classifies each one;
//! [`fixed_frequency_per_turn`] reduces them to one per-turn count that does not depend on
//! which component happens to dominate.
//!
//! # Algorithm
//!
//! 1. Samples where `t` or `y` is not finite (NaN, infinite) are **skipped** (the gap is then
//!    bridged by the linear interpolation of step 2). No error is raised: a signal with no
//!    finite sample gives no component.
//! 2. If [`ComponentOptions::dt`] is given, or the time steps are not uniform (relative
//!    spread above $10^{-6}$), the signal is interpolated linearly with [`resample_uniform`]
//!    onto a uniform grid of step `dt` (default: the median step). $N$ samples, step
//!    $\Delta t$; the record length is $T = N\Delta t$ and the frequency resolution (one
//!    *bin*) is $\Delta f = 1/T$.
//! 3. The mean is removed, and with [`ComponentOptions::detrend`] (default) the
//!    least-squares straight line.
//! 4. A periodic Hann window $w_n = \frac12(1 - \cos 2\pi n/N)$ is applied and the record
//!    zero-padded to $M \ge P N$ samples ($P$ = [`ComponentOptions::zero_pad`], $M$ a power of
//!    two), then Fourier-transformed: the padded spectrum samples the window's response every
//!    $N/M \le 1/P$ bin.
//! 5. **Peaks**: the local maxima of the padded amplitude spectrum below Nyquist. Only those
//!    at $f \ge \max(c f_r, 2\Delta f)$ (the low cut; $c$ =
//!    [`ComponentOptions::min_cycles_per_turn`]) are reported; those below serve only to
//!    recognise leakage (step 8). Below 2 bins (fewer than two cycles in the record) a
//!    component cannot be told from the mean and trend: a removed trend, real or fitted to
//!    a few cycles of a sine, leaves a bump at about one bin.
//! 6. **Frequency**: a parabola through the log-amplitudes of the peak and its two padded
//!    neighbours (Gaussian interpolation) places the peak at
//!    $\delta = \frac12(\alpha-\gamma)/(\alpha - 2\beta + \gamma)$ padded bins from the peak
//!    bin ($\alpha,\beta,\gamma$ the log-amplitudes).
//! 7. **Amplitude**: the windowed discrete-time Fourier transform evaluated directly at that
//!    frequency, corrected for the window's coherent gain,
//!    $A = 2\,\big|\sum_n w_n x_n e^{-2\pi i f n \Delta t}\big| / \sum_n w_n$, so that a sine
//!    $A\sin(2\pi f t + \varphi)$ gives $A$ (its half peak-to-peak). A frequency error of
//!    $\varepsilon$ bins lowers it by about $0.65\,\varepsilon^2$ (0.16 % at 0.05 bin).
//!    It is evaluated for the peaks kept only: the selection (step 8) uses the cheaper
//!    estimate $A_k / W(\delta N/M)$ from the padded bin's amplitude $A_k$, with
//!    $W(d) = \operatorname{sinc} d / (1 - d^2)$ the Hann response $d$ bins off centre.
//! 8. **Selection**: peaks below [`ComponentOptions::rel_threshold`] times the largest peak
//!    above the low cut, or below $10^{-10}\max|y|$ (rounding noise, e.g. of a constant
//!    signal), are dropped. The rest are taken strongest first; a peak closer than 2 bins
//!    to a stronger accepted one (inside its main lobe), or at $d$ bins from it and weaker
//!    than twice the Hann side-lobe envelope $A_\text{strong} / (\pi d (d^2 - 1))$, is
//!    dropped as leakage of that one. At most [`ComponentOptions::max_components`] are
//!    kept. Two sines closer than 2 bins are thus not resolved (record more turns).
//!
//! The result is sorted by decreasing amplitude.
//!
//! # Classification, tolerances and precedence
//!
//! With $\Delta f = 1/T$ the resolution and $\tau$ =
//! [`ComponentOptions::rotation_tolerance_bins`] (default 0.5, in bins), a component at $f$
//! (Hz) is:
//!
//! - [`ComponentKind::NodePassing`]`{ harmonic: h }` if `rim_nodes > 0`, $h \ge 1$ and
//!   $|f - h N_\text{rim} f_r| \le \tau\,\Delta f$ (Hz);
//! - [`ComponentKind::Mode`]`{ index, hz }` if $|f - f_i| \le \rho f_i$ for a given mode
//!   $f_i$ = `modes_hz[index]`, $\rho$ = [`ComponentOptions::mode_tolerance_rel`] (default
//!   0.03, relative); the nearest such mode (relative distance) when several are;
//! - [`ComponentKind::Locked`]`{ cycles_per_turn: m }` if $m \ge 1$ and
//!   $|f - m f_r| \le \tau\,\Delta f$ (Hz), i.e. within $\tau / (\text{turns})$ cycles per
//!   turn of a whole number;
//! - [`ComponentKind::Unclassified`] otherwise.
//!
//! When several apply, `kind` is the first in the order **node passing, mode, locked**, and
//! the others are listed in [`Component::also`] (an ambiguity to look at, e.g. a mode near
//! the node-passing frequency: a resonance that one run cannot tell apart). Node passing
//! comes first because its frequency is known exactly from the kinematics; a mode comes
//! before locked because it is an explicit, specific prediction, whereas a tolerance of
//! $\tau$ bins is $\tau/\text{turns}$ cycles per turn, so that any frequency falls near a
//! whole number of cycles per turn by chance with probability $2\tau/\text{turns}$ (20 %
//! over five turns with the default, certainly over one). Node passing at harmonic
//! $h$ is also locked at $h N_\text{rim}$ cycles per turn by definition: that is not listed
//! in `also`.

use super::signal::resample_uniform;
use rustfft::{num_complex::Complex, FftPlanner};
use serde::Serialize;
use std::f64::consts::PI;

/// Options of [`spectral_components`]; see the module docs for how each is used.
#[derive(Debug, Clone, PartialEq)]
pub struct ComponentOptions {
    /// Low cut, cycles per turn: peaks below `min_cycles_per_turn * omega / (2 pi)` Hz, or
    /// below 2 bins (`2 / T`, Hz), are ignored. Default 0.5.
    pub min_cycles_per_turn: f64,
    /// Peaks below this fraction of the largest peak (above the low cut) are ignored.
    /// Default 0.05.
    pub rel_threshold: f64,
    /// At most this many components, the strongest. Default 8.
    pub max_components: usize,
    /// Zero-padding factor: the windowed record is padded to the next power of two at least
    /// `zero_pad` times its length (at least 1). Default 4.
    pub zero_pad: usize,
    /// Remove the least-squares straight line (in addition to the mean). Default `true`.
    pub detrend: bool,
    /// Tolerance of the rotation-locked kinds (node passing, locked), in bins of the
    /// frequency resolution `1 / T` (`T` the record length, s). Default 0.5.
    pub rotation_tolerance_bins: f64,
    /// Tolerance of a mode, relative to the mode's frequency. Default 0.03.
    pub mode_tolerance_rel: f64,
    /// Step of the uniform grid the samples are interpolated onto, s. `None`: the samples
    /// as they are if uniform, else the median time step. Default `None`.
    pub dt: Option<f64>,
}

impl Default for ComponentOptions {
    fn default() -> Self {
        Self {
            min_cycles_per_turn: 0.5,
            rel_threshold: 0.05,
            max_components: 8,
            zero_pad: 4,
            detrend: true,
            rotation_tolerance_bins: 0.5,
            mode_tolerance_rel: 0.03,
            dt: None,
        }
    }
}

/// What a spectral component is (module docs: tolerances and precedence).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum ComponentKind {
    /// The base passing rim nodes: `harmonic * rim_nodes` cycles per turn.
    NodePassing {
        /// 1 for the node-passing frequency itself, 2 for twice it, ...
        harmonic: usize,
    },
    /// A given fixed-frequency mode.
    Mode {
        /// Index in `modes_hz`.
        index: usize,
        /// The given frequency `modes_hz[index]`, Hz (the measured one is [`Component::hz`]).
        hz: f64,
    },
    /// Locked to the rotation: a whole number of cycles per turn.
    Locked {
        /// Cycles per turn.
        cycles_per_turn: usize,
    },
    /// None of the above.
    Unclassified,
}

/// One spectral component.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Component {
    /// Frequency, Hz (interpolated between bins).
    pub hz: f64,
    /// `hz` divided by the rotation frequency `|omega| / (2 pi)`.
    pub cycles_per_turn: f64,
    /// Amplitude (half peak-to-peak of the sinusoid), in the units of the signal.
    pub amplitude: f64,
    /// The kind, by the precedence node passing, mode, locked.
    pub kind: ComponentKind,
    /// The other kinds that also apply (an ambiguity), in the same order; empty if none.
    pub also: Vec<ComponentKind>,
}

impl Component {
    /// Whether the component is of fixed frequency: a mode or unclassified (neither locked
    /// nor node passing).
    pub fn is_fixed_frequency(&self) -> bool {
        matches!(
            self.kind,
            ComponentKind::Mode { .. } | ComponentKind::Unclassified
        )
    }
}

/// The spectral components of the signal `(t, y)` of a body spinning at `omega_rad_s`
/// (rad/s; its sign is ignored) with `rim_nodes` nodes on the rim, classified against the
/// fixed-frequency modes `modes_hz` (Hz). See the module docs for the algorithm, the
/// tolerances and the precedence of the kinds.
///
/// `t` (s) must be non-decreasing; only the first `min(t.len(), y.len())` samples are used.
/// Samples where `t` or `y` is not finite are skipped. `rim_nodes = 0` disables node
/// passing. Sorted by decreasing amplitude.
///
/// Returns no component (never panics) for fewer than 4 finite samples, a zero time span, an
/// `omega_rad_s` that is zero or not finite, or a signal with no peak above rounding noise
/// (e.g. constant).
pub fn spectral_components(
    t: &[f64],
    y: &[f64],
    omega_rad_s: f64,
    rim_nodes: usize,
    modes_hz: &[f64],
    opts: &ComponentOptions,
) -> Vec<Component> {
    let rot_hz = omega_rad_s.abs() / (2.0 * PI);
    if !(rot_hz > 0.0 && rot_hz.is_finite()) {
        return Vec::new();
    }
    let Some((dt, mut x)) = uniform_samples(t, y, opts.dt) else {
        return Vec::new();
    };
    let scale = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    remove_trend(&mut x, opts.detrend);

    let n = x.len();
    let nf = n as f64;
    let window: Vec<f64> = (0..n)
        .map(|i| 0.5 * (1.0 - (2.0 * PI * i as f64 / nf).cos()))
        .collect();
    let window_sum: f64 = window.iter().sum();
    let m = (n.saturating_mul(opts.zero_pad.max(1))).next_power_of_two();
    let mut buf = vec![Complex::new(0.0, 0.0); m];
    for ((b, &w), &v) in buf.iter_mut().zip(&window).zip(&x) {
        *b = Complex::new(w * v, 0.0);
    }
    FftPlanner::new().plan_fft_forward(m).process(&mut buf);
    let amp: Vec<f64> = buf[..=m / 2]
        .iter()
        .map(|c| 2.0 * c.norm() / window_sum)
        .collect();

    let df = 1.0 / (nf * dt); // one bin of the unpadded record, Hz
    let dfp = 1.0 / (m as f64 * dt); // one padded bin, Hz
    let nyquist = 0.5 / dt;
    // Below 2 bins, a component is not told apart from the mean and trend.
    let low = (opts.min_cycles_per_turn * rot_hz).max(2.0 * df);

    // Peaks: local maxima of the padded spectrum below Nyquist. Those below the low cut are
    // not reported but may explain (by leakage) peaks above it.
    let mut peaks: Vec<(f64, f64)> = Vec::new(); // (hz, amplitude)
    for k in 1..amp.len() - 1 {
        let (a0, a1, a2) = (amp[k - 1], amp[k], amp[k + 1]);
        if !(a1 > a0 && a1 >= a2 && a1 > 0.0) || k as f64 * dfp >= nyquist {
            continue;
        }
        let delta = if a0 > 0.0 && a2 > 0.0 {
            let (al, be, ga) = (a0.ln(), a1.ln(), a2.ln());
            let denom = al - 2.0 * be + ga;
            if denom < 0.0 {
                (0.5 * (al - ga) / denom).clamp(-0.5, 0.5)
            } else {
                0.0
            }
        } else {
            0.0
        };
        // The padded bin's reading, corrected for the Hann response delta padded bins off
        // (refined below for the peaks kept).
        let hz = (k as f64 + delta) * dfp;
        peaks.push((hz, a1 / hann_response(delta * nf / m as f64)));
    }
    let largest = peaks
        .iter()
        .filter(|p| p.0 >= low)
        .fold(0.0f64, |m, p| m.max(p.1));
    if largest <= 1e-10 * scale {
        return Vec::new();
    }
    let floor = (opts.rel_threshold * largest).max(1e-10 * scale);
    peaks.retain(|p| p.1 >= floor && p.1.is_finite());
    peaks.sort_by(|a, b| b.1.total_cmp(&a.1));

    let mut strong: Vec<(f64, f64)> = Vec::new(); // accepted, below the cut included
    let mut kept: Vec<(f64, f64)> = Vec::new();
    for (hz, a) in peaks {
        if kept.len() >= opts.max_components {
            break;
        }
        let leakage = strong.iter().any(|&(hk, ak)| {
            let d = (hz - hk).abs() / df;
            d < 2.0 || a < 2.0 * ak / (PI * d * (d * d - 1.0))
        });
        if !leakage {
            strong.push((hz, a));
            if hz >= low {
                kept.push((hz, a));
            }
        }
    }

    let tol_hz = opts.rotation_tolerance_bins * df;
    let mut components: Vec<Component> = kept
        .into_iter()
        .map(|(hz, _)| {
            let amplitude = windowed_amplitude(&x, &window, window_sum, hz * dt);
            let mut kinds = classify(hz, rot_hz, rim_nodes, modes_hz, tol_hz, opts);
            let kind = kinds.remove(0);
            Component {
                hz,
                cycles_per_turn: hz / rot_hz,
                amplitude,
                kind,
                also: kinds,
            }
        })
        .collect();
    components.sort_by(|a, b| b.amplitude.total_cmp(&a.amplitude));
    components
}

/// Amplitude response of the Hann window to a sine `d` bins off the bin centre, relative to
/// an on-bin sine (large-`N` limit): `sinc(d) / (1 - d^2)`, `|d| <= 1/2`.
fn hann_response(d: f64) -> f64 {
    if d == 0.0 {
        return 1.0;
    }
    let x = PI * d;
    x.sin() / (x * (1.0 - d * d))
}

/// A per-turn count of the force's oscillations that is stable on every mesh: the cycles
/// per turn of the largest fixed-frequency component (a [`ComponentKind::Mode`] or
/// [`ComponentKind::Unclassified`]; neither locked nor node passing), or `None` if there is
/// none.
///
/// The count of peaks per turn (or the frequency of the largest peak) follows whichever
/// component happens to dominate, and on another mesh that changes: more rim nodes move the
/// node-passing ripple and change its amplitude, a finer or less symmetric mesh changes the
/// locked components. This count leaves out both kinds, which are properties of the mesh
/// and of the rotation, and keeps the wheel's own vibration, whose frequency is a property
/// of the wheel on its support: it changes little with the mesh once the mode is resolved,
/// and with `omega` it falls as `1/omega` (its frequency in Hz does not change). A mode whose
/// `also` lists [`ComponentKind::Locked`] still counts (it is a mode by precedence).
pub fn fixed_frequency_per_turn(components: &[Component]) -> Option<f64> {
    components
        .iter()
        .filter(|c| c.is_fixed_frequency())
        .max_by(|a, b| a.amplitude.total_cmp(&b.amplitude))
        .map(|c| c.cycles_per_turn)
}

/// The finite samples, on a uniform grid: `(dt, values)`. `None` when fewer than 4 finite
/// samples or no positive step.
fn uniform_samples(t: &[f64], y: &[f64], dt: Option<f64>) -> Option<(f64, Vec<f64>)> {
    let (ts, ys): (Vec<f64>, Vec<f64>) = t
        .iter()
        .zip(y)
        .filter(|(a, b)| a.is_finite() && b.is_finite())
        .map(|(a, b)| (*a, *b))
        .unzip();
    if ts.len() < 4 {
        return None;
    }
    let mut steps: Vec<f64> = ts.windows(2).map(|w| w[1] - w[0]).collect();
    steps.sort_by(f64::total_cmp);
    let median = steps[steps.len() / 2];
    let uniform = median > 0.0
        && steps[0] >= median * (1.0 - 1e-6)
        && steps[steps.len() - 1] <= median * (1.0 + 1e-6);
    let wanted = dt.filter(|d| *d > 0.0 && d.is_finite());
    let (dt, x) = match wanted {
        None if uniform => (median, ys),
        Some(dt) => (dt, resample_uniform(&ts, &ys, dt).1),
        None if median > 0.0 => (median, resample_uniform(&ts, &ys, median).1),
        None => return None,
    };
    (x.len() >= 4).then_some((dt, x))
}

/// Subtracts the mean and, if `linear`, the least-squares slope (over the sample index).
fn remove_trend(x: &mut [f64], linear: bool) {
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    let c = 0.5 * (n - 1.0);
    let slope = if linear {
        let (sxy, sxx) = x.iter().enumerate().fold((0.0, 0.0), |(sxy, sxx), (i, v)| {
            let d = i as f64 - c;
            (sxy + d * (v - mean), sxx + d * d)
        });
        if sxx > 0.0 {
            sxy / sxx
        } else {
            0.0
        }
    } else {
        0.0
    };
    for (i, v) in x.iter_mut().enumerate() {
        *v -= mean + slope * (i as f64 - c);
    }
}

/// Amplitude of the windowed record at `cycles_per_sample` (= f dt): twice the modulus of
/// its discrete-time Fourier transform there, over the window's sum.
fn windowed_amplitude(x: &[f64], w: &[f64], window_sum: f64, cycles_per_sample: f64) -> f64 {
    let step = Complex::from_polar(1.0, -2.0 * PI * cycles_per_sample);
    let mut phasor = Complex::new(1.0, 0.0);
    let mut acc = Complex::new(0.0, 0.0);
    for (i, (&v, &wi)) in x.iter().zip(w).enumerate() {
        if i % 1024 == 0 {
            // Renormalise the recurrence against rounding drift.
            phasor = Complex::from_polar(1.0, -2.0 * PI * cycles_per_sample * i as f64);
        }
        acc += phasor * (wi * v);
        phasor *= step;
    }
    2.0 * acc.norm() / window_sum
}

/// The kinds that apply to a component at `hz`, in the order of precedence (never empty:
/// [`ComponentKind::Unclassified`] when none does).
fn classify(
    hz: f64,
    rot_hz: f64,
    rim_nodes: usize,
    modes_hz: &[f64],
    tol_hz: f64,
    opts: &ComponentOptions,
) -> Vec<ComponentKind> {
    let mut kinds = Vec::new();
    let mut node_passing = false;
    if rim_nodes > 0 {
        let f_np = rot_hz * rim_nodes as f64;
        let h = (hz / f_np).round();
        if h >= 1.0 && (hz - h * f_np).abs() <= tol_hz {
            kinds.push(ComponentKind::NodePassing {
                harmonic: h as usize,
            });
            node_passing = true;
        }
    }
    let mut modes: Vec<(f64, usize, f64)> = modes_hz
        .iter()
        .enumerate()
        .filter(|(_, m)| **m > 0.0 && m.is_finite())
        .map(|(i, &m)| ((hz - m).abs() / m, i, m))
        .filter(|(r, _, _)| *r <= opts.mode_tolerance_rel)
        .collect();
    modes.sort_by(|a, b| a.0.total_cmp(&b.0));
    kinds.extend(
        modes
            .into_iter()
            .map(|(_, index, hz)| ComponentKind::Mode { index, hz }),
    );
    let m = (hz / rot_hz).round();
    if !node_passing && m >= 1.0 && (hz - m * rot_hz).abs() <= tol_hz {
        kinds.push(ComponentKind::Locked {
            cycles_per_turn: m as usize,
        });
    }
    if kinds.is_empty() {
        kinds.push(ComponentKind::Unclassified);
    }
    kinds
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Time step of the wheel runs, s.
    const H: f64 = 2e-6;
    const TURNS: f64 = 5.0;
    const RIM: usize = 72;
    const MODE_HZ: f64 = 5500.0;

    /// Deterministic pseudo-random numbers in [-1, 1).
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> f64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            let v = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D);
            (v >> 11) as f64 / (1u64 << 52) as f64 - 1.0
        }
    }

    /// Amplitudes (N) of the synthetic wheel force: locked 6 per turn, node passing and its
    /// second harmonic, the fixed mode; and the uniform noise's half-width.
    #[derive(Clone, Copy)]
    struct Mix {
        locked: f64,
        ripple: f64,
        ripple2: f64,
        mode: f64,
        noise: f64,
    }

    const MIX: Mix = Mix {
        locked: 20e3,
        ripple: 30e3,
        ripple2: 6e3,
        mode: 8e3,
        noise: 5e3,
    };

    /// Five turns at `omega` sampled every `H` after a settling time, on a 200 kN mean with
    /// a 10 kN drift, plus noise.
    fn wheel_force(omega: f64, mix: Mix, seed: u64) -> (Vec<f64>, Vec<f64>) {
        let rot = omega / (2.0 * PI);
        let n = (TURNS / rot / H).round() as usize;
        let t0 = 0.05;
        let mut rng = Rng(seed);
        (0..n)
            .map(|i| {
                let t = t0 + i as f64 * H;
                let s = i as f64 / n as f64;
                let y = 200e3
                    + 10e3 * s
                    + mix.locked * (2.0 * PI * 6.0 * rot * t + 0.3).sin()
                    + mix.ripple * (2.0 * PI * RIM as f64 * rot * t + 1.1).sin()
                    + mix.ripple2 * (2.0 * PI * 2.0 * RIM as f64 * rot * t + 2.0).sin()
                    + mix.mode * (2.0 * PI * MODE_HZ * t + 0.5).sin()
                    + mix.noise * rng.next();
                (t, y)
            })
            .unzip()
    }

    fn find<'a>(cs: &'a [Component], kind: &ComponentKind) -> &'a Component {
        cs.iter()
            .find(|c| &c.kind == kind)
            .unwrap_or_else(|| panic!("no {kind:?} in {cs:#?}"))
    }

    /// Checks the four components of [`wheel_force`]; returns the worst relative errors of
    /// frequency and amplitude.
    fn check_wheel(cs: &[Component], omega: f64, mix: Mix) -> (f64, f64) {
        let rot = omega / (2.0 * PI);
        let expected = [
            (
                ComponentKind::Locked { cycles_per_turn: 6 },
                6.0 * rot,
                mix.locked,
            ),
            (
                ComponentKind::NodePassing { harmonic: 1 },
                RIM as f64 * rot,
                mix.ripple,
            ),
            (
                ComponentKind::NodePassing { harmonic: 2 },
                2.0 * RIM as f64 * rot,
                mix.ripple2,
            ),
            (
                ComponentKind::Mode {
                    index: 1,
                    hz: MODE_HZ,
                },
                MODE_HZ,
                mix.mode,
            ),
        ];
        assert_eq!(cs.len(), expected.len(), "{cs:#?}");
        let (mut ef, mut ea) = (0.0f64, 0.0f64);
        for (kind, hz, amp) in expected {
            let c = find(cs, &kind);
            assert!(c.also.is_empty(), "{c:?}");
            let (rf, ra) = ((c.hz - hz).abs() / hz, (c.amplitude - amp).abs() / amp);
            assert!(rf < 2e-3, "{kind:?}: {} Hz vs {hz}", c.hz);
            assert!(ra < 2e-2, "{kind:?}: amplitude {} vs {amp}", c.amplitude);
            assert!((c.cycles_per_turn - c.hz / rot).abs() < 1e-9 * c.cycles_per_turn);
            ef = ef.max(rf);
            ea = ea.max(ra);
        }
        // Strongest first.
        assert!(cs.windows(2).all(|w| w[0].amplitude >= w[1].amplitude));
        (ef, ea)
    }

    /// Modes given to the classifier: the 5.5 kHz one at index 1, one far away at index 0.
    const MODES: [f64; 2] = [1234.0, MODE_HZ];

    #[test]
    fn wheel_components_found_and_classified_at_two_speeds() {
        let mut per_turn = Vec::new();
        for omega in [300.0, 520.0] {
            let (t, y) = wheel_force(omega, MIX, 7);
            let cs = spectral_components(&t, &y, omega, RIM, &MODES, &ComponentOptions::default());
            let (ef, ea) = check_wheel(&cs, omega, MIX);
            eprintln!("omega {omega}: worst frequency error {ef:.2e}, amplitude error {ea:.2e}");
            let fixed = fixed_frequency_per_turn(&cs).unwrap();
            assert!(
                (fixed - MODE_HZ * 2.0 * PI / omega).abs() < 2e-3 * fixed,
                "{fixed}"
            );
            per_turn.push(fixed);
        }
        // A fixed frequency counted per turn falls as 1/omega.
        let ratio = per_turn[0] / per_turn[1];
        eprintln!("fixed per turn {per_turn:?}, ratio {ratio}");
        assert!((ratio - 520.0 / 300.0).abs() < 2e-3 * ratio, "{ratio}");
    }

    #[test]
    fn fixed_frequency_count_does_not_follow_the_dominant_component() {
        let omega = 300.0;
        let opts = ComponentOptions::default();
        let mut counts = Vec::new();
        let mut strongest = Vec::new();
        // The ripple dominates, then the locked component, then the mode itself.
        for (locked, ripple, mode) in [(20e3, 30e3, 8e3), (60e3, 10e3, 8e3), (5e3, 4e3, 12e3)] {
            let mix = Mix {
                locked,
                ripple,
                mode,
                ..MIX
            };
            let (t, y) = wheel_force(omega, mix, 11);
            let cs = spectral_components(&t, &y, omega, RIM, &MODES, &opts);
            check_wheel(&cs, omega, mix);
            strongest.push(cs[0].kind.clone());
            counts.push(fixed_frequency_per_turn(&cs).unwrap());
        }
        assert_eq!(
            strongest,
            vec![
                ComponentKind::NodePassing { harmonic: 1 },
                ComponentKind::Locked { cycles_per_turn: 6 },
                ComponentKind::Mode {
                    index: 1,
                    hz: MODE_HZ
                },
            ]
        );
        for c in &counts {
            assert!((c - counts[0]).abs() < 1e-3 * counts[0], "{counts:?}");
        }
    }

    #[test]
    fn pure_sine_amplitude_and_frequency_across_a_bin() {
        // 0.01 s at H: 5000 samples, one bin = 100 Hz; sweep a sine over one bin.
        let n = 5000;
        let omega = 300.0;
        let (mut worst_a, mut worst_f) = (0.0f64, 0.0f64);
        for step in 0..=20 {
            let f0 = (57.0 + step as f64 / 20.0) * 100.0;
            let a0 = 3.7;
            let t: Vec<f64> = (0..n).map(|i| i as f64 * H).collect();
            let y: Vec<f64> = t
                .iter()
                .map(|t| 1.5 + a0 * (2.0 * PI * f0 * t + 0.9).sin())
                .collect();
            // A threshold far below the Hann window's first side lobe (2.7 %): the side lobes
            // must still not show up as peaks.
            let opts = ComponentOptions {
                rel_threshold: 1e-3,
                ..Default::default()
            };
            let cs = spectral_components(&t, &y, omega, 0, &[], &opts);
            assert_eq!(cs.len(), 1, "{f0} Hz: {cs:#?}");
            worst_a = worst_a.max((cs[0].amplitude - a0).abs() / a0);
            worst_f = worst_f.max((cs[0].hz - f0).abs() / 100.0);
        }
        eprintln!("pure sine: worst amplitude error {worst_a:.2e}, frequency {worst_f:.2e} bin");
        assert!(worst_a < 1e-2, "{worst_a}");
        assert!(worst_f < 0.02, "{worst_f} bin");
    }

    #[test]
    fn empty_constant_and_degenerate_signals_give_nothing() {
        let opts = ComponentOptions::default();
        let none = |t: &[f64], y: &[f64], omega: f64| {
            let cs = spectral_components(t, y, omega, RIM, &MODES, &opts);
            assert!(cs.is_empty(), "{cs:?}");
        };
        none(&[], &[], 300.0);
        none(&[0.0, H, 2.0 * H], &[1.0, 2.0, 1.0], 300.0);
        let t: Vec<f64> = (0..20_000).map(|i| i as f64 * H).collect();
        none(&t, &[123_456.789; 20_000], 300.0);
        none(&t, &[0.0; 20_000], 300.0);
        let no_trend = ComponentOptions {
            detrend: false,
            ..Default::default()
        };
        assert!(spectral_components(&t, &[-0.1; 20_000], 300.0, RIM, &MODES, &no_trend).is_empty());
        // A straight line is only a trend.
        let line: Vec<f64> = t.iter().map(|t| 5.0 + 3e4 * t).collect();
        none(&t, &line, 300.0);
        // All times equal, no rotation, no finite sample.
        none(&[1.0; 100], &[2.0; 100], 300.0);
        let (t, y) = wheel_force(300.0, MIX, 3);
        none(&t, &y, 0.0);
        none(&t, &y, f64::NAN);
        none(&t, &vec![f64::NAN; y.len()], 300.0);
        // Mismatched lengths use the shorter one.
        let cs = spectral_components(&t, &y[..y.len() / 2], 300.0, RIM, &MODES, &opts);
        assert!(!cs.is_empty());
    }

    #[test]
    fn nan_samples_are_skipped() {
        let omega = 520.0;
        let (mut t, mut y) = wheel_force(omega, MIX, 5);
        let n = y.len();
        for i in (0..n).step_by(997) {
            y[i] = f64::NAN;
        }
        for v in &mut y[n / 3..n / 3 + 5] {
            *v = f64::INFINITY;
        }
        t[n / 2] = f64::NAN;
        let cs = spectral_components(&t, &y, omega, RIM, &MODES, &ComponentOptions::default());
        let (ef, ea) = check_wheel(&cs, omega, MIX);
        eprintln!("with NaN: worst frequency error {ef:.2e}, amplitude error {ea:.2e}");
    }

    #[test]
    fn irregular_steps_are_resampled() {
        let omega = 300.0;
        let (t, y) = wheel_force(omega, MIX, 9);
        // Keep a random subset of the samples: steps of 1 to 3 H.
        let mut rng = Rng(21);
        let (ts, ys): (Vec<f64>, Vec<f64>) = t
            .iter()
            .zip(&y)
            .filter(|_| rng.next() < 0.4)
            .map(|(a, b)| (*a, *b))
            .unzip();
        let opts = ComponentOptions {
            dt: Some(H),
            ..Default::default()
        };
        let cs = spectral_components(&ts, &ys, omega, RIM, &MODES, &opts);
        check_wheel(&cs, omega, MIX);
        // Without `dt`: the median step.
        let cs = spectral_components(&ts, &ys, omega, RIM, &MODES, &ComponentOptions::default());
        check_wheel(&cs, omega, MIX);
    }

    #[test]
    fn ambiguities_are_flagged_and_precedence_holds() {
        let omega = 300.0;
        let rot = omega / (2.0 * PI);
        let n = (TURNS / rot / H).round() as usize;
        let t: Vec<f64> = (0..n).map(|i| i as f64 * H).collect();
        // 10 per turn (a given mode sits there), the node-passing frequency (a mode sits
        // there too), 37.3 per turn (nothing), 0.3 per turn (below the low cut).
        let (f_locked, f_np, f_free, f_slow) = (10.0 * rot, 72.0 * rot, 37.3 * rot, 0.3 * rot);
        let y: Vec<f64> = t
            .iter()
            .map(|t| {
                5e3 * (2.0 * PI * f_locked * t).sin()
                    + 4e3 * (2.0 * PI * f_np * t + 1.0).sin()
                    + 3e3 * (2.0 * PI * f_free * t + 2.0).sin()
                    + 9e3 * (2.0 * PI * f_slow * t).sin()
            })
            .collect();
        let modes = [f_np * 1.01, f_locked * 0.99];
        let cs = spectral_components(&t, &y, omega, RIM, &modes, &ComponentOptions::default());
        assert_eq!(cs.len(), 3, "{cs:#?}");
        let c = find(
            &cs,
            &ComponentKind::Mode {
                index: 1,
                hz: modes[1],
            },
        );
        assert_eq!(
            c.also,
            vec![ComponentKind::Locked {
                cycles_per_turn: 10
            }]
        );
        let c = find(&cs, &ComponentKind::NodePassing { harmonic: 1 });
        assert_eq!(
            c.also,
            vec![ComponentKind::Mode {
                index: 0,
                hz: modes[0]
            }]
        );
        let c = find(&cs, &ComponentKind::Unclassified);
        assert!((c.cycles_per_turn - 37.3).abs() < 0.01, "{c:?}");
        assert!(c.also.is_empty());
        // The largest fixed-frequency component is the mode at 10 per turn (5 kN > 3 kN):
        // its measured cycles per turn, not the given mode's 9.9.
        let fixed = fixed_frequency_per_turn(&cs).unwrap();
        assert!((fixed - 10.0).abs() < 0.01, "{fixed}");

        // Without rim nodes or modes, the same peaks are only locked or unclassified.
        let cs = spectral_components(&t, &y, omega, 0, &[], &ComponentOptions::default());
        let kinds: Vec<_> = cs.iter().map(|c| c.kind.clone()).collect();
        assert_eq!(
            kinds,
            vec![
                ComponentKind::Locked {
                    cycles_per_turn: 10
                },
                ComponentKind::Locked {
                    cycles_per_turn: 72
                },
                ComponentKind::Unclassified,
            ]
        );
        assert_eq!(fixed_frequency_per_turn(&cs[..2]), None);
        let fixed = fixed_frequency_per_turn(&cs).unwrap();
        assert!((fixed - 37.3).abs() < 0.01, "{fixed}");
    }

    #[test]
    fn serializes_for_the_summary() {
        let c = Component {
            hz: 3437.7,
            cycles_per_turn: 72.0,
            amplitude: 3e4,
            kind: ComponentKind::NodePassing { harmonic: 1 },
            also: vec![ComponentKind::Mode {
                index: 0,
                hz: 3400.0,
            }],
        };
        let v = serde_json::to_value(&c).unwrap();
        assert_eq!(v["kind"]["type"], "node_passing");
        assert_eq!(v["kind"]["harmonic"], 1);
        assert_eq!(v["also"][0]["type"], "mode");
        assert_eq!(v["also"][0]["hz"], 3400.0);
        assert_eq!(v["amplitude"], 3e4);
        let u = serde_json::to_value(ComponentKind::Unclassified).unwrap();
        assert_eq!(u["type"], "unclassified");
    }
}
