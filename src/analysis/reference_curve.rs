//! A creep curve computed by another code (a half-space solver, CONTACT) that a creep sweep
//! is drawn and measured against: `rolling.reference_curve = "file.csv"` (relative to the
//! scenario's folder).
//!
//! The file is CSV with a header naming the columns `creepage_mu_a_R` (the longitudinal
//! creepage on the undeformed radius, softway's sign: `> 0` the wheel drives, in units of
//! `mu a / R`, `a` Hertz's semi-axis along the rolling and `R` the wheel's radius) and
//! `traction_ratio` (`Q / (mu N)`, `> 0` when the wheel drives); lines starting with `#`
//! before the header are comments (the reference's provenance). The creepages must increase.
//! With `mu` and the materials fixed, a Hertzian creep curve depends on the creepage only
//! through `xi R / (mu a)` (the saturation creepage and the pressure's tangential strain both
//! scale as `a / R`), so one curve serves every load. `validation/halfspace3d/rolling3d_reference.csv`
//! is the coupled half-space answer for steel on a rigid crown, `mu = 0.3`.
//!
//! A run that names one copies it into its `summary.json` (`traction.reference`), with the
//! reference's traction ratio at the run's own creepage; `softway sweep` draws it beside the
//! sweep's creep curve and, on a refinement ladder, gives its creepages at the ladder's
//! traction ratios beside the Richardson limits ([`crate::run::sweep`]).

use std::path::Path;

/// A reference creep curve: its file and its points `(creepage / (mu a / R), Q / (mu N))`,
/// creepage increasing.
#[derive(Debug, Clone, PartialEq)]
pub struct ReferenceCurve {
    /// The file as read.
    pub file: String,
    /// The points, creepage increasing.
    pub points: Vec<(f64, f64)>,
}

impl ReferenceCurve {
    /// Reads `path` (module docs). The error says what is wrong, for the caller to name the
    /// key.
    ///
    /// # Errors
    /// A message when the file cannot be read, has no `creepage_mu_a_R` and
    /// `traction_ratio` columns, holds a value that is not a finite number, fewer than two
    /// points, or creepages that do not increase.
    pub fn load(path: &Path) -> Result<Self, String> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| format!("{} could not be read: {e}", path.display()))?;
        Self::parse(&text)
            .map(|points| ReferenceCurve {
                file: path.display().to_string(),
                points,
            })
            .map_err(|e| format!("{}: {e}", path.display()))
    }

    /// The points of a reference file's text (module docs).
    ///
    /// # Errors
    /// As [`ReferenceCurve::load`].
    pub fn parse(text: &str) -> Result<Vec<(f64, f64)>, String> {
        let mut lines = text
            .lines()
            .enumerate()
            .filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'));
        let (_, header) = lines
            .next()
            .ok_or("no header: expected the columns creepage_mu_a_R,traction_ratio")?;
        let cols: Vec<&str> = header.split(',').map(str::trim).collect();
        let find = |name: &str| {
            cols.iter().position(|c| *c == name).ok_or(format!(
                "the header `{header}` has no column {name} (expected creepage_mu_a_R and traction_ratio)"
            ))
        };
        let (ix, iy) = (find("creepage_mu_a_R")?, find("traction_ratio")?);
        let mut points: Vec<(f64, f64)> = Vec::new();
        for (k, line) in lines {
            let cells: Vec<&str> = line.split(',').map(str::trim).collect();
            let num = |i: usize| -> Result<f64, String> {
                cells
                    .get(i)
                    .and_then(|c| c.parse::<f64>().ok())
                    .filter(|v| v.is_finite())
                    .ok_or(format!(
                        "line {}: `{line}` needs a finite number in column {}",
                        k + 1,
                        i + 1
                    ))
            };
            let p = (num(ix)?, num(iy)?);
            if let Some(last) = points.last() {
                if p.0 <= last.0 {
                    return Err(format!(
                        "line {}: the creepage {} does not increase (after {})",
                        k + 1,
                        p.0,
                        last.0
                    ));
                }
            }
            points.push(p);
        }
        if points.len() < 2 {
            return Err(format!(
                "{} point(s): a curve needs two or more",
                points.len()
            ));
        }
        Ok(points)
    }

    /// The reference's traction ratio at the creepage `x` (in `mu a / R`), linearly
    /// interpolated; `None` outside its range.
    pub fn at(&self, x: f64) -> Option<f64> {
        interpolate(&self.points, x)
    }

    /// The curve as `summary.json`'s `traction.reference` (with the ratio at the run's
    /// creepage `x`, `mu a / R`, when within range).
    pub fn to_json(&self, x: f64) -> serde_json::Value {
        serde_json::json!({
            "file": self.file,
            "creepage_mu_a_R": self.points.iter().map(|p| p.0).collect::<Vec<_>>(),
            "traction_ratio": self.points.iter().map(|p| p.1).collect::<Vec<_>>(),
            "creepage_of_run_mu_a_R": x,
            "traction_ratio_at_run": self.at(x),
        })
    }

    /// The curve from a summary's `traction.reference` ([`ReferenceCurve::to_json`]); `None`
    /// when it has none or it is malformed.
    pub fn from_summary(summary: &serde_json::Value) -> Option<Self> {
        let r = summary.pointer("/traction/reference")?;
        let list = |k: &str| -> Option<Vec<f64>> {
            r.get(k)?.as_array()?.iter().map(|v| v.as_f64()).collect()
        };
        let (xs, ys) = (list("creepage_mu_a_R")?, list("traction_ratio")?);
        (xs.len() == ys.len() && xs.len() >= 2).then(|| ReferenceCurve {
            file: r
                .get("file")
                .and_then(|f| f.as_str())
                .unwrap_or("")
                .to_string(),
            points: xs.into_iter().zip(ys).collect(),
        })
    }

    /// The file's name without its folder, for a legend.
    pub fn name(&self) -> &str {
        Path::new(&self.file)
            .file_name()
            .and_then(|f| f.to_str())
            .unwrap_or(&self.file)
    }
}

/// Linear interpolation in `pts` (`x` increasing); `None` outside `[x_0, x_last]`.
fn interpolate(pts: &[(f64, f64)], x: f64) -> Option<f64> {
    let k = pts.windows(2).position(|w| w[0].0 <= x && x <= w[1].0)?;
    let ((x0, y0), (x1, y1)) = (pts[k], pts[k + 1]);
    Some(y0 + (y1 - y0) * (x - x0) / (x1 - x0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parse_reads_the_columns_by_name_and_skips_comments() {
        let t = "# from CONTACT\n# more\ntraction_ratio,creepage_mu_a_R\n-1,-2\n0.5,0.25\n1,3\n";
        let p = ReferenceCurve::parse(t).unwrap();
        assert_eq!(p, vec![(-2.0, -1.0), (0.25, 0.5), (3.0, 1.0)]);
        let c = ReferenceCurve {
            file: "x/ref.csv".into(),
            points: p,
        };
        assert_eq!(c.at(0.25), Some(0.5));
        assert!((c.at(1.625).unwrap() - 0.75).abs() < 1e-15);
        assert_eq!(c.at(3.5), None);
        assert_eq!(c.name(), "ref.csv");
        let back = ReferenceCurve::from_summary(
            &serde_json::json!({"traction": {"reference": c.to_json(0.0)}}),
        );
        assert_eq!(back, Some(c));
    }

    #[test]
    fn parse_refuses_what_is_not_a_curve() {
        let bad = [
            ("", "no header"),
            ("x,y\n1,2\n", "no column creepage_mu_a_R"),
            ("creepage_mu_a_R,traction_ratio\n1,0\n", "1 point(s)"),
            (
                "creepage_mu_a_R,traction_ratio\n1,0\n1,0.5\n",
                "does not increase",
            ),
            (
                "creepage_mu_a_R,traction_ratio\n1,0\n2,nan\n",
                "finite number in column 2",
            ),
            ("creepage_mu_a_R,traction_ratio\n1,0\n2\n", "line 3"),
        ];
        for (text, why) in bad {
            let e = ReferenceCurve::parse(text).unwrap_err();
            assert!(e.contains(why), "{text:?}: {e}");
        }
    }
}
