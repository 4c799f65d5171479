//! `softway shakedown`: Johnson's rolling shakedown on the half-space
//! ([`crate::plasticity::shakedown`]) for one or more loads: a table per pass on standard
//! output and, with `--out`, `shakedown.csv` (per load and pass), `residual.csv` (the
//! residual `sigma_xx` at `x = 0` after the last pass) and `shakedown.png`.

use super::{print_result, CommandResult, Replace};
use crate::output::csv::{push_record, record};
use crate::output::files::write_atomic;
use crate::output::job::JobFolder;
use crate::output::plot::{panels, Panel, Series, SeriesStyle};
use crate::plasticity::shakedown::{
    first_yield, PassResult, Shakedown, ShakedownConfig, ShakedownError,
};
use std::fmt::Write as _;
use std::path::PathBuf;

/// The options of `softway shakedown`.
#[derive(clap::Args, Debug)]
pub(super) struct ShakedownArgs {
    /// p0/k, k = sigma_y / sqrt(3); repeatable (one run each).
    #[arg(long = "p0-over-k", required = true)]
    p0_over_k: Vec<f64>,
    /// Passes of the load.
    #[arg(long, default_value_t = 10, value_parser = clap::value_parser!(u64).range(1..=1000))]
    passes: u64,
    /// Cell size under the path, / a.
    #[arg(long, default_value_t = 0.125)]
    h_over_a: f64,
    /// Half-length of the path, / a (the central region is |x| <= L - 2a).
    #[arg(long, default_value_t = 4.0)]
    path_over_a: f64,
    /// Move of the load per increment, / a.
    #[arg(long, default_value_t = 0.1)]
    step_over_a: f64,
    /// Half-width and depth of the half-space, / a.
    #[arg(long, default_value_t = 30.0)]
    far_over_a: f64,
    /// Also write shakedown.csv, residual.csv and shakedown.png into this folder.
    #[arg(long)]
    out: Option<PathBuf>,
    #[command(flatten)]
    replace: Replace,
}

/// Runs `softway shakedown`. A signal (SIGINT, SIGTERM, SIGHUP) stops it after the pass
/// under way: the passes finished are reported and written (with `--out`, the folder marked
/// interrupted), exit 130.
pub(super) fn shakedown_command(args: ShakedownArgs, cancel: &crate::run::Cancel) -> CommandResult {
    let base = ShakedownConfig {
        h_over_a: args.h_over_a,
        path_over_a: args.path_over_a,
        step_over_a: args.step_over_a,
        far_over_a: args.far_over_a,
        ..ShakedownConfig::default()
    };
    let configs: Vec<ShakedownConfig> = args
        .p0_over_k
        .iter()
        .map(|&p0_over_k| ShakedownConfig { p0_over_k, ..base })
        .collect();
    for c in &configs {
        c.validate().map_err(|e| match e {
            ShakedownError::Parameter {
                name,
                value,
                allowed,
            } => format!(
                "shakedown: --{} {value} is not allowed; allowed: {allowed}",
                name.replace('_', "-")
            ),
            other => other.to_string(),
        })?;
    }
    // The folder is claimed before the work: a folder of the user's files is refused at once.
    let stage = match &args.out {
        Some(dir) => Some(JobFolder::begin("shakedown", dir, args.replace.force, &[])?),
        None => None,
    };
    let fy = first_yield(base.elastic.poisson);
    let mut text = format!(
        "first yield of the exact field (von Mises, plane strain, nu = {}): p0/k = {:.4} at depth {:.4} a; Johnson's shakedown limit (free rolling): p0/k = 4.0\n",
        base.elastic.poisson, fy.p0_over_k, fy.depth_over_a
    );
    let mut runs: Vec<(f64, Vec<PassResult>)> = Vec::new();
    let a2 = base.a * base.a;
    for c in configs {
        if cancel.is_cancelled() {
            break;
        }
        let mut s = Shakedown::new(c)?;
        let _ = writeln!(
            text,
            "\np0/k = {}: {} triangles, h = a/{:.0}, {} increments per pass\npass  d_eq_max   d_eq_int/a^2  net_max    eq_max     iterations",
            c.p0_over_k,
            s.space.triangles.len(),
            1.0 / c.h_over_a,
            c.increments_per_pass()
        );
        let mut rows = Vec::new();
        for _ in 0..args.passes {
            if cancel.is_cancelled() {
                break;
            }
            let r = s.run_pass()?;
            let _ = writeln!(
                text,
                "{:4}  {:.3e}  {:.3e}     {:.3e}  {:.3e}  {}",
                r.pass,
                r.d_eq_max,
                r.d_eq_integral / a2,
                r.net_max,
                r.eq_max,
                r.iterations
            );
            rows.push(r);
        }
        if !rows.is_empty() {
            runs.push((c.p0_over_k, rows));
        }
    }
    let interrupted = cancel.is_cancelled();
    if interrupted {
        let _ = writeln!(
            text,
            "\ninterrupted: the passes above are the ones finished"
        );
    }
    if let Some(stage) = stage {
        let files = write(&runs, &base, stage.dir())?;
        let files = stage.finish(
            &files,
            None::<&crate::scenario::Scenario<crate::scenario::RunSpec>>,
            interrupted,
        )?;
        for f in files {
            let _ = writeln!(text, "wrote {}", f.display());
        }
    }
    print_result(&text)?;
    Ok(super::exit_code(interrupted))
}

/// Writes the CSVs and the figure into `dir`; returns their paths.
fn write(
    runs: &[(f64, Vec<PassResult>)],
    c: &ShakedownConfig,
    dir: &std::path::Path,
) -> Result<Vec<PathBuf>, Box<dyn std::error::Error>> {
    let mut csv = record([
        "p0_over_k",
        "pass",
        "d_eq_max",
        "d_eq_integral_m2",
        "net_max",
        "net_integral_m2",
        "eq_max",
        "flowed",
        "surface_ux_m",
        "iterations",
        "max_iterations",
    ]);
    let mut res = record(["p0_over_k", "depth_m", "sigma_xx_pa"]);
    let mut p1 = Panel::new(
        "Plastic strain increment per pass (central region)",
        "pass",
        "largest increase of the equivalent plastic strain",
    );
    p1.y_log = true;
    p1.note = format!(
        "h = a/{:.0}; Johnson's shakedown limit p0/k = 4.0 (free rolling); a value that falls pass by pass is elastic shakedown; a load with no flow (zero) has no line on the log axis",
        1.0 / c.h_over_a
    );
    let mut p2 = Panel::new(
        "Residual sigma_xx at x = 0 after the last pass",
        "depth / a",
        "sigma_xx / k",
    );
    for (p0k, rows) in runs {
        for r in rows {
            push_record(
                &mut csv,
                [
                    format!("{p0k}"),
                    format!("{}", r.pass),
                    format!("{:e}", r.d_eq_max),
                    format!("{:e}", r.d_eq_integral),
                    format!("{:e}", r.net_max),
                    format!("{:e}", r.net_integral),
                    format!("{:e}", r.eq_max),
                    format!("{}", r.flowed),
                    format!("{:e}", r.surface_ux),
                    format!("{}", r.iterations),
                    format!("{}", r.max_iterations),
                ],
            );
        }
        // A zero (no flow) is left off the log axis.
        p1.series.push(Series::new(
            format!("p0/k = {}", crate::output::plot::sig(*p0k, 3)),
            rows.iter().map(|r| r.pass as f64).collect(),
            rows.iter().map(|r| r.d_eq_max).collect(),
            SeriesStyle::LineMarkers,
        ));
        if let Some(last) = rows.last() {
            for &(z, s) in &last.residual_sxx {
                push_record(
                    &mut res,
                    [format!("{p0k}"), format!("{z:e}"), format!("{s:e}")],
                );
            }
            let near: Vec<_> = last
                .residual_sxx
                .iter()
                .filter(|(z, _)| *z <= 3.0 * c.a)
                .collect();
            p2.series.push(Series::new(
                format!("p0/k = {}", crate::output::plot::sig(*p0k, 3)),
                near.iter().map(|(z, _)| z / c.a).collect(),
                near.iter().map(|(_, s)| s / c.k()).collect(),
                SeriesStyle::LineMarkers,
            ));
        }
    }
    let (f1, f2, f3) = (
        dir.join("shakedown.csv"),
        dir.join("residual.csv"),
        dir.join("shakedown.png"),
    );
    write_atomic(&f1, csv.as_bytes())?;
    write_atomic(&f2, res.as_bytes())?;
    panels(&f3, &[p1, p2], 1, 2, (1600, 700))?;
    Ok(vec![f1, f2, f3])
}
