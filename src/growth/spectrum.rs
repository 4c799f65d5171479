//! The profile's arithmetic: the smoothing of the wear step, the DFT orders, the
//! one-third-octave band levels (dB re 1 um) and the growth rates (dB per 1e5 real passes).
//!
//! **Orders.** The DFT of the `n` samples, `Z_k = sum_i z_i e^{-2 pi i k i / n}`; order `k`
//! (`1 <= k < n / 2`) has the amplitude `A_k = 2 |Z_k| / n` and the wavelength `n dx / k`;
//! on a wheel it is the polygon order (harmonics per revolution). An open profile is taken
//! as one period of length `n dx` (no window).
//!
//! **Bands.** One-third-octave bands in wavelength with the centres `10^(j/10)` mm (the
//! preferred series: ..., 6.3, 8, 10, 12.5, 16, ... mm) and the edges `lambda_c 10^(+-1/20)`;
//! a band's level is `10 log10(sum A_k^2 / 2 / (1 um)^2)` over the orders whose wavelength
//! lies in `[lambda_lo, lambda_hi)`. Bands holding no order are left out.
//!
//! **Growth rate.** The least-squares slope of a level (dB) against the real passes
//! (`N_w` per simulated pass), times 1e5.

use rustfft::num_complex::Complex;

/// Mean.
pub fn mean(v: &[f64]) -> f64 {
    if v.is_empty() {
        0.0
    } else {
        v.iter().sum::<f64>() / v.len() as f64
    }
}

/// Root mean square about the mean.
pub fn rms(v: &[f64]) -> f64 {
    let m = mean(v);
    if v.is_empty() {
        return 0.0;
    }
    (v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / v.len() as f64).sqrt()
}

/// Samples of the moving average of width `width_m` at spacing `dx`: the odd count
/// `2 floor(width / (2 dx)) + 1` (1: no smoothing).
pub fn window_samples(dx: f64, width_m: f64) -> usize {
    if width_m.is_nan() || dx.is_nan() || width_m <= 0.0 || dx <= 0.0 {
        return 1;
    }
    // Saturating: an absurd width gives the widest window that can be counted, never an
    // overflow (the study refuses a window wider than its profile first:
    // `GrowthConfig::check_grid`).
    let half = (width_m / (2.0 * dx)).floor().min((usize::MAX / 4) as f64) as usize;
    2 * half + 1
}

/// The smoothing of the wear step (module docs of [`crate::growth`]): the centred moving
/// average of `v` over `m = window_samples(dx, width_m)` samples applied twice, i.e. a
/// triangular window spanning `2 m - 1` samples. Periodic profiles wrap round, open ones
/// average what lies inside the window near their ends.
pub fn smooth(v: &[f64], dx: f64, width_m: f64, periodic: bool) -> Vec<f64> {
    let m = window_samples(dx, width_m);
    let once = moving_average(v, m, periodic);
    moving_average(&once, m, periodic)
}

/// The centred moving average of `v` over the odd number `m` of samples.
pub fn moving_average(v: &[f64], m: usize, periodic: bool) -> Vec<f64> {
    let n = v.len();
    if m <= 1 || n == 0 {
        return v.to_vec();
    }
    let half = (m / 2) as isize;
    (0..n as isize)
        .map(|i| {
            let (mut s, mut c) = (0.0, 0usize);
            for j in i - half..=i + half {
                let k = if periodic {
                    j.rem_euclid(n as isize) as usize
                } else if j < 0 || j >= n as isize {
                    continue;
                } else {
                    j as usize
                };
                s += v[k];
                c += 1;
            }
            s / c as f64
        })
        .collect()
}

/// The gain of [`smooth`] on the periodic harmonic of order `k` of `n` samples with a
/// window of `m` samples: `(sin(pi m k / n) / (m sin(pi k / n)))^2`, never negative (a
/// single moving average's gain, the square root, turns negative beyond `k = n / m`, where
/// it would turn a wear that flattens the profile into one that roughens it).
pub fn smoothing_gain(m: usize, k: usize, n: usize) -> f64 {
    let x = std::f64::consts::PI * k as f64 / n as f64;
    if k % n == 0 {
        return 1.0;
    }
    let g = (m as f64 * x).sin() / (m as f64 * x.sin());
    g * g
}

/// The ideal low-pass of the wear step at the wavelength `cutoff_m` (m; 0: none): the DFT
/// components of `v` whose wavelength `n dx / k` is shorter than the cutoff removed, the
/// rest kept exactly (an open profile is taken as one period of `n dx`).
pub fn low_pass(v: &[f64], dx: f64, cutoff_m: f64) -> Vec<f64> {
    let n = v.len();
    if cutoff_m.is_nan() || cutoff_m <= 0.0 || n < 3 {
        return v.to_vec();
    }
    let length = n as f64 * dx;
    let mut z = dft(v);
    for k in 1..n {
        let order = k.min(n - k);
        if length / (order as f64) < cutoff_m {
            z[k] = Complex::new(0.0, 0.0);
        }
    }
    let mut planner = rustfft::FftPlanner::<f64>::new();
    planner.plan_fft_inverse(n).process(&mut z);
    z.iter().map(|c| c.re / n as f64).collect()
}

/// The DFT `Z_k` of `v`, `k = 0..n`.
pub fn dft(v: &[f64]) -> Vec<Complex<f64>> {
    let mut buf: Vec<Complex<f64>> = v.iter().map(|&x| Complex::new(x, 0.0)).collect();
    if buf.is_empty() {
        return buf;
    }
    let mut planner = rustfft::FftPlanner::<f64>::new();
    planner.plan_fft_forward(buf.len()).process(&mut buf);
    buf
}

/// Amplitudes `A_k = 2 |Z_k| / n` of the orders `k = 1 ..= max_order(n)` (index `k - 1`).
pub fn order_amplitudes(v: &[f64]) -> Vec<f64> {
    let n = v.len();
    let z = dft(v);
    (1..=max_order(n))
        .map(|k| 2.0 * z[k].norm() / n as f64)
        .collect()
}

/// The highest order below the Nyquist one: `ceil(n / 2) - 1`.
pub fn max_order(n: usize) -> usize {
    n.div_ceil(2).saturating_sub(1)
}

/// A one-third-octave band in wavelength.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Band {
    /// Centre wavelength, m.
    pub centre: f64,
    /// Lower edge, m.
    pub lo: f64,
    /// Upper edge, m.
    pub hi: f64,
    /// First order in the band.
    pub k_first: usize,
    /// Last order in the band.
    pub k_last: usize,
}

/// The bands holding at least one order of a profile of `n` samples over the period
/// `length` (m), longest wavelength first (module docs).
pub fn bands(n: usize, length: f64) -> Vec<Band> {
    let kmax = max_order(n);
    if kmax == 0 || length.is_nan() || length <= 0.0 {
        return Vec::new();
    }
    let shortest = length / kmax as f64;
    let j_hi = (10.0 * (length * 1e3).log10()).ceil() as i64 + 1;
    let j_lo = (10.0 * (shortest * 1e3).log10()).floor() as i64 - 1;
    let mut out = Vec::new();
    for j in (j_lo..=j_hi).rev() {
        let centre = 10f64.powf(j as f64 / 10.0) * 1e-3;
        let (lo, hi) = (centre * 10f64.powf(-0.05), centre * 10f64.powf(0.05));
        // Orders with lo <= length / k < hi: length / hi < k <= length / lo.
        let k_first = ((length / hi).floor() as usize + 1).max(1);
        let k_last = ((length / lo).floor() as usize).min(kmax);
        if k_first <= k_last {
            out.push(Band {
                centre,
                lo,
                hi,
                k_first,
                k_last,
            });
        }
    }
    out
}

/// The level of each band, dB re 1 um, from the order amplitudes (index `k - 1`).
pub fn band_levels(amplitudes: &[f64], bands: &[Band]) -> Vec<f64> {
    bands
        .iter()
        .map(|b| {
            let ms: f64 = (b.k_first..=b.k_last)
                .map(|k| 0.5 * amplitudes[k - 1] * amplitudes[k - 1])
                .sum();
            level_db(ms.sqrt())
        })
        .collect()
}

/// `20 log10(rms / 1 um)`.
pub fn level_db(rms_m: f64) -> f64 {
    20.0 * (rms_m / 1e-6).log10()
}

/// The least-squares slope of `y` against `x` (NaN for fewer than two finite points).
pub fn slope(x: &[f64], y: &[f64]) -> f64 {
    let pts: Vec<(f64, f64)> = x
        .iter()
        .zip(y)
        .filter(|(a, b)| a.is_finite() && b.is_finite())
        .map(|(a, b)| (*a, *b))
        .collect();
    if pts.len() < 2 {
        return f64::NAN;
    }
    let n = pts.len() as f64;
    let mx = pts.iter().map(|p| p.0).sum::<f64>() / n;
    let my = pts.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx) * (p.0 - mx)).sum();
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    if sxx == 0.0 {
        f64::NAN
    } else {
        sxy / sxx
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// The moving average multiplies each periodic harmonic by its closed-form gain.
    #[test]
    fn smoothing_gain_is_the_closed_form() {
        let n = 256;
        let dx = 1e-3;
        for width in [5e-3, 12e-3] {
            let m = window_samples(dx, width);
            assert_eq!(m % 2, 1);
            for k in [1usize, 3, 10, 21, 40, 90] {
                let v: Vec<f64> = (0..n)
                    .map(|i| (2.0 * PI * (k * i) as f64 / n as f64 + 0.3).cos())
                    .collect();
                let s = smooth(&v, dx, width, true);
                let g = smoothing_gain(m, k, n);
                for i in 0..n {
                    let want = g * v[i];
                    assert!((s[i] - want).abs() < 1e-12, "k {k} m {m} i {i}");
                }
            }
        }
    }

    /// A harmonic's order amplitude and its band's level.
    #[test]
    fn orders_and_bands_of_a_harmonic() {
        let n = 288;
        let length = 2.0 * PI * 0.1;
        let (k, a) = (17usize, 3e-6);
        let v: Vec<f64> = (0..n)
            .map(|i| a * (2.0 * PI * (k * i) as f64 / n as f64).sin())
            .collect();
        let amp = order_amplitudes(&v);
        assert!((amp[k - 1] - a).abs() < 1e-15);
        assert!(amp
            .iter()
            .enumerate()
            .all(|(i, x)| i == k - 1 || *x < 1e-18));
        let b = bands(n, length);
        // Every order in exactly one band.
        let covered: usize = b.iter().map(|b| b.k_last + 1 - b.k_first).sum();
        assert_eq!(covered, max_order(n));
        let levels = band_levels(&amp, &b);
        let i = b
            .iter()
            .position(|b| (b.k_first..=b.k_last).contains(&k))
            .unwrap();
        assert!((levels[i] - level_db(a / 2f64.sqrt())).abs() < 1e-9);
        let lam = length / k as f64;
        assert!(b[i].lo <= lam && lam < b[i].hi);
    }

    /// The low-pass keeps the orders at or above the cutoff wavelength and removes the
    /// others.
    #[test]
    fn low_pass_cuts_at_the_wavelength() {
        let n = 100;
        let dx = 1e-3; // period 0.1 m: order k has the wavelength 0.1 / k
        let wave = |k: usize, i: usize| (2.0 * PI * (k * i) as f64 / n as f64 + 0.4).sin();
        let v: Vec<f64> = (0..n)
            .map(|i| 0.3 + wave(4, i) + 0.5 * wave(30, i))
            .collect();
        let f = low_pass(&v, dx, 0.01); // keeps k <= 10
        for i in 0..n {
            assert!((f[i] - 0.3 - wave(4, i)).abs() < 1e-12);
        }
    }

    #[test]
    fn slope_of_a_line() {
        let x = [0.0, 1.0, 2.0, 3.0];
        let y = [1.0, 3.0, 5.0, 7.0];
        assert!((slope(&x, &y) - 2.0).abs() < 1e-12);
        assert!(slope(&x[..1], &y[..1]).is_nan());
    }
}
