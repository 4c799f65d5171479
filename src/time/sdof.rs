//! The one-degree-of-freedom scheme of the paper, Eqs. (9), (10) and (24), and its
//! amplification matrix.
//!
//! For `m v' + k x = 0` with `Omega = omega h`, `omega^2 = k/m`, one step reads
//!
//! $$v_1 = \frac{1 - \Omega^2(\alpha - \alpha^2/2)}{1 + \alpha^2\Omega^2/2} v_0
//!        - \frac{\omega\\,\Omega}{1 + \alpha^2\Omega^2/2} x_0 \qquad \text{(Eq. 9)}$$
//! $$x_1 = x_0 + h[(1-\beta) v_0 + \beta v_1] \qquad \text{(Eq. 10)}.$$
//!
//! In the scaled state `z = (omega x, v)` the step is `z1 = G(Omega) z0` with `G` depending
//! on `Omega`, `alpha` and `beta` only. Its eigenvalues `lambda = rho e^{\pm i \bar\omega h}`
//! give the spectral radius `rho`, the algorithmic damping ratio
//! `xi = -ln(rho) / (\bar\omega h)` and the relative period error
//! `(T_num - T) / T = Omega / (\bar\omega h) - 1`.

use super::params::{beta, Coriolis, SpaceTimeParams};
use serde::Serialize;

/// One step of Eqs. (9)-(10) for `m v' + k x = f` (f constant over the step, taken at
/// `t0 + alpha h`). Returns `(x1, v1)`.
pub fn step(m: f64, k: f64, f: f64, p: SpaceTimeParams, x0: f64, v0: f64) -> (f64, f64) {
    let (alpha, gamma, h) = (p.alpha, p.gamma, p.h);
    let d = 1.0 + k * alpha * alpha * h * h / (2.0 * m);
    let num = 1.0 - k * h * h / (2.0 * m) * (1.0 - (1.0 - alpha).powi(2));
    let v1 = num / d * v0 - k / m * h / d * x0 + h * f / (m * d);
    let b = beta(alpha, gamma);
    let x1 = x0 + h * ((1.0 - b) * v0 + b * v1);
    (x1, v1)
}

/// The amplification matrix `G(Omega)` acting on `(omega x, v)`.
pub fn amplification_matrix(alpha: f64, gamma: f64, omega_h: f64) -> [[f64; 2]; 2] {
    let w = omega_h;
    let b = beta(alpha, gamma);
    let d = 1.0 + alpha * alpha * w * w / 2.0;
    let a_vv = (1.0 - w * w * (alpha - alpha * alpha / 2.0)) / d;
    let a_vx = -w / d;
    [
        [1.0 + w * b * a_vx, w * ((1.0 - b) + b * a_vv)],
        [a_vx, a_vv],
    ]
}

/// Spectral properties of the scheme at one `omega h`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Amplification {
    /// `omega h`.
    pub omega_h: f64,
    /// Spectral radius of `G`.
    pub spectral_radius: f64,
    /// Algorithmic damping ratio `xi` (NaN when the eigenvalues are real: no oscillation).
    pub damping_ratio: f64,
    /// Relative period error `(T_num - T)/T` (NaN when the eigenvalues are real).
    pub period_error: f64,
}

/// Eigen-analysis of `G(omega h)`.
pub fn amplification(alpha: f64, gamma: f64, omega_h: f64) -> Amplification {
    let g = amplification_matrix(alpha, gamma, omega_h);
    let tr = g[0][0] + g[1][1];
    let det = g[0][0] * g[1][1] - g[0][1] * g[1][0];
    let disc = tr * tr / 4.0 - det;
    if disc < 0.0 {
        // Complex pair: |lambda|^2 = det.
        let rho = det.sqrt();
        let phase = (-disc).sqrt().atan2(tr / 2.0);
        Amplification {
            omega_h,
            spectral_radius: rho,
            damping_ratio: -rho.ln() / phase,
            period_error: omega_h / phase - 1.0,
        }
    } else {
        let s = disc.sqrt();
        let l1 = (tr / 2.0 + s).abs();
        let l2 = (tr / 2.0 - s).abs();
        Amplification {
            omega_h,
            spectral_radius: l1.max(l2),
            damping_ratio: f64::NAN,
            period_error: f64::NAN,
        }
    }
}

/// Summary of the stability of a parameter pair.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StabilityReport {
    /// `alpha`.
    pub alpha: f64,
    /// `gamma`.
    pub gamma: f64,
    /// `beta` from Eq. (24).
    pub beta: f64,
    /// High-frequency limit of the spectral radius (`omega h -> infinity`).
    pub rho_inf: f64,
    /// True when the spectral radius stays `<= 1` for every `omega h` checked (1e-6..1e8).
    pub unconditionally_stable: bool,
    /// Smallest `omega h` with spectral radius above 1 (None when unconditionally stable).
    pub stability_limit_omega_h: Option<f64>,
    /// The table on the log ladder of `omega h` from 1e-3 to 1e4.
    pub table: Vec<Amplification>,
}

/// Tolerance on the spectral radius above 1 that still counts as stable (round-off).
pub const STABILITY_TOL: f64 = 1e-9;

/// Full analysis: the table on a log ladder (`per_decade` points per decade from 1e-3 to
/// 1e4), `rho_inf` and the stability limit (found on a fine ladder, refined by bisection).
pub fn analyse(alpha: f64, gamma: f64, per_decade: usize) -> StabilityReport {
    let ladder = |lo: f64, hi: f64, per: usize| -> Vec<f64> {
        let n = ((hi.log10() - lo.log10()) * per as f64).round() as usize;
        (0..=n)
            .map(|i| 10f64.powf(lo.log10() + i as f64 / per as f64))
            .collect()
    };
    let table: Vec<Amplification> = ladder(1e-3, 1e4, per_decade.max(1))
        .into_iter()
        .map(|w| amplification(alpha, gamma, w))
        .collect();
    let rho_inf = amplification(alpha, gamma, 1e12).spectral_radius;
    let fine = ladder(1e-6, 1e8, 200);
    let unstable = |w: f64| amplification(alpha, gamma, w).spectral_radius > 1.0 + STABILITY_TOL;
    let mut limit = None;
    for pair in fine.windows(2) {
        if unstable(pair[1]) {
            let (mut lo, mut hi) = (pair[0], pair[1]);
            if unstable(lo) {
                limit = Some(lo);
                break;
            }
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                if unstable(mid) {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            limit = Some(hi);
            break;
        }
    }
    StabilityReport {
        alpha,
        gamma,
        beta: beta(alpha, gamma),
        rho_inf,
        unconditionally_stable: limit.is_none(),
        stability_limit_omega_h: limit,
        table,
    }
}

/// The step's amplification on the gyroscopic oscillator of a rotating frame: a unit mass in
/// the plane, `v' + 2 Omega J v + (omega0^2 - Omega^2) u = 0` with `J` the quarter turn
/// (the Coriolis term skew, the spin softening in the stiffness), one mode of the spinning
/// wheel seen from its frame. Arguments are `omega0 h` and `Omega h`.
///
/// The state is `(u, v, a)` (six real entries; `a = (v1 - v0)/h`, which only
/// [`Coriolis::Extrapolated`] reads: there the Coriolis force of the step is taken at
/// `v0 + h a0`). Returns the six eigenvalues of the one-step map as `(re, im)`, largest
/// modulus first; with [`Coriolis::Implicit`] two of them are zero (the `a` columns).
pub fn gyroscopic_eigenvalues(
    alpha: f64,
    gamma: f64,
    omega0_h: f64,
    spin_h: f64,
    coriolis: Coriolis,
) -> Vec<(f64, f64)> {
    let b = beta(alpha, gamma);
    let k = omega0_h * omega0_h - spin_h * spin_h;
    let c = 2.0 * spin_h;
    // `J (x, y) = (-y, x)`.
    let j = |x: [f64; 2]| [-x[1], x[0]];
    let step = |s: [f64; 6]| -> [f64; 6] {
        let (u0, v0, a0) = ([s[0], s[1]], [s[2], s[3]], [s[4], s[5]]);
        let diag = 1.0 + 0.5 * alpha * alpha * k;
        let bv = 1.0 - (alpha - 0.5 * alpha * alpha) * k;
        let mut rhs = [0.0; 2];
        for d in 0..2 {
            rhs[d] = bv * v0[d] - k * u0[d];
        }
        let v1 = match coriolis {
            Coriolis::Implicit => {
                // (diag I + alpha c J) v1 = rhs - (1 - alpha) c J v0.
                let jv = j(v0);
                for d in 0..2 {
                    rhs[d] -= (1.0 - alpha) * c * jv[d];
                }
                let off = alpha * c;
                let det = diag * diag + off * off;
                [
                    (diag * rhs[0] + off * rhs[1]) / det,
                    (diag * rhs[1] - off * rhs[0]) / det,
                ]
            }
            Coriolis::Extrapolated => {
                // diag v1 = rhs - c J (v0 + alpha a0).
                let jw = j([v0[0] + alpha * a0[0], v0[1] + alpha * a0[1]]);
                [(rhs[0] - c * jw[0]) / diag, (rhs[1] - c * jw[1]) / diag]
            }
        };
        let mut out = [0.0; 6];
        for d in 0..2 {
            out[d] = u0[d] + (1.0 - b) * v0[d] + b * v1[d];
            out[2 + d] = v1[d];
            out[4 + d] = v1[d] - v0[d];
        }
        out
    };
    let g = faer::Mat::<f64>::from_fn(6, 6, |i, col| {
        let mut e = [0.0; 6];
        e[col] = 1.0;
        step(e)[i]
    });
    let mut ev: Vec<(f64, f64)> = g
        .eigenvalues()
        .map(|v| v.iter().map(|z| (z.re, z.im)).collect())
        .unwrap_or_default();
    ev.sort_by(|p, q| q.0.hypot(q.1).total_cmp(&p.0.hypot(p.1)));
    ev
}

/// The two treatments of the Coriolis term compared at one `omega0 h` (a row of
/// [`gyroscopic_table`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct GyroscopicRow {
    /// `omega0 h`.
    pub omega0_h: f64,
    /// Spectral radius with the Coriolis term in the step's matrix (the exact scheme).
    pub rho_implicit: f64,
    /// Spectral radius with it on the right-hand side, extrapolated.
    pub rho_extrapolated: f64,
    /// The largest distance from an exact eigenvalue to the nearest extrapolated one (the
    /// four physical ones).
    pub eigenvalue_gap: f64,
    /// Modulus of the largest parasitic eigenvalue of the extrapolation.
    pub parasitic: f64,
}

/// [`GyroscopicRow`]s for the spin `Omega h` on a log ladder of `omega0 h` from 3 times the
/// spin to 1e4 (`per_decade` points a decade).
pub fn gyroscopic_table(
    alpha: f64,
    gamma: f64,
    spin_h: f64,
    per_decade: usize,
) -> Vec<GyroscopicRow> {
    let lo = 3.0 * spin_h;
    let decades = (1e4 / lo).log10().max(0.0);
    let count = (decades * per_decade.max(1) as f64).round() as usize;
    let r = |z: &(f64, f64)| z.0.hypot(z.1);
    (0..=count)
        .map(|i| {
            let w = lo * 10f64.powf(i as f64 / per_decade.max(1) as f64);
            let ex = gyroscopic_eigenvalues(alpha, gamma, w, spin_h, Coriolis::Extrapolated);
            let im = gyroscopic_eigenvalues(alpha, gamma, w, spin_h, Coriolis::Implicit);
            let gap = im[..4]
                .iter()
                .map(|z| {
                    ex[..4]
                        .iter()
                        .map(|e| (e.0 - z.0).hypot(e.1 - z.1))
                        .fold(f64::INFINITY, f64::min)
                })
                .fold(0.0, f64::max);
            GyroscopicRow {
                omega0_h: w,
                rho_implicit: r(&im[0]),
                rho_extrapolated: r(&ex[0]),
                eigenvalue_gap: gap,
                parasitic: r(&ex[4]),
            }
        })
        .collect()
}

/// Spectral radius of [`gyroscopic_eigenvalues`] (NaN if the eigen-solver fails).
pub fn gyroscopic_spectral_radius(
    alpha: f64,
    gamma: f64,
    omega0_h: f64,
    spin_h: f64,
    coriolis: Coriolis,
) -> f64 {
    gyroscopic_eigenvalues(alpha, gamma, omega0_h, spin_h, coriolis)
        .first()
        .map_or(f64::NAN, |z| z.0.hypot(z.1))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The Coriolis term on the right-hand side at the extrapolated velocity
    /// ([`Coriolis::Extrapolated`]) against the exact scheme on the spinning oscillator, for
    /// the spins of the wheel's runs (`Omega h` = 6e-4: 300 rad/s at 2 us; up to 100 times
    /// that) and every mode from 3 times the spin to the high-frequency limit: its spectral
    /// radius no larger than the exact scheme's (to 1e-9), both below 1 from 5 times the spin
    /// on, its four physical eigenvalues within `2 (Omega h) min((omega0 h)^2, 1)` of the
    /// exact ones (measured: 0.4 of that at low `omega0 h`) and its two parasitic ones
    /// (the extrapolation's memory) below `2 Omega h` in modulus (measured: 1.6).
    #[test]
    fn extrapolated_coriolis_keeps_the_exact_schemes_stability() {
        let (a, g) = (0.8, 0.2);
        for spin_h in [6e-4, 6e-3, 6e-2] {
            let table = gyroscopic_table(a, g, spin_h, 20);
            assert!(table.len() >= 90, "{} rows", table.len());
            for row in table {
                let (w, ri, rx) = (row.omega0_h, row.rho_implicit, row.rho_extrapolated);
                let at = format!("spin h {spin_h}, omega0 h {w:.3e}");
                assert!(rx <= ri.max(1.0) + 1e-9, "{at}: rho {rx} against {ri}");
                if w >= 5.0 * spin_h {
                    assert!(rx <= 1.0 + 1e-9, "{at}: rho {rx}");
                    assert!(ri <= 1.0 + 1e-9, "{at}: exact rho {ri}");
                }
                let bound = 2.0 * spin_h * (w * w).min(1.0);
                assert!(
                    row.eigenvalue_gap <= bound,
                    "{at}: eigenvalues {:e} apart, bound {bound:e}",
                    row.eigenvalue_gap
                );
                assert!(
                    row.parasitic < 2.0 * spin_h,
                    "{at}: parasitic {}",
                    row.parasitic
                );
            }
            // The exact scheme ignores `a`: two zero eigenvalues.
            let im = gyroscopic_eigenvalues(a, g, 0.3, spin_h, Coriolis::Implicit);
            assert!(im[4].0.hypot(im[4].1) < 1e-12);
        }
    }

    fn sp(alpha: f64, gamma: f64, h: f64) -> SpaceTimeParams {
        SpaceTimeParams { alpha, gamma, h }
    }

    /// Eq. (9) written out literally as printed in the paper.
    fn eq9(m: f64, k: f64, a: f64, h: f64, x0: f64, v0: f64) -> f64 {
        (1.0 - k * h * h / (2.0 * m) * (1.0 - (1.0 - a) * (1.0 - a)))
            / (1.0 + k * a * a * h * h / (2.0 * m))
            * v0
            - k / m * h / (1.0 + k * a * a * h * h / (2.0 * m)) * x0
    }

    #[test]
    fn step_is_eq_9_and_eq_10() {
        let (m, k, a, g, h) = (2.0, 50.0, 0.8, 0.2, 0.05);
        let (x0, v0) = (0.3, -1.1);
        let (x1, v1) = step(m, k, 0.0, sp(a, g, h), x0, v0);
        let v1_ref = eq9(m, k, a, h, x0, v0);
        assert!((v1 - v1_ref).abs() < 1e-14);
        let b = 1.0 - a / (1.0 + g);
        assert!((x1 - (x0 + h * ((1.0 - b) * v0 + b * v1_ref))).abs() < 1e-14);
    }

    #[test]
    fn amplification_matrix_matches_the_step() {
        let (m, k, a, g, h): (f64, f64, f64, f64, f64) = (1.5, 12.0, 0.75, 0.1, 0.3);
        let w = (k / m).sqrt();
        let (x0, v0) = (0.7, 0.2);
        let (x1, v1) = step(m, k, 0.0, sp(a, g, h), x0, v0);
        let gm = amplification_matrix(a, g, w * h);
        let z1 = [
            gm[0][0] * w * x0 + gm[0][1] * v0,
            gm[1][0] * w * x0 + gm[1][1] * v0,
        ];
        assert!((z1[0] - w * x1).abs() < 1e-13);
        assert!((z1[1] - v1).abs() < 1e-13);
    }

    #[test]
    fn gamma_zero_conserves_amplitude_for_alpha_in_the_stable_range() {
        for a in [std::f64::consts::FRAC_1_SQRT_2 + 1e-12, 0.75, 0.8, 0.9, 1.0] {
            for i in 0..=70 {
                let w = 10f64.powf(-3.0 + i as f64 * 0.1);
                let r = amplification(a, 0.0, w).spectral_radius;
                assert!((r - 1.0).abs() < 1e-12, "alpha {a} omega h {w}: rho {r}");
            }
        }
    }

    #[test]
    fn alpha_below_sqrt2_over_2_is_only_conditionally_stable() {
        let rep = analyse(0.6, 0.0, 10);
        assert!(!rep.unconditionally_stable);
        let lim = rep.stability_limit_omega_h.unwrap();
        assert!(amplification(0.6, 0.0, lim * 0.999).spectral_radius <= 1.0 + STABILITY_TOL);
        assert!(amplification(0.6, 0.0, lim * 1.001).spectral_radius > 1.0 + STABILITY_TOL);
        assert!(analyse(0.8, 0.0, 10).unconditionally_stable);
    }

    #[test]
    fn gamma_damps_high_frequencies() {
        let r = analyse(0.9, 0.5, 10);
        assert!(r.unconditionally_stable);
        assert!(r.rho_inf < 0.95);
        // Low frequencies are barely touched.
        assert!(amplification(0.9, 0.5, 1e-3).spectral_radius > 0.9999);
    }

    /// Period of the discrete oscillation measured from the upward zero crossings of `x`
    /// (linear interpolation) over `cycles` periods of `x'' + x = 0`.
    fn measured_period(a: f64, g: f64, h: f64, cycles: f64) -> f64 {
        let n = (cycles * 2.0 * std::f64::consts::PI / h) as usize;
        let (mut x, mut v) = (0.0, 1.0);
        let mut crossings = Vec::new();
        for i in 0..n {
            let (x1, v1) = step(1.0, 1.0, 0.0, sp(a, g, h), x, v);
            if x < 0.0 && x1 >= 0.0 {
                crossings.push(h * (i as f64 + x / (x - x1)));
            }
            (x, v) = (x1, v1);
        }
        (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64
    }

    #[test]
    fn period_error_converges_at_second_order() {
        let t = 2.0 * std::f64::consts::PI;
        for (a, g) in [(0.8, 0.0), (0.75, 0.0), (0.8, 0.2)] {
            let errs: Vec<f64> = [0.2, 0.1, 0.05, 0.025]
                .iter()
                .map(|&h| (measured_period(a, g, h, 40.0) - t).abs() / t)
                .collect();
            for w in errs.windows(2) {
                let order = (w[0] / w[1]).log2();
                assert!(
                    (order - 2.0).abs() < 0.1,
                    "alpha {a} gamma {g}: order {order} ({errs:?})"
                );
            }
            // The same from the amplification matrix.
            let pe: Vec<f64> = [0.1, 0.05]
                .iter()
                .map(|&w| amplification(a, g, w).period_error)
                .collect();
            assert!(((pe[0] / pe[1]).log2() - 2.0).abs() < 0.01);
        }
    }

    #[test]
    fn state_error_is_second_order_at_whole_periods_first_order_in_between() {
        // x'' + x = 0 from (1, 0). beta != 1/2 distorts the discrete orbit by O(h), an
        // oscillating error that vanishes at whole periods, where only the O(h^2) phase
        // drift is left, growing linearly with the number of periods.
        let err_at = |h: f64, t_target: f64| {
            let n = (t_target / h).round() as usize;
            let t = n as f64 * h;
            let (mut x, mut v) = (1.0, 0.0);
            for _ in 0..n {
                (x, v) = step(1.0, 1.0, 0.0, sp(0.8, 0.0, h), x, v);
            }
            ((x - t.cos()).powi(2) + (v + t.sin()).powi(2)).sqrt()
        };
        let tp = 2.0 * std::f64::consts::PI;
        let whole: Vec<f64> = [0.02, 0.01, 0.005].iter().map(|&h| err_at(h, tp)).collect();
        for w in whole.windows(2) {
            let order = (w[0] / w[1]).log2();
            assert!((order - 2.0).abs() < 0.1, "whole period: order {order}");
        }
        let ratio = err_at(0.01, 10.0 * tp) / err_at(0.01, tp);
        assert!(
            ratio > 9.0 && ratio < 11.0,
            "phase drift not linear: {ratio}"
        );
        let between: Vec<f64> = [0.02, 0.01, 0.005]
            .iter()
            .map(|&h| err_at(h, 2.0))
            .collect();
        for w in between.windows(2) {
            let order = (w[0] / w[1]).log2();
            assert!((order - 1.0).abs() < 0.15, "t = 2: order {order}");
        }
        // beta = 1/2 (alpha = 1/2, gamma = 0) is second order pointwise.
        let e2 = |h: f64| {
            let n = (2.0 / h).round() as usize;
            let (mut x, mut v) = (1.0, 0.0);
            for _ in 0..n {
                (x, v) = step(1.0, 1.0, 0.0, sp(0.5, 0.0, h), x, v);
            }
            ((x - 2f64.cos()).powi(2) + (v + 2f64.sin()).powi(2)).sqrt()
        };
        assert!(((e2(0.01) / e2(0.005)).log2() - 2.0).abs() < 0.1);
    }
}
