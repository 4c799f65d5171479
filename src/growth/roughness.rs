//! The initial roughness of a study on its grid.
//!
//! - **Harmonic**: `A sin(2 pi (x - x0) / lambda)`; on a periodic profile the wavelength is
//!   rounded to the nearest whole order `k = round(L / lambda)` (a rim closes on itself).
//! - **CSV** (`x_m,z_m`, one header line): read through
//!   [`crate::contact::profile::Profile::from_points`] (resampled at the points' smallest
//!   spacing, cubic Hermite between) and sampled at the grid's abscissae; zero outside.
//! - **Spectrum** (band levels, dB re 1 um, with a seed): on a periodic profile of length
//!   `L` the orders `k` whose wavelength `L / k` lies in a band (edges `lambda_c 10^(+-1/20)`)
//!   share the band's mean square equally, each with a random phase (SplitMix64 from the
//!   seed), so the band's level is the one given exactly; a band holding no order is left
//!   out. On an open profile: [`crate::contact::profile::Profile::from_spectrum`] (8
//!   harmonics a band, faded at the ends), sampled at the grid.
//! - **EN ISO 3095's limit spectrum** ([`ISO3095_LIMIT`]) is a spectrum with those bands.

use super::Roughness;
use crate::contact::profile::Profile;
use std::f64::consts::PI;

/// The rail roughness limit spectrum of EN ISO 3095 (one-third-octave band centre in cm,
/// level in dB re 1 um), as the standard's limit curve is commonly reproduced: +17.1 dB at
/// 25 cm falling 2 dB a band to 2.5 cm and 0.6 dB a band below, down to 0.3 cm. Transcribed
/// from the literature that quotes it, not from the standard's own table (which the
/// search tools of this work could not reach): check it against your copy before a
/// compliance use; `growth.offset` shifts it.
pub const ISO3095_LIMIT: [(f64, f64); 20] = [
    (25.0, 17.1),
    (20.0, 15.1),
    (16.0, 13.1),
    (12.5, 11.1),
    (10.0, 9.1),
    (8.0, 7.1),
    (6.3, 5.1),
    (5.0, 3.1),
    (4.0, 1.1),
    (3.15, -0.9),
    (2.5, -2.9),
    (2.0, -3.5),
    (1.6, -4.1),
    (1.25, -4.7),
    (1.0, -5.3),
    (0.8, -5.9),
    (0.63, -6.5),
    (0.5, -7.1),
    (0.4, -7.7),
    (0.315, -8.3),
];

pub use crate::contact::profile::SplitMix;

/// The roughness on the grid `(x0, dx, n, periodic)`, m.
///
/// # Errors
/// A one-line message (a CSV that cannot be read, a spectrum that fits no band).
pub fn realise(
    r: &Roughness,
    (x0, dx, n, periodic): (f64, f64, usize, bool),
) -> Result<Vec<f64>, String> {
    let length = if periodic {
        n as f64 * dx
    } else {
        (n as f64 - 1.0) * dx
    };
    let x = |i: usize| x0 + i as f64 * dx;
    match r {
        Roughness::None => Ok(vec![0.0; n]),
        Roughness::Harmonic {
            amplitude,
            wavelength,
        } => {
            let lambda = if periodic {
                let k = (length / wavelength).round().max(1.0);
                length / k
            } else {
                *wavelength
            };
            Ok((0..n)
                .map(|i| amplitude * (2.0 * PI * (x(i) - x0) / lambda).sin())
                .collect())
        }
        Roughness::Csv { path } => {
            let text = std::fs::read_to_string(path)
                .map_err(|e| format!("growth.file = \"{}\": {e}", path.display()))?;
            let mut pts = Vec::new();
            for (l, line) in text.lines().enumerate() {
                if line.trim().is_empty() {
                    continue;
                }
                let mut it = crate::output::csv::number_cells(line).map(|s| s.parse::<f64>());
                match (it.next(), it.next()) {
                    (Some(Ok(a)), Some(Ok(b))) => pts.push((a, b)),
                    // The first line is a header when it is not two numbers (it was always
                    // dropped: a file without one lost its first point).
                    _ if l == 0 => continue,
                    _ => {
                        return Err(format!(
                            "growth.file = \"{}\", line {}: expected two numbers x_m,z_m",
                            path.display(),
                            l + 1
                        ))
                    }
                }
            }
            let p = Profile::from_points(&pts)
                .map_err(|e| format!("growth.file = \"{}\": {e}", path.display()))?;
            Ok((0..n).map(|i| p.at(x(i)).0).collect())
        }
        Roughness::Spectrum { bands, seed } => {
            let mut rng = SplitMix(*seed);
            if periodic {
                let mut z = vec![0.0; n];
                let kmax = super::spectrum::max_order(n);
                let mut used = 0;
                for &(centre, db) in bands {
                    let (lo, hi) = (centre * 10f64.powf(-0.05), centre * 10f64.powf(0.05));
                    let k_first = ((length / hi).floor() as usize + 1).max(1);
                    let k_last = ((length / lo).floor() as usize).min(kmax);
                    if k_first > k_last {
                        continue;
                    }
                    used += 1;
                    let m = (k_last + 1 - k_first) as f64;
                    let rms = 1e-6 * 10f64.powf(db / 20.0);
                    let a = rms * (2.0 / m).sqrt();
                    for k in k_first..=k_last {
                        let ph = 2.0 * PI * rng.next_f64();
                        for (i, zi) in z.iter_mut().enumerate() {
                            *zi += a * (2.0 * PI * (k * i) as f64 / n as f64 + ph).cos();
                        }
                    }
                }
                if used == 0 {
                    return Err(format!(
                        "growth: no band of the roughness spectrum holds a whole order of the profile (period {length:.4e} m, {n} samples)"
                    ));
                }
                Ok(z)
            } else {
                let p = Profile::from_spectrum(bands, 8, (x0, x0 + length), *seed)
                    .map_err(|e| format!("growth: {e}"))?;
                Ok((0..n).map(|i| p.at(x(i)).0).collect())
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::growth::spectrum::{band_levels, bands, order_amplitudes};

    /// A periodic spectrum's band levels are the ones asked for.
    #[test]
    fn periodic_spectrum_has_the_levels_asked_for() {
        let n = 288;
        let dx = 2.0 * PI * 0.1 / n as f64;
        let c = |j: f64| 10f64.powf(j / 10.0) * 1e-3;
        let want = [(c(20.0), -10.0), (c(17.0), -14.0), (c(13.0), -20.0)];
        let z = realise(
            &Roughness::Spectrum {
                bands: want.to_vec(),
                seed: 7,
            },
            (0.0, dx, n, true),
        )
        .unwrap();
        let b = bands(n, n as f64 * dx);
        let lv = band_levels(&order_amplitudes(&z), &b);
        for (c, db) in want {
            let i = b
                .iter()
                .position(|b| (b.centre / c - 1.0).abs() < 0.03)
                .unwrap();
            assert!((lv[i] - db).abs() < 1e-9, "{c}: {} against {db}", lv[i]);
        }
    }
}
