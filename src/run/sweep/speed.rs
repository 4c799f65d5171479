//! The creep forces against the rolling speed: what inertia changes, which a quasi-static
//! contact code (CONTACT, Kalker's theory) leaves out by assumption.
//!
//! A sweep of a rolling 3D scenario over the rim's speed (`rolling.speed_km_h`, or
//! `rolling.omega`), alone or with one more key (a refinement ladder, `[sweep] ladder = {
//! key = "wheel.zone_sectors", ... }`, or a list of creepages), gives on each series of the
//! other key the steady `Q / (mu N)`, `Q_y / (mu N)` and `N` at each speed and their change
//! from the slowest speed. The slowest is the quasi-static answer of the same model when it
//! is slow enough: inertia's share of the forces grows as `(V / c)^2` (`c` the waves'
//! speeds), so at 5 km/h it is 1/3600 of its share at 300 km/h. For the change to be
//! inertia's alone, the run must roll the same distance in the same steps at every speed
//! (`rolling.step_mm` and `rolling.settle_mm` in place of `time.h` and
//! `rolling.settle_ms`): then the discretization of the moving contact is the same, and
//! only the mass's share of the step's matrix differs.
//!
//! On a refinement ladder of three or more rungs the change at each speed gets its observed
//! order and Richardson limit ([`crate::analysis::richardson`]), as the creep ladder's
//! creepages do ([`super::creep`]). Each run's steady figures carry the spread of their four
//! windows' means (`steady.traction_ratio_windows`), the noise a change is to be read
//! against.
//!
//! Files: `speed_effect.csv` (every point), `speed_effect.md` (the changes, the ladder's
//! orders and limits) and `speed_effect.png` (the change of `Q / (mu N)` and of `N` against
//! the speed, a line per series).

use super::{SweepError, SweepPoint};
use crate::output::csv::{push_record, record};
use crate::output::plot::{panels, Panel, Series, SeriesStyle};
use crate::run::RunError;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The keys that set the rolling speed.
pub const SPEED_KEYS: [&str; 2] = ["rolling.speed_km_h", "rolling.omega"];

/// The keys whose values are not a refinement: a series over one of them gets no order or
/// limit.
const PHYSICAL_KEYS: [&str; 4] = [
    "rolling.creepage",
    "rolling.lateral_creepage",
    "rolling.spin_creepage",
    "contact.friction",
];

/// One run's steady figures.
#[derive(Debug, Clone, PartialEq)]
pub struct SpeedPoint {
    /// The rim's speed, km/h.
    pub speed: f64,
    /// The steady normal force, N.
    pub normal: f64,
    /// The steady `Q / (mu N)`.
    pub ratio: f64,
    /// The steady `Q_y / (mu N)`.
    pub lateral: f64,
    /// The spread (max - min) of the four windows' `Q / (mu N)`.
    pub spread: f64,
    /// The windows' `Q / (mu N)`.
    pub windows: Vec<f64>,
}

impl SpeedPoint {
    fn of(p: &SweepPoint) -> Option<SpeedPoint> {
        let s = &p.summary;
        let num = |ptr: &str| s.pointer(ptr).and_then(serde_json::Value::as_f64);
        let speed = num("/speed_km_h").or_else(|| num("/speed_m_s").map(|v| 3.6 * v))?;
        let windows: Vec<f64> = s
            .pointer("/steady/traction_ratio_windows")
            .and_then(|w| w.as_array())
            .map(|w| w.iter().filter_map(serde_json::Value::as_f64).collect())
            .unwrap_or_default();
        let spread = windows.iter().copied().fold(f64::NEG_INFINITY, f64::max)
            - windows.iter().copied().fold(f64::INFINITY, f64::min);
        Some(SpeedPoint {
            speed,
            normal: num("/traction/normal").unwrap_or(f64::NAN),
            ratio: super::steady_traction_ratio(p),
            lateral: num("/traction/lateral_ratio").unwrap_or(f64::NAN),
            spread: if spread.is_finite() { spread } else { f64::NAN },
            windows,
        })
    }
}

/// The speeds' series of one value of the other key, sorted by speed.
#[derive(Debug, Clone, PartialEq)]
pub struct SpeedSeries {
    /// The other key's value (NaN when the sweep varies the speed alone).
    pub value: f64,
    /// Its points, by speed.
    pub points: Vec<SpeedPoint>,
}

impl SpeedSeries {
    /// The change of `Q / (mu N)` from the slowest point, at each point.
    pub fn ratio_change(&self) -> Vec<f64> {
        let base = self.points.first().map_or(f64::NAN, |p| p.ratio);
        self.points.iter().map(|p| p.ratio - base).collect()
    }

    /// The relative change of `N` from the slowest point, at each point.
    pub fn normal_change(&self) -> Vec<f64> {
        let base = self.points.first().map_or(f64::NAN, |p| p.normal);
        self.points.iter().map(|p| p.normal / base - 1.0).collect()
    }
}

/// The change of `Q / (mu N)` at one speed over a refinement ladder.
#[derive(Debug, Clone, PartialEq)]
pub struct SpeedLadderRow {
    /// The speed, km/h.
    pub speed: f64,
    /// The change on each rung (NaN where the rung lacks the speed).
    pub changes: Vec<f64>,
    /// The observed order from the last three rungs, within the creep ladder's bounds.
    pub order: Option<f64>,
    /// The Richardson limit, when there is an order.
    pub limit: Option<f64>,
}

/// The ladder's rows: at each speed but the slowest, the change of `Q / (mu N)` on each rung
/// of `series` (the rungs `rungs`), its order and limit.
pub fn ladder_rows(rungs: &[f64], series: &[SpeedSeries]) -> Vec<SpeedLadderRow> {
    let regular = super::creep::is_ladder(rungs);
    let mut speeds: Vec<f64> = series
        .iter()
        .flat_map(|s| s.points.iter().map(|p| p.speed))
        .collect();
    speeds.sort_by(f64::total_cmp);
    speeds.dedup_by(|a, b| (*a - *b).abs() <= 1e-9 * b.abs());
    speeds
        .into_iter()
        .skip(1)
        .map(|v| {
            let changes: Vec<f64> = series
                .iter()
                .map(|s| {
                    let d = s.ratio_change();
                    s.points
                        .iter()
                        .position(|p| (p.speed - v).abs() <= 1e-9 * v.abs())
                        .map_or(f64::NAN, |k| d[k])
                })
                .collect();
            let (order, limit) = if regular {
                super::creep::order_and_limit(rungs, &changes)
            } else {
                (None, None)
            };
            SpeedLadderRow {
                speed: v,
                changes,
                order,
                limit,
            }
        })
        .collect()
}

/// Whether the sweep over `keys`, of which `varying` vary, is a speed study of rolling 3D
/// points: the index of the speed key and of the other varying key, if any.
pub fn study_keys(
    points: &[SweepPoint],
    keys: &[String],
    varying: &[usize],
) -> Option<(usize, Option<usize>)> {
    let rolling3d = points
        .iter()
        .any(|p| p.summary["kind"].as_str() == Some("rolling3d"));
    let speed = |i: &usize| SPEED_KEYS.contains(&keys[*i].as_str());
    let numeric = |i: usize| {
        points
            .iter()
            .all(|p| p.sets[i].value.trim_matches('"').parse::<f64>().is_ok())
    };
    if !rolling3d {
        return None;
    }
    match varying {
        [i] if speed(i) => Some((*i, None)),
        [i, j] if speed(i) && !speed(j) && numeric(*j) => Some((*i, Some(*j))),
        [i, j] if speed(j) && !speed(i) && numeric(*i) => Some((*j, Some(*i))),
        _ => None,
    }
}

/// Writes the speed study (module docs) of the sweep's complete points; returns the files.
///
/// # Errors
/// [`SweepError`] when a file cannot be written.
pub fn speed_effect(
    out: &Path,
    points: &[SweepPoint],
    i_series: Option<usize>,
) -> Result<Vec<PathBuf>, SweepError> {
    let study = Study::of(points, i_series);
    let write = |name: &str, text: String| super::write_text(out, name, &text);
    let mut files = vec![
        write("speed_effect.csv", study.csv())?,
        write("speed_effect.md", study.md())?,
    ];
    let png = out.join("speed_effect.png");
    panels(&png, &study.panels(), 1, 2, (1100, 1100)).map_err(|e| RunError::output(&png, e))?;
    files.push(png);
    Ok(files)
}

/// The sweep's series and, on a ladder, its rows.
struct Study {
    /// The other key, if any.
    key: Option<String>,
    series: Vec<SpeedSeries>,
    /// The ladder's rows, when the other key is a refinement of three or more rungs.
    rows: Vec<SpeedLadderRow>,
}

impl Study {
    fn of(points: &[SweepPoint], i_series: Option<usize>) -> Study {
        let value = |p: &SweepPoint| {
            i_series.map_or(f64::NAN, |i| {
                p.sets[i]
                    .value
                    .trim_matches('"')
                    .parse::<f64>()
                    .unwrap_or(f64::NAN)
            })
        };
        let mut values: Vec<f64> = Vec::new();
        for p in points {
            let v = value(p);
            if !values.iter().any(|w| w.total_cmp(&v).is_eq()) {
                values.push(v);
            }
        }
        let key = i_series.map(|i| points[0].sets[i].key.clone());
        let refinement = key.as_deref().is_some_and(|k| !PHYSICAL_KEYS.contains(&k));
        if refinement {
            // A ladder's rungs coarsest to finest, whatever order they were written in.
            super::creep::coarse_to_fine(&mut values, points, value);
        }
        let series: Vec<SpeedSeries> = values
            .iter()
            .map(|&v| {
                let mut pts: Vec<SpeedPoint> = points
                    .iter()
                    .filter(|p| p.status.is_complete() && value(p).total_cmp(&v).is_eq())
                    .filter_map(SpeedPoint::of)
                    .collect();
                pts.sort_by(|a, b| a.speed.total_cmp(&b.speed));
                SpeedSeries {
                    value: v,
                    points: pts,
                }
            })
            .collect();
        let rows = if refinement && series.len() >= 3 {
            ladder_rows(&values, &series)
        } else {
            Vec::new()
        };
        Study { key, series, rows }
    }

    fn label(&self, s: &SpeedSeries) -> String {
        self.key
            .as_deref()
            .map_or("the run".to_string(), |k| format!("{k} = {}", s.value))
    }

    /// speed_effect.csv: every point with its series.
    fn csv(&self) -> String {
        let mut csv = record([
            self.key.as_deref().unwrap_or("series"),
            "speed_km_h",
            "normal_N",
            "normal_change",
            "traction_ratio",
            "traction_ratio_change",
            "lateral_ratio",
            "traction_ratio_window_spread",
        ]);
        for s in &self.series {
            let (dq, dn) = (s.ratio_change(), s.normal_change());
            for (k, p) in s.points.iter().enumerate() {
                push_record(
                    &mut csv,
                    [
                        format!("{}", s.value),
                        format!("{}", p.speed),
                        format!("{:e}", p.normal),
                        format!("{:e}", dn[k]),
                        format!("{:e}", p.ratio),
                        format!("{:e}", dq[k]),
                        format!("{:e}", p.lateral),
                        format!("{:e}", p.spread),
                    ],
                );
            }
        }
        csv
    }

    /// speed_effect.md: each series' figures and changes; the ladder's orders and limits.
    fn md(&self) -> String {
        let mut md = String::from(
            "The steady creep forces against the rim's speed, and their change from the slowest speed's (the quasi-static answer of the same model: inertia's share grows as the speed squared). `spread`: max - min of the run's four windows' Q/(mu N), the noise a change is read against.\n\n| series | km/h | N, kN | N change | Q/(mu N) | change | Q_y/(mu N) | spread |\n|---|---:|---:|---:|---:|---:|---:|---:|\n",
        );
        for s in &self.series {
            let (dq, dn) = (s.ratio_change(), s.normal_change());
            for (k, p) in s.points.iter().enumerate() {
                let _ = writeln!(
                    md,
                    "| {} | {} | {:.2} | {:+.3} % | {:.4} | {:+.5} | {:.4} | {:.5} |",
                    self.label(s),
                    p.speed,
                    1e-3 * p.normal,
                    100.0 * dn[k],
                    p.ratio,
                    dq[k],
                    p.lateral,
                    p.spread
                );
            }
        }
        if !self.rows.is_empty() {
            let key = self.key.as_deref().unwrap_or_default();
            let _ = write!(
                md,
                "\nThe change of Q/(mu N) from the slowest speed on each rung of {key}, its observed order and Richardson limit (the last three rungs)\n\n| km/h |"
            );
            for s in &self.series {
                let _ = write!(md, " {} |", s.value);
            }
            md.push_str(" order | limit |\n|---:|");
            for _ in &self.series {
                md.push_str("---:|");
            }
            md.push_str("---:|---:|\n");
            for r in &self.rows {
                let _ = write!(md, "| {} |", r.speed);
                for c in &r.changes {
                    let _ = write!(md, " {c:+.5} |");
                }
                let _ = writeln!(
                    md,
                    " {} | {} |",
                    r.order
                        .map_or("- (not asymptotic)".into(), |o| format!("{o:.2}")),
                    r.limit.map_or("-".into(), |l| format!("{l:+.5}"))
                );
            }
        }
        md
    }

    /// speed_effect.png: the change of Q/(mu N), and of N, against the speed.
    fn panels(&self) -> [Panel; 2] {
        let mut q = Panel::new(
            "Q / (mu N): change from the slowest speed",
            "rim speed, km/h",
            "change of Q / (mu N)",
        );
        let mut n = Panel::new(
            "N at the same flattening: change",
            "rim speed, km/h",
            "change of N, %",
        );
        for s in &self.series {
            let v: Vec<f64> = s.points.iter().map(|p| p.speed).collect();
            q.series.push(Series::new(
                self.label(s),
                v.clone(),
                s.ratio_change(),
                SeriesStyle::LineMarkers,
            ));
            n.series.push(Series::new(
                self.label(s),
                v,
                s.normal_change().iter().map(|c| 100.0 * c).collect(),
                SeriesStyle::LineMarkers,
            ));
        }
        // The last series' windows: the noise its changes are read against.
        if let Some(s) = self.series.last() {
            let base = s.points.first().map_or(f64::NAN, |p| p.ratio);
            let (v, w): (Vec<f64>, Vec<f64>) = s
                .points
                .iter()
                .flat_map(|p| p.windows.iter().map(move |w| (p.speed, w - base)))
                .unzip();
            if !v.is_empty() {
                q.series.push(Series::new(
                    // Short: a ladder's key and value would make the legend wider than
                    // the panel.
                    match self.key.as_deref() {
                        Some(k) if !PHYSICAL_KEYS.contains(&k) => {
                            "the finest rung's four windows".to_string()
                        }
                        Some(_) => "the last series' four windows".to_string(),
                        None => "the runs' four windows".to_string(),
                    },
                    v,
                    w,
                    SeriesStyle::Markers,
                ));
            }
        }
        let limits: Vec<(f64, f64)> = self
            .rows
            .iter()
            .filter_map(|r| Some((r.speed, r.limit?)))
            .collect();
        if !limits.is_empty() {
            q.series.push(Series::new(
                "Richardson limit of the ladder",
                limits.iter().map(|l| l.0).collect(),
                limits.iter().map(|l| l.1).collect(),
                SeriesStyle::Markers,
            ));
        }
        let spread = self
            .series
            .iter()
            .flat_map(|s| s.points.iter().map(|p| p.spread))
            .filter(|s| s.is_finite())
            .fold(0.0, f64::max);
        q.hlines = vec![(0.0, "the slowest speed (quasi-static)".into())];
        q.note = format!(
            "Q/(mu N): the steady rolling's (the mean of the last two windows, or their extrapolation); the largest spread of a run's four windows: {spread:.1e}"
        );
        [q, n]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn series(value: f64, law: impl Fn(f64) -> f64) -> SpeedSeries {
        SpeedSeries {
            value,
            points: [5.0, 50.0, 150.0, 300.0]
                .iter()
                .map(|&v| SpeedPoint {
                    speed: v,
                    normal: 1e5 * (1.0 + 1e-3 * (v / 300.0).powi(2)),
                    ratio: law(v),
                    lateral: 0.0,
                    spread: 0.0,
                    windows: Vec::new(),
                })
                .collect(),
        }
    }

    /// A change `c(V) (1 + e h^p)` on a ladder halving `h` gives back `p` and `c(V)` at
    /// every speed, and the changes are taken from the slowest speed.
    #[test]
    fn a_ladder_of_changes_gives_back_its_order_and_limit() {
        let c = |v: f64| 2e-3 * (v / 300.0).powi(2);
        let rungs = [384.0, 768.0, 1536.0];
        let all: Vec<SpeedSeries> = rungs
            .iter()
            .map(|&z| {
                let err = 1.0 + 0.5 * (384.0_f64 / z).powf(1.5);
                series(z, move |v| -0.3 + c(v) * err)
            })
            .collect();
        let d = all[0].ratio_change();
        assert!(
            d[0] == 0.0 && (d[3] - 1.5 * 2e-3 * (1.0 - (5.0f64 / 300.0).powi(2))).abs() < 1e-15
        );
        let rows = ladder_rows(&rungs, &all);
        assert_eq!(rows.len(), 3);
        for r in &rows {
            let exact = c(r.speed) - c(5.0);
            assert!((r.order.unwrap() - 1.5).abs() < 1e-9, "{r:?}");
            assert!(
                (r.limit.unwrap() - exact).abs() < 1e-12 * exact.abs().max(1e-3),
                "{r:?}"
            );
        }
        assert!(
            (all[0].normal_change()[3]
                - (1e-3 * (1.0 - (5.0f64 / 300.0).powi(2))
                    / (1.0 + 1e-3 * (5.0f64 / 300.0).powi(2))))
            .abs()
                < 1e-15
        );
    }

    /// Rungs that are not a ladder (two, or not geometric) get no order.
    #[test]
    fn no_order_off_a_ladder() {
        let two = [series(384.0, |v| v), series(768.0, |v| 0.5 * v)];
        assert!(ladder_rows(&[384.0, 768.0], &two)
            .iter()
            .all(|r| r.order.is_none() && r.limit.is_none()));
    }
}
