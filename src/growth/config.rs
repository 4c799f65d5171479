//! The scenario's `[growth]` and `[wear]` tables, validated (unknown keys and bad values
//! refused naming the file and the key).
//!
//! ```toml
//! [growth]
//! passes = 20               # simulated passes (softway grow --passes overrides)
//! passes_per_pass = 2e4     # N_w: real passes one simulated pass stands for (the wear step)
//! smoothing = 4e-3          # m: triangular window of the wear (0: none)
//! cutoff = 1e-2             # m: wear shorter than this wavelength removed (0: none)
//! reference = true          # subtract the smooth surface's wear pattern (default false)
//! roughness = "random"      # "harmonic" | "csv" | "spectrum" | "random" | "iso3095" | "none"
//! level = -20.0             # random: dB re 1 um in every band ...
//! min_wavelength = 5e-3     # ... whose centre lies in [min, max], m
//! max_wavelength = 0.2
//! seed = 1
//! # harmonic: amplitude (m), wavelength (m; on a periodic profile rounded to whole orders)
//! # csv: file = "rough.csv" (x_m,z_m; relative to the scenario's folder)
//! # spectrum: band_wavelengths = [m, ...], band_levels = [dB, ...], seed
//! # iso3095: offset = dB added to EN ISO 3095's limit spectrum (default 0), seed
//!
//! [wear]
//! law = "archard"           # "archard" | "frictional_power" | "usfd"
//! k = 1e-4                  # archard: dimensionless
//! hardness = 3e9            # archard: Pa
//! map = "jendel"            # archard: k from Jendel's map (k1..k4 override its values)
//! # frictional_power: k_mass (kg/J, default 5.3e-9)
//! # usfd: k1, x1, k2, x2, k3, c3 (default R8T, crate::wear)
//! density = 7830.0          # kg/m^3 of the worn material (default: the body's)
//! ```

use super::roughness::ISO3095_LIMIT;
use crate::scenario::error::ScenarioError;
use crate::wear::{Archard, FrictionalPower, JendelMap, Usfd, WearLaw};
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// Where the worn pressure comes from (the rail's growth study, `crate::kinds::track::growth`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum WearPatch {
    /// The step's force over Hertz's patch under the axle.
    Hertz,
    /// The rim nodes' own forces.
    Nodes,
}

/// Which surface grows in a study on the track (`crate::kinds::track`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum GrowthSurface {
    /// The rail's top over the recorded bays (`crate::kinds::track::growth`).
    Rail,
    /// The wheel's rim, one sample per rim node (`crate::kinds::track::polygon`).
    Wheel,
}

/// What slides the rail (the rail's growth study, `crate::kinds::track::growth`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SlidingModel {
    /// A steady creepage and traction coefficient (`growth.creepage`,
    /// `growth.traction_coefficient`) under the dynamic normal force: the classic model.
    Steady,
    /// Each rim node's own normal force, friction force and slip speed in the run with
    /// friction (`contact.friction`, `vehicle.creepage`).
    Dynamic,
}

/// A validated growth study (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct GrowthConfig {
    /// Simulated passes when the command line does not say (default 10).
    pub passes: usize,
    /// Real passes per simulated pass, `N_w` (the wear step; default 1e4).
    pub passes_per_pass: f64,
    /// Moving-average width of the wear, m (0: none; the default).
    pub smoothing_m: f64,
    /// Subtract the smooth surface's wear pattern (default false).
    pub reference: bool,
    /// The wear's low-pass wavelength, m (0: none; the default).
    pub cutoff_m: f64,
    /// The initial roughness.
    pub roughness: Roughness,
    /// The key that sets its heights (`growth.level` of a random roughness,
    /// `growth.amplitude` of a harmonic, ...), named when they do not fit the body.
    pub roughness_key: &'static str,
    /// The wear law.
    pub wear: WearLaw,
    /// Density of the worn material, kg/m^3 (`None`: the body's).
    pub wear_density: Option<f64>,
    /// The keys of a rail's study (`kind = "track"`; refused on the wheel).
    pub rail: RailKeys,
}

impl GrowthConfig {
    /// Checks the study against the profile's grid `(x0, dx, n, periodic)` of its runner,
    /// before anything is run or written: each key that cannot be carried out on it is
    /// refused by name (`key`, `value`, `allowed`). A smoothing window wider than the
    /// profile (`growth.smoothing = 1e300` asked for a window of `usize::MAX` samples), a
    /// cutoff longer than the profile, a harmonic shorter than two samples (aliased onto a
    /// longer wavelength without a word).
    ///
    /// # Errors
    /// `(key, value, allowed)` of the first key refused.
    pub fn check_grid(
        &self,
        (_, dx, n, _): (f64, f64, usize, bool),
    ) -> Result<(), (String, String, String)> {
        let length = n as f64 * dx;
        let refuse =
            |key: &str, v: f64, allowed: String| Err((key.to_string(), v.to_string(), allowed));
        if self.smoothing_m > length {
            return refuse(
                "growth.smoothing",
                self.smoothing_m,
                format!("at most the profile's length, {length:.4e} m ({n} samples of {dx:.4e} m); 0: no smoothing"),
            );
        }
        if self.cutoff_m > length {
            return refuse(
                "growth.cutoff",
                self.cutoff_m,
                format!("at most the profile's length, {length:.4e} m; 0: no low-pass"),
            );
        }
        let shortest = 2.0 * dx;
        match &self.roughness {
            // On the rim it is rounded to whole orders: beyond 1.5 lengths to order 0,
            // which was silently made order 1 (a 1 km harmonic ran as the circumference).
            Roughness::Harmonic { wavelength, .. } if *wavelength > 1.5 * length => refuse(
                "growth.wavelength",
                *wavelength,
                format!("at most the profile's length, {length:.4e} m (order 1 on a rim)"),
            ),
            Roughness::Harmonic { wavelength, .. } if *wavelength < shortest => refuse(
                "growth.wavelength",
                *wavelength,
                format!("at least two samples of the profile, {shortest:.4e} m (a shorter harmonic is aliased)"),
            ),
            // A spectrum's bands keep the orders the grid holds and leave out a band that
            // holds none (crate::growth::roughness): nothing is aliased there.
            _ => Ok(()),
        }
    }
}

/// The `[growth]` keys of a rail's study ([`crate::kinds::track::growth`]), as given.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RailKeys {
    /// `growth.dx`: the rail profile's spacing, m.
    pub dx: Option<f64>,
    /// `growth.creepage`: the rim's steady slip over the rolling speed.
    pub creepage: Option<f64>,
    /// `growth.traction_coefficient`: `T / N`.
    pub traction_coefficient: Option<f64>,
    /// `growth.patch`: where the worn pressure comes from.
    pub patch: Option<WearPatch>,
    /// `growth.sliding`: what slides the rail (steady when absent).
    pub sliding: Option<SlidingModel>,
    /// `growth.surface`: which surface grows on a track (the rail when absent).
    pub surface: Option<GrowthSurface>,
}

impl RailKeys {
    /// The keys given, by name.
    pub fn given(&self) -> Vec<&'static str> {
        let mut v = Vec::new();
        if self.dx.is_some() {
            v.push("growth.dx");
        }
        if self.creepage.is_some() {
            v.push("growth.creepage");
        }
        if self.traction_coefficient.is_some() {
            v.push("growth.traction_coefficient");
        }
        if self.patch.is_some() {
            v.push("growth.patch");
        }
        if self.sliding.is_some() {
            v.push("growth.sliding");
        }
        if self.surface.is_some() {
            v.push("growth.surface");
        }
        v
    }
}

/// The initial roughness of a study.
#[derive(Debug, Clone, PartialEq)]
pub enum Roughness {
    /// A smooth surface.
    None,
    /// `amplitude sin(2 pi x / wavelength)`.
    Harmonic {
        /// m.
        amplitude: f64,
        /// m.
        wavelength: f64,
    },
    /// `x_m,z_m` rows of a file.
    Csv {
        /// The file.
        path: PathBuf,
    },
    /// Band levels: `(centre wavelength m, dB re 1 um)`, random phases from the seed.
    Spectrum {
        /// The bands.
        bands: Vec<(f64, f64)>,
        /// The seed.
        seed: u64,
    },
}

#[derive(Debug, Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawGrowth {
    passes: Option<i64>,
    passes_per_pass: Option<f64>,
    smoothing: Option<f64>,
    cutoff: Option<f64>,
    reference: Option<bool>,
    roughness: Option<String>,
    amplitude: Option<f64>,
    wavelength: Option<f64>,
    file: Option<String>,
    band_wavelengths: Option<Vec<f64>>,
    band_levels: Option<Vec<f64>>,
    level: Option<f64>,
    min_wavelength: Option<f64>,
    max_wavelength: Option<f64>,
    offset: Option<f64>,
    seed: Option<i64>,
    dx: Option<f64>,
    creepage: Option<f64>,
    traction_coefficient: Option<f64>,
    patch: Option<String>,
    sliding: Option<String>,
    surface: Option<String>,
}

#[derive(Debug, Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawWear {
    law: Option<String>,
    k: Option<f64>,
    hardness: Option<f64>,
    map: Option<String>,
    k1: Option<f64>,
    k2: Option<f64>,
    k3: Option<f64>,
    k4: Option<f64>,
    k_mass: Option<f64>,
    x1: Option<f64>,
    x2: Option<f64>,
    c3: Option<f64>,
    density: Option<f64>,
}

/// Default simulated passes.
pub const DEFAULT_PASSES: usize = 10;
/// Default real passes per simulated pass.
pub const DEFAULT_PASSES_PER_PASS: f64 = 1e4;

/// Validates the `[growth]` and `[wear]` tables of the scenario `path` (`None` when
/// neither is given; `[wear]` alone is refused, as is `[growth]` without `[wear]`).
///
/// # Errors
/// [`ScenarioError`] naming the file and the key.
pub fn validate(
    growth: Option<toml::Table>,
    wear: Option<toml::Table>,
    path: &Path,
) -> Result<Option<GrowthConfig>, ScenarioError> {
    let Some((g, w)) = raw_tables(growth, wear, path)? else {
        return Ok(None);
    };
    let keys = Keys(path);
    let (passes, passes_per_pass, smoothing_m, cutoff_m) = study_keys(&g, keys)?;
    let seed = match g.seed {
        None => 1,
        Some(s) if s >= 0 => s as u64,
        Some(s) => return Err(keys.invalid("growth.seed", s.to_string(), "must be >= 0")),
    };
    let rail = rail_keys(&g, keys)?;
    let roughness = roughness(&g, seed, keys)?;
    let roughness_key = match g.roughness.as_deref() {
        Some("harmonic") => "growth.amplitude",
        Some("csv") => "growth.file",
        Some("spectrum") => "growth.band_levels",
        Some("random") => "growth.level",
        Some("iso3095") => "growth.offset",
        _ => "growth.roughness",
    };
    let wear = wear_law(&w, path)?;
    let wear_density = match w.density {
        None => None,
        Some(d) => Some(keys.positive("wear.density", d)?),
    };
    Ok(Some(GrowthConfig {
        passes,
        passes_per_pass,
        smoothing_m,
        reference: g.reference.unwrap_or(false),
        cutoff_m,
        roughness,
        roughness_key,
        wear,
        wear_density,
        rail,
    }))
}

/// The scenario file's errors, by key.
#[derive(Clone, Copy)]
struct Keys<'a>(&'a Path);

impl Keys<'_> {
    fn invalid(self, key: &str, value: String, allowed: &str) -> ScenarioError {
        ScenarioError::Invalid {
            path: self.0.to_path_buf(),
            key: key.to_string(),
            value,
            allowed: allowed.to_string(),
        }
    }

    /// `v` if finite and > 0, else refused by `key`.
    fn positive(self, key: &str, v: f64) -> Result<f64, ScenarioError> {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(self.invalid(key, v.to_string(), "must be finite and > 0"))
        }
    }

    /// `growth.{key}`'s value, or refused as missing (`why`: what it is).
    fn need(self, key: &str, v: Option<f64>, why: &str) -> Result<f64, ScenarioError> {
        v.ok_or_else(|| self.missing(&format!("growth.{key}"), why))
    }

    fn missing(self, key: &str, why: &str) -> ScenarioError {
        ScenarioError::Missing {
            path: self.0.to_path_buf(),
            key: key.to_string(),
            why: why.to_string(),
        }
    }
}

/// The two tables read into their keys (`None`: neither given); one without the other is
/// refused.
fn raw_tables(
    growth: Option<toml::Table>,
    wear: Option<toml::Table>,
    path: &Path,
) -> Result<Option<(RawGrowth, RawWear)>, ScenarioError> {
    let keys = Keys(path);
    let (g, w) = match (growth, wear) {
        (None, None) => return Ok(None),
        (Some(_), None) => {
            return Err(keys.missing(
                "wear",
                "a growth study needs its wear law ([wear] law = \"archard\" | \"frictional_power\" | \"usfd\")",
            ))
        }
        (None, Some(_)) => {
            return Err(keys.missing(
                "growth",
                "[wear] is read by the growth study (softway grow): give its [growth] table",
            ))
        }
        (Some(g), Some(w)) => (g, w),
    };
    let parse = |table: &str, e: toml::de::Error| ScenarioError::Parse {
        path: path.to_path_buf(),
        message: format!("[{table}]: {}", e.message()),
    };
    let g: RawGrowth = toml::Value::Table(g)
        .try_into()
        .map_err(|e| parse("growth", e))?;
    let w: RawWear = toml::Value::Table(w)
        .try_into()
        .map_err(|e| parse("wear", e))?;
    Ok(Some((g, w)))
}

/// The study's own keys: passes, real passes per pass, smoothing and cutoff (m).
fn study_keys(g: &RawGrowth, keys: Keys) -> Result<(usize, f64, f64, f64), ScenarioError> {
    let passes = match g.passes {
        None => DEFAULT_PASSES,
        Some(p) if (1..=100_000).contains(&p) => p as usize,
        Some(p) => {
            return Err(keys.invalid("growth.passes", p.to_string(), "between 1 and 100000"))
        }
    };
    // At least one: the rates are per real pass (1e-300 of a pass wrote rates of inf).
    let passes_per_pass = match g.passes_per_pass.unwrap_or(DEFAULT_PASSES_PER_PASS) {
        n if n.is_finite() && n >= 1.0 => n,
        n if n.is_finite() && n > 0.0 => {
            return Err(keys.invalid(
                "growth.passes_per_pass",
                n.to_string(),
                "must be at least 1 (the real passes one simulated pass stands for)",
            ))
        }
        n => keys.positive("growth.passes_per_pass", n)?,
    };
    let smoothing_m = match g.smoothing {
        None => 0.0,
        Some(s) if s.is_finite() && s >= 0.0 => s,
        Some(s) => {
            return Err(keys.invalid(
                "growth.smoothing",
                s.to_string(),
                "must be >= 0 m (0: no smoothing)",
            ))
        }
    };
    let cutoff_m = match g.cutoff {
        None => 0.0,
        Some(s) if s.is_finite() && s >= 0.0 => s,
        Some(s) => {
            return Err(keys.invalid(
                "growth.cutoff",
                s.to_string(),
                "must be >= 0 m (0: no low-pass)",
            ))
        }
    };
    Ok((passes, passes_per_pass, smoothing_m, cutoff_m))
}

/// The keys of a rail's study.
fn rail_keys(g: &RawGrowth, keys: Keys) -> Result<RailKeys, ScenarioError> {
    Ok(RailKeys {
        dx: g.dx.map(|v| keys.positive("growth.dx", v)).transpose()?,
        creepage: match g.creepage {
            Some(c) if !(c.is_finite() && c > 0.0 && c < 1.0) => {
                return Err(keys.invalid(
                    "growth.creepage",
                    c.to_string(),
                    "must be in (0, 1): the rim's slip over the rolling speed",
                ))
            }
            c => c,
        },
        traction_coefficient: match g.traction_coefficient {
            Some(c) if !(c.is_finite() && c >= 0.0) => {
                return Err(keys.invalid(
                    "growth.traction_coefficient",
                    c.to_string(),
                    "must be finite and >= 0",
                ))
            }
            c => c,
        },
        patch: match g.patch.as_deref() {
            None => None,
            Some("hertz") => Some(WearPatch::Hertz),
            Some("nodes") => Some(WearPatch::Nodes),
            Some(other) => {
                return Err(keys.invalid(
                    "growth.patch",
                    format!("\"{other}\""),
                    "\"hertz\" (the contact force over Hertz's patch) or \"nodes\" (the rim nodes' own forces)",
                ))
            }
        },
        sliding: match g.sliding.as_deref() {
            None => None,
            Some("steady") => Some(SlidingModel::Steady),
            Some("dynamic") => Some(SlidingModel::Dynamic),
            Some(other) => {
                return Err(keys.invalid(
                    "growth.sliding",
                    format!("\"{other}\""),
                    "\"steady\" (growth.creepage and growth.traction_coefficient under the dynamic normal force) or \"dynamic\" (each rim node's own friction in the run: contact.friction and vehicle.creepage)",
                ))
            }
        },
        surface: match g.surface.as_deref() {
            None => None,
            Some("rail") => Some(GrowthSurface::Rail),
            Some("wheel") => Some(GrowthSurface::Wheel),
            Some(other) => {
                return Err(keys.invalid(
                    "growth.surface",
                    format!("\"{other}\""),
                    "\"rail\" (the rail's top over the recorded bays) or \"wheel\" (the wheel's rim, its polygon orders)",
                ))
            }
        },
    })
}

/// The initial roughness: `growth.roughness` and the keys it reads (any other roughness
/// key given is refused).
fn roughness(g: &RawGrowth, seed: u64, keys: Keys) -> Result<Roughness, ScenarioError> {
    let kind = g.roughness.clone().unwrap_or_else(|| "none".into());
    let given: Vec<(&str, bool)> = vec![
        ("amplitude", g.amplitude.is_some()),
        ("wavelength", g.wavelength.is_some()),
        ("file", g.file.is_some()),
        ("band_wavelengths", g.band_wavelengths.is_some()),
        ("band_levels", g.band_levels.is_some()),
        ("level", g.level.is_some()),
        ("min_wavelength", g.min_wavelength.is_some()),
        ("max_wavelength", g.max_wavelength.is_some()),
        ("offset", g.offset.is_some()),
        ("seed", g.seed.is_some()),
    ];
    let reads: &[&str] = match kind.as_str() {
        "none" => &[],
        "harmonic" => &["amplitude", "wavelength"],
        "csv" => &["file"],
        "spectrum" => &["band_wavelengths", "band_levels", "seed"],
        "random" => &["level", "min_wavelength", "max_wavelength", "seed"],
        "iso3095" => &["offset", "seed"],
        other => {
            return Err(keys.invalid(
                "growth.roughness",
                format!("\"{other}\""),
                "one of \"none\", \"harmonic\", \"csv\", \"spectrum\", \"random\", \"iso3095\"",
            ))
        }
    };
    if let Some((k, _)) = given.iter().find(|(k, on)| *on && !reads.contains(k)) {
        return Err(keys.invalid(
            &format!("growth.{k}"),
            "(given)".into(),
            &format!(
                "not read with roughness = \"{kind}\" (it reads {}): remove it",
                if reads.is_empty() {
                    "no other key".to_string()
                } else {
                    reads.join(", ")
                }
            ),
        ));
    }
    match kind.as_str() {
        "none" => Ok(Roughness::None),
        "harmonic" => harmonic(g, keys),
        "csv" => {
            let f = g.file.clone().unwrap_or_default();
            if f.is_empty() {
                return Err(keys.missing("growth.file", "the CSV of x_m,z_m rows"));
            }
            let p = PathBuf::from(&f);
            let p = if p.is_relative() {
                keys.0.parent().unwrap_or(Path::new(".")).join(p)
            } else {
                p
            };
            Ok(Roughness::Csv { path: p })
        }
        "spectrum" => spectrum(g, seed, keys),
        "random" => random(g, seed, keys),
        _ => {
            let offset = g.offset.unwrap_or(0.0);
            if !offset.is_finite() {
                return Err(keys.invalid("growth.offset", offset.to_string(), "must be finite dB"));
            }
            Ok(Roughness::Spectrum {
                bands: ISO3095_LIMIT
                    .iter()
                    .map(|&(cm, db)| (cm * 1e-2, db + offset))
                    .collect(),
                seed,
            })
        }
    }
}

/// `roughness = "harmonic"`: amplitude and wavelength.
fn harmonic(g: &RawGrowth, keys: Keys) -> Result<Roughness, ScenarioError> {
    let amplitude = keys.need("amplitude", g.amplitude, "the harmonic's amplitude, m")?;
    if !amplitude.is_finite() {
        return Err(keys.invalid("growth.amplitude", amplitude.to_string(), "must be finite"));
    }
    Ok(Roughness::Harmonic {
        amplitude,
        wavelength: keys.positive(
            "growth.wavelength",
            keys.need("wavelength", g.wavelength, "the harmonic's wavelength, m")?,
        )?,
    })
}

/// `roughness = "spectrum"`: the bands' wavelengths and levels, one each.
fn spectrum(g: &RawGrowth, seed: u64, keys: Keys) -> Result<Roughness, ScenarioError> {
    let (Some(l), Some(d)) = (&g.band_wavelengths, &g.band_levels) else {
        return Err(keys.missing(
            "growth.band_wavelengths / growth.band_levels",
            "the bands' centre wavelengths (m) and levels (dB re 1 um), one each",
        ));
    };
    if l.len() != d.len() || l.is_empty() {
        return Err(keys.invalid(
            "growth.band_levels",
            format!("{} values", d.len()),
            &format!("one per band wavelength ({} given), at least one", l.len()),
        ));
    }
    for &x in l {
        keys.positive("growth.band_wavelengths", x)?;
    }
    if let Some(x) = d.iter().find(|x| !x.is_finite()) {
        return Err(keys.invalid(
            "growth.band_levels",
            x.to_string(),
            "must be finite dB re 1 um",
        ));
    }
    Ok(Roughness::Spectrum {
        bands: l.iter().copied().zip(d.iter().copied()).collect(),
        seed,
    })
}

/// `roughness = "random"`: one level in every one-third-octave band of a range.
fn random(g: &RawGrowth, seed: u64, keys: Keys) -> Result<Roughness, ScenarioError> {
    let level = keys.need("level", g.level, "the level of every band, dB re 1 um")?;
    if !level.is_finite() {
        return Err(keys.invalid(
            "growth.level",
            level.to_string(),
            "must be finite dB re 1 um",
        ));
    }
    let lo = keys.positive(
        "growth.min_wavelength",
        keys.need(
            "min_wavelength",
            g.min_wavelength,
            "the shortest band centre, m",
        )?,
    )?;
    let hi = keys.positive(
        "growth.max_wavelength",
        keys.need(
            "max_wavelength",
            g.max_wavelength,
            "the longest band centre, m",
        )?,
    )?;
    let bands = preferred_bands(lo, hi);
    if bands.is_empty() {
        return Err(keys.invalid(
            "growth.max_wavelength",
            hi.to_string(),
            &format!("no one-third-octave band centre (10^(j/10) mm) lies in [{lo}, {hi}] m: widen the range"),
        ));
    }
    Ok(Roughness::Spectrum {
        bands: bands.into_iter().map(|c| (c, level)).collect(),
        seed,
    })
}

/// The one-third-octave centres `10^(j/10)` mm within `[lo, hi]` m, longest first.
pub fn preferred_bands(lo: f64, hi: f64) -> Vec<f64> {
    let j_lo = (10.0 * (lo * 1e3).log10() - 1e-9).ceil() as i64;
    let j_hi = (10.0 * (hi * 1e3).log10() + 1e-9).floor() as i64;
    (j_lo..=j_hi)
        .rev()
        .map(|j| 10f64.powf(j as f64 / 10.0) * 1e-3)
        .collect()
}

fn wear_law(w: &RawWear, path: &Path) -> Result<WearLaw, ScenarioError> {
    let invalid = |key: &str, value: String, allowed: &str| ScenarioError::Invalid {
        path: path.to_path_buf(),
        key: key.to_string(),
        value,
        allowed: allowed.to_string(),
    };
    let law = w.law.clone().ok_or_else(|| ScenarioError::Missing {
        path: path.to_path_buf(),
        key: "wear.law".into(),
        why: "\"archard\", \"frictional_power\" or \"usfd\"".into(),
    })?;
    let given: Vec<(&str, bool)> = vec![
        ("k", w.k.is_some()),
        ("hardness", w.hardness.is_some()),
        ("map", w.map.is_some()),
        ("k1", w.k1.is_some()),
        ("k2", w.k2.is_some()),
        ("k3", w.k3.is_some()),
        ("k4", w.k4.is_some()),
        ("k_mass", w.k_mass.is_some()),
        ("x1", w.x1.is_some()),
        ("x2", w.x2.is_some()),
        ("c3", w.c3.is_some()),
    ];
    let jendel = w.map.as_deref() == Some("jendel");
    let reads: &[&str] = match (law.as_str(), jendel) {
        ("archard", false) => &["k", "hardness", "map"],
        ("archard", true) => &["hardness", "map", "k1", "k2", "k3", "k4"],
        ("frictional_power", _) => &["k_mass"],
        ("usfd", _) => &["k1", "x1", "k2", "x2", "k3", "c3"],
        (other, _) => {
            return Err(invalid(
                "wear.law",
                format!("\"{other}\""),
                "one of \"archard\", \"frictional_power\", \"usfd\"",
            ))
        }
    };
    if let Some((k, _)) = given.iter().find(|(k, on)| *on && !reads.contains(k)) {
        return Err(invalid(
            &format!("wear.{k}"),
            "(given)".into(),
            &format!(
                "not read by law = \"{law}\"{} (it reads {}): remove it",
                if jendel { " with map = \"jendel\"" } else { "" },
                reads.join(", ")
            ),
        ));
    }
    let out = match law.as_str() {
        "archard" => {
            let map = match w.map.as_deref() {
                None | Some("none") => None,
                Some("jendel") => {
                    let d = JendelMap::DRY;
                    Some(JendelMap {
                        k1: w.k1.unwrap_or(d.k1),
                        k2: w.k2.unwrap_or(d.k2),
                        k3: w.k3.unwrap_or(d.k3),
                        k4: w.k4.unwrap_or(d.k4),
                    })
                }
                Some(other) => {
                    return Err(invalid(
                        "wear.map",
                        format!("\"{other}\""),
                        "\"none\" or \"jendel\"",
                    ))
                }
            };
            let hardness = w.hardness.ok_or_else(|| ScenarioError::Missing {
                path: path.to_path_buf(),
                key: "wear.hardness".into(),
                why: "the worn surface's hardness, Pa (Archard's H)".into(),
            })?;
            let k = match (map.is_some(), w.k) {
                (true, _) => 0.0,
                (false, Some(k)) => k,
                (false, None) => {
                    return Err(ScenarioError::Missing {
                        path: path.to_path_buf(),
                        key: "wear.k".into(),
                        why: "Archard's dimensionless wear coefficient (or map = \"jendel\")"
                            .into(),
                    })
                }
            };
            WearLaw::Archard(Archard { k, hardness, map })
        }
        "frictional_power" => WearLaw::FrictionalPower(FrictionalPower {
            k_mass: w.k_mass.unwrap_or(FrictionalPower::DEFAULT_K_MASS),
        }),
        _ => {
            let d = Usfd::R8T;
            WearLaw::Usfd(Usfd {
                k1: w.k1.unwrap_or(d.k1),
                x1: w.x1.unwrap_or(d.x1),
                k2: w.k2.unwrap_or(d.k2),
                x2: w.x2.unwrap_or(d.x2),
                k3: w.k3.unwrap_or(d.k3),
                c3: w.c3.unwrap_or(d.c3),
            })
        }
    };
    out.check().map_err(|m| {
        let key = m.split(' ').next().unwrap_or("wear").to_string();
        ScenarioError::Invalid {
            path: path.to_path_buf(),
            key,
            value: m
                .split(" = ")
                .nth(1)
                .and_then(|s| s.split(':').next())
                .unwrap_or("")
                .to_string(),
            allowed: m.split(": ").nth(1).unwrap_or(&m).to_string(),
        }
    })?;
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tables(g: &str, w: &str) -> (Option<toml::Table>, Option<toml::Table>) {
        (Some(g.parse().unwrap()), Some(w.parse().unwrap()))
    }

    #[test]
    fn defaults_and_errors_name_the_key() {
        let p = Path::new("s.toml");
        let (g, w) = tables("", "law = \"frictional_power\"");
        let c = validate(g, w, p).unwrap().unwrap();
        assert_eq!(c.passes, DEFAULT_PASSES);
        assert_eq!(c.passes_per_pass, DEFAULT_PASSES_PER_PASS);
        assert_eq!(c.smoothing_m, 0.0);
        assert_eq!(c.cutoff_m, 0.0);
        assert!(!c.reference);
        assert_eq!(c.roughness, Roughness::None);
        let (g, w) = tables("pases = 3", "law = \"usfd\"");
        let e = validate(g, w, p).unwrap_err().to_string();
        assert!(e.contains("s.toml") && e.contains("pases"), "{e}");
        let (g, w) = tables("passes_per_pass = -1.0", "law = \"usfd\"");
        let e = validate(g, w, p).unwrap_err().to_string();
        assert!(e.contains("growth.passes_per_pass"), "{e}");
        let (g, w) = tables("", "law = \"archard\"\nk = 1e-4");
        let e = validate(g, w, p).unwrap_err().to_string();
        assert!(e.contains("wear.hardness"), "{e}");
        let (g, w) = tables("", "law = \"usfd\"\nk_mass = 1.0");
        let e = validate(g, w, p).unwrap_err().to_string();
        assert!(e.contains("wear.k_mass"), "{e}");
        let (g, w) = tables(
            "roughness = \"harmonic\"\namplitude = 1e-6\nlevel = 3.0",
            "law = \"usfd\"",
        );
        let e = validate(g, w, p).unwrap_err().to_string();
        assert!(e.contains("growth.level"), "{e}");
        let (g, w) = tables("", "law = \"archard\"\nhardness = -3.0\nk = 1e-4");
        let e = validate(g, w, p).unwrap_err().to_string();
        assert!(e.contains("wear.hardness"), "{e}");
    }

    #[test]
    fn preferred_centres() {
        let c = preferred_bands(5e-3, 0.1);
        assert!((c[0] - 0.1).abs() < 1e-12);
        assert!((c[c.len() - 1] - 5.0119e-3).abs() < 1e-6);
        assert_eq!(c.len(), 14);
    }
}
