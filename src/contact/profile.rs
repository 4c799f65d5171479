//! A surface irregularity: the height `r(X)` (m) a master surface carries above its
//! geometric line, over the abscissa `X` of the master's frame (a rail's roughness, a
//! corrugation, a dipped weld). It enters the gap of every searched pair on that surface
//! ([`super::search::Search::with_profile`]): the surface point under a node is raised by
//! `r(X)` and its normal turned by the slope `r'(X)`,
//! $$x_s = \big(X,\ Y + w(X) + r(X)\big),\qquad
//!   n \propto \big(-(w\' + r\'),\ 1\big)$$
//! so that a node sliding along the surface at the relative speed `V` sees the normal
//! velocity `V r'(X)` through the frozen row's drift term (the search's module docs), as it
//! sees the beam's own slope.
//!
//! **Representation.** Heights at equally spaced abscissae `X_0 + i dX`, interpolated by
//! cubic Hermite pieces whose slopes are the central differences (Catmull-Rom): `r` and `r'`
//! continuous, zero outside the samples. Three ways in:
//! - [`Profile::harmonic`]: `A sin(2 pi (X - X_0) / lambda)` over a stretch, faded in and out
//!   over `fade` wavelengths by a raised cosine (no step in the slope where it starts);
//! - [`Profile::from_points`]: measured `(X, r)` pairs (a CSV), resampled at their smallest
//!   spacing;
//! - [`Profile::from_spectrum`]: a random profile whose one-third-octave band levels (dB re
//!   1 um, against the band's centre wavelength) are given: in each band `per_band` harmonics
//!   at log-spaced wavelengths with random phases (a seeded generator), each carrying an equal
//!   share of the band's mean square, so the band's RMS is `1e-6 10^(L / 20)` m.
//!
//! A sampled harmonic with 64 samples a wavelength is within 3e-5 of its amplitude of the
//! sine (the interpolation's error, `tests`).

/// Errors of building a profile.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ProfileError {
    /// A value out of its range.
    #[error("irregularity: {what} = {value}: {allowed}")]
    Invalid {
        /// The quantity.
        what: &'static str,
        /// Its value.
        value: f64,
        /// What is allowed.
        allowed: &'static str,
    },
    /// Too many samples.
    #[error("irregularity: {0} samples (at most 20,000,000: a longer stretch or a longer sample spacing)")]
    TooLong(usize),
}

/// The largest profile, samples.
const MAX_SAMPLES: usize = 20_000_000;

/// A surface irregularity (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Profile {
    x0: f64,
    dx: f64,
    values: Vec<f64>,
}

fn check(
    what: &'static str,
    value: f64,
    ok: bool,
    allowed: &'static str,
) -> Result<f64, ProfileError> {
    if ok && value.is_finite() {
        Ok(value)
    } else {
        Err(ProfileError::Invalid {
            what,
            value,
            allowed,
        })
    }
}

fn samples(length: f64, dx: f64) -> Result<usize, ProfileError> {
    let n = (length / dx).ceil();
    if n.is_nan() || n >= MAX_SAMPLES as f64 {
        return Err(ProfileError::TooLong(n as usize));
    }
    Ok(n as usize + 1)
}

impl Profile {
    /// Heights `values` (m) at `x0 + i dx` (module docs).
    ///
    /// # Errors
    /// [`ProfileError::Invalid`] for a spacing that is not positive, a value that is not
    /// finite, or fewer than two samples.
    pub fn sampled(x0: f64, dx: f64, values: Vec<f64>) -> Result<Self, ProfileError> {
        check("x0", x0, true, "must be finite")?;
        check("sample spacing", dx, dx > 0.0, "must be > 0 m")?;
        if values.len() < 2 {
            return Err(ProfileError::Invalid {
                what: "samples",
                value: values.len() as f64,
                allowed: "give at least two",
            });
        }
        for &v in &values {
            check("height", v, true, "must be finite")?;
        }
        Ok(Self { x0, dx, values })
    }

    /// `amplitude sin(2 pi (X - from) / wavelength)` for `X` in `[from, to]`, faded in and
    /// out over `fade` wavelengths at each end by a raised cosine, sampled 64 times a
    /// wavelength (module docs).
    ///
    /// # Errors
    /// [`ProfileError`] for a wavelength or stretch that is not positive, a negative fade.
    pub fn harmonic(
        amplitude: f64,
        wavelength: f64,
        (from, to): (f64, f64),
        fade: f64,
    ) -> Result<Self, ProfileError> {
        check("amplitude", amplitude, true, "must be finite")?;
        check("wavelength", wavelength, wavelength > 0.0, "must be > 0 m")?;
        check("start", from, true, "must be finite")?;
        check("end", to, to > from, "must be after the start")?;
        check("fade", fade, fade >= 0.0, "must be >= 0 wavelengths")?;
        let dx = wavelength / 64.0;
        let n = samples(to - from, dx)?;
        let lf = fade * wavelength;
        let values = (0..n)
            .map(|i| {
                let x = (i as f64 * dx).min(to - from);
                let edge = x.min(to - from - x);
                let w = if lf > 0.0 && edge < lf {
                    0.5 * (1.0 - (std::f64::consts::PI * edge / lf).cos())
                } else {
                    1.0
                };
                w * amplitude * (2.0 * std::f64::consts::PI * x / wavelength).sin()
            })
            .collect();
        Self::sampled(from, dx, values)
    }

    /// A measured profile: `(X, r)` pairs, `X` increasing, resampled (linearly) at the
    /// smallest spacing of the points.
    ///
    /// # Errors
    /// [`ProfileError`] for fewer than two points, abscissae that do not increase, values
    /// that are not finite.
    pub fn from_points(points: &[(f64, f64)]) -> Result<Self, ProfileError> {
        if points.len() < 2 {
            return Err(ProfileError::Invalid {
                what: "points",
                value: points.len() as f64,
                allowed: "give at least two",
            });
        }
        let mut dx = f64::INFINITY;
        for w in points.windows(2) {
            let d = w[1].0 - w[0].0;
            check("abscissa step", d, d > 0.0, "the abscissae must increase")?;
            dx = dx.min(d);
        }
        for &(x, r) in points {
            check("abscissa", x, true, "must be finite")?;
            check("height", r, true, "must be finite")?;
        }
        let (x0, x1) = (points[0].0, points[points.len() - 1].0);
        let n = samples(x1 - x0, dx)?;
        let mut k = 0;
        let values = (0..n)
            .map(|i| {
                let x = (x0 + i as f64 * dx).min(x1);
                while k + 2 < points.len() && points[k + 1].0 < x {
                    k += 1;
                }
                let (a, b) = (points[k], points[k + 1]);
                let t = ((x - a.0) / (b.0 - a.0)).clamp(0.0, 1.0);
                (1.0 - t) * a.1 + t * b.1
            })
            .collect();
        Self::sampled(x0, dx, values)
    }

    /// A random profile over `[from, to]` with the one-third-octave band levels `bands`
    /// (`(centre wavelength m, level dB re 1 um)`), `per_band` harmonics a band, random
    /// phases from `seed`, faded over the longest wavelength at each end (module docs).
    ///
    /// # Errors
    /// [`ProfileError`] for a band whose wavelength is not positive or whose level is not
    /// finite, an empty band list, a stretch shorter than the longest wavelength.
    pub fn from_spectrum(
        bands: &[(f64, f64)],
        per_band: usize,
        (from, to): (f64, f64),
        seed: u64,
    ) -> Result<Self, ProfileError> {
        if bands.is_empty() || per_band == 0 {
            return Err(ProfileError::Invalid {
                what: "bands",
                value: bands.len().min(per_band) as f64,
                allowed: "give at least one band and one harmonic a band",
            });
        }
        let mut shortest = f64::INFINITY;
        let mut longest: f64 = 0.0;
        for &(l, db) in bands {
            check("band wavelength", l, l > 0.0, "must be > 0 m")?;
            check("band level", db, true, "must be finite (dB re 1 um)")?;
            shortest = shortest.min(l);
            longest = longest.max(l);
        }
        // A band spans a factor 2^(1/3) in wavelength about its centre.
        let lo = 2f64.powf(-1.0 / 6.0);
        longest /= lo;
        check(
            "end",
            to,
            to - from > longest,
            "the stretch must be longer than the longest wavelength",
        )?;
        let dx = shortest * lo / 16.0;
        let n = samples(to - from, dx)?;
        let mut rng = SplitMix(seed);
        let mut harmonics = Vec::with_capacity(bands.len() * per_band);
        for &(l, db) in bands {
            let rms = 1e-6 * 10f64.powf(db / 20.0);
            let amp = rms * (2.0 / per_band as f64).sqrt();
            for j in 0..per_band {
                let f = (j as f64 + 0.5) / per_band as f64;
                let wl = l * lo * 2f64.powf(f / 3.0);
                harmonics.push((amp, wl, 2.0 * std::f64::consts::PI * rng.next_f64()));
            }
        }
        let values = (0..n)
            .map(|i| {
                let x = (i as f64 * dx).min(to - from);
                let edge = x.min(to - from - x);
                let w = if edge < longest {
                    0.5 * (1.0 - (std::f64::consts::PI * edge / longest).cos())
                } else {
                    1.0
                };
                w * harmonics
                    .iter()
                    .map(|&(a, wl, ph)| a * (2.0 * std::f64::consts::PI * x / wl + ph).sin())
                    .sum::<f64>()
            })
            .collect();
        Self::sampled(from, dx, values)
    }

    /// The stretch the profile covers, m.
    pub fn range(&self) -> (f64, f64) {
        (self.x0, self.x0 + (self.values.len() - 1) as f64 * self.dx)
    }

    /// The sample spacing, m.
    pub fn spacing(&self) -> f64 {
        self.dx
    }

    /// `(r(X), r'(X))` (module docs): m and m/m; zero outside the samples.
    pub fn at(&self, x: f64) -> (f64, f64) {
        let s = (x - self.x0) / self.dx;
        let n = self.values.len();
        if !(s >= 0.0 && s <= (n - 1) as f64) {
            return (0.0, 0.0);
        }
        let i = (s.floor() as usize).min(n - 2);
        let t = s - i as f64;
        let v = |k: isize| -> f64 {
            if k < 0 || k as usize >= n {
                0.0
            } else {
                self.values[k as usize]
            }
        };
        let i = i as isize;
        let (p0, p1) = (v(i), v(i + 1));
        // Catmull-Rom slopes (per sample), zero beyond the ends.
        let m0 = 0.5 * (p1 - v(i - 1));
        let m1 = 0.5 * (v(i + 2) - p0);
        let (t2, t3) = (t * t, t * t * t);
        let r = (2.0 * t3 - 3.0 * t2 + 1.0) * p0
            + (t3 - 2.0 * t2 + t) * m0
            + (-2.0 * t3 + 3.0 * t2) * p1
            + (t3 - t2) * m1;
        let dr = (6.0 * t2 - 6.0 * t) * p0
            + (3.0 * t2 - 4.0 * t + 1.0) * m0
            + (-6.0 * t2 + 6.0 * t) * p1
            + (3.0 * t2 - 2.0 * t) * m1;
        (r, dr / self.dx)
    }
}

/// SplitMix64: a small, well-mixed seeded generator for random phases (reproducible bits on
/// every platform); [`SplitMix::next_f64`] is uniform in `[0, 1)`. The rail's random
/// profiles here and the growth study's initial roughness
/// ([`crate::growth::roughness`]) draw from it.
pub struct SplitMix(pub u64);

impl SplitMix {
    /// The next number in `[0, 1)`.
    pub fn next_f64(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn a_sampled_harmonic_follows_the_sine_and_its_slope() {
        let (a, l) = (1e-4, 0.05);
        let p = Profile::harmonic(a, l, (1.0, 3.0), 0.0).unwrap();
        let mut worst: f64 = 0.0;
        let mut worst_slope: f64 = 0.0;
        for i in 0..2000 {
            let x = 1.0 + 0.1 + 1.8 * i as f64 / 2000.0;
            let (r, dr) = p.at(x);
            let ph = 2.0 * PI * (x - 1.0) / l;
            worst = worst.max((r - a * ph.sin()).abs());
            worst_slope = worst_slope.max((dr - a * 2.0 * PI / l * ph.cos()).abs());
        }
        assert!(worst < 3e-5 * a, "value error {worst:e}");
        assert!(
            worst_slope < 2e-3 * a * 2.0 * PI / l,
            "slope error {worst_slope:e}"
        );
        assert_eq!(p.at(0.5), (0.0, 0.0));
        assert_eq!(p.at(3.5), (0.0, 0.0));
    }

    #[test]
    fn a_faded_harmonic_starts_without_a_step_and_reaches_its_amplitude() {
        let p = Profile::harmonic(1.0, 1.0, (0.0, 10.0), 2.0).unwrap();
        let (r0, s0) = p.at(0.0);
        assert!(r0.abs() < 1e-12 && s0.abs() < 0.01, "{r0} {s0}");
        let peak = (0..1000)
            .map(|i| p.at(4.0 + i as f64 / 1000.0).0.abs())
            .fold(0.0, f64::max);
        assert!((peak - 1.0).abs() < 1e-3, "peak {peak}");
    }

    #[test]
    fn measured_points_are_resampled_and_interpolated() {
        let pts: Vec<(f64, f64)> = (0..=100)
            .map(|i| {
                let x = 0.01 * i as f64;
                (x, 3.0 * x - 1.0)
            })
            .collect();
        let p = Profile::from_points(&pts).unwrap();
        // A straight line is reproduced inside (Catmull-Rom is exact on linear data).
        let (r, dr) = p.at(0.555);
        assert!((r - (3.0 * 0.555 - 1.0)).abs() < 1e-12 && (dr - 3.0).abs() < 1e-9);
        assert!(Profile::from_points(&[(0.0, 0.0), (0.0, 1.0)]).is_err());
        assert!(Profile::from_points(&[(0.0, 0.0)]).is_err());
    }

    #[test]
    fn a_random_profile_has_the_band_levels_it_was_given() {
        // One band at 50 mm, 20 dB re 1 um: RMS 10 um; over a long stretch the profile's
        // mean square is the band's (the harmonics are incommensurate: cross terms average).
        let p = Profile::from_spectrum(&[(0.05, 20.0)], 8, (0.0, 40.0), 7).unwrap();
        let n = 200_000;
        let ms = (0..n)
            .map(|i| p.at(2.0 + 36.0 * i as f64 / n as f64).0.powi(2))
            .sum::<f64>()
            / n as f64;
        let rms = ms.sqrt();
        assert!((rms / 1e-5 - 1.0).abs() < 0.05, "rms {rms:e}");
        let q = Profile::from_spectrum(&[(0.05, 20.0)], 8, (0.0, 40.0), 7).unwrap();
        assert_eq!(p, q, "the same seed gives the same bits");
    }
}
