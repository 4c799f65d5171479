//! `[irregularity]` of a track scenario: a harmonic, a measured profile or a random one
//! from band levels, every value under its key.

use crate::scenario::raw::RawIrregularity;
use crate::scenario::Ctx;
use crate::scenario::{Irregularity, ScenarioError};

/// `[irregularity]`: a harmonic, a measured profile (CSV `x_m,r_m`, relative to the
/// scenario's folder) or a random profile from band levels.
pub(super) fn irregularity(cx: &Ctx, i: RawIrregularity) -> Result<Irregularity, ScenarioError> {
    let kind = i.kind.as_deref().unwrap_or("harmonic");
    let given = |key: &str| match key {
        "amplitude" => i.amplitude.is_some(),
        "wavelength" => i.wavelength.is_some(),
        "fade" => i.fade.is_some(),
        "file" => i.file.is_some(),
        "bands" => i.bands.is_some(),
        "per_band" => i.per_band.is_some(),
        "seed" => i.seed.is_some(),
        _ => false,
    };
    let uses: &[&str] = match kind {
        "harmonic" => &["amplitude", "wavelength", "fade"],
        "measured" => &["file"],
        "spectrum" => &["bands", "per_band", "seed"],
        other => {
            return Err(cx.invalid(
                "irregularity.type",
                format!("\"{other}\""),
                "allowed: \"harmonic\", \"measured\" (a CSV file), \"spectrum\" (band levels)",
            ))
        }
    };
    for key in [
        "amplitude",
        "wavelength",
        "fade",
        "file",
        "bands",
        "per_band",
        "seed",
    ] {
        if given(key) && !uses.contains(&key) {
            return Err(cx.invalid(
                &format!("irregularity.{key}"),
                "(given)",
                &format!(
                    "not used with irregularity.type = \"{kind}\" (it reads: {})",
                    uses.join(", ")
                ),
            ));
        }
    }
    match kind {
        "harmonic" => {
            let amplitude = i.amplitude.ok_or_else(|| {
                cx.missing("irregularity.amplitude", "the harmonic's amplitude, m")
            })?;
            let wavelength = i.wavelength.ok_or_else(|| {
                cx.missing("irregularity.wavelength", "the harmonic's wavelength, m")
            })?;
            let amplitude = cx.positive("irregularity.amplitude", amplitude)?;
            if amplitude > 1e-3 {
                return Err(cx.invalid(
                    "irregularity.amplitude",
                    amplitude,
                    "at most 1e-3 m (a roughness, not a step)",
                ));
            }
            Ok(Irregularity::Harmonic {
                amplitude,
                wavelength: cx.positive("irregularity.wavelength", wavelength)?,
                fade: cx.non_negative("irregularity.fade", i.fade.unwrap_or(2.0))?,
            })
        }
        "measured" => measured(cx, i.file),
        _ => spectrum(cx, &i),
    }
}

/// `irregularity.type = "measured"`: the CSV file's rows of `x_m,r_m`.
fn measured(cx: &Ctx, file: Option<String>) -> Result<Irregularity, ScenarioError> {
    let file =
        file.ok_or_else(|| cx.missing("irregularity.file", "a CSV file of x_m,r_m (m) rows"))?;
    let path = cx
        .path()
        .parent()
        .unwrap_or(std::path::Path::new("."))
        .join(&file);
    let text = std::fs::read_to_string(&path).map_err(|e| {
        cx.invalid(
            "irregularity.file",
            format!("\"{file}\""),
            &format!("cannot be read: {e}"),
        )
    })?;
    let mut points = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let line = line.trim();
        let mut cells = crate::output::csv::number_cells(line);
        if line.is_empty()
            || line.starts_with('#')
            || (n == 0
                && cells
                    .next()
                    .is_some_and(|c| c.starts_with(|c: char| c.is_alphabetic())))
        {
            continue;
        }
        let parsed: Option<(f64, f64)> = (|| {
            let mut it = crate::output::csv::number_cells(line).map(|v| v.parse::<f64>().ok());
            let x = it.next()??;
            let r = it.next()??;
            it.next().is_none().then_some((x, r))
        })();
        match parsed {
            Some((x, r)) if x.is_finite() && r.is_finite() && r.abs() <= 1e-3 => {
                points.push((x, r))
            }
            _ => {
                return Err(cx.invalid(
                    "irregularity.file",
                    format!("\"{file}\" line {}", n + 1),
                    "rows of two numbers x_m,r_m (|r| at most 1e-3 m)",
                ))
            }
        }
    }
    if points.len() < 2 || points.windows(2).any(|w| w[1].0 <= w[0].0) {
        return Err(cx.invalid(
            "irregularity.file",
            format!("\"{file}\""),
            "at least two rows with increasing x_m",
        ));
    }
    Ok(Irregularity::Measured { file: path, points })
}

/// `irregularity.type = "spectrum"`: one-third-octave band levels, `per_band` harmonics each.
fn spectrum(cx: &Ctx, i: &RawIrregularity) -> Result<Irregularity, ScenarioError> {
    let raw = i.bands.as_ref().ok_or_else(|| {
        cx.missing(
            "irregularity.bands",
            "one-third-octave band levels: [[wavelength_m, level_dB_re_1um], ...]",
        )
    })?;
    let mut bands = Vec::with_capacity(raw.len());
    for b in raw {
        match b.as_slice() {
            &[l, db] if l.is_finite() && l > 0.0 && db.is_finite() && db <= 60.0 => {
                bands.push((l, db))
            }
            _ => {
                return Err(cx.invalid(
                    "irregularity.bands",
                    format!("{b:?}"),
                    "pairs [wavelength_m > 0, level dB re 1 um <= 60]",
                ))
            }
        }
    }
    if bands.is_empty() {
        return Err(cx.invalid("irregularity.bands", "[]", "give at least one band"));
    }
    Ok(Irregularity::Spectrum {
        bands,
        per_band: cx.count("irregularity.per_band", i.per_band.unwrap_or(8), 1000)?,
        seed: match i.seed {
            Some(s) if s >= 0 => s as u64,
            Some(s) => return Err(cx.invalid("irregularity.seed", s, "must be >= 0")),
            None => 1,
        },
    })
}
