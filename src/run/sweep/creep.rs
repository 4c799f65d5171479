//! The creep curve on a refinement ladder: a creepage sweep run on every rung of a mesh (or
//! step) ladder (`[sweep] ladder = { key, values }`, or `softway sweep --set
//! rolling.creepage=... --set wheel.zone_rim_nodes=4608,9216,18432`) gives the creep curve
//! on each rung and, at the traction ratios `Q / (mu P)` = -0.5, 0 (free rolling) and +0.5,
//! the creepage on each rung, its observed order and its Richardson limit
//! ([`crate::run::converge`]'s): the converged creep curve with the estimate of the finest
//! rung's remaining error.
//!
//! On each rung the creepage at a traction ratio `T` is the root, between the two sweep
//! points that bracket `T`, of the parabola through them and the nearer third point
//! ([`creepage_at`]); the traction ratio of a point is the steady one
//! (`traction.traction_ratio_steady`: the start-up transient extrapolated,
//! [`crate::kinds::wheel::run::traction::steady_ratio`]). The creepage is read on the undeformed
//! radius (`traction.creepage_undeformed`, the half-space codes' reference) and given in
//! units of `mu a / R` as well (`a` Hertz's half-width of the finest rung's mean normal
//! force, `R` the wheel's radius), the unit in which Carter's curve saturates at 1.
//!
//! Files: `creep_curve.png` (a curve per rung, the limits marked), `creep_curve.csv` (every
//! point, a row each, with its rung), `creep_ladder.csv` and `creep_ladder.md` (the
//! creepages at the three traction ratios, the orders, the limits and the finest rung's
//! distance from them).

use super::{SweepError, SweepPoint};
use crate::analysis::reference_curve::ReferenceCurve;
use crate::analysis::richardson::{extrapolate, observed_orders};
use crate::output::csv::{push_record, record};
use crate::output::plot::{panels, Panel, Series, SeriesStyle};
use crate::run::RunError;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The traction ratios `Q / (mu P)` at which the ladder's creepages are compared.
pub const TARGETS: [f64; 3] = [-0.5, 0.0, 0.5];

/// The creepage at which the creep curve `pts` (`(creepage, Q/(mu P))`, sorted by
/// creepage) reaches the traction ratio `target`: between the first two neighbouring points
/// that bracket it, the root of the parabola through them and the nearer of their outer
/// neighbours (the line through the two when there is no third point). `None` when no two
/// neighbours bracket `target`.
pub fn creepage_at(pts: &[(f64, f64)], target: f64) -> Option<f64> {
    let k = pts.windows(2).position(|w| {
        let (a, b) = (w[0].1 - target, w[1].1 - target);
        a.is_finite() && b.is_finite() && a * b <= 0.0 && w[0].0 < w[1].0
    })?;
    let ((x0, y0), (x1, y1)) = (pts[k], pts[k + 1]);
    if y0 == target {
        return Some(x0);
    }
    if y1 == target {
        return Some(x1);
    }
    // The third point: the outer neighbour nearer to the bracket.
    let before = k.checked_sub(1).map(|i| pts[i]);
    let after = pts.get(k + 2).copied();
    let third = match (before, after) {
        (Some(b), Some(a)) => Some(if x0 - b.0 <= a.0 - x1 { b } else { a }),
        (b, a) => b.or(a),
    }
    .filter(|p| p.1.is_finite());
    let f = |x: f64| -> f64 {
        let line = y0 + (y1 - y0) * (x - x0) / (x1 - x0);
        match third {
            // Newton's form through (x0, y0), (x1, y1), (x2, y2).
            Some((x2, y2)) => {
                let f01 = (y1 - y0) / (x1 - x0);
                let f12 = (y2 - y1) / (x2 - x1);
                let f012 = if (x2 - x1).abs() > 0.0 && (x2 - x0).abs() > 0.0 {
                    (f12 - f01) / (x2 - x0)
                } else {
                    0.0
                };
                line + f012 * (x - x0) * (x - x1) - target
            }
            None => line - target,
        }
    };
    // Bisection on the bracket: the interpolant takes y0 and y1 at its ends.
    let (mut lo, mut hi) = (x0, x1);
    let mut f_lo = f(lo);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        let f_mid = f(mid);
        if (f_mid <= 0.0) == (f_lo <= 0.0) {
            lo = mid;
            f_lo = f_mid;
        } else {
            hi = mid;
        }
    }
    Some(0.5 * (lo + hi))
}

/// The slope `d(Q/(mu P)) / d(creepage)` of the creep curve `pts` where it reaches the
/// traction ratio `target`: the inverse of the central difference of [`creepage_at`] over
/// `target +- 0.02` (the same interpolant's inverse). `None` when the curve does not
/// bracket both.
pub fn slope_at(pts: &[(f64, f64)], target: f64) -> Option<f64> {
    const D: f64 = 0.02;
    let (lo, hi) = (creepage_at(pts, target - D)?, creepage_at(pts, target + D)?);
    (hi != lo).then(|| 2.0 * D / (hi - lo))
}

/// The least observed order from which a limit is extrapolated: below it the differences
/// shrink so slowly that the limit lies far beyond the ladder (an order of 0.3 on a ladder
/// halving the pitch puts it 4 differences beyond the finest rung): the rungs are not yet
/// in the asymptotic range.
pub const MIN_ORDER: f64 = 0.5;

/// The largest: beyond it the differences collapse faster than any discretization of the
/// problem converges (a chance agreement of two rungs).
pub const MAX_ORDER: f64 = 4.0;

/// The ladder's creepages at one traction ratio.
#[derive(Debug, Clone, PartialEq)]
pub struct LadderRow {
    /// The traction ratio `Q / (mu P)`.
    pub target: f64,
    /// The creepage on the undeformed radius at each rung (NaN where the rung's curve does
    /// not reach the target).
    pub values: Vec<f64>,
    /// The observed order from the last three rungs (`None`: fewer than three rungs, or
    /// differences that do not shrink at an order within [`MIN_ORDER`] to [`MAX_ORDER`]:
    /// not in the asymptotic range).
    pub order: Option<f64>,
    /// The Richardson limit from the last three rungs, when there is an order.
    pub limit: Option<f64>,
}

impl LadderRow {
    /// The finest rung's distance from the limit (its estimated remaining error), when
    /// there is a limit.
    pub fn finest_error(&self) -> Option<f64> {
        Some(self.values.last()? - self.limit?)
    }
}

/// The rungs `rungs` (values of one key) from the coarsest to the finest, whatever the order
/// they were written in: by the unknowns of their complete runs (more is finer), then by
/// the step (smaller is finer); rungs alike in both keep their order. `rung_of` gives a
/// point's rung. A ladder written finest first (`wheel.zone_sectors=1536,768,384`) is the
/// same study as one written coarsest first.
pub fn coarse_to_fine(
    rungs: &mut [f64],
    points: &[SweepPoint],
    rung_of: impl Fn(&SweepPoint) -> f64,
) {
    let size = |r: f64| {
        let runs: Vec<&SweepPoint> = points
            .iter()
            .filter(|p| p.status.is_complete() && rung_of(p).to_bits() == r.to_bits())
            .collect();
        let mean = |key: &str| {
            let v: Vec<f64> = runs
                .iter()
                .filter_map(|p| p.summary.get(key).and_then(serde_json::Value::as_f64))
                .collect();
            if v.is_empty() {
                f64::NAN
            } else {
                v.iter().sum::<f64>() / v.len() as f64
            }
        };
        (mean("dofs"), mean("h_s"))
    };
    let known: Vec<(f64, f64)> = rungs.iter().map(|&r| size(r)).collect();
    if known.iter().any(|(d, h)| d.is_nan() || h.is_nan()) {
        return;
    }
    let mut order: Vec<usize> = (0..rungs.len()).collect();
    order.sort_by(|&a, &b| {
        known[a]
            .0
            .total_cmp(&known[b].0)
            .then(known[b].1.total_cmp(&known[a].1))
    });
    let sorted: Vec<f64> = order.iter().map(|&i| rungs[i]).collect();
    rungs.copy_from_slice(&sorted);
}

/// Whether the rungs are a refinement ladder of three or more
/// ([`crate::scenario::overrides::ladder_rungs`]): a `--set` grid may be anything.
pub fn is_ladder(rungs: &[f64]) -> bool {
    let strings: Vec<String> = rungs.iter().map(|r| r.to_string()).collect();
    crate::scenario::overrides::ladder_rungs(&strings, 3).is_ok()
}

/// The observed order of `values` on the rungs `rungs` from the last three, and their
/// Richardson limit, when every value is finite and the order lies within [`MIN_ORDER`] to
/// [`MAX_ORDER`] (else `(None, None)`: not in the asymptotic range).
pub fn order_and_limit(rungs: &[f64], values: &[f64]) -> (Option<f64>, Option<f64>) {
    if !values.iter().all(|v| v.is_finite()) {
        return (None, None);
    }
    let orders = observed_orders(rungs, values);
    let order = orders.last().copied().flatten();
    if order.is_some_and(|p| (MIN_ORDER..=MAX_ORDER).contains(&p)) {
        (order, extrapolate(rungs, values, &orders))
    } else {
        (None, None)
    }
}

/// The ladder's rows at [`TARGETS`] from the creep curves `curves` (one per rung, at the
/// rung sizes `rungs`, each `(creepage, Q/(mu P))` sorted by creepage). Orders and limits
/// only where the rungs are a ladder (three or more at one ratio,
/// [`crate::scenario::overrides::ladder_rungs`]).
pub fn ladder_rows(rungs: &[f64], curves: &[Vec<(f64, f64)>]) -> Vec<LadderRow> {
    // Orders only on three or more rungs at one ratio (a `--set` grid may be anything).
    let regular = is_ladder(rungs);
    TARGETS
        .iter()
        .map(|&target| {
            let values: Vec<f64> = curves
                .iter()
                .map(|c| creepage_at(c, target).unwrap_or(f64::NAN))
                .collect();
            let (order, limit) = if regular {
                order_and_limit(rungs, &values)
            } else {
                (None, None)
            };
            LadderRow {
                target,
                values,
                order,
                limit,
            }
        })
        .collect()
}

/// One rung's points: `(creepage on rho, creepage on R, steady Q/(mu P), window-mean Q/(mu
/// P), mu, a, R)`.
type RungPoint = (f64, f64, f64, f64, f64, f64, f64);

/// Writes the creep curve on the ladder (module docs) of a sweep whose key `i_creep` is
/// `rolling.creepage` and whose key `i_rung` is the ladder's (numbers), from its complete
/// points; returns the files.
///
/// # Errors
/// [`SweepError`] when a file cannot be written.
pub fn creep_ladder(
    out: &Path,
    points: &[SweepPoint],
    i_creep: usize,
    i_rung: usize,
) -> Result<Vec<PathBuf>, SweepError> {
    let ladder = Ladder::of(points, i_creep, i_rung);
    let write = |name: &str, text: String| super::write_text(out, name, &text);
    let mut files = vec![
        write("creep_curve.csv", ladder.points_csv())?,
        write("creep_ladder.csv", ladder.targets_csv())?,
        write("creep_ladder.md", ladder.targets_md())?,
    ];
    let png = out.join("creep_curve.png");
    panels(&png, &[ladder.panel()], 1, 1, (1100, 750)).map_err(|e| RunError::output(&png, e))?;
    files.push(png);
    Ok(files)
}

/// The creep curve on each rung of a ladder, and the creepages at the targets.
struct Ladder {
    rung_key: String,
    /// The rungs in the order given.
    rungs: Vec<f64>,
    /// Each rung's complete points, by creepage.
    curves: Vec<Vec<RungPoint>>,
    /// mu a / R from the finest rung's points.
    unit: f64,
    /// The creepages at the targets ([`ladder_rows`]).
    rows: Vec<LadderRow>,
    /// Another code's curve the points name (`traction.reference`), and its creepages at
    /// the targets, `mu a / R`.
    reference: Option<(ReferenceCurve, Vec<Option<f64>>)>,
    /// The creep curve's slope at free rolling on each rung, `d(Q/(mu P)) / d(xi_R / (mu
    /// a / R))` ([`slope_at`]), its order and limit, and the reference's.
    slopes: Vec<f64>,
    slope_fit: (Option<f64>, Option<f64>),
    reference_slope: Option<f64>,
    /// Kalker's scale of a creep coefficient in these units: `C = slope N R / (a G c^2)`
    /// (`dQ/dxi / (G c^2)`), from the finest rung's summaries' `hertz3d` (NaN without).
    kalker_factor: f64,
}

impl Ladder {
    fn of(points: &[SweepPoint], i_creep: usize, i_rung: usize) -> Ladder {
        let num = super::traction_figure;
        let value = |p: &SweepPoint, i: usize| {
            p.sets[i]
                .value
                .trim_matches('"')
                .parse::<f64>()
                .unwrap_or(f64::NAN)
        };
        let rung_key = points[0].sets[i_rung].key.clone();
        let mut rungs: Vec<f64> = Vec::new();
        for p in points {
            let r = value(p, i_rung);
            if !rungs.contains(&r) {
                rungs.push(r);
            }
        }
        coarse_to_fine(&mut rungs, points, |p| value(p, i_rung));
        let curves: Vec<Vec<RungPoint>> = rungs
            .iter()
            .map(|&r| {
                let mut c: Vec<RungPoint> = points
                    .iter()
                    .filter(|p| p.status.is_complete() && value(p, i_rung) == r)
                    .map(|p| {
                        let xr = num(p, "creepage_undeformed");
                        let x = value(p, i_creep);
                        (
                            x,
                            if xr.is_finite() { xr } else { x },
                            super::steady_traction_ratio(p),
                            num(p, "traction_ratio"),
                            num(p, "friction"),
                            num(p, "hertz_half_width"),
                            num(p, "radius"),
                        )
                    })
                    .collect();
                c.sort_by(|a, b| a.0.total_cmp(&b.0));
                c
            })
            .collect();
        let finest = curves.iter().rev().find(|c| !c.is_empty());
        let unit = finest.map_or(f64::NAN, |c| {
            let n = c.len() as f64;
            let (mu, a, r) = c.iter().fold((0.0, 0.0, 0.0), |s, p| {
                (s.0 + p.4 / n, s.1 + p.5 / n, s.2 + p.6 / n)
            });
            mu * a / r
        });
        let on_r: Vec<Vec<(f64, f64)>> = curves
            .iter()
            .map(|c| c.iter().map(|p| (p.1, p.2)).collect())
            .collect();
        let rows = ladder_rows(&rungs, &on_r);
        let reference = points
            .iter()
            .filter(|p| p.status.is_complete())
            .find_map(|p| ReferenceCurve::from_summary(&p.summary))
            .map(|rc| {
                let at = TARGETS
                    .iter()
                    .map(|&t| creepage_at(&rc.points, t))
                    .collect();
                (rc, at)
            });
        let slopes: Vec<f64> = on_r
            .iter()
            .map(|c| {
                let c: Vec<(f64, f64)> = c.iter().map(|p| (p.0 / unit, p.1)).collect();
                slope_at(&c, 0.0).unwrap_or(f64::NAN)
            })
            .collect();
        let slope_fit = if is_ladder(&rungs) {
            order_and_limit(&rungs, &slopes)
        } else {
            (None, None)
        };
        let reference_slope = reference
            .as_ref()
            .and_then(|(rc, _)| slope_at(&rc.points, 0.0));
        let finest_pts: Vec<&SweepPoint> = points
            .iter()
            .filter(|p| p.status.is_complete() && Some(&value(p, i_rung)) == rungs.last())
            .collect();
        let kalker_factor = {
            let n = finest_pts.len() as f64;
            let mean =
                |f: &dyn Fn(&SweepPoint) -> f64| finest_pts.iter().map(|p| f(p)).sum::<f64>() / n;
            let h = |p: &SweepPoint, k: &str| {
                p.summary
                    .pointer(&format!("/hertz3d/{k}"))
                    .and_then(serde_json::Value::as_f64)
                    .unwrap_or(f64::NAN)
            };
            let (nn, r, a) = (
                mean(&|p| num(p, "normal")),
                mean(&|p| num(p, "radius")),
                mean(&|p| num(p, "hertz_half_width")),
            );
            let (g, c) = (
                mean(&|p| h(p, "combined_shear_modulus_Pa")),
                mean(&|p| h(p, "c_m")),
            );
            nn * r / (a * g * c * c)
        };
        Ladder {
            rung_key,
            rungs,
            curves,
            unit,
            rows,
            reference,
            slopes,
            slope_fit,
            reference_slope,
            kalker_factor,
        }
    }

    /// creep_curve.csv: every point with its rung.
    fn points_csv(&self) -> String {
        let unit = self.unit;
        let mut csv = record([
            self.rung_key.as_str(),
            "creepage",
            "creepage_undeformed",
            "creepage_undeformed_mu_a_R",
            "traction_ratio",
            "traction_ratio_window",
        ]);
        for (r, c) in self.rungs.iter().zip(&self.curves) {
            for p in c {
                push_record(
                    &mut csv,
                    [
                        format!("{r}"),
                        format!("{:e}", p.0),
                        format!("{:e}", p.1),
                        format!("{:.6}", p.1 / unit),
                        format!("{:e}", p.2),
                        format!("{:e}", p.3),
                    ],
                );
            }
        }
        csv
    }

    /// creep_ladder.csv: the creepages at the targets on each rung, the order, the limit
    /// and the finest rung's distance from it.
    fn targets_csv(&self) -> String {
        let unit = self.unit;
        let head: Vec<String> = self
            .rungs
            .iter()
            .map(|r| format!("{}={r}", self.rung_key))
            .collect();
        let mut cells = vec!["traction_ratio".to_string()];
        for h in &head {
            cells.push(format!("creepage_undeformed@{h}"));
            cells.push(format!("mu_a_R@{h}"));
        }
        cells.extend(
            [
                "order",
                "richardson_limit",
                "richardson_limit_mu_a_R",
                "finest_minus_limit_mu_a_R",
                "reference_mu_a_R",
                "limit_minus_reference_mu_a_R",
                "finest_minus_reference_mu_a_R",
            ]
            .map(String::from),
        );
        let mut csv = record(&cells);
        for (k, row) in self.rows.iter().enumerate() {
            let rf = self.reference_at(k);
            let mut cells = vec![format!("{}", row.target)];
            for v in &row.values {
                let abs = if v.is_finite() {
                    format!("{v:e}")
                } else {
                    String::new()
                };
                cells.push(abs);
                cells.push(fixed(Some(v / unit), 6));
            }
            cells.extend([
                fixed(row.order, 4),
                row.limit.map_or(String::new(), |l| format!("{l:e}")),
                fixed(row.limit.map(|l| l / unit), 6),
                fixed(row.finest_error().map(|e| e / unit), 6),
                fixed(rf, 6),
                fixed(row.limit.zip(rf).map(|(l, r)| l / unit - r), 6),
                fixed(row.values.last().zip(rf).map(|(v, r)| v / unit - r), 6),
            ]);
            push_record(&mut csv, &cells);
        }
        csv
    }

    /// creep_ladder.md: the table of [`Ladder::targets_csv`] in units of mu a / R.
    fn targets_md(&self) -> String {
        let (unit, rung_key) = (self.unit, &self.rung_key);
        let mut md = format!(
            "Creepage on the undeformed radius in units of mu a / R = {unit:.4e}, at Q/(mu P) on each rung of {rung_key}; the Richardson limit from the last three rungs and the finest rung's distance from it\n\n| Q/(mu P) |"
        );
        for r in &self.rungs {
            let _ = write!(md, " {r} |");
        }
        md.push_str(" order | limit | finest - limit |");
        if let Some((rc, _)) = &self.reference {
            let _ = write!(
                md,
                " reference ({}) | finest - reference | limit - reference |",
                rc.name()
            );
        }
        md.push_str("\n|---|");
        for _ in &self.rungs {
            md.push_str("---:|");
        }
        md.push_str("---:|---:|---:|");
        if self.reference.is_some() {
            md.push_str("---:|---:|---:|");
        }
        md.push('\n');
        for (k, row) in self.rows.iter().enumerate() {
            let _ = write!(md, "| {:+.1} |", row.target);
            for v in &row.values {
                let _ = write!(md, " {} |", fixed(Some(v / unit), 4));
            }
            let err = row.finest_error().map(|e| {
                format!(
                    "{:+.4} ({:+.2} %)",
                    e / unit,
                    100.0 * e / row.limit.unwrap_or(f64::NAN)
                )
            });
            let _ = write!(
                md,
                " {} | {} | {} |",
                row.order
                    .map_or("- (not asymptotic)".to_string(), |o| format!("{o:.2}")),
                fixed(row.limit.map(|l| l / unit), 4),
                err.unwrap_or_default()
            );
            if self.reference.is_some() {
                let rf = self.reference_at(k);
                let _ = write!(
                    md,
                    " {} | {} | {} |",
                    fixed(rf, 4),
                    fixed(row.values.last().zip(rf).map(|(v, r)| v / unit - r), 4),
                    fixed(row.limit.zip(rf).map(|(l, r)| l / unit - r), 4)
                );
            }
            md.push('\n');
        }
        if let Some((rc, _)) = &self.reference {
            let _ = writeln!(
                md,
                "\nreference: {} (its creepages at the traction ratios found as the rungs' are: the root of the parabola through the two points that bracket the ratio and the nearer third)",
                rc.file
            );
        }
        md.push_str(&self.slope_md());
        md
    }

    /// The slope at free rolling on each rung, its order and limit, the reference's, and
    /// the same as Kalker's coefficient `C = dQ/dxi / (G c^2)` when the summaries give `G`
    /// and `c`.
    fn slope_md(&self) -> String {
        let k = self.kalker_factor;
        let (order, limit) = self.slope_fit;
        let mut md = format!(
            "\nThe creep curve's slope at free rolling, d(Q/(mu P)) / d(xi_R / (mu a / R)), on each rung of {}{}\n\n| |",
            self.rung_key,
            if k.is_finite() {
                format!(", and as Kalker's coefficient C = (dQ/dxi_R) / (G c^2) = slope x N R / (a G c^2) = slope x {k:.4}")
            } else {
                String::new()
            }
        );
        for r in &self.rungs {
            let _ = write!(md, " {r} |");
        }
        md.push_str(" order | limit | reference | finest - reference | limit - reference |\n|---|");
        for _ in &self.rungs {
            md.push_str("---:|");
        }
        md.push_str("---:|---:|---:|---:|---:|\n");
        let rf = self.reference_slope;
        let mut row = |name: &str, f: f64| {
            let _ = write!(md, "| {name} |");
            for v in &self.slopes {
                let _ = write!(md, " {} |", fixed(Some(v * f), 4));
            }
            let _ = writeln!(
                md,
                " {} | {} | {} | {} | {} |",
                order.map_or("- (not asymptotic)".to_string(), |o| format!("{o:.2}")),
                fixed(limit.map(|l| l * f), 4),
                fixed(rf.map(|r| r * f), 4),
                fixed(self.slopes.last().zip(rf).map(|(v, r)| (v - r) * f), 4),
                fixed(limit.zip(rf).map(|(l, r)| (l - r) * f), 4),
            );
        };
        row("slope", 1.0);
        if k.is_finite() {
            row("C", k);
        }
        md
    }

    /// creep_curve.png: a curve per rung, the limits marked.
    fn panel(&self) -> Panel {
        let (unit, rung_key, rows) = (self.unit, &self.rung_key, &self.rows);
        let mut panel = Panel::new(
            format!(
                "Creep curve on the ladder {rung_key} = {}: mu a / R = {}",
                self.rungs
                    .iter()
                    .map(|r| r.to_string())
                    .collect::<Vec<_>>()
                    .join(", "),
                crate::output::plot::sig(unit, 3)
            ),
            "creepage on the undeformed radius, xi_R / (mu a / R)",
            "Q / (mu P)",
        );
        for (r, c) in self.rungs.iter().zip(&self.curves) {
            if c.is_empty() {
                continue;
            }
            panel.series.push(Series::new(
                format!("{rung_key} = {r}"),
                c.iter().map(|p| p.1 / unit).collect(),
                c.iter().map(|p| p.2).collect(),
                SeriesStyle::LineMarkers,
            ));
        }
        let limits: Vec<(f64, f64)> = rows
            .iter()
            .filter_map(|r| Some((r.limit? / unit, r.target)))
            .collect();
        if !limits.is_empty() {
            panel.series.push(Series::new(
                "Richardson limit of the ladder",
                limits.iter().map(|l| l.0).collect(),
                limits.iter().map(|l| l.1).collect(),
                SeriesStyle::Markers,
            ));
        }
        if let Some((rc, _)) = &self.reference {
            // The reference over the sweep's creepages and a quarter of their span beyond.
            let xs = self.curves.iter().flatten().map(|p| p.1 / unit);
            let (lo, hi) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), x| {
                (l.min(x), h.max(x))
            });
            panel
                .series
                .push(super::figures::reference_series(rc, (lo, hi), |x| x));
        }
        panel.hlines = vec![(1.0, "full slip, Q = mu P".into()), (-1.0, String::new())];
        panel.y_range = Some((-1.15, 1.15));
        panel.note = format!(
            "Q/(mu P): the steady rolling's (the start-up transient extrapolated). Finest rung at Q/(mu P) = -0.5 / 0 / +0.5: {}",
            rows.iter()
                .map(|r| match (r.values.last().filter(|v| v.is_finite()), r.limit) {
                    (Some(v), Some(l)) => format!("{:.4} (limit {:.4})", v / unit, l / unit),
                    (Some(v), None) => format!("{:.4} (no limit: not asymptotic)", v / unit),
                    _ => "-".into(),
                })
                .collect::<Vec<_>>()
                .join(" / ")
        );
        if self.reference.is_some() {
            let _ = write!(
                panel.note,
                "; reference: {}",
                (0..rows.len())
                    .map(|k| self
                        .reference_at(k)
                        .map_or("-".into(), |r| format!("{r:.4}")))
                    .collect::<Vec<_>>()
                    .join(" / ")
            );
        }
        panel
    }
}

impl Ladder {
    /// The reference's creepage at the `k`-th target, `mu a / R`.
    fn reference_at(&self, k: usize) -> Option<f64> {
        self.reference.as_ref().and_then(|(_, at)| at[k])
    }
}

/// `v` with `digits` decimals, empty when missing or not finite.
fn fixed(v: Option<f64>, digits: usize) -> String {
    v.filter(|x| x.is_finite())
        .map_or(String::new(), |x| format!("{x:.digits$}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A quadratic creep curve is inverted exactly between any bracketing points (the
    /// parabola through three of its points is itself); a cubic to the interpolation's
    /// third order; a target outside the points has no creepage.
    #[test]
    fn creepage_at_inverts_the_curve_through_its_points() {
        let quad = |x: f64| -0.8 + 3.0 * x - 0.9 * x * x;
        let xs = [-0.2, 0.1, 0.3, 0.5, 0.8, 1.2];
        let pts: Vec<(f64, f64)> = xs.iter().map(|&x| (x, quad(x))).collect();
        for t in TARGETS {
            // The root of -0.8 + 3x - 0.9x^2 = t on the rising branch.
            let exact = (3.0 - (9.0 - 3.6 * (0.8 + t)).sqrt()) / 1.8;
            let x = creepage_at(&pts, t).unwrap();
            assert!((x - exact).abs() < 1e-12, "{t}: {x} vs {exact}");
        }
        assert!(creepage_at(&pts, 2.0).is_none());
        // Two points: the line.
        assert_eq!(creepage_at(&[(0.0, -1.0), (1.0, 1.0)], 0.0), Some(0.5));
        let cubic = |x: f64| x * x * x + x;
        let pts: Vec<(f64, f64)> = (0..=10)
            .map(|i| 0.1 * i as f64 - 0.5)
            .map(|x| (x, cubic(x)))
            .collect();
        let x = creepage_at(&pts, cubic(0.23)).unwrap();
        assert!((x - 0.23).abs() < 2e-3, "{x}");
    }

    /// On a ladder whose creepages converge as `x* + C h^p` (h halved each rung) the rows
    /// give back `p` and `x*`; a ladder whose differences grow, or shrink at an order below
    /// [`MIN_ORDER`], has no order and no limit.
    #[test]
    fn ladder_rows_give_the_order_and_the_limit() {
        let rungs: [f64; 3] = [4608.0, 9216.0, 18432.0];
        // Curves Q/(mu P) = 2 (xi - x0) with x0 = 0.6 - 0.3 (4608 / n)^1.2.
        let curves: Vec<Vec<(f64, f64)>> = rungs
            .iter()
            .map(|&n| {
                let x0 = 0.6 - 0.3 * (4608.0f64 / n).powf(1.2);
                (0..8)
                    .map(|i| {
                        let x = 0.2 * i as f64;
                        (x, 2.0 * (x - x0))
                    })
                    .collect()
            })
            .collect();
        let rows = ladder_rows(&rungs, &curves);
        for row in &rows {
            assert!((row.order.unwrap() - 1.2).abs() < 1e-9, "{row:?}");
            let limit = 0.6 + row.target / 2.0;
            assert!((row.limit.unwrap() - limit).abs() < 1e-12, "{row:?}");
            let finest = row.finest_error().unwrap();
            assert!((finest + 0.3 * 0.25f64.powf(1.2)).abs() < 1e-12, "{finest}");
        }
        let growing: Vec<Vec<(f64, f64)>> = [0.0, 0.1, 0.3]
            .iter()
            .map(|&x0| vec![(-1.0, 2.0 * (-1.0 - x0)), (2.0, 2.0 * (2.0 - x0))])
            .collect();
        let rows = ladder_rows(&rungs, &growing);
        assert!(rows.iter().all(|r| r.order.is_none() && r.limit.is_none()));
        // Rungs not at one ratio: no order (it would assume one).
        let rows = ladder_rows(&[4608.0, 9216.0, 36864.0], &curves);
        assert!(rows.iter().all(|r| r.order.is_none() && r.limit.is_none()));
        // Differences that shrink at an order of 0.27 (below MIN_ORDER): no limit either.
        let slow: Vec<Vec<(f64, f64)>> = rungs
            .iter()
            .map(|&n: &f64| {
                let x0 = 0.6 - 0.3 * (4608.0f64 / n).powf(0.27);
                vec![(-1.0, 2.0 * (-1.0 - x0)), (2.0, 2.0 * (2.0 - x0))]
            })
            .collect();
        let rows = ladder_rows(&rungs, &slow);
        assert!(rows.iter().all(|r| r.order.is_none() && r.limit.is_none()));
    }
}
