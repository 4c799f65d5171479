//! The track's receptance: the rail's displacement per unit harmonic force, from the
//! assembled `M`, `C`, `K` of the track ([`super::Track`]):
//! $$\big(K - \omega^2 M + i\omega C\big)\\,\hat u = N_w(x)\qquad
//!   \alpha(x, \omega) = N_w(x)^T \hat u\quad\text{(m/N)},$$
//! with `N_w(x)` the beam's own deflection shape functions at the point `x` (a point between
//! nodes is loaded and read through them). Each frequency is one complex sparse LU of the
//! dynamic stiffness on the pattern of the model, its symbolic analysis done once
//! ([`Pencil`]: faer's sparse LU on `c64`).
//!
//! # What is read off the curves ([`frequencies`])
//!
//! - **Pinned-pinned frequency**: the peak of the mid-span receptance near the frequency of a
//!   simply supported span of one bay ([`simply_supported_hz`]: the exact first frequency of
//!   the span for the rail's theory), searched in `[0.6, 1.4]` times it. It is the lower edge
//!   of the stop band of the Bloch waves of wavelength `2 s`: their mode, `sin(pi x / s)`,
//!   has its nodes on the pads, so neither the pads' stiffness nor their damping acts on it,
//!   and its frequency is the span's whatever the pads (point pads; the FE's 1061.8 Hz at six
//!   elements a bay against the span's 1058.2 Hz is the mesh's +0.34%, 1058.2 Hz at twelve;
//!   pads of 50 MN/m to 2 GN/m move it by less than 0.1%, `tests/track.rs`). What the pads
//!   move is the receptance above the sleeper: its anti-resonance sits above the peak and
//!   comes down to it as the pads soften (1224.7 Hz at 2 GN/m, 1087.6 Hz at 200 MN/m,
//!   1076.5 Hz at 50 MN/m). With no damping in the rail (none in this parameter set) the
//!   infinite track's receptance is singular at the band edge (a group velocity of zero, an
//!   undamped mode): a finite track's peak is finite and grows with its length (5.4e-9,
//!   9.0e-9, 1.6e-8, 2.9e-8 m/N for 50, 100, 200, 400 bays) while its frequency converges
//!   (1059.8, 1061.8, 1062.6, 1062.9 Hz).
//! - **Track resonance**: the peak of the mid-span receptance at low frequency (below
//!   `0.3` times the span's frequency): the rail and sleepers bouncing on the ballast,
//!   62.7 Hz for the `"uic60"` set (the rigid track of one bay on its ballast spring,
//!   `sqrt(k_b / (m_s + rho A s)) / 2 pi`, is 68.9 Hz; the ballast's damping and the rail's
//!   bending lower the peak). The second peak, near 400 Hz, is the rail on its pads.
//! - **P2 frequency**: the unsprung mass `m_u` on the track through the Hertz spring `k_H`
//!   ([`super::hertz`]) resonates where the receptances in series
//!   $$D(\omega) = -\frac{1}{m_u\omega^2} + \frac{1}{k_H} + \alpha(x, \omega)$$
//!   (the wheel's, the contact's and the rail's) have their smallest modulus: the lowest
//!   local minimum of `|D|` (the wheel and the track bouncing together on the ballast; a
//!   second, at a few hundred hertz, is the wheel and the rail on the pads, reported
//!   beside it), searched below half the span's frequency. `1 / |D|` is the contact force
//!   per unit of roughness. The single-dof estimate `sqrt(k_eff / m_u) / (2 pi)`, with
//!   `k_eff` the series of `k_H` and the track's static stiffness `1 / alpha(x, 0)`, is
//!   higher: the track's mass that moves with the wheel is left out (`"uic60"`, 800 kg,
//!   100 kN: 43.8 Hz against 50.4 Hz, the mass of 262 kg of track added to the wheel's).
//!
//! Every extremum found on the grid is refined by a golden-section search on `ln f` between
//! the grid's neighbours (each trial frequency one more factorization), so the numbers do
//! not depend on the grid's spacing.
//!
//! # A range that misses a frequency
//!
//! Each frequency is read off the range of the receptance only where the range holds it:
//! the lowest minimum of `|D|` in a range that starts above the P2 resonance is the second
//! coupled one (issue 47: `f_min = 45 Hz` reported the second coupled minimum, 176.2 Hz,
//! as P2), and the largest peak below `0.3` times the span's frequency in a range that
//! starts above the track resonance is not that resonance. So the P2 frequencies and the
//! track resonance are reported only when their curve still falls (`|D|`) or rises
//! (`|alpha|`) all the way from [`SCAN_FROM_HZ`] up to the range's first frequencies
//! (scanned on [`SCAN_POINTS`] more frequencies below it: no extremum is left below the
//! range); else `None`, and [`Frequencies::p2_below_range`] or
//! [`Frequencies::track_resonance_below_range`] says why. (A range that cuts the
//! pinned-pinned window reads its peak where it holds one, none where it does not: the
//! peak dominates its window.)

use super::{Track, TrackError};
use crate::element::beam::{BeamSection, BeamTheory};
use crate::linalg::Pattern;
use faer::c64;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::lu::{factorize_symbolic_lu, LuRef, NumericLu, SymbolicLu};
use faer::sparse::SparseColMatRef;
use faer::{Conj, MatMut, Par};
use std::f64::consts::PI;

/// The track's dynamic stiffness `K - omega^2 M + i omega C` factored at one frequency at a
/// time, on one symbolic analysis (module docs).
pub struct Pencil {
    pattern: Pattern,
    m: Vec<f64>,
    c: Vec<f64>,
    k: Vec<f64>,
    values: Vec<c64>,
    symbolic: SymbolicLu<usize>,
    numeric: NumericLu<usize, c64>,
    factor_mem: MemBuffer,
    solve_mem: MemBuffer,
    factored: bool,
}

impl std::fmt::Debug for Pencil {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Pencil")
            .field("n", &self.pattern.nrows())
            .finish()
    }
}

impl Pencil {
    /// The symbolic analysis of the track's pattern.
    ///
    /// # Errors
    /// [`TrackError::Solve`] when faer cannot analyse it.
    pub fn new(track: &Track) -> Result<Self, TrackError> {
        let model = &track.joined.model;
        let pattern = model.pattern().clone();
        let symbolic = factorize_symbolic_lu(pattern.as_ref(), Default::default())
            .map_err(|e| TrackError::Solve(format!("symbolic analysis: {e:?}")))?;
        let factor_mem = MemBuffer::new(
            symbolic.factorize_numeric_lu_scratch::<c64>(Par::Seq, Default::default()),
        );
        let solve_mem = MemBuffer::new(symbolic.solve_in_place_scratch::<c64>(1, Par::Seq));
        Ok(Self {
            values: vec![c64::new(0.0, 0.0); model.m.len()],
            m: model.m.clone(),
            c: model.c.clone(),
            k: model.k.clone(),
            pattern,
            symbolic,
            numeric: NumericLu::new(),
            factor_mem,
            solve_mem,
            factored: false,
        })
    }

    /// Order of the matrix.
    pub fn n(&self) -> usize {
        self.pattern.nrows()
    }

    /// Factors `K - omega^2 M + i omega C` (`omega` in rad/s; 0: the static stiffness).
    ///
    /// # Errors
    /// [`TrackError::Solve`] when the matrix is singular.
    pub fn factor(&mut self, omega: f64) -> Result<(), TrackError> {
        let w2 = omega * omega;
        for (s, v) in self.values.iter_mut().enumerate() {
            *v = c64::new(self.k[s] - w2 * self.m[s], omega * self.c[s]);
        }
        self.factored = false;
        self.symbolic
            .factorize_numeric_lu(
                &mut self.numeric,
                SparseColMatRef::new(self.pattern.as_ref(), &self.values),
                Par::Seq,
                MemStack::new(&mut self.factor_mem),
                Default::default(),
            )
            .map_err(|e| TrackError::Solve(format!("singular at omega = {omega} rad/s: {e:?}")))?;
        self.factored = true;
        Ok(())
    }

    /// `rhs <- A^{-1} rhs` with the last factorization.
    ///
    /// # Errors
    /// [`TrackError::Solve`] before any factorization.
    pub fn solve_in_place(&mut self, rhs: &mut [c64]) -> Result<(), TrackError> {
        if !self.factored || rhs.len() != self.n() {
            return Err(TrackError::Solve("no factorization of this size".into()));
        }
        let n = self.n();
        LuRef::new_unchecked(&self.symbolic, &self.numeric).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(rhs, n, 1),
            Par::Seq,
            MemStack::new(&mut self.solve_mem),
        );
        Ok(())
    }

    /// The rail's point receptance at `x` (m/N) at the last factorization's frequency.
    ///
    /// # Errors
    /// [`TrackError`] for a point off the rail.
    pub fn point_receptance(&mut self, track: &Track, x: f64) -> Result<c64, TrackError> {
        let (dofs, nw) = track.point(x)?;
        let mut rhs = vec![c64::new(0.0, 0.0); self.n()];
        for a in 0..4 {
            rhs[dofs[a]] = c64::new(nw[a], 0.0);
        }
        self.solve_in_place(&mut rhs)?;
        Ok((0..4).fold(c64::new(0.0, 0.0), |s, a| s + rhs[dofs[a]] * nw[a]))
    }

    /// The static displacement (m) under `force` (N) at `x` (m), after [`Pencil::factor`]
    /// at zero frequency.
    ///
    /// # Errors
    /// [`TrackError`] for a point off the rail.
    pub fn static_displacement(
        &mut self,
        track: &Track,
        x: f64,
        force: f64,
    ) -> Result<Vec<f64>, TrackError> {
        let (dofs, nw) = track.point(x)?;
        let mut rhs = vec![c64::new(0.0, 0.0); self.n()];
        for a in 0..4 {
            rhs[dofs[a]] = c64::new(force * nw[a], 0.0);
        }
        self.solve_in_place(&mut rhs)?;
        Ok(rhs.iter().map(|z| z.re).collect())
    }
}

/// `points` frequencies (Hz) spaced evenly in `ln f` from `f_min` to `f_max`.
pub fn log_frequencies(f_min: f64, f_max: f64, points: usize) -> Vec<f64> {
    if points < 2 {
        return vec![f_min];
    }
    let r = (f_max / f_min).ln() / (points - 1) as f64;
    (0..points)
        .map(|i| {
            if i + 1 == points {
                f_max
            } else {
                f_min * (r * i as f64).exp()
            }
        })
        .collect()
}

/// The receptance at two points of the rail over a set of frequencies.
#[derive(Debug, Clone, PartialEq)]
pub struct Receptance {
    /// Frequencies, Hz.
    pub frequency_hz: Vec<f64>,
    /// The mid-span point ([`Track::middle_span`]), m.
    pub mid_span_x: f64,
    /// The point above the middle sleeper ([`Track::middle`]), m.
    pub above_sleeper_x: f64,
    /// The mid-span receptance, m/N.
    pub mid_span: Vec<c64>,
    /// The receptance above the sleeper, m/N.
    pub above_sleeper: Vec<c64>,
}

/// The receptance at mid-span and above the middle sleeper at `frequency_hz` (module docs).
///
/// # Errors
/// [`TrackError::Solve`] when a dynamic stiffness is singular.
pub fn receptance(track: &Track, frequency_hz: &[f64]) -> Result<Receptance, TrackError> {
    receptance_until(
        track,
        frequency_hz,
        &std::sync::atomic::AtomicBool::new(false),
    )
}

/// [`receptance`], stopped before the next frequency once `interrupt` is set: the result
/// holds the frequencies computed so far (all of them when it was never set).
///
/// # Errors
/// As [`receptance`].
pub fn receptance_until(
    track: &Track,
    frequency_hz: &[f64],
    interrupt: &std::sync::atomic::AtomicBool,
) -> Result<Receptance, TrackError> {
    let mut pencil = Pencil::new(track)?;
    let (xm, xs) = (track.middle_span(), track.middle());
    let mut mid = Vec::with_capacity(frequency_hz.len());
    let mut above = Vec::with_capacity(frequency_hz.len());
    for &f in frequency_hz {
        if interrupt.load(std::sync::atomic::Ordering::Relaxed) {
            break;
        }
        pencil.factor(2.0 * PI * f)?;
        mid.push(pencil.point_receptance(track, xm)?);
        above.push(pencil.point_receptance(track, xs)?);
    }
    Ok(Receptance {
        frequency_hz: frequency_hz[..mid.len()].to_vec(),
        mid_span_x: xm,
        above_sleeper_x: xs,
        mid_span: mid,
        above_sleeper: above,
    })
}

/// The rail's point receptance averaged over `points` evenly spaced abscissae across the
/// bay after the middle sleeper (m/N, one per frequency): what a contact point moving along
/// the rail sees on average ([`crate::kinds::track::growth`]'s prediction of growth).
///
/// # Errors
/// [`TrackError::Solve`] when a dynamic stiffness is singular.
pub fn bay_averaged(
    track: &Track,
    frequency_hz: &[f64],
    points: usize,
) -> Result<Vec<c64>, TrackError> {
    let mut pencil = Pencil::new(track)?;
    let (x0, s) = (track.middle(), track.spec.spacing);
    let points = points.max(1);
    frequency_hz
        .iter()
        .map(|&f| {
            pencil.factor(2.0 * PI * f)?;
            let mut sum = c64::new(0.0, 0.0);
            for i in 0..points {
                sum += pencil.point_receptance(track, x0 + s * (i as f64 + 0.5) / points as f64)?;
            }
            Ok(sum / points as f64)
        })
        .collect()
}

/// The first frequency (Hz) of a simply supported span of length `span` (m) of the rail:
/// Euler-Bernoulli `omega = k^2 sqrt(EI / rho A)`; Timoshenko the lower root of
/// `a omega^4 - b omega^2 + c = 0`, `a = rho^2 I / (kappa G)`,
/// `b = rho A + rho I k^2 (1 + E / (kappa G))`, `c = EI k^4`, with `k = pi / span`
/// (Timoshenko's equation with `w = sin(k x) e^{i omega t}`).
pub fn simply_supported_hz(s: &BeamSection, theory: BeamTheory, span: f64) -> f64 {
    let k = PI / span;
    let omega = match theory {
        BeamTheory::EulerBernoulli => k * k * (s.ei() / s.rho_a()).sqrt(),
        BeamTheory::Timoshenko => {
            let kg = s.shear_coefficient * s.shear_modulus;
            let a = s.density * s.density * s.inertia / kg;
            let b = s.rho_a() + s.density * s.inertia * k * k * (1.0 + s.young / kg);
            let c = s.ei() * k.powi(4);
            (2.0 * c / (b + (b * b - 4.0 * a * c).sqrt())).sqrt()
        }
    };
    omega / (2.0 * PI)
}

/// The wheel on the track for the P2 resonance.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Wheel {
    /// Unsprung mass per wheel `m_u`, kg.
    pub unsprung_mass: f64,
    /// Static wheel load `P`, N.
    pub load: f64,
    /// Wheel radius `R_w`, m.
    pub radius: f64,
}

/// The frequencies read off the receptance (module docs).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Frequencies {
    /// The span's simply supported frequency (the search window's centre), Hz.
    pub simply_supported_hz: f64,
    /// The peak of the mid-span receptance near it, Hz.
    pub pinned_pinned_hz: Option<f64>,
    /// The mid-span receptance there, m/N.
    pub pinned_pinned_receptance: Option<f64>,
    /// The anti-resonance of the receptance above the sleeper near it, Hz.
    pub above_sleeper_antiresonance_hz: Option<f64>,
    /// The low-frequency peak of the mid-span receptance, Hz.
    pub track_resonance_hz: Option<f64>,
    /// The mid-span receptance there, m/N.
    pub track_resonance_receptance: Option<f64>,
    /// The P2 frequency at mid-span, Hz.
    pub p2_hz: Option<f64>,
    /// The P2 frequency above the sleeper, Hz.
    pub p2_above_sleeper_hz: Option<f64>,
    /// The second local minimum of `|D|` at mid-span (the wheel and the rail on the pads,
    /// the sleepers above their own resonance on the ballast), Hz.
    pub second_coupled_hz: Option<f64>,
    /// The Hertz spring `k_H`, N/m.
    pub hertz_stiffness: f64,
    /// The track's static stiffness at mid-span `1 / alpha(x, 0)`, N/m.
    pub static_stiffness_mid_span: f64,
    /// The track's static stiffness above the sleeper, N/m.
    pub static_stiffness_above_sleeper: f64,
    /// The single-dof P2 estimate at mid-span `sqrt(k_eff / m_u) / (2 pi)`, Hz.
    pub p2_single_dof_hz: f64,
    /// The range of the receptance starts above the P2 resonance and the second coupled
    /// minimum (`|D|` does not fall all the way up to its first frequency): they are not
    /// read off it (module docs).
    pub p2_below_range: bool,
    /// The range starts above the track resonance (`|alpha|` at mid-span does not rise all
    /// the way up to its first frequency).
    pub track_resonance_below_range: bool,
}

/// Where the scans below a range's first frequency start, Hz (module docs).
pub const SCAN_FROM_HZ: f64 = 1.0;

/// The frequencies of each scan below a range's first frequency.
pub const SCAN_POINTS: usize = 48;

/// True when `score` rises (never falls) over [`SCAN_POINTS`] log-spaced frequencies from
/// [`SCAN_FROM_HZ`] up to `f0` and on to `f1` (the range's first two frequencies): no local
/// maximum of it lies below the range. True at once when `f0` is at or below the scan's
/// start.
fn rises_into(
    (f0, f1): (f64, f64),
    score: &mut dyn FnMut(f64) -> Result<f64, TrackError>,
) -> Result<bool, TrackError> {
    if f0 <= SCAN_FROM_HZ {
        return Ok(true);
    }
    let mut grid = log_frequencies(SCAN_FROM_HZ, f0, SCAN_POINTS);
    grid.push(f1);
    let mut last = f64::NEG_INFINITY;
    for f in grid {
        let v = score(f)?;
        if v < last {
            return Ok(false);
        }
        last = v;
    }
    Ok(true)
}

/// The P2 frequency of a wheel of mass `unsprung_mass` (kg) on the contact spring
/// `contact_stiffness` (N/m) over the rail's point `x` (m) of `track`: the lowest local
/// minimum of `|alpha(x, f) + 1 / k_c - 1 / (m_u (2 pi f)^2)|` between 5 Hz and half the
/// span's simply supported frequency, on `points` log-spaced frequencies refined by golden
/// section (module docs). `None` when that band holds no minimum.
///
/// # Errors
/// [`TrackError`] for a failed solve.
pub fn p2_with(
    track: &Track,
    x: f64,
    unsprung_mass: f64,
    contact_stiffness: f64,
    points: usize,
) -> Result<Option<f64>, TrackError> {
    let spec = &track.spec;
    let f_ss = simply_supported_hz(&spec.section, spec.theory, spec.spacing);
    let mut pencil = Pencil::new(track)?;
    let mut score = |f: f64| -> Result<f64, TrackError> {
        pencil.factor(2.0 * PI * f)?;
        let alpha = pencil.point_receptance(track, x)?;
        let w = 2.0 * PI * f;
        let d = alpha + c64::new(1.0 / contact_stiffness - 1.0 / (unsprung_mass * w * w), 0.0);
        Ok(-d.norm())
    };
    let freqs = log_frequencies(5.0, 0.5 * f_ss, points.max(3));
    let values = freqs
        .iter()
        .map(|&f| score(f))
        .collect::<Result<Vec<f64>, TrackError>>()?;
    refined_extremum(
        &freqs,
        &values,
        (0.0, f64::INFINITY),
        Pick::Lowest,
        &mut score,
    )
}

/// Which local maximum of a score [`refined_extremum`] takes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Pick {
    /// The largest.
    Largest,
    /// The lowest in frequency.
    Lowest,
    /// The second lowest in frequency.
    SecondLowest,
}

/// Where on the grid `score` (to maximise) has its interior local maximum `pick` within
/// `[lo, hi]` Hz, refined by golden section on `ln f` between the neighbours with `eval`.
fn refined_extremum(
    freqs: &[f64],
    score: &[f64],
    (lo, hi): (f64, f64),
    pick: Pick,
    eval: &mut dyn FnMut(f64) -> Result<f64, TrackError>,
) -> Result<Option<f64>, TrackError> {
    let maxima: Vec<usize> = (1..freqs.len().saturating_sub(1))
        .filter(|&i| {
            let inside = freqs[i] >= lo && freqs[i] <= hi;
            inside && score[i] >= score[i - 1] && score[i] >= score[i + 1]
        })
        .collect();
    let chosen = match pick {
        Pick::Largest => maxima
            .iter()
            .copied()
            .reduce(|b, i| if score[i] > score[b] { i } else { b }),
        Pick::Lowest => maxima.first().copied(),
        Pick::SecondLowest => maxima.get(1).copied(),
    };
    let Some(i) = chosen else {
        return Ok(None);
    };
    let (mut a, mut b) = (freqs[i - 1].ln(), freqs[i + 1].ln());
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let (mut c, mut d) = (b - g * (b - a), a + g * (b - a));
    let (mut fc, mut fd) = (eval(c.exp())?, eval(d.exp())?);
    for _ in 0..48 {
        if fc > fd {
            b = d;
            d = c;
            fd = fc;
            c = b - g * (b - a);
            fc = eval(c.exp())?;
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + g * (b - a);
            fd = eval(d.exp())?;
        }
        if b - a < 1e-9 {
            break;
        }
    }
    Ok(Some((0.5 * (a + b)).exp()))
}

/// The frequencies of the module docs from the receptance `r` of `track` and the `wheel`.
///
/// # Errors
/// [`TrackError`] for a failed solve or a wheel the Hertz contact refuses.
pub fn frequencies(
    track: &Track,
    r: &Receptance,
    wheel: &Wheel,
) -> Result<Frequencies, TrackError> {
    let spec = &track.spec;
    let f_ss = simply_supported_hz(&spec.section, spec.theory, spec.spacing);
    let hertz = super::hertz::contact(
        wheel.load,
        wheel.radius,
        spec.head_radius,
        spec.section.young,
        spec.poisson,
    )
    .ok_or(TrackError::Invalid {
        name: "wheel",
        value: wheel.load,
        allowed: "the load and the wheel radius must be finite and > 0",
    })?;
    let k_h = hertz.stiffness;
    let mut pencil = Pencil::new(track)?;
    let mut at = |x: f64, f: f64| -> Result<c64, TrackError> {
        pencil.factor(2.0 * PI * f)?;
        pencil.point_receptance(track, x)
    };
    let (xm, xs) = (r.mid_span_x, r.above_sleeper_x);
    let f = &r.frequency_hz;
    let mid_abs: Vec<f64> = r.mid_span.iter().map(|z| z.norm()).collect();
    let above_neg: Vec<f64> = r.above_sleeper.iter().map(|z| -z.norm()).collect();
    let window = (0.6 * f_ss, 1.4 * f_ss);
    let largest = Pick::Largest;
    // The range's ends (module docs: a frequency is read off only a range that holds it).
    let (first, second) = match f.as_slice() {
        [a, b, _, ..] => (*a, *b),
        _ => {
            return Err(TrackError::Invalid {
                name: "receptance.points",
                value: f.len() as f64,
                allowed: "at least 3 frequencies",
            })
        }
    };
    let pinned_pinned =
        refined_extremum(f, &mid_abs, window, largest, &mut |q| Ok(at(xm, q)?.norm()))?;
    let antiresonance = refined_extremum(f, &above_neg, window, largest, &mut |q| {
        Ok(-at(xs, q)?.norm())
    })?;
    let low = (0.0, 0.3 * f_ss);
    let track_resonance_below_range = !rises_into((first, second), &mut |q| Ok(at(xm, q)?.norm()))?;
    let track_resonance = if track_resonance_below_range {
        None
    } else {
        refined_extremum(f, &mid_abs, low, largest, &mut |q| Ok(at(xm, q)?.norm()))?
    };
    let mu = wheel.unsprung_mass;
    let series = |q: f64, alpha: c64| {
        let w = 2.0 * PI * q;
        (alpha + c64::new(1.0 / k_h - 1.0 / (mu * w * w), 0.0)).norm()
    };
    let p2_window = (0.0, 0.5 * f_ss);
    let mid_score: Vec<f64> = f
        .iter()
        .zip(&r.mid_span)
        .map(|(&q, &a)| -series(q, a))
        .collect();
    let above_score: Vec<f64> = f
        .iter()
        .zip(&r.above_sleeper)
        .map(|(&q, &a)| -series(q, a))
        .collect();
    // |D| must fall from the scan's start up to the range at both points.
    let p2_below_range = !rises_into((first, second), &mut |q| Ok(-series(q, at(xm, q)?)))?
        || !rises_into((first, second), &mut |q| Ok(-series(q, at(xs, q)?)))?;
    let mut coupled = |score: &[f64], x: f64, pick: Pick| {
        refined_extremum(f, score, p2_window, pick, &mut |q| {
            Ok(-series(q, at(x, q)?))
        })
    };
    let (p2, second, p2_above) = if p2_below_range {
        (None, None, None)
    } else {
        (
            coupled(&mid_score, xm, Pick::Lowest)?,
            coupled(&mid_score, xm, Pick::SecondLowest)?,
            coupled(&above_score, xs, Pick::Lowest)?,
        )
    };
    let k_mid = 1.0 / at(xm, 0.0)?.re;
    let k_above = 1.0 / at(xs, 0.0)?.re;
    let k_eff = 1.0 / (1.0 / k_h + 1.0 / k_mid);
    let value_at = |q: Option<f64>, at: &mut dyn FnMut(f64, f64) -> Result<c64, TrackError>| {
        q.map(|q| at(xm, q).map(|z| z.norm())).transpose()
    };
    let pp_value = value_at(pinned_pinned, &mut at)?;
    let tr_value = value_at(track_resonance, &mut at)?;
    Ok(Frequencies {
        simply_supported_hz: f_ss,
        pinned_pinned_hz: pinned_pinned,
        pinned_pinned_receptance: pp_value,
        above_sleeper_antiresonance_hz: antiresonance,
        track_resonance_hz: track_resonance,
        track_resonance_receptance: tr_value,
        p2_hz: p2,
        p2_above_sleeper_hz: p2_above,
        second_coupled_hz: second,
        hertz_stiffness: k_h,
        static_stiffness_mid_span: k_mid,
        static_stiffness_above_sleeper: k_above,
        p2_single_dof_hz: (k_eff / mu).sqrt() / (2.0 * PI),
        p2_below_range,
        track_resonance_below_range,
    })
}
