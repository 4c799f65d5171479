//! The 3D rolling under refinement of its mesh and its step: the steady creep force, the slip
//! area and the ripple of the forces, and how far the histories lie apart from rung to rung
//! (`slip_history.md`, `.csv` and `.png`). It is the study for a friction coefficient falling
//! with the slip speed, whose micro-slip explicit codes have seen oscillate for numerical
//! reasons; it applies to Coulomb's law as well.
//!
//! A sweep of a `rolling3d` scenario over the zone's pitch (`wheel.zone_sectors`), the step
//! (`time.h`) or both (their product, `[sweep] key = "time.h"` with `ladder = { key =
//! "wheel.zone_sectors", ... }`, or `--grid zip`) reads each point's steady figures from
//! its `summary.json`, `steady`:
//! - `Q / (mu_s N)`, the mean of the last half of the rolling (not the windows'
//!   extrapolation, which the ripple would disturb; `mu_s` the coefficient at rest);
//! - the slip share: the mean count of sliding nodes over the mean count of nodes in contact;
//! - the ripple: the RMS of `Q / (mu_s N)` about its mean, with its strongest frequency,
//!   against the rim pitch's passage through the patch, `omega sectors / (2 pi)`.
//!
//! It reads each point's history from `history.csv`.
//!
//! **Lines.** The points fall on lines of one refinement:
//! - the mesh at each step;
//! - the step at each mesh;
//! - when both vary, the diagonals on which `sectors x h` is constant, so that the rim's
//!   pitch is crossed in the same number of steps.
//!
//! On a line of three or more rungs at one ratio, the steady `Q / (mu_s N)` and slip share
//! get their observed order and Richardson limit ([`super::creep::order_and_limit`]).
//!
//! **Histories.** Between successive rungs of a line, the histories' distance is the RMS of
//! the finer's history (interpolated linearly) less the coarser's, over the coarser's samples
//! from the end of the load's ramp (`steady.from_s / 2`) to the run's end. It is taken for
//! `Q / (mu_s N)` and for the slip share. Two distances give the histories' order,
//! `ln(d_1 / d_2) / ln r`.
//!
//! **The figure** draws four panels:
//! - the histories of the longest line (the diagonal when both keys vary), each averaged over
//!   one pitch's passage (the ripple that the pitch puts on the forces is the mesh's own);
//! - the steady `Q / (mu_s N)` and slip share against the zone's pitch, with the limits;
//! - the ripple against the zone's pitch.

use super::{SweepError, SweepPoint};
use crate::output::csv::{number_cells, push_record, record};
use crate::output::plot::{panels, Panel, Series, SeriesStyle};
use crate::run::RunError;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The key of the zone's pitch (a count round the rim).
pub const MESH_KEY: &str = "wheel.zone_sectors";
/// The key of the step.
pub const STEP_KEY: &str = "time.h";

/// Whether the sweep over `keys`, of which `varying` vary, is a refinement study of
/// rolling 3D points: every varying key is [`MESH_KEY`] or [`STEP_KEY`], with numbers.
pub fn applies(points: &[SweepPoint], keys: &[String], varying: &[usize]) -> bool {
    let rolling3d = points
        .iter()
        .any(|p| p.summary["kind"].as_str() == Some("rolling3d"));
    let numeric = |i: usize| {
        points
            .iter()
            .all(|p| p.sets[i].value.trim_matches('"').parse::<f64>().is_ok())
    };
    rolling3d
        && !varying.is_empty()
        && varying
            .iter()
            .all(|&i| [MESH_KEY, STEP_KEY].contains(&keys[i].as_str()) && numeric(i))
}

/// A run's history after the load's ramp: time, `Q / (mu_s N)` and the slip share.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct History {
    /// Time, s.
    pub t: Vec<f64>,
    /// `Q / (mu_s N)`.
    pub ratio: Vec<f64>,
    /// Sliding nodes over nodes in contact (0 without contact).
    pub share: Vec<f64>,
}

impl History {
    /// Reads `history.csv` of a `rolling3d` run (its `t_s`, `traction_ratio`,
    /// `nodes_in_contact` and `nodes_sliding` columns), from `from` seconds on; `None` when
    /// the file or a column is missing.
    fn read(file: &Path, from: f64) -> Option<History> {
        let text = std::fs::read_to_string(file).ok()?;
        let mut lines = text.lines();
        let header: Vec<&str> = lines.next()?.split(',').map(str::trim).collect();
        let col = |name: &str| header.iter().position(|h| *h == name);
        let (it, ir, ic, is) = (
            col("t_s")?,
            col("traction_ratio")?,
            col("nodes_in_contact")?,
            col("nodes_sliding")?,
        );
        let mut h = History::default();
        for line in lines {
            let cells: Vec<f64> = number_cells(line)
                .map(|c| c.parse::<f64>().unwrap_or(f64::NAN))
                .collect();
            let t = *cells.get(it)?;
            if t < from {
                continue;
            }
            let (held, sliding) = (*cells.get(ic)?, *cells.get(is)?);
            h.t.push(t);
            h.ratio.push(*cells.get(ir)?);
            h.share.push(if held > 0.0 {
                sliding.min(held) / held
            } else {
                0.0
            });
        }
        (!h.t.is_empty()).then_some(h)
    }
}

/// The RMS of `fine` (interpolated linearly at `coarse`'s times) less `coarse`, over
/// `coarse`'s samples within `fine`'s time span; NaN when none is.
pub fn history_distance(coarse: (&[f64], &[f64]), fine: (&[f64], &[f64])) -> f64 {
    let (tc, yc) = coarse;
    let (tf, yf) = fine;
    let (Some(&t0), Some(&t1)) = (tf.first(), tf.last()) else {
        return f64::NAN;
    };
    let mut j = 0;
    let (mut sum, mut n) = (0.0, 0usize);
    let tol = 1e-9 * (t1 - t0).abs().max(f64::MIN_POSITIVE);
    for (&t, &y) in tc.iter().zip(yc) {
        if t < t0 - tol || t > t1 + tol {
            continue;
        }
        while j + 1 < tf.len() && tf[j + 1] < t {
            j += 1;
        }
        let v = if j + 1 < tf.len() && tf[j + 1] > tf[j] {
            let w = ((t - tf[j]) / (tf[j + 1] - tf[j])).clamp(0.0, 1.0);
            yf[j] + w * (yf[j + 1] - yf[j])
        } else {
            yf[j]
        };
        sum += (v - y).powi(2);
        n += 1;
    }
    if n == 0 {
        f64::NAN
    } else {
        (sum / n as f64).sqrt()
    }
}

/// The order `ln(d_1 / d_2) / ln r` of two successive distances on a ladder of ratio `r`;
/// `None` unless both are positive and finite and `r > 1`.
pub fn distance_order(d1: f64, d2: f64, r: f64) -> Option<f64> {
    (d1 > 0.0 && d2 > 0.0 && d1.is_finite() && d2.is_finite() && r > 1.0)
        .then(|| (d1 / d2).ln() / r.ln())
}

/// One run's figures.
#[derive(Debug, Clone)]
struct Point {
    /// The zone's pitch as a count round the rim (the mesh's sectors without a zone).
    sectors: f64,
    /// The step, s.
    h: f64,
    dofs: f64,
    normal: f64,
    ratio: f64,
    share: f64,
    ripple: f64,
    peak_hz: f64,
    passage_hz: f64,
    share_ripple: f64,
    history: History,
}

impl Point {
    fn of(p: &SweepPoint) -> Option<Point> {
        let s = &p.summary;
        let num = |ptr: &str| s.pointer(ptr).and_then(serde_json::Value::as_f64);
        let sectors = num("/zone/zone_sectors").or_else(|| num("/mesh/1"))?;
        let from = num("/steady/from_s")?;
        Some(Point {
            sectors,
            h: num("/h_s")?,
            dofs: num("/dofs").unwrap_or(f64::NAN),
            normal: num("/steady/normal_force_N").unwrap_or(f64::NAN),
            ratio: num("/steady/traction_ratio")?,
            share: num("/steady/slip_share").unwrap_or(f64::NAN),
            ripple: num("/steady/traction_ratio_ripple").unwrap_or(f64::NAN),
            peak_hz: num("/steady/ripple_peak_hz").unwrap_or(f64::NAN),
            passage_hz: num("/steady/pitch_passage_hz").unwrap_or(f64::NAN),
            share_ripple: num("/steady/slip_share_ripple").unwrap_or(f64::NAN),
            history: History::read(&p.dir.join("history.csv"), 0.5 * from).unwrap_or_default(),
        })
    }

    /// Steps of the run while a rim pitch passes.
    fn steps_a_pitch(&self) -> f64 {
        1.0 / (self.passage_hz * self.h)
    }

    fn label(&self) -> String {
        format!("{} sectors, h = {} us", self.sectors, us(self.h))
    }
}

/// Microseconds to four significant digits, as the figures print numbers.
fn us(seconds: f64) -> String {
    crate::output::plot::sig(1e6 * seconds, 4)
}

/// What a line refines.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Refines {
    Mesh,
    Step,
    Both,
}

/// A line of points of one refinement, coarse to fine.
#[derive(Debug, Clone)]
struct Line {
    refines: Refines,
    /// The points' indices.
    members: Vec<usize>,
    /// Each member's rung: the sectors (mesh, both) or `1 / h` (step).
    rungs: Vec<f64>,
    label: String,
    ratio: (Option<f64>, Option<f64>),
    share: (Option<f64>, Option<f64>),
    /// Between successive members: the distance of `Q / (mu_s N)`'s histories and of the
    /// slip share's.
    distances: Vec<(f64, f64)>,
}

fn same(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * a.abs().max(b.abs())
}

impl Line {
    fn of(points: &[Point], refines: Refines, mut members: Vec<usize>, label: String) -> Line {
        let rung = |p: &Point| match refines {
            Refines::Step => 1.0 / p.h,
            Refines::Mesh | Refines::Both => p.sectors,
        };
        members.sort_by(|&a, &b| rung(&points[a]).total_cmp(&rung(&points[b])));
        let rungs: Vec<f64> = members.iter().map(|&k| rung(&points[k])).collect();
        let values = |f: &dyn Fn(&Point) -> f64| -> Vec<f64> {
            members.iter().map(|&k| f(&points[k])).collect()
        };
        let ladder = super::creep::is_ladder(&rungs);
        let fit = |v: Vec<f64>| {
            if ladder {
                super::creep::order_and_limit(&rungs, &v)
            } else {
                (None, None)
            }
        };
        let distances = members
            .windows(2)
            .map(|w| {
                let (c, f) = (&points[w[0]].history, &points[w[1]].history);
                (
                    history_distance((&c.t, &c.ratio), (&f.t, &f.ratio)),
                    history_distance((&c.t, &c.share), (&f.t, &f.share)),
                )
            })
            .collect();
        Line {
            refines,
            ratio: fit(values(&|p| p.ratio)),
            share: fit(values(&|p| p.share)),
            members,
            rungs,
            label,
            distances,
        }
    }

    /// The histories' orders of `Q / (mu_s N)` and the slip share from the last two
    /// distances.
    fn history_orders(&self) -> (Option<f64>, Option<f64>) {
        let n = self.distances.len();
        if n < 2 {
            return (None, None);
        }
        let r = self.rungs[n] / self.rungs[n - 1];
        let (a, b) = (self.distances[n - 2], self.distances[n - 1]);
        (distance_order(a.0, b.0, r), distance_order(a.1, b.1, r))
    }
}

/// The points and their lines.
struct Study {
    points: Vec<Point>,
    lines: Vec<Line>,
    /// The friction law, as a sentence.
    law: String,
}

impl Study {
    fn of(sweep: &[SweepPoint]) -> Study {
        let points: Vec<Point> = sweep
            .iter()
            .filter(|p| p.status.is_complete())
            .filter_map(Point::of)
            .collect();
        let mut lines = Vec::new();
        // Groups of points sharing `key` (within round-off), in order of first appearance.
        let groups = |key: &dyn Fn(&Point) -> f64| {
            let mut g: Vec<(f64, Vec<usize>)> = Vec::new();
            for (k, p) in points.iter().enumerate() {
                match g.iter_mut().find(|(v, _)| same(*v, key(p))) {
                    Some((_, m)) => m.push(k),
                    None => g.push((key(p), vec![k])),
                }
            }
            g.into_iter().filter(|(_, m)| m.len() >= 2)
        };
        let vary = |f: &dyn Fn(&Point) -> f64| points.iter().any(|p| !same(f(p), f(&points[0])));
        let (mesh_varies, step_varies) = (vary(&|p| p.sectors), vary(&|p| p.h));
        if mesh_varies && step_varies {
            for (_, m) in groups(&|p| p.sectors * p.h) {
                // Named by its coarsest point: a product grid has several diagonals.
                let first = m
                    .iter()
                    .map(|&k| &points[k])
                    .min_by(|a, b| a.sectors.total_cmp(&b.sectors))
                    .map_or(String::new(), |p| {
                        format!(" from {} sectors, {} us", p.sectors, us(p.h))
                    });
                let label = format!("the mesh and the step together{first}");
                lines.push(Line::of(&points, Refines::Both, m, label));
            }
        }
        if mesh_varies {
            for (h, m) in groups(&|p| p.h) {
                let label = format!("the mesh at h = {} us", us(h));
                lines.push(Line::of(&points, Refines::Mesh, m, label));
            }
        }
        if step_varies {
            for (s, m) in groups(&|p| p.sectors) {
                let label = format!("the step at {s} sectors");
                lines.push(Line::of(&points, Refines::Step, m, label));
            }
        }
        let law = sweep
            .iter()
            .find_map(|p| {
                let l = p.summary.get("friction_law")?;
                let memory = match l["memory_um"].as_f64() {
                    Some(m) if m > 0.0 => format!(", a memory of {m} um of slip"),
                    Some(_) => ", no memory".to_string(),
                    None => String::new(),
                };
                Some(format!(
                    "mu(v) = mu_k + (mu_s - mu_k) exp(-|v| / v_s), mu_s = {}, mu_k = {}, v_s = {} m/s{memory}",
                    l["static"].as_f64()?,
                    l["kinetic"].as_f64()?,
                    l["stribeck_velocity_m_s"].as_f64()?
                ))
            })
            .or_else(|| {
                let mu = sweep.first()?.summary["friction"].as_f64()?;
                Some(format!("Coulomb's, mu = {mu}"))
            })
            .unwrap_or_default();
        Study { points, lines, law }
    }

    /// The line the histories are drawn for: the longest, the diagonal first, then the mesh
    /// at the finest step (the lines are built in that order).
    fn drawn(&self) -> Option<&Line> {
        let most = self.lines.iter().map(|l| l.members.len()).max()?;
        self.lines.iter().find(|l| l.members.len() == most)
    }

    fn csv(&self) -> String {
        let mut csv = record([
            "zone_sectors",
            "h_s",
            "dofs",
            "steps_a_pitch",
            "normal_N",
            "traction_ratio",
            "slip_share",
            "traction_ratio_ripple",
            "ripple_peak_hz",
            "pitch_passage_hz",
            "slip_share_ripple",
        ]);
        for p in &self.points {
            push_record(
                &mut csv,
                [
                    format!("{}", p.sectors),
                    format!("{:e}", p.h),
                    format!("{}", p.dofs),
                    format!("{:e}", p.steps_a_pitch()),
                    format!("{:e}", p.normal),
                    format!("{:e}", p.ratio),
                    format!("{:e}", p.share),
                    format!("{:e}", p.ripple),
                    format!("{:e}", p.peak_hz),
                    format!("{:e}", p.passage_hz),
                    format!("{:e}", p.share_ripple),
                ],
            );
        }
        csv
    }

    fn md(&self) -> String {
        let mut md = format!(
            "The 3D rolling under refinement of the zone's pitch and the step. Friction: {}. Q/(mu_s N) and the slip share (sliding nodes over nodes in contact) are the means of the last half of the rolling; the ripple is the RMS of Q/(mu_s N) about its mean there, its peak the strongest frequency of the rolling's record, against the rim pitch's passage through the patch.\n\n",
            self.law
        );
        md.push_str("| zone sectors | h, us | unknowns | steps a pitch | N, kN | Q/(mu_s N) | slip share | ripple | its peak, kHz | pitch passage, kHz | slip share's ripple |\n|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
        for p in &self.points {
            let _ = writeln!(
                md,
                "| {} | {} | {} | {:.2} | {:.3} | {:.4} | {:.4} | {:.2e} | {:.1} | {:.1} | {:.3} |",
                p.sectors,
                us(p.h),
                p.dofs,
                p.steps_a_pitch(),
                1e-3 * p.normal,
                p.ratio,
                p.share,
                p.ripple,
                1e-3 * p.peak_hz,
                1e-3 * p.passage_hz,
                p.share_ripple
            );
        }
        let opt = |v: Option<f64>, d: usize| v.map_or("-".to_string(), |v| format!("{v:.d$}"));
        for l in &self.lines {
            let _ = write!(
                md,
                "\n**{}.** Each rung's steady figures; the distance of its histories (from the end of the load's ramp) from the next rung's.\n\n| zone sectors | h, us | Q/(mu_s N) | slip share | ripple | history of Q/(mu_s N): distance to the next | of the slip share |\n|---:|---:|---:|---:|---:|---:|---:|\n",
                l.label
            );
            for (i, &k) in l.members.iter().enumerate() {
                let p = &self.points[k];
                let d = l.distances.get(i);
                let _ = writeln!(
                    md,
                    "| {} | {} | {:.4} | {:.4} | {:.2e} | {} | {} |",
                    p.sectors,
                    us(p.h),
                    p.ratio,
                    p.share,
                    p.ripple,
                    d.map_or("".into(), |d| format!("{:.2e}", d.0)),
                    d.map_or("".into(), |d| format!("{:.2e}", d.1)),
                );
            }
            let (ho_r, ho_s) = l.history_orders();
            let _ = writeln!(
                md,
                "| order | | {} | {} | | {} | {} |\n| limit | | {} | {} | | | |",
                opt(l.ratio.0, 2),
                opt(l.share.0, 2),
                opt(ho_r, 2),
                opt(ho_s, 2),
                opt(l.ratio.1, 4),
                opt(l.share.1, 4),
            );
        }
        md.push_str("\nAn order is given where the differences shrink at an order within 0.5 to 4 on three rungs at one ratio (`-`: not in the asymptotic range, or fewer rungs); the limit is Richardson's from the last three rungs.\n");
        md
    }

    fn panels(&self) -> Vec<Panel> {
        let mut out = Vec::new();
        if let Some(l) = self.drawn() {
            let mut q = Panel::new(
                format!("Q / (mu_s N): {}", l.label),
                "t, ms",
                "Q / (mu_s N)",
            );
            let mut s = Panel::new(
                format!("slip share: {}", l.label),
                "t, ms",
                "sliding nodes / nodes in contact",
            );
            for &k in &l.members {
                let p = &self.points[k];
                let w = p.steps_a_pitch().round().max(1.0) as usize;
                let t: Vec<f64> = p.history.t.iter().map(|t| 1e3 * t).collect();
                let avg = |y: &[f64]| crate::analysis::signal::moving_average(y, w);
                q.series.push(Series::new(
                    p.label(),
                    t.clone(),
                    avg(&p.history.ratio),
                    SeriesStyle::Line,
                ));
                s.series.push(Series::new(
                    p.label(),
                    t,
                    avg(&p.history.share),
                    SeriesStyle::Line,
                ));
            }
            let note = "From the end of the load's ramp; each history averaged over one rim pitch's passage (the ripple at that frequency is the mesh's: the lower right panel).";
            q.note = note.into();
            s.note = note.into();
            out.extend([q, s]);
        }
        let mut steady = Panel::new(
            "The steady figures against the zone's pitch",
            "zone sectors (the rim's count at the zone's pitch)",
            "Q / (mu_s N), slip share",
        );
        steady.x_log = true;
        let mut ripple = Panel::new(
            "The ripple of Q / (mu_s N) at the rim pitch's passage",
            "zone sectors (the rim's count at the zone's pitch)",
            "RMS of Q / (mu_s N) about its mean",
        );
        ripple.x_log = true;
        ripple.y_log = true;
        // The lines over the mesh (alone or with the step), the longest only (three rungs
        // and more, when there are); the steady panel draws the first diagonal and the mesh
        // at the finest step, the ripple panel every one.
        let over_mesh: Vec<&Line> = self
            .lines
            .iter()
            .filter(|l| l.refines != Refines::Step)
            .collect();
        let longest = over_mesh.iter().map(|l| l.members.len()).max().unwrap_or(0);
        let drawn: Vec<&Line> = over_mesh
            .into_iter()
            .filter(|l| l.members.len() == longest)
            .collect();
        let finest_mesh_line =
            drawn
                .iter()
                .filter(|l| l.refines == Refines::Mesh)
                .min_by(|a, b| {
                    self.points[a.members[0]]
                        .h
                        .total_cmp(&self.points[b.members[0]].h)
                });
        let on_steady = |l: &Line| {
            let first_diagonal = drawn.iter().find(|d| d.refines == Refines::Both);
            first_diagonal.is_some_and(|d| std::ptr::eq(*d, l))
                || finest_mesh_line.is_some_and(|d| std::ptr::eq(*d, l))
        };
        // Each rung drawn on its own labelled tick.
        let rungs: Vec<f64> = drawn
            .iter()
            .flat_map(|l| l.members.iter().map(|&k| self.points[k].sectors))
            .collect();
        steady.x_ticks = rungs.clone();
        ripple.x_ticks = rungs;
        for l in drawn.iter().copied() {
            let x: Vec<f64> = l.members.iter().map(|&k| self.points[k].sectors).collect();
            let y = |f: &dyn Fn(&Point) -> f64| -> Vec<f64> {
                l.members.iter().map(|&k| f(&self.points[k])).collect()
            };
            if on_steady(l) {
                steady.series.push(Series::new(
                    format!("Q/(mu_s N), {}", l.label),
                    x.clone(),
                    y(&|p| p.ratio),
                    SeriesStyle::LineMarkers,
                ));
                steady.series.push(Series::new(
                    format!("slip share, {}", l.label),
                    x.clone(),
                    y(&|p| p.share),
                    SeriesStyle::Dashed,
                ));
            }
            ripple.series.push(Series::new(
                l.label.clone(),
                x,
                y(&|p| p.ripple),
                SeriesStyle::LineMarkers,
            ));
        }
        let limits: Vec<(f64, f64)> = drawn
            .iter()
            .filter(|l| on_steady(l))
            .flat_map(|l| {
                let x = l.rungs.last().copied().unwrap_or(f64::NAN);
                [l.ratio.1, l.share.1]
                    .into_iter()
                    .flatten()
                    .map(move |v| (x, v))
            })
            .collect();
        if !limits.is_empty() {
            steady.series.push(Series::new(
                "Richardson limits (at the finest rung's pitch)",
                limits.iter().map(|l| l.0).collect(),
                limits.iter().map(|l| l.1).collect(),
                SeriesStyle::Markers,
            ));
        }
        steady.note = "Solid: Q/(mu_s N); dashed: the slip share. The other lines (the step's at one mesh among them) are in slip_history.md.".into();
        if !steady.series.is_empty() {
            out.extend([steady, ripple]);
        }
        out
    }
}

/// Writes the study (module docs) of the sweep's complete points; returns the files.
///
/// # Errors
/// [`SweepError`] when a file cannot be written.
pub fn slip_history(out: &Path, points: &[SweepPoint]) -> Result<Vec<PathBuf>, SweepError> {
    let study = Study::of(points);
    if study.points.is_empty() {
        return Ok(Vec::new());
    }
    let write = |name: &str, text: String| super::write_text(out, name, &text);
    let mut files = vec![
        write("slip_history.csv", study.csv())?,
        write("slip_history.md", study.md())?,
    ];
    let panes = study.panels();
    if !panes.is_empty() {
        let png = out.join("slip_history.png");
        let rows = panes.len().div_ceil(2);
        panels(&png, &panes, rows, 2, (1500, 560 * rows as u32))
            .map_err(|e| RunError::output(&png, e))?;
        files.push(png);
    }
    Ok(files)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The distance of a history from itself is zero; from one shifted by `c`, `c`; the
    /// finer history is read at the coarser's times by linear interpolation.
    #[test]
    fn history_distance_interpolates_the_finer() {
        let tc: Vec<f64> = (0..11).map(|k| 0.1 * k as f64).collect();
        let tf: Vec<f64> = (0..21).map(|k| 0.05 * k as f64).collect();
        let line = |t: &[f64], c: f64| t.iter().map(|t| 2.0 * t + c).collect::<Vec<_>>();
        let (yc, yf) = (line(&tc, 0.0), line(&tf, 0.0));
        assert!(history_distance((&tc, &yc), (&tf, &yf)) < 1e-14);
        let shifted = line(&tf, 0.25);
        let d = history_distance((&tc, &yc), (&tf, &shifted));
        assert!((d - 0.25).abs() < 1e-14, "{d}");
        // Only the span of the finer counts: a finer history of the first half.
        let half = &tf[..11];
        let d = history_distance((&tc, &yc), (half, &shifted[..11]));
        assert!((d - 0.25).abs() < 1e-14, "{d}");
        assert!(history_distance((&tc, &yc), (&[], &[])).is_nan());
    }

    /// Distances falling as `C r^-p` give back `p`.
    #[test]
    fn distances_give_their_order() {
        let (c, p, r) = (0.3, 1.7, 2.0_f64);
        let d = |k: i32| c * r.powf(-p * k as f64);
        let o = distance_order(d(1), d(2), r).unwrap();
        assert!((o - p).abs() < 1e-12, "{o}");
        assert_eq!(distance_order(0.0, d(2), r), None);
        assert_eq!(distance_order(d(1), d(2), 1.0), None);
    }
}
