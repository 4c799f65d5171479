//! What a sweep's 3D rolling runs cost: each run's step against its free step and against
//! the memory's floor, and the time for one metre of rolling (`cost.md`, `.csv` and `.png`).
//!
//! Every `rolling3d` run records its `cost` in `summary.json` (the kind's run, Cost): the
//! set-up, the factor, the free step (a step's right-hand side and solve without contact:
//! the mean of the loop's own predictions solved, so under the loop's conditions) and the
//! bytes it reads, the loop's
//! step with the contact, the solves a step and `metre_s`. The study adds the floor: the
//! free step's bytes over the memory's bandwidth on the run's threads, measured when the
//! study is written (the STREAM-like triad of [`crate::linalg::bandwidth`], once for each
//! count of threads the runs had, on the machine and at the load of that moment: a study
//! gathered elsewhere measures the gathering machine).
//!
//! The ratios are what a user compares:
//! - `free / floor`: how near the free step is to reading its factor once at the memory's
//!   speed (the solve's floor; a ratio below 1 says the bandwidth measured was low, as on a
//!   loaded machine, not that a solve beats memory);
//! - `step / free`: what the contact costs on top of the step without it (the soft way's
//!   predictions made again, the columns `A^-1 e_d` of the dofs entering the patch, the
//!   rows' dense solves);
//! - the minutes a metre of rolling takes at the run's speed and step on its threads, after
//!   the set-up.
//!
//! The times are the runs' own, taken as they ran: side by side with the sweep's other runs
//! (`--jobs`) and whatever else the machine ran. The ratios of one run (its step against its
//! own free step) are the robust figures; the seconds are not.

use super::{SweepError, SweepPoint};
use crate::linalg::bandwidth::Bandwidth;
use crate::output::csv::{push_record, record};
use crate::output::plot::{panels, sig, Panel, Series, SeriesStyle};
use crate::run::RunError;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Arrays of the bandwidth's measure, MiB each (three): far larger than the caches.
const BANDWIDTH_MIB: usize = 128;
/// Rounds of the bandwidth's measure (the best kept).
const BANDWIDTH_ROUNDS: usize = 5;

/// One run's cost, from its summary.
#[derive(Debug, Clone, PartialEq)]
pub struct RunCost {
    /// The point's values.
    pub label: String,
    /// Unknowns.
    pub dofs: f64,
    /// Threads of the run.
    pub threads: f64,
    /// The factorization (its name in the summary).
    pub factor: String,
    /// The factor's stored entries.
    pub factor_nnz: f64,
    /// Set-up, s.
    pub setup_s: f64,
    /// The free step, s.
    pub free_step_s: f64,
    /// The bytes a free step reads.
    pub free_step_bytes: f64,
    /// The loop's step with the contact, s.
    pub step_s: f64,
    /// Free solves (predictions not made again) a step.
    pub free_solves: f64,
    /// Columns' solves a step.
    pub column_solves: f64,
    /// The loop's time for one metre of rolling, s.
    pub metre_s: f64,
    /// The run's step, s.
    pub h: f64,
    /// The rim's speed, m/s.
    pub speed: f64,
}

impl RunCost {
    /// The cost of a complete point whose summary has one.
    pub fn of(p: &SweepPoint) -> Option<RunCost> {
        if !p.status.is_complete() {
            return None;
        }
        let s = &p.summary;
        let c = s.get("cost")?;
        let num = |v: &serde_json::Value| v.as_f64().unwrap_or(f64::NAN);
        let factor = match &c["factor"] {
            serde_json::Value::String(k) => k.clone(),
            serde_json::Value::Object(m) => m
                .iter()
                .map(|(k, v)| format!("{k} ({})", v.as_str().unwrap_or("?")))
                .collect::<Vec<_>>()
                .join(", "),
            _ => "-".to_string(),
        };
        Some(RunCost {
            label: p.value.clone(),
            dofs: num(&s["dofs"]),
            threads: num(&c["threads"]),
            factor,
            factor_nnz: num(&c["factor_nnz"]),
            setup_s: num(&c["setup_s"]),
            free_step_s: num(&c["free_step_s"]),
            free_step_bytes: num(&c["free_step_bytes"]),
            step_s: num(&c["step_s"]),
            free_solves: num(&c["free_solves_per_step"]),
            column_solves: num(&c["column_solves_per_step"]),
            metre_s: num(&c["metre_s"]),
            h: num(&s["h_s"]),
            speed: num(&s["speed_m_s"]),
        })
    }

    /// The free step's floor at the bandwidth `bw` (bytes/s), s.
    pub fn floor_s(&self, bw: f64) -> f64 {
        self.free_step_bytes / bw
    }
}

/// Whether the sweep's points carry a cost record (the `rolling3d` runs).
pub fn applies(points: &[SweepPoint]) -> bool {
    points.iter().any(|p| RunCost::of(p).is_some())
}

/// Writes `cost.csv`, `cost.md` and `cost.png` (module docs) into `out`, measuring the
/// bandwidth now.
///
/// # Errors
/// [`SweepError`] when a file cannot be written.
pub fn cost(out: &Path, points: &[SweepPoint]) -> Result<Vec<PathBuf>, SweepError> {
    let mut threads: Vec<usize> = points
        .iter()
        .filter_map(RunCost::of)
        .map(|r| r.threads.max(1.0) as usize)
        .collect();
    threads.sort_unstable();
    threads.dedup();
    let bws = Bandwidths(
        threads
            .into_iter()
            .map(|t| crate::linalg::bandwidth::measure(BANDWIDTH_MIB, BANDWIDTH_ROUNDS, t))
            .collect(),
    );
    cost_at(out, points, &bws)
}

/// The bandwidths measured, one per count of threads.
#[derive(Debug, Clone, PartialEq)]
pub struct Bandwidths(pub Vec<Bandwidth>);

impl Bandwidths {
    /// The triad on `threads` threads (the measure on the nearest count), bytes/s.
    pub fn triad(&self, threads: f64) -> f64 {
        self.0
            .iter()
            .min_by(|a, b| {
                (a.threads as f64 - threads)
                    .abs()
                    .total_cmp(&(b.threads as f64 - threads).abs())
            })
            .map_or(f64::NAN, |b| b.triad)
    }
}

/// [`cost`] at a bandwidth measured before.
///
/// # Errors
/// [`SweepError`] when a file cannot be written.
pub fn cost_at(
    out: &Path,
    points: &[SweepPoint],
    bw: &Bandwidths,
) -> Result<Vec<PathBuf>, SweepError> {
    let runs: Vec<RunCost> = points.iter().filter_map(RunCost::of).collect();
    let write = |name: &str, text: String| super::write_text(out, name, &text);
    let mut files = vec![
        write("cost.csv", csv(&runs, bw))?,
        write("cost.md", md(&runs, bw))?,
    ];
    let png = out.join("cost.png");
    panels(&png, &figure(&runs, bw), 1, 3, (1800, 620)).map_err(|e| RunError::output(&png, e))?;
    files.push(png);
    Ok(files)
}

/// cost.csv: a row per run.
fn csv(runs: &[RunCost], bw: &Bandwidths) -> String {
    let mut csv = record([
        "point",
        "dofs",
        "threads",
        "factor",
        "factor_nnz",
        "setup_s",
        "free_step_ms",
        "floor_ms",
        "free_over_floor",
        "step_ms",
        "step_over_free",
        "step_over_floor",
        "free_solves_per_step",
        "column_solves_per_step",
        "h_s",
        "speed_m_s",
        "metre_min",
        "bandwidth_triad_GB_s",
    ]);
    for r in runs {
        let floor = r.floor_s(bw.triad(r.threads));
        push_record(
            &mut csv,
            [
                r.label.clone(),
                format!("{}", r.dofs),
                format!("{}", r.threads),
                r.factor.clone(),
                format!("{}", r.factor_nnz),
                format!("{:e}", r.setup_s),
                format!("{:e}", 1e3 * r.free_step_s),
                format!("{:e}", 1e3 * floor),
                format!("{:e}", r.free_step_s / floor),
                format!("{:e}", 1e3 * r.step_s),
                format!("{:e}", r.step_s / r.free_step_s),
                format!("{:e}", r.step_s / floor),
                format!("{:e}", r.free_solves),
                format!("{:e}", r.column_solves),
                format!("{:e}", r.h),
                format!("{:e}", r.speed),
                format!("{:e}", r.metre_s / 60.0),
                format!("{:e}", bw.triad(r.threads) / 1e9),
            ],
        );
    }
    csv
}

/// cost.md: the table and how to read it.
fn md(runs: &[RunCost], bw: &Bandwidths) -> String {
    let measured =
        bw.0.iter()
            .map(|b| {
                format!(
                    "on {} thread{}, triad {:.2} GB/s, read {:.2} GB/s",
                    b.threads,
                    if b.threads == 1 { "" } else { "s" },
                    b.triad / 1e9,
                    b.read / 1e9
                )
            })
            .collect::<Vec<_>>()
            .join("; ");
    let (mib, rounds) = bw.0.first().map_or((0, 0), |b| (b.mib, b.rounds));
    let mut md = format!(
        "What each run's step cost. The free step is a step's right-hand side and solve without contact, the mean of the loop's own predictions solved; its floor is the bytes it reads (the factor once forward and once back, the right-hand side's rows, the passes over the state) over the memory's bandwidth on the run's threads, measured when this file was written: {measured} (arrays of {mib} MiB, best of {rounds}). The step is the loop's, with the contact, over its steps. The times are the runs' own, side by side with the sweep's other runs and whatever else ran: the ratio of a run's step to its own free step, both timed in its loop, holds better than the seconds.\n\n| point | unknowns | threads | factor, entries | set-up s | free step ms | floor ms | free / floor | step ms | step / free | free solves a step | columns' solves a step | one metre, min |\n|---|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n"
    );
    for r in runs {
        let floor = r.floor_s(bw.triad(r.threads));
        let _ = writeln!(
            md,
            "| {} | {} | {} | {}, {:.3e} | {:.1} | {} | {} | {:.2} | {} | {:.2} | {:.2} | {:.3} | {} |",
            r.label,
            r.dofs,
            r.threads,
            r.factor,
            r.factor_nnz,
            r.setup_s,
            sig(1e3 * r.free_step_s, 3),
            sig(1e3 * floor, 3),
            r.free_step_s / floor,
            sig(1e3 * r.step_s, 3),
            r.step_s / r.free_step_s,
            r.free_solves,
            r.column_solves,
            sig(r.metre_s / 60.0, 3),
        );
    }
    let _ = write!(
        md,
        "\nOne metre: the loop's time to roll a metre at the run's speed and step (`step / (V h)`), after the set-up, on the run's threads."
    );
    if let Some(big) = runs
        .iter()
        .filter(|r| r.dofs.is_finite())
        .max_by(|a, b| a.dofs.total_cmp(&b.dofs))
    {
        let _ = write!(
            md,
            " The largest run ({} unknowns at {} m/s, h = {} us) rolls a metre in {} minutes; explicit finite-element wheel-rail models with penalty contact are reported to take hours to days a metre.",
            big.dofs,
            sig(big.speed, 3),
            sig(1e6 * big.h, 3),
            sig(big.metre_s / 60.0, 3)
        );
    }
    md.push('\n');
    md
}

/// cost.png: the step, the free step and the floor against the unknowns; the ratios against
/// the marks a user holds them to; the minutes a metre.
fn figure(runs: &[RunCost], bw: &Bandwidths) -> [Panel; 3] {
    let x: Vec<f64> = runs.iter().map(|r| r.dofs).collect();
    let of = |f: &dyn Fn(&RunCost) -> f64| runs.iter().map(f).collect::<Vec<_>>();
    let mut step = Panel::new(
        "A step's time against the unknowns",
        "unknowns",
        "time a step, ms",
    );
    step.x_log = true;
    step.y_log = true;
    step.series = vec![
        Series::new(
            "the step with the contact",
            x.clone(),
            of(&|r| 1e3 * r.step_s),
            SeriesStyle::Markers,
        ),
        Series::new(
            "the free step (no contact)",
            x.clone(),
            of(&|r| 1e3 * r.free_step_s),
            SeriesStyle::Markers,
        ),
        Series::new(
            "the free step's floor: its bytes at the triad's bandwidth".to_string(),
            x.clone(),
            of(&|r| 1e3 * r.floor_s(bw.triad(r.threads))),
            SeriesStyle::Markers,
        ),
    ];
    step.note = "Each run's own times, taken as it ran, beside the sweep's other runs.".to_string();
    let mut ratio = Panel::new("The ratios", "unknowns", "ratio");
    ratio.x_log = true;
    ratio.series = vec![
        Series::new(
            "the step with the contact / the free step",
            x.clone(),
            of(&|r| r.step_s / r.free_step_s),
            SeriesStyle::Markers,
        ),
        Series::new(
            "the free step / its floor",
            x.clone(),
            of(&|r| r.free_step_s / r.floor_s(bw.triad(r.threads))),
            SeriesStyle::Markers,
        ),
    ];
    ratio.hlines = vec![
        (2.0, "the contact at 2 free steps".to_string()),
        (1.5, "the free step at 1.5 floors".to_string()),
    ];
    ratio.note =
        "Both times of a ratio are the same run's, in its loop: the robust figures.".to_string();
    let mut metre = Panel::new(
        "One metre of rolling, after the set-up",
        "unknowns",
        "minutes a metre",
    );
    metre.x_log = true;
    metre.y_log = true;
    metre.series = vec![Series::new(
        "each run, at its speed and step",
        x,
        of(&|r| r.metre_s / 60.0),
        SeriesStyle::Markers,
    )];
    let threads = runs.iter().map(|r| r.threads).fold(0.0, f64::max);
    metre.note = format!(
        "The loop's time a step over the distance a step rolls, V h, on {threads} thread{}.",
        if threads == 1.0 { "" } else { "s" }
    );
    [step, ratio, metre]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(dofs: f64, free: f64, step: f64, bytes: f64) -> RunCost {
        RunCost {
            label: format!("n = {dofs}"),
            dofs,
            threads: 2.0,
            factor: "lu (nested_dissection)".into(),
            factor_nnz: 1e6,
            setup_s: 1.0,
            free_step_s: free,
            free_step_bytes: bytes,
            step_s: step,
            free_solves: 1.2,
            column_solves: 0.01,
            metre_s: step / (30.0 * 1e-5),
            h: 1e-5,
            speed: 30.0,
        }
    }

    /// The table's ratios are the runs' own: the floor is the bytes over the bandwidth, and
    /// each ratio the quotient of the columns it names.
    #[test]
    fn the_ratios_are_the_quotients_they_name() {
        let bw = Bandwidths(vec![Bandwidth {
            triad: 1e10,
            read: 1.2e10,
            mib: 128,
            rounds: 5,
            threads: 2,
        }]);
        let runs = [run(1e4, 2e-3, 5e-3, 1e7), run(2e5, 0.1, 0.25, 8e8)];
        let text = csv(&runs, &bw);
        let rows: Vec<Vec<&str>> = text
            .lines()
            .skip(1)
            .map(|l| crate::output::csv::number_cells(l).collect())
            .collect();
        let head: Vec<&str> =
            crate::output::csv::number_cells(text.lines().next().unwrap()).collect();
        let col = |name: &str| head.iter().position(|h| *h == name).unwrap();
        for (r, row) in runs.iter().zip(&rows) {
            let get = |name: &str| row[col(name)].parse::<f64>().unwrap();
            let floor = 1e3 * r.free_step_bytes / 1e10;
            assert!((get("floor_ms") - floor).abs() < 1e-12 * floor);
            assert!((get("free_over_floor") - get("free_step_ms") / floor).abs() < 1e-12);
            assert!((get("step_over_free") - get("step_ms") / get("free_step_ms")).abs() < 1e-12);
            assert!((get("metre_min") - get("step_ms") * 1e-3 / (30.0 * 1e-5) / 60.0).abs() < 1e-9);
        }
        let md = md(&runs, &bw);
        assert!(
            md.contains("| 2.50 |") && md.contains("triad 10.00 GB/s"),
            "{md}"
        );
        assert!(md.contains("The largest run (200000 unknowns"), "{md}");
    }
}
